//! The fit's free global parameters and the model and camera they make.
//!
//! The drag coefficients are fitted as `ln C_i` (they are positive and span decades; a step
//! in `ln C` is a relative change), and so are the body's dimensions where they are free (the
//! diagnosis: a header's caliper readings are measurements too). An effect's strength
//! (`physics::effects`) is fitted as it is, so that it can start at, and come out as, zero;
//! `camera_distortion` sets the camera's `k1`, `camera_perspective` its distance (strength
//! `1000 mm / D`, 0 orthographic) with the tilt a number of its own, every other effect the
//! physics.

use crate::physics::effects::{self, EffectKind};
use crate::physics::{Model, SlipStart};
use crate::recording::Camera;

/// One free global parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Free {
    /// Drag coefficient `C_{i+1}`.
    Drag(usize),
    /// The strength of an effect.
    Effect(EffectKind),
    /// A dimension of the body (model units): 0 the outer radius `R`, 1 the width `h`.
    Body(usize),
    /// The camera's tilt from the vertical (degrees), beside `camera_perspective`'s distance.
    CameraTilt,
    /// The rim's share of the speed that sets `reynolds_drag`'s Reynolds number (0 to 1,
    /// `ReynoldsDrag::rim_share`), beside its exponent.
    ReynoldsRimShare,
    /// The slip velocity at the fit's start (model units), 0 along the heading and 1 across
    /// it, beside `slip`'s `mu` (`Effects::slip_start_velocity`): a slide in progress where
    /// the recording begins.
    SlipStartVelocity(usize),
}

/// The largest camera tilt a fit may try (degrees): beyond, a lab would not call the camera
/// one that looks down on the table.
pub const MAX_FITTED_TILT_DEG: f64 = 30.0;

impl Free {
    pub fn name(&self) -> String {
        match self {
            Free::Drag(i) => format!("C{}", i + 1),
            Free::Effect(k) => format!("{k} strength"),
            Free::Body(0) => "R".into(),
            Free::Body(_) => "h".into(),
            Free::CameraTilt => "camera tilt (deg)".into(),
            Free::ReynoldsRimShare => "reynolds_drag rim share".into(),
            Free::SlipStartVelocity(0) => "slip velocity at the start, along".into(),
            Free::SlipStartVelocity(_) => "slip velocity at the start, across".into(),
        }
    }
}

/// The Reynolds numbers at a fit's start state, of the centre's speed and of the rim's: the
/// reference of `reynolds_drag`, so that its `C_i` are those at the start whichever speed
/// its law follows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StartReynolds {
    pub centre: f64,
    pub rim: f64,
}

impl StartReynolds {
    /// At the start state `y` of `model`'s body.
    pub fn of(model: &Model, y: &crate::physics::StateVec) -> StartReynolds {
        let w = (y[3] * y[3] + y[4] * y[4] + y[5] * y[5]).sqrt();
        StartReynolds {
            centre: crate::physics::Sample::new(model, 0.0, y).reynolds,
            rim: model.reynolds(w * model.body.r),
        }
    }

    /// Where the Reynolds number's speed is the rim's by `rim_share` (`ReynoldsDrag`).
    pub fn blended(&self, rim_share: f64) -> f64 {
        let (c, r) = (self.centre * self.centre, self.rim * self.rim);
        (c + rim_share * (r - c)).max(0.0).sqrt()
    }
}

/// The base model and camera and which of their parameters are free.
#[derive(Clone, Debug)]
pub struct ModelSpec {
    /// Body, gravity, air, and the starting drag coefficients (model units).
    pub base: Model,
    pub camera: Camera,
    pub free: Vec<Free>,
    /// Reynolds numbers at the start (the reference of `reynolds_drag`).
    pub re_start: StartReynolds,
    /// Where each effect's strength may go (an effect not listed: wherever it allows).
    pub strength_ranges: Vec<(EffectKind, (f64, f64))>,
}

impl ModelSpec {
    /// Whether `v` lies outside the range given for `kind`'s strength.
    fn out_of_range(&self, kind: EffectKind, v: f64) -> bool {
        self.strength_ranges.iter().any(|&(k, (lo, hi))| k == kind && !(lo..=hi).contains(&v))
    }

    /// Internal coordinates of parameter values.
    pub fn to_internal(&self, values: &[f64]) -> Vec<f64> {
        self.free
            .iter()
            .zip(values)
            .map(|(f, v)| match f {
                Free::Drag(_) | Free::Body(_) => v.max(1e-12).ln(),
                Free::Effect(_)
                | Free::CameraTilt
                | Free::ReynoldsRimShare
                | Free::SlipStartVelocity(_) => *v,
            })
            .collect()
    }

    /// Parameter values of internal coordinates.
    pub fn to_values(&self, internal: &[f64]) -> Vec<f64> {
        self.free
            .iter()
            .zip(internal)
            .map(|(f, x)| match f {
                Free::Drag(_) | Free::Body(_) => x.exp(),
                Free::Effect(_)
                | Free::CameraTilt
                | Free::ReynoldsRimShare
                | Free::SlipStartVelocity(_) => *x,
            })
            .collect()
    }

    /// Derivative of a value by its internal coordinate (for the uncertainties).
    pub fn value_per_internal(&self, internal: &[f64]) -> Vec<f64> {
        self.free
            .iter()
            .zip(internal)
            .map(|(f, x)| match f {
                Free::Drag(_) | Free::Body(_) => x.exp(),
                Free::Effect(_)
                | Free::CameraTilt
                | Free::ReynoldsRimShare
                | Free::SlipStartVelocity(_) => 1.0,
            })
            .collect()
    }

    /// The values of the free parameters in the base model and camera.
    pub fn initial_values(&self) -> Vec<f64> {
        self.free
            .iter()
            .map(|f| match f {
                Free::Drag(i) => self.base.c_drag[*i],
                Free::Effect(EffectKind::CameraDistortion) => self.camera.k1,
                Free::Effect(EffectKind::CameraPerspective) => {
                    self.camera.distance_mm.map_or(0.0, |d| 1000.0 / d)
                }
                Free::Effect(_) => 0.0,
                Free::CameraTilt => self.camera.tilt_rad.to_degrees(),
                Free::ReynoldsRimShare => {
                    self.base.effects.reynolds_drag.map_or(0.0, |r| r.rim_share)
                }
                Free::SlipStartVelocity(i) => self.base.effects.slip_start_velocity[*i],
                Free::Body(0) => self.base.body.r,
                Free::Body(_) => self.base.body.h,
            })
            .collect()
    }

    /// Model and camera at internal coordinates; None outside their domain.
    pub fn build(&self, internal: &[f64]) -> Option<(Model, Camera)> {
        let mut model = self.base.clone();
        let mut camera = self.camera;
        let values = self.to_values(internal);
        if values.iter().any(|v| !v.is_finite()) {
            return None;
        }
        // The body first: an effect's strength may be relative to its size.
        let (mut r, mut h) = (model.body.r, model.body.h);
        let mut resized = false;
        for (f, &v) in self.free.iter().zip(&values) {
            match f {
                Free::Body(0) => (r, resized) = (v, true),
                Free::Body(_) => (h, resized) = (v, true),
                _ => {}
            }
        }
        if resized {
            let b = &model.body;
            // A ring keeps its wall; a disk is solid (w = R).
            let w = if b.shape == crate::physics::Shape::Disk { r } else { b.w };
            model.body = crate::physics::Body::new(b.shape, r, h, w).ok()?;
        }
        for (f, &v) in self.free.iter().zip(&values) {
            match f {
                Free::Drag(i) => model.c_drag[*i] = v,
                Free::Effect(EffectKind::CameraDistortion) => {
                    if v.abs() > 0.5 || self.out_of_range(EffectKind::CameraDistortion, v) {
                        return None;
                    }
                    camera.k1 = v;
                }
                Free::Effect(EffectKind::CameraPerspective) => {
                    if v < 0.0 || self.out_of_range(EffectKind::CameraPerspective, v) {
                        return None;
                    }
                    camera.distance_mm = (v > 0.0).then(|| 1000.0 / v);
                }
                Free::CameraTilt => {
                    if v.abs() > MAX_FITTED_TILT_DEG {
                        return None;
                    }
                    camera.tilt_rad = v.to_radians();
                }
                Free::Effect(kind) => {
                    if self.out_of_range(*kind, v) {
                        return None;
                    }
                    effects::apply(
                        *kind,
                        v,
                        model.body.r,
                        self.re_start.centre,
                        &mut model.effects,
                    )
                    .ok()?;
                }
                // After the exponent (its `Free` comes later): where that is zero the drag
                // has no Reynolds law for the share to shape.
                Free::ReynoldsRimShare => {
                    if !(0.0..=1.0).contains(&v) {
                        return None;
                    }
                    if let Some(r) = model.effects.reynolds_drag.as_mut() {
                        r.rim_share = v;
                        r.re_ref = self.re_start.blended(v).max(1e-9);
                    }
                }
                Free::SlipStartVelocity(i) => model.effects.slip_start_velocity[*i] = v,
                Free::Body(_) => {}
            }
        }
        Some((model, camera))
    }

    /// Whether the body's dimensions are free (the marks' circle then follows the body).
    pub fn body_free(&self) -> bool {
        self.free.iter().any(|f| matches!(f, Free::Body(_)))
    }

    /// Forward-difference step in internal coordinates.
    pub fn step(&self, i: usize, x: f64) -> f64 {
        match self.free[i] {
            Free::Drag(_) | Free::Body(_) => 1e-6,
            Free::Effect(_) => 1e-6 * x.abs().max(1e-3),
            Free::CameraTilt => 1e-5,
            Free::SlipStartVelocity(_) => 1e-6,
            // Into the box from either bound.
            Free::ReynoldsRimShare => {
                if x > 0.5 {
                    -1e-6
                } else {
                    1e-6
                }
            }
        }
    }

    /// Internal coordinates brought into the box of the bounded parameters (the rim's share
    /// of the Reynolds speed, 0 to 1): a least-squares step that would leave it stops at the
    /// bound, the rest of the step kept. The paper's law sits at a bound (share 0), so without
    /// this every step towards a law the share cannot make would be refused whole.
    ///
    /// A start held rolling has no slide in progress: there the slip velocity at the start is
    /// held at zero, a box of one point (its runs ignore it, and the least squares would move
    /// a number the residuals do not see by their rounding divided by the damping).
    pub fn project(&self, internal: &mut [f64]) {
        let held = self.base.effects.slip_start == SlipStart::HeldRolling;
        for (f, x) in self.free.iter().zip(internal.iter_mut()) {
            match f {
                Free::ReynoldsRimShare => *x = x.clamp(0.0, 1.0),
                Free::SlipStartVelocity(_) if held => *x = 0.0,
                _ => {}
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::{Effects, paper};

    fn slip_spec(start: SlipStart) -> ModelSpec {
        let effects = Effects { slip_start: start, ..Default::default() };
        let base = paper::ring_model(paper::C_RING).with_effects(effects).expect("valid");
        let mut free: Vec<Free> = (0..3).map(Free::Drag).collect();
        free.extend([Free::Effect(EffectKind::Slip)]);
        free.extend([0, 1].map(Free::SlipStartVelocity));
        ModelSpec {
            base,
            camera: Camera::centred(3.0, 1280.0, 1024.0),
            free,
            re_start: StartReynolds { centre: 1.0, rim: 1.0 },
            strength_ranges: Vec::new(),
        }
    }

    #[test]
    fn the_slip_velocity_at_the_start_is_a_number_of_the_model() {
        let spec = slip_spec(SlipStart::Cone);
        let g = spec.to_internal(&[0.03, 0.06, 0.08, 0.3, 0.02, -0.01]);
        let (model, _) = spec.build(&g).expect("valid");
        assert_eq!(model.effects.slip_mu, Some(0.3));
        assert_eq!(model.effects.slip_start_velocity, [0.02, -0.01]);
    }

    #[test]
    fn a_start_held_rolling_pins_the_slip_velocity_at_zero() {
        let values = [0.03, 0.06, 0.08, 0.3, 0.02, -0.01];
        let mut cone = slip_spec(SlipStart::Cone).to_internal(&values);
        let before = cone.clone();
        slip_spec(SlipStart::Cone).project(&mut cone);
        assert_eq!(cone, before, "a cone start leaves it free");
        let held_spec = slip_spec(SlipStart::HeldRolling);
        let mut held = held_spec.to_internal(&values);
        held_spec.project(&mut held);
        assert_eq!(held[4..], [0.0, 0.0]);
        assert_eq!(held[..4], before[..4], "the rest as it was");
    }
}
