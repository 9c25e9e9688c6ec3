//! What a configuration of the integer correlation-filter tracker costs a frame on a
//! Cortex-M4: the operations each stage of `CfTracker::step_profiled` does, counted from
//! the configuration and the target, times per-operation instruction costs fitted to the
//! QEMU counts of `examples/budget.rs` (`rbtrack cost BUDGET_OUTPUT --fit` fits them,
//! `rbtrack cost BUDGET_OUTPUT` checks every row against them).
//!
//! Counted for a frame while tracking (no re-detection). The operations:
//! - features: the search patch's px (`(G cell)^2`), its cells times their fHOG channels
//!   (normalised one by one), the frame rows it touches (every row of the region, at most
//!   2 a patch row) times the patch columns (each row interpolated across once) and times
//!   the pixels read of each (the region's width, at most 2 a patch column), and a
//!   constant;
//! - filter: the butterflies of the 2-D transforms (the channels in complex pairs and one
//!   inverse, `G^2 log2 G` each) and the cells times the channels (the response's
//!   products);
//! - colour: the colour map's px (`(G cell / colour_step)^2`) and a constant;
//! - scale: per sample, its px (the scale model's, fixed by the first box; its features'
//!   transforms and products go with them, as the core's samples have 9 channels a cell)
//!   and a constant; the frame pixels the samples read, as runs and one by one (as for
//!   the patch);
//! - learning: the cells times the channels (the filter's numerator and denominator), the
//!   scale filter's feature pairs times the scales, and a constant.

use super::params::Params;
use super::scale::model_size;
use super::tracker::scale_params;
use serde::Serialize;

/// The stages of a frame, as `CfStageCycles` counts them.
pub const STAGES: [&str; 5] = ["features", "filter", "colour", "scale", "learn"];

/// Instructions an operation, per stage, in the order of [`Operations::terms`]' terms:
/// least squares on the relative error over the rows of `examples/budget.rs` in QEMU
/// (`rbtrack cost BUDGET_OUTPUT --fit`).
pub const PER_OPERATION: [&[f64]; 5] = [
    &[112.1, 77.2, 16.8, 9.0, 21_844.7],
    &[27.0, 41.4],
    &[105.0, 7_936.4],
    &[256.1, 15.3, 25.8, 8_537.1],
    &[50.6, 67.7, 28_308.1],
];

/// The target the cost depends on: its first box, px (width, height), which fixes the
/// scale model, and its size on the frames costed, px, which sets the frame rows read.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Target {
    /// The first box, px (width, height).
    pub first: (f64, f64),
    /// The size on the frames costed, px (width, height).
    pub current: (f64, f64),
}

impl Target {
    /// The budget example's scene (`rbtrack_firmware::scene`) with its target scaled by
    /// `scale`: a first box of 11.375 x 26 px, 23.625 x 54 px on the mean frame.
    pub fn scene(scale: f64) -> Self {
        Self {
            first: (11.375 * scale, 26.0 * scale),
            current: (23.625 * scale, 54.0 * scale),
        }
    }

    /// This target with its box `height` px tall on the frames costed, its sides in the
    /// same ratio: the tracker's own box sets the frame rows read.
    pub fn tracked(self, height: f64) -> Self {
        let (w, h) = self.current;
        Self {
            current: (w * height / h, height),
            ..self
        }
    }
}

/// The reference's settings for a row of the budget example (`examples/budget.rs`): the
/// integer tracker's defaults with a `grid x grid` grid, `scales` scales, cells of `cell`
/// px, a scale model of at most `area` px^2 and `ring` re-detection regions.
pub fn budget_row(grid: usize, scales: usize, cell: usize, area: u32, ring: usize) -> Params {
    let defaults = rbtrack::tracker::CfConfig::default();
    let config = rbtrack::tracker::CfConfig {
        cell,
        redetect: ring,
        scale: rbtrack::cf::scale::ScaleSettings {
            area,
            ..defaults.scale
        },
        ..defaults
    };
    Params::of_core(&config, grid, scales)
}

/// Operations of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Operations {
    /// Search patch px.
    pub patch_px: f64,
    /// Search grid cells.
    pub cells: f64,
    /// Channels of a cell: fHOG and grey.
    pub channels: f64,
    /// fHOG channels of a cell.
    pub hog_channels: f64,
    /// Frame rows the search patch touches times its columns: horizontal interpolations.
    pub patch_across: f64,
    /// Frame pixels read for the search patch.
    pub patch_reads: f64,
    /// Butterflies of the translation filter's 2-D transforms.
    pub butterflies: f64,
    /// Colour map px.
    pub colour_px: f64,
    /// Scale samples.
    pub samples: f64,
    /// Px of one scale sample.
    pub sample_px: f64,
    /// Frame pixels read as runs for the scale samples, all of them.
    pub sample_runs: f64,
    /// Frame pixels read one by one for the scale samples, all of them.
    pub sample_one_by_one: f64,
    /// Feature pairs of a scale sample.
    pub pairs: f64,
}

/// What resampling a region `region` px (width, height) into `cols x rows` patch px
/// costs: (frame rows touched times `cols`, the horizontal interpolations; frame pixels
/// read as runs; frame pixels read one by one). Each frame row touched (every row of the
/// region, at most 2 a patch row) is interpolated across once and read once: as one run
/// of the region's width where that is at most 2 a patch column, else 2 a patch column
/// one by one.
fn reads(region: (f64, f64), cols: f64, rows: f64) -> (f64, f64, f64) {
    let touched = (region.1.ceil() + 1.0).min(2.0 * rows);
    let span = region.0.ceil() + 1.0;
    match span <= 2.0 * cols {
        true => (touched * cols, touched * span, 0.0),
        false => (touched * cols, 0.0, touched * 2.0 * cols),
    }
}

impl Operations {
    /// The operations of `params`' configuration on `target`.
    pub fn of(params: &Params, target: Target) -> Self {
        let g = params.grid as f64;
        let side = g * params.cell as f64;
        let hog_channels = params.hog.channels() as f64;
        let channels = hog_channels + f64::from(u8::from(params.grey));
        let (w, h) = target.current;
        let pad = params.padding * (w + h) / 2.0;
        let (patch_across, runs, one_by_one) = reads((w + pad, h + pad), side, side);
        let mut ops = Self {
            patch_px: side * side,
            cells: g * g,
            channels,
            hog_channels,
            patch_across,
            patch_reads: runs + one_by_one,
            butterflies: ((channels / 2.0).ceil() + 1.0) * g * g * g.log2(),
            colour_px: (side / params.colour_step.max(1) as f64).powi(2),
            ..Self::default()
        };
        if params.scales > 0 {
            let (mw, mh) = model_size(&scale_params(params), target.first);
            let (mw, mh) = (mw as f64, mh as f64);
            let middle = params.scales.div_ceil(2) as f64 - 1.0;
            ops.samples = params.scales as f64;
            ops.sample_px = mw * mh;
            for s in 0..params.scales {
                let f = params.scale_step.powf(middle - s as f64);
                let (_, runs, one_by_one) = reads((w * f, h * f), mw, mh);
                ops.sample_runs += runs;
                ops.sample_one_by_one += one_by_one;
            }
            let cells = (mw * mh) / (params.scale_cell * params.scale_cell) as f64;
            ops.pairs = (cells * params.scale_hog.channels() as f64 / 2.0).ceil();
        }
        ops
    }

    /// Each stage's terms, in the order of [`PER_OPERATION`]'s costs.
    pub fn terms(&self) -> [Vec<f64>; 5] {
        let s = self.samples;
        [
            vec![
                self.patch_px,
                self.cells * self.hog_channels,
                self.patch_across,
                self.patch_reads,
                1.0,
            ],
            vec![self.butterflies, self.cells * self.channels],
            vec![self.colour_px, 1.0],
            vec![
                s * self.sample_px,
                self.sample_runs,
                self.sample_one_by_one,
                s,
            ],
            vec![self.cells * self.channels, self.pairs * s, 1.0],
        ]
    }

    /// Estimated Cortex-M4 instructions of each stage, by `costs` (per stage, per term).
    pub fn stages_by(&self, costs: &[&[f64]; 5]) -> [f64; 5] {
        let terms = self.terms();
        std::array::from_fn(|i| terms[i].iter().zip(costs[i]).map(|(t, c)| t * c).sum())
    }

    /// Estimated Cortex-M4 instructions of each stage ([`STAGES`]).
    pub fn stages(&self) -> [f64; 5] {
        self.stages_by(&PER_OPERATION)
    }

    /// Estimated Cortex-M4 instructions a frame.
    pub fn instructions(&self) -> u64 {
        self.stages().iter().sum::<f64>().round() as u64
    }
}

/// The costs of each term that fit `rows` (operations, measured instructions of the stage)
/// best in relative error (least squares on `1 - estimate / measured`), by the normal
/// equations; `None` where they are singular.
pub fn fit(rows: &[(Vec<f64>, f64)]) -> Option<Vec<f64>> {
    let n = rows.first()?.0.len();
    // A^T A x = A^T b over the rows scaled by 1 / measured.
    let mut m = vec![vec![0.0; n + 1]; n];
    for (terms, measured) in rows {
        let a: Vec<f64> = terms.iter().map(|t| t / measured).collect();
        for i in 0..n {
            for j in 0..n {
                m[i][j] += a[i] * a[j];
            }
            m[i][n] += a[i];
        }
    }
    // Gaussian elimination with partial pivoting.
    for col in 0..n {
        let pivot = (col..n).max_by(|&a, &b| m[a][col].abs().total_cmp(&m[b][col].abs()))?;
        if m[pivot][col].abs() < 1e-12 {
            return None;
        }
        m.swap(col, pivot);
        for row in 0..n {
            if row != col {
                let f = m[row][col] / m[col][col];
                let pivot_row = m[col].clone();
                for (v, p) in m[row].iter_mut().zip(&pivot_row) {
                    *v -= f * p;
                }
            }
        }
    }
    Some((0..n).map(|i| m[i][n] / m[i][i]).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cf64::fhog::Hog;

    #[test]
    fn a_16_cell_grid_counts_as_the_design_says() {
        // 10 channels: 5 pairs and an inverse, six 16 x 16 2-D transforms of 32 transforms
        // of 16 points, 32 butterflies each; grey alone, one pair and the inverse.
        let params = Params {
            grid: 16,
            cell: 4,
            colour_step: 2,
            hog: Hog::Unsigned9,
            grey: true,
            scales: 0,
            ..Params::default()
        };
        let ops = Operations::of(&params, Target::scene(1.0));
        assert_eq!(ops.butterflies, 6.0 * 32.0 * 32.0);
        assert_eq!(ops.patch_px, 64.0 * 64.0);
        assert_eq!(ops.colour_px, 32.0 * 32.0);
        assert_eq!(ops.samples, 0.0);
        let grey = Params {
            hog: Hog::Off,
            ..params
        };
        assert_eq!(
            Operations::of(&grey, Target::scene(1.0)).butterflies,
            2.0 * 32.0 * 32.0
        );
    }

    #[test]
    fn a_region_is_read_once_a_row_at_most_two_rows_a_patch_row() {
        // 64 x 64 patch px: a 30 px tall region touches 31 rows, a 300 px one 2 a patch
        // row; a row reads the region's width as a run, or 2 a patch column one by one.
        assert_eq!(
            reads((20.0, 30.0), 64.0, 64.0),
            (64.0 * 31.0, 21.0 * 31.0, 0.0)
        );
        assert_eq!(
            reads((300.0, 300.0), 64.0, 64.0),
            (64.0 * 128.0, 0.0, 128.0 * 128.0)
        );
    }

    #[test]
    fn the_fit_recovers_known_costs() {
        let costs = [3.0, 200.0, 5_000.0];
        let rows: Vec<(Vec<f64>, f64)> = [(100.0, 4.0), (400.0, 9.0), (50.0, 30.0), (900.0, 2.0)]
            .iter()
            .map(|&(a, b)| {
                let terms = vec![a, b, 1.0];
                let measured = terms.iter().zip(&costs).map(|(t, c)| t * c).sum();
                (terms, measured)
            })
            .collect();
        let fitted = fit(&rows).unwrap();
        for (f, c) in fitted.iter().zip(&costs) {
            assert!((f - c).abs() < 1e-6 * c, "{fitted:?}");
        }
        assert_eq!(fit(&[(vec![1.0, 2.0], 3.0), (vec![2.0, 4.0], 6.0)]), None);
    }
}
