//! Host harness for rbtrack: f64 reference implementations, synthetic scenes, metrics and
//! the `rbtrack` command-line program.

pub mod calibrate;
pub mod camera;
pub mod cf64;
pub mod cli;
pub mod config_fields;
pub mod draw;
pub mod faults;
pub mod fields;
pub mod follow;
pub mod loss;
pub mod metrics;
pub mod paper;
pub mod pixels;
pub mod recovery;
pub mod reference;
pub mod run;
pub mod scene;
pub mod sequence;
