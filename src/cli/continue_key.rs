//! `rubsim continue --key KEY`: a periodic orbit continued over a numeric scene key's values at
//! a fixed speed (`analysis::continuation::continue_key`): the files of a branch in speed, the
//! key's column in branch.csv and bifurcations.csv, branch.png over the key.

use super::continuation::{report_diagram, ContinueArgs, ContinueBody};
use super::{default_out, load, shooting_settings, UnitArg};
use anyhow::{Context, Result};
use rubsim::analysis::{self, continuation::KeyBranch};
use rubsim::output::summary::{finish, Base, Summary};

/// The fixed speed ν of a branch in `--key` (`--speed` in `--unit`, or the scene's one speed)
/// and its range `(from, to, step)` in the key's units.
pub(super) fn key_speed_range(
    a: &ContinueArgs,
    (ls, model): (&rubsim::scene::LoadedScene, &rubsim::model::Model),
) -> Result<(f64, (f64, f64, f64))> {
    let key = a.key.as_deref().unwrap_or_default();
    if a.speed.is_none() && a.unit != UnitArg::Ratio {
        anyhow::bail!(
            "--unit applies to --speed only (the key's values are in its own units): give --speed in that unit, or leave --unit out"
        );
    }
    let (Some(from), Some(to), Some(step)) = (a.from, a.to, a.step) else {
        anyhow::bail!(
            "--key {key} needs --from, --to and --step, in the key's own units (the scene's [run.sweep] is a range of speeds)"
        );
    };
    if let Some(v) = a.speed {
        if !(v.is_finite() && v > 0.0) {
            anyhow::bail!("--speed must be a positive speed, got {v}");
        }
    }
    let nu = a
        .speed
        .map(|v| a.unit.ratio(v, model.rotor.natural_frequency()))
        .or_else(|| analysis::single_speed(&ls.scene.run, model))
        .with_context(|| {
            format!(
                "{}: `rubsim continue --key` runs at one speed: --speed, or the scene's run.speed_ratio or run.speed",
                a.c.scene.display()
            )
        })?;
    Ok((nu, (from, to, step)))
}

/// Continues the period-`--period` orbit over `--key` from `--from` to `--to` by `--step` (the
/// key's units) at `--speed` (in `--unit`; default the scene's single speed), and writes the
/// branch's files. Everything the key's values refuse is refused before a run, nothing written.
pub fn continuation_in_key(args: &ContinueArgs) -> Result<()> {
    let a = args.clone();
    let key = a.key.as_deref().unwrap_or_default();
    let (ls, model) = load(&a.c)?;
    super::periodic::check_period(a.period)?;
    if a.sweep.is_some() {
        anyhow::bail!(
            "--sweep draws a sweep's points over speed: not with --key (the branch is drawn over `{key}`)"
        );
    }
    if !a.orbits_at.is_empty() {
        anyhow::bail!(
            "--orbits-at picks orbits by speed on a branch in speed: not with --key (this branch is at one speed; shoot an orbit of it with `rubsim periodic --set {key}=VALUE`)"
        );
    }
    let (nu, (from, to, step)) = key_speed_range(&a, (&ls, &model))?;
    if a.arclength && a.max_points < 2 {
        anyhow::bail!("--max-points must be at least 2, got {}", a.max_points);
    }
    if a.switch && a.max_period < 2 {
        anyhow::bail!(
            "--max-period must be at least 2 (a switched branch doubles the period), got {}",
            a.max_period
        );
    }
    analysis::continuation::values(from, to, step)
        .with_context(|| format!("--from {from}, --to {to}, --step {step}"))?;
    let branch = KeyBranch {
        key,
        speed_ratio: nu,
        range: (from, to, step),
        period: a.period,
        arclength: a.arclength.then_some(a.max_points),
        switch: a.switch.then_some(a.max_period),
    };
    let s = shooting_settings(&ls, &model, &[nu])?;
    let t0 = std::time::Instant::now();
    // The key's refusals come before the output folder is made: nothing is written.
    let d = analysis::continuation::continue_key(&ls, &s, &branch)
        .with_context(|| format!("{}: --key {key}", a.c.scene.display()))?;
    let mut outd = super::open_out(
        &a.out
            .unwrap_or_else(|| default_out(&a.c.scene).join("continue")),
    )?;
    let png = ls
        .scene
        .output
        .png
        .then_some(rubsim::output::branch::DiagramView {
            component: ls.scene.output.component.as_str(),
            sweep: &[],
        });
    if a.switch {
        rubsim::output::branch::write_diagram(&mut outd, &ls.scene.title, &d, png)?;
    } else {
        rubsim::output::branch::write_branch(&mut outd, &ls.scene.title, &d.branches[0], png)?;
    }
    report_diagram(&d);
    let body = ContinueBody {
        branch: &d.branches[0],
        switched: a.switch.then_some(&d),
        coexisting: Vec::new(),
        orbits: Vec::new(),
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
