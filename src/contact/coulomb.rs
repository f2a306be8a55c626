//! The 2-D frictional contact problem of a step with Coulomb's law, by nonsmooth Gauss–Seidel
//! (the NSGS of Moreau and Jean, Siconos's `fc2d_nsgs`): pair by pair, each pair's local
//! problem solved exactly with the others' forces held, sweep after sweep until no force moves.
//!
//! **The problem.** `q` pairs, each with a normal force `p_i ≥ 0` (N, compression positive);
//! `m` of them (`rows`) with stick also a tangential force `t_k` (N) of their own, the others
//! slipping with their tangential share already in their normal column (permanent slip,
//! `n + μa`). Both the gaps and the slips are linear in the forces:
//!
//! * gap `g_i = g̃_i + Σ_j W_nn,ij p_j + Σ_k W_nt,ik t_k` (m), Signorini: `p_i ≥ 0`, `g_i ≥ 0`,
//!   `p_i g_i = 0`;
//! * slip `ζ_k = ζ̃_k − Σ_j W_tn,kj p_j − Σ_l W_tt,kl t_l` (m, the surface of the rotor section
//!   over the stator's material point along `a` over the step), Coulomb: `|t_k| ≤ μ_k p`, and
//!   `ζ_k = 0` inside the cone, `t_k = σ μ_k p` with `σ ζ_k ≥ 0` on it (the friction opposes
//!   the slip).
//!
//! **A pair's local problem** (the others' forces held: `g = g⁰ + A p + B t`,
//! `ζ = ζ⁰ − C p − D t`, `A = W_nn,ii > 0`, `D = W_tt,kk > 0`): separated (`p = t = 0`) when
//! `g⁰ ≥ 0`; else sticking — `g = 0`, `ζ = 0` — when that 2 × 2 solve gives `p ≥ 0` inside the
//! cone; else slipping forward or backward — `g = 0` with `t = ±μ p` — whichever keeps its slip's
//! sign. A pair without stick is the projection `p = max(0, −g⁰/A)`.
//!
//! The active set on the friction states (`time::stick`) is exact and fast when it settles;
//! this is its fallback when it does not (several pairs of a meshed stator in stick, whose
//! states can cycle, or a Schur complement that is no P-matrix): slower, but every sweep
//! lowers what moves, and a sweep that leaves the problem unsolved past the limit is a
//! failure the caller reports.

/// The problem's matrices, row-major (module docs): `w_nn` `q × q`, `g` `q`, `w_nt` `q × m`,
/// `w_tn` `m × q`, `w_tt` `m × m`, `zeta` `m`, `rows` the pair of each tangential unknown, `mu`
/// its friction coefficient.
#[derive(Debug, Clone, Copy)]
pub struct FrictionProblem<'a> {
    /// Pairs.
    pub q: usize,
    /// `∂g_i/∂p_j` (m/N).
    pub w_nn: &'a [f64],
    /// Predicted gaps `g̃` (m).
    pub g: &'a [f64],
    /// `∂g_i/∂t_k` (m/N).
    pub w_nt: &'a [f64],
    /// `−∂ζ_k/∂p_j` (m/N).
    pub w_tn: &'a [f64],
    /// `−∂ζ_k/∂t_l` (m/N).
    pub w_tt: &'a [f64],
    /// Predicted slips `ζ̃` (m).
    pub zeta: &'a [f64],
    /// The pair of each tangential unknown.
    pub rows: &'a [usize],
    /// The friction coefficient of each tangential unknown.
    pub mu: &'a [f64],
}

/// Why the sweeps did not solve the problem.
#[derive(Debug, Clone, PartialEq)]
pub struct NsgsFailure {
    /// Sweeps taken.
    pub sweeps: usize,
    /// The largest change of a force over the last sweep relative to the largest force.
    pub change: f64,
}

impl std::fmt::Display for NsgsFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the Gauss–Seidel sweeps over the frictional contact did not settle in {} sweeps (the forces still moved by {:.1e} of the largest)",
            self.sweeps, self.change
        )
    }
}

/// Relative change of the forces over a sweep below which the sweeps have settled.
pub const SETTLED: f64 = 1e-12;

impl FrictionProblem<'_> {
    /// `g_i` at the forces `p`, `t` (m).
    fn gap(&self, i: usize, p: &[f64], t: &[f64]) -> f64 {
        let (q, m) = (self.q, self.rows.len());
        let wn = &self.w_nn[i * q..(i + 1) * q];
        let wt = &self.w_nt[i * m..(i + 1) * m];
        self.g[i]
            + wn.iter().zip(p).map(|(w, p)| w * p).sum::<f64>()
            + wt.iter().zip(t).map(|(w, t)| w * t).sum::<f64>()
    }

    /// `ζ_k` at the forces `p`, `t` (m).
    fn slip(&self, k: usize, p: &[f64], t: &[f64]) -> f64 {
        let (q, m) = (self.q, self.rows.len());
        let wn = &self.w_tn[k * q..(k + 1) * q];
        let wt = &self.w_tt[k * m..(k + 1) * m];
        self.zeta[k]
            - wn.iter().zip(p).map(|(w, p)| w * p).sum::<f64>()
            - wt.iter().zip(t).map(|(w, t)| w * t).sum::<f64>()
    }

    /// Pair `i`'s local solve with its tangential unknown `k` (module docs): the new `(p, t)`.
    fn local(&self, (i, k): (usize, usize), p: &[f64], t: &[f64]) -> (f64, f64) {
        let (q, m) = (self.q, self.rows.len());
        let (a, b) = (self.w_nn[i * q + i], self.w_nt[i * m + k]);
        let (c, d) = (self.w_tn[k * q + i], self.w_tt[k * m + k]);
        let g0 = self.gap(i, p, t) - a * p[i] - b * t[k];
        let z0 = self.slip(k, p, t) + c * p[i] + d * t[k];
        if g0 >= 0.0 {
            return (0.0, 0.0);
        }
        let mu = self.mu[k];
        // Stick: A p + B t = −g⁰, C p + D t = ζ⁰.
        let det = a * d - b * c;
        if det != 0.0 {
            let (ps, ts) = ((-g0 * d - b * z0) / det, (a * z0 + c * g0) / det);
            if ps >= 0.0 && ts.abs() <= mu * ps {
                return (ps, ts);
            }
        }
        // Slip σ = ±1: (A + σμB) p = −g⁰, its slip ζ⁰ − (C + σμD) p of the sign σ.
        let slip = |s: f64| {
            let den = a + s * mu * b;
            let ps = if den > 0.0 { -g0 / den } else { f64::INFINITY };
            let z = z0 - (c + s * mu * d) * ps;
            (ps, s * mu * ps, s * z)
        };
        let (fwd, back) = (slip(1.0), slip(-1.0));
        let ok = |s: &(f64, f64, f64)| s.0.is_finite() && s.0 >= 0.0 && s.2 >= 0.0;
        match (ok(&fwd), ok(&back)) {
            (true, _) => (fwd.0, fwd.1),
            (false, true) => (back.0, back.1),
            // Neither keeps its slip's sign: slip the way the free slip goes.
            _ => {
                let s = if z0 >= 0.0 { fwd } else { back };
                if s.0.is_finite() {
                    (s.0.max(0.0), s.1)
                } else {
                    (0.0, 0.0)
                }
            }
        }
    }
}

/// Solves `prob` by nonsmooth Gauss–Seidel from the forces in `p` (`q`) and `t` (`m`), in
/// place; returns the sweeps taken. Settled when a sweep changes no force by more than
/// [`SETTLED`] of the largest.
///
/// # Errors
/// [`NsgsFailure`] when `max_sweeps` sweeps do not settle.
///
/// # Panics
/// When the slices are shorter than the sizes say (a caller's sizing bug).
pub fn solve_nsgs(
    prob: &FrictionProblem<'_>,
    p: &mut [f64],
    t: &mut [f64],
    max_sweeps: usize,
) -> Result<usize, NsgsFailure> {
    let (q, m) = (prob.q, prob.rows.len());
    assert!(p.len() >= q && t.len() >= m && prob.g.len() >= q && prob.zeta.len() >= m);
    // The tangential unknown of each pair, if any.
    let unknown = |i: usize| prob.rows.iter().position(|&r| r == i);
    let mut change = f64::INFINITY;
    for sweep in 1..=max_sweeps {
        let mut moved: f64 = 0.0;
        for i in 0..q {
            let pi = match unknown(i) {
                Some(k) => {
                    let (pi, ti) = prob.local((i, k), p, t);
                    moved = moved.max((ti - t[k]).abs());
                    t[k] = ti;
                    pi
                }
                None => {
                    let a = prob.w_nn[i * q + i];
                    let g0 = prob.gap(i, p, t) - a * p[i];
                    (-g0 / a).max(0.0)
                }
            };
            moved = moved.max((pi - p[i]).abs());
            p[i] = pi;
        }
        let largest = p[..q]
            .iter()
            .chain(&t[..m])
            .fold(0.0_f64, |a, v| a.max(v.abs()));
        change = if largest > 0.0 { moved / largest } else { 0.0 };
        if change <= SETTLED {
            return Ok(sweep);
        }
    }
    Err(NsgsFailure {
        sweeps: max_sweeps,
        change,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One pair with stick against a spring of flexibility `a` normal and `d` tangential
    /// (uncoupled), predicted gap `g` and slip `z`.
    fn one(g: f64, z: f64, mu: f64) -> (f64, f64) {
        let prob = FrictionProblem {
            q: 1,
            w_nn: &[2.0],
            g: &[g],
            w_nt: &[0.0],
            w_tn: &[0.0],
            w_tt: &[4.0],
            zeta: &[z],
            rows: &[0],
            mu: &[mu],
        };
        let (mut p, mut t) = ([0.0], [0.0]);
        solve_nsgs(&prob, &mut p, &mut t, 100).unwrap();
        (p[0], t[0])
    }

    #[test]
    fn one_pair_sticks_inside_the_cone_slips_on_it_and_separates() {
        // Penetration 1 → p = 0.5; a slip of 0.4 held by t = 0.1 (inside 0.3 × 0.5).
        assert_eq!(one(-1.0, 0.4, 0.3), (0.5, 0.1));
        // A slip of 1.0 would need t = 0.25 > 0.15: slips on the cone, forward.
        assert_eq!(one(-1.0, 1.0, 0.3), (0.5, 0.15));
        assert_eq!(one(-1.0, -1.0, 0.3), (0.5, -0.15));
        // Open: no force.
        assert_eq!(one(0.5, 1.0, 0.3), (0.0, 0.0));
    }

    #[test]
    fn coupled_pairs_settle_to_a_solution_of_the_whole_problem() {
        // Two pairs with stick, coupled normal and tangential flexibilities (a symmetric,
        // positive definite operator) and a permanent-slip pair: the settled forces meet every
        // condition of the module's problem.
        let q = 3;
        let w_nn = [2.0, 0.5, 0.2, 0.5, 2.0, 0.3, 0.2, 0.3, 1.5];
        let g = [-1.0, -0.8, -0.2];
        let rows = [0, 1];
        let w_nt = [0.3, 0.1, 0.1, 0.3, 0.05, 0.05];
        let w_tn = [0.3, 0.1, 0.1, 0.1, 0.3, 0.05];
        let w_tt = [3.0, 0.8, 0.8, 3.0];
        let zeta = [0.6, -2.0];
        let mu = [0.3, 0.3];
        let prob = FrictionProblem {
            q,
            w_nn: &w_nn,
            g: &g,
            w_nt: &w_nt,
            w_tn: &w_tn,
            w_tt: &w_tt,
            zeta: &zeta,
            rows: &rows,
            mu: &mu,
        };
        let (mut p, mut t) = ([0.0; 3], [0.0; 2]);
        let sweeps = solve_nsgs(&prob, &mut p, &mut t, 10_000).unwrap();
        assert!(sweeps > 1);
        let tol = 1e-10;
        for i in 0..q {
            let gi = prob.gap(i, &p, &t);
            assert!(
                p[i] >= 0.0 && gi >= -tol && (p[i] * gi).abs() < tol,
                "pair {i}: p {p:?} g {gi}"
            );
        }
        for k in 0..2 {
            let (pk, z) = (p[rows[k]], prob.slip(k, &p, &t));
            assert!(t[k].abs() <= mu[k] * pk * (1.0 + 1e-12));
            if t[k].abs() < mu[k] * pk * (1.0 - 1e-9) {
                assert!(z.abs() < tol, "sticking pair {k} slips {z}");
            } else {
                assert!(
                    t[k].signum() * z >= -tol,
                    "pair {k} slips against its friction"
                );
            }
        }
        // The second pair's free slip (−2) is too large to hold: it slips backward.
        assert!((t[1] + mu[1] * p[1]).abs() < 1e-9, "{t:?} {p:?}");
    }
}
