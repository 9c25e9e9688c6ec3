//! The correlation-filter tracker's colour model: how likely each colour is to belong to
//! the object rather than to its surroundings (DAT, Possegger et al. 2015; Staple), and the
//! colour response it gives over the search region.
//!
//! The search region is sampled on a square grid of `side x side` points, one frame pixel
//! each (the pixel nearest the sample's centre, clamped into the frame). Two histograms
//! over the colour bins, each normalised to 1: `O` of the samples in an object box (the
//! target shrunk by the inner padding) and `S` of those outside the target box. A colour
//! `u` is object with probability `P(u) = O(u) / (O(u) + S(u))` (0 for a colour seen in
//! neither). The response at a place is the mean of `P` over a target-sized box there,
//! read from an integral image of `P` over the samples in four reads.
//!
//! The frame is read and binned once a frame: the map keeps the histogram of all its
//! samples, and learning reads only the samples in the target box again (those outside
//! it are the grid's less those inside).
//!
//! Scales: histograms Q0.24 (`2^24` is 1), probabilities Q0.16 (`65535` is 1), box means
//! Q16.16. A box is given in sample units (Q16.16) and covers the samples whose centres
//! (`k + 1/2`) it contains, at least one each way, as the f64 reference's regions do.

use crate::fixed::{div_u64_u32, Q16};
use crate::image::{Binning, ImageView, PixelFormat};

/// Largest sampling grid side, samples.
pub const MAX_SIDE: usize = 64;

/// Entries per row of the integral image.
const STRIDE: usize = MAX_SIDE + 1;

/// Fraction bits of a histogram (Q0.24).
const HIST_BITS: u32 = 24;

/// The sampling grid over a region of the frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Grid {
    /// Region centre, px (pixel centres at integer coordinates), Q16.16.
    pub cx: Q16,
    /// Region centre, px, Q16.16.
    pub cy: Q16,
    /// Region width, px, Q16.16.
    pub width: Q16,
    /// Region height, px, Q16.16.
    pub height: Q16,
    /// Samples a side, `1..=MAX_SIDE` (larger is taken as `MAX_SIDE`).
    pub side: usize,
}

impl Grid {
    fn side(&self) -> usize {
        self.side.clamp(1, MAX_SIDE)
    }

    /// Frame pixel of sample `i` along an axis of centre `c` and extent `len` (px,
    /// Q16.16): the one nearest `c - len/2 + (i + 1/2) len / side`.
    fn pixel(&self, c: Q16, len: Q16, i: usize) -> i32 {
        let side = self.side() as i64;
        let offset = (2 * i as i64 + 1) * len.to_bits() as i64 / (2 * side);
        let at = c.to_bits() as i64 - len.to_bits() as i64 / 2 + offset;
        ((at + (1 << 15)) >> Q16::FRAC_BITS).clamp(i32::MIN as i64, i32::MAX as i64) as i32
    }

    /// Calls `f(column, row, bin)` for every sample in `ranges` (columns, rows; see
    /// [`SampleBox::ranges`]), row by row; returns the samples read.
    fn for_each_bin<Bn: Binning, P: PixelFormat>(
        &self,
        frame: &ImageView<'_, P>,
        ranges: Ranges,
        mut f: impl FnMut(usize, usize, u16),
    ) -> u32 {
        let side = self.side();
        let ((x0, x1), (y0, y1)) = ranges;
        let (x1, y1) = (x1.min(side), y1.min(side));
        let mut columns = [0i32; MAX_SIDE];
        for (i, x) in columns.iter_mut().enumerate().take(x1).skip(x0) {
            *x = self.pixel(self.cx, self.width, i);
        }
        for row in y0..y1 {
            let y = self.pixel(self.cy, self.height, row);
            for (col, &x) in columns.iter().enumerate().take(x1).skip(x0) {
                f(col, row, frame.bin::<Bn>(x, y));
            }
        }
        (x1.saturating_sub(x0) * y1.saturating_sub(y0)) as u32
    }

    /// Every sample's index ranges.
    fn all(&self) -> Ranges {
        ((0, self.side()), (0, self.side()))
    }
}

/// Sample index ranges, `((x0, x1), (y0, y1))`: columns `x0..x1`, rows `y0..y1`.
type Ranges = ((usize, usize), (usize, usize));

/// A box of samples, Q16.16 sample units: columns `x0..x1`, rows `y0..y1`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SampleBox {
    /// Left edge, samples, Q16.16.
    pub x0: Q16,
    /// Top edge, samples, Q16.16.
    pub y0: Q16,
    /// Right edge, samples, Q16.16.
    pub x1: Q16,
    /// Bottom edge, samples, Q16.16.
    pub y1: Q16,
}

impl SampleBox {
    /// The box of `size` (width, height) centred on `centre`, samples, Q16.16.
    pub fn centred(centre: (Q16, Q16), size: (Q16, Q16)) -> Self {
        let half = |v: Q16| Q16::from_bits(v.to_bits() / 2);
        Self {
            x0: centre.0.saturating_sub(half(size.0)),
            y0: centre.1.saturating_sub(half(size.1)),
            x1: centre.0.saturating_add(half(size.0)),
            y1: centre.1.saturating_add(half(size.1)),
        }
    }

    /// Its sample index ranges on a `side x side` grid: the samples whose centre lies
    /// inside, at least one each way.
    fn ranges(&self, side: usize) -> Ranges {
        let range = |a: Q16, b: Q16| {
            let n = side as i64;
            // ceil(v - 1/2) in samples.
            let first = |v: Q16| (v.to_bits() as i64 - (1 << 15) + 0xFFFF) >> Q16::FRAC_BITS;
            let lo = first(a).max(0).min(n - 1);
            let hi = first(b).max(0).min(n).max(lo + 1);
            (lo as usize, hi as usize)
        };
        (range(self.x0, self.x1), range(self.y0, self.y1))
    }

    #[inline]
    fn contains(ranges: &Ranges, col: usize, row: usize) -> bool {
        let ((x0, x1), (y0, y1)) = *ranges;
        (x0..x1).contains(&col) && (y0..y1).contains(&row)
    }
}

/// Object and surroundings histograms over `B` colour bins, and the object probability of
/// each bin (see the module documentation).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ColourModel<const B: usize> {
    /// `O`, Q0.24.
    object: [u32; B],
    /// `S`, Q0.24.
    surroundings: [u32; B],
    /// `P(object | u)`, Q0.16.
    prob: [u16; B],
}

impl<const B: usize> Default for ColourModel<B> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const B: usize> ColourModel<B> {
    /// An empty model: every colour's probability 0.
    pub const fn new() -> Self {
        Self {
            object: [0; B],
            surroundings: [0; B],
            prob: [0; B],
        }
    }

    /// `P(object | u)` per bin, Q0.16.
    pub fn prob(&self) -> &[u16; B] {
        &self.prob
    }

    /// Blends in the histograms of the samples of `map`'s grid in `object` and outside
    /// `target` at `rate` (Q16.16 in `[0, 1]`; 1 replaces the model); `frame` is the one
    /// `map` was built on. Returns the samples read: those in `object` and `target`'s
    /// bounding box.
    pub fn learn<Bn: Binning, P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        map: &ColourMap<B>,
        object: &SampleBox,
        target: &SampleBox,
        rate: Q16,
    ) -> u32 {
        const { assert!(Bn::BINS == B, "the binning must have B bins") };
        let grid = &map.grid;
        let side = grid.side();
        let (inner, outer) = (object.ranges(side), target.ranges(side));
        // The surroundings: the grid's samples less those in `target`.
        let mut counts = [[0u16; B], map.counts];
        let mut totals = [0u32, map.samples];
        let span = |a: (usize, usize), b: (usize, usize)| (a.0.min(b.0), a.1.max(b.1));
        let both = (span(inner.0, outer.0), span(inner.1, outer.1));
        let samples = grid.for_each_bin::<Bn, P>(frame, both, |col, row, bin| {
            let b = bin as usize;
            if SampleBox::contains(&inner, col, row) {
                if let Some(c) = counts[0].get_mut(b) {
                    *c += 1;
                    totals[0] += 1;
                }
            }
            if SampleBox::contains(&outer, col, row) {
                if let Some(c) = counts[1].get_mut(b) {
                    *c = c.saturating_sub(1);
                    totals[1] = totals[1].saturating_sub(1);
                }
            }
        });
        let rate = rate.to_bits().clamp(0, 1 << 16) as u64;
        for ((model, counts), total) in [&mut self.object, &mut self.surroundings]
            .into_iter()
            .zip(&counts)
            .zip(totals)
        {
            if total == 0 {
                continue;
            }
            for (h, &c) in model.iter_mut().zip(counts.iter()) {
                let new = match c {
                    0 => 0,
                    _ => div_u64_u32(u64::from(c) << HIST_BITS, total),
                };
                let blended = ((1 << 16) - rate) * *h as u64 + rate * new;
                *h = (blended >> 16) as u32;
            }
        }
        for ((p, &o), &s) in self
            .prob
            .iter_mut()
            .zip(self.object.iter())
            .zip(self.surroundings.iter())
        {
            // `o <= sum < 2^25`: the quotient is at most 65535.
            let sum = u64::from(o) + u64::from(s);
            *p = match o {
                0 => 0,
                _ => div_u64_u32(u64::from(o) * 65535, sum as u32).min(65535) as u16,
            };
        }
        samples
    }
}

/// The object probability of the samples of a grid, as an integral image, and the
/// histogram of the samples over the `B` colour bins.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ColourMap<const B: usize> {
    /// The grid it was built on (side 0 before the first build).
    grid: Grid,
    /// Samples of each bin.
    counts: [u16; B],
    /// Samples counted in `counts`.
    samples: u32,
    /// `integral[r * STRIDE + c]`: sum of the probabilities (Q0.16) above row `r` and left
    /// of column `c` (`<= 64^2 * 65535 < 2^28`).
    integral: [u32; STRIDE * STRIDE],
}

impl<const B: usize> Default for ColourMap<B> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const B: usize> ColourMap<B> {
    /// An empty map, every bit zero (a `static` of one takes no flash): every box's mean
    /// 0.
    pub const fn new() -> Self {
        Self {
            grid: Grid {
                cx: Q16::ZERO,
                cy: Q16::ZERO,
                width: Q16::ZERO,
                height: Q16::ZERO,
                side: 0,
            },
            counts: [0; B],
            samples: 0,
            integral: [0; STRIDE * STRIDE],
        }
    }

    /// Builds the map of `grid` from `model`'s probabilities; returns the samples read.
    pub fn build<Bn: Binning, P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        grid: &Grid,
        model: &ColourModel<B>,
    ) -> u32 {
        const { assert!(Bn::BINS == B, "the binning must have B bins") };
        self.grid = Grid {
            side: grid.side(),
            ..*grid
        };
        self.integral[..STRIDE].fill(0);
        self.counts.fill(0);
        let (mut run, mut counted) = (0u32, 0u32);
        let (integral, counts) = (&mut self.integral, &mut self.counts);
        let samples = grid.for_each_bin::<Bn, P>(frame, grid.all(), |col, row, bin| {
            if col == 0 {
                run = 0;
                if let Some(v) = integral.get_mut((row + 1) * STRIDE) {
                    *v = 0;
                }
            }
            if let Some(n) = counts.get_mut(bin as usize) {
                *n += 1;
                counted += 1;
            }
            run += model.prob.get(bin as usize).copied().unwrap_or(0) as u32;
            let above = integral.get(row * STRIDE + col + 1).copied().unwrap_or(0);
            if let Some(v) = integral.get_mut((row + 1) * STRIDE + col + 1) {
                *v = above + run;
            }
        });
        self.samples = counted;
        samples
    }

    /// The mean probability over the samples of `b`, Q16.16 in `[0, 1]`.
    pub fn mean(&self, b: &SampleBox) -> Q16 {
        if self.grid.side == 0 {
            return Q16::ZERO;
        }
        let ((x0, x1), (y0, y1)) = b.ranges(self.grid.side);
        let at = |r: usize, c: usize| self.integral.get(r * STRIDE + c).copied().unwrap_or(0);
        let sum = (at(y1, x1) + at(y0, x0)).wrapping_sub(at(y0, x1) + at(y1, x0));
        let count = ((x1 - x0) * (y1 - y0)) as u32;
        Q16::from_bits(sum.checked_div(count).unwrap_or(0) as i32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Rgb888, Rgb8x8x8};
    use std::vec::Vec;

    /// A 20 x 20 frame: red square (px 5..15) on green, one blue pixel in the red.
    fn frame() -> Vec<u8> {
        (0..400)
            .flat_map(|i| {
                let (x, y) = (i % 20, i / 20);
                if (x, y) == (10, 10) {
                    [0, 0, 250]
                } else if (5..15).contains(&x) && (5..15).contains(&y) {
                    [250, 0, 0]
                } else {
                    [0, 250, 0]
                }
            })
            .collect()
    }

    fn q(v: f64) -> Q16 {
        Q16::from_f64(v)
    }

    /// The whole frame, one sample a pixel.
    fn grid() -> Grid {
        Grid {
            cx: q(9.5),
            cy: q(9.5),
            width: q(20.0),
            height: q(20.0),
            side: 20,
        }
    }

    fn square(c: f64, s: f64) -> SampleBox {
        SampleBox::centred((q(c), q(c)), (q(s), q(s)))
    }

    /// Learns the samples of `grid` in `object` and outside `target` into `model`, through
    /// a map built on them; returns the samples learning read.
    fn learn(
        model: &mut ColourModel<512>,
        img: &ImageView<'_, Rgb888>,
        grid: &Grid,
        object: &SampleBox,
        target: &SampleBox,
        rate: Q16,
    ) -> u32 {
        let mut map = ColourMap::new();
        map.build::<Rgb8x8x8, _>(img, grid, &ColourModel::new());
        model.learn::<Rgb8x8x8, _>(img, &map, object, target, rate)
    }

    #[test]
    fn object_colours_score_one_and_surrounding_colours_zero() {
        let buf = frame();
        let img = ImageView::<Rgb888>::new(&buf, 20, 20, 20).unwrap();
        let mut model = ColourModel::<512>::new();
        let target = square(10.0, 10.0);
        // Learning reads the target's 100 samples again, not the grid's 400.
        assert_eq!(
            learn(&mut model, &img, &grid(), &target, &target, Q16::ONE),
            100
        );
        let mut map = ColourMap::new();
        assert_eq!(map.build::<Rgb8x8x8, _>(&img, &grid(), &model), 400);
        // The red square is all object, a box on the green all surroundings.
        assert_eq!(map.mean(&square(10.0, 8.0)), Q16::from_bits(65535));
        assert_eq!(map.mean(&square(2.0, 4.0)), Q16::ZERO);
        // Half on the square, half off: half object.
        let half = SampleBox::centred((q(5.0), q(10.0)), (q(4.0), q(4.0)));
        assert!((map.mean(&half).to_f64() - 0.5).abs() < 1e-3);
    }

    #[test]
    fn a_colour_in_both_scores_by_its_densities() {
        // The object box also covers one ring of green: 99 red, 1 blue, 44 green of 144
        // object samples; 300 green of 300 surrounding samples.
        let buf = frame();
        let img = ImageView::<Rgb888>::new(&buf, 20, 20, 20).unwrap();
        let mut model = ColourModel::<512>::new();
        learn(
            &mut model,
            &img,
            &grid(),
            &square(10.0, 12.0),
            &square(10.0, 10.0),
            Q16::ONE,
        );
        let green = model.prob()[img.bin::<Rgb8x8x8>(0, 0) as usize] as f64 / 65535.0;
        let (o, s) = (44.0 / 144.0, 1.0);
        assert!((green - o / (o + s)).abs() < 1e-4, "{green}");
    }

    #[test]
    fn learning_blends_the_histograms() {
        let buf = frame();
        let swapped: Vec<u8> = buf.chunks(3).flat_map(|p| [p[1], p[0], p[2]]).collect();
        let img = ImageView::<Rgb888>::new(&buf, 20, 20, 20).unwrap();
        let other = ImageView::<Rgb888>::new(&swapped, 20, 20, 20).unwrap();
        let target = square(10.0, 10.0);
        let mut model = ColourModel::<512>::new();
        learn(&mut model, &img, &grid(), &target, &target, Q16::ONE);
        learn(&mut model, &other, &grid(), &target, &target, Q16::HALF);
        // Red is now half object (first frame), half surroundings (second).
        let red = model.prob()[img.bin::<Rgb8x8x8>(6, 10) as usize] as f64 / 65535.0;
        let (o, s) = (0.5 * 99.0 / 100.0, 0.5 * 300.0 / 300.0);
        assert!((red - o / (o + s)).abs() < 1e-4, "{red}");
    }

    #[test]
    fn a_region_off_the_frame_repeats_its_edge() {
        let buf = frame();
        let img = ImageView::<Rgb888>::new(&buf, 20, 20, 20).unwrap();
        let off = Grid {
            cx: q(-100.0),
            cy: q(500.0),
            width: q(1e4),
            height: q(0.0),
            side: 1000,
        };
        let mut model = ColourModel::<512>::new();
        let all = square(32.0, 64.0);
        assert_eq!(learn(&mut model, &img, &off, &all, &all, Q16::ONE), 64 * 64);
        let mut map = ColourMap::new();
        map.build::<Rgb8x8x8, _>(&img, &off, &model);
        assert_eq!(map.mean(&all), Q16::from_bits(65535));
    }

    /// Histograms counted over every sample of `grid` (the definition learning
    /// follows), as `(object, surroundings)` counts per bin.
    fn counted(
        img: &ImageView<'_, Rgb888>,
        grid: &Grid,
        object: &SampleBox,
        target: &SampleBox,
    ) -> [[u32; 512]; 2] {
        let side = grid.side();
        let (inner, outer) = (object.ranges(side), target.ranges(side));
        let mut counts = [[0u32; 512]; 2];
        grid.for_each_bin::<Rgb8x8x8, _>(img, grid.all(), |col, row, bin| {
            if SampleBox::contains(&inner, col, row) {
                counts[0][bin as usize] += 1;
            }
            if !SampleBox::contains(&outer, col, row) {
                counts[1][bin as usize] += 1;
            }
        });
        counts
    }

    proptest::proptest! {
        /// Learning from the map's histogram and the target's samples gives the model
        /// that counting every sample gives, on any grid over the frame and any boxes.
        #[test]
        fn learning_from_the_map_counts_every_sample(
            pixels in proptest::collection::vec(0u8..=255, 3 * 24 * 18),
            cx in -10.0f64..34.0, cy in -10.0f64..28.0,
            width in 0.0f64..60.0, height in 0.0f64..60.0, side in 1usize..80,
            t in (-5.0f64..70.0, -5.0f64..70.0, 0.0f64..80.0, 0.0f64..80.0),
            shrink in 0.0f64..1.0,
        ) {
            let img = ImageView::<Rgb888>::new(&pixels, 24, 18, 24).unwrap();
            let grid = Grid { cx: q(cx), cy: q(cy), width: q(width), height: q(height), side };
            let target = SampleBox::centred((q(t.0), q(t.1)), (q(t.2), q(t.3)));
            let object = SampleBox::centred((q(t.0), q(t.1)), (q(t.2 * shrink), q(t.3 * shrink)));
            let mut model = ColourModel::<512>::new();
            learn(&mut model, &img, &grid, &object, &target, Q16::ONE);
            let [o, s] = counted(&img, &grid, &object, &target);
            let (no, ns) = (o.iter().sum::<u32>(), s.iter().sum::<u32>());
            let share = |c: u32, n: u32| ((u64::from(c) << HIST_BITS) / u64::from(n.max(1))) as u32;
            for b in 0..512 {
                let (ob, sb) = (share(o[b], no), share(s[b], ns));
                proptest::prop_assert_eq!(model.object[b], ob);
                proptest::prop_assert_eq!(model.surroundings[b], sb);
                let p = (u64::from(ob) * 65535).checked_div(u64::from(ob + sb)).unwrap_or(0);
                proptest::prop_assert_eq!(u64::from(model.prob[b]), p);
            }
        }
    }
}
