//! `rbtrack`: the command-line program of the host harness. It parses the command line
//! and hands each subcommand to [`rbtrack_host::cli`]. Exit codes: 0 success (also when
//! the reader of stdout closes it early), 1 a failure while running (bad data, unwritable
//! output, a sequence of `eval` skipped), 2 a command-line mistake.

use clap::Parser;
use rbtrack_host::cli::{self, args, Failure};
use std::io::ErrorKind;
use std::process::ExitCode;

fn main() -> ExitCode {
    let command = match args::Cli::try_parse() {
        Ok(parsed) => parsed.command,
        Err(e) => return ExitCode::from(args::report(&e)),
    };
    let mut out = std::io::stdout().lock();
    let (name, outcome) = match &command {
        args::Command::Demo(a) => ("demo", cli::demo(a, &mut out).map(|()| true)),
        args::Command::Track(a) => ("track", cli::track(a, &mut out).map(|()| true)),
        args::Command::Eval(a) => ("eval", cli::eval(a, &mut out)),
        args::Command::Port(a) => ("port", cli::port(a, &mut out)),
        args::Command::Cost(a) => ("cost", cli::cost(a, &mut out)),
        args::Command::Follow(a) => ("follow", cli::follow(a, &mut out).map(|()| true)),
        args::Command::Frames(a) => ("frames", cli::frames(a, &mut out).map(|()| true)),
        args::Command::Paper(a) => ("paper", cli::paper(a, &mut out).map(|()| true)),
    };
    match outcome {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(Failure::Output(e)) if e.kind() == ErrorKind::BrokenPipe => ExitCode::SUCCESS,
        Err(f) => {
            eprintln!("rbtrack {name}: {f}");
            ExitCode::FAILURE
        }
    }
}
