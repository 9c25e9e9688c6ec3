//! Tracker configuration, checked once by [`Config::validate`].

use crate::fixed::Q16;
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
    /// footage the narrowed noise loses targets that jerk (README, "Motion-adaptive noise").
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
    /// Points on the ellipse boundary where the gradient cue looks, `4..=64` (RBPF).
    pub gradient_points: u8,
    /// Half-length of the search along the boundary normal, px, `1..=16` (RBPF).
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
    /// Adapt only when the confidence is at least this, Q16.16 in `[0, 1]`.
    pub adapt_above: Q16,
    /// Status `Uncertain` below this confidence, Q16.16 in `[0, 1]`.
    pub uncertain_below: Q16,
    /// Status `Lost` below this confidence, Q16.16 in `[0, uncertain_below]`.
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
}

/// A configuration field out of its documented range; names the field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ConfigError {
    /// The named field is outside its documented range.
    OutOfRange(&'static str),
    /// The particle count `N` is 0 or above 65535.
    ParticleCount,
    /// The initial ellipse has a half-axis below `min_half_axis` or its centre outside
    /// the frame.
    InitialEllipse,
}

impl core::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::OutOfRange(field) => write!(f, "configuration field `{field}` out of range"),
            Self::ParticleCount => write!(f, "particle count must be in 1..=65535"),
            Self::InitialEllipse => {
                write!(f, "initial ellipse too small or centred outside the frame")
            }
        }
    }
}

impl core::error::Error for ConfigError {}

/// Quantities derived from a valid [`Config`] once, at construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Derived {
    pub colour: CostScale,
    pub gradient: CostScale,
}

impl Config {
    /// Defaults for `variant`: constant velocity with position noise 2 px plus 0.2 px per px
    /// of half-axis and velocity noise 1 px/frame; 300 pixels per window; colour sigma 0.2,
    /// gradient sigma 0.3, gradient cue on 24 boundary points searched 2 px each side of
    /// the boundary (5 gradients per point: as accurate as 3 px on the built-in scenes
    /// and the real sequences, for 29 % fewer gradients); Kalman `Q = 0.25 I`, `R = 4 I`
    /// (smoother sizes than the RBPF paper's `4 I` and `2 I`, which follow every noisy
    /// scale measurement); systematic resampling below half the particles.
    pub fn new(variant: Variant) -> Self {
        Self {
            variant,
            seed: 1,
            pixels_per_window: 300,
            position_noise: Q16::from_int(2),
            relative_position_noise: Q16::from_f64(0.2),
            velocity_noise: Q16::ONE,
            velocity_keep: Q16::from_f64(0.95),
            noise_gain: Q16::ZERO,
            noise_floor: Q16::from_f64(0.25),
            scale_noise: match variant {
                Variant::ColourPf => Q16::from_f64(0.03),
                Variant::Rbpf => Q16::from_f64(0.3),
            },
            colour_sigma: Q16::from_f64(0.2),
            gradient_sigma: Q16::from_f64(0.3),
            cue_mix: CueMix::Product,
            gradient_points: 24,
            gradient_search: 2,
            resampling: Scheme::Systematic,
            resample_below: Q16::HALF,
            readout: Readout::Mean,
            adapt_rate: Q16::from_f64(0.05),
            adapt_above: Q16::from_f64(0.85),
            uncertain_below: Q16::from_f64(0.75),
            lost_below: Q16::from_f64(0.6),
            redetect_share: Q16::HALF,
            scale_per_row: Q16::ZERO,
            kalman_q: Q16::from_f64(0.25),
            kalman_r: Q16::from_int(4),
            scale_step: Q16::from_f64(0.05),
            min_half_axis: Q16::from_int(2),
        }
    }

    /// Checks every field; the error names the first one out of range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let unit = Q16::ZERO..=Q16::ONE;
        let checks: [(bool, &'static str); 25] = [
            (
                (16..=65536).contains(&self.pixels_per_window),
                "pixels_per_window",
            ),
            (
                self.position_noise > Q16::ZERO && self.position_noise <= Q16::from_int(256),
                "position_noise",
            ),
            (
                (Q16::ZERO..=Q16::from_int(4)).contains(&self.relative_position_noise),
                "relative_position_noise",
            ),
            (
                (Q16::ZERO..=Q16::from_int(64)).contains(&self.velocity_noise),
                "velocity_noise",
            ),
            (unit.contains(&self.velocity_keep), "velocity_keep"),
            (
                (Q16::ZERO..=Q16::from_int(16)).contains(&self.noise_gain),
                "noise_gain",
            ),
            (
                self.noise_floor > Q16::ZERO && self.noise_floor <= Q16::ONE,
                "noise_floor",
            ),
            (
                match self.variant {
                    Variant::ColourPf => unit.contains(&self.scale_noise),
                    Variant::Rbpf => (Q16::ZERO..=Q16::from_int(64)).contains(&self.scale_noise),
                },
                "scale_noise",
            ),
            (
                CostScale::from_sigma_q16(self.colour_sigma).is_some(),
                "colour_sigma",
            ),
            (
                CostScale::from_sigma_q16(self.gradient_sigma).is_some(),
                "gradient_sigma",
            ),
            (
                match self.cue_mix {
                    CueMix::Average(a) => unit.contains(&a),
                    CueMix::Product => true,
                },
                "cue_mix",
            ),
            ((4..=64).contains(&self.gradient_points), "gradient_points"),
            ((1..=16).contains(&self.gradient_search), "gradient_search"),
            (
                self.resample_below > Q16::ZERO && self.resample_below <= Q16::ONE,
                "resample_below",
            ),
            (
                match self.readout {
                    Readout::RobustMean(r) => r > Q16::ZERO,
                    Readout::Mean | Readout::Best => true,
                },
                "readout",
            ),
            (unit.contains(&self.adapt_rate), "adapt_rate"),
            (unit.contains(&self.adapt_above), "adapt_above"),
            (unit.contains(&self.uncertain_below), "uncertain_below"),
            (
                self.lost_below >= Q16::ZERO && self.lost_below <= self.uncertain_below,
                "lost_below",
            ),
            (unit.contains(&self.redetect_share), "redetect_share"),
            (
                (Q16::from_int(-4)..=Q16::from_int(4)).contains(&self.scale_per_row),
                "scale_per_row",
            ),
            (
                self.kalman_q > Q16::ZERO && self.kalman_q <= Q16::from_int(1024),
                "kalman_q",
            ),
            (
                self.kalman_r > Q16::ZERO && self.kalman_r <= Q16::from_int(1024),
                "kalman_r",
            ),
            (
                (Q16::from_f64(0.01)..=Q16::HALF).contains(&self.scale_step),
                "scale_step",
            ),
            (
                (Q16::ONE..=Q16::from_int(1024)).contains(&self.min_half_axis),
                "min_half_axis",
            ),
        ];
        match checks.iter().find(|(ok, _)| !ok) {
            Some((_, field)) => Err(ConfigError::OutOfRange(field)),
            None => Ok(()),
        }
    }

    /// Validates and derives the cost scales.
    pub(crate) fn derive(&self) -> Result<Derived, ConfigError> {
        self.validate()?;
        let colour = CostScale::from_sigma_q16(self.colour_sigma)
            .ok_or(ConfigError::OutOfRange("colour_sigma"))?;
        let gradient = CostScale::from_sigma_q16(self.gradient_sigma)
            .ok_or(ConfigError::OutOfRange("gradient_sigma"))?;
        Ok(Derived { colour, gradient })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        assert_eq!(Config::new(Variant::ColourPf).validate(), Ok(()));
        assert_eq!(Config::new(Variant::Rbpf).validate(), Ok(()));
    }

    #[test]
    fn each_error_names_its_field() {
        let base = Config::new(Variant::Rbpf);
        let cases: [(Config, &str); 10] = [
            (
                Config {
                    pixels_per_window: 3,
                    ..base
                },
                "pixels_per_window",
            ),
            (
                Config {
                    position_noise: Q16::ZERO,
                    ..base
                },
                "position_noise",
            ),
            (
                Config {
                    colour_sigma: Q16::ZERO,
                    ..base
                },
                "colour_sigma",
            ),
            (
                Config {
                    gradient_points: 200,
                    ..base
                },
                "gradient_points",
            ),
            (
                Config {
                    resample_below: Q16::ZERO,
                    ..base
                },
                "resample_below",
            ),
            (
                Config {
                    lost_below: Q16::from_f64(0.9),
                    ..base
                },
                "lost_below",
            ),
            (
                Config {
                    kalman_r: Q16::MIN,
                    ..base
                },
                "kalman_r",
            ),
            (
                Config {
                    cue_mix: CueMix::Average(Q16::from_int(2)),
                    ..base
                },
                "cue_mix",
            ),
            (
                Config {
                    noise_gain: Q16::from_int(17),
                    ..base
                },
                "noise_gain",
            ),
            (
                Config {
                    noise_floor: Q16::ZERO,
                    ..base
                },
                "noise_floor",
            ),
        ];
        for (config, field) in cases {
            assert_eq!(config.validate(), Err(ConfigError::OutOfRange(field)));
        }
    }
}
