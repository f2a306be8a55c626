//! What a mesh holds, summed up for a report (`rubsim mesh`): its extent, its cells by kind,
//! its physical groups, and where its contact boundary lies.

use super::Mesh;
use crate::error::MeshError;
use std::collections::BTreeMap;

/// A physical group in numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupSummary {
    /// Group name.
    pub name: String,
    /// Dimension of its entities.
    pub dim: usize,
    /// gmsh's physical tag.
    pub tag: i32,
    /// Geometric entities in the group.
    pub entities: usize,
    /// Cells of those entities.
    pub elements: usize,
    /// Distinct nodes of those cells.
    pub nodes: usize,
}

/// A mesh in numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshSummary {
    /// Dimension of the mesh (of its top cells).
    pub dim: usize,
    /// Number of nodes.
    pub nodes: usize,
    /// Bounding box `[min, max]` of the node coordinates (m).
    pub bounds: [[f64; 3]; 2],
    /// Cells per kind name (`"Tri6"`, …).
    pub cells: BTreeMap<&'static str, usize>,
    /// The physical groups, in the file's order.
    pub groups: Vec<GroupSummary>,
}

/// Where a contact boundary lies with respect to the rotor axis (z).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundarySummary {
    /// Nodes on the boundary.
    pub nodes: usize,
    /// Smallest and largest distance of those nodes from the axis (m).
    pub radius: [f64; 2],
    /// Nodes whose outward normal points toward the axis (the face a rotor inside can touch).
    pub facing_axis: usize,
}

impl Mesh {
    /// Extent, cells per kind and physical groups.
    pub fn summary(&self) -> MeshSummary {
        let mut cells: BTreeMap<&'static str, usize> = BTreeMap::new();
        for b in &self.blocks {
            *cells.entry(b.kind.name()).or_default() += b.len();
        }
        let bounds = self.nodes.iter().fold(
            [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]],
            |[mut lo, mut hi], p| {
                for i in 0..3 {
                    lo[i] = lo[i].min(p[i]);
                    hi[i] = hi[i].max(p[i]);
                }
                [lo, hi]
            },
        );
        let groups = self
            .groups
            .iter()
            .map(|g| GroupSummary {
                name: g.name.clone(),
                dim: g.dim,
                tag: g.tag,
                entities: g.entities.len(),
                elements: self.group_blocks(g).map(|b| b.len()).sum(),
                nodes: self.group_nodes(&g.name).map(|v| v.len()).unwrap_or(0),
            })
            .collect();
        MeshSummary {
            dim: self.dim(),
            nodes: self.nodes.len(),
            bounds,
            cells,
            groups,
        }
    }

    /// The boundary group `name` against the rotor axis, `None` when the mesh has no such group.
    ///
    /// # Errors
    /// Those of [`Mesh::boundary_normals`] (a group of the wrong dimension).
    pub fn boundary_summary(&self, name: &str) -> Result<Option<BoundarySummary>, MeshError> {
        if !self.groups.iter().any(|g| g.name == name) {
            return Ok(None);
        }
        let n = self.boundary_normals(name)?;
        let rho = |i: usize| self.nodes[i][0].hypot(self.nodes[i][1]);
        Ok(Some(BoundarySummary {
            nodes: n.len(),
            radius: [
                n.iter().map(|(i, _)| rho(*i)).fold(f64::INFINITY, f64::min),
                n.iter().map(|(i, _)| rho(*i)).fold(0.0, f64::max),
            ],
            facing_axis: n
                .iter()
                .filter(|(i, v)| v[0] * self.nodes[*i][0] + v[1] * self.nodes[*i][1] < 0.0)
                .count(),
        }))
    }
}
