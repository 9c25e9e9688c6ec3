//! Pixel formats: the sealed marker types of the byte layouts a camera delivers, and how
//! each reads a pixel's luma and colour bin from its bytes.

use super::bins::{luma_of_rgb, rgb565_luma, Binning};

/// A pixel layout (sealed: the marker types of this module). Frames of every format are
/// read through [`super::ImageView`], which hands out complete rows only.
pub trait PixelFormat: Read + Copy + core::fmt::Debug + 'static {
    /// Bytes per pixel (a [`Yuv422`] pair of pixels takes 4).
    const BYTES_PER_PIXEL: usize;
    /// Whether width and stride must be even.
    const PAIRED: bool;
}

mod private {
    use super::Binning;

    /// A run of pixels along a row: `count` of them from column `x0`, `step` apart (px,
    /// `step >= 1`).
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub struct Run {
        /// The first pixel's column, px.
        pub x0: usize,
        /// The distance between two pixels, px.
        pub step: usize,
        /// The number of pixels.
        pub count: u32,
    }

    /// How a format reads pixels from bytes (sealed, and called by [`super::super::ImageView`]
    /// and [`super::super::Row`] alone). Every method returns 0 for a pixel past the end
    /// of the bytes, so none can panic.
    pub trait Read {
        /// Luma (0..=255) of the pixel whose bytes start at `index` of `bytes` (`x *
        /// BYTES_PER_PIXEL` into a row, or that plus whole rows into a frame; for
        /// [`super::Yuv422`], `2 x`); 0 past the end.
        fn luma_at_byte(bytes: &[u8], index: usize) -> u8;
        /// Bin (`0..Bn::BINS`) of pixel `x` (px) of `row`; 0 past its end.
        fn bin_at<Bn: Binning>(row: &[u8], x: usize) -> u16;
        /// Calls `f(bin)` for the pixels of `run` in `bytes`, left to right, as
        /// [`Read::bin_at`] would give them; the fixed-size formats read them without a
        /// bounds check per pixel.
        #[inline(always)]
        fn for_each_bin<Bn: Binning>(bytes: &[u8], run: Run, mut f: impl FnMut(u16)) {
            let mut x = run.x0;
            for _ in 0..run.count {
                f(Self::bin_at::<Bn>(bytes, x));
                x = x.wrapping_add(run.step);
            }
        }
        /// Fills `out` with the luma of the pixels from column `x0` (px) of `row` on, as
        /// [`Read::luma_at_byte`] would give them, without a bounds check per pixel.
        fn lumas(row: &[u8], x0: usize, out: &mut [u8]);
    }
}

pub(super) use private::Read;
pub(crate) use private::Run;

/// [`Read::lumas`] for a format of `BPP` bytes per pixel, `luma` giving a pixel's luma
/// from its bytes: one bounds check, then fixed-size chunks (0 past the row's end).
#[inline(always)]
fn lumas_of_run<const BPP: usize>(
    row: &[u8],
    x0: usize,
    out: &mut [u8],
    luma: impl Fn(&[u8; BPP]) -> u8,
) {
    let start = x0.saturating_mul(BPP).min(row.len());
    let run = row.get(start..).unwrap_or_default().chunks_exact(BPP);
    // The run first, so that the first output past its end is left to the zeros below.
    let mut out = out.iter_mut();
    for (px, o) in run.zip(out.by_ref()) {
        *o = px.first_chunk::<BPP>().map_or(0, &luma);
    }
    for o in out {
        *o = 0;
    }
}

/// [`Read::for_each_bin`] for a format of `BPP` bytes per pixel, `bin` giving a pixel's
/// bin from its bytes: one bounds check per run, then fixed-size chunks.
#[inline(always)]
fn bins_of_run<const BPP: usize>(
    row: &[u8],
    Run { x0, step, count }: Run,
    bin: impl Fn(&[u8; BPP]) -> u16,
    mut f: impl FnMut(u16),
) {
    let Some(last) = (count as usize).checked_sub(1) else {
        return;
    };
    let stride = step.max(1) * BPP; // >= BPP, unless it wraps
    let start = x0.saturating_mul(BPP);
    // First byte of the first pixel to the last byte of the last one.
    let run = last
        .checked_mul(stride)
        .and_then(|len| start.checked_add(len))
        .and_then(|tail| row.get(start..tail.checked_add(BPP)?));
    match run {
        // Consecutive pixels (every window below the pixel cap): chunks of a constant
        // size, no division to set them up.
        Some(run) if step == 1 => {
            for chunk in run.chunks_exact(BPP) {
                if let Some(px) = chunk.first_chunk::<BPP>() {
                    f(bin(px));
                }
            }
        }
        // `last` chunks of `stride` bytes and the last pixel's `BPP` bytes left over (or,
        // for a stride of `BPP`, `last + 1` chunks and nothing left over).
        Some(run) if stride > 0 => {
            let mut chunks = run.chunks_exact(stride);
            for chunk in &mut chunks {
                if let Some(px) = chunk.first_chunk::<BPP>() {
                    f(bin(px));
                }
            }
            if let Some(px) = chunks.remainder().first_chunk::<BPP>() {
                f(bin(px));
            }
        }
        // Partly past the row's end (never for the windows of `crate::window`): one by
        // one, 0 past the end.
        _ => {
            let mut x = x0;
            for _ in 0..count {
                let px = x
                    .checked_mul(BPP)
                    .and_then(|i| row.get(i..))
                    .and_then(|r| r.first_chunk::<BPP>());
                f(px.map_or(0, &bin));
                x = x.wrapping_add(step);
            }
        }
    }
}

/// 8-bit grey.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Gray8;

/// RGB565, each pixel a `u16`, big-endian when `BIG_ENDIAN` (cameras deliver either);
/// use the aliases [`Rgb565Le`] and [`Rgb565Be`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Rgb565<const BIG_ENDIAN: bool>;

/// RGB565, each pixel a little-endian `u16`.
pub type Rgb565Le = Rgb565<false>;

/// RGB565, each pixel a big-endian `u16`.
pub type Rgb565Be = Rgb565<true>;

/// 24-bit RGB, bytes in the order R, G, B.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Rgb888;

/// 24-bit RGB, bytes in the order B, G, R (OpenCV's).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Bgr888;

/// YUV 4:2:2: each pair of pixels in four bytes, sharing U and V, as `Y0 U Y1 V` (YUYV)
/// or, when `CHROMA_FIRST`, `U Y0 V Y1` (UYVY); sensors deliver either. Use the aliases
/// [`Yuyv`] and [`Uyvy`]; `Yuv422` alone is YUYV.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Yuv422<const CHROMA_FIRST: bool = false>;

/// YUV 4:2:2 as `Y0 U Y1 V` per pixel pair.
pub type Yuyv = Yuv422<false>;

/// YUV 4:2:2 as `U Y0 V Y1` per pixel pair.
pub type Uyvy = Yuv422<true>;

impl PixelFormat for Gray8 {
    const BYTES_PER_PIXEL: usize = 1;
    const PAIRED: bool = false;
}

impl<const BIG_ENDIAN: bool> PixelFormat for Rgb565<BIG_ENDIAN> {
    const BYTES_PER_PIXEL: usize = 2;
    const PAIRED: bool = false;
}

impl PixelFormat for Rgb888 {
    const BYTES_PER_PIXEL: usize = 3;
    const PAIRED: bool = false;
}

impl PixelFormat for Bgr888 {
    const BYTES_PER_PIXEL: usize = 3;
    const PAIRED: bool = false;
}

impl<const CHROMA_FIRST: bool> PixelFormat for Yuv422<CHROMA_FIRST> {
    const BYTES_PER_PIXEL: usize = 2;
    const PAIRED: bool = true;
}

impl Read for Gray8 {
    #[inline(always)]
    fn luma_at_byte(bytes: &[u8], index: usize) -> u8 {
        bytes.get(index).copied().unwrap_or(0)
    }
    #[inline(always)]
    fn bin_at<Bn: Binning>(row: &[u8], x: usize) -> u16 {
        Bn::from_luma(Self::luma_at_byte(row, x))
    }
    #[inline(always)]
    fn for_each_bin<Bn: Binning>(row: &[u8], run: Run, f: impl FnMut(u16)) {
        bins_of_run::<1>(row, run, |&[y]| Bn::from_luma(y), f)
    }
    #[inline(always)]
    fn lumas(row: &[u8], x0: usize, out: &mut [u8]) {
        lumas_of_run::<1>(row, x0, out, |&[y]| y)
    }
}

#[inline(always)]
fn rgb565_word(row: &[u8], x: usize, big_endian: bool) -> u16 {
    match row.get(2 * x..2 * x + 2) {
        Some(&[a, b]) if big_endian => u16::from_be_bytes([a, b]),
        Some(&[a, b]) => u16::from_le_bytes([a, b]),
        _ => 0,
    }
}

impl<const BIG_ENDIAN: bool> Read for Rgb565<BIG_ENDIAN> {
    #[inline(always)]
    fn luma_at_byte(bytes: &[u8], index: usize) -> u8 {
        match (bytes.get(index), bytes.get(index.wrapping_add(1))) {
            (Some(&a), Some(&b)) if BIG_ENDIAN => rgb565_luma(a, b),
            (Some(&lo), Some(&hi)) => rgb565_luma(hi, lo),
            _ => 0,
        }
    }
    #[inline(always)]
    fn bin_at<Bn: Binning>(row: &[u8], x: usize) -> u16 {
        Bn::from_rgb565(rgb565_word(row, x, BIG_ENDIAN))
    }
    #[inline(always)]
    fn for_each_bin<Bn: Binning>(row: &[u8], run: Run, f: impl FnMut(u16)) {
        bins_of_run::<2>(
            row,
            run,
            |&px| {
                Bn::from_rgb565(if BIG_ENDIAN {
                    u16::from_be_bytes(px)
                } else {
                    u16::from_le_bytes(px)
                })
            },
            f,
        )
    }
    #[inline(always)]
    fn lumas(row: &[u8], x0: usize, out: &mut [u8]) {
        lumas_of_run::<2>(row, x0, out, |&[a, b]| match BIG_ENDIAN {
            true => rgb565_luma(a, b),
            false => rgb565_luma(b, a),
        })
    }
}

/// `(r, g, b)` of a 24-bit pixel's bytes: R, G, B, or B, G, R when `BGR`.
#[inline(always)]
const fn rgb_of<const BGR: bool>([a, g, c]: [u8; 3]) -> (u8, u8, u8) {
    if BGR {
        (c, g, a)
    } else {
        (a, g, c)
    }
}

/// [`Read::luma_at_byte`] of a 24-bit format ([`rgb_of`]).
#[inline(always)]
fn luma_24<const BGR: bool>(bytes: &[u8], index: usize) -> u8 {
    match (
        bytes.get(index),
        bytes.get(index.wrapping_add(1)),
        bytes.get(index.wrapping_add(2)),
    ) {
        (Some(&a), Some(&g), Some(&c)) => {
            let (r, g, b) = rgb_of::<BGR>([a, g, c]);
            luma_of_rgb(r, g, b)
        }
        _ => 0,
    }
}

/// A 24-bit pixel's bin ([`rgb_of`]).
#[inline(always)]
fn bin_24<Bn: Binning, const BGR: bool>(px: [u8; 3]) -> u16 {
    let (r, g, b) = rgb_of::<BGR>(px);
    Bn::from_rgb888(r, g, b)
}

/// [`Read::bin_at`] of a 24-bit format.
#[inline(always)]
fn bin_at_24<Bn: Binning, const BGR: bool>(row: &[u8], x: usize) -> u16 {
    match row.get(3 * x..3 * x + 3) {
        Some(&[a, g, c]) => bin_24::<Bn, BGR>([a, g, c]),
        _ => 0,
    }
}

/// [`Read`] for a 24-bit format of byte order `BGR` ([`rgb_of`]).
macro_rules! read_24 {
    ($format:ty, $bgr:literal) => {
        impl Read for $format {
            #[inline(always)]
            fn luma_at_byte(bytes: &[u8], index: usize) -> u8 {
                luma_24::<$bgr>(bytes, index)
            }
            #[inline(always)]
            fn bin_at<Bn: Binning>(row: &[u8], x: usize) -> u16 {
                bin_at_24::<Bn, $bgr>(row, x)
            }
            #[inline(always)]
            fn for_each_bin<Bn: Binning>(row: &[u8], run: Run, f: impl FnMut(u16)) {
                bins_of_run::<3>(row, run, |&px| bin_24::<Bn, $bgr>(px), f)
            }
            #[inline(always)]
            fn lumas(row: &[u8], x0: usize, out: &mut [u8]) {
                lumas_of_run::<3>(row, x0, out, |&px| {
                    let (r, g, b) = rgb_of::<$bgr>(px);
                    luma_of_rgb(r, g, b)
                })
            }
        }
    };
}

read_24!(Rgb888, false);
read_24!(Bgr888, true);

impl<const CHROMA_FIRST: bool> Read for Yuv422<CHROMA_FIRST> {
    #[inline(always)]
    fn luma_at_byte(bytes: &[u8], index: usize) -> u8 {
        // A pixel's two bytes are `Y C` (YUYV) or `C Y` (UYVY).
        bytes
            .get(index.wrapping_add(CHROMA_FIRST as usize))
            .copied()
            .unwrap_or(0)
    }
    #[inline(always)]
    fn bin_at<Bn: Binning>(row: &[u8], x: usize) -> u16 {
        let pair = 2 * (x & !1);
        match row.get(pair..pair + 4) {
            Some(&[a, b, c, d]) => {
                let [y0, u, y1, v] = if CHROMA_FIRST {
                    [b, a, d, c]
                } else {
                    [a, b, c, d]
                };
                Bn::from_yuv(if x & 1 == 0 { y0 } else { y1 }, u, v)
            }
            _ => 0,
        }
    }
    #[inline(always)]
    fn lumas(row: &[u8], x0: usize, out: &mut [u8]) {
        lumas_of_run::<2>(row, x0, out, |&[a, b]| if CHROMA_FIRST { b } else { a })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{ImageView, Rgb8x8x8};

    /// BGR bytes read as the RGB pixel they hold: the same luma and bins.
    #[test]
    fn bgr_reads_as_the_reversed_rgb() {
        let rgb = [200u8, 30, 90, 10, 250, 120];
        let bgr = [90u8, 30, 200, 120, 250, 10];
        let (a, b) = (
            ImageView::<Rgb888>::new(&rgb, 2, 1, 2).unwrap(),
            ImageView::<Bgr888>::new(&bgr, 2, 1, 2).unwrap(),
        );
        for x in 0..2 {
            assert_eq!(a.luma(x, 0), b.luma(x, 0));
            assert_eq!(
                a.row(0).bin::<Rgb8x8x8>(x as usize),
                b.row(0).bin::<Rgb8x8x8>(x as usize)
            );
        }
    }

    /// Runs of bins equal the bins one by one, every format, every step, at and past the
    /// row's end.
    #[test]
    fn runs_of_bins_and_lumas_equal_single_ones() {
        fn check<P: PixelFormat>(bytes_per_px: usize) {
            extern crate std;
            use std::vec::Vec;
            let mut r = crate::rng::Rng::new(2);
            let (w, h) = (14usize, 3usize);
            let buf: Vec<u8> = (0..w * h * bytes_per_px)
                .map(|_| r.next_u32() as u8)
                .collect();
            let img = ImageView::<P>::new(&buf, w, h, w).unwrap();
            let row = img.row(1).bytes();
            for x0 in 0..w + 2 {
                for step in 1..6 {
                    for count in 0..8u32 {
                        let mut got = Vec::new();
                        let run = Run { x0, step, count };
                        P::for_each_bin::<Rgb8x8x8>(row, run, |b| got.push(b));
                        let want: Vec<u16> = (0..count as usize)
                            .map(|k| P::bin_at::<Rgb8x8x8>(row, x0 + k * step))
                            .collect();
                        assert_eq!(got, want, "x0 {x0} step {step} count {count}");
                        if step == 1 {
                            let mut got = std::vec![7u8; count as usize];
                            P::lumas(row, x0, &mut got);
                            let want: Vec<u8> = (0..count as usize)
                                .map(|k| P::luma_at_byte(row, (x0 + k) * bytes_per_px))
                                .collect();
                            assert_eq!(got, want, "luma: x0 {x0} count {count}");
                        }
                    }
                }
            }
        }
        check::<Gray8>(1);
        check::<Rgb565Le>(2);
        check::<Rgb565Be>(2);
        check::<Rgb888>(3);
        check::<Bgr888>(3);
        check::<Yuyv>(2);
        check::<Uyvy>(2);
    }
}
