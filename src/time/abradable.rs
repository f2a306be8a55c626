//! The elasto-plastic abradable coating in the contact solve (`[stator.abradable]`,
//! `scene::abradable`; Legrand, Batailly, Pierre et al. 2012).
//!
//! Each contact target with a coating carries a radial rod of it, in series with the stator:
//! elastic stiffness `k_a = E A / h`, yield force `f_y(d_p) = f_0 + k_h d_p` (`f_0 = A σ_y`,
//! `k_h = H A / h`), `d_p ≥ 0` its plastic shortening so far. Over one solve a pair's gap
//! (to the coating's surface, receded by `d_p`: `select::Pairs::worn`) closes by
//! `W p + p / k_a + Δ`, `Δ ≥ 0` the solve's plastic increment, so the contact problem is
//!
//! ```text
//! w = g + (W + diag 1/k_a) p + Δ ≥ 0,   p ≥ 0,   p w = 0
//! y = f_y(d_p) + k_h Δ − p ≥ 0,         Δ ≥ 0,   Δ y = 0,
//! ```
//!
//! a complementarity problem with the force bounded by the yield force. It is solved by an
//! outer active set on the pairs at their cap ([`solve_bounded`]): given the capped set C, a
//! perfectly plastic pair of C (`k_h = 0`) carries the known force `f_y`, a hardening one
//! `p = f_y + s` with `s = k_h Δ ≥ 0` the unknown (its row of `W` gains `1/k_h`: the
//! increment beyond `f_y` shortens the rod plastically); the other pairs and those `s` solve
//! the LCP of `contact::lcp` with the capped forces `f_y` moved to the gaps. Then a capped pair
//! whose gap would open (`w > 0`: it needs less than `f_y`) is released and a free pair above
//! its `f_y` is capped, all at once for the first rounds, then the lowest index alone (Murty's
//! rule, so that a cycle cannot persist), until no pair changes — at most `2q + 8` rounds, or
//! an error. A capped pair's plastic increment is its remaining penetration `Δ = −w` (`s/k_h`
//! with hardening). For one pair this is `p = clamp(p_elastic, 0, f_y)`.
//!
//! After the solve each capped pair's coating shortens by `Δ` ([`Stepper::abrade_step`]): its
//! gap opens by `Δ` for good, the volume `A Δ` is cut off and the plastic work `p Δ` (J) is
//! done (`p = f_y(d_p + Δ)`, the force that does it).

use super::select::Pairs;
use super::stepper::Stepper;
use super::workspace::{AbradableScratch, StepWorkspace};
use crate::contact::lcp;

/// Rounds of the outer active set that toggle every violating pair at once before they go one
/// at a time.
const BLOCK_ROUNDS: usize = 4;

/// A capped pair is released when its gap would open by more than this fraction of the
/// problem's largest gap (m/m): round-off of the gap, not a physical opening.
const OPEN_TOL: f64 = 1e-9;

/// A free pair is capped when its force exceeds its yield force by more than this fraction.
const CAP_TOL: f64 = 1e-9;

/// Adds each selected pair's coating compliance `1/k_a` to the diagonal of the assembled `W`;
/// true when some selected pair has a coating (the problem is then bounded).
pub(crate) fn add_compliance(ws: &mut StepWorkspace, pairs: &Pairs) -> bool {
    let q = ws.sel.len();
    let mut any = false;
    for (i, &ci) in ws.sel.iter().enumerate() {
        let ka = pairs.layer[ci][0];
        if ka > 0.0 {
            ws.wmat[i * q + i] += 1.0 / ka;
            any = true;
        }
    }
    any
}

/// Solves the bounded contact problem of the module docs over `ws.sel` (`W` with the coatings'
/// compliance in `ws.wmat`, gaps `ws.gvec`) into `ws.pvec`, the plastic increments into
/// `ws.abr.plastic`; returns the principal pivots taken.
///
/// # Errors
/// The LCP's failure, or the active set not settling, as a message.
pub(crate) fn solve_bounded(ws: &mut StepWorkspace, pairs: &mut Pairs) -> Result<usize, String> {
    let q = ws.sel.len();
    let StepWorkspace {
        sel,
        wmat,
        gvec,
        pvec,
        lcp: lws,
        carried,
        abr,
        ..
    } = ws;
    abr.grow(q);
    let mut gscale = 0.0_f64;
    for (i, &ci) in sel.iter().enumerate() {
        let [ka, f0, kh] = pairs.layer[ci];
        let coated = ka > 0.0;
        abr.fy[i] = if coated {
            f0 + kh * pairs.abraded[ci]
        } else {
            f64::INFINITY
        };
        abr.kh[i] = kh;
        abr.capped[i] = coated && pairs.capped[ci];
        gscale = gscale.max(gvec[i].abs());
    }
    let open_tol = OPEN_TOL * gscale;
    let rounds = 2 * q + 8;
    let mut pivots = 0;
    for round in 0..rounds {
        pivots +=
            round_solve(q, sel, wmat, gvec, pvec, lws, carried, abr).map_err(|e| e.to_string())?;
        // The gaps with these forces; the pairs that violate their bound.
        let mut first = None;
        for i in 0..q {
            let w = gvec[i]
                + wmat[i * q..(i + 1) * q]
                    .iter()
                    .zip(&pvec[..q])
                    .map(|(a, p)| a * p)
                    .sum::<f64>();
            abr.w_gap[i] = w;
            let bad = if abr.capped[i] {
                w > open_tol
            } else {
                pvec[i] > abr.fy[i] * (1.0 + CAP_TOL)
            };
            if bad {
                first.get_or_insert(i);
                if round < BLOCK_ROUNDS {
                    abr.capped[i] = !abr.capped[i];
                }
            }
        }
        match first {
            None => {
                finish(q, sel, pvec, carried, abr, pairs);
                return Ok(pivots);
            }
            Some(i) if round >= BLOCK_ROUNDS => abr.capped[i] = !abr.capped[i],
            Some(_) => {}
        }
    }
    Err(format!(
        "the abradable coating's bounded contact problem ({q} pairs) did not settle in {rounds} rounds of its active set (pairs at the yield force)"
    ))
}

/// One round: the LCP of the free pairs and the hardening capped pairs' excess `s`, the capped
/// forces moved to the gaps; the forces of every selected pair into `pvec`.
#[allow(clippy::too_many_arguments)]
fn round_solve(
    q: usize,
    sel: &[usize],
    wmat: &[f64],
    gvec: &[f64],
    pvec: &mut [f64],
    lws: &mut lcp::LcpWorkspace,
    carried: &[bool],
    abr: &mut AbradableScratch,
) -> Result<usize, lcp::LcpFailure> {
    abr.unk.clear();
    for i in 0..q {
        if !abr.capped[i] || abr.kh[i] > 0.0 {
            abr.unk.push(i);
        }
    }
    let m = abr.unk.len();
    for (r, &i) in abr.unk.iter().enumerate() {
        let row = &wmat[i * q..(i + 1) * q];
        abr.g[r] = gvec[i]
            + row
                .iter()
                .zip(abr.capped[..q].iter().zip(&abr.fy[..q]))
                .filter(|(_, (c, _))| **c)
                .map(|(w, (_, f))| w * f)
                .sum::<f64>();
        abr.guess[r] = carried[sel[i]];
        for (s, &j) in abr.unk.iter().enumerate() {
            abr.w[r * m + s] = row[j];
        }
        if abr.capped[i] {
            abr.w[r * m + r] += 1.0 / abr.kh[i];
        }
    }
    let pivots = lcp::solve_warm(
        m,
        &abr.w[..m * m],
        &abr.g[..m],
        &mut abr.x[..m],
        lws,
        &abr.guess[..m],
    )?;
    for ((p, c), f) in pvec[..q].iter_mut().zip(&abr.capped).zip(&abr.fy) {
        *p = if *c { *f } else { 0.0 };
    }
    for (r, &i) in abr.unk.iter().enumerate() {
        pvec[i] += abr.x[r];
    }
    Ok(pivots)
}

/// The settled solve: each capped pair's plastic increment (`s/k_h` with hardening, else its
/// remaining penetration `−w`), the warm starts for the next solve.
fn finish(
    q: usize,
    sel: &[usize],
    pvec: &[f64],
    carried: &mut [bool],
    abr: &mut AbradableScratch,
    pairs: &mut Pairs,
) {
    for i in 0..q {
        let ci = sel[i];
        abr.plastic[i] = match (abr.capped[i], abr.kh[i] > 0.0) {
            (false, _) => 0.0,
            (true, true) => ((pvec[i] - abr.fy[i]) / abr.kh[i]).max(0.0),
            (true, false) => (-abr.w_gap[i]).max(0.0),
        };
        carried[ci] = pvec[i] > 0.0;
        if pairs.layer[ci][0] > 0.0 {
            pairs.capped[ci] = abr.capped[i];
        }
    }
    abr.pending = q;
}

impl Stepper<'_> {
    /// Applies the plastic increments of the bounded solve just made: each capped pair's
    /// coating shortens by `Δ` — its target recedes by `Δ` (`worn`), the run's abraded volume
    /// grows by `A Δ` and its plastic work by `p Δ`.
    pub(crate) fn abrade_step(&mut self) {
        let q = std::mem::take(&mut self.ws.abr.pending);
        for i in 0..q {
            let d = self.ws.abr.plastic[i];
            if d <= 0.0 {
                continue;
            }
            let ci = self.ws.sel[i];
            self.pairs.abraded[ci] += d;
            self.pairs.worn[ci] += d;
            self.abradable[0] += self.pairs.wear[ci].1 * d;
            self.abradable[1] += self.ws.pvec[i] * d;
        }
    }
}
