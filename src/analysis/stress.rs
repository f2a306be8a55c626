//! Stator stress and strain during a run (the paper's Fig. 10).
//!
//! [`StressProbe`] is a [`FrameSink`]: every `every` steps it takes each stator's displacement
//! from the frame (massless stators rebuild theirs from the contact forces, one solve) and
//! records the largest element stress and strain and the total normal contact force on it.
//! Element stress follows [`StatorModel::element_forces`]: the axial stress of bars and frames
//! (sign kept: tension positive) and the von Mises stress at the centroid of 2-D and 3-D cells.
//! Strain is stress over the element's Young's modulus (axial strain of bars; the von Mises
//! equivalent strain σ_vm/E of continuum cells). The field of the instant of largest stress is
//! kept for a picture.
//!
//! The command layer builds the probe from a prepared run ([`StressProbe::for_run`]) and
//! attaches it to [`Prepared::run`]; nothing of the normal run changes.

use super::Prepared;
use crate::error::Result;
use crate::model::stator::{StatorElement, StatorModel};
use crate::time::{Frame, FrameSink, StepPlan};

/// One stator's history.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct StressTrace {
    /// Stator index.
    pub stator: usize,
    /// Stator name.
    pub name: String,
    /// Sample times (s).
    pub t: Vec<f64>,
    /// Total normal contact force on the stator, Σ p (N).
    pub force: Vec<f64>,
    /// Element stress of largest magnitude (Pa): signed axial stress of a bar or frame, von
    /// Mises stress of a cell.
    pub stress: Vec<f64>,
    /// Strain of that element: stress / E.
    pub strain: Vec<f64>,
    /// Index of that element.
    pub element: Vec<usize>,
    /// Element stresses (Pa) at the instant of largest |stress|.
    pub peak_field: Vec<f64>,
    /// Time of that instant (s).
    pub peak_time: f64,
    /// Stator nodes in contact at that instant.
    pub peak_contacts: Vec<usize>,
}

impl StressTrace {
    /// Largest |stress| over the trace (Pa; 0 when empty).
    pub fn peak_stress(&self) -> f64 {
        self.stress.iter().fold(0.0_f64, |m, s| m.max(s.abs()))
    }
    /// Largest |strain| over the trace (0 when empty).
    pub fn peak_strain(&self) -> f64 {
        self.strain.iter().fold(0.0_f64, |m, s| m.max(s.abs()))
    }
    /// Mean total normal contact force over the samples (N; 0 when empty).
    pub fn mean_force(&self) -> f64 {
        self.force.iter().sum::<f64>() / self.force.len().max(1) as f64
    }
}

/// Young's modulus of an element (Pa), NaN for springs.
fn modulus(el: &StatorElement) -> f64 {
    match el {
        StatorElement::Bar { youngs_modulus, .. } => *youngs_modulus,
        StatorElement::Frame { section, .. } => section.youngs_modulus,
        StatorElement::Solid2 { material, .. } => material.youngs_modulus,
        StatorElement::Solid3 { material, .. } => material.youngs_modulus,
        StatorElement::Spring { .. } => f64::NAN,
    }
}

/// Records the stress of every stator every `every` steps.
pub struct StressProbe<'a> {
    stators: &'a [StatorModel],
    every: usize,
    start: f64,
    peak: Vec<f64>,
    /// One trace per stator.
    pub traces: Vec<StressTrace>,
}

impl<'a> StressProbe<'a> {
    /// A probe over `stators`, sampling every `every` steps from time `start` (s) on.
    pub fn new(stators: &'a [StatorModel], every: usize, start: f64) -> Self {
        Self {
            stators,
            every,
            start,
            peak: vec![-1.0; stators.len()],
            traces: stators
                .iter()
                .enumerate()
                .map(|(i, s)| StressTrace {
                    stator: i,
                    name: s.name.clone(),
                    peak_time: f64::NAN,
                    ..Default::default()
                })
                .collect(),
        }
    }
}

impl FrameSink for StressProbe<'_> {
    fn every(&self) -> usize {
        self.every
    }
    fn frame(&mut self, f: &Frame<'_>) -> Result<()> {
        if f.t < self.start {
            return Ok(());
        }
        for (k, s) in self.stators.iter().enumerate() {
            let forces = s.element_forces(f.stator_u(k));
            let (mut best, mut at) = (0.0_f64, usize::MAX);
            for (e, (_, st)) in forces.iter().enumerate() {
                if st.is_finite() && st.abs() > best.abs() {
                    best = *st;
                    at = e;
                }
            }
            let tr = &mut self.traces[k];
            let p: f64 = f.pairs.iter().filter(|q| q.stator == k).map(|q| q.p).sum();
            tr.t.push(f.t);
            tr.force.push(p);
            tr.stress.push(best);
            tr.strain.push(if at == usize::MAX {
                0.0
            } else {
                best / modulus(&s.elements[at])
            });
            tr.element.push(at);
            if best.abs() > self.peak[k] {
                self.peak[k] = best.abs();
                tr.peak_field = forces.iter().map(|x| x.1).collect();
                tr.peak_time = f.t;
                tr.peak_contacts = f
                    .pairs
                    .iter()
                    .filter(|q| q.stator == k && q.p > 0.0)
                    .map(|q| q.node)
                    .collect();
            }
        }
        Ok(())
    }
}

/// Stress histories of one speed.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StressResults {
    /// ω/ω_n.
    pub speed_ratio: f64,
    /// ω (rad/s).
    pub omega: f64,
    /// The step plan.
    pub plan: StepPlan,
    /// One trace per stator, over the last `window` revolutions.
    pub traces: Vec<StressTrace>,
}

impl<'a> StressProbe<'a> {
    /// The probe of a prepared run: `per_rev` samples per revolution over the last `window`
    /// revolutions of the plan (the whole run when `window` is 0 or not shorter than it).
    pub fn for_run(prep: &'a Prepared, per_rev: usize, window: usize) -> Self {
        let every = (prep.plan.steps_per_rev / per_rev.max(1)).max(1);
        let revs = prep.plan.steps / prep.plan.steps_per_rev.max(1);
        let start = if window == 0 || window >= revs {
            0.0
        } else {
            (revs - window) as f64 * 2.0 * std::f64::consts::PI / prep.omega
        };
        Self::new(&prep.case.stators, every, start)
    }
}

impl StressResults {
    /// The histories a probe recorded during the run of `prep`.
    pub fn new(prep: &Prepared, probe: StressProbe<'_>) -> Self {
        Self {
            speed_ratio: prep.speed_ratio,
            omega: prep.omega,
            plan: prep.plan,
            traces: probe.traces,
        }
    }
}
