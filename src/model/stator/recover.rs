//! Stress and strain recovery of stators from a free-DOF displacement: element forces and
//! stresses ([`StatorModel::element_forces`]), von Mises stresses at cell centroids and nodal
//! stresses averaged over the cells sharing a node ([`nodal_stress`]).

use super::{StatorElement, StatorModel};
use crate::element::solid2d::{self, Elastic2};
use crate::element::solid3d::{self, Elastic3};
use crate::math::V2;
use crate::mesh::CellKind;

impl StatorModel {
    /// Axial force (N) and stress (Pa) in each bar and frame for a free-DOF displacement `u`;
    /// springs give their force and NaN stress; 2-D cells NaN force and the von Mises stress at
    /// their centroid (nodal stresses: [`nodal_stress`]).
    pub fn element_forces(&self, u: &[f64]) -> Vec<(f64, f64)> {
        let disp = |n: usize| -> V2 {
            let d = self.node_dofs[n];
            [d[0].map_or(0.0, |i| u[i]), d[1].map_or(0.0, |i| u[i])]
        };
        self.elements
            .iter()
            .map(|el| match el {
                StatorElement::Bar {
                    nodes,
                    ea,
                    youngs_modulus,
                    length,
                } => {
                    let a = self.nodes[nodes[0]];
                    let b = self.nodes[nodes[1]];
                    let e = [(b[0] - a[0]) / length, (b[1] - a[1]) / length];
                    let ua = disp(nodes[0]);
                    let ub = disp(nodes[1]);
                    let strain = ((ub[0] - ua[0]) * e[0] + (ub[1] - ua[1]) * e[1]) / length;
                    (ea * strain, youngs_modulus * strain)
                }
                StatorElement::Spring {
                    node,
                    stiffness,
                    dir,
                } => {
                    let d = disp(*node);
                    (stiffness * (d[0] * dir[0] + d[1] * dir[1]), f64::NAN)
                }
                StatorElement::Solid2 {
                    kind,
                    nodes,
                    material,
                } => (
                    f64::NAN,
                    centroid_von_mises(self, *kind, nodes, material, u),
                ),
                StatorElement::Solid3 {
                    kind,
                    nodes,
                    material,
                } => (
                    f64::NAN,
                    centroid_von_mises_3d(self, *kind, nodes, material, u),
                ),
                StatorElement::Frame {
                    nodes,
                    rot_dofs,
                    section,
                    ..
                } => {
                    let (a, b) = (disp(nodes[0]), disp(nodes[1]));
                    let r = |k: usize| rot_dofs[k].map_or(0.0, |i| u[i]);
                    let ue = [a[0], a[1], r(0), b[0], b[1], r(1)];
                    let (n, _, _) = crate::element::frame::frame_section_forces(
                        self.nodes[nodes[0]],
                        self.nodes[nodes[1]],
                        section,
                        &ue,
                    );
                    (n, n / section.area)
                }
            })
            .collect()
    }
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
    for el in model.elements.iter() {
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
