//! Likelihoods from cue costs: `exp(-cost)` by table, integer only, and the cost scale
//! `1 / (2 sigma^2)` of a cue.
//!
//! A cue turns its measurement into a cost in Q16.16: the colour cue
//! `(1 - rho) / (2 sigma_c^2)`, the gradient cue `(1 - g)^2 / (2 sigma_g^2)`. The factor
//! `1 / (2 sigma^2)` is computed once from the configuration ([`CostScale`]); per particle
//! there is one multiply and one table look-up with linear interpolation.
//!
//! Accuracy: the table holds `exp(-c)` at steps of 1/64 in `[0, 16]`, rounded to 1/65535;
//! linear interpolation between steps adds at most `65535 (1/64)^2 / 8 = 2.0`, so the result
//! is within 3 of `65535 exp(-c)` (the tests measure 2.41). Costs at or above 16 give 0.
//!
//! # Examples
//! ```
//! use rbtrack::fixed::Q16;
//! use rbtrack::likelihood::{exp_neg, CostScale};
//! let scale = CostScale::from_sigma(0.2).unwrap(); // 1 / (2 * 0.04) = 12.5
//! let cost = scale.cost(Q16::from_f64(0.1)); // 1.25
//! assert_eq!(exp_neg(Q16::ZERO), 65535);
//! assert!((exp_neg(cost) as f64 / 65535.0 - (-1.25f64).exp()).abs() < 1e-4);
//! ```

use crate::fixed::Q16;

include!(concat!(env!("OUT_DIR"), "/exp_table.rs"));

/// Largest cost with a non-zero likelihood, Q16.16 (16.0).
pub const COST_MAX: Q16 = Q16::from_int(16);

/// `log2` of the table's steps per unit of cost: steps of 1/64.
const STEP_LOG2: u32 = 6;

/// Fraction bits of a likelihood from [`exp_neg`]: Q0.16, `65535` standing for
/// `exp(0) = 1`.
pub const LIKELIHOOD_BITS: u32 = 16;

/// `65535 * exp(-cost)` for `cost` in Q16.16; negative costs count as zero, costs at or
/// above [`COST_MAX`] give 0. Result in `0..=65535` (Q0.16).
#[inline]
pub fn exp_neg(cost: Q16) -> u32 {
    let bits = cost.to_bits().max(0) as u32;
    let shift = Q16::FRAC_BITS - STEP_LOG2; // the fraction of a step
    let index = (bits >> shift) as usize;
    let frac = bits & ((1 << shift) - 1);
    match (EXP_NEG_Q16.get(index), EXP_NEG_Q16.get(index + 1)) {
        (Some(&lo), Some(&hi)) => {
            let (lo, hi) = (lo as u32, hi as u32);
            lo - (((lo - hi) * frac + (1 << (shift - 1))) >> shift)
        }
        _ => 0,
    }
}

/// The factor `1 / (2 sigma^2)` that turns a cue's distance into a cost, Q16.16.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CostScale(Q16);

impl CostScale {
    /// Every distance costs nothing.
    pub const ZERO: Self = Self(Q16::ZERO);

    /// From the cue's sigma (dimensionless, in `[0.01, 10]`); `None` outside that range or
    /// for NaN. Configuration time only.
    pub fn from_sigma(sigma: f64) -> Option<Self> {
        if !(0.01..=10.0).contains(&sigma) {
            return None;
        }
        Some(Self(Q16::from_f64(1.0 / (2.0 * sigma * sigma))))
    }

    /// From a sigma in Q16.16 (same range as [`CostScale::from_sigma`]), in integer
    /// arithmetic: `1 / (2 sigma^2)` is `2^47 / bits^2` in Q16.16 (`bits` = `sigma`'s
    /// raw value), rounded to nearest, the value `from_sigma(sigma.to_f64())` gives
    /// (checked for every sigma in the range).
    pub fn from_sigma_q16(sigma: Q16) -> Option<Self> {
        // 0.01 and 10 in Q16.16: 655.36 rounded up, and 655,360.
        let bits = sigma.to_bits();
        if !(656..=655_360).contains(&bits) {
            return None;
        }
        let square = bits as u64 * bits as u64;
        let quotient = (1u64 << 47).checked_div(square)?;
        let half_up = 2 * ((1u64 << 47) - quotient * square) >= square;
        // At most 2^47 / 656^2 + 1 < 2^29.
        Some(Self(Q16::from_bits((quotient + half_up as u64) as i32)))
    }

    /// `distance / (2 sigma^2)`, saturating.
    #[inline]
    pub fn cost(self, distance: Q16) -> Q16 {
        distance * self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_matches_exp_within_three_units() {
        let mut worst = 0f64;
        for bits in (0..=(17 << 16)).step_by(97) {
            let c = bits as f64 / 65536.0;
            let want = if c >= 16.0 { 0.0 } else { 65535.0 * (-c).exp() };
            let got = exp_neg(Q16::from_bits(bits)) as f64;
            worst = worst.max((got - want).abs());
        }
        assert!(worst <= 3.0, "worst {worst}");
    }

    #[test]
    fn edges() {
        assert_eq!(exp_neg(Q16::MIN), 65535);
        assert_eq!(exp_neg(Q16::MAX), 0);
        assert_eq!(exp_neg(COST_MAX), 0);
        assert!(exp_neg(COST_MAX - Q16::EPSILON) <= 1);
        assert!(CostScale::from_sigma(0.0).is_none());
        assert!(CostScale::from_sigma(f64::NAN).is_none());
        let s = CostScale::from_sigma(0.01).unwrap(); // 5000
        assert_eq!(s.cost(Q16::MAX), Q16::MAX);
    }

    #[test]
    fn integer_scale_equals_the_float_one_for_every_sigma() {
        for bits in 0..=700_000 {
            let sigma = Q16::from_bits(bits);
            assert_eq!(
                CostScale::from_sigma_q16(sigma),
                CostScale::from_sigma(sigma.to_f64()),
                "{bits}"
            );
        }
        assert_eq!(CostScale::from_sigma_q16(Q16::from_int(-1)), None);
    }

    #[test]
    fn monotone() {
        let mut last = u32::MAX;
        for bits in (0..(16 << 16)).step_by(13) {
            let v = exp_neg(Q16::from_bits(bits));
            assert!(v <= last);
            last = v;
        }
    }
}
