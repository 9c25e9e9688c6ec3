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
//! correlation filter's Q16 features, its scale filter's Q21 ones) that they cannot
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
//! 32 x 32 full-scale samples 161,800; one 8-point transform of Q21 samples (the scale
//! filter's) 305, 25 a butterfly. The butterflies run along runs of values in loops of
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

/// How a stage runs: [`FAST`], [`SCAN`] or [`SHIFT`].
type Mode = u8;

/// No shift, and no scan of the outputs: the headroom proves that the next stage does
/// not shift either.
const FAST: Mode = 0;

/// No shift; the outputs' magnitude bits ORed, for the next stage's shift.
const SCAN: Mode = 1;

/// A right shift by `s` in `1..=3`; the outputs' magnitude bits ORed.
const SHIFT: Mode = 2;

/// The parts of a stage's shift `s` (`1..=3`; unused without a shift) its arithmetic
/// takes: `2^(s - 1)`, the rounding of a product `2^(30 + s)` and `s - 1`.
#[derive(Clone, Copy)]
struct Shift {
    s: u32,
    half: i32,
    product_half: i64,
}

impl Shift {
    fn new(s: u32) -> Self {
        let s = s.clamp(1, 3);
        Self {
            s,
            half: 1 << (s - 1),
            product_half: 1 << (30 + s),
        }
    }

    /// `x / 2^s`, rounded to nearest (half up; `i32::MAX` rounds down).
    #[inline(always)]
    fn round(self, x: i32) -> i32 {
        x.saturating_add(self.half) >> self.s
    }

    /// `x / 2^s`, rounded to nearest, ties toward zero (as a product by the twiddle
    /// table's 1, `1 - 2^-31`, would round): unbiased, where ties up would add a bias to
    /// every sum with a [`Shift::round`]ed value.
    #[inline(always)]
    fn round_to_zero(self, x: i32) -> i32 {
        x.saturating_add(self.half - 1 - (x >> 31)) >> self.s
    }
}

/// `w b` (`w = cos - i sin`, Q31, `nsin = -sin`), each part rounded (half up), without a
/// shift: for parts of at most `2^29`, doubled, the high word of the 64-bit sum of
/// products, plus the low word's top bit (`smull`, `smlal`, an add).
#[inline(always)]
fn rotated(b: Complex, (cos, sin, nsin): (i32, i32, i32)) -> Complex {
    let (x, y) = (i64::from(b.re << 1), i64::from(b.im << 1));
    let (cos, sin, nsin) = (i64::from(cos), i64::from(sin), i64::from(nsin));
    let high = |p: i64| ((p >> 32) as i32).wrapping_add((p as u32 >> 31) as i32);
    Complex::new(high(x * cos + y * sin), high(y * cos + x * nsin))
}

/// `w b / 2^s` (`w = cos - i sin`, Q31, `nsin = -sin`), each part rounded (half up), for
/// parts of at most `2^31`: `|.| <= sqrt 2 2^31 / 2^s`.
#[inline(always)]
fn rotated_shifted(b: Complex, (cos, sin, nsin): (i32, i32, i32), shift: Shift) -> Complex {
    let (x, y) = (i64::from(b.re), i64::from(b.im));
    let (cos, sin, nsin) = (i64::from(cos), i64::from(sin), i64::from(nsin));
    // The sum rounded, then `>> 32` and `>> (s - 1)`: a 64-bit shift by 31 + s.
    let round = |p: i64| (((p + shift.product_half) >> 32) as i32) >> (shift.s - 1);
    Complex::new(round(x * cos + y * sin), round(y * cos + x * nsin))
}

/// `b` times the twiddle `w` (exactly 1 if `ONE`), divided by `2^s` if `SHIFTED`.
#[inline(always)]
fn twiddled<const ONE: bool, const SHIFTED: bool>(
    b: Complex,
    w: (i32, i32, i32),
    shift: Shift,
) -> Complex {
    match (ONE, SHIFTED) {
        (true, true) => Complex::new(shift.round_to_zero(b.re), shift.round_to_zero(b.im)),
        (true, false) => b,
        (false, true) => rotated_shifted(b, w, shift),
        (false, false) => rotated(b, w),
    }
}

/// A twiddle `(cos, sin)` with `-sin`.
#[inline(always)]
fn with_neg((cos, sin): (i32, i32)) -> (i32, i32, i32) {
    (cos, sin, sin.wrapping_neg())
}

/// Where a kernel works in `data`: in every group of `stride` values, the `len` values
/// from `first` (`lo`) and the `len` values `apart` further on (`hi`).
#[derive(Clone, Copy)]
struct Runs {
    first: usize,
    len: usize,
    apart: usize,
    stride: usize,
}

impl Runs {
    /// The pairs of runs `(lo, hi)` of every group.
    #[inline(always)]
    fn of(self, data: &mut [Complex]) -> impl Iterator<Item = (&mut [Complex], &mut [Complex])> {
        data.chunks_exact_mut(self.stride.max(1))
            .filter_map(move |group| {
                let (lo, hi) = group.split_at_mut((self.first + self.apart).min(group.len()));
                let lo = lo.get_mut(self.first..)?.get_mut(..self.len)?;
                Some((lo, hi.get_mut(..self.len)?))
            })
    }
}

/// The radix-2 butterflies of the runs `at` of `data`, `(a, b) <- (a + r w b, a - r w b)`
/// for `a` in `lo` and `b` in `hi`, divided by `2^s` (rounded) if `SHIFTED`, with
/// `w = cos - i sin` (`w = 1` exactly if `ONE`) and `r = 1`, or if `QUARTER` the quarter
/// turn `-i` (the twiddle `N/4` further on); the outputs' magnitude bits ORed if
/// `SCANNED`, else 0. Each output below `1.3e9` (module doc): the adds wrap nowhere.
#[inline(never)]
fn butterflies<const ONE: bool, const QUARTER: bool, const SHIFTED: bool, const SCANNED: bool>(
    data: &mut [Complex],
    at: Runs,
    w: (i32, i32),
    shift: Shift,
) -> u32 {
    let w = with_neg(w);
    let mut mag = 0;
    for (lo, hi) in at.of(data) {
        for (a, b) in lo.iter_mut().zip(hi) {
            let t = twiddled::<ONE, SHIFTED>(*b, w, shift);
            let u = match SHIFTED {
                true => Complex::new(shift.round(a.re), shift.round(a.im)),
                false => *a,
            };
            // `-i t = (tim, -tre)`, folded into the adds.
            let (tre, tim) = match QUARTER {
                false => (t.re, t.im),
                true => (t.im, t.re.wrapping_neg()),
            };
            *a = Complex::new(u.re.wrapping_add(tre), u.im.wrapping_add(tim));
            *b = Complex::new(u.re.wrapping_sub(tre), u.im.wrapping_sub(tim));
            if SCANNED {
                mag |= a.magnitude_bits() | b.magnitude_bits();
            }
        }
    }
    mag
}

/// `(c, d) <- (u + v, u - v)` for `u = w c`, `v = x d` (`c` in `lo`, `d` in `hi` of the
/// runs `at`; `w`, `x` twiddles as [`butterflies`] takes them, both 1 exactly if `ONE`),
/// divided by `2^s` if `SHIFTED`: the sum and difference of the third and fourth twiddled
/// terms of radix-4 butterflies.
#[inline(never)]
fn twiddled_pairs<const ONE: bool, const SHIFTED: bool>(
    data: &mut [Complex],
    at: Runs,
    (w, x): ((i32, i32), (i32, i32)),
    shift: Shift,
) {
    let (w, x) = (with_neg(w), with_neg(x));
    for (lo, hi) in at.of(data) {
        for (c, d) in lo.iter_mut().zip(hi) {
            let u = twiddled::<ONE, SHIFTED>(*c, w, shift);
            let v = twiddled::<ONE, SHIFTED>(*d, x, shift);
            *c = Complex::new(u.re.wrapping_add(v.re), u.im.wrapping_add(v.im));
            *d = Complex::new(u.re.wrapping_sub(v.re), u.im.wrapping_sub(v.im));
        }
    }
}

/// A [`butterflies`] kernel.
type Run = fn(&mut [Complex], Runs, (i32, i32), Shift) -> u32;

/// A [`twiddled_pairs`] kernel.
type Pairs = fn(&mut [Complex], Runs, ((i32, i32), (i32, i32)), Shift);

/// The [`butterflies`] of a stage in `MODE`: shifting and scanning as it says.
const fn run<const ONE: bool, const QUARTER: bool, const MODE: Mode>() -> Run {
    match MODE {
        FAST => butterflies::<ONE, QUARTER, false, false>,
        SCAN => butterflies::<ONE, QUARTER, false, true>,
        _ => butterflies::<ONE, QUARTER, true, true>,
    }
}

/// One radix-2 stage over `data`, items of `lanes` values (row-major), butterflies
/// `half_lanes / lanes` items apart (`half`): the outputs' magnitude bits ORed (0 if
/// `MODE` is [`FAST`]). The butterfly `j + half / 2` of a group takes the twiddle of `j`
/// turned by a quarter, and those of `j = 0` and `half / 2` do not multiply.
fn stage<const MODE: Mode>(data: &mut [Complex], half_lanes: usize, lanes: usize, s: u32) -> u32 {
    let (lanes, shift) = (lanes.max(1), Shift::new(s));
    let half = half_lanes / lanes;
    // `W^j` of the stage's `2 half` points for `0 < j < half / 2`.
    let twiddles = TWIDDLES.get(half / 2 + 1..half).unwrap_or_default();
    let one = (0, 0);
    let at = |j: usize| Runs {
        first: j * lanes,
        len: lanes,
        apart: half_lanes,
        stride: 2 * half_lanes,
    };
    if half == 1 {
        return run::<true, false, MODE>()(data, at(0), one, shift);
    }
    let quarter = half / 2;
    let mut mag = run::<true, false, MODE>()(data, at(0), one, shift);
    mag |= run::<true, true, MODE>()(data, at(quarter), one, shift);
    for (j, &w) in (1..).zip(twiddles) {
        mag |= run::<false, false, MODE>()(data, at(j), w, shift);
        mag |= run::<false, true, MODE>()(data, at(quarter + j), w, shift);
    }
    mag
}

/// One radix-4 stage over `data`, items of `lanes` values, quarters of `h = h_lanes /
/// lanes` items, `h >= 2` (the radix-2 stages `h` and `2 h` apart at once): the outputs'
/// magnitude bits ORed (0 if `MODE` is [`FAST`]).
///
/// The butterflies of the quarters `q` (`w` = `W^j, W^2j, W^3j`): `u = (q0, W^2j q1,
/// W^j q2, W^3j q3) / 2^s`, rounded, then `q0 = u0 + u1 + u2 + u3`, `q1 = u0 - u1 -
/// i (u2 - u3)`, `q2 = u0 + u1 - u2 - u3`, `q3 = u0 - u1 + i (u2 - u3)`, in two passes
/// of two quarters each (a loop over four runs of values takes more registers than the
/// core has): `(q0, q1) <- (u0 + u1, u0 - u1)`, `(q2, q3) <- (u2 + u3, u2 - u3)`, then
/// the sums. The terms are at most `sqrt 2 2^28 + 1/2`, the sums of four of them below
/// `1.5e9` (module doc): the adds wrap nowhere.
fn stage4<const MODE: Mode>(data: &mut [Complex], h_lanes: usize, lanes: usize, s: u32) -> u32 {
    let (lanes, shift) = (lanes.max(1), Shift::new(s));
    let h = h_lanes / lanes;
    let first = h.saturating_sub(2) / 3;
    let twiddles = TWIDDLES4.get(first + 1..first + h).unwrap_or_default();
    let (first01, rest01, first23, rest23): (Run, Run, Pairs, Pairs) = match MODE == SHIFT {
        false => (
            butterflies::<true, false, false, false>,
            butterflies::<false, false, false, false>,
            twiddled_pairs::<true, false>,
            twiddled_pairs::<false, false>,
        ),
        true => (
            butterflies::<true, false, true, false>,
            butterflies::<false, false, true, false>,
            twiddled_pairs::<true, true>,
            twiddled_pairs::<false, true>,
        ),
    };
    let one = (0, 0);
    // Items `j` of the quarters `k` and `k + 1`.
    let at = |k: usize, j: usize| Runs {
        first: k * h_lanes + j * lanes,
        len: lanes,
        apart: h_lanes,
        stride: 4 * h_lanes,
    };
    first01(data, at(0, 0), one, shift);
    first23(data, at(2, 0), (one, one), shift);
    for (j, w) in (1..).zip(twiddles) {
        rest01(data, at(0, j), w[1], shift);
        rest23(data, at(2, j), (w[0], w[2]), shift);
    }
    // `(u0 + u1) +- (u2 + u3)`, `(u0 - u1) -+ i (u2 - u3)`.
    let quarters = |k: usize| Runs {
        first: k * h_lanes,
        len: h_lanes,
        apart: 2 * h_lanes,
        stride: 4 * h_lanes,
    };
    let (sums, turned): (Run, Run) = match MODE {
        FAST => (run::<true, false, FAST>(), run::<true, true, FAST>()),
        _ => (run::<true, false, SCAN>(), run::<true, true, SCAN>()),
    };
    sums(data, quarters(0), one, shift) | turned(data, quarters(1), one, shift)
}

/// A bound on the magnitude bits of a stage's outputs from `mag`, a bound on its inputs'
/// (or their OR), and its shift `s`: a radix-2 butterfly grows a part by at most
/// `1 + sqrt 2 < 5/2`, a radix-4 one by at most `1 + 3 sqrt 2 < 21/4`, and the roundings
/// add less than 2 to each input and 1 to each output. `u32::MAX` where it would not fit
/// (no stage is then proved shift-free).
#[inline]
fn grown(mag: u32, s: u32, radix4: bool) -> u32 {
    let inputs = (mag >> s).saturating_add(2);
    match (radix4, inputs < 1 << 27) {
        (true, true) => inputs * 21 / 4 + 1,
        (false, true) => inputs * 5 / 2 + 1,
        (_, false) => u32::MAX,
    }
}

/// Whether the stage at `k` of a transform of `2^log2` points is a radix-4 one.
fn is_radix4(k: i32, log2: i32) -> bool {
    k > 0 && k + 2 <= log2
}

/// The stages from `k` on of the transforms of the columns of `data` (`lanes` values an
/// item, blocks of `2^log2` items, bit-reversed), sharing one block exponent. `mag`: the inputs'
/// magnitude bits ORed. `next`: what follows, a radix-2 stage reading the outputs'
/// magnitude bits (`true`, the columns' transform after the rows') or nothing. Returns
/// the shifts applied and the outputs' magnitude bits (if `next`) or a bound on them.
///
/// A stage shifts by what its inputs' magnitude bits say; a stage whose outputs' bound
/// ([`grown`]) proves that the next does not shift skips their scan ([`FAST`]).
fn stages(
    data: &mut [Complex],
    (log2, mut k): (i32, i32),
    lanes: usize,
    mut mag: u32,
    next: bool,
) -> (i32, u32) {
    let mut shifts = 0;
    // Butterflies `2^k` items apart (`half`, `h`), from the stage `k` given.
    while k < log2 {
        let radix4 = is_radix4(k, log2);
        let s = match radix4 {
            true => stage_shift4(mag),
            false => stage_shift(mag),
        };
        let after = k + 1 + radix4 as i32;
        let bound = grown(mag, s, radix4);
        // The shift the next stage's inputs could need at most.
        let next_shift = match (after < log2, next) {
            (true, _) if is_radix4(after, log2) => stage_shift4(bound),
            (true, _) | (false, true) => stage_shift(bound),
            (false, false) => 0,
        };
        let fast = s == 0 && next_shift == 0;
        let apart = lanes << k;
        let out = match (radix4, fast, s) {
            (true, true, _) => stage4::<FAST>(data, apart, lanes, s),
            (true, false, 0) => stage4::<SCAN>(data, apart, lanes, s),
            (true, false, _) => stage4::<SHIFT>(data, apart, lanes, s),
            (false, true, _) => stage::<FAST>(data, apart, lanes, s),
            (false, false, 0) => stage::<SCAN>(data, apart, lanes, s),
            (false, false, _) => stage::<SHIFT>(data, apart, lanes, s),
        };
        mag = match fast {
            true => bound,
            false => out,
        };
        shifts += s as i32;
        k = after;
    }
    (shifts, mag)
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

/// Swaps each item (`lanes` values) of every block of `N` items of `data` with the one at
/// its bit-reversed index.
fn bit_reverse<const N: usize>(data: &mut [Complex], lanes: usize) {
    let (table, count) = &BitReversal::<N>::SWAPS;
    let swaps = table.get(..*count).unwrap_or_default();
    for block in data.chunks_exact_mut(N * lanes.max(1)) {
        for &(i, j) in swaps {
            let (lo, hi) = block.split_at_mut((j as usize * lanes).min(block.len()));
            let lo = lo.get_mut(i as usize * lanes..).unwrap_or_default();
            for (a, b) in lo.iter_mut().zip(hi).take(lanes) {
                core::mem::swap(a, b);
            }
        }
    }
}

/// An item of a transform: one value, or a row of them (the columns of a grid, all at
/// once).
trait Lanes: Sized {
    /// The values of `items`, item after item.
    fn flat(items: &mut [Self]) -> &mut [Complex];

    /// `f` on the same lane of the four items `q`, lane by lane.
    fn each4(q: [&mut Self; 4], f: impl FnMut([&mut Complex; 4]));

    /// Swaps the items `i < j` of `items` (nothing where either is missing).
    fn swap(items: &mut [Self], i: usize, j: usize);
}

impl Lanes for Complex {
    fn flat(items: &mut [Self]) -> &mut [Complex] {
        items
    }

    #[inline(always)]
    fn each4(q: [&mut Self; 4], mut f: impl FnMut([&mut Complex; 4])) {
        f(q)
    }

    #[inline(always)]
    fn swap(items: &mut [Self], i: usize, j: usize) {
        if let (Some(&a), Some(&b)) = (items.get(i), items.get(j)) {
            if let Some(x) = items.get_mut(i) {
                *x = b;
            }
            if let Some(x) = items.get_mut(j) {
                *x = a;
            }
        }
    }
}

impl<const L: usize> Lanes for [Complex; L] {
    fn flat(items: &mut [Self]) -> &mut [Complex] {
        items.as_flattened_mut()
    }

    #[inline(always)]
    fn each4([q0, q1, q2, q3]: [&mut Self; 4], mut f: impl FnMut([&mut Complex; 4])) {
        for l in 0..L {
            if let (Some(a), Some(b), Some(c), Some(d)) =
                (q0.get_mut(l), q1.get_mut(l), q2.get_mut(l), q3.get_mut(l))
            {
                f([a, b, c, d])
            }
        }
    }

    #[inline(always)]
    fn swap(items: &mut [Self], i: usize, j: usize) {
        if let Some((lo, [b, ..])) = items.split_at_mut_checked(j) {
            if let Some(a) = lo.get_mut(i) {
                for (a, b) in a.iter_mut().zip(b) {
                    core::mem::swap(a, b);
                }
            }
        }
    }
}

/// `a +- b`, wrapping (in range wherever it is used).
#[inline(always)]
fn sum_difference(a: Complex, b: Complex) -> (Complex, Complex) {
    (
        Complex::new(a.re.wrapping_add(b.re), a.im.wrapping_add(b.im)),
        Complex::new(a.re.wrapping_sub(b.re), a.im.wrapping_sub(b.im)),
    )
}

/// `-i v`.
#[inline(always)]
fn turned(v: Complex) -> Complex {
    Complex::new(v.im, v.re.wrapping_neg())
}

/// The first two stages of a transform (butterflies 1 apart, then 2 apart) of the 4
/// bit-reversed values `v`, for values that cannot shift there: exact adds,
/// `(s01 +- s23, d01 -+ i d23)`.
#[inline(always)]
fn four([a, b, c, d]: [&mut Complex; 4]) {
    let ((s01, d01), (s23, d23)) = (sum_difference(*a, *b), sum_difference(*c, *d));
    (*a, *c) = sum_difference(s01, s23);
    (*b, *d) = sum_difference(d01, turned(d23));
}

/// The first three stages of a transform (butterflies 1 apart, then the radix-4 stage of
/// quarters 2 apart) of the 8 bit-reversed items `x`, for values whose shifts those
/// stages and the next would all choose 0 ([`FAST`]): then only two of its products
/// round, `W^1 d45` and `W^3 d67`, the twiddle `W^2 = -i` and every sum are exact, and
/// the three stages are the same arithmetic in three passes over the values, not seven.
#[inline(never)]
fn eight<T: Lanes>(x: &mut [T; 8]) {
    // `W^1` and `W^3` of 8 points (`j = 1` of the quarters of 2), read at run time: as
    // constants, the compiler factors `cos = sin` out of the two products into a longer
    // 64-bit one.
    let w = core::hint::black_box(&TWIDDLES4[1]);
    let (w1, w3) = (with_neg(w[0]), with_neg(w[2]));
    // Each pass reads its values from memory: of one item a lane (a 1-D transform), the
    // compiler would otherwise keep all 8 in more registers than there are.
    let [x0, x1, x2, x3, _, _, _, _] = core::hint::black_box(&mut *x);
    T::each4([x0, x1, x2, x3], four);
    let [_, _, _, _, x4, x5, x6, x7] = core::hint::black_box(&mut *x);
    // Items 4 to 7: `(s45 +- s67, W^1 d45 +- W^3 d67)`.
    T::each4([x4, x5, x6, x7], |[a, b, c, d]| {
        let ((s45, d45), (s67, d67)) = (sum_difference(*a, *b), sum_difference(*c, *d));
        (*a, *c) = sum_difference(s45, s67);
        (*b, *d) = sum_difference(rotated(d45, w1), rotated(d67, w3));
    });
    // The radix-4 sums: `(u0 + u1) +- (u2 + u3)`, `(u0 - u1) -+ i (u2 - u3)`.
    let [x0, x1, _, _, x4, x5, _, _] = core::hint::black_box(&mut *x);
    T::each4([x0, x1, x4, x5], |[a, b, c, d]| {
        (*a, *c) = sum_difference(*a, *c);
        (*b, *d) = sum_difference(*b, *d);
    });
    let [_, _, x2, x3, _, _, x6, x7] = core::hint::black_box(&mut *x);
    T::each4([x2, x3, x6, x7], |[a, b, c, d]| {
        (*a, *c) = sum_difference(*a, turned(*c));
        (*b, *d) = sum_difference(*b, turned(*d));
    });
}

/// Swaps each of the `N` items with the one at its bit-reversed index.
fn reverse<T: Lanes, const N: usize>(items: &mut [T; N]) {
    let (table, count) = &BitReversal::<N>::SWAPS;
    for &(i, j) in table.get(..*count).unwrap_or_default() {
        T::swap(items, i.into(), j.into());
    }
}

/// The `N`-point transforms of the columns of `items` (blocks of `N` items, bit-reversed
/// already), sharing one block exponent; `mag` and `next` as [`stages`] takes them. Where
/// the headroom proves that the first three stages and the next need no shift, [`eight`]
/// takes those three.
fn transform<T: Lanes, const N: usize>(
    items: &mut [T],
    lanes: usize,
    mag: u32,
    next: bool,
) -> (i32, u32) {
    let log2 = log2_points::<N>();
    // The bounds after the radix-2 stage, then the radix-4 one.
    let first = grown(mag, 0, false);
    let bound = grown(first, 0, true);
    let after = match (log2, next) {
        (3, false) => 0,
        (3, true) => stage_shift(bound),
        _ if is_radix4(3, log2) => stage_shift4(bound),
        _ => stage_shift(bound),
    };
    if log2 >= 3 && stage_shift(mag) == 0 && stage_shift4(first) == 0 && after == 0 {
        for group in items.chunks_exact_mut(8) {
            if let Ok(group) = <&mut [T; 8]>::try_from(group) {
                eight(group);
            }
        }
        return match log2 {
            3 => (0, bound),
            _ => stages(T::flat(items), (log2, 3), lanes, bound, next),
        };
    }
    // 4 points: the two stages, and the next if any, shift-free.
    let after = match next {
        true => stage_shift(grown(first, 0, false)),
        false => 0,
    };
    if log2 == 2 && stage_shift(mag) == 0 && stage_shift(first) == 0 && after == 0 {
        for group in items.chunks_exact_mut(4) {
            if let [a, b, c, d] = group {
                T::each4([a, b, c, d], four);
            }
        }
        return (0, grown(first, 0, false));
    }
    stages(T::flat(items), (log2, 0), lanes, mag, next)
}

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
