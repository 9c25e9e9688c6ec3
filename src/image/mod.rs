//! Camera frames: the checked, borrowed [`ImageView`], its pixel formats and colour-bin
//! mappings, and every read of frame memory the tracker makes.
//!
//! A frame is a `&[u8]` (or the `&[u32]` a DMA engine fills, [`ImageView::from_words`])
//! with a width, a height and a row stride, all in pixels, checked once by
//! [`ImageView::new`] (in the manner of a checked packet view): after that no accessor can
//! panic, and reads outside the frame are clamped or empty, never out of bounds. The
//! modules above read frames only through it: pixels and rows ([`ImageView::luma`],
//! [`Row`]), runs of colour bins along a row and the 5-pixel crosses of a gradient
//! operator; none computes a byte offset.
//!
//! # Pixel formats
//! Sealed marker types implementing [`PixelFormat`]:
//!
//! | type | bytes per pixel | layout |
//! | --- | --- | --- |
//! | [`Gray8`] | 1 | luma |
//! | [`Rgb565Le`] | 2 | `u16` little-endian, `RRRRRGGG GGGBBBBB` |
//! | [`Rgb565Be`] | 2 | `u16` big-endian, same bits |
//! | [`Rgb888`] | 3 | R, G, B |
//! | [`Bgr888`] | 3 | B, G, R (OpenCV's order) |
//! | [`Yuyv`] (= [`Yuv422`]) | 2 | `Y0 U Y1 V` per pixel pair (width and stride even) |
//! | [`Uyvy`] | 2 | `U Y0 V Y1` per pixel pair (width and stride even) |
//!
//! Which format a sensor delivers is set by its registers: `docs/camera.md` lists the
//! common ones. Luma is BT.601 full range: `Y = (77 R + 150 G + 29 B + 128) >> 8` (0..=255,
//! white is 255); for YUV 4:2:2 it is the Y byte. RGB565 channels widen to 8 bits by bit
//! replication (`r8 = r5 << 3 | r5 >> 2`); the luma of an RGB565 pixel is read from two
//! 256-entry tables indexed by its two bytes ([`rgb565_luma`], the same value).
//!
//! # Colour bins
//! A [`Binning`] is a sealed marker type that maps any pixel format to a bin index in
//! `0..BINS`. The histogram size is a const generic `B` and
//! `hist::Histogram::fill` checks `Bn::BINS == B` at compile time.
//!
//! | type | `BINS` | bits | from RGB565 |
//! | --- | --- | --- | --- |
//! | [`Rgb8x8x8`] | 512 | R3 G3 B3 | three shifts, three masks, two ORs |
//! | [`Rgb8x8x4`] | 256 | R3 G3 B2 (coarse blue, fewer bins) | three shifts, three masks, two ORs |
//! | [`Yuv8x8x4`] | 256 | U3 V3 Y2: chroma-heavy, little brightness | integer RGB to YUV |
//! | [`Luma64`] | 64 | Y6, for grey cameras | the luma formula |
//!
//! Conversions between RGB and YUV (BT.601 full range, JFIF) are integer multiplies and
//! shifts, never divisions. A [`Gray8`] pixel is the grey RGB `(y, y, y)`, or
//! `(Y, U, V) = (y, 128, 128)`, so colour binnings put it on the grey axis.
//!
//! # Examples
//! ```
//! use rbtrack::image::{ImageError, ImageView, Rgb565Le, Rgb8x8x8};
//! // 2 x 2 frame, stride 3 px: the third pixel of each row is padding.
//! let buf = [0x00, 0xF8, 0xE0, 0x07, 0, 0, 0x1F, 0x00, 0xFF, 0xFF, 0, 0];
//! let img = ImageView::<Rgb565Le>::new(&buf, 2, 2, 3)?;
//! assert_eq!(img.luma(0, 0), 77); // pure red (0xF800)
//! assert_eq!(img.luma(1, 1), 255); // white
//! assert_eq!(img.luma(-5, 9), img.luma(0, 1)); // clamped into the frame
//! assert_eq!(img.row(0).bin::<Rgb8x8x8>(0), 0b111_000_000);
//! assert_eq!(img.row(1).bin::<Rgb8x8x8>(0), 0b000_000_111); // pure blue
//! assert_eq!(
//!     ImageView::<Rgb565Le>::new(&buf[..9], 2, 2, 3).unwrap_err(),
//!     ImageError::BufferTooShort
//! );
//! # Ok::<(), ImageError>(())
//! ```

use core::marker::PhantomData;

mod bins;
mod pixel;

pub use bins::{
    luma_of_rgb, rgb565_luma, rgb565_to_rgb888, rgb888_to_rgb565, rgb_to_yuv, yuv_to_rgb, Binning,
    Luma64, Rgb8x8x4, Rgb8x8x8, Yuv8x8x4,
};
pub(crate) use pixel::Run;
pub use pixel::{
    Bgr888, Gray8, PixelFormat, Rgb565, Rgb565Be, Rgb565Le, Rgb888, Uyvy, Yuv422, Yuyv,
};

/// Largest accepted width or height, px (so that coordinates fit Q16.16 with room to spare).
pub const MAX_SIDE: usize = 16_383;

mod private {
    /// Seals [`super::Binning`]: only this module's binnings implement it.
    pub trait Sealed {}
}

/// Why [`ImageView::new`] rejected a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum ImageError {
    /// Width or height is zero.
    ZeroSize,
    /// Width or height is above [`MAX_SIDE`].
    TooLarge,
    /// Stride (px) is smaller than the width.
    StrideTooSmall,
    /// [`Yuv422`] needs an even width and an even stride (whole pixel pairs).
    OddYuvSize,
    /// The buffer is shorter than `((height - 1) * stride + width) * bytes_per_pixel`.
    BufferTooShort,
}

impl core::fmt::Display for ImageError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            Self::ZeroSize => "image width or height is zero",
            Self::TooLarge => "image width or height is above 16383 px",
            Self::StrideTooSmall => "image stride is smaller than its width",
            Self::OddYuvSize => "YUV 4:2:2 image width and stride must be even",
            Self::BufferTooShort => "image buffer is too short for width, height and stride",
        })
    }
}

impl core::error::Error for ImageError {}

/// A checked, borrowed frame in pixel format `P`.
///
/// Invariants (checked by [`ImageView::new`]): `1 <= width, height <= MAX_SIDE`,
/// `stride >= width`, every row's `width` pixels lie inside the buffer, and for
/// [`Yuv422`] width and stride are even.
#[derive(Clone, Copy, Debug)]
pub struct ImageView<'a, P: PixelFormat> {
    buf: &'a [u8],
    width: usize,
    height: usize,
    stride: usize,
    _format: PhantomData<P>,
}

#[cfg(feature = "defmt")]
impl<P: PixelFormat> defmt::Format for ImageView<'_, P> {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(
            f,
            "ImageView {{ width: {}, height: {}, stride: {} }}",
            self.width,
            self.height,
            self.stride
        )
    }
}

impl<'a, P: PixelFormat> ImageView<'a, P> {
    /// Checks and wraps a frame.
    ///
    /// # Arguments
    /// - `buf`: the pixels, row after row; may be longer than needed.
    /// - `width`, `height`: frame size, px, `1..=MAX_SIDE`.
    /// - `stride`: distance between row starts, px, `>= width`.
    pub fn new(
        buf: &'a [u8],
        width: usize,
        height: usize,
        stride: usize,
    ) -> Result<Self, ImageError> {
        if width == 0 || height == 0 {
            return Err(ImageError::ZeroSize);
        }
        if width > MAX_SIDE || height > MAX_SIDE {
            return Err(ImageError::TooLarge);
        }
        if stride < width {
            return Err(ImageError::StrideTooSmall);
        }
        if P::PAIRED && !(width.is_multiple_of(2) && stride.is_multiple_of(2)) {
            return Err(ImageError::OddYuvSize);
        }
        let needed = (height - 1)
            .checked_mul(stride)
            .and_then(|px| px.checked_add(width))
            .and_then(|px| px.checked_mul(P::BYTES_PER_PIXEL))
            .ok_or(ImageError::BufferTooShort)?;
        if buf.len() < needed {
            return Err(ImageError::BufferTooShort);
        }
        Ok(Self {
            buf,
            width,
            height,
            stride,
            _format: PhantomData,
        })
    }

    /// Checks and wraps a frame held in 32-bit words, as a DMA engine fills them, without
    /// a copy: [`ImageView::new`] over the words' bytes in memory order.
    ///
    /// A camera interface such as the STM32 DCMI packs four received bytes into each word,
    /// the first in bits 7..0, so on a little-endian core (every Cortex-M with a camera
    /// interface) word `w` holds the bytes `w.to_le_bytes()`, in the order the sensor sent
    /// them: choose the pixel format for that byte order (`Rgb565Be` for a sensor that
    /// sends the high byte first). Rows padded to whole words are a stride above the
    /// width (px).
    ///
    /// # Arguments
    /// - `words`: the pixels, row after row; may be longer than needed.
    /// - `width`, `height`, `stride`: as for [`ImageView::new`] (px).
    ///
    /// # Examples
    /// ```
    /// use rbtrack::image::{ImageView, Rgb565Be};
    /// // Red (0xF800) then green (0x07E0), each sent high byte first: F8 00 07 E0.
    /// let dma = [u32::from_le_bytes([0xF8, 0x00, 0x07, 0xE0])];
    /// let img = ImageView::<Rgb565Be>::from_words(&dma, 2, 1, 2)?;
    /// assert_eq!((img.luma(0, 0), img.luma(1, 0)), (77, 149));
    /// # Ok::<(), rbtrack::image::ImageError>(())
    /// ```
    pub fn from_words(
        words: &'a [u32],
        width: usize,
        height: usize,
        stride: usize,
    ) -> Result<Self, ImageError> {
        Self::new(bytemuck::must_cast_slice(words), width, height, stride)
    }

    /// Width, px, `1..=MAX_SIDE`.
    #[inline(always)]
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height, px, `1..=MAX_SIDE`.
    #[inline(always)]
    pub fn height(&self) -> usize {
        self.height
    }

    /// Distance between row starts, px, `>= width`.
    #[inline(always)]
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// The whole borrowed buffer.
    pub fn as_bytes(&self) -> &'a [u8] {
        self.buf
    }

    /// Row `y` (px, `0..height`); a row past the bottom is empty (every pixel reads 0).
    #[inline(always)]
    pub fn row(&self, y: usize) -> Row<'a, P> {
        let bytes = if y < self.height {
            let start = y * self.stride * P::BYTES_PER_PIXEL;
            self.buf
                .get(start..start + self.width * P::BYTES_PER_PIXEL)
                .unwrap_or(&[])
        } else {
            &[]
        };
        Row {
            bytes,
            y,
            _format: PhantomData,
        }
    }

    /// `(x, y)` (px, any values) clamped into the frame.
    #[inline(always)]
    pub fn clamp(&self, x: i32, y: i32) -> (usize, usize) {
        // max then min (not `clamp`, which has a panic path for an inverted range).
        (
            x.min(self.width as i32 - 1).max(0) as usize,
            y.min(self.height as i32 - 1).max(0) as usize,
        )
    }

    /// Luma (0..=255) at `(x, y)` (px), coordinates clamped into the frame.
    #[inline(always)]
    pub fn luma(&self, x: i32, y: i32) -> u8 {
        let (x, y) = self.clamp(x, y);
        self.row(y).luma(x)
    }

    /// Bin (`0..Bn::BINS`) at `(x, y)` (px), coordinates clamped into the frame.
    #[inline(always)]
    pub fn bin<Bn: Binning>(&self, x: i32, y: i32) -> u16 {
        let (x, y) = self.clamp(x, y);
        self.row(y).bin::<Bn>(x)
    }

    /// The frame's runs of colour bins ([`Runs`]).
    #[inline(always)]
    pub(crate) fn runs(&self) -> Runs<'a, P> {
        Runs {
            bytes: self.buf,
            stride: self.stride,
            width: self.width,
            height: self.height,
            _format: PhantomData,
        }
    }

    /// The frame's crosses of taps ([`Crosses`]).
    #[inline(always)]
    pub(crate) fn crosses(&self) -> Crosses<'a, P> {
        Crosses {
            bytes: self.buf,
            // Exact whenever a second row exists (the buffer holds it); a one-row frame
            // may have any stride, and its crosses never reach another row.
            row: self.stride.saturating_mul(P::BYTES_PER_PIXEL),
            width: self.width as i32,
            height: self.height as i32,
            _format: PhantomData,
        }
    }

    /// `[line(row), line(column)]` of the cross of taps of `(x, y)` (px, any values,
    /// clamped into the frame first), every tap clamped into the frame (see [`Crosses`]).
    #[inline]
    pub(crate) fn clamped_cross<T: Default>(
        &self,
        x: i32,
        y: i32,
        line: impl Fn(Taps) -> T,
    ) -> [T; 2] {
        let (xc, yc) = self.clamp(x, y);
        let (x, y) = (xc as i32, yc as i32); // <= MAX_SIDE: the taps cannot overflow
        let crosses = self.crosses();
        if crosses.inside(x, y) {
            return crosses.cross(xc, yc, line);
        }
        let row = self.row(yc);
        let along_row = |dx: i32| row.luma(self.clamp(x + dx, y).0) as i32;
        let along_column = |dy: i32| self.row(self.clamp(x, y + dy).1).luma(xc) as i32;
        [
            line([along_row(-2), along_row(-1), along_row(1), along_row(2)]),
            line([
                along_column(-2),
                along_column(-1),
                along_column(1),
                along_column(2),
            ]),
        ]
    }
}

/// One row of an [`ImageView`]: `width` pixels of bytes (or none, past the bottom).
#[derive(Clone, Copy, Debug)]
pub struct Row<'a, P: PixelFormat> {
    bytes: &'a [u8],
    y: usize,
    _format: PhantomData<P>,
}

#[cfg(feature = "defmt")]
impl<P: PixelFormat> defmt::Format for Row<'_, P> {
    fn format(&self, f: defmt::Formatter) {
        defmt::write!(f, "Row {{ y: {}, bytes: {} }}", self.y, self.bytes.len())
    }
}

impl<'a, P: PixelFormat> Row<'a, P> {
    /// The row's index, px.
    #[inline(always)]
    pub fn y(&self) -> usize {
        self.y
    }

    /// The row's pixel bytes (`width * BYTES_PER_PIXEL` of them, no padding).
    #[inline(always)]
    pub fn bytes(&self) -> &'a [u8] {
        self.bytes
    }

    /// Luma (0..=255) of pixel `x` (px); 0 past the row's end.
    #[inline(always)]
    pub fn luma(&self, x: usize) -> u8 {
        P::luma_at_byte(self.bytes, x.wrapping_mul(P::BYTES_PER_PIXEL))
    }

    /// Fills `out` with the luma of pixels `x0..x0 + out.len()` (px), 0 past the row's
    /// end: one bounds check for the run.
    #[inline(always)]
    pub fn lumas(&self, x0: usize, out: &mut [u8]) {
        P::lumas(self.bytes, x0, out)
    }

    /// Bin (`0..Bn::BINS`) of pixel `x` (px); 0 past the row's end.
    #[inline(always)]
    pub fn bin<Bn: Binning>(&self, x: usize) -> u16 {
        P::bin_at::<Bn>(self.bytes, x)
    }
}

/// Runs of colour bins along a frame's rows, read as one checked slice each: the frame's
/// bytes with its stride at hand.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Runs<'a, P: PixelFormat> {
    bytes: &'a [u8],
    /// Pixels per row (the stride).
    stride: usize,
    width: usize,
    height: usize,
    _format: PhantomData<P>,
}

impl<P: PixelFormat> Runs<'_, P> {
    /// Calls `f(bin)` for the pixels of `run` along row `y`, left to right, read as one
    /// checked slice of the frame (the fixed-size formats without a bounds check per
    /// pixel). The run lies in the frame: `y < height`, `step >= 1` and `x0 + (count - 1)
    /// step < width`, the caller's contract (every window run and map row is clipped to
    /// the frame).
    #[inline(always)]
    pub(crate) fn for_each_bin<Bn: Binning>(&self, y: usize, run: Run, f: impl FnMut(u16)) {
        let Run { x0, step, count } = run;
        debug_assert!(y < self.height && step >= 1, "run outside the frame");
        debug_assert!(
            count == 0 || x0 + (count as usize - 1) * step < self.width,
            "run past the row's end"
        );
        // The run counted from the frame's start: pixels of one row, read from the frame.
        let run = Run {
            x0: y * self.stride + x0,
            ..run
        };
        P::for_each_bin::<Bn>(self.bytes, run, f)
    }
}

/// The crosses of taps of a frame's pixels, read unclamped: the frame's bytes with its
/// row length and size at hand.
///
/// The cross of `(x, y)` is the pixel's neighbours up to [`CROSS_REACH`] px away along its
/// row and its column, the taps of a 5-tap derivative operator (whose centre weight is
/// 0): [`Taps`] of the row (columns `x - 2`, `x - 1`, `x + 1`, `x + 2`) and of the column
/// (rows `y - 2`, `y - 1`, `y + 1`, `y + 2`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Crosses<'a, P: PixelFormat> {
    bytes: &'a [u8],
    /// Bytes per row (the stride).
    row: usize,
    width: i32,
    height: i32,
    _format: PhantomData<P>,
}

impl<P: PixelFormat> Crosses<'_, P> {
    /// Whether the whole cross of `(x, y)` (px) lies in the frame, so that
    /// [`Crosses::cross`] reads it.
    #[inline(always)]
    pub(crate) fn inside(&self, x: i32, y: i32) -> bool {
        let reach = CROSS_REACH as i32;
        x >= reach && x + reach < self.width && y >= reach && y + reach < self.height
    }

    /// `[line(row), line(column)]` of the cross of `(x, y)` (px), which lies in the frame
    /// ([`Crosses::inside`], the caller's contract): each line read at its offsets in the
    /// frame from one checked slice, neither clamped nor sliced tap by tap (a line that
    /// left the buffer, never one inside the frame, would give `T::default()`).
    #[inline(always)]
    pub(crate) fn cross<T: Default>(&self, x: usize, y: usize, line: impl Fn(Taps) -> T) -> [T; 2] {
        debug_assert!(self.inside(x as i32, y as i32), "cross outside the frame");
        let (px, row) = (P::BYTES_PER_PIXEL, self.row);
        let centre = y.wrapping_mul(row).wrapping_add(x.wrapping_mul(px));
        [self.line(centre, px, &line), self.line(centre, row, &line)]
    }

    /// `line` of the taps 2 and 1 `spacing` bytes before and 1 and 2 after the pixel at
    /// byte `centre`, read from one slice of known length.
    #[inline(always)]
    fn line<T: Default>(&self, centre: usize, spacing: usize, line: impl Fn(Taps) -> T) -> T {
        let first = centre.wrapping_sub(CROSS_REACH * spacing);
        let end = centre.wrapping_add(CROSS_REACH * spacing + P::BYTES_PER_PIXEL);
        match self.bytes.get(first..end) {
            Some(s) => {
                let luma = |k: usize| P::luma_at_byte(s, k * spacing) as i32;
                line([luma(0), luma(1), luma(3), luma(4)])
            }
            None => {
                debug_assert!(false, "a line of taps left the buffer");
                T::default()
            }
        }
    }
}

/// How far a cross of taps reaches either side of its centre, px.
pub(crate) const CROSS_REACH: usize = 2;

/// The lumas (0..=255) of one line of a cross of taps ([`Crosses`]): the pixels 2 and 1 px
/// before the centre and 1 and 2 px after it (as `i32`, the operator's arithmetic).
pub(crate) type Taps = [i32; 2 * CROSS_REACH];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_frames() {
        let buf = [0u8; 64];
        assert_eq!(
            ImageView::<Gray8>::new(&buf, 0, 4, 4).unwrap_err(),
            ImageError::ZeroSize
        );
        assert_eq!(
            ImageView::<Gray8>::new(&buf, 4, 0, 4).unwrap_err(),
            ImageError::ZeroSize
        );
        assert_eq!(
            ImageView::<Gray8>::new(&buf, 4, 4, 3).unwrap_err(),
            ImageError::StrideTooSmall
        );
        assert_eq!(
            ImageView::<Gray8>::new(&buf, 16_384, 1, 16_384).unwrap_err(),
            ImageError::TooLarge
        );
        assert_eq!(
            ImageView::<Rgb888>::new(&buf, 4, 6, 4).unwrap_err(),
            ImageError::BufferTooShort
        );
        assert_eq!(
            ImageView::<Yuv422>::new(&buf, 3, 2, 4).unwrap_err(),
            ImageError::OddYuvSize
        );
        assert_eq!(
            ImageView::<Yuv422>::new(&buf, 2, 2, 3).unwrap_err(),
            ImageError::OddYuvSize
        );
        assert_eq!(
            ImageView::<Gray8>::new(&buf, 4, 2, usize::MAX).unwrap_err(),
            ImageError::BufferTooShort
        );
        // Exactly long enough: the last row needs no padding.
        let big = [0u8; 128];
        assert!(ImageView::<Rgb888>::new(&big[..(3 * 7 + 4) * 3], 4, 4, 7).is_ok());
        assert!(ImageView::<Rgb888>::new(&big[..(3 * 7 + 4) * 3 - 1], 4, 4, 7).is_err());
        extern crate std;
        use std::string::ToString;
        assert!(ImageError::BufferTooShort.to_string().contains("short"));
    }

    #[test]
    fn one_pixel_frame_clamps_everything() {
        let img = ImageView::<Gray8>::new(&[42], 1, 1, 1).unwrap();
        for (x, y) in [(0, 0), (-1, -1), (5, 0), (i32::MIN, i32::MAX)] {
            assert_eq!(img.luma(x, y), 42);
        }
        assert_eq!(img.row(1).bytes().len(), 0);
        assert_eq!(img.row(usize::MAX).luma(0), 0);
        assert_eq!(img.row(0).luma(usize::MAX), 0);
        assert_eq!(img.bin::<Luma64>(3, 3), 10);
    }

    #[test]
    fn stride_wider_than_width_skips_padding() {
        // 2 x 3 gray frame, stride 5: padding bytes are 0xEE.
        let buf = [1, 2, 0xEE, 0xEE, 0xEE, 3, 4, 0xEE, 0xEE, 0xEE, 5, 6];
        let img = ImageView::<Gray8>::new(&buf, 2, 3, 5).unwrap();
        assert_eq!(img.row(1).bytes(), &[3, 4]);
        assert_eq!(img.luma(1, 2), 6);
        assert_eq!(img.luma(4, 1), 4); // clamped to x = 1, not the padding
        assert_eq!(img.row(2).luma(2), 0); // past the row end
    }

    /// Golden bytes per format: hand-computed luma and bins (zero fields written out).
    #[test]
    #[allow(clippy::identity_op)]
    fn golden_pixels_every_format() {
        // Gray8: 200 -> grey (200, 200, 200): r3 = g3 = b3 = 6.
        let img = ImageView::<Gray8>::new(&[200], 1, 1, 1).unwrap();
        assert_eq!(img.luma(0, 0), 200);
        assert_eq!(img.bin::<Rgb8x8x8>(0, 0), (6 << 6) | (6 << 3) | 6);
        assert_eq!(img.bin::<Rgb8x8x4>(0, 0), (6 << 5) | (6 << 2) | 3);
        assert_eq!(img.bin::<Yuv8x8x4>(0, 0), (4 << 5) | (4 << 2) | 3);
        assert_eq!(img.bin::<Luma64>(0, 0), 50);

        // RGB565 0x07E0 = pure green: (0, 255, 0), luma (150*255+128)>>8 = 149.
        let le = ImageView::<Rgb565Le>::new(&[0xE0, 0x07], 1, 1, 1).unwrap();
        let be = ImageView::<Rgb565Be>::new(&[0x07, 0xE0], 1, 1, 1).unwrap();
        for (luma, bin8, bin4, yuv) in [
            (
                le.luma(0, 0),
                le.bin::<Rgb8x8x8>(0, 0),
                le.bin::<Rgb8x8x4>(0, 0),
                le.bin::<Yuv8x8x4>(0, 0),
            ),
            (
                be.luma(0, 0),
                be.bin::<Rgb8x8x8>(0, 0),
                be.bin::<Rgb8x8x4>(0, 0),
                be.bin::<Yuv8x8x4>(0, 0),
            ),
        ] {
            assert_eq!(luma, 149);
            assert_eq!(bin8, 7 << 3);
            assert_eq!(bin4, 7 << 2);
            // Green: U = (-85*255+128)>>8 + 128 = 43, V = (-107*255+128)>>8 + 128 = 21.
            assert_eq!(yuv, (1 << 5) | (0 << 2) | 2);
        }

        // RGB888 (10, 100, 250): luma (770 + 15000 + 7250 + 128) >> 8 = 90.
        let img = ImageView::<Rgb888>::new(&[10, 100, 250], 1, 1, 1).unwrap();
        assert_eq!(img.luma(0, 0), 90);
        assert_eq!(img.bin::<Rgb8x8x8>(0, 0), (0 << 6) | (3 << 3) | 7);
        assert_eq!(img.bin::<Rgb8x8x4>(0, 0), (0 << 5) | (3 << 2) | 3);
        assert_eq!(img.bin::<Luma64>(0, 0), 22);

        // YUYV: pixels (Y=16, U=240, V=16) and (Y=235, U=240, V=16).
        let img = ImageView::<Yuv422>::new(&[16, 240, 235, 16], 2, 1, 2).unwrap();
        assert_eq!(img.luma(0, 0), 16);
        assert_eq!(img.luma(1, 0), 235);
        assert_eq!(img.bin::<Yuv8x8x4>(0, 0), (7 << 5) | (0 << 2) | 0);
        assert_eq!(img.bin::<Yuv8x8x4>(1, 0), (7 << 5) | (0 << 2) | 3);
        // Y=235, U-128 = 112, V-128 = -112: R = 235 + ((-40208+128)>>8) = 78,
        // G = 235 - ((9856 - 20496 + 128)>>8) = 235 + 42 = 277 -> 255,
        // B = 235 + ((50848+128)>>8) = 434 -> 255.
        assert_eq!(yuv_to_rgb(235, 240, 16), (78, 255, 255));
        assert_eq!(img.bin::<Rgb8x8x8>(1, 0), (2 << 6) | (7 << 3) | 7);

        // UYVY: the same two pixels, chroma first.
        let uyvy = ImageView::<Uyvy>::new(&[240, 16, 16, 235], 2, 1, 2).unwrap();
        assert_eq!((uyvy.luma(0, 0), uyvy.luma(1, 0)), (16, 235));
        assert_eq!(uyvy.row(0).luma(2), 0); // past the row end
        for x in 0..2 {
            assert_eq!(uyvy.bin::<Yuv8x8x4>(x, 0), img.bin::<Yuv8x8x4>(x, 0));
            assert_eq!(uyvy.bin::<Rgb8x8x8>(x, 0), img.bin::<Rgb8x8x8>(x, 0));
        }
    }

    /// Words as a DMA engine fills them: bytes in memory order, rows padded to whole words.
    #[test]
    #[allow(clippy::identity_op)]
    fn words_are_bytes_in_memory_order() {
        // 3 x 2 RGB565, sent high byte first, each row padded to 8 bytes (stride 4 px).
        // Row 0: red F800, green 07E0, blue 001F; row 1: white, black, grey 8410.
        let words = [
            0xE007_00F8, // F8 00 | 07 E0
            0xEEEE_1F00, // 00 1F | padding
            0x0000_FFFF, // FF FF | 00 00
            0xEEEE_1084, // 84 10 | padding
        ];
        let img = ImageView::<Rgb565Be>::from_words(&words, 3, 2, 4).unwrap();
        assert_eq!(
            img.as_bytes(),
            &[
                0xF8, 0x00, 0x07, 0xE0, 0x00, 0x1F, 0xEE, 0xEE, 0xFF, 0xFF, 0x00, 0x00, 0x84, 0x10,
                0xEE, 0xEE
            ]
        );
        assert_eq!(img.row(1).bytes(), &[0xFF, 0xFF, 0x00, 0x00, 0x84, 0x10]);
        // Red 77, green 149, blue (29 * 255 + 128) >> 8 = 29; white, black, grey:
        // 0x8410 widens to (132, 130, 132), luma (10164 + 19500 + 3828 + 128) >> 8 = 131.
        let lumas = [[77, 149, 29], [255, 0, 131]];
        for (y, row) in lumas.iter().enumerate() {
            for (x, &luma) in row.iter().enumerate() {
                assert_eq!(img.luma(x as i32, y as i32), luma, "({x}, {y})");
            }
        }
        assert_eq!(img.luma(3, 0), 29); // clamped to x = 2, not the padding
        assert_eq!(img.bin::<Rgb8x8x8>(2, 0), 0b000_000_111);

        // YUYV and UYVY words: (Y=16, U=240, V=16) and (Y=235, U=240, V=16) as above.
        let yuyv = ImageView::<Yuyv>::from_words(&[0x10EB_F010], 2, 1, 2).unwrap();
        let uyvy = ImageView::<Uyvy>::from_words(&[0xEB10_10F0], 2, 1, 2).unwrap();
        assert_eq!((yuyv.luma(0, 0), yuyv.luma(1, 0)), (16, 235));
        assert_eq!((uyvy.luma(0, 0), uyvy.luma(1, 0)), (16, 235));
        assert_eq!(uyvy.bin::<Yuv8x8x4>(1, 0), (7 << 5) | (0 << 2) | 3);

        // The check is that of `new`, in bytes: 3 px of the last row need 6 of its 8.
        assert_eq!(
            ImageView::<Rgb565Be>::from_words(&words[..3], 3, 2, 4).unwrap_err(),
            ImageError::BufferTooShort
        );
        assert!(ImageView::<Rgb565Be>::from_words(&words[..3], 2, 2, 4).is_ok());
    }
}
