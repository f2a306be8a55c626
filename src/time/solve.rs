//! The contact solve of a step: assemble `W` over the selected pairs, solve the complementarity
//! problem, apply the forces (Eqs. 45–47).
//!
//! The contact law enters here only through the force direction per unit normal force
//! `b = n + μa` (permanent slip, Eq. 19; [`crate::contact::PairState::b`]): the problem is
//! `p ≥ 0, g + W p ≥ 0, pᵀ(g + W p) = 0` with `W_ij = n_i · F (b_j)` summed over the bodies of
//! the pair (`F` their flexibility at the contact DOFs), and the correction adds `F b_j p_j`.
//! Another law (stick, wear) changes `b`, the unknowns per pair and the correction, not the
//! loop. Ring targets re-align their frozen normal with the solved configuration and solve
//! again (`super::ring`): their gap is exact, the ring's friction-driven displacement included.

use super::blocks::{Block, Key};
use super::frame::PairForce;
use super::stator::StatorDyn;
use super::stepper::Stepper;
use super::workspace::{ForceSet, Held, StepWorkspace};
use crate::error::SolveError;
use crate::math::{dot, V2};
use crate::model::Target;

impl Stepper<'_> {
    /// Assembles `W` (row-major) and the gaps of the selected pairs into the workspace:
    /// `W_ij = n_i · F_r(s_i, s_j) b_j` (the rotor's flexibility between the pairs' stations,
    /// unless held) `+ n_i · F_s,ij s_j` (the stator's between their targets, when on one
    /// stator; [`PairBlocks`] keeps those while the selection holds).
    #[inline]
    pub(crate) fn assemble(&mut self, held: Held) {
        let (case, pairs, rotor, stators) = (self.case, &self.pairs, &self.rotor, &self.stators);
        let ws = &mut self.ws;
        let q = ws.sel.len();
        ws.blocks.update(
            &ws.sel,
            |ci| key(case, pairs, stators, ci),
            |ki, kj| {
                if ki.0 == kj.0 {
                    stators[ki.0].block_at(ki.1, kj.1)
                } else {
                    [[0.0; 2]; 2]
                }
            },
            |ki, kj| ki.0 != kj.0 || stators[ki.0].symmetric(),
        );
        let ns = pairs.station_dofs.len();
        if held == Held::No {
            for (s, rs) in pairs.station_dofs.iter().enumerate() {
                for (t, rt) in pairs.station_dofs.iter().enumerate() {
                    let blk = &mut ws.rblocks[s * ns + t];
                    for a in 0..2 {
                        for b in 0..2 {
                            blk[a][b] = rotor.flex(rs[a], rt[b]);
                        }
                    }
                }
            }
        }
        ws.dirs.clear();
        for &ci in &ws.sel {
            let d = pair_dirs(case, &pairs.cands[ci], &ws.states[ci], ws.mu_eff[ci]);
            ws.dirs.push(d);
        }
        // The rotor's displacement at each station per unit p_j: F_r(s, s_j) b_j.
        ws.rv.clear();
        for s in 0..ns {
            for &(_, bj, _, sj) in &ws.dirs {
                ws.rv.push(if held == Held::No {
                    apply2(&ws.rblocks[s * ns + sj], bj)
                } else {
                    [0.0; 2]
                });
            }
        }
        let StepWorkspace {
            blocks,
            dirs,
            rv,
            wstat,
            wmat,
            gvec,
            states,
            sel,
            ..
        } = ws;
        for (i, &(ni, _, _, si)) in dirs.iter().enumerate() {
            gvec[i] = states[sel[i]].g;
            let rows = wstat[i * q..(i + 1) * q]
                .iter_mut()
                .zip(&mut wmat[i * q..(i + 1) * q]);
            let (brow, slots) = blocks.row(i);
            let cols = slots.iter().zip(dirs.iter()).zip(&rv[si * q..(si + 1) * q]);
            for ((ws_ij, w_ij), ((&sl, &(_, _, sj, _)), r)) in rows.zip(cols) {
                let w_s = dot(ni, apply2(&brow[sl], sj));
                *ws_ij = w_s;
                *w_ij = dot(ni, *r) + w_s;
            }
        }
    }

    /// One complementarity solve over `ws.sel` (frozen geometry in `ws.states`) at step `step`,
    /// time `time` (s): the normal forces `ws.pvec`, applied to the rotor (unless held), the
    /// stators and the station forces `into`; returns the principal pivots taken.
    pub(crate) fn solve_contact(
        &mut self,
        held: Held,
        into: ForceSet,
        step: usize,
        time: f64,
    ) -> Result<usize, SolveError> {
        let q = self.ws.sel.len();
        self.ws.grow(q);
        for &ci in &self.ws.sel {
            let c = &self.pairs.cands[ci];
            self.stators[c.stator].prepare(self.case.stators[c.stator].targets[c.target].dofs());
        }
        let dashpots = self.any_dashpot();
        let rings = self.pairs.exact_rings && self.ring_start(held);
        let mut pivots = 0;
        let stick = self.stick_selected();
        for k in 0..super::ring::MAX_SOLVES {
            if stick {
                // Dashpots and stick are not combined (the scene refuses them).
                pivots += self.solve_friction(held, step, time)?;
            } else {
                pivots += self.solve_normal(held, dashpots, q, step, time)?;
            }
            // Ring targets: solve again with normals aligned to the solved configuration (not
            // after the last solve, whose forces must match the normals they are applied along).
            if !(rings && k + 1 < super::ring::MAX_SOLVES && self.ring_align(held)) {
                break;
            }
        }
        self.apply_forces(held, into);
        if dashpots {
            self.apply_dashpots(held, into);
        }
        self.target_displacements();
        // Before the dissipation keeps the targets' end for the next step's slip.
        self.wear_step(held, step, time);
        self.abrade_step();
        self.friction_dissipation(held, into, step, time);
        Ok(pivots)
    }

    /// One complementarity solve of the normal forces `ws.pvec` with every pair's force
    /// direction fixed (permanent slip, Eq. 19); returns the principal pivots taken.
    fn solve_normal(
        &mut self,
        held: Held,
        dashpots: bool,
        q: usize,
        step: usize,
        time: f64,
    ) -> Result<usize, SolveError> {
        self.assemble(held);
        if dashpots {
            self.dashpot_into_problem(held);
        }
        let contact = |message: String| SolveError::Contact {
            step,
            time,
            pairs: q,
            message,
        };
        // Abradable coatings (the scene keeps them from dashpots and stick): their compliance
        // in W and the force bounded by their yield force.
        if self.pairs.any_layer && super::abradable::add_compliance(&mut self.ws, &self.pairs) {
            return super::abradable::solve_bounded(&mut self.ws, &mut self.pairs).map_err(contact);
        }
        self.ws.solve_lcp().map_err(|e| contact(e.to_string()))
    }

    /// Applies the solved normal forces: `−b p` on the rotor section (a correction along M̃⁻¹, or
    /// a load of the next prediction when the rotor is held), `+b p` on the stator target, and the
    /// friction torque on the station's θ_z when the rotor has torsional DOFs.
    fn apply_forces(&mut self, held: Held, into: ForceSet) {
        let (case, pairs) = (self.case, &self.pairs);
        let (ws, rotor, stators) = (&mut self.ws, &mut self.rotor, &mut self.stators);
        let rotor_in = held == Held::No;
        for i in 0..ws.sel.len() {
            let p = ws.pvec[i];
            if p == 0.0 {
                continue;
            }
            let ci = ws.sel[i];
            let c = &pairs.cands[ci];
            let b = ws.states[ci].b(ws.mu_eff[ci]);
            let n = ws.states[ci].n;
            let rd = pairs.station_dofs[c.station];
            if rotor_in {
                rotor.apply(rd[0], -b[0] * p);
                rotor.apply(rd[1], -b[1] * p);
            }
            // Friction torque on the station's θ_z (rotors with torsional DOFs): the force
            // −(n + μa)p acts at R·n from the section centre, τ_z = R (n × F)_z = −R μ p (n × a)_z.
            // θ_z is uncoupled from the lateral DOFs in M̃ (M, C + ΩG, bearings have no entries
            // between them), so the torque moves no gap and W above is unchanged. Collocated
            // static solve (rotor held): the torque joins the step's load like the force.
            let tau = -c.radius * (n[0] * b[1] - n[1] * b[0]) * p;
            ws.friction_torque -= tau;
            let tz = case
                .loop_rotor()
                .node_torsion
                .get(case.stations[c.station].node);
            if let Some(&Some(tz)) = tz {
                if rotor_in {
                    rotor.apply(tz, tau);
                } else {
                    rotor.rhs[tz] += tau;
                }
            }
            let f = ws.forces(into);
            f.total[c.station][0] -= b[0] * p;
            f.total[c.station][1] -= b[1] * p;
            f.normal[c.station][0] -= n[0] * p;
            f.normal[c.station][1] -= n[1] * p;
            let tg = &case.stators[c.stator].targets[c.target];
            let (td, sb) = (tg.dofs(), tg.stator_direction(n, b));
            for a in 0..2 {
                if let Some(d) = td[a] {
                    stators[c.stator].apply(d, sb[a] * p);
                }
            }
        }
    }

    /// The displacement of each selected pair's stator target after the solve into `ws.us`
    /// (m): a massless stator's `Σ_j F_s,ij s_j p_j` from the kept blocks (its forces since it
    /// was undeformed are this solve's), any other stator's current displacement.
    fn target_displacements(&mut self) {
        let (case, pairs, stators) = (self.case, &self.pairs, &self.stators);
        let ws = &mut self.ws;
        let q = ws.sel.len();
        ws.us.clear();
        // The force on each stator target with one, s_j p_j, by the target's slot (the pairs
        // without force add nothing).
        ws.forced.clear();
        let slots = ws.blocks.slots();
        ws.forced.extend(
            ws.dirs
                .iter()
                .zip(&ws.pvec[..q])
                .zip(slots)
                .filter(|((_, &p), _)| p != 0.0)
                .map(|((d, &p), &sl)| (sl, [d.2[0] * p, d.2[1] * p])),
        );
        for (i, &ci) in ws.sel.iter().enumerate() {
            let c = &pairs.cands[ci];
            let us = match &stators[c.stator] {
                StatorDyn::Massless(_) => {
                    let mut u = [0.0; 2];
                    let (brow, _) = ws.blocks.row(i);
                    for &(sl, sp) in &ws.forced {
                        let d = apply2(&brow[sl], sp);
                        u[0] += d[0];
                        u[1] += d[1];
                    }
                    u
                }
                st => st.target_disp(case.stators[c.stator].targets[c.target].dofs()),
            };
            ws.us.push(us);
        }
    }

    /// Elastic energy stored in the massless stators by the solved forces (J):
    /// `½ Σ p_i s_i · u_s,i`.
    pub(crate) fn stator_energy(&self) -> f64 {
        let (pairs, ws, stators) = (&self.pairs, &self.ws, &self.stators);
        let mut e = 0.0;
        for (i, &ci) in ws.sel.iter().enumerate() {
            if let StatorDyn::Massless(_) = &stators[pairs.cands[ci].stator] {
                let (s, us) = (ws.dirs[i].2, ws.us[i]);
                e += 0.5 * ws.pvec[i] * dot(s, us);
            }
        }
        e
    }

    /// Appends the selected pairs that carry force to the frame's pairs (`ForceSet::Main`) or
    /// to the collocated scheme's pairs of stators with mass, up to the buffer's capacity.
    pub(crate) fn collect_pairs(&mut self, into: ForceSet) {
        let (case, pairs) = (self.case, &self.pairs);
        let ws = &mut self.ws;
        let (sel, states, pvec, mu_eff) = (&ws.sel, &ws.states, &ws.pvec, &ws.mu_eff);
        let out = match into {
            ForceSet::Main => &mut ws.frame_pairs,
            ForceSet::WithMass => &mut ws.with_mass_pairs,
        };
        for (i, &ci) in sel.iter().enumerate() {
            let p = pvec[i];
            if p > 0.0 && out.len() < out.capacity() {
                let c = &pairs.cands[ci];
                let b = states[ci].b(mu_eff[ci]);
                let node = match &case.stators[c.stator].targets[c.target] {
                    Target::Node { node, .. } => *node,
                    Target::Ring { .. } => 0,
                };
                out.push(PairForce {
                    station: c.station,
                    stator: c.stator,
                    node,
                    n: states[ci].n,
                    p,
                    force: [b[0] * p, b[1] * p],
                });
            }
        }
    }
}

/// A pair's directions in a solve (`ws.dirs`): its normal `n`, the force direction on the
/// rotor section per unit normal force `b = n + μ_e a` (friction coefficient `mu`: the
/// station's μ, or a pair with stick's `±μ` or `t/p`), the stator's share of it, and its
/// station.
#[inline]
pub(super) fn pair_dirs(
    case: &crate::model::Case,
    c: &crate::contact::Candidate,
    st: &crate::contact::PairState,
    mu: f64,
) -> (V2, V2, V2, usize) {
    let b = st.b(mu);
    let tg = &case.stators[c.stator].targets[c.target];
    (st.n, b, tg.stator_direction(st.n, b), c.station)
}

/// `F v` of a 2 × 2 block.
#[inline]
fn apply2(f: &Block, v: [f64; 2]) -> [f64; 2] {
    [
        f[0][0] * v[0] + f[0][1] * v[1],
        f[1][0] * v[0] + f[1][1] * v[1],
    ]
}

/// The [`Key`] of candidate `ci`'s blocks: its stator and the stator's index of its target's
/// DOFs.
fn key(
    case: &crate::model::Case,
    pairs: &super::select::Pairs,
    stators: &[StatorDyn],
    ci: usize,
) -> Key {
    let c = &pairs.cands[ci];
    let dofs = case.stators[c.stator].targets[c.target].dofs();
    (c.stator, stators[c.stator].key(dofs))
}
