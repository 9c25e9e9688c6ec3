//! Borrowed camera frames ([`ImageView`]), their pixel formats and the colour-bin mappings.
//!
//! A frame is a `&[u8]` (or the `&[u32]` a DMA engine fills, [`ImageView::from_words`])
//! with a width, a height and a row stride, all in pixels, checked once by
//! [`ImageView::new`] (in the manner of a checked packet view): after that no accessor can
//! panic, and reads outside the frame are clamped or empty, never out of bounds.
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
//! [`crate::hist::Histogram::fill`] checks `Bn::BINS == B` at compile time.
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

/// Largest accepted width or height, px (so that coordinates fit Q16.16 with room to spare).
pub const MAX_SIDE: usize = 16_383;

mod private {
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

/// BT.601 full-range luma of 8-bit RGB, 0..=255.
#[inline(always)]
pub const fn luma_of_rgb(r: u8, g: u8, b: u8) -> u8 {
    // 77 + 150 + 29 = 256, so the sum is at most 255 * 256 + 128 and the shift gives <= 255.
    ((77 * r as u32 + 150 * g as u32 + 29 * b as u32 + 128) >> 8) as u8
}

/// 8-bit RGB of an RGB565 word, by bit replication (each channel 0..=255).
#[inline(always)]
pub const fn rgb565_to_rgb888(v: u16) -> (u8, u8, u8) {
    let r5 = (v >> 11) as u8;
    let g6 = ((v >> 5) & 0x3F) as u8;
    let b5 = (v & 0x1F) as u8;
    (
        (r5 << 3) | (r5 >> 2),
        (g6 << 2) | (g6 >> 4),
        (b5 << 3) | (b5 >> 2),
    )
}

/// Luma sums of an RGB565 word's high byte (`RRRRRGGG`): `77 R8 + 150 G8_hi + 128`,
/// where `G8 = G8_hi + G8_lo` splits the widened green into the part from the high byte's
/// three green bits (`g << 5 | g >> 1`) and the part from the low byte's (`g << 2`): their
/// bits do not overlap, so the bit replication is a sum.
const RGB565_LUMA_HI: [u16; 256] = {
    let mut t = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let r5 = (i >> 3) as u32;
        let g3 = (i & 7) as u32;
        let r8 = (r5 << 3) | (r5 >> 2);
        t[i] = (77 * r8 + 150 * ((g3 << 5) | (g3 >> 1)) + 128) as u16;
        i += 1;
    }
    t
};

/// Luma sums of an RGB565 word's low byte (`GGGBBBBB`): `150 G8_lo + 29 B8`.
const RGB565_LUMA_LO: [u16; 256] = {
    let mut t = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let g3 = (i >> 5) as u32;
        let b5 = (i & 31) as u32;
        let b8 = (b5 << 3) | (b5 >> 2);
        t[i] = (150 * (g3 << 2) + 29 * b8) as u16;
        i += 1;
    }
    t
};

/// The two tables in one place, so that one base address serves both.
static RGB565_LUMA: [[u16; 256]; 2] = [RGB565_LUMA_HI, RGB565_LUMA_LO];

/// BT.601 full-range luma of an RGB565 word given as its high and low bytes: the same
/// value as [`luma_of_rgb`] of [`rgb565_to_rgb888`], by two table look-ups (1 KiB of
/// tables) instead of widening and three multiplies.
#[inline(always)]
pub fn rgb565_luma(hi: u8, lo: u8) -> u8 {
    let [t_hi, t_lo] = &RGB565_LUMA;
    ((t_hi[hi as usize] as u32 + t_lo[lo as usize] as u32) >> 8) as u8
}

/// BT.601 full-range (JFIF) YUV of 8-bit RGB; U and V are centred on 128, all 0..=255.
#[inline(always)]
pub const fn rgb_to_yuv(r: u8, g: u8, b: u8) -> (u8, u8, u8) {
    let (r, g, b) = (r as i32, g as i32, b as i32);
    let u = ((-43 * r - 85 * g + 128 * b + 128) >> 8) + 128;
    let v = ((128 * r - 107 * g - 21 * b + 128) >> 8) + 128;
    (
        luma_of_rgb(r as u8, g as u8, b as u8),
        clamp_u8(u),
        clamp_u8(v),
    )
}

/// 8-bit RGB of BT.601 full-range (JFIF) YUV, each channel clamped to 0..=255.
#[inline(always)]
pub const fn yuv_to_rgb(y: u8, u: u8, v: u8) -> (u8, u8, u8) {
    let (y, u, v) = (y as i32, u as i32 - 128, v as i32 - 128);
    let r = y + ((359 * v + 128) >> 8);
    let g = y - ((88 * u + 183 * v + 128) >> 8);
    let b = y + ((454 * u + 128) >> 8);
    (clamp_u8(r), clamp_u8(g), clamp_u8(b))
}

#[inline(always)]
const fn clamp_u8(v: i32) -> u8 {
    if v < 0 {
        0
    } else if v > 255 {
        255
    } else {
        v as u8
    }
}

/// A mapping from pixels to colour bins `0..BINS` (sealed: the types of this module).
///
/// Every method returns an index below [`Binning::BINS`].
pub trait Binning: private::Sealed + Copy + core::fmt::Debug + 'static {
    /// Number of bins.
    const BINS: usize;
    /// Bin of an 8-bit RGB pixel (channels 0..=255).
    fn from_rgb888(r: u8, g: u8, b: u8) -> u16;
    /// Bin of an RGB565 word; equals `from_rgb888` of the widened pixel.
    #[inline(always)]
    fn from_rgb565(v: u16) -> u16 {
        let (r, g, b) = rgb565_to_rgb888(v);
        Self::from_rgb888(r, g, b)
    }
    /// Bin of a YUV pixel (BT.601 full range, U and V centred on 128); by default the bin
    /// of its RGB conversion.
    #[inline(always)]
    fn from_yuv(y: u8, u: u8, v: u8) -> u16 {
        let (r, g, b) = yuv_to_rgb(y, u, v);
        Self::from_rgb888(r, g, b)
    }
    /// Bin of a grey pixel of luma `y` (0..=255); by default the bin of `(y, y, y)`.
    #[inline(always)]
    fn from_luma(y: u8) -> u16 {
        Self::from_rgb888(y, y, y)
    }
}

/// 512 bins: 3 bits each of R, G and B (`r3 << 6 | g3 << 3 | b3`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Rgb8x8x8;

/// 256 bins: 3 bits of R, 3 of G, 2 of B (`r3 << 5 | g3 << 2 | b2`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Rgb8x8x4;

/// 256 bins, chroma-heavy: 3 bits of U, 3 of V, 2 of Y (`u3 << 5 | v3 << 2 | y2`), so
/// a brightness change moves a pixel across at most a few of 4 luma slices.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Yuv8x8x4;

/// 64 bins of luma (`y >> 2`), for grey cameras.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Luma64;

impl private::Sealed for Rgb8x8x8 {}
impl private::Sealed for Rgb8x8x4 {}
impl private::Sealed for Yuv8x8x4 {}
impl private::Sealed for Luma64 {}

impl Binning for Rgb8x8x8 {
    const BINS: usize = 512;
    #[inline(always)]
    fn from_rgb888(r: u8, g: u8, b: u8) -> u16 {
        ((r as u16 >> 5) << 6) | ((g as u16 >> 5) << 3) | (b as u16 >> 5)
    }
    #[inline(always)]
    fn from_rgb565(v: u16) -> u16 {
        ((v >> 7) & 0x1C0) | ((v >> 5) & 0x38) | ((v >> 2) & 0x7)
    }
}

impl Binning for Rgb8x8x4 {
    const BINS: usize = 256;
    #[inline(always)]
    fn from_rgb888(r: u8, g: u8, b: u8) -> u16 {
        ((r as u16 >> 5) << 5) | ((g as u16 >> 5) << 2) | (b as u16 >> 6)
    }
    #[inline(always)]
    fn from_rgb565(v: u16) -> u16 {
        ((v >> 8) & 0xE0) | ((v >> 6) & 0x1C) | ((v >> 3) & 0x3)
    }
}

impl Binning for Yuv8x8x4 {
    const BINS: usize = 256;
    #[inline(always)]
    fn from_rgb888(r: u8, g: u8, b: u8) -> u16 {
        let (y, u, v) = rgb_to_yuv(r, g, b);
        Self::from_yuv(y, u, v)
    }
    #[inline(always)]
    fn from_yuv(y: u8, u: u8, v: u8) -> u16 {
        ((u as u16 >> 5) << 5) | ((v as u16 >> 5) << 2) | (y as u16 >> 6)
    }
    #[inline(always)]
    fn from_luma(y: u8) -> u16 {
        Self::from_yuv(y, 128, 128)
    }
}

impl Binning for Luma64 {
    const BINS: usize = 64;
    #[inline(always)]
    fn from_rgb888(r: u8, g: u8, b: u8) -> u16 {
        Self::from_luma(luma_of_rgb(r, g, b))
    }
    #[inline(always)]
    fn from_yuv(y: u8, _u: u8, _v: u8) -> u16 {
        Self::from_luma(y)
    }
    #[inline(always)]
    fn from_luma(y: u8) -> u16 {
        y as u16 >> 2
    }
}

/// A pixel layout (sealed: the marker types of this module).
///
/// The row methods read pixel `x` of one row's bytes and return 0 when the row is too
/// short, so they never panic; [`ImageView`] only hands out complete rows.
pub trait PixelFormat: private::Sealed + Copy + core::fmt::Debug + 'static {
    /// Bytes per pixel (a [`Yuv422`] pair of pixels takes 4).
    const BYTES_PER_PIXEL: usize;
    /// Whether width and stride must be even.
    const PAIRED: bool;
    /// Luma (0..=255) of pixel `x` (px) of `row`; 0 past its end.
    #[inline(always)]
    fn luma_at(row: &[u8], x: usize) -> u8 {
        Self::luma_at_byte(row, x.wrapping_mul(Self::BYTES_PER_PIXEL))
    }
    /// Luma (0..=255) of the pixel whose bytes start at `index` of `bytes` (`x *
    /// BYTES_PER_PIXEL` into a row, or that plus whole rows into a frame; for [`Yuv422`],
    /// `2 x`); 0 past the end.
    fn luma_at_byte(bytes: &[u8], index: usize) -> u8;
    /// Bin (`0..Bn::BINS`) of pixel `x` (px) of `row`; 0 past its end.
    fn bin_at<Bn: Binning>(row: &[u8], x: usize) -> u16;
    /// Calls `f(bin)` for the `count` pixels `x0, x0 + step, ...` of `row` (px,
    /// `step >= 1`), left to right, as [`PixelFormat::bin_at`] would give them; the
    /// fixed-size formats read them without a bounds check per pixel. `row` may also be
    /// a whole frame, with `x0` counted from its start (`y stride + x`).
    #[inline(always)]
    fn for_each_bin<Bn: Binning>(
        row: &[u8],
        x0: usize,
        step: usize,
        count: u32,
        mut f: impl FnMut(u16),
    ) {
        let mut x = x0;
        for _ in 0..count {
            f(Self::bin_at::<Bn>(row, x));
            x = x.wrapping_add(step);
        }
    }
}

/// [`PixelFormat::for_each_bin`] for a format of `BPP` bytes per pixel, `bin` giving a
/// pixel's bin from its bytes: one bounds check per run, then fixed-size chunks.
#[inline(always)]
fn bins_of_run<const BPP: usize>(
    row: &[u8],
    x0: usize,
    step: usize,
    count: u32,
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
        // one, bin 0 past the end.
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

impl private::Sealed for Gray8 {}
impl<const BIG_ENDIAN: bool> private::Sealed for Rgb565<BIG_ENDIAN> {}
impl private::Sealed for Rgb888 {}
impl<const CHROMA_FIRST: bool> private::Sealed for Yuv422<CHROMA_FIRST> {}

impl PixelFormat for Gray8 {
    const BYTES_PER_PIXEL: usize = 1;
    const PAIRED: bool = false;
    #[inline(always)]
    fn luma_at_byte(bytes: &[u8], index: usize) -> u8 {
        bytes.get(index).copied().unwrap_or(0)
    }
    #[inline(always)]
    fn bin_at<Bn: Binning>(row: &[u8], x: usize) -> u16 {
        Bn::from_luma(Self::luma_at(row, x))
    }
    #[inline(always)]
    fn for_each_bin<Bn: Binning>(
        row: &[u8],
        x0: usize,
        step: usize,
        count: u32,
        f: impl FnMut(u16),
    ) {
        bins_of_run::<1>(row, x0, step, count, |&[y]| Bn::from_luma(y), f)
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

impl<const BIG_ENDIAN: bool> PixelFormat for Rgb565<BIG_ENDIAN> {
    const BYTES_PER_PIXEL: usize = 2;
    const PAIRED: bool = false;
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
    fn for_each_bin<Bn: Binning>(
        row: &[u8],
        x0: usize,
        step: usize,
        count: u32,
        f: impl FnMut(u16),
    ) {
        bins_of_run::<2>(
            row,
            x0,
            step,
            count,
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
}

impl PixelFormat for Rgb888 {
    const BYTES_PER_PIXEL: usize = 3;
    const PAIRED: bool = false;
    #[inline(always)]
    fn luma_at_byte(bytes: &[u8], index: usize) -> u8 {
        match (
            bytes.get(index),
            bytes.get(index.wrapping_add(1)),
            bytes.get(index.wrapping_add(2)),
        ) {
            (Some(&r), Some(&g), Some(&b)) => luma_of_rgb(r, g, b),
            _ => 0,
        }
    }
    #[inline(always)]
    fn bin_at<Bn: Binning>(row: &[u8], x: usize) -> u16 {
        match row.get(3 * x..3 * x + 3) {
            Some(&[r, g, b]) => Bn::from_rgb888(r, g, b),
            _ => 0,
        }
    }
    #[inline(always)]
    fn for_each_bin<Bn: Binning>(
        row: &[u8],
        x0: usize,
        step: usize,
        count: u32,
        f: impl FnMut(u16),
    ) {
        bins_of_run::<3>(
            row,
            x0,
            step,
            count,
            |&[r, g, b]| Bn::from_rgb888(r, g, b),
            f,
        )
    }
}

impl<const CHROMA_FIRST: bool> PixelFormat for Yuv422<CHROMA_FIRST> {
    const BYTES_PER_PIXEL: usize = 2;
    const PAIRED: bool = true;
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
}

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
        P::luma_at(self.bytes, x)
    }

    /// Bin (`0..Bn::BINS`) of pixel `x` (px); 0 past the row's end.
    #[inline(always)]
    pub fn bin<Bn: Binning>(&self, x: usize) -> u16 {
        P::bin_at::<Bn>(self.bytes, x)
    }

    /// Calls `f(bin)` for the `count` pixels `x0, x0 + step, ...` (px, `step >= 1`), left
    /// to right; pixels past the row's end give bin 0.
    #[inline(always)]
    pub fn for_each_bin<Bn: Binning>(
        &self,
        x0: usize,
        step: usize,
        count: u32,
        f: impl FnMut(u16),
    ) {
        P::for_each_bin::<Bn>(self.bytes, x0, step, count, f)
    }
}

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

    /// Runs of bins equal the bins one by one, every format, every step, at and past the
    /// row's end.
    #[test]
    fn runs_of_bins_equal_single_bins() {
        fn check<P: PixelFormat>(bytes_per_px: usize) {
            extern crate std;
            use std::vec::Vec;
            let mut r = crate::rng::Rng::new(2);
            let (w, h) = (14usize, 3usize);
            let buf: Vec<u8> = (0..w * h * bytes_per_px)
                .map(|_| r.next_u32() as u8)
                .collect();
            let img = ImageView::<P>::new(&buf, w, h, w).unwrap();
            let row = img.row(1);
            for x0 in 0..w + 2 {
                for step in 1..6 {
                    for count in 0..8u32 {
                        let mut got = Vec::new();
                        row.for_each_bin::<Rgb8x8x8>(x0, step, count, |b| got.push(b));
                        let want: Vec<u16> = (0..count as usize)
                            .map(|k| row.bin::<Rgb8x8x8>(x0 + k * step))
                            .collect();
                        assert_eq!(got, want, "x0 {x0} step {step} count {count}");
                    }
                }
            }
        }
        check::<Gray8>(1);
        check::<Rgb565Le>(2);
        check::<Rgb565Be>(2);
        check::<Rgb888>(3);
        check::<Yuyv>(2);
        check::<Uyvy>(2);
    }

    #[test]
    fn rgb565_bins_equal_widened_rgb888_bins() {
        for v in 0..=u16::MAX {
            let (r, g, b) = rgb565_to_rgb888(v);
            let [hi, lo] = v.to_be_bytes();
            assert_eq!(rgb565_luma(hi, lo), luma_of_rgb(r, g, b), "{v:#06x}");
            assert_eq!(Rgb8x8x8::from_rgb565(v), Rgb8x8x8::from_rgb888(r, g, b));
            assert_eq!(Rgb8x8x4::from_rgb565(v), Rgb8x8x4::from_rgb888(r, g, b));
            assert!((Rgb8x8x8::from_rgb565(v) as usize) < Rgb8x8x8::BINS);
            assert!((Yuv8x8x4::from_rgb565(v) as usize) < Yuv8x8x4::BINS);
            assert!((Luma64::from_rgb565(v) as usize) < Luma64::BINS);
        }
    }

    #[test]
    fn colour_conversions_at_the_extremes() {
        assert_eq!(luma_of_rgb(255, 255, 255), 255);
        assert_eq!(luma_of_rgb(0, 0, 0), 0);
        assert_eq!(rgb_to_yuv(255, 255, 255), (255, 128, 128));
        assert_eq!(rgb_to_yuv(0, 0, 0), (0, 128, 128));
        assert_eq!(rgb565_to_rgb888(0xFFFF), (255, 255, 255));
        for (r, g, b) in [(255, 0, 0), (0, 255, 0), (0, 0, 255), (128, 64, 200)] {
            let (y, u, v) = rgb_to_yuv(r, g, b);
            let (r2, g2, b2) = yuv_to_rgb(y, u, v);
            for (a, b) in [(r, r2), (g, g2), (b, b2)] {
                assert!((a as i32 - b as i32).abs() <= 3, "{r},{g},{b}");
            }
        }
        for y in 0..=255u8 {
            for u in [0u8, 128, 255] {
                for v in [0u8, 77, 255] {
                    assert!((Rgb8x8x8::from_yuv(y, u, v) as usize) < 512);
                }
            }
        }
    }
}
