//! One error for code that builds frames and starts trackers in one place.

use crate::image::ImageError;
use crate::tracker::ConfigError;

/// A frame that could not be viewed, or a tracker that could not start: what `?` turns
/// [`ImageError`] and [`ConfigError`] into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Error {
    /// [`crate::ImageView::new`] refused the frame.
    Image(ImageError),
    /// The tracker refused its configuration or its start.
    Config(ConfigError),
}

impl core::fmt::Display for Error {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::Image(e) => write!(f, "frame: {e}"),
            Self::Config(e) => write!(f, "tracker: {e}"),
        }
    }
}

impl core::error::Error for Error {
    fn source(&self) -> Option<&(dyn core::error::Error + 'static)> {
        match self {
            Self::Image(e) => Some(e),
            Self::Config(e) => Some(e),
        }
    }
}

impl From<ImageError> for Error {
    fn from(e: ImageError) -> Self {
        Self::Image(e)
    }
}

impl From<ConfigError> for Error {
    fn from(e: ConfigError) -> Self {
        Self::Config(e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::ToString;

    #[test]
    fn says_which_part_refused() {
        let frame: Error = ImageError::ZeroSize.into();
        assert!(frame.to_string().starts_with("frame: "), "{frame}");
        let tracker: Error = ConfigError::OutOfRange("colour_sigma").into();
        assert_eq!(
            tracker.to_string(),
            "tracker: configuration field `colour_sigma` out of range"
        );
    }
}
