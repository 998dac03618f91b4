//! `beadchain` command line: run scenes, compare engines, export and inspect snapshots.
//!
//! Exit codes: 0 success; 1 `check` found the engines disagreeing beyond tolerance; 2 bad input
//! (scene, snapshot or arguments) or a failed run. Errors are one line on standard error, but
//! for argument errors found by the parser, which keep clap's whole message (missing arguments,
//! valid values, "did you mean", usage) after their `beadchain: error:` line; no command at all
//! prints the command list (exit 2). No output file is left behind on failure.
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
        Err(e) => exit_on_parse_error(&e),
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

/// Prints a parser error the way clap means it and exits. Help and version go to standard
/// output (exit 0). A missing command (bare `beadchain`, `beadchain plot`) prints that level's
/// help, command list included, on standard error (exit 2, clap's usage-error code). Every
/// other error is clap's whole message, first line `beadchain: error: …`, then clap's
/// context: the missing arguments, the valid values, a "did you mean" tip, the usage line.
fn exit_on_parse_error(e: &clap::Error) -> ! {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            let _ = e.print();
            std::process::exit(0);
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            std::process::exit(2);
        }
        _ => {
            let text = e.to_string();
            let body = text.strip_prefix("error: ").unwrap_or(&text);
            eprint!("beadchain: error: {}", body);
            if !body.ends_with('\n') {
                eprintln!();
            }
            std::process::exit(2);
        }
    }
}

/// The error and its causes on one line, skipping a cause whose text the message already holds
/// and writing once what a context and its cause both begin with;
/// control characters (a tab or newline in a file name) are escaped (`\t`, `\n`), so the line
/// shows the name as it is.
fn one_line(e: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in e.chain() {
        let text = cause.to_string();
        if out.contains(&text) {
            continue;
        }
        if !out.is_empty() && text.starts_with(&out) {
            out = text; // a cause that names what the context named (`f.snap: f.snap: …`)
            continue;
        }
        if !out.is_empty() {
            out.push_str(": ");
        }
        out.push_str(&text);
    }
    beadchain::scene::error::one_line(&out)
}
