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
    /// Wall time of the command (s).
    wall_s: f64,
}

/// Continues the scene's autonomous orbit over speed (`--from`, `--to`, `--step` or the
/// scene's `[run.sweep]`) or over `--key` at `--speed`, and writes its files. What the options
/// or the key refuse is refused before the output folder is made.
pub fn continuation_autonomous(args: &ContinueArgs) -> Result<()> {
    let a = args.clone();
    if a.sweep.is_some() || !a.orbits_at.is_empty() {
        anyhow::bail!(
            "--sweep and --orbits-at draw and write forced orbits: not with --autonomous (its branch.csv holds each orbit's period, whirl and radius)"
        );
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
    let body = AutonomousBranchBody {
        autonomous_branch: &branch,
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
