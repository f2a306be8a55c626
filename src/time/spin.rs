//! The speed-dependent terms of a gyroscopic rotor under a varying speed Ω(t).
//!
//! The rotor's equations are `M q̈ + (C + Ω G) q̇ + (K + Ω̇ K_st) q = f(t)`
//! ([`crate::model::rotor::Gyroscopic`]). The step operators are factored once, at the case's
//! speed Ω_f: `M̃ = M/Δt² + (C + Ω_f G)/(2Δt)`, so the constant-speed step is unchanged at
//! Ω = Ω_f. The central-difference step at Ωₙ = Ω_f + dₙ differs from it by
//! `dₙ G (uⁿ⁺¹ − uⁿ⁻¹)/(2Δt) + Ω̇ₙ K_st uⁿ` on the left. With u⁽⁰⁾ the constant-speed
//! prediction (`M̃ u⁽⁰⁾ = f̃ⁿ`), the step's uⁿ⁺¹ = u⁽⁰⁾ + δⁿ solves
//! `M̃ δⁿ = −dₙ G (u⁽⁰⁾ + δⁿ − uⁿ⁻¹)/(2Δt) − Ω̇ₙ K_st uⁿ`, which is taken with the previous
//! step's δⁿ⁻¹ in place of δⁿ on the right: one product with G (K_st is G's y–z rows, so
//! one pass by node blocks serves both) and one more solve with the factor M̃ per step.
//!
//! Accuracy: δ = O(dΔt² q̇) is smooth, δⁿ − δⁿ⁻¹ = O(Δt³), so the lag puts an O(Δt⁴) error in
//! a step — the scheme's own local order: the step stays second order (`tests/suite/transients.rs`,
//! fitted slope). Stability: the lag's share of the gyroscopic force is δ's size against the
//! step, `|d| Δt I_p/(2 I_d)` ≪ 1. A fully explicit velocity (the second-order backward
//! difference `(3uⁿ − 4uⁿ⁻¹ + uⁿ⁻²)/(2Δt)`, no second solve) was tried first and measured
//! unstable: it adds to a whirl mode of frequency ω the damping
//! `∓d (I_p/2I_d)(1 − cos ωΔt)`, negative for one whirl direction, so the rotor's highest modes
//! (ωΔt ≈ 1.6) grow unless their own damping exceeds it; the paper's FE rotor diverged at
//! 1.85 ω_n with M̃ factored at ω_n. Cost per step: `docs/PERFORMANCE.md`.
//!
//! At the first step δⁿ⁻¹ = 0 (a one-step local error O(dΔt³)).
//!
//! **Implicit schemes** ([`super::newmark`]) hold the speed inside their step operator: the
//! balance at tₙ₊₁ (α-weighted with tₙ for generalised-α) has `(C + Ωₙ₊₁G) vₙ₊₁` and
//! `(K + Ω̇ₙ₊₁K_st) uₙ₊₁` with `vₙ₊₁ = ṽ + c (uₙ₊₁ − ũ)`, `c = γ/(βΔt)`, so
//! `S(Ω, Ω̇) = S_f + (Ω − Ω_f) c G + Ω̇ K_st`. Its factor (with its columns at the contact DOFs)
//! is rebuilt when the step's end (Ωₙ₊₁, Ω̇ₙ₊₁) has moved from the pair (Ω_k, Ω̇_k) it was
//! factored at by more than [`REFACTOR`] of the terms' size ([`SpinOperator`]: a shaft chain's
//! blocks are combined and refactored in place, allocation free; any other rotor is assembled
//! and factored anew). The right-hand side gets
//! `(Ωₙ₊₁ − Ω_f) G (c ũ − ṽ) − w [(Ωₙ − Ω_f) G vₙ + Ω̇ₙ K_st uₙ] − ΔE ū`, `w = α_f/(1 − α_f)`,
//! with `ΔE = (Ωₙ₊₁ − Ω_k) c G + (Ω̇ₙ₊₁ − Ω̇_k) K_st` the factor's mismatch acting on the
//! predictor `ū = ũ + βΔt² aₙ`: an error `ΔE (uₙ₊₁ − ū) = O(ΔE Δt³)` a step. Nothing is lagged:
//! the step keeps the scheme's order and unconditional stability (docs/IMPLICIT.md §8).

use super::body::{DynBody, MInv, Ops, StepSolver};
use super::newmark::Alpha;
use crate::linalg::{BlockParts, BlockTri, Csc, LinalgError, LowRank, PairCsr, NODE_BLOCK};
use crate::model::rotor::Gyroscopic;
use crate::model::RotorBody;
use crate::model::SpinState;

/// `y += G x + K_st z`. K_st is G's rows of the y–z plane (u_y, θ_x: rows 1 and 2 of each
/// node block), so the sum is `G_r (x + z)` on those rows and `G_r x` on the others: when that
/// holds and G is block tridiagonal (a shaft chain in its natural numbering), one product of
/// G by 4 × 4 node blocks. Else G and K_st on G's row-compressed pattern.
#[derive(Debug)]
enum GkProduct {
    /// G as node blocks; K_st = G's rows 1 and 2 of each block.
    Block(BlockTri),
    /// G and K_st on G's row-compressed pattern (K_st's entries are a subset of G's).
    Csr(PairCsr),
}

/// The rows of a node block that K_st holds: u_y and θ_x.
const K_ST_ROWS: [bool; NODE_BLOCK] = [false, true, true, false];

impl GkProduct {
    fn new(terms: &Gyroscopic) -> Self {
        let (g, k) = (&terms.g, &terms.k_st);
        // K_st − (G's marked rows) = 0 entry by entry, to round-off of G's size.
        let scale = g.triplets().fold(0.0_f64, |m, (_, _, v)| m.max(v.abs()));
        let mut diff: Vec<(usize, usize, f64)> = k.triplets().collect();
        diff.extend(
            g.triplets()
                .filter(|(r, _, _)| K_ST_ROWS[r % NODE_BLOCK])
                .map(|(r, c, v)| (r, c, -v)),
        );
        let d = Csc::from_triplets(g.nrows(), g.ncols(), &diff);
        let rows_of_g = d.triplets().all(|(_, _, v)| v.abs() <= 1e-14 * scale);
        match BlockTri::new(g).filter(|_| rows_of_g) {
            Some(b) => GkProduct::Block(b),
            None => GkProduct::Csr(PairCsr::new(g, k)),
        }
    }

    /// `y += G x + K_st z`; `z` is overwritten.
    #[inline]
    fn mul_add(&self, x: &[f64], z: &mut [f64], y: &mut [f64]) {
        match self {
            GkProduct::Block(b) => {
                for (zi, xi) in z.iter_mut().zip(x) {
                    *zi += xi;
                }
                b.mul_add_rows(x, z, K_ST_ROWS, y);
            }
            GkProduct::Csr(p) => p.mul_add(x, z, y),
        }
    }
}

/// The speed-dependent correction of a gyroscopic rotor's prediction (see the module).
#[derive(Debug)]
pub(crate) struct GyroLoad {
    /// `G x + K_st z`.
    gk: GkProduct,
    /// The speed M̃ was factored at (rad/s).
    omega_f: f64,
    dt: f64,
    /// `−d (u⁽⁰⁾ + δⁿ⁻¹ − uⁿ⁻¹)/(2Δt)` (m/s, rad/s scaled by rad/s).
    x: Vec<f64>,
    /// `−Ω̇ uⁿ` (rad/s² · m or rad).
    z: Vec<f64>,
    /// The load of δ, then δⁿ (m, rad).
    delta: Vec<f64>,
    /// δⁿ⁻¹ (m, rad).
    delta_prev: Vec<f64>,
    /// Implicit schemes: the step operator's dependence on the speed.
    op: Option<SpinOperator>,
}

/// The implicit step operator `S(Ω, Ω̇) = S_f + (Ω − Ω_f) c G + Ω̇ K_st` of a gyroscopic rotor
/// (see the module) and the pair it is factored at.
#[derive(Debug)]
pub(crate) struct SpinOperator {
    co: Alpha,
    /// The speed the case's `C` holds (rad/s).
    omega_f: f64,
    /// `c = γ/(βΔt)` (1/s).
    cc: f64,
    /// (Ω − Ω_f, Ω̇) the body's factor holds (rad/s, rad/s²); NaN before the first step.
    at: (f64, f64),
    form: OperatorForm,
}

/// The relative mismatch of the speed terms `|Δd| c + |ΔΩ̇|` against `|Ω| c + |Ω̇|` below
/// which [`SpinOperator`] keeps its factor and carries the mismatch `ΔE ū` on the right-hand
/// side (ū the step's predictor): an error `ΔE (uₙ₊₁ − ū) = O(ΔE Δt³)` a step, this fraction of
/// the gyroscopic share of the scheme's own local error.
const REFACTOR: f64 = 1e-3;

/// How [`SpinOperator`] rebuilds the factor.
#[derive(Debug)]
enum OperatorForm {
    /// A shaft chain in node blocks: `work = base + d c G + Ω̇ K_st` block by block, then the
    /// block Thomas factor in place.
    Blocks {
        base: BlockParts,
        g: BlockParts,
        k_st: BlockParts,
        work: BlockParts,
    },
    /// Any other rotor (or one with low-rank damping): the sparse operator assembled and
    /// factored anew.
    Sparse {
        base: Csc,
        g: Csc,
        k_st: Csc,
        low: Option<LowRank>,
    },
}

impl SpinOperator {
    /// The operator of `body` (the loop rotor, `C` at Ω_f) for the scheme `co` at step `dt`.
    fn new(body: &RotorBody, terms: &Gyroscopic, co: Alpha, omega_f: f64, dt: f64) -> Self {
        let (base, cc) = co.operator(&body.m, &body.c, &body.k, dt);
        let blocks = (
            BlockParts::new(&base),
            BlockParts::new(&terms.g),
            BlockParts::new(&terms.k_st),
        );
        let form = match blocks {
            (Some(base), Some(g), Some(k_st)) if body.c_low.is_none() => OperatorForm::Blocks {
                work: base.clone(),
                base,
                g,
                k_st,
            },
            _ => OperatorForm::Sparse {
                base,
                g: terms.g.clone(),
                k_st: terms.k_st.clone(),
                low: body.c_low.clone(),
            },
        };
        Self {
            co,
            omega_f,
            cc,
            at: (f64::NAN, f64::NAN),
            form,
        }
    }

    /// Makes `body`'s factor hold `S(Ω_f + d, a)` within the tolerance [`REFACTOR`]: when
    /// the factored pair is farther, refactors (with the contact columns) at `(d, a)`. Returns
    /// the mismatch `(d − d_k, a − a_k)` that is left, whose term the right-hand side carries.
    ///
    /// # Errors
    /// [`LinalgError`] when the operator cannot be factored.
    fn hold(&mut self, d: f64, a: f64, body: &mut DynBody) -> Result<(f64, f64), LinalgError> {
        let (dd, da) = (d - self.at.0, a - self.at.1);
        let size = (self.omega_f + d).abs() * self.cc + a.abs();
        if (dd.abs() * self.cc + da.abs()) <= REFACTOR * size {
            return Ok((dd, da));
        }
        self.refactor(d, a, body)?;
        Ok((0.0, 0.0))
    }

    /// Factors `S(Ω_f + d, a)` into `body` with its contact columns.
    fn refactor(&mut self, d: f64, a: f64, body: &mut DynBody) -> Result<(), LinalgError> {
        let MInv::Lu { lu, .. } = &mut body.minv else {
            // A diagonal operator has no gyroscopic coupling to follow.
            return Ok(());
        };
        let dc = d * self.cc;
        match (&mut self.form, lu.as_mut()) {
            (
                OperatorForm::Blocks {
                    base,
                    g,
                    k_st,
                    work,
                },
                StepSolver::Block(f),
            ) => {
                work.set_lin_comb(base, (dc, g), (a, k_st));
                f.refactor(work)?;
            }
            (OperatorForm::Blocks { .. }, _) => unreachable!("block operator, block factor"),
            (OperatorForm::Sparse { base, g, k_st, low }, solver) => {
                let s = Csc::lin_comb(1.0, &Csc::lin_comb(1.0, base, dc, g), a, k_st);
                *solver = StepSolver::new(&s, low.as_ref(), self.cc)?;
            }
        }
        body.minv.fill_columns();
        self.at = (d, a);
        Ok(())
    }
}

impl GyroLoad {
    /// The correction of `terms` for a step `dt` (s) whose M̃ holds Ω_f G, `omega_f` in rad/s;
    /// `implicit`: the loop rotor and the coefficients of an implicit scheme, whose operator
    /// then follows the speed ([`GyroLoad::implicit_step`]).
    pub(crate) fn new(
        terms: &Gyroscopic,
        omega_f: f64,
        dt: f64,
        implicit: Option<(&RotorBody, Alpha)>,
    ) -> Self {
        let n = terms.g.nrows();
        Self {
            op: implicit.map(|(body, co)| SpinOperator::new(body, terms, co, omega_f, dt)),
            gk: GkProduct::new(terms),
            omega_f,
            dt,
            x: vec![0.0; n],
            z: vec![0.0; n],
            delta: vec![0.0; n],
            delta_prev: vec![0.0; n],
        }
    }

    /// The first part of the step's load at rest: `−(Ω − Ω_f) G v⁰ − Ω̇ K_st u⁰` added to `f`
    /// (N, N·m) for the initial acceleration, `v`, `u` the initial velocity and displacement.
    pub(crate) fn add_initial(&mut self, spin: SpinState, u: &[f64], v: &[f64], f: &mut [f64]) {
        let d = spin.omega - self.omega_f;
        for (((x, z), vi), ui) in self.x.iter_mut().zip(self.z.iter_mut()).zip(v).zip(u) {
            *x = -d * vi;
            *z = -spin.omega_dot * ui;
        }
        self.gk.mul_add(&self.x, &mut self.z, f);
    }

    /// An implicit step's speed terms, between [`DynBody::load`] and [`DynBody::solve`]:
    /// `S` held within [`REFACTOR`] of the step's end `next` (Ωₙ₊₁, Ω̇ₙ₊₁) and
    /// `(Ωₙ₊₁ − Ω_f) G (c ũ − ṽ) − w [(Ωₙ − Ω_f) G vₙ + Ω̇ₙ K_st uₙ] − ΔE ū` added to `body.rhs`,
    /// `now` the state at tₙ (see the module). Does nothing for an explicit body.
    ///
    /// # Errors
    /// [`LinalgError`] when the operator cannot be factored at `next`.
    pub(crate) fn implicit_step(
        &mut self,
        now: SpinState,
        next: SpinState,
        body: &mut DynBody,
    ) -> Result<(), LinalgError> {
        let Some(op) = &mut self.op else {
            return Ok(());
        };
        let (d0, d1) = (now.omega - self.omega_f, next.omega - self.omega_f);
        let (md, ma) = op.hold(d1, next.omega_dot, body)?;
        let Ops::Implicit(imp) = &body.ops else {
            return Ok(());
        };
        let (ut, vt) = imp.known();
        let w = op.co.alpha_f / (1.0 - op.co.alpha_f);
        let (cc, a0) = (op.cc, now.omega_dot);
        let b2 = op.co.beta * self.dt * self.dt;
        let it = self.x.iter_mut().zip(self.z.iter_mut());
        let known = ut.iter().zip(vt).zip(&imp.v).zip(&imp.a).zip(&body.u);
        for ((x, z), ((((ut, vt), v), acc), u)) in it.zip(known) {
            // ū = ũ + βΔt² aₙ: uₙ₊₁ predicted with aₙ₊₁ = aₙ, where the factor's mismatch acts.
            let ubar = ut + b2 * acc;
            *x = d1 * (cc * ut - vt) - w * d0 * v - md * cc * ubar;
            *z = -w * a0 * u - ma * ubar;
        }
        self.gk.mul_add(&self.x, &mut self.z, &mut body.rhs);
        Ok(())
    }

    /// Corrects the constant-speed prediction `body.u_next` = u⁽⁰⁾ at `spin`:
    /// `u_next += δⁿ`, `M̃ δⁿ = −d G (u⁽⁰⁾ + δⁿ⁻¹ − uⁿ⁻¹)/(2Δt) − Ω̇ K_st uⁿ`.
    #[inline]
    pub(crate) fn correct(&mut self, spin: SpinState, body: &mut DynBody) {
        let d = spin.omega - self.omega_f;
        let a = spin.omega_dot;
        if d == 0.0 && a == 0.0 {
            self.delta_prev.fill(0.0);
            return;
        }
        let h = 0.5 / self.dt;
        let it = self.x.iter_mut().zip(self.z.iter_mut());
        let us = body.u_next.iter().zip(&self.delta_prev).zip(&body.u_prev);
        for (((x, z), ((u0, dp), up)), un) in it.zip(us).zip(&body.u) {
            *x = -d * h * (u0 + dp - up);
            *z = -a * un;
        }
        self.delta.fill(0.0);
        self.gk.mul_add(&self.x, &mut self.z, &mut self.delta);
        body.correct(&mut self.delta);
        std::mem::swap(&mut self.delta, &mut self.delta_prev);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// G = K_st − K_stᵀ of three nodes, K_st on the u_y and θ_x rows coupling neighbours.
    fn terms(far: bool) -> Gyroscopic {
        let mut t = Vec::new();
        for r in (0..12_usize).filter(|r| K_ST_ROWS[r % 4]) {
            for c in (0..12_usize).filter(|c| !K_ST_ROWS[c % 4]) {
                if (r / 4).abs_diff(c / 4) <= 1 {
                    t.push((r, c, 0.3 + 0.1 * r as f64 - 0.05 * c as f64));
                }
            }
        }
        if far {
            t.push((1, 11, 0.7));
        }
        let k_st = Csc::from_triplets(12, 12, &t);
        let mut g: Vec<(usize, usize, f64)> = t.clone();
        g.extend(t.iter().map(|&(r, c, v)| (c, r, -v)));
        Gyroscopic {
            g: Csc::from_triplets(12, 12, &g),
            k_st,
        }
    }

    #[test]
    fn block_product_of_g_and_its_rows_matches_the_row_compressed_pair() {
        for far in [false, true] {
            let tm = terms(far);
            let p = GkProduct::new(&tm);
            assert_eq!(matches!(p, GkProduct::Block(_)), !far);
            let x: Vec<f64> = (0..12).map(|i| (0.4 * i as f64).sin()).collect();
            let z: Vec<f64> = (0..12).map(|i| (0.8 * i as f64).cos()).collect();
            let mut y = vec![0.1; 12];
            p.mul_add(&x, &mut z.clone(), &mut y);
            let mut want = vec![0.1; 12];
            PairCsr::new(&tm.g, &tm.k_st).mul_add(&x, &z, &mut want);
            for (a, b) in y.iter().zip(&want) {
                assert!((a - b).abs() < 1e-13, "{a} vs {b}");
            }
        }
    }
}
