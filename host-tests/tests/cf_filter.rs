//! The core's integer translation filter (`rbtrack::cf::filter`) against the host's f64
//! reference (`cf64::filter`), on the same Q15 features: both trained on one grid, then
//! answering shifted, noisy grids and learning them at rates 0.01 to 0.1 with fractional
//! target shifts, for sigma 1 and 2 cells and lambda 1e-3. The largest absolute error of
//! the response (units of 1.0, over the whole grid and every frame) is printed
//! (`--nocapture`) and asserted below 0.01, and the peak cells agree.

use rbtrack::cf::features::{Cell, CHANNELS};
use rbtrack::cf::filter::{Filter, FilterSettings};
use rbtrack::rng::Rng;
use rbtrack::Q16;
use rbtrack_host::cf64::fhog::Features;
use rbtrack_host::cf64::filter::{cosine_window, Filter as F64Filter};

const G: usize = 32;

type Grid = [[Cell; G]; G];

/// A channel's range: grey in `[-0.5, 0.5]`, fHOG in `[0, 0.4]`, Q15.
fn range(c: usize) -> (f64, f64) {
    if c == 0 {
        (-0.5, 0.5)
    } else {
        (0.0, 0.4)
    }
}

fn q15(v: f64, c: usize) -> i16 {
    let (lo, hi) = range(c);
    (v.clamp(lo, hi) * 32_768.0).round() as i16
}

/// Independent uniform values in each channel's range.
fn random_grid(rng: &mut Rng) -> Box<Grid> {
    let mut grid = Box::new([[[0i16; CHANNELS]; G]; G]);
    for cell in grid.as_flattened_mut() {
        for (c, v) in cell.iter_mut().enumerate() {
            let (lo, hi) = range(c);
            *v = q15(lo + (hi - lo) * rng.next_u32() as f64 / 4_294_967_296.0, c);
        }
    }
    grid
}

/// Sums of a few sinusoids per channel, scaled into the channel's range.
fn smooth_grid(rng: &mut Rng) -> Box<Grid> {
    let mut grid = Box::new([[[0i16; CHANNELS]; G]; G]);
    let mut uniform = || rng.next_u32() as f64 / 4_294_967_296.0;
    for c in 0..CHANNELS {
        let waves: Vec<(f64, f64, f64)> = (0..3)
            .map(|_| {
                let (fy, fx) = ((uniform() * 4.0).floor(), (uniform() * 4.0).floor());
                (fy, fx, uniform() * std::f64::consts::TAU)
            })
            .collect();
        let (lo, hi) = range(c);
        for (y, row) in grid.iter_mut().enumerate() {
            for (x, cell) in row.iter_mut().enumerate() {
                let s: f64 = waves
                    .iter()
                    .map(|(fy, fx, p)| {
                        (std::f64::consts::TAU * (fy * y as f64 + fx * x as f64) / G as f64 + p)
                            .cos()
                    })
                    .sum();
                cell[c] = q15(lo + (hi - lo) * (0.5 + s / 6.0), c);
            }
        }
    }
    grid
}

/// `grid` moved by `(dy, dx)` cells (wrapping), plus uniform noise of `noise` (units of
/// 1.0), clamped to the channels' ranges.
fn moved(grid: &Grid, dy: usize, dx: usize, noise: f64, rng: &mut Rng) -> Box<Grid> {
    let mut out = Box::new([[[0i16; CHANNELS]; G]; G]);
    for (y, row) in out.iter_mut().enumerate() {
        for (x, cell) in row.iter_mut().enumerate() {
            let from = grid[(y + G - dy) % G][(x + G - dx) % G];
            for (c, v) in cell.iter_mut().enumerate() {
                let n = noise * (rng.next_u32() as f64 / 2_147_483_648.0 - 1.0);
                *v = q15(from[c] as f64 / 32_768.0 + n, c);
            }
        }
    }
    out
}

/// The reference's windowed features of `grid`, channel-major.
fn reference_features(grid: &Grid) -> Features {
    let mut data = vec![0.0; CHANNELS * G * G];
    for (y, row) in grid.iter().enumerate() {
        for (x, cell) in row.iter().enumerate() {
            for (c, v) in cell.iter().enumerate() {
                data[(c * G + y) * G + x] = *v as f64 / 32_768.0;
            }
        }
    }
    Features {
        cols: G,
        rows: G,
        channels: CHANNELS,
        data,
    }
    .windowed(&cosine_window(G, G))
}

fn argmax(values: impl Iterator<Item = f64>) -> usize {
    values
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or(0, |(i, _)| i)
}

/// Trains both filters on `first`, then for each frame responds to it and learns it: the
/// largest absolute error of the response over all frames.
fn run(sigma: f64, first: &Grid, frames: &[(Box<Grid>, (f64, f64), f64)]) -> f64 {
    let settings = FilterSettings {
        sigma: Q16::from_f64(sigma),
        lambda: 1_073_742,
    };
    let lambda = settings.lambda as f64 / (1u64 << 30) as f64;
    let mut filter = Box::new(Filter::<G>::new(settings, first));
    let mut reference = F64Filter::new(&reference_features(first), sigma, lambda);
    let mut out = Box::new([[0i32; G]; G]);
    let mut worst = 0f64;
    for (t, (grid, shift, rate)) in frames.iter().enumerate() {
        filter.respond(grid, &mut out);
        let spectra = reference.spectra(&reference_features(grid));
        let want = reference.response(&spectra);
        let got: Vec<f64> = out
            .as_flattened()
            .iter()
            .map(|&v| v as f64 / 65_536.0)
            .collect();
        let error = got
            .iter()
            .zip(&want)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let (pg, pw) = (argmax(got.iter().copied()), argmax(want.iter().copied()));
        println!(
            "sigma {sigma} frame {t}: peak {:.4} at {:?} (reference {:.4} at {:?}), error {error:.2e}",
            got[pg],
            (pg / G, pg % G),
            want[pw],
            (pw / G, pw % G)
        );
        assert_eq!(pg, pw, "sigma {sigma} frame {t}: peaks differ");
        worst = worst.max(error);
        let (dy, dx) = (Q16::from_f64(shift.0), Q16::from_f64(shift.1));
        let rate = Q16::from_f64(*rate);
        filter.learn((dy, dx), rate);
        reference.learn(&spectra, (dy.to_f64(), dx.to_f64()), rate.to_f64());
    }
    worst
}

/// Frames of `base` moved by a few cells with noise, learnt with fractional shifts.
fn frames(base: &Grid, rng: &mut Rng) -> Vec<(Box<Grid>, (f64, f64), f64)> {
    let moves = [
        (0, 0),
        (1, 2),
        (31, 30),
        (3, 0),
        (0, 29),
        (2, 2),
        (30, 1),
        (1, 31),
    ];
    let rates = [0.1, 0.05, 0.01, 0.1, 0.02, 0.1, 0.05, 0.01];
    moves
        .iter()
        .zip(rates)
        .enumerate()
        .map(|(t, (&(dy, dx), rate))| {
            let shift = (0.37 * t as f64 - 1.1, 0.8 - 0.29 * t as f64);
            (moved(base, dy, dx, 0.02, rng), shift, rate)
        })
        .collect()
}

#[test]
fn the_integer_filter_answers_as_the_f64_reference() {
    let mut rng = Rng::new(29);
    let mut worst = 0f64;
    for sigma in [1.0, 2.0] {
        for smooth in [false, true] {
            let base = if smooth {
                smooth_grid(&mut rng)
            } else {
                random_grid(&mut rng)
            };
            let frames = frames(&base, &mut rng);
            let error = run(sigma, &base, &frames);
            println!("sigma {sigma}, smooth {smooth}: largest error {error:.2e}");
            worst = worst.max(error);
        }
    }
    println!("largest response error: {worst:.2e} of 1.0");
    assert!(worst < 0.01, "largest error {worst}");
}
