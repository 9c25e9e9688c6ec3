//! Per-cell features of a region of the frame resampled to a grid of cells: the cell's
//! mean luma and Felzenszwalb's 9 unsigned orientation channels (fHOG), in Q15.
//!
//! The integer port of the host's f64 reference (`cf64::fhog::features` of
//! `RgbImage::luma_patch(..)`, grey channel, `Hog::Unsigned9`, `Gradients::CORE`), in one
//! pass over the patch, row by row:
//! - **Resampling.** Patch pixel `i` of an axis is centred at `left + (i + 1/2) step` px
//!   of the frame, `step = size / out`, positions in Q32.32 (`step` rounded down, off by
//!   under `2^-23` px across the patch), and interpolated bilinearly between the 2 x 2
//!   source pixels nearest that centre (weights Q24), whether the axis shrinks or grows,
//!   as OpenCV's `INTER_LINEAR`. Source pixels outside the frame repeat its nearest
//!   edge. Each column's two source pixels (clamped) and weight are found once a patch; a
//!   frame row is read once (one run of pixels, or pixel by pixel where the region is
//!   wider than 512 px) and interpolated across into one of two rows of horizontal
//!   values (Q24 luma), for all the patch rows between it and its neighbour: each patch
//!   pixel is then one interpolation down. The patch's luma is kept in Q8 (`1/256`).
//! - **Gradient.** Central differences of the patch luma, Q9 luma per px (one-sided at
//!   the patch's edge, doubled: the rows' ends and the rows above the first and below the
//!   last are extrapolated); the magnitude `sqrt(gx^2 + gy^2)` in Q10, the larger part
//!   times `sqrt(1 + r^2)` of the parts' ratio from a table; the orientation folded into
//!   the upper half-plane and binned against the tangents of the boundaries between the
//!   unsigned bins ([`TANGENTS`], 10 + 20 k degrees, Q15): a division `ay / ax` (which
//!   serves the magnitude too where `ay <= ax`) and 2 or 3 comparisons, the second
//!   quadrant's by mirror symmetry.
//! - **Histogram.** Each pixel's magnitude is shared by the half of its cell it lies in
//!   (the cell is even), each way 3/4 to its cell and 1/4 to the neighbour on that side:
//!   9/16, 3/16, 3/16 and 1/16 to 4 cells of two open cell rows (the mean of the bilinear
//!   weights over each half), in units of `2^-14 / 16` luma per px, exact integers. The
//!   reference's division by `cell^2` is left out, as the normalisation cancels it (its
//!   `eps` is scaled to match).
//! - **Normalisation.** A complete cell row keeps each cell's energy and its root
//!   (a 16-bit mantissa and an exponent, [`sqrt_u64_m16`]) and stores its bins over the
//!   root (`t`, Q15, in `out`, so the bins need no third row of storage); each 2x2 block
//!   of the edge-replicated grid gives the root of its 4 energies and `eps`, and channel
//!   `o` of a cell is `1/2 sum over its 4 blocks of min(t_o r_k, 0.2)`, `r_k` the cell's
//!   root over block `k`'s (Q16); where no product clips, the sum is `t_o` times the
//!   ratios' sum.
//!
//! Error against the f64 reference (host test `cf_features`, Gray8 and RGB frames,
//! synthetic and real, 11 regions each: shrinking, growing, oblong, past the edge, cells of
//! 2 to 8 px), which reads the frame's 8-bit luma and keeps its patch to `1/256` as here:
//! see that test for the bounds. The rounding to `1/256` is part of the definition: it
//! keeps a pixel's gradient on the same side of a bin boundary in both.
//!
//! Working memory ([`Extractor`], kept by its owner so that no call clears it), for
//! patches of at most 256 px a side: the columns' source pixels and weights, the run of
//! a frame row's luma and two rows of horizontal values (5,660 B on a 32-bit target),
//! three patch rows (3,096 B), each column's cells (1,024 B), four rows of histograms (of
//! 512 words each, a power of two so that an index needs no bounds check: 8,192 B), the
//! energies and roots of three and two cell rows and one row of blocks' roots (1,544 B)
//! and a cell row's luma sums: about 19.6 KB on a 32-bit target. A call's stack frame is small
//! (the firmware's whole step stays under 4.4 KB).

use crate::fixed::{sqrt_u64_m16, Q16};
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

/// The tangents of the boundaries between the unsigned bins in the first quadrant, 10,
/// 30, 50 and 70 degrees, Q15, rounded: a gradient `(ax, ay)` there is at or past
/// boundary `k` where `ay 2^15 >= TANGENTS[k] ax`; those of the second quadrant are their
/// mirror images, `180 -` these. The f64 reference bins by the same numbers.
pub const TANGENTS: [u32; 4] = [5_778, 18_919, 39_051, 90_029];

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
    /// Cell side, px of the resampled patch, even, `2..=MAX_CELL`.
    pub cell: usize,
}

/// Values a patch row holds: its `MAX_PX` pixels and one more at either end.
const STRIDE: usize = MAX_PX + 2;

/// Words of one cell row of histograms in [`Extractor::hist`]: cells -1 to `MAX_CELLS`
/// (the padding cells take the shares of the neighbours outside the grid), `BINS` each,
/// within a power-of-two span so that an index masked to it needs no check.
const HIST_ROW: usize = 512;

/// Cell rows of histograms: three open rows and one that takes the shares of the rows
/// outside the grid.
const HIST_ROWS: usize = 4;

/// The feature extraction and its working memory, kept between calls (so that no call
/// clears it; nothing carries over from one call to the next): about 19.6 KB on a 32-bit
/// target.
#[derive(Clone, Debug)]
pub struct Extractor {
    source: SourceRows,
    /// Three patch rows, luma Q8, row `p` at `p % 3`, pixel `x` at `x + 1`, the ends
    /// extrapolated.
    rows: [[i32; STRIDE]; 3],
    /// Each patch column's cell and the neighbour it shares with ([`Grid::columns`]).
    columns: [u32; MAX_PX],
    /// Cell rows of histograms, row `r` at `r % 3`, the outside at 3: cell `x` bin `o` at
    /// `(x + 1) BINS + o` of its row.
    hist: [[u32; HIST_ROW]; HIST_ROWS],
    /// Three cell rows' energies (sums of their bins squared), row `r` at `r % 3`.
    energy: [[u64; MAX_CELLS]; 3],
    /// Two cell rows' root energies, row `r` at `r % 2`.
    roots: [[Root; MAX_CELLS]; 2],
    /// The root energies of one row of blocks ([`Grid::finish`]).
    blocks: [Root; MAX_CELLS + 1],
    /// A cell row's luma sums, Q8.
    luma: [u32; MAX_CELLS],
}

impl Default for Extractor {
    fn default() -> Self {
        Self::NEW
    }
}

impl Extractor {
    /// An extractor, every bit zero.
    pub const NEW: Self = Self {
        source: SourceRows::NEW,
        rows: [[0; STRIDE]; 3],
        columns: [0; MAX_PX],
        hist: [[0; HIST_ROW]; HIST_ROWS],
        energy: [[0; MAX_CELLS]; 3],
        roots: [[Root::ZERO; MAX_CELLS]; 2],
        blocks: [Root::ZERO; MAX_CELLS + 1],
        luma: [0; MAX_CELLS],
    };

    /// Fills `out[y * cols + x]` with the features of cell `(x, y)` of `sampling` (see
    /// the module documentation), reading at most `4 cols rows cell^2` frame pixels.
    ///
    /// `cols`, `rows` are clamped into `1..=MAX_CELLS` and `cell` into `2..=MAX_CELL`, an
    /// odd one rounded down; a negative width or height counts as 0 (every patch pixel
    /// then interpolates at the centre). Only the first `cols * rows` entries of `out` are
    /// written, and if `out` is shorter, the cells that fit (the features of a cell do not
    /// depend on the length of `out`).
    pub fn extract<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        sampling: &Sampling,
        out: &mut [Cell],
    ) {
        let cols = sampling.cols.clamp(1, MAX_CELLS);
        let rows = sampling.rows.clamp(1, MAX_CELLS);
        let cell = sampling.cell.clamp(2, MAX_CELL) & !1;
        let half = cell / 2;
        let (w, h) = (cols * cell, rows * cell);
        let grid = Grid::new(cols, rows, cell);
        let mut ys = Axis::new(sampling.cy, sampling.height, h);
        self.source
            .start(frame, Axis::new(sampling.cx, sampling.width, w), w, SPAN);
        grid.columns(&mut self.columns);
        // The outside row holds shares from the last call's; the others are clear.
        let used = (cols + 2) * BINS;
        for row in &mut self.hist {
            row.get_mut(..used).unwrap_or_default().fill(0);
        }
        self.luma = [0; MAX_CELLS];

        // Patch rows 0 and 1 (row 0 again where it is the only one), and above row 0 its
        // extrapolation: the top row's difference is one-sided.
        let mut next = |slot: &mut [i32; STRIDE], source: &mut SourceRows| {
            if let Some(ty) = ys.next() {
                source.sample(frame, ty, slot, w);
            }
        };
        let [r0, r1, r2] = &mut self.rows;
        next(r0, &mut self.source);
        match h {
            1 => *r1 = *r0,
            _ => next(r1, &mut self.source),
        }
        extrapolate(r2, r0, r1, w);
        for p in 0..h {
            // Row `p` is at `p % 3`, the one above at `(p + 2) % 3` (the extrapolation
            // above row 0), and the one below is read (or, below the last, extrapolated)
            // into the slot after it.
            if p >= 1 {
                let [above, cur, below] = ring(&mut self.rows, p);
                match p + 1 < h {
                    true => next(below, &mut self.source),
                    false => extrapolate(below, cur, above, w),
                }
            }
            // The cell row this pixel row lies in and the one its half shares with.
            let r = p / cell;
            let neighbour = match p % cell < half {
                true => r.checked_sub(1),
                false => Some(r + 1).filter(|&n| n < rows),
            };
            let other = neighbour.map_or(HIST_ROWS - 1, |n| n % 3);
            self.add_gradients(p, w, r % 3, other);
            let [_, cur, _] = ring(&mut self.rows, p);
            grid.add_luma(cur, &mut self.luma);
            if (p + 1) % cell == 0 {
                grid.write_luma(&mut self.luma, out_row(out, r, cols));
            }
            // The top half of cell row `r` done, row `r - 1` is complete.
            if p % cell + 1 == half && r >= 1 {
                self.complete(&grid, r - 1, out);
            }
        }
        self.complete(&grid, rows - 1, out);
        self.finish(&grid, rows - 1, out);
    }

    /// Cell row `y`'s histograms are complete: settled, and with them row `y - 1`'s
    /// neighbours, so that it is finished.
    fn complete(&mut self, grid: &Grid, y: usize, out: &mut [Cell]) {
        let cols = grid.cols;
        let (hist, energy, roots) = (
            &mut self.hist[y % 3],
            &mut self.energy[y % 3],
            &mut self.roots[y % 2],
        );
        grid.settle(hist, energy, roots, out_row(out, y, cols));
        if y >= 1 {
            self.finish(grid, y - 1, out);
        }
    }

    /// Cell row `y`'s fHOG channels ([`Grid::finish`]).
    fn finish(&mut self, grid: &Grid, y: usize, out: &mut [Cell]) {
        let roots = &self.roots[y % 2];
        grid.finish(
            y,
            &self.energy,
            roots,
            &mut self.blocks,
            out_row(out, y, grid.cols),
        );
    }

    /// Adds the gradients of patch row `p` to the histograms, each pixel's magnitude 9/16
    /// to its cell and 3/16 to its neighbour across (both in cell row `own`), 3/16 and
    /// 1/16 to those in the cell row `other` (indices into [`Extractor::hist`]'s rows):
    /// central differences of the rows, whose extrapolated ends make the one-sided
    /// differences at the patch's edge.
    fn add_gradients(&mut self, p: usize, w: usize, own: usize, other: usize) {
        let [above, cur, below] = ring(&mut self.rows, p);
        let Ok([own, other]) = self.hist.get_disjoint_mut([own, other]) else {
            return;
        };
        for (x, &column) in self.columns.iter().enumerate().take(w) {
            // Indices below `STRIDE`: `x < MAX_PX`.
            let gx = cur[x + 2] - cur[x];
            let gy = below[x + 1] - above[x + 1];
            let Some((m, bin)) = magnitude_and_bin(gx, gy) else {
                continue;
            };
            // Indices below `HIST_ROW`, a power of two.
            let at = ((column & 0xFFFF) as usize + bin) % HIST_ROW;
            let across = ((column >> 16) as usize + bin) % HIST_ROW;
            own[at] += 9 * m;
            own[across] += 3 * m;
            other[at] += 3 * m;
            other[across] += m;
        }
    }
}

/// The patch rows above, at and below row `p` of the ring.
fn ring(rows: &mut [[i32; STRIDE]; 3], p: usize) -> [&mut [i32; STRIDE]; 3] {
    let [a, b, c] = rows;
    match p % 3 {
        0 => [c, a, b],
        1 => [a, b, c],
        _ => [b, c, a],
    }
}

/// `to` becomes `2 from - beyond` over the first `w` pixels and the ends: the straight
/// line through both continued a row, so that the difference across `from` is one-sided,
/// doubled.
fn extrapolate(to: &mut [i32; STRIDE], from: &[i32; STRIDE], beyond: &[i32; STRIDE], w: usize) {
    for ((t, &a), &b) in to.iter_mut().zip(from).zip(beyond).take(w + 2) {
        *t = 2 * a - b;
    }
}

/// Row `y` of `out` (`cols` cells, fewer or none if `out` is short).
fn out_row(out: &mut [Cell], y: usize, cols: usize) -> &mut [Cell] {
    let start = (y * cols).min(out.len());
    let rest = out.get_mut(start..).unwrap_or(&mut []);
    let len = cols.min(rest.len());
    rest.get_mut(..len).unwrap_or(&mut [])
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

/// A patch column's source pixels: the index of the first in [`SourceRows::luma`],
/// whether the second is the next (1) or the same (0), and the weight of the second, Q24.
#[derive(Clone, Copy, Debug, Default)]
struct Column {
    i: u16,
    next: u16,
    f: u32,
}

/// Most frame pixels a frame row's read takes at once.
const SPAN: usize = 2 * MAX_PX;

/// The patch's columns and two frame rows interpolated across at them: a patch row
/// between the same frame rows as the last (a region that grows) or sharing one with it
/// reads and interpolates only the row it lacks. A frame row is read as one run of the
/// pixels from the columns' first source pixel to their last, where at most [`SPAN`]
/// (the region is at most `SPAN` px wide, or twice the patch), else pixel by pixel at the
/// columns' source pixels, each once.
#[derive(Clone, Debug)]
struct SourceRows {
    columns: [Column; MAX_PX],
    /// The run's first pixel, px.
    first: usize,
    /// Its length, px; 0 to read pixel by pixel at `xs`.
    span: usize,
    /// The columns' source pixels, px, left to right, each once (where no run).
    xs: [u16; SPAN],
    /// Their count.
    n: usize,
    /// A frame row's luma over the run, or at `xs`.
    luma: [u8; SPAN],
    /// `across[slot][i]`: a frame row interpolated at patch column `i`, luma Q24.
    across: [[u32; MAX_PX]; 2],
    /// The frame row each slot holds.
    row: [Option<usize>; 2],
}

impl SourceRows {
    /// No columns, nothing read.
    const NEW: Self = Self {
        columns: [Column {
            i: 0,
            next: 0,
            f: 0,
        }; MAX_PX],
        first: 0,
        span: 0,
        xs: [0; SPAN],
        n: 0,
        luma: [0; SPAN],
        across: [[0; MAX_PX]; 2],
        row: [None; 2],
    };

    /// Takes the first `w` columns of `xs`, nothing read yet, a frame row to be read as
    /// one run where the columns' pixels span at most `max_span` px ([`SPAN`]).
    fn start<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        xs: Axis,
        w: usize,
        max_span: usize,
    ) {
        // Clamped into the frame (at most `MAX_SIDE - 1`): they fit a `u16`. The centres
        // do not decrease, so neither do the pixels.
        let pixels = |tx: Taps| [tx.first, tx.first.saturating_add(1)].map(|x| frame.clamp(x, 0).0);
        let (mut head, mut tail) = (xs, xs);
        let first = head.next().map_or(0, |t| pixels(t)[0]);
        let last = tail
            .nth(w.saturating_sub(1))
            .map_or(first, |t| pixels(t)[1]);
        let span = last - first + 1;
        self.row = [None; 2];
        if span <= max_span.min(SPAN) {
            (self.first, self.span) = (first, span);
            for (c, tx) in self.columns.iter_mut().take(w).zip(xs) {
                let [x0, x1] = pixels(tx);
                *c = Column {
                    i: (x0 - first) as u16,
                    next: u16::from(x1 != x0),
                    f: tx.f,
                };
            }
            return;
        }
        self.span = 0;
        let mut n = 0;
        for (c, tx) in self.columns.iter_mut().take(w).zip(xs) {
            // A first pixel not past the last listed is the last or the one before (the
            // previous column's).
            let [x0, x1] = pixels(tx).map(|x| x as u16);
            let xs = &mut self.xs;
            let last = |n: usize, xs: &[u16]| n.checked_sub(1).and_then(|i| xs.get(i)).copied();
            let push = |x: u16, n: &mut usize, xs: &mut [u16; SPAN]| {
                if last(*n, xs).is_none_or(|l| x > l) {
                    if let Some(slot) = xs.get_mut(*n) {
                        *slot = x;
                        *n += 1;
                    }
                }
            };
            push(x0, &mut n, xs);
            let i = match last(n, xs) == Some(x0) {
                true => n.saturating_sub(1),
                false => n.saturating_sub(2),
            };
            push(x1, &mut n, xs);
            *c = Column {
                i: i as u16,
                next: u16::from(x1 != x0),
                f: tx.f,
            };
        }
        self.n = n;
    }

    /// The patch row of row taps `ty`, luma in Q8, into `out[1..=w]`, the ends
    /// extrapolated (`out[0] = 2 out[1] - out[2]`, likewise at the right; both the edge
    /// pixel where `w` is 1): each patch pixel interpolated bilinearly between its 2 x 2
    /// source pixels.
    fn sample<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        ty: Taps,
        out: &mut [i32; STRIDE],
        w: usize,
    ) {
        let [top, bottom] = [ty.first, ty.first.saturating_add(1)].map(|y| frame.clamp(0, y).1);
        let t = self.load(frame, top, w, bottom);
        let b = self.load(frame, bottom, w, top);
        let (w_top, w_bottom) = (u64::from((1 << 24) - ty.f), u64::from(ty.f));
        let [slot0, slot1] = &self.across;
        let pick = |s: usize| if s == 0 { slot0 } else { slot1 };
        let inner = out.get_mut(1..=w).unwrap_or_default();
        for (v, (&t, &b)) in inner.iter_mut().zip(pick(t).iter().zip(pick(b))) {
            // At most 255 2^48 (the weights sum to 2^24 each way): Q8 at most 65,280.
            let acc = w_top * u64::from(t) + w_bottom * u64::from(b);
            *v = ((acc + (1 << 39)) >> 40) as i32;
        }
        let at = |i: usize| out.get(i).copied().unwrap_or(0);
        let (left, right) = match w {
            1 => (at(1), at(1)),
            _ => (2 * at(1) - at(2), 2 * at(w) - at(w - 1)),
        };
        out[0] = left;
        if let Some(end) = out.get_mut(w + 1) {
            *end = right;
        }
    }

    /// The slot holding frame row `y` interpolated at the first `w` columns, read into
    /// the slot that does not hold row `keep` if no slot holds `y`.
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
        match self.span {
            0 => {
                for (l, &x) in self.luma.iter_mut().zip(&self.xs).take(self.n) {
                    *l = row.luma(usize::from(x));
                }
            }
            span => row.lumas(self.first, self.luma.get_mut(..span).unwrap_or_default()),
        }
        let across = if s == 0 {
            &mut self.across[0]
        } else {
            &mut self.across[1]
        };
        let luma = &self.luma;
        for (a, c) in across.iter_mut().zip(&self.columns).take(w) {
            // Indices below `2 MAX_PX`, a power of two.
            let i = usize::from(c.i);
            let l0 = u32::from(luma[i % luma.len()]);
            let l1 = u32::from(luma[(i + usize::from(c.next)) % luma.len()]);
            // (1 - f) l0 + f l1 = l0 + f (l1 - l0), Q24: in [0, 255 2^24], so the
            // wrapping sum of the two terms is exact.
            *a = (l0 << 24).wrapping_add(l1.wrapping_sub(l0).wrapping_mul(c.f));
        }
        s
    }
}

/// `sqrt(1 + r^2)` for `r = k / 128`, `k` in `0..=128`, Q16, rounded (bits 0-16), and
/// the step to the next (bits 17-26, at most 725; 0 for the last): [`hypot`]'s table.
const HYPOT: [u32; 129] = {
    // sqrt(2^32 + (k 2^9)^2) in Q16, rounded: the root of 4 times it, halved.
    const fn at(k: u64) -> u32 {
        (4 * ((1 << 32) + (k << 9) * (k << 9))).isqrt().div_ceil(2) as u32
    }
    let mut t = [0u32; 129];
    let mut k = 0;
    while k < 129 {
        let step = if k < 128 { at(k + 1) - at(k) } else { 0 };
        t[k as usize] = at(k) | step << 17;
        k += 1;
    }
    t
};

/// `hi sqrt(1 + r^2)` in Q10 of the larger part `hi` of a gradient (Q9, at most 130,560)
/// and the ratio of the smaller to it `r` (Q15, at most 1, floored): [`HYPOT`]
/// interpolated, within a relative `2.5e-5` (most of it the ratio's flooring) and a unit;
/// below 369,282 < 2^19, so 9 times it is below 2^22.
#[inline(always)]
fn hypot(hi: u32, r: u32) -> u32 {
    let entry = HYPOT.get((r >> 8) as usize).copied().unwrap_or(0);
    let (a, step) = (entry & 0x1_FFFF, entry >> 17);
    // `step f` is below 2^18.
    let s = a + ((step * (r & 0xFF) + 0x80) >> 8);
    // Q9 times Q16 below 2^35, to Q10.
    ((u64::from(hi) * u64::from(s) + (1 << 14)) >> 15) as u32
}

/// A gradient's magnitude (Q10, [`hypot`]) and unsigned orientation bin (`0..9`), or
/// none for a zero gradient (`gx, gy` in Q9, `|gx|, |gy| <= 130,560 < 2^17`).
///
/// The bin is the nearest of 9 directions `20 k` degrees modulo 180: the count, modulo 9,
/// of the boundaries `10 + 20 k` degrees ([`TANGENTS`]) that the angle folded into
/// `[0, 180)` has passed, a boundary going to the bin nearer 90 degrees (90 itself to the
/// bin above). One division `ay / ax` in Q15 serves the bin and, where `ay <= ax`, the
/// magnitude; a second `ax / ay` the magnitude otherwise.
#[inline(always)]
fn magnitude_and_bin(gx: i32, gy: i32) -> Option<(u32, usize)> {
    let (ax, ay) = (gx.unsigned_abs(), gy.unsigned_abs());
    if ax == 0 && ay == 0 {
        return None;
    }
    // `ay 2^15` is below 2^32; past every boundary at `ax = 0`.
    let q = (ay << 15).checked_div(ax).unwrap_or(u32::MAX);
    let m = match ay <= ax {
        true => hypot(ax, q),
        false => hypot(ay, (ax << 15).checked_div(ay).unwrap_or(0)),
    };
    // Folded into the upper half-plane (`gx` negated where `gy < 0`), the gradient lies in
    // [90, 180) degrees where the folded `gx` is at most 0, and is there `180 -` the
    // first-quadrant angle of `(ax, ay)`.
    let mirrored = (if gy < 0 { -gx } else { gx }) <= 0;
    // At or past boundary `k` of the first quadrant where `ay 2^15 >= T_k ax`, that is
    // where the floored quotient is at least `T_k`.
    let [t10, t30, t50, t70] = TANGENTS;
    let count = match q >= t50 {
        true => 3 + usize::from(q >= t70),
        false if q >= t30 => 2,
        false => usize::from(q >= t10),
    };
    // Mirrored: the 5 boundaries to 90 degrees and those from 110 on that the angle has
    // passed, `9 - count`, modulo 9.
    const BIN: [u8; 10] = [0, 1, 2, 3, 4, 0, 8, 7, 6, 5];
    let bin = usize::from(BIN[(5 * usize::from(mirrored) + count) % BIN.len()]);
    Some((m, bin))
}

/// A root energy `sqrt(e) ~ m 2^exp` ([`sqrt_u64_m16`]: `m` in `2^15..2^16`, or 0 with
/// `e`), a cell's or a block's (whose `1 / sqrt(energy + eps)` is the normaliser).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Root {
    m: u32,
    exp: i32,
}

impl Root {
    const ZERO: Self = Self { m: 0, exp: 0 };

    /// The root of `energy`.
    #[inline(always)]
    fn of(energy: u64) -> Self {
        let (m, exp) = sqrt_u64_m16(energy);
        Self { m, exp }
    }

    /// `cell / self` in Q16 of a cell's root at most this block's: at most 1.
    #[inline(always)]
    fn ratio(self, cell: Root) -> u32 {
        // Both mantissas below 2^16: the quotient (below 2^17) is shifted down by the
        // exponents' difference, at least 0.
        let q = (cell.m << 16).checked_div(self.m).unwrap_or(0);
        let d = (self.exp - cell.exp).clamp(0, 31) as u32;
        (q >> d).min(1 << 16)
    }

    /// The shifts that take a bin `b` at most this cell's root to `b 2^(15 - exp)`, left
    /// then right: `b << left >> right` over `m` is `b / self` in Q15, at most 1 (`b <= m
    /// 2^exp < 2^(16 + exp)`, so the shifted `b` is below 2^31).
    #[inline(always)]
    fn shares(self) -> (u32, u32) {
        let d = 15 - self.exp;
        (d.clamp(0, 31) as u32, (-d).clamp(0, 31) as u32)
    }
}

/// The grid's sizes and the fixed-point scales that depend on them.
#[derive(Clone, Copy, Debug)]
struct Grid {
    cols: usize,
    rows: usize,
    /// Cell side, px of the patch (even).
    cell: usize,
    /// `cell^2 * 255`: a cell's luma sum (Q8) at 255.
    full: u32,
}

/// The reference's `eps` (`1e-4 / 4 / cell^4` of its bins squared) in the unit of the
/// energies, the bin unit squared: the bin unit is `2^-14 / 16` luma per px over `cell^2`
/// px, so `1e-4 / 4 2^28`, whatever the cell (6,710.9, rounded).
const EPS: u64 = 6_711;

impl Grid {
    fn new(cols: usize, rows: usize, cell: usize) -> Self {
        Self {
            cols,
            rows,
            cell,
            full: (cell * cell) as u32 * 255,
        }
    }

    /// Fills the first `w` entries of `columns` (`w` the patch's width): each patch
    /// column's cell, as the offset of its bins in a row of histograms (`(x / cell + 1)
    /// BINS`, bits 0-15), and that of the neighbour its half shares with (the cell before
    /// for the first half, after for the second, bits 16-31).
    fn columns(&self, columns: &mut [u32; MAX_PX]) {
        let (cell, half) = (self.cell.max(2), self.cell / 2);
        let w = self.cols * self.cell;
        for (x, c) in columns.iter_mut().enumerate().take(w) {
            let own = x / cell + 1;
            let across = match x % cell < half {
                true => own - 1,
                false => own + 1,
            };
            *c = (own * BINS) as u32 | ((across * BINS) as u32) << 16;
        }
    }

    /// Adds a patch row's luma (Q8, padded) to its cells' sums.
    fn add_luma(&self, row: &[i32; STRIDE], sums: &mut [u32; MAX_CELLS]) {
        let w = self.cols * self.cell;
        let pixels = row.get(1..=w).unwrap_or_default();
        // `cell` is at least 2: `max` restates it where the optimiser no longer sees the
        // clamp, so that `chunks_exact` links no panic path.
        for (sum, px) in sums.iter_mut().zip(pixels.chunks_exact(self.cell.max(1))) {
            *sum += px.iter().sum::<i32>() as u32;
        }
    }

    /// Turns a cell row's luma sums (Q8, below `2^22`) into their means, and clears them.
    fn write_luma(&self, sums: &mut [u32; MAX_CELLS], out: &mut [Cell]) {
        for (c, sum) in out.iter_mut().zip(sums.iter_mut()) {
            // sum / full - 1/2 in Q15: sum 2^15 / (full 2^8) = sum 2^7 / full.
            let q = (*sum * 128 + self.full / 2)
                .checked_div(self.full)
                .unwrap_or(0);
            c[0] = (q as i32 - (1 << 14)) as i16;
            *sum = 0;
        }
    }

    /// A cell row's histograms `hist` (one row of [`Extractor::hist`]) are complete:
    /// keeps each cell's energy and root energy, stores its bins over its root energy
    /// (Q15, in `out`, channels 1 to 9), and clears the row, its padding cells included.
    fn settle(
        &self,
        hist: &mut [u32],
        energy: &mut [u64; MAX_CELLS],
        roots: &mut [Root; MAX_CELLS],
        out: &mut [Cell],
    ) {
        let bins = hist.get(BINS..).unwrap_or_default().chunks_exact(BINS);
        let cells = bins.zip(energy.iter_mut()).zip(roots.iter_mut());
        for (x, ((bins, e), root)) in cells.take(self.cols).enumerate() {
            // Bins below 2^29: the energy (below 9 2^58, four of them below 2^63.2) fits.
            *e = bins.iter().map(|&b| u64::from(b) * u64::from(b)).sum();
            *root = Root::of(*e);
            if let Some(c) = out.get_mut(x) {
                let (left, right) = root.shares();
                for (t, &b) in c[1..].iter_mut().zip(bins) {
                    let q = (b << left >> right).checked_div(root.m).unwrap_or(0);
                    *t = q.min(i16::MAX as u32) as i16;
                }
            }
        }
        let used = (self.cols + 2) * BINS;
        if let Some(row) = hist.get_mut(..used) {
            row.fill(0);
        }
    }

    /// Cell row `y`'s fHOG channels, from its bins over their root energy in `out`, its
    /// root energies and the energies of rows `y - 1..=y + 1` (ring of 3). `blocks` holds
    /// the root energies of block row `y` (those above the cells; filled here for `y = 0`)
    /// and leaves with those of `y + 1`, so that each block's is computed once.
    fn finish(
        &self,
        y: usize,
        energy: &[[u64; MAX_CELLS]; 3],
        roots: &[Root; MAX_CELLS],
        blocks: &mut [Root; MAX_CELLS + 1],
        out: &mut [Cell],
    ) {
        if y == 0 {
            self.blocks(self.column_sums(0, energy), blocks);
        }
        let below = self.column_sums(y + 1, energy);
        let mut below_left = self.block(&below, 0);
        for (x, &root) in roots.iter().enumerate().take(self.cols) {
            let below_right = self.block(&below, x + 1);
            let above = |bx: usize| blocks.get(bx).copied().unwrap_or_default();
            // The cell's root energy over each block's, Q16, at most 1.
            let (a, b) = (above(x).ratio(root), below_left.ratio(root));
            let (c, d) = (above(x + 1).ratio(root), below_right.ratio(root));
            let sum = a + b + c + d;
            let most = a.max(b).max(c.max(d));
            if let Some(cell) = out.get_mut(x) {
                for t in cell[1..].iter_mut() {
                    // t (Q15, at most 1) times a ratio, Q31, clipped at 0.2; where even
                    // the largest ratio does not clip, the sum of the 4 products is that of
                    // the ratios times t (below 4 CLIP < 2^32).
                    let t_q15 = u32::from(t.unsigned_abs());
                    let sum = match t_q15 * most <= CLIP {
                        true => t_q15 * sum,
                        false => {
                            let clipped = |r: u32| (t_q15 * r).min(CLIP);
                            clipped(a) + clipped(b) + clipped(c) + clipped(d)
                        }
                    };
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

    /// The energies of the two cell rows that block row `by` of the edge-replicated
    /// `(rows + 1) x (cols + 1)` grid covers (cells `by - 1..=by`, clamped), summed per
    /// column.
    fn column_sums(&self, by: usize, energy: &[[u64; MAX_CELLS]; 3]) -> [u64; MAX_CELLS] {
        let y0 = by.saturating_sub(1).min(self.rows.saturating_sub(2));
        let y1 = (y0 + 1).min(self.rows - 1);
        let (a, b) = (&energy[y0 % 3], &energy[y1 % 3]);
        let mut sums = [0; MAX_CELLS];
        for ((s, &a), &b) in sums.iter_mut().zip(a).zip(b).take(self.cols) {
            *s = a + b;
        }
        sums
    }

    /// The root energy (eps included) of block `bx` of the row whose column sums are
    /// `sums` (columns `bx - 1..=bx`, clamped).
    #[inline(always)]
    fn block(&self, sums: &[u64; MAX_CELLS], bx: usize) -> Root {
        let x0 = bx.saturating_sub(1).min(self.cols.saturating_sub(2));
        let x1 = (x0 + 1).min(self.cols - 1);
        let at = |x: usize| sums.get(x).copied().unwrap_or(0);
        Root::of(EPS + at(x0) + at(x1))
    }

    /// Every block's root energy of the row whose column sums are `sums`.
    fn blocks(&self, sums: [u64; MAX_CELLS], blocks: &mut [Root; MAX_CELLS + 1]) {
        for (bx, n) in blocks.iter_mut().enumerate().take(self.cols + 1) {
            *n = self.block(&sums, bx);
        }
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
        Extractor::default().extract(&frame, s, &mut out);
        out
    }

    /// Q15 to f64.
    fn f(v: i16) -> f64 {
        f64::from(v) / 32768.0
    }

    /// [`magnitude_and_bin`]'s bin of a nonzero gradient.
    fn bin(gx: i32, gy: i32) -> usize {
        magnitude_and_bin(gx, gy).map_or(usize::MAX, |(_, b)| b)
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
                Extractor::default().extract(&frame, &s, &mut out);
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
        let mut extractor = Extractor::NEW;
        extractor.extract(&frame, &cases[1], &mut a);
        extractor.extract(
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
            bin((c * 1e5) as i32, (s * 1e5) as i32)
        };
        assert_eq!(bin(1, 0), 0);
        assert_eq!(bin(0, 1), 5); // 90 degrees: on a boundary, to the bin above
        assert_eq!(bin(0, -1), 5);
        assert_eq!(bin(-1, 0), 0);
        assert_eq!(at(9.9), 0);
        assert_eq!(at(10.1), 1);
        assert_eq!(at(169.9), 8);
        assert_eq!(at(170.1), 0);
        assert_eq!(at(200.0), 1);
        assert_eq!(at(355.0), 0);
        assert_eq!(at(345.0), 8);
    }

    #[test]
    fn magnitudes_are_the_root_within_their_bound() {
        let mut rng = crate::rng::Rng::new(8);
        for i in 0..200_000 {
            let g = |r: &mut crate::rng::Rng| {
                let v = r.below(2 * 130_560 + 1) as i32 - 130_560;
                v >> r.below(17)
            };
            let (gx, gy) = match i {
                0 => (130_560, 130_560),
                1 => (-130_560, 1),
                _ => (g(&mut rng), g(&mut rng)),
            };
            let Some((m, _)) = magnitude_and_bin(gx, gy) else {
                assert_eq!((gx, gy), (0, 0));
                continue;
            };
            let want = 2.0 * f64::from(gx).hypot(f64::from(gy));
            let err = (f64::from(m) - want).abs();
            assert!(err <= 1.0 + 2.5e-5 * want, "{gx}, {gy}: {m} against {want}");
        }
        assert_eq!(magnitude_and_bin(0, 0), None);
    }

    #[test]
    fn orientation_bins_count_the_boundaries_passed() {
        // The bin is the number of the 9 boundaries 10 + 20 k degrees (as TANGENTS gives
        // them) that the angle folded into [0, 180) has passed, modulo 9: to 90 degrees a
        // boundary it is at counts, beyond 90 not (a tie goes to the bin nearer 90).
        let folded = |gx: i64, gy: i64| {
            if gy < 0 || (gy == 0 && gx < 0) {
                (-gx, -gy)
            } else {
                (gx, gy)
            }
        };
        // The 9 boundaries: the first quadrant's, 90 degrees, and their mirror images.
        let boundaries: Vec<(i64, i64, i64)> = TANGENTS
            .iter()
            .map(|&t| (1 << 15, i64::from(t), 0))
            .chain([(0, 1, 0)])
            .chain(
                TANGENTS
                    .iter()
                    .rev()
                    .map(|&t| (-(1 << 15), i64::from(t), 1)),
            )
            .collect();
        let passed = |gx: i32, gy: i32| {
            let (gx, gy) = folded(i64::from(gx), i64::from(gy));
            boundaries
                .iter()
                .filter(|&&(c, s, strict)| c * gy - s * gx >= strict)
                .count()
                % 9
        };
        let mut rng = crate::rng::Rng::new(5);
        for _ in 0..200_000 {
            // Differences of Q8 luma, one-sided ones doubled: at most 130,560.
            let g = |r: &mut crate::rng::Rng| {
                let v = r.below(2 * 130_560 + 1) as i32 - 130_560;
                v >> r.below(17)
            };
            let (gx, gy) = (g(&mut rng), g(&mut rng));
            if (gx, gy) != (0, 0) {
                assert_eq!(bin(gx, gy), passed(gx, gy), "{gx}, {gy}");
            }
        }
        for gx in -40..=40 {
            for gy in -40..=40 {
                if (gx, gy) != (0, 0) {
                    assert_eq!(bin(gx, gy), passed(gx, gy), "{gx}, {gy}");
                }
            }
        }
    }

    #[test]
    fn frame_rows_read_as_a_run_or_pixel_by_pixel_alike() {
        // Regions that shrink, keep and grow a 300 px wide frame's rows into 40 columns.
        let mut rng = crate::rng::Rng::new(9);
        let buf: Vec<u8> = (0..300 * 2 * 2).map(|_| rng.below(256) as u8).collect();
        let frame = ImageView::<crate::image::Rgb565Le>::new(&buf, 300, 2, 300).unwrap();
        for (centre, size) in [(150, 290), (20, 40), (299, 13), (-5, 20)] {
            let xs = Axis::new(Q16::from_int(centre), Q16::from_int(size), 40);
            let across = |max_span: usize| {
                let mut rows = SourceRows::NEW;
                rows.start(&frame, xs, 40, max_span);
                let slot = rows.load(&frame, 1, 40, 0);
                rows.across[slot]
            };
            assert_eq!(across(SPAN), across(0), "{centre} {size}");
        }
    }

    #[test]
    fn a_pixel_shares_nine_sixteenths_with_its_cell() {
        // Pixel 6 of the middle row is 100 / 256 brighter (Q8): pixels 5 and 7 of cell 1 see
        // a difference of 100 across (bin 0), 5 in the cell's first half (its neighbour across
        // cell 0), 7 in its second (cell 2); 9/16 to cell 1, 3/16 to the neighbour across,
        // and in the other row 3/16 and 1/16.
        let grid = Grid::new(4, 3, 4);
        let mut e = Extractor::default();
        grid.columns(&mut e.columns);
        e.rows[1][6 + 1] = 100;
        e.add_gradients(1, 16, 0, 2);
        let bin0 = |row: usize, cell: usize| e.hist[row][(cell + 1) * BINS];
        let own: Vec<u32> = (0..4).map(|c| bin0(0, c)).collect();
        let other: Vec<u32> = (0..4).map(|c| bin0(2, c)).collect();
        // A difference of 100 (Q8) over 2 px is a magnitude of 100 in Q9, 200 in Q10.
        assert_eq!(own, [600, 3600, 600, 0]);
        assert_eq!(other, [200, 1200, 200, 0]);
        assert_eq!(e.hist.as_flattened().iter().sum::<u32>(), 2 * 16 * 200);
    }
}
