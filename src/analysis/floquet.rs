//! The Floquet multipliers' own step error (`rubsim periodic --refine`): the shot orbit found
//! again at half the step, each multiplier beside its twin, and — for an orbit without contact —
//! their Richardson extrapolation to the continuous flow's.
//!
//! A shot orbit's multipliers are those of the run's discrete map ([`super::periodic`]): for a
//! case without contact the eigenvalues of the `k N`-step central-difference propagator, which
//! differ from the continuous flow's `exp(λ k T)` (λ the rotor's eigenvalues, `rubsim modal`) by
//! `C Δt²` (docs/VALIDATION.md §19: 1.8e-5 at the paper's step, order 2.000). Shooting the same
//! orbit at `Δt/2` (`2N` steps a revolution, Newton from the fixed point carried to the finer
//! step by [`crate::time::EndState::retimed`]) gives each multiplier's twin `ρ(Δt/2)`, matched
//! to `ρ(Δt)` by nearest distance in the complex plane. Then:
//!
//! - without contact on either orbit (contact fraction 0) the map is linear and the scheme's
//!   error is `C Δt² + O(Δt⁴)`: `ρ* = ρ(Δt/2) + (ρ(Δt/2) − ρ(Δt))/3` removes the `Δt²` term
//!   (on the free paper rotor at N = 384 the closed-form propagators leave 3.3e-11), and the
//!   error of `ρ(Δt/2)` is estimated as `|ρ(Δt/2) − ρ(Δt)|/3`. The variational monodromy of
//!   such a map is its propagator to round-off (1e-11); where the monodromy is by differences
//!   of whole maps (a step with no linearisation: `periodic::Monodromy`) their round-off
//!   remains (≈ 1e-8 at shooting's step of `1e-5 max |x|` and 768 steps a revolution: 1.7e-8
//!   after extrapolation), and an orbit that keeps clear of contact has an affine map, whose
//!   differences are exact at any step, so both levels' multipliers are taken again from
//!   differences of [`AFFINE_STEP`], a hundredth of the round-off;
//! - with contact the map is only piecewise smooth and its order in Δt is not known (first
//!   order for the forward increment against a massless stator): no extrapolation, and the
//!   error of `ρ(Δt/2)` is estimated by the whole difference `|ρ(Δt/2) − ρ(Δt)|` (the
//!   first-order bound).
//!
//! The stability verdict is compared at both steps: `verdict_changes` says when the step alone
//! decides it (a multiplier within its own step error of the unit circle).

use super::periodic::{self, PeriodicOrbit};
use super::speed::Prepared;
use crate::error::Result;
use crate::time::StepPlan;
use serde::Serialize;

/// The relative step (of max |x|) of the monodromy's differences for an orbit that keeps clear
/// of contact: its map is affine there, so the differences are exact at any step and a larger
/// one divides their round-off (≈ 1e-8 at shooting's `1e-5` on the free paper rotor at N = 768
/// steps a revolution) by 100.
pub const AFFINE_STEP: f64 = 1e-3;

/// An orbit keeps clear of contact for [`AFFINE_STEP`]'s differences when it had no contact
/// and its smallest gap (none evaluated: no candidate pair came near) is at least 100 times
/// the differences' step.
fn clear_of_contact(o: &PeriodicOrbit) -> bool {
    let size = o.fixed_point.0.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let gap = o.orbit.stats.min_gap;
    o.orbit.contact_fraction == 0.0 && (gap.is_nan() || gap > 100.0 * AFFINE_STEP * size)
}

/// The orbit's multipliers at half its step and their extrapolation ([module docs](self)).
#[derive(Debug, Clone, Serialize)]
pub struct StepRefinement {
    /// Δt of the orbit and of its refinement (s).
    pub dt: [f64; 2],
    /// Whether Newton converged at `Δt/2`.
    pub converged: bool,
    /// Newton's relative residual at `Δt/2`.
    pub residual: f64,
    /// `ρ(Δt)` `[Re, Im]` as refined: the orbit's multipliers, or — an orbit clear of contact —
    /// the same from differences of [`AFFINE_STEP`] (equal to them within their round-off).
    pub coarse: Vec<[f64; 2]>,
    /// `ρ(Δt/2)` `[Re, Im]`, the i-th matched to the orbit's i-th multiplier.
    pub half_step: Vec<[f64; 2]>,
    /// `|ρ(Δt/2) − ρ(Δt)|` per multiplier.
    pub difference: Vec<f64>,
    /// The estimated error of `ρ(Δt/2)`: `difference / 3` without contact (order 2),
    /// `difference` with contact (the first-order bound).
    pub error_estimate: Vec<f64>,
    /// The order assumed in Δt: 2 without contact, 1 with.
    pub order: u32,
    /// Without contact, `ρ(Δt/2) + (ρ(Δt/2) − ρ(Δt))/3`: the continuous flow's multipliers
    /// (`exp(λ k T)`) to `O(Δt⁴)`; `None` with contact.
    pub extrapolated: Option<Vec<[f64; 2]>>,
    /// The largest `|ρ(Δt/2)|`.
    pub largest_modulus: f64,
    /// Every `|ρ(Δt/2)| < 1` (and converged).
    pub stable: bool,
    /// The stability verdicts at `Δt` and `Δt/2` differ: the step decides it.
    pub verdict_changes: bool,
    /// Steps integrated for the refinement.
    pub steps: u64,
}

/// [`periodic::shoot_at`], and with `refine` the orbit shot again at half its step
/// ([`refine`]): `rubsim periodic [--refine]` and the Python package's
/// `Scene.periodic`.
///
/// # Errors
/// As [`periodic::shoot_at`] and [`refine`].
pub fn shoot_refined(
    model: &crate::model::Model,
    s: &super::RunSettings,
    speed_ratio: f64,
    period: Option<usize>,
    refine: bool,
) -> Result<(PeriodicOrbit, Option<StepRefinement>)> {
    let prep = super::prepare(model, &periodic::request_at(s, speed_ratio))?;
    let orbit = periodic::shoot(&prep, period)?;
    let refined = if refine {
        Some(self::refine(&prep, &orbit)?)
    } else {
        None
    };
    Ok((orbit, refined))
}

/// The orbit `o` (shot on `prep`) shot again at half its step, its multipliers matched,
/// differenced and, without contact, extrapolated ([module docs](self)).
///
/// # Errors
/// As [`periodic::shoot`]: the map's run errors at the finer step.
pub fn refine(prep: &Prepared, o: &PeriodicOrbit) -> Result<StepRefinement> {
    let plan = &prep.plan;
    let half = StepPlan {
        dt: plan.dt / 2.0,
        steps_per_rev: 2 * plan.steps_per_rev,
        record_every: 2 * plan.record_every,
        ..*plan
    };
    let fine = periodic::shoot_at_step(prep, o, &half)?;
    let half_step = matched(&o.multipliers, &fine.multipliers);
    let smooth = o.orbit.contact_fraction == 0.0 && fine.orbit.contact_fraction == 0.0;
    let mut steps = fine.steps;
    let mut coarse = o.multipliers.clone();
    let mut half_step = half_step;
    let differenced = o.monodromy == periodic::Monodromy::FiniteDifference;
    if differenced && smooth && clear_of_contact(o) && clear_of_contact(&fine) {
        // The map is affine: differences of a larger step are exact and carry less round-off.
        let (c, s1) = periodic::multipliers_at(prep, o, plan, AFFINE_STEP)?;
        let (f, s2) = periodic::multipliers_at(prep, &fine, &half, AFFINE_STEP)?;
        half_step = matched(&c, &f);
        coarse = c;
        steps += s1 + s2;
    }
    let difference: Vec<f64> = coarse
        .iter()
        .zip(&half_step)
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
        .collect();
    let (order, error_estimate, extrapolated) = if smooth {
        let ext = coarse
            .iter()
            .zip(&half_step)
            .map(|(a, b)| [b[0] + (b[0] - a[0]) / 3.0, b[1] + (b[1] - a[1]) / 3.0])
            .collect();
        (2, difference.iter().map(|d| d / 3.0).collect(), Some(ext))
    } else {
        (1, difference.clone(), None)
    };
    Ok(StepRefinement {
        dt: [plan.dt, half.dt],
        converged: fine.converged,
        residual: fine.residual,
        largest_modulus: fine.largest_modulus,
        stable: fine.stable,
        verdict_changes: fine.stable != o.stable,
        half_step,
        difference,
        error_estimate,
        order,
        extrapolated,
        coarse,
        steps,
    })
}

/// `fine` reordered so that its i-th is the nearest (in the complex plane) to `coarse`'s i-th,
/// each taken once (greedy in `coarse`'s order, largest modulus first).
fn matched(coarse: &[[f64; 2]], fine: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut left: Vec<[f64; 2]> = fine.to_vec();
    coarse
        .iter()
        .filter_map(|c| {
            let (i, _) = left
                .iter()
                .enumerate()
                .min_by(|(_, a), (_, b)| dist(a, c).total_cmp(&dist(b, c)))?;
            Some(left.swap_remove(i))
        })
        .collect()
}

fn dist(a: &[f64; 2], b: &[f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[cfg(test)]
mod tests {
    use super::matched;

    #[test]
    fn multipliers_are_matched_to_their_nearest_twin_once() {
        let coarse = [[0.9, 0.1], [0.9, -0.1], [-0.5, 0.0]];
        let fine = [[-0.49, 0.0], [0.91, -0.1], [0.91, 0.1]];
        assert_eq!(
            matched(&coarse, &fine),
            vec![[0.91, 0.1], [0.91, -0.1], [-0.49, 0.0]]
        );
    }
}
