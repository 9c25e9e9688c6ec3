//! The rbtrack Python module: OpenCV's tracker interface (`init`, `update`) over the
//! rbtrack core, NumPy `uint8` frames in. Built by maturin (`pip install ./python`); the
//! stubs and docs of the Python API are `rbtrack.pyi`.

use numpy::PyReadonlyArrayDyn;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use rbtrack::tracker::{Config, Estimate, Status, Variant};
use rbtrack::RgbTracker;
use rbtrack_ffi::{ellipse_of_box, Track};

mod frame;

use frame::{Order, Pixels};

/// Particle counts offered.
const PARTICLES: [usize; 4] = [25, 50, 100, 200];

/// A tracker with OpenCV's interface: `init(frame, box)`, then `ok, box = update(frame)`.
#[pyclass(module = "rbtrack")]
struct Tracker {
    variant: Variant,
    particles: usize,
    seed: u64,
    order: Order,
    tracker: Box<dyn Track + Send + Sync>,
    /// The last estimate, `None` before `init`.
    estimate: Option<Estimate>,
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

/// The 0-based box `(x, y, w, h)`, px, as the core's ellipse; a `ValueError` unless finite.
fn ellipse(bbox: (f64, f64, f64, f64)) -> PyResult<rbtrack::Ellipse> {
    let (x, y, w, h) = bbox;
    if ![x, y, w, h].iter().all(|v| v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "box {bbox:?} must be four finite numbers"
        )));
    }
    Ok(ellipse_of_box(x, y, w, h))
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
}

#[pymethods]
impl Tracker {
    #[new]
    #[pyo3(signature = (variant = "rbpf", particles = 100, seed = 1, format = "bgr"))]
    fn new(variant: &str, particles: usize, seed: u64, format: &str) -> PyResult<Self> {
        let variant = match variant {
            "rbpf" => Variant::Rbpf,
            "pf" => Variant::ColourPf,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "variant must be 'rbpf' or 'pf', not {variant:?}"
                )))
            }
        };
        Ok(Self {
            variant,
            particles,
            seed,
            order: Order::named(format)?,
            tracker: unstarted(particles)?,
            estimate: None,
        })
    }

    /// Starts on the box `bbox` = `(x, y, w, h)` (px, 0-based) of `frame`.
    fn init(&mut self, frame: &Bound<'_, PyAny>, bbox: (f64, f64, f64, f64)) -> PyResult<()> {
        let array = frame::borrow(frame)?;
        let pixels = Pixels::of(&array, self.order)?;
        let mut config = Config::new(self.variant);
        config.seed = self.seed;
        let init = ellipse(bbox)?;
        self.tracker
            .start(config, &pixels.frame()?, init)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        self.estimate = Some(self.tracker.estimate());
        Ok(())
    }

    /// Tracks one frame, the GIL released; `(ok, (x, y, w, h))` with the box in whole
    /// pixels and `ok` false while the status is `"lost"`.
    fn update(
        &mut self,
        py: Python<'_>,
        frame: &Bound<'_, PyAny>,
    ) -> PyResult<(bool, (i32, i32, i32, i32))> {
        self.last()?;
        let array: PyReadonlyArrayDyn<'_, u8> = frame::borrow(frame)?;
        let pixels = Pixels::of(&array, self.order)?;
        let frame = pixels.frame()?;
        let tracker = &mut self.tracker;
        let estimate = py.detach(|| tracker.step(&frame));
        self.estimate = Some(estimate);
        Ok((estimate.status != Status::Lost, estimate.rect().px()))
    }

    /// Moves the tracker onto the box `bbox` = `(x, y, w, h)` of `frame` (a detector's, say),
    /// keeping the colour model it learnt.
    fn relocate(&mut self, frame: &Bound<'_, PyAny>, bbox: (f64, f64, f64, f64)) -> PyResult<()> {
        self.last()?;
        let array = frame::borrow(frame)?;
        let pixels = Pixels::of(&array, self.order)?;
        let at = ellipse(bbox)?;
        self.tracker
            .relocate(&pixels.frame()?, at)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        self.estimate = Some(self.tracker.estimate());
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

    /// How sure the tracker is, 0..1.
    #[getter]
    fn confidence(&self) -> PyResult<f64> {
        Ok(self.last()?.confidence.to_f64())
    }

    /// `"rbpf"` or `"pf"`.
    #[getter]
    fn variant(&self) -> &'static str {
        match self.variant {
            Variant::Rbpf => "rbpf",
            Variant::ColourPf => "pf",
        }
    }

    /// Particles.
    #[getter]
    fn particles(&self) -> usize {
        self.particles
    }

    /// Seed of the random draws.
    #[getter]
    fn seed(&self) -> u64 {
        self.seed
    }

    /// `"bgr"`, `"rgb"` or `"gray"`.
    #[getter]
    fn format(&self) -> &'static str {
        self.order.name()
    }

    fn __repr__(&self) -> String {
        format!(
            "rbtrack.Tracker(variant={:?}, particles={}, seed={}, format={:?})",
            self.variant(),
            self.particles,
            self.seed,
            self.order.name()
        )
    }
}

/// `Tracker(...)`, named as OpenCV names its factories (`cv2.TrackerCSRT_create`).
#[pyfunction]
#[pyo3(name = "TrackerCreate", signature = (variant = "rbpf", particles = 100, seed = 1, format = "bgr"))]
fn tracker_create(variant: &str, particles: usize, seed: u64, format: &str) -> PyResult<Tracker> {
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
