//! The raster every picture is drawn on: allocated, then encoded as PNG, with one error for
//! both steps.

use resvg::tiny_skia::Pixmap;

/// Why a picture's raster cannot be allocated or encoded.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum PixmapError {
    /// The pixmap cannot be allocated.
    #[error("cannot allocate a {width}×{height} pixmap")]
    Allocate {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// PNG encoding failed.
    #[error("cannot encode the PNG: {message}")]
    Encode {
        /// The encoder's description.
        message: String,
    },
}

/// A transparent `width × height` pixmap, or [`PixmapError::Allocate`].
pub(crate) fn new_pixmap(width: u32, height: u32) -> Result<Pixmap, PixmapError> {
    Pixmap::new(width, height).ok_or(PixmapError::Allocate { width, height })
}

/// `image` as 8-bit RGBA PNG bytes, or [`PixmapError::Encode`].
pub(crate) fn encode_png(image: &Pixmap) -> Result<Vec<u8>, PixmapError> {
    image.encode_png().map_err(|e| PixmapError::Encode {
        message: e.to_string(),
    })
}
