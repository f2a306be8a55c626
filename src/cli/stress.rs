//! `rubsim stress`: stator stress and strain during a run (the paper's Fig. 10).

use super::{default_out, finish, load_scene, settings};
use anyhow::{bail, Result};
use rubsim::analysis::{self, StressProbe, StressResults, StressTrace};
use rubsim::error::Error;
use rubsim::output::summary::{self, StressSummary};
use rubsim::output::{csv, figures};
use std::path::PathBuf;

/// Options of `rubsim stress`.
#[derive(clap::Args, Clone, Debug)]
pub struct StressArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Override a scene value (repeatable), as for the other commands.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Speeds in `--unit` (repeatable; default: the scene's speed, or ω/ω_n = 1.7, 3.1, 4.9 —
    /// Fig. 10).
    #[arg(long = "speed")]
    pub speeds: Vec<f64>,
    /// Unit of `--speed`: ratio (ω/ω_n), rad/s or rpm.
    #[arg(long, value_enum, default_value_t = super::UnitArg::Ratio)]
    pub unit: super::UnitArg,
    /// Stress samples per revolution.
    #[arg(long, default_value_t = 64)]
    pub per_rev: usize,
    /// Revolutions at the end of the run that are kept (0: all).
    #[arg(long, default_value_t = 5)]
    pub window: usize,
    /// Output directory (default: out/<scene name>/stress).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `rubsim stress`: stress and strain histories of every stator (Fig. 10), the stress
/// field at the instant of largest stress, `stress.csv` and `summary.json`.
pub fn stress(a: &StressArgs) -> Result<()> {
    let (ls, model) = load_scene(&a.scene, &a.set, || {
        format!("{}: building the model", a.scene.display())
    })?;
    let settings = settings(&ls);
    let wn = model.rotor.natural_frequency();
    let given: Vec<f64> = a.speeds.iter().map(|v| a.unit.ratio(*v, wn)).collect();
    let speeds = analysis::study_speeds(&ls.scene.run, &model, &given);
    for v in &speeds {
        if !(v.is_finite() && *v > 0.0) {
            bail!("--speed must be positive, got ω/ω_n = {v}");
        }
    }
    let dir = a
        .out
        .clone()
        .unwrap_or_else(|| default_out(&a.scene).join("stress"));
    let mut outd = super::open_out(&dir)?;
    let png = ls.scene.output.png;
    let mut runs = Vec::new();
    let mut records = Vec::new();
    for &v in &speeds {
        let prep = analysis::prepare(&model, &settings.request(v))?;
        let mut probe = StressProbe::for_run(&prep, a.per_rev, a.window);
        prep.integrate(&mut [&mut probe])
            .map_err(|e| Error::AtSpeed {
                speed_ratio: v,
                source: Box::new(e),
            })?;
        let r = StressResults::new(&prep, probe);
        for tr in &r.traces {
            report(v, tr);
            if png {
                figures::write_stress_field(&mut outd, v, tr, &prep.case.stators[tr.stator])?;
            }
        }
        records.extend(summary::stress_records(&r));
        runs.push(r);
    }
    csv::write_stress(&mut outd, &runs)?;
    if png {
        figures::write_stress(&mut outd, &runs)?;
    }
    let sum = StressSummary::new(&a.scene, &a.set, a.per_rev, a.window, records);
    finish(outd, &sum)
}

/// Prints one stator's peak stress and strain at ω/ω_n = `v`.
fn report(v: f64, tr: &StressTrace) {
    println!(
        "ω/ωn = {v}: stator `{}`: largest |stress| {:.4e} Pa (strain {:.3e}) at t = {:.6} s, {} node(s) in contact then; mean contact force {:.4e} N",
        tr.name,
        tr.peak_stress(),
        tr.peak_strain(),
        tr.peak_time,
        tr.peak_contacts.len(),
        tr.mean_force()
    );
}
