//! Lengthening a window that is not periodic for the 0–1 test ([`super::dynamics`]), and what a
//! run that runs away when continued reports.
//!
//! A run whose steady window has no period up to [`MAX_PERIOD`] goes on to
//! `run.classify_revolutions` revolutions so that its Poincaré section has enough points for
//! the 0–1 test — unless it rolls on its stator (dry whirl, [`super::dry::record_rolls`]),
//! whose whirl at −RΩ/δ is not locked to the spin. A response that is bounded over the window may still grow without bound when
//! continued (dry whip building up, a slowly unstable orbit): the lengthened run then meets the
//! divergence guard ([`SolveError::Diverged`], or a value that is not finite). That is not a
//! failure of the run the user asked for — its window was integrated without error — but a
//! finding about the response: the window is kept, re-run as it was planned (the stepper's
//! state is lost to the divergence), and reported as [`super::Regime::Diverging`], not steady,
//! with the time at which the continuation left the bounds. A run that diverges inside its own
//! planned window (the transient and the analysed window) still stops with the error.
//!
//! # A verdict that does not hang on round-off
//!
//! At a finite number `N` of Poincaré points the 0–1 test's median `K` of a chaotic response
//! scatters below its limit 1: on the chaotic cell ν 2.4, δ_nd 0.5, ξ 0.02 of
//! `scenes/paper/regime_map.toml` it read 0.87 at `N` = 400, and 0.68 (`undetermined`) after a
//! round-off change of the unbalance load, while at 800 and 1600 points both trajectories read
//! 0.95–0.99. So a window lengthened to `classify` revolutions whose `K` falls between
//! [`K_REGULAR`] and [`K_CHAOTIC`] (and is not a regular window still settling) is lengthened
//! again, doubling, up to [`MAX_CLASSIFY_FACTOR`] × `classify` revolutions (within
//! `run.max_steps`): the thresholds stay, the sample grows until `K` leaves the band or the
//! bound is reached — weak or intermittent chaos, a torus breaking up, then reads
//! `undetermined` on the longest window.

use super::discrepancy::orbit_span;
use super::dry::record_rolls;
use super::dynamics::{dynamics, Regime, K_CHAOTIC, K_REGULAR};
use super::speed::{window_points, Prepared};
use super::steady::judge;
use super::{RunRequest, MAX_PERIOD};
use crate::error::{Result, SolveError};
use crate::math::V2;
use crate::signal::extents;
use crate::time::{History, Sink, Stepper};

/// Most revolutions a window that is not periodic is lengthened to, as a multiple of
/// `run.classify_revolutions`, while its 0–1 test's `K` stays between the thresholds (module
/// doc): 4, two doublings.
pub const MAX_CLASSIFY_FACTOR: usize = 4;

/// Whether the window `w` (non-dimensional samples, `nrev` whole revolutions of `spr` samples,
/// the request `s`) reads `undetermined` by a 0–1 test `K` between [`K_REGULAR`] and
/// [`K_CHAOTIC`], as [`super::analyse`] would classify it: a longer sample may tell it.
fn k_in_band(w: &[V2], spr: usize, nrev: usize, s: &RunRequest) -> bool {
    let (stn, steady, class) = judge(w, spr, nrev, s.tolerance, MAX_PERIOD);
    let section: Vec<V2> = w.iter().step_by(spr.max(1)).take(nrev).copied().collect();
    let span = orbit_span(&extents(w));
    let d = dynamics(
        class.period,
        &section,
        s.component,
        span,
        class.tolerance,
        &stn,
        steady,
    );
    d.regime == Regime::Undetermined
        && d.zero_one_k
            .is_some_and(|k| (K_REGULAR..=K_CHAOTIC).contains(&k))
}

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
    /// revolutions (`run.classify_revolutions`) when it is not periodic (the rule of
    /// [`super::analyse`]), then doubles it while its 0–1 test's `K` is between the thresholds,
    /// up to [`MAX_CLASSIFY_FACTOR`] × `classify` (module doc), within `run.max_steps`; with
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
        let spr = s.step.samples_per_rev;
        let (w, nrev) = window_points(&self.case, s, &p, st.recorded());
        let (_, _, class) = judge(&w, spr, nrev, s.tolerance, MAX_PERIOD);
        // A roll whirls at −RΩ/δ, not locked to the spin: its section is a turning circle and
        // its class dry whirl whatever a longer section would read (docs/STICK.md §4).
        let first = p.steady_from / p.record_every.max(1);
        if class.period > 0 || classify == 0 || record_rolls(&self.case, st.recorded(), first) {
            return Ok((st, None));
        }
        // To `classify` revolutions, then doubling while the 0–1 test is undetermined by a K
        // between its thresholds (module doc), within `run.max_steps`.
        let mut target = classify;
        let mut at = p.steps;
        let t = loop {
            let by_steps = (s.step.max_steps as usize).saturating_sub(at) / spr_steps;
            let now = (at - p.steady_from) / spr_steps;
            let more = target.saturating_sub(now).min(by_steps);
            if more == 0 {
                return Ok((st, None));
            }
            let steps = at + more * spr_steps;
            st.extend(steps, p.steady_from);
            let mut go = || -> std::result::Result<(), SolveError> {
                if keep_end {
                    // The end state is the lengthened run's: uᴺ⁻² kept on the way again.
                    st.run_to(steps - 1, sink)?;
                    *older = Some(st.history());
                }
                st.run_to(steps, sink)
            };
            match go() {
                Ok(()) => {}
                Err(e) => match runaway_time(&e) {
                    Some(t) => break t,
                    None => return Err(e.into()),
                },
            }
            at = steps;
            let longer = 2 * target;
            if longer > MAX_CLASSIFY_FACTOR * classify {
                return Ok((st, None));
            }
            let q = *st.plan();
            let (w, nrev) = window_points(&self.case, s, &q, st.recorded());
            if !k_in_band(&w, spr, nrev, s) {
                return Ok((st, None));
            }
            target = longer;
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
