//! Generates the quantile tables behind `rng::Rng::normal` into `OUT_DIR/normal_table.rs`.
//!
//! `HALF_NORMAL_Q16[i]` is the quantile of |Z| (Z standard normal) at probability `i / 256`,
//! for i in 0..=255, and `HALF_NORMAL_TAIL_Q16[j]` refines the last bin: the quantile at
//! probability `(255 + j / 256) / 256` for j in 0..=255, closed by the value at
//! `1 - 2^-24` (5.33). All in Q16.16.
//!
//! Also `EXP_NEG_Q16[i] = round(65535 * exp(-i / 64))` for i in 0..=1024 into
//! `OUT_DIR/exp_table.rs`, the likelihood table of `likelihood::exp_neg`.

use std::{env, fs, path::Path};

/// P(|Z| > t) for a standard normal Z.
fn half_normal_tail(t: f64) -> f64 {
    libm::erfc(t / std::f64::consts::SQRT_2)
}

/// t such that P(|Z| <= t) = p, by bisection (p in [0, 1)).
fn half_normal_quantile(p: f64) -> f64 {
    let (mut lo, mut hi) = (0.0f64, 40.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if 1.0 - half_normal_tail(mid) < p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

fn q16(v: f64) -> i32 {
    (v * 65536.0).round() as i32
}

fn table(name: &str, values: &[f64]) -> String {
    let body: Vec<String> = values.iter().map(|&v| q16(v).to_string()).collect();
    format!(
        "pub(crate) const {name}: [i32; {}] = [{}];\n",
        values.len(),
        body.join(", ")
    )
}

fn main() {
    let main: Vec<f64> = (0..256)
        .map(|i| half_normal_quantile(i as f64 / 256.0))
        .collect();
    let tail: Vec<f64> = (0..=256)
        .map(|j| {
            if j == 256 {
                half_normal_quantile(1.0 - 1.0 / 16_777_216.0)
            } else {
                half_normal_quantile((255.0 + j as f64 / 256.0) / 256.0)
            }
        })
        .collect();
    let mut out = String::new();
    out += &table("HALF_NORMAL_Q16", &main);
    out += &table("HALF_NORMAL_TAIL_Q16", &tail);
    let path = Path::new(&env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("normal_table.rs");
    fs::write(path, out).expect("OUT_DIR is writable");
    let exp: Vec<String> = (0..=1024)
        .map(|i| ((-(i as f64) / 64.0).exp() * 65535.0).round().to_string())
        .collect();
    let exp_table = format!(
        "pub(crate) const EXP_NEG_Q16: [u16; 1025] = [{}];\n",
        exp.join(", ")
    );
    let exp_path =
        Path::new(&env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("exp_table.rs");
    fs::write(exp_path, exp_table).expect("OUT_DIR is writable");
    println!("cargo:rerun-if-changed=build.rs");
}
