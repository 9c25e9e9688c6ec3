//! Boxes in pixels, the way detectors and datasets give a target, and their ellipses.
//!
//! A [`Rect`] `{x, y, w, h}` is 0-based, with pixel centres at integer coordinates: a box
//! of whole pixels covers columns `x..=x+w-1` and rows `y..=y+h-1`, so its centre is
//! `(x + (w-1)/2, y + (h-1)/2)` (the OTB benchmark's convention). The trackers work on
//! the box's inscribed ellipse: that centre, half-axes `w/2` and `h/2`. The conversion
//! back gives the ellipse's bounding box, so a box survives the round trip exactly.

use crate::fixed::Q16;
use crate::window::Ellipse;

/// An axis-aligned box: top-left corner `(x, y)` and size `w x h`, px, Q16.16, 0-based.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Rect {
    /// Left edge, px, Q16.16 (the centre of the leftmost pixel column).
    pub x: Q16,
    /// Top edge, px, Q16.16 (the centre of the top pixel row).
    pub y: Q16,
    /// Width, px, Q16.16.
    pub w: Q16,
    /// Height, px, Q16.16.
    pub h: Q16,
}

impl Rect {
    /// A box of whole pixels: top-left `(x, y)`, size `w x h`, px (saturating at the
    /// Q16.16 range, ±32,767 px).
    pub const fn new(x: i32, y: i32, w: i32, h: i32) -> Self {
        Self {
            x: Q16::from_int(x),
            y: Q16::from_int(y),
            w: Q16::from_int(w),
            h: Q16::from_int(h),
        }
    }

    /// A box from Q16.16 fields, px.
    pub const fn from_q16(x: Q16, y: Q16, w: Q16, h: Q16) -> Self {
        Self { x, y, w, h }
    }

    /// The box rounded to whole pixels `(x, y, w, h)`, halves up.
    pub const fn px(&self) -> (i32, i32, i32, i32) {
        (
            self.x.round_int(),
            self.y.round_int(),
            self.w.round_int(),
            self.h.round_int(),
        )
    }

    /// The centre `(x + (w-1)/2, y + (h-1)/2)`, px, Q16.16.
    pub const fn centre(&self) -> (Q16, Q16) {
        (centre_of(self.x, self.w), centre_of(self.y, self.h))
    }
}

/// One half, px.
const HALF: Q16 = Q16::from_bits(1 << 15);

/// `start + (size - 1) / 2`, rounded to nearest (halves away from zero), saturating.
const fn centre_of(start: Q16, size: Q16) -> Q16 {
    // Twice the centre, exact in i64: 2 start + size - 1.
    halve(2 * start.to_bits() as i64 + size.to_bits() as i64 - Q16::ONE.to_bits() as i64)
}

/// `value / 2`, rounded to nearest (halves away from zero).
const fn half(value: Q16) -> Q16 {
    halve(value.to_bits() as i64)
}

/// `bits / 2` (Q16.16 bits), rounded to nearest (halves away from zero), saturating.
const fn halve(bits: i64) -> Q16 {
    let half = if bits >= 0 {
        (bits + 1) >> 1
    } else {
        -((-bits + 1) >> 1)
    };
    Q16::saturate(half)
}

impl From<Rect> for Ellipse {
    /// The inscribed ellipse: the box's centre, half-axes `w/2` and `h/2`.
    fn from(r: Rect) -> Self {
        let (cx, cy) = r.centre();
        Ellipse::new(cx, cy, half(r.w), half(r.h))
    }
}

impl From<Ellipse> for Rect {
    /// The bounding box: size `2hx x 2hy`, top-left `(cx - hx + 1/2, cy - hy + 1/2)`.
    fn from(e: Ellipse) -> Self {
        let (w, h) = (e.hx.mul_int(2), e.hy.mul_int(2));
        let corner = |c: Q16, half_axis: Q16| c.saturating_sub(half_axis).saturating_add(HALF);
        Rect::from_q16(corner(e.cx, e.hx), corner(e.cy, e.hy), w, h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn q(v: f64) -> Q16 {
        Q16::from_f64(v)
    }

    #[test]
    fn whole_pixel_box_has_the_otb_centre_and_half_axes() {
        // Columns 10..=19, rows 20..=49.
        let e = Ellipse::from(Rect::new(10, 20, 10, 30));
        assert_eq!(
            (e.cx, e.cy, e.hx, e.hy),
            (q(14.5), q(34.5), q(5.0), q(15.0))
        );
        assert_eq!(Rect::new(10, 20, 10, 30).centre(), (q(14.5), q(34.5)));
    }

    #[test]
    fn round_trip_is_exact() {
        for (x, y, w, h) in [
            (0, 0, 1, 1),
            (-5, 7, 3, 8),
            (140, 90, 40, 60),
            (0, 0, 320, 240),
        ] {
            let r = Rect::new(x, y, w, h);
            assert_eq!(Rect::from(Ellipse::from(r)), r);
            assert_eq!(r.px(), (x, y, w, h));
        }
        let e = Ellipse::new(q(72.25), q(64.75), q(5.5), q(12.875));
        assert_eq!(Ellipse::from(Rect::from(e)), e);
    }

    #[test]
    fn conversion_matches_the_f64_formula_rounded() {
        // Fractional boxes as datasets give them, Q16.16 fields.
        let mut state = 0x2545_f491u32;
        for _ in 0..20_000 {
            let mut next = || {
                state ^= state << 13;
                state ^= state >> 17;
                state ^= state << 5;
                state
            };
            let bits = |n: u32, range: i32| (n % (2 * range as u32)) as i32 - range;
            let r = Rect::from_q16(
                Q16::from_bits(bits(next(), 1 << 26)),
                Q16::from_bits(bits(next(), 1 << 26)),
                Q16::from_bits((next() % (1 << 26)) as i32),
                Q16::from_bits((next() % (1 << 26)) as i32),
            );
            let e = Ellipse::from(r);
            let (x, w) = (r.x.to_f64(), r.w.to_f64());
            assert_eq!(e.cx, q(x + (w - 1.0) / 2.0), "{r:?}");
            assert_eq!(e.hx, q(w / 2.0), "{r:?}");
        }
    }

    #[test]
    fn conversions_saturate_at_the_rails() {
        let e = Ellipse::from(Rect::from_q16(Q16::MAX, Q16::MIN, Q16::MAX, Q16::MAX));
        let (min, max) = (Q16::MIN.to_f64(), Q16::MAX.to_f64());
        assert_eq!((e.cx, e.cy), (Q16::MAX, q(min + (max - 1.0) / 2.0)));
        let r = Rect::from(Ellipse::new(Q16::MIN, Q16::MAX, Q16::MAX, Q16::MAX));
        // x = MIN - MAX saturates to MIN before the half is added.
        assert_eq!((r.x, r.y), (q(-32767.5), q(0.5)));
        assert_eq!((r.w, r.h), (Q16::MAX, Q16::MAX));
        assert_eq!(Rect::new(i32::MAX, i32::MIN, 0, 0).x, Q16::MAX);
    }
}
