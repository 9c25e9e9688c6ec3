//! How well a tracker's status and confidence tell when it has lost the target, and how
//! often it fails, measured against the ground truth.
//!
//! A frame with a valid ground-truth box is *lost* when the estimate's IoU with it is below
//! [`LOST_IOU`] and *good* when it is at least [`GOOD_IOU`]; frames without a valid box (the
//! target absent) count for nothing. A *loss* is a run of at least [`FLAG_WITHIN`]
//! consecutive lost frames; it is *flagged* when the status is `Lost` on one of its first
//! [`FLAG_WITHIN`] frames. A *failure* (VOT style) starts at a frame of IoU 0 after one of
//! IoU above 0 and lasts until the IoU is above 0 again, the frames to recover counted from
//! its first frame. A frame is *on the target* when it is good; the *reliability* of the
//! confidence is, per tenth of it, the share of its frames on the target.

use crate::metrics::BBox;
use rbtrack::tracker::{Estimate, Status};
use serde::Serialize;

/// IoU below which a frame is lost.
pub const LOST_IOU: f64 = 0.1;

/// IoU from which a frame is good.
pub const GOOD_IOU: f64 = 0.5;

/// Shortest loss, frames, and the frames from its start within which it must be flagged.
pub const FLAG_WITHIN: usize = 5;

/// One frame with a valid ground-truth box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameCheck {
    /// IoU of the estimate with the ground truth.
    pub iou: f64,
    /// The tracker's own score, 0..=1.
    pub score: f64,
    /// The tracker's confidence, 0..=1.
    pub confidence: f64,
    /// Whether the status is `Lost`.
    pub flagged: bool,
}

/// Per frame of a run, its check; `None` where the ground truth has no valid box (or the
/// run no estimate).
pub fn frame_checks(
    truth: &[BBox],
    boxes: &[BBox],
    estimates: &[Estimate],
) -> Vec<Option<FrameCheck>> {
    truth
        .iter()
        .zip(boxes)
        .zip(estimates)
        .map(|((t, b), e)| {
            t.is_valid().then(|| FrameCheck {
                iou: t.iou(b),
                score: e.score.to_f64(),
                confidence: e.confidence.to_f64(),
                flagged: e.status == Status::Lost,
            })
        })
        .collect()
}

/// Bins of a reliability table: tenths of the confidence.
pub const BINS: usize = 10;

/// Frames in one bin of confidence and those on the target.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Bin {
    /// Frames whose value falls in the bin.
    pub frames: usize,
    /// Of those, the frames of IoU at least [`GOOD_IOU`].
    pub on_target: usize,
}

impl Bin {
    /// The share of the bin's frames on the target; `None` when empty.
    pub fn share(&self) -> Option<f64> {
        (self.frames > 0).then(|| self.on_target as f64 / self.frames as f64)
    }
}

/// Per tenth of `value` (the confidence, or the score), the frames and those on the
/// target; 1 falls in the last tenth.
pub fn reliability<'a>(
    checks: impl IntoIterator<Item = &'a FrameCheck>,
    value: impl Fn(&FrameCheck) -> f64,
) -> [Bin; BINS] {
    let mut bins = [Bin::default(); BINS];
    for f in checks {
        let i = ((value(f).clamp(0.0, 1.0) * BINS as f64) as usize).min(BINS - 1);
        bins[i].frames += 1;
        bins[i].on_target += usize::from(f.iou >= GOOD_IOU);
    }
    bins
}

/// The largest distance of a non-empty bin's on-target share from its tenth's midpoint,
/// over bins of at least `min_frames` frames.
pub fn worst_gap(bins: &[Bin; BINS], min_frames: usize) -> Option<f64> {
    bins.iter()
        .enumerate()
        .filter(|(_, b)| b.frames >= min_frames.max(1))
        .filter_map(|(i, b)| {
            b.share()
                .map(|s| (s - (i as f64 + 0.5) / BINS as f64).abs())
        })
        .reduce(f64::max)
}

/// Counts of one or more runs, added up.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Counts {
    frames: usize,
    lost: usize,
    good: usize,
    good_flagged: usize,
    losses: usize,
    losses_flagged: usize,
    failures: usize,
    recoveries: usize,
    recover_frames: usize,
}

impl Counts {
    fn of(checks: &[Option<FrameCheck>]) -> Self {
        let mut c = Self::default();
        let valid = || checks.iter().flatten();
        c.frames = valid().count();
        c.lost = valid().filter(|f| f.iou < LOST_IOU).count();
        c.good = valid().filter(|f| f.iou >= GOOD_IOU).count();
        c.good_flagged = valid().filter(|f| f.iou >= GOOD_IOU && f.flagged).count();
        // Losses: runs of lost frames among the valid ones.
        let valid: Vec<&FrameCheck> = valid().collect();
        let mut start = 0;
        while start < valid.len() {
            if valid[start].iou >= LOST_IOU {
                start += 1;
                continue;
            }
            let len = valid[start..]
                .iter()
                .take_while(|f| f.iou < LOST_IOU)
                .count();
            if len >= FLAG_WITHIN {
                c.losses += 1;
                let flagged = valid[start..start + FLAG_WITHIN].iter().any(|f| f.flagged);
                c.losses_flagged += usize::from(flagged);
            }
            start += len;
        }
        // Failures: IoU 0 after IoU above 0, until above 0 again.
        let mut since: Option<usize> = None;
        let mut before = true;
        for (i, f) in checks.iter().enumerate() {
            let Some(f) = f else { continue };
            let overlaps = f.iou > 0.0;
            match (since, overlaps) {
                (None, false) if before => {
                    c.failures += 1;
                    since = Some(i);
                }
                (Some(at), true) => {
                    c.recoveries += 1;
                    c.recover_frames += i - at;
                    since = None;
                }
                _ => {}
            }
            before = overlaps;
        }
        c
    }

    fn add(self, o: Self) -> Self {
        Self {
            frames: self.frames + o.frames,
            lost: self.lost + o.lost,
            good: self.good + o.good,
            good_flagged: self.good_flagged + o.good_flagged,
            losses: self.losses + o.losses,
            losses_flagged: self.losses_flagged + o.losses_flagged,
            failures: self.failures + o.failures,
            recoveries: self.recoveries + o.recoveries,
            recover_frames: self.recover_frames + o.recover_frames,
        }
    }
}

/// ROC AUC of the confidence as a detector of lost frames: the probability that a lost
/// frame has a lower confidence than a frame that is not lost (ties count half); `None`
/// when either kind is missing.
pub fn loss_roc_auc<'a>(checks: impl IntoIterator<Item = &'a FrameCheck>) -> Option<f64> {
    let mut frames: Vec<(f64, bool)> = checks
        .into_iter()
        .map(|f| (f.confidence, f.iou < LOST_IOU))
        .collect();
    let lost = frames.iter().filter(|f| f.1).count();
    let kept = frames.len() - lost;
    if lost == 0 || kept == 0 {
        return None;
    }
    frames.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Over groups of equal confidence: each kept frame beats the lost frames below it, and
    // ties with its group's lost frames half.
    let (mut lost_below, mut wins, mut i) = (0usize, 0.0f64, 0);
    while i < frames.len() {
        let j = i + frames[i..]
            .iter()
            .take_while(|f| f.0 == frames[i].0)
            .count();
        let group_lost = frames[i..j].iter().filter(|f| f.1).count();
        let group_kept = (j - i) - group_lost;
        wins += group_kept as f64 * (lost_below as f64 + group_lost as f64 / 2.0);
        lost_below += group_lost;
        i = j;
    }
    Some(wins / (lost as f64 * kept as f64))
}

/// Loss detection and failures over one or more runs (their frames pooled).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct LossReport {
    /// Share of the frames that are lost.
    pub lost_share: f64,
    /// [`loss_roc_auc`] over the pooled frames.
    pub roc_auc: Option<f64>,
    /// Losses of at least [`FLAG_WITHIN`] frames.
    pub losses: usize,
    /// Share of those flagged `Lost` within their first [`FLAG_WITHIN`] frames.
    pub flagged_share: Option<f64>,
    /// Share of the good frames flagged `Lost`.
    pub good_flagged_share: Option<f64>,
    /// VOT-style failures per run.
    pub failures_per_run: f64,
    /// Mean frames from a failure's start until the IoU is above 0 again (those that
    /// recover).
    pub recover_frames: Option<f64>,
    /// Per tenth of the confidence, the frames and those on the target
    /// ([`crate::calibrate`]).
    pub reliability: [Bin; BINS],
}

impl LossReport {
    /// The report over `runs`, each its frames' checks.
    pub fn of<'a>(runs: impl IntoIterator<Item = &'a [Option<FrameCheck>]> + Clone) -> Self {
        let (mut c, mut n) = (Counts::default(), 0usize);
        for checks in runs.clone() {
            c = c.add(Counts::of(checks));
            n += 1;
        }
        let share = |a: usize, b: usize| (b > 0).then(|| a as f64 / b as f64);
        Self {
            lost_share: share(c.lost, c.frames).unwrap_or(0.0),
            roc_auc: loss_roc_auc(runs.clone().into_iter().flatten().flatten()),
            losses: c.losses,
            flagged_share: share(c.losses_flagged, c.losses),
            good_flagged_share: share(c.good_flagged, c.good),
            failures_per_run: share(c.failures, n).unwrap_or(0.0),
            recover_frames: share(c.recover_frames, c.recoveries),
            reliability: reliability(runs.into_iter().flatten().flatten(), |f| f.confidence),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(iou: f64, confidence: f64, flagged: bool) -> Option<FrameCheck> {
        Some(FrameCheck {
            iou,
            score: confidence,
            confidence,
            flagged,
        })
    }

    #[test]
    fn reliability_bins_by_tenth() {
        let frame = |confidence: f64, on: bool| FrameCheck {
            iou: if on { 0.8 } else { 0.0 },
            score: confidence,
            confidence,
            flagged: false,
        };
        let frames = [frame(0.05, false), frame(0.05, true), frame(1.0, true)];
        let bins = reliability(frames.iter(), |f| f.confidence);
        assert_eq!(
            bins[0],
            Bin {
                frames: 2,
                on_target: 1
            }
        );
        assert_eq!(
            bins[9],
            Bin {
                frames: 1,
                on_target: 1
            }
        );
        assert_eq!(bins.iter().map(|b| b.frames).sum::<usize>(), 3);
        assert_eq!(worst_gap(&bins, 1), Some(0.45));
    }

    #[test]
    fn roc_auc_ranks_lost_frames_by_confidence() {
        let perfect = [check(0.0, 0.1, true), check(0.8, 0.9, false)];
        assert_eq!(loss_roc_auc(perfect.iter().flatten()), Some(1.0));
        let inverted = [check(0.0, 0.9, false), check(0.8, 0.1, false)];
        assert_eq!(loss_roc_auc(inverted.iter().flatten()), Some(0.0));
        let tied = [check(0.0, 0.5, false), check(0.8, 0.5, false)];
        assert_eq!(loss_roc_auc(tied.iter().flatten()), Some(0.5));
        // Lost at 0.2 and 0.6, kept at 0.4, 0.6, 0.8: of the 6 pairs, 4 won, 1 tied.
        let mixed = [
            check(0.05, 0.2, false),
            check(0.05, 0.6, false),
            check(0.3, 0.4, false),
            check(0.3, 0.6, false),
            check(0.9, 0.8, false),
        ];
        let expected = (4.0 + 0.5) / 6.0;
        assert!((loss_roc_auc(mixed.iter().flatten()).unwrap() - expected).abs() < 1e-12);
        assert_eq!(loss_roc_auc(perfect[1..].iter().flatten()), None);
    }

    #[test]
    fn losses_flags_and_failures_are_counted() {
        let good = check(0.7, 0.9, false);
        let lost = |flagged| check(0.0, 0.2, flagged);
        // Frames 2-7 lost (flagged on the 5th), 9-13 lost with no truth at 11 (4 valid
        // frames: too short to count), 14 good but flagged, 15-20 lost (20 at IoU 0.05).
        let mut run = vec![good, good];
        run.extend([
            lost(false),
            lost(false),
            lost(false),
            lost(false),
            lost(true),
        ]);
        run.extend([lost(false), good]);
        run.extend([lost(false), lost(false), None, lost(false), lost(false)]);
        run.push(check(0.7, 0.9, true));
        run.extend([lost(false); 5]);
        run.push(check(0.05, 0.3, false));
        let r = LossReport::of([&run[..]]);
        assert_eq!(r.losses, 2);
        assert_eq!(r.flagged_share, Some(0.5));
        assert_eq!(r.good_flagged_share, Some(0.25));
        // Failures start at frames 2, 9 and 15 and end at 8, 14 (the frame without truth
        // counts as a frame) and 20 (IoU 0.05 is above 0).
        assert_eq!(r.failures_per_run, 3.0);
        assert_eq!(r.recover_frames, Some((6.0 + 5.0 + 5.0) / 3.0));
        assert!((r.lost_share - 16.0 / 20.0).abs() < 1e-12, "{r:?}");
        // Two runs pool their frames and count failures per run.
        let twice = LossReport::of([&run[..], &run[..]]);
        assert_eq!((twice.losses, twice.failures_per_run), (4, 3.0));
    }
}
