//! Stator models as linear 2-D bodies in the plane of the station they face.
//!
//! Coordinates are relative to the undeformed centre of that station (m). Node DOFs are
//! `[u_x, u_y]`; fixed DOFs are removed, so a node's DOF is `Option<usize>` (`None` = fixed).
//! A stator with zero total mass is *massless* (paper Sec. 2.5.1): it enters the time loop only
//! through the compliance `K⁻¹` of its contact DOFs. Otherwise it is lumped and explicit.

use crate::error::ModelError;
use crate::linalg::{Cholesky, Csc};
use crate::math::V2;
use crate::scene::{FeElementSpec, FeStatorSpec};

/// What the rotor section can touch.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// A stator node at undeformed position `x0` (node-to-nodes, paper Method III).
    Node {
        /// Node index in the stator mesh.
        node: usize,
        /// Undeformed position (m).
        x0: V2,
        /// Free DOFs `[x, y]` (None = fixed).
        dofs: [Option<usize>; 2],
    },
    /// The inner circle of a rigid ring centred at `center0 + u` (circle-in-circle contact).
    Ring {
        /// Undeformed centre (m).
        center0: V2,
        /// Inner radius r + δ (m).
        inner_radius: f64,
        /// Free DOFs of the ring centre `[x, y]`.
        dofs: [Option<usize>; 2],
    },
}

impl Target {
    /// The target's free DOFs.
    pub fn dofs(&self) -> [Option<usize>; 2] {
        match self {
            Target::Node { dofs, .. } | Target::Ring { dofs, .. } => *dofs,
        }
    }
}

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
        let mut scatter = |dofs: &[Option<usize>], ke: &[f64]| {
            let n = dofs.len();
            for i in 0..n {
                for j in 0..n {
                    if let (Some(a), Some(b)) = (dofs[i], dofs[j]) {
                        if ke[i * n + j] != 0.0 {
                            kt.push((a, b, ke[i * n + j]));
                        }
                    }
                }
            }
        };
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
                    scatter(&dofs, &ke);
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
                    scatter(&node_dofs[*node], &ke);
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
        // K_cc = (C_cc)^-1 with C_cc the compliance on contact DOFs.
        let cd = self.contact_dofs();
        if cd.is_empty() {
            return 0.0;
        }
        let n = self.ndof;
        let chol = match Cholesky::new(&self.k) {
            Ok(c) => c,
            Err(_) => return f64::INFINITY,
        };
        let nc = cd.len();
        let mut cols = vec![0.0; n * nc];
        for (j, &d) in cd.iter().enumerate() {
            cols[j * n + d] = 1.0;
        }
        chol.solve_in_place(&mut cols);
        let cmat = nalgebra::DMatrix::from_fn(nc, nc, |i, j| cols[j * n + cd[i]]);
        let kcc = match cmat.try_inverse() {
            Some(k) => k,
            None => return f64::INFINITY,
        };
        // Translation matrix T (nc × 2).
        let mut t = nalgebra::DMatrix::zeros(nc, 2);
        for tg in &self.targets {
            for comp in 0..2 {
                if let Some(d) = tg.dofs()[comp] {
                    let i = cd.iter().position(|x| *x == d).expect("contact dof");
                    t[(i, comp)] = 1.0;
                }
            }
        }
        let k2 = t.transpose() * kcc * t;
        let (a, b, c) = (k2[(0, 0)], k2[(0, 1)], k2[(1, 1)]);
        0.5 * (a + c) + (0.25 * (a - c) * (a - c) + b * b).sqrt()
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
    /// lumped mass; `0` for a massless stator.
    pub fn omega_max_sq_bound(&self) -> f64 {
        if self.massless() {
            return 0.0;
        }
        let md = self.m.diagonal();
        let mut rows = vec![0.0; self.ndof];
        for (r, _, v) in self.k.triplets() {
            rows[r] += v.abs();
        }
        rows.iter().zip(&md).map(|(s, m)| s / m).fold(0.0, f64::max)
    }

    /// Axial force (N) and stress (Pa) in each bar for a free-DOF displacement `u`; springs give
    /// their force and NaN stress.
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
