//! `rubsim sweep`, `rubsim map` and `rubsim merge` on the command line: the arguments and the
//! environment (`--shard`, a Slurm array's variables) turned into a [`rubsim::study`] request,
//! the study's progress printed, and its results handed to the tables and pictures
//! ([`super::sweep`], [`super::map`]) and the summary.

use super::progress::Printed;
use super::{default_out, finish, load, open_out, Common};
use anyhow::Result;
use rubsim::model::Model;
use rubsim::output::summary::{Base, ModelRecord, Summary};
use rubsim::output::OutDir;
use rubsim::scene::LoadedScene;
use rubsim::study::assemble::Tables;
use rubsim::study::summary::{ShardBody, ShardRecord};
use rubsim::study::{self, CaseStore, Computed, Kind, Merged, Study, StudyRequest};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

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

/// `rubsim sweep` / `rubsim map`: runs the cases not yet finished (of the shard, when asked),
/// each written to the case store as soon as it is done; unsharded, assembles the results.
pub fn run(c: &Common, kind: Kind, a: &StudyArgs) -> Result<()> {
    let (ls, model) = load(c)?;
    if kind == Kind::Map && ls.scene.thermal.is_some() {
        return thermal_map(c, a, (&ls, &model));
    }
    let study = Study::of(&ls, Some(model.rotor.natural_frequency()), kind)?;
    let shard = super::shard_of(a.shard.as_deref())?;
    let root = a.out.clone().unwrap_or_else(|| default_out(&c.scene));
    let dir = shard.map_or(root.clone(), |s| root.join(s.folder()));
    let mut outd = open_out(&dir)?;
    let t0 = std::time::Instant::now();
    let req = StudyRequest {
        scene: &ls,
        model: &model,
        study: &study,
        shard,
        fresh: a.fresh,
    };
    let printed = Printed::new("cases", OnceLock::new());
    let ran = study::run(&req, &mut outd, &printed)?;
    let model_rec = ModelRecord::of(&model);
    match shard {
        Some(s) => {
            let base = Base::with_model(&ls, model_rec, &format!("{} shard", kind.name()));
            let body = ShardBody {
                shard: ShardRecord::new(s, &ran),
                wall_s: t0.elapsed().as_secs_f64(),
            };
            println!(
                "shard {}/{}: {} cases ({} computed now); assemble with `rubsim merge {}`",
                s.index,
                s.count,
                ran.mine,
                ran.computed,
                root.display()
            );
            finish(outd, &Summary { base, body })
        }
        None => {
            let stores = [&ran.store];
            assemble(outd, &ls, &study, (&stores, ran.held), model_rec, t0)
        }
    }
}

/// Writes the study's tables, pictures and summary from the cases this process computed
/// (`held`) and the case files of `stores` ([`study::assemble::write`]), commits the output
/// directory and prints what it found.
fn assemble(
    outd: OutDir,
    ls: &LoadedScene,
    study: &Study,
    (stores, held): (&[&CaseStore], Vec<Computed>),
    model_rec: ModelRecord,
    t0: std::time::Instant,
) -> Result<()> {
    let (tables, dir) = study::assemble::write(outd, (ls, study), (stores, held), model_rec, t0)?;
    match &tables {
        Tables::Sweep(variants) => variants.iter().for_each(super::sweep::report),
        Tables::Map(map, runs) => super::map::report(map, runs),
    }
    println!("results in {}", dir.display());
    Ok(())
}

/// `rubsim merge DIR [MORE…]`: the case stores of `DIR` (its `cases/` and its
/// `shard-*/cases/`) and of the other directories, all of one scene, assembled into `DIR`
/// exactly as a one-machine run writes them.
pub fn merge(dirs: &[PathBuf], sweep: Option<&Path>) -> Result<()> {
    let t0 = std::time::Instant::now();
    let folders = study::merge_folders(dirs)?;
    let out = &dirs[0];
    let first = CaseStore::read_only(&folders[0].join(study::CASES_DIR))?;
    if let Some(spec) = &first.plan().continuation {
        if let (Some(key), Some(_)) = (&spec.key, sweep) {
            anyhow::bail!(
                "--sweep draws a sweep's points over speed: {} holds a continuation in `{key}`",
                out.display()
            );
        }
        return super::continue_segments::merge(out, &folders, sweep, t0);
    }
    if sweep.is_some() {
        anyhow::bail!(
            "--sweep draws a sweep's points under a continuation's branches: {} holds a `rubsim {}`, not a continuation",
            out.display(),
            first.plan().command
        );
    }
    let mut outd = open_out(out)?;
    let merged = Merged::open(&folders, out)?;
    merged.gather_series(&mut outd)?;
    let refs: Vec<&CaseStore> = merged.stores.iter().collect();
    assemble(
        outd,
        &merged.scene,
        &merged.study,
        (&refs, Vec::new()),
        merged.model.clone(),
        t0,
    )
}

/// `rubsim map` of a scene with `[thermal]`: the thermal spiral at every cell
/// ([`rubsim::study::thermal_map`]), its tables, pictures and summary; no shards.
fn thermal_map(c: &Common, a: &StudyArgs, (ls, model): (&LoadedScene, &Model)) -> Result<()> {
    use rubsim::study::thermal_map as tm;
    if a.shard.is_some() {
        anyhow::bail!(
            "{}: a thermal map runs whole (its cells are not kept in a case store): leave out --shard",
            c.scene.display()
        );
    }
    let outd = open_out(&a.out.clone().unwrap_or_else(|| default_out(&c.scene)))?;
    let t0 = std::time::Instant::now();
    let map = tm::run(ls, model)?;
    let classes = tm::MapRecord::of(&map).classes;
    let dir = tm::write_all(outd, (ls, model), &map, t0)?;
    println!(
        "thermal map {} × {}: {} cells — {} stable, {} growing, {} running away, {} whose vibration is not synchronous",
        map.axes.values[0].len(),
        map.axes.values[1].len(),
        map.cells.len(),
        classes[0],
        classes[1],
        classes[2],
        classes[3]
    );
    println!("results in {}", dir.display());
    Ok(())
}
