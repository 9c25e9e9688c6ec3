//! The rbtrack core behind a C API, for C firmware and host programs, and the safe Rust
//! layer under it, which the Python module (`python/`) uses too.
//!
//! - [`capi`]: the C functions and types; `include/rbtrack.h` is their header, generated
//!   by cbindgen (`tests/header.rs` fails when it is stale). The library is
//!   `librbtrack_ffi.a`: `cargo build --release -p rbtrack-ffi` for the host,
//!   `--target thumbv7em-none-eabihf` (or any target the core builds for) for firmware.
//! - [`Frame`]: a frame of a [`Format`] chosen at run time.
//! - [`Track`]: a particle filter of any size and binning behind one interface;
//!   [`CfTrack`]: the correlation-filter tracker of any grid and scales behind another.
//!
//! `no_std`, no allocation. On bare-metal targets the library's panic handler calls a
//! function defined nowhere (`rbtrack_panic_path_is_reachable`), so a program links only
//! if no panic is reachable from the C functions it calls; CI links one that calls every
//! one of them (docs/c.md, "No panic"). On hosted targets the library links `std` for its
//! panic runtime alone.
#![no_std]

#[cfg(not(target_os = "none"))]
extern crate std;

pub mod capi;
mod frame;
mod track;

pub use frame::{Format, Frame};
pub use track::{ellipse_of_box, CfTrack, Track};

/// The no-panic proof's panic handler: it calls a function defined nowhere, so a program
/// in which a call to it survives optimisation does not link.
#[cfg(target_os = "none")]
#[panic_handler]
fn panic(_: &core::panic::PanicInfo<'_>) -> ! {
    extern "C" {
        fn rbtrack_panic_path_is_reachable() -> !;
    }
    // SAFETY: a program in which this call survives fails to link (undefined symbol), so
    // it never runs.
    #[allow(unsafe_code)]
    unsafe {
        rbtrack_panic_path_is_reachable()
    }
}
