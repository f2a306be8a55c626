//! Mesh refinement (`rubsim refine`): one run per refinement of a meshed stator, with the
//! contact force's ripple — the node-to-nodes contact's sensitivity to the boundary
//! discretisation — and the cost per step.

use super::{prepare, Keep, RunSettings, SpeedResults};
use crate::error::Result;
use crate::model::Model;

/// Total variation of a force history per revolution over twice its peak-to-peak range: 1 for
/// a smooth once-per-revolution pulse, larger when the force ripples (nodes being passed).
/// `history` holds `(time in revolutions, force)`; NaN for fewer than 3 samples, a constant
/// force or no elapsed time.
pub fn ripple(history: &[(f64, f64)]) -> f64 {
    if history.len() < 3 {
        return f64::NAN;
    }
    let tv: f64 = history.windows(2).map(|w| (w[1].1 - w[0].1).abs()).sum();
    let (lo, hi) = history
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.1), b.max(p.1))
        });
    let revs = history.last().map_or(0.0, |p| p.0) - history[0].0;
    if hi - lo <= 0.0 || revs <= 0.0 {
        return f64::NAN;
    }
    tv / (2.0 * (hi - lo) * revs)
}

/// One refinement's run.
#[derive(Debug, Clone)]
pub struct RefinePoint {
    /// The run (orbit and force history kept).
    pub results: SpeedResults,
    /// Contact targets of all stators.
    pub targets: usize,
    /// Free DOFs of all stators.
    pub dofs: usize,
    /// End of the force history (revolutions).
    pub t_end: f64,
    /// The force history over the last `window` revolutions (revolutions, F_y/|U|ω²).
    pub tail: Vec<(f64, f64)>,
    /// [`ripple`] of that tail.
    pub ripple: f64,
    /// Loop time per step (µs).
    pub us_per_step: f64,
    /// Time of everything but the loop: case, plan, analysis (s).
    pub setup_s: f64,
}

/// Runs `model` at ν = `speed_ratio` keeping orbit and force history, and measures the force's
/// ripple over the last `window` revolutions.
pub fn refine_point(
    model: &Model,
    s: &RunSettings,
    speed_ratio: f64,
    window: usize,
) -> Result<RefinePoint> {
    let keep = Keep {
        orbit: true,
        force_history: true,
        spectrum_up_to: None,
        full_spectrum: false,
    };
    let t0 = std::time::Instant::now();
    let prep = prepare(model, &s.request(speed_ratio))?;
    let r = prep.run(keep, &mut [])?;
    let setup_s = t0.elapsed().as_secs_f64() - r.stats.wall_s;
    let us_per_step = 1e6 * r.stats.wall_s / r.stats.steps.max(1) as f64;
    let targets: usize = prep.case.stators.iter().map(|m| m.targets.len()).sum();
    let dofs: usize = prep.case.stators.iter().map(|m| m.ndof).sum();
    let t_end = r.force_history.last().map_or(0.0, |p| p.0);
    let tail: Vec<(f64, f64)> = r
        .force_history
        .iter()
        .copied()
        .filter(|p| p.0 >= t_end - window as f64)
        .collect();
    Ok(RefinePoint {
        ripple: ripple(&tail),
        results: r,
        targets,
        dofs,
        t_end,
        tail,
        us_per_step,
        setup_s,
    })
}
