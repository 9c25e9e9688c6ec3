//! The core's integer correlation-filter tracker against its f64 reference (`cf64` with
//! [`Params::of_core`]): frame by frame on the synthetic scenes and on real frames, the
//! same boxes within a stated tolerance.

use rbtrack::tracker::{CfConfig, Variant};
use rbtrack_host::cf64::Params;
use rbtrack_host::metrics::BBox;
use rbtrack_host::pixels::Frame;
use rbtrack_host::run::{track, Options};
use rbtrack_host::scene::{Scene, SceneConfig, Variant as SceneVariant};
use rbtrack_host::sequence::{shared_data_dir, GtOrigin, Sequence};

/// The integer tracker at `config`, and its f64 reference.
fn both(config: CfConfig) -> [Options; 2] {
    let base = Options::new(Variant::Rbpf);
    [
        Options {
            cf: Some(config),
            ..base
        },
        Options {
            cf64: Some(Params::of_core(&config)),
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

/// Checks that the trackers agree on the first `frames` frames: centres within
/// `centre` of the mean side, widths within `width` of each other.
fn assert_agree(name: &str, per_frame: &[(f64, f64)], centre: f64, width: f64) {
    let worst_centre = per_frame.iter().map(|p| p.0).fold(0.0, f64::max);
    let worst_width = per_frame
        .iter()
        .map(|p| (p.1 - 1.0).abs())
        .fold(0.0, f64::max);
    println!(
        "{name}: {} frames, centres at most {worst_centre:.3} of a side apart, widths within {worst_width:.3}",
        per_frame.len()
    );
    assert!(worst_centre <= centre, "{name}: centre {worst_centre}");
    assert!(worst_width <= width, "{name}: width {worst_width}");
}

/// On the synthetic scenes (seeds 1-3), the integer tracker follows its f64 reference:
/// centres within a tenth of the target's side, sizes within 5 %, every frame.
#[test]
fn follows_the_f64_reference_on_the_synthetic_scenes() {
    for kind in [SceneVariant::Perspective, SceneVariant::BrightnessRamp] {
        for seed in 1..=3 {
            let scene = Scene::new(SceneConfig::new(kind, seed)).expect("scene");
            let frames: Vec<_> = scene.frames().collect();
            let truth = scene.boxes();
            let per_frame = agreement(&frames, &truth[0]);
            assert_agree(&format!("{kind:?} seed {seed}"), &per_frame, 0.1, 0.05);
        }
    }
}

/// On the first 60 frames of every dev sequence, the same within a fifth of the side and
/// 10 % of the size (skipped without ../shared/data).
#[test]
fn follows_the_f64_reference_on_real_frames() {
    let Some(data) = shared_data_dir() else {
        println!("SKIPPED: no ../shared/data folder with the real sequences");
        return;
    };
    let mut names: Vec<String> = std::fs::read_dir(&data)
        .expect("data folder")
        .filter_map(|e| e.ok())
        .filter(|e| e.path().join("img").is_dir())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    for name in &names {
        let seq = Sequence::open(data.join(name), GtOrigin::of_shared(name)).expect("opens");
        let frames: Vec<_> = seq
            .frames()
            .take(60)
            .map(|f| f.expect("decodes"))
            .collect();
        let init = seq.init_box().expect("ground truth");
        assert_agree(name, &agreement(&frames, &init), 0.2, 0.1);
    }
}
