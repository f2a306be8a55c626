//! The output grid ([`OutputGrid`]) and where everything of a case sits in it ([`Layout`]):
//! stator points and cells, ring drawings, rotor nodes, contact pairs (see the module
//! documentation of [`crate::results`]).

use crate::math::V2;
use crate::mesh::CellKind;
use crate::model::stator::StatorElement;
use crate::model::{Case, Model, Rotor, Target};
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
    /// The contact target the ring is: the contact kernel ([`pair_state`](crate::contact::pair_state)) gives its normal.
    pub fn target(&self) -> Target {
        Target::Ring {
            center0: self.center0,
            inner_radius: self.inner_radius,
            dofs: self.dofs,
            // The drawing's normal (`pair_state`) does not depend on the contact law.
            radial: false,
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
    /// Some stator wears (`[stator.wear]`): every frame carries the point field `worn_depth`.
    pub wear: bool,
}

impl Layout {
    /// Lays out a case of `model` (which tells whether rotor nodes carry rotations).
    pub fn new(model: &Model, case: &Case) -> Self {
        let z = rotor_node_z(case);
        let mut g = OutputGrid::new();
        let (stator_first_point, stator_num_points, ring_points) = stator_points(&mut g, case, &z);
        let rotor_first_point = g.points.len();
        g.points.extend(z.iter().map(|z| [0.0, 0.0, *z]));
        let element_cells = body_cells(
            &mut g,
            case,
            &stator_first_point,
            &ring_points,
            rotor_first_point,
            z.len(),
        );
        let body_cells = g.num_cells();
        let (pairs, rings, pair_of) = pair_cells(
            &mut g,
            case,
            &stator_first_point,
            &ring_points,
            rotor_first_point,
        );
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
            wear: case.stators.iter().any(|s| s.wear.is_some()),
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

/// Per stator, per ring target: (target, first circle point, contact point).
type RingPoints = Vec<Vec<(usize, usize, usize)>>;

/// The points of every stator (its nodes, then the drawing of its ring targets), stator after
/// stator; returns each stator's first point and point count and its ring drawings.
fn stator_points(
    g: &mut OutputGrid,
    case: &Case,
    z: &[f64],
) -> (Vec<usize>, Vec<usize>, RingPoints) {
    let mut stator_first_point = Vec::new();
    let mut stator_num_points = Vec::new();
    let mut ring_points: RingPoints = Vec::new();
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
    (stator_first_point, stator_num_points, ring_points)
}

/// The cells of the bodies: every stator's elements and ring circles, then the rotor; returns
/// the grid cell of each stator element.
fn body_cells(
    g: &mut OutputGrid,
    case: &Case,
    stator_first_point: &[usize],
    ring_points: &RingPoints,
    rotor_first_point: usize,
    nr: usize,
) -> Vec<Vec<Option<usize>>> {
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
    if nr == 1 {
        g.push_cell(CellType::Vertex, &[rotor_first_point], part::ROTOR, -1, 0);
    } else if nr > 1 {
        let pts: Vec<usize> = (rotor_first_point..rotor_first_point + nr).collect();
        g.push_cell(CellType::PolyLine, &pts, part::ROTOR, -1, 0);
    }
    element_cells
}

/// The cells of the contact candidates, stator by stator, target by target; returns the pair
/// slots, the ring slots and the pair index of each stator node.
fn pair_cells(
    g: &mut OutputGrid,
    case: &Case,
    stator_first_point: &[usize],
    ring_points: &RingPoints,
    rotor_first_point: usize,
) -> (Vec<PairSlot>, Vec<RingSlot>, Vec<Vec<Option<usize>>>) {
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
                    ..
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
    (pairs, rings, pair_of)
}
