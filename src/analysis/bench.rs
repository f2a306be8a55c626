//! The bench: a scene's sweep timed (best of several repetitions, no output) and, on request,
//! compared with a converged reference sweep.

use super::{
    extents_error, run_speed, sweep, ExtentsScale, Keep, RunRequest, RunSettings, SweepResults,
};
use crate::error::Result;
use crate::model::Model;
use crate::scene::RunSpec;
use crate::time::one_at_a_time;

/// The speeds a bench times: the scene's sweep, or its single speed (ν = 1 without one).
pub fn speeds(run: &RunSpec, model: &Model) -> Vec<f64> {
    match &run.sweep {
        Some(w) => super::sweep_speeds(w.from, w.to, w.step),
        None => vec![super::single_speed(run, model).unwrap_or(1.0)],
    }
}

/// Runs the sweep over `speeds` `repeat` times (at least once, nothing kept but the scalars)
/// and returns the fastest by wall time.
pub fn best_of(
    model: &Model,
    s: &RunSettings,
    speeds: &[f64],
    repeat: usize,
) -> Result<SweepResults> {
    let mut best: Option<SweepResults> = None;
    for _ in 0..repeat.max(1) {
        let run = |k, v| run_speed(model, &s.request_at(k, v), Keep::default());
        let r = sweep(one_at_a_time(model), speeds, &run, &|| {})?;
        if best.as_ref().is_none_or(|b| r.wall_s < b.wall_s) {
            best = Some(r);
        }
    }
    Ok(best.expect("at least one repetition"))
}

/// Loop time per step of the main runs (ns): the loops' wall times over their steps.
pub fn ns_per_step(r: &SweepResults) -> f64 {
    let loop_s: f64 = r.speeds.iter().map(|x| x.stats.wall_s).sum();
    loop_s / r.total_steps() as f64 * 1e9
}

/// The converged reference sweep over `speeds`: each speed's [`RunRequest::reference`]
/// (collocated at Δt 16× finer, from the scene's start, without error estimate).
pub fn reference(model: &Model, s: &RunSettings, speeds: &[f64]) -> Result<SweepResults> {
    let run = |_, v| run_speed(model, &RunRequest::reference(s, v), Keep::default());
    sweep(one_at_a_time(model), speeds, &run, &|| {})
}

/// The orbit-extents error of a timed sweep against a reference sweep over the same speeds:
/// per speed [`extents_error`] relative to the reference orbit's size ([`ExtentsScale::Span`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceComparison {
    /// Median error over the speeds.
    pub median: f64,
    /// Largest error over the speeds where the reference is periodic (0 when none is).
    pub largest_periodic: f64,
    /// Largest error over all speeds.
    pub largest: f64,
    /// Speed ω/ω_n of the largest error.
    pub largest_at: f64,
    /// Reference Poincaré period at that speed.
    pub largest_period: usize,
    /// Speeds with an error above 1 %.
    pub above_one_percent: usize,
    /// Speeds compared.
    pub speeds: usize,
}

/// Compares `timed` with `reference` speed by speed (the two sweeps over the same speeds).
pub fn compare(timed: &SweepResults, reference: &SweepResults) -> ReferenceComparison {
    let mut errs: Vec<(f64, f64, usize)> = timed
        .speeds
        .iter()
        .zip(&reference.speeds)
        .map(|(a, b)| {
            let e = extents_error(&a.extents_nd, &b.extents_nd, ExtentsScale::Span);
            (a.speed_ratio, e, b.period)
        })
        .collect();
    let periodic: Vec<f64> = errs.iter().filter(|x| x.2 > 0).map(|x| x.1).collect();
    let worst = errs
        .iter()
        .cloned()
        .fold((0.0, 0.0, 0), |m, x| if x.1 > m.1 { x } else { m });
    errs.sort_by(|a, b| a.1.total_cmp(&b.1));
    ReferenceComparison {
        median: errs[errs.len() / 2].1,
        largest_periodic: periodic.iter().cloned().fold(0.0, f64::max),
        largest: worst.1,
        largest_at: worst.0,
        largest_period: worst.2,
        above_one_percent: errs.iter().filter(|x| x.1 > 0.01).count(),
        speeds: errs.len(),
    }
}
