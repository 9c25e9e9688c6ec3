//! A tracker's confidence: its own score mapped through a table, so that the same
//! confidence means the same chance of being on the target whichever tracker reports it.
//!
//! Each tracker scores its estimate its own way (the correlation filter by its merged
//! response's margin, a particle filter by its window's colour coefficient less the
//! particles' spread), and the same score means different things: at the defaults the
//! correlation filter tracks well at a score of 0.2, a particle filter is lost at it. A
//! [`Calibration`] is a rising piecewise-linear map from score to confidence, one table
//! per tracker, fitted on the pooled dev and validation sequences (`rbtrack eval
//! --calibrate`, docs/accuracy.md) so that of the frames reported at a confidence `c` about
//! `c` have the estimate's box overlapping the true one by an IoU of at least 0.5. The
//! statuses then share their thresholds ([`LOST_BELOW`], [`UNCERTAIN_BELOW`]).
//!
//! The tables hold for the trackers' default configurations; another configuration
//! scores differently, and its confidence is then only ordered, not calibrated.

use crate::fixed::Q16;

/// Knots of a table.
pub const KNOTS: usize = 10;

/// The confidence below which every tracker's status is `Lost` by default: at most about
/// one frame in five so reported is on the target, Q16.16.
pub const LOST_BELOW: Q16 = Q16::from_ratio(1, 5);

/// The confidence below which every tracker's status is `Uncertain` by default: less than
/// even odds of being on the target, Q16.16.
pub const UNCERTAIN_BELOW: Q16 = Q16::from_ratio(1, 2);

/// A rising piecewise-linear map from a tracker's score to its confidence: `KNOTS` points
/// `(score, confidence)`, both Q16.16 in `[0, 1]`, scores strictly rising from 0 to 1 and
/// confidences rising; linear between knots.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Calibration {
    knots: [(Q16, Q16); KNOTS],
}

impl Calibration {
    /// The table of `knots`, given as thousandths `(score, confidence)`; `None` unless the
    /// scores rise strictly from 0 to 1000 and the confidences rise within `[0, 1000]`.
    pub const fn from_thousandths(knots: [(u16, u16); KNOTS]) -> Option<Self> {
        let mut out = [(Q16::ZERO, Q16::ZERO); KNOTS];
        let mut i = 0;
        while i < KNOTS {
            let (s, c) = knots[i];
            if s > 1000 || c > 1000 {
                return None;
            }
            if i > 0 && (s <= knots[i - 1].0 || c < knots[i - 1].1) {
                return None;
            }
            out[i] = (
                Q16::from_ratio(s as i64, 1000),
                Q16::from_ratio(c as i64, 1000),
            );
            i += 1;
        }
        if knots[0].0 != 0 || knots[KNOTS - 1].0 != 1000 {
            return None;
        }
        Some(Self { knots: out })
    }

    /// The confidence at `score`, Q16.16 in `[0, 1]` (a score outside `[0, 1]` is taken
    /// at the nearer end).
    pub const fn confidence(&self, score: Q16) -> Q16 {
        let s = score.clamp(Q16::ZERO, Q16::ONE).to_bits() as i64;
        let mut i = 1;
        while i < KNOTS - 1 && s > self.knots[i].0.to_bits() as i64 {
            i += 1;
        }
        let (s0, c0) = self.knots[i - 1];
        let (s1, c1) = self.knots[i];
        let (s0, c0) = (s0.to_bits() as i64, c0.to_bits() as i64);
        let (ds, dc) = (s1.to_bits() as i64 - s0, c1.to_bits() as i64 - c0);
        // Knots rise strictly (`ds > 0`); the test also keeps the division free of a
        // panic path.
        let along = if ds > 0 { dc * (s - s0) / ds } else { 0 };
        Q16::saturate(c0 + along)
    }
}

/// Unwraps a table known good at compile time (a bad one fails the build).
const fn table(knots: [(u16, u16); KNOTS]) -> Calibration {
    match Calibration::from_thousandths(knots) {
        Some(c) => c,
        None => panic!("a calibration table's knots must rise from score 0 to 1"),
    }
}

/// The identity: the confidence is the score.
pub const IDENTITY: Calibration = table([
    (0, 0),
    (100, 100),
    (200, 200),
    (300, 300),
    (400, 400),
    (500, 500),
    (600, 600),
    (700, 700),
    (800, 800),
    (1000, 1000),
]);

// The tables below are fits of `rbtrack eval ../shared/data ../valset --tracker all
// --seed 1 --starts spatial --zero-based-sequences ball1_vot15 --calibrate` (44 sequences,
// 7 starts each, 58,184 frames a tracker), the runs made with the tables before them; with
// these in place the same command measures the reliability docs/accuracy.md gives.

/// The correlation-filter tracker's table (score: the merged response margin).
pub const CORRELATION: Calibration = table([
    (0, 38),
    (20, 101),
    (34, 196),
    (46, 297),
    (56, 461),
    (82, 583),
    (115, 688),
    (133, 842),
    (181, 943),
    (1000, 1000),
]);

/// The colour particle filter's table (score: the colour coefficient less the spread
/// penalty).
pub const COLOUR_PF: Calibration = table([
    (0, 7),
    (378, 123),
    (508, 192),
    (607, 303),
    (683, 439),
    (742, 485),
    (792, 574),
    (831, 724),
    (870, 894),
    (1000, 990),
]);

/// The RBPF's table (score as the colour particle filter's).
pub const RBPF: Calibration = table([
    (0, 12),
    (392, 129),
    (520, 177),
    (610, 282),
    (678, 395),
    (733, 455),
    (786, 563),
    (828, 744),
    (867, 883),
    (1000, 991),
]);

#[cfg(test)]
mod tests {
    use super::*;

    fn q(v: f64) -> Q16 {
        Q16::from_f64(v)
    }

    /// A rising table, knots as thousandths.
    const EXAMPLE: [(u16, u16); KNOTS] = [
        (0, 0),
        (100, 50),
        (200, 100),
        (300, 300),
        (500, 500),
        (700, 800),
        (800, 850),
        (850, 870),
        (900, 900),
        (1000, 950),
    ];

    #[test]
    fn interpolates_between_knots_and_clamps_outside() {
        let c = Calibration::from_thousandths(EXAMPLE).unwrap();
        let at = |s: f64| c.confidence(q(s)).to_f64();
        assert!((at(0.05) - 0.025).abs() < 1e-4);
        assert!((at(0.25) - 0.2).abs() < 1e-4);
        assert!((at(0.6) - 0.65).abs() < 1e-4);
        assert!((at(0.3) - 0.3).abs() < 1e-4);
        assert_eq!(c.confidence(q(-0.5)), Q16::ZERO);
        assert!((at(1.0) - 0.95).abs() < 1e-4);
        assert_eq!(c.confidence(Q16::from_int(7)), c.confidence(Q16::ONE));
        assert_eq!(c.confidence(Q16::from_bits(i32::MIN)), Q16::ZERO);
        assert_eq!(
            c.confidence(Q16::from_bits(i32::MAX)),
            c.confidence(Q16::ONE)
        );
    }

    #[test]
    fn rising_scores_give_rising_confidences() {
        for table in [CORRELATION, COLOUR_PF, RBPF] {
            let mut last = Q16::ZERO;
            for bits in (0..=65536).step_by(7) {
                let c = table.confidence(Q16::from_bits(bits));
                assert!(c >= last && c <= Q16::ONE, "{c:?} after {last:?}");
                last = c;
            }
        }
    }

    #[test]
    fn every_tracker_shares_the_default_thresholds() {
        use crate::tracker::{CfConfig, Config, Variant};
        let cf = CfConfig::default();
        assert_eq!(
            (cf.lost_below, cf.uncertain_below),
            (LOST_BELOW, UNCERTAIN_BELOW)
        );
        for variant in [Variant::ColourPf, Variant::Rbpf] {
            let c = Config::new(variant);
            assert_eq!(
                (c.lost_below, c.uncertain_below),
                (LOST_BELOW, UNCERTAIN_BELOW)
            );
            // The papers' trackers are lost below a coefficient of 0.6.
            let paper = Config::paper(variant).lost_below;
            let table = variant.calibration();
            assert!(table.confidence(q(0.599)) < paper, "{variant:?}");
            assert!(table.confidence(q(0.6)) >= paper, "{variant:?}");
        }
        assert!(LOST_BELOW < UNCERTAIN_BELOW);
    }

    #[test]
    fn refuses_tables_that_do_not_rise_from_0_to_1() {
        let good = EXAMPLE;
        assert!(Calibration::from_thousandths(good).is_some());
        let mut flat = good;
        flat[2].0 = 100;
        assert!(Calibration::from_thousandths(flat).is_none());
        let mut falling = good;
        falling[3].1 = 90;
        assert!(Calibration::from_thousandths(falling).is_none());
        let mut short = good;
        short[9].0 = 990;
        assert!(Calibration::from_thousandths(short).is_none());
        let mut late = good;
        late[0].0 = 10;
        assert!(Calibration::from_thousandths(late).is_none());
        let mut over = good;
        over[9].1 = 1001;
        assert!(Calibration::from_thousandths(over).is_none());
    }
}
