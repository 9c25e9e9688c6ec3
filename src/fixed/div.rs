//! Division of a 64-bit dividend by a 32-bit divisor in 32-bit steps.

/// Bits of a quotient digit: the low word's quotient is found as two digits.
const DIGIT_BITS: u32 = 16;

/// The low digit of a word.
const DIGIT_MASK: u32 = (1 << DIGIT_BITS) - 1;

/// `n / d` rounded down (0 for `d = 0`), exactly, with 32-bit divisions only: the
/// Cortex-M4 divides 32 by 32 bits in one instruction, where a 64-bit division is a
/// library call of about a hundred. A dividend below `2^32` takes that one division;
/// above, the high word takes one, the low word two 16-bit quotient digits, each
/// estimated by one division and corrected (Knuth's algorithm D, as `divlu` in Hacker's
/// Delight, 2nd ed., 9-3). Not inlined: its callers are themselves inlined into every
/// histogram fill, and one copy serves them all.
#[inline(never)]
pub fn div_u64_u32(n: u64, d: u32) -> u64 {
    if let Ok(n) = u32::try_from(n) {
        return u64::from(n.checked_div(d).unwrap_or(0));
    }
    let (hi, lo) = ((n >> 32) as u32, n as u32);
    let (Some(q_hi), Some(r)) = (hi.checked_div(d), hi.checked_rem(d)) else {
        return 0;
    };
    // (r 2^32 + lo) / d with r < d: a 32-bit quotient. Normalise d to its top bit.
    let s = d.leading_zeros();
    let v = d << s;
    let (v1, v0) = (v >> DIGIT_BITS, v & DIGIT_MASK); // v1 >= 2^15
    let top = (r << s) | (lo >> 1 >> (31 - s)); // the top 32 bits of (r : lo) << s
    let u10 = lo << s;
    // One 16-bit digit of (u 2^16 + next) / v from u < v: estimated from the top
    // halves, then lowered at most twice.
    let digit = |u: u32, next: u32| {
        let mut q = u.checked_div(v1).unwrap_or(0);
        let mut rhat = u - q * v1;
        while q >= 1 << DIGIT_BITS || q * v0 > (rhat << DIGIT_BITS | next) {
            q -= 1;
            rhat += v1;
            if rhat >= 1 << DIGIT_BITS {
                break;
            }
        }
        // The remainder, below v.
        let rem = (u << DIGIT_BITS | next).wrapping_sub(q.wrapping_mul(v));
        (q, rem)
    };
    let (q1, rem) = digit(top, u10 >> DIGIT_BITS);
    let (q0, _) = digit(rem, u10 & DIGIT_MASK);
    (q_hi as u64) << 32 | (q1 << DIGIT_BITS | q0) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn div_u64_u32_is_exact() {
        let mut x = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        for i in 0..2_000_000u32 {
            let n = next() >> (i % 64);
            let d = (next() >> (32 + (i / 64) % 32)) as u32;
            let want = if d == 0 { 0 } else { n / d as u64 };
            assert_eq!(div_u64_u32(n, d), want, "{n} / {d}");
        }
        for (n, d) in [
            (u64::MAX, 1),
            (u64::MAX, u32::MAX),
            (u64::MAX, 0x8000_0000),
            (u64::MAX, 0x8000_0001),
            (1 << 62, 1 << 15),
            (1 << 62, (1 << 31) + 1),
            ((1 << 32) - 1, 1 << 16),
            (0xFFFF_FFFF_0000_0000, 0xFFFF_FFFF),
            (0x7FFF_8000_0000_0000, 0x8000_FFFF),
            (0, 7),
            (5, 0),
            (u32::MAX.into(), 0),
            (u32::MAX.into(), 3),
            (1 << 32, 3),
        ] {
            let want = if d == 0 { 0 } else { n / d as u64 };
            assert_eq!(div_u64_u32(n, d), want, "{n} / {d}");
        }
    }
}
