//! Resampling primitives: `normalise`, `resample` (every scheme) and
//! `effective_sample_size` on any weights (all zero, one non-zero, saturated, more than
//! `MAX_PARTICLES`) and any number of draws.
//!
//! Oracles: no panic; `resample` fails exactly for more than `MAX_PARTICLES` weights or
//! none for a non-empty output, and otherwise fills every output slot with a valid index,
//! never one of a zero weight unless all are zero; `normalise` sums to exactly
//! `WEIGHT_TOTAL` and keeps zeros; the effective sample size lies between 1 and the
//! number of non-zero weights (0 when all are zero).
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use rbtrack::fixed::Q16;
use rbtrack::resample::{
    effective_sample_size, normalise, resample, Normalised, MAX_PARTICLES, WEIGHT_TOTAL,
};
use rbtrack::rng::Rng;
use rbtrack_fuzz::SchemeSpec;

#[derive(Arbitrary, Debug, Clone, Copy)]
enum Weight {
    Raw(u32),
    Zero,
    Max,
}

/// A number of weights: mostly small (fast inputs), sometimes above `MAX_PARTICLES`.
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Len {
    /// 0..=255.
    Small(u8),
    /// 0..=2047.
    Medium(u16),
    /// 0..70,000.
    Large(u32),
}

impl Len {
    fn get(self) -> usize {
        match self {
            Len::Small(n) => n as usize,
            Len::Medium(n) => (n % 2048) as usize,
            Len::Large(n) => (n % 70_000) as usize,
        }
    }
}

#[derive(Arbitrary, Debug, Clone)]
struct Input {
    scheme: SchemeSpec,
    seed: u64,
    /// Weights, repeated to `len` entries (zeros when empty).
    pattern: Vec<Weight>,
    /// Number of weights.
    len: Len,
    /// Number of draws: `draws % 4096`.
    draws: u16,
}

fuzz_target!(|input: Input| {
    let len = input.len.get();
    let weights: Vec<u32> = if input.pattern.is_empty() {
        vec![0; len]
    } else {
        input
            .pattern
            .iter()
            .map(|w| match w {
                Weight::Raw(v) => *v,
                Weight::Zero => 0,
                Weight::Max => u32::MAX,
            })
            .cycle()
            .take(len)
            .collect()
    };
    let nonzero = weights.iter().filter(|&&w| w > 0).count();

    let ess = effective_sample_size(&weights);
    if nonzero == 0 {
        assert_eq!(ess, Q16::ZERO);
    } else {
        assert!(ess >= Q16::ONE - Q16::EPSILON, "ess {ess:?}");
        assert!(
            ess <= Q16::from_int(nonzero as i32),
            "ess {ess:?} of {nonzero}"
        );
    }

    let mut normalised = weights.clone();
    let found = normalise(&mut normalised);
    assert_eq!(found == Normalised::AllZero, nonzero == 0);
    if len > 0 {
        let total: u64 = normalised.iter().map(|&w| w as u64).sum();
        assert_eq!(total, WEIGHT_TOTAL as u64);
    }
    if nonzero > 0 {
        for (a, b) in normalised.iter().zip(weights.iter()) {
            assert!(*b != 0 || *a == 0, "a zero weight became non-zero");
        }
    }

    let draws = (input.draws % 4096) as usize;
    let mut scratch = weights.clone();
    let mut out = vec![u16::MAX; draws];
    let mut rng = Rng::new(input.seed);
    match resample(input.scheme.get(), &mut scratch, &mut rng, &mut out) {
        Ok(found) => {
            assert!(len <= MAX_PARTICLES && (len > 0 || draws == 0));
            assert_eq!(found == Normalised::AllZero, nonzero == 0);
            for &i in &out {
                let i = i as usize;
                assert!(i < len, "index {i} of {len}");
                // A weight that normalises to zero (a share below 2^-24) may not be drawn.
                assert!(nonzero == 0 || normalised[i] > 0, "drew weight 0 at {i}");
            }
        }
        Err(_) => assert!(len > MAX_PARTICLES || (len == 0 && draws > 0)),
    }
});
