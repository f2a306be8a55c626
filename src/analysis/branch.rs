//! A periodic orbit continued in speed, its stability along the branch and where it changes
//! (issue 29, second part: natural-parameter continuation; pseudo-arclength, which follows a
//! branch around a fold, is not built yet).
//!
//! The orbit of period `k` revolutions is shot at the first speed from its settled run
//! ([`super::periodic::shoot`]); at each next speed Newton starts from the previous fixed point,
//! its velocities `(uᴺ − uᴺ⁻¹)/Δt` carried to the new speed's step
//! ([`crate::time::EndState::retimed`]); where Newton does not converge the step is halved
//! ([`MAX_SUBSTEPS`] times at most, the midpoints joining the branch). The branch ends where it
//! still does not (a fold — the orbit turns back, `rubsim continue --arclength` follows it —,
//! or the orbit ceases to exist); the report says at which speed. A reduced model's cut-off is
//! pinned for the whole branch ([`pinned_reduction`]). Between two converged points whose stability differs (every `|ρ| < 1` on one
//! side only) the change is located by bisection in ν ([`LOCATE_STEPS`] halvings, each a
//! Newton from the nearer point) and named by the multiplier that crosses the unit circle on
//! the unstable side: `period_doubling` (ρ through −1), `fold` (through +1) or
//! `neimark_sacker` (a complex pair).

use super::periodic::{self, PeriodicOrbit};
use super::speed::prepare;
use super::RunSettings;
use crate::error::Result;
use crate::model::Model;
use serde::Serialize;

/// Halvings of a continuation step whose Newton does not converge, each reaching the
/// midpoint first (the contact set can change much between two speeds of a sweep's grid).
pub const MAX_SUBSTEPS: usize = 4;

/// Halvings of the interval in which a change of stability is located (the interval shrinks
/// to 1/2⁶ = 1/64 of the continuation step).
pub const LOCATE_STEPS: usize = 6;

/// One converged point of the branch.
#[derive(Debug, Clone, Serialize)]
pub struct BranchPoint {
    /// ν = ω/ω_n.
    pub speed_ratio: f64,
    /// Every `|ρ| < 1`.
    pub stable: bool,
    /// Largest `|ρ|`.
    pub largest_modulus: f64,
    /// The multiplier of largest modulus `[Re, Im]`.
    pub rho1: [f64; 2],
    /// How it is unstable (`period_doubling`, `fold`, `neimark_sacker`), `None` when stable.
    pub instability: Option<&'static str>,
    /// The orbit's extents `[x_min, x_max, y_min, y_max]` / |Z0|.
    pub extents_nd: [f64; 4],
    /// 1× amplitude / |Z0|.
    pub amp_1x_nd: f64,
    /// Fraction of the period in contact.
    pub contact_fraction: f64,
    /// Newton iterations from the predicted state.
    pub iterations: usize,
    /// Newton's final relative residual.
    pub residual: f64,
}

/// A change of stability located between two speeds.
#[derive(Debug, Clone, Serialize)]
pub struct Bifurcation {
    /// `period_doubling`, `fold` or `neimark_sacker`: the unstable side's crossing multiplier.
    pub kind: &'static str,
    /// The located interval `[ν_a, ν_b]`: stable at one end, unstable at the other.
    pub between: [f64; 2],
    /// Its midpoint, the reported location.
    pub speed_ratio: f64,
    /// The crossing multiplier on the stable and on the unstable side.
    pub rho: [[f64; 2]; 2],
}

/// A branch of period-`k` orbits over speed.
#[derive(Debug, Clone, Serialize)]
pub struct Branch {
    /// Period in revolutions.
    pub period: usize,
    /// The converged points, in the order continued.
    pub points: Vec<BranchPoint>,
    /// The changes of stability located along it.
    pub bifurcations: Vec<Bifurcation>,
    /// Why the branch stops before the last speed, when it does.
    pub ended: Option<String>,
    /// Steps integrated in all.
    pub steps: u64,
}

impl BranchPoint {
    fn of(o: &PeriodicOrbit) -> Self {
        Self {
            speed_ratio: o.speed_ratio,
            stable: o.stable,
            largest_modulus: o.largest_modulus,
            rho1: o.multipliers.first().copied().unwrap_or_default(),
            instability: o.instability,
            extents_nd: o.orbit.extents_nd,
            amp_1x_nd: o.orbit.amp_1x_nd,
            contact_fraction: o.orbit.contact_fraction,
            iterations: o.iterations,
            residual: o.residual,
        }
    }
}

/// Continues the period-`period` orbit (`None`: the first speed's settled period) over
/// `speeds` (ν, in the order given) with the scene's run settings `s` (module docs).
///
/// # Errors
/// The first speed's shooting errors ([`periodic::shoot`]); a run error at a later speed
/// ends the branch there (`ended`), it is not returned.
pub fn continue_in_speed(
    model: &Model,
    s: &RunSettings,
    speeds: &[f64],
    period: Option<usize>,
) -> Result<Branch> {
    let Some((&first, rest)) = speeds.split_first() else {
        return Ok(Branch {
            period: period.unwrap_or(1),
            points: Vec::new(),
            bifurcations: Vec::new(),
            ended: None,
            steps: 0,
        });
    };
    let top = speeds.iter().fold(first, |m, v| m.max(*v));
    let pinned = pinned_reduction(model, s, top)?;
    let s = &pinned;
    let start = periodic::shoot(&prepare(model, &request(s, first))?, period)?;
    let k = start.period;
    let mut steps = start.steps;
    let mut branch = Branch {
        period: k,
        points: Vec::new(),
        bifurcations: Vec::new(),
        ended: None,
        steps: 0,
    };
    if !start.converged {
        branch.ended = Some(format!(
            "no periodic orbit of {k} revolution(s) at ω/ωn = {first:.4} (residual {:.2e})",
            start.residual
        ));
        branch.steps = steps;
        return Ok(branch);
    }
    let mut prev = start;
    branch.points.push(BranchPoint::of(&prev));
    // Speeds still to reach, the next last; a step whose Newton fails is halved (up to
    // [`MAX_SUBSTEPS`] times) by reaching its midpoint first.
    let mut todo: Vec<(f64, usize)> = rest.iter().rev().map(|&v| (v, 0)).collect();
    while let Some((v, depth)) = todo.pop() {
        let next = match at_speed(model, s, v, &prev) {
            Ok(o) if o.converged => o,
            Ok(o) if depth < MAX_SUBSTEPS => {
                steps += o.steps;
                todo.push((v, depth + 1));
                todo.push((0.5 * (prev.speed_ratio + v), depth + 1));
                continue;
            }
            Ok(o) => {
                steps += o.steps;
                branch.ended = Some(format!(
                    "Newton did not converge at ω/ωn = {v:.4} from the orbit at {:.4} (residual {:.2e}, the step halved {MAX_SUBSTEPS} times): a fold, or the period-{k} orbit ends there",
                    prev.speed_ratio, o.residual
                ));
                break;
            }
            Err(e) => {
                branch.ended = Some(format!("ω/ωn = {v:.4}: {e}"));
                break;
            }
        };
        steps += next.steps;
        if next.stable != prev.stable {
            let (b, st) = locate(model, s, &prev, &next);
            steps += st;
            branch.bifurcations.extend(b);
        }
        branch.points.push(BranchPoint::of(&next));
        prev = next;
    }
    branch.steps = steps;
    Ok(branch)
}

/// The settings `s` with a reduced model's cut-off pinned for the whole branch: a default
/// cut-off `cutoff_factor × max(harmonics × ω, ω_c)` follows the speed, and with it the
/// reduced basis — a state at one speed would mean another thing at the next. Pinned at the
/// branch's highest speed `top_ratio` (ν), every point keeps the modes its own speed would ask
/// for and one basis. Unchanged without a reduction or with a fixed `cutoff`.
///
/// # Errors
/// The case at the top speed.
pub fn pinned_reduction(model: &Model, s: &RunSettings, top_ratio: f64) -> Result<RunSettings> {
    let Some(r) = s.reduction_of(model).copied() else {
        return Ok(*s);
    };
    if r.cutoff.is_some() {
        return Ok(*s);
    }
    let top = top_ratio * model.rotor.natural_frequency();
    let cf = model.case_with(top, None)?.contact_frequency();
    let cut = r.cutoff_factor * (r.harmonics * top).max(cf);
    Ok(RunSettings {
        reduction: Some(crate::resolve::ReductionInput {
            cutoff: Some(cut),
            ..r
        }),
        ..*s
    })
}

/// The run request of the continuation at ν: the scene's settings, no follow-ups (also
/// [`super::arclength`]'s).
pub(super) fn request(s: &RunSettings, v: f64) -> super::RunRequest {
    let mut r = s.request(v);
    r.follow_ups = super::FollowUps::default();
    r
}

/// The period-`k` orbit at ν = `v` by Newton from the orbit `from` at a neighbouring speed.
fn at_speed(model: &Model, s: &RunSettings, v: f64, from: &PeriodicOrbit) -> Result<PeriodicOrbit> {
    let prep = prepare(model, &request(s, v))?;
    periodic::shoot_from(&prep, from)
}

/// Bisects the interval between `a` and `b` (stable on one side only) [`LOCATE_STEPS`] times;
/// the bifurcation found (none when a midpoint's Newton fails, which ends the location at the
/// interval reached) and the steps it took.
fn locate(
    model: &Model,
    s: &RunSettings,
    a: &PeriodicOrbit,
    b: &PeriodicOrbit,
) -> (Option<Bifurcation>, u64) {
    let (mut lo, mut hi) = (a.clone(), b.clone());
    let mut steps = 0;
    for _ in 0..LOCATE_STEPS {
        let mid = 0.5 * (lo.speed_ratio + hi.speed_ratio);
        match at_speed(model, s, mid, &lo) {
            Ok(m) if m.converged => {
                steps += m.steps;
                if m.stable == lo.stable {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            _ => break,
        }
    }
    let (stable, unstable) = if lo.stable { (&lo, &hi) } else { (&hi, &lo) };
    let rho = |o: &PeriodicOrbit| o.multipliers.first().copied().unwrap_or_default();
    let bif = unstable.instability.map(|kind| Bifurcation {
        kind,
        between: [lo.speed_ratio, hi.speed_ratio],
        speed_ratio: 0.5 * (lo.speed_ratio + hi.speed_ratio),
        rho: [rho(stable), rho(unstable)],
    });
    (bif, steps)
}
