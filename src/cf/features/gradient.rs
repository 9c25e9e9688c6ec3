//! A pixel's gradient magnitude and unsigned orientation bin, without a square root or an
//! arctangent: a table of `sqrt(1 + r^2)` and comparisons against the bin boundaries'
//! tangents.

/// The tangents of the boundaries between the unsigned bins in the first quadrant, 10,
/// 30, 50 and 70 degrees, Q15, rounded: a gradient `(ax, ay)` there is at or past
/// boundary `k` where `ay 2^15 >= TANGENTS[k] ax`; those of the second quadrant are their
/// mirror images, `180 -` these. The f64 reference bins by the same numbers.
pub const TANGENTS: [u32; 4] = [5_778, 18_919, 39_051, 90_029];

/// `sqrt(1 + r^2)` for `r = k / 128`, `k` in `0..=128`, Q16, rounded (bits 0-16), and
/// the step to the next (bits 17-26, at most 725; 0 for the last): [`hypot`]'s table,
/// zero past `k = 128` so that a byte indexes it without a check (508 B of flash for
/// about 12 k instructions a frame).
pub(super) const HYPOT: [u32; 256] = {
    // sqrt(2^32 + (k 2^9)^2) in Q16, rounded: the root of 4 times it, halved.
    pub(super) const fn at(k: u64) -> u32 {
        (4 * ((1 << 32) + (k << 9) * (k << 9))).isqrt().div_ceil(2) as u32
    }
    let mut t = [0u32; 256];
    let mut k = 0;
    while k < 129 {
        let step = if k < 128 { at(k + 1) - at(k) } else { 0 };
        t[k as usize] = at(k) | step << 17;
        k += 1;
    }
    t
};

/// `hi sqrt(1 + r^2)` in Q10 of the larger part `hi` of a gradient (Q9, at most 130,560)
/// and the ratio of the smaller to it `r` (Q15, at most 1, floored): [`HYPOT`]
/// interpolated, within a relative `2.5e-5` (most of it the ratio's flooring) and a unit;
/// below 369,282 < 2^19, so 9 times it is below 2^22.
#[inline(always)]
pub(super) fn hypot(hi: u32, r: u32) -> u32 {
    // `r >> 8` is at most 128: the byte is the index itself.
    let entry = HYPOT[(r >> 8) as u8 as usize];
    let (a, step) = (entry & 0x1_FFFF, entry >> 17);
    // `step f` is below 2^18.
    let s = a + ((step * (r & 0xFF) + 0x80) >> 8);
    // Q9 times Q16 below 2^35, to Q10.
    ((u64::from(hi) * u64::from(s) + (1 << 14)) >> 15) as u32
}

/// A gradient's magnitude (Q10, [`hypot`]) and unsigned orientation bin (`0..9`), or
/// none for a zero gradient (`gx, gy` in Q9, `|gx|, |gy| <= 130,560 < 2^17`).
///
/// The bin is the nearest of 9 directions `20 k` degrees modulo 180: the count, modulo 9,
/// of the boundaries `10 + 20 k` degrees ([`TANGENTS`]) that the angle folded into
/// `[0, 180)` has passed, a boundary going to the bin nearer 90 degrees (90 itself to the
/// bin above). One division `ay / ax` in Q15 serves the bin and, where `ay <= ax`, the
/// magnitude; a second `ax / ay` the magnitude otherwise.
#[inline(always)]
pub(super) fn magnitude_and_bin(gx: i32, gy: i32) -> Option<(u32, usize)> {
    let (ax, ay) = (gx.unsigned_abs(), gy.unsigned_abs());
    if ax == 0 && ay == 0 {
        return None;
    }
    // `ay 2^15` is below 2^32; past every boundary at `ax = 0`.
    let q = (ay << 15).checked_div(ax).unwrap_or(u32::MAX);
    let m = match ay <= ax {
        true => hypot(ax, q),
        false => hypot(ay, (ax << 15).checked_div(ay).unwrap_or(0)),
    };
    // Folded into the upper half-plane (`gx` negated where `gy < 0`), the gradient lies in
    // [90, 180) degrees where the folded `gx` is at most 0, and is there `180 -` the
    // first-quadrant angle of `(ax, ay)`.
    let mirrored = (if gy < 0 { -gx } else { gx }) <= 0;
    // At or past boundary `k` of the first quadrant where `ay 2^15 >= T_k ax`, that is
    // where the floored quotient is at least `T_k`.
    let [t10, t30, t50, t70] = TANGENTS;
    let count = match q >= t50 {
        true => 3 + usize::from(q >= t70),
        false if q >= t30 => 2,
        false => usize::from(q >= t10),
    };
    // Mirrored: the 5 boundaries to 90 degrees and those from 110 on that the angle has
    // passed, `9 - count`, modulo 9.
    pub(super) const BIN: [u8; 10] = [0, 1, 2, 3, 4, 0, 8, 7, 6, 5];
    let bin = usize::from(BIN[(5 * usize::from(mirrored) + count) % BIN.len()]);
    Some((m, bin))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    /// [`magnitude_and_bin`]'s bin of a nonzero gradient.
    fn bin(gx: i32, gy: i32) -> usize {
        magnitude_and_bin(gx, gy).map_or(usize::MAX, |(_, b)| b)
    }

    #[test]
    fn orientation_bins_split_at_ten_degrees_off_their_centre() {
        let at = |d: f64| {
            let (s, c) = d.to_radians().sin_cos();
            bin((c * 1e5) as i32, (s * 1e5) as i32)
        };
        assert_eq!(bin(1, 0), 0);
        assert_eq!(bin(0, 1), 5); // 90 degrees: on a boundary, to the bin above
        assert_eq!(bin(0, -1), 5);
        assert_eq!(bin(-1, 0), 0);
        assert_eq!(at(9.9), 0);
        assert_eq!(at(10.1), 1);
        assert_eq!(at(169.9), 8);
        assert_eq!(at(170.1), 0);
        assert_eq!(at(200.0), 1);
        assert_eq!(at(355.0), 0);
        assert_eq!(at(345.0), 8);
    }

    #[test]
    fn magnitudes_are_the_root_within_their_bound() {
        let mut rng = crate::rng::Rng::new(8);
        for i in 0..200_000 {
            let g = |r: &mut crate::rng::Rng| {
                let v = r.below(2 * 130_560 + 1) as i32 - 130_560;
                v >> r.below(17)
            };
            let (gx, gy) = match i {
                0 => (130_560, 130_560),
                1 => (-130_560, 1),
                _ => (g(&mut rng), g(&mut rng)),
            };
            let Some((m, _)) = magnitude_and_bin(gx, gy) else {
                assert_eq!((gx, gy), (0, 0));
                continue;
            };
            let want = 2.0 * f64::from(gx).hypot(f64::from(gy));
            let err = (f64::from(m) - want).abs();
            assert!(err <= 1.0 + 2.5e-5 * want, "{gx}, {gy}: {m} against {want}");
        }
        assert_eq!(magnitude_and_bin(0, 0), None);
    }

    #[test]
    fn orientation_bins_count_the_boundaries_passed() {
        // The bin is the number of the 9 boundaries 10 + 20 k degrees (as TANGENTS gives
        // them) that the angle folded into [0, 180) has passed, modulo 9: to 90 degrees a
        // boundary it is at counts, beyond 90 not (a tie goes to the bin nearer 90).
        let folded = |gx: i64, gy: i64| {
            if gy < 0 || (gy == 0 && gx < 0) {
                (-gx, -gy)
            } else {
                (gx, gy)
            }
        };
        // The 9 boundaries: the first quadrant's, 90 degrees, and their mirror images.
        let boundaries: Vec<(i64, i64, i64)> = TANGENTS
            .iter()
            .map(|&t| (1 << 15, i64::from(t), 0))
            .chain([(0, 1, 0)])
            .chain(
                TANGENTS
                    .iter()
                    .rev()
                    .map(|&t| (-(1 << 15), i64::from(t), 1)),
            )
            .collect();
        let passed = |gx: i32, gy: i32| {
            let (gx, gy) = folded(i64::from(gx), i64::from(gy));
            boundaries
                .iter()
                .filter(|&&(c, s, strict)| c * gy - s * gx >= strict)
                .count()
                % 9
        };
        let mut rng = crate::rng::Rng::new(5);
        for _ in 0..200_000 {
            // Differences of Q8 luma, one-sided ones doubled: at most 130,560.
            let g = |r: &mut crate::rng::Rng| {
                let v = r.below(2 * 130_560 + 1) as i32 - 130_560;
                v >> r.below(17)
            };
            let (gx, gy) = (g(&mut rng), g(&mut rng));
            if (gx, gy) != (0, 0) {
                assert_eq!(bin(gx, gy), passed(gx, gy), "{gx}, {gy}");
            }
        }
        for gx in -40..=40 {
            for gy in -40..=40 {
                if (gx, gy) != (0, 0) {
                    assert_eq!(bin(gx, gy), passed(gx, gy), "{gx}, {gy}");
                }
            }
        }
    }
}
