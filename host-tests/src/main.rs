//! `rbtrack`: command-line front end of the host harness.

fn main() {}
