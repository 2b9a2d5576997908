//! Pictures as PNG files: the window's screenshot (an egui image) or a rendered view.

use super::ExportError;
use eframe::egui;
use image::RgbaImage;
use std::path::Path;

/// Writes `img` as a PNG (a download in a web page); the folder must exist.
pub fn save_png(img: &RgbaImage, path: &Path) -> Result<(), ExportError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
        && !dir.is_dir()
    {
        return Err(ExportError::Invalid(format!(
            "{}: the folder {} does not exist",
            path.display(),
            dir.display()
        )));
    }
    let mut png = std::io::Cursor::new(Vec::new());
    img.write_to(&mut png, image::ImageFormat::Png)
        .map_err(|e| ExportError::Encode { path: path.to_path_buf(), message: e.to_string() })?;
    super::deliver::deliver(path, png.get_ref())
}

/// An egui screenshot as an image (egui's colours are premultiplied; a window's are opaque).
pub fn from_color_image(c: &egui::ColorImage) -> RgbaImage {
    let [w, h] = c.size;
    let bytes: Vec<u8> = c.pixels.iter().flat_map(|p| p.to_srgba_unmultiplied()).collect();
    RgbaImage::from_raw(w as u32, h as u32, bytes).unwrap_or_else(|| RgbaImage::new(1, 1))
}

/// Views side by side on white in a picture of `size`, each at `i (w + gap)` (the 3D view of
/// two runs; `w` the first's width).
pub fn side_by_side(images: &[RgbaImage], size: [u32; 2], gap: u32) -> RgbaImage {
    let mut out =
        RgbaImage::from_pixel(size[0].max(1), size[1].max(1), image::Rgba([255, 255, 255, 255]));
    let w = images.first().map_or(0, |i| i.width());
    for (i, img) in images.iter().enumerate() {
        image::imageops::replace(&mut out, img, (i as u32 * (w + gap)) as i64, 0);
    }
    out
}
