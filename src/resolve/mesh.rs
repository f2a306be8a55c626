//! Meshed stators resolved: the geometry file found, meshed by gmsh (through the cache of
//! [`crate::mesh::gmsh`]) or read as a `.msh`, and the `[[stator]]` entry's names turned into
//! station indices and enums. The mesh is checked against the entry (dimension, thickness, plane
//! z = 0 in 2-D, conforming, material regions, cell orientation): [`body`].
//!
//! Relative paths are resolved against the scene file's directory, then its ancestors
//! ([`resolve_path`]). The groups that carry supports, springs, frames and contact are looked
//! up when the model is assembled ([`crate::model::stator::mesh`]).

use super::Clearance;
use crate::element::solid2d::Plane;
use crate::element::{solid2d, solid3d};
use crate::error::{Error, MeshError, ModelError};
use crate::mesh::gmsh::{self, MeshRequest};
use crate::mesh::{CellKind, Mesh};
use crate::scene::validate::{at_most_one, extra_station_index, mesh_plane};
use crate::scene::{LoadedScene, MeshStatorSpec};
use std::path::{Path, PathBuf};

pub use crate::scene::{FrameSpec, RegionSpec, SpringSupportSpec};

/// Where a meshed stator is placed at each speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Placement {
    /// Where the geometry puts it: its clearance is the geometry's.
    AsMeshed,
    /// Translated rigidly along `approach_deg` (degrees from +x, from the station centre toward
    /// the stator) until its nearest contact node is at `clearance` from the rotor surface.
    At {
        /// The clearance δ.
        clearance: Clearance,
        /// Direction of approach (degrees from +x).
        approach_deg: f64,
    },
}

/// What the assembly of a meshed stator needs of its `[[stator]]` entry: materials, the
/// physical groups that carry contact, supports, springs and frames, and damping. Group names
/// are looked up in the mesh when it is assembled.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshStatorParams {
    /// Stator name.
    pub name: String,
    /// Index of the station it faces.
    pub station: usize,
    /// 2-D meshes: plane stress or strain.
    pub plane: Plane,
    /// 2-D meshes: out-of-plane thickness (m); a 2-D mesh needs it.
    pub thickness: Option<f64>,
    /// Young's modulus E (Pa) of the default material.
    pub youngs_modulus: f64,
    /// Poisson's ratio ν of the default material.
    pub poisson_ratio: f64,
    /// Density ρ (kg/m³) of the default material.
    pub density: f64,
    /// Material of particular regions (physical groups of the mesh's dimension).
    pub regions: Vec<RegionSpec>,
    /// Physical group of the contact boundary.
    pub contact_group: String,
    /// Groups whose nodes are fixed in every direction (frame nodes clamped).
    pub fixed: Vec<String>,
    /// Groups whose nodes have u_x = 0.
    pub fixed_x: Vec<String>,
    /// Groups whose nodes have u_y = 0.
    pub fixed_y: Vec<String>,
    /// 3-D meshes: groups whose nodes have u_z = 0.
    pub fixed_z: Vec<String>,
    /// Grounded springs on the nodes of groups.
    pub springs: Vec<SpringSupportSpec>,
    /// Bars and frames on the line elements of groups (2-D meshes).
    pub frames: Vec<FrameSpec>,
    /// Rayleigh damping `[α, β]` (with mass only).
    pub rayleigh: [f64; 2],
    /// 3-D meshes: axial position along the rotor (m) of the mesh's z = 0.
    pub axial_origin: f64,
}

impl MeshStatorParams {
    /// The parameters of `spec` facing station `station`, in `plane`.
    pub fn new(spec: &MeshStatorSpec, station: usize, plane: Plane) -> Self {
        Self {
            name: spec.name.clone(),
            station,
            plane,
            thickness: spec.thickness,
            youngs_modulus: spec.youngs_modulus,
            poisson_ratio: spec.poisson_ratio,
            density: spec.density,
            regions: spec.regions.clone(),
            contact_group: spec.contact_group.clone(),
            fixed: spec.fixed.clone(),
            fixed_x: spec.fixed_x.clone(),
            fixed_y: spec.fixed_y.clone(),
            fixed_z: spec.fixed_z.clone(),
            springs: spec.springs.clone(),
            frames: spec.frames.clone(),
            rayleigh: spec.rayleigh,
            axial_origin: spec.axial_origin,
        }
    }

    /// The parameters of a spec outside a scene file (library use, tests): as [`Self::new`]
    /// with the plane `spec.plane` names, an error when it names none.
    pub fn from_spec(spec: &MeshStatorSpec, station: usize) -> Result<Self, ModelError> {
        let plane = spec.plane().ok_or_else(|| ModelError::Inconsistent {
            what: format!("stator `{}`", spec.name),
            message: "`plane` must be \"stress\" or \"strain\"".into(),
        })?;
        Ok(Self::new(spec, station, plane))
    }
}

/// A meshed stator, resolved: its parameters, the stations its contact nodes may face, its
/// placement and its mesh.
#[derive(Debug, Clone)]
pub struct MeshStatorInput {
    /// Materials, groups, damping.
    pub params: MeshStatorParams,
    /// Stations the contact nodes may face: `params.station` first, then the spec's further
    /// `stations` (3-D meshes assign each contact node to the nearest along the axis).
    pub stations: Vec<usize>,
    /// Placement at each speed.
    pub placement: Placement,
    /// The mesh read.
    pub mesh: Mesh,
    /// Its body, checked against the parameters.
    pub body: MeshBody,
    /// The geometry file it was meshed from (or the `.msh` itself).
    pub geometry: PathBuf,
    /// True when gmsh was not run (mesh from the cache or a `.msh`).
    pub from_cache: bool,
}

/// Resolves meshed stator `i` of a checked scene, facing station `station`: finds the
/// geometry, meshes or reads it.
pub fn resolve(
    ls: &LoadedScene,
    i: usize,
    station: usize,
    spec: &MeshStatorSpec,
) -> Result<MeshStatorInput, Error> {
    let mut stations = vec![station];
    for (j, name) in spec.stations.iter().enumerate() {
        stations.push(extra_station_index(ls, i, j, name)?);
    }
    let params = MeshStatorParams::new(spec, station, mesh_plane(ls, i, spec)?);
    let placement = match at_most_one(
        ls,
        ("clearance", spec.clearance),
        ("clearance_nd", spec.clearance_nd),
        &format!("stator.{i}"),
    )? {
        None => Placement::AsMeshed,
        Some(c) => Placement::At {
            clearance: Clearance::from(c),
            approach_deg: spec.approach_deg,
        },
    };
    check_msh_options(ls, i, spec)?;
    let (mesh, geometry, from_cache) =
        load_mesh(spec, &ls.file).map_err(|e| parameter_key(ls, i, e))?;
    let body = body(&mesh, &params)?;
    Ok(MeshStatorInput {
        params,
        stations,
        placement,
        mesh,
        body,
        geometry,
        from_cache,
    })
}

/// True when a stator's geometry names a mesh file (`.msh`), read as it is.
fn is_msh(geometry: &str) -> bool {
    Path::new(geometry)
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("msh"))
}

/// A `.msh` geometry is read as it is: the keys that only tell gmsh how to mesh a geometry
/// (`parameters`, `order`, `quads`, `serendipity`, `size_factor`) are refused, naming the key,
/// rather than ignored.
fn check_msh_options(ls: &LoadedScene, i: usize, spec: &MeshStatorSpec) -> Result<(), Error> {
    if !is_msh(&spec.geometry) {
        return Ok(());
    }
    let key = if let Some(name) = spec.parameters.keys().next() {
        format!("parameters.{name}")
    } else if spec.order != 1 {
        "order".into()
    } else if spec.quads {
        "quads".into()
    } else if spec.serendipity {
        "serendipity".into()
    } else if spec.size_factor != 1.0 {
        "size_factor".into()
    } else {
        return Ok(());
    };
    let what = key.split('.').next().unwrap_or_default();
    Err(ls
        .invalid(
            &format!("stator.{i}.{key}"),
            format!(
                "`{}` is a mesh, read as it is: `{what}` applies only to a geometry gmsh meshes (`.geo` or CAD); remove it, or name the geometry the mesh came from",
                spec.geometry
            ),
        )
        .into())
}

/// A parameter error of gmsh's request, reported at the scene key that set the parameter
/// (`stator.<i>.parameters.<name>`, with its line); other errors as they are.
fn parameter_key(ls: &LoadedScene, i: usize, e: MeshError) -> Error {
    match &e {
        MeshError::UnknownParameter { name, .. } | MeshError::ParameterOutOfRange { name, .. } => {
            ls.invalid(&format!("stator.{i}.parameters.{name}"), e.to_string())
                .into()
        }
        _ => e.into(),
    }
}

/// Material of a continuum cell of a meshed stator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
    /// Out-of-plane thickness (m) of a 2-D cell; 1 in 3-D.
    pub thickness: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
}

/// A continuum cell of a meshed stator.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// Cell type.
    pub kind: CellKind,
    /// Mesh node indices: counter-clockwise in 2-D, gmsh order (positive volume) in 3-D.
    pub nodes: Vec<usize>,
    /// Material of its region.
    pub material: Material,
}

/// The body of a meshed stator as checked against its parameters: the mesh dimension, the
/// thickness of a 2-D mesh (1 in 3-D) and the continuum cells with their materials.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshBody {
    /// Mesh dimension, 2 or 3.
    pub dim: usize,
    /// Thickness (m) of a 2-D mesh; 1 in 3-D.
    pub thickness: f64,
    /// Continuum cells.
    pub cells: Vec<Cell>,
}

/// Checks the mesh against the parameters (see [`check_mesh`]) and collects its continuum
/// cells, oriented, with the material of their region.
pub fn body(mesh: &Mesh, p: &MeshStatorParams) -> Result<MeshBody, Error> {
    let (dim, thickness) = check_mesh(mesh, p)?;
    let cells = cells(mesh, p, dim, thickness)?;
    Ok(MeshBody {
        dim,
        thickness,
        cells,
    })
}

/// Renumbering that reverses a 2-D cell's orientation.
fn flip_order(kind: CellKind) -> &'static [usize] {
    match kind {
        CellKind::Tri3 => &[0, 2, 1],
        CellKind::Tri6 => &[0, 2, 1, 5, 4, 3],
        CellKind::Quad4 => &[0, 3, 2, 1],
        CellKind::Quad8 => &[0, 3, 2, 1, 7, 6, 5, 4],
        CellKind::Quad9 => &[0, 3, 2, 1, 7, 6, 5, 4, 8],
        _ => &[],
    }
}

/// Checks what the mesh must be for these parameters: nodes, cells of dimension 2 or 3, a
/// thickness for 2-D meshes, a 2-D mesh in the plane z = 0, frames only in 2-D, `fixed_z`
/// only in 3-D, a conforming mesh. Returns the dimension and the thickness (1 in 3-D).
pub fn check_mesh(mesh: &Mesh, p: &MeshStatorParams) -> Result<(usize, f64), Error> {
    let file = &mesh.file;
    let what = format!("stator `{}`", p.name);
    if mesh.nodes.is_empty() {
        return Err(MeshError::Empty {
            file: file.clone(),
            message: "no nodes".into(),
        }
        .into());
    }
    let dim = mesh.dim();
    if dim < 2 {
        return Err(MeshError::Empty {
            file: file.clone(),
            message: format!("no 2-D or 3-D cells (highest cell dimension {dim}); the geometry needs a Physical Surface (2-D) or Physical Volume (3-D) for the stator body"),
        }
        .into());
    }
    let solid = dim == 3;
    let thickness = if solid {
        1.0
    } else {
        p.thickness.ok_or_else(|| ModelError::Inconsistent {
            what: what.clone(),
            message: "a 2-D mesh needs `thickness` (m)".into(),
        })?
    };
    if !solid {
        let scale = mesh
            .nodes
            .iter()
            .map(|p| p[0].abs().max(p[1].abs()))
            .fold(0.0, f64::max);
        if let Some(p) = mesh
            .nodes
            .iter()
            .find(|p| p[2].abs() > 1e-9 * scale.max(1e-3))
        {
            return Err(bad_group(
                file,
                "(all)",
                format!(
                    "a 2-D stator mesh must lie in the station plane z = 0; a node is at z = {:.3e} m",
                    p[2]
                ),
            ));
        }
    } else if let Some(fr) = p.frames.first() {
        return Err(ModelError::Inconsistent {
            what,
            message: format!(
                "frames (group `{}`) are for 2-D meshes; this mesh is 3-D",
                fr.group
            ),
        }
        .into());
    }
    if !p.fixed_z.is_empty() && !solid {
        return Err(ModelError::Inconsistent {
            what,
            message: format!(
                "`fixed_z` (group `{}`) applies to 3-D meshes; this mesh is 2-D",
                p.fixed_z[0]
            ),
        }
        .into());
    }
    mesh.check_conforming()?;
    Ok((dim, thickness))
}

/// The material of the cells of entity `entity`: the default, overridden by the `regions`
/// whose group holds the entity; with the name of its region for messages.
fn region_of(
    mesh: &Mesh,
    p: &MeshStatorParams,
    dim: usize,
    default: Material,
    entity: i32,
) -> (Material, String) {
    let groups: Vec<&crate::mesh::Group> = mesh
        .groups
        .iter()
        .filter(|g| g.dim == dim && g.entities.contains(&entity))
        .collect();
    let mut reg = default;
    let mut name = groups
        .first()
        .map_or_else(|| format!("(entity {entity})"), |g| g.name.clone());
    for r in &p.regions {
        if groups.iter().any(|g| g.name == r.group) {
            reg.youngs_modulus = r.youngs_modulus.unwrap_or(reg.youngs_modulus);
            reg.poisson_ratio = r.poisson_ratio.unwrap_or(reg.poisson_ratio);
            reg.thickness = r.thickness.unwrap_or(reg.thickness);
            reg.density = r.density.unwrap_or(reg.density);
            name = r.group.clone();
        }
    }
    (reg, name)
}

/// The continuum cells with their materials: 2-D cells oriented counter-clockwise (a surface
/// clockwise throughout is renumbered), tetrahedra positive; an inverted cell is an error.
fn cells(
    mesh: &Mesh,
    p: &MeshStatorParams,
    dim: usize,
    thickness: f64,
) -> Result<Vec<Cell>, Error> {
    let file = &mesh.file;
    let solid = dim == 3;
    // Material regions: groups of the mesh's dimension.
    for r in &p.regions {
        let g = mesh.group(&r.group)?;
        if g.dim != dim {
            return Err(bad_group(
                file,
                &r.group,
                format!("a material region of a {dim}-D mesh must be a group of dimension {dim}, this one has dimension {}", g.dim),
            ));
        }
    }
    let default = Material {
        youngs_modulus: p.youngs_modulus,
        poisson_ratio: p.poisson_ratio,
        thickness,
        density: p.density,
    };
    let mut cells: Vec<Cell> = Vec::new();
    let mut x2 = [[0.0; 2]; solid2d::MAX_NODES];
    let mut x3 = [[0.0; 3]; solid3d::MAX_NODES];
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == dim) {
        let (reg, gname) = region_of(mesh, p, dim, default, b.entity);
        let nn = b.kind.nodes();
        let mut dets = Vec::with_capacity(b.len());
        for cell in b.cells() {
            dets.push(if solid {
                for (k, &n) in cell.iter().enumerate() {
                    x3[k] = mesh.nodes[n];
                }
                solid3d::det_j_range(b.kind, &x3[..nn])
            } else {
                for (k, &n) in cell.iter().enumerate() {
                    x2[k] = [mesh.nodes[n][0], mesh.nodes[n][1]];
                }
                solid2d::det_j_range(b.kind, &x2[..nn])
            });
        }
        // A 2-D surface meshed with normal −z is clockwise throughout: renumber it. Solids
        // are not renumbered (gmsh writes positive tetrahedra).
        let ccw = dets.iter().filter(|d| d.0 > 0.0).count();
        let cw = dets.iter().filter(|d| d.1 < 0.0).count();
        let flip = !solid && cw > ccw;
        let bad: Vec<usize> = (0..b.len())
            .filter(|&i| {
                if flip {
                    dets[i].1 >= 0.0
                } else {
                    dets[i].0 <= 0.0
                }
            })
            .collect();
        if let Some(&i) = bad.first() {
            return Err(MeshError::Inverted {
                file: file.clone(),
                group: gname,
                element: b.tags[i],
                det: if flip { -dets[i].1 } else { dets[i].0 },
                count: bad.len(),
            }
            .into());
        }
        for cell in b.cells() {
            let nodes: Vec<usize> = if flip {
                flip_order(b.kind).iter().map(|&k| cell[k]).collect()
            } else {
                cell.to_vec()
            };
            cells.push(Cell {
                kind: b.kind,
                nodes,
                material: reg,
            });
        }
    }
    if cells.is_empty() {
        return Err(MeshError::Empty {
            file: file.clone(),
            message: format!("no {dim}-D cells"),
        }
        .into());
    }
    Ok(cells)
}

pub(crate) fn bad_group(file: &Path, group: &str, message: impl Into<String>) -> Error {
    MeshError::BadGroup {
        file: file.to_path_buf(),
        group: group.to_string(),
        message: message.into(),
    }
    .into()
}

/// Resolves a path named in a scene: absolute, or relative to the scene file's directory or
/// the nearest of its ancestors where it exists.
pub fn resolve_path(given: &str, scene_file: &Path) -> Result<PathBuf, MeshError> {
    let p = Path::new(given);
    if p.is_absolute() {
        return if p.exists() {
            Ok(p.to_path_buf())
        } else {
            Err(MeshError::MissingFile {
                file: p.to_path_buf(),
                referenced_by: Some(scene_file.to_path_buf()),
            })
        };
    }
    let start = scene_file.parent().unwrap_or(Path::new(""));
    let mut dir = Some(start);
    while let Some(d) = dir {
        let c = d.join(p);
        if c.exists() {
            return Ok(c);
        }
        dir = d.parent();
    }
    Err(MeshError::MissingFile {
        file: start.join(p),
        referenced_by: Some(scene_file.to_path_buf()),
    })
}

/// Meshes (or reads) the geometry of a meshed-stator spec: `(mesh, geometry path, from cache)`.
pub fn load_mesh(
    spec: &MeshStatorSpec,
    scene_file: &Path,
) -> Result<(Mesh, PathBuf, bool), MeshError> {
    let geo = resolve_path(&spec.geometry, scene_file)?;
    if geo.extension().and_then(|e| e.to_str()) == Some("msh") {
        let m = Mesh::read(&geo)?;
        return Ok((m, geo, true));
    }
    let req = MeshRequest {
        geometry: geo.clone(),
        parameters: spec.parameters.clone(),
        order: spec.order,
        recombine: spec.quads,
        serendipity: spec.serendipity,
        size_factor: spec.size_factor,
        referenced_by: Some(scene_file.to_path_buf()),
        time_limit: None,
    };
    let (mesh, meshed) = gmsh::mesh_and_read(&req, &gmsh::default_cache_dir(&geo))?;
    Ok((mesh, geo, meshed.from_cache))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolves_paths_against_scene_ancestors() {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path();
        std::fs::create_dir_all(root.join("geometry")).unwrap();
        std::fs::create_dir_all(root.join("scenes/stators")).unwrap();
        std::fs::write(root.join("geometry/a.geo"), "").unwrap();
        let scene = root.join("scenes/stators/s.toml");
        assert_eq!(
            resolve_path("geometry/a.geo", &scene).unwrap(),
            root.join("geometry/a.geo")
        );
        let e = resolve_path("geometry/missing.geo", &scene)
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing.geo") && e.contains("s.toml"), "{e}");
    }
}
