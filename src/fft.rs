//! Radix-2 fast Fourier transforms of complex integer samples, in place over the caller's
//! arrays: 1-D of `N` points and 2-D of `R x C` grids (row-major; the rows' transforms,
//! then the columns'), for the correlation filter's feature grids. `N`, `R` and `C` are
//! powers of two from 2 to [`MAX_POINTS`], checked at compile time. No allocation, no
//! floating point, no panic path.
//!
//! The forward transform is `X_k = sum_j x_j e^(-2 pi i j k / N)`, the inverse
//! `x_j = 1/N sum_k X_k e^(2 pi i j k / N)` (rustfft's forward, and its inverse divided by
//! `N`), so that `inverse(forward(x)) = x`.
//!
//! # Scale: block floating point
//! Samples are `i32` ([`Complex`]), twiddles Q31. A radix-2 butterfly `a +- w b` can grow
//! the largest component `M` of a block by up to `1 + sqrt 2`, so before each stage `M`
//! (over the whole block: the transform, or the whole grid) picks the stage's right shift
//! `s`: 0 while `M <= 2^29`, 1 while `M <= 2^30`, else 2 (`M <= 2^31`). Every output is
//! then below `(1 + sqrt 2) 2^29 + 2 < 1.3e9 < 2^31`: no stage can overflow on any input,
//! `i32::MIN` everywhere included (the adds saturate all the same). A block that never
//! comes near the rails is never shifted. Each function returns the block exponent `e`:
//! the exact transform of the input is the output times `2^e` (`e` counts the shifts, less
//! `log2 N` for the inverse's `1/N`), so a caller adds it to the input's own exponent.
//! [`normalise`] shifts a block up to use the headroom first.
//!
//! # Why Q31 and not Q15
//! A 32 x 32 grid's spectrum grows by up to 10 bits over its samples: in Q15 an 8-bit
//! feature would lose its low bits to the shifts, in Q31 none are lost and the rounding
//! stays near `2^-31` of the block's scale. On the Cortex-M4, without the dual 16-bit
//! multiplies (the core uses no target intrinsics), a Q15 butterfly takes the same four
//! multiplies as a Q31 one (`smull`/`smlal`, one cycle each); Q31 adds the 64-bit
//! rounding and twice the RAM (8 bytes a complex sample, 8 KiB for a 32 x 32 grid). One
//! 32 x 32 forward transform is 243,920 instructions in QEMU (`examples/budget.rs`), about
//! 48 a butterfly.
//!
//! # Accuracy
//! In LSB of the output (`2^e` of the input's units), for a transform of `P` points (`N`,
//! or `R C` in 2-D), against the exact transform:
//! - **Any input: at most [`error_bound_lsb`] = `3 P`.** A stage adds at most 2.2 LSB to
//!   each output (the twiddle's rounding 0.35, the product's 0.71, the shift's 1.06, as
//!   complex magnitudes) and passes on at most twice its inputs' error, halved by each
//!   shift: after `log2 P` stages, at most `2.2 (P - 1) (1 + 2^-30)^log2 P`. A wrapped
//!   overflow would be `2^32` LSB off: the property tests and the fuzz target assert
//!   this bound on full-scale extremes.
//! - **Random inputs: at most `4 + sqrt P`**, the roundings
//!   adding up like a random walk. Against rustfft on random samples of every magnitude,
//!   both directions, the largest error measured is 7.2 LSB at 64 points, 8.8 at 16 x 16,
//!   17.9 at 32 x 32 and 40.2 at 64 x 64 (bounds 12, 20, 36, 68), asserted by
//!   `host-tests/tests/fft.rs`. Repeated patterns add up more coherently: the fuzzer's
//!   largest, 36.9 LSB at 32 x 32.
//!
//! Relative to the signal, a block normalised first ([`normalise`]) keeps above 147 dB;
//! small samples left as they are keep only their own precision (2-bit samples: 18 dB).
//!
//! # Examples
//! ```
//! use rbtrack::fft::{forward, inverse, Complex};
//! let mut x = [Complex::new(1 << 20, -3); 8]; // a constant...
//! assert_eq!(forward(&mut x), 0); // (no shift: far from the rails)
//! assert_eq!(x[0], Complex::new(8 << 20, -24)); // ...is all in bin 0
//! assert_eq!(inverse(&mut x), -3); // 1/8 by the exponent
//! assert_eq!(x, [Complex::new(8 << 20, -24); 8]);
//! ```
//! A size that is not a power of two does not compile:
//! ```compile_fail
//! rbtrack::fft::forward(&mut [rbtrack::fft::Complex::ZERO; 12]);
//! ```

use crate::trig::cos_sin_bits;

/// Largest transform length, points (1-D) or grid side (2-D).
pub const MAX_POINTS: usize = 64;

/// The largest error of any output of a transform of `points` values (`N`, or `R C` in
/// 2-D) on any input, in LSB of the output (`2^e` of the input's units): `3 points`.
pub const fn error_bound_lsb(points: usize) -> u32 {
    3 * points as u32
}

/// A complex sample or spectrum value: integer real and imaginary parts, scaled by the
/// block exponent that goes with the array.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Complex {
    /// Real part.
    pub re: i32,
    /// Imaginary part.
    pub im: i32,
}

impl Complex {
    /// 0.
    pub const ZERO: Self = Self::new(0, 0);

    /// `re + i im`.
    #[inline]
    pub const fn new(re: i32, im: i32) -> Self {
        Self { re, im }
    }

    /// `|re|` and `|im|` ORed, less one for a negative part (`x ^ (x >> 31)`, one
    /// instruction): as many bits as the larger magnitude, one fewer at `-2^k`.
    #[inline]
    fn magnitude_bits(self) -> u32 {
        ((self.re ^ (self.re >> 31)) | (self.im ^ (self.im >> 31))) as u32
    }
}

/// `(cos, sin)` of `2 pi k / MAX_POINTS` for `k < MAX_POINTS / 2`, Q31 (1 saturates to
/// `i32::MAX`): a transform of `N` points takes every `MAX_POINTS / N`-th.
const TWIDDLES: [(i32, i32); MAX_POINTS / 2] = twiddles();

/// The [`TWIDDLES`] table, at compile time.
const fn twiddles() -> [(i32, i32); MAX_POINTS / 2] {
    let mut table = [(0, 0); MAX_POINTS / 2];
    let mut k = 0;
    while k < table.len() {
        let (cos, sin) = cos_sin_bits(k as u32, MAX_POINTS as u32, 31);
        table[k] = (saturate(cos), saturate(sin));
        k += 1;
    }
    table
}

/// `v` clamped to the `i32` range.
const fn saturate(v: i64) -> i32 {
    if v > i32::MAX as i64 {
        i32::MAX
    } else if v < i32::MIN as i64 {
        i32::MIN
    } else {
        v as i32
    }
}

/// The right shift of a stage whose inputs' [`Complex::magnitude_bits`] OR to `mag`: 0
/// for magnitudes up to `2^29`, 1 up to `2^30`, else 2 (see the module doc).
#[inline]
fn stage_shift(mag: u32) -> u32 {
    (u32::BITS - mag.leading_zeros()).saturating_sub(29).min(2)
}

/// `log2 N`, and a compile-time error unless `N` is a power of two in `2..=MAX_POINTS`.
fn log2_points<const N: usize>() -> i32 {
    const {
        assert!(
            N.is_power_of_two() && N >= 2 && N <= MAX_POINTS,
            "FFT sizes are powers of two from 2 to MAX_POINTS"
        )
    };
    N.trailing_zeros() as i32
}

/// What a butterfly transforms: one complex value, or a row of them (the columns of a
/// grid, all at once).
trait Lanes {
    /// `(a, b) <- ((a + w b) / 2^S, (a - w b) / 2^S)`, `w = cos -+ i sin` (forward or
    /// inverse), rounded; the outputs' magnitude bits ORed.
    fn butterfly<const INVERSE: bool, const S: u32>(
        a: &mut Self,
        b: &mut Self,
        w: (i32, i32),
    ) -> u32;

    /// The butterfly of `w = 1` (the first stage's), exact but for the shift.
    fn add_sub<const S: u32>(a: &mut Self, b: &mut Self) -> u32;
}

/// `x / 2^S`, rounded to nearest (half up; `i32::MAX` rounds down).
#[inline]
fn shift_round<const S: u32>(x: i32) -> i32 {
    match S {
        0 => x,
        _ => x.saturating_add(1 << (S - 1)) >> S,
    }
}

impl Lanes for Complex {
    #[inline]
    fn butterfly<const INVERSE: bool, const S: u32>(
        a: &mut Self,
        b: &mut Self,
        w: (i32, i32),
    ) -> u32 {
        // `w b / 2^S`, Q31 products rounded (|.| <= sqrt 2 2^31 / 2^S): the shift is a
        // constant, so taking the product's high word is a shift or nothing.
        let (sin_re, sin_im) = if INVERSE { (-w.1, w.1) } else { (w.1, -w.1) };
        let (cos, bre, bim) = (w.0 as i64, b.re as i64, b.im as i64);
        let half = 1i64 << (30 + S);
        let tre = ((half + bre * cos + bim * sin_re as i64) >> (31 + S)) as i32;
        let tim = ((half + bim * cos + bre * sin_im as i64) >> (31 + S)) as i32;
        let (are, aim) = (shift_round::<S>(a.re), shift_round::<S>(a.im));
        *a = Self::new(are.saturating_add(tre), aim.saturating_add(tim));
        *b = Self::new(are.saturating_sub(tre), aim.saturating_sub(tim));
        a.magnitude_bits() | b.magnitude_bits()
    }

    #[inline]
    fn add_sub<const S: u32>(a: &mut Self, b: &mut Self) -> u32 {
        let (are, aim) = (shift_round::<S>(a.re), shift_round::<S>(a.im));
        let (bre, bim) = (shift_round::<S>(b.re), shift_round::<S>(b.im));
        *a = Self::new(are.saturating_add(bre), aim.saturating_add(bim));
        *b = Self::new(are.saturating_sub(bre), aim.saturating_sub(bim));
        a.magnitude_bits() | b.magnitude_bits()
    }
}

impl<const C: usize> Lanes for [Complex; C] {
    #[inline]
    fn butterfly<const INVERSE: bool, const S: u32>(
        a: &mut Self,
        b: &mut Self,
        w: (i32, i32),
    ) -> u32 {
        a.iter_mut().zip(b.iter_mut()).fold(0, |mag, (a, b)| {
            mag | Complex::butterfly::<INVERSE, S>(a, b, w)
        })
    }

    #[inline]
    fn add_sub<const S: u32>(a: &mut Self, b: &mut Self) -> u32 {
        a.iter_mut()
            .zip(b.iter_mut())
            .fold(0, |mag, (a, b)| mag | Complex::add_sub::<S>(a, b))
    }
}

/// The magnitude bits of every value, ORed.
fn magnitude_bits(values: &[Complex]) -> u32 {
    values.iter().fold(0, |mag, v| mag | v.magnitude_bits())
}

/// Swaps each item with the one at its bit-reversed index.
fn bit_reverse<T, const N: usize>(items: &mut [T; N]) {
    let bits = log2_points::<N>() as u32;
    for i in 1..N {
        let j = (i.reverse_bits() >> (usize::BITS - bits)) & (N - 1);
        if i < j {
            items.swap(i, j);
        }
    }
}

/// One stage of butterflies, `half` apart, shifting by `S`, over every array of `batch`:
/// the outputs' magnitude bits ORed.
fn stage<T: Lanes, const N: usize, const INVERSE: bool, const S: u32>(
    batch: &mut [[T; N]],
    half: usize,
) -> u32 {
    let mut mag = 0;
    if half == 1 {
        for pair in batch.as_flattened_mut().chunks_exact_mut(2) {
            if let [a, b] = pair {
                mag |= T::add_sub::<S>(a, b);
            }
        }
        return mag;
    }
    let stride = (MAX_POINTS / (2 * half)).max(1);
    for items in batch.iter_mut() {
        for group in items.chunks_exact_mut(2 * half) {
            let Some((lo, hi)) = group.split_at_mut_checked(half) else {
                continue;
            };
            // Every `stride`-th twiddle: the first of each chunk.
            for ((a, b), twiddles) in lo.iter_mut().zip(hi).zip(TWIDDLES.chunks_exact(stride)) {
                if let [w, ..] = twiddles {
                    mag |= T::butterfly::<INVERSE, S>(a, b, *w);
                }
            }
        }
    }
    mag
}

/// The transforms of every array of `batch` (decimation in time: bit reversal, then
/// `log2 N` stages), sharing one block exponent. `mag`: the inputs' magnitude bits ORed.
/// Returns the shifts applied and the outputs' magnitude bits.
fn transform<T: Lanes, const N: usize, const INVERSE: bool>(
    batch: &mut [[T; N]],
    mut mag: u32,
) -> (i32, u32) {
    for items in batch.iter_mut() {
        bit_reverse(items);
    }
    let mut shifts = 0;
    for k in 0..log2_points::<N>() {
        let half = 1usize << k;
        let s = stage_shift(mag);
        mag = match s {
            0 => stage::<T, N, INVERSE, 0>(batch, half),
            1 => stage::<T, N, INVERSE, 1>(batch, half),
            _ => stage::<T, N, INVERSE, 2>(batch, half),
        };
        shifts += s as i32;
    }
    (shifts, mag)
}

/// Forward transform of `data` in place; returns the block exponent `e` (the exact
/// transform is the output times `2^e`, `0 <= e <= 2 log2 N`).
pub fn forward<const N: usize>(data: &mut [Complex; N]) -> i32 {
    let mag = magnitude_bits(data);
    transform::<Complex, N, false>(core::slice::from_mut(data), mag).0
}

/// Inverse transform of `data` in place, `1/N` included; returns the block exponent `e`
/// (the exact inverse is the output times `2^e`, `-log2 N <= e <= log2 N`).
pub fn inverse<const N: usize>(data: &mut [Complex; N]) -> i32 {
    let mag = magnitude_bits(data);
    transform::<Complex, N, true>(core::slice::from_mut(data), mag).0 - log2_points::<N>()
}

/// 2-D forward transform of an `R x C` grid in place (rows, then columns); returns the
/// block exponent of the whole grid, as [`forward`]'s.
pub fn forward_2d<const R: usize, const C: usize>(data: &mut [[Complex; C]; R]) -> i32 {
    let mag = magnitude_bits(data.as_flattened());
    let (rows, mag) = transform::<Complex, C, false>(data, mag);
    let (cols, _) = transform::<[Complex; C], R, false>(core::slice::from_mut(data), mag);
    rows + cols
}

/// 2-D inverse transform of an `R x C` grid in place, `1/(R C)` included; returns the
/// block exponent of the whole grid, as [`inverse`]'s.
pub fn inverse_2d<const R: usize, const C: usize>(data: &mut [[Complex; C]; R]) -> i32 {
    let mag = magnitude_bits(data.as_flattened());
    let (rows, mag) = transform::<Complex, C, true>(data, mag);
    let (cols, _) = transform::<[Complex; C], R, true>(core::slice::from_mut(data), mag);
    rows + cols - log2_points::<R>() - log2_points::<C>()
}

/// Shifts a block left as far as no stage then shifts on its first (its largest component
/// below `2^29`), for the most precision; returns the exponent change, `-k` for a shift by
/// `k` (0 for a block already that large, or all zero).
pub fn normalise(data: &mut [Complex]) -> i32 {
    let mag = magnitude_bits(data);
    if mag == 0 {
        return 0;
    }
    let k = (mag.leading_zeros()).saturating_sub(u32::BITS - 29);
    for v in data.iter_mut() {
        *v = Complex::new(v.re << k, v.im << k);
    }
    -(k as i32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;
    use core::f64::consts::PI;
    use std::vec::Vec;

    /// The exact DFT (forward or inverse with `1/N`) of `x` in f64.
    fn dft(x: &[Complex], inverse: bool) -> Vec<(f64, f64)> {
        let n = x.len();
        let sign = if inverse { 1.0 } else { -1.0 };
        let scale = if inverse { 1.0 / n as f64 } else { 1.0 };
        (0..n)
            .map(|k| {
                x.iter().enumerate().fold((0.0, 0.0), |(re, im), (j, v)| {
                    let t = sign * 2.0 * PI * ((j * k) % n) as f64 / n as f64;
                    let (c, s) = (t.cos(), t.sin());
                    let (vr, vi) = (v.re as f64, v.im as f64);
                    (
                        re + scale * (vr * c - vi * s),
                        im + scale * (vr * s + vi * c),
                    )
                })
            })
            .collect()
    }

    /// The bound on random inputs (module doc), LSB.
    fn typical_error_lsb(points: usize) -> f64 {
        4.0 + (points as f64).sqrt()
    }

    /// Largest error of `out` times `2^e` against `want`, in LSB of the output.
    fn max_error_lsb(out: &[Complex], e: i32, want: &[(f64, f64)]) -> f64 {
        let lsb = 2f64.powi(e);
        out.iter().zip(want).fold(0.0, |worst: f64, (o, w)| {
            let (dr, di) = (o.re as f64 - w.0 / lsb, o.im as f64 - w.1 / lsb);
            worst.max(dr.abs()).max(di.abs())
        })
    }

    fn random<const N: usize>(rng: &mut Rng, bits: u32) -> [Complex; N] {
        let mut sample = || (rng.next_u32() as i32) >> (32 - bits);
        core::array::from_fn(|_| Complex::new(sample(), sample()))
    }

    /// One size: random blocks of every magnitude, both directions, within the bound.
    fn matches_the_dft<const N: usize>() {
        let mut rng = Rng::new(N as u64);
        for bits in [4, 12, 20, 28, 30, 32] {
            for _ in 0..8 {
                let x = random::<N>(&mut rng, bits);
                let mut y = x;
                let e = forward(&mut y);
                let err = max_error_lsb(&y, e, &dft(&x, false));
                assert!(err <= typical_error_lsb(N), "N {N}, {bits} bits: {err} LSB");
                let mut z = x;
                let e = inverse(&mut z);
                let err = max_error_lsb(&z, e, &dft(&x, true));
                assert!(
                    err <= typical_error_lsb(N),
                    "N {N}, {bits} bits, inverse: {err} LSB"
                );
            }
        }
    }

    #[test]
    fn twiddles_are_cos_and_sin_within_half_an_lsb() {
        for (k, &(c, s)) in TWIDDLES.iter().enumerate() {
            let t = 2.0 * PI * k as f64 / MAX_POINTS as f64;
            let (want_c, want_s) = (libm::cos(t) * 2f64.powi(31), libm::sin(t) * 2f64.powi(31));
            // 1 saturates to 1 - 2^-31.
            let tol = |v| if v == i32::MAX { 1.0 } else { 0.5 + 1e-6 };
            assert!((c as f64 - want_c).abs() <= tol(c), "cos {k}: {c}");
            assert!((s as f64 - want_s).abs() <= tol(s), "sin {k}: {s}");
        }
    }

    #[test]
    fn an_impulse_at_zero_is_flat_and_exact() {
        let mut x = [Complex::ZERO; 64];
        x[0] = Complex::new(1 << 20, -(1 << 19));
        assert_eq!(forward(&mut x), 0);
        assert!(x.iter().all(|&v| v == Complex::new(1 << 20, -(1 << 19))));
        // At full scale the first stages shift, the block exponent keeps the value.
        let mut x = [Complex::ZERO; 16];
        x[0] = Complex::new(i32::MIN, i32::MIN);
        let e = forward(&mut x);
        assert_eq!(e, 2);
        assert!(x
            .iter()
            .all(|&v| v == Complex::new(i32::MIN >> 2, i32::MIN >> 2)));
    }

    #[test]
    fn a_constant_lands_in_bin_zero() {
        let mut x = [Complex::new(1000, -3000); 32];
        assert_eq!(forward(&mut x), 0);
        assert_eq!(x[0], Complex::new(32_000, -96_000));
        assert!(x[1..].iter().all(|&v| v == Complex::ZERO), "{x:?}");
        // Its inverse is an impulse of the constant: 1/N by the exponent alone.
        let mut x = [Complex::new(1 << 28, 0); 32];
        let e = inverse(&mut x);
        assert_eq!(x[0].re as i64 * (1i64 << (e + 5)), 1i64 << 33);
        assert!(x[1..].iter().all(|&v| v == Complex::ZERO), "{x:?}");
    }

    #[test]
    fn a_tone_lands_in_its_bin() {
        const N: usize = 64;
        for bin in [1usize, 5, 31, 32, 63] {
            let amp = (1 << 24) as f64;
            let x: [Complex; N] = core::array::from_fn(|j| {
                let t = 2.0 * PI * (bin * j) as f64 / N as f64;
                Complex::new(
                    (amp * t.cos()).round() as i32,
                    (amp * t.sin()).round() as i32,
                )
            });
            let mut y = x;
            let e = forward(&mut y);
            let err = max_error_lsb(&y, e, &dft(&x, false));
            assert!(err <= typical_error_lsb(N), "bin {bin}: {err} LSB");
            let power = |v: &Complex| (v.re as f64).powi(2) + (v.im as f64).powi(2);
            let total: f64 = y.iter().map(power).sum();
            assert!(power(&y[bin]) > 0.999_999 * total, "bin {bin}: {y:?}");
        }
    }

    #[test]
    fn every_size_matches_the_dft() {
        matches_the_dft::<2>();
        matches_the_dft::<4>();
        matches_the_dft::<8>();
        matches_the_dft::<16>();
        matches_the_dft::<32>();
        matches_the_dft::<64>();
    }

    #[test]
    fn inverse_of_forward_is_the_input_within_the_bound() {
        let mut rng = Rng::new(7);
        for _ in 0..64 {
            let x = random::<64>(&mut rng, 32);
            let mut y = x;
            let e = forward(&mut y) + inverse(&mut y);
            // The round trip's shifts leave `e` bits of the input's LSB behind.
            let lsb = 2f64.powi(e);
            let err = x.iter().zip(&y).fold(0.0f64, |worst, (x, y)| {
                let dr = (y.re as f64 - x.re as f64 / lsb).abs();
                worst.max(dr).max((y.im as f64 - x.im as f64 / lsb).abs())
            });
            assert!(err <= 2.0 * typical_error_lsb(64), "{err} LSB, e {e}");
        }
    }

    #[test]
    fn parseval_holds_within_the_rounding() {
        let mut rng = Rng::new(11);
        for _ in 0..32 {
            let mut x = random::<32>(&mut rng, 31);
            let energy = |v: &[Complex]| {
                v.iter()
                    .map(|c| (c.re as f64).powi(2) + (c.im as f64).powi(2))
                    .sum::<f64>()
            };
            let before = energy(&x) * 32.0;
            let e = forward(&mut x);
            let after = energy(&x) * 4f64.powi(e);
            assert!((after / before - 1.0).abs() < 1e-6, "{after} / {before}");
        }
    }

    #[test]
    fn the_exponent_counts_only_the_shifts_needed() {
        // Below 2^29 / (1 + sqrt 2)^log2 N nothing shifts: a 64-point block under 2^21.
        let mut rng = Rng::new(3);
        let x = random::<64>(&mut rng, 20);
        assert_eq!(forward(&mut x.clone()), 0);
        assert_eq!(inverse(&mut x.clone()), -6);
        // Full scale shifts at least once a stage after the first, at most twice a stage.
        let mut x = [Complex::new(i32::MIN, i32::MIN); 64];
        let e = forward(&mut x);
        assert!((6..=12).contains(&e), "{e}");
        assert_eq!(x[0].re as i64 * (1i64 << e), 64 * i32::MIN as i64);
        // Normalising a block gives it 29 bits.
        let mut x = [Complex::new(3, -5), Complex::new(0, 1)];
        assert_eq!(normalise(&mut x), -26);
        assert_eq!(
            x,
            [Complex::new(3 << 26, -5 << 26), Complex::new(0, 1 << 26)]
        );
        assert_eq!(normalise(&mut x), 0);
        assert_eq!(normalise(&mut [Complex::ZERO; 4]), 0);
    }

    #[test]
    fn the_2d_transform_is_rows_then_columns() {
        const N: usize = 16;
        let mut rng = Rng::new(5);
        let x: [[Complex; N]; N] = core::array::from_fn(|_| random::<N>(&mut rng, 32));
        let mut y = x;
        let e = forward_2d(&mut y);
        // The exact 2-D DFT: rows, then columns, in f64.
        let rows: Vec<Vec<(f64, f64)>> = x.iter().map(|r| dft(r, false)).collect();
        for col in 0..N {
            let column: Vec<(f64, f64)> = rows.iter().map(|r| r[col]).collect();
            let want: Vec<(f64, f64)> = (0..N)
                .map(|k| {
                    column
                        .iter()
                        .enumerate()
                        .fold((0.0, 0.0), |(re, im), (j, v)| {
                            let t = -2.0 * PI * ((j * k) % N) as f64 / N as f64;
                            (
                                re + v.0 * t.cos() - v.1 * t.sin(),
                                im + v.0 * t.sin() + v.1 * t.cos(),
                            )
                        })
                })
                .collect();
            let got: Vec<Complex> = y.iter().map(|r| r[col]).collect();
            let err = max_error_lsb(&got, e, &want);
            assert!(err <= typical_error_lsb(N * N), "column {col}: {err} LSB");
        }
        let mut z = y;
        let back = inverse_2d(&mut z) + e;
        let lsb = 2f64.powi(back);
        for (zr, xr) in z.iter().zip(&x) {
            for (z, x) in zr.iter().zip(xr) {
                assert!((z.re as f64 - x.re as f64 / lsb).abs() <= 2.0 * typical_error_lsb(N * N));
                assert!((z.im as f64 - x.im as f64 / lsb).abs() <= 2.0 * typical_error_lsb(N * N));
            }
        }
    }
}
