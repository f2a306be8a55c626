//! A body with mass in the loop, integrated by central differences ([`DynBody`]); a stator's
//! state in the loop, which may be such a body, is [`super::stator::StatorDyn`].
//!
//! Central differences (Eqs. 35–36): `M̃ uⁿ⁺¹ = fⁿ + A uⁿ + B uⁿ⁻¹` with `M̃ = M/Δt² + C/(2Δt)`,
//! `A = 2M/Δt² − K`, `B = C/(2Δt) − M/Δt²`. M̃ is factored once per run. The implicit schemes
//! ([`super::newmark`]) put their step operator `S` in M̃'s place: the contact sees either
//! through the same flexibility and correction.

use super::newmark::{Alpha, Implicit};
use crate::linalg::{BlockTridiag, Csc, LinalgError, LowRank, PairCsr, StepLu, WoodburyLu};

/// M̃⁻¹ of a body with mass.
#[derive(Debug)]
pub(crate) enum MInv {
    /// Diagonal M̃ (Jeffcott rotor, lumped stators without stiffness-proportional damping).
    Diag(Vec<f64>),
    /// A factored M̃ with its columns at the contact DOFs.
    Lu {
        /// The factor.
        lu: Box<StepSolver>,
        /// Columns M̃⁻¹ e_d for contact DOFs, column-major n × ncd.
        cols: Vec<f64>,
        /// DOF → column index in `cols` (`usize::MAX` for other DOFs).
        col_of: Vec<usize>,
    },
}

impl MInv {
    /// Recomputes the columns `M̃⁻¹ e_d` at the contact DOFs from the factor (allocation free).
    pub(crate) fn fill_columns(&mut self) {
        if let MInv::Lu { lu, cols, col_of } = self {
            let n = col_of.len();
            for (d, &j) in col_of.iter().enumerate().filter(|(_, j)| **j != usize::MAX) {
                let c = &mut cols[j * n..(j + 1) * n];
                c.fill(0.0);
                c[d] = 1.0;
                lu.solve_in_place(c);
            }
        }
    }
}

/// The factored M̃: sparse LU, or sparse LU plus the Woodbury correction of a low-rank
/// damping term (modal damping).
#[derive(Debug)]
pub(crate) enum StepSolver {
    /// Block-tridiagonal LU in 4 × 4 node blocks (shaft models without pedestal, axial or
    /// torsional DOFs).
    Block(BlockTridiag),
    /// General sparse LU with pivoting (faer).
    Sparse(StepLu),
    /// Sparse LU plus the Woodbury correction of a low-rank damping term.
    LowRank(WoodburyLu),
}

impl StepSolver {
    /// Factors `mt`: with a low-rank damping term `low` (scaled by `low_factor`, 1/(2Δt) for
    /// central differences, γ/(βΔt) implicit) the Woodbury form; a shaft chain in node blocks
    /// the block Thomas solver; anything else (or a singular pivot block) the pivoting sparse
    /// LU.
    pub(crate) fn new(
        mt: &Csc,
        low: Option<&LowRank>,
        low_factor: f64,
    ) -> Result<Self, LinalgError> {
        Ok(match low {
            // M̃ = S + U diag(d/(2Δt)) Uᵀ (implicit: d γ/(βΔt)).
            Some(lr) => {
                let scaled = LowRank {
                    n: lr.n,
                    u: lr.u.clone(),
                    d: lr.d.iter().map(|d| d * low_factor).collect(),
                };
                StepSolver::LowRank(WoodburyLu::new(mt, scaled)?)
            }
            None => match BlockTridiag::new(mt) {
                Ok(Some(b)) => StepSolver::Block(b),
                _ => StepSolver::Sparse(StepLu::new(mt)?),
            },
        })
    }

    pub(crate) fn solve_in_place(&mut self, b: &mut [f64]) {
        match self {
            StepSolver::Block(lu) => lu.solve_in_place(b),
            StepSolver::Sparse(lu) => lu.solve_in_place(b),
            StepSolver::LowRank(w) => w.solve_in_place(b),
        }
    }
}

/// How a body's prediction is formed.
#[derive(Debug)]
pub(crate) enum Ops {
    /// Central differences: `A = 2M/Δt² − K` and `B = C/(2Δt) − M/Δt²` on one pattern.
    Central(PairCsr),
    /// Implicit generalised-α (Newmark): velocity, acceleration and the operators of the
    /// known part of the step.
    Implicit(Box<Implicit>),
}

/// A body with mass, integrated by central differences or implicitly.
#[derive(Debug)]
pub(crate) struct DynBody {
    pub(crate) n: usize,
    pub(crate) ops: Ops,
    pub(crate) minv: MInv,
    pub(crate) u_prev: Vec<f64>,
    pub(crate) u: Vec<f64>,
    pub(crate) u_next: Vec<f64>,
    pub(crate) rhs: Vec<f64>,
}

impl DynBody {
    /// `low`: an optional low-rank damping term added to `c` (M̃ then gets a Woodbury solve);
    /// `implicit`: the generalised-α coefficients of an implicit scheme (`None`: central
    /// differences).
    pub(crate) fn new(
        m: &Csc,
        c: &Csc,
        k: &Csc,
        low: Option<&LowRank>,
        dt: f64,
        contact_dofs: &[usize],
        implicit: Option<Alpha>,
    ) -> Result<Self, LinalgError> {
        let n = m.nrows();
        // The matrix factored and the factor its low-rank damping carries.
        let (mt, low_factor, ops) = match implicit {
            None => {
                let aop = Csc::lin_comb(2.0 / (dt * dt), m, -1.0, k);
                let bop = Csc::lin_comb(1.0 / (2.0 * dt), c, -1.0 / (dt * dt), m);
                let mt = Csc::lin_comb(1.0 / (dt * dt), m, 1.0 / (2.0 * dt), c);
                (mt, 1.0 / (2.0 * dt), Ops::Central(PairCsr::new(&aop, &bop)))
            }
            Some(co) => {
                let (s, cc) = co.operator(m, c, k, dt);
                let imp = Implicit::new(co, m, c, k, low, dt);
                (s, cc, Ops::Implicit(Box::new(imp)))
            }
        };
        let minv = if mt.is_diagonal() && low.is_none() {
            let d = mt.diagonal();
            if let Some(i) = d.iter().position(|v| *v <= 0.0) {
                return Err(LinalgError::NonPositiveDiagonal { n, index: i });
            }
            MInv::Diag(d.iter().map(|v| 1.0 / v).collect())
        } else {
            let lu = StepSolver::new(&mt, low, low_factor)?;
            let mut col_of = vec![usize::MAX; n];
            for (j, &d) in contact_dofs.iter().enumerate() {
                col_of[d] = j;
            }
            let mut minv = MInv::Lu {
                lu: Box::new(lu),
                cols: vec![0.0; n * contact_dofs.len()],
                col_of,
            };
            minv.fill_columns();
            minv
        };
        Ok(Self {
            n,
            ops,
            minv,
            u_prev: vec![0.0; n],
            u: vec![0.0; n],
            u_next: vec![0.0; n],
            rhs: vec![0.0; n],
        })
    }

    /// `u_next = M̃⁻¹ (rhs + A u + B u_prev)`; `rhs` holds the external force on entry (at
    /// tₙ; implicit: at tₙ₊₁, and `u_next = S⁻¹(rhs + known part)`, [`Implicit::load_rhs`]).
    pub(crate) fn predict(&mut self) {
        if self.load() {
            self.solve();
        }
    }

    /// The first half of [`DynBody::predict`]: the step's whole right-hand side in `rhs`
    /// (central differences `fⁿ + A uⁿ + B uⁿ⁻¹`; implicit `fₙ₊₁` plus the known part); true
    /// when [`DynBody::solve`] is still to be called (false: a diagonal body predicted in the
    /// same pass).
    #[allow(clippy::needless_range_loop)] // the diagonal kernel indexes six slices of one length
    pub(crate) fn load(&mut self) -> bool {
        if let (Ops::Central(ab), MInv::Diag(inv)) = (&self.ops, &self.minv) {
            if let Some((a, b)) = ab.diagonal() {
                // Diagonal M̃, A and B (a Jeffcott rotor, a lumped stator): one pass, the same
                // sums as `PairCsr::mul_add` and the diagonal solve below.
                let n = self.n;
                let (u, up, inv) = (&self.u[..n], &self.u_prev[..n], &inv[..n]);
                let (rhs, next) = (&mut self.rhs[..n], &mut self.u_next[..n]);
                let (a, b) = (&a[..n], &b[..n]);
                for i in 0..n {
                    rhs[i] += 0.0 + (a[i] * u[i] + b[i] * up[i]);
                    next[i] = inv[i] * rhs[i];
                }
                return false;
            }
        }
        match &mut self.ops {
            Ops::Central(ab) => {
                ab.mul_add(&self.u, &self.u_prev, &mut self.rhs);
                // Low-rank damping C_l: its share of B, C_l/(2Δt), is the term the Woodbury
                // solver holds (M̃ = S + C_l/(2Δt)).
                if let MInv::Lu { lu, .. } = &mut self.minv {
                    if let StepSolver::LowRank(w) = lu.as_mut() {
                        w.low_rank_mul_add(&self.u_prev, &mut self.rhs);
                    }
                }
            }
            Ops::Implicit(imp) => {
                imp.keep_external(&self.rhs);
                imp.load_rhs(&self.u, &mut self.rhs);
            }
        }
        true
    }

    /// The second half of [`DynBody::predict`]: `u_next = M̃⁻¹ rhs`.
    pub(crate) fn solve(&mut self) {
        match &mut self.minv {
            MInv::Diag(inv) => {
                for ((u, r), d) in self.u_next.iter_mut().zip(&self.rhs).zip(inv.iter()) {
                    *u = d * r;
                }
            }
            MInv::Lu { lu, .. } => {
                self.u_next.copy_from_slice(&self.rhs);
                lu.solve_in_place(&mut self.u_next);
            }
        }
    }

    /// `r ← M̃⁻¹ (r + A u + B u_prev)`: the step's linear part applied to a tangent `(u, u_prev)`
    /// of central differences (`r` holds a load on entry; an implicit body leaves `r` as it is,
    /// `time::stepper::tangent` not carrying those).
    pub(crate) fn propagate(&mut self, u: &[f64], up: &[f64], r: &mut [f64]) {
        let Ops::Central(ab) = &self.ops else {
            return;
        };
        if let (Some((a, b)), MInv::Diag(inv)) = (ab.diagonal(), &self.minv) {
            for i in 0..self.n {
                r[i] = inv[i] * (r[i] + (a[i] * u[i] + b[i] * up[i]));
            }
            return;
        }
        ab.mul_add(u, up, r);
        match &mut self.minv {
            MInv::Diag(inv) => r.iter_mut().zip(inv.iter()).for_each(|(r, d)| *r *= d),
            MInv::Lu { lu, .. } => {
                if let StepSolver::LowRank(w) = lu.as_mut() {
                    w.low_rank_mul_add(up, r);
                }
                lu.solve_in_place(r);
            }
        }
    }

    /// `u_next += M̃⁻¹ r`; `r` is overwritten.
    pub(crate) fn correct(&mut self, r: &mut [f64]) {
        match &mut self.minv {
            MInv::Diag(inv) => {
                for ((u, r), d) in self.u_next.iter_mut().zip(r.iter()).zip(inv.iter()) {
                    *u += d * r;
                }
            }
            MInv::Lu { lu, .. } => {
                lu.solve_in_place(r);
                for (u, r) in self.u_next.iter_mut().zip(r.iter()) {
                    *u += r;
                }
            }
        }
    }

    #[inline]
    pub(crate) fn flex(&self, a: usize, b: usize) -> f64 {
        match &self.minv {
            MInv::Diag(inv) => {
                if a == b {
                    inv[a]
                } else {
                    0.0
                }
            }
            MInv::Lu { cols, col_of, .. } => cols[col_of[b] * self.n + a],
        }
    }

    /// `u_next += M̃⁻¹ e_d · f` (implicit schemes with α_f ≠ 0 also count `f` in the load of
    /// tₙ₊₁).
    #[inline]
    pub(crate) fn apply(&mut self, d: usize, f: f64) {
        if let Ops::Implicit(imp) = &mut self.ops {
            if let Some(l) = imp.load_next.get_mut(d) {
                *l += f;
            }
        }
        match &self.minv {
            MInv::Diag(inv) => self.u_next[d] += inv[d] * f,
            MInv::Lu { cols, col_of, .. } => {
                let c = &cols[col_of[d] * self.n..(col_of[d] + 1) * self.n];
                for (u, v) in self.u_next.iter_mut().zip(c) {
                    *u += v * f;
                }
            }
        }
    }

    /// uⁿ⁺¹ becomes uⁿ (implicit: with its velocity and acceleration).
    pub(crate) fn rotate(&mut self) {
        if let Ops::Implicit(imp) = &mut self.ops {
            imp.finish(&self.u_next);
        }
        std::mem::swap(&mut self.u_prev, &mut self.u);
        std::mem::swap(&mut self.u, &mut self.u_next);
    }
}
