//! `lgh`: the command-line tool of the lighting grid hierarchy.
//!
//! Thin by design: it parses arguments, shows progress and writes files; the work is in the
//! library crates. Errors print as one line on stderr with a non-zero exit.

#![forbid(unsafe_code)]

/// `println!` that stops quietly when stdout is closed (`lgh inspect … | head`) and returns other
/// write errors.
macro_rules! say {
    ($($arg:tt)*) => {
        $crate::say(format_args!($($arg)*))?
    };
}

mod bench;
mod bench_explosion;
mod bench_flicker;
mod bench_gpu;
mod bench_table1;
mod compare;
mod dark;
mod demo;
mod explosion;
mod gi;
mod hints;
mod inspect;
mod manifest;
mod output;
mod paquette;
mod probes;
mod progress;
mod room;

use clap::{CommandFactory, FromArgMatches, Subcommand};

/// Lighting with millions of point lights through the Lighting Grid Hierarchy.
#[derive(Debug, clap::Parser)]
#[command(
    name = "lgh",
    version,
    about = "Lighting with millions of point lights through the Lighting Grid Hierarchy"
)]
struct Cli {
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long, global = true)]
    threads: Option<usize>,
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
    Gpu(bench_gpu::GpuBenchArgs),
}

/// The CLI's error: any library's typed error or a message, shown as one line by `main`.
pub(crate) type Error = Box<dyn std::error::Error + Send + Sync>;

/// A command line that cannot work however often it is retried (a farm task's flag that is
/// the manifest's, a damaged or foreign manifest): `main` exits with 2, as for the parser's own
/// refusals, not 1, which a farm reads as a frame that failed and may be retried.
#[derive(Debug)]
pub(crate) struct Usage(pub String);

impl std::fmt::Display for Usage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Usage {}

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

/// Checks that an input file is there, and is a file (a folder says so), before any work.
pub(crate) fn check_file(path: &std::path::Path) -> Result<(), crate::Error> {
    if path.is_file() {
        Ok(())
    } else if path.is_dir() {
        Err(format!("{}: is a folder, not a file", path.display()).into())
    } else {
        Err(format!("{}: no such file", path.display()).into())
    }
}

/// Validates the paper's α before any work is done.
pub(crate) fn check_alpha(alpha: f32) -> Result<(), crate::Error> {
    Ok(lgh_core::check_alpha(alpha)?)
}

/// SIGINT and SIGTERM stop `lgh` at once, with the conventional exit codes (130, 143): a
/// watcher thread waits for the file being written, if any (a frame's EXR and PNG together),
/// and exits. Every file written before is whole, none after is begun, and no temporary file is
/// left: a sequence interrupted mid-way keeps each finished frame.
#[cfg(unix)]
fn exit_on_signals() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let mut signals = match signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("lgh: warning: cannot watch for SIGINT and SIGTERM: {e}");
            return;
        }
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            let _files = lgh_image::hold_writes();
            let (name, code) = if signal == SIGINT {
                ("SIGINT", 130)
            } else {
                ("SIGTERM", 143)
            };
            eprintln!("\nlgh: stopped by {name}; every file written so far is complete");
            std::process::exit(code);
        }
    });
}

fn main() {
    #[cfg(unix)]
    exit_on_signals();
    let matches = Cli::command().get_matches();
    let cli = Cli::from_arg_matches(&matches).unwrap_or_else(|e| e.exit());
    if let Some(t) = cli.threads {
        if t == 0 {
            eprintln!("lgh: error: --threads must be at least 1");
            std::process::exit(2);
        }
        if let Err(e) = rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build_global()
        {
            eprintln!("lgh: error: cannot start {t} threads: {e}");
            std::process::exit(1);
        }
    }
    let result = match &cli.command {
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
        Command::Bench {
            which: BenchCommand::Gpu(a),
        } => bench_gpu::run(a),
    };
    if let Err(e) = result {
        // One line: the library's words, then the flags that change the settings they name.
        match hints::flags(e.as_ref()) {
            Some(flags) => eprintln!("lgh: error: {e}; on the command line: {flags}"),
            None => eprintln!("lgh: error: {e}"),
        }
        std::process::exit(if e.downcast_ref::<Usage>().is_some() {
            2
        } else {
            1
        });
    }
}
