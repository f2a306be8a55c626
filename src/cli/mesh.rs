//! `rubsim mesh`: mesh a geometry through gmsh (or take it from the cache) and report it.

use anyhow::{bail, Context, Result};
use rubsim::mesh::gmsh::{self, MeshRequest};
use rubsim::mesh::Mesh;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Options of `rubsim mesh`.
#[derive(clap::Args, Clone, Debug)]
pub struct MeshArgs {
    /// Geometry: a gmsh `.geo`, or a CAD file (`.step`, `.stp`, `.brep`, `.iges`, `.igs`).
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
    let req = MeshRequest {
        geometry: a.geometry.clone(),
        parameters: parse_set(&a.set)?,
        order: a.order,
        recombine: a.quads,
        serendipity: a.serendipity,
        size_factor: a.size_factor,
        referenced_by: None,
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
    report(&m)?;
    if let Some(out) = &a.out {
        std::fs::copy(&meshed.msh, out)
            .with_context(|| format!("copying the mesh to {}", out.display()))?;
        println!("copied to {}", out.display());
    }
    Ok(())
}

/// Prints nodes, cells per kind, groups, and checks conformity and the contact boundary.
fn report(m: &Mesh) -> Result<()> {
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
    if let Some(b) = m.boundary_summary("stator_contact")? {
        println!(
            "  stator_contact: {} nodes at radius {:.6e} … {:.6e} m from the axis; {} of them face the axis (outward normal pointing inward)",
            b.nodes, b.radius[0], b.radius[1], b.facing_axis
        );
    }
    Ok(())
}
