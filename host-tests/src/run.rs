//! Runs the core tracker over [`Frame`]s in any of the core's pixel formats: the glue
//! between frames, boxes and the `no_std` API, shared by the command-line program and the
//! behaviour tests. Each frame is handed to the tracker in its own format, as a camera
//! would deliver it.
//!
//! Particle counts are const generics in the core; [`Options::particles`] picks one of
//! [`PARTICLE_COUNTS`] at run time. Colour bins: 8x8x8 RGB (512).

use crate::cf64;
use crate::metrics::BBox;
use crate::pixels::{Format, Frame};
use rbtrack::fixed::Q16;
use rbtrack::image::{
    Binning, Gray8, ImageView, Luma64, PixelFormat, Rgb565Be, Rgb565Le, Rgb888, Rgb8x8x4, Rgb8x8x8,
    Uyvy, Yuv8x8x4, Yuyv,
};
use rbtrack::tracker::{
    CameraMotion, CfConfig, CfTracker, Config, ConfigError, Estimate, Tracker, Variant,
};
use rbtrack::window::Ellipse;
use rbtrack::Rect;
use std::fmt;
use std::time::{Duration, Instant};

/// Particle counts the harness can run (the core takes any `N` in `1..=65535`).
pub const PARTICLE_COUNTS: [usize; 6] = [25, 50, 100, 200, 400, 800];

/// What to run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Tracker configuration (variant, seed, noise levels...).
    pub config: Config,
    /// Particles and colour bins.
    pub shape: Shape,
    /// With settings, the f64 correlation-filter tracker runs instead of the core's.
    pub cf64: Option<cf64::Params>,
    /// With settings, the core's correlation-filter tracker runs instead of a particle
    /// filter.
    pub cf: Option<CoreCf>,
}

/// The core correlation-filter tracker's configuration and sizes (its const generics).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CoreCf {
    /// Its settings.
    pub config: CfConfig,
    /// Cells a side, `G`: one of [`CF_SHAPES`] with `scales`.
    pub grid: usize,
    /// Scales, `S`.
    pub scales: usize,
}

impl Default for CoreCf {
    /// The defaults: [`CF_GRID`] cells a side, [`CF_SCALES`] scales.
    fn default() -> Self {
        Self {
            config: CfConfig::default(),
            grid: CF_GRID,
            scales: CF_SCALES,
        }
    }
}

impl Options {
    /// The defaults for `variant`, 100 particles, 8x8x8 RGB bins.
    pub fn new(variant: Variant) -> Self {
        Self {
            config: Config::new(variant),
            shape: Shape::default(),
            cf64: None,
            cf: None,
        }
    }
}

/// The tracker's sizes: particle count and colour binning (the core's const generics).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shape {
    /// Particle count, one of [`PARTICLE_COUNTS`].
    pub particles: usize,
    /// Colour binning.
    pub bins: Bins,
}

impl Default for Shape {
    /// 100 particles, 8x8x8 RGB bins.
    fn default() -> Self {
        Self {
            particles: 100,
            bins: Bins::Rgb8x8x8,
        }
    }
}

/// The core's colour binnings by name.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Bins {
    /// 512 bins, 3 bits each of R, G, B (`rbtrack::image::Rgb8x8x8`).
    #[default]
    #[value(name = "rgb8x8x8")]
    #[serde(rename = "rgb8x8x8")]
    Rgb8x8x8,
    /// 256 bins, 3 bits of R and G, 2 of B (`Rgb8x8x4`).
    #[value(name = "rgb8x8x4")]
    #[serde(rename = "rgb8x8x4")]
    Rgb8x8x4,
    /// 256 bins, 3 bits of U and V, 2 of Y (`Yuv8x8x4`).
    #[value(name = "yuv8x8x4")]
    #[serde(rename = "yuv8x8x4")]
    Yuv8x8x4,
    /// 64 bins of luma (`Luma64`).
    #[value(name = "luma64")]
    Luma64,
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
    /// The f64 correlation-filter tracker rejected its settings or the initial box.
    Cf64(String),
    /// The core correlation-filter tracker's grid and scales are not one of [`CF_SHAPES`].
    CfShape(usize, usize),
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Particles(n) => write!(f, "--particles {n}: choose one of {PARTICLE_COUNTS:?}"),
            Self::Frame(e) => write!(f, "bad frame: {e}"),
            Self::Config(e) => write!(f, "{e}"),
            Self::Cf64(e) => write!(f, "cf64: {e}"),
            Self::CfShape(g, n) => write!(
                f,
                "cf.grid={g}, cf.scales={n}: the integer tracker has (grid, scales) {CF_SHAPES:?}"
            ),
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
    /// Time inside `step`.
    pub elapsed: Duration,
    /// Pixels the step read into histograms.
    pub pixels_visited: u32,
}

/// A tracker of any supported size behind one interface.
pub trait Run {
    /// Tracks one frame.
    fn step(&mut self, frame: &Frame) -> Result<Step, RunError>;
    /// Tells the tracker how the picture moved before the next frame
    /// (`Tracker::camera_moved`).
    fn camera_moved(&mut self, motion: &CameraMotion);
    /// The current estimate (the initial box's before any step).
    fn estimate(&self) -> Estimate;
    /// The ground-plane slope in use (`Tracker::scale_per_row`), px/px.
    fn scale_per_row(&self) -> Q16;
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

struct Runner<Bn: Binning, const N: usize, const B: usize> {
    tracker: Tracker<Bn, N, B>,
}

fn view<P: PixelFormat>(frame: &Frame) -> Result<ImageView<'_, P>, RunError> {
    let (w, h) = (frame.width as usize, frame.height as usize);
    ImageView::new(&frame.bytes, w, h, w).map_err(|e| RunError::Frame(e.to_string()))
}

/// Evaluates `$body` with `$view` the frame's checked [`ImageView`] in its own format.
macro_rules! with_view {
    ($frame:expr, $view:ident => $body:expr) => {
        match $frame.format {
            Format::Gray8 => {
                let $view = view::<Gray8>($frame)?;
                $body
            }
            Format::Rgb565Le => {
                let $view = view::<Rgb565Le>($frame)?;
                $body
            }
            Format::Rgb565Be => {
                let $view = view::<Rgb565Be>($frame)?;
                $body
            }
            Format::Rgb888 => {
                let $view = view::<Rgb888>($frame)?;
                $body
            }
            Format::Yuyv => {
                let $view = view::<Yuyv>($frame)?;
                $body
            }
            Format::Uyvy => {
                let $view = view::<Uyvy>($frame)?;
                $body
            }
        }
    };
}

impl<Bn: Binning, const N: usize, const B: usize> Runner<Bn, N, B> {
    fn start(config: Config, frame: &Frame, init: &BBox) -> Result<Self, RunError> {
        let init = ellipse_of(init);
        let tracker =
            with_view!(frame, v => Tracker::new(config, &v, init)).map_err(RunError::Config)?;
        Ok(Self { tracker })
    }
}

impl<Bn: Binning, const N: usize, const B: usize> Run for Runner<Bn, N, B> {
    fn step(&mut self, frame: &Frame) -> Result<Step, RunError> {
        let (estimate, elapsed) = with_view!(frame, v => {
            let start = Instant::now();
            let e = self.tracker.step(&v);
            (e, start.elapsed())
        });
        Ok(Step {
            estimate,
            bbox: bbox_of(&estimate),
            elapsed,
            pixels_visited: self.tracker.pixels_visited(),
        })
    }

    fn camera_moved(&mut self, motion: &CameraMotion) {
        self.tracker.camera_moved(motion);
    }

    fn estimate(&self) -> Estimate {
        self.tracker.estimate()
    }

    fn scale_per_row(&self) -> Q16 {
        self.tracker.scale_per_row()
    }
}

/// Starts a tracker on the first frame and box `init` (0-based): the f64
/// correlation-filter tracker where `options` give its settings, else the core's.
pub fn start(options: &Options, frame: &Frame, init: &BBox) -> Result<Box<dyn Run>, RunError> {
    if let Some(params) = options.cf64 {
        let tracker = with_rgb(frame, |img| {
            cf64::Tracker::new(params, img, init, options.config.seed)
        })
        .map_err(RunError::Cf64)?;
        return Ok(Box::new(Cf64Runner { tracker }));
    }
    if let Some(cf) = options.cf {
        macro_rules! by_shape {
            ($bn:ty, $b:literal) => {
                match (cf.grid, cf.scales) {
                    (16, 8) => CfRunner::<$bn, $b, 16, 8>::start(cf.config, frame, init),
                    (16, 5) => CfRunner::<$bn, $b, 16, 5>::start(cf.config, frame, init),
                    (16, 4) => CfRunner::<$bn, $b, 16, 4>::start(cf.config, frame, init),
                    (8, 8) => CfRunner::<$bn, $b, 8, 8>::start(cf.config, frame, init),
                    (8, 4) => CfRunner::<$bn, $b, 8, 4>::start(cf.config, frame, init),
                    (g, n) => Err(RunError::CfShape(g, n)),
                }
            };
        }
        return match options.shape.bins {
            Bins::Rgb8x8x8 => by_shape!(Rgb8x8x8, 512),
            Bins::Rgb8x8x4 => by_shape!(Rgb8x8x4, 256),
            Bins::Yuv8x8x4 => by_shape!(Yuv8x8x4, 256),
            Bins::Luma64 => by_shape!(Luma64, 64),
        };
    }
    fn boxed<Bn: Binning, const N: usize, const B: usize>(
        config: Config,
        frame: &Frame,
        init: &BBox,
    ) -> Result<Box<dyn Run>, RunError> {
        Ok(Box::new(Runner::<Bn, N, B>::start(config, frame, init)?))
    }
    /// `boxed` for the binning `$bn` of `$b` bins and every particle count.
    macro_rules! by_count {
        ($bn:ty, $b:literal) => {
            match options.shape.particles {
                25 => boxed::<$bn, 25, $b>(options.config, frame, init),
                50 => boxed::<$bn, 50, $b>(options.config, frame, init),
                100 => boxed::<$bn, 100, $b>(options.config, frame, init),
                200 => boxed::<$bn, 200, $b>(options.config, frame, init),
                400 => boxed::<$bn, 400, $b>(options.config, frame, init),
                800 => boxed::<$bn, 800, $b>(options.config, frame, init),
                n => Err(RunError::Particles(n)),
            }
        };
    }
    match options.shape.bins {
        Bins::Rgb8x8x8 => by_count!(Rgb8x8x8, 512),
        Bins::Rgb8x8x4 => by_count!(Rgb8x8x4, 256),
        Bins::Yuv8x8x4 => by_count!(Yuv8x8x4, 256),
        Bins::Luma64 => by_count!(Luma64, 64),
    }
}

/// Cells a side of the host's correlation-filter tracker by default.
pub const CF_GRID: usize = 16;
/// Its scales by default.
pub const CF_SCALES: usize = 4;
/// The (grid, scales) the host runs the core correlation-filter tracker at: the default,
/// then the others `examples/budget.rs` prices.
pub const CF_SHAPES: [(usize, usize); 5] = [(CF_GRID, CF_SCALES), (16, 5), (16, 8), (8, 8), (8, 4)];

/// The core's correlation-filter tracker behind [`Run`], on the heap (it is large).
struct CfRunner<Bn: Binning, const B: usize, const G: usize, const S: usize> {
    tracker: Box<CfTracker<Bn, B, G, S>>,
}

impl<Bn: Binning, const B: usize, const G: usize, const S: usize> CfRunner<Bn, B, G, S> {
    fn start(config: CfConfig, frame: &Frame, init: &BBox) -> Result<Box<dyn Run>, RunError> {
        let mut tracker = Box::new(CfTracker::unstarted());
        let init = Rect::from(ellipse_of(init));
        with_view!(frame, v => tracker.start(config, &v, init)).map_err(RunError::Config)?;
        Ok(Box::new(Self { tracker }))
    }
}

impl<Bn: Binning, const B: usize, const G: usize, const S: usize> Run for CfRunner<Bn, B, G, S> {
    fn step(&mut self, frame: &Frame) -> Result<Step, RunError> {
        let (estimate, elapsed) = with_view!(frame, v => {
            let start = Instant::now();
            let e = self.tracker.step(&v);
            (e, start.elapsed())
        });
        Ok(Step {
            estimate,
            bbox: bbox_of(&estimate),
            elapsed,
            pixels_visited: 0,
        })
    }

    fn camera_moved(&mut self, motion: &CameraMotion) {
        self.tracker.camera_moved(motion);
    }

    fn estimate(&self) -> Estimate {
        *self.tracker.estimate()
    }

    fn scale_per_row(&self) -> Q16 {
        Q16::ZERO
    }
}

/// The f64 correlation-filter tracker behind [`Run`]. Its estimate's ellipse is its box's,
/// its velocity the last move, its confidence and status [`cf64::Output`]'s.
struct Cf64Runner {
    tracker: cf64::Tracker,
}

/// An RGB888 view of a frame for the f64 tracker, converted where it is in another format.
fn with_rgb<T>(frame: &Frame, body: impl FnOnce(&cf64::image::RgbImage) -> T) -> T {
    let owned;
    let rgb = match frame.format {
        Format::Rgb888 => &frame.bytes,
        _ => {
            owned = frame.to_rgb888();
            &owned
        }
    };
    body(&cf64::image::RgbImage {
        width: frame.width as usize,
        height: frame.height as usize,
        rgb,
    })
}

/// The core's form of an f64 tracker's answer.
fn cf64_estimate(out: &cf64::Output) -> Estimate {
    Estimate {
        ellipse: ellipse_of(&out.bbox),
        vx: Q16::from_f64(out.velocity.0),
        vy: Q16::from_f64(out.velocity.1),
        score: Q16::from_f64(out.score),
        confidence: Q16::from_f64(out.confidence),
        status: out.status,
    }
}

impl Run for Cf64Runner {
    fn step(&mut self, frame: &Frame) -> Result<Step, RunError> {
        let (out, elapsed) = with_rgb(frame, |img| {
            let start = Instant::now();
            let out = self.tracker.step(img);
            (out, start.elapsed())
        });
        Ok(Step {
            estimate: cf64_estimate(&out),
            bbox: out.bbox,
            elapsed,
            pixels_visited: 0,
        })
    }

    fn camera_moved(&mut self, motion: &CameraMotion) {
        let about = (motion.centre_x.to_f64(), motion.centre_y.to_f64());
        let shift = (motion.dx.to_f64(), motion.dy.to_f64());
        self.tracker
            .camera_moved(shift, motion.zoom.to_f64().clamp(0.125, 8.0), about);
    }

    fn estimate(&self) -> Estimate {
        cf64_estimate(&self.tracker.last())
    }

    fn scale_per_row(&self) -> Q16 {
        Q16::ZERO
    }
}

/// Tracks a whole sequence of frames from `init` (the box of frame 0). The first returned
/// box is `init` itself; then one step per following frame.
pub fn track<'a>(
    options: &Options,
    frames: impl IntoIterator<Item = &'a Frame>,
    init: &BBox,
) -> Result<(Vec<BBox>, Vec<Step>), RunError> {
    let mut frames = frames.into_iter();
    let Some(first) = frames.next() else {
        return Ok((Vec::new(), Vec::new()));
    };
    let mut runner = start(options, first, init)?;
    let mut boxes = vec![*init];
    let mut steps = Vec::new();
    for frame in frames {
        let step = runner.step(frame)?;
        boxes.push(step.bbox);
        steps.push(step);
    }
    Ok((boxes, steps))
}
