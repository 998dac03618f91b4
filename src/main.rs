//! `beadchain` command line: run scenes, compare engines, export and inspect snapshots.
//!
//! Exit codes: 0 success; 1 `check` found the engines disagreeing beyond tolerance; 2 bad input
//! (scene, snapshot or arguments) or a failed run. No output file is left behind on failure.

mod cli;

use clap::Parser;

fn main() {
    let args = cli::Cli::parse();
    match cli::dispatch(args) {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            eprintln!("beadchain: error: {e:#}");
            std::process::exit(2);
        }
    }
}
