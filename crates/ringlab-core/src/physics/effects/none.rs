//! `none`: the recording agrees with the paper's model. The diagnosis's baseline, listed with
//! the effects so that a table of candidates and a concealed-effect family can name it.

use super::{USUAL_IN_PLAN, 
    Descriptor, Role, Terms, from_zero, no_camera, no_physics, no_words, usual_search,
};

pub struct Effect;
impl Terms for Effect {
    type Params = ();
}

pub const DESCRIPTOR: Descriptor = Descriptor {
    name: "none",
    parameter: "-",
    what: "nothing: the paper's model (pure rolling, quadratic air drag of eq. 5)",
    role: Role::Nothing,
    realistic: (0.0, 0.0),
    baseline: Some(0.0),
    apply: no_physics,
    camera: no_camera,
    read: from_zero,
    extras: &[],
    scan: |_, _| vec![0.0],
    search: usual_search,
    blind: super::no_blind,
    words: no_words,
    plan: USUAL_IN_PLAN,
};
