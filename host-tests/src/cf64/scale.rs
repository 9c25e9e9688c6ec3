//! The scale filter (DSST, Danelljan et al., BMVC 2014): a 1-D correlation filter over a
//! pyramid of `S` scaled copies of the target.
//!
//! Sample `s` is the target's box times `step^(ceil(S / 2) - 1 - s)` (`s` from 0), resampled
//! to a fixed model size of at most `area` px in whole cells ([`model_size`]), described by
//! its fHOG cells flattened into
//! one column of `D` values, optionally weighted by a Hann window over the scales. Per
//! feature `d`, `X_d` is the 1-D transform of its row over the scales; the filter keeps
//! `A_d <- (1 - eta) A_d + eta Y conj(X_d)` and `B <- (1 - eta) B + eta sum_d |X_d|^2`,
//! `Y` the transform of a Gaussian over the scales peaked at the sample of the target's size
//! (the middle one for samples taken at that size); a new sample `Z` answers
//! `IFFT(sum_d A_d Z_d / (B + lambda))`, peaked at the scale the target now has.

use super::fft::{Fft1, C64};
use super::fhog::{features, Gradients, Hog};
use super::filter::hann;
use super::image::{Resample, RgbImage};

/// Settings of the scale filter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScaleParams {
    /// Scales in the pyramid.
    pub scales: usize,
    /// Ratio between neighbouring scales.
    pub step: f64,
    /// Width of the desired response, as a share of `sqrt(scales)` (in scales).
    pub sigma: f64,
    /// Largest model size, px^2.
    pub area: f64,
    /// fHOG cell, px.
    pub cell: usize,
    /// fHOG channels.
    pub hog: Hog,
    /// fHOG's per-pixel definition.
    pub gradients: Gradients,
    /// Regulariser.
    pub lambda: f64,
    /// Weigh the samples by a Hann window over the scales.
    pub window: bool,
    /// fHOG gradients of the luma alone.
    pub luma: bool,
    /// How the samples read the frame.
    pub resample: Resample,
}

/// Most cells of a sample, as the core's ([`rbtrack::cf::scale::MAX_CELLS`]).
const MAX_CELLS: usize = rbtrack::cf::scale::MAX_CELLS;

/// The model of a first box of `size` px: each side times `sqrt(area / (w h))` where that
/// shrinks it, else grown (up to that) until the shorter side is 3 cells; in whole cells
/// (at least 2), at most [`MAX_CELLS`] cells (the longer side cut to `MAX_CELLS` over the
/// other's cells, that at most half of them), px.
pub fn model_size(params: &ScaleParams, size: (f64, f64)) -> (usize, usize) {
    let (w, h) = size;
    let fit = (params.area / (w * h)).sqrt();
    let shorter = w.min(h);
    let least = (3 * params.cell) as f64;
    let side = |v: f64| match fit < 1.0 {
        true => v * fit,
        false if shorter >= least => v,
        false => (v * least / shorter).min(v * fit),
    };
    let cells = |v: f64| (side(v) as usize / params.cell).max(2);
    let (cols, rows) = (cells(w), cells(h));
    let (cols, rows) = if cols * rows <= MAX_CELLS {
        (cols, rows)
    } else if cols >= rows {
        let rows = rows.min(MAX_CELLS / 2);
        (MAX_CELLS / rows, rows)
    } else {
        let cols = cols.min(MAX_CELLS / 2);
        (cols, MAX_CELLS / cols)
    };
    (cols * params.cell, rows * params.cell)
}

/// The scale filter.
#[derive(Clone)]
pub struct ScaleFilter {
    params: ScaleParams,
    /// Factor of sample `s` on the current size.
    factors: Vec<f64>,
    window: Vec<f64>,
    /// Model size, px (width, height), whole cells.
    model: (usize, usize),
    fft: Fft1,
    /// Numerator, feature-major: `num[d * S + s]`.
    num: Vec<C64>,
    den: Vec<f64>,
}

impl ScaleFilter {
    /// A filter for a target of `size` px (width, height), trained on `frame` at `centre`.
    pub fn new(
        params: ScaleParams,
        frame: &RgbImage,
        centre: (f64, f64),
        size: (f64, f64),
    ) -> Self {
        let s = params.scales;
        let mid = s.div_ceil(2) as f64 - 1.0;
        let factors = (0..s).map(|i| params.step.powf(mid - i as f64)).collect();
        let model = model_size(&params, size);
        let mut filter = Self {
            params,
            factors,
            window: if params.window { hann(s) } else { vec![1.0; s] },
            model,
            fft: Fft1::new(s),
            num: Vec::new(),
            den: vec![0.0; s],
        };
        let x = filter.sample(frame, centre, size);
        filter.num = vec![C64::default(); x.len()];
        filter.learn(&x, filter.middle(), 1.0);
        filter
    }

    /// Scale factor of each sample.
    pub fn factors(&self) -> &[f64] {
        &self.factors
    }

    /// The samples at `centre` for a target of `size` px: their features, `D x S`,
    /// feature-major, each row transformed along the scales: what
    /// [`ScaleFilter::response`] and [`ScaleFilter::learn`] take.
    pub fn sample(&self, frame: &RgbImage, centre: (f64, f64), size: (f64, f64)) -> Vec<C64> {
        let s = self.params.scales;
        let mut columns = Vec::with_capacity(s);
        for (&f, &w) in self.factors.iter().zip(&self.window) {
            let extent = ((size.0 * f).max(2.0), (size.1 * f).max(2.0));
            let resample = self.params.resample;
            let patch = match self.params.luma {
                true => frame.luma_patch(centre, extent, self.model, resample),
                false => frame.patch(centre, extent, self.model, resample),
            };
            let feat = features(
                &patch,
                self.params.cell,
                self.params.hog,
                false,
                self.params.gradients,
            );
            columns.push(feat.data.into_iter().map(|v| v * w).collect::<Vec<_>>());
        }
        let d = columns[0].len();
        let mut out = vec![C64::default(); d * s];
        for (i, row) in out.chunks_mut(s).enumerate() {
            for (v, column) in row.iter_mut().zip(&columns) {
                *v = C64::new(column[i], 0.0);
            }
            self.fft.forward(row);
        }
        out
    }

    /// The response over the scales to the samples `z`: one value per factor of
    /// [`ScaleFilter::factors`].
    pub fn response(&self, z: &[C64]) -> Vec<f64> {
        let s = self.params.scales;
        let mut sum = vec![C64::default(); s];
        for (zr, ar) in z.chunks(s).zip(self.num.chunks(s)) {
            for ((t, z), a) in sum.iter_mut().zip(zr).zip(ar) {
                *t += a * z;
            }
        }
        for (t, d) in sum.iter_mut().zip(&self.den) {
            *t /= d + self.params.lambda;
        }
        self.fft.inverse(&mut sum);
        sum.into_iter().map(|v| v.re).collect()
    }

    /// Learns the samples `x` at rate `eta`, the target's size being that of sample
    /// `at` (the desired response peaked there; the middle one is the size they were
    /// taken for).
    pub fn learn(&mut self, x: &[C64], at: usize, eta: f64) {
        let s = self.params.scales;
        let label = self.label_at(at);
        let mut den = vec![0.0; s];
        for (row, num) in x.chunks(s).zip(self.num.chunks_mut(s)) {
            for (((v, y), d), a) in row.iter().zip(&label).zip(&mut den).zip(num) {
                *a = (1.0 - eta) * *a + eta * y * v.conj();
                *d += v.norm_sqr();
            }
        }
        for (a, b) in self.den.iter_mut().zip(den) {
            *a = (1.0 - eta) * *a + eta * b;
        }
    }

    /// The desired response's transform, peaked at sample `at`.
    fn label_at(&self, at: usize) -> Vec<C64> {
        let sigma = (self.params.scales as f64).sqrt() * self.params.sigma;
        let mut label: Vec<C64> = (0..self.params.scales)
            .map(|i| {
                let d = i as f64 - at as f64;
                C64::new((-0.5 * d * d / (sigma * sigma)).exp(), 0.0)
            })
            .collect();
        self.fft.forward(&mut label);
        label
    }

    /// The index of the middle sample (factor 1).
    pub fn middle(&self) -> usize {
        self.params.scales.div_ceil(2) - 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 200 x 200 frame with a textured disc of radius `r` px centred on (100, 100).
    fn frame(r: f64) -> Vec<u8> {
        (0..200 * 200)
            .flat_map(|i| {
                let (x, y) = ((i % 200) as f64 - 100.0, (i / 200) as f64 - 100.0);
                let d = (x * x + y * y).sqrt() / r;
                let v = if d < 1.0 {
                    (128.0 + 100.0 * (d * 9.0).cos() * (y.atan2(x) * 3.0).sin()) as u8
                } else {
                    40
                };
                [v, v, v]
            })
            .collect()
    }

    #[test]
    fn a_scaled_target_peaks_at_its_scale() {
        let params = ScaleParams {
            scales: 33,
            step: 1.02,
            sigma: 0.25,
            area: 32.0 * 16.0,
            cell: 4,
            hog: Hog::Fhog31,
            gradients: Gradients::default(),
            lambda: 1e-2,
            window: true,
            luma: false,
            resample: Resample::Area,
        };
        let base = frame(30.0);
        fn img(rgb: &[u8]) -> RgbImage<'_> {
            RgbImage {
                width: 200,
                height: 200,
                rgb,
            }
        }
        let filter = ScaleFilter::new(params, &img(&base), (100.0, 100.0), (60.0, 60.0));
        let best = |r: Vec<f64>| {
            let i = (0..r.len())
                .max_by(|&a, &b| r[a].total_cmp(&r[b]))
                .unwrap_or(0);
            filter.factors()[i]
        };
        let respond =
            |rgb: &[u8]| filter.response(&filter.sample(&img(rgb), (100.0, 100.0), (60.0, 60.0)));
        assert_eq!(best(respond(&base)), 1.0);
        for grown in [1.06, 1.1, 0.92] {
            let found = best(respond(&frame(30.0 * grown)));
            assert!(
                (found / grown - 1.0).abs() < 0.025,
                "grown {grown}: found {found}"
            );
        }
    }
}
