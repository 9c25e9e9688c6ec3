//! Camera frames, borrowed for a call.

use super::rbt_error::{self, *};
use crate::frame::{Format, Frame};

/// A pixel format (`rbt_image.format`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum rbt_format {
    /// 8-bit grey, 1 byte per pixel.
    RBT_FORMAT_GRAY8 = 1,
    /// RGB565, a little-endian 16-bit word per pixel.
    RBT_FORMAT_RGB565LE = 2,
    /// RGB565, a big-endian 16-bit word per pixel.
    RBT_FORMAT_RGB565BE = 3,
    /// 3 bytes per pixel: R, G, B.
    RBT_FORMAT_RGB888 = 4,
    /// 3 bytes per pixel: B, G, R.
    RBT_FORMAT_BGR888 = 5,
    /// YUV 4:2:2, `Y0 U Y1 V` per pixel pair (width and stride even).
    RBT_FORMAT_YUYV = 6,
    /// YUV 4:2:2, `U Y0 V Y1` per pixel pair (width and stride even).
    RBT_FORMAT_UYVY = 7,
}

/// A camera frame, borrowed for the call.
#[repr(C)]
#[derive(Clone, Copy, Debug)]
pub struct rbt_image {
    /// The pixels, row after row; `size` bytes readable.
    pub data: *const u8,
    /// Bytes at `data`; at least `((height - 1) * stride + width) * bytes per pixel`.
    pub size: usize,
    /// Width, px, 1..=16383.
    pub width: u32,
    /// Height, px, 1..=16383.
    pub height: u32,
    /// Distance between row starts, px, `>= width`.
    pub stride: u32,
    /// An `rbt_format`.
    pub format: u32,
}

/// The frame `image` describes.
///
/// # Safety
/// `image` is null or points to an `rbt_image` whose `data` is null or points to `size`
/// bytes that stay readable and unchanged for `'a`.
pub(super) unsafe fn frame<'a>(image: *const rbt_image) -> Result<Frame<'a>, rbt_error> {
    // SAFETY: `image` is null (refused here) or points to an `rbt_image` (the caller's
    // promise).
    let image = unsafe { image.as_ref() }.ok_or(RBT_ERR_NULL)?;
    let format = Format::from_code(image.format).ok_or(RBT_ERR_FORMAT)?;
    if image.data.is_null() {
        return Err(RBT_ERR_NULL);
    }
    // A slice may not exceed isize::MAX bytes; a prefix of readable bytes is readable.
    let size = image.size.min(isize::MAX as usize);
    // SAFETY: `data` is non-null and points to at least `size` readable bytes that stay
    // unchanged for `'a` (the caller's promise); `u8` has no alignment or validity needs.
    let bytes = unsafe { core::slice::from_raw_parts(image.data, size) };
    let side = |v: u32| usize::try_from(v).unwrap_or(usize::MAX);
    let (width, height, stride) = (side(image.width), side(image.height), side(image.stride));
    Ok(Frame::new(format, bytes, width, height, stride)?)
}
