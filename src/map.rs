//! The object-probability map: every cell of a grid over the search region holds
//! `P(object | colour)` of a pixel sampled there, summed into an integral image, so that
//! the mean probability of any box costs 16 reads, whatever its size.
//!
//! The per-bin probabilities come from the colour model
//! ([`crate::colour::ColourModel::object_prob`]);
//! the map is built once per frame over the region all particles' boxes cover, at most
//! [`SIDE`] cells a side (the cell grows with the region), and shared by all particles.
//!
//! A box's sum is read from the integral image with bilinear interpolation, which is
//! exact for the piecewise-constant map: a box that covers a third of a cell counts a
//! third of it, so scores move smoothly with sub-cell shifts and sizes.

use crate::fixed::{div_u64_u32, Q16};
use crate::image::{Binning, ImageView, PixelFormat, Run};

/// Cells per side of the map, at most.
pub const SIDE: usize = 64;

/// Entries per row of the integral image.
const STRIDE: usize = SIDE + 1;

/// One cell, or a probability of 1, in the Q16.16 scale of cell coordinates and of the
/// interpolation weights.
const ONE: i64 = 1 << Q16::FRAC_BITS;

/// An axis-aligned box, px, Q16.16: columns `x0..x1`, rows `y0..y1` (pixel `x` covers
/// `[x - 1/2, x + 1/2)`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Span {
    /// Left edge, px.
    pub x0: Q16,
    /// Top edge, px.
    pub y0: Q16,
    /// Right edge, px.
    pub x1: Q16,
    /// Bottom edge, px.
    pub y1: Q16,
}

/// The object-probability map of one frame (see the module documentation).
#[derive(Clone, Debug)]
pub struct ObjectMap {
    /// Left and top edge of cell (0, 0), px.
    left: i32,
    top: i32,
    /// Cell side, px (`>= 1` once built; 0 before, every bit of an empty map zero).
    cell: i32,
    /// `floor(2^32 / cell)` (`u32::MAX` for a 1 px cell; 0 before the first build).
    cell_reciprocal: u32,
    /// Cells in use per row and per column (`<= SIDE`).
    cols: usize,
    rows: usize,
    /// `integral[r * STRIDE + c]`: sum of the cells above row `r` and left of column `c`,
    /// probabilities Q0.16 (`<= SIDE^2 * 65535 < 2^32`).
    integral: [u32; STRIDE * STRIDE],
}

#[cfg(feature = "defmt")]
impl defmt::Format for ObjectMap {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "ObjectMap {{ cell: {}, cols: {}, rows: {} }}",
            self.cell,
            self.cols,
            self.rows
        )
    }
}

impl Default for ObjectMap {
    fn default() -> Self {
        Self::new()
    }
}

impl ObjectMap {
    /// An empty map (every bit zero): every box has mean probability 0.
    pub const fn new() -> Self {
        Self {
            left: 0,
            top: 0,
            cell: 0,
            cell_reciprocal: 0,
            cols: 0,
            rows: 0,
            integral: [0; STRIDE * STRIDE],
        }
    }

    /// Builds the map over `region` (clipped to `img`) from the per-bin object
    /// probabilities `prob` (Q0.16), one pixel per cell, at its centre. Returns the number
    /// of pixels read (`<= SIDE^2`).
    pub fn build<Bn: Binning, P: PixelFormat, const B: usize>(
        &mut self,
        img: &ImageView<'_, P>,
        region: &Span,
        prob: &[u16; B],
    ) -> u32 {
        const { assert!(Bn::BINS == B, "the binning must have B bins") };
        let (width, height) = (img.width() as i32, img.height() as i32);
        // `clamp` as `max` then `min`: the same for a frame of at least one pixel, with no
        // `lo <= hi` assertion.
        let left = region.x0.round_int().max(0).min(width - 1);
        let top = region.y0.round_int().max(0).min(height - 1);
        let right = region.x1.round_int().max(left + 1).min(width);
        let bottom = region.y1.round_int().max(top + 1).min(height);
        let side = SIDE as i32;
        let cell = ((right - left).max(bottom - top) + side - 1) / side;
        let cell = cell.max(1);
        let cols = ((right - left + cell - 1) / cell) as usize;
        // At most `SIDE`, as the cell is at least a `SIDE`-th of the longer side.
        let rows = (((bottom - top + cell - 1) / cell) as usize).min(SIDE);
        // Sample each cell's centre, moved left (up) where the last cell's centre would
        // leave the frame; the last cell starts inside it.
        let last_x = left + (cols as i32 - 1) * cell;
        let last_y = top + (rows as i32 - 1) * cell;
        let dx = (cell / 2).min(width - 1 - last_x).max(0);
        let dy = (cell / 2).min(height - 1 - last_y).max(0);
        (self.left, self.top, self.cell, self.cols, self.rows) = (left, top, cell, cols, rows);
        self.cell_reciprocal = ((1u64 << 32) / cell as u64).min(u32::MAX as u64) as u32;

        let runs = img.runs();
        self.integral[..STRIDE].fill(0);
        for r in 0..rows {
            let y = (top + r as i32 * cell + dy) as usize;
            let x = (left + dx) as usize;
            let (above, here) = self.integral.split_at_mut((r + 1) * STRIDE);
            let above = &above[r * STRIDE..];
            here[0] = 0;
            let mut c = 0usize;
            let mut run = 0u32;
            let cells = Run {
                x0: x,
                step: cell as usize,
                count: cols as u32,
            };
            runs.for_each_bin::<Bn>(y, cells, |bin| {
                debug_assert!((bin as usize) < B, "bin {bin} out of range");
                run += prob.get(bin as usize).copied().unwrap_or(0) as u32;
                c += 1;
                if let (Some(out), Some(&up)) = (here.get_mut(c), above.get(c)) {
                    *out = up + run;
                }
            });
        }
        (rows * cols) as u32
    }

    /// Sum of the map over `span` (px), in cell units times probability Q0.16, with the
    /// covered area in cells, Q16.16; parts outside the map count for nothing.
    fn sum(&self, span: &Span) -> (u64, u64) {
        let u0 = self.to_cells(span.x0, self.left, self.cols);
        let u1 = self.to_cells(span.x1, self.left, self.cols);
        let v0 = self.to_cells(span.y0, self.top, self.rows);
        let v1 = self.to_cells(span.y1, self.top, self.rows);
        if u1 <= u0 || v1 <= v0 {
            return (0, 0);
        }
        let s = self.at(u1, v1) + self.at(u0, v0) - self.at(u0, v1) - self.at(u1, v0);
        let area = ((u1 - u0) as u64 * (v1 - v0) as u64) >> Q16::FRAC_BITS;
        (s.max(0) as u64, area)
    }

    /// A coordinate (px, Q16.16) in cells from `origin` (px), Q16.16 clamped to
    /// `[0, count]`; the pixel grid's `-1/2` offset is applied here.
    fn to_cells(&self, v: Q16, origin: i32, count: usize) -> i64 {
        let px = v.to_bits() as i64 + ONE / 2 - ((origin as i64) << Q16::FRAC_BITS);
        // Left of the map is 0 cells; to the right, px / cell by the cell's reciprocal,
        // corrected once (exact for px below 2^32).
        let (px, cell) = (px.clamp(0, u32::MAX as i64) as u64, self.cell as u64);
        let mut cells = (px * self.cell_reciprocal as u64) >> 32;
        if (cells + 1) * cell <= px {
            cells += 1;
        }
        (cells as i64).min((count as i64) << Q16::FRAC_BITS)
    }

    /// The integral image at `(u, v)` (cells, Q16.16, in range), bilinearly
    /// interpolated; Q16.16 scale on the sums.
    fn at(&self, u: i64, v: i64) -> i64 {
        let (i, j) = (
            (u >> Q16::FRAC_BITS) as usize,
            (v >> Q16::FRAC_BITS) as usize,
        );
        let (fu, fv) = (u & (ONE - 1), v & (ONE - 1));
        // Rows and columns up to `SIDE`: always inside the integral image.
        let t = |r: usize, c: usize| -> i64 {
            let index = r.min(self.rows) * STRIDE + c.min(self.cols);
            debug_assert!(index < self.integral.len(), "integral image entry {index}");
            self.integral.get(index).copied().unwrap_or(0) as i64
        };
        let top = t(j, i) * (ONE - fu) + t(j, i + 1) * fu;
        let bottom = t(j + 1, i) * (ONE - fu) + t(j + 1, i + 1) * fu;
        (top >> Q16::FRAC_BITS) * (ONE - fv) + (bottom >> Q16::FRAC_BITS) * fv
    }

    /// Mean object probability inside `inner` minus that in the ring between `inner` and
    /// `outer` (px), Q16.16 in `[-1, 1]`: high when the box holds the object and its
    /// surroundings do not. 0 when `inner` misses the map.
    pub fn contrast(&self, inner: &Span, outer: &Span) -> Q16 {
        let (s_in, a_in) = self.sum(inner);
        if a_in == 0 {
            return Q16::ZERO;
        }
        let (s_out, a_out) = self.sum(outer);
        // Areas are below 2^29 (64^2 cells, Q16.16): 64-by-32-bit divisions.
        let mean = |sum: u64, area: u64| div_u64_u32(sum, area.min(u32::MAX as u64) as u32) as i64;
        let mean_in = mean(s_in, a_in); // Q0.16 probability
        let mean_ring = match a_out.checked_sub(a_in) {
            Some(a) if a > 0 => mean(s_out.saturating_sub(s_in), a),
            _ => 0,
        };
        Q16::from_bits((mean_in - mean_ring).clamp(-ONE, ONE) as i32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Gray8, Luma64};

    use crate::rng::Rng;
    use std::vec;
    use std::vec::Vec;

    fn q(v: f64) -> Q16 {
        Q16::from_f64(v)
    }

    fn span(x0: f64, y0: f64, x1: f64, y1: f64) -> Span {
        Span {
            x0: q(x0),
            y0: q(y0),
            x1: q(x1),
            y1: q(y1),
        }
    }

    /// Probability table of Luma64: bin `u` has `P = u / 63`.
    fn ramp() -> [u16; 64] {
        core::array::from_fn(|u| (u as u32 * 65535 / 63) as u16)
    }

    #[test]
    fn contrast_matches_f64_box_means_on_the_sampled_cells() {
        let (w, h) = (97usize, 61usize);
        let mut rng = Rng::new(5);
        let buf: Vec<u8> = (0..w * h).map(|_| rng.next_u32() as u8).collect();
        let img = ImageView::<Gray8>::new(&buf, w, h, w).unwrap();
        let prob = ramp();
        let mut map = ObjectMap::new();
        // 97 x 61 px: cells of 2 px, 49 columns, 31 rows. The last column and row start
        // on the frame's last pixel, so every cell is sampled at its top-left pixel.
        let region = span(-10.0, -5.0, 120.0, 70.0);
        assert_eq!(
            map.build::<Luma64, Gray8, 64>(&img, &region, &prob),
            49 * 31
        );
        let cell_p = |c: usize, r: usize| -> f64 {
            prob[img.bin::<Luma64>(2 * c as i32, 2 * r as i32) as usize] as f64 / 65535.0
        };
        // Box mean in f64: area-weighted over the cells it covers (pixel grid offset 1/2).
        let mean = |s: &Span| -> f64 {
            let to_cells = |v: Q16, n: usize| ((v.to_f64() + 0.5) / 2.0).clamp(0.0, n as f64);
            let (u0, u1) = (to_cells(s.x0, 49), to_cells(s.x1, 49));
            let (v0, v1) = (to_cells(s.y0, 31), to_cells(s.y1, 31));
            let (mut sum, mut area) = (0.0, 0.0);
            for r in 0..31 {
                for c in 0..49 {
                    let a = ((u1.min(c as f64 + 1.0) - u0.max(c as f64)).max(0.0))
                        * ((v1.min(r as f64 + 1.0) - v0.max(r as f64)).max(0.0));
                    sum += a * cell_p(c, r);
                    area += a;
                }
            }
            (sum, area).0 / area
        };
        let mut worst = 0f64;
        for _ in 0..2000 {
            let f = |n: usize, r: &mut Rng| (r.next_u32() % (n as u32 * 100)) as f64 / 100.0;
            let (cx, cy) = (f(w, &mut rng), f(h, &mut rng));
            let (hx, hy) = (1.0 + f(20, &mut rng), 1.0 + f(15, &mut rng));
            let inner = span(cx - hx, cy - hy, cx + hx, cy + hy);
            let outer = span(cx - 1.5 * hx, cy - 1.5 * hy, cx + 1.5 * hx, cy + 1.5 * hy);
            let (m_in, m_out) = (mean(&inner), mean(&outer));
            let a = |s: &Span| {
                let c = |v: Q16, n: usize| ((v.to_f64() + 0.5) / 2.0).clamp(0.0, n as f64);
                (c(s.x1, 49) - c(s.x0, 49)) * (c(s.y1, 31) - c(s.y0, 31))
            };
            let (a_in, a_out) = (a(&inner), a(&outer));
            let ring = if a_out - a_in > 0.0 {
                (m_out * a_out - m_in * a_in) / (a_out - a_in)
            } else {
                0.0
            };
            let want = m_in - ring;
            let got = map.contrast(&inner, &outer).to_f64();
            worst = worst.max((got - want).abs());
        }
        assert!(worst < 2e-3, "max error {worst}");
    }

    #[test]
    fn contrast_peaks_at_the_blobs_size() {
        // A 21x31 blob of probability 1 at (60, 40) on probability 0; a 60 px map region,
        // so 1 px cells.
        let (w, h) = (120usize, 80usize);
        let mut buf = vec![0u8; w * h];
        for y in 25..56 {
            buf[y * w + 50..y * w + 71].fill(255);
        }
        let img = ImageView::<Gray8>::new(&buf, w, h, w).unwrap();
        let mut map = ObjectMap::new();
        map.build::<Luma64, Gray8, 64>(&img, &span(30.0, 10.0, 90.0, 70.0), &ramp());
        let score = |k: f64| {
            let (hx, hy) = (10.5 * k, 15.5 * k);
            let inner = span(60.0 - hx, 40.0 - hy, 60.0 + hx, 40.0 + hy);
            let outer = span(
                60.0 - 1.1 * hx,
                40.0 - 1.1 * hy,
                60.0 + 1.1 * hx,
                40.0 + 1.1 * hy,
            );
            map.contrast(&inner, &outer).to_f64()
        };
        assert!(score(1.0) > 0.99, "{}", score(1.0));
        for k in [0.8, 0.9, 0.95, 1.05, 1.1, 1.25] {
            assert!(score(k) < score(1.0), "{k}");
        }
    }

    #[test]
    fn boxes_outside_the_map_or_frame_count_nothing() {
        let buf = [255u8; 16 * 16];
        let img = ImageView::<Gray8>::new(&buf, 16, 16, 16).unwrap();
        let mut map = ObjectMap::new();
        assert_eq!(
            map.contrast(&span(0.0, 0.0, 4.0, 4.0), &span(-1.0, -1.0, 5.0, 5.0)),
            Q16::ZERO
        );
        map.build::<Luma64, Gray8, 64>(&img, &span(-100.0, -100.0, 100.0, 100.0), &ramp());
        // The whole frame has probability 1: inside 1, ring 1.
        let c = map.contrast(&span(2.0, 2.0, 8.0, 8.0), &span(1.0, 1.0, 9.0, 9.0));
        assert!(c.abs() <= Q16::from_bits(2), "{c}");
        // A box wholly outside the frame; a box of no area.
        assert_eq!(
            map.contrast(&span(30.0, 30.0, 40.0, 40.0), &span(25.0, 25.0, 45.0, 45.0)),
            Q16::ZERO
        );
        assert_eq!(
            map.contrast(&span(5.0, 5.0, 5.0, 9.0), &span(4.0, 4.0, 6.0, 10.0)),
            Q16::ZERO
        );
        // A box straddling the border: its ring is what lies in the frame.
        let c = map.contrast(&span(-3.0, -3.0, 3.0, 3.0), &span(-6.0, -6.0, 6.0, 6.0));
        assert!(c.abs() <= Q16::from_bits(2), "{c}");
        // Extreme spans neither panic nor leave [-1, 1].
        let wild = span(-32768.0, -32768.0, 32767.0, 32767.0);
        let c = map.contrast(&wild, &wild);
        assert!(c >= -Q16::ONE && c <= Q16::ONE);
    }
}
