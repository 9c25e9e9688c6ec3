//! Elliptical image windows.

use crate::fixed::Q16;

/// An axis-aligned ellipse in image coordinates.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Ellipse {
    /// Centre column, px, Q16.16 (pixel column `x` has its centre at `x`).
    pub cx: Q16,
    /// Centre row, px, Q16.16.
    pub cy: Q16,
    /// Horizontal half-axis, px, Q16.16 (> 0 for a non-empty window).
    pub hx: Q16,
    /// Vertical half-axis, px, Q16.16 (> 0 for a non-empty window).
    pub hy: Q16,
}
