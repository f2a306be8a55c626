//! [`CaseStore`]: the finished cases of a sweep or map, one small file each, kept across runs.
//!
//! A sweep or map is a list of *cases* — a variant of the scene (its overrides) at one speed —
//! each named by a stable id made of its parameters (`speed_ratio=1.7`,
//! `stator.0.clearance_nd=0.4,speed_ratio=1.7`; [`super::CaseId`]). As soon
//! as a case is computed, its results are written to `cases/<id>.toml` (a temporary file, then
//! a rename), and the command's tables and pictures are assembled from the results the run
//! holds and from those files for the cases it did not compute, so:
//!
//! - a run killed anywhere (even by SIGKILL) loses no finished case, and the next run of the
//!   same command into the same directory computes only the cases still missing;
//! - shards of one study (`--shard i/n`, each in `shard-<i>-of-<n>/` beside the others) and a
//!   one-machine run write the same files, and `rubsim merge` assembles them the same way.
//!
//! **Files.** `cases/plan.json` ([`StorePlan`]) says whose cases these are: the command, the
//! *scene hash* ([`scene_hash`]: the resolved scene with every override, the command and the
//! program version), the scene's text and overrides (so `merge` rebuilds the same scene) and
//! the summary's model record. A run whose scene hash differs is refused (or, with `--fresh`,
//! the old cases are discarded first): cases of two scenes are never mixed. Each case file is
//! TOML ([`CaseRecord`]: exact `f64` round trip, NaN included; the numeric arrays packed, one
//! base64 string each, [`super::packed`]) ending with the line
//! `# end <FNV-1a of everything above>`; a file without a matching end line is reported as
//! half-written or damaged, naming it — never silently recomputed or read.
//!
//! **Time series.** A case whose per-speed VTK/HDF5 series are asked for (`output.per_speed`)
//! writes them into `cases/series/.tmp-<id>/`, which is synced and renamed to
//! `cases/series/<id>/` before the case file is written, stamped with the output settings it
//! was written with (`output.vtk`, `output.hdf5`, which the scene hash leaves out); the results
//! link them (`speed_<ν>/…`). A rerun keeps a finished case whose series carry this run's stamp,
//! and runs it again otherwise; series no case asks for any more are removed.
//!
//! **With the output protocol** ([`crate::output::outdir`]): the folder is written only by the holder
//! of the output directory's lock, directly (not staged): it is a journal of finished work,
//! not a result. The commit's manifest never lists it, so a commit neither moves nor removes
//! it; temporary files (`cases/.tmp-*`) left by a killed run are removed under the lock.
//!
//! **Test hooks** (compiled only with the cargo feature `fault-injection`, which the test
//! scripts turn on; without it the variables are never read). `RUBSIM_CASE_LOG=<file>` appends
//! each case id to the file when its case file is in place; `RUBSIM_KILL_AFTER_CASES=N` kills
//! the process with SIGKILL right after its N-th case file (tests of resume).

use super::case::CaseId;
use crate::analysis::SpeedResults;
use crate::error::{Error, Result};
use crate::math::{Fnv128, V2};
use crate::output::durable;
use crate::output::summary::ModelRecord;
use crate::plot::Boundary;
use crate::scene::Scene;
use serde::{Deserialize, Serialize};
use std::fs;
use std::io::ErrorKind;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The folder of the case files inside an output directory.
pub const CASES_DIR: &str = "cases";
/// The store's plan inside [`CASES_DIR`].
pub const PLAN: &str = "plan.json";
/// Version of the case-file format (2: the results carry the whirl of the full spectrum; 3:
/// the numeric arrays packed, [`super::packed`]; 4: a flagged speed's coexistence check
/// carries its two responses as periodic orbits, `coexistence.orbits`).
pub const FORMAT: u32 = 4;
/// Test hook: append every case id written to this file.
#[cfg(feature = "fault-injection")]
pub const CASE_LOG_ENV: &str = "RUBSIM_CASE_LOG";
/// Test hook: SIGKILL the process after this many case files.
#[cfg(feature = "fault-injection")]
pub const KILL_ENV: &str = "RUBSIM_KILL_AFTER_CASES";
const TMP_PREFIX: &str = ".tmp-";
const END: &str = "# end ";

/// Whose cases a store holds (`cases/plan.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StorePlan {
    /// Version of the format ([`FORMAT`]).
    pub format: u32,
    /// `"sweep"` or `"map"`.
    pub command: String,
    /// [`scene_hash`] of the scene and command.
    pub scene_hash: String,
    /// Version of the program that made the cases.
    pub rubsim_version: String,
    /// Number of cases of the whole study (every shard).
    pub cases: usize,
    /// The scene file as given on the command line.
    pub scene_file: String,
    /// The scene file's text.
    pub source: String,
    /// The overrides (`--set key=value`).
    pub overrides: Vec<String>,
    /// The `model` record of the summary (not rebuilt by `merge`).
    pub model: ModelRecord,
    /// A continuation's segments (`command` `continue`): what they continue; `None` for a
    /// sweep or map.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub continuation: Option<super::segment_spec::SegmentSpec>,
}

/// The identity of a study's cases: FNV-1a of the program version, the command and the
/// resolved scene (every override applied) as JSON — without the output choices that change
/// no case's results (`output.png`, `output.vtk`, `output.hdf5`, `output.per_speed`), so
/// asking for other pictures or time series keeps the finished cases.
pub fn scene_hash(command: &str, scene: &Scene) -> String {
    let mut s = scene.clone();
    s.output.png = true;
    s.output.vtk = None;
    s.output.hdf5 = None;
    s.output.per_speed = Default::default();
    let mut h = Fnv128::new();
    h.write(env!("CARGO_PKG_VERSION").as_bytes());
    h.write(command.as_bytes());
    h.write(serde_json::to_string(&s).unwrap_or_default().as_bytes());
    h.hex()
}

/// One finished case: its results with the heavy data the pictures draw. The numeric arrays
/// (orbit, force history, spectrum, Poincaré points) are written packed
/// ([`super::packed`]: base64 of their `f64`s, exact); the rest is plain TOML.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CaseRecord {
    /// The case id.
    pub id: CaseId,
    /// [`scene_hash`] of the study.
    pub scene_hash: String,
    /// Steady orbit / |Z0| (when kept).
    #[serde(with = "super::packed::points")]
    pub orbit_nd: Vec<V2>,
    /// Contact-force history (revolutions, force / |U|ω²) (when kept).
    #[serde(with = "super::packed::tuples")]
    pub force_history: Vec<(f64, f64)>,
    /// Spectrum (f/ω_n, amplitude / |Z0|) (when kept).
    #[serde(with = "super::packed::tuples")]
    pub spectrum: Vec<(f64, f64)>,
    /// Poincaré points / |Z0|.
    #[serde(with = "super::packed::points")]
    pub poincare_nd: Vec<V2>,
    /// The stator boundary drawn in orbit panels.
    pub boundary: Boundary,
    /// The results.
    pub results: SpeedResults,
}

impl CaseRecord {
    /// A record of `results` (its kept orbit, force history, spectrum and Poincaré points
    /// moved in; what the file does not hold dropped — the full spectrum, which a study never
    /// keeps, and the pilots' end states of its step choice — so that the record is what its
    /// file reads back as).
    pub fn new(
        id: &CaseId,
        scene_hash: &str,
        mut results: SpeedResults,
        boundary: Boundary,
    ) -> Self {
        results.full_spectrum = Vec::new();
        if let Some(c) = &mut results.step_choice {
            c.starts = Default::default();
        }
        Self {
            id: id.clone(),
            scene_hash: scene_hash.to_string(),
            orbit_nd: std::mem::take(&mut results.orbit_nd),
            force_history: std::mem::take(&mut results.force_history),
            spectrum: std::mem::take(&mut results.spectrum),
            poincare_nd: std::mem::take(&mut results.poincare_nd),
            boundary,
            results,
        }
    }

    /// The numbers of the record that must be finite, by field name: the speed, |Z0|, the
    /// clearances, the unbalance force, the extents, the 1×, ½× and ⅓× lines, the contact
    /// force, fraction and penetration, and every value of the orbit, force history, spectrum
    /// and Poincaré points. [`CaseStore::read`] refuses a file where one is not (a NaN written
    /// into a case file whose end line was then recomputed); a run never stores one.
    pub fn numbers(&self) -> Vec<(&'static str, f64)> {
        let r = &self.results;
        let mut v = vec![
            ("results.speed_ratio", r.speed_ratio),
            ("results.omega", r.omega),
            ("results.z0", r.z0),
            ("results.unbalance_force", r.unbalance_force),
            ("results.amp_1x_nd", r.amp_1x_nd),
            ("results.amp_half_nd", r.amp_half_nd),
            ("results.amp_third_nd", r.amp_third_nd),
            ("results.contact_force_max_nd", r.contact_force_max_nd),
            ("results.contact_fraction", r.contact_fraction),
            ("results.penetration_max_m", r.penetration_max_m),
        ];
        v.extend(r.clearances.iter().map(|&c| ("results.clearances", c)));
        v.extend(r.extents_nd.iter().map(|&c| ("results.extents_nd", c)));
        let pairs = |name, xs: &[V2]| {
            xs.iter()
                .flatten()
                .map(move |&x| (name, x))
                .collect::<Vec<_>>()
        };
        let tuples = |name, xs: &[(f64, f64)]| {
            xs.iter()
                .flat_map(|p| [p.0, p.1])
                .map(move |x| (name, x))
                .collect::<Vec<_>>()
        };
        v.extend(pairs("orbit_nd", &self.orbit_nd));
        v.extend(pairs("poincare_nd", &self.poincare_nd));
        v.extend(tuples("force_history", &self.force_history));
        v.extend(tuples("spectrum", &self.spectrum));
        v
    }

    /// The results with their orbit, force history, spectrum and Poincaré points, and the
    /// boundary.
    pub fn into_parts(self) -> (SpeedResults, Boundary) {
        let mut r = self.results;
        r.orbit_nd = self.orbit_nd;
        r.force_history = self.force_history;
        r.spectrum = self.spectrum;
        r.poincare_nd = self.poincare_nd;
        (r, self.boundary)
    }

    /// The case file's bytes: the record as TOML and its end line.
    ///
    /// # Errors
    /// [`Error::Output`] naming `path` when the record cannot be written as TOML.
    pub fn sealed(&self, path: &Path) -> Result<Vec<u8>> {
        let text = toml::to_string(self).map_err(|e| Error::output(path, e))?;
        Ok(seal(text))
    }
}

/// A store file's bytes: `text` and its end line `# end <FNV-1a of text>`, which
/// [`CaseStore::read_body`] checks.
pub fn seal(mut text: String) -> Vec<u8> {
    let mut h = Fnv128::new();
    h.write(text.as_bytes());
    text.push_str(&format!("{END}{}\n", h.hex()));
    text.into_bytes()
}

/// The case files of one output directory (or shard folder); see the module docs.
#[derive(Debug)]
pub struct CaseStore {
    dir: PathBuf,
    plan: StorePlan,
    written: AtomicUsize,
}

impl CaseStore {
    /// Opens (creating it when needed) the store of the output directory `out`, whose lock the
    /// caller holds. A store of another scene is refused, or emptied when `fresh`; temporary
    /// files of a killed run are removed. Returns the store and a note for the user when old
    /// cases were discarded.
    ///
    /// # Errors
    /// [`Error::Output`] naming the folder: cases of another scene (without `fresh`), a
    /// damaged plan, or an I/O failure.
    pub fn open(out: &Path, plan: StorePlan, fresh: bool) -> Result<(Self, Option<String>)> {
        let dir = out.join(CASES_DIR);
        let mut note = None;
        if dir.exists() && (dir.join(PLAN).exists() || !no_cases(&dir)) {
            let found = read_plan(&dir);
            let same = matches!(&found, Ok(p) if p.scene_hash == plan.scene_hash);
            if !same && fresh {
                fs::remove_dir_all(&dir).map_err(|e| Error::output(&dir, e))?;
                note = Some(format!(
                    "{}: discarded the cases of an earlier study (--fresh)",
                    dir.display()
                ));
            } else if !same {
                return Err(Error::output(&dir, foreign_message(&found, &plan)));
            }
        }
        fs::create_dir_all(&dir).map_err(|e| Error::output(&dir, e))?;
        remove_temporaries(&dir);
        let plan_path = dir.join(PLAN);
        if !plan_path.exists() {
            let text = serde_json::to_string_pretty(&plan).map_err(|e| Error::output(&dir, e))?;
            let name = plan_path.file_name().unwrap_or_default().to_string_lossy();
            let tmp = plan_path.with_file_name(format!("{TMP_PREFIX}{name}"));
            write_atomic(&tmp, &plan_path, text.as_bytes())?;
        }
        let store = Self {
            dir,
            plan,
            written: AtomicUsize::new(0),
        };
        Ok((store, note))
    }

    /// Opens an existing store `dir` (a `cases/` folder) for reading.
    ///
    /// # Errors
    /// [`Error::Output`] when it has no readable plan.
    pub fn read_only(dir: &Path) -> Result<Self> {
        let plan = read_plan(dir).map_err(|m| Error::output(dir.join(PLAN), m))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            plan,
            written: AtomicUsize::new(0),
        })
    }

    /// The folder of the case files.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The store's plan.
    pub fn plan(&self) -> &StorePlan {
        &self.plan
    }

    /// The file of case `id`.
    pub fn path(&self, id: &CaseId) -> PathBuf {
        self.dir.join(format!("{id}.toml"))
    }

    /// Whether case `id` is finished: its file exists and is whole (its end line matches).
    ///
    /// # Errors
    /// [`Error::Output`] naming a case file that is half-written or damaged.
    pub fn finished(&self, id: &CaseId) -> Result<bool> {
        let p = self.path(id);
        match fs::read_to_string(&p) {
            Ok(text) => body(&p, &text).map(|_| true),
            Err(e) if e.kind() == ErrorKind::NotFound => Ok(false),
            Err(e) => Err(Error::output(&p, e)),
        }
    }

    /// Writes `rec` to its case file (temporary file, then rename); may be called from
    /// several threads at once for different cases.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file.
    pub fn write(&self, rec: &CaseRecord) -> Result<()> {
        let bytes = rec.sealed(&self.path(&rec.id))?;
        self.write_sealed(&[(rec.id.clone(), bytes)])
    }

    /// Writes case files already sealed ([`CaseRecord::sealed`]), as one batch: each to a
    /// temporary file, synced, then every one renamed into place and the folder synced once —
    /// a case file that exists after a crash or a power loss is whole, and a batch costs one
    /// folder sync instead of one per case.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file; the files of the batch renamed before it stay.
    pub fn write_sealed(&self, batch: &[(CaseId, Vec<u8>)]) -> Result<()> {
        let mut tmps = Vec::with_capacity(batch.len());
        for (_, bytes) in batch {
            let tmp = self.dir.join(format!(
                "{TMP_PREFIX}{}-{}",
                std::process::id(),
                self.written.fetch_add(1, Ordering::SeqCst)
            ));
            durable::write_synced(&tmp, bytes)?;
            tmps.push(tmp);
        }
        for ((id, _), tmp) in batch.iter().zip(&tmps) {
            let p = self.path(id);
            fs::rename(tmp, &p).map_err(|e| Error::output(&p, e))?;
            test_hooks(id.as_str());
        }
        durable::sync_dir(&self.dir)
    }

    /// The text of the file of `id` above its end line ([`seal`]); `None` when it has no file.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file: unreadable, half-written or damaged.
    pub fn read_body(&self, id: &CaseId) -> Result<Option<String>> {
        let p = self.path(id);
        let text = match fs::read_to_string(&p) {
            Ok(t) => t,
            Err(e) if e.kind() == ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(Error::output(&p, e)),
        };
        body(&p, &text).map(|b| Some(b.to_string()))
    }

    /// Reads case `id`; `None` when it has no file.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file: half-written or damaged, of another case or of
    /// another scene, or a number of its results not finite ([`CaseRecord::numbers`]).
    pub fn read(&self, id: &CaseId) -> Result<Option<CaseRecord>> {
        let p = self.path(id);
        let Some(text) = self.read_body(id)? else {
            return Ok(None);
        };
        let rec: CaseRecord = toml::from_str(&text)
            .map_err(|e| Error::output(&p, format!("damaged case file: {}", e.message())))?;
        if rec.id != *id {
            return Err(Error::output(
                &p,
                format!("holds case `{}`, not `{id}`", rec.id),
            ));
        }
        if rec.scene_hash != self.plan.scene_hash {
            return Err(Error::output(
                &p,
                format!(
                    "is a case of another scene (hash {}, this study's is {})",
                    rec.scene_hash, self.plan.scene_hash
                ),
            ));
        }
        if let Some((field, x)) = rec.numbers().into_iter().find(|(_, x)| !x.is_finite()) {
            return Err(Error::output(
                &p,
                format!(
                    "damaged case file: `{field}` holds {x}, and a case's results are finite \
                     numbers; delete the file to have the case computed again"
                ),
            ));
        }
        Ok(Some(rec))
    }
}

/// The folder, inside [`CASES_DIR`], of the per-speed VTK/HDF5 time series kept with their
/// cases (`cases/series/<id>/`, the files under the names they have in the results).
pub const SERIES_DIR: &str = "series";
/// The file in a kept series folder that names the output settings it was written with.
const SERIES_STAMP: &str = ".stamp";

impl CaseStore {
    /// The folder of case `id`'s kept time series.
    pub fn series_path(&self, id: &CaseId) -> PathBuf {
        self.dir.join(SERIES_DIR).join(id.as_str())
    }

    /// A new empty folder in which to write case `id`'s time series; [`CaseStore::keep_series`]
    /// puts it in place. A folder left by a killed run is removed first.
    ///
    /// # Errors
    /// [`Error::Output`] naming the folder.
    pub fn stage_series(&self, id: &CaseId) -> Result<PathBuf> {
        let p = self.dir.join(SERIES_DIR).join(format!("{TMP_PREFIX}{id}"));
        if p.exists() {
            fs::remove_dir_all(&p).map_err(|e| Error::output(&p, e))?;
        }
        fs::create_dir_all(&p).map_err(|e| Error::output(&p, e))?;
        Ok(p)
    }

    /// Puts the series staged for case `id` in place, stamped with `stamp` (the output settings
    /// they were written with): its files and folders synced, then renamed over an older
    /// series of the case. Call it before the case file is written, so that a finished case
    /// whose series were asked for has them.
    ///
    /// # Errors
    /// [`Error::Output`] naming the folder.
    pub fn keep_series(&self, id: &CaseId, stamp: &str) -> Result<()> {
        let tmp = self.dir.join(SERIES_DIR).join(format!("{TMP_PREFIX}{id}"));
        let stamp_path = tmp.join(SERIES_STAMP);
        fs::write(&stamp_path, stamp).map_err(|e| Error::output(&stamp_path, e))?;
        let mut dirs = vec![tmp.clone()];
        for f in files_below(&tmp)? {
            let p = tmp.join(&f);
            durable::sync_file(&p)?;
            if let Some(d) = p.parent() {
                if !dirs.iter().any(|x| x == d) {
                    dirs.push(d.to_path_buf());
                }
            }
        }
        for d in &dirs {
            durable::sync_dir(d)?;
        }
        let fin = self.series_path(id);
        if fin.exists() {
            fs::remove_dir_all(&fin).map_err(|e| Error::output(&fin, e))?;
        }
        fs::rename(&tmp, &fin).map_err(|e| Error::output(&fin, e))?;
        durable::sync_dir(&self.dir.join(SERIES_DIR))
    }

    /// The files of case `id`'s kept series, relative to its folder, when it has series written
    /// with the output settings `stamp`; `None` otherwise (none kept, or other settings).
    ///
    /// # Errors
    /// [`Error::Output`] naming the folder when it cannot be read.
    pub fn series_files(&self, id: &CaseId, stamp: &str) -> Result<Option<Vec<String>>> {
        let dir = self.series_path(id);
        match fs::read_to_string(dir.join(SERIES_STAMP)) {
            Ok(s) if s == stamp => {}
            _ => return Ok(None),
        }
        let mut files = files_below(&dir)?;
        files.retain(|f| f != SERIES_STAMP);
        Ok(Some(files))
    }

    /// Removes the kept series of every case not in `keep`, and the series staged by a killed
    /// run: series nobody asks for any more do not stay hidden in the store.
    ///
    /// # Errors
    /// [`Error::Output`] naming the folder.
    pub fn prune_series(&self, keep: &[CaseId]) -> Result<()> {
        let dir = self.dir.join(SERIES_DIR);
        let Ok(rd) = fs::read_dir(&dir) else {
            return Ok(());
        };
        for e in rd.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            if !keep.iter().any(|k| k.as_str() == name) {
                fs::remove_dir_all(e.path()).map_err(|err| Error::output(e.path(), err))?;
            }
        }
        if keep.is_empty() {
            let _ = fs::remove_dir(&dir);
        }
        Ok(())
    }
}

/// The files below `dir`, relative to it with `/` separators, sorted.
fn files_below(dir: &Path) -> Result<Vec<String>> {
    let mut out = Vec::new();
    let mut stack = vec![PathBuf::new()];
    while let Some(rel) = stack.pop() {
        let here = dir.join(&rel);
        for e in fs::read_dir(&here).map_err(|e| Error::output(&here, e))? {
            let e = e.map_err(|err| Error::output(&here, err))?;
            let r = rel.join(e.file_name());
            let ft = e.file_type().map_err(|err| Error::output(e.path(), err))?;
            if ft.is_dir() {
                stack.push(r);
            } else if ft.is_file() {
                out.push(r.to_string_lossy().replace('\\', "/"));
            }
        }
    }
    out.sort();
    Ok(out)
}

/// The text of a case file above its end line, when the end line matches it.
fn body<'a>(p: &Path, text: &'a str) -> Result<&'a str> {
    let half = |why: &str| {
        Error::output(
            p,
            format!(
                "half-written or damaged case file ({why}); delete it to have the case \
                 computed again"
            ),
        )
    };
    let t = text.strip_suffix('\n').ok_or_else(|| half("no end line"))?;
    let (head, end) = t
        .rsplit_once('\n')
        .map_or(("", t), |(a, b)| (&t[..a.len() + 1], b));
    let hex = end.strip_prefix(END).ok_or_else(|| half("no end line"))?;
    let mut h = Fnv128::new();
    h.write(head.as_bytes());
    if h.hex() != hex {
        return Err(half("its end line does not match its content"));
    }
    Ok(head)
}

/// The plan of the store `dir`, or why it cannot be read.
fn read_plan(dir: &Path) -> std::result::Result<StorePlan, String> {
    let p = dir.join(PLAN);
    let text = fs::read_to_string(&p).map_err(|e| match e.kind() {
        ErrorKind::NotFound => format!("{} is missing", p.display()),
        _ => format!("{}: {e}", p.display()),
    })?;
    let plan: StorePlan =
        serde_json::from_str(&text).map_err(|e| format!("{}: damaged plan: {e}", p.display()))?;
    if plan.format != FORMAT {
        return Err(format!(
            "{}: case format {} (this rubsim reads and writes format {FORMAT} only): the \
             cases were written by {} rubsim {}; use a fresh output directory, or --fresh \
             to discard them",
            p.display(),
            plan.format,
            if plan.format < FORMAT {
                "an older"
            } else {
                "another"
            },
            plan.rubsim_version
        ));
    }
    Ok(plan)
}

/// Why a store is not this study's.
fn foreign_message(found: &std::result::Result<StorePlan, String>, plan: &StorePlan) -> String {
    let what = match found {
        Ok(p) => {
            format!(
                "holds the cases of another scene (`rubsim {}` of {}{}, scene hash {})",
                p.command,
                p.scene_file,
                if p.overrides.is_empty() {
                    String::new()
                } else {
                    format!(" with --set {}", p.overrides.join(" --set "))
                },
                p.scene_hash
            ) + &continuation_differs(p, plan)
        }
        Err(why) => format!("holds cases this run cannot identify ({why})"),
    };
    format!(
        "{what}; this run's scene hash is {}. Cases of two scenes are never mixed: rerun with \
         --fresh to discard them, or choose another --out",
        plan.scene_hash
    )
}

/// How the continuation in segments of `found` differs from `plan`'s, when both are one and
/// they differ (the scene hash includes it); empty otherwise.
fn continuation_differs(found: &StorePlan, plan: &StorePlan) -> String {
    match (&found.continuation, &plan.continuation) {
        (Some(a), Some(b)) if a != b => format!(
            ", continuing {} over {:?} at period {} in {} segments where this run continues {} over {:?} at period {} in {}",
            a.key.as_deref().unwrap_or("speed_ratio"),
            a.range,
            a.period,
            a.segments,
            b.key.as_deref().unwrap_or("speed_ratio"),
            b.range,
            b.period,
            b.segments
        ),
        _ => String::new(),
    }
}

/// True when `dir` holds no case file (e.g. a run killed before it wrote its plan).
fn no_cases(dir: &Path) -> bool {
    fs::read_dir(dir).map_or(true, |rd| {
        !rd.flatten()
            .any(|e| e.file_name().to_string_lossy().ends_with(".toml"))
    })
}

/// Removes the temporary files of killed runs (only the lock holder calls this).
fn remove_temporaries(dir: &Path) {
    let Ok(rd) = fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        if e.file_name().to_string_lossy().starts_with(TMP_PREFIX) {
            let _ = fs::remove_file(e.path());
        }
    }
}

/// Writes `bytes` to `path` through the temporary file `tmp` (in the same folder, named with
/// [`TMP_PREFIX`] so an interrupted write is swept away), synced, renamed, the folder synced
/// ([`durable::write_atomic`]): a case file that exists after a power loss is whole.
fn write_atomic(tmp: &Path, path: &Path, bytes: &[u8]) -> Result<()> {
    durable::write_atomic(tmp, path, bytes, || {})
}

/// The test hooks of the module docs, after the case file of `id` is in place.
#[cfg(feature = "fault-injection")]
fn test_hooks(id: &str) {
    use std::io::Write;
    if let Some(log) = std::env::var_os(CASE_LOG_ENV) {
        if let Ok(mut f) = fs::OpenOptions::new().append(true).create(true).open(log) {
            let _ = f.write_all(format!("{id}\n").as_bytes());
        }
    }
    static DONE: AtomicUsize = AtomicUsize::new(0);
    let limit = std::env::var(KILL_ENV)
        .ok()
        .and_then(|v| v.parse::<usize>().ok());
    if let Some(n) = limit {
        if DONE.fetch_add(1, Ordering::SeqCst) + 1 >= n {
            eprintln!("rubsim: test hook {KILL_ENV}={n}: killing the process");
            // SAFETY: raise(2) with a valid signal number has no memory-safety preconditions.
            unsafe {
                libc::raise(libc::SIGKILL);
            }
        }
    }
}

/// Nothing after a case file: the test hooks are not compiled in.
#[cfg(not(feature = "fault-injection"))]
fn test_hooks(_id: &str) {}

#[cfg(test)]
mod tests {
    use super::*;

    fn sealed(body: &str) -> String {
        let mut h = Fnv128::new();
        h.write(body.as_bytes());
        format!("{body}{END}{}\n", h.hex())
    }

    #[test]
    fn a_case_file_is_whole_only_with_its_matching_end_line() {
        let p = Path::new("cases/x.toml");
        let text = sealed("id = \"x\"\nvalue = 1.5\n");
        assert_eq!(body(p, &text).unwrap(), "id = \"x\"\nvalue = 1.5\n");
        // Cut anywhere (at a line end too), or changed: named as half-written or damaged.
        for cut in [0, 5, 12, text.len() - 1] {
            let e = body(p, &text[..cut]).unwrap_err().to_string();
            assert!(
                e.contains("cases/x.toml") && e.contains("half-written"),
                "{e}"
            );
        }
        let changed = text.replace("1.5", "2.5");
        assert!(body(p, &changed).is_err());
    }

    #[test]
    fn a_store_killed_before_its_plan_is_reused_and_another_scene_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let plan = |hash: &str| StorePlan {
            format: FORMAT,
            command: "sweep".into(),
            scene_hash: hash.into(),
            rubsim_version: "0".into(),
            cases: 1,
            scene_file: "s.toml".into(),
            source: String::new(),
            overrides: Vec::new(),
            model: ModelRecord {
                omega_n_rad_s: 1.0,
                rotor: String::new(),
            },
            continuation: None,
        };
        // A folder with only a temporary file: a run killed before its plan was in place.
        fs::create_dir_all(tmp.path().join(CASES_DIR)).unwrap();
        fs::write(tmp.path().join(CASES_DIR).join(".tmp-plan.json"), "{").unwrap();
        let (s, note) = CaseStore::open(tmp.path(), plan("a"), false).unwrap();
        assert!(note.is_none());
        assert!(!s.dir().join(".tmp-plan.json").exists());
        assert_eq!(CaseStore::read_only(s.dir()).unwrap().plan(), &plan("a"));
        let e = CaseStore::open(tmp.path(), plan("b"), false).unwrap_err();
        assert!(e.to_string().contains("--fresh"), "{e}");
        let (_, note) = CaseStore::open(tmp.path(), plan("b"), true).unwrap();
        assert!(note.unwrap().contains("discarded"));
        // A store of an older case format is refused, naming its plan and what to do.
        let old = StorePlan {
            format: FORMAT - 1,
            ..plan("b")
        };
        let text = serde_json::to_string(&old).unwrap();
        fs::write(tmp.path().join(CASES_DIR).join(PLAN), text).unwrap();
        let e = CaseStore::open(tmp.path(), plan("b"), false)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("plan.json") && e.contains("older rubsim") && e.contains("fresh output"),
            "{e}"
        );
    }
}
