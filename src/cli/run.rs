//! `rubsim run`: one speed, its summary, pictures and time series.

use super::{chosen_settings, default_out, load, run_single, settings, Common, UnitArg};
use anyhow::{Context, Result};
use rubsim::analysis::{self, Keep};
use rubsim::output::summary::{
    self, Base, RunBody, SnapshotsRecord, Summary, TransientBody, WaterfallRecord,
};
use rubsim::output::transient_stress::TransientStress;
use rubsim::output::{figures, transient as transient_out, whirl as whirl_out};
use rubsim::results::ResultsSink;
use rubsim::results::Series;
use rubsim::time::FrameSink;
use std::path::PathBuf;

/// Runs the scene at `speed` (default: its own single speed) and writes `summary.json`,
/// `orbit.png`, `spectrum.png`, `contact_force.png` and the VTK/HDF5 series it asks for.
pub fn run(c: &Common, out: Option<PathBuf>, speed: Option<f64>, unit: UnitArg) -> Result<()> {
    let (ls, model) = load(c)?;
    if ls.scene.run.speed_profile.is_some() {
        return transient(c, &ls, &model, out, speed);
    }
    if let Some(v) = speed {
        if !(v.is_finite() && v > 0.0) {
            anyhow::bail!("--speed must be a positive speed, got {v}");
        }
    }
    let speed = speed.map(|v| unit.ratio(v, model.rotor.natural_frequency()));
    let v = speed
        .or_else(|| analysis::single_speed(&ls.scene.run, &model))
        .with_context(|| {
            format!(
                "{}: `rubsim run` needs run.speed_ratio or run.speed, or --speed (this scene has a sweep: use `rubsim sweep`)",
                c.scene.display()
            )
        })?;
    let mut outd = super::open_out(&out.unwrap_or_else(|| default_out(&c.scene)))?;
    let t0 = std::time::Instant::now();
    let s = chosen_settings(&ls, &model, &[v])?;
    let keep = Keep::single_run(&ls.scene.output, v);
    let writes_series = rubsim::results::wanted(&ls.scene.output);
    let prep = analysis::prepare(&model, &s.request_for(0, v, writes_series))?;
    // VTK/HDF5 time series (output.vtk, output.hdf5) stream into the staging folder.
    let scene_json = serde_json::to_string(&ls.scene)?;
    let series = Series {
        output: &ls.scene.output,
        scene_json: &scene_json,
        staging: outd.staging_dir(),
    };
    let (r, written) = run_single(&series, &model, &prep, keep, "")?;
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
    whirl_out::write_run(&mut outd, &ls.scene.title, &r, ls.scene.output.png)?;
    let body = RunBody {
        result: &r,
        regime: analysis::regime_label(&r),
        dynamics: r.dynamics.regime.name(),
        coexisting: r.coexistence.as_ref().map(|c| c.coexisting),
        wall_s: t0.elapsed().as_secs_f64(),
    };
    let base = Base::new(&ls, &model, "run");
    let dir = summary::finish(outd, &Summary { base, body })?;
    println!(
        "ω/ωn = {:.3}: {} | x/|Z0| ∈ [{:.3}, {:.3}], y/|Z0| ∈ [{:.3}, {:.3}] | 1× {:.3}, 1/2× {:.3}, 1/3× {:.3} | whirl {} ({:+.3}×; 1× forward {:.3}, backward {:.3}) | {} {} steps (Δt = {:.3e} s) in {:.3} s | est. rel. error {}",
        r.speed_ratio,
        analysis::regime_label(&r),
        r.extents_nd[0], r.extents_nd[1], r.extents_nd[2], r.extents_nd[3],
        r.amp_1x_nd, r.amp_half_nd, r.amp_third_nd,
        r.whirl.direction.name(), r.whirl.dominant_order, r.whirl.forward_1x_nd, r.whirl.backward_1x_nd,
        s.step.integrator.name(), r.stats.steps, r.plan.dt, r.stats.wall_s,
        r.error.map(|e| format!("{:.1e}", e.extents_rel)).unwrap_or_else(|| "not estimated".into())
    );
    if r.stats.columns > 0 {
        println!(
            "  the stator compliance: {} columns computed in {:.3} s of the run (kept for its later runs)",
            r.stats.columns, r.stats.columns_s
        );
    }
    if let Some(f) = &r.step_refinement {
        println!("{}", f.describe(&r, ls.scene.run.tolerance));
    }
    warn_run(&r, ls.scene.run.tolerance);
    println!("results in {}", dir.display());
    Ok(())
}

/// The warnings of a steady run on stderr: an error estimate above the tolerance the pilots
/// predicted to meet, coexisting responses, a runaway, the run's own warnings or an unproven
/// steady state (`tolerance`: `run.tolerance`).
fn warn_run(r: &analysis::SpeedResults, tolerance: f64) {
    if let (Some(e), Some(c)) = (r.error, r.step_choice) {
        if e.largest() > c.tolerance {
            eprintln!(
                "warning: ω/ωn = {:.3}: the run's 2Δt error estimate {:.1e} is above `run.tolerance` = {:e} although the pilots predicted {:.1e} for the chosen step: their short window did not represent this steady response; give a smaller `run.dt` (docs/VALIDATION.md §16)",
                r.speed_ratio,
                e.largest(),
                c.tolerance,
                c.error_predicted
            );
        }
    }
    if let Some(c) = r.coexistence.filter(|c| c.coexisting) {
        eprintln!("warning: {}", coexist_warning(r, &c));
    }
    if let Some(why) = &r.coexistence_failed {
        eprintln!("warning: {why}");
    }
    if let Some(t) = r.dynamics.runaway_at_s {
        eprintln!(
            "warning: ω/ωn = {:.3}: the response runs away when continued: lengthened past its {}-revolution window for the 0–1 test (`run.classify_revolutions`), the run left the divergence bounds at t = {t:.4e} s; the results are those of the window (regime `diverging`, `steady = false`)",
            r.speed_ratio, r.window_revolutions
        );
    } else if !r.warnings.is_empty() {
        for w in &r.warnings {
            eprintln!("warning: {w}");
        }
    } else if !r.steady {
        eprintln!(
            "warning: ω/ωn = {:.3}: the steady state was not proven within {} transient revolutions (`run.max_transient_revolutions`): the analysed window still changes by {:.1e} of the orbit's size, above `run.tolerance` = {:e}; the results carry that error (summary.json: `steady = false`)",
            r.speed_ratio,
            r.transient_revolutions,
            r.stationarity.residual,
            tolerance
        );
    }
}

/// A scene with `[run.speed_profile]`: integrates the whole profile and writes
/// `summary.json`, the speed history, the response, the order tracking (CSV) and their
/// pictures (`rubsim::output::transient`), and the VTK/HDF5 series the scene asks for, whose
/// frames carry the spin state (`results::ResultsSink::for_transient`).
fn transient(
    c: &Common,
    ls: &rubsim::scene::LoadedScene,
    model: &rubsim::model::Model,
    out: Option<PathBuf>,
    speed: Option<f64>,
) -> Result<()> {
    let spec = ls
        .scene
        .run
        .speed_profile
        .as_ref()
        .context("no speed profile")?;
    if speed.is_some() {
        anyhow::bail!(
            "{}: --speed does not apply to a scene with [run.speed_profile] (the profile sets the speed)",
            c.scene.display()
        );
    }
    let mut outd = super::open_out(&out.unwrap_or_else(|| default_out(&c.scene)))?;
    let s = settings(ls);
    let t0 = std::time::Instant::now();
    let prep = analysis::prepare_transient(model, &s, spec)?.with_events(&ls.scene.run.event)?;
    print_plan(&prep);
    // VTK/HDF5 time series (output.vtk, output.hdf5): the frames carry Ω, Ω/ωn, φ and Ω̇.
    let scene_json = serde_json::to_string(&ls.scene)?;
    let mut writer = ResultsSink::for_transient(
        model,
        &prep,
        &ls.scene.output,
        &scene_json,
        outd.staging_dir(),
        "",
    )?;
    let mut probe = stress_probe(&prep);
    let mut sinks: Vec<&mut dyn FrameSink> = Vec::with_capacity(2);
    if let Some(w) = writer.as_mut() {
        sinks.push(w);
    }
    if let Some(p) = probe.as_mut() {
        sinks.push(p);
    }
    let r = prep.run(&mut sinks)?;
    drop(sinks);
    if let Some(w) = writer {
        for name in w.finish()? {
            outd.adopt(&name)?;
        }
    }
    let stress = probe.map(|p| TransientStress::new(&r, p.traces));
    if let Some(st) = &stress {
        st.write_csv(&mut outd)?;
        if ls.scene.output.png {
            st.write_figures(&mut outd, &ls.scene.title)?;
        }
    }
    transient_out::write_csv(&mut outd, &r)?;
    let snapshots = &ls.scene.output.snapshot_speeds;
    let (snaps, missed) = snapshots_out(c, ls, &prep, &r, &mut outd)?;
    let waterfall = analysis::whirl::full_waterfall(&r, prep.window_revolutions);
    whirl_out::write_waterfall(
        &mut outd,
        &ls.scene.title,
        &waterfall,
        r.omega_n,
        ls.scene.output.png,
    )?;
    if ls.scene.output.png {
        transient_out::write_figures(&mut outd, &ls.scene.title, &r, &ls.scene.output.component)?;
    }
    let body = TransientBody {
        transient: &r,
        stator_stress: stress.as_ref(),
        orbit_snapshots: (!snapshots.is_empty()).then_some(SnapshotsRecord {
            revolutions: analysis::SNAPSHOT_REVOLUTIONS,
            snapshots: &snaps,
            missed_speed_ratios: &missed,
        }),
        full_waterfall: WaterfallRecord {
            windows: waterfall.len(),
            window_revolutions: prep.window_revolutions,
            backward_dominant_windows: waterfall
                .iter()
                .filter(|w| w.lines.first().is_some_and(|l| l.0 < 0.0))
                .count(),
        },
        wall_s: t0.elapsed().as_secs_f64(),
    };
    let base = Base::new(ls, model, "run");
    let dir = summary::finish(outd, &Summary { base, body })?;
    print_end(&r, stress.as_ref());
    println!("results in {}", dir.display());
    Ok(())
}

/// The stress probe of a transient whose stators have elements (meshed, bars, frames): their
/// largest stress at every recorded sample (the probe's interval is the recording interval, so
/// its instants are the speed history's); `None` without such a stator.
fn stress_probe(prep: &analysis::TransientPrepared) -> Option<analysis::StressProbe<'_>> {
    prep.case
        .stators
        .iter()
        .any(|s| !s.elements.is_empty())
        .then(|| analysis::StressProbe::new(&prep.case.stators, prep.plan.record_every, 0.0))
}

/// Prints a transient's plan: its profile (or driven rotor), Δt and steps.
fn print_plan(prep: &analysis::TransientPrepared) {
    match &prep.drive {
        Some(d) => println!(
            "speed profile: driven rotor, {:.3} s from Ω₀ = {:.3} ωn (J = {:.4e} kg·m², Δt planned for Ω ≤ {:.3} ωn); Δt = {:.3e} s, {} steps",
            d.duration,
            d.speed0 / prep.omega_n,
            d.inertia,
            d.speed_bound() / prep.omega_n,
            prep.plan.dt,
            prep.plan.steps
        ),
        None => println!(
            "speed profile: {:.3} s, {:.1} revolutions, Ω ≤ {:.3} ωn; Δt = {:.3e} s, {} steps",
            prep.profile.duration(),
            prep.profile.total_angle() / (2.0 * std::f64::consts::PI),
            prep.profile.max_speed() / prep.omega_n,
            prep.plan.dt,
            prep.plan.steps
        ),
    }
}

/// The orbit snapshots at `output.snapshot_speeds` (a warning for each speed the history never
/// passes), written when asked; returns them and the missed speeds.
fn snapshots_out(
    c: &Common,
    ls: &rubsim::scene::LoadedScene,
    prep: &analysis::TransientPrepared,
    r: &analysis::TransientResults,
    outd: &mut rubsim::output::OutDir,
) -> Result<(Vec<analysis::OrbitSnapshot>, Vec<f64>)> {
    let snapshots = &ls.scene.output.snapshot_speeds;
    let (snaps, missed) = analysis::orbit_snapshots(prep, r, snapshots)?;
    for v in &missed {
        eprintln!(
            "warning: {}: output.snapshot_speeds: the speed history never passes ω/ωn = {v} (it spans {:.3} … {:.3} ωn); no snapshot at that speed",
            c.scene.display(),
            r.spin.iter().map(|s| s[1]).fold(f64::INFINITY, f64::min) / r.omega_n,
            r.spin.iter().map(|s| s[1]).fold(0.0, f64::max) / r.omega_n,
        );
    }
    if !snapshots.is_empty() {
        transient_out::write_snapshots(
            outd,
            &ls.scene.title,
            &snaps,
            &prep.case,
            ls.scene.output.png,
        )?;
    }
    Ok((snaps, missed))
}

/// Prints a transient's end: steps and their cost, the peak 1×, the contact, the friction
/// energy, each stator's largest stress.
fn print_end(r: &analysis::TransientResults, stress: Option<&TransientStress>) {
    println!(
        "{} steps in {:.3} s ({:.1} ns/step) | peak 1× {:.4e} m at Ω/ωn = {:.3} | contact in {} steps, max |F| {:.3e} N | friction energy {:.4e} J",
        r.stats.steps,
        r.stats.wall_s,
        1e9 * r.stats.wall_s / r.stats.steps.max(1) as f64,
        r.peak_1x.0,
        r.peak_1x.1 / r.omega_n,
        r.stats.contact_steps,
        r.contact_force_max,
        r.friction_energy
    );
    match &r.error_estimate {
        Some(e) => println!(
            "estimated error: the tracked 1× within {:.2e} of its peak (order {} against a companion at Δt = {:.3e} s, {} steps)",
            e.relative_1x, e.order, e.companion_dt, e.companion_steps
        ),
        None => println!("estimated error: none (`run.error_estimate = false`, or no companion step could be planned)"),
    }
    for p in stress.iter().flat_map(|s| &s.peaks) {
        println!(
            "stator `{}`: largest stress {:.4e} Pa at t = {:.4} s, Ω/ωn = {:.3} ({} nodes in contact)",
            p.name, p.stress_pa, p.t_s, p.speed_ratio, p.contacts
        );
    }
}

/// The warning of a run whose response is not the only one at its speed
/// (`analysis::coexist`): what the companion from the other start found, and that the error
/// estimate covers the time step only.
pub(crate) fn coexist_warning(r: &analysis::SpeedResults, c: &analysis::Coexistence) -> String {
    format!(
        "ω/ωn = {:.3}: the response depends on the start: from {} the same scheme and Δt settle on another response (contact fraction {:.2} against the run's {:.2}, period {} against {}, extents {:.1e} of the largest extent apart); the run's estimated error ({}) covers the time step only, not which response is taken (summary.json: `coexistence`; `run.check_coexistence`)",
        r.speed_ratio,
        match c.start {
            analysis::Start::Free => "the no-contact linear response",
            analysis::Start::FullContact => "full contact at the clearance, whirling forward",
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
