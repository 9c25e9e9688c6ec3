//! Discrete Fourier transforms in f64 (rustfft): 2-D over a `rows x cols` grid and 1-D,
//! forward unnormalised, inverse divided by the number of points, so that `inverse(forward(x))
//! = x`.

use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};
use std::sync::Arc;

/// A complex number of f64.
pub type C64 = Complex64;

/// Forward and inverse transforms of one length.
#[derive(Clone)]
pub struct Fft1 {
    forward: Arc<dyn Fft<f64>>,
    inverse: Arc<dyn Fft<f64>>,
}

impl Fft1 {
    /// Transforms of `n` points.
    pub fn new(n: usize) -> Self {
        let mut planner = FftPlanner::new();
        Self {
            forward: planner.plan_fft_forward(n),
            inverse: planner.plan_fft_inverse(n),
        }
    }

    /// Points per transform.
    pub fn len(&self) -> usize {
        self.forward.len()
    }

    /// Whether it transforms nothing.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The forward transform of `data` in place, `sum_k x_k e^(-2 pi i j k / n)`.
    pub fn forward(&self, data: &mut [C64]) {
        self.forward.process(data);
    }

    /// The inverse transform of `data` in place, divided by `n`.
    pub fn inverse(&self, data: &mut [C64]) {
        self.inverse.process(data);
        let n = self.len() as f64;
        for v in data {
            *v /= n;
        }
    }
}

/// 2-D transforms of a `rows x cols` grid, row-major: the rows' transforms, then the
/// columns'.
#[derive(Clone)]
pub struct Fft2 {
    rows: Fft1,
    cols: Fft1,
}

impl Fft2 {
    /// Transforms of `rows x cols` grids.
    pub fn new(rows: usize, cols: usize) -> Self {
        Self {
            rows: Fft1::new(cols),
            cols: Fft1::new(rows),
        }
    }

    fn apply(&self, data: &mut [C64], one: impl Fn(&Fft1, &mut [C64])) {
        let (cols, rows) = (self.rows.len(), self.cols.len());
        for row in data.chunks_mut(cols) {
            one(&self.rows, row);
        }
        let mut column = vec![C64::default(); rows];
        for x in 0..cols {
            for (y, v) in column.iter_mut().enumerate() {
                *v = data[y * cols + x];
            }
            one(&self.cols, &mut column);
            for (y, v) in column.iter().enumerate() {
                data[y * cols + x] = *v;
            }
        }
    }

    /// The forward 2-D transform of a real grid.
    pub fn forward_real(&self, grid: &[f64]) -> Vec<C64> {
        let mut data: Vec<C64> = grid.iter().map(|&v| C64::new(v, 0.0)).collect();
        self.apply(&mut data, Fft1::forward);
        data
    }

    /// The inverse 2-D transform's real part (the grid of a real signal's spectrum).
    pub fn inverse_real(&self, mut spectrum: Vec<C64>) -> Vec<f64> {
        self.apply(&mut spectrum, Fft1::inverse);
        spectrum.into_iter().map(|v| v.re).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forward_then_inverse_is_the_identity() {
        let fft = Fft2::new(4, 8);
        let grid: Vec<f64> = (0..32).map(|i| ((i * 7) % 11) as f64 - 3.0).collect();
        let back = fft.inverse_real(fft.forward_real(&grid));
        for (a, b) in grid.iter().zip(&back) {
            assert!((a - b).abs() < 1e-12);
        }
    }

    #[test]
    fn the_transform_is_the_direct_sum() {
        let (rows, cols) = (4, 8);
        let fft = Fft2::new(rows, cols);
        let grid: Vec<f64> = (0..32).map(|i| ((i * 5) % 9) as f64).collect();
        let spectrum = fft.forward_real(&grid);
        for (u, v) in [(0, 0), (1, 3), (3, 7), (2, 4)] {
            let mut sum = C64::default();
            for y in 0..rows {
                for x in 0..cols {
                    let phase = -std::f64::consts::TAU
                        * ((u * y) as f64 / rows as f64 + (v * x) as f64 / cols as f64);
                    sum += grid[y * cols + x] * C64::from_polar(1.0, phase);
                }
            }
            assert!((spectrum[u * cols + v] - sum).norm() < 1e-9, "({u}, {v})");
        }
    }
}
