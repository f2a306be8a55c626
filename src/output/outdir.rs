//! [`OutDir`]: the output directory protocol — lock, staging folder, commit journal, manifest.
//!
//! **Invariant.** At every instant, a directory that holds `summary.json` (the run's *marker*,
//! at the top level; a run writes exactly one) holds exactly one run's complete results: the
//! files its manifest lists, all from that run, and none of an earlier run.
//!
//! **Files of the protocol** (all start with `.rubsim-`, none is ever a result):
//! - `.rubsim-lock`: every run holds an exclusive lock on it (`flock(2)`) from
//!   [`OutDir::prepare`] to the end of [`OutDir::commit`] (or its drop). A second run into the
//!   same directory fails at once. Since only the lock holder writes, anything else of the
//!   protocol found by the lock holder belongs to a dead run — whatever its PID namespace.
//! - `.rubsim-partial-<pid>/`: the staging folder; every result is written there first.
//! - `.rubsim-files`: the manifest of the last committed run ([`super::manifest`]).
//! - `.rubsim-commit`: the commit journal, naming the staging folder being committed.
//!
//! **Commit** (each step is a rename or a removal, in this order):
//! 0. the new manifest is written into the staging folder, and every destination checked (no
//!    symbolic link, no directory where a file goes) — a failure here changes nothing; every
//!    staged file and folder is synced to the disk (`fsync`);
//! 1. the journal is written (temporary file, synced, renamed; the directory synced) — the
//!    commit point;
//! 2. the old `summary.json` is removed: the directory stops looking complete;
//! 3. the files of the old manifest that the new run does not produce are removed, and the
//!    folders they leave empty;
//! 4. the new manifest is renamed into place;
//! 5. every new file is renamed into place;
//!    then every folder that gained or lost an entry is synced;
//! 6. the new `summary.json` is renamed into place, last, and the directory synced;
//! 7. the journal is removed (the directory synced) and the staging folder.
//!
//! Steps 2–7 are idempotent and keyed on what is still in the staging folder, so a commit
//! killed anywhere is rolled forward by the next [`OutDir::prepare`] when its staging folder
//! is complete, and discarded otherwise (the directory then holds no `summary.json`, or the
//! previous run's intact results when the kill came before step 2); a one-line note says which.
//! A commit that fails after its commit point (an I/O error) removes its journal and leaves a
//! directory without `summary.json`. The syncs ([`super::durable`]) extend this to a power
//! loss: the data of every file is on the disk before its name can appear beside a
//! `summary.json`, and `summary.json` is on the disk before the journal goes.
//!
//! **Test hook** (compiled only with the cargo feature `fault-injection`, which the test scripts
//! turn on; without it the variable is never read). With `RUBSIM_FAULT_AFTER_STEPS=N` in the
//! environment the process aborts (as if killed) before the commit step N + 1 (every rename and
//! removal of steps 1–7 counts, the temporary journal write included), so tests can kill a
//! commit at every point.

use super::durable;
use super::manifest::{check_owner, check_relative, parse_manifest, MANIFEST, PROTOCOL_PREFIX};
use crate::error::{Error, Result};
use std::collections::BTreeSet;
use std::fs::{self, File, TryLockError};
use std::io::{ErrorKind, Write};
use std::path::{Path, PathBuf};

/// The run's marker: the top-level file written last; its presence means "complete".
pub const MARKER: &str = "summary.json";
/// The lock file every run holds for its whole life.
pub const LOCK: &str = ".rubsim-lock";
/// The commit journal, present only while a commit is under way (or was killed).
pub const JOURNAL: &str = ".rubsim-commit";
/// Environment variable of the fault-injection test hook (see the module docs).
#[cfg(feature = "fault-injection")]
pub const FAULT_ENV: &str = "RUBSIM_FAULT_AFTER_STEPS";
const STAGING_PREFIX: &str = ".rubsim-partial-";

/// An output directory with a staging area, locked for the life of the value.
#[derive(Debug)]
pub struct OutDir {
    dir: PathBuf,
    staging: PathBuf,
    files: Vec<String>,
    notes: Vec<String>,
    lock: File,
    committed: bool,
    created: bool,
}

impl OutDir {
    /// Creates `dir` if needed, takes its lock, completes or discards a commit an earlier run
    /// left unfinished, removes staging folders of dead runs and checks that files can be
    /// written there. Notes about what it found (a recovered commit, manifest entries that
    /// were ignored) are in [`OutDir::notes`].
    ///
    /// # Errors
    /// [`Error::Output`] when `dir` is not a directory, cannot be created or written, or
    /// another run holds its lock.
    /// A directory that exists, is not empty and holds none of the protocol's files (a folder
    /// rubsim did not make) is refused, as is the file system's root: see
    /// [`OutDir::prepare_forced`].
    pub fn prepare(dir: &Path) -> Result<Self> {
        Self::open(dir, false)
    }

    /// [`OutDir::prepare`] into a directory that may be someone else's (the command line's
    /// `--force`): an existing, non-empty directory without the protocol's files is written
    /// into, its files of the results' names replaced. The file system's root is still refused.
    ///
    /// # Errors
    /// As [`OutDir::prepare`].
    pub fn prepare_forced(dir: &Path) -> Result<Self> {
        Self::open(dir, true)
    }

    fn open(dir: &Path, force: bool) -> Result<Self> {
        if dir.exists() && !dir.is_dir() {
            return Err(Error::output(
                dir,
                "output path exists and is not a directory",
            ));
        }
        check_owner(dir, force)?;
        let created = !dir.exists();
        let lock = acquire_lock(dir)?;
        let mut me = Self {
            dir: dir.to_path_buf(),
            staging: dir.join(format!("{STAGING_PREFIX}{}", std::process::id())),
            files: Vec::new(),
            notes: Vec::new(),
            lock,
            committed: false,
            created,
        };
        recover(dir, &mut me.notes)?;
        remove_leftovers(dir, &mut me.notes);
        me.notes.extend(manifest_warnings(dir));
        let probe = me.staging.join(".probe");
        fs::create_dir_all(&me.staging)
            .and_then(|()| File::create(&probe))
            .and_then(|mut f| f.write_all(b"probe"))
            .map_err(|e| Error::output(dir, format!("output directory is not writable: {e}")))?;
        let _ = fs::remove_file(&probe);
        Ok(me)
    }

    /// The final directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// One-line notes from [`OutDir::prepare`] for the user (a recovered or discarded
    /// commit, removed staging folders, manifest entries ignored as not confined).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// Staging path of a file to be produced as `name` (relative, may contain `/`).
    ///
    /// # Errors
    /// [`Error::Output`] when `name` is not a confined relative path or its folder cannot be
    /// created.
    pub fn stage(&mut self, name: &str) -> Result<PathBuf> {
        check_relative(name).map_err(|why| Error::output(self.dir.join(name), why))?;
        let p = self.staging.join(name);
        if let Some(parent) = p.parent() {
            fs::create_dir_all(parent).map_err(|e| Error::output(parent, e))?;
        }
        if !self.files.iter().any(|f| f == name) {
            self.files.push(name.to_string());
        }
        Ok(p)
    }

    /// The staging folder: files written below it and [`OutDir::adopt`]ed are moved into place
    /// by [`OutDir::commit`] (for writers that run on other threads, e.g. per-speed results).
    pub fn staging_dir(&self) -> &Path {
        &self.staging
    }

    /// Registers `name` (relative), already written below [`OutDir::staging_dir`], for commit.
    ///
    /// # Errors
    /// [`Error::Output`] when `name` is not confined or was not written.
    pub fn adopt(&mut self, name: &str) -> Result<()> {
        check_relative(name).map_err(|why| Error::output(self.dir.join(name), why))?;
        if !self.staging.join(name).is_file() {
            return Err(Error::output(
                self.dir.join(name),
                "was not written to the staging folder",
            ));
        }
        if !self.files.iter().any(|f| f == name) {
            self.files.push(name.to_string());
        }
        Ok(())
    }

    /// Writes bytes to `name` in the staging area (synced to the disk by the commit).
    ///
    /// # Errors
    /// [`Error::Output`] naming the file.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<()> {
        let p = self.stage(name)?;
        fs::write(&p, bytes).map_err(|e| Error::output(self.dir.join(name), e))
    }

    /// Commits the staged files (see the module docs for the steps): afterwards the directory
    /// holds exactly this run's files, `summary.json` moved last. Returns the final paths.
    ///
    /// # Errors
    /// [`Error::Output`] when no `summary.json` was staged, a destination is a directory or
    /// crosses a symbolic link (nothing changed then), or a rename fails (the directory is then
    /// left without `summary.json`).
    pub fn commit(mut self) -> Result<Vec<PathBuf>> {
        if !self.files.iter().any(|f| f == MARKER) {
            return Err(Error::output(
                self.dir.join(MARKER),
                "was not written, and a run's results are complete only with it",
            ));
        }
        let mut names = self.files.clone();
        names.sort();
        self.preflight(&names)?;
        let staged = self.staging.join(MANIFEST);
        fs::write(&staged, names.join("\n") + "\n").map_err(|e| Error::output(&staged, e))?;
        sync_staged(&self.staging, &names)?;
        let staging_name = self.staging.file_name().unwrap_or_default();
        let mut text = staging_name.to_string_lossy().into_owned();
        text.push('\n');
        write_atomic(&self.dir.join(JOURNAL), text.as_bytes())?;
        if let Err(e) = roll_forward(&self.dir, &self.staging) {
            let _ = fs::remove_file(self.dir.join(JOURNAL));
            return Err(e);
        }
        self.committed = true;
        names.sort_by_key(|n| n == MARKER);
        Ok(names.iter().map(|n| self.dir.join(n)).collect())
    }

    /// Refuses, before anything changes, a destination that crosses a symbolic link or a
    /// non-directory, or that is a directory (or a link) where a file must go.
    fn preflight(&self, names: &[String]) -> Result<()> {
        let old = fs::read_to_string(self.dir.join(MANIFEST))
            .map(|t| parse_manifest(&t).entries)
            .unwrap_or_default();
        for name in names {
            let to = self.dir.join(name);
            match on_disk_confined(&self.dir, name) {
                Ok(()) => {}
                // An old file where a folder of the new run goes is removed in step 3.
                Err(why)
                    if why == CROSSES_FILE && crosses_only_old_files(&self.dir, name, &old) => {}
                Err(why) => {
                    return Err(Error::output(
                        &to,
                        format!("cannot be written: the path {why}"),
                    ))
                }
            }
        }
        Ok(())
    }
}

impl Drop for OutDir {
    fn drop(&mut self) {
        if self.committed {
            return;
        }
        let _ = fs::remove_dir_all(&self.staging);
        if self.created {
            // A directory this run created and leaves empty is removed, lock file included
            // (unlinked while locked: a run that opened it meanwhile sees it replaced, retries).
            #[cfg(unix)]
            {
                let only_lock = fs::read_dir(&self.dir)
                    .map(|rd| rd.flatten().all(|e| e.file_name() == LOCK))
                    .unwrap_or(false);
                if only_lock && is_same_file(&self.lock, &self.dir.join(LOCK)) {
                    let _ = fs::remove_file(self.dir.join(LOCK));
                }
            }
            let _ = fs::remove_dir(&self.dir);
        }
    }
}

/// How long a held lock is retried before it is reported busy: a process that spawns a child
/// (gmsh, or another thread's command) lends the child a copy of every open descriptor between
/// fork and exec — `O_CLOEXEC` closes it only at the exec — so a lock this process has just
/// released can stay held for that instant; a run holding it lasts far longer.
const LOCK_PATIENCE: std::time::Duration = std::time::Duration::from_millis(250);

/// Opens `dir/.rubsim-lock` (creating `dir` and the file) and locks it exclusively, waiting
/// at most [`LOCK_PATIENCE`]; retries when the file was replaced between open and lock.
fn acquire_lock(dir: &Path) -> Result<File> {
    let t0 = std::time::Instant::now();
    loop {
        match try_acquire_lock(dir) {
            Err(Busy::Held) if t0.elapsed() < LOCK_PATIENCE => {
                std::thread::sleep(std::time::Duration::from_millis(10));
            }
            Err(Busy::Held) => {
                return Err(Error::output(
                    dir,
                    format!(
                        "another rubsim run is writing to this output directory (it holds \
                         {LOCK}); wait for it to finish or choose another --out"
                    ),
                ))
            }
            Err(Busy::Failed(e)) => return Err(e),
            Ok(f) => return Ok(f),
        }
    }
}

/// Why the lock was not taken.
enum Busy {
    /// Another open file description holds it.
    Held,
    /// Any other error, as reported.
    Failed(Error),
}

/// One attempt of [`acquire_lock`].
fn try_acquire_lock(dir: &Path) -> std::result::Result<File, Busy> {
    let path = dir.join(LOCK);
    for _ in 0..16 {
        fs::create_dir_all(dir).map_err(|e| {
            Busy::Failed(Error::output(
                dir,
                format!("cannot create output directory: {e}"),
            ))
        })?;
        let f = fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(|e| {
                Busy::Failed(Error::output(
                    dir,
                    format!("output directory is not writable (its lock file {LOCK}): {e}"),
                ))
            })?;
        match f.try_lock() {
            Ok(()) => {}
            Err(TryLockError::WouldBlock) => return Err(Busy::Held),
            Err(TryLockError::Error(e)) => {
                return Err(Busy::Failed(Error::output(
                    &path,
                    format!("cannot lock the output directory: {e}"),
                )))
            }
        }
        if is_same_file(&f, &path) {
            return Ok(f);
        }
    }
    Err(Busy::Failed(Error::output(
        &path,
        "cannot lock the output directory: its lock file keeps being replaced",
    )))
}

/// True when the open file `f` is the file at `path` (same device and inode).
#[cfg(unix)]
fn is_same_file(f: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (f.metadata(), fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

/// Elsewhere a locked file cannot be removed, so the file at `path` is the one locked.
#[cfg(not(unix))]
fn is_same_file(_: &File, path: &Path) -> bool {
    path.exists()
}

/// Counts a commit step; with the test hook set, aborts the process before step N + 1.
#[cfg(feature = "fault-injection")]
fn fault_point() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::OnceLock;
    static LIMIT: OnceLock<Option<usize>> = OnceLock::new();
    static DONE: AtomicUsize = AtomicUsize::new(0);
    let limit = *LIMIT.get_or_init(|| std::env::var(FAULT_ENV).ok()?.parse().ok());
    if let Some(n) = limit {
        if DONE.fetch_add(1, Ordering::SeqCst) >= n {
            eprintln!("rubsim: test hook {FAULT_ENV}={n}: aborting the commit here");
            std::process::abort();
        }
    }
}

/// A commit step (nothing to count: the fault-injection hook is not compiled in).
#[cfg(not(feature = "fault-injection"))]
fn fault_point() {}

/// A commit step: renames `from` to `to`.
fn rename(from: &Path, to: &Path) -> Result<()> {
    fault_point();
    fs::rename(from, to).map_err(|e| Error::output(to, e))
}

/// A commit step: removes the file `p` if it exists.
fn remove_if_present(p: &Path) -> Result<()> {
    fault_point();
    match fs::remove_file(p) {
        Err(e) if e.kind() != ErrorKind::NotFound => Err(Error::output(p, e)),
        _ => Ok(()),
    }
}

/// Writes `bytes` to `path` through a synced temporary file and a rename (one commit step:
/// the fault point sits between the two), the directory synced after.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    durable::write_atomic(&PathBuf::from(tmp), path, bytes, fault_point)
}

/// Syncs the staged files `names` and the manifest, then every folder of the staging tree
/// holding them (deepest first), before the commit point: a commit rolled forward after a
/// power loss moves only data that reached the disk.
fn sync_staged(staging: &Path, names: &[String]) -> Result<()> {
    let mut dirs = BTreeSet::new();
    for name in names.iter().map(String::as_str).chain([MANIFEST]) {
        let p = staging.join(name);
        // A name staged but never written is not committed either (`roll_forward`).
        if !p.is_file() {
            continue;
        }
        durable::sync_file(&p)?;
        dirs.extend(
            p.ancestors()
                .skip(1)
                .take_while(|a| a.starts_with(staging))
                .map(Path::to_path_buf),
        );
    }
    dirs.iter().rev().try_for_each(|d| durable::sync_dir(d))
}

/// Steps 2–7 of the commit of `staging` into `dir`, each skipped when already done.
fn roll_forward(dir: &Path, staging: &Path) -> Result<()> {
    let staged = staging.join(MANIFEST);
    let manifest_staged = staged.is_file();
    let list = if manifest_staged {
        staged.clone()
    } else {
        dir.join(MANIFEST)
    };
    let text = fs::read_to_string(&list).map_err(|e| Error::output(&list, e))?;
    let new = parse_manifest(&text).entries;
    let marker_staged = staging.join(MARKER).is_file();
    if marker_staged {
        remove_if_present(&dir.join(MARKER))?;
    }
    if manifest_staged {
        if let Ok(old) = fs::read_to_string(dir.join(MANIFEST)) {
            for name in parse_manifest(&old).entries {
                if !new.contains(&name) && on_disk_confined(dir, &name).is_ok() {
                    remove_if_present(&dir.join(&name))?;
                    prune_empty_parents(dir, &name);
                }
            }
        }
        rename(&staged, &dir.join(MANIFEST))?;
    }
    // Every folder that gains or loses an entry: synced before the marker goes in.
    let mut touched = BTreeSet::from([dir.to_path_buf()]);
    for name in new.iter().filter(|n| *n != MARKER) {
        let from = staging.join(name);
        if fs::symlink_metadata(&from).is_ok() {
            let to = dir.join(name);
            if let Some(parent) = to.parent() {
                fs::create_dir_all(parent).map_err(|e| Error::output(parent, e))?;
                touched.extend(
                    parent
                        .ancestors()
                        .take_while(|a| a.starts_with(dir))
                        .map(Path::to_path_buf),
                );
            }
            rename(&from, &to)?;
        }
    }
    touched
        .iter()
        .rev()
        .try_for_each(|d| durable::sync_dir(d))?;
    if marker_staged {
        rename(&staging.join(MARKER), &dir.join(MARKER))?;
        durable::sync_dir(dir)?;
    }
    remove_if_present(&dir.join(JOURNAL))?;
    durable::sync_dir(dir)?;
    fault_point();
    let _ = fs::remove_dir_all(staging);
    Ok(())
}

/// Removes the folders between `dir/name` and `dir` that are empty (deepest first).
fn prune_empty_parents(dir: &Path, name: &str) {
    let mut p = Path::new(name).parent();
    while let Some(rel) = p.filter(|r| !r.as_os_str().is_empty()) {
        if fs::remove_dir(dir.join(rel)).is_err() {
            break;
        }
        p = rel.parent();
    }
}

const CROSSES_FILE: &str = "crosses a file that is not a directory";

/// Checks on disk that `dir/name` (a confined relative path) stays inside `dir`: no folder on
/// the way is a symbolic link or a file, and the path itself (when it exists) is neither a
/// link nor a directory. Missing parts are fine.
fn on_disk_confined(dir: &Path, name: &str) -> std::result::Result<(), &'static str> {
    let mut p = dir.to_path_buf();
    let parts: Vec<&str> = name.split('/').collect();
    for (i, part) in parts.iter().enumerate() {
        p.push(part);
        let Ok(m) = fs::symlink_metadata(&p) else {
            return Ok(());
        };
        let last = i + 1 == parts.len();
        if m.file_type().is_symlink() {
            return Err(if last {
                "is a symbolic link"
            } else {
                "crosses a symbolic link"
            });
        }
        if last && m.is_dir() {
            return Err("is a directory");
        }
        if !last && !m.is_dir() {
            return Err(CROSSES_FILE);
        }
    }
    Ok(())
}

/// True when every non-directory on the way to `dir/name` is a file of the old manifest
/// (step 3 removes it before step 5 creates the folder).
fn crosses_only_old_files(dir: &Path, name: &str, old: &[String]) -> bool {
    let parts: Vec<&str> = name.split('/').collect();
    (1..parts.len()).all(|k| {
        let rel = parts[..k].join("/");
        fs::symlink_metadata(dir.join(&rel)).map_or(true, |m| m.is_dir() || old.contains(&rel))
    })
}

/// The staging folder `name` names, when it is a plain `.rubsim-partial-…` name.
fn staging_named(dir: &Path, name: &str) -> Option<PathBuf> {
    (name.starts_with(STAGING_PREFIX)
        && !name.contains(['/', '\\', '\0'])
        && name != STAGING_PREFIX)
        .then(|| dir.join(name))
}

/// True when `staging` holds (or, once its manifest was moved, `dir` holds) every file of
/// the commit, `summary.json` included.
fn complete(dir: &Path, staging: &Path) -> bool {
    let staged = staging.join(MANIFEST);
    let moved = !staged.is_file();
    let text = fs::read_to_string(if moved { dir.join(MANIFEST) } else { staged });
    let Ok(text) = text else {
        return false;
    };
    let m = parse_manifest(&text);
    m.rejected.is_empty()
        && m.entries.iter().any(|e| e == MARKER)
        && m.entries
            .iter()
            .all(|n| staging.join(n).is_file() || (moved && dir.join(n).is_file()))
}

/// Completes (rolls forward) or discards a commit that a dead run left in `dir`.
fn recover(dir: &Path, notes: &mut Vec<String>) -> Result<()> {
    let journal = dir.join(JOURNAL);
    let text = match fs::read_to_string(&journal) {
        Ok(t) => t,
        Err(e) if e.kind() == ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(Error::output(&journal, format!("cannot read it: {e}"))),
    };
    let staging = staging_named(dir, text.trim_end_matches('\n'));
    let done = staging
        .filter(|s| s.is_dir() && complete(dir, s))
        .is_some_and(|s| roll_forward(dir, &s).is_ok());
    if done {
        notes.push(format!(
            "{}: completed the commit of an earlier run that was interrupted",
            dir.display()
        ));
    } else {
        let _ = fs::remove_file(&journal);
        notes.push(format!(
            "{}: discarded the commit of an earlier run that was interrupted ({})",
            dir.display(),
            if dir.join(MARKER).exists() {
                "the previous results are intact"
            } else {
                "no complete results are left"
            }
        ));
    }
    Ok(())
}

/// Removes what dead runs left (staging folders, temporary protocol files); only called by
/// the lock holder, so none of it belongs to a live run.
fn remove_leftovers(dir: &Path, notes: &mut Vec<String>) {
    let Ok(rd) = fs::read_dir(dir) else {
        return;
    };
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with(STAGING_PREFIX) {
            if fs::remove_dir_all(e.path()).is_ok() {
                notes.push(format!(
                    "{}: removed the staging folder {name} of a run that did not finish",
                    dir.display()
                ));
            }
        } else if name.starts_with(PROTOCOL_PREFIX) && name.ends_with(".tmp") {
            let _ = fs::remove_file(e.path());
        }
    }
}

/// A warning for every manifest entry that is ignored because it is not confined to `dir`
/// (by its text or on disk), naming the manifest and the line.
fn manifest_warnings(dir: &Path) -> Vec<String> {
    let path = dir.join(MANIFEST);
    let Ok(text) = fs::read_to_string(&path) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (i, line) in text.split('\n').enumerate() {
        if line.is_empty() {
            continue;
        }
        let why = match check_relative(line) {
            Err(why) => why,
            Ok(()) => match on_disk_confined(dir, line) {
                Err(why) => why,
                Ok(()) => continue,
            },
        };
        out.push(format!(
            "{}:{}: ignored the entry {:?}: it {why}; it is not removed",
            path.display(),
            i + 1,
            line
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn rerun_replaces_results_and_failed_run_leaves_nothing() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("o");
        let mut o = OutDir::prepare(&dir).unwrap();
        o.write("a.csv", b"1").unwrap();
        o.write("sub/b.png", b"2").unwrap();
        o.write(MARKER, b"{}").unwrap();
        o.commit().unwrap();
        assert!(dir.join("sub/b.png").exists());
        // A rerun that produces fewer files removes the stale one and its empty folder.
        let mut o = OutDir::prepare(&dir).unwrap();
        o.write("a.csv", b"3").unwrap();
        o.write(MARKER, b"{}").unwrap();
        o.commit().unwrap();
        assert!(!dir.join("sub").exists());
        assert_eq!(fs::read(dir.join("a.csv")).unwrap(), b"3");
        assert_eq!(names(&dir), [MANIFEST, LOCK, "a.csv", MARKER]);
        // A run that fails (dropped without commit) changes nothing and leaves no staging.
        {
            let mut o = OutDir::prepare(&dir).unwrap();
            o.write("a.csv", b"half").unwrap();
        }
        assert_eq!(fs::read(dir.join("a.csv")).unwrap(), b"3");
        assert_eq!(names(&dir), [MANIFEST, LOCK, "a.csv", MARKER]);
        // A failed run into a directory it created leaves no directory.
        let fresh = tmp.path().join("fresh");
        drop(OutDir::prepare(&fresh).unwrap());
        assert!(!fresh.exists());
    }

    #[test]
    fn second_writer_is_refused_and_stale_staging_removed_under_the_lock() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        // A staging folder of any PID (here our own) found under the lock is a dead run's.
        let dead = dir.join(format!("{STAGING_PREFIX}{}", std::process::id()));
        fs::create_dir_all(dead.join("vtk")).unwrap();
        let first = OutDir::prepare(dir).unwrap();
        assert!(first
            .notes()
            .iter()
            .any(|n| n.contains("removed the staging")));
        let e = OutDir::prepare(dir).unwrap_err().to_string();
        assert!(e.contains("another rubsim run is writing"), "{e}");
        // The refused run touched nothing of the live one.
        assert!(first.staging_dir().is_dir());
        drop(first);
        assert!(OutDir::prepare(dir).is_ok());
    }

    #[test]
    fn names_and_destinations_outside_the_directory_are_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("o");
        let mut o = OutDir::prepare(&dir).unwrap();
        assert!(o.write("../x", b"1").is_err());
        assert!(o.write("/abs", b"1").is_err());
        assert!(o.write(LOCK, b"1").is_err());
        // A symbolic link inside the directory that leads out is not written through.
        #[cfg(unix)]
        {
            let outside = tmp.path().join("outside");
            fs::create_dir_all(&outside).unwrap();
            std::os::unix::fs::symlink(&outside, dir.join("vtk")).unwrap();
            o.write("vtk/f.vtu", b"1").unwrap();
            o.write(MARKER, b"{}").unwrap();
            let e = o.commit().unwrap_err().to_string();
            assert!(e.contains("crosses a symbolic link"), "{e}");
            assert!(!outside.join("f.vtu").exists());
            assert!(!dir.join(MARKER).exists());
        }
    }

    #[test]
    fn journal_of_an_incomplete_or_foreign_staging_is_discarded() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path();
        let mut o = OutDir::prepare(dir).unwrap();
        o.write("a.csv", b"old").unwrap();
        o.write(MARKER, b"{}").unwrap();
        o.commit().unwrap();
        let outside = tmp.path().join("..").join("victim-dir");
        for (staging, lists_missing) in [(".rubsim-partial-1", true), ("../victim-dir", false)] {
            // A dead run's journal; its staging folder lacks a file its manifest lists.
            if lists_missing {
                let s = dir.join(staging);
                fs::create_dir_all(&s).unwrap();
                fs::write(s.join(MANIFEST), "a.csv\nb.csv\nsummary.json\n").unwrap();
                fs::write(s.join("a.csv"), b"new").unwrap();
                fs::write(s.join(MARKER), b"{}").unwrap();
            }
            fs::write(dir.join(JOURNAL), format!("{staging}\n")).unwrap();
            let o = OutDir::prepare(dir).unwrap();
            assert!(
                o.notes()
                    .iter()
                    .any(|n| n.contains("discarded")
                        && n.contains("the previous results are intact")),
                "{:?}",
                o.notes()
            );
            drop(o);
            assert_eq!(fs::read(dir.join("a.csv")).unwrap(), b"old");
            assert_eq!(names(dir), [MANIFEST, LOCK, "a.csv", MARKER]);
        }
        assert!(!outside.exists());
    }

    #[test]
    fn commit_without_summary_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let mut o = OutDir::prepare(tmp.path()).unwrap();
        o.write("a.csv", b"1").unwrap();
        assert!(o.commit().is_err());
        assert!(!tmp.path().join("a.csv").exists());
    }
}
