//! Coexisting responses: is the run's response the only one at its speed?
//!
//! A rubbing rotor can settle on more than one response at one speed — no contact and full
//! annular rub above the critical speed (the jump, or hysteresis, of a run-up against a
//! coast-down), partial rub and full annular rub, partial rubs of different periods. Which one
//! a run lands on depends on where it starts and on its transient, not on Δt; the error
//! estimate's companions (2Δt, Δt/2) restart from the run's own state or share its transient,
//! land on the same response and cannot see the other (docs/VALIDATION.md §16.2).
//!
//! The check ([`check`]) runs one companion at the run's scheme and Δt from a start at the
//! other extreme of the response's contact:
//!
//! - a run in full contact (contact fraction ≥ [`FULL_CONTACT`]) restarts on the no-contact
//!   linear response `u = Re X`, `v = Re(iωX)` (X the unbalance response at station 0's node),
//!   when that orbit fits inside the clearance (|u| < δ) — where it does not, no response without
//!   contact exists and the check is not run;
//! - any other run in contact, and a run without contact whose linear orbit reaches
//!   [`REACH`] × δ, restarts in full contact: at the clearance δ of station 0's stator, in
//!   phase with the unbalance force at t = 0 (a rotor stiffened by a closed contact runs below
//!   its own critical speed, where the response follows the unbalance), whirling forward at
//!   the spin speed (`v = ω ẑ × u`) — synchronous full annular rub at its threshold.
//!
//! The companion settles as the run does (the same stationarity test, `run.tolerance`) from
//! `min(`[`SETTLE_REVOLUTIONS`]`, the run's transient)` revolutions up to the run's own
//! transient, and is analysed over lcm(6, period) revolutions of a steady periodic run (the
//! scene's window otherwise); a window then not periodic is lengthened to
//! `run.classify_revolutions` as the run's is ([`crate::analysis::RunRequest::coexistence`]).
//! When the run is steady and periodic and kept its end state (a settling run with an error
//! estimate), the companion stops as soon as its state joins the run's at a whole revolution of
//! its settling ([`JOIN_FRACTION`]): from there it integrates the run's own response. The responses differ ([`Coexistence::coexisting`]) when their
//! contact fractions differ by more than [`CONTACT_FRACTION_DIFF`] (a response not steady or not
//! periodic: [`CONTACT_FRACTION_DIFF_APERIODIC`]), or, both steady and periodic, their periods
//! differ or their extents differ by more than [`EXTENTS_FACTOR`] × `run.tolerance` of the
//! orbit's size. What it can miss: a third response neither start reaches (a partial rub
//! beside another partial rub found only from a neighbouring speed's state), responses whose
//! basins both starts miss, and a run in full contact whose linear orbit does not fit the
//! clearance.
//!
//! At a flagged speed the two responses are then shot as periodic orbits from their settled
//! end states ([`super::coexist_orbits`]: period, extents, contact fraction, stability, largest
//! Floquet multiplier, whether they are two orbits): [`Coexistence::orbits`]. The run keeps its
//! end state for that whenever the check follows it (with or without an error estimate); the
//! companion joins it only when the run kept it for its error estimate.

use super::discrepancy::{max_diff, orbit_span, Discrepancy, ExtentsScale, Scales};
use super::RunRequest;
use super::{Keep, Prepared, SpeedResults};
use crate::math::{lcm, V2};
use crate::model::{Case, Model};
use crate::time::{EndState, Initial, StepPlan, Stepper, WINDOW_MULTIPLE};
use serde::{Deserialize, Serialize};

/// Contact fraction from which a run counts as in full contact (full annular rub).
pub const FULL_CONTACT: f64 = 0.95;

/// A run without contact is checked when its linear orbit |u| reaches this fraction of the
/// clearance (a full annular rub can coexist with the linear orbit only near the stator).
pub const REACH: f64 = 0.5;

/// Transient revolutions the companion starts with before its stationarity test (at most the
/// run's own; the test lengthens it up to the run's transient).
pub const SETTLE_REVOLUTIONS: usize = 40;

/// Two steady periodic responses differ when their contact fractions differ by more than this.
pub const CONTACT_FRACTION_DIFF: f64 = 0.05;

/// The same for a response not steady or not periodic, whose window's contact fraction
/// samples a response that does not repeat.
pub const CONTACT_FRACTION_DIFF_APERIODIC: f64 = 0.1;

/// Two steady periodic responses differ when their extents differ by more than this multiple
/// of `run.tolerance` × the orbit's size (the same response from two starts, each steady to
/// the tolerance, differs by at most about twice it).
pub const EXTENTS_FACTOR: f64 = 10.0;

/// Where the companion of the check starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Start {
    /// On the no-contact linear response.
    Free,
    /// In full contact at the clearance, whirling forward at the spin speed.
    FullContact,
}

impl Start {
    /// Name as written in summary.json and sweep.csv.
    pub fn name(self) -> &'static str {
        match self {
            Start::Free => "free",
            Start::FullContact => "full_contact",
        }
    }
}

/// The companion of the check and how it compares with the run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Coexistence {
    /// Where the companion started.
    pub start: Start,
    /// Whether it settled on another response than the run: the run's result depends on its
    /// start, and its error estimate (Δt only) does not cover that.
    pub coexisting: bool,
    /// The companion's contact fraction (of the steps of its analysed window).
    pub contact_fraction: f64,
    /// The companion's Poincaré period (0: not periodic).
    pub period: usize,
    /// Whether the companion's steady state was proven.
    pub steady: bool,
    /// The companion's `[x_min, x_max, y_min, y_max]` / |Z0|.
    pub extents_nd: [f64; 4],
    /// `max_i |E_i − E'_i|` of the two responses' extents over the run's largest |extent| (as
    /// the error estimate's `extents_rel`).
    pub extents_rel: f64,
    /// The largest difference of the 1×, ½×, ⅓× lines over the run's largest line.
    pub lines_rel: f64,
    /// The companion's transient revolutions (grown while it was not steady).
    pub transient_revolutions: usize,
    /// The companion's steps.
    pub steps: usize,
    /// Whether the companion stopped on joining the run's own state ([`JOIN_FRACTION`]): its
    /// contact fraction, period, steadiness and extents are then the run's, and `extents_rel`
    /// and `lines_rel` hold the relative state gap it joined at.
    #[serde(default)]
    pub joined: bool,
    /// At a flagged speed (`coexisting`): the two responses — the run's and the companion's —
    /// shot as periodic orbits from their settled end states, or why not
    /// ([`super::coexist_orbits`]); `None` at a speed not flagged.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orbits: Option<CoexistOrbits>,
}

/// The companion stops when, at a whole revolution of its settling, its state is within this
/// fraction of `run.tolerance` of the run's end state (displacements and velocities of every
/// body, relative: `Stepper::state_gap`) — the run being steady and periodic, so that its end
/// state lies on its response. From there it integrates the run's own response (the same case,
/// scheme and Δt from the same state, to 1e-5 of it at the default tolerance) and cannot settle
/// on another, so the rest of its settling and its window are not run.
pub const JOIN_FRACTION: f64 = 0.01;

/// The companion's run: stopped when it joins the run's state, or integrated whole.
enum Companion {
    Joined {
        revolutions: usize,
        gap: f64,
    },
    /// Its results and its end state (for shooting its orbit at a flagged speed).
    Ran(Box<SpeedResults>, Option<EndState>),
}

/// Integrates the companion `cs` over `plan` as [`Prepared::execute`] does, probing its state
/// against `end` (the run's end state, when given) at each whole revolution of its settling.
fn run_companion(
    prep: &Prepared,
    cs: &RunRequest,
    plan: &StepPlan,
    end: Option<&EndState>,
    tolerance: f64,
) -> crate::error::Result<Companion> {
    let mut st = Stepper::new(&prep.case, cs.step.integrator, plan, cs.initial())?;
    if let Some(end) = end {
        let spr = plan.steps_per_rev.max(1);
        for k in 1..=plan.steady_from / spr {
            st.run_to(k * spr, &mut None)?;
            if let Some(gap) = st
                .state_gap(end)
                .filter(|g| *g <= JOIN_FRACTION * tolerance)
            {
                return Ok(Companion::Joined {
                    revolutions: k,
                    gap,
                });
            }
        }
    }
    // Its end state is kept (the error estimate's bookkeeping: the last steps in two chunks,
    // the same steps) for shooting its orbit when the speed is flagged.
    let mut keep = *cs;
    keep.follow_ups.error_estimate = true;
    let (rec, stats, plan, end, _) = prep.drive_from(st, plan, &keep, None)?;
    let res = super::analyse(&prep.case, cs, &plan, &rec, stats, Keep::default());
    Ok(Companion::Ran(Box::new(res), end))
}

/// The no-contact linear response at station 0's node at t = 0, `[u, v]`: u = Re X,
/// v = Re(iωX) (m, m/s), X the complex unbalance response of the rotor at ω. `None` without
/// stations or when the response cannot be computed.
pub fn linear_start(model: &Model, case: &Case) -> Option<[V2; 2]> {
    let node = case.stations.first()?.node;
    let x = model.rotor.unbalance_response(case.omega).ok()?;
    let d = model.rotor.node_dofs(node);
    let (zx, zy) = (*x.get(d[0])?, *x.get(d[1])?);
    let w = case.omega;
    let u = [zx.re, zy.re];
    let v = [-w * zx.im, -w * zy.im];
    (u.iter().chain(&v).all(|c| c.is_finite())).then_some([u, v])
}

/// The start of the check for `res` ([`Start`]; module doc): `None` when none applies — no
/// stator at station 0, a run in full contact whose linear orbit does not fit the clearance,
/// a run without contact far inside it.
pub fn start_for(res: &SpeedResults, case: &Case, linear: [V2; 2]) -> Option<(Start, Initial)> {
    let delta = case
        .stators
        .iter()
        .filter(|s| s.station == 0)
        .map(|s| s.clearance)
        .fold(f64::INFINITY, f64::min);
    if !delta.is_finite() || delta <= 0.0 {
        return None;
    }
    let [u, v] = linear;
    let r = u[0].hypot(u[1]);
    if res.contact_fraction >= FULL_CONTACT {
        return (r < delta).then_some((Start::Free, Initial { u, v }));
    }
    if res.contact_fraction <= 0.0 && r < REACH * delta {
        return None;
    }
    // In phase with the unbalance at t = 0: the rotor stiffened by a closed contact runs
    // below its own critical speed, where the response follows the unbalance.
    let ub = case.rotor.unbalance_resultant();
    let b = ub[0].hypot(ub[1]);
    let n = if b > 0.0 {
        [ub[0] / b, ub[1] / b]
    } else if r > 0.0 {
        [u[0] / r, u[1] / r]
    } else {
        [1.0, 0.0]
    };
    let w = case.omega;
    let uc = [delta * n[0], delta * n[1]];
    Some((
        Start::FullContact,
        Initial {
            u: uc,
            v: [-w * uc[1], w * uc[0]],
        },
    ))
}

/// Runs the check for `res`, the run of `prep` ([`Coexistence`]; module doc), `end` the run's
/// end state when it kept one (the companion stops when it joins it: [`JOIN_FRACTION`]).
/// `Ok(None)` when no start applies.
///
/// # Errors
/// The companion's failure, as a sentence naming the speed, the start and the error, for the
/// run's `coexistence_failed`: the check never stops the run, and never fails silently.
pub fn check(
    prep: &Prepared,
    res: &SpeedResults,
    end: Option<&EndState>,
) -> Result<Option<Coexistence>, String> {
    Ok(check_with_companion(prep, res, end)?.map(|(c, _)| c))
}

/// The companion's results and its end state (kept for shooting its orbit).
pub type CompanionRun = (Box<SpeedResults>, Option<EndState>);

/// [`check`], and the companion's results and end state when it was integrated whole (not when
/// it joined the run's state): what `super::coexist_orbits::shoot_both` shoots at a flagged
/// speed (`Prepared::run` calls both).
///
/// # Errors
/// As [`check`].
pub fn check_with_companion(
    prep: &Prepared,
    res: &SpeedResults,
    end: Option<&EndState>,
) -> Result<Option<(Coexistence, Option<CompanionRun>)>, String> {
    let Some((start, init)) = prep
        .linear_start
        .and_then(|linear| start_for(res, &prep.case, linear))
    else {
        return Ok(None);
    };
    let s = &prep.request;
    let settle = SETTLE_REVOLUTIONS.min(res.transient_revolutions).max(1);
    let cs = s.coexistence(init, res.transient_revolutions.max(settle));
    let repeat = lcm(WINDOW_MULTIPLE, res.period);
    let window = if res.steady && res.period > 0 {
        repeat
    } else {
        s.step
            .revolutions
            .saturating_sub(s.step.transient_revolutions)
            .max(WINDOW_MULTIPLE)
    };
    let spr = res.plan.steps_per_rev.max(1);
    let plan = StepPlan {
        steps: (settle + window) * spr,
        steady_from: settle * spr,
        ..res.plan
    };
    // The companion may join the run's state when the run kept it for its error estimate (a
    // run without one keeps it for the orbits only: its companion is integrated whole).
    let end = end.filter(|_| res.steady && res.period > 0 && s.follow_ups.error_estimate);
    let companion = run_companion(prep, &cs, &plan, end, s.tolerance).map_err(|e| {
        format!(
            "ω/ωn = {:.3}: the coexistence check's companion from the {} start failed ({e}); whether the response depends on the start is not known at this speed (`coexistence_failed`)",
            res.speed_ratio,
            start.name()
        )
    })?;
    Ok(Some(match companion {
        Companion::Ran(c, comp_end) => (compare(start, res, &c, s.tolerance), Some((c, comp_end))),
        Companion::Joined { revolutions, gap } => (
            Coexistence {
                start,
                coexisting: false,
                contact_fraction: res.contact_fraction,
                period: res.period,
                steady: true,
                extents_nd: res.extents_nd,
                extents_rel: gap,
                lines_rel: gap,
                transient_revolutions: revolutions,
                steps: revolutions * spr,
                joined: true,
                orbits: None,
            },
            None,
        ),
    }))
}

/// How the companion `c`, started at `start`, compares with the run `res` at `tolerance`
/// (module doc).
pub fn compare(start: Start, res: &SpeedResults, c: &SpeedResults, tolerance: f64) -> Coexistence {
    let d = Discrepancy::between(c, res, Scales::of(res, ExtentsScale::Largest));
    let d_ext = max_diff(&c.extents_nd, &res.extents_nd);
    let d_cf = (c.contact_fraction - res.contact_fraction).abs();
    let periodic = res.steady && c.steady && res.period > 0 && c.period > 0;
    let coexisting = if periodic {
        d_cf > CONTACT_FRACTION_DIFF
            || c.period != res.period
            || d_ext > EXTENTS_FACTOR * tolerance * orbit_span(&res.extents_nd)
    } else {
        d_cf > CONTACT_FRACTION_DIFF_APERIODIC
    };
    Coexistence {
        start,
        coexisting,
        contact_fraction: c.contact_fraction,
        period: c.period,
        steady: c.steady,
        extents_nd: c.extents_nd,
        extents_rel: d.extents,
        lines_rel: d.lines,
        transient_revolutions: c.transient_revolutions,
        steps: c.stats.steps,
        joined: false,
        orbits: None,
    }
}

/// Hausdorff distance of two orbits' Poincaré sections, relative to the run's orbit size
/// (`orbit_span` of its extents), above which they are distinct orbits. Two shots of one
/// orbit meet to the shooting tolerance (1e-9 of the state, measured ≤ 1e-8 of the span);
/// coexisting orbits of the paper's case lie 0.1–1 of the span apart.
pub const DISTINCT_SECTION: f64 = 1e-4;

/// One response of a flagged speed as a periodic orbit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CoexistOrbit {
    /// Whose response: `run` or `companion`.
    pub response: String,
    /// The period it was shot with (revolutions): the period its run read (0: none).
    pub period: usize,
    /// Why it was not shot (not periodic, state too large, no end state, a failed run), or
    /// `None` when it was.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub not_shot: Option<String>,
    /// Newton converged ([`super::periodic::SHOOT_TOLERANCE`]).
    #[serde(default)]
    pub converged: bool,
    /// Newton's final relative residual (NaN when not shot).
    #[serde(default)]
    pub residual: f64,
    /// Converged and every `|ρ| < 1`.
    #[serde(default)]
    pub stable: bool,
    /// The largest `|ρ|` (NaN when not shot).
    #[serde(default)]
    pub largest_modulus: f64,
    /// How it is unstable (`period_doubling`, `fold`, `neimark_sacker`), when it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instability: Option<String>,
    /// The orbit's `[x_min, x_max, y_min, y_max]` / |Z0| (its run's when not shot).
    pub extents_nd: [f64; 4],
    /// The orbit's contact fraction (its run's when not shot).
    pub contact_fraction: f64,
    /// The orbit's Poincaré section: its `period` points once per revolution, `[x, y]` / |Z0|.
    #[serde(default)]
    pub section_nd: Vec<[f64; 2]>,
}

/// The two responses of a flagged speed as periodic orbits ([`Coexistence::orbits`],
/// [`super::coexist_orbits`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CoexistOrbits {
    /// The run's response, then the companion's.
    pub orbits: Vec<CoexistOrbit>,
    /// The Hausdorff distance of the two converged orbits' sections over the run's orbit size
    /// (`None` unless both converged).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distance: Option<f64>,
    /// Both converged and more than [`DISTINCT_SECTION`] apart (`None` unless both converged).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub distinct: Option<bool>,
    /// The number of stable periodic responses found (distinct orbits counted once each).
    pub coexisting_stable: usize,
    /// Steps the shots took.
    pub steps: u64,
}
