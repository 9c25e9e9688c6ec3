//! `rbtrack demo`: the core's three trackers on a built-in synthetic scene, with pictures.

use super::args::DemoArgs;
use super::report::{plot_pair, tracker_table, Curves};
use super::runs::{overlay, track_frames, RunSpec, Start};
use super::{create_dir, emit, fail, Failure, TrackerKind};
use crate::draw;
use crate::pixels::Frame;
use crate::run::{CoreCf, Shape};
use crate::scene::{Scene, SceneConfig};
use rbtrack::tracker::{Config, Variant};
use std::io::Write;

/// Frames of the demo's image strip.
const STRIP_FRAMES: usize = 8;

/// Particles per tracker.
const PARTICLES: usize = 100;

/// Runs `rbtrack demo`: the synthetic scene (seed 1, QVGA), the correlation-filter tracker
/// at its defaults, and the RBPF and the colour PF with 100 particles and the scene's
/// settings ([`Scene::configure`]), scored against the scene's ground truth; prints the table and writes into `--out`: `strip.png`
/// (8 evenly spaced frames), `demo.gif` (every second frame, unless
/// `--no-gif`), `success.png` and `precision.png`.
pub fn demo(args: &DemoArgs, out: &mut dyn Write) -> Result<(), Failure> {
    let mut scene_config = SceneConfig::new(args.scene, 1);
    scene_config.frames = args.frames;
    let scene = Scene::new(scene_config).map_err(fail)?;
    let (w, h) = (scene.width(), scene.height());
    let specs = TrackerKind::CORE.map(|tracker| {
        let mut config = Config::new(tracker.variant().unwrap_or(Variant::Rbpf));
        scene.configure(&mut config);
        RunSpec {
            tracker,
            config,
            cf64: None,
            cf: (tracker == TrackerKind::Cf).then(CoreCf::default),
            start: Start::GIVEN,
        }
    });
    let truth = scene.boxes();
    let n = scene.len();
    let strip_at: Vec<usize> = (0..STRIP_FRAMES)
        .map(|k| (k * (n - 1) + (STRIP_FRAMES - 1) / 2) / (STRIP_FRAMES - 1))
        .collect();
    let gif = !args.no_gif;
    let (mut strip, mut anim) = (Vec::new(), Vec::new());
    let rendered = (0..n).map(|i| {
        let rgb = scene.render(i).map_err(fail)?;
        Frame::rgb888(w, h, rgb).map_err(fail)
    });
    let mut runs = track_frames(
        &specs,
        Shape {
            particles: PARTICLES,
            ..Shape::default()
        },
        rendered,
        &truth[0],
        &[],
        |i, frame, runs| {
            let in_strip = strip_at.contains(&i);
            let in_gif = gif && i % 2 == 0;
            if in_strip || in_gif {
                let img = overlay(frame, i, truth.get(i), runs, false)?;
                if in_strip {
                    strip.push(img.clone());
                }
                if in_gif {
                    anim.push(img);
                }
            }
            Ok(())
        },
    )?
    .complete()?;
    for r in &mut runs {
        r.score(&truth);
    }

    create_dir(&args.out)?;
    let mut files = Vec::new();
    let path = args.out.join("strip.png");
    let refs: Vec<&[u8]> = strip.iter().map(Vec::as_slice).collect();
    draw::save_strip(&path, &refs, w, h, STRIP_FRAMES / 2).map_err(fail)?;
    files.push(path);
    if gif {
        let path = args.out.join("demo.gif");
        let refs: Vec<&[u8]> = anim.iter().map(Vec::as_slice).collect();
        draw::save_gif(&path, &refs, w, h, 100).map_err(fail)?;
        files.push(path);
    }
    let curves: Vec<Curves> = runs
        .iter()
        .filter_map(|r| {
            let e = r.evaluation.as_ref()?;
            Some(Curves {
                label: r.spec.label(PARTICLES),
                colour: r.tracker().colour(),
                success: e.success_curve.to_vec(),
                precision: e.precision_curve.clone(),
            })
        })
        .collect();
    let title = format!("synthetic {} scene", args.scene.name());
    files.extend(plot_pair(&args.out, "", &title, &curves)?);

    emit(
        out,
        &format!(
            "synthetic scene: {}, seed 1, {w}x{h} px, {n} frames; {PARTICLES} particles per \
             particle filter, the correlation-filter tracker at its defaults; ms/frame is \
             tracking only\n\n",
            args.scene.name()
        ),
    )?;
    emit(out, &tracker_table(&runs))?;
    let colours: Vec<String> = TrackerKind::CORE
        .iter()
        .map(|t| format!("{t} {}", t.colour_name()))
        .collect();
    emit(
        out,
        &format!("\nframes: ground truth green, {}\n", colours.join(", ")),
    )?;
    for f in &files {
        emit(out, &format!("wrote {}\n", f.display()))?;
    }
    Ok(())
}
