//! `rbtrack`: command-line front end of the host harness.
//!
//! ```text
//! rbtrack <subcommand> [options]
//! rbtrack paper [--runs 10] [--particles 200] [--json] [--plots DIR]
//! ```
//! Each subcommand parses its own options; arguments are hand-parsed (no dependency).

use std::process::ExitCode;

use rbtrack_host::paper;

/// Top-level usage text.
const USAGE: &str = "usage: rbtrack <subcommand> [options]

subcommands:
  paper   the RBPF paper's simulation study (section 3.1): RBPF against PF, the
          dependency sweep S = 1..15 and the particle-count comparison
  help    this text

run `rbtrack <subcommand> --help` for its options";

/// Usage of `rbtrack paper`.
const PAPER_USAGE: &str = "usage: rbtrack paper [--runs N] [--particles N] [--json] [--plots DIR]

  --runs N        runs (seeds 1..=N), default 10
  --particles N   particles for the main comparison and the sweep, default 200 (max 65535)
  --json          print JSON instead of the table
  --plots DIR     also write PNG figures into DIR";

/// A command-line mistake, with the message to print above the usage.
struct CliError(String);

/// Options of `rbtrack paper`.
#[derive(Debug)]
struct PaperArgs {
    runs: usize,
    particles: usize,
    json: bool,
    plots: Option<std::path::PathBuf>,
}

fn parse_count(flag: &str, value: Option<String>, max: usize) -> Result<usize, CliError> {
    let value = value.ok_or_else(|| CliError(format!("{flag} needs a value")))?;
    match value.parse::<usize>() {
        Ok(n) if (1..=max).contains(&n) => Ok(n),
        _ => Err(CliError(format!(
            "{flag}: expected a whole number in 1..={max}, got {value:?}"
        ))),
    }
}

fn parse_paper(args: impl Iterator<Item = String>) -> Result<Option<PaperArgs>, CliError> {
    let mut out = PaperArgs {
        runs: paper::RUNS,
        particles: paper::PARTICLES,
        json: false,
        plots: None,
    };
    let mut args = args;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--runs" => out.runs = parse_count("--runs", args.next(), 10_000)?,
            "--particles" => {
                out.particles = parse_count("--particles", args.next(), u16::MAX as usize)?
            }
            "--json" => out.json = true,
            "--plots" => {
                let dir = args
                    .next()
                    .ok_or_else(|| CliError("--plots needs a directory".into()))?;
                out.plots = Some(dir.into());
            }
            "-h" | "--help" => return Ok(None),
            other => return Err(CliError(format!("unknown option {other:?}"))),
        }
    }
    Ok(Some(out))
}

fn run_paper(args: impl Iterator<Item = String>) -> ExitCode {
    let opts = match parse_paper(args) {
        Ok(Some(o)) => o,
        Ok(None) => {
            println!("{PAPER_USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(CliError(msg)) => {
            eprintln!("rbtrack paper: {msg}\n\n{PAPER_USAGE}");
            return ExitCode::from(2);
        }
    };
    let params = paper::Params::STUDY;
    let study = paper::study(&params, opts.runs, opts.particles);
    if opts.json {
        println!("{}", paper::json(&study, &params));
    } else {
        print!("{}", paper::table(&study, &params));
    }
    if let Some(dir) = opts.plots {
        match paper::write_plots(&study, &dir) {
            Ok(files) => {
                for f in files {
                    eprintln!("wrote {}", f.display());
                }
            }
            Err(e) => {
                eprintln!("rbtrack paper: plots: {e}");
                return ExitCode::FAILURE;
            }
        }
    }
    ExitCode::SUCCESS
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    match args.next().as_deref() {
        Some("paper") => run_paper(args),
        Some("help" | "-h" | "--help") => {
            println!("{USAGE}");
            ExitCode::SUCCESS
        }
        Some(other) => {
            eprintln!("rbtrack: unknown subcommand {other:?}\n\n{USAGE}");
            ExitCode::from(2)
        }
        None => {
            eprintln!("{USAGE}");
            ExitCode::from(2)
        }
    }
}
