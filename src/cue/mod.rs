//! The boundary-gradient cue: how strongly the luma edges of a frame follow an ellipse.
//!
//! # Definition
//! The 5-tap operator on luma `I`, with coordinates clamped at the frame borders:
//! `gx = I(x+2, y) + 2 I(x+1, y) - 2 I(x-1, y) - I(x-2, y)`, `gy` likewise in `y`,
//! `|g| = sqrt(gx^2 + gy^2)` (0..=1082 for 8-bit luma).
//!
//! For `K` boundary points `b_k = (cx + hx cos t_k, cy + hy sin t_k)`, `t_k = 2 pi k / K`,
//! the cue searches along the ellipse's unit normal `n_k ∝ (cos t_k / hx, sin t_k / hy)`
//! at the pixels nearest to `b_k + j n_k`, `j = -search..=search` px (halves rounded up),
//! skipping pixels outside the frame, and keeps the largest magnitude `m_k` (0 if none
//! is in the frame). The cue is `g = (1/K) sum_k min(m_k / saturation, 1)`, in `[0, 1]`.
//!
//! # Fixed point
//! `cos t_k`, `sin t_k` are Q16.16 tables built once by [`GradientCue::new`] (integer
//! series, equal to the rounded `f64` functions).
//! Per boundary point the unit normal takes a table square root and two 32-bit
//! divisions, and the search positions are 32-bit. The search compares squared
//! magnitudes (integers); a point whose largest one reaches the saturation scores 1
//! without a square root, the others take one table square root (`m_k` to 1/32). The mean
//! multiplies by a reciprocal tabulated at construction: no 64-bit division. Against
//! an f64 evaluation of the same definition the error is below 1e-3 except where a
//! sample position lies within about 1e-4 px of a pixel boundary and rounds the other
//! way (see `host-tests/tests/gradient_reference.rs`).
//!
//! # Examples
//! ```
//! use rbtrack::cue::{GradientConfig, GradientCue};
//! use rbtrack::fixed::Q16;
//! use rbtrack::image::{Gray8, ImageView};
//! use rbtrack::window::Ellipse;
//! // A bright disc of radius 10 px centred at (20, 20) on black.
//! let mut buf = [0u8; 40 * 40];
//! for (i, p) in buf.iter_mut().enumerate() {
//!     let (x, y) = ((i % 40) as i32 - 20, (i / 40) as i32 - 20);
//!     *p = if x * x + y * y <= 100 { 200 } else { 0 };
//! }
//! let img = ImageView::<Gray8>::new(&buf, 40, 40, 40)?;
//! let cue = GradientCue::new(&GradientConfig::new()).expect("default config is valid");
//! let q = |v: i32| Q16::from_int(v);
//! let on_edge = cue.evaluate(&img, &Ellipse::new(q(20), q(20), q(10), q(10)));
//! let inside = cue.evaluate(&img, &Ellipse::new(q(20), q(20), q(3), q(3)));
//! assert_eq!(on_edge, Q16::ONE); // a 200-level step saturates the default 192
//! assert_eq!(inside, Q16::ZERO);
//! # Ok::<(), rbtrack::image::ImageError>(())
//! ```

use crate::fixed::{isqrt32, sqrt_q8, Q16};
use crate::image::{Crosses, ImageView, PixelFormat, CROSS_REACH};
use crate::window::Ellipse;

mod gradient;
mod memo;

use gradient::interior_gradient_sq;
pub use gradient::{gradient, gradient_sq};
use memo::Memoised;
pub use memo::{GradientMemo, MEMO_SLOTS};

/// Most boundary points per ellipse.
pub const MAX_POINTS: usize = 64;

/// Longest search along the normal, px, each side of the boundary.
pub const MAX_SEARCH_PX: u32 = 32;

/// Largest gradient magnitude of 8-bit luma, `ceil(765 sqrt 2)`.
pub const MAX_MAGNITUDE: u32 = 1082;

/// Default saturation magnitude: 192, the response to a sharp step of 64 grey levels
/// (a quarter of the range), so any clear object boundary scores 1.
pub const DEFAULT_SATURATION: u32 = 192;

/// Fraction bits of the per-point magnitude `m_k` (1/32).
const MAG_FRAC_BITS: u32 = 5;

/// Fraction bits of the mean's reciprocal ([`GradientCue`]'s `recip`): `2^48 / (K sat
/// 2^5)`.
const RECIP_FRAC_BITS: u32 = 48;

/// Why [`GradientCue::new`] rejected a configuration: the name of the field.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum GradientError {
    /// The named field is outside its documented range.
    OutOfRange(&'static str),
}

impl core::fmt::Display for GradientError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::OutOfRange(field) => write!(f, "gradient cue: {field} is out of range"),
        }
    }
}

impl core::error::Error for GradientError {}

/// Configuration of the gradient cue.
#[non_exhaustive]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GradientConfig {
    /// Boundary points `K`, `1..=MAX_POINTS` (default 32).
    pub points: usize,
    /// Search distance along the normal each side of the boundary, px,
    /// `0..=MAX_SEARCH_PX` (default 4).
    pub search_px: u32,
    /// Magnitude at which a point scores 1, in `|g|` units, `1..=MAX_MAGNITUDE`
    /// (default [`DEFAULT_SATURATION`]).
    pub saturation: u32,
}

impl GradientConfig {
    /// The defaults: 32 points, 4 px search, saturation 192.
    pub const fn new() -> Self {
        Self {
            points: 32,
            search_px: 4,
            saturation: DEFAULT_SATURATION,
        }
    }

    /// Checks every field against its range; the error names the first one out of it.
    pub const fn check(&self) -> Result<(), GradientError> {
        if self.points < 1 || self.points > MAX_POINTS {
            return Err(GradientError::OutOfRange("points"));
        }
        if self.search_px > MAX_SEARCH_PX {
            return Err(GradientError::OutOfRange("search_px"));
        }
        if self.saturation < 1 || self.saturation > MAX_MAGNITUDE {
            return Err(GradientError::OutOfRange("saturation"));
        }
        Ok(())
    }
}

impl Default for GradientConfig {
    fn default() -> Self {
        Self::new()
    }
}

/// The gradient cue, with its angle tables.
#[derive(Clone, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct GradientCue {
    cos: [Q16; MAX_POINTS],
    sin: [Q16; MAX_POINTS],
    points: usize,
    search: i32,
    saturation: u32,
    /// `floor(2^48 / (K saturation 2^5))`: the mean's divisor as a multiplier.
    recip: u64,
}

impl GradientCue {
    /// A cue of no boundary points (every window's cue is 0), before one is configured.
    pub const UNSET: Self = Self {
        cos: [Q16::ZERO; MAX_POINTS],
        sin: [Q16::ZERO; MAX_POINTS],
        points: 0,
        search: 0,
        saturation: 0,
        recip: 0,
    };

    /// Checks `config` ([`GradientConfig::check`]) and tabulates the `K` angles (integer
    /// arithmetic).
    pub fn new(config: &GradientConfig) -> Result<Self, GradientError> {
        config.check()?;
        let mut cos = [Q16::ZERO; MAX_POINTS];
        let mut sin = [Q16::ZERO; MAX_POINTS];
        for (k, (c, s)) in cos.iter_mut().zip(sin.iter_mut()).enumerate() {
            if k < config.points {
                (*c, *s) = crate::trig::cos_sin_of_turn(k as u32, config.points as u32);
            }
        }
        let den = config.points as u64 * ((config.saturation as u64) << MAG_FRAC_BITS);
        Ok(Self {
            cos,
            sin,
            points: config.points,
            search: config.search_px as i32,
            saturation: config.saturation,
            recip: (1u64 << RECIP_FRAC_BITS) / den.max(1 << MAG_FRAC_BITS), // den >= 2^5
        })
    }

    /// Boundary points `K`.
    pub fn points(&self) -> usize {
        self.points
    }

    /// Search distance each side of the boundary, px.
    pub fn search_px(&self) -> u32 {
        self.search as u32
    }

    /// Saturation magnitude, `|g|` units.
    pub fn saturation(&self) -> u32 {
        self.saturation
    }

    /// `cos t_k` and `sin t_k` of boundary point `k` (`< K`), Q16.16.
    pub fn angle(&self, k: usize) -> (Q16, Q16) {
        (
            self.cos.get(k).copied().unwrap_or(Q16::ZERO),
            self.sin.get(k).copied().unwrap_or(Q16::ZERO),
        )
    }

    /// The cue `g` of `e` in `img`, Q16.16 in `[0, 1]`; 0 for an ellipse with a half-axis
    /// below [`crate::window::MIN_HALF_AXIS`].
    ///
    /// Cost: `K (2 search + 1)` gradient evaluations (8 luma reads each; a point whose
    /// whole search segment lies at least 2 px inside the frame reads its taps without
    /// clamping), per point a table square root and two 32-bit divisions for the unit
    /// normal and at most one table square root for the magnitude; no 64-bit division.
    pub fn evaluate<P: PixelFormat>(&self, img: &ImageView<'_, P>, e: &Ellipse) -> Q16 {
        let mut sampler = Direct;
        let crosses = img.crosses();
        let sum = (0..self.points).fold(0, |sum, k| {
            sum + self.point(img, &crosses, e, k, &mut sampler)
        });
        self.mean(sum)
    }

    /// [`GradientCue::evaluate`] reading gradients through `memo` (the same value: the memo
    /// only saves recomputing a gradient at a pixel it already holds for this frame).
    /// Call [`GradientMemo::start_frame`] before the first window of every new frame.
    pub fn evaluate_memo<P: PixelFormat>(
        &self,
        img: &ImageView<'_, P>,
        e: &Ellipse,
        memo: &mut GradientMemo,
    ) -> Q16 {
        if !self.memo_serves(memo, img) {
            return self.evaluate(img, e);
        }
        let mut sampler = Memoised::new(memo, img);
        let crosses = img.crosses();
        let sum = (0..self.points).fold(0, |sum, k| {
            sum + self.point(img, &crosses, e, k, &mut sampler)
        });
        self.mean(sum)
    }

    /// The cue of every window `ellipse(i)`, `i < out.len()`, into `out[i]`: the values of
    /// [`GradientCue::evaluate`], computed boundary point by boundary point across all the
    /// windows, so that the windows' samples of one point, which lie close together when
    /// the windows do (a particle cloud), meet in `memo` and each pixel's gradient is
    /// computed about once. Call [`GradientMemo::start_frame`] before the first window of
    /// every new frame.
    #[inline(never)]
    pub fn evaluate_each<P: PixelFormat>(
        &self,
        img: &ImageView<'_, P>,
        ellipse: impl Fn(usize) -> Ellipse,
        out: &mut [Q16],
        memo: &mut GradientMemo,
    ) {
        // The sums (< 2^22) accumulate in `out`, then become the means.
        out.iter_mut().for_each(|g| *g = Q16::ZERO);
        let crosses = img.crosses();
        if self.memo_serves(memo, img) {
            let mut sampler = Memoised::new(memo, img);
            for k in 0..self.points {
                for (i, g) in out.iter_mut().enumerate() {
                    let term = self.point(img, &crosses, &ellipse(i), k, &mut sampler);
                    *g = Q16::from_bits(g.to_bits().wrapping_add(term as i32));
                }
            }
        } else {
            for (i, g) in out.iter_mut().enumerate() {
                *g = self.evaluate(img, &ellipse(i));
            }
            return;
        }
        for g in out.iter_mut() {
            *g = self.mean(g.to_bits() as u32);
        }
    }

    /// `g = sum / (K sat)`, rounded, by the reciprocal tabulated at construction:
    /// `sum <= K sat`, so `sum * recip <= 2^48`.
    #[inline(always)]
    fn mean(&self, sum: u32) -> Q16 {
        let shift = RECIP_FRAC_BITS - Q16::FRAC_BITS;
        let g = (sum as u64 * self.recip + (1 << (shift - 1))) >> shift;
        Q16::from_bits(g.min(Q16::ONE.to_bits() as u64) as i32)
    }

    /// Boundary point `k`'s term of `e`'s cue, `min(m_k, saturation)` in 1/32 units (0
    /// for a degenerate ellipse or a point whose segment misses the frame), its
    /// gradients read through `sampler`.
    #[inline(always)]
    fn point<P: PixelFormat, S: Sampler<P>>(
        &self,
        img: &ImageView<'_, P>,
        crosses: &Crosses<'_, P>,
        e: &Ellipse,
        k: usize,
        sampler: &mut S,
    ) -> u32 {
        if !e.is_visitable() {
            return 0;
        }
        debug_assert!(k < self.points, "boundary point {k} of {}", self.points);
        let (Some(&c), Some(&s)) = (self.cos.get(k), self.sin.get(k)) else {
            return 0;
        };
        let (c, s) = (c.to_bits(), s.to_bits()); // |.| <= 2^16
        let (hx, hy) = (e.hx.to_bits(), e.hy.to_bits()); // 2^15..2^31
        let (w, h) = (img.width() as i32, img.height() as i32); // <= MAX_SIDE < 2^14
        let search = self.search;
        let frac = Q16::FRAC_BITS;
        // Beyond the search segment, px Q16.
        let reach = (search + 1) << frac;
        // The offsets h c / 2^16 lie in [-h, h], h < 2^31.
        let offset = |h: i32, c: i32| ((h as i64 * c as i64) >> frac) as i32;
        // Every search position lies within `reach` of the box `c +- h` (|offset| <= h, the
        // normal's components are at most 1), so a window whose box so widened has only
        // interior pixels needs no test per point (the usual case, checked in 32 bits).
        let (cx, cy) = (e.cx.to_bits(), e.cy.to_bits());
        let taps = (CROSS_REACH as i32) << frac; // a cross's reach, px Q16
        let inside = |c: i32, h: i32, side: i32| {
            let margin = h.saturating_add(reach);
            c.saturating_sub(margin) >= taps && c.saturating_add(margin) < (side << frac) - taps
        };
        let interior = inside(cx, hx, w) && inside(cy, hy, h);
        let (bx, by) = if interior {
            (cx + offset(hx, c), cy + offset(hy, s))
        } else {
            // A centre plus offset beyond the i32 range is far outside the frame.
            let (Some(bx), Some(by)) =
                (cx.checked_add(offset(hx, c)), cy.checked_add(offset(hy, s)))
            else {
                return 0;
            };
            // A segment wholly outside the frame has no sample in it (and this keeps the
            // positions below in i32).
            let (right, bottom) = ((w << frac) + reach, (h << frac) + reach);
            if bx < -reach || by < -reach || bx >= right || by >= bottom {
                return 0;
            }
            (bx, by)
        };
        // The normal at angle t is along (cos t / hx, sin t / hy) ~ (cos t hy, sin t hx).
        let (ux, uy) = unit_normal(c, s, hx, hy);
        // The nearest pixel, halves rounded up.
        let half = Q16::HALF.to_bits();
        let at = |j: i32| ((bx + j * ux + half) >> frac, (by + j * uy + half) >> frac);
        // Positions are monotone in j, so the two ends bound the segment.
        let ends_interior = || {
            let ((x0, y0), (x1, y1)) = (at(-search), at(search));
            crosses.inside(x0.min(x1), y0.min(y1)) && crosses.inside(x0.max(x1), y0.max(y1))
        };
        let mut best = 0u32;
        // (Half-open ranges: an inclusive one tests its exhaustion flag every step.)
        if interior || ends_interior() {
            for j in -search..search + 1 {
                let (x, y) = at(j);
                best = best.max(sampler.interior(crosses, x, y));
            }
        } else {
            for j in -search..search + 1 {
                let (x, y) = at(j);
                if (0..w).contains(&x) && (0..h).contains(&y) {
                    best = best.max(sampler.clamped(img, x, y));
                }
            }
        }
        // min(sqrt(best), saturation) to 1/32: saturated points need no square root;
        // below, best < 1082^2 < 2^21.
        let sat = self.saturation << MAG_FRAC_BITS;
        if best >= self.saturation * self.saturation {
            sat
        } else {
            magnitude(best).min(sat)
        }
    }
}

/// Where [`GradientCue`] gets a squared gradient magnitude at an in-frame pixel.
trait Sampler<P: PixelFormat> {
    /// At `(x, y)`, whose cross of taps lies in the frame ([`Crosses::inside`]).
    fn interior(&mut self, crosses: &Crosses<'_, P>, x: i32, y: i32) -> u32;
    /// At `(x, y)` in the frame, taps clamped.
    fn clamped(&mut self, img: &ImageView<'_, P>, x: i32, y: i32) -> u32;
}

/// Computes every gradient.
struct Direct;

impl<P: PixelFormat> Sampler<P> for Direct {
    #[inline(always)]
    fn interior(&mut self, crosses: &Crosses<'_, P>, x: i32, y: i32) -> u32 {
        interior_gradient_sq(crosses, x, y)
    }
    #[inline(always)]
    fn clamped(&mut self, img: &ImageView<'_, P>, x: i32, y: i32) -> u32 {
        gradient_sq(img, x, y)
    }
}

/// `floor(sqrt(best) 2^MAG_FRAC_BITS)` (= `isqrt(best << 10)`) for `best < 2^21`.
#[inline(always)]
fn magnitude(best: u32) -> u32 {
    isqrt32(best << (2 * MAG_FRAC_BITS))
}

/// The unit vector along `(c hy, s hx)` (`|c|, |s| <= 2^16`, half-axes `hx, hy` in
/// `2^15..2^31`), Q16.16 components, by a table square root and two 32-bit divisions;
/// `(c, s)` for the zero vector. Within 4e-5 of the exact direction.
#[inline(always)]
fn unit_normal(c: i32, s: i32, hx: i32, hy: i32) -> (i32, i32) {
    // Component magnitudes below 2^47.
    let ax = c.unsigned_abs() as u64 * hy as u64;
    let ay = s.unsigned_abs() as u64 * hx as u64;
    let longer = ax.max(ay);
    if longer == 0 {
        return (c, s);
    }
    // Components below 2^16, the longer at least 2^15: shift 0..=31, so the low word of
    // a >> shift is lo >> shift | hi << (32 - shift) (hi << 32 = 0 through two shifts).
    let shift = (64 - longer.leading_zeros()).saturating_sub(16);
    let down = |a: u64| ((a as u32) >> shift) | (((a >> 32) as u32) << 1 << (31 - shift));
    let (ax, ay) = (down(ax), down(ay));
    // (a^2 + b^2) / 4 < 2^31; sqrt_q8 of it is the length times 128.
    // len >= 2^15, so a 2^16 + len / 2 < 2^32 - 2^16 + 2^15.6: no overflow; the quotient
    // is <= 2^16 + 1.
    let len = ((sqrt_q8(((ax * ax) >> 2) + ((ay * ay) >> 2)) + 64) >> 7).max(1);
    let one = Q16::ONE.to_bits() as u32;
    let unit = |a: u32| (((a << Q16::FRAC_BITS) + len / 2) / len).min(one) as i32;
    let (ux, uy) = (unit(ax), unit(ay));
    (if c < 0 { -ux } else { ux }, if s < 0 { -uy } else { uy })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Gray8, Rgb565Le, Rgb888, Yuv422};
    use std::vec;
    use std::vec::Vec;

    fn cue() -> GradientCue {
        GradientCue::new(&GradientConfig::new()).unwrap()
    }

    #[test]
    fn config_is_checked() {
        let mut c = GradientConfig::new();
        c.points = 0;
        assert_eq!(
            GradientCue::new(&c),
            Err(GradientError::OutOfRange("points"))
        );
        c.points = MAX_POINTS + 1;
        assert_eq!(
            GradientCue::new(&c),
            Err(GradientError::OutOfRange("points"))
        );
        c.points = MAX_POINTS;
        c.search_px = MAX_SEARCH_PX + 1;
        assert_eq!(
            GradientCue::new(&c),
            Err(GradientError::OutOfRange("search_px"))
        );
        c.search_px = 0;
        c.saturation = 0;
        assert_eq!(
            GradientCue::new(&c),
            Err(GradientError::OutOfRange("saturation"))
        );
        c.saturation = MAX_MAGNITUDE + 1;
        assert!(GradientCue::new(&c).is_err());
        c.saturation = MAX_MAGNITUDE;
        let cue = GradientCue::new(&c).unwrap();
        assert_eq!(cue.angle(0), (Q16::ONE, Q16::ZERO));
        assert_eq!(cue.angle(16).0, Q16::ZERO);
        use std::string::ToString;
        assert!(GradientError::OutOfRange("points")
            .to_string()
            .contains("points"));
    }

    #[test]
    fn magnitude_is_the_integer_square_root() {
        for best in (0..1u32 << 21)
            .step_by(7)
            .chain([(1 << 21) - 1, 1082 * 1082])
        {
            assert_eq!(magnitude(best), (best << 10).isqrt(), "{best}");
        }
    }

    #[test]
    fn flat_frame_and_degenerate_windows_give_zero() {
        let buf = vec![255u8; 30 * 30];
        let img = ImageView::<Gray8>::new(&buf, 30, 30, 30).unwrap();
        assert_eq!(
            cue().evaluate(&img, &Ellipse::from_f64(15.0, 15.0, 8.0, 5.0)),
            Q16::ZERO
        );
        let one = ImageView::<Gray8>::new(&[7], 1, 1, 1).unwrap();
        assert_eq!(
            cue().evaluate(&one, &Ellipse::from_f64(0.0, 0.0, 3.0, 3.0)),
            Q16::ZERO
        );
        assert_eq!(
            cue().evaluate(&img, &Ellipse::from_f64(15.0, 15.0, 0.0, 5.0)),
            Q16::ZERO
        );
        assert_eq!(
            cue().evaluate(&img, &Ellipse::from_f64(15.0, 15.0, -4.0, -5.0)),
            Q16::ZERO
        );
        // Wholly outside: no sample in the frame.
        assert_eq!(
            cue().evaluate(&img, &Ellipse::from_f64(-100.0, 15.0, 8.0, 5.0)),
            Q16::ZERO
        );
        assert_eq!(
            cue().evaluate(
                &img,
                &Ellipse::from_f64(-32_768.0, 32_767.0, 32_767.0, 32_767.0)
            ),
            Q16::ZERO
        );
    }

    fn disc_frame(w: usize, h: usize, cx: f64, cy: f64, rx: f64, ry: f64, level: u8) -> Vec<u8> {
        (0..w * h)
            .map(|i| {
                let (x, y) = ((i % w) as f64 - cx, (i / w) as f64 - cy);
                if (x / rx).powi(2) + (y / ry).powi(2) <= 1.0 {
                    level
                } else {
                    0
                }
            })
            .collect()
    }

    #[test]
    fn peaks_on_the_boundary_of_an_elliptic_blob() {
        let buf = disc_frame(80, 60, 40.0, 30.0, 20.0, 10.0, 60);
        let img = ImageView::<Gray8>::new(&buf, 80, 60, 80).unwrap();
        let c = cue();
        let on = c
            .evaluate(&img, &Ellipse::from_f64(40.0, 30.0, 20.0, 10.0))
            .to_f64();
        // A 60-level step gives 180 of 192 on the axes, a little less on the diagonals.
        assert!(on > 0.85 && on <= 1.0, "{on}");
        let off = c
            .evaluate(&img, &Ellipse::from_f64(40.0, 30.0, 10.0, 3.0))
            .to_f64();
        assert!(off < 0.05, "{off}");
        let shifted = c
            .evaluate(&img, &Ellipse::from_f64(40.0, 30.0, 22.5, 11.5))
            .to_f64();
        assert!(shifted > 0.8, "search finds the edge: {shifted}");
        // A saturation above the step scales the cue down in proportion.
        let mut cfg = GradientConfig::new();
        cfg.saturation = 360;
        let half = GradientCue::new(&cfg)
            .unwrap()
            .evaluate(&img, &Ellipse::from_f64(40.0, 30.0, 20.0, 10.0));
        assert!(half.to_f64() < 0.7 && half.to_f64() > 0.5, "{half}");
    }

    #[test]
    fn partly_outside_counts_missing_points_as_zero() {
        let buf = disc_frame(40, 40, 0.0, 20.0, 10.0, 10.0, 255);
        let img = ImageView::<Gray8>::new(&buf, 40, 40, 40).unwrap();
        let g = cue()
            .evaluate(&img, &Ellipse::from_f64(0.0, 20.0, 10.0, 10.0))
            .to_f64();
        // About half of the boundary is inside the frame.
        assert!(g > 0.35 && g < 0.65, "{g}");
    }

    /// Reads every gradient of its frame, interior ones included, through the clamping
    /// path.
    struct Clamped<'a, P: PixelFormat>(ImageView<'a, P>);

    impl<P: PixelFormat> Sampler<P> for Clamped<'_, P> {
        fn interior(&mut self, _: &Crosses<'_, P>, x: i32, y: i32) -> u32 {
            gradient_sq(&self.0, x, y)
        }
        fn clamped(&mut self, img: &ImageView<'_, P>, x: i32, y: i32) -> u32 {
            gradient_sq(img, x, y)
        }
    }

    /// The cue with interior segments read unclamped equals the cue with every sample
    /// clamped, over random windows inside, across and outside the frame.
    #[test]
    fn unclamped_segments_give_the_clamped_cue() {
        let mut rng = crate::rng::Rng::new(8);
        let (w, h) = (61usize, 47usize);
        let buf: Vec<u8> = (0..w * h * 2).map(|_| rng.below(256) as u8).collect();
        let img = ImageView::<Rgb565Le>::new(&buf, w, h, w).unwrap();
        for i in 0..3000 {
            let mut config = GradientConfig::new();
            config.points = 1 + rng.below(MAX_POINTS as u32) as usize;
            config.search_px = rng.below(8);
            let c = GradientCue::new(&config).unwrap();
            let e = Ellipse::from_f64(
                rng.below(90) as f64 - 15.0 + rng.uniform().to_f64(),
                rng.below(80) as f64 - 15.0 + rng.uniform().to_f64(),
                0.5 + rng.below(40) as f64 * rng.uniform().to_f64(),
                0.5 + rng.below(40) as f64 * rng.uniform().to_f64(),
            );
            let mut clamped = Clamped(img);
            let crosses = img.crosses();
            let sum = (0..c.points).fold(0, |sum, k| {
                sum + c.point(&img, &crosses, &e, k, &mut clamped)
            });
            assert_eq!(c.evaluate(&img, &e), c.mean(sum), "window {i}: {e:?}");
        }
    }

    /// The memo never changes a result: `evaluate_memo` and `evaluate_each` equal
    /// `evaluate` window by window, over frames that change pixel values at the same
    /// places (the memo must forget them), change size, and wrap the generation.
    #[test]
    fn memo_gives_the_direct_cue() {
        let mut rng = crate::rng::Rng::new(17);
        let mut memo = GradientMemo::new();
        for frame in 0..300 {
            let (w, h) = if frame % 7 == 3 {
                (23usize, 61usize)
            } else {
                (64, 48)
            };
            let buf: Vec<u8> = (0..w * h * 2).map(|_| (rng.below(4) * 60) as u8).collect();
            let img = ImageView::<Rgb565Le>::new(&buf, w, h, w).unwrap();
            memo.start_frame();
            let mut config = GradientConfig::new();
            config.points = 1 + rng.below(40) as usize;
            config.search_px = rng.below(6);
            config.saturation = [192, 40, 255, 256, 700][frame % 5];
            let c = GradientCue::new(&config).unwrap();
            // A cloud of windows around one ellipse, some across the border.
            let (cx, cy) = (rng.below(70) as f64 - 3.0, rng.below(55) as f64 - 3.0);
            let windows: Vec<Ellipse> = (0..12)
                .map(|_| {
                    Ellipse::from_f64(
                        cx + 6.0 * rng.uniform().to_f64() - 3.0,
                        cy + 6.0 * rng.uniform().to_f64() - 3.0,
                        0.4 + 15.0 * rng.uniform().to_f64(),
                        0.4 + 15.0 * rng.uniform().to_f64(),
                    )
                })
                .collect();
            let direct: Vec<Q16> = windows.iter().map(|e| c.evaluate(&img, e)).collect();
            let mut each = vec![Q16::MAX; windows.len()];
            c.evaluate_each(&img, |i| windows[i], &mut each, &mut memo);
            assert_eq!(each, direct, "frame {frame}");
            for (e, &d) in windows.iter().zip(&direct) {
                assert_eq!(c.evaluate_memo(&img, e, &mut memo), d, "frame {frame}");
            }
        }
    }

    #[test]
    fn every_format_sees_the_same_edges() {
        let gray = disc_frame(32, 24, 16.0, 12.0, 9.0, 6.0, 255);
        let rgb: Vec<u8> = gray.iter().flat_map(|&v| [v, v, v]).collect();
        let rgb565: Vec<u8> = gray
            .iter()
            .flat_map(|&v| if v > 0 { [0xFF, 0xFF] } else { [0, 0] })
            .collect();
        let yuv: Vec<u8> = gray.iter().flat_map(|&v| [v, 128]).collect();
        let e = Ellipse::from_f64(16.0, 12.0, 9.0, 6.0);
        let c = cue();
        let g = c.evaluate(&ImageView::<Gray8>::new(&gray, 32, 24, 32).unwrap(), &e);
        assert!(g > Q16::from_f64(0.9));
        assert_eq!(
            c.evaluate(&ImageView::<Rgb888>::new(&rgb, 32, 24, 32).unwrap(), &e),
            g
        );
        assert_eq!(
            c.evaluate(
                &ImageView::<Rgb565Le>::new(&rgb565, 32, 24, 32).unwrap(),
                &e
            ),
            g
        );
        assert_eq!(
            c.evaluate(&ImageView::<Yuv422>::new(&yuv, 32, 24, 32).unwrap(), &e),
            g
        );
    }
}
