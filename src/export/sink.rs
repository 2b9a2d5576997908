//! What an encoder is to a video's frames (the GIF and MP4 writers are ones; `video` opens
//! them by the file's name).

use super::ExportError;
use image::RgbaImage;

/// An encoder taking frames one by one.
pub trait FrameSink {
    fn push(&mut self, frame: &RgbaImage) -> Result<(), ExportError>;
    /// Ends the file.
    fn finish(self: Box<Self>) -> Result<(), ExportError>;
    /// Stops without a file (cancelled or failed): what was written is removed.
    fn abandon(self: Box<Self>);
}
