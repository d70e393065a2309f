//! `lgh`: the command-line tool of the lighting grid hierarchy (the library `lgh_cli` does the
//! work). Errors print as one line on stderr with a non-zero exit.

#![forbid(unsafe_code)]

use clap::{CommandFactory, FromArgMatches};
use lgh_cli::Cli;

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
    if let Err(e) = lgh_cli::dispatch(&cli, &matches) {
        eprintln!("lgh: error: {}", lgh_cli::describe(e.as_ref()));
        std::process::exit(lgh_cli::exit_code(e.as_ref()));
    }
}
