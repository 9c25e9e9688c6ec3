//! The functions the page calls, over numbers and one frame buffer in the module's memory.
//!
//! A frame: `rb_frame(width, height)` returns where to write its RGBA bytes (the page
//! copies a canvas's `ImageData` there); then `rb_start(...)` on the first frame or
//! `rb_step()` on the next ones, which convert it once and track. `rb_report()` and
//! `rb_report_bits()` point at the last estimate. Errors are negative codes
//! ([`crate::WebError::code`]). The state is one session, kept in a `static`.
#![allow(unsafe_code)] // `#[no_mangle]` exports only: no unsafe block.

use crate::{cf_firmware_checksum, firmware_checksum, Frames, Kind, Session, WebError};
use rbtrack::tracker::{Estimate, Variant};
use std::sync::{Mutex, PoisonError};

/// Values of [`rb_report`]: centre `cx`, `cy`, half-axes `hx`, `hy` (px, 0-based),
/// velocity `vx`, `vy` (px/frame), confidence (0..1), status (0 lost, 1 uncertain, 2
/// tracking), pixels the step read.
pub const REPORT_LEN: usize = 9;

/// Values of [`rb_report_bits`]: the Q16.16 bits of `cx`, `cy`, `hx`, `hy`, `vx`, `vy`
/// and the confidence, for exact read-outs.
pub const REPORT_BITS_LEN: usize = 7;

struct State {
    frames: Frames,
    session: Option<Session>,
    report: [f64; REPORT_LEN],
    bits: [i32; REPORT_BITS_LEN],
}

static STATE: Mutex<State> = Mutex::new(State {
    frames: Frames::new(),
    session: None,
    report: [0.0; REPORT_LEN],
    bits: [0; REPORT_BITS_LEN],
});

fn state() -> std::sync::MutexGuard<'static, State> {
    STATE.lock().unwrap_or_else(PoisonError::into_inner)
}

impl State {
    fn record(&mut self, e: &Estimate, pixels: u32) {
        let el = e.ellipse;
        let q = [el.cx, el.cy, el.hx, el.hy, e.vx, e.vy, e.confidence];
        for (bits, v) in self.bits.iter_mut().zip(q) {
            *bits = v.to_bits();
        }
        for (value, v) in self.report.iter_mut().zip(q) {
            *value = v.to_f64();
        }
        self.report[7] = e.status as u8 as f64;
        self.report[8] = pixels as f64;
    }
}

/// Where to write the RGBA bytes of a `width x height` frame (rows top to bottom, no
/// padding); null for a side of 0 or above 4096 px. The address holds until the next call.
#[no_mangle]
pub extern "C" fn rb_frame(width: u32, height: u32) -> *mut u8 {
    match state().frames.rgba_mut(width, height) {
        Some(buf) => buf.as_mut_ptr(),
        None => std::ptr::null_mut(),
    }
}

/// Starts tracking on the frame written: `tracker` 0 the RBPF, 1 the colour PF, 2 the
/// correlation-filter tracker; `particles` 25, 50, 100 or 200 (particle filters only); the
/// random draws' `seed`; the 0-based box `x, y, w, h`, px. Returns 0, or a negative error
/// code.
#[no_mangle]
pub extern "C" fn rb_start(
    tracker: u32,
    particles: u32,
    seed: u32,
    x: f64,
    y: f64,
    w: f64,
    h: f64,
) -> i32 {
    let kind = match tracker {
        0 => Kind::Particles(Variant::Rbpf, particles as usize),
        2 => Kind::CorrelationFilter,
        _ => Kind::Particles(Variant::ColourPf, particles as usize),
    };
    let state = &mut *state();
    let started = state
        .frames
        .view()
        .map_err(WebError::Frame)
        .and_then(|view| Session::start(kind, seed as u64, &view, (x, y, w, h)));
    match started {
        Ok(session) => {
            state.record(&session.estimate(), 0);
            state.session = Some(session);
            0
        }
        Err(e) => e.code(),
    }
}

/// Tracks the frame written. Returns 0, or a negative error code.
#[no_mangle]
pub extern "C" fn rb_step() -> i32 {
    let state = &mut *state();
    let Some(session) = state.session.as_mut() else {
        return WebError::NotStarted.code();
    };
    let estimate = match state.frames.view() {
        Ok(view) => session.step(&view),
        Err(e) => return WebError::Frame(e).code(),
    };
    let pixels = session.pixels_visited();
    state.record(&estimate, pixels);
    0
}

/// The last estimate: [`REPORT_LEN`] `f64` values.
#[no_mangle]
pub extern "C" fn rb_report() -> *const f64 {
    state().report.as_ptr()
}

/// The last estimate's Q16.16 bits: [`REPORT_BITS_LEN`] `i32` values.
#[no_mangle]
pub extern "C" fn rb_report_bits() -> *const i32 {
    state().bits.as_ptr()
}

/// The firmware scene's checksum ([`firmware_checksum`]), as a 64-bit integer (0 if the
/// run could not start).
#[no_mangle]
pub extern "C" fn rb_firmware_checksum() -> u64 {
    firmware_checksum().unwrap_or(0)
}

/// The correlation-filter firmware's checksum on the same scene ([`cf_firmware_checksum`]),
/// 0 if the run could not start.
#[no_mangle]
pub extern "C" fn rb_cf_firmware_checksum() -> u64 {
    cf_firmware_checksum().unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_abi_tracks_a_frame_written_in_place() {
        assert_eq!(rb_step(), -6, "not started");
        assert!(rb_frame(0, 4).is_null());
        let ptr = rb_frame(64, 48);
        assert!(!ptr.is_null());
        // The page writes through the pointer; here, through the same buffer.
        if let Some(buf) = state().frames.rgba_mut(64, 48) {
            for (i, px) in buf.chunks_exact_mut(4).enumerate() {
                let inside = (20..36).contains(&(i % 64)) && (16..32).contains(&(i / 64));
                px.copy_from_slice(&if inside { [230, 40, 40, 255] } else { [90; 4] });
            }
        }
        assert_eq!(rb_start(1, 30, 1, 20.0, 16.0, 16.0, 16.0), -1);
        assert_eq!(rb_start(1, 50, 1, 20.0, 16.0, 16.0, 16.0), 0);
        assert_eq!(rb_step(), 0);
        let report = state().report;
        assert!((report[0] - 27.5).abs() < 2.0, "{report:?}");
        assert_eq!(report[7], 2.0, "tracking");
        assert!(report[8] > 0.0, "pixels read");
        assert_eq!(state().bits[2] as f64 / 65536.0, report[2]);
    }
}
