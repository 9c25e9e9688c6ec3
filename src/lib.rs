#![doc = include_str!("../README.md")]
//!
//! # Layers, from the bottom
//! Each module uses only those listed above it.
//!
//! Arithmetic:
//! - [`fixed`]: the Q16.16 number type, saturating, and the integer division and square
//!   roots of the per-frame path.
//! - `trig` (private): cosine and sine of whole fractions of a turn, integer only.
//! - [`rng`]: seeded Xoshiro128++ draws, uniform and standard normal, without floats.
//!
//! Frames:
//! - [`image`]: [`image::ImageView`], a checked borrowed frame, its pixel formats and
//!   colour bins; every read of frame memory goes through it.
//! - [`window`]: elliptical windows: the pixels of an ellipse on a sampling lattice, row
//!   by row, clipped to the frame, with their Epanechnikov kernel weights and a cap on how
//!   many are visited.
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
//! - [`tracker`]: the colour particle filter and the Rao-Blackwellised particle filter,
//!   configured once and stepped one frame at a time.
#![no_std]
#![forbid(unsafe_code)]

#[cfg(test)]
extern crate std;

// Arithmetic.
pub mod fixed;
pub mod rng;
mod trig;

// Frames.
pub mod image;
pub mod window;

// Cues.
pub mod colour;
pub mod cue;
pub mod hist;
pub mod likelihood;
pub mod map;

// Estimation.
pub mod ground;
pub mod kalman;
pub mod profile;
pub mod resample;

// The trackers.
pub mod tracker;
