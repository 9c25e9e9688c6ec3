//! The frame as the f64 tracker reads it: RGB888 pixels, and image patches resampled from
//! it to a fixed size in px.

/// A borrowed RGB888 frame, rows back to back.
#[derive(Clone, Copy, Debug)]
pub struct RgbImage<'a> {
    /// Width, px.
    pub width: usize,
    /// Height, px.
    pub height: usize,
    /// `width * height * 3` bytes, R, G, B per pixel.
    pub rgb: &'a [u8],
}

/// How a patch reads the frame along an axis that shrinks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Resample {
    /// Each output pixel is the mean of the source pixels whose centres fall in its
    /// footprint (OpenCV's `INTER_AREA`): reads grow with the region.
    Area,
    /// Each output pixel is interpolated linearly between the two source pixels nearest its
    /// centre, as along an axis that grows (OpenCV's `INTER_LINEAR`): 2 reads an axis.
    Bilinear,
}

/// An image patch in f64: `width x height` px of R, G, B in `[0, 255]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Patch {
    /// Width, px.
    pub width: usize,
    /// Height, px.
    pub height: usize,
    /// R, G, B per pixel, rows back to back.
    pub rgb: Vec<[f64; 3]>,
}

impl Patch {
    /// The pixel at column `x`, row `y`.
    pub fn at(&self, x: usize, y: usize) -> [f64; 3] {
        self.rgb[y * self.width + x]
    }

    /// The patch in grey: every channel of a pixel its luma.
    pub fn greyed(&self) -> Patch {
        Patch {
            width: self.width,
            height: self.height,
            rgb: self.grey().into_iter().map(|l| [l; 3]).collect(),
        }
    }

    /// Luma `0.299 R + 0.587 G + 0.114 B` per pixel, in `[0, 255]`.
    pub fn grey(&self) -> Vec<f64> {
        self.rgb
            .iter()
            .map(|p| 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2])
            .collect()
    }
}

impl RgbImage<'_> {
    fn pixel(&self, x: usize, y: usize) -> [f64; 3] {
        let i = (y * self.width + x) * 3;
        [
            f64::from(self.rgb[i]),
            f64::from(self.rgb[i + 1]),
            f64::from(self.rgb[i + 2]),
        ]
    }

    /// The frame's 8-bit luma at a pixel, as the core reads it
    /// ([`rbtrack::image::luma_of_rgb`]: `(77 R + 150 G + 29 B + 128) >> 8`), in every
    /// channel.
    fn luma(&self, x: usize, y: usize) -> [f64; 3] {
        let i = (y * self.width + x) * 3;
        let l = rbtrack::image::luma_of_rgb(self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]);
        [f64::from(l); 3]
    }

    /// The region of `size` px (width, height) centred on `centre` (px, pixel centres at
    /// integer coordinates) resampled to `out` px (width, height). Along an axis that
    /// shrinks, each output pixel is read as `resample` says; along one that grows, it is
    /// interpolated linearly between the two nearest. Pixels outside the frame repeat its
    /// nearest edge.
    pub fn patch(
        &self,
        centre: (f64, f64),
        size: (f64, f64),
        out: (usize, usize),
        resample: Resample,
    ) -> Patch {
        self.resampled(centre, size, out, resample, |x, y| self.pixel(x, y))
    }

    /// [`RgbImage::patch`] of the frame's 8-bit luma, as the core reads a frame's luma
    /// before resampling it and keeps the result (to `1/256` of a grey level, a half
    /// rounded up): every channel of a patch pixel its luma.
    pub fn luma_patch(
        &self,
        centre: (f64, f64),
        size: (f64, f64),
        out: (usize, usize),
        resample: Resample,
    ) -> Patch {
        let mut patch = self.resampled(centre, size, out, resample, |x, y| self.luma(x, y));
        for p in &mut patch.rgb {
            *p = [(p[0] * 256.0 + 0.5).floor() / 256.0; 3];
        }
        patch
    }

    /// The region of `size` px centred on `centre` read at `out` samples (width, height),
    /// each the frame pixel nearest its centre (`left + (i + 1/2) size / out`, a half
    /// rounded up), clamped into the frame: the colour samples the core reads.
    pub fn nearest(&self, centre: (f64, f64), size: (f64, f64), out: (usize, usize)) -> Patch {
        let at = |c: f64, len: f64, n: usize, limit: usize| -> Vec<usize> {
            (0..n)
                .map(|i| {
                    let x = c - len / 2.0 + (i as f64 + 0.5) * len / n as f64;
                    (x + 0.5).floor().clamp(0.0, limit as f64 - 1.0) as usize
                })
                .collect()
        };
        let xs = at(centre.0, size.0, out.0, self.width);
        let ys = at(centre.1, size.1, out.1, self.height);
        let rgb = ys
            .iter()
            .flat_map(|&y| xs.iter().map(move |&x| (x, y)))
            .map(|(x, y)| self.pixel(x, y))
            .collect();
        Patch {
            width: out.0,
            height: out.1,
            rgb,
        }
    }

    /// [`RgbImage::patch`] of the pixels `read` gives.
    fn resampled(
        &self,
        centre: (f64, f64),
        size: (f64, f64),
        out: (usize, usize),
        resample: Resample,
        read: impl Fn(usize, usize) -> [f64; 3],
    ) -> Patch {
        let xs = taps(centre.0, size.0, out.0, self.width, resample);
        let ys = taps(centre.1, size.1, out.1, self.height, resample);
        let mut rgb = Vec::with_capacity(out.0 * out.1);
        for ty in &ys {
            for tx in &xs {
                let mut sum = [0.0; 3];
                for &(y, wy) in ty {
                    for &(x, wx) in tx {
                        let p = read(x, y);
                        for c in 0..3 {
                            sum[c] += wy * wx * p[c];
                        }
                    }
                }
                rgb.push(sum);
            }
        }
        Patch {
            width: out.0,
            height: out.1,
            rgb,
        }
    }
}

/// Per output pixel along one axis, the source pixels (clamped into `0..len`) and their
/// weights, summing to 1: `out` pixels over `size` px centred on `centre`.
fn taps(
    centre: f64,
    size: f64,
    out: usize,
    len: usize,
    resample: Resample,
) -> Vec<Vec<(usize, f64)>> {
    let clamp = |i: i64| i.clamp(0, len as i64 - 1) as usize;
    let step = size / out as f64;
    (0..out)
        .map(|i| {
            // The footprint [left, left + step) in px; pixel k covers [k - 0.5, k + 0.5).
            let left = centre - size / 2.0 + i as f64 * step;
            if step > 1.0 && resample == Resample::Area {
                let lo = left.ceil() as i64;
                let hi = ((left + step).ceil() as i64).max(lo + 1);
                let w = 1.0 / (hi - lo) as f64;
                (lo..hi).map(|k| (clamp(k), w)).collect()
            } else {
                let at = left + step / 2.0;
                let k = at.floor();
                let f = at - k;
                let k = k as i64;
                vec![(clamp(k), 1.0 - f), (clamp(k + 1), f)]
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(width: usize, height: usize) -> Vec<u8> {
        (0..height)
            .flat_map(|y| (0..width).flat_map(move |x| [x as u8, y as u8, 7]))
            .collect()
    }

    /// The 20 x 10 frame of [`ramp`].
    fn image(rgb: &[u8]) -> RgbImage<'_> {
        RgbImage {
            width: 20,
            height: 10,
            rgb,
        }
    }

    #[test]
    fn a_patch_of_the_same_size_copies_the_pixels() {
        let rgb = ramp(20, 10);
        let img = image(&rgb);
        // 6 x 4 px centred on (8.5, 4.5): columns 6..=11, rows 3..=6.
        let p = img.patch((8.5, 4.5), (6.0, 4.0), (6, 4), Resample::Area);
        assert_eq!(p.at(0, 0), [6.0, 3.0, 7.0]);
        assert_eq!(p.at(5, 3), [11.0, 6.0, 7.0]);
    }

    #[test]
    fn shrinking_by_two_averages_pairs() {
        let rgb = ramp(20, 10);
        let img = image(&rgb);
        let p = img.patch((9.5, 4.5), (20.0, 10.0), (10, 5), Resample::Area);
        assert_eq!(p.at(0, 0), [0.5, 0.5, 7.0]);
        assert_eq!(p.at(9, 4), [18.5, 8.5, 7.0]);
    }

    #[test]
    fn outside_the_frame_repeats_the_edge() {
        let rgb = ramp(20, 10);
        let img = image(&rgb);
        // 4 x 4 px centred on (0.5, 0.5): columns and rows -1..=2.
        let p = img.patch((0.5, 0.5), (4.0, 4.0), (4, 4), Resample::Area);
        assert_eq!(p.at(0, 0), [0.0, 0.0, 7.0]);
        assert_eq!(p.at(3, 3), [2.0, 2.0, 7.0]);
    }

    #[test]
    fn colour_samples_are_the_nearest_pixels() {
        let rgb = ramp(20, 10);
        let img = image(&rgb);
        // 4 x 2 samples over 8 x 4 px centred on (9.5, 4.5): centres 6.5, 8.5, 10.5, 12.5
        // across (halves rounded up) and 3.5, 5.5 down.
        let p = img.nearest((9.5, 4.5), (8.0, 4.0), (4, 2));
        assert_eq!(p.at(0, 0), [7.0, 4.0, 7.0]);
        assert_eq!(p.at(3, 1), [13.0, 6.0, 7.0]);
        // Past the edge, the edge pixel.
        assert_eq!(
            img.nearest((0.0, 0.0), (8.0, 4.0), (4, 2)).at(0, 0),
            [0.0, 0.0, 7.0]
        );
    }

    #[test]
    fn the_luma_patch_is_the_cores_8_bit_luma() {
        let rgb = ramp(20, 10);
        let img = image(&rgb);
        let luma = |x: u32, y: u32| f64::from((77 * x + 150 * y + 29 * 7 + 128) >> 8);
        let p = img.luma_patch((8.5, 4.5), (6.0, 4.0), (6, 4), Resample::Bilinear);
        assert_eq!(p.at(0, 0), [luma(6, 3); 3]);
        assert_eq!(p.at(5, 3), [luma(11, 6); 3]);
        // Between pixels, interpolated and kept to 1/256.
        let p = img.luma_patch((5.5, 5.5), (2.0, 2.0), (4, 4), Resample::Bilinear);
        // The first output pixel's centre is at (4.75, 4.75).
        let want = 0.25 * 0.25 * luma(4, 4)
            + 0.25 * 0.75 * (luma(5, 4) + luma(4, 5))
            + 0.75 * 0.75 * luma(5, 5);
        assert_eq!(p.at(0, 0)[0], (want * 256.0 + 0.5).floor() / 256.0);
    }

    #[test]
    fn growing_interpolates_linearly() {
        let rgb = ramp(20, 10);
        let img = image(&rgb);
        // 2 x 2 px centred on (5.5, 5.5) to 4 x 4: output centres at 4.75, 5.25, 5.75, 6.25.
        let p = img.patch((5.5, 5.5), (2.0, 2.0), (4, 4), Resample::Area);
        assert_eq!(p.at(0, 0), [4.75, 4.75, 7.0]);
        assert_eq!(p.at(1, 2), [5.25, 5.75, 7.0]);
        assert_eq!(p.at(3, 3), [6.25, 6.25, 7.0]);
    }
}
