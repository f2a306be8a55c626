//! Studies made of cases — `rubsim sweep`, `rubsim map` — and `rubsim merge`: run the cases
//! still missing (one shard of them, or all) into the case store of the output directory
//! ([`rubsim::output::cases`]), then assemble the tables and pictures from the case files.

use super::{default_out, finish, load, open_out, progress_bar, settings, Common, Series};
use anyhow::{bail, Context, Result};
use rubsim::analysis::sweep::{self as sw, CaseSpec, Shard, SweepKeep, Variant};
use rubsim::analysis::{self, Keep, SpeedResults};
use rubsim::model::Model;
use rubsim::output::cases::{scene_hash, CaseRecord, CaseStore, StorePlan, CASES_DIR, FORMAT};
use rubsim::output::{figures, summary, OutDir};
use rubsim::plot::Boundary;
use rubsim::results::{per_speed_selection, speed_folder};
use rubsim::scene::LoadedScene;
use std::path::{Path, PathBuf};

/// The options every study command shares.
#[derive(clap::Args, Clone, Debug)]
pub struct StudyArgs {
    /// Output directory (default: out/<scene name>).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    pub jobs: Option<usize>,
    /// Run only shard i of n (1 ≤ i ≤ n) into <out>/shard-<i>-of-<n>/, for `rubsim merge`;
    /// inside a Slurm array job the default is the task's (SLURM_ARRAY_TASK_ID − MIN + 1 of
    /// SLURM_ARRAY_TASK_COUNT).
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Discard the finished cases of an earlier, different scene in the output directory
    /// instead of refusing to run.
    #[arg(long)]
    pub fresh: bool,
}

/// The two studies made of cases.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `[run.sweep]`: speeds, once or per value of `[run.sweep.vary]`.
    Sweep,
    /// `[run.map]`: two parameters.
    Map,
}

impl Kind {
    /// The command's name.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Sweep => "sweep",
            Kind::Map => "map",
        }
    }

    fn from_name(name: &str) -> Option<Self> {
        match name {
            "sweep" => Some(Kind::Sweep),
            "map" => Some(Kind::Map),
            _ => None,
        }
    }
}

/// A study: its variants of the scene and its speeds; the cases are every speed of every
/// variant ([`sw::cases`]).
pub struct Study {
    /// Which command.
    pub kind: Kind,
    /// The variants (overrides) of the scene.
    pub variants: Vec<Variant>,
    /// The speeds ω/ω_n of every variant.
    pub speeds: Vec<f64>,
    /// A map's axes, else `None`.
    pub map: Option<super::map::MapAxes>,
}

impl Study {
    /// The study a scene describes for `kind`.
    pub fn of(ls: &LoadedScene, model_wn: Option<f64>, kind: Kind) -> Result<Self> {
        match kind {
            Kind::Sweep => {
                let spec = ls.scene.run.sweep.as_ref().with_context(|| {
                    format!(
                        "{}: `rubsim sweep` needs a [run.sweep] table",
                        ls.file.display()
                    )
                })?;
                Ok(Self {
                    kind,
                    variants: sw::variants(spec.vary.as_ref()),
                    speeds: analysis::sweep_speeds(spec.from, spec.to, spec.step),
                    map: None,
                })
            }
            Kind::Map => super::map::study(ls, model_wn),
        }
    }

    /// What the case at ν = `v` keeps for the pictures.
    fn keep(&self, ls: &LoadedScene, v: f64) -> Keep {
        match self.kind {
            Kind::Sweep => {
                let o = &ls.scene.output;
                SweepKeep::new(o, sw::cascade_max(o, &self.speeds)).at(v)
            }
            Kind::Map => Keep::default(),
        }
    }
}

/// `rubsim sweep` / `rubsim map`: runs the cases not yet finished (of the shard, when asked),
/// each written to the case store as soon as it is done; unsharded, assembles the results.
pub fn run(c: &Common, kind: Kind, a: &StudyArgs) -> Result<()> {
    let (ls, model) = load(c)?;
    let study = Study::of(&ls, Some(model.rotor.natural_frequency()), kind)?;
    let cases = sw::cases(&study.variants, &study.speeds);
    let shard = match &a.shard {
        Some(s) => Some(Shard::parse(s)?),
        None => Shard::from_slurm(|k| std::env::var(k).ok())?,
    };
    if let Some(s) = shard {
        if s.count > cases.len() {
            bail!(
                "--shard {}/{}: the study has {} cases, fewer than {} shards",
                s.index,
                s.count,
                cases.len(),
                s.count
            );
        }
    }
    let root = a.out.clone().unwrap_or_else(|| default_out(&c.scene));
    let dir = shard.map_or(root.clone(), |s| root.join(s.folder()));
    let mut outd = open_out(&dir)?;
    let model_rec = summary::model_record(&model);
    let plan = StorePlan {
        format: FORMAT,
        command: kind.name().into(),
        scene_hash: scene_hash(kind.name(), &ls.scene),
        rubsim_version: env!("CARGO_PKG_VERSION").into(),
        cases: cases.len(),
        scene_file: ls.file.display().to_string(),
        source: ls.source.clone(),
        overrides: ls.overrides.clone(),
        model: model_rec.clone(),
    };
    let (store, note) = CaseStore::open(outd.dir(), plan, a.fresh)?;
    if let Some(n) = note {
        eprintln!("warning: {n}");
    }
    let t0 = std::time::Instant::now();
    let mine: Vec<&CaseSpec> = cases
        .iter()
        .enumerate()
        .filter(|(k, _)| shard.is_none_or(|s| s.contains(*k)))
        .map(|(_, c)| c)
        .collect();
    let series = series_wanted(&ls, &study)?;
    let stamp = series_stamp(&ls);
    let with_series: Vec<&CaseSpec> = mine
        .iter()
        .copied()
        .filter(|c| series.contains(&(c.variant, c.speed_ratio.to_bits())))
        .collect();
    let keep: Vec<&str> = with_series.iter().map(|c| c.id.as_str()).collect();
    store.prune_series(&keep)?;
    let mut todo = Vec::new();
    for case in &mine {
        // A finished case whose series are asked for is done only when the store keeps them,
        // written with this run's output settings.
        let done = store.finished(&case.id)?
            && (!keep.contains(&case.id.as_str())
                || store.series_files(&case.id, &stamp)?.is_some());
        if !done {
            todo.push(*case);
        }
    }
    if todo.len() < mine.len() {
        eprintln!(
            "{} of {} cases already finished in {}; running {}",
            mine.len() - todo.len(),
            mine.len(),
            store.dir().display(),
            todo.len()
        );
    }
    let ran = run_cases(c, &ls, &model, &study, &todo, &store, &series, &stamp)?;
    for case in &with_series {
        link_series(&store, &case.id, &stamp, &mut outd)?;
    }
    match shard {
        Some(s) => {
            let mut sum = summary::base_with(&ls, model_rec, &format!("{} shard", kind.name()));
            sum["shard"] = serde_json::json!({
                "index": s.index, "count": s.count, "cases": mine.len(),
                "computed": ran, "study_cases": cases.len(), "cases_dir": CASES_DIR,
            });
            sum["wall_s"] = t0.elapsed().as_secs_f64().into();
            println!(
                "shard {}/{}: {} cases ({} computed now); assemble with `rubsim merge {}`",
                s.index,
                s.count,
                mine.len(),
                ran,
                root.display()
            );
            finish(outd, &sum)
        }
        None => assemble(outd, &ls, &study, &[&store], model_rec, t0),
    }
}

/// The (variant, speed bits) pairs whose per-speed VTK/HDF5 time series are asked for
/// (`output.per_speed`, sweeps only): their series are kept with the cases
/// (`cases/series/<id>/`) and linked into the results.
fn series_wanted(ls: &LoadedScene, study: &Study) -> Result<Vec<(usize, u64)>> {
    if study.kind != Kind::Sweep {
        return Ok(Vec::new());
    }
    let o = &ls.scene.output;
    let sel =
        per_speed_selection(o, &study.speeds).map_err(|m| ls.invalid("output.per_speed", m))?;
    Ok((0..study.variants.len())
        .flat_map(|i| {
            study
                .speeds
                .iter()
                .zip(&sel)
                .filter(|(_, s)| **s)
                .map(move |(v, _)| (i, v.to_bits()))
        })
        .collect())
}

/// What the kept series of a case depend on besides the case itself: the scene's
/// `output.vtk` and `output.hdf5` (the scene hash of the store leaves them out).
fn series_stamp(ls: &LoadedScene) -> String {
    let o = &ls.scene.output;
    let mut h = rubsim::math::Fnv128::new();
    h.write(
        serde_json::to_string(&(&o.vtk, &o.hdf5))
            .unwrap_or_default()
            .as_bytes(),
    );
    h.hex()
}

/// Links (or, across file systems, copies) the kept series of case `id` into the staging
/// folder of `outd` under their names in the results, and registers them for the commit.
fn link_series(store: &CaseStore, id: &str, stamp: &str, outd: &mut OutDir) -> Result<()> {
    let files = store
        .series_files(id, stamp)?
        .with_context(|| format!("the time series of case {id} are missing from the store"))?;
    let from = store.series_path(id);
    for name in &files {
        let (src, dst) = (from.join(name), outd.staging_dir().join(name));
        if let Some(d) = dst.parent() {
            std::fs::create_dir_all(d).with_context(|| d.display().to_string())?;
        }
        if std::fs::hard_link(&src, &dst).is_err() {
            std::fs::copy(&src, &dst).with_context(|| format!("{}", src.display()))?;
        }
        outd.adopt(name)?;
    }
    Ok(())
}

/// For `rubsim merge`: links the per-speed time series of every case that asks for them
/// (`output.per_speed`) from whichever store (shard) kept them into `outd`, so that the merged
/// directory holds them as a one-machine run does; a case whose series no store keeps is an
/// error naming the case and the stores searched.
fn gather_series(
    ls: &LoadedScene,
    study: &Study,
    stores: &[CaseStore],
    outd: &mut OutDir,
) -> Result<()> {
    let series = series_wanted(ls, study)?;
    let stamp = series_stamp(ls);
    for case in sw::cases(&study.variants, &study.speeds) {
        if !series.contains(&(case.variant, case.speed_ratio.to_bits())) {
            continue;
        }
        let mut from = None;
        for st in stores {
            if st.series_files(&case.id, &stamp)?.is_some() {
                from = Some(st);
                break;
            }
        }
        let Some(st) = from else {
            bail!(
                "case {} (ω/ωn = {}) asks for its time series (`output.per_speed`), but none of \
                 the merged stores keeps them ({}); run its shard again",
                case.id,
                case.speed_ratio,
                stores
                    .iter()
                    .map(|s| s.dir().display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        };
        link_series(st, &case.id, &stamp, outd)?;
    }
    Ok(())
}

/// Runs `todo` in parallel, each case's record written to `store` when done, after the
/// case's per-speed time series (when `series` asks for them) are kept in the store stamped
/// `stamp`. Returns the number of cases run.
#[allow(clippy::too_many_arguments)]
fn run_cases(
    c: &Common,
    ls: &LoadedScene,
    model: &Model,
    study: &Study,
    todo: &[&CaseSpec],
    store: &CaseStore,
    series: &[(usize, u64)],
    stamp: &str,
) -> Result<usize> {
    if todo.is_empty() {
        return Ok(0);
    }
    // The models of the variants that have cases to run (the scene's own for a plain sweep).
    let mut models: Vec<Option<(LoadedScene, Model)>> = Vec::new();
    for (i, var) in study.variants.iter().enumerate() {
        let needed = todo.iter().any(|t| t.variant == i) && !var.is_base();
        models.push(if needed {
            let mut set = c.set.clone();
            set.extend(var.overrides.iter().cloned());
            Some(load(&Common {
                scene: c.scene.clone(),
                set,
                tol: c.tol,
            })?)
        } else {
            None
        });
    }
    let of = |i: usize| match &models[i] {
        Some((l, m)) => (l, m),
        None => (ls, model),
    };
    // Each variant's integrator and Δt, chosen from the tolerance over the study's speeds.
    let mut sets = Vec::with_capacity(models.len());
    for (i, m) in models.iter().enumerate() {
        sets.push(match m {
            Some((l, m)) => Some(super::chosen_settings(l, m, &study.speeds)?),
            None if todo.iter().any(|t| t.variant == i) => {
                Some(super::chosen_settings(ls, model, &study.speeds)?)
            }
            None => None,
        });
    }
    let speeds: Vec<f64> = todo.iter().map(|t| t.speed_ratio).collect();
    let first = sets.iter().flatten().next().copied();
    super::announce_sweep(
        model,
        &first.unwrap_or_else(|| settings(ls)),
        &speeds,
        todo.len(),
    );
    let pb = progress_bar(todo.len());
    let scene_json = serde_json::to_string(&ls.scene)?;
    let hash = &store.plan().scene_hash;
    let run = |case: &&CaseSpec| -> rubsim::error::Result<()> {
        let (l, m) = of(case.variant);
        let v = case.speed_ratio;
        let st = sets[case.variant].unwrap_or_else(|| settings(l));
        let prep = analysis::prepare(m, &st, v)?;
        let keep = study.keep(l, v);
        let r = if series.contains(&(case.variant, v.to_bits())) {
            let staging = store.stage_series(&case.id)?;
            let sr = Series {
                output: &l.scene.output,
                scene_json: &scene_json,
                staging: &staging,
            };
            let prefix = &study.variants[case.variant].prefix;
            let (r, _) = sr.run(m, &prep, keep, &format!("{prefix}{}", speed_folder(v)))?;
            store.keep_series(&case.id, stamp)?;
            r
        } else {
            prep.run(keep, &mut [])?
        };
        store.write(&CaseRecord::new(
            &case.id,
            hash,
            r,
            figures::boundary(&prep.case),
        ))
    };
    let run_named = |case: &&CaseSpec| {
        run(case).map_err(|e| rubsim::error::Error::AtCase {
            id: case.id.clone(),
            source: Box::new(e),
        })
    };
    let res = sw::run_all(todo, &run_named, &|| pb.inc(1));
    pb.finish_and_clear();
    res?;
    Ok(todo.len())
}

/// The results of every case, read from the first store that holds each, in case order;
/// fails listing the missing cases (and, for each shard count seen, the shards to run again).
fn read_all(
    stores: &[&CaseStore],
    cases: &[CaseSpec],
    shard_counts: &[usize],
) -> Result<Vec<(SpeedResults, Boundary)>> {
    let missing: Vec<(usize, &CaseSpec)> = cases
        .iter()
        .enumerate()
        .filter(|(_, c)| !stores.iter().any(|s| s.path(&c.id).is_file()))
        .collect();
    if !missing.is_empty() {
        let mut msg = format!("{} of {} cases are missing:", missing.len(), cases.len());
        for (_, c) in missing.iter().take(20) {
            msg.push_str(&format!("\n  {}", c.id));
        }
        if missing.len() > 20 {
            msg.push_str(&format!("\n  … and {} more", missing.len() - 20));
        }
        for n in shard_counts {
            let mut shards: Vec<usize> = missing.iter().map(|(k, _)| k % n + 1).collect();
            shards.dedup();
            shards.sort_unstable();
            shards.dedup();
            let list: Vec<String> = shards.iter().map(|s| s.to_string()).collect();
            msg.push_str(&format!(
                "\nthey belong to shards {} of {n}: run those again (Slurm: sbatch --array={} …)",
                list.join(", "),
                list.join(",")
            ));
        }
        bail!(msg);
    }
    cases
        .iter()
        .map(|c| {
            for s in stores {
                if let Some(rec) = s.read(&c.id)? {
                    return Ok(rec.into_parts());
                }
            }
            bail!("case {} disappeared while being read", c.id)
        })
        .collect()
}

/// Writes the study's tables, pictures and summary from the case files of `stores`, and
/// commits the output directory.
fn assemble(
    mut outd: OutDir,
    ls: &LoadedScene,
    study: &Study,
    stores: &[&CaseStore],
    model_rec: serde_json::Value,
    t0: std::time::Instant,
) -> Result<()> {
    let cases = sw::cases(&study.variants, &study.speeds);
    let counts = shard_counts(outd.dir());
    let results = read_all(stores, &cases, &counts)?;
    let mut sum = summary::base_with(ls, model_rec, study.kind.name());
    match study.kind {
        Kind::Sweep => {
            let records = super::sweep::assemble(&mut outd, ls, study, results)?;
            sum["sweeps"] = serde_json::Value::Array(records);
        }
        Kind::Map => {
            sum["map"] = super::map::assemble(&mut outd, ls, study, results)?;
        }
    }
    sum["cases"] = serde_json::json!({
        "count": cases.len(),
        "scene_hash": stores.first().map(|s| s.plan().scene_hash.clone()),
        "folders": stores.iter().map(|s| s.dir().display().to_string()).collect::<Vec<_>>(),
    });
    sum["wall_s"] = t0.elapsed().as_secs_f64().into();
    finish(outd, &sum)
}

/// The shard counts n of the `shard-<i>-of-<n>` folders in `dir`, ascending.
fn shard_counts(dir: &Path) -> Vec<usize> {
    let mut v: Vec<usize> = shard_folders(dir)
        .iter()
        .filter_map(|p| {
            let name = p.file_name()?.to_string_lossy().into_owned();
            name.rsplit_once("-of-")?.1.parse().ok()
        })
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}

/// The `shard-*` folders of `dir` that hold a case store, sorted.
fn shard_folders(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("shard-"))
                && p.join(CASES_DIR).is_dir()
        })
        .collect();
    v.sort();
    v
}

/// `rubsim merge DIR [MORE…]`: the case stores of `DIR` (its `cases/` and its
/// `shard-*/cases/`) and of the other directories, all of one scene, assembled into `DIR`
/// exactly as a one-machine run writes them.
pub fn merge(dirs: &[PathBuf]) -> Result<()> {
    let Some(out) = dirs.first() else {
        bail!("rubsim merge needs at least one directory");
    };
    let t0 = std::time::Instant::now();
    let mut folders = Vec::new();
    for d in dirs {
        if !d.is_dir() {
            bail!("{}: no such directory", d.display());
        }
        if d.join(CASES_DIR).is_dir() {
            folders.push(d.clone());
        }
        folders.extend(shard_folders(d));
    }
    if folders.is_empty() {
        bail!(
            "{}: no cases to merge (neither {CASES_DIR}/ nor shard-*/{CASES_DIR}/ found)",
            dirs.iter()
                .map(|d| d.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let outd = open_out(out)?;
    // Each shard folder's lock is held while its cases are read: a shard still running is
    // refused, not read half-way.
    let mut locks = Vec::new();
    for f in folders.iter().filter(|f| *f != out) {
        locks.push(
            OutDir::prepare(f)
                .with_context(|| format!("{}: a shard still running?", f.display()))?,
        );
    }
    let stores = folders
        .iter()
        .map(|f| CaseStore::read_only(&f.join(CASES_DIR)))
        .collect::<rubsim::error::Result<Vec<_>>>()?;
    let first = stores[0].plan();
    for s in &stores[1..] {
        if s.plan().scene_hash != first.scene_hash {
            bail!(
                "{} and {} hold cases of different scenes (scene hashes {} and {}: `rubsim {}` of \
                 {} with {:?}, and `rubsim {}` of {} with {:?}); merge only the shards of one study",
                stores[0].dir().display(),
                s.dir().display(),
                first.scene_hash,
                s.plan().scene_hash,
                first.command,
                first.scene_file,
                first.overrides,
                s.plan().command,
                s.plan().scene_file,
                s.plan().overrides
            );
        }
    }
    let kind = Kind::from_name(&first.command).with_context(|| {
        format!(
            "{}: unknown command {:?}",
            stores[0].dir().display(),
            first.command
        )
    })?;
    let ls = rubsim::scene::parse(
        Path::new(&first.scene_file),
        &first.source,
        &first.overrides,
    )?;
    if scene_hash(kind.name(), &ls.scene) != first.scene_hash {
        bail!(
            "{}: its cases were made by rubsim {} from a scene this rubsim ({}) reads \
             differently; merge them with that version",
            stores[0].dir().display(),
            first.rubsim_version,
            env!("CARGO_PKG_VERSION")
        );
    }
    let wn = first.model["omega_n_rad_s"].as_f64();
    let study = Study::of(&ls, wn, kind)?;
    let mut outd = outd;
    gather_series(&ls, &study, &stores, &mut outd)?;
    let refs: Vec<&CaseStore> = stores.iter().collect();
    let model_rec = first.model.clone();
    assemble(outd, &ls, &study, &refs, model_rec, t0)?;
    drop(locks);
    Ok(())
}
