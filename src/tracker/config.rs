//! Tracker configuration: [`Config`], checked once, and what a tracker derives from it.

use super::calibration::{self, Calibration};
use crate::colour::ColourSettings;
use crate::cue::{self, GradientConfig, GradientCue, DEFAULT_SATURATION};
use crate::fixed::Q16;
use crate::kalman::{BlockNoise, KalmanError, SharedCovariance, Sym2};
use crate::likelihood::CostScale;
use crate::resample::Scheme;

/// Which filter runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Variant {
    /// The colour particle filter: every state component sampled, colour cue only.
    ColourPf,
    /// The Rao-Blackwellised particle filter: motion sampled, ellipse size by a Kalman
    /// filter per particle, colour and boundary-gradient cues.
    Rbpf,
}

impl Variant {
    /// The variant's confidence table ([`crate::tracker::calibration`]).
    pub const fn calibration(self) -> &'static Calibration {
        match self {
            Self::ColourPf => &calibration::COLOUR_PF,
            Self::Rbpf => &calibration::RBPF,
        }
    }
}

/// How the colour and gradient likelihoods combine into a particle weight (RBPF).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum CueMix {
    /// `a G_c + (1 - a) G_g`, with `a` the colour share in `[0, 1]`, Q16.16.
    Average(Q16),
    /// `G_c G_g`.
    Product,
}

/// How the estimate is read out of the weighted particles.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Readout {
    /// Weighted mean of all particles.
    Mean,
    /// The particle of largest weight.
    Best,
    /// Weighted mean of the particles within this distance of the best one, px, Q16.16.
    RobustMean(Q16),
}

/// How the RBPF measures the target's size once per frame (the Kalman filter's `Y`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SizeMeasurement {
    /// The scale of highest likelihood (the particles' cues) among five around the
    /// weighted mean; a smaller window often matches the model as well, so sizes drift
    /// down on real video.
    Likelihood,
    /// The scale of highest contrast on the object map: object probability inside the
    /// window against a ring just outside it (the `map` module), with the window scale
    /// calibrated on the first frame.
    Contrast,
}

/// Everything a tracker needs besides its sizes (particles `N`, bins `B`).
///
/// Fields are public; [`Config::new`] fills in defaults that track the built-in scenes and
/// the real sequences. [`Config::validate`] checks every field once, at construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub struct Config {
    /// Filter variant.
    pub variant: Variant,
    /// Seed of the particles' random draws.
    pub seed: u64,
    /// Cap on pixels visited per window, in `16..=65536`; larger windows are subsampled.
    pub pixels_per_window: u32,
    /// Standard deviation of the per-frame position noise, px, Q16.16, in `(0, 256]`.
    pub position_noise: Q16,
    /// Extra position noise per px of mean half-axis, Q16.16 in `[0, 4]`: the standard
    /// deviation is `position_noise + relative_position_noise * (Hx + Hy) / 2`.
    pub relative_position_noise: Q16,
    /// Standard deviation of the per-frame velocity change, px/frame, Q16.16, in `[0, 64]`.
    pub velocity_noise: Q16,
    /// How the motion noise follows the target's recent motion, Q16.16 in `[0, 16]`.
    /// 0 (the default): fixed noise. Otherwise, while tracking, both the position and the
    /// velocity noise are scaled by `clamp(noise_gain * s / sigma, noise_floor, 1)`, where
    /// `s` is the mean recent innovation (how far the estimate lands from the last one
    /// moved by its velocity, px, averaged with weight 1/8) and `sigma` the unscaled
    /// position noise at the estimate. A target that moves smoothly then keeps its
    /// particles on its path, and a look-alike crossing it cannot pull them over; one
    /// that moves abruptly keeps the full noise. Off by default: on hand-held and aerial
    /// footage the narrowed noise loses targets that jerk (docs/accuracy.md, "A look-alike
    /// crossing").
    pub noise_gain: Q16,
    /// Smallest share of the unscaled noise that `noise_gain` may leave, Q16.16 in `(0, 1]`.
    pub noise_floor: Q16,
    /// Share of the velocity kept each frame, Q16.16 in `[0, 1]` (1: constant velocity).
    pub velocity_keep: Q16,
    /// Standard deviation of the relative size change per frame (colour PF) or of the
    /// half-axis rate (RBPF, px/frame), Q16.16, in `[0, 1]` and `[0, 64]`.
    pub scale_noise: Q16,
    /// Colour cue sigma, dimensionless, Q16.16 in `[0.01, 10]`.
    pub colour_sigma: Q16,
    /// Gradient cue sigma, dimensionless, Q16.16 in `[0.01, 10]` (RBPF).
    pub gradient_sigma: Q16,
    /// How the two cues combine (RBPF).
    pub cue_mix: CueMix,
    /// Points on the ellipse boundary where the gradient cue looks (RBPF), in the cue's
    /// range `1..=`[`cue::MAX_POINTS`] ([`GradientConfig::points`]).
    pub gradient_points: u8,
    /// Half-length of the search along the boundary normal, px (RBPF), in the cue's range
    /// `0..=`[`cue::MAX_SEARCH_PX`] ([`GradientConfig::search_px`]).
    pub gradient_search: u8,
    /// Resampling scheme.
    pub resampling: Scheme,
    /// Resample when the effective sample size falls below this share of `N`,
    /// Q16.16 in `(0, 1]` (1: every frame).
    pub resample_below: Q16,
    /// Estimate read-out.
    pub readout: Readout,
    /// Model adaptation rate `a` in `q <- (1 - a) q + a p`, Q16.16 in `[0, 1]` (0: fixed model).
    pub adapt_rate: Q16,
    /// Adapt only when the score (before calibration) is at least this, Q16.16 in `[0, 1]`.
    pub adapt_above: Q16,
    /// How much the particles' spread lowers the score: the score is the
    /// estimate's colour coefficient minus this times the spread (the particles' weighted
    /// mean distance `|dx| + |dy|` from the estimate's centre over its mean half-axis),
    /// Q16.16 in `[0, 4]` (0: the coefficient alone).
    pub spread_penalty: Q16,
    /// Status `Uncertain` below this confidence, Q16.16 in `[0, 1]` (by default the
    /// threshold every tracker shares, [`calibration::UNCERTAIN_BELOW`]).
    pub uncertain_below: Q16,
    /// Status `Lost` below this confidence, Q16.16 in `[0, uncertain_below]` (by default
    /// [`calibration::LOST_BELOW`]).
    pub lost_below: Q16,
    /// Share of particles re-drawn uniformly over the frame each frame while the status is
    /// not `Tracking`,
    /// Q16.16 in `[0, 1]`.
    pub redetect_share: Q16,
    /// Half-height change per px of downward motion (alpha / beta of the RBPF paper),
    /// px/px, Q16.16 in `[-4, 4]`; 0 when the scene geometry is unknown.
    pub scale_per_row: Q16,
    /// Kalman process noise (diagonal of Q), px^2, Q16.16 in `(0, 1024]` (RBPF).
    pub kalman_q: Q16,
    /// Kalman measurement noise (diagonal of R), px^2, Q16.16 in `(0, 1024]` (RBPF).
    pub kalman_r: Q16,
    /// Relative step between the scales tried when measuring the size, Q16.16 in
    /// `[0.01, 0.5]` (RBPF; five scales: 1 - 2s, 1 - s, 1, 1 + s, 1 + 2s).
    pub scale_step: Q16,
    /// Smallest half-axis, px, Q16.16 in `[1, 1024]`.
    pub min_half_axis: Q16,
    /// Weight the colour model by its surroundings (CBWH, the `colour` module): colours
    /// common around the target count less.
    pub background_weighting: bool,
    /// Floor of `o*` in the background weighting, as a share of the ring, Q16.16 in
    /// `[0, 1]`.
    pub background_floor: Q16,
    /// Outer scale of the ring whose colours are the target's surroundings, relative to
    /// the window, Q16.16 in `(1, 4]`.
    pub ring_scale: Q16,
    /// Model the window's upper and lower halves apart (the `colour` module).
    pub split_halves: bool,
    /// Sigma of the contrast cue on the object map in the particle weights, Q16.16 in
    /// `[0.01, 10]`; `None`: not in the weights.
    pub contrast_sigma: Option<Q16>,
    /// Outer scale of the contrast ring around a window's box, Q16.16 in `(1, 2]`.
    pub contrast_ring: Q16,
    /// How the RBPF measures the size.
    pub size_measurement: SizeMeasurement,
    /// Keep every particle's size at the initial one, within the frame's bounds (for
    /// comparing scale mechanisms).
    pub freeze_size: bool,
    /// Prior weight of a re-detected particle against one that followed the motion,
    /// Q16.16 in `(0, 1]`: a re-detection wins only where it matches this many times
    /// better.
    pub redetect_prior: Q16,
    /// Learn `scale_per_row` online while tracking (the `ground` module) and use the
    /// learnt slope once it is trustworthy.
    pub learn_scale_per_row: bool,
}

/// Why a configuration, or the start it was given, was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ConfigError {
    /// The named field is outside its documented range.
    OutOfRange(&'static str),
    /// The gradient cue refused its settings ([`Config::gradient`]: `gradient_points`,
    /// `gradient_search`).
    Gradient(cue::GradientError),
    /// The Kalman filter refused its noise or start covariance (from `kalman_q` and
    /// `kalman_r`).
    Kalman(KalmanError),
    /// The particle count `N` is 0 or above 65535.
    ParticleCount,
    /// The initial ellipse has a half-axis below `min_half_axis`.
    InitialTooSmall,
    /// The initial ellipse's centre lies outside the frame.
    InitialOutside,
    /// A target model learnt under other colour settings, or given to an unstarted
    /// tracker ([`super::Tracker::set_model`]); a correlation-filter tracker relocated
    /// before it started, with no models to keep ([`super::CfTracker::relocate`]).
    ModelSettings,
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::OutOfRange(field) => write!(f, "configuration field `{field}` out of range"),
            Self::Gradient(e) => write!(f, "{e}"),
            Self::Kalman(e) => write!(f, "Kalman filter: {e}"),
            Self::ParticleCount => write!(f, "particle count must be in 1..=65535"),
            Self::InitialTooSmall => write!(f, "initial ellipse below the smallest half-axis"),
            Self::InitialOutside => write!(f, "initial ellipse centred outside the frame"),
            Self::ModelSettings => write!(
                f,
                "target model learnt under other colour settings, or none (not started)"
            ),
        }
    }
}

impl core::error::Error for ConfigError {
    fn source(&self) -> Option<&(dyn core::error::Error + 'static)> {
        match self {
            Self::Gradient(e) => Some(e),
            Self::Kalman(e) => Some(e),
            _ => None,
        }
    }
}

impl From<cue::GradientError> for ConfigError {
    fn from(e: cue::GradientError) -> Self {
        Self::Gradient(e)
    }
}

impl From<KalmanError> for ConfigError {
    fn from(e: KalmanError) -> Self {
        Self::Kalman(e)
    }
}

/// `n / den` rounded to nearest (half away from zero), Q16.16: a decimal constant in a
/// `const` context, equal to `Q16::from_f64` of it (checked in the tests).
pub(super) const fn decimal(n: i64, den: i64) -> Q16 {
    let scaled = n << Q16::FRAC_BITS;
    let half = den / 2;
    let rounded = if scaled >= 0 {
        (scaled + half) / den
    } else {
        (scaled - half) / den
    };
    Q16::from_bits(rounded as i32)
}

/// What a tracker derives once per (re)start from its valid [`Config`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) struct Derived {
    /// `1 / (2 colour_sigma^2)`.
    pub colour_cost: CostScale,
    /// `1 / (2 gradient_sigma^2)`.
    pub gradient_cost: CostScale,
    /// `1 / (2 contrast_sigma^2)`, if the contrast cue is in the weights.
    pub contrast_cost: Option<CostScale>,
    /// The gradient cue, with its angle tables.
    pub cue: GradientCue,
    /// The size covariance every (re)start begins from, both blocks.
    pub initial_cov: Sym2,
}

impl Derived {
    /// Before [`Config::derive`]: every bit zero.
    pub const UNSET: Self = Self {
        colour_cost: CostScale::ZERO,
        gradient_cost: CostScale::ZERO,
        contrast_cost: None,
        cue: GradientCue::UNSET,
        initial_cov: Sym2::ZERO,
    };
}

/// `Ok` if `ok`, else the error naming `field`.
fn check(ok: bool, field: &'static str) -> Result<(), ConfigError> {
    ok.then_some(()).ok_or(ConfigError::OutOfRange(field))
}

/// Whether `v` lies in `[0, 1]`.
fn unit(v: Q16) -> bool {
    (Q16::ZERO..=Q16::ONE).contains(&v)
}

/// Whether `v` lies in `[0, max]`.
fn up_to(v: Q16, max: i32) -> bool {
    (Q16::ZERO..=Q16::from_int(max)).contains(&v)
}

/// Whether `v` lies in `(0, max]`.
fn positive_up_to(v: Q16, max: Q16) -> bool {
    v > Q16::ZERO && v <= max
}

/// Whether `v` lies in `(1, max]`.
fn above_one_up_to(v: Q16, max: i32) -> bool {
    v > Q16::ONE && v <= Q16::from_int(max)
}

/// The cost scale of the cue sigma in `field`, or the error naming it.
fn cost_scale(sigma: Q16, field: &'static str) -> Result<CostScale, ConfigError> {
    CostScale::from_sigma_q16(sigma).ok_or(ConfigError::OutOfRange(field))
}

impl Config {
    /// Every field zero: the configuration of an unstarted tracker, never validated or
    /// used (`Tracker::start` replaces it).
    pub(crate) const UNSET: Self = Self {
        variant: Variant::ColourPf,
        seed: 0,
        pixels_per_window: 0,
        position_noise: Q16::ZERO,
        relative_position_noise: Q16::ZERO,
        velocity_noise: Q16::ZERO,
        velocity_keep: Q16::ZERO,
        noise_gain: Q16::ZERO,
        noise_floor: Q16::ZERO,
        scale_noise: Q16::ZERO,
        colour_sigma: Q16::ZERO,
        gradient_sigma: Q16::ZERO,
        cue_mix: CueMix::Average(Q16::ZERO),
        gradient_points: 0,
        gradient_search: 0,
        resampling: Scheme::Multinomial,
        resample_below: Q16::ZERO,
        readout: Readout::Mean,
        adapt_rate: Q16::ZERO,
        adapt_above: Q16::ZERO,
        spread_penalty: Q16::ZERO,
        uncertain_below: Q16::ZERO,
        lost_below: Q16::ZERO,
        redetect_share: Q16::ZERO,
        scale_per_row: Q16::ZERO,
        kalman_q: Q16::ZERO,
        kalman_r: Q16::ZERO,
        scale_step: Q16::ZERO,
        min_half_axis: Q16::ZERO,
        background_weighting: false,
        background_floor: Q16::ZERO,
        ring_scale: Q16::ZERO,
        split_halves: false,
        contrast_sigma: None,
        contrast_ring: Q16::ZERO,
        size_measurement: SizeMeasurement::Likelihood,
        freeze_size: false,
        redetect_prior: Q16::ZERO,
        learn_scale_per_row: false,
    };

    /// The defaults for `variant`, chosen on the real sequences (docs/accuracy.md):
    /// - appearance: 8x8x8 colour histograms of the window's upper and lower halves,
    ///   weighted by the ring around the target (twice its size), fixed after the first
    ///   frame (`adapt_rate` 0: an adapting model drifts onto what hides the target);
    ///   colour sigma 0.1, gradient sigma 0.3 (RBPF, product of the cues);
    /// - motion: a random walk of 2 px plus 0.4 px per px of mean half-axis a frame (no
    ///   velocity: camera jerks and bouncing targets break constant velocity);
    /// - size: the RBPF measures it by contrast on the object map and filters it with
    ///   Kalman `Q = 0.01 I`, `R = 16 I` (a slow, steady size); the colour PF samples it
    ///   (1 % a frame) and weighs the contrast cue (sigma 0.2); the ground-plane slope is
    ///   not learnt (on the real sequences the learnt slope did not raise the accuracy:
    ///   docs/accuracy.md);
    /// - status: the score is the colour coefficient less 0.3 times the particles'
    ///   spread, the confidence that score through the variant's table; `Uncertain` below
    ///   0.5 and `Lost` below 0.1, as every tracker;
    /// - search: while not `Tracking`, a quarter of the particles are re-drawn over the
    ///   frame with prior weight 1/200;
    /// - 300 pixels per window, 24 gradient points searched 2 px each side, systematic
    ///   resampling below half the particles.
    pub const fn new(variant: Variant) -> Self {
        let rbpf = matches!(variant, Variant::Rbpf);
        Self {
            variant,
            seed: 1,
            pixels_per_window: 300,
            position_noise: Q16::from_int(2),
            relative_position_noise: decimal(4, 10),
            velocity_noise: Q16::ZERO,
            velocity_keep: Q16::ZERO,
            noise_gain: Q16::ZERO,
            noise_floor: decimal(25, 100),
            scale_noise: if rbpf { Q16::ZERO } else { decimal(1, 100) },
            colour_sigma: decimal(1, 10),
            gradient_sigma: decimal(3, 10),
            cue_mix: CueMix::Product,
            gradient_points: 24,
            gradient_search: 2,
            resampling: Scheme::Systematic,
            resample_below: Q16::HALF,
            readout: Readout::Mean,
            adapt_rate: Q16::ZERO,
            adapt_above: decimal(85, 100),
            spread_penalty: decimal(3, 10),
            uncertain_below: calibration::UNCERTAIN_BELOW,
            lost_below: calibration::LOST_BELOW,
            redetect_share: decimal(25, 100),
            scale_per_row: Q16::ZERO,
            kalman_q: decimal(1, 100),
            kalman_r: Q16::from_int(16),
            scale_step: decimal(5, 100),
            min_half_axis: Q16::from_int(2),
            background_weighting: true,
            background_floor: decimal(1, 100),
            ring_scale: Q16::from_int(2),
            split_halves: true,
            contrast_sigma: if rbpf { None } else { Some(decimal(2, 10)) },
            contrast_ring: decimal(11, 10),
            size_measurement: SizeMeasurement::Contrast,
            freeze_size: false,
            redetect_prior: decimal(5, 1000),
            learn_scale_per_row: false,
        }
    }

    /// The source papers' trackers, as the seeds describe them: the target-only colour
    /// model (whole window, kernel-weighted 8x8x8 histogram, Bhattacharyya coefficient,
    /// colour sigma 0.2) adapting at 5 % above a coefficient of 0.85, constant velocity
    /// (noise 1 px/frame, 0.95 kept), weighted-mean read-out; the colour PF samples the
    /// size (3 % a frame); the RBPF adds the boundary-gradient cue (sigma 0.3), averages
    /// the two likelihoods with `a = 0.5` (its eq. 10d), filters the size with the paper's
    /// Kalman `Q = 4 I`, `R = 2 I`, measured by likelihood, and takes `scale_per_row` as
    /// given. Re-detection as before the object map: half the particles, no prior. The
    /// score is the coefficient alone, `Lost` below a score of 0.6.
    pub const fn paper(variant: Variant) -> Self {
        let rbpf = matches!(variant, Variant::Rbpf);
        Self {
            relative_position_noise: decimal(2, 10),
            velocity_noise: Q16::ONE,
            velocity_keep: decimal(95, 100),
            scale_noise: if rbpf {
                decimal(3, 10)
            } else {
                decimal(3, 100)
            },
            colour_sigma: decimal(2, 10),
            cue_mix: CueMix::Average(Q16::HALF),
            adapt_rate: decimal(5, 100),
            spread_penalty: Q16::ZERO,
            lost_below: variant.calibration().confidence(decimal(6, 10)),
            redetect_share: Q16::HALF,
            kalman_q: Q16::from_int(4),
            kalman_r: Q16::from_int(2),
            background_weighting: false,
            split_halves: false,
            contrast_sigma: None,
            size_measurement: SizeMeasurement::Likelihood,
            redetect_prior: Q16::ONE,
            ..Self::new(variant)
        }
    }

    /// Checks every field; the error names the first one out of range, or wraps the
    /// gradient cue's or the Kalman filter's refusal of the settings they take.
    pub fn validate(&self) -> Result<(), ConfigError> {
        self.derive().map(drop)
    }

    /// The gradient cue's settings: `gradient_points` boundary points searched
    /// `gradient_search` px each side, saturating at [`DEFAULT_SATURATION`].
    pub const fn gradient(&self) -> GradientConfig {
        let mut gradient = GradientConfig::new();
        gradient.points = self.gradient_points as usize;
        gradient.search_px = self.gradient_search as u32;
        gradient.saturation = DEFAULT_SATURATION;
        gradient
    }

    /// The colour model's settings.
    pub(crate) const fn colour(&self) -> ColourSettings {
        ColourSettings {
            split_halves: self.split_halves,
            background: if self.background_weighting {
                Some(self.background_floor)
            } else {
                None
            },
            ring_scale: self.ring_scale,
            cap: self.pixels_per_window,
        }
    }

    /// The Kalman filter's noise: `Q = kalman_q I`, `R = kalman_r I`.
    pub(crate) const fn size_noise(&self) -> BlockNoise {
        let (q, r) = (self.kalman_q, self.kalman_r);
        BlockNoise::diagonal([q; 4], [r; 2])
    }

    /// The size covariance of a (re)start, `diag(kalman_r, kalman_q)` in each block: the
    /// half-axis as uncertain as one measurement, the rate as one step's noise.
    pub(crate) const fn initial_size_cov(&self) -> Sym2 {
        Sym2::diagonal(self.kalman_r, self.kalman_q)
    }

    /// Checks every field in declaration order (one line each) and derives what the
    /// tracker needs from them.
    pub(crate) fn derive(&self) -> Result<Derived, ConfigError> {
        let rbpf = self.variant == Variant::Rbpf;
        check(
            (16..=65536).contains(&self.pixels_per_window),
            "pixels_per_window",
        )?;
        check(
            positive_up_to(self.position_noise, Q16::from_int(256)),
            "position_noise",
        )?;
        check(
            up_to(self.relative_position_noise, 4),
            "relative_position_noise",
        )?;
        check(up_to(self.velocity_noise, 64), "velocity_noise")?;
        check(unit(self.velocity_keep), "velocity_keep")?;
        check(up_to(self.noise_gain, 16), "noise_gain")?;
        check(positive_up_to(self.noise_floor, Q16::ONE), "noise_floor")?;
        check(
            up_to(self.scale_noise, if rbpf { 64 } else { 1 }),
            "scale_noise",
        )?;
        let colour_cost = cost_scale(self.colour_sigma, "colour_sigma")?;
        let gradient_cost = cost_scale(self.gradient_sigma, "gradient_sigma")?;
        check(
            !matches!(self.cue_mix, CueMix::Average(a) if !unit(a)),
            "cue_mix",
        )?;
        let cue = GradientCue::new(&self.gradient())?;
        check(
            positive_up_to(self.resample_below, Q16::ONE),
            "resample_below",
        )?;
        check(
            !matches!(self.readout, Readout::RobustMean(r) if r <= Q16::ZERO),
            "readout",
        )?;
        check(unit(self.adapt_rate), "adapt_rate")?;
        check(unit(self.adapt_above), "adapt_above")?;
        check(
            self.spread_penalty >= Q16::ZERO && self.spread_penalty <= Q16::from_int(4),
            "spread_penalty",
        )?;
        check(unit(self.uncertain_below), "uncertain_below")?;
        check(
            self.lost_below >= Q16::ZERO && self.lost_below <= self.uncertain_below,
            "lost_below",
        )?;
        check(unit(self.redetect_share), "redetect_share")?;
        check(
            self.scale_per_row.abs() <= Q16::from_int(4),
            "scale_per_row",
        )?;
        check(
            positive_up_to(self.kalman_q, Q16::from_int(1024)),
            "kalman_q",
        )?;
        check(
            positive_up_to(self.kalman_r, Q16::from_int(1024)),
            "kalman_r",
        )?;
        let initial_cov = self.initial_size_cov();
        SharedCovariance::new(initial_cov, initial_cov, self.size_noise())?;
        check(
            (decimal(1, 100)..=Q16::HALF).contains(&self.scale_step),
            "scale_step",
        )?;
        check(
            (Q16::ONE..=Q16::from_int(1024)).contains(&self.min_half_axis),
            "min_half_axis",
        )?;
        check(unit(self.background_floor), "background_floor")?;
        check(above_one_up_to(self.ring_scale, 4), "ring_scale")?;
        let contrast = self.contrast_sigma.map(|s| cost_scale(s, "contrast_sigma"));
        let contrast_cost = contrast.transpose()?;
        check(above_one_up_to(self.contrast_ring, 2), "contrast_ring")?;
        check(
            positive_up_to(self.redetect_prior, Q16::ONE),
            "redetect_prior",
        )?;
        Ok(Derived {
            colour_cost,
            gradient_cost,
            contrast_cost,
            cue,
            initial_cov,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decimal_constants_equal_their_float_conversion() {
        for den in [10, 100, 1000] {
            for n in -5000..=5000 {
                assert_eq!(
                    decimal(n, den),
                    Q16::from_f64(n as f64 / den as f64),
                    "{n}/{den}"
                );
            }
        }
    }

    #[test]
    fn configurations_are_const() {
        const DEFAULT: Config = Config::new(Variant::Rbpf);
        const PAPER: Config = Config::paper(Variant::ColourPf);
        assert_eq!(DEFAULT.colour_sigma, Q16::from_f64(0.1));
        assert_eq!(PAPER.colour_sigma, Q16::from_f64(0.2));
    }

    #[test]
    fn defaults_are_valid() {
        assert_eq!(Config::new(Variant::ColourPf).validate(), Ok(()));
        assert_eq!(Config::new(Variant::Rbpf).validate(), Ok(()));
    }

    #[test]
    fn each_error_names_its_field_or_wraps_the_inner_one() {
        let base = Config::new(Variant::Rbpf);
        let cases: [(Config, ConfigError); 10] = [
            (
                Config {
                    pixels_per_window: 3,
                    ..base
                },
                ConfigError::OutOfRange("pixels_per_window"),
            ),
            (
                Config {
                    position_noise: Q16::ZERO,
                    ..base
                },
                ConfigError::OutOfRange("position_noise"),
            ),
            (
                Config {
                    colour_sigma: Q16::ZERO,
                    ..base
                },
                ConfigError::OutOfRange("colour_sigma"),
            ),
            (
                Config {
                    gradient_points: 200,
                    ..base
                },
                ConfigError::Gradient(cue::GradientError::OutOfRange("points")),
            ),
            (
                Config {
                    resample_below: Q16::ZERO,
                    ..base
                },
                ConfigError::OutOfRange("resample_below"),
            ),
            (
                Config {
                    lost_below: Q16::from_f64(0.9),
                    ..base
                },
                ConfigError::OutOfRange("lost_below"),
            ),
            (
                Config {
                    kalman_r: Q16::MIN,
                    ..base
                },
                ConfigError::OutOfRange("kalman_r"),
            ),
            (
                Config {
                    cue_mix: CueMix::Average(Q16::from_int(2)),
                    ..base
                },
                ConfigError::OutOfRange("cue_mix"),
            ),
            (
                Config {
                    noise_gain: Q16::from_int(17),
                    ..base
                },
                ConfigError::OutOfRange("noise_gain"),
            ),
            (
                Config {
                    noise_floor: Q16::ZERO,
                    ..base
                },
                ConfigError::OutOfRange("noise_floor"),
            ),
        ];
        for (config, error) in cases {
            assert_eq!(config.validate(), Err(error));
        }
    }
}
