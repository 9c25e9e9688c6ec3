//! The firmware's workload: both trackers over the scene, the checksum of their
//! estimates, and the tightest pixel-to-bin loop the pixel-visit bound is priced with.
//!
//! The firmware runs this under QEMU and the host test `host-tests/tests/firmware.rs`
//! runs it on x86; both print [`Checksum::value`], and CI checks that they agree.

use crate::scene::{self, FRAMES, HEIGHT, WIDTH};
use rbtrack::fixed::Q16;
use rbtrack::image::{Binning, ImageView, Rgb565Le, Rgb8x8x8};
use rbtrack::profile::{CycleCounter, StageCycles};
use rbtrack::tracker::{
    max_pixels_per_step, Config, ConfigError, Estimate, Status, Tracker, Variant,
};
use rbtrack::window::Ellipse;

/// Particles of both trackers.
pub const PARTICLES: usize = 100;
/// Histogram bins: 8x8x8 RGB.
pub const BINS: usize = 512;
/// Seed of both trackers' random draws.
pub const TRACKER_SEED: u64 = 1;

/// The firmware's tracker: 100 particles on 8x8x8 RGB histograms.
pub type FirmwareTracker = Tracker<Rgb8x8x8, PARTICLES, BINS>;

/// The configuration of `variant`: the defaults, the fixed seed and, for the RBPF, the
/// scene's ground-plane slope.
pub fn config(variant: Variant) -> Config {
    let mut config = Config::new(variant);
    config.seed = TRACKER_SEED;
    if variant == Variant::Rbpf {
        config.scale_per_row = scene::SCALE_PER_ROW;
    }
    config
}

/// The pixels one step of `variant` may read, the core's documented bound
/// [`max_pixels_per_step`]; the firmware fails if a frame exceeds it.
pub fn pixel_bound(variant: Variant) -> u32 {
    max_pixels_per_step(PARTICLES, config(variant).pixels_per_window) as u32
}

/// Stack the firmware may use, bytes: the run's frames (the tracker and the frame buffer
/// are statics, never on the stack). The firmware paints the stack at reset and fails if
/// the high-water mark after the run is above this.
pub const STACK_BUDGET_BYTES: u32 = 16 * 1024;

/// 64-bit FNV-1a over every estimate's fields, as little-endian 32-bit words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Checksum(u64);

impl Default for Checksum {
    fn default() -> Self {
        Self::new()
    }
}

impl Checksum {
    /// The empty checksum (the FNV-1a offset basis).
    pub const fn new() -> Self {
        Self(0xCBF2_9CE4_8422_2325)
    }

    /// Adds one 32-bit word.
    pub fn add_word(&mut self, word: u32) {
        for byte in word.to_le_bytes() {
            self.0 ^= byte as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01B3);
        }
    }

    /// Adds an estimate: centre, half-axes, velocity and confidence (Q16.16 bits) and the
    /// status (0 tracking, 1 uncertain, 2 lost).
    pub fn add(&mut self, e: &Estimate) {
        let status = match e.status {
            Status::Tracking => 0,
            Status::Uncertain => 1,
            Status::Lost => 2,
        };
        for q in [
            e.ellipse.cx,
            e.ellipse.cy,
            e.ellipse.hx,
            e.ellipse.hy,
            e.vx,
            e.vy,
            e.confidence,
        ] {
            self.add_word(q.to_bits() as u32);
        }
        self.add_word(status);
    }

    /// The checksum so far.
    pub fn value(&self) -> u64 {
        self.0
    }
}

/// One tracked frame.
#[derive(Clone, Copy, Debug)]
pub struct FrameReport {
    /// Frame index, `1..=FRAMES`.
    pub frame: usize,
    /// The tracker's estimate.
    pub estimate: Estimate,
    /// Counter units spent per stage.
    pub cycles: StageCycles,
    /// Pixels the step read into histograms.
    pub pixels: u32,
    /// The target's true ellipse.
    pub truth: Ellipse,
}

/// The trackers in the order [`run_all`] runs them.
pub const VARIANTS: [Variant; 2] = [Variant::Rbpf, Variant::ColourPf];

/// Runs `variant` over the scene: renders frame 0 into `buf`, starts `tracker` in place
/// on the true ellipse, then renders and steps frames `1..=FRAMES`, timing each step with
/// `counter` and handing each frame to `report`.
///
/// # Errors
/// The tracker's [`ConfigError`] (none with this crate's configuration).
///
/// # Panics
/// If `buf` is shorter than [`scene::FRAME_BYTES`].
pub fn run<C: CycleCounter>(
    variant: Variant,
    tracker: &mut FirmwareTracker,
    buf: &mut [u8],
    counter: C,
    report: impl FnMut(&FrameReport),
) -> Result<(), ConfigError> {
    run_config(
        config(variant),
        tracker,
        FRAMES,
        Q16::ONE,
        buf,
        counter,
        report,
    )
}

/// [`run`] with any configuration and particle count `N`, over frames `1..=frames`
/// (at most [`FRAMES`]) of the scene with its target's half-axes times `target_scale`
/// ([`scene::truth_scaled`]): the scene's workload for a tracker of `config` (the budget
/// and cycles examples' measure of a configuration's cost).
///
/// # Errors
/// The tracker's [`ConfigError`].
///
/// # Panics
/// If `buf` is shorter than [`scene::FRAME_BYTES`].
pub fn run_config<C: CycleCounter, const N: usize>(
    config: Config,
    tracker: &mut Tracker<Rgb8x8x8, N, BINS>,
    frames: usize,
    target_scale: Q16,
    buf: &mut [u8],
    mut counter: C,
    mut report: impl FnMut(&FrameReport),
) -> Result<(), ConfigError> {
    scene::render_scaled(scene::SEED, 0, target_scale, buf);
    tracker.start(config, &view(buf), scene::truth_scaled(0, target_scale))?;
    for frame in 1..=frames.min(FRAMES) {
        scene::render_scaled(scene::SEED, frame, target_scale, buf);
        step_begins();
        let (estimate, cycles) = tracker.step_profiled(&view(buf), &mut counter);
        step_ends();
        report(&FrameReport {
            frame,
            estimate,
            cycles,
            pixels: tracker.pixels_visited(),
            truth: scene::truth_scaled(frame, target_scale),
        });
    }
    Ok(())
}

/// Runs every tracker of [`VARIANTS`] in turn in `tracker` ([`run`]) and returns the
/// checksum over all their estimates, in run order: the figure the firmware and the host
/// test compare.
///
/// # Errors
/// The first tracker's [`ConfigError`].
///
/// # Panics
/// If `buf` is shorter than [`scene::FRAME_BYTES`].
pub fn run_all<C: CycleCounter>(
    tracker: &mut FirmwareTracker,
    buf: &mut [u8],
    mut counter: C,
    mut report: impl FnMut(Variant, &FrameReport),
) -> Result<Checksum, ConfigError> {
    let mut checksum = Checksum::new();
    for variant in VARIANTS {
        run(variant, tracker, buf, &mut counter, |r| {
            checksum.add(&r.estimate);
            report(variant, r);
        })?;
    }
    Ok(checksum)
}

/// Called right before each step: a mark for instruction-level timing tools
/// (`ucount.py --start step_begins --end step_ends`), never inlined, does nothing.
#[inline(never)]
pub fn step_begins() {
    // A body of its own, so the linker cannot fold the two marks into one function.
    core::hint::black_box(1u32);
}

/// Called right after each step (see [`step_begins`]).
#[inline(never)]
pub fn step_ends() {
    core::hint::black_box(2u32);
}

/// `buf` as a QVGA RGB565 frame.
///
/// # Panics
/// If `buf` is shorter than [`scene::FRAME_BYTES`].
fn view(buf: &[u8]) -> ImageView<'_, Rgb565Le> {
    ImageView::new(buf, WIDTH, HEIGHT, WIDTH).expect("the buffer holds a QVGA frame")
}

/// The tightest loop that reads a pixel and adds to a histogram bin: every RGB565
/// little-endian pixel of `frame`, 8x8x8 bin (the core's own `from_rgb565`), `weight`
/// added to `counts[bin]`. Returns the pixels read. The pixel-visit bound of a step is
/// its pixels times this loop's cost per pixel.
#[inline(never)]
pub fn bin_pixels(frame: &[u8], counts: &mut [u32; BINS], weight: u32) -> u32 {
    let mut n = 0;
    for px in frame.chunks_exact(2) {
        let v = u16::from_le_bytes([px[0], px[1]]);
        let bin = Rgb8x8x8::from_rgb565(v) as usize & (BINS - 1);
        counts[bin] = counts[bin].wrapping_add(weight);
        n += 1;
    }
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use rbtrack::profile::NoCounter;

    #[test]
    fn bin_loop_counts_every_pixel() {
        let frame = [0x00u8, 0xF8, 0x1F, 0x00, 0xFF, 0xFF];
        let mut counts = [0u32; BINS];
        assert_eq!(bin_pixels(&frame, &mut counts, 3), 3);
        assert_eq!(counts[0b111_000_000], 3); // red
        assert_eq!(counts[0b000_000_111], 3); // blue
        assert_eq!(counts[BINS - 1], 3); // white
        assert_eq!(counts.iter().sum::<u32>(), 9);
    }

    #[test]
    fn checksum_is_fnv1a() {
        let mut c = Checksum::new();
        c.add_word(u32::from_le_bytes(*b"abcd"));
        // FNV-1a 64 of "abcd".
        assert_eq!(c.value(), 0xFC17_9F83_EE07_24DD);
    }

    #[test]
    fn checksum_covers_both_runs() {
        let mut buf = [0u8; scene::FRAME_BYTES];
        let mut tracker = FirmwareTracker::unstarted();
        let mut frames = 0;
        let all = run_all(&mut tracker, &mut buf, NoCounter, |_, _| frames += 1).unwrap();
        assert_eq!(frames, 2 * FRAMES);
        let mut each = Checksum::new();
        for variant in VARIANTS {
            let mut fresh = FirmwareTracker::unstarted();
            run(variant, &mut fresh, &mut buf, NoCounter, |r| {
                each.add(&r.estimate)
            })
            .unwrap();
        }
        assert_eq!(all, each);
    }

    #[test]
    fn both_trackers_follow_the_target() {
        let mut buf = [0u8; scene::FRAME_BYTES];
        let mut tracker = FirmwareTracker::unstarted();
        for variant in [Variant::Rbpf, Variant::ColourPf] {
            let mut worst = 0i64;
            run(variant, &mut tracker, &mut buf, NoCounter, |r| {
                let dx = (r.estimate.ellipse.cx - r.truth.cx).round_int() as i64;
                let dy = (r.estimate.ellipse.cy - r.truth.cy).round_int() as i64;
                worst = worst.max(dx * dx + dy * dy);
            })
            .unwrap();
            assert!(
                worst < 20 * 20,
                "{variant:?}: squared centre error up to {worst} px^2"
            );
        }
    }
}
