//! Bilinear resampling of a frame region, row by row: each frame row read once and
//! interpolated across once for the patch rows beside it.

use super::{MAX_PX, STRIDE};
use crate::fixed::Q16;
use crate::image::{ImageView, PixelFormat};

/// One patch pixel's source pixels along an axis: `first` and `first + 1` (px, before
/// clamping into the frame), weighted `1 - f` and `f` (`f` in Q24).
#[derive(Clone, Copy, Debug)]
pub(super) struct Taps {
    first: i32,
    f: u32,
}

/// The centres of successive patch pixels along one axis, as `RgbImage::patch` takes them
/// with `Resample::Bilinear`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Axis {
    /// The next pixel's centre, px, Q32.32.
    pos: i64,
    /// Px of the frame per patch px, Q32.32, rounded down.
    step: i64,
}

impl Axis {
    /// `out` pixels (`>= 1`) over `size` px (Q16.16, negative as 0) centred on `centre` px.
    pub(super) fn new(centre: Q16, size: Q16, out: usize) -> Self {
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
pub(super) struct Column {
    i: u16,
    next: u16,
    f: u32,
}

/// Most frame pixels a frame row's read takes at once.
pub(super) const SPAN: usize = 2 * MAX_PX;

/// The patch's columns and two frame rows interpolated across at them: a patch row
/// between the same frame rows as the last (a region that grows) or sharing one with it
/// reads and interpolates only the row it lacks. A frame row is read as one run of the
/// pixels from the columns' first source pixel to their last, where at most [`SPAN`]
/// (the region is at most `SPAN` px wide, or twice the patch), else pixel by pixel at the
/// columns' source pixels, each once.
#[derive(Clone, Debug)]
pub(super) struct SourceRows {
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
    pub(super) const NEW: Self = Self {
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
    pub(super) fn start<P: PixelFormat>(
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
    pub(super) fn sample<P: PixelFormat>(
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
    pub(super) fn load<P: PixelFormat>(
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

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
}
