//! The recovered motion as a table (CSV), frame by frame, in mm and s and in model units.

use super::recover::RecoveredMotion;
use std::io::{self, Write};

/// Columns of [`write_motion_csv`]. Angles in rad; `*_model` in the model's units (lengths in
/// mean radii, time in its unit); `v_p_px_per_frame` as in the paper's Fig. 3. Unknown
/// values (no pose, an unbounded sigma) are empty.
pub const MOTION_COLUMNS: &[&str] = &[
    "frame",
    "t_s",
    "t_model",
    "marks",
    "ax_mm",
    "ay_mm",
    "a_sigma_mm",
    "ax_model",
    "ay_model",
    "a_sigma_model",
    "phi",
    "phi_sigma",
    "theta",
    "theta_sigma",
    "psi",
    "psi_sigma",
    "branch_checked",
    "v_p_mm_s",
    "v_p_sigma_mm_s",
    "v_p_model",
    "v_p_sigma_model",
    "v_p_px_per_frame",
    "still",
];

pub fn write_motion_csv(
    out: &mut impl Write,
    m: &RecoveredMotion,
    first_frame: u64,
) -> io::Result<()> {
    writeln!(out, "{}", MOTION_COLUMNS.join(","))?;
    let k = m.to_model();
    let px_per_frame = m.camera.px_per_mm / m.fps;
    let num =
        |v: Option<f64>| v.filter(|x| x.is_finite()).map(|x| format!("{x:.6}")).unwrap_or_default();
    for (i, f) in m.frames.iter().enumerate() {
        let a = f.a_mm;
        let ang = f.angles;
        let row = [
            (first_frame + i as u64).to_string(),
            num(Some(f.t_s)),
            num(Some(f.t_s * k.time)),
            f.marks.to_string(),
            num(a.map(|p| p[0])),
            num(a.map(|p| p[1])),
            num(a.map(|_| f.a_sigma_mm)),
            num(a.map(|p| p[0] * k.length)),
            num(a.map(|p| p[1] * k.length)),
            num(a.map(|_| f.a_sigma_mm * k.length)),
            num(ang.map(|x| x.phi)),
            num(ang.map(|_| f.angles_sigma[0])),
            num(ang.map(|x| x.theta)),
            num(ang.map(|_| f.angles_sigma[1])),
            num(ang.map(|x| x.psi)),
            num(ang.map(|_| f.angles_sigma[2])),
            (f.branch_checked as u8).to_string(),
            num(f.v_p_mm_s),
            num(f.v_p_mm_s.map(|_| f.v_p_sigma_mm_s)),
            num(f.v_p_mm_s.map(|v| v * k.speed())),
            num(f.v_p_mm_s.map(|_| f.v_p_sigma_mm_s * k.speed())),
            num(f.v_p_mm_s.map(|v| v * px_per_frame)),
            (m.rest_from.is_some_and(|r| i >= r) as u8).to_string(),
        ];
        writeln!(out, "{}", row.join(","))?;
    }
    Ok(())
}
