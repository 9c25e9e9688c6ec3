//! The core's fixed-point FFT (`rbtrack::fft`) against rustfft in f64. Errors are the
//! largest absolute error of any output, in LSB of the output's block scale (`2^e`, `e`
//! the returned exponent), for `P` points:
//! - Every size, 1-D (2 to 64 points) and 2-D (16 x 16, 32 x 32, 64 x 64, and 8 x 32),
//!   forward and inverse, on random samples of every magnitude (2 to 32 bits), as they
//!   come and normalised first: within `4 + sqrt P`, and
//!   normalised blocks above 140 dB of signal to error. `cargo test --test fft --
//!   --nocapture` prints the largest errors.
//! - Property tests over arbitrary samples with the full-scale extremes (`i32::MIN`
//!   everywhere, alternating `i32::MIN` and `i32::MAX`, constants, any `i32`): no panic,
//!   and within `error_bound_lsb(P)` (`3 P`, the bound for any input), which a wrapped
//!   overflow (`2^32` LSB off) would break.

use proptest::prelude::*;
use rbtrack::fft::{error_bound_lsb, forward, forward_2d, inverse, inverse_2d, normalise, Complex};
use rbtrack::rng::Rng;
use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;

/// The exact transform of a `rows x cols` grid (row-major; `rows = 1` in 1-D), inverse
/// divided by the points, in f64.
fn oracle(x: &[Complex], rows: usize, cols: usize, inverse: bool) -> Vec<Complex64> {
    let mut data: Vec<Complex64> = x
        .iter()
        .map(|v| Complex64::new(v.re as f64, v.im as f64))
        .collect();
    let mut planner = FftPlanner::new();
    let mut plan = |n| match inverse {
        false => planner.plan_fft_forward(n),
        true => planner.plan_fft_inverse(n),
    };
    let (row_fft, col_fft) = (plan(cols), plan(rows));
    for row in data.chunks_mut(cols) {
        row_fft.process(row);
    }
    let mut column = vec![Complex64::default(); rows];
    for c in 0..cols {
        for (y, v) in column.iter_mut().enumerate() {
            *v = data[y * cols + c];
        }
        col_fft.process(&mut column);
        for (y, v) in column.iter().enumerate() {
            data[y * cols + c] = *v;
        }
    }
    if inverse {
        let points = (rows * cols) as f64;
        data.iter_mut().for_each(|v| *v /= points);
    }
    data
}

/// The largest error of `out` times `2^e` against `want`, in LSB of `out`, and the signal
/// to error ratio, dB (infinite without error).
fn errors(out: &[Complex], e: i32, want: &[Complex64]) -> (f64, f64) {
    let lsb = 2f64.powi(e);
    let (mut worst, mut noise, mut signal) = (0f64, 0.0, 0.0);
    for (o, w) in out.iter().zip(want) {
        let (dr, di) = (o.re as f64 - w.re / lsb, o.im as f64 - w.im / lsb);
        worst = worst.max(dr.abs()).max(di.abs());
        noise += dr * dr + di * di;
        signal += (w.re / lsb).powi(2) + (w.im / lsb).powi(2);
    }
    let snr = match noise {
        0.0 => f64::INFINITY,
        _ => 10.0 * (signal / noise).log10(),
    };
    (worst, snr)
}

/// The bound on random inputs, `4 + sqrt P` LSB for `P` points (`rbtrack::fft`'s doc).
fn typical_error_lsb(points: usize) -> f64 {
    4.0 + (points as f64).sqrt()
}

/// Random samples of `bits` bits (`-2^(bits-1)` to `2^(bits-1) - 1`).
fn random(rng: &mut Rng, n: usize, bits: u32) -> Vec<Complex> {
    let mut sample = || (rng.next_u32() as i32) >> (32 - bits);
    (0..n).map(|_| Complex::new(sample(), sample())).collect()
}

/// A transform as the core does it, of `x` into `out`, normalised first or not: its
/// exponent.
type Transform = fn(x: &[Complex], out: &mut Vec<Complex>, inverse: bool, normalised: bool) -> i32;

/// The 1-D transforms of `N` points.
fn one_d<const N: usize>(x: &[Complex], out: &mut Vec<Complex>, inv: bool, norm: bool) -> i32 {
    let mut data: [Complex; N] = x.try_into().expect("N samples");
    let e0 = if norm { normalise(&mut data) } else { 0 };
    let e = if inv {
        inverse(&mut data)
    } else {
        forward(&mut data)
    };
    *out = data.to_vec();
    e0 + e
}

/// The 2-D transforms of `R x C` grids.
fn two_d<const R: usize, const C: usize>(
    x: &[Complex],
    out: &mut Vec<Complex>,
    inv: bool,
    norm: bool,
) -> i32 {
    let mut grid = [[Complex::ZERO; C]; R];
    grid.as_flattened_mut().copy_from_slice(x);
    let e0 = if norm {
        normalise(grid.as_flattened_mut())
    } else {
        0
    };
    let e = if inv {
        inverse_2d(&mut grid)
    } else {
        forward_2d(&mut grid)
    };
    *out = grid.as_flattened().to_vec();
    e0 + e
}

/// Random blocks of every magnitude through one size, both directions, raw and
/// normalised: asserts the bound, prints the largest error.
fn random_blocks((rows, cols): (usize, usize), transform: Transform, blocks: usize) {
    let points = rows * cols;
    let mut out = Vec::new();
    let mut rng = Rng::new(points as u64);
    let (mut worst, mut min_snr) = (0f64, f64::MAX);
    for bits in [2, 8, 16, 24, 29, 31, 32] {
        for _ in 0..blocks {
            let x = random(&mut rng, points, bits);
            for (inv, normalised) in [(false, false), (true, false), (false, true), (true, true)] {
                let e = transform(&x, &mut out, inv, normalised);
                let (err, snr) = errors(&out, e, &oracle(&x, rows, cols, inv));
                assert!(
                    err <= typical_error_lsb(points),
                    "{rows} x {cols}, {bits} bits, inverse {inv}, normalised {normalised}: {err} LSB"
                );
                if normalised {
                    assert!(snr > 140.0, "{rows} x {cols}, {bits} bits: {snr} dB");
                    min_snr = min_snr.min(snr);
                }
                worst = worst.max(err);
            }
        }
    }
    println!(
        "{rows} x {cols}: largest error {worst:.2} LSB (bound {:.1}), normalised SNR >= {min_snr:.1} dB",
        typical_error_lsb(points)
    );
}

#[test]
fn every_1d_size_is_within_the_bound() {
    random_blocks((1, 2), one_d::<2>, 200);
    random_blocks((1, 4), one_d::<4>, 200);
    random_blocks((1, 8), one_d::<8>, 200);
    random_blocks((1, 16), one_d::<16>, 200);
    random_blocks((1, 32), one_d::<32>, 200);
    random_blocks((1, 64), one_d::<64>, 200);
}

#[test]
fn every_2d_size_is_within_the_bound() {
    random_blocks((16, 16), two_d::<16, 16>, 20);
    random_blocks((32, 32), two_d::<32, 32>, 10);
    random_blocks((64, 64), two_d::<64, 64>, 5);
    random_blocks((8, 32), two_d::<8, 32>, 20);
}

/// Samples: any `i32`, the rails and small values.
fn sample() -> impl Strategy<Value = i32> {
    prop_oneof![
        any::<i32>(),
        Just(i32::MIN),
        Just(i32::MAX),
        Just(0),
        -4i32..4,
    ]
}

/// Blocks of `n` samples: arbitrary, `i32::MIN` everywhere, alternating extremes (both
/// parts, or crossed), a constant.
fn block(n: usize) -> impl Strategy<Value = Vec<Complex>> {
    let min = Complex::new(i32::MIN, i32::MIN);
    let max = Complex::new(i32::MAX, i32::MAX);
    prop_oneof![
        proptest::collection::vec((sample(), sample()), n)
            .prop_map(|v| v.into_iter().map(|(re, im)| Complex::new(re, im)).collect()),
        Just(vec![min; n]),
        Just((0..n).map(|i| if i % 2 == 0 { min } else { max }).collect()),
        Just(
            (0..n)
                .map(|i| match i % 2 {
                    0 => Complex::new(i32::MIN, i32::MAX),
                    _ => Complex::new(i32::MAX, i32::MIN),
                })
                .collect()
        ),
        (sample(), sample()).prop_map(move |(re, im)| vec![Complex::new(re, im); n]),
    ]
}

/// Both directions of one block, raw and normalised, within the bound.
fn check(
    x: &[Complex],
    (rows, cols): (usize, usize),
    transform: Transform,
) -> Result<(), TestCaseError> {
    let mut out = Vec::new();
    for inv in [false, true] {
        for normalised in [false, true] {
            let e = transform(x, &mut out, inv, normalised);
            let (err, _) = errors(&out, e, &oracle(x, rows, cols, inv));
            prop_assert!(
                err <= error_bound_lsb(rows * cols) as f64,
                "{rows} x {cols}, inverse {inv}, normalised {normalised}: {err} LSB"
            );
        }
    }
    Ok(())
}

proptest! {
    #[test]
    fn extremes_in_1d_stay_within_the_bound(x8 in block(8), x64 in block(64)) {
        check(&x8, (1, 8), one_d::<8>)?;
        check(&x64, (1, 64), one_d::<64>)?;
    }

    #[test]
    fn extremes_in_2d_stay_within_the_bound(x16 in block(256), x32 in block(1024)) {
        check(&x16, (16, 16), two_d::<16, 16>)?;
        check(&x32, (32, 32), two_d::<32, 32>)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    #[test]
    fn extremes_in_64_x_64_stay_within_the_bound(x in block(4096)) {
        check(&x, (64, 64), two_d::<64, 64>)?;
    }
}
