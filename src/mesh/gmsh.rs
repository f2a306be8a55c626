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
//! silently ignored.

use super::Mesh;
use crate::error::MeshError;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

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

/// Names declared by `DefineConstant[ a = …, b = {…, Name "…"}, … ]` in a `.geo` text.
pub fn defined_parameters(text: &str) -> Vec<String> {
    let text = strip_comments(text);
    let mut out = Vec::new();
    let mut rest = text.as_str();
    while let Some(i) = rest.find("DefineConstant") {
        rest = &rest[i + "DefineConstant".len()..];
        let Some(open) = rest.find('[') else { break };
        // Matching close bracket.
        let mut depth = 0usize;
        let mut end = rest.len();
        for (k, c) in rest[open..].char_indices() {
            match c {
                '[' | '{' | '(' => depth += 1,
                ']' | '}' | ')' => {
                    depth -= 1;
                    if depth == 0 {
                        end = open + k;
                        break;
                    }
                }
                _ => {}
            }
        }
        let body = &rest[open + 1..end.min(rest.len())];
        // Top-level comma-separated `name = value` items.
        let mut depth = 0usize;
        let mut start = 0;
        let mut items = Vec::new();
        for (k, c) in body.char_indices() {
            match c {
                '[' | '{' | '(' => depth += 1,
                ']' | '}' | ')' => depth = depth.saturating_sub(1),
                ',' if depth == 0 => {
                    items.push(&body[start..k]);
                    start = k + 1;
                }
                _ => {}
            }
        }
        items.push(&body[start..]);
        for it in items {
            if let Some((name, _)) = it.split_once('=') {
                let name = name.trim();
                if !name.is_empty() && name.chars().all(|c| c.is_alphanumeric() || c == '_') {
                    out.push(name.to_string());
                }
            }
        }
        rest = &rest[end.min(rest.len())..];
    }
    out.sort();
    out.dedup();
    out
}

/// Files a `.geo` text imports: string arguments of `ShapeFromFile`, `Merge`, `Include`.
pub fn referenced_files(text: &str) -> Vec<String> {
    let text = strip_comments(text);
    let mut out = Vec::new();
    for kw in ["ShapeFromFile", "Merge", "Include"] {
        let mut rest = text.as_str();
        while let Some(i) = rest.find(kw) {
            rest = &rest[i + kw.len()..];
            let t = rest.trim_start().trim_start_matches('(').trim_start();
            if let Some(s) = t.strip_prefix('"') {
                if let Some(e) = s.find('"') {
                    out.push(s[..e].to_string());
                }
            }
        }
    }
    out
}

fn strip_comments(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut chars = text.chars().peekable();
    let mut in_str = false;
    while let Some(c) = chars.next() {
        if in_str {
            out.push(c);
            if c == '"' {
                in_str = false;
            }
            continue;
        }
        match (c, chars.peek()) {
            ('"', _) => {
                in_str = true;
                out.push(c);
            }
            ('/', Some('/')) => {
                for d in chars.by_ref() {
                    if d == '\n' {
                        out.push('\n');
                        break;
                    }
                }
            }
            ('/', Some('*')) => {
                chars.next();
                let mut prev = ' ';
                for d in chars.by_ref() {
                    if prev == '*' && d == '/' {
                        break;
                    }
                    prev = d;
                }
            }
            _ => out.push(c),
        }
    }
    out
}

/// 128-bit FNV-1a: a stable content hash for cache keys (not cryptographic).
#[derive(Debug, Clone, Copy)]
struct Fnv128(u128);

impl Fnv128 {
    fn new() -> Self {
        Fnv128(0x6c62272e07bb014262b821756295c58d)
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 ^= *b as u128;
            self.0 = self.0.wrapping_mul(0x0000000001000000000000000000013B);
        }
        // Field separator, so that ("ab", "c") and ("a", "bc") differ.
        self.0 ^= 0xff;
        self.0 = self.0.wrapping_mul(0x0000000001000000000000000000013B);
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
    let text = String::from_utf8(bytes).map_err(|_| MeshError::GmshFailed {
        geometry: geo.clone(),
        status: None,
        message: "the geometry is not UTF-8 text".into(),
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
    let mut h = Fnv128::new();
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
    format!("{:032x}", h.0)
}

/// Meshes `req` into `cache` (created if needed), or returns the cached mesh.
///
/// Errors: the geometry or an imported file is missing ([`MeshError::MissingFile`]), a
/// parameter is not declared by the geometry ([`MeshError::UnknownParameter`]), gmsh cannot be
/// started ([`MeshError::GmshNotFound`]) or reports errors ([`MeshError::GmshFailed`], with
/// gmsh's own lines).
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
    let tag = format!("{}-{}", std::process::id(), unique());
    let tmp = cache.join(format!(".{stem}-{key}.{tag}.msh"));
    // CAD files get a generated wrapper next to the output.
    let (input, wrapper) = if is_cad(geo) {
        let w = cache.join(format!(".{stem}-{key}.{tag}.geo"));
        std::fs::write(&w, &text).map_err(|e| MeshError::Io {
            file: w.clone(),
            source: e,
        })?;
        (w.clone(), Some(w))
    } else {
        (geo.clone(), None)
    };
    let program = gmsh_program();
    let result = gmsh_command(&program, req, &input, &tmp).output();
    if let Some(w) = &wrapper {
        let _ = std::fs::remove_file(w);
    }
    let output = result.map_err(|e| MeshError::GmshNotFound {
        geometry: geo.clone(),
        program: program.clone(),
        message: e.to_string(),
    })?;
    check_gmsh_output(geo, &output, &tmp)?;
    // Provenance beside the mesh: how it was made.
    let _ = std::fs::write(out.with_extension("toml"), provenance(req, &key));
    std::fs::rename(&tmp, &out).map_err(|e| MeshError::Io {
        file: out.clone(),
        source: e,
    })?;
    Ok(Meshed {
        msh: out,
        from_cache: false,
        key,
    })
}

/// Every `-setnumber` parameter of `req` must be declared by the geometry's `DefineConstant`
/// (`text`: the geometry's source); CAD files declare none.
fn check_parameters(req: &MeshRequest, text: &str) -> Result<(), MeshError> {
    if req.parameters.is_empty() {
        return Ok(());
    }
    let known = if is_cad(&req.geometry) {
        vec![]
    } else {
        defined_parameters(text)
    };
    for name in req.parameters.keys() {
        if !known.contains(name) {
            return Err(MeshError::UnknownParameter {
                geometry: req.geometry.clone(),
                name: name.clone(),
                known,
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

/// gmsh failed when it exited with an error status, printed `Error` lines or wrote no mesh to
/// `tmp` (then removed): [`MeshError::GmshFailed`] with its error lines, or its last 20 lines.
fn check_gmsh_output(
    geo: &Path,
    output: &std::process::Output,
    tmp: &Path,
) -> Result<(), MeshError> {
    let all = format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    );
    let errors: Vec<&str> = all
        .lines()
        .filter(|l| l.trim_start().starts_with("Error"))
        .collect();
    let produced = std::fs::metadata(tmp).map(|m| m.len() > 0).unwrap_or(false);
    if output.status.success() && errors.is_empty() && produced {
        return Ok(());
    }
    let _ = std::fs::remove_file(tmp);
    let message = if errors.is_empty() {
        let tail: Vec<&str> = all.lines().rev().take(20).collect();
        tail.into_iter().rev().collect::<Vec<_>>().join("\n")
    } else {
        errors.join("\n")
    };
    Err(MeshError::GmshFailed {
        geometry: geo.to_path_buf(),
        status: output.status.code(),
        message: if message.trim().is_empty() {
            "no mesh written and no message".into()
        } else {
            message
        },
    })
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
    fn finds_declared_parameters_and_imports() {
        let geo = r#"
// DefineConstant[ commented = 1 ];
DefineConstant[ ri = 0.06, ro = {0.08, Min 0.07, Name "Parameters/ro"},
  h = 0.004 ];
/* Merge "ignored.step"; */
v() = ShapeFromFile( "part.step" );
Include "common.geo";
"#;
        assert_eq!(defined_parameters(geo), vec!["h", "ri", "ro"]);
        assert_eq!(referenced_files(geo), vec!["part.step", "common.geo"]);
    }

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
