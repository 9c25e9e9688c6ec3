//! The three trackers, each run one frame at a time by its `step`, each giving an
//! [`Estimate`] whose confidence sets its [`Status`]. Each scores its estimate its own way
//! and reports the score through its [`Calibration`] table, so that the confidence means
//! the same for all three and they share the status thresholds ([`calibration`]):
//!
//! - [`CfTracker`], the correlation-filter tracker (Staple class; [`RgbCfTracker`] at its
//!   defaults, the most accurate): a translation filter on per-cell luma and gradient
//!   features and a colour model answer over a search region, their merged peak is the
//!   new position and its margin over the rest of the response the score, and a scale
//!   filter finds the size there; while the peak is low it searches more regions around
//!   where the target was last seen. Its parts are
//!   in [`crate::cf`], its step in `correlation.rs`.
//! - [`Tracker`], the colour particle filter and the Rao-Blackwellised particle filter
//!   (RBPF): one engine with a [`Variant`] switch, described below.
//!
//! Both particle filters share the window, histogram, cue, resampling and read-out code;
//! they differ in how a particle's ellipse size moves (sampled, or a Kalman filter per
//! particle fed by a once-per-frame scale measurement) and in the weight (colour, or
//! colour and gradient).
//!
//! # A particle filter's step
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
//!    Bhattacharyya coefficient, through the variant's confidence table, is below
//!    `lost_below` (no target there: the prediction stands).
//! 4. **Estimate**: weighted mean, best particle or robust mean; its window's Bhattacharyya
//!    coefficient less the spread penalty is the score, which, when high, blends the
//!    window's histogram into the model; through the variant's table
//!    ([`calibration`]) the score is the confidence, which sets the [`Status`].
//! 5. **Resample** when the effective sample size is below `resample_below * N`.
//!
//! # A particle filter's layout
//! A [`Tracker`] holds its [`Config`] and what it derives once per (re)start (cost scales,
//! the gradient cue's tables, the initial size covariance, the contrast box calibration),
//! the filter's state carried from frame to frame (random stream, particles, weights, size
//! covariance, colour model, ground plane, last estimate), scratch memory that each step
//! rebuilds (cues and costs, histograms, the object map, the gradient memo, resampling
//! indices) and the report of what the last step did. Each stage of a step is its own file: `propagate.rs`,
//! `weigh.rs` (with the object map's contrast cue in `contrast.rs`), `size.rs` and
//! `estimate.rs`.
//!
//! # Bounded work
//! A particle filter's step visits at most [`max_pixels_per_step`]`(N, pixels_per_window)` =
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

pub mod calibration;
mod camera;
mod config;
mod contrast;
mod correlation;
mod estimate;
mod model;
mod particle;
mod propagate;
mod size;
mod weigh;

pub use crate::resample::Scheme;
pub use calibration::Calibration;
pub use camera::CameraMotion;
pub use config::{Config, ConfigError, CueMix, Readout, SizeMeasurement, Variant};
pub use correlation::{search_offset, CfConfig, CfTracker, ANCHOR_FRAMES};
pub use estimate::{Estimate, Status};
pub use model::TargetModel;
pub use particle::Particle;

use crate::cue::GradientMemo;
use crate::fixed::Q16;
use crate::ground::GroundPlane;
use crate::hist::Histogram;
use crate::image::{Binning, ImageView, Luma64, PixelFormat, Rgb8x8x4, Rgb8x8x8, Yuv8x8x4};
use crate::kalman::{SharedCovariance, Sym4};
use crate::map::ObjectMap;
use crate::profile::{CycleCounter, NoCounter, StageCycles, Stopwatch};
use crate::resample::{MAX_PARTICLES, WEIGHT_TOTAL};
use crate::rng::Rng;
use crate::window::{Ellipse, MAX_CAP};
use config::Derived;
use core::marker::PhantomData;
use particle::Bounds;

/// The most pixels a step of `particles` particles with a pixel cap of `cap` px reads
/// (see "Bounded work" in the module documentation), px.
pub const fn max_pixels_per_step(particles: usize, cap: u32) -> u64 {
    let cap = if cap < MAX_CAP { cap } else { MAX_CAP } as u64;
    let map_cells = (crate::map::SIDE * crate::map::SIDE) as u64;
    (particles as u64 + 10) * cap + 2 * map_cells
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
    if init.hx < config.min_half_axis || init.hy < config.min_half_axis {
        return Err(ConfigError::InitialTooSmall);
    }
    let centred = inside(init.cx, bounds.max_x) && inside(init.cy, bounds.max_y);
    centred.then_some(()).ok_or(ConfigError::InitialOutside)
}

/// A tracker of `N` particles on 8x8x8 RGB histograms (512 bins), the default.
pub type RgbTracker<const N: usize> = Tracker<Rgb8x8x8, N, 512>;
/// A tracker of `N` particles on 8x8x4 RGB histograms (256 bins: half the model's RAM).
pub type Rgb256Tracker<const N: usize> = Tracker<Rgb8x8x4, N, 256>;
/// A tracker of `N` particles on 8x8x4 YUV histograms (256 bins).
pub type YuvTracker<const N: usize> = Tracker<Yuv8x8x4, N, 256>;
/// A tracker of `N` particles on 64-level grey histograms.
pub type LumaTracker<const N: usize> = Tracker<Luma64, N, 64>;
/// The correlation-filter tracker at its defaults: 16 x 16 cells, 4 scales, 8x8x8 RGB
/// colour histograms (82,040 bytes on a 32-bit target).
pub type RgbCfTracker = CfTracker<Rgb8x8x8, 512, 16, 4>;

/// A tracker of `N` particles (`1..=65535`) on colour histograms of `B` bins laid out by
/// the binning `Bn` (`Bn::BINS == B`, checked at compile time).
///
/// Its RAM is its `size_of`, all inline: 48 bytes per particle (state, weight, gradient
/// cue, colour cost, resampling scratch), the colour model (about 19 KiB with 512 bins),
/// two scratch histograms, the object map (16.5 KiB), the 6 KiB gradient memo
/// (`cue::GradientMemo`) and under 1 KiB more: 54,456 bytes at N = 100 with 512
/// bins on x86-64 (pinned by `host-tests/tests/tracking.rs`).
#[derive(Clone, Debug)]
pub struct Tracker<Bn: Binning, const N: usize, const B: usize> {
    /// The configuration in use.
    config: Config,
    /// What [`Tracker::start`] derived from the configuration.
    derived: Derived,
    /// What the filter knows, carried from frame to frame.
    state: State<N, B>,
    /// Working memory of one step.
    scratch: Scratch<N, B>,
    /// What the last step did, and how often the weights vanished.
    report: Report,
    binning: PhantomData<Bn>,
}

/// The filter's state, carried from one frame to the next.
#[derive(Clone, Debug)]
struct State<const N: usize, const B: usize> {
    /// The random stream (`None` until [`Tracker::start`]).
    rng: Option<Rng>,
    particles: [Particle; N],
    /// The particles' weights, normalised to [`WEIGHT_TOTAL`].
    weights: [u32; N],
    /// The Kalman covariance of the particles' sizes, shared by all (RBPF).
    size_cov: SharedCovariance,
    /// What the tracker learnt of its target.
    model: TargetModel<B>,
    /// The ground-plane fit of the measured sizes.
    ground: GroundPlane,
    /// The last step's estimate (the initial ellipse before any).
    estimate: Estimate,
    /// The last estimate with status `Tracking`.
    last_confident: Ellipse,
    /// Mean recent innovation of the estimate against its constant-velocity prediction,
    /// px, Q16.16 (see [`Config::noise_gain`]); `None` until the first step while tracking.
    motion_spread: Option<Q16>,
}

/// Working memory of a step: written and read within one frame, meaningless between
/// frames.
#[derive(Clone, Debug)]
struct Scratch<const N: usize, const B: usize> {
    /// The gradient cue of each particle's window (RBPF).
    cues: [Q16; N],
    /// The colour cost of each particle's window.
    colour_costs: [Q16; N],
    /// Gradients already computed in this frame (RBPF).
    memo: GradientMemo,
    /// The particle indices the resampling drew.
    indices: [u16; N],
    /// Whether the last step resampled (then [`Scratch::indices`] holds its draw).
    resampled: bool,
    /// How many copies of each particle the resampling drew.
    counts: [u16; N],
    /// The histograms of the window being compared.
    histograms: [Histogram<B>; 2],
    /// This frame's object map.
    map: ObjectMap,
}

/// What the last step did, and a count since the start.
#[derive(Clone, Copy, Debug)]
struct Report {
    /// Pixels read.
    pixels_visited: u32,
    /// The factor of the scale the size measurement chose.
    scale_factor: Option<Q16>,
    /// Steps whose weights all vanished and were reset to uniform, since construction.
    weight_recoveries: u32,
}

impl Report {
    /// Adds `pixels` read to the step's count.
    fn read(&mut self, pixels: u32) {
        self.pixels_visited = self.pixels_visited.saturating_add(pixels);
    }
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
            state: State {
                rng: None,
                particles: [Particle::at(&origin); N],
                weights: [0; N],
                size_cov: SharedCovariance::UNSET,
                model: TargetModel::UNSET,
                ground: GroundPlane::new(),
                estimate: Estimate::lost_at(origin),
                last_confident: origin,
                motion_spread: None,
            },
            scratch: Scratch {
                cues: [Q16::ZERO; N],
                colour_costs: [Q16::ZERO; N],
                memo: GradientMemo::UNSTARTED,
                indices: [0; N],
                resampled: false,
                counts: [0; N],
                histograms: [Histogram::new(), Histogram::new()],
                map: ObjectMap::new(),
            },
            report: Report {
                pixels_visited: 0,
                scale_factor: None,
                weight_recoveries: 0,
            },
            binning: PhantomData,
        }
    }

    /// Checks `config`, builds the target model from the window `init` of `frame` and
    /// places every particle on `init`, in place, whatever the tracker did before; the
    /// random stream starts from `config.seed`.
    ///
    /// # Errors
    /// As [`Config::validate`] (the first bad field, or the gradient cue's or Kalman
    /// filter's refusal), [`ConfigError::ParticleCount`] for `N` outside `1..=65535`,
    /// [`ConfigError::InitialTooSmall`] for an ellipse with a half-axis below
    /// `min_half_axis`, [`ConfigError::InitialOutside`] for one centred outside the frame;
    /// the tracker is then unchanged.
    pub fn start<P: PixelFormat>(
        &mut self,
        config: Config,
        frame: &ImageView<'_, P>,
        init: impl Into<Ellipse>,
    ) -> Result<(), ConfigError> {
        let init = init.into();
        if N == 0 || N > MAX_PARTICLES {
            return Err(ConfigError::ParticleCount);
        }
        let derived = config.derive()?;
        check_init(&config, frame, &init)?;
        let initial = derived.initial_cov;
        self.state.size_cov = SharedCovariance::new(initial, initial, config.size_noise())?;
        self.config = config;
        self.derived = derived;
        self.state.model.colour.configure(config.colour());
        self.scratch.memo.clear();
        self.state.rng = Some(Rng::new(config.seed));
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
        init: impl Into<Ellipse>,
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
    /// [`ConfigError::InitialTooSmall`] or [`ConfigError::InitialOutside`] as for
    /// [`Tracker::start`]; the tracker is unchanged.
    pub fn reset<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        init: impl Into<Ellipse>,
    ) -> Result<(), ConfigError> {
        let init = init.into();
        if self.state.rng.is_none() {
            return self.start(Config::new(Variant::Rbpf), frame, init);
        }
        check_init(&self.config, frame, &init)?;
        let size_cov = self.initial_size_cov()?;
        self.state
            .model
            .colour
            .learn::<Bn, P>(frame, &init, &mut self.scratch.histograms);
        self.state.model.calibration = self.calibrate(frame, &init);
        self.state.ground = GroundPlane::new();
        self.place(init, size_cov);
        Ok(())
    }

    /// The size covariance every (re)start begins from, with the configured noise.
    fn initial_size_cov(&self) -> Result<SharedCovariance, ConfigError> {
        let initial = self.derived.initial_cov;
        let noise = *self.state.size_cov.noise();
        Ok(SharedCovariance::new(initial, initial, noise)?)
    }

    /// Every particle at rest on `init` with equal weights, the size covariance
    /// `size_cov`, and `init` the estimate.
    fn place(&mut self, init: Ellipse, size_cov: SharedCovariance) {
        let calibration = self.config.variant.calibration();
        let state = &mut self.state;
        state.particles = [Particle::at(&init); N];
        state.weights = [WEIGHT_TOTAL / N as u32; N];
        state.size_cov = size_cov;
        state.estimate = Estimate::first(init, calibration);
        state.last_confident = init;
        state.motion_spread = None;
        self.scratch.memo.start_frame();
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
        if self.state.rng.is_none() {
            return (self.state.estimate, cycles);
        }
        let bounds = Bounds::for_frame(frame.width(), frame.height(), self.config.min_half_axis);
        self.report.pixels_visited = 0;
        self.report.scale_factor = None;
        self.scratch.memo.start_frame();

        self.propagate(&bounds);
        cycles.propagate = watch.lap();

        self.weigh(frame);
        cycles.weigh = watch.lap();

        if self.config.variant == Variant::Rbpf && !self.config.freeze_size {
            self.update_sizes(frame, &bounds);
        }
        cycles.update = watch.lap();

        self.state.estimate = self.read_out(frame);
        cycles.estimate = watch.lap();

        self.resample_if_degenerate();
        cycles.resample = watch.lap();
        (self.state.estimate, cycles)
    }

    /// The ground-plane slope in use (`alpha / beta`, px of half-height per px the centre
    /// moves down, Q16.16): the learnt one once trustworthy (with
    /// [`Config::learn_scale_per_row`]), else [`Config::scale_per_row`].
    pub fn scale_per_row(&self) -> Q16 {
        let learnt = match self.config.learn_scale_per_row {
            // Rows spread over a quarter of the half-height at least (standard deviation).
            true => self.state.ground.slope(Q16::from_bits(
                self.state.last_confident.hy.to_bits() >> GROUND_SPREAD_SHARE_LOG2,
            )),
            false => None,
        };
        learnt.unwrap_or(self.config.scale_per_row)
    }

    /// The estimate of the last step (the initial ellipse before any).
    pub fn estimate(&self) -> Estimate {
        self.state.estimate
    }

    /// The configuration in use.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The particles, after the last step's resampling.
    pub fn particles(&self) -> &[Particle; N] {
        &self.state.particles
    }

    /// The particle indices the last step's resampling drew (`rbtrack::resample::resample`
    /// order, before the in-place copy), or `None` if the last step did not resample.
    /// For checking the filter against a reference that follows the same ancestry.
    pub fn last_resampling(&self) -> Option<&[u16; N]> {
        self.scratch.resampled.then_some(&self.scratch.indices)
    }

    /// The factor of the scale the last step's size measurement chose (RBPF:
    /// `1 + k scale_step`, `k` in `-2..=2`), or `None` when nothing was measured (colour PF,
    /// or every scale had likelihood 0).
    pub fn last_scale_factor(&self) -> Option<Q16> {
        self.report.scale_factor
    }

    /// Pixels read in the last step (`<= max_pixels_per_step(N, pixels_per_window)`).
    pub fn pixels_visited(&self) -> u32 {
        self.report.pixels_visited
    }

    /// Steps whose weights all vanished and were reset to uniform, since construction.
    pub fn weight_recoveries(&self) -> u32 {
        self.report.weight_recoveries
    }

    /// The Kalman covariance of the particles' sizes `(Hx, dHx, Hy, dHy)`, shared by every
    /// particle (RBPF; the colour PF leaves it at its initial value). Read-only, for checks
    /// such as the long-run soak test.
    pub fn size_covariance(&self) -> Sym4 {
        self.state.size_cov.cov()
    }
}

/// The spread of rows the learnt ground plane needs, as a share of the last confident
/// half-height: `2^-GROUND_SPREAD_SHARE_LOG2`, a quarter.
const GROUND_SPREAD_SHARE_LOG2: u32 = 2;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Gray8, Luma64, Rgb888, Rgb8x8x8};

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
            Err(ConfigError::InitialTooSmall)
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

    /// Regression (found by the `tracker` fuzz target): a frozen size larger than the
    /// frame was reported as it was, past the frame's longer side.
    #[test]
    fn a_frozen_size_stays_within_the_frame() {
        let (buf, init, mut config) = still_target(Q16::ZERO);
        config.freeze_size = true;
        let huge = Ellipse {
            hx: Q16::from_int(30_000),
            hy: Q16::from_int(20_000),
            ..init
        };
        let frame = ImageView::<Gray8>::new(&buf, 64, 48, 64).unwrap();
        for variant in [Variant::ColourPf, Variant::Rbpf] {
            config.variant = variant;
            let mut t = Tracker::<Luma64, 50, 64>::new(config, &frame, huge).unwrap();
            let e = t.step(&frame).ellipse;
            assert_eq!((e.hx, e.hy), (Q16::from_int(63), Q16::from_int(63)));
            let mut normal = Tracker::<Luma64, 50, 64>::new(config, &frame, init).unwrap();
            assert_eq!(normal.step(&frame).ellipse.hx, init.hx, "{variant:?}");
        }
    }

    /// Regression (found by the `tracker` fuzz target): a one-row frame may have any
    /// stride, and its row length in bytes overflowed when the gradient cue read it.
    #[test]
    fn a_one_row_frame_of_any_stride_steps() {
        let buf = [90u8; 64 * 3];
        let frame = ImageView::<Rgb888>::new(&buf, 64, 1, usize::MAX / 2).unwrap();
        let init = Ellipse::new(
            Q16::from_int(30),
            Q16::ZERO,
            Q16::from_int(8),
            Q16::from_int(8),
        );
        let config = Config::new(Variant::Rbpf);
        let mut t = Tracker::<Rgb8x8x8, 8, 512>::new(config, &frame, init).unwrap();
        for _ in 0..3 {
            assert_eq!(t.step(&frame).ellipse.cy, Q16::ZERO);
        }
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
