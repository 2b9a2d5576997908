//! The diagnosis in plain words: what was left out, how the mismatch's signature points to
//! it, and the fitted parameter; numbers from the diagnosis itself.

use super::result::{Diagnosis, ModelFit, Signature};
use crate::physics::effects::EffectKind;
use std::fmt::Write;

/// What each effect is, in a lab's words.
pub fn describe(kind: EffectKind) -> &'static str {
    match kind {
        EffectKind::None => "nothing: the paper's model (pure rolling, quadratic air drag of eq. 5)",
        EffectKind::ReynoldsDrag => "drag coefficients that grow as the ring slows down (C_i rising as the Reynolds number falls)",
        EffectKind::RollingFriction => "rolling friction: a torque proportional to the normal force that resists the rolling",
        EffectKind::PivotFriction => "pivot friction: a torque proportional to the normal force that resists spinning about the vertical",
        EffectKind::Slip => "slipping at the contact: the ring slides where rolling would need more friction than the table gives",
        EffectKind::TranslationalDrag => "air drag on the travel of the ring (on its centre of mass), not only on its rotation",
        EffectKind::CameraDistortion => "the camera's radial lens distortion (a measurement effect; the physics is unchanged)",
    }
}

fn pm(v: f64, s: f64) -> String {
    if s.is_finite() { format!("{} +- {}", sig(v), sig(s)) } else { format!("{} (uncertainty unknown)", sig(v)) }
}

/// Three significant digits, plain notation where readable.
pub fn sig(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let mag = v.abs().log10().floor() as i32;
    if (-4..6).contains(&mag) {
        format!("{:.*}", (2 - mag).max(0) as usize, v)
    } else {
        format!("{v:.2e}")
    }
}

fn end_clause(s: &Signature) -> String {
    match (s.end_data_s, s.end_before_s) {
        (Some(d), Some(b)) => format!(
            " The recording's motion ends at {d:.2} s, the baseline's at {b:.2} s{}.",
            s.end_after_s.map_or(String::new(), |a| format!(", the improved model's at {a:.2} s"))
        ),
        (Some(d), None) => format!(" The recording's motion ends at {d:.2} s; the baseline's runs on past the recording."),
        _ => String::new(),
    }
}

fn thirds(s: &Signature) -> String {
    let [a, b, c] = s.thirds_rms_px;
    format!("{a:.2}, {b:.2} and {c:.2} px rms in the first, middle and last third of the run")
}

/// Why the signature points to the named effect.
fn signature_words(kind: EffectKind, d: &Diagnosis) -> String {
    let s = &d.signature;
    let late = 100.0 * s.late_share;
    match kind {
        EffectKind::ReynoldsDrag => format!(
            "The signature is at the end of the run: {late:.0}% of the baseline's misfit beyond the noise lies in the last third ({}).{} Constant drag coefficients cannot both damp the early cycloids at the recorded rate and end the final spiral in time; coefficients that grow as the ring slows can. This is the paper's own explanation of its long-lived simulated spiral (section III: as Re decreases the drag coefficients increase); laminar skin friction suggests an exponent near 1/2.",
            thirds(s),
            end_clause(s)
        ),
        EffectKind::RollingFriction => format!(
            "The mismatch builds up along the run ({}).{} A rolling-resistance torque k F_N takes energy at a rate that does not fall with the square of the speed, as air drag does; fitted drag alone cannot match the decay of the fast start and of the slow end together.",
            thirds(s),
            end_clause(s)
        ),
        EffectKind::PivotFriction => format!(
            "The mismatch builds up along the run ({}).{} A torque k F_N against the spin about the table normal slows the precession and turns the heading of the path differently from the quadratic drag on the body's axes, which cannot imitate it.",
            thirds(s),
            end_clause(s)
        ),
        EffectKind::Slip => {
            let slides = if s.slides_s.is_empty() {
                "The improved model slides only briefly.".to_string()
            } else {
                let list: Vec<String> = s.slides_s.iter().take(6).map(|(a, b)| format!("{a:.3}-{b:.3} s")).collect();
                format!(
                    "The improved model slides {} time{} ({}{}), where rolling would need more friction than mu F_N: at the launch and at the cusps of the walk.",
                    s.slides_s.len(),
                    if s.slides_s.len() == 1 { "" } else { "s" },
                    list.join(", "),
                    if s.slides_s.len() > 6 { ", ..." } else { "" }
                )
            };
            format!(
                "The path is displaced rather than slowed ({}): each slide shifts it, and the baseline, which must roll, drifts from then on. {slides} The paper names slippage at cuspy turning points as a cause of its drift.",
                thirds(s)
            )
        }
        EffectKind::TranslationalDrag => format!(
            "The travel of the ring falls short of the baseline's while its rotation decays as fitted ({}).{} Air drag on the centre of mass slows the translation; the rotational drag of eq. 5 acts on the spin and cannot do that alone.",
            thirds(s),
            end_clause(s)
        ),
        EffectKind::CameraDistortion => format!(
            "The mismatch depends on where the ring is in the image rather than on when: {:.0}% of the baseline's squared residual points along the radius from the image centre (50% would mean no preference), and {:.0}% of the correction is radial. That is a lens's radial distortion (barrel for k1 < 0), the paper's 'image distortions'; the dynamics are unchanged.",
            100.0 * s.radial_share,
            100.0 * s.change_radial_share
        ),
        EffectKind::None => String::new(),
    }
}

fn fitted(f: &ModelFit) -> String {
    format!("C1 = {}, C2 = {}, C3 = {}", pm(f.c[0], f.c_sigma[0]), pm(f.c[1], f.c_sigma[1]), pm(f.c[2], f.c_sigma[2]))
}

/// The explanation of a finished diagnosis (everything but the explanation filled in).
pub fn explain(d: &Diagnosis) -> String {
    let mut out = String::new();
    let noise = format!(
        "{:.3} px{}",
        d.noise_px,
        if d.noise_from_marks { " (the recording's pixel noise, estimated from the marks)" } else { " (the baseline's segment misfit; the marks gave no noise estimate)" }
    );
    let runner_up = d.candidates.iter().find(|c| c.effect != d.left_out && c.effect != EffectKind::None);
    let where_ = match &d.mismatch {
        Some(m) => format!(
            "The baseline departs from the recording beyond its noise from {:.2} s to {:.2} s ({:.2} px rms there, {:.0}% of its misfit beyond the noise){}.",
            m.start_s,
            m.end_s,
            m.rms_px,
            100.0 * m.share,
            if d.windows.len() > 1 { format!("; {} windows in all", d.windows.len()) } else { String::new() }
        ),
        None => "The baseline does not depart from the recording beyond its noise in any window.".to_string(),
    };
    if d.left_out == EffectKind::None {
        let _ = write!(
            out,
            "Nothing was left out that this recording can show. The paper's model, fitted over the whole run from the first inner turning point, follows the marks to {:.3} px rms against a noise of {noise}. {where_}",
            d.before.rms_px
        );
        if let Some(c) = runner_up {
            let _ = write!(
                out,
                " No candidate lowers the misfit by more than its extra parameter costs: the best, {}, reaches {:.3} px (BIC {:+.1} against the baseline; {:.0} below is needed).",
                c.effect, c.rms_px, c.delta_score, d.evidence
            );
        }
        let _ = write!(out, " Fitted: {}.", fitted(&d.before));
        return out;
    }
    let kind = d.left_out;
    let ratio = d.before.rms_px / d.after.rms_px.max(1e-12);
    let _ = write!(out, "Left out: {}. ", describe(kind));
    let (value, sigma) = d.after.strength.unwrap_or((f64::NAN, f64::NAN));
    let _ = write!(
        out,
        "With it ({} = {}) the misfit over the whole run falls from {:.3} px to {:.3} px rms ({ratio:.1}x lower; noise {noise}).",
        kind.parameter(),
        pm(value, sigma),
        d.before.rms_px,
        d.after.rms_px
    );
    let delta = d.after.score - d.before.score;
    match runner_up {
        Some(c) => {
            let _ = write!(out, " Its BIC is {delta:.1} against the baseline; the next candidate, {}, reaches {:.3} px ({:+.1}).", c.effect, c.rms_px, c.delta_score);
        }
        None => {
            let _ = write!(out, " Its BIC is {delta:.1} against the baseline.");
        }
    }
    let _ = write!(out, " {where_} {}", signature_words(kind, d));
    if ratio < 2.0 {
        let _ = write!(out, " The improvement is modest: the effect is near what {:.2} px of noise lets a recording show.", d.noise_px);
    }
    let _ = write!(out, " Fitted with it: {}.", fitted(&d.after));
    out
}
