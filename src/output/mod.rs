//! Writing results: the output directory ([`OutDir`]), `summary.json` ([`summary`]), every
//! CSV table ([`csv`]) and the PNG pictures ([`figures`]). The VTK/HDF5 time series are
//! written by the frame sinks of [`crate::results`] into the same staging folder.
//!
//! Every file is first written into a staging folder inside the output directory and moved
//! into place only when the whole command has succeeded, `summary.json` last; a failed or
//! killed run leaves no file that looks complete. The directory is checked for writability
//! before any computation starts ([`OutDir::prepare`]).

pub mod csv;
pub mod figures;
pub mod summary;

use crate::error::{Error, Result};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Name of the manifest listing the files of the last completed run in a directory.
pub const MANIFEST: &str = ".rubsim-files";
const STAGING_PREFIX: &str = ".rubsim-partial-";

/// An output directory with a staging area.
#[derive(Debug)]
pub struct OutDir {
    dir: PathBuf,
    staging: PathBuf,
    files: Vec<String>,
    committed: bool,
    created: bool,
}

/// True when a staging folder's owner process no longer runs (Linux `/proc`; elsewhere
/// staging folders of other processes are left alone).
fn stale_staging(name: &str) -> bool {
    match name
        .strip_prefix(STAGING_PREFIX)
        .and_then(|p| p.parse::<u32>().ok())
    {
        Some(pid) => {
            Path::new("/proc/self").exists()
                && pid != std::process::id()
                && !Path::new(&format!("/proc/{pid}")).exists()
        }
        None => false,
    }
}

impl OutDir {
    /// Creates `dir` if needed and checks that files can be written there; removes staging
    /// folders left by killed runs.
    pub fn prepare(dir: &Path) -> Result<Self> {
        if dir.exists() && !dir.is_dir() {
            return Err(Error::output(
                dir,
                "output path exists and is not a directory",
            ));
        }
        let created = !dir.exists();
        std::fs::create_dir_all(dir)
            .map_err(|e| Error::output(dir, format!("cannot create output directory: {e}")))?;
        if let Ok(rd) = std::fs::read_dir(dir) {
            for e in rd.flatten() {
                let name = e.file_name().to_string_lossy().to_string();
                if stale_staging(&name) {
                    let _ = std::fs::remove_dir_all(e.path());
                }
            }
        }
        let staging = dir.join(format!("{STAGING_PREFIX}{}", std::process::id()));
        std::fs::create_dir_all(&staging)
            .map_err(|e| Error::output(dir, format!("output directory is not writable: {e}")))?;
        let probe = staging.join(".probe");
        std::fs::File::create(&probe)
            .and_then(|mut f| f.write_all(b"probe"))
            .map_err(|e| Error::output(dir, format!("output directory is not writable: {e}")))?;
        let _ = std::fs::remove_file(&probe);
        Ok(Self {
            dir: dir.to_path_buf(),
            staging,
            files: Vec::new(),
            committed: false,
            created,
        })
    }

    /// The final directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Staging path of a file to be produced as `name` (relative, may contain `/`).
    pub fn stage(&mut self, name: &str) -> Result<PathBuf> {
        let p = self.staging.join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).map_err(|e| Error::output(parent, e))?;
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
    pub fn adopt(&mut self, name: &str) -> Result<()> {
        let p = self.staging.join(name);
        if !p.is_file() {
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

    /// Writes bytes to `name` in the staging area.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<()> {
        let p = self.stage(name)?;
        std::fs::write(&p, bytes).map_err(|e| Error::output(self.dir.join(name), e))
    }

    /// Moves every staged file into place (`summary.json` files last), removes the files of
    /// the previous run in this directory that this run did not produce (from its manifest),
    /// writes the new manifest and removes the staging folder. Returns the final paths.
    pub fn commit(mut self) -> Result<Vec<PathBuf>> {
        let mut names = self.files.clone();
        names.sort_by_key(|n| n.ends_with("summary.json"));
        let manifest = self.dir.join(MANIFEST);
        if let Ok(old) = std::fs::read_to_string(&manifest) {
            for f in manifest_entries(&old) {
                if !names.iter().any(|n| n == f) {
                    let _ = std::fs::remove_file(self.dir.join(f));
                }
            }
        }
        let mut out = Vec::new();
        for n in &names {
            let from = self.staging.join(n);
            let to = self.dir.join(n);
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent).map_err(|e| Error::output(parent, e))?;
            }
            std::fs::rename(&from, &to).map_err(|e| Error::output(&to, e))?;
            out.push(to);
        }
        std::fs::write(&manifest, names.join("\n") + "\n")
            .map_err(|e| Error::output(&manifest, e))?;
        let _ = std::fs::remove_dir_all(&self.staging);
        self.committed = true;
        Ok(out)
    }
}

/// The file names a manifest's text lists, one per line: empty lines and names with `..` are
/// skipped (a manifest never names anything outside its directory).
pub fn manifest_entries(text: &str) -> Vec<&str> {
    text.lines()
        .filter(|l| !l.is_empty() && !l.contains(".."))
        .collect()
}

impl Drop for OutDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
            if self.created {
                // Only removes the directory when it is still empty.
                let _ = std::fs::remove_dir(&self.dir);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rerun_replaces_results_and_failed_run_leaves_nothing() {
        let tmp = std::env::temp_dir().join(format!("rubsim-outdir-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&tmp);
        let mut o = OutDir::prepare(&tmp).unwrap();
        o.write("a.csv", b"1").unwrap();
        o.write("b.png", b"2").unwrap();
        o.write("summary.json", b"{}").unwrap();
        o.commit().unwrap();
        assert!(tmp.join("b.png").exists());
        // A rerun that produces fewer files removes the stale one.
        let mut o = OutDir::prepare(&tmp).unwrap();
        o.write("a.csv", b"3").unwrap();
        o.write("summary.json", b"{}").unwrap();
        o.commit().unwrap();
        assert!(!tmp.join("b.png").exists());
        assert_eq!(std::fs::read(tmp.join("a.csv")).unwrap(), b"3");
        // A run that fails (dropped without commit) changes nothing and leaves no staging.
        {
            let mut o = OutDir::prepare(&tmp).unwrap();
            o.write("a.csv", b"half").unwrap();
        }
        assert_eq!(std::fs::read(tmp.join("a.csv")).unwrap(), b"3");
        // A staging folder of a dead process is cleaned up by the next prepare.
        let dead = tmp.join(format!("{STAGING_PREFIX}{}", u32::MAX - 7));
        std::fs::create_dir_all(&dead).unwrap();
        let o = OutDir::prepare(&tmp).unwrap();
        assert!(!dead.exists());
        drop(o);
        let left: Vec<_> = std::fs::read_dir(&tmp)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().to_string())
            .filter(|n| n.starts_with(STAGING_PREFIX))
            .collect();
        assert!(left.is_empty(), "{left:?}");
        std::fs::remove_dir_all(&tmp).unwrap();
    }
}
