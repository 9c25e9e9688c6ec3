//! The fixed-point FFT on any samples: every 1-D size (2 to 64 points) and the 2-D grids
//! 16 x 16, 32 x 32 and 64 x 64, forward and inverse, normalised first or not; the
//! fuzzer's samples repeated to fill the block, or one of them everywhere.
//!
//! Oracles: no panic; every output within `error_bound_lsb` LSB of the exact transform
//! (an f64 DFT) at the returned exponent, which a wrapped overflow would break.
#![no_main]

use arbitrary::Arbitrary;
use libfuzzer_sys::fuzz_target;
use rbtrack::fft::{error_bound_lsb, forward, forward_2d, inverse, inverse_2d, normalise, Complex};

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
    let x: Vec<Complex> = match (input.samples.first(), input.constant) {
        (None, _) => vec![Complex::ZERO; points],
        (Some(&(re, im)), true) => vec![Complex::new(re, im); points],
        (Some(_), false) => input
            .samples
            .iter()
            .cycle()
            .take(points)
            .map(|&(re, im)| Complex::new(re, im))
            .collect(),
    };
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
    }
});
