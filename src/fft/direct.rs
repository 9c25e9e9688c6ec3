//! The direct transform of a short row of any length `N` from 2 to [`MAX_DIRECT_POINTS`]:
//! `X_k = sum_j x_j e^(-2 pi i j k / N)` summed term by term, for rows too short for the
//! fast transform to pay (the scale filter's 4 scales by default) and of lengths it does not
//! take (5, say).
//!
//! Bins `k` and `N - k` share their sums: with `A_k = sum_j x_j cos(2 pi j k / N)` and
//! `B_k = sum_j x_j sin(2 pi j k / N)` (complex), `X_k = A_k - i B_k` and
//! `X_N-k = A_k + i B_k`; and points `j` and `N - j` share a cosine and negate a sine, so
//! `A_k` takes `x_j + x_N-j` and `B_k` takes `x_j - x_N-j`: a row is 4 multiply-accumulates
//! for each `k` and `j` from 1 up to `N / 2` (`k` from 0), 24 for 5 points and 80 for 8,
//! against `4 N^2` term by term. The twiddles are a compile-time table indexed by `k` and
//! `j`.
//!
//! # Scale
//! Twiddles Q27 (built at compile time). Input parts are saturated to `[-2^30, 2^30)`
//! first, so a sum or difference of two fits an `i32`; each product of one and a twiddle
//! is at most `2^58`, `A_k` and `B_k` sums of at most 8 of them and the first point's
//! `2^57`, so `A_k +- i B_k` stays below `2^62`: an `i64` wraps nowhere, on any input.
//! Outputs are rounded and saturated to `i32`; there is no block exponent. Against the
//! exact transform of the saturated input an output is off by at most `1/2` LSB plus
//! `2^-28` times the sum of the input's magnitudes (each twiddle within `2^-28`): below
//! 1 LSB for inputs below `2^27 / N`.

use super::Complex;
use crate::trig::cos_sin_bits;

/// Longest row of the direct transforms, points.
pub const MAX_DIRECT_POINTS: usize = 16;

/// Fraction bits of the twiddles.
const TWIDDLE_BITS: u32 = 27;

/// Rows of the twiddle matrix: `k` up to `N / 2`.
const ROWS: usize = MAX_DIRECT_POINTS / 2 + 1;

/// `(cos, sin)` of `2 pi j k / N`, Q27, at `[k][j]` for `j, k <= N / 2`.
const fn twiddles<const N: usize>() -> [[(i32, i32); ROWS]; ROWS] {
    let mut table = [[(0, 0); ROWS]; ROWS];
    let mut k = 0;
    while k <= N / 2 && k < ROWS {
        let mut j = 0;
        while j <= N / 2 && j < ROWS {
            let (cos, sin) = cos_sin_bits((j * k % N) as u32, N as u32, TWIDDLE_BITS);
            table[k][j] = (cos as i32, sin as i32);
            j += 1;
        }
        k += 1;
    }
    table
}

/// Largest magnitude of an input part: parts beyond `[-2^30, 2^30)` are saturated to it,
/// so that `x_j + x_N-j` and `x_j - x_N-j` fit an `i32`.
const INPUT_LIMIT: i32 = 1 << 30;

/// `sum_j x_j e^(-2 pi i j k / N)` of `data` for every `k`, Q27 times the input's units,
/// `(re, im)`, each handed to `out` with its `k`.
#[inline(always)]
fn sums<const N: usize>(data: &[Complex; N], mut out: impl FnMut(usize, (i64, i64))) {
    const {
        assert!(
            N >= 2 && N <= MAX_DIRECT_POINTS,
            "direct transforms take 2 to 16 points"
        )
    };
    let table = const { twiddles::<N>() };
    let at = |j: usize| {
        let v = data.get(j).copied().unwrap_or_default();
        let limit = |v: i32| v.clamp(-INPUT_LIMIT, INPUT_LIMIT - 1);
        (limit(v.re), limit(v.im))
    };
    let first = at(0);
    for k in 0..=N / 2 {
        let Some(row) = table.get(k) else { continue };
        let mut a = (
            i64::from(first.0) << TWIDDLE_BITS,
            i64::from(first.1) << TWIDDLE_BITS,
        );
        let mut b = (0i64, 0i64);
        // Points j and N - j share a cosine and negate a sine: their sum meets the
        // cosine, their difference the sine; an even N's middle point (j = N - j) meets
        // the cosine alone.
        for j in 1..=N / 2 {
            let Some(&(c, s)) = row.get(j) else { continue };
            let (p, m) = (at(j), at(N - j));
            let (sum, diff) = match 2 * j == N {
                true => (p, (0, 0)),
                false => ((p.0 + m.0, p.1 + m.1), (p.0 - m.0, p.1 - m.1)),
            };
            a = (
                a.0 + i64::from(sum.0) * i64::from(c),
                a.1 + i64::from(sum.1) * i64::from(c),
            );
            b = (
                b.0 + i64::from(diff.0) * i64::from(s),
                b.1 + i64::from(diff.1) * i64::from(s),
            );
        }
        // X_k = A - i B, X_N-k = A + i B.
        out(k, (a.0 + b.1, a.1 - b.0));
        if 2 * k != N && k != 0 {
            out(N - k, (a.0 - b.1, a.1 + b.0));
        }
    }
}

/// The forward transform of `data` in place, rounded (half up), saturated (no block
/// exponent).
pub fn forward_direct<const N: usize>(data: &mut [Complex; N]) -> &mut [Complex; N] {
    let round = |v: i64| {
        let v = (v + (1 << (TWIDDLE_BITS - 1))) >> TWIDDLE_BITS;
        v.clamp(i32::MIN.into(), i32::MAX.into()) as i32
    };
    let mut spectrum = [Complex::ZERO; N];
    sums(data, |k, (re, im)| {
        if let Some(v) = spectrum.get_mut(k) {
            *v = Complex::new(round(re), round(im));
        }
    });
    *data = spectrum;
    data
}

/// The real parts of the inverse transform of `spectrum`, `1/N` included, rounded to
/// nearest (half away from zero), saturated: `x_j = 1/N sum_k X_k e^(2 pi i j k / N)`,
/// the signal of a Hermitian spectrum.
pub fn inverse_direct_real<const N: usize>(spectrum: &[Complex; N]) -> [i32; N] {
    // The inverse is the forward transform of the conjugate, conjugated: the real parts
    // are those of the forward transform of the conjugate.
    let mut conjugate = *spectrum;
    for v in conjugate.iter_mut() {
        v.im = v.im.saturating_neg();
    }
    let d = (N as i64) << TWIDDLE_BITS;
    let mut out = [0; N];
    sums(&conjugate, |j, (re, _)| {
        let q = match re >= 0 {
            true => (re + d / 2) / d,
            false => (re - d / 2) / d,
        };
        if let Some(v) = out.get_mut(j) {
            *v = q.clamp(i32::MIN.into(), i32::MAX.into()) as i32;
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fft::dft_f64;
    use crate::rng::Rng;

    fn random<const N: usize>(rng: &mut Rng, bits: u32) -> [Complex; N] {
        let mut v = || (rng.next_u32() as i32) >> (32 - bits);
        core::array::from_fn(|_| Complex::new(v(), v()))
    }

    fn worst_error<const N: usize>(bits: u32) -> f64 {
        let mut rng = Rng::new(N as u64 + bits as u64);
        let mut worst: f64 = 0.0;
        for _ in 0..200 {
            let x = random::<N>(&mut rng, bits);
            let want = dft_f64(&x.map(|v| (v.re as f64, v.im as f64)), false);
            let mut got = x;
            forward_direct(&mut got);
            for (g, w) in got.iter().zip(&want) {
                let clamp = |v: f64| v.round().clamp(i32::MIN as f64, i32::MAX as f64);
                worst = worst
                    .max((g.re as f64 - clamp(w.0)).abs())
                    .max((g.im as f64 - clamp(w.1)).abs());
            }
        }
        worst
    }

    #[test]
    fn forward_agrees_with_the_f64_transform_within_the_bound() {
        // Inputs below 2^21 (the scale filter's Q21 features): within 1 LSB.
        assert!(worst_error::<2>(22) <= 1.0);
        assert!(worst_error::<4>(22) <= 1.0);
        assert!(worst_error::<5>(22) <= 1.0);
        assert!(worst_error::<8>(22) <= 1.0);
        assert!(worst_error::<16>(22) <= 1.0);
        // Inputs up to 2^30 (none saturated), saturating where the exact output leaves
        // i32: within 1/2 + 2^-28 N 2^30 = 1/2 + 4 N.
        assert!(worst_error::<5>(31) <= 0.5 + 4.0 * 5.0);
        assert!(worst_error::<16>(31) <= 0.5 + 4.0 * 16.0);
    }

    #[test]
    fn extremes_saturate_without_wrapping() {
        let mut x = [Complex::new(i32::MIN, i32::MAX); 16];
        forward_direct(&mut x);
        assert_eq!(x[0], Complex::new(i32::MIN, i32::MAX));
        // Parts beyond 2^30 are saturated first: bin 0 of a row of one large value.
        let mut x = [Complex::ZERO; 5];
        x[1] = Complex::new(i32::MAX, i32::MIN);
        forward_direct(&mut x);
        assert_eq!(x[0], Complex::new((1 << 30) - 1, -(1 << 30)));
        // The inverse of a constant spectrum is an impulse, of the saturated value.
        let x = [Complex::new(i32::MAX, i32::MIN); 16];
        assert_eq!(inverse_direct_real(&x)[0], (1 << 30) - 1);
        let mut x = [Complex::new(i32::MIN, i32::MIN); 5];
        forward_direct(&mut x);
        assert_eq!(x[0], Complex::new(i32::MIN, i32::MIN));
    }

    #[test]
    fn inverse_undoes_forward_for_real_rows() {
        let mut rng = Rng::new(7);
        for _ in 0..100 {
            let x: [Complex; 5] = random::<5>(&mut rng, 22).map(|v| Complex::new(v.re, 0));
            let mut spectrum = x;
            forward_direct(&mut spectrum);
            let back = inverse_direct_real(&spectrum);
            for (b, x) in back.iter().zip(&x) {
                assert!((b - x.re).abs() <= 1, "{b} {}", x.re);
            }
        }
    }
}
