//! The diagnosis on recordings ringlab did not make (`tests/data/independent/`, copied from the
//! project's shared data): another simulator's integrator and slip model, a pinhole camera, a
//! lens, a tracker's glitches, two effects at once, each with its `truth.json` entry. Each
//! must be named as the truth says (`none`: nothing), the noise estimated within 20% of the
//! true 0.5 px, and a named effect must cut the misfit beyond the noise at least 4x or to
//! below 0.15 noise.

mod common;
mod said;

fn check(name: &str) -> ringlab_core::analysis::diagnose::Diagnosis {
    said::check("independent", name)
}

/// The other simulator starts its hybrid contact rolling beyond the friction cone and slides
/// only from where the demand crosses `mu F_N`: the slip candidate's held start finds it.
#[test]
fn slip_of_another_simulator_is_named() {
    let d = check("slip-hybrid");
    // "Before" is the baseline at its best: refitted from slip's solution, one fit runs out of
    // its Jacobians well short of it, and only fitted again from where it stopped does it
    // settle (docs/speed.md, "the baseline's before", has the figures).
    assert!(
        d.before.rms_px < 8.75,
        "before {} px: the baseline short of its best",
        d.before.rms_px
    );
    let (mu, _) = d.after.strength.expect("a fitted mu");
    assert!((mu - 0.40).abs() < 0.02, "mu {mu}");
    for (i, want) in [0.03, 0.063, 0.085].iter().enumerate() {
        assert!((d.after.c[i] / want - 1.0).abs() < 0.05, "C{} = {}", i + 1, d.after.c[i]);
    }
}

#[test]
fn a_pinhole_camera_straight_down_is_named() {
    check("perspective");
}

#[test]
fn a_tilted_pinhole_camera_is_named() {
    check("tilted-camera");
}

#[test]
fn a_lens_off_centre_is_named() {
    check("lens-off-centre");
}

/// Both are named, and each one's share of the improvement is real: without it the misfit
/// comes back well above what the pair leaves.
#[test]
fn two_effects_are_both_named() {
    let d = check("two-effects");
    let named = d.finding.named();
    assert_eq!(d.shares.len(), named.len(), "a share for each named effect");
    for s in &d.shares {
        assert!(named.contains(&s.effect), "{:?} has a share but is not named", s.effect);
        assert!(s.share > 0.05 && s.share <= 1.0 + 1e-9, "{:?}: share {}", s.effect, s.share);
        assert!(
            s.rms_without_px > 2.0 * d.after.rms_px,
            "{:?}: {} px without it",
            s.effect,
            s.rms_without_px
        );
    }
}

#[test]
fn glitches_are_left_out_and_nothing_is_missing() {
    let d = check("glitches");
    // 0.5% of 1,808 x 4 marks off, and labels 1 and 3 swapped a few frames four times.
    assert!((40..=70).contains(&d.glitches.len()), "{} glitches", d.glitches.len());
    assert!(
        d.before.rms_px < 1.1 * d.noise_px,
        "misfit over the coordinates kept: {}",
        d.before.rms_px
    );
}
