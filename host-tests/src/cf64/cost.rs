//! What a configuration costs a frame: the operations the tracker does, counted from its
//! settings, and the Cortex-M4 instructions they come to at the per-operation costs of
//! the integer design (docs/design.md, "A shape template"): an estimate to choose the
//! microcontroller's configuration by, before the integer tracker measures itself in QEMU.
//!
//! Counted for a frame while tracking (no re-detection), for a target of the scale
//! filter's full sample area:
//! - resampled and featurised px: the search patch (twice with `fresh_patch`) and the
//!   scale samples (twice with `fresh_patch`);
//! - cells normalised: the search grid's and the scale samples';
//! - butterflies: the 2-D transforms of the channels (two real channels in one complex
//!   transform), once for detection and again with `fresh_patch`, and one inverse; the
//!   scale filter's transforms over the scales (`S/2 log2 S` butterflies for a power of two,
//!   else a direct transform of `S^2` complex products counted as MACs);
//! - complex multiply-accumulates: the response (one per cell and channel), the learning
//!   (numerator and denominator, two per cell and channel), and the scale filter's alike;
//! - colour px: the likelihood lookup, the integral image and the histograms' learning
//!   over the patch.

use super::params::Params;
use serde::Serialize;

/// Instructions a pixel to resample (read, weigh, sum the source pixels).
pub const RESAMPLE_PER_PX: u64 = 10;
/// Instructions a pixel for its gradient, orientation bin and cell vote.
pub const FEATURE_PER_PX: u64 = 15;
/// Instructions a cell and channel to normalise (four block norms, clip, sum).
pub const NORMALISE_PER_CELL_CHANNEL: u64 = 12;
/// Instructions a radix-2 butterfly (Q15, with its scaling).
pub const PER_BUTTERFLY: u64 = 12;
/// Instructions a complex multiply-accumulate.
pub const PER_MAC: u64 = 6;
/// Instructions a pixel for the colour work (bin, look up, add).
pub const COLOUR_PER_PX: u64 = 11;

/// Operations of one frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Operations {
    /// Pixels resampled and featurised.
    pub pixels: u64,
    /// Cell-channels normalised.
    pub cell_channels: u64,
    /// FFT butterflies.
    pub butterflies: u64,
    /// Complex multiply-accumulates.
    pub macs: u64,
    /// Pixels of colour work.
    pub colour_pixels: u64,
}

impl Operations {
    /// The operations of `params`' configuration.
    pub fn of(params: &Params) -> Self {
        let passes = if params.fresh_patch { 2 } else { 1 };
        let g = params.grid as u64;
        let side = g * params.cell as u64;
        let channels = (params.hog.channels() + usize::from(params.grey)) as u64;
        let cells = g * g;
        let fft2 = 2 * g * (g / 2) * u64::from(g.max(2).ilog2());
        let transforms = passes * channels.div_ceil(2) + 1;
        let mut ops = Self {
            pixels: passes * side * side,
            cell_channels: passes * cells * params.hog.channels() as u64,
            butterflies: transforms * fft2,
            macs: 3 * channels * cells,
            colour_pixels: 3 * (side / params.colour_step as u64).pow(2),
        };
        if params.scales > 0 {
            let s = params.scales as u64;
            let area = params.scale_area as u64;
            let scale_cells = area / (params.scale_cell * params.scale_cell) as u64;
            let rows = scale_cells * params.scale_hog.channels() as u64;
            ops.pixels += passes * s * area;
            ops.cell_channels += passes * s * rows;
            let transforms = passes * rows + 1;
            if s.is_power_of_two() {
                ops.butterflies += transforms * (s / 2) * u64::from(s.max(2).ilog2());
            } else {
                ops.macs += transforms * s * s;
            }
            ops.macs += 3 * rows * s;
        }
        ops
    }

    /// Estimated Cortex-M4 instructions.
    pub fn instructions(&self) -> u64 {
        self.pixels * (RESAMPLE_PER_PX + FEATURE_PER_PX)
            + self.cell_channels * NORMALISE_PER_CELL_CHANNEL
            + self.butterflies * PER_BUTTERFLY
            + self.macs * PER_MAC
            + self.colour_pixels * COLOUR_PER_PX
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cf64::fhog::Hog;

    #[test]
    fn a_16_cell_grid_counts_as_the_design_says() {
        // A 16 x 16 2-D transform: 16 + 16 transforms of 16 points, 32 butterflies each.
        let params = Params {
            grid: 16,
            cell: 4,
            hog: Hog::Off,
            grey: true,
            scales: 0,
            fresh_patch: false,
            ..Params::default()
        };
        let ops = Operations::of(&params);
        assert_eq!(ops.butterflies, 2 * 1024);
        assert_eq!(ops.pixels, 64 * 64);
        assert_eq!(ops.macs, 3 * 256);
        assert_eq!(ops.cell_channels, 0);
    }

    #[test]
    fn fresh_patches_double_the_pixels() {
        let once = Operations::of(&Params {
            fresh_patch: false,
            ..Params::default()
        });
        let twice = Operations::of(&Params {
            fresh_patch: true,
            ..Params::default()
        });
        assert_eq!(twice.pixels, 2 * once.pixels);
        assert!(twice.instructions() > once.instructions());
    }
}
