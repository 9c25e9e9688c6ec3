//! The correlation-filter tracker's parts, in integers: per-cell features of a resampled
//! region ([`features`]), the multi-channel translation filter ([`filter`]) and the
//! scale filter ([`scale`]), the integer port of the host's f64 `cf64` tracker
//! (Staple-class: Bertinetto et al., CVPR 2016; DSST, Danelljan et al., BMVC 2014).

pub mod colour;
pub mod features;
pub mod filter;
pub mod scale;
