//! `beadchain` command line: run scenes, compare engines, export and inspect snapshots.
//!
//! Exit codes: 0 success; 1 `check` found the engines disagreeing beyond tolerance; 2 bad input
//! (scene, snapshot or arguments) or a failed run. Errors are one line on standard error. No
//! output file is left behind on failure.
//!
//! Standard output closed early (`beadchain scenes | head -1`, `export | head`): every write to
//! standard output goes through [`outln!`]/[`out!`], which return the write error instead of
//! panicking like `println!`; `main` turns a broken pipe into a quiet exit 0, as `head` users
//! expect (Rust ignores SIGPIPE, so the write fails with EPIPE instead of killing the process).

/// `println!` that returns the error (`?`) instead of panicking when standard output is closed.
macro_rules! outln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        writeln!(std::io::stdout().lock(), $($arg)*)?
    }};
}

/// `print!` that returns the error (`?`) instead of panicking when standard output is closed.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let mut lock = std::io::stdout().lock();
        write!(lock, $($arg)*)?;
        lock.flush()?
    }};
}

mod cli;

use clap::{CommandFactory, FromArgMatches};

/// Every (sub)command takes negative numbers as values (`--every -1` is then refused by the
/// validator with the real reason, not by the parser as an unknown flag).
fn allow_negative_numbers(c: clap::Command) -> clap::Command {
    c.allow_negative_numbers(true)
        .mut_subcommands(allow_negative_numbers)
}

/// `--key -1e-8` → `--key=-1e-8`: clap takes `-1` but not `-1e-8` for a negative number.
fn join_negative_values(args: Vec<std::ffi::OsString>) -> Vec<std::ffi::OsString> {
    let mut out: Vec<std::ffi::OsString> = Vec::with_capacity(args.len());
    for a in args {
        let joins = a
            .to_str()
            .is_some_and(|s| s.starts_with('-') && s.parse::<f64>().is_ok())
            && out
                .last()
                .and_then(|p| p.to_str())
                .is_some_and(|p| p.starts_with("--") && p.len() > 2 && !p.contains('='));
        match out.last_mut() {
            Some(prev) if joins => {
                prev.push("=");
                prev.push(&a);
            }
            _ => out.push(a),
        }
    }
    out
}

fn parse() -> Result<cli::Cli, clap::Error> {
    let args = join_negative_values(std::env::args_os().collect());
    let matches = allow_negative_numbers(cli::Cli::command()).try_get_matches_from(args)?;
    cli::Cli::from_arg_matches(&matches)
}

fn main() {
    let args = match parse() {
        Ok(a) => a,
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
                let _ = e.print();
                std::process::exit(0);
            }
            // clap's message is several lines (usage, hint): keep the first, as one line.
            let text = e.to_string();
            let first = text.lines().next().unwrap_or("invalid arguments");
            let first = first.trim_start_matches("error: ");
            eprintln!("beadchain: error: {first} (see `beadchain --help`)");
            std::process::exit(2);
        }
    };
    match cli::dispatch(args) {
        Ok(code) => std::process::exit(code),
        Err(e) if cli::is_broken_pipe(&e) => std::process::exit(0),
        Err(e) => {
            eprintln!("beadchain: error: {}", one_line(&e));
            std::process::exit(2);
        }
    }
}

/// The error and its causes on one line, skipping a cause whose text the message already holds.
fn one_line(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if out.contains(&text) {
            continue;
        }
        if !out.is_empty() {
            out.push_str(": ");
        }
        out.push_str(&text);
    }
    out.replace('\n', " ")
}
