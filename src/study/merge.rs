//! Reading a study's cases back: every case from the stores that hold them ([`results`]), and
//! the stores of a sharded study gathered for `rubsim merge` ([`merge_folders`], [`Merged`]).

use super::case::{CaseId, CaseSpec};
use super::run::Computed;
use super::series::SeriesPlan;
use super::shard::shard_folders;
use super::store::{scene_hash, CaseRecord, CaseStore, CASES_DIR};
use super::{Kind, Study};
use crate::analysis::SpeedResults;
use crate::error::{Error, Result};
use crate::output::summary::ModelRecord;
use crate::output::OutDir;
use crate::plot::Boundary;
use crate::scene::LoadedScene;
use std::path::{Path, PathBuf};

/// The results of every case of `study`, in case order: those of `held` (the cases this
/// process computed, [`super::StudyRun::held`]) as they are, every other read from the first
/// of `stores` that holds it; `shard_counts` are the shard counts n seen
/// (`shard-<i>-of-<n>` folders), for the message about missing cases.
///
/// # Errors
/// [`Error::Study`] listing the missing cases (and, for each shard count, the shards to run
/// again), or naming a case two stores hold in differing copies, with both files; a damaged
/// case file ([`CaseStore::read`]).
pub fn results(
    stores: &[&CaseStore],
    study: &Study,
    shard_counts: &[usize],
    held: Vec<Computed>,
) -> Result<Vec<(SpeedResults, Boundary)>> {
    let cases = study.cases();
    let mut slots: Vec<Option<(SpeedResults, Boundary)>> = cases.iter().map(|_| None).collect();
    for (k, r, b) in held {
        if let Some(slot) = slots.get_mut(k) {
            *slot = Some((r, b));
        }
    }
    let missing: Vec<&CaseSpec> = cases
        .iter()
        .zip(&slots)
        .filter(|(c, h)| h.is_none() && !stores.iter().any(|s| s.path(&c.id).is_file()))
        .map(|(c, _)| c)
        .collect();
    if !missing.is_empty() {
        return Err(Error::study(
            "",
            missing_message(&missing, cases.len(), shard_counts),
        ));
    }
    cases
        .iter()
        .zip(slots)
        .map(|(c, held)| {
            if let Some(r) = held {
                return Ok(r);
            }
            let mut found: Option<(&CaseStore, CaseRecord)> = None;
            for s in stores {
                let Some(rec) = s.read(&c.id)? else { continue };
                match &found {
                    None => found = Some((s, rec)),
                    Some((first, kept)) if !same_results(kept, &rec) => {
                        return Err(conflict(&c.id, first, s))
                    }
                    Some(_) => {}
                }
            }
            found.map(|(_, rec)| rec.into_parts()).ok_or_else(|| {
                Error::study("", format!("case {} disappeared while being read", c.id))
            })
        })
        .collect()
}

/// True when two copies of a case hold the same results, bit for bit (NaN equal to NaN): every
/// number [`CaseRecord::numbers`] checks, the period and steadiness; the run's timings may
/// differ (a case computed again by a shard of another layout).
fn same_results(a: &CaseRecord, b: &CaseRecord) -> bool {
    let bits =
        |r: &CaseRecord| -> Vec<u64> { r.numbers().iter().map(|(_, x)| x.to_bits()).collect() };
    a.results.period == b.results.period
        && a.results.steady == b.results.steady
        && bits(a) == bits(b)
}

/// Two stores hold differing copies of case `id`: which one is right is not for the merge to
/// guess.
fn conflict(id: &CaseId, a: &CaseStore, b: &CaseStore) -> Error {
    Error::study(
        id.as_str(),
        format!(
            "two copies of this case differ: {} and {}; the shards did not compute it alike \
             (another rubsim, another scene or an edited file): delete the wrong copy (or the \
             shard folder) and merge again",
            a.path(id).display(),
            b.path(id).display()
        ),
    )
}

/// "n of N cases are missing:", up to 20 of them, and the shards they belong to.
fn missing_message(missing: &[&CaseSpec], total: usize, shard_counts: &[usize]) -> String {
    let mut msg = format!("{} of {} cases are missing:", missing.len(), total);
    for c in missing.iter().take(20) {
        msg.push_str(&format!("\n  {}", c.id));
    }
    if missing.len() > 20 {
        msg.push_str(&format!("\n  … and {} more", missing.len() - 20));
    }
    let indices: Vec<usize> = missing.iter().map(|c| c.index).collect();
    msg + &super::shard::rerun_hint(&indices, shard_counts)
}

/// The folders whose case stores a merge of `dirs` reads: each directory that holds
/// `cases/`, and its `shard-*/` folders that do.
///
/// # Errors
/// [`Error::Study`]: no directory, a directory that does not exist, or no cases anywhere.
pub fn merge_folders(dirs: &[PathBuf]) -> Result<Vec<PathBuf>> {
    if dirs.is_empty() {
        return Err(Error::study(
            "",
            "rubsim merge needs at least one directory",
        ));
    }
    let mut folders = Vec::new();
    for d in dirs {
        if !d.is_dir() {
            return Err(Error::study(d.display(), "no such directory"));
        }
        if d.join(CASES_DIR).is_dir() {
            folders.push(d.clone());
        }
        folders.extend(shard_folders(d));
    }
    if folders.is_empty() {
        let names: Vec<String> = dirs.iter().map(|d| d.display().to_string()).collect();
        return Err(Error::study(
            names.join(", "),
            format!("no cases to merge (neither {CASES_DIR}/ nor shard-*/{CASES_DIR}/ found)"),
        ));
    }
    Ok(folders)
}

/// The case stores of a sharded study, all of one scene, with the scene and study rebuilt
/// from the stores' plan; each shard folder's lock is held while it lives, so a shard still
/// running is refused, not read half-way.
pub struct Merged {
    /// The scene, parsed from the text and overrides kept in the plan.
    pub scene: LoadedScene,
    /// The study.
    pub study: Study,
    /// The stores, in the order of the folders.
    pub stores: Vec<CaseStore>,
    /// The summary's `model` record, kept in the plan (the model is not rebuilt).
    pub model: ModelRecord,
    _locks: Vec<OutDir>,
}

impl Merged {
    /// Locks and reads the stores of `folders` (from [`merge_folders`]) other than `out`, the
    /// merge's output directory, whose lock the caller holds.
    ///
    /// # Errors
    /// A shard folder locked by a running shard ([`Error::Context`]); stores of different
    /// scenes, of an unknown command, or made by a rubsim that reads the scene differently
    /// ([`Error::Study`]); an unreadable plan.
    pub fn open(folders: &[PathBuf], out: &Path) -> Result<Self> {
        let (locks, stores) = locked_stores(folders, out)?;
        let first = &stores[0];
        let plan = first.plan();
        let dir = first.dir().display();
        let kind = Kind::from_name(&plan.command)
            .ok_or_else(|| Error::study(&dir, format!("unknown command {:?}", plan.command)))?;
        let scene = scene_of(first, kind.name())?;
        let study = Study::of(&scene, Some(plan.model.omega_n_rad_s), kind)?;
        let model = plan.model.clone();
        Ok(Self {
            scene,
            study,
            stores,
            model,
            _locks: locks,
        })
    }

    /// Links the kept time series of every case that asks for them into `outd`
    /// ([`SeriesPlan::gather`]).
    ///
    /// # Errors
    /// As [`SeriesPlan::gather`].
    pub fn gather_series(&self, outd: &mut OutDir) -> Result<()> {
        SeriesPlan::of(&self.scene, &self.study)?.gather(&self.study, &self.stores, outd)
    }
}

/// The stores of `folders` (at least one), each folder other than `out` (the merge's output
/// directory, whose lock the caller holds) locked while the returned locks live; every store
/// of one scene hash.
///
/// # Errors
/// A shard folder locked by a running shard ([`Error::Context`]); stores of different scenes
/// ([`Error::Study`]); an unreadable plan.
pub fn locked_stores(folders: &[PathBuf], out: &Path) -> Result<(Vec<OutDir>, Vec<CaseStore>)> {
    let mut locks = Vec::new();
    for f in folders.iter().filter(|f| *f != out) {
        locks.push(
            OutDir::prepare(f)
                .map_err(|e| e.context(format!("{}: a shard still running?", f.display())))?,
        );
    }
    let stores = folders
        .iter()
        .map(|f| CaseStore::read_only(&f.join(CASES_DIR)))
        .collect::<Result<Vec<_>>>()?;
    let first = stores
        .first()
        .ok_or_else(|| Error::study("", "no cases to merge"))?;
    for s in &stores[1..] {
        if s.plan().scene_hash != first.plan().scene_hash {
            return Err(different_scenes(first, s));
        }
    }
    Ok((locks, stores))
}

/// Why the stores `a` and `b` cannot be merged.
fn different_scenes(a: &CaseStore, b: &CaseStore) -> Error {
    let (p, q) = (a.plan(), b.plan());
    Error::study(
        format!("{} and {}", a.dir().display(), b.dir().display()),
        format!(
            "hold cases of different scenes (scene hashes {} and {}: `rubsim {}` of {} with \
             {:?}, and `rubsim {}` of {} with {:?}); merge only the shards of one study",
            p.scene_hash,
            q.scene_hash,
            p.command,
            p.scene_file,
            p.overrides,
            q.command,
            q.scene_file,
            q.overrides
        ),
    )
}

/// The scene of a store, rebuilt from its plan and checked against its scene hash, which
/// was taken with the command `command` ([`scene_hash`]).
///
/// # Errors
/// The scene's own errors; [`Error::Study`] when the hash differs (another rubsim's reading).
pub fn scene_of(store: &CaseStore, command: &str) -> Result<LoadedScene> {
    let plan = store.plan();
    let dir = store.dir().display();
    let ls = crate::scene::parse(Path::new(&plan.scene_file), &plan.source, &plan.overrides)?;
    if scene_hash(command, &ls.scene) != plan.scene_hash {
        return Err(Error::study(
            &dir,
            format!(
                "its cases were made by rubsim {} from a scene this rubsim ({}) reads \
                 differently; merge them with that version",
                plan.rubsim_version,
                env!("CARGO_PKG_VERSION")
            ),
        ));
    }
    Ok(ls)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::variant::variants;

    #[test]
    fn missing_cases_are_listed_with_the_shards_that_ran_them() {
        let cs = crate::study::cases(&variants(None), &[1.0, 2.0, 3.0, 4.0, 5.0]);
        let missing: Vec<&CaseSpec> = [&cs[1], &cs[4]].into();
        let m = missing_message(&missing, cs.len(), &[3]);
        assert!(m.starts_with("2 of 5 cases are missing:"), "{m}");
        assert!(m.contains("\n  speed_ratio=2\n  speed_ratio=5"), "{m}");
        // k = 1 and k = 4 are both in shard 2 of 3 (k mod 3 = 1).
        assert!(
            m.contains("shards 2 of 3") && m.contains("--array=2 "),
            "{m}"
        );
    }
}
