//! `rbtrack track`: one tracker over one sequence, video or raw dump.

use super::args::TrackArgs;
use super::input::Input;
use super::report::{self, per_frame_csv, Scores, SeedScores};
use super::runs::{
    self, box_line, check_init, create_parent, write_overlay, RunResult, RunSpec, Start,
};
use super::{
    cf64_for, cf_for, check_read, config_for, config_summary, configured_seed, configured_tracker,
    create_dir, emit, fail, overrides, progress_bar, settings_json, wrote, Failure, TrackerKind,
};
use crate::camera::parse_motions;
use crate::loss::LossReport;
use crate::run::Bins;
use crate::sequence::{self, read_groundtruth, GtOrigin};
use serde::Serialize;
use std::io::Write;

/// `track`'s JSON document.
#[derive(Serialize)]
struct TrackJson<'a> {
    sequence: &'a str,
    tracker: TrackerKind,
    frames: usize,
    #[serde(flatten)]
    scores: Scores,
    particles: usize,
    bins: Bins,
    seed: u64,
    format: &'static str,
    box_origin: &'static str,
    config: serde_json::Value,
}

/// Runs `rbtrack track`.
pub fn track(args: &TrackArgs, out: &mut dyn Write) -> Result<(), Failure> {
    let origin = args.convention.origin();
    let need_groundtruth = args.init.is_none() && args.groundtruth.is_none();
    let input = Input::open(&args.input, args.raw, origin, need_groundtruth)?;
    let groundtruth = match &args.groundtruth {
        Some(path) => read_groundtruth(path, origin).map_err(fail)?,
        None => input.groundtruth().to_vec(),
    };
    let (init, shown) = match args.init {
        Some(b) => (origin.to_zero_based(b), b),
        None => {
            let b = groundtruth.first().copied().ok_or_else(|| {
                if args.groundtruth.is_none() && !matches!(input, Input::Folder(_)) {
                    return fail(format!(
                        "{}: a video or raw dump has no ground truth: give the first frame's \
                         box with --init x,y,w,h (or a box file with --groundtruth FILE)",
                        args.input.display()
                    ));
                }
                let file = match &args.groundtruth {
                    Some(path) => path.clone(),
                    None => args.input.join(sequence::GROUNDTRUTH_FILE),
                };
                fail(format!(
                    "{}: no ground-truth box for the first frame; give --init x,y,w,h",
                    file.display()
                ))
            })?;
            (b, origin.from_zero_based(b))
        }
    };
    let (width, height) = input.size();
    check_init(&init, width, height, &shown)?;

    let overrides = overrides(&args.config)?;
    let tracker = args
        .tracker
        .or_else(|| configured_tracker(&overrides))
        .unwrap_or(TrackerKind::DEFAULT);
    check_read(&overrides, &[tracker])?;
    let seed = args.seed.unwrap_or_else(|| configured_seed(&overrides));
    let spec = RunSpec {
        tracker,
        config: config_for(&overrides, tracker, seed)?,
        cf64: cf64_for(&overrides, tracker)?,
        cf: cf_for(&overrides, tracker)?,
        start: Start::GIVEN,
    };
    let format = args.raw.map_or(args.format, |raw| raw.format);
    if let Some(dir) = &args.overlay {
        create_dir(dir)?;
    }

    let motions = match &args.camera_motion {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| fail(format!("cannot read {}: {e}", path.display())))?;
            parse_motions(&text, width, height)
                .map_err(|e| fail(format!("{}: {e}", path.display())))?
        }
        None => Vec::new(),
    };
    let name = input.name();
    let bar = progress_bar(input.len().map(|n| n as u64), &name);
    let frames = input.frames(format)?;
    let runs::Tracked { mut runs, stopped } = runs::track_frames(
        &[spec],
        args.config.shape(),
        frames,
        &init,
        &motions,
        |index, frame, runs| {
            bar.inc(1);
            match &args.overlay {
                Some(dir) => write_overlay(dir, frame, index, groundtruth.get(index), runs, false),
                None => Ok(()),
            }
        },
    )?;
    bar.finish_and_clear();
    let Some(run) = runs.first_mut() else {
        return Err(fail("no frames"));
    };
    run.score(&groundtruth);
    let frames = run.estimates.len();
    if let Some(failure) = stopped {
        // What was tracked before the failure is kept: the box and per-frame files.
        let kept = write_files(args, run, origin, out)?;
        let kept = if kept {
            "; the files hold"
        } else {
            "; tracked"
        };
        return Err(fail(format!(
            "{failure}{kept} the {frames} frames before it"
        )));
    }
    if !groundtruth.is_empty() && groundtruth.len() != frames {
        eprintln!(
            "rbtrack track: note: {} ground-truth boxes for {frames} frames; scoring the first {}",
            groundtruth.len(),
            groundtruth.len().min(frames)
        );
    }

    let scores = Scores::of(run);
    if args.json {
        let doc = TrackJson {
            sequence: &name,
            tracker,
            frames,
            scores,
            particles: args.config.particles,
            bins: args.config.bins,
            seed,
            format: format.name(),
            box_origin: origin.name(),
            config: settings_json(&run.spec),
        };
        let text = serde_json::to_string(&doc).map_err(fail)?;
        emit(out, &format!("{text}\n"))?;
    } else {
        emit(
            out,
            &format!(
                "{name}: {frames} frames, {width}x{height} px, {format}; {tracker}, {} particles, \
                 seed {seed}; config: {}; init {} ({})\n\n",
                args.config.particles,
                config_summary(&run.spec),
                box_line(&shown),
                origin.name()
            ),
        )?;
        let rows = [report::SequenceRow {
            sequence: name.clone(),
            tracker,
            frames,
            scores: report::OverSeeds::new(vec![SeedScores {
                seed,
                start: None,
                scores,
            }]),
            loss: LossReport::of([&run.checks[..]]),
        }];
        emit(out, &report::sequence_table(&rows, &[], false))?;
        emit(
            out,
            if groundtruth.is_empty() {
                "(no ground truth: scores omitted; ms/frame is tracking only)\n"
            } else {
                "(ms/frame is tracking only, decoding excluded)\n"
            },
        )?;
    }
    write_files(args, run, origin, out)?;
    if let Some(dir) = &args.overlay {
        let what = format!("{frames} overlay frames into {}", dir.display());
        wrote(out, args.json, &what)?;
    }
    Ok(())
}

/// Writes the box file (`--boxes`) and the per-frame CSV (`--per-frame`) of `run`;
/// whether any was asked for.
fn write_files(
    args: &TrackArgs,
    run: &RunResult,
    origin: GtOrigin,
    out: &mut dyn Write,
) -> Result<bool, Failure> {
    if let Some(path) = &args.boxes {
        runs::write_boxes(path, &run.boxes, origin)?;
        wrote(out, args.json, &path.display().to_string())?;
    }
    if let Some(path) = &args.per_frame {
        create_parent(path)?;
        std::fs::write(path, per_frame_csv(run, origin))
            .map_err(|e| fail(format!("cannot write {}: {e}", path.display())))?;
        wrote(out, args.json, &path.display().to_string())?;
    }
    Ok(args.boxes.is_some() || args.per_frame.is_some())
}
