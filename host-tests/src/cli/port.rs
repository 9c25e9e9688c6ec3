//! `rbtrack port`: the core's integer correlation-filter tracker (`cf`) against its f64
//! reference (cf64 configured as the integer design, [`cf64::Params::of_core`]) over every
//! sequence of one or more folders, frame by frame: where the two runs part, how their
//! sizes compare while the reference still holds the target, and both scores. Beside them,
//! the reference against itself started [`NUDGE`] px to the right: where a run parts from
//! one that differs from it by nothing a port could avoid, the floor for the port's
//! figures (the trackers' runs are chaotic: any difference grows until they part).

use super::args::PortArgs;
use super::eval::{open_folders, run_in_parallel, Folders, Plan};
use super::runs::{RunResult, RunSpec, SequenceResult, Start};
use super::TrackerKind;
use super::{cf_for, check_read, config_for, emit, fail, overrides, progress_bar, Failure};
use crate::cf64;
use crate::loss::LOST_IOU;
use crate::metrics::BBox;
use crate::sequence::Sequence;
use serde::Serialize;
use std::io::Write;
use std::path::Path;

/// Centres further apart than this, px, part two runs.
pub const PART_PX: f64 = 2.0;

/// Widths or heights further apart than this share part two runs.
pub const PART_SIZE: f64 = 0.03;

/// The nudged reference's first box is this far right of the reference's, px.
pub const NUDGE: f64 = 0.01;

/// One sequence: the two trackers from each start.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PortRow {
    /// Sequence name.
    pub sequence: String,
    /// Its data folder.
    pub data_dir: String,
    /// Frames tracked.
    pub frames: usize,
    /// The first frame (1-based) where the runs from the first box part: centres more
    /// than [`PART_PX`] apart or widths or heights more than [`PART_SIZE`] apart; `None`
    /// if they never do.
    pub parts_at: Option<usize>,
    /// The share of the starts whose runs part at all.
    pub parted_share: f64,
    /// The first frame where the reference and the nudged reference from the first box
    /// part, as [`PortRow::parts_at`].
    pub nudged_parts_at: Option<usize>,
    /// The mean of `ln(cf size / reference size)` (the geometric mean of width and height)
    /// over the frames before the reference first loses the target (IoU below
    /// [`LOST_IOU`]), over the starts.
    pub log_size_ratio: f64,
    /// Success AUC of cf, the mean over the starts.
    pub cf_auc: f64,
    /// Success AUC of the reference, the mean over the starts.
    pub reference_auc: f64,
    /// Success AUC of the nudged reference, the mean over the starts.
    pub nudged_auc: f64,
}

/// A folder's summary, or the pooled one.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PortSummary {
    /// The folder, or `all`.
    pub scope: String,
    /// Sequences.
    pub sequences: usize,
    /// Mean success AUC of cf over the sequences.
    pub cf_auc: f64,
    /// Mean success AUC of the reference.
    pub reference_auc: f64,
    /// Mean success AUC of the nudged reference.
    pub nudged_auc: f64,
    /// Sequences where cf trails the reference by more than 0.10.
    pub trailing: usize,
    /// Sequences where the nudged reference trails the reference by more than 0.10.
    pub nudged_trailing: usize,
    /// Sequences whose runs from the first box never part.
    pub never_part: usize,
    /// The median first parting frame of those that part (a sequence that never parts
    /// counts as its length).
    pub median_part: Option<usize>,
    /// The same for the reference and the nudged reference.
    pub nudged_median_part: Option<usize>,
    /// The mean of the sequences' log size ratios.
    pub log_size_ratio: f64,
}

/// `port`'s JSON document.
#[derive(Serialize)]
struct PortJson<'a> {
    data_dirs: Vec<String>,
    starts: &'a [Start],
    /// The integer tracker's settings; the reference's are [`cf64::Params::of_core`] of
    /// them.
    cf: serde_json::Value,
    reference: serde_json::Value,
    sequences: &'a [PortRow],
    summaries: &'a [PortSummary],
}

/// AUC by which cf may trail its reference on a sequence before the summary counts it.
const TRAILING: f64 = 0.10;

/// Runs `rbtrack port`; `Ok(false)` when some sequence failed (reported and skipped).
pub fn port(args: &PortArgs, out: &mut dyn Write) -> Result<bool, Failure> {
    let overrides = overrides(&args.config)?;
    check_read(&overrides, &[TrackerKind::Cf, TrackerKind::Cf64])?;
    let cf = cf_for(&overrides, TrackerKind::Cf)?.ok_or_else(|| fail("no cf settings"))?;
    let reference = cf64::Params::of_core(&cf.config, cf.grid, cf.scales);
    let config = config_for(&overrides, TrackerKind::Cf, 1)?;
    let starts = args.starts.starts();
    let mut specs = Vec::new();
    for &start in starts {
        specs.push(RunSpec {
            tracker: TrackerKind::Cf,
            config,
            cf64: None,
            cf: Some(cf),
            start,
        });
        let nudged = Start {
            dx: start.dx + NUDGE,
            ..start
        };
        for start in [start, nudged] {
            specs.push(RunSpec {
                tracker: TrackerKind::Cf64,
                config,
                cf64: Some(reference),
                cf: None,
                start,
            });
        }
    }
    let mut all_ok = true;
    let mut skip = |name: &Path, e: &dyn std::fmt::Display| {
        eprintln!("rbtrack port: skipping {}: {e}", name.display());
        all_ok = false;
    };
    let Folders { seqs, folder_of } = open_folders(
        &args.data,
        &args.zero_based_sequences,
        args.convention.origin(),
        "port",
        &mut skip,
    )?;
    let bar = progress_bar(Some(seqs.iter().map(|s| s.len() as u64).sum()), "port");
    let plan = Plan {
        specs: &specs,
        shape: args.config.shape(),
        format: crate::pixels::Format::Rgb888,
        overlay: None,
        camera: None,
        label_seeds: false,
        bar: &bar,
    };
    let outcomes = run_in_parallel(&seqs, &plan);
    bar.finish_and_clear();
    let mut rows = Vec::new();
    for ((seq, &k), outcome) in seqs.iter().zip(&folder_of).zip(outcomes) {
        match outcome {
            Ok(result) => rows.push(compare(seq, &args.data[k], &result)),
            Err(e) => skip(&seq.dir, &e),
        }
    }
    if rows.is_empty() {
        return Err(fail("no sequence could be tracked"));
    }
    let mut summaries: Vec<PortSummary> = args
        .data
        .iter()
        .map(|d| {
            let scope = d.display().to_string();
            let set: Vec<&PortRow> = rows.iter().filter(|r| r.data_dir == scope).collect();
            summary(scope, &set)
        })
        .collect();
    if args.data.len() > 1 {
        summaries.push(summary("all".into(), &rows.iter().collect::<Vec<_>>()));
    }
    if args.json {
        let doc = PortJson {
            data_dirs: args.data.iter().map(|d| d.display().to_string()).collect(),
            starts,
            cf: super::settings_json(&specs[0]),
            reference: reference.to_json(),
            sequences: &rows,
            summaries: &summaries,
        };
        emit(out, &(serde_json::to_string(&doc).map_err(fail)? + "\n"))?;
    } else {
        emit(out, &table(&rows, &summaries, starts.len()))?;
    }
    Ok(all_ok)
}

/// The row of one sequence from its runs: cf, the reference and the nudged reference,
/// start by start.
fn compare(seq: &Sequence, data_dir: &Path, result: &SequenceResult) -> PortRow {
    let runs: Vec<&[RunResult]> = result.runs.chunks_exact(3).collect();
    let pairs: Vec<(&RunResult, &RunResult)> = runs.iter().map(|r| (&r[0], &r[1])).collect();
    let auc = |r: &RunResult| r.evaluation.as_ref().map_or(0.0, |e| e.success_auc);
    let mean = |v: &mut dyn Iterator<Item = f64>| {
        let (sum, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
        sum / n.max(1) as f64
    };
    let parting: Vec<Option<usize>> = pairs
        .iter()
        .map(|(a, b)| parts_at(&a.boxes, &b.boxes))
        .collect();
    PortRow {
        sequence: result.name.clone(),
        data_dir: data_dir.display().to_string(),
        frames: result.frames,
        parts_at: parting.first().copied().flatten(),
        parted_share: parting.iter().filter(|p| p.is_some()).count() as f64
            / parting.len().max(1) as f64,
        log_size_ratio: mean(
            &mut pairs
                .iter()
                .map(|(a, b)| log_size_ratio(&a.boxes, &b.boxes, &seq.groundtruth)),
        ),
        cf_auc: mean(&mut pairs.iter().map(|(a, _)| auc(a))),
        reference_auc: mean(&mut pairs.iter().map(|(_, b)| auc(b))),
        nudged_parts_at: runs
            .first()
            .and_then(|r| parts_at(&r[1].boxes, &r[2].boxes)),
        nudged_auc: mean(&mut runs.iter().map(|r| auc(&r[2]))),
    }
}

/// The first frame (1-based) where boxes `a` and `b` part: centres more than [`PART_PX`]
/// apart, or a width or height more than [`PART_SIZE`] off.
pub fn parts_at(a: &[BBox], b: &[BBox]) -> Option<usize> {
    a.iter()
        .zip(b)
        .position(|(a, b)| {
            let (ca, cb) = (a.centre(), b.centre());
            let apart = (ca.0 - cb.0).hypot(ca.1 - cb.1) > PART_PX;
            let off = |x: f64, y: f64| (x / y - 1.0).abs() > PART_SIZE;
            apart || off(a.w, b.w) || off(a.h, b.h)
        })
        .map(|i| i + 1)
}

/// The mean over the frames before `b` first loses the target of `truth` (IoU below
/// [`LOST_IOU`]) of `ln(size a / size b)`, each size the geometric mean of width and
/// height; frames without a valid truth count as held.
pub fn log_size_ratio(a: &[BBox], b: &[BBox], truth: &[BBox]) -> f64 {
    let held = b
        .iter()
        .zip(truth.iter().map(Some).chain(std::iter::repeat(None)))
        .take_while(|(b, t)| t.is_none_or(|t| !t.is_valid() || b.iou(t) >= LOST_IOU))
        .count();
    let ratios: Vec<f64> = a
        .iter()
        .zip(b)
        .take(held)
        .map(|(a, b)| 0.5 * ((a.w * a.h) / (b.w * b.h)).ln())
        .collect();
    ratios.iter().sum::<f64>() / ratios.len().max(1) as f64
}

/// The summary of `rows` under `scope`.
fn summary(scope: String, rows: &[&PortRow]) -> PortSummary {
    let n = rows.len().max(1) as f64;
    let mean = |f: &dyn Fn(&PortRow) -> f64| rows.iter().map(|r| f(r)).sum::<f64>() / n;
    let median = |f: &dyn Fn(&PortRow) -> Option<usize>| {
        let mut at: Vec<usize> = rows.iter().map(|r| f(r).unwrap_or(r.frames)).collect();
        at.sort_unstable();
        at.get(at.len() / 2).copied()
    };
    let trailing = |f: &dyn Fn(&PortRow) -> f64| {
        rows.iter()
            .filter(|r| f(r) < r.reference_auc - TRAILING)
            .count()
    };
    PortSummary {
        scope,
        sequences: rows.len(),
        cf_auc: mean(&|r| r.cf_auc),
        reference_auc: mean(&|r| r.reference_auc),
        nudged_auc: mean(&|r| r.nudged_auc),
        trailing: trailing(&|r| r.cf_auc),
        nudged_trailing: trailing(&|r| r.nudged_auc),
        never_part: rows.iter().filter(|r| r.parts_at.is_none()).count(),
        median_part: median(&|r| r.parts_at),
        nudged_median_part: median(&|r| r.nudged_parts_at),
        log_size_ratio: mean(&|r| r.log_size_ratio),
    }
}

/// The text table: a row per sequence, then the summaries.
fn table(rows: &[PortRow], summaries: &[PortSummary], starts: usize) -> String {
    let over = match starts {
        1 => "from the first box".to_string(),
        n => format!("AUCs over {n} starts, parting frames of the first box's runs"),
    };
    let mut text = format!(
        "cf against its reference (cf64 as the integer design), {over}; runs part where \
         centres are more than {PART_PX} px or sizes more than {:.0} % apart; size ratio: \
         mean ln(cf / reference) before the reference loses the target (IoU < {LOST_IOU}); \
         nudged: the reference from the first box moved {NUDGE} px right\n\n",
        100.0 * PART_SIZE
    );
    text += &format!(
        "{:<20} {:>6} {:>8} {:>6} {:>10} {:>7} {:>7} {:>7} {:>7} {:>7}\n",
        "sequence",
        "frames",
        "parts at",
        "nudged",
        "size ratio",
        "cf",
        "ref",
        "nudged",
        "cf-ref",
        "nud-ref"
    );
    let frame = |p: Option<usize>| p.map_or("-".into(), |p| p.to_string());
    for r in rows {
        text += &format!(
            "{:<20} {:>6} {:>8} {:>6} {:>+10.3} {:>7.3} {:>7.3} {:>7.3} {:>+7.3} {:>+7.3}\n",
            r.sequence,
            r.frames,
            frame(r.parts_at),
            frame(r.nudged_parts_at),
            r.log_size_ratio,
            r.cf_auc,
            r.reference_auc,
            r.nudged_auc,
            r.cf_auc - r.reference_auc,
            r.nudged_auc - r.reference_auc
        );
    }
    text += "\n";
    for s in summaries {
        text += &format!(
            "{}: {} sequences; AUC cf {:.3}, reference {:.3}, nudged {:.3} ({:+.3}, {:+.3}); \
             trailing the reference by more than {TRAILING:.2}: cf on {}, nudged on {}; \
             median parting frame cf {}, nudged {} ({} never part); mean size ratio {:+.3}\n",
            s.scope,
            s.sequences,
            s.cf_auc,
            s.reference_auc,
            s.nudged_auc,
            s.cf_auc - s.reference_auc,
            s.nudged_auc - s.reference_auc,
            s.trailing,
            s.nudged_trailing,
            frame(s.median_part),
            frame(s.nudged_median_part),
            s.never_part,
            s.log_size_ratio
        );
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    fn b(x: f64, y: f64, w: f64, h: f64) -> BBox {
        BBox { x, y, w, h }
    }

    #[test]
    fn runs_part_where_centres_or_sizes_leave_their_bounds() {
        let a = [b(0.0, 0.0, 10.0, 10.0); 4];
        let near = [b(0.0, 0.0, 10.0, 10.0), b(1.9, 0.0, 10.0, 10.0)];
        assert_eq!(parts_at(&a, &near), None);
        let moved = [b(0.0, 0.0, 10.0, 10.0), b(1.5, 1.5, 10.0, 10.0)];
        assert_eq!(parts_at(&a, &moved), Some(2));
        // 3.2 % taller, centre unchanged.
        let taller = [
            b(0.0, 0.0, 10.0, 10.0),
            b(0.0, 0.0, 10.0, 10.0),
            b(0.0, -0.16, 10.0, 10.32),
        ];
        assert_eq!(parts_at(&a, &taller), Some(3));
    }

    #[test]
    fn the_size_ratio_counts_frames_until_the_reference_loses_the_target() {
        let truth = [b(0.0, 0.0, 10.0, 10.0); 3];
        let reference = [
            b(0.0, 0.0, 10.0, 10.0),
            b(0.0, 0.0, 10.0, 10.0),
            b(50.0, 50.0, 10.0, 10.0),
        ];
        // Twice the area on the two held frames, anything after.
        let cf = [
            b(0.0, 0.0, 20.0, 10.0),
            b(0.0, 0.0, 10.0, 20.0),
            b(0.0, 0.0, 1.0, 1.0),
        ];
        let r = log_size_ratio(&cf, &reference, &truth);
        assert!((r - 0.5 * 2f64.ln()).abs() < 1e-12, "{r}");
    }
}
