//! `cos` and `sin` of a whole fraction of a turn, `2 pi k / n`, rounded to Q16.16 or any
//! other fraction bits in integer arithmetic: the gradient cue's boundary angles, without
//! floating point or a float library in the firmware, and the FFT's Q31 twiddles, built
//! at compile time.
//!
//! The angle is reduced to the first octant exactly (quadrant and complement from `4 k`
//! modulo `n`), then both functions are Taylor series in Q2.62 (to `x^15 / 15!` and
//! `x^16 / 16!`, truncation below `5e-17` for `x <= pi / 4`). The results are rounded to
//! nearest, half away from zero, as `Q16::from_f64(libm::cos(t))` rounds them: the tests
//! check that both agree on every angle of every point count the cue accepts.

use crate::fixed::Q16;

/// `pi / 2` in Q2.62 (rounded down; the next bit is 0).
const HALF_PI_Q62: u64 = 7_244_019_458_077_122_842;

/// 1 in Q2.62.
const ONE_Q62: u64 = 1 << 62;

/// `a b` for `a`, `b` in Q2.62 below 2, rounded down. Not inlined: the tables are built
/// once, and one copy of the 128-bit product is smaller than twenty.
#[inline(never)]
const fn mul_q62(a: u64, b: u64) -> u64 {
    ((a as u128 * b as u128) >> 62) as u64
}

/// `1 - x2 / d1 (1 - x2 / d2 (1 - ...))` over the divisors `d` (innermost last), Q2.62,
/// for `x2 < 1` (every partial value then lies in `(0, 1]`).
const fn nested_series(x2: u64, divisors: &[u64]) -> u64 {
    let (mut inner, mut rest) = (ONE_Q62, divisors);
    while let [outer @ .., d] = rest {
        inner = ONE_Q62
            - match mul_q62(x2, inner).checked_div(*d) {
                Some(q) => q,
                None => 0,
            };
        rest = outer;
    }
    inner
}

/// Rounds a Q2.62 value in `[0, 1]` to `bits <= 62` fraction bits (nearest, half up).
const fn round_q62(v: u64, bits: u32) -> i64 {
    let drop = 62 - bits;
    ((v + ((1 << drop) >> 1)) >> drop) as i64
}

/// `(cos, sin)` of `2 pi k / n` with `bits <= 62` fraction bits, rounded to nearest (half
/// away from zero); `(1, 0)` for `n = 0`. Const, so tables of it are built at compile time.
pub(crate) const fn cos_sin_bits(k: u32, n: u32, bits: u32) -> (i64, i64) {
    if n == 0 {
        return (1 << bits, 0);
    }
    // 4 k / n quarter turns: quadrant `q`, then `r / n` of a quarter turn.
    let quarters = 4 * (k % n) as u64;
    let (quadrant, r) = (quarters / n as u64, quarters % n as u64);
    // Reflect into [0, pi / 4]: cos and sin swap past the octant.
    let swap = 2 * r > n as u64;
    let r = if swap { n as u64 - r } else { r };
    let x = (HALF_PI_Q62 / n as u64) * r;
    let x2 = mul_q62(x, x);
    let cos = nested_series(x2, &[2, 12, 30, 56, 90, 132, 182, 240]);
    let sin = mul_q62(x, nested_series(x2, &[6, 20, 42, 72, 110, 156, 210]));
    let (c, s) = match swap {
        false => (round_q62(cos, bits), round_q62(sin, bits)),
        true => (round_q62(sin, bits), round_q62(cos, bits)),
    };
    match quadrant {
        0 => (c, s),
        1 => (-s, c),
        2 => (-c, -s),
        _ => (s, -c),
    }
}

/// `(cos, sin)` of `2 pi k / n`, Q16.16 rounded to nearest (half away from zero); `(1, 0)`
/// for `n = 0`.
pub(crate) fn cos_sin_of_turn(k: u32, n: u32) -> (Q16, Q16) {
    let (cos, sin) = cos_sin_bits(k, n, Q16::FRAC_BITS);
    (Q16::from_bits(cos as i32), Q16::from_bits(sin as i32))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cue::MAX_POINTS;

    #[test]
    fn equals_the_rounded_float_functions_for_every_point_count() {
        for n in 1..=MAX_POINTS as u32 {
            for k in 0..n {
                let t = 2.0 * core::f64::consts::PI * k as f64 / n as f64;
                let want = (Q16::from_f64(libm::cos(t)), Q16::from_f64(libm::sin(t)));
                assert_eq!(cos_sin_of_turn(k, n), want, "{k} / {n}");
            }
        }
    }

    #[test]
    fn close_to_the_exact_values_for_any_count() {
        for n in [65u32, 100, 360, 1000, 4096, 65_537, u32::MAX] {
            for k in (0..n).step_by((n / 97).max(1) as usize) {
                let t = 2.0 * core::f64::consts::PI * (k as f64 / n as f64);
                let (c, s) = cos_sin_of_turn(k, n);
                assert!((c.to_f64() - t.cos()).abs() <= 1.0 / 65536.0, "{k} / {n}");
                assert!((s.to_f64() - t.sin()).abs() <= 1.0 / 65536.0, "{k} / {n}");
            }
        }
        assert_eq!(cos_sin_of_turn(3, 0), (Q16::ONE, Q16::ZERO));
        assert_eq!(cos_sin_of_turn(5, 4), cos_sin_of_turn(1, 4));
    }
}
