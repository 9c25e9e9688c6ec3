//! f64 reference implementations of the two trackers (colour PF and RBPF), the oracle the
//! fixed-point core in `rbtrack::tracker` is checked against.
//!
//! [`ReferenceTracker`] mirrors `Tracker::step` stage for stage (propagate, weigh, update,
//! estimate, resample) and consumes **the same random draws in the same order**: it owns an
//! `rbtrack::rng::Rng` seeded with `config.seed` and calls `normal`, `below` and the
//! resampling draws exactly where the core does, converting each draw to f64
//! (`Q16::to_f64`). Given the same frames, both filters then move the same particles by
//! the same noise, and differ only by arithmetic.
//!
//! # What is f64
//! Everything computed from the draws and the frame:
//! - motion: `v <- keep v + sigma_v n`, `x <- x + v + sigma n` with
//!   `sigma = position_noise + relative_noise (Hx + Hy) / 2`, centre clamped to the frame;
//!   with `noise_gain`, both noises times `clamp(gain s / sigma(estimate), floor, 1)`, `s`
//!   the innovation mean (`s += ((|dx| + |dy|) / 2 - s) / 8` after each tracking step);
//! - colour PF size: both half-axes times `1 + sigma n`; RBPF size (eq. 7):
//!   `Hy^- = Hy + dHy + k dy`, `Hx^- = Hx Hy^- / Hy`, rates `+ sigma n`; half-axes clamped
//!   to `[min_half_axis, max(width, height) - 1]`;
//! - histograms: kernel `1 - d^2` with `d` from the f64 ellipse, over the pixel set the
//!   core's sampling lattice visits ([`rbtrack::window::visit`] enumerates the pixels, on
//!   the ellipse rounded to Q16.16; its fixed-point weights are ignored);
//! - Bhattacharyya `sum sqrt(p_u q_u)`, the gradient cue (the core's boundary points from
//!   its tabulated angles `GradientCue::angle`, normals, rounding of the search samples,
//!   magnitudes by `f64::hypot` of the exact integer 5-tap gradients), costs
//!   `(1 - rho) / (2 sigma_c^2)` and `(1 - g)^2 / (2 sigma_g^2)`;
//! - likelihood `exp(-cost)`, zero at costs of at least [`COST_MAX`] (the core's defined
//!   cut-off, so that "all weights vanished" means the same in both);
//! - weights, their normalisation and the uniform recovery, the effective sample size;
//! - the shared Kalman covariance (`P^- = A P A^T + Q`, `K = P H^T / S`, `P -= K H P`) and
//!   the size mean update; the five-scale size measurement;
//! - read-out (mean, best, robust mean), confidence, status, model adaptation
//!   `q <- (1 - a) q + a p`, and redetection while not `Tracking`.
//!
//! # Resampling
//! Systematic, stratified and multinomial resampling are reimplemented in f64 on the f64
//! cumulative weights, with positions from the same 24-bit uniform draws as
//! `rbtrack::resample::resample` (`next_u32 >> 8`, one per frame or one per particle):
//! particle `j` is taken for position `r` when it is the smallest with `c_j > r`.
//! Residual resampling, whose number of draws depends on integer copy counts, converts
//! the f64 weights to the core's integer form (`round(w 2^24)`) and calls
//! `rbtrack::resample::resample` itself. The drawn indices are then applied with the
//! core's in-place slot layout, so particle `i` of the reference is particle `i` of the
//! core.
//!
//! # Two ways to step
//! - [`ReferenceTracker::step`]: fully independent; the reference decides and draws its
//!   own resampling from its own weights.
//! - [`ReferenceTracker::step_following`]: the reference still makes its own discrete
//!   choices (and consumes the draws), but then adopts the core's ([`CoreChoices`]): the
//!   resampling (`Tracker::last_resampling`), so both filters keep one ancestry, and the
//!   scale the RBPF's size measurement picked (`Tracker::last_scale_factor`). It counts
//!   where its own choice differed ([`Coupling`]). Everything continuous stays its own.
//!
//! Why the second: resampling is discontinuous in the weights. When a cumulative weight
//! lies closer to a systematic position than the arithmetic difference between two
//! implementations, one copy goes to a neighbouring particle; the copy carries a different
//! weight next frame, shifting every later cumulative weight, and within a few frames the
//! two particle sets are unrelated (two equally valid Monte Carlo runs, about 1 px apart
//! with 100 particles). Measured on the perspective scene, seeds 1..=3: two *f64*
//! trackers whose likelihoods differ by a relative 1e-4 part within 16-61 frames in 5 of
//! 6 runs (then 2-4 px apart at worst), by 1e-5 in 2 of 3 RBPF runs, by 1e-6 in none;
//! Q16.16 likelihoods (`exp` table steps of 1/65535, measured mean relative difference
//! 5e-5) cannot be that close. The RBPF's size measurement is a second switch: the arg-max of five likelihoods
//! that are often within a few per cent of each other, and the gradient cue is piecewise
//! constant in the ellipse (search samples round to pixels), so a 0.01 px difference in
//! the mean ellipse can reorder two scales; a different scale moves every size by about
//! `K * scale_step * H`, roughly 1 px. Following the core's choices removes this chaos and
//! leaves what the comparison is for: the arithmetic of propagation, cues, weights, Kalman
//! update and read-out.

use rbtrack::cue::{gradient, GradientCue};
use rbtrack::fixed::Q16;
use rbtrack::image::{Binning, ImageView, PixelFormat};
use rbtrack::likelihood::COST_MAX;
use rbtrack::resample::{replicate, resample, Scheme, WEIGHT_TOTAL};
use rbtrack::rng::Rng;
use rbtrack::tracker::{Config, ConfigError, CueMix, Readout, Status, Tracker, Variant};
use rbtrack::window::{visit, Ellipse};
use std::marker::PhantomData;

/// An ellipse in f64: centre and half-axes, px.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RefEllipse {
    /// Centre column, px.
    pub cx: f64,
    /// Centre row, px.
    pub cy: f64,
    /// Horizontal half-axis, px.
    pub hx: f64,
    /// Vertical half-axis, px.
    pub hy: f64,
}

impl RefEllipse {
    /// The f64 value of a Q16.16 ellipse (exact).
    pub fn from_q16(e: &Ellipse) -> Self {
        Self {
            cx: e.cx.to_f64(),
            cy: e.cy.to_f64(),
            hx: e.hx.to_f64(),
            hy: e.hy.to_f64(),
        }
    }

    /// Rounded to Q16.16 (only to enumerate the pixels of the window).
    pub fn to_q16(&self) -> Ellipse {
        Ellipse::new(
            Q16::from_f64(self.cx),
            Q16::from_f64(self.cy),
            Q16::from_f64(self.hx),
            Q16::from_f64(self.hy),
        )
    }
}

/// One particle in f64, laid out as `rbtrack::tracker::Particle`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RefParticle {
    /// Centre column, px.
    pub x: f64,
    /// Centre row, px.
    pub y: f64,
    /// Horizontal velocity, px/frame.
    pub vx: f64,
    /// Vertical velocity, px/frame.
    pub vy: f64,
    /// Half-axes, px, and their rates, px/frame.
    pub size: RefSize,
}

/// A particle's size in f64, laid out as `rbtrack::kalman::Size`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RefSize {
    /// Horizontal half-axis, px.
    pub hx: f64,
    /// Its rate, px/frame.
    pub dhx: f64,
    /// Vertical half-axis, px.
    pub hy: f64,
    /// Its rate, px/frame.
    pub dhy: f64,
}

impl RefParticle {
    /// A particle at rest on `e`.
    pub fn at(e: &RefEllipse) -> Self {
        Self {
            x: e.cx,
            y: e.cy,
            vx: 0.0,
            vy: 0.0,
            size: RefSize {
                hx: e.hx,
                hy: e.hy,
                ..RefSize::default()
            },
        }
    }

    /// The particle's window.
    pub fn ellipse(&self) -> RefEllipse {
        RefEllipse {
            cx: self.x,
            cy: self.y,
            hx: self.size.hx,
            hy: self.size.hy,
        }
    }
}

/// The reference's estimate after a step, as `rbtrack::tracker::Estimate` in f64.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RefEstimate {
    /// Centre and half-axes, px.
    pub ellipse: RefEllipse,
    /// Horizontal velocity, px/frame.
    pub vx: f64,
    /// Vertical velocity, px/frame.
    pub vy: f64,
    /// Bhattacharyya coefficient of the estimate's window against the model, in `[0, 1]`.
    pub confidence: f64,
    /// Tracking, uncertain or lost (same thresholds as the core).
    pub status: Status,
}

/// The core's discrete choices in one step, adopted by
/// [`ReferenceTracker::step_following`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CoreChoices {
    /// The indices the core's resampling drew, `None` if it did not resample.
    pub resampling: Option<Vec<u16>>,
    /// The factor of the scale the core's size measurement picked (RBPF), `None` if it
    /// measured nothing.
    pub scale_factor: Option<Q16>,
}

impl CoreChoices {
    /// The choices of `tracker`'s last step.
    pub fn of<Bn: Binning, const N: usize, const B: usize>(tracker: &Tracker<Bn, N, B>) -> Self {
        Self {
            resampling: tracker.last_resampling().map(|r| r.to_vec()),
            scale_factor: tracker.last_scale_factor(),
        }
    }
}

/// Where the reference's own discrete choices differed from the one it followed
/// ([`ReferenceTracker::step_following`]), since construction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Coupling {
    /// Steps where the reference's own effective-sample-size test decided otherwise.
    pub decisions: u32,
    /// Drawn indices (over all steps where both resampled) that differed.
    pub index_flips: u32,
    /// Steps where the size measurement picked another scale (RBPF).
    pub scales: u32,
}

/// Smallest half-height divided by in the aspect-ratio step (the core's one raw unit).
const EPS_HALF: f64 = 1.0 / 65536.0;

/// Frame limits: largest centre column and row, half-axis range, px.
#[derive(Clone, Copy, Debug)]
struct Bounds {
    max_x: f64,
    max_y: f64,
    min_half: f64,
    max_half: f64,
    max_speed: f64,
}

impl Bounds {
    fn for_frame(width: usize, height: usize, min_half: f64) -> Self {
        let (max_x, max_y) = (width as f64 - 1.0, height as f64 - 1.0);
        Self {
            max_x,
            max_y,
            min_half,
            max_half: max_x.max(max_y).max(min_half),
            max_speed: (width.max(height) / 4) as f64,
        }
    }

    /// `(hx, hy)` into range keeping their ratio (the core's `Bounds::halves`).
    fn halves(&self, hx: f64, hy: f64) -> (f64, f64) {
        let small = hx.min(hy);
        let (hx, hy) = if small <= 0.0 {
            (hx.max(self.min_half), hy.max(self.min_half))
        } else if small < self.min_half {
            (hx * self.min_half / small, hy * self.min_half / small)
        } else {
            (hx, hy)
        };
        (hx.min(self.max_half), hy.min(self.max_half))
    }
}

/// Covariance `[[p00, p01], [p01, p11]]` of one (half-axis, rate) block of the size.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Block {
    p00: f64,
    p01: f64,
    p11: f64,
}

impl Block {
    /// `P <- A P A^T + diag(q, q)`, `A = [[1, 1], [0, 1]]`.
    fn predict(&mut self, q: f64) {
        let Self { p00, p01, p11 } = *self;
        *self = Self {
            p00: p00 + 2.0 * p01 + p11 + q,
            p01: p01 + p11,
            p11: p11 + q,
        };
    }

    /// Gain `(k_position, k_rate) = P[:, 0] / (p00 + r)`.
    fn gain(&self, r: f64) -> [f64; 2] {
        let s = self.p00 + r;
        [self.p00 / s, self.p01 / s]
    }

    /// `P <- P - K H P`.
    fn update(&mut self, r: f64) {
        let s = self.p00 + r;
        let Self { p00, p01, p11 } = *self;
        *self = Self {
            p00: p00 - p00 * p00 / s,
            p01: p01 - p00 * p01 / s,
            p11: p11 - p01 * p01 / s,
        };
    }
}

/// `exp(-cost)` with the core's cut-off: 0 at costs of at least [`COST_MAX`].
fn exp_neg(cost: f64) -> f64 {
    if cost >= COST_MAX.to_f64() {
        0.0
    } else {
        (-cost.max(0.0)).exp()
    }
}

/// `1 / (2 sigma^2)`.
fn cost_scale(sigma: Q16) -> f64 {
    let s = sigma.to_f64();
    1.0 / (2.0 * s * s)
}

/// The f64 reference tracker on colour histograms of the binning `Bn`; `N` is chosen at
/// run time. See the module docs.
#[derive(Clone, Debug)]
pub struct ReferenceTracker<Bn: Binning> {
    config: Config,
    cue: GradientCue,
    rng: Rng,
    particles: Vec<RefParticle>,
    weights: Vec<f64>,
    /// Target model `q_u`, sums to 1.
    model: Vec<f64>,
    /// Shared size covariance: `(Hx, dHx)` and `(Hy, dHy)` blocks.
    cov: [Block; 2],
    estimate: RefEstimate,
    last_confident: RefEllipse,
    /// Innovation mean, px (`noise_gain`); `None` until a step while tracking.
    motion_spread: Option<f64>,
    weight_recoveries: u32,
    coupling: Coupling,
    binning: PhantomData<Bn>,
}

/// The first setting of `config` the reference does not model (it models the papers'
/// trackers, `Config::paper`): the background-aware colour model, the object map, the
/// contrast size measurement, the re-detection prior, the learnt ground plane, frozen
/// sizes.
pub fn unmodelled(config: &Config) -> Option<&'static str> {
    let paper = Config::paper(config.variant);
    [
        (config.background_weighting, "background_weighting"),
        (config.split_halves, "split_halves"),
        (config.contrast_sigma.is_some(), "contrast_sigma"),
        (
            config.size_measurement != paper.size_measurement,
            "size_measurement",
        ),
        (config.redetect_prior != Q16::ONE, "redetect_prior"),
        (config.spread_penalty != Q16::ZERO, "spread_penalty"),
        (config.learn_scale_per_row, "learn_scale_per_row"),
        (config.freeze_size, "freeze_size"),
    ]
    .into_iter()
    .find_map(|(used, field)| used.then_some(field))
}

impl<Bn: Binning> ReferenceTracker<Bn> {
    /// Starts like `Tracker::<Bn, N, _>::new(config, frame, init)` with `n` particles.
    ///
    /// # Errors
    /// As the core: a field out of range, `n` outside `1..=65535`, or an initial ellipse
    /// too small or centred outside the frame; and `OutOfRange` naming a setting the
    /// reference does not model ([`unmodelled`]).
    pub fn new<P: PixelFormat>(
        config: Config,
        n: usize,
        frame: &ImageView<'_, P>,
        init: &Ellipse,
    ) -> Result<Self, ConfigError> {
        config.validate()?;
        if let Some(field) = unmodelled(&config) {
            return Err(ConfigError::OutOfRange(field));
        }
        if n == 0 || n > rbtrack::resample::MAX_PARTICLES {
            return Err(ConfigError::ParticleCount);
        }
        let cue = GradientCue::new(&config.gradient())?;
        let bounds = bounds(&config, frame);
        let init = RefEllipse::from_q16(init);
        let inside = |v: f64, max: f64| (0.0..=max).contains(&v);
        if init.hx < bounds.min_half || init.hy < bounds.min_half {
            return Err(ConfigError::InitialTooSmall);
        }
        if !inside(init.cx, bounds.max_x) || !inside(init.cy, bounds.max_y) {
            return Err(ConfigError::InitialOutside);
        }
        let (r, q) = (config.kalman_r.to_f64(), config.kalman_q.to_f64());
        let block = Block {
            p00: r,
            p01: 0.0,
            p11: q,
        };
        let mut tracker = Self {
            config,
            cue,
            rng: Rng::new(config.seed),
            particles: vec![RefParticle::at(&init); n],
            weights: vec![1.0 / n as f64; n],
            model: Vec::new(),
            cov: [block; 2],
            estimate: RefEstimate {
                ellipse: init,
                vx: 0.0,
                vy: 0.0,
                confidence: calibrated(&config, 1.0),
                status: Status::Tracking,
            },
            last_confident: init,
            motion_spread: None,
            weight_recoveries: 0,
            coupling: Coupling::default(),
            binning: PhantomData,
        };
        tracker.model = tracker.histogram(frame, &init);
        Ok(tracker)
    }

    /// One frame: propagate, weigh, update (RBPF), estimate, resample.
    pub fn step<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>) -> RefEstimate {
        self.filter(frame, None);
        if self.is_degenerate() {
            let indices = self.draw_indices();
            self.apply(&indices);
        }
        self.estimate
    }

    /// [`ReferenceTracker::step`], but adopting the core's discrete choices of its step on
    /// the same `frame` ([`CoreChoices::of`] the core after its step). The reference still
    /// draws its own indices when the core resampled, so the random streams stay aligned,
    /// and counts the differences in [`ReferenceTracker::coupling`].
    pub fn step_following<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        core: &CoreChoices,
    ) -> RefEstimate {
        self.filter(frame, Some(core.scale_factor));
        if self.is_degenerate() != core.resampling.is_some() {
            self.coupling.decisions += 1;
        }
        if let Some(given) = &core.resampling {
            let own = self.draw_indices();
            let given: Vec<usize> = given.iter().map(|&i| i as usize).collect();
            let flips = own.iter().zip(&given).filter(|(a, b)| a != b).count();
            self.coupling.index_flips += flips as u32;
            self.apply(&given);
        }
        self.estimate
    }

    /// Stages 1 to 4 of a step; sets the estimate. `scale`: the scale factor to adopt
    /// (`Some(None)`: measure nothing), `None` to use the reference's own.
    fn filter<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>, scale: Option<Option<Q16>>) {
        let bounds = bounds(&self.config, frame);
        self.propagate(&bounds);
        self.weigh(frame);
        if self.config.variant == Variant::Rbpf {
            let own = self.measure_scale(frame, &bounds);
            let factor = match scale {
                Some(given) => {
                    if given.map(Q16::to_f64) != own {
                        self.coupling.scales += 1;
                    }
                    given.map(Q16::to_f64)
                }
                None => own,
            };
            self.update_sizes(factor, &bounds);
        }
        self.estimate = self.read_out(frame);
    }

    /// The estimate of the last step (the initial ellipse before any).
    pub fn estimate(&self) -> RefEstimate {
        self.estimate
    }

    /// The particles, after the last step's resampling.
    pub fn particles(&self) -> &[RefParticle] {
        &self.particles
    }

    /// The weights, normalised (uniform after a resampling).
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The target model `q_u` (sums to 1).
    pub fn model(&self) -> &[f64] {
        &self.model
    }

    /// Bhattacharyya coefficient of window `e` of `frame` against the current model.
    pub fn rho_of<P: PixelFormat>(&self, frame: &ImageView<'_, P>, e: &RefEllipse) -> f64 {
        self.bhattacharyya(&self.histogram(frame, e))
    }

    /// Likelihood of window `e` of `frame` (colour cue, and gradient cue for the RBPF).
    pub fn likelihood_of<P: PixelFormat>(&self, frame: &ImageView<'_, P>, e: &RefEllipse) -> f64 {
        self.likelihood(frame, e)
    }

    /// Steps whose weights all vanished and were reset to uniform.
    pub fn weight_recoveries(&self) -> u32 {
        self.weight_recoveries
    }

    /// Differences from the resampling followed by [`ReferenceTracker::step_following`].
    pub fn coupling(&self) -> Coupling {
        self.coupling
    }

    // --- 1. Propagate ------------------------------------------------------------------

    fn propagate(&mut self, bounds: &Bounds) {
        let searching = self.estimate.status != Status::Tracking;
        if searching {
            self.redetect(bounds);
        }
        let scale = self.noise_scale();
        for i in 0..self.particles.len() {
            let mut p = self.particles[i];
            let y_before = p.y;
            self.drift(&mut p, scale, bounds);
            match self.config.variant {
                Variant::ColourPf => self.scale_randomly(&mut p, bounds),
                Variant::Rbpf => {
                    if searching {
                        (p.size.dhx, p.size.dhy) = (0.0, 0.0);
                    }
                    let dy = p.y - y_before;
                    self.predict_size(&mut p, dy, searching, bounds)
                }
            }
            self.particles[i] = p;
        }
        if self.config.variant == Variant::Rbpf {
            let q = self.config.kalman_q.to_f64();
            self.cov.iter_mut().for_each(|b| b.predict(q));
        }
    }

    /// A normal draw with standard deviation `sigma` (the core's `Rng::gaussian`).
    fn gaussian(&mut self, sigma: f64) -> f64 {
        self.rng.normal().to_f64() * sigma
    }

    /// Unscaled position noise of a particle with half-axes `hx`, `hy`, px.
    fn nominal_noise(&self, hx: f64, hy: f64) -> f64 {
        let c = &self.config;
        c.position_noise.to_f64() + c.relative_position_noise.to_f64() * (hx + hy) / 2.0
    }

    /// Factor on both motion noises this frame (`noise_gain`).
    fn noise_scale(&self) -> f64 {
        let gain = self.config.noise_gain.to_f64();
        match self.motion_spread {
            Some(s) if gain > 0.0 && self.estimate.status == Status::Tracking => {
                let e = &self.estimate.ellipse;
                (gain * s / self.nominal_noise(e.hx, e.hy))
                    .clamp(self.config.noise_floor.to_f64(), 1.0)
            }
            _ => 1.0,
        }
    }

    /// Constant-velocity drift with both noises times `f` (`noise_scale`).
    fn drift(&mut self, p: &mut RefParticle, f: f64, bounds: &Bounds) {
        let c = &self.config;
        let (keep, sigma_v) = (c.velocity_keep.to_f64(), f * c.velocity_noise.to_f64());
        let sigma = f * self.nominal_noise(p.size.hx, p.size.hy);
        let vmax = bounds.max_speed;
        p.vx = (keep * p.vx + self.gaussian(sigma_v)).clamp(-vmax, vmax);
        p.vy = (keep * p.vy + self.gaussian(sigma_v)).clamp(-vmax, vmax);
        p.x = (p.x + p.vx + self.gaussian(sigma)).clamp(0.0, bounds.max_x);
        p.y = (p.y + p.vy + self.gaussian(sigma)).clamp(0.0, bounds.max_y);
    }

    fn scale_randomly(&mut self, p: &mut RefParticle, bounds: &Bounds) {
        let factor = 1.0 + self.gaussian(self.config.scale_noise.to_f64());
        (p.size.hx, p.size.hy) = bounds.halves(p.size.hx * factor, p.size.hy * factor);
    }

    /// Eq. 7: the half-height follows the vertical motion, the aspect ratio is kept; no
    /// rate noise while searching.
    fn predict_size(&mut self, p: &mut RefParticle, dy: f64, searching: bool, bounds: &Bounds) {
        let RefSize { hx, dhx, hy, dhy } = p.size;
        let hy_raw = hy + dhy + self.config.scale_per_row.to_f64() * dy;
        let (hx, hy) = bounds.halves(hx * hy_raw / hy.max(EPS_HALF), hy_raw);
        let sigma = if searching {
            0.0
        } else {
            self.config.scale_noise.to_f64()
        };
        let dhy = dhy + self.gaussian(sigma);
        let dhx = dhx + self.gaussian(sigma);
        p.size = RefSize { hx, dhx, hy, dhy };
    }

    /// Re-draws `redetect_share` of the particles uniformly over the frame, at rest, sized
    /// by the ground-plane relation from the last confident estimate.
    fn redetect(&mut self, bounds: &Bounds) {
        let n = self.particles.len();
        let count = (self.config.redetect_share.to_f64() * n as f64).floor() as usize;
        let last = self.last_confident;
        let (width, height) = (bounds.max_x as u32 + 1, bounds.max_y as u32 + 1);
        let k = self.config.scale_per_row.to_f64();
        for i in 0..count {
            let x = self.rng.below(width) as f64;
            let y = self.rng.below(height) as f64;
            let hy = last.hy + k * (y - last.cy);
            let (hx, hy) = bounds.halves(last.hx * (hy / last.hy), hy);
            self.particles[i] = RefParticle::at(&RefEllipse {
                cx: x,
                cy: y,
                hx,
                hy,
            });
        }
        self.weights = vec![1.0 / n as f64; n];
    }

    // --- 2. Weigh ----------------------------------------------------------------------

    /// Kernel-weighted colour histogram of window `e`, normalised (all zero if empty).
    fn histogram<P: PixelFormat>(&self, frame: &ImageView<'_, P>, e: &RefEllipse) -> Vec<f64> {
        let mut hist = vec![0.0; Bn::BINS];
        let mut mass = 0.0;
        visit(
            frame,
            &e.to_q16(),
            self.config.pixels_per_window,
            |row, x, _| {
                let dx = (x as f64 - e.cx) / e.hx;
                let dy = (row.y() as f64 - e.cy) / e.hy;
                let w = (1.0 - dx * dx - dy * dy).max(0.0);
                hist[row.bin::<Bn>(x) as usize] += w;
                mass += w;
            },
        );
        if mass > 0.0 {
            hist.iter_mut().for_each(|h| *h /= mass);
        }
        hist
    }

    fn bhattacharyya(&self, p: &[f64]) -> f64 {
        p.iter()
            .zip(&self.model)
            .map(|(&p, &q)| (p * q).sqrt())
            .sum::<f64>()
            .min(1.0)
    }

    /// The boundary-gradient cue `g` in `[0, 1]` (see `rbtrack::cue`).
    fn gradient_cue<P: PixelFormat>(&self, frame: &ImageView<'_, P>, e: &RefEllipse) -> f64 {
        let (w, h) = (frame.width() as i64, frame.height() as i64);
        let search = self.cue.search_px() as i32;
        let saturation = self.cue.saturation() as f64;
        let mut sum = 0.0;
        for k in 0..self.cue.points() {
            let (c, s) = self.cue.angle(k);
            let (c, s) = (c.to_f64(), s.to_f64());
            let (bx, by) = (e.cx + e.hx * c, e.cy + e.hy * s);
            let (nx, ny) = (c / e.hx, s / e.hy);
            let len = nx.hypot(ny);
            let (ux, uy) = if len > 0.0 {
                (nx / len, ny / len)
            } else {
                (c, s)
            };
            let mut best = 0f64;
            for j in -search..=search {
                let x = (bx + j as f64 * ux + 0.5).floor() as i64;
                let y = (by + j as f64 * uy + 0.5).floor() as i64;
                if (0..w).contains(&x) && (0..h).contains(&y) {
                    let (gx, gy) = gradient(frame, x as i32, y as i32);
                    best = best.max((gx as f64).hypot(gy as f64));
                }
            }
            sum += (best / saturation).min(1.0);
        }
        sum / self.cue.points() as f64
    }

    /// The colour and gradient (RBPF, else 0) costs of window `e`.
    fn costs<P: PixelFormat>(&self, frame: &ImageView<'_, P>, e: &RefEllipse) -> (f64, f64) {
        let rho = self.bhattacharyya(&self.histogram(frame, e));
        let colour = cost_scale(self.config.colour_sigma) * (1.0 - rho);
        let gradient = match self.config.variant {
            Variant::ColourPf => 0.0,
            Variant::Rbpf => {
                let miss = 1.0 - self.gradient_cue(frame, e);
                cost_scale(self.config.gradient_sigma) * miss * miss
            }
        };
        (colour, gradient)
    }

    /// The core's likelihood of costs `(colour, gradient)`: `exp(-(colour + gradient -
    /// offset))`, or with `CueMix::Average` (RBPF) `a exp(-colour) + (1 - a)
    /// exp(-gradient)`.
    fn combine(&self, (colour, gradient): (f64, f64), offset: f64) -> f64 {
        match (self.config.variant, self.config.cue_mix) {
            (Variant::Rbpf, CueMix::Average(a)) => {
                let a = a.to_f64();
                a * exp_neg(colour) + (1.0 - a) * exp_neg(gradient)
            }
            _ => exp_neg(colour + gradient - offset),
        }
    }

    /// Likelihood of window `e` (no offset: the size measurement's ranking).
    fn likelihood<P: PixelFormat>(&self, frame: &ImageView<'_, P>, e: &RefEllipse) -> f64 {
        self.combine(self.costs(frame, e), 0.0)
    }

    /// Weights times likelihoods, the costs shifted by the frame's smallest as in the core.
    fn weigh<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>) {
        let costs: Vec<(f64, f64)> = self
            .particles
            .iter()
            .map(|p| self.costs(frame, &p.ellipse()))
            .collect();
        let offset = costs
            .iter()
            .map(|(c, g)| c + g)
            .fold(f64::INFINITY, f64::min);
        let likelihoods: Vec<f64> = costs.iter().map(|&c| self.combine(c, offset)).collect();
        for (w, l) in self.weights.iter_mut().zip(likelihoods) {
            *w *= l;
        }
        let total: f64 = self.weights.iter().sum();
        let n = self.weights.len() as f64;
        if total > 0.0 {
            self.weights.iter_mut().for_each(|w| *w /= total);
        } else {
            self.weights.iter_mut().for_each(|w| *w = 1.0 / n);
            self.weight_recoveries += 1;
        }
    }

    // --- 3. Update (RBPF) --------------------------------------------------------------

    /// The factor of the most likely of five scales of the weighted mean's ellipse
    /// (`1 + {0, -1, 1, -2, 2} scale_step`, the first of equals), `None` if all are 0.
    fn measure_scale<P: PixelFormat>(
        &self,
        frame: &ImageView<'_, P>,
        bounds: &Bounds,
    ) -> Option<f64> {
        let mean = self.weighted_mean(|_| true).ellipse;
        let step = self.config.scale_step.to_f64();
        let mut best = (0.0, 1.0, 0.0);
        for k in [0.0, -1.0, 1.0, -2.0, 2.0] {
            let factor = 1.0 + step * k;
            let (hx, hy) = bounds.halves(mean.hx * factor, mean.hy * factor);
            let e = RefEllipse { hx, hy, ..mean };
            let likelihood = self.likelihood(frame, &e);
            if likelihood > best.0 {
                let rho = self.bhattacharyya(&self.histogram(frame, &e));
                best = (likelihood, factor, rho);
            }
        }
        (best.0 > 0.0 && calibrated(&self.config, best.2) >= self.config.lost_below.to_f64())
            .then_some(best.1)
    }

    /// Measures the size as the weighted mean's times `factor` and gives every size the
    /// Kalman update with the shared gain (`None`: no measurement, the means keep their
    /// prediction); the shared covariance takes its update either way.
    fn update_sizes(&mut self, factor: Option<f64>, bounds: &Bounds) {
        let r = self.config.kalman_r.to_f64();
        let gains = self.cov.map(|b| b.gain(r));
        self.cov.iter_mut().for_each(|b| b.update(r));
        let Some(factor) = factor else {
            return;
        };
        let mean = self.weighted_mean(|_| true).ellipse;
        let (hx, hy) = bounds.halves(mean.hx * factor, mean.hy * factor);
        let [gain_x, gain_y] = gains;
        // `(position, rate) += K (y - position)`.
        let update = |position: &mut f64, rate: &mut f64, [k0, k1]: [f64; 2], y: f64| {
            let innovation = y - *position;
            *position += k0 * innovation;
            *rate += k1 * innovation;
        };
        for p in self.particles.iter_mut() {
            update(&mut p.size.hx, &mut p.size.dhx, gain_x, hx);
            update(&mut p.size.hy, &mut p.size.dhy, gain_y, hy);
            (p.size.hx, p.size.hy) = bounds.halves(p.size.hx, p.size.hy);
        }
    }

    // --- 4. Estimate -------------------------------------------------------------------

    /// Weighted mean of the particles that `keep` accepts.
    fn weighted_mean(&self, keep: impl Fn(&RefParticle) -> bool) -> RefEstimate {
        let mut sums = [0.0; 6];
        let mut total = 0.0;
        for (p, &w) in self.particles.iter().zip(&self.weights) {
            if !keep(p) {
                continue;
            }
            total += w;
            for (s, v) in sums
                .iter_mut()
                .zip([p.x, p.y, p.vx, p.vy, p.size.hx, p.size.hy])
            {
                *s += w * v;
            }
        }
        let [cx, cy, vx, vy, hx, hy] = sums.map(|s| if total > 0.0 { s / total } else { 0.0 });
        RefEstimate {
            ellipse: RefEllipse { cx, cy, hx, hy },
            vx,
            vy,
            confidence: 0.0,
            status: Status::Lost,
        }
    }

    /// The particle of largest weight (the last of equals, as the core).
    fn best_particle(&self) -> RefParticle {
        let mut best = (0.0, RefParticle::default());
        for (p, &w) in self.particles.iter().zip(&self.weights) {
            if w >= best.0 {
                best = (w, *p);
            }
        }
        best.1
    }

    fn read_out<P: PixelFormat>(&mut self, frame: &ImageView<'_, P>) -> RefEstimate {
        let mut estimate = match self.config.readout {
            Readout::Mean => self.weighted_mean(|_| true),
            Readout::Best => {
                let best = self.best_particle();
                RefEstimate {
                    ellipse: best.ellipse(),
                    vx: best.vx,
                    vy: best.vy,
                    confidence: 0.0,
                    status: Status::Lost,
                }
            }
            Readout::RobustMean(radius) => {
                let (best, radius) = (self.best_particle(), radius.to_f64());
                self.weighted_mean(|p| {
                    (p.x - best.x).abs() <= radius && (p.y - best.y).abs() <= radius
                })
            }
        };
        let hist = self.histogram(frame, &estimate.ellipse);
        let score = self.bhattacharyya(&hist);
        let c = &self.config;
        let confidence = calibrated(c, score);
        estimate.confidence = confidence;
        estimate.status = if confidence < c.lost_below.to_f64() {
            Status::Lost
        } else if confidence < c.uncertain_below.to_f64() {
            Status::Uncertain
        } else {
            Status::Tracking
        };
        if estimate.status == Status::Tracking {
            self.last_confident = estimate.ellipse;
            let last = &self.estimate;
            let dx = estimate.ellipse.cx - (last.ellipse.cx + last.vx);
            let dy = estimate.ellipse.cy - (last.ellipse.cy + last.vy);
            let e = &estimate.ellipse;
            let s = self
                .motion_spread
                .unwrap_or_else(|| self.nominal_noise(e.hx, e.hy));
            self.motion_spread = Some(s + ((dx.abs() + dy.abs()) / 2.0 - s) / 8.0);
        } else {
            self.motion_spread = None;
        }
        let c = &self.config;
        let rate = c.adapt_rate.to_f64();
        let empty = hist.iter().all(|&p| p == 0.0);
        if score >= c.adapt_above.to_f64() && rate > 0.0 && !empty {
            for (q, p) in self.model.iter_mut().zip(&hist) {
                *q = (1.0 - rate) * *q + rate * p;
            }
        }
        estimate
    }

    // --- 5. Resample -------------------------------------------------------------------

    /// Whether the effective sample size `1 / sum w^2` is below `resample_below * N`.
    fn is_degenerate(&self) -> bool {
        let n = self.particles.len() as f64;
        let ess = 1.0 / self.weights.iter().map(|w| w * w).sum::<f64>();
        ess < self.config.resample_below.to_f64() * n
    }

    /// Replaces the particles by the drawn ones (the core's slot layout), weights uniform.
    fn apply(&mut self, indices: &[usize]) {
        let n = self.particles.len();
        // The core's in-place copy step, on the reference's particles.
        let drawn: Vec<u16> = indices.iter().map(|&i| i as u16).collect();
        replicate(&mut self.particles, &drawn, &mut vec![0; n]);
        self.weights = vec![1.0 / n as f64; n];
    }

    /// Indices of the resampled particles, drawing as `rbtrack::resample::resample` does.
    fn draw_indices(&mut self) -> Vec<usize> {
        let n = self.particles.len();
        let cumulative: Vec<f64> = self
            .weights
            .iter()
            .scan(0.0, |acc, &w| {
                *acc += w;
                Some(*acc)
            })
            .collect();
        let total = cumulative.last().copied().unwrap_or(0.0);
        // A position in [0, 1) from the 24-bit draw the core uses.
        let position = |rng: &mut Rng| (rng.next_u32() >> 8) as f64 / WEIGHT_TOTAL as f64;
        let pick = |r: f64| cumulative.partition_point(|&c| c <= r * total).min(n - 1);
        match self.config.resampling {
            Scheme::Multinomial => (0..n).map(|_| pick(position(&mut self.rng))).collect(),
            Scheme::Systematic => {
                let u = position(&mut self.rng);
                (0..n).map(|k| pick((k as f64 + u) / n as f64)).collect()
            }
            Scheme::Stratified => (0..n)
                .map(|k| pick((k as f64 + position(&mut self.rng)) / n as f64))
                .collect(),
            Scheme::Residual => {
                let mut integer: Vec<u32> = self
                    .weights
                    .iter()
                    .map(|w| (w * WEIGHT_TOTAL as f64).round() as u32)
                    .collect();
                let mut out = vec![0u16; n];
                match resample(Scheme::Residual, &mut integer, &mut self.rng, &mut out) {
                    Ok(_) => out.iter().map(|&i| i as usize).collect(),
                    Err(_) => (0..n).collect(),
                }
            }
        }
    }
}

fn bounds<P: PixelFormat>(config: &Config, frame: &ImageView<'_, P>) -> Bounds {
    Bounds::for_frame(frame.width(), frame.height(), config.min_half_axis.to_f64())
}

/// The confidence of a window of coefficient `score` by the core's table of the
/// configured variant.
fn calibrated(config: &Config, score: f64) -> f64 {
    config
        .variant
        .calibration()
        .confidence(Q16::from_f64(score))
        .to_f64()
}
