//! `rbtrack`: command-line front end of the host harness.
//!
//! ```text
//! rbtrack <subcommand> [options]
//! rbtrack demo [--out DIR] [--scene NAME] [--frames N] [--no-gif]
//! rbtrack track SEQ_DIR [--tracker rbpf|pf] [--particles N] [--seed S] [--format F]
//!               [--init x,y,w,h] [--boxes FILE] [--overlay DIR] [--json]
//! rbtrack eval DATA_DIR [--tracker rbpf|pf|both] [--particles N] [--seed S] [--format F]
//!              [--out DIR] [--boxes DIR] [--overlay DIR] [--json]
//! rbtrack paper [--runs 10] [--particles 200] [--json] [--plots DIR]
//! ```
//! Each subcommand parses its own options; arguments are hand-parsed (no dependency). The
//! work is in [`rbtrack_host::cli`]. Exit codes: 0 success, 1 a failure while running (bad
//! data, unwritable output), 2 a command-line mistake.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use rbtrack_host::cli::{self, Failure, Settings, TrackerKind};
use rbtrack_host::metrics::BBox;
use rbtrack_host::paper;
use rbtrack_host::progress::Progress;
use rbtrack_host::run::PARTICLE_COUNTS;
use rbtrack_host::scene::Variant;
use rbtrack_host::sequence::{self, Sequence};

/// Top-level usage text.
const USAGE: &str = "usage: rbtrack <subcommand> [options]

subcommands:
  demo    track the built-in synthetic scene with both trackers: metrics table, image
          strip, animated GIF, success and precision plots
            rbtrack demo [--out DIR] [--scene NAME] [--frames N] [--no-gif]
  track   track one sequence folder (OTB layout: img/*.jpg|png, groundtruth_rect.txt)
            rbtrack track SEQ_DIR [--tracker rbpf|pf] [--particles N] [--seed S]
                  [--format rgb888|rgb565] [--init x,y,w,h] [--boxes FILE]
                  [--overlay DIR] [--json]
  eval    track every sequence folder of DATA_DIR: table per sequence and the mean,
          success and precision plots
            rbtrack eval DATA_DIR [--tracker rbpf|pf|both] [--particles N] [--seed S]
                  [--format rgb888|rgb565] [--out DIR] [--boxes DIR] [--overlay DIR]
                  [--json]
  paper   the RBPF paper's simulation study (section 3.1): RBPF against PF, the
          dependency sweep S = 1..15 and the particle-count comparison
            rbtrack paper [--runs N] [--particles N] [--json] [--plots DIR]
  help    this text

run `rbtrack <subcommand> --help` for its options";

/// Usage of `rbtrack demo`.
const DEMO_USAGE: &str = "usage: rbtrack demo [--out DIR] [--scene NAME] [--frames N] [--no-gif]

Tracks a built-in synthetic scene (seed 1, 320x240; the perspective walk unless --scene)
with the RBPF and the colour PF (100 particles each, the scene's settings), prints a
metrics table and writes into DIR: strip.png (8 frames), demo.gif (every second frame),
success.png and precision.png. Ground truth is drawn as a green box, the RBPF's ellipse
yellow, the PF's cyan.

  --out DIR      output folder, default out/demo
  --scene NAME   perspective (default), distractor, occlusion, brightness, fast or leave
  --frames N     scene length, 10..=1000, default 100
  --no-gif       skip the animated GIF";

/// Usage of `rbtrack track`.
const TRACK_USAGE: &str = "usage: rbtrack track SEQ_DIR [options]

Tracks the sequence in SEQ_DIR (frames SEQ_DIR/img/*.jpg|png in numeric order, ground truth
SEQ_DIR/groundtruth_rect.txt, one x,y,w,h line per frame) from the first ground-truth box,
and prints success AUC, precision at 20 px, mean IoU, success rate (IoU > 0.5) and
tracking-only ms per frame (decoding excluded).

  --tracker T       rbpf (default) or pf (colour particle filter)
  --particles N     one of 25, 50, 100, 200, 400, 800; default 100
  --seed S          seed of the tracker's random draws, default 1
  --format F        pixels handed to the tracker: rgb888 (default) or rgb565
  --init x,y,w,h    initial box instead of the first ground-truth line, in the ground-truth
                    file's convention (1-based; 0-based for *_vot* folders); with --init the
                    ground-truth file may be missing (scores are then omitted)
  --boxes FILE      write the estimated box per frame, one x,y,w,h line each (first line:
                    the initial box), in the ground-truth file's convention
  --overlay DIR     write every frame as DIR/0001.png, ... with the estimate (ellipse:
                    rbpf yellow, pf cyan) and the ground truth (green box) drawn
  --json            print one JSON object: sequence, tracker, frames, auc, prec20, miou,
                    success_rate, ms_per_frame, particles, seed, format (scores null
                    without ground truth)";

/// Usage of `rbtrack eval`.
const EVAL_USAGE: &str = "usage: rbtrack eval DATA_DIR [options]

Tracks every sequence folder of DATA_DIR (sorted by name; folders without img/ are skipped
with a note) from its first ground-truth box. Prints a table per sequence and the mean
over sequences, writes success and precision plots (one curve per sequence and the mean)
and shows progress on stderr.

  --tracker T       rbpf (default), pf, or both
  --particles N     one of 25, 50, 100, 200, 400, 800; default 100
  --seed S          seed of the trackers' random draws, default 1
  --format F        rgb888 (default) or rgb565
  --out DIR         plot folder, default out/eval (success.png, precision.png; with
                    --tracker both also success_rbpf.png, success_pf.png, ...)
  --boxes DIR       write DIR/<sequence>.txt (DIR/<sequence>_<tracker>.txt for both)
  --overlay DIR     write DIR/<sequence>/0001.png, ... with every estimate drawn
  --json            print one JSON object: data_dir, particles, seed, format, trackers,
                    sequences (one object per sequence and tracker, keys as track's) and
                    mean (one object per tracker)";

/// Usage of `rbtrack paper`.
const PAPER_USAGE: &str = "usage: rbtrack paper [--runs N] [--particles N] [--json] [--plots DIR]

  --runs N        runs (seeds 1..=N), default 10
  --particles N   particles for the main comparison and the sweep, default 200 (max 65535)
  --json          print JSON instead of the table
  --plots DIR     also write PNG figures into DIR";

/// A command-line mistake.
#[derive(Debug)]
enum CliError {
    /// Unknown option or missing argument: reported with the usage text.
    Usage(String),
    /// A bad option value: reported on one line.
    Value(String),
}

/// Reports a parse error of subcommand `cmd` on stderr; exit code 2.
fn report(cmd: &str, usage: &str, e: CliError) -> ExitCode {
    match e {
        CliError::Usage(msg) => eprintln!("rbtrack {cmd}: {msg}\n\n{usage}"),
        CliError::Value(msg) => eprintln!("rbtrack {cmd}: {msg}"),
    }
    ExitCode::from(2)
}

/// Reports a failure of subcommand `cmd` on one line of stderr; exit code 1.
fn failed(cmd: &str, f: Failure) -> ExitCode {
    eprintln!("rbtrack {cmd}: {f}");
    ExitCode::FAILURE
}

/// Options of `rbtrack paper`.
#[derive(Debug)]
struct PaperArgs {
    runs: usize,
    particles: usize,
    json: bool,
    plots: Option<std::path::PathBuf>,
}

/// The value after `flag`.
fn value_of(flag: &str, value: Option<String>) -> Result<String, CliError> {
    value.ok_or_else(|| CliError::Value(format!("{flag} needs a value")))
}

fn parse_count(flag: &str, value: Option<String>, max: usize) -> Result<usize, CliError> {
    parse_range(flag, value, 1, max)
}

fn parse_range(
    flag: &str,
    value: Option<String>,
    min: usize,
    max: usize,
) -> Result<usize, CliError> {
    let value = value_of(flag, value)?;
    match value.parse::<usize>() {
        Ok(n) if (min..=max).contains(&n) => Ok(n),
        _ => Err(CliError::Value(format!(
            "{flag}: expected a whole number in {min}..={max}, got {value:?}"
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
                    .ok_or_else(|| CliError::Value("--plots needs a directory".into()))?;
                out.plots = Some(dir.into());
            }
            "-h" | "--help" => return Ok(None),
            other => return Err(CliError::Usage(format!("unknown option {other:?}"))),
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
        Err(e) => return report("paper", PAPER_USAGE, e),
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

/// Options of `rbtrack demo`.
#[derive(Debug)]
struct DemoArgs {
    out: PathBuf,
    scene: Variant,
    frames: usize,
    gif: bool,
}

fn parse_demo(args: impl Iterator<Item = String>) -> Result<Option<DemoArgs>, CliError> {
    let mut out = DemoArgs {
        out: PathBuf::from("out/demo"),
        scene: Variant::Perspective,
        frames: 100,
        gif: true,
    };
    let mut args = args;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--out" => out.out = value_of("--out", args.next())?.into(),
            "--scene" => {
                let name = value_of("--scene", args.next())?;
                out.scene = Variant::from_name(&name).ok_or_else(|| {
                    CliError::Value(format!(
                        "--scene: expected perspective, distractor, occlusion, brightness, \
                         fast or leave, got {name:?}"
                    ))
                })?;
            }
            "--frames" => out.frames = parse_range("--frames", args.next(), 10, 1000)?,
            "--no-gif" => out.gif = false,
            "-h" | "--help" => return Ok(None),
            other => return Err(CliError::Usage(format!("unknown option {other:?}"))),
        }
    }
    Ok(Some(out))
}

fn run_demo(args: impl Iterator<Item = String>) -> ExitCode {
    let opts = match parse_demo(args) {
        Ok(Some(o)) => o,
        Ok(None) => {
            println!("{DEMO_USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(e) => return report("demo", DEMO_USAGE, e),
    };
    let demo = match cli::demo(&opts.out, opts.scene, opts.frames, opts.gif) {
        Ok(d) => d,
        Err(f) => return failed("demo", f),
    };
    let r = &demo.result;
    println!(
        "synthetic scene: {}, seed 1, {}x{} px, {} frames; 100 particles per tracker; \
         ms/frame is tracking only\n",
        opts.scene.name(),
        r.width,
        r.height,
        r.frames
    );
    print!("{}", cli::tracker_table(r));
    println!(
        "\nframes: ground truth green, {}",
        r.runs
            .iter()
            .map(|t| format!("{} {}", t.tracker, t.tracker.colour_name()))
            .collect::<Vec<_>>()
            .join(", ")
    );
    for f in &demo.files {
        println!("wrote {}", f.display());
    }
    ExitCode::SUCCESS
}

/// Which subcommand [`parse_seq`] parses for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SeqCmd {
    Track,
    Eval,
}

/// Options of `rbtrack track` and `rbtrack eval`.
#[derive(Debug)]
struct SeqArgs {
    /// The sequence folder (track) or data folder (eval).
    dir: PathBuf,
    settings: Settings,
    /// `--init`, as written (the ground-truth file's convention).
    init: Option<BBox>,
    /// A file (track) or a folder (eval).
    boxes: Option<PathBuf>,
    overlay: Option<PathBuf>,
    /// Plot folder (eval).
    out: PathBuf,
    json: bool,
}

fn parse_seq(cmd: SeqCmd, args: impl Iterator<Item = String>) -> Result<Option<SeqArgs>, CliError> {
    let mut dir = None;
    let mut out = SeqArgs {
        dir: PathBuf::new(),
        settings: Settings::default(),
        init: None,
        boxes: None,
        overlay: None,
        out: PathBuf::from("out/eval"),
        json: false,
    };
    let mut args = args;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--tracker" => {
                let v = value_of("--tracker", args.next())?;
                out.settings.trackers = match (TrackerKind::from_name(&v), cmd) {
                    (Some(k), _) => vec![k],
                    (None, SeqCmd::Eval) if v.eq_ignore_ascii_case("both") => {
                        TrackerKind::ALL.to_vec()
                    }
                    _ => {
                        let choices = match cmd {
                            SeqCmd::Track => "rbpf or pf",
                            SeqCmd::Eval => "rbpf, pf or both",
                        };
                        return Err(CliError::Value(format!(
                            "--tracker: expected {choices}, got {v:?}"
                        )));
                    }
                };
            }
            "--particles" => {
                let v = value_of("--particles", args.next())?;
                out.settings.particles = v
                    .parse::<usize>()
                    .ok()
                    .filter(|n| PARTICLE_COUNTS.contains(n))
                    .ok_or_else(|| {
                        CliError::Value(format!(
                            "--particles: expected one of {PARTICLE_COUNTS:?}, got {v:?}"
                        ))
                    })?;
            }
            "--seed" => {
                let v = value_of("--seed", args.next())?;
                out.settings.seed = v.parse::<u64>().map_err(|_| {
                    CliError::Value(format!(
                        "--seed: expected a whole number in 0..={}, got {v:?}",
                        u64::MAX
                    ))
                })?;
            }
            "--format" => {
                let v = value_of("--format", args.next())?;
                out.settings.format = cli::format_from_name(&v).ok_or_else(|| {
                    CliError::Value(format!("--format: expected rgb888 or rgb565, got {v:?}"))
                })?;
            }
            "--init" if cmd == SeqCmd::Track => {
                let v = value_of("--init", args.next())?;
                out.init = Some(
                    sequence::parse_bbox(&v)
                        .map_err(|e| CliError::Value(format!("--init: {e}")))?,
                );
            }
            "--boxes" => out.boxes = Some(value_of("--boxes", args.next())?.into()),
            "--overlay" => out.overlay = Some(value_of("--overlay", args.next())?.into()),
            "--out" if cmd == SeqCmd::Eval => out.out = value_of("--out", args.next())?.into(),
            "--init" => {
                return Err(CliError::Usage(
                    "--init applies to `rbtrack track` only (eval starts every sequence from \
                     its first ground-truth box)"
                        .into(),
                ))
            }
            "--json" => out.json = true,
            "-h" | "--help" => return Ok(None),
            other if other.starts_with('-') && other.len() > 1 => {
                return Err(CliError::Usage(format!("unknown option {other:?}")))
            }
            positional => {
                if dir.is_some() {
                    return Err(CliError::Usage(format!(
                        "unexpected argument {positional:?}"
                    )));
                }
                dir = Some(PathBuf::from(positional));
            }
        }
    }
    out.dir = dir.ok_or_else(|| {
        CliError::Usage(match cmd {
            SeqCmd::Track => "missing SEQ_DIR".into(),
            SeqCmd::Eval => "missing DATA_DIR".into(),
        })
    })?;
    Ok(Some(out))
}

fn fail(e: impl std::fmt::Display) -> Failure {
    Failure(e.to_string())
}

/// Prints "wrote ..." lines: on stdout, or on stderr when stdout carries JSON.
fn wrote(json: bool, what: &str) {
    if json {
        eprintln!("wrote {what}");
    } else {
        println!("wrote {what}");
    }
}

fn settings_line(s: &Settings) -> String {
    format!(
        "{}, {} particles, seed {}, {}",
        s.trackers
            .iter()
            .map(|k| k.name())
            .collect::<Vec<_>>()
            .join(" and "),
        s.particles,
        s.seed,
        cli::format_name(s.format)
    )
}

fn track(a: &SeqArgs) -> Result<(), Failure> {
    let seq = match a.init {
        Some(_) => Sequence::open_optional_groundtruth(&a.dir),
        None => Sequence::open(&a.dir),
    }
    .map_err(fail)?;
    let (init, shown) = match a.init {
        Some(b) => (seq.origin.to_zero_based(b), b),
        None => {
            let b = seq.init_box().ok_or_else(|| {
                Failure(format!(
                    "{}: no ground-truth box for the first frame; give --init x,y,w,h",
                    a.dir.join(sequence::GROUNDTRUTH_FILE).display()
                ))
            })?;
            (b, seq.origin.from_zero_based(b))
        }
    };
    cli::check_init(&init, seq.width, seq.height, &shown)?;
    if seq.has_groundtruth() && seq.groundtruth.len() != seq.len() {
        eprintln!(
            "rbtrack track: note: {} ground-truth boxes for {} frames; scoring the first {}",
            seq.groundtruth.len(),
            seq.len(),
            seq.groundtruth.len().min(seq.len())
        );
    }
    let result = cli::track_sequence(&seq, &a.settings, &init, a.overlay.as_deref(), None)?;
    if a.json {
        println!("{}", cli::track_json(&result, &a.settings));
    } else {
        println!(
            "{}: {} frames, {}x{} px; {}; init {}\n",
            result.name,
            result.frames,
            result.width,
            result.height,
            settings_line(&a.settings),
            cli::box_line(&shown)
        );
        print!(
            "{}",
            cli::sequence_table(std::slice::from_ref(&result), &a.settings.trackers)
        );
        if !seq.has_groundtruth() {
            println!("(no ground truth: scores omitted; ms/frame is tracking only)");
        } else {
            println!("(ms/frame is tracking only, decoding excluded)");
        }
    }
    if let (Some(path), Some(run)) = (&a.boxes, result.runs.first()) {
        cli::write_boxes(path, &run.boxes, seq.origin)?;
        wrote(a.json, &path.display().to_string());
    }
    if let Some(dir) = &a.overlay {
        wrote(
            a.json,
            &format!("{} overlay frames into {}", result.frames, dir.display()),
        );
    }
    Ok(())
}

fn run_track(args: impl Iterator<Item = String>) -> ExitCode {
    match parse_seq(SeqCmd::Track, args) {
        Ok(Some(a)) => match track(&a) {
            Ok(()) => ExitCode::SUCCESS,
            Err(f) => failed("track", f),
        },
        Ok(None) => {
            println!("{TRACK_USAGE}");
            ExitCode::SUCCESS
        }
        Err(e) => report("track", TRACK_USAGE, e),
    }
}

/// The sequence folders of `data`, sorted by name; notes the folders without `img/`.
fn sequence_dirs(data: &Path) -> Result<Vec<PathBuf>, Failure> {
    let entries = std::fs::read_dir(data)
        .map_err(|e| Failure(format!("cannot read data folder {}: {e}", data.display())))?;
    let mut dirs: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    Ok(dirs
        .into_iter()
        .filter(|d| {
            let ok = d.join("img").is_dir();
            if !ok {
                eprintln!(
                    "rbtrack eval: note: skipping {}: no img/ folder",
                    d.display()
                );
            }
            ok
        })
        .collect())
}

/// Runs `eval`; `Ok(false)` when some sequence failed (reported and skipped).
fn eval(a: &SeqArgs) -> Result<bool, Failure> {
    let mut all_ok = true;
    let mut skip = |name: &Path, e: &dyn std::fmt::Display| {
        eprintln!("rbtrack eval: skipping {}: {e}", name.display());
        all_ok = false;
    };
    let mut seqs = Vec::new();
    for dir in sequence_dirs(&a.dir)? {
        match Sequence::open(&dir) {
            Ok(s) => seqs.push(s),
            Err(e) => skip(&dir, &e),
        }
    }
    if seqs.is_empty() {
        return Err(Failure(format!(
            "no usable sequence folders (with img/ and {}) in {}",
            sequence::GROUNDTRUTH_FILE,
            a.dir.display()
        )));
    }
    let total = seqs.iter().map(|s| s.len() as u64).sum();
    let mut progress = Progress::new("eval", total);
    let several = a.settings.trackers.len() > 1;
    let mut results = Vec::new();
    let mut written = Vec::new();
    for seq in &seqs {
        let init = match seq
            .init_box()
            .ok_or_else(|| Failure(format!("{} is empty", sequence::GROUNDTRUTH_FILE)))
        {
            Ok(b) => b,
            Err(e) => {
                skip(&seq.dir, &e);
                continue;
            }
        };
        let checked = cli::check_init(
            &init,
            seq.width,
            seq.height,
            &seq.origin.from_zero_based(init),
        );
        let overlay = a.overlay.as_ref().map(|d| d.join(&seq.name));
        let result = checked.and_then(|()| {
            cli::track_sequence(
                seq,
                &a.settings,
                &init,
                overlay.as_deref(),
                Some(&mut progress),
            )
        });
        let result = match result {
            Ok(r) => r,
            Err(e) => {
                skip(&seq.dir, &e);
                continue;
            }
        };
        if let Some(dir) = &a.boxes {
            for run in &result.runs {
                let file = match several {
                    true => format!("{}_{}.txt", seq.name, run.tracker),
                    false => format!("{}.txt", seq.name),
                };
                let path = dir.join(file);
                cli::write_boxes(&path, &run.boxes, seq.origin)?;
                written.push(path.display().to_string());
            }
        }
        if let Some(d) = overlay {
            written.push(format!(
                "{} overlay frames into {}",
                result.frames,
                d.display()
            ));
        }
        results.push(result);
    }
    progress.finish();
    if results.is_empty() {
        return Err(Failure("no sequence could be tracked".into()));
    }
    if a.json {
        println!("{}", cli::eval_json(&a.dir, &results, &a.settings));
    } else {
        println!(
            "{}: {} sequences; {}; mean over sequences; ms/frame is tracking only\n",
            a.dir.display(),
            results.len(),
            settings_line(&a.settings)
        );
        print!("{}", cli::sequence_table(&results, &a.settings.trackers));
    }
    for f in cli::eval_plots(&a.out, &results, &a.settings)? {
        written.push(f.display().to_string());
    }
    for w in &written {
        wrote(a.json, w);
    }
    Ok(all_ok)
}

fn run_eval(args: impl Iterator<Item = String>) -> ExitCode {
    match parse_seq(SeqCmd::Eval, args) {
        Ok(Some(a)) => match eval(&a) {
            Ok(true) => ExitCode::SUCCESS,
            Ok(false) => ExitCode::FAILURE,
            Err(f) => failed("eval", f),
        },
        Ok(None) => {
            println!("{EVAL_USAGE}");
            ExitCode::SUCCESS
        }
        Err(e) => report("eval", EVAL_USAGE, e),
    }
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    match args.next().as_deref() {
        Some("demo") => run_demo(args),
        Some("track") => run_track(args),
        Some("eval") => run_eval(args),
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
