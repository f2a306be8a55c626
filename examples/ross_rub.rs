//! One transient run of a scene from rest, timed, its observed node's displacement printed as
//! CSV (`t,x,y`, one row per recorded sample) — what `scripts/ross_compare.py` reads to set
//! rubsim beside ROSS on ROSS's rub example (docs/PERFORMANCE.md).
//!
//! `cargo run --release --example ross_rub -- SCENE [KEY=VALUE]…` (scene overrides as `--set`);
//! the timing goes to stderr as `setup_s=… loop_s=… steps=… dt=…`.

use rubsim::analysis::{self, RunSettings};
use rubsim::model::Model;
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
    // The scene's settings as every command takes them (generalised-α's ρ∞ from `run.rho_inf`,
    // else 0.8 — 0 with a stator with mass), the case and the step plan prepared once, then the
    // plan integrated as it stands: no steady-state test, no companion run.
    let settings = RunSettings::from_scene(&ls.scene);
    let prep = analysis::prepare(
        &model,
        &settings.request(omega / model.rotor.natural_frequency()),
    )?;
    let setup = start.elapsed().as_secs_f64();
    let (rec, stats) = prep.integrate(&mut [])?;
    eprintln!(
        "setup_s={setup:.6} loop_s={:.6} steps={} dt={:e} dashpot_energy={:e}",
        stats.wall_s, stats.steps, prep.plan.dt, stats.dashpot_energy
    );
    let mut out = String::with_capacity(rec.len() * 48);
    out.push_str("t,x,y\n");
    for (t, d) in rec.t.iter().zip(&rec.observed) {
        out.push_str(&format!("{t:.9e},{:.9e},{:.9e}\n", d[0], d[1]));
    }
    print!("{out}");
    Ok(())
}
