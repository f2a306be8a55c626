//! Time series for ParaView and pyvista: VTK XML frames (`.vtu` files and a `.pvd` collection,
//! [`vtk`]) and one HDF5 file per run with a transient VTKHDF group ([`hdf5`], cargo feature
//! `hdf5`). The layout of both is documented in `docs/OUTPUTS.md`.
//!
//! [`ResultsSink`] is a [`FrameSink`]: the integrator hands it the full state every few steps
//! and it streams frames to disk while the run goes, so memory does not grow with the run.
//! Files are written below the output directory's staging folder
//! ([`crate::output::OutDir::staging_dir`]) and moved into place when the command succeeds.
//!
//! # The output grid
//!
//! Both formats write the same unstructured grid ([`Layout`]):
//!
//! * points: the points of every stator, stator after stator, then the rotor nodes on the axis
//!   `(0, 0, z)`. A stator's points are its nodes — 2-D stators in the plane `z` of the rotor
//!   node carrying their station, 3-D (tetrahedral) meshed stators at their own axial position
//!   `z = node z + axial_origin` — followed, for a ring target, by the [`RING_POINTS`] points
//!   of its contact circle and the ring's contact point ([`RingSlot`]). Points are at their
//!   **undeformed** positions (m); the point array `displacement` moves them (ParaView's
//!   *Warp By Vector*).
//! * cells: one per stator element ([`element_cell`]), a closed polyline per ring (its
//!   contact circle), the rotor (a vertex for a one-node rotor, else a polyline through its
//!   nodes), then the contact pairs as lines from the rotor node of the station the target
//!   faces to the stator node (a ring: to its contact point). The `.vtu` frames hold only the
//!   pairs in contact at that instant; the VTKHDF grid, written once, holds every candidate pair
//!   with `normal_force = 0` while it is open.
//! * cell data `part` (0 stator element or ring circle, 1 rotor, 2 contact pair), `stator`
//!   (stator index, −1 for the rotor) and `index` (element index in its stator, −1 for a ring
//!   circle, pair index, 0 for the rotor).
//! * rotor points: `displacement` `[u_x, u_y, u_z]` (u_z of rotors with axial DOFs, else 0);
//!   with torsional DOFs ([`Layout::rotor_has_torsion`]) the point array `twist` (θ_z, rad,
//!   counter-clockwise seen from +z, the sense of the spin) and, with velocities,
//!   `twist_rate` (rad/s), NaN on the stator points. The bending rotations θ_x, θ_y are not
//!   grid arrays (a point array spans every stator point); the HDF5 file's `/rotor/u` with
//!   `/rotor/node_dofs` ([`RotorNodeDofs`]) holds them.
//!
//! Conventions are the crate's: SI units, x horizontal, y vertical, rotor axis z; contact force
//! positive on the body it acts on (`contact_force` at a stator node is `Σ (n + μa) p` of its
//! pairs, at a rotor node the opposite sum); `normal_force` is the multiplier `p ≥ 0`
//! (compression).

pub mod vtk;

#[cfg(feature = "hdf5")]
pub mod hdf5;

use crate::analysis::Prepared;
use crate::contact::{pair_state, target_disp};
use crate::error::{Error, Result};
use crate::math::{gcd, V2};
use crate::mesh::CellKind;
use crate::model::stator::StatorElement;
use crate::model::{Case, Model, Rotor, Target};
use crate::scene::{OutputSpec, PerSpeed, SeriesField, SeriesSpec};
use crate::time::{Frame, FrameSink, StepPlan};
use std::path::Path;
pub use vtkio::model::CellType;

/// Values of the `part` cell array.
pub mod part {
    /// A stator element.
    pub const STATOR: u8 = 0;
    /// The rotor.
    pub const ROTOR: u8 = 1;
    /// A contact pair (station–stator node).
    pub const CONTACT: u8 = 2;
}

/// The VTK cell of a stator element: its type and its nodes (indices into the stator's nodes)
/// in VTK's node order; `None` only for a cell kind VTK has no type for (left out of the
/// output).
///
/// Bars and frames are `VTK_LINE`, springs to ground `VTK_VERTEX` on their node, the
/// continuum cells of meshed stators their VTK cell ([`CellKind::vtk_type`]). gmsh and VTK
/// number the nodes of lines, triangles, quadrilaterals and the 4-node tetrahedron alike;
/// for the 10-node tetrahedron gmsh's mid-edge nodes 8 and 9 lie on edges (2,3) and (1,3),
/// VTK's on (1,3) and (2,3), so the two are swapped ([`gmsh_to_vtk_order`]). New
/// [`StatorElement`] kinds add their arm here; cell data follow
/// [`crate::model::StatorModel::element_forces`].
pub fn element_cell(el: &StatorElement) -> Option<(CellType, Vec<usize>)> {
    match el {
        StatorElement::Bar { nodes, .. } => Some((CellType::Line, nodes.to_vec())),
        StatorElement::Spring { node, .. } => Some((CellType::Vertex, vec![*node])),
        StatorElement::Frame { nodes, .. } => Some((CellType::Line, nodes.to_vec())),
        StatorElement::Solid2 { kind, nodes, .. } | StatorElement::Solid3 { kind, nodes, .. } => {
            vtk_cell_type(kind.vtk_type()).map(|t| (t, gmsh_to_vtk_order(*kind, nodes)))
        }
    }
}

/// A cell's nodes reordered from gmsh's to VTK's node order: the identity except for the
/// 10-node tetrahedron, whose last two mid-edge nodes swap (gmsh: 4 (0,1), 5 (1,2), 6 (2,0),
/// 7 (0,3), 8 (2,3), 9 (1,3); VTK `VTK_QUADRATIC_TETRA`: … 8 (1,3), 9 (2,3)).
pub fn gmsh_to_vtk_order(kind: CellKind, nodes: &[usize]) -> Vec<usize> {
    let mut v = nodes.to_vec();
    if kind == CellKind::Tet10 && v.len() == 10 {
        v.swap(8, 9);
    }
    v
}

/// The `vtkio` cell type of a VTK cell type number (the linear and quadratic cells of lines,
/// triangles, quadrilaterals and tetrahedra).
pub fn vtk_cell_type(n: u8) -> Option<CellType> {
    Some(match n {
        1 => CellType::Vertex,
        3 => CellType::Line,
        4 => CellType::PolyLine,
        5 => CellType::Triangle,
        9 => CellType::Quad,
        10 => CellType::Tetra,
        21 => CellType::QuadraticEdge,
        22 => CellType::QuadraticTriangle,
        23 => CellType::QuadraticQuad,
        24 => CellType::QuadraticTetra,
        28 => CellType::BiquadraticQuad,
        _ => return None,
    })
}

/// Strain of an element from its stress (Pa): σ/E for bars and frames (axial), NaN where it is
/// not defined (springs; continuum cells, whose stress is the centroid von Mises stress).
fn element_strain(el: &StatorElement, stress: f64) -> f64 {
    match el {
        StatorElement::Bar { youngs_modulus, .. } => stress / youngs_modulus,
        StatorElement::Frame { section, .. } => stress / section.youngs_modulus,
        _ => f64::NAN,
    }
}

/// Axial position z (m) of each rotor node, in node order.
///
/// Axial node positions of the rotor (m): the Jeffcott rotor's one node at z = 0, the FE
/// rotor's nodes along its shaft; stator planes sit at their station's node.
pub fn rotor_node_z(case: &Case) -> Vec<f64> {
    case.rotor.node_z.clone()
}

/// The rotor DOFs of one node in the order [`ROTOR_DOF_NAMES`]:
/// `[u_x, u_y, θ_x, θ_y, u_z, θ_z]` (indices into the rotor DOF vector; `None` where the
/// rotor has no such DOF). Units m and rad; `θ_x`, `θ_y` follow the right-hand rule about x
/// and y ([`crate::element::timoshenko`]: `θ_y = ∂u_x/∂z`, `θ_x = −∂u_y/∂z`), `u_z` is
/// positive along +z, `θ_z` counter-clockwise seen from +z (the sense of the spin Ω).
pub type RotorNodeDofs = [Option<usize>; 6];

/// Names of the columns of [`RotorNodeDofs`] (and of the HDF5 dataset `/rotor/node_dofs`).
pub const ROTOR_DOF_NAMES: [&str; 6] = ["u_x", "u_y", "theta_x", "theta_y", "u_z", "theta_z"];

/// Column of `θ_z` in [`RotorNodeDofs`].
pub const THETA_Z: usize = 5;
/// Column of `u_z` in [`RotorNodeDofs`].
pub const U_Z: usize = 4;

/// Every DOF of each rotor node of a case ([`RotorNodeDofs`], in node order): the Jeffcott
/// rotor `[0, 1, −, −, −, −]`; an FE rotor `[4i, 4i + 1, 4i + 2, 4i + 3, u_z, θ_z]` (the
/// lateral numbering of [`crate::model::fe_rotor`]) with `u_z`, `θ_z` from
/// [`crate::model::rotor::RotorBody::node_axial`] and `node_torsion` (after all lateral DOFs).
pub fn rotor_dof_map(model: &Model, case: &Case) -> Vec<RotorNodeDofs> {
    let r = &case.rotor;
    // Bending rotations: an FE rotor's node owns [u_x, u_y, θ_x, θ_y] at 4i..4i+4.
    let bending = matches!(model.rotor, Rotor::Fe(_));
    r.node_dofs
        .iter()
        .enumerate()
        .map(|(i, d)| {
            let rot = |k: usize| bending.then_some(d[0] + k);
            [
                Some(d[0]),
                Some(d[1]),
                rot(2),
                rot(3),
                r.node_axial.get(i).copied().flatten(),
                r.node_torsion.get(i).copied().flatten(),
            ]
        })
        .collect()
}

/// The unstructured grid written by both formats (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct OutputGrid {
    /// Undeformed point coordinates `[x, y, z]` (m).
    pub points: Vec<[f64; 3]>,
    /// Point indices of every cell, cell after cell.
    pub connectivity: Vec<i64>,
    /// Start of each cell in `connectivity`, with the end as last entry (cells + 1 values).
    pub offsets: Vec<i64>,
    /// VTK cell types.
    pub types: Vec<CellType>,
    /// Cell data `part` ([`part`]).
    pub part: Vec<u8>,
    /// Cell data `stator`: stator index, −1 for the rotor.
    pub stator: Vec<i32>,
    /// Cell data `index`: element index in its stator, pair index, 0 for the rotor.
    pub index: Vec<i64>,
}

impl OutputGrid {
    fn new() -> Self {
        Self {
            points: Vec::new(),
            connectivity: Vec::new(),
            offsets: vec![0],
            types: Vec::new(),
            part: Vec::new(),
            stator: Vec::new(),
            index: Vec::new(),
        }
    }

    fn push_cell(&mut self, kind: CellType, pts: &[usize], part: u8, stator: i32, index: i64) {
        self.connectivity.extend(pts.iter().map(|p| *p as i64));
        self.offsets.push(self.connectivity.len() as i64);
        self.types.push(kind);
        self.part.push(part);
        self.stator.push(stator);
        self.index.push(index);
    }

    /// Number of cells.
    pub fn num_cells(&self) -> usize {
        self.types.len()
    }

    /// Point indices of cell `c`.
    pub fn cell(&self, c: usize) -> &[i64] {
        &self.connectivity[self.offsets[c] as usize..self.offsets[c + 1] as usize]
    }
}

/// A contact candidate as the integrator enumerates them (stator by stator, target by target).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PairSlot {
    /// Station index: the station the target faces
    /// ([`crate::model::StatorModel::target_station`]).
    pub station: usize,
    /// Stator index.
    pub stator: usize,
    /// Stator node of the target (ring: 0, its centre).
    pub node: usize,
    /// Grid point of the rotor node carrying the station.
    pub rotor_point: usize,
    /// Grid point the pair's line ends at: the stator node, for a ring its contact point
    /// ([`RingSlot::contact_point`]).
    pub stator_point: usize,
    /// Grid point of the stator node (a ring: its centre), where the point array
    /// `contact_force` adds the pair's force.
    pub node_point: usize,
}

/// Points drawn on the contact circle of a ring target (a closed polyline).
pub const RING_POINTS: usize = 64;

/// How a ring target (rigid ring on springs, circle-in-circle contact) is drawn.
///
/// * Its **contact circle** (inner radius `R = r + δ`): [`RING_POINTS`] grid points at
///   `center0 + R (cos θ_i, sin θ_i)`, `θ_i = 2π i / RING_POINTS`, joined by a closed
///   `VTK_POLY_LINE` (first point repeated at the end). Their `displacement` is the ring's
///   (its centre's DOFs), so *Warp By Vector* translates the circle rigidly with the ring at any
///   scale factor.
/// * Its **contact point** `P`, where the pair's line ends: the material point of the ring on
///   the line of centres, `center0 + R n` with `n = (x_C − x_S)/|x_C − x_S|` from the displaced
///   ring centre `x_S = center0 + u_S` to the displaced section centre `x_C` (the contact
///   kernel's normal; `(1, 0)` when the centres coincide), so that the displaced point
///   `P + u_S = x_C + (r + g) n` is the ring's surface point facing the section. In a `.vtu`
///   frame `P` is written at that undeformed position with displacement `u_S` (exact at any
///   warp factor); the VTKHDF grid is written once and keeps `P` at the ring centre, so its
///   pair line is the line of centres (parallel to `n`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingSlot {
    /// Stator index.
    pub stator: usize,
    /// Pair index of the ring's target.
    pub pair: usize,
    /// Undeformed centre (m, relative to the station centre).
    pub center0: V2,
    /// Inner radius R = r + δ (m).
    pub inner_radius: f64,
    /// Free DOFs of the ring centre `[x, y]` in the stator's vector.
    pub dofs: [Option<usize>; 2],
    /// Rotor DOFs `[x, y]` of the section centre the ring faces.
    pub rotor_dofs: [usize; 2],
    /// First grid point of the contact circle ([`RING_POINTS`] points).
    pub first_circle_point: usize,
    /// Grid point of the contact point `P`.
    pub contact_point: usize,
    /// Axial position z of the drawing (m): the plane of the station.
    pub z: f64,
}

impl RingSlot {
    /// The contact target the ring is: the contact kernel ([`pair_state`]) gives its normal.
    pub fn target(&self) -> Target {
        Target::Ring {
            center0: self.center0,
            inner_radius: self.inner_radius,
            dofs: self.dofs,
        }
    }
}

/// Where everything of a case sits in the [`OutputGrid`].
#[derive(Debug, Clone)]
pub struct Layout {
    /// The grid with every candidate pair (the VTKHDF grid).
    pub grid: OutputGrid,
    /// First grid point of each stator.
    pub stator_first_point: Vec<usize>,
    /// Number of grid points of each stator: its nodes (first), then the points drawing its
    /// ring targets ([`RingSlot`]).
    pub stator_num_points: Vec<usize>,
    /// First grid point of the rotor; its nodes are the last points of the grid, in node
    /// order.
    pub rotor_first_point: usize,
    /// Every DOF of each rotor node ([`rotor_dof_map`]).
    pub rotor_dofs: Vec<RotorNodeDofs>,
    /// Grid cell of each stator element (`None`: no cell, see [`element_cell`]).
    pub element_cells: Vec<Vec<Option<usize>>>,
    /// Cells before the contact pairs (stator elements, ring circles and the rotor).
    pub body_cells: usize,
    /// Contact candidates; pair `i` is grid cell `body_cells + i`.
    pub pairs: Vec<PairSlot>,
    /// Ring targets and their drawing.
    pub rings: Vec<RingSlot>,
    /// Pair index of `(stator, node)`.
    pair_of: Vec<Vec<Option<usize>>>,
    /// Stator names.
    pub stator_names: Vec<String>,
    /// Station names.
    pub station_names: Vec<String>,
}

impl Layout {
    /// Lays out a case of `model` (which tells whether rotor nodes carry rotations).
    pub fn new(model: &Model, case: &Case) -> Self {
        let z = rotor_node_z(case);
        let mut g = OutputGrid::new();
        let mut stator_first_point = Vec::new();
        let mut stator_num_points = Vec::new();
        // Per stator, per ring target: (target, first circle point, contact point).
        let mut ring_points: Vec<Vec<(usize, usize, usize)>> = Vec::new();
        for s in &case.stators {
            let first = g.points.len();
            stator_first_point.push(first);
            let zs = z[case.stations[s.station].node];
            match s.mesh.as_ref().filter(|m| !m.node_z.is_empty()) {
                // 3-D meshed stator: every node at its own axial position.
                Some(md) => {
                    let z0 = md.axial_origin;
                    g.points.extend(
                        s.nodes
                            .iter()
                            .zip(&md.node_z)
                            .map(|(p, nz)| [p[0], p[1], nz + z0]),
                    );
                }
                None => g.points.extend(s.nodes.iter().map(|p| [p[0], p[1], zs])),
            }
            let mut rp = Vec::new();
            for (t, tg) in s.targets.iter().enumerate() {
                if let Target::Ring {
                    center0,
                    inner_radius,
                    ..
                } = tg
                {
                    let zr = z[case.stations[s.target_station(t)].node];
                    let c = g.points.len();
                    g.points.extend((0..RING_POINTS).map(|i| {
                        let th = std::f64::consts::TAU * i as f64 / RING_POINTS as f64;
                        [
                            center0[0] + inner_radius * th.cos(),
                            center0[1] + inner_radius * th.sin(),
                            zr,
                        ]
                    }));
                    // The contact point: at the ring centre in the static grid.
                    g.points.push([center0[0], center0[1], zr]);
                    rp.push((t, c, c + RING_POINTS));
                }
            }
            ring_points.push(rp);
            stator_num_points.push(g.points.len() - first);
        }
        let rotor_first_point = g.points.len();
        g.points.extend(z.iter().map(|z| [0.0, 0.0, *z]));
        let mut element_cells = Vec::new();
        for (k, s) in case.stators.iter().enumerate() {
            let first = stator_first_point[k];
            let cells = s
                .elements
                .iter()
                .enumerate()
                .map(|(e, el)| {
                    element_cell(el).map(|(kind, nodes)| {
                        let pts: Vec<usize> = nodes.iter().map(|n| first + n).collect();
                        g.push_cell(kind, &pts, part::STATOR, k as i32, e as i64);
                        g.num_cells() - 1
                    })
                })
                .collect();
            element_cells.push(cells);
            for &(_, c, _) in &ring_points[k] {
                let pts: Vec<usize> = (c..c + RING_POINTS).chain(std::iter::once(c)).collect();
                g.push_cell(CellType::PolyLine, &pts, part::STATOR, k as i32, -1);
            }
        }
        let nr = z.len();
        if nr == 1 {
            g.push_cell(CellType::Vertex, &[rotor_first_point], part::ROTOR, -1, 0);
        } else if nr > 1 {
            let pts: Vec<usize> = (rotor_first_point..rotor_first_point + nr).collect();
            g.push_cell(CellType::PolyLine, &pts, part::ROTOR, -1, 0);
        }
        let body_cells = g.num_cells();
        let mut pairs = Vec::new();
        let mut rings = Vec::new();
        let mut pair_of = Vec::new();
        for (k, s) in case.stators.iter().enumerate() {
            let mut of = vec![None; s.nodes.len()];
            for (t, tg) in s.targets.iter().enumerate() {
                let station = s.target_station(t);
                let rotor_node = case.stations[station].node;
                let (node, stator_point) = match tg {
                    Target::Node { node, .. } => (*node, stator_first_point[k] + node),
                    Target::Ring {
                        center0,
                        inner_radius,
                        dofs,
                    } => {
                        let &(_, c, p) = ring_points[k]
                            .iter()
                            .find(|r| r.0 == t)
                            .expect("every ring target has its drawing");
                        rings.push(RingSlot {
                            stator: k,
                            pair: pairs.len(),
                            center0: *center0,
                            inner_radius: *inner_radius,
                            dofs: *dofs,
                            rotor_dofs: case.rotor.node_dofs[rotor_node],
                            first_circle_point: c,
                            contact_point: p,
                            z: g.points[p][2],
                        });
                        (0, p)
                    }
                };
                let slot = PairSlot {
                    station,
                    stator: k,
                    node,
                    rotor_point: rotor_first_point + rotor_node,
                    stator_point,
                    node_point: stator_first_point[k] + node,
                };
                if let Some(o) = of.get_mut(node) {
                    *o = Some(pairs.len());
                }
                g.push_cell(
                    CellType::Line,
                    &[slot.rotor_point, slot.stator_point],
                    part::CONTACT,
                    k as i32,
                    pairs.len() as i64,
                );
                pairs.push(slot);
            }
            pair_of.push(of);
        }
        Self {
            grid: g,
            stator_first_point,
            stator_num_points,
            rotor_first_point,
            rotor_dofs: rotor_dof_map(model, case),
            element_cells,
            body_cells,
            pairs,
            rings,
            pair_of,
            stator_names: case.stators.iter().map(|s| s.name.clone()).collect(),
            station_names: case.stations.iter().map(|s| s.name.clone()).collect(),
        }
    }

    /// Number of grid points.
    pub fn num_points(&self) -> usize {
        self.grid.points.len()
    }

    /// True when the rotor has torsional DOFs θ_z: the grid then carries the point arrays
    /// `twist` (and `twist_rate`).
    pub fn rotor_has_torsion(&self) -> bool {
        self.rotor_dofs.iter().any(|d| d[THETA_Z].is_some())
    }

    /// A point array of the rotor: NaN on every stator point, then `per_node[i]` on rotor
    /// node `i` (the rotor's points are the last of the grid).
    pub fn rotor_point_values<'a>(&self, per_node: &'a [f64]) -> impl Iterator<Item = f64> + 'a {
        debug_assert_eq!(self.rotor_first_point + per_node.len(), self.num_points());
        std::iter::repeat_n(f64::NAN, self.rotor_first_point).chain(per_node.iter().copied())
    }

    /// Pair index of a stator node, if it is a contact target.
    pub fn pair_index(&self, stator: usize, node: usize) -> Option<usize> {
        self.pair_of.get(stator)?.get(node).copied().flatten()
    }
}

/// Which fields a writer writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Fields {
    /// Point `displacement` (and the rotor DOFs in HDF5).
    pub displacement: bool,
    /// Point `velocity` (and the rotor DOF velocities in HDF5).
    pub velocity: bool,
    /// Point `contact_force`, cell `normal_force`, HDF5 `/contact`.
    pub contact_force: bool,
    /// Cell `axial_force`, `stress`, `strain`.
    pub stress: bool,
}

impl Fields {
    /// From a scene's list.
    pub fn from_list(list: &[SeriesField]) -> Self {
        let has = |f| list.contains(&f);
        Self {
            displacement: has(SeriesField::Displacement),
            velocity: has(SeriesField::Velocity),
            contact_force: has(SeriesField::ContactForce),
            stress: has(SeriesField::Stress),
        }
    }
}

/// The frames of one writer: steps `first, first + every, … ≤ last`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FramePlan {
    /// Steps between frames.
    pub every: usize,
    /// First frame step (a multiple of `every`).
    pub first: usize,
    /// Last step that may hold a frame.
    pub last: usize,
    /// Fields written.
    pub fields: Fields,
}

impl FramePlan {
    /// Resolves a scene's writer against a run's step plan.
    pub fn new(spec: &SeriesSpec, plan: &StepPlan) -> Self {
        let every = spec.every.unwrap_or(plan.record_every).max(1);
        let spr = plan.steps_per_rev as f64;
        let first =
            ((spec.from_revolution * spr - 1e-6).ceil().max(0.0) as usize).div_ceil(every) * every;
        let last = spec.to_revolution.map_or(plan.steps, |r| {
            ((r * spr + 1e-6).floor().max(0.0) as usize).min(plan.steps)
        });
        Self {
            every,
            first,
            last,
            fields: Fields::from_list(&spec.fields),
        }
    }

    /// True when `step` holds a frame.
    pub fn contains(&self, step: usize) -> bool {
        step >= self.first && step <= self.last && step % self.every == 0
    }

    /// Number of frames.
    pub fn count(&self) -> usize {
        if self.first > self.last {
            0
        } else {
            (self.last - self.first) / self.every + 1
        }
    }
}

/// The state of one frame on the [`OutputGrid`], in buffers reused from frame to frame.
#[derive(Debug, Clone)]
pub struct FrameState {
    /// Step index.
    pub step: usize,
    /// Time (s).
    pub t: f64,
    /// Rotor DOF vector (m, rad).
    pub rotor_u: Vec<f64>,
    /// Rotor DOF velocities (m/s, rad/s), backward difference over one step.
    pub rotor_v: Vec<f64>,
    /// Twist θ_z of each rotor node (rad, counter-clockwise seen from +z, the sense of Ω;
    /// 0 where the node has no θ_z).
    pub rotor_twist: Vec<f64>,
    /// Twist rate dθ_z/dt of each rotor node (rad/s), from `rotor_v`.
    pub rotor_twist_rate: Vec<f64>,
    /// Point displacements (m); at rotor nodes `[u_x, u_y, u_z]`.
    pub displacement: Vec<[f64; 3]>,
    /// Point velocities (m/s), backward difference over one step.
    pub velocity: Vec<[f64; 3]>,
    /// Point contact forces (N) on the body the point belongs to.
    pub contact_force: Vec<[f64; 3]>,
    /// Normal force p ≥ 0 of every candidate pair (N); 0 when open.
    pub pair_p: Vec<f64>,
    /// Force `(n + μa) p` on the stator node of every pair (N).
    pub pair_force: Vec<[f64; 2]>,
    /// Unit normal of every pair in contact (0 when open).
    pub pair_normal: Vec<[f64; 2]>,
    /// Total contact force on each station of the rotor (N).
    pub station_force: Vec<[f64; 2]>,
    /// Axial force (N) per grid cell: stator elements; NaN for other cells.
    pub axial_force: Vec<f64>,
    /// Stress (Pa) per grid cell: stator elements; NaN for other cells.
    pub stress: Vec<f64>,
    /// Strain per grid cell: stator elements; NaN for other cells.
    pub strain: Vec<f64>,
    /// Undeformed position (m) of the contact point of each ring ([`Layout::rings`]) in this
    /// frame's contact direction: `center0 + R n` (see [`RingSlot`]); the `.vtu` writes it.
    pub ring_contact: Vec<[f64; 3]>,
}

impl FrameState {
    fn new(layout: &Layout, case: &Case) -> Self {
        let np = layout.num_points();
        let nc = layout.grid.num_cells();
        let npairs = layout.pairs.len();
        Self {
            step: 0,
            t: 0.0,
            rotor_u: vec![0.0; case.rotor.ndof],
            rotor_v: vec![0.0; case.rotor.ndof],
            rotor_twist: vec![0.0; layout.rotor_dofs.len()],
            rotor_twist_rate: vec![0.0; layout.rotor_dofs.len()],
            displacement: vec![[0.0; 3]; np],
            velocity: vec![[0.0; 3]; np],
            contact_force: vec![[0.0; 3]; np],
            pair_p: vec![0.0; npairs],
            pair_force: vec![[0.0; 2]; npairs],
            pair_normal: vec![[0.0; 2]; npairs],
            station_force: vec![[0.0; 2]; case.stations.len()],
            axial_force: vec![f64::NAN; nc],
            stress: vec![f64::NAN; nc],
            strain: vec![f64::NAN; nc],
            ring_contact: layout
                .rings
                .iter()
                .map(|r| layout.grid.points[r.contact_point])
                .collect(),
        }
    }

    /// Fills displacements, contact forces and element fields from a frame (not velocities).
    fn fill(&mut self, layout: &Layout, case: &Case, f: &Frame<'_>) {
        self.step = f.step;
        self.t = f.t;
        self.rotor_u.copy_from_slice(f.rotor_u);
        for (k, s) in case.stators.iter().enumerate() {
            let u = f.stator_u(k);
            let c = |i: Option<usize>| i.map_or(0.0, |i| u[i]);
            let first = layout.stator_first_point[k];
            // 3-D meshed stators carry u_z; 2-D ones move in their plane.
            let axial = s.mesh.as_ref().map_or(&[][..], |m| &m.axial_dofs[..]);
            for (n, d) in s.node_dofs.iter().enumerate() {
                let uz = axial.get(n).map_or(0.0, |a| c(*a));
                self.displacement[first + n] = [c(d[0]), c(d[1]), uz];
            }
        }
        let dof = |d: Option<usize>| d.map_or(0.0, |i| f.rotor_u[i]);
        for (n, d) in layout.rotor_dofs.iter().enumerate() {
            self.displacement[layout.rotor_first_point + n] = [dof(d[0]), dof(d[1]), dof(d[U_Z])];
            self.rotor_twist[n] = dof(d[THETA_Z]);
        }
        // Rings: the circle and the contact point move with the ring centre; the contact point
        // sits on the line of centres (the contact kernel's normal).
        for (ring, pos) in layout.rings.iter().zip(self.ring_contact.iter_mut()) {
            let us = target_disp(ring.dofs, f.stator_u(ring.stator));
            let uc = ring.rotor_dofs.map(|i| f.rotor_u[i]);
            let n = pair_state(&ring.target(), 0.0, uc, us, 0.0).n;
            *pos = [
                ring.center0[0] + ring.inner_radius * n[0],
                ring.center0[1] + ring.inner_radius * n[1],
                ring.z,
            ];
            let c = ring.first_circle_point;
            self.displacement[c..=c + RING_POINTS].fill([us[0], us[1], 0.0]);
        }
        self.contact_force.fill([0.0; 3]);
        self.pair_p.fill(0.0);
        self.pair_force.fill([0.0; 2]);
        self.pair_normal.fill([0.0; 2]);
        self.station_force.fill([0.0; 2]);
        for p in f.pairs {
            if let Some(i) = layout.pair_index(p.stator, p.node) {
                self.pair_p[i] += p.p;
                self.pair_force[i][0] += p.force[0];
                self.pair_force[i][1] += p.force[1];
                self.pair_normal[i] = p.n;
                let slot = layout.pairs[i];
                for c in 0..2 {
                    self.contact_force[slot.node_point][c] += p.force[c];
                    self.contact_force[slot.rotor_point][c] -= p.force[c];
                }
            }
            self.station_force[p.station][0] -= p.force[0];
            self.station_force[p.station][1] -= p.force[1];
        }
        for (k, s) in case.stators.iter().enumerate() {
            if s.elements.is_empty() {
                continue;
            }
            let ef = s.element_forces(f.stator_u(k));
            for (e, (force, stress)) in ef.into_iter().enumerate() {
                if let Some(c) = layout.element_cells[k][e] {
                    self.axial_force[c] = force;
                    self.stress[c] = stress;
                    self.strain[c] = element_strain(&s.elements[e], stress);
                }
            }
        }
    }
}

/// Run information stored with the results (HDF5 attributes, `.pvd` comment).
#[derive(Debug, Clone, PartialEq)]
pub struct RunInfo {
    /// The resolved scene as JSON.
    pub scene_json: String,
    /// ω/ω_n.
    pub speed_ratio: f64,
    /// ω (rad/s).
    pub omega: f64,
    /// The step plan.
    pub plan: StepPlan,
    /// Integrator name.
    pub integrator: &'static str,
}

/// Displacements of the step before a frame (for the backward-difference velocities).
#[derive(Debug, Clone)]
struct PrevStep {
    step: usize,
    t: f64,
    displacement: Vec<[f64; 3]>,
    rotor_u: Vec<f64>,
}

/// Streams the frames of one run to the VTK and HDF5 writers a scene asks for.
pub struct ResultsSink<'a> {
    case: &'a Case,
    layout: Layout,
    state: FrameState,
    every: usize,
    /// The step before a frame, for velocities.
    prev: Option<PrevStep>,
    need_velocity: bool,
    init_velocity: [f64; 2],
    vtk: Option<(FramePlan, vtk::VtkSeries)>,
    #[cfg(feature = "hdf5")]
    hdf5: Option<(FramePlan, hdf5::Hdf5Series)>,
}

impl std::fmt::Debug for ResultsSink<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ResultsSink")
            .field("every", &self.every)
            .field("points", &self.layout.num_points())
            .finish_non_exhaustive()
    }
}

/// Errors when the file system holding `dir` has less free space than `bytes` (estimated size
/// of the series) plus a 5 % margin. Unix only (`statvfs`); elsewhere no check.
pub fn check_free_space(dir: &Path, bytes: f64) -> Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        let Ok(c) = std::ffi::CString::new(dir.as_os_str().as_bytes()) else {
            return Ok(());
        };
        // SAFETY: `c` is a valid NUL-terminated path and `st` a zeroed out-parameter.
        let mut st: libc::statvfs = unsafe { std::mem::zeroed() };
        if unsafe { libc::statvfs(c.as_ptr(), &mut st) } != 0 {
            return Ok(());
        }
        let free = st.f_bavail as f64 * st.f_frsize as f64;
        if bytes * 1.05 > free {
            return Err(Error::output(
            dir,
            format!(
                "the requested VTK/HDF5 series needs about {:.0} MB but only {:.0} MB are free; write fewer frames (output.*.every, from_revolution/to_revolution, fields) or choose another --out",
                bytes / 1e6,
                free / 1e6
            ),
        ));
        }
    }
    #[cfg(not(unix))]
    let _ = (dir, bytes);
    Ok(())
}

/// True when the scene asks for any time series.
pub fn wanted(o: &OutputSpec) -> bool {
    o.vtk.is_some() || o.hdf5.is_some()
}

/// Frame plans of the scene's writers at one speed, as `(format, plan)`, e.g. for reports.
pub fn frame_plans(o: &OutputSpec, plan: &StepPlan) -> Vec<(&'static str, FramePlan)> {
    let mut v = Vec::new();
    if let Some(s) = &o.vtk {
        v.push(("vtk", FramePlan::new(s, plan)));
    }
    if let Some(s) = &o.hdf5 {
        v.push(("hdf5", FramePlan::new(s, plan)));
    }
    v
}

/// One line per time-series writer for `rubsim check`: files, frame count and interval at the
/// speed of `plan`.
pub fn describe(o: &OutputSpec, plan: &StepPlan, sweep: bool) -> Vec<String> {
    let folder = if sweep {
        match &o.per_speed {
            PerSpeed::All(false) => {
                return vec!["time series: none (sweep without output.per_speed)".into()]
            }
            PerSpeed::All(true) => "speed_<ν>/ for every speed, ",
            PerSpeed::Speeds(_) => "speed_<ν>/ for the speeds of output.per_speed, ",
        }
    } else {
        ""
    };
    frame_plans(o, plan)
        .into_iter()
        .map(|(fmt, fp)| {
            let files = match fmt {
                "vtk" => format!("{} + {}/frame_NNNNNN.vtu", vtk::PVD, vtk::FRAME_DIR),
                _ => "results.vtkhdf".to_string(),
            };
            format!(
                "{fmt}: {folder}{files}: {} frames, every {} steps (Δt = {:.3e} s), steps {}–{} of {}",
                fp.count(),
                fp.every,
                plan.dt,
                fp.first,
                fp.last,
                plan.steps
            )
        })
        .collect()
}

impl<'a> ResultsSink<'a> {
    /// The writers `output` asks for at the prepared run `prep` of `model`, or `None` when it
    /// asks for no time series ([`wanted`]); see [`ResultsSink::new`].
    ///
    /// # Errors
    /// As [`ResultsSink::new`].
    pub fn for_output(
        model: &Model,
        prep: &'a Prepared,
        output: &OutputSpec,
        scene_json: &str,
        staging: &Path,
        prefix: &str,
    ) -> Result<Option<Self>> {
        if !wanted(output) {
            return Ok(None);
        }
        Self::new(model, prep, output, scene_json, staging, prefix).map(Some)
    }

    /// Prepares the writers of `output` for the prepared run `prep` of `model` (whose case and
    /// step plan it lays out and frames); files go below `staging/prefix` (`prefix` empty or
    /// ending in `/`). Opens every file and writes the static parts at once, so an unwritable
    /// directory fails before the run.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file when a writer cannot be created or the disk is too
    /// full for the series.
    pub fn new(
        model: &Model,
        prep: &'a Prepared,
        output: &OutputSpec,
        scene_json: &str,
        staging: &Path,
        prefix: &str,
    ) -> Result<Self> {
        let (case, plan) = (&prep.case, prep.plan);
        let layout = Layout::new(model, case);
        let state = FrameState::new(&layout, case);
        let info = RunInfo {
            scene_json: scene_json.to_string(),
            speed_ratio: case.speed_ratio,
            omega: prep.omega,
            plan,
            integrator: prep.settings.step.integrator.name(),
        };
        // Refuse a run whose series cannot fit on the disk before it spends its time.
        let mut need_bytes = 0.0;
        let pts = layout.num_points() as f64;
        let cells = layout.grid.num_cells() as f64;
        let conn = layout.grid.connectivity.len() as f64;
        // `twist` and `twist_rate`: one value per point each.
        let twist = if layout.rotor_has_torsion() { 2.0 } else { 0.0 };
        if let Some(spec) = &output.vtk {
            let fp = FramePlan::new(spec, &plan);
            // Per .vtu: geometry and fields as base64 text (4/3) of f64/i64.
            let per =
                (pts * (3.0 + 9.0 + twist) + conn + 2.0 * cells + 4.0 * cells) * 8.0 * 4.0 / 3.0;
            need_bytes += fp.count() as f64 * per;
        }
        if let Some(spec) = &output.hdf5 {
            let fp = FramePlan::new(spec, &plan);
            let per = (pts * (9.0 + twist) + 4.0 * cells + case.rotor.ndof as f64 * 2.0) * 8.0;
            need_bytes += fp.count() as f64 * per;
        }
        check_free_space(staging, need_bytes)?;
        let mut every = 0;
        let mut need_velocity = false;
        let vtk = match &output.vtk {
            Some(spec) => {
                let fp = FramePlan::new(spec, &plan);
                every = gcd(every, fp.every);
                need_velocity |= fp.fields.velocity;
                Some((fp, vtk::VtkSeries::create(staging, prefix, &info)?))
            }
            None => None,
        };
        #[cfg(feature = "hdf5")]
        let hdf5 = match &output.hdf5 {
            Some(spec) => {
                let fp = FramePlan::new(spec, &plan);
                every = gcd(every, fp.every);
                need_velocity |= fp.fields.velocity;
                Some((
                    fp,
                    hdf5::Hdf5Series::create(staging, prefix, &layout, case, &fp, &info)?,
                ))
            }
            None => None,
        };
        #[cfg(not(feature = "hdf5"))]
        if output.hdf5.is_some() {
            return Err(Error::output(
                staging.join(prefix),
                "output.hdf5 is set but rubsim was built without the `hdf5` feature (rebuild with default features, libhdf5 installed)",
            ));
        }
        if need_velocity {
            every = 1;
        }
        Ok(Self {
            case,
            layout,
            state,
            every,
            prev: None,
            need_velocity,
            init_velocity: prep.settings.initial.v,
            vtk,
            #[cfg(feature = "hdf5")]
            hdf5,
        })
    }

    /// The grid layout.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    fn wants(&self, step: usize) -> bool {
        let v = self.vtk.as_ref().is_some_and(|(p, _)| p.contains(step));
        #[cfg(feature = "hdf5")]
        let h = self.hdf5.as_ref().is_some_and(|(p, _)| p.contains(step));
        #[cfg(not(feature = "hdf5"))]
        let h = false;
        v || h
    }

    fn velocities(&mut self) {
        let st = &mut self.state;
        match &self.prev {
            Some(p) if p.step + 1 == st.step && st.t > p.t => {
                let dt = st.t - p.t;
                for (v, (a, b)) in st
                    .velocity
                    .iter_mut()
                    .zip(st.displacement.iter().zip(&p.displacement))
                {
                    *v = [(a[0] - b[0]) / dt, (a[1] - b[1]) / dt, (a[2] - b[2]) / dt];
                }
                for (v, (a, b)) in st.rotor_v.iter_mut().zip(st.rotor_u.iter().zip(&p.rotor_u)) {
                    *v = (a - b) / dt;
                }
            }
            _ => {
                // First frame of the run: the initial velocity (rotor station node; stators at
                // rest).
                st.velocity.fill([0.0; 3]);
                st.rotor_v.fill(0.0);
                if st.step == 0 {
                    let node = self.case.stations.first().map_or(0, |s| s.node);
                    let d = self.case.rotor.node_dofs[node];
                    st.rotor_v[d[0]] = self.init_velocity[0];
                    st.rotor_v[d[1]] = self.init_velocity[1];
                    let p = self.layout.rotor_first_point + node;
                    st.velocity[p] = [self.init_velocity[0], self.init_velocity[1], 0.0];
                }
            }
        }
        // Twist rates: the same backward difference, on the θ_z DOFs.
        for (r, d) in st.rotor_twist_rate.iter_mut().zip(&self.layout.rotor_dofs) {
            *r = d[THETA_Z].map_or(0.0, |i| st.rotor_v[i]);
        }
    }

    fn write(&mut self) -> Result<()> {
        let step = self.state.step;
        if let Some((fp, w)) = &mut self.vtk {
            if fp.contains(step) {
                w.write(&self.layout, &self.state, &fp.fields)?;
            }
        }
        #[cfg(feature = "hdf5")]
        if let Some((fp, w)) = &mut self.hdf5 {
            if fp.contains(step) {
                w.write(&self.layout, &self.state, &fp.fields)?;
            }
        }
        Ok(())
    }

    /// Flushes and closes every writer; returns the files written (relative to the staging
    /// folder, prefix included), to be adopted by the output directory.
    ///
    /// # Errors
    /// [`Error::Output`] naming the file.
    pub fn finish(self) -> Result<Vec<String>> {
        let mut names = Vec::new();
        if let Some((_, w)) = self.vtk {
            names.extend(w.finish()?);
        }
        #[cfg(feature = "hdf5")]
        if let Some((_, w)) = self.hdf5 {
            names.extend(w.finish()?);
        }
        Ok(names)
    }
}

impl FrameSink for ResultsSink<'_> {
    fn every(&self) -> usize {
        self.every
    }

    fn frame(&mut self, frame: &Frame<'_>) -> Result<()> {
        let now = self.wants(frame.step);
        let before_next = self.need_velocity && self.wants(frame.step + 1);
        if !now && !before_next {
            return Ok(());
        }
        self.state.fill(&self.layout, self.case, frame);
        if now {
            if self.need_velocity {
                self.velocities();
            }
            self.write()?;
        }
        if before_next {
            // Reuses the buffers of the previous copy: no allocation after the first frame.
            let p = match self.prev.take() {
                Some(mut p) => {
                    p.displacement.copy_from_slice(&self.state.displacement);
                    p.rotor_u.copy_from_slice(&self.state.rotor_u);
                    p
                }
                None => PrevStep {
                    step: 0,
                    t: 0.0,
                    displacement: self.state.displacement.clone(),
                    rotor_u: self.state.rotor_u.clone(),
                },
            };
            self.prev = Some(PrevStep {
                step: frame.step,
                t: frame.t,
                ..p
            });
        }
        Ok(())
    }
}

/// The sub-folder of a speed's time series in a sweep: `speed_<ω/ω_n>/`.
pub fn speed_folder(speed_ratio: f64) -> String {
    format!("speed_{speed_ratio}/")
}

/// Which sweep speeds write time series (`output.per_speed`), as a flag per speed.
///
/// # Errors
/// A listed speed that is not one of the sweep's (the message lists them).
pub fn per_speed_selection(
    o: &OutputSpec,
    speeds: &[f64],
) -> std::result::Result<Vec<bool>, String> {
    match &o.per_speed {
        PerSpeed::All(all) => Ok(vec![*all && wanted(o); speeds.len()]),
        PerSpeed::Speeds(list) => {
            let mut sel = vec![false; speeds.len()];
            for v in list {
                match speeds.iter().position(|s| (s - v).abs() < 1e-6) {
                    Some(i) => sel[i] = true,
                    None => {
                        return Err(format!(
                            "ω/ω_n = {v} is not a speed of the sweep ({})",
                            speeds
                                .iter()
                                .map(|s| s.to_string())
                                .collect::<Vec<_>>()
                                .join(", ")
                        ))
                    }
                }
            }
            Ok(sel)
        }
    }
}
