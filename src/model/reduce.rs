//! Modal reduction of an FE rotor that keeps the contact exact (`[run.reduction]`,
//! docs/IMPLICIT.md §7).
//!
//! The basis spans the lowest undamped modes Φ_L of `K φ = ω² M φ` at the case's speed (no
//! gyroscopics, M-orthonormal) with ω < ω_cut, and one static column `K⁻¹ e_d` per *interface*
//! DOF d: every station's `u_x`, `u_y` (and θ_z when the rotor has it), the unbalances' DOFs,
//! the observed node's and the initial state's node. In that span the basis is written so that
//! the interface DOFs are coordinates themselves:
//!
//! ```text
//! T = [N  Φ̃],   N = K⁻¹ E_B (E_Bᵀ K⁻¹ E_B)⁻¹,   Φ̃ = Φ_L − N (E_Bᵀ Φ_L)   (then M-orthonormalised),
//! ```
//!
//! so `E_Bᵀ T = [I 0]`: `q = [u_B; η]`, u_B the interface displacements in metres (radians
//! for θ_z), η the amplitudes of the internal modes Φ̃ (each scaled to a largest lateral
//! translation of 1, so η is in metres). Loads on interface DOFs enter the reduced equations
//! unchanged (`Tᵀ e_d = e_{q(d)}`), and the loop reads and loads the stations as before.
//!
//! **Exact contact flexibility.** The columns of `K⁻¹ E_B` lie in the span, so the reduced
//! static solution under any interface load `E_B f` is the full one (Ritz on the energy: the
//! exact minimiser lies in the subspace): `E_Bᵀ T K_r⁻¹ Tᵀ E_B = E_Bᵀ K⁻¹ E_B`, the contact
//! stiffness and the local deformation under the rub are the full model's.
//!
//! **Exact frequencies below the cut-off.** The modes Φ_L lie in the span, and its part
//! M-orthogonal to them is K-orthogonal to them too (`Φ_Lᵀ K v = Λ Φ_Lᵀ M v = 0`), so the
//! Rayleigh–Ritz problem `(K_r, M_r)` has Φ_L's frequencies as its lowest ones and the others
//! above ω_(L+1) ≥ ω_cut (Ritz values bound from above): the explicit stability limit is set by
//! the reduced model's highest Ritz frequency, not by the shaft's top modes.
//!
//! `M_r = Tᵀ M T`, `K_r = Tᵀ K T`, `C_r = Tᵀ (C + Ω G + C_modal) T` dense (r × r); the full
//! displacement is `u = T q` ([`ReducedRotor::expand`]).

use super::fe_rotor::{dense, undamped_modes};
use super::rotor::{Gyroscopic, RotatingLoad, RotorBody};
use super::Case;
use crate::error::ModelError;
use crate::linalg::Csc;
use crate::resolve::ReductionInput;
use nalgebra::DMatrix;

/// An FE rotor in its reduced basis, as the time loop integrates it.
#[derive(Debug, Clone)]
pub struct ReducedRotor {
    /// The reduced body in `q = [u_B; η]`: dense `M_r`, `C_r` (damping, Ω G and modal damping
    /// at the case's speed), `K_r`; `node_dofs` of an interface node are its q indices, of any
    /// other node `[usize::MAX; 2]` (the loop never reads them); no tilt or axial DOFs; the
    /// unbalances on their q indices; the [`crate::model::rotor::Gyroscopic`] terms of a
    /// varying speed projected on the basis (`Tᵀ G T`, `Tᵀ K_st T`).
    pub body: RotorBody,
    /// T (n × r): `u = T q`.
    pub basis: DMatrix<f64>,
    /// ω_cut (rad/s).
    pub cutoff: f64,
    /// Internal modes kept (undamped modes below ω_cut).
    pub modes: usize,
    /// The full model's DOFs of the static columns, in q order (`q[j]` is DOF `statics[j]`).
    pub statics: Vec<usize>,
    /// Undamped natural frequencies of the reduced model (rad/s), ascending.
    pub frequencies: Vec<f64>,
    /// Undamped natural frequencies of the full model at the same speed (rad/s), ascending.
    pub full_frequencies: Vec<f64>,
    /// Largest `|ω_r,i − ω_i| / ω_i` over the full model's modes below ω_cut (0 when none).
    pub frequency_error: f64,
}

/// The internal shapes of the reduction basis from the first `keep` undamped modes `phi`:
/// each made zero at the `interface` DOFs (less the static columns `nmat` times its interface
/// values), then M-orthonormalised against the ones before (modified Gram–Schmidt, mass
/// matrix `m`); a shape the static columns already span is dropped.
fn internal_shapes(
    phi: &DMatrix<f64>,
    keep: usize,
    interface: &[usize],
    nmat: &DMatrix<f64>,
    m: &DMatrix<f64>,
) -> Vec<nalgebra::DVector<f64>> {
    let nb = interface.len();
    let mut internal: Vec<nalgebra::DVector<f64>> = Vec::with_capacity(keep);
    for i in 0..keep {
        let p = phi.column(i);
        let pb = DMatrix::from_fn(nb, 1, |r, _| p[interface[r]]);
        let mut v = p.into_owned() - (nmat * pb).column(0);
        let norm0 = (v.transpose() * m * &v)[(0, 0)].sqrt();
        for w in &internal {
            let c = (w.transpose() * m * &v)[(0, 0)];
            v -= w * c;
        }
        let norm = (v.transpose() * m * &v)[(0, 0)].sqrt();
        if norm > 1e-8 * norm0 && norm > 0.0 {
            internal.push(v / norm);
        }
    }
    internal
}

/// The reduced rotor's body: the reduced matrices `m`, `c`, `k` in `q` (interface DOFs
/// first, in `interface` order, then the modal coordinates) and each node's, station's and
/// unbalance's DOFs mapped to `q` (`usize::MAX` where a lateral pair is not at the
/// interface); no tilt or axial terms, the gyroscopic ones set by the caller.
fn reduced_body(full: &RotorBody, interface: &[usize], m: Csc, c: Csc, k: Csc) -> RotorBody {
    let q_of = |d: usize| interface.iter().position(|x| *x == d);
    RotorBody {
        ndof: m.nrows(),
        m,
        c,
        c_low: None,
        k,
        node_dofs: (full.node_dofs.iter())
            .map(|d| match (q_of(d[0]), q_of(d[1])) {
                (Some(x), Some(y)) => [x, y],
                _ => [usize::MAX; 2],
            })
            .collect(),
        node_tilt: vec![None; full.node_dofs.len()],
        node_axial: vec![None; full.node_dofs.len()],
        node_torsion: (full.node_torsion.iter())
            .map(|d| d.and_then(q_of))
            .collect(),
        node_z: full.node_z.clone(),
        unbalance: (full.unbalance.iter())
            .map(|u| {
                let mut v = *u;
                v.dofs = u.dofs.map(|d| q_of(d).unwrap_or(usize::MAX));
                v
            })
            .collect(),
        rotating: Vec::new(),
        gyro: None,
    }
}

impl ReducedRotor {
    /// Reduces `full` with static columns at `interface` (full DOF indices; sorted, unique)
    /// and the undamped modes below `cutoff` (rad/s).
    ///
    /// # Errors
    /// [`ModelError::Singular`] when K is not positive definite (free axial or torsional
    /// DOFs: no static column exists) or M is not, or when the basis is degenerate.
    pub fn new(full: &RotorBody, interface: &[usize], cutoff: f64) -> Result<Self, ModelError> {
        let n = full.ndof;
        let singular = |detail: &str| ModelError::Singular {
            what: "rotor (`run.reduction`)".into(),
            detail: detail.into(),
        };
        let m = dense(&full.m);
        let k = dense(&full.k);
        let kch = k.clone().cholesky().ok_or_else(|| {
            singular("its stiffness matrix is not positive definite (free axial or torsional DOFs?): a reduced rotor needs the static columns K⁻¹ e_d")
        })?;
        let nb = interface.len();
        // N = K⁻¹ E_B (E_Bᵀ K⁻¹ E_B)⁻¹: unit displacement at one interface DOF, the others
        // held at zero, the rest of the rotor in static equilibrium.
        let mut e = DMatrix::zeros(n, nb);
        for (j, &d) in interface.iter().enumerate() {
            e[(d, j)] = 1.0;
        }
        let kinv_e = kch.solve(&e);
        let fbb = DMatrix::from_fn(nb, nb, |i, j| kinv_e[(interface[i], j)]);
        let fbb_inv = fbb
            .cholesky()
            .ok_or_else(|| singular("the interface flexibility is not positive definite"))?
            .inverse();
        let nmat = &kinv_e * fbb_inv;
        let (lam, phi) = undamped_modes(&full.m, &full.k)?;
        let full_frequencies: Vec<f64> = lam.iter().map(|l| l.max(0.0).sqrt()).collect();
        let keep = full_frequencies.iter().filter(|w| **w < cutoff).count();
        // Internal shapes: zero at the interface, then M-orthonormalised (modified
        // Gram–Schmidt); a shape the static columns already span is dropped.
        let translation: Vec<usize> = full.node_dofs.iter().flatten().copied().collect();
        let internal = internal_shapes(&phi, keep, interface, &nmat, &m);
        let modes = internal.len();
        let r = nb + modes;
        let mut t = DMatrix::zeros(n, r);
        t.columns_mut(0, nb).copy_from(&nmat);
        for (j, v) in internal.iter().enumerate() {
            // η in metres: the shape's largest lateral translation is 1.
            let s = translation.iter().map(|&d| v[d].abs()).fold(0.0, f64::max);
            let s = if s > 0.0 { s } else { v.amax() };
            t.column_mut(nb + j).copy_from(&(v / s));
        }
        let tt = t.transpose();
        let sym = |a: DMatrix<f64>| (&a + a.transpose()) * 0.5;
        let mr = sym(&tt * &m * &t);
        let kr = sym(&tt * &k * &t);
        let mut cr = &tt * dense(&full.c) * &t;
        if let Some(lr) = &full.c_low {
            let u = DMatrix::from_column_slice(lr.n, lr.rank(), &lr.u);
            let tu = &tt * u;
            let d = DMatrix::from_diagonal(&nalgebra::DVector::from_column_slice(&lr.d));
            cr += &tu * d * tu.transpose();
        }
        let csc = |a: &DMatrix<f64>| Csc::dense(r, r, |i, j| a[(i, j)]);
        let mut body = reduced_body(full, interface, csc(&mr), csc(&cr), csc(&kr));
        // A varying speed's terms in the basis: `G_r = Tᵀ G T`, `K_st,r = Tᵀ K_st T` (the basis
        // is the undamped, non-spinning one: it does not depend on Ω).
        body.gyro = full.gyro.as_ref().map(|g| Gyroscopic {
            g: csc(&(&tt * dense(&g.g) * &t)),
            k_st: csc(&(&tt * dense(&g.k_st) * &t)),
        });
        body.rotating = project_rotating(&t, &full.rotating);
        if body.unbalance.iter().any(|u| u.dofs.contains(&usize::MAX)) {
            return Err(singular("an unbalance DOF is not an interface DOF"));
        }
        let (lr, _) = undamped_modes(&body.m, &body.k)?;
        let frequencies: Vec<f64> = lr.iter().map(|l| l.max(0.0).sqrt()).collect();
        let frequency_error = (0..keep.min(frequencies.len()))
            .map(|i| (frequencies[i] - full_frequencies[i]).abs() / full_frequencies[i])
            .fold(0.0, f64::max);
        Ok(Self {
            body,
            basis: t,
            cutoff,
            modes,
            statics: interface.to_vec(),
            frequencies,
            full_frequencies,
            frequency_error,
        })
    }

    /// The full displacement `u = T q` (`q` of length r, `u` of length n). Allocation-free.
    pub fn expand(&self, q: &[f64], u: &mut [f64]) {
        u.fill(0.0);
        for (col, qj) in self.basis.column_iter().zip(q) {
            if *qj != 0.0 {
                for (ui, ti) in u.iter_mut().zip(col.iter()) {
                    *ui += ti * qj;
                }
            }
        }
    }

    /// The reduced static flexibility at the interface DOFs, `E_Bᵀ T K_r⁻¹ Tᵀ E_B` (m/N), in
    /// the order of [`ReducedRotor::statics`]; `None` when K_r cannot be factored.
    pub fn interface_flexibility(&self) -> Option<DMatrix<f64>> {
        let kr = dense(&self.body.k);
        let nb = self.statics.len();
        let inv = kr.cholesky()?.inverse();
        Some(inv.view((0, 0), (nb, nb)).into_owned())
    }

    /// Highest undamped frequency of the reduced model (rad/s).
    pub fn omega_max(&self) -> f64 {
        self.frequencies.last().copied().unwrap_or(0.0)
    }
}

/// Loads fixed in the rotor's frame on the full DOFs, in the basis `T`: `a_q = Tᵀ a` (the
/// virtual work `δuᵀ f = δqᵀ Tᵀ f` of `u = T q`), one [`RotatingLoad`] per reduced coordinate
/// that gets a nonzero amplitude.
fn project_rotating(t: &DMatrix<f64>, full: &[RotatingLoad]) -> Vec<RotatingLoad> {
    (0..t.ncols())
        .filter_map(|j| {
            let a = full.iter().fold([0.0; 2], |a, l| {
                let tj = t[(l.dof, j)];
                [a[0] + tj * l.amplitude[0], a[1] + tj * l.amplitude[1]]
            });
            (a != [0.0; 2]).then_some(RotatingLoad {
                dof: j,
                amplitude: a,
            })
        })
        .collect()
}

impl Case {
    /// Sets the loads fixed in the rotor's frame ([`RotatingLoad`], on the full rotor's DOFs)
    /// of the case's rotor and, when the case is reduced, of its reduced body (`Tᵀ a`).
    pub fn set_rotating(&mut self, loads: Vec<RotatingLoad>) {
        if let Some(r) = self.reduced.as_deref_mut() {
            r.body.rotating = project_rotating(&r.basis, &loads);
        }
        self.rotor.rotating = loads;
    }

    /// The rotor the time loop integrates: the reduced body when the case is reduced, else
    /// [`Case::rotor`].
    pub fn loop_rotor(&self) -> &RotorBody {
        self.reduced.as_deref().map_or(&self.rotor, |r| &r.body)
    }

    /// The contact frequency ω_c = max over stations of √((k_r + Σk_s)/m_r), at least ω_n
    /// (rad/s): the T_min of the paper's rule (the Jeffcott-equivalent system's).
    pub fn contact_frequency(&self) -> f64 {
        let mut k = vec![0.0; self.stations.len()];
        for s in &self.stators {
            let kb = s.contact_stiffness_bound();
            for st in s.stations() {
                if let Some(v) = k.get_mut(st) {
                    *v += kb;
                }
            }
        }
        k.iter()
            .map(|k| ((self.rotor_stiffness + k) / self.rotor_mass).sqrt())
            .fold(self.omega / self.speed_ratio, f64::max)
    }

    /// The rotor DOFs that get a static column: the stations' `u_x`, `u_y` (and θ_z), the
    /// unbalances' DOFs, the observed node's and the initial state's node (station 0's, node 0
    /// without stations); sorted, unique.
    pub fn interface_dofs(&self) -> Vec<usize> {
        let r = &self.rotor;
        let node0 = self.stations.first().map_or(0, |s| s.node);
        let nodes = (self.stations.iter().map(|s| s.node)).chain([self.observed_node, node0]);
        let mut d: Vec<usize> = nodes
            .clone()
            .flat_map(|n| r.node_dofs[n])
            .chain(self.stations.iter().filter_map(|s| r.node_torsion[s.node]))
            .chain(r.unbalance.iter().flat_map(|u| u.dofs))
            .collect();
        d.sort_unstable();
        d.dedup();
        d
    }

    /// Replaces the loop's rotor by its reduction with cut-off `cutoff` (rad/s): the stability
    /// data (`rotor_omega_max`, `station_inv_mass`) become the reduced model's.
    ///
    /// # Errors
    /// As [`ReducedRotor::new`].
    pub fn reduce(&mut self, cutoff: f64) -> Result<(), ModelError> {
        let red = ReducedRotor::new(&self.rotor, &self.interface_dofs(), cutoff)?;
        let minv = dense(&red.body.m)
            .try_inverse()
            .ok_or(ModelError::Singular {
                what: "reduced rotor mass matrix".into(),
                detail: "not invertible".into(),
            })?;
        for (s, v) in self.stations.iter().zip(self.station_inv_mass.iter_mut()) {
            *v = minv[(red.body.node_dofs[s.node][0], red.body.node_dofs[s.node][0])];
        }
        self.rotor_omega_max = red.omega_max();
        self.reduced = Some(Box::new(red));
        Ok(())
    }

    /// The case reduced as `spec` asks (unchanged for `None`): ω_cut = `spec.cutoff`, else
    /// `cutoff_factor × max(harmonics × ω, ω_c)`.
    pub(crate) fn reduced_by(self, spec: Option<&ReductionInput>) -> Result<Self, ModelError> {
        let top = self.omega;
        self.reduced_to(spec, top)
    }

    /// The case reduced as `spec` asks for speeds up to `top` (rad/s; a speed transient's
    /// highest): the default cut-off `cutoff_factor × max(harmonics × top, ω_c)`.
    ///
    /// # Errors
    /// As [`ReducedRotor::new`].
    pub fn reduced_to(
        mut self,
        spec: Option<&ReductionInput>,
        top: f64,
    ) -> Result<Self, ModelError> {
        if let Some(s) = spec {
            let cut = s.cutoff.unwrap_or_else(|| {
                s.cutoff_factor * (s.harmonics * top).max(self.contact_frequency())
            });
            if s.rotor {
                self.reduce(cut)?;
            }
            if s.stators {
                self.reduce_stators(cut)?;
            }
        }
        Ok(self)
    }

    /// Replaces every meshed stator with mass in the loop by its Craig–Bampton reduction with
    /// cut-off `cutoff` (rad/s, [`crate::model::stator::reduce::ReducedStator`]), shared by
    /// every case with the same cut-off.
    ///
    /// # Errors
    /// As [`crate::model::stator::reduce::ReducedStator::new`].
    pub fn reduce_stators(&mut self, cutoff: f64) -> Result<(), ModelError> {
        for s in &mut self.stators {
            if s.massless() {
                continue;
            }
            if let Some(md) = s.mesh.clone() {
                s.reduced = Some(md.reduction(s, cutoff)?);
            }
        }
        Ok(())
    }
}
