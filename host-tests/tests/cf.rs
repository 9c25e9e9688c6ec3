//! The core's integer correlation-filter tracker against its f64 reference (`cf64` with
//! [`Params::of_core`]): whole runs on the synthetic scenes and single steps on real
//! frames, the same boxes within stated tolerances.

use rbtrack::tracker::{CfConfig, Variant};
use rbtrack_host::cf64::Params;
use rbtrack_host::metrics::BBox;
use rbtrack_host::pixels::Frame;
use rbtrack_host::run::{track, Options, CF_GRID};
use rbtrack_host::scene::{Scene, SceneConfig, Variant as SceneVariant};
use rbtrack_host::sequence::{sequence_names, shared_data_dir, GtOrigin, Sequence};

/// The integer tracker at `config`, and its f64 reference.
fn both(config: CfConfig) -> [Options; 2] {
    let base = Options::new(Variant::Rbpf);
    [
        Options {
            cf: Some(config),
            ..base
        },
        Options {
            cf64: Some(Params::of_core(&config, CF_GRID)),
            ..base
        },
    ]
}

/// Per frame, the distance between the two trackers' centres over the reference box's
/// mean side, and the ratio of their widths.
fn agreement(frames: &[Frame], init: &BBox) -> Vec<(f64, f64)> {
    let [core, reference] = both(CfConfig::default());
    let (a, _) = track(&core, frames, init).expect("starts");
    let (b, _) = track(&reference, frames, init).expect("starts");
    a.iter()
        .zip(&b)
        .map(|(a, b)| {
            let ((ax, ay), (bx, by)) = (a.centre(), b.centre());
            let side = (b.w + b.h) / 2.0;
            ((ax - bx).hypot(ay - by) / side, a.w / b.w)
        })
        .collect()
}

/// The largest centre distance (a share of the side) and width difference (a share) over
/// `per_frame`, printed.
fn worst(name: &str, per_frame: &[(f64, f64)]) -> (f64, f64) {
    let centre = per_frame.iter().map(|p| p.0).fold(0.0, f64::max);
    let width = per_frame
        .iter()
        .map(|p| (p.1 - 1.0).abs())
        .fold(0.0, f64::max);
    println!(
        "{name}: {} frames, centres at most {centre:.3} of a side apart, widths within {width:.3}",
        per_frame.len()
    );
    (centre, width)
}

/// On the synthetic scenes (seeds 1-3), the integer tracker follows its f64 reference:
/// centres within a tenth of the target's side and sizes within 10 %, every frame.
#[test]
fn follows_the_f64_reference_on_the_synthetic_scenes() {
    let mut all = Vec::new();
    for kind in [SceneVariant::Perspective, SceneVariant::BrightnessRamp] {
        for seed in 1..=3 {
            let scene = Scene::new(SceneConfig::new(kind, seed)).expect("scene");
            let frames: Vec<_> = scene.frames().collect();
            let truth = scene.boxes();
            all.push(worst(
                &format!("{kind:?} seed {seed}"),
                &agreement(&frames, &truth[0]),
            ));
        }
    }
    assert!(all.iter().all(|&(c, w)| c <= 0.1 && w <= 0.1), "{all:?}");
}

/// One step from the same start: both trackers started on the ground truth of frame
/// `k - 1` and stepped to frame `k`, for every 10th `k` of every dev sequence (so that the
/// port's error is measured, not the chaos of a long run): centres within 2 % of the
/// side and sizes within 2 % in at least 95 % of the steps, none more than a fifth of a side
/// apart (skipped without ../shared/data).
#[test]
fn one_step_agrees_with_the_f64_reference_on_real_frames() {
    let Some(data) = shared_data_dir() else {
        println!("SKIPPED: no ../shared/data folder with the real sequences");
        return;
    };
    let names = sequence_names(&data);
    let mut steps = Vec::new();
    for name in &names {
        let seq = Sequence::open(data.join(name), GtOrigin::of_shared(name)).expect("opens");
        let frames: Vec<_> = seq.frames().map(|f| f.expect("decodes")).collect();
        let mut per_step = Vec::new();
        for k in (10..frames.len()).step_by(10) {
            let init = &seq.groundtruth[k - 1];
            if init.w < 4.0 || init.h < 4.0 {
                continue;
            }
            per_step.extend(agreement(&frames[k - 1..=k], init).into_iter().skip(1));
        }
        worst(name, &per_step);
        steps.extend(per_step);
    }
    let close = steps
        .iter()
        .filter(|&&(c, w)| c <= 0.02 && (w - 1.0).abs() <= 0.02)
        .count();
    let share = close as f64 / steps.len() as f64;
    let farthest = steps.iter().map(|s| s.0).fold(0.0, f64::max);
    println!(
        "{close} of {} steps agree ({:.1} %), centres at most {farthest:.3} of a side apart",
        steps.len(),
        100.0 * share
    );
    assert!(steps.len() >= 300, "{} steps", steps.len());
    assert!(share >= 0.95 && farthest <= 0.2, "{share} {farthest}");
}
