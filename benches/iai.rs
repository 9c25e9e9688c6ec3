//! Deterministic instruction counts (Valgrind's Callgrind through iai-callgrind) of one
//! tracker step and of the primitives, on the same frames as `benches/step.rs`.
//!
//! ```sh
//! cargo install iai-callgrind-runner --version 0.16.1   # once; same version as the crate
//! cargo bench --bench iai
//! ```
//!
//! Counts repeat exactly from run to run on one machine and compiler, so a regression of
//! a fraction of a per cent shows; iai-callgrind prints the change against the last run.
//! x86-64 instructions, not Cortex-M ones: for those run the example firmware in QEMU.

// The iai-callgrind macros generate public items without docs.
#![allow(missing_docs)]

mod common;

use common::{hd_scene, qvga_scene, Scene, BINS};
use iai_callgrind::{library_benchmark, library_benchmark_group, main};
use rbtrack::cue::GradientCue;
use rbtrack::fixed::Q16;
use rbtrack::hist::{Histogram, Model};
use rbtrack::image::{PixelFormat, Rgb565Le, Rgb888, Rgb8x8x8};
use rbtrack::kalman::{BlockNoise, SharedCovariance, SharedGain, Size, Sym2};
use rbtrack::resample::{normalise, resample, Normalised, Scheme};
use rbtrack::rng::Rng;
use rbtrack::tracker::{Estimate, Tracker, Variant};
use rbtrack::window::Ellipse;
use std::hint::black_box;

/// A warmed-up tracker and the scene whose next frame it steps on.
struct Case<P: PixelFormat, const N: usize> {
    tracker: Tracker<Rgb8x8x8, N, BINS>,
    scene: Scene<P>,
}

impl<P: PixelFormat, const N: usize> Case<P, N> {
    fn step(&mut self) -> Estimate {
        self.tracker.step(&self.scene.measured())
    }
}

// Set-ups leak what they build, so that freeing the frames is not counted.

fn qvga<const N: usize>(variant: Variant) -> &'static mut Case<Rgb565Le, N> {
    let scene = qvga_scene();
    Box::leak(Box::new(Case {
        tracker: scene.tracker::<N>(variant),
        scene,
    }))
}

fn hd<const N: usize>(variant: Variant) -> &'static mut Case<Rgb888, N> {
    let scene = hd_scene();
    Box::leak(Box::new(Case {
        tracker: scene.tracker::<N>(variant),
        scene,
    }))
}

#[library_benchmark]
#[bench::pf(qvga(Variant::ColourPf))]
#[bench::rbpf(qvga(Variant::Rbpf))]
fn step_qvga_n50(case: &'static mut Case<Rgb565Le, 50>) -> Estimate {
    black_box(case.step())
}

#[library_benchmark]
#[bench::pf(qvga(Variant::ColourPf))]
#[bench::rbpf(qvga(Variant::Rbpf))]
fn step_qvga_n100(case: &'static mut Case<Rgb565Le, 100>) -> Estimate {
    black_box(case.step())
}

#[library_benchmark]
#[bench::pf(qvga(Variant::ColourPf))]
#[bench::rbpf(qvga(Variant::Rbpf))]
fn step_qvga_n200(case: &'static mut Case<Rgb565Le, 200>) -> Estimate {
    black_box(case.step())
}

#[library_benchmark]
#[bench::pf(hd(Variant::ColourPf))]
#[bench::rbpf(hd(Variant::Rbpf))]
fn step_hd720_n100(case: &'static mut Case<Rgb888, 100>) -> Estimate {
    black_box(case.step())
}

/// The QVGA frame the steps run on and the target's window in it.
struct Window {
    scene: Scene<Rgb565Le>,
    ellipse: Ellipse,
    hist: Histogram<BINS>,
    model: Model<BINS>,
    cue: GradientCue,
}

fn window() -> &'static mut Window {
    let scene = qvga_scene();
    let ellipse = common::truth_qvga(common::FRAME + 1);
    let config = common::config(Variant::Rbpf);
    let mut hist = Histogram::new();
    hist.fill::<Rgb8x8x8, _>(&scene.measured(), &ellipse, config.pixels_per_window);
    let model = Model::from_histogram(&hist);
    Box::leak(Box::new(Window {
        scene,
        ellipse,
        hist,
        model,
        cue: GradientCue::new(&config.gradient()).expect("default cue configuration"),
    }))
}

#[library_benchmark]
#[bench::target(window())]
fn histogram_fill(w: &'static mut Window) -> u32 {
    let cap = common::config(Variant::Rbpf).pixels_per_window;
    black_box(
        w.hist
            .fill::<Rgb8x8x8, _>(&w.scene.measured(), &w.ellipse, cap),
    )
}

#[library_benchmark]
#[bench::target(window())]
fn bhattacharyya(w: &'static mut Window) -> Q16 {
    black_box(w.hist.bhattacharyya(&w.model))
}

#[library_benchmark]
#[bench::target(window())]
fn gradient_cue(w: &'static mut Window) -> Q16 {
    black_box(w.cue.evaluate(&w.scene.measured(), &w.ellipse))
}

/// 100 unnormalised weights (as the tracker's weigh stage leaves them), a random source
/// and the index output.
struct Weights {
    weights: [u32; 100],
    rng: Rng,
    out: [u16; 100],
}

fn weights() -> &'static mut Weights {
    let mut rng = Rng::new(3);
    let weights = core::array::from_fn(|_| rng.next_u32() >> 12);
    Box::leak(Box::new(Weights {
        weights,
        rng,
        out: [0; 100],
    }))
}

#[library_benchmark]
#[bench::n100(weights())]
fn normalise_weights(w: &'static mut Weights) -> Normalised {
    black_box(normalise(&mut w.weights))
}

#[library_benchmark]
#[bench::n100(weights())]
fn resample_systematic(w: &'static mut Weights) -> bool {
    black_box(resample(Scheme::Systematic, &mut w.weights, &mut w.rng, &mut w.out).is_ok())
}

/// The shared Kalman covariance of the default configuration and 100 particle sizes.
struct Kalman {
    cov: SharedCovariance,
    sizes: [Size; 100],
}

fn kalman() -> &'static mut Kalman {
    let config = common::config(Variant::Rbpf);
    let (q, r) = (config.kalman_q, config.kalman_r);
    let p0 = Sym2::diagonal(r, q);
    let cov =
        SharedCovariance::new(p0, p0, BlockNoise::diagonal([q; 4], [r, r])).expect("valid noise");
    let sizes =
        core::array::from_fn(|i| Size::at_rest(Q16::from_int(9), Q16::from_int(20 + i as i32 % 7)));
    Box::leak(Box::new(Kalman { cov, sizes }))
}

// One frame of the RBPF's Kalman work: the shared covariance's prediction, gain and
// update, and the mean update of 100 particle sizes.
#[library_benchmark]
#[bench::n100(kalman())]
fn kalman_predict_update(k: &'static mut Kalman) -> SharedGain {
    k.cov.predict(Q16::ONE);
    black_box(
        k.cov
            .update(&mut k.sizes, Q16::from_int(10), Q16::from_int(22)),
    )
}

library_benchmark_group!(
    name = steps;
    benchmarks = step_qvga_n50, step_qvga_n100, step_qvga_n200, step_hd720_n100
);
library_benchmark_group!(
    name = primitives;
    benchmarks = histogram_fill, bhattacharyya, gradient_cue, normalise_weights,
        resample_systematic, kalman_predict_update
);
main!(library_benchmark_groups = steps, primitives);
