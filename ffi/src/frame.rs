//! Frames of any pixel format chosen at run time: [`Format`] by number, [`Frame`] the
//! core's checked [`ImageView`] of that format.

use rbtrack::image::{
    Bgr888, Gray8, ImageError, ImageView, PixelFormat, Rgb565Be, Rgb565Le, Rgb888, Uyvy, Yuyv,
};

/// A pixel format by number, as the C header (`rbt_format`) and the Python module name it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// [`Gray8`]: 1 byte per pixel.
    Gray8,
    /// [`Rgb565Le`]: 2 bytes per pixel.
    Rgb565Le,
    /// [`Rgb565Be`]: 2 bytes per pixel.
    Rgb565Be,
    /// [`Rgb888`]: 3 bytes per pixel, R, G, B.
    Rgb888,
    /// [`Bgr888`]: 3 bytes per pixel, B, G, R.
    Bgr888,
    /// [`Yuyv`]: 2 bytes per pixel, width and stride even.
    Yuyv,
    /// [`Uyvy`]: 2 bytes per pixel, width and stride even.
    Uyvy,
}

impl Format {
    /// Every format, in the order of their numbers `1..=7`.
    pub const ALL: [Format; 7] = [
        Format::Gray8,
        Format::Rgb565Le,
        Format::Rgb565Be,
        Format::Rgb888,
        Format::Bgr888,
        Format::Yuyv,
        Format::Uyvy,
    ];

    /// The format numbered `code` (`1..=7`, the C header's `RBT_FORMAT_*`), if any.
    pub fn from_code(code: u32) -> Option<Self> {
        let index = usize::try_from(code).ok()?.checked_sub(1)?;
        Self::ALL.get(index).copied()
    }

    /// Bytes per pixel.
    pub fn bytes_per_pixel(self) -> usize {
        match self {
            Format::Gray8 => Gray8::BYTES_PER_PIXEL,
            Format::Rgb565Le => Rgb565Le::BYTES_PER_PIXEL,
            Format::Rgb565Be => Rgb565Be::BYTES_PER_PIXEL,
            Format::Rgb888 => Rgb888::BYTES_PER_PIXEL,
            Format::Bgr888 => Bgr888::BYTES_PER_PIXEL,
            Format::Yuyv => Yuyv::BYTES_PER_PIXEL,
            Format::Uyvy => Uyvy::BYTES_PER_PIXEL,
        }
    }
}

/// A checked frame of a [`Format`] chosen at run time.
#[derive(Clone, Copy, Debug)]
pub enum Frame<'a> {
    /// [`Format::Gray8`].
    Gray8(ImageView<'a, Gray8>),
    /// [`Format::Rgb565Le`].
    Rgb565Le(ImageView<'a, Rgb565Le>),
    /// [`Format::Rgb565Be`].
    Rgb565Be(ImageView<'a, Rgb565Be>),
    /// [`Format::Rgb888`].
    Rgb888(ImageView<'a, Rgb888>),
    /// [`Format::Bgr888`].
    Bgr888(ImageView<'a, Bgr888>),
    /// [`Format::Yuyv`].
    Yuyv(ImageView<'a, Yuyv>),
    /// [`Format::Uyvy`].
    Uyvy(ImageView<'a, Uyvy>),
}

/// Evaluates `$body` with `$view` bound to the [`ImageView`] inside the [`Frame`] `$frame`.
macro_rules! with_view {
    ($frame:expr, $view:ident => $body:expr) => {
        match $frame {
            $crate::Frame::Gray8($view) => $body,
            $crate::Frame::Rgb565Le($view) => $body,
            $crate::Frame::Rgb565Be($view) => $body,
            $crate::Frame::Rgb888($view) => $body,
            $crate::Frame::Bgr888($view) => $body,
            $crate::Frame::Yuyv($view) => $body,
            $crate::Frame::Uyvy($view) => $body,
        }
    };
}
pub(crate) use with_view;

impl<'a> Frame<'a> {
    /// Checks and wraps `bytes` as a `width x height` frame of `format`, rows `stride` px
    /// apart ([`ImageView::new`]).
    ///
    /// # Errors
    /// [`ImageView::new`]'s.
    pub fn new(
        format: Format,
        bytes: &'a [u8],
        width: usize,
        height: usize,
        stride: usize,
    ) -> Result<Self, ImageError> {
        Ok(match format {
            Format::Gray8 => Frame::Gray8(ImageView::new(bytes, width, height, stride)?),
            Format::Rgb565Le => Frame::Rgb565Le(ImageView::new(bytes, width, height, stride)?),
            Format::Rgb565Be => Frame::Rgb565Be(ImageView::new(bytes, width, height, stride)?),
            Format::Rgb888 => Frame::Rgb888(ImageView::new(bytes, width, height, stride)?),
            Format::Bgr888 => Frame::Bgr888(ImageView::new(bytes, width, height, stride)?),
            Format::Yuyv => Frame::Yuyv(ImageView::new(bytes, width, height, stride)?),
            Format::Uyvy => Frame::Uyvy(ImageView::new(bytes, width, height, stride)?),
        })
    }

    /// Width, px.
    pub fn width(&self) -> usize {
        with_view!(self, v => v.width())
    }

    /// Height, px.
    pub fn height(&self) -> usize {
        with_view!(self, v => v.height())
    }
}
