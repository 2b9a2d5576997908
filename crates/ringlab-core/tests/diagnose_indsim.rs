//! The diagnosis on recordings of a third simulator (`tests/data/indsim/`, made by
//! `tools/indsim/indsim.py`, written apart from ringlab: its own integrator, contact and
//! camera), each kept because the diagnosis once got it wrong: a tracker that writes whole
//! pixels (its noise was read too low), a lens beside a pinhole (no pair of camera effects was
//! tried), a sliding ring filmed through a pinhole (slip alone never left the baseline through
//! the wrong camera), pincushion distortion, glitches with swaps of adjacent marks, and a table that is
//! not level (physics no candidate has: `unexplained`, never another effect's name).

mod common;
mod said;

#[test]
fn whole_pixel_tracks_are_consistent_with_their_noise() {
    let d = said::check("indsim", "quantised");
    assert!(d.before.rms_px < 1.1 * d.noise_px, "{} against {}", d.before.rms_px, d.noise_px);
}

#[test]
fn a_lens_beside_a_pinhole_is_named_as_both() {
    let d = said::check("indsim", "lens-persp");
    // 450 mm and k1 = -0.05 in truth.json.
    let distance = d.after.camera.distance_mm.expect("a pinhole");
    assert!((distance / 450.0 - 1.0).abs() < 0.05, "{distance} mm");
    assert!((d.after.camera.k1 + 0.05).abs() < 0.005, "k1 {}", d.after.camera.k1);
}

#[test]
fn pincushion_distortion_is_named() {
    let d = said::check("indsim", "lens-pincushion");
    assert!((d.after.camera.k1 - 0.05).abs() < 0.01, "k1 {}", d.after.camera.k1);
}

#[test]
fn glitches_with_adjacent_swaps_are_left_out() {
    let d = said::check("indsim", "glitches-2pct");
    assert!(d.before.rms_px < 1.1 * d.noise_px, "{} against {}", d.before.rms_px, d.noise_px);
}

#[test]
fn a_table_that_is_not_level_is_unexplained() {
    said::check("indsim", "table-slope");
}

#[test]
fn slip_filmed_through_a_pinhole_is_named_with_the_camera() {
    let d = said::check("indsim", "slip-persp");
    // mu = 0.40 and 500 mm in truth.json.
    let mu = d.after.model.effects.slip_mu.expect("a sliding contact");
    assert!((mu - 0.40).abs() < 0.01, "mu {mu}");
    let distance = d.after.camera.distance_mm.expect("a pinhole");
    assert!((distance / 500.0 - 1.0).abs() < 0.05, "{distance} mm");
}
