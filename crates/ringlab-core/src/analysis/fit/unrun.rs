//! Derivative columns that need no run. A global whose step leaves the model that segment `s`
//! runs as it is (a camera's number, a number held at zero, a slide at the recording's start
//! for any later segment) moves only how the run is seen: its column is the point's run seen
//! through the stepped camera. The same column as a run would give, without the run.

use super::shooting::{Shooting, segment_model};
use crate::physics::{Model, StateVec};
use crate::recording::Camera;

impl Shooting<'_> {
    /// The columns of segment `s` at `global` (`model`, `camera` built from it) that need no
    /// run, by
    /// their global's index, from `seen` (each frame's top centre and state of the run at the
    /// point that the other columns are differenced against). None where a stepped global
    /// leaves the model's domain, as its run would have failed.
    pub(super) fn unrun_columns(
        &self,
        s: usize,
        global: &[f64],
        model: &Model,
        camera: &Camera,
        seen: &[([f64; 2], StateVec)],
    ) -> Option<Vec<(usize, Vec<f64>)>> {
        let runs = segment_model(model, s);
        let geometry = self.geometry_of(model);
        let mut base: Option<Vec<f64>> = None;
        let mut out = Vec::new();
        for i in 0..global.len() {
            let mut stepped = global.to_vec();
            let h = self.spec.step(i, stepped[i]);
            stepped[i] += h;
            let (m, stepped_camera) = self.spec.build(&stepped)?;
            if *segment_model(&m, s) != *runs {
                continue;
            }
            let base = base.get_or_insert_with(|| {
                self.residuals_of(s, &self.seen_through(&geometry, camera, seen))
            });
            let moved = self.residuals_of(s, &self.seen_through(&geometry, &stepped_camera, seen));
            out.push((i, moved.iter().zip(base.iter()).map(|(a, b)| (a - b) / h).collect()));
        }
        Some(out)
    }
}

#[cfg(test)]
mod tests {
    use super::super::last_runs::LastRuns;
    use super::super::lm::BlockProblem;
    use super::super::params::{Free, ModelSpec, StartReynolds};
    use super::super::shooting::{NEVER_CANCELLED, Shooting, WorkBudget};
    use crate::physics::{EffectKind, RunOptions, paper};
    use crate::recording::marks::{MarkGeometry, MarkOrder};
    use crate::recording::{Camera, FrameMarks};
    use std::sync::Arc;

    /// The paper's ring through a near pinhole, its drag and the camera's numbers free.
    fn through_a_pinhole(observed: &[FrameMarks]) -> Shooting<'_> {
        let base = paper::ring_model(paper::C_RING);
        let units = paper::units();
        let mut free: Vec<Free> = (0..3).map(Free::Drag).collect();
        free.extend(Free::of_effect(EffectKind::CameraPerspective));
        let mut camera = Camera::centred(3.0, 1280.0, 1024.0);
        camera.set_numbers(&crate::physics::effects::CameraNumbers {
            distance_mm: Some(400.0),
            ..camera.numbers()
        });
        Shooting {
            observed,
            segments: vec![0..40, 40..80],
            dt: (1.0 / 300.0) / units.time_s,
            geometry: MarkGeometry::of_body(&base.body, MarkOrder::Forward),
            spec: ModelSpec {
                base,
                camera,
                free,
                re_start: StartReynolds { centre: 1.0, rim: 1.0 },
                strength_ranges: Vec::new(),
            },
            run: RunOptions::default(),
            length_mm: units.length_mm,
            budget: Some(Arc::new(WorkBudget::new(u64::MAX))),
            last_runs: LastRuns::default(),
            cancel: &NEVER_CANCELLED,
        }
    }

    #[test]
    fn a_cameras_columns_are_the_runs_seen_again_and_cost_what_their_runs_did() {
        let observed = vec![[Some([0.0, 0.0]); 4]; 80];
        let p = through_a_pinhole(&observed);
        let global = p.spec.to_internal(&p.spec.initial_values());
        let y0 = paper::initial().to_state();
        for cheap in [false, true] {
            p.residuals(0, &global, &y0).expect("the point runs");
            let at = p.at_point(0, &global, &y0, cheap).expect("the point runs");
            let given: Vec<usize> = at.unrun.iter().map(|(i, _)| *i).collect();
            // The distance, the tilt and the table's scale: not the drag.
            assert_eq!(given, [3, 4, 5], "cheap {cheap}");
            let base = at
                .column_base
                .clone()
                .unwrap_or_else(|| p.residuals(0, &global, &y0).expect("the point runs"));
            for (i, col) in &at.unrun {
                let mut stepped = global.clone();
                let h = p.global_step(*i, stepped[*i]);
                stepped[*i] += h;
                let run = p.column_residuals(0, &stepped, &y0, &at).expect("the column runs");
                let worst = run
                    .iter()
                    .zip(&base)
                    .zip(col)
                    .map(|((r, b), c)| ((r - b) / h - c).abs() / c.abs().max(1.0))
                    .fold(0.0, f64::max);
                assert!(worst < 1e-6, "column {i}, cheap {cheap}: {worst:e}");
            }
            // The work each would have cost: the point's run's.
            let budget = p.budget.as_ref().expect("a budget");
            let before = budget.used();
            p.column_residuals(0, &global, &y0, &at).expect("the column runs");
            let one = budget.used() - before;
            assert_eq!(at.deferred_work, 3 * one, "cheap {cheap}");
        }
    }
}
