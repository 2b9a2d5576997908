//! Recordings with a concealed effect, for the proof of the diagnosis (its tests and
//! `ringlab diagnose-bench`): the paper's ring with a random start state and drag, one effect
//! at a random strength within its realistic range, filmed by `synth` with 0.5 px noise.
//! The recording carries nothing of how it was made (its header's extra keys are cleared).

use crate::config::{Case, load_preset};
use crate::physics::effects::{ApplyAt, EffectKind, apply_with_extras};
use crate::physics::{Initial, SlipStart, paper};
use crate::recording::Recording;
use crate::recording::rng::Rng;
use crate::recording::synth::{SynthError, SynthOptions, synthesize};
use std::f64::consts::PI;

/// What was concealed in a recording.
#[derive(Clone, Debug, PartialEq)]
pub struct Concealed {
    pub effect: EffectKind,
    pub strength: f64,
    /// The effect's extra numbers drawn (empty: none drawn, see [`concealed_case`]).
    pub extras: Vec<f64>,
    pub c: [f64; 3],
    pub initial: Initial,
    pub seed: u64,
}

/// The extra numbers of `kind` where its file gives any a realistic range (uniform there; the
/// others at their start), none otherwise (no number drawn, so the recordings of the effects
/// without such numbers stay as they were).
fn draw_extras(kind: EffectKind, rng: &mut Rng) -> Vec<f64> {
    let extras = kind.descriptor().extras;
    if !extras.iter().any(|x| x.realistic.0 < x.realistic.1) {
        return Vec::new();
    }
    extras
        .iter()
        .map(|x| {
            let (lo, hi) = x.realistic;
            if lo < hi { lo + (hi - lo) * rng.uniform() } else { x.start }
        })
        .collect()
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
/// strength log-uniform over the effect's realistic range. Slip begins one way or the other
/// at even odds ([`SlipStart`]: these starts all need more friction than `mu F_N`), drawn
/// last so that the other draws do not depend on it.
pub fn concealed_case(
    effect: EffectKind,
    seed: u64,
) -> Result<(Case, SynthOptions, Concealed), String> {
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
    let mut opts = SynthOptions {
        noise_px: 0.5,
        effect: (effect != EffectKind::None).then_some((effect, strength)),
        seed: rng.next_u64(),
        ..SynthOptions::default()
    };
    if effect == EffectKind::Slip && rng.uniform() < 0.5 {
        case.model.effects.slip_start = SlipStart::HeldRolling;
    }
    // Drawn last, so that the recordings of the other effects stay as they were.
    opts.effect_extras = draw_extras(effect, &mut rng);
    let truth = Concealed {
        effect,
        strength,
        extras: opts.effect_extras.clone(),
        c: case.model.c_drag,
        initial: case.initial,
        seed,
    };
    Ok((case, opts, truth))
}

/// Recording `seed` with `effect` concealed (see [`concealed_case`]).
pub fn concealed_recording(
    effect: EffectKind,
    seed: u64,
) -> Result<(Recording, Concealed), String> {
    let (case, opts, truth) = concealed_case(effect, seed)?;
    let s = synthesize(&case, &opts).map_err(|e: SynthError| e.to_string())?;
    let mut rec = s.recording;
    rec.header.extra.clear();
    Ok((rec, truth))
}

/// A kind of concealed recording for the proof, and what a diagnosis should say of it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// One effect (or none), every candidate offered ([`concealed_case`]).
    Single(EffectKind),
    /// One effect (or none) and a tracker's glitches: 0.2% to 2% of the marks off by 10 to 60
    /// px, and one to four label swaps of one to three frames ([`spoil_tracking`]).
    Glitches(EffectKind),
    /// Two effects at once, each at a random strength in its realistic range.
    Pair(EffectKind, EffectKind),
    /// One effect whose candidate is not offered: the answer must be `unexplained`.
    Withheld(EffectKind),
    /// No effect, filmed by a pinhole camera (300 to 800 mm, tilted when `tilted`, up to 12
    /// degrees) that the header describes: the answer must be `none`.
    CameraKnown { tilted: bool },
}

impl Family {
    /// Its name in the bench's rows: `single:NAME`, `glitches:NAME`, `pair:A+B`,
    /// `withheld:NAME`, `camera-known:pinhole` or `camera-known:tilted`.
    pub fn name(&self) -> String {
        match self {
            Family::Single(k) => format!("single:{k}"),
            Family::Glitches(k) => format!("glitches:{k}"),
            Family::Pair(a, b) => format!("pair:{a}+{b}"),
            Family::Withheld(k) => format!("withheld:{k}"),
            Family::CameraKnown { tilted } => {
                format!("camera-known:{}", if *tilted { "tilted" } else { "pinhole" })
            }
        }
    }

    pub fn from_name(s: &str) -> Option<Family> {
        let (kind, rest) = s.trim().split_once(':')?;
        let effect = |n: &str| EffectKind::from_name(n);
        match kind {
            "single" => effect(rest).map(Family::Single),
            "glitches" => effect(rest).map(Family::Glitches),
            "withheld" => effect(rest).filter(|&k| k != EffectKind::None).map(Family::Withheld),
            "pair" => {
                let (a, b) = rest.split_once('+')?;
                let (a, b) = (effect(a)?, effect(b)?);
                (a != b && a != EffectKind::None && b != EffectKind::None)
                    .then_some(Family::Pair(a, b))
            }
            "camera-known" => match rest {
                "pinhole" => Some(Family::CameraKnown { tilted: false }),
                "tilted" => Some(Family::CameraKnown { tilted: true }),
                _ => None,
            },
            _ => None,
        }
    }

    /// The pairs the bench conceals: drags of two laws, a contact torque with a camera effect,
    /// a physical effect with the pinhole, a real camera (a lens and a tilted pinhole), a
    /// sliding ring filmed through a pinhole, and a sloping table filmed through one.
    pub const PAIRS: [(EffectKind, EffectKind); 6] = [
        (EffectKind::ReynoldsDrag, EffectKind::PivotFriction),
        (EffectKind::RollingFriction, EffectKind::CameraDistortion),
        (EffectKind::TranslationalDrag, EffectKind::CameraPerspective),
        (EffectKind::CameraDistortion, EffectKind::CameraPerspective),
        (EffectKind::Slip, EffectKind::CameraPerspective),
        (EffectKind::TableSlope, EffectKind::CameraPerspective),
    ];

    /// Every family of the bench.
    pub fn all() -> Vec<Family> {
        let mut v: Vec<Family> = EffectKind::ALL.iter().map(|&k| Family::Single(k)).collect();
        v.extend(EffectKind::ALL.iter().map(|&k| Family::Glitches(k)));
        v.extend(Family::PAIRS.iter().map(|&(a, b)| Family::Pair(a, b)));
        v.extend(
            EffectKind::ALL
                .iter()
                .filter(|&&k| k != EffectKind::None)
                .map(|&k| Family::Withheld(k)),
        );
        v.extend([Family::CameraKnown { tilted: false }, Family::CameraKnown { tilted: true }]);
        v
    }

    /// What the diagnosis should say: effect names (in any order), `none` or `unexplained`.
    pub fn expected(&self) -> Vec<&'static str> {
        match self {
            Family::Single(k) | Family::Glitches(k) => vec![k.name()],
            Family::Pair(a, b) => vec![a.name(), b.name()],
            Family::Withheld(_) => vec!["unexplained"],
            Family::CameraKnown { .. } => vec!["none"],
        }
    }

    /// The candidates to offer (all but a withheld one).
    pub fn candidates(&self) -> Vec<EffectKind> {
        EffectKind::ALL
            .iter()
            .copied()
            .filter(|&k| k != EffectKind::None && *self != Family::Withheld(k))
            .collect()
    }
}

/// Moves the path anywhere in the image (a camera's effects depend on where the ring is): the
/// start up to 5 mean radii (100 mm) across and 3.5 along from the image centre.
fn anywhere(case: &mut Case, rng: &mut Rng) {
    case.initial.x_c = 5.0 * (2.0 * rng.uniform() - 1.0);
    case.initial.y_c = 3.5 * (2.0 * rng.uniform() - 1.0);
}

/// A pinhole camera 300 to 800 mm from the table, tilted up to 12 degrees either way.
fn pinhole(opts: &mut SynthOptions, rng: &mut Rng, tilted: bool) {
    opts.camera_distance_mm = Some(300.0 + 500.0 * rng.uniform());
    opts.camera_tilt_deg = if tilted { 12.0 * (2.0 * rng.uniform() - 1.0) } else { 0.0 };
}

/// A tracker's glitches in `rec`: each tracked mark of the moving part off by 10 to 60 px in a
/// random direction with probability `share`, and `swaps` times marks 1 and 3 (or 2 and 4)
/// swapped for one to three frames. Returns how many positions it spoiled.
pub fn spoil_tracking(rec: &mut Recording, share: f64, swaps: usize, rng: &mut Rng) -> usize {
    let n = rec.frames.len();
    let mut spoiled = 0;
    for f in rec.frames.iter_mut() {
        for m in f.iter_mut().flatten() {
            if rng.uniform() < share {
                let (off, angle) = (10.0 + 50.0 * rng.uniform(), 2.0 * PI * rng.uniform());
                *m = [m[0] + off * angle.cos(), m[1] + off * angle.sin()];
                spoiled += 1;
            }
        }
    }
    for _ in 0..swaps {
        let (start, len) = (10 + rng.below(n.saturating_sub(80).max(1)), 1 + rng.below(3));
        let pair = if rng.uniform() < 0.5 { (0, 2) } else { (1, 3) };
        for f in rec.frames.iter_mut().skip(start).take(len) {
            f.swap(pair.0, pair.1);
            spoiled += 2;
        }
    }
    spoiled
}

/// Recording `seed` of `family`: the case of [`concealed_case`] for its (first) effect, with
/// what the family adds. The header tells nothing of the effects; it gives the camera only for
/// [`Family::CameraKnown`].
pub fn family_recording(family: Family, seed: u64) -> Result<Recording, String> {
    let first = match family {
        Family::Single(k) | Family::Glitches(k) | Family::Withheld(k) => k,
        Family::Pair(a, _) => a,
        Family::CameraKnown { .. } => EffectKind::None,
    };
    let (mut case, mut opts, _) = concealed_case(first, seed)?;
    let mut rng = Rng::new(seed.wrapping_mul(0x5851_f42d_4c95_7f2d) ^ 0xc0ffee);
    if first == EffectKind::CameraPerspective {
        opts.camera_tilt_deg = 12.0 * (2.0 * rng.uniform() - 1.0);
        anywhere(&mut case, &mut rng);
    }
    match family {
        Family::Pair(a, b) => {
            // The first as the case's physics (or the camera), the second as synth's effect.
            let (lo, hi) = b.realistic_range();
            let strength = log_uniform(&mut rng, lo, hi);
            if a.is_physical() {
                let start = crate::physics::Sample::new(&case.model, 0.0, &case.initial.to_state());
                let (_, s) = opts.effect.take().ok_or("a pair's first effect has no strength")?;
                let at = ApplyAt::new(case.model.body.r, start.reynolds);
                let mut numbers = opts.camera().numbers();
                let extras = std::mem::take(&mut opts.effect_extras);
                apply_with_extras(a, s, &extras, &at, &mut case.model.effects, &mut numbers)
                    .map_err(|e| e.to_string())?;
            }
            if b == EffectKind::CameraPerspective {
                anywhere(&mut case, &mut rng);
                if a.is_camera() {
                    // A real camera: tilted as the single pinhole's is (drawn after the rest,
                    // so the other pairs' recordings stay as they were).
                    opts.camera_tilt_deg = 12.0 * (2.0 * rng.uniform() - 1.0);
                }
            }
            // Drawn after the rest, so the other pairs' recordings stay as they were.
            opts.effect_extras = draw_extras(b, &mut rng);
            if a.is_physical() {
                opts.effect = Some((b, strength));
            } else if let Some((_, s)) = opts.effect.take() {
                // A camera effect first: it goes to the camera, the second to the physics.
                let mut numbers = opts.camera().numbers();
                (a.descriptor().camera)(s, &mut numbers);
                opts.lens_k1 = numbers.k1;
                opts.camera_distance_mm = numbers.distance_mm;
                opts.effect = Some((b, strength));
            }
        }
        Family::CameraKnown { tilted } => {
            pinhole(&mut opts, &mut rng, tilted);
            opts.camera_in_header = true;
            anywhere(&mut case, &mut rng);
        }
        _ => {}
    }
    let mut rec = synthesize(&case, &opts).map_err(|e: SynthError| e.to_string())?.recording;
    if let Family::Glitches(_) = family {
        let share = 0.002 * (10f64).powf(rng.uniform());
        let swaps = 1 + rng.below(4);
        spoil_tracking(&mut rec, share, swaps, &mut rng);
    }
    rec.header.extra.clear();
    Ok(rec)
}
