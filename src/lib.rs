//! A `no_std`, allocation-free, integer-only visual object tracker core for microcontroller
//! camera boards: three trackers, each a fixed-size value stepped once per frame, with
//! bounded work, no heap and no panic path.
//!
//! - The correlation-filter tracker, [`CfTracker`] ([`RgbCfTracker`] at its defaults), the
//!   most accurate and the default choice: a correlation filter on luma and gradient
//!   features, a colour model and a scale filter (Staple class), which searches around
//!   where it last saw the target while it is lost.
//! - The Rao-Blackwellised particle filter (RBPF) and the colour particle filter, one
//!   [`Tracker`] with a [`Variant`] switch: cheaper a frame, colour cues (and boundary
//!   gradients, RBPF) weighing particles, the RBPF's sizes by a Kalman filter.
//!
//! Start a tracker on the target's box in the first frame, then hand it each frame:
//!
//! ```
//! use rbtrack::{CfConfig, Gray8, ImageView, Rect, RgbCfTracker, Status};
//!
//! // A bright 20x20 square on a dark 64x48 grey frame, moving right 1 px a frame.
//! let frame_at = |x0: usize| {
//!     let mut buf = vec![40u8; 64 * 48];
//!     for y in 14..34 {
//!         buf[y * 64 + x0..y * 64 + x0 + 20].fill(220);
//!     }
//!     buf
//! };
//! let first = frame_at(10);
//! let view = ImageView::<Gray8>::new(&first, 64, 48, 64)?;
//! let mut tracker = RgbCfTracker::new(CfConfig::default(), &view, Rect::new(10, 14, 20, 20))?;
//! for x0 in 11..30 {
//!     let buf = frame_at(x0);
//!     let estimate = tracker.step(&ImageView::<Gray8>::new(&buf, 64, 48, 64)?);
//!     assert_eq!(estimate.status, Status::Tracking);
//! }
//! let (x, _, w, _) = tracker.estimate().rect().px();
//! assert!((x - 29).abs() <= 2 && (w - 20).abs() <= 4, "x {x}, w {w}");
//! # Ok::<(), rbtrack::Error>(())
//! ```
//!
//! A particle filter starts the same way, with its configuration and particle count:
//! `RgbTracker::<50>::new(Config::new(Variant::Rbpf), &view, rect)`. On a board, each
//! tracker is built `unstarted()` in a `static` and started in place: they are tens of
//! kilobytes.
//!
//! The crate's `README.md` has the key figures and a firmware quick start; `docs/` in its
//! repository has the design, accuracy, performance, firmware and guarantees pages.
//!
//! # Layers, from the bottom
//! Each module uses only those listed above it. The modules a user needs are [`tracker`],
//! [`image`], [`rect`], [`window`], [`fixed`] and [`profile`]; the others are the
//! trackers' building blocks, public for the tests and the host harness and hidden from
//! these pages.
//!
//! Arithmetic:
//! - [`fixed`]: the Q16.16 number type, saturating, and the integer division and square
//!   roots of the per-frame path.
//! - `trig` (private): cosine and sine of whole fractions of a turn, integer only.
//! - [`fft`]: radix-2 FFTs, 1-D and 2-D, of Q31 complex samples, block floating point.
//! - [`rng`]: seeded Xoshiro128++ draws, uniform and standard normal, without floats.
//!
//! Frames:
//! - [`image`]: [`image::ImageView`], a checked borrowed frame, its pixel formats and
//!   colour bins; every read of frame memory goes through it.
//! - [`window`]: elliptical windows: the pixels of an ellipse on a sampling lattice, row
//!   by row, clipped to the frame, with their Epanechnikov kernel weights and a cap on how
//!   many are visited.
//! - [`rect`]: boxes in pixels, as detectors and datasets give them, and their ellipses.
//!
//! Cues:
//! - [`hist`]: kernel-weighted colour histograms, target models and the Bhattacharyya
//!   coefficient.
//! - [`colour`]: the target's colour model against its surroundings (background
//!   weighting, halves, the object probability of each colour).
//! - [`map`]: the object-probability map of a frame region, and the contrast of a box.
//! - [`cue`]: the boundary-gradient cue.
//! - [`likelihood`]: cue costs to likelihoods, `exp(-cost)` by table.
//!
//! Estimation:
//! - [`resample`]: effective sample size and four resampling schemes.
//! - [`kalman`]: the Kalman filter of the particles' sizes, one covariance for all.
//! - [`ground`]: the ground plane (half-height against row) learnt online.
//! - [`profile`]: the cycle-counter hook and the per-stage counts of a step.
//!
//! The trackers:
//! - [`cf`]: the correlation-filter tracker's parts: per-cell features of a resampled
//!   region, the translation filter, the colour map and the scale filter.
//! - [`tracker`]: the three trackers, the correlation-filter tracker and the colour and
//!   Rao-Blackwellised particle filters, configured once and stepped one frame at a time.
//! - [`Error`]: a frame's or a tracker's refusal, for `?` in code that does both.
//!
//! Output:
//! - [`pantilt`]: pan and tilt commands that keep the target in the middle of the picture.
#![no_std]
#![forbid(unsafe_code)]

#[cfg(test)]
extern crate std;

// Arithmetic.
#[doc(hidden)]
pub mod fft;
pub mod fixed;
#[doc(hidden)]
pub mod rng;
mod trig;

// Frames.
pub mod image;
pub mod rect;
pub mod window;

// Cues.
#[doc(hidden)]
pub mod cf;
#[doc(hidden)]
pub mod colour;
#[doc(hidden)]
pub mod cue;
#[doc(hidden)]
pub mod hist;
#[doc(hidden)]
pub mod likelihood;
#[doc(hidden)]
pub mod map;

// Estimation.
#[doc(hidden)]
pub mod ground;
#[doc(hidden)]
pub mod kalman;
pub mod profile;
#[doc(hidden)]
pub mod resample;

// The trackers.
pub mod tracker;

// Output.
pub mod pantilt;

mod error;

pub use error::Error;
pub use fixed::Q16;
pub use image::{
    Bgr888, Binning, Gray8, ImageError, ImageView, Luma64, PixelFormat, Rgb565Be, Rgb565Le, Rgb888,
    Rgb8x8x4, Rgb8x8x8, Uyvy, Yuv8x8x4, Yuyv,
};
pub use rect::Rect;
pub use tracker::{
    CameraMotion, CfConfig, CfTracker, Config, ConfigError, Estimate, LumaTracker, Rgb256Tracker,
    RgbCfTracker, RgbTracker, Status, TargetModel, Tracker, Variant, YuvTracker,
};
pub use window::Ellipse;

/// The README's Rust examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
