//! One transient run of a scene from rest, timed, its observed node's displacement printed as
//! CSV (`t,x,y`, one row per recorded sample) — what `scripts/ross_compare.py` reads to set
//! rubsim beside ROSS on ROSS's rub example (docs/PERFORMANCE.md).
//!
//! `cargo run --release --example ross_rub -- SCENE [KEY=VALUE]…` (scene overrides as `--set`);
//! the timing goes to stderr as `setup_s=… loop_s=… steps=… dt=…`.

use rubsim::analysis::RunSettings;
use rubsim::model::Model;
use rubsim::time::{plan_steps, Stepper};
use std::path::Path;
use std::time::Instant;

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((scene, sets)) = args.split_first() else {
        anyhow::bail!("usage: ross_rub SCENE [KEY=VALUE]…");
    };
    let start = Instant::now();
    let ls = rubsim::scene::load(Path::new(scene), sets)?;
    let model = Model::from_scene(&ls)?;
    let omega = ls
        .scene
        .run
        .speed
        .ok_or_else(|| anyhow::anyhow!("the scene needs run.speed (rad/s)"))?;
    let case = model.case(omega)?;
    let settings = RunSettings::from_run(&ls.scene.run, &ls.scene.output.component);
    let plan = plan_steps(&case, &settings.step)?;
    let st = Stepper::new(&case, settings.step.integrator, &plan, settings.initial)?;
    let setup = start.elapsed().as_secs_f64();
    let (rec, stats) = st.run(None)?;
    eprintln!(
        "setup_s={setup:.6} loop_s={:.6} steps={} dt={:e} dashpot_energy={:e}",
        stats.wall_s, stats.steps, plan.dt, stats.dashpot_energy
    );
    let mut out = String::with_capacity(rec.len() * 48);
    out.push_str("t,x,y\n");
    for (t, d) in rec.t.iter().zip(&rec.observed) {
        out.push_str(&format!("{t:.9e},{:.9e},{:.9e}\n", d[0], d[1]));
    }
    print!("{out}");
    Ok(())
}
