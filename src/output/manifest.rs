//! The manifest `.rubsim-files`: the files of the last completed run in an output directory,
//! one path per line, relative to the directory. The next run removes the files it lists that
//! the new run does not produce, so the manifest is trusted only as far as
//! [`parse_manifest`] confines it: a path that could name a file outside the directory (or a
//! file of the output protocol itself) is refused, never followed.

use crate::error::{Error, Result};
use std::fs;
use std::path::Path;

/// Name of the manifest listing the files of the last completed run in a directory.
pub const MANIFEST: &str = ".rubsim-files";

/// Prefix of every file and folder of the output protocol (manifest, lock, commit journal,
/// staging folders); no result file may start with it.
pub const PROTOCOL_PREFIX: &str = ".rubsim-";

/// Longest accepted entry, in bytes (Linux `PATH_MAX`).
const MAX_LEN: usize = 4096;

/// A manifest read from text: the confined entries and the lines refused.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Manifest {
    /// Accepted paths, in the order of the text, each once.
    pub entries: Vec<String>,
    /// Lines that were not confined to the directory; they are ignored (never deleted).
    pub rejected: Vec<Rejected>,
}

/// A manifest line that was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rejected {
    /// 1-based line number in the manifest.
    pub line: usize,
    /// The line as written (lossless; may hold control characters).
    pub entry: String,
    /// Why it was refused.
    pub reason: &'static str,
}

/// Reads a manifest's text: every non-empty line is an entry, accepted when
/// [`check_relative`] confines it, refused with its line number otherwise. Pure and total —
/// no input panics or touches the file system (a fuzz target calls it). Whether a confined
/// path crosses a symbolic link on disk is checked where it is used, not here.
pub fn parse_manifest(text: &str) -> Manifest {
    let mut m = Manifest::default();
    for (i, line) in text.split('\n').enumerate() {
        if line.is_empty() {
            continue;
        }
        match check_relative(line) {
            Ok(()) => {
                if !m.entries.iter().any(|e| e == line) {
                    m.entries.push(line.to_string());
                }
            }
            Err(reason) => m.rejected.push(Rejected {
                line: i + 1,
                entry: line.to_string(),
                reason,
            }),
        }
    }
    m
}

/// Accepts only a normalised relative path below a directory: `/`-separated, non-empty
/// components, none `.` or `..`, no leading `/`, no backslash or control character (NUL
/// included), at most 4096 bytes, and not a file of the output protocol (its first
/// component does not start with `.rubsim-`). Returns why `name` is refused otherwise.
pub fn check_relative(name: &str) -> Result<(), &'static str> {
    if name.is_empty() {
        return Err("is empty");
    }
    if name.len() > MAX_LEN {
        return Err("is longer than 4096 bytes");
    }
    if name.contains('\0') {
        return Err("contains a NUL byte");
    }
    if name.chars().any(char::is_control) {
        return Err("contains a control character");
    }
    if name.contains('\\') {
        return Err("contains a backslash");
    }
    if name.starts_with('/') {
        return Err("is an absolute path");
    }
    for part in name.split('/') {
        match part {
            "" => return Err("has an empty component (`//` or a trailing `/`)"),
            "." | ".." => return Err("has a `.` or `..` component"),
            _ => {}
        }
    }
    if name.starts_with(PROTOCOL_PREFIX) {
        return Err("names a file of the output protocol");
    }
    // Belt and braces for platforms with other path syntax (drive prefixes).
    if !std::path::Path::new(name)
        .components()
        .all(|c| matches!(c, std::path::Component::Normal(_)))
    {
        return Err("is not a plain relative path");
    }
    Ok(())
}

/// Refuses the file system's root as an output directory ([`super::OutDir::prepare`]),
/// and (unless `force`) an existing directory holding something not rubsim's: it is rubsim's
/// when it holds a protocol (`.rubsim-`) file, or only folders that do (a sharded study's
/// `shard-*/`, the `refine/` or `modal/` of a scene's default folder). Anything else is a
/// folder rubsim did not make, whose `summary.json` or `orbit.png` the results would replace.
///
/// # Errors
/// [`Error::Output`] naming the directory, and what to do.
pub fn check_owner(dir: &Path, force: bool) -> Result<()> {
    let Ok(entries) = fs::read_dir(dir) else {
        // Missing (it is created) or unreadable (the lock reports it).
        return Ok(());
    };
    if fs::canonicalize(dir).is_ok_and(|c| c.parent().is_none()) {
        return Err(Error::output(
            dir,
            "is the root of the file system: rubsim does not write its results there \
             (--force does not change this); choose a folder for them with --out",
        ));
    }
    let mut foreign = None;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with(PROTOCOL_PREFIX) {
            return Ok(());
        }
        if !holds_protocol_file(&e.path()) {
            foreign.get_or_insert(name);
        }
    }
    match foreign {
        Some(name) if !force => Err(Error::output(
            dir,
            format!(
                "is not empty (it holds `{name}`) and is not a rubsim output directory (it has no \
                 {PROTOCOL_PREFIX} files, such as {MANIFEST}): the results would replace files of the same names \
                 (summary.json, orbit.png, …); choose a new or empty folder with --out, or \
                 give --force to write into this one"
            ),
        )),
        _ => Ok(()),
    }
}

/// True when `dir` is a directory holding a file of the protocol: an output directory of
/// rubsim's, as a sharded study's `shard-<i>-of-<n>/` folders are in the folder `rubsim merge`
/// writes to, and `refine/`, `modal/`, … in a scene's default `out/<scene>/`.
fn holds_protocol_file(dir: &Path) -> bool {
    fs::symlink_metadata(dir).is_ok_and(|m| m.is_dir())
        && fs::read_dir(dir).is_ok_and(|rd| {
            rd.flatten()
                .any(|e| e.file_name().to_string_lossy().starts_with(PROTOCOL_PREFIX))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn confined_entries_are_kept_and_escapes_refused_with_their_line() {
        let text = "summary.json\nvtk/frame_000001.vtu\n/etc/passwd\n../x\nvtk/../../y\n\
                    a//b\n./a\nvtk/\n.rubsim-lock\nwin\\x\nnul\0x\ncr\r\n\nsummary.json\n";
        let m = parse_manifest(text);
        assert_eq!(m.entries, vec!["summary.json", "vtk/frame_000001.vtu"]);
        let lines: Vec<usize> = m.rejected.iter().map(|r| r.line).collect();
        assert_eq!(lines, vec![3, 4, 5, 6, 7, 8, 9, 10, 11, 12]);
        assert_eq!(m.rejected[0].reason, "is an absolute path");
        assert_eq!(m.rejected[1].reason, "has a `.` or `..` component");
        assert_eq!(m.rejected[7].reason, "contains a backslash");
        assert_eq!(m.rejected[8].reason, "contains a NUL byte");
        assert_eq!(m.rejected[9].reason, "contains a control character");
    }

    #[test]
    fn the_root_and_foreign_folders_are_refused_ours_and_empty_ones_taken() {
        for force in [false, true] {
            let e = check_owner(Path::new("/"), force).unwrap_err().to_string();
            assert!(e.contains("root of the file system"), "{e}");
        }
        let d = tempfile::tempdir().unwrap();
        let dir = d.path().join("out");
        assert!(
            check_owner(&dir, false).is_ok(),
            "a missing folder is created"
        );
        fs::create_dir(&dir).unwrap();
        assert!(check_owner(&dir, false).is_ok(), "an empty folder is taken");
        fs::write(dir.join("orbit.png"), "mine").unwrap();
        let e = check_owner(&dir, false).unwrap_err().to_string();
        assert!(e.contains("orbit.png") && e.contains("--force"), "{e}");
        assert!(check_owner(&dir, true).is_ok());
        // A folder holding output folders (a sharded study's, a scene's `refine/`) besides a
        // file of its own is not rubsim's; holding only them, it is; and rubsim's own folder.
        for sub in ["shard-1-of-2", "refine"] {
            fs::create_dir_all(dir.join(sub)).unwrap();
            fs::write(dir.join(sub).join(".rubsim-lock"), "").unwrap();
        }
        assert!(check_owner(&dir, false).is_err());
        fs::create_dir(dir.join("notes")).unwrap();
        fs::rename(dir.join("orbit.png"), dir.join("notes/orbit.png")).unwrap();
        assert!(
            check_owner(&dir, false).is_err(),
            "`notes/` is not rubsim's"
        );
        fs::remove_dir_all(dir.join("notes")).unwrap();
        assert!(check_owner(&dir, false).is_ok());
        fs::write(dir.join("orbit.png"), "mine").unwrap();
        fs::write(dir.join(MANIFEST), "orbit.png\n").unwrap();
        assert!(check_owner(&dir, false).is_ok());
    }

    #[test]
    fn empty_and_odd_texts_do_not_panic() {
        assert_eq!(parse_manifest(""), Manifest::default());
        assert!(parse_manifest("\n\n\n").entries.is_empty());
        assert_eq!(parse_manifest(&"a".repeat(5000)).rejected.len(), 1);
        assert_eq!(parse_manifest("é/ü.csv").entries, vec!["é/ü.csv"]);
    }
}
