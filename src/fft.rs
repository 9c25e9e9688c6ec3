//! Radix-2 and radix-4 fast Fourier transforms of complex integer samples, in place over
//! the caller's arrays: 1-D of `N` points and 2-D of `R x C` grids (row-major; the rows'
//! transforms, then the columns'), for the correlation filter's feature grids. `N`, `R` and
//! `C` are powers of two from 2 to [`MAX_POINTS`], checked at compile time. No allocation,
//! no floating point, no panic path.
//!
//! The forward transform is `X_k = sum_j x_j e^(-2 pi i j k / N)`, the inverse
//! `x_j = 1/N sum_k X_k e^(2 pi i j k / N)` (rustfft's forward, and its inverse divided by
//! `N`), so that `inverse(forward(x)) = x`. Decimation in time: a bit reversal, a radix-2
//! stage of butterflies 1 apart, radix-4 stages (two radix-2 stages at once, butterflies
//! 2 and 4 apart, then 8 and 16), and a last radix-2 stage where one is left (`N` = 4, 16,
//! 64). The inverse is the forward transform of the conjugate, conjugated, so one
//! transform's code serves both (10 KB less flash in `examples/cf_firmware.rs`, by
//! `llvm-size -A`, than forward and inverse copies).
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
//! included, so the radix-4 adds need no saturation. A block that never comes near the
//! rails is never shifted. Each function returns the block exponent `e`: the exact
//! transform of the input is the output times `2^e` (`e` counts the shifts, less `log2 N`
//! for the inverse's `1/N`), so a caller adds it to the input's own exponent.
//! [`normalise`] shifts a block up to use the headroom first.
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
//! One 32 x 32 forward transform is 170,720 instructions in QEMU (`examples/budget.rs`,
//! Cortex-M4F), 33 a radix-2 butterfly (5,120 of them); 16 x 16, 39,440 (39 a
//! butterfly). A radix-4 butterfly loads, stores and scans each value once for two
//! stages and multiplies three times where four radix-2 butterflies would four; the
//! butterflies of twiddle 1 (the first of each group) multiply not at all, and a radix-2
//! stage's butterfly `j + half / 2` takes the twiddle of `j` turned by a quarter, a swap
//! of parts. The bit reversal is a table of swaps built at compile time, and a square
//! grid's rows are transformed as its transpose's columns.
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

use crate::fixed::Q16;
use crate::trig::cos_sin_bits;
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

/// `(cos, sin)` of `2 pi k / n`, Q31, 1 saturated to `i32::MAX` (`Q16::saturate` clamps
/// any raw `i64`).
const fn twiddle(k: u32, n: u32) -> (i32, i32) {
    let (cos, sin) = cos_sin_bits(k, n, 31);
    (Q16::saturate(cos).to_bits(), Q16::saturate(sin).to_bits())
}

/// The twiddles of every stage, `(cos, sin)` Q31 (1 saturates to `i32::MAX`): those of
/// the stage of butterflies `half` apart, `2 pi j / (2 half)` for `j < half / 2` (a quarter
/// turn), at `half / 2 + j`, so that each stage's are contiguous.
const TWIDDLES: [(i32, i32); MAX_POINTS / 2] = twiddles();

/// The [`TWIDDLES`] table, at compile time.
const fn twiddles() -> [(i32, i32); MAX_POINTS / 2] {
    let mut table = [(0, 0); MAX_POINTS / 2];
    let mut quarter = 1;
    while quarter < table.len() {
        let mut j = 0;
        while j < quarter {
            table[quarter + j] = twiddle(j as u32, 4 * quarter as u32);
            j += 1;
        }
        quarter *= 2;
    }
    table
}

/// The twiddles of the radix-4 stages, `(W^j, W^2j, W^3j)` with `W = (cos, sin)` of
/// `2 pi / (4 h)` Q31, for quarters of `h = 2, 8, ...` points and `j < h`, at
/// `(h - 2) / 3 + j`.
const TWIDDLES4: [[(i32, i32); 3]; (MAX_POINTS / 2 - 2) / 3] = twiddles4();

/// The [`TWIDDLES4`] table, at compile time.
const fn twiddles4() -> [[(i32, i32); 3]; (MAX_POINTS / 2 - 2) / 3] {
    let mut table = [[(0, 0); 3]; (MAX_POINTS / 2 - 2) / 3];
    let mut h = 2;
    while 4 * h <= MAX_POINTS / 2 {
        let mut j = 0;
        while j < h {
            let mut k = 0;
            while k < 3 {
                table[(h - 2) / 3 + j][k] = twiddle(((k + 1) * j) as u32, 4 * h as u32);
                k += 1;
            }
            j += 1;
        }
        h *= 4;
    }
    table
}

/// The right shift of a stage whose inputs' [`Complex::magnitude_bits`] OR to `mag`: 0
/// for magnitudes up to `2^29`, 1 up to `2^30`, else 2 (see the module doc).
#[inline]
fn stage_shift(mag: u32) -> u32 {
    (u32::BITS - mag.leading_zeros()).saturating_sub(29).min(2)
}

/// The right shift of a radix-4 stage whose inputs' magnitude bits OR to `mag`: 0 for
/// magnitudes up to `2^28`, 1 up to `2^29`, 2 up to `2^30`, else 3 (see the module doc).
#[inline]
fn stage_shift4(mag: u32) -> u32 {
    (u32::BITS - mag.leading_zeros()).saturating_sub(28).min(3)
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
    /// `(a, b) <- ((a + r w b) / 2^S, (a - r w b) / 2^S)`, rounded, with `w = cos - i sin`
    /// (`w = 1` exactly if `ONE`) and `r = 1`, or if `QUARTER` the quarter turn `-i` (the
    /// twiddle `N/4` further on); the outputs' magnitude bits ORed.
    fn butterfly<const ONE: bool, const QUARTER: bool, const S: u32>(
        a: &mut Self,
        b: &mut Self,
        w: (i32, i32),
    ) -> u32;

    /// The radix-4 butterfly of the quarters `q` (two radix-2 stages, `h` and `2 h` apart,
    /// at once): `u = (q0, W^2j q1, W^j q2, W^3j q3) / 2^S` (`w` = `W^j, W^2j, W^3j`; all 1
    /// exactly if `ONE`), rounded, then `q0 = u0 + u1 + u2 + u3`, `q1 = u0 - u1 - i (u2 -
    /// u3)`, `q2 = u0 + u1 - u2 - u3`, `q3 = u0 - u1 + i (u2 - u3)`; the outputs' magnitude
    /// bits ORed.
    fn butterfly4<const ONE: bool, const S: u32>(q: [&mut Self; 4], w: &[(i32, i32); 3]) -> u32;
}

/// `x / 2^S`, rounded to nearest (half up; `i32::MAX` rounds down).
#[inline]
fn shift_round<const S: u32>(x: i32) -> i32 {
    match S {
        0 => x,
        _ => x.saturating_add(1 << (S - 1)) >> S,
    }
}

/// `x / 2^S`, rounded to nearest, ties toward zero (as a product by the twiddle table's 1,
/// `1 - 2^-31`, would round): unbiased, where ties up would add a bias to every sum with a
/// [`shift_round`]ed value.
#[inline]
fn shift_round_to_zero<const S: u32>(x: i32) -> i32 {
    match S {
        0 => x,
        _ => x.saturating_add((1 << (S - 1)) - 1 - (x >> 31)) >> S,
    }
}

/// `(x cos + y sin) / 2^(31 + S)`, rounded, for `|x|, |y| <= 2^31`, or `<= 2^29` if `S`
/// is 0: the high word of one 64-bit multiply-accumulate pair (`smull`, `smlal`). For
/// `S = 0` the inputs are doubled first (at most `2^30`, no overflow), so that the
/// result is the high word there too, without a 64-bit shift.
#[inline]
fn q31_dot<const S: u32>(x: i32, y: i32, cos: i32, sin: i32) -> i32 {
    let (x, y, shift) = match S {
        0 => (x << 1, y << 1, 32),
        _ => (x, y, 31 + S),
    };
    (((1i64 << (shift - 1)) + x as i64 * cos as i64 + y as i64 * sin as i64) >> shift) as i32
}

/// `w b / 2^S` (`w = cos - i sin`; `b / 2^S` exactly if `ONE`), each
/// part rounded: `|.| <= sqrt 2 2^31 / 2^S`.
#[inline]
fn twiddled<const ONE: bool, const S: u32>(b: Complex, w: (i32, i32)) -> Complex {
    if ONE {
        Complex::new(
            shift_round_to_zero::<S>(b.re),
            shift_round_to_zero::<S>(b.im),
        )
    } else {
        let sin = w.1;
        Complex::new(
            q31_dot::<S>(b.re, b.im, w.0, sin),
            q31_dot::<S>(b.im, b.re, w.0, sin.wrapping_neg()),
        )
    }
}

impl Lanes for Complex {
    // Inlined into the loops, or the quarters pass through memory.
    #[inline(always)]
    fn butterfly4<const ONE: bool, const S: u32>(
        [q0, q1, q2, q3]: [&mut Self; 4],
        w: &[(i32, i32); 3],
    ) -> u32 {
        // Terms of at most `sqrt 2 2^28 + 1/2`, sums of four of them below `1.5e9` (module
        // doc): the adds wrap nowhere.
        let u0 = Self::new(shift_round::<S>(q0.re), shift_round::<S>(q0.im));
        let u1 = twiddled::<ONE, S>(*q1, w[1]);
        let (are, aim) = (u0.re.wrapping_add(u1.re), u0.im.wrapping_add(u1.im));
        let (bre, bim) = (u0.re.wrapping_sub(u1.re), u0.im.wrapping_sub(u1.im));
        let u2 = twiddled::<ONE, S>(*q2, w[0]);
        let u3 = twiddled::<ONE, S>(*q3, w[2]);
        let (cre, cim) = (u2.re.wrapping_add(u3.re), u2.im.wrapping_add(u3.im));
        // `-i (u2 - u3)`: `(im, -re)` of `u2 - u3`.
        let (dre, dim) = (u2.im.wrapping_sub(u3.im), u3.re.wrapping_sub(u2.re));
        *q0 = Self::new(are.wrapping_add(cre), aim.wrapping_add(cim));
        *q2 = Self::new(are.wrapping_sub(cre), aim.wrapping_sub(cim));
        let mag = q0.magnitude_bits() | q2.magnitude_bits();
        *q1 = Self::new(bre.wrapping_add(dre), bim.wrapping_add(dim));
        *q3 = Self::new(bre.wrapping_sub(dre), bim.wrapping_sub(dim));
        mag | q1.magnitude_bits() | q3.magnitude_bits()
    }

    #[inline]
    fn butterfly<const ONE: bool, const QUARTER: bool, const S: u32>(
        a: &mut Self,
        b: &mut Self,
        w: (i32, i32),
    ) -> u32 {
        let Self { re: tre, im: tim } = twiddled::<ONE, S>(*b, w);
        // `r t`: `-i t = (tim, -tre)`, folded into the adds (no negation to overflow).
        let (are, aim) = (shift_round::<S>(a.re), shift_round::<S>(a.im));
        let (plus, minus) = match QUARTER {
            false => (
                Self::new(are.saturating_add(tre), aim.saturating_add(tim)),
                Self::new(are.saturating_sub(tre), aim.saturating_sub(tim)),
            ),
            true => (
                Self::new(are.saturating_add(tim), aim.saturating_sub(tre)),
                Self::new(are.saturating_sub(tim), aim.saturating_add(tre)),
            ),
        };
        *a = plus;
        *b = minus;
        plus.magnitude_bits() | minus.magnitude_bits()
    }
}

impl<const C: usize> Lanes for [Complex; C] {
    #[inline]
    fn butterfly<const ONE: bool, const QUARTER: bool, const S: u32>(
        a: &mut Self,
        b: &mut Self,
        w: (i32, i32),
    ) -> u32 {
        a.iter_mut().zip(b.iter_mut()).fold(0, |mag, (a, b)| {
            mag | Complex::butterfly::<ONE, QUARTER, S>(a, b, w)
        })
    }

    #[inline]
    fn butterfly4<const ONE: bool, const S: u32>(
        [q0, q1, q2, q3]: [&mut Self; 4],
        w: &[(i32, i32); 3],
    ) -> u32 {
        let mut mag = 0;
        let (mut i0, mut i1, mut i2, mut i3) =
            (q0.iter_mut(), q1.iter_mut(), q2.iter_mut(), q3.iter_mut());
        while let (Some(a0), Some(a1), Some(a2), Some(a3)) =
            (i0.next(), i1.next(), i2.next(), i3.next())
        {
            mag |= Complex::butterfly4::<ONE, S>([a0, a1, a2, a3], w);
        }
        mag
    }
}

/// The magnitude bits of every value, ORed.
fn magnitude_bits(values: &[Complex]) -> u32 {
    values.iter().fold(0, |mag, v| mag | v.magnitude_bits())
}

/// The swaps of a bit reversal of `N` items, `(i, j)` with `i < j`, as a table built at
/// compile time: its first `.1`.
struct BitReversal<const N: usize>;

/// The most swaps of a bit reversal, those of [`MAX_POINTS`] = 64 items: `(64 - 8) / 2`
/// (the 8 indices of 6 bits that read the same reversed stay). A larger `MAX_POINTS`
/// without a larger table does not compile.
const MAX_SWAPS: usize = 28;

impl<const N: usize> BitReversal<N> {
    const SWAPS: ([(u8, u8); MAX_SWAPS], usize) = {
        let mut table = [(0, 0); MAX_SWAPS];
        let (mut i, mut count) = (1, 0);
        while i < N {
            let j = i.reverse_bits() >> (usize::BITS - N.trailing_zeros()) & (N - 1);
            if i < j {
                table[count] = (i as u8, j as u8);
                count += 1;
            }
            i += 1;
        }
        (table, count)
    };
}

/// Swaps each item with the one at its bit-reversed index.
fn bit_reverse<T, const N: usize>(items: &mut [T; N]) {
    let (table, count) = &BitReversal::<N>::SWAPS;
    for &(i, j) in table.get(..*count).unwrap_or_default() {
        if let Some((lo, hi)) = items.split_at_mut_checked(j as usize) {
            if let (Some(a), Some(b)) = (lo.get_mut(i as usize), hi.first_mut()) {
                core::mem::swap(a, b);
            }
        }
    }
}

/// One stage of butterflies `half = 2^k` apart, shifting by `S`, over every array of `batch`:
/// the outputs' magnitude bits ORed. The butterfly `j + half / 2` of a group takes the
/// twiddle of `j` turned by a quarter, and those of `j = 0` and `half / 2` do not multiply.
fn stage<T: Lanes, const N: usize, const S: u32>(batch: &mut [[T; N]], k: i32) -> u32 {
    let mut mag = 0;
    let half = 1 << k;
    let quarter = half / 2;
    // `W^j` of the stage's `2 half` points for `0 < j < half / 2`.
    let twiddles = TWIDDLES.get(quarter + 1..half).unwrap_or_default();
    for group in batch.as_flattened_mut().chunks_exact_mut(1 << (k + 1)) {
        let Some((lo, hi)) = group.split_at_mut_checked(half) else {
            continue;
        };
        if let ([a], [b]) = (&mut *lo, &mut *hi) {
            mag |= T::butterfly::<true, false, S>(a, b, (0, 0));
            continue;
        }
        let (Some((lo0, lo1)), Some((hi0, hi1))) = (
            lo.split_at_mut_checked(quarter),
            hi.split_at_mut_checked(quarter),
        ) else {
            continue;
        };
        if let (Some((a, lo0)), Some((b, hi0))) = (lo0.split_first_mut(), hi0.split_first_mut()) {
            mag |= T::butterfly::<true, false, S>(a, b, (0, 0));
            for ((a, b), w) in lo0.iter_mut().zip(hi0).zip(twiddles) {
                mag |= T::butterfly::<false, false, S>(a, b, *w);
            }
        }
        if let (Some((a, lo1)), Some((b, hi1))) = (lo1.split_first_mut(), hi1.split_first_mut()) {
            mag |= T::butterfly::<true, true, S>(a, b, (0, 0));
            for ((a, b), w) in lo1.iter_mut().zip(hi1).zip(twiddles) {
                mag |= T::butterfly::<false, true, S>(a, b, *w);
            }
        }
    }
    mag
}

/// One radix-4 stage, quarters of `h = 2^k` points, `k > 0` (the radix-2 stages `h` and
/// `2 h` apart at once), shifting by `S`, over every array of `batch`: the outputs'
/// magnitude bits ORed.
fn stage4<T: Lanes, const N: usize, const S: u32>(batch: &mut [[T; N]], k: i32) -> u32 {
    let mut mag = 0;
    let h = 1 << k;
    let twiddles = TWIDDLES4
        .get((h - 2) / 3 + 1..(h - 2) / 3 + h)
        .unwrap_or_default();
    for group in batch.as_flattened_mut().chunks_exact_mut(1 << (k + 2)) {
        let Some((lo, hi)) = group.split_at_mut_checked(2 * h) else {
            continue;
        };
        let (Some((q0, q1)), Some((q2, q3))) =
            (lo.split_at_mut_checked(h), hi.split_at_mut_checked(h))
        else {
            continue;
        };
        let (Some((a0, q0)), Some((a1, q1)), Some((a2, q2)), Some((a3, q3))) = (
            q0.split_first_mut(),
            q1.split_first_mut(),
            q2.split_first_mut(),
            q3.split_first_mut(),
        ) else {
            continue;
        };
        mag |= T::butterfly4::<true, S>([a0, a1, a2, a3], &[(0, 0); 3]);
        let quarters = q0
            .iter_mut()
            .zip(q1.iter_mut())
            .zip(q2.iter_mut().zip(q3.iter_mut()));
        for (((a0, a1), (a2, a3)), w) in quarters.zip(twiddles) {
            mag |= T::butterfly4::<false, S>([a0, a1, a2, a3], w);
        }
    }
    mag
}

/// The transforms of every array of `batch` (decimation in time: bit reversal, then
/// `log2 N` stages), sharing one block exponent. `mag`: the inputs' magnitude bits ORed.
/// Returns the shifts applied and the outputs' magnitude bits.
fn transform<T: Lanes, const N: usize>(batch: &mut [[T; N]], mut mag: u32) -> (i32, u32) {
    for items in batch.iter_mut() {
        bit_reverse(items);
    }
    // Radix 2 for butterflies 1 apart, radix 4 for `2, 4`, `8, 16` apart, and radix 2
    // for the last stage if one is left (`N` = 4, 16 or 64).
    let mut shifts = 0;
    // Butterflies `2^k` apart (`half`, `h`): `1 << k` is never 0, so the chunk sizes have
    // no zero to panic on.
    let mut k = 0;
    while k < log2_points::<N>() {
        let (s, next);
        (s, mag, next) = if k > 0 && k + 2 <= log2_points::<N>() {
            let s = stage_shift4(mag);
            let mag = match s {
                0 => stage4::<T, N, 0>(batch, k),
                1 => stage4::<T, N, 1>(batch, k),
                2 => stage4::<T, N, 2>(batch, k),
                _ => stage4::<T, N, 3>(batch, k),
            };
            (s, mag, k + 2)
        } else {
            let s = stage_shift(mag);
            let mag = match s {
                0 => stage::<T, N, 0>(batch, k),
                1 => stage::<T, N, 1>(batch, k),
                _ => stage::<T, N, 2>(batch, k),
            };
            (s, mag, k + 1)
        };
        shifts += s as i32;
        k = next;
    }
    (shifts, mag)
}

/// Forward transform of `data` in place; returns the block exponent `e` (the exact
/// transform is the output times `2^e`, `0 <= e <= 2 log2 N`).
pub fn forward<const N: usize>(data: &mut [Complex; N]) -> i32 {
    let mag = magnitude_bits(data);
    transform::<Complex, N>(core::slice::from_mut(data), mag).0
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

/// The rows' transforms, then the columns', of `data`: the shifts of both. A square grid's
/// rows are transformed as the columns of its transpose, the same arithmetic in fewer
/// instructions (a butterfly of columns runs along two whole rows with one twiddle): at
/// 32 x 32, 170,720 with the two transposes against 177,680 row by row.
fn transform_2d<const R: usize, const C: usize>(data: &mut [[Complex; C]; R]) -> i32 {
    let mag = magnitude_bits(data.as_flattened());
    let square: Option<&mut [[Complex; R]; C]> = (data as &mut dyn Any).downcast_mut();
    let (rows, mag) = match square {
        Some(grid) => {
            transpose(grid);
            let rows = transform::<[Complex; R], C>(core::slice::from_mut(grid), mag);
            transpose(grid);
            rows
        }
        None => transform::<Complex, C>(data, mag),
    };
    let (cols, _) = transform::<[Complex; C], R>(core::slice::from_mut(data), mag);
    rows + cols
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
    fn twiddles_are_cos_and_sin_within_half_an_lsb() {
        for (k, &(c, s)) in TWIDDLES.iter().enumerate().skip(1) {
            let quarter = 1 << k.ilog2();
            let t = 2.0 * PI * (k - quarter) as f64 / (4 * quarter) as f64;
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
