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
//!    highest likelihood (same cues as the particles) gives `Y = (Hy, Hx)`; every leaf mean
//!    takes the Kalman update with the shared gain, unless that window's Bhattacharyya
//!    coefficient is below `lost_below` (no target there: the prediction stands).
//! 4. **Estimate**: weighted mean, best particle or robust mean; its window's Bhattacharyya
//!    coefficient is the confidence, which sets the [`Status`] and, when high, blends the
//!    window's histogram into the model.
//! 5. **Resample** when the effective sample size is below `resample_below * N`.
//!
//! # Bounded work
//! A step visits at most `(N + 6) * pixels_per_window` pixels: `N` particle windows, one
//! estimate window and, for the RBPF, five scale windows; the RBPF's gradient cue reads
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

pub use config::{Config, ConfigError, CueMix, Readout, Variant};
pub use particle::Particle;

use crate::cue::{GradientConfig, GradientCue, GradientMemo};
use crate::fixed::Q16;
use crate::hist::{Histogram, Model};
use crate::image::{Binning, ImageView, PixelFormat};
use crate::kalman::{BlockNoise, SharedCovariance, Sym2};
use crate::likelihood::exp_neg;
use crate::profile::{CycleCounter, NoCounter, StageCycles, Stopwatch};
use crate::resample::{
    effective_sample_size_at_least, normalise, replicate, resample, Normalised, WEIGHT_TOTAL,
};
use crate::rng::Rng;
use crate::window::Ellipse;
use config::Derived;
use core::marker::PhantomData;
use particle::{predict_leaf, scale_randomly, Bounds, Motion};

/// How sure the tracker is of its estimate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Status {
    /// Confidence at or above `uncertain_below`.
    Tracking,
    /// Confidence in `[lost_below, uncertain_below)`; like `Lost`, the tracker searches
    /// the whole frame with part of its particles.
    Uncertain,
    /// Confidence below `lost_below`.
    Lost,
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
    leaf_cov: SharedCovariance,
    rng: Rng,
    particles: [Particle; N],
    weights: [u32; N],
    /// The gradient cue of each particle's window, this frame (RBPF).
    cue_values: [Q16; N],
    /// Gradients already computed in this frame (RBPF).
    memo: GradientMemo,
    indices: [u16; N],
    counts: [u16; N],
    resampled: bool,
    scale_factor: Option<Q16>,
    model: Model<B>,
    hist: Histogram<B>,
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
    /// Checks `config`, builds the target model from the window `init` of `frame` and
    /// places every particle on `init`.
    ///
    /// # Errors
    /// [`ConfigError::OutOfRange`] naming the first bad field, [`ConfigError::ParticleCount`]
    /// for `N` outside `1..=65535`, [`ConfigError::InitialEllipse`] for an ellipse with a
    /// half-axis below `min_half_axis` or a centre outside the frame.
    pub fn new<P: PixelFormat>(
        config: Config,
        frame: &ImageView<'_, P>,
        init: Ellipse,
    ) -> Result<Self, ConfigError> {
        const { assert!(Bn::BINS == B, "the binning must have B bins") };
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
        let leaf_cov = SharedCovariance::new(initial_cov, initial_cov, noise)
            .map_err(|_| ConfigError::OutOfRange("kalman_q"))?;
        let mut tracker = Self {
            config,
            derived,
            cue,
            initial_cov,
            leaf_cov,
            rng: Rng::new(config.seed),
            particles: [Particle::default(); N],
            weights: [0; N],
            cue_values: [Q16::ZERO; N],
            memo: GradientMemo::new(),
            indices: [0; N],
            counts: [0; N],
            resampled: false,
            scale_factor: None,
            model: Model::from_histogram(&Histogram::new()),
            hist: Histogram::new(),
            estimate: Estimate {
                ellipse: init,
                vx: Q16::ZERO,
                vy: Q16::ZERO,
                confidence: Q16::ONE,
                status: Status::Tracking,
            },
            last_confident: init,
            motion_spread: None,
            pixels_visited: 0,
            weight_recoveries: 0,
            binning: PhantomData,
        };
        tracker.reset(frame, init)?;
        Ok(tracker)
    }

    /// Re-initialises on the window `init` of `frame` (new model, particles on `init`,
    /// fresh covariance) without rebuilding; the random stream continues.
    ///
    /// # Errors
    /// [`ConfigError::InitialEllipse`] as for [`Tracker::new`]; the tracker is unchanged.
    pub fn reset<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        init: Ellipse,
    ) -> Result<(), ConfigError> {
        let bounds = Bounds::for_frame(frame.width(), frame.height(), self.config.min_half_axis);
        let inside = |v: Q16, max: Q16| v >= Q16::ZERO && v <= max;
        if init.hx < self.config.min_half_axis
            || init.hy < self.config.min_half_axis
            || !inside(init.cx, bounds.max_x)
            || !inside(init.cy, bounds.max_y)
        {
            return Err(ConfigError::InitialEllipse);
        }
        self.hist
            .fill::<Bn, P>(frame, &init, self.config.pixels_per_window);
        self.model = Model::from_histogram(&self.hist);
        self.particles = [Particle::at(&init); N];
        self.weights = [WEIGHT_TOTAL / N as u32; N];
        self.leaf_cov =
            SharedCovariance::new(self.initial_cov, self.initial_cov, *self.leaf_cov.noise())
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
        let bounds = Bounds::for_frame(frame.width(), frame.height(), self.config.min_half_axis);
        self.pixels_visited = 0;
        self.scale_factor = None;
        self.memo.start_frame();

        self.propagate(&bounds);
        cycles.propagate = watch.lap();

        self.weigh(frame);
        cycles.weigh = watch.lap();

        if self.config.variant == Variant::Rbpf {
            self.update_sizes(frame, &bounds);
        }
        cycles.update = watch.lap();

        self.estimate = self.read_out(frame);
        cycles.estimate = watch.lap();

        self.resample_if_degenerate();
        cycles.resample = watch.lap();
        (self.estimate, cycles)
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

    /// Pixels read into histograms in the last step (`<= (N + 6) * pixels_per_window`).
    pub fn pixels_visited(&self) -> u32 {
        self.pixels_visited
    }

    /// Steps whose weights all vanished and were reset to uniform, since construction.
    pub fn weight_recoveries(&self) -> u32 {
        self.weight_recoveries
    }

    /// The Kalman covariance of the leaf `(Hy, dHy, Hx, dHx)` that every particle shares
    /// (RBPF; the colour PF leaves it at its initial value). Read-only, for checks such
    /// as the long-run soak test.
    pub fn leaf_covariance(&self) -> crate::kalman::Sym4 {
        self.leaf_cov.cov()
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
        let rng = &mut self.rng;
        for p in self.particles.iter_mut() {
            let y_before = p.y;
            motion.drift(p, rng, bounds);
            match self.config.variant {
                Variant::ColourPf => scale_randomly(p, self.config.scale_noise, rng, bounds),
                Variant::Rbpf => {
                    if searching {
                        (p.leaf[1], p.leaf[3]) = (Q16::ZERO, Q16::ZERO);
                    }
                    let dy = p.y - y_before;
                    predict_leaf(p, dy, self.config.scale_per_row, rate_noise, rng, bounds)
                }
            }
        }
        if self.config.variant == Variant::Rbpf {
            self.leaf_cov.predict(Q16::ONE);
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
        Motion::new(&self.config, Q16::ONE).position_sigma(e.hy, e.hx)
    }

    /// Re-draws `redetect_share` of the particles uniformly over the frame, at rest, sized
    /// as the last confident estimate moved along the ground-plane relation to their row.
    fn redetect(&mut self, bounds: &Bounds) {
        let count = (self.config.redetect_share.to_bits() as u64 * N as u64) >> 16;
        let last = self.last_confident;
        let width = bounds.max_x.floor_int() as u32 + 1;
        let height = bounds.max_y.floor_int() as u32 + 1;
        for p in self.particles.iter_mut().take(count as usize) {
            let x = Q16::from_int(self.rng.below(width) as i32);
            let y = Q16::from_int(self.rng.below(height) as i32);
            let hy = last.hy + self.config.scale_per_row * (y - last.cy);
            let (hy, hx) = bounds.halves(hy, last.hx * (hy / last.hy));
            *p = Particle::at(&Ellipse {
                cx: x,
                cy: y,
                hx,
                hy,
            });
        }
        self.weights = [WEIGHT_TOTAL / N as u32; N];
    }

    /// Likelihood of window `e`, Q0.16 in `0..=65535`, and its Bhattacharyya coefficient;
    /// `cue` is the window's gradient cue if already known (RBPF).
    fn likelihood<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        e: &Ellipse,
        cue: Option<Q16>,
    ) -> (u32, Q16) {
        self.pixels_visited = self.pixels_visited.saturating_add(self.hist.fill::<Bn, P>(
            frame,
            e,
            self.config.pixels_per_window,
        ));
        let rho = self.hist.bhattacharyya(&self.model);
        let colour_cost = self.derived.colour.cost(Q16::ONE - rho);
        let likelihood = match self.config.variant {
            Variant::ColourPf => exp_neg(colour_cost),
            Variant::Rbpf => {
                let g = match cue {
                    Some(g) => g,
                    None => self.cue.evaluate_memo(frame, e, &mut self.memo),
                };
                let miss = Q16::ONE - g;
                let gradient_cost = self.derived.gradient.cost(miss * miss);
                match self.config.cue_mix {
                    CueMix::Product => exp_neg(colour_cost + gradient_cost),
                    CueMix::Average(a) => {
                        let a = a.to_bits() as u64; // Q16.16 in 0..=65536
                        ((a * exp_neg(colour_cost) as u64
                            + (65536 - a) * exp_neg(gradient_cost) as u64)
                            >> 16) as u32
                    }
                }
            }
        };
        (likelihood, rho)
    }

    fn weigh<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>) {
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
        for i in 0..N {
            let e = self.particles[i].ellipse();
            let cue = self.cue_values[i];
            let (likelihood, _) = self.likelihood(frame, &e, Some(cue));
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
        let mean = self.weighted_mean(|_| true);
        let step = self.config.scale_step;
        let mut best = (0u32, Q16::ONE, Q16::ZERO);
        for k in [0, -1, 1, -2, 2] {
            let factor = Q16::ONE + step.mul_int(k);
            let (hy, hx) = bounds.halves(mean.ellipse.hy * factor, mean.ellipse.hx * factor);
            let e = Ellipse {
                hx,
                hy,
                ..mean.ellipse
            };
            let (likelihood, rho) = self.likelihood(frame, &e, None);
            if likelihood > best.0 {
                best = (likelihood, factor, rho);
            }
        }
        let gain = self.leaf_cov.gain();
        self.leaf_cov.update_cov();
        if best.0 == 0 || best.2 < self.config.lost_below {
            return;
        }
        self.scale_factor = Some(best.1);
        let (hy, hx) = bounds.halves(mean.ellipse.hy * best.1, mean.ellipse.hx * best.1);
        let y = [hy, hx];
        for p in self.particles.iter_mut() {
            gain.update_mean(&mut p.leaf, y);
            (p.leaf[0], p.leaf[2]) = bounds.halves(p.leaf[0], p.leaf[2]);
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
                .zip([p.x, p.y, p.vx, p.vy, p.leaf[2], p.leaf[0]])
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
        self.pixels_visited = self.pixels_visited.saturating_add(self.hist.fill::<Bn, P>(
            frame,
            &estimate.ellipse,
            self.config.pixels_per_window,
        ));
        let confidence = self.hist.bhattacharyya(&self.model);
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
            self.model.update(&self.hist, self.config.adapt_rate);
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
        if resample(scheme, &mut self.weights, &mut self.rng, &mut self.indices).is_ok() {
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
