//! `rubsim run`: one speed, its summary, pictures and time series.

use super::{default_out, load, settings, Common, Series};
use anyhow::{Context, Result};
use rubsim::analysis::{self, Keep};
use rubsim::output::{figures, summary, OutDir};
use std::path::PathBuf;

/// Runs the scene at `speed` (default: its own single speed) and writes `summary.json`,
/// `orbit.png`, `spectrum.png`, `contact_force.png` and the VTK/HDF5 series it asks for.
pub fn run(c: &Common, out: Option<PathBuf>, speed: Option<f64>) -> Result<()> {
    let (ls, model) = load(c)?;
    if let Some(v) = speed {
        if !(v.is_finite() && v > 0.0) {
            anyhow::bail!("--speed must be a positive ω/ω_n, got {v}");
        }
    }
    let v = speed
        .or_else(|| analysis::single_speed(&ls.scene.run, &model))
        .with_context(|| {
            format!(
                "{}: `rubsim run` needs run.speed_ratio or run.speed, or --speed (this scene has a sweep: use `rubsim sweep`)",
                c.scene.display()
            )
        })?;
    let mut outd = OutDir::prepare(&out.unwrap_or_else(|| default_out(&c.scene)))?;
    let s = settings(&ls);
    let keep = Keep::single_run(&ls.scene.output, v);
    let t0 = std::time::Instant::now();
    let prep = analysis::prepare(&model, &s, v)?;
    // VTK/HDF5 time series (output.vtk, output.hdf5) stream into the staging folder.
    let scene_json = serde_json::to_string(&ls.scene)?;
    let series = Series {
        output: &ls.scene.output,
        scene_json: &scene_json,
        staging: outd.staging_dir(),
    };
    let (r, written) = series.run_single(&model, &prep, keep, "")?;
    for name in &written {
        outd.adopt(name)?;
    }
    if ls.scene.output.png {
        figures::write_run(
            &mut outd,
            &ls.scene.title,
            &r,
            figures::boundary(&prep.case),
            &ls.scene.output.component,
        )?;
    }
    let mut sum = summary::base(&ls, &model, "run");
    sum["result"] = serde_json::to_value(&r)?;
    sum["regime"] = analysis::regime_name(r.period).into();
    sum["wall_s"] = t0.elapsed().as_secs_f64().into();
    let dir = summary::finish(outd, &sum)?;
    println!(
        "ω/ωn = {:.3}: {} | x/|Z0| ∈ [{:.3}, {:.3}], y/|Z0| ∈ [{:.3}, {:.3}] | 1× {:.3}, 1/2× {:.3}, 1/3× {:.3} | {} steps (Δt = {:.3e} s) in {:.3} s | est. rel. error {}",
        r.speed_ratio,
        analysis::regime_name(r.period),
        r.extents_nd[0], r.extents_nd[1], r.extents_nd[2], r.extents_nd[3],
        r.amp_1x_nd, r.amp_half_nd, r.amp_third_nd,
        r.stats.steps, r.plan.dt, r.stats.wall_s,
        r.error.map(|e| format!("{:.1e}", e.extents_rel)).unwrap_or_else(|| "not estimated".into())
    );
    println!("results in {}", dir.display());
    Ok(())
}
