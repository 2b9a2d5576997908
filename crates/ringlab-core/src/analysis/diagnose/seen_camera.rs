//! The camera the multiple-shooting segments see: the baseline's segments refitted with the
//! camera's distance, tilt and lens free.
//!
//! Segments re-anchored to the data every second or so absorb what a missing physical effect
//! does to the motion, but not what the camera does to each frame's marks: a pinhole magnifies
//! the marks above the table in every frame, whatever the motion. So the segments find the
//! camera apart from the physics, where a whole-run camera candidate lets the camera soak up
//! the physics it lacks (a pinhole 337 mm away beside translational drag fits alone as 378 mm
//! over the whole run, and the drag through that camera stays 3.4 noise levels off; the
//! segments find 337.0 mm). The camera found here is where the fits "through the camera"
//! (`again.rs`) start; the decision still rests on the whole-run misfits alone.

use super::options::DiagnoseError;
use super::rules::bic_per_parameter;
use super::whole::{WholeFit, search_range};
use crate::analysis::fit::lm::{self, LmError, LmOptions};
use crate::analysis::fit::shooting::Shooting;
use crate::analysis::fit::{FitResult, Free};
use crate::physics::effects::EffectKind;
use crate::recording::Camera;

/// A camera found by a fit: the camera effects it holds with their internal numbers (in the
/// order a fit through it frees them), and the camera they make.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FoundCamera {
    pub(crate) camera: Camera,
    pub(crate) numbers: Vec<(EffectKind, Vec<f64>)>,
}

impl FoundCamera {
    /// The camera effects of fit `w` with their internal numbers, in `w`'s order (its numbers
    /// are the drag, the body, then each effect's in the order `also`, `kind`).
    pub(crate) fn of(w: &WholeFit) -> FoundCamera {
        let kinds: Vec<EffectKind> = w.also.iter().map(|(k, _)| *k).chain([w.kind]).collect();
        let own: usize = kinds.iter().map(|k| k.free_count()).sum();
        let mut at = w.internal.len().saturating_sub(own);
        let mut numbers = Vec::new();
        for k in kinds {
            let n = k.free_count();
            if k.is_camera() && at + n <= w.internal.len() {
                numbers.push((k, w.internal[at..at + n].to_vec()));
            }
            at += n;
        }
        FoundCamera { camera: w.camera, numbers }
    }
}

/// The camera the baseline's segments (`base`, its problem `ms`) see, with `offered` camera effects free: `None`
/// where no camera effect is offered, the fit fails, or none of them is worth its numbers.
/// An effect is kept where its strength (the inverse distance, the lens's `k1`) lowers the
/// segments' BIC by `evidence`, judged by its squared z-score (the change in cost a linear fit
/// would give); the camera is the one with only those effects, at the values found with all
/// of them free.
pub(super) fn seen_camera(
    base: &FitResult,
    ms: &Shooting,
    offered: &[EffectKind],
    evidence: f64,
) -> Result<Option<FoundCamera>, DiagnoseError> {
    // The camera effects, the last listed first (the pinhole's numbers lead the fit's).
    let kinds: Vec<EffectKind> = EffectKind::ALL
        .into_iter()
        .rev()
        .filter(|k| k.is_camera() && offered.contains(k))
        .collect();
    if kinds.is_empty() {
        return Ok(None);
    }
    let mut sh = ms.clone();
    let mu_max = crate::physics::slip::painleve_mu_limit(&sh.spec.base);
    for &k in &kinds {
        sh.spec.free.extend(Free::of_effect(k));
        sh.spec.strength_ranges.push((k, search_range(k, mu_max)));
    }
    let global = sh.spec.to_internal(&sh.spec.initial_values());
    let locals: Vec<Vec<f64>> = base.segment_states.iter().map(|y| y.to_vec()).collect();
    let opts = LmOptions { max_iterations: 30, rel_tol: 1e-6, ..LmOptions::default() };
    let sol = match lm::solve(&sh, global, locals, &opts, &mut |_, _| {}, sh.cancel) {
        Ok(s) => s,
        Err(LmError::Cancelled) => return Err(DiagnoseError::Cancelled),
        Err(LmError::BadStart) => return Ok(None),
    };
    let params = sh.spec.fitted_count() + 8 * sol.local.len();
    let jac = sh.spec.value_per_internal(&sol.global);
    let values = sh.spec.to_values(&sol.global);
    let worth = bic_per_parameter(sol.residual_count) + evidence;
    let z2 = |i: usize| {
        let s = sol.global_sigma(i, params, &jac);
        if s.is_finite() && s > 0.0 { (values[i] / s).powi(2) } else { 0.0 }
    };
    let mut global = sol.global.clone();
    let mut numbers = Vec::new();
    for &k in &kinds {
        let at = |f: Free| sh.spec.free.iter().position(|g| *g == f);
        let Some(i) = at(Free::Effect(k)) else { continue };
        let mine: Vec<usize> = Free::of_effect(k).filter_map(at).collect();
        // The distance (or the lens) must be worth its number: a tilt alone is no pinhole,
        // and where the segments miss (a ring that slides) the tilt takes up some of it (a
        // sliding ring: the tilt 1.6 degrees at z^2 77, the distance 32 m at z^2 1.2).
        if z2(i) > worth {
            numbers.push((k, mine.iter().map(|&j| sol.global[j]).collect()));
        } else {
            for j in mine {
                global[j] = 0.0;
            }
        }
    }
    if numbers.is_empty() {
        return Ok(None);
    }
    let Some((_, camera)) = sh.spec.build(&global) else { return Ok(None) };
    Ok(Some(FoundCamera { camera, numbers }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::diagnose::DiagnoseOptions;
    use crate::analysis::diagnose::concealed::{Family, family_recording};
    use crate::analysis::fit::fit;
    use std::sync::atomic::AtomicBool;

    /// The camera the segments of the baseline's multiple-shooting fit see on the bench's
    /// recording `seed` of `family`.
    fn seen_on(family: &str, seed: u64) -> Option<FoundCamera> {
        let family = Family::from_name(family).expect("a bench family");
        let rec = family_recording(family, seed).expect("the recording is made");
        let opts = DiagnoseOptions::default();
        let cancel = AtomicBool::new(false);
        let base = fit(&rec, &opts.fit, &|_| {}, &cancel).expect("the baseline fits");
        let ms = base.shooting(&rec.frames, &cancel);
        seen_camera(&base, &ms, &opts.candidates, opts.evidence).expect("not cancelled")
    }

    fn distance_mm(found: &FoundCamera) -> f64 {
        found.camera.distance_mm.expect("a pinhole")
    }

    #[test]
    fn the_segments_see_a_pinhole_that_translational_drag_hides_from_the_whole_run() {
        // The bench drew a pinhole 336.9 mm away for this recording; the pinhole alone over
        // the whole run fits as 378 mm.
        let found = seen_on("pair:translational_drag+camera_perspective", 7).expect("a camera");
        assert_eq!(found.numbers.len(), 1, "{found:?}");
        assert_eq!(found.numbers[0].0, EffectKind::CameraPerspective);
        let d = distance_mm(&found);
        assert!((d / 336.89 - 1.0).abs() < 0.01, "{d} mm");
    }

    #[test]
    fn the_segments_see_a_lens_beside_a_tilted_pinhole() {
        // Drawn: 329.7 mm away, tilted, with a barrel lens.
        let found = seen_on("pair:camera_distortion+camera_perspective", 10).expect("a camera");
        assert_eq!(found.numbers.len(), 2, "{found:?}");
        let d = distance_mm(&found);
        assert!((d / 329.67 - 1.0).abs() < 0.02, "{d} mm");
        assert!(found.camera.k1 < 0.0, "{found:?}");
    }

    #[test]
    fn the_segments_see_no_camera_where_the_physics_alone_is_missing() {
        for (family, seed) in [("single:translational_drag", 1), ("single:slip", 2)] {
            let found = seen_on(family, seed);
            assert!(found.is_none(), "{family} seed {seed}: {found:?}");
        }
    }
}
