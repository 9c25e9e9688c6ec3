//! Fixed-point arithmetic: the Q16.16 number type of every coordinate, velocity, half-axis
//! and covariance in the per-frame path, and the integer division and square roots it
//! takes.
//!
//! [`Q16`] wraps an `i32` holding `value * 65536`, so it spans
//! `[-32768, 32768 - 2^-16]` with a resolution of `2^-16` (about `1.5e-5`).
//! Products and quotients go through `i64`, and every arithmetic operator saturates at
//! [`Q16::MIN`] / [`Q16::MAX`] instead of wrapping: a runaway filter state sticks at the rail
//! where a test can see it, never flips sign.
//!
//! Float constructors ([`Q16::from_f64`]) exist for configuration time only; the per-frame
//! path is integer arithmetic.
//!
//! # Examples
//! ```
//! use rbtrack::fixed::Q16;
//! let a = Q16::from_int(3);
//! let b = Q16::from_bits(0x8000); // 0.5
//! assert_eq!((a * b).to_bits(), 0x1_8000); // 1.5
//! assert_eq!(Q16::MAX + Q16::ONE, Q16::MAX); // saturates
//! ```

use core::ops::{Add, AddAssign, Div, Mul, Neg, Sub, SubAssign};

mod div;
mod sqrt;

#[doc(hidden)]
pub use div::div_u64_u32;
#[doc(hidden)]
pub use sqrt::{isqrt32, isqrt_u64, sqrt_q8, sqrt_u64_m16, sqrt_u64_q8, SQRT_FRAC_BITS};

/// `2^16`, a [`Q16`]'s raw value per unit, as a float (for the float conversions).
const SCALE: f64 = (1u32 << Q16::FRAC_BITS) as f64;

/// Signed Q16.16 fixed-point number (`i32`, 16 fraction bits), saturating arithmetic.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(transparent)]
pub struct Q16(i32);

impl Q16 {
    /// Number of fraction bits.
    pub const FRAC_BITS: u32 = 16;
    /// 0.
    pub const ZERO: Self = Self(0);
    /// 1.
    pub const ONE: Self = Self(1 << Self::FRAC_BITS);
    /// 0.5.
    pub const HALF: Self = Self(1 << (Self::FRAC_BITS - 1));
    /// Largest value, `32768 - 2^-16`.
    pub const MAX: Self = Self(i32::MAX);
    /// Smallest value, `-32768`.
    pub const MIN: Self = Self(i32::MIN);
    /// Smallest positive value, `2^-16`.
    pub const EPSILON: Self = Self(1);

    /// From the raw representation (`value * 65536`).
    #[inline]
    pub const fn from_bits(bits: i32) -> Self {
        Self(bits)
    }

    /// The raw representation (`value * 65536`).
    #[inline]
    pub const fn to_bits(self) -> i32 {
        self.0
    }

    /// From an integer, saturating outside `[-32768, 32767]`.
    #[inline]
    pub const fn from_int(n: i32) -> Self {
        Self::saturate((n as i64) << Self::FRAC_BITS)
    }

    /// `num / den` rounded toward zero, saturating; `den == 0` gives [`Q16::ZERO`].
    #[inline]
    pub const fn from_ratio(num: i64, den: i64) -> Self {
        if den == 0 {
            return Self::ZERO;
        }
        let wide = ((num as i128) << Self::FRAC_BITS) / den as i128;
        if wide > i32::MAX as i128 {
            Self::MAX
        } else if wide < i32::MIN as i128 {
            Self::MIN
        } else {
            Self(wide as i32)
        }
    }

    /// From a float, rounded to nearest and saturating (NaN gives zero). Configuration
    /// time only: the per-frame path never converts floats.
    #[inline]
    pub fn from_f64(v: f64) -> Self {
        // `as` saturates and maps NaN to 0.
        Self(libm::round(v * SCALE) as i32)
    }

    /// To a float, exactly (for reports, tests and configuration-time tables).
    #[inline]
    pub fn to_f64(self) -> f64 {
        self.0 as f64 / SCALE
    }

    /// Saturates an `i64` raw value to the `i32` range.
    #[inline]
    pub const fn saturate(bits: i64) -> Self {
        let low = bits as i32;
        if low as i64 == bits {
            Self(low)
        } else if bits < 0 {
            Self::MIN
        } else {
            Self::MAX
        }
    }

    /// Largest integer not above `self`.
    #[inline]
    pub const fn floor_int(self) -> i32 {
        self.0 >> Self::FRAC_BITS
    }

    /// Nearest integer, halves rounded up.
    #[inline]
    pub const fn round_int(self) -> i32 {
        ((self.0 as i64 + Self::HALF.0 as i64) >> Self::FRAC_BITS) as i32
    }

    /// Saturating addition.
    #[inline]
    pub const fn saturating_add(self, rhs: Self) -> Self {
        Self(self.0.saturating_add(rhs.0))
    }

    /// Saturating subtraction.
    #[inline]
    pub const fn saturating_sub(self, rhs: Self) -> Self {
        Self(self.0.saturating_sub(rhs.0))
    }

    /// Saturating product, rounded to nearest.
    #[inline]
    pub const fn saturating_mul(self, rhs: Self) -> Self {
        Self::saturate((self.0 as i64 * rhs.0 as i64 + Self::HALF.0 as i64) >> Self::FRAC_BITS)
    }

    /// Saturating quotient, rounded toward zero; division by zero saturates toward the
    /// dividend's sign (`0 / 0` is zero).
    #[inline]
    pub const fn saturating_div(self, rhs: Self) -> Self {
        if rhs.0 == 0 {
            return if self.0 > 0 {
                Self::MAX
            } else if self.0 < 0 {
                Self::MIN
            } else {
                Self::ZERO
            };
        }
        Self::saturate(((self.0 as i64) << Self::FRAC_BITS) / rhs.0 as i64)
    }

    /// Product with an integer, saturating.
    #[inline]
    pub const fn mul_int(self, n: i32) -> Self {
        Self::saturate(self.0 as i64 * n as i64)
    }

    /// Absolute value, saturating (`|MIN|` is `MAX`).
    #[inline]
    pub const fn abs(self) -> Self {
        Self(self.0.saturating_abs())
    }

    /// Square root, rounded down; negative input gives zero.
    #[inline]
    pub const fn sqrt(self) -> Self {
        if self.0 <= 0 {
            return Self::ZERO;
        }
        // sqrt(v 2^16) 2^8 = sqrt(v 2^32) = sqrt(v) 2^16
        Self(isqrt_u64((self.0 as u64) << Self::FRAC_BITS) as i32)
    }

    /// The smaller of two values.
    #[inline]
    pub const fn min(self, other: Self) -> Self {
        if self.0 < other.0 {
            self
        } else {
            other
        }
    }

    /// The larger of two values.
    #[inline]
    pub const fn max(self, other: Self) -> Self {
        if self.0 > other.0 {
            self
        } else {
            other
        }
    }

    /// `self` limited to `[lo, hi]` (`lo <= hi` is the caller's contract).
    #[inline]
    pub const fn clamp(self, lo: Self, hi: Self) -> Self {
        self.max(lo).min(hi)
    }
}

impl Add for Q16 {
    type Output = Self;
    #[inline]
    fn add(self, rhs: Self) -> Self {
        self.saturating_add(rhs)
    }
}

impl Sub for Q16 {
    type Output = Self;
    #[inline]
    fn sub(self, rhs: Self) -> Self {
        self.saturating_sub(rhs)
    }
}

impl Mul for Q16 {
    type Output = Self;
    #[inline]
    fn mul(self, rhs: Self) -> Self {
        self.saturating_mul(rhs)
    }
}

impl Div for Q16 {
    type Output = Self;
    #[inline]
    fn div(self, rhs: Self) -> Self {
        self.saturating_div(rhs)
    }
}

impl Neg for Q16 {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self(self.0.saturating_neg())
    }
}

impl AddAssign for Q16 {
    #[inline]
    fn add_assign(&mut self, rhs: Self) {
        *self = *self + rhs;
    }
}

impl SubAssign for Q16 {
    #[inline]
    fn sub_assign(&mut self, rhs: Self) {
        *self = *self - rhs;
    }
}

impl core::fmt::Display for Q16 {
    /// Decimal with four fraction digits, computed without floats.
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let neg = self.0 < 0;
        let mag = (self.0 as i64).unsigned_abs();
        let (one, half) = (Self::ONE.0 as u64, Self::HALF.0 as u64);
        let int = mag >> Self::FRAC_BITS;
        let frac = ((mag & (one - 1)) * 10_000 + half) >> Self::FRAC_BITS;
        let (int, frac) = if frac == 10_000 {
            (int + 1, 0)
        } else {
            (int, frac)
        };
        write!(f, "{}{}.{:04}", if neg { "-" } else { "" }, int, frac)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversions_round_trip() {
        assert_eq!(Q16::from_int(7).to_bits(), 7 << 16);
        assert_eq!(Q16::from_int(-1).to_bits(), -65536);
        assert_eq!(Q16::from_f64(1.5).to_bits(), 0x1_8000);
        assert_eq!(Q16::from_f64(-0.25).to_f64(), -0.25);
        assert_eq!(Q16::from_f64(f64::NAN), Q16::ZERO);
        assert_eq!(Q16::from_ratio(1, 3).to_bits(), 21845);
        assert_eq!(Q16::from_ratio(5, 0), Q16::ZERO);
    }

    #[test]
    fn saturate_clamps_an_i64_to_the_i32_range() {
        let max = i64::from(i32::MAX);
        let min = i64::from(i32::MIN);
        for (bits, want) in [
            (0, Q16::ZERO),
            (max, Q16::MAX),
            (max + 1, Q16::MAX),
            (1 << 32, Q16::MAX),
            (i64::MAX, Q16::MAX),
            (min, Q16::MIN),
            (min - 1, Q16::MIN),
            (-(1 << 32), Q16::MIN),
            (i64::MIN, Q16::MIN),
            (-5, Q16::from_bits(-5)),
        ] {
            assert_eq!(Q16::saturate(bits), want, "{bits}");
        }
    }

    #[test]
    fn saturates_at_the_edges() {
        assert_eq!(Q16::from_int(40_000), Q16::MAX);
        assert_eq!(Q16::from_int(-40_000), Q16::MIN);
        assert_eq!(Q16::from_f64(1e12), Q16::MAX);
        assert_eq!(Q16::from_f64(-1e12), Q16::MIN);
        assert_eq!(Q16::MAX + Q16::EPSILON, Q16::MAX);
        assert_eq!(Q16::MIN - Q16::EPSILON, Q16::MIN);
        assert_eq!(Q16::MAX * Q16::from_int(2), Q16::MAX);
        assert_eq!(Q16::MAX * Q16::from_int(-2), Q16::MIN);
        assert_eq!(Q16::MIN * Q16::MIN, Q16::MAX);
        assert_eq!(-Q16::MIN, Q16::MAX);
        assert_eq!(Q16::MIN.abs(), Q16::MAX);
        assert_eq!(Q16::ONE / Q16::ZERO, Q16::MAX);
        assert_eq!(-Q16::ONE / Q16::ZERO, Q16::MIN);
        assert_eq!(Q16::ZERO / Q16::ZERO, Q16::ZERO);
        assert_eq!(Q16::from_int(20_000) / Q16::HALF, Q16::MAX);
        assert_eq!(Q16::from_ratio(i64::MAX, 1), Q16::MAX);
        assert_eq!(Q16::MAX.mul_int(-3), Q16::MIN);
    }

    #[test]
    fn arithmetic_rounds_as_documented() {
        let third = Q16::from_ratio(1, 3);
        assert_eq!((third * Q16::from_int(3)).to_bits(), 65535);
        assert_eq!((Q16::EPSILON * Q16::HALF).to_bits(), 1); // 0.5 ulp rounds up
        assert_eq!((Q16::from_int(7) / Q16::from_int(2)).to_bits(), 0x3_8000);
        assert_eq!(Q16::from_f64(2.5).round_int(), 3);
        assert_eq!(Q16::from_f64(-2.5).round_int(), -2);
        assert_eq!(Q16::from_f64(-2.5).floor_int(), -3);
    }

    #[test]
    fn sqrt_matches_float_within_one_ulp() {
        for bits in [
            0,
            1,
            2,
            3,
            65535,
            65536,
            65537,
            1 << 20,
            123_456_789,
            i32::MAX,
        ] {
            let got = Q16::from_bits(bits).sqrt().to_f64();
            let want = Q16::from_bits(bits).to_f64().sqrt();
            assert!(
                got <= want && want - got < 2.0 / 65536.0,
                "{bits}: {got} vs {want}"
            );
        }
        assert_eq!(Q16::from_int(-4).sqrt(), Q16::ZERO);
        assert_eq!(Q16::from_int(4).sqrt(), Q16::from_int(2));
    }

    #[test]
    fn displays_without_floats() {
        extern crate std;
        use std::format;
        assert_eq!(format!("{}", Q16::from_f64(1.5)), "1.5000");
        assert_eq!(format!("{}", Q16::from_f64(-0.25)), "-0.2500");
        assert_eq!(format!("{}", Q16::from_bits(65535)), "1.0000");
        assert_eq!(format!("{}", Q16::MIN), "-32768.0000");
    }
}
