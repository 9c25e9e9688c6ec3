//! The C API: `#[repr(C)]` types and `extern "C"` functions over raw pointers, checked
//! before use. The header `include/rbtrack.h` is generated from this file by cbindgen.
//!
//! Every function returns an [`rbt_error`] (`RBT_OK` on success) and writes its results
//! through pointers; a null pointer, a short or misaligned buffer, an unknown pixel
//! format or enum value, or a handle that no `rbt_tracker_place_*` made is an error code,
//! never undefined behaviour. Fixed-point values are Q16.16 ([`rbt_q16`]): the value
//! times 65536.
#![allow(unsafe_code, non_camel_case_types)]

use crate::frame::{Format, Frame};
use crate::track::{CfTrack, Track};
use core::ffi::{c_char, c_void, CStr};
use core::fmt::Write;
use core::ptr::{self, NonNull};
use rbtrack::cf::scale::ScaleSettings;
use rbtrack::image::ImageError;
use rbtrack::pantilt::{AxisConfig, Command, PanTilt, PanTiltConfig, PanTiltError};
use rbtrack::tracker::{
    CameraMotion, CfConfig, CfTracker, Config, ConfigError, CueMix, Estimate, Readout, Scheme,
    SizeMeasurement, Status, Variant,
};
use rbtrack::{
    Binning, Ellipse, LumaTracker, Rect, Rgb256Tracker, RgbCfTracker, RgbTracker, Tracker,
    YuvTracker, Q16,
};

/// A Q16.16 fixed-point number: the value times 65536 (`RBT_Q16_ONE` is 1).
pub type rbt_q16 = i32;

/// 1 in Q16.16.
pub const RBT_Q16_ONE: rbt_q16 = 1 << 16;

/// What a function returns: `RBT_OK`, or why it refused (`rbt_error_name` names it).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum rbt_error {
    /// Success.
    RBT_OK = 0,
    /// A pointer argument is null.
    RBT_ERR_NULL = 1,
    /// The tracker memory is smaller than the configuration's `RBT_TRACKER_*_SIZE`.
    RBT_ERR_MEMORY_SIZE = 2,
    /// The tracker memory is not aligned to `RBT_TRACKER_ALIGN`.
    RBT_ERR_MEMORY_ALIGN = 3,
    /// The handle was not made by an `rbt_tracker_place_*` function.
    RBT_ERR_NOT_A_TRACKER = 4,
    /// The controller was not started by `rbt_pantilt_start`.
    RBT_ERR_NOT_A_PANTILT = 5,
    /// The image's pixel format is not an `rbt_format`, or not one this library was built
    /// with (its Cargo features).
    RBT_ERR_FORMAT = 6,
    /// The image's width or height is 0.
    RBT_ERR_IMAGE_EMPTY = 7,
    /// The image's width or height is above 16383 px.
    RBT_ERR_IMAGE_TOO_LARGE = 8,
    /// The image's stride is smaller than its width.
    RBT_ERR_IMAGE_STRIDE = 9,
    /// A YUV 4:2:2 image's width or stride is odd.
    RBT_ERR_IMAGE_ODD_YUV = 10,
    /// The image's buffer is shorter than its width, height and stride need.
    RBT_ERR_IMAGE_SHORT = 11,
    /// An enum field of the configuration holds an unknown value.
    RBT_ERR_CONFIG_ENUM = 12,
    /// A configuration field is out of its range (`rbt_config_check` names it).
    RBT_ERR_CONFIG_RANGE = 13,
    /// The Kalman filter refused `kalman_q` and `kalman_r`.
    RBT_ERR_CONFIG_KALMAN = 14,
    /// The particle count is outside 1..=65535.
    RBT_ERR_PARTICLE_COUNT = 15,
    /// The box is smaller than twice `min_half_axis`.
    RBT_ERR_BOX_TOO_SMALL = 16,
    /// The box's centre lies outside the frame.
    RBT_ERR_BOX_OUTSIDE = 17,
    /// A target model learnt under other colour settings.
    RBT_ERR_MODEL_SETTINGS = 18,
    /// An estimate's status is not an `rbt_status`.
    RBT_ERR_STATUS = 19,
    /// The pan/tilt frame width or height is 0.
    RBT_ERR_PANTILT_FRAME = 20,
    /// A pan/tilt field of view is outside (0, 360] degrees.
    RBT_ERR_PANTILT_FOV = 21,
    /// A pan/tilt gain is outside [0, 4].
    RBT_ERR_PANTILT_GAIN = 22,
    /// A pan/tilt dead band is negative or a rate limit not positive.
    RBT_ERR_PANTILT_LIMIT = 23,
    /// A pan/tilt `min` is above `max`, or `home` is outside them.
    RBT_ERR_PANTILT_RANGE = 24,
    /// The call is for the other kind of tracker: a particle filter's (`rbt_start`,
    /// `rbt_reset`, `rbt_relocate`) on the correlation-filter tracker, or `rbt_cf_start` on
    /// a particle filter.
    RBT_ERR_TRACKER_KIND = 25,
}

use rbt_error::*;

impl rbt_error {
    /// Every code, in order.
    const ALL: [rbt_error; 26] = [
        RBT_OK,
        RBT_ERR_NULL,
        RBT_ERR_MEMORY_SIZE,
        RBT_ERR_MEMORY_ALIGN,
        RBT_ERR_NOT_A_TRACKER,
        RBT_ERR_NOT_A_PANTILT,
        RBT_ERR_FORMAT,
        RBT_ERR_IMAGE_EMPTY,
        RBT_ERR_IMAGE_TOO_LARGE,
        RBT_ERR_IMAGE_STRIDE,
        RBT_ERR_IMAGE_ODD_YUV,
        RBT_ERR_IMAGE_SHORT,
        RBT_ERR_CONFIG_ENUM,
        RBT_ERR_CONFIG_RANGE,
        RBT_ERR_CONFIG_KALMAN,
        RBT_ERR_PARTICLE_COUNT,
        RBT_ERR_BOX_TOO_SMALL,
        RBT_ERR_BOX_OUTSIDE,
        RBT_ERR_MODEL_SETTINGS,
        RBT_ERR_STATUS,
        RBT_ERR_PANTILT_FRAME,
        RBT_ERR_PANTILT_FOV,
        RBT_ERR_PANTILT_GAIN,
        RBT_ERR_PANTILT_LIMIT,
        RBT_ERR_PANTILT_RANGE,
        RBT_ERR_TRACKER_KIND,
    ];

    /// The code's name and meaning, as `rbt_error_name` returns it.
    fn name(self) -> &'static CStr {
        match self {
            RBT_OK => c"RBT_OK: success",
            RBT_ERR_NULL => c"RBT_ERR_NULL: a pointer argument is null",
            RBT_ERR_MEMORY_SIZE => c"RBT_ERR_MEMORY_SIZE: tracker memory smaller than its size",
            RBT_ERR_MEMORY_ALIGN => c"RBT_ERR_MEMORY_ALIGN: tracker memory misaligned",
            RBT_ERR_NOT_A_TRACKER => c"RBT_ERR_NOT_A_TRACKER: not a placed tracker",
            RBT_ERR_NOT_A_PANTILT => c"RBT_ERR_NOT_A_PANTILT: not a started pan/tilt controller",
            RBT_ERR_FORMAT => c"RBT_ERR_FORMAT: pixel format unknown or not built in",
            RBT_ERR_IMAGE_EMPTY => c"RBT_ERR_IMAGE_EMPTY: image width or height is zero",
            RBT_ERR_IMAGE_TOO_LARGE => {
                c"RBT_ERR_IMAGE_TOO_LARGE: image width or height is above 16383 px"
            }
            RBT_ERR_IMAGE_STRIDE => c"RBT_ERR_IMAGE_STRIDE: image stride is smaller than its width",
            RBT_ERR_IMAGE_ODD_YUV => {
                c"RBT_ERR_IMAGE_ODD_YUV: YUV 4:2:2 image width and stride must be even"
            }
            RBT_ERR_IMAGE_SHORT => {
                c"RBT_ERR_IMAGE_SHORT: image buffer is too short for width, height and stride"
            }
            RBT_ERR_CONFIG_ENUM => {
                c"RBT_ERR_CONFIG_ENUM: a configuration enum holds an unknown value"
            }
            RBT_ERR_CONFIG_RANGE => c"RBT_ERR_CONFIG_RANGE: a configuration field is out of range",
            RBT_ERR_CONFIG_KALMAN => {
                c"RBT_ERR_CONFIG_KALMAN: the Kalman filter refused kalman_q and kalman_r"
            }
            RBT_ERR_PARTICLE_COUNT => {
                c"RBT_ERR_PARTICLE_COUNT: particle count must be in 1..=65535"
            }
            RBT_ERR_BOX_TOO_SMALL => {
                c"RBT_ERR_BOX_TOO_SMALL: box narrower or lower than twice min_half_axis"
            }
            RBT_ERR_BOX_OUTSIDE => c"RBT_ERR_BOX_OUTSIDE: box centred outside the frame",
            RBT_ERR_MODEL_SETTINGS => {
                c"RBT_ERR_MODEL_SETTINGS: target model learnt under other colour settings"
            }
            RBT_ERR_STATUS => c"RBT_ERR_STATUS: unknown estimate status",
            RBT_ERR_PANTILT_FRAME => {
                c"RBT_ERR_PANTILT_FRAME: frame width and height must be positive"
            }
            RBT_ERR_PANTILT_FOV => {
                c"RBT_ERR_PANTILT_FOV: field of view must be in (0, 360] degrees"
            }
            RBT_ERR_PANTILT_GAIN => c"RBT_ERR_PANTILT_GAIN: gains must be in [0, 4]",
            RBT_ERR_PANTILT_LIMIT => {
                c"RBT_ERR_PANTILT_LIMIT: dead band must be >= 0 and the rate limit > 0"
            }
            RBT_ERR_PANTILT_RANGE => {
                c"RBT_ERR_PANTILT_RANGE: min must be <= max, with home between them"
            }
            RBT_ERR_TRACKER_KIND => c"RBT_ERR_TRACKER_KIND: a call for the other kind of tracker",
        }
    }
}

impl From<ImageError> for rbt_error {
    fn from(e: ImageError) -> Self {
        match e {
            ImageError::ZeroSize => RBT_ERR_IMAGE_EMPTY,
            ImageError::TooLarge => RBT_ERR_IMAGE_TOO_LARGE,
            ImageError::StrideTooSmall => RBT_ERR_IMAGE_STRIDE,
            ImageError::OddYuvSize => RBT_ERR_IMAGE_ODD_YUV,
            ImageError::BufferTooShort => RBT_ERR_IMAGE_SHORT,
        }
    }
}

impl From<ConfigError> for rbt_error {
    fn from(e: ConfigError) -> Self {
        match e {
            ConfigError::OutOfRange(_) | ConfigError::Gradient(_) => RBT_ERR_CONFIG_RANGE,
            ConfigError::Kalman(_) => RBT_ERR_CONFIG_KALMAN,
            ConfigError::ParticleCount => RBT_ERR_PARTICLE_COUNT,
            ConfigError::InitialTooSmall => RBT_ERR_BOX_TOO_SMALL,
            ConfigError::InitialOutside => RBT_ERR_BOX_OUTSIDE,
            ConfigError::ModelSettings => RBT_ERR_MODEL_SETTINGS,
        }
    }
}

impl From<PanTiltError> for rbt_error {
    fn from(e: PanTiltError) -> Self {
        match e {
            PanTiltError::FrameSize => RBT_ERR_PANTILT_FRAME,
            PanTiltError::FieldOfView => RBT_ERR_PANTILT_FOV,
            PanTiltError::Gain => RBT_ERR_PANTILT_GAIN,
            PanTiltError::Limit => RBT_ERR_PANTILT_LIMIT,
            PanTiltError::Range => RBT_ERR_PANTILT_RANGE,
        }
    }
}

/// `RBT_OK` for `Ok`, the error's code otherwise.
fn code<E: Into<rbt_error>>(result: Result<(), E>) -> rbt_error {
    result.map_or_else(Into::into, |()| RBT_OK)
}

/// An `rbt_error` passed from C, where an enum may hold any value of its integer type: read
/// as that integer, so that a value no code has is no undefined behaviour. The header
/// calls it `rbt_error` (cbindgen.toml renames it).
pub type rbt_error_code = i32;

/// The name and meaning of an `rbt_error` code, as a static NUL-terminated string (never
/// null; "unknown" for a code that is none).
#[no_mangle]
pub extern "C" fn rbt_error_name(code: rbt_error_code) -> *const c_char {
    let known = rbt_error::ALL.into_iter().find(|&e| e as i32 == code);
    known
        .map_or(c"unknown rbt_error code", rbt_error::name)
        .as_ptr()
}

/// A pixel format (`rbt_image.format`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum rbt_format {
    /// 8-bit grey, 1 byte per pixel.
    RBT_FORMAT_GRAY8 = 1,
    /// RGB565, a little-endian 16-bit word per pixel.
    RBT_FORMAT_RGB565LE = 2,
    /// RGB565, a big-endian 16-bit word per pixel.
    RBT_FORMAT_RGB565BE = 3,
    /// 3 bytes per pixel: R, G, B.
    RBT_FORMAT_RGB888 = 4,
    /// 3 bytes per pixel: B, G, R.
    RBT_FORMAT_BGR888 = 5,
    /// YUV 4:2:2, `Y0 U Y1 V` per pixel pair (width and stride even).
    RBT_FORMAT_YUYV = 6,
    /// YUV 4:2:2, `U Y0 V Y1` per pixel pair (width and stride even).
    RBT_FORMAT_UYVY = 7,
}

/// A camera frame, borrowed for the call.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct rbt_image {
    /// The pixels, row after row; `size` bytes readable.
    pub data: *const u8,
    /// Bytes at `data`; at least `((height - 1) * stride + width) * bytes per pixel`.
    pub size: usize,
    /// Width, px, 1..=16383.
    pub width: u32,
    /// Height, px, 1..=16383.
    pub height: u32,
    /// Distance between row starts, px, `>= width`.
    pub stride: u32,
    /// An `rbt_format`.
    pub format: u32,
}

/// The frame `image` describes.
///
/// # Safety
/// `image` is null or points to an `rbt_image` whose `data` is null or points to `size`
/// bytes that stay readable and unchanged for `'a`.
unsafe fn frame<'a>(image: *const rbt_image) -> Result<Frame<'a>, rbt_error> {
    // SAFETY: `image` is null (refused here) or points to an `rbt_image` (the caller's
    // promise).
    let image = unsafe { image.as_ref() }.ok_or(RBT_ERR_NULL)?;
    let format = Format::from_code(image.format).ok_or(RBT_ERR_FORMAT)?;
    if image.data.is_null() {
        return Err(RBT_ERR_NULL);
    }
    // A slice may not exceed isize::MAX bytes; a prefix of readable bytes is readable.
    let size = image.size.min(isize::MAX as usize);
    // SAFETY: `data` is non-null and points to at least `size` readable bytes that stay
    // unchanged for `'a` (the caller's promise); `u8` has no alignment or validity needs.
    let bytes = unsafe { core::slice::from_raw_parts(image.data, size) };
    let side = |v: u32| usize::try_from(v).unwrap_or(usize::MAX);
    let (width, height, stride) = (side(image.width), side(image.height), side(image.stride));
    Ok(Frame::new(format, bytes, width, height, stride)?)
}

/// A box: top-left corner `(x, y)` and size `w x h`, px, Q16.16, 0-based (a box of whole
/// pixels covers columns `x..=x+w-1`). A tracker works on its inscribed ellipse.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct rbt_rect {
    /// Left edge (the centre of the leftmost pixel column), px, Q16.16.
    pub x: rbt_q16,
    /// Top edge (the centre of the top pixel row), px, Q16.16.
    pub y: rbt_q16,
    /// Width, px, Q16.16.
    pub w: rbt_q16,
    /// Height, px, Q16.16.
    pub h: rbt_q16,
}

impl rbt_rect {
    /// The box's inscribed ellipse.
    fn ellipse(&self) -> Ellipse {
        let q = Q16::from_bits;
        Rect::from_q16(q(self.x), q(self.y), q(self.w), q(self.h)).into()
    }
}

/// The box at `rect`.
///
/// # Safety
/// `rect` is null or points to an `rbt_rect`.
unsafe fn ellipse(rect: *const rbt_rect) -> Result<Ellipse, rbt_error> {
    // SAFETY: null (refused) or an `rbt_rect` (the caller's promise).
    unsafe { rect.as_ref() }
        .map(rbt_rect::ellipse)
        .ok_or(RBT_ERR_NULL)
}

/// How sure the tracker is of its estimate, numbered from least to most sure.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum rbt_status {
    /// Confidence below `lost_below`: the target is hidden or gone; the tracker searches.
    RBT_STATUS_LOST = 0,
    /// Confidence in `[lost_below, uncertain_below)`: the tracker searches too.
    RBT_STATUS_UNCERTAIN = 1,
    /// Confidence at or above `uncertain_below`.
    RBT_STATUS_TRACKING = 2,
}

/// Where the target is after a step.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct rbt_estimate {
    /// The box: the ellipse's bounding box, px, Q16.16.
    pub rect: rbt_rect,
    /// The ellipse's centre column, px, Q16.16; always inside the frame.
    pub cx: rbt_q16,
    /// The ellipse's centre row, px, Q16.16.
    pub cy: rbt_q16,
    /// Horizontal half-axis, px, Q16.16.
    pub hx: rbt_q16,
    /// Vertical half-axis, px, Q16.16.
    pub hy: rbt_q16,
    /// Horizontal velocity, px/frame, Q16.16.
    pub vx: rbt_q16,
    /// Vertical velocity, px/frame, Q16.16.
    pub vy: rbt_q16,
    /// How well the window matches the model, less the particles' spread, Q16.16 in [0, 1].
    pub confidence: rbt_q16,
    /// An `rbt_status`.
    pub status: u32,
}

impl From<Estimate> for rbt_estimate {
    fn from(e: Estimate) -> Self {
        let r = e.rect();
        let el = e.ellipse;
        Self {
            rect: rbt_rect {
                x: r.x.to_bits(),
                y: r.y.to_bits(),
                w: r.w.to_bits(),
                h: r.h.to_bits(),
            },
            cx: el.cx.to_bits(),
            cy: el.cy.to_bits(),
            hx: el.hx.to_bits(),
            hy: el.hy.to_bits(),
            vx: e.vx.to_bits(),
            vy: e.vy.to_bits(),
            confidence: e.confidence.to_bits(),
            status: match e.status {
                Status::Lost => rbt_status::RBT_STATUS_LOST,
                Status::Uncertain => rbt_status::RBT_STATUS_UNCERTAIN,
                Status::Tracking => rbt_status::RBT_STATUS_TRACKING,
            } as u32,
        }
    }
}

impl rbt_estimate {
    /// The core's estimate of these fields (the ellipse, not `rect`).
    fn estimate(&self) -> Result<Estimate, rbt_error> {
        let status = match self.status {
            0 => Status::Lost,
            1 => Status::Uncertain,
            2 => Status::Tracking,
            _ => return Err(RBT_ERR_STATUS),
        };
        let q = Q16::from_bits;
        Ok(Estimate {
            ellipse: Ellipse::new(q(self.cx), q(self.cy), q(self.hx), q(self.hy)),
            vx: q(self.vx),
            vy: q(self.vy),
            confidence: q(self.confidence),
            status,
        })
    }
}

/// Writes `value` to `out`.
///
/// # Safety
/// `out` is null or points to a writable `T`.
unsafe fn put<T>(out: *mut T, value: T) -> rbt_error {
    if out.is_null() {
        return RBT_ERR_NULL;
    }
    // SAFETY: non-null, and a writable `T` (the caller's promise); `T` has no drop glue
    // here (plain `repr(C)` values), so overwriting without reading is fine.
    unsafe { out.write(value) };
    RBT_OK
}

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
enum BadConfig {
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
unsafe fn config(config: *const rbt_config) -> Result<Result<Config, BadConfig>, rbt_error> {
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
    /// Learn only from frames whose confidence is at least this, Q16.16.
    pub learn_above: rbt_q16,
    /// Status uncertain below this confidence, Q16.16 in [0, 1].
    pub uncertain_below: rbt_q16,
    /// Status lost below this confidence (and until `uncertain_below` again), Q16.16.
    pub lost_below: rbt_q16,
    /// Regions searched besides the usual one each frame while lost, 0..=8.
    pub redetect: u32,
    /// A searched region takes over when its merged peak is at least this, Q16.16...
    pub redetect_above: rbt_q16,
    /// ...and its colour score at least this, Q16.16.
    pub redetect_colour: rbt_q16,
    /// While lost, search where the velocity it had when lost puts the target (flag).
    pub coast: u8,
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
            redetect_above,
            redetect_colour
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
unsafe fn cf_config(
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

/// A tracker, in memory its caller owns (`rbt_tracker_place_*` makes one).
pub struct rbt_tracker {
    _private: [u8; 0],
}

/// Written at the start of a placed tracker: `b"RBT1"`.
const MAGIC: u32 = u32::from_le_bytes(*b"RBT1");

/// The start of a placed tracker's memory: the magic word, then how to reach the tracker.
#[repr(C)]
struct Header {
    magic: u32,
    open: unsafe fn(NonNull<Header>) -> Placed,
}

/// A placed tracker of either kind, as its header reaches it.
enum Placed {
    /// A particle filter.
    Particles(NonNull<dyn Track>),
    /// The correlation-filter tracker.
    Correlation(NonNull<dyn CfTrack>),
}

/// A placed tracker of either kind, borrowed.
enum Engine<'a> {
    /// A particle filter.
    Particles(&'a mut dyn Track),
    /// The correlation-filter tracker.
    Correlation(&'a mut dyn CfTrack),
}

/// A placed tracker: the header, then the tracker.
#[repr(C)]
struct Slot<T> {
    header: Header,
    tracker: T,
}

/// The tracker of the slot of type `T` that `header` starts.
///
/// # Safety
/// `header` starts a live `Slot<T>`.
unsafe fn tracker_of<T>(header: NonNull<Header>) -> NonNull<T> {
    let slot = header.cast::<Slot<T>>().as_ptr();
    // SAFETY: `slot` is a live `Slot<T>` (the caller's promise), so the field's address is
    // in bounds and non-null.
    unsafe { NonNull::new_unchecked(ptr::addr_of_mut!((*slot).tracker)) }
}

/// A tracker that can be placed: its unstarted value is a constant, and its header
/// reaches it as its kind.
trait Placeable: Sized + 'static {
    /// The unstarted tracker (`unstarted()`: all zero bits).
    const UNSTARTED: Self;
    /// The tracker of the slot that `header` starts.
    ///
    /// # Safety
    /// `header` starts a live `Slot<Self>`.
    unsafe fn open(header: NonNull<Header>) -> Placed;
}

impl<Bn: Binning + 'static, const N: usize, const B: usize> Placeable for Tracker<Bn, N, B> {
    const UNSTARTED: Self = Self::unstarted();

    unsafe fn open(header: NonNull<Header>) -> Placed {
        // SAFETY: as this function's contract.
        Placed::Particles(unsafe { tracker_of::<Self>(header) })
    }
}

impl<Bn: Binning + 'static, const B: usize, const G: usize, const S: usize> Placeable
    for CfTracker<Bn, B, G, S>
{
    const UNSTARTED: Self = Self::unstarted();

    unsafe fn open(header: NonNull<Header>) -> Placed {
        // SAFETY: as this function's contract.
        Placed::Correlation(unsafe { tracker_of::<Self>(header) })
    }
}

/// Places an unstarted `T` at `memory` and writes its handle to `out`.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes, which the tracker then owns;
/// `out` is null or points to a writable pointer.
unsafe fn place<T: Placeable>(
    memory: *mut c_void,
    size: usize,
    out: *mut *mut rbt_tracker,
) -> rbt_error {
    if memory.is_null() || out.is_null() {
        return RBT_ERR_NULL;
    }
    if size < size_of::<Slot<T>>() {
        return RBT_ERR_MEMORY_SIZE;
    }
    let slot = memory.cast::<Slot<T>>();
    if !slot.is_aligned() {
        return RBT_ERR_MEMORY_ALIGN;
    }
    // SAFETY: `slot` is non-null, aligned and has room for a `Slot<T>` (checked above) in
    // memory the caller hands over; the value is a constant, written in place.
    unsafe {
        slot.write(Slot {
            header: Header {
                magic: MAGIC,
                open: T::open,
            },
            tracker: T::UNSTARTED,
        });
        out.write(slot.cast::<rbt_tracker>());
    }
    RBT_OK
}

/// The tracker behind `handle`.
///
/// # Safety
/// `handle` is null or a handle from an `rbt_tracker_place_*` function whose memory is
/// still the tracker's, not used elsewhere during the borrow `'a`; or other memory whose
/// first 4 bytes are readable and not `b"RBT1"`.
unsafe fn tracker<'a>(handle: *mut rbt_tracker) -> Result<Engine<'a>, rbt_error> {
    let header = NonNull::new(handle.cast::<Header>()).ok_or(RBT_ERR_NULL)?;
    if !header.as_ptr().is_aligned() {
        return Err(RBT_ERR_NOT_A_TRACKER);
    }
    // SAFETY: the first 4 bytes are readable (the caller's promise) and aligned (checked);
    // any bits are a `u32`.
    let magic = unsafe { ptr::addr_of!((*header.as_ptr()).magic).read() };
    if magic != MAGIC {
        return Err(RBT_ERR_NOT_A_TRACKER);
    }
    // SAFETY: the magic word says `place` wrote this header and its slot, which is live
    // and borrowed by no one else for `'a` (the caller's promise).
    unsafe {
        let open = ptr::addr_of!((*header.as_ptr()).open).read();
        Ok(match open(header) {
            Placed::Particles(t) => Engine::Particles(&mut *t.as_ptr()),
            Placed::Correlation(t) => Engine::Correlation(&mut *t.as_ptr()),
        })
    }
}

/// Runs `f` on the tracker behind `handle`, returning its code.
///
/// # Safety
/// As [`tracker`].
unsafe fn with_tracker(
    handle: *mut rbt_tracker,
    f: impl FnOnce(Engine<'_>) -> rbt_error,
) -> rbt_error {
    // SAFETY: as this function's contract.
    match unsafe { tracker(handle) } {
        Ok(t) => f(t),
        Err(e) => e,
    }
}

/// Runs `f` on the particle filter behind `handle`, returning its code;
/// `RBT_ERR_TRACKER_KIND` for the correlation-filter tracker.
///
/// # Safety
/// As [`tracker`].
unsafe fn with_particles(
    handle: *mut rbt_tracker,
    f: impl FnOnce(&mut dyn Track) -> rbt_error,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe {
        with_tracker(handle, |t| match t {
            Engine::Particles(t) => f(t),
            Engine::Correlation(_) => RBT_ERR_TRACKER_KIND,
        })
    }
}

// Bytes of tracker memory of each configuration offered, on 32-bit targets (Cortex-M,
// RISC-V) and on 64-bit ones; each is checked against the tracker at compile time, and
// `place` checks the memory it is given against the size on the target it runs on.
/// Bytes of memory for a tracker of 25 particles on 512 RGB bins (8x8x8) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_RGB_25_SIZE: usize = 50840;
/// Bytes of memory for a tracker of 25 particles on 512 RGB bins (8x8x8) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_RGB_25_SIZE: usize = 50880;
/// Bytes of memory for a tracker of 50 particles on 512 RGB bins (8x8x8) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_RGB_50_SIZE: usize = 52048;
/// Bytes of memory for a tracker of 50 particles on 512 RGB bins (8x8x8) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_RGB_50_SIZE: usize = 52080;
/// Bytes of memory for a tracker of 100 particles on 512 RGB bins (8x8x8) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_RGB_100_SIZE: usize = 54448;
/// Bytes of memory for a tracker of 100 particles on 512 RGB bins (8x8x8) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_RGB_100_SIZE: usize = 54480;
/// Bytes of memory for a tracker of 200 particles on 512 RGB bins (8x8x8) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_RGB_200_SIZE: usize = 59248;
/// Bytes of memory for a tracker of 200 particles on 512 RGB bins (8x8x8) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_RGB_200_SIZE: usize = 59280;
/// Bytes of memory for a tracker of 100 particles on 256 RGB bins (8x8x4) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_RGB256_100_SIZE: usize = 41648;
/// Bytes of memory for a tracker of 100 particles on 256 RGB bins (8x8x4) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_RGB256_100_SIZE: usize = 41680;
/// Bytes of memory for a tracker of 100 particles on 256 YUV bins (8x8x4) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_YUV_100_SIZE: usize = 41648;
/// Bytes of memory for a tracker of 100 particles on 256 YUV bins (8x8x4) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_YUV_100_SIZE: usize = 41680;
/// Bytes of memory for a tracker of 100 particles on 64 grey levels (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_LUMA_100_SIZE: usize = 32048;
/// Bytes of memory for a tracker of 100 particles on 64 grey levels (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_LUMA_100_SIZE: usize = 32080;
/// Bytes of memory for the correlation-filter tracker at its defaults: 16 x 16 cells, 8
/// scales, 512 RGB bins (8x8x8) (32-bit targets).
#[cfg(target_pointer_width = "32")]
pub const RBT_TRACKER_CF_SIZE: usize = 70616;
/// Bytes of memory for the correlation-filter tracker at its defaults: 16 x 16 cells, 8
/// scales, 512 RGB bins (8x8x8) (64-bit targets).
#[cfg(target_pointer_width = "64")]
pub const RBT_TRACKER_CF_SIZE: usize = 70696;
/// Alignment of every tracker's memory, bytes.
pub const RBT_TRACKER_ALIGN: usize = 8;

/// Checks a configuration's memory constants at compile time.
macro_rules! check_memory {
    ($tracker:ty, $size:ident) => {
        const _: () = assert!(
            size_of::<Slot<$tracker>>() == $size
                && align_of::<Slot<$tracker>>() <= RBT_TRACKER_ALIGN,
            "the header's size or alignment is not the tracker's"
        );
    };
}
check_memory!(RgbTracker<25>, RBT_TRACKER_RGB_25_SIZE);
check_memory!(RgbTracker<50>, RBT_TRACKER_RGB_50_SIZE);
check_memory!(RgbTracker<100>, RBT_TRACKER_RGB_100_SIZE);
check_memory!(RgbTracker<200>, RBT_TRACKER_RGB_200_SIZE);
check_memory!(Rgb256Tracker<100>, RBT_TRACKER_RGB256_100_SIZE);
check_memory!(YuvTracker<100>, RBT_TRACKER_YUV_100_SIZE);
check_memory!(LumaTracker<100>, RBT_TRACKER_LUMA_100_SIZE);
check_memory!(RgbCfTracker, RBT_TRACKER_CF_SIZE);

/// Places an unstarted tracker of 25 particles on 512 RGB bins (8x8x8) in `memory`
/// (`RBT_TRACKER_RGB_25_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_rgb_25(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<RgbTracker<25>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 50 particles on 512 RGB bins (8x8x8) in `memory`
/// (`RBT_TRACKER_RGB_50_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_rgb_50(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<RgbTracker<50>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 100 particles on 512 RGB bins (8x8x8): the defaults of the example firmware and the host tool in `memory`
/// (`RBT_TRACKER_RGB_100_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_rgb_100(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<RgbTracker<100>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 200 particles on 512 RGB bins (8x8x8) in `memory`
/// (`RBT_TRACKER_RGB_200_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_rgb_200(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<RgbTracker<200>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 100 particles on 256 RGB bins (8x8x4) in `memory`
/// (`RBT_TRACKER_RGB256_100_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_rgb256_100(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<Rgb256Tracker<100>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 100 particles on 256 YUV bins (8x8x4) in `memory`
/// (`RBT_TRACKER_YUV_100_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_yuv_100(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<YuvTracker<100>>(memory, size, tracker) }
}

/// Places an unstarted tracker of 100 particles on 64 grey levels in `memory`
/// (`RBT_TRACKER_LUMA_100_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle
/// to `tracker`; `rbt_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_luma_100(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<LumaTracker<100>>(memory, size, tracker) }
}

/// Places the unstarted correlation-filter tracker at its defaults (16 x 16 cells, 8
/// scales, 512 RGB bins (8x8x8): the core's `RgbCfTracker`) in `memory`
/// (`RBT_TRACKER_CF_SIZE` bytes, aligned to `RBT_TRACKER_ALIGN`) and writes its handle to
/// `tracker`; `rbt_cf_start` starts it.
///
/// # Safety
/// `memory` is null or points to `size` writable bytes that the tracker owns from then
/// on; `tracker` is null or points to a writable pointer.
#[no_mangle]
pub unsafe extern "C" fn rbt_tracker_place_cf(
    memory: *mut c_void,
    size: usize,
    tracker: *mut *mut rbt_tracker,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe { place::<RgbCfTracker>(memory, size, tracker) }
}

/// Starts the correlation-filter tracker on the box `box` of `frame` with `config`, in
/// place, whatever it did before (the core's `CfTracker::start`: its models learn the box
/// afresh); `RBT_ERR_TRACKER_KIND` for a particle filter.
///
/// # Safety
/// `tracker` is null or a handle from `rbt_tracker_place_*` whose memory is still the
/// tracker's and used by no other call meanwhile; `config`, `frame` and `box` are null or
/// point to their types, and `frame->data` to `frame->size` readable bytes.
#[no_mangle]
pub unsafe extern "C" fn rbt_cf_start(
    tracker: *mut rbt_tracker,
    config: *const rbt_cf_config,
    frame: *const rbt_image,
    r#box: *const rbt_rect,
) -> rbt_error {
    // SAFETY: as this function's contract.
    let (config, frame, init) =
        match unsafe { (cf_config(config), self::frame(frame), ellipse(r#box)) } {
            (Ok(Ok(config)), Ok(frame), Ok(init)) => (config, frame, Rect::from(init)),
            (Ok(Err(bad)), ..) => return bad.into(),
            (Err(e), ..) | (_, Err(e), _) | (.., Err(e)) => return e,
        };
    // SAFETY: as this function's contract.
    unsafe {
        with_tracker(tracker, |t| match t {
            Engine::Correlation(t) => code(t.start(config, &frame, init)),
            Engine::Particles(_) => RBT_ERR_TRACKER_KIND,
        })
    }
}

/// Starts the tracker on the box `box` of `frame` with `config`, in place, whatever it did
/// before (the core's `Tracker::start`); `RBT_ERR_TRACKER_KIND` for the correlation-filter
/// tracker, which `rbt_cf_start` starts.
///
/// # Safety
/// `tracker` is null or a handle from `rbt_tracker_place_*` whose memory is still the
/// tracker's and used by no other call meanwhile; `config`, `frame` and `box` are null or
/// point to their types, and `frame->data` to `frame->size` readable bytes.
#[no_mangle]
pub unsafe extern "C" fn rbt_start(
    tracker: *mut rbt_tracker,
    config: *const rbt_config,
    frame: *const rbt_image,
    r#box: *const rbt_rect,
) -> rbt_error {
    // SAFETY: as this function's contract.
    let (config, frame, init) =
        match unsafe { (self::config(config), self::frame(frame), ellipse(r#box)) } {
            (Ok(Ok(config)), Ok(frame), Ok(init)) => (config, frame, init),
            (Ok(Err(bad)), ..) => return bad.into(),
            (Err(e), ..) | (_, Err(e), _) | (.., Err(e)) => return e,
        };
    // SAFETY: as this function's contract.
    unsafe { with_particles(tracker, |t| code(t.start(config, &frame, init))) }
}

/// Re-initialises the tracker on the box `box` of `frame`: a new model, the
/// configuration kept (the core's `Tracker::reset`); `RBT_ERR_TRACKER_KIND` for the
/// correlation-filter tracker (`rbt_cf_start` starts it again).
///
/// # Safety
/// As `rbt_start`.
#[no_mangle]
pub unsafe extern "C" fn rbt_reset(
    tracker: *mut rbt_tracker,
    frame: *const rbt_image,
    r#box: *const rbt_rect,
) -> rbt_error {
    // SAFETY: as this function's contract.
    let (frame, init) = match unsafe { (self::frame(frame), ellipse(r#box)) } {
        (Ok(frame), Ok(init)) => (frame, init),
        (Err(e), _) | (_, Err(e)) => return e,
    };
    // SAFETY: as this function's contract.
    unsafe { with_particles(tracker, |t| code(t.reset(&frame, init))) }
}

/// Moves the tracker onto the box `box` of `frame` (say a detector's), keeping the model
/// it learnt (the core's `Tracker::relocate`); `RBT_ERR_TRACKER_KIND` for the
/// correlation-filter tracker, whose models learn a new box afresh (`rbt_cf_start`).
///
/// # Safety
/// As `rbt_start`.
#[no_mangle]
pub unsafe extern "C" fn rbt_relocate(
    tracker: *mut rbt_tracker,
    frame: *const rbt_image,
    r#box: *const rbt_rect,
) -> rbt_error {
    // SAFETY: as this function's contract.
    let (frame, at) = match unsafe { (self::frame(frame), ellipse(r#box)) } {
        (Ok(frame), Ok(at)) => (frame, at),
        (Err(e), _) | (_, Err(e)) => return e,
    };
    // SAFETY: as this function's contract.
    unsafe { with_particles(tracker, |t| code(t.relocate(&frame, at))) }
}

/// Tracks one frame and writes the estimate to `estimate` (the core's `Tracker::step`;
/// an unstarted tracker's estimate is `RBT_STATUS_LOST`, confidence 0, unchanged).
///
/// # Safety
/// As `rbt_start`; `estimate` is null or points to a writable `rbt_estimate`.
#[no_mangle]
pub unsafe extern "C" fn rbt_step(
    tracker: *mut rbt_tracker,
    frame: *const rbt_image,
    estimate: *mut rbt_estimate,
) -> rbt_error {
    if estimate.is_null() {
        return RBT_ERR_NULL;
    }
    // SAFETY: as this function's contract.
    let frame = match unsafe { self::frame(frame) } {
        Ok(frame) => frame,
        Err(e) => return e,
    };
    // SAFETY: as this function's contract.
    unsafe {
        with_tracker(tracker, |t| {
            let e = match t {
                Engine::Particles(t) => t.step(&frame),
                Engine::Correlation(t) => t.step(&frame),
            };
            put(estimate, e.into())
        })
    }
}

/// Writes the tracker's last estimate (its box before any step) to `estimate`.
///
/// # Safety
/// As `rbt_step`.
#[no_mangle]
pub unsafe extern "C" fn rbt_estimate_of(
    tracker: *mut rbt_tracker,
    estimate: *mut rbt_estimate,
) -> rbt_error {
    // SAFETY: as this function's contract.
    unsafe {
        with_tracker(tracker, |t| {
            let e = match t {
                Engine::Particles(t) => t.estimate(),
                Engine::Correlation(t) => t.estimate(),
            };
            put(estimate, e.into())
        })
    }
}

/// How the picture moved since the last frame: the scene point seen at `p` is next seen
/// at `centre + zoom (p - centre) + (dx, dy)`, px, Q16.16.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct rbt_motion {
    /// Horizontal shift, px, Q16.16 (a camera panning right moves the picture left).
    pub dx: rbt_q16,
    /// Vertical shift, px, Q16.16.
    pub dy: rbt_q16,
    /// Zoom factor, Q16.16 (`RBT_Q16_ONE`: none; applied within [1/8, 8]).
    pub zoom: rbt_q16,
    /// Column the zoom keeps in place, px, Q16.16.
    pub centre_x: rbt_q16,
    /// Row the zoom keeps in place, px, Q16.16.
    pub centre_y: rbt_q16,
}

/// Tells the tracker how the picture moved before the next `rbt_step` (the core's
/// `Tracker::camera_moved`).
///
/// # Safety
/// `tracker` as for `rbt_start`; `motion` is null or points to an `rbt_motion`.
#[no_mangle]
pub unsafe extern "C" fn rbt_camera_moved(
    tracker: *mut rbt_tracker,
    motion: *const rbt_motion,
) -> rbt_error {
    // SAFETY: null (refused) or an `rbt_motion` (the caller's promise).
    let Some(m) = (unsafe { motion.as_ref() }) else {
        return RBT_ERR_NULL;
    };
    let q = Q16::from_bits;
    let motion = CameraMotion {
        dx: q(m.dx),
        dy: q(m.dy),
        zoom: q(m.zoom),
        centre_x: q(m.centre_x),
        centre_y: q(m.centre_y),
    };
    // SAFETY: as this function's contract.
    unsafe {
        with_tracker(tracker, |t| {
            match t {
                Engine::Particles(t) => t.camera_moved(&motion),
                Engine::Correlation(t) => t.camera_moved(&motion),
            }
            RBT_OK
        })
    }
}

/// One axis of the pan/tilt controller (`rbtrack::pantilt::AxisConfig`), degrees, Q16.16.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct rbt_pantilt_axis {
    /// Share of the error moved per frame, in [0, 4].
    pub kp: rbt_q16,
    /// Share of the summed error moved per frame, in [0, 4].
    pub ki: rbt_q16,
    /// Share of the error's change moved per frame, in [0, 4].
    pub kd: rbt_q16,
    /// Errors this small count as zero, degrees, `>= 0`.
    pub dead_band: rbt_q16,
    /// Largest move per frame, degrees, `> 0`.
    pub max_rate: rbt_q16,
    /// Smallest command, degrees.
    pub min: rbt_q16,
    /// Largest command, degrees, `>= min`.
    pub max: rbt_q16,
    /// Command at the start, degrees, in `min..=max`.
    pub home: rbt_q16,
}

/// The head and the camera on it (`rbtrack::pantilt::PanTiltConfig`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct rbt_pantilt_config {
    /// Frame width, px, `> 0`.
    pub width: u32,
    /// Frame height, px, `> 0`.
    pub height: u32,
    /// Horizontal field of view, degrees, Q16.16 in (0, 360].
    pub fov_x: rbt_q16,
    /// Vertical field of view, degrees, Q16.16 in (0, 360].
    pub fov_y: rbt_q16,
    /// The pan axis.
    pub pan: rbt_pantilt_axis,
    /// The tilt axis.
    pub tilt: rbt_pantilt_axis,
}

impl From<AxisConfig> for rbt_pantilt_axis {
    fn from(a: AxisConfig) -> Self {
        Self {
            kp: a.kp.to_bits(),
            ki: a.ki.to_bits(),
            kd: a.kd.to_bits(),
            dead_band: a.dead_band.to_bits(),
            max_rate: a.max_rate.to_bits(),
            min: a.min.to_bits(),
            max: a.max.to_bits(),
            home: a.home.to_bits(),
        }
    }
}

impl From<rbt_pantilt_axis> for AxisConfig {
    fn from(a: rbt_pantilt_axis) -> Self {
        let q = Q16::from_bits;
        let mut axis = AxisConfig::new();
        (axis.kp, axis.ki, axis.kd) = (q(a.kp), q(a.ki), q(a.kd));
        (axis.dead_band, axis.max_rate) = (q(a.dead_band), q(a.max_rate));
        (axis.min, axis.max, axis.home) = (q(a.min), q(a.max), q(a.home));
        axis
    }
}

/// Writes the controller's defaults for a `width x height` px camera of `fov_x x fov_y`
/// degrees (Q16.16) to `config`: both axes at `AxisConfig::new` (kp 0.5, ki 0.02, dead
/// band 0.5 degree, at most 5 degrees a frame, -90..=90 degrees, home 0).
///
/// # Safety
/// `config` is null or points to a writable `rbt_pantilt_config`.
#[no_mangle]
pub unsafe extern "C" fn rbt_pantilt_config_default(
    width: u32,
    height: u32,
    fov_x: rbt_q16,
    fov_y: rbt_q16,
    config: *mut rbt_pantilt_config,
) -> rbt_error {
    let c = PanTiltConfig::new(width, height, Q16::from_bits(fov_x), Q16::from_bits(fov_y));
    let out = rbt_pantilt_config {
        width: c.width,
        height: c.height,
        fov_x: c.fov_x.to_bits(),
        fov_y: c.fov_y.to_bits(),
        pan: c.pan.into(),
        tilt: c.tilt.into(),
    };
    // SAFETY: as this function's contract.
    unsafe { put(config, out) }
}

/// 32-bit words of a controller's state.
pub const RBT_PANTILT_WORDS: usize = 26;
const _: () = assert!(
    size_of::<PanTilt>() <= 4 * RBT_PANTILT_WORDS && align_of::<PanTilt>() <= 4,
    "rbt_pantilt must hold a PanTilt"
);

/// A pan/tilt controller: plain memory the caller owns (a static, a local), started by
/// `rbt_pantilt_start`.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct rbt_pantilt {
    /// `"RBT1"` once started.
    pub magic: u32,
    /// The controller's state.
    pub state: [u32; RBT_PANTILT_WORDS],
}

/// The controller in `head`, if started.
///
/// # Safety
/// `head` is null or points to an `rbt_pantilt` used by no other call meanwhile.
unsafe fn pantilt<'a>(head: *mut rbt_pantilt) -> Result<&'a mut PanTilt, rbt_error> {
    // SAFETY: null (refused) or an `rbt_pantilt` (the caller's promise).
    let head = unsafe { head.as_mut() }.ok_or(RBT_ERR_NULL)?;
    if head.magic != MAGIC {
        return Err(RBT_ERR_NOT_A_PANTILT);
    }
    // SAFETY: the magic word says `rbt_pantilt_start` wrote a `PanTilt` at `state`, which
    // holds one (size and alignment checked at compile time).
    Ok(unsafe { &mut *head.state.as_mut_ptr().cast::<PanTilt>() })
}

/// Starts the controller `head` with the head at home (the core's `PanTilt::new`).
///
/// # Safety
/// `head` is null or points to a writable `rbt_pantilt`; `config` is null or points to
/// an `rbt_pantilt_config`.
#[no_mangle]
pub unsafe extern "C" fn rbt_pantilt_start(
    head: *mut rbt_pantilt,
    config: *const rbt_pantilt_config,
) -> rbt_error {
    // SAFETY: null (refused) or the types named (the caller's promise).
    let (Some(head), Some(c)) = (unsafe { head.as_mut() }, unsafe { config.as_ref() }) else {
        return RBT_ERR_NULL;
    };
    let mut config = PanTiltConfig::new(
        c.width,
        c.height,
        Q16::from_bits(c.fov_x),
        Q16::from_bits(c.fov_y),
    );
    (config.pan, config.tilt) = (c.pan.into(), c.tilt.into());
    match PanTilt::new(config) {
        Ok(controller) => {
            // SAFETY: `state` holds a `PanTilt` (size and alignment checked at compile
            // time); it is written, not read.
            unsafe { head.state.as_mut_ptr().cast::<PanTilt>().write(controller) };
            head.magic = MAGIC;
            RBT_OK
        }
        Err(e) => e.into(),
    }
}

/// The head's commands, degrees, Q16.16.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct rbt_command {
    /// Pan angle, positive to the right.
    pub pan: rbt_q16,
    /// Tilt angle, positive down.
    pub tilt: rbt_q16,
}

impl From<Command> for rbt_command {
    fn from(c: Command) -> Self {
        Self {
            pan: c.pan.to_bits(),
            tilt: c.tilt.to_bits(),
        }
    }
}

/// Moves the head's commands after `estimate` (its ellipse and status are read; the head
/// holds while `RBT_STATUS_LOST`) and writes them to `command` (the core's
/// `PanTilt::step`).
///
/// # Safety
/// `head` is null or points to an `rbt_pantilt`; `estimate` is null or points to an
/// `rbt_estimate`; `command` is null or points to a writable `rbt_command`.
#[no_mangle]
pub unsafe extern "C" fn rbt_pantilt_step(
    head: *mut rbt_pantilt,
    estimate: *const rbt_estimate,
    command: *mut rbt_command,
) -> rbt_error {
    // SAFETY: null (refused) or an `rbt_estimate` (the caller's promise).
    let Some(estimate) = (unsafe { estimate.as_ref() }) else {
        return RBT_ERR_NULL;
    };
    if command.is_null() {
        return RBT_ERR_NULL;
    }
    let estimate = match estimate.estimate() {
        Ok(e) => e,
        Err(e) => return e,
    };
    // SAFETY: as this function's contract.
    match unsafe { pantilt(head) } {
        // SAFETY: `command` is non-null and writable (the caller's promise).
        Ok(controller) => unsafe { put(command, controller.step(&estimate).into()) },
        Err(e) => e,
    }
}
