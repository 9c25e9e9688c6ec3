//! The trackers' configurations: their defaults and their checks.

use super::rbt_error::{self, *};
use super::{put, rbt_q16};
use core::ffi::c_char;
use core::fmt::Write;
use rbtrack::cf::scale::ScaleSettings;
use rbtrack::tracker::{
    CfConfig, Config, ConfigError, CueMix, Readout, Scheme, SizeMeasurement, Variant,
};
use rbtrack::Q16;

/// Which filter runs (`rbt_config.variant`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum rbt_variant {
    /// The colour particle filter.
    RBT_VARIANT_COLOUR_PF = 0,
    /// The Rao-Blackwellised particle filter.
    RBT_VARIANT_RBPF = 1,
}

/// How the colour and gradient likelihoods combine (`rbt_config.cue_mix`, RBPF).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum rbt_cue_mix {
    /// `a G_c + (1 - a) G_g`, `a` = `rbt_config.cue_mix_colour_share`.
    RBT_CUE_MIX_AVERAGE = 0,
    /// `G_c G_g`.
    RBT_CUE_MIX_PRODUCT = 1,
}

/// Resampling scheme (`rbt_config.resampling`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum rbt_resampling {
    /// Independent draws.
    RBT_RESAMPLING_MULTINOMIAL = 0,
    /// One offset, evenly spaced positions.
    RBT_RESAMPLING_SYSTEMATIC = 1,
    /// One position in each of N strata.
    RBT_RESAMPLING_STRATIFIED = 2,
    /// Deterministic copies, the rest multinomial.
    RBT_RESAMPLING_RESIDUAL = 3,
}

/// How the estimate is read out (`rbt_config.readout`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum rbt_readout {
    /// Weighted mean of all particles.
    RBT_READOUT_MEAN = 0,
    /// The particle of largest weight.
    RBT_READOUT_BEST = 1,
    /// Weighted mean of those within `rbt_config.readout_radius` of the best one.
    RBT_READOUT_ROBUST_MEAN = 2,
}

/// How the RBPF measures the size (`rbt_config.size_measurement`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum rbt_size_measurement {
    /// The scale of highest likelihood.
    RBT_SIZE_LIKELIHOOD = 0,
    /// The scale of highest contrast on the object map.
    RBT_SIZE_CONTRAST = 1,
}

/// A tracker's configuration: the core's `rbtrack::tracker::Config`, field for field
/// (its documentation gives each range). `rbt_config_default` fills in the defaults;
/// enums are `uint32_t` of the named enum, flags 0 or not 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct rbt_config {
    /// An `rbt_variant`.
    pub variant: u32,
    /// Seed of the particles' random draws.
    pub seed: u64,
    /// Cap on pixels visited per window, 16..=65536.
    pub pixels_per_window: u32,
    /// Per-frame position noise, px, Q16.16.
    pub position_noise: rbt_q16,
    /// Extra position noise per px of mean half-axis, Q16.16.
    pub relative_position_noise: rbt_q16,
    /// Per-frame velocity noise, px/frame, Q16.16.
    pub velocity_noise: rbt_q16,
    /// How the motion noise follows the target's recent motion, Q16.16 (0: fixed).
    pub noise_gain: rbt_q16,
    /// Smallest share of the noise `noise_gain` may leave, Q16.16.
    pub noise_floor: rbt_q16,
    /// Share of the velocity kept each frame, Q16.16.
    pub velocity_keep: rbt_q16,
    /// Size noise (relative per frame, colour PF; half-axis rate, px/frame, RBPF), Q16.16.
    pub scale_noise: rbt_q16,
    /// Colour cue sigma, Q16.16.
    pub colour_sigma: rbt_q16,
    /// Gradient cue sigma, Q16.16 (RBPF).
    pub gradient_sigma: rbt_q16,
    /// An `rbt_cue_mix` (RBPF).
    pub cue_mix: u32,
    /// The colour share `a` of `RBT_CUE_MIX_AVERAGE`, Q16.16 in [0, 1].
    pub cue_mix_colour_share: rbt_q16,
    /// Boundary points of the gradient cue (RBPF).
    pub gradient_points: u8,
    /// Half-length of the gradient search, px (RBPF).
    pub gradient_search: u8,
    /// An `rbt_resampling`.
    pub resampling: u32,
    /// Resample below this share of N effective particles, Q16.16.
    pub resample_below: rbt_q16,
    /// An `rbt_readout`.
    pub readout: u32,
    /// The radius of `RBT_READOUT_ROBUST_MEAN`, px, Q16.16.
    pub readout_radius: rbt_q16,
    /// Model adaptation rate, Q16.16 (0: fixed model).
    pub adapt_rate: rbt_q16,
    /// Adapt only at this confidence or above, Q16.16.
    pub adapt_above: rbt_q16,
    /// How much the particles' spread lowers the confidence, Q16.16.
    pub spread_penalty: rbt_q16,
    /// Status uncertain below this confidence, Q16.16.
    pub uncertain_below: rbt_q16,
    /// Status lost below this confidence, Q16.16.
    pub lost_below: rbt_q16,
    /// Share of particles re-drawn over the frame while not tracking, Q16.16.
    pub redetect_share: rbt_q16,
    /// Half-height change per px of downward motion, px/px, Q16.16.
    pub scale_per_row: rbt_q16,
    /// Kalman process noise, px^2, Q16.16 (RBPF).
    pub kalman_q: rbt_q16,
    /// Kalman measurement noise, px^2, Q16.16 (RBPF).
    pub kalman_r: rbt_q16,
    /// Relative step between the scales tried, Q16.16 (RBPF).
    pub scale_step: rbt_q16,
    /// Smallest half-axis, px, Q16.16.
    pub min_half_axis: rbt_q16,
    /// Weight the colour model by its surroundings (flag).
    pub background_weighting: u8,
    /// Floor of the background weighting, Q16.16.
    pub background_floor: rbt_q16,
    /// Outer scale of the surroundings' ring, Q16.16.
    pub ring_scale: rbt_q16,
    /// Model the window's halves apart (flag).
    pub split_halves: u8,
    /// Sigma of the contrast cue in the weights, Q16.16; 0: not in the weights.
    pub contrast_sigma: rbt_q16,
    /// Outer scale of the contrast ring, Q16.16.
    pub contrast_ring: rbt_q16,
    /// An `rbt_size_measurement` (RBPF).
    pub size_measurement: u32,
    /// Keep every particle's size at the initial one (flag).
    pub freeze_size: u8,
    /// Prior weight of a re-detected particle, Q16.16.
    pub redetect_prior: rbt_q16,
    /// Learn `scale_per_row` online (flag).
    pub learn_scale_per_row: u8,
}

/// Calls `$apply!(field, ...)` with every Q16.16 field `rbt_config` and `Config` share.
macro_rules! q16_fields {
    ($apply:ident) => {
        $apply!(
            position_noise,
            relative_position_noise,
            velocity_noise,
            noise_gain,
            noise_floor,
            velocity_keep,
            scale_noise,
            colour_sigma,
            gradient_sigma,
            resample_below,
            adapt_rate,
            adapt_above,
            spread_penalty,
            uncertain_below,
            lost_below,
            redetect_share,
            scale_per_row,
            kalman_q,
            kalman_r,
            scale_step,
            min_half_axis,
            background_floor,
            ring_scale,
            contrast_ring,
            redetect_prior
        )
    };
}

/// Why an `rbt_config` is not a valid `Config`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum BadConfig {
    /// The named enum field holds an unknown value.
    Enum(&'static str),
    /// The core refused it.
    Core(ConfigError),
}

impl From<BadConfig> for rbt_error {
    fn from(e: BadConfig) -> Self {
        match e {
            BadConfig::Enum(_) => RBT_ERR_CONFIG_ENUM,
            BadConfig::Core(e) => e.into(),
        }
    }
}

impl core::fmt::Display for BadConfig {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Enum(field) => write!(f, "configuration field `{field}` holds an unknown value"),
            Self::Core(e) => write!(f, "{e}"),
        }
    }
}

impl From<&Config> for rbt_config {
    fn from(c: &Config) -> Self {
        let mut out = Self {
            variant: match c.variant {
                Variant::ColourPf => rbt_variant::RBT_VARIANT_COLOUR_PF,
                Variant::Rbpf => rbt_variant::RBT_VARIANT_RBPF,
            } as u32,
            seed: c.seed,
            pixels_per_window: c.pixels_per_window,
            gradient_points: c.gradient_points,
            gradient_search: c.gradient_search,
            resampling: match c.resampling {
                Scheme::Multinomial => rbt_resampling::RBT_RESAMPLING_MULTINOMIAL,
                Scheme::Systematic => rbt_resampling::RBT_RESAMPLING_SYSTEMATIC,
                Scheme::Stratified => rbt_resampling::RBT_RESAMPLING_STRATIFIED,
                Scheme::Residual => rbt_resampling::RBT_RESAMPLING_RESIDUAL,
            } as u32,
            background_weighting: c.background_weighting.into(),
            split_halves: c.split_halves.into(),
            contrast_sigma: c.contrast_sigma.map_or(0, Q16::to_bits),
            size_measurement: match c.size_measurement {
                SizeMeasurement::Likelihood => rbt_size_measurement::RBT_SIZE_LIKELIHOOD,
                SizeMeasurement::Contrast => rbt_size_measurement::RBT_SIZE_CONTRAST,
            } as u32,
            freeze_size: c.freeze_size.into(),
            learn_scale_per_row: c.learn_scale_per_row.into(),
            ..Self::default()
        };
        (out.cue_mix, out.cue_mix_colour_share) = match c.cue_mix {
            CueMix::Average(a) => (rbt_cue_mix::RBT_CUE_MIX_AVERAGE as u32, a.to_bits()),
            CueMix::Product => (rbt_cue_mix::RBT_CUE_MIX_PRODUCT as u32, 0),
        };
        (out.readout, out.readout_radius) = match c.readout {
            Readout::Mean => (rbt_readout::RBT_READOUT_MEAN as u32, 0),
            Readout::Best => (rbt_readout::RBT_READOUT_BEST as u32, 0),
            Readout::RobustMean(r) => (rbt_readout::RBT_READOUT_ROBUST_MEAN as u32, r.to_bits()),
        };
        macro_rules! copy {
            ($($field:ident),*) => { $(out.$field = c.$field.to_bits();)* };
        }
        q16_fields!(copy);
        out
    }
}

impl rbt_config {
    /// The core's configuration of these fields, checked.
    fn config(&self) -> Result<Config, BadConfig> {
        let variant = match self.variant {
            0 => Variant::ColourPf,
            1 => Variant::Rbpf,
            _ => return Err(BadConfig::Enum("variant")),
        };
        let q = Q16::from_bits;
        let mut c = Config::new(variant);
        c.seed = self.seed;
        c.pixels_per_window = self.pixels_per_window;
        c.cue_mix = match self.cue_mix {
            0 => CueMix::Average(q(self.cue_mix_colour_share)),
            1 => CueMix::Product,
            _ => return Err(BadConfig::Enum("cue_mix")),
        };
        c.gradient_points = self.gradient_points;
        c.gradient_search = self.gradient_search;
        c.resampling = match self.resampling {
            0 => Scheme::Multinomial,
            1 => Scheme::Systematic,
            2 => Scheme::Stratified,
            3 => Scheme::Residual,
            _ => return Err(BadConfig::Enum("resampling")),
        };
        c.readout = match self.readout {
            0 => Readout::Mean,
            1 => Readout::Best,
            2 => Readout::RobustMean(q(self.readout_radius)),
            _ => return Err(BadConfig::Enum("readout")),
        };
        c.background_weighting = self.background_weighting != 0;
        c.split_halves = self.split_halves != 0;
        c.contrast_sigma = (self.contrast_sigma != 0).then(|| q(self.contrast_sigma));
        c.size_measurement = match self.size_measurement {
            0 => SizeMeasurement::Likelihood,
            1 => SizeMeasurement::Contrast,
            _ => return Err(BadConfig::Enum("size_measurement")),
        };
        c.freeze_size = self.freeze_size != 0;
        c.learn_scale_per_row = self.learn_scale_per_row != 0;
        macro_rules! copy {
            ($($field:ident),*) => { $(c.$field = q(self.$field);)* };
        }
        q16_fields!(copy);
        c.validate().map_err(BadConfig::Core)?;
        Ok(c)
    }
}

/// The configuration at `config`.
///
/// # Safety
/// `config` is null or points to an `rbt_config`.
pub(super) unsafe fn config(
    config: *const rbt_config,
) -> Result<Result<Config, BadConfig>, rbt_error> {
    // SAFETY: null (refused) or an `rbt_config` (the caller's promise); every bit pattern
    // of its integer fields is a value.
    let config = unsafe { config.as_ref() }.ok_or(RBT_ERR_NULL)?;
    Ok(config.config())
}

/// Writes the defaults of `variant` (an `rbt_variant`) to `config`: the core's
/// `Config::new`, tuned on real video.
///
/// # Safety
/// `config` is null or points to a writable `rbt_config`.
#[no_mangle]
pub unsafe extern "C" fn rbt_config_default(variant: u32, config: *mut rbt_config) -> rbt_error {
    let variant = match variant {
        0 => Variant::ColourPf,
        1 => Variant::Rbpf,
        _ => return RBT_ERR_CONFIG_ENUM,
    };
    // SAFETY: as this function's contract.
    unsafe { put(config, rbt_config::from(&Config::new(variant))) }
}

/// The correlation-filter tracker's configuration: the core's
/// `rbtrack::tracker::CfConfig`, field for field, its scale filter's settings flattened
/// (`scale_*`; the core's documentation gives each range). `rbt_cf_config_default` fills in
/// the defaults; flags are 0 or not 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct rbt_cf_config {
    /// Context around the target each way, times the mean of its width and height,
    /// Q16.16 in (0, 4].
    pub padding: rbt_q16,
    /// Cell side, px of the resampled region: 2, 4, 6 or 8.
    pub cell: u32,
    /// Width of the translation filter's desired response, share of the target's
    /// `sqrt(w h)`, Q16.16 above 0.
    pub sigma: rbt_q16,
    /// Regulariser of the translation filter, units of `2^-30` of a squared feature.
    pub lambda: u32,
    /// Learning rate of the translation filter, Q16.16 in [0, 1].
    pub cf_rate: rbt_q16,
    /// Learning rate of the colour histograms, Q16.16 in [0, 1].
    pub colour_rate: rbt_q16,
    /// The object's histogram is taken this share of the target's mean side inside its
    /// box, Q16.16 in [0, 1).
    pub inner_padding: rbt_q16,
    /// Weight of the colour response in the merged response, Q16.16 in [0, 1].
    pub merge: rbt_q16,
    /// Ratio between neighbouring scales, Q16.16 in (1, 1.5].
    pub scale_step: rbt_q16,
    /// Width of the scale filter's desired response, times `sqrt(S)`, scales, Q16.16.
    pub scale_sigma: rbt_q16,
    /// Regulariser of the scale filter, units of `2^-32` of a squared feature.
    pub scale_lambda: u32,
    /// Largest area of the scale filter's model, px^2.
    pub scale_area: u32,
    /// Cell side of the scale filter's samples, px.
    pub scale_cell: u32,
    /// Read the scale between samples (flag).
    pub scale_interpolate: u8,
    /// Learning rate of the scale filter, Q16.16 in [0, 1].
    pub scale_rate: rbt_q16,
    /// Largest change of size in a frame, a factor, Q16.16 at least 1.
    pub max_scale_change: rbt_q16,
    /// Learn only from frames whose merged peak is at least this, Q16.16.
    pub learn_above: rbt_q16,
    /// Status uncertain below this confidence, Q16.16 in [0, 1].
    pub uncertain_below: rbt_q16,
    /// Status lost below this confidence, Q16.16 in [0, uncertain_below].
    pub lost_below: rbt_q16,
    /// Search for the target below this merged peak, Q16.16 in [0, search_until]...
    pub search_below: rbt_q16,
    /// ...until the peak reaches this, Q16.16 in [0, 1].
    pub search_until: rbt_q16,
    /// Ring regions a search visits between two searches of the region where the target
    /// was last seen, one region a frame besides the usual one, 0..=8 (0: no re-detection).
    pub redetect: u32,
    /// A searched region takes over when its merged peak is at least this, Q16.16...
    pub redetect_above: rbt_q16,
    /// ...and its colour score at least this, Q16.16.
    pub redetect_colour: rbt_q16,
    /// While searching, search where the velocity it had when the search began puts the
    /// target (flag).
    pub coast: u8,
    /// Change the size only on frames whose merged peak is at least this, Q16.16.
    pub scale_above: rbt_q16,
    /// Centre the search this share of the smoothed velocity ahead, Q16.16 in [0, 1].
    pub lead: rbt_q16,
}

/// Calls `$apply!(field, ...)` with every Q16.16 field `rbt_cf_config` and `CfConfig`
/// share.
macro_rules! cf_q16_fields {
    ($apply:ident) => {
        $apply!(
            padding,
            sigma,
            cf_rate,
            colour_rate,
            inner_padding,
            merge,
            scale_rate,
            max_scale_change,
            learn_above,
            uncertain_below,
            lost_below,
            search_below,
            search_until,
            redetect_above,
            redetect_colour,
            scale_above,
            lead
        )
    };
}

impl From<&CfConfig> for rbt_cf_config {
    fn from(c: &CfConfig) -> Self {
        let count = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
        let mut out = Self {
            cell: count(c.cell),
            lambda: c.lambda,
            scale_step: c.scale.step.to_bits(),
            scale_sigma: c.scale.sigma.to_bits(),
            scale_lambda: c.scale.lambda,
            scale_area: c.scale.area,
            scale_cell: count(c.scale.cell),
            scale_interpolate: c.scale.interpolate.into(),
            redetect: count(c.redetect),
            coast: c.coast.into(),
            ..Self::default()
        };
        macro_rules! copy {
            ($($field:ident),*) => { $(out.$field = c.$field.to_bits();)* };
        }
        cf_q16_fields!(copy);
        out
    }
}

impl rbt_cf_config {
    /// The core's configuration of these fields, checked.
    fn config(&self) -> Result<CfConfig, ConfigError> {
        let q = Q16::from_bits;
        let count = |n: u32| usize::try_from(n).unwrap_or(usize::MAX);
        let mut c = CfConfig {
            cell: count(self.cell),
            lambda: self.lambda,
            scale: ScaleSettings {
                step: q(self.scale_step),
                sigma: q(self.scale_sigma),
                lambda: self.scale_lambda,
                area: self.scale_area,
                cell: count(self.scale_cell),
                interpolate: self.scale_interpolate != 0,
            },
            redetect: count(self.redetect),
            coast: self.coast != 0,
            ..CfConfig::default()
        };
        macro_rules! copy {
            ($($field:ident),*) => { $(c.$field = q(self.$field);)* };
        }
        cf_q16_fields!(copy);
        c.validate()?;
        Ok(c)
    }
}

/// The correlation-filter configuration at `config`.
///
/// # Safety
/// `config` is null or points to an `rbt_cf_config`.
pub(super) unsafe fn cf_config(
    config: *const rbt_cf_config,
) -> Result<Result<CfConfig, ConfigError>, rbt_error> {
    // SAFETY: null (refused) or an `rbt_cf_config` (the caller's promise); every bit
    // pattern of its integer fields is a value.
    let config = unsafe { config.as_ref() }.ok_or(RBT_ERR_NULL)?;
    Ok(config.config())
}

/// Writes the correlation-filter tracker's defaults to `config`: the core's
/// `CfConfig::default()`, the configuration its accuracy figures measure.
///
/// # Safety
/// `config` is null or points to a writable `rbt_cf_config`.
#[no_mangle]
pub unsafe extern "C" fn rbt_cf_config_default(config: *mut rbt_cf_config) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { put(config, rbt_cf_config::from(&CfConfig::default())) }
}

/// A `core::fmt::Write` into a C buffer: as much as fits, then NUL-terminated.
struct CBuffer<'a> {
    bytes: &'a mut [u8],
    len: usize,
}

impl Write for CBuffer<'_> {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        let room = self.bytes.len().saturating_sub(self.len + 1);
        let tail = self.bytes.iter_mut().skip(self.len).take(room);
        for (to, &from) in tail.zip(s.as_bytes()) {
            *to = from;
            self.len += 1;
        }
        if let Some(end) = self.bytes.get_mut(self.len) {
            *end = 0;
        }
        Ok(())
    }
}

/// Checks `config` as `rbt_start` would; on a refusal, writes the reason (for
/// `RBT_ERR_CONFIG_RANGE`, the field's name) to `message` as a NUL-terminated string of
/// at most `size` bytes, if `message` is not null.
///
/// # Safety
/// `config` is null or points to an `rbt_config`; `message` is null or points to `size`
/// writable bytes.
#[no_mangle]
pub unsafe extern "C" fn rbt_config_check(
    config: *const rbt_config,
    message: *mut c_char,
    size: usize,
) -> rbt_error {
    // SAFETY: as this function's contract.
    let checked = match unsafe { self::config(config) } {
        Ok(checked) => checked,
        Err(e) => return e,
    };
    let Err(bad) = checked else {
        return RBT_OK;
    };
    // SAFETY: as this function's contract.
    unsafe { refuse(bad, message, size) }
}

/// Checks `config` as `rbt_cf_start` would; on a refusal, writes the reason (for
/// `RBT_ERR_CONFIG_RANGE`, the field's name) to `message` as `rbt_config_check` does.
///
/// # Safety
/// `config` is null or points to an `rbt_cf_config`; `message` is null or points to `size`
/// writable bytes.
#[no_mangle]
pub unsafe extern "C" fn rbt_cf_config_check(
    config: *const rbt_cf_config,
    message: *mut c_char,
    size: usize,
) -> rbt_error {
    // SAFETY: as this function's contract.
    let checked = match unsafe { cf_config(config) } {
        Ok(checked) => checked,
        Err(e) => return e,
    };
    let Err(bad) = checked else {
        return RBT_OK;
    };
    // SAFETY: as this function's contract.
    unsafe { refuse(bad, message, size) }
}

/// Writes why `bad` was refused to `message` as a NUL-terminated string of at most `size`
/// bytes, if `message` is not null, and returns its code.
///
/// # Safety
/// `message` is null or points to `size` writable bytes.
unsafe fn refuse<E: core::fmt::Display + Into<rbt_error>>(
    bad: E,
    message: *mut c_char,
    size: usize,
) -> rbt_error {
    if !message.is_null() && size > 0 {
        // SAFETY: `message` is non-null and points to `size` writable bytes (the caller's
        // promise).
        let bytes = unsafe { core::slice::from_raw_parts_mut(message.cast::<u8>(), size) };
        let mut out = CBuffer { bytes, len: 0 };
        let _ = write!(out, "{bad}");
        let _ = out.write_str(""); // NUL-terminates an empty message too
    }
    bad.into()
}
