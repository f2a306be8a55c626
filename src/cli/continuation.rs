//! `rubsim continue`: a periodic orbit continued over speed (`analysis::branch`): branch.csv,
//! bifurcations.csv, branch.png and summary.json; with `--key`, over a scene key's values at a
//! fixed speed (`super::continue_key`).

use super::{default_out, load, shooting_settings, Common, UnitArg};
use anyhow::{Context, Result};
use rubsim::analysis::{self, branch::Branch};
use rubsim::output::summary::{finish, Base, Summary};
use serde::Serialize;
use std::path::PathBuf;

/// The body of `summary.json` of `rubsim continue`.
#[derive(Debug, Serialize)]
pub(super) struct ContinueBody<'a> {
    /// The branch: its points, bifurcations and where it ended.
    pub(super) branch: &'a Branch,
    /// With `--switch`: every branch (the first is `branch`), where each switched one came
    /// from, the doublings not followed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) switched: Option<&'a analysis::switch::Diagram>,
    /// With `--sweep`: each speed the sweep flagged as coexisting, the branches holding its
    /// responses and those it added.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) coexisting: Vec<analysis::coexist_branches::CoexistRecord>,
    /// With `--orbits-at`: each orbit shot there and its time series.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(super) orbits: Vec<OrbitEntry>,
    /// Wall time of the command (s).
    pub(super) wall_s: f64,
}

/// An orbit of `--orbits-at` as summary.json lists it: where it was shot from, its Newton and
/// stability, its series.
#[derive(Debug, Serialize)]
pub(super) struct OrbitEntry {
    #[serde(flatten)]
    orbit: analysis::orbits_at::OrbitAtRecord,
    /// Its VTK/HDF5 series, when the scene asks for one and Newton converged.
    series: Option<super::periodic::OrbitSeries>,
}

/// Options of `rubsim continue`.
#[derive(clap::Args, Clone)]
pub struct ContinueArgs {
    #[command(flatten)]
    pub c: Common,
    /// First speed, in `--unit` (default: the scene's `[run.sweep]`); with `--key`, the key's
    /// first value in its own units.
    #[arg(long, allow_negative_numbers = true)]
    pub from: Option<f64>,
    /// Last speed, in `--unit` (below `--from`: continued downwards); with `--key`, the key's
    /// last value.
    #[arg(long, allow_negative_numbers = true)]
    pub to: Option<f64>,
    /// Speed step, in `--unit`; with `--key`, the key's step in its own units.
    #[arg(long, allow_negative_numbers = true)]
    pub step: Option<f64>,
    /// Continue in this numeric scene key instead of the speed (the dotted keys of `--set`:
    /// `station.0.friction`, `stator.0.stiffness_ratio`, `stator.0.clearance`, …), at the fixed
    /// speed `--speed`, from `--from` to `--to` by `--step` in the key's units.
    #[arg(long)]
    pub key: Option<String>,
    /// With `--key`: the fixed speed, in `--unit` (default: the scene's `run.speed_ratio` or
    /// `run.speed`).
    #[arg(long, requires = "key")]
    pub speed: Option<f64>,
    /// Unit of the speeds (with `--key`: of `--speed` only): ratio (ω/ω_n), rad/s or rpm.
    #[arg(long, value_enum, default_value_t = UnitArg::Ratio)]
    pub unit: UnitArg,
    /// Period of the orbit in revolutions (default: the first speed's settled period).
    #[arg(long)]
    pub period: Option<usize>,
    /// Pseudo-arclength continuation: the branch followed around folds, starting from
    /// `--from` towards `--to` with `--step` as the first step, within their range.
    #[arg(long)]
    pub arclength: bool,
    /// Most points of a pseudo-arclength branch.
    #[arg(long, default_value_t = 200)]
    pub max_points: usize,
    /// Branch switching: from every period doubling located, the period-2k orbit that branches
    /// off it, continued over the speeds beyond (and from its own doublings, up to
    /// `--max-period`); branches.csv, switches.csv, every branch in branch.png.
    #[arg(long)]
    pub switch: bool,
    /// Largest period (revolutions) a switched branch may have.
    #[arg(long, default_value_t = 8)]
    pub max_period: usize,
    /// The output folder of `rubsim sweep` of the same scene: its Poincaré points drawn under
    /// the branches in branch.png.
    #[arg(long)]
    pub sweep: Option<PathBuf>,
    /// Values of the branch parameter (speeds, in `--unit`, comma-separated) at which each
    /// branch spanning them writes its periodic orbit as the scene's VTK/HDF5 series, under
    /// `orbits/branch<i>_<ν>/`: Newton at exactly that value from the branch's nearest
    /// converged point (an autonomous branch's: one whirl period).
    #[arg(long, value_delimiter = ',')]
    pub orbits_at: Vec<f64>,
    /// The autonomous orbit — a whirl at its own frequency (dry whip) in a scene without
    /// unbalance — continued with its period unknown (`rubsim periodic --autonomous` at each
    /// value, Newton from the previous orbit): in speed, or with `--key` in the key at `--speed`.
    #[arg(long, conflicts_with_all = ["arclength", "switch", "period"])]
    pub autonomous: bool,
    /// Split the branch into this many segments, each continued from its own settled run at
    /// its first value (period `--period`, default 1), in parallel, each kept in the output
    /// folder's case store as soon as it is done: a rerun resumes, `--shard` runs a part
    /// (`rubsim merge` joins them); segments.csv says where they join.
    #[arg(long, conflicts_with_all = ["arclength", "switch", "autonomous", "orbits_at"])]
    pub segments: Option<usize>,
    /// With `--segments`: run only the segments of shard i of n (the j-th with j mod n = i − 1)
    /// into <out>/shard-<i>-of-<n>/, for `rubsim merge`; inside a Slurm array job the default
    /// is the task's.
    #[arg(long, value_name = "I/N", requires = "segments")]
    pub shard: Option<String>,
    /// With `--segments`: worker threads running segments at once (default: all cores).
    #[arg(long, requires = "segments")]
    pub jobs: Option<usize>,
    /// With `--segments`: discard the segments of an earlier, different continuation in the
    /// output folder instead of refusing to run.
    #[arg(long, requires = "segments")]
    pub fresh: bool,
    /// Output directory (default: out/<scene name>/continue).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Continues the period-`period` orbit over the speeds `from … to` by `step` (in `unit`;
/// default: the scene's `[run.sweep]`) — in ν alone, or by pseudo-arclength from `from`
/// (`arclength`: at most that many points) — and writes its files.
pub fn continuation(args: &ContinueArgs) -> Result<()> {
    let ContinueArgs {
        c,
        unit,
        period,
        arclength,
        max_points,
        switch,
        max_period,
        sweep: sweep_dir,
        orbits_at,
        out,
        ..
    } = args.clone();
    let arclength = arclength.then_some(max_points);
    let (ls, model) = load(&c)?;
    super::periodic::check_period(period)?;
    let wn = model.rotor.natural_frequency();
    let (a, b, h) = speed_range(args, &ls, &model)?;
    if arclength.is_some_and(|n| n < 2) {
        anyhow::bail!("--max-points must be at least 2, got {max_points}");
    }
    if switch && max_period < 2 {
        anyhow::bail!(
            "--max-period must be at least 2 (a switched branch doubles the period), got {max_period}"
        );
    }
    let speeds = analysis::continuation::speeds(a, b, h)
        .with_context(|| format!("--from {a}, --to {b}, --step {h}"))?;
    let component = ls.scene.output.component.as_str();
    let dots = match &sweep_dir {
        Some(d) => {
            rubsim::study::overlay::sweep_poincare(&ls, &model, d, usize::from(component == "y"))
                .context("--sweep")?
        }
        None => Vec::new(),
    };
    let mut outd = super::open_out(&out.unwrap_or_else(|| default_out(&c.scene).join("continue")))?;
    let t0 = std::time::Instant::now();
    let s = shooting_settings(&ls, &model, &speeds)?;
    let title = &ls.scene.title;
    let png = ls
        .scene
        .output
        .png
        .then_some(rubsim::output::branch::DiagramView {
            component,
            sweep: &dots,
        });
    let mut diagram = diagram_of(
        &model,
        &s,
        (a, b, h),
        period,
        (switch, arclength, max_period),
    )?;
    let coexisting = match &sweep_dir {
        Some(d) => coexisting_branches((&ls, &model), &s, d, &mut diagram, &speeds)?,
        None => Vec::new(),
    };
    let several = switch || diagram.branches.len() > 1;
    if several {
        rubsim::output::branch::write_diagram(&mut outd, title, &diagram, png)?;
    } else {
        rubsim::output::branch::write_branch(&mut outd, title, &diagram.branches[0], png)?;
    }
    report_diagram(&diagram);
    let values: Vec<f64> = orbits_at.iter().map(|v| unit.ratio(*v, wn)).collect();
    let folds = switch || arclength.is_some();
    let orbits = write_orbits(
        &mut outd,
        (&ls, &model),
        &s,
        (&diagram, (a, b, h), folds),
        &values,
    )?;
    let body = ContinueBody {
        branch: &diagram.branches[0],
        switched: several.then_some(&diagram),
        coexisting,
        orbits,
        wall_s: t0.elapsed().as_secs_f64(),
    };
    let base = Base::new(&ls, &model, "continue");
    finish(outd, &Summary { base, body })?;
    Ok(())
}

/// The diagram `rubsim continue` asks for over the speeds `range` (ν): the branch in ν alone
/// or by pseudo-arclength (`arclength`: at most that many points), with `switch` the branches
/// switched at its period doublings up to period `max_period`.
fn diagram_of(
    model: &rubsim::model::Model,
    s: &analysis::RunSettings,
    range: (f64, f64, f64),
    period: Option<usize>,
    (switch, arclength, max_period): (bool, Option<usize>, usize),
) -> Result<analysis::switch::Diagram> {
    use analysis::continuation as c;
    Ok(match (switch, arclength) {
        (true, Some(n)) => c::arclength_switching(model, s, range, period, (n, max_period))?,
        (true, None) => c::continue_switching(model, s, range, period, max_period)?,
        (false, _) => {
            analysis::switch::Diagram::of(c::continue_branch(model, s, range, period, arclength)?)
        }
    })
}

/// With `--sweep DIR`: the responses of every speed the sweep in `dir` flagged as coexisting
/// that lie on no branch of `d`, continued as branches of their own over `speeds`
/// (`analysis::coexist_branches`), each flagged speed's record printed.
pub(super) fn coexisting_branches(
    (ls, model): (&rubsim::scene::LoadedScene, &rubsim::model::Model),
    s: &analysis::RunSettings,
    dir: &std::path::Path,
    d: &mut analysis::switch::Diagram,
    speeds: &[f64],
) -> Result<Vec<analysis::coexist_branches::CoexistRecord>> {
    let flagged = rubsim::study::overlay::sweep_flagged(ls, model, dir).context("--sweep")?;
    if flagged.is_empty() {
        return Ok(Vec::new());
    }
    let top = speeds.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let c = analysis::parameter::Continued::of_speed(model, s, top)?;
    Ok(report_coexisting(
        analysis::coexist_branches::add_coexisting(&c, d, &flagged, speeds),
    ))
}

/// Prints each flagged speed's record ([`coexisting_branches`]) and hands them back.
pub(super) fn report_coexisting(
    recs: Vec<analysis::coexist_branches::CoexistRecord>,
) -> Vec<analysis::coexist_branches::CoexistRecord> {
    for r in &recs {
        let on: Vec<String> = r
            .on_branch
            .iter()
            .map(|b| b.map_or("none".to_string(), |i| i.to_string()))
            .collect();
        println!(
            "coexisting responses at ω/ωn {} (the sweep's check): on branch(es) {}{}{}",
            r.speed_ratio,
            on.join(", "),
            if r.new_branches.is_empty() {
                String::new()
            } else {
                format!(" — new branch(es) {:?}", r.new_branches)
            },
            r.note.as_ref().map_or(String::new(), |n| format!(" ({n})"))
        );
    }
    recs
}

/// The branch's speeds `(from, to, step)` as ν: `--from`, `--to`, `--step` in `--unit`, or the
/// scene's `[run.sweep]`.
pub(super) fn speed_range(
    args: &ContinueArgs,
    ls: &rubsim::scene::LoadedScene,
    model: &rubsim::model::Model,
) -> Result<(f64, f64, f64)> {
    let wn = model.rotor.natural_frequency();
    let sweep = ls.scene.run.sweep.as_ref();
    let pick = |given: Option<f64>, scene: Option<f64>, name: &str| -> Result<f64> {
        given
            .map(|v| args.unit.ratio(v, wn))
            .or(scene)
            .with_context(|| {
                format!(
                    "{}: `rubsim continue` needs --{name} or the scene's [run.sweep]",
                    args.c.scene.display()
                )
            })
    };
    Ok((
        pick(args.from, sweep.map(|s| s.from), "from")?,
        pick(args.to, sweep.map(|s| s.to), "to")?,
        pick(args.step, sweep.map(|s| s.step), "step")?,
    ))
}

/// The orbits of `--orbits-at` (`values`, ν) on the branches of `d` (continued over
/// `range` with the settings `s`, `around_folds` by pseudo-arclength or switching), each
/// written as the scene's time series under `orbits/branch<i>_<ν>/`; the warnings printed.
fn write_orbits(
    outd: &mut rubsim::output::OutDir,
    (ls, model): (&rubsim::scene::LoadedScene, &rubsim::model::Model),
    s: &analysis::RunSettings,
    (d, range, around_folds): (&analysis::switch::Diagram, (f64, f64, f64), bool),
    values: &[f64],
) -> Result<Vec<OrbitEntry>> {
    if values.is_empty() {
        return Ok(Vec::new());
    }
    if let Some(v) = values.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        anyhow::bail!("--orbits-at: every value must be a positive speed, got {v}");
    }
    if !rubsim::results::wanted(&ls.scene.output) {
        eprintln!("warning: --orbits-at: the scene asks for no time series (`output.vtk`, `output.hdf5`; e.g. `--set 'output.vtk={{}}'`): the orbits are shot and listed in summary.json, no series written");
    }
    let pinned = analysis::orbits_at::branch_settings(model, s, range, around_folds)?;
    let (found, notes) = analysis::orbits_at::orbits_at(model, &pinned, &d.branches, values);
    for n in &notes {
        eprintln!("warning: {n}");
    }
    let mut entries = Vec::with_capacity(found.len());
    for o in &found {
        let r = o.record();
        println!(
            "orbit at ω/ωn = {} on branch {} (period {}), Newton from {:.4}: {} in {} iteration(s), residual {:.2e}, {} (largest |ρ| {:.4})",
            r.speed_ratio,
            r.branch,
            r.period,
            r.from_speed_ratio,
            if r.converged { "converged" } else { "did NOT converge" },
            r.iterations,
            r.residual,
            if r.stable { "stable" } else { "unstable" },
            r.largest_modulus
        );
        let folder = format!("orbits/branch{}_{}/", o.branch, o.speed_ratio);
        let series = super::periodic::write_series(outd, (ls, model), &o.prep, &o.orbit, &folder)?;
        entries.push(OrbitEntry { orbit: r, series });
    }
    Ok(entries)
}

/// Prints every branch of `d` ([`report`]), where each switched one came from, and the
/// doublings not switched.
pub(super) fn report_diagram(d: &analysis::switch::Diagram) {
    for (i, b) in d.branches.iter().enumerate() {
        if let Some(r) = i.checked_sub(1).and_then(|k| d.switched.get(k)) {
            println!(
                "switched at the period doubling of branch {} at {} {:.4} (found at {:.4}, {}):",
                r.parent,
                parameter_label(b),
                r.at,
                r.found_at,
                if r.supercritical {
                    "supercritical"
                } else {
                    "subcritical"
                }
            );
        }
        report(b);
    }
    for why in &d.not_switched {
        eprintln!("warning: not switched: {why}");
    }
}

/// Prints the branch's stretches of stability, its bifurcations and where it ended.
fn report(b: &Branch) {
    let (Some(first), Some(last)) = (b.points.first(), b.points.last()) else {
        println!("no point of the period-{} branch converged", b.period);
        if let Some(why) = &b.ended {
            eprintln!("warning: {why}");
        }
        return;
    };
    let on = parameter_label(b);
    println!(
        "period-{} orbit continued over {on} {:.4} … {:.4}: {} points, {} steps",
        b.period,
        first.parameter,
        last.parameter,
        b.points.len(),
        b.steps
    );
    let mut start = 0;
    for i in 1..=b.points.len() {
        if i == b.points.len() || b.points[i].stable != b.points[start].stable {
            println!(
                "  {:>8}  {on} {:.4} – {:.4}",
                if b.points[start].stable {
                    "stable"
                } else {
                    "unstable"
                },
                b.points[start].parameter,
                b.points[i - 1].parameter
            );
            start = i;
        }
    }
    for x in &b.bifurcations {
        println!(
            "  {} at {on} {:.4} (between {:.4} and {:.4}; ρ {:+.4}{:+.4}i → {:+.4}{:+.4}i)",
            x.kind,
            x.parameter,
            x.between[0],
            x.between[1],
            x.rho[0][0],
            x.rho[0][1],
            x.rho[1][0],
            x.rho[1][1]
        );
    }
    if let Some(why) = &b.ended {
        eprintln!("warning: the branch ends before the last speed: {why}");
    }
}

/// The branch's parameter in messages: `ω/ωn`, or its scene key.
fn parameter_label(b: &Branch) -> &str {
    if b.at_speed_ratio.is_some() {
        &b.parameter
    } else {
        "ω/ωn"
    }
}
