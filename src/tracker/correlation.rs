//! The correlation-filter tracker (Staple-class: Bertinetto et al., CVPR 2016), in
//! integers: the port of the host's f64 `cf64` tracker, which is its reference in the
//! tests.
//!
//! # One step
//! 1. The search region (the target plus `padding` times the mean of its sides, each way),
//!    centred `lead` of the smoothed velocity ahead of the last position, is resampled to
//!    `G x G` cells of `cell` px, each the mean luma and 9 fHOG channels
//!    ([`crate::cf::features`]).
//! 2. The translation filter answers with a response over the grid
//!    ([`crate::cf::filter`]), one value per move of whole cells.
//! 3. The colour model gives, per move, the mean object probability of a target-sized
//!    box there ([`crate::cf::colour`], `2G x 2G` samples of the region).
//! 4. The two merge as `(1 - merge) filter + merge colour` over the moves that keep the
//!    target box inside the region, each axis on its own; the best move, refined between
//!    cells by parabolas, is the new position. The score is the merged response's margin:
//!    its peak less the best value of the moves beyond the peak's lobe (more than
//!    [`LOBE`] cells from it on either axis), high where one clear peak stands out, low
//!    where the response is flat or a look-alike answers as well; the score through the
//!    tracker's table ([`crate::tracker::calibration`]) is the confidence, which sets the
//!    status.
//! 5. The scale filter ([`crate::cf::scale`]) finds the size there, at most
//!    `max_scale_change` away from the last; the size changes only when the merged peak is
//!    at least `scale_above`, and below both it and `learn_above` the scale samples are
//!    not taken.
//! 6. When the merged peak is at least `learn_above`, the three models learn the frame:
//!    the search region's spectra and colour samples with the target where it was found,
//!    and the scale samples.
//!
//! When the merged peak falls below `search_below` the tracker searches for the target
//! until a peak reaches `search_until`. Each frame of a search searches one region
//! besides the usual one ([`search_offset`]): where the target was last seen (the anchor:
//! an occluded target reappears there, while the usual search follows the best peak,
//! often the occluder) for its first [`ANCHOR_FRAMES`] frames, then the anchor's and
//! `redetect` regions of a ring half a region around it in turn; it may centre its
//! searches where the velocity it had when the search began puts it (`coast`). Such a
//! region takes over only when its merged peak and colour score clear `redetect_above`
//! and `redetect_colour` and its peak beats the usual region's; the frame it takes over
//! only moves the target (nothing is learnt), and no frame of a search takes scale
//! samples (the size holds).
//! The search follows the peak, the status the margin: a look-alike beside the target
//! lowers the status while the tracker stays where it is; once `Lost`, the status stays
//! so while the search lasts, until the confidence reaches `uncertain_below`.
//! A frame of a search is then at most 2 searches and the filter's and colour model's
//! learning (1.94 M instructions on a lost frame at the defaults, against 1.87 M on the
//! mean tracked frame: `examples/budget.rs`). By default the ring has 2 regions between
//! the anchor's and the search does not coast (docs/accuracy.md measures both).
//!
//! # Memory
//! `size_of::<CfTracker<Bn, B, G, S>>()` is dominated by the translation filter (its
//! numerator and the last spectra, half spectra of `10 G (G/2 + 1)` complex values each),
//! the feature grid (`20 G^2` bytes), the colour map (`4 (2G + 1)^2 + 2 B` bytes) and the scale
//! filter; `examples/budget.rs` reports it.

use super::{calibration, CameraMotion, ConfigError, Estimate, Status};
use crate::cf::colour::{ColourMap, ColourModel, Grid, SampleBox};
use crate::cf::features::{Cell, Extractor, Sampling, CHANNELS};
use crate::cf::filter::{Filter, FilterSettings};
use crate::cf::scale::{ScaleFilter, ScaleSettings};
use crate::fixed::Q16;
use crate::image::{Binning, ImageView, PixelFormat};
use crate::profile::{CfStageCycles, CycleCounter, NoCounter, Stopwatch};
use crate::rect::Rect;
use crate::window::Ellipse;
use core::marker::PhantomData;

/// Smallest target side, px.
const MIN_SIDE: i32 = 4;

/// Moves within this many cells of the merged response's peak, each way, lie in its lobe;
/// the margin (the score) is taken over those beyond.
pub const LOBE: i32 = 2;

/// The re-detection ring: offsets from where the target was last seen, half regions.
const RING: [(i32, i32); 8] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (1, 1),
    (-1, -1),
    (1, -1),
    (-1, 1),
];

/// The frames of a search that search the anchor's region alone besides the usual one: an
/// occluded target reappears where it was last seen within about this many frames; one
/// lost for longer is looked for on the ring too.
pub const ANCHOR_FRAMES: usize = 20;

/// The region a search frame searches besides the usual one, as an offset from the anchor
/// in half regions (`(0, 0)` the anchor's own), or `None` with `redetect` 0: frame `k` of
/// a search (from 0) searches the anchor's for the first [`ANCHOR_FRAMES`] frames, then
/// the anchor's and `redetect` ring regions in turn, one a frame.
pub fn search_offset(k: usize, redetect: usize) -> Option<(i32, i32)> {
    if redetect == 0 {
        return None;
    }
    let Some(k) = k.checked_sub(ANCHOR_FRAMES) else {
        return Some((0, 0));
    };
    // A round is the anchor's region and `redetect` ring regions.
    let round = redetect.saturating_add(1);
    let (n, j) = (k / round, k % round);
    Some(match j.checked_sub(1) {
        None => (0, 0),
        Some(j) => RING[n.wrapping_mul(redetect).wrapping_add(j) % RING.len()],
    })
}

/// The correlation-filter tracker's settings. [`CfConfig::default`] is the configuration
/// docs/accuracy.md measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct CfConfig {
    /// Context around the target: the search region is the target plus this times the
    /// mean of its width and height, each way, Q16.16 above 0.
    pub padding: Q16,
    /// Cell side, px of the resampled region, `2..=8`, even.
    pub cell: usize,
    /// Width of the translation filter's desired response: this share of the target's
    /// `sqrt(w h)`, Q16.16 above 0.
    pub sigma: Q16,
    /// Regulariser of the translation filter, units of `2^-30` of a squared feature
    /// ([`FilterSettings::lambda`]).
    pub lambda: u32,
    /// Learning rate of the translation filter, Q16.16 in `[0, 1]`.
    pub cf_rate: Q16,
    /// Learning rate of the colour histograms, Q16.16 in `[0, 1]`.
    pub colour_rate: Q16,
    /// The object's histogram is taken this share of the target's mean side inside its
    /// box, Q16.16 in `[0, 1)`.
    pub inner_padding: Q16,
    /// Weight of the colour response in the merged response, Q16.16 in `[0, 1]`.
    pub merge: Q16,
    /// The scale filter's settings.
    pub scale: ScaleSettings,
    /// Learning rate of the scale filter, Q16.16 in `[0, 1]`.
    pub scale_rate: Q16,
    /// Largest change of size in a frame, a factor, Q16.16 at least 1.
    pub max_scale_change: Q16,
    /// Learn only from frames whose merged peak is at least this, Q16.16.
    pub learn_above: Q16,
    /// Change the size only on frames whose merged peak is at least this, Q16.16: a
    /// frame too unsure of where the target is cannot say how big it is.
    pub scale_above: Q16,
    /// Below this confidence the target is uncertain, Q16.16 in `[0, 1]` (by default the
    /// threshold every tracker shares, [`calibration::UNCERTAIN_BELOW`]).
    pub uncertain_below: Q16,
    /// Below this confidence it is lost, Q16.16 in `[0, uncertain_below]` (by default
    /// [`calibration::LOST_BELOW`]); once lost, it stays lost while the tracker searches
    /// (below), until the confidence reaches `uncertain_below`.
    pub lost_below: Q16,
    /// Below this merged peak the target is searched for ([`CfConfig::redetect`],
    /// [`CfConfig::coast`]), until the peak reaches `search_until`, Q16.16 in
    /// `[0, search_until]`.
    pub search_below: Q16,
    /// The merged peak that ends a search, Q16.16 in `[0, 1]`.
    pub search_until: Q16,
    /// Ring regions a search visits between two searches of the anchor's region, one
    /// region a frame besides the usual one ([`search_offset`]), `0..=8`: the next of a
    /// ring of 8, each half a region from where the target was last seen (0: no
    /// re-detection, not even the anchor's).
    pub redetect: usize,
    /// A searched region takes over when its merged peak is at least this, Q16.16...
    pub redetect_above: Q16,
    /// ...and its colour score (the object probability at its peak) at least this,
    /// Q16.16.
    pub redetect_colour: Q16,
    /// While searching, search where the target would be had it kept the velocity it had
    /// when the search began.
    pub coast: bool,
    /// The search region is centred this share of the smoothed velocity ahead of the last
    /// position, Q16.16 in `[0, 1]` (0: on it).
    pub lead: Q16,
}

impl CfConfig {
    /// The defaults, evaluated at compile time (a firmware links no floating point).
    const DEFAULT: Self = {
        /// A positive value in Q16.16, rounded to nearest.
        const fn q(v: f64) -> Q16 {
            Q16::from_bits((v * 65536.0 + 0.5) as i32)
        }
        Self {
            padding: Q16::ONE,
            cell: 4,
            sigma: q(1.0 / 16.0),
            lambda: 1_073_742,
            cf_rate: q(0.02),
            colour_rate: q(0.04),
            inner_padding: q(0.2),
            merge: q(0.3),
            scale: ScaleSettings {
                step: q(1.18),
                sigma: q(0.25),
                lambda: 4_294_967,
                area: 512,
                cell: 4,
                interpolate: true,
            },
            scale_rate: q(0.025),
            max_scale_change: q(1.08),
            learn_above: q(0.2),
            scale_above: q(0.25),
            uncertain_below: calibration::UNCERTAIN_BELOW,
            lost_below: calibration::LOST_BELOW,
            // 0.2226 and 0.2632.
            search_below: Q16::from_bits(14_586),
            search_until: Q16::from_bits(17_246),
            redetect: 2,
            redetect_above: q(0.3),
            redetect_colour: q(0.5),
            coast: false,
            lead: q(0.5),
        }
    };

    /// Every field zero: the configuration of an unstarted tracker.
    const UNSET: Self = Self {
        padding: Q16::ZERO,
        cell: 0,
        sigma: Q16::ZERO,
        lambda: 0,
        cf_rate: Q16::ZERO,
        colour_rate: Q16::ZERO,
        inner_padding: Q16::ZERO,
        merge: Q16::ZERO,
        scale: ScaleSettings::UNSET,
        scale_rate: Q16::ZERO,
        max_scale_change: Q16::ZERO,
        learn_above: Q16::ZERO,
        scale_above: Q16::ZERO,
        uncertain_below: Q16::ZERO,
        lost_below: Q16::ZERO,
        search_below: Q16::ZERO,
        search_until: Q16::ZERO,
        redetect: 0,
        redetect_above: Q16::ZERO,
        redetect_colour: Q16::ZERO,
        coast: false,
        lead: Q16::ZERO,
    };
}

impl Default for CfConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl CfConfig {
    /// Checks every setting; the error names the first one out of its range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let check =
            |ok: bool, name: &'static str| ok.then_some(()).ok_or(ConfigError::OutOfRange(name));
        let unit = |v: Q16| v >= Q16::ZERO && v <= Q16::ONE;
        check(
            self.padding > Q16::ZERO && self.padding <= Q16::from_int(4),
            "padding",
        )?;
        check(matches!(self.cell, 2 | 4 | 6 | 8), "cell")?;
        check(matches!(self.scale.cell, 2 | 4 | 6 | 8), "scale.cell")?;
        check(self.sigma > Q16::ZERO, "sigma")?;
        check(self.lambda > 0, "lambda")?;
        check(unit(self.cf_rate), "cf_rate")?;
        check(unit(self.colour_rate), "colour_rate")?;
        check(
            unit(self.inner_padding) && self.inner_padding < Q16::ONE,
            "inner_padding",
        )?;
        check(unit(self.merge), "merge")?;
        let step = self.scale.step;
        check(
            step > Q16::ONE && step <= Q16::from_ratio(3, 2),
            "scale.step",
        )?;
        check(unit(self.scale_rate), "scale_rate")?;
        check(self.max_scale_change >= Q16::ONE, "max_scale_change")?;
        check(unit(self.uncertain_below), "uncertain_below")?;
        check(
            self.lost_below >= Q16::ZERO && self.lost_below <= self.uncertain_below,
            "lost_below",
        )?;
        check(unit(self.search_until), "search_until")?;
        check(
            self.search_below >= Q16::ZERO && self.search_below <= self.search_until,
            "search_below",
        )?;
        check(self.redetect <= RING.len(), "redetect")?;
        check(unit(self.redetect_above), "redetect_above")?;
        check(unit(self.redetect_colour), "redetect_colour")?;
        check(unit(self.scale_above), "scale_above")?;
        check(unit(self.lead), "lead")
    }
}

/// Where the search region lies for a target of a given size.
#[derive(Clone, Copy, Debug)]
struct Geometry {
    /// Region size in the frame, px, Q16.16.
    region: (Q16, Q16),
    /// Patch px per frame px, per axis, Q16.16.
    zoom: (Q16, Q16),
    /// Target size in the patch, px, Q16.16.
    target: (Q16, Q16),
}

/// The correlation-filter tracker of a `G x G` grid (a power of two, 8..=32) and `S`
/// scales, on colour histograms of `Bn` (`B` bins).
#[derive(Clone, Debug)]
pub struct CfTracker<Bn: Binning, const B: usize, const G: usize, const S: usize> {
    config: CfConfig,
    frame_size: (i32, i32),
    /// Target centre, px, Q16.16.
    centre: (Q16, Q16),
    /// Target size, px, Q16.16.
    size: (Q16, Q16),
    /// The first box's size, px, the size factor on it (the size is `base` times it,
    /// kept so that no division rounds it frame after frame) and its bounds, Q16.16.
    base: (Q16, Q16),
    factor: Q16,
    factor_bounds: (Q16, Q16),
    filter: Filter<G>,
    scale: ScaleFilter<S>,
    colour: ColourModel<B>,
    map: ColourMap<B>,
    /// The feature extraction's working memory, for the search regions and the scale
    /// samples.
    extractor: Extractor,
    /// The last search region's features.
    cells: [[Cell; G]; G],
    /// The translation filter's last response, Q16.16.
    response: [[i32; G]; G],
    /// The centre's step, smoothed (half the last step and half the previous value), px a
    /// frame, Q16.16.
    velocity: (Q16, Q16),
    /// Where the target was last seen, or, coasting, where the velocity it had then puts
    /// it now, px, Q16.16.
    anchor: (Q16, Q16),
    /// The smoothed velocity when the search began, px a frame, Q16.16.
    lost_velocity: (Q16, Q16),
    /// Frames in a row the target has been searched for.
    search_frames: usize,
    /// The last step's merged peak, Q16.16 in `[0, 1]`.
    peak: Q16,
    estimate: Estimate,
    _binning: PhantomData<Bn>,
}

/// The result of searching one region.
struct Detection {
    /// Target centre, px, Q16.16.
    found: (Q16, Q16),
    /// Its move from the region's centre, patch px, Q16.16.
    moved: (Q16, Q16),
    /// The merged response's peak, Q16.16.
    peak: Q16,
    /// Its margin: the peak less the best value of the moves beyond its lobe (0 where the
    /// search has none), Q16.16.
    margin: Q16,
    /// The colour response at the peak's cell, Q16.16.
    colour: Q16,
    geometry: Geometry,
}

impl<Bn: Binning, const B: usize, const G: usize, const S: usize> CfTracker<Bn, B, G, S> {
    /// Colour samples a side of the search region.
    const COLOUR_SIDE: usize = 2 * G;

    /// A tracker that has not started: every bit zero (a `static` of one takes no
    /// flash), its estimate lost at the origin until [`CfTracker::start`].
    pub const fn unstarted() -> Self {
        const {
            assert!(G.is_power_of_two() && G >= 8 && G <= 32, "G: 8, 16 or 32");
            assert!(Bn::BINS == B, "the binning must have B bins");
        };
        let origin = Ellipse::new(Q16::ZERO, Q16::ZERO, Q16::ZERO, Q16::ZERO);
        Self {
            config: CfConfig::UNSET,
            frame_size: (0, 0),
            centre: (Q16::ZERO, Q16::ZERO),
            size: (Q16::ZERO, Q16::ZERO),
            base: (Q16::ZERO, Q16::ZERO),
            factor: Q16::ZERO,
            factor_bounds: (Q16::ZERO, Q16::ZERO),
            filter: Filter::UNSET,
            scale: ScaleFilter::UNSET,
            colour: ColourModel::new(),
            map: ColourMap::new(),
            extractor: Extractor::NEW,
            cells: [[[0; CHANNELS]; G]; G],
            response: [[0; G]; G],
            velocity: (Q16::ZERO, Q16::ZERO),
            anchor: (Q16::ZERO, Q16::ZERO),
            lost_velocity: (Q16::ZERO, Q16::ZERO),
            search_frames: 0,
            peak: Q16::ZERO,
            estimate: Estimate::lost_at(origin),
            _binning: PhantomData,
        }
    }

    /// A tracker started on `frame` with the target in `init` (px). On a board, start an
    /// [`CfTracker::unstarted`] `static` in place instead: this value is large.
    pub fn new<P: PixelFormat>(
        config: CfConfig,
        frame: &ImageView<'_, P>,
        init: Rect,
    ) -> Result<Self, ConfigError> {
        let mut tracker = Self::unstarted();
        tracker.start(config, frame, init)?;
        Ok(tracker)
    }

    /// (Re)starts in place on `frame` with the target in `init` (px): the models learn it
    /// afresh. On an error the tracker is left as it was.
    pub fn start<P: PixelFormat>(
        &mut self,
        config: CfConfig,
        frame: &ImageView<'_, P>,
        init: Rect,
    ) -> Result<(), ConfigError> {
        config.validate()?;
        check_box(frame, init)?;
        self.config = config;
        self.place(frame, init);
        let (centre, size) = (self.centre, self.size);
        let geometry = self.geometry();
        self.sample_cells(frame, centre, &geometry);
        let target = geometry.target;
        let sigma = target
            .0
            .saturating_mul(target.1)
            .sqrt()
            .saturating_mul(config.sigma)
            .saturating_div(Q16::from_int(config.cell as i32));
        let settings = FilterSettings {
            sigma,
            lambda: config.lambda,
        };
        self.filter.reset(settings, &self.cells);
        self.scale
            .start(config.scale, frame, centre, size, &mut self.extractor);
        let grid = self.colour_grid(centre, &geometry);
        self.map.build::<Bn, P>(frame, &grid, &self.colour);
        let still = (Q16::ZERO, Q16::ZERO);
        self.learn_colour(frame, &geometry, still, size, Q16::ONE);
        Ok(())
    }

    /// Moves the tracker onto `init` in `frame` (px; say a box a detector found) and keeps
    /// what it learnt: the translation filter, the colour model and the scale filter. The
    /// box is the new first box (the size factor starts again at 1 and its bounds follow
    /// it), the velocity is forgotten, and the status is `Tracking`; nothing is learnt
    /// from this frame. An unstarted tracker, having nothing to keep, refuses it.
    ///
    /// # Errors
    /// [`ConfigError::ModelSettings`] if the tracker has not started;
    /// [`ConfigError::InitialTooSmall`] or [`ConfigError::InitialOutside`] as for
    /// [`CfTracker::start`]. On an error the tracker is left as it was.
    pub fn relocate<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        init: Rect,
    ) -> Result<(), ConfigError> {
        if self.config.cell == 0 {
            return Err(ConfigError::ModelSettings);
        }
        check_box(frame, init)?;
        self.place(frame, init);
        Ok(())
    }

    /// Puts the target at `init` in `frame` as a first box: centre, size and its bounds,
    /// no velocity, `Tracking`. The models are not touched.
    fn place<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>, init: Rect) {
        let frame_size = (frame.width() as i32, frame.height() as i32);
        let (centre, size) = (init.centre(), (init.w, init.h));
        let ratio = |a: i32, b: Q16| Q16::from_ratio((a as i64) << 16, b.to_bits() as i64);
        self.frame_size = frame_size;
        self.centre = centre;
        self.size = size;
        self.base = size;
        self.factor = Q16::ONE;
        self.velocity = (Q16::ZERO, Q16::ZERO);
        self.anchor = centre;
        self.lost_velocity = (Q16::ZERO, Q16::ZERO);
        self.search_frames = 0;
        self.peak = Q16::ONE;
        // The least factor is rounded up (one bit above the floored ratio), so that the
        // first box times it is never below MIN_SIDE, and at most 1 (the first box).
        self.factor_bounds = (
            ratio(MIN_SIDE, size.0)
                .max(ratio(MIN_SIDE, size.1))
                .saturating_add(Q16::from_bits(1))
                .min(Q16::ONE),
            ratio(frame_size.0, size.0)
                .min(ratio(frame_size.1, size.1))
                .max(Q16::ONE),
        );
        self.estimate = Estimate::first(Ellipse::from(init), &calibration::CORRELATION);
    }

    /// The configuration.
    pub fn config(&self) -> &CfConfig {
        &self.config
    }

    /// The last estimate (the first box's before any step).
    pub fn estimate(&self) -> &Estimate {
        &self.estimate
    }

    /// The last step's merged response peak, Q16.16 in `[0, 1]` (1 on the first box, 0
    /// before it), which the learning, size and search gates read; the estimate's score is
    /// its margin.
    pub fn peak(&self) -> Q16 {
        self.peak
    }

    /// Tracks one frame (of the size the tracker started on: a frame of another size is
    /// read clamped to its edges). An unstarted tracker returns its estimate unchanged.
    pub fn step<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>) -> Estimate {
        self.step_profiled(frame, NoCounter).0
    }

    /// [`CfTracker::step`], reading `counter` at each stage boundary.
    pub fn step_profiled<P: PixelFormat, C: CycleCounter>(
        &mut self,
        frame: &ImageView<'_, P>,
        counter: C,
    ) -> (Estimate, CfStageCycles) {
        let mut watch = Stopwatch::start(counter);
        let mut cycles = CfStageCycles::default();
        if self.config.cell == 0 {
            return (self.estimate, cycles);
        }
        let c = self.config;
        let previous = self.centre;
        let searching = self.search_frames > 0;
        if searching && c.coast {
            let (x, y) = self.anchor;
            let (vx, vy) = self.lost_velocity;
            self.anchor = self.inside((x.saturating_add(vx), y.saturating_add(vy)));
        }
        let ahead = self.inside((
            previous
                .0
                .saturating_add(self.velocity.0.saturating_mul(c.lead)),
            previous
                .1
                .saturating_add(self.velocity.1.saturating_mul(c.lead)),
        ));
        let search = match searching && c.coast {
            true => self.anchor,
            false => ahead,
        };
        let more = match searching {
            true => self.search_more(frame, &mut watch, &mut cycles),
            false => None,
        };
        let usual = self.detect(frame, search, &mut watch, &mut cycles);
        // A region other than the usual one that takes over only moves the target: the
        // filter holds the usual region's spectra, so nothing is learnt this frame.
        let (found, taken_over) = match more.filter(|d| d.peak > usual.peak) {
            Some(d) => (d, true),
            None => (usual, false),
        };
        self.centre = found.found;
        // The gates read the peak; the score, and so the confidence and the status, the
        // margin.
        let peak = found.peak.max(Q16::ZERO).min(Q16::ONE);
        self.peak = peak;
        let score = found.margin.max(Q16::ZERO).min(Q16::ONE);
        let confidence = calibration::CORRELATION.confidence(score);
        let still_searching = peak < c.search_below || (searching && peak < c.search_until);
        // Once lost, lost while the search lasts, until the confidence reaches
        // `uncertain_below` (no flicker while the target is hidden).
        let held = still_searching
            && self.estimate.status == Status::Lost
            && confidence < c.uncertain_below;
        let status = match held {
            true => Status::Lost,
            false => Status::of(confidence, c.lost_below, c.uncertain_below),
        };
        if still_searching {
            if self.search_frames == 0 {
                self.lost_velocity = self.velocity;
            }
            self.search_frames = self.search_frames.saturating_add(1);
        } else {
            self.search_frames = 0;
            self.anchor = self.centre;
        }

        // The scale samples serve a size change (at `scale_above`) and learning (at
        // `learn_above`): below both, and on a search frame, they are not taken.
        let learn = peak >= c.learn_above && !taken_over;
        let sampled = !searching && (peak >= c.scale_above || learn);
        let factor = match sampled {
            true => self
                .scale
                .respond(frame, self.centre, self.size, &mut self.extractor),
            false => Q16::ONE,
        };
        let factor = match sampled && peak >= c.scale_above {
            true => factor,
            false => Q16::ONE,
        }
        .max(Q16::ONE.saturating_div(c.max_scale_change))
        .min(c.max_scale_change);
        cycles.scale = watch.lap();
        let old_size = self.size;
        self.resize(self.factor.saturating_mul(factor));

        if learn {
            let cell = Q16::from_int(c.cell as i32);
            let shift = (
                found.moved.1.saturating_div(cell),
                found.moved.0.saturating_div(cell),
            );
            self.filter.learn(shift, c.cf_rate);
            self.learn_colour(frame, &found.geometry, found.moved, old_size, c.colour_rate);
            if sampled {
                self.scale.learn(c.scale_rate);
            }
        }
        cycles.learn = watch.lap();
        let velocity = (
            self.centre.0.saturating_sub(previous.0),
            self.centre.1.saturating_sub(previous.1),
        );
        let halfway = |a: Q16, b: Q16| Q16::saturate((a.to_bits() as i64 + b.to_bits() as i64) / 2);
        self.velocity = (
            halfway(self.velocity.0, velocity.0),
            halfway(self.velocity.1, velocity.1),
        );
        self.estimate = Estimate {
            ellipse: self.ellipse(),
            vx: velocity.0,
            vy: velocity.1,
            score,
            confidence,
            status,
        };
        (self.estimate, cycles)
    }

    /// Moves the target with the picture (a pan/tilt head's command, an IMU's reading): the
    /// centre as [`CameraMotion::point`] moves it, clamped into the frame, and the size
    /// as [`CameraMotion::length`] scales it, within the size bounds. The models stay as
    /// they are.
    pub fn camera_moved(&mut self, motion: &CameraMotion) {
        if self.config.cell == 0 {
            return;
        }
        self.centre = self.inside(motion.point(self.centre.0, self.centre.1));
        self.anchor = self.inside(motion.point(self.anchor.0, self.anchor.1));
        let length = |(x, y): (Q16, Q16)| (motion.length(x), motion.length(y));
        self.velocity = length(self.velocity);
        self.lost_velocity = length(self.lost_velocity);
        self.resize(motion.length(self.factor));
        let e = self.estimate;
        self.estimate = Estimate {
            ellipse: self.ellipse(),
            vx: motion.length(e.vx),
            vy: motion.length(e.vy),
            ..e
        };
    }

    /// Sets the size to the first box's times `factor` (Q16.16), within the size bounds.
    fn resize(&mut self, factor: Q16) {
        let f = factor.max(self.factor_bounds.0).min(self.factor_bounds.1);
        self.factor = f;
        self.size = (self.base.0.saturating_mul(f), self.base.1.saturating_mul(f));
    }

    /// The ellipse of the current centre and size (half-axes half the size), px.
    fn ellipse(&self) -> Ellipse {
        let half = |v: Q16| Q16::from_bits(v.to_bits() / 2);
        Ellipse::new(
            self.centre.0,
            self.centre.1,
            half(self.size.0),
            half(self.size.1),
        )
    }

    /// Searches the region around `centre` for the target at its current size.
    fn detect<P: PixelFormat, C: CycleCounter>(
        &mut self,
        frame: &ImageView<'_, P>,
        centre: (Q16, Q16),
        watch: &mut Stopwatch<C>,
        cycles: &mut CfStageCycles,
    ) -> Detection {
        let c = self.config;
        let geometry = self.geometry();
        self.sample_cells(frame, centre, &geometry);
        cycles.features = watch.lap();
        self.filter.respond(&self.cells, &mut self.response);
        cycles.filter = watch.lap();
        let grid = self.colour_grid(centre, &geometry);
        self.map.build::<Bn, P>(frame, &grid, &self.colour);

        // The largest move the colour response can see, cells: the target box stays
        // inside the region.
        let side = Q16::from_int((G * c.cell) as i32);
        let reach_of = |target: Q16| {
            (side.saturating_sub(target).floor_int() / 2)
                .checked_div(c.cell as i32)
                .unwrap_or(0)
                .clamp(0, G as i32 / 2 - 1)
        };
        let (reach_x, reach_y) = (reach_of(geometry.target.0), reach_of(geometry.target.1));
        let cell = Q16::from_int(c.cell as i32);
        let merged = |dx: i32, dy: i32| -> i64 {
            let wrap = |d: i32| d.rem_euclid(G as i32) as usize;
            let cf = self
                .response
                .get(wrap(dy))
                .and_then(|row| row.get(wrap(dx)))
                .copied()
                .unwrap_or(0) as i64;
            let moved = (cell.mul_int(dx), cell.mul_int(dy));
            let colour = self
                .map
                .mean(&self.target_box(moved, geometry.target))
                .to_bits() as i64;
            let m = c.merge.to_bits() as i64;
            (((1 << 16) - m) * cf + m * colour) >> 16
        };
        // The merged response over the moves, at `[dy + reach_y][dx + reach_x]` (at most
        // `G - 1` a side), and its best move.
        let mut values = [[0i32; G]; G];
        let (mut best, mut at) = (i64::MIN, (0, 0));
        for (dy, row) in (-reach_y..=reach_y).zip(values.iter_mut()) {
            for (dx, slot) in (-reach_x..=reach_x).zip(row.iter_mut()) {
                let v = merged(dx, dy);
                *slot = v as i32;
                if v > best {
                    (best, at) = (v, (dx, dy));
                }
            }
        }
        let (dx, dy) = at;
        let value = |x: i32, y: i32| {
            let get = |v: i32, reach: i32| usize::try_from(v + reach).ok();
            get(y, reach_y)
                .and_then(|j| values.get(j))
                .zip(get(x, reach_x))
                .and_then(|(row, i)| row.get(i))
                .map_or(0, |&v| i64::from(v))
        };
        // The best move beyond the peak's lobe, 0 where there is none.
        let beyond = |x: i32, y: i32| (x - dx).abs() > LOBE || (y - dy).abs() > LOBE;
        let rival = (-reach_y..=reach_y)
            .flat_map(|y| (-reach_x..=reach_x).map(move |x| (x, y)))
            .filter(|&(x, y)| beyond(x, y))
            .map(|(x, y)| value(x, y))
            .max()
            .unwrap_or(0);
        let between = |at: i32, reach: i32, value: &dyn Fn(i32) -> i64| {
            if at <= -reach || at >= reach {
                return Q16::ZERO;
            }
            parabola_peak(value(at - 1), best, value(at + 1))
        };
        let fx = between(dx, reach_x, &|x| value(x, dy));
        let fy = between(dy, reach_y, &|y| value(dx, y));
        // The move, patch px, then frame px.
        let moved = (
            cell.mul_int(dx).saturating_add(fx.saturating_mul(cell)),
            cell.mul_int(dy).saturating_add(fy.saturating_mul(cell)),
        );
        let found = self.inside((
            centre
                .0
                .saturating_add(moved.0.saturating_div(geometry.zoom.0)),
            centre
                .1
                .saturating_add(moved.1.saturating_div(geometry.zoom.1)),
        ));
        let at_peak = (cell.mul_int(dx), cell.mul_int(dy));
        let colour = self.map.mean(&self.target_box(at_peak, geometry.target));
        cycles.colour = watch.lap();
        Detection {
            moved: (
                found
                    .0
                    .saturating_sub(centre.0)
                    .saturating_mul(geometry.zoom.0),
                found
                    .1
                    .saturating_sub(centre.1)
                    .saturating_mul(geometry.zoom.1),
            ),
            found,
            peak: Q16::saturate(best),
            margin: Q16::saturate(best - rival),
            colour,
            geometry,
        }
    }

    /// While searching: searches the region [`search_offset`] names for this frame of the
    /// search (none when `redetect` is 0) and returns it if it clears `redetect_above` and
    /// `redetect_colour`. Its work is `cycles.redetect`.
    fn search_more<P: PixelFormat, C: CycleCounter>(
        &mut self,
        frame: &ImageView<'_, P>,
        watch: &mut Stopwatch<C>,
        cycles: &mut CfStageCycles,
    ) -> Option<Detection> {
        let c = self.config;
        let (ox, oy) = search_offset(self.search_frames.saturating_sub(1), c.redetect)?;
        let region = self.geometry().region;
        let half = |side: Q16, k: i32| Q16::from_bits(side.to_bits() / 2).mul_int(k);
        let centre = self.inside((
            self.anchor.0.saturating_add(half(region.0, ox)),
            self.anchor.1.saturating_add(half(region.1, oy)),
        ));
        let mut spent = CfStageCycles::default();
        let d = self.detect(frame, centre, watch, &mut spent);
        cycles.redetect = cycles.redetect.saturating_add(spent.search());
        (d.peak >= c.redetect_above && d.colour >= c.redetect_colour).then_some(d)
    }

    /// `point` (px, Q16.16) clamped into the frame.
    fn inside(&self, point: (Q16, Q16)) -> (Q16, Q16) {
        let last = |n: i32| Q16::from_int(n - 1);
        (
            point.0.max(Q16::ZERO).min(last(self.frame_size.0)),
            point.1.max(Q16::ZERO).min(last(self.frame_size.1)),
        )
    }

    /// The search region's geometry at the current size.
    fn geometry(&self) -> Geometry {
        let c = &self.config;
        let pad = c.padding.saturating_mul(mean(self.size));
        let region = (
            self.size.0.saturating_add(pad),
            self.size.1.saturating_add(pad),
        );
        let side = (G * c.cell) as i64;
        // `Q16::from_ratio(side << 16, r)` without its 128-bit division: `side << 32` is at
        // most 2^40 (256 px), and the region is at least 4 px (2^18).
        let zoom =
            |r: Q16| Q16::saturate((side << 32).checked_div(r.to_bits().into()).unwrap_or(0));
        let zoom = (zoom(region.0), zoom(region.1));
        Geometry {
            region,
            zoom,
            target: (
                self.size.0.saturating_mul(zoom.0),
                self.size.1.saturating_mul(zoom.1),
            ),
        }
    }

    /// Resamples the region of `geometry` around `centre` into the feature grid.
    fn sample_cells<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        centre: (Q16, Q16),
        geometry: &Geometry,
    ) {
        let sampling = Sampling {
            cx: centre.0,
            cy: centre.1,
            width: geometry.region.0,
            height: geometry.region.1,
            cols: G,
            rows: G,
            cell: self.config.cell,
        };
        self.extractor
            .extract(frame, &sampling, self.cells.as_flattened_mut());
    }

    /// The colour samples of the region of `geometry` around `centre`.
    fn colour_grid(&self, centre: (Q16, Q16), geometry: &Geometry) -> Grid {
        Grid {
            cx: centre.0,
            cy: centre.1,
            width: geometry.region.0,
            height: geometry.region.1,
            side: Self::COLOUR_SIDE,
        }
    }

    /// Patch px in colour samples: `2G` samples over `G cell` px.
    fn to_samples(&self, v: Q16) -> Q16 {
        let px = v.to_bits() as i64 * 2;
        Q16::saturate(px.checked_div(self.config.cell as i64).unwrap_or(0))
    }

    /// A box of `size` patch px moved by `moved` patch px from the region's centre, in
    /// colour samples.
    fn target_box(&self, moved: (Q16, Q16), size: (Q16, Q16)) -> SampleBox {
        let c = Q16::from_int(G as i32);
        SampleBox::centred(
            (
                c.saturating_add(self.to_samples(moved.0)),
                c.saturating_add(self.to_samples(moved.1)),
            ),
            (self.to_samples(size.0), self.to_samples(size.1)),
        )
    }

    /// Blends the colour samples of the last map's grid into the model at `rate`, the
    /// target of `size` px found `moved` patch px from its centre.
    fn learn_colour<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        geometry: &Geometry,
        moved: (Q16, Q16),
        size: (Q16, Q16),
        rate: Q16,
    ) {
        let shrink = self.config.inner_padding.saturating_mul(mean(size));
        let inner = |side: Q16, zoom: Q16| {
            side.saturating_sub(shrink)
                .saturating_mul(zoom)
                .max(Q16::ONE)
        };
        let object = (
            inner(size.0, geometry.zoom.0),
            inner(size.1, geometry.zoom.1),
        );
        let object = self.target_box(moved, object);
        let target = self.target_box(moved, geometry.target);
        self.colour
            .learn::<Bn, P>(frame, &self.map, &object, &target, rate);
    }
}

/// The mean of a width and a height, px, Q16.16.
fn mean(size: (Q16, Q16)) -> Q16 {
    Q16::saturate((size.0.to_bits() as i64 + size.1.to_bits() as i64) / 2)
}

/// A first box's checks: each side at least [`MIN_SIDE`] px, the centre inside `frame`.
fn check_box<P: PixelFormat>(frame: &ImageView<'_, P>, init: Rect) -> Result<(), ConfigError> {
    let min = Q16::from_int(MIN_SIDE);
    if init.w < min || init.h < min {
        return Err(ConfigError::InitialTooSmall);
    }
    let centre = init.centre();
    let inside = |v: Q16, n: usize| v >= Q16::ZERO && v <= Q16::from_int(n as i32 - 1);
    match inside(centre.0, frame.width()) && inside(centre.1, frame.height()) {
        true => Ok(()),
        false => Err(ConfigError::InitialOutside),
    }
}

/// The offset in `[-1/2, 1/2]` (Q16.16) of the top of the parabola through `(-1, l)`,
/// `(0, c)` and `(1, r)`; 0 where the three do not curve down.
fn parabola_peak(l: i64, c: i64, r: i64) -> Q16 {
    let curve = l - 2 * c + r;
    if curve >= 0 {
        return Q16::ZERO;
    }
    Q16::from_ratio(l - r, 2 * curve)
        .max(-Q16::HALF)
        .min(Q16::HALF)
}

#[cfg(test)]
mod tests;
