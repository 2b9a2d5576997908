//! The rules that name an effect, or nothing, or "unexplained": shared by the decision
//! ([`super::run`]) and the words that explain it ([`super::explain`]).

use super::whole::WholeFit;

/// The share of the baseline's misfit beyond the noise that an effect must explain to be named.
pub const MIN_EXPLAINED: f64 = 0.5;

/// The baseline is consistent with the noise (`none`) when its misfit over the coordinates kept
/// is at most this many times the noise estimated from the tracks: an excess of 0.75 noise.
/// The estimate itself is good to a few percent on recordings without glitches and to about
/// 6% with them; a right model ends within 2% of the true noise. So a right baseline stays
/// below it with room to spare, and a misfit twice the noise is never called consistent.
pub const CONSISTENT_RATIO: f64 = 1.25;

/// The part of a misfit beyond the noise (px): `sqrt(max(rms^2 - noise^2, 0))`.
pub fn excess_px(rms_px: f64, noise_px: f64) -> f64 {
    (rms_px * rms_px - noise_px * noise_px).max(0.0).sqrt()
}

/// A model whose excess over the noise is at most this share of the noise has settled the
/// recording: no other model can do better than the noise lets one tell, so the forward
/// selection tries no further pairs. 0.3 noise is a misfit of 1.044 times the noise: the
/// noise estimate is itself off by a few percent (docs/diagnosis.md), so a right model can end
/// 1.02 to 1.03 times the noise estimated, which a tighter rule never called settled.
/// Tighter than [`CONSISTENT_RATIO`], which says only that nothing is missing.
pub const SETTLED_EXCESS: f64 = 0.3;

/// How near the noise a model has come: the one test of "settled" that every pass of the plan
/// and every queue of fits stops by ([`reached`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reach {
    /// An excess over the noise of at most [`SETTLED_EXCESS`] noise: no other model can be
    /// told better.
    Settled,
    /// Within [`CONSISTENT_RATIO`] of the noise: nothing is left that needs another effect.
    Consistent,
}

impl Reach {
    /// Whether a model with misfit `rms_px` has come this near the noise `noise_px`.
    pub fn by(self, rms_px: f64, noise_px: f64) -> bool {
        match self {
            Reach::Settled => excess_px(rms_px, noise_px) <= SETTLED_EXCESS * noise_px,
            Reach::Consistent => rms_px <= CONSISTENT_RATIO * noise_px,
        }
    }
}

/// Whether any of `fits` has come as near the noise as `reach` says.
pub fn reached<'a>(
    fits: impl IntoIterator<Item = &'a WholeFit>,
    reach: Reach,
    noise_px: f64,
) -> bool {
    fits.into_iter().any(|w| reach.by(w.rms_px(), noise_px))
}

/// The share of the baseline's squared misfit beyond the noise (`before^2 - noise^2`) that a
/// model with misfit `after` removes (1: all of it, down to the noise).
pub fn explained_share(before_px: f64, after_px: f64, noise_px: f64) -> f64 {
    let excess = before_px * before_px - noise_px * noise_px;
    if !(excess > 0.0) {
        return 0.0;
    }
    ((before_px * before_px - after_px * after_px) / excess).clamp(0.0, 1.0)
}

/// BIC of a fit with `cost` over `n` residuals and `k` parameters, where `dependence`
/// residuals count as one independent one (1 for white noise; a tracker's correlated noise
/// moves a fitted parameter as much as white noise on `n / dependence` residuals would:
/// `noise_correlation`).
pub fn bic(cost: f64, n: usize, k: usize, dependence: f64) -> f64 {
    let n_independent = n.max(1) as f64 / dependence.max(1.0);
    n_independent * (cost / n.max(1) as f64).max(1e-300).ln() + k as f64 * n_independent.ln()
}

/// What one more free number costs in [`bic`] over `n` residuals: a number is worth keeping
/// where it lowers the cost by more than this many noise variances (and the evidence asked).
pub fn bic_per_parameter(n: usize) -> f64 {
    (n.max(1) as f64).ln()
}

/// How many times a named model, one effect or a pair, must cut the misfit beyond the noise
/// (against the baseline, or for a pair against the effect it adds to), unless it ends
/// consistent with the noise. A candidate that imitates an effect it was not offered cuts the
/// excess a few times and leaves several noise levels: with rolling friction withheld, pivot
/// friction took a 17 px excess to 4.1 px (8 noise levels); two free strengths imitate more
/// easily still. A right model leaves a fraction of the noise (docs/diagnosis.md has the
/// cuts the bench measured on both sides).
pub const MIN_EXCESS_CUT: f64 = 10.0;

/// The explain-the-excess rule: a model with misfit `after` explains a recording that another
/// model misses by `before` when it removes at least [`MIN_EXPLAINED`] of the squared misfit
/// beyond the noise AND either cuts the excess [`MIN_EXCESS_CUT`] times or is itself within
/// [`CONSISTENT_RATIO`] of the noise.
pub fn explains(before_px: f64, after_px: f64, noise_px: f64) -> bool {
    explained_share(before_px, after_px, noise_px) >= MIN_EXPLAINED
        && (excess_px(after_px, noise_px) * MIN_EXCESS_CUT <= excess_px(before_px, noise_px)
            || after_px <= CONSISTENT_RATIO * noise_px)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settled_is_an_excess_of_three_tenths_of_the_noise() {
        // An excess of 0.3 noise is a misfit of sqrt(1.09) = 1.0440 times the noise.
        let settled = |rms, noise| Reach::Settled.by(rms, noise);
        assert!(settled(0.5220, 0.5));
        assert!(!settled(0.5221, 0.5));
        // A right model where the noise was estimated 3% low.
        assert!(settled(0.496, 0.485));
        assert!(settled(0.49, 0.5));
        // Stricter than consistent: 1.1 times the noise is consistent but not settled.
        assert!(Reach::Consistent.by(0.55, 0.5) && !settled(0.55, 0.5));
        assert!(Reach::Consistent.by(0.625, 0.5) && !Reach::Consistent.by(0.6251, 0.5));
    }
}
