//! Motion-adaptive noise (`Config::noise_gain`, `noise_floor`) against the look-alike
//! crossing and the real sequences: the table in the README's section "A look-alike
//! crossing".
//!
//! ```sh
//! cargo run --release -p rbtrack-host --example noise_gain [DATA_DIR]
//! ```
//! For each setting: how many of the distractor scene's seeds 1-5 each tracker comes
//! through (IoU > 0.5 within 10 frames of the target being fully visible), the RBPF's mean
//! IoU on every scene (seeds 1-5), and, when the real sequences are found (DATA_DIR or
//! `../shared/data`), each tracker's mean success AUC for tracker seeds 1-3.

use rbtrack::fixed::Q16;
use rbtrack::tracker::{Config, Variant};
use rbtrack_host::metrics::Evaluation;
use rbtrack_host::recovery::recovery;
use rbtrack_host::run::{track, Options};
use rbtrack_host::scene::{Scene, SceneConfig, Variant as SceneVariant};
use rbtrack_host::sequence::{shared_data_dir, GtOrigin, Sequence};
use std::path::PathBuf;

const SETTINGS: [(f64, f64); 3] = [(0.0, 0.15), (2.0, 0.15), (4.0, 0.15)];
const VARIANTS: [Variant; 2] = [Variant::Rbpf, Variant::ColourPf];

fn with_noise(mut config: Config, (gain, floor): (f64, f64)) -> Config {
    config.noise_gain = Q16::from_f64(gain);
    config.noise_floor = Q16::from_f64(floor);
    config
}

/// Options for `variant` on `scene`: the scene's settings, then the noise setting.
fn scene_options(variant: Variant, seed: u64, scene: &Scene, setting: (f64, f64)) -> Options {
    let mut o = Options::new(variant);
    o.config.seed = seed;
    scene.configure(&mut o.config);
    o.config = with_noise(o.config, setting);
    o
}

fn main() {
    let data = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .or_else(shared_data_dir);
    let sequences: Vec<(Sequence, Vec<_>)> = data
        .iter()
        .flat_map(|d| std::fs::read_dir(d).into_iter().flatten().flatten())
        .filter_map(|entry| {
            let origin = GtOrigin::of_shared(&entry.file_name().to_string_lossy());
            Sequence::open(entry.path(), origin).ok()
        })
        .map(|seq| {
            let frames = seq.frames().filter_map(Result::ok).collect();
            (seq, frames)
        })
        .collect();
    if sequences.is_empty() {
        println!("(no real sequences found: the AUC columns are left out)");
    }
    for setting in SETTINGS {
        println!("noise_gain {} / noise_floor {}", setting.0, setting.1);
        for variant in VARIANTS {
            let delays: Vec<String> = (1..=5)
                .map(|seed| {
                    let scene = Scene::new(SceneConfig::new(SceneVariant::Distractor, seed))
                        .expect("scene");
                    let r = recovery(&scene, &scene_options(variant, seed, &scene, setting))
                        .expect("tracker starts");
                    match r.delay {
                        Some(d) if r.within(10) => format!("{d}"),
                        Some(d) => format!("late {d}"),
                        None => "never".into(),
                    }
                })
                .collect();
            let ok = delays.iter().filter(|d| d.parse::<usize>().is_ok()).count();
            println!(
                "  {variant:?}: distractor seeds 1-5 within 10 frames: {ok} of 5 ({})",
                delays.join(", ")
            );
        }
        let ious: Vec<String> = SceneVariant::ALL
            .into_iter()
            .map(|kind| {
                let mean: f64 = (1..=5)
                    .map(|seed| {
                        let scene = Scene::new(SceneConfig::new(kind, seed)).expect("scene");
                        let frames: Vec<_> = scene.frames().collect();
                        let truth = scene.boxes();
                        let options = scene_options(Variant::Rbpf, seed, &scene, setting);
                        let (boxes, _) =
                            track(&options, &frames, &truth[0]).expect("tracker starts");
                        Evaluation::new(&truth, &boxes).mean_iou
                    })
                    .sum::<f64>()
                    / 5.0;
                format!("{} {mean:.3}", kind.name())
            })
            .collect();
        println!("  RBPF mean IoU, seeds 1-5: {}", ious.join(", "));
        if sequences.is_empty() {
            continue;
        }
        for variant in VARIANTS {
            let aucs: Vec<String> = (1..=3)
                .map(|seed| {
                    let mut options = Options::new(variant);
                    options.config.seed = seed;
                    options.config = with_noise(options.config, setting);
                    let auc: f64 = sequences
                        .iter()
                        .map(|(seq, frames)| {
                            let init = seq.init_box().expect("ground truth");
                            let (boxes, _) =
                                track(&options, frames, &init).expect("tracker starts");
                            Evaluation::new(&seq.groundtruth, &boxes).success_auc
                        })
                        .sum::<f64>()
                        / sequences.len() as f64;
                    format!("{auc:.3}")
                })
                .collect();
            println!(
                "  {variant:?}: real sequences ({}), mean AUC, tracker seeds 1 / 2 / 3: {}",
                sequences.len(),
                aucs.join(" / ")
            );
        }
    }
}
