//! A continuation split into segments (`rubsim continue --segments n`, issue 29): the branch's
//! values cut into `n` stretches ([`SegmentSpec::bounds`]: consecutive segments share their end
//! value), each continued on its own — its orbit shot from a settled run at its first value,
//! then Newton from value to value as [`crate::analysis::branch::follow`] does — so that the
//! segments run in parallel on one machine, as the shards of a Slurm array
//! (`--shard i/n`: the segments `j` with `j mod n = i − 1`, into `shard-<i>-of-<n>/`) and
//! resume after a kill: each finished segment is a file of the output directory's case store
//! (`cases/segment=<j>-of-<n>.toml`, [`SegmentRecord`], sealed as a case file is), and a rerun
//! into the same directory computes only the segments still missing. `rubsim merge` assembles
//! the shards' segments as the one-machine run does.
//!
//! **Every segment is continued as the whole branch would be**: the same [`Continued`] (in
//! speed with the reduced model's cut-off pinned at the branch's top speed; in a key with the
//! one step plan of the whole range's ends), the same period (`--period`, default 1: it cannot
//! come from the first value's settled run, which only the first segment has), the same values.
//! Each interval between two values belongs to one segment, so the changes of stability and
//! grazing points are located exactly as the unsplit branch locates them.
//!
//! **Joining** ([`join`]): where segment `j` reached its last value and segment `j + 1`
//! starts there on the same orbit (their Poincaré points within [`DISTINCT`] of the orbit's
//! size), the two are one branch and the shared point is kept once. Where they do not — a
//! segment that ended early (a fold, an orbit that ceases to exist) or a next segment whose
//! settled run found another orbit (coexisting responses) — the result is a *seam*: the parts
//! are drawn and listed as separate branches (branches.csv), and the seam is reported with
//! its reason, never bridged.

use super::case::CaseId;
use super::run::Progress;
use super::segment_spec::SegmentSpec;
use super::shard::Shard;
use super::store::{scene_hash, seal, CaseStore, StorePlan, FORMAT};
use crate::analysis::branch::{Branch, BranchPoint};
use crate::analysis::parameter::Continued;
use crate::analysis::periodic::DISTINCT;
use crate::analysis::switch::Diagram;
use crate::analysis::RunSettings;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::output::summary::ModelRecord;
use crate::output::OutDir;
use crate::scene::LoadedScene;
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

/// A continuation in segments to run: the scene and its model, the settings every segment
/// runs with, what is continued, which shard (every segment when `None`), and whether the
/// segments of an earlier, different continuation in the output directory are discarded
/// (`fresh`) instead of refused.
pub struct SegmentRequest<'a> {
    /// The scene, with the command line's overrides.
    pub scene: &'a LoadedScene,
    /// Its model.
    pub model: &'a Model,
    /// The run settings (the step chosen for the branch's speeds).
    pub settings: &'a RunSettings,
    /// What is continued and how it is cut.
    pub spec: &'a SegmentSpec,
    /// The shard to run, or every segment.
    pub shard: Option<Shard>,
    /// Discard the segments of another continuation instead of refusing to run.
    pub fresh: bool,
}

/// One finished segment, as its file holds it.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SegmentRecord {
    /// `segment=<j + 1>-of-<n>`.
    pub id: CaseId,
    /// [`scene_hash`] of the continuation.
    pub scene_hash: String,
    /// 0-based index j.
    pub index: usize,
    /// Its first and last value (ν, or the key's).
    pub range: [f64; 2],
    /// Wall time of the segment (s).
    pub wall_s: f64,
    /// Its branch (without restart states).
    pub branch: Branch,
}

/// What [`run`] did.
#[derive(Debug)]
pub struct SegmentRun {
    /// The case store of the output directory (or shard folder).
    pub store: CaseStore,
    /// Segments of the whole continuation.
    pub segments: usize,
    /// Segments of this shard (all of them unsharded).
    pub mine: usize,
    /// The segments computed by this run, as their files hold them.
    pub held: Vec<SegmentRecord>,
}

/// The store plan of the continuation `spec` of `scene`.
pub fn store_plan(scene: &LoadedScene, model: &Model, spec: &SegmentSpec) -> StorePlan {
    StorePlan {
        format: FORMAT,
        command: "continue".into(),
        scene_hash: scene_hash(&spec.command(), &scene.scene),
        rubsim_version: env!("CARGO_PKG_VERSION").into(),
        cases: spec.segments,
        scene_file: scene.file.display().to_string(),
        source: scene.source.clone(),
        overrides: scene.overrides.clone(),
        model: ModelRecord::of(model),
        continuation: Some(spec.clone()),
    }
}

/// Runs the segments of `req` not yet finished in the case store of `outd` (the output
/// directory, or the shard's folder, whose lock `outd` holds), in parallel, each written to
/// the store as soon as it is done ([module docs](self)).
///
/// # Errors
/// [`Error::Study`] for a spec that cuts no segment ([`SegmentSpec::bounds`]);
/// [`Error::Shard`] for more shards than segments; the store's errors (segments of another
/// continuation); a segment's first
/// shooting error, named by its id ([`Error::AtCase`]) — every segment runs even when one
/// fails, and the finished ones are kept.
pub fn run(
    req: &SegmentRequest,
    c: &Continued<'_>,
    outd: &mut OutDir,
    progress: &dyn Progress,
) -> Result<SegmentRun> {
    let spec = req.spec;
    let values = spec.values()?;
    let bounds = spec.bounds()?;
    if let Some(s) = req.shard {
        let what = format!("the continuation has {} segments", bounds.len());
        s.check_count(bounds.len(), &what)?;
    }
    let plan = store_plan(req.scene, req.model, spec);
    let hash = plan.scene_hash.clone();
    let (store, note) = CaseStore::open(outd.dir(), plan, req.fresh)?;
    if let Some(n) = note {
        progress.warning(&n);
    }
    let mine: Vec<usize> = (0..bounds.len())
        .filter(|j| req.shard.is_none_or(|s| s.contains(*j)))
        .collect();
    let mut todo = Vec::new();
    for &j in &mine {
        if !store.finished(&CaseId::segment(j, bounds.len()))? {
            todo.push(j);
        }
    }
    if todo.len() < mine.len() {
        progress.resumed(mine.len() - todo.len(), mine.len(), store.dir());
    }
    let one = |&j: &usize| -> Result<SegmentRecord> {
        let id = CaseId::segment(j, bounds.len());
        let [a, b] = bounds[j];
        let rec = segment(c, &values[a..=b], (&id, j, spec.period), &hash).map_err(|e| {
            Error::AtCase {
                id: id.to_string(),
                source: Box::new(e),
            }
        })?;
        let text = toml::to_string(&rec).map_err(|e| Error::output(store.path(&id), e))?;
        store.write_sealed(&[(id, seal(text))])?;
        Ok(rec)
    };
    let held = crate::analysis::sweep::run_all(false, &todo, &one, &|| progress.case_done())?;
    progress.end();
    Ok(SegmentRun {
        store,
        segments: bounds.len(),
        mine: mine.len(),
        held,
    })
}

/// The parameter every segment of `req` is continued in ([`run`]'s `c`): the speed (the
/// cut-off pinned at the top of all the values) or the key over all the values (their one
/// step plan). Built before the output directory is opened, so that what the key refuses
/// leaves nothing written.
///
/// # Errors
/// As [`SegmentSpec::values`]; [`Continued::of_speed`], [`Continued::of_key`]; a scheme or
/// state that shooting refuses ([`crate::analysis::periodic::check_shootable`]).
pub fn continued<'a>(req: &SegmentRequest<'a>) -> Result<Continued<'a>> {
    let values = req.spec.values()?;
    let values = values.as_slice();
    let c = match (&req.spec.key, req.spec.speed_ratio) {
        (Some(key), Some(nu)) => Continued::of_key(req.scene, req.settings, (key, nu), values)?,
        (Some(key), None) => {
            return Err(Error::study(key, "a branch in a key needs its fixed speed"))
        }
        (None, _) => {
            let top = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            Continued::of_speed(req.model, req.settings, top)?
        }
    };
    crate::analysis::periodic::check_shootable(&c.prepare(values[0])?)?;
    Ok(c)
}

/// Segment `j`'s (named `id`) branch over `values` (its own, first to last), period `period`.
fn segment(
    c: &Continued<'_>,
    values: &[f64],
    (id, j, period): (&CaseId, usize, usize),
    hash: &str,
) -> Result<SegmentRecord> {
    let t0 = std::time::Instant::now();
    let mut branch = crate::analysis::branch::continue_in(c, values, Some(period))?;
    branch.points.iter_mut().for_each(|p| p.start = None);
    let (first, last) = (values[0], values[values.len() - 1]);
    let rec = SegmentRecord {
        id: id.clone(),
        scene_hash: hash.to_string(),
        index: j,
        range: [first, last],
        wall_s: t0.elapsed().as_secs_f64(),
        branch,
    };
    Ok(rec)
}

/// Every segment of `spec`, in order: those of `held` (computed by this process) as they are,
/// each other read from the first of `stores` that holds it.
///
/// # Errors
/// [`Error::Study`] listing the missing segments and the shards (of each count in
/// `shard_counts`) that run them; a damaged segment file, or one of another continuation.
pub fn records(
    stores: &[&CaseStore],
    spec: &SegmentSpec,
    shard_counts: &[usize],
    held: Vec<SegmentRecord>,
) -> Result<Vec<SegmentRecord>> {
    let n = spec.bounds()?.len();
    let mut slots: Vec<Option<SegmentRecord>> = (0..n).map(|_| None).collect();
    for r in held {
        if let Some(s) = slots.get_mut(r.index) {
            *s = Some(r);
        }
    }
    for (j, slot) in slots.iter_mut().enumerate().filter(|(_, s)| s.is_none()) {
        let id = CaseId::segment(j, n);
        for s in stores {
            let Some(text) = s.read_body(&id)? else {
                continue;
            };
            let p = s.path(&id);
            let rec: SegmentRecord = toml::from_str(&text)
                .map_err(|e| Error::output(&p, format!("damaged segment file: {}", e.message())))?;
            if rec.scene_hash != s.plan().scene_hash || rec.index != j {
                return Err(Error::output(
                    &p,
                    "is a segment of another continuation; delete it (or its folder) and run again",
                ));
            }
            *slot = Some(rec);
            break;
        }
    }
    let missing: Vec<usize> = (0..n).filter(|j| slots[*j].is_none()).collect();
    if !missing.is_empty() {
        return Err(Error::study("", missing_message(&missing, n, shard_counts)));
    }
    Ok(slots.into_iter().flatten().collect())
}

/// "k of n segments are missing: …", and the shards that run them.
fn missing_message(missing: &[usize], n: usize, shard_counts: &[usize]) -> String {
    let list: Vec<String> = missing.iter().map(|j| (j + 1).to_string()).collect();
    let msg = format!(
        "{} of {n} segments are missing: {}",
        missing.len(),
        list.join(", ")
    );
    msg + &super::shard::rerun_hint(missing, shard_counts)
}

/// Where two consecutive segments do not join ([`join`]).
#[derive(Debug, Clone, Serialize)]
pub struct Seam {
    /// The 1-based number of the segment before the seam.
    pub after_segment: usize,
    /// The shared value of the two segments.
    pub at: f64,
    /// Why they do not join.
    pub why: String,
}

/// The segments joined: the branches (one when every seam joins), the seams, the steps.
#[derive(Debug, Clone)]
pub struct Joined {
    /// The parts, as a diagram of branches without switches (the first the one asked for).
    pub diagram: Diagram,
    /// Where consecutive segments did not join.
    pub seams: Vec<Seam>,
}

/// Joins the segments `recs` (in order) into branches ([module docs](self)).
pub fn join(recs: &[SegmentRecord]) -> Joined {
    let mut branches: Vec<Branch> = Vec::new();
    let mut seams = Vec::new();
    let mut current: Option<Branch> = None;
    for (j, r) in recs.iter().enumerate() {
        let next = r.branch.clone();
        let Some(mut cur) = current.take() else {
            current = Some(next);
            continue;
        };
        match joins(&cur, &next, r.range[0]) {
            Ok(()) => {
                cur.points.extend(next.points.into_iter().skip(1));
                cur.bifurcations.extend(next.bifurcations);
                cur.steps += next.steps;
                cur.ended = next.ended;
                current = Some(cur);
            }
            Err(why) => {
                seams.push(Seam {
                    after_segment: j,
                    at: r.range[0],
                    why,
                });
                if !cur.points.is_empty() {
                    branches.push(cur);
                }
                current = Some(next);
            }
        }
    }
    if let Some(cur) = current {
        if !cur.points.is_empty() || branches.is_empty() {
            branches.push(cur);
        }
    }
    let steps = recs.iter().map(|r| r.branch.steps).sum();
    let mut diagram = Diagram::of(branches.remove(0));
    diagram.branches.extend(branches);
    diagram.steps = steps;
    Joined { diagram, seams }
}

/// Whether the branch `next`, starting at `at`, continues `cur`: `cur` reached `at` (its last
/// point there, not ended) and `next`'s first point is the same orbit; why not otherwise.
fn joins(cur: &Branch, next: &Branch, at: f64) -> std::result::Result<(), String> {
    let Some(last) = cur.points.last().filter(|p| p.parameter == at) else {
        return Err(format!(
            "the segment before ends short of {at}: {}",
            cur.ended.as_deref().unwrap_or("no point reached it")
        ));
    };
    let Some(first) = next.points.first().filter(|p| p.parameter == at) else {
        return Err(format!(
            "the segment after has no orbit at {at}: {}",
            next.ended
                .as_deref()
                .unwrap_or("its first point is elsewhere")
        ));
    };
    let d = distance(last, first);
    if d > DISTINCT {
        return Err(format!(
            "the two segments found different period-{} orbits at {at} (Poincaré points {d:.2e} apart, of the orbit's size): coexisting responses, the next segment's settled run reached the other",
            cur.period
        ));
    }
    Ok(())
}

/// The relative distance between the Poincaré points of two orbits of one period: their
/// Hausdorff distance (the orbits may be one revolution apart in phase, so points are matched
/// to the nearest, both ways), over the largest point's size.
fn distance(a: &BranchPoint, b: &BranchPoint) -> f64 {
    if a.poincare_nd.len() != b.poincare_nd.len() {
        return f64::INFINITY;
    }
    let size = a
        .poincare_nd
        .iter()
        .chain(&b.poincare_nd)
        .fold(1e-300_f64, |m, p| m.max(p[0].hypot(p[1])));
    crate::analysis::coexist_orbits::hausdorff(&a.poincare_nd, &b.poincare_nd) / size
}

/// segments.csv: each segment's range, points, steps, wall time and whether it joins the next.
pub fn segments_csv(recs: &[SegmentRecord], seams: &[Seam]) -> String {
    let mut csv = String::from("segment,from,to,points,steps,wall_s,joins_next,ended\n");
    for r in recs {
        let joins = if r.index + 1 == recs.len() {
            ""
        } else if seams.iter().any(|s| s.after_segment == r.index + 1) {
            "false"
        } else {
            "true"
        };
        let ended = r.branch.ended.as_deref().unwrap_or("").replace('"', "'");
        let _ = writeln!(
            csv,
            "{},{},{},{},{},{:.3},{joins},\"{ended}\"",
            r.index + 1,
            r.range[0],
            r.range[1],
            r.branch.points.len(),
            r.branch.steps,
            r.wall_s
        );
    }
    csv
}

/// The case stores of a continuation's segments (a sharded run's folders), with the scene
/// and the continuation rebuilt from their plan; each shard folder's lock is held while it
/// lives, so a shard still running is refused, not read half-way.
pub struct MergedSegments {
    /// The scene, parsed from the text and overrides kept in the plan.
    pub scene: LoadedScene,
    /// What was continued.
    pub spec: SegmentSpec,
    /// The stores, in the order of the folders.
    pub stores: Vec<CaseStore>,
    /// The summary's `model` record, kept in the plan.
    pub model: ModelRecord,
    _locks: Vec<OutDir>,
}

impl MergedSegments {
    /// Locks and reads the stores of `folders` ([`super::merge_folders`]) other than `out`,
    /// the merge's output directory, whose lock the caller holds.
    ///
    /// # Errors
    /// As [`super::merge::locked_stores`]; [`Error::Study`] for a store that holds no
    /// continuation, or one made by a rubsim that reads the scene differently.
    pub fn open(folders: &[std::path::PathBuf], out: &std::path::Path) -> Result<Self> {
        let (locks, stores) = super::merge::locked_stores(folders, out)?;
        let first = &stores[0];
        let plan = first.plan();
        let spec = plan.continuation.clone().ok_or_else(|| {
            Error::study(
                first.dir().display(),
                format!("a store of `rubsim {}` holds no continuation", plan.command),
            )
        })?;
        let scene = super::merge::scene_of(first, &spec.command())?;
        Ok(Self {
            scene,
            spec,
            model: plan.model.clone(),
            stores,
            _locks: locks,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(parameter: f64, p: [f64; 2]) -> BranchPoint {
        BranchPoint {
            speed_ratio: parameter,
            parameter,
            stable: true,
            largest_modulus: 0.5,
            rho1: [0.5, 0.0],
            instability: None,
            extents_nd: [0.0; 4],
            amp_1x_nd: 1.0,
            contact_fraction: 0.0,
            poincare_nd: vec![p],
            iterations: 1,
            residual: 0.0,
            start: None,
        }
    }

    fn record(index: usize, pts: &[(f64, [f64; 2])], ended: Option<&str>) -> SegmentRecord {
        SegmentRecord {
            id: CaseId::segment(index, 3),
            scene_hash: "h".into(),
            index,
            range: [pts[0].0, pts[pts.len() - 1].0],
            wall_s: 0.0,
            branch: Branch {
                parameter: "speed_ratio".into(),
                at_speed_ratio: None,
                period: 1,
                points: pts.iter().map(|(v, p)| point(*v, *p)).collect(),
                bifurcations: Vec::new(),
                ended: ended.map(str::to_string),
                steps: 10,
                doublings: Vec::new(),
            },
        }
    }

    #[test]
    fn segments_on_one_orbit_join_and_another_orbit_is_a_seam() {
        let a = record(0, &[(1.0, [1.0, 0.0]), (1.5, [1.1, 0.0])], None);
        let b = record(1, &[(1.5, [1.1, 1e-9]), (2.0, [1.2, 0.0])], None);
        let c = record(2, &[(2.0, [3.0, 0.0]), (2.5, [3.1, 0.0])], None);
        let j = join(&[a, b, c]);
        assert_eq!(j.diagram.branches.len(), 2);
        assert_eq!(j.diagram.branches[0].points.len(), 3);
        assert_eq!(j.diagram.steps, 30);
        assert_eq!(j.seams.len(), 1);
        assert_eq!(j.seams[0].after_segment, 2);
        assert!(j.seams[0].why.contains("different period-1 orbits"));
    }

    /// Two period-2 sections of which one holds a point twice: every point of the first is
    /// near one of the second, not the other way round — two orbits, which the one-sided
    /// distance took for one.
    #[test]
    fn the_join_distance_is_symmetric() {
        let mut a = point(1.5, [1.0, 0.0]);
        a.poincare_nd = vec![[1.0, 0.0], [1.0, 0.0]];
        let mut b = point(1.5, [1.0, 0.0]);
        b.poincare_nd = vec![[1.0, 0.0], [-1.0, 0.0]];
        assert_eq!(distance(&a, &b), 2.0);
        assert_eq!(distance(&b, &a), 2.0);
        assert_eq!(distance(&a, &a), 0.0);
    }

    #[test]
    fn a_segment_that_ends_early_is_a_seam_naming_why() {
        let a = record(0, &[(1.0, [1.0, 0.0]), (1.2, [1.1, 0.0])], Some("a fold"));
        let b = record(1, &[(1.5, [2.0, 0.0]), (2.0, [2.1, 0.0])], None);
        let mut b2 = b.clone();
        b2.range[0] = 1.5;
        let j = join(&[a, b2]);
        assert_eq!(j.diagram.branches.len(), 2);
        assert!(j.seams[0].why.contains("a fold"), "{}", j.seams[0].why);
        let csv = segments_csv(&[record(0, &[(1.0, [1.0, 0.0])], None)], &[]);
        assert!(csv.starts_with("segment,from,to,points"));
    }

    #[test]
    fn a_segment_record_reads_back_as_written() {
        let mut r = record(1, &[(1.5, [1.1, 0.2]), (2.0, [1.2, f64::NAN])], None);
        r.branch.points[1].instability = Some("period_doubling");
        let text = toml::to_string(&r).unwrap();
        let back: SegmentRecord = toml::from_str(&text).unwrap();
        assert_eq!(back.branch.points[1].instability, Some("period_doubling"));
        assert_eq!(back.branch.points[0].poincare_nd, [[1.1, 0.2]]);
        assert!(back.branch.points[1].poincare_nd[0][1].is_nan());
        let bad = text.replace("period_doubling", "flutter");
        let e = toml::from_str::<SegmentRecord>(&bad)
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown kind `flutter`"), "{e}");
    }
}
