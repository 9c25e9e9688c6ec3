//! Frames in the core's pixel formats ([`Format`]) and the conversions between them and
//! RGB888: what decoded images and videos are turned into before tracking, what raw dumps
//! from a board hold, and what overlays are drawn on.
//!
//! The conversions use the core's own colour arithmetic ([`rbtrack::image`]'s BT.601 luma
//! and YUV, RGB565 widening by bit replication); RGB888 to RGB565 truncates each channel
//! ([`rgb565`]).

use rbtrack::image::{luma_of_rgb, rgb565_to_rgb888, rgb888_to_rgb565, rgb_to_yuv, yuv_to_rgb};
use std::fmt;

/// A pixel layout of the core (`rbtrack::image`): the formats a camera delivers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Format {
    /// 8-bit grey, 1 byte per pixel (`rbtrack::image::Gray8`).
    #[value(name = "gray8")]
    Gray8,
    /// RGB565, a little-endian `u16` per pixel (`Rgb565Le`).
    #[value(name = "rgb565le", alias = "rgb565")]
    Rgb565Le,
    /// RGB565, a big-endian `u16` per pixel (`Rgb565Be`).
    #[value(name = "rgb565be")]
    Rgb565Be,
    /// 24-bit RGB, bytes R, G, B (`Rgb888`).
    #[value(name = "rgb888")]
    Rgb888,
    /// YUV 4:2:2 as YUYV, 4 bytes per pair of pixels (`Yuyv`); the width is even.
    #[value(name = "yuyv")]
    Yuyv,
    /// YUV 4:2:2 as UYVY, 4 bytes per pair of pixels (`Uyvy`); the width is even.
    #[value(name = "uyvy")]
    Uyvy,
}

impl Format {
    /// Every format, in the order of the command line's choices.
    pub const ALL: [Format; 6] = [
        Self::Gray8,
        Self::Rgb565Le,
        Self::Rgb565Be,
        Self::Rgb888,
        Self::Yuyv,
        Self::Uyvy,
    ];

    /// Command-line name: `gray8`, `rgb565le`, `rgb565be`, `rgb888`, `yuyv` or `uyvy`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Gray8 => "gray8",
            Self::Rgb565Le => "rgb565le",
            Self::Rgb565Be => "rgb565be",
            Self::Rgb888 => "rgb888",
            Self::Yuyv => "yuyv",
            Self::Uyvy => "uyvy",
        }
    }

    /// The format called `name` ([`Format::name`], or `rgb565` for `rgb565le`).
    pub fn from_name(name: &str) -> Option<Self> {
        <Self as clap::ValueEnum>::from_str(name, true).ok()
    }

    /// Bytes of one `width x height` frame; `None` for a zero size, an odd YUV 4:2:2
    /// width or a size that overflows.
    pub fn frame_bytes(self, width: u32, height: u32) -> Option<usize> {
        let yuv422 = matches!(self, Self::Yuyv | Self::Uyvy);
        if width == 0 || height == 0 || (yuv422 && width % 2 == 1) {
            return None;
        }
        let per_pixel = match self {
            Self::Gray8 => 1,
            Self::Rgb565Le | Self::Rgb565Be | Self::Yuyv | Self::Uyvy => 2,
            Self::Rgb888 => 3,
        };
        (width as usize)
            .checked_mul(height as usize)?
            .checked_mul(per_pixel)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Why bytes are not a frame.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FrameError {
    /// The size is zero, or odd for YUYV.
    Size {
        /// The format.
        format: Format,
        /// Width, px.
        width: u32,
        /// Height, px.
        height: u32,
    },
    /// The buffer does not hold exactly one frame.
    Length {
        /// Bytes a frame takes.
        expected: usize,
        /// Bytes given.
        found: usize,
    },
}

impl fmt::Display for FrameError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Size {
                format,
                width,
                height,
            } => write!(f, "no {format} frame is {width}x{height} px"),
            Self::Length { expected, found } => {
                write!(f, "frame holds {found} bytes, expected {expected}")
            }
        }
    }
}

impl std::error::Error for FrameError {}

/// One frame: `width x height` pixels in `format`, rows back to back (stride = width).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    /// Pixel layout of `bytes`.
    pub format: Format,
    /// Width, px.
    pub width: u32,
    /// Height, px.
    pub height: u32,
    /// The pixels, exactly [`Format::frame_bytes`] of them.
    pub bytes: Vec<u8>,
}

impl Frame {
    /// Checks that `bytes` is one `width x height` frame in `format`.
    pub fn new(
        format: Format,
        width: u32,
        height: u32,
        bytes: Vec<u8>,
    ) -> Result<Self, FrameError> {
        let expected = format.frame_bytes(width, height).ok_or(FrameError::Size {
            format,
            width,
            height,
        })?;
        if bytes.len() != expected {
            return Err(FrameError::Length {
                expected,
                found: bytes.len(),
            });
        }
        Ok(Self {
            format,
            width,
            height,
            bytes,
        })
    }

    /// An RGB888 frame ([`Frame::new`] with [`Format::Rgb888`]).
    pub fn rgb888(width: u32, height: u32, rgb: Vec<u8>) -> Result<Self, FrameError> {
        Self::new(Format::Rgb888, width, height, rgb)
    }

    /// The pixels as RGB888 (for drawing and for conversion).
    pub fn to_rgb888(&self) -> Vec<u8> {
        let b = &self.bytes;
        match self.format {
            Format::Rgb888 => b.clone(),
            Format::Gray8 => b.iter().flat_map(|&y| [y, y, y]).collect(),
            Format::Rgb565Le | Format::Rgb565Be => b
                .chunks_exact(2)
                .flat_map(|p| {
                    let v = match self.format {
                        Format::Rgb565Be => u16::from_be_bytes([p[0], p[1]]),
                        _ => u16::from_le_bytes([p[0], p[1]]),
                    };
                    let (r, g, b) = rgb565_to_rgb888(v);
                    [r, g, b]
                })
                .collect(),
            Format::Yuyv | Format::Uyvy => b
                .chunks_exact(4)
                .flat_map(|p| {
                    // [Y0, U, Y1, V] for YUYV, [U, Y0, V, Y1] for UYVY.
                    let [y0, u, y1, v] = match self.format {
                        Format::Uyvy => [p[1], p[0], p[3], p[2]],
                        _ => [p[0], p[1], p[2], p[3]],
                    };
                    let (r0, g0, b0) = yuv_to_rgb(y0, u, v);
                    let (r1, g1, b1) = yuv_to_rgb(y1, u, v);
                    [r0, g0, b0, r1, g1, b1]
                })
                .collect(),
        }
    }

    /// This frame in `format`, converted through RGB888 (itself when it already is).
    pub fn convert(self, format: Format) -> Result<Frame, FrameError> {
        if format == self.format {
            return Ok(self);
        }
        let rgb = self.to_rgb888();
        let bytes = match format {
            Format::Rgb888 => rgb,
            Format::Gray8 => rgb
                .chunks_exact(3)
                .map(|p| luma_of_rgb(p[0], p[1], p[2]))
                .collect(),
            Format::Rgb565Le => rgb
                .chunks_exact(3)
                .flat_map(|p| rgb888_to_rgb565(p[0], p[1], p[2]).to_le_bytes())
                .collect(),
            Format::Rgb565Be => rgb
                .chunks_exact(3)
                .flat_map(|p| rgb888_to_rgb565(p[0], p[1], p[2]).to_be_bytes())
                .collect(),
            Format::Yuyv | Format::Uyvy => rgb
                .chunks_exact(6)
                .flat_map(|p| {
                    let (y0, u0, v0) = rgb_to_yuv(p[0], p[1], p[2]);
                    let (y1, u1, v1) = rgb_to_yuv(p[3], p[4], p[5]);
                    let mid = |a: u8, b: u8| (a as u16 + b as u16).div_ceil(2) as u8;
                    let (u, v) = (mid(u0, u1), mid(v0, v1));
                    match format {
                        Format::Uyvy => [u, y0, v, y1],
                        _ => [y0, u, y1, v],
                    }
                })
                .collect(),
        };
        Frame::new(format, self.width, self.height, bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(format: Format, width: u32, height: u32, bytes: &[u8]) -> Frame {
        Frame::new(format, width, height, bytes.to_vec()).unwrap()
    }

    #[test]
    fn rgb565_packs_by_truncation() {
        assert_eq!(rgb888_to_rgb565(255, 0, 0), 0xF800);
        assert_eq!(rgb888_to_rgb565(0, 255, 0), 0x07E0);
        assert_eq!(rgb888_to_rgb565(0, 0, 255), 0x001F);
        assert_eq!(rgb888_to_rgb565(0x84, 0x82, 0x08), 0x8401);
        let f = frame(Format::Rgb888, 2, 1, &[255, 0, 0, 0x84, 0x82, 0x08]);
        let le = f.clone().convert(Format::Rgb565Le).unwrap();
        assert_eq!(le.bytes, [0x00, 0xF8, 0x01, 0x84]);
        let be = f.convert(Format::Rgb565Be).unwrap();
        assert_eq!(be.bytes, [0xF8, 0x00, 0x84, 0x01]);
        // Widening replicates the top bits.
        assert_eq!(le.to_rgb888(), [255, 0, 0, 0x84, 0x82, 0x08]);
    }

    #[test]
    fn grey_and_yuyv_use_the_cores_colour_arithmetic() {
        let rgb = [200, 30, 40, 10, 220, 90];
        let f = frame(Format::Rgb888, 2, 1, &rgb);
        let grey = f.clone().convert(Format::Gray8).unwrap();
        assert_eq!(
            grey.bytes,
            [luma_of_rgb(200, 30, 40), luma_of_rgb(10, 220, 90)]
        );
        assert_eq!(grey.to_rgb888()[..3], [grey.bytes[0]; 3]);
        let yuyv = f.convert(Format::Yuyv).unwrap();
        let (y0, u0, v0) = rgb_to_yuv(200, 30, 40);
        let (y1, u1, v1) = rgb_to_yuv(10, 220, 90);
        assert_eq!(yuyv.bytes[0], y0);
        assert_eq!(yuyv.bytes[2], y1);
        assert_eq!(yuyv.bytes[1], (u0 as u16 + u1 as u16).div_ceil(2) as u8);
        assert_eq!(yuyv.bytes[3], (v0 as u16 + v1 as u16).div_ceil(2) as u8);
        let (r, g, b) = yuv_to_rgb(y0, yuyv.bytes[1], yuyv.bytes[3]);
        assert_eq!(yuyv.to_rgb888()[..3], [r, g, b]);
        // UYVY holds the same samples, chroma first; both read back to the same RGB.
        let uyvy = yuyv.clone().convert(Format::Uyvy).unwrap();
        let b = &yuyv.bytes;
        assert_eq!(uyvy.bytes, [b[1], b[0], b[3], b[2]]);
        assert_eq!(uyvy.to_rgb888(), yuyv.to_rgb888());
    }

    #[test]
    fn sizes_are_checked() {
        assert_eq!(Format::Yuyv.frame_bytes(4, 3), Some(24));
        assert_eq!(Format::Yuyv.frame_bytes(3, 3), None);
        assert_eq!(Format::Uyvy.frame_bytes(3, 3), None);
        assert_eq!(Format::Gray8.frame_bytes(0, 3), None);
        assert_eq!(
            Frame::new(Format::Rgb888, 2, 2, vec![0; 11]),
            Err(FrameError::Length {
                expected: 12,
                found: 11
            })
        );
        let odd = frame(Format::Rgb888, 3, 1, &[0; 9]);
        assert!(matches!(
            odd.convert(Format::Yuyv),
            Err(FrameError::Size { .. })
        ));
        for f in Format::ALL {
            assert_eq!(Format::from_name(f.name()), Some(f));
        }
        assert_eq!(Format::from_name("rgb565"), Some(Format::Rgb565Le));
    }
}
