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
//! first candidate on a tie. The schemes are piloted cheapest coarsest step first, and one
//! whose coarsest step already costs more than the best found (or as much, after it) is not
//! piloted: on the FE paper rotor the reduced collocated scheme is piloted first
//! and the full schemes are not.
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
pub use super::pilot::{PILOT_TRANSIENT, PILOT_WINDOW};
pub use super::request::{PilotStart, PILOT_RESETTLE, RESTART_TRANSIENT};
use super::{prepare, scheme, sweep::run_all, RunRequest, RunSettings};
use crate::error::{Error, Result, SolveError};
use crate::model::{Model, Rotor};
use crate::resolve::ReductionInput;
use crate::scene::IntegratorKind;
use crate::time::{estimate, plan_steps, Scheme};
use serde::{Deserialize, Serialize};

mod fit;

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
    /// ([`StepChoice::start_at`], [`RunSettings::request_at`]). Not written out.
    #[serde(skip)]
    pub starts: [Option<PilotStart>; 3],
}

/// The pilot speeds of a run over `speeds`: those at [`pilot_indices`].
pub fn pilot_speeds(speeds: &[f64]) -> Vec<f64> {
    pilot_indices(speeds.len())
        .iter()
        .map(|&k| speeds[k])
        .collect()
}

/// The pilot speeds of a run over `n` speeds, as indices: all of up to two speeds, else the
/// first, the middle and the last.
pub fn pilot_indices(n: usize) -> Vec<usize> {
    match n {
        0..=2 => (0..n).collect(),
        n => vec![0, n / 2, n - 1],
    }
}

impl StepChoice {
    /// The state the pilots ended in at the `index`-th of the speeds the choice was made for,
    /// if that speed was a pilot speed and its pilots kept one.
    pub fn start_at(&self, index: usize) -> Option<PilotStart> {
        self.starts
            .iter()
            .flatten()
            .find(|p| p.speed_index == index)
            .copied()
    }
}

/// A scheme's outcome over the pilot speeds.
struct Outcome {
    kind: IntegratorKind,
    /// The reduction its runs integrate (`RunSettings::reduction`).
    reduction: Option<(ReductionInput, CutoffChoice)>,
    fits: Vec<fit::Fit>,
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

/// The candidate variants (scheme, reduced) of the candidate `kinds`: each as the scene
/// reduces it (reduced with κ from the tolerance where `scene_red` is automatic), then, where
/// the scene gives no reduction and the model is `reducible`, each again reduced (forward
/// increment only when it is the one candidate).
fn variants(
    kinds: &[IntegratorKind],
    scene_red: Option<ReductionInput>,
    reducible: bool,
) -> Vec<(IntegratorKind, bool)> {
    let scene_auto = scene_red.is_some_and(|r| r.auto);
    let mut variants: Vec<(IntegratorKind, bool)> =
        kinds.iter().map(|k| (*k, scene_auto)).collect();
    if scene_red.is_none() && reducible {
        let reduced = kinds
            .iter()
            .filter(|k| kinds.len() == 1 || **k != IntegratorKind::ForwardIncrement);
        variants.extend(reduced.map(|k| (*k, true)));
    }
    variants
}

/// Cost (s) of one revolution at each pilot speed of `kind` at `scale`, summed.
fn cost(model: &Model, s: &RunSettings, kind: Scheme, speeds: &[f64], scale: f64) -> Result<f64> {
    let mut total = 0.0;
    for &v in speeds {
        let prep = prepare(model, &RunRequest::pilot(s, v, kind, scale))?;
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
    choose_among(
        model,
        s,
        &candidates(model, run_integrator),
        rho_inf,
        speeds,
    )
}

/// [`choose`] for the commands that shoot periodic orbits (`rubsim periodic`, `rubsim
/// continue`), whose maps restart central differences: among the explicit schemes only
/// (collocated, forward increment, on the full or the reduced model) when the scene names no
/// integrator; a scene that names an implicit one keeps it (and shooting refuses it, naming
/// the key).
///
/// # Errors
/// As [`choose`].
pub fn choose_explicit(
    model: &Model,
    s: &RunSettings,
    run_integrator: Option<IntegratorKind>,
    rho_inf: Option<f64>,
    speeds: &[f64],
) -> Result<RunSettings> {
    let mut kinds = candidates(model, run_integrator);
    if run_integrator.is_none() {
        kinds.retain(|k| {
            matches!(
                k,
                IntegratorKind::Collocated | IntegratorKind::ForwardIncrement
            )
        });
    }
    choose_among(model, s, &kinds, rho_inf, speeds)
}

/// [`choose`] among the schemes `kinds`.
fn choose_among(
    model: &Model,
    s: &RunSettings,
    kinds: &[IntegratorKind],
    rho_inf: Option<f64>,
    speeds: &[f64],
) -> Result<RunSettings> {
    if s.step.dt.is_some() || speeds.is_empty() {
        return Ok(*s);
    }
    let pilots = pilot_speeds(speeds);
    let target = SAFETY * s.tolerance;
    let rho = Some(match rho_inf {
        Some(r) => r,
        None => super::default_rho_inf(&model.case(pilots[0] * model.rotor.natural_frequency())?),
    });
    // The candidates, each with the cost of its coarsest step, cheapest first (the first
    // candidate wins a tie): a scheme that cannot beat the best found is not piloted.
    // A scheme that cannot even be planned keeps its reason: when none can, that reason (a
    // speed, clearance or stator the run itself would refuse, naming its key) is the error.
    let mut last_err: Option<Error> = None;
    let (mut pilot_steps, mut pilot_wall, mut piloted) = (0u64, 0.0, 0usize);
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
    let variants = variants(kinds, scene_red, reduced_base.is_some());
    let floors = Floors {
        model,
        s,
        reduced_base,
        rho,
        pilots: &pilots,
    };
    let order = floors.order(&variants, &mut last_err);
    // The best found with its candidate's rank: of equal cost, the earlier candidate wins.
    let mut best: Option<(usize, Outcome)> = None;
    for (rank, kind, reduced, floor) in order {
        // A scheme that cannot beat the best found (nor tie it from an earlier candidate).
        if best
            .as_ref()
            .is_some_and(|(br, b)| b.meets && (b.cost, *br) < (floor, rank))
        {
            continue;
        }
        let sch = scheme(kind, rho);
        let red = if reduced {
            let counts = (&mut pilot_steps, &mut pilot_wall);
            let chosen = auto_red.get_or_insert_with(|| {
                reduced_base.and_then(|base| auto_reduction(model, s, base, &pilots, rho, counts))
            });
            match *chosen {
                Some(r) => Some(r),
                None => continue,
            }
        } else {
            None
        };
        let mut counts = (pilot_steps, pilot_wall, piloted);
        let outcome = pilot_scheme(model, s, (kind, sch), red, &pilots, target, &mut counts);
        (pilot_steps, pilot_wall, piloted) = counts;
        match outcome {
            // A scheme predicted to meet the tolerance beats one that is not (a step bounded
            // by `MAX_EXTRAPOLATION` on pilots that did not converge), then the cheaper one.
            Ok(o) => {
                if best.as_ref().is_none_or(|(br, b)| {
                    (o.meets && !b.meets) || (o.meets == b.meets && (o.cost, rank) < (b.cost, *br))
                }) {
                    best = Some((rank, o));
                }
            }
            Err(e) => last_err = Some(e),
        }
    }
    let Some((_, b)) = best else {
        return Err(last_err.unwrap_or_else(|| {
            SolveError::ToleranceUnreachable {
                tolerance: s.tolerance,
                detail: "no integrator could be piloted".into(),
            }
            .into()
        }));
    };
    let counts = (pilot_steps, pilot_wall, piloted);
    finish(model, s, &b, rho, (&pilots, speeds), counts)
}

/// The multiple of the paper's rule a scheme's `fits` at the pilot speeds choose: the smallest
/// of their [`fit::Fit::scale_for`], the rule itself (1) where the pilots predict it meets
/// `tolerance` at every pilot speed.
fn scale_of(fits: &[fit::Fit], target: f64, tolerance: f64) -> f64 {
    let mut scale = fits
        .iter()
        .map(|f| f.scale_for(target, tolerance))
        .fold(f64::INFINITY, f64::min);
    // The paper's rule is kept where the pilots predict it meets the tolerance itself.
    let rule_meets = fits
        .iter()
        .all(|f| f.error_at(f.rule_dt.min(f.h0)) <= tolerance);
    if scale < 1.0 && rule_meets {
        scale = 1.0;
    }
    scale
}

/// The cost floors of the candidate `variants` (scheme, reduced) at the pilot speeds.
struct Floors<'a> {
    model: &'a Model,
    s: &'a RunSettings,
    /// The reduction the reduced variants run (κ to be chosen).
    reduced_base: Option<ReductionInput>,
    rho: Option<f64>,
    pilots: &'a [f64],
}

impl Floors<'_> {
    /// Each variant that can be planned with the cost of its coarsest step (a reduced one at
    /// the default κ: a larger κ costs more), cheapest floor first (the variants' order on a
    /// tie): the scheme most likely to win is piloted first, and one whose floor is above
    /// what it costs is not piloted at all. The first planning error is kept in `last_err`.
    fn order(
        &self,
        variants: &[(IntegratorKind, bool)],
        last_err: &mut Option<Error>,
    ) -> Vec<(usize, IntegratorKind, bool, f64)> {
        let mut order = Vec::new();
        for (rank, &(kind, reduced)) in variants.iter().enumerate() {
            let sch = scheme(kind, self.rho);
            // The floor of a reduced candidate: its cost at the default κ (a larger κ costs more).
            let sr = if reduced {
                let base = self.reduced_base.map(|b| ReductionInput {
                    cutoff: None,
                    cutoff_factor: crate::scene::DEFAULT_CUTOFF_FACTOR,
                    auto: false,
                    ..b
                });
                RunSettings {
                    reduction: base,
                    ..*self.s
                }
            } else {
                *self.s
            };
            match cost(self.model, &sr, sch, self.pilots, COARSEST) {
                Ok(c) => order.push((rank, kind, reduced, c)),
                Err(e) => {
                    last_err.get_or_insert(e);
                }
            }
        }
        order.sort_by(|a, b| a.3.total_cmp(&b.3));
        order
    }
}

/// `s` with the best scheme's choice `b` set (`step.integrator`, `step.dt_scale`, the
/// reduction, `choice`), its budget checked at the ends of `speeds`; `counts`: the pilots'
/// steps, wall time (s) and schemes piloted.
///
/// # Errors
/// As [`check_budget`].
fn finish(
    model: &Model,
    s: &RunSettings,
    b: &Outcome,
    rho: Option<f64>,
    (pilots, speeds): (&[f64], &[f64]),
    counts: (u64, f64, usize),
) -> Result<RunSettings> {
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
        .map(|f| f.predicted(b.scale) + trunc)
        .fold(0.0, f64::max);
    let order_observed = b.fits.iter().map(|f| f.p_obs).fold(f64::NAN, f64::min);
    let indices = pilot_indices(speeds.len());
    out.choice = Some(StepChoice {
        integrator: b.kind,
        dt_scale: b.scale,
        order_observed,
        order_used: b.fits.iter().map(|f| f.p).fold(f64::INFINITY, f64::min),
        error_predicted,
        tolerance: s.tolerance,
        pilot_speeds: pilots.len(),
        pilot_steps: counts.0,
        pilot_wall_s: counts.1,
        schemes_piloted: counts.2,
        reduction: b.reduction.map(|r| r.1),
        starts: std::array::from_fn(|i| {
            let (&speed_index, f) = (indices.get(i)?, b.fits.get(i)?);
            f.end.map(|initial| PilotStart {
                speed_index,
                speed_ratio: speeds[speed_index],
                initial,
            })
        }),
    });
    Ok(out)
}

/// Pilots `kind` (the time loop's `sch`), reduced as `red` when given, at the `pilots` speeds
/// and chooses its step for `target`; its pilots' steps, wall time (s) and one scheme piloted
/// are added to `counts` once they ran.
///
/// # Errors
/// A pilot's error; a chosen step the budget refuses ([`unreachable`]).
fn pilot_scheme(
    model: &Model,
    s: &RunSettings,
    (kind, sch): (IntegratorKind, Scheme),
    red: Option<(ReductionInput, CutoffChoice)>,
    pilots: &[f64],
    target: f64,
    counts: &mut (u64, f64, usize),
) -> Result<Outcome> {
    let s = &RunSettings {
        reduction: red.map(|r| r.0).or(s.reduction),
        ..*s
    };
    let trunc = red.map_or(0.0, |r| r.1.truncation_error);
    let fits = run_all(
        crate::time::one_at_a_time(model),
        pilots,
        &|&v| fit::fit(model, s, sch, v, target),
        &|| {},
    )?;
    counts.2 += 1;
    counts.0 += fits.iter().map(|f| f.steps).sum::<u64>();
    counts.1 += fits.iter().map(|f| f.wall_s).sum::<f64>();
    let scale = scale_of(&fits, target, s.tolerance);
    let c = cost(model, s, sch, pilots, scale).map_err(|e| unreachable(s.tolerance, sch, e))?;
    let meets = fits
        .iter()
        .all(|f| f.predicted(scale) + trunc <= s.tolerance);
    Ok(Outcome {
        kind,
        reduction: red,
        fits,
        scale,
        cost: c,
        meets,
    })
}

/// The reduction `base` with κ chosen from the tolerance at the `pilots` speeds
/// ([`choose_cutoff`]), its pilots' steps and wall time (s) added to `counts`; `None` when the
/// cut-off cannot be chosen.
fn auto_reduction(
    model: &Model,
    s: &RunSettings,
    base: ReductionInput,
    pilots: &[f64],
    rho: Option<f64>,
    counts: (&mut u64, &mut f64),
) -> Option<(ReductionInput, CutoffChoice)> {
    let c = choose_cutoff(model, s, base, pilots, rho).ok()?;
    *counts.0 += c.pilot_steps;
    *counts.1 += c.pilot_wall_s;
    Some((
        ReductionInput {
            cutoff: None,
            cutoff_factor: c.cutoff_factor,
            auto: false,
            ..base
        },
        c,
    ))
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
