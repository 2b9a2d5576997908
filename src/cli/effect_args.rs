//! `--effect NAME --effect-strength X` (repeatable), with `--effect-extra X` for an effect's
//! numbers beyond its strength: the physics beyond the paper's model, by the names,
//! dimensionless strengths and extra numbers of `physics::effects`.

use anyhow::{Context, Result, bail};
use clap::Args;
use ringlab::config::Case;
use ringlab::physics::effects::{ApplyAt, apply_with_extras};
use ringlab::physics::slip::painleve_mu_limit;
use ringlab::physics::{EffectKind, Sample, SlipStart};
use ringlab::recording::Camera;

#[derive(Args, Debug, Clone, Default)]
pub struct EffectArgs {
    /// Add physics beyond the paper's model (repeatable): reynolds_drag, rolling_friction,
    /// pivot_friction, slip, translational_drag, table_slope (or none); each takes an
    /// --effect-strength, in the same order. `ringlab effects` lists them with their strengths,
    /// extra numbers and ranges
    #[arg(long = "effect", value_name = "NAME")]
    pub effect: Vec<String>,
    /// Strength of the --effect at the same position (dimensionless: the Reynolds exponent n,
    /// arms k/R, the friction coefficient mu, or k R)
    #[arg(long = "effect-strength", value_name = "X", allow_negative_numbers = true)]
    pub effect_strength: Vec<f64>,
    /// The effects' extra numbers beyond their strengths (repeatable), each effect's in turn in
    /// the order of --effect (table_slope's direction in degrees, ...); those not given stay
    /// where the effect starts them
    #[arg(long = "effect-extra", value_name = "X", allow_negative_numbers = true)]
    pub effect_extra: Vec<f64>,
    /// With --effect slip: how a start that needs more friction than mu F_N begins: cone
    /// (slides at once) or held (rolls on until it needs no more, as an event-driven hybrid
    /// simulator started rolling does)
    #[arg(long, value_enum, value_name = "HOW")]
    pub slip_start: Option<SlipStartArg>,
}

/// `--slip-start`: [`SlipStart`] on the command line.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlipStartArg {
    Cone,
    Held,
}

impl SlipStartArg {
    pub fn start(self) -> SlipStart {
        match self {
            SlipStartArg::Cone => SlipStart::Cone,
            SlipStartArg::Held => SlipStart::HeldRolling,
        }
    }
}

/// `--slip-start` checked against the effects asked for: it needs slip.
pub fn slip_start_for(arg: Option<SlipStartArg>, slip: bool) -> Result<Option<SlipStart>> {
    match arg {
        Some(_) if !slip => bail!("--slip-start needs --effect slip (it says how sliding begins)"),
        a => Ok(a.map(SlipStartArg::start)),
    }
}

fn known_names() -> String {
    EffectKind::ALL.iter().map(|k| k.name()).collect::<Vec<_>>().join(", ")
}

impl EffectArgs {
    /// The effects asked for, validated as names and paired with their strengths.
    pub fn effects(&self) -> Result<Vec<(EffectKind, f64)>> {
        let kinds = self
            .effect
            .iter()
            .map(|name| {
                EffectKind::from_name(name)
                    .with_context(|| format!("--effect '{name}' is not one of {}", known_names()))
            })
            .collect::<Result<Vec<_>>>()?;
        if kinds == [EffectKind::None] && self.effect_strength.is_empty() {
            return Ok(Vec::new());
        }
        if kinds.len() != self.effect_strength.len() {
            let missing = kinds.get(self.effect_strength.len()).copied();
            match missing {
                Some(k) => bail!(
                    "--effect {k} needs an --effect-strength X ({}); give one --effect-strength per --effect, in the same order",
                    k.parameter()
                ),
                None => bail!(
                    "{} --effect-strength values for {} --effect names; give one --effect-strength per --effect, in the same order",
                    self.effect_strength.len(),
                    kinds.len()
                ),
            }
        }
        let mut out: Vec<(EffectKind, f64)> = Vec::new();
        for (&kind, &x) in kinds.iter().zip(&self.effect_strength) {
            if out.iter().any(|(k, _)| *k == kind) {
                bail!("--effect {kind} is given twice");
            }
            if !x.is_finite() {
                bail!("--effect-strength {x} for {kind}: must be a finite number");
            }
            if kind != EffectKind::None {
                out.push((kind, x));
            }
        }
        Ok(out)
    }

    /// Switches the effects on in `case` (the physical ones; `camera_distortion` is refused:
    /// it belongs to a recording, not to the motion).
    pub fn apply_to(&self, case: &mut Case) -> Result<Vec<(EffectKind, f64)>> {
        let effects = self.effects()?;
        let slip = effects.iter().any(|(k, _)| *k == EffectKind::Slip);
        if let Some(start) = slip_start_for(self.slip_start, slip)? {
            case.model.effects.slip_start = start;
        }
        let start = Sample::new(&case.model, 0.0, &case.initial.to_state());
        let at = ApplyAt::new(case.model.body.r, start.reynolds);
        // No camera here: the physical effects' extras leave it alone.
        let mut camera = Camera::centred(1.0, 1.0, 1.0).numbers();
        let mut extras = self.effect_extra.iter().copied();
        for &(kind, x) in &effects {
            if kind.is_camera() {
                bail!(
                    "--effect {kind} changes the camera, not the motion: give it to `ringlab synth`"
                );
            }
            let own: Vec<f64> = extras.by_ref().take(kind.descriptor().extras.len()).collect();
            let mut e = case.model.effects;
            apply_with_extras(kind, x, &own, &at, &mut e, &mut camera).with_context(|| {
                format!("--effect-strength {x} for {kind} ({})", kind.parameter())
            })?;
            let mut model = case.model.clone();
            model.effects = e;
            if let Err(err) = model.check_effects() {
                if kind == EffectKind::Slip {
                    bail!(
                        "--effect-strength {x} for slip: {err}; for this body mu must stay below {:.3}",
                        painleve_mu_limit(&model)
                    );
                }
                bail!("--effect-strength {x} for {kind}: {err}");
            }
            case.model = model;
        }
        let left = extras.count();
        if left > 0 {
            bail!(
                "{left} --effect-extra values beyond the extra numbers of the effects given (`ringlab effects` lists each effect's)"
            );
        }
        Ok(effects)
    }
}
