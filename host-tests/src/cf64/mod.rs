//! `cf64`: a correlation-filter tracker of the Staple class (Bertinetto et al., CVPR 2016)
//! in f64, on the host: the design the microcontroller tracker ports, and the reference
//! it is held to.
//!
//! Per frame ([`tracker`]):
//! 1. the search region (the target plus the mean of its sides each way), centred `lead`
//!    of the smoothed velocity ahead of the last position, is resampled to a square patch
//!    of `grid x grid` cells ([`image`]; with `luma_gradient`, the frame's 8-bit luma as
//!    the core reads it);
//! 2. each cell gets fHOG channels and its mean grey ([`fhog`]), under a cosine window;
//! 3. the multi-channel correlation filter answers with a response over the grid
//!    ([`filter`], transforms by [`fft`]);
//! 4. the colour model (object against surroundings, [`colour`]) gives the mean object
//!    probability of a target-sized box at each cell, from an integral image of the
//!    region's colour samples (the frame pixels nearest their centres);
//! 5. the two merge (`(1 - merge) filter + merge colour`) over the moves that keep the
//!    target box inside the region, each axis on its own; the peak, refined between cells,
//!    is the move and its height the confidence;
//! 6. the scale filter (DSST, [`scale`]) finds the size at the new position, applied when
//!    the confidence is at least `scale_above`;
//! 7. if the confidence clears `learn_above`, all three models learn the frame; while it is
//!    below `lost_below` the target is lost (until it reaches `uncertain_below` again),
//!    and the tracker may coast on its last
//!    velocity and search further regions (`coast`, `redetect`).
//!
//! Optionally, particles ([`particles`]) weigh hypotheses by the merged response instead
//! of taking its peak. Every setting is in [`Params`] (`rbtrack --set cf.FIELD=VALUE`);
//! [`cost`] counts what a configuration costs a frame on a Cortex-M4. docs/design.md
//! explains the choices, docs/accuracy.md measures them.

pub mod colour;
pub mod cost;
pub mod fft;
pub mod fhog;
pub mod filter;
pub mod image;
pub mod params;
pub mod particles;
pub mod scale;
pub mod tracker;

pub use params::Params;
pub use tracker::{Output, Tracker};
