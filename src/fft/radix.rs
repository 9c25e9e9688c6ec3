//! The radix-2 and radix-4 stages of the transforms in block floating point: each stage
//! shifts by what its inputs' magnitudes need, and skips their scan where the headroom
//! proves it needless.

use super::{Complex, MAX_POINTS};
use crate::fixed::Q16;
use crate::trig::cos_sin_bits;

/// `(cos, sin)` of `2 pi k / n`, Q31, 1 saturated to `i32::MAX` (`Q16::saturate` clamps
/// any raw `i64`).
pub(super) const fn twiddle(k: u32, n: u32) -> (i32, i32) {
    let (cos, sin) = cos_sin_bits(k, n, 31);
    (Q16::saturate(cos).to_bits(), Q16::saturate(sin).to_bits())
}

/// The twiddles of every stage, `(cos, sin)` Q31 (1 saturates to `i32::MAX`): those of
/// the stage of butterflies `half` apart, `2 pi j / (2 half)` for `j < half / 2` (a quarter
/// turn), at `half / 2 + j`, so that each stage's are contiguous.
pub(super) const TWIDDLES: [(i32, i32); MAX_POINTS / 2] = twiddles();

/// The [`TWIDDLES`] table, at compile time.
pub(super) const fn twiddles() -> [(i32, i32); MAX_POINTS / 2] {
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
pub(super) const TWIDDLES4: [[(i32, i32); 3]; (MAX_POINTS / 2 - 2) / 3] = twiddles4();

/// The [`TWIDDLES4`] table, at compile time.
pub(super) const fn twiddles4() -> [[(i32, i32); 3]; (MAX_POINTS / 2 - 2) / 3] {
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
pub(super) fn stage_shift(mag: u32) -> u32 {
    (u32::BITS - mag.leading_zeros()).saturating_sub(29).min(2)
}

/// The right shift of a radix-4 stage whose inputs' magnitude bits OR to `mag`: 0 for
/// magnitudes up to `2^28`, 1 up to `2^29`, 2 up to `2^30`, else 3 (see the module doc).
#[inline]
pub(super) fn stage_shift4(mag: u32) -> u32 {
    (u32::BITS - mag.leading_zeros()).saturating_sub(28).min(3)
}

/// `log2 N`, and a compile-time error unless `N` is a power of two in `2..=MAX_POINTS`.
pub(super) fn log2_points<const N: usize>() -> i32 {
    const {
        assert!(
            N.is_power_of_two() && N >= 2 && N <= MAX_POINTS,
            "FFT sizes are powers of two from 2 to MAX_POINTS"
        )
    };
    N.trailing_zeros() as i32
}

/// How a stage runs: [`FAST`], [`SCAN`] or [`SHIFT`].
pub(super) type Mode = u8;

/// No shift, and no scan of the outputs: the headroom proves that the next stage does
/// not shift either.
pub(super) const FAST: Mode = 0;

/// No shift; the outputs' magnitude bits ORed, for the next stage's shift.
pub(super) const SCAN: Mode = 1;

/// A right shift by `s` in `1..=3`; the outputs' magnitude bits ORed.
pub(super) const SHIFT: Mode = 2;

/// The parts of a stage's shift `s` (`1..=3`; unused without a shift) its arithmetic
/// takes: `2^(s - 1)`, the rounding of a product `2^(30 + s)` and `s - 1`.
#[derive(Clone, Copy)]
pub(super) struct Shift {
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
pub(super) fn rotated(b: Complex, (cos, sin, nsin): (i32, i32, i32)) -> Complex {
    let (x, y) = (i64::from(b.re << 1), i64::from(b.im << 1));
    let (cos, sin, nsin) = (i64::from(cos), i64::from(sin), i64::from(nsin));
    let high = |p: i64| ((p >> 32) as i32).wrapping_add((p as u32 >> 31) as i32);
    Complex::new(high(x * cos + y * sin), high(y * cos + x * nsin))
}

/// `w b / 2^s` (`w = cos - i sin`, Q31, `nsin = -sin`), each part rounded (half up), for
/// parts of at most `2^31`: `|.| <= sqrt 2 2^31 / 2^s`.
#[inline(always)]
pub(super) fn rotated_shifted(
    b: Complex,
    (cos, sin, nsin): (i32, i32, i32),
    shift: Shift,
) -> Complex {
    let (x, y) = (i64::from(b.re), i64::from(b.im));
    let (cos, sin, nsin) = (i64::from(cos), i64::from(sin), i64::from(nsin));
    // The sum rounded, then `>> 32` and `>> (s - 1)`: a 64-bit shift by 31 + s.
    let round = |p: i64| (((p + shift.product_half) >> 32) as i32) >> (shift.s - 1);
    Complex::new(round(x * cos + y * sin), round(y * cos + x * nsin))
}

/// `b` times the twiddle `w` (exactly 1 if `ONE`), divided by `2^s` if `SHIFTED`.
#[inline(always)]
pub(super) fn twiddled<const ONE: bool, const SHIFTED: bool>(
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
pub(super) fn with_neg((cos, sin): (i32, i32)) -> (i32, i32, i32) {
    (cos, sin, sin.wrapping_neg())
}

/// Where a kernel works in `data`: in every group of `stride` values, the `len` values
/// from `first` (`lo`) and the `len` values `apart` further on (`hi`).
#[derive(Clone, Copy)]
pub(super) struct Runs {
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
pub(super) fn butterflies<
    const ONE: bool,
    const QUARTER: bool,
    const SHIFTED: bool,
    const SCANNED: bool,
>(
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
pub(super) fn twiddled_pairs<const ONE: bool, const SHIFTED: bool>(
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
pub(super) type Run = fn(&mut [Complex], Runs, (i32, i32), Shift) -> u32;

/// A [`twiddled_pairs`] kernel.
pub(super) type Pairs = fn(&mut [Complex], Runs, ((i32, i32), (i32, i32)), Shift);

/// The [`butterflies`] of a stage in `MODE`: shifting and scanning as it says.
pub(super) const fn run<const ONE: bool, const QUARTER: bool, const MODE: Mode>() -> Run {
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
pub(super) fn stage<const MODE: Mode>(
    data: &mut [Complex],
    half_lanes: usize,
    lanes: usize,
    s: u32,
) -> u32 {
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
pub(super) fn stage4<const MODE: Mode>(
    data: &mut [Complex],
    h_lanes: usize,
    lanes: usize,
    s: u32,
) -> u32 {
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
pub(super) fn grown(mag: u32, s: u32, radix4: bool) -> u32 {
    let inputs = (mag >> s).saturating_add(2);
    match (radix4, inputs < 1 << 27) {
        (true, true) => inputs * 21 / 4 + 1,
        (false, true) => inputs * 5 / 2 + 1,
        (_, false) => u32::MAX,
    }
}

/// Whether the stage at `k` of a transform of `2^log2` points is a radix-4 one.
pub(super) fn is_radix4(k: i32, log2: i32) -> bool {
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
pub(super) fn stages(
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
pub(super) fn magnitude_bits(values: &[Complex]) -> u32 {
    values.iter().fold(0, |mag, v| mag | v.magnitude_bits())
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

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
}
