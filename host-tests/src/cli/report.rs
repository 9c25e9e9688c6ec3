//! What the commands report: scores per run and over seeds, the tables, and the
//! per-frame CSV. The JSON documents are built from these types (serde).

use super::runs::{status_name, RunResult, SequenceResult, Start};
use super::{fail, Failure, TrackerKind};
use crate::draw::{self, Rgb, Series};
use crate::loss::{worst_gap, LossReport, BINS, FLAG_WITHIN, GOOD_IOU, LOST_IOU};
use crate::sequence::GtOrigin;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Scores of one run, or their means over runs; `None` without ground truth (and
/// `ms_per_frame` for a one-frame run).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Scores {
    /// Success AUC.
    pub auc: Option<f64>,
    /// Precision at 20 px.
    pub prec20: Option<f64>,
    /// Mean IoU.
    pub miou: Option<f64>,
    /// Share of frames with IoU > 0.5.
    pub success_rate: Option<f64>,
    /// Tracking-only milliseconds per frame.
    pub ms_per_frame: Option<f64>,
}

fn mean(values: impl Iterator<Item = Option<f64>>) -> Option<f64> {
    let (sum, n) = values
        .flatten()
        .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    (n > 0).then(|| sum / n as f64)
}

impl Scores {
    /// The scores of one run.
    pub fn of(run: &RunResult) -> Self {
        let e = run.evaluation.as_ref();
        Self {
            auc: e.map(|e| e.success_auc),
            prec20: e.map(|e| e.precision_20),
            miou: e.map(|e| e.mean_iou),
            success_rate: e.map(|e| e.success_rate),
            ms_per_frame: run.ms_per_frame(),
        }
    }

    /// Each score's mean over `all` (of those that have it).
    pub fn mean(all: &[Scores]) -> Self {
        Self {
            auc: mean(all.iter().map(|s| s.auc)),
            prec20: mean(all.iter().map(|s| s.prec20)),
            miou: mean(all.iter().map(|s| s.miou)),
            success_rate: mean(all.iter().map(|s| s.success_rate)),
            ms_per_frame: mean(all.iter().map(|s| s.ms_per_frame)),
        }
    }
}

/// One seed's scores (of one start, or over the starts).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SeedScores {
    /// The seed.
    pub seed: u64,
    /// The start's name ([`Start::name`]); `None` over the starts.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub start: Option<&'static str>,
    /// Its scores.
    #[serde(flatten)]
    pub scores: Scores,
}

/// One start's scores, means over the sequences and seeds.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StartScores {
    /// The start's name ([`Start::name`]).
    pub start: &'static str,
    /// Its scores.
    #[serde(flatten)]
    pub scores: Scores,
}

/// Scores over runs (seeds, and starts): their mean, the lowest and highest AUC, and every
/// run's.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OverSeeds {
    /// Means over the seeds.
    #[serde(flatten)]
    pub mean: Scores,
    /// Lowest AUC of a run.
    pub auc_min: Option<f64>,
    /// Highest AUC of a run.
    pub auc_max: Option<f64>,
    /// Each run's scores, in the order run.
    pub per_seed: Vec<SeedScores>,
}

impl OverSeeds {
    /// The summary of `per_seed`.
    pub fn new(per_seed: Vec<SeedScores>) -> Self {
        let scores: Vec<Scores> = per_seed.iter().map(|s| s.scores).collect();
        let aucs = || per_seed.iter().filter_map(|s| s.scores.auc);
        Self {
            mean: Scores::mean(&scores),
            auc_min: aucs().reduce(f64::min),
            auc_max: aucs().reduce(f64::max),
            per_seed,
        }
    }
}

/// One sequence and tracker, over the seeds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SequenceRow {
    /// Sequence name.
    pub sequence: String,
    /// The tracker.
    pub tracker: TrackerKind,
    /// Frames tracked.
    pub frames: usize,
    /// Scores over the seeds.
    #[serde(flatten)]
    pub scores: OverSeeds,
    /// Loss detection and failures, the runs pooled.
    pub loss: LossReport,
}

/// One tracker over the sequences: per seed, the mean over sequences; then over seeds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeanRow {
    /// The tracker.
    pub tracker: TrackerKind,
    /// Sequences averaged (those with ground truth).
    pub sequences: usize,
    /// Frames tracked over them.
    pub frames: usize,
    /// The set's mean per seed and over seeds.
    #[serde(flatten)]
    pub scores: OverSeeds,
    /// The set's mean per start over the seeds (with several starts).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub per_start: Vec<StartScores>,
    /// Loss detection and failures, every run of every sequence pooled.
    pub loss: LossReport,
}

/// The mean rows of a group of sequences: all those evaluated (`scope` empty), or one data
/// folder's (`scope` " FOLDER"); the tables label the rows `mean{scope}` and `all{scope}`.
pub struct MeanGroup {
    /// What the labels end with.
    pub scope: String,
    /// One row per tracker.
    pub rows: Vec<MeanRow>,
}

/// One row per sequence and tracker (in `trackers` order), over each tracker's seeds.
pub fn sequence_rows(results: &[SequenceResult], trackers: &[TrackerKind]) -> Vec<SequenceRow> {
    let mut rows = Vec::new();
    for s in results {
        for &tracker in trackers {
            let per_seed: Vec<SeedScores> = s
                .runs
                .iter()
                .filter(|r| r.tracker() == tracker)
                .map(|r| SeedScores {
                    seed: r.seed(),
                    start: Some(r.start().name),
                    scores: Scores::of(r),
                })
                .collect();
            if !per_seed.is_empty() {
                let runs = s.runs.iter().filter(|r| r.tracker() == tracker);
                rows.push(SequenceRow {
                    sequence: s.name.clone(),
                    tracker,
                    frames: s.frames,
                    scores: OverSeeds::new(per_seed),
                    loss: LossReport::of(runs.map(|r| &r.checks[..])),
                });
            }
        }
    }
    rows
}

/// Per tracker, the set's mean over the sequences with ground truth for each seed (over
/// the starts), and over the seeds; with several `starts`, also for each start; `None`
/// for a tracker without such sequences.
pub fn mean_rows(
    results: &[SequenceResult],
    trackers: &[TrackerKind],
    seeds: &[u64],
    starts: &[Start],
) -> Vec<MeanRow> {
    trackers
        .iter()
        .filter_map(|&tracker| {
            let scored: Vec<&SequenceResult> = results
                .iter()
                .filter(|s| {
                    s.runs
                        .iter()
                        .any(|r| r.tracker() == tracker && r.evaluation.is_some())
                })
                .collect();
            if scored.is_empty() {
                return None;
            }
            let mean_of = |keep: &dyn Fn(&RunResult) -> bool| {
                let runs: Vec<Scores> = scored
                    .iter()
                    .flat_map(|s| &s.runs)
                    .filter(|r| r.tracker() == tracker && keep(r))
                    .map(Scores::of)
                    .collect();
                Scores::mean(&runs)
            };
            let per_seed = seeds
                .iter()
                .map(|&seed| SeedScores {
                    seed,
                    start: None,
                    scores: mean_of(&|r| r.seed() == seed),
                })
                .collect();
            let per_start = match starts {
                [_] => Vec::new(),
                _ => starts
                    .iter()
                    .map(|&start| StartScores {
                        start: start.name,
                        scores: mean_of(&|r| r.start() == start),
                    })
                    .collect(),
            };
            let runs = scored
                .iter()
                .flat_map(|s| &s.runs)
                .filter(|r| r.tracker() == tracker);
            Some(MeanRow {
                tracker,
                sequences: scored.len(),
                frames: scored.iter().map(|s| s.frames).sum(),
                scores: OverSeeds::new(per_seed),
                per_start,
                loss: LossReport::of(runs.map(|r| &r.checks[..])),
            })
        })
        .collect()
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

/// The score cells of a row: AUC (then its lowest and highest over seeds, if `range` is
/// given), precision at 20 px, mean IoU, success rate, ms per frame.
fn score_cells(s: &Scores, range: Option<[Option<f64>; 2]>) -> Vec<String> {
    let mut cells = vec![score(s.auc)];
    cells.extend(range.into_iter().flatten().map(score));
    cells.extend([
        score(s.prec20),
        score(s.miou),
        score(s.success_rate),
        millis(s.ms_per_frame),
    ]);
    cells
}

fn score_header(spread: bool) -> Vec<&'static str> {
    let mut header = vec!["AUC"];
    if spread {
        header.extend(["AUC min", "AUC max"]);
    }
    header.extend(["prec@20", "mIoU", "success", "ms/frame"]);
    header
}

/// The table of `track` and `eval`: one row per sequence and tracker, then each group's
/// `mean` rows; with `spread`, each AUC's lowest and highest over the seeds (for `mean`:
/// of the set's mean per seed).
pub fn sequence_table(rows: &[SequenceRow], means: &[MeanGroup], spread: bool) -> String {
    let range = |s: &OverSeeds| spread.then_some([s.auc_min, s.auc_max]);
    let mut cells = Vec::new();
    for r in rows {
        let mut row = vec![
            r.sequence.clone(),
            r.tracker.to_string(),
            r.frames.to_string(),
        ];
        row.extend(score_cells(&r.scores.mean, range(&r.scores)));
        cells.push(row);
    }
    for g in means {
        for m in &g.rows {
            let mut row = vec![
                format!("mean{}", g.scope),
                m.tracker.to_string(),
                m.frames.to_string(),
            ];
            row.extend(score_cells(&m.scores.mean, range(&m.scores)));
            cells.push(row);
        }
    }
    let mut header = vec!["sequence", "tracker", "frames"];
    header.extend(score_header(spread));
    render_table(&header, &cells, 2)
}

/// The demo's table: one row per run (success AUC, precision at 20 px, mean IoU, success
/// rate at IoU 0.5, tracking-only ms per frame).
pub fn tracker_table(runs: &[RunResult]) -> String {
    let cells: Vec<Vec<String>> = runs
        .iter()
        .map(|r| {
            let mut row = vec![r.tracker().to_string()];
            row.extend(score_cells(&Scores::of(r), None));
            row
        })
        .collect();
    let mut header = vec!["tracker"];
    header.extend(score_header(false));
    render_table(&header, &cells, 1)
}

/// One line of a success plot and of a precision plot.
#[derive(Clone)]
pub struct Curves {
    /// Legend text.
    pub label: String,
    /// Colour of both lines.
    pub colour: Rgb,
    /// Success rate per overlap threshold.
    pub success: Vec<f64>,
    /// Precision per location error threshold.
    pub precision: Vec<f64>,
}

/// Writes `success{stem}.png` and `precision{stem}.png` into `dir`.
pub fn plot_pair(
    dir: &Path,
    stem: &str,
    title: &str,
    curves: &[Curves],
) -> Result<Vec<PathBuf>, Failure> {
    let series = |values: fn(&Curves) -> &[f64]| -> Vec<Series<'_>> {
        curves
            .iter()
            .map(|c| Series {
                label: &c.label,
                values: values(c),
                colour: c.colour,
            })
            .collect()
    };
    let sp = dir.join(format!("success{stem}.png"));
    let pp = dir.join(format!("precision{stem}.png"));
    draw::success_plot(
        &sp,
        &format!("Success plot: {title}"),
        &series(|c| &c.success),
    )
    .map_err(fail)?;
    draw::precision_plot(
        &pp,
        &format!("Precision plot: {title}"),
        &series(|c| &c.precision),
    )
    .map_err(fail)?;
    Ok(vec![sp, pp])
}

/// The loss-detection table: per sequence and tracker, then per group and tracker,
/// the share of lost frames, the confidence's ROC AUC as a loss detector, the losses, the
/// share flagged in time, the good frames flagged `Lost`, failures per run and frames to
/// recover ([`crate::loss`]).
pub fn loss_table(rows: &[SequenceRow], means: &[MeanGroup]) -> String {
    let header = [
        "sequence",
        "tracker",
        "lost",
        "ROC AUC",
        "losses",
        "flagged",
        "good as Lost",
        "failures/run",
        "recover",
    ];
    let cells = |name: &str, tracker: TrackerKind, l: &LossReport| {
        let share = |v: Option<f64>| v.map_or("-".into(), |v| format!("{:.1} %", 100.0 * v));
        vec![
            name.to_string(),
            tracker.to_string(),
            share(Some(l.lost_share)),
            score(l.roc_auc),
            l.losses.to_string(),
            share(l.flagged_share),
            share(l.good_flagged_share),
            format!("{:.2}", l.failures_per_run),
            l.recover_frames.map_or("-".into(), |v| format!("{v:.1}")),
        ]
    };
    let mut table: Vec<Vec<String>> = rows
        .iter()
        .map(|r| cells(&r.sequence, r.tracker, &r.loss))
        .collect();
    for g in means {
        table.extend(
            g.rows
                .iter()
                .map(|m| cells(&format!("all{}", g.scope), m.tracker, &m.loss)),
        );
    }
    format!(
        "\nloss detection (a frame is lost at IoU < {LOST_IOU}, good at IoU >= {GOOD_IOU}; a loss \
         is {FLAG_WITHIN}+ lost frames, flagged if `Lost` within its first {FLAG_WITHIN}; a \
         failure is IoU 0 until above 0 again, recover in frames; runs pooled):\n{}",
        render_table(&header, &table, 2)
    )
}

/// The reliability table of each group's pooled runs: per tracker and tenth of the
/// confidence, the share of frames on the target (IoU >= [`GOOD_IOU`]) and the frames.
pub fn reliability_table(means: &[MeanGroup]) -> String {
    let mut header = vec!["group".to_string(), "tracker".to_string()];
    header
        .extend((0..BINS).map(|i| format!("{:.1}-{:.1}", i as f64 / 10.0, (i + 1) as f64 / 10.0)));
    header.push("worst".into());
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    let mut table = Vec::new();
    for g in means {
        for m in &g.rows {
            let mut row = vec![format!("all{}", g.scope), m.tracker.to_string()];
            row.extend(m.loss.reliability.iter().map(|b| match b.share() {
                Some(s) => format!("{s:.2} ({})", b.frames),
                None => "-".into(),
            }));
            row.push(score(worst_gap(&m.loss.reliability, 1)));
            table.push(row);
        }
    }
    format!(
        "\nreliability (per tenth of the confidence, the share of frames on the target, IoU >= \
         {GOOD_IOU}, and the frames; worst: the largest distance of a share from its tenth's \
         midpoint; runs pooled):\n{}",
        render_table(&header, &table, 2)
    )
}

/// Header of [`per_frame_csv`].
pub const PER_FRAME_HEADER: &str = "frame,x,y,w,h,cx,cy,hx,hy,vx,vy,confidence,status";

/// One CSV row per frame of `run`: the frame number (from 1), the box `x,y,w,h` and the
/// ellipse centre `cx,cy` in `origin`'s convention, the half-axes `hx,hy` (px), the
/// velocity `vx,vy` (px/frame; 0 under a motion model that keeps no velocity, the
/// default), the confidence (0..1) and the status.
pub fn per_frame_csv(run: &RunResult, origin: GtOrigin) -> String {
    let mut out = String::from(PER_FRAME_HEADER);
    out.push('\n');
    let shift = origin.offset();
    for (i, (b, e)) in run.boxes.iter().zip(&run.estimates).enumerate() {
        let b = origin.from_zero_based(*b);
        let el = e.ellipse;
        let _ = writeln!(
            out,
            "{},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2},{:.2},{:.3},{:.3},{:.4},{}",
            i + 1,
            b.x,
            b.y,
            b.w,
            b.h,
            el.cx.to_f64() + shift,
            el.cy.to_f64() + shift,
            el.hx.to_f64(),
            el.hy.to_f64(),
            e.vx.to_f64(),
            e.vy.to_f64(),
            e.confidence.to_f64(),
            status_name(e.status)
        );
    }
    out
}
