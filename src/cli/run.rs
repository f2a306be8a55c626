//! `rubsim run`: one speed, its summary, pictures and time series.

use super::{chosen_settings, default_out, load, Common, UnitArg};
use anyhow::{Context, Result};
use rubsim::analysis;
use rubsim::output::transient_stress::TransientStress;
use rubsim::study::single;
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
    let outd = super::open_out(&out.unwrap_or_else(|| default_out(&c.scene)))?;
    let t0 = std::time::Instant::now();
    let s = chosen_settings(&ls, &model, &[v])?;
    if ls.scene.thermal.is_some() {
        let (r, dir) = single::run_thermal(outd, (&ls, &model), (&s, v), t0)?;
        print_thermal(&r);
        println!("results in {}", dir.display());
        return Ok(());
    }
    let mut hooks = Hooks::default();
    let (r, dir) = single::run_speed(outd, (&ls, &model), (&s, v), t0, &mut hooks)?;
    hooks.done();
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
    for w in analysis::notices::run_warnings(&r, ls.scene.run.tolerance) {
        eprintln!("warning: {w}");
    }
    println!("results in {}", dir.display());
    Ok(())
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
    if speed.is_some() {
        anyhow::bail!(
            "{}: --speed does not apply to a scene with [run.speed_profile] (the profile sets the speed)",
            c.scene.display()
        );
    }
    let outd = super::open_out(&out.unwrap_or_else(|| default_out(&c.scene)))?;
    let t0 = std::time::Instant::now();
    let mut hooks = Hooks::default();
    let t = single::run_transient(outd, (ls, model), t0, &mut hooks)?;
    print_end(&t.results, t.stress.as_ref());
    print_dry_spans(&analysis::waterfall::dry_spans(
        &t.waterfall,
        t.results.omega_n,
    ));
    println!("results in {}", t.dir.display());
    Ok(())
}

/// What `rubsim run` shows while a run goes: the estimate and, for a long run on a terminal,
/// a progress bar (stderr); a transient's plan (stdout); warnings (stderr).
#[derive(Default)]
struct Hooks {
    progress: Option<super::Progress>,
}

impl Hooks {
    /// Clears the progress bar.
    fn done(self) {
        if let Some(p) = self.progress {
            p.pb.finish_and_clear();
        }
    }
}

impl single::RunHooks for Hooks {
    fn prepared(&mut self, prep: &analysis::Prepared) {
        super::announce(prep);
        self.progress = super::Progress::for_run(prep);
    }
    fn transient_prepared(&mut self, prep: &analysis::TransientPrepared) {
        print_plan(prep);
    }
    fn progress(&mut self) -> Option<&mut dyn FrameSink> {
        self.progress.as_mut().map(|p| p as &mut dyn FrameSink)
    }
    fn warning(&mut self, message: &str) {
        eprintln!("warning: {message}");
    }
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
    if let Some(w) = &r.wear {
        println!(
            "wear (magnification A = {}, wear time {:.4e} s): {:.4e} m³ worn, largest depth {:.4e} m{}{}",
            w.acceleration,
            w.acceleration * r.duration,
            w.volume_m3,
            w.max_depth_m,
            w.deepest.as_ref().map_or(String::new(), |n| format!(
                " at stator `{}` node {} ({:.1}°, z = {:.4} m)",
                n.stator, n.node, n.angle_deg, n.z
            )),
            if w.free_at_end {
                "; the rub has worn itself free (no contact over the last revolution)"
            } else {
                ""
            }
        );
        if let Some(a) = &w.abradable {
            println!(
                "abradable coating: {:.4e} m³ cut off (plastic work {:.4e} J), deepest cut {:.4e} m{}",
                a.volume_m3,
                a.plastic_work_j,
                a.max_depth_m,
                a.deepest.as_ref().map_or(String::new(), |n| format!(
                    " at stator `{}` node {} ({:.1}°, z = {:.4} m)",
                    n.stator, n.node, n.angle_deg, n.z
                )),
            );
        }
    }
    for p in stress.iter().flat_map(|s| &s.peaks) {
        println!(
            "stator `{}`: largest stress {:.4e} Pa at t = {:.4} s, Ω/ωn = {:.3} ({} nodes in contact)",
            p.name, p.stress_pa, p.t_s, p.speed_ratio, p.contacts
        );
    }
}

/// Prints a transient's spans of dry whirl and dry whip, one line each, in time order.
fn print_dry_spans(spans: &[rubsim::analysis::waterfall::DrySpan]) {
    for s in spans {
        println!(
            "{}: t {:.3} … {:.3} s, Ω/ωn {:.3} … {:.3} ({} window(s))",
            s.regime.label(),
            s.t_s[0],
            s.t_s[1],
            s.speed_ratio[0],
            s.speed_ratio[1],
            s.windows
        );
    }
}

/// Prints a thermal run's error estimate and its two parts (`run.error_estimate`).
fn print_thermal_error(r: &analysis::thermal::ThermalResults) {
    let Some(e) = &r.error else { return };
    println!(
        "  estimated error: ΔT within {:.2e} of its largest, growth rate ± {:.2e} 1/s, rotation ± {:.2e} rad/s (coupling step: {:.2e} against h = {:.4e} s; time step: {})",
        e.delta_t,
        e.growth_rate,
        e.rotation_rate,
        e.coupling.delta_t,
        e.coupling.coupling_step_s,
        e.step.map_or_else(
            || "no estimate".to_string(),
            |d| format!("{:.2e} against Δt = {:.4e} s", d.delta_t, d.dt_s)
        )
    );
    if let Some(why) = &e.step_failed {
        eprintln!(
            "warning: ω/ωn = {:.3}: the thermal run's companion at 2Δt failed ({why}): its error estimate leaves out the time step's part",
            r.speed_ratio
        );
    }
}

/// Prints a thermal run's end: the coupling, the spiral's growth and rotation, a runaway.
fn print_thermal(r: &analysis::thermal::ThermalResults) {
    let last = r.samples.last();
    println!(
        "ω/ωn = {:.3}: thermal spiral over {:.4} s of machine time in {} coupling steps of {:.4e} s ({}; {:.1} revolution(s) integrated a step, {} steps in all)",
        r.speed_ratio,
        r.machine_time_s,
        r.samples.len(),
        r.coupling_step_s,
        if r.resolved { "fully resolved" } else { "accelerated" },
        r.revolutions_per_step,
        r.steps
    );
    if let Some(f) = &r.section {
        println!("  heat: {}", f.describe());
    }
    if let Some(s) = last {
        println!(
            "  at the end: |ΔT| = {:.4e} K, |bow| = {:.4e} m, |1×| = {:.4e} m at {:.2}° (rotor frame), friction power {:.4e} W",
            s.delta_t[0].hypot(s.delta_t[1]),
            s.bow[0].hypot(s.bow[1]),
            s.one_x[0].hypot(s.one_x[1]),
            s.one_x[1].atan2(s.one_x[0]).to_degrees(),
            s.power
        );
    }
    println!(
        "  spiral: growth rate {:+.4e} 1/s, rotation {:+.4e} rad/s in the rotor's frame ({})",
        r.growth_rate,
        r.rotation_rate,
        if r.growth_rate > 0.0 {
            "growing"
        } else {
            "settling"
        }
    );
    print_thermal_error(r);
    if let Some(t) = r.unsynchronous_at_s {
        let change = r.samples.last().map_or(0.0, |s| s.non_synchronous);
        eprintln!(
            "warning: ω/ωn = {:.3}: the vibration is not synchronous at t = {t:.4} s: the station's orbit changed by {:.1} % of its radius over a revolution (more than {:.0} %) — a whirl of the rub's own (dry friction whirl where μ k_s exceeds the damping), or a response that does not settle; the hot-spot model's heat does not follow the bow there, so the run stopped and its growth rate is not fitted",
            r.speed_ratio,
            100.0 * change,
            100.0 * analysis::thermal::MAX_NON_SYNCHRONOUS
        );
    }
    if let Some(t) = r.runaway_at_s {
        eprintln!(
            "warning: ω/ωn = {:.3}: the thermal spiral runs away: |ΔT| passed `thermal.max_temperature_difference` at t = {t:.4} s, growing at {:.4e} 1/s; the run stopped there",
            r.speed_ratio, r.growth_rate
        );
    }
}
