//! Runs the core tracker over RGB888 frames: the glue between frames, boxes and the
//! `no_std` API, shared by the command-line program and the behaviour tests.
//!
//! Particle counts are const generics in the core; [`Options::particles`] picks one of
//! [`PARTICLE_COUNTS`] at run time. Colour bins: 8x8x8 RGB (512).

use crate::metrics::BBox;
use rbtrack::fixed::Q16;
use rbtrack::image::{ImageView, PixelFormat, Rgb565Le, Rgb888, Rgb8x8x8};
use rbtrack::tracker::{Config, ConfigError, Estimate, Tracker, Variant};
use rbtrack::window::Ellipse;
use std::fmt;
use std::time::{Duration, Instant};

/// Particle counts the harness can run (the core takes any `N` in `1..=65535`).
pub const PARTICLE_COUNTS: [usize; 6] = [25, 50, 100, 200, 400, 800];

/// Pixel format the frames are handed to the tracker in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// 3 bytes per pixel, as decoded.
    Rgb888,
    /// Converted to RGB565 little-endian first, as a camera delivers.
    Rgb565,
}

/// What to run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Tracker configuration (variant, seed, noise levels...).
    pub config: Config,
    /// Particle count, one of [`PARTICLE_COUNTS`].
    pub particles: usize,
    /// Pixel format handed to the tracker.
    pub format: Format,
}

impl Options {
    /// The defaults for `variant`: 100 particles, RGB888.
    pub fn new(variant: Variant) -> Self {
        Self {
            config: Config::new(variant),
            particles: 100,
            format: Format::Rgb888,
        }
    }
}

/// Why a run could not start.
#[derive(Clone, Debug, PartialEq)]
pub enum RunError {
    /// The particle count is not one of [`PARTICLE_COUNTS`].
    Particles(usize),
    /// The frame buffer does not match its size.
    Frame(String),
    /// The tracker rejected the configuration or the initial box.
    Config(ConfigError),
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Particles(n) => write!(f, "--particles {n}: choose one of {PARTICLE_COUNTS:?}"),
            Self::Frame(e) => write!(f, "bad frame: {e}"),
            Self::Config(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for RunError {}

/// One tracked frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    /// The core's estimate.
    pub estimate: Estimate,
    /// Its box.
    pub bbox: BBox,
    /// Time inside `step` (format conversion excluded).
    pub elapsed: Duration,
    /// Pixels the step read into histograms.
    pub pixels_visited: u32,
}

/// A tracker of any supported size behind one interface.
pub trait Run {
    /// Tracks one RGB888 frame of `width x height` px.
    fn step(&mut self, rgb: &[u8], width: usize, height: usize) -> Result<Step, RunError>;
}

/// The ellipse of a 0-based box ([`BBox::to_ellipse_f64`]) in Q16.16.
pub fn ellipse_of(b: &BBox) -> Ellipse {
    let (cx, cy, hx, hy) = b.to_ellipse_f64();
    Ellipse {
        cx: Q16::from_f64(cx),
        cy: Q16::from_f64(cy),
        hx: Q16::from_f64(hx),
        hy: Q16::from_f64(hy),
    }
}

/// The box of an estimate.
pub fn bbox_of(e: &Estimate) -> BBox {
    let el = e.ellipse;
    BBox::from_ellipse(
        el.cx.to_f64(),
        el.cy.to_f64(),
        el.hx.to_f64(),
        el.hy.to_f64(),
    )
}

struct Runner<const N: usize> {
    tracker: Tracker<Rgb8x8x8, N, 512>,
    format: Format,
    scratch: Vec<u8>,
}

fn view<'a, P: PixelFormat>(
    buf: &'a [u8],
    width: usize,
    height: usize,
) -> Result<ImageView<'a, P>, RunError> {
    ImageView::new(buf, width, height, width).map_err(|e| RunError::Frame(e.to_string()))
}

fn rgb565_into(rgb: &[u8], out: &mut Vec<u8>) {
    out.clear();
    for p in rgb.chunks_exact(3) {
        let v = ((p[0] as u16 >> 3) << 11) | ((p[1] as u16 >> 2) << 5) | (p[2] as u16 >> 3);
        out.extend_from_slice(&v.to_le_bytes());
    }
}

impl<const N: usize> Runner<N> {
    fn start(
        options: &Options,
        rgb: &[u8],
        width: usize,
        height: usize,
        init: &BBox,
    ) -> Result<Self, RunError> {
        let init = ellipse_of(init);
        let mut scratch = Vec::new();
        let tracker = match options.format {
            Format::Rgb888 => {
                Tracker::new(options.config, &view::<Rgb888>(rgb, width, height)?, init)
            }
            Format::Rgb565 => {
                rgb565_into(rgb, &mut scratch);
                Tracker::new(
                    options.config,
                    &view::<Rgb565Le>(&scratch, width, height)?,
                    init,
                )
            }
        }
        .map_err(RunError::Config)?;
        Ok(Self {
            tracker,
            format: options.format,
            scratch,
        })
    }
}

impl<const N: usize> Run for Runner<N> {
    fn step(&mut self, rgb: &[u8], width: usize, height: usize) -> Result<Step, RunError> {
        let (estimate, elapsed) = match self.format {
            Format::Rgb888 => {
                let frame = view::<Rgb888>(rgb, width, height)?;
                let start = Instant::now();
                let e = self.tracker.step(&frame);
                (e, start.elapsed())
            }
            Format::Rgb565 => {
                rgb565_into(rgb, &mut self.scratch);
                let frame = view::<Rgb565Le>(&self.scratch, width, height)?;
                let start = Instant::now();
                let e = self.tracker.step(&frame);
                (e, start.elapsed())
            }
        };
        Ok(Step {
            estimate,
            bbox: bbox_of(&estimate),
            elapsed,
            pixels_visited: self.tracker.pixels_visited(),
        })
    }
}

/// Starts a tracker on the first frame (`width x height` RGB888) and box `init` (0-based).
pub fn start(
    options: &Options,
    rgb: &[u8],
    width: usize,
    height: usize,
    init: &BBox,
) -> Result<Box<dyn Run>, RunError> {
    fn boxed<const N: usize>(
        o: &Options,
        rgb: &[u8],
        w: usize,
        h: usize,
        init: &BBox,
    ) -> Result<Box<dyn Run>, RunError> {
        Ok(Box::new(Runner::<N>::start(o, rgb, w, h, init)?))
    }
    match options.particles {
        25 => boxed::<25>(options, rgb, width, height, init),
        50 => boxed::<50>(options, rgb, width, height, init),
        100 => boxed::<100>(options, rgb, width, height, init),
        200 => boxed::<200>(options, rgb, width, height, init),
        400 => boxed::<400>(options, rgb, width, height, init),
        800 => boxed::<800>(options, rgb, width, height, init),
        n => Err(RunError::Particles(n)),
    }
}

/// Tracks a whole sequence of RGB888 frames from `init` (the box of frame 0). The first
/// returned box is `init` itself; then one step per following frame.
pub fn track<'a>(
    options: &Options,
    frames: impl IntoIterator<Item = (&'a [u8], usize, usize)>,
    init: &BBox,
) -> Result<(Vec<BBox>, Vec<Step>), RunError> {
    let mut frames = frames.into_iter();
    let Some((rgb, w, h)) = frames.next() else {
        return Ok((Vec::new(), Vec::new()));
    };
    let mut runner = start(options, rgb, w, h, init)?;
    let mut boxes = vec![*init];
    let mut steps = Vec::new();
    for (rgb, w, h) in frames {
        let step = runner.step(rgb, w, h)?;
        boxes.push(step.bbox);
        steps.push(step);
    }
    Ok((boxes, steps))
}
