//! `table_slope`: a table that is not level. Its normal is tilted from the vertical by a small
//! angle `alpha` toward a direction `beta` (degrees from the table's `+X` axis, turning toward
//! `+Y`): gravity then has a part `g sin(alpha)` along the table, toward `beta` (where the
//! table falls), and its part along the normal is `g cos(alpha)`. Strength: `alpha` in degrees;
//! the direction a second fitted number.
//!
//! Why: a lab table levelled by eye or with a bench level is off by a tenth of a degree or so,
//! and a ring that rolls for seconds drifts downhill by much more than a tracker's noise.
//! Realistic `alpha` in [0.05, 0.5] degrees. The force is that of gravity's tilt on the centre
//! of mass (`Terms::force_at_centre`), the same for the rolling and the sliding contact; the
//! camera still looks along the table's normal.

use super::{USUAL_IN_PLAN, 
    ApplyAt, At, CameraNumbers, Descriptor, Effects, Extra, Role, Step, Terms, Words, from_zero,
    never_held, no_camera, non_negative, usual_scan, usual_search,
};
use crate::physics::body::{ParamError, check_finite};
use crate::physics::trig::sin_cos;
use nalgebra::Vector3;

/// The tilt of the table's normal from the vertical (rad) and the direction toward which the
/// table falls (rad from the table's `+X` axis, turning toward `+Y`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TableSlope {
    pub angle: f64,
    pub direction: f64,
}

pub struct Effect;
impl Terms for Effect {
    type Params = Option<TableSlope>;
    #[inline]
    fn active(p: &Option<TableSlope>) -> bool {
        p.is_some()
    }
    /// `g (sin(alpha) d + (1 - cos(alpha)) Z)`: gravity tilted, less the model's `-g Z`; `d`
    /// the direction the table falls, in the frame (`e1 = (cos phi, sin phi)`, `e2` and `e3`
    /// turned from the horizontal by `theta`).
    #[inline]
    fn force_at_centre(p: &Option<TableSlope>, at: &At) -> Option<Vector3<f64>> {
        let t = p.as_ref()?;
        let (sa, ca) = sin_cos(t.angle);
        let (sb, cb) = sin_cos(t.direction);
        let ((sp, cp), (st, ct)) = (at.heading, at.theta);
        let along_e1 = cb * cp + sb * sp;
        let along_e2h = -cb * sp + sb * cp;
        let d = Vector3::new(along_e1, along_e2h * ct, -along_e2h * st);
        Some(at.g * (sa * d + (1.0 - ca) * at.z))
    }
    fn validate(p: &Option<TableSlope>) -> Result<(), ParamError> {
        let Some(t) = p else { return Ok(()) };
        check_finite("table_slope angle", t.angle)?;
        check_finite("table_slope direction", t.direction)?;
        if !(0.0..0.2).contains(&t.angle) {
            return Err(ParamError {
                name: "table_slope angle",
                value: t.angle.to_degrees(),
                reason: "must lie in [0, 11.5) degrees (a table, not a ramp)",
            });
        }
        Ok(())
    }
}

fn apply(s: f64, _: &ApplyAt, e: &mut Effects) -> Result<(), ParamError> {
    let direction = e.table_slope.map_or(0.0, |t| t.direction);
    e.table_slope =
        (non_negative(s)? != 0.0).then(|| TableSlope { angle: s.to_radians(), direction });
    Ok(())
}

fn write_direction(v: f64, _: &ApplyAt, e: &mut Effects, _: &mut CameraNumbers) -> bool {
    if let Some(t) = e.table_slope.as_mut() {
        t.direction = v.to_radians();
    }
    true
}

fn words(w: &Words) -> String {
    let (beta, sigma) = w.extras.first().copied().unwrap_or((0.0, f64::INFINITY));
    let spread = if sigma.is_finite() { format!(" +- {}", super::sig(sigma)) } else { String::new() };
    format!(
        "The table is not level: it falls {} degrees toward {:.0}{spread} degrees from the table's +X axis (turning toward +Y). Gravity's part along the table pulls the ring downhill all the time, so its path drifts the same way through every cycloid, which no drag or friction (all of them against the motion) can imitate.{}{}",
        super::pm(w.strength, w.strength_sigma),
        beta.rem_euclid(360.0),
        w.late,
        w.end
    )
}

pub const DESCRIPTOR: Descriptor = Descriptor {
    name: "table_slope",
    parameter: "tilt of the table from level (degrees)",
    what: "a table that is not level: gravity pulls the ring along it, toward where it falls",
    role: Role::Physical,
    realistic: (0.05, 0.5),
    baseline: Some(0.0),
    apply,
    camera: no_camera,
    read: from_zero,
    extras: &[Extra {
        name: "table_slope direction (deg)",
        json: Some("table_slope_direction_deg"),
        start: 0.0,
        scan: &[0.0, 90.0, 180.0, 270.0],
        realistic: (0.0, 360.0),
        bounds: (-1080.0, 1080.0),
        projected: false,
        step: Step::Fixed(1e-4),
        read: |e, _| e.table_slope.map_or(0.0, |t| t.direction.to_degrees()),
        write: write_direction,
        held_at_zero: never_held,
    }],
    scan: usual_scan,
    search: usual_search,
    blind: super::no_blind,
    words,
    plan: USUAL_IN_PLAN,
};
