//! The multi-channel correlation filter in closed form (Bolme et al. 2010; Danelljan et al.
//! 2014; Staple, Bertinetto et al. 2016), over a `rows x cols` grid of cells.
//!
//! With `X_l` the 2-D transform of channel `l` of the windowed features of a training
//! patch, `Y` that of the desired response (a Gaussian peak at the origin) and `n` the
//! cells, the filter keeps a running numerator per channel and one shared denominator:
//!
//! `A_l <- (1 - eta) A_l + eta conj(Y) X_l / n`, `B <- (1 - eta) B + eta sum_l |X_l|^2 / n`.
//!
//! A new patch's features `Z_l` give the response
//! `r = IFFT(sum_l conj(A_l) Z_l / (B + lambda))`, whose peak is where the trained pattern
//! moved: cell `(y, x)` of `r` is a move of `(y, x)` cells, wrapping (the last row is one
//! cell up).

use super::fft::{Fft2, C64};
use super::fhog::Features;

/// The translation filter.
#[derive(Clone)]
pub struct Filter {
    rows: usize,
    cols: usize,
    fft: Fft2,
    /// Transform of the desired response.
    label: Vec<C64>,
    /// Numerator per channel, channel-major.
    num: Vec<C64>,
    /// Shared denominator.
    den: Vec<f64>,
    /// Regulariser added to the denominator.
    lambda: f64,
}

/// A Gaussian of `sigma` cells centred on cell `(0, 0)` of a `rows x cols` grid, wrapping.
pub fn gaussian_label(rows: usize, cols: usize, sigma: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(rows * cols);
    for y in 0..rows {
        for x in 0..cols {
            let (dy, dx) = (wrap(y, rows) as f64, wrap(x, cols) as f64);
            out.push((-(dy * dy + dx * dx) / (2.0 * sigma * sigma)).exp());
        }
    }
    out
}

/// Cell index `i` of `n` as a signed move in `[-n / 2, n / 2)`.
pub fn wrap(i: usize, n: usize) -> i64 {
    let i = i as i64;
    let n = n as i64;
    if i < (n + 1) / 2 {
        i
    } else {
        i - n
    }
}

/// A Hann window of `n` points without zeros: `0.5 (1 - cos(2 pi (k + 1) / (n + 1)))`.
pub fn hann(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| 0.5 * (1.0 - (std::f64::consts::TAU * (k + 1) as f64 / (n + 1) as f64).cos()))
        .collect()
}

/// The separable cosine window of a `rows x cols` grid.
pub fn cosine_window(rows: usize, cols: usize) -> Vec<f64> {
    let (wy, wx) = (hann(rows), hann(cols));
    wy.iter()
        .flat_map(|a| wx.iter().map(move |b| a * b))
        .collect()
}

impl Filter {
    /// A filter trained on one patch's windowed features `x`, with the desired response
    /// a Gaussian of `sigma` cells and regulariser `lambda`.
    pub fn new(x: &Features, sigma: f64, lambda: f64) -> Self {
        let fft = Fft2::new(x.rows, x.cols);
        let label = fft.forward_real(&gaussian_label(x.rows, x.cols, sigma));
        let cells = x.rows * x.cols;
        let mut filter = Self {
            rows: x.rows,
            cols: x.cols,
            fft,
            label,
            num: vec![C64::default(); x.channels * cells],
            den: vec![0.0; cells],
            lambda,
        };
        let spectra = filter.spectra(x);
        filter.learn(&spectra, (0.0, 0.0), 1.0);
        filter
    }

    /// The 2-D transforms of the channels of the windowed features `x`, channel-major:
    /// what [`Filter::response`] and [`Filter::learn`] take.
    pub fn spectra(&self, x: &Features) -> Vec<C64> {
        (0..x.channels)
            .flat_map(|c| self.fft.forward_real(x.channel(c)))
            .collect()
    }

    /// Learns the patch whose spectra are `x` at rate `eta`, the target lying `(dy, dx)`
    /// cells from the patch's centre (the desired response's peak moved there).
    pub fn learn(&mut self, x: &[C64], shift: (f64, f64), eta: f64) {
        let cells = self.rows * self.cols;
        let n = cells as f64;
        let label = self.shifted_label(shift);
        for (num, spectrum) in self.num.chunks_mut(cells).zip(x.chunks(cells)) {
            for ((a, s), y) in num.iter_mut().zip(spectrum).zip(&label) {
                *a = (1.0 - eta) * *a + eta * y.conj() * s / n;
            }
        }
        for (i, d) in self.den.iter_mut().enumerate() {
            let energy: f64 = x.chunks(cells).map(|s| s[i].norm_sqr()).sum();
            *d = (1.0 - eta) * *d + eta * energy / n;
        }
    }

    /// The desired response's transform with its peak at `(dy, dx)` cells: times the phase
    /// ramp `e^(-2 pi i (u dy / rows + v dx / cols))`.
    fn shifted_label(&self, (dy, dx): (f64, f64)) -> Vec<C64> {
        if dy == 0.0 && dx == 0.0 {
            return self.label.clone();
        }
        let tau = std::f64::consts::TAU;
        (0..self.rows * self.cols)
            .map(|i| {
                let (u, v) = (
                    wrap(i / self.cols, self.rows),
                    wrap(i % self.cols, self.cols),
                );
                let phase =
                    -tau * (u as f64 * dy / self.rows as f64 + v as f64 * dx / self.cols as f64);
                self.label[i] * C64::from_polar(1.0, phase)
            })
            .collect()
    }

    /// The response to the patch whose spectra are `z`: one value per cell, row-major.
    pub fn response(&self, z: &[C64]) -> Vec<f64> {
        let cells = self.rows * self.cols;
        let mut sum = vec![C64::default(); cells];
        for (spectrum, num) in z.chunks(cells).zip(self.num.chunks(cells)) {
            for ((s, a), z) in sum.iter_mut().zip(num).zip(spectrum) {
                *s += a.conj() * z;
            }
        }
        for (s, d) in sum.iter_mut().zip(&self.den) {
            *s /= d + self.lambda;
        }
        self.fft.inverse_real(sum)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Features of one channel: a smooth random-looking pattern shifted by `(dy, dx)`
    /// cells (wrapping).
    fn pattern(rows: usize, cols: usize, dy: usize, dx: usize) -> Features {
        let value = |y: usize, x: usize| {
            let (y, x) = ((y + rows - dy) % rows, (x + cols - dx) % cols);
            ((y * 7 + x * 13) % 17) as f64 / 17.0 + ((x * y) % 5) as f64 / 10.0
        };
        let data = (0..rows)
            .flat_map(|y| (0..cols).map(move |x| value(y, x)))
            .collect();
        Features {
            cols,
            rows,
            channels: 1,
            data,
        }
    }

    fn peak(r: &[f64], cols: usize) -> (usize, usize) {
        let i = (0..r.len())
            .max_by(|&a, &b| r[a].total_cmp(&r[b]))
            .unwrap_or(0);
        (i / cols, i % cols)
    }

    #[test]
    fn a_shifted_pattern_moves_the_peak_by_the_shift() {
        let filter = Filter::new(&pattern(16, 32, 0, 0), 1.0, 1e-4);
        let respond = |x: &Features| filter.response(&filter.spectra(x));
        let r = respond(&pattern(16, 32, 0, 0));
        assert_eq!(peak(&r, 32), (0, 0));
        assert!((r[0] - 1.0).abs() < 0.05, "peak {}", r[0]);
        for (dy, dx) in [(3, 5), (15, 1), (8, 30)] {
            let r = respond(&pattern(16, 32, dy, dx));
            assert_eq!(peak(&r, 32), (dy, dx));
        }
    }

    #[test]
    fn learning_moves_the_model_towards_the_new_patch() {
        let a = pattern(8, 8, 0, 0);
        let b = pattern(8, 8, 2, 3);
        let mut filter = Filter::new(&a, 1.0, 1e-4);
        let (sa, sb) = (filter.spectra(&a), filter.spectra(&b));
        for _ in 0..200 {
            filter.learn(&sb, (0.0, 0.0), 0.1);
        }
        // Fully adapted to b: b answers at the origin, a at minus the shift.
        assert_eq!(peak(&filter.response(&sb), 8), (0, 0));
        assert_eq!(peak(&filter.response(&sa), 8), (6, 5));
    }

    #[test]
    fn learning_with_a_moved_peak_equals_learning_the_moved_pattern() {
        // The pattern shifted by (2, 3) learnt as the target at (2, 3) trains the same
        // filter as the unshifted pattern learnt at the centre.
        let a = pattern(8, 8, 0, 0);
        let moved = pattern(8, 8, 2, 3);
        let mut centred = Filter::new(&a, 1.0, 1e-4);
        let mut shifted = centred.clone();
        centred.learn(&centred.spectra(&a), (0.0, 0.0), 1.0);
        shifted.learn(&shifted.spectra(&moved), (2.0, 3.0), 1.0);
        let probe = centred.spectra(&pattern(8, 8, 1, 6));
        let (r1, r2) = (centred.response(&probe), shifted.response(&probe));
        for (x, y) in r1.iter().zip(&r2) {
            assert!((x - y).abs() < 1e-9);
        }
    }

    #[test]
    fn wrap_gives_signed_moves() {
        assert_eq!(
            [0, 1, 7, 8, 9, 15].map(|i| wrap(i, 16)),
            [0, 1, 7, -8, -7, -1]
        );
        assert_eq!([0, 2, 3, 4].map(|i| wrap(i, 5)), [0, 2, -2, -1]);
    }

    #[test]
    fn the_window_is_symmetric_and_positive() {
        let w = hann(8);
        for k in 0..8 {
            assert!(w[k] > 0.0);
            assert!((w[k] - w[7 - k]).abs() < 1e-12);
        }
    }
}
