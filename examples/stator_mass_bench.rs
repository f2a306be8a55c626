//! A fixed number of revolutions of a scene from its initial state, timed phase by phase, the
//! observed node's displacement and the first station's contact force printed as CSV
//! (`t,x,y,fx,fy`, one row per recorded sample, `run.samples_per_rev` a revolution) — the
//! benchmark of a meshed stator with mass, full and explicit against reduced and implicit
//! (docs/PERFORMANCE.md; `scripts/compare_history.py` compares two such files).
//!
//! `cargo run --release --example stator_mass_bench -- SCENE REVOLUTIONS [KEY=VALUE]…` (scene
//! overrides as `--set`; `REVOLUTIONS` may be a fraction, rounded up to whole
//! recording intervals). `rubsim run` lengthens its analysed window to at least six
//! revolutions (`time::WINDOW_MULTIPLE`); this runs `REVOLUTIONS` from t = 0. The speed
//! is `run.speed` (rad/s) or `run.speed_ratio` × ω_n. The timing goes to stderr as
//! `model_cpu_s` (mesh, assembly), `case_cpu_s` (the case at the speed: the reduction's
//! basis and operators when `[run.reduction]` asks), `setup_cpu_s` (the stepper: factors and
//! contact columns), `loop_cpu_s`, `loop_wall_s`, the steps, Δt and the DOFs in the loop; CPU
//! times are the process's user + system time (getrusage), so they do not count other work on a
//! loaded machine.

use rubsim::analysis::RunSettings;
use rubsim::model::Model;
use rubsim::time::{plan_steps, Stepper};
use std::path::Path;

/// User + system CPU time of this process so far (s).
fn cpu_s() -> f64 {
    // SAFETY: getrusage writes the struct it is given; a zeroed rusage is a valid value.
    let mut ru: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: RUSAGE_SELF with a valid pointer.
    let rc = unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut ru) };
    if rc != 0 {
        return f64::NAN;
    }
    let tv = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    tv(ru.ru_utime) + tv(ru.ru_stime)
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [scene, revs, sets @ ..] = args.as_slice() else {
        anyhow::bail!("usage: stator_mass_bench SCENE REVOLUTIONS [KEY=VALUE]…");
    };
    let revs: f64 = revs
        .parse()
        .ok()
        .filter(|r: &f64| r.is_finite() && *r > 0.0 && *r <= 1e4)
        .ok_or_else(|| anyhow::anyhow!("REVOLUTIONS: a number in (0, 1e4], got `{revs}`"))?;
    let c0 = cpu_s();
    let ls = rubsim::scene::load(Path::new(scene), sets)?;
    let model = Model::from_scene(&ls)?;
    let c1 = cpu_s();
    let run = &ls.scene.run;
    let omega = match (run.speed, run.speed_ratio) {
        (Some(w), _) => w,
        (None, Some(r)) => r * model.rotor.natural_frequency(),
        (None, None) => anyhow::bail!("the scene needs run.speed or run.speed_ratio"),
    };
    let case = model.case(omega)?;
    let c2 = cpu_s();
    let settings = RunSettings::from_scene(&ls.scene);
    let mut plan = plan_steps(&case, &settings.step)?;
    // Whole recording intervals: a fraction of a revolution times the per-step cost alone.
    let every = plan.record_every.max(1);
    plan.steps = ((revs * plan.steps_per_rev as f64 / every as f64).ceil() as usize).max(1) * every;
    plan.steady_from = plan.steady_from.min(plan.steps);
    let st = Stepper::new(&case, settings.step.integrator, &plan, settings.initial)?;
    let c3 = cpu_s();
    let (rec, stats) = st.run(None)?;
    let c4 = cpu_s();
    let full: usize = case.stators.iter().map(|s| s.k.nrows()).sum();
    let in_loop: usize = case
        .stators
        .iter()
        .map(|s| s.reduced.as_ref().map_or(s.k.nrows(), |r| r.rdof()))
        .sum();
    eprintln!(
        "model_cpu_s={:.3} case_cpu_s={:.3} setup_cpu_s={:.3} loop_cpu_s={:.3} loop_wall_s={:.3} \
         steps={} steps_per_rev={} dt={:e} stability_limit={:e} omega={omega:.6} \
         stator_dofs={full} in_loop={in_loop} max_active={} contact_steps={}",
        c1 - c0,
        c2 - c1,
        c3 - c2,
        c4 - c3,
        stats.wall_s,
        stats.steps,
        plan.steps_per_rev,
        plan.dt,
        plan.limit,
        stats.max_active,
        stats.contact_steps,
    );
    let mut out = String::with_capacity(rec.len() * 80);
    out.push_str("t,x,y,fx,fy\n");
    for (i, (t, d)) in rec.t.iter().zip(&rec.observed).enumerate() {
        let f = rec
            .force
            .get(i * rec.nstations)
            .copied()
            .unwrap_or([0.0; 2]);
        out.push_str(&format!(
            "{t:.9e},{:.9e},{:.9e},{:.9e},{:.9e}\n",
            d[0], d[1], f[0], f[1]
        ));
    }
    print!("{out}");
    Ok(())
}
