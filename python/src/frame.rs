//! NumPy `uint8` frames as the core's frames: borrowed where the rows lie in one buffer
//! with unit pixel and channel steps (any row stride), copied otherwise.

use numpy::{
    PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use rbtrack_ffi::{Format, Frame};
use std::borrow::Cow;

/// How a frame's bytes are laid out, by the `format` argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Order {
    /// `(H, W, 3)`, B, G, R: OpenCV's order.
    Bgr,
    /// `(H, W, 3)`, R, G, B.
    Rgb,
    /// `(H, W)` or `(H, W, 1)`, grey levels.
    Gray,
}

impl Order {
    /// The order named `name` (`"bgr"`, `"rgb"`, `"gray"` or `"grey"`).
    pub fn named(name: &str) -> PyResult<Self> {
        match name {
            "bgr" => Ok(Self::Bgr),
            "rgb" => Ok(Self::Rgb),
            "gray" | "grey" => Ok(Self::Gray),
            _ => Err(PyValueError::new_err(format!(
                "format must be 'bgr', 'rgb' or 'gray', not {name:?}"
            ))),
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Bgr => "bgr",
            Self::Rgb => "rgb",
            Self::Gray => "gray",
        }
    }

    fn format(self) -> Format {
        match self {
            Self::Bgr => Format::Bgr888,
            Self::Rgb => Format::Rgb888,
            Self::Gray => Format::Gray8,
        }
    }
}

/// `frame` as a read-only `uint8` array, or a `TypeError` saying what it is.
pub fn borrow<'py>(frame: &Bound<'py, PyAny>) -> PyResult<PyReadonlyArrayDyn<'py, u8>> {
    let untyped = frame.cast::<PyUntypedArray>().map_err(|_| {
        PyTypeError::new_err(format!(
            "frame must be a NumPy uint8 array, not {}",
            frame
                .get_type()
                .name()
                .map_or_else(|_| "?".into(), |n| n.to_string())
        ))
    })?;
    let dtype = untyped.dtype();
    let typed = frame
        .cast::<PyArrayDyn<u8>>()
        .map_err(|_| PyTypeError::new_err(format!("frame must be a uint8 array, not {dtype}")))?;
    typed
        .try_readonly()
        .map_err(|e| PyValueError::new_err(format!("frame cannot be read: {e}")))
}

/// The pixels of a frame: bytes, width, height and row stride (px).
pub struct Pixels<'a> {
    bytes: Cow<'a, [u8]>,
    width: usize,
    height: usize,
    stride: usize,
    format: Format,
}

impl<'a> Pixels<'a> {
    /// The pixels of `array` in `order`, borrowed if its layout allows; a `ValueError` for
    /// a shape that `order` does not take.
    pub fn of(array: &'a PyReadonlyArrayDyn<'_, u8>, order: Order) -> PyResult<Self> {
        let view = array.as_array();
        let channels = match order {
            Order::Bgr | Order::Rgb => 3,
            Order::Gray => 1,
        };
        let (height, width) = match (view.shape(), order) {
            (&[h, w], Order::Gray) => (h, w),
            (&[h, w, c], _) if c == channels => (h, w),
            (shape, _) => {
                let want = match order {
                    Order::Gray => "(height, width) or (height, width, 1)",
                    _ => "(height, width, 3)",
                };
                return Err(PyValueError::new_err(format!(
                    "a {} frame has shape {want}, not {shape:?}",
                    order.name()
                )));
            }
        };
        let strides = view.strides();
        let unit = |axis: usize, step: isize| strides.get(axis).is_none_or(|&s| s == step);
        let row = strides.first().copied().unwrap_or(0);
        let rows_apart = usize::try_from(row)
            .ok()
            .filter(|&r| r % channels == 0 && r >= width * channels);
        let (bytes, stride) = match rows_apart {
            Some(row) if unit(1, channels as isize) && unit(2, 1) && height > 0 && width > 0 => {
                let len = (height - 1) * row + width * channels;
                // SAFETY: the array's elements are `u8` in one buffer that starts at
                // `as_ptr()` (its first element, the strides being positive) and holds
                // element `(h - 1, w - 1, c - 1)` at byte `len - 1`; `array` keeps the
                // buffer alive and borrowed read-only (NumPy's borrow flag) for `'a`.
                #[allow(unsafe_code)]
                let bytes = unsafe { std::slice::from_raw_parts(view.as_ptr(), len) };
                (Cow::Borrowed(bytes), row / channels)
            }
            _ => (Cow::Owned(view.iter().copied().collect()), width),
        };
        Ok(Self {
            bytes,
            width,
            height,
            stride,
            format: order.format(),
        })
    }

    /// Width and height, px.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// Whether the pixels are the array's own memory, not a copy.
    pub fn borrowed(&self) -> bool {
        matches!(self.bytes, Cow::Borrowed(_))
    }

    /// The core's frame, or a `ValueError` with the core's message.
    pub fn frame(&self) -> PyResult<Frame<'_>> {
        Frame::new(
            self.format,
            &self.bytes,
            self.width,
            self.height,
            self.stride,
        )
        .map_err(|e| PyValueError::new_err(e.to_string()))
    }
}
