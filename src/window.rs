//! Elliptical image windows: the pixels inside an axis-aligned ellipse, clipped to the
//! frame, each with its Epanechnikov kernel weight, and never more of them than a cap.
//!
//! # Kernel weights
//! A pixel at `(x, y)` has `d^2 = ((x - cx) / hx)^2 + ((y - cy) / hy)^2` and weight
//! `k = 1 - d^2` in Q0.16: an integer in `0..=65536` ([`WEIGHT_ONE`] is 1 at the centre).
//! Along a row the weights follow from second differences (two additions per pixel); the
//! error against the exact `65536 (1 - d^2)` is below 2 units (about 3e-5).
//!
//! # Sampling lattice and the pixel cap
//! Pixels are visited on a square lattice of step `s` px anchored at the pixel nearest the
//! centre: `x = round(cx) + i s`, `y = round(cy) + j s`, row by row, left to right. The
//! step is the smallest integer that satisfies
//! `pi hx hy / s^2 + 2 (hx + hy) / s + 1 <= cap`, which bounds the lattice points inside
//! the ellipse by `cap` (rows: at most `2 hy / s + 1`; a row whose chord is `c` long holds
//! at most `c / s + 1` points; and because the chord length is unimodal in `y`,
//! `s * sum(c) <= area + s * 2 hx`). So [`visit`] visits at most `cap` pixels, whatever
//! the ellipse size; the tracker's worst-case pixel work per window is `cap`.
//! [`sampling_step`] gives `s` (one integer square root and one division per window).
//! Caps above [`MAX_CAP`] are lowered to it, so a window's total kernel mass
//! (`<= 65535 * 65536`) always fits a `u32`.
//!
//! # Cost
//! Per window: two 64-by-32-bit divisions done by 32-bit ones ([`div_u64_u32`]). Per row:
//! one 32-bit integer square root (a table look-up and a correction, no bit-by-bit loop)
//! and a few multiplies. Per pixel: two additions, a shift, a clamp and the caller's
//! closure; no multiply, no division.
//!
//! # Degenerate and clipped windows
//! A window with a half-axis below [`MIN_HALF_AXIS`] (0.5 px; zero and negative included)
//! or a cap of 0 visits nothing. A window partly or wholly outside the frame visits only
//! its in-frame lattice points (possibly none); nothing outside the frame is ever read.
//!
//! # Examples
//! ```
//! use rbtrack::fixed::Q16;
//! use rbtrack::image::{Gray8, ImageView};
//! use rbtrack::window::{visit, Ellipse, WEIGHT_ONE};
//! let frame = [0u8; 20 * 10];
//! let img = ImageView::<Gray8>::new(&frame, 20, 10, 20)?;
//! let e = Ellipse::new(Q16::from_int(5), Q16::from_int(5), Q16::from_int(3), Q16::from_int(2));
//! let mut mass = 0;
//! let n = visit(&img, &e, 1000, |_row, _x, w| mass += w);
//! assert_eq!(n, 15); // rows 4, 5, 6 hold 5 pixels each with d < 1 (step 1)
//! assert!(mass > 0 && mass < n * WEIGHT_ONE);
//! # Ok::<(), rbtrack::image::ImageError>(())
//! ```

use crate::fixed::{div_u64_u32, isqrt32, Q16};
use crate::image::{ImageView, PixelFormat, Row, Run};

/// Fraction bits of a kernel weight: Q0.16.
pub const WEIGHT_FRAC_BITS: u32 = 16;

/// Kernel weight of the ellipse centre, 1.0 in Q0.16.
pub const WEIGHT_ONE: u32 = 1 << WEIGHT_FRAC_BITS;

/// Largest cap on the pixels visited per window, px.
pub const MAX_CAP: u32 = 65_535;

/// Smallest half-axis of a non-empty window, px, Q16.16 (0.5 px).
pub const MIN_HALF_AXIS: Q16 = Q16::HALF;

/// Fraction bits of the normalised coordinates inside [`visit`]: Q2.30.
const Q30_FRAC_BITS: u32 = 30;

/// 1.0 in Q2.30.
const ONE_Q30: i64 = 1 << Q30_FRAC_BITS;

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

impl Ellipse {
    /// An ellipse from its centre `(cx, cy)` and half-axes `(hx, hy)`, px, Q16.16.
    pub const fn new(cx: Q16, cy: Q16, hx: Q16, hy: Q16) -> Self {
        Self { cx, cy, hx, hy }
    }

    /// Whether [`visit`] can visit any pixel: both half-axes at least [`MIN_HALF_AXIS`].
    pub const fn is_visitable(&self) -> bool {
        self.hx.to_bits() >= MIN_HALF_AXIS.to_bits() && self.hy.to_bits() >= MIN_HALF_AXIS.to_bits()
    }
}

#[cfg(test)]
impl Ellipse {
    /// An ellipse from its centre and half-axes in floats (px), rounded to Q16.16.
    pub(crate) fn from_f64(cx: f64, cy: f64, hx: f64, hy: f64) -> Self {
        let q = Q16::from_f64;
        Self::new(q(cx), q(cy), q(hx), q(hy))
    }
}

/// The lattice step [`visit`] uses for `e` under `cap`, px (`>= 1`); 0 when it visits
/// nothing (degenerate ellipse or `cap == 0`). `cap` is in px, lowered to [`MAX_CAP`].
pub fn sampling_step(e: &Ellipse, cap: u32) -> u32 {
    let cap = cap.min(MAX_CAP) as u64;
    if cap == 0 || !e.is_visitable() {
        return 0;
    }
    let (hx, hy) = (e.hx.to_bits() as u64, e.hy.to_bits() as u64);
    // Any step above the longer axis leaves at most one lattice point per axis.
    let one_point = ((2 * hx.max(hy)) >> Q16::FRAC_BITS) + 1;
    if cap == 1 {
        return one_point as u32;
    }
    // Smallest s with (cap - 1) s^2 - 2 P s - A >= 0, P = hx + hy, A = pi hx hy (px^2),
    // worked in 1/16 px with every quantity rounded up (pi as 3217/1024 > pi).
    let (hx16, hy16) = ((hx + 4095) >> 12, (hy + 4095) >> 12); // <= 2^19
    let p16 = hx16 + hy16; // <= 2^20
    let a256 = (hx16 * hy16 * 3217 + 1023) >> 10; // <= 2^40, px^2 / 256
    let disc = p16 * p16 + (cap - 1) * a256; // <= 2^57
    let mut root = disc.isqrt(); // <= 2^29
    if root * root < disc {
        root += 1;
    }
    let num = (p16 + root) as u32; // < 2^30
    let den = 16 * (cap as u32 - 1); // 16..2^20
    let s = num.div_ceil(den.max(1)) as u64;
    s.clamp(1, one_point) as u32
}

/// Visits the pixels of `img` inside `e` on the sampling lattice, at most `cap` of them
/// (px, lowered to [`MAX_CAP`]), calling `f(row, x, weight)` for each: `row` is the pixel's
/// row, `x` its column (px, `< img.width()`), `weight` its kernel weight in Q0.16
/// (`0..=WEIGHT_ONE`). Returns the number of pixels visited (`<= cap`).
///
/// Rows are visited top to bottom and pixels left to right.
#[inline]
pub fn visit<'a, P, F>(img: &ImageView<'a, P>, e: &Ellipse, cap: u32, mut f: F) -> u32
where
    P: PixelFormat,
    F: FnMut(&Row<'a, P>, usize, u32),
{
    let cap = cap.min(MAX_CAP);
    rows(img, e, cap, |mut run| {
        let row = img.row(run.y);
        let mut x = run.pixels.x0;
        for _ in 0..run.pixels.count {
            f(&row, x, run.weights.next());
            x += run.pixels.step;
        }
    })
}

/// `floor(a / s)` for `s >= 1` (0 for `s <= 0`, which callers never pass).
#[inline(always)]
fn floor_div(a: i32, s: i32) -> i32 {
    debug_assert!(s > 0, "a lattice step of {s}");
    if s > 0 {
        a.div_euclid(s)
    } else {
        0
    }
}

/// The kernel weights of one row's lattice points, by second differences: point `k` has
/// `W_k = 1 - ry - t_k^2` (Q2.30, `t_k` its normalised column offset) and weight
/// `max(W_k, 0) >> 14` (Q0.16); `W_{k+1} = W_k - D_k`, `D_{k+1} = D_k + E`, where
/// `D_0 = (2 t_0 dt + dt^2) / 2^30` and `E = 2 dt^2 / 2^30` are rounded once per row. Two
/// additions, a shift and a clamp per pixel; the rounding of `D_0` and `E` adds at most
/// `k^2 / 4 + k / 2` units of `2^-30` at point `k` (below 1.5 units of the weight for the
/// longest row of a window).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowWeights {
    w: i32,
    d: i32,
    e: i32,
}

impl RowWeights {
    /// The weights of the points at `t0, t0 + dt, ...` (Q2.30, `|t0| <= 1`, `dt >= 0`)
    /// of a row with squared offset `ry` (Q2.30, `<= 1`); `dt2 = dt^2 / 2^30` and
    /// `e = 2 dt^2 / 2^30` are the window's (rounded down). Every increment fits an `i32`
    /// for as many points as lie strictly inside the chord (when three do, `2 dt < 2`),
    /// and the later ones wrap unused.
    #[inline(always)]
    fn new(t0: i32, dt: i32, dt2: i64, e: i32, ry: u32) -> Self {
        let t = t0 as i64;
        let w = ONE_Q30 - ry as i64 - ((t * t) >> Q30_FRAC_BITS);
        let d = ((2 * t * dt as i64) >> Q30_FRAC_BITS) + dt2;
        Self {
            w: w as i32,
            d: d as i32,
            e,
        }
    }

    /// The next point's weight, Q0.16 (`0..=WEIGHT_ONE`).
    #[inline(always)]
    #[allow(clippy::should_implement_trait)] // an infinite, infallible sequence
    pub(crate) fn next(&mut self) -> u32 {
        let weight = (self.w.max(0) as u32) >> (Q30_FRAC_BITS - WEIGHT_FRAC_BITS);
        self.w = self.w.wrapping_sub(self.d);
        self.d = self.d.wrapping_add(self.e);
        weight
    }
}

/// One row's part of a window: the lattice points of row `y` inside the frame and
/// strictly inside the ellipse's chord, with their kernel weights.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowRun {
    /// The row, px.
    pub y: usize,
    /// The points along it.
    pub pixels: Run,
    /// Their kernel weights, in order.
    pub weights: RowWeights,
}

/// The rows of [`visit`]: calls `f` once per row that has lattice points inside the
/// ellipse and the frame, top to bottom, with at most `cap` points in all (px, `<=
/// MAX_CAP`, the caller's contract). Returns the number of points.
///
/// Per row: one exact 32-bit table square root ([`isqrt32`]) and a few
/// multiplies; per window, [`sampling_step`] and two [`div_u64_u32`].
#[inline(always)]
pub(crate) fn rows<P, F>(img: &ImageView<'_, P>, e: &Ellipse, cap: u32, mut f: F) -> u32
where
    P: PixelFormat,
    F: FnMut(RowRun),
{
    let s = sampling_step(e, cap);
    if s == 0 {
        return 0;
    }
    let frac = Q16::FRAC_BITS;
    let (cx, cy) = (e.cx.to_bits() as i64, e.cy.to_bits() as i64);
    let (hx, hy) = (e.hx.to_bits() as u32, e.hy.to_bits() as u32); // 2^15..2^31
    let (xc, yc) = (e.cx.round_int(), e.cy.round_int()); // px, |.| <= 32768
    let si = s as i32; // 1..=65536

    // Rows inside the ellipse and the frame, as lattice indices j (y = yc + j s).
    let y_lo = (-((hy as i64 - cy) >> frac)).max(0) as i32; // ceil(cy - hy)
    let y_hi = ((cy + hy as i64) >> frac).min(img.height() as i64 - 1) as i32; // floor(cy + hy)
    if y_lo > y_hi {
        return 0;
    }
    let j_lo = -floor_div(yc - y_lo, si); // ceil((y_lo - yc) / s)
    let j_hi = floor_div(y_hi - yc, si);
    // Columns inside the frame, as lattice indices k (x = xc + k s).
    let k_frame_lo = -floor_div(xc, si);
    let k_frame_hi = floor_div(img.width() as i32 - 1 - xc, si);
    if k_frame_lo > k_frame_hi || j_lo > j_hi {
        return 0;
    }

    // Reciprocal half-axes, 2^62 / h (2^31..2^47): (v - c) * inv >> 32 is (v - c) / h in
    // Q2.30 for |v - c| <= h, with a relative error below 2^-31.
    let inv_hx = div_u64_u32(1 << (Q30_FRAC_BITS + 32), hx) as i64;
    let inv_hy = div_u64_u32(1 << (Q30_FRAC_BITS + 32), hy) as i64;
    // The lattice step in normalised x and y, Q2.30 (`(s << 16) inv >> 32`); past one
    // point per row (column) the step is unused, so clamping it keeps the loops in `i32`.
    let step_q30 = |inv: i64| ((s as u64 * inv as u64) >> (32 - frac)).min(i32::MAX as u64) as i32;
    let (dt, dty) = (step_q30(inv_hx), step_q30(inv_hy));
    let dt2 = (dt as i64 * dt as i64) >> Q30_FRAC_BITS;
    let e2 = ((2 * dt as i64 * dt as i64) >> Q30_FRAC_BITS).min(i32::MAX as i64) as i32;
    // Normalised offsets of the lattice's column 0 and of its first row, Q2.30.
    let norm = |v: i64, c: i64, inv: i64| (((v << frac) - c) * inv) >> 32;
    let tc = norm(xc as i64, cx, inv_hx).clamp(-ONE_Q30, ONE_Q30) as i32;
    let mut ty = norm((yc + j_lo * si) as i64, cy, inv_hy).clamp(-ONE_Q30, ONE_Q30) as i32;
    // The half-axis and the centre's offset from the anchor in lattice units, Q16 (`s >= 1`:
    // the divisions cannot fail).
    let ax = hx.checked_div(s).unwrap_or(0).min(1 << 30) as u64;
    let off = ((cx - ((xc as i64) << frac)) as i32)
        .checked_div(si)
        .unwrap_or(0); // |.| < 2^16

    let mut visited = 0u32;
    let mut y = (yc + j_lo * si) as usize; // y_lo..=y_hi
    let mut j = j_lo;
    while j <= j_hi && visited < cap {
        // |y - cy| <= hy, so |ty| <= 1 (the additions drift by at most j units).
        // ty^2, Q2.30, and sqrt(1 - ty^2), Q0.15.
        let ry = (((ty as i64 * ty as i64) >> Q30_FRAC_BITS) as u32).min(ONE_Q30 as u32);
        let root = isqrt32(ONE_Q30 as u32 - ry) as u64;
        // Lattice units, Q16, <= 2^30: chords longer than any frame (2^14 px) are clipped
        // anyway.
        let half_chord = ((ax * root) >> (Q30_FRAC_BITS / 2)) as i32;
        // Lattice points strictly inside the chord (points on the boundary weigh 0).
        let k_lo = (-((half_chord - off - 1) >> frac)).max(k_frame_lo);
        let k_hi = ((off + half_chord - 1) >> frac).min(k_frame_hi);
        if k_lo <= k_hi {
            // The step keeps the window within its cap (see the module docs): the stop at
            // `cap` is a safety belt that never acts.
            let points = (k_hi - k_lo + 1) as u32; // <= width
            debug_assert!(visited + points <= cap, "the lattice step exceeded the cap");
            let count = points.min(cap - visited);
            visited += count;
            // The first point, inside the frame and the chord. A point inside the chord has
            // |t| < 1. If it is not the anchor's column (k != 0), the step is below 2
            // (unclamped), so neither k dt nor the sum overflows; for k = 0 the product is 0.
            let x0 = xc + k_lo * si;
            let t0 = tc.wrapping_add(k_lo.wrapping_mul(dt));
            f(RowRun {
                y,
                pixels: Run {
                    x0: x0 as usize,
                    step: s as usize,
                    count,
                },
                weights: RowWeights::new(t0, dt, dt2, e2, ry),
            });
        }
        j += 1;
        y = y.wrapping_add(s as usize);
        ty = ty.wrapping_add(dty);
    }
    visited
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Gray8, Rgb888};
    use std::vec;
    use std::vec::Vec;

    fn collect<P: PixelFormat>(
        img: &ImageView<'_, P>,
        e: &Ellipse,
        cap: u32,
    ) -> Vec<(usize, usize, u32)> {
        let mut out = Vec::new();
        let n = visit(img, e, cap, |row, x, w| out.push((x, row.y(), w)));
        assert_eq!(n as usize, out.len());
        out
    }

    #[test]
    fn weights_match_the_kernel() {
        let buf = vec![0u8; 64 * 48];
        let img = ImageView::<Gray8>::new(&buf, 64, 48, 64).unwrap();
        let e = Ellipse::from_f64(30.3, 20.7, 12.4, 7.9);
        let px = collect(&img, &e, MAX_CAP);
        let (cx, cy, hx, hy) = (e.cx.to_f64(), e.cy.to_f64(), e.hx.to_f64(), e.hy.to_f64());
        let mut expected = 0;
        for y in 0..48 {
            for x in 0..64 {
                let d2 = ((x as f64 - cx) / hx).powi(2) + ((y as f64 - cy) / hy).powi(2);
                if d2 <= 1.0 - 1e-6 {
                    expected += 1;
                }
            }
        }
        assert!(
            px.len() >= expected && px.len() <= expected + 2,
            "{} vs {expected}",
            px.len()
        );
        for &(x, y, w) in &px {
            let d2 = ((x as f64 - cx) / hx).powi(2) + ((y as f64 - cy) / hy).powi(2);
            let exact = 65536.0 * (1.0 - d2).max(0.0);
            assert!((w as f64 - exact).abs() < 8.0, "({x},{y}) {w} vs {exact}");
        }
        let centre = px.iter().find(|p| p.0 == 30 && p.1 == 21).unwrap();
        assert!(centre.2 > 64_000);
    }

    /// The weights by second differences stay within 2 units (Q0.16) of the exact
    /// `65536 (1 - d^2)` over random windows, long rows (wide, flat ellipses, uncapped)
    /// included.
    #[test]
    fn second_difference_weights_are_accurate() {
        let buf = vec![0u8; 700 * 90];
        let img = ImageView::<Gray8>::new(&buf, 700, 90, 700).unwrap();
        let mut rng = crate::rng::Rng::new(31);
        let mut worst = 0f64;
        for i in 0..4000 {
            // Small, medium, long flat rows, and narrow tall windows whose step exceeds the
            // half-width (at most two points per row).
            let hx = 0.5 + [3.0, 30.0, 340.0, 2.0][i % 4] * rng.uniform().to_f64();
            let hy = 0.5 + [3.0, 40.0, 2.0, 40.0][i % 4] * rng.uniform().to_f64();
            let e = Ellipse::from_f64(
                350.0 + 10.0 * rng.uniform().to_f64(),
                45.0 + 4.0 * rng.uniform().to_f64(),
                hx,
                hy,
            );
            let cap = [300, MAX_CAP, 20, 4][i % 4];
            let (cx, cy, hx, hy) = (e.cx.to_f64(), e.cy.to_f64(), e.hx.to_f64(), e.hy.to_f64());
            visit(&img, &e, cap, |row, x, w| {
                let d2 = ((x as f64 - cx) / hx).powi(2) + ((row.y() as f64 - cy) / hy).powi(2);
                let exact = 65536.0 * (1.0 - d2).max(0.0);
                worst = worst.max((w as f64 - exact).abs());
            });
        }
        std::println!("largest weight error {worst:.2} units");
        assert!(worst < 2.0, "{worst}");
    }

    #[test]
    fn centre_pixel_of_a_tiny_window() {
        let buf = [7u8; 9];
        let img = ImageView::<Gray8>::new(&buf, 3, 3, 3).unwrap();
        let px = collect(&img, &Ellipse::from_f64(1.0, 1.0, 0.5, 0.5), 100);
        assert_eq!(px, vec![(1, 1, WEIGHT_ONE)]);
        // Below half a pixel, or zero, or negative: nothing.
        for (hx, hy) in [(0.49, 3.0), (3.0, 0.0), (-2.0, 2.0), (0.0, 0.0)] {
            assert!(collect(&img, &Ellipse::from_f64(1.0, 1.0, hx, hy), 100).is_empty());
        }
        assert!(collect(&img, &Ellipse::from_f64(1.0, 1.0, 2.0, 2.0), 0).is_empty());
    }

    #[test]
    fn one_pixel_frame() {
        let img = ImageView::<Gray8>::new(&[9], 1, 1, 1).unwrap();
        assert_eq!(
            collect(&img, &Ellipse::from_f64(0.0, 0.0, 4.0, 4.0), 10).len(),
            1
        );
        assert_eq!(
            collect(&img, &Ellipse::from_f64(0.2, -0.3, 30_000.0, 30_000.0), 1).len(),
            1
        );
        assert!(collect(&img, &Ellipse::from_f64(3.0, 0.0, 2.0, 2.0), 10).is_empty());
    }

    #[test]
    fn windows_outside_the_frame_visit_nothing() {
        let buf = vec![0u8; 40 * 30 * 3];
        let img = ImageView::<Rgb888>::new(&buf, 40, 30, 40).unwrap();
        for e in [
            Ellipse::from_f64(-20.0, 15.0, 10.0, 10.0),
            Ellipse::from_f64(60.0, 15.0, 10.0, 10.0),
            Ellipse::from_f64(20.0, -20.0, 10.0, 10.0),
            Ellipse::from_f64(20.0, 50.0, 10.0, 10.0),
            Ellipse::from_f64(-32_768.0, -32_768.0, 1000.0, 1000.0),
            Ellipse::from_f64(32_767.0, 32_767.0, 32_767.0, 0.5),
        ] {
            assert!(collect(&img, &e, 1000).is_empty(), "{e:?}");
        }
    }

    #[test]
    fn clipped_windows_stay_in_bounds() {
        // stride > width: padding must never be visited.
        let (w, h, stride) = (37usize, 23usize, 41usize);
        let buf = vec![0u8; stride * h];
        let img = ImageView::<Gray8>::new(&buf, w, h, stride).unwrap();
        let mut rng = crate::rng::Rng::new(5);
        for _ in 0..2000 {
            let cx = rng.below(140) as f64 - 50.0 + rng.uniform().to_f64();
            let cy = rng.below(120) as f64 - 50.0 + rng.uniform().to_f64();
            let hx = rng.below(60) as f64 + rng.uniform().to_f64();
            let hy = rng.below(60) as f64 + rng.uniform().to_f64();
            let cap = rng.below(400);
            let e = Ellipse::from_f64(cx, cy, hx, hy);
            let mut n = 0;
            let visited = visit(&img, &e, cap, |row, x, wt| {
                assert!(x < w && row.y() < h && wt <= WEIGHT_ONE);
                assert_eq!(row.bytes().len(), w);
                n += 1;
            });
            assert_eq!(visited, n);
            assert!(n <= cap);
        }
    }

    /// The step alone keeps every window within its cap: run without the safety stop
    /// over many sizes, shapes, positions and caps, including ellipses larger than the
    /// frame and caps of 1 and 2.
    #[test]
    fn step_bounds_the_pixel_count() {
        let buf = vec![0u8; 400 * 300];
        let img = ImageView::<Gray8>::new(&buf, 400, 300, 400).unwrap();
        let mut rng = crate::rng::Rng::new(77);
        let mut tight = 0.0f64;
        for i in 0..20_000 {
            let scale = [1.0, 4.0, 16.0, 64.0, 256.0, 2000.0][i % 6];
            let hx = 0.5 + scale * rng.uniform().to_f64();
            let hy = 0.5 + scale * rng.uniform().to_f64();
            let cx = 200.0 + (rng.uniform().to_f64() - 0.5) * 100.0;
            let cy = 150.0 + (rng.uniform().to_f64() - 0.5) * 100.0;
            let cap = match i % 4 {
                0 => 1 + rng.below(3),
                1 => 1 + rng.below(64),
                2 => 1 + rng.below(4096),
                _ => MAX_CAP - rng.below(1000),
            };
            let e = Ellipse::from_f64(cx, cy, hx, hy);
            // `rows` also asserts that its stop at `cap` never acts.
            let n = rows(&img, &e, cap, |_| {});
            assert!(
                n <= cap,
                "{e:?} cap {cap}: {n} pixels, step {}",
                sampling_step(&e, cap)
            );
            if cap >= 256 && hx * hy * 3.2 > cap as f64 && hx < 150.0 && hy < 100.0 {
                tight = tight.max(n as f64 / cap as f64);
            }
        }
        // The bound is not wastefully loose: some capped windows use most of their cap.
        std::println!("best use of the cap {tight}");
        assert!(tight > 0.6, "best use of the cap {tight}");
    }

    #[test]
    fn step_grows_with_the_window() {
        let small = Ellipse::from_f64(0.0, 0.0, 5.0, 5.0);
        assert_eq!(sampling_step(&small, 1000), 1);
        let big = Ellipse::from_f64(0.0, 0.0, 200.0, 100.0);
        let s = sampling_step(&big, 1000);
        assert!((8..=10).contains(&s), "{s}");
        assert_eq!(sampling_step(&big, 0), 0);
        assert_eq!(
            sampling_step(&Ellipse::from_f64(0.0, 0.0, 0.25, 9.0), 10),
            0
        );
        let huge = Ellipse::from_f64(0.0, 0.0, 32_767.9, 32_767.9);
        assert_eq!(sampling_step(&huge, 1), 65_536);
        assert!(sampling_step(&huge, u32::MAX) >= 228);
    }

    #[test]
    fn symmetric_window_is_symmetric() {
        let buf = vec![0u8; 21 * 21];
        let img = ImageView::<Gray8>::new(&buf, 21, 21, 21).unwrap();
        let px = collect(&img, &Ellipse::from_f64(10.0, 10.0, 6.5, 4.25), 10_000);
        for &(x, y, w) in &px {
            let mirror = px.iter().find(|p| p.0 == 20 - x && p.1 == 20 - y).unwrap();
            assert!((mirror.2 as i64 - w as i64).abs() <= 2, "{x},{y}");
        }
    }
}
