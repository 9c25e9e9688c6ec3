//! The correlation-filter tracker's workload: the same scene as [`crate::run`], its own
//! checksum (the particle filters' checksum, which the C firmware and the browser page
//! reproduce, is unchanged by it).
//!
//! `examples/cf_firmware.rs` runs this under QEMU and `host-tests/tests/cf_firmware.rs` on
//! x86; both print [`Checksum::value`], and CI checks that they agree.

use crate::run::{step_begins, step_ends, Checksum, BINS};
use crate::scene::{self, FRAMES, HEIGHT, WIDTH};
use rbtrack::image::{ImageView, Rgb565Le, Rgb8x8x8};
use rbtrack::profile::{CfStageCycles, CycleCounter};
use rbtrack::rect::Rect;
use rbtrack::tracker::{CfConfig, CfTracker, ConfigError, Estimate};
use rbtrack::window::Ellipse;

/// Cells a side of the firmware's correlation-filter tracker (the default).
pub const CF_GRID: usize = 16;
/// Its scales.
pub const CF_SCALES: usize = 8;

/// The firmware's correlation-filter tracker: 16 x 16 cells, 8 scales, 8x8x8 RGB colours.
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

/// Runs the tracker over the scene at `config`: renders frame 0 into `buf`, starts
/// `tracker` in place on the true box, then renders and steps frames `1..=FRAMES`, timing
/// each step with `counter`, handing each frame to `report`; returns the checksum of the
/// estimates.
///
/// # Errors
/// The tracker's [`ConfigError`] (none at the defaults).
///
/// # Panics
/// If `buf` is shorter than [`scene::FRAME_BYTES`].
pub fn run_cf<C: CycleCounter, const G: usize>(
    config: CfConfig,
    tracker: &mut CfTracker<Rgb8x8x8, BINS, G, CF_SCALES>,
    buf: &mut [u8],
    mut counter: C,
    mut report: impl FnMut(&CfFrameReport),
) -> Result<Checksum, ConfigError> {
    let mut checksum = Checksum::new();
    scene::render(scene::SEED, 0, buf);
    tracker.start(config, &view(buf), Rect::from(scene::truth(0)))?;
    for frame in 1..=FRAMES {
        scene::render(scene::SEED, frame, buf);
        step_begins();
        let (estimate, cycles) = tracker.step_profiled(&view(buf), &mut counter);
        step_ends();
        checksum.add(&estimate);
        report(&CfFrameReport {
            frame,
            estimate,
            cycles,
            truth: scene::truth(frame),
        });
    }
    Ok(checksum)
}

/// `buf` as a QVGA RGB565 frame.
///
/// # Panics
/// If `buf` is shorter than [`scene::FRAME_BYTES`].
fn view(buf: &[u8]) -> ImageView<'_, Rgb565Le> {
    ImageView::new(buf, WIDTH, HEIGHT, WIDTH).expect("the buffer holds a QVGA frame")
}
