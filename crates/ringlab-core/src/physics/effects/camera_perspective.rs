//! `camera_perspective`: a pinhole camera at a finite distance `D` from the table (marks above
//! the table look farther from the image centre), its tilt a second fitted number; strength
//! `1000 mm / D` (0: the orthographic camera).
//!
//! Realistic `1000 mm / D` in [1.25, 3.33]: a camera 300 to 800 mm above the table, where a lab
//! films a 40 mm ring with a normal lens; the paper names perspective as one of the two causes
//! of its 5% error. The search goes from orthographic down to 100 mm (2.5 ring diameters).

use super::{USUAL_IN_PLAN, InPlan, 
    CameraNumbers, Descriptor, Extra, Role, Step, Terms, Words, never_held, no_physics,
    usual_scan,
};

/// The largest camera tilt a fit may try (degrees): a tripod beside the table tilts its camera
/// up to 45 degrees from the vertical; beyond, a lab would not call the camera one that looks
/// down on the table.
pub const MAX_FITTED_TILT_DEG: f64 = 50.0;

pub struct Effect;
impl Terms for Effect {
    type Params = ();
}

fn words(w: &Words) -> String {
    let distance =
        if w.strength > 0.0 { format!("{:.0} mm", 1000.0 / w.strength) } else { "far".into() };
    let tilt = w.extras.first().map_or(String::new(), |&(t, s)| {
        format!(", tilted {} degrees from the vertical", super::pm(t, s))
    });
    let scale = match w.extras.get(1) {
        Some(&(c, s)) if c != 0.0 => format!(
            " The table's scale the tracker measured through the near camera is corrected by {}%.",
            super::pm(c, s)
        ),
        _ => String::new(),
    };
    format!(
        "The mismatch depends on where the ring is in the image and on how high its marks are: a camera at a finite distance magnifies what is nearer to it, so the top edge's marks look farther from the image centre the higher the ring stands, and a tilted camera foreshortens one direction of the table. {:.0}% of the baseline's squared residual points along the radius from the image centre. The fitted camera sits {distance} from the table{tilt}; give `camera_distance_mm` and `camera_tilt_deg` in the header when they are known.{scale}",
        100.0 * w.radial_share
    )
}

/// The largest correction of a tracker's table scale a fit may try (percent): a tracker's
/// scale through a near camera is off by its distance's error, about a percent.
pub const MAX_SCALE_CORRECTION_PCT: f64 = 5.0;

fn write_scale(v: f64, _: &super::ApplyAt, _: &mut super::Effects, cam: &mut CameraNumbers) -> bool {
    cam.px_per_mm *= 1.0 + v / 100.0;
    true
}

/// Only where the scale is a tracker's estimate through a near camera (`scale_free`): a scale
/// the lab measured stays as it is.
fn scale_held(_: &super::Effects, cam: &CameraNumbers) -> bool {
    !cam.scale_free
}

fn write_tilt(v: f64, _: &super::ApplyAt, _: &mut super::Effects, cam: &mut CameraNumbers) -> bool {
    cam.tilt_rad = v.to_radians();
    true
}

pub const DESCRIPTOR: Descriptor = Descriptor {
    name: "camera_perspective",
    parameter: "inverse camera distance 1000 mm / D",
    what: "the camera's perspective: a pinhole at a finite distance, perhaps tilted, sees marks above the table magnified (a measurement effect)",
    role: Role::Camera,
    realistic: (1.25, 3.33),
    baseline: Some(0.0),
    apply: no_physics,
    camera: |s, cam| {
        if s < 0.0 {
            return false;
        }
        cam.distance_mm = (s > 0.0).then(|| 1000.0 / s);
        true
    },
    read: |_, cam| cam.distance_mm.map_or(0.0, |d| 1000.0 / d),
    extras: &[Extra {
        name: "camera tilt (deg)",
        json: Some("camera_tilt_deg"),
        start: 0.0,
        scan: &[],
        realistic: (0.0, 0.0),
        bounds: (-MAX_FITTED_TILT_DEG, MAX_FITTED_TILT_DEG),
        projected: false,
        step: Step::Fixed(1e-5),
        read: |_, cam| cam.tilt_rad.to_degrees(),
        write: write_tilt,
        held_at_zero: never_held,
    },
    Extra {
        name: "table scale correction (%)",
        json: Some("table_scale_correction_pct"),
        start: 0.0,
        scan: &[],
        realistic: (0.0, 0.0),
        bounds: (-MAX_SCALE_CORRECTION_PCT, MAX_SCALE_CORRECTION_PCT),
        projected: true,
        step: Step::Fixed(1e-4),
        // Relative to the camera it starts from, so a fit started from a corrected camera
        // starts at no correction.
        read: |_, _| 0.0,
        write: write_scale,
        held_at_zero: scale_held,
    }],
    scan: usual_scan,
    search: |_, _| (0.0, 10.0),
    blind: super::no_blind,
    words,
    plan: InPlan { header_camera: true, ..USUAL_IN_PLAN },
};
