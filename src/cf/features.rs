//! Per-cell features of a region of the frame resampled to a grid of cells: the cell's
//! mean luma and Felzenszwalb's 9 unsigned orientation channels (fHOG), in Q15.
//!
//! The integer port of the host's f64 reference (`cf64::fhog::features` of
//! `RgbImage::luma_patch(..)`, grey channel and `Hog::Unsigned9`), in one pass over the
//! patch, row by row:
//! - **Resampling.** Patch pixel `i` of an axis is centred at `left + (i + 1/2) step` px
//!   of the frame, `step = size / out`, positions in Q32.32 (`step` rounded down, off by
//!   under `2^-23` px across the patch), and interpolated bilinearly between the 2 x 2
//!   source pixels nearest that centre (weights Q24), whether the axis shrinks or grows,
//!   as OpenCV's `INTER_LINEAR`. Source pixels outside the frame repeat its nearest
//!   edge. Each column's two source pixels (clamped) and weight are found once; the luma
//!   of both at the two frame rows of the last patch row is kept, so that a frame row is
//!   read once for all the patch rows between it and its neighbour: 4 reads a patch pixel
//!   where the region shrinks by 2 or more, 2 to 4 where by 1 to 2, at most 2 where it
//!   grows. The patch's luma is kept in Q8 (`1/256`).
//! - **Gradient.** Central differences of the patch luma (one-sided at its edge), Q9 luma
//!   per px; the magnitude by [`sqrt_u64_q8`] (no per-pixel division), Q13; the orientation
//!   folded into the upper half-plane and binned by integer cross products against the
//!   boundaries of the unsigned bins (10 + 20 k degrees, cos and sin in Q30; 2 or 3 of the
//!   4 in the first quadrant, the second quadrant's by mirror symmetry), which gives the
//!   reference's signed bin `o` modulo 9 (`o` and `o + 9` are opposite directions).
//! - **Histogram.** Each pixel's magnitude is spread bilinearly over its 4 nearest cells
//!   (weights in `1 / (2 cell)` each way, exact), in units of `2^-13 / (4 cell^4) 2^shift`
//!   luma (`shift = 2 ceil(log2 cell) + 1`, so a bin stays below `3.8e8`); the reference's
//!   division by `cell^2` is left out, as the normalisation cancels it (its `eps` is scaled
//!   to match).
//! - **Normalisation.** A finished cell row keeps each cell's `s = sqrt(energy)` (Q2 of
//!   the bin unit) and stores its bins as `t = bin / s` (Q15, in `out`, so the bins need
//!   no third row of storage); each 2x2 block of the edge-replicated grid gives
//!   `n = 1 / sqrt(sum of its 4 energies + eps)` by one integer square root and one
//!   division, and channel `o` of a cell is `1/2 sum over its 4 blocks of
//!   min(t_o s n, 0.2)`, Q31 before the final rounding.
//!
//! Error against the f64 reference (host test `cf_features`, Gray8 and RGB frames,
//! synthetic and real, 11 regions each: shrinking, growing, oblong, past the edge, cells of
//! 2 to 8 px), which reads the frame's 8-bit luma and keeps its patch to `1/256` as here:
//! the grey channel within `2.3e-5`, the fHOG channels within `9e-5` (mean `1.2e-5`). The
//! rounding to `1/256` is part of the definition: without it, mean `5e-5` to `2.2e-4`, with
//! 0.4 to 1.4 % of the values off by more than `1e-3` and a few by up to 0.4, where it
//! moves a pixel's gradient across a bin boundary and the pixel's share of a cell from one
//! channel to the next (a strong pixel in a weak block moves a whole clipped value).
//!
//! Working memory, on the stack, for a patch of at most 256 px a side: the columns' source
//! pixels and weights (`256 x 8` bytes) and the luma of two frame rows at them
//! (`2 x 256 x 2` u8), three patch rows (`3 x 258` u16: the row below is sampled before the
//! gradients of a row are taken; each row's edge pixels are repeated at either end, so
//! that one loop without bounds checks takes every difference), each column's two cells
//! and weights across (`256` u16, found once a patch), the histograms of two cell rows
//! (`2 x 34 x 9` u32: a pixel row reaches only the cell rows on either side of it, and a
//! padding cell at either end), three rows of root energies (`3 x 32` u32: a cell row's
//! normalisers need the rows above and below) and one row of block normalisers (`33` u64,
//! each computed once), 8,244 bytes; the luma sums of a cell row are kept in `out` until it
//! is complete. On the Cortex-M4 (thumbv7em, opt-level `s`) `extract`'s frame is 9,016
//! bytes.

use crate::fixed::{div_u64_u32, sqrt_u64_q8, Q16};
use crate::image::{ImageView, PixelFormat};

/// Channels per cell: `[0]` the mean luma, `[1..10]` the 9 unsigned fHOG channels.
pub const CHANNELS: usize = 10;

/// One cell's features, Q15 (32,768 stands for 1): `[0]` mean luma `/ 255 - 1/2`,
/// `[1..10]` unsigned fHOG (each in `[0, 0.4]`).
pub type Cell = [i16; CHANNELS];

/// Largest grid side, cells: the translation filter's grid (`G <= 32`) and the scale
/// filter's samples (at most 32 cells) fit.
pub const MAX_CELLS: usize = 32;

/// Largest cell side, px of the patch.
pub const MAX_CELL: usize = 8;

/// Widest patch, px.
const MAX_PX: usize = MAX_CELLS * MAX_CELL;

/// Unsigned orientation bins.
const BINS: usize = 9;

/// `(cos, sin)` of the boundaries between the unsigned bins in the first quadrant, 10, 30,
/// 50 and 70 degrees, Q30 (times a Q9 gradient below `2^18`, a cross product stays below
/// `2^49`); those of the second quadrant are their mirror images, `180 -` these.
const BOUNDARIES: [(u32, u32); 4] = [
    (1_057_429_273, 186_453_311),
    (929_887_697, 536_870_912),
    (690_187_940, 822_533_958),
    (367_241_333, 1_008_987_269),
];

/// A cell row's histograms, cell `x` at `x + 1`: cells -1 and `cols` (which pixels near
/// the grid's edge reach) are padding, so that a pixel's 4 shares need no test.
type HistRow = [[u32; BINS]; MAX_CELLS + 2];

/// Two empty cell rows of histograms (a constant, so that they are cleared in place).
const NO_HIST: [HistRow; 2] = [[[0; BINS]; MAX_CELLS + 2]; 2];

/// The clip of a normalised bin, 0.2, in Q31.
const CLIP: u32 = 429_496_730;

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
    /// Cell side, px of the resampled patch, `1..=MAX_CELL`.
    pub cell: usize,
}

/// Fills `out[y * cols + x]` with the features of cell `(x, y)` (see the module
/// documentation), reading `4 cols rows cell^2` frame pixels.
///
/// `cols`, `rows` are clamped into `1..=MAX_CELLS` and `cell` into `1..=MAX_CELL`; a
/// negative width or height counts as 0 (every patch pixel then interpolates at the
/// centre). Only the first `cols * rows` entries of `out` are written, and if `out` is
/// shorter, the cells that fit (the features of a cell do not depend on the length of
/// `out`).
pub fn extract<P: PixelFormat>(frame: &ImageView<'_, P>, sampling: &Sampling, out: &mut [Cell]) {
    let cols = sampling.cols.clamp(1, MAX_CELLS);
    let rows = sampling.rows.clamp(1, MAX_CELLS);
    let cell = sampling.cell.clamp(1, MAX_CELL);
    let (w, h) = (cols * cell, rows * cell);
    let grid = Grid::new(cols, rows, cell);
    let xs = Axis::new(sampling.cx, sampling.width, w);
    let mut ys = Axis::new(sampling.cy, sampling.height, h);

    let mut patch = [[0u16; MAX_PX + 2]; 3];
    let mut source = SourceRows::new(frame, xs, w);
    let mut hist = NO_HIST;
    let mut energy = [[0u32; MAX_CELLS]; 3];
    let mut blocks = [0u64; MAX_CELLS + 1];
    let across = grid.across(w);

    if let Some(ty) = ys.next() {
        source.sample_padded(frame, ty, &mut patch[0], w);
    }
    let mut sy = Split::first(cell);
    let (mut luma_row, mut luma_lines) = (0, 0);
    for p in 0..h {
        // Patch row `p` is `patch[p % 3]`: the row below is sampled before the gradients
        // of `p` are taken, over the row above.
        if p + 1 < h {
            if let Some(ty) = ys.next() {
                source.sample_padded(frame, ty, &mut patch[(p + 1) % 3], w);
            }
        }
        let around = [p.saturating_sub(1), p, (p + 1).min(h - 1)]
            .map(|i| patch[i % 3].get(..w + 2).unwrap_or_default());
        // A one-sided difference at the patch's edge counts twice.
        let scale_y = match (p, h) {
            (_, 1) => 0,
            (0, _) => 2,
            _ if p + 1 == h => 2,
            _ => 1,
        };
        // The two cell rows this pixel row reaches, as the bands of their histograms (cell
        // row `cy` in band `cy % 2`) and weights; a row outside the grid weighs 0.
        let bands = sy
            .cells()
            .map(|(cy, wy)| if cy < rows { (cy % 2, wy) } else { (0, 0) });
        grid.add_gradients(around, &across, scale_y, bands, &mut hist);
        // The luma sums of the cell row's cells, kept in `out` until it is complete (`cell`
        // is at least 1: `max` restates it where the optimiser no longer sees the clamp, so
        // that `chunks_exact` links no panic path).
        let row = around[1].get(1..=w).unwrap_or_default();
        for (c, px) in out_row(out, luma_row, cols)
            .iter_mut()
            .zip(row.chunks_exact(cell.max(1)))
        {
            let sum = px.iter().map(|&v| u32::from(v)).sum();
            add_luma(c, sum, luma_lines == 0);
        }
        luma_lines += 1;
        if luma_lines == cell {
            grid.write_luma(out_row(out, luma_row, cols));
            (luma_row, luma_lines) = (luma_row + 1, 0);
        }
        // A cell row is complete once no later pixel row reaches it.
        let below = sy.hi;
        sy.advance();
        if (sy.hi > below || p + 1 == h) && below >= 1 {
            let y = below - 1;
            grid.settle(&mut hist[y % 2], &mut energy[y % 3], out_row(out, y, cols));
            if y >= 1 {
                grid.finish(y - 1, &energy, &mut blocks, out_row(out, y - 1, cols));
            }
        }
    }
    grid.finish(rows - 1, &energy, &mut blocks, out_row(out, rows - 1, cols));
}

/// Row `y` of `out` (`cols` cells, fewer or none if `out` is short).
fn out_row(out: &mut [Cell], y: usize, cols: usize) -> &mut [Cell] {
    let start = (y * cols).min(out.len());
    let rest = out.get_mut(start..).unwrap_or(&mut []);
    let len = cols.min(rest.len());
    rest.get_mut(..len).unwrap_or(&mut [])
}

/// The luma sum (Q8, below `2^23`) that [`add_luma`] keeps in a cell's channels 0 and 1.
fn luma_sum(c: &Cell) -> u32 {
    u32::from(c[0] as u16) | u32::from(c[1] as u16) << 16
}

/// Adds `v` to the luma sum of a cell whose pixel rows are being read, kept in its
/// channels 0 and 1 (the low and high halves of a u32; both are overwritten once the cell
/// row is complete); `first` starts the sum.
fn add_luma(c: &mut Cell, v: u32, first: bool) {
    let sum = if first {
        v
    } else {
        luma_sum(c).saturating_add(v)
    };
    c[0] = sum as u16 as i16;
    c[1] = (sum >> 16) as u16 as i16;
}

/// One patch pixel's source pixels along an axis: `first` and `first + 1` (px, before
/// clamping into the frame), weighted `1 - f` and `f` (`f` in Q24).
#[derive(Clone, Copy, Debug)]
struct Taps {
    first: i32,
    f: u32,
}

/// The centres of successive patch pixels along one axis, as `RgbImage::patch` takes them
/// with `Resample::Bilinear`.
#[derive(Clone, Copy, Debug)]
struct Axis {
    /// The next pixel's centre, px, Q32.32.
    pos: i64,
    /// Px of the frame per patch px, Q32.32, rounded down.
    step: i64,
}

impl Axis {
    /// `out` pixels (`>= 1`) over `size` px (Q16.16, negative as 0) centred on `centre` px.
    fn new(centre: Q16, size: Q16, out: usize) -> Self {
        let size = i64::from(size.to_bits().max(0));
        let out = out.max(1) as i64;
        let step = (size << 16).checked_div(out).unwrap_or(0);
        let left = (2 * i64::from(centre.to_bits()) - size) << 15;
        Self {
            pos: left + step / 2,
            step,
        }
    }
}

impl Iterator for Axis {
    type Item = Taps;

    #[inline(always)]
    fn next(&mut self) -> Option<Taps> {
        let pos = self.pos;
        self.pos += self.step;
        Some(Taps {
            first: (pos >> 32) as i32,
            f: ((pos & 0xFFFF_FFFF) >> 8) as u32,
        })
    }
}

/// A patch column's two source pixels, clamped into the frame, px, and the weight of the
/// second, Q24.
#[derive(Clone, Copy, Debug, Default)]
struct Column {
    x: [u16; 2],
    f: u32,
}

/// The patch's columns and the luma of two frame rows at each column's two source pixels:
/// a patch row between the same frame rows as the last (a region that grows) or sharing
/// one with it reads the frame only for the row it lacks.
struct SourceRows {
    columns: [Column; MAX_PX],
    /// `luma[slot][i]`: the luma of patch column `i`'s two source pixels.
    luma: [[[u8; 2]; MAX_PX]; 2],
    /// The frame row each slot holds.
    row: [Option<usize>; 2],
}

impl SourceRows {
    /// The first `w` columns of `xs`, nothing read yet.
    fn new<P: PixelFormat>(frame: &ImageView<'_, P>, xs: Axis, w: usize) -> Self {
        let mut columns = [Column::default(); MAX_PX];
        for (c, tx) in columns.iter_mut().take(w).zip(xs) {
            // Clamped into the frame (at most `MAX_SIDE - 1`): they fit a `u16`.
            let x = [tx.first, tx.first.saturating_add(1)].map(|x| frame.clamp(x, 0).0 as u16);
            *c = Column { x, f: tx.f };
        }
        Self {
            columns,
            luma: [[[0; 2]; MAX_PX]; 2],
            row: [None; 2],
        }
    }

    /// The patch row of row taps `ty`, luma in Q8, one value for each of `out`'s columns:
    /// each patch pixel interpolated bilinearly between its 2 x 2 source pixels.
    fn sample<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>, ty: Taps, out: &mut [u16]) {
        let [top, bottom] = [ty.first, ty.first.saturating_add(1)].map(|y| frame.clamp(0, y).1);
        let t = self.load(frame, top, out.len(), bottom);
        let b = self.load(frame, bottom, out.len(), top);
        let (w_top, w_bottom) = (u64::from((1 << 24) - ty.f), u64::from(ty.f));
        let [slot0, slot1] = &self.luma;
        let pick = |s: usize| if s == 0 { slot0 } else { slot1 };
        for ((v, c), (&[t0, t1], &[b0, b1])) in out
            .iter_mut()
            .zip(&self.columns)
            .zip(pick(t).iter().zip(pick(b)))
        {
            // Values (at most 255) times Q24: below 2^32.
            let along =
                |l0: u8, l1: u8| u64::from(((1 << 24) - c.f) * u32::from(l0) + c.f * u32::from(l1));
            // At most 255 2^48 (the weights sum to 2^24 each way): Q8 at most 65,280.
            let acc = w_top * along(t0, t1) + w_bottom * along(b0, b1);
            *v = ((acc + (1 << 39)) >> 40) as u16;
        }
    }

    /// [`Self::sample`] of `w` columns into `row[1..=w]`, the edge pixels repeated into
    /// `row[0]` and `row[w + 1]`.
    fn sample_padded<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        ty: Taps,
        row: &mut [u16; MAX_PX + 2],
        w: usize,
    ) {
        if let Some(inner) = row.get_mut(1..=w) {
            self.sample(frame, ty, inner);
        }
        if let (Some(&first), Some(&last)) = (row.get(1), row.get(w)) {
            row[0] = first;
            if let Some(pad) = row.get_mut(w + 1) {
                *pad = last;
            }
        }
    }

    /// The slot holding frame row `y` at the first `w` columns, read into the slot that
    /// does not hold row `keep` if no slot holds `y`.
    fn load<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        y: usize,
        w: usize,
        keep: usize,
    ) -> usize {
        if let Some(s) = self.row.iter().position(|&r| r == Some(y)) {
            return s;
        }
        let s = usize::from(self.row[0] == Some(keep));
        self.row[s] = Some(y);
        let row = frame.row(y);
        let luma = if s == 0 {
            &mut self.luma[0]
        } else {
            &mut self.luma[1]
        };
        for (l, c) in luma.iter_mut().zip(&self.columns).take(w) {
            let [x0, x1] = c.x;
            *l = [row.luma(usize::from(x0)), row.luma(usize::from(x1))];
        }
        s
    }
}

/// `sqrt(gx^2 + gy^2)`, Q13, of a gradient in Q9 (`|gx|, |gy| <= 2^17`).
#[inline(always)]
fn magnitude(gx: i32, gy: i32) -> u32 {
    let (gx, gy) = (i64::from(gx), i64::from(gy));
    // Below 2^36, so that the root is below 2^26 and the rounding fits 32 bits.
    let n = (gx * gx + gy * gy) as u64;
    (sqrt_u64_q8(n) as u32 + 8) >> 4
}

/// The unsigned orientation bin (`0..9`) of a gradient: the nearest of 9 directions
/// `20 k` degrees modulo 180, a boundary going to the bin above.
#[inline(always)]
fn unsigned_bin(gx: i32, gy: i32) -> usize {
    // Folded into angles [0, 180) degrees.
    let (gx, gy) = if gy < 0 || (gy == 0 && gx < 0) {
        (-gx, -gy)
    } else {
        (gx, gy)
    };
    // The first-quadrant boundaries `(ax, gy)` is past (`past(b, d)`: its cross product
    // with boundary `b` at least `d`), found in 2 or 3 comparisons.
    // Both `ax` and `gy` are at least 0 here: the products are unsigned.
    let gy = gy.unsigned_abs();
    let count = |ax: u32, d: u64| {
        let past =
            |(c, s): (u32, u32)| u64::from(c) * u64::from(gy) >= u64::from(s) * u64::from(ax) + d;
        let [b10, b30, b50, b70] = BOUNDARIES;
        match (past(b30), past(b10)) {
            (true, _) if past(b50) => 3 + usize::from(past(b70)),
            (true, _) => 2,
            (false, below) => usize::from(below),
        }
    };
    match gx {
        // [0, 90): the boundaries it is at or past.
        1.. => count(gx.unsigned_abs(), 0),
        // 90 degrees: past 10 to 90.
        0 => 5,
        // (90, 180): mirrored, `180 - angle` in (0, 90) is at or below the mirror images
        // of the boundaries from 110 degrees on that the angle is at or past.
        _ => (BINS - count(gx.unsigned_abs(), 1)) % BINS,
    }
}

/// A patch pixel's two nearest cells along an axis: at `(p + 1/2) / cell - 1/2` cells, it
/// lies between cells `hi - 1` and `hi`, weighted `2 cell - r` and `r` (in `1 / (2 cell)`).
#[derive(Clone, Copy, Debug)]
struct Split {
    hi: usize,
    r: u32,
    span: u32,
}

impl Split {
    /// Pixel 0: `(1 + cell) / (2 cell)` cells past cell -1.
    fn first(cell: usize) -> Self {
        let span = 2 * cell as u32;
        let r = 1 + cell as u32;
        if r >= span {
            Self {
                hi: 1,
                r: r - span,
                span,
            }
        } else {
            Self { hi: 0, r, span }
        }
    }

    /// On to the next pixel.
    #[inline(always)]
    fn advance(&mut self) {
        self.r += 2;
        if self.r >= self.span {
            self.r -= self.span;
            self.hi += 1;
        }
    }

    /// The two cells and their weights (cell -1 as `usize::MAX`).
    #[inline(always)]
    fn cells(&self) -> [(usize, u32); 2] {
        [
            (self.hi.wrapping_sub(1), self.span - self.r),
            (self.hi, self.r),
        ]
    }
}

/// The grid's sizes and the fixed-point scales that depend on them.
#[derive(Clone, Copy, Debug)]
struct Grid {
    cols: usize,
    rows: usize,
    /// Cell side, px of the patch.
    cell: usize,
    /// `cell^2 * 255`: a cell's luma sum (Q8) at 255.
    full: u32,
    /// Right shift of a pixel's weighted magnitude into the histogram's unit.
    shift: u32,
    /// The reference's `eps` in the unit of the energies (Q4 of the bin unit squared).
    eps: u64,
}

/// Packs a patch column's cells across: the offset of its left cell's bins in a band
/// (`c BINS <= 297`, cell `c - 1` at `c`), bits 0-8, the left cell's weight `w0` (in
/// `1 / (2 cell)`, at most 16), bits 9-13 (the right cell's is `2 cell - w0`), and bit 14
/// set at the patch's first and last column, where the difference is one-sided.
fn pack_across(c: usize, w0: u32, edge: bool) -> u16 {
    (c * BINS) as u16 | (w0 as u16) << 9 | u16::from(edge) << 14
}

impl Grid {
    fn new(cols: usize, rows: usize, cell: usize) -> Self {
        let shift = 2 * (usize::BITS - (cell - 1).leading_zeros()) + 1;
        let cell4 = (cell * cell * cell * cell) as u64;
        Self {
            cols,
            rows,
            cell,
            full: (cell * cell) as u32 * 255,
            shift,
            // 1e-4 / 4 / cell^4 luma^2 times (4 cell^4 2^(13 - shift))^2, times 16.
            eps: (cell4 << (30 - 2 * shift)) / 2500,
        }
    }

    /// Each of the first `w` patch columns' cells across ([`pack_across`]).
    fn across(&self, w: usize) -> [u16; MAX_PX] {
        let mut across = [0; MAX_PX];
        let mut sx = Split::first(self.cell);
        for (x, a) in across.iter_mut().enumerate().take(w) {
            let [(_, w0), (c, _)] = sx.cells();
            *a = pack_across(c, w0, x == 0 || x + 1 == w);
            sx.advance();
        }
        across
    }

    /// Spreads the gradients of patch row `around[1]` (luma, Q8, between the rows above and
    /// below it, `around[0]` and `around[2]`, each padded by a pixel at either end;
    /// vertical differences times `scale_y`) over the histograms of the cell rows `bands`
    /// (band, weight) reaches, column `x` over the cells `across[x]`.
    ///
    /// The pixels are read through `windows(3)`, with no bounds check; a band of weight 0
    /// (a cell row outside the grid) gains `share(m, 0) = 0`, so the two bands' weights
    /// are summed per band and both histograms take every pixel.
    fn add_gradients(
        &self,
        around: [&[u16]; 3],
        across: &[u16; MAX_PX],
        scale_y: i32,
        bands: [(usize, u32); 2],
        hist: &mut [HistRow; 2],
    ) {
        let [above, cur, below] = around;
        let mut wy = [0u32; 2];
        for (band, w) in bands {
            wy[band & 1] += w;
        }
        let [wy0, wy1] = wy;
        let [band0, band1] = hist;
        let (band0, band1) = (band0.as_flattened_mut(), band1.as_flattened_mut());
        let span = 2 * self.cell as u32;
        // Central differences of the padded rows (their edge pixels repeated): one-sided at
        // the edges, where `across` doubles them.
        let pixels = cur
            .windows(3)
            .zip(below.get(1..).unwrap_or_default())
            .zip(above.get(1..).unwrap_or_default())
            .zip(across);
        for (((win, &below), &above), &across) in pixels {
            let gx = (i32::from(win[2]) - i32::from(win[0])) << ((across >> 14) & 1);
            let gy = scale_y * (i32::from(below) - i32::from(above));
            let m = magnitude(gx, gy);
            if m == 0 {
                continue;
            }
            let at = usize::from(across & 0x1FF) + unsigned_bin(gx, gy);
            let w0 = u32::from((across >> 9) & 0x1F);
            let w1 = span - w0;
            // The left cell's bin and the right one's, `BINS` apart, in either band.
            if let Some([left, .., right]) = band0.get_mut(at..=at + BINS) {
                *left += self.share(m, w0 * wy0);
                *right += self.share(m, w1 * wy0);
            }
            if let Some([left, .., right]) = band1.get_mut(at..=at + BINS) {
                *left += self.share(m, w0 * wy1);
                *right += self.share(m, w1 * wy1);
            }
        }
    }

    /// Magnitude `m` (Q13) times bilinear weight `w` (`<= 4 cell^2`), in the bin unit.
    #[inline(always)]
    fn share(&self, m: u32, w: u32) -> u32 {
        // m <= 2.95e6 and w <= 256: the product stays below 2^30.
        (m * w + (1 << self.shift >> 1)) >> self.shift
    }

    /// Turns the luma sums (Q8, see [`add_luma`]) of a cell row's cells into their means.
    fn write_luma(&self, out: &mut [Cell]) {
        for c in out.iter_mut() {
            let sum = luma_sum(c);
            // sum / full - 1/2 in Q15: sum 2^15 / (full 2^8) = sum 2^7 / full.
            let q = (sum * 128 + self.full / 2)
                .checked_div(self.full)
                .unwrap_or(0);
            c[0] = (q as i32 - (1 << 14)) as i16;
        }
    }

    /// A cell row's histograms are complete: keeps each cell's root energy (`s`, Q2),
    /// stores its bins over `s` (Q15) in `out`, and clears the histograms.
    fn settle(&self, hist: &mut HistRow, energy: &mut [u32; MAX_CELLS], out: &mut [Cell]) {
        let (padding, cells) = hist.split_at_mut(1);
        padding[0] = [0; BINS];
        for (x, (bins, s)) in cells
            .iter_mut()
            .zip(energy.iter_mut())
            .enumerate()
            .take(self.cols)
        {
            // Bins < 3.8e8: the energy (below 9 2^57) fits.
            let e: u64 = bins.iter().map(|&b| u64::from(b) * u64::from(b)).sum();
            *s = (sqrt_u64_q8(e.saturating_mul(16)) >> 8) as u32;
            let over_s = div_u64_u32(1 << 49, *s); // 2^47 / s, s Q2
            if let Some(c) = out.get_mut(x) {
                for (t, &b) in c[1..].iter_mut().zip(bins.iter()) {
                    // b <= s / 4 (to the root's rounding): below 2^46.
                    *t = ((u64::from(b) * over_s) >> 32).min(i16::MAX as u64) as i16;
                }
            }
            *bins = [0; BINS];
        }
        if let Some(bins) = cells.get_mut(self.cols) {
            *bins = [0; BINS];
        }
    }

    /// Cell row `y`'s fHOG channels, from its bins over `s` in `out` and the root energies
    /// of rows `y - 1..=y + 1` (ring of 3). `blocks` holds the normalisers of block row `y`
    /// (those above the cells; filled here for `y = 0`) and leaves with those of `y + 1`,
    /// so that each block's is computed once.
    fn finish(
        &self,
        y: usize,
        energy: &[[u32; MAX_CELLS]; 3],
        blocks: &mut [u64; MAX_CELLS + 1],
        out: &mut [Cell],
    ) {
        if y == 0 {
            for (bx, n) in blocks.iter_mut().enumerate().take(self.cols + 1) {
                *n = self.normaliser(0, bx, energy);
            }
        }
        let mut below_left = self.normaliser(y + 1, 0, energy);
        for x in 0..self.cols {
            let below_right = self.normaliser(y + 1, x + 1, energy);
            let above = |bx: usize| blocks.get(bx).copied().unwrap_or(0);
            let s = u64::from(energy[y % 3].get(x).copied().unwrap_or(0));
            // s n, Q16: at most 1, as s is at most the root of the block's energy.
            let ratio = |n: u64| (s.saturating_mul(n) >> 44).min(1 << 16) as u32;
            let [a, b, c, d] = [above(x), below_left, above(x + 1), below_right].map(ratio);
            if let Some(cell) = out.get_mut(x) {
                for t in cell[1..].iter_mut() {
                    // t (Q15, at most 1) times a ratio, Q31, clipped; 4 of them fit.
                    let t_q15 = u32::from(t.unsigned_abs());
                    let clipped = |r: u32| (t_q15 * r).min(CLIP);
                    let sum = clipped(a) + clipped(b) + clipped(c) + clipped(d);
                    // Half the sum, Q31 to Q15.
                    *t = ((sum + (1 << 16)) >> 17) as i16;
                }
            }
            // Block `x` above the cells is used up: it becomes the row below's.
            if let Some(n) = blocks.get_mut(x) {
                *n = below_left;
            }
            below_left = below_right;
        }
        if let Some(n) = blocks.get_mut(self.cols) {
            *n = below_left;
        }
    }

    /// `2^60 / sqrt(energy + eps)` of block `(by, bx)` of the edge-replicated
    /// `(rows + 1) x (cols + 1)` grid (cells `by - 1..=by`, `bx - 1..=bx`, clamped).
    fn normaliser(&self, by: usize, bx: usize, energy: &[[u32; MAX_CELLS]; 3]) -> u64 {
        let pair = |b: usize, n: usize| {
            let a = b.saturating_sub(1).min(n.saturating_sub(2));
            (a, (a + 1).min(n.saturating_sub(1)))
        };
        let ((y0, y1), (x0, x1)) = (pair(by, self.rows), pair(bx, self.cols));
        let e = [(y0, x0), (y1, x0), (y0, x1), (y1, x1)]
            .iter()
            .fold(self.eps, |sum, &(y, x)| {
                let s = energy[y % 3].get(x).copied().unwrap_or(0);
                sum.saturating_add(u64::from(s) * u64::from(s))
            });
        div_u64_u32(
            1 << 60,
            (sqrt_u64_q8(e) >> 8).min(u64::from(u32::MAX)) as u32,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::Gray8;
    use std::vec;
    use std::vec::Vec;

    /// `cols x rows` cells of `cell` px over the whole `w x h` frame, 1 frame px per patch px.
    fn whole(w: usize, h: usize, cell: usize) -> Sampling {
        Sampling {
            cx: Q16::from_ratio(w as i64 - 1, 2),
            cy: Q16::from_ratio(h as i64 - 1, 2),
            width: Q16::from_int(w as i32),
            height: Q16::from_int(h as i32),
            cols: w / cell,
            rows: h / cell,
            cell,
        }
    }

    fn run(buf: &[u8], w: usize, h: usize, s: &Sampling) -> Vec<Cell> {
        let frame = ImageView::<Gray8>::new(buf, w, h, w).unwrap();
        let mut out = vec![[0i16; CHANNELS]; s.cols * s.rows];
        extract(&frame, s, &mut out);
        out
    }

    /// Q15 to f64.
    fn f(v: i16) -> f64 {
        f64::from(v) / 32768.0
    }

    #[test]
    fn a_ramp_fills_its_orientation_bin_in_every_cell() {
        // Integer slopes (exact in the frame's bytes) near each bin's centre, 20 k degrees.
        let slopes = [
            (1, 0),
            (3, 1),
            (1, 1),
            (1, 2),
            (1, 6),
            (-1, 6),
            (-1, 2),
            (-1, 1),
            (-3, 1),
        ];
        for (bin, (a, b)) in slopes.into_iter().enumerate() {
            let n = 24;
            let buf: Vec<u8> = (0..n * n)
                .map(|i| {
                    let (x, y) = ((i % n) as i32, (i / n) as i32);
                    let v = a * x + b * y - 23 * a.min(0) + 20;
                    v as u8
                })
                .collect();
            let out = run(&buf, n, n, &whole(n, n, 4));
            for (i, c) in out.iter().enumerate() {
                for (o, &v) in c[1..].iter().enumerate() {
                    let want = if o == bin { 0.4 } else { 0.0 };
                    assert!((f(v) - want).abs() < 1e-4, "bin {bin} cell {i} o {o}: {v}");
                }
            }
        }
    }

    #[test]
    fn a_step_edge_marks_only_the_cells_along_it() {
        // Dark left half, bright right half: the gradient points right (bin 0) on the two
        // pixel columns beside the edge, in cells 3 and 4 of each row.
        let buf: Vec<u8> = (0..32 * 32)
            .map(|i| if i % 32 < 16 { 20 } else { 220 })
            .collect();
        let out = run(&buf, 32, 32, &whole(32, 32, 4));
        for (i, c) in out.iter().enumerate() {
            let x = i % 8;
            if x == 3 || x == 4 {
                assert!(f(c[1]) > 0.3, "cell {i}: {c:?}");
            } else {
                assert_eq!(c[1], 0, "cell {i}");
            }
            assert!(c[2..].iter().all(|&v| v == 0), "cell {i}: {c:?}");
        }
        // Bright to dark: the same unsigned bin.
        let flipped: Vec<u8> = buf.iter().map(|&v| 240 - v).collect();
        let back = run(&flipped, 32, 32, &whole(32, 32, 4));
        for (a, b) in out.iter().zip(&back) {
            assert_eq!(a[1..], b[1..]);
        }
    }

    #[test]
    fn grey_is_the_cell_mean_centred() {
        let buf: Vec<u8> = (0..8 * 8)
            .map(|i| if i % 8 < 4 { 0 } else { 255 })
            .collect();
        let out = run(&buf, 8, 8, &whole(8, 8, 4));
        let grey: Vec<i16> = out.iter().map(|c| c[0]).collect();
        assert_eq!(grey, [-16384, 16384, -16384, 16384]);
        let flat = vec![100u8; 8 * 8];
        let out = run(&flat, 8, 8, &whole(8, 8, 2));
        for c in &out {
            // 100 / 255 - 1/2 = -0.10784
            assert_eq!(c[0], (-0.107_843_f64 * 32768.0).round() as i16);
            assert!(c[1..].iter().all(|&v| v == 0));
        }
    }

    #[test]
    fn a_region_partly_outside_the_frame_repeats_the_edge() {
        // A 16 x 16 frame and the same frame inside a 32 x 32 one, its edges repeated.
        let mut rng = crate::rng::Rng::new(3);
        let small: Vec<u8> = (0..16 * 16).map(|_| rng.below(256) as u8).collect();
        let big: Vec<u8> = (0..32 * 32usize)
            .map(|i| {
                let x = (i % 32).saturating_sub(8).min(15);
                let y = (i / 32).saturating_sub(8).min(15);
                small[y * 16 + x]
            })
            .collect();
        for (size, cell) in [(16, 4), (24, 2), (10, 4)] {
            let s = Sampling {
                cx: Q16::from_ratio(5, 2),
                cy: Q16::from_ratio(-3, 4),
                width: Q16::from_int(size),
                height: Q16::from_int(size),
                cols: 4,
                rows: 4,
                cell,
            };
            let moved = Sampling {
                cx: s.cx + Q16::from_int(8),
                cy: s.cy + Q16::from_int(8),
                ..s
            };
            assert_eq!(run(&small, 16, 16, &s), run(&big, 32, 32, &moved));
        }
    }

    #[test]
    fn out_of_range_sampling_does_not_panic() {
        let buf: Vec<u8> = (0..40 * 30).map(|i| (i * 7 % 251) as u8).collect();
        let frame = ImageView::<Gray8>::new(&buf, 40, 30, 40).unwrap();
        let base = whole(40, 30, 4);
        let cases = [
            Sampling {
                cols: 0,
                rows: 0,
                cell: 0,
                ..base
            },
            Sampling {
                cols: 100,
                rows: MAX_CELLS + 1,
                cell: 9,
                ..base
            },
            Sampling {
                width: Q16::from_int(-5),
                height: Q16::ZERO,
                ..base
            },
            Sampling {
                cx: Q16::MIN,
                cy: Q16::MAX,
                ..base
            },
            Sampling {
                width: Q16::from_int(400),
                height: Q16::from_int(300),
                ..base
            },
            Sampling {
                cols: 1,
                rows: 1,
                cell: 1,
                ..base
            },
        ];
        for s in cases {
            for len in [0, 1, 7, MAX_CELLS * MAX_CELLS] {
                let mut out = vec![[0x55i16; CHANNELS]; len];
                extract(&frame, &s, &mut out);
                let cells = s.cols.clamp(1, MAX_CELLS) * s.rows.clamp(1, MAX_CELLS);
                for c in out.iter().skip(cells) {
                    assert_eq!(c, &[0x55; CHANNELS]);
                }
                for c in out.iter().take(cells) {
                    assert!(c[1..].iter().all(|&v| (0..=13_108).contains(&v)), "{s:?}");
                }
            }
        }
        // The clamped grid is the grid asked for in range.
        let mut a = vec![[0i16; CHANNELS]; MAX_CELLS * MAX_CELLS];
        let mut b = a.clone();
        extract(&frame, &cases[1], &mut a);
        extract(
            &frame,
            &Sampling {
                cols: MAX_CELLS,
                rows: MAX_CELLS,
                cell: MAX_CELL,
                ..base
            },
            &mut b,
        );
        assert_eq!(a, b);
    }

    #[test]
    fn orientation_bins_split_at_ten_degrees_off_their_centre() {
        let at = |d: f64| {
            let (s, c) = d.to_radians().sin_cos();
            unsigned_bin((c * 1e5) as i32, (s * 1e5) as i32)
        };
        assert_eq!(unsigned_bin(1, 0), 0);
        assert_eq!(unsigned_bin(0, 1), 5); // 90 degrees: on a boundary, to the bin above
        assert_eq!(unsigned_bin(0, -1), 5);
        assert_eq!(unsigned_bin(-1, 0), 0);
        assert_eq!(at(9.9), 0);
        assert_eq!(at(10.1), 1);
        assert_eq!(at(169.9), 8);
        assert_eq!(at(170.1), 0);
        assert_eq!(at(200.0), 1);
        assert_eq!(at(355.0), 0);
        assert_eq!(at(345.0), 8);
    }

    #[test]
    fn orientation_bins_count_the_boundaries_passed() {
        // The bin is the number of the 9 boundaries 10 + 20 k degrees at or past the angle
        // folded into [0, 180), modulo 9: ties included, such as (1, 1) against 50 degrees.
        let folded = |gx: i64, gy: i64| {
            if gy < 0 || (gy == 0 && gx < 0) {
                (-gx, -gy)
            } else {
                (gx, gy)
            }
        };
        let passed = |gx: i32, gy: i32| {
            let (gx, gy) = folded(i64::from(gx), i64::from(gy));
            (0..9)
                .filter(|&k| {
                    let (s, c) = (10.0 + 20.0 * k as f64).to_radians().sin_cos();
                    let q = |v: f64| (v * f64::from(1 << 30)).round() as i64;
                    q(c) * gy - q(s) * gx >= 0
                })
                .count()
                % 9
        };
        let mut rng = crate::rng::Rng::new(5);
        for _ in 0..200_000 {
            let g = |r: &mut crate::rng::Rng| {
                let v = r.below(1 << 18) as i32 - (1 << 17);
                v >> r.below(17)
            };
            let (gx, gy) = (g(&mut rng), g(&mut rng));
            if (gx, gy) != (0, 0) {
                assert_eq!(unsigned_bin(gx, gy), passed(gx, gy), "{gx}, {gy}");
            }
        }
        for gx in -40..=40 {
            for gy in -40..=40 {
                if (gx, gy) != (0, 0) {
                    assert_eq!(unsigned_bin(gx, gy), passed(gx, gy), "{gx}, {gy}");
                }
            }
        }
    }

    #[test]
    fn magnitude_is_the_root_in_q13() {
        for (gx, gy) in [(0, 0), (3, 4), (-512, 0), (130_560, 130_560), (-7, 1)] {
            let want = ((gx as f64).hypot(gy as f64) * 16.0).round();
            let got = f64::from(magnitude(gx, gy));
            assert!((got - want).abs() <= 1.0 + want * 1e-5, "{gx}, {gy}: {got}");
        }
    }
}
