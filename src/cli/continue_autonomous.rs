//! `rubsim continue --autonomous`: the autonomous orbit (a whirl at its own frequency, dry
//! whip) continued in speed or, with `--key`, in a scene key at a fixed speed
//! (`analysis::continuation::continue_autonomous`): branch.csv, branch.png, summary.json.

use super::continuation::ContinueArgs;
use super::{default_out, load, shooting_settings};
use anyhow::{Context, Result};
use rubsim::analysis::{self, autonomous_branch::AutonomousBranch};
use rubsim::output::summary::{finish, Base, Summary};
use serde::Serialize;

/// The body of `summary.json` of `rubsim continue --autonomous`.
#[derive(Debug, Serialize)]
struct AutonomousBranchBody<'a> {
    /// The branch: its orbits and where it ended.
    autonomous_branch: &'a AutonomousBranch,
    /// With `--orbits-at`: each orbit shot there and its time series.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    orbits: Vec<AutonomousEntry>,
    /// Wall time of the command (s).
    wall_s: f64,
}

/// An orbit of `--orbits-at` on an autonomous branch as summary.json lists it.
#[derive(Debug, Serialize)]
struct AutonomousEntry {
    /// The speed asked, ν.
    speed_ratio: f64,
    /// ν of the branch's point Newton started from.
    from_speed_ratio: f64,
    /// The orbit: its period, whirl, radius, Newton and multipliers.
    orbit: analysis::autonomous::AutonomousOrbit,
    /// Its VTK/HDF5 series, when the scene asks for one and Newton converged.
    series: Option<super::periodic::OrbitSeries>,
}

/// Continues the scene's autonomous orbit over speed (`--from`, `--to`, `--step` or the
/// scene's `[run.sweep]`) or over `--key` at `--speed`, and writes its files. What the options
/// or the key refuse is refused before the output folder is made.
pub fn continuation_autonomous(args: &ContinueArgs) -> Result<()> {
    let a = args.clone();
    if a.sweep.is_some() {
        anyhow::bail!(
            "--sweep draws a sweep's points under forced orbits: not with --autonomous (its branch.csv holds each orbit's period, whirl and radius)"
        );
    }
    if a.key.is_some() && !a.orbits_at.is_empty() {
        anyhow::bail!(
            "--orbits-at picks orbits by speed on a branch in speed: not with --key (shoot an orbit of this branch with `rubsim periodic --autonomous --set KEY=VALUE`)"
        );
    }
    if let Some(v) = a.orbits_at.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        anyhow::bail!("--orbits-at: every value must be a positive speed, got {v}");
    }
    let (ls, model) = load(&a.c)?;
    let (key, range, speeds) = match a.key.as_deref() {
        Some(k) => {
            let (nu, range) = super::continue_key::key_speed_range(&a, (&ls, &model))?;
            (Some((k, nu)), range, vec![nu])
        }
        None => {
            let range = super::continuation::speed_range(&a, &ls, &model)?;
            let (f, t, h) = range;
            let v = analysis::continuation::speeds(f, t, h)
                .with_context(|| format!("--from {f}, --to {t}, --step {h}"))?;
            (None, range, v)
        }
    };
    let s = shooting_settings(&ls, &model, &speeds)?;
    let t0 = std::time::Instant::now();
    let branch = analysis::continuation::continue_autonomous((&ls, &model), &s, key, range)
        .with_context(|| format!("{}: --autonomous", a.c.scene.display()))?;
    let mut outd = super::open_out(
        &a.out
            .unwrap_or_else(|| default_out(&a.c.scene).join("continue")),
    )?;
    rubsim::output::autonomous::write_autonomous_branch(
        &mut outd,
        &ls.scene.title,
        &branch,
        ls.scene.output.png,
    )?;
    report(&branch);
    let wn = model.rotor.natural_frequency();
    let values: Vec<f64> = a.orbits_at.iter().map(|v| a.unit.ratio(*v, wn)).collect();
    let orbits = write_orbits(&mut outd, (&ls, &model), (&s, range), &branch, &values)?;
    let body = AutonomousBranchBody {
        autonomous_branch: &branch,
        orbits,
        wall_s: t0.elapsed().as_secs_f64(),
    };
    finish(
        outd,
        &Summary {
            base: Base::new(&ls, &model, "continue"),
            body,
        },
    )?;
    Ok(())
}

/// Prints the branch: its range, its stretches of stability with the whirl and radius at
/// their ends, and where it ended.
fn report(b: &AutonomousBranch) {
    let on = if b.at_speed_ratio.is_some() {
        b.parameter.as_str()
    } else {
        "ω/ωn"
    };
    let (Some(first), Some(last)) = (b.points.first(), b.points.last()) else {
        return;
    };
    println!(
        "autonomous orbit continued over {on} {:.6} … {:.6}: {} points, {} steps",
        first.parameter,
        last.parameter,
        b.points.len(),
        b.steps
    );
    for (stable, i, j) in b.stretches() {
        let (p, q) = (&b.points[i], &b.points[j]);
        println!(
            "  {:>8}  {on} {:.6} – {:.6}: whirl {:+.6} … {:+.6} ω_n, radius {:.6e} … {:.6e} m, largest other |ρ| {:.6} … {:.6}",
            if stable { "stable" } else { "unstable" },
            p.parameter,
            q.parameter,
            p.whirl_ratio,
            q.whirl_ratio,
            0.5 * (p.radius_m[0] + p.radius_m[1]),
            0.5 * (q.radius_m[0] + q.radius_m[1]),
            p.largest_modulus,
            q.largest_modulus
        );
    }
    if let Some(why) = &b.ended {
        eprintln!("warning: the branch ends before its last value: {why}");
    }
}

/// The orbits of `--orbits-at` (`values`, ν) on the autonomous branch `b` (continued over
/// `range` with the settings `s`), each written as the scene's time series under
/// `orbits/branch0_<ν>/`; the warnings printed.
fn write_orbits(
    outd: &mut rubsim::output::OutDir,
    (ls, model): (&rubsim::scene::LoadedScene, &rubsim::model::Model),
    (s, range): (&analysis::RunSettings, (f64, f64, f64)),
    b: &AutonomousBranch,
    values: &[f64],
) -> Result<Vec<AutonomousEntry>> {
    if values.is_empty() {
        return Ok(Vec::new());
    }
    if !rubsim::results::wanted(&ls.scene.output) {
        eprintln!("warning: --orbits-at: the scene asks for no time series (`output.vtk`, `output.hdf5`; e.g. `--set 'output.vtk={{}}'`): the orbits are shot and listed in summary.json, no series written");
    }
    let (found, notes) = analysis::continuation::autonomous_orbits_at(model, s, range, b, values)?;
    for n in &notes {
        eprintln!("warning: {n}");
    }
    let mut entries = Vec::with_capacity(found.len());
    for f in found {
        let o = &f.orbit;
        println!(
            "autonomous orbit at ω/ωn = {}, Newton from {:.4}: {} in {} iteration(s), residual {:.2e}, period {:.6e} s, whirl {:+.6} ω_n, {} (largest other |ρ| {:.4})",
            f.value,
            f.from,
            if o.converged { "converged" } else { "did NOT converge" },
            o.iterations,
            o.residual,
            o.period_s,
            o.whirl_ratio,
            if o.stable { "stable" } else { "unstable" },
            o.largest_modulus
        );
        let folder = format!("orbits/branch0_{}/", f.value);
        let series =
            super::periodic::write_autonomous_series(outd, (ls, model), &f.prep, o, &folder)?;
        entries.push(AutonomousEntry {
            speed_ratio: f.value,
            from_speed_ratio: f.from,
            orbit: f.orbit,
            series,
        });
    }
    Ok(entries)
}
