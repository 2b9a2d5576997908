//! The fit's free global parameters and the model and camera they make.
//!
//! The drag coefficients are fitted as `ln C_i` (they are positive and span decades; a step
//! in `ln C` is a relative change), and so are the body's dimensions where they are free (the
//! diagnosis: a header's caliper readings are measurements too). An effect's strength and its
//! extra numbers (`physics::effects`, each effect's file) are fitted as they are, so that they
//! can start at, and come out as, zero; each effect's descriptor says what they set in the
//! physics or the camera.

use crate::physics::Model;
use crate::physics::effects::{self, ApplyAt, EffectKind, Role, Step};
use crate::recording::Camera;

/// One free global parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Free {
    /// Drag coefficient `C_{i+1}`.
    Drag(usize),
    /// The strength of an effect.
    Effect(EffectKind),
    /// The `i`th extra number of an effect (`Descriptor::extras`: a pinhole's tilt, the rim's
    /// share of Reynolds drag's speed, a slide in progress at the start), beside its strength.
    Extra(EffectKind, usize),
    /// A dimension of the body (model units): 0 the outer radius `R`, 1 the width `h`.
    Body(usize),
}

/// The largest camera tilt a fit may try (degrees).
pub use crate::physics::effects::camera_perspective::MAX_FITTED_TILT_DEG;

impl Free {
    pub fn name(&self) -> String {
        match self {
            Free::Drag(i) => format!("C{}", i + 1),
            Free::Effect(k) => format!("{k} strength"),
            Free::Extra(k, i) => k.descriptor().extras[*i].name.into(),
            Free::Body(0) => "R".into(),
            Free::Body(_) => "h".into(),
        }
    }

    /// An effect's strength followed by its extra numbers, as a fit frees them.
    pub fn of_effect(kind: EffectKind) -> impl Iterator<Item = Free> {
        let extras = kind.descriptor().extras.len();
        std::iter::once(Free::Effect(kind)).chain((0..extras).map(move |i| Free::Extra(kind, i)))
    }
}

/// The Reynolds numbers at a fit's start state, of the centre's speed and of the rim's: the
/// reference of `reynolds_drag`, so that its `C_i` are those at the start whichever speed
/// its law follows.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
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
                Free::Effect(_) | Free::Extra(..) => *v,
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
                Free::Effect(_) | Free::Extra(..) => *x,
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
                Free::Effect(_) | Free::Extra(..) => 1.0,
            })
            .collect()
    }

    /// The values of the free parameters in the base model and camera.
    pub fn initial_values(&self) -> Vec<f64> {
        let (effects, camera) = (&self.base.effects, &self.camera.numbers());
        self.free
            .iter()
            .map(|f| match f {
                Free::Drag(i) => self.base.c_drag[*i],
                Free::Effect(k) => (k.descriptor().read)(effects, camera),
                Free::Extra(k, i) => (k.descriptor().extras[*i].read)(effects, camera),
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
        let at =
            ApplyAt { r: model.body.r, re_centre: self.re_start.centre, re_rim: self.re_start.rim };
        let mut numbers = camera.numbers();
        for (f, &v) in self.free.iter().zip(&values) {
            match *f {
                Free::Drag(i) => model.c_drag[i] = v,
                Free::Effect(kind) => {
                    if self.out_of_range(kind, v) {
                        return None;
                    }
                    let d = kind.descriptor();
                    match d.role {
                        Role::Physical => {
                            effects::apply_at(kind, v, &at, &mut model.effects).ok()?;
                        }
                        Role::Camera => {
                            if !(d.camera)(v, &mut numbers) {
                                return None;
                            }
                        }
                        Role::Nothing => {}
                    }
                }
                // After the strength (its `Free` comes first).
                Free::Extra(kind, i) => {
                    let x = &kind.descriptor().extras[i];
                    if !(x.bounds.0..=x.bounds.1).contains(&v)
                        || !(x.write)(v, &at, &mut model.effects, &mut numbers)
                    {
                        return None;
                    }
                }
                Free::Body(_) => {}
            }
        }
        camera.set_numbers(&numbers);
        Some((model, camera))
    }

    /// Whether `f` is held where it starts (`Extra::held_at_zero`): in the fit's vector, but
    /// neither fitted, nor counted among the parameters, nor reported.
    pub fn is_held(&self, f: Free) -> bool {
        match f {
            Free::Extra(k, i) => {
                (k.descriptor().extras[i].held_at_zero)(&self.base.effects, &self.camera.numbers())
            }
            _ => false,
        }
    }

    /// The number of parameters fitted: those free and not held.
    pub fn fitted_count(&self) -> usize {
        self.free.iter().filter(|f| !self.is_held(**f)).count()
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
            Free::Extra(k, j) => {
                let extra = &k.descriptor().extras[j];
                match extra.step {
                    Step::Fixed(h) => h,
                    // Into the box from the nearer bound.
                    Step::IntoBox(h) => {
                        if x > 0.5 * (extra.bounds.0 + extra.bounds.1) {
                            -h
                        } else {
                            h
                        }
                    }
                }
            }
        }
    }

    /// Internal coordinates brought into the box of the bounded numbers (`Extra::projected`,
    /// as the rim's share of the Reynolds speed, 0 to 1): a least-squares step that would leave
    /// it stops at the bound, the rest of the step kept. The paper's law sits at a bound (share
    /// 0), so without this every step towards a law the share cannot make would be refused
    /// whole. A number the model holds at zero (`Extra::held_at_zero`: the slip velocity at a
    /// start held rolling) is a box of one point (its runs ignore it, and the least squares
    /// would move a number the residuals do not see by their rounding divided by the damping).
    pub fn project(&self, internal: &mut [f64]) {
        let numbers = self.camera.numbers();
        for (f, x) in self.free.iter().zip(internal.iter_mut()) {
            if let Free::Extra(k, j) = *f {
                let extra = &k.descriptor().extras[j];
                if (extra.held_at_zero)(&self.base.effects, &numbers) {
                    *x = 0.0;
                } else if extra.projected {
                    *x = x.clamp(extra.bounds.0, extra.bounds.1);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::{Effects, SlipStart, paper};

    fn slip_spec(start: SlipStart) -> ModelSpec {
        let effects = Effects { slip_start: start, ..Default::default() };
        let base = paper::ring_model(paper::C_RING).with_effects(effects).expect("valid");
        let mut free: Vec<Free> = (0..3).map(Free::Drag).collect();
        free.extend(Free::of_effect(EffectKind::Slip));
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
