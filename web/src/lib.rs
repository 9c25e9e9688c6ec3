//! The rbtrack core in WebAssembly, for the browser page in `web/www`: the same source as
//! the firmware's, built for `wasm32-unknown-unknown` with no feature that changes results,
//! so the page computes the estimates the board computes, bit for bit.
//!
//! The page hands each frame over as the RGBA bytes of a canvas; [`Frames`] converts them
//! once to RGB888, the core's [`Rgb888`] view, and a [`Session`] tracks it with the RBPF
//! or the colour PF of 25 to 200 particles (512 colour bins), or the correlation-filter
//! tracker (`CfTracker`, 16 x 16 cells, 4 scales, as `rbtrack --tracker cf` and the
//! correlation-filter firmware run it). [`firmware_checksum`] and [`cf_firmware_checksum`]
//! run the example firmwares' synthetic scene and return the checksums QEMU prints.
//!
//! The binding is a plain `extern "C"` ABI ([`abi`]): a handful of functions over numbers
//! and one frame buffer in the module's memory, which the page fills in place. It needs no
//! generated glue and no tool beyond `cargo`, and the module imports nothing.

use rbtrack::fixed::Q16;
use rbtrack::image::{ImageError, ImageView, Rgb888};
use rbtrack::profile::NoCounter;
use rbtrack::tracker::{CfConfig, Config, ConfigError, Estimate, Variant};
use rbtrack::{Ellipse, Rect, RgbTracker};
use rbtrack_firmware::cf::{run_cf, FirmwareCfTracker};
use rbtrack_firmware::run::{run_all, FirmwareTracker};
use rbtrack_firmware::scene::FRAME_BYTES;

pub mod abi;

/// Particle counts the page offers.
pub const PARTICLE_COUNTS: [usize; 4] = [25, 50, 100, 200];

/// The trackers the page offers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A particle filter of a number of particles (one of [`PARTICLE_COUNTS`]).
    Particles(Variant, usize),
    /// The correlation-filter tracker at its defaults.
    CorrelationFilter,
}

/// The largest frame side accepted, px.
pub const MAX_SIDE: u32 = 4096;

/// Why a session could not start or step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WebError {
    /// The particle count is not one of [`PARTICLE_COUNTS`].
    Particles,
    /// No frame of a valid size was handed over.
    Frame(ImageError),
    /// The tracker refused the configuration or the initial box.
    Config(ConfigError),
    /// A step before any start.
    NotStarted,
}

impl WebError {
    /// The code the ABI returns for it, negative: -1 particles, -2 frame, -3 a box too
    /// small, -4 a box centred outside the frame, -5 another configuration error, -6 not
    /// started.
    pub fn code(self) -> i32 {
        match self {
            Self::Particles => -1,
            Self::Frame(_) => -2,
            Self::Config(ConfigError::InitialTooSmall) => -3,
            Self::Config(ConfigError::InitialOutside) => -4,
            Self::Config(_) => -5,
            Self::NotStarted => -6,
        }
    }
}

/// The frame buffers: the RGBA bytes the page writes and their RGB888 conversion.
#[derive(Debug, Default)]
pub struct Frames {
    rgba: Vec<u8>,
    rgb: Vec<u8>,
    width: u32,
    height: u32,
}

impl Frames {
    /// No frame yet.
    pub const fn new() -> Self {
        Self {
            rgba: Vec::new(),
            rgb: Vec::new(),
            width: 0,
            height: 0,
        }
    }

    /// The RGBA buffer of a `width x height` frame, rows top to bottom, to fill; `None`
    /// for a side of 0 or above [`MAX_SIDE`].
    pub fn rgba_mut(&mut self, width: u32, height: u32) -> Option<&mut [u8]> {
        let sides = 1..=MAX_SIDE;
        if !sides.contains(&width) || !sides.contains(&height) {
            return None;
        }
        let pixels = width as usize * height as usize;
        self.rgba.resize(pixels * 4, 0);
        self.rgb.resize(pixels * 3, 0);
        (self.width, self.height) = (width, height);
        Some(&mut self.rgba)
    }

    /// The frame as the core's RGB888 view, converted from the RGBA bytes (alpha dropped).
    pub fn view(&mut self) -> Result<ImageView<'_, Rgb888>, ImageError> {
        for (rgb, rgba) in self.rgb.chunks_exact_mut(3).zip(self.rgba.chunks_exact(4)) {
            rgb.copy_from_slice(&rgba[..3]);
        }
        let (w, h) = (self.width as usize, self.height as usize);
        ImageView::new(&self.rgb, w, h, w)
    }
}

/// Any of the page's trackers behind one interface.
trait Track {
    fn start(&mut self, frame: &ImageView<'_, Rgb888>, init: Ellipse) -> Result<(), ConfigError>;
    fn step(&mut self, frame: &ImageView<'_, Rgb888>) -> Estimate;
    fn estimate(&self) -> Estimate;
    /// Frame pixels the last step read; 0 where the tracker does not count them.
    fn pixels_visited(&self) -> u32;
}

/// A particle filter and its configuration.
struct Particles<const N: usize> {
    tracker: RgbTracker<N>,
    config: Config,
}

impl<const N: usize> Track for Particles<N> {
    fn start(&mut self, frame: &ImageView<'_, Rgb888>, init: Ellipse) -> Result<(), ConfigError> {
        self.tracker.start(self.config, frame, init)
    }

    fn step(&mut self, frame: &ImageView<'_, Rgb888>) -> Estimate {
        self.tracker.step(frame)
    }

    fn estimate(&self) -> Estimate {
        self.tracker.estimate()
    }

    fn pixels_visited(&self) -> u32 {
        self.tracker.pixels_visited()
    }
}

impl Track for FirmwareCfTracker {
    fn start(&mut self, frame: &ImageView<'_, Rgb888>, init: Ellipse) -> Result<(), ConfigError> {
        FirmwareCfTracker::start(self, CfConfig::default(), frame, Rect::from(init))
    }

    fn step(&mut self, frame: &ImageView<'_, Rgb888>) -> Estimate {
        FirmwareCfTracker::step(self, frame)
    }

    fn estimate(&self) -> Estimate {
        *FirmwareCfTracker::estimate(self)
    }

    fn pixels_visited(&self) -> u32 {
        0
    }
}

/// One tracked target.
pub struct Session {
    tracker: Box<dyn Track + Send>,
}

impl Session {
    /// A tracker of `kind` at its defaults (the particle filters' random draws seeded by
    /// `seed`), started on the 0-based box `(x, y, w, h)` (px) of `frame`: its inscribed
    /// ellipse, as the host tool's `--init` takes it.
    pub fn start(
        kind: Kind,
        seed: u64,
        frame: &ImageView<'_, Rgb888>,
        (x, y, w, h): (f64, f64, f64, f64),
    ) -> Result<Self, WebError> {
        fn particles<const N: usize>(variant: Variant, seed: u64) -> Box<dyn Track + Send> {
            let mut config = Config::new(variant);
            config.seed = seed;
            Box::new(Particles {
                tracker: RgbTracker::<N>::unstarted(),
                config,
            })
        }
        let mut tracker: Box<dyn Track + Send> = match kind {
            Kind::Particles(v, 25) => particles::<25>(v, seed),
            Kind::Particles(v, 50) => particles::<50>(v, seed),
            Kind::Particles(v, 100) => particles::<100>(v, seed),
            Kind::Particles(v, 200) => particles::<200>(v, seed),
            Kind::Particles(..) => return Err(WebError::Particles),
            Kind::CorrelationFilter => Box::new(FirmwareCfTracker::unstarted()),
        };
        let init = Ellipse {
            cx: Q16::from_f64(x + (w - 1.0) / 2.0),
            cy: Q16::from_f64(y + (h - 1.0) / 2.0),
            hx: Q16::from_f64(w / 2.0),
            hy: Q16::from_f64(h / 2.0),
        };
        tracker.start(frame, init).map_err(WebError::Config)?;
        Ok(Self { tracker })
    }

    /// One frame.
    pub fn step(&mut self, frame: &ImageView<'_, Rgb888>) -> Estimate {
        self.tracker.step(frame)
    }

    /// The last estimate (the initial ellipse before any step).
    pub fn estimate(&self) -> Estimate {
        self.tracker.estimate()
    }

    /// Pixels the last step read (the step's cost, without counting instructions).
    pub fn pixels_visited(&self) -> u32 {
        self.tracker.pixels_visited()
    }
}

/// The example firmware's run on its synthetic scene (both trackers, 60 frames each) and
/// the checksum over every estimate: the value the firmware prints in QEMU.
pub fn firmware_checksum() -> Result<u64, ConfigError> {
    let mut frame = vec![0u8; FRAME_BYTES];
    let mut tracker = Box::new(FirmwareTracker::unstarted());
    let checksum = run_all(&mut tracker, &mut frame, NoCounter, |_, _| {})?;
    Ok(checksum.value())
}

/// The correlation-filter firmware's run on the same scene (60 frames) and its checksum:
/// the value `examples/cf_firmware.rs` prints in QEMU.
pub fn cf_firmware_checksum() -> Result<u64, ConfigError> {
    let mut frame = vec![0u8; FRAME_BYTES];
    let mut tracker = Box::new(FirmwareCfTracker::unstarted());
    let checksum = run_cf(
        CfConfig::default(),
        &mut tracker,
        Q16::ONE,
        &mut frame,
        NoCounter,
        |_| {},
    )?;
    Ok(checksum.value())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bright square on grey, as RGBA.
    fn square(frames: &mut Frames, x0: u32) {
        let buf = frames.rgba_mut(64, 48).unwrap();
        for (i, px) in buf.chunks_exact_mut(4).enumerate() {
            let (x, y) = (i as u32 % 64, i as u32 / 64);
            let inside = (x0..x0 + 16).contains(&x) && (16..32).contains(&y);
            px.copy_from_slice(&if inside {
                [230, 40, 40, 255]
            } else {
                [90, 90, 90, 7]
            });
        }
    }

    #[test]
    fn rgba_becomes_the_cores_rgb888_and_a_square_is_followed() {
        let mut frames = Frames::new();
        assert!(frames.rgba_mut(0, 10).is_none());
        assert!(frames.rgba_mut(10, MAX_SIDE + 1).is_none());
        square(&mut frames, 20);
        let view = frames.view().unwrap();
        assert_eq!((view.width(), view.height()), (64, 48));
        let box_ = (20.0, 16.0, 16.0, 16.0);
        let mut session =
            Session::start(Kind::Particles(Variant::ColourPf, 50), 1, &view, box_).unwrap();
        assert_eq!(session.estimate().ellipse.cx, Q16::from_f64(27.5));
        follow(&mut session, &mut frames, |s| {
            assert!(s.pixels_visited() > 0)
        });
    }

    /// Moves the square 2 px a frame, three times: the session's centre follows it within
    /// 2 px, and `check` holds after every step.
    fn follow(session: &mut Session, frames: &mut Frames, check: impl Fn(&Session)) {
        for x0 in [22, 24, 26] {
            square(frames, x0);
            let e = session.step(&frames.view().unwrap());
            assert!(
                (e.ellipse.cx.to_f64() - (x0 as f64 + 7.5)).abs() < 2.0,
                "{e:?}"
            );
            check(session);
        }
    }

    #[test]
    fn bad_starts_say_why() {
        let mut frames = Frames::new();
        square(&mut frames, 20);
        let view = frames.view().unwrap();
        let start = |n, b| {
            Session::start(Kind::Particles(Variant::Rbpf, n), 1, &view, b)
                .err()
                .map(WebError::code)
        };
        assert_eq!(start(30, (20.0, 16.0, 16.0, 16.0)), Some(-1));
        assert_eq!(start(25, (20.0, 16.0, 1.0, 1.0)), Some(-3));
        assert_eq!(start(25, (200.0, 16.0, 16.0, 16.0)), Some(-4));
        assert_eq!(start(25, (20.0, 16.0, 16.0, 16.0)), None);
    }

    /// CI passes the checksums the firmwares printed in QEMU; the page's runs must give them.
    #[test]
    fn the_firmware_scene_gives_the_firmwares_checksums() {
        for (run, var) in [
            (
                firmware_checksum as fn() -> Result<u64, ConfigError>,
                "RBTRACK_FIRMWARE_CHECKSUM",
            ),
            (cf_firmware_checksum, "RBTRACK_CF_FIRMWARE_CHECKSUM"),
        ] {
            let checksum = run().unwrap();
            assert_eq!(run(), Ok(checksum), "deterministic");
            match std::env::var(var) {
                Ok(qemu) => assert_eq!(format!("{checksum:#018x}"), qemu.trim(), "{var}"),
                Err(_) => println!("no {var}: {checksum:#018x} not compared"),
            }
        }
    }

    #[test]
    fn the_correlation_filter_follows_a_square() {
        let mut frames = Frames::new();
        square(&mut frames, 20);
        let view = frames.view().unwrap();
        let box_ = (20.0, 16.0, 16.0, 16.0);
        let tiny = Session::start(Kind::CorrelationFilter, 1, &view, (20.0, 16.0, 1.0, 1.0));
        assert_eq!(tiny.err().map(WebError::code), Some(-3));
        let mut session = Session::start(Kind::CorrelationFilter, 1, &view, box_).unwrap();
        follow(&mut session, &mut frames, |_| {});
    }
}
