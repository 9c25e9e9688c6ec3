//! Kernel-weighted colour histograms of windows, the target models made from them and the
//! Bhattacharyya coefficient between the two, in integers.
//!
//! A [`Histogram<B>`] sums the Q0.16 Epanechnikov weights of a window's pixels
//! ([`crate::window`]) into `B` bins chosen by a [`Binning`]; `fill::<Bn, P>` checks at
//! compile time that `Bn::BINS == B`. It keeps the list of bins it touched, so clearing it
//! and comparing it with a model cost time in proportion to the touched bins, not to `B`.
//! Counts and the total mass are `u32` in weight units (1 pixel at the centre adds
//! 65536); a single window never saturates them (at most 65535 pixels of weight at most
//! 65536), and adding several windows saturates instead of wrapping.
//!
//! A [`Model<B>`] is the normalised target histogram `q` (Q0.30 per bin, sum 1) with its
//! square roots precomputed. The Bhattacharyya coefficient of a window histogram `n`
//! (mass `N`) against it is
//! `rho = sum_u sqrt(n_u / N) sqrt(q_u) = (sum_u sqrt(n_u) sqrt(q_u)) / sqrt(N)`:
//! one square root per touched bin (by [`sqrt_q8`]: a 193-entry table, linear
//! interpolation) and one division per window. Against an f64 computation of the same
//! quantity (f64 kernel weights, same pixels) the error is below 2e-3 (see
//! `host-tests/tests/hist_reference.rs`, which prints max and RMS).
//!
//! # Examples
//! ```
//! use rbtrack::fixed::Q16;
//! use rbtrack::hist::{Histogram, Model};
//! use rbtrack::image::{ImageView, Rgb565Le, Rgb8x8x8};
//! use rbtrack::window::Ellipse;
//! // 8 x 8 frame: left half red (0xF800), right half blue (0x001F).
//! let mut buf = [0u8; 8 * 8 * 2];
//! for (i, px) in buf.chunks_exact_mut(2).enumerate() {
//!     px.copy_from_slice(&if i % 8 < 4 { 0xF800u16 } else { 0x001F }.to_le_bytes());
//! }
//! let img = ImageView::<Rgb565Le>::new(&buf, 8, 8, 8)?;
//! let q = |v: i32| Q16::from_int(v);
//! let mut h = Histogram::<512>::new();
//! h.fill::<Rgb8x8x8, _>(&img, &Ellipse::new(q(1), q(4), q(2), q(3)), 256);
//! assert_eq!(h.touched(), &[0b111_000_000]); // red only
//! let red = Model::from_histogram(&h);
//! assert!(h.bhattacharyya(&red) > Q16::from_f64(0.999));
//! h.fill::<Rgb8x8x8, _>(&img, &Ellipse::new(q(6), q(4), q(1), q(3)), 256);
//! assert_eq!(h.bhattacharyya(&red), Q16::ZERO); // blue only
//! # Ok::<(), rbtrack::image::ImageError>(())
//! ```
//!
//! The binning must have `B` bins:
//! ```compile_fail
//! # use rbtrack::{hist::Histogram, image::{Gray8, ImageView, Rgb8x8x8}, window::Ellipse};
//! let img = ImageView::<Gray8>::new(&[0], 1, 1, 1).unwrap();
//! let mut h = Histogram::<256>::new();
//! h.fill::<Rgb8x8x8, _>(&img, &Ellipse::default(), 16); // 512 bins != 256
//! ```

use crate::fixed::{div_u64_u32, sqrt_q8, Q16, SQRT_FRAC_BITS};
use crate::image::{Binning, ImageView, PixelFormat};
use crate::window::{rows, Ellipse, MAX_CAP, WEIGHT_ONE};

mod model;

pub(crate) use model::blend;
pub use model::Model;

/// Fraction bits of a probability: Q0.30, [`PROB_ONE`] being 1.
pub const PROB_FRAC_BITS: u32 = 30;

/// 1.0 in Q0.30, the scale of model probabilities.
pub const PROB_ONE: u32 = 1 << PROB_FRAC_BITS;

/// Fraction bits of the square root of a probability, `sqrt(q_u)` ([`sqrt_q8`] of a Q0.30
/// value): Q0.23.
pub const SQRT_PROB_FRAC_BITS: u32 = PROB_FRAC_BITS / 2 + SQRT_FRAC_BITS;

/// How a fill weighs a pixel from its kernel weight `w` (Q0.16, `<= WEIGHT_ONE`).
trait Weighting: Copy {
    /// The pixel's weight, at most [`WEIGHT_ONE`].
    fn weight(self, w: u32) -> u32;
}

/// A window's pixels: their kernel weight.
#[derive(Clone, Copy)]
struct Kernel;

impl Weighting for Kernel {
    #[inline(always)]
    fn weight(self, w: u32) -> u32 {
        w
    }
}

/// A ring's pixels: [`WEIGHT_ONE`] where the outer kernel weight is in `(0, edge]`, the
/// part of the outer ellipse outside the inner one; 0 elsewhere.
#[derive(Clone, Copy)]
struct Ring {
    edge: u32,
}

impl Weighting for Ring {
    #[inline(always)]
    fn weight(self, w: u32) -> u32 {
        if w > 0 && w <= self.edge {
            WEIGHT_ONE
        } else {
            0
        }
    }
}

/// Clears `upper` (and `lower`) and adds the pixels of the window `e` of `img`, each
/// weighed by `weighting`: every row into `upper`, or, given `lower`, the rows from the
/// centre row `round(e.cy)` down into it. Returns the number of pixels visited
/// (`<= cap`). One copy per weighting, called from every fill (the per-pixel loop is
/// inlined inside it).
#[inline(never)]
fn fill_rows<Bn: Binning, P: PixelFormat, const B: usize>(
    upper: &mut Histogram<B>,
    mut lower: Option<&mut Histogram<B>>,
    img: &ImageView<'_, P>,
    e: &Ellipse,
    cap: u32,
    weighting: impl Weighting,
) -> u32 {
    const { assert!(Bn::BINS == B, "the binning must have B bins") };
    upper.clear();
    if let Some(lower) = lower.as_deref_mut() {
        lower.clear();
    }
    let split = e.cy.round_int().max(0) as usize;
    let cap = cap.min(MAX_CAP);
    let runs = img.runs();
    let n = rows(img, e, cap, |run| {
        let h = match lower.as_deref_mut() {
            Some(lower) if run.y >= split => lower,
            _ => &mut *upper,
        };
        let (counts, touched) = (&mut h.counts, &mut h.touched);
        let mut weights = run.weights;
        runs.for_each_bin::<Bn>(run.y, run.pixels, |bin| {
            let w = weighting.weight(weights.next());
            if let Some(c) = counts.get_mut(bin as usize) {
                if *c == 0 && w != 0 {
                    let listed = touched.push(bin);
                    debug_assert!(
                        listed.is_ok(),
                        "a bin enters the list once, while its count is 0"
                    );
                }
                // One window's mass is below 2^32 (window::MAX_CAP pixels of weight at
                // most 2^16), so no count of a cleared histogram can wrap.
                *c = c.wrapping_add(w);
            }
        });
    });
    upper.recount_mass();
    if let Some(lower) = lower {
        lower.recount_mass();
    }
    n
}

/// `table[u]` for a touched bin `u`: always below `B` (a bin enters the touched list
/// only through its count), so the fallback 0 never serves.
#[inline(always)]
fn entry<const B: usize>(table: &[u32; B], u: usize) -> u32 {
    debug_assert!(u < B, "touched bin {u} out of range");
    table.get(u).copied().unwrap_or(0)
}

/// `acc / sqrt(mass)` for a sum `acc` of `sqrt_q8(n_u) sqrt(q_u)` (Q8 times Q0.23 = Q31),
/// rounded, as Q16.16 clamped to `[0, 1]`; 0 for no mass.
#[inline]
fn ratio(acc: u64, mass: u32) -> Q16 {
    // Q31 / (Q8 << 7) = Q16; sqrt_q8 < 2^24.
    let den = sqrt_q8(mass) << (SQRT_PROB_FRAC_BITS - Q16::FRAC_BITS);
    if den == 0 {
        return Q16::ZERO;
    }
    let rho = div_u64_u32(acc + (den / 2) as u64, den);
    Q16::from_bits(rho.min(Q16::ONE.to_bits() as u64) as i32)
}

/// A kernel-weighted colour histogram of `B` bins (`1 <= B <= 65536`).
#[derive(Clone, Debug)]
pub struct Histogram<const B: usize> {
    /// Kernel mass per bin, weight units (Q0.16 per pixel), saturating.
    counts: [u32; B],
    /// Bins with a non-zero count, in the order first touched.
    touched: heapless::Vec<u16, B>,
    /// Sum of `counts`, weight units, saturating.
    mass: u32,
}

#[cfg(feature = "defmt")]
impl<const B: usize> defmt::Format for Histogram<B> {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "Histogram {{ bins: {}, touched: {}, mass: {} }}",
            B,
            self.touched.len(),
            self.mass
        )
    }
}

impl<const B: usize> Default for Histogram<B> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const B: usize> Histogram<B> {
    /// An empty histogram.
    pub const fn new() -> Self {
        const { assert!(B >= 1 && B <= 1 << 16, "bins must fit a u16 index") };
        Self {
            counts: [0; B],
            touched: heapless::Vec::new(),
            mass: 0,
        }
    }

    /// Empties the histogram, in time proportional to the touched bins.
    #[inline]
    pub fn clear(&mut self) {
        for &u in self.touched.iter() {
            debug_assert!((u as usize) < B, "touched bin {u} out of range");
            if let Some(c) = self.counts.get_mut(u as usize) {
                *c = 0;
            }
        }
        self.touched.clear();
        self.mass = 0;
    }

    /// Adds `weight` (Q0.16 kernel weight) to `bin` (`< B`; larger bins are ignored).
    #[inline(always)]
    pub fn add(&mut self, bin: u16, weight: u32) {
        let Some(c) = self.counts.get_mut(bin as usize) else {
            return;
        };
        if *c == 0 && weight != 0 {
            let listed = self.touched.push(bin);
            debug_assert!(
                listed.is_ok(),
                "a bin enters the list once, while its count is 0"
            );
        }
        *c = c.saturating_add(weight);
        self.mass = self.mass.saturating_add(weight);
    }

    /// Clears the histogram and fills it from the window `e` of `img`: at most `cap` pixels
    /// (px, see [`crate::window::visit`]), binned by `Bn` (which must have `B` bins; checked
    /// at compile time). Returns the number of pixels visited.
    ///
    /// Cost per pixel: the bin, the kernel weight, a load, compare and store of the bin's
    /// count (no saturation: one window's mass is below `2^32`); the pixels of a row are
    /// read as one slice of the frame.
    #[inline]
    pub fn fill<Bn: Binning, P: PixelFormat>(
        &mut self,
        img: &ImageView<'_, P>,
        e: &Ellipse,
        cap: u32,
    ) -> u32 {
        fill_rows::<Bn, P, B>(self, None, img, e, cap, Kernel)
    }

    /// Clears `upper` and `lower` and fills them from the window `e` as [`Histogram::fill`]
    /// would fill one: the rows above the centre row `round(e.cy)` into `upper`, the
    /// others into `lower`. Returns the number of pixels visited (both halves).
    #[inline]
    pub fn fill_halves<Bn: Binning, P: PixelFormat>(
        upper: &mut Self,
        lower: &mut Self,
        img: &ImageView<'_, P>,
        e: &Ellipse,
        cap: u32,
    ) -> u32 {
        fill_rows::<Bn, P, B>(upper, Some(lower), img, e, cap, Kernel)
    }

    /// Clears the histogram and fills it from the ring between the ellipse `inner` and the
    /// same ellipse scaled by `scale` (Q16.16, above 1): the surroundings of a target whose
    /// window is `inner`. The outer ellipse is sampled as [`Histogram::fill`] samples a
    /// window (at most `cap` pixels); the sampled pixels outside `inner` count
    /// [`WEIGHT_ONE`] each. Returns the number of pixels visited.
    pub fn fill_ring<Bn: Binning, P: PixelFormat>(
        &mut self,
        img: &ImageView<'_, P>,
        inner: &Ellipse,
        scale: Q16,
        cap: u32,
    ) -> u32 {
        let outer = Ellipse {
            hx: inner.hx.saturating_mul(scale),
            hy: inner.hy.saturating_mul(scale),
            ..*inner
        };
        // A pixel at normalised distance d from the centre of `outer` is inside `inner`
        // when d < 1 / scale, that is when its kernel weight 1 - d^2 exceeds 1 - 1/scale^2.
        let inv = Q16::ONE / scale.max(Q16::ONE);
        let edge = (Q16::ONE - inv * inv).to_bits().clamp(0, WEIGHT_ONE as i32) as u32;
        fill_rows::<Bn, P, B>(self, None, img, &outer, cap, Ring { edge })
    }

    /// Sets the mass to the sum of the touched bins' counts (below `2^32` after a fill).
    #[inline]
    fn recount_mass(&mut self) {
        self.mass = self
            .touched
            .iter()
            .map(|&u| entry(&self.counts, u as usize))
            .fold(0u32, u32::wrapping_add);
    }

    /// Total kernel mass, weight units (65536 per centre pixel), `0..=u32::MAX`.
    #[inline]
    pub fn mass(&self) -> u32 {
        self.mass
    }

    /// Whether no pixel with a non-zero weight was added.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.mass == 0
    }

    /// Kernel mass of `bin`, weight units; 0 for `bin >= B`.
    #[inline]
    pub fn count(&self, bin: usize) -> u32 {
        self.counts.get(bin).copied().unwrap_or(0)
    }

    /// All bin counts, weight units.
    pub fn counts(&self) -> &[u32; B] {
        &self.counts
    }

    /// Bins with a non-zero count, in the order first touched.
    pub fn touched(&self) -> &[u16] {
        &self.touched
    }

    /// Normalised count `p_u = n_u / N` of `bin`, Q0.30 (`0..=PROB_ONE`), rounded down;
    /// 0 for an empty histogram or `bin >= B`. This is the `p` of the adaptive model
    /// update ([`Model::update`]).
    #[inline]
    pub fn probability(&self, bin: usize) -> u32 {
        if self.mass == 0 {
            return 0;
        }
        ((self.count(bin) as u64 * PROB_ONE as u64) / self.mass as u64) as u32
    }

    /// The Bhattacharyya coefficient `rho = sum_u sqrt(p_u q_u)` of this histogram against
    /// `model`, Q16.16 in `[0, 1]`; 0 when either is empty.
    ///
    /// Cost: one [`sqrt_q8`] and one multiply-add per touched bin, one division.
    #[inline]
    pub fn bhattacharyya(&self, model: &Model<B>) -> Q16 {
        self.coefficient(model.sqrt_table())
    }

    /// [`Histogram::coefficient`] of the sum of this histogram and `other` (counts and
    /// masses added), without forming it: two windows' halves compared as one.
    #[inline]
    pub fn coefficient_with(&self, other: &Histogram<B>, sqrt_q: &[u32; B]) -> Q16 {
        let mass = self.mass.saturating_add(other.mass);
        let sq = |u: usize| entry(sqrt_q, u) as u64;
        // Bins of `self` (with `other`'s count added), then those only `other` touched.
        let mut acc = 0u64;
        for &u in self.touched.iter() {
            let u = u as usize;
            acc += sqrt_q8(self.count(u).saturating_add(other.count(u))) as u64 * sq(u);
        }
        for &u in other.touched.iter() {
            let u = u as usize;
            if self.count(u) == 0 {
                acc += sqrt_q8(other.count(u)) as u64 * sq(u);
            }
        }
        ratio(acc, mass)
    }

    /// `sum_u sqrt(n_u / N) sqrt_q[u]` for a table `sqrt_q` of square roots of a
    /// distribution (Q0.23, summing in square to about 1), Q16.16 in `[0, 1]`; 0 when the
    /// histogram is empty. [`Histogram::bhattacharyya`] with any model's table.
    #[inline]
    pub fn coefficient(&self, sqrt_q: &[u32; B]) -> Q16 {
        if self.mass == 0 {
            return Q16::ZERO;
        }
        let mut acc = 0u64; // Q8 * Q0.23 = Q31; <= sqrt(N) 2^31 <= 2^47
        for &u in self.touched.iter() {
            let u = u as usize;
            let sq = entry(sqrt_q, u) as u64;
            acc += sqrt_q8(self.count(u)) as u64 * sq;
        }
        ratio(acc, self.mass)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{
        Gray8, Luma64, Rgb565Be, Rgb565Le, Rgb888, Rgb8x8x4, Rgb8x8x8, Yuv422, Yuv8x8x4,
    };
    use crate::rng::Rng;
    use crate::window::{visit, MAX_CAP, WEIGHT_ONE};
    use std::vec;
    use std::vec::Vec;

    fn noise(len: usize, seed: u64) -> Vec<u8> {
        let mut r = Rng::new(seed);
        (0..len).map(|_| r.next_u32() as u8).collect()
    }

    /// RAM of the per-window scratch histogram and of the model, for 512 bins.
    #[test]
    fn sizes() {
        use core::mem::size_of;
        assert_eq!(size_of::<Model<512>>(), 4096);
        assert!(size_of::<Histogram<512>>() <= 512 * 4 + 512 * 2 + 16);
    }

    #[test]
    fn mass_equals_kernel_sum_every_format() {
        fn run<P: PixelFormat>(bytes_per_px: usize) {
            let (w, h, stride) = (30usize, 20usize, 34usize);
            let buf = noise(stride * h * bytes_per_px, 9);
            let img = ImageView::<P>::new(&buf, w, h, stride).unwrap();
            let e = Ellipse::from_f64(14.6, 9.2, 11.0, 7.5);
            let mut kernel = 0u64;
            let mut per_bin = vec![0u64; 512];
            visit(&img, &e, 300, |row, x, wt| {
                kernel += wt as u64;
                per_bin[row.bin::<Rgb8x8x8>(x) as usize] += wt as u64;
            });
            let mut hist = Histogram::<512>::new();
            let n = hist.fill::<Rgb8x8x8, P>(&img, &e, 300);
            assert!(n > 100 && n <= 300);
            assert_eq!(hist.mass() as u64, kernel);
            assert_eq!(hist.counts().iter().map(|&c| c as u64).sum::<u64>(), kernel);
            for (u, &c) in per_bin.iter().enumerate() {
                assert_eq!(hist.count(u) as u64, c);
            }
            let mut touched: Vec<u16> = hist.touched().to_vec();
            touched.sort();
            touched.dedup();
            assert_eq!(touched.len(), hist.touched().len());
            assert_eq!(touched.len(), per_bin.iter().filter(|&&c| c > 0).count());
        }
        run::<Gray8>(1);
        run::<Rgb565Le>(2);
        run::<Rgb565Be>(2);
        run::<Rgb888>(3);
        run::<Yuv422>(2);
    }

    #[test]
    fn every_binning_fills() {
        let buf = noise(16 * 16 * 2, 3);
        let img = ImageView::<Rgb565Le>::new(&buf, 16, 16, 16).unwrap();
        let e = Ellipse::from_f64(8.0, 8.0, 6.0, 6.0);
        let mut h8 = Histogram::<512>::new();
        let mut h4 = Histogram::<256>::new();
        let mut hy = Histogram::<256>::new();
        let mut hl = Histogram::<64>::new();
        let n = h8.fill::<Rgb8x8x8, _>(&img, &e, 1000);
        assert_eq!(h4.fill::<Rgb8x8x4, _>(&img, &e, 1000), n);
        assert_eq!(hy.fill::<Yuv8x8x4, _>(&img, &e, 1000), n);
        assert_eq!(hl.fill::<Luma64, _>(&img, &e, 1000), n);
        let mass = h8.mass();
        assert!(mass > 0);
        assert_eq!(h4.mass(), mass);
        assert_eq!(hy.mass(), mass);
        assert_eq!(hl.mass(), mass);
    }

    #[test]
    fn clear_resets_only_what_was_touched() {
        let buf = noise(32 * 32, 4);
        let img = ImageView::<Gray8>::new(&buf, 32, 32, 32).unwrap();
        let mut h = Histogram::<64>::new();
        h.fill::<Luma64, _>(&img, &Ellipse::from_f64(16.0, 16.0, 10.0, 10.0), 500);
        assert!(!h.is_empty());
        h.clear();
        assert!(h.is_empty());
        assert!(h.touched().is_empty());
        assert!(h.counts().iter().all(|&c| c == 0));
        h.add(5, 0); // zero weight: not touched
        assert!(h.touched().is_empty());
        h.add(64, 100); // out of range: ignored
        assert!(h.is_empty());
    }

    #[test]
    fn empty_window_gives_zero() {
        let img = ImageView::<Gray8>::new(&[1, 2, 3, 4], 2, 2, 2).unwrap();
        let mut h = Histogram::<64>::new();
        h.fill::<Luma64, _>(&img, &Ellipse::from_f64(1.0, 1.0, 1.0, 1.0), 10);
        let model = Model::from_histogram(&h);
        assert_eq!(
            h.fill::<Luma64, _>(&img, &Ellipse::from_f64(-9.0, 1.0, 1.0, 1.0), 10),
            0
        );
        assert_eq!(h.bhattacharyya(&model), Q16::ZERO);
        assert_eq!(h.probability(0), 0);
        assert!(Model::from_histogram(&h).is_empty());
        h.fill::<Luma64, _>(&img, &Ellipse::from_f64(1.0, 1.0, 1.0, 1.0), 10);
        assert_eq!(h.bhattacharyya(&Model::new()), Q16::ZERO);
        // An empty histogram leaves the model alone.
        let mut m = model.clone();
        m.update(&Histogram::new(), Q16::HALF);
        assert_eq!(m, model);
    }

    #[test]
    fn own_model_gives_one_and_rho_never_exceeds_one() {
        let mut r = Rng::new(11);
        let mut h = Histogram::<512>::new();
        let mut g = Histogram::<512>::new();
        for trial in 0..300 {
            // Few colours (blocky) or pure noise.
            let (w, hgt) = (40usize, 30usize);
            let buf: Vec<u8> = if trial % 2 == 0 {
                noise(w * hgt * 3, trial)
            } else {
                (0..w * hgt)
                    .flat_map(|i| {
                        let c = ((i % w) / 10 + 4 * ((i / w) / 10)) as u8;
                        [c.wrapping_mul(71), c.wrapping_mul(29), c.wrapping_mul(113)]
                    })
                    .collect()
            };
            let img = ImageView::<Rgb888>::new(&buf, w, hgt, w).unwrap();
            let e1 = Ellipse::from_f64(
                r.below(40) as f64,
                r.below(30) as f64,
                1.0 + r.below(25) as f64,
                1.0 + r.below(25) as f64,
            );
            let e2 = Ellipse::from_f64(
                r.below(40) as f64,
                r.below(30) as f64,
                1.0 + r.below(25) as f64,
                1.0 + r.below(25) as f64,
            );
            let cap = 1 + r.below(2000);
            h.fill::<Rgb8x8x8, _>(&img, &e1, cap);
            g.fill::<Rgb8x8x8, _>(&img, &e2, cap);
            let m = Model::from_histogram(&h);
            if !h.is_empty() {
                let own = h.bhattacharyya(&m).to_f64();
                assert!((own - 1.0).abs() < 1e-3, "own {own}");
            }
            let rho = g.bhattacharyya(&m);
            assert!(rho >= Q16::ZERO && rho <= Q16::ONE);
        }
    }

    #[test]
    fn saturated_pixels_and_huge_mass() {
        // All pixels white, biggest cap: one bin holds the whole mass, no saturation.
        let (w, h) = (300usize, 300usize);
        let buf = vec![0xFFu8; w * h * 2];
        let img = ImageView::<Rgb565Be>::new(&buf, w, h, w).unwrap();
        let e = Ellipse::from_f64(150.0, 150.0, 140.0, 140.0);
        let mut hist = Histogram::<512>::new();
        let n = hist.fill::<Rgb8x8x8, _>(&img, &e, u32::MAX);
        assert!(n <= MAX_CAP && n > MAX_CAP / 2, "{n}");
        assert_eq!(hist.touched(), &[511]);
        assert!(hist.mass() < u32::MAX);
        assert_eq!(hist.count(511), hist.mass());
        let m = Model::from_histogram(&hist);
        assert_eq!(m.q(511), PROB_ONE);
        assert_eq!(hist.bhattacharyya(&m), Q16::ONE);
        // Accumulating more windows saturates the mass and the bin, never wraps.
        for _ in 0..4 {
            visit(&img, &e, u32::MAX, |row, x, w| {
                hist.add(row.bin::<Rgb8x8x8>(x), w)
            });
        }
        assert_eq!(hist.mass(), u32::MAX);
        assert_eq!(hist.bhattacharyya(&m), Q16::ONE);
        // The largest per-window mass fits: 65535 centre-weight pixels.
        let mut big = Histogram::<64>::new();
        for _ in 0..MAX_CAP {
            big.add(1, WEIGHT_ONE);
        }
        assert_eq!(big.mass(), MAX_CAP * WEIGHT_ONE);
        assert!(big.bhattacharyya(&Model::from_histogram(&big)) == Q16::ONE);
    }

    #[test]
    fn hand_computed_histogram() {
        // 3 x 1 gray frame, unit circle on the middle pixel: only it has weight > 0.
        let img = ImageView::<Gray8>::new(&[0, 100, 255], 3, 1, 3).unwrap();
        let mut h = Histogram::<64>::new();
        assert_eq!(
            h.fill::<Luma64, _>(&img, &Ellipse::from_f64(1.0, 0.0, 1.0, 1.0), 100),
            1
        );
        assert_eq!(h.touched(), &[25]);
        assert_eq!(h.mass(), WEIGHT_ONE);
        // Wider: the side pixels sit at d = 1/2, weight 3/4.
        h.fill::<Luma64, _>(&img, &Ellipse::from_f64(1.0, 0.0, 2.0, 1.0), 100);
        assert_eq!(h.touched(), &[0, 25, 63]);
        assert_eq!(h.count(0), 49152);
        assert_eq!(h.count(63), 49152);
        assert_eq!(h.mass(), WEIGHT_ONE + 2 * 49152);
        assert_eq!(h.probability(25), (PROB_ONE as u64 * 65536 / 163840) as u32);
        // Against the model of the middle pixel alone: rho = sqrt(65536 / 163840).
        let mut mid = Histogram::<64>::new();
        mid.add(25, 1000);
        let rho = h.bhattacharyya(&Model::from_histogram(&mid)).to_f64();
        assert!((rho - 0.4f64.sqrt()).abs() < 2e-5, "{rho}");
    }

    /// An 11x11 Gray8 frame: a 5x5 bright square (220) centred at (5, 5) on 40.
    fn square_frame() -> Vec<u8> {
        let mut buf = vec![40u8; 11 * 11];
        for y in 3..8 {
            buf[y * 11 + 3..y * 11 + 8].fill(220);
        }
        buf
    }

    #[test]
    fn ring_counts_only_the_surroundings() {
        let buf = square_frame();
        let img = ImageView::<Gray8>::new(&buf, 11, 11, 11).unwrap();
        let bright = Luma64::from_luma(220) as usize;
        let dark = Luma64::from_luma(40) as usize;
        let mut ring = Histogram::<64>::new();
        // Window: the square's inscribed circle (radius 2.5); ring out to radius 5.
        let inner = Ellipse::from_f64(5.0, 5.0, 2.5, 2.5);
        let n = ring.fill_ring::<Luma64, Gray8>(&img, &inner, Q16::from_int(2), 1000);
        // By hand: pixels at distance d from (5, 5) with 2.5 <= d < 5 count one unit each:
        // 69 pixels have d^2 < 25, 21 of them d^2 <= 6, so 48 are in the ring, of which the
        // square's 4 corners (d^2 = 8) are bright.
        let (mut want_bright, mut want_dark) = (0, 0);
        for y in 0..11i32 {
            for x in 0..11i32 {
                let d2 = ((x - 5) * (x - 5) + (y - 5) * (y - 5)) as f64;
                if (6.25..25.0).contains(&d2) {
                    let is_bright = (3..8).contains(&x) && (3..8).contains(&y);
                    *if is_bright {
                        &mut want_bright
                    } else {
                        &mut want_dark
                    } += 1;
                }
            }
        }
        assert!(n >= 69, "the whole outer disc is sampled at step 1: {n}");
        assert_eq!(ring.count(bright), want_bright * WEIGHT_ONE);
        assert_eq!(ring.count(dark), want_dark * WEIGHT_ONE);
        assert_eq!(ring.mass(), (want_bright + want_dark) * WEIGHT_ONE);
        assert_eq!((want_bright, want_dark), (4, 44));
    }

    #[test]
    fn halves_split_the_rows_and_sum_to_the_window() {
        let buf = noise(30 * 20 * 3, 11);
        let img = ImageView::<Rgb888>::new(&buf, 30, 20, 30).unwrap();
        let e = Ellipse::from_f64(14.2, 9.6, 9.0, 7.0);
        let mut whole = Histogram::<512>::new();
        let (mut upper, mut lower) = (Histogram::<512>::new(), Histogram::<512>::new());
        let n = whole.fill::<Rgb8x8x8, Rgb888>(&img, &e, 300);
        assert_eq!(
            Histogram::fill_halves::<Rgb8x8x8, Rgb888>(&mut upper, &mut lower, &img, &e, 300),
            n
        );
        let (mut above, mut below) = (vec![0u32; 512], vec![0u32; 512]);
        visit(&img, &e, 300, |row, x, w| {
            let counts = if row.y() < 10 { &mut above } else { &mut below };
            counts[row.bin::<Rgb8x8x8>(x) as usize] += w;
        });
        assert_eq!(&upper.counts()[..], &above[..]);
        assert_eq!(&lower.counts()[..], &below[..]);
        for u in 0..512 {
            assert_eq!(whole.count(u), upper.count(u) + lower.count(u));
        }
        let model = Model::from_histogram(&whole);
        let joint = upper.coefficient_with(&lower, model.sqrt_table());
        assert_eq!(joint, whole.bhattacharyya(&model));
        assert!(joint > Q16::from_f64(0.999));
    }
}
