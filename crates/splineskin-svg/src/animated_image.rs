//! Animated previews any viewer plays: APNG (the `png` crate) and GIF (the `gif` crate, colours
//! reduced per frame by NeuQuant), from rendered frames ([`crate::render::render_rgba`]).
//!
//! Frame `k` is shown for `delays[k]` seconds, rounded to what the format stores: milliseconds
//! in APNG (`delay_num / delay_den` with `den = 1000`), hundredths of a second in GIF (at least
//! 2, since browsers play shorter GIF delays as 0.1 s). Both loop forever. Frames are
//! written as they come ([`AnimatedImage::push`]), so memory is that of one frame plus the
//! encoded output.

use crate::render::RgbaImage;

/// The format of an [`AnimatedImage`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AnimatedFormat {
    /// Animated PNG: full colour and alpha.
    Apng,
    /// GIF: 256 colours per frame.
    Gif,
}

/// Why an animated image could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum AnimatedImageError {
    /// A frame or delay is not valid (the message says what was expected).
    #[error("cannot write the animated image: {what}")]
    Invalid {
        /// What is wrong.
        what: String,
    },
    /// The encoder failed.
    #[error("cannot encode the animated image: {message}")]
    Encode {
        /// The encoder's description.
        message: String,
    },
}

enum Encoder {
    /// The PNG writer writes into a buffer it does not give back: the other handle keeps it.
    Apng(png::Writer<Buffer>, Buffer),
    Gif(gif::Encoder<Vec<u8>>),
}

/// A byte buffer with two handles (the `png` writer has no `into_inner`).
#[derive(Clone, Default)]
struct Buffer(std::rc::Rc<std::cell::RefCell<Vec<u8>>>);

impl std::io::Write for Buffer {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().extend_from_slice(bytes);
        Ok(bytes.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// An animated image being written, frame by frame.
pub struct AnimatedImage {
    encoder: Encoder,
    width: u32,
    height: u32,
    n_frames: usize,
    written: usize,
}

/// An encoder's failure.
fn encode(e: impl std::fmt::Display) -> AnimatedImageError {
    AnimatedImageError::Encode {
        message: e.to_string(),
    }
}

/// The largest side a GIF can have: 65 535 pixels.
const MAX_GIF_SIDE: u32 = u16::MAX as u32;

/// NeuQuant sampling factor of the GIF colour reduction: 10 (1 is best and slowest, 30
/// fastest; 10 is the usual balance).
const GIF_QUANTIZER_SPEED: i32 = 10;

impl AnimatedImage {
    /// Starts an animated image of `n_frames` frames of `width × height` pixels.
    ///
    /// ```
    /// use splineskin_svg::animated_image::{AnimatedFormat, AnimatedImage};
    /// use splineskin_svg::render::RgbaImage;
    /// let frame = |v: u8| RgbaImage { width: 2, height: 1, data: vec![v, 0, 0, 255, 0, v, 0, 255] };
    /// for format in [AnimatedFormat::Apng, AnimatedFormat::Gif] {
    ///     let mut image = AnimatedImage::new(format, 2, 1, 2)?;
    ///     image.push(&frame(255), 0.5)?;
    ///     image.push(&frame(128), 0.5)?;
    ///     let bytes = image.finish()?;
    ///     assert!(bytes.starts_with(if format == AnimatedFormat::Gif { b"GIF89a" } else { b"\x89PNG" }));
    /// }
    /// # Ok::<(), splineskin_svg::animated_image::AnimatedImageError>(())
    /// ```
    pub fn new(
        format: AnimatedFormat,
        width: u32,
        height: u32,
        n_frames: usize,
    ) -> Result<AnimatedImage, AnimatedImageError> {
        let invalid = |what: String| Err(AnimatedImageError::Invalid { what });
        if width == 0 || height == 0 {
            return invalid(format!(
                "{width} × {height} pixels (expected at least 1 × 1)"
            ));
        }
        if n_frames == 0 || u32::try_from(n_frames).is_err() {
            return invalid(format!("{n_frames} frames (expected 1 to {})", u32::MAX));
        }
        let encoder = match format {
            AnimatedFormat::Apng => {
                let buffer = Buffer::default();
                let mut e = png::Encoder::new(buffer.clone(), width, height);
                e.set_color(png::ColorType::Rgba);
                e.set_depth(png::BitDepth::Eight);
                e.set_animated(n_frames as u32, 0).map_err(encode)?;
                Encoder::Apng(e.write_header().map_err(encode)?, buffer)
            }
            AnimatedFormat::Gif => {
                if width > MAX_GIF_SIDE || height > MAX_GIF_SIDE {
                    return invalid(format!(
                        "{width} × {height} pixels (a GIF has at most {MAX_GIF_SIDE} on a side)"
                    ));
                }
                let mut e = gif::Encoder::new(Vec::new(), width as u16, height as u16, &[])
                    .map_err(encode)?;
                e.set_repeat(gif::Repeat::Infinite).map_err(encode)?;
                Encoder::Gif(e)
            }
        };
        Ok(AnimatedImage {
            encoder,
            width,
            height,
            n_frames,
            written: 0,
        })
    }

    /// Appends `frame`, shown for `delay` seconds (positive, finite, below 65 s).
    pub fn push(&mut self, frame: &RgbaImage, delay: f64) -> Result<(), AnimatedImageError> {
        let invalid = |what: String| Err(AnimatedImageError::Invalid { what });
        if (frame.width, frame.height) != (self.width, self.height)
            || frame.data.len() != 4 * frame.width as usize * frame.height as usize
        {
            return invalid(format!(
                "frame {} is {} × {} pixels with {} bytes (expected {} × {}, 4 bytes a pixel)",
                self.written,
                frame.width,
                frame.height,
                frame.data.len(),
                self.width,
                self.height
            ));
        }
        if !(delay.is_finite() && delay > 0.0 && delay < 65.0) {
            return invalid(format!(
                "frame {}: delay {delay} s (expected a positive number below 65 s)",
                self.written
            ));
        }
        if self.written == self.n_frames {
            return invalid(format!("more than the {} frames announced", self.n_frames));
        }
        match &mut self.encoder {
            Encoder::Apng(w, _) => {
                let ms = (delay * 1000.0).round().max(1.0) as u16;
                w.set_frame_delay(ms, 1000).map_err(encode)?;
                w.write_image_data(&frame.data).map_err(encode)?;
            }
            Encoder::Gif(e) => {
                let mut pixels = frame.data.clone();
                let mut f = gif::Frame::from_rgba_speed(
                    frame.width as u16,
                    frame.height as u16,
                    &mut pixels,
                    GIF_QUANTIZER_SPEED,
                );
                f.delay = (delay * 100.0).round().max(2.0) as u16;
                e.write_frame(&f).map_err(encode)?;
            }
        }
        self.written += 1;
        Ok(())
    }

    /// Ends the image: its bytes. Errors if fewer frames were pushed than announced.
    pub fn finish(self) -> Result<Vec<u8>, AnimatedImageError> {
        if self.written != self.n_frames {
            return Err(AnimatedImageError::Invalid {
                what: format!(
                    "{} of the {} frames announced were written",
                    self.written, self.n_frames
                ),
            });
        }
        match self.encoder {
            Encoder::Apng(w, buffer) => {
                w.finish().map_err(encode)?;
                Ok(buffer.0.take())
            }
            Encoder::Gif(e) => e.into_inner().map_err(encode),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Frame `k` of a 3 × 2 test animation: a red square moving right one pixel a frame over
    /// white, in pure colours (which survive GIF's colour reduction exactly).
    fn frame(k: usize) -> RgbaImage {
        let mut data = Vec::new();
        for _y in 0..2 {
            for x in 0..3 {
                data.extend(if x == k {
                    [255, 0, 0, 255]
                } else {
                    [255, 255, 255, 255]
                });
            }
        }
        RgbaImage {
            width: 3,
            height: 2,
            data,
        }
    }

    #[test]
    fn apng_round_trips_frames_and_delays() {
        let mut image = AnimatedImage::new(AnimatedFormat::Apng, 3, 2, 3).unwrap();
        for (k, delay) in [0.1, 0.25, 0.0333].into_iter().enumerate() {
            image.push(&frame(k), delay).unwrap();
        }
        let bytes = image.finish().unwrap();
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .unwrap();
        let control = reader.info().animation_control.unwrap();
        assert_eq!((control.num_frames, control.num_plays), (3, 0));
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        for (k, ms) in [100, 250, 33].into_iter().enumerate() {
            reader.next_frame(&mut buf).unwrap();
            let fc = reader.info().frame_control.unwrap();
            assert_eq!((fc.delay_num, fc.delay_den), (ms, 1000), "frame {k}");
            assert_eq!(buf[..24], frame(k).data[..], "frame {k}");
        }
    }

    #[test]
    fn gif_round_trips_frames_and_delays() {
        let mut image = AnimatedImage::new(AnimatedFormat::Gif, 3, 2, 3).unwrap();
        for (k, delay) in [0.1, 0.25, 0.001].into_iter().enumerate() {
            image.push(&frame(k), delay).unwrap();
        }
        let bytes = image.finish().unwrap();
        let mut options = gif::DecodeOptions::new();
        options.set_color_output(gif::ColorOutput::RGBA);
        let mut decoder = options.read_info(std::io::Cursor::new(bytes)).unwrap();
        // 0.001 s is stored as the shortest delay browsers honour, 2 hundredths.
        for (k, delay) in [10, 25, 2].into_iter().enumerate() {
            let f = decoder.read_next_frame().unwrap().unwrap();
            assert_eq!(f.delay, delay, "frame {k}");
            assert_eq!(f.buffer[..], frame(k).data[..], "frame {k}");
        }
        assert!(decoder.read_next_frame().unwrap().is_none());
    }

    #[test]
    fn animated_images_reject_what_they_cannot_write() {
        assert!(AnimatedImage::new(AnimatedFormat::Apng, 0, 2, 1).is_err());
        assert!(AnimatedImage::new(AnimatedFormat::Gif, 3, 2, 0).is_err());
        assert!(AnimatedImage::new(AnimatedFormat::Gif, 70_000, 2, 1).is_err());
        let mut image = AnimatedImage::new(AnimatedFormat::Apng, 3, 2, 1).unwrap();
        let wrong = RgbaImage {
            width: 2,
            height: 2,
            data: vec![0; 16],
        };
        assert!(image
            .push(&wrong, 0.1)
            .unwrap_err()
            .to_string()
            .contains("expected 3 × 2"));
        for delay in [0.0, -1.0, f64::NAN, 100.0] {
            assert!(image.push(&frame(0), delay).is_err(), "{delay}");
        }
        image.push(&frame(0), 0.1).unwrap();
        assert!(image
            .push(&frame(1), 0.1)
            .unwrap_err()
            .to_string()
            .contains("more than the 1"));
        let short = AnimatedImage::new(AnimatedFormat::Gif, 3, 2, 2).unwrap();
        assert!(short
            .finish()
            .unwrap_err()
            .to_string()
            .contains("0 of the 2"));
    }
}
