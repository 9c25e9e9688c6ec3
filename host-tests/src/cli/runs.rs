//! Runs of one or more trackers over one sequence's frames, each frame decoded once and
//! handed to every run; the overlays drawn on those frames; box files.

use super::{create_dir, fail, Failure, TrackerKind};
use crate::cf64;
use crate::draw::{self, GREEN};
use crate::loss::{frame_checks, FrameCheck};
use crate::metrics::{BBox, Evaluation};
use crate::pixels::Frame;
use crate::run::{self, CoreCf, Options, RunError, Shape};
use crate::sequence::GtOrigin;
use rbtrack::fixed::Q16;
use rbtrack::tracker::{
    calibration, Calibration, CameraMotion, Config, ConfigError, Estimate, Status,
};
use serde::Serialize;
use std::path::Path;
use std::time::Duration;

/// One run to make: a tracker, its configuration (the seed included) and its first box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSpec {
    /// The tracker.
    pub tracker: TrackerKind,
    /// The core's configuration, checked (of the cf64 tracker's runs, only the seed).
    pub config: Config,
    /// The cf64 tracker's settings, checked, for its runs.
    pub cf64: Option<cf64::Params>,
    /// The core correlation-filter tracker's settings, for its runs.
    pub cf: Option<CoreCf>,
    /// Where its first box lies against the given one.
    pub start: Start,
}

impl RunSpec {
    /// The tracker and its size, as plots name it: `cf, 16 x 16 cells, 4 scales` for a
    /// correlation-filter tracker, `pf, 100 particles` for a particle filter of
    /// `particles`.
    pub fn label(&self, particles: usize) -> String {
        let (grid, scales) = match (&self.cf, &self.cf64) {
            (Some(cf), _) => (cf.grid, cf.scales),
            (None, Some(cf64)) => (cf64.grid, cf64.scales),
            (None, None) => return format!("{}, {particles} particles", self.tracker),
        };
        format!("{}, {grid} x {grid} cells, {scales} scales", self.tracker)
    }

    /// The tracker's confidence table and the confidences below which its status is
    /// `Lost` and `Uncertain`.
    pub fn status_thresholds(&self) -> (Calibration, Q16, Q16) {
        match (&self.cf, &self.cf64) {
            (Some(cf), _) => (
                calibration::CORRELATION,
                cf.config.lost_below,
                cf.config.uncertain_below,
            ),
            (None, Some(p)) => (
                calibration::CORRELATION,
                Q16::from_f64(p.lost_below),
                Q16::from_f64(p.uncertain_below),
            ),
            (None, None) => (
                *self.config.variant.calibration(),
                self.config.lost_below,
                self.config.uncertain_below,
            ),
        }
    }
}

/// A run's first box: the given (ground-truth) box shifted by `dx`, `dy` px and scaled by
/// `scale` about its centre, as in OTB's spatial robustness evaluation (SRE).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Start {
    /// Short name (`box`, `left2`, ..., `scale1.05`), for tables and file names.
    pub name: &'static str,
    /// Shift to the right, px.
    pub dx: f64,
    /// Shift down, px.
    pub dy: f64,
    /// Width and height factor.
    pub scale: f64,
}

impl Start {
    /// The given box itself.
    pub const GIVEN: Start = Start::new("box", 0.0, 0.0, 1.0);

    /// The spatial robustness starts: the box, shifted 2 px left, right, up and down,
    /// and scaled by 0.95 and 1.05.
    pub const SPATIAL: [Start; 7] = [
        Start::GIVEN,
        Start::new("left2", -2.0, 0.0, 1.0),
        Start::new("right2", 2.0, 0.0, 1.0),
        Start::new("up2", 0.0, -2.0, 1.0),
        Start::new("down2", 0.0, 2.0, 1.0),
        Start::new("scale0.95", 0.0, 0.0, 0.95),
        Start::new("scale1.05", 0.0, 0.0, 1.05),
    ];

    /// [`Start::SPATIAL`] and 14 more: shifted 1 and 3 px left, right, up and down, 2 px
    /// along each diagonal, and scaled by 0.9 and 1.1. Three times the runs, for telling
    /// two designs apart where the 7 starts' pooled means differ by less than their
    /// spread (a standard error of about 0.008 on the 44 sequences).
    pub const WIDE: [Start; 21] = [
        Start::SPATIAL[0],
        Start::SPATIAL[1],
        Start::SPATIAL[2],
        Start::SPATIAL[3],
        Start::SPATIAL[4],
        Start::SPATIAL[5],
        Start::SPATIAL[6],
        Start::new("left1", -1.0, 0.0, 1.0),
        Start::new("right1", 1.0, 0.0, 1.0),
        Start::new("up1", 0.0, -1.0, 1.0),
        Start::new("down1", 0.0, 1.0, 1.0),
        Start::new("left3", -3.0, 0.0, 1.0),
        Start::new("right3", 3.0, 0.0, 1.0),
        Start::new("up3", 0.0, -3.0, 1.0),
        Start::new("down3", 0.0, 3.0, 1.0),
        Start::new("upleft2", -2.0, -2.0, 1.0),
        Start::new("upright2", 2.0, -2.0, 1.0),
        Start::new("downleft2", -2.0, 2.0, 1.0),
        Start::new("downright2", 2.0, 2.0, 1.0),
        Start::new("scale0.9", 0.0, 0.0, 0.9),
        Start::new("scale1.1", 0.0, 0.0, 1.1),
    ];

    const fn new(name: &'static str, dx: f64, dy: f64, scale: f64) -> Self {
        Self {
            name,
            dx,
            dy,
            scale,
        }
    }

    /// `given` moved to this start.
    pub fn apply(&self, given: &BBox) -> BBox {
        let (w, h) = (given.w * self.scale, given.h * self.scale);
        BBox {
            x: given.x + (given.w - w) / 2.0 + self.dx,
            y: given.y + (given.h - h) / 2.0 + self.dy,
            w,
            h,
        }
    }
}

/// One run over one sequence.
#[derive(Clone, Debug, PartialEq)]
pub struct RunResult {
    /// What ran.
    pub spec: RunSpec,
    /// Estimated box per frame, 0-based; the first is the initial box.
    pub boxes: Vec<BBox>,
    /// The core's estimate per frame; the first is the initial one.
    pub estimates: Vec<Estimate>,
    /// Scores against the ground truth, if there is any.
    pub evaluation: Option<Evaluation>,
    /// Per frame, the loss detection's check against the ground truth (none without it).
    pub checks: Vec<Option<FrameCheck>>,
    /// Total time inside the tracker's `step`.
    pub tracking: Duration,
}

impl RunResult {
    /// The filter.
    pub fn tracker(&self) -> TrackerKind {
        self.spec.tracker
    }

    /// The seed of its random draws.
    pub fn seed(&self) -> u64 {
        self.spec.config.seed
    }

    /// Its first box against the given one.
    pub fn start(&self) -> Start {
        self.spec.start
    }

    /// Tracking-only milliseconds per frame after the first; `None` for one frame.
    pub fn ms_per_frame(&self) -> Option<f64> {
        let steps = self.estimates.len().saturating_sub(1);
        (steps > 0).then(|| self.tracking.as_secs_f64() * 1e3 / steps as f64)
    }

    /// Scores the boxes, status and confidence against `truth` (0-based); none when
    /// `truth` is empty.
    pub fn score(&mut self, truth: &[BBox]) {
        self.evaluation = (!truth.is_empty()).then(|| Evaluation::new(truth, &self.boxes));
        self.checks = frame_checks(truth, &self.boxes, &self.estimates);
    }
}

/// Every run over one sequence.
#[derive(Clone, Debug, PartialEq)]
pub struct SequenceResult {
    /// Sequence name.
    pub name: String,
    /// Frames tracked, the first included.
    pub frames: usize,
    /// Convention of the sequence's box files.
    pub origin: GtOrigin,
    /// One entry per run, in the order of the specs.
    pub runs: Vec<RunResult>,
}

/// Checks that an initial box (0-based) is usable on a `width x height` frame: finite,
/// positive size, centre inside the frame. `shown` is the box as the user wrote it, for
/// the message.
pub fn check_init(init: &BBox, width: u32, height: u32, shown: &BBox) -> Result<(), Failure> {
    if !init.is_valid() {
        return Err(fail(format!(
            "initial box {} has no positive, finite size",
            box_line(shown)
        )));
    }
    let (cx, cy) = init.centre();
    if !(cx >= 0.0 && cy >= 0.0 && cx <= width as f64 - 1.0 && cy <= height as f64 - 1.0) {
        return Err(fail(format!(
            "initial box {} is outside the {width}x{height} frame (its centre must lie inside)",
            box_line(shown)
        )));
    }
    Ok(())
}

/// The error of a tracker that did not start from `init` (0-based) on a `width x height`
/// frame, the box's size or centre in it when the core refused the box.
fn start_error(e: RunError, config: &Config, init: &BBox, width: u32, height: u32) -> Failure {
    match e {
        RunError::Config(ConfigError::InitialTooSmall) => fail(format!(
            "initial box {:.2}x{:.2} px is too small: its width and height must be at least \
             {} px",
            init.w,
            init.h,
            2.0 * config.min_half_axis.to_f64()
        )),
        RunError::Config(ConfigError::InitialOutside) => {
            let (cx, cy) = init.centre();
            fail(format!(
                "initial box centred at ({cx:.2}, {cy:.2}) is outside the {width}x{height} frame"
            ))
        }
        e => fail(e),
    }
}

/// What [`track_frames`] made: every run's results over the frames tracked, and why it
/// stopped early, if it did (a frame that could not be read or tracked, or a failure of
/// `on_frame`).
pub struct Tracked {
    /// One entry per run, in the order of the specs.
    pub runs: Vec<RunResult>,
    /// The failure that ended the runs before the last frame.
    pub stopped: Option<Failure>,
}

impl Tracked {
    /// The runs, or the failure that stopped them.
    pub fn complete(self) -> Result<Vec<RunResult>, Failure> {
        match self.stopped {
            Some(f) => Err(f),
            None => Ok(self.runs),
        }
    }
}

/// Runs every spec in trackers of `shape` over `frames` from its start of `init`, the
/// 0-based box of the first frame, each frame decoded once for all of them. Before frame
/// `i` every tracker is told `motions[i]`, how the picture moved (none past the end of
/// `motions`). After each
/// frame is tracked, `on_frame(index, frame, runs)` sees it with the runs so far (their
/// last estimate is this frame's), e.g. to draw it. Results carry no evaluation. A failure
/// before the first frame is tracked is an error; a later one ends the runs and is kept in
/// [`Tracked::stopped`] with the results so far.
pub fn track_frames<I>(
    specs: &[RunSpec],
    shape: Shape,
    frames: I,
    init: &BBox,
    motions: &[CameraMotion],
    mut on_frame: impl FnMut(usize, &Frame, &[RunResult]) -> Result<(), Failure>,
) -> Result<Tracked, Failure>
where
    I: IntoIterator<Item = Result<Frame, Failure>>,
{
    let mut frames = frames.into_iter();
    let mut runs: Vec<RunResult> = specs
        .iter()
        .map(|&spec| RunResult {
            spec,
            boxes: Vec::new(),
            estimates: Vec::new(),
            evaluation: None,
            checks: Vec::new(),
            tracking: Duration::ZERO,
        })
        .collect();
    let Some(first) = frames.next() else {
        return Ok(Tracked {
            runs,
            stopped: None,
        });
    };
    let first = first?;
    let mut runners = Vec::with_capacity(specs.len());
    for r in &mut runs {
        let options = Options {
            config: r.spec.config,
            shape,
            cf64: r.spec.cf64,
            cf: r.spec.cf,
        };
        let init = r.spec.start.apply(init);
        let runner = run::start(&options, &first, &init)
            .map_err(|e| start_error(e, &r.spec.config, &init, first.width, first.height))?;
        r.boxes.push(init);
        r.estimates.push(runner.estimate());
        runners.push(runner);
    }
    let mut stopped = on_frame(0, &first, &runs).err();
    for (index, frame) in (1..).zip(frames) {
        if stopped.is_some() {
            break;
        }
        let frame = match frame {
            Ok(frame) => frame,
            Err(e) => {
                stopped = Some(e);
                break;
            }
        };
        for (runner, r) in runners.iter_mut().zip(&mut runs) {
            if let Some(motion) = motions.get(index) {
                runner.camera_moved(motion);
            }
            match runner.step(&frame) {
                Ok(step) => {
                    r.tracking += step.elapsed;
                    r.boxes.push(step.bbox);
                    r.estimates.push(step.estimate);
                }
                Err(e) => stopped = Some(fail(e)),
            }
        }
        if stopped.is_none() {
            stopped = on_frame(index, &frame, &runs).err();
        }
    }
    Ok(Tracked { runs, stopped })
}

/// Lower-case name of a status: `tracking`, `uncertain` or `lost`.
pub fn status_name(status: Status) -> &'static str {
    match status {
        Status::Tracking => "tracking",
        Status::Uncertain => "uncertain",
        Status::Lost => "lost",
    }
}

/// Frame `index` (0-based) as RGB888 with the ground truth `truth` (green box, if valid),
/// each run's latest estimate (its ellipse, in [`TrackerKind::colour`]) and, in the
/// top-left corner, the frame number and each run's status and confidence (with its seed
/// when `label_seeds`).
pub fn overlay(
    frame: &Frame,
    index: usize,
    truth: Option<&BBox>,
    runs: &[RunResult],
    label_seeds: bool,
) -> Result<Vec<u8>, Failure> {
    let (width, height) = (frame.width, frame.height);
    let mut img = frame.to_rgb888();
    let thick = if width >= 640 { 3 } else { 2 };
    if let Some(t) = truth.filter(|t| t.is_valid()) {
        draw::draw_box(&mut img, width, height, t, GREEN, thick);
    }
    let mut lines = vec![(format!("frame {}", index + 1), [255, 255, 255])];
    for r in runs {
        let (Some(b), Some(e)) = (r.boxes.last(), r.estimates.last()) else {
            continue;
        };
        let kind = r.tracker();
        draw::draw_ellipse(
            &mut img,
            width,
            height,
            b.to_ellipse_f64(),
            kind.colour(),
            thick,
        );
        let seed = if label_seeds {
            format!(" seed {}", r.seed())
        } else {
            String::new()
        };
        lines.push((
            format!(
                "{kind}{seed} {} {:.2}",
                status_name(e.status),
                e.confidence.to_f64()
            ),
            kind.colour(),
        ));
    }
    draw::draw_text_lines(&mut img, width, height, &lines).map_err(fail)?;
    Ok(img)
}

/// Writes [`overlay`] of frame `index` as `dir/0001.png`, ... (1-based numbers).
pub fn write_overlay(
    dir: &Path,
    frame: &Frame,
    index: usize,
    truth: Option<&BBox>,
    runs: &[RunResult],
    label_seeds: bool,
) -> Result<(), Failure> {
    let img = overlay(frame, index, truth, runs, label_seeds)?;
    let path = dir.join(format!("{:04}.png", index + 1));
    draw::save_png(path, &img, frame.width, frame.height).map_err(fail)
}

/// A box as one `x,y,w,h` line (two decimals), as written to box files.
pub fn box_line(b: &BBox) -> String {
    format!("{:.2},{:.2},{:.2},{:.2}", b.x, b.y, b.w, b.h)
}

/// Creates the folder a file goes into.
pub fn create_parent(path: &Path) -> Result<(), Failure> {
    match path.parent().filter(|p| !p.as_os_str().is_empty()) {
        Some(parent) => create_dir(parent),
        None => Ok(()),
    }
}

/// Writes 0-based `boxes` to `path`, one `x,y,w,h` line per frame, in `origin`'s
/// convention.
pub fn write_boxes(path: &Path, boxes: &[BBox], origin: GtOrigin) -> Result<(), Failure> {
    let text: String = boxes
        .iter()
        .map(|b| box_line(&origin.from_zero_based(*b)) + "\n")
        .collect();
    create_parent(path)?;
    std::fs::write(path, text).map_err(|e| fail(format!("cannot write {}: {e}", path.display())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rbtrack::tracker::Variant;

    #[test]
    fn labels_name_each_trackers_own_size() {
        let spec = |tracker, cf| RunSpec {
            tracker,
            config: Config::new(Variant::Rbpf),
            cf64: None,
            cf,
            start: Start::GIVEN,
        };
        let cf = spec(TrackerKind::Cf, Some(CoreCf::default()));
        assert_eq!(cf.label(100), "cf, 16 x 16 cells, 4 scales");
        assert_eq!(spec(TrackerKind::Pf, None).label(50), "pf, 50 particles");
    }

    #[test]
    fn wide_starts_extend_the_spatial_ones_each_distinct() {
        assert_eq!(Start::WIDE[..7], Start::SPATIAL);
        for (i, a) in Start::WIDE.iter().enumerate() {
            for b in &Start::WIDE[i + 1..] {
                assert_ne!(a.name, b.name);
                assert_ne!((a.dx, a.dy, a.scale), (b.dx, b.dy, b.scale), "{}", a.name);
            }
        }
    }
}
