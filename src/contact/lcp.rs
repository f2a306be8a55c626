//! Linear complementarity solve for the contact multipliers.
//!
//! Find `p ≥ 0` with `w = g + W p ≥ 0` and `pᵢ wᵢ = 0` for every pair, where `g` are the
//! predicted gaps (m), `W` (m/N) the delassus-type operator `G_N M̃⁻¹ B` (or its massless-stator
//! form, Eq. 49) and `p` the normal contact forces (N, compression positive).
//!
//! Solved by block principal pivoting (Júdice & Pires, Comput. Oper. Res. 21, 1994): every
//! infeasible index of the current active set toggled at once while their number falls, with
//! Murty's least-index single pivot as the backup after three block pivots without
//! progress, which terminates finitely whenever `W` is a P-matrix (true for the symmetric
//! positive definite frictionless `W` and for friction small enough to keep the unsymmetric
//! `W` a P-matrix). A warm-started step whose contact set moves by a few pairs takes one or
//! two pivots instead of one per pair. Each pivot solves the principal
//! subsystem `W_AA p_A = −g_A` densely; a rigid circle touching many nodes makes `W_AA`
//! ill-conditioned, so a singular pivot is reported, not papered over.

use crate::math::{lu_in_place, lu_solve};

/// Block pivots allowed without fewer infeasible indices before a single Murty pivot
/// (Júdice & Pires 1994).
const BLOCK_TRIES: usize = 3;

/// Why a complementarity solve failed.
#[derive(Debug, Clone, PartialEq)]
pub enum LcpFailure {
    /// The principal pivoting did not terminate within the iteration cap.
    NoConvergence {
        /// Iterations spent.
        iterations: usize,
    },
    /// A principal submatrix was singular.
    Singular {
        /// Size of the active set.
        active: usize,
    },
}

impl std::fmt::Display for LcpFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LcpFailure::NoConvergence { iterations } => write!(
                f,
                "principal pivoting did not converge in {iterations} iterations (W is not a P-matrix: friction too large for this contact set?)"
            ),
            LcpFailure::Singular { active } => write!(
                f,
                "singular contact operator on an active set of {active} pairs (redundant constraints)"
            ),
        }
    }
}

/// Preallocated buffers for [`solve`]; sized once for the largest number of pairs.
#[derive(Debug, Clone)]
pub struct LcpWorkspace {
    cap: usize,
    guess: Vec<bool>,
    active: Vec<bool>,
    /// Per index: infeasible in the current iteration.
    bad: Vec<bool>,
    idx: Vec<usize>,
    sub: Vec<f64>,
    piv: Vec<usize>,
    rhs: Vec<f64>,
    w: Vec<f64>,
}

impl LcpWorkspace {
    /// Workspace for problems with up to `cap` pairs.
    pub fn new(cap: usize) -> Self {
        Self {
            cap,
            guess: vec![false; cap],
            active: vec![false; cap],
            bad: vec![false; cap],
            idx: vec![0; cap],
            sub: vec![0.0; cap * cap],
            piv: vec![0; cap],
            rhs: vec![0.0; cap],
            w: vec![0.0; cap],
        }
    }

    /// Largest problem size this workspace holds.
    pub fn capacity(&self) -> usize {
        self.cap
    }
}

/// Solves the LCP of size `q` (`W` row-major `q×q` in `wmat[..q*q]`, gaps `g[..q]`) into
/// `p[..q]`. Returns the number of pivots used.
///
/// # Panics
/// If `q` exceeds the workspace capacity (a sizing bug in the caller).
#[allow(clippy::needless_range_loop)] // dense index kernel
pub fn solve(
    q: usize,
    wmat: &[f64],
    g: &[f64],
    p: &mut [f64],
    ws: &mut LcpWorkspace,
) -> Result<usize, LcpFailure> {
    solve_from(q, wmat, g, p, ws, false)
}

/// [`solve`] started from a guessed active set instead of the predicted penetrations: pair `i`
/// starts active when `guess[i]` (e.g. it carried force in the previous step); an empty guess
/// starts from the predicted penetrations `g[i] < 0` as [`solve`] does.
/// Murty's least-index method terminates from any starting set when `W` is a P-matrix, and the
/// solution is the same; a good guess (a contact patch that moved little since the last step)
/// saves most of the pivots, each of which refactors the active block.
///
/// # Panics
/// If `q` exceeds the workspace capacity or `guess` is shorter than `q`.
pub fn solve_warm(
    q: usize,
    wmat: &[f64],
    g: &[f64],
    p: &mut [f64],
    ws: &mut LcpWorkspace,
    guess: &[bool],
) -> Result<usize, LcpFailure> {
    assert!(guess.len() >= q, "guess shorter than the problem");
    assert!(q <= ws.cap, "LCP of size {q} exceeds workspace {}", ws.cap);
    ws.guess[..q].copy_from_slice(&guess[..q]);
    solve_from(q, wmat, g, p, ws, true)
}

fn solve_from(
    q: usize,
    wmat: &[f64],
    g: &[f64],
    p: &mut [f64],
    ws: &mut LcpWorkspace,
    warm: bool,
) -> Result<usize, LcpFailure> {
    assert!(q <= ws.cap, "LCP of size {q} exceeds workspace {}", ws.cap);
    let gscale = g[..q].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    p[..q].fill(0.0);
    if q == 0 || gscale == 0.0 {
        return Ok(0);
    }
    if q == 1 {
        // Scalar complementarity: p = max(0, −g/W).
        if g[0] < 0.0 {
            if wmat[0] <= 0.0 {
                return Err(LcpFailure::Singular { active: 1 });
            }
            p[0] = -g[0] / wmat[0];
        }
        return Ok(1);
    }
    let tol = 1e-12 * gscale;
    // Start from the guess when warm (and it is not empty), else from the set of predicted
    // penetrations.
    let warm = warm && ws.guess[..q].iter().any(|b| *b);
    for (i, gi) in g[..q].iter().enumerate() {
        ws.active[i] = if warm { ws.guess[i] } else { *gi < 0.0 };
    }
    let max_iter = 50 + 20 * q * q;
    let (mut fewest, mut tries) = (usize::MAX, BLOCK_TRIES);
    for iter in 0..max_iter {
        principal(q, wmat, g, p, ws)?;
        if !pivot(q, p, ws, tol, &mut fewest, &mut tries) {
            for v in p[..q].iter_mut() {
                if *v < 0.0 {
                    *v = 0.0;
                }
            }
            return Ok(iter + 1);
        }
    }
    Err(LcpFailure::NoConvergence {
        iterations: max_iter,
    })
}

/// Solves the principal subsystem of the active set, `W_AA p_A = −g_A` (`p` zero elsewhere),
/// and the slacks `w = g + W p` into `ws.w`.
#[allow(clippy::needless_range_loop)] // dense index kernel
fn principal(
    q: usize,
    wmat: &[f64],
    g: &[f64],
    p: &mut [f64],
    ws: &mut LcpWorkspace,
) -> Result<(), LcpFailure> {
    let mut m = 0;
    for i in 0..q {
        if ws.active[i] {
            ws.idx[m] = i;
            m += 1;
        }
    }
    for a in 0..m {
        let i = ws.idx[a];
        for b in 0..m {
            ws.sub[a * m + b] = wmat[i * q + ws.idx[b]];
        }
        ws.rhs[a] = -g[i];
    }
    if m > 0 {
        if !lu_in_place(&mut ws.sub, m, &mut ws.piv, 1e-13) {
            return Err(LcpFailure::Singular { active: m });
        }
        lu_solve(&ws.sub, m, &ws.piv, &mut ws.rhs);
    }
    p[..q].fill(0.0);
    for a in 0..m {
        p[ws.idx[a]] = ws.rhs[a];
    }
    slacks(q, wmat, g, &ws.idx[..m], &ws.rhs[..m], &mut ws.w[..q]);
    Ok(())
}

/// `w = g + W p` with `p` zero but at `idx` (`p[idx[a]] = pa[a]`): four rows at a time, each
/// summed in the order of `idx` (four independent chains of additions instead of one).
fn slacks(q: usize, wmat: &[f64], g: &[f64], idx: &[usize], pa: &[f64], w: &mut [f64]) {
    let mut rows = wmat[..q * q].chunks_exact(q);
    let mut i = 0;
    while i + 4 <= q {
        let r: [&[f64]; 4] = std::array::from_fn(|_| rows.next().unwrap_or_default());
        let mut s = [g[i], g[i + 1], g[i + 2], g[i + 3]];
        for (&j, &pj) in idx.iter().zip(pa) {
            for (sk, rk) in s.iter_mut().zip(&r) {
                *sk += rk[j] * pj;
            }
        }
        w[i..i + 4].copy_from_slice(&s);
        i += 4;
    }
    for (row, (wi, gi)) in rows.zip(w[i..q].iter_mut().zip(&g[i..q])) {
        let mut s = *gi;
        for (&j, &pj) in idx.iter().zip(pa) {
            s += row[j] * pj;
        }
        *wi = s;
    }
}

/// Toggles the active set at the infeasible indices (an active `p_i < 0`, an inactive
/// `w_i < −tol`): all of them while their number falls below the `fewest` seen, or for
/// [`BLOCK_TRIES`] more block pivots after it last fell; then Murty's least-index single pivot,
/// finite for a P-matrix. False when none is infeasible (solved).
#[allow(clippy::needless_range_loop)] // dense index kernel
fn pivot(
    q: usize,
    p: &[f64],
    ws: &mut LcpWorkspace,
    tol: f64,
    fewest: &mut usize,
    tries: &mut usize,
) -> bool {
    let pscale = p[..q].iter().fold(0.0_f64, |mx, v| mx.max(v.abs()));
    let mut infeasible = 0;
    for i in 0..q {
        ws.bad[i] = if ws.active[i] {
            p[i] < -1e-12 * pscale
        } else {
            ws.w[i] < -tol
        };
        infeasible += usize::from(ws.bad[i]);
    }
    if infeasible == 0 {
        return false;
    }
    if infeasible < *fewest || *tries > 0 {
        if infeasible < *fewest {
            *fewest = infeasible;
            *tries = BLOCK_TRIES;
        } else {
            *tries -= 1;
        }
        for i in 0..q {
            ws.active[i] ^= ws.bad[i];
        }
    } else if let Some(i) = ws.bad[..q].iter().position(|&b| b) {
        ws.active[i] = !ws.active[i];
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(q: usize, w: &[f64], g: &[f64], p: &[f64]) {
        for i in 0..q {
            let wi: f64 = g[i] + (0..q).map(|j| w[i * q + j] * p[j]).sum::<f64>();
            assert!(p[i] >= 0.0);
            assert!(wi >= -1e-12, "w[{i}] = {wi}");
            assert!((p[i] * wi).abs() < 1e-12, "complementarity {i}");
        }
    }

    #[test]
    fn single_pair_is_the_scalar_formula() {
        let mut ws = LcpWorkspace::new(1);
        let mut p = [0.0];
        solve(1, &[2.0], &[-4.0], &mut p, &mut ws).unwrap();
        assert_eq!(p[0], 2.0);
        solve(1, &[2.0], &[4.0], &mut p, &mut ws).unwrap();
        assert_eq!(p[0], 0.0);
    }

    #[test]
    fn coupled_pairs_release_the_one_pulled_away() {
        // Two pairs strongly coupled: pushing pair 0 opens pair 1, whose predicted
        // penetration is small; a single linear solve would give it a tensile force.
        let w = [1.0, 0.9, 0.9, 1.0];
        let g = [-1.0, -0.1];
        let mut p = [0.0; 2];
        let mut ws = LcpWorkspace::new(2);
        solve(2, &w, &g, &mut p, &mut ws).unwrap();
        check(2, &w, &g, &p);
        assert!(p[0] > 0.0 && p[1] == 0.0);
    }

    #[test]
    fn random_p_matrices_are_solved() {
        // Deterministic pseudo-random SPD plus small skew part (friction-like).
        let mut seed = 12345_u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        for q in 1..8 {
            let mut a = vec![0.0; q * q];
            for v in a.iter_mut() {
                *v = rnd();
            }
            let mut w = vec![0.0; q * q];
            for i in 0..q {
                for j in 0..q {
                    let mut s = 0.0;
                    for k in 0..q {
                        s += a[i * q + k] * a[j * q + k];
                    }
                    w[i * q + j] = s + if i == j { 0.5 } else { 0.0 } + 0.05 * (rnd());
                }
            }
            let g: Vec<f64> = (0..q).map(|_| rnd()).collect();
            let mut p = vec![0.0; q];
            let mut ws = LcpWorkspace::new(q);
            solve(q, &w, &g, &mut p, &mut ws).unwrap();
            check(q, &w, &g, &p);
        }
    }

    /// A warm start wrong at 20 of 40 pairs (a contact set moved along the boundary) is put
    /// right by one block pivot: 2 iterations, where single pivots would take 21; the result is
    /// the cold start's.
    #[test]
    fn a_warm_start_off_by_many_pairs_takes_one_block_pivot() {
        let q = 40;
        let mut w = vec![0.0; q * q];
        for i in 0..q {
            for j in 0..q {
                w[i * q + j] = if i == j {
                    4.0
                } else {
                    0.5 / (1.0 + (i as f64 - j as f64).abs())
                };
            }
        }
        // Every other pair penetrates deeply enough to stay active.
        let g: Vec<f64> = (0..q)
            .map(|i| if i % 2 == 0 { -1.0 } else { 5.0 })
            .collect();
        let mut cold = vec![0.0; q];
        let mut ws = LcpWorkspace::new(q);
        solve(q, &w, &g, &mut cold, &mut ws).unwrap();
        check(q, &w, &g, &cold);
        let mut guess: Vec<bool> = cold.iter().map(|p| *p > 0.0).collect();
        for flip in guess.iter_mut().take(20) {
            *flip = !*flip;
        }
        let mut p = vec![0.0; q];
        let iterations = solve_warm(q, &w, &g, &mut p, &mut ws, &guess).unwrap();
        assert_eq!(iterations, 2);
        assert_eq!(p, cold);
    }
}
