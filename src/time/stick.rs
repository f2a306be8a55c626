//! Coulomb friction with stick in a contact solve (`station.N.stick`, issue 28; docs/STICK.md).
//!
//! A pair with stick has two unknowns: the normal force `p ≥ 0` and the tangential force `t`
//! (on the rotor section `−a t`, on the stator `+a t`; `t = μ p` is the permanent slip of
//! Eq. 19). Its slip over the step is the tangential displacement of the section's surface
//! relative to the stator's material point at the contact,
//!
//! `ζ = a·(Δx_C − Δx_A) + R |Δφ| + s R Δθ_z`   (m),
//!
//! with `Δ` the increment tₙ → tₙ₊₁ (a held rotor: tₙ₋₁ → tₙ), `Δφ` the spin's, `θ_z` the
//! section's torsion when the rotor has it and `s = sign Ω` (`a = s ẑ × n`). Like the gap it is
//! linear in the step's forces, with the same flexibilities (the rotor's `M̃⁻¹` or `S⁻¹`, the
//! stator's) read along `a`, plus the torsion's and — a driven rotor — the spin's: a torque
//! `−R s t` on them turns the surface back by `R² F t`. Coulomb's law per pair:
//!
//! * stick: `ζ = 0` and `|t| ≤ μ p`;
//! * slip: `t = σ μ p` with `σ ζ ≥ 0` (`σ = ±1`, friction against the slip).
//!
//! Solved by an active set on the friction states, which every pair keeps from step to step:
//! with the states fixed, the sticking pairs' `t` are eliminated (`ζ = 0` is a linear equation,
//! its matrix `a·F a` positive definite) and the normal forces solve the usual complementarity
//! problem on the Schur complement; a sticking pair whose `t` leaves the cone then slips in the
//! direction its `t` pushed, a slipping pair whose slip reversed sticks. All violations switch at
//! once, then — past as many rounds as there are pairs with stick — the worst alone, which ends
//! the cycles block switching can make. A problem that still does not settle (several pairs of
//! a meshed stator, whose states can cycle), or whose Schur complement is no P-matrix, is
//! solved by nonsmooth Gauss–Seidel sweeps instead (`contact::coulomb`); one that those do not
//! settle either stops the run.

use super::blocks::Block;
use super::drive::Spin;
use super::solve::pair_dirs;
use super::stator::StatorDyn;
use super::stepper::Stepper;
use super::workspace::{ForceSet, Held, StepWorkspace};
use crate::contact::coulomb::{solve_nsgs, FrictionProblem};
use crate::error::SolveError;
use crate::math::{dot, lu_in_place, lu_solve, V2};

/// Relative tolerance of the cone, `|t| ≤ μ p (1 + CONE_TOL)`, and of a reversed slip.
const CONE_TOL: f64 = 1e-10;

/// Most nonsmooth Gauss–Seidel sweeps of a step's fallback solve ([`Stepper::friction_by_sweeps`]).
const NSGS_SWEEPS: usize = 20_000;

impl Stepper<'_> {
    /// True when some selected pair has stick.
    pub(crate) fn stick_selected(&self) -> bool {
        self.pairs.any_stick && self.ws.sel.iter().any(|&ci| self.pairs.cands[ci].stick)
    }

    /// The normal forces `ws.pvec` of the selected pairs with stick and slip (module docs), and
    /// the friction coefficient `ws.mu_eff` each pair's force direction then has; returns the
    /// principal pivots taken.
    pub(crate) fn solve_friction(
        &mut self,
        held: Held,
        step: usize,
        time: f64,
    ) -> Result<usize, SolveError> {
        let (dphi, kappa) = self.spin_step(held, step, time);
        self.predicted_slip(held, step, dphi);
        let rows = self.ws.stick.rows.len();
        let cap = 3 * rows + 4;
        let mut pivots = 0;
        for round in 0..cap {
            self.friction_directions();
            self.assemble(held);
            self.assemble_tangential(held, kappa);
            match self.solve_schur(step, time) {
                Ok(p) => pivots += p,
                // A Schur complement that is no P-matrix, a singular tangential block.
                Err(_) => break,
            }
            if !self.switch_states(round >= rows + 2) {
                self.settle_friction();
                return Ok(pivots);
            }
        }
        self.friction_by_sweeps(held, kappa, (step, time))?;
        Ok(pivots)
    }

    /// The step's frictional contact by nonsmooth Gauss–Seidel (`contact::coulomb`) when the
    /// active set on the friction states does not settle: every pair with stick's `t` an
    /// unknown, the sweeps from no force, then each pair's state read off its solution — on
    /// the cone it slips, inside it sticks — and settled as the active set's are.
    ///
    /// # Errors
    /// [`SolveError::Contact`] when the sweeps do not settle either.
    fn friction_by_sweeps(
        &mut self,
        held: Held,
        kappa: f64,
        (step, time): (usize, f64),
    ) -> Result<(), SolveError> {
        for r in 0..self.ws.stick.rows.len() {
            let ci = self.ws.sel[self.ws.stick.rows[r]];
            self.ws.slip[ci] = 0;
        }
        self.friction_directions();
        self.assemble(held);
        self.assemble_tangential(held, kappa);
        let ws = &mut self.ws;
        let q = ws.sel.len();
        let sk = &mut ws.stick;
        let m = sk.rows.len();
        sk.mu.clear();
        sk.mu
            .extend(sk.rows.iter().map(|&i| self.pairs.cands[ws.sel[i]].mu));
        sk.t.clear();
        sk.t.resize(m, 0.0);
        ws.pvec[..q].fill(0.0);
        let prob = FrictionProblem {
            q,
            w_nn: &ws.wmat[..q * q],
            g: &ws.gvec[..q],
            w_nt: &sk.wnt,
            w_tn: &sk.wtn,
            w_tt: &sk.wtt,
            zeta: &sk.zeta,
            rows: &sk.rows,
            mu: &sk.mu,
        };
        solve_nsgs(&prob, &mut ws.pvec[..q], &mut sk.t, NSGS_SWEEPS).map_err(|e| {
            SolveError::Contact {
                step,
                time,
                pairs: q,
                message: format!("stick and slip did not settle in the active set on the friction states, and {e}"),
            }
        })?;
        // The states of the solution; the sticking pairs' t kept in row order.
        let mut kept = 0;
        for r in 0..m {
            let (ci, t) = (ws.sel[sk.rows[r]], sk.t[r]);
            let cone = sk.mu[r] * ws.pvec[sk.rows[r]];
            if cone > 0.0 && t.abs() >= cone * (1.0 - CONE_TOL) {
                ws.slip[ci] = if t < 0.0 { -1 } else { 1 };
            } else {
                sk.t[kept] = t;
                kept += 1;
            }
        }
        sk.t.truncate(kept);
        for (i, &ci) in ws.sel.iter().enumerate() {
            ws.carried[ci] = ws.pvec[i] > 0.0;
        }
        self.stats.friction_sweep_solves += 1;
        self.settle_friction();
        Ok(())
    }

    /// The spin's increment over the step (rad, `|Δφ|`) and its flexibility to a friction
    /// torque (`κ`, rad/(N·m): a driven rotor's, 0 otherwise).
    pub(super) fn spin_step(&self, held: Held, n: usize, t: f64) -> (f64, f64) {
        let dt = self.plan.dt;
        match (&self.spin, held) {
            (Spin::Constant, _) => (self.case.omega.abs() * dt, 0.0),
            (Spin::Profile(p), Held::No) => ((p.at(t + dt).phi - p.at(t).phi).abs(), 0.0),
            (Spin::Profile(p), Held::Rotor) => {
                if n == 0 {
                    (p.at(0.0).omega.abs() * dt, 0.0)
                } else {
                    ((p.at(t).phi - p.at(t - dt).phi).abs(), 0.0)
                }
            }
            (Spin::Driven(d), Held::No) => {
                d.free_increment(self.case, &self.events, &self.rotor, n, t)
            }
            (Spin::Driven(d), Held::Rotor) => (d.last_increment(), 0.0),
        }
    }

    /// The rows of the selected pairs with stick and their slip over step `n` with no contact
    /// force, `ζ̃` (module docs; the spin turning by `dphi`), into `ws.stick`.
    fn predicted_slip(&mut self, held: Held, n: usize, dphi: f64) {
        self.ws.stick.rows.clear();
        self.ws.stick.zeta.clear();
        for (i, &ci) in self.ws.sel.iter().enumerate() {
            let c = &self.pairs.cands[ci];
            if !c.stick {
                continue;
            }
            let dofs = self.case.stators[c.stator].targets[c.target].dofs();
            let s1 = match held {
                Held::No => self.stators[c.stator].target_disp(dofs),
                Held::Rotor => [0.0; 2],
            };
            let zeta = self.slip(held, (ci, n), s1, dphi);
            self.ws.stick.rows.push(i);
            self.ws.stick.zeta.push(zeta);
        }
    }

    /// The slip `ζ` of candidate `ci` over step `n` (m, module docs): its rotor section from
    /// the step's start to the rotor's present state (`held`: `uⁿ⁻¹` to `uⁿ`, else `uⁿ` to
    /// `u_next`), its stator target from its start to `s1`, the spin by `dphi` (rad). A
    /// radially elastic ring's material point does not move along the tangent (its friction
    /// goes to ground). A massless stator's start is its displacement after the pair's solve
    /// of step n − 1 when it had one, else the sum over that solve's forces.
    pub(super) fn slip(&self, held: Held, (ci, n): (usize, usize), s1: V2, dphi: f64) -> f64 {
        let (case, pairs, rotor) = (self.case, &self.pairs, &self.rotor);
        let (u1, u0) = match held {
            Held::No => (&rotor.u_next, &rotor.u),
            Held::Rotor => (&rotor.u, &rotor.u_prev),
        };
        let c = &pairs.cands[ci];
        let st = &self.ws.states[ci];
        let tg = &case.stators[c.stator].targets[c.target];
        let (c1, c0) = (pairs.centre(ci, u1), pairs.centre(ci, u0));
        let mut rel = [c1[0] - c0[0], c1[1] - c0[1]];
        if !tg.friction_to_ground() {
            let s0 = match (&self.stators[c.stator], self.ws.us_end[ci]) {
                (StatorDyn::Massless(_), (u, at)) if at.wrapping_add(1) == n => u,
                (st, _) => st.target_disp_start(tg.dofs()),
            };
            rel = [rel[0] - (s1[0] - s0[0]), rel[1] - (s1[1] - s0[1])];
        }
        let mut zeta = dot(st.a, rel) + c.radius * dphi;
        if let Some(tz) = torsion_dof(case, c.station) {
            zeta += spin_sign(st.n, st.a) * c.radius * (u1[tz] - u0[tz]);
        }
        zeta
    }

    /// After a solve: the friction power `t ζ/Δt` of every pair with force (W; `t = μ_e p`,
    /// `ζ` its slip over the step with the solved forces — 0 while it sticks) added to its
    /// station in the forces `into`, when the instant the solve ends at is recorded (the
    /// record is its only reader); a driven spin's increment is its free one less the step's
    /// friction torque's share. Then, when a pair sticks or the next instant is recorded, every
    /// selected pair's target displacement is kept for the next step's start (`ws.us_end`).
    pub(crate) fn friction_dissipation(&mut self, held: Held, into: ForceSet, n: usize, t: f64) {
        let instant = match held {
            Held::No => n + 1,
            Held::Rotor => n,
        };
        if instant == self.next_record {
            let (dphi, kappa) = self.spin_step(held, n, t);
            let dphi = dphi - kappa * self.ws.friction_torque;
            let dt = self.plan.dt;
            for i in 0..self.ws.sel.len() {
                let (ci, p) = (self.ws.sel[i], self.ws.pvec[i]);
                let mu = self.ws.mu_eff[ci];
                if p == 0.0 || mu == 0.0 {
                    continue;
                }
                let power = mu * p * self.slip(held, (ci, n), self.ws.us[i], dphi) / dt;
                let station = self.pairs.cands[ci].station;
                self.ws.power[into as usize][station] += power;
                self.ws.power_set = true;
            }
        }
        if self.pairs.any_stick || self.pairs.any_wear || instant + 1 == self.next_record {
            let ws = &mut self.ws;
            for (&ci, &u) in ws.sel.iter().zip(&ws.us) {
                ws.us_end[ci] = (u, n);
            }
        }
    }

    /// Every selected pair with stick's force direction for the normal problem: `n ± μ a`
    /// while it slips, `n` while it sticks (its `t` is an unknown of its own).
    fn friction_directions(&mut self) {
        let ws = &mut self.ws;
        for &i in &ws.stick.rows {
            let ci = ws.sel[i];
            ws.mu_eff[ci] = f64::from(ws.slip[ci]) * self.pairs.cands[ci].mu;
        }
    }

    /// The tangential rows against every normal column and tangential unknown, and the normal
    /// rows against the unknowns (`ws.stick`), after [`Stepper::assemble`] of the same states.
    fn assemble_tangential(&mut self, held: Held, kappa: f64) {
        let (case, pairs, rotor) = (self.case, &self.pairs, &self.rotor);
        let q = self.ws.sel.len();
        let ns = pairs.station_dofs.len();
        let StepWorkspace {
            sel,
            states,
            rblocks,
            blocks,
            dirs,
            mu_eff,
            slip,
            stick: sk,
            ..
        } = &mut self.ws;
        sk.unk.clear();
        sk.unk
            .extend((0..sk.rows.len()).filter(|&r| slip[sel[sk.rows[r]]] == 0));
        let (nr, m) = (sk.rows.len(), sk.unk.len());
        sk.wtn.resize(nr * q, 0.0);
        sk.wtt.resize(nr * m, 0.0);
        sk.wnt.resize(q * m, 0.0);
        // Along `row` at pair i, the displacement per unit force `col` on pair j's rotor
        // section and `stat` on its stator target, plus — `fr`, the force's tangential share
        // per unit unknown, 0 for a normal row — the torsion's and the spin's
        // `R_i R_j (F_θ + κ) fr` along a tangential row.
        let coupling = |i: usize, row: V2, j: usize, col: V2, stat: V2, fr: f64| {
            let (ci, cj) = (sel[i], sel[j]);
            let (si, sj) = (pairs.cands[ci].station, pairs.cands[cj].station);
            let mut w = 0.0;
            if held == Held::No {
                w += dot(row, apply2(&rblocks[si * ns + sj], col));
            }
            let (brow, slots) = blocks.row(i);
            w += dot(row, apply2(&brow[slots[j]], stat));
            if held == Held::No && fr != 0.0 {
                let mut f = kappa;
                if let (Some(a), Some(b)) = (torsion_dof(case, si), torsion_dof(case, sj)) {
                    f += rotor.flex(a, b);
                }
                w += pairs.cands[ci].radius * pairs.cands[cj].radius * f * fr;
            }
            w
        };
        let tangential = |j: usize| {
            let ci = sel[j];
            let c = &pairs.cands[ci];
            let a = states[ci].a;
            (
                a,
                case.stators[c.stator].targets[c.target].tangential_direction(a),
            )
        };
        for (r, &i) in sk.rows.iter().enumerate() {
            let a = states[sel[i]].a;
            for (j, &(_, b, s, _)) in dirs.iter().enumerate() {
                sk.wtn[r * q + j] = coupling(i, a, j, b, s, mu_eff[sel[j]]);
            }
            for (k, &rk) in sk.unk.iter().enumerate() {
                let (aj, sj) = tangential(sk.rows[rk]);
                sk.wtt[r * m + k] = coupling(i, a, sk.rows[rk], aj, sj, 1.0);
            }
        }
        for (i, d) in dirs.iter().enumerate() {
            for (k, &rk) in sk.unk.iter().enumerate() {
                let (aj, sj) = tangential(sk.rows[rk]);
                sk.wnt[i * m + k] = coupling(i, d.0, sk.rows[rk], aj, sj, 0.0);
            }
        }
    }

    /// The normal forces with the sticking pairs' `t` eliminated (the Schur complement of
    /// their `a·F a` block in `ws.wmat`, `ws.gvec`), then the `t` and every row's slip.
    fn solve_schur(&mut self, step: usize, time: f64) -> Result<usize, SolveError> {
        let ws = &mut self.ws;
        let q = ws.sel.len();
        let sk = &mut ws.stick;
        let (nr, m) = (sk.rows.len(), sk.unk.len());
        let fail = |message: String| SolveError::Contact {
            step,
            time,
            pairs: q,
            message,
        };
        sk.x.resize(m * (q + 1), 0.0);
        sk.t.resize(m, 0.0);
        if m > 0 {
            sk.lu.resize(m * m, 0.0);
            sk.piv.resize(m, 0);
            sk.col.resize(m, 0.0);
            for k in 0..m {
                for l in 0..m {
                    sk.lu[k * m + l] = sk.wtt[sk.unk[k] * m + l];
                }
            }
            if !lu_in_place(&mut sk.lu, m, &mut sk.piv, 1e-13) {
                return Err(fail(format!(
                    "singular tangential operator of {m} sticking pairs"
                )));
            }
            // X = W_TT⁻¹ [W_TN | −ζ̃] over the unknowns' rows, column by column.
            for c in 0..=q {
                for k in 0..m {
                    let r = sk.unk[k];
                    sk.col[k] = if c < q {
                        sk.wtn[r * q + c]
                    } else {
                        -sk.zeta[r]
                    };
                }
                lu_solve(&sk.lu, m, &sk.piv, &mut sk.col);
                for k in 0..m {
                    sk.x[k * (q + 1) + c] = sk.col[k];
                }
            }
            for i in 0..q {
                for k in 0..m {
                    let w = sk.wnt[i * m + k];
                    if w == 0.0 {
                        continue;
                    }
                    let xk = &sk.x[k * (q + 1)..(k + 1) * (q + 1)];
                    for (wij, x) in ws.wmat[i * q..(i + 1) * q].iter_mut().zip(xk) {
                        *wij -= w * x;
                    }
                    ws.gvec[i] -= w * xk[q];
                }
            }
        }
        let pivots = ws.solve_lcp().map_err(|e| fail(e.to_string()))?;
        let (sk, p) = (&mut ws.stick, &ws.pvec[..q]);
        for k in 0..m {
            let xk = &sk.x[k * (q + 1)..(k + 1) * (q + 1)];
            sk.t[k] = -(xk[q] + xk[..q].iter().zip(p).map(|(x, p)| x * p).sum::<f64>());
        }
        sk.slip.resize(nr, 0.0);
        for r in 0..nr {
            let wt = sk.wtn[r * q..(r + 1) * q].iter().zip(p);
            let tt = sk.wtt[r * m..(r + 1) * m].iter().zip(&sk.t);
            let minus = -sk.zeta[r]
                + wt.map(|(w, p)| w * p).sum::<f64>()
                + tt.map(|(w, t)| w * t).sum::<f64>();
            sk.slip[r] = -minus;
        }
        Ok(pivots)
    }

    /// Switches the friction states that the last solve contradicts (module docs): all at once,
    /// or the worst alone when `single`; false when every state holds.
    fn switch_states(&mut self, single: bool) -> bool {
        let ws = &mut self.ws;
        let sk = &ws.stick;
        let scale = sk.zeta.iter().fold(0.0_f64, |m, z| m.max(z.abs()));
        let mut worst: Option<(usize, i8, f64)> = None;
        let mut changed = false;
        let mut k = 0;
        for (r, &i) in sk.rows.iter().enumerate() {
            let ci = ws.sel[i];
            let (p, mu) = (ws.pvec[i], self.pairs.cands[ci].mu);
            let (to, excess) = if ws.slip[ci] == 0 {
                let t = sk.t[k];
                k += 1;
                if p <= 0.0 {
                    (if t < 0.0 { -1 } else { 1 }, f64::INFINITY)
                } else if t.abs() > mu * p * (1.0 + CONE_TOL) {
                    (if t < 0.0 { -1 } else { 1 }, t.abs() / (mu * p) - 1.0)
                } else {
                    continue;
                }
            } else {
                let back = -f64::from(ws.slip[ci]) * sk.slip[r];
                if p > 0.0 && back > CONE_TOL * scale {
                    (0, back / scale.max(f64::MIN_POSITIVE))
                } else {
                    continue;
                }
            };
            changed = true;
            if single {
                if worst.is_none_or(|w| excess > w.2) {
                    worst = Some((ci, to, excess));
                }
            } else {
                ws.slip[ci] = to;
            }
        }
        if let Some((ci, to, _)) = worst {
            ws.slip[ci] = to;
        }
        changed
    }

    /// With the states settled: each pair's friction coefficient of its force direction
    /// (`t/p` while it sticks), the force directions of `ws.dirs` to match, and the count of
    /// sticking pairs; a pair without force starts its next contact slipping forward.
    fn settle_friction(&mut self) {
        let (case, pairs) = (self.case, &self.pairs);
        let ws = &mut self.ws;
        let mut k = 0;
        for &i in &ws.stick.rows {
            let ci = ws.sel[i];
            let p = ws.pvec[i];
            if ws.slip[ci] == 0 {
                let t = ws.stick.t[k];
                k += 1;
                if p > 0.0 {
                    ws.mu_eff[ci] = t / p;
                    ws.sticking += 1;
                } else {
                    ws.slip[ci] = 1;
                }
            } else if p <= 0.0 {
                ws.slip[ci] = 1;
            }
            ws.dirs[i] = pair_dirs(case, &pairs.cands[ci], &ws.states[ci], ws.mu_eff[ci]);
        }
    }
}

/// The rotor's torsional DOF θ_z at station `s`'s node, when the rotor has one.
fn torsion_dof(case: &crate::model::Case, s: usize) -> Option<usize> {
    let node = case.stations[s].node;
    case.loop_rotor().node_torsion.get(node).copied().flatten()
}

/// `sign Ω` of a pair's tangent `a = s ẑ × n`.
#[inline]
fn spin_sign(n: V2, a: V2) -> f64 {
    if dot(a, [-n[1], n[0]]) < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// `F v` of a 2 × 2 block.
#[inline]
fn apply2(f: &Block, v: V2) -> V2 {
    [
        f[0][0] * v[0] + f[0][1] * v[1],
        f[1][0] * v[0] + f[1][1] * v[1],
    ]
}
