//! Stator models as linear 2-D bodies in the plane of the station they face.
//!
//! Coordinates are relative to the undeformed centre of that station (m). Node DOFs are
//! `[u_x, u_y]`; fixed DOFs are removed, so a node's DOF is `Option<usize>` (`None` = fixed).
//! A stator with zero total mass is *massless* (paper Sec. 2.5.1): it enters the time loop only
//! through the compliance `K⁻¹` of its contact DOFs. Otherwise it is lumped and explicit.

use crate::assembly::scatter;
use crate::contact::Target;
use crate::error::ModelError;
use crate::linalg::{Cholesky, Csc};
use crate::math::V2;
use crate::scene::{FeElementSpec, FeStatorSpec};

/// Element connectivity kept for output and stress recovery.
#[derive(Debug, Clone, PartialEq)]
pub enum StatorElement {
    /// Bar between two nodes with axial stiffness `ea` (N) and length `length` (m).
    Bar {
        /// Node indices.
        nodes: [usize; 2],
        /// E·A (N).
        ea: f64,
        /// E (Pa), for stress.
        youngs_modulus: f64,
        /// Undeformed length (m).
        length: f64,
    },
    /// Spring to ground.
    Spring {
        /// Node.
        node: usize,
        /// Stiffness (N/m).
        stiffness: f64,
        /// Unit direction.
        dir: V2,
    },
    /// 2-D continuum cell of a meshed stator (plane stress or strain).
    Solid2 {
        /// Cell type (3/6-node triangle, 4/8/9-node quadrilateral).
        kind: crate::mesh::CellKind,
        /// Node indices in gmsh order, counter-clockwise.
        nodes: Vec<usize>,
        /// Material and thickness.
        material: crate::element::solid2d::Elastic2,
    },
    /// Tetrahedron of a 3-D meshed stator (node z and u_z DOFs in
    /// [`super::mesh_stator::MeshStatorData`]).
    Solid3 {
        /// Cell type (4- or 10-node tetrahedron).
        kind: crate::mesh::CellKind,
        /// Node indices in gmsh order.
        nodes: Vec<usize>,
        /// Material.
        material: crate::element::solid3d::Elastic3,
    },
    /// Frame (beam-column) between two nodes with rotation DOFs θ_z (meshed-stator supports).
    Frame {
        /// Node indices.
        nodes: [usize; 2],
        /// Free DOFs of θ_z at the two nodes (numbered after the translations).
        rot_dofs: [Option<usize>; 2],
        /// Cross-section.
        section: crate::element::frame::FrameSection,
        /// Undeformed length (m).
        length: f64,
    },
}

/// A stator ready for the integrator.
#[derive(Debug, Clone)]
pub struct StatorModel {
    /// Name from the scene.
    pub name: String,
    /// Index of the station it faces.
    pub station: usize,
    /// Node coordinates (m), relative to the station centre.
    pub nodes: Vec<V2>,
    /// Free DOF of each node component (None = fixed).
    pub node_dofs: Vec<[Option<usize>; 2]>,
    /// Number of free DOFs.
    pub ndof: usize,
    /// Stiffness over free DOFs (N/m).
    pub k: Csc,
    /// Lumped mass over free DOFs (kg); all zero for a massless stator.
    pub m: Csc,
    /// Damping over free DOFs (N·s/m).
    pub c: Csc,
    /// Contact targets.
    pub targets: Vec<Target>,
    /// Elements (for output).
    pub elements: Vec<StatorElement>,
    /// Clearance δ at this speed (m), as resolved (for reports and plots).
    pub clearance: f64,
    /// Direction of the stator seen from the station (degrees), for plots (rod: its axis).
    pub angle_deg: Option<f64>,
    /// True for a ring (the clearance is a circle).
    pub is_ring: bool,
    /// Meshed stators: the mesh's provenance and quantities shared by every speed.
    pub mesh: Option<std::sync::Arc<super::mesh_stator::MeshStatorData>>,
}

impl StatorModel {
    /// True when the stator carries no mass (enters the loop as a compliance).
    pub fn massless(&self) -> bool {
        self.m.triplets().all(|(_, _, v)| v == 0.0)
    }

    /// Builds a general FE stator from nodes, elements and fixed DOFs (scene `kind = "fe"`).
    pub fn from_fe(spec: &FeStatorSpec, station: usize) -> Result<Self, ModelError> {
        let nn = spec.nodes.len();
        let mut fixed = vec![[false; 2]; nn];
        for f in &spec.fixed {
            fixed[f[0]][f[1]] = true;
        }
        let mut elements = Vec::new();
        let mut mass_node = vec![0.0; nn];
        for el in &spec.elements {
            match el {
                FeElementSpec::Bar {
                    nodes,
                    youngs_modulus,
                    area,
                    density,
                } => {
                    let a = spec.nodes[nodes[0]];
                    let b = spec.nodes[nodes[1]];
                    let l = (b[0] - a[0]).hypot(b[1] - a[1]);
                    elements.push(StatorElement::Bar {
                        nodes: *nodes,
                        ea: youngs_modulus * area,
                        youngs_modulus: *youngs_modulus,
                        length: l,
                    });
                    let half = density * area * l / 2.0;
                    mass_node[nodes[0]] += half;
                    mass_node[nodes[1]] += half;
                }
                FeElementSpec::Spring {
                    node,
                    stiffness,
                    angle_deg,
                } => {
                    let t = angle_deg.to_radians();
                    elements.push(StatorElement::Spring {
                        node: *node,
                        stiffness: *stiffness,
                        dir: [t.cos(), t.sin()],
                    });
                }
            }
        }
        for (n, m) in &spec.point_masses {
            mass_node[*n] += m;
        }
        let targets_nodes: Vec<usize> = spec.contact_nodes.clone();
        Self::assemble(
            &spec.name,
            station,
            spec.nodes.clone(),
            fixed,
            elements,
            &mass_node,
            spec.rayleigh,
            &targets_nodes,
        )
    }

    /// The paper's rod: `elements` bars along direction `angle_deg` from the station centre,
    /// tip at distance `radius + clearance`, far end fixed, lateral DOFs guided.
    #[allow(clippy::too_many_arguments)]
    pub fn rod(
        name: &str,
        station: usize,
        radius: f64,
        clearance: f64,
        length: f64,
        ea: f64,
        youngs_modulus: f64,
        mass_per_length: f64,
        elements: usize,
        angle_deg: f64,
        rayleigh: [f64; 2],
    ) -> Result<Self, ModelError> {
        let t = angle_deg.to_radians();
        let dir = [t.cos(), t.sin()];
        let r0 = radius + clearance;
        let le = length / elements as f64;
        let nodes: Vec<V2> = (0..=elements)
            .map(|i| {
                let s = r0 + i as f64 * le;
                [s * dir[0], s * dir[1]]
            })
            .collect();
        // Guide: lateral motion is fixed. For an axis along x or y this is the other
        // component; for an oblique rod a skew constraint would be needed, so the rod axis is
        // restricted to the coordinate axes.
        let lateral = if dir[0].abs() > dir[1].abs() { 1 } else { 0 };
        if dir[lateral].abs() > 1e-9 {
            return Err(ModelError::Inconsistent {
                what: format!("stator `{name}`"),
                message: format!(
                    "rod angle {angle_deg}° is not along a coordinate axis (0, 90, 180, 270); use kind = \"fe\" for oblique rods"
                ),
            });
        }
        let mut fixed = vec![[false; 2]; elements + 1];
        for f in fixed.iter_mut() {
            f[lateral] = true;
        }
        fixed[elements] = [true, true];
        let bars = (0..elements)
            .map(|i| StatorElement::Bar {
                nodes: [i, i + 1],
                ea,
                youngs_modulus,
                length: le,
            })
            .collect();
        let mut mass_node = vec![0.0; elements + 1];
        for i in 0..elements {
            mass_node[i] += mass_per_length * le / 2.0;
            mass_node[i + 1] += mass_per_length * le / 2.0;
        }
        let mut s = Self::assemble(
            name,
            station,
            nodes,
            fixed,
            bars,
            &mass_node,
            rayleigh,
            &[0],
        )?;
        s.clearance = clearance;
        s.angle_deg = Some(angle_deg);
        Ok(s)
    }

    /// Rigid ring on isotropic springs `stiffness` around a station of radius `radius`, with
    /// radial clearance `clearance`; `mass` 0 for massless.
    pub fn ring(
        name: &str,
        station: usize,
        radius: f64,
        clearance: f64,
        stiffness: f64,
        mass: f64,
        damping: f64,
    ) -> Self {
        let d = |v: f64| Csc::from_triplets(2, 2, &[(0, 0, v), (1, 1, v)]);
        StatorModel {
            name: name.to_string(),
            station,
            nodes: vec![[0.0, 0.0]],
            node_dofs: vec![[Some(0), Some(1)]],
            ndof: 2,
            k: d(stiffness),
            m: if mass > 0.0 {
                d(mass)
            } else {
                Csc::zeros(2, 2)
            },
            c: if mass > 0.0 {
                d(damping)
            } else {
                Csc::zeros(2, 2)
            },
            targets: vec![Target::Ring {
                center0: [0.0, 0.0],
                inner_radius: radius + clearance,
                dofs: [Some(0), Some(1)],
            }],
            elements: vec![],
            clearance,
            angle_deg: None,
            is_ring: true,
            mesh: None,
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn assemble(
        name: &str,
        station: usize,
        nodes: Vec<V2>,
        fixed: Vec<[bool; 2]>,
        elements: Vec<StatorElement>,
        mass_node: &[f64],
        rayleigh: [f64; 2],
        contact_nodes: &[usize],
    ) -> Result<Self, ModelError> {
        let mut ndof = 0;
        let node_dofs: Vec<[Option<usize>; 2]> = fixed
            .iter()
            .map(|f| {
                let mut d = [None, None];
                for c in 0..2 {
                    if !f[c] {
                        d[c] = Some(ndof);
                        ndof += 1;
                    }
                }
                d
            })
            .collect();
        let mut kt: Vec<(usize, usize, f64)> = Vec::new();
        for el in &elements {
            match el {
                StatorElement::Bar {
                    nodes: nd,
                    ea,
                    length,
                    ..
                } => {
                    let a = nodes[nd[0]];
                    let b = nodes[nd[1]];
                    let (c, s) = ((b[0] - a[0]) / length, (b[1] - a[1]) / length);
                    let kk = ea / length;
                    let q = [c, s, -c, -s];
                    let mut ke = [0.0; 16];
                    for i in 0..4 {
                        for j in 0..4 {
                            ke[i * 4 + j] = kk * q[i] * q[j];
                        }
                    }
                    let dofs = [
                        node_dofs[nd[0]][0],
                        node_dofs[nd[0]][1],
                        node_dofs[nd[1]][0],
                        node_dofs[nd[1]][1],
                    ];
                    scatter(&mut kt, &dofs, &ke);
                }
                StatorElement::Spring {
                    node,
                    stiffness,
                    dir,
                } => {
                    let ke = [
                        stiffness * dir[0] * dir[0],
                        stiffness * dir[0] * dir[1],
                        stiffness * dir[1] * dir[0],
                        stiffness * dir[1] * dir[1],
                    ];
                    scatter(&mut kt, &node_dofs[*node], &ke);
                }
                StatorElement::Solid2 { .. }
                | StatorElement::Solid3 { .. }
                | StatorElement::Frame { .. } => {
                    unreachable!("meshed-stator elements are assembled by model::mesh_stator")
                }
            }
        }
        let k = Csc::from_triplets(ndof, ndof, &kt);
        let mut mt = Vec::new();
        for (n, d) in node_dofs.iter().enumerate() {
            for dof in d.iter().flatten() {
                mt.push((*dof, *dof, mass_node[n]));
            }
        }
        let m = Csc::from_triplets(ndof, ndof, &mt);
        let total_mass: f64 = mt.iter().map(|t| t.2).sum();
        let what = format!("stator `{name}`");
        if total_mass > 0.0 {
            if let Some((dof, _, _)) = mt.iter().find(|t| t.2 <= 0.0) {
                return Err(ModelError::Inconsistent {
                    what,
                    message: format!(
                        "free DOF {dof} has no mass while the stator has mass; give every free node mass (density or point_masses) or make the stator massless"
                    ),
                });
            }
        }
        let c = Csc::lin_comb(rayleigh[0], &m, rayleigh[1], &k);
        let targets = contact_nodes
            .iter()
            .map(|&n| Target::Node {
                node: n,
                x0: nodes[n],
                dofs: node_dofs[n],
            })
            .collect();
        let model = StatorModel {
            name: name.to_string(),
            station,
            nodes,
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
            mesh: None,
        };
        if ndof > 0 {
            Cholesky::new(&model.k).map_err(|e| ModelError::Singular {
                what: format!("stator `{name}` stiffness"),
                detail: format!(
                    "{e}; the stator has a free rigid-body or mechanism mode: fix more DOFs"
                ),
            })?;
        }
        Ok(model)
    }

    /// Upper bound of the stiffness the rotor section feels when it pushes all contact
    /// targets together in one direction (N/m): the largest eigenvalue of `Tᵀ K_cc T`, with
    /// `K_cc` the stiffness condensed on the contact DOFs and `T` a rigid translation. Any
    /// subset of targets in contact is softer (Schur complement argument).
    pub fn contact_stiffness_bound(&self) -> f64 {
        match &self.mesh {
            // Invariant under the rigid placement: computed once for every speed.
            Some(md) => *md
                .contact_stiffness
                .get_or_init(|| self.contact_stiffness_schur()),
            None => self.contact_stiffness_schur(),
        }
    }

    /// `Tᵀ S T` with `S = K_cc − K_ci K_ii⁻¹ K_ic` the Schur complement on the contact DOFs
    /// (= (K⁻¹)_cc⁻¹): one sparse Cholesky of the interior block and two solves, whatever the
    /// number of contact DOFs.
    fn contact_stiffness_schur(&self) -> f64 {
        let cd = self.contact_dofs();
        if cd.is_empty() {
            return 0.0;
        }
        let n = self.ndof;
        // Translation component of each contact DOF (T), interior numbering of the others.
        let mut comp: Vec<Option<usize>> = vec![None; n];
        for tg in &self.targets {
            for (c, d) in tg.dofs().iter().enumerate() {
                if let Some(d) = d {
                    comp[*d] = Some(c);
                }
            }
        }
        let mut inner = vec![usize::MAX; n];
        let mut ni = 0;
        for (d, c) in comp.iter().enumerate() {
            if c.is_none() {
                inner[d] = ni;
                ni += 1;
            }
        }
        let mut k2 = [[0.0; 2]; 2];
        let mut rhs = vec![0.0; 2 * ni];
        let mut kii = Vec::new();
        for (r, c, v) in self.k.triplets() {
            match (comp[r], comp[c]) {
                (Some(a), Some(b)) => k2[a][b] += v,
                (None, Some(b)) => rhs[b * ni + inner[r]] += v,
                (None, None) => kii.push((inner[r], inner[c], v)),
                (Some(_), None) => {}
            }
        }
        if ni > 0 {
            let kii = Csc::from_triplets(ni, ni, &kii);
            let chol = match Cholesky::new(&kii) {
                Ok(c) => c,
                Err(_) => return f64::INFINITY,
            };
            let mut x = rhs.clone();
            chol.solve_in_place(&mut x);
            for a in 0..2 {
                for b in 0..2 {
                    k2[a][b] -= (0..ni)
                        .map(|i| rhs[a * ni + i] * x[b * ni + i])
                        .sum::<f64>();
                }
            }
        }
        let (a, b, c) = (k2[0][0], 0.5 * (k2[0][1] + k2[1][0]), k2[1][1]);
        0.5 * (a + c) + (0.25 * (a - c) * (a - c) + b * b).sqrt()
    }

    /// The station contact target `t` faces: `station`, except for 3-D meshed stators whose
    /// contact nodes are assigned to stations by axial position.
    pub fn target_station(&self, t: usize) -> usize {
        self.mesh
            .as_ref()
            .and_then(|m| m.target_station.get(t).copied())
            .unwrap_or(self.station)
    }

    /// Sorted distinct stations the stator's targets face.
    pub fn stations(&self) -> Vec<usize> {
        let mut v: Vec<usize> = (0..self.targets.len())
            .map(|t| self.target_station(t))
            .chain(std::iter::once(self.station))
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Sorted distinct free DOFs referenced by contact targets.
    pub fn contact_dofs(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self
            .targets
            .iter()
            .flat_map(|t| t.dofs().into_iter().flatten())
            .collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Gershgorin upper bound of the largest eigenvalue of `M⁻¹K` (rad²/s²) for a stator with
    /// lumped mass (meshed stators: the smaller of it and the element eigenvalue bound);
    /// `0` for a massless stator.
    pub fn omega_max_sq_bound(&self) -> f64 {
        if self.massless() {
            return 0.0;
        }
        let md = self.m.diagonal();
        let mut rows = vec![0.0; self.ndof];
        for (r, _, v) in self.k.triplets() {
            rows[r] += v.abs();
        }
        let gershgorin = rows.iter().zip(&md).map(|(s, m)| s / m).fold(0.0, f64::max);
        // Meshed stators: the element eigenvalue bound when it applies (tighter).
        match self.mesh.as_ref().and_then(|m| m.omega_max_sq) {
            Some(e) => gershgorin.min(e),
            None => gershgorin,
        }
    }

    /// Axial force (N) and stress (Pa) in each bar and frame for a free-DOF displacement `u`;
    /// springs give their force and NaN stress; 2-D cells NaN force and the von Mises stress at
    /// their centroid (nodal stresses: [`super::mesh_stator::nodal_stress`]).
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
                    super::mesh_stator::centroid_von_mises(self, *kind, nodes, material, u),
                ),
                StatorElement::Solid3 {
                    kind,
                    nodes,
                    material,
                } => (
                    f64::NAN,
                    super::mesh_stator::centroid_von_mises_3d(self, *kind, nodes, material, u),
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rod_stiffness_is_ea_over_l_whatever_the_elements() {
        for ne in [1, 3, 8] {
            let r = StatorModel::rod("r", 0, 0.06, 1e-4, 0.04, 75e3, 3e9, 0.0, ne, 90.0, [0.0; 2])
                .unwrap();
            let k = r.contact_stiffness_bound();
            assert!((k / (75e3 / 0.04) - 1.0).abs() < 1e-10, "{ne}: {k}");
            assert!(r.massless());
            // tip above the rotor at r + δ
            assert!((r.nodes[0][1] - 0.0601).abs() < 1e-15);
        }
    }

    #[test]
    fn ring_is_isotropic_spring() {
        let r = StatorModel::ring("g", 0, 0.05, 1e-4, 2e6, 0.0, 0.0);
        assert!((r.contact_stiffness_bound() - 2e6).abs() < 1e-6);
    }

    #[test]
    fn unsupported_fe_stator_is_singular() {
        let spec = FeStatorSpec {
            name: "free".into(),
            station: "s".into(),
            nodes: vec![[0.0, 0.1], [0.0, 0.2]],
            elements: vec![FeElementSpec::Bar {
                nodes: [0, 1],
                youngs_modulus: 1e9,
                area: 1e-4,
                density: 0.0,
            }],
            fixed: vec![],
            contact_nodes: vec![0],
            rayleigh: [0.0; 2],
            point_masses: vec![],
        };
        let e = StatorModel::from_fe(&spec, 0).unwrap_err().to_string();
        assert!(e.contains("free") && e.contains("rigid-body"), "{e}");
    }
}
