//! The diagnosis in plain words: what was left out, how the mismatch's signature points to
//! it, and the fitted parameter; numbers from the diagnosis itself.

use super::result::extras_of;
use super::result::{Candidate, Diagnosis, Finding, ModelFit, Partial, Signature};
use super::rules::{CONSISTENT_RATIO, MIN_EXCESS_CUT, MIN_EXPLAINED, explained_share};
use crate::physics::SlipStart;
use crate::physics::effects::{EffectKind, Words};
use std::fmt::Write;

/// What each effect is, in a lab's words.
pub fn describe(kind: EffectKind) -> &'static str {
    kind.descriptor().what
}

pub use crate::physics::effects::{pm, sig};

fn end_clause(s: &Signature) -> String {
    match (s.end_data_s, s.end_before_s) {
        (Some(d), Some(b)) => format!(
            " The recording's motion ends at {d:.2} s, the baseline's at {b:.2} s{}.",
            s.end_after_s.map_or(String::new(), |a| format!(", the improved model's at {a:.2} s"))
        ),
        (Some(d), None) => format!(
            " The recording's motion ends at {d:.2} s; the baseline's runs on past the recording."
        ),
        _ => String::new(),
    }
}

fn thirds(s: &Signature) -> String {
    let [a, b, c] = s.thirds_rms_px;
    format!("{a:.2}, {b:.2} and {c:.2} px rms in the first, middle and last third")
}

/// Where the baseline parts from the recording, in words.
fn departure_words(d: &Diagnosis) -> String {
    let s = &d.signature;
    match s.departure_s {
        Some(t) => format!(
            "Fitted to a growing stretch from the start, the baseline follows the recording within its noise up to {t:.2} s ({:.0}% of the run) and no further; fitted to the whole run it misses by {}.",
            100.0 * s.followed_share,
            thirds(s)
        ),
        None => format!("The baseline, fitted to the whole run, misses by {}.", thirds(s)),
    }
}

/// Why the signature points to the named effect (its descriptor's words).
fn signature_words(kind: EffectKind, d: &Diagnosis) -> String {
    let s = &d.signature;
    let (strength, strength_sigma) = if d.after.effect == kind {
        d.after.strength
    } else {
        d.after.also.iter().find(|(k, _)| *k == kind).map(|x| x.1)
    }
    .unwrap_or((f64::NAN, f64::INFINITY));
    let late = if s.late_share > 0.5 {
        format!(
            " {:.0}% of the whole-run misfit beyond the noise lies in the last third.",
            100.0 * s.late_share
        )
    } else {
        String::new()
    };
    let extras = extras_of(&d.after.extras, kind);
    let words = Words {
        strength,
        strength_sigma,
        extras: &extras,
        late: &late,
        end: &end_clause(s),
        radial_share: s.radial_share,
        change_radial_share: s.change_radial_share,
        r_mm: d.after.model.body.r * d.after.units.length_mm,
        slides_s: &s.slides_s,
        held_rolling: d.after.model.effects.slip_start == SlipStart::HeldRolling,
        start_s: d.after.start_s,
        slip_start_mm_s: d.after.slip_start_mm_s(),
    };
    (kind.descriptor().words)(&words)
}

/// The body's dimensions where they fit away from the header's (beyond 3 sigma and 0.5%).
fn body_words(d: &Diagnosis) -> String {
    let f = &d.after;
    let mut out = String::new();
    for (i, name) in ["outer radius", "width"].iter().enumerate() {
        let (v, s) = f.body_mm[i];
        let header = d.header_body_mm[i];
        if (v - header).abs() > (3.0 * s).max(0.005 * header) {
            let _ = write!(
                out,
                " The body's {name} fits as {v:.3} +- {s:.3} mm where the header says {header} mm: the header's value is off, or the marks do not sit where it implies."
            );
        }
    }
    out
}

fn fitted(f: &ModelFit) -> String {
    format!(
        "C1 = {}, C2 = {}, C3 = {}",
        pm(f.c[0], f.c_sigma[0]),
        pm(f.c[1], f.c_sigma[1]),
        pm(f.c[2], f.c_sigma[2])
    )
}

/// The noise in words.
fn noise_words(d: &Diagnosis) -> String {
    let source = if d.noise_from_marks {
        "the recording's pixel noise, estimated from each mark's track alone, or a film tracker's own estimate of its centres' error where larger"
    } else {
        "the baseline's segment misfit; the tracks gave no noise estimate"
    };
    let glitches = match d.glitches.len() {
        0 => String::new(),
        n => format!(
            "; {n} tracked position{} left out as the tracker's glitches",
            if n == 1 { "" } else { "s" }
        ),
    };
    let correlated = match &d.noise_correlation {
        None => String::new(),
        Some(c) => format!(
            "; the tracker's noise is correlated from frame to frame ({:.2} at one frame, died out by {} frames, in the baseline's residual and nothing longer), which the tracks read low as {:.3} px, so their reading is corrected for it",
            c.rho.get(1).copied().unwrap_or(0.0),
            c.range_frames,
            c.tracks_px
        ),
    };
    format!("{:.3} px ({source}{glitches}{correlated})", d.noise_px)
}

/// The consistency test, in words.
fn consistency_words(d: &Diagnosis) -> String {
    let ratio = d.before.rms_px / d.noise_px.max(1e-12);
    format!(
        "The baseline misses by {:.3} px rms over the coordinates kept, {ratio:.2} times the noise; it counts as consistent with the noise up to {CONSISTENT_RATIO} times (an excess over the noise of {:.3} px here, {:.3} px allowed).",
        d.before.rms_px,
        d.excess_px(d.before.rms_px),
        d.excess_px(CONSISTENT_RATIO * d.noise_px)
    )
}

/// The best candidate against the naming rules, in words.
fn runner_up_words(d: &Diagnosis, c: &super::result::Candidate) -> String {
    let share = explained_share(d.before.rms_px, c.rms_px, d.noise_px);
    if c.delta_score < -d.evidence {
        format!(
            " The best candidate, {}, earns its parameter by BIC ({:+.1} against the baseline) but reaches only {:.3} px: it explains {:.0}% of the squared misfit beyond the noise, and to be named an effect must explain at least {:.0}% and cut the excess {MIN_EXCESS_CUT} times or end within {CONSISTENT_RATIO} times the noise.",
            c.effect,
            c.delta_score,
            c.rms_px,
            100.0 * share,
            100.0 * MIN_EXPLAINED
        )
    } else {
        format!(
            " No candidate lowers the misfit by more than its extra parameter costs: the best, {}, reaches {:.3} px (BIC {:+.1} against the baseline; {:.0} below is needed).",
            c.effect, c.rms_px, c.delta_score, d.evidence
        )
    }
}

/// The explanation of a finished diagnosis (everything but the explanation filled in).
pub fn explain(d: &Diagnosis) -> String {
    let named = d.finding.named();
    let words = Common {
        noise: noise_words(d),
        runner_up: d
            .candidates
            .iter()
            .find(|c| !named.contains(&c.effect) && c.effect != EffectKind::None),
        where_: match &d.mismatch {
            Some(m) => {
                format!("Mismatch: {:.2} s to {:.2} s. {}", m.start_s, m.end_s, departure_words(d))
            }
            None => "The baseline follows the recording within its noise over the whole run."
                .to_string(),
        },
    };
    match &d.finding {
        Finding::Nothing => nothing_words(d, &words),
        Finding::Unexplained { partial } => unexplained_words(d, partial.as_ref(), &words),
        Finding::Named(named) => named_words(d, named, &words),
    }
}

/// What every finding's words use: the noise in words, the best candidate not named, and
/// where the baseline departs.
struct Common<'a> {
    noise: String,
    runner_up: Option<&'a Candidate>,
    where_: String,
}

/// The words for `Finding::Nothing`.
fn nothing_words(d: &Diagnosis, words: &Common) -> String {
    let Common { noise, runner_up, where_ } = words;
    let mut out = String::new();
    let _ = write!(
        out,
        "Nothing was left out that this recording can show. The paper's model, fitted over the whole run from the first inner turning point, follows the marks to {:.3} px rms against a noise of {noise}. {} {where_}",
        d.before.rms_px,
        consistency_words(d)
    );
    if let Some(c) = runner_up {
        out.push_str(&runner_up_words(d, c));
    }
    let _ = write!(out, " Fitted: {}.{}", fitted(&d.before), body_words(d));
    out
}

/// The words for `Finding::Unexplained`, with the best partial candidate where there is one.
fn unexplained_words(d: &Diagnosis, partial: Option<&Partial>, words: &Common) -> String {
    let Common { noise, runner_up, where_ } = words;
    let mut out = String::new();
    let _ = write!(
        out,
        "Something was left out that none of the candidates explains. The paper's model misses the recording by {:.3} px rms over the whole run against a noise of {noise}: an excess of {:.3} px beyond the noise. {} {where_} {}",
        d.before.rms_px,
        d.excess_px(d.before.rms_px),
        consistency_words(d),
        residual_words(d)
    );
    match partial {
        Some(p) => {
            let _ = write!(
                out,
                " The best partial candidate is {p}: it explains {:.0}% of the squared misfit beyond the noise and leaves an excess of {:.3} px ({:.1} times the noise), not enough to name it (at least {:.0}%, and the excess cut {MIN_EXCESS_CUT} times or within {CONSISTENT_RATIO} times the noise), so it is at most part of the answer: {p} with another law, or an effect not among the candidates that it imitates in part.",
                100.0 * p.share,
                d.excess_px(p.rms_px),
                d.excess_px(p.rms_px) / d.noise_px,
                100.0 * MIN_EXPLAINED
            );
        }
        None => out.push_str(" No candidate explains any of it."),
    }
    if let Some(c) = runner_up {
        out.push_str(&runner_up_words(d, c));
    }
    let _ = write!(
        out,
        " The start state and the body's radius and width were fitted with every model; what is missing is none of the effects tried (or not one of them alone). Fitted: {}.{}",
        fitted(&d.before),
        body_words(d)
    );
    out
}

/// The words for `Finding::Named`: the effects, their numbers, what they explain.
fn named_words(d: &Diagnosis, named: &[EffectKind], words: &Common) -> String {
    let Common { noise, runner_up, where_ } = words;
    let mut out = String::new();
    let kind = d.finding.first();
    let excess_before = d.excess_px(d.before.rms_px);
    let excess_after = d.excess_px(d.after.rms_px);
    let names: Vec<String> = named.iter().map(|k| describe(*k).to_string()).collect();
    let _ = write!(out, "Left out: {}. ", names.join("; and "));
    let (value, sigma) = d.after.strength.unwrap_or((f64::NAN, f64::NAN));
    let mut values: Vec<String> = d
        .after
        .also
        .iter()
        .map(|(k, (v, s))| format!("{} = {}", k.parameter(), pm(*v, *s)))
        .collect();
    values.push(format!("{} = {}", d.after.effect.parameter(), pm(value, sigma)));
    let _ = write!(
        out,
        "With {} ({}) the misfit over the whole run falls from {:.3} px to {:.3} px rms (noise {noise}); the excess over the noise from {excess_before:.3} px to {excess_after:.3} px.",
        if named.len() > 1 { "them" } else { "it" },
        values.join(", "),
        d.before.rms_px,
        d.after.rms_px
    );
    let delta = d.after.score - d.before.score;
    match runner_up {
        Some(c) => {
            let _ = write!(
                out,
                " Its BIC is {delta:.1} against the baseline; the next candidate, {}, reaches {:.3} px ({:+.1}).",
                c.effect, c.rms_px, c.delta_score
            );
        }
        None => {
            let _ = write!(out, " Its BIC is {delta:.1} against the baseline.");
        }
    }
    out.push_str(&share_words(d));
    let _ = write!(out, " {where_} {}", signature_words(kind, d));
    if d.after.rms_px > CONSISTENT_RATIO * d.noise_px {
        let _ = write!(
            out,
            " It leaves an excess of {excess_after:.3} px beyond the noise ({:.2} times the noise in all): the effect is there, but the model of it is not the whole story (another law of the same effect, or something more left out).",
            d.after.rms_px / d.noise_px.max(1e-12)
        );
    }
    let _ = write!(out, " Fitted with it: {}.{}", fitted(&d.after), body_words(d));
    out
}

/// Each named effect's share of the improvement, in words, where more than one is named (one
/// alone has all of it).
fn share_words(d: &Diagnosis) -> String {
    if d.shares.len() < 2 {
        return String::new();
    }
    let each: Vec<String> = d
        .shares
        .iter()
        .map(|s| {
            format!("{} {:.1}% ({:.3} px without it)", s.effect, 100.0 * s.share, s.rms_without_px)
        })
        .collect();
    format!(
        " Each effect's share of the improvement on the baseline, the part of it that comes back without that effect: {}; each is worth its numbers against the model without it, on the residuals that count as independent (their correlation in time counted).",
        each.join(", ")
    )
}

/// Where and how the baseline's residual departs, in words, for a finding no candidate names.
fn residual_words(d: &Diagnosis) -> String {
    let s = &d.signature;
    let radial = if s.radial_share > 0.65 {
        format!(
            " {:.0}% of its squared residual points along the radius from the image centre (50% is no preference): it depends on where the ring is in the image, as a camera's effects do.",
            100.0 * s.radial_share
        )
    } else if s.radial_share < 0.35 {
        format!(
            " Only {:.0}% of its squared residual is radial from the image centre: it is across the radius, as a turn of the path is.",
            100.0 * s.radial_share
        )
    } else {
        String::new()
    };
    let late = if s.late_share > 0.5 {
        format!(
            " {:.0}% of the misfit beyond the noise lies in the last third of the run, where the ring slows.",
            100.0 * s.late_share
        )
    } else {
        String::new()
    };
    format!("{late}{radial}{}", end_clause(s))
}
