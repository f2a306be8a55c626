//! The contact dashpot (`contact_damping`, massless stators) in a contact solve.
//!
//! While a pair is in contact, a dashpot `c` between the rotor section and ground damps the
//! rate ḋ of `d`, the penetration of the section into the stator's *undeformed* surface — which,
//! with the gap closed, is the stator's deflection at the contact point. The force on the
//! section is `−n D` with `D = c ḋ` (a penalty law would read `k d + c ḋ`; here `k d` is the
//! multiplier `p` of the elastic stator). Over the step tₙ → tₙ₊₁ (backward difference, the
//! forward increment's instant):
//!
//! ```text
//! D_i = (c_i/Δt)(d_i(tₙ₊₁) − d_i(tₙ)),   d_i(tₙ₊₁) = Σ_j Ws_ij p_j   (the gap is closed),
//! d_i(tₙ)   = max(0, −g_i − n_i·(u*_C − u_C,n))                    (geometry, frozen n)
//! ```
//!
//! where `Ws` is the stators' part of `W` (a massless stator's deflection along `n_i` per unit
//! `p_j`), `g_i` the gap of the prediction `u*` against the undeformed stator. So the velocity at
//! tₙ₊₁ is known through the constraint, affine in the multipliers, and the dashpot stays inside
//! the one complementarity problem: with `R` the rotor's normal–normal flexibility
//! `n_i·F_r n_k`, `W ← W + R diag(c/Δt) Ws` and `g ← g − R diag(c/Δt) d(tₙ)`. Each step the
//! dashpot takes `D_i (d_i(tₙ₊₁) − d_i(tₙ)) = (Δt/c) D_i² ≥ 0` (counted in
//! [`super::record::RunStats::dashpot_energy`]). The collocated scheme's static solve holds the
//! rotor at uⁿ: there `D` follows from the solved forces at tₙ and the geometry at tₙ₋₁ and loads
//! the next prediction. With `full` the tangential velocity of the section `a·v_C` (backward
//! difference over the step, after the normal solve) is damped too, `−a c (a·v_C)`, for the
//! pairs that carry force.

use super::body::DynBody;
use super::stepper::Stepper;
use super::workspace::{ForceSet, Held};

impl Stepper<'_> {
    /// True when a selected pair belongs to a stator with a contact dashpot.
    pub(crate) fn any_dashpot(&self) -> bool {
        self.ws.sel.iter().any(|&ci| {
            self.case.stators[self.pairs.cands[ci].stator]
                .dashpot
                .active()
        })
    }

    /// The rotor's displacement at the solve's instant and at the instant before: the
    /// prediction and uⁿ (rotor free), or uⁿ and uⁿ⁻¹ (rotor held).
    fn instants(&self, held: Held) -> (&[f64], &[f64]) {
        instants(&self.rotor, held)
    }

    /// Fills `ws.dn` (the previous instant's penetration into the undeformed stator, zero for
    /// pairs without a dashpot) and, the rotor free, adds the dashpot to `W` and the gaps.
    pub(crate) fn dashpot_into_problem(&mut self, held: Held) {
        let dt = self.plan.dt;
        let (case, pairs, rotor) = (self.case, &self.pairs, &self.rotor);
        let (now, before) = instants(rotor, held);
        let ws = &mut self.ws;
        let q = ws.sel.len();
        for (i, &ci) in ws.sel.iter().enumerate() {
            let c = &pairs.cands[ci];
            let st = &ws.states[ci];
            ws.dn[i] = if case.stators[c.stator].dashpot.active() {
                let rd = pairs.station_dofs[c.station];
                let dx = [now[rd[0]] - before[rd[0]], now[rd[1]] - before[rd[1]]];
                (-st.g - st.n[0] * dx[0] - st.n[1] * dx[1]).max(0.0)
            } else {
                0.0
            };
        }
        if held == Held::Rotor {
            return;
        }
        for (i, &ci) in ws.sel.iter().enumerate() {
            let rdi = pairs.station_dofs[pairs.cands[ci].station];
            let ni = ws.states[ci].n;
            for (k, &ck) in ws.sel.iter().enumerate() {
                let rdk = pairs.station_dofs[pairs.cands[ck].station];
                let nk = ws.states[ck].n;
                let mut r = 0.0;
                for a in 0..2 {
                    for b in 0..2 {
                        r += ni[a] * rotor.flex(rdi[a], rdk[b]) * nk[b];
                    }
                }
                ws.rnn[i * q + k] = r;
            }
        }
        for k in 0..q {
            let ck = case.stators[pairs.cands[ws.sel[k]].stator].dashpot.c / dt;
            if ck == 0.0 {
                continue;
            }
            for i in 0..q {
                let r = ws.rnn[i * q + k] * ck;
                if r == 0.0 {
                    continue;
                }
                ws.gvec[i] -= r * ws.dn[k];
                for j in 0..q {
                    ws.wmat[i * q + j] += r * ws.wstat[k * q + j];
                }
            }
        }
    }

    /// Applies the solved dashpot forces: `−n D` on the rotor section (a correction, or, the
    /// rotor held, a load of the next prediction through the station forces), and with `full`
    /// `−a c (a·v_C)` on the pairs that carry force; counts the energy they take.
    pub(crate) fn apply_dashpots(&mut self, held: Held, into: ForceSet) {
        let dt = self.plan.dt;
        let q = self.ws.sel.len();
        let mut energy = 0.0;
        for i in 0..q {
            let ci = self.ws.sel[i];
            let cand = self.pairs.cands[ci];
            let dp = self.case.stators[cand.stator].dashpot;
            if !dp.active() {
                continue;
            }
            let ws = &self.ws;
            let d_next: f64 = (0..q).map(|j| ws.wstat[i * q + j] * ws.pvec[j]).sum();
            let step = d_next - ws.dn[i];
            let force = dp.c / dt * step;
            energy += force * step;
            let n = ws.states[ci].n;
            self.push_rotor(held, into, cand.station, [-n[0] * force, -n[1] * force], n);
        }
        // The tangential part, from the velocity over the step after the normal correction.
        for i in 0..q {
            let ci = self.ws.sel[i];
            let cand = self.pairs.cands[ci];
            let dp = self.case.stators[cand.stator].dashpot;
            if !(dp.active() && dp.full && self.ws.pvec[i] > 0.0) {
                continue;
            }
            let a = self.ws.states[ci].a;
            let rd = self.pairs.station_dofs[cand.station];
            let (now, before) = self.instants(held);
            let vt =
                (a[0] * (now[rd[0]] - before[rd[0]]) + a[1] * (now[rd[1]] - before[rd[1]])) / dt;
            let force = dp.c * vt;
            energy += force * vt * dt;
            self.push_rotor(
                held,
                into,
                cand.station,
                [-a[0] * force, -a[1] * force],
                [0.0; 2],
            );
        }
        self.stats.dashpot_energy += energy;
    }

    /// A dashpot force `f` on a station's section: a correction of the rotor's prediction
    /// (rotor free) and the station forces `into` (whose normal part takes `f`'s component
    /// along `n`; `n` zero for a tangential force).
    fn push_rotor(&mut self, held: Held, into: ForceSet, station: usize, f: [f64; 2], n: [f64; 2]) {
        let rd = self.pairs.station_dofs[station];
        if held == Held::No {
            self.rotor.apply(rd[0], f[0]);
            self.rotor.apply(rd[1], f[1]);
        }
        let fs = self.ws.forces(into);
        fs.total[station][0] += f[0];
        fs.total[station][1] += f[1];
        let fn_ = f[0] * n[0] + f[1] * n[1];
        fs.normal[station][0] += fn_ * n[0];
        fs.normal[station][1] += fn_ * n[1];
    }
}

/// The rotor's displacement at a solve's instant and at the instant before.
fn instants(rotor: &DynBody, held: Held) -> (&[f64], &[f64]) {
    match held {
        Held::No => (&rotor.u_next, &rotor.u),
        Held::Rotor => (&rotor.u, &rotor.u_prev),
    }
}
