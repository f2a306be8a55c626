//! Periodic responses by shooting, with their Floquet multipliers and stability (issue 29):
//! one orbit at one speed; its continuation is [`super::branch`] and [`super::arclength`].
//!
//! **The map.** A constant-speed run's discrete Poincaré map `P` takes the state `x` at a whole
//! revolution — `x = (uᴺ, uᴺ⁻¹)` of every body of central differences, the rotor then the
//! stators with mass ([`EndState::state_vector`]; a massless stator carries no state, its
//! contact forces being solved anew at each step) — to the state `k` revolutions later: `k N`
//! steps of the run's own scheme and Δt (`N` steps a revolution), the unbalance starting at its
//! phase of t = 0. A periodic response of period `k T` (`T = 2π/Ω`) is a fixed point
//! `x* = P(x*)`: the same discrete orbit a long run settles on, without its transient.
//!
//! **Newton.** `F(x) = P(x) − x` is solved by Newton from a settled run's end state, with the
//! Jacobian `M = ∂P/∂x` (below) and steps halved up to [`MAX_HALVINGS`] times while the
//! residual does not fall. Converged when `max |F| ≤` [`SHOOT_TOLERANCE`] `· max |x|`; after
//! [`MAX_NEWTON`] iterations without it the report says so (`converged = false`, the residual
//! reached) — a response that is not periodic at period `k` (a torus, chaos) gets that report,
//! not a Newton that runs on.
//!
//! **The monodromy.** `M` is taken by the variational equations of the scheme's own step
//! ([`Monodromy::Variational`], `time::Tangent`): one run of the map carries the tangent
//! `∂(uⁿ⁺¹, uⁿ)/∂x` along, the step being linear in the rotor's state but for its contact,
//! whose forces (the collocated scheme's static multipliers `L`, the forward-increment
//! scheme's increments `D`) are differentiated at each step in contact by central differences
//! over the contact DOFs alone (relative step [`TANGENT_STEP`]), on the step's own active set:
//! where a perturbation of one sign changes the set, that column is taken one-sided on the
//! side that keeps it ([`TangentStats::one_sided`]). That is the derivative of the discrete map
//! on the nominal orbit's contact sequence — the discrete counterpart of the saltation-matrix
//! monodromy of the flow — at the cost of about one map, where differences of whole maps cost
//! `2 dim x` maps and, when a perturbation moves a contact event across a step, straddle it
//! (measured: at `h = 10⁻⁵ max |x|` they miss the paper case's period-2 monodromy at ν 3.1 by
//! 3e-3 of its entries). A step with no linearisation (a stator with mass, stick, dashpots,
//! wear, an abradable coating) keeps central differences of whole maps
//! ([`Monodromy::FiniteDifference`], two `k`-revolution runs per component, `h = 10⁻⁵ max |x|`);
//! the orbit says which it took.
//!
//! **Floquet multipliers.** At the fixed point `M` is the monodromy matrix of the discrete map
//! and its eigenvalues `ρ` the Floquet multipliers: the orbit is stable when every `|ρ| < 1`.
//! It loses stability through `ρ = −1` (period doubling), `ρ = +1` (a fold or a symmetry-breaking
//! branch) or a complex pair crossing the unit circle (Neimark–Sacker: a torus). For a case
//! without contact the map is linear and `ρ` are the eigenvalues of the `k N`-step propagator
//! (the variational monodromy gives them to round-off), which approach `exp(λ k T)` (λ the
//! rotor's eigenvalues, `rubsim modal`) as Δt² for central differences. With contact the map
//! is piecewise smooth (the forward-increment multipliers make it Lipschitz). An orbit that
//! sits on a contact event — a contact starting or ending exactly at a step, or grazing — is a
//! kink of the map: its one-sided derivatives differ, the central differences are their mean
//! and the derivative of neither side, and the variational monodromy is a one-sided one (the
//! FE paper rotor at ν 1.7: sides 8e-3 apart, each variational column within 2e-6 of one of
//! them). Such an orbit's multipliers are those of one side and are reported as found; the
//! linearisation's `one_sided` count says when it happened.

use super::speed::{analyse, Prepared, SpeedResults};
use super::Keep;
use crate::error::{Error, Result};
use crate::time::{EndState, Record, RunStats, Sink, StepPlan, Stepper, TangentStats};
use nalgebra::DMatrix;
use serde::Serialize;

mod map;

/// Relative residual `max |P(x) − x| / max |x|` of a converged fixed point.
pub const SHOOT_TOLERANCE: f64 = 1e-9;
/// Newton iterations before the shooting reports no convergence.
pub const MAX_NEWTON: usize = 16;
/// Halvings of a Newton step that does not lower the residual.
pub const MAX_HALVINGS: usize = 6;
/// Largest state (components of `x`) shot: each Newton iteration carries `dim x` tangent
/// columns through a run of the map (the variational monodromy) or runs the map twice per
/// component (where the step has no linearisation), and solves and diagonalises a dense
/// `dim x`-square matrix, so a larger state (an FE rotor with many nodes, a stator with mass)
/// is refused before it starts rather than left to run for hours (a reduced model is the way
/// there).
pub const MAX_STATE: usize = 400;
/// Relative distance (of max |x|) above which two fixed points are distinct orbits: a switched
/// period-2k orbit from its parent's fixed point, and its k-map residual from an orbit that
/// repeats after k revolutions already (`super::switch`, `super::branch::follow`).
pub const DISTINCT: f64 = 1e-6;
/// Relative central-difference step of the Jacobian of whole maps (of `max |x|`), where the
/// step has no linearisation.
const FD_STEP: f64 = 1e-5;
/// Relative perturbation (of `max |x|`) of the contact DOFs in each step's linearisation of
/// the variational monodromy (`time::Tangent`: truncation `(h/R)²`, round-off `ε R/h`, R the
/// section radius).
pub const TANGENT_STEP: f64 = 1e-4;

/// How a monodromy `∂P/∂x` was taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Monodromy {
    /// The variational equations of the scheme's own step carried along one run of the map
    /// (`time::Tangent`): the body's operators exact, each step's contact solve linearised on
    /// its own active set.
    Variational,
    /// Central differences of whole maps, two per state component (scenes whose step has no
    /// linearisation: stators with mass, stick, dashpots, wear, abradable coatings).
    FiniteDifference,
}

impl Monodromy {
    /// The name written in outputs.
    pub fn name(self) -> &'static str {
        match self {
            Monodromy::Variational => "variational",
            Monodromy::FiniteDifference => "finite_difference",
        }
    }
}

/// A periodic response found by shooting ([`shoot`]) and its stability.
#[derive(Debug, Clone, Serialize)]
pub struct PeriodicOrbit {
    /// ν = ω/ω_n.
    pub speed_ratio: f64,
    /// The value of the parameter a continuation found it at
    /// ([`super::parameter::Continued`]): ν for a branch in speed, the scene key's value for a
    /// branch in a key; ν when shot alone.
    #[serde(skip)]
    pub(crate) parameter: f64,
    /// Period in revolutions `k` (the orbit repeats after `k T`).
    pub period: usize,
    /// Whether Newton met [`SHOOT_TOLERANCE`].
    pub converged: bool,
    /// Newton iterations taken.
    pub iterations: usize,
    /// `max |P(x) − x| / max |x|` at the last iterate.
    pub residual: f64,
    /// The Floquet multipliers `[Re ρ, Im ρ]`, largest modulus first (at the last iterate).
    pub multipliers: Vec<[f64; 2]>,
    /// The largest `|ρ|`.
    pub largest_modulus: f64,
    /// Every `|ρ| < 1` (and converged).
    pub stable: bool,
    /// How the largest multiplier leaves the unit circle when it does: `period_doubling` (real,
    /// `ρ < −1`), `fold` (real, `ρ > 1`: a fold or a symmetry-breaking branch) or
    /// `neimark_sacker` (a complex pair); `None` when stable.
    pub instability: Option<&'static str>,
    /// The orbit from the fixed point, run for `6 k` revolutions and analysed as a steady
    /// window (extents, lines, contact fraction).
    pub orbit: Box<SpeedResults>,
    /// Components of the state `x`.
    pub state_size: usize,
    /// How the monodromy of the multipliers was taken.
    pub monodromy: Monodromy,
    /// The variational monodromy's linearisation at the fixed point (steps in contact, contact
    /// DOF columns differenced on one side of an event or across one); `None` for differences.
    pub linearisation: Option<TangentStats>,
    /// Steps integrated in all: the settling run, the maps and their differences, the orbit.
    pub steps: u64,
    /// The last iterate `x` and the state it is laid out in (a start for a neighbouring speed:
    /// [`shoot_from`]).
    #[serde(skip)]
    pub(crate) fixed_point: (Vec<f64>, EndState),
}

/// `rubsim periodic`'s orbit: the run of `model` at ν = `speed_ratio` with the settings `s`
/// (without the coexistence check and the step refinement, which shooting does not use),
/// prepared and shot ([`shoot`]).
///
/// # Errors
/// As [`super::prepare`] and [`shoot`].
pub fn shoot_at(
    model: &crate::model::Model,
    s: &super::RunSettings,
    speed_ratio: f64,
    period: Option<usize>,
) -> Result<PeriodicOrbit> {
    shoot(&super::prepare(model, &request_at(s, speed_ratio))?, period)
}

/// The request [`shoot_at`] prepares: the run at ν = `speed_ratio` with the settings `s`,
/// without the coexistence check and the step refinement.
pub fn request_at(s: &super::RunSettings, speed_ratio: f64) -> super::RunRequest {
    let mut request = s.request_at(0, speed_ratio);
    request.follow_ups.coexistence = false;
    request.follow_ups.refine_step = false;
    request
}

/// Runs `prep` to its settled state and shoots the periodic response of period `period`
/// revolutions from there (`None`: the period the settled run was classified with, 1 when it
/// was not periodic). See the module docs.
///
/// # Errors
/// The run's errors (an unstable step, a contact solve that fails); [`Error::Study`] for a
/// state larger than [`MAX_STATE`], an implicit scheme or a speed that is not constant.
pub fn shoot(prep: &Prepared, period: Option<usize>) -> Result<PeriodicOrbit> {
    let (settled, end) = settle(prep)?;
    let steps = settled.stats.steps as u64;
    let end = end.ok_or_else(|| {
        Error::study(
            "run.integrator",
            "shooting restarts the run's scheme from its settled state, which this run does not keep (an implicit scheme or a fixed window `run.duration`): use an explicit scheme with a settling window".to_string(),
        )
    })?;
    let k = period.unwrap_or(settled.period).max(1);
    let mut o = shoot_state(prep, k, end)?;
    o.steps += steps;
    Ok(o)
}

/// `prep`'s run to its settled state, analysed, and the end state it keeps (none for an
/// implicit scheme or a fixed window): where shooting starts ([`shoot`],
/// `super::coexist_branches`).
///
/// # Errors
/// The run's errors.
pub(crate) fn settle(prep: &Prepared) -> Result<(SpeedResults, Option<EndState>)> {
    let mut req = prep.request;
    // The settling run keeps its end state (kept with the error estimate's bookkeeping).
    req.follow_ups.error_estimate = true;
    let (rec, stats, plan, end, _) = prep.drive_with(&prep.plan, &req, None)?;
    Ok((
        analyse(&prep.case, &req, &plan, &rec, stats, Keep::default()),
        end,
    ))
}

/// The period-`k` orbit of `prep` by Newton from `end`, a settled state of a run of `prep`
/// (its step) taken at a whole revolution: [`shoot`] without the settling run (the coexistence
/// check's two responses, `super::coexist_orbits`).
///
/// # Errors
/// [`Error::Study`] for an implicit scheme's state or a state larger than [`MAX_STATE`]; the
/// map's run errors.
pub fn shoot_state(prep: &Prepared, k: usize, end: EndState) -> Result<PeriodicOrbit> {
    let k = k.max(1);
    let x0 = end.state_vector().ok_or_else(implicit_refused)?;
    if x0.len() > MAX_STATE {
        return Err(too_large(x0.len()));
    }
    solve(prep, k, &prep.plan, end, (x0, None))
}

/// Whether `prep`'s runs can be shot, checked from two steps before any long run: an explicit
/// scheme's state of at most [`MAX_STATE`] components.
///
/// # Errors
/// [`Error::Study`] as [`shoot_state`] refuses; the two steps' run errors.
pub fn check_shootable(prep: &Prepared) -> Result<()> {
    match state_size(prep)? {
        None => Err(implicit_refused()),
        Some(n) if n > MAX_STATE => Err(too_large(n)),
        Some(_) => Ok(()),
    }
}

/// An implicit scheme's state, which shooting does not restart.
fn implicit_refused() -> Error {
    Error::study(
        "run.integrator",
        "shooting needs the state of central differences; the implicit schemes are not shot yet (choose an explicit one: `--set run.integrator=collocated` or `forward_increment`)".to_string(),
    )
}

/// A state of `n` components, above [`MAX_STATE`].
fn too_large(n: usize) -> Error {
    Error::study(
        "rotor",
        format!(
            "the periodic orbit's state has {n} components; shooting carries one tangent column per component through each Newton iteration's map (two maps per component where the step has no linearisation) and is limited to {MAX_STATE} (reduce the rotor, e.g. `rotor.modal_reduction`, or make the stators massless)"
        ),
    )
}

/// The period-`from.period` orbit of `prep` by Newton from the orbit `from` found at a
/// neighbouring speed (its state carried to this speed's step: `EndState::retimed`), without
/// a settling run.
///
/// # Errors
/// As [`shoot`].
pub fn shoot_from(prep: &Prepared, from: &PeriodicOrbit) -> Result<PeriodicOrbit> {
    shoot_at_step(prep, from, &prep.plan)
}

/// The period-`from.period` orbit of `prep` at the step of `plan` (`prep`'s own, or another:
/// the multipliers' refinement shoots at half of it) by Newton from the fixed point of `from`
/// carried to that step (`EndState::retimed`).
///
/// # Errors
/// As [`shoot`].
pub(super) fn shoot_at_step(
    prep: &Prepared,
    from: &PeriodicOrbit,
    plan: &StepPlan,
) -> Result<PeriodicOrbit> {
    let (x, end) = &from.fixed_point;
    let start = end
        .with_state_vector(x)
        .map(|e| e.retimed(plan.dt))
        .ok_or_else(|| {
            Error::study("run", "the orbit's state does not fit this run".to_string())
        })?;
    let x0 = start.state_vector().ok_or_else(|| {
        Error::study("run", "the orbit's state does not fit this run".to_string())
    })?;
    solve(prep, from.period, plan, start, (x0, None))
}

/// The period-`k` orbit of `prep` by Newton from the state `start` (an orbit's fixed point at a
/// neighbouring speed: [`PeriodicOrbit::start_state`]), carried to this speed's step
/// (`EndState::retimed`), without a settling run: `rubsim continue --orbits-at` at a value
/// between the branch's points.
///
/// # Errors
/// As [`shoot`]; a state that does not fit this run.
pub fn shoot_from_state(prep: &Prepared, k: usize, start: &EndState) -> Result<PeriodicOrbit> {
    let start = start.retimed(prep.plan.dt);
    let x0 = start.state_vector().ok_or_else(|| {
        Error::study("run", "the orbit's state does not fit this run".to_string())
    })?;
    solve(prep, k.max(1), &prep.plan, start, (x0, None))
}

impl PeriodicOrbit {
    /// The fixed point as a state a run restarts from (`Stepper::restart` at the orbit's own
    /// step then starts exactly on it), `None` when its vector does not fit its layout.
    pub fn start_state(&self) -> Option<EndState> {
        self.fixed_point.1.with_state_vector(&self.fixed_point.0)
    }

    /// The fixed point `x` ([`EndState::state_vector`]'s layout: per body of central
    /// differences, the rotor first, its uᴺ then uᴺ⁻¹, m and rad; the rotor's uᴺ are its DOFs
    /// in the model's order, `[u_x, u_y]` for a Jeffcott rotor).
    pub fn fixed_state(&self) -> &[f64] {
        &self.fixed_point.0
    }
}

/// The step plan of an orbit's time series ([`integrate_orbit`]) of period `k` at `plan`'s
/// step: `2 k N` steps from the fixed point, nothing cut. The first `k` revolutions lead in —
/// a restart carries the bodies' displacements only, not the contact forces solved at the
/// fixed point's instant nor a massless stator's deformation from them, which the first step
/// recomputes —, the second `k` (steps `k N … 2 k N`) are written: the orbit once, its first
/// frame on the fixed point `P(x*) = x*` and its last on `P²(x*)`, each to the shooting
/// tolerance.
pub fn series_plan(plan: &StepPlan, k: usize) -> StepPlan {
    StepPlan {
        steps: 2 * k.max(1) * plan.steps_per_rev.max(1),
        steady_from: 0,
        ..*plan
    }
}

/// Integrates the orbit `o` (found on `prep`: its speed and step) from its fixed point over
/// `plan` ([`series_plan`]), handing its frames to `sink`; the record and counters.
///
/// # Errors
/// A state that does not restart the run's scheme; the run's errors.
pub fn integrate_orbit(
    prep: &Prepared,
    o: &PeriodicOrbit,
    plan: &StepPlan,
    sink: Sink<'_>,
) -> Result<(Record, RunStats)> {
    let start = o.start_state().ok_or_else(not_restarted)?;
    Ok(restarted(prep, plan, &start)?.run(sink)?)
}

/// The monodromy `∂P/∂x` of the orbit `o` found on `prep` (its own speed and step) at its
/// fixed point, its fixed point `x`, and the steps the differences took.
///
/// # Errors
/// The map's run errors.
pub(super) fn monodromy(
    prep: &Prepared,
    o: &PeriodicOrbit,
) -> Result<(DMatrix<f64>, Vec<f64>, u64)> {
    let (x, end) = &o.fixed_point;
    let (m, steps) = map::Map::new(prep, o.period, &prep.plan, end.clone()).jacobian(x)?;
    Ok((m, x.clone(), steps))
}

/// The monodromy of the orbit `o` found on `prep` at its fixed point by the variational
/// equations, each step's contact DOFs perturbed by `rel · max |x|`, and the linearisation's
/// counters; `None` where the run's step has no linearisation (a check of the monodromy
/// against [`monodromy_differences`] and of its independence of `rel`).
///
/// # Errors
/// The map's run errors.
pub fn monodromy_variational(
    prep: &Prepared,
    o: &PeriodicOrbit,
    rel: f64,
) -> Result<Option<(DMatrix<f64>, TangentStats)>> {
    let (x, end) = &o.fixed_point;
    let map = map::Map::new(prep, o.period, &prep.plan, end.clone());
    Ok(map.variational(x, rel)?.map(|(m, st, _)| (m, st)))
}

/// The variational monodromy `∂P/∂x` of the map of `prep`'s plan (its steps as they are, at
/// its step) at the state `start` (`x` in [`EndState::state_vector`]'s layout); `None` where
/// the run's step has no linearisation. Pseudo-arclength's map at its fixed steps a
/// revolution (`super::arclength`).
///
/// # Errors
/// A state that does not restart the run's scheme; the run's errors.
pub(super) fn variational_over(prep: &Prepared, start: &EndState) -> Result<Option<DMatrix<f64>>> {
    let x = start.state_vector().ok_or_else(not_restarted)?;
    let map = map::Map::over(prep, &prep.plan, start.clone());
    Ok(map.variational(&x, TANGENT_STEP)?.map(|(m, _, _)| m))
}

/// Which differences of whole maps [`monodromy_differences`] takes: central
/// `(P(x + h eⱼ) − P(x − h eⱼ)) / 2h`, forward `(P(x + h eⱼ) − P(x)) / h` or backward
/// `(P(x) − P(x − h eⱼ)) / h`. At an orbit on a contact event (a grazing or a kink of the map)
/// the two one-sided derivatives differ and the central one is their mean, the derivative of
/// neither side.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Difference {
    /// Centred on `x`: second order where the map is smooth.
    Central,
    /// From `x` towards `+eⱼ`.
    Forward,
    /// From `x` towards `−eⱼ`.
    Backward,
}

/// The monodromy of the orbit `o` found on `prep` at its fixed point by differences
/// (`kind`) of whole maps of relative step `rel` (of max |x|).
///
/// # Errors
/// The map's run errors.
pub fn monodromy_differences(
    prep: &Prepared,
    o: &PeriodicOrbit,
    rel: f64,
    kind: Difference,
) -> Result<DMatrix<f64>> {
    let (x, end) = &o.fixed_point;
    let map = map::Map::new(prep, o.period, &prep.plan, end.clone());
    Ok(map.differences(x, rel, kind)?.0)
}

/// Newton on the `k`-revolution map of `prep` from `x0`, laid out as the orbit `like`'s fixed
/// point (found on `prep`), with that fixed point deflated: Newton on
/// `D(x) (P(x) − x)`, `D(x) = 1/‖x − x_like‖² + 1` (norms scaled by max |x_like|), whose
/// roots are those of `P(x) − x` but `x_like` — so that a start near `x_like` is pushed off
/// it, to another fixed point of the map (Farrell, Birkisson & Funke, SIAM J. Sci. Comput.
/// 2015: deflated Newton). Each step is the Newton step of `P − I` scaled by
/// `1/(1 − ∇D·δ/D)`.
///
/// # Errors
/// As [`shoot`].
pub(super) fn solve_deflated(
    prep: &Prepared,
    k: usize,
    like: &PeriodicOrbit,
    x0: Vec<f64>,
) -> Result<PeriodicOrbit> {
    let root = like.fixed_point.0.clone();
    solve(
        prep,
        k,
        &prep.plan,
        like.fixed_point.1.clone(),
        (x0, Some(&root)),
    )
}

/// The Floquet multipliers of the orbit `o` found on `prep` at the step of `plan`, from its
/// monodromy: variational where the step has its linearisation, else central differences of
/// relative step `rel` (of max |x|; [`FD_STEP`] when shooting) — a larger step removes
/// round-off where the map is affine, an orbit that keeps clear of every contact with its
/// perturbations (the multipliers' refinement) —, and the steps it took.
///
/// # Errors
/// The map's run errors.
pub(super) fn multipliers_at(
    prep: &Prepared,
    o: &PeriodicOrbit,
    plan: &StepPlan,
    rel: f64,
) -> Result<(Vec<[f64; 2]>, u64)> {
    let (x, end) = &o.fixed_point;
    let (m, steps) = map::Map::new(prep, o.period, plan, end.clone()).jacobian_at(x, rel)?;
    Ok((floquet(&m), steps))
}

/// `max |Pᵏ(x) − x| / max |x|` of the `k`-revolution map of `prep` at the fixed point of `o`
/// (found on `prep`), and the steps it took: whether `o` repeats after `k` revolutions already.
///
/// # Errors
/// The map's run errors.
pub(super) fn residual_after(prep: &Prepared, o: &PeriodicOrbit, k: usize) -> Result<(f64, u64)> {
    let (x, end) = &o.fixed_point;
    let map = map::Map::new(prep, k, &prep.plan, end.clone());
    let px = map.apply(x)?;
    Ok((residual(x, &px), map.plan.steps as u64))
}

/// Newton from `x0` (laid out as `end`) on the `k`-revolution map of `prep` at the step of
/// `plan` — with a root deflated when given ([`solve_deflated`]) —, the multipliers at the last
/// iterate and its orbit.
fn solve(
    prep: &Prepared,
    k: usize,
    plan: &StepPlan,
    end: EndState,
    (x0, deflated): (Vec<f64>, Option<&[f64]>),
) -> Result<PeriodicOrbit> {
    let map = map::Map::new(prep, k, plan, end);
    let (x, newton) = map::newton_with_fallback(&map, x0, deflated)?;
    let mut steps = newton.steps;
    let (multipliers, jsteps) = map.multipliers(&x)?;
    steps += jsteps;
    let (monodromy, linearisation) = map.taken.get();
    let (orbit, osteps) = map.orbit(&x, k)?;
    steps += osteps;
    let largest = multipliers.first().map_or(0.0, |r| r[0].hypot(r[1]));
    let instability = (largest >= 1.0).then(|| crossing(multipliers[0], largest));
    Ok(PeriodicOrbit {
        speed_ratio: prep.speed_ratio,
        parameter: prep.speed_ratio,
        period: k,
        converged: newton.converged,
        iterations: newton.iterations,
        residual: newton.residual,
        stable: newton.converged && largest < 1.0,
        largest_modulus: largest,
        instability,
        multipliers,
        orbit: Box::new(orbit),
        state_size: x.len(),
        monodromy,
        linearisation,
        steps,
        fixed_point: (x, map.end),
    })
}

/// How a multiplier `r` of modulus `largest` ≥ 1 leaves the unit circle: `neimark_sacker` (a
/// complex pair), `period_doubling` (real, negative) or `fold` (real, positive).
pub(crate) fn crossing(r: [f64; 2], largest: f64) -> &'static str {
    if r[1].abs() > 1e-9 * largest {
        "neimark_sacker"
    } else if r[0] < 0.0 {
        "period_doubling"
    } else {
        "fold"
    }
}

/// The components of the state vector of `p`'s runs ([`EndState::state_vector`]: the rotor's
/// and each stator's with mass), taken from two steps of its scheme; `None` for an implicit
/// scheme.
///
/// # Errors
/// The two steps' run errors.
pub(super) fn state_size(p: &Prepared) -> Result<Option<usize>> {
    let plan = StepPlan {
        steps: 2,
        steady_from: 0,
        ..p.plan
    };
    let mut st = stepper(p, &plan)?;
    Ok(run_to_end(&mut st, 2)?
        .and_then(|e| e.state_vector())
        .map(|x| x.len()))
}

/// The error of a state that does not restart the run's scheme at its own step.
fn not_restarted() -> Error {
    Error::study(
        "run.integrator",
        "the run's state does not restart at its own step".to_string(),
    )
}

/// A stepper of `p`'s case, scheme and start on `plan`.
pub(super) fn stepper<'a>(p: &'a Prepared, plan: &StepPlan) -> Result<Stepper<'a>> {
    Ok(Stepper::new(
        &p.case,
        p.request.step.integrator,
        plan,
        p.request.initial(),
    )?)
}

/// A stepper of `p`'s case and scheme on `plan`, restarted from `start` (taken at `plan`'s
/// step: [`Stepper::restart`] then keeps it as it is).
pub(super) fn restarted<'a>(
    p: &'a Prepared,
    plan: &StepPlan,
    start: &EndState,
) -> Result<Stepper<'a>> {
    let mut st = stepper(p, plan)?;
    if !st.restart(start) {
        return Err(not_restarted());
    }
    Ok(st)
}

/// The state vector ([`EndState::state_vector`]) after `plan.steps` steps of `p` from `start`.
pub(super) fn end_after(p: &Prepared, plan: &StepPlan, start: &EndState) -> Result<Vec<f64>> {
    let mut st = restarted(p, plan, start)?;
    run_to_end(&mut st, plan.steps)?
        .and_then(|e| e.state_vector())
        .ok_or_else(|| Error::study("run", "the map's end state could not be taken".to_string()))
}

/// Runs `st` to step `n` and takes its end state there (the history one step before kept for
/// it); `None` when it cannot be taken ([`Stepper::end_state`]).
pub(super) fn run_to_end(st: &mut Stepper<'_>, n: usize) -> Result<Option<EndState>> {
    st.run_to(n - 1, &mut None)?;
    let older = st.history();
    st.run_to(n, &mut None)?;
    Ok(st.end_state(&older))
}

/// The orbit of `p` from `start` over `6 k` revolutions of `plan`'s step, analysed as a steady
/// window (extents, lines, contact fraction).
pub(super) fn orbit_from(
    p: &Prepared,
    plan: &StepPlan,
    start: &EndState,
    k: usize,
) -> Result<SpeedResults> {
    let plan = StepPlan {
        steps: 6 * k * plan.steps_per_rev.max(1),
        steady_from: 0,
        ..*plan
    };
    let (rec, stats) = restarted(p, &plan, start)?.run(None)?;
    let mut s = p.request;
    s.step.revolutions = 6 * k;
    s.step.transient_revolutions = 0;
    Ok(analyse(&p.case, &s, &plan, &rec, stats, Keep::default()))
}

/// The eigenvalues `[Re ρ, Im ρ]` of a monodromy matrix `m`, largest modulus first.
pub(super) fn floquet(m: &DMatrix<f64>) -> Vec<[f64; 2]> {
    let mut rho: Vec<[f64; 2]> = m
        .complex_eigenvalues()
        .iter()
        .map(|c| [c.re, c.im])
        .collect();
    rho.sort_by(|a, b| b[0].hypot(b[1]).total_cmp(&a[0].hypot(a[1])));
    rho
}

/// `max |P(x) − x| / max |x|` (∞ for a non-finite map): also the distance of a state `px`
/// from `x` relative to `x`'s size.
pub(super) fn residual(x: &[f64], px: &[f64]) -> f64 {
    let scale = x.iter().fold(0.0_f64, |m, v| m.max(v.abs())).max(1e-300);
    let d = x
        .iter()
        .zip(px)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    if d.is_finite() {
        d / scale
    } else {
        f64::INFINITY
    }
}
