//! Resampling: integer weights, normalised to an exact power-of-two total, and four
//! schemes that draw particle indices from them.
//!
//! # Weights
//! Weights are `u32`, any scale. [`normalise`] rescales them to sum to exactly
//! [`WEIGHT_TOTAL`] (`2^24`) by cumulative rounding: `w_i = floor(C_i 2^24 / C) -
//! floor(C_{i-1} 2^24 / C)` with `C_i` the running sum, so the total is exact, every weight
//! is within one unit of its ideal share, and a zero weight stays zero (a weight below
//! `2^-24` of the total may round to zero). When every weight is zero it writes uniform
//! weights and reports [`Normalised::AllZero`], so the caller can count the recovery.
//!
//! # Schemes
//! All draw against the cumulative sums `c_j` of the normalised weights (`c_{N-1} = 2^24`)
//! and take, for a position `r` in `[0, 2^24)`, the smallest `j` with `c_j > r`. No `r`
//! can reach `2^24`, so no draw can index past the end.
//! - [`Scheme::Multinomial`]: `M` independent positions, binary search each
//!   (`O(M log N)`).
//! - [`Scheme::Systematic`]: `r_k = floor((k 2^24 + u) / M)`, one `u` for all `k`; particle
//!   `i` gets `floor(M w_i)` or `ceil(M w_i)` copies (`w_i` as a fraction). `O(N + M)`.
//! - [`Scheme::Stratified`]: as systematic with a fresh `u` per `k`. `O(N + M)`.
//! - [`Scheme::Residual`]: `floor(M w_i)` copies of each particle, then the remaining draws
//!   multinomially from the residual weights (kept to 16 fraction bits). The copies come
//!   first in the output, in index order.
//!
//! # Buffers and limits
//! [`resample`] writes `out.len()` (= `M`) indices into `out: &mut [u16]`, so there can be
//! at most [`MAX_PARTICLES`] (65535) weights, and uses `weights` as scratch: on return it
//! holds the cumulative sums (residual: of the residual weights). Nothing else is
//! allocated or borrowed.
//!
//! # Examples
//! ```
//! use rbtrack::resample::{resample, Normalised, Scheme};
//! use rbtrack::rng::Rng;
//! let mut weights = [0u32, 3, 1, 0];
//! let mut out = [0u16; 4];
//! let mut rng = Rng::new(1);
//! let n = resample(Scheme::Systematic, &mut weights, &mut rng, &mut out).unwrap();
//! assert_eq!(n, Normalised::Scaled);
//! assert_eq!(out.iter().filter(|&&i| i == 1).count(), 3);
//! assert_eq!(out.iter().filter(|&&i| i == 2).count(), 1);
//! ```

use crate::fixed::Q16;
use crate::rng::Rng;

/// `log2` of [`WEIGHT_TOTAL`].
pub const WEIGHT_TOTAL_LOG2: u32 = 24;

/// Sum of the weights after [`normalise`]: `2^24` (weight 1.0).
pub const WEIGHT_TOTAL: u32 = 1 << WEIGHT_TOTAL_LOG2;

/// Fraction bits the residual scheme keeps of each residual weight (see [`residual`]).
const RESIDUAL_FRAC_BITS: u32 = 16;

/// Largest number of weights [`resample`] accepts (indices are `u16`).
pub const MAX_PARTICLES: usize = u16::MAX as usize;

/// Resampling scheme; see the module docs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Scheme {
    /// Independent draws by binary search on the cumulative weights.
    Multinomial,
    /// One uniform offset, evenly spaced positions (lowest variance, cheapest).
    #[default]
    Systematic,
    /// One uniform position in each of `M` equal strata.
    Stratified,
    /// Deterministic `floor(M w_i)` copies, the rest multinomial.
    Residual,
}

/// What [`normalise`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Normalised {
    /// The weights had a positive sum and were scaled to [`WEIGHT_TOTAL`].
    Scaled,
    /// Every weight was zero (or there were none): they are now uniform.
    AllZero,
}

/// A resampling request that cannot be served.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ResampleError {
    /// More than [`MAX_PARTICLES`] weights.
    TooManyParticles,
    /// No weights but a non-empty output.
    NoParticles,
    /// More than `u32::MAX` indices asked for (an output longer than that).
    TooManyDraws,
}

impl core::fmt::Display for ResampleError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::TooManyParticles => {
                write!(f, "more than {MAX_PARTICLES} weights to resample")
            }
            Self::NoParticles => f.write_str("no weights to resample from"),
            Self::TooManyDraws => write!(f, "more than {} indices to draw", u32::MAX),
        }
    }
}

impl core::error::Error for ResampleError {}

/// Rescales `weights` to sum to exactly [`WEIGHT_TOTAL`] (cumulative rounding, see the
/// module docs); all zero becomes uniform. Any length up to `2^32`; each weight is any
/// `u32`.
///
/// Cost: when the sum is a power of two (weights already normalised sum to `2^24`) a shift
/// per weight, no division; when it is below `2^40` (any `2^16` weights below `2^24`
/// each, or the tracker's weights, which sum to at most `2^32`) one `u64` division per
/// weight; only larger sums take 24 steps of binary long division per weight.
pub fn normalise(weights: &mut [u32]) -> Normalised {
    let sum: u64 = weights.iter().map(|&w| w as u64).sum();
    let (total, all_zero) = if sum == 0 {
        (weights.len() as u64, true)
    } else {
        (sum, false)
    };
    if total == 0 {
        return Normalised::AllZero;
    }
    let weight = |w: u32| if all_zero { 1 } else { w as u64 };
    if total.is_power_of_two() {
        // floor(cum 2^24 / 2^p) is a shift.
        let p = total.trailing_zeros();
        rescale(weights, weight, |cum| {
            if p >= WEIGHT_TOTAL_LOG2 {
                cum >> (p - WEIGHT_TOTAL_LOG2)
            } else {
                cum << (WEIGHT_TOTAL_LOG2 - p)
            }
        });
    } else if total < 1 << (64 - WEIGHT_TOTAL_LOG2) {
        // cum <= total < 2^40, so cum << 24 fits a u64.
        rescale(weights, weight, |cum| (cum << WEIGHT_TOTAL_LOG2) / total);
    } else {
        rescale(weights, weight, |cum| scaled_long(cum, total));
    }
    if all_zero {
        Normalised::AllZero
    } else {
        Normalised::Scaled
    }
}

/// `floor(cum 2^24 / total)` for `cum <= total`, exactly, by binary long division: one
/// quotient bit per step, no `u128` (where `cum << 24` does not fit a `u64`).
fn scaled_long(cum: u64, total: u64) -> u64 {
    // The integer part is 0 or 1; the remainder stays below `total`.
    let (mut quotient, mut rem) = match cum.checked_sub(total) {
        Some(rem) => (1, rem),
        None => (0, cum),
    };
    for _ in 0..WEIGHT_TOTAL_LOG2 {
        // 2 rem < 2 total, so one subtraction brings it below `total` again; `carry` is
        // the doubled remainder's bit 64, and the wrapping subtraction is then exact.
        let (doubled, carry) = rem.overflowing_add(rem);
        let bit = carry || doubled >= total;
        rem = if bit {
            doubled.wrapping_sub(total)
        } else {
            doubled
        };
        quotient = quotient << 1 | bit as u64;
    }
    quotient
}

/// Replaces each weight by `edge(C_i) - edge(C_{i-1})`, `C_i` the running sum of
/// `weight(w)`.
#[inline(always)]
fn rescale(weights: &mut [u32], weight: impl Fn(u32) -> u64, edge: impl Fn(u64) -> u64) {
    let mut cum = 0u64;
    let mut prev = 0u64;
    for w in weights.iter_mut() {
        cum += weight(*w);
        let e = edge(cum);
        *w = (e - prev) as u32;
        prev = e;
    }
}

/// Effective sample size `(sum w)^2 / sum w^2` (= `1 / sum w^2` for normalised weights),
/// in particles, Q16.16, between 1 and the number of non-zero weights; saturates at
/// [`Q16::MAX`] (32768) for more particles than that. All-zero or empty weights give 0.
pub fn effective_sample_size(weights: &[u32]) -> Q16 {
    let (sum, sum_sq) = sums(weights);
    if sum_sq == 0 {
        return Q16::ZERO;
    }
    let ess_q16 = ess_ratio_q16(sum, sum_sq);
    Q16::saturate(ess_q16.min(i64::MAX as u128) as i64)
}

/// Whether `effective_sample_size(weights) >= threshold`, decided by one multiplication
/// and comparison instead of a 128-bit division (the resampling test of a filter step).
pub fn effective_sample_size_at_least(weights: &[u32], threshold: Q16) -> bool {
    let (sum, sum_sq) = sums(weights);
    if sum_sq == 0 {
        return threshold <= Q16::ZERO;
    }
    if threshold <= Q16::ZERO {
        return true;
    }
    // floor(X / Y) >= T  <=>  X >= T Y for integers; sum <= 2^48 for 65535 weights, so
    // X = sum^2 2^16 <= 2^112 and T Y < 2^31 2^80: no overflow for any `MAX_PARTICLES`
    // weights, and a saturating product stays correct beyond.
    let x = sum.saturating_mul(sum).saturating_mul(1 << Q16::FRAC_BITS);
    x >= (threshold.to_bits() as u128).saturating_mul(sum_sq)
}

/// `(sum w, sum w^2)`.
#[inline]
fn sums(weights: &[u32]) -> (u128, u128) {
    weights.iter().fold((0u128, 0u128), |(s, q), &w| {
        let w = w as u64;
        (s + w as u128, q + (w * w) as u128)
    })
}

/// `sum^2 2^16 / sum_sq`, rounded down; exact for `sum <= 2^56` (e.g. 65535 weights of
/// `u32`, `sum <= 2^48`), saturating beyond.
fn ess_ratio_q16(sum: u128, sum_sq: u128) -> u128 {
    match sum
        .checked_mul(sum)
        .and_then(|s2| s2.checked_mul(1 << Q16::FRAC_BITS))
    {
        Some(n) => n / sum_sq,
        None => u128::MAX,
    }
}

/// Draws `out.len()` particle indices from `weights` by `scheme`.
///
/// # Arguments
/// - `weights`: one non-negative weight per particle, any scale; used as scratch (on
///   return it holds cumulative sums). At most [`MAX_PARTICLES`].
/// - `rng`: random source.
/// - `out`: receives the indices, each `< weights.len()`; at most `u32::MAX` of them.
///
/// # Returns
/// Whether the weights were all zero (then the draw was uniform), or an error when there
/// are too many weights, none for a non-empty `out`, or more than `u32::MAX` indices to
/// draw (`out` untouched).
pub fn resample(
    scheme: Scheme,
    weights: &mut [u32],
    rng: &mut Rng,
    out: &mut [u16],
) -> Result<Normalised, ResampleError> {
    if weights.len() > MAX_PARTICLES {
        return Err(ResampleError::TooManyParticles);
    }
    if u32::try_from(out.len()).is_err() {
        return Err(ResampleError::TooManyDraws);
    }
    if weights.is_empty() {
        return if out.is_empty() {
            Ok(Normalised::AllZero)
        } else {
            Err(ResampleError::NoParticles)
        };
    }
    let found = normalise(weights);
    match scheme {
        Scheme::Multinomial => {
            cumulate(weights);
            for o in out.iter_mut() {
                *o = search(weights, rng.next_u32() >> (32 - WEIGHT_TOTAL_LOG2));
            }
        }
        Scheme::Systematic => {
            cumulate(weights);
            let u = rng.next_u32() >> (32 - WEIGHT_TOTAL_LOG2);
            spaced(weights, out, |_| u);
        }
        Scheme::Stratified => {
            cumulate(weights);
            spaced(weights, out, |_| rng.next_u32() >> (32 - WEIGHT_TOTAL_LOG2));
        }
        Scheme::Residual => residual(weights, rng, out),
    }
    Ok(found)
}

/// In-place prefix sums, saturating (never reached: normalised weights sum to `2^24`,
/// [`residual`]'s residuals to less than `2^32`).
fn cumulate(weights: &mut [u32]) {
    let mut acc = 0u32;
    for w in weights.iter_mut() {
        debug_assert!(acc.checked_add(*w).is_some(), "cumulative weights overflow");
        acc = acc.saturating_add(*w);
        *w = acc;
    }
}

/// Smallest `j` with `cum[j] > r`, clamped to the last index (`cum` non-empty,
/// non-decreasing; `r < cum[last]` is the callers' invariant, the clamp is defensive).
fn search(cum: &[u32], r: u32) -> u16 {
    let j = cum.partition_point(|&c| c <= r);
    debug_assert!(j < cum.len(), "position {r} at or past the total");
    j.min(cum.len().saturating_sub(1)) as u16
}

/// Evenly spaced positions `r_k = floor((k 2^24 + u_k) / M)` (`u_k < 2^24`, `M =
/// out.len() <= u32::MAX`), walked against `cum` in one pass. The quotient of `k 2^24` by
/// `M` is carried from one `k` to the next with its remainder, so a position costs one
/// 32-bit division (of `u_k`), not a 64-bit one.
fn spaced(cum: &[u32], out: &mut [u16], mut offset: impl FnMut(usize) -> u32) {
    let m = u32::try_from(out.len());
    debug_assert!(m.is_ok(), "resample draws at most u32::MAX indices");
    let Ok(m) = m else { return };
    if m == 0 {
        return;
    }
    let last = cum.len().saturating_sub(1);
    let (step_q, step_r) = (WEIGHT_TOTAL / m, WEIGHT_TOTAL % m);
    // k 2^24 = q M + rem, with rem < M.
    let (mut q, mut rem) = (0u32, 0u32);
    let mut j = 0usize;
    for (k, o) in out.iter_mut().enumerate() {
        let u = offset(k);
        let (uq, ur) = (u / m, u % m);
        // floor((q M + rem + uq M + ur) / M), rem + ur < 2 M; every term below 2^25.
        let r = q + uq + ((rem as u64 + ur as u64) >= m as u64) as u32;
        while j < last && cum.get(j).is_some_and(|&c| c <= r) {
            j += 1;
        }
        *o = j as u16;
        q += step_q;
        rem += step_r;
        if rem >= m {
            rem -= m;
            q += 1;
        }
    }
}

/// Residual resampling on normalised `weights` (sum `2^24`).
fn residual(weights: &mut [u32], rng: &mut Rng, out: &mut [u16]) {
    let m = out.len() as u64;
    // Deterministic copies: floor(M w_i / 2^24) of particle i; the residual
    // (M w_i mod 2^24), kept to 16 fraction bits, replaces the weight. The residuals sum
    // to R 2^24 for R < N remaining draws, so R 2^16 < 2^32 fits the cumulative sums.
    let mut filled = 0usize;
    for (i, w) in weights.iter_mut().enumerate() {
        let scaled = m * *w as u64;
        let copies = (scaled >> WEIGHT_TOTAL_LOG2) as usize;
        for o in out.iter_mut().skip(filled).take(copies) {
            *o = i as u16;
        }
        filled += copies;
        *w = ((scaled & (WEIGHT_TOTAL as u64 - 1)) >> (WEIGHT_TOTAL_LOG2 - RESIDUAL_FRAC_BITS))
            as u32;
    }
    cumulate(weights);
    let total = weights.last().copied().unwrap_or(0);
    for o in out.iter_mut().skip(filled) {
        *o = search(weights, rng.below(total));
    }
}

/// Replaces `items` by the resampled set in place, given the `indices` resampling drew
/// (each `< items.len()`; others are ignored): an item drawn `k >= 1` times keeps its slot
/// and its `k - 1` extra copies fill, in order, the slots of the items drawn zero times.
/// `counts` is scratch of the same length. The result is the drawn multiset in another
/// order, which a particle filter does not see; it needs no second particle array.
pub fn replicate<T: Copy>(items: &mut [T], indices: &[u16], counts: &mut [u16]) {
    counts.iter_mut().for_each(|c| *c = 0);
    for &i in indices {
        if let Some(c) = counts.get_mut(i as usize) {
            *c = c.saturating_add(1);
        }
    }
    let len = items.len().min(counts.len());
    let mut source = 0;
    for slot in 0..len {
        if counts[slot] != 0 {
            continue;
        }
        // Next item with a spare copy.
        while source < len && counts[source] <= 1 {
            source += 1;
        }
        if source >= len {
            break;
        }
        counts[source] -= 1;
        items[slot] = items[source];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    extern crate std;
    use std::vec;
    use std::vec::Vec;

    const ALL: [Scheme; 4] = [
        Scheme::Multinomial,
        Scheme::Systematic,
        Scheme::Stratified,
        Scheme::Residual,
    ];

    /// [`spaced`] by the definition, with a 64-bit division per position.
    fn spaced_wide(cum: &[u32], out: &mut [u16], mut offset: impl FnMut(usize) -> u32) {
        let m = out.len() as u64;
        let last = cum.len().saturating_sub(1);
        let mut j = 0usize;
        for (k, o) in out.iter_mut().enumerate() {
            let r = (((k as u64) << WEIGHT_TOTAL_LOG2) + offset(k) as u64) / m;
            while j < last && cum.get(j).is_some_and(|&c| c as u64 <= r) {
                j += 1;
            }
            *o = j as u16;
        }
    }

    fn counts(out: &[u16], n: usize) -> Vec<usize> {
        let mut c = vec![0; n];
        for &i in out {
            c[i as usize] += 1;
        }
        c
    }

    #[test]
    fn normalise_is_exact() {
        for weights in [
            vec![1u32, 2, 3],
            vec![u32::MAX; 1000],
            vec![7; 3],
            vec![0, 0, 5, 0],
            vec![1, u32::MAX, 1, 0],
            vec![3; 65535],
        ] {
            let mut w = weights.clone();
            assert_eq!(normalise(&mut w), Normalised::Scaled);
            assert_eq!(
                w.iter().map(|&x| x as u64).sum::<u64>(),
                WEIGHT_TOTAL as u64
            );
            let sum: f64 = weights.iter().map(|&x| x as f64).sum();
            for (a, b) in w.iter().zip(weights.iter()) {
                let ideal = *b as f64 / sum * WEIGHT_TOTAL as f64;
                assert!((*a as f64 - ideal).abs() <= 1.0, "{a} vs {ideal}");
                if *b == 0 {
                    assert_eq!(*a, 0);
                }
            }
        }
        let mut w = [0u32; 3];
        assert_eq!(normalise(&mut w), Normalised::AllZero);
        assert_eq!(w.iter().sum::<u32>(), WEIGHT_TOTAL);
        assert!(w.iter().all(|&x| x == 5_592_405 || x == 5_592_406));
        let mut empty: [u32; 0] = [];
        assert_eq!(normalise(&mut empty), Normalised::AllZero);
    }

    /// Every path of `normalise` (shift, u64 division, long division) gives the cumulative
    /// rounding `floor(C_i 2^24 / C)` computed in u128; `spaced` gives
    /// `floor((k 2^24 + u) / M)` for every `k`.
    #[test]
    fn fast_paths_equal_the_wide_arithmetic() {
        let mut r = Rng::new(21);
        for trial in 0..3000 {
            let n = 1 + r.below(300) as usize;
            let mut w: Vec<u32> = (0..n)
                .map(|_| match trial % 3 {
                    0 => r.next_u32() >> (r.next_u32() % 32),
                    1 => r.next_u32(),
                    _ => r.below(4),
                })
                .collect();
            if trial % 5 == 0 {
                // A power-of-two total, as after a previous normalisation.
                normalise(&mut w);
            }
            let total: u128 = w.iter().map(|&x| x as u128).sum();
            let mut expected = w.clone();
            let (mut cum, mut prev) = (0u128, 0u128);
            for e in expected.iter_mut() {
                cum += *e as u128;
                let edge = (cum << 24).checked_div(total).unwrap_or(0);
                *e = (edge - prev) as u32;
                prev = edge;
            }
            let found = normalise(&mut w);
            if total > 0 {
                assert_eq!(found, Normalised::Scaled);
                assert_eq!(w, expected, "trial {trial}");
            }
            // Spaced positions against the direct 64-bit formula.
            let m = 1 + r.below(400) as usize;
            let offsets: Vec<u32> = (0..m).map(|_| r.next_u32() >> 8).collect();
            let mut cum = w.clone();
            cumulate(&mut cum);
            let mut fast = vec![0u16; m];
            spaced(&cum, &mut fast, |k| offsets[k]);
            let mut wide = vec![0u16; m];
            spaced_wide(&cum, &mut wide, |k| offsets[k]);
            assert_eq!(fast, wide, "trial {trial}");
        }
    }

    /// The long division of sums from `2^40` to `2^64 - 1` equals the `u128` formula.
    #[test]
    fn long_division_is_exact() {
        let mut r = Rng::new(8);
        for trial in 0..20_000u32 {
            let total = match trial % 4 {
                0 => u64::MAX - r.below(1000) as u64,
                1 => (1 << 40) + r.next_u32() as u64,
                _ => ((r.next_u32() as u64) << 32 | r.next_u32() as u64) | 1 << 40,
            };
            let cum = match trial % 3 {
                0 => total,
                1 => total - (r.next_u32() as u64).min(total),
                _ => {
                    let any = (r.next_u32() as u64) << 32 | r.next_u32() as u64;
                    total.checked_add(1).map_or(any, |m| any % m)
                }
            };
            let expected = ((cum as u128) << WEIGHT_TOTAL_LOG2) / total as u128;
            assert_eq!(scaled_long(cum, total) as u128, expected, "{cum} / {total}");
        }
    }

    /// Exactly N valid indices for all-zero, one non-zero, saturated and mixed weights,
    /// every scheme, several N (including 1).
    #[test]
    fn always_n_valid_indices() {
        let mut rng = Rng::new(5);
        for n in [1usize, 2, 3, 10, 200, 1000] {
            let cases: [Vec<u32>; 4] = [
                vec![0; n],
                (0..n).map(|i| (i == n / 2) as u32).collect(),
                vec![u32::MAX; n],
                (0..n)
                    .map(|i| (i as u32).wrapping_mul(2_654_435_761) | 1)
                    .collect(),
            ];
            for (c, weights) in cases.iter().enumerate() {
                for scheme in ALL {
                    let mut w = weights.clone();
                    let mut out = vec![u16::MAX; n];
                    let r = resample(scheme, &mut w, &mut rng, &mut out).unwrap();
                    assert_eq!(r == Normalised::AllZero, c == 0);
                    assert!(out.iter().all(|&i| (i as usize) < n), "{scheme:?} {n} {c}");
                    if c == 1 {
                        assert!(out.iter().all(|&i| i as usize == n / 2), "{scheme:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn output_length_may_differ_from_input() {
        let mut rng = Rng::new(6);
        for scheme in ALL {
            let mut w = [1u32, 1, 1];
            let mut out = [u16::MAX; 7];
            resample(scheme, &mut w, &mut rng, &mut out).unwrap();
            assert!(out.iter().all(|&i| i < 3));
            let mut w = [1u32; 9];
            let mut out = [u16::MAX; 2];
            resample(scheme, &mut w, &mut rng, &mut out).unwrap();
            assert!(out.iter().all(|&i| i < 9));
        }
    }

    #[test]
    fn empty_and_oversized_inputs() {
        let mut rng = Rng::new(7);
        for scheme in ALL {
            let mut w: [u32; 0] = [];
            let mut out: [u16; 0] = [];
            assert_eq!(
                resample(scheme, &mut w, &mut rng, &mut out),
                Ok(Normalised::AllZero)
            );
            let mut out = [9u16; 3];
            assert_eq!(
                resample(scheme, &mut w, &mut rng, &mut out),
                Err(ResampleError::NoParticles)
            );
            assert_eq!(out, [9; 3]);
            let mut w = [1u32; 2];
            let mut out: [u16; 0] = [];
            assert!(resample(scheme, &mut w, &mut rng, &mut out).is_ok());
            let mut big = vec![1u32; MAX_PARTICLES + 1];
            let mut out = [0u16; 1];
            assert_eq!(
                resample(scheme, &mut big, &mut rng, &mut out),
                Err(ResampleError::TooManyParticles)
            );
        }
        let mut max = vec![1u32; MAX_PARTICLES];
        max[MAX_PARTICLES - 1] = u32::MAX;
        let mut out = vec![0u16; MAX_PARTICLES];
        for scheme in ALL {
            let mut w = max.clone();
            resample(scheme, &mut w, &mut rng, &mut out).unwrap();
            // The last particle holds ~99.4 % of the mass.
            let last = out
                .iter()
                .filter(|&&i| i as usize == MAX_PARTICLES - 1)
                .count();
            assert!(last > MAX_PARTICLES * 99 / 100, "{scheme:?} {last}");
        }
    }

    /// Systematic and residual give floor or ceil(N w_i) copies; stratified and
    /// residual within one stratum's worth.
    #[test]
    fn low_variance_schemes_give_expected_counts() {
        let mut rng = Rng::new(8);
        for trial in 0..200u32 {
            let n = 1 + (trial as usize * 7) % 150;
            let weights: Vec<u32> = (0..n)
                .map(|i| ((i as u32 + trial).wrapping_mul(2_246_822_519) >> (trial % 20)) % 1000)
                .collect();
            let mut norm = weights.clone();
            let all_zero = normalise(&mut norm) == Normalised::AllZero;
            for scheme in [Scheme::Systematic, Scheme::Residual] {
                let mut w = weights.clone();
                let mut out = vec![0u16; n];
                let r = resample(scheme, &mut w, &mut rng, &mut out).unwrap();
                assert_eq!(r == Normalised::AllZero, all_zero);
                let c = counts(&out, n);
                for (i, &ci) in c.iter().enumerate() {
                    let ideal = n as f64 * norm[i] as f64 / WEIGHT_TOTAL as f64;
                    assert!(ci >= ideal.floor() as usize, "{scheme:?} {i} {ci} {ideal}");
                    if scheme == Scheme::Systematic {
                        assert!(ci <= ideal.ceil() as usize, "{i} {ci} {ideal}");
                    }
                }
            }
        }
    }

    /// Over many draws every scheme's mean count per particle is N w_i within a few
    /// standard errors.
    #[test]
    fn schemes_are_unbiased() {
        let weights = [1u32, 0, 7, 2, 10, 30, 0, 50];
        let n = weights.len();
        let sum: u32 = weights.iter().sum();
        let draws = 20_000;
        for scheme in ALL {
            let mut rng = Rng::new(11);
            let mut total = vec![0u64; n];
            for _ in 0..draws {
                let mut w = weights;
                let mut out = [0u16; 8];
                resample(scheme, &mut w, &mut rng, &mut out).unwrap();
                for (t, c) in total.iter_mut().zip(counts(&out, n)) {
                    *t += c as u64;
                }
            }
            for i in 0..n {
                let p = weights[i] as f64 / sum as f64;
                let mean = total[i] as f64 / draws as f64;
                // Multinomial standard error is the largest of the four.
                let se = (n as f64 * p * (1.0 - p) / draws as f64).sqrt();
                assert!(
                    (mean - n as f64 * p).abs() <= 5.0 * se + 1e-3,
                    "{scheme:?} particle {i}: {mean} vs {}",
                    n as f64 * p
                );
            }
        }
    }

    #[test]
    fn effective_sample_size_edges() {
        let ess = |w: &[u32]| effective_sample_size(w).to_f64();
        assert_eq!(ess(&[]), 0.0);
        assert_eq!(ess(&[0, 0, 0]), 0.0);
        assert_eq!(ess(&[5]), 1.0);
        assert_eq!(ess(&[0, 9, 0]), 1.0);
        assert_eq!(ess(&[3; 100]), 100.0);
        assert_eq!(ess(&[u32::MAX; 1000]), 1000.0);
        // 16 / 6 particles, rounded down to Q16.16.
        assert_eq!(effective_sample_size(&[1, 1, 2]).to_bits(), (16 << 16) / 6);
        assert_eq!(effective_sample_size(&vec![1; 40_000]), Q16::MAX);
        assert_eq!(effective_sample_size(&vec![u32::MAX; 65_535]), Q16::MAX);
        // The comparison agrees with the value, at and around it.
        let mut r = Rng::new(12);
        for n in [1usize, 2, 7, 100, 1000] {
            for _ in 0..50 {
                let w: Vec<u32> = (0..n)
                    .map(|_| r.next_u32() >> (r.next_u32() % 32))
                    .collect();
                let e = effective_sample_size(&w);
                for t in [-1, 0, 1, 2] {
                    let threshold = Q16::from_bits(e.to_bits().saturating_add(t));
                    assert_eq!(
                        effective_sample_size_at_least(&w, threshold),
                        e >= threshold
                    );
                }
            }
        }
        assert!(!effective_sample_size_at_least(&[0, 0], Q16::ONE));
        assert!(effective_sample_size_at_least(&[0, 0], Q16::ZERO));
        assert!(effective_sample_size_at_least(
            &vec![u32::MAX; 65_535],
            Q16::MAX
        ));
        let mut w = [4u32, 1, 0, 3];
        let before = ess(&w);
        normalise(&mut w);
        assert!((ess(&w) - before).abs() < 1e-4);
    }

    #[test]
    fn error_messages() {
        use std::string::ToString;
        assert_eq!(
            ResampleError::TooManyParticles.to_string(),
            "more than 65535 weights to resample"
        );
        assert_eq!(
            ResampleError::NoParticles.to_string(),
            "no weights to resample from"
        );
        assert_eq!(
            ResampleError::TooManyDraws.to_string(),
            "more than 4294967295 indices to draw"
        );
    }

    #[test]
    fn replicate_gives_the_drawn_multiset() {
        let mut items = [0, 1, 2, 3, 4, 5];
        replicate(&mut items, &[4, 4, 4, 1, 0, 1], &mut [0; 6]);
        let mut got = items;
        got.sort();
        assert_eq!(got, [0, 1, 1, 4, 4, 4]);
    }

    #[test]
    fn replicate_identity_single_survivor_and_bad_indices() {
        let mut items = [0, 1, 2, 3];
        replicate(&mut items, &[0, 1, 2, 3], &mut [0; 4]);
        assert_eq!(items, [0, 1, 2, 3]);
        replicate(&mut items, &[2, 2, 2, 2], &mut [0; 4]);
        assert_eq!(items, [2, 2, 2, 2]);
        let mut items = [7, 8];
        replicate(&mut items, &[9, 1], &mut [0; 2]); // 9 is out of range: ignored
        assert_eq!(items, [7, 8]);
    }
}
