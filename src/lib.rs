#![doc = include_str!("../README.md")]
//!
//! # Layers, from the bottom
//! - [`fixed`]: the Q16.16 number type; saturating arithmetic and square root.
//! - `trig` (private): cosine and sine of whole fractions of a turn, integer only.
//! - [`rng`]: seeded Xoshiro128++ draws, uniform and standard normal, without floats.
//! - [`image`]: [`image::ImageView`], a checked borrowed frame, and its pixel formats.
//! - [`window`]: the pixels of an elliptical window, clipped to the frame, with their
//!   Epanechnikov kernel weights and a cap on how many are visited.
//! - [`hist`]: kernel-weighted colour histograms and the Bhattacharyya coefficient.
//! - [`cue`]: the boundary-gradient cue.
//! - [`resample`]: effective sample size and four resampling schemes.
//! - [`kalman`]: the hand-unrolled 4-state, 2-measurement Kalman filter.
//! - [`likelihood`]: cue costs to likelihoods, `exp(-cost)` by table.
//! - [`profile`]: the cycle-counter hook and per-stage cycle counts.
//! - [`tracker`]: the colour particle filter and the Rao-Blackwellised particle filter.
#![no_std]
#![forbid(unsafe_code)]

#[cfg(test)]
extern crate std;

pub mod colour;
pub mod cue;
pub mod fixed;
pub mod ground;
pub mod hist;
pub mod image;
pub mod kalman;
pub mod likelihood;
pub mod map;
pub mod profile;
pub mod resample;
pub mod rng;
pub mod tracker;
mod trig;
pub mod window;
