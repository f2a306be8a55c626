//! What a run keeps: the recorded samples ([`Record`]) and the loop's counters ([`RunStats`]).

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
    /// Elastic energy stored in massless stators (J) per sample.
    pub stator_energy: Vec<f64>,
    /// Active pairs per sample.
    pub active: Vec<u32>,
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
            stator_energy: Vec::with_capacity(samples),
            active: Vec::with_capacity(samples),
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
}

/// Counters of a finished run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct RunStats {
    /// Steps taken.
    pub steps: usize,
    /// Wall time of the loop (s).
    pub wall_s: f64,
    /// Most negative gap after correction over the run (m); ≥ 0 means no penetration.
    pub min_gap: f64,
    /// Largest number of simultaneously active pairs.
    pub max_active: usize,
    /// Steps with at least one active pair.
    pub contact_steps: usize,
    /// Total principal pivots of the complementarity solves.
    pub pivots: usize,
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

    /// Appends one sample: time `t` (s), the rotor DOF vector, the contact force and its normal
    /// part on each station (N), the massless stators' elastic energy (J), the active pairs.
    pub(crate) fn sample(
        &mut self,
        t: f64,
        rotor_u: &[f64],
        force: &[V2],
        force_normal: &[V2],
        energy: f64,
        active: usize,
    ) {
        let rec = &mut self.rec;
        rec.t.push(t);
        let o = self.observed;
        rec.observed.push([rotor_u[o[0]], rotor_u[o[1]]]);
        for (s, d) in self.station_dofs.iter().enumerate() {
            rec.disp.push([rotor_u[d[0]], rotor_u[d[1]]]);
            rec.force.push(force[s]);
            rec.force_normal.push(force_normal[s]);
        }
        if self.station_dofs.is_empty() {
            let d = self.fallback;
            rec.disp.push([rotor_u[d[0]], rotor_u[d[1]]]);
            rec.force.push([0.0; 2]);
            rec.force_normal.push([0.0; 2]);
        }
        rec.stator_energy.push(energy);
        rec.active.push(active as u32);
    }
}
