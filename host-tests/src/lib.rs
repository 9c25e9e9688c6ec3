//! Host harness for rbtrack: f64 reference implementations, synthetic scenes, metrics and
//! the `rbtrack` command-line program.

pub mod paper;
