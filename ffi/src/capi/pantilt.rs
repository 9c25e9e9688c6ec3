//! The pan/tilt controller: an estimate to the head's commands.

use super::estimate::rbt_estimate;
use super::rbt_error::{self, *};
use super::{put, rbt_q16, MAGIC};
use rbtrack::pantilt::{AxisConfig, Command, PanTilt, PanTiltConfig};
use rbtrack::Q16;

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
