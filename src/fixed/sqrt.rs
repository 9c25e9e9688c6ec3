//! Integer square roots by table: [`sqrt_q8`] to 1/256 and the exact [`isqrt32`], with no
//! division and no bit-by-bit loop; and the exact [`isqrt_u64`] for set-up work, a
//! bit-by-bit loop a tenth the size of `u64::isqrt` (about 60 bytes against 610 on the
//! Cortex-M4), where flash counts more than the 32 steps.

/// Fraction bits of [`sqrt_q8`]'s result (Q24.8).
pub const SQRT_FRAC_BITS: u32 = 8;

/// Bits of the linear interpolation between two table entries.
const INTERPOLATION_BITS: u32 = 16;

/// `floor(sqrt(64 + i) * 2^20)` for `i` in `0..=192`: square roots of `[64, 256]`.
const SQRT_TABLE: [u32; 193] = {
    let mut t = [0u32; 193];
    let mut i = 0;
    while i < 193 {
        t[i] = ((64 + i as u64) << 40).isqrt() as u32;
        i += 1;
    }
    t
};

/// `sqrt(n) * 256` (Q24.8), rounded down within a relative error of 8e-6 plus 1 unit:
/// `n` is shifted left by an even amount into `[2^30, 2^32)`, its top 8 bits index
/// a table of `sqrt(64..=256)` and the next 16 interpolate linearly. No division, no loop.
#[inline]
pub fn sqrt_q8(n: u32) -> u32 {
    if n == 0 {
        return 0;
    }
    let shift = n.leading_zeros() & !1; // even, 0..=30
    let m = n << shift; // [2^30, 2^32)
    let i = (m >> 24) as usize - 64; // 0..=191
    let frac = (m >> 8) & ((1 << INTERPOLATION_BITS) - 1);
    let (lo, hi) = match (SQRT_TABLE.get(i), SQRT_TABLE.get(i + 1)) {
        (Some(&lo), Some(&hi)) => (lo, hi),
        _ => return 0,
    };
    // hi - lo <= 65231 (at i = 0), so the product stays below 2^32.
    (lo + (((hi - lo) * frac) >> INTERPOLATION_BITS)) >> (shift / 2)
}

/// `sqrt(n) * 256` of any `u64`, within a relative error of `1.6e-5` plus 1 unit: `n`
/// shifted right by an even amount below `2^32` (keeping at least 31 of its bits) and its
/// [`sqrt_q8`] shifted back by half of it.
#[inline]
pub fn sqrt_u64_q8(n: u64) -> u64 {
    if let Ok(small) = u32::try_from(n) {
        return u64::from(sqrt_q8(small));
    }
    let half = (u64::BITS - n.leading_zeros())
        .saturating_sub(32)
        .div_ceil(2);
    u64::from(sqrt_q8((n >> (2 * half)) as u32)) << half
}

/// `sqrt(n)` of any `u64` as a 16-bit mantissa `m` (`2^15..2^16`) and an exponent `e`,
/// `sqrt(n) ~ m 2^e` within a relative error of `4e-5` (`(0, 0)` for 0; the mantissa rounded down): `n` shifted
/// left by an even amount so that its top 32 bits hold at least 31 bits, and their
/// [`sqrt_q8`]. A few 32-bit operations, where [`sqrt_u64_q8`] shifts 64-bit values.
#[inline]
pub fn sqrt_u64_m16(n: u64) -> (u32, i32) {
    // In 32-bit halves: the Cortex-M has no 64-bit shifts.
    let (hi, lo) = ((n >> 32) as u32, n as u32);
    let (top, k) = match hi {
        0 if lo == 0 => return (0, 0),
        0 => {
            let k = lo.leading_zeros() & !1;
            (lo << k, 32 + k)
        }
        _ => {
            let k = hi.leading_zeros() & !1; // even, 0..=30
            (hi << k | lo.checked_shr(32 - k).unwrap_or(0), k)
        }
    }; // top in [2^30, 2^32), n ~ top 2^(32 - k)
    let m = (sqrt_q8(top) >> SQRT_FRAC_BITS).clamp(1 << 15, (1 << 16) - 1);
    (m, (32 - k as i32) / 2)
}

/// `floor(sqrt(n))`, exactly, for any `n < 2^31`: [`sqrt_q8`] (never above the exact
/// root, at most a unit below it) corrected upwards; no bit-by-bit loop.
#[inline]
pub fn isqrt32(n: u32) -> u32 {
    let n = n.min(i32::MAX as u32);
    let mut m = sqrt_q8(n) >> SQRT_FRAC_BITS;
    while (m + 1) * (m + 1) <= n {
        m += 1;
    }
    m
}

/// `floor(sqrt(n))`, exactly, for any `u64`: two result bits a step, 32 steps at most.
pub const fn isqrt_u64(n: u64) -> u64 {
    let (mut rest, mut root) = (n, 0u64);
    let mut bit = 1u64 << 62;
    while bit > n {
        bit >>= 2;
    }
    while bit != 0 {
        if rest >= root + bit {
            rest -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn sqrt_q8_is_accurate() {
        let mut worst = 0f64;
        let mut check = |n: u32| {
            let got = sqrt_q8(n) as f64 / 256.0;
            let want = (n as f64).sqrt();
            assert!(got <= want + 1e-9, "{n}: {got} > {want}");
            let err = (want - got) - 1.0 / 256.0;
            worst = worst.max(err / want);
        };
        for n in 0..100_000 {
            check(n);
        }
        let mut r = Rng::new(1);
        for _ in 0..1_000_000 {
            check(r.next_u32() >> (r.next_u32() % 32));
        }
        for n in [u32::MAX, u32::MAX - 1, 1 << 30, (1 << 30) - 1, 1 << 31] {
            check(n);
        }
        assert!(worst < 8e-6, "relative error {worst}");
        assert_eq!(sqrt_q8(1), 256);
        assert_eq!(sqrt_q8(65536), 65536);
    }

    #[test]
    fn sqrt_u64_q8_is_accurate() {
        let mut r = Rng::new(6);
        let mut worst = 0f64;
        for k in 0..1_000_000u32 {
            let n = (u64::from(r.next_u32()) << 32 | u64::from(r.next_u32())) >> (k % 64);
            let got = sqrt_u64_q8(n) as f64 / 256.0;
            let want = (n as f64).sqrt();
            assert!(got <= want * (1.0 + 1e-12) + 1e-9, "{n}: {got} > {want}");
            if want > 0.0 {
                worst = worst.max((want - got - 1.0 / 256.0) / want);
            }
        }
        assert!(worst < 1.6e-5, "relative error {worst}");
        let top = sqrt_u64_q8(u64::MAX) as f64 / 256.0;
        assert!(
            (top - 2f64.powi(32)).abs() < 2f64.powi(32) * 1.6e-5,
            "{top}"
        );
        assert_eq!(sqrt_u64_q8(1 << 40), 1 << 28);
    }

    #[test]
    fn isqrt_u64_is_exact() {
        let mut r = Rng::new(7);
        for k in 0..1_000_000u32 {
            let n = (u64::from(r.next_u32()) << 32 | u64::from(r.next_u32())) >> (k % 64);
            assert_eq!(isqrt_u64(n), n.isqrt(), "{n}");
        }
        for n in (0..70_000).chain([u64::MAX, u64::MAX - 1, 1 << 62, (1 << 62) - 1, 1 << 63]) {
            assert_eq!(isqrt_u64(n), n.isqrt(), "{n}");
        }
        let r = u64::from(u32::MAX);
        for n in [r * r, r * r - 1, r * r + 1] {
            assert_eq!(isqrt_u64(n), n.isqrt(), "{n}");
        }
    }

    #[test]
    fn isqrt32_is_exact() {
        let mut r = Rng::new(4);
        for n in (0..1u32 << 20).chain((0..1_000_000).map(|_| r.next_u32() >> 1)) {
            assert_eq!(isqrt32(n), n.isqrt(), "{n}");
        }
        for n in [
            i32::MAX as u32,
            (1 << 30) - 1,
            1 << 30,
            46_340 * 46_340,
            46_341 * 46_341 - 1,
        ] {
            assert_eq!(isqrt32(n), n.isqrt(), "{n}");
        }
    }

    #[test]
    fn the_16_bit_mantissa_root_is_within_its_bound() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        for i in 0..200_000u32 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let n = x >> (i % 64);
            let (m, e) = sqrt_u64_m16(n);
            if n == 0 {
                assert_eq!((m, e), (0, 0));
                continue;
            }
            assert!((1 << 15..1 << 16).contains(&m), "{n}: {m}");
            let got = f64::from(m) * 2f64.powi(e);
            let want = (n as f64).sqrt();
            assert!((got - want).abs() <= 4e-5 * want, "{n}: {got} {want}");
        }
    }
}
