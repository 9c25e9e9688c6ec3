//! [`Track`]: a particle filter of any size and binning behind one object-safe
//! interface, and [`CfTrack`]: the correlation-filter tracker of any grid and scales; both
//! over frames of any [`Format`](crate::Format).

use crate::frame::{with_view, Frame};
use rbtrack::image::Binning;
use rbtrack::tracker::{CameraMotion, CfConfig, CfTracker, Config, ConfigError, Estimate, Tracker};
use rbtrack::{Ellipse, Rect, Q16};

/// The tracker's life over [`Frame`]s: [`Tracker`]'s methods of the same names.
pub trait Track {
    /// [`Tracker::start`].
    ///
    /// # Errors
    /// [`Tracker::start`]'s.
    fn start(
        &mut self,
        config: Config,
        frame: &Frame<'_>,
        init: Ellipse,
    ) -> Result<(), ConfigError>;
    /// [`Tracker::reset`].
    ///
    /// # Errors
    /// [`Tracker::reset`]'s.
    fn reset(&mut self, frame: &Frame<'_>, init: Ellipse) -> Result<(), ConfigError>;
    /// [`Tracker::relocate`].
    ///
    /// # Errors
    /// [`Tracker::relocate`]'s.
    fn relocate(&mut self, frame: &Frame<'_>, at: Ellipse) -> Result<(), ConfigError>;
    /// [`Tracker::step`].
    fn step(&mut self, frame: &Frame<'_>) -> Estimate;
    /// [`Tracker::camera_moved`].
    fn camera_moved(&mut self, motion: &CameraMotion);
    /// [`Tracker::estimate`].
    fn estimate(&self) -> Estimate;
}

impl<Bn: Binning, const N: usize, const B: usize> Track for Tracker<Bn, N, B> {
    fn start(
        &mut self,
        config: Config,
        frame: &Frame<'_>,
        init: Ellipse,
    ) -> Result<(), ConfigError> {
        with_view!(frame, v => Tracker::start(self, config, v, init))
    }

    fn reset(&mut self, frame: &Frame<'_>, init: Ellipse) -> Result<(), ConfigError> {
        with_view!(frame, v => Tracker::reset(self, v, init))
    }

    fn relocate(&mut self, frame: &Frame<'_>, at: Ellipse) -> Result<(), ConfigError> {
        with_view!(frame, v => Tracker::relocate(self, v, at))
    }

    fn step(&mut self, frame: &Frame<'_>) -> Estimate {
        with_view!(frame, v => Tracker::step(self, v))
    }

    fn camera_moved(&mut self, motion: &CameraMotion) {
        Tracker::camera_moved(self, motion)
    }

    fn estimate(&self) -> Estimate {
        Tracker::estimate(self)
    }
}

/// The correlation-filter tracker's life over [`Frame`]s: [`CfTracker`]'s methods of the
/// same names.
pub trait CfTrack {
    /// [`CfTracker::start`].
    ///
    /// # Errors
    /// [`CfTracker::start`]'s.
    fn start(&mut self, config: CfConfig, frame: &Frame<'_>, init: Rect)
        -> Result<(), ConfigError>;
    /// [`CfTracker::relocate`].
    ///
    /// # Errors
    /// [`CfTracker::relocate`]'s.
    fn relocate(&mut self, frame: &Frame<'_>, init: Rect) -> Result<(), ConfigError>;
    /// [`CfTracker::step`].
    fn step(&mut self, frame: &Frame<'_>) -> Estimate;
    /// [`CfTracker::camera_moved`].
    fn camera_moved(&mut self, motion: &CameraMotion);
    /// [`CfTracker::estimate`].
    fn estimate(&self) -> Estimate;
}

impl<Bn: Binning, const B: usize, const G: usize, const S: usize> CfTrack
    for CfTracker<Bn, B, G, S>
{
    fn start(
        &mut self,
        config: CfConfig,
        frame: &Frame<'_>,
        init: Rect,
    ) -> Result<(), ConfigError> {
        with_view!(frame, v => CfTracker::start(self, config, v, init))
    }

    fn relocate(&mut self, frame: &Frame<'_>, init: Rect) -> Result<(), ConfigError> {
        with_view!(frame, v => CfTracker::relocate(self, v, init))
    }

    fn step(&mut self, frame: &Frame<'_>) -> Estimate {
        with_view!(frame, v => CfTracker::step(self, v))
    }

    fn camera_moved(&mut self, motion: &CameraMotion) {
        CfTracker::camera_moved(self, motion)
    }

    fn estimate(&self) -> Estimate {
        *CfTracker::estimate(self)
    }
}

/// The inscribed ellipse of the 0-based box `(x, y, w, h)`, px: centre
/// `(x + (w - 1) / 2, y + (h - 1) / 2)`, half-axes `w / 2`, `h / 2`, each computed in
/// `f64` and then rounded to Q16.16, as the host tool (`rbtrack track --init`) does, so
/// that a box with fractions starts the same tracker.
pub fn ellipse_of_box(x: f64, y: f64, w: f64, h: f64) -> Ellipse {
    Ellipse::new(
        Q16::from_f64(x + (w - 1.0) / 2.0),
        Q16::from_f64(y + (h - 1.0) / 2.0),
        Q16::from_f64(w / 2.0),
        Q16::from_f64(h / 2.0),
    )
}
