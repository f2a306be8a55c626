//! Lengthening a window that is not periodic for the 0–1 test ([`super::dynamics`]), and what a
//! run that runs away when continued reports.
//!
//! A run whose steady window has no period up to [`MAX_PERIOD`] goes on to
//! `run.classify_revolutions` revolutions so that its Poincaré section has enough points for
//! the 0–1 test. A response that is bounded over the window may still grow without bound when
//! continued (dry whip building up, a slowly unstable orbit): the lengthened run then meets the
//! divergence guard ([`SolveError::Diverged`], or a value that is not finite). That is not a
//! failure of the run the user asked for — its window was integrated without error — but a
//! finding about the response: the window is kept, re-run as it was planned (the stepper's
//! state is lost to the divergence), and reported as [`super::Regime::Diverging`], not steady,
//! with the time at which the continuation left the bounds. A run that diverges inside its own
//! planned window (the transient and the analysed window) still stops with the error.

use super::speed::{window_points, Prepared};
use super::steady::judge;
use super::{RunRequest, MAX_PERIOD};
use crate::error::{Result, SolveError};
use crate::time::{History, Sink, Stepper};

/// The time (s) of a divergence stop — the guard's bound or a value that is not finite — or
/// `None` for any other error.
fn runaway_time(e: &SolveError) -> Option<f64> {
    match e {
        SolveError::Diverged { time, .. } | SolveError::NonFinite { time, .. } => Some(*time),
        _ => None,
    }
}

impl Prepared {
    /// Lengthens the window of `st` (run to the end of its plan, the request `s`) to `classify`
    /// revolutions (`run.classify_revolutions`) when it is not periodic (the rule of [`super::analyse`]), within `run.max_steps`; with
    /// `keep_end`, `older` receives uᴺ⁻² of the run's end on the way. Returns the stepper to
    /// finish and, when the lengthening ran away, the time (s) the guard stopped it: the
    /// stepper is then a fresh run of the plan as it stood before the lengthening, without
    /// frames (its sink already had them).
    ///
    /// # Errors
    /// The loop's errors other than a divergence of the lengthening; a divergence of the
    /// re-run plan (it did not diverge the first time, so only a changed loop would).
    pub(super) fn lengthen<'a>(
        &'a self,
        mut st: Stepper<'a>,
        s: &RunRequest,
        classify: usize,
        sink: &mut Sink<'_>,
        keep_end: bool,
        older: &mut Option<History>,
    ) -> Result<(Stepper<'a>, Option<f64>)> {
        let p = *st.plan();
        let spr_steps = p.steps_per_rev.max(1);
        let (w, nrev) = window_points(&self.case, s, &p, st.recorded());
        let (_, _, class) = judge(&w, s.step.samples_per_rev, nrev, s.tolerance, MAX_PERIOD);
        let by_steps = (s.step.max_steps as usize).saturating_sub(p.steps) / spr_steps;
        let more = classify.saturating_sub(nrev).min(by_steps);
        if class.period > 0 || more == 0 {
            return Ok((st, None));
        }
        let steps = p.steps + more * spr_steps;
        st.extend(steps, p.steady_from);
        let mut go = || -> std::result::Result<(), SolveError> {
            if keep_end {
                // The end state is the lengthened run's: uᴺ⁻² kept on the way again.
                st.run_to(steps - 1, sink)?;
                *older = Some(st.history());
            }
            st.run_to(steps, sink)
        };
        let t = match go() {
            Ok(()) => return Ok((st, None)),
            Err(e) => match runaway_time(&e) {
                Some(t) => t,
                None => return Err(e.into()),
            },
        };
        // The window as planned, again: the same steps up to the lengthening's start.
        let mut again = Stepper::new(&self.case, s.step.integrator, &p, s.initial())?;
        let mut none: Sink<'_> = None;
        if keep_end {
            again.run_to(p.steps.saturating_sub(1), &mut none)?;
            *older = Some(again.history());
        }
        again.run_to(p.steps, &mut none)?;
        Ok((again, Some(t)))
    }
}
