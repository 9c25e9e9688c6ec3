//! The two trackers: the colour particle filter and the Rao-Blackwellised particle filter,
//! one engine with a [`Variant`] switch.
//!
//! Both share the window, histogram, cue, resampling and read-out code; they differ in how
//! a particle's ellipse size moves (sampled, or a Kalman filter per particle fed by a
//! once-per-frame scale measurement) and in the weight (colour, or colour and gradient).
//!
//! # One step
//! 1. **Propagate**: constant-velocity drift with Gaussian noise; the size is scaled by a
//!    random factor (colour PF) or predicted by eq. 7 of the RBPF paper, the half-height
//!    following the vertical motion by `scale_per_row` and the aspect ratio kept (RBPF),
//!    with one shared Kalman covariance prediction. While the status is not `Tracking`, a
//!    share of the particles is first re-drawn uniformly over the frame. With
//!    [`Config::noise_gain`] set, the motion noise narrows while the target moves as
//!    predicted (see there).
//! 2. **Weigh**: every particle's window gives a histogram, its Bhattacharyya coefficient
//!    against the model gives the colour cost, the boundary gradient the gradient cost
//!    (RBPF); `exp(-cost)` by table multiplies the particle's weight. Weights are then
//!    normalised; if all vanished they become uniform.
//! 3. **Update** (RBPF): the size is measured once, around the weighted mean: of five
//!    scales `1 + {0, -1, 1, -2, 2} scale_step` of the mean predicted ellipse, the one of
//!    highest likelihood (same cues as the particles) gives `Y = (Hx, Hy)`; every
//!    particle's size takes the Kalman update with the shared gain, unless that window's
//!    Bhattacharyya coefficient is below `lost_below` (no target there: the prediction
//!    stands).
//! 4. **Estimate**: weighted mean, best particle or robust mean; its window's Bhattacharyya
//!    coefficient is the confidence, which sets the [`Status`] and, when high, blends the
//!    window's histogram into the model.
//! 5. **Resample** when the effective sample size is below `resample_below * N`.
//!
//! # Bounded work
//! A step visits at most [`max_pixels_per_step`]`(N, pixels_per_window)` =
//! `(N + 10) * cap + 2 * map::SIDE^2` pixels (`cap` the pixel cap lowered to
//! [`crate::window::MAX_CAP`]): `N` particle windows, the estimate's window, five scale
//! windows (RBPF, size by likelihood), the adaptation's whole window, halves and ring (a
//! ring samples twice the cap), and at most two object maps of `SIDE^2` cells; the RBPF's
//! gradient cue reads
//! `(N + 5) * gradient_points * (2 * gradient_search + 1)` 5-tap gradients on top, at
//! most (the particles' samples of one boundary point repeat pixels, and each pixel's
//! gradient is computed once per frame while it stays in the memo).
//! [`Tracker::pixels_visited`] reports the figure of the last step.
//!
//! # Examples
//! ```
//! use rbtrack::fixed::Q16;
//! use rbtrack::image::{ImageView, Rgb888, Rgb8x8x8};
//! use rbtrack::tracker::{Config, Status, Tracker, Variant};
//! use rbtrack::window::Ellipse;
//!
//! // A red square on grey, 64x48 RGB888.
//! let (w, h) = (64, 48);
//! let mut buf = vec![128u8; w * h * 3];
//! for y in 14..34 {
//!     for x in 22..42 {
//!         buf[(y * w + x) * 3..][..3].copy_from_slice(&[220, 30, 30]);
//!     }
//! }
//! let frame = ImageView::<Rgb888>::new(&buf, w, h, w).unwrap();
//! let start = Ellipse {
//!     cx: Q16::from_f64(31.5),
//!     cy: Q16::from_f64(23.5),
//!     hx: Q16::from_int(10),
//!     hy: Q16::from_int(10),
//! };
//! let config = Config::new(Variant::Rbpf);
//! let mut tracker = Tracker::<Rgb8x8x8, 50, 512>::new(config, &frame, start).unwrap();
//! let estimate = tracker.step(&frame);
//! assert_eq!(estimate.status, Status::Tracking);
//! assert!((estimate.ellipse.cx.to_f64() - 31.5).abs() < 3.0);
//! ```

mod config;
mod particle;

pub use config::{Config, ConfigError, CueMix, Readout, SizeMeasurement, Variant};
pub use particle::Particle;

use crate::colour::{ColourModel, ColourSettings};
use crate::cue::{GradientConfig, GradientCue, GradientMemo};
use crate::fixed::Q16;
use crate::ground::GroundPlane;
use crate::hist::Histogram;
use crate::image::{Binning, ImageView, PixelFormat};
use crate::kalman::{BlockNoise, SharedCovariance, Sym2};
use crate::likelihood::exp_neg;
use crate::map::{ObjectMap, Span};
use crate::profile::{CycleCounter, NoCounter, StageCycles, Stopwatch};
use crate::resample::{
    effective_sample_size_at_least, normalise, replicate, resample, Normalised, WEIGHT_TOTAL,
};
use crate::rng::Rng;
use crate::window::{Ellipse, MAX_CAP};
use config::Derived;
use core::marker::PhantomData;
use particle::{predict_size, scale_randomly, Bounds, Motion};

/// The most pixels a step of `particles` particles with a pixel cap of `cap` px reads
/// (see "Bounded work" in the module documentation), px.
pub const fn max_pixels_per_step(particles: usize, cap: u32) -> u64 {
    let cap = if cap < MAX_CAP { cap } else { MAX_CAP } as u64;
    let map_cells = (crate::map::SIDE * crate::map::SIDE) as u64;
    (particles as u64 + 10) * cap + 2 * map_cells
}

/// The colour model's settings in `config`.
const fn colour_settings(config: &Config) -> ColourSettings {
    ColourSettings {
        split_halves: config.split_halves,
        background: if config.background_weighting {
            Some(config.background_floor)
        } else {
            None
        },
        ring_scale: config.ring_scale,
        cap: config.pixels_per_window,
    }
}

/// Whether `init` can start a tracker of `config` on `frame`: half-axes at least
/// `min_half_axis`, centre inside the frame.
fn check_init<P: PixelFormat>(
    config: &Config,
    frame: &ImageView<'_, P>,
    init: &Ellipse,
) -> Result<(), ConfigError> {
    let bounds = Bounds::for_frame(frame.width(), frame.height(), config.min_half_axis);
    let inside = |v: Q16, max: Q16| v >= Q16::ZERO && v <= max;
    let usable = init.hx >= config.min_half_axis
        && init.hy >= config.min_half_axis
        && inside(init.cx, bounds.max_x)
        && inside(init.cy, bounds.max_y);
    usable.then_some(()).ok_or(ConfigError::InitialEllipse)
}

/// The scales tried when measuring the size: `1 + k scale_step` for these `k`, the
/// unchanged size first (it wins a tie).
const SCALE_STEPS: [i32; 5] = [0, -1, 1, -2, 2];

/// How sure the tracker is of its estimate.
///
/// `Lost` is 0, so that an unstarted tracker ([`Tracker::unstarted`]) is all zero bits and
/// a `static` of one takes no flash.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum Status {
    /// Confidence at or above `uncertain_below`.
    Tracking = 1,
    /// Confidence in `[lost_below, uncertain_below)`; like `Lost`, the tracker searches
    /// the whole frame with part of its particles.
    Uncertain = 2,
    /// Confidence below `lost_below`.
    Lost = 0,
}

/// Where the target is after a step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Estimate {
    /// Centre and half-axes, px, Q16.16; the centre is always inside the frame.
    pub ellipse: Ellipse,
    /// Horizontal velocity, px/frame, Q16.16.
    pub vx: Q16,
    /// Vertical velocity, px/frame, Q16.16.
    pub vy: Q16,
    /// Bhattacharyya coefficient of the estimate's window against the model, Q16.16 in
    /// `[0, 1]`.
    pub confidence: Q16,
    /// Tracking, uncertain or lost.
    pub status: Status,
}

/// A tracker of `N` particles (`1..=65535`) on colour histograms of `B` bins laid out by
/// the binning `Bn` (`Bn::BINS == B`, checked at compile time).
///
/// Its RAM is its `size_of`, all inline: 44 bytes per particle (state, weight, gradient
/// cue, resampling scratch), about 14 bytes per bin (model, histogram, touched-bin list),
/// the 6 KiB gradient memo ([`crate::cue::GradientMemo`]) and under 1 KiB more. With 512
/// bins: 16,352 bytes at N = 50, 18,552 at N = 100, 22,952 at N = 200 on x86-64 (pinned
/// by `host-tests/tests/tracking.rs`).
#[derive(Clone, Debug)]
pub struct Tracker<Bn: Binning, const N: usize, const B: usize> {
    config: Config,
    derived: Derived,
    cue: GradientCue,
    initial_cov: Sym2,
    size_cov: SharedCovariance,
    /// The random stream (`None` until [`Tracker::start`]).
    rng: Option<Rng>,
    particles: [Particle; N],
    weights: [u32; N],
    /// The gradient cue of each particle's window this frame (RBPF), then its cost.
    cue_values: [Q16; N],
    /// The colour cost of each particle's window, this frame.
    colour_costs: [Q16; N],
    /// Gradients already computed in this frame (RBPF).
    memo: GradientMemo,
    indices: [u16; N],
    counts: [u16; N],
    resampled: bool,
    scale_factor: Option<Q16>,
    colour: ColourModel<B>,
    /// The histograms of the window being compared.
    scratch: [Histogram<B>; 2],
    /// This frame's object map.
    map: ObjectMap,
    /// Scale of the contrast boxes relative to the windows' bounding boxes, Q16.16: the
    /// scale at which the first window had the highest contrast.
    calibration: Q16,
    /// The ground-plane fit of the confident estimates.
    ground: GroundPlane,
    estimate: Estimate,
    last_confident: Ellipse,
    /// Mean recent innovation of the estimate against its constant-velocity prediction,
    /// px, Q16.16 (see [`Config::noise_gain`]); `None` until the first step while tracking.
    motion_spread: Option<Q16>,
    pixels_visited: u32,
    weight_recoveries: u32,
    binning: PhantomData<Bn>,
}

impl<Bn: Binning, const N: usize, const B: usize> Tracker<Bn, N, B> {
    /// A tracker that has not started: no configuration, random stream or model, every
    /// particle at the origin, every bit zero. `const`, so firmware can place it in a
    /// `static` (for example `static_cell::ConstStaticCell`): it lands in `.bss`, takes no
    /// flash and never a tracker-sized place on the stack; [`Tracker::start`] then
    /// configures and starts it in place. Until then [`Tracker::step`] returns its
    /// estimate (status `Lost`, confidence 0) unchanged.
    pub const fn unstarted() -> Self {
        const { assert!(Bn::BINS == B, "the binning must have B bins") };
        let origin = Ellipse::new(Q16::ZERO, Q16::ZERO, Q16::ZERO, Q16::ZERO);
        Self {
            config: Config::UNSET,
            derived: Derived::UNSET,
            cue: GradientCue::UNSET,
            initial_cov: Sym2::diagonal(Q16::ZERO, Q16::ZERO),
            size_cov: SharedCovariance::UNSET,
            rng: None,
            particles: [Particle::at(&origin); N],
            weights: [0; N],
            cue_values: [Q16::ZERO; N],
            colour_costs: [Q16::ZERO; N],
            memo: GradientMemo::UNSTARTED,
            indices: [0; N],
            counts: [0; N],
            resampled: false,
            scale_factor: None,
            colour: ColourModel::UNSET,
            scratch: [Histogram::new(), Histogram::new()],
            map: ObjectMap::new(),
            calibration: Q16::ZERO,
            ground: GroundPlane::new(),
            estimate: Estimate {
                ellipse: origin,
                vx: Q16::ZERO,
                vy: Q16::ZERO,
                confidence: Q16::ZERO,
                status: Status::Lost,
            },
            last_confident: origin,
            motion_spread: None,
            pixels_visited: 0,
            weight_recoveries: 0,
            binning: PhantomData,
        }
    }

    /// Checks `config`, builds the target model from the window `init` of `frame` and
    /// places every particle on `init`, in place, whatever the tracker did before; the
    /// random stream starts from `config.seed`.
    ///
    /// # Errors
    /// [`ConfigError::OutOfRange`] naming the first bad field, [`ConfigError::ParticleCount`]
    /// for `N` outside `1..=65535`, [`ConfigError::InitialEllipse`] for an ellipse with a
    /// half-axis below `min_half_axis` or a centre outside the frame; the tracker is then
    /// unchanged.
    pub fn start<P: PixelFormat>(
        &mut self,
        config: Config,
        frame: &ImageView<'_, P>,
        init: Ellipse,
    ) -> Result<(), ConfigError> {
        if N == 0 || N > crate::resample::MAX_PARTICLES {
            return Err(ConfigError::ParticleCount);
        }
        let derived = config.derive()?;
        let mut gradient = GradientConfig::new();
        gradient.points = config.gradient_points as usize;
        gradient.search_px = config.gradient_search as u32;
        let cue = GradientCue::new(&gradient).map_err(|_| ConfigError::OutOfRange("gradient"))?;
        let initial_cov = Sym2::diagonal(config.kalman_r, config.kalman_q);
        let q = config.kalman_q;
        let r = config.kalman_r;
        let noise = BlockNoise::diagonal([q, q, q, q], [r, r]);
        let size_cov = SharedCovariance::new(initial_cov, initial_cov, noise)
            .map_err(|_| ConfigError::OutOfRange("kalman_q"))?;
        check_init(&config, frame, &init)?;
        self.config = config;
        (self.derived, self.cue, self.initial_cov, self.size_cov) =
            (derived, cue, initial_cov, size_cov);
        self.colour.configure(colour_settings(&config));
        self.memo.clear();
        self.rng = Some(Rng::new(config.seed));
        self.reset(frame, init)
    }

    /// [`Tracker::unstarted`], then [`Tracker::start`]: a tracker of `config` on the window
    /// `init` of `frame`. The tracker is returned by value: firmware short of stack
    /// starts one in a `static` instead.
    ///
    /// # Errors
    /// As [`Tracker::start`].
    pub fn new<P: PixelFormat>(
        config: Config,
        frame: &ImageView<'_, P>,
        init: Ellipse,
    ) -> Result<Self, ConfigError> {
        let mut tracker = Self::unstarted();
        tracker.start(config, frame, init)?;
        Ok(tracker)
    }

    /// Re-initialises on the window `init` of `frame` (new model, particles on `init`,
    /// fresh covariance) without rebuilding; the configuration stays and the random
    /// stream continues. An unstarted tracker is started with the defaults of the RBPF
    /// ([`Tracker::start`]).
    ///
    /// # Errors
    /// [`ConfigError::InitialEllipse`] as for [`Tracker::start`]; the tracker is unchanged.
    pub fn reset<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        init: Ellipse,
    ) -> Result<(), ConfigError> {
        if self.rng.is_none() {
            return self.start(Config::new(Variant::Rbpf), frame, init);
        }
        check_init(&self.config, frame, &init)?;
        self.colour.learn::<Bn, P>(frame, &init, &mut self.scratch);
        self.calibration = self.calibrate(frame, &init);
        self.ground = GroundPlane::new();
        self.particles = [Particle::at(&init); N];
        self.weights = [WEIGHT_TOTAL / N as u32; N];
        self.size_cov =
            SharedCovariance::new(self.initial_cov, self.initial_cov, *self.size_cov.noise())
                .map_err(|_| ConfigError::OutOfRange("kalman_q"))?;
        self.estimate = Estimate {
            ellipse: init,
            vx: Q16::ZERO,
            vy: Q16::ZERO,
            confidence: Q16::ONE,
            status: Status::Tracking,
        };
        self.last_confident = init;
        self.motion_spread = None;
        self.memo.start_frame();
        Ok(())
    }

    /// One frame: propagate, weigh, update, estimate, resample.
    pub fn step<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>) -> Estimate {
        self.step_profiled(frame, NoCounter).0
    }

    /// [`Tracker::step`], reading `counter` at each stage boundary.
    pub fn step_profiled<P: PixelFormat, C: CycleCounter>(
        &mut self,
        frame: &ImageView<'_, P>,
        counter: C,
    ) -> (Estimate, StageCycles) {
        let mut watch = Stopwatch::start(counter);
        let mut cycles = StageCycles::default();
        if self.rng.is_none() {
            return (self.estimate, cycles);
        }
        let bounds = Bounds::for_frame(frame.width(), frame.height(), self.config.min_half_axis);
        self.pixels_visited = 0;
        self.scale_factor = None;
        self.memo.start_frame();

        self.propagate(&bounds);
        cycles.propagate = watch.lap();

        self.weigh(frame);
        cycles.weigh = watch.lap();

        if self.config.variant == Variant::Rbpf && !self.config.freeze_size {
            self.update_sizes(frame, &bounds);
        }
        cycles.update = watch.lap();

        self.estimate = self.read_out(frame);
        cycles.estimate = watch.lap();

        self.resample_if_degenerate();
        cycles.resample = watch.lap();
        (self.estimate, cycles)
    }

    /// The ground-plane slope in use (`alpha / beta`, px of half-height per px the centre
    /// moves down, Q16.16): the learnt one once trustworthy (with
    /// [`Config::learn_scale_per_row`]), else [`Config::scale_per_row`].
    pub fn scale_per_row(&self) -> Q16 {
        let learnt = match self.config.learn_scale_per_row {
            // Rows spread over a quarter of the half-height at least (standard deviation).
            true => self
                .ground
                .slope(Q16::from_bits(self.last_confident.hy.to_bits() >> 2)),
            false => None,
        };
        learnt.unwrap_or(self.config.scale_per_row)
    }

    /// The estimate of the last step (the initial ellipse before any).
    pub fn estimate(&self) -> Estimate {
        self.estimate
    }

    /// The configuration in use.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The particles, after the last step's resampling.
    pub fn particles(&self) -> &[Particle; N] {
        &self.particles
    }

    /// The particle indices the last step's resampling drew (`rbtrack::resample::resample`
    /// order, before the in-place copy), or `None` if the last step did not resample.
    /// For checking the filter against a reference that follows the same ancestry.
    pub fn last_resampling(&self) -> Option<&[u16; N]> {
        self.resampled.then_some(&self.indices)
    }

    /// The factor of the scale the last step's size measurement chose (RBPF:
    /// `1 + k scale_step`, `k` in `-2..=2`), or `None` when nothing was measured (colour PF,
    /// or every scale had likelihood 0).
    pub fn last_scale_factor(&self) -> Option<Q16> {
        self.scale_factor
    }

    /// Pixels read in the last step (`<= max_pixels_per_step(N, pixels_per_window)`).
    pub fn pixels_visited(&self) -> u32 {
        self.pixels_visited
    }

    /// Steps whose weights all vanished and were reset to uniform, since construction.
    pub fn weight_recoveries(&self) -> u32 {
        self.weight_recoveries
    }

    /// The Kalman covariance of the particles' sizes `(Hx, dHx, Hy, dHy)`, shared by every
    /// particle (RBPF; the colour PF leaves it at its initial value). Read-only, for checks
    /// such as the long-run soak test.
    pub fn size_covariance(&self) -> crate::kalman::Sym4 {
        self.size_cov.cov()
    }

    fn propagate(&mut self, bounds: &Bounds) {
        let searching = self.estimate.status != Status::Tracking;
        if searching {
            self.redetect(bounds);
        }
        // While searching, RBPF sizes follow the ground plane only (rates held at zero), so
        // they cannot drift away from what the rows predict before the target is found.
        let rate_noise = if searching {
            Q16::ZERO
        } else {
            self.config.scale_noise
        };
        let motion = Motion::new(&self.config, self.noise_scale(searching));
        let slope = self.scale_per_row();
        let Some(rng) = self.rng.as_mut() else {
            return;
        };
        for p in self.particles.iter_mut() {
            let y_before = p.y;
            motion.drift(p, rng, bounds);
            if self.config.freeze_size {
                continue;
            }
            match self.config.variant {
                Variant::ColourPf => scale_randomly(p, self.config.scale_noise, rng, bounds),
                Variant::Rbpf => {
                    if searching {
                        (p.size.dhx, p.size.dhy) = (Q16::ZERO, Q16::ZERO);
                    }
                    let dy = p.y - y_before;
                    predict_size(p, dy, slope, rate_noise, rng, bounds)
                }
            }
        }
        if self.config.variant == Variant::Rbpf {
            self.size_cov.predict(Q16::ONE);
        }
    }

    /// The factor on the motion noise this frame: `clamp(noise_gain * s / sigma,
    /// noise_floor, 1)` while tracking with a known innovation `s`, else 1.
    fn noise_scale(&self, searching: bool) -> Q16 {
        match self.motion_spread {
            Some(spread) if !searching && self.config.noise_gain > Q16::ZERO => {
                let sigma = self.nominal_noise(&self.estimate.ellipse);
                (self.config.noise_gain * spread / sigma).clamp(self.config.noise_floor, Q16::ONE)
            }
            _ => Q16::ONE,
        }
    }

    /// The innovation mean after `estimate`: the distance of its centre from the last
    /// estimate moved by its velocity, `(|dx| + |dy|) / 2` px, averaged with weight 1/8
    /// (starting from the unscaled noise, so the noise narrows gradually).
    fn next_spread(&self, estimate: &Estimate) -> Q16 {
        let last = &self.estimate;
        let dx = estimate.ellipse.cx - (last.ellipse.cx + last.vx);
        let dy = estimate.ellipse.cy - (last.ellipse.cy + last.vy);
        let innovation = Q16::from_bits((dx.abs().to_bits() >> 1) + (dy.abs().to_bits() >> 1));
        let spread = self
            .motion_spread
            .unwrap_or_else(|| self.nominal_noise(&estimate.ellipse));
        spread + Q16::from_bits((innovation - spread).to_bits() >> 3)
    }

    /// The unscaled position noise of a particle on `e`, px.
    fn nominal_noise(&self, e: &Ellipse) -> Q16 {
        Motion::new(&self.config, Q16::ONE).position_sigma(e.hx, e.hy)
    }

    /// Re-draws `redetect_share` of the particles uniformly over the frame, at rest, sized
    /// as the last confident estimate moved along the ground-plane relation to their row,
    /// with weight `redetect_prior` against the others' 1.
    fn redetect(&mut self, bounds: &Bounds) {
        let count = ((self.config.redetect_share.to_bits() as u64 * N as u64) >> 16) as usize;
        let last = self.last_confident;
        let slope = self.scale_per_row();
        let width = bounds.max_x.floor_int() as u32 + 1;
        let height = bounds.max_y.floor_int() as u32 + 1;
        for p in self.particles.iter_mut().take(count) {
            let Some(rng) = self.rng.as_mut() else {
                return;
            };
            let x = Q16::from_int(rng.below(width) as i32);
            let y = Q16::from_int(rng.below(height) as i32);
            let hy = last.hy + slope * (y - last.cy);
            let (hx, hy) = bounds.halves(last.hx * (hy / last.hy), hy);
            *p = Particle::at(&Ellipse {
                cx: x,
                cy: y,
                hx,
                hy,
            });
        }
        let even = WEIGHT_TOTAL / N as u32;
        let prior = (self.config.redetect_prior * Q16::from_bits(even as i32)).to_bits() as u32;
        for (i, w) in self.weights.iter_mut().enumerate() {
            *w = if i < count { prior.max(1) } else { even };
        }
    }

    /// The costs of window `e` of colour score `score` ([`crate::colour::Match::score`]):
    /// colour (the score's, plus the contrast cue's when configured) and gradient (RBPF,
    /// else 0), Q16.16; `cue` is the window's gradient cue if already known (RBPF).
    fn costs<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        e: &Ellipse,
        score: Q16,
        cue: Option<Q16>,
    ) -> (Q16, Q16) {
        let mut colour = self.derived.colour.cost(Q16::ONE - score);
        if let Some(scale) = self.derived.contrast {
            colour += scale.cost(Q16::ONE - self.contrast(e));
        }
        let gradient = match self.config.variant {
            Variant::ColourPf => Q16::ZERO,
            Variant::Rbpf => {
                let g = match cue {
                    Some(g) => g,
                    None => self.cue.evaluate_memo(frame, e, &mut self.memo),
                };
                let miss = Q16::ONE - g;
                self.derived.gradient.cost(miss * miss)
            }
        };
        (colour, gradient)
    }

    /// Likelihood, Q0.16 in `0..=65535`, of a window of colour cost `colour` and gradient
    /// cost `gradient`: `exp(-(colour + gradient - offset))`, `offset` the frame's
    /// smallest cost (so the best window has 65535 and sharp cues never underflow the
    /// table for every window at once); with [`CueMix::Average`], the RBPF paper's
    /// `a exp(-colour) + (1 - a) exp(-gradient)`, no offset.
    fn likelihood(&self, colour: Q16, gradient: Q16, offset: Q16) -> u32 {
        match (self.config.variant, self.config.cue_mix) {
            (Variant::Rbpf, CueMix::Average(a)) => {
                let a = a.to_bits() as u64; // Q16.16 in 0..=65536
                ((a * exp_neg(colour) as u64 + (65536 - a) * exp_neg(gradient) as u64) >> 16) as u32
            }
            _ => exp_neg(colour + gradient - offset),
        }
    }

    /// Mean object probability inside window `e`'s contrast box minus that in the ring
    /// around it, on this frame's map (see [`crate::map::ObjectMap::contrast`]).
    fn contrast(&self, e: &Ellipse) -> Q16 {
        let inner = self.contrast_span(e, Q16::ONE);
        let outer = self.contrast_span(e, self.config.contrast_ring);
        self.map.contrast(&inner, &outer)
    }

    /// The contrast box of window `e` (its bounding box times the calibration), scaled by
    /// `k` about its centre.
    fn contrast_span(&self, e: &Ellipse, k: Q16) -> Span {
        let k = self.calibration.saturating_mul(k);
        let (hx, hy) = (e.hx.saturating_mul(k), e.hy.saturating_mul(k));
        Span {
            x0: e.cx - hx,
            y0: e.cy - hy,
            x1: e.cx + hx,
            y1: e.cy + hy,
        }
    }

    /// Whether the RBPF measures sizes on the object map.
    fn measures_size_by_contrast(&self) -> bool {
        self.config.variant == Variant::Rbpf
            && self.config.size_measurement == SizeMeasurement::Contrast
            && !self.config.freeze_size
    }

    /// The region every particle's contrast ring covers.
    fn particle_region(&self) -> Span {
        let outer = |p: &Particle| self.contrast_span(&p.ellipse(), self.config.contrast_ring);
        let mut region = self.particles.first().map(outer).unwrap_or_default();
        for s in self.particles.iter().map(outer) {
            region = Span {
                x0: region.x0.min(s.x0),
                y0: region.y0.min(s.y0),
                x1: region.x1.max(s.x1),
                y1: region.y1.max(s.y1),
            };
        }
        region
    }

    /// Builds this frame's object map over `region`.
    fn build_map<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>, region: &Span) {
        let prob = self.colour.object_prob();
        let n = self.map.build::<Bn, P, B>(frame, region, prob);
        self.pixels_visited = self.pixels_visited.saturating_add(n);
    }

    /// The contrast box scale at which `init` has the highest contrast on `frame`, by
    /// steps of 5 % from 1 (at most 20, within `[1/2, 2]`): the measured sizes are then
    /// relative to the box the user gave, whatever the target's share of it.
    fn calibrate<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>, init: &Ellipse) -> Q16 {
        self.calibration = Q16::ONE;
        if !self.measures_size_by_contrast() && self.derived.contrast.is_none() {
            return Q16::ONE;
        }
        // Over three rings: a coarser map than the per-frame measurement's, measured to
        // hold the sizes better on the real sequences.
        let reach = Q16::from_int(3) * self.config.contrast_ring;
        self.build_map(frame, &self.contrast_span(init, reach));
        let step = self.config.scale_step;
        for _ in 0..20 {
            // The best of one step down, none and one step up (no step on a tie).
            let mut best = (self.contrast(init), Q16::ONE);
            for factor in [Q16::ONE - step, Q16::ONE + step] {
                let c = self.contrast(&Ellipse {
                    hx: init.hx * factor,
                    hy: init.hy * factor,
                    ..*init
                });
                if c > best.0 {
                    best = (c, factor);
                }
            }
            if best.1 == Q16::ONE {
                break;
            }
            self.calibration = (self.calibration * best.1).clamp(Q16::HALF, Q16::from_int(2));
        }
        self.calibration
    }

    fn weigh<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>) {
        if self.derived.contrast.is_some() {
            self.build_map(frame, &self.particle_region());
        }
        if self.config.variant == Variant::Rbpf {
            // Boundary point by boundary point across the particles: their samples of one
            // point lie close together, so the memo computes each pixel's gradient about
            // once (the values are those of `GradientCue::evaluate`).
            let particles = &self.particles;
            self.cue.evaluate_each(
                frame,
                |i| particles.get(i).map(Particle::ellipse).unwrap_or_default(),
                &mut self.cue_values,
                &mut self.memo,
            );
        }
        let mut offset = Q16::MAX;
        for i in 0..N {
            let e = self.particles[i].ellipse();
            let (score, pixels) = self.colour.score::<Bn, P>(frame, &e, &mut self.scratch);
            self.pixels_visited = self.pixels_visited.saturating_add(pixels);
            let (colour, gradient) = self.costs(frame, &e, score, Some(self.cue_values[i]));
            (self.colour_costs[i], self.cue_values[i]) = (colour, gradient);
            offset = offset.min(colour + gradient);
        }
        for i in 0..N {
            let likelihood = self.likelihood(self.colour_costs[i], self.cue_values[i], offset);
            // weight <= 2^24 (normalised) times likelihood < 2^16, over 2^8: below 2^32.
            self.weights[i] = ((self.weights[i] as u64 * likelihood as u64) >> 8) as u32;
        }
        if normalise(&mut self.weights) == Normalised::AllZero {
            self.weight_recoveries = self.weight_recoveries.saturating_add(1);
        }
    }

    /// Measures the size around the weighted mean and gives every leaf the Kalman update.
    /// A measurement whose window matches the model less than `lost_below` (the target is
    /// not there) is dropped: the means keep their prediction, while the shared covariance
    /// takes its update regardless, so it stays at its data-independent steady state.
    fn update_sizes<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>, bounds: &Bounds) {
        let mean = self.weighted_mean(|_| true).ellipse;
        let step = self.config.scale_step;
        let scaled = |k: i32| {
            let factor = Q16::ONE + step.mul_int(k);
            let (hx, hy) = bounds.halves(mean.hx * factor, mean.hy * factor);
            (factor, Ellipse { hx, hy, ..mean })
        };
        if self.config.size_measurement == SizeMeasurement::Contrast {
            // The largest scale's ring, with a margin for the map's whole cells.
            let (_, largest) = scaled(SCALE_STEPS[SCALE_STEPS.len() - 1]);
            let reach = self.config.contrast_ring * const { config::decimal(11, 10) };
            self.build_map(frame, &self.contrast_span(&largest, reach));
        }
        // (score, factor, usable): the highest score among the scales, the first on a tie.
        let mut best = (i64::MIN, Q16::ONE, false);
        for k in SCALE_STEPS {
            let (factor, e) = scaled(k);
            let (score, usable) = match self.config.size_measurement {
                // A window that does not stand out from its ring is not on the target.
                SizeMeasurement::Contrast => {
                    let c = self.contrast(&e);
                    (c.to_bits() as i64, c > Q16::ZERO)
                }
                SizeMeasurement::Likelihood => {
                    let m = self.colour.compare::<Bn, P>(frame, &e, &mut self.scratch);
                    self.pixels_visited = self.pixels_visited.saturating_add(m.pixels);
                    let (colour, gradient) = self.costs(frame, &e, m.score, None);
                    let score = match self.config.cue_mix {
                        CueMix::Average(_) => self.likelihood(colour, gradient, Q16::ZERO) as i64,
                        CueMix::Product => -((colour + gradient).to_bits() as i64),
                    };
                    // No target there, or (averaged likelihoods) nothing matches at all.
                    let matched = matches!(self.config.cue_mix, CueMix::Product) || score > 0;
                    let usable = m.rho >= self.config.lost_below && matched;
                    (score, usable)
                }
            };
            if score > best.0 {
                best = (score, factor, usable);
            }
        }
        let gain = self.size_cov.gain();
        self.size_cov.update_cov();
        let (_, factor, usable) = best;
        if !usable {
            return;
        }
        self.scale_factor = Some(factor);
        let (hx, hy) = bounds.halves(mean.hx * factor, mean.hy * factor);
        // The slope is learnt from measured sizes (not from estimates, which already
        // follow the slope's own prediction), while tracking.
        if self.config.learn_scale_per_row && self.estimate.status == Status::Tracking {
            self.ground.observe(mean.cy, hy);
        }
        for p in self.particles.iter_mut() {
            gain.update_mean(&mut p.size, hx, hy);
            (p.size.hx, p.size.hy) = bounds.halves(p.size.hx, p.size.hy);
        }
    }

    /// Weighted mean of the particles that `keep` accepts (all weights normalised).
    fn weighted_mean(&self, keep: impl Fn(&Particle) -> bool) -> Estimate {
        let mut sums = [0i64; 6];
        let mut total = 0i64;
        for (p, &w) in self.particles.iter().zip(self.weights.iter()) {
            if !keep(p) {
                continue;
            }
            let w = w as i64;
            total += w;
            for (s, v) in sums
                .iter_mut()
                .zip([p.x, p.y, p.vx, p.vy, p.size.hx, p.size.hy])
            {
                *s += w * v.to_bits() as i64;
            }
        }
        let [cx, cy, vx, vy, hx, hy] = sums.map(|s| Q16::saturate(s / total.max(1)));
        Estimate {
            ellipse: Ellipse { cx, cy, hx, hy },
            vx,
            vy,
            confidence: Q16::ZERO,
            status: Status::Lost,
        }
    }

    fn best_particle(&self) -> Particle {
        let mut best = (0u32, Particle::default());
        for (p, &w) in self.particles.iter().zip(self.weights.iter()) {
            if w >= best.0 {
                best = (w, *p);
            }
        }
        best.1
    }

    fn read_out<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>) -> Estimate {
        let mut estimate = match self.config.readout {
            Readout::Mean => self.weighted_mean(|_| true),
            Readout::Best => {
                let best = self.best_particle();
                Estimate {
                    ellipse: best.ellipse(),
                    vx: best.vx,
                    vy: best.vy,
                    confidence: Q16::ZERO,
                    status: Status::Lost,
                }
            }
            Readout::RobustMean(radius) => {
                let best = self.best_particle();
                self.weighted_mean(|p| {
                    (p.x - best.x).abs() <= radius && (p.y - best.y).abs() <= radius
                })
            }
        };
        let m = self
            .colour
            .compare::<Bn, P>(frame, &estimate.ellipse, &mut self.scratch);
        self.pixels_visited = self.pixels_visited.saturating_add(m.pixels);
        let confidence = m.rho;
        estimate.confidence = confidence;
        estimate.status = if confidence < self.config.lost_below {
            Status::Lost
        } else if confidence < self.config.uncertain_below {
            Status::Uncertain
        } else {
            Status::Tracking
        };
        if estimate.status == Status::Tracking {
            self.last_confident = estimate.ellipse;
            self.motion_spread = Some(self.next_spread(&estimate));
        } else {
            self.motion_spread = None;
        }
        if confidence >= self.config.adapt_above && self.config.adapt_rate > Q16::ZERO {
            let rate = self.config.adapt_rate;
            let n = self
                .colour
                .adapt::<Bn, P>(frame, &estimate.ellipse, &mut self.scratch, rate);
            self.pixels_visited = self.pixels_visited.saturating_add(n);
        }
        estimate
    }

    fn resample_if_degenerate(&mut self) {
        let threshold = self.config.resample_below.mul_int(N as i32);
        self.resampled = false;
        if effective_sample_size_at_least(&self.weights, threshold) {
            return;
        }
        let scheme = self.config.resampling;
        let Some(rng) = self.rng.as_mut() else {
            return;
        };
        if resample(scheme, &mut self.weights, rng, &mut self.indices).is_ok() {
            replicate(&mut self.particles, &self.indices, &mut self.counts);
            self.resampled = true;
        }
        self.weights = [WEIGHT_TOTAL / N as u32; N];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Gray8, Luma64};

    /// A still bright square on a dark 64x48 frame, and a tracker of it.
    fn still_target(noise_gain: Q16) -> ([u8; 64 * 48], Ellipse, Config) {
        let mut buf = [40u8; 64 * 48];
        for y in 14..34 {
            buf[y * 64 + 22..y * 64 + 42].fill(220);
        }
        let init = Ellipse {
            cx: Q16::from_f64(31.5),
            cy: Q16::from_f64(23.5),
            hx: Q16::from_int(10),
            hy: Q16::from_int(10),
        };
        let mut config = Config::new(Variant::ColourPf);
        config.noise_gain = noise_gain;
        (buf, init, config)
    }

    #[test]
    fn starts_in_place_like_new_and_does_nothing_before() {
        // A tracker is `const`-constructible, so it can live in a `static`.
        const UNSTARTED: Tracker<Luma64, 50, 64> = Tracker::unstarted();
        let (buf, init, config) = still_target(Q16::ZERO);
        let frame = ImageView::<Gray8>::new(&buf, 64, 48, 64).unwrap();
        let mut in_place = UNSTARTED;
        let before = in_place.step(&frame);
        assert_eq!(
            (before.status, before.confidence),
            (Status::Lost, Q16::ZERO)
        );
        assert_eq!(in_place.pixels_visited(), 0);
        let bad = Ellipse {
            hx: Q16::ONE,
            ..init
        };
        assert_eq!(
            in_place.start(config, &frame, bad),
            Err(ConfigError::InitialEllipse)
        );
        assert_eq!(
            in_place.step(&frame),
            before,
            "a refused start leaves it unstarted"
        );
        in_place.start(config, &frame, init).unwrap();
        let mut built = Tracker::<Luma64, 50, 64>::new(config, &frame, init).unwrap();
        for _ in 0..10 {
            assert_eq!(in_place.step(&frame), built.step(&frame));
        }
        let mut reset_first = UNSTARTED;
        reset_first.reset(&frame, init).unwrap();
        assert_eq!(reset_first.step(&frame).status, Status::Tracking);
    }

    #[test]
    fn noise_narrows_on_a_predictable_target_and_only_when_asked() {
        for gain in [Q16::ZERO, Q16::from_int(2)] {
            let (buf, init, config) = still_target(gain);
            let frame = ImageView::<Gray8>::new(&buf, 64, 48, 64).unwrap();
            let mut t = Tracker::<Luma64, 50, 64>::new(config, &frame, init).unwrap();
            assert_eq!(
                t.noise_scale(false),
                Q16::ONE,
                "nothing known before a step"
            );
            for _ in 0..60 {
                assert_eq!(t.step(&frame).status, Status::Tracking);
            }
            assert_eq!(t.noise_scale(true), Q16::ONE, "full noise while searching");
            let scale = t.noise_scale(false);
            if gain == Q16::ZERO {
                assert_eq!(scale, Q16::ONE);
            } else {
                // The estimate jitters well under the 4 px of unscaled noise.
                assert!(scale < Q16::HALF, "{scale}");
                assert!(scale >= config.noise_floor);
            }
        }
    }
}
