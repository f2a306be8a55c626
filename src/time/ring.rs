//! Ring targets in a contact solve: the frozen normal re-aligned with the solved configuration
//! (exact circle-in-circle kinematics, [`crate::contact::ring`]).
//!
//! After a complementarity solve with frozen normals, each ring pair that carries force gets the
//! normal at which its own solved relative position `d = d̃ − p W b` is parallel to it, the
//! other pairs' forces held ([`crate::contact::ring::align_normal`], Newton on the angle); the
//! problem is then assembled and solved again with those normals, until no normal moves by more
//! than [`ANGLE_TOL`]. With one ring pair the Newton solve is exact and the second solve
//! confirms it; coupled pairs (several rings on one flexible rotor) converge by this outer
//! iteration. Its gaps stay linear in the multipliers: `g_i = δ_i − n_i·d_i⁰`, `d_i⁰` the
//! relative position at the solve's start. The ring's displacement in `d` is its whole
//! displacement, the friction-driven tangential part included, in both forms: a massless ring
//! through its compliance `K⁻¹`, a ring with mass through its step operator's `M̃⁻¹` from its
//! predicted position.

use super::stepper::Stepper;
use super::workspace::Held;
use crate::contact::ring::align_normal;
use crate::math::{dot, V2};
use crate::model::Target;

/// Largest change of a ring normal (rad) that still takes another solve. The penetration a
/// residual angle ψ leaves is `δ ψ²/2`: 1e-9 rad gives 5e-19 δ.
pub(crate) const ANGLE_TOL: f64 = 1e-9;

/// Most complementarity solves of one contact phase with ring pairs.
pub(crate) const MAX_SOLVES: usize = 12;

impl Stepper<'_> {
    /// Records the relative position and the gap's `δ` of every selected ring pair at the
    /// solve's start (`ws.rel0`, `ws.clear0`); true when there is one.
    pub(crate) fn ring_start(&mut self, held: Held) -> bool {
        let (case, pairs, rotor, stators) = (self.case, &self.pairs, &self.rotor, &self.stators);
        let u = match held {
            Held::No => &rotor.u_next,
            Held::Rotor => &rotor.u,
        };
        let ws = &mut self.ws;
        let mut any = false;
        for &ci in &ws.sel {
            let c = &pairs.cands[ci];
            if let Target::Ring {
                center0,
                dofs,
                radial: false,
                ..
            } = &case.stators[c.stator].targets[c.target]
            {
                let uc = pairs.centre(ci, u);
                let us = stators[c.stator].target_disp(*dofs);
                let d = [uc[0] - center0[0] - us[0], uc[1] - center0[1] - us[1]];
                let st = &ws.states[ci];
                ws.rel0[ci] = d;
                ws.clear0[ci] = st.g + dot(st.n, d);
                any = true;
            }
        }
        any
    }

    /// The relative flexibility of pair `i` to a force on pair `j` (selected pairs' candidate
    /// indices `ci`, `cj`), 2×2 (m/N): `Δd_i = −block · b_j p_j`, the rotor's (unless held) plus
    /// the stator's when both pairs are on it.
    fn pair_block(&self, held: Held, ci: usize, cj: usize) -> [[f64; 2]; 2] {
        let (c, d) = (&self.pairs.cands[ci], &self.pairs.cands[cj]);
        let mut m = [[0.0; 2]; 2];
        if held == Held::No {
            let (ri, rj) = (
                self.pairs.station_dofs[c.station],
                self.pairs.station_dofs[d.station],
            );
            for a in 0..2 {
                for b in 0..2 {
                    m[a][b] += self.rotor.flex(ri[a], rj[b]);
                }
            }
        }
        if c.stator == d.stator {
            let ti = self.case.stators[c.stator].targets[c.target].dofs();
            let tj = self.case.stators[d.stator].targets[d.target].dofs();
            for a in 0..2 {
                for b in 0..2 {
                    if let (Some(x), Some(y)) = (ti[a], tj[b]) {
                        m[a][b] += self.stators[c.stator].flex(x, y);
                    }
                }
            }
        }
        m
    }

    /// After a solve: aligns the normal of every ring pair that carries force with its solved
    /// relative position (module docs) and resets its frozen gap; true when a normal moved by
    /// more than [`ANGLE_TOL`], i.e. the problem must be solved again.
    pub(crate) fn ring_align(&mut self, held: Held) -> bool {
        let q = self.ws.sel.len();
        let mut moved = false;
        for i in 0..q {
            let ci = self.ws.sel[i];
            let pi = self.ws.pvec[i];
            if pi <= 0.0 {
                continue;
            }
            let c = self.pairs.cands[ci];
            if !self.case.stators[c.stator].targets[c.target].exact_ring() {
                continue;
            }
            // d̃: the start position moved by every other pair's force.
            let mut rel: V2 = self.ws.rel0[ci];
            for j in 0..q {
                let pj = self.ws.pvec[j];
                if j == i || pj == 0.0 {
                    continue;
                }
                let cj = self.ws.sel[j];
                let bj = self.ws.states[cj].b(self.ws.mu_eff[cj]);
                let m = self.pair_block(held, ci, cj);
                for a in 0..2 {
                    rel[a] -= (m[a][0] * bj[0] + m[a][1] * bj[1]) * pj;
                }
            }
            let w = self.pair_block(held, ci, ci);
            let st = self.ws.states[ci];
            let spin = dot(st.a, [-st.n[1], st.n[0]]).signum();
            let clear = self.ws.clear0[ci];
            let Some(al) = align_normal(
                rel,
                w,
                self.ws.mu_eff[ci],
                spin,
                clear,
                st.n,
                0.1 * ANGLE_TOL,
            ) else {
                continue;
            };
            let turn = (st.n[0] * al.n[1] - st.n[1] * al.n[0]).atan2(dot(st.n, al.n));
            if turn.abs() > ANGLE_TOL {
                moved = true;
            }
            let n = al.n;
            let s = &mut self.ws.states[ci];
            s.n = n;
            s.a = [-spin * n[1], spin * n[0]];
            s.g = clear - dot(n, self.ws.rel0[ci]);
        }
        moved
    }
}
