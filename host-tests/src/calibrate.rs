//! The fit of a confidence table ([`rbtrack::tracker::calibration`]) to the frames of
//! runs against the ground truth.
//!
//! A frame is *on the target* when the estimate's IoU with the true box is at least
//! [`GOOD_IOU`]. The fit is isotonic (pool-adjacent-violators: the rising step function
//! nearest the frames' on-target indicator in least squares), then read at the table's
//! knots: the knot's value is the mean of the step function over the frames nearer that
//! knot than any other.

use crate::loss::{reliability, Bin, FrameCheck, BINS, GOOD_IOU};
use rbtrack::fixed::Q16;
use rbtrack::tracker::calibration::{Calibration, KNOTS};

/// The rising step function nearest `points` (score, on target) in least squares, as one
/// fitted value per point in score order (pool adjacent violators).
fn isotonic(points: &mut [(f64, bool)]) -> Vec<f64> {
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Blocks of (sum, count), merged while a block's mean is below the one before.
    let mut blocks: Vec<(f64, usize)> = Vec::new();
    for &(_, on) in points.iter() {
        blocks.push((f64::from(u8::from(on)), 1));
        while blocks.len() > 1 {
            let (s1, n1) = blocks[blocks.len() - 1];
            let (s0, n0) = blocks[blocks.len() - 2];
            if s0 / n0 as f64 <= s1 / n1 as f64 {
                break;
            }
            blocks.pop();
            *blocks.last_mut().expect("two blocks") = (s0 + s1, n0 + n1);
        }
    }
    blocks
        .iter()
        .flat_map(|&(s, n)| std::iter::repeat_n(s / n as f64, n))
        .collect()
}

/// A fitted table: its knots as thousandths and the table.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// `(score, confidence)` thousandths, as [`Calibration::from_thousandths`] takes them.
    pub thousandths: [(u16, u16); KNOTS],
    /// The table.
    pub table: Calibration,
}

/// The table fitted to `checks`' frames: knots at scores 0 and 1 and where the isotonic
/// fit reaches each tenth (then at score quantiles, [`knot_scores`]), each knot's confidence the mean isotonic fit of the
/// frames nearer it than any other knot, raised where needed so that the confidences rise
/// strictly (a table that keeps every pair of scores in order keeps the confidence's ROC
/// AUC as the score's). `None` without frames.
pub fn fit<'a>(checks: impl IntoIterator<Item = &'a FrameCheck>) -> Option<Fit> {
    let mut points: Vec<(f64, bool)> = checks
        .into_iter()
        .map(|f| (f.score.clamp(0.0, 1.0), f.iou >= GOOD_IOU))
        .collect();
    if points.is_empty() {
        return None;
    }
    let fitted = isotonic(&mut points);
    let scores: Vec<f64> = points.iter().map(|p| p.0).collect();
    let knot_scores = knot_scores(&scores, &fitted);
    let mut thousandths = [(0u16, 0u16); KNOTS];
    let mut last: Option<u16> = None;
    for k in 0..KNOTS {
        let lo = match k {
            0 => f64::NEG_INFINITY,
            _ => (knot_scores[k - 1] + knot_scores[k]) / 2.0,
        };
        let hi = match k + 1 {
            KNOTS => f64::INFINITY,
            _ => (knot_scores[k] + knot_scores[k + 1]) / 2.0,
        };
        let near: Vec<f64> = scores
            .iter()
            .zip(&fitted)
            .filter(|(s, _)| **s >= lo && **s < hi)
            .map(|(_, v)| *v)
            .collect();
        let mean = near.iter().sum::<f64>() / near.len().max(1) as f64;
        // Room above for the knots still to come, one thousandth each.
        let room = (KNOTS - 1 - k) as u16;
        let c = ((mean * 1000.0).round() as u16)
            .max(last.map_or(0, |l| l + 1))
            .min(1000 - room);
        last = Some(c);
        thousandths[k] = ((knot_scores[k] * 1000.0).round() as u16, c);
    }
    let table = Calibration::from_thousandths(thousandths)?;
    Some(Fit { thousandths, table })
}

/// The knots' scores in whole thousandths: 0, 1, and between them the scores where the
/// isotonic fit (`fitted`, of the frames' scores `sorted`) first reaches 0.2, 0.4, 0.6,
/// 0.8, then 0.1, 0.3, 0.5, 0.7, 0.9 (so that the table bends where the share on the
/// target changes, which is what each tenth of confidence is judged on), then score
/// quantiles of the frames, evenly spaced first; skipping any within 0.01 of a knot
/// already there.
fn knot_scores(sorted: &[f64], fitted: &[f64]) -> [f64; KNOTS] {
    let mut knots = vec![0.0, 1.0];
    let levels = [2, 4, 6, 8, 1, 3, 5, 7, 9].map(|t| f64::from(t) / 10.0);
    let crossings = levels.iter().filter_map(|&level| {
        let i = fitted.iter().position(|&v| v >= level)?;
        Some(thousandths(sorted[i]))
    });
    let n = 4 * (KNOTS - 1);
    let even = (1..n).filter(|j| j % 4 == 0);
    let quantiles = even
        .chain((1..n).filter(|j| j % 4 != 0))
        .map(|j| thousandths(sorted[j * (sorted.len() - 1) / n]));
    for at in crossings.chain(quantiles) {
        if knots.len() < KNOTS && knots.iter().all(|k| (k - at).abs() >= 0.01) {
            knots.push(at);
        }
    }
    // Too few distinct scores: halve the widest gaps.
    while knots.len() < KNOTS {
        knots.sort_by(f64::total_cmp);
        let (i, _) = knots
            .windows(2)
            .enumerate()
            .max_by(|a, b| (a.1[1] - a.1[0]).total_cmp(&(b.1[1] - b.1[0])))
            .expect("two knots");
        knots.push(thousandths((knots[i] + knots[i + 1]) / 2.0));
    }
    knots.sort_by(f64::total_cmp);
    let mut out = [0.0; KNOTS];
    out.copy_from_slice(&knots);
    out
}

/// `v` rounded to whole thousandths, as a table holds it.
fn thousandths(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// The least score that `table` gives `confidence` or more, 0..=1.
pub fn score_at(table: &Calibration, confidence: Q16) -> f64 {
    let (mut lo, mut hi) = (0i32, 1 << 16);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if table.confidence(Q16::from_bits(mid)) >= confidence {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    Q16::from_bits(lo).to_f64()
}

/// `fit`'s table applied to `checks`' scores: the reliability it would give (the scores,
/// hence the runs, unchanged).
pub fn refit_reliability<'a>(
    checks: impl IntoIterator<Item = &'a FrameCheck>,
    table: &Calibration,
) -> [Bin; BINS] {
    reliability(checks, |f| {
        table.confidence(Q16::from_f64(f.score)).to_f64()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::loss::worst_gap;
    use rbtrack::tracker::calibration;

    fn frame(score: f64, on: bool) -> FrameCheck {
        FrameCheck {
            iou: if on { 0.8 } else { 0.0 },
            score,
            confidence: score,
            flagged: false,
        }
    }

    #[test]
    fn isotonic_pools_violators() {
        let mut points = vec![(0.1, true), (0.2, false), (0.3, false), (0.4, true)];
        let fitted = isotonic(&mut points);
        let third = 1.0 / 3.0;
        assert_eq!(fitted.len(), 4);
        for (got, want) in fitted.iter().zip([third, third, third, 1.0]) {
            assert!((got - want).abs() < 1e-12, "{fitted:?}");
        }
    }

    #[test]
    fn the_fit_calibrates_a_known_chance() {
        // Frames at scores s = i / 1000 are on the target with chance s^2, exactly in
        // proportion.
        let mut frames = Vec::new();
        for i in 0..1000 {
            let s = i as f64 / 1000.0;
            let on = (s * s * 100.0).round() as usize;
            frames.extend((0..on).map(|_| frame(s, true)));
            frames.extend((on..100).map(|_| frame(s, false)));
        }
        let fit = fit(&frames).unwrap();
        let bins = refit_reliability(&frames, &fit.table);
        assert!(worst_gap(&bins, 100).unwrap() < 0.05, "{bins:?} {fit:?}");
        // Without the fit (the score itself) the same frames are off by far more.
        assert!(worst_gap(&reliability(&frames, |f| f.score), 100).unwrap() > 0.2);
        // The confidences rise strictly, and the score inverts.
        assert!(
            fit.thousandths.windows(2).all(|w| w[1].1 > w[0].1),
            "{fit:?}"
        );
        let at = fit.table.confidence(Q16::from_f64(0.548));
        assert!((score_at(&fit.table, at) - 0.548).abs() < 1e-4);
        assert_eq!(score_at(&calibration::IDENTITY, Q16::from_f64(0.25)), 0.25);
        assert!(super::fit(&[]).is_none());
    }

    #[test]
    fn a_table_of_one_score_still_rises() {
        let frames = vec![frame(0.5, true), frame(0.5, false)];
        let fit = fit(&frames).unwrap();
        assert!(fit
            .thousandths
            .windows(2)
            .all(|w| w[1].1 > w[0].1 && w[1].0 > w[0].0));
    }
}
