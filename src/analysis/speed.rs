//! One speed: prepare the case and step plan once ([`prepare`]), run them with any set of
//! frame sinks ([`Prepared::run`]), analyse the record ([`analyse`]); the discretisation
//! error's companion runs are [`super::estimate`]'s.

use super::discrepancy::orbit_span;
use super::dynamics::{dynamics, never_repeats, Dynamics, Regime};
use super::fanout::with_sinks;
pub use super::fanout::Fanout;
use super::steady::{
    attractor_stationarity, judge, judge_attractor, lines_revolutions, stationarity,
    Classification, Stationarity,
};
use super::whirl::{signed_orders, whirl_lines, WhirlLines};
use super::{Keep, RunRequest, Window, MAX_PERIOD};
use crate::error::Result;
use crate::math::V2;
use crate::model::{Case, Model};
use crate::signal::{extents, hann_spectrum, line_exact};
use crate::time::{plan_steps, EndState, FrameSink, Record, RunStats, Sink, StepPlan, Stepper};
use serde::{Deserialize, Serialize};

pub use super::estimate::ErrorEstimate;
pub use crate::time::budget::FINE_SETTLE_REVOLUTIONS;

pub use super::richardson::{attractor_error, combine_fine, combine_levels, richardson};

/// Results of a run at one speed.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SpeedResults {
    /// ω/ω_n.
    pub speed_ratio: f64,
    /// ω (rad/s).
    pub omega: f64,
    /// Rotor node whose response is analysed (orbit, Poincaré section, spectrum, extents).
    pub node: usize,
    /// |Z0(ω)| at the analysed node (m).
    pub z0: f64,
    /// Clearance of each stator at this speed (m).
    pub clearances: Vec<f64>,
    /// Unbalance force |U| ω² (N).
    pub unbalance_force: f64,
    /// Poincaré period 1–8, 0 when not periodic (judged on the whole orbit to
    /// `run.tolerance`: [`Classification`]).
    pub period: usize,
    /// Whether the steady state is proven: the analysed window's transient residual
    /// (`stationarity.residual`) is within `run.tolerance` of the orbit's size. A run that does
    /// not settle within `run.max_transient_revolutions` is reported with `false`.
    pub steady: bool,
    /// Revolutions cut as transient before the analysed window (`run.transient_revolutions`,
    /// more when the run went on to reach the steady state).
    pub transient_revolutions: usize,
    /// Revolutions of the analysed window (at least 6; `run.classify_revolutions` when the run
    /// is not periodic and `run.max_steps` allows).
    pub window_revolutions: usize,
    /// How stationary the analysed window is (the transient's share of the error).
    pub stationarity: Stationarity,
    /// How the period was told, and how surely.
    pub classification: Classification,
    /// Periodic, quasi-periodic, chaotic or undetermined, and the 0–1 test's `K` of a window
    /// that is not periodic ([`super::dynamics`]).
    #[serde(default)]
    pub dynamics: Dynamics,
    /// Revolutions (the last of the window) the 1×, ½×, ⅓× lines are read over: a multiple of
    /// `lcm(6, period)`.
    pub lines_revolutions: usize,
    /// Whether the lines are read over a whole number of the period's and the lines' periods
    /// (exact bins, no leakage); false when the window is shorter than `lcm(6, period)`.
    pub lines_resolved: bool,
    /// `[x_min, x_max, y_min, y_max]` / |Z0| over the analysis window.
    pub extents_nd: [f64; 4],
    /// 1× amplitude of the analysed component / |Z0|, read at its exact frequency over
    /// `lines_revolutions` ([`crate::signal::line_exact`]).
    pub amp_1x_nd: f64,
    /// 1/2× amplitude / |Z0|.
    pub amp_half_nd: f64,
    /// 1/3× amplitude / |Z0|.
    pub amp_third_nd: f64,
    /// The whirl: forward and backward 1×, the dominant line with its sign and the strongest
    /// lines of the full spectrum of x + iy over the same revolutions as the lines above
    /// ([`super::whirl::whirl_lines`]).
    pub whirl: WhirlLines,
    /// Largest contact-force magnitude on station 0 over every step of the analysed steady
    /// window (after the transient) / |U|ω² ([`RunStats::steady`]).
    pub contact_force_max_nd: f64,
    /// A run whose stations stick (`station.N.stick`): the fraction of the steady window's
    /// contact instants at which some pair stuck; `None` without stick.
    #[serde(default)]
    pub stick_fraction: Option<f64>,
    /// A run with stick in a backward whirl of full annular contact: dry whirl (rolling) or
    /// dry whip (slipping) ([`super::dry`]).
    #[serde(default)]
    pub dry_rub: Option<super::dry::DryRub>,
    /// Fraction of the steps of the analysed steady window with at least one pair carrying
    /// force ([`RunStats::steady`]).
    pub contact_fraction: f64,
    /// Largest penetration over every step of the whole run (m), `max(0, −g)` of the exact
    /// post-correction gaps ([`RunStats::whole`]); the steady window's is in `stats.steady`.
    pub penetration_max_m: f64,
    /// Step plan.
    pub plan: StepPlan,
    /// Loop counters.
    pub stats: RunStats,
    /// Error estimate (None when not asked or not possible).
    pub error: Option<ErrorEstimate>,
    /// The integrator and Δt chosen from `run.tolerance` by pilot runs (None when `run.dt` or
    /// the paper's rule set the step).
    #[serde(default)]
    pub step_choice: Option<super::StepChoice>,
    /// Whether the run started from the pilots' settled state at its speed
    /// ([`super::RunSettings::request_at`], [`super::RunRequest::from_pilot`]).
    #[serde(default)]
    pub started_from_pilot: bool,
    /// The check for a coexisting response: the companion from another start and whether it
    /// found another response (`run.check_coexistence`, [`super::coexist`]); `None` when not
    /// run.
    #[serde(default)]
    pub coexistence: Option<super::Coexistence>,
    /// Why the coexistence check could not answer, when its companion failed (the companion's
    /// error: an unstable start, a contact solve that did not converge, …): whether the
    /// response depends on the start is then not known at this speed, and `coexistence` is
    /// `None`. `None` when the check answered or did not run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coexistence_failed: Option<String>,
    /// The step refined after the run, where its own estimate missed the tolerance the step
    /// was chosen for ([`super::verify`]); `None` when it was not.
    #[serde(default)]
    pub step_refinement: Option<super::refinement::StepRefinement>,
    /// What the run reports without failing: a fixed window (`run.duration`) that is not
    /// steady to `run.tolerance` ([`fixed_window_warning`]). Empty otherwise.
    #[serde(default)]
    pub warnings: Vec<String>,
    /// What the step or the record does not resolve of the run's roll
    /// ([`super::dry::roll_resolution`]), one sentence each. Empty otherwise.
    #[serde(default)]
    pub roll_warnings: Vec<String>,
    /// Poincaré points / |Z0| (analysis window).
    pub poincare_nd: Vec<V2>,
    /// Steady orbit / |Z0| (kept on request).
    #[serde(skip)]
    pub orbit_nd: Vec<V2>,
    /// Time in revolutions and vertical force on the stator / |U|ω² (kept on request).
    #[serde(skip)]
    pub force_history: Vec<(f64, f64)>,
    /// Spectrum: (f/ω_n, amplitude/|Z0|) (kept on request).
    #[serde(skip)]
    pub spectrum: Vec<(f64, f64)>,
    /// Full spectrum of (x + iy)/|Z0| over the lines' revolutions: (signed f/ω_n, amplitude /
    /// |Z0|), ascending, within the spectrum's frequency (kept on request, [`Keep::full_spectrum`]).
    #[serde(skip)]
    pub full_spectrum: Vec<(f64, f64)>,
}

/// A run at one speed, ready to integrate: the case and the step plan, built once.
///
/// Sinks that want frames of this run (VTK/HDF5 writers, a stress probe) are built from
/// `case` and `plan` and handed to [`Prepared::run`].
#[derive(Debug)]
pub struct Prepared {
    /// ν = ω/ω_n as asked (the case's `speed_ratio` is ω/ω_n recomputed from ω).
    pub speed_ratio: f64,
    /// ω = ν ω_n (rad/s).
    pub omega: f64,
    /// The run requested.
    pub request: RunRequest,
    /// The case at ω.
    pub case: Case,
    /// The step plan (Δt, steps, recording interval).
    pub plan: StepPlan,
    /// The no-contact linear response at station 0's node at t = 0, `[u, v]` (m, m/s):
    /// u = Re X, v = Re(iωX), X the unbalance response; a start of the coexistence check
    /// ([`super::coexist`]). `None` when not asked or not computed.
    pub linear_start: Option<[V2; 2]>,
}

/// Prepares the run `request` of `model`: the case at ω = ν ω_n and its step plan.
///
/// # Errors
/// Model errors of the case; [`crate::error::SolveError::StepTooLarge`] and other plan errors.
pub fn prepare(model: &Model, request: &RunRequest) -> Result<Prepared> {
    let speed_ratio = request.speed_ratio;
    let omega = speed_ratio * model.rotor.natural_frequency();
    let case = model.case_with(omega, request.reduction_of(model))?;
    let plan = plan_steps(&case, &request.step)?;
    let linear_start = if request.follow_ups.coexistence {
        super::coexist::linear_start(model, &case)
    } else {
        None
    };
    Ok(Prepared {
        speed_ratio,
        omega,
        request: *request,
        case,
        plan,
        linear_start,
    })
}

impl Prepared {
    /// One revolution 2π/ω (s).
    pub fn revolution(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega
    }

    /// Integrates the case with the plan as it stands, handing frames to `sinks` (each at its
    /// own [`FrameSink::every`]); returns the record and the loop's counters. No steady-state
    /// test: the fixed plan (the stress probe's runs).
    ///
    /// # Errors
    /// [`crate::error::SolveError`] of the loop, a sink's error included.
    pub fn integrate(&self, sinks: &mut [&mut dyn FrameSink]) -> Result<(Record, RunStats)> {
        let fixed = self.request.fixed();
        let (rec, stats, ..) = with_sinks(sinks, |sink| self.drive_with(&self.plan, &fixed, sink))?;
        Ok((rec, stats))
    }

    /// `request` on this case over its own plan (of its step rule), without frames: the plan,
    /// the record and the counters (a pilot's levels, its settling run).
    ///
    /// # Errors
    /// Plan errors; as `Prepared::drive_with`.
    pub fn record(&self, request: &RunRequest) -> Result<(StepPlan, Record, RunStats)> {
        let plan = plan_steps(&self.case, &request.step)?;
        let (rec, stats, plan, ..) = self.drive_with(&plan, request, None)?;
        Ok((plan, rec, stats))
    }

    /// The one driver of every run on this case: `request` integrated over `plan` by
    /// `Prepared::drive_with` (its window policy), without frames, and analysed
    /// ([`analyse`], `keep`). The error-estimate companions, the coexistence check and the
    /// pilots run through it; the run itself adds its sinks and follow-ups
    /// ([`Prepared::run`]).
    ///
    /// # Errors
    /// As `Prepared::drive_with`.
    pub fn execute(
        &self,
        request: &RunRequest,
        plan: &StepPlan,
        keep: Keep,
    ) -> Result<SpeedResults> {
        let (rec, stats, plan, ..) = self.drive_with(plan, request, None)?;
        Ok(analyse(&self.case, request, &plan, &rec, stats, keep))
    }

    /// Integrates `request` over `plan` from its start, handing frames to `sink`. A
    /// [`Window::Settle`] run goes on until the steady state is proven: while the analysed
    /// window's transient residual ([`stationarity`]) is above the tolerance and the transient
    /// below `max_transient` revolutions (and the steps below `run.max_steps`), the run goes on
    /// and the window slides — by as many revolutions as the observed decay asks, at least a
    /// third of the window; a window then not periodic (no period up to [`MAX_PERIOD`], the
    /// rule of [`analyse`]) is lengthened to `classify` revolutions within `run.max_steps`,
    /// for [`super::dynamics`]. A [`Window::Fixed`] run (a pilot, a companion,
    /// `run.duration`) takes its plan and no more. Returns the record, the counters, the plan
    /// as it ended and, for a settling run with an error estimate or a coexistence check to
    /// follow, the bodies' end state (the finer companion of the error estimate restarts from
    /// it; the coexistence check shoots the run's periodic orbit from it).
    pub(super) fn drive_with(
        &self,
        plan: &StepPlan,
        request: &RunRequest,
        sink: Sink<'_>,
    ) -> Result<Driven> {
        let st = Stepper::new(&self.case, request.step.integrator, plan, request.initial())?;
        self.drive_from(st, plan, request, sink)
    }

    /// [`Prepared::drive_with`] from the stepper `st` of `plan`, which may have taken steps of
    /// it already (a probe: `super::coexist`).
    pub(super) fn drive_from<'a>(
        &'a self,
        mut st: Stepper<'a>,
        plan: &StepPlan,
        request: &RunRequest,
        mut sink: Sink<'_>,
    ) -> Result<Driven> {
        let s = request;
        let spr_steps = plan.steps_per_rev.max(1);
        let window = (plan.steps - plan.steady_from) / spr_steps;
        let settle = match s.window {
            Window::Settle {
                max_transient,
                classify,
            } => Some((max_transient, classify)),
            Window::Fixed => None,
        };
        // The end state: the error estimate's finer companion restarts from it, the
        // coexistence check's companion may join it and its orbit is shot from it.
        let keep_end =
            settle.is_some() && (s.follow_ups.error_estimate || s.follow_ups.coexistence);
        let mut older = None;
        loop {
            let p = *st.plan();
            if keep_end {
                // The run in two chunks takes the same steps; uᴺ⁻² is kept on the way.
                st.run_to(p.steps.saturating_sub(1), &mut sink)?;
                older = Some(st.history());
            }
            st.run_to(p.steps, &mut sink)?;
            let Some((max_transient, _)) = settle else {
                break;
            };
            let transient = p.steady_from / spr_steps;
            let cap = max_transient.max(transient);
            if window < 3 || transient >= cap {
                break;
            }
            let (w, nrev) = window_points(&self.case, s, &p, st.recorded());
            let span = orbit_span(&extents(&w));
            let mut stn = stationarity(&w, s.step.samples_per_rev, nrev, span);
            let first = p.steady_from / p.record_every.max(1);
            if super::dry::record_rolls(&self.case, st.recorded(), first) {
                // A roll whirls at −RΩ/δ whatever the spin's phase: judged by its extents'
                // statistics, as a response that never repeats.
                if let Some((_, r)) = attractor_stationarity(&w, s.step.samples_per_rev, nrev, span)
                {
                    stn.residual = r;
                }
            }
            if stn.residual <= s.tolerance {
                break;
            }
            let by_steps = (s.step.max_steps as usize).saturating_sub(p.steps) / spr_steps;
            let more = stn
                .revolutions_needed(s.tolerance)
                .min(cap - transient)
                .min(by_steps);
            if more == 0 {
                break;
            }
            st.extend(p.steps + more * spr_steps, p.steady_from + more * spr_steps);
        }
        // A window that is not periodic is lengthened for the 0–1 test (`dynamics`); one that
        // runs away when continued keeps its window (`super::lengthen`).
        let mut runaway = None;
        if let Some((_, classify)) = settle {
            (st, runaway) = self.lengthen(st, s, classify, &mut sink, keep_end, &mut older)?;
        }
        let plan = *st.plan();
        let end = older.and_then(|o| st.end_state(&o));
        if runaway.is_some() {
            sink = None; // the re-run window's frames went to the sink the first time
        }
        let (rec, stats) = st.finish(&mut sink)?;
        Ok((rec, stats, plan, end, runaway))
    }

    /// The run of the request without the step's verification and the coexistence check
    /// ([`Prepared::run`] adds them): integrated by its window policy
    /// (`Prepared::drive_with`), handing frames to `sinks`, [`analyse`]d, its error estimate's
    /// companions run (no sinks, the same transient, [`ErrorEstimate`]). Also returns the
    /// bodies' end state when the run kept one (a settling run with an error estimate), which
    /// the coexistence check's companion compares itself with.
    ///
    /// # Errors
    /// As [`Prepared::integrate`]; the companion run's failure only leaves the estimate out.
    pub(super) fn run_estimated(
        &self,
        keep: Keep,
        sinks: &mut [&mut dyn FrameSink],
    ) -> Result<(SpeedResults, Option<EndState>)> {
        let req = &self.request;
        let (rec, stats, plan, end, runaway) =
            with_sinks(sinks, |sink| self.drive_with(&self.plan, req, sink))?;
        let mut res = analyse(&self.case, req, &plan, &rec, stats, keep);
        res.started_from_pilot = req.from_pilot_state();
        if let Some(t) = runaway {
            // Bounded over its window, running away when continued: not a steady state.
            res.steady = false;
            res.dynamics.regime = Regime::Diverging;
            res.dynamics.runaway_at_s = Some(t);
        }
        if req.follow_ups.error_estimate {
            res.error = self.error_estimate(&res, end.as_ref());
        }
        if let Some(d) = req.step.duration {
            res.warnings
                .extend(fixed_window_warning(&res, d, req.tolerance));
        }
        if res
            .stick_fraction
            .is_some_and(|s| super::dry::rolls(res.contact_fraction, s))
        {
            res.roll_warnings = super::dry::roll_resolution(&self.case, self.case.omega, &plan);
        }
        Ok((res, end))
    }
}

/// What [`Prepared::drive`] returns: the record, the counters, the plan as it ended, the
/// bodies' end state and the time (s) a lengthening for the 0–1 test ran away.
pub(super) type Driven = (Record, RunStats, StepPlan, Option<EndState>, Option<f64>);

/// The warning of a fixed window of `duration` (s, `run.duration`) whose analysed half is not
/// steady to `tolerance`: its transient residual and that the run was not lengthened. `None`
/// when it is steady.
pub fn fixed_window_warning(res: &SpeedResults, duration: f64, tolerance: f64) -> Option<String> {
    (!res.steady).then(|| {
        let residual = res.stationarity.residual;
        let why = if residual.is_finite() {
            format!("it still changes by {residual:.1e} of the orbit's size, above `run.tolerance` = {tolerance:e}")
        } else {
            "too short to compare one revolution with the next, so it cannot be shown steady".into()
        };
        format!(
            "ω/ωn = {:.3}: the fixed window (`run.duration` = {duration} s, analysed over its second half, {} whole revolutions) is not steady: {why}; not lengthened (a fixed window), its results carry that (`steady = false`)",
            res.speed_ratio, res.window_revolutions
        )
    })
}

/// Runs `request` without sinks: [`prepare`] then [`Prepared::run`].
pub fn run_speed(model: &Model, request: &RunRequest, keep: Keep) -> Result<SpeedResults> {
    prepare(model, request)?.run(keep, &mut [])
}

/// The analysed window of a record, non-dimensional (/|Z0|): the samples at the instants
/// `plan.steady_from ≤ k < plan.steps`, and its whole revolutions.
pub(super) fn window_points(
    case: &Case,
    s: &RunRequest,
    plan: &StepPlan,
    rec: &Record,
) -> (Vec<V2>, usize) {
    let spr = s.step.samples_per_rev;
    let z0 = if case.z0 > 0.0 { case.z0 } else { 1.0 };
    let first = plan.steady_from / plan.record_every;
    let last = (plan.steps / plan.record_every).min(rec.len().saturating_sub(1));
    let w: Vec<V2> = (first..last.max(first))
        .map(|i| {
            let d = rec.observed[i];
            [d[0] / z0, d[1] / z0]
        })
        .collect();
    let nrev = w.len() / spr.max(1);
    (w, nrev)
}

/// The force scale of the non-dimensional forces: the unbalance force |U|ω² (N), or 1 N
/// without unbalance.
fn force_scale(case: &Case) -> f64 {
    Some(case.unbalance_force)
        .filter(|f| *f > 0.0)
        .unwrap_or(1.0)
}

/// Analysis of a record: transient cut, Poincaré section, extents, spectrum; the contact
/// figures come from the loop's counters `stats`, taken at every step (the record keeps one
/// step in `record_every`).
///
/// The analysed window is the steady part of the run, the samples at the instants
/// `plan.steady_from ≤ k < plan.steps` (k the step index); its contact figures are
/// [`RunStats::steady`]'s over the same instants.
pub fn analyse(
    case: &Case,
    s: &RunRequest,
    plan: &StepPlan,
    rec: &Record,
    stats: RunStats,
    keep: Keep,
) -> SpeedResults {
    let spr = s.step.samples_per_rev;
    let z0 = if case.z0 > 0.0 { case.z0 } else { 1.0 };
    let fu = force_scale(case);
    let (window, nrev) = window_points(case, s, plan, rec);
    let first = plan.steady_from / plan.record_every;
    let last = first + window.len();
    let poincare: Vec<V2> = (first..=last.min(rec.len().saturating_sub(1)))
        .step_by(spr)
        .map(|i| {
            let d = rec.observed[i];
            [d[0] / z0, d[1] / z0]
        })
        .collect();
    let ext = extents(&window);
    let section = &poincare[..nrev.min(poincare.len())];
    let rolling = super::dry::window_rolls(case, &stats.steady);
    let (stn, steady, class, dynamics) = judged(s, (&window, nrev), section, rolling);
    let period = class.period;
    let comp: Vec<f64> = window.iter().map(|p| p[s.component]).collect();
    let (lrev, resolved) = lines_revolutions(nrev, period);
    let lines = &comp[(nrev - lrev) * spr..nrev * spr];
    let amp = |order: f64| line_exact(lines, spr, order);
    let (whirl, full) = whirl_lines(&window[(nrev - lrev) * spr..nrev * spr], lrev);
    let nrev_f = (last - first) as f64 / spr as f64;
    let (spectrum, full_spectrum) = spectra(case, keep, &comp, &full, lrev, nrev_f);
    let (stick_fraction, dry_rub) = super::dry::of_run(case, &stats.steady, &whirl);
    SpeedResults {
        speed_ratio: case.speed_ratio,
        omega: case.omega,
        node: case.observed_node,
        z0: case.z0,
        clearances: case.stators.iter().map(|s| s.clearance).collect(),
        unbalance_force: case.unbalance_force,
        period,
        steady,
        transient_revolutions: plan.steady_from / plan.steps_per_rev.max(1),
        window_revolutions: nrev,
        stationarity: stn,
        classification: class,
        dynamics,
        lines_revolutions: lrev,
        lines_resolved: resolved,
        extents_nd: ext,
        amp_1x_nd: amp(1.0),
        amp_half_nd: amp(0.5),
        amp_third_nd: amp(1.0 / 3.0),
        whirl,
        contact_force_max_nd: stats.steady.force_max / fu,
        stick_fraction,
        dry_rub,
        contact_fraction: stats.steady.fraction(),
        penetration_max_m: stats.whole.penetration_max,
        plan: *plan,
        stats,
        error: None,
        step_choice: s.choice,
        started_from_pilot: false,
        coexistence: None,
        coexistence_failed: None,
        step_refinement: None,
        warnings: Vec::new(),
        roll_warnings: Vec::new(),
        poincare_nd: poincare,
        orbit_nd: if keep.orbit { window } else { Vec::new() },
        force_history: if keep.force_history {
            force_history(case, rec, fu)
        } else {
            Vec::new()
        },
        spectrum,
        full_spectrum,
    }
}

/// What the analysed `window` of `nrev` revolutions (Poincaré `section`) claims under the
/// request `s`: its stationarity, whether it is steady, its period and its dynamics — a window
/// that never repeats, or that `rolls` (a dry whirl whirls at −RΩ/δ, not locked to the spin's
/// phase: its Poincaré points turn even when R/δ is a whole number), judged by the statistics
/// of its extents ([`judge_attractor`]).
fn judged(
    s: &RunRequest,
    (window, nrev): (&[V2], usize),
    section: &[V2],
    rolls: bool,
) -> (Stationarity, bool, Classification, Dynamics) {
    let spr = s.step.samples_per_rev;
    let (stn, steady, class) = judge(window, spr, nrev, s.tolerance, MAX_PERIOD);
    let span = orbit_span(&extents(window));
    let dynamics = dynamics(
        class.period,
        section,
        s.component,
        span,
        class.tolerance,
        &stn,
        steady,
    );
    let never_repeats = never_repeats(&dynamics, &stn, steady) || rolls;
    let (stn, steady) = judge_attractor(
        never_repeats,
        stn,
        steady,
        window,
        spr,
        nrev,
        span,
        s.tolerance,
    );
    (stn, steady, class, dynamics)
}

/// A spectrum as kept: (f/ω_n, amplitude/|Z0|) pairs.
type Spectrum = Vec<(f64, f64)>;

/// The spectra [`analyse`] keeps (`keep.spectrum_up_to`): of the analysed component `comp`
/// over its window of `nrev_f` revolutions (f/ω_n, amplitude/|Z0|), and — with
/// `keep.full_spectrum` — the full spectrum `full` of x + iy over `lrev` revolutions as
/// (signed f/ω_n, amplitude/|Z0|).
fn spectra(
    case: &Case,
    keep: Keep,
    comp: &[f64],
    full: &crate::signal::FullSpectrum,
    lrev: usize,
    nrev_f: f64,
) -> (Spectrum, Spectrum) {
    let full_spectrum = match keep.spectrum_up_to {
        Some(fm) if keep.full_spectrum => {
            let nu = case.speed_ratio;
            signed_orders(full, lrev, fm as f64 / nu.max(1e-300))
                .into_iter()
                .map(|(o, a)| (o * nu, a))
                .collect()
        }
        _ => Vec::new(),
    };
    let spectrum = match keep.spectrum_up_to {
        Some(fm) => hann_spectrum(comp)
            .iter()
            .enumerate()
            .map(|(k, a)| (k as f64 / nrev_f * case.speed_ratio, *a))
            .take_while(|(f, _)| *f <= fm as f64 + 1e-9)
            .collect(),
        None => Vec::new(),
    };
    (spectrum, full_spectrum)
}

/// The whole record's time in revolutions and vertical force on the stator over |U|ω² (`fu`).
fn force_history(case: &Case, rec: &Record, fu: f64) -> Vec<(f64, f64)> {
    let t_rev = 2.0 * std::f64::consts::PI / case.omega;
    (0..rec.len())
        .map(|i| (rec.t[i] / t_rev, -rec.force_at(i, 0)[1] / fu))
        .collect()
}
