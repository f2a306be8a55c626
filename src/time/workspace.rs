//! Every buffer a step uses, allocated before the loop.

use super::blocks::{Block, PairBlocks};
use super::frame::PairForce;
use crate::contact::lcp::{self, LcpWorkspace};
use crate::contact::PairState;
use crate::math::V2;

/// The dense contact buffers are first sized for this many pairs at once (all candidates when
/// fewer); they grow only if a contact problem is larger (large meshed stators).
const LCP_CAP: usize = 256;

/// Contact force on each station `[Fx, Fy]` (N) and its normal part, summed over pairs.
#[derive(Debug, Clone)]
pub(crate) struct StationForces {
    /// Total force `−Σ (n + μa) p` on each station's section.
    pub(crate) total: Vec<V2>,
    /// Normal part `−Σ n p`.
    pub(crate) normal: Vec<V2>,
}

impl StationForces {
    fn new(nst: usize) -> Self {
        Self {
            total: vec![[0.0; 2]; nst],
            normal: vec![[0.0; 2]; nst],
        }
    }
    /// Back to zero.
    #[inline]
    pub(crate) fn clear(&mut self) {
        for f in self.total.iter_mut().chain(self.normal.iter_mut()) {
            *f = [0.0; 2];
        }
    }
    /// `self = a + b`, component by component.
    #[inline]
    pub(crate) fn set_sum(&mut self, a: &StationForces, b: &StationForces) {
        for (o, (x, y)) in self.total.iter_mut().zip(a.total.iter().zip(&b.total)) {
            *o = [x[0] + y[0], x[1] + y[1]];
        }
        for (o, (x, y)) in self.normal.iter_mut().zip(a.normal.iter().zip(&b.normal)) {
            *o = [x[0] + y[0], x[1] + y[1]];
        }
    }
}

/// Which accumulator a contact solve adds its station forces to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ForceSet {
    /// The forces that enter the next prediction and the record: every pair in the
    /// forward-increment scheme, the massless stators' static forces in the collocated one.
    Main = 0,
    /// Collocated scheme only: the stators with mass, solved by forward increment within the
    /// step and reported at its end.
    WithMass = 1,
}

/// Who takes part in a contact solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Held {
    /// The rotor moves with the contact forces (forward increment): its flexibility `M̃⁻¹`
    /// enters `W` and the forces correct its prediction.
    No,
    /// The rotor is held at uⁿ (collocated static solve of massless stators): only the
    /// stators' compliance enters `W`; the forces load the rotor's next prediction.
    Rotor,
}

/// Preallocated buffers of the stepper: selection, complementarity problem, forces, frames.
#[derive(Debug)]
pub(crate) struct StepWorkspace {
    /// Broad-phase output: candidates near the rotor.
    pub(crate) near: Vec<usize>,
    /// Station centres and reach of a broad-phase query.
    pub(crate) centre: Vec<V2>,
    /// Reach `r + margin` per station (m).
    pub(crate) reach: Vec<f64>,
    /// Frozen geometry per candidate.
    pub(crate) states: Vec<PairState>,
    /// Per candidate: the selection (by [`StepWorkspace::stamp`]) that last computed its
    /// geometry in `states`, so a selection's second pass reuses what its first computed.
    pub(crate) stamped: Vec<u64>,
    /// Selections made so far.
    pub(crate) stamp: u64,
    /// Per candidate (ring targets): the relative position `x_C − x_S` of the section centre
    /// to the ring centre at the start of the solve (m) (`super::ring`).
    pub(crate) rel0: Vec<V2>,
    /// Per candidate (ring targets): the gap's `δ`, inner radius − section radius + offset (m).
    pub(crate) clear0: Vec<f64>,
    /// Candidates of the current complementarity problem.
    pub(crate) sel: Vec<usize>,
    /// Per candidate: did it carry force when last solved (the warm start of the LCP).
    pub(crate) carried: Vec<bool>,
    /// Warm-start guess per selected pair.
    pub(crate) guess: Vec<bool>,
    /// LCP pivoting workspace.
    pub(crate) lcp: LcpWorkspace,
    /// Contact operator `W` (row-major q × q), gaps `g`, normal forces `p`.
    pub(crate) wmat: Vec<f64>,
    /// Gaps of the selected pairs (m).
    pub(crate) gvec: Vec<f64>,
    /// Normal forces of the selected pairs (N).
    pub(crate) pvec: Vec<f64>,
    /// The stators' share of `W` (row-major q × q, m/N): a massless stator's deflection along
    /// `n_i` per unit `p_j` (the contact dashpot's rate, `super::dashpot`).
    pub(crate) wstat: Vec<f64>,
    /// The rotor's normal–normal flexibility `n_i · F_r n_j` (row-major q × q, m/N).
    pub(crate) rnn: Vec<f64>,
    /// Penetration of each selected pair's section into the undeformed stator at the previous
    /// instant (m).
    pub(crate) dn: Vec<f64>,
    /// Station forces entering the prediction and the record.
    pub(crate) main: StationForces,
    /// Collocated scheme: forces of the stators with mass from the step ending now.
    pub(crate) with_mass: StationForces,
    /// Collocated scheme: the sum of both, as recorded.
    pub(crate) recorded: StationForces,
    /// Collocated scheme: the pairs of stators with mass in contact at the step's end.
    pub(crate) with_mass_pairs: Vec<PairForce>,
    /// Collocated scheme: how many of those.
    pub(crate) with_mass_active: usize,
    /// Collocated scheme: how many of those stuck.
    pub(crate) with_mass_sticking: usize,
    /// Pairs in contact at the frame's instant.
    pub(crate) frame_pairs: Vec<PairForce>,
    /// The rub's friction torque on the rotor of the step, `Σ R μ p` over the pairs of its
    /// contact solves (N·m, resisting a positive spin).
    pub(crate) friction_torque: f64,
    /// A reduced rotor's full displacement `u = T q` for the frames (empty otherwise).
    pub(crate) full_u: Vec<f64>,
    /// The stators' flexibility blocks among the selected pairs, kept while they hold.
    pub(crate) blocks: PairBlocks,
    /// The rotor's flexibility blocks between stations (row-major, stations × stations).
    pub(crate) rblocks: Vec<Block>,
    /// Per selected pair: normal `n`, force direction `b = n + μa` on the section and `s` on
    /// the stator target, and its station.
    pub(crate) dirs: Vec<(V2, V2, V2, usize)>,
    /// Per selected pair: its stator target's displacement after the solve (m).
    pub(crate) us: Vec<V2>,
    /// Scratch per station and selected pair: the rotor's displacement there per unit `p_j`
    /// (assembly).
    pub(crate) rv: Vec<V2>,
    /// The selected pairs with force after a solve: their slot in `blocks` and the force
    /// `s_j p_j` on their target (the targets' displacements).
    pub(crate) forced: Vec<(usize, V2)>,
    /// Per candidate: the signed friction coefficient `μ_e` of its force direction
    /// `b = n + μ_e a` — the station's μ under permanent slip; with stick, `±μ` while the pair
    /// slips, `t/p` while it sticks (`super::stick`).
    pub(crate) mu_eff: Vec<f64>,
    /// Per candidate with stick: its friction state, `+1`/`−1` slipping with the section's
    /// surface ahead of/behind the stator's along `a`, `0` sticking; kept from step to step.
    pub(crate) slip: Vec<i8>,
    /// Pairs that stuck in the last solve.
    pub(crate) sticking: usize,
    /// Friction power dissipated at each station's pairs (W, `Σ t ζ/Δt`, `super::stick`), by
    /// [`ForceSet`] (`Main`, `WithMass`): computed for the recorded instants only, added to the
    /// sample and zeroed when it is recorded.
    pub(crate) power: [Vec<f64>; 2],
    /// Some entry of `power` is set (not yet recorded).
    pub(crate) power_set: bool,
    /// Per candidate: its stator target's displacement after its last solve (m) and that
    /// solve's step (`usize::MAX`: never) — a massless stator's displacement at the start of
    /// the next step without summing its forces again (`super::stick`).
    pub(crate) us_end: Vec<(V2, usize)>,
    /// The tangential part of a problem with stick (`super::stick`).
    pub(crate) stick: StickScratch,
    /// The bounded problem of abradable coatings (`super::abradable`).
    pub(crate) abr: AbradableScratch,
}

/// Buffers of the tangential rows of a contact problem with stick (`super::stick`), grown only
/// when a problem is larger than every earlier one.
#[derive(Debug, Default)]
pub(crate) struct StickScratch {
    /// The selected-pair index of each tangential row (the pairs with stick).
    pub(crate) rows: Vec<usize>,
    /// The row of each tangential unknown (the rows whose pair sticks).
    pub(crate) unk: Vec<usize>,
    /// Per row: the slip `ζ̃` of the section's surface over the stator's along `a` over the
    /// step with no contact force (m).
    pub(crate) zeta: Vec<f64>,
    /// Per row: the slip with the solved forces (m).
    pub(crate) slip: Vec<f64>,
    /// Per row: `−∂ζ/∂p_j` (rows × q, m/N).
    pub(crate) wtn: Vec<f64>,
    /// Per row: `−∂ζ/∂t_k` (rows × unknowns, m/N).
    pub(crate) wtt: Vec<f64>,
    /// Per normal row: `∂g/∂t_k` (q × unknowns, m/N).
    pub(crate) wnt: Vec<f64>,
    /// The unknowns' block of `wtt`, factored (unknowns²) and its pivots.
    pub(crate) lu: Vec<f64>,
    pub(crate) piv: Vec<usize>,
    /// `X = W_TT⁻¹ [W_TN | −ζ̃]` of the unknowns (unknowns × (q + 1)).
    pub(crate) x: Vec<f64>,
    /// Scratch column (unknowns).
    pub(crate) col: Vec<f64>,
    /// Tangential forces of the unknowns (N; on the rotor `−a t`).
    pub(crate) t: Vec<f64>,
    /// Per row: its pair's friction coefficient (the Gauss–Seidel fallback's).
    pub(crate) mu: Vec<f64>,
}

impl StepWorkspace {
    /// Buffers for `nc` candidate pairs and `nst` stations (at least one force slot), and a
    /// reduced rotor's full displacement of `nfull` DOFs (0: none).
    pub(crate) fn new(nc: usize, nstations: usize, nfull: usize) -> Self {
        let cap0 = nc.clamp(1, LCP_CAP);
        let nst = nstations.max(1);
        Self {
            near: Vec::with_capacity(nc),
            centre: vec![[0.0; 2]; nstations],
            reach: vec![0.0; nstations],
            states: vec![PairState::default(); nc],
            stamped: vec![0; nc],
            stamp: 0,
            rel0: vec![[0.0; 2]; nc],
            clear0: vec![0.0; nc],
            sel: Vec::with_capacity(nc),
            carried: vec![false; nc],
            guess: vec![false; nc],
            lcp: LcpWorkspace::new(cap0),
            wmat: vec![0.0; cap0 * cap0],
            gvec: vec![0.0; cap0],
            pvec: vec![0.0; cap0],
            wstat: vec![0.0; cap0 * cap0],
            rnn: vec![0.0; cap0 * cap0],
            dn: vec![0.0; cap0],
            main: StationForces::new(nst),
            with_mass: StationForces::new(nst),
            recorded: StationForces::new(nst),
            with_mass_pairs: Vec::with_capacity(nc),
            with_mass_active: 0,
            with_mass_sticking: 0,
            frame_pairs: Vec::with_capacity(nc),
            friction_torque: 0.0,
            full_u: vec![0.0; nfull],
            blocks: PairBlocks::default(),
            rblocks: vec![[[0.0; 2]; 2]; nstations * nstations],
            dirs: Vec::with_capacity(cap0),
            us: Vec::with_capacity(cap0),
            rv: Vec::with_capacity(cap0 * nst),
            forced: Vec::with_capacity(cap0),
            mu_eff: vec![0.0; nc],
            slip: vec![1; nc],
            sticking: 0,
            power: [vec![0.0; nst], vec![0.0; nst]],
            power_set: false,
            us_end: vec![([0.0; 2], usize::MAX); nc],
            stick: StickScratch::default(),
            abr: Default::default(),
        }
    }

    /// The friction coefficient of every candidate's force direction at the start: its μ
    /// (permanent slip, or a pair with stick slipping forward).
    pub(crate) fn with_friction(mut self, cands: &[crate::contact::Candidate]) -> Self {
        self.mu_eff = cands.iter().map(|c| c.mu).collect();
        self
    }

    /// Makes room for a problem of `q` pairs (allocates only when `q` exceeds every earlier
    /// problem and the first capacity).
    pub(crate) fn grow(&mut self, q: usize) {
        if q > self.lcp.capacity() {
            self.lcp = LcpWorkspace::new(q);
            self.wmat.resize(q * q, 0.0);
            self.gvec.resize(q, 0.0);
            self.pvec.resize(q, 0.0);
            self.wstat.resize(q * q, 0.0);
            self.rnn.resize(q * q, 0.0);
            self.dn.resize(q, 0.0);
        }
    }

    /// The warm-started complementarity solve of the assembled problem (`wmat`, `gvec`) into
    /// `pvec`: the pairs that carried force when last solved start active, and `carried` keeps
    /// this solve's; returns the principal pivots taken.
    pub(crate) fn solve_lcp(&mut self) -> Result<usize, lcp::LcpFailure> {
        let q = self.sel.len();
        for (i, &ci) in self.sel.iter().enumerate() {
            self.guess[i] = self.carried[ci];
        }
        let pivots = lcp::solve_warm(
            q,
            &self.wmat[..q * q],
            &self.gvec[..q],
            &mut self.pvec[..q],
            &mut self.lcp,
            &self.guess,
        )?;
        for (i, &ci) in self.sel.iter().enumerate() {
            self.carried[ci] = self.pvec[i] > 0.0;
        }
        Ok(pivots)
    }

    /// The station-force accumulator `which`.
    #[inline]
    pub(crate) fn forces(&mut self, which: ForceSet) -> &mut StationForces {
        match which {
            ForceSet::Main => &mut self.main,
            ForceSet::WithMass => &mut self.with_mass,
        }
    }

    /// The station forces of an instant as recorded: `Main`, or (`WithMass`) the collocated
    /// scheme's sum of the static forces and those of the stators with mass.
    #[inline]
    pub(crate) fn instant_forces(&self, which: ForceSet) -> &StationForces {
        match which {
            ForceSet::Main => &self.main,
            ForceSet::WithMass => &self.recorded,
        }
    }

    /// Number of selected pairs that carry force after a solve.
    #[inline]
    pub(crate) fn active(&self) -> usize {
        self.pvec[..self.sel.len()]
            .iter()
            .filter(|p| **p > 0.0)
            .count()
    }
}

/// Buffers of the bounded problem of abradable coatings (`super::abradable`), per selected pair
/// or unknown; grown only when a problem is larger than every earlier one.
#[derive(Debug, Default)]
pub(crate) struct AbradableScratch {
    /// Per selected pair: at its yield force in the current round.
    pub(crate) capped: Vec<bool>,
    /// Per selected pair: its yield force `f_y(d_p)` at the start of the solve (N; +∞ without
    /// a coating).
    pub(crate) fy: Vec<f64>,
    /// Per selected pair: its hardening stiffness `k_h` (N/m).
    pub(crate) kh: Vec<f64>,
    /// Per selected pair: its gap with the round's forces, `w = g + W p` (m).
    pub(crate) w_gap: Vec<f64>,
    /// The selected pair of each unknown of the round's LCP.
    pub(crate) unk: Vec<usize>,
    /// The round's LCP: operator (row-major), gaps, solution, warm start.
    pub(crate) w: Vec<f64>,
    pub(crate) g: Vec<f64>,
    pub(crate) x: Vec<f64>,
    pub(crate) guess: Vec<bool>,
    /// Per selected pair: the plastic increment `Δ` of the last bounded solve (m).
    pub(crate) plastic: Vec<f64>,
    /// Pairs of the last bounded solve whose increments `Stepper::abrade_step` has not yet
    /// applied (0: none).
    pub(crate) pending: usize,
}

impl AbradableScratch {
    pub(crate) fn grow(&mut self, q: usize) {
        if self.capped.len() < q {
            self.capped.resize(q, false);
            self.fy.resize(q, 0.0);
            self.kh.resize(q, 0.0);
            self.w_gap.resize(q, 0.0);
            self.unk.reserve(q);
            self.w.resize(q * q, 0.0);
            self.g.resize(q, 0.0);
            self.x.resize(q, 0.0);
            self.guess.resize(q, false);
            self.plastic.resize(q, 0.0);
        }
    }
}
