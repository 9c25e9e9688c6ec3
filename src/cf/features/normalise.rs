//! Cell histograms to normalised fHOG channels: each cell's energy and root, each 2x2
//! block's root, the clipped sums (Felzenszwalb's normalisation in integers).

use super::{Cell, BINS, MAX_CELLS, MAX_PX, STRIDE};
use crate::fixed::sqrt_u64_m16;

/// The clip of a normalised bin, 0.2, in Q31.
pub(super) const CLIP: u32 = 429_496_730;

/// A root energy `sqrt(e) ~ m 2^exp` ([`sqrt_u64_m16`]: `m` in `2^15..2^16`, or 0 with
/// `e`), a cell's or a block's (whose `1 / sqrt(energy + eps)` is the normaliser).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Root {
    m: u32,
    exp: i32,
}

impl Root {
    pub(super) const ZERO: Self = Self { m: 0, exp: 0 };

    /// The root of `energy`.
    #[inline(always)]
    pub(super) fn of(energy: u64) -> Self {
        let (m, exp) = sqrt_u64_m16(energy);
        Self { m, exp }
    }

    /// `cell / self` in Q16 of a cell's root at most this block's: at most 1.
    #[inline(always)]
    pub(super) fn ratio(self, cell: Root) -> u32 {
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
    pub(super) fn shares(self) -> (u32, u32) {
        let d = 15 - self.exp;
        (d.clamp(0, 31) as u32, (-d).clamp(0, 31) as u32)
    }
}

/// The grid's sizes and the fixed-point scales that depend on them.
#[derive(Clone, Copy, Debug)]
pub(super) struct Grid {
    pub(super) cols: usize,
    pub(super) rows: usize,
    /// Cell side, px of the patch (even).
    cell: usize,
    /// `cell^2 * 255`: a cell's luma sum (Q8) at 255.
    full: u32,
}

/// The reference's `eps` (`1e-4 / 4 / cell^4` of its bins squared) in the unit of the
/// energies, the bin unit squared: the bin unit is `2^-14 / 16` luma per px over `cell^2`
/// px, so `1e-4 / 4 2^28`, whatever the cell (6,710.9, rounded).
pub(super) const EPS: u64 = 6_711;

impl Grid {
    pub(super) fn new(cols: usize, rows: usize, cell: usize) -> Self {
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
    pub(super) fn columns(&self, columns: &mut [u32; MAX_PX]) {
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
    pub(super) fn add_luma(&self, row: &[i32; STRIDE], sums: &mut [u32; MAX_CELLS]) {
        let w = self.cols * self.cell;
        let pixels = row.get(1..=w).unwrap_or_default();
        // `cell` is at least 2: `max` restates it where the optimiser no longer sees the
        // clamp, so that `chunks_exact` links no panic path.
        for (sum, px) in sums.iter_mut().zip(pixels.chunks_exact(self.cell.max(1))) {
            *sum += px.iter().sum::<i32>() as u32;
        }
    }

    /// Turns a cell row's luma sums (Q8, below `2^22`) into their means, and clears them.
    pub(super) fn write_luma(&self, sums: &mut [u32; MAX_CELLS], out: &mut [Cell]) {
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
    pub(super) fn settle(
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
    pub(super) fn finish(
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
    pub(super) fn column_sums(
        &self,
        by: usize,
        energy: &[[u64; MAX_CELLS]; 3],
    ) -> [u64; MAX_CELLS] {
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
    pub(super) fn block(&self, sums: &[u64; MAX_CELLS], bx: usize) -> Root {
        let x0 = bx.saturating_sub(1).min(self.cols.saturating_sub(2));
        let x1 = (x0 + 1).min(self.cols - 1);
        let at = |x: usize| sums.get(x).copied().unwrap_or(0);
        Root::of(EPS + at(x0) + at(x1))
    }

    /// Every block's root energy of the row whose column sums are `sums`.
    pub(super) fn blocks(&self, sums: [u64; MAX_CELLS], blocks: &mut [Root; MAX_CELLS + 1]) {
        for (bx, n) in blocks.iter_mut().enumerate().take(self.cols + 1) {
            *n = self.block(&sums, bx);
        }
    }
}
