//! Criterion benchmarks: one tracker step and the primitives it is made of.
//!
//! ```sh
//! cargo bench --bench step                  # everything (about 3 minutes)
//! cargo bench --bench step -- step/qvga     # one group or filter
//! ```
//!
//! - `step/<frame>/<variant>/<N>`: one `Tracker::step` of the colour PF (`pf`) and the RBPF
//!   (`rbpf`) at N = 50, 100, 200, on the firmware's scene as a QVGA RGB565 frame
//!   (`qvga_rgb565`) and as a 1280x720 RGB888 frame (`hd720_rgb888`, 12x the pixels, the
//!   target 12x larger). Each iteration steps a clone of a tracker warmed up over 5 frames;
//!   the clone is not timed. The per-window pixel cap makes the cost follow N, not the
//!   frame or target size.
//! - `primitives/*`: on the target's window of the QVGA frame: `Histogram::fill`,
//!   `Histogram::bhattacharyya`, `GradientCue::evaluate`, resampling of 100 weights
//!   (normalise, systematic draw), the shared Kalman covariance's predict / gain / update
//!   and the size mean update of 100 particles.
//!
//! Deterministic instruction counts of the same cases: `benches/iai.rs`.

mod common;

use common::{hd_scene, qvga_scene, Scene, BINS};
use criterion::{criterion_group, criterion_main, BatchSize, BenchmarkId, Criterion};
use rbtrack::cue::GradientCue;
use rbtrack::fixed::Q16;
use rbtrack::hist::{Histogram, Model};
use rbtrack::image::{PixelFormat, Rgb8x8x8};
use rbtrack::kalman::{BlockNoise, SharedCovariance, Size, Sym2};
use rbtrack::resample::{normalise, resample, Scheme};
use rbtrack::rng::Rng;
use rbtrack::tracker::Variant;
use std::hint::black_box;
use std::time::Duration;

fn step_case<P: PixelFormat, const N: usize>(
    c: &mut Criterion,
    frame: &str,
    scene: &Scene<P>,
    variant: Variant,
) {
    let name = match variant {
        Variant::ColourPf => "pf",
        Variant::Rbpf => "rbpf",
    };
    let tracker = scene.tracker::<N>(variant);
    let view = scene.measured();
    c.bench_with_input(
        BenchmarkId::new(format!("step/{frame}/{name}"), N),
        &view,
        |b, view| {
            b.iter_batched_ref(
                || tracker.clone(),
                |t| black_box(t.step(view)),
                BatchSize::SmallInput,
            )
        },
    );
}

fn steps(c: &mut Criterion) {
    let qvga = qvga_scene();
    let hd = hd_scene();
    for variant in [Variant::ColourPf, Variant::Rbpf] {
        step_case::<_, 50>(c, "qvga_rgb565", &qvga, variant);
        step_case::<_, 100>(c, "qvga_rgb565", &qvga, variant);
        step_case::<_, 200>(c, "qvga_rgb565", &qvga, variant);
        step_case::<_, 50>(c, "hd720_rgb888", &hd, variant);
        step_case::<_, 100>(c, "hd720_rgb888", &hd, variant);
        step_case::<_, 200>(c, "hd720_rgb888", &hd, variant);
    }
}

fn primitives(c: &mut Criterion) {
    let scene = qvga_scene();
    let img = scene.measured();
    let e = common::truth_qvga(common::FRAME + 1);
    let config = common::config(Variant::Rbpf);
    let cap = config.pixels_per_window;

    let mut hist = Histogram::<BINS>::new();
    c.bench_function("primitives/histogram_fill", |b| {
        b.iter(|| black_box(hist.fill::<Rgb8x8x8, _>(black_box(&img), black_box(&e), cap)))
    });
    hist.fill::<Rgb8x8x8, _>(&img, &e, cap);
    let model = Model::from_histogram(&hist);
    c.bench_function("primitives/bhattacharyya", |b| {
        b.iter(|| black_box(black_box(&hist).bhattacharyya(black_box(&model))))
    });

    let cue = GradientCue::new(&config.gradient()).expect("default cue configuration");
    c.bench_function("primitives/gradient_cue", |b| {
        b.iter(|| black_box(cue.evaluate(black_box(&img), black_box(&e))))
    });

    let mut rng = Rng::new(3);
    let weights: Vec<u32> = (0..100).map(|_| rng.next_u32() >> 12).collect();
    c.bench_function("primitives/normalise_100", |b| {
        b.iter_batched_ref(
            || weights.clone(),
            |w| black_box(normalise(w)),
            BatchSize::SmallInput,
        )
    });
    let mut out = [0u16; 100];
    c.bench_function("primitives/resample_systematic_100", |b| {
        b.iter_batched_ref(
            || weights.clone(),
            |w| black_box(resample(Scheme::Systematic, w, &mut rng, &mut out)),
            BatchSize::SmallInput,
        )
    });

    let q = Q16::from_f64(0.25);
    let r = Q16::from_int(4);
    let p0 = Sym2::diagonal(r, q);
    let cov =
        SharedCovariance::new(p0, p0, BlockNoise::diagonal([q; 4], [r, r])).expect("valid noise");
    c.bench_function("primitives/kalman_shared_predict_update", |b| {
        b.iter_batched_ref(
            || cov,
            |k| {
                k.predict(Q16::ONE);
                let g = k.gain();
                k.update_cov();
                black_box(g)
            },
            BatchSize::SmallInput,
        )
    });
    let gain = cov.gain();
    let sizes: Vec<Size> = (0..100)
        .map(|i| Size::at_rest(Q16::from_int(9), Q16::from_int(20 + i % 7)))
        .collect();
    c.bench_function("primitives/kalman_update_mean_100", |b| {
        b.iter_batched_ref(
            || sizes.clone(),
            |m| {
                for size in m.iter_mut() {
                    gain.update_mean(size, Q16::from_int(10), Q16::from_int(22));
                }
            },
            BatchSize::SmallInput,
        )
    });
}

fn config() -> Criterion {
    Criterion::default()
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(3))
        .configure_from_args()
}

criterion_group! {
    name = benches;
    config = config();
    targets = steps, primitives
}
criterion_main!(benches);
