//! The rbtrack core in WebAssembly, for the browser page in `web/www`: the same source as
//! the firmware's, built for `wasm32-unknown-unknown` with no feature that changes results,
//! so the page computes the estimates the board computes, bit for bit.
//!
//! The page hands each frame over as the RGBA bytes of a canvas; [`Frames`] converts them
//! once to RGB888, the core's [`Rgb888`] view, and a [`Session`] tracks it with the RBPF
//! or the colour PF of 25 to 200 particles (512 colour bins). [`firmware_checksum`] runs
//! the example firmware's synthetic scene and returns the checksum QEMU prints.
//!
//! The binding is a plain `extern "C"` ABI ([`abi`]): a handful of functions over numbers
//! and one frame buffer in the module's memory, which the page fills in place. It needs no
//! generated glue and no tool beyond `cargo`, and the module imports nothing.

use rbtrack::fixed::Q16;
use rbtrack::image::{ImageError, ImageView, Rgb888};
use rbtrack::profile::NoCounter;
use rbtrack::tracker::{Config, ConfigError, Estimate, Variant};
use rbtrack::{Ellipse, RgbTracker};
use rbtrack_firmware::run::{run_all, FirmwareTracker};
use rbtrack_firmware::scene::FRAME_BYTES;

pub mod abi;

/// Particle counts the page offers.
pub const PARTICLE_COUNTS: [usize; 4] = [25, 50, 100, 200];

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

/// A tracker of any particle count behind one interface.
trait Track {
    fn start(
        &mut self,
        config: Config,
        frame: &ImageView<'_, Rgb888>,
        init: Ellipse,
    ) -> Result<(), ConfigError>;
    fn step(&mut self, frame: &ImageView<'_, Rgb888>) -> Estimate;
    fn estimate(&self) -> Estimate;
    fn pixels_visited(&self) -> u32;
}

impl<const N: usize> Track for RgbTracker<N> {
    fn start(
        &mut self,
        config: Config,
        frame: &ImageView<'_, Rgb888>,
        init: Ellipse,
    ) -> Result<(), ConfigError> {
        RgbTracker::start(self, config, frame, init)
    }

    fn step(&mut self, frame: &ImageView<'_, Rgb888>) -> Estimate {
        RgbTracker::step(self, frame)
    }

    fn estimate(&self) -> Estimate {
        RgbTracker::estimate(self)
    }

    fn pixels_visited(&self) -> u32 {
        RgbTracker::pixels_visited(self)
    }
}

/// One tracked target.
pub struct Session {
    tracker: Box<dyn Track + Send>,
}

impl Session {
    /// A tracker of `variant` with `particles` particles and the defaults (seed `seed`),
    /// started on the 0-based box `(x, y, w, h)` (px) of `frame`: its inscribed ellipse,
    /// as the host tool's `--init` takes it.
    pub fn start(
        variant: Variant,
        particles: usize,
        seed: u64,
        frame: &ImageView<'_, Rgb888>,
        (x, y, w, h): (f64, f64, f64, f64),
    ) -> Result<Self, WebError> {
        let mut tracker: Box<dyn Track + Send> = match particles {
            25 => Box::new(RgbTracker::<25>::unstarted()),
            50 => Box::new(RgbTracker::<50>::unstarted()),
            100 => Box::new(RgbTracker::<100>::unstarted()),
            200 => Box::new(RgbTracker::<200>::unstarted()),
            _ => return Err(WebError::Particles),
        };
        let mut config = Config::new(variant);
        config.seed = seed;
        let init = Ellipse {
            cx: Q16::from_f64(x + (w - 1.0) / 2.0),
            cy: Q16::from_f64(y + (h - 1.0) / 2.0),
            hx: Q16::from_f64(w / 2.0),
            hy: Q16::from_f64(h / 2.0),
        };
        tracker
            .start(config, frame, init)
            .map_err(WebError::Config)?;
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
        let mut session = Session::start(Variant::ColourPf, 50, 1, &view, box_).unwrap();
        assert_eq!(session.estimate().ellipse.cx, Q16::from_f64(27.5));
        for x0 in [22, 24, 26] {
            square(&mut frames, x0);
            let e = session.step(&frames.view().unwrap());
            assert!(
                (e.ellipse.cx.to_f64() - (x0 as f64 + 7.5)).abs() < 2.0,
                "{e:?}"
            );
            assert!(session.pixels_visited() > 0);
        }
    }

    #[test]
    fn bad_starts_say_why() {
        let mut frames = Frames::new();
        square(&mut frames, 20);
        let view = frames.view().unwrap();
        let start = |n, b| {
            Session::start(Variant::Rbpf, n, 1, &view, b)
                .err()
                .map(WebError::code)
        };
        assert_eq!(start(30, (20.0, 16.0, 16.0, 16.0)), Some(-1));
        assert_eq!(start(25, (20.0, 16.0, 1.0, 1.0)), Some(-3));
        assert_eq!(start(25, (200.0, 16.0, 16.0, 16.0)), Some(-4));
        assert_eq!(start(25, (20.0, 16.0, 16.0, 16.0)), None);
    }

    /// CI passes the checksum the firmware printed in QEMU; the page's run must give it.
    #[test]
    fn the_firmware_scene_gives_the_firmwares_checksum() {
        let checksum = firmware_checksum().unwrap();
        assert_eq!(firmware_checksum(), Ok(checksum), "deterministic");
        match std::env::var("RBTRACK_FIRMWARE_CHECKSUM") {
            Ok(qemu) => assert_eq!(format!("{checksum:#018x}"), qemu.trim()),
            Err(_) => println!("no RBTRACK_FIRMWARE_CHECKSUM: {checksum:#018x} not compared"),
        }
    }
}
