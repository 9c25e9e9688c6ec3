//! The C API: `#[repr(C)]` types and `extern "C"` functions over raw pointers, checked
//! before use. The header `include/rbtrack.h` is generated from this module by cbindgen.
//!
//! Every function returns an [`rbt_error`] (`RBT_OK` on success) and writes its results
//! through pointers; a null pointer, a short or misaligned buffer, an unknown pixel
//! format or enum value, or a handle that no `rbt_tracker_place_*` made is an error code,
//! never undefined behaviour. Fixed-point values are Q16.16 ([`rbt_q16`]): the value
//! times 65536.
//!
//! By what they serve: [error codes](mod@error), [camera frames](mod@image), [boxes and
//! estimates](mod@estimate), [the trackers' configurations](mod@config), [trackers placed
//! in memory the caller owns](mod@memory), [what a tracker does](mod@tracker) and [the
//! pan/tilt controller](mod@pantilt).
#![allow(unsafe_code, non_camel_case_types)]

// In the header's order: what the declarations of each need comes before them.
pub mod error;

pub mod image;

pub mod estimate;

pub mod config;

pub mod memory;

pub mod tracker;

pub mod pantilt;

pub use config::*;
pub use error::*;
pub use estimate::*;
pub use image::*;
pub use memory::*;
pub use pantilt::*;
pub use tracker::*;

use rbt_error::*;

/// A Q16.16 fixed-point number: the value times 65536 (`RBT_Q16_ONE` is 1).
pub type rbt_q16 = i32;

/// 1 in Q16.16.
pub const RBT_Q16_ONE: rbt_q16 = 1 << 16;

/// Marks a placed tracker and a started pan/tilt controller: `b"RBT1"`, their first word.
const MAGIC: u32 = u32::from_le_bytes(*b"RBT1");

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
