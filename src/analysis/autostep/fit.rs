//! One scheme's pilots at one speed and the fit of its order and error constant on them
//! ([`fit`]; the parent module's doc, steps 1–4).

use super::{
    ASYMPTOTIC, COARSEST, CONVERGING, ESTIMATE_SAFETY, MAX_EXTRAPOLATION, MAX_LEVELS, MIN_ORDER,
    SETTLE_REVOLUTIONS,
};
use crate::analysis::discrepancy::difference;
use crate::analysis::{analyse, prepare, Keep, Prepared, RunRequest, RunSettings, SpeedResults};
use crate::error::Result;
use crate::model::Model;
use crate::time::{Initial, Scheme};

/// One scheme's fit at one speed.
#[derive(Debug, Clone, Copy)]
pub(super) struct Fit {
    /// Observed order (NaN when undefined).
    pub(super) p_obs: f64,
    /// Order used.
    pub(super) p: f64,
    /// Error constant: error ≈ c·h^p.
    pub(super) c: f64,
    /// The finest step the choice may take (s): [`MAX_EXTRAPOLATION`] below the finest pilot.
    pub(super) h_min: f64,
    /// Whether the pilots started from the settled state.
    pub(super) settled: bool,
    /// The finest pilot's end state (pilots from the settled state only).
    pub(super) end: Option<Initial>,
    /// The paper's rule at this speed (s).
    pub(super) rule_dt: f64,
    /// The coarsest step the choice may take (s): the coarsest of the three pilots fitted (no
    /// extrapolation above the steps that showed the order), and no coarser than the pilot
    /// step from which on the 2Δt estimate the run will make, as the pilots measure it, is
    /// within the target.
    pub(super) h0: f64,
    /// The steps of the three pilots fitted (s), coarsest first.
    pub(super) levels: [f64; 3],
    /// Pilot steps and loop wall time.
    pub(super) steps: u64,
    pub(super) wall_s: f64,
}

impl Fit {
    /// The multiple of the rule of the step chosen: the coarsest of the fitted pilots' steps
    /// (at most `h0`) whose fitted error is within `tolerance` — a step the pilots ran, so
    /// the run repeats a measured pilot over a longer window rather than an extrapolated
    /// step — else the step whose extrapolated error is `target` (within `h_min … h0`).
    pub(super) fn scale_for(&self, target: f64, tolerance: f64) -> f64 {
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
    pub(super) fn error_at(&self, h: f64) -> f64 {
        self.c * h.powf(self.p)
    }
    /// The fitted error at `scale` × the rule (within `h0`).
    pub(super) fn predicted(&self, scale: f64) -> f64 {
        self.error_at((scale * self.rule_dt).min(self.h0))
    }
}

/// The settled state the pilots start from: the pilot request `pilot` of `prep` run from its
/// start with the plan of `settle` (whole steps per revolution) over `min(s`'s transient,
/// [`SETTLE_REVOLUTIONS`]`)` revolutions ([`RunRequest::settling`]), its disk displacement at
/// the last instant (a whole revolution: the unbalance at the phase of t = 0) and velocity by
/// the one-sided second-order difference of the last three samples
/// `(3x_N − 4x_{N−1} + x_{N−2})/(2δ)`, δ the sampling interval. `None` where that is not the
/// whole state: a rotor with more than the disk's two DOFs, a stator with mass. Returned with
/// the settling run's steps and loop wall time (s).
fn settled_start(
    prep: &Prepared,
    s: &RunSettings,
    pilot: &RunRequest,
    settle: f64,
) -> Result<Option<(Initial, u64, f64)>> {
    let case = &prep.case;
    if case.loop_rotor().ndof != 2 || !case.stators.iter().all(|st| st.massless()) {
        return Ok(None);
    }
    let revolutions = s.step.transient_revolutions.clamp(1, SETTLE_REVOLUTIONS);
    let (_, rec, stats) = prep.record(&pilot.settling(settle, revolutions))?;
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
pub(super) fn fit(
    model: &Model,
    s: &RunSettings,
    kind: Scheme,
    v: f64,
    target: f64,
) -> Result<Fit> {
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
    let mut ps = RunRequest::pilot(s, v, kind, COARSEST);
    let prep = prepare(model, &ps)?;
    let coarsest = prep.plan.dt;
    let rule_dt = prep.plan.rule_dt;
    let settle = coarsest / rule_dt / 2.0 * (1.0 + 1e-9);
    let (mut steps, mut wall_s) = (0u64, 0.0);
    let start = if settled {
        settled_start(&prep, s, &ps, settle)?
    } else {
        None
    };
    let from_settled = start.is_some();
    if let Some((init, n, w)) = start {
        ps = ps.resettled(init);
        steps += n;
        wall_s += w;
    }
    let mut res: Vec<(f64, SpeedResults)> = Vec::with_capacity(MAX_LEVELS);
    let mut k = 0;
    let (d01, d12) = loop {
        let level = ps.at_scale(coarsest / rule_dt / (1u64 << k) as f64 * (1.0 + 1e-9));
        let (plan, rec, stats) = prep.record(&level)?;
        steps += stats.steps as u64;
        wall_s += stats.wall_s;
        let r = analyse(&prep.case, &level, &plan, &rec, stats, Keep::default());
        // From the settled state, the next (finer) pilot starts where this one ended (a whole
        // revolution): its start differs from its own steady state only by the step's change,
        // not by the settling step's error.
        if from_settled {
            if let Some(init) = end_state(&rec) {
                ps = ps.from_state(init);
            }
        }
        res.push((plan.dt, r));
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
    let end = from_settled.then_some(ps.initial());
    Ok(fitted(
        &res,
        (d01, d12),
        kind,
        s.tolerance,
        rule_dt,
        end,
        (steps, wall_s),
    ))
}

/// The fit on the last three pilots of `res` (step, results), finest last, whose successive
/// differences are `d` = (d₀₁, d₁₂): the observed and used order, the error constant and the
/// bounds of the step (module doc, 3–4); `end`: the finest pilot's end state when the pilots
/// started from the settled state; `count`: their steps and loop wall time (s).
fn fitted(
    res: &[(f64, SpeedResults)],
    d: (f64, f64),
    kind: Scheme,
    tolerance: f64,
    rule_dt: f64,
    end: Option<Initial>,
    count: (u64, f64),
) -> Fit {
    let (d01, d12) = d;
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
        if est > ESTIMATE_SAFETY * tolerance {
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
    Fit {
        p_obs,
        p,
        c: e2 / h2.powf(p),
        rule_dt,
        h0: h0.min(cap),
        levels: [h0, h1, h2],
        h_min: h2 / MAX_EXTRAPOLATION,
        settled: end.is_some(),
        end,
        steps: count.0,
        wall_s: count.1,
    }
}
