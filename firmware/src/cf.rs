//! The correlation-filter tracker's workload: the same scene as [`crate::run`], its own
//! checksum (the particle filters' checksum, which the C firmware and the browser page
//! reproduce, is unchanged by it).
//!
//! `examples/cf_firmware.rs` runs this under QEMU and `host-tests/tests/cf_firmware.rs` on
//! x86; both print [`Checksum::value`], and CI checks that they agree.

use crate::run::{step_begins, step_ends, Checksum, BINS};
use crate::scene::{self, FRAMES, HEIGHT, WIDTH};
use rbtrack::fixed::Q16;
use rbtrack::image::{ImageView, Rgb565Le, Rgb8x8x8};
use rbtrack::profile::{CfStageCycles, CycleCounter};
use rbtrack::rect::Rect;
use rbtrack::tracker::{CfConfig, CfTracker, ConfigError, Estimate};
use rbtrack::window::Ellipse;

/// Cells a side of the firmware's correlation-filter tracker (the default).
pub const CF_GRID: usize = 16;
/// Its scales.
pub const CF_SCALES: usize = 4;

/// The firmware's correlation-filter tracker: 16 x 16 cells, 4 scales, 8x8x8 RGB colours.
pub type FirmwareCfTracker = CfTracker<Rgb8x8x8, BINS, CF_GRID, CF_SCALES>;

/// One tracked frame.
#[derive(Clone, Copy, Debug)]
pub struct CfFrameReport {
    /// Frame index, `1..=FRAMES`.
    pub frame: usize,
    /// The tracker's estimate.
    pub estimate: Estimate,
    /// Counter units spent per stage.
    pub cycles: CfStageCycles,
    /// The target's true ellipse.
    pub truth: Ellipse,
}

/// Runs the tracker over the scene at `config` with its target times `target_scale` (1: the
/// scene as it is): renders frame 0 into `buf`, starts `tracker` in place on the true box,
/// then renders and steps frames `1..=FRAMES`, timing each step with `counter`, handing
/// each frame to `report`; returns the checksum of the estimates.
///
/// # Errors
/// The tracker's [`ConfigError`] (none at the defaults).
///
/// # Panics
/// If `buf` is shorter than [`scene::FRAME_BYTES`].
pub fn run_cf<C: CycleCounter, const G: usize, const S: usize>(
    config: CfConfig,
    tracker: &mut CfTracker<Rgb8x8x8, BINS, G, S>,
    target_scale: Q16,
    buf: &mut [u8],
    mut counter: C,
    mut report: impl FnMut(&CfFrameReport),
) -> Result<Checksum, ConfigError> {
    let mut checksum = Checksum::new();
    let truth = |frame| scene::truth_scaled(frame, target_scale);
    scene::render_scaled(scene::SEED, 0, target_scale, buf);
    tracker.start(config, &view(buf), Rect::from(truth(0)))?;
    for frame in 1..=FRAMES {
        scene::render_scaled(scene::SEED, frame, target_scale, buf);
        step_begins();
        let (estimate, cycles) = tracker.step_profiled(&view(buf), &mut counter);
        step_ends();
        checksum.add(&estimate);
        report(&CfFrameReport {
            frame,
            estimate,
            cycles,
            truth: truth(frame),
        });
    }
    Ok(checksum)
}

/// The intersection over union of the bounding boxes of `a` and `b`, in thousandths
/// (0 to 1000, rounded down): how well an estimate covers the truth, integer-only.
pub fn iou_permille(a: &Ellipse, b: &Ellipse) -> u32 {
    // Edges in Q16.16 bits shifted to 1/256 px (a QVGA box's area stays far below 2^40).
    let span = |c: Q16, h: Q16| {
        let (c, h) = (c.to_bits() as i64 >> 8, h.to_bits().max(0) as i64 >> 8);
        (c - h, c + h)
    };
    let (ax, ay) = (span(a.cx, a.hx), span(a.cy, a.hy));
    let (bx, by) = (span(b.cx, b.hx), span(b.cy, b.hy));
    let overlap = |p: (i64, i64), q: (i64, i64)| (p.1.min(q.1) - p.0.max(q.0)).max(0);
    let area = |x: (i64, i64), y: (i64, i64)| (x.1 - x.0).saturating_mul(y.1 - y.0);
    let inter = overlap(ax, bx).saturating_mul(overlap(ay, by));
    let union = area(ax, ay)
        .saturating_add(area(bx, by))
        .saturating_sub(inter);
    if union <= 0 {
        return 0;
    }
    (inter.saturating_mul(1000) / union).clamp(0, 1000) as u32
}

/// `buf` as a QVGA RGB565 frame.
///
/// # Panics
/// If `buf` is shorter than [`scene::FRAME_BYTES`].
fn view(buf: &[u8]) -> ImageView<'_, Rgb565Le> {
    ImageView::new(buf, WIDTH, HEIGHT, WIDTH).expect("the buffer holds a QVGA frame")
}

#[cfg(test)]
mod tests {
    use super::*;
    use rbtrack::profile::NoCounter;
    use rbtrack::tracker::Status;

    fn ellipse(cx: i32, cy: i32, hx: i32, hy: i32) -> Ellipse {
        let q = Q16::from_int;
        Ellipse::new(q(cx), q(cy), q(hx), q(hy))
    }

    #[test]
    fn iou_of_boxes() {
        let a = ellipse(50, 50, 10, 20);
        assert_eq!(iou_permille(&a, &a), 1000);
        // Shifted by half its width: overlap 10 x 40 of a union 30 x 40.
        assert_eq!(iou_permille(&a, &ellipse(60, 50, 10, 20)), 333);
        assert_eq!(iou_permille(&a, &ellipse(200, 50, 10, 20)), 0);
        assert_eq!(iou_permille(&a, &ellipse(0, 0, 0, 0)), 0);
    }

    /// The run at `G` cells a side: frames, lost frames, mean IoU (thousandths), checksum.
    fn run_at<const G: usize, const S: usize>(
        tracker: &mut CfTracker<Rgb8x8x8, BINS, G, S>,
    ) -> (usize, usize, u32, Checksum) {
        let mut buf = [0u8; scene::FRAME_BYTES];
        let (mut frames, mut lost, mut iou) = (0, 0, 0);
        let mut each = Checksum::new();
        let checksum = run_cf(
            CfConfig::default(),
            tracker,
            Q16::ONE,
            &mut buf,
            NoCounter,
            |r| {
                assert_eq!(r.frame, frames + 1);
                frames += 1;
                lost += usize::from(r.estimate.status == Status::Lost);
                iou += iou_permille(&r.estimate.ellipse, &r.truth);
                each.add(&r.estimate);
            },
        )
        .unwrap();
        assert_eq!(
            checksum, each,
            "the checksum is over every estimate, in order"
        );
        (frames, lost, iou / frames.max(1) as u32, checksum)
    }

    #[test]
    fn firmware_tracker_follows_the_target_reproducibly() {
        let mut tracker = FirmwareCfTracker::unstarted();
        let (frames, lost, iou, checksum) = run_at(&mut tracker);
        assert_eq!(frames, FRAMES);
        assert_eq!(lost, 0);
        assert!(iou >= 500, "mean IoU {iou}/1000");
        // Restarted in the same static: the same run.
        assert_eq!(run_at(&mut tracker).3, checksum);
        let mut fresh = FirmwareCfTracker::unstarted();
        assert_eq!(run_at(&mut fresh).3, checksum);
    }

    #[test]
    fn budget_grid_runs_the_scene() {
        let mut tracker = CfTracker::<Rgb8x8x8, BINS, 8, CF_SCALES>::unstarted();
        let (frames, lost, iou, _) = run_at(&mut tracker);
        assert_eq!(frames, FRAMES);
        assert_eq!(lost, 0);
        assert!(iou >= 400, "mean IoU {iou}/1000 at 8 x 8 cells");
    }
}
