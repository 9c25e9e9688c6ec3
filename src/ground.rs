//! The ground plane learnt online: the slope of the target's half-height against its
//! image row (the RBPF paper's `alpha / beta`), fitted by least squares over the recent
//! confident estimates.
//!
//! A camera looking down on a ground plane sees a target grow as it comes down the image;
//! over a short stretch the half-height is close to linear in the row, `hy = a + k cy`.
//! [`GroundPlane::observe`] adds an estimate with exponential forgetting (each sample's
//! weight falls by 1/64 per new sample, so about the last 64 count), and
//! [`GroundPlane::slope`] gives `k` once the fit deserves trust: enough samples, rows
//! spread over at least a given distance (standard deviation; the tracker asks a quarter
//! of the target's half-height), and a correlation
//! `r^2 >= 1/2` (a hand-held or aerial camera, where size does not follow the row, never
//! gets there).
//!
//! Integer only: rows and half-heights in 1/16 px, sums in `i64` (rows below 2^18
//! sixteenths, squares below 2^36, at most 64 times that in a sum).
//!
//! # Examples
//! ```
//! use rbtrack::fixed::Q16;
//! use rbtrack::ground::GroundPlane;
//! let mut g = GroundPlane::new();
//! for i in 0..40 {
//!     let cy = 100 + 4 * i; // px
//!     g.observe(Q16::from_int(cy), Q16::from_int(cy / 4)); // hy = cy / 4
//! }
//! let k = g.slope(Q16::from_int(10)).unwrap();
//! assert!((k.to_f64() - 0.25).abs() < 0.01);
//! ```

use crate::fixed::Q16;

/// Forgetting: each sample's weight falls by `2^-FORGET_LOG2` per new sample.
const FORGET_LOG2: u32 = 6;

/// Weight of one new sample in the sums, `1 << WEIGHT_LOG2`.
const WEIGHT_LOG2: u32 = 8;

/// Smallest total weight of a trusted fit: 16 samples' worth.
const MIN_WEIGHT: i64 = 16 << WEIGHT_LOG2;

/// Sixteenths of a pixel per Q16.16 unit shift: `px << 4` from `Q16 >> 12`.
const SIXTEENTHS: u32 = 12;

/// Exponentially weighted sums of rows and half-heights (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GroundPlane {
    /// Total weight.
    n: i64,
    /// Weighted sums of `y`, `h`, `y^2`, `y h`, `h^2` (1/16 px, weights `1 << WEIGHT_LOG2`).
    sy: i64,
    sh: i64,
    syy: i64,
    syh: i64,
    shh: i64,
}

impl GroundPlane {
    /// No samples: no slope.
    pub const fn new() -> Self {
        Self {
            n: 0,
            sy: 0,
            sh: 0,
            syy: 0,
            syh: 0,
            shh: 0,
        }
    }

    /// Adds an estimate centred on row `cy` with half-height `hy` (px, Q16.16; both
    /// clamped to `[0, 16384)` px).
    pub fn observe(&mut self, cy: Q16, hy: Q16) {
        let sixteenths = |v: Q16| (v.to_bits().clamp(0, (1 << 30) - 1) >> SIXTEENTHS) as i64;
        let (y, h) = (sixteenths(cy), sixteenths(hy)); // < 2^18
        let add = |s: &mut i64, v: i64| *s += (v << WEIGHT_LOG2) - (*s >> FORGET_LOG2);
        add(&mut self.n, 1);
        add(&mut self.sy, y);
        add(&mut self.sh, h);
        add(&mut self.syy, y * y);
        add(&mut self.syh, y * h);
        add(&mut self.shh, h * h);
    }

    /// The slope `k` of half-height against row (px/px, Q16.16 clamped to `[-4, 4]`), or
    /// `None` while the fit is not trustworthy: under 16 samples' weight, rows spread
    /// (standard deviation) no more than `min_spread` (px, Q16.16), or `r^2 < 1/2`.
    pub fn slope(&self, min_spread: Q16) -> Option<Q16> {
        if self.n < MIN_WEIGHT {
            return None;
        }
        // Weighted means and (co)variances, in 1/16 px and (1/16 px)^2.
        let (n, sy, sh) = (self.n as i128, self.sy as i128, self.sh as i128);
        let vy = (self.syy as i128 * n - sy * sy) / (n * n);
        let vh = (self.shh as i128 * n - sh * sh) / (n * n);
        let cov = (self.syh as i128 * n - sy * sh) / (n * n);
        let spread = (min_spread.to_bits().max(0) >> SIXTEENTHS) as i128;
        if vy <= spread * spread || vh <= 0 || 2 * cov * cov < vy * vh {
            return None;
        }
        let k = ((cov << 16) / vy).clamp(-(4 << 16), 4 << 16);
        Some(Q16::from_bits(k as i32))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    fn q(v: f64) -> Q16 {
        Q16::from_f64(v)
    }

    #[test]
    fn recovers_a_noisy_slope() {
        let mut g = GroundPlane::new();
        let mut rng = Rng::new(3);
        for i in 0..200 {
            let cy = 50.0 + (i % 100) as f64 * 3.0;
            let hy = 5.0 + 0.3 * cy + rng.gaussian(q(2.0)).to_f64();
            g.observe(q(cy), q(hy));
        }
        let k = g.slope(q(10.0)).expect("trusted").to_f64();
        assert!((k - 0.3).abs() < 0.03, "{k}");
    }

    #[test]
    fn distrusts_few_samples_a_still_target_and_no_relation() {
        let mut g = GroundPlane::new();
        for i in 0..10 {
            g.observe(q(100.0 + 10.0 * i as f64), q(20.0 + 2.0 * i as f64));
        }
        assert_eq!(g.slope(q(5.0)), None, "10 samples");
        let mut still = GroundPlane::new();
        for i in 0..100 {
            still.observe(q(100.0 + (i % 3) as f64), q(20.0 + (i % 3) as f64));
        }
        assert_eq!(still.slope(q(5.0)), None, "rows within 1 px");
        let mut noise = GroundPlane::new();
        let mut rng = Rng::new(9);
        for i in 0..200 {
            let hy = 20.0 + rng.gaussian(q(5.0)).to_f64();
            noise.observe(q(50.0 + (i % 50) as f64 * 4.0), q(hy));
        }
        assert_eq!(noise.slope(q(5.0)), None, "size independent of row");
    }

    #[test]
    fn forgets_an_old_slope() {
        let mut g = GroundPlane::new();
        for i in 0..300 {
            let cy = 100.0 + (i % 60) as f64 * 2.0;
            g.observe(q(cy), q(0.5 * cy));
        }
        assert!((g.slope(q(5.0)).unwrap().to_f64() - 0.5).abs() < 0.01);
        for i in 0..400 {
            let cy = 100.0 + (i % 60) as f64 * 2.0;
            g.observe(q(cy), q(0.1 * cy + 40.0));
        }
        assert!((g.slope(q(5.0)).unwrap().to_f64() - 0.1).abs() < 0.01);
    }

    #[test]
    fn extreme_inputs_stay_bounded() {
        let mut g = GroundPlane::new();
        for i in 0..1000 {
            let v = if i % 2 == 0 { Q16::MAX } else { Q16::MIN };
            g.observe(v, Q16::MAX);
            g.observe(Q16::from_int(i), Q16::from_int(16 * i));
        }
        if let Some(k) = g.slope(Q16::ZERO) {
            assert!(k >= Q16::from_int(-4) && k <= Q16::from_int(4));
        }
    }
}
