//! The integrator and Δt chosen from `run.tolerance` (issue 11, item 1): pilot runs on a short
//! window at three steps, the observed order, the step that meets the target with a safety
//! factor within the stability limit (explicit) or the accuracy limit (implicit), and the
//! cheaper scheme for it.
//!
//! # Method
//!
//! For each candidate scheme (`run.integrator` when the scene gives one, else collocated,
//! forward increment and generalised-α, ρ∞ = [`crate::scene::DEFAULT_RHO_INF`], or 0 with a
//! stator with mass, [`super::default_rho_inf`]) and each pilot speed
//! ([`pilot_speeds`]: a single run's speed; a sweep's first, middle and last):
//!
//! 1. the coarsest step the scheme allows — 0.8× the explicit stability limit, or `T_min/4`
//!    for an implicit scheme, and at most one step per recorded sample — then its halves
//!    (whole samples per revolution): three steps, more (up to [`MAX_LEVELS`]) until the last
//!    three show an order near the scheme's own (`p_obs ≥ `[`ASYMPTOTIC`]` · p_nominal`) and
//!    either the finest one's error `E₂` (as in 4) is within the target or they converge
//!    (`d₁₂ < d₀₁/`[`CONVERGING`]) asking a step at most [`MAX_EXTRAPOLATION`] below the
//!    finest; `h₀ > h₁ > h₂` the last three. A lower observed order is the coarse pilots'
//!    pre-asymptotic range, not the order below them: on `diaphragm` forward increment's
//!    error is not monotone up to 512 steps/rev at ν = 2 and of order 1 beyond, and at ν = 1.3
//!    the differences shrink at order 0.65 up to 2048 steps/rev and stop at a 1e-4 floor
//!    beyond; the fit on the first three pilots chose a step 2.6× finer than needed;
//! 2. a pilot run at each over a steady window, analysed as a run is (orbit extents and the 1×,
//!    ½×, ⅓× lines, relative as the error estimate makes them: [`difference`]). Where the
//!    rotor's state is its disk's `[x, y]` and velocity (a Jeffcott rotor, every stator
//!    massless: the stator scenes), one settling run at the second pilot step over
//!    `min(run.transient_revolutions, `[`SETTLE_REVOLUTIONS`]`)` revolutions from the run's
//!    initial state gives the state at a whole revolution (`settled_start`); the first pilot
//!    starts from it, each finer one from where the previous ended (a whole revolution: its
//!    start is off its own steady state by the step's change only, not by the settling step's
//!    error, which left a residue of 2e-4 in the finest pilots' extents on `diaphragm`), and
//!    each analyses [`PILOT_WINDOW`] revolutions after [`PILOT_RESETTLE`]: the
//!    pilots measure the step's error on the steady response the run analyses, not on the
//!    first revolutions from rest. Otherwise — and where the pilots from the settled state do
//!    not converge (observed order below [`MIN_ORDER`], error above the target at the finest
//!    step allowed: a response that is not periodic) — the pilots start as the run does and
//!    analyse [`PILOT_WINDOW`] revolutions after [`PILOT_TRANSIENT`];
//! 3. the observed order `p_obs = log(d₀₁/d₁₂)/log(h₁/h₂)`, `dᵢⱼ` the differences of
//!    successive pilots; the order used `p = clamp(p_obs, ½, p_nominal)` (a smaller order
//!    predicts a larger error below the pilots' steps: the clamp errs on the safe side);
//! 4. the error of the finest pilot `E₂ = d₁₂/((h₁/h₂)^p − 1)`, its constant `C = E₂/h₂^p`,
//!    and the step: the coarsest of `h₀, h₁, h₂` (within the bounds below) whose fitted error
//!    `C·h^p` is within the tolerance — a step the pilots ran, so the run repeats a measured
//!    pilot over a longer window and on the response that pilot was on (on
//!    `segmented_casing_beams` at ν = 3 an extrapolated 576 steps/rev instead of the piloted
//!    512 ran to a response 0.11 off its Δt/8 reference) — else
//!    `h* = (S·tol/C)^{1/p}` with the safety factor `S` = [`SAFETY`], at most `h₀`
//!    (no extrapolation above the steps that showed the order), at most the coarsest pilot
//!    step from which on the run's own 2Δt estimate, measured between the pilots
//!    (`d(h, 2h)/(2^p_nominal − 1)`), is within [`ESTIMATE_SAFETY`] × the tolerance (the
//!    estimate the run reports agrees with the choice; measured, not extrapolated, so with a
//!    smaller margin than `S`), and at least `h₂/`[`MAX_EXTRAPOLATION`]: a fit on differences
//!    that barely shrink (observed orders near 0: the node-to-node contact's events, a
//!    response that is not periodic) asked 1.4·10⁹ steps of `segmented_casing` before the
//!    pilots went on towards the step; where the bound binds, the predicted error at it is
//!    above the target and reported (`error_predicted`), and the run's estimate says the rest.
//!
//! Where the pilots predict that the paper's rule (Δt of `run.harmonics`) meets the tolerance
//! itself, a step finer than the rule is not asked for: the rule is the validated default
//! (docs/VALIDATION.md) and the safety factor only guards a step the pilots extrapolate to.
//!
//! The step is kept as a multiple of the paper's rule (`StepParams::dt_scale`, the smallest
//! over the pilot speeds), so the other speeds of a sweep take the same fraction of their own
//! rule. Each scheme's cost is its steps per revolution at the pilot speeds times its cost per
//! step (the budget's cost model, [`crate::time::estimate`]: the schemes' steps cost the same
//! within the pilots' timing noise, 124–158 ns on the paper's Jeffcott rotor and rod); of the
//! schemes predicted to meet the tolerance (all of them when none is) the cheapest wins, the
//! first candidate on a tie. A scheme whose coarsest step already costs more than the best found is not piloted.
//! The pilots' steps and wall time are counted and reported ([`StepChoice`]).
//!
//! # Reduced schemes
//!
//! An FE rotor or a meshed stator with mass can be integrated in its modal reduction
//! (docs/IMPLICIT.md §7). Where the scene gives no `[run.reduction]`, the candidates' implicit
//! and collocated schemes are candidates again on the reduced model (`RunSettings::reduction`),
//! after the full model's: their cut-off factor κ is chosen from the tolerance first
//! ([`super::cutoff::choose_cutoff`], the truncation taking at most a quarter of it), their
//! pilots run the reduced model, and the predicted error they must meet is the step's plus the
//! truncation indicator. A reduced scheme is chosen when it is predicted to meet the tolerance
//! cheaper (its cost per step by the reduced DOFs, its step by the reduced model's stability
//! limit). Where the scene gives `[run.reduction]` without a cut-off, every candidate runs
//! reduced with κ chosen so; with a cut-off, as the scene reduces it.

use super::cutoff::{choose_cutoff, CutoffChoice};
pub use super::discrepancy::difference;
use super::pilot::pilot_settings;
pub use super::pilot::{PILOT_TRANSIENT, PILOT_WINDOW};
use super::{analyse, prepare, scheme, sweep::run_all, Keep, RunSettings, SpeedResults};
use crate::error::{Error, Result, SolveError};
use crate::model::{Model, Rotor};
use crate::resolve::ReductionInput;
use crate::scene::IntegratorKind;
use crate::time::{estimate, integrate, plan_steps, Initial, Scheme};
use serde::{Deserialize, Serialize};

mod start;
pub use start::{pilot_start, start_from_pilot, PilotStart, RESTART_TRANSIENT};

/// Revolutions of a pilot started from the settled state before its analysed window: the
/// pilot step's own start-up (its velocity estimate) settles in them.
pub const PILOT_RESETTLE: usize = 2;
/// Most revolutions of the settling run (`settled_start`).
pub const SETTLE_REVOLUTIONS: usize = 30;
/// The smallest order the step is chosen with (`p = clamp(p_obs, MIN_ORDER, p_nominal)`): a
/// smaller observed order is taken as this one, bounded by [`MAX_EXTRAPOLATION`].
pub const MIN_ORDER: f64 = 0.5;
/// The chosen step's predicted error is this fraction of `run.tolerance`.
pub const SAFETY: f64 = 0.5;
/// Most pilot steps per scheme and speed (the coarsest and six halvings).
pub const MAX_LEVELS: usize = 7;
/// The last three pilots show convergence when their second difference is below the first over
/// this factor (an observed order above log₂ 1.5 ≈ 0.58).
pub const CONVERGING: f64 = 1.5;
/// The furthest below the finest pilot step a fitted order is extrapolated: a fit asking a
/// finer step pilots on (up to [`MAX_LEVELS`]), so the order that sets the step is observed
/// near it (on `segmented_casing` three pilots from 64 steps/rev fitted 0.68 on differences
/// that did not shrink further, and asked 150× below them).
pub const MAX_EXTRAPOLATION: f64 = 4.0;
/// The pilots' order fit is taken as asymptotic (trusted to extrapolate below the finest
/// pilot) from this fraction of the scheme's nominal order on.
pub const ASYMPTOTIC: f64 = 0.9;
/// The chosen step is at most the coarsest pilot step from which on the run's own 2Δt
/// estimate, as the pilots measure it, is within this fraction of `run.tolerance`: a measured
/// (not extrapolated) error, so a smaller margin than [`SAFETY`] (the 6-revolution pilot
/// window standing in for the run's).
pub const ESTIMATE_SAFETY: f64 = 0.8;
/// A multiple of the rule large enough that only the caps (stability, accuracy, one step per
/// sample) bound the step: the coarsest step a scheme allows.
const COARSEST: f64 = 1e12;

/// What the error-target choice settled on, reported with every run it chose for.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StepChoice {
    /// The chosen integrator.
    pub integrator: IntegratorKind,
    /// Δt as a multiple of the paper's rule (`StepParams::dt_scale`).
    pub dt_scale: f64,
    /// Observed order of the chosen scheme (fitted on the pilots; the smallest over the pilot
    /// speeds); NaN when the pilots did not differ.
    pub order_observed: f64,
    /// Order the step was chosen with, `clamp(order_observed, ½, nominal)`.
    pub order_used: f64,
    /// Predicted relative error (extents and lines) at the chosen step, the largest over the
    /// pilot speeds (above the tolerance where the step is bounded by
    /// [`MAX_EXTRAPOLATION`] below the finest pilot).
    pub error_predicted: f64,
    /// The tolerance aimed at (`run.tolerance`).
    pub tolerance: f64,
    /// Pilot speeds ω/ω_n: how many, the first and the last.
    pub pilot_speeds: usize,
    /// Steps of every pilot run together.
    pub pilot_steps: u64,
    /// Wall time of the pilots' loops together (s).
    pub pilot_wall_s: f64,
    /// Schemes piloted.
    pub schemes_piloted: usize,
    /// The cut-off chosen from the tolerance when the chosen scheme integrates a reduced model
    /// with it (its truncation error indicator is in `error_predicted`); `None` otherwise.
    #[serde(default)]
    pub reduction: Option<CutoffChoice>,
    /// The state the chosen scheme's pilots ended in at each pilot speed (a whole revolution;
    /// pilots from the settled state only), from which the run at that speed starts
    /// ([`start_from_pilot`]). Not written out.
    #[serde(skip)]
    pub starts: [Option<PilotStart>; 3],
}

/// The pilot speeds of a run over `speeds`: all of up to two speeds, else the first, the
/// middle and the last.
pub fn pilot_speeds(speeds: &[f64]) -> Vec<f64> {
    match speeds.len() {
        0..=2 => speeds.to_vec(),
        n => vec![speeds[0], speeds[n / 2], speeds[n - 1]],
    }
}

/// One scheme's fit at one speed.
#[derive(Debug, Clone, Copy)]
struct Fit {
    /// Observed order (NaN when undefined).
    p_obs: f64,
    /// Order used.
    p: f64,
    /// Error constant: error ≈ c·h^p.
    c: f64,
    /// The finest step the choice may take (s): [`MAX_EXTRAPOLATION`] below the finest pilot.
    h_min: f64,
    /// Whether the pilots started from the settled state.
    settled: bool,
    /// The finest pilot's end state (pilots from the settled state only).
    end: Option<Initial>,
    /// The paper's rule at this speed (s).
    rule_dt: f64,
    /// The coarsest step the choice may take (s): the coarsest of the three pilots fitted (no
    /// extrapolation above the steps that showed the order), and no coarser than the pilot
    /// step from which on the 2Δt estimate the run will make, as the pilots measure it, is
    /// within the target.
    h0: f64,
    /// The steps of the three pilots fitted (s), coarsest first.
    levels: [f64; 3],
    /// Pilot steps and loop wall time.
    steps: u64,
    wall_s: f64,
}

impl Fit {
    /// The multiple of the rule of the step chosen: the coarsest of the fitted pilots' steps
    /// (at most `h0`) whose fitted error is within `tolerance` — a step the pilots ran, so
    /// the run repeats a measured pilot over a longer window rather than an extrapolated
    /// step — else the step whose extrapolated error is `target` (within `h_min … h0`).
    fn scale_for(&self, target: f64, tolerance: f64) -> f64 {
        let piloted = self
            .levels
            .iter()
            .find(|&&h| h <= self.h0 * (1.0 + 1e-9) && self.error_at(h) <= tolerance);
        if let (Some(&h), true) = (piloted, self.c > 0.0) {
            return h / self.rule_dt;
        }
        let h = if self.c > 0.0 {
            (target / self.c)
                .powf(1.0 / self.p)
                .min(self.h0)
                .max(self.h_min)
        } else {
            self.h0
        };
        h / self.rule_dt
    }
    fn error_at(&self, h: f64) -> f64 {
        self.c * h.powf(self.p)
    }
}

/// The settled state the pilots start from: the run from `s.initial` with the plan of
/// `settle` (whole steps per revolution) over `min(s`'s transient, [`SETTLE_REVOLUTIONS`]`)`
/// revolutions, its disk displacement at the last instant (a whole revolution: the unbalance
/// at the phase of t = 0) and velocity by the one-sided second-order difference of the last
/// three samples `(3x_N − 4x_{N−1} + x_{N−2})/(2δ)`, δ the sampling interval. `None` where
/// that is not the whole state: a rotor with more than the disk's two DOFs, a stator with
/// mass. Returned with the settling run's steps and loop wall time (s).
fn settled_start(
    prep: &super::Prepared,
    s: &RunSettings,
    settle: f64,
) -> Result<Option<(Initial, u64, f64)>> {
    let case = &prep.case;
    if case.loop_rotor().ndof != 2 || !case.stators.iter().all(|st| st.massless()) {
        return Ok(None);
    }
    let mut st = prep.settings.step;
    st.dt_scale = settle;
    st.revolutions = s.step.transient_revolutions.clamp(1, SETTLE_REVOLUTIONS);
    st.transient_revolutions = 0;
    let plan = plan_steps(case, &st)?;
    let (rec, stats) = integrate(case, st.integrator, &plan, s.initial)?;
    Ok(end_state(&rec).map(|init| (init, stats.steps as u64, stats.wall_s)))
}

/// The disk's state at the last recorded instant of `rec`: displacement as recorded, velocity
/// by the one-sided second-order difference of the last three samples
/// `(3x_N − 4x_{N−1} + x_{N−2})/(2δ)`, δ the sampling interval. `None` with fewer than three
/// samples.
fn end_state(rec: &crate::time::Record) -> Option<Initial> {
    let n = rec.observed.len();
    if n < 3 || rec.t.len() != n {
        return None;
    }
    let (a, b, c) = (
        rec.observed[n - 3],
        rec.observed[n - 2],
        rec.observed[n - 1],
    );
    let d = rec.t[n - 1] - rec.t[n - 2];
    let v = [0, 1].map(|i| (3.0 * c[i] - 4.0 * b[i] + a[i]) / (2.0 * d));
    Some(Initial { u: c, v })
}

/// Pilots `kind` at speed `v` at halving steps from the coarsest it allows — three, and more
/// (up to [`MAX_LEVELS`]) while the finest one's error is above `target` and the last three
/// show no convergence (`d₁₂ ≥ d₀₁/`[`CONVERGING`]) or ask a step more than
/// [`MAX_EXTRAPOLATION`] below the finest — from the settled state where there is one
/// ([`settled_start`]), and fits its order and error constant on the last three.
fn fit(model: &Model, s: &RunSettings, kind: Scheme, v: f64, target: f64) -> Result<Fit> {
    let f = fit_from(model, s, kind, v, target, true)?;
    // From the settled state the pilots did not converge (a response that is not periodic
    // there: the paper's rod at ε = 10⁵, ν = 1.5): piloted again from the run's start, as the
    // run begins, whose fit is used (both pilots counted).
    if f.settled && f.p_obs.is_finite() && f.p_obs < MIN_ORDER && f.error_at(f.h_min) > target {
        let g = fit_from(model, s, kind, v, target, false)?;
        return Ok(Fit {
            steps: f.steps + g.steps,
            end: None,
            wall_s: f.wall_s + g.wall_s,
            ..g
        });
    }
    Ok(f)
}

/// [`fit`]'s pilots, from the settled state when `settled` and there is one, else from the
/// run's start.
fn fit_from(
    model: &Model,
    s: &RunSettings,
    kind: Scheme,
    v: f64,
    target: f64,
    settled: bool,
) -> Result<Fit> {
    let mut ps = pilot_settings(s, kind, COARSEST);
    let mut prep = prepare(model, &ps, v)?;
    let coarsest = prep.plan.dt;
    let rule_dt = prep.plan.rule_dt;
    let settle = coarsest / rule_dt / 2.0 * (1.0 + 1e-9);
    let (mut steps, mut wall_s) = (0u64, 0.0);
    let start = if settled {
        settled_start(&prep, s, settle)?
    } else {
        None
    };
    let from_settled = start.is_some();
    if let Some((init, n, w)) = start {
        ps.initial = init;
        steps += n;
        wall_s += w;
        ps.step.transient_revolutions = PILOT_RESETTLE;
        ps.step.revolutions = PILOT_RESETTLE + PILOT_WINDOW;
        prep = prepare(model, &ps, v)?;
    }
    let mut res: Vec<(f64, SpeedResults)> = Vec::with_capacity(MAX_LEVELS);
    let mut k = 0;
    let (d01, d12) = loop {
        let mut st = ps.step;
        st.dt_scale = coarsest / rule_dt / (1u64 << k) as f64 * (1.0 + 1e-9);
        prep.plan = plan_steps(&prep.case, &st)?;
        let (rec, stats) = prep.integrate(&mut [])?;
        steps += stats.steps as u64;
        wall_s += stats.wall_s;
        let r = analyse(&prep.case, &ps, &prep.plan, &rec, stats, Keep::default());
        // From the settled state, the next (finer) pilot starts where this one ended (a whole
        // revolution): its start differs from its own steady state only by the step's change,
        // not by the settling step's error.
        if from_settled {
            if let Some(init) = end_state(&rec) {
                prep.settings.initial = init;
            }
        }
        res.push((prep.plan.dt, r));
        k += 1;
        let n = res.len();
        if n < 3 {
            continue;
        }
        let d01 = difference(&res[n - 3].1, &res[n - 2].1);
        let d12 = difference(&res[n - 2].1, &res[n - 1].1);
        // The finest pilot's error by the order as it will be used: within the target, or
        // converging with the step it asks within [`MAX_EXTRAPOLATION`] of the finest pilot,
        // the fit is used; otherwise the pilots go on towards that step.
        let r = res[n - 2].0 / res[n - 1].0;
        let p_raw = (d01 / d12).ln() / r.ln();
        let p = p_raw.clamp(MIN_ORDER, kind.nominal_order());
        let e2 = if p.is_finite() {
            d12 / (r.powf(p) - 1.0)
        } else {
            0.0
        };
        // The fit is used only on an order near the scheme's own: a lower observed order is
        // the coarse pilots' pre-asymptotic range (on `diaphragm` at ν = 2 forward
        // increment's error is not monotone up to 512 steps/rev and of order 1 beyond; at
        // ν = 1.3 the differences shrink at order 0.65 up to 2048 steps/rev and are at a
        // 1e-4 floor beyond), so the pilots go on halving (up to [`MAX_LEVELS`]).
        let asymptotic = p_raw >= ASYMPTOTIC * kind.nominal_order();
        let near = (target / e2).powf(1.0 / p) * MAX_EXTRAPOLATION >= 1.0;
        if n >= MAX_LEVELS
            || e2 == 0.0
            || (asymptotic && (e2 <= target || (d12 * CONVERGING < d01 && near)))
        {
            break (d01, d12);
        }
    };
    let n = res.len();
    let (h0, h1, h2) = (res[n - 3].0, res[n - 2].0, res[n - 1].0);
    let ratio = h1 / h2;
    let nominal = kind.nominal_order();
    // The run's own 2Δt estimate at a pilot step, d(h, 2h)/(2^p_nominal − 1), as measured: the
    // step may not exceed the coarsest pilot step from which on every such estimate is within
    // the target.
    let mut cap = h2;
    for k in (1..n).rev() {
        let r = res[k - 1].0 / res[k].0;
        let est = difference(&res[k - 1].1, &res[k].1) / (r.powf(nominal) - 1.0);
        if est > ESTIMATE_SAFETY * s.tolerance {
            break;
        }
        cap = res[k].0;
    }
    let p_obs = (d01 / d12).ln() / ratio.ln();
    let p = if p_obs.is_finite() {
        p_obs.clamp(MIN_ORDER, nominal)
    } else {
        nominal
    };
    let p_obs = if p_obs.is_finite() { p_obs } else { f64::NAN };
    let e2 = if d12 > 0.0 {
        d12 / (ratio.powf(p) - 1.0)
    } else {
        0.0
    };
    Ok(Fit {
        p_obs,
        p,
        c: e2 / h2.powf(p),
        rule_dt,
        h0: h0.min(cap),
        levels: [h0, h1, h2],
        h_min: h2 / MAX_EXTRAPOLATION,
        settled: from_settled,
        end: from_settled.then_some(prep.settings.initial),
        steps,
        wall_s,
    })
}

/// A scheme's outcome over the pilot speeds.
struct Outcome {
    kind: IntegratorKind,
    /// The reduction its runs integrate (`RunSettings::reduction`).
    reduction: Option<(ReductionInput, CutoffChoice)>,
    fits: Vec<Fit>,
    scale: f64,
    cost: f64,
    /// Whether the predicted error at `scale` is within the tolerance at every pilot speed.
    meets: bool,
}

/// The candidate schemes: the scene's integrator, or the three that take any scene — without
/// generalised-α on a ring with mass, where its pilots under-predict its error: on
/// `tests/data/scenes/ring.toml` at 1.7 ω_n they predict 6.0e-4 at the paper's rule and the
/// run is 1.04e-3 off the converged explicit one in extents (`run.tolerance` 1e-3), while
/// collocated's prediction holds. The scene can still name it (`run.integrator`).
fn candidates(model: &Model, run_integrator: Option<IntegratorKind>) -> Vec<IntegratorKind> {
    let ring_with_mass = super::has_ring_with_mass(model);
    match run_integrator {
        Some(k) => vec![k],
        None if ring_with_mass => {
            vec![IntegratorKind::Collocated, IntegratorKind::ForwardIncrement]
        }
        None => vec![
            IntegratorKind::Collocated,
            IntegratorKind::ForwardIncrement,
            IntegratorKind::GeneralizedAlpha,
        ],
    }
}

/// The reduction the reduced candidates would run (κ to be chosen), when the scene gives none:
/// the FE rotor (when its K admits static columns) and every meshed stator with mass; `None`
/// when there is nothing to reduce.
fn reducible(model: &Model, s: &RunSettings, v: f64) -> Option<ReductionInput> {
    let case = model.case(v * model.rotor.natural_frequency()).ok()?;
    let stators = case
        .stators
        .iter()
        .any(|st| !st.massless() && st.mesh.is_some());
    let rotor = matches!(model.rotor, Rotor::Fe(_)) && case.clone().reduce(1.0).is_ok();
    (rotor || stators).then_some(ReductionInput {
        cutoff: None,
        cutoff_factor: crate::scene::DEFAULT_CUTOFF_FACTOR,
        harmonics: s.step.harmonics,
        rotor,
        stators,
        auto: true,
    })
}

/// Cost (s) of one revolution at each pilot speed of `kind` at `scale`, summed.
fn cost(model: &Model, s: &RunSettings, kind: Scheme, speeds: &[f64], scale: f64) -> Result<f64> {
    let mut total = 0.0;
    for &v in speeds {
        let prep = prepare(model, &pilot_settings(s, kind, scale), v)?;
        let b = estimate(&prep.case, &prep.plan, false);
        total += b.step_s * prep.plan.steps_per_rev as f64;
    }
    Ok(total)
}

/// Chooses the integrator (unless `run_integrator` names one) and Δt of runs of `model` at
/// `speeds` from `s.tolerance`, and returns `s` with them set (`step.integrator`,
/// `step.dt_scale`, `choice`). Settings with a `dt` are returned unchanged.
///
/// # Errors
/// [`SolveError::ToleranceUnreachable`] when no scheme meets the tolerance within
/// `run.max_steps`, naming `run.tolerance`; a model error of a pilot speed's case.
pub fn choose(
    model: &Model,
    s: &RunSettings,
    run_integrator: Option<IntegratorKind>,
    rho_inf: Option<f64>,
    speeds: &[f64],
) -> Result<RunSettings> {
    if s.step.dt.is_some() || speeds.is_empty() {
        return Ok(*s);
    }
    let pilots = pilot_speeds(speeds);
    let target = SAFETY * s.tolerance;
    let rho = match rho_inf {
        Some(r) => Some(r),
        None => {
            let w = pilots[0] * model.rotor.natural_frequency();
            Some(super::default_rho_inf(&model.case(w)?))
        }
    };
    // The candidates in their order (the first wins a tie), each with the cost of its coarsest
    // step: a scheme that cannot beat the best found is not piloted.
    // A scheme that cannot even be planned keeps its reason: when none can, that reason (a
    // speed, clearance or stator the run itself would refuse, naming its key) is the error.
    let mut order = Vec::new();
    let mut last_err: Option<Error> = None;
    let (mut pilot_steps, mut pilot_wall, mut piloted) = (0u64, 0.0, 0usize);
    let kinds = candidates(model, run_integrator);
    // The reduction with κ from the tolerance: the scene's when it gives no cut-off (every
    // candidate runs it), else the one the reduced candidates would run; chosen when first
    // needed (a reduced candidate that cannot beat the best found costs no pilots).
    let scene_red = s.reduction_of(model).copied();
    let mut auto_red: Option<Option<(ReductionInput, CutoffChoice)>> = None;
    let reduced_base = match scene_red {
        Some(r) if r.auto => Some(r),
        Some(_) => None,
        None => reducible(model, s, pilots[0]),
    };
    let mut choose_red = |steps: &mut u64, wall: &mut f64| {
        if auto_red.is_none() {
            let c = reduced_base.and_then(|base| {
                let c = choose_cutoff(model, s, base, &pilots, rho).ok()?;
                *steps += c.pilot_steps;
                *wall += c.pilot_wall_s;
                Some((
                    ReductionInput {
                        cutoff: None,
                        cutoff_factor: c.cutoff_factor,
                        auto: false,
                        ..base
                    },
                    c,
                ))
            });
            auto_red = Some(c);
        }
        auto_red.flatten()
    };
    let scene_auto = scene_red.is_some_and(|r| r.auto);
    let mut variants: Vec<(IntegratorKind, bool)> =
        kinds.iter().map(|k| (*k, scene_auto)).collect();
    if scene_red.is_none() && reduced_base.is_some() {
        let reduced = kinds
            .iter()
            .filter(|k| kinds.len() == 1 || **k != IntegratorKind::ForwardIncrement);
        variants.extend(reduced.map(|k| (*k, true)));
    }
    for (kind, reduced) in variants {
        let sch = scheme(kind, rho);
        // The floor of a reduced candidate: its cost at the default κ (a larger κ costs more).
        let sr = if reduced {
            let base = reduced_base.map(|b| ReductionInput {
                cutoff: None,
                cutoff_factor: crate::scene::DEFAULT_CUTOFF_FACTOR,
                auto: false,
                ..b
            });
            RunSettings {
                reduction: base,
                ..*s
            }
        } else {
            *s
        };
        match cost(model, &sr, sch, &pilots, COARSEST) {
            Ok(c) => order.push((kind, reduced, c)),
            Err(e) => {
                last_err.get_or_insert(e);
            }
        }
    }
    let mut best: Option<Outcome> = None;
    for (kind, reduced, floor) in order {
        if best.as_ref().is_some_and(|b| b.meets && b.cost <= floor) {
            continue;
        }
        let sch = scheme(kind, rho);
        let red = if reduced {
            match choose_red(&mut pilot_steps, &mut pilot_wall) {
                Some(r) => Some(r),
                None => continue,
            }
        } else {
            None
        };
        let s = &RunSettings {
            reduction: red.map(|r| r.0).or(s.reduction),
            ..*s
        };
        let trunc = red.map_or(0.0, |r| r.1.truncation_error);
        let fits = run_all(&pilots, &|&v| fit(model, s, sch, v, target), &|| {});
        let fits = match fits {
            Ok(f) => f,
            Err(e) => {
                last_err = Some(e);
                continue;
            }
        };
        piloted += 1;
        pilot_steps += fits.iter().map(|f| f.steps).sum::<u64>();
        pilot_wall += fits.iter().map(|f| f.wall_s).sum::<f64>();
        let mut scale = fits
            .iter()
            .map(|f| f.scale_for(target, s.tolerance))
            .fold(f64::INFINITY, f64::min);
        // The paper's rule is kept where the pilots predict it meets the tolerance itself.
        let rule_meets = fits
            .iter()
            .all(|f| f.error_at(f.rule_dt.min(f.h0)) <= s.tolerance);
        if scale < 1.0 && rule_meets {
            scale = 1.0;
        }
        let c = match cost(model, s, sch, &pilots, scale) {
            Ok(c) => c,
            Err(e) => {
                last_err = Some(unreachable(s.tolerance, sch, e));
                continue;
            }
        };
        // A scheme predicted to meet the tolerance beats one that is not (a step bounded by
        // `MAX_EXTRAPOLATION` on pilots that did not converge), then the cheaper one.
        let meets = fits
            .iter()
            .all(|f| f.error_at((scale * f.rule_dt).min(f.h0)) + trunc <= s.tolerance);
        if best
            .as_ref()
            .is_none_or(|b| (meets && !b.meets) || (meets == b.meets && c < b.cost))
        {
            best = Some(Outcome {
                kind,
                reduction: red,
                fits,
                scale,
                cost: c,
                meets,
            });
        }
    }
    let Some(b) = best else {
        return Err(last_err.unwrap_or_else(|| {
            SolveError::ToleranceUnreachable {
                tolerance: s.tolerance,
                detail: "no integrator could be piloted".into(),
            }
            .into()
        }));
    };
    let mut out = *s;
    out.step.integrator = scheme(b.kind, rho);
    out.step.dt_scale = b.scale;
    if let Some((r, _)) = b.reduction {
        out.reduction = Some(r);
    }
    check_budget(model, &out, speeds)?;
    let trunc = b.reduction.map_or(0.0, |r| r.1.truncation_error);
    let error_predicted = b
        .fits
        .iter()
        .map(|f| f.error_at((b.scale * f.rule_dt).min(f.h0)) + trunc)
        .fold(0.0, f64::max);
    let order_observed = b.fits.iter().map(|f| f.p_obs).fold(f64::NAN, f64::min);
    out.choice = Some(StepChoice {
        integrator: b.kind,
        dt_scale: b.scale,
        order_observed,
        order_used: b.fits.iter().map(|f| f.p).fold(f64::INFINITY, f64::min),
        error_predicted,
        tolerance: s.tolerance,
        pilot_speeds: pilots.len(),
        pilot_steps,
        pilot_wall_s: pilot_wall,
        schemes_piloted: piloted,
        reduction: b.reduction.map(|r| r.1),
        starts: std::array::from_fn(|i| {
            let (v, f) = (pilots.get(i)?, b.fits.get(i)?);
            f.end.map(|initial| PilotStart {
                speed_ratio: *v,
                initial,
            })
        }),
    });
    Ok(out)
}

/// A plan refused for its steps, as the tolerance that asked for them; other errors as they
/// are.
fn unreachable(tolerance: f64, kind: Scheme, e: Error) -> Error {
    match e {
        Error::Solve(SolveError::TooManySteps {
            steps, dt, max, ..
        }) => SolveError::ToleranceUnreachable {
            tolerance,
            detail: format!(
                "the {} integrator needs Δt = {dt:.3e} s for it, {steps:.3e} steps, above `run.max_steps` = {max}; raise `run.tolerance` or `run.max_steps`, or give `run.dt`",
                kind.name()
            ),
        }
        .into(),
        e => e,
    }
}

/// Refuses a choice whose runs at the sweep's ends need more than `run.max_steps` steps,
/// naming `run.tolerance`.
fn check_budget(model: &Model, s: &RunSettings, speeds: &[f64]) -> Result<()> {
    let ends = [speeds[0], speeds[speeds.len() - 1]];
    for v in ends {
        let omega = v * model.rotor.natural_frequency();
        let case = model.case_with(omega, s.reduction_of(model))?;
        if let Err(e) = plan_steps(&case, &s.step) {
            return Err(unreachable(s.tolerance, s.step.integrator, e.into()));
        }
    }
    Ok(())
}
