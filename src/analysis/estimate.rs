//! The discretisation error of a run at one speed ([`ErrorEstimate`]): companion runs of the
//! same request at about 2Δt and, at a rub, 4Δt from the start or Δt/2 restarted from the run's
//! end state, their differences from the run by Richardson extrapolation at the scheme's
//! nominal order (`analysis::richardson`).

use super::discrepancy::{extent_scale, orbit_span, Discrepancy, ExtentsScale, Scales};
use super::richardson::{attractor_error, combine_fine, combine_levels, richardson};
use super::speed::{analyse, Prepared, SpeedResults};
use super::{Keep, RunRequest};
use crate::math::lcm;
use crate::model::Case;
use crate::time::budget::FINE_SETTLE_REVOLUTIONS;
use crate::time::{plan_steps, EndState, StepPlan, Stepper, WINDOW_MULTIPLE};
use serde::{Deserialize, Serialize};

/// Discretisation-error estimate from companion runs at about 2Δt and, at rub speeds, 4Δt
/// (Richardson at the scheme's nominal order; [`combine_levels`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ErrorEstimate {
    /// Companion Δt (s): about 2Δt, or Δt/2 when 2Δt would be unstable.
    pub dt_coarse: f64,
    /// Order assumed.
    pub order: f64,
    /// Estimated relative error of the orbit extents (of the finer run): the two levels'
    /// estimates combined ([`combine_levels`]), or `extents_rel_pair` alone without a second
    /// companion.
    pub extents_rel: f64,
    /// Estimated error of the 1×, 1/2×, 1/3× amplitudes relative to the largest of them
    /// (combined as `extents_rel`).
    pub lines_rel: f64,
    /// Whether the companion run found the same Poincaré period.
    pub same_period: bool,
    /// Δt of the second companion (s), about 4Δt: run at rub speeds only (contact in the
    /// analysed window of the run or of the first companion), when the first companion is
    /// coarser than the run and a coarser plan exists (at least one step per recorded sample).
    #[serde(default)]
    pub dt_coarser: Option<f64>,
    /// The (Δt, 2Δt) pair's estimate of the extents' error, `|Q_h − Q_2h|/(r₁^p − 1)`.
    #[serde(default)]
    pub extents_rel_pair: f64,
    /// The (2Δt, 4Δt) pair's estimate of the 2Δt run's extents error brought to Δt,
    /// `|Q_2h − Q_4h|/((r₂^p − 1) r₁^p)` (relative to the run's largest |extent|).
    #[serde(default)]
    pub extents_rel_coarse_pair: Option<f64>,
    /// Δt/2 (s): the finer companion, run at rub speeds of a steady periodic run, restarted
    /// from the run's end state ([`FINE_SETTLE_REVOLUTIONS`] to settle, then lcm(6, period)
    /// revolutions analysed); it takes the second companion's place.
    #[serde(default)]
    pub dt_fine: Option<f64>,
    /// The (Δt, Δt/2) pair's estimate of the run's extents error, `|Q_h − Q_{h/2}|/(1 − 2^−p)`.
    #[serde(default)]
    pub extents_rel_fine_pair: Option<f64>,
    /// For a run that never repeats (quasi-periodic, chaotic, or undetermined with a `K` and
    /// no decaying transient: [`super::dynamics::never_repeats`]): the sampling
    /// uncertainty of its window's extents (the halves' difference, relative to the largest
    /// |extent|), and `extents_rel` is the error of the attractor's extents — this plus the
    /// time-step bias left in the (Δt, 2Δt) difference once both windows' sampling is taken out
    /// ([`attractor_error`]; no 4Δt companion). `None` for other runs.
    #[serde(default)]
    pub extents_rel_sampling: Option<f64>,
}

impl ErrorEstimate {
    /// The estimate the tolerance is held to: `max(extents_rel, lines_rel)` (`f64::max`: a
    /// NaN on one side gives the other).
    pub fn largest(&self) -> f64 {
        self.extents_rel.max(self.lines_rel)
    }
}

impl Prepared {
    /// Companion run at 2Δt (at Δt/2 when 2Δt is above the stability limit); the error of the
    /// main run ≈ |Q_h − Q_c| / |r^p − 1|, r = h_c / h, p the scheme's nominal order. At a rub
    /// (contact in the analysed window) a second companion at about 4Δt gives the (2Δt, 4Δt)
    /// pair's estimate too and the two are combined ([`combine_levels`]).
    pub(super) fn error_estimate(
        &self,
        res: &SpeedResults,
        end: Option<&EndState>,
    ) -> Option<ErrorEstimate> {
        let (case, plan) = (&self.case, &res.plan);
        // The companions cut the transient the main run ended with. A steady periodic run's
        // window repeats every `period` revolutions: its extents and lines are those of
        // lcm(6, period) of them, so the companions analyse that many (the whole window when
        // the run is not steady or not periodic).
        let (s, window, periodic) = self.companion_request(res);
        let s = &s;
        let coarser_than = |p: &StepPlan, cap: f64| coarser_plan(case, s, p, cap);
        let cplan = coarser_than(plan, f64::INFINITY)
            .or_else(|| {
                let mut fine = s.step;
                fine.dt = Some(0.5 * plan.dt);
                plan_steps(case, &fine).ok()
            })
            .filter(|c| c.steps_per_rev != plan.steps_per_rev)?;
        let companion = |p: &StepPlan| self.execute(s, p, Keep::default()).ok();
        let c = companion(&cplan)?;
        let p = s.step.integrator.nominal_order();
        let r1 = plan.steps_per_rev as f64 / cplan.steps_per_rev as f64;
        // Every pair's difference relative to the run's scales.
        let scales = Scales::of(res, ExtentsScale::Largest);
        let d1 = Discrepancy::between(&c, res, scales);
        let ext1 = richardson(d1.extents, r1, p);
        let lin1 = richardson(d1.lines, r1, p);
        // A second level at rubs only: without contact the error is the smooth expansion
        // C h^p and one pair measures it (docs/VALIDATION.md §15). A steady periodic run of a
        // second-order scheme gets a companion at Δt/2 restarted from its end state (its
        // difference from the run is dominated by the run's own error); any other, a companion
        // at about 4Δt from the start. At order 1 the finer pair reads the run's error times
        // `|1 − C(h/2)/(2C(h))|/(1 − ½)`: as exposed to the coefficient's phase noise as a
        // coarser pair, so it is not run.
        let rub = res.contact_fraction > 0.0 || c.contact_fraction > 0.0;
        let fine = match end {
            Some(e) if rub && r1 > 1.0 && periodic && p >= 2.0 => {
                self.fine_companion(res, e, window)
            }
            _ => None,
        };
        // A run that never repeats: the error of its attractor's extents.
        let sampling = |r: &SpeedResults| {
            let a = r.stationarity.attractor?;
            Some(a.extents_sampling * orbit_span(&r.extents_nd) / extent_scale(&r.extents_nd))
        };
        let s_run = sampling(res).filter(|_| res.period == 0);
        let second = if rub && r1 > 1.0 && fine.is_none() && s_run.is_none() {
            coarser_than(&cplan, 0.8 * cplan.limit).and_then(|p4| Some((p4, companion(&p4)?)))
        } else {
            None
        };
        let (dt_coarser, ext2, lin2) = match &second {
            Some((p4, c4)) => {
                let r2 = cplan.steps_per_rev as f64 / p4.steps_per_rev as f64;
                let down = r1.powf(p);
                let d = Discrepancy::between(c4, &c, scales);
                let e = richardson(d.extents, r2, p) / down;
                let l = richardson(d.lines, r2, p) / down;
                (Some(p4.dt), Some(e), Some(l))
            }
            None => (None, None, None),
        };
        let (dt_fine, extf, linf) = match &fine {
            Some((fp, f)) => {
                let d = Discrepancy::between(f, res, scales);
                (
                    Some(fp.dt),
                    Some(richardson(d.extents, 0.5, p)),
                    Some(richardson(d.lines, 0.5, p)),
                )
            }
            None => (None, None, None),
        };
        let (extents_rel, lines_rel) = match (extf, linf, s_run) {
            (Some(ef), Some(lf), _) => (combine_fine(ef, ext1), combine_fine(lf, lin1)),
            (_, _, Some(sr)) => {
                let sc = sampling(&c).unwrap_or(0.0) * extent_scale(&c.extents_nd) / scales.extents;
                (attractor_error(d1.extents, sr, sc, r1, p), lin1)
            }
            _ => (combine_levels(ext1, ext2), combine_levels(lin1, lin2)),
        };
        Some(ErrorEstimate {
            dt_coarse: cplan.dt,
            order: p,
            extents_rel,
            lines_rel,
            same_period: c.period == res.period,
            dt_coarser,
            extents_rel_pair: ext1,
            extents_rel_coarse_pair: ext2,
            dt_fine,
            extents_rel_fine_pair: extf,
            extents_rel_sampling: s_run,
        })
    }
}

impl Prepared {
    /// The error estimate's companion request for the run `res`: its transient cut, then
    /// lcm(6, period) revolutions analysed when it is steady and periodic (`periodic`), its
    /// whole window otherwise ([`RunRequest::companion`]). Returns the request, the analysed
    /// revolutions and `periodic`.
    fn companion_request(&self, res: &SpeedResults) -> (RunRequest, usize, bool) {
        let repeat = lcm(WINDOW_MULTIPLE, res.period);
        let periodic = res.steady && res.period > 0 && repeat <= res.window_revolutions;
        let window = if periodic {
            repeat
        } else {
            res.window_revolutions
        };
        let s = self.request.companion(res.transient_revolutions, window);
        (s, window, periodic)
    }
}

/// The plan of `s` at 2Δt of `p` (at most `cap`, s) when it has fewer steps per revolution.
fn coarser_plan(case: &Case, s: &RunRequest, p: &StepPlan, cap: f64) -> Option<StepPlan> {
    let mut coarse = s.step;
    coarse.dt = Some((2.0 * p.dt).min(cap));
    plan_steps(case, &coarse)
        .ok()
        .filter(|c| c.steps_per_rev < p.steps_per_rev)
}

impl Prepared {
    /// The companion at Δt/2 restarted from the run's end state `end` ([`Stepper::restart`]):
    /// [`FINE_SETTLE_REVOLUTIONS`] (at most the run's transient) to settle out the restart, then
    /// `window` analysed. Returns its plan and results; `None` when it cannot restart or fails.
    /// A fixed window (`run.duration`) keeps no end state (`drive_with`), so it never runs: it
    /// would integrate past the window's end.
    fn fine_companion(
        &self,
        res: &SpeedResults,
        end: &EndState,
        window: usize,
    ) -> Option<(StepPlan, SpeedResults)> {
        let (plan, s) = (&res.plan, &self.request);
        if end.step != plan.steps || plan.steps % plan.steps_per_rev.max(1) != 0 {
            return None;
        }
        let settle = FINE_SETTLE_REVOLUTIONS.min(res.transient_revolutions);
        let spr = 2 * plan.steps_per_rev;
        let fplan = StepPlan {
            dt: 0.5 * plan.dt,
            steps_per_rev: spr,
            record_every: 2 * plan.record_every,
            steps: (settle + window) * spr,
            steady_from: settle * spr,
            ..*plan
        };
        let mut st = Stepper::new(&self.case, s.step.integrator, &fplan, s.initial()).ok()?;
        if !st.restart(end) {
            return None;
        }
        let (rec, stats) = st.run(None).ok()?;
        Some((
            fplan,
            analyse(&self.case, s, &fplan, &rec, stats, Keep::default()),
        ))
    }
}
