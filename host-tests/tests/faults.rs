//! Fault scenes: black frames, frames of pure noise, a frozen frame repeated,
//! torn frames, a target out of the frame for 50 frames and a sudden illumination
//! change, each for both trackers over scene seeds 1 to 5 (100 particles, 320x240).
//!
//! In every frame of every scene the estimate must be sane: centre inside the frame,
//! half-axes positive and at most the frame's longer side, confidence in `[0, 1]`. While
//! the target cannot be seen (black or noise frames, wholly out of the frame) the status
//! must be `Lost`. Once the target is plainly visible again (wholly in view, frame not
//! faulty) the tracker must re-acquire it within 10 frames: status `Tracking` with the
//! estimate's centre inside the target's ellipse.
//!
//! Each test prints, per seed, the frames it took to re-acquire and any frame where the
//! target could not be seen but the status was not `Lost`
//! (`cargo test --release -p rbtrack-host --test faults -- --nocapture --include-ignored`).

use rbtrack::fixed::Q16;
use rbtrack::tracker::{Estimate, Status, Variant};
use rbtrack_host::faults::{Fault, FaultyScene};
use rbtrack_host::pixels::Frame;
use rbtrack_host::run::{start, Options};
use rbtrack_host::scene::{Scene, SceneConfig, Truth, Variant as SceneVariant};

/// Frames within which the target must be re-acquired once plainly visible again.
const REACQUIRE_FRAMES: usize = 10;
/// Scene seeds (the tracker uses the same seed).
const SEEDS: std::ops::RangeInclusive<u64> = 1..=5;

/// What happened in one run.
#[derive(Debug)]
struct Outcome {
    seed: u64,
    /// Frames where the target could not be seen but the status was not `Lost`, with the
    /// status.
    not_lost: Vec<(usize, Status)>,
    /// First plainly visible frame after the last fault or absence.
    visible_again: Option<usize>,
    /// Frames from `visible_again` (1 = that frame) to the first one on target and
    /// `Tracking`; `None` if never within the scene.
    reacquired_after: Option<usize>,
}

fn on_target(e: &Estimate, t: &Truth) -> bool {
    let dx = (e.ellipse.cx.to_f64() - t.cx) / t.hx;
    let dy = (e.ellipse.cy.to_f64() - t.cy) / t.hy;
    e.status == Status::Tracking && dx * dx + dy * dy <= 1.0
}

/// The estimate keeps its guarantees in a `w x h` frame.
fn assert_sane(e: &Estimate, w: usize, h: usize, frame: usize) {
    let el = e.ellipse;
    let (cx, cy, hx, hy) = (
        el.cx.to_f64(),
        el.cy.to_f64(),
        el.hx.to_f64(),
        el.hy.to_f64(),
    );
    assert!(
        [cx, cy, hx, hy].iter().all(|v| v.is_finite()),
        "frame {frame}: {e:?}"
    );
    assert!(
        (0.0..=(w - 1) as f64).contains(&cx) && (0.0..=(h - 1) as f64).contains(&cy),
        "frame {frame}: centre ({cx}, {cy}) outside {w}x{h}"
    );
    let longer = (w.max(h) - 1) as f64;
    assert!(
        hx > 0.0 && hy > 0.0 && hx <= longer && hy <= longer,
        "frame {frame}: half-axes ({hx}, {hy})"
    );
    assert!(e.confidence >= Q16::ZERO && e.confidence <= Q16::ONE);
}

/// Runs `variant` over `scene` (started on frame 0's truth) and measures the outcome.
fn run(variant: Variant, scene: &FaultyScene, seed: u64) -> Outcome {
    let base = scene.scene();
    let (w, h) = (base.width() as usize, base.height() as usize);
    let mut options = Options::new(variant);
    options.config.seed = seed;
    base.configure(&mut options.config);
    let frame = |i| Frame::rgb888(w as u32, h as u32, scene.render(i).expect("frame")).unwrap();
    let mut runner = start(&options, &frame(0), &base.boxes()[0]).expect("tracker starts");
    // The last frame where the target could not be plainly seen.
    let last_hidden = (0..scene.len())
        .rev()
        .find(|&i| !scene.plainly_visible(i))
        .unwrap_or(0);
    let visible_again = (last_hidden + 1..scene.len()).find(|&i| scene.plainly_visible(i));
    let mut outcome = Outcome {
        seed,
        not_lost: Vec::new(),
        visible_again,
        reacquired_after: None,
    };
    for i in 1..scene.len() {
        let e = runner.step(&frame(i)).expect("step").estimate;
        assert_sane(&e, w, h, i);
        if scene.target_hidden(i) && e.status != Status::Lost {
            outcome.not_lost.push((i, e.status));
        }
        if let Some(v) = visible_again {
            let truth = scene.shown_truth(i).expect("truth");
            if i >= v && outcome.reacquired_after.is_none() && on_target(&e, truth) {
                outcome.reacquired_after = Some(i - v + 1);
            }
        }
    }
    outcome
}

/// Runs every seed, prints the outcomes, then asserts them: `Lost` whenever the target
/// cannot be seen, re-acquired within [`REACQUIRE_FRAMES`].
fn check(name: &str, variant: Variant, make: impl Fn(u64) -> FaultyScene) {
    let outcomes: Vec<Outcome> = SEEDS.map(|seed| run(variant, &make(seed), seed)).collect();
    for o in &outcomes {
        println!(
            "{name} {variant:?} seed {}: visible again at {:?}, re-acquired after {:?} frames, \
             not Lost while unseen in {} frames {:?}",
            o.seed,
            o.visible_again,
            o.reacquired_after,
            o.not_lost.len(),
            o.not_lost
        );
    }
    for o in &outcomes {
        assert!(
            o.not_lost.is_empty(),
            "{name} {variant:?} seed {}: status not Lost in frames {:?} where the target cannot be seen",
            o.seed,
            o.not_lost
        );
        assert!(
            o.visible_again.is_some(),
            "{name}: the target never shows again"
        );
        assert!(
            o.reacquired_after.is_some_and(|n| n <= REACQUIRE_FRAMES),
            "{name} {variant:?} seed {}: re-acquired after {:?} frames (limit {REACQUIRE_FRAMES})",
            o.seed,
            o.reacquired_after
        );
    }
}

fn perspective(seed: u64, faults: Vec<(Fault, std::ops::Range<usize>)>) -> FaultyScene {
    let scene = Scene::new(SceneConfig::new(SceneVariant::Perspective, seed)).expect("scene");
    FaultyScene::new(scene, faults)
}

fn black(seed: u64) -> FaultyScene {
    perspective(seed, vec![(Fault::Black, 40..55)])
}

fn noise(seed: u64) -> FaultyScene {
    perspective(seed, vec![(Fault::Noise, 40..55)])
}

fn frozen(seed: u64) -> FaultyScene {
    perspective(seed, vec![(Fault::Frozen, 40..60)])
}

fn torn(seed: u64) -> FaultyScene {
    // Torn at a different row every frame, from a third of the way down to two thirds.
    let faults = (30..70)
        .map(|i| {
            let split = 1.0 / 3.0 + (i % 7) as f64 / 18.0;
            (Fault::Torn { split }, i..i + 1)
        })
        .collect();
    perspective(seed, faults)
}

fn illumination(seed: u64) -> FaultyScene {
    perspective(
        seed,
        vec![
            (Fault::Illumination { gain: 0.55 }, 40..55),
            (Fault::Illumination { gain: 1.5 }, 55..65),
        ],
    )
}

/// The target walks out of the right edge, is wholly outside for 50 frames, walks back.
fn leave(seed: u64) -> FaultyScene {
    let mut config = SceneConfig::new(SceneVariant::LeaveAndReturn, seed);
    config.frames = 250;
    let scene = Scene::new(config).expect("scene");
    let out = (0..scene.len())
        .filter(|&i| scene.truth(i).is_some_and(|t| t.visible_fraction == 0.0))
        .count();
    assert_eq!(out, 50, "frames wholly out of view");
    FaultyScene::new(scene, Vec::new())
}

#[test]
fn black_frames_rbpf() {
    check("black", Variant::Rbpf, black);
}

#[test]
fn black_frames_colour_pf() {
    check("black", Variant::ColourPf, black);
}

#[test]
fn noise_frames_rbpf() {
    check("noise", Variant::Rbpf, noise);
}

#[test]
fn noise_frames_colour_pf() {
    check("noise", Variant::ColourPf, noise);
}

#[test]
fn frozen_frame_rbpf() {
    check("frozen", Variant::Rbpf, frozen);
}

#[test]
fn frozen_frame_colour_pf() {
    check("frozen", Variant::ColourPf, frozen);
}

#[test]
fn torn_frames_rbpf() {
    check("torn", Variant::Rbpf, torn);
}

#[test]
fn torn_frames_colour_pf() {
    check("torn", Variant::ColourPf, torn);
}

#[test]
fn illumination_change_rbpf() {
    check("illumination", Variant::Rbpf, illumination);
}

#[test]
fn illumination_change_colour_pf() {
    check("illumination", Variant::ColourPf, illumination);
}

#[test]
fn leaves_for_50_frames_rbpf() {
    check("leave", Variant::Rbpf, leave);
}

#[test]
fn leaves_for_50_frames_colour_pf() {
    check("leave", Variant::ColourPf, leave);
}
