//! Finite-element rotor: Timoshenko shaft elements, rigid disks, point masses, bearings (to
//! ground or through a pedestal mass), unbalances, Rayleigh damping and gyroscopics.
//!
//! Global DOFs: node `i` owns `[u_x, u_y, θ_x, θ_y]` at `4i..4i+4` (see
//! [`crate::element::timoshenko`] for the signs); pedestal masses add `[u_x, u_y]` after the
//! shaft DOFs. These are the lateral DOFs `0..ndof_lateral`. Optional axial and torsional DOFs
//! follow them, so switching them on leaves the lateral numbering and matrices unchanged:
//! with `axial` node `i`'s `u_z` (m, along +z) is DOF `ndof_lateral + i`; with `torsion` its
//! `θ_z` (rad, counter-clockwise seen from +z, the sense of Ω) comes after the axial DOFs
//! ([`FeRotor::node_axial`], [`FeRotor::node_torsion`]). Node positions `z` (m) run along the
//! shaft from its left end.
//!
//! The equations are `M q̈ + (C + Ω G) q̇ + K q = f(t)`, `C = C_bearings + C_supports + C_R`. The
//! Rayleigh part `C_R` is what [`FeRotorData::rayleigh_on`] says: `α M + β K(Ω)` of the
//! assembly (disks, point masses, pedestals and bearings included; the default),
//! `Σ_e (α M_e + β K_e)` over the shaft elements alone (bending, and the axial and torsional
//! elements when those DOFs are on) — ROSS 2's convention, where α and β are shaft-element
//! data —, or `α (M_shaft + M_disks + M_point_masses) + β K_shaft` — ROSS 3's rotor-level
//! convention, the rotor's matrices without its bearings, pedestals and supports.
//! Axial and torsional DOFs are uncoupled from the lateral ones (linear theory: no entries
//! between them in M, K, G, bearings or supports). They may be free — no axial support (thrust
//! bearing, [`FeRotorData::axial_supports`]) or no torsional restraint (coupling or drive,
//! [`FeRotorData::torsional_supports`]) of positive stiffness, ROSS's `kzz = 0` — and then have
//! one rigid-body mode each, the uniform `u_z` or `θ_z` ([`FeRotor::free_axial`],
//! [`FeRotor::free_torsion`], [`FeRotor::rigid_body_modes`]): K is singular on them, so the
//! static and unbalance solves use the lateral block only (the loads are lateral), the modal
//! analysis reports them as rigid-body modes, and the time loop, which factors M̃ and never K,
//! carries them as they are (unloaded, they stay put). The lateral DOFs must be held: a rotor
//! without a bearing is refused.

mod triplets;

use crate::error::ModelError;
use crate::linalg::{Csc, LowRank};
use crate::model::rotor::{Gyroscopic, RotorBody, UnbalanceLoad};
pub use crate::resolve::rotor::{Bearing, Disk, FeRotorData, GroundSpring, ModalDamping};
use crate::scene::RayleighOn;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use triplets::Triplets;

/// The FE rotor model (speed independent parts assembled once).
#[derive(Debug, Clone)]
pub struct FeRotor {
    /// Node positions along the axis (m).
    pub z: Vec<f64>,
    /// The shaft elements in order: element `e` joins nodes `e` and `e + 1`.
    pub elements: Vec<crate::element::timoshenko::ShaftSection>,
    /// Outer diameter of the shaft at each node (m), for plots.
    pub node_diameter: Vec<f64>,
    /// Number of DOFs (shaft lateral + pedestals + axial + torsional).
    pub ndof: usize,
    /// Number of lateral DOFs (shaft bending + pedestals): DOFs `0..ndof_lateral`.
    pub ndof_lateral: usize,
    /// `u_z` DOF of each node (m, along +z); `None` without axial DOFs.
    pub node_axial: Vec<Option<usize>>,
    /// `θ_z` DOF of each node (rad, counter-clockwise seen from +z); `None` without torsion.
    pub node_torsion: Vec<Option<usize>>,
    /// Axial supports (thrust bearings) on `u_z`.
    pub axial_supports: Vec<GroundSpring>,
    /// Torsional restraints (couplings, drives) on `θ_z`.
    pub torsional_supports: Vec<GroundSpring>,
    /// The axial DOFs are on and no axial support has positive stiffness: a rigid-body mode.
    pub free_axial: bool,
    /// The torsional DOFs are on and no restraint has positive stiffness: a rigid-body mode.
    pub free_torsion: bool,
    /// Mass (shaft, disks, point masses, pedestals).
    pub m: Csc,
    /// Stiffness of the shaft alone (bearings and supports added per speed by [`FeRotor::k`]).
    pub k_shaft: Csc,
    /// Gyroscopic matrix per unit spin.
    pub g: Csc,
    /// Bearings.
    pub bearings: Vec<Bearing>,
    /// Rayleigh `[α, β]` (1/s, s).
    pub rayleigh: [f64; 2],
    /// What the Rayleigh damping acts on ([`FeRotorData::rayleigh_on`]).
    pub rayleigh_on: RayleighOn,
    /// The Rayleigh damping matrix when it is not that of the assembly
    /// ([`FeRotorData::rayleigh_on`]): `Σ_e (α M_e + β K_e)` over the shaft elements
    /// (`"shaft"`), or that plus `α` times the disks' and point masses' mass (`"rotor"`);
    /// `None`: `α M + β K(Ω)` of the assembly, refilled per speed.
    pub rayleigh_part: Option<Csc>,
    /// Modal damping (none when `None`).
    pub modal_damping: Option<ModalDamping>,
    /// Unbalances.
    pub unbalance: Vec<UnbalanceLoad>,
    /// Disks.
    pub disks: Vec<Disk>,
    /// Pedestal DOF base of each bearing that has one.
    pub pedestal_dofs: Vec<Option<usize>>,
    /// Total mass (kg) and total polar inertia about the axis (kg·m²), for checks.
    pub total_mass: f64,
    /// Total polar inertia (kg·m²).
    pub total_polar_inertia: f64,
    /// Patterns of K(Ω) and C(Ω), built once, refilled per speed.
    refill: Refill,
}

/// The speed-dependent matrices' patterns and where each contribution lands in them: K(Ω) =
/// K_shaft + K_b(Ω) and C(Ω) = C_b(Ω) + α M + β K(Ω) are refilled value by value (the sums
/// are those of the triplet assembly, bit for bit).
#[derive(Debug, Clone)]
struct Refill {
    /// Pattern of K(Ω) (values unused).
    k: Csc,
    /// Pattern of C(Ω) without gyroscopics (values unused).
    c: Csc,
    /// Slot in `k` of each stored entry of `k_shaft`.
    k_shaft_in_k: Vec<usize>,
    /// Slot in `k` of each stored entry of the bearing stiffness matrix.
    kb_in_k: Vec<usize>,
    /// Slot in `c` of each stored entry of M, of K(Ω) and of the bearing damping matrix.
    m_in_c: Vec<usize>,
    k_in_c: Vec<usize>,
    cb_in_c: Vec<usize>,
    /// Slot in `c` of each stored entry of the Rayleigh matrix `rayleigh_part` (empty without).
    rs_in_c: Vec<usize>,
}

impl Refill {
    fn new(m: &Csc, k_shaft: &Csc, kb: &Csc, cb: &Csc, rs: Option<&Csc>) -> Self {
        let n = m.nrows();
        let pat = |parts: &[&Csc]| {
            let t: Vec<(usize, usize, f64)> = parts
                .iter()
                .flat_map(|a| a.triplets().map(|(r, c, _)| (r, c, 0.0)))
                .collect();
            Csc::from_triplets(n, n, &t)
        };
        let slots = |a: &Csc, into: &Csc| -> Vec<usize> {
            a.triplets()
                .map(|(r, c, _)| into.slot(r, c).expect("pattern holds every part"))
                .collect()
        };
        let k = pat(&[k_shaft, kb]);
        let empty = Csc::zeros(n, n);
        let rs = rs.unwrap_or(&empty);
        let c = pat(&[m, &k, cb, rs]);
        Self {
            rs_in_c: slots(rs, &c),
            k_shaft_in_k: slots(k_shaft, &k),
            kb_in_k: slots(kb, &k),
            m_in_c: slots(m, &c),
            k_in_c: slots(&k, &c),
            cb_in_c: slots(cb, &c),
            k,
            c,
        }
    }
}

/// Mass-normalised undamped modes `(ω², Φ)` of `K φ = ω² M φ`, ascending (`Φᵀ M Φ = I`),
/// dense (by a Cholesky factor of M: every DOF needs mass or rotary inertia).
pub fn undamped_modes(m: &Csc, k: &Csc) -> Result<(Vec<f64>, DMatrix<f64>), ModelError> {
    let (a, linv) = symmetric_form(dense(m), dense(k))?;
    let na = a.nrows();
    let eig = a.symmetric_eigen();
    let mut order: Vec<usize> = (0..eig.eigenvalues.len()).collect();
    order.sort_by(|x, y| eig.eigenvalues[*x].total_cmp(&eig.eigenvalues[*y]));
    let lam: Vec<f64> = order.iter().map(|i| eig.eigenvalues[*i]).collect();
    let v = DMatrix::from_fn(na, order.len(), |r, c| eig.eigenvectors[(r, order[c])]);
    Ok((lam, linv.transpose() * v))
}

/// `(A, L⁻¹)` with `A = L⁻¹ K L⁻ᵀ` (symmetrised), `M = L Lᵀ`: the standard symmetric form of
/// `K φ = ω² M φ` (eigenvalues ω², eigenvectors ψ = Lᵀ φ).
fn symmetric_form(
    m: DMatrix<f64>,
    k: DMatrix<f64>,
) -> Result<(DMatrix<f64>, DMatrix<f64>), ModelError> {
    let l = m.cholesky().ok_or_else(|| ModelError::Singular {
        what: "rotor mass matrix".into(),
        detail: "not positive definite: every DOF needs mass or rotary inertia".into(),
    })?;
    let linv = l.l().try_inverse().ok_or_else(|| ModelError::Singular {
        what: "rotor mass matrix".into(),
        detail: "Cholesky factor not invertible".into(),
    })?;
    let a = &linv * k * linv.transpose();
    Ok(((&a + a.transpose()) * 0.5, linv))
}

impl FeRotor {
    /// Assembles the model. Errors name the offending item: a node that does not exist, a
    /// rotor without bearing, supports of DOFs that are off, negative or infinite support
    /// stiffness or negative damping. Axial or torsional DOFs without a support of positive
    /// stiffness are free ([`FeRotor::free_axial`], [`FeRotor::free_torsion`]).
    pub fn build(d: &FeRotorData) -> Result<Self, ModelError> {
        let (z, node_diameter) = check(d)?;
        let nn = z.len();
        let mut ndof = 4 * nn;
        let mut pedestal_dofs = Vec::new();
        for b in &d.bearings {
            if b.pedestal.is_some() {
                pedestal_dofs.push(Some(ndof));
                ndof += 2;
            } else {
                pedestal_dofs.push(None);
            }
        }
        let ndof_lateral = ndof;
        let mut scalar_dofs = |on: bool| -> Vec<Option<usize>> {
            let base = ndof;
            if on {
                ndof += nn;
            }
            (0..nn).map(|i| on.then_some(base + i)).collect()
        };
        let node_axial = scalar_dofs(d.axial);
        let node_torsion = scalar_dofs(d.torsion);
        // Before anything n × n is allocated (the scene's validation refuses it first, naming
        // the keys; this guards the library's callers).
        if let Some(why) = crate::scene::validate::dense_rotor_cost(ndof).excess() {
            return Err(ModelError::Inconsistent {
                what: "FE rotor".into(),
                message: format!("{why}: use fewer elements"),
            });
        }
        let t = Triplets::assemble(d, &pedestal_dofs, &node_axial, &node_torsion);
        let unbalance = d
            .unbalances
            .iter()
            .map(|(n, me, ph)| UnbalanceLoad {
                dofs: [4 * n, 4 * n + 1],
                me: *me,
                phase: *ph,
            })
            .collect();
        let mut rotor = FeRotor {
            z,
            elements: d.elements.clone(),
            node_diameter,
            ndof,
            ndof_lateral,
            node_axial,
            node_torsion,
            axial_supports: d.axial_supports.clone(),
            torsional_supports: d.torsional_supports.clone(),
            free_axial: d.axial && !d.axial_supports.iter().any(|s| s.stiffness > 0.0),
            free_torsion: d.torsion && !d.torsional_supports.iter().any(|s| s.stiffness > 0.0),
            m: Csc::from_triplets(ndof, ndof, &t.mt),
            k_shaft: Csc::from_triplets(ndof, ndof, &t.kt),
            g: Csc::from_triplets(ndof, ndof, &t.gt),
            bearings: d.bearings.clone(),
            rayleigh: d.rayleigh,
            rayleigh_on: d.rayleigh_on,
            rayleigh_part: (d.rayleigh_on != RayleighOn::Assembly)
                .then(|| Csc::from_triplets(ndof, ndof, &t.rt)),
            modal_damping: d.modal_damping,
            unbalance,
            disks: d.disks.clone(),
            pedestal_dofs,
            total_mass: t.total_mass,
            total_polar_inertia: t.total_ip,
            refill: Refill {
                k: Csc::zeros(0, 0),
                c: Csc::zeros(0, 0),
                k_shaft_in_k: Vec::new(),
                kb_in_k: Vec::new(),
                m_in_c: Vec::new(),
                k_in_c: Vec::new(),
                cb_in_c: Vec::new(),
                rs_in_c: Vec::new(),
            },
        };
        // Every bearing coefficient is stored even where it is zero at some speed (the
        // pattern of `bearing_matrices` does not depend on Ω).
        let (kb, cb) = rotor.bearing_matrices(0.0);
        rotor.refill = Refill::new(
            &rotor.m,
            &rotor.k_shaft,
            &kb,
            &cb,
            rotor.rayleigh_part.as_ref(),
        );
        Ok(rotor)
    }

    /// Number of shaft nodes.
    pub fn nodes(&self) -> usize {
        self.z.len()
    }

    /// The rigid-body modes of the free axial and torsional DOFs, `[axial, torsional]`: the
    /// uniform `u_z = 1` m (or `θ_z = 1` rad) on every node, zero elsewhere — `K r = 0` exactly
    /// (the bar and torsion elements' rows sum to zero and nothing ties the DOFs to ground).
    /// `None` where the DOFs are off or held.
    pub fn rigid_body_modes(&self) -> [Option<Vec<f64>>; 2] {
        let uniform = |free: bool, dofs: &[Option<usize>]| {
            free.then(|| {
                let mut r = vec![0.0; self.ndof];
                for d in dofs.iter().flatten() {
                    r[*d] = 1.0;
                }
                r
            })
        };
        [
            uniform(self.free_axial, &self.node_axial),
            uniform(self.free_torsion, &self.node_torsion),
        ]
    }

    /// Bearing stiffness and damping at speed ω, plus the axial and torsional supports (to
    /// ground, speed independent), as sparse matrices.
    pub fn bearing_matrices(&self, omega: f64) -> (Csc, Csc) {
        let (mut kt, mut ct) = (Vec::new(), Vec::new());
        for (b, pd) in self.bearings.iter().zip(&self.pedestal_dofs) {
            let (k, c) = b.coefficients(omega);
            let n = [4 * b.node, 4 * b.node + 1];
            // Between the journal and the pedestal (or ground).
            let add = |t: &mut Vec<(usize, usize, f64)>, v: [f64; 4]| {
                let vals = [[v[0], v[1]], [v[2], v[3]]];
                for i in 0..2 {
                    for j in 0..2 {
                        t.push((n[i], n[j], vals[i][j]));
                        if let Some(p) = pd {
                            t.push((p + i, p + j, vals[i][j]));
                            t.push((n[i], p + j, -vals[i][j]));
                            t.push((p + i, n[j], -vals[i][j]));
                        }
                    }
                }
            };
            add(&mut kt, k);
            add(&mut ct, c);
            if let (Some((_, ks, cs)), Some(p)) = (b.pedestal, pd) {
                for i in 0..2 {
                    kt.push((p + i, p + i, ks));
                    ct.push((p + i, p + i, cs));
                }
            }
        }
        for (supports, dofs) in [
            (&self.axial_supports, &self.node_axial),
            (&self.torsional_supports, &self.node_torsion),
        ] {
            for s in supports {
                if let Some(d) = dofs[s.node] {
                    kt.push((d, d, s.stiffness));
                    ct.push((d, d, s.damping));
                }
            }
        }
        (
            Csc::from_triplets(self.ndof, self.ndof, &kt),
            Csc::from_triplets(self.ndof, self.ndof, &ct),
        )
    }

    /// Stiffness at speed ω (shaft + bearings), refilled on the pattern built once.
    pub fn k(&self, omega: f64) -> Csc {
        let (kb, _) = self.bearing_matrices(omega);
        self.k_with(&kb)
    }

    fn k_with(&self, kb: &Csc) -> Csc {
        let r = &self.refill;
        let mut k = r.k.clone();
        let v = k.values_mut();
        v.fill(0.0);
        for (s, x) in r.k_shaft_in_k.iter().zip(self.k_shaft.values()) {
            v[*s] = *x;
        }
        for (s, x) in r.kb_in_k.iter().zip(kb.values()) {
            v[*s] += *x;
        }
        k
    }

    /// Sparse damping without gyroscopics at speed ω: bearings + the Rayleigh part (α M + β K
    /// of the assembly, of the shaft elements alone, or of the rotor without its bearings, see
    /// the module docs; no modal part),
    /// refilled on the pattern built once.
    pub fn c_sparse(&self, omega: f64) -> Csc {
        let (kb, cb) = self.bearing_matrices(omega);
        let k = self.k_with(&kb);
        let r = &self.refill;
        let [alpha, beta] = match self.rayleigh_part {
            Some(_) => [0.0; 2],
            None => self.rayleigh,
        };
        let mut c = r.c.clone();
        let v = c.values_mut();
        v.fill(0.0);
        for (s, x) in r.m_in_c.iter().zip(self.m.values()) {
            v[*s] = alpha * x;
        }
        for (s, x) in r.k_in_c.iter().zip(k.values()) {
            v[*s] += beta * x;
        }
        for (s, x) in r.cb_in_c.iter().zip(cb.values()) {
            v[*s] += *x;
        }
        if let Some(rs) = &self.rayleigh_part {
            for (s, x) in r.rs_in_c.iter().zip(rs.values()) {
                v[*s] += *x;
            }
        }
        c
    }

    /// Damping without gyroscopics at speed ω: [`FeRotor::c_sparse`] plus the modal damping
    /// [`FeRotor::modal_damping_term`] assembled densely (for the frequency-domain analyses;
    /// the time loop keeps the modal part factored).
    pub fn c(&self, omega: f64) -> Result<Csc, ModelError> {
        let c = self.c_sparse(omega);
        Ok(match self.modal_damping_term(omega)? {
            Some(lr) => {
                let mut t: Vec<(usize, usize, f64)> = c.triplets().collect();
                t.extend(lr.triplets(1.0));
                Csc::from_triplets(self.ndof, self.ndof, &t)
            }
            None => c,
        })
    }

    /// Modal damping at speed ω as the rank-m term `C_m = U diag(d) Uᵀ`, `U = M Φ`,
    /// `dᵢ = 2 ζ ωᵢ`, over the mass-normalised undamped modes φᵢ (`Φᵀ M Φ = I`) of
    /// `K(ω) φ = ω² M φ` (bearings at ω, no gyroscopics) that the [`ModalDamping`] selects;
    /// then `Φᵀ C_m Φ = diag(2ζωᵢ)` on them and zero on every other mode. `None` without
    /// modal damping or when no mode is selected.
    pub fn modal_damping_term(&self, omega: f64) -> Result<Option<LowRank>, ModelError> {
        let Some(md) = self.modal_damping else {
            return Ok(None);
        };
        if md.ratio == 0.0 {
            return Ok(None);
        }
        let (lam, phi) = undamped_modes(&self.m, &self.k(omega))?;
        let w: Vec<f64> = lam.iter().map(|l| l.max(0.0).sqrt()).collect();
        let mut m_sel = w
            .iter()
            .take_while(|wi| **wi <= md.max_frequency)
            .count()
            .min(md.modes);
        // Keep repeated frequencies (the x and y bending modes of an axisymmetric rotor)
        // together: a count that ends inside a pair takes the pair's other half too.
        while m_sel > 0 && m_sel < w.len() && (w[m_sel] - w[m_sel - 1]).abs() <= 1e-6 * w[m_sel] {
            m_sel += 1;
        }
        let sel: Vec<usize> = (0..m_sel).filter(|&i| w[i] > 0.0).collect();
        if sel.is_empty() {
            return Ok(None);
        }
        let n = self.ndof;
        let mut u = vec![0.0; n * sel.len()];
        let mut x = vec![0.0; n];
        for (j, &i) in sel.iter().enumerate() {
            for (r, xr) in x.iter_mut().enumerate() {
                *xr = phi[(r, i)];
            }
            self.m.mul_add(1.0, &x, &mut u[j * n..(j + 1) * n]);
        }
        Ok(Some(LowRank {
            n,
            u,
            d: sel.iter().map(|&i| 2.0 * md.ratio * w[i]).collect(),
        }))
    }

    /// The integrator's body at speed ω: damping includes Ω G; modal damping is kept as the
    /// low-rank term [`RotorBody::c_low`].
    pub fn body(&self, omega: f64) -> Result<RotorBody, ModelError> {
        let c = Csc::lin_comb(1.0, &self.c_sparse(omega), omega, &self.g);
        Ok(RotorBody {
            c_low: self.modal_damping_term(omega)?,
            ndof: self.ndof,
            m: self.m.clone(),
            c,
            k: self.k(omega),
            node_dofs: (0..self.nodes()).map(|i| [4 * i, 4 * i + 1]).collect(),
            node_tilt: (0..self.nodes())
                .map(|i| Some([4 * i + 2, 4 * i + 3]))
                .collect(),
            node_axial: self.node_axial.clone(),
            node_torsion: self.node_torsion.clone(),
            node_z: self.z.clone(),
            unbalance: self.unbalance.clone(),
            rotating: Vec::new(),
            gyro: self.gyroscopic(),
        })
    }

    /// G and K_st of the rotor ([`crate::model::rotor::Gyroscopic`]); `None` without rotary
    /// inertia. The y–z plane's DOFs are each shaft node's `u_y` and `θ_x` (`4i + 1`, `4i + 2`).
    pub fn gyroscopic(&self) -> Option<Gyroscopic> {
        let shaft = 4 * self.nodes();
        Gyroscopic::new(&self.g, |d| d < shaft && matches!(d % 4, 1 | 2))
    }

    /// Undamped natural frequencies at rest without gyroscopics (rad/s), ascending, from the
    /// symmetric generalized problem K φ = ω² M φ (dense; M must be positive definite). All
    /// DOFs: with axial or torsional DOFs their modes are in the list (the explicit stability
    /// limit needs the highest of all).
    pub fn undamped_frequencies(&self, omega_for_bearings: f64) -> Result<Vec<f64>, ModelError> {
        self.block_frequencies(omega_for_bearings, self.ndof)
    }

    /// [`FeRotor::undamped_frequencies`] of the lateral DOFs alone (`0..ndof_lateral`): the
    /// bending modes, without the axial and torsional ones (uncoupled from them). Equal to
    /// `undamped_frequencies` when the rotor has neither.
    pub fn lateral_frequencies(&self, omega_for_bearings: f64) -> Result<Vec<f64>, ModelError> {
        self.block_frequencies(omega_for_bearings, self.ndof_lateral)
    }

    /// Frequencies of the leading `n × n` block of (K, M).
    fn block_frequencies(&self, omega_for_bearings: f64, n: usize) -> Result<Vec<f64>, ModelError> {
        let m = dense(&self.m).view((0, 0), (n, n)).into_owned();
        let k = dense(&self.k(omega_for_bearings))
            .view((0, 0), (n, n))
            .into_owned();
        let (a, _) = symmetric_form(m, k)?;
        let mut ev: Vec<f64> = a
            .symmetric_eigenvalues()
            .iter()
            .map(|v| v.max(0.0).sqrt())
            .collect();
        ev.sort_by(|a, b| a.total_cmp(b));
        Ok(ev)
    }

    /// Complex unbalance response `q` at speed ω: `(K − ω²M + iω(C + ωG)) q = F`, with
    /// `F_x = m_u e ω² e^{iφ}`, `F_y = −i m_u e ω² e^{iφ}` (forward rotating force).
    /// The load is lateral and the axial and torsional DOFs are uncoupled from the lateral
    /// ones, so only the lateral block is solved; the axial and torsional entries are zero.
    pub fn unbalance_response(&self, omega: f64) -> Result<Vec<Complex64>, ModelError> {
        let n = self.ndof_lateral;
        let k = dense(&self.k(omega));
        let c = dense(&Csc::lin_comb(1.0, &self.c(omega)?, omega, &self.g));
        let m = dense(&self.m);
        let a = DMatrix::<Complex64>::from_fn(n, n, |i, j| {
            Complex64::new(k[(i, j)] - omega * omega * m[(i, j)], omega * c[(i, j)])
        });
        let mut f = DVector::<Complex64>::zeros(n);
        for u in &self.unbalance {
            let e = Complex64::from_polar(u.me * omega * omega, u.phase);
            f[u.dofs[0]] += e;
            f[u.dofs[1]] += e * Complex64::new(0.0, -1.0);
        }
        let q = a.lu().solve(&f).ok_or_else(|| ModelError::Singular {
            what: format!("rotor dynamic stiffness at ω = {omega} rad/s"),
            detail: "singular (undamped resonance or unsupported rotor)".into(),
        })?;
        let mut q: Vec<Complex64> = q.iter().copied().collect();
        q.resize(self.ndof, Complex64::new(0.0, 0.0));
        Ok(q)
    }

    /// Static stiffness at a node in y (N/m): 1 / (K⁻¹)_yy — the `k_r` that ε refers to
    /// (from the lateral block of K, uncoupled from the axial and torsional DOFs).
    pub fn node_stiffness(&self, node: usize) -> Result<f64, ModelError> {
        let nl = self.ndof_lateral;
        let k = dense(&self.k(0.0)).view((0, 0), (nl, nl)).into_owned();
        let k_scale = k.diagonal().amax();
        let lu = k.lu();
        let mut e = DVector::zeros(nl);
        e[4 * node + 1] = 1.0;
        let singular = pivots;
        let x = lu.solve(&e).ok_or_else(singular)?;
        let kd = 1.0 / x[4 * node + 1];
        // A numerically singular K solves to a huge flexibility: the reference stiffness is then
        // round-off, not the rotor's (and ε k_r would make every ratio-given stator singular).
        if !(kd.is_finite() && kd > 1e-12 * k_scale) {
            return Err(singular());
        }
        Ok(kd)
    }
}

/// The error of a rotor its bearings do not hold laterally: its stiffness matrix is singular
/// (`model::blame` names the bearing key behind it).
pub(crate) fn pivots() -> ModelError {
    ModelError::Singular {
        what: "rotor stiffness".into(),
        detail: "singular: the bearings do not hold the rotor in every direction (`rotor.bearing` stiffnesses: a rotor on one bearing, or on a bearing of zero stiffness, pivots)".into(),
    }
}

/// Whether the bearings hold the rotor laterally: in x and in y, bearings with a non-zero
/// direct stiffness (`k_xx`, resp. `k_yy`, at some tabulated speed; a pedestal of non-zero
/// stiffness between bearing and ground) on at least two distinct nodes. The bearings are the
/// rotor's only lateral supports and the shaft is one connected beam, so this is exact: held
/// at one node, the rotor pivots about it. Decided on the data, not on K, whose factorisation
/// can miss the singularity by round-off (a pivoting rotor then had a first "frequency" of
/// 1.5e-4 rad/s and was refused only by the step budget).
pub(crate) fn held_laterally(bearings: &[Bearing]) -> bool {
    let holds = |b: &Bearing, d: usize| {
        b.k.iter().any(|k| k[d] != 0.0) && b.pedestal.is_none_or(|(_, ks, _)| ks != 0.0)
    };
    [0, 3].iter().all(|&d| {
        let mut nodes: Vec<usize> = bearings
            .iter()
            .filter(|b| holds(b, d))
            .map(|b| b.node)
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes.len() >= 2
    })
}

/// Checks what [`FeRotor::build`] needs of the data; returns the node positions z (m) and the
/// outer diameter at each node (m).
fn check(d: &FeRotorData) -> Result<(Vec<f64>, Vec<f64>), ModelError> {
    let err = |what: String, message: String| ModelError::Inconsistent { what, message };
    if d.elements.is_empty() {
        return Err(err("rotor".into(), "no shaft elements".into()));
    }
    let nn = d.elements.len() + 1;
    let mut z = vec![0.0; nn];
    let mut node_diameter = vec![0.0_f64; nn];
    for (i, e) in d.elements.iter().enumerate() {
        let bad_end = |o: f64, d: f64| o.is_nan() || o <= d || d.is_nan() || d < 0.0;
        if e.length.is_nan()
            || e.length <= 0.0
            || bad_end(e.outer_diameter, e.inner_diameter)
            || bad_end(e.outer_diameter_right, e.inner_diameter_right)
        {
            return Err(err(
                    format!("rotor shaft element {i}"),
                    format!(
                        "needs length > 0 and outer diameter > inner diameter ≥ 0 at both ends (L = {}, D = {} … {}, d = {} … {})",
                        e.length, e.outer_diameter, e.outer_diameter_right, e.inner_diameter, e.inner_diameter_right
                    ),
                ));
        }
        z[i + 1] = z[i] + e.length;
        node_diameter[i] = node_diameter[i].max(e.outer_diameter);
        node_diameter[i + 1] = e.outer_diameter_right;
    }
    let check_node = |what: String, n: usize| -> Result<(), ModelError> {
        if n >= nn {
            Err(err(
                what,
                format!(
                    "node {n} does not exist (the shaft has nodes 0..={})",
                    nn - 1
                ),
            ))
        } else {
            Ok(())
        }
    };
    for (i, dk) in d.disks.iter().enumerate() {
        check_node(format!("rotor disk {i}"), dk.node)?;
    }
    for (i, b) in d.bearings.iter().enumerate() {
        check_node(format!("rotor bearing {i}"), b.node)?;
    }
    for (i, (n, _)) in d.point_masses.iter().enumerate() {
        check_node(format!("rotor point mass {i}"), *n)?;
    }
    for (i, (n, _, _)) in d.unbalances.iter().enumerate() {
        check_node(format!("rotor unbalance {i}"), *n)?;
    }
    if d.bearings.is_empty() {
        return Err(err(
            "rotor".into(),
            "no bearing: a free rotor has rigid-body modes and no static equilibrium".into(),
        ));
    }
    for (kind, on, supports) in [
        ("axial", d.axial, &d.axial_supports),
        ("torsional", d.torsion, &d.torsional_supports),
    ] {
        for (i, s) in supports.iter().enumerate() {
            let what = format!("rotor {kind} support {i}");
            check_node(what.clone(), s.node)?;
            if !on {
                return Err(err(
                    what,
                    format!("the rotor has no {kind} DOFs: switch them on to use it"),
                ));
            }
            if !(s.stiffness.is_finite() && s.stiffness >= 0.0) {
                return Err(err(
                    what,
                    format!(
                        "stiffness must be zero or positive and finite, got {}",
                        s.stiffness
                    ),
                ));
            }
            if !(s.damping.is_finite() && s.damping >= 0.0) {
                return Err(err(
                    what,
                    format!("damping must be zero or positive, got {}", s.damping),
                ));
            }
        }
    }
    Ok((z, node_diameter))
}

/// Largest radius of the forced ellipse `x = Re(X e^{iωt}), y = Re(Y e^{iωt})`:
/// `r_max² = (|X|² + |Y|²)/2 + |X² + Y²|/2`.
pub fn ellipse_major(x: Complex64, y: Complex64) -> f64 {
    (0.5 * (x.norm_sqr() + y.norm_sqr()) + 0.5 * (x * x + y * y).norm()).sqrt()
}

/// Dense copy of a sparse matrix.
pub fn dense(a: &Csc) -> DMatrix<f64> {
    let mut d = DMatrix::zeros(a.nrows(), a.ncols());
    for (r, c, v) in a.triplets() {
        d[(r, c)] += v;
    }
    d
}
