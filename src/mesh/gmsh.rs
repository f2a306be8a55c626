//! Running gmsh on parametric geometries, with a content-addressed mesh cache.
//!
//! A [`MeshRequest`] names a `.geo` file (or a STEP/BREP/IGES file, wrapped in a generated
//! `.geo` that imports it through OpenCASCADE), its parameters and the mesh options. The mesh is
//! written to `meshes/<stem>-<key>.msh`, where `key` hashes everything the mesh depends on: the
//! geometry's text, the content of every file it imports (`ShapeFromFile`, `Merge`, `Include`),
//! the parameters and the options. A request whose mesh is in the cache never runs gmsh.
//!
//! gmsh is run as a command line program (`gmsh GEO -3 -format msh41 -bin -setnumber name value
//! … -o OUT`); `RUBSIM_GMSH` overrides the program. Parameters must be declared by the geometry
//! with `DefineConstant[ name = default, … ]`, so a misspelt parameter is an error rather than
//! silently ignored, and must lie within the `Min`/`Max` the declaration gives
//! ([`super::geo`]).
//!
//! # Time limit, killing, temporary files
//!
//! gmsh runs under a time limit: [`DEFAULT_TIME_LIMIT`] (300 s), or `$RUBSIM_GMSH_TIMEOUT`
//! (seconds), or the request's [`MeshRequest::time_limit`] (`rubsim mesh --timeout`). Past it
//! gmsh is killed and the error names the geometry and the limit. gmsh runs in its own process
//! group and dies with rubsim ([`super::process`]).
//!
//! gmsh writes into the cache directory under a temporary name,
//! `.rubsim-gmsh-<pid>-<n>.msh` (and `.geo` for a CAD wrapper), which is renamed to the cache
//! name only once gmsh has succeeded. Beside it a lock file `.rubsim-gmsh-<pid>-<n>.lock` is held
//! (std's `File::try_lock`: `flock` on Linux) while gmsh runs. The temporary files are removed
//! on every way out of [`mesh`] (success, failure, time-out) and by the signal thread of
//! [`super::process`] when rubsim is stopped by `SIGTERM`, `SIGINT` or `SIGHUP`; after a
//! `SIGKILL` of rubsim they are removed by the next [`mesh`] into the same cache: a temporary
//! file whose lock nobody holds is stale. (A lock, not the pid, decides, so a process in
//! another PID namespace sharing the cache is never mistaken for a dead one.)

use super::geo::declared_parameters;
pub use super::geo::{defined_parameters, referenced_files};
use super::process::{self, Condensed, Finished};
use super::Mesh;
use crate::error::MeshError;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Duration;

/// The time gmsh may take when neither the request nor `$RUBSIM_GMSH_TIMEOUT` says otherwise:
/// 300 s (the shipped geometries mesh in 0.3–3 s).
pub const DEFAULT_TIME_LIMIT: Duration = Duration::from_secs(300);

/// Cache format version: bump when the way meshes are produced changes.
const CACHE_VERSION: &str = "rubsim-mesh-1";

/// What to mesh and how.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshRequest {
    /// A `.geo` file, or a `.step`/`.stp`/`.brep`/`.iges`/`.igs` CAD file.
    pub geometry: PathBuf,
    /// `-setnumber` parameters (must be declared by the geometry's `DefineConstant`).
    pub parameters: BTreeMap<String, f64>,
    /// Element order: 1 (linear) or 2 (quadratic).
    pub order: u8,
    /// Recombine triangles into quadrilaterals (`Mesh.RecombineAll`).
    pub recombine: bool,
    /// Incomplete (serendipity) second-order cells: 8-node instead of 9-node quadrilaterals.
    pub serendipity: bool,
    /// Scale of every mesh size (`-clscale`); 1 keeps the geometry's sizes.
    pub size_factor: f64,
    /// The scene that asked for the mesh (for messages).
    pub referenced_by: Option<PathBuf>,
    /// How long gmsh may run; `None`: `$RUBSIM_GMSH_TIMEOUT` (seconds) or
    /// [`DEFAULT_TIME_LIMIT`]. Not part of the cache key.
    pub time_limit: Option<Duration>,
}

impl MeshRequest {
    /// A request with default options: linear, triangles, sizes as the geometry sets them.
    pub fn new(geometry: impl Into<PathBuf>) -> Self {
        Self {
            geometry: geometry.into(),
            parameters: BTreeMap::new(),
            order: 1,
            recombine: false,
            serendipity: false,
            size_factor: 1.0,
            referenced_by: None,
            time_limit: None,
        }
    }
}

/// A mesh on disk.
#[derive(Debug, Clone, PartialEq)]
pub struct Meshed {
    /// The `.msh` file in the cache.
    pub msh: PathBuf,
    /// True when it was already there (gmsh not run).
    pub from_cache: bool,
    /// The cache key (32 hex digits).
    pub key: String,
}

/// True for file names gmsh imports as CAD through OpenCASCADE.
pub fn is_cad(path: &Path) -> bool {
    matches!(
        path.extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase())
            .as_deref(),
        Some("step" | "stp" | "brep" | "iges" | "igs")
    )
}

/// The gmsh program: `$RUBSIM_GMSH` or `gmsh` on the PATH.
pub fn gmsh_program() -> String {
    std::env::var("RUBSIM_GMSH").unwrap_or_else(|_| "gmsh".to_string())
}

/// The default cache directory for a geometry: `meshes/` beside the `geometry/` directory
/// holding it (so `geometry/annulus.geo` → `meshes/`), else `meshes/` beside the file;
/// `$RUBSIM_MESH_DIR` overrides both.
pub fn default_cache_dir(geometry: &Path) -> PathBuf {
    if let Ok(d) = std::env::var("RUBSIM_MESH_DIR") {
        return PathBuf::from(d);
    }
    let dir = geometry.parent().unwrap_or(Path::new("."));
    if dir.file_name().and_then(|n| n.to_str()) == Some("geometry") {
        dir.parent().unwrap_or(Path::new(".")).join("meshes")
    } else {
        dir.join("meshes")
    }
}

fn read_file(file: &Path, referenced_by: Option<&Path>) -> Result<Vec<u8>, MeshError> {
    std::fs::read(file).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            MeshError::MissingFile {
                file: file.to_path_buf(),
                referenced_by: referenced_by.map(Path::to_path_buf),
            }
        } else {
            MeshError::Io {
                file: file.to_path_buf(),
                source: e,
            }
        }
    })
}

/// The `.geo` text gmsh runs for a request: the file itself, or for a CAD file a wrapper that
/// imports it and names the physical groups `stator` (every body) and `boundary_<tag>` (each
/// boundary entity), so a scene can pick its contact and fixed boundaries by entity.
/// Returns `(text to run, text to hash, imported files with their bytes)`; the two texts differ
/// only for CAD wrappers, whose absolute import path must not enter the key.
#[allow(clippy::type_complexity)]
fn geo_text(req: &MeshRequest) -> Result<(String, String, Vec<(PathBuf, Vec<u8>)>), MeshError> {
    let geo = &req.geometry;
    let base = geo.parent().unwrap_or(Path::new("."));
    if is_cad(geo) {
        let bytes = read_file(geo, req.referenced_by.as_deref())?;
        let abs = std::fs::canonicalize(geo).map_err(|e| MeshError::Io {
            file: geo.clone(),
            source: e,
        })?;
        let wrap = |path: &str| {
            format!(
                r#"// Generated by rubsim: import {name} and name its parts.
SetFactory("OpenCASCADE");
v() = ShapeFromFile("{path}");
vols() = Volume{{:}};
If (#vols() > 0)
  Physical Volume("stator") = vols();
  b() = Abs(Boundary{{ Volume{{vols()}}; }});
  For i In {{0:#b()-1}}
    Physical Surface(Sprintf("boundary_%g", b(i))) = {{b(i)}};
  EndFor
Else
  surfs() = Surface{{:}};
  Physical Surface("stator") = surfs();
  b() = Abs(Boundary{{ Surface{{surfs()}}; }});
  For i In {{0:#b()-1}}
    Physical Curve(Sprintf("boundary_%g", b(i))) = {{b(i)}};
  EndFor
EndIf
"#,
                name = geo.display(),
            )
        };
        let name = geo
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        let run = wrap(&abs.display().to_string().replace('\\', "/"));
        return Ok((run, wrap(&name), vec![(geo.clone(), bytes)]));
    }
    let bytes = read_file(geo, req.referenced_by.as_deref())?;
    if bytes.starts_with(b"$MeshFormat") {
        return Err(MeshError::NotAGeometry {
            geometry: geo.clone(),
            message: "it is a gmsh mesh (MSH), not a geometry to mesh: name it as a stator's `geometry` (it is read as it is), or report it with `rubsim mesh FILE.msh`".into(),
        });
    }
    let text = String::from_utf8(bytes).map_err(|_| MeshError::NotAGeometry {
        geometry: geo.clone(),
        message: "the file is not text; a geometry is a gmsh `.geo` script (text) or a CAD file named `.step`, `.stp`, `.brep`, `.iges` or `.igs`".into(),
    })?;
    let mut deps = Vec::new();
    for f in referenced_files(&text) {
        let p = base.join(&f);
        let b = read_file(&p, Some(geo))?;
        deps.push((p, b));
    }
    Ok((text.clone(), text, deps))
}

/// The cache key of a request (32 hex digits). Reads the geometry and its imports.
pub fn cache_key(req: &MeshRequest) -> Result<String, MeshError> {
    let (_, text, deps) = geo_text(req)?;
    Ok(key_of(req, &text, &deps))
}

fn key_of(req: &MeshRequest, text: &str, deps: &[(PathBuf, Vec<u8>)]) -> String {
    let mut h = crate::math::Fnv128::new();
    h.write(CACHE_VERSION.as_bytes());
    h.write(text.as_bytes());
    for (p, b) in deps {
        h.write(
            p.file_name()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
                .as_bytes(),
        );
        h.write(b);
    }
    for (k, v) in &req.parameters {
        h.write(k.as_bytes());
        h.write(&v.to_bits().to_le_bytes());
    }
    h.write(&[req.order, req.recombine as u8, req.serendipity as u8]);
    h.write(&req.size_factor.to_bits().to_le_bytes());
    h.hex()
}

/// Meshes `req` into `cache` (created if needed), or returns the cached mesh.
///
/// Errors: the geometry or an imported file is missing ([`MeshError::MissingFile`]), a
/// parameter is not declared by the geometry ([`MeshError::UnknownParameter`]) or lies outside
/// its declared bounds ([`MeshError::ParameterOutOfRange`]), gmsh cannot be started
/// ([`MeshError::GmshNotFound`]), reports errors ([`MeshError::GmshFailed`], with gmsh's own
/// lines, repeated lines counted) or runs past its time limit ([`MeshError::GmshTimeout`]).
pub fn mesh(req: &MeshRequest, cache: &Path) -> Result<Meshed, MeshError> {
    let geo = &req.geometry;
    if !(req.order == 1 || req.order == 2) {
        return Err(MeshError::GmshFailed {
            geometry: geo.clone(),
            status: None,
            message: format!("element order {} (rubsim reads orders 1 and 2)", req.order),
        });
    }
    let (text, hash_text, deps) = geo_text(req)?;
    check_parameters(req, &text)?;
    let limit = time_limit(req)?;
    let key = key_of(req, &hash_text, &deps);
    let stem = geo
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "mesh".into());
    let out = cache.join(format!("{stem}-{key}.msh"));
    if out.is_file() {
        return Ok(Meshed {
            msh: out,
            from_cache: true,
            key,
        });
    }
    std::fs::create_dir_all(cache).map_err(|e| MeshError::Io {
        file: cache.to_path_buf(),
        source: e,
    })?;
    remove_stale_temporaries(cache);
    let scratch = Scratch::new(cache)?;
    // CAD files get a generated wrapper next to the output.
    let input = if is_cad(geo) {
        std::fs::write(&scratch.geo, &text).map_err(|e| MeshError::Io {
            file: scratch.geo.clone(),
            source: e,
        })?;
        scratch.geo.clone()
    } else {
        geo.clone()
    };
    let program = gmsh_program();
    let cmd = gmsh_command(&program, req, &input, &scratch.msh);
    let finished = process::run(
        cmd,
        limit,
        &[&scratch.msh, &scratch.geo, &scratch.lock_path],
    )
    .map_err(|e| MeshError::GmshNotFound {
        geometry: geo.clone(),
        program: program.clone(),
        message: e.to_string(),
    })?;
    check_gmsh_output(geo, finished, &scratch.msh, limit)?;
    // Provenance beside the mesh: how it was made.
    let _ = std::fs::write(out.with_extension("toml"), provenance(req, &key));
    std::fs::rename(&scratch.msh, &out).map_err(|e| MeshError::Io {
        file: out.clone(),
        source: e,
    })?;
    Ok(Meshed {
        msh: out,
        from_cache: false,
        key,
    })
}

/// The time limit of a request: its own, else `$RUBSIM_GMSH_TIMEOUT` (seconds, positive),
/// else [`DEFAULT_TIME_LIMIT`].
pub fn time_limit(req: &MeshRequest) -> Result<Duration, MeshError> {
    if let Some(t) = req.time_limit {
        return Ok(t);
    }
    match std::env::var("RUBSIM_GMSH_TIMEOUT") {
        Err(_) => Ok(DEFAULT_TIME_LIMIT),
        Ok(v) => v
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|s| s.is_finite() && *s > 0.0 && *s < 1e9)
            .map(Duration::from_secs_f64)
            .ok_or_else(|| MeshError::GmshFailed {
                geometry: req.geometry.clone(),
                status: None,
                message: format!(
                    "RUBSIM_GMSH_TIMEOUT=`{v}`: expected a positive number of seconds"
                ),
            }),
    }
}

/// Prefix of the temporary files of a running gmsh in the cache.
const TEMP_PREFIX: &str = ".rubsim-gmsh-";

/// The temporary files of one gmsh run (`.rubsim-gmsh-<pid>-<n>.{msh,geo,lock}` in the cache)
/// and the lock that marks them live; dropping it removes them.
struct Scratch {
    msh: PathBuf,
    geo: PathBuf,
    lock_path: PathBuf,
    _lock: std::fs::File,
}

impl Scratch {
    /// Creates and locks `.rubsim-gmsh-<pid>-<n>.lock` (created under another name, locked,
    /// then renamed, so a cleaner never sees it unlocked).
    fn new(cache: &Path) -> Result<Self, MeshError> {
        let tag = format!("{TEMP_PREFIX}{}-{}", std::process::id(), unique());
        let io = |file: &Path| {
            let file = file.to_path_buf();
            move |source| MeshError::Io { file, source }
        };
        let locking = cache.join(format!("{tag}.locking"));
        let lock_path = cache.join(format!("{tag}.lock"));
        let lock = std::fs::File::create(&locking).map_err(io(&locking))?;
        if lock.try_lock().is_err() {
            let _ = std::fs::remove_file(&locking);
            return Err(MeshError::Io {
                file: locking,
                source: std::io::Error::other("cannot lock"),
            });
        }
        std::fs::rename(&locking, &lock_path).map_err(io(&lock_path))?;
        Ok(Scratch {
            msh: cache.join(format!("{tag}.msh")),
            geo: cache.join(format!("{tag}.geo")),
            lock_path,
            _lock: lock,
        })
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.msh);
        let _ = std::fs::remove_file(&self.geo);
        let _ = std::fs::remove_file(&self.lock_path);
    }
}

/// Removes the temporary files of gmsh runs that are over (their lock is free: the rubsim that
/// ran them was killed), and stray lock files older than an hour that were never renamed.
fn remove_stale_temporaries(cache: &Path) {
    let Ok(rd) = std::fs::read_dir(cache) else {
        return;
    };
    let names: Vec<String> = rd
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(TEMP_PREFIX))
        .collect();
    for n in &names {
        if let Some(tag) = n.strip_suffix(".lock") {
            let path = cache.join(n);
            let free = std::fs::File::open(&path).is_ok_and(|f| f.try_lock().is_ok());
            if free {
                for ext in ["msh", "geo"] {
                    let _ = std::fs::remove_file(cache.join(format!("{tag}.{ext}")));
                }
                let _ = std::fs::remove_file(&path);
            }
        } else if n.ends_with(".locking") {
            let path = cache.join(n);
            let old = std::fs::metadata(&path)
                .and_then(|m| m.modified())
                .ok()
                .and_then(|t| t.elapsed().ok())
                .is_some_and(|age| age > Duration::from_secs(3600));
            if old {
                let _ = std::fs::remove_file(&path);
            }
        } else {
            // A `.msh`/`.geo` without its lock file: its run is over.
            let tag = n.rsplit_once('.').map_or(n.as_str(), |(t, _)| t);
            if !names.iter().any(|m| m == &format!("{tag}.lock")) {
                let _ = std::fs::remove_file(cache.join(n));
            }
        }
    }
}

/// Every `-setnumber` parameter of `req` must be finite, declared by the geometry's
/// `DefineConstant` (`text`: the geometry's source; CAD files declare none) and within the
/// `Min`/`Max` bounds of its declaration.
fn check_parameters(req: &MeshRequest, text: &str) -> Result<(), MeshError> {
    if req.parameters.is_empty() {
        return Ok(());
    }
    let declared = if is_cad(&req.geometry) {
        vec![]
    } else {
        declared_parameters(text)
    };
    for (name, &value) in &req.parameters {
        let Some(d) = declared.iter().find(|d| &d.name == name) else {
            return Err(MeshError::UnknownParameter {
                geometry: req.geometry.clone(),
                name: name.clone(),
                known: declared.iter().map(|d| d.name.clone()).collect(),
            });
        };
        let below = d.min.is_some_and(|m| value < m);
        let above = d.max.is_some_and(|m| value > m);
        if !value.is_finite() || below || above {
            return Err(MeshError::ParameterOutOfRange {
                geometry: req.geometry.clone(),
                name: name.clone(),
                value,
                min: d.min,
                max: d.max,
            });
        }
    }
    Ok(())
}

/// The gmsh command line that meshes `input` as `req` asks into `tmp` (MSH 4.1, binary, one
/// thread).
fn gmsh_command(program: &str, req: &MeshRequest, input: &Path, tmp: &Path) -> Command {
    let mut cmd = Command::new(program);
    cmd.arg(input)
        .args(["-3", "-format", "msh41", "-bin", "-v", "2", "-nt", "1"])
        .arg("-order")
        .arg(req.order.to_string());
    for (k, v) in &req.parameters {
        cmd.arg("-setnumber").arg(k).arg(format!("{v:e}"));
    }
    if req.recombine {
        cmd.args(["-setnumber", "Mesh.RecombineAll", "1"]);
    }
    if req.serendipity {
        cmd.args(["-setnumber", "Mesh.SecondOrderIncomplete", "1"]);
    }
    if req.size_factor != 1.0 {
        cmd.arg("-clscale").arg(format!("{:e}", req.size_factor));
    }
    cmd.arg("-o").arg(tmp);
    cmd
}

/// gmsh failed when it ran past `limit`, exited with an error status, printed `Error` lines or
/// wrote no mesh to `tmp`: [`MeshError::GmshTimeout`] with its last lines, or
/// [`MeshError::GmshFailed`] with its error lines (or its last 20 lines), each distinct line
/// once with its count.
fn check_gmsh_output(
    geo: &Path,
    finished: Finished,
    tmp: &Path,
    limit: Duration,
) -> Result<(), MeshError> {
    let (status, output) = match finished {
        Finished::TimedOut { output } => {
            return Err(MeshError::GmshTimeout {
                geometry: geo.to_path_buf(),
                limit_s: limit.as_secs_f64(),
                message: match last_lines(&output, 10) {
                    l if l.trim().is_empty() => "(gmsh printed nothing)".into(),
                    l => l,
                },
            })
        }
        Finished::Exited { status, output } => (status, output),
    };
    let is_error = |l: &str| l.trim_start().starts_with("Error") && !gmsh_summary_line(l);
    let has_errors = output.lines.iter().any(|(l, _)| is_error(l));
    let produced = std::fs::metadata(tmp).map(|m| m.len() > 0).unwrap_or(false);
    if status.success() && !has_errors && produced {
        return Ok(());
    }
    let message = if has_errors {
        output.render(is_error)
    } else {
        last_lines(&output, 20)
    };
    Err(MeshError::GmshFailed {
        geometry: geo.to_path_buf(),
        status: status.code(),
        message: if message.trim().is_empty() {
            "no mesh written and no message".into()
        } else {
            message
        },
    })
}

/// Lines of gmsh's closing error summary (`Mesh generation error summary`, `N errors`, …), which
/// repeat what the error lines say.
fn gmsh_summary_line(l: &str) -> bool {
    let body = l.split_once(':').map_or(l, |(_, b)| b).trim();
    let words: Vec<&str> = body.split_whitespace().collect();
    let count = matches!(
        words.as_slice(),
        [n, "error" | "errors" | "warning" | "warnings"] if n.parse::<u64>().is_ok()
    );
    count
        || body.is_empty()
        || body.chars().all(|c| c == '-')
        || body == "Mesh generation error summary"
        || body == "Check the full log for details"
}

/// The last `n` distinct lines of a condensed output (with their counts).
fn last_lines(output: &Condensed, n: usize) -> String {
    let skip = output.lines.len().saturating_sub(n);
    let tail = Condensed {
        lines: output.lines[skip..].to_vec(),
        dropped: output.dropped,
    };
    tail.render(|_| true)
}

/// The provenance file written beside a cached mesh (TOML): geometry, key, options, parameters.
fn provenance(req: &MeshRequest, key: &str) -> String {
    let mut info = format!(
        "geometry = {:?}\nkey = \"{key}\"\norder = {}\nrecombine = {}\nserendipity = {}\nsize_factor = {}\n[parameters]\n",
        req.geometry.display().to_string(),
        req.order,
        req.recombine,
        req.serendipity,
        req.size_factor
    );
    for (k, v) in &req.parameters {
        info.push_str(&format!("{k} = {v:e}\n"));
    }
    info
}

/// Meshes (or takes from the cache) and reads the mesh.
pub fn mesh_and_read(req: &MeshRequest, cache: &Path) -> Result<(Mesh, Meshed), MeshError> {
    let m = mesh(req, cache)?;
    let mesh = Mesh::read(&m.msh)?;
    Ok((mesh, m))
}

fn unique() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static N: AtomicU64 = AtomicU64::new(0);
    N.fetch_add(1, Ordering::Relaxed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_changes_with_every_input() {
        let r = MeshRequest::new("a.geo");
        let k0 = key_of(&r, "x", &[]);
        assert_eq!(k0, key_of(&r, "x", &[]));
        assert_ne!(k0, key_of(&r, "y", &[]));
        let mut r2 = r.clone();
        r2.parameters.insert("h".into(), 0.1);
        assert_ne!(k0, key_of(&r2, "x", &[]));
        let mut r3 = r.clone();
        r3.order = 2;
        assert_ne!(k0, key_of(&r3, "x", &[]));
        assert_ne!(
            key_of(&r, "x", &[(PathBuf::from("p.step"), b"1".to_vec())]),
            key_of(&r, "x", &[(PathBuf::from("p.step"), b"2".to_vec())])
        );
    }

    #[test]
    fn cache_dir_is_beside_geometry_dir() {
        if std::env::var("RUBSIM_MESH_DIR").is_ok() {
            return;
        }
        assert_eq!(
            default_cache_dir(Path::new("repo/geometry/annulus.geo")),
            PathBuf::from("repo/meshes")
        );
        assert_eq!(
            default_cache_dir(Path::new("elsewhere/x.geo")),
            PathBuf::from("elsewhere/meshes")
        );
    }
}
