//! Bit reversal and the transforms of one row or of a grid's columns at once: the first
//! three or two stages unrolled where the headroom allows, the rest by [`super::radix`].

use super::radix::{
    grown, is_radix4, log2_points, rotated, stage_shift, stage_shift4, stages, with_neg, TWIDDLES4,
};
use super::Complex;

/// The swaps of a bit reversal of `N` items, `(i, j)` with `i < j`, as a table built at
/// compile time: its first `.1`.
pub(super) struct BitReversal<const N: usize>;

/// The most swaps of a bit reversal, those of [`MAX_POINTS`](super::MAX_POINTS) = 64
/// items: `(64 - 8) / 2` (the 8 indices of 6 bits that read the same reversed stay). A
/// larger `MAX_POINTS` without a larger table does not compile.
pub(super) const MAX_SWAPS: usize = 28;

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
pub(super) fn bit_reverse<const N: usize>(data: &mut [Complex], lanes: usize) {
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
pub(super) trait Lanes: Sized {
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
pub(super) fn sum_difference(a: Complex, b: Complex) -> (Complex, Complex) {
    (
        Complex::new(a.re.wrapping_add(b.re), a.im.wrapping_add(b.im)),
        Complex::new(a.re.wrapping_sub(b.re), a.im.wrapping_sub(b.im)),
    )
}

/// `-i v`.
#[inline(always)]
pub(super) fn turned(v: Complex) -> Complex {
    Complex::new(v.im, v.re.wrapping_neg())
}

/// The first two stages of a transform (butterflies 1 apart, then 2 apart) of the 4
/// bit-reversed values `v`, for values that cannot shift there: exact adds,
/// `(s01 +- s23, d01 -+ i d23)`.
#[inline(always)]
pub(super) fn four([a, b, c, d]: [&mut Complex; 4]) {
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
pub(super) fn eight<T: Lanes>(x: &mut [T; 8]) {
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
pub(super) fn reverse<T: Lanes, const N: usize>(items: &mut [T; N]) {
    let (table, count) = &BitReversal::<N>::SWAPS;
    for &(i, j) in table.get(..*count).unwrap_or_default() {
        T::swap(items, i.into(), j.into());
    }
}

/// The `N`-point transforms of the columns of `items` (blocks of `N` items, bit-reversed
/// already), sharing one block exponent; `mag` and `next` as [`stages`] takes them. Where
/// the headroom proves that the first three stages and the next need no shift, [`eight`]
/// takes those three.
pub(super) fn transform<T: Lanes, const N: usize>(
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
