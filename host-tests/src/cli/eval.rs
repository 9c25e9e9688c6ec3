//! `rbtrack eval`: every tracker and seed over every sequence of one or more folders, with
//! each folder's mean and the pooled one. Each sequence's frames are decoded once for all
//! its runs, and the sequences of all folders run in parallel, one thread per available
//! core.

use super::args::EvalArgs;
use super::report::{
    loss_table, mean_rows, plot_pair, reliability_table, sequence_rows, sequence_table, Curves,
    MeanGroup, MeanRow, SequenceRow,
};
use super::runs::{self, check_init, track_frames, write_overlay, RunSpec, SequenceResult, Start};
use super::{
    cf64_for, cf_for, check_read, config_for, config_summary, configured_seed, configured_tracker,
    create_dir, emit, fail, overrides, progress_bar, settings_json, wrote, Failure, TrackerKind,
};
use crate::calibrate::{fit, refit_reliability, score_at};
use crate::camera::{Camera, VirtualCamera};
use crate::cf64::cost::{Operations, Target};
use crate::draw::{self, Series};
use crate::loss::{reliability, worst_gap, Bin, FrameCheck, BINS};
use crate::metrics::{BBox, Evaluation, PRECISION_MAX_PX, SUCCESS_STEPS};
use crate::pixels::Format;
use crate::run::{Bins, Shape};
use crate::sequence::{self, folder_name, GtOrigin, Sequence};
use clap::ValueEnum;
use indicatif::ProgressBar;
use rbtrack::tracker::CameraMotion;
use serde::Serialize;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Default plot folder.
const PLOTS: &str = "out/eval";

/// `eval`'s JSON document.
#[derive(Serialize)]
struct EvalJson<'a> {
    /// The data folder, with one.
    #[serde(skip_serializing_if = "Option::is_none")]
    data_dir: Option<String>,
    data_dirs: Vec<String>,
    particles: usize,
    bins: Bins,
    seeds: &'a [u64],
    starts: &'a [Start],
    /// The virtual camera, if any.
    camera: Option<Camera>,
    format: &'static str,
    box_origin: &'static str,
    zero_based_sequences: &'a [String],
    trackers: &'a [TrackerKind],
    /// Per tracker, the configuration of its first seed's runs (the others differ only in
    /// `seed`).
    config: BTreeMap<&'static str, serde_json::Value>,
    /// The cf64 tracker's operations a frame and the Cortex-M4 instructions they come to
    /// (`cf64::cost`), when it runs.
    cf64_cost: Option<Cf64Cost>,
    sequences: &'a [SequenceRow],
    /// The mean over all sequences.
    mean: &'a [MeanRow],
    /// Each data folder's mean.
    sets: Vec<SetJson<'a>>,
    seconds: f64,
}

/// One data folder's part of `eval`'s JSON document.
#[derive(Serialize)]
struct SetJson<'a> {
    data_dir: String,
    /// Sequences tracked.
    sequences: usize,
    mean: &'a [MeanRow],
}

/// The cost model's estimate of a cf64 configuration.
#[derive(Serialize)]
struct Cf64Cost {
    operations: Operations,
    instructions: u64,
}

/// What every sequence runs with.
pub(super) struct Plan<'a> {
    pub specs: &'a [RunSpec],
    pub shape: Shape,
    pub format: Format,
    pub overlay: Option<&'a Path>,
    pub camera: Option<Camera>,
    pub label_seeds: bool,
    pub bar: &'a ProgressBar,
}

/// Runs `rbtrack eval`; `Ok(false)` when some sequence failed (reported and skipped).
pub fn eval(args: &EvalArgs, out: &mut dyn Write) -> Result<bool, Failure> {
    let started = Instant::now();
    let overrides = overrides(&args.config)?;
    let trackers = match args.tracker {
        Some(choice) => choice.trackers(),
        None => vec![configured_tracker(&overrides).unwrap_or(TrackerKind::DEFAULT)],
    };
    check_read(&overrides, &trackers)?;
    let seeds = match (&args.seeds[..], args.seed) {
        ([], Some(seed)) => vec![seed],
        ([], None) => vec![configured_seed(&overrides)],
        (seeds, _) => seeds.to_vec(),
    };
    if let Some(twice) = seeds
        .iter()
        .find(|s| seeds.iter().filter(|t| t == s).count() > 1)
    {
        return Err(fail(format!("--seeds: seed {twice} is given twice")));
    }
    let starts = args.starts.starts();
    let mut specs = Vec::new();
    for &tracker in &trackers {
        for &seed in &seeds {
            let config = config_for(&overrides, tracker, seed)?;
            let cf64 = cf64_for(&overrides, tracker)?;
            for &start in starts {
                specs.push(RunSpec {
                    tracker,
                    config,
                    cf64,
                    cf: cf_for(&overrides, tracker)?,
                    start,
                });
            }
        }
    }

    let mut all_ok = true;
    let mut skip = |name: &Path, e: &dyn std::fmt::Display| {
        eprintln!("rbtrack eval: skipping {}: {e}", name.display());
        all_ok = false;
    };
    let Folders { seqs, folder_of } = open_folders(
        &args.data,
        &args.zero_based_sequences,
        args.convention.origin(),
        "eval",
        &mut skip,
    )?;

    let bar = progress_bar(Some(seqs.iter().map(|s| s.len() as u64).sum()), "eval");
    let plan = Plan {
        specs: &specs,
        shape: args.config.shape(),
        format: args.format,
        overlay: args.overlay.as_deref(),
        camera: args.camera,
        label_seeds: seeds.len() > 1,
        bar: &bar,
    };
    let outcomes = run_in_parallel(&seqs, &plan);
    bar.finish_and_clear();
    let mut results = Vec::new();
    let mut tracked = vec![0; args.data.len()];
    for ((seq, &k), outcome) in seqs.iter().zip(&folder_of).zip(outcomes) {
        match outcome {
            Ok(r) => {
                results.push(r);
                tracked[k] += 1;
            }
            Err(e) => skip(&seq.dir, &e),
        }
    }
    if results.is_empty() {
        return Err(fail("no sequence could be tracked"));
    }
    // Each folder's results: consecutive in `results`.
    let mut rest = &results[..];
    let sets: Vec<&[SequenceResult]> = tracked
        .iter()
        .map(|&n| {
            let (set, tail) = rest.split_at(n);
            rest = tail;
            set
        })
        .collect();

    let mut written = Vec::new();
    if let Some(dir) = &args.boxes {
        for s in &results {
            for run in &s.runs {
                let mut file = s.name.clone();
                if trackers.len() > 1 {
                    file += &format!("_{}", run.tracker());
                }
                if seeds.len() > 1 {
                    file += &format!("_seed{}", run.seed());
                }
                if starts.len() > 1 {
                    file += &format!("_{}", run.start().name);
                }
                let path = dir.join(file + ".txt");
                runs::write_boxes(&path, &run.boxes, s.origin)?;
                written.push(path.display().to_string());
            }
        }
    }
    if let Some(dir) = &args.overlay {
        for s in &results {
            let d = dir.join(&s.name);
            written.push(format!("{} overlay frames into {}", s.frames, d.display()));
        }
    }

    let rows = sequence_rows(&results, &trackers);
    // Each folder's mean rows, then the pooled ones.
    let mut groups: Vec<MeanGroup> = args
        .data
        .iter()
        .zip(&sets)
        .map(|(dir, set)| MeanGroup {
            scope: format!(" {}", dir.display()),
            rows: mean_rows(set, &trackers, &seeds, starts),
        })
        .collect();
    groups.push(MeanGroup {
        scope: String::new(),
        rows: mean_rows(&results, &trackers, &seeds, starts),
    });
    let pooled = &groups[sets.len()].rows;
    let seconds = started.elapsed().as_secs_f64();
    if args.json {
        let config = specs
            .iter()
            .filter(|s| s.config.seed == seeds[0] && s.start == Start::GIVEN)
            .map(|s| (s.tracker.name(), settings_json(s)))
            .collect();
        let doc = EvalJson {
            data_dir: match &args.data[..] {
                [one] => Some(one.display().to_string()),
                _ => None,
            },
            data_dirs: args.data.iter().map(|d| d.display().to_string()).collect(),
            particles: args.config.particles,
            bins: args.config.bins,
            seeds: &seeds,
            starts,
            camera: args.camera,
            format: args.format.name(),
            box_origin: args.convention.origin().name(),
            zero_based_sequences: &args.zero_based_sequences,
            trackers: &trackers,
            config,
            cf64_cost: specs.iter().find_map(|s| s.cf64).map(|p| {
                let operations = Operations::of(&p, Target::scene(1.0));
                Cf64Cost {
                    operations,
                    instructions: operations.instructions(),
                }
            }),
            sequences: &rows,
            mean: pooled,
            sets: args
                .data
                .iter()
                .zip(&sets)
                .zip(&groups)
                .map(|((dir, set), g)| SetJson {
                    data_dir: dir.display().to_string(),
                    sequences: set.len(),
                    mean: &g.rows,
                })
                .collect(),
            seconds,
        };
        let text = serde_json::to_string(&doc).map_err(fail)?;
        emit(out, &format!("{text}\n"))?;
    } else {
        emit(out, &header(args, &sets, &trackers, &seeds, &specs))?;
        // One folder's mean is the pooled one, shown once.
        let shown = &groups[if sets.len() > 1 { 0 } else { 1 }..];
        emit(
            out,
            &sequence_table(
                &rows,
                if results.len() > 1 { shown } else { &[] },
                specs.len() > trackers.len(),
            ),
        )?;
        if seeds.len() > 1 {
            emit(out, &per_seed_means(shown))?;
        }
        if starts.len() > 1 {
            emit(out, &per_start_means(shown))?;
        }
        emit(out, &loss_table(&rows, shown))?;
        emit(out, &reliability_table(shown))?;
    }
    if args.calibrate {
        emit(out, &calibration_fits(&results, &specs, &trackers))?;
    }
    if !args.json || args.plots || args.out.is_some() {
        let dir = args.out.clone().unwrap_or_else(|| PathBuf::from(PLOTS));
        for f in eval_plots(
            &dir,
            &results,
            pooled,
            &specs,
            &trackers,
            args.config.particles,
        )? {
            written.push(f.display().to_string());
        }
    }
    for w in &written {
        wrote(out, args.json, w)?;
    }
    let runs = results
        .iter()
        .map(|s| s.runs.len() * s.frames)
        .sum::<usize>();
    eprintln!(
        "rbtrack eval: {} sequences x {} runs, {runs} tracked frames in {seconds:.1} s",
        results.len(),
        specs.len()
    );
    Ok(all_ok)
}

/// The sequences of one or more data folders, folder by folder.
pub(super) struct Folders {
    /// The sequences opened.
    pub seqs: Vec<Sequence>,
    /// The index of each one's folder.
    pub folder_of: Vec<usize>,
}

/// Opens every sequence folder of each of `data`, its ground truth 0-based if named in
/// `zero_based`, else counted from `origin`; a sequence that cannot be opened is handed to
/// `skip`. Fails on a folder name in two data folders, a `zero_based` name in none, and a
/// data folder without a usable sequence. `command` names the command in notes.
pub(super) fn open_folders(
    data: &[PathBuf],
    zero_based: &[String],
    origin: GtOrigin,
    command: &str,
    skip: &mut dyn FnMut(&Path, &dyn std::fmt::Display),
) -> Result<Folders, Failure> {
    let folders = data
        .iter()
        .map(|d| sequence_dirs(d, command))
        .collect::<Result<Vec<_>, _>>()?;
    let mut seen = BTreeMap::new();
    for dir in folders.iter().flatten() {
        if let Some(first) = seen.insert(folder_name(dir), dir) {
            return Err(fail(format!(
                "sequence {:?} is in two data folders: {} and {}",
                folder_name(dir),
                first.display(),
                dir.display()
            )));
        }
    }
    for name in zero_based {
        if !seen.contains_key(name) {
            return Err(fail(format!(
                "--zero-based-sequences: no sequence folder {name:?} in {}",
                listed(data)
            )));
        }
    }
    let (mut seqs, mut folder_of) = (Vec::new(), Vec::new());
    for (k, (dir_of_set, dirs)) in data.iter().zip(folders).enumerate() {
        let opened = seqs.len();
        for dir in dirs {
            let origin = match zero_based.contains(&folder_name(&dir)) {
                true => GtOrigin::ZeroBased,
                false => origin,
            };
            match Sequence::open(&dir, origin) {
                Ok(s) => {
                    seqs.push(s);
                    folder_of.push(k);
                }
                Err(e) => skip(&dir, &e),
            }
        }
        if seqs.len() == opened {
            return Err(fail(format!(
                "no usable sequence folders (with img/ and {}) in {}",
                sequence::GROUNDTRUTH_FILE,
                dir_of_set.display()
            )));
        }
    }
    Ok(Folders { seqs, folder_of })
}

/// The data folders, comma-separated.
fn listed(dirs: &[PathBuf]) -> String {
    let shown: Vec<String> = dirs.iter().map(|d| d.display().to_string()).collect();
    shown.join(", ")
}

/// The lines above `eval`'s table: what ran, on which folders' `sets` of results, with
/// which configuration.
fn header(
    args: &EvalArgs,
    sets: &[&[SequenceResult]],
    trackers: &[TrackerKind],
    seeds: &[u64],
    specs: &[RunSpec],
) -> String {
    let names: Vec<&str> = trackers.iter().map(|t| t.name()).collect();
    let seeds_text: Vec<String> = seeds.iter().map(u64::to_string).collect();
    let counts: Vec<String> = sets.iter().map(|s| s.len().to_string()).collect();
    let mut text = format!(
        "{}: {} sequences{}; {}, {} particles, seed{} {}, {}; {}",
        listed(&args.data),
        sets.iter().map(|s| s.len()).sum::<usize>(),
        match &counts[..] {
            [_] => String::new(),
            _ => format!(" ({})", counts.join(" + ")),
        },
        names.join(" and "),
        args.config.particles,
        if seeds.len() > 1 { "s" } else { "" },
        seeds_text.join(", "),
        args.format,
        match sets {
            [_] => "mean over sequences",
            _ => "means over each folder's sequences and over all of them",
        }
    );
    let starts = specs.len() / (seeds.len() * trackers.len()).max(1);
    if starts > 1 {
        text += &format!(
            "; {starts} starts per seed (the first ground-truth box, shifted 2 px left, \
             right, up and down, scaled by 0.95 and 1.05)"
        );
    }
    if specs.len() > trackers.len() {
        text += "; scores are means over the runs, AUC min and max the lowest and highest \
                 run (for mean: of the set's mean AUC per seed)";
    }
    if let Some(camera) = args.camera {
        text += &format!(
            "; virtual camera {}: a window 3/4 of each frame's width and height, first centred on the target, {}",
            camera
                .to_possible_value()
                .map_or(String::new(), |v| v.get_name().to_owned()),
            match camera {
                Camera::Still => "still",
                Camera::Pan => "sweeping back and forth keeping the target in view, the tracker not told",
                Camera::PanKnown => "sweeping back and forth keeping the target in view, the tracker told each shift",
            }
        );
    }
    text += "; ms/frame is tracking only\n";
    for s in specs
        .iter()
        .filter(|s| s.config.seed == seeds[0] && s.start == Start::GIVEN)
    {
        text += &format!("config {}: {}\n", s.tracker, config_summary(s));
        if let Some(params) = &s.cf64 {
            text += &format!(
                "cf64 estimated Cortex-M4 instructions a frame (cf64::cost, the budget example's scene): {}\n",
                Operations::of(params, Target::scene(1.0)).instructions()
            );
        }
    }
    text + "\n"
}

/// One line per group: `what{scope}: ` and `part` of each of its rows, `; `-separated.
fn group_lines(groups: &[MeanGroup], what: &str, part: impl Fn(&MeanRow) -> String) -> String {
    let mut text = String::new();
    for g in groups {
        let parts: Vec<String> = g.rows.iter().map(&part).collect();
        text += &format!("{what}{}: {}\n", g.scope, parts.join("; "));
    }
    text
}

/// Each group's mean AUC of each seed, per tracker.
fn per_seed_means(groups: &[MeanGroup]) -> String {
    let lines = group_lines(groups, "mean AUC per seed", |m| {
        let per_seed: Vec<String> = m
            .scores
            .per_seed
            .iter()
            .map(|s| format!("{} {:.3}", s.seed, s.scores.auc.unwrap_or(f64::NAN)))
            .collect();
        format!("{}: {}", m.tracker, per_seed.join(", "))
    });
    format!("\n{lines}")
}

/// Per tracker, the confidence table fitted to all its runs' frames
/// ([`crate::calibrate::fit`]) as the core writes it, the scores where its status changes
/// now, and the reliability by score, by confidence and with the fit.
fn calibration_fits(
    results: &[SequenceResult],
    specs: &[RunSpec],
    trackers: &[TrackerKind],
) -> String {
    let mut text = String::from("\nconfidence tables fitted to the runs (pooled):\n");
    for &tracker in trackers {
        let Some(spec) = specs.iter().find(|s| s.tracker == tracker) else {
            continue;
        };
        let checks: Vec<&FrameCheck> = results
            .iter()
            .flat_map(|s| &s.runs)
            .filter(|r| r.tracker() == tracker)
            .flat_map(|r| r.checks.iter().flatten())
            .collect();
        let (table, lost, uncertain) = spec.status_thresholds();
        let (lost_at, uncertain_at) = (score_at(&table, lost), score_at(&table, uncertain));
        let line = |name: &str, bins: &[Bin; BINS]| {
            let shares: Vec<String> = bins
                .iter()
                .map(|b| b.share().map_or("-".into(), |s| format!("{s:.2}")))
                .collect();
            format!(
                "  {name}: {} (worst {})\n",
                shares.join(" "),
                worst_gap(bins, 1).map_or("-".into(), |g| format!("{g:.3}"))
            )
        };
        text += &format!(
            "{tracker}: {} frames; status changes at score {lost_at:.3} (Lost) and \
             {uncertain_at:.3} (Uncertain)\n",
            checks.len()
        );
        text += &line(
            "by score     ",
            &reliability(checks.iter().copied(), |f| f.score),
        );
        text += &line(
            "by confidence",
            &reliability(checks.iter().copied(), |f| f.confidence),
        );
        match fit(checks.iter().copied()) {
            Some(f) => {
                text += &line(
                    "fitted       ",
                    &refit_reliability(checks.iter().copied(), &f.table),
                );
                let knots: Vec<String> = f
                    .thousandths
                    .iter()
                    .map(|(s, c)| format!("({s}, {c})"))
                    .collect();
                text += &format!("  table: [{}]\n", knots.join(", "));
            }
            None => text += "  no fit: no frames\n",
        }
    }
    text
}

/// Each group's mean AUC from each start (over seeds), per tracker, and the mean over the
/// perturbed starts.
fn per_start_means(groups: &[MeanGroup]) -> String {
    group_lines(groups, "mean AUC per start", |m| {
        let per_start: Vec<String> = m
            .per_start
            .iter()
            .map(|s| format!("{} {:.3}", s.start, s.scores.auc.unwrap_or(f64::NAN)))
            .collect();
        let perturbed: Vec<f64> = m
            .per_start
            .iter()
            .filter(|s| s.start != Start::GIVEN.name)
            .filter_map(|s| s.scores.auc)
            .collect();
        let mean = perturbed.iter().sum::<f64>() / perturbed.len().max(1) as f64;
        format!(
            "{}: {}, perturbed mean {mean:.3}",
            m.tracker,
            per_start.join(", ")
        )
    })
}

/// Evaluates every sequence of `seqs` with `plan`, on as many threads as there are cores
/// (at most one per sequence), the largest sequences first. Results in `seqs` order.
pub(super) fn run_in_parallel(
    seqs: &[Sequence],
    plan: &Plan,
) -> Vec<Result<SequenceResult, Failure>> {
    let mut order: Vec<usize> = (0..seqs.len()).collect();
    let cost = |s: &Sequence| s.len() as u64 * s.width as u64 * s.height as u64;
    order.sort_by_key(|&i| std::cmp::Reverse(cost(&seqs[i])));
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(seqs.len());
    let next = AtomicUsize::new(0);
    let mut outcomes: Vec<Option<Result<SequenceResult, Failure>>> =
        seqs.iter().map(|_| None).collect();
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    while let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
                        done.push((i, evaluate(&seqs[i], plan)));
                    }
                    done
                })
            })
            .collect();
        for worker in workers {
            match worker.join() {
                Ok(done) => {
                    for (i, outcome) in done {
                        outcomes[i] = Some(outcome);
                    }
                }
                Err(panic) => std::panic::resume_unwind(panic),
            }
        }
    });
    outcomes
        .into_iter()
        .map(|o| o.unwrap_or_else(|| Err(fail("not evaluated"))))
        .collect()
}

/// Every run of `plan` over one sequence, from its start of the first ground-truth box,
/// scored; through the plan's virtual camera, if any.
fn evaluate(seq: &Sequence, plan: &Plan) -> Result<SequenceResult, Failure> {
    let (w, h) = (seq.width, seq.height);
    let first = seq
        .init_box()
        .ok_or_else(|| fail(format!("{} is empty", sequence::GROUNDTRUTH_FILE)))?;
    let camera = plan
        .camera
        .map(|c| VirtualCamera::new(c, w, h, &seq.groundtruth));
    let window = |i: usize| camera.as_ref().map(|c| c.window(i));
    let groundtruth: Vec<BBox> = match &camera {
        Some(_) => (0..)
            .zip(&seq.groundtruth)
            .filter_map(|(i, b)| window(i).map(|v| v.to_view(b)))
            .collect(),
        None => seq.groundtruth.clone(),
    };
    let (vw, vh) = window(0).map_or((w, h), |v| (v.width, v.height));
    let init = window(0).map_or(first, |v| v.to_view(&first));
    for spec in plan.specs {
        let start = spec.start.apply(&init);
        check_init(&start, vw, vh, &seq.origin.from_zero_based(start))?;
    }
    let overlay = plan.overlay.map(|d| d.join(&seq.name));
    if let Some(dir) = &overlay {
        create_dir(dir)?;
    }
    let format = plan.format;
    let frames = (0..).zip(seq.frames()).map(|(i, f)| {
        let f = f.map_err(fail)?;
        let f = match window(i) {
            Some(v) => v
                .crop(&f)
                .ok_or_else(|| fail("the camera's window leaves the frame"))?,
            None => f,
        };
        f.convert(format).map_err(fail)
    });
    let motions: Vec<CameraMotion> = match &camera {
        Some(c) => (0..seq.len()).map(|i| c.told(i)).collect(),
        None => Vec::new(),
    };
    let mut runs = track_frames(
        plan.specs,
        plan.shape,
        frames,
        &init,
        &motions,
        |i, frame, runs| {
            plan.bar.inc(1);
            match &overlay {
                Some(dir) => {
                    write_overlay(dir, frame, i, groundtruth.get(i), runs, plan.label_seeds)
                }
                None => Ok(()),
            }
        },
    )?
    .complete()?;
    for r in &mut runs {
        r.score(&groundtruth);
    }
    Ok(SequenceResult {
        name: seq.name.clone(),
        frames: runs.first().map_or(0, |r| r.boxes.len()),
        origin: seq.origin,
        runs,
    })
}

/// The sequence folders of `data`, sorted by name; notes the folders without `img/`.
fn sequence_dirs(data: &Path, command: &str) -> Result<Vec<PathBuf>, Failure> {
    let entries = std::fs::read_dir(data)
        .map_err(|e| fail(format!("cannot read data folder {}: {e}", data.display())))?;
    let mut dirs: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .collect();
    dirs.sort();
    dirs.retain(|d| {
        let ok = d.join("img").is_dir();
        if !ok {
            eprintln!(
                "rbtrack {command}: note: skipping {}: no img/ folder",
                d.display()
            );
        }
        ok
    });
    Ok(dirs)
}

/// The mean of `curves` point by point (all of length `len`).
fn mean_curve(curves: &[&[f64]], len: usize) -> Vec<f64> {
    (0..len)
        .map(|i| curves.iter().map(|c| c[i]).sum::<f64>() / curves.len().max(1) as f64)
        .collect()
}

/// Per sequence and tracker, its success and precision curves averaged over its seeds.
fn curves(s: &SequenceResult, tracker: TrackerKind) -> Option<(Vec<f64>, Vec<f64>)> {
    let evals: Vec<&Evaluation> = s
        .runs
        .iter()
        .filter(|r| r.tracker() == tracker)
        .filter_map(|r| r.evaluation.as_ref())
        .collect();
    if evals.is_empty() {
        return None;
    }
    let success: Vec<&[f64]> = evals.iter().map(|e| &e.success_curve[..]).collect();
    let precision: Vec<&[f64]> = evals.iter().map(|e| &e.precision_curve[..]).collect();
    Some((
        mean_curve(&success, SUCCESS_STEPS),
        mean_curve(&precision, PRECISION_MAX_PX + 1),
    ))
}

/// Writes `eval`'s plots into `dir`: per tracker, success and precision plots with one
/// curve per sequence (the mean over its seeds, in [`draw::PALETTE`]'s colours) and their
/// mean in the tracker's colour (`success.png`, `precision.png` for one tracker;
/// `success_rbpf.png`, ... for several, plus `success.png`, `precision.png` comparing the
/// trackers' mean curves, each in its colour). Titles and legends name each tracker's
/// configuration ([`RunSpec::label`]). And `reliability.png`: each tracker's reliability
/// diagram over every run (`pooled`'s rows). Returns the files written.
fn eval_plots(
    dir: &Path,
    results: &[SequenceResult],
    pooled: &[MeanRow],
    specs: &[RunSpec],
    trackers: &[TrackerKind],
    particles: usize,
) -> Result<Vec<PathBuf>, Failure> {
    create_dir(dir)?;
    let mut files = Vec::new();
    let several = trackers.len() > 1;
    let mut means = Vec::new();
    for &k in trackers {
        let mut plotted = Vec::new();
        for s in results {
            if let Some((success, precision)) = curves(s, k) {
                plotted.push(Curves {
                    label: s.name.clone(),
                    colour: draw::palette(plotted.len()),
                    success,
                    precision,
                });
            }
        }
        let label = specs
            .iter()
            .find(|s| s.tracker == k)
            .map_or_else(|| k.to_string(), |s| s.label(particles));
        let mean_of = |values: fn(&Curves) -> &[f64], len| {
            mean_curve(&plotted.iter().map(values).collect::<Vec<_>>(), len)
        };
        let mean = Curves {
            label: label.clone(),
            colour: k.colour(),
            success: mean_of(|c| &c.success, SUCCESS_STEPS),
            precision: mean_of(|c| &c.precision, PRECISION_MAX_PX + 1),
        };
        match plotted.len() {
            0 => continue,
            1 => plotted[0].colour = k.colour(),
            _ => plotted.push(Curves {
                label: "mean".into(),
                ..mean.clone()
            }),
        }
        let stem = if several {
            format!("_{k}")
        } else {
            String::new()
        };
        files.extend(plot_pair(dir, &stem, &label, &plotted)?);
        means.push(mean);
    }
    if several && !means.is_empty() {
        files.extend(plot_pair(dir, "", "mean over sequences", &means)?);
    }
    // Every tracker's reliability, all its runs' frames pooled (the pooled rows' tables).
    let shares: Vec<(TrackerKind, String, Vec<f64>)> = pooled
        .iter()
        .map(|m| {
            let bins = m.loss.reliability.iter();
            let shares = bins.map(|b| b.share().unwrap_or(f64::NAN));
            (m.tracker, m.tracker.to_string(), shares.collect())
        })
        .collect();
    let series: Vec<Series> = shares
        .iter()
        .map(|(k, label, values)| Series {
            label,
            values,
            colour: k.colour(),
        })
        .collect();
    let path = dir.join("reliability.png");
    draw::reliability_plot(&path, "confidence against being on the target", &series)
        .map_err(fail)?;
    files.push(path);
    Ok(files)
}
