//! Meshes of stators as gmsh writes them: nodes, cells grouped in blocks by kind, and the named
//! physical groups that are the contract between a geometry and a scene.
//!
//! # Conventions
//!
//! * Coordinates are in metres, `[x, y, z]`, with the rotor axis along z and the origin on the
//!   undeformed centre of the rotor section the stator faces (so a 2-D stator lies in the
//!   station plane z = 0).
//! * Nodes are numbered `0..nodes.len()` in file order; [`Mesh::node_tags`] keeps gmsh's tags
//!   for messages. Cells keep gmsh's node order (see [`CellKind`]), 0-based.
//! * A physical group is a set of geometric entities of one dimension; its cells are the cells
//!   of those entities. The names rubsim looks for by default are `stator_contact` (the contact
//!   boundary: curves in 2-D, surfaces in 3-D) and `stator_fixed` (fixed supports); groups of the
//!   mesh's top dimension are material regions.
//! * Boundary normals ([`Mesh::boundary_normals`]) point out of the body.
//!
//! [`gmsh`] runs the mesher on parametric `.geo` files and caches its output; [`Mesh::read`]
//! reads MSH 4.1 (ASCII or binary) with the `mshio` crate plus the `$PhysicalNames` section,
//! which `mshio` does not parse.
//!
//! [`geo`] reads what rubsim needs of a `.geo` text (declared parameters and their bounds,
//! imported files); [`process`] runs gmsh under a time limit, in its own process group, killed
//! with rubsim, its output condensed (`condensed`). The reader lives in `msh`, the topology (group nodes, facets, outward normals, the
//! conformity check) in `topology`, the report of a mesh ([`Mesh::summary`]) in `summary`;
//! they add methods to [`Mesh`].

mod condensed;
pub mod geo;
pub mod gmsh;
mod msh;
pub mod process;
mod summary;
mod topology;

pub use summary::{BoundarySummary, GroupSummary, MeshSummary};

use crate::error::MeshError;
use std::path::PathBuf;

/// Cell types rubsim reads, with gmsh's node ordering.
///
/// Node order (gmsh): corners first, counter-clockwise for 2-D cells in a surface whose normal
/// is +z; then mid-edge nodes of edges (0,1), (1,2), (2,0) for `Tri6`, (0,1), (1,2), (2,3),
/// (3,0) for `Quad8`/`Quad9`, then the centre node of `Quad9`. `Tet10` mid-edge nodes follow
/// edges (0,1), (1,2), (2,0), (0,3), (2,3), (1,3) (gmsh's order, note the last two).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CellKind {
    /// 1-node point.
    Point,
    /// 2-node line.
    Line2,
    /// 3-node line (ends, then middle).
    Line3,
    /// 3-node triangle.
    Tri3,
    /// 6-node triangle.
    Tri6,
    /// 4-node quadrilateral.
    Quad4,
    /// 8-node (serendipity) quadrilateral.
    Quad8,
    /// 9-node (Lagrange) quadrilateral.
    Quad9,
    /// 4-node tetrahedron.
    Tet4,
    /// 10-node tetrahedron.
    Tet10,
}

impl CellKind {
    /// From gmsh's element type number, `None` for types rubsim does not read.
    pub fn from_gmsh(t: mshio::ElementType) -> Option<Self> {
        use mshio::ElementType as E;
        Some(match t {
            E::Pnt => CellKind::Point,
            E::Lin2 => CellKind::Line2,
            E::Lin3 => CellKind::Line3,
            E::Tri3 => CellKind::Tri3,
            E::Tri6 => CellKind::Tri6,
            E::Qua4 => CellKind::Quad4,
            E::Qua8 => CellKind::Quad8,
            E::Qua9 => CellKind::Quad9,
            E::Tet4 => CellKind::Tet4,
            E::Tet10 => CellKind::Tet10,
            _ => return None,
        })
    }

    /// Topological dimension.
    pub fn dim(self) -> usize {
        match self {
            CellKind::Point => 0,
            CellKind::Line2 | CellKind::Line3 => 1,
            CellKind::Tri3
            | CellKind::Tri6
            | CellKind::Quad4
            | CellKind::Quad8
            | CellKind::Quad9 => 2,
            CellKind::Tet4 | CellKind::Tet10 => 3,
        }
    }

    /// Number of nodes.
    pub fn nodes(self) -> usize {
        match self {
            CellKind::Point => 1,
            CellKind::Line2 => 2,
            CellKind::Line3 => 3,
            CellKind::Tri3 => 3,
            CellKind::Tri6 => 6,
            CellKind::Quad4 => 4,
            CellKind::Quad8 => 8,
            CellKind::Quad9 => 9,
            CellKind::Tet4 => 4,
            CellKind::Tet10 => 10,
        }
    }

    /// Number of corner (vertex) nodes, which come first.
    pub fn corners(self) -> usize {
        match self {
            CellKind::Point => 1,
            CellKind::Line2 | CellKind::Line3 => 2,
            CellKind::Tri3 | CellKind::Tri6 => 3,
            CellKind::Quad4 | CellKind::Quad8 | CellKind::Quad9 => 4,
            CellKind::Tet4 | CellKind::Tet10 => 4,
        }
    }

    /// Local corner nodes of each facet (edges of 2-D cells, faces of tetrahedra, ends of
    /// lines). Facets are matched by their sorted corner nodes.
    pub fn facets(self) -> &'static [&'static [usize]] {
        match self {
            CellKind::Point => &[],
            CellKind::Line2 | CellKind::Line3 => &[&[0], &[1]],
            CellKind::Tri3 | CellKind::Tri6 => &[&[0, 1], &[1, 2], &[2, 0]],
            CellKind::Quad4 | CellKind::Quad8 | CellKind::Quad9 => {
                &[&[0, 1], &[1, 2], &[2, 3], &[3, 0]]
            }
            CellKind::Tet4 | CellKind::Tet10 => &[&[0, 2, 1], &[0, 1, 3], &[0, 3, 2], &[1, 2, 3]],
        }
    }

    /// gmsh's name of the type.
    pub fn name(self) -> &'static str {
        match self {
            CellKind::Point => "point",
            CellKind::Line2 => "2-node line",
            CellKind::Line3 => "3-node line",
            CellKind::Tri3 => "3-node triangle",
            CellKind::Tri6 => "6-node triangle",
            CellKind::Quad4 => "4-node quadrilateral",
            CellKind::Quad8 => "8-node quadrilateral",
            CellKind::Quad9 => "9-node quadrilateral",
            CellKind::Tet4 => "4-node tetrahedron",
            CellKind::Tet10 => "10-node tetrahedron",
        }
    }

    /// VTK cell type number (for writers).
    pub fn vtk_type(self) -> u8 {
        match self {
            CellKind::Point => 1,
            CellKind::Line2 => 3,
            CellKind::Line3 => 21,
            CellKind::Tri3 => 5,
            CellKind::Tri6 => 22,
            CellKind::Quad4 => 9,
            CellKind::Quad8 => 23,
            CellKind::Quad9 => 28,
            CellKind::Tet4 => 10,
            CellKind::Tet10 => 24,
        }
    }
}

/// Cells of one kind on one geometric entity.
#[derive(Debug, Clone, PartialEq)]
pub struct CellBlock {
    /// Cell type.
    pub kind: CellKind,
    /// Dimension of the geometric entity (equals `kind.dim()`).
    pub entity_dim: usize,
    /// gmsh tag of the geometric entity.
    pub entity: i32,
    /// Connectivity, `kind.nodes()` 0-based node indices per cell, flat.
    pub conn: Vec<usize>,
    /// gmsh element tag of each cell.
    pub tags: Vec<u64>,
}

impl CellBlock {
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.tags.len()
    }
    /// True when the block has no cells.
    pub fn is_empty(&self) -> bool {
        self.tags.is_empty()
    }
    /// Node indices of cell `i`.
    pub fn cell(&self, i: usize) -> &[usize] {
        let n = self.kind.nodes();
        &self.conn[i * n..(i + 1) * n]
    }
    /// Iterates the cells' node lists.
    pub fn cells(&self) -> impl Iterator<Item = &[usize]> {
        self.conn.chunks_exact(self.kind.nodes())
    }
}

/// A named physical group.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// Name from `$PhysicalNames` (or `group_<tag>` when the file names none).
    pub name: String,
    /// Dimension of its entities.
    pub dim: usize,
    /// gmsh physical tag.
    pub tag: i32,
    /// Tags of its geometric entities (of dimension `dim`).
    pub entities: Vec<i32>,
}

/// A mesh read from a gmsh MSH 4.1 file.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// The file it was read from (for messages).
    pub file: PathBuf,
    /// Node coordinates `[x, y, z]` (m).
    pub nodes: Vec<[f64; 3]>,
    /// gmsh tag of each node.
    pub node_tags: Vec<u64>,
    /// Cell blocks, one per (entity, kind).
    pub blocks: Vec<CellBlock>,
    /// Physical groups.
    pub groups: Vec<Group>,
}

impl Mesh {
    /// Highest dimension of any cell (0 for a mesh without cells).
    pub fn dim(&self) -> usize {
        self.blocks
            .iter()
            .filter(|b| !b.is_empty())
            .map(|b| b.kind.dim())
            .max()
            .unwrap_or(0)
    }

    /// The physical group called `name`.
    pub fn group(&self, name: &str) -> Result<&Group, MeshError> {
        self.groups
            .iter()
            .find(|g| g.name == name)
            .ok_or_else(|| MeshError::MissingGroup {
                file: self.file.clone(),
                name: name.to_string(),
                available: self.group_list(),
            })
    }

    /// The groups as `name (dim d)`, for messages.
    pub fn group_list(&self) -> Vec<String> {
        self.groups
            .iter()
            .map(|g| format!("{} (dim {})", g.name, g.dim))
            .collect()
    }

    /// The cell blocks of a group.
    pub fn group_blocks<'a>(&'a self, g: &'a Group) -> impl Iterator<Item = &'a CellBlock> + 'a {
        self.blocks
            .iter()
            .filter(move |b| b.entity_dim == g.dim && g.entities.contains(&b.entity))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// Two triangles forming the unit square, its bottom edge a `stator_contact` group.
    pub(crate) const SQUARE: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
1 2 \"stator_contact\"
2 1 \"stator\"
$EndPhysicalNames
$Entities
0 1 1 0
1 0 0 0 1 0 0 1 2 0
1 0 0 0 1 1 0 1 1 0
$EndEntities
$Nodes
2 4 1 4
1 1 0 2
1
2
0 0 0
1 0 0
2 1 0 2
3
4
1 1 0
0 1 0
$EndNodes
$Elements
2 3 1 3
1 1 1 1
1 1 2
2 1 2 2
2 1 2 3
3 1 3 4
$EndElements
";

    #[test]
    fn reads_nodes_cells_and_named_groups() {
        let m = Mesh::parse(Path::new("sq.msh"), SQUARE.as_bytes()).unwrap();
        assert_eq!(m.nodes.len(), 4);
        assert_eq!(m.dim(), 2);
        assert_eq!(m.group("stator").unwrap().dim, 2);
        assert_eq!(m.group_nodes("stator_contact").unwrap(), vec![0, 1]);
        let n = m.boundary_normals("stator_contact").unwrap();
        // Bottom edge of the square: outward normal −y.
        for (_, v) in n {
            assert!((v[1] + 1.0).abs() < 1e-12 && v[0].abs() < 1e-12, "{v:?}");
        }
        m.check_conforming().unwrap();
        let e = m.group("stator_fixed").unwrap_err().to_string();
        assert!(
            e.contains("sq.msh")
                && e.contains("stator_fixed")
                && e.contains("stator_contact (dim 1)"),
            "{e}"
        );
    }
}
