//! The target's colour model against its surroundings: the target histogram (whole, or
//! its upper and lower halves apart), the histogram of a ring around it, the
//! background-weighted model and the per-bin object probability.
//!
//! # Background weighting (CBWH)
//! With `o_u` the ring's normalised histogram and `o*` its smallest non-zero bin, the
//! corrected background-weighted histogram (Ning et al., IET Computer Vision 2012)
//! weights the target model by `v_u = min(o* / o_u, 1)` and renormalises:
//! `q'_u = C v_u q_u`. Colours common around the target count less; a window is scored by
//! its Bhattacharyya coefficient against `q'`. `o*` is the smallest non-zero bin, but at
//! least a floor share of the ring ([`ColourSettings::background`]): one stray pixel in
//! the ring then cannot make every other ring colour nearly worthless.
//!
//! # Object probability
//! `P(object | u) = q_u / (q_u + o_u)` (DAT, Possegger et al. 2015; Staple, Bertinetto et
//! al. 2016), each histogram normalised to 1; a colour seen neither on the target nor
//! around it has `1/2`. [`crate::map::ObjectMap`] looks it up per pixel.
//!
//! # Halves
//! With [`ColourSettings::split_halves`] the rows above the window's centre and those
//! from the centre down have a model each, and a window's score is the mean of the two
//! halves' coefficients: a pedestrian in a light shirt and dark trousers no longer matches
//! a window of the same colours the other way up. Every pixel still goes into one
//! histogram, so a window costs what a whole one costs, plus two coefficients. The whole
//! window keeps a model too: its plain coefficient is the confidence, its `q` the object
//! probability's.
//!
//! Everything here is computed when the model is learnt or adapted, once per frame at
//! most: `B` divisions and square roots. Windows are compared at the cost of
//! [`Histogram::fill`] and [`Histogram::coefficient`].

use crate::fixed::{sqrt_q8, Q16};
use crate::hist::{blend, Histogram, Model, PROB_FRAC_BITS, PROB_ONE};
use crate::image::{Binning, ImageView, PixelFormat};
use crate::window::Ellipse;

/// `P(object | u) = 1`: the object probabilities are Q0.16, `u16::MAX` standing for 1.
pub const OBJECT_PROB_ONE: u16 = u16::MAX;

/// `P(object | u)` of a colour seen neither on the target nor around it, Q0.16 (1/2).
pub const OBJECT_PRIOR: u16 = 1 << 15;

/// How a [`ColourModel`] is laid out and weighted.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ColourSettings {
    /// Model the upper and lower halves of the window apart.
    pub split_halves: bool,
    /// Background weighting, with the floor of `o*` as a share of the ring, Q16.16 in
    /// `[0, 1]`; `None`: target-only model (the surroundings still give the object
    /// probability).
    pub background: Option<Q16>,
    /// Outer scale of the surroundings ring, relative to the window, Q16.16 above 1.
    pub ring_scale: Q16,
    /// Pixels sampled per window, px; the ring's outer ellipse is sampled with twice as
    /// many.
    pub cap: u32,
}

/// A window compared with a [`ColourModel`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Match {
    /// Bhattacharyya coefficient against the target model (mean of the halves' when
    /// split), Q16.16 in `[0, 1]`: how much the window looks like the target.
    pub rho: Q16,
    /// The coefficient that scores the window: against the background-weighted model, or
    /// `rho` without background weighting, Q16.16 in `[0, 1]`.
    pub score: Q16,
    /// Pixels read, px.
    pub pixels: u32,
}

/// The target's colour model against its surroundings (see the module documentation).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ColourModel<const B: usize> {
    settings: ColourSettings,
    /// The whole window's model.
    whole: Model<B>,
    /// The upper and lower halves' models (empty unless split).
    halves: [Model<B>; 2],
    /// `sqrt(q'_u)` of the background-weighted models that score a window: the whole
    /// window's in `[0]`, or the halves'.
    weighted: [[u32; B]; 2],
    /// The ring's normalised histogram `o_u`, Q0.30 (all 0 before [`ColourModel::learn`]).
    surroundings: [u32; B],
    /// `P(object | u)`, Q0.16.
    object_prob: [u16; B],
}

#[cfg(feature = "defmt")]
impl<const B: usize> defmt::Format for ColourModel<B> {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(f, "ColourModel {{ bins: {}, {} }}", B, self.settings)
    }
}

impl<const B: usize> ColourModel<B> {
    /// Every bit zero, with zero settings: the colour model of an unstarted tracker, for
    /// [`ColourModel::configure`] to set up.
    pub const UNSET: Self = Self {
        settings: ColourSettings {
            split_halves: false,
            background: None,
            ring_scale: Q16::ZERO,
            cap: 0,
        },
        whole: Model::new(),
        halves: [Model::new(), Model::new()],
        weighted: [[0; B]; 2],
        surroundings: [0; B],
        object_prob: [0; B],
    };

    /// An empty model: every window's coefficients are 0, every object probability
    /// [`OBJECT_PRIOR`].
    pub const fn new(settings: ColourSettings) -> Self {
        Self {
            settings,
            whole: Model::new(),
            halves: [Model::new(), Model::new()],
            weighted: [[0; B]; 2],
            surroundings: [0; B],
            object_prob: [OBJECT_PRIOR; B],
        }
    }

    /// The settings.
    pub fn settings(&self) -> &ColourSettings {
        &self.settings
    }

    /// Empties the model in place and takes `settings` (what [`ColourModel::new`] gives,
    /// without a model-sized value on the stack).
    pub fn configure(&mut self, settings: ColourSettings) {
        self.settings = settings;
        self.whole.clear();
        for half in self.halves.iter_mut() {
            half.clear();
        }
        for table in self.weighted.iter_mut() {
            table.fill(0);
        }
        self.surroundings.fill(0);
        self.object_prob.fill(OBJECT_PRIOR);
    }

    /// Learns the model from the window `e` of `img` and the ring around it, replacing
    /// what it knew; `scratch` holds the histograms on the way. Returns the pixels read
    /// (the whole window, its halves and the ring).
    pub fn learn<Bn: Binning, P: PixelFormat>(
        &mut self,
        img: &ImageView<'_, P>,
        e: &Ellipse,
        scratch: &mut [Histogram<B>; 2],
    ) -> u32 {
        self.configure(self.settings);
        self.adapt::<Bn, P>(img, e, scratch, Q16::ONE)
    }

    /// Blends the window `e` and the ring around it into the model at `rate` (Q16.16 in
    /// `[0, 1]`: `q <- (1 - rate) q + rate p`, the ring likewise). Returns the pixels
    /// read.
    pub fn adapt<Bn: Binning, P: PixelFormat>(
        &mut self,
        img: &ImageView<'_, P>,
        e: &Ellipse,
        scratch: &mut [Histogram<B>; 2],
        rate: Q16,
    ) -> u32 {
        let cap = self.settings.cap;
        let [first, second] = scratch;
        let mut pixels = first.fill::<Bn, P>(img, e, cap);
        self.whole.update(first, rate);
        if self.settings.split_halves {
            pixels += Histogram::fill_halves::<Bn, P>(first, second, img, e, cap);
            self.halves[0].update(first, rate);
            self.halves[1].update(second, rate);
        }
        let ring = first;
        let ring_cap = cap.saturating_mul(2);
        pixels += ring.fill_ring::<Bn, P>(img, e, self.settings.ring_scale, ring_cap);
        if !ring.is_empty() {
            blend(&mut self.surroundings, ring, rate);
        }
        self.derive();
        pixels
    }

    /// Compares the window `e` of `img` with the model; `scratch` holds its histograms.
    #[inline]
    pub fn compare<Bn: Binning, P: PixelFormat>(
        &self,
        img: &ImageView<'_, P>,
        e: &Ellipse,
        scratch: &mut [Histogram<B>; 2],
    ) -> Match {
        let pixels = self.fill::<Bn, P>(img, e, scratch);
        let [first, second] = &*scratch;
        let rho = match self.settings.split_halves {
            true => first.coefficient_with(second, self.whole.sqrt_table()),
            false => first.coefficient(self.whole.sqrt_table()),
        };
        let score = self.score_filled(scratch);
        Match { rho, score, pixels }
    }

    /// [`Match::score`] of the window `e` and the pixels read: [`ColourModel::compare`]
    /// without the confidence, the per-particle path.
    #[inline]
    pub fn score<Bn: Binning, P: PixelFormat>(
        &self,
        img: &ImageView<'_, P>,
        e: &Ellipse,
        scratch: &mut [Histogram<B>; 2],
    ) -> (Q16, u32) {
        let pixels = self.fill::<Bn, P>(img, e, scratch);
        (self.score_filled(scratch), pixels)
    }

    /// Fills `scratch` from the window `e`: the whole window into `scratch[0]`, or its
    /// halves into both. Returns the pixels read.
    #[inline]
    fn fill<Bn: Binning, P: PixelFormat>(
        &self,
        img: &ImageView<'_, P>,
        e: &Ellipse,
        scratch: &mut [Histogram<B>; 2],
    ) -> u32 {
        let [first, second] = scratch;
        let cap = self.settings.cap;
        match self.settings.split_halves {
            true => Histogram::fill_halves::<Bn, P>(first, second, img, e, cap),
            false => first.fill::<Bn, P>(img, e, cap),
        }
    }

    /// The score of the window whose histograms `scratch` holds ([`ColourModel::fill`]):
    /// its (background-weighted) coefficient, or the mean of the halves' (the one half, if
    /// the other is empty).
    #[inline]
    fn score_filled(&self, scratch: &[Histogram<B>; 2]) -> Q16 {
        let background = self.settings.background.is_some();
        let parts = if self.settings.split_halves { 2 } else { 1 };
        let (mut sum, mut filled) = (0i32, 0i32);
        for ((hist, model), weighted) in scratch
            .iter()
            .zip(self.scoring_models())
            .zip(self.weighted.iter())
            .take(parts)
        {
            if !hist.is_empty() {
                let table = if background {
                    weighted
                } else {
                    model.sqrt_table()
                };
                sum += hist.coefficient(table).to_bits();
                filled += 1;
            }
        }
        Q16::from_bits(sum.checked_div(filled).unwrap_or(0))
    }

    /// The models that score windows: the whole window's, or the halves'.
    fn scoring_models(&self) -> [&Model<B>; 2] {
        match self.settings.split_halves {
            true => [&self.halves[0], &self.halves[1]],
            false => [&self.whole, &self.whole],
        }
    }

    /// `P(object | u)` per bin, Q0.16.
    pub fn object_prob(&self) -> &[u16; B] {
        &self.object_prob
    }

    /// The surroundings' normalised histogram `o_u`, Q0.30.
    pub fn surroundings(&self) -> &[u32; B] {
        &self.surroundings
    }

    /// The whole window's target model.
    pub fn whole(&self) -> &Model<B> {
        &self.whole
    }

    /// The upper (`0`) or lower (`1`) half's target model, when split.
    pub fn half(&self, i: usize) -> Option<&Model<B>> {
        self.halves.get(i).filter(|_| self.settings.split_halves)
    }

    /// `sqrt(q'_u)`, Q0.23, of the background-weighted model that scores windows: the
    /// whole window's (`0`) or, when split, a half's (`0` upper, `1` lower); `None`
    /// without background weighting.
    pub fn weighted_sqrt(&self, i: usize) -> Option<&[u32; B]> {
        let parts = if self.settings.split_halves { 2 } else { 1 };
        self.weighted
            .get(i)
            .filter(|_| i < parts && self.settings.background.is_some())
    }

    /// Recomputes the background-weighted models and the object probabilities.
    fn derive(&mut self) {
        // The floor's share of the ring, Q16.16, as a probability (Q0.30).
        let floor = |share: Q16| share.clamp(Q16::ZERO, Q16::ONE).to_bits() as u64;
        let o_floor =
            self.settings.background.map_or(0, floor) << (PROB_FRAC_BITS - Q16::FRAC_BITS);
        let o_min = self.surroundings.iter().copied().filter(|&o| o > 0).min();
        let o_star = o_min.map(|o| (o as u64).max(o_floor));
        let scoring = match self.settings.split_halves {
            true => [&self.halves[0], &self.halves[1]],
            false => [&self.whole, &self.whole],
        };
        for (model, weighted) in scoring.into_iter().zip(self.weighted.iter_mut()) {
            reweight(model.probabilities(), &self.surroundings, o_star, weighted);
        }
        for (u, p) in self.object_prob.iter_mut().enumerate() {
            let q = self.whole.q(u) as u64;
            let o = self.surroundings.get(u).copied().unwrap_or(0) as u64;
            *p = (q * OBJECT_PROB_ONE as u64)
                .checked_div(q + o)
                .map_or(OBJECT_PRIOR, |v| v as u16);
        }
    }
}

/// `out[u] = sqrt(q'_u)` (Q0.23) for `q'_u = C v_u q_u`, `v_u = min(o* / o_u, 1)`
/// (`q`, `o` Q0.30); `sqrt(q_u)` where no surroundings are known (`o_star` `None`).
fn reweight<const B: usize>(q: &[u32; B], o: &[u32; B], o_star: Option<u64>, out: &mut [u32; B]) {
    let weight = |q: u32, o: u32| -> u64 {
        match o_star {
            Some(o_star) if o as u64 > o_star => q as u64 * o_star / o as u64,
            _ => q as u64,
        }
    };
    let total: u64 = q.iter().zip(o.iter()).map(|(&q, &o)| weight(q, o)).sum();
    for ((s, &q), &o) in out.iter_mut().zip(q.iter()).zip(o.iter()) {
        let w = (weight(q, o) << PROB_FRAC_BITS)
            .checked_div(total)
            .unwrap_or(0);
        *s = sqrt_q8(w.min(PROB_ONE as u64) as u32);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Binning, Gray8, Luma64};
    use crate::window::visit;
    use std::vec;
    use std::vec::Vec;

    const W: usize = 13;
    /// Luma values and their Luma64 bins.
    const TOP: u8 = 220;
    const BOTTOM: u8 = 120;
    const BACK: u8 = 40;

    /// A 13x13 frame: a 5x5 target at (6, 6), its rows 4-5 `TOP`, rows 6-8 `BOTTOM`, on
    /// `BACK`, with a `BOTTOM` stripe in column 2 (in the ring, not in the window).
    fn frame(upside_down: bool) -> Vec<u8> {
        let mut buf = vec![BACK; W * W];
        for y in 4..9 {
            let v = if (y < 6) != upside_down { TOP } else { BOTTOM };
            buf[y * W + 4..y * W + 9].fill(v);
            buf[y * W + 2] = BOTTOM;
        }
        buf
    }

    fn settings(split_halves: bool, floor: Option<f64>) -> ColourSettings {
        ColourSettings {
            split_halves,
            background: floor.map(Q16::from_f64),
            ring_scale: Q16::from_int(2),
            cap: 1000,
        }
    }

    fn window() -> Ellipse {
        let h = Q16::from_f64(2.5);
        Ellipse::new(Q16::from_int(6), Q16::from_int(6), h, h)
    }

    /// The f64 reference: kernel-weighted window histogram and uniform ring histogram
    /// (the same pixels as the core), both normalised.
    fn reference(img: &ImageView<'_, Gray8>) -> (Vec<f64>, Vec<f64>) {
        let e = window();
        let mut q = vec![0f64; 64];
        visit(img, &e, 1000, |row, x, w| {
            q[row.bin::<Luma64>(x) as usize] += w as f64
        });
        let mut o = vec![0f64; 64];
        for y in 0..W as i32 {
            for x in 0..W as i32 {
                let d2 = ((x - 6) * (x - 6) + (y - 6) * (y - 6)) as f64 / 6.25;
                if (1.0..4.0).contains(&d2) {
                    o[img.bin::<Luma64>(x, y) as usize] += 1.0;
                }
            }
        }
        let norm = |v: &mut Vec<f64>| {
            let s: f64 = v.iter().sum();
            v.iter_mut().for_each(|x| *x /= s);
        };
        norm(&mut q);
        norm(&mut o);
        (q, o)
    }

    #[test]
    fn weighted_model_and_object_probability_match_f64() {
        let buf = frame(false);
        let img = ImageView::<Gray8>::new(&buf, W, W, W).unwrap();
        let (q, o) = reference(&img);
        for floor in [0.0, 0.05] {
            let mut m = ColourModel::<64>::new(settings(false, Some(floor)));
            let mut scratch = [Histogram::new(), Histogram::new()];
            m.learn::<Luma64, Gray8>(&img, &window(), &mut scratch);
            let o_min = o.iter().copied().filter(|&v| v > 0.0).fold(1.0, f64::min);
            let o_star = o_min.max(floor);
            let w: Vec<f64> = (0..64)
                .map(|u| {
                    if o[u] > o_star {
                        q[u] * o_star / o[u]
                    } else {
                        q[u]
                    }
                })
                .collect();
            let total: f64 = w.iter().sum();
            let table = m.weighted_sqrt(0).unwrap();
            for u in 0..64 {
                let want = (w[u] / total).sqrt();
                let got = table[u] as f64 / (1u32 << 23) as f64;
                assert!(
                    (got - want).abs() < 1e-4,
                    "floor {floor} bin {u}: {got} {want}"
                );
                let p = if q[u] + o[u] > 0.0 {
                    q[u] / (q[u] + o[u])
                } else {
                    0.5
                };
                let got_p = m.object_prob()[u] as f64 / 65535.0;
                assert!((got_p - p).abs() < 2e-4, "bin {u}: {got_p} {p}");
            }
            // The stripe's colour is common in the ring: against the target's top it counts
            // less than in the plain model.
            let (top, bottom) = (
                Luma64::from_luma(TOP) as usize,
                Luma64::from_luma(BOTTOM) as usize,
            );
            let plain = m.whole().sqrt_table();
            let ratio = |t: &[u32; 64]| t[bottom] as f64 / t[top] as f64;
            assert!(ratio(table) < 0.8 * ratio(plain), "floor {floor}");
            assert!(m.object_prob()[top] > m.object_prob()[bottom]);
            assert_eq!(
                m.object_prob()[Luma64::from_luma(255) as usize],
                OBJECT_PRIOR
            );
        }
    }

    #[test]
    fn halves_tell_a_target_from_its_upside_down_twin() {
        let buf = frame(false);
        let flipped = frame(true);
        let img = ImageView::<Gray8>::new(&buf, W, W, W).unwrap();
        let twin = ImageView::<Gray8>::new(&flipped, W, W, W).unwrap();
        let mut scratch = [Histogram::new(), Histogram::new()];
        for split in [false, true] {
            let mut m = ColourModel::<64>::new(settings(split, None));
            m.learn::<Luma64, Gray8>(&img, &window(), &mut scratch);
            let own = m.compare::<Luma64, Gray8>(&img, &window(), &mut scratch);
            let other = m.compare::<Luma64, Gray8>(&twin, &window(), &mut scratch);
            assert!(own.score > Q16::from_f64(0.999) && own.rho > Q16::from_f64(0.999));
            assert!(own.pixels > 0);
            // The whole window's coefficient (the confidence) ignores the layout.
            let whole_twin = other.rho.to_f64();
            if split {
                assert!(other.score.to_f64() < whole_twin - 0.3, "{other:?}");
                assert!(m.half(1).is_some());
            } else {
                assert_eq!(other.score, other.rho);
                assert!(m.half(0).is_none());
            }
        }
    }

    #[test]
    fn empty_model_and_empty_windows_score_zero() {
        let buf = frame(false);
        let img = ImageView::<Gray8>::new(&buf, W, W, W).unwrap();
        let mut scratch = [Histogram::new(), Histogram::new()];
        let m = ColourModel::<64>::new(settings(true, Some(0.01)));
        let r = m.compare::<Luma64, Gray8>(&img, &window(), &mut scratch);
        assert_eq!((r.rho, r.score), (Q16::ZERO, Q16::ZERO));
        let mut m = ColourModel::<64>::new(settings(true, Some(0.01)));
        m.learn::<Luma64, Gray8>(&img, &window(), &mut scratch);
        let outside = Ellipse::new(Q16::from_int(-50), Q16::from_int(-50), Q16::ONE, Q16::ONE);
        let r = m.compare::<Luma64, Gray8>(&img, &outside, &mut scratch);
        assert_eq!((r.rho, r.score, r.pixels), (Q16::ZERO, Q16::ZERO, 0));
    }
}
