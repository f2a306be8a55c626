//! The step choice verified by the run it chose for ([`Prepared::run`]): the pilots predict the
//! chosen step's error on a short window, the run then measures it on its own steady window
//! with its companions ([`super::ErrorEstimate`]). Where the two disagree — the run's estimate
//! `max(extents_rel, lines_rel)` is above `run.tolerance` — the pilots' short window did not
//! represent the steady response, and the step is refined and the run repeated.
//!
//! A companion at 2Δt that finds another Poincaré period (`same_period = false`) is not a miss
//! by itself: the coarser companion of a step that is fine enough can be in another regime —
//! on the paper's rod at ε = 10⁵, ν = 1.5 the steady 1× run at Δt = 2.60e-6 s (estimate 4.7e-4,
//! by its finer pair) has a chaotic companion at 2Δt, and asking the two to agree refined a run
//! that meets the tolerance to a quarter of its step. The estimate, which weighs the finer pair
//! where there is one, decides.
//!
//! # Rule
//!
//! Of a run whose step was chosen from the tolerance ([`super::StepChoice`]), whose request asks
//! for it ([`super::FollowUps::refine_step`]: not a run whose frames are written to a time
//! series as they are computed) and whose error estimate *misses* (above):
//!
//! 1. the step is halved, `Δt_{k+1} = Δt_k / 2` (the scale of the paper's rule halved: the
//!    pilots' levels are halvings, so this is the next finer level the pilots measured when the
//!    choice was one), and the run repeated with its companions — from the scene's start and
//!    over the scene's transient, not from the pilots' end state: that state belongs to the
//!    step the run just rejected (on the paper's rod at ε = 10⁵, ν = 1.5 the run at Δt/2
//!    restarted from the pilots' state with its transient cut to 2 revolutions had not settled,
//!    a residual of 1.2e-3 read as a long period 9; from the scene's start it is the steady 1×
//!    response, estimate 5.8e-4);
//! 2. at most [`MAX_STEP_REFINEMENTS`] times, and not past `run.max_steps` (a plan the budget
//!    refuses ends the refinement);
//! 3. the run delivered is the last one (the finest step), with a [`StepRefinement`] that lists
//!    each rejected step, its estimate and why it was rejected, and whether the last one meets
//!    the tolerance; its steps and loop wall time are counted there.
//!
//! The cost is paid only where the run's own estimate misses: a run that meets the tolerance
//! at the chosen step is delivered as it is. With `e(h) ≈ C hᵖ` a halving divides the step's
//! error by `2ᵖ` (4 for the second-order schemes), so a run the pilots' fit under-predicted by
//! less than that meets the tolerance after one refinement; a response that changes character
//! with the step (periodic at Δt/2, chaotic at Δt: the paper's rod at ε = 10⁵, ν = 1.5) is
//! found on the finer step's own estimate.

use super::refinement::{RejectedStep, StepRefinement};
use super::speed::{Prepared, SpeedResults};
use super::{Keep, RunRequest};
use crate::error::Result;
use crate::time::{plan_steps, FrameSink};

/// Most times the step is halved after a run whose estimate misses the tolerance.
pub const MAX_STEP_REFINEMENTS: usize = 2;

impl StepRefinement {
    /// One line saying what was refined and why, for the command line.
    pub fn describe(&self, res: &SpeedResults, tolerance: f64) -> String {
        let steps: Vec<String> = self
            .rejected
            .iter()
            .map(|r| {
                format!(
                    "Δt = {:.3e} s ({}, estimate {:.1e} > {tolerance:e})",
                    r.dt,
                    r.regime.name(),
                    r.estimate
                )
            })
            .collect();
        let end = match (&self.stopped, res.error) {
            (None, Some(e)) => format!("meets it ({:.1e})", e.largest()),
            (Some(s), _) => format!("still misses it (stopped: {s})"),
            (None, None) => "not estimated".to_string(),
        };
        format!(
            "ω/ωn = {:.3}: step refined after the run: {} rejected; Δt = {:.3e} s {end}",
            res.speed_ratio,
            steps.join(", "),
            res.plan.dt
        )
    }
}

/// Whether the run `res`'s own error estimate `max(extents_rel, lines_rel)` is above
/// `tolerance` (or not a number); false when it was not estimated.
pub fn misses(res: &SpeedResults, tolerance: f64) -> bool {
    res.error.is_some_and(|e| {
        let est = e.largest();
        est > tolerance || est.is_nan()
    })
}

impl Prepared {
    /// Runs the request: integrates it by its window policy (`Prepared::drive_with`: a
    /// settling run until the steady state is proven or the transient reaches its cap),
    /// handing frames to `sinks`, then [`super::analyse`]s the window and runs its follow-ups:
    /// the error estimate's companions (no sinks, the same transient,
    /// [`super::ErrorEstimate`]); where the step was chosen from the tolerance and that
    /// estimate misses it, the step refined and the run repeated (module doc,
    /// [`SpeedResults::step_refinement`]); then, on the run delivered, the coexistence check.
    /// Frames cover the revolutions their sinks ask for, counted from the start of the run
    /// (a repeated run hands its frames to the sinks again).
    ///
    /// # Errors
    /// As [`Prepared::integrate`]; the companion run's failure only leaves the estimate out.
    pub fn run(&self, keep: Keep, sinks: &mut [&mut dyn FrameSink]) -> Result<SpeedResults> {
        let (mut res, mut end) = self.run_estimated(keep, sinks)?;
        let refining = self.request.follow_ups.refine_step && self.request.choice.is_some();
        let mut finer: Option<Prepared> = None;
        let mut rejected = Vec::new();
        let mut stopped = None;
        while refining && misses(&res, self.request.tolerance) {
            if rejected.len() >= MAX_STEP_REFINEMENTS {
                stopped = Some("bound".to_string());
                break;
            }
            let current = finer.as_ref().unwrap_or(self);
            let Some(next) = current.halved() else {
                stopped = Some("budget".to_string());
                break;
            };
            rejected.push(rejected_step(&current.request, &res));
            (res, end) = next.run_estimated(keep, sinks)?;
            finer = Some(next);
        }
        if !rejected.is_empty() {
            res.step_refinement = Some(StepRefinement {
                rejected,
                met: stopped.is_none(),
                stopped,
            });
        }
        let last = finer.as_ref().unwrap_or(self);
        if last.request.follow_ups.coexistence {
            match super::coexist::check_with_companion(last, &res, end.as_ref()) {
                Ok(Some((mut c, companion))) => {
                    // A flagged speed: both responses shot as periodic orbits.
                    if let Some((cr, ce)) = companion.filter(|_| c.coexisting) {
                        let run = (&res, end.as_ref());
                        let other = (&*cr, ce.as_ref());
                        c.orbits = Some(super::coexist_orbits::shoot_both(last, run, other));
                    }
                    res.coexistence = Some(c);
                }
                Ok(None) => res.coexistence = None,
                Err(why) => res.coexistence_failed = Some(why),
            }
        }
        Ok(res)
    }

    /// This run at half its step (the scale of the paper's rule halved) from the scene's start
    /// ([`RunRequest::without_pilot`]), the case a copy; `None` when its plan is refused (above
    /// `run.max_steps`) or has no more steps a revolution.
    fn halved(&self) -> Option<Prepared> {
        let mut request: RunRequest = self.request.without_pilot();
        request.step.dt_scale *= 0.5;
        let plan = plan_steps(&self.case, &request.step).ok()?;
        (plan.steps_per_rev > self.plan.steps_per_rev).then(|| Prepared {
            request,
            plan,
            case: self.case.clone(),
            ..*self
        })
    }
}

/// The record of the run `res` of `request`, rejected by its estimate.
fn rejected_step(request: &RunRequest, res: &SpeedResults) -> RejectedStep {
    let e = res.error;
    RejectedStep {
        dt: res.plan.dt,
        dt_scale: request.step.dt_scale,
        estimate: e.map_or(f64::NAN, |e| e.largest()),
        same_period: e.is_none_or(|e| e.same_period),
        regime: res.dynamics.regime,
        steps: res.stats.steps as u64,
        wall_s: res.stats.wall_s,
    }
}
