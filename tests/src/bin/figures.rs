//! `figures check` and `figures refresh [ID …]` (through `tools/figures`): the published
//! figures of `docs/figures.json` checked against the pages, or measured again
//! (`lgh_tests::figures`).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

use lgh_tests::figures;

const USAGE: &str = "usage: tools/figures check | tools/figures refresh [ID ...] \
                     | tools/figures take OUTPUT.json CORES CPU ID ...";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = match Command::new("git")
        .args(["rev-parse", "--show-toplevel"])
        .output()
    {
        Ok(out) if out.status.success() => {
            PathBuf::from(String::from_utf8_lossy(&out.stdout).trim())
        }
        _ => {
            eprintln!("figures: run it inside the repository (git rev-parse failed)");
            return ExitCode::FAILURE;
        }
    };
    let result = match args.first().map(String::as_str) {
        Some("check") if args.len() == 1 => figures::check(&root),
        Some("refresh") => figures::refresh(&root, &args[1..]),
        Some("take") if args.len() >= 5 => match args[2].parse::<u64>() {
            Ok(cores) => {
                let machine = serde_json::json!({ "cores": cores, "cpu": args[3] });
                figures::take(&root, Path::new(&args[1]), machine, &args[4..])
            }
            Err(_) => Err(format!("CORES: {:?} is not a count", args[2])),
        },
        _ => {
            eprintln!("{USAGE}");
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(lines) if args[0] == "check" && !lines.is_empty() => {
            for l in &lines {
                eprintln!("{l}");
            }
            eprintln!("figures: {} problems", lines.len());
            ExitCode::FAILURE
        }
        Ok(lines) => {
            for l in &lines {
                println!("{l}");
            }
            if args[0] == "check" {
                println!("figures: every published figure is its entry's");
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("figures: {e}");
            ExitCode::FAILURE
        }
    }
}
