//! Craig–Bampton reduction of a meshed stator with mass that keeps the contact exact
//! (`[run.reduction] stators = true`, docs/IMPLICIT.md §7.2).
//!
//! The free DOFs split into the *boundary* B — every contact DOF of the stator (the DOFs of its
//! contact targets, [`StatorModel::contact_dofs`]) — and the interior I. The basis is
//!
//! ```text
//!        ⎡ I   0 ⎤   q = [u_B; η],   Ψ = −K_II⁻¹ K_IB   (constraint modes),
//!   T =  ⎣ Ψ   Φ ⎦                   K_II Φ = M_II Φ Ω²,  Φᵀ M_II Φ = I  (fixed-interface modes)
//! ```
//!
//! with Φ every fixed-interface mode whose frequency lies below the cut-off ω_cut (rad/s). The
//! boundary displacements are coordinates themselves (metres), η the modal amplitudes
//! (√kg·m, mass-normalised). `M_r = Tᵀ M T`, `C_r = Tᵀ C T`, `K_r = Tᵀ K T` (dense, r × r,
//! r = |B| + modes), `u = T q`.
//!
//! **Exact contact flexibility.** `K_r = diag(S, Ω²)` with `S = K_BB − K_BI K_II⁻¹ K_IB` the
//! Schur complement on B, and `S⁻¹ = (K⁻¹)_BB`: the reduced static response to any load on the
//! contact DOFs is the full one (the constraint modes are the exact static shapes).
//!
//! **Frequencies.** Rayleigh–Ritz in the span of T: every reduced frequency bounds the full
//! model's of the same rank from above; modes well below ω_cut are reproduced closely (the
//! error is measured, not bounded, in `tests/suite/reduction_stator.rs`).
//!
//! The fixed-interface eigenproblem of a large sparse stator is solved by shift-invert
//! subspace iteration on the sparse Cholesky factor of `K_II` (no dense eigenproblem of the
//! mesh's size); T is never stored whole: the interior of a frame is recovered by one solve,
//! `u_I = −K_II⁻¹ K_IB u_B + Φ η` ([`ReducedStator::expand`]).

use super::StatorModel;
use crate::error::ModelError;
use crate::linalg::{Cholesky, CholeskyScratch, Csc};
use nalgebra::DMatrix;

/// Most fixed-interface modes one reduced stator keeps (a higher cut-off is refused).
pub const MAX_STATOR_MODES: usize = 400;

/// Right-hand sides per block solve with the interior factor.
const BLOCK: usize = 32;

/// A meshed stator with mass in its Craig–Bampton basis, as the time loop integrates it.
#[derive(Debug)]
pub struct ReducedStator {
    /// Free DOFs of the full stator (n).
    pub ndof: usize,
    /// Boundary (contact) DOFs of the full model, ascending: `q[j]` is `u[boundary[j]]`.
    pub boundary: Vec<usize>,
    /// Interior DOFs of the full model, ascending.
    pub interior: Vec<usize>,
    /// Reduced mass `Tᵀ M T` (kg), dense r × r.
    pub m: Csc,
    /// Reduced damping `Tᵀ C T` (N·s/m), dense r × r.
    pub c: Csc,
    /// Reduced stiffness `Tᵀ K T` (N/m), dense r × r (block diagonal: Schur complement, Ω²).
    pub k: Csc,
    /// ω_cut (rad/s).
    pub cutoff: f64,
    /// Fixed-interface frequencies kept (rad/s), ascending.
    pub modes: Vec<f64>,
    /// Undamped frequencies of the reduced model (rad/s), ascending.
    pub frequencies: Vec<f64>,
    /// Φ, n_I × modes, column-major.
    phi: Vec<f64>,
    /// Sparse Cholesky factor of `K_II`.
    kii: Cholesky,
    /// `K_IB`, n_I × |B|.
    kib: Csc,
}

/// Buffers of [`ReducedStator::expand`] (allocated once, outside the loop).
#[derive(Debug)]
pub struct ExpandScratch {
    w: Vec<f64>,
    chol: CholeskyScratch,
}

/// Dense copy of a sparse matrix.
fn dense(a: &Csc) -> DMatrix<f64> {
    let mut d = DMatrix::zeros(a.nrows(), a.ncols());
    for (r, c, v) in a.triplets() {
        d[(r, c)] += v;
    }
    d
}

/// `(λ, Q)` of `K Q = M Q Λ`, λ ascending, `Qᵀ M Q = I`; `None` when M is not positive
/// definite.
pub(crate) fn generalized_eigen(
    k: &DMatrix<f64>,
    m: &DMatrix<f64>,
) -> Option<(Vec<f64>, DMatrix<f64>)> {
    let ms = (m + m.transpose()) * 0.5;
    let l = ms.cholesky()?.l();
    let linv = l.clone().try_inverse()?;
    let a = &linv * k * linv.transpose();
    let a = (&a + a.transpose()) * 0.5;
    let na = a.nrows();
    let eig = a.symmetric_eigen();
    let mut order: Vec<usize> = (0..eig.eigenvalues.len()).collect();
    order.sort_by(|x, y| eig.eigenvalues[*x].total_cmp(&eig.eigenvalues[*y]));
    let lam = order.iter().map(|i| eig.eigenvalues[*i]).collect();
    let v = DMatrix::from_fn(na, order.len(), |r, c| eig.eigenvectors[(r, order[c])]);
    Some((lam, linv.transpose() * v))
}

/// `y += A x` for each of the `k` columns of `x` (column-major, `A.ncols()` rows) into `y`
/// (`A.nrows()` rows).
fn mul_cols(a: &Csc, alpha: f64, x: &[f64], y: &mut [f64]) {
    let (nr, nc) = (a.nrows(), a.ncols());
    for (xc, yc) in x.chunks(nc).zip(y.chunks_mut(nr)) {
        a.mul_add(alpha, xc, yc);
    }
}

/// Blocks of a full matrix on the partition (B, I).
struct Parts {
    bb: Csc,
    bi: Csc,
    ib: Csc,
    ii: Csc,
}

fn split(a: &Csc, pos: &[(bool, usize)], nb: usize, ni: usize) -> Parts {
    let (mut bb, mut bi, mut ib, mut ii) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (r, c, v) in a.triplets() {
        let ((rb, ri), (cb, ci)) = (pos[r], pos[c]);
        match (rb, cb) {
            (true, true) => bb.push((ri, ci, v)),
            (true, false) => bi.push((ri, ci, v)),
            (false, true) => ib.push((ri, ci, v)),
            (false, false) => ii.push((ri, ci, v)),
        }
    }
    Parts {
        bb: Csc::from_triplets(nb, nb, &bb),
        bi: Csc::from_triplets(nb, ni, &bi),
        ib: Csc::from_triplets(ni, nb, &ib),
        ii: Csc::from_triplets(ni, ni, &ii),
    }
}

/// Deterministic start vectors in (−1, 1) (a linear congruential sequence).
fn start_vectors(n: usize, p: usize, seed: u64) -> Vec<f64> {
    let mut s = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (0..n * p)
        .map(|_| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        })
        .collect()
}

/// The fixed-interface modes below `cut` (rad/s): shift-invert subspace iteration
/// `Y = K_II⁻¹ M_II X`, Rayleigh–Ritz on span Y, until the Ritz values up to the first one
/// above the cut-off change by less than 1e-10 relative; the subspace grows while every Ritz
/// value lies below the cut-off. Returns `(ω, Φ)` (Φ column-major, `Φᵀ M Φ = I`).
fn fixed_interface_modes(
    kii: &Cholesky,
    mii: &Csc,
    cut: f64,
    what: &str,
) -> Result<(Vec<f64>, Vec<f64>), ModelError> {
    let n = mii.nrows();
    let cut2 = cut * cut;
    let mut p = 16.min(n);
    let mut x = start_vectors(n, p, 1);
    let fail = |detail: String| ModelError::Singular {
        what: what.into(),
        detail,
    };
    loop {
        let mut lam_old: Vec<f64> = vec![f64::INFINITY; p];
        let mut lam = Vec::new();
        let mut converged = false;
        for _ in 0..400 {
            // MX, then Y = K⁻¹ M X.
            let mut mx = vec![0.0; n * p];
            mul_cols(mii, 1.0, &x, &mut mx);
            let mut y = mx.clone();
            for blk in y.chunks_mut(n * BLOCK) {
                kii.solve_in_place(blk);
            }
            let ym = DMatrix::from_column_slice(n, p, &y);
            let mxm = DMatrix::from_column_slice(n, p, &mx);
            let mut my = vec![0.0; n * p];
            mul_cols(mii, 1.0, &y, &mut my);
            let mym = DMatrix::from_column_slice(n, p, &my);
            // K̂ = Yᵀ K Y = Yᵀ M X, M̂ = Yᵀ M Y.
            let kh = ym.transpose() * &mxm;
            let kh = (&kh + kh.transpose()) * 0.5;
            let mh = ym.transpose() * &mym;
            let (l, q) = generalized_eigen(&kh, &mh)
                .ok_or_else(|| fail("the subspace iteration lost rank".into()))?;
            let xn = ym * q;
            x.copy_from_slice(xn.as_slice());
            lam = l;
            let below = lam.iter().filter(|l| **l < cut2).count();
            // Ritz values only fall: when the modes below the cut-off (and a guard of a
            // quarter of the subspace, whose last vectors converge slowly) do not fit, grow.
            if p < n && below + 1 + p / 4 > p {
                break;
            }
            let check = (below + 1).min(p);
            converged = (0..check).all(|i| {
                (lam[i] - lam_old[i]).abs() <= 1e-10 * lam[i].abs().max(f64::MIN_POSITIVE)
            });
            lam_old.clone_from(&lam);
            if converged {
                break;
            }
        }
        let below = lam.iter().filter(|l| **l < cut2).count();
        let fits = p == n || below + 1 + p / 4 <= p;
        if fits && !converged {
            return Err(fail(format!(
                "the fixed-interface modes did not converge in 400 iterations with {p} vectors"
            )));
        }
        if fits && below > MAX_STATOR_MODES {
            return Err(ModelError::Inconsistent {
                what: what.into(),
                message: format!(
                    "{below} fixed-interface modes lie below the cut-off {cut:.4e} rad/s, more than {MAX_STATOR_MODES}: lower `run.reduction.cutoff` (or `cutoff_factor`), or leave the stator unreduced"
                ),
            });
        }
        if fits {
            let phi = x[..n * below].to_vec();
            return Ok((
                lam[..below].iter().map(|l| l.max(0.0).sqrt()).collect(),
                phi,
            ));
        }
        if below >= MAX_STATOR_MODES {
            return Err(ModelError::Inconsistent {
                what: what.into(),
                message: format!(
                    "more than {MAX_STATOR_MODES} fixed-interface modes lie below the cut-off {cut:.4e} rad/s: lower `run.reduction.cutoff` (or `cutoff_factor`), or leave the stator unreduced"
                ),
            });
        }
        // The modes below the cut-off fill the subspace: grow it.
        let q = (2 * p + 8).max(2 * below + 8).min(n);
        x.extend(start_vectors(n, q - p, p as u64 + 7));
        p = q;
    }
}

/// Each DOF of a stator of `n` DOFs as (boundary?, its index among the boundary or the
/// interior DOFs), and the interior DOFs in order: the contact DOFs `boundary` are kept.
fn partition(n: usize, boundary: &[usize]) -> (Vec<(bool, usize)>, Vec<usize>) {
    let mut pos = vec![(false, 0); n];
    let mut interior = Vec::with_capacity(n - boundary.len());
    for (j, &d) in boundary.iter().enumerate() {
        pos[d] = (true, j);
    }
    for (d, p) in pos.iter_mut().enumerate() {
        if !p.0 {
            *p = (false, interior.len());
            interior.push(d);
        }
    }
    (pos, interior)
}

/// What the reduced matrices are assembled from: the stiffness, mass and damping split into
/// boundary (B) and interior (I) blocks, the factor of `K_II`, whether there is damping, the
/// numbers of boundary and interior DOFs.
struct Blocks<'a> {
    kp: &'a Parts,
    mp: &'a Parts,
    cp: &'a Parts,
    kii: &'a Cholesky,
    damped: bool,
    nb: usize,
    ni: usize,
}

impl Blocks<'_> {
    /// The boundary blocks of the reduced `mr`, `kr`, `cr` (the static constraint modes Ψ).
    fn boundary(&self, mr: &mut DMatrix<f64>, kr: &mut DMatrix<f64>, cr: &mut DMatrix<f64>) {
        let (kp, mp, cp, kii) = (self.kp, self.mp, self.cp, self.kii);
        let (damped, nb, ni) = (self.damped, self.nb, self.ni);
        // Boundary blocks, BLOCK constraint modes at a time:
        //   A_r,BB = A_BB + A_BI Ψ + Ψᵀ A_IB + Ψᵀ A_II Ψ, with Ψᵀ v = −K_IBᵀ K_II⁻¹ v;
        //   K_r,BB = K_BB + K_BI Ψ (the Schur complement: the other two terms cancel).
        let mut p_m = DMatrix::<f64>::zeros(nb, nb); // M_BI Ψ
        let mut p_c = DMatrix::<f64>::zeros(nb, nb); // C_BI Ψ
        let kbi = &kp.bi;
        for j0 in (0..nb).step_by(BLOCK) {
            let b = BLOCK.min(nb - j0);
            let mut psi = vec![0.0; ni * b];
            for (jj, col) in psi.chunks_mut(ni.max(1)).enumerate().take(b) {
                let mut e = vec![0.0; nb];
                e[j0 + jj] = 1.0;
                kp.ib.mul_add(-1.0, &e, col);
            }
            if ni > 0 {
                kii.solve_in_place(&mut psi);
            }
            for jj in 0..b {
                let j = j0 + jj;
                let col = &psi[jj * ni..(jj + 1) * ni];
                let mut t = vec![0.0; nb];
                kbi.mul_add(1.0, col, &mut t);
                for i in 0..nb {
                    kr[(i, j)] = kp.bb.get(i, j) + t[i];
                }
                let mut t = vec![0.0; nb];
                mp.bi.mul_add(1.0, col, &mut t);
                p_m.column_mut(j).copy_from_slice(&t);
                if damped {
                    let mut t = vec![0.0; nb];
                    cp.bi.mul_add(1.0, col, &mut t);
                    p_c.column_mut(j).copy_from_slice(&t);
                }
            }
            // Ψᵀ A_II Ψ_blk = −K_BI K_II⁻¹ (A_II Ψ_blk).
            let parts: Vec<(&Parts, &mut DMatrix<f64>)> = if damped {
                vec![(mp, &mut *mr), (cp, &mut *cr)]
            } else {
                vec![(mp, &mut *mr)]
            };
            for (ap, out) in parts {
                let mut w = vec![0.0; ni * b];
                mul_cols(&ap.ii, 1.0, &psi, &mut w);
                if ni > 0 {
                    kii.solve_in_place(&mut w);
                }
                for jj in 0..b {
                    let j = j0 + jj;
                    let mut t = vec![0.0; nb];
                    kbi.mul_add(-1.0, &w[jj * ni..(jj + 1) * ni], &mut t);
                    for i in 0..nb {
                        out[(i, j)] += ap.bb.get(i, j) + t[i];
                    }
                }
            }
        }
        mr.view_mut((0, 0), (nb, nb))
            .zip_apply(&(&p_m + p_m.transpose()), |a, b| *a += b);
        if damped {
            cr.view_mut((0, 0), (nb, nb))
                .zip_apply(&(&p_c + p_c.transpose()), |a, b| *a += b);
        }
    }

    // Modal blocks: A_r,Bη = A_BI Φ − K_BI K_II⁻¹ (A_II Φ) (zero for K), A_r,ηη = Φᵀ A_II Φ.
    /// The fixed-interface modes `phi` (column-major, interior DOFs × modes) fill the modal
    /// blocks of the reduced `mr`, `kr`, `cr`.
    fn modal(
        &self,
        phi: &[f64],
        mr: &mut DMatrix<f64>,
        kr: &mut DMatrix<f64>,
        cr: &mut DMatrix<f64>,
    ) {
        let (kp, mp, cp, kii) = (self.kp, self.mp, self.cp, self.kii);
        let (damped, nb, ni) = (self.damped, self.nb, self.ni);
        let nm = phi.len() / ni;
        let kbi = &kp.bi;
        let phim = DMatrix::from_column_slice(ni, nm, phi);
        let fill = |ap: &Parts, out: &mut DMatrix<f64>| {
            let mut w = vec![0.0; ni * nm];
            mul_cols(&ap.ii, 1.0, phi, &mut w);
            let aphi = DMatrix::from_column_slice(ni, nm, &w);
            let ee = phim.transpose() * &aphi;
            for blk in w.chunks_mut(ni * BLOCK) {
                kii.solve_in_place(blk);
            }
            for j in 0..nm {
                let mut t = vec![0.0; nb];
                ap.bi.mul_add(1.0, &phi[j * ni..(j + 1) * ni], &mut t);
                kbi.mul_add(-1.0, &w[j * ni..(j + 1) * ni], &mut t);
                for i in 0..nb {
                    out[(i, nb + j)] = t[i];
                    out[(nb + j, i)] = t[i];
                }
                for i in 0..nm {
                    out[(nb + i, nb + j)] = ee[(i, j)];
                }
            }
        };
        fill(mp, mr);
        if damped {
            fill(cp, cr);
        }
        // K_r,ηη = Φᵀ K_II Φ as computed (Ω² only to the iteration's tolerance on the
        // vectors); K_r,Bη = 0 exactly for any Φ (K_BI Φ − K_BI K_II⁻¹ K_II Φ).
        let mut w = vec![0.0; ni * nm];
        mul_cols(&kp.ii, 1.0, phi, &mut w);
        let kphi = DMatrix::from_column_slice(ni, nm, &w);
        let ee = phim.transpose() * kphi;
        kr.view_mut((nb, nb), (nm, nm)).copy_from(&ee);
    }
}

impl ReducedStator {
    /// Reduces the stator `s` (with mass) on its contact DOFs with the fixed-interface modes
    /// below `cutoff` (rad/s).
    ///
    /// # Errors
    /// [`ModelError::Singular`] when `K_II` is not positive definite, the stator has no
    /// contact DOF or the reduced mass is singular; [`ModelError::Inconsistent`] when more than
    /// [`MAX_STATOR_MODES`] modes lie below the cut-off.
    pub fn new(s: &StatorModel, cutoff: f64) -> Result<Self, ModelError> {
        let what = format!("stator `{}` (`run.reduction.stators`)", s.name);
        let singular = |detail: String| ModelError::Singular {
            what: what.clone(),
            detail,
        };
        let n = s.ndof;
        let boundary = s.contact_dofs();
        if boundary.is_empty() {
            return Err(singular("it has no contact DOF to keep".into()));
        }
        let (pos, interior) = partition(n, &boundary);
        let (nb, ni) = (boundary.len(), interior.len());
        let kp = split(&s.k, &pos, nb, ni);
        let mp = split(&s.m, &pos, nb, ni);
        let cp = split(&s.c, &pos, nb, ni);
        let damped = s.c.values().iter().any(|v| *v != 0.0);
        let kii = Cholesky::new(&kp.ii).map_err(|e| {
            singular(format!(
                "its stiffness with the contact DOFs held is not positive definite ({e})"
            ))
        })?;
        let (modes, phi) = if ni == 0 {
            (Vec::new(), Vec::new())
        } else {
            fixed_interface_modes(&kii, &mp.ii, cutoff, &what)?
        };
        let nm = modes.len();
        let r = nb + nm;
        let mut mr = DMatrix::<f64>::zeros(r, r);
        let mut kr = DMatrix::<f64>::zeros(r, r);
        let mut cr = DMatrix::<f64>::zeros(r, r);
        let blocks = Blocks {
            kp: &kp,
            mp: &mp,
            cp: &cp,
            kii: &kii,
            damped,
            nb,
            ni,
        };
        blocks.boundary(&mut mr, &mut kr, &mut cr);
        if nm > 0 {
            blocks.modal(&phi, &mut mr, &mut kr, &mut cr);
        }
        let sym = |a: DMatrix<f64>| (&a + a.transpose()) * 0.5;
        let (mr, kr, cr) = (sym(mr), sym(kr), sym(cr));
        let (lam, _) = generalized_eigen(&kr, &mr)
            .ok_or_else(|| singular("its reduced mass matrix is not positive definite".into()))?;
        let csc = |a: &DMatrix<f64>| Csc::dense(r, r, |i, j| a[(i, j)]);
        Ok(Self {
            ndof: n,
            boundary,
            interior,
            m: csc(&mr),
            c: if damped { csc(&cr) } else { Csc::zeros(r, r) },
            k: csc(&kr),
            cutoff,
            modes,
            frequencies: lam.iter().map(|l| l.max(0.0).sqrt()).collect(),
            phi,
            kii,
            kib: kp.ib,
        })
    }

    /// Reduced DOFs r = |B| + modes.
    pub fn rdof(&self) -> usize {
        self.boundary.len() + self.modes.len()
    }

    /// Highest undamped frequency of the reduced model (rad/s): its explicit stability limit
    /// is 2/ω_max.
    pub fn omega_max(&self) -> f64 {
        self.frequencies.last().copied().unwrap_or(0.0)
    }

    /// The reduced static flexibility on the boundary, `K_r,BB⁻¹` (m/N), in the order of
    /// [`ReducedStator::boundary`]; `None` when it cannot be factored.
    pub fn boundary_flexibility(&self) -> Option<DMatrix<f64>> {
        let nb = self.boundary.len();
        let k = dense(&self.k);
        Some(k.view((0, 0), (nb, nb)).into_owned().cholesky()?.inverse())
    }

    /// Buffers for [`ReducedStator::expand`].
    pub fn expand_scratch(&self) -> ExpandScratch {
        ExpandScratch {
            w: vec![0.0; self.interior.len()],
            chol: self.kii.solve_scratch(1),
        }
    }

    /// The full displacement `u = T q` (length n): `u_B = q_B`,
    /// `u_I = −K_II⁻¹ K_IB u_B + Φ η` — one solve with the interior factor. Allocation-free.
    pub fn expand(&self, q: &[f64], u: &mut [f64], scratch: &mut ExpandScratch) {
        let nb = self.boundary.len();
        let ni = self.interior.len();
        for (j, &d) in self.boundary.iter().enumerate() {
            u[d] = q[j];
        }
        if ni == 0 {
            return;
        }
        let w = &mut scratch.w;
        w.fill(0.0);
        self.kib.mul_add(-1.0, &q[..nb], w);
        self.kii.solve_in_place_with(w, &mut scratch.chol);
        for (j, eta) in q[nb..].iter().enumerate() {
            if *eta != 0.0 {
                for (wi, p) in w.iter_mut().zip(&self.phi[j * ni..(j + 1) * ni]) {
                    *wi += p * eta;
                }
            }
        }
        for (i, &d) in self.interior.iter().enumerate() {
            u[d] = w[i];
        }
    }
}
