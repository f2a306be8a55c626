//! `summary.json`: the base every command shares (version, command, scene, model,
//! conventions), the per-command records, and the finishing step that writes it last and
//! commits the output directory.

use super::OutDir;
use crate::analysis::refine::RefinePoint;
use crate::analysis::sweep::Variant;
use crate::analysis::{RegimeRange, StressResults, SweepResults};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::scene::LoadedScene;
use serde_json::{json, Value};
use std::path::PathBuf;

/// The part of `summary.json` every scene command writes: version, command, the scene (file,
/// overrides, resolved values), the rotor model and the conventions of the numbers.
pub fn base(ls: &LoadedScene, model: &Model, command: &str) -> Value {
    base_with(ls, model_record(model), command)
}

/// The `model` record of [`base`]: the rotor's description and ω_n.
pub fn model_record(model: &Model) -> Value {
    json!({
        "rotor": model.rotor.describe(),
        "omega_n_rad_s": model.rotor.natural_frequency(),
    })
}

/// [`base`] with the `model` record given (e.g. kept with a study's cases, so `rubsim merge`
/// needs no model).
pub fn base_with(ls: &LoadedScene, model: Value, command: &str) -> Value {
    json!({
        "rubsim_version": env!("CARGO_PKG_VERSION"),
        "command": command,
        "scene_file": ls.file.display().to_string(),
        "overrides": ls.overrides,
        "scene": ls.scene,
        "model": model,
        "conventions": {
            "units": "SI; _nd = displacement / |Z0(ω)|, force / (|Σ m_u e e^{iφ}| ω²), frequency / ω_n",
            "axes": "x horizontal, y vertical, rotor spins counter-clockwise seen from +z",
            "period": "Poincaré period in revolutions (the whole orbit repeats to run.tolerance of its size); 0 = not periodic",
            "dynamics": "periodic, quasi-periodic (0-1 test K < 0.2 on the Poincaré section), chaotic (K > 0.8) or undetermined; long_period = a period above 8 found on the Poincaré points (docs/OUTPUTS.md)",
        }
    })
}

/// Writes `summary.json` last, moves every staged file into place; returns the directory.
///
/// # Errors
/// [`Error::Output`] naming the file that could not be written or moved.
pub fn finish(mut out: OutDir, summary: &Value) -> Result<PathBuf> {
    let text = serde_json::to_string_pretty(summary)
        .map_err(|e| Error::output(out.dir().join("summary.json"), e))?;
    out.write("summary.json", text.as_bytes())?;
    let dir = out.dir().to_path_buf();
    out.commit()?;
    Ok(dir)
}

/// The record of one sweep of a parameter study (`sweeps[i]` of a sweep's summary).
pub fn sweep_variant(
    variant: &Variant,
    res: &SweepResults,
    regimes: &[RegimeRange],
    peaks: &[(usize, f64)],
) -> Value {
    json!({
        "variant": variant.overrides,
        "directory": variant.prefix,
        "wall_s": res.wall_s,
        "steps": res.total_steps(),
        "max_estimated_extents_error": res.max_estimated_error(),
        "unsteady_speeds": res.speeds.iter().filter(|r| !r.steady).map(|r| r.speed_ratio).collect::<Vec<_>>(),
        "regimes": regimes,
        "quasi_resonances": peaks,
        "speeds": res.speeds,
    })
}

/// The records of a stress run: one per stator and speed, with its peak stress and strain.
pub fn stress_records(r: &StressResults) -> Vec<Value> {
    r.traces
        .iter()
        .map(|tr| {
            json!({
                "speed_ratio": r.speed_ratio,
                "stator": tr.name,
                "peak_stress_pa": tr.peak_stress(),
                "peak_strain": tr.peak_strain(),
                "peak_time_s": tr.peak_time,
                "contacts_at_peak": tr.peak_contacts.len(),
                "samples": tr.t.len(),
                "dt_s": r.plan.dt,
            })
        })
        .collect()
}

/// The record of one refinement `(value of the key, its run)`.
pub fn refine_record(value: &str, p: &RefinePoint) -> Value {
    let r = &p.results;
    json!({
        "value": value, "targets": p.targets, "dofs": p.dofs, "extents_nd": r.extents_nd,
        "amp_1x_nd": r.amp_1x_nd, "contact_force_max_nd": r.contact_force_max_nd,
        "ripple": p.ripple, "period": r.period, "steps": r.stats.steps, "wall_s": r.stats.wall_s,
        "us_per_step": p.us_per_step, "setup_s": p.setup_s, "dt_s": r.plan.dt,
    })
}

/// The `summary.json` of `rubsim stress` (no scene base: the command's own record).
pub fn stress(
    scene_file: &std::path::Path,
    overrides: &[String],
    per_rev: usize,
    window: usize,
    records: Vec<Value>,
) -> Value {
    json!({
        "command": "stress",
        "scene_file": scene_file.display().to_string(),
        "overrides": overrides,
        "per_rev": per_rev,
        "window_revolutions": window,
        "results": records,
    })
}

/// The `summary.json` of `rubsim refine` (no scene base: the command's own record).
pub fn refine(
    scene_file: &std::path::Path,
    key: &str,
    overrides: &[String],
    records: Vec<Value>,
) -> Value {
    json!({
        "command": "refine", "scene_file": scene_file.display().to_string(),
        "key": key, "overrides": overrides, "results": records,
    })
}
