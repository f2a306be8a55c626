//! Meshed stators: a gmsh mesh and a scene's `kind = "mesh"` stator become a [`StatorModel`].
//!
//! The pipeline: resolve the geometry path ([`resolve_path`]), mesh it through gmsh with the
//! cache ([`crate::mesh::gmsh`]) or read a `.msh`, check the mesh (conforming, cells oriented,
//! groups present with the right dimension), then assemble over free DOFs:
//!
//! * 2-D continuum cells of every material region ([`crate::element::solid2d`], plane stress or
//!   strain, thickness per region), HRZ-lumped mass;
//! * bars and frames on line groups ([`crate::element::frame`]): frames add a rotation DOF
//!   θ_z at their nodes, numbered after every translation DOF;
//! * grounded springs on the nodes of a group;
//! * fixed components from the `fixed*` groups;
//! * contact targets: the nodes of the contact group, with their outward normals.
//!
//! The model is speed independent; [`place`] moves it rigidly to a clearance at each speed.
//!
//! # Conventions
//!
//! Coordinates relative to the undeformed station centre (m); node DOFs `[u_x, u_y]` as every
//! stator ([`StatorModel`]); 2-D meshes lie in the plane z = 0. A cell whose nodes run clockwise
//! (a surface meshed with normal −z) is renumbered counter-clockwise when its whole surface is
//! clockwise; a cell oriented against the rest of its surface, folded or degenerate, is an
//! error ([`MeshError::Inverted`]).

use super::stator::{StatorElement, StatorModel};
use crate::assembly::scatter;
use crate::contact::Target;
use crate::element::frame::{self, FrameSection};
use crate::element::solid2d::{self, Elastic2, Plane};
use crate::element::solid3d::{self, Elastic3};
use crate::error::{Error, MeshError, ModelError};
use crate::linalg::{Cholesky, Csc};
use crate::math::V2;
use crate::mesh::gmsh::{self, MeshRequest};
use crate::mesh::{CellKind, Mesh};
use crate::scene::MeshStatorSpec;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};

/// What a meshed stator keeps beyond [`StatorModel`]: where its mesh came from and the
/// speed-independent quantities computed once and shared by every speed of a sweep.
#[derive(Debug)]
pub struct MeshStatorData {
    /// The mesh file read (in the cache, or the scene's `.msh`).
    pub mesh_file: PathBuf,
    /// The geometry it was meshed from.
    pub geometry: PathBuf,
    /// True when gmsh was not run (mesh from the cache or a `.msh`).
    pub from_cache: bool,
    /// Mesh dimension (2 or 3).
    pub dim: usize,
    /// Number of continuum cells.
    pub cells: usize,
    /// Outward unit normal of the body at each contact target, projected on the station
    /// plane (same order as `targets`).
    pub contact_normals: Vec<V2>,
    /// Station each contact target faces (same order as `targets`).
    pub target_station: Vec<usize>,
    /// 3-D stators: axial coordinate z of every node (m, mesh frame); empty in 2-D.
    pub node_z: Vec<f64>,
    /// 3-D stators: free DOF of u_z of every node; empty in 2-D.
    pub axial_dofs: Vec<Option<usize>>,
    /// Stators with mass: upper bound of the largest eigenvalue of `M⁻¹K` (rad²/s²) from the
    /// elements (Irons' element eigenvalue theorem: `λ_max ≤ max_e λ_max(K_e, M_e)`), tighter
    /// than Gershgorin; `None` when it does not apply (massless, springs, bars or frames).
    pub omega_max_sq: Option<f64>,
    /// Contact stiffness bound (N/m), computed on first use (invariant under placement).
    pub contact_stiffness: OnceLock<f64>,
    /// Sparse Cholesky factor of K, computed on first use and shared by every run.
    pub factor: OnceLock<Result<Arc<Cholesky>, String>>,
}

impl MeshStatorData {
    /// The Cholesky factor of `k` (the model's stiffness), factored once.
    pub fn factor(&self, k: &Csc) -> Result<Arc<Cholesky>, String> {
        self.factor
            .get_or_init(|| Cholesky::new(k).map(Arc::new))
            .clone()
    }
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
    };
    let (mesh, meshed) = gmsh::mesh_and_read(&req, &gmsh::default_cache_dir(&geo))?;
    Ok((mesh, geo, meshed.from_cache))
}

/// Builds the speed-independent model of a meshed stator facing station `station`;
/// `stations_z` lists `(station index, axial position z (m))` of the stations a 3-D stator's
/// contact nodes may be assigned to (see [`from_mesh`]).
pub fn build(
    spec: &MeshStatorSpec,
    scene_file: &Path,
    station: usize,
    stations_z: &[(usize, f64)],
) -> Result<StatorModel, Error> {
    let (mesh, geo, from_cache) = load_mesh(spec, scene_file)?;
    from_mesh(&mesh, spec, station, stations_z, geo, from_cache)
}

/// Material of a continuum cell.
#[derive(Debug, Clone, Copy)]
struct Region {
    youngs_modulus: f64,
    poisson_ratio: f64,
    thickness: f64,
    density: f64,
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

fn bad_group(file: &Path, group: &str, message: impl Into<String>) -> Error {
    MeshError::BadGroup {
        file: file.to_path_buf(),
        group: group.to_string(),
        message: message.into(),
    }
    .into()
}

/// Builds a [`StatorModel`] from a mesh (see the module documentation).
///
/// 2-D meshes (cells in the plane z = 0) give plane stress or strain bodies of thickness
/// `spec.thickness`; 3-D meshes (tetrahedra) give solids with an axial DOF u_z per node (kept in
/// [`MeshStatorData::axial_dofs`]; contact acts in the station plane). Each contact node of a
/// 3-D stator is assigned to the station of `stations_z` nearest to its axial position
/// `z + spec.axial_origin`; 2-D stators (and 3-D ones with fewer than two candidate stations)
/// face `station`.
pub fn from_mesh(
    mesh: &Mesh,
    spec: &MeshStatorSpec,
    station: usize,
    stations_z: &[(usize, f64)],
    geometry: PathBuf,
    from_cache: bool,
) -> Result<StatorModel, Error> {
    let file = &mesh.file;
    let what = format!("stator `{}`", spec.name);
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
        spec.thickness.ok_or_else(|| ModelError::Inconsistent {
            what: what.clone(),
            message: "a 2-D mesh needs `thickness` (m)".into(),
        })?
    };
    let plane = if spec.plane == "strain" {
        Plane::Strain
    } else {
        Plane::Stress
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
    } else if let Some(fr) = spec.frames.first() {
        return Err(ModelError::Inconsistent {
            what,
            message: format!(
                "frames (group `{}`) are for 2-D meshes; this mesh is 3-D",
                fr.group
            ),
        }
        .into());
    }
    if !spec.fixed_z.is_empty() && !solid {
        return Err(ModelError::Inconsistent {
            what,
            message: format!(
                "`fixed_z` (group `{}`) applies to 3-D meshes; this mesh is 2-D",
                spec.fixed_z[0]
            ),
        }
        .into());
    }
    mesh.check_conforming()?;

    // Material regions: groups of the mesh's dimension.
    for r in &spec.regions {
        let g = mesh.group(&r.group)?;
        if g.dim != dim {
            return Err(bad_group(
                file,
                &r.group,
                format!("a material region of a {dim}-D mesh must be a group of dimension {dim}, this one has dimension {}", g.dim),
            ));
        }
    }
    let default = Region {
        youngs_modulus: spec.youngs_modulus,
        poisson_ratio: spec.poisson_ratio,
        thickness,
        density: spec.density,
    };
    let region_of = |entity: i32| -> (Region, String) {
        let groups: Vec<&crate::mesh::Group> = mesh
            .groups
            .iter()
            .filter(|g| g.dim == dim && g.entities.contains(&entity))
            .collect();
        let mut reg = default;
        let mut name = groups
            .first()
            .map_or_else(|| format!("(entity {entity})"), |g| g.name.clone());
        for r in &spec.regions {
            if groups.iter().any(|g| g.name == r.group) {
                reg.youngs_modulus = r.youngs_modulus.unwrap_or(reg.youngs_modulus);
                reg.poisson_ratio = r.poisson_ratio.unwrap_or(reg.poisson_ratio);
                reg.thickness = r.thickness.unwrap_or(reg.thickness);
                reg.density = r.density.unwrap_or(reg.density);
                name = r.group.clone();
            }
        }
        (reg, name)
    };

    // Continuum cells: 2-D oriented counter-clockwise, tetrahedra positive.
    let mut cells: Vec<(CellKind, Vec<usize>, Region)> = Vec::new();
    let mut x2 = [[0.0; 2]; solid2d::MAX_NODES];
    let mut x3 = [[0.0; 3]; solid3d::MAX_NODES];
    for b in mesh.blocks.iter().filter(|b| b.kind.dim() == dim) {
        let (reg, gname) = region_of(b.entity);
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
            cells.push((b.kind, nodes, reg));
        }
    }
    if cells.is_empty() {
        return Err(MeshError::Empty {
            file: file.clone(),
            message: format!("no {dim}-D cells"),
        }
        .into());
    }

    // Line groups carrying bars and frames (2-D).
    let mut lines: Vec<([usize; 2], &crate::scene::FrameSpec)> = Vec::new();
    for fr in &spec.frames {
        let g = mesh.group(&fr.group)?;
        if g.dim != 1 {
            return Err(bad_group(
                file,
                &fr.group,
                format!(
                    "bars and frames need a curve group (dimension 1), this one has dimension {}",
                    g.dim
                ),
            ));
        }
        for b in mesh.group_blocks(g) {
            if !matches!(b.kind, CellKind::Line2 | CellKind::Line3) {
                return Err(MeshError::UnsupportedCell {
                    file: file.clone(),
                    group: fr.group.clone(),
                    kind: format!("{} (bars and frames take lines)", b.kind.name()),
                    count: b.len(),
                }
                .into());
            }
            // A 3-node line (second-order mesh) is one straight element between its ends; its
            // middle node belongs to no element and gets no DOF.
            lines.extend(b.cells().map(|c| ([c[0], c[1]], fr)));
        }
        if !lines.iter().any(|l| std::ptr::eq(l.1, fr)) {
            return Err(bad_group(file, &fr.group, "the group has no line elements"));
        }
    }
    let spring_nodes: Vec<(Vec<usize>, [f64; 2])> = spec
        .springs
        .iter()
        .map(|s| Ok((mesh.group_nodes(&s.group)?, s.stiffness)))
        .collect::<Result<_, MeshError>>()?;

    // Nodes that carry DOFs, fixed components.
    let nn = mesh.nodes.len();
    let mut used = vec![false; nn];
    for (_, c, _) in &cells {
        for &n in c {
            used[n] = true;
        }
    }
    for (l, _) in &lines {
        used[l[0]] = true;
        used[l[1]] = true;
    }
    let mut fixed = vec![[false; 3]; nn];
    for (names, comps) in [
        (&spec.fixed, &[0usize, 1, 2][..]),
        (&spec.fixed_x, &[0][..]),
        (&spec.fixed_y, &[1][..]),
        (&spec.fixed_z, &[2][..]),
    ] {
        for name in names {
            for n in mesh.group_nodes(name)? {
                for &c in comps {
                    fixed[n][c] = true;
                }
            }
        }
    }
    let ncomp = if solid { 3 } else { 2 };
    let mut ndof = 0;
    let mut node_dofs: Vec<[Option<usize>; 2]> = vec![[None, None]; nn];
    let mut axial_dofs: Vec<Option<usize>> = if solid { vec![None; nn] } else { vec![] };
    for n in (0..nn).filter(|&n| used[n]) {
        for c in 0..ncomp {
            if !fixed[n][c] {
                if c < 2 {
                    node_dofs[n][c] = Some(ndof);
                } else {
                    axial_dofs[n] = Some(ndof);
                }
                ndof += 1;
            }
        }
    }
    // The DOFs of a node in element order ([x, y] or [x, y, z]).
    let dofs_of = |n: usize, out: &mut Vec<Option<usize>>| {
        out.push(node_dofs[n][0]);
        out.push(node_dofs[n][1]);
        if solid {
            out.push(axial_dofs[n]);
        }
    };
    // Rotation DOFs of frame nodes; nodes of the `fixed` groups are clamped (θ fixed too).
    let mut clamped = vec![false; nn];
    for name in &spec.fixed {
        for n in mesh.group_nodes(name)? {
            clamped[n] = true;
        }
    }
    let mut rot: HashMap<usize, Option<usize>> = HashMap::new();
    for (l, fr) in &lines {
        if fr.inertia.is_some() {
            for &n in l {
                rot.entry(n).or_insert_with(|| {
                    (!clamped[n]).then(|| {
                        ndof += 1;
                        ndof - 1
                    })
                });
            }
        }
    }

    // Assembly.
    let per_cell: usize = cells
        .iter()
        .map(|c| (ncomp * c.0.nodes()).pow(2))
        .sum::<usize>();
    let mut kt: Vec<(usize, usize, f64)> = Vec::with_capacity(per_cell + 36 * lines.len());
    let mut mass = vec![0.0; ndof];
    let mut elements: Vec<StatorElement> = Vec::with_capacity(cells.len() + lines.len());
    let mut ke = vec![0.0; (3 * solid3d::MAX_NODES).pow(2)];
    let mut ml = [0.0; solid3d::MAX_NODES];
    let mut dofs: Vec<Option<usize>> = Vec::with_capacity(3 * solid3d::MAX_NODES);
    let mut element_bound = 0.0_f64;
    for (kind, nodes, reg) in &cells {
        let nn = kind.nodes();
        let ke = &mut ke[..(ncomp * nn).pow(2)];
        if solid {
            for (k, &n) in nodes.iter().enumerate() {
                x3[k] = mesh.nodes[n];
            }
            let material = Elastic3 {
                youngs_modulus: reg.youngs_modulus,
                poisson_ratio: reg.poisson_ratio,
            };
            solid3d::stiffness(*kind, &x3[..nn], &material, ke);
            if reg.density > 0.0 {
                solid3d::mass_lumped(*kind, &x3[..nn], reg.density, &mut ml);
            }
            elements.push(StatorElement::Solid3 {
                kind: *kind,
                nodes: nodes.clone(),
                material,
            });
        } else {
            for (k, &n) in nodes.iter().enumerate() {
                x2[k] = [mesh.nodes[n][0], mesh.nodes[n][1]];
            }
            let material = Elastic2 {
                youngs_modulus: reg.youngs_modulus,
                poisson_ratio: reg.poisson_ratio,
                thickness: reg.thickness,
                plane,
            };
            solid2d::stiffness(*kind, &x2[..nn], &material, ke);
            if reg.density > 0.0 {
                solid2d::mass_lumped(*kind, &x2[..nn], reg.density * reg.thickness, &mut ml);
            }
            elements.push(StatorElement::Solid2 {
                kind: *kind,
                nodes: nodes.clone(),
                material,
            });
        }
        dofs.clear();
        for &n in nodes {
            dofs_of(n, &mut dofs);
        }
        scatter(&mut kt, &dofs, ke);
        if reg.density > 0.0 {
            // Element eigenvalue bound (Irons): λ_max(K, M) ≤ max_e λ_max(K_e, M_e) with the
            // element's lumped mass, on its free DOFs.
            let free: Vec<usize> = (0..dofs.len()).filter(|&i| dofs[i].is_some()).collect();
            if !free.is_empty() {
                let nd = dofs.len();
                let a = nalgebra::DMatrix::from_fn(free.len(), free.len(), |i, j| {
                    let (fi, fj) = (free[i], free[j]);
                    ke[fi * nd + fj] / (ml[fi / ncomp] * ml[fj / ncomp]).sqrt()
                });
                let lmax = a.symmetric_eigenvalues().max();
                element_bound = element_bound.max(lmax);
            }
            for (k, m) in ml[..nn].iter().enumerate() {
                for d in dofs[ncomp * k..ncomp * (k + 1)].iter().flatten() {
                    mass[*d] += m;
                }
            }
        }
    }
    for (l, fr) in &lines {
        let a = [mesh.nodes[l[0]][0], mesh.nodes[l[0]][1]];
        let b = [mesh.nodes[l[1]][0], mesh.nodes[l[1]][1]];
        let length = (b[0] - a[0]).hypot(b[1] - a[1]);
        if length <= 0.0 {
            return Err(bad_group(file, &fr.group, "a zero-length line element"));
        }
        match fr.inertia {
            None => {
                let mut kb = [0.0; 16];
                frame::bar_stiffness(a, b, fr.youngs_modulus * fr.area, &mut kb);
                let d = [node_dofs[l[0]], node_dofs[l[1]]].concat();
                scatter(&mut kt, &d, &kb);
                let half = fr.density * fr.area * length / 2.0;
                for &n in l {
                    for d in node_dofs[n].iter().flatten() {
                        mass[*d] += half;
                    }
                }
                elements.push(StatorElement::Bar {
                    nodes: *l,
                    ea: fr.youngs_modulus * fr.area,
                    youngs_modulus: fr.youngs_modulus,
                    length,
                });
            }
            Some(inertia) => {
                let section = FrameSection {
                    youngs_modulus: fr.youngs_modulus,
                    shear_modulus: fr.youngs_modulus / (2.0 * (1.0 + fr.poisson_ratio)),
                    area: fr.area,
                    inertia,
                    shear_factor: fr.shear_factor,
                    density: fr.density,
                };
                let mut kf = [0.0; 36];
                frame::frame_stiffness(a, b, &section, &mut kf);
                let rot_dofs = [rot[&l[0]], rot[&l[1]]];
                let d = [
                    node_dofs[l[0]][0],
                    node_dofs[l[0]][1],
                    rot_dofs[0],
                    node_dofs[l[1]][0],
                    node_dofs[l[1]][1],
                    rot_dofs[1],
                ];
                scatter(&mut kt, &d, &kf);
                let [mt, mr] = frame::frame_mass_lumped(a, b, &section);
                for (k, &n) in l.iter().enumerate() {
                    for d in node_dofs[n].iter().flatten() {
                        mass[*d] += mt;
                    }
                    if let Some(r) = rot_dofs[k] {
                        mass[r] += mr;
                    }
                }
                elements.push(StatorElement::Frame {
                    nodes: *l,
                    rot_dofs,
                    section,
                    length,
                });
            }
        }
    }
    for (nodes, k) in &spring_nodes {
        let share = 1.0 / nodes.len() as f64;
        for &n in nodes {
            for (c, kc) in k.iter().enumerate() {
                if *kc > 0.0 {
                    if let Some(d) = node_dofs[n][c] {
                        kt.push((d, d, kc * share));
                    }
                    let dir = if c == 0 { [1.0, 0.0] } else { [0.0, 1.0] };
                    elements.push(StatorElement::Spring {
                        node: n,
                        stiffness: kc * share,
                        dir,
                    });
                }
            }
        }
    }
    let k = Csc::from_triplets(ndof, ndof, &kt);
    drop(kt);
    let total_mass: f64 = mass.iter().sum();
    if total_mass > 0.0 {
        if let Some(d) = mass.iter().position(|m| *m <= 0.0) {
            return Err(ModelError::Inconsistent {
                what,
                message: format!(
                    "free DOF {d} has no mass while the stator has mass (frames and bars need a density when the body has one)"
                ),
            }
            .into());
        }
    }
    let m = Csc::from_triplets(
        ndof,
        ndof,
        &mass
            .iter()
            .enumerate()
            .filter(|(_, v)| **v > 0.0)
            .map(|(i, v)| (i, i, *v))
            .collect::<Vec<_>>(),
    );
    let c = if total_mass > 0.0 {
        Csc::lin_comb(spec.rayleigh[0], &m, spec.rayleigh[1], &k)
    } else {
        Csc::zeros(ndof, ndof)
    };

    // Contact targets with their outward normals and stations.
    let normals = mesh.boundary_normals(&spec.contact_group)?;
    let mut targets = Vec::with_capacity(normals.len());
    let mut contact_normals = Vec::with_capacity(normals.len());
    let mut target_station = Vec::with_capacity(normals.len());
    for (n, nv) in &normals {
        if !used[*n] {
            return Err(bad_group(
                file,
                &spec.contact_group,
                format!(
                    "node {} belongs to no element of the stator",
                    mesh.node_tags[*n]
                ),
            ));
        }
        targets.push(Target::Node {
            node: *n,
            x0: [mesh.nodes[*n][0], mesh.nodes[*n][1]],
            dofs: node_dofs[*n],
        });
        let h = nv[0].hypot(nv[1]);
        contact_normals.push(if h > 0.0 {
            [nv[0] / h, nv[1] / h]
        } else {
            [0.0, 0.0]
        });
        let z = mesh.nodes[*n][2] + spec.axial_origin;
        target_station.push(if solid && stations_z.len() > 1 {
            stations_z
                .iter()
                .min_by(|a, b| (a.1 - z).abs().total_cmp(&(b.1 - z).abs()))
                .map_or(station, |s| s.0)
        } else {
            station
        });
    }
    if targets.iter().all(|t| t.dofs() == [None, None]) {
        return Err(bad_group(
            file,
            &spec.contact_group,
            "every contact node is fixed: the rotor would hit a rigid wall",
        ));
    }
    // The element bound holds when every element carrying stiffness carries its own mass.
    let omega_max_sq = (total_mass > 0.0
        && lines.is_empty()
        && spring_nodes.is_empty()
        && cells.iter().all(|c| c.2.density > 0.0))
    .then_some(element_bound);
    let data = MeshStatorData {
        omega_max_sq,
        mesh_file: file.clone(),
        geometry,
        from_cache,
        dim,
        cells: cells.len(),
        contact_normals,
        target_station,
        node_z: if solid {
            mesh.nodes.iter().map(|p| p[2]).collect()
        } else {
            vec![]
        },
        axial_dofs,
        contact_stiffness: OnceLock::new(),
        factor: OnceLock::new(),
    };
    let model = StatorModel {
        name: spec.name.clone(),
        station,
        nodes: mesh.nodes.iter().map(|p| [p[0], p[1]]).collect(),
        node_dofs,
        ndof,
        k,
        m,
        c,
        targets,
        elements,
        clearance: f64::NAN,
        angle_deg: None,
        is_ring: false,
        mesh: Some(Arc::new(data)),
    };
    if let Err(e) = model.mesh.as_ref().expect("mesh data").factor(&model.k) {
        return Err(ModelError::Singular {
            what: format!("stator `{}` stiffness ({})", spec.name, file.display()),
            detail: format!(
                "{e}; the stator has a free rigid-body or mechanism mode: check the groups in `fixed` ({}) and the springs",
                spec.fixed.join(", ")
            ),
        }
        .into());
    }
    Ok(model)
}

/// Clearance of a meshed stator as placed: the smallest distance from the surface of the
/// station each contact node faces (`radii[station]`, m) to that node (m).
pub fn clearance_of(model: &StatorModel, radii: &[f64]) -> f64 {
    model
        .targets
        .iter()
        .enumerate()
        .filter_map(|(t, tg)| match tg {
            Target::Node { x0, .. } => Some(x0[0].hypot(x0[1]) - radii[model.target_station(t)]),
            Target::Ring { .. } => None,
        })
        .fold(f64::INFINITY, f64::min)
}

/// Translates the stator rigidly along `approach_deg` so that, coming from far along that
/// direction, its first contact node meets the circle of radius `r + clearance` of its station
/// (`r = radii[station]`): the translation is `s d` with
/// `s = max_i (−x_i·d + √((x_i·d)² − |x_i|² + (r_i+δ)²))` over the contact nodes whose line of
/// approach meets their circle.
pub fn place(
    model: &mut StatorModel,
    radii: &[f64],
    clearance: f64,
    approach_deg: f64,
) -> Result<(), ModelError> {
    let t = approach_deg.to_radians();
    let d = [t.cos(), t.sin()];
    let s = model
        .targets
        .iter()
        .enumerate()
        .filter_map(|(i, tg)| match tg {
            Target::Node { x0, .. } => {
                let rc = radii[model.target_station(i)] + clearance;
                let b = x0[0] * d[0] + x0[1] * d[1];
                let disc = b * b - (x0[0] * x0[0] + x0[1] * x0[1]) + rc * rc;
                (disc >= 0.0).then(|| -b + disc.sqrt())
            }
            Target::Ring { .. } => None,
        })
        .fold(f64::NEG_INFINITY, f64::max);
    if !s.is_finite() {
        return Err(ModelError::Inconsistent {
            what: format!("stator `{}`", model.name),
            message: format!(
                "moved along approach_deg = {approach_deg}°, no contact node ever meets the rotor section: check approach_deg"
            ),
        });
    }
    for p in model.nodes.iter_mut() {
        p[0] += s * d[0];
        p[1] += s * d[1];
    }
    for tg in model.targets.iter_mut() {
        if let Target::Node { x0, .. } = tg {
            x0[0] += s * d[0];
            x0[1] += s * d[1];
        }
    }
    model.clearance = clearance_of(model, radii);
    model.angle_deg = Some(approach_deg);
    Ok(())
}

/// Stress at the nodes of the continuum cells, averaged over the cells sharing each node:
/// `[σ_xx, σ_yy, τ_xy, σ_zz]` (Pa) per node for a free-DOF displacement `u` (m); nodes of no
/// continuum cell get zeros. The von Mises stress of a node is
/// [`solid2d::von_mises`] of its entry.
pub fn nodal_stress(model: &StatorModel, u: &[f64]) -> Vec<[f64; 4]> {
    let mut acc = vec![[0.0; 4]; model.nodes.len()];
    let mut cnt = vec![0u32; model.nodes.len()];
    let mut x = [[0.0; 2]; solid2d::MAX_NODES];
    let mut ue = [0.0; 2 * solid2d::MAX_NODES];
    for el in &model.elements {
        if let StatorElement::Solid2 {
            kind,
            nodes,
            material,
        } = el
        {
            let nn = kind.nodes();
            gather(model, nodes, u, &mut x, &mut ue);
            for (k, xi) in solid2d::node_xi(*kind).iter().enumerate() {
                let s = material.stress(solid2d::strain(*kind, &x[..nn], &ue[..2 * nn], *xi));
                for c in 0..4 {
                    acc[nodes[k]][c] += s[c];
                }
                cnt[nodes[k]] += 1;
            }
        }
    }
    for (a, c) in acc.iter_mut().zip(&cnt) {
        if *c > 0 {
            for v in a.iter_mut() {
                *v /= *c as f64;
            }
        }
    }
    acc
}

/// von Mises stress (Pa) at the centroid of a tetrahedron for a free-DOF displacement `u`.
pub(crate) fn centroid_von_mises_3d(
    model: &StatorModel,
    kind: CellKind,
    nodes: &[usize],
    material: &Elastic3,
    u: &[f64],
) -> f64 {
    let Some(md) = &model.mesh else {
        return f64::NAN;
    };
    let mut x = [[0.0; 3]; solid3d::MAX_NODES];
    let mut ue = [0.0; 3 * solid3d::MAX_NODES];
    for (k, &n) in nodes.iter().enumerate() {
        x[k] = [model.nodes[n][0], model.nodes[n][1], md.node_z[n]];
        let d = model.node_dofs[n];
        ue[3 * k] = d[0].map_or(0.0, |i| u[i]);
        ue[3 * k + 1] = d[1].map_or(0.0, |i| u[i]);
        ue[3 * k + 2] = md.axial_dofs[n].map_or(0.0, |i| u[i]);
    }
    let nn = kind.nodes();
    let eps = solid3d::strain(kind, &x[..nn], &ue[..3 * nn], [0.25; 3]);
    solid3d::von_mises(material.stress(eps))
}

/// Coordinates and displacements of a cell's nodes.
pub(crate) fn gather(
    model: &StatorModel,
    nodes: &[usize],
    u: &[f64],
    x: &mut [[f64; 2]],
    ue: &mut [f64],
) {
    for (k, &n) in nodes.iter().enumerate() {
        x[k] = model.nodes[n];
        let d = model.node_dofs[n];
        ue[2 * k] = d[0].map_or(0.0, |i| u[i]);
        ue[2 * k + 1] = d[1].map_or(0.0, |i| u[i]);
    }
}

/// von Mises stress (Pa) at the centroid of a 2-D cell for a free-DOF displacement `u`.
pub(crate) fn centroid_von_mises(
    model: &StatorModel,
    kind: CellKind,
    nodes: &[usize],
    material: &Elastic2,
    u: &[f64],
) -> f64 {
    let mut x = [[0.0; 2]; solid2d::MAX_NODES];
    let mut ue = [0.0; 2 * solid2d::MAX_NODES];
    gather(model, nodes, u, &mut x, &mut ue);
    let xi = if matches!(kind, CellKind::Tri3 | CellKind::Tri6) {
        [1.0 / 3.0, 1.0 / 3.0]
    } else {
        [0.0, 0.0]
    };
    let nn = kind.nodes();
    solid2d::von_mises(material.stress(solid2d::strain(kind, &x[..nn], &ue[..2 * nn], xi)))
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
