//! `rubsim import-ross FILE [--out SCENE] [--force]`: the scene of a rotor saved by ROSS,
//! checked by building its model before it is written; `--out` never overwrites without
//! `--force`, never the ROSS file itself, never through a symbolic link, and writes atomically.

use anyhow::{bail, Context, Result};
use rubsim::model::Model;
use rubsim::output::durable::write_atomic;
use rubsim::scene;
use std::fs::{self, Metadata};
use std::io::ErrorKind;
use std::path::{Path, PathBuf};

/// Imports `file` and prints the scene, or writes it to `out` (see the module's rules).
pub fn import_ross(file: &Path, out: Option<&Path>, force: bool) -> Result<()> {
    if let Some(p) = out {
        check_target(file, p, force)?;
    }
    let text = fs::read_to_string(file)
        .with_context(|| format!("{}: cannot read the ROSS file", file.display()))?;
    let scene_text = scene::ross::import(file, &text)?;
    let ls = scene::parse(file, &scene_text, &[])
        .with_context(|| format!("{}: the imported scene is not valid", file.display()))?;
    Model::from_scene(&ls)
        .with_context(|| format!("{}: building the imported rotor", file.display()))?;
    match out {
        Some(p) => {
            check_target(file, p, force)?;
            write(p, &scene_text)
        }
        None => {
            print!("{scene_text}");
            Ok(())
        }
    }
}

/// Refuses to write the scene to `out` when it is a symbolic link, a directory, the ROSS file
/// `input` itself, or (without `force`) any existing file.
fn check_target(input: &Path, out: &Path, force: bool) -> Result<()> {
    let meta = match fs::symlink_metadata(out) {
        Ok(m) => m,
        Err(e) if e.kind() == ErrorKind::NotFound => return Ok(()),
        Err(e) => bail!("{}: cannot inspect the --out file: {e}", out.display()),
    };
    if meta.file_type().is_symlink() {
        bail!(
            "{}: is a symbolic link; import-ross does not write through links (remove it or choose another --out)",
            out.display()
        );
    }
    if meta.is_dir() {
        bail!(
            "{}: is a directory; --out names the scene file",
            out.display()
        );
    }
    if fs::metadata(input).is_ok_and(|m| same_file(&m, &meta, input, out)) {
        bail!(
            "{}: is the ROSS file being imported; choose another --out (--force does not overwrite the input)",
            out.display()
        );
    }
    if !force {
        bail!("{}: exists; give --force to overwrite it", out.display());
    }
    Ok(())
}

/// Whether the files `a` (at `pa`) and `b` (at `pb`) are one (also through a link or a second
/// name).
fn same_file(a: &Metadata, b: &Metadata, pa: &Path, pb: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let _ = (pa, pb);
        a.dev() == b.dev() && a.ino() == b.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (a, b);
        matches!((fs::canonicalize(pa), fs::canonicalize(pb)), (Ok(x), Ok(y)) if x == y)
    }
}

/// Writes `text` to `out` atomically: a temporary file beside it (never through a link,
/// [`write_atomic`]), synced, renamed onto `out`; the temporary file is removed when any step
/// fails.
fn write(out: &Path, text: &str) -> Result<()> {
    let dir = match out.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = out
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.import-ross-{}.tmp", std::process::id()));
    write_atomic(&tmp, out, text.as_bytes(), || {})
        .inspect_err(|_| {
            let _ = fs::remove_file(&tmp);
        })
        .with_context(|| format!("{}: cannot write the scene", out.display()))
}
