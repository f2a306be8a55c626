//! What a run keeps: the recorded samples ([`Record`]) and the loop's counters ([`RunStats`]).

use super::workspace::StationForces;
use crate::math::V2;

/// What the run keeps: rotor-station displacements and contact forces on the rotor, every
/// `record_every` steps, plus the massless stators' elastic energy.
#[derive(Debug, Clone, Default)]
pub struct Record {
    /// Number of stations.
    pub nstations: usize,
    /// Sample times (s).
    pub t: Vec<f64>,
    /// Station displacements `[x, y]` per sample and station (m), sample-major.
    pub disp: Vec<V2>,
    /// Displacement `[x, y]` of the observed node ([`crate::model::Case::observed_node`]) per
    /// sample (m).
    pub observed: Vec<V2>,
    /// Total contact force on each station `[Fx, Fy]` (N), sample-major.
    pub force: Vec<V2>,
    /// Normal part of the contact force on each station (N), sample-major.
    pub force_normal: Vec<V2>,
    /// Friction power dissipated at each station's contacts (W), sample-major: `Σ t ζ/Δt` over
    /// its pairs of the step ending at the sample, `t` the tangential force and `ζ` the slip
    /// of the section's surface over the stator's material point (docs/STICK.md §1) — 0 in
    /// stick.
    pub friction_power: Vec<f64>,
    /// Elastic energy stored in massless stators (J) per sample.
    pub stator_energy: Vec<f64>,
    /// Active pairs (carrying force) per sample.
    pub active: Vec<u32>,
    /// Pairs in stick per sample (`station.N.stick`, docs/STICK.md): 0 without stick, and at
    /// every instant a pair slips.
    pub sticking: Vec<u32>,
    /// A driven rotor's spin per sample: `[φ (rad), Ω (rad/s), Ω̇ (rad/s²), drive torque
    /// T_d (N·m), rub friction torque Σ R μ p (N·m)]` (`time::drive`); empty otherwise.
    pub spin: Vec<[f64; 5]>,
    /// With wear (`[stator.wear]`) or an abradable coating (`[stator.abradable]`), per sample:
    /// the volume removed so far — worn and cut off the coatings — (m³) and the largest depth a
    /// target receded (m); empty otherwise.
    pub wear: Vec<[f64; 2]>,
    /// With wear or a coating, at the run's end: the depth every candidate pair's target
    /// receded (m, worn and abraded), in the candidates' order — stator by stator, target by
    /// target; empty otherwise.
    pub worn: Vec<f64>,
    /// With a coating, at the run's end: the plastic shortening `d_p` of every candidate pair's
    /// coating (m, in the candidates' order; part of `worn`); empty otherwise.
    pub abraded: Vec<f64>,
    /// With a coating, at the run's end: the volume cut off the coatings (m³) and the plastic
    /// work done on them (J, `Σ p Δd_p`); zeros otherwise.
    pub abradable: [f64; 2],
}

impl Record {
    fn with_capacity(nstations: usize, samples: usize) -> Self {
        Self {
            nstations,
            t: Vec::with_capacity(samples),
            disp: Vec::with_capacity(samples * nstations),
            observed: Vec::with_capacity(samples),
            force: Vec::with_capacity(samples * nstations),
            force_normal: Vec::with_capacity(samples * nstations),
            friction_power: Vec::with_capacity(samples * nstations),
            stator_energy: Vec::with_capacity(samples),
            active: Vec::with_capacity(samples),
            sticking: Vec::with_capacity(samples),
            spin: Vec::new(),
            wear: Vec::new(),
            worn: Vec::new(),
            abraded: Vec::new(),
            abradable: [0.0; 2],
        }
    }
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }
    /// True when nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
    /// Displacement of station `s` at sample `i`.
    pub fn disp_at(&self, i: usize, s: usize) -> V2 {
        self.disp[i * self.nstations + s]
    }
    /// Contact force on station `s` at sample `i`.
    pub fn force_at(&self, i: usize, s: usize) -> V2 {
        self.force[i * self.nstations + s]
    }
    /// Friction power dissipated at station `s` at sample `i` (W; 0 when not recorded).
    pub fn friction_power_at(&self, i: usize, s: usize) -> f64 {
        self.friction_power
            .get(i * self.nstations + s)
            .copied()
            .unwrap_or(0.0)
    }
}

/// Counters of a finished run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunStats {
    /// Steps taken.
    pub steps: usize,
    /// Wall time of the loop (s).
    pub wall_s: f64,
    /// Most negative gap after correction over the run (m); ≥ 0 means no penetration, NaN when
    /// no contact problem was ever solved.
    pub min_gap: f64,
    /// Largest number of simultaneously active pairs.
    pub max_active: usize,
    /// Steps with at least one active pair.
    pub contact_steps: usize,
    /// Total principal pivots of the complementarity solves.
    pub pivots: usize,
    /// Contact solves with stick whose friction states the active set did not settle, solved
    /// instead by nonsmooth Gauss–Seidel sweeps (`contact::coulomb`; docs/STICK.md §2).
    #[serde(default)]
    pub friction_sweep_solves: usize,
    /// Entries of the massless stators' compliance `K⁻¹` the loop read (the flexibility blocks
    /// of the pairs entering its contact problems — four entries per 2 × 2 block, one block of
    /// each symmetric pair read, the other its transpose — and the displacements at their
    /// pairs): the work of the stator side of the contact, which grows with the pairs in
    /// contact and not with the mesh. The column solves (once per touched node, shared by later
    /// runs) and frames' field rebuilds are not counted.
    #[serde(default)]
    pub stator_reads: u64,
    /// Compliance columns of massless stators this run computed (one per contact DOF first
    /// touched that no earlier run of the stator had computed; a batch's neighbours included)
    /// and the wall time they took (s, within `wall_s`).
    #[serde(default)]
    pub columns: u64,
    /// Wall time of those columns (s).
    #[serde(default)]
    pub columns_s: f64,
    /// Energy taken by the contact dashpots over the run (J, `contact_damping`): Σ over steps
    /// and pairs of `D Δd` (normal) and `c (a·v)² Δt` (tangential, mode `"full"`).
    #[serde(default)]
    pub dashpot_energy: f64,
    /// Contact over every instant tₖ = kΔt of the whole run, k = 0 … `steps`.
    pub whole: ContactStats,
    /// Contact over every instant of the analysed steady window, k = `plan.steady_from` …
    /// `steps − 1` — the instants whose samples the analysis reads after the transient.
    pub steady: ContactStats,
}

/// Contact statistics of a window of instants tₖ = kΔt, taken at every step (not from the
/// recorded samples, which keep one step in `record_every`).
///
/// An instant's contact state is what a sample taken at tₖ would record: forward increment,
/// the forces after the correction of the step that ends at tₖ; collocated, the massless
/// stators' static forces at tₖ plus the forces of the stators with mass from the step that
/// ends at tₖ. Its gaps are the exact post-correction gaps of the pairs solved for tₖ.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ContactStats {
    /// First instant index of the window (tₖ = kΔt).
    pub from_step: usize,
    /// Instants observed.
    pub instants: usize,
    /// Instants with at least one pair carrying force.
    pub contact_instants: usize,
    /// Instants with at least one pair sticking (`station.N.stick`; docs/STICK.md).
    #[serde(default)]
    pub stick_instants: usize,
    /// Largest magnitude of the contact force on station 0 (N), 0 without contact.
    pub force_max: f64,
    /// Time of `force_max` (s); 0 without contact.
    pub force_max_time: f64,
    /// Largest penetration `max(0, −g)` over the post-correction gaps of every pair solved (m).
    pub penetration_max: f64,
    /// Largest number of pairs carrying force at one instant.
    pub active_max: usize,
}

impl ContactStats {
    /// An empty window starting at instant `from_step`.
    pub fn starting_at(from_step: usize) -> Self {
        Self {
            from_step,
            ..Self::default()
        }
    }

    /// Fraction of the window's instants in contact at which some pair stuck (0 without
    /// contact).
    pub fn stick_fraction(&self) -> f64 {
        if self.contact_instants == 0 {
            0.0
        } else {
            self.stick_instants as f64 / self.contact_instants as f64
        }
    }

    /// Fraction of the window's instants in contact (0 for an empty window).
    pub fn fraction(&self) -> f64 {
        if self.instants == 0 {
            0.0
        } else {
            self.contact_instants as f64 / self.instants as f64
        }
    }

    /// The statistics of this window followed by the adjacent window `later`.
    pub fn merge(self, later: Self) -> Self {
        let (force_max, force_max_time) = if later.force_max > self.force_max {
            (later.force_max, later.force_max_time)
        } else {
            (self.force_max, self.force_max_time)
        };
        Self {
            from_step: self.from_step,
            instants: self.instants + later.instants,
            contact_instants: self.contact_instants + later.contact_instants,
            stick_instants: self.stick_instants + later.stick_instants,
            force_max,
            force_max_time,
            penetration_max: self.penetration_max.max(later.penetration_max),
            active_max: self.active_max.max(later.active_max),
        }
    }

    /// Adds instant tₖ = kΔt, `k` = `n`, `dt` = Δt (s): the force on station 0 `[Fx, Fy]` (N),
    /// the pairs carrying force and those sticking, and the smallest post-correction gap of
    /// the instant (m; +∞ when no pair was solved).
    #[inline]
    pub(crate) fn observe(
        &mut self,
        n: usize,
        dt: f64,
        force: V2,
        (active, sticking): (usize, usize),
        gap: f64,
    ) {
        self.instants += 1;
        if active > 0 {
            self.contact_instants += 1;
            self.active_max = self.active_max.max(active);
        }
        if sticking > 0 {
            self.stick_instants += 1;
        }
        // Squares: no square root on the instants that set no new peak.
        let f2 = force[0] * force[0] + force[1] * force[1];
        if f2 > self.force_max * self.force_max {
            self.force_max = f2.sqrt();
            self.force_max_time = n as f64 * dt;
        }
        if -gap > self.penetration_max {
            self.penetration_max = -gap;
        }
    }
}

/// Fills a [`Record`] sized for the whole run up front, so recording never allocates.
#[derive(Debug)]
pub(crate) struct Recorder {
    /// Rotor DOFs `[x, y]` of each station's node.
    station_dofs: Vec<[usize; 2]>,
    /// Rotor DOFs of the observed node.
    observed: [usize; 2],
    /// Rotor DOFs recorded as "station 0" when the case has no station.
    fallback: [usize; 2],
    pub(crate) rec: Record,
}

impl Recorder {
    /// A recorder for `samples` samples of `nstations` stations (at least one slot).
    pub(crate) fn new(
        station_dofs: Vec<[usize; 2]>,
        observed: [usize; 2],
        fallback: [usize; 2],
        samples: usize,
    ) -> Self {
        let nst = station_dofs.len().max(1);
        Self {
            station_dofs,
            observed,
            fallback,
            rec: Record::with_capacity(nst, samples),
        }
    }

    /// Room for `more` samples beyond those already planned (a run lengthened in chunks).
    pub(crate) fn reserve(&mut self, more: usize) {
        let rec = &mut self.rec;
        let nst = rec.nstations;
        rec.t.reserve(more);
        rec.disp.reserve(more * nst);
        rec.observed.reserve(more);
        rec.force.reserve(more * nst);
        rec.force_normal.reserve(more * nst);
        rec.friction_power.reserve(more * nst);
        rec.stator_energy.reserve(more);
        rec.active.reserve(more);
        rec.sticking.reserve(more);
    }

    /// Appends one sample: time `t` (s), the rotor DOF vector, the contact force and its normal
    /// part on each station (`forces`, N), the friction power on each station (W, the sum of
    /// the two `power` vectors), the massless stators' elastic energy (J), the pairs carrying
    /// force and those of them in stick.
    pub(crate) fn sample(
        &mut self,
        t: f64,
        rotor_u: &[f64],
        (forces, power): (&StationForces, &[Vec<f64>; 2]),
        energy: f64,
        (active, sticking): (usize, usize),
    ) {
        let (force, force_normal) = (&forces.total, &forces.normal);
        let rec = &mut self.rec;
        rec.t.push(t);
        let o = self.observed;
        rec.observed.push([rotor_u[o[0]], rotor_u[o[1]]]);
        for (s, d) in self.station_dofs.iter().enumerate() {
            rec.disp.push([rotor_u[d[0]], rotor_u[d[1]]]);
            rec.force.push(force[s]);
            rec.force_normal.push(force_normal[s]);
            rec.friction_power.push(power[0][s] + power[1][s]);
        }
        if self.station_dofs.is_empty() {
            let d = self.fallback;
            rec.disp.push([rotor_u[d[0]], rotor_u[d[1]]]);
            rec.force.push([0.0; 2]);
            rec.force_normal.push([0.0; 2]);
            rec.friction_power.push(0.0);
        }
        rec.stator_energy.push(energy);
        rec.active.push(active as u32);
        rec.sticking.push(sticking as u32);
    }
}
