//! Seeded random numbers without floats: uniform and standard-normal draws in Q16.16.
//!
//! [`Rng`] wraps `rand_xoshiro::Xoshiro128PlusPlus` (16 bytes of state, 32-bit
//! operations only), so the same seed gives the same draws on x86 and on a Cortex-M.
//!
//! Normal draws invert the distribution function by table: one 32-bit word gives the sign
//! (1 bit), a bin of |Z| of equal probability 1/256 (8 bits) and a linear position inside
//! it (23 bits). The outermost bin (|Z| > 2.66) takes a second word and a second table
//! that splits it into 256 finer bins, so the tails reach 5.33 sigma. The moments and
//! tail shares this gives are checked in the tests below.
//!
//! # Examples
//! ```
//! use rbtrack::rng::Rng;
//! let mut a = Rng::new(7);
//! let mut b = Rng::new(7);
//! assert_eq!(a.normal(), b.normal());
//! assert!(a.uniform().to_bits() < 1 << 16);
//! ```

use crate::fixed::Q16;
use rand_core::{Rng as _, SeedableRng};
use rand_xoshiro::Xoshiro128PlusPlus;

include!(concat!(env!("OUT_DIR"), "/normal_table.rs"));

/// Bits of a normal draw's word that choose its bin of equal probability (`2^-8` each).
const BIN_BITS: u32 = 8;

/// Bits of a normal draw's word that place it inside its bin.
const POSITION_BITS: u32 = u32::BITS - 1 - BIN_BITS;

/// Bits of the outermost bin's second word that choose its finer bin.
const TAIL_BIN_BITS: u32 = 8;

/// Bits of the second word that place the draw inside its finer bin.
const TAIL_POSITION_BITS: u32 = u32::BITS - TAIL_BIN_BITS;

/// Deterministic pseudo-random source (Xoshiro128++).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Rng(Xoshiro128PlusPlus);

impl Rng {
    /// A generator seeded from `seed` (any value, zero included).
    pub fn new(seed: u64) -> Self {
        Self(Xoshiro128PlusPlus::seed_from_u64(seed))
    }

    /// A uniformly distributed 32-bit word.
    pub fn next_u32(&mut self) -> u32 {
        self.0.next_u32()
    }

    /// Uniform draw in `[0, 1)`, Q16.16 (raw value in `0..65536`).
    pub fn uniform(&mut self) -> Q16 {
        Q16::from_bits((self.next_u32() >> (u32::BITS - Q16::FRAC_BITS)) as i32)
    }

    /// Uniform integer in `0..n` by multiply-shift (bias below `n / 2^32`); `n == 0` gives 0.
    pub fn below(&mut self, n: u32) -> u32 {
        ((self.next_u32() as u64 * n as u64) >> 32) as u32
    }

    /// Standard-normal draw (mean 0, variance 1), Q16.16, |value| <= 5.33.
    pub fn normal(&mut self) -> Q16 {
        let word = self.next_u32();
        let last_bin = (1 << BIN_BITS) - 1;
        let bin = ((word >> POSITION_BITS) & last_bin) as usize;
        let magnitude = if bin < last_bin as usize {
            let position = word & ((1 << POSITION_BITS) - 1);
            interpolate(&HALF_NORMAL_Q16, bin, position, POSITION_BITS)
        } else {
            let fine = self.next_u32();
            let position = fine & ((1 << TAIL_POSITION_BITS) - 1);
            let bin = (fine >> TAIL_POSITION_BITS) as usize;
            interpolate(&HALF_NORMAL_TAIL_Q16, bin, position, TAIL_POSITION_BITS)
        };
        if word >> 31 == 1 {
            Q16::from_bits(-magnitude)
        } else {
            Q16::from_bits(magnitude)
        }
    }

    /// Normal draw with standard deviation `sigma` (Q16.16), saturating.
    pub fn gaussian(&mut self, sigma: Q16) -> Q16 {
        self.normal() * sigma
    }
}

/// `table[i] + (table[i + 1] - table[i]) * frac / 2^frac_bits`; the callers keep
/// `i + 1 < table.len()` (0 otherwise, never a panic).
fn interpolate(table: &[i32], i: usize, frac: u32, frac_bits: u32) -> i32 {
    debug_assert!(i + 1 < table.len(), "bin {i} past the table's end");
    let (Some(&lo), Some(&hi)) = (table.get(i), table.get(i + 1)) else {
        return 0;
    };
    let (lo, hi) = (lo as i64, hi as i64);
    (lo + (((hi - lo) * frac as i64) >> frac_bits)) as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_draws() {
        let mut a = Rng::new(42);
        let mut b = Rng::new(42);
        for _ in 0..1000 {
            assert_eq!(a.normal(), b.normal());
            assert_eq!(a.next_u32(), b.next_u32());
        }
        assert_ne!(Rng::new(1).next_u32(), Rng::new(2).next_u32());
    }

    #[test]
    fn tables_are_monotone_and_join() {
        assert!(HALF_NORMAL_Q16.windows(2).all(|w| w[0] < w[1]));
        assert!(HALF_NORMAL_TAIL_Q16.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(HALF_NORMAL_Q16[0], 0);
        assert_eq!(HALF_NORMAL_Q16[255], HALF_NORMAL_TAIL_Q16[0]);
    }

    #[test]
    fn below_stays_in_range() {
        let mut r = Rng::new(3);
        for n in [1u32, 2, 7, 100, u32::MAX] {
            for _ in 0..1000 {
                assert!(r.below(n) < n);
            }
        }
        assert_eq!(r.below(0), 0);
    }

    #[test]
    fn uniform_moments() {
        let mut r = Rng::new(9);
        let n = 1_000_000;
        let (mut sum, mut sq) = (0f64, 0f64);
        for _ in 0..n {
            let u = r.uniform().to_f64();
            assert!((0.0..1.0).contains(&u));
            sum += u;
            sq += u * u;
        }
        let mean = sum / n as f64;
        let var = sq / n as f64 - mean * mean;
        assert!((mean - 0.5).abs() < 0.002, "mean {mean}");
        assert!((var / (1.0 / 12.0) - 1.0).abs() < 0.02, "var {var}");
    }

    /// 1e6 draws: mean within 0.01, variance within 2 %, shares beyond 2 and 3 sigma
    /// within 10 % of the normal distribution's (0.045500, 0.002700).
    #[test]
    fn normal_moments_and_tails() {
        let mut r = Rng::new(2024);
        let n = 1_000_000;
        let (mut sum, mut sq, mut beyond2, mut beyond3) = (0f64, 0f64, 0u32, 0u32);
        for _ in 0..n {
            let z = r.normal().to_f64();
            sum += z;
            sq += z * z;
            beyond2 += (z.abs() > 2.0) as u32;
            beyond3 += (z.abs() > 3.0) as u32;
        }
        let mean = sum / n as f64;
        let var = sq / n as f64 - mean * mean;
        let p2 = beyond2 as f64 / n as f64;
        let p3 = beyond3 as f64 / n as f64;
        std::println!("normal, 1e6 draws: mean {mean:.5} var {var:.5} >2s {p2:.6} >3s {p3:.6}");
        assert!(mean.abs() < 0.01, "mean {mean}");
        assert!((var - 1.0).abs() < 0.02, "var {var}");
        assert!((p2 / 0.045_500 - 1.0).abs() < 0.10, "beyond 2 sigma {p2}");
        assert!((p3 / 0.002_700 - 1.0).abs() < 0.10, "beyond 3 sigma {p3}");
    }
}
