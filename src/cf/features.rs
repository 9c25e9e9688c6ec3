//! Per-cell features of a region of the frame resampled to a grid of cells: the cell's
//! mean luma and Felzenszwalb's 9 unsigned orientation channels (fHOG), in Q15.

use crate::fixed::Q16;
use crate::image::{ImageView, PixelFormat};

/// Channels per cell: `[0]` the mean luma, `[1..10]` the 9 unsigned fHOG channels.
pub const CHANNELS: usize = 10;

/// One cell's features, Q15 (32,768 stands for 1): `[0]` mean luma `/ 255 - 1/2`,
/// `[1..10]` unsigned fHOG (each in `[0, 0.4]`).
pub type Cell = [i16; CHANNELS];

/// Largest grid side, cells.
pub const MAX_CELLS: usize = 64;

/// A region of the frame resampled to `cols x rows` cells of `cell x cell` px.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampling {
    /// Region centre, px (pixel centres at integer coordinates), Q16.16.
    pub cx: Q16,
    /// Region centre, px, Q16.16.
    pub cy: Q16,
    /// Region width in the frame, px, Q16.16.
    pub width: Q16,
    /// Region height in the frame, px, Q16.16.
    pub height: Q16,
    /// Cells across, `1..=MAX_CELLS`.
    pub cols: usize,
    /// Cells down, `1..=MAX_CELLS`.
    pub rows: usize,
    /// Cell side, px of the resampled patch, `1..=8`.
    pub cell: usize,
}

/// Fills `out[y * cols + x]` with the features of cell `(x, y)`; returns the frame pixels
/// read.
pub fn extract<P: PixelFormat>(
    frame: &ImageView<'_, P>,
    sampling: &Sampling,
    out: &mut [Cell],
) -> u32 {
    let _ = (frame, sampling, out);
    0
}
