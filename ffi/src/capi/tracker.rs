//! What a placed tracker does: start, reset, relocate, step, its estimate, camera motion.

use super::config::{cf_config, config, rbt_cf_config, rbt_config};
use super::error::code;
use super::estimate::{ellipse, rbt_estimate, rbt_rect};
use super::image::{frame, rbt_image};
use super::memory::{rbt_tracker, with_particles, with_tracker, Engine};
use super::rbt_error::{self, *};
use super::{put, rbt_q16};
use rbtrack::tracker::CameraMotion;
use rbtrack::{Rect, Q16};

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

/// Moves the tracker onto the box `box` of `frame` (say a detector's), keeping what it
/// learnt: a particle filter's model (the core's `Tracker::relocate`), the
/// correlation-filter tracker's filter, colour model and scale filter, the box its new
/// first box (`CfTracker::relocate`; `RBT_ERR_MODEL_SETTINGS` before `rbt_cf_start`).
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
    unsafe {
        with_tracker(tracker, |t| match t {
            Engine::Particles(t) => code(t.relocate(&frame, at)),
            Engine::Correlation(t) => code(t.relocate(&frame, Rect::from(at))),
        })
    }
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
