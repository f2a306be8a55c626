//! Stator models as linear 2-D bodies in the plane of the station they face.
//!
//! Coordinates are relative to the undeformed centre of that station (m). Node DOFs are
//! `[u_x, u_y]`; fixed DOFs are removed, so a node's DOF is `Option<usize>` (`None` = fixed).
//! A stator with zero total mass is *massless* (paper Sec. 2.5.1): it enters the time loop only
//! through the compliance `K⁻¹` of its contact DOFs. Otherwise it is lumped and explicit.
//!
//! This module holds the stator types; the builders are its children, one per kind
//! ([`rod`], [`ring`], [`fe`], [`mesh`]), and stress recovery is [`recover`]. The children
//! import from here, never the other way, so the stator code has no import cycle.

pub mod fe;
pub mod mesh;
pub mod recover;
pub mod reduce;
pub mod ring;
pub mod rod;

use crate::assembly::scatter;
use crate::contact::{Dashpot, Target};
use crate::error::ModelError;
use crate::linalg::{Cholesky, Csc, LinalgError};
use crate::math::V2;
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

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
    /// [`MeshStatorData`]).
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
    /// Stiffness over free DOFs (N/m). Shared (like `m`, `c` and `elements`) by the copies
    /// of a meshed stator placed per speed, which differ only in their targets and clearance.
    pub k: Arc<Csc>,
    /// Lumped mass over free DOFs (kg); all zero for a massless stator.
    pub m: Arc<Csc>,
    /// Damping over free DOFs (N·s/m).
    pub c: Arc<Csc>,
    /// Contact targets.
    pub targets: Vec<Target>,
    /// Elements (for output).
    pub elements: Arc<Vec<StatorElement>>,
    /// Clearance δ at this speed (m), as resolved (for reports and plots).
    pub clearance: f64,
    /// Direction of the stator seen from the station (degrees), for plots (rod: its axis).
    pub angle_deg: Option<f64>,
    /// True for a ring (the clearance is a circle).
    pub is_ring: bool,
    /// Meshed stators: the mesh's provenance and quantities shared by every speed.
    pub mesh: Option<Arc<MeshStatorData>>,
    /// The contact dashpot (`contact_damping`; massless stators only).
    pub dashpot: Dashpot,
    /// The Craig–Bampton reduction the time loop integrates instead of the full stator
    /// (`[run.reduction] stators = true`, [`reduce::ReducedStator`]); `None`: the full model.
    pub reduced: Option<Arc<reduce::ReducedStator>>,
    /// Archard wear of the contact targets (`[stator.wear]`, `time::wear`); `None`: no wear.
    pub wear: Option<StatorWear>,
}

/// How a stator's contact targets recede: Archard wear (`scene::wear`) — a target with force
/// `p` that slips by `ζ` over a step recedes by `rate p |ζ| / area` (m) — and the plastic
/// shortening of an abradable coating (`scene::abradable`, `time::abradable`).
#[derive(Debug, Clone, PartialEq)]
pub struct StatorWear {
    /// k A (m²/N): Archard's dimensional coefficient `[stator.wear] coefficient` times the wear
    /// magnification `run.wear_acceleration`; 0 for a coating without `[stator.wear]`.
    pub rate: f64,
    /// A: the wear magnification (`run.wear_acceleration`): a run of time t wears as Archard's
    /// law over A t.
    pub acceleration: f64,
    /// Tributary area of each contact target (m², in target order): a rod's cross-section, a
    /// meshed stator's share of its contact boundary ([`MeshStatorData::contact_areas`]).
    pub areas: Vec<f64>,
    /// The elasto-plastic abradable coating on every contact target (`[stator.abradable]`);
    /// `None` without. Never magnified by `run.wear_acceleration`.
    pub layer: Option<crate::resolve::AbradableLayer>,
}

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
    /// Tributary area of each contact target (m², same order as `targets`): an equal share of
    /// every boundary facet it belongs to — in 2-D the facet's length times the thickness, in
    /// 3-D its area ([`crate::mesh::Mesh::boundary_measures`]); what wear divides a worn volume
    /// by.
    pub contact_areas: Vec<f64>,
    /// Station each contact target faces (same order as `targets`).
    pub target_station: Vec<usize>,
    /// 3-D stators: axial coordinate z of every node (m, mesh frame); empty in 2-D.
    pub node_z: Vec<f64>,
    /// 3-D stators: free DOF of u_z of every node; empty in 2-D.
    pub axial_dofs: Vec<Option<usize>>,
    /// 3-D stators: axial position along the rotor (m, rotor frame) of the mesh's z = 0.
    pub axial_origin: f64,
    /// Stators with mass: upper bound of the largest eigenvalue of `M⁻¹K` (rad²/s²) from the
    /// elements (Irons' element eigenvalue theorem: `λ_max ≤ max_e λ_max(K_e, M_e)`), tighter
    /// than Gershgorin; `None` when it does not apply (massless, springs, bars or frames).
    pub omega_max_sq: Option<f64>,
    /// Contact stiffness bound (N/m), computed on first use (invariant under placement).
    pub contact_stiffness: OnceLock<f64>,
    /// Sparse Cholesky factor of K, computed on first use and shared by every run.
    pub factor: OnceLock<Result<Arc<Cholesky>, LinalgError>>,
    /// Columns of `K⁻¹` among the contact DOFs computed by the runs so far (the time loop's
    /// massless-stator compliance, [`ContactColumns`]). K and the contact DOFs do not change
    /// with the speed or the step, so every run of a sweep and every pilot run of the step
    /// choice starts with the columns the earlier ones computed.
    pub compliance_columns: std::sync::Mutex<ContactColumns>,
    /// Craig–Bampton reductions made so far, by cut-off (rad/s): every speed of a sweep with
    /// the same cut-off shares one (the stiffness and mass do not change with the placement).
    pub reductions: std::sync::Mutex<Vec<(f64, Arc<reduce::ReducedStator>)>>,
}

/// Entries of a massless stator's compliance `F = K⁻¹` (m/N) among the contact nodes that have
/// touched, in the order their columns were computed — nothing at interior DOFs nor at contact
/// nodes that never entered a contact problem. By 2 × 2 node blocks ([`NodeBlock`]: a
/// contact node's two DOFs, as its target has them), packed upper-triangular: the node computed
/// `j`-th keeps its blocks with the nodes `i ≤ j` (F is symmetric), so `m` touched nodes hold
/// `32·m(m+1)/2` bytes, a pair of targets' block lies in one cache line, and a column once
/// written never changes: runs share the blocks by reference and append their own.
#[derive(Debug, Default, Clone)]
pub struct ContactColumns {
    /// Contact nodes with a column, in the order computed: each node's two DOFs
    /// (`usize::MAX` for a component it does not have).
    pub touched: Vec<[usize; 2]>,
    /// One block per blocked solve: the node columns of `touched[s..e]` one after the other,
    /// node column `j` holding its `j + 1` blocks with the nodes `0..=j`.
    pub blocks: Vec<Arc<[NodeBlock]>>,
    /// The forward solutions `L⁻¹ P e` of the touched nodes' DOFs on their elimination-tree
    /// paths, labelled by touched position `2·node + component`, when the columns are
    /// computed from paths ([`crate::linalg::Cholesky::path_columns`]; empty otherwise).
    pub paths: crate::linalg::PathStore,
}

/// The compliance between two contact nodes (m/N): `.0[a][b]` the displacement of component
/// `a` of the first per unit force along component `b` of the second (0 for a component a
/// node does not have). Aligned to 32 bytes: a block never straddles two cache lines.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
#[repr(C, align(32))]
pub struct NodeBlock(pub [[f64; 2]; 2]);

impl MeshStatorData {
    /// The Cholesky factor of `k` (the model's stiffness), factored once.
    pub fn factor(&self, k: &Csc) -> Result<Arc<Cholesky>, LinalgError> {
        self.factor
            .get_or_init(|| Cholesky::new(k).map(Arc::new))
            .clone()
    }

    /// The reduction of `s` (this mesh's stator) at cut-off `cutoff` (rad/s), made once per
    /// cut-off.
    ///
    /// # Errors
    /// As [`reduce::ReducedStator::new`].
    pub fn reduction(
        &self,
        s: &StatorModel,
        cutoff: f64,
    ) -> Result<Arc<reduce::ReducedStator>, ModelError> {
        let mut cache = self
            .reductions
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        if let Some((_, r)) = cache.iter().find(|(c, _)| *c == cutoff) {
            return Ok(r.clone());
        }
        let r = Arc::new(reduce::ReducedStator::new(s, cutoff)?);
        cache.push((cutoff, r.clone()));
        Ok(r)
    }
}

impl StatorModel {
    /// True when the stator carries no mass (enters the loop as a compliance).
    pub fn massless(&self) -> bool {
        self.m.triplets().all(|(_, _, v)| v == 0.0)
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

    /// Stored entries of the Cholesky factor of K, when it is known: a meshed stator's,
    /// factored when the model was built (`None` before, after a failed factorisation, and for
    /// a stator without a mesh).
    pub fn factor_nnz(&self) -> Option<usize> {
        self.built_factor().map(|f| f.nnz())
    }

    /// A meshed stator's Cholesky factor of K if it has been computed.
    pub fn built_factor(&self) -> Option<&Arc<Cholesky>> {
        self.mesh
            .as_ref()
            .and_then(|md| md.factor.get())
            .and_then(|f| f.as_ref().ok())
    }

    /// Bytes of a massless stator's compliance among all its contact nodes `n` (the targets'
    /// distinct DOF pairs), packed symmetric by 2 × 2 node blocks ([`ContactColumns`]):
    /// `32·n(n+1)/2`, its bound when every contact node touches.
    pub fn packed_compliance_bytes(&self) -> f64 {
        let mut nodes: Vec<[Option<usize>; 2]> = self
            .targets
            .iter()
            .map(|t| t.dofs())
            .filter(|d| d.iter().any(Option::is_some))
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        let n = nodes.len() as f64;
        16.0 * n * (n + 1.0)
    }

    /// Gershgorin upper bound of the largest eigenvalue of `M⁻¹K` (rad²/s²) for a stator with
    /// lumped mass (meshed stators: the smaller of it and the element eigenvalue bound);
    /// `0` for a massless stator.
    pub fn omega_max_sq_bound(&self) -> f64 {
        if self.massless() {
            return 0.0;
        }
        // A reduced stator: the reduced model's highest frequency, exactly.
        if let Some(r) = &self.reduced {
            return r.omega_max().powi(2);
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
}

/// A stator of bars and springs with lumped nodal masses before assembly: the rod and the
/// general FE stator.
pub(super) struct Lumped<'a> {
    /// Stator name.
    pub name: &'a str,
    /// Index of the station it faces.
    pub station: usize,
    /// Node coordinates (m).
    pub nodes: Vec<V2>,
    /// Fixed components of each node.
    pub fixed: Vec<[bool; 2]>,
    /// Bars and springs.
    pub elements: Vec<StatorElement>,
    /// Lumped mass of each node (kg).
    pub mass_node: Vec<f64>,
    /// Rayleigh damping `[α, β]`.
    pub rayleigh: [f64; 2],
    /// Nodes that can touch the rotor.
    pub contact_nodes: Vec<usize>,
}

/// Why a massless stator refuses damping (`rayleigh`; a ring's `damping` is refused by the
/// scene's validation for the same reason): it enters the loop as the static compliance of its
/// contact boundary, which has no velocity to damp; `contact_damping` is the dashpot it can have
/// (issue 15, item 3).
pub(crate) const MASSLESS_DAMPING: &str = "`rayleigh` damping on a massless stator: a massless stator enters the time loop as the static compliance of its contact boundary and has no velocity to damp (for damping at the contact use `contact_damping` (N·s/m)); give it mass (`density`, `point_masses`) or leave `rayleigh` out";

impl Lumped<'_> {
    /// Numbers the free DOFs, assembles K, the lumped M and C = α M + β K, and checks that K
    /// is positive definite (no free rigid-body or mechanism mode).
    pub fn assemble(self) -> Result<StatorModel, ModelError> {
        let Lumped {
            name,
            station,
            nodes,
            fixed,
            elements,
            mass_node,
            rayleigh,
            contact_nodes,
        } = self;
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
        let kt = bar_spring_triplets(name, &elements, &nodes, &node_dofs)?;
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
        if total_mass == 0.0 && rayleigh != [0.0; 2] {
            return Err(ModelError::Inconsistent {
                what,
                message: MASSLESS_DAMPING.into(),
            });
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
            k: Arc::new(k),
            m: Arc::new(m),
            c: Arc::new(c),
            targets,
            elements: Arc::new(elements),
            clearance: f64::NAN,
            angle_deg: None,
            is_ring: false,
            mesh: None,
            dashpot: Default::default(),
            reduced: None,
            wear: None,
        };
        if ndof > 0 {
            Cholesky::new(&model.k).map_err(|e| ModelError::Factorisation {
                what: format!("stator `{name}` stiffness"),
                hint: "the stator has a free rigid-body or mechanism mode, fix more DOFs".into(),
                source: e,
            })?;
        }
        Ok(model)
    }
}

/// Stiffness triplets of bars (E A / L along the bar) and grounded springs (k along their
/// direction) over the free DOFs `node_dofs`.
fn bar_spring_triplets(
    name: &str,
    elements: &[StatorElement],
    nodes: &[V2],
    node_dofs: &[[Option<usize>; 2]],
) -> Result<Vec<(usize, usize, f64)>, ModelError> {
    let mut kt: Vec<(usize, usize, f64)> = Vec::new();
    for el in elements {
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
                return Err(ModelError::Inconsistent {
                    what: format!("stator `{name}`"),
                    message: "continuum cells and frames are assembled with their mesh \
                              (model::stator::mesh), not as lumped bars and springs"
                        .into(),
                })
            }
        }
    }
    Ok(kt)
}
