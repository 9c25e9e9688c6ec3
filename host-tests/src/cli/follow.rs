//! `rbtrack follow`: the pan/tilt closed loop ([`crate::follow`]) over a sequence folder
//! or the built-in synthetic scene, with its figures and pictures.

use super::args::FollowArgs;
use super::runs::status_name;
use super::{
    cf64_for, cf_for, check_read, config_for, create_dir, emit, fail, overrides, wrote, Failure,
};
use crate::draw::{self, Series, GREEN};
use crate::follow::{self, FollowFrame, FollowSummary, BAND_SHARE, FIELD_OF_VIEW_X, JUMP_SHARE};
use crate::metrics::BBox;
use crate::pixels::Frame;
use crate::run::{bbox_of, Options};
use crate::scene::{self, Scene, SceneConfig};
use crate::sequence::Sequence;
use serde::Serialize;
use std::io::Write;

/// Frames of the image strip.
const STRIP_FRAMES: usize = 8;

/// The built-in scene's size, px, and length, frames.
const SCENE_SIZE: (u32, u32) = (640, 480);
const SCENE_FRAMES: usize = 200;

/// `follow`'s JSON document.
#[derive(Serialize)]
struct FollowJson<'a> {
    scene: &'a str,
    frames: usize,
    tracker: super::TrackerKind,
    seed: u64,
    field_of_view_x: f64,
    #[serde(flatten)]
    summary: &'a FollowSummary,
}

/// Runs `rbtrack follow`.
pub fn follow(args: &FollowArgs, out: &mut dyn Write) -> Result<(), Failure> {
    let overrides = overrides(&args.config)?;
    check_read(&overrides, &[args.tracker])?;
    let mut config = config_for(&overrides, args.tracker, args.seed)?;
    let cf64 = cf64_for(&overrides, args.tracker)?;
    let cf = cf_for(&overrides, args.tracker)?;
    let options = |config| Options {
        config,
        shape: args.config.shape(),
        cf64,
        cf,
    };
    let gif = !args.no_gif;
    let mut pictures = Pictures::default();
    let (name, follow, frames) = match &args.sequence {
        Some(dir) => {
            let seq = Sequence::open(dir, args.convention.origin()).map_err(fail)?;
            let frames = seq.len().min(seq.groundtruth.len());
            let draw = |i: usize, view: &Frame, f: &FollowFrame| {
                pictures.add(i, frames, gif, view, f, args.tracker)
            };
            let run = follow::follow(
                seq.frames(),
                &seq.groundtruth,
                seq.width,
                seq.height,
                &options(config),
                draw,
            )
            .map_err(|e| fail(format!("{}: {e}", dir.display())))?;
            (seq.name.clone(), run, frames)
        }
        None => {
            let mut scene_config = SceneConfig::new(scene::Variant::Perspective, 1);
            (scene_config.width, scene_config.height) = SCENE_SIZE;
            scene_config.frames = SCENE_FRAMES;
            let scene = Scene::new(scene_config).map_err(fail)?;
            scene.configure(&mut config);
            let rendered = (0..scene.len()).map(|i| {
                let rgb = scene.render(i).map_err(|e| e.to_string())?;
                Frame::rgb888(SCENE_SIZE.0, SCENE_SIZE.1, rgb).map_err(|e| e.to_string())
            });
            let draw = |i: usize, view: &Frame, f: &FollowFrame| {
                pictures.add(i, SCENE_FRAMES, gif, view, f, args.tracker)
            };
            let (w, h) = SCENE_SIZE;
            let run = follow::follow(rendered, &scene.boxes(), w, h, &options(config), draw)
                .map_err(fail)?;
            ("synthetic perspective scene".to_owned(), run, SCENE_FRAMES)
        }
    };
    let summary = follow.summary();

    create_dir(&args.out)?;
    let mut files = Vec::new();
    let (vw, vh) = summary.view;
    let path = args.out.join("strip.png");
    let refs: Vec<&[u8]> = pictures.strip.iter().map(Vec::as_slice).collect();
    draw::save_strip(&path, &refs, vw, vh, STRIP_FRAMES / 2).map_err(fail)?;
    files.push(path);
    if gif {
        let path = args.out.join("view.gif");
        let refs: Vec<&[u8]> = pictures.gif.iter().map(Vec::as_slice).collect();
        draw::save_gif(&path, &refs, vw, vh, 66).map_err(fail)?;
        files.push(path);
    }
    let path = args.out.join("error.png");
    let width = vw as f64;
    let error: Vec<f64> = follow
        .frames
        .iter()
        .map(|f| {
            let (ex, ey) = f.error();
            ex.hypot(ey) / width
        })
        .collect();
    let band = vec![BAND_SHARE; error.len()];
    let title = format!("{name}: centring error, {} frames", follow.frames.len());
    let series = [
        Series {
            label: "distance of the target from the centre / view width",
            values: &error,
            colour: args.tracker.colour(),
        },
        Series {
            label: "band",
            values: &band,
            colour: draw::palette(0),
        },
    ];
    draw::error_plot(&path, &title, "share of the view's width", &series).map_err(fail)?;
    files.push(path);

    if args.json {
        let doc = FollowJson {
            scene: &name,
            frames,
            tracker: args.tracker,
            seed: args.seed,
            field_of_view_x: FIELD_OF_VIEW_X,
            summary: &summary,
        };
        let text = serde_json::to_string(&doc).map_err(fail)?;
        emit(out, &format!("{text}\n"))?;
    } else {
        emit(out, &report(&name, &follow, &summary, args))?;
    }
    for f in &files {
        wrote(out, args.json, &f.display().to_string())?;
    }
    Ok(())
}

/// The text report.
fn report(name: &str, follow: &follow::Follow, s: &FollowSummary, args: &FollowArgs) -> String {
    let (vw, vh) = s.view;
    let settling: Vec<String> = follow
        .jumps
        .iter()
        .zip(&s.settling)
        .map(|(jump, settle)| match settle {
            Some(n) => format!("at frame {}: {n} frames", jump + 1),
            None => format!("at frame {}: never", jump + 1),
        })
        .collect();
    format!(
        "{name}: {} frames; the camera sees {vw}x{vh} px ({FIELD_OF_VIEW_X} degrees wide) \
         where the head points; {}, {} particles, seed {}; the tracker is told each turn\n\
         settling after the target jumps {:.0} % of the width off centre (start, knock): {}\n\
         settled frames {}: centred (within {:.1} px, {:.0} % of the width) {:.1} %, {:.1} % \
         of the {} with the target within the head's reach; error mean {:.1} px, 95th \
         percentile {:.1} px; largest overshoot {:.1} px\n\
         pictures: ground truth green, the estimate {}, the view's centre white\n",
        follow.frames.len(),
        args.tracker,
        args.config.particles,
        args.seed,
        JUMP_SHARE * 100.0,
        settling.join(", "),
        s.settled_frames,
        s.band,
        BAND_SHARE * 100.0,
        s.centred * 100.0,
        s.centred_in_reach * 100.0,
        s.settled_frames - s.out_of_reach,
        s.mean_error,
        s.p95_error,
        s.overshoot,
        args.tracker.colour_name(),
    )
}

/// The views drawn for the strip and the GIF.
#[derive(Default)]
struct Pictures {
    strip: Vec<Vec<u8>>,
    gif: Vec<Vec<u8>>,
}

impl Pictures {
    /// Draws frame `index` of `frames` if the strip (8 evenly spaced) or the GIF (every
    /// second) takes it.
    fn add(
        &mut self,
        index: usize,
        frames: usize,
        gif: bool,
        view: &Frame,
        f: &FollowFrame,
        tracker: super::TrackerKind,
    ) -> Result<(), String> {
        let in_strip = (0..STRIP_FRAMES).any(|k| {
            (k * frames.saturating_sub(1) + (STRIP_FRAMES - 1) / 2) / (STRIP_FRAMES - 1) == index
        });
        let in_gif = gif && index.is_multiple_of(2);
        if !(in_strip || in_gif) {
            return Ok(());
        }
        let (w, h) = (view.width, view.height);
        let mut img = view.to_rgb888();
        let centre = ((w as f64 - 1.0) / 2.0, (h as f64 - 1.0) / 2.0);
        draw::draw_cross(&mut img, w, h, centre, 6, [255, 255, 255]);
        if f.truth.is_valid() {
            draw::draw_box(&mut img, w, h, &f.truth, GREEN, 2);
        }
        let estimate: BBox = bbox_of(&f.estimate);
        draw::draw_ellipse(
            &mut img,
            w,
            h,
            estimate.to_ellipse_f64(),
            tracker.colour(),
            2,
        );
        let (ex, ey) = f.error();
        let lines = [
            (format!("frame {}", index + 1), [255, 255, 255]),
            (
                format!(
                    "{tracker} {} {:.2}",
                    status_name(f.estimate.status),
                    f.estimate.confidence.to_f64()
                ),
                tracker.colour(),
            ),
            (format!("error {ex:+.0},{ey:+.0} px"), [255, 255, 255]),
            (
                format!(
                    "pan {:+.1} tilt {:+.1} deg",
                    f.command.pan.to_f64(),
                    f.command.tilt.to_f64()
                ),
                [255, 255, 255],
            ),
        ];
        draw::draw_text_lines(&mut img, w, h, &lines).map_err(|e| e.to_string())?;
        if in_strip {
            self.strip.push(img.clone());
        }
        if in_gif {
            self.gif.push(img);
        }
        Ok(())
    }
}
