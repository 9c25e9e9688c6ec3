//! Error codes: what every function returns, and their names.

use core::ffi::{c_char, CStr};
use rbt_error::*;
use rbtrack::image::ImageError;
use rbtrack::pantilt::PanTiltError;
use rbtrack::tracker::ConfigError;

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
    /// A target model learnt under other colour settings, or none to keep (the
    /// correlation-filter tracker relocated before `rbt_cf_start`).
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
                c"RBT_ERR_MODEL_SETTINGS: target model learnt under other colour settings, or none"
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
pub(super) fn code<E: Into<rbt_error>>(result: Result<(), E>) -> rbt_error {
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
