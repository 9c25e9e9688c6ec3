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
//! - **Normalisation.** A complete cell row keeps each cell's energy and its root (a
//!   16-bit mantissa and an exponent, [`crate::fixed::sqrt_u64_m16`]) and stores its bins
//!   over the root (`t`, Q15, in `out`, so the bins need no third row of storage); each
//!   2x2 block of the edge-replicated grid gives the root of its 4 energies and `eps`,
//!   and channel `o` of a cell is `1/2 sum over its 4 blocks of min(t_o r_k, 0.2)`, `r_k`
//!   the cell's root over block `k`'s (Q16); where no product clips, the sum is `t_o`
//!   times the ratios' sum.
//!
//! The resampling is `resample`'s, a pixel's magnitude and bin `gradient`'s, the cells'
//! normalisation `normalise`'s; this module runs them over the patch and shares the
//! magnitudes between cells.
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

mod gradient;
mod normalise;
mod resample;

pub use gradient::TANGENTS;

use crate::fixed::Q16;
use crate::image::{ImageView, PixelFormat};
use gradient::magnitude_and_bin;
use normalise::{Grid, Root};
use resample::{Axis, SourceRows, SPAN};

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
        for x in 0..w.min(MAX_PX) {
            let column = self.columns[x];
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
