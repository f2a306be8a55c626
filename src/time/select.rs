//! Contact selection: which candidate pairs enter a complementarity problem.
//!
//! Every contact phase of a step selects the same way ([`Pairs::select`]): freeze `n`, `a` and
//! the gap `g` of every candidate that can be near the rotor (broad phase), find the deepest
//! penetration `d = max(−g, 0)`; if there is one, every pair with `g < d` enters the problem
//! (a pair that is open now may close when the others push the rotor toward it). Phases
//! differ only in which stators they see, whether the broad-phase index is used, and whether
//! the stators are taken deformed ([`Phase`]).

use super::stator::StatorDyn;
use super::workspace::StepWorkspace;
use crate::contact::search::BroadPhase;
use crate::contact::{exact_gap, pair_state, Candidate, PairState};
use crate::math::V2;
use crate::model::{Case, Target};

/// Which candidates a contact phase considers, and how it sees the stators.
#[derive(Debug, Clone)]
pub(crate) struct Phase {
    /// Query the broad-phase index (node targets of massless stators).
    pub(crate) use_index: bool,
    /// Per stator: whether its non-indexed candidates (stators with mass, ring targets) take
    /// part.
    pub(crate) keep: Vec<bool>,
    /// Gaps with the stators' current displacement (`false`: undeformed).
    pub(crate) deformed: bool,
    /// The phase's candidates, sorted, when it visits them without the index
    /// ([`Pairs::direct`]): the same set whatever the margin, so [`Pairs::select`] computes
    /// their geometry once. `None`: gathered through the index at each margin.
    pub(crate) direct: Option<Vec<usize>>,
}

/// Phases whose index would hold at most this many node targets visit every candidate
/// directly: a query (its reach, its bins, a sort) costs more than the few exact gaps.
const DIRECT: usize = 4;

/// Squared-distance screen of a node target (no square root): false only when the pair's
/// gap `g = |d| − r + Δ` is certainly at least `margin` — `|d|` beyond the reach
/// `r − Δ + margin` by more than a band of 1e-9 (r + |Δ| + margin), many orders above the
/// round-off of the gap (≈ 1e-16 of those terms) — so a pair it rejects could not have entered
/// the problem. A non-positive reach always passes.
#[inline]
fn may_reach(d: V2, r: f64, offset: f64, margin: f64) -> bool {
    let reach = r - offset + margin;
    let band = 1e-9 * (r + offset.abs() + margin);
    reach <= 0.0 || d[0] * d[0] + d[1] * d[1] <= (reach + band) * (reach + band)
}

/// The candidate pairs of a run and the index that finds the ones near the rotor.
#[derive(Debug)]
pub(crate) struct Pairs {
    /// Every (station, stator target) pair that may touch.
    pub(crate) cands: Vec<Candidate>,
    /// Rotor DOFs `[x, y]` of each station's node.
    pub(crate) station_dofs: Vec<[usize; 2]>,
    /// Section radius of each station (m).
    station_radius: Vec<f64>,
    /// Node targets of massless stators, which do not move in a prediction, binned by radius
    /// and angle (`contact::search`).
    broad: BroadPhase,
    /// Candidates visited every step (stators with mass, ring targets).
    dynamic: Vec<usize>,
    /// Spin (rad/s), for the tangent `a = Ω × n`.
    omega: f64,
    /// Per stator: the offset Δ (m) added to every gap of its pairs — a clearance event
    /// ([`crate::model::ClearanceEvent`]); 0 without.
    pub(crate) offset: Vec<f64>,
    /// `max(0, −min Δ)` (m): how much nearer the stators are than placed, widening the
    /// broad phase's reach.
    pub(crate) closer: f64,
    /// Some candidate is a ring with exact kinematics (its solves re-align normals,
    /// `super::ring`).
    pub(crate) exact_rings: bool,
    /// Some candidate has Coulomb friction with stick (`super::stick`).
    pub(crate) any_stick: bool,
    /// Per candidate: its target's wear, `(k A, area)` (m²/N, m², `model::StatorWear`); `(0, 0)`
    /// for a target that does not wear.
    pub(crate) wear: Vec<(f64, f64)>,
    /// Per candidate: its target's worn depth (m), added to its gap (`super::wear`).
    pub(crate) worn: Vec<f64>,
    /// Some candidate wears or carries an abradable coating (its target recedes).
    pub(crate) any_wear: bool,
    /// Per candidate: its target's abradable coating `[k_a, f_0, k_h]` (N/m, N, N/m,
    /// `resolve::AbradableLayer::at`); `k_a = 0` without one (`super::abradable`).
    pub(crate) layer: Vec<[f64; 3]>,
    /// Per candidate: its coating's plastic shortening `d_p` so far (m), part of `worn`.
    pub(crate) abraded: Vec<f64>,
    /// Per candidate: its coating was at its yield force in its last solve (the warm start of
    /// the bounded problem, `super::abradable`).
    pub(crate) capped: Vec<bool>,
    /// Some candidate has a coating.
    pub(crate) any_layer: bool,
}

impl Pairs {
    /// Every station against every target of the stators facing it.
    pub(crate) fn new(case: &Case) -> Self {
        let mut cands: Vec<Candidate> = Vec::new();
        for (k, s) in case.stators.iter().enumerate() {
            for t in 0..s.targets.len() {
                let station = s.target_station(t);
                let st = &case.stations[station];
                cands.push(Candidate {
                    station,
                    stator: k,
                    target: t,
                    mu: st.friction,
                    radius: st.radius,
                    stick: st.stick,
                });
            }
        }
        let station_dofs: Vec<[usize; 2]> = case
            .stations
            .iter()
            .map(|s| case.loop_rotor().node_dofs[s.node])
            .collect();
        let mut indexed = Vec::new();
        let mut dynamic = Vec::new();
        for (ci, c) in cands.iter().enumerate() {
            match &case.stators[c.stator].targets[c.target] {
                Target::Node { x0, .. } if case.stators[c.stator].massless() => {
                    indexed.push((ci, c.station, *x0))
                }
                _ => dynamic.push(ci),
            }
        }
        let exact_rings = cands
            .iter()
            .any(|c| case.stators[c.stator].targets[c.target].exact_ring());
        let wear: Vec<(f64, f64)> = cands
            .iter()
            .map(|c| {
                case.stators[c.stator]
                    .wear
                    .as_ref()
                    .map_or((0.0, 0.0), |w| {
                        (w.rate, w.areas.get(c.target).copied().unwrap_or(0.0))
                    })
            })
            .collect();
        let layer: Vec<[f64; 3]> = cands
            .iter()
            .map(|c| {
                let s = &case.stators[c.stator];
                match (s.wear.as_ref().and_then(|w| w.layer), &s.wear) {
                    (Some(l), Some(w)) => l.at(w.areas.get(c.target).copied().unwrap_or(0.0)),
                    _ => [0.0; 3],
                }
            })
            .collect();
        let any_layer = layer.iter().any(|l| l[0] > 0.0);
        Self {
            any_layer,
            abraded: vec![0.0; cands.len()],
            capped: vec![false; cands.len()],
            layer,
            exact_rings,
            any_stick: cands.iter().any(|c| c.stick),
            any_wear: any_layer || wear.iter().any(|w| w.0 > 0.0 && w.1 > 0.0),
            worn: vec![0.0; cands.len()],
            wear,
            broad: BroadPhase::new(&indexed, 16),
            cands,
            station_dofs,
            station_radius: case.stations.iter().map(|s| s.radius).collect(),
            dynamic,
            omega: case.omega,
            offset: vec![0.0; case.stators.len()],
            closer: 0.0,
        }
    }

    /// Number of candidates.
    pub(crate) fn len(&self) -> usize {
        self.cands.len()
    }

    /// The candidates a phase visits directly (sorted): every candidate it can see, when its
    /// index holds at most [`DIRECT`] node targets (or it does not use the index); `None`
    /// when it needs the index. `use_index` and `keep` as in [`Phase`].
    pub(crate) fn direct(&self, use_index: bool, keep: &[bool]) -> Option<Vec<usize>> {
        if use_index && self.broad.len() > DIRECT {
            return None;
        }
        let mut list: Vec<usize> = self
            .dynamic
            .iter()
            .copied()
            .filter(|&ci| keep[self.cands[ci].stator])
            .collect();
        if use_index {
            list.extend(self.broad.candidates());
        }
        list.sort_unstable();
        list.dedup();
        Some(list)
    }

    /// Section centre `[x, y]` of a candidate's station with the rotor at `u`.
    #[inline]
    pub(crate) fn centre(&self, ci: usize, u: &[f64]) -> V2 {
        let rd = self.station_dofs[self.cands[ci].station];
        [u[rd[0]], u[rd[1]]]
    }

    /// Frozen geometry of candidate `ci` with the rotor at `u` and the stator as `stator` is
    /// now (None: undeformed, the start of a massless stator's step).
    #[inline]
    fn pair_at(&self, case: &Case, ci: usize, u: &[f64], stator: Option<&StatorDyn>) -> PairState {
        let c = &self.cands[ci];
        let tg = &case.stators[c.stator].targets[c.target];
        let us = stator.map_or([0.0; 2], |s| s.target_disp(tg.dofs()));
        let mut st = pair_state(tg, c.radius, self.centre(ci, u), us, self.omega);
        st.g += self.offset[c.stator] + self.worn[ci];
        st
    }

    /// The candidates that may have `g < margin` with the stations displaced as in `u`: from
    /// the index when the phase uses it, plus the non-indexed candidates the phase keeps;
    /// sorted.
    fn gather(&self, ws: &mut StepWorkspace, u: &[f64], margin: f64, phase: &Phase) {
        ws.near.clear();
        if phase.use_index && !self.broad.is_empty() {
            for (s, d) in self.station_dofs.iter().enumerate() {
                ws.centre[s] = [u[d[0]], u[d[1]]];
                ws.reach[s] = self.station_radius[s] + margin + self.closer;
            }
            self.broad.query(&ws.centre, &ws.reach, &mut ws.near);
        }
        let before = ws.near.len();
        ws.near.extend(
            self.dynamic
                .iter()
                .copied()
                .filter(|&ci| phase.keep[self.cands[ci].stator]),
        );
        if before > 0 && ws.near.len() > before {
            ws.near.sort_unstable();
        }
    }

    /// Fills `ws.sel` with the pairs of this phase's complementarity problem and their frozen
    /// geometry in `ws.states`, the rotor at `u`; true when there is one (some pair
    /// penetrates).
    pub(crate) fn select(
        &self,
        case: &Case,
        ws: &mut StepWorkspace,
        u: &[f64],
        stators: &[StatorDyn],
        phase: &Phase,
    ) -> bool {
        let disp = |k: usize| phase.deformed.then(|| &stators[k]);
        ws.sel.clear();
        if let Some(list) = &phase.direct {
            return self.select_direct(case, ws, u, stators, phase.deformed, list);
        }
        let mut deepest = 0.0_f64;
        self.gather(ws, u, 0.0, phase);
        ws.stamp += 1;
        for &ci in &ws.near {
            ws.states[ci] = self.pair_at(case, ci, u, disp(self.cands[ci].stator));
            ws.stamped[ci] = ws.stamp;
            deepest = deepest.max(-ws.states[ci].g);
        }
        if deepest <= 0.0 {
            return false;
        }
        // Every pair with g < deepest, from the nodes within r + deepest (the geometry of
        // those the first pass saw is this configuration's already).
        self.gather(ws, u, deepest, phase);
        for &ci in &ws.near {
            if ws.stamped[ci] != ws.stamp {
                ws.states[ci] = self.pair_at(case, ci, u, disp(self.cands[ci].stator));
            }
            if ws.states[ci].g < deepest {
                ws.sel.push(ci);
            }
        }
        true
    }

    /// [`Pairs::select`] over a fixed list of candidates: the same pairs and geometry as the
    /// index would give (the index returns a superset of the pairs within reach, and the pairs
    /// it leaves out have `g ≥` the margin), each pair's geometry computed once a step, and a
    /// node target the squared-distance screen ([`may_reach`]) puts beyond the margin skipped.
    fn select_direct(
        &self,
        case: &Case,
        ws: &mut StepWorkspace,
        u: &[f64],
        stators: &[StatorDyn],
        deformed: bool,
        list: &[usize],
    ) -> bool {
        let disp = |k: usize| deformed.then(|| &stators[k]);
        // Bit i: the pair `list[i]` has its geometry in `ws.states` (lists hold at most
        // DIRECT indexed targets, plus the dynamic ones, which are never screened).
        let mut fresh = 0u128;
        let mut deepest = 0.0_f64;
        for (i, &ci) in list.iter().enumerate() {
            let screen = i < 128;
            if let Some(st) = self.pair_near(case, ci, u, disp(self.cands[ci].stator), 0.0, screen)
            {
                ws.states[ci] = st;
                deepest = deepest.max(-st.g);
                if screen {
                    fresh |= 1 << i;
                }
            }
        }
        if deepest <= 0.0 {
            return false;
        }
        for (i, &ci) in list.iter().enumerate() {
            let screen = i < 128;
            if !screen || fresh & (1 << i) == 0 {
                let stator = disp(self.cands[ci].stator);
                match self.pair_near(case, ci, u, stator, deepest, screen) {
                    Some(st) => ws.states[ci] = st,
                    None => continue,
                }
            }
            if ws.states[ci].g < deepest {
                ws.sel.push(ci);
            }
        }
        true
    }

    /// [`Pairs::pair_at`] of candidate `ci`, or `None` when `screen` and the pair's gap is
    /// certainly at least `margin` (m): a node target beyond [`may_reach`] (rings are never
    /// screened out).
    #[inline]
    fn pair_near(
        &self,
        case: &Case,
        ci: usize,
        u: &[f64],
        stator: Option<&StatorDyn>,
        margin: f64,
        screen: bool,
    ) -> Option<PairState> {
        let c = &self.cands[ci];
        let tg = &case.stators[c.stator].targets[c.target];
        let us = stator.map_or([0.0; 2], |s| s.target_disp(tg.dofs()));
        let uc = self.centre(ci, u);
        if let (true, Target::Node { x0, .. }) = (screen, tg) {
            let d = [x0[0] + us[0] - uc[0], x0[1] + us[1] - uc[1]];
            if !may_reach(d, c.radius, self.offset[c.stator], margin) {
                return None;
            }
        }
        let mut st = pair_state(tg, c.radius, uc, us, self.omega);
        st.g += self.offset[c.stator] + self.worn[ci];
        Some(st)
    }

    /// Smallest exact gap (no frozen normal) of the selected pairs after their correction,
    /// the rotor at `u` and each pair's stator target displaced by `us` (m).
    pub(crate) fn min_gap(
        &self,
        case: &Case,
        sel: &[usize],
        u: &[f64],
        us: &[V2],
        mut min: f64,
    ) -> f64 {
        for (&ci, us) in sel.iter().zip(us) {
            let c = &self.cands[ci];
            let tg = &case.stators[c.stator].targets[c.target];
            min = min.min(
                exact_gap(tg, c.radius, self.centre(ci, u), *us)
                    + self.offset[c.stator]
                    + self.worn[ci],
            );
        }
        min
    }
}
