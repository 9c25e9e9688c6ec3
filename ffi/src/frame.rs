//! Frames of any pixel format chosen at run time: [`Format`] by number, [`Frame`] the
//! core's checked [`ImageView`] of that format.

use rbtrack::image::{self, ImageError, ImageView};

#[cfg(not(any(
    feature = "gray8",
    feature = "rgb565le",
    feature = "rgb565be",
    feature = "rgb888",
    feature = "bgr888",
    feature = "yuyv",
    feature = "uyvy"
)))]
compile_error!("rbtrack-ffi needs at least one pixel format feature (gray8, rgb565le, ...)");

/// A pixel format by number, as the C header (`rbt_format`) and the Python module name it;
/// each is a Cargo feature of this crate (all on by default), so that a firmware links the
/// tracker for the formats its camera delivers alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// [`image::Gray8`]: 1 byte per pixel.
    #[cfg(feature = "gray8")]
    Gray8,
    /// [`image::Rgb565Le`]: 2 bytes per pixel.
    #[cfg(feature = "rgb565le")]
    Rgb565Le,
    /// [`image::Rgb565Be`]: 2 bytes per pixel.
    #[cfg(feature = "rgb565be")]
    Rgb565Be,
    /// [`image::Rgb888`]: 3 bytes per pixel, R, G, B.
    #[cfg(feature = "rgb888")]
    Rgb888,
    /// [`image::Bgr888`]: 3 bytes per pixel, B, G, R.
    #[cfg(feature = "bgr888")]
    Bgr888,
    /// [`image::Yuyv`]: 2 bytes per pixel, width and stride even.
    #[cfg(feature = "yuyv")]
    Yuyv,
    /// [`image::Uyvy`]: 2 bytes per pixel, width and stride even.
    #[cfg(feature = "uyvy")]
    Uyvy,
}

impl Format {
    /// The format numbered `code` (the C header's `RBT_FORMAT_*`, `1..=7`), if this build
    /// has it (its Cargo feature: all by default).
    pub fn from_code(code: u32) -> Option<Self> {
        match code {
            #[cfg(feature = "gray8")]
            1 => Some(Format::Gray8),
            #[cfg(feature = "rgb565le")]
            2 => Some(Format::Rgb565Le),
            #[cfg(feature = "rgb565be")]
            3 => Some(Format::Rgb565Be),
            #[cfg(feature = "rgb888")]
            4 => Some(Format::Rgb888),
            #[cfg(feature = "bgr888")]
            5 => Some(Format::Bgr888),
            #[cfg(feature = "yuyv")]
            6 => Some(Format::Yuyv),
            #[cfg(feature = "uyvy")]
            7 => Some(Format::Uyvy),
            _ => None,
        }
    }
}

/// A checked frame of a [`Format`] chosen at run time.
#[derive(Clone, Copy, Debug)]
pub enum Frame<'a> {
    /// [`Format::Gray8`].
    #[cfg(feature = "gray8")]
    Gray8(ImageView<'a, image::Gray8>),
    /// [`Format::Rgb565Le`].
    #[cfg(feature = "rgb565le")]
    Rgb565Le(ImageView<'a, image::Rgb565Le>),
    /// [`Format::Rgb565Be`].
    #[cfg(feature = "rgb565be")]
    Rgb565Be(ImageView<'a, image::Rgb565Be>),
    /// [`Format::Rgb888`].
    #[cfg(feature = "rgb888")]
    Rgb888(ImageView<'a, image::Rgb888>),
    /// [`Format::Bgr888`].
    #[cfg(feature = "bgr888")]
    Bgr888(ImageView<'a, image::Bgr888>),
    /// [`Format::Yuyv`].
    #[cfg(feature = "yuyv")]
    Yuyv(ImageView<'a, image::Yuyv>),
    /// [`Format::Uyvy`].
    #[cfg(feature = "uyvy")]
    Uyvy(ImageView<'a, image::Uyvy>),
}

/// Evaluates `$body` with `$view` bound to the [`ImageView`] inside the [`Frame`] `$frame`.
macro_rules! with_view {
    ($frame:expr, $view:ident => $body:expr) => {
        match $frame {
            #[cfg(feature = "gray8")]
            $crate::Frame::Gray8($view) => $body,
            #[cfg(feature = "rgb565le")]
            $crate::Frame::Rgb565Le($view) => $body,
            #[cfg(feature = "rgb565be")]
            $crate::Frame::Rgb565Be($view) => $body,
            #[cfg(feature = "rgb888")]
            $crate::Frame::Rgb888($view) => $body,
            #[cfg(feature = "bgr888")]
            $crate::Frame::Bgr888($view) => $body,
            #[cfg(feature = "yuyv")]
            $crate::Frame::Yuyv($view) => $body,
            #[cfg(feature = "uyvy")]
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
            #[cfg(feature = "gray8")]
            Format::Gray8 => Frame::Gray8(ImageView::new(bytes, width, height, stride)?),
            #[cfg(feature = "rgb565le")]
            Format::Rgb565Le => Frame::Rgb565Le(ImageView::new(bytes, width, height, stride)?),
            #[cfg(feature = "rgb565be")]
            Format::Rgb565Be => Frame::Rgb565Be(ImageView::new(bytes, width, height, stride)?),
            #[cfg(feature = "rgb888")]
            Format::Rgb888 => Frame::Rgb888(ImageView::new(bytes, width, height, stride)?),
            #[cfg(feature = "bgr888")]
            Format::Bgr888 => Frame::Bgr888(ImageView::new(bytes, width, height, stride)?),
            #[cfg(feature = "yuyv")]
            Format::Yuyv => Frame::Yuyv(ImageView::new(bytes, width, height, stride)?),
            #[cfg(feature = "uyvy")]
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
