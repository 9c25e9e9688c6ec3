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

/// Extra fraction bits of the total weight.
const WEIGHT_FRACTION_BITS: u32 = 16;

/// Smallest total weight of a trusted fit: 16 samples' worth.
const MIN_WEIGHT: i64 = 16 << WEIGHT_LOG2;

/// Sixteenths of a pixel per Q16.16 unit shift: `px << 4` from `Q16 >> 12`.
const SIXTEENTHS: u32 = Q16::FRAC_BITS - 4;

/// Largest slope reported, px/px: [`GroundPlane::slope`] clamps to `[-4, 4]`.
const MAX_SLOPE: u32 = 4;

/// Exponentially weighted sums of rows and half-heights (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GroundPlane {
    /// Total weight, with [`WEIGHT_FRACTION_BITS`] more fraction bits than the sums'
    /// weights, so that its forgetting rounds no coarser than theirs.
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
        add(&mut self.n, 1 << WEIGHT_FRACTION_BITS);
        add(&mut self.sy, y);
        add(&mut self.sh, h);
        add(&mut self.syy, y * y);
        add(&mut self.syh, y * h);
        add(&mut self.shh, h * h);
    }

    /// Moves every sample as the picture moved: row `y -> zoom y + offset`, half-height
    /// `h -> zoom h` (`zoom` Q16.16 in `[1/8, 8]`, `offset` px, Q16.16), so that samples
    /// from before a camera's tilt or zoom fit with those after it. Sums saturate.
    pub fn move_rows(&mut self, zoom: Q16, offset: Q16) {
        let one = Q16::ONE.to_bits() as i128;
        let z = zoom.to_bits().clamp(one as i32 >> 3, (one as i32) << 3) as i128;
        let b = (offset.to_bits() >> SIXTEENTHS) as i128;
        let n = self.n as i128;
        // `z s` and `z^2 s` of a sum `s`, back to its own scale.
        let once = |s: i64| (z * s as i128) >> Q16::FRAC_BITS;
        let twice = |s: i64| (((z * z) >> Q16::FRAC_BITS) * s as i128) >> Q16::FRAC_BITS;
        let (zy, zh) = (once(self.sy), once(self.sh));
        let fit = |v: i128| v.clamp(i64::MIN as i128, i64::MAX as i128) as i64;
        self.syy = fit(twice(self.syy) + 2 * b * zy + ((b * b * n) >> WEIGHT_FRACTION_BITS));
        self.syh = fit(twice(self.syh) + b * zh);
        self.shh = fit(twice(self.shh));
        self.sy = fit(zy + ((b * n) >> WEIGHT_FRACTION_BITS));
        self.sh = fit(zh);
    }

    /// The slope `k` of half-height against row (px/px, Q16.16 clamped to `[-4, 4]`), or
    /// `None` while the fit is not trustworthy: under 16 samples' weight, rows spread
    /// (standard deviation) no more than `min_spread` (px, Q16.16), or `r^2 < 1/2`.
    pub fn slope(&self, min_spread: Q16) -> Option<Q16> {
        let weight = self.n >> WEIGHT_FRACTION_BITS;
        if weight < MIN_WEIGHT {
            return None;
        }
        // The total weight tends to `2^(WEIGHT_LOG2 + FORGET_LOG2)` from below.
        let n = u32::try_from(weight).ok()?;
        // Weighted means and (co)variances, in 1/16 px and (1/16 px)^2:
        // `(s_ab n - s_a s_b) / n^2`, rounded toward zero.
        let moment = |s_ab: i64, s_a: i64, s_b: i64| {
            let centred = s_ab as i128 * n as i128 - s_a as i128 * s_b as i128;
            let mag = div_u128_u32(div_u128_u32(centred.unsigned_abs(), n), n) as i128;
            if centred < 0 {
                -mag
            } else {
                mag
            }
        };
        let vy = moment(self.syy, self.sy, self.sy);
        let vh = moment(self.shh, self.sh, self.sh);
        let cov = moment(self.syh, self.sy, self.sh);
        let spread = (min_spread.to_bits().max(0) >> SIXTEENTHS) as i128;
        if vy <= spread * spread || vh <= 0 || 2 * cov * cov < vy * vh {
            return None;
        }
        // `(cov << 16) / vy` rounded toward zero, clamped to 4 (2^18), with `vy > 0`.
        let k = slope_q16(cov.unsigned_abs(), vy.unsigned_abs()) as i32;
        Some(Q16::from_bits(if cov < 0 { -k } else { k }))
    }
}

/// `n / d` rounded down (0 for `d = 0`), exactly, by 32-bit digits: `u64` divisions by a
/// `u32` instead of a `u128` division.
fn div_u128_u32(n: u128, d: u32) -> u128 {
    let mut quotient = 0u128;
    let mut rem = 0u64;
    for shift in [96, 64, 32, 0] {
        // rem < d, so the digit's quotient fits 32 bits.
        let x = rem << 32 | (n >> shift) as u32 as u64;
        let q = x.checked_div(d as u64).unwrap_or(0);
        rem = x - q * d as u64;
        quotient |= (q as u128) << shift;
    }
    quotient
}

/// `min(floor(cov 2^16 / var), 2^18)` for `var > 0` (`2^18` for `var = 0`), by binary
/// long division: the quotient has at most 18 bits.
fn slope_q16(cov: u128, var: u128) -> u32 {
    const LIMIT: u32 = MAX_SLOPE << Q16::FRAC_BITS;
    // floor(cov 2^16 / var) >= 2^18 exactly when cov >= 4 var.
    if cov / MAX_SLOPE as u128 >= var {
        return LIMIT;
    }
    // cov < 4 var: the integer part (at most 3) by subtraction, then 16 fraction bits.
    let (mut quotient, mut rem) = (0u32, cov);
    while rem >= var {
        rem -= var;
        quotient += 1;
    }
    for _ in 0..16 {
        // rem < var, so 2 rem fits and one subtraction brings it below var.
        rem <<= 1;
        quotient <<= 1;
        if rem >= var {
            rem -= var;
            quotient |= 1;
        }
    }
    quotient
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

    /// A tilt of 60 px between two runs of samples of `hy = cy / 4`: moved, the old
    /// samples fit with the new ones; not moved, the fit is lost.
    #[test]
    fn moved_rows_keep_the_fit_across_a_tilt() {
        for moved in [true, false] {
            let mut g = GroundPlane::new();
            for i in 0..40 {
                let cy = 100.0 + i as f64;
                g.observe(q(cy), q(cy / 4.0));
            }
            if moved {
                g.move_rows(Q16::ONE, q(60.0));
            }
            for i in 0..40 {
                let cy = 100.0 + i as f64;
                g.observe(q(cy + 60.0), q(cy / 4.0));
            }
            let k = g.slope(q(10.0));
            match moved {
                true => assert!((k.unwrap().to_f64() - 0.25).abs() < 0.002, "{k:?}"),
                false => assert!(k.is_none_or(|k| (k.to_f64() - 0.25).abs() > 0.03), "{k:?}"),
            }
        }
        // A zoom by 2 about row 0 doubles rows and heights: the slope stays.
        let mut g = GroundPlane::new();
        for i in 0..40 {
            let cy = 50.0 + 2.0 * i as f64;
            g.observe(q(cy), q(cy / 4.0));
        }
        g.move_rows(Q16::from_int(2), Q16::ZERO);
        for i in 0..40 {
            let cy = 100.0 + 4.0 * i as f64;
            g.observe(q(cy), q(cy / 4.0));
        }
        assert!((g.slope(q(10.0)).unwrap().to_f64() - 0.25).abs() < 0.002);
        // Extreme moves saturate instead of overflowing.
        g.move_rows(Q16::MAX, Q16::MAX);
        g.move_rows(Q16::MIN, Q16::MIN);
        let _ = g.slope(Q16::ZERO);
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

    /// The slope by `i128` division, as the fit is defined.
    fn slope_i128(g: &GroundPlane, min_spread: Q16) -> Option<Q16> {
        if g.n >> WEIGHT_FRACTION_BITS < MIN_WEIGHT {
            return None;
        }
        let n = (g.n >> WEIGHT_FRACTION_BITS) as i128;
        let (sy, sh) = (g.sy as i128, g.sh as i128);
        let vy = (g.syy as i128 * n - sy * sy) / (n * n);
        let vh = (g.shh as i128 * n - sh * sh) / (n * n);
        let cov = (g.syh as i128 * n - sy * sh) / (n * n);
        let spread = (min_spread.to_bits().max(0) >> SIXTEENTHS) as i128;
        if vy <= spread * spread || vh <= 0 || 2 * cov * cov < vy * vh {
            return None;
        }
        let k = ((cov << 16) / vy).clamp(-(4 << 16), 4 << 16);
        Some(Q16::from_bits(k as i32))
    }

    #[test]
    fn integer_divisions_equal_the_i128_fit() {
        let mut rng = Rng::new(17);
        let mut trusted = 0;
        for run in 0..400 {
            let mut g = GroundPlane::new();
            let k = Q16::from_bits(rng.next_u32() as i32 >> (8 + run % 12));
            let noise = Q16::from_bits((rng.next_u32() >> (10 + run % 16)) as i32);
            for i in 0..(run % 7) * 40 {
                let cy = match run % 5 {
                    0 => Q16::from_bits(rng.next_u32() as i32),
                    _ => Q16::from_int((i * 37 + run) % 480),
                };
                let hy = Q16::from_int(20) + k * cy + rng.gaussian(noise);
                g.observe(cy, hy);
                let spread = Q16::from_bits((rng.next_u32() >> 12) as i32);
                let want = slope_i128(&g, spread);
                trusted += want.is_some() as u32;
                assert_eq!(g.slope(spread), want, "run {run}, sample {i}");
            }
        }
        assert!(trusted > 10_000, "{trusted} trusted fits");
        for i in 0..100_000u32 {
            let cov = (rng.next_u32() as u128) << (i % 80);
            let var = (rng.next_u32() as u128 | 1) << (i / 7 % 80);
            let want = ((cov << 16) / var).min(4 << 16);
            assert_eq!(slope_q16(cov, var) as u128, want, "{cov} / {var}");
        }
        let wide = u128::MAX >> 2;
        assert_eq!(div_u128_u32(wide, 3), wide / 3);
        assert_eq!(div_u128_u32(wide, u32::MAX), wide / u32::MAX as u128);
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
