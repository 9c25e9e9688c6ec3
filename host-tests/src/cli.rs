//! The work behind the `demo`, `track` and `eval` subcommands of `rbtrack`: running one or
//! both trackers over the synthetic scene or OTB-layout sequences, scoring them, and the
//! tables, JSON, box files, overlays and plots the program writes. Argument parsing lives
//! in the binary (`main.rs`).
//!
//! Conventions:
//! - Boxes are 0-based in memory ([`crate::metrics`]). Box files (`--boxes`) and `--init`
//!   use the convention of the sequence's ground-truth file, as [`Sequence`] reads it: 1-based
//!   for OTB, UAV123 and PETS folders, 0-based for VOT-derived (`*_vot*`) folders
//!   ([`GtOrigin::for_sequence`]).
//! - Timings are tracking only: the sum of [`crate::run::Step::elapsed`] (time inside the
//!   core's `step`, decoding and format conversion excluded) over the frames after the
//!   first, divided by their number.
//! - Scores follow OTB: every frame with a valid ground-truth box counts, the first
//!   (initialisation) frame included.

use crate::draw::{self, Rgb, Series, GREEN};
use crate::metrics::{BBox, Evaluation, PRECISION_MAX_PX, SUCCESS_STEPS};
use crate::progress::Progress;
use crate::run::{self, Format, Options, Run, RunError};
use crate::scene::{self, Scene, SceneConfig};
use crate::sequence::{GtOrigin, Sequence};
use rbtrack::tracker::{ConfigError, Variant};
use std::fmt::{self, Write as _};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// A failure to report on one line (no usage text): bad input data, an unwritable file...
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure(pub String);

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Failure {}

fn fail(e: impl fmt::Display) -> Failure {
    Failure(e.to_string())
}

/// Which filter a run uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TrackerKind {
    /// The Rao-Blackwellised particle filter ([`Variant::Rbpf`]).
    Rbpf,
    /// The colour particle filter ([`Variant::ColourPf`]).
    Pf,
}

impl TrackerKind {
    /// Both, in the order tables and plots list them.
    pub const ALL: [TrackerKind; 2] = [TrackerKind::Rbpf, TrackerKind::Pf];

    /// Command-line name: `rbpf` or `pf`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Rbpf => "rbpf",
            Self::Pf => "pf",
        }
    }

    /// The tracker called `name` ([`TrackerKind::name`], case-insensitive).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(name.trim()))
    }

    /// The core's variant.
    pub fn variant(self) -> Variant {
        match self {
            Self::Rbpf => Variant::Rbpf,
            Self::Pf => Variant::ColourPf,
        }
    }

    /// Colour of its estimates drawn on frames: RBPF yellow, PF cyan (from
    /// [`draw::TRACKER_COLOURS`]; red and blue would vanish on the synthetic target's red
    /// shirt and blue trousers). Plots colour their curves in series order instead.
    pub fn colour(self) -> Rgb {
        match self {
            Self::Rbpf => draw::tracker_colour(2),
            Self::Pf => draw::tracker_colour(4),
        }
    }

    /// Name of [`TrackerKind::colour`].
    pub fn colour_name(self) -> &'static str {
        match self {
            Self::Rbpf => "yellow",
            Self::Pf => "cyan",
        }
    }
}

impl fmt::Display for TrackerKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Command-line name of a pixel format: `rgb888` or `rgb565`.
pub fn format_name(format: Format) -> &'static str {
    match format {
        Format::Rgb888 => "rgb888",
        Format::Rgb565 => "rgb565",
    }
}

/// The pixel format called `name` ([`format_name`], case-insensitive).
pub fn format_from_name(name: &str) -> Option<Format> {
    [Format::Rgb888, Format::Rgb565]
        .into_iter()
        .find(|f| format_name(*f).eq_ignore_ascii_case(name.trim()))
}

/// What to run, shared by every tracker of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct Settings {
    /// Trackers to run (one or both), each over the same decoded frames.
    pub trackers: Vec<TrackerKind>,
    /// Particle count, one of [`run::PARTICLE_COUNTS`].
    pub particles: usize,
    /// Seed of the trackers' random draws.
    pub seed: u64,
    /// Pixel format handed to the trackers.
    pub format: Format,
}

impl Default for Settings {
    /// The RBPF alone, 100 particles, seed 1, RGB888.
    fn default() -> Self {
        Self {
            trackers: vec![TrackerKind::Rbpf],
            particles: 100,
            seed: 1,
            format: Format::Rgb888,
        }
    }
}

impl Settings {
    /// Runner options for `kind`: the defaults, or for a synthetic `scene` what
    /// [`Scene::configure`] sets (ground-plane slope, motion-adaptive noise).
    pub fn options(&self, kind: TrackerKind, scene: Option<&Scene>) -> Options {
        let mut o = Options::new(kind.variant());
        o.config.seed = self.seed;
        if let Some(scene) = scene {
            scene.configure(&mut o.config);
        }
        o.particles = self.particles;
        o.format = self.format;
        o
    }
}

/// One tracker's run over one sequence.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackerResult {
    /// The tracker.
    pub tracker: TrackerKind,
    /// Estimated box per frame, 0-based; the first is the initial box.
    pub boxes: Vec<BBox>,
    /// Scores against the ground truth, if there is any.
    pub evaluation: Option<Evaluation>,
    /// Total time inside the tracker's `step` (decoding excluded).
    pub tracking: Duration,
    /// Number of steps timed (frames after the first).
    pub steps: usize,
}

impl TrackerResult {
    /// Tracking-only milliseconds per frame; `None` when no frame was stepped.
    pub fn ms_per_frame(&self) -> Option<f64> {
        (self.steps > 0).then(|| self.tracking.as_secs_f64() * 1e3 / self.steps as f64)
    }
}

/// Every tracker's run over one sequence.
#[derive(Clone, Debug, PartialEq)]
pub struct SequenceResult {
    /// Sequence (folder) name.
    pub name: String,
    /// Frames tracked, the first included.
    pub frames: usize,
    /// Frame width, px.
    pub width: u32,
    /// Frame height, px.
    pub height: u32,
    /// One entry per tracker, in the order of [`Settings::trackers`].
    pub runs: Vec<TrackerResult>,
}

impl SequenceResult {
    /// The run of `kind`, if it ran.
    pub fn run(&self, kind: TrackerKind) -> Option<&TrackerResult> {
        self.runs.iter().find(|r| r.tracker == kind)
    }
}

/// Checks that an initial box (0-based) is usable on a `width x height` frame: finite,
/// positive size, centre inside the frame. `shown` is the box as the user wrote it, for
/// the message.
pub fn check_init(init: &BBox, width: u32, height: u32, shown: &BBox) -> Result<(), Failure> {
    if !init.is_valid() {
        return Err(Failure(format!(
            "initial box {} has no positive, finite size",
            box_line(shown)
        )));
    }
    let (cx, cy) = init.centre();
    if !(cx >= 0.0 && cy >= 0.0 && cx <= width as f64 - 1.0 && cy <= height as f64 - 1.0) {
        return Err(Failure(format!(
            "initial box {} is outside the {width}x{height} frame (its centre must lie inside)",
            box_line(shown)
        )));
    }
    Ok(())
}

fn run_error(e: RunError) -> Failure {
    match e {
        RunError::Config(ConfigError::InitialEllipse) => {
            let min = 2.0
                * rbtrack::tracker::Config::new(Variant::Rbpf)
                    .min_half_axis
                    .to_f64();
            Failure(format!(
                "initial box too small (width and height must be at least {min} px) or \
                 centred outside the frame"
            ))
        }
        e => fail(e),
    }
}

/// Runs every tracker of `settings` over `frames` (RGB888, `(rgb, width, height)`) from
/// `init`, the 0-based box of the first frame, decoding each frame once. After each frame
/// is tracked, `on_frame(index, rgb, width, height, boxes)` sees it with every tracker's
/// box for it (the initial box for frame 0), e.g. to draw it. Results carry no evaluation.
pub fn run_trackers<I>(
    settings: &Settings,
    scene: Option<&Scene>,
    frames: I,
    init: &BBox,
    mut on_frame: impl FnMut(usize, &[u8], u32, u32, &[BBox]) -> Result<(), Failure>,
) -> Result<Vec<TrackerResult>, Failure>
where
    I: IntoIterator<Item = Result<(Vec<u8>, u32, u32), Failure>>,
{
    let mut frames = frames.into_iter();
    let mut results: Vec<TrackerResult> = settings
        .trackers
        .iter()
        .map(|&tracker| TrackerResult {
            tracker,
            boxes: Vec::new(),
            evaluation: None,
            tracking: Duration::ZERO,
            steps: 0,
        })
        .collect();
    let Some(first) = frames.next() else {
        return Ok(results);
    };
    let (rgb, w, h) = first?;
    let mut runners: Vec<Box<dyn Run>> = Vec::with_capacity(results.len());
    for r in &mut results {
        let opts = settings.options(r.tracker, scene);
        runners.push(run::start(&opts, &rgb, w as usize, h as usize, init).map_err(run_error)?);
        r.boxes.push(*init);
    }
    let mut current = vec![*init; results.len()];
    on_frame(0, &rgb, w, h, &current)?;
    for (index, frame) in (1..).zip(frames) {
        let (rgb, w, h) = frame?;
        for ((runner, r), b) in runners.iter_mut().zip(&mut results).zip(&mut current) {
            let step = runner
                .step(&rgb, w as usize, h as usize)
                .map_err(run_error)?;
            r.tracking += step.elapsed;
            r.steps += 1;
            r.boxes.push(step.bbox);
            *b = step.bbox;
        }
        on_frame(index, &rgb, w, h, &current)?;
    }
    Ok(results)
}

/// Draws ground truth `truth` (green box, if valid) and each tracker's estimate (its
/// ellipse, in [`TrackerKind::colour`]) on a copy of `rgb`.
pub fn overlay(
    rgb: &[u8],
    width: u32,
    height: u32,
    truth: Option<&BBox>,
    estimates: &[(TrackerKind, BBox)],
) -> Vec<u8> {
    let mut img = rgb.to_vec();
    let thick = if width >= 640 { 3 } else { 2 };
    if let Some(t) = truth.filter(|t| t.is_valid()) {
        draw::draw_box(&mut img, width, height, t, GREEN, thick);
    }
    for (kind, b) in estimates {
        draw::draw_ellipse(
            &mut img,
            width,
            height,
            b.to_ellipse_f64(),
            kind.colour(),
            thick,
        );
    }
    img
}

fn create_dir(dir: &Path) -> Result<(), Failure> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Failure(format!("cannot create {}: {e}", dir.display())))
}

/// Tracks an opened sequence from `init` (0-based box of frame 0) with every tracker of
/// `settings` and scores each against the sequence's ground truth, if any. With `overlay`,
/// writes every frame as `DIR/0001.png`, ... (1-based frame numbers) with the ground truth
/// and the estimates drawn. `progress` advances by one per frame.
pub fn track_sequence(
    seq: &Sequence,
    settings: &Settings,
    init: &BBox,
    overlay_dir: Option<&Path>,
    mut progress: Option<&mut Progress>,
) -> Result<SequenceResult, Failure> {
    if let Some(dir) = overlay_dir {
        create_dir(dir)?;
    }
    let frames = seq
        .frames()
        .map(|f| f.map(|f| (f.rgb, f.width, f.height)).map_err(fail));
    let kinds = settings.trackers.clone();
    let mut runs = run_trackers(settings, None, frames, init, |i, rgb, w, h, boxes| {
        if let Some(p) = progress.as_deref_mut() {
            p.inc(1);
        }
        let Some(dir) = overlay_dir else {
            return Ok(());
        };
        let est: Vec<_> = kinds.iter().copied().zip(boxes.iter().copied()).collect();
        let img = overlay(rgb, w, h, seq.groundtruth.get(i), &est);
        draw::save_png(dir.join(format!("{:04}.png", i + 1)), &img, w, h).map_err(fail)
    })?;
    if seq.has_groundtruth() {
        for r in &mut runs {
            r.evaluation = Some(Evaluation::new(&seq.groundtruth, &r.boxes));
        }
    }
    Ok(SequenceResult {
        name: seq.name.clone(),
        frames: runs.first().map_or(0, |r| r.boxes.len()),
        width: seq.width,
        height: seq.height,
        runs,
    })
}

/// A box as one `x,y,w,h` line (two decimals), as written to box files.
pub fn box_line(b: &BBox) -> String {
    format!("{:.2},{:.2},{:.2},{:.2}", b.x, b.y, b.w, b.h)
}

/// Writes 0-based `boxes` to `path`, one `x,y,w,h` line per frame, converted to `origin`
/// (the convention of the sequence's ground-truth file).
pub fn write_boxes(path: &Path, boxes: &[BBox], origin: GtOrigin) -> Result<(), Failure> {
    let mut text = String::with_capacity(boxes.len() * 28);
    for b in boxes {
        text.push_str(&box_line(&origin.from_zero_based(*b)));
        text.push('\n');
    }
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        create_dir(parent)?;
    }
    std::fs::write(path, text).map_err(|e| Failure(format!("cannot write {}: {e}", path.display())))
}

/// Mean scores of one tracker over several sequences (each sequence weighs the same).
#[derive(Clone, Debug, PartialEq)]
pub struct MeanResult {
    /// The tracker.
    pub tracker: TrackerKind,
    /// Sequences averaged (those with ground truth).
    pub sequences: usize,
    /// Total frames tracked over them.
    pub frames: usize,
    /// Mean success AUC.
    pub auc: f64,
    /// Mean precision at 20 px.
    pub prec20: f64,
    /// Mean of the per-sequence mean IoUs.
    pub miou: f64,
    /// Mean share of frames with IoU > 0.5.
    pub success_rate: f64,
    /// Mean tracking-only ms per frame (over sequences that stepped).
    pub ms_per_frame: Option<f64>,
    /// Mean success curve.
    pub success_curve: Vec<f64>,
    /// Mean precision curve (0..=50 px).
    pub precision_curve: Vec<f64>,
}

fn mean_of(values: impl Iterator<Item = f64>) -> Option<f64> {
    let (sum, n) = values.fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    (n > 0).then(|| sum / n as f64)
}

/// The mean of `kind`'s scores over the sequences of `results` that have ground truth;
/// `None` when there are none.
pub fn mean_result(results: &[SequenceResult], kind: TrackerKind) -> Option<MeanResult> {
    let runs: Vec<(&SequenceResult, &TrackerResult, &Evaluation)> = results
        .iter()
        .filter_map(|s| {
            let r = s.run(kind)?;
            Some((s, r, r.evaluation.as_ref()?))
        })
        .collect();
    if runs.is_empty() {
        return None;
    }
    let avg = |f: &dyn Fn(&Evaluation) -> f64| mean_of(runs.iter().map(|(_, _, e)| f(e)));
    let curve = |len: usize, f: &dyn Fn(&Evaluation) -> &[f64]| -> Vec<f64> {
        (0..len)
            .map(|i| mean_of(runs.iter().map(|(_, _, e)| f(e)[i])).unwrap_or(0.0))
            .collect()
    };
    Some(MeanResult {
        tracker: kind,
        sequences: runs.len(),
        frames: runs.iter().map(|(s, _, _)| s.frames).sum(),
        auc: avg(&|e| e.success_auc)?,
        prec20: avg(&|e| e.precision_20)?,
        miou: avg(&|e| e.mean_iou)?,
        success_rate: avg(&|e| e.success_rate)?,
        ms_per_frame: mean_of(runs.iter().filter_map(|(_, r, _)| r.ms_per_frame())),
        success_curve: curve(SUCCESS_STEPS, &|e| &e.success_curve),
        precision_curve: curve(PRECISION_MAX_PX + 1, &|e| &e.precision_curve),
    })
}

fn score(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.3}"))
}

fn millis(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:.2}"))
}

/// Formats rows under `header`; the first `left` columns are left-aligned, the rest
/// right-aligned.
fn render_table(header: &[&str], rows: &[Vec<String>], left: usize) -> String {
    let mut widths: Vec<usize> = header.iter().map(|h| h.len()).collect();
    for row in rows {
        for (w, cell) in widths.iter_mut().zip(row) {
            *w = (*w).max(cell.len());
        }
    }
    let line = |cells: &mut dyn Iterator<Item = &str>| {
        let mut out = String::new();
        for (i, (cell, w)) in cells.zip(&widths).enumerate() {
            if i > 0 {
                out.push_str("  ");
            }
            if i < left {
                let _ = write!(out, "{cell:<w$}");
            } else {
                let _ = write!(out, "{cell:>w$}");
            }
        }
        out.trim_end().to_string() + "\n"
    };
    let mut out = line(&mut header.iter().copied());
    let rule: usize = widths.iter().sum::<usize>() + 2 * widths.len().saturating_sub(1);
    out.push_str(&"-".repeat(rule));
    out.push('\n');
    for row in rows {
        out.push_str(&line(&mut row.iter().map(String::as_str)));
    }
    out
}

fn metric_cells(r: &TrackerResult) -> [String; 5] {
    let e = r.evaluation.as_ref();
    [
        score(e.map(|e| e.success_auc)),
        score(e.map(|e| e.precision_20)),
        score(e.map(|e| e.mean_iou)),
        score(e.map(|e| e.success_rate)),
        millis(r.ms_per_frame()),
    ]
}

/// The demo's table: one row per tracker (success AUC, precision at 20 px, mean IoU,
/// success rate at IoU 0.5, tracking-only ms per frame).
pub fn tracker_table(result: &SequenceResult) -> String {
    let rows: Vec<Vec<String>> = result
        .runs
        .iter()
        .map(|r| {
            let mut row = vec![r.tracker.name().to_string()];
            row.extend(metric_cells(r));
            row
        })
        .collect();
    render_table(
        &["tracker", "AUC", "prec@20", "mIoU", "success", "ms/frame"],
        &rows,
        1,
    )
}

/// The table of `track` and `eval`: one row per sequence and tracker, then (for more
/// than one sequence) one `mean` row per tracker.
pub fn sequence_table(results: &[SequenceResult], trackers: &[TrackerKind]) -> String {
    let mut rows = Vec::new();
    for s in results {
        for r in &s.runs {
            let mut row = vec![
                s.name.clone(),
                r.tracker.name().into(),
                s.frames.to_string(),
            ];
            row.extend(metric_cells(r));
            rows.push(row);
        }
    }
    if results.len() > 1 {
        for &k in trackers {
            if let Some(m) = mean_result(results, k) {
                rows.push(vec![
                    "mean".into(),
                    k.name().into(),
                    m.frames.to_string(),
                    score(Some(m.auc)),
                    score(Some(m.prec20)),
                    score(Some(m.miou)),
                    score(Some(m.success_rate)),
                    millis(m.ms_per_frame),
                ]);
            }
        }
    }
    render_table(
        &[
            "sequence", "tracker", "frames", "AUC", "prec@20", "mIoU", "success", "ms/frame",
        ],
        &rows,
        2,
    )
}

/// A JSON string literal.
pub fn json_str(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A JSON number (6 decimals), or `null` for `None` or a non-finite value.
pub fn json_num(v: Option<f64>) -> String {
    match v {
        Some(v) if v.is_finite() => format!("{v:.6}"),
        _ => "null".into(),
    }
}

/// One sequence's run as a JSON object: `sequence`, `tracker`, `frames`, `auc`, `prec20`,
/// `miou`, `success_rate`, `ms_per_frame` (scores `null` without ground truth).
pub fn run_json(sequence: &SequenceResult, run: &TrackerResult) -> String {
    let e = run.evaluation.as_ref();
    format!(
        "{{\"sequence\": {}, \"tracker\": {}, \"frames\": {}, \"auc\": {}, \"prec20\": {}, \
         \"miou\": {}, \"success_rate\": {}, \"ms_per_frame\": {}}}",
        json_str(&sequence.name),
        json_str(run.tracker.name()),
        sequence.frames,
        json_num(e.map(|e| e.success_auc)),
        json_num(e.map(|e| e.precision_20)),
        json_num(e.map(|e| e.mean_iou)),
        json_num(e.map(|e| e.success_rate)),
        json_num(run.ms_per_frame()),
    )
}

fn settings_json(settings: &Settings) -> String {
    format!(
        "\"particles\": {}, \"seed\": {}, \"format\": {}",
        settings.particles,
        settings.seed,
        json_str(format_name(settings.format))
    )
}

/// `track`'s JSON: [`run_json`] of its one run plus `particles`, `seed`, `format`.
pub fn track_json(result: &SequenceResult, settings: &Settings) -> String {
    let run = result.runs.first();
    match run {
        Some(r) => {
            let obj = run_json(result, r);
            format!("{}, {}}}", &obj[..obj.len() - 1], settings_json(settings))
        }
        None => format!(
            "{{\"sequence\": {}, \"frames\": 0, {}}}",
            json_str(&result.name),
            settings_json(settings)
        ),
    }
}

fn mean_json(m: &MeanResult) -> String {
    format!(
        "{{\"tracker\": {}, \"sequences\": {}, \"frames\": {}, \"auc\": {}, \"prec20\": {}, \
         \"miou\": {}, \"success_rate\": {}, \"ms_per_frame\": {}}}",
        json_str(m.tracker.name()),
        m.sequences,
        m.frames,
        json_num(Some(m.auc)),
        json_num(Some(m.prec20)),
        json_num(Some(m.miou)),
        json_num(Some(m.success_rate)),
        json_num(m.ms_per_frame),
    )
}

/// `eval`'s JSON: `{"data_dir", "particles", "seed", "format", "trackers": [...],
/// "sequences": [run objects], "mean": [one object per tracker]}`.
pub fn eval_json(data_dir: &Path, results: &[SequenceResult], settings: &Settings) -> String {
    let sequences: Vec<String> = results
        .iter()
        .flat_map(|s| s.runs.iter().map(move |r| run_json(s, r)))
        .collect();
    let means: Vec<String> = settings
        .trackers
        .iter()
        .filter_map(|&k| mean_result(results, k))
        .map(|m| mean_json(&m))
        .collect();
    let trackers: Vec<String> = settings
        .trackers
        .iter()
        .map(|k| json_str(k.name()))
        .collect();
    format!(
        "{{\"data_dir\": {}, {}, \"trackers\": [{}], \"sequences\": [{}], \"mean\": [{}]}}",
        json_str(&data_dir.display().to_string()),
        settings_json(settings),
        trackers.join(", "),
        sequences.join(", "),
        means.join(", ")
    )
}

fn plot_pair(
    dir: &Path,
    stem: &str,
    title: &str,
    labels: &[String],
    success: &[Vec<f64>],
    precision: &[Vec<f64>],
) -> Result<Vec<PathBuf>, Failure> {
    fn series<'a>(labels: &'a [String], curves: &'a [Vec<f64>]) -> Vec<Series<'a>> {
        labels
            .iter()
            .zip(curves)
            .map(|(label, values)| Series { label, values })
            .collect()
    }
    let (s, p) = (series(labels, success), series(labels, precision));
    let sp = dir.join(format!("success{stem}.png"));
    let pp = dir.join(format!("precision{stem}.png"));
    draw::success_plot(&sp, &format!("Success plot: {title}"), &s).map_err(fail)?;
    draw::precision_plot(&pp, &format!("Precision plot: {title}"), &p).map_err(fail)?;
    Ok(vec![sp, pp])
}

/// Writes `eval`'s plots into `dir`: per tracker, success and precision plots with one
/// curve per sequence plus the mean curve (`success.png`, `precision.png` for one tracker;
/// `success_rbpf.png`, ... for both, plus `success.png`, `precision.png` comparing the
/// trackers' mean curves). Returns the files written.
pub fn eval_plots(
    dir: &Path,
    results: &[SequenceResult],
    settings: &Settings,
) -> Result<Vec<PathBuf>, Failure> {
    create_dir(dir)?;
    let mut files = Vec::new();
    let several = settings.trackers.len() > 1;
    let mut means = Vec::new();
    for &k in &settings.trackers {
        let Some(mean) = mean_result(results, k) else {
            continue;
        };
        let (mut labels, mut success, mut precision) = (Vec::new(), Vec::new(), Vec::new());
        for s in results {
            if let Some(e) = s.run(k).and_then(|r| r.evaluation.as_ref()) {
                labels.push(s.name.clone());
                success.push(e.success_curve.to_vec());
                precision.push(e.precision_curve.clone());
            }
        }
        if results.len() > 1 {
            labels.push("mean".into());
            success.push(mean.success_curve.clone());
            precision.push(mean.precision_curve.clone());
        }
        let stem = if several {
            format!("_{}", k.name())
        } else {
            String::new()
        };
        let title = format!("{k}, {} particles", settings.particles);
        files.extend(plot_pair(
            dir, &stem, &title, &labels, &success, &precision,
        )?);
        means.push(mean);
    }
    if several && !means.is_empty() {
        let labels: Vec<String> = means
            .iter()
            .map(|m| format!("{} mean", m.tracker))
            .collect();
        let success: Vec<Vec<f64>> = means.iter().map(|m| m.success_curve.clone()).collect();
        let precision: Vec<Vec<f64>> = means.iter().map(|m| m.precision_curve.clone()).collect();
        let title = format!("mean over sequences, {} particles", settings.particles);
        files.extend(plot_pair(dir, "", &title, &labels, &success, &precision)?);
    }
    Ok(files)
}

/// What `demo` ran and wrote.
#[derive(Clone, Debug, PartialEq)]
pub struct Demo {
    /// Both trackers' runs over the scene.
    pub result: SequenceResult,
    /// Files written.
    pub files: Vec<PathBuf>,
}

/// Frames of the demo's image strip.
pub const STRIP_FRAMES: usize = 8;

/// The demo: the synthetic scene `variant` (seed 1, QVGA, `frames` frames, at least 10),
/// the RBPF and the colour PF with 100 particles and the scene's settings
/// ([`Scene::configure`]), scored against the scene's ground truth. Writes into `out`:
/// `strip.png` ([`STRIP_FRAMES`] evenly spaced frames), `demo.gif` (every second frame,
/// if `gif`), `success.png` and `precision.png`.
pub fn demo(
    out: &Path,
    variant: scene::Variant,
    frames: usize,
    gif: bool,
) -> Result<Demo, Failure> {
    let mut config = SceneConfig::new(variant, 1);
    config.frames = frames;
    let scene = Scene::new(config).map_err(fail)?;
    let (w, h) = (scene.width(), scene.height());
    let settings = Settings {
        trackers: TrackerKind::ALL.to_vec(),
        ..Settings::default()
    };
    let truth = scene.boxes();
    let init = truth[0];
    let n = scene.len();
    let strip_at: Vec<usize> = (0..STRIP_FRAMES)
        .map(|k| (k * (n - 1) + (STRIP_FRAMES - 1) / 2) / (STRIP_FRAMES - 1))
        .collect();
    let mut strip = Vec::new();
    let mut anim = Vec::new();
    let rendered = (0..n).map(|i| scene.render(i).map(|rgb| (rgb, w, h)).map_err(fail));
    let kinds = settings.trackers.clone();
    let mut runs = run_trackers(
        &settings,
        Some(&scene),
        rendered,
        &init,
        |i, rgb, w, h, boxes| {
            if (gif && i % 2 == 0) || strip_at.contains(&i) {
                let est: Vec<_> = kinds.iter().copied().zip(boxes.iter().copied()).collect();
                let img = overlay(rgb, w, h, truth.get(i), &est);
                if strip_at.contains(&i) {
                    strip.push(img.clone());
                }
                if gif && i % 2 == 0 {
                    anim.push(img);
                }
            }
            Ok(())
        },
    )?;
    for r in &mut runs {
        r.evaluation = Some(Evaluation::new(&truth, &r.boxes));
    }
    let result = SequenceResult {
        name: format!("perspective seed 1, {n} frames"),
        frames: n,
        width: w,
        height: h,
        runs,
    };
    create_dir(out)?;
    let mut files = Vec::new();
    let path = out.join("strip.png");
    let refs: Vec<&[u8]> = strip.iter().map(Vec::as_slice).collect();
    draw::save_strip(&path, &refs, w, h, STRIP_FRAMES / 2).map_err(fail)?;
    files.push(path);
    if gif {
        let path = out.join("demo.gif");
        let refs: Vec<&[u8]> = anim.iter().map(Vec::as_slice).collect();
        draw::save_gif(&path, &refs, w, h, 100).map_err(fail)?;
        files.push(path);
    }
    let labels: Vec<String> = result.runs.iter().map(|r| r.tracker.to_string()).collect();
    let evals: Vec<&Evaluation> = result
        .runs
        .iter()
        .filter_map(|r| r.evaluation.as_ref())
        .collect();
    let success: Vec<Vec<f64>> = evals.iter().map(|e| e.success_curve.to_vec()).collect();
    let precision: Vec<Vec<f64>> = evals.iter().map(|e| e.precision_curve.clone()).collect();
    let title = format!(
        "synthetic perspective scene, {} particles",
        settings.particles
    );
    files.extend(plot_pair(out, "", &title, &labels, &success, &precision)?);
    Ok(Demo { result, files })
}
