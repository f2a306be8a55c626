//! `rubsim mesh`: mesh a geometry through gmsh (or take it from the cache) and report it; a
//! `.msh` file is reported as it is.

use anyhow::{bail, Context, Result};
use rubsim::mesh::gmsh::{self, MeshRequest};
use rubsim::mesh::Mesh;
use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Options of `rubsim mesh`.
#[derive(clap::Args, Clone, Debug)]
pub struct MeshArgs {
    /// Geometry: a gmsh `.geo`, or a CAD file (`.step`, `.stp`, `.brep`, `.iges`, `.igs`); or a
    /// mesh (`.msh`, MSH 4.1), reported without meshing.
    pub geometry: PathBuf,
    /// Set a geometry parameter (declared by its `DefineConstant`): `--set ri=0.0601` (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Element order (1 linear, 2 quadratic).
    #[arg(long, default_value_t = 1)]
    pub order: u8,
    /// Recombine triangles into quadrilaterals.
    #[arg(long)]
    pub quads: bool,
    /// Second order without the face-centre node (8-node quadrilaterals).
    #[arg(long)]
    pub serendipity: bool,
    /// Factor on every mesh size.
    #[arg(long, default_value_t = 1.0)]
    pub size_factor: f64,
    /// Cache directory (default: `meshes/` beside the geometry's `geometry/` directory).
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// Also copy the mesh to this file.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Seconds gmsh may run before it is stopped (default: $RUBSIM_GMSH_TIMEOUT, else 300).
    #[arg(long, value_name = "SECONDS")]
    pub timeout: Option<f64>,
    /// Physical group of the contact boundary to report, as a scene's `contact_group` names it
    /// (default `stator_contact`; a mesh without it gets a warning, without a named one an error).
    #[arg(long, value_name = "GROUP")]
    pub contact_group: Option<String>,
}

fn parse_set(set: &[String]) -> Result<BTreeMap<String, f64>> {
    let mut p = BTreeMap::new();
    for a in set {
        let (k, v) = a
            .split_once('=')
            .with_context(|| format!("--set {a}: expected NAME=VALUE"))?;
        let v: f64 = v
            .trim()
            .parse()
            .with_context(|| format!("--set {a}: `{}` is not a number", v.trim()))?;
        if !v.is_finite() {
            bail!("--set {a}: the value must be finite");
        }
        p.insert(k.trim().to_string(), v);
    }
    Ok(p)
}

/// Runs `rubsim mesh`.
pub fn mesh(a: &MeshArgs) -> Result<()> {
    if is_mesh_file(&a.geometry)? {
        let m = Mesh::read(&a.geometry)?;
        println!(
            "{}: a mesh, read as it is (gmsh not run)",
            a.geometry.display()
        );
        return report(&m, a.contact_group.as_deref());
    }
    let time_limit = match a.timeout {
        None => None,
        Some(t) if t.is_finite() && t > 0.0 && t < 1e9 => Some(Duration::from_secs_f64(t)),
        Some(t) => bail!("--timeout must be a positive number of seconds, got {t}"),
    };
    let req = MeshRequest {
        geometry: a.geometry.clone(),
        parameters: parse_set(&a.set)?,
        order: a.order,
        recombine: a.quads,
        serendipity: a.serendipity,
        size_factor: a.size_factor,
        referenced_by: None,
        time_limit,
    };
    if !(a.size_factor.is_finite() && a.size_factor > 0.0) {
        bail!("--size-factor must be positive, got {}", a.size_factor);
    }
    let cache = a
        .cache
        .clone()
        .unwrap_or_else(|| gmsh::default_cache_dir(&a.geometry));
    let t0 = std::time::Instant::now();
    let meshed = gmsh::mesh(&req, &cache)?;
    let took = t0.elapsed().as_secs_f64();
    let m = Mesh::read(&meshed.msh)?;
    println!(
        "{}: {} ({})",
        a.geometry.display(),
        meshed.msh.display(),
        if meshed.from_cache {
            "up to date, gmsh not run".to_string()
        } else {
            format!("meshed by gmsh in {took:.2} s")
        }
    );
    report(&m, a.contact_group.as_deref())?;
    if let Some(out) = &a.out {
        std::fs::copy(&meshed.msh, out)
            .with_context(|| format!("copying the mesh to {}", out.display()))?;
        println!("copied to {}", out.display());
    }
    Ok(())
}

/// True for a gmsh mesh: named `.msh`, or starting with `$MeshFormat` (ASCII or binary). The
/// options that tell gmsh how to mesh do not apply to it.
fn is_mesh_file(path: &Path) -> Result<bool> {
    let named = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("msh"));
    let mut head = [0u8; 11];
    let starts = std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok()
        && &head == b"$MeshFormat";
    Ok(named || starts)
}

/// Prints nodes, cells per kind, groups, and checks conformity and the contact boundary
/// `contact` (a warning naming the candidate groups when the mesh has none of that name: a rub
/// run needs one).
fn report(m: &Mesh, named: Option<&str>) -> Result<()> {
    let contact = named.unwrap_or("stator_contact");
    let s = m.summary();
    let [lo, hi] = s.bounds;
    println!(
        "  {}-D mesh, {} nodes, bounding box [{:.4e}, {:.4e}] × [{:.4e}, {:.4e}] × [{:.4e}, {:.4e}] m",
        s.dim, s.nodes, lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
    );
    for (k, n) in &s.cells {
        println!("  {n} × {k}");
    }
    for g in &s.groups {
        println!(
            "  group `{}` (dim {}, tag {}): {} entities, {} elements, {} nodes",
            g.name, g.dim, g.tag, g.entities, g.elements, g.nodes
        );
    }
    m.check_conforming()?;
    println!("  conforming: no coincident or hanging nodes");
    match m.boundary_summary(contact)? {
        Some(b) => println!(
            "  {contact}: {} nodes at radius {:.6e} … {:.6e} m from the axis; {} of them face the axis (outward normal pointing inward)",
            b.nodes, b.radius[0], b.radius[1], b.facing_axis
        ),
        None if named.is_some() => {
            m.group(contact)?;
        }
        None => {
            let boundary: Vec<String> = s
                .groups
                .iter()
                .filter(|g| s.dim > 0 && g.dim + 1 == s.dim)
                .map(|g| format!("`{}`", g.name))
                .collect();
            eprintln!(
                "warning: {}: no physical group `{contact}`: a stator needs a contact boundary to rub on ({}); {}",
                m.file.display(),
                if s.dim == 3 { "surfaces" } else { "curves" },
                if boundary.is_empty() {
                    format!("define one in the geometry with Physical {}(\"{contact}\")", if s.dim == 3 { "Surface" } else { "Curve" })
                } else {
                    format!("groups that could be one: {} (a scene names it with `contact_group`; `rubsim mesh --contact-group NAME` reports it)", boundary.join(", "))
                }
            );
        }
    }
    Ok(())
}
