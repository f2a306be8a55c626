//! The cut-off of a modal reduction chosen from `run.tolerance` (issue 15 item 2,
//! docs/IMPLICIT.md §7.3): the factor κ of `ω_cut = κ max(n ω, ω_c)` raised until the
//! truncation error indicator is within its share of the tolerance.
//!
//! # The indicator
//!
//! The static columns (the rotor's interface DOFs, the stator's constraint modes) make the
//! reduced model's static response at the contact exact, so what the truncation leaves out is
//! the dynamic part of the modes above ω_cut: their response to a load at frequency ω is
//! `1/(ω_k² − ω²)` instead of the static `1/ω_k²` already in the basis, a relative error
//! `ω²/(ω_k² − ω²) ≈ (ω/ω_k)²` — second order in `1/κ`. Doubling κ divides it by about 4, so
//! the difference of two pilot runs at κ and 2κ (same scheme, same step, same start: the step's
//! own error cancels) is `d = e(κ) − e(2κ) ≈ ¾ e(κ)`, and
//!
//! ```text
//! E(κ) = 4/3 · d(κ, 2κ)        (d: `autostep::difference`, extents and 1×, ½×, ⅓× lines)
//! ```
//!
//! estimates the truncation error of the run at κ, 2κ standing for the next factor whose
//! basis holds more modes (one that passes no new mode would read 0). κ starts at
//! [`crate::scene::DEFAULT_CUTOFF_FACTOR`] and doubles while E(κ), the largest over the pilot
//! speeds, is above [`TRUNCATION_SHARE`] × `run.tolerance`; when no mode lies between the
//! cut-off and [`MAX_FACTOR`] × max(nω, ω_c), E is 0 (the modes left out respond to the
//! resolved band with less than (1/64)² of their static share, which the static columns hold). The pilots run generalised-α (unconditionally
//! stable: the two models take the same step although their highest frequencies differ) at
//! [`PILOT_STEP_SCALE`] × the paper's rule — the modes near the cut-off resolved rather than
//! damped by the scheme — from the run's initial state, [`super::autostep::PILOT_WINDOW`]
//! revolutions analysed after [`super::autostep::PILOT_TRANSIENT`].

use super::discrepancy::difference;
use super::{prepare, scheme, Keep, RunRequest, RunSettings, SpeedResults};
use crate::error::Result;
use crate::model::Model;
use crate::resolve::ReductionInput;
use crate::scene::IntegratorKind;
use serde::{Deserialize, Serialize};

/// The share of `run.tolerance` the truncation may take (the step's error takes
/// [`super::autostep::SAFETY`], the rest is margin).
pub const TRUNCATION_SHARE: f64 = 0.25;
/// The largest κ tried.
pub const MAX_FACTOR: f64 = 64.0;
/// The pilots' step as a multiple of the paper's rule.
pub const PILOT_STEP_SCALE: f64 = 0.25;

/// The cut-off factor chosen from the tolerance, reported with the runs that use it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CutoffChoice {
    /// κ of `ω_cut = κ max(n ω, ω_c)`.
    pub cutoff_factor: f64,
    /// The truncation error indicator E(κ) at the chosen κ (relative, as `run.tolerance`), the
    /// largest over the pilot speeds.
    pub truncation_error: f64,
    /// What E(κ) had to meet: [`TRUNCATION_SHARE`] × `run.tolerance`.
    pub target: f64,
    /// Steps of the pilots together.
    pub pilot_steps: u64,
    /// Wall time of the pilots' loops together (s).
    pub pilot_wall_s: f64,
}

/// The pilot results of `model` reduced as `red` at each of `speeds` (ω/ω_n), by `sch` at
/// [`PILOT_STEP_SCALE`] × the paper's rule ([`RunRequest::pilot`]).
fn pilots(
    model: &Model,
    s: &RunSettings,
    sch: crate::time::Scheme,
    red: &ReductionInput,
    speeds: &[f64],
    acc: &mut (u64, f64),
) -> Result<Vec<SpeedResults>> {
    let mut out = Vec::with_capacity(speeds.len());
    for &v in speeds {
        let ps = RunRequest::pilot(s, v, sch, PILOT_STEP_SCALE).reduced(*red);
        let prep = prepare(model, &ps)?;
        let r = prep.execute(&ps, &prep.plan, Keep::default())?;
        acc.0 += r.stats.steps as u64;
        acc.1 += r.stats.wall_s;
        out.push(r);
    }
    Ok(out)
}

/// Chooses κ for `base` (its `cutoff_factor` ignored) from `s.tolerance` at the pilot speeds
/// `speeds` (ω/ω_n); `rho_inf`: the pilots' generalised-α ρ∞.
///
/// # Errors
/// A model error of the reduction (a rotor whose K is singular), a plan or a pilot run's error.
pub fn choose_cutoff(
    model: &Model,
    s: &RunSettings,
    base: ReductionInput,
    speeds: &[f64],
    rho_inf: Option<f64>,
) -> Result<CutoffChoice> {
    let sch = scheme(IntegratorKind::GeneralizedAlpha, rho_inf);
    let target = TRUNCATION_SHARE * s.tolerance;
    let at = |k: f64| ReductionInput {
        cutoff: None,
        cutoff_factor: k,
        ..base
    };
    let mut acc = (0u64, 0.0);
    let mut kappa = crate::scene::DEFAULT_CUTOFF_FACTOR;
    let mut lo = pilots(model, s, sch, &at(kappa), speeds, &mut acc)?;
    let mut modes_lo = modes(model, &at(kappa), speeds)?;
    loop {
        // The next κ whose basis differs (a cut-off that passes no new mode changes nothing:
        // compared with it, the truncation would read 0).
        let mut next = 2.0 * kappa;
        while next <= MAX_FACTOR && modes(model, &at(next), speeds)? == modes_lo {
            next *= 2.0;
        }
        if next > MAX_FACTOR {
            // No mode between this cut-off and MAX_FACTOR × max(nω, ω_c): the modes left out
            // respond to the resolved band with less than (1/MAX_FACTOR)² of their static
            // share, and that share is in the basis.
            return Ok(CutoffChoice {
                cutoff_factor: kappa,
                truncation_error: 0.0,
                target,
                pilot_steps: acc.0,
                pilot_wall_s: acc.1,
            });
        }
        let hi = pilots(model, s, sch, &at(next), speeds, &mut acc)?;
        let e = lo
            .iter()
            .zip(&hi)
            .map(|(a, b)| 4.0 / 3.0 * difference(a, b))
            .fold(0.0, f64::max);
        if e <= target {
            return Ok(CutoffChoice {
                cutoff_factor: kappa,
                truncation_error: e,
                target,
                pilot_steps: acc.0,
                pilot_wall_s: acc.1,
            });
        }
        kappa = next;
        lo = hi;
        modes_lo = modes(model, &at(kappa), speeds)?;
    }
}

/// The modes each reduction keeps at each of `speeds` (ω/ω_n): the rotor's internal modes and
/// every reduced stator's fixed-interface modes.
fn modes(model: &Model, red: &ReductionInput, speeds: &[f64]) -> Result<Vec<usize>> {
    let wn = model.rotor.natural_frequency();
    let mut out = Vec::new();
    for &v in speeds {
        let case = model.case_with(v * wn, Some(red))?;
        out.push(case.reduced.as_ref().map_or(0, |r| r.modes));
        out.extend((case.stators.iter()).map(|s| s.reduced.as_ref().map_or(0, |r| r.modes.len())));
    }
    Ok(out)
}
