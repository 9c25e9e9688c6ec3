//! The rbtrack Python module: OpenCV's tracker interface (`init`, `update`) over the
//! rbtrack core, NumPy `uint8` frames in. Built by maturin (`pip install ./python`); the
//! stubs and docs of the Python API are `rbtrack.pyi`.

use numpy::PyReadonlyArrayDyn;
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use rbtrack::tracker::{CfConfig, Config, Estimate, Status, Variant};
use rbtrack::{Rect, RgbCfTracker, RgbTracker};
use rbtrack_ffi::{ellipse_of_box, CfTrack, Track};

mod frame;

use frame::{Order, Pixels};

/// Particle counts offered.
const PARTICLES: [usize; 4] = [25, 50, 100, 200];

/// A particle filter's particles unless given.
const DEFAULT_PARTICLES: usize = 100;

/// A particle filter's seed unless given.
const DEFAULT_SEED: u64 = 1;

/// The core tracker behind a [`Tracker`]: the correlation-filter tracker at its defaults
/// (`RgbCfTracker`: 16 x 16 cells, 4 scales, 512 RGB bins), or a particle filter.
enum Engine {
    Correlation(Box<dyn CfTrack + Send + Sync>),
    Particles {
        variant: Variant,
        particles: usize,
        seed: u64,
        tracker: Box<dyn Track + Send + Sync>,
    },
}

impl Engine {
    /// Tracks one frame.
    fn step(&mut self, frame: &rbtrack_ffi::Frame<'_>) -> Estimate {
        match self {
            Engine::Correlation(tracker) => tracker.step(frame),
            Engine::Particles { tracker, .. } => tracker.step(frame),
        }
    }

    /// The last estimate.
    fn estimate(&self) -> Estimate {
        match self {
            Engine::Correlation(tracker) => tracker.estimate(),
            Engine::Particles { tracker, .. } => tracker.estimate(),
        }
    }

    /// `"cf"`, `"rbpf"` or `"pf"`.
    fn name(&self) -> &'static str {
        match self {
            Engine::Correlation(_) => "cf",
            Engine::Particles {
                variant: Variant::Rbpf,
                ..
            } => "rbpf",
            Engine::Particles {
                variant: Variant::ColourPf,
                ..
            } => "pf",
        }
    }
}

/// A tracker with OpenCV's interface: `init(frame, box)`, then `ok, box = update(frame)`.
#[pyclass(module = "rbtrack")]
struct Tracker {
    order: Order,
    engine: Engine,
    /// The last estimate, `None` before `init`.
    estimate: Option<Estimate>,
    /// Width and height of `init`'s frame, px: every frame's after it.
    size: (usize, usize),
}

/// An unstarted tracker of `particles` particles on 512 RGB bins.
fn unstarted(particles: usize) -> PyResult<Box<dyn Track + Send + Sync>> {
    Ok(match particles {
        25 => Box::new(RgbTracker::<25>::unstarted()),
        50 => Box::new(RgbTracker::<50>::unstarted()),
        100 => Box::new(RgbTracker::<100>::unstarted()),
        200 => Box::new(RgbTracker::<200>::unstarted()),
        n => {
            return Err(PyValueError::new_err(format!(
                "particles must be one of {PARTICLES:?}, not {n}"
            )))
        }
    })
}

/// The 0-based box `bbox` = `(x, y, w, h)`, px, any sequence of 4 finite numbers, as the
/// core's ellipse; a `TypeError` for what is not a sequence of numbers, a `ValueError` for
/// another count or a number that is not finite.
fn ellipse(bbox: &Bound<'_, PyAny>) -> PyResult<rbtrack::Ellipse> {
    let shown = || bbox.repr().map_or_else(|_| "?".into(), |r| r.to_string());
    let numbers: Vec<f64> = bbox.extract().map_err(|_| {
        PyTypeError::new_err(format!("box must be 4 numbers x, y, w, h, not {}", shown()))
    })?;
    match numbers[..] {
        [x, y, w, h] if numbers.iter().all(|v| v.is_finite()) => Ok(ellipse_of_box(x, y, w, h)),
        [_, _, _, _] => Err(PyValueError::new_err(format!(
            "box must be 4 finite numbers x, y, w, h, not {}",
            shown()
        ))),
        _ => Err(PyValueError::new_err(format!(
            "box must be 4 numbers x, y, w, h, not {} ({})",
            numbers.len(),
            shown()
        ))),
    }
}

/// `status`'s name: `"tracking"`, `"uncertain"` or `"lost"`.
fn status_name(status: Status) -> &'static str {
    match status {
        Status::Tracking => "tracking",
        Status::Uncertain => "uncertain",
        Status::Lost => "lost",
    }
}

impl Tracker {
    /// The last estimate, or a `RuntimeError` before `init`.
    fn last(&self) -> PyResult<Estimate> {
        self.estimate
            .ok_or_else(|| PyRuntimeError::new_err("the tracker has no target: call init first"))
    }

    /// A `ValueError` unless `pixels` are of the size of `init`'s frame.
    fn check_size(&self, pixels: &Pixels<'_>) -> PyResult<()> {
        let ((w, h), (init_w, init_h)) = (pixels.size(), self.size);
        if (w, h) == self.size {
            return Ok(());
        }
        Err(PyValueError::new_err(format!(
            "frame is {w} x {h} px, but init's was {init_w} x {init_h} px: a tracker takes \
             frames of one size (init again for another)"
        )))
    }
}

#[pymethods]
impl Tracker {
    #[new]
    #[pyo3(signature = (variant = "cf", particles = None, seed = None, format = "bgr"))]
    fn new(
        variant: &str,
        particles: Option<usize>,
        seed: Option<u64>,
        format: &str,
    ) -> PyResult<Self> {
        let variant = match variant {
            "cf" => None,
            "rbpf" => Some(Variant::Rbpf),
            "pf" => Some(Variant::ColourPf),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "variant must be 'cf', 'rbpf' or 'pf', not {variant:?}"
                )))
            }
        };
        let engine = match variant {
            None if particles.is_some() || seed.is_some() => {
                return Err(PyValueError::new_err(
                    "the correlation-filter tracker ('cf') has no particles and no seed: \
                     they are the particle filters' ('rbpf', 'pf')",
                ))
            }
            None => Engine::Correlation(Box::new(RgbCfTracker::unstarted())),
            Some(variant) => {
                let particles = particles.unwrap_or(DEFAULT_PARTICLES);
                Engine::Particles {
                    variant,
                    particles,
                    seed: seed.unwrap_or(DEFAULT_SEED),
                    tracker: unstarted(particles)?,
                }
            }
        };
        Ok(Self {
            order: Order::named(format)?,
            engine,
            estimate: None,
            size: (0, 0),
        })
    }

    /// Starts on the box `bbox` = `(x, y, w, h)` (px, 0-based) of `frame`.
    fn init(&mut self, frame: &Bound<'_, PyAny>, bbox: &Bound<'_, PyAny>) -> PyResult<()> {
        let array = frame::borrow(frame)?;
        let pixels = Pixels::of(&array, self.order)?;
        let frame = pixels.frame()?;
        let init = ellipse(bbox)?;
        let started = match &mut self.engine {
            Engine::Correlation(tracker) => {
                tracker.start(CfConfig::default(), &frame, Rect::from(init))
            }
            Engine::Particles {
                variant,
                seed,
                tracker,
                ..
            } => {
                let mut config = Config::new(*variant);
                config.seed = *seed;
                tracker.start(config, &frame, init)
            }
        };
        started.map_err(|e| PyValueError::new_err(e.to_string()))?;
        self.estimate = Some(self.engine.estimate());
        self.size = pixels.size();
        Ok(())
    }

    /// Tracks one frame of `init`'s frame's size, the GIL released; `(ok, (x, y, w, h))`
    /// with the box in whole pixels and `ok` false while the status is `"lost"`.
    fn update(
        &mut self,
        py: Python<'_>,
        frame: &Bound<'_, PyAny>,
    ) -> PyResult<(bool, (i32, i32, i32, i32))> {
        self.last()?;
        let array: PyReadonlyArrayDyn<'_, u8> = frame::borrow(frame)?;
        let pixels = Pixels::of(&array, self.order)?;
        self.check_size(&pixels)?;
        let frame = pixels.frame()?;
        let engine = &mut self.engine;
        let estimate = py.detach(|| engine.step(&frame));
        self.estimate = Some(estimate);
        Ok((estimate.status != Status::Lost, estimate.rect().px()))
    }

    /// Moves the tracker onto the box `bbox` = `(x, y, w, h)` of `frame` (a detector's, say;
    /// of `init`'s frame's size), keeping what it learnt: a particle filter's colour model,
    /// the correlation-filter tracker's filter, colour model and scale filter.
    fn relocate(&mut self, frame: &Bound<'_, PyAny>, bbox: &Bound<'_, PyAny>) -> PyResult<()> {
        self.last()?;
        let array = frame::borrow(frame)?;
        let pixels = Pixels::of(&array, self.order)?;
        self.check_size(&pixels)?;
        let at = ellipse(bbox)?;
        let frame = pixels.frame()?;
        match &mut self.engine {
            Engine::Correlation(tracker) => tracker.relocate(&frame, Rect::from(at)),
            Engine::Particles { tracker, .. } => tracker.relocate(&frame, at),
        }
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
        self.estimate = Some(self.engine.estimate());
        Ok(())
    }

    /// The last box `(x, y, w, h)`, px, exact (multiples of 1/65536).
    #[getter(r#box)]
    fn bbox(&self) -> PyResult<(f64, f64, f64, f64)> {
        let r = self.last()?.rect();
        Ok((r.x.to_f64(), r.y.to_f64(), r.w.to_f64(), r.h.to_f64()))
    }

    /// The last ellipse `(cx, cy, hx, hy)`: centre and half-axes, px.
    #[getter]
    fn ellipse(&self) -> PyResult<(f64, f64, f64, f64)> {
        let e = self.last()?.ellipse;
        Ok((e.cx.to_f64(), e.cy.to_f64(), e.hx.to_f64(), e.hy.to_f64()))
    }

    /// `"tracking"`, `"uncertain"` or `"lost"`.
    #[getter]
    fn status(&self) -> PyResult<&'static str> {
        Ok(status_name(self.last()?.status))
    }

    /// How sure the tracker is, 0..1: about the chance that the box overlaps the
    /// target's by an IoU of at least 0.5, alike for every tracker; it sets the status.
    #[getter]
    fn confidence(&self) -> PyResult<f64> {
        Ok(self.last()?.confidence.to_f64())
    }

    /// The tracker's own score, 0..1, before calibration (a particle filter's colour
    /// coefficient less its spread, the correlation filter's merged response margin).
    #[getter]
    fn score(&self) -> PyResult<f64> {
        Ok(self.last()?.score.to_f64())
    }

    /// `"cf"`, `"rbpf"` or `"pf"`.
    #[getter]
    fn variant(&self) -> &'static str {
        self.engine.name()
    }

    /// A particle filter's particles; `None` for the correlation-filter tracker.
    #[getter]
    fn particles(&self) -> Option<usize> {
        match self.engine {
            Engine::Correlation(_) => None,
            Engine::Particles { particles, .. } => Some(particles),
        }
    }

    /// A particle filter's seed of the random draws; `None` for the correlation-filter
    /// tracker (it draws none).
    #[getter]
    fn seed(&self) -> Option<u64> {
        match self.engine {
            Engine::Correlation(_) => None,
            Engine::Particles { seed, .. } => Some(seed),
        }
    }

    /// `"bgr"`, `"rgb"` or `"gray"`.
    #[getter]
    fn format(&self) -> &'static str {
        self.order.name()
    }

    fn __repr__(&self) -> String {
        let format = self.order.name();
        match self.engine {
            Engine::Correlation(_) => format!("rbtrack.Tracker(variant=\"cf\", format={format:?})"),
            Engine::Particles {
                particles, seed, ..
            } => format!(
                "rbtrack.Tracker(variant={:?}, particles={particles}, seed={seed}, format={format:?})",
                self.engine.name(),
            ),
        }
    }
}

/// `Tracker(...)`, named as OpenCV names its factories (`cv2.TrackerCSRT_create`).
#[pyfunction]
#[pyo3(name = "TrackerCreate", signature = (variant = "cf", particles = None, seed = None, format = "bgr"))]
fn tracker_create(
    variant: &str,
    particles: Option<usize>,
    seed: Option<u64>,
    format: &str,
) -> PyResult<Tracker> {
    Tracker::new(variant, particles, seed, format)
}

/// Whether `frame` would be tracked in place, without a copy, in `format`.
#[pyfunction]
#[pyo3(signature = (frame, format = "bgr"))]
fn frame_is_borrowed(frame: &Bound<'_, PyAny>, format: &str) -> PyResult<bool> {
    let array = frame::borrow(frame)?;
    Ok(Pixels::of(&array, Order::named(format)?)?.borrowed())
}

/// The rbtrack visual object tracker (rbtrack.pyi documents it).
#[pymodule(name = "rbtrack")]
fn rbtrack_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Tracker>()?;
    m.add_function(wrap_pyfunction!(tracker_create, m)?)?;
    m.add_function(wrap_pyfunction!(frame_is_borrowed, m)?)?;
    m.add("PARTICLES", PARTICLES.to_vec())?;
    Ok(())
}
