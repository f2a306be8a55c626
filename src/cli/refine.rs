//! `rubsim refine`: one scene at several mesh refinements.

use super::{default_out, finish, load_scene, settings};
use anyhow::Result;
use rubsim::analysis::refine::{check_refines, meshed_dofs, refine_point};
use rubsim::output::summary::{RefineRecord, RefineSummary};
use rubsim::output::{csv, figures};
use std::path::PathBuf;

/// Options of `rubsim refine`.
#[derive(clap::Args, Clone, Debug)]
pub struct RefineArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Override a scene value (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// The scene key that refines the mesh, e.g. `stator.0.parameters.nx`.
    #[arg(long)]
    pub key: String,
    /// Its values, coarse to fine (comma separated).
    #[arg(long, value_delimiter = ',', required = true)]
    pub values: Vec<String>,
    /// Speed in `--unit` (default: the scene's, or ω/ω_n = 1.7).
    #[arg(long)]
    pub speed: Option<f64>,
    /// Unit of `--speed`: ratio (ω/ω_n), rad/s or rpm (converted with each refinement's ω_n).
    #[arg(long, value_enum, default_value_t = super::UnitArg::Ratio)]
    pub unit: super::UnitArg,
    /// Revolutions of the force histories drawn.
    #[arg(long, default_value_t = 3)]
    pub window: usize,
    /// Output directory (default: out/<scene name>/refine).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `rubsim refine`: the same scene at several mesh refinements (the node-to-nodes
/// contact's sensitivity to the boundary discretisation): refine.csv, force and orbit overlays.
pub fn refine(a: &RefineArgs) -> Result<()> {
    let mut loaded = Vec::new();
    for v in &a.values {
        let mut set = a.set.clone();
        set.push(format!("{}={v}", a.key));
        set.push("run.error_estimate=false".into());
        let (ls, model) = load_scene(&a.scene, &set, || {
            format!("{} with {} = {v}", a.scene.display(), a.key)
        })?;
        loaded.push((v, ls, model));
    }
    // Every refinement is meshed before any runs: one that does not refine is refused before
    // anything is written.
    let steps: Vec<(String, usize)> = loaded
        .iter()
        .filter(|(_, _, m)| meshed_dofs(m) > 0)
        .map(|(v, _, m)| (v.to_string(), meshed_dofs(m)))
        .collect();
    if steps.len() == loaded.len() {
        check_refines(&a.key, &steps)
            .map_err(|why| anyhow::anyhow!("{}: refine: {why}", a.scene.display()))?;
    }
    let dir = a
        .out
        .clone()
        .unwrap_or_else(|| default_out(&a.scene).join("refine"));
    let mut outd = super::open_out(&dir)?;
    let mut points = Vec::new();
    for (v, ls, model) in loaded {
        let wn = model.rotor.natural_frequency();
        let speed = a
            .speed
            .map(|v| a.unit.ratio(v, wn))
            .or(ls.scene.run.speed_ratio)
            .unwrap_or(1.7);
        let p = refine_point(&model, &settings(&ls), speed, a.window)?;
        let r = &p.results;
        println!(
            "{} = {v}: {} contact nodes, {} DOF: y/|Z0| ∈ [{:.4}, {:.4}], 1× {:.4}, max force {:.4} (nd), ripple {:.3}, period {}, {} steps in {:.2} s ({:.2} µs/step; setup {:.2} s)",
            a.key,
            p.targets,
            p.dofs,
            r.extents_nd[2],
            r.extents_nd[3],
            r.amp_1x_nd,
            r.contact_force_max_nd,
            p.ripple,
            r.period,
            r.stats.steps,
            r.stats.wall_s,
            p.us_per_step,
            p.setup_s
        );
        points.push((v.clone(), p));
    }
    csv::write_refine(&mut outd, &points)?;
    figures::write_refine(&mut outd, &a.key, a.window, &points)?;
    let records = points
        .iter()
        .map(|(v, p)| RefineRecord::new(v, p))
        .collect();
    finish(outd, &RefineSummary::new(&a.scene, &a.key, &a.set, records))
}
