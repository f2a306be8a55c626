//! Meshed stators: a mesh and the parameters of a `kind = "mesh"` stator become a
//! [`StatorModel`].
//!
//! The mesh was found, made by gmsh or read, and checked against the stator's parameters
//! (dimension, conforming, cells oriented, material regions) by the resolve stage
//! ([`crate::resolve::mesh`]); here its groups are looked up (present, with the right
//! dimension) and it is assembled over free DOFs:
//!
//! * 2-D continuum cells of every material region ([`crate::element::solid2d`], plane stress or
//!   strain, thickness per region), HRZ-lumped mass; tetrahedra of 3-D meshes
//!   ([`crate::element::solid3d`]) with an axial DOF u_z per node;
//! * bars and frames on line groups ([`crate::element::frame`]): frames add a rotation DOF
//!   θ_z at their nodes, numbered after every translation DOF;
//! * grounded springs on the nodes of a group;
//! * fixed components from the `fixed*` groups;
//! * contact targets: the nodes of the contact group, with their outward normals.
//!
//! The model is speed independent; `model::place` moves it rigidly to a clearance at each speed.
//!
//! # Conventions
//!
//! Coordinates relative to the undeformed station centre (m); node DOFs `[u_x, u_y]` as every
//! stator ([`StatorModel`]); 2-D meshes lie in the plane z = 0. A cell whose nodes run clockwise
//! (a surface meshed with normal −z) is renumbered counter-clockwise when its whole surface is
//! clockwise; a cell oriented against the rest of its surface, folded or degenerate, is an
//! error ([`MeshError::Inverted`]).

use super::{MeshStatorData, StatorElement, StatorModel};
use crate::contact::Target;
use crate::element::frame::{self, FrameSection};
use crate::element::solid2d::{self, Elastic2, Plane};
use crate::element::solid3d::{self, Elastic3};
use crate::error::{Error, MeshError, ModelError};
use crate::linalg::{Csc, PatternAssembly};
use crate::math::V2;
use crate::mesh::{CellKind, Mesh};
use crate::resolve::mesh::{
    self as resolved, bad_group, Cell, FrameSpec, MeshBody, MeshStatorInput, MeshStatorParams,
};
use crate::scene::MeshStatorSpec;
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

/// Builds the speed-independent model of a resolved meshed stator; `stations_z` lists
/// `(station index, axial position z (m))` of the stations its contact nodes may face (see
/// [`from_mesh`]).
pub fn from_input(
    input: &MeshStatorInput,
    stations_z: &[(usize, f64)],
) -> Result<StatorModel, Error> {
    from_mesh(
        &input.mesh,
        &input.body,
        &input.params,
        stations_z,
        input.geometry.clone(),
        input.from_cache,
    )
}

/// [`from_mesh`] for a spec outside a scene file (library use, tests), facing station
/// `station` (its parameters by [`MeshStatorParams::from_spec`]).
pub fn from_spec(
    mesh: &Mesh,
    spec: &MeshStatorSpec,
    station: usize,
    stations_z: &[(usize, f64)],
    geometry: PathBuf,
    from_cache: bool,
) -> Result<StatorModel, Error> {
    let params = MeshStatorParams::from_spec(spec, station)?;
    let body = resolved::body(mesh, &params)?;
    from_mesh(mesh, &body, &params, stations_z, geometry, from_cache)
}

/// A line element carrying a bar or a frame of a `frames` entry.
type Line<'a> = ([usize; 2], &'a FrameSpec);

/// Builds a [`StatorModel`] from a mesh (see the module documentation).
///
/// `body` is the mesh checked against `p` ([`resolved::body`]). 2-D meshes (cells in the plane
/// z = 0) give plane stress or strain bodies of thickness `p.thickness`; 3-D meshes (tetrahedra) give solids with an axial DOF u_z per node (kept in
/// [`MeshStatorData::axial_dofs`]; contact acts in the station plane). Each contact node of a
/// 3-D stator is assigned to the station of `stations_z` nearest to its axial position
/// `z + p.axial_origin`; 2-D stators (and 3-D ones with fewer than two candidate stations)
/// face `p.station`.
pub fn from_mesh(
    mesh: &Mesh,
    body: &MeshBody,
    p: &MeshStatorParams,
    stations_z: &[(usize, f64)],
    geometry: PathBuf,
    from_cache: bool,
) -> Result<StatorModel, Error> {
    let file = &mesh.file;
    let (dim, cells) = (body.dim, &body.cells);
    let solid = dim == 3;
    let lines = frame_lines(mesh, p)?;
    let spring_nodes: Vec<(Vec<usize>, [f64; 2])> = p
        .springs
        .iter()
        .map(|s| Ok((mesh.group_nodes(&s.group)?, s.stiffness)))
        .collect::<Result<_, MeshError>>()?;
    supports_hold(mesh, p, cells, &lines)?;
    let dofs = Dofs::number(mesh, p, solid, cells, &lines)?;
    let ndof = dofs.ndof;
    let mut asm = Assembly::new(ndof, cells, &lines, &spring_nodes, &dofs);
    asm.cells(mesh, p.plane, solid, cells, &dofs);
    asm.lines(mesh, &lines, &dofs)?;
    asm.springs(&spring_nodes, &dofs);
    let Assembly {
        k,
        mass,
        elements,
        element_bound,
    } = asm;
    let k = k.finish();
    let (m, c, total_mass) = mass_and_damping(p, &mass, &k)?;
    let contact = contact_targets(mesh, p, solid, stations_z, &dofs)?;
    // The element bound holds when every element carrying stiffness carries its own mass.
    let omega_max_sq = (total_mass > 0.0
        && lines.is_empty()
        && spring_nodes.is_empty()
        && cells.iter().all(|c| c.material.density > 0.0))
    .then_some(element_bound);
    let data = Arc::new(MeshStatorData {
        omega_max_sq,
        mesh_file: file.clone(),
        geometry,
        from_cache,
        dim,
        cells: cells.len(),
        contact_normals: contact.normals,
        contact_areas: contact.areas,
        target_station: contact.stations,
        node_z: if solid {
            mesh.nodes.iter().map(|p| p[2]).collect()
        } else {
            vec![]
        },
        axial_dofs: dofs.axial_dofs,
        axial_origin: p.axial_origin,
        contact_stiffness: OnceLock::new(),
        factor: OnceLock::new(),
        compliance_columns: Default::default(),
        reductions: Default::default(),
    });
    let s = StatorModel {
        name: p.name.clone(),
        station: p.station,
        nodes: mesh.nodes.iter().map(|p| [p[0], p[1]]).collect(),
        node_dofs: dofs.node_dofs,
        ndof,
        k: Arc::new(k),
        m: Arc::new(m),
        c: Arc::new(c),
        targets: contact.targets,
        elements: Arc::new(elements),
        clearance: f64::NAN,
        angle_deg: None,
        is_ring: false,
        mesh: Some(Arc::clone(&data)),
        dashpot: Default::default(),
        reduced: None,
        wear: None,
    };
    // The contact stiffness bound (every run's step plan asks for it) factors the interior
    // block K_ii: done before K's own factor, so the two factors are never held at once.
    s.contact_stiffness_bound();
    match data.factor(&s.k) {
        Err(e) => Err(ModelError::Factorisation {
            what: format!("stator `{}` stiffness ({})", p.name, file.display()),
            hint: format!(
                "the stator has a free rigid-body or mechanism mode, check the groups in `fixed` ({}) and the springs",
                p.fixed.join(", ")
            ),
            source: e,
        }
        .into()),
        Ok(_) => Ok(s),
    }
}

/// The lumped mass matrix of the DOF masses `mass` (kg), the Rayleigh damping
/// `C = α M + β K` of `p.rayleigh` (none for a massless stator, which may not ask for it), and
/// the total mass; a DOF without mass in a stator with mass is refused.
fn mass_and_damping(p: &MeshStatorParams, mass: &[f64], k: &Csc) -> Result<(Csc, Csc, f64), Error> {
    let ndof = mass.len();
    let total_mass: f64 = mass.iter().sum();
    if total_mass == 0.0 && p.rayleigh != [0.0; 2] {
        return Err(ModelError::Inconsistent {
            what: format!("stator `{}`", p.name),
            message: super::MASSLESS_DAMPING.into(),
        }
        .into());
    }
    if total_mass > 0.0 {
        if let Some(d) = mass.iter().position(|m| *m <= 0.0) {
            return Err(ModelError::Inconsistent {
                what: format!("stator `{}`", p.name),
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
        Csc::lin_comb(p.rayleigh[0], &m, p.rayleigh[1], k)
    } else {
        Csc::zeros(ndof, ndof)
    };
    Ok((m, c, total_mass))
}

/// Refuses a stator whose supports certainly hold nothing — no spring, and no node of the
/// `fixed`, `fixed_x`, `fixed_y`, `fixed_z` groups on an element that carries stiffness (a cell
/// of the body, a line of a `frames` entry): its stiffness matrix would be singular, and the
/// factorisation could not tell why. Names the curve groups the supports lie on that carry no
/// `frames` entry (the bars or frames that would attach them; `model::blame` then blames
/// `stator.<i>.frames`), else the `fixed` groups.
fn supports_hold(
    mesh: &Mesh,
    p: &MeshStatorParams,
    cells: &[Cell],
    lines: &[Line],
) -> Result<(), Error> {
    if !p.springs.is_empty() {
        return Ok(());
    }
    let mut supported = vec![false; mesh.nodes.len()];
    for name in p
        .fixed
        .iter()
        .chain(&p.fixed_x)
        .chain(&p.fixed_y)
        .chain(&p.fixed_z)
    {
        for n in mesh.group_nodes(name)? {
            supported[n] = true;
        }
    }
    let on_elements = cells
        .iter()
        .flat_map(|c| c.nodes.iter())
        .chain(lines.iter().flat_map(|(l, _)| l.iter()))
        .any(|&n| supported[n]);
    if on_elements {
        return Ok(());
    }
    let loose: Vec<&str> = mesh
        .groups
        .iter()
        .filter(|g| g.dim == 1 && !p.frames.iter().any(|f| f.group == g.name))
        .filter(|g| {
            mesh.group_blocks(g)
                .any(|b| b.conn.iter().any(|&n| supported[n]))
        })
        .map(|g| g.name.as_str())
        .collect();
    let groups = p
        .fixed
        .iter()
        .chain(&p.fixed_x)
        .chain(&p.fixed_y)
        .chain(&p.fixed_z)
        .map(String::as_str)
        .collect::<Vec<_>>()
        .join(", ");
    let message = if loose.is_empty() {
        format!(
            "the supports ({groups}) hold no node of the stator's cells or frames: the stator is free (a rigid-body mode); fix a group of its own nodes"
        )
    } else {
        format!(
            "the supports ({groups}) hold no node of the stator's cells or frames: they lie on the line elements of the group(s) {}, which carry no `frames` entry (bars or frames that would attach the body to them), so the stator is free (a rigid-body mode)",
            loose.join(", ")
        )
    };
    Err(ModelError::Inconsistent {
        what: format!("stator `{}` ({})", p.name, mesh.file.display()),
        message,
    }
    .into())
}

/// The line elements of the `frames` groups (2-D): a 3-node line (second-order mesh) is one
/// straight element between its ends; its middle node belongs to no element and gets no DOF.
fn frame_lines<'a>(mesh: &Mesh, p: &'a MeshStatorParams) -> Result<Vec<Line<'a>>, Error> {
    let file = &mesh.file;
    let mut lines: Vec<Line<'a>> = Vec::new();
    for fr in &p.frames {
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
            lines.extend(b.cells().map(|c| ([c[0], c[1]], fr)));
        }
        if !lines.iter().any(|l| std::ptr::eq(l.1, fr)) {
            return Err(bad_group(file, &fr.group, "the group has no line elements"));
        }
    }
    Ok(lines)
}

/// The free DOFs: translations of the nodes of cells and lines that no `fixed*` group fixes
/// (`[x, y]`, then z in 3-D, node by node), then the rotations θ_z of frame nodes that the
/// `fixed` groups do not clamp.
struct Dofs {
    /// Number of free DOFs.
    ndof: usize,
    /// `[u_x, u_y]` DOFs of each node.
    node_dofs: Vec<[Option<usize>; 2]>,
    /// u_z DOF of each node (3-D; empty in 2-D).
    axial_dofs: Vec<Option<usize>>,
    /// θ_z DOF of each frame node.
    rot: HashMap<usize, Option<usize>>,
    /// Nodes of some element.
    used: Vec<bool>,
    /// 3-D mesh.
    solid: bool,
}

impl Dofs {
    fn number(
        mesh: &Mesh,
        p: &MeshStatorParams,
        solid: bool,
        cells: &[Cell],
        lines: &[Line],
    ) -> Result<Self, Error> {
        let nn = mesh.nodes.len();
        let mut used = vec![false; nn];
        for c in cells {
            for &n in &c.nodes {
                used[n] = true;
            }
        }
        for (l, _) in lines {
            used[l[0]] = true;
            used[l[1]] = true;
        }
        let mut fixed = vec![[false; 3]; nn];
        for (names, comps) in [
            (&p.fixed, &[0usize, 1, 2][..]),
            (&p.fixed_x, &[0][..]),
            (&p.fixed_y, &[1][..]),
            (&p.fixed_z, &[2][..]),
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
        // Rotation DOFs of frame nodes; nodes of the `fixed` groups are clamped (θ fixed too).
        let mut clamped = vec![false; nn];
        for name in &p.fixed {
            for n in mesh.group_nodes(name)? {
                clamped[n] = true;
            }
        }
        let mut rot: HashMap<usize, Option<usize>> = HashMap::new();
        for (l, fr) in lines {
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
        Ok(Dofs {
            ndof,
            node_dofs,
            axial_dofs,
            rot,
            used,
            solid,
        })
    }

    /// Appends the DOFs of node `n` in element order (`[x, y]` or `[x, y, z]`).
    fn of(&self, n: usize, out: &mut Vec<Option<usize>>) {
        out.push(self.node_dofs[n][0]);
        out.push(self.node_dofs[n][1]);
        if self.solid {
            out.push(self.axial_dofs[n]);
        }
    }
}

/// A line element's DOFs in its matrix's order: a bar's `[u_x, u_y]` at both ends, a frame's
/// `[u_x, u_y, θ_z]` at both ends.
fn line_dofs((l, fr): &Line, dofs: &Dofs) -> Vec<Option<usize>> {
    let nd = &dofs.node_dofs;
    match fr.inertia {
        None => [nd[l[0]], nd[l[1]]].concat(),
        Some(_) => vec![
            nd[l[0]][0],
            nd[l[0]][1],
            dofs.rot[&l[0]],
            nd[l[1]][0],
            nd[l[1]][1],
            dofs.rot[&l[1]],
        ],
    }
}

/// The stiffness summed on its pattern, lumped masses and elements as they are assembled, with
/// the element eigenvalue bound.
struct Assembly {
    k: PatternAssembly,
    mass: Vec<f64>,
    elements: Vec<StatorElement>,
    element_bound: f64,
}

impl Assembly {
    /// The stiffness's pattern from every element's free DOFs (cells, lines, springs).
    fn new(
        ndof: usize,
        cells: &[Cell],
        lines: &[Line],
        springs: &[(Vec<usize>, [f64; 2])],
        dofs: &Dofs,
    ) -> Self {
        let mut offsets = vec![0];
        let mut flat: Vec<u32> = Vec::new();
        let mut ed = Vec::new();
        let mut push = |ed: &[Option<usize>]| {
            flat.extend(ed.iter().flatten().map(|&d| d as u32));
            offsets.push(flat.len());
        };
        for c in cells {
            ed.clear();
            for &n in &c.nodes {
                dofs.of(n, &mut ed);
            }
            push(&ed);
        }
        for l in lines {
            push(&line_dofs(l, dofs));
        }
        let spring_dofs = springs.iter().flat_map(|(nodes, _)| nodes);
        for d in spring_dofs.flat_map(|&n| dofs.node_dofs[n]) {
            push(&[d]);
        }
        Assembly {
            k: PatternAssembly::new(ndof, &offsets, &flat),
            mass: vec![0.0; ndof],
            elements: Vec::with_capacity(cells.len() + lines.len()),
            element_bound: 0.0,
        }
    }

    /// Continuum cells: stiffness, HRZ-lumped mass, and the element eigenvalue bound (Irons:
    /// λ_max(K, M) ≤ max_e λ_max(K_e, M_e) with the element's lumped mass, on its free DOFs).
    fn cells(&mut self, mesh: &Mesh, plane: Plane, solid: bool, cells: &[Cell], dofs: &Dofs) {
        let ncomp = if solid { 3 } else { 2 };
        let mut x2 = [[0.0; 2]; solid2d::MAX_NODES];
        let mut x3 = [[0.0; 3]; solid3d::MAX_NODES];
        let mut ke = vec![0.0; (3 * solid3d::MAX_NODES).pow(2)];
        let mut ml = [0.0; solid3d::MAX_NODES];
        let mut ed: Vec<Option<usize>> = Vec::with_capacity(3 * solid3d::MAX_NODES);
        for Cell {
            kind,
            nodes,
            material: reg,
        } in cells
        {
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
                self.elements.push(StatorElement::Solid3 {
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
                self.elements.push(StatorElement::Solid2 {
                    kind: *kind,
                    nodes: nodes.clone(),
                    material,
                });
            }
            ed.clear();
            for &n in nodes {
                dofs.of(n, &mut ed);
            }
            self.k.add(&ed, ke);
            if reg.density > 0.0 {
                let free: Vec<usize> = (0..ed.len()).filter(|&i| ed[i].is_some()).collect();
                if !free.is_empty() {
                    let nd = ed.len();
                    let a = nalgebra::DMatrix::from_fn(free.len(), free.len(), |i, j| {
                        let (fi, fj) = (free[i], free[j]);
                        ke[fi * nd + fj] / (ml[fi / ncomp] * ml[fj / ncomp]).sqrt()
                    });
                    let lmax = a.symmetric_eigenvalues().max();
                    self.element_bound = self.element_bound.max(lmax);
                }
                for (k, m) in ml[..nn].iter().enumerate() {
                    for d in ed[ncomp * k..ncomp * (k + 1)].iter().flatten() {
                        self.mass[*d] += m;
                    }
                }
            }
        }
    }

    /// Bars (E A / L, half of ρ A L at each end) and frames (beam-columns with θ_z, lumped
    /// translational and rotary mass) on the line elements.
    fn lines(&mut self, mesh: &Mesh, lines: &[Line], dofs: &Dofs) -> Result<(), Error> {
        let node_dofs = &dofs.node_dofs;
        for (l, fr) in lines {
            let a = [mesh.nodes[l[0]][0], mesh.nodes[l[0]][1]];
            let b = [mesh.nodes[l[1]][0], mesh.nodes[l[1]][1]];
            let length = (b[0] - a[0]).hypot(b[1] - a[1]);
            if length <= 0.0 {
                return Err(bad_group(
                    &mesh.file,
                    &fr.group,
                    "a zero-length line element",
                ));
            }
            match fr.inertia {
                None => {
                    let mut kb = [0.0; 16];
                    frame::bar_stiffness(a, b, fr.youngs_modulus * fr.area, &mut kb);
                    self.k.add(&line_dofs(&(*l, *fr), dofs), &kb);
                    let half = fr.density * fr.area * length / 2.0;
                    for &n in l {
                        for d in node_dofs[n].iter().flatten() {
                            self.mass[*d] += half;
                        }
                    }
                    self.elements.push(StatorElement::Bar {
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
                    let rot_dofs = [dofs.rot[&l[0]], dofs.rot[&l[1]]];
                    self.k.add(&line_dofs(&(*l, *fr), dofs), &kf);
                    let [mt, mr] = frame::frame_mass_lumped(a, b, &section);
                    for (k, &n) in l.iter().enumerate() {
                        for d in node_dofs[n].iter().flatten() {
                            self.mass[*d] += mt;
                        }
                        if let Some(r) = rot_dofs[k] {
                            self.mass[r] += mr;
                        }
                    }
                    self.elements.push(StatorElement::Frame {
                        nodes: *l,
                        rot_dofs,
                        section,
                        length,
                    });
                }
            }
        }
        Ok(())
    }

    /// Grounded springs: each group's total stiffness `[k_x, k_y]` shared equally by its nodes.
    fn springs(&mut self, spring_nodes: &[(Vec<usize>, [f64; 2])], dofs: &Dofs) {
        for (nodes, k) in spring_nodes {
            let share = 1.0 / nodes.len() as f64;
            for &n in nodes {
                for (c, kc) in k.iter().enumerate() {
                    if *kc > 0.0 {
                        let d = dofs.node_dofs[n][c];
                        self.k.add(&[d], &[kc * share]);
                        let dir = if c == 0 { [1.0, 0.0] } else { [0.0, 1.0] };
                        self.elements.push(StatorElement::Spring {
                            node: n,
                            stiffness: kc * share,
                            dir,
                        });
                    }
                }
            }
        }
    }
}

/// Contact targets with their outward normals (unit, in the station plane) and the station
/// each faces.
struct Contact {
    targets: Vec<Target>,
    normals: Vec<V2>,
    /// Tributary area of each target (m²): the boundary's measure times the thickness in 2-D.
    areas: Vec<f64>,
    stations: Vec<usize>,
}

/// The nodes of the contact group as targets; each node must belong to an element, and not
/// every one may be fixed.
fn contact_targets(
    mesh: &Mesh,
    p: &MeshStatorParams,
    solid: bool,
    stations_z: &[(usize, f64)],
    dofs: &Dofs,
) -> Result<Contact, Error> {
    let file = &mesh.file;
    let normals = mesh.boundary_normals(&p.contact_group)?;
    let measures = mesh.boundary_measures(&p.contact_group)?;
    // 2-D: a boundary length times the stator's thickness (its regions' own are not read).
    let depth = if solid {
        1.0
    } else {
        p.thickness.unwrap_or(1.0)
    };
    let mut c = Contact {
        targets: Vec::with_capacity(normals.len()),
        normals: Vec::with_capacity(normals.len()),
        areas: Vec::with_capacity(normals.len()),
        stations: Vec::with_capacity(normals.len()),
    };
    for ((n, nv), (_, measure)) in normals.iter().zip(&measures) {
        c.areas.push(measure * depth);
        if !dofs.used[*n] {
            return Err(bad_group(
                file,
                &p.contact_group,
                format!(
                    "node {} belongs to no element of the stator",
                    mesh.node_tags[*n]
                ),
            ));
        }
        c.targets.push(Target::Node {
            node: *n,
            x0: [mesh.nodes[*n][0], mesh.nodes[*n][1]],
            dofs: dofs.node_dofs[*n],
        });
        let h = nv[0].hypot(nv[1]);
        c.normals.push(if h > 0.0 {
            [nv[0] / h, nv[1] / h]
        } else {
            [0.0, 0.0]
        });
        let z = mesh.nodes[*n][2] + p.axial_origin;
        c.stations.push(if solid && stations_z.len() > 1 {
            stations_z
                .iter()
                .min_by(|a, b| (a.1 - z).abs().total_cmp(&(b.1 - z).abs()))
                .map_or(p.station, |s| s.0)
        } else {
            p.station
        });
    }
    if c.targets.iter().all(|t| t.dofs() == [None, None]) {
        return Err(bad_group(
            file,
            &p.contact_group,
            "every contact node is fixed: the rotor would hit a rigid wall",
        ));
    }
    Ok(c)
}
