//! Recordings with a concealed effect, for the proof of the diagnosis (its tests and
//! `ringlab diagnose-bench`): the paper's ring with a random start state and drag, one effect
//! at a random strength within its realistic range, filmed by `synth` with 0.5 px noise.
//! The recording carries nothing of how it was made (its header's extra keys are cleared).

use crate::config::{Case, load_preset};
use crate::physics::effects::EffectKind;
use crate::physics::{Initial, paper};
use crate::recording::rng::Rng;
use crate::recording::synth::{SynthError, SynthOptions, synthesize};
use crate::recording::Recording;
use std::f64::consts::PI;

/// What was concealed in a recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Concealed {
    pub effect: EffectKind,
    pub strength: f64,
    pub c: [f64; 3],
    pub initial: Initial,
    pub seed: u64,
}

/// Log-uniform in `[lo, hi]` by magnitude (the ranges span up to a decade; the sign kept).
fn log_uniform(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    if lo == hi {
        return lo;
    }
    let (a, b) = (lo.abs().min(hi.abs()), lo.abs().max(hi.abs()));
    let v = (a.ln() + rng.uniform() * (b.ln() - a.ln())).exp();
    if lo < 0.0 { -v } else { v }
}

/// The case and synth options of recording `seed` with `effect` concealed: start at an inner
/// turning point with `theta0` in [0.45, 0.65] rad, `|phi'0|` in [4, 5] of either sign,
/// `psi'0` in [-0.1, 0.1], any heading; each `C_i` the paper's within a factor 1.3; the
/// strength log-uniform over the effect's realistic range.
pub fn concealed_case(effect: EffectKind, seed: u64) -> Result<(Case, SynthOptions, Concealed), String> {
    let mut rng = Rng::new(seed.wrapping_mul(0x9e37_79b9).wrapping_add(effect as u64));
    let file = load_preset("paper-ring").map_err(|e| e.to_string())?;
    let mut case = file.build()?;
    let sign = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
    case.initial = Initial {
        phi: PI * (2.0 * rng.uniform() - 1.0),
        theta: 0.45 + 0.2 * rng.uniform(),
        psi: 0.0,
        theta_dot: 0.0,
        phi_dot: sign * (4.0 + rng.uniform()),
        psi_dot: 0.1 * (2.0 * rng.uniform() - 1.0),
        x_c: 0.0,
        y_c: 0.0,
    };
    case.model.c_drag = paper::C_RING.map(|c| c * (0.26 * (2.0 * rng.uniform() - 1.0)).exp());
    let (lo, hi) = effect.realistic_range();
    let strength = log_uniform(&mut rng, lo, hi);
    let opts = SynthOptions {
        noise_px: 0.5,
        effect: (effect != EffectKind::None).then_some((effect, strength)),
        seed: rng.next_u64(),
        ..SynthOptions::default()
    };
    let truth = Concealed { effect, strength, c: case.model.c_drag, initial: case.initial, seed };
    Ok((case, opts, truth))
}

/// Recording `seed` with `effect` concealed (see [`concealed_case`]).
pub fn concealed_recording(effect: EffectKind, seed: u64) -> Result<(Recording, Concealed), String> {
    let (case, opts, truth) = concealed_case(effect, seed)?;
    let s = synthesize(&case, &opts).map_err(|e: SynthError| e.to_string())?;
    let mut rec = s.recording;
    rec.header.extra.clear();
    Ok((rec, truth))
}
