//! The writer of format v1 (the inverse of [`super::read`]).

use super::Recording;
use super::read::{COLUMNS, MAGIC};
use std::io::{self, Write};

/// Decimals written for pixel coordinates (a hundredth of a pixel, as in the sample).
pub const PIXEL_DECIMALS: usize = 2;

/// Writes a recording; header numbers are written so that they read back exactly, pixel
/// coordinates to [`PIXEL_DECIMALS`].
pub fn write_recording(out: &mut impl Write, rec: &Recording) -> io::Result<()> {
    write_with(out, rec, Some(PIXEL_DECIMALS))
}

/// Writes a recording whose pixel coordinates too read back exactly (the shortest decimals that
/// do). A kept recording must give the answer it gave in memory: a diagnosis can end in another
/// valley of its least squares after rounding to a hundredth of a pixel, far below the noise.
pub fn write_recording_exact(out: &mut impl Write, rec: &Recording) -> io::Result<()> {
    write_with(out, rec, None)
}

/// `decimals`: the pixel coordinates' decimals; `None`, as many as read back exactly.
fn write_with(out: &mut impl Write, rec: &Recording, decimals: Option<usize>) -> io::Result<()> {
    let h = &rec.header;
    writeln!(out, "{MAGIC}")?;
    writeln!(out, "# fps = {:?}", h.fps)?;
    writeln!(out, "# px_per_mm = {:?}", h.px_per_mm)?;
    writeln!(out, "# shape = {}", h.shape.name())?;
    writeln!(out, "# outer_radius_mm = {:?}", h.outer_radius_mm)?;
    writeln!(out, "# width_mm = {:?}", h.width_mm)?;
    if let Some(w) = h.thickness_mm {
        writeln!(out, "# thickness_mm = {w:?}")?;
    }
    if let Some(w) = h.image_width_px {
        writeln!(out, "# image_width_px = {w}")?;
    }
    if let Some(v) = h.image_height_px {
        writeln!(out, "# image_height_px = {v}")?;
    }
    if let Some(d) = h.camera_distance_mm {
        writeln!(out, "# camera_distance_mm = {d:?}")?;
    }
    if let Some(t) = h.camera_tilt_deg {
        writeln!(out, "# camera_tilt_deg = {t:?}")?;
    }
    for (k, v) in &h.extra {
        writeln!(out, "# {k} = {v}")?;
    }
    writeln!(out, "{}", COLUMNS.join(","))?;
    for (i, marks) in rec.frames.iter().enumerate() {
        write!(out, "{}", rec.frame_number(i))?;
        for m in marks {
            match m {
                Some([x, y]) => match decimals {
                    Some(d) => write!(out, ",{x:.d$},{y:.d$}")?,
                    None => write!(out, ",{x:?},{y:?}")?,
                },
                None => write!(out, ",,")?,
            }
        }
        writeln!(out)?;
    }
    Ok(())
}
