//! The fixed-point FFT on any samples: every 1-D size (2 to 64 points) and the 2-D grids
//! 16 x 16, 32 x 32 and 64 x 64, forward and inverse, normalised first or not; and the
//! direct transforms of 3, 4, 5 and 16 points (`forward_direct`, `inverse_direct_real`); the
//! fuzzer's samples repeated to fill the block, or one of them everywhere.
//!
//! Oracles: no panic; every FFT output within `error_bound_lsb` LSB of the exact transform
//! (an f64 DFT) at the returned exponent, which a wrapped overflow would break; every
//! direct output within `1/2 + 2^-28 sum |x|` of the exact transform of the input
//! saturated to `[-2^30, 2^30)`, saturated to `i32`.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use rbtrack::fft::{
    error_bound_lsb, forward, forward_2d, forward_direct, inverse, inverse_2d, inverse_direct_real,
    normalise, Complex,
};

#[derive(Arbitrary, Debug, Clone, Copy)]
enum Size {
    P2,
    P4,
    P8,
    P16,
    P32,
    P64,
    G16,
    G32,
    G64,
    D3,
    D4,
    D5,
    D16,
}

#[derive(Arbitrary, Debug)]
struct Input {
    size: Size,
    inverse: bool,
    normalise: bool,
    /// One sample everywhere instead of the samples repeated.
    constant: bool,
    samples: Vec<(i32, i32)>,
}

/// The exact transform of a `rows x cols` grid, row-major, inverse divided by the points.
fn dft(x: &[Complex], rows: usize, cols: usize, inverse: bool) -> Vec<(f64, f64)> {
    let sign = if inverse { 1.0 } else { -1.0 };
    let one = |v: &[(f64, f64)]| -> Vec<(f64, f64)> {
        let n = v.len();
        (0..n)
            .map(|k| {
                v.iter()
                    .enumerate()
                    .fold((0.0, 0.0), |(re, im), (j, &(vr, vi))| {
                        let t = sign * 2.0 * std::f64::consts::PI * ((j * k) % n) as f64 / n as f64;
                        let (c, s) = (t.cos(), t.sin());
                        (re + vr * c - vi * s, im + vr * s + vi * c)
                    })
            })
            .collect()
    };
    let mut data: Vec<(f64, f64)> = x.iter().map(|v| (v.re as f64, v.im as f64)).collect();
    for row in data.chunks_mut(cols) {
        let out = one(row);
        row.copy_from_slice(&out);
    }
    for c in 0..cols {
        let column: Vec<(f64, f64)> = (0..rows).map(|y| data[y * cols + c]).collect();
        for (y, v) in one(&column).into_iter().enumerate() {
            data[y * cols + c] = v;
        }
    }
    let scale = if inverse {
        1.0 / (rows * cols) as f64
    } else {
        1.0
    };
    data.into_iter()
        .map(|(re, im)| (re * scale, im * scale))
        .collect()
}

/// Transforms `block` (`rows x cols`) by `run`, which returns the exponent, and checks
/// the outputs against the exact transform.
fn check(input: &Input, rows: usize, cols: usize, run: impl Fn(&mut [Complex], bool) -> i32) {
    let points = rows * cols;
    let x = samples(input, points);
    let mut out = x.clone();
    let e0 = if input.normalise {
        normalise(&mut out)
    } else {
        0
    };
    let e = e0 + run(&mut out, input.inverse);
    let lsb = 2f64.powi(e);
    let bound = error_bound_lsb(points) as f64;
    for (o, w) in out.iter().zip(dft(&x, rows, cols, input.inverse)) {
        let err = (o.re as f64 - w.0 / lsb)
            .abs()
            .max((o.im as f64 - w.1 / lsb).abs());
        assert!(err <= bound, "{rows} x {cols}: {err} LSB, e {e}");
    }
}

/// The input's `N` samples, as [`check`] fills a block.
fn samples(input: &Input, points: usize) -> Vec<Complex> {
    match (input.samples.first(), input.constant) {
        (None, _) => vec![Complex::ZERO; points],
        (Some(&(re, im)), true) => vec![Complex::new(re, im); points],
        (Some(_), false) => input
            .samples
            .iter()
            .cycle()
            .take(points)
            .map(|&(re, im)| Complex::new(re, im))
            .collect(),
    }
}

/// The direct transform of `N` samples against the exact transform of the saturated ones.
fn direct<const N: usize>(input: &Input) {
    let x = samples(input, N);
    let limit = |v: i32| v.clamp(-(1 << 30), (1 << 30) - 1);
    let saturated: Vec<Complex> = x
        .iter()
        .map(|v| Complex::new(limit(v.re), limit(v.im)))
        .collect();
    let magnitude: f64 = saturated
        .iter()
        .map(|v| (v.re as f64).abs() + (v.im as f64).abs())
        .sum();
    let bound = 0.5 + magnitude * 2f64.powi(-28) + 1e-6;
    let want = dft(&saturated, 1, N, input.inverse);
    let clamp = |v: f64| v.clamp(i32::MIN as f64, i32::MAX as f64);
    let block: [Complex; N] = x.try_into().expect("N samples");
    if input.inverse {
        for (o, w) in inverse_direct_real(&block).iter().zip(&want) {
            let err = (*o as f64 - clamp(w.0)).abs();
            assert!(err <= bound, "{N} points, inverse: {err} LSB");
        }
    } else {
        let mut out = block;
        forward_direct(&mut out);
        for (o, w) in out.iter().zip(&want) {
            let err = (o.re as f64 - clamp(w.0))
                .abs()
                .max((o.im as f64 - clamp(w.1)).abs());
            assert!(err <= bound, "{N} points: {err} LSB");
        }
    }
}

fn one_d<const N: usize>(input: &Input) {
    check(input, 1, N, |data, inv| {
        let data: &mut [Complex; N] = data.try_into().expect("N samples");
        if inv {
            inverse(data)
        } else {
            forward(data)
        }
    });
}

fn two_d<const N: usize>(input: &Input) {
    check(input, N, N, |data, inv| {
        let mut grid = [[Complex::ZERO; N]; N];
        grid.as_flattened_mut().copy_from_slice(data);
        let e = if inv {
            inverse_2d(&mut grid)
        } else {
            forward_2d(&mut grid)
        };
        data.copy_from_slice(grid.as_flattened());
        e
    });
}

fuzz_target!(|input: Input| {
    match input.size {
        Size::P2 => one_d::<2>(&input),
        Size::P4 => one_d::<4>(&input),
        Size::P8 => one_d::<8>(&input),
        Size::P16 => one_d::<16>(&input),
        Size::P32 => one_d::<32>(&input),
        Size::P64 => one_d::<64>(&input),
        Size::G16 => two_d::<16>(&input),
        Size::G32 => two_d::<32>(&input),
        Size::G64 => two_d::<64>(&input),
        Size::D3 => direct::<3>(&input),
        Size::D4 => direct::<4>(&input),
        Size::D5 => direct::<5>(&input),
        Size::D16 => direct::<16>(&input),
    }
});
