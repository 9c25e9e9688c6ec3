//! The example firmware's workload and board support.
//!
//! - [`scene`]: the deterministic QVGA RGB565 scene, integer-only.
//! - [`run`]: the trackers' configuration, the run over the scene, the checksum of the
//!   estimates and the tightest pixel-to-bin loop (the pixel-visit bound's unit cost).
//! - [`cf`]: the same for the correlation-filter tracker, with its own checksum.
//! - `board` (Cortex-M only): the SysTick and DWT counters, the SysTick calibration, the
//!   static frame buffer, the stack high-water mark, the examples' exit and panic report,
//!   and the no-panic proof's panic handler.
//!
//! `scene` and `run` build on any target: the host test `host-tests/tests/firmware.rs`
//! runs them on x86 and must print the checksum the firmware prints in QEMU.
#![no_std]

#[cfg(target_os = "none")]
pub mod board;
pub mod cf;
pub mod run;
pub mod scene;
