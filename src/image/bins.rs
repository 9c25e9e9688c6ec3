//! Colour: BT.601 luma and YUV of RGB pixels, and the colour-bin mappings ([`Binning`]).

use super::private::Sealed;

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

/// The RGB565 word of 8-bit RGB, each channel truncated to its 5 or 6 bits (the inverse
/// of [`rgb565_to_rgb888`] on the colours it gives).
#[inline(always)]
pub const fn rgb888_to_rgb565(r: u8, g: u8, b: u8) -> u16 {
    ((r as u16 >> 3) << 11) | ((g as u16 >> 2) << 5) | (b as u16 >> 3)
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
pub trait Binning: Sealed + Copy + core::fmt::Debug + 'static {
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

impl Sealed for Rgb8x8x8 {}
impl Sealed for Rgb8x8x4 {}
impl Sealed for Yuv8x8x4 {}
impl Sealed for Luma64 {}

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rgb565_bins_equal_widened_rgb888_bins() {
        for v in 0..=u16::MAX {
            let (r, g, b) = rgb565_to_rgb888(v);
            assert_eq!(rgb888_to_rgb565(r, g, b), v);
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
