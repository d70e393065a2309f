//! `lgh`: the command-line tool of the lighting grid hierarchy, as a library: the binary
//! (`main.rs`) parses the command line and calls [`dispatch`]. Five modules are public, for the
//! Python package: [`explosion`], whose [`render_in_memory`](explosion::render_in_memory) is
//! `lgh explosion` rendering into memory and [`prepare_in_memory`](explosion::prepare_in_memory)
//! a frame made ready for many cameras; [`gi`], whose
//! [`render_in_memory_with`](gi::render_in_memory_with) is `lgh gi`'s; [`memory`], what the
//! renders into memory share (their settings, their parse, the error's stage); [`inspect`],
//! whose [`report`](inspect::report) is `lgh inspect --json`'s record of an OpenVDB file's
//! grids; and [`files`], the input files' checks, whose [`MissingFile`] tells a missing file
//! from a refused setting.
//!
//! Thin by design: it parses arguments, shows progress and writes files; the work is in the
//! library crates. Errors print as one line on stderr with a non-zero exit ([`exit_code`]).

#![forbid(unsafe_code)]

/// `println!` that stops quietly when stdout is closed (`lgh inspect … | head`) and returns other
/// write errors.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::say(format_args!($($arg)*))?
    };
}

/// An error type that is its message: `Display` writes the message, `Error` has no source.
macro_rules! message_error {
    ($name:ident) => {
        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(&self.0)
            }
        }

        impl std::error::Error for $name {}
    };
}

mod bench;
mod bench_explosion;
mod bench_flicker;
#[cfg(feature = "gpu")]
mod bench_gpu;
mod bench_table1;
mod compare;
mod dark;
mod demo;
pub mod explosion;
pub mod files;
pub mod gi;
mod hints;
pub mod inspect;
mod manifest;
pub mod memory;
mod output;
mod paquette;
mod probes;
mod progress;
mod room;

use clap::Subcommand;

pub use files::MissingFile;
pub use progress::Bars;

/// Lighting with millions of point lights through the Lighting Grid Hierarchy.
#[derive(Debug, clap::Parser)]
#[command(
    name = "lgh",
    version,
    about = "Lighting with millions of point lights through the Lighting Grid Hierarchy"
)]
pub struct Cli {
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long, global = true)]
    pub threads: Option<usize>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Render the built-in procedural explosion, lit by its own fire (EXR + PNG).
    Demo(demo::DemoArgs),
    /// Render frames of a simulation cache (OpenVDB), lit by its own fire (EXR + PNG).
    Explosion(Box<explosion::ExplosionArgs>),
    /// Indirect illumination of an OBJ scene from virtual point lights, with shadow rays
    /// (EXR + PNG).
    Gi(Box<gi::GiArgs>),
    /// Evaluate unshadowed lighting L(x) = Σ B·I·g(d) at every point of a PLY point cloud.
    Probes(probes::ProbesArgs),
    /// Describe the grids of an OpenVDB file (type, voxel size, active voxels, bounds, statistics).
    Inspect(inspect::InspectArgs),
    /// Compare an image with a reference: relative RMSE, max and mean error, difference PNG.
    Compare(compare::CompareArgs),
    /// Paquette et al.'s test scenes: brute force, Ward, the light octree, Lightcuts and LGH
    /// (their Tables 2 and 3).
    Paquette(paquette::PaquetteArgs),
    /// Benchmarks that print machine-readable JSON.
    Bench {
        #[command(subcommand)]
        which: BenchCommand,
    },
}

#[derive(Debug, Subcommand)]
enum BenchCommand {
    /// Build and query speed and accuracy of lgh-core on three light sets.
    Core(bench::CoreBenchArgs),
    /// The explosion renderer: LGH at several α against brute force and the path tracer.
    Explosion(bench_explosion::ExplosionBenchArgs),
    /// The paper's Table 1 for one procedural frame: lights, cube-map bytes and precompute
    /// seconds per level, render seconds, against ray-marched and no shadows in the same run.
    Table1(bench_table1::Table1Args),
    /// Indirect light from VPLs (the paper's Fig. 13): the hierarchy at several α against brute
    /// force over every VPL, on the same pixels, in the same run.
    Gi(gi::BenchGiArgs),
    /// Temporal flicker of a sequence (the paper's Figs. 9, 10): the hierarchy, Lightcuts and
    /// the paper's flickering variants against brute force, frame by frame.
    Flicker(bench_flicker::FlickerArgs),
    /// The hierarchy's query on the GPU (lgh-gpu) against the CPU path on every core, on the
    /// web page's ember swarm, in the same run.
    #[cfg(feature = "gpu")]
    Gpu(bench_gpu::GpuBenchArgs),
}

/// The CLI's error: any library's typed error or a message, shown as one line by `main`.
pub type Error = Box<dyn std::error::Error + Send + Sync>;

/// A command line that cannot work however often it is retried (a farm task's flag that is
/// the manifest's, a damaged or foreign manifest): `main` exits with 2, as for the parser's own
/// refusals, not 1, which a farm reads as a frame that failed and may be retried.
#[derive(Debug)]
pub struct Usage(pub String);

message_error!(Usage);

/// A [`Usage`] error.
pub(crate) fn usage(message: impl Into<String>) -> Error {
    Box::new(Usage(message.into()))
}

/// Writes one line to stdout (see [`say!`]).
pub(crate) fn say(line: std::fmt::Arguments<'_>) -> Result<(), crate::Error> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match writeln!(out, "{line}").and_then(|_| out.flush()) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => std::process::exit(0),
        Err(e) => Err(format!("cannot write to stdout: {e}").into()),
    }
}

/// Validates the paper's α before any work is done.
pub(crate) fn check_alpha(alpha: f32) -> Result<(), crate::Error> {
    Ok(lgh_core::check_alpha(alpha)?)
}

/// Runs the command `cli` (parsed from `matches`).
pub fn dispatch(cli: &Cli, matches: &clap::ArgMatches) -> Result<(), Error> {
    match &cli.command {
        Command::Demo(a) => demo::run(a),
        Command::Explosion(a) => match matches.subcommand_matches("explosion") {
            Some(m) => explosion::run(a, m),
            None => Err("the explosion subcommand's arguments are missing".into()),
        },
        Command::Gi(a) => gi::run(a),
        Command::Bench {
            which: BenchCommand::Gi(a),
        } => gi::bench(a),
        Command::Probes(a) => probes::run(a),
        Command::Inspect(a) => inspect::run(a),
        Command::Compare(a) => compare::run(a),
        Command::Paquette(a) => paquette::run(a),
        Command::Bench {
            which: BenchCommand::Core(a),
        } => bench::run(a),
        Command::Bench {
            which: BenchCommand::Explosion(a),
        } => bench_explosion::run(a),
        Command::Bench {
            which: BenchCommand::Table1(a),
        } => bench_table1::run(a),
        Command::Bench {
            which: BenchCommand::Flicker(a),
        } => bench_flicker::run(a),
        #[cfg(feature = "gpu")]
        Command::Bench {
            which: BenchCommand::Gpu(a),
        } => bench_gpu::run(a),
    }
}

/// The line `lgh` prints for `e`: the library's words, then the flags that change the settings
/// they name.
#[must_use]
pub fn describe(e: &(dyn std::error::Error + 'static)) -> String {
    match hints::flags(e) {
        Some(flags) => format!("{e}; on the command line: {flags}"),
        None => e.to_string(),
    }
}

/// The exit status for `e`: 2 for a command line that cannot work however often it is retried
/// ([`Usage`], as for the parser's own refusals), 1 for the rest.
#[must_use]
pub fn exit_code(e: &(dyn std::error::Error + 'static)) -> i32 {
    if e.downcast_ref::<Usage>().is_some() {
        2
    } else {
        1
    }
}
