//! Bounded work: a step never reads more than
//! `tracker::max_pixels_per_step(N, pixels_per_window)` pixels (`Tracker::pixels_visited`;
//! the tracker module doc, "Bounded work"), whatever the target size (as large as the
//! frame, and larger), the frames and the configuration.

use proptest::prelude::*;
use rbtrack::fixed::Q16;
use rbtrack::image::{ImageView, Rgb888, Rgb8x8x8};
use rbtrack::resample::Scheme;
use rbtrack::rng::Rng;
use rbtrack::tracker::{
    max_pixels_per_step, Config, CueMix, Readout, SizeMeasurement, Tracker, Variant,
};
use rbtrack::window::Ellipse;

/// One random run: configuration, frame size, target and frame contents.
#[derive(Debug, Clone)]
struct WorkCase {
    config: Config,
    width: usize,
    height: usize,
    target: Ellipse,
    frame_seeds: Vec<(u64, u8)>,
}

fn config_case() -> impl Strategy<Value = Config> {
    (
        (
            any::<bool>(),
            any::<u64>(),
            16u32..=65_536,
            0usize..4,
            0usize..4,
        ),
        (
            1u32..=256 << 16,
            0u32..=4 << 16,
            0u32..=64 << 16,
            0u32..=1 << 16,
        ),
        (
            1u32..=1 << 16,
            1u32..=1 << 16,
            0u32..=1 << 16,
            0u32..=1 << 16,
            0u32..=1 << 16,
        ),
        (
            0u32..=1 << 16,
            -4i32 << 16..=4 << 16,
            1u32..=1024 << 16,
            1u32..=1024 << 16,
            1u32..=16,
        ),
        (
            any::<bool>(),
            any::<bool>(),
            any::<bool>(),
            any::<bool>(),
            any::<bool>(),
            any::<bool>(),
        ),
    )
        .prop_map(|(a, b, c, d, e)| {
            let (rbpf, seed, cap, scheme, readout) = a;
            let (pos, rel, vel, keep) = b;
            let (resample_below, uncertain, lost_share, adapt_above, adapt_rate) = c;
            let (redetect, per_row, kq, kr, min_half) = d;
            let (by_likelihood, contrast_cue, split, background, frozen, learn) = e;
            let q = |bits: u32| Q16::from_bits(bits as i32);
            let mut c = Config::new(if rbpf {
                Variant::Rbpf
            } else {
                Variant::ColourPf
            });
            c.seed = seed;
            c.pixels_per_window = cap;
            c.position_noise = q(pos);
            c.relative_position_noise = q(rel);
            c.velocity_noise = q(vel);
            c.velocity_keep = q(keep);
            c.resampling = [
                Scheme::Multinomial,
                Scheme::Systematic,
                Scheme::Stratified,
                Scheme::Residual,
            ][scheme];
            c.readout = [
                Readout::Mean,
                Readout::Best,
                Readout::RobustMean(Q16::from_int(5)),
                Readout::RobustMean(Q16::from_int(500)),
            ][readout];
            c.resample_below = q(resample_below);
            c.uncertain_below = q(uncertain);
            c.lost_below = q(uncertain) * q(lost_share);
            c.adapt_above = q(adapt_above);
            c.adapt_rate = q(adapt_rate);
            c.redetect_share = q(redetect);
            c.scale_per_row = Q16::from_bits(per_row);
            c.kalman_q = q(kq);
            c.kalman_r = q(kr);
            c.min_half_axis = Q16::from_int(min_half as i32);
            c.size_measurement = match by_likelihood {
                true => SizeMeasurement::Likelihood,
                false => SizeMeasurement::Contrast,
            };
            c.contrast_sigma = contrast_cue.then_some(Q16::from_f64(0.2));
            c.split_halves = split;
            c.background_weighting = background;
            c.freeze_size = frozen;
            c.learn_scale_per_row = learn;
            if rbpf && seed % 3 == 0 {
                c.cue_mix = CueMix::Average(Q16::HALF);
            }
            c
        })
}

fn work_case() -> impl Strategy<Value = WorkCase> {
    (
        config_case(),
        8usize..=160,
        8usize..=120,
        (0.0f64..=1.0, 0.0f64..=1.0, 0.0f64..=1.6, 0.0f64..=1.6),
        prop::collection::vec((any::<u64>(), 0u8..4), 1..=6),
    )
        .prop_map(|(config, width, height, (fx, fy, sx, sy), frame_seeds)| {
            let min = config.min_half_axis.to_f64();
            // Half-axes from the smallest allowed to 1.6 times the frame's own.
            let hx = min + sx * (width as f64 / 2.0);
            let hy = min + sy * (height as f64 / 2.0);
            let target = Ellipse::new(
                Q16::from_f64(fx * (width - 1) as f64),
                Q16::from_f64(fy * (height - 1) as f64),
                Q16::from_f64(hx),
                Q16::from_f64(hy),
            );
            WorkCase {
                config,
                width,
                height,
                target,
                frame_seeds,
            }
        })
}

/// An RGB888 frame: noise, flat grey, large colour blocks or black.
fn frame(width: usize, height: usize, seed: u64, kind: u8) -> Vec<u8> {
    let mut rng = Rng::new(seed);
    match kind {
        0 => (0..width * height * 3)
            .map(|_| rng.next_u32() as u8)
            .collect(),
        1 => vec![rng.next_u32() as u8; width * height * 3],
        2 => {
            let palette: Vec<u8> = (0..48).map(|_| rng.next_u32() as u8).collect();
            let cell = 1 + rng.below(16) as usize;
            let mut out = Vec::with_capacity(width * height * 3);
            for y in 0..height {
                for x in 0..width {
                    let i = ((x / cell + 3 * (y / cell)) % 16) * 3;
                    out.extend_from_slice(&palette[i..i + 3]);
                }
            }
            out
        }
        _ => vec![0; width * height * 3],
    }
}

/// Runs the case with `N` particles; returns the largest share of the bound used.
fn run<const N: usize>(case: &WorkCase) -> Result<f64, TestCaseError> {
    let (w, h) = (case.width, case.height);
    let first = frame(w, h, case.frame_seeds[0].0, 2);
    let view = ImageView::<Rgb888>::new(&first, w, h, w).expect("frame");
    let mut tracker = Tracker::<Rgb8x8x8, N, 512>::new(case.config, &view, case.target)
        .map_err(|e| TestCaseError::fail(format!("{e}: {case:?}")))?;
    let bound = max_pixels_per_step(N, case.config.pixels_per_window);
    let mut worst = 0.0f64;
    for &(seed, kind) in &case.frame_seeds {
        let buf = frame(w, h, seed, kind);
        let view = ImageView::<Rgb888>::new(&buf, w, h, w).expect("frame");
        tracker.step(&view);
        let visited = tracker.pixels_visited() as u64;
        prop_assert!(
            visited <= bound,
            "{} > {} pixels: {:?}",
            visited,
            bound,
            case
        );
        worst = worst.max(visited as f64 / bound as f64);
    }
    Ok(worst)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    /// Random configurations (both variants, every read-out and scheme, caps from 16 to
    /// 65536), frame sizes, targets up to 1.6 times the frame, random frames.
    #[test]
    fn pixels_per_step_never_exceed_the_bound(case in work_case(), n in 0usize..3) {
        match n {
            0 => run::<1>(&case)?,
            1 => run::<8>(&case)?,
            _ => run::<50>(&case)?,
        };
    }
}

/// A target the size of the frame (and the largest ellipse the frame allows) with the
/// smallest and largest caps, in the configuration that reads the most (size by
/// likelihood, adapting every frame, the contrast cue): the bound holds and, for a small
/// cap on a big window, is nearly reached (the bound is not loose).
#[test]
fn frame_sized_target() {
    let (w, h) = (320usize, 240usize);
    let mut worst = 0.0f64;
    for variant in [Variant::Rbpf, Variant::ColourPf] {
        for cap in [16u32, 300, 4096, 65_536] {
            for (hx, hy) in [(160.0, 120.0), (319.0, 239.0), (400.0, 400.0)] {
                let mut config = Config::new(variant);
                config.pixels_per_window = cap;
                config.size_measurement = SizeMeasurement::Likelihood;
                config.adapt_rate = Q16::from_f64(0.05);
                config.adapt_above = Q16::ZERO;
                config.contrast_sigma = Some(Q16::from_f64(0.2));
                let target = Ellipse::new(
                    Q16::from_f64(159.5),
                    Q16::from_f64(119.5),
                    Q16::from_f64(hx),
                    Q16::from_f64(hy),
                );
                let first = frame(w, h, 1, 2);
                let view = ImageView::<Rgb888>::new(&first, w, h, w).expect("frame");
                let mut tracker =
                    Tracker::<Rgb8x8x8, 20, 512>::new(config, &view, target).expect("starts");
                let bound = max_pixels_per_step(20, cap);
                for seed in 0..5 {
                    let buf = frame(w, h, seed, (seed % 3) as u8);
                    let view = ImageView::<Rgb888>::new(&buf, w, h, w).expect("frame");
                    tracker.step(&view);
                    let visited = tracker.pixels_visited() as u64;
                    assert!(
                        visited <= bound,
                        "{variant:?} cap {cap} ({hx}, {hy}): {visited} > {bound}"
                    );
                    if cap == 300 {
                        worst = worst.max(visited as f64 / bound as f64);
                    }
                }
            }
        }
    }
    println!("frame-sized targets, cap 300: up to {worst:.3} of the bound");
    assert!(worst > 0.5, "the bound is loose: {worst}");
}
