//! Radix-2 and radix-4 fast Fourier transforms of complex integer samples, in place over
//! the caller's arrays: 1-D of `N` points and 2-D of `R x C` grids (row-major; the rows'
//! transforms, then the columns'), for the correlation filter's feature grids. `N`, `R` and
//! `C` are powers of two from 2 to [`MAX_POINTS`], checked at compile time; and the direct
//! transform of a short row of any length ([`forward_direct`], [`inverse_direct_real`]).
//! No allocation, no floating point, no panic path.
//!
//! The forward transform is `X_k = sum_j x_j e^(-2 pi i j k / N)`, the inverse
//! `x_j = 1/N sum_k X_k e^(2 pi i j k / N)` (rustfft's forward, and its inverse divided by
//! `N`), so that `inverse(forward(x)) = x`. Decimation in time: a bit reversal, a radix-2
//! stage of butterflies 1 apart, radix-4 stages (two radix-2 stages at once, butterflies
//! 2 and 4 apart, then 8 and 16), and a last radix-2 stage where one is left (`N` = 4, 16,
//! 64). The inverse is the forward transform of the conjugate, conjugated, so one
//! transform's code serves both.
//!
//! # Scale: block floating point
//! Samples are `i32` ([`Complex`]), twiddles Q31. Before each stage the largest component
//! `M` of the block (the transform, or the whole grid) picks the stage's right shift `s`:
//! - a radix-2 butterfly `a +- w b` grows `M` by up to `1 + sqrt 2`: `s` is 0 while
//!   `M <= 2^29`, 1 while `M <= 2^30`, else 2 (`M <= 2^31`), and every output is below
//!   `(1 + sqrt 2) 2^29 + 2 < 1.3e9`;
//! - a radix-4 butterfly, `u0 +- u1 +- u2 +- u3` with three of the `u` twiddled, grows it
//!   by up to `1 + 3 sqrt 2`: `s` is 0 while `M <= 2^28`, 1, 2 up to `2^29`, `2^30`, else 3,
//!   and every output is below `(1 + 3 sqrt 2) 2^28 + 2 < 1.41e9`.
//!
//! Below `2^31` either way: no stage can overflow on any input, `i32::MIN` everywhere
//! included, so no add needs saturation (they wrap, and never do). A block that never
//! comes near the rails is never shifted. Each function returns the block exponent `e`:
//! the exact transform of the input is the output times `2^e` (`e` counts the shifts,
//! less `log2 N` for the inverse's `1/N`), so a caller adds it to the input's own
//! exponent. [`normalise`] shifts a block up to use the headroom first.
//!
//! # Headroom: stages without a scan
//! A stage's outputs are at most `5/2` (radix 2) or `21/4` (radix 4) times its inputs'
//! largest magnitude, plus the roundings (`grown`): from the input's magnitude, scanned
//! once, that bound proves for the first stages of a block well inside the rails (the
//! correlation filter's Q16 features) that they cannot
//! shift. Those stages skip the scan of their outputs; a stage whose successor the bound
//! cannot clear scans, so the next shift is always read from the values. The shifts, and
//! so the outputs, are those of a scan at every stage, bit for bit.
//!
//! Where the first three stages (butterflies 1 apart, then the radix-4 stage of quarters
//! 2 apart) and the next are proved shift-free, they are exact adds but for two products
//! (`W^1` and `W^3` of 8 points; `W^2 = -i` is exact there), and run on each 8 items in
//! four passes (`eight`) where the stages take seven.
//!
//! # Why Q31 and not Q15
//! A 32 x 32 grid's spectrum grows by up to 10 bits over its samples: in Q15 an 8-bit
//! feature would lose its low bits to the shifts, in Q31 none are lost and the rounding
//! stays near `2^-31` of the block's scale. On the Cortex-M4, without the dual 16-bit
//! multiplies (the core uses no target intrinsics), a Q15 butterfly takes the same four
//! multiplies as a Q31 one (`smull`/`smlal`, one cycle each); Q31 adds the 64-bit
//! rounding and twice the RAM (8 bytes a complex sample, 8 KiB for a 32 x 32 grid).
//!
//! # Cost
//! Instructions in QEMU (Cortex-M4F; `examples/budget.rs` for 32 x 32): one 2-D forward
//! transform of 16 x 16 Q16 samples (the correlation filter's) 20,640, 20.2 a radix-2
//! butterfly (1,024 of them); of full-scale samples, shifting at every stage, 40,600; of
//! 32 x 32 full-scale samples 161,720 (the scale filter's rows take the direct
//! transform instead: 572 a 4-point row of Q21 samples). The butterflies run along runs of values in loops of
//! two runs each: a radix-2 butterfly loads, stores and adds a pair of values, a radix-4
//! one makes two such passes (a loop over four runs takes more registers than the core
//! has, and the compiler then spills), with three multiplies where four radix-2
//! butterflies would take four; the butterflies of twiddle 1 (the first of each group)
//! multiply not at all, and a radix-2 stage's butterfly `j + half / 2` takes the twiddle
//! of `j` turned by a quarter, a swap of parts. A product is two multiply-accumulates and
//! an add of the low word's top bit. The bit reversal is a table of swaps built at
//! compile time; a square grid's rows are transformed as the columns of its transpose,
//! the transpose's both indices bit-reversed, so that one transpose between the passes
//! leaves the columns' items bit-reversed as well.
//!
//! # Accuracy
//! In LSB of the output (`2^e` of the input's units), for a transform of `P` points (`N`,
//! or `R C` in 2-D), against the exact transform:
//! - **Any input: at most [`error_bound_lsb`] = `3 P`.** A radix-2 stage adds at most
//!   2.2 LSB to each output (the twiddle's rounding 0.35, the product's 0.71, the shift's
//!   1.06, as complex magnitudes) and passes on at most twice its inputs' error, halved by
//!   each shift: after `log2 P` stages, at most `2.2 (P - 1) (1 + 2^-30)^log2 P`. A
//!   radix-4 stage adds at most 4.3 (four terms of 1.06) and passes on at most four times
//!   its inputs' error: less than the two radix-2 stages it stands for (6.6, four times),
//!   so the bound holds. A wrapped overflow would be `2^32` LSB off: the property tests
//!   and the fuzz target assert this bound on full-scale extremes.
//! - **Random inputs: at most `4 + sqrt P`**, the roundings
//!   adding up like a random walk. Against rustfft on random samples of every magnitude,
//!   both directions, the largest error measured is 6.5 LSB at 64 points, 11.5 at
//!   16 x 16, 22.4 at 32 x 32 and 47.6 at 64 x 64 (bounds 12, 20, 36, 68), asserted by
//!   `host-tests/tests/fft.rs`. Repeated patterns add up more coherently: fuzzing found
//!   36.9 LSB at 32 x 32, above `4 + sqrt P` and well within `3 P`.
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

use core::any::Any;

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

mod direct;
mod radix;
mod rows;

pub use direct::{forward_direct, inverse_direct_real, MAX_DIRECT_POINTS};

use radix::{log2_points, magnitude_bits, stages};
use rows::{bit_reverse, reverse, transform};

/// The `N`-point transforms of the columns of `data`, blocks of `N` items of `lanes`
/// values (row-major), sharing one block exponent; `mag` and `next` as [`stages`] takes
/// them.
fn columns<const N: usize>(data: &mut [Complex], lanes: usize, mag: u32, next: bool) -> (i32, u32) {
    bit_reverse::<N>(data, lanes);
    stages(data, (log2_points::<N>(), 0), lanes, mag, next)
}

/// Forward transform of `data` in place; returns the block exponent `e` (the exact
/// transform is the output times `2^e`, `0 <= e <= 2 log2 N`).
pub fn forward<const N: usize>(data: &mut [Complex; N]) -> i32 {
    let mag = magnitude_bits(data);
    reverse::<Complex, N>(data);
    transform::<Complex, N>(data, 1, mag, false).0
}

/// The values of `row` at `0, N - 1, N - 2, .., 1`: bin `N - k` (mod `N`) of a spectrum
/// beside bin `k`, where a real signal's spectrum holds the conjugate of bin `k`.
pub fn mirrored<T, const N: usize>(row: &[T; N]) -> impl Iterator<Item = &T> {
    row.iter().take(1).chain(row.iter().skip(1).rev())
}

/// Inverse transform of `data` in place, `1/N` included; returns the block exponent `e`
/// (the exact inverse is the output times `2^e`, `-log2 N <= e <= log2 N`). The forward
/// transform of the conjugate, conjugated: one transform's code serves both.
pub fn inverse<const N: usize>(data: &mut [Complex; N]) -> i32 {
    conjugate(data);
    let e = forward(data);
    conjugate(data);
    e - log2_points::<N>()
}

/// 2-D forward transform of an `R x C` grid in place (rows, then columns); returns the
/// block exponent of the whole grid, as [`forward`]'s.
pub fn forward_2d<const R: usize, const C: usize>(data: &mut [[Complex; C]; R]) -> i32 {
    transform_2d::<R, C>(data)
}

/// 2-D inverse transform of an `R x C` grid in place, `1/(R C)` included; returns the
/// block exponent of the whole grid, as [`inverse`]'s.
pub fn inverse_2d<const R: usize, const C: usize>(data: &mut [[Complex; C]; R]) -> i32 {
    conjugate(data.as_flattened_mut());
    let e = forward_2d(data);
    conjugate(data.as_flattened_mut());
    e - log2_points::<R>() - log2_points::<C>()
}

/// Negates the imaginary parts, saturating (`i32::MIN` becomes `i32::MAX`, 1 LSB off).
fn conjugate(data: &mut [Complex]) {
    for v in data {
        v.im = v.im.saturating_neg();
    }
}

/// The rows' transforms, then the columns', of `data`: the shifts of both.
///
/// A square grid is transformed along its columns both times, a butterfly running along
/// two whole rows with one twiddle: [`reverse_transposed`] leaves each row's bit-reversed
/// values in a column (and scans the grid), the rows' transforms follow as the columns',
/// a transpose leaves their rows bit-reversed as the columns' transforms take them, and
/// those give the spectrum in place. Another grid takes the rows' transforms one row at a
/// time.
fn transform_2d<const R: usize, const C: usize>(data: &mut [[Complex; C]; R]) -> i32 {
    let square: Option<&mut [[Complex; C]; C]> = (data as &mut dyn Any).downcast_mut();
    let (rows, cols) = match square {
        Some(grid) => {
            let mag = reverse_transposed(grid);
            let (rows, mag) = transform::<[Complex; C], C>(grid, C, mag, true);
            transpose(grid);
            (rows, transform::<[Complex; C], C>(grid, C, mag, false).0)
        }
        None => {
            let mag = magnitude_bits(data.as_flattened());
            let (rows, mag) = columns::<C>(data.as_flattened_mut(), 1, mag, true);
            (rows, columns::<R>(data.as_flattened_mut(), C, mag, false).0)
        }
    };
    rows + cols
}

/// `i` with its `N.trailing_zeros()` low bits reversed (`N` a power of two, at least 2).
#[inline(always)]
fn reversed<const N: usize>(i: usize) -> usize {
    ((i as u32).reverse_bits() >> (u32::BITS - N.trailing_zeros()).min(31)) as usize
}

/// Swaps `grid[r][rev c]` and `grid[c][rev r]` for every `c < r` (`rev` the bit reversal
/// of `log2 N` bits), leaving `grid[r][rev r]`: the transpose of the grid with both
/// indices bit-reversed, `grid[rev c][rev r]` now holding what `grid[r][c]` held. Returns
/// the magnitude bits of every value ORed.
fn reverse_transposed<const N: usize>(grid: &mut [[Complex; N]; N]) -> u32 {
    let mut mag = 0;
    for r in 0..N {
        let Some((above, [row, ..])) = grid.split_at_mut_checked(r) else {
            continue;
        };
        let rr = reversed::<N>(r);
        if let Some(v) = row.get(rr) {
            mag |= v.magnitude_bits();
        }
        for (c, upper) in above.iter_mut().enumerate() {
            if let (Some(a), Some(b)) = (row.get_mut(reversed::<N>(c)), upper.get_mut(rr)) {
                core::mem::swap(a, b);
                mag |= a.magnitude_bits() | b.magnitude_bits();
            }
        }
    }
    mag
}

/// Transposes a square grid in place (`R = C`; of another grid, swaps `[i][j]` and
/// `[j][i]` where both exist).
fn transpose<const R: usize, const C: usize>(grid: &mut [[Complex; C]; R]) {
    for i in 1..R {
        let Some((above, [row, ..])) = grid.split_at_mut_checked(i) else {
            continue;
        };
        // `row[j]` and `above[j][i]`, `j < i`.
        for (a, upper) in row.iter_mut().zip(above.iter_mut()) {
            if let Some(b) = upper.get_mut(i) {
                core::mem::swap(a, b);
            }
        }
    }
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

/// The exact DFT (forward, or inverse with `1/N`) of `(re, im)` values in f64: the
/// reference the fixed-point transforms and the filters built on them are tested against.
#[cfg(test)]
pub(crate) fn dft_f64(x: &[(f64, f64)], inverse: bool) -> std::vec::Vec<(f64, f64)> {
    let n = x.len();
    let sign = if inverse { 1.0 } else { -1.0 };
    let scale = if inverse { 1.0 / n as f64 } else { 1.0 };
    (0..n)
        .map(|k| {
            x.iter()
                .enumerate()
                .fold((0.0, 0.0), |(re, im), (j, &(vr, vi))| {
                    let t = sign * core::f64::consts::TAU * ((j * k) % n) as f64 / n as f64;
                    let (c, s) = (t.cos(), t.sin());
                    (
                        re + scale * (vr * c - vi * s),
                        im + scale * (vr * s + vi * c),
                    )
                })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;
    use core::f64::consts::PI;
    use std::vec::Vec;

    /// The exact DFT (forward or inverse with `1/N`) of `x` in f64.
    fn dft(x: &[Complex], inverse: bool) -> Vec<(f64, f64)> {
        let x: Vec<(f64, f64)> = x.iter().map(|v| (v.re as f64, v.im as f64)).collect();
        dft_f64(&x, inverse)
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
    fn an_impulse_at_zero_is_flat_and_exact() {
        let mut x = [Complex::ZERO; 64];
        x[0] = Complex::new(1 << 20, -(1 << 19));
        assert_eq!(forward(&mut x), 0);
        assert!(x.iter().all(|&v| v == Complex::new(1 << 20, -(1 << 19))));
        // At full scale the first stages shift (the first by 2, the radix-4 one above
        // `2^28` by 1), the block exponent keeps the value.
        let mut x = [Complex::ZERO; 16];
        x[0] = Complex::new(i32::MIN, i32::MIN);
        let e = forward(&mut x);
        assert_eq!(e, 3);
        assert!(x
            .iter()
            .all(|&v| v == Complex::new(i32::MIN >> 3, i32::MIN >> 3)));
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
        // A 64-point block under 2^21 stays below each stage's threshold (2^29 for radix 2,
        // 2^28 for radix 4, grown by at most (1 + sqrt 2)^2 (1 + 3 sqrt 2)^2 < 2^7.6):
        // nothing shifts.
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
            let want = dft_f64(&column, false);
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
