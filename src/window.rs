//! Elliptical image windows: the pixels inside an axis-aligned ellipse, clipped to the
//! frame, each with its Epanechnikov kernel weight, and never more of them than a cap.
//!
//! # Kernel weights
//! A pixel at `(x, y)` has `d^2 = ((x - cx) / hx)^2 + ((y - cy) / hy)^2` and weight
//! `k = 1 - d^2` in Q0.16: an integer in `0..=65536` ([`WEIGHT_ONE`] is 1 at the centre).
//! The error against the exact `65536 (1 - d^2)` is below 8 units (about 1.2e-4).
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
//! Per window: a few 64-bit divisions. Per row: one 32-bit integer square root and a few
//! multiplies. Per pixel: an add, a shift, a multiply, a saturating subtract and the
//! caller's closure; no division.
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

use crate::fixed::Q16;
use crate::image::{ImageView, PixelFormat, Row};

/// Kernel weight of the ellipse centre, 1.0 in Q0.16.
pub const WEIGHT_ONE: u32 = 1 << 16;

/// Largest cap on the pixels visited per window, px.
pub const MAX_CAP: u32 = 65_535;

/// Smallest half-axis of a non-empty window, px, Q16.16 (0.5 px).
pub const MIN_HALF_AXIS: Q16 = Q16::HALF;

/// 1.0 in Q2.30, the scale of the normalised coordinates inside [`visit`].
const ONE_Q30: i64 = 1 << 30;

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

/// The lattice step [`visit`] uses for `e` under `cap`, px (`>= 1`); 0 when it visits
/// nothing (degenerate ellipse or `cap == 0`). `cap` is in px, lowered to [`MAX_CAP`].
pub fn sampling_step(e: &Ellipse, cap: u32) -> u32 {
    let cap = cap.min(MAX_CAP) as u64;
    if cap == 0 || !e.is_visitable() {
        return 0;
    }
    let (hx, hy) = (e.hx.to_bits() as u64, e.hy.to_bits() as u64);
    // Any step above the longer axis leaves at most one lattice point per axis.
    let one_point = ((2 * hx.max(hy)) >> 16) + 1;
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
pub fn visit<'a, P, F>(img: &ImageView<'a, P>, e: &Ellipse, cap: u32, f: F) -> u32
where
    P: PixelFormat,
    F: FnMut(&Row<'a, P>, usize, u32),
{
    let cap = cap.min(MAX_CAP);
    visit_limited(img, e, cap, cap, f)
}

/// `floor(a / s)` for `s >= 1` (0 for `s <= 0`, which callers never pass).
#[inline(always)]
fn floor_div(a: i32, s: i32) -> i32 {
    if s > 0 {
        a.div_euclid(s)
    } else {
        0
    }
}

/// [`visit`] with the step chosen for `cap` but the count stopped at `limit` instead
/// (tests pass `u32::MAX` to check that the step alone keeps the count within `cap`).
#[inline(always)]
fn visit_limited<'a, P, F>(
    img: &ImageView<'a, P>,
    e: &Ellipse,
    cap: u32,
    limit: u32,
    mut f: F,
) -> u32
where
    P: PixelFormat,
    F: FnMut(&Row<'a, P>, usize, u32),
{
    let s = sampling_step(e, cap);
    if s == 0 {
        return 0;
    }
    let (cx, cy) = (e.cx.to_bits() as i64, e.cy.to_bits() as i64);
    let (hx, hy) = (e.hx.to_bits() as u32, e.hy.to_bits() as u32); // 2^15..2^31
    let (xc, yc) = (e.cx.round_int(), e.cy.round_int()); // px, |.| <= 32768
    let si = s as i32; // 1..=65536

    // Rows inside the ellipse and the frame, as lattice indices j (y = yc + j s).
    let y_lo = (-((hy as i64 - cy) >> 16)).max(0) as i32; // ceil(cy - hy)
    let y_hi = ((cy + hy as i64) >> 16).min(img.height() as i64 - 1) as i32; // floor(cy + hy)
    if y_lo > y_hi {
        return 0;
    }
    let j_lo = -floor_div(yc - y_lo, si); // ceil((y_lo - yc) / s)
    let j_hi = floor_div(y_hi - yc, si);
    // Columns inside the frame, as lattice indices k (x = xc + k s).
    let k_frame_lo = -floor_div(xc, si) as i64;
    let k_frame_hi = floor_div(img.width() as i32 - 1 - xc, si) as i64;
    if k_frame_lo > k_frame_hi {
        return 0;
    }

    // Reciprocal half-axes, 2^62 / h (2^31..2^47): (v - c) * inv >> 32 is (v - c) / h in
    // Q2.30 for |v - c| <= h, with a relative error below 2^-31.
    let inv_hx = (1u64 << 62).checked_div(hx as u64).unwrap_or(0) as i64;
    let inv_hy = (1u64 << 62).checked_div(hy as u64).unwrap_or(0) as i64;
    // The lattice step in normalised x, Q2.30; past one point per row it is unused, so
    // clamping it keeps the inner loop in `i32`.
    let dt = ((s as u64 * inv_hx as u64) >> 16).min(i32::MAX as u64) as i32;
    // The half-axis and the centre's offset from the anchor in lattice units, Q16.
    let ax = hx.checked_div(s).unwrap_or(0) as i64;
    let off = ((cx - ((xc as i64) << 16)) as i32)
        .checked_div(si)
        .unwrap_or(0) as i64;

    let mut visited = 0u32;
    let mut j = j_lo;
    while j <= j_hi && visited < limit {
        let y = yc + j * si; // y_lo..=y_hi, so |y - cy| <= hy
        let ty = ((((y as i64) << 16) - cy) * inv_hy) >> 32; // (y - cy) / hy, Q2.30
        let ry = ((ty * ty) >> 30).min(ONE_Q30); // ty^2, Q2.30
        let root = ((ONE_Q30 - ry) as u32).isqrt() as i64; // sqrt(1 - ty^2), Q0.15
        let half_chord = (ax * root) >> 15; // lattice units, Q16
                                            // Lattice points strictly inside the chord (points on the boundary weigh 0).
        let k_lo = (-((half_chord - off - 1) >> 16)).max(k_frame_lo);
        let k_hi = ((off + half_chord - 1) >> 16).min(k_frame_hi);
        if k_lo <= k_hi {
            let count = ((k_hi - k_lo + 1) as u32).min(limit - visited);
            visited += count;
            let row = img.row(y as usize);
            let x0 = xc as i64 + k_lo * s as i64; // 0..width, inside the chord
            let mut t = ((((x0 << 16) - cx) * inv_hx) >> 32).clamp(-ONE_Q30, ONE_Q30) as i32;
            let mut x = x0 as usize;
            let ry = ry as u32;
            for _ in 0..count {
                // |t| <= 1 (Q2.30) inside the chord, so t15^2 + ry <= 2^31 + 2^17.
                let t15 = t.wrapping_add(1 << 14) >> 15;
                let d2 = (t15.wrapping_mul(t15) as u32).wrapping_add(ry);
                let w = (1u32 << 30).saturating_sub(d2) >> 14;
                f(&row, x, w);
                t = t.wrapping_add(dt);
                x += s as usize;
            }
        }
        j += 1;
    }
    visited
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Gray8, Rgb888};
    use std::vec;
    use std::vec::Vec;

    fn q(v: f64) -> Q16 {
        Q16::from_f64(v)
    }

    fn ellipse(cx: f64, cy: f64, hx: f64, hy: f64) -> Ellipse {
        Ellipse::new(q(cx), q(cy), q(hx), q(hy))
    }

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
        let e = ellipse(30.3, 20.7, 12.4, 7.9);
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

    #[test]
    fn centre_pixel_of_a_tiny_window() {
        let buf = [7u8; 9];
        let img = ImageView::<Gray8>::new(&buf, 3, 3, 3).unwrap();
        let px = collect(&img, &ellipse(1.0, 1.0, 0.5, 0.5), 100);
        assert_eq!(px, vec![(1, 1, WEIGHT_ONE)]);
        // Below half a pixel, or zero, or negative: nothing.
        for (hx, hy) in [(0.49, 3.0), (3.0, 0.0), (-2.0, 2.0), (0.0, 0.0)] {
            assert!(collect(&img, &ellipse(1.0, 1.0, hx, hy), 100).is_empty());
        }
        assert!(collect(&img, &ellipse(1.0, 1.0, 2.0, 2.0), 0).is_empty());
    }

    #[test]
    fn one_pixel_frame() {
        let img = ImageView::<Gray8>::new(&[9], 1, 1, 1).unwrap();
        assert_eq!(collect(&img, &ellipse(0.0, 0.0, 4.0, 4.0), 10).len(), 1);
        assert_eq!(
            collect(&img, &ellipse(0.2, -0.3, 30_000.0, 30_000.0), 1).len(),
            1
        );
        assert!(collect(&img, &ellipse(3.0, 0.0, 2.0, 2.0), 10).is_empty());
    }

    #[test]
    fn windows_outside_the_frame_visit_nothing() {
        let buf = vec![0u8; 40 * 30 * 3];
        let img = ImageView::<Rgb888>::new(&buf, 40, 30, 40).unwrap();
        for e in [
            ellipse(-20.0, 15.0, 10.0, 10.0),
            ellipse(60.0, 15.0, 10.0, 10.0),
            ellipse(20.0, -20.0, 10.0, 10.0),
            ellipse(20.0, 50.0, 10.0, 10.0),
            ellipse(-32_768.0, -32_768.0, 1000.0, 1000.0),
            ellipse(32_767.0, 32_767.0, 32_767.0, 0.5),
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
            let e = ellipse(cx, cy, hx, hy);
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
            let e = ellipse(cx, cy, hx, hy);
            let n = visit_limited(&img, &e, cap, u32::MAX, |_, _, _| {});
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
        let small = ellipse(0.0, 0.0, 5.0, 5.0);
        assert_eq!(sampling_step(&small, 1000), 1);
        let big = ellipse(0.0, 0.0, 200.0, 100.0);
        let s = sampling_step(&big, 1000);
        assert!((8..=10).contains(&s), "{s}");
        assert_eq!(sampling_step(&big, 0), 0);
        assert_eq!(sampling_step(&ellipse(0.0, 0.0, 0.25, 9.0), 10), 0);
        let huge = ellipse(0.0, 0.0, 32_767.9, 32_767.9);
        assert_eq!(sampling_step(&huge, 1), 65_536);
        assert!(sampling_step(&huge, u32::MAX) >= 228);
    }

    #[test]
    fn symmetric_window_is_symmetric() {
        let buf = vec![0u8; 21 * 21];
        let img = ImageView::<Gray8>::new(&buf, 21, 21, 21).unwrap();
        let px = collect(&img, &ellipse(10.0, 10.0, 6.5, 4.25), 10_000);
        for &(x, y, w) in &px {
            let mirror = px.iter().find(|p| p.0 == 20 - x && p.1 == 20 - y).unwrap();
            assert!((mirror.2 as i64 - w as i64).abs() <= 2, "{x},{y}");
        }
    }
}
