//! What a steady run tells its user without failing, as sentences: the command line prints
//! them as warnings, the Python package raises them as `RuntimeWarning`s.

use super::{Coexistence, SpeedResults, Start, SweepResults};

/// The warnings of a steady run, one message each (the command line prints them on stderr
/// after `warning: `): an error estimate above the tolerance the pilots
/// predicted to meet, coexisting responses, a roll the step or the record does not resolve, a
/// runaway, the run's own warnings or an unproven steady state (`tolerance`: `run.tolerance`).
pub fn run_warnings(r: &SpeedResults, tolerance: f64) -> Vec<String> {
    let mut out = Vec::new();
    if let (Some(e), Some(c)) = (r.error, r.step_choice) {
        if e.largest() > c.tolerance {
            out.push(format!(
                "ω/ωn = {:.3}: the run's 2Δt error estimate {:.1e} is above `run.tolerance` = {:e} although the pilots predicted {:.1e} for the chosen step: their short window did not represent this steady response; give a smaller `run.dt` (docs/VALIDATION.md §16)",
                r.speed_ratio,
                e.largest(),
                c.tolerance,
                c.error_predicted
            ));
        }
    }
    if let Some(c) = r.coexistence.as_ref().filter(|c| c.coexisting) {
        out.push(coexist_warning(r, c));
    }
    if let Some(why) = &r.coexistence_failed {
        out.push(why.clone());
    }
    out.extend(
        r.roll_warnings
            .iter()
            .map(|w| format!("ω/ωn = {:.3}: {w}", r.speed_ratio)),
    );
    if let Some(t) = r.dynamics.runaway_at_s {
        out.push(format!(
            "ω/ωn = {:.3}: the response runs away when continued: lengthened past its {}-revolution window for the 0–1 test (`run.classify_revolutions`), the run left the divergence bounds at t = {t:.4e} s; the results are those of the window (regime `diverging`, `steady = false`)",
            r.speed_ratio, r.window_revolutions
        ));
    } else if !r.warnings.is_empty() {
        out.extend(r.warnings.iter().cloned());
    } else if !r.steady {
        out.push(format!(
            "ω/ωn = {:.3}: the steady state was not proven within {} transient revolutions (`run.max_transient_revolutions`): the analysed window still changes by {:.1e} of the orbit's size, above `run.tolerance` = {:e}; the results carry that error (summary.json: `steady = false`)",
            r.speed_ratio,
            r.transient_revolutions,
            r.stationarity.residual,
            tolerance
        ));
    }
    out
}

/// The warning of a run whose response is not the only one at its speed
/// (`analysis::coexist`): what the companion from the other start found, and that the error
/// estimate covers the time step only.
pub fn coexist_warning(r: &SpeedResults, c: &Coexistence) -> String {
    let orbits = c
        .orbits
        .as_ref()
        .map(|o| format!("; as periodic orbits: {}", o.describe()))
        .unwrap_or_default();
    format!(
        "ω/ωn = {:.3}: the response depends on the start: from {} the same scheme and Δt settle on another response (contact fraction {:.2} against the run's {:.2}, period {} against {}, extents {:.1e} of the largest extent apart); the run's estimated error ({}) covers the time step only, not which response is taken (summary.json: `coexistence`; `run.check_coexistence`){orbits}",
        r.speed_ratio,
        match c.start {
            Start::Free => "the no-contact linear response",
            Start::FullContact => "full contact at the clearance, whirling forward",
        },
        c.contact_fraction,
        r.contact_fraction,
        c.period,
        r.period,
        c.extents_rel,
        r.error
            .map(|e| format!("{:.1e}", e.extents_rel))
            .unwrap_or_else(|| "not estimated".into()),
    )
}

/// The speeds of `res` (ω/ωn, two decimals) where `flag` holds.
pub fn speeds_where(res: &SweepResults, flag: impl Fn(&SpeedResults) -> bool) -> Vec<String> {
    res.speeds
        .iter()
        .filter(|r| flag(r))
        .map(|r| format!("{:.2}", r.speed_ratio))
        .collect()
}

/// The warnings of a sweep `res`, one message each, `prefix` starting each (a variant's
/// overrides and `: `, or empty): the speeds whose response runs away, whose steady state was
/// not proven, whose roll the step or the record does not resolve, whose response depends on
/// the start and whose coexistence check failed.
pub fn sweep_warnings(prefix: &str, res: &SweepResults) -> Vec<String> {
    let n = res.speeds.len();
    let mut out = Vec::new();
    let away: Vec<String> = res
        .speeds
        .iter()
        .filter_map(|r| {
            Some(format!(
                "{:.2} (t = {:.3e} s)",
                r.speed_ratio, r.dynamics.runaway_at_s?
            ))
        })
        .collect();
    if !away.is_empty() {
        out.push(format!(
            "{prefix}the response runs away when continued at ω/ωn {}: lengthened past its window for the 0–1 test (`run.classify_revolutions`), the run left the divergence bounds; their results are those of the window (regime `diverging`, `steady = false`)",
            away.join(", ")
        ));
    }
    let unsteady = speeds_where(res, |r| !r.steady && r.dynamics.runaway_at_s.is_none());
    if !unsteady.is_empty() {
        out.push(format!(
            "{prefix}the steady state was not proven at {} of {n} speeds (ω/ωn {}): their analysed window still changes by more than `run.tolerance` of the orbit's size {}; their results carry that error (`steady = false`, `transient_residual` in sweep.csv)",
            unsteady.len(),
            unsteady.join(", "),
            // A fixed window (`run.duration`) carries its warning in each case's record.
            if res.speeds.iter().any(|r| !r.warnings.is_empty()) {
                "at the end of the fixed window `run.duration`, not lengthened"
            } else {
                "after `run.max_transient_revolutions`"
            }
        ));
    }
    let unresolved = speeds_where(res, |r| !r.roll_warnings.is_empty());
    if !unresolved.is_empty() {
        out.push(format!(
            "{prefix}the roll at {} of {n} speeds (ω/ωn {}) is not resolved by the step or the record (each case's `roll_warnings`; the first: {})",
            unresolved.len(),
            unresolved.join(", "),
            res.speeds
                .iter()
                .find_map(|r| r.roll_warnings.first())
                .map_or("", String::as_str)
        ));
    }
    let coexisting = speeds_where(res, |r| {
        r.coexistence.as_ref().is_some_and(|c| c.coexisting)
    });
    if !coexisting.is_empty() {
        out.push(format!(
            "{prefix}the response depends on the start at {} of {n} speeds (ω/ωn {}): a companion at the same scheme and Δt from another start settled on another response (contact fraction, period or extents; `coexisting` and the `coexist_*` columns of sweep.csv); their estimated error covers the time step only",
            coexisting.len(),
            coexisting.join(", ")
        ));
    }
    let unchecked = speeds_where(res, |r| r.coexistence_failed.is_some());
    if !unchecked.is_empty() {
        out.push(format!(
            "{prefix}the coexistence check failed at {} of {n} speeds (ω/ωn {}): its companion from another start stopped with an error, so whether the response depends on the start is not known there (`coexistence_failed` in each case's record and in summary.json; the first: {})",
            unchecked.len(),
            unchecked.join(", "),
            res.speeds
                .iter()
                .find_map(|r| r.coexistence_failed.as_deref())
                .unwrap_or_default()
        ));
    }
    out
}
