//! Running a study: the cases still missing from the store (all, or one shard's), in
//! parallel, each written to the store as soon as it is done — what makes resume work.

use super::case::{CaseId, CaseSpec};
use super::series::SeriesPlan;
use super::shard::Shard;
use super::store::{scene_hash, CaseRecord, CaseStore, StorePlan, FORMAT};
use super::Study;
use crate::analysis::sweep::run_all;
use crate::analysis::{self, RunSettings, SpeedResults, StepChoice};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::output::summary::ModelRecord;
use crate::output::{figures, OutDir};
use crate::plot::Boundary;
use crate::results::{speed_folder, Series};
use crate::scene::LoadedScene;
use std::path::Path;
use std::sync::mpsc;

/// What a study reports to its caller while it runs (the command line prints it; the default
/// methods ignore it). Called from the worker threads too, hence `Sync`.
pub trait Progress: Sync {
    /// Something the user should know that does not stop the study (old cases discarded).
    fn warning(&self, _message: &str) {}
    /// A variant's integrator and Δt, chosen from `run.tolerance` by pilot runs.
    fn step_chosen(&self, _choice: &StepChoice) {}
    /// `finished` of the `of` cases asked for were found finished in the store `store`.
    fn resumed(&self, _finished: usize, _of: usize, _store: &Path) {}
    /// `runs` cases at the speeds `speeds` (ω/ω_n) are about to run, the first variant's
    /// `model` with `settings`.
    fn start(&self, _model: &Model, _settings: &RunSettings, _speeds: &[f64], _runs: usize) {}
    /// One more case is done.
    fn case_done(&self) {}
    /// Every case has run (or failed).
    fn end(&self) {}
}

/// A [`Progress`] that reports nothing.
pub struct Quiet;

impl Progress for Quiet {}

/// A study to run: the scene and its model, the study it describes, which shard (all cases
/// when `None`), and whether the cases of an earlier, different scene in the output directory
/// are discarded (`fresh`) instead of refused.
pub struct StudyRequest<'a> {
    /// The scene, with the command line's overrides.
    pub scene: &'a LoadedScene,
    /// Its model.
    pub model: &'a Model,
    /// The study.
    pub study: &'a Study,
    /// The shard to run, or every case.
    pub shard: Option<Shard>,
    /// Discard the cases of another scene instead of refusing to run.
    pub fresh: bool,
}

/// What [`run`] did.
#[derive(Debug)]
pub struct StudyRun {
    /// The case store of the output directory.
    pub store: CaseStore,
    /// Cases of the whole study.
    pub cases: usize,
    /// Cases of this shard (all of them unsharded).
    pub mine: usize,
    /// Cases computed by this run (the others were finished already).
    pub computed: usize,
    /// The results of the cases computed by this run, as their files hold them: the tables
    /// are assembled from these and read only the other cases back ([`super::results`]).
    pub held: Vec<Computed>,
}

/// Runs the cases of `req` not yet finished in the case store of `outd` (the output
/// directory, or the shard's folder, whose lock `outd` holds), each written to the store as
/// soon as it is done; then links the kept time series of this shard's cases into `outd`.
///
/// # Errors
/// [`Error::Shard`] for more shards than cases; the store's errors ([`CaseStore::open`]: cases
/// of another scene); a case's error, named by its id ([`Error::AtCase`]).
pub fn run(req: &StudyRequest, outd: &mut OutDir, progress: &dyn Progress) -> Result<StudyRun> {
    let (ls, kind) = (req.scene, req.study.kind);
    let cases = req.study.cases();
    if let Some(s) = req.shard {
        s.check_count(cases.len(), &format!("the study has {} cases", cases.len()))?;
    }
    let plan = StorePlan {
        format: FORMAT,
        command: kind.name().into(),
        scene_hash: scene_hash(kind.name(), &ls.scene),
        rubsim_version: env!("CARGO_PKG_VERSION").into(),
        cases: cases.len(),
        scene_file: ls.file.display().to_string(),
        source: ls.source.clone(),
        overrides: ls.overrides.clone(),
        model: ModelRecord::of(req.model),
        continuation: None,
    };
    let (store, note) = CaseStore::open(outd.dir(), plan, req.fresh)?;
    if let Some(n) = note {
        progress.warning(&n);
    }
    let mine: Vec<&CaseSpec> = cases
        .iter()
        .filter(|c| req.shard.is_none_or(|s| s.contains(c.index)))
        .collect();
    let series = SeriesPlan::of(ls, req.study)?;
    let with_series: Vec<&CaseSpec> = mine.iter().copied().filter(|c| series.wants(c)).collect();
    let keep: Vec<_> = with_series.iter().map(|c| c.id.clone()).collect();
    store.prune_series(&keep)?;
    let todo = unfinished(&store, &mine, &series)?;
    if todo.len() < mine.len() {
        progress.resumed(mine.len() - todo.len(), mine.len(), store.dir());
    }
    let held = run_cases(
        &CasesRequest {
            scene: ls,
            model: req.model,
            study: req.study,
            todo: &todo,
            store: &store,
            series: &series,
        },
        progress,
    )?;
    for case in &with_series {
        series.link(&store, &case.id, outd)?;
    }
    Ok(StudyRun {
        store,
        cases: cases.len(),
        mine: mine.len(),
        computed: held.len(),
        held,
    })
}

/// The cases of `mine` still to run: not finished in `store`, or finished without the time
/// series `series` asks for, written with this run's output settings.
fn unfinished<'c>(
    store: &CaseStore,
    mine: &[&'c CaseSpec],
    series: &SeriesPlan,
) -> Result<Vec<&'c CaseSpec>> {
    let mut todo = Vec::new();
    for &case in mine {
        let done = store.finished(&case.id)?
            && (!series.wants(case) || store.series_files(&case.id, series.stamp())?.is_some());
        if !done {
            todo.push(case);
        }
    }
    Ok(todo)
}

/// Cases to run ([`run_cases`]): the scene and model of the study, the cases, the store they
/// are written to and which of them keep their time series.
pub struct CasesRequest<'a> {
    /// The scene, with the command line's overrides.
    pub scene: &'a LoadedScene,
    /// Its model.
    pub model: &'a Model,
    /// The study the cases belong to.
    pub study: &'a Study,
    /// The cases to run.
    pub todo: &'a [&'a CaseSpec],
    /// Where each finished case is written.
    pub store: &'a CaseStore,
    /// Which cases keep their time series, and their stamp.
    pub series: &'a SeriesPlan,
}

/// The scene, model and run settings of one variant of a study.
struct VariantRun {
    scene: Option<(LoadedScene, Model)>,
    settings: RunSettings,
}

/// A case computed by a run: its index in the study, its results and boundary exactly as its
/// case file holds them (what [`super::results`] would read back).
pub type Computed = (usize, SpeedResults, Boundary);

/// Runs `req.todo` in parallel, each case's record written to the store when done, after the
/// case's time series (when asked for) are kept in the store. The workers seal each record
/// and hand it to one writer thread, which writes the files that are waiting as one batch
/// ([`CaseStore::write_sealed`]), so that the disk's syncs overlap the computing. Returns
/// the results of the cases run.
///
/// # Errors
/// A variant's scene or model, the choice of its step, or a case's error (named by its id:
/// [`Error::AtCase`]); every case runs even when one fails, and the first failure in case
/// order is returned; then a case file that could not be written.
pub fn run_cases(req: &CasesRequest, progress: &dyn Progress) -> Result<Vec<Computed>> {
    let todo = req.todo;
    if todo.is_empty() {
        return Ok(Vec::new());
    }
    let runs = variant_runs(req, progress)?;
    let speeds: Vec<f64> = todo.iter().map(|t| t.speed_ratio).collect();
    let first = runs.iter().flatten().next().map(|r| r.settings);
    progress.start(
        req.model,
        &first.unwrap_or_else(|| RunSettings::from_scene(&req.scene.scene)),
        &speeds,
        todo.len(),
    );
    // Every variant's model: one holding large columns of its own makes all go one at a time.
    let one_at_a_time = std::iter::once(req.model)
        .chain(
            runs.iter()
                .flatten()
                .filter_map(|r| r.scene.as_ref().map(|(_, m)| m)),
        )
        .any(crate::analysis::sweep::one_at_a_time);
    let scene_json =
        serde_json::to_string(&req.scene.scene).map_err(|e| Error::output(req.store.dir(), e))?;
    let (tx, rx) = mpsc::sync_channel::<(CaseId, Vec<u8>)>(2 * rayon::current_num_threads());
    let (res, wrote) = std::thread::scope(|sc| {
        let writer = sc.spawn(move || write_queue(req.store, &rx));
        let res = {
            let tx = tx;
            let run_named = |case: &&CaseSpec| {
                runs[case.variant]
                    .as_ref()
                    .ok_or_else(|| Error::study("", "a case of a variant without run settings"))
                    .and_then(|var| run_case(req, var, case, &scene_json, &tx))
                    .map_err(|e| Error::AtCase {
                        id: case.id.to_string(),
                        source: Box::new(e),
                    })
            };
            run_all(one_at_a_time, todo, &run_named, &|| progress.case_done())
        };
        let wrote = writer
            .join()
            .unwrap_or_else(|_| Err(Error::study("", "the writer of the case files failed")));
        (res, wrote)
    });
    progress.end();
    let res = res?;
    wrote?;
    Ok(res)
}

/// The writer thread of [`run_cases`]: every sealed case file received, those waiting written
/// as one batch. After a failed write it writes nothing more (the cases keep running and are
/// reported; the next run computes the ones without a file) and returns the failure.
fn write_queue(store: &CaseStore, rx: &mpsc::Receiver<(CaseId, Vec<u8>)>) -> Result<()> {
    let mut failed = None;
    while let Ok(first) = rx.recv() {
        let mut batch = vec![first];
        batch.extend(rx.try_iter());
        if failed.is_none() {
            failed = store.write_sealed(&batch).err();
        }
    }
    failed.map_or(Ok(()), Err)
}

/// The scene, model and settings of every variant that has cases in `req.todo` (`None` for
/// the others): the study's own for a plain sweep; each variant's step chosen from the
/// tolerance over the study's speeds.
fn variant_runs(req: &CasesRequest, progress: &dyn Progress) -> Result<Vec<Option<VariantRun>>> {
    let ls = req.scene;
    let mut runs = Vec::with_capacity(req.study.variants.len());
    for (i, var) in req.study.variants.iter().enumerate() {
        if !req.todo.iter().any(|t| t.variant == i) {
            runs.push(None);
            continue;
        }
        let scene = if var.is_base() {
            None
        } else {
            let l = ls.with_overrides(&var.overrides)?;
            let m = Model::from_scene(&l)
                .map_err(|e| e.context(format!("{}: building the model", ls.file.display())))?;
            Some((l, m))
        };
        let (l, m) = scene.as_ref().map_or((ls, req.model), |(l, m)| (l, m));
        let settings = run_settings(l, m, &req.study.speeds).map_err(|e| {
            e.context(format!(
                "{}: choosing Δt for `run.tolerance`",
                l.file.display()
            ))
        })?;
        if let Some(c) = &settings.choice {
            progress.step_chosen(c);
        }
        runs.push(Some(VariantRun { scene, settings }));
    }
    Ok(runs)
}

/// Runs one case of a variant and hands its sealed record to the writer (its series kept
/// first, when asked for); returns its results as the record holds them.
fn run_case(
    req: &CasesRequest,
    var: &VariantRun,
    case: &CaseSpec,
    scene_json: &str,
    writer: &mpsc::SyncSender<(CaseId, Vec<u8>)>,
) -> Result<Computed> {
    let (l, m) = var
        .scene
        .as_ref()
        .map_or((req.scene, req.model), |(l, m)| (l, m));
    let v = case.speed_ratio;
    let series = req.series.wants(case);
    let prep = analysis::prepare(m, &var.settings.request_for(case.speed, v, series))?;
    let keep = req.study.keep(l, v);
    let r = if series {
        let staging = req.store.stage_series(&case.id)?;
        let sr = Series {
            output: &l.scene.output,
            scene_json,
            staging: &staging,
        };
        let prefix = &req.study.variants[case.variant].prefix;
        let (r, _) = sr.run(m, &prep, keep, &format!("{prefix}{}", speed_folder(v)))?;
        req.store.keep_series(&case.id, req.series.stamp())?;
        r
    } else {
        prep.run(keep, &mut [])?
    };
    let rec = CaseRecord::new(
        &case.id,
        &req.store.plan().scene_hash,
        r,
        figures::boundary(&prep.case),
    );
    let bytes = rec.sealed(&req.store.path(&case.id))?;
    writer
        .send((case.id.clone(), bytes))
        .map_err(|_| Error::study("", "the writer of the case files stopped"))?;
    let (r, b) = rec.into_parts();
    Ok((case.index, r, b))
}

/// The run settings of a scene whose runs are at `speeds` (ω/ω_n): the scene's
/// ([`RunSettings::from_scene`]), with the integrator and Δt chosen from `run.tolerance` by
/// pilot runs ([`analysis::choose`]) when the scene asks for it (`run.auto_step`) and gives no
/// `run.dt` and no speed profile.
///
/// # Errors
/// As [`analysis::choose`].
pub fn run_settings(ls: &LoadedScene, model: &Model, speeds: &[f64]) -> Result<RunSettings> {
    settings_with(ls, model, speeds, analysis::choose)
}

/// [`run_settings`] for the commands that shoot periodic orbits (`rubsim periodic`, `rubsim
/// continue` and the Python package's `periodic`, `continuation`): the step chosen among the
/// explicit schemes, whose state the maps restart ([`analysis::autostep::choose_explicit`]).
///
/// # Errors
/// As [`run_settings`].
pub fn shooting_settings(ls: &LoadedScene, model: &Model, speeds: &[f64]) -> Result<RunSettings> {
    settings_with(ls, model, speeds, analysis::autostep::choose_explicit)
}

/// A step choice: [`analysis::choose`] or [`analysis::autostep::choose_explicit`].
type Chooser = fn(
    &Model,
    &RunSettings,
    Option<crate::scene::IntegratorKind>,
    Option<f64>,
    &[f64],
) -> Result<RunSettings>;

/// The scene's run settings, with the step chosen by `choose` when the scene asks for it.
fn settings_with(
    ls: &LoadedScene,
    model: &Model,
    speeds: &[f64],
    choose: Chooser,
) -> Result<RunSettings> {
    let s = RunSettings::from_scene(&ls.scene);
    let run = &ls.scene.run;
    if !run.auto_step || run.dt.is_some() || run.speed_profile.is_some() {
        return Ok(s);
    }
    choose(model, &s, run.integrator, run.rho_inf, speeds)
}
