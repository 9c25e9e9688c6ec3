//! The 5-tap gradient operator on luma, read through the frame's crosses of taps.

use crate::image::{Crosses, ImageView, PixelFormat, Taps};

/// The 5-tap derivative `I(+2) + 2 I(+1) - 2 I(-1) - I(-2)` of the taps `[I(-2), I(-1),
/// I(+1), I(+2)]` of a line, `-765..=765`.
#[inline(always)]
fn derivative(taps: Taps) -> i32 {
    let [before2, before1, after1, after2] = taps;
    after2 + 2 * after1 - 2 * before1 - before2
}

/// `gx^2 + gy^2`, `0..=2 * 765^2`.
#[inline(always)]
fn squared([gx, gy]: [i32; 2]) -> u32 {
    (gx * gx + gy * gy) as u32
}

/// `gx^2 + gy^2` at `(x, y)` (px), whose cross of taps lies in the frame
/// ([`Crosses::inside`]): the taps read unclamped.
#[inline(always)]
pub(super) fn interior_gradient_sq<P: PixelFormat>(
    crosses: &Crosses<'_, P>,
    x: i32,
    y: i32,
) -> u32 {
    squared(crosses.cross(x as usize, y as usize, derivative))
}

/// The 5-tap gradient `(gx, gy)` at `(x, y)` (px; clamped into the frame first), taps
/// clamped into the frame; each component in `-765..=765`.
#[inline]
pub fn gradient<P: PixelFormat>(img: &ImageView<'_, P>, x: i32, y: i32) -> (i32, i32) {
    let [gx, gy] = img.clamped_cross(x, y, derivative);
    (gx, gy)
}

/// Squared gradient magnitude `gx^2 + gy^2` at `(x, y)` (px), `0..=2 * 765^2`.
#[inline]
pub fn gradient_sq<P: PixelFormat>(img: &ImageView<'_, P>, x: i32, y: i32) -> u32 {
    squared(img.clamped_cross(x, y, derivative))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Gray8, Rgb565Le, Rgb888, Yuv422};
    use std::vec::Vec;

    #[test]
    fn operator_on_a_ramp_and_a_step() {
        // Horizontal ramp I = 10 x: gx = 10 (2 + 2 + 2 + 2) = 80, gy = 0.
        let buf: Vec<u8> = (0..10 * 5).map(|i| (10 * (i % 10)) as u8).collect();
        let img = ImageView::<Gray8>::new(&buf, 10, 5, 10).unwrap();
        assert_eq!(gradient(&img, 5, 2), (80, 0));
        // At the left border taps clamp: I(-1) = I(-2) = I(0) = 0 -> gx = 20 + 20 = 40.
        assert_eq!(gradient(&img, 0, 2), (40, 0));
        assert_eq!(gradient(&img, 9, 0), (40, 0));
        assert_eq!(gradient_sq(&img, 5, 2), 6400);
        // Coordinates far outside clamp, never panic.
        assert_eq!(gradient(&img, i32::MAX, i32::MIN), (40, 0));
        // Saturated step, 0 -> 255 between rows 2 and 3: gy = 3 * 255 at rows 2 and 3.
        let buf: Vec<u8> = (0..6 * 6)
            .map(|i| if i / 6 >= 3 { 255 } else { 0 })
            .collect();
        let img = ImageView::<Gray8>::new(&buf, 6, 6, 6).unwrap();
        assert_eq!(gradient(&img, 2, 2), (0, 765));
        assert_eq!(gradient(&img, 2, 3), (0, 765));
        assert_eq!(gradient(&img, 2, 1), (0, 255));
    }

    /// The gradient with every tap read through the clamping accessor.
    fn clamped_gradient<P: PixelFormat>(img: &ImageView<'_, P>, x: i32, y: i32) -> (i32, i32) {
        let (xc, yc) = img.clamp(x, y);
        let (x, y) = (xc as i32, yc as i32);
        let l = |dx: i32, dy: i32| img.luma(x + dx, y + dy) as i32;
        (
            l(2, 0) + 2 * l(1, 0) - 2 * l(-1, 0) - l(-2, 0),
            l(0, 2) + 2 * l(0, 1) - 2 * l(0, -1) - l(0, -2),
        )
    }

    fn interior_and_border_agree<P: PixelFormat>(bytes_per_px: usize) {
        let mut rng = crate::rng::Rng::new(5);
        for (w, h, stride) in [(1, 1, 1), (4, 3, 4), (5, 5, 6), (12, 9, 16), (31, 7, 32)] {
            let buf: Vec<u8> = (0..stride * h * bytes_per_px)
                .map(|_| rng.below(256) as u8)
                .collect();
            let Ok(img) = ImageView::<P>::new(&buf, w, h, stride) else {
                continue; // odd YUYV sizes
            };
            for y in -3..h as i32 + 3 {
                for x in -3..w as i32 + 3 {
                    assert_eq!(
                        gradient(&img, x, y),
                        clamped_gradient(&img, x, y),
                        "{w}x{h} stride {stride} at ({x}, {y})"
                    );
                }
            }
        }
    }

    #[test]
    fn interior_fast_path_reads_the_clamped_taps() {
        interior_and_border_agree::<Gray8>(1);
        interior_and_border_agree::<Rgb888>(3);
        interior_and_border_agree::<Rgb565Le>(2);
        interior_and_border_agree::<crate::image::Rgb565Be>(2);
        interior_and_border_agree::<Yuv422>(2);
    }
}
