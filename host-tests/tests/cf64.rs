//! The f64 correlation-filter tracker (`cf64`) on the synthetic scenes and the real
//! sequences.

use rbtrack::tracker::Variant;
use rbtrack_host::cf64::Params;
use rbtrack_host::metrics::Evaluation;
use rbtrack_host::recovery::{recovery, Recovery};
use rbtrack_host::run::{track, Options};
use rbtrack_host::scene::{Scene, SceneConfig, Variant as SceneVariant};
use rbtrack_host::sequence::{sequence_names, shared_data_dir, GtOrigin, Sequence};

fn options(params: Params) -> Options {
    Options {
        cf64: Some(params),
        cf: None,
        ..Options::new(Variant::Rbpf)
    }
}

fn scene(kind: SceneVariant, seed: u64) -> Scene {
    Scene::new(SceneConfig::new(kind, seed)).expect("scene")
}

fn evaluate(kind: SceneVariant, seed: u64, params: Params) -> Evaluation {
    let s = scene(kind, seed);
    let frames: Vec<_> = s.frames().collect();
    let truth = s.boxes();
    let (boxes, _) = track(&options(params), &frames, &truth[0]).expect("starts");
    Evaluation::new(&truth, &boxes)
}

/// The perspective scene's walker grows about 2.5x: the scale filter follows him (mean IoU
/// at least 0.8, every frame above 0.5), and the brightness ramp does not move it, over
/// seeds 1-3.
#[test]
fn follows_growth_and_brightness() {
    for kind in [SceneVariant::Perspective, SceneVariant::BrightnessRamp] {
        for seed in 1..=3 {
            let e = evaluate(kind, seed, Params::default());
            println!(
                "{kind:?} seed {seed}: success {:.3} IoU {:.3}",
                e.success_rate, e.mean_iou
            );
            assert!(
                e.success_rate == 1.0 && e.mean_iou >= 0.8,
                "{kind:?} seed {seed}"
            );
        }
    }
}

fn reacquisition(kind: SceneVariant, seed: u64, params: Params) -> Recovery {
    recovery(&scene(kind, seed), &options(params)).expect("starts")
}

/// Behind the occluder the confidence falls: the defaults report `Lost` in most hidden
/// frames (pooled over seeds 1-3) and, with re-detection and coasting, find the walker
/// again within 10 frames of him being fully visible on at least 2 of seeds 1-3 (the
/// defaults on none), `Lost` in at least three quarters of the frames he is hidden.
#[test]
fn occlusion_is_lost_and_the_target_found_again() {
    let (mut hidden, mut lost) = (0, 0);
    for seed in 1..=3 {
        let r = reacquisition(SceneVariant::Occlusion, seed, Params::default());
        println!("defaults, seed {seed}: {r:?}");
        hidden += r.hidden;
        lost += r.lost_while_hidden;
        assert!(!r.within(10), "seed {seed}: the defaults found it again");
    }
    assert!(lost * 2 >= hidden, "lost {lost} of {hidden}");
    let searching = Params {
        redetect: 2,
        coast: true,
        ..Params::default()
    };
    let mut found = 0;
    for seed in 1..=3 {
        let r = reacquisition(SceneVariant::Occlusion, seed, searching);
        println!("re-detection and coasting, seed {seed}: {r:?}");
        found += usize::from(r.within(10));
        assert!(r.lost_while_hidden * 4 >= r.hidden * 3, "seed {seed}");
    }
    assert!(found >= 2, "found again on {found} of 3 seeds");
}

/// The dev set from the first box (`rbtrack eval ../shared/data --tracker cf64`): mean
/// success AUC at least 0.62 at the defaults. No sequence's single run is held to a floor:
/// a run is chaotic (`TUDCampus_id5` scores under 0.2 or over 0.7 from starts a pixel
/// apart, as a passer-by takes the track or not).
#[test]
fn dev_set_from_the_first_box() {
    let Some(data) = shared_data_dir() else {
        println!("SKIPPED: no ../shared/data folder with the real sequences");
        return;
    };
    let names = sequence_names(&data);
    let mut aucs = Vec::new();
    for name in &names {
        let seq = Sequence::open(data.join(name), GtOrigin::of_shared(name)).expect("opens");
        let frames: Vec<_> = seq.frames().map(|f| f.expect("decodes")).collect();
        let init = seq.init_box().expect("ground truth");
        let (boxes, _) = track(&options(Params::default()), &frames, &init).expect("starts");
        let auc = Evaluation::new(&seq.groundtruth, &boxes).success_auc;
        println!("{name:18} AUC {auc:.3}");
        aucs.push(auc);
    }
    let mean = aucs.iter().sum::<f64>() / aucs.len() as f64;
    println!("mean AUC {mean:.3} over {} sequences", aucs.len());
    assert_eq!(aucs.len(), 14);
    assert!(mean >= 0.62, "mean AUC {mean}");
}
