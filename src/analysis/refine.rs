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

/// Free DOFs of the meshed stators of `model` (0 when it has none): what a mesh refinement
/// must make grow.
pub fn meshed_dofs(model: &Model) -> usize {
    model
        .stators
        .iter()
        .map(|s| match s {
            crate::model::StatorPlan::Mesh { model, .. } => model.ndof,
            _ => 0,
        })
        .sum()
}

/// Checks that a refinement study refines: the meshed stators' free DOFs of each value of
/// `key` (`steps`: value, DOFs, coarse to fine) exceed those of the value before. Errors name
/// the key, both values and both counts — a finer size that gives no finer mesh (a fixed
/// boundary count, a structured mesh ignoring the key, the values given fine to coarse) would
/// make the study compare equal or coarser meshes without a word.
pub fn check_refines(key: &str, steps: &[(String, usize)]) -> std::result::Result<(), String> {
    for w in steps.windows(2) {
        let ((a, na), (b, nb)) = (&w[0], &w[1]);
        if nb <= na {
            return Err(format!(
                "`{key}` = {b} gives the meshed stators {nb} free DOFs, no more than the {na} of `{key}` = {a} before it: the mesh is not refined as asked (the values go coarse to fine, and this key must refine the mesh: a geometry's fixed boundary counts or structured mesh may ignore it)"
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::check_refines;

    #[test]
    fn a_refinement_that_does_not_grow_is_refused_naming_key_values_and_counts() {
        let s = |v: &str, n| (v.to_string(), n);
        assert!(check_refines("k", &[s("1", 10), s("2", 20), s("3", 40)]).is_ok());
        let e = check_refines(
            "stator.0.parameters.h",
            &[s("0.002", 4668), s("0.001", 768)],
        )
        .unwrap_err();
        for part in ["`stator.0.parameters.h` = 0.001", "768", "4668", "= 0.002"] {
            assert!(e.contains(part), "{part}: {e}");
        }
        assert!(check_refines("k", &[s("1", 10), s("2", 10)]).is_err());
    }
}
