//! Durable file operations of the output protocol ([`super::outdir`]) and the case store
//! (`crate::study::store`): a file's data reaches the disk (`fsync`) before the rename that makes
//! it visible, and a directory is synced after the renames and removals in it, so that after a
//! power loss a name never points to data that was not written — in particular, a
//! `summary.json` never stands beside results whose bytes were lost.
//!
//! POSIX makes a rename durable only once its directory is synced; Linux syncs a directory
//! with `fsync(2)` on a descriptor opened read-only. File systems that cannot sync a directory
//! (they answer `EINVAL`) are taken as they are: the protocol still holds against a killed
//! process there, as before.

use crate::error::{Error, Result};
use std::fs::{self, File};
use std::io::{ErrorKind, Write};
use std::path::Path;

/// Flushes the data and metadata of the file `path` to the disk.
///
/// # Errors
/// [`Error::Output`] naming the file when it cannot be opened or synced (`EIO`: the data may
/// be lost).
pub fn sync_file(path: &Path) -> Result<()> {
    File::open(path)
        .and_then(|f| f.sync_all())
        .map_err(|e| Error::output(path, format!("cannot sync it to the disk: {e}")))
}

/// Makes the entries of the directory `dir` (files created, renamed or removed in it) durable.
///
/// # Errors
/// [`Error::Output`] naming the directory when it cannot be opened or synced; a file system
/// that does not sync directories (`EINVAL`, unsupported) is not an error.
pub fn sync_dir(dir: &Path) -> Result<()> {
    let dir = if dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        dir
    };
    match File::open(dir).and_then(|f| f.sync_all()) {
        Err(e) if !matches!(e.kind(), ErrorKind::InvalidInput | ErrorKind::Unsupported) => Err(
            Error::output(dir, format!("cannot sync the directory to the disk: {e}")),
        ),
        _ => Ok(()),
    }
}

/// Writes `bytes` to `path` atomically and durably: into the temporary file `tmp` (same
/// folder), synced, then `before_rename()` (the output protocol's fault-injection point), the
/// rename onto `path`, and the folder synced. A reader sees the old file or the whole new
/// one; after a power loss, the new name never holds unwritten data. Whatever is at `tmp` (a
/// temporary file a killed run left, a symbolic or hard link someone put there) is unlinked and
/// the file created anew, exclusively (`O_EXCL`, which never follows a link): the bytes go into
/// a new file of the folder, never through a link into another file.
///
/// # Errors
/// [`Error::Output`] naming the temporary file (create, write, sync) or `path` (rename,
/// folder sync).
pub fn write_atomic(tmp: &Path, path: &Path, bytes: &[u8], before_rename: fn()) -> Result<()> {
    write_synced(tmp, bytes)?;
    before_rename();
    fs::rename(tmp, path).map_err(|e| Error::output(path, e))?;
    sync_dir(path.parent().unwrap_or(Path::new(".")))
}

/// The first half of [`write_atomic`]: `bytes` written to the temporary file `tmp` and synced,
/// for a caller that renames several such files and then syncs their folder once. A name left
/// at `tmp` is unlinked first (a link, not what it points to), and the file is created with
/// `create_new` (`O_CREAT | O_EXCL`): never through a symbolic link, never into a file that
/// another name (a hard link) shares; if something reappears at `tmp` meanwhile, the write
/// fails instead.
///
/// # Errors
/// [`Error::Output`] naming `tmp`.
pub fn write_synced(tmp: &Path, bytes: &[u8]) -> Result<()> {
    match fs::remove_file(tmp) {
        Err(e) if e.kind() != ErrorKind::NotFound => return Err(Error::output(tmp, e)),
        _ => {}
    }
    let mut f = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(tmp)
        .map_err(|e| Error::output(tmp, e))?;
    f.write_all(bytes)
        .and_then(|()| f.sync_all())
        .map_err(|e| Error::output(tmp, e))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn write_atomic_replaces_the_file_and_leaves_no_temporary() {
        let d = tempfile::tempdir().unwrap();
        let (tmp, p) = (d.path().join(".x.tmp"), d.path().join("x"));
        write_atomic(&tmp, &p, b"one", || {}).unwrap();
        write_atomic(&tmp, &p, b"two", || {}).unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"two");
        assert!(!tmp.exists());
        // A link at the temporary name is not written through: the symbolic link's target is
        // neither created nor written, a hard link's other name keeps its bytes.
        #[cfg(unix)]
        {
            let target = d.path().join("elsewhere");
            std::os::unix::fs::symlink(&target, &tmp).unwrap();
            write_atomic(&tmp, &p, b"three", || {}).unwrap();
            assert!(!target.exists());
            assert_eq!(fs::read(&p).unwrap(), b"three");
            assert!(!p.is_symlink());
            let other = d.path().join("other");
            fs::write(&other, b"mine").unwrap();
            fs::hard_link(&other, &tmp).unwrap();
            write_atomic(&tmp, &p, b"four", || {}).unwrap();
            assert_eq!(fs::read(&other).unwrap(), b"mine");
            assert_eq!(fs::read(&p).unwrap(), b"four");
        }
        sync_file(&p).unwrap();
        sync_dir(d.path()).unwrap();
        // A missing file is an error naming it.
        let e = sync_file(&d.path().join("absent")).unwrap_err().to_string();
        assert!(e.contains("absent") && e.contains("cannot sync"), "{e}");
        let e = write_atomic(&d.path().join("no/such/.t"), &p, b"x", || {})
            .unwrap_err()
            .to_string();
        assert!(e.contains("no/such/.t"), "{e}");
    }
}
