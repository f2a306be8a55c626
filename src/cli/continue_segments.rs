//! `rubsim continue --segments n`: a branch in speed or in `--key` cut into segments run in
//! parallel, each kept as it finishes (resume), one shard of them with `--shard` or in a
//! Slurm array, and `rubsim merge` of the shards (`rubsim::study::segments`): the files of
//! `rubsim continue` and segments.csv.

use super::continuation::{report_diagram, speed_range, ContinueArgs};
use super::{default_out, finish, load, open_out, progress_bar, shooting_settings};
use anyhow::{Context, Result};
use rubsim::analysis::{self, branch::Branch, coexist_branches::CoexistRecord, switch::Diagram};
use rubsim::output::branch::{write_branch, write_diagram, DiagramView};
use rubsim::output::summary::{Base, ModelRecord, Summary};
use rubsim::output::OutDir;
use rubsim::scene::LoadedScene;
use rubsim::study::segment_spec::SegmentSpec;
use rubsim::study::segments::{self, MergedSegments, Seam, SegmentRecord, SegmentRequest};
use rubsim::study::summary::{ShardBody, ShardRecord};
use rubsim::study::{shard_counts, CaseStore, CASES_DIR};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The body of `summary.json` of `rubsim continue --segments` (and of its merge).
#[derive(Debug, Serialize)]
struct SegmentedBody<'a> {
    /// The branch asked for (the first part when the segments do not all join).
    branch: &'a Branch,
    /// Every part, when a seam splits the branch (and the flagged speeds' branches of
    /// `--sweep`).
    #[serde(skip_serializing_if = "Option::is_none")]
    parts: Option<&'a Diagram>,
    /// What was continued and how it was cut.
    continuation: &'a SegmentSpec,
    /// Each segment: its range, points, steps, wall time, where it ended.
    segments: Vec<SegmentLine>,
    /// Where consecutive segments do not join, and why.
    seams: &'a [Seam],
    /// With `--sweep`: each flagged speed, the branches holding its responses and those it
    /// added (as `rubsim continue --sweep`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    coexisting: Vec<CoexistRecord>,
    /// Wall time of the command (s).
    wall_s: f64,
}

/// One segment in summary.json.
#[derive(Debug, Serialize)]
struct SegmentLine {
    segment: usize,
    range: [f64; 2],
    points: usize,
    steps: u64,
    wall_s: f64,
    ended: Option<String>,
}

/// What `args` continue, cut into `--segments`, and the speeds the step is chosen for.
fn spec_of(
    args: &ContinueArgs,
    (ls, model): (&LoadedScene, &rubsim::model::Model),
) -> Result<(SegmentSpec, Vec<f64>)> {
    let (key, speed_ratio, (a, b, h), speeds) = match args.key.as_deref() {
        Some(k) => {
            let (nu, range) = super::continue_key::key_speed_range(args, (ls, model))?;
            (Some(k.to_string()), Some(nu), range, vec![nu])
        }
        None => {
            let (a, b, h) = speed_range(args, ls, model)?;
            let v = analysis::continuation::speeds(a, b, h)
                .with_context(|| format!("--from {a}, --to {b}, --step {h}"))?;
            (None, None, (a, b, h), v)
        }
    };
    let spec = SegmentSpec {
        key,
        speed_ratio,
        range: [a, b, h],
        period: args.period.unwrap_or(1),
        segments: args.segments.unwrap_or(1),
    };
    spec.bounds()
        .with_context(|| format!("--from {a}, --to {b}, --step {h}"))?;
    Ok((spec, speeds))
}

/// Runs the segments of the continuation `args` asks for that are not finished yet (a
/// shard's, with `--shard` or in a Slurm array), and — unsharded — joins every segment and
/// writes the branch's files. What the options or the key refuse is refused before the output
/// folder is made.
pub fn continuation_in_segments(args: &ContinueArgs) -> Result<()> {
    let a = args.clone();
    let (ls, model) = load(&a.c)?;
    super::periodic::check_period(a.period)?;
    if a.key.is_some() && a.sweep.is_some() {
        anyhow::bail!("--sweep draws a sweep's points over speed: not with --key");
    }
    let (spec, speeds) = spec_of(&a, (&ls, &model))?;
    let shard = super::shard_of(a.shard.as_deref())?;
    if shard.is_some() && a.sweep.is_some() {
        anyhow::bail!(
            "--sweep is drawn where the segments are joined: give it to `rubsim merge DIR --sweep SWEEP_DIR`, not to a shard"
        );
    }
    let dots = match (&a.sweep, shard) {
        (Some(d), None) => rubsim::study::overlay::sweep_poincare(
            &ls,
            &model,
            d,
            usize::from(ls.scene.output.component == "y"),
        )
        .context("--sweep")?,
        _ => Vec::new(),
    };
    let s = shooting_settings(&ls, &model, &speeds)?;
    let req = SegmentRequest {
        scene: &ls,
        model: &model,
        settings: &s,
        spec: &spec,
        shard,
        fresh: a.fresh,
    };
    let c = segments::continued(&req).with_context(|| format!("{}", a.c.scene.display()))?;
    let root = a
        .out
        .clone()
        .unwrap_or_else(|| default_out(&a.c.scene).join("continue"));
    let mut outd = open_out(&shard.map_or(root.clone(), |s| root.join(s.folder())))?;
    let t0 = std::time::Instant::now();
    let mine = shard.map_or(spec.segments, |s| {
        (0..spec.segments).filter(|j| s.contains(*j)).count()
    });
    println!(
        "period-{} orbit continued in {} segments{}",
        spec.period,
        spec.segments,
        shard.map_or(String::new(), |s| format!(
            " (shard {}/{}: {mine} of them)",
            s.index, s.count
        ))
    );
    let printed = super::progress::Printed::new("segments", OnceLock::from(progress_bar(mine)));
    let ran = segments::run(&req, &c, &mut outd, &printed)?;
    match shard {
        Some(sh) => {
            let base = Base::with_model(&ls, ModelRecord::of(&model), "continue shard");
            let body = ShardBody {
                shard: ShardRecord {
                    index: sh.index,
                    count: sh.count,
                    cases: ran.mine,
                    computed: ran.held.len(),
                    study_cases: ran.segments,
                    cases_dir: CASES_DIR,
                },
                wall_s: t0.elapsed().as_secs_f64(),
            };
            println!(
                "shard {}/{}: {} segments ({} computed now); assemble with `rubsim merge {}`",
                sh.index,
                sh.count,
                ran.mine,
                ran.held.len(),
                root.display()
            );
            finish(outd, &Summary { base, body })
        }
        None => {
            let base = Base::with_model(&ls, ModelRecord::of(&model), "continue");
            let recs = segments::records(&[&ran.store], &spec, &[], ran.held)?;
            let sweep = a.sweep.as_deref().filter(|_| spec.key.is_none());
            let (joined, coexisting) =
                joined_with_coexisting(&recs, (&ls, &model), (&c, &speeds), sweep)?;
            assemble(
                outd,
                (&ls, base),
                (&spec, &recs),
                (joined, coexisting),
                (&dots, t0),
            )
        }
    }
}

/// The segments `recs` joined and, with `--sweep DIR` (a branch in speed), the responses of
/// the speeds that sweep flagged as coexisting added as branches in `c` over `speeds`
/// (`analysis::coexist_branches`), their records printed.
fn joined_with_coexisting(
    recs: &[SegmentRecord],
    (ls, model): (&LoadedScene, &rubsim::model::Model),
    (c, speeds): (&analysis::parameter::Continued<'_>, &[f64]),
    sweep: Option<&Path>,
) -> Result<(segments::Joined, Vec<CoexistRecord>)> {
    let mut joined = segments::join(recs);
    let Some(d) = sweep else {
        return Ok((joined, Vec::new()));
    };
    let flagged = rubsim::study::overlay::sweep_flagged(ls, model, d).context("--sweep")?;
    let add = analysis::coexist_branches::add_coexisting;
    let recs = add(c, &mut joined.diagram, &flagged, speeds);
    Ok((joined, super::continuation::report_coexisting(recs)))
}

/// `rubsim merge` of a continuation's shards: every segment of `folders` joined into `out`;
/// with `sweep` (a branch in speed), the sweep's points drawn under the branches and its
/// flagged speeds' responses added, as [`continuation_in_segments`] does unsharded.
pub(super) fn merge(
    out: &Path,
    folders: &[PathBuf],
    sweep: Option<&Path>,
    t0: std::time::Instant,
) -> Result<()> {
    let outd = open_out(out)?;
    let m = MergedSegments::open(folders, out)?;
    let refs: Vec<&CaseStore> = m.stores.iter().collect();
    let recs = segments::records(&refs, &m.spec, &shard_counts(out), Vec::new())?;
    let base = Base::with_model(&m.scene, m.model.clone(), "continue");
    let Some(d) = sweep else {
        let joined = segments::join(&recs);
        return assemble(
            outd,
            (&m.scene, base),
            (&m.spec, &recs),
            (joined, Vec::new()),
            (&[], t0),
        );
    };
    let model = rubsim::model::Model::from_scene(&m.scene)
        .with_context(|| format!("{}: building the model", m.scene.file.display()))?;
    let component = usize::from(m.scene.scene.output.component == "y");
    let dots = rubsim::study::overlay::sweep_poincare(&m.scene, &model, d, component)
        .context("--sweep")?;
    let speeds = m.spec.values()?;
    let s = shooting_settings(&m.scene, &model, &speeds)?;
    let req = SegmentRequest {
        scene: &m.scene,
        model: &model,
        settings: &s,
        spec: &m.spec,
        shard: None,
        fresh: false,
    };
    let c = segments::continued(&req)?;
    let (joined, coexisting) =
        joined_with_coexisting(&recs, (&m.scene, &model), (&c, &speeds), Some(d))?;
    assemble(
        outd,
        (&m.scene, base),
        (&m.spec, &recs),
        (joined, coexisting),
        (&dots, t0),
    )
}

/// Writes the joined segments `recs` (`joined`, with the flagged speeds' branches of
/// `--sweep` and their `coexisting` records): branch.csv, bifurcations.csv (with several
/// branches branches.csv), the pictures, segments.csv and summary.json; prints the branches
/// and the seams.
fn assemble(
    mut outd: OutDir,
    (ls, base): (&LoadedScene, Base<'_>),
    (spec, recs): (&SegmentSpec, &[SegmentRecord]),
    (joined, coexisting): (segments::Joined, Vec<CoexistRecord>),
    (dots, t0): (&[(f64, f64)], std::time::Instant),
) -> Result<()> {
    let d = &joined.diagram;
    let png = ls.scene.output.png.then_some(DiagramView {
        component: ls.scene.output.component.as_str(),
        sweep: dots,
    });
    let title = &ls.scene.title;
    if d.branches.len() == 1 {
        write_branch(&mut outd, title, &d.branches[0], png)?;
    } else {
        write_diagram(&mut outd, title, d, png)?;
    }
    outd.write(
        "segments.csv",
        segments::segments_csv(recs, &joined.seams).as_bytes(),
    )?;
    report_diagram(d);
    for s in &joined.seams {
        eprintln!(
            "warning: segments {} and {} do not join at {}: {}",
            s.after_segment,
            s.after_segment + 1,
            s.at,
            s.why
        );
    }
    let body = SegmentedBody {
        branch: &d.branches[0],
        parts: (d.branches.len() > 1).then_some(d),
        continuation: spec,
        segments: recs
            .iter()
            .map(|r| SegmentLine {
                segment: r.index + 1,
                range: r.range,
                points: r.branch.points.len(),
                steps: r.branch.steps,
                wall_s: r.wall_s,
                ended: r.branch.ended.clone(),
            })
            .collect(),
        seams: &joined.seams,
        coexisting,
        wall_s: t0.elapsed().as_secs_f64(),
    };
    finish(outd, &Summary { base, body })
}
