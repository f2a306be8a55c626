//! What the stepper keeps of each instant: the recorded samples, the contact statistics of
//! every instant (per revolution), and the frames handed to a sink.

use super::{Sink, Stepper};
use crate::error::SolveError;
use crate::time::drive::Spin;
use crate::time::frame::{Frame, FrameSink};
use crate::time::loop_rotor::full_displacement;
use crate::time::record::ContactStats;
use crate::time::stator::StatorDyn;
use crate::time::workspace::ForceSet;

impl Stepper<'_> {
    /// Collocated scheme: records tₙ with the static forces plus the forces of the stators
    /// with mass from the step that ended at tₙ, and hands the frame to the sink.
    pub(super) fn record_collocated(
        &mut self,
        sink: &mut Sink<'_>,
        n: usize,
        t: f64,
    ) -> Result<(), SolveError> {
        let ws = &mut self.ws;
        ws.recorded.set_sum(&ws.main, &ws.with_mass);
        for pf in &ws.with_mass_pairs {
            if ws.frame_pairs.len() < ws.frame_pairs.capacity() {
                ws.frame_pairs.push(*pf);
            }
        }
        let active = self.active + ws.with_mass_active;
        self.observe(n, ForceSet::WithMass, active);
        if self.record_due(n) {
            self.record(t, ForceSet::WithMass, active);
        }
        self.emit(sink, n, t)
    }

    /// Whether instant `k` is recorded (`k` a multiple of `plan.record_every`); instants are
    /// asked in order, each once.
    #[inline]
    pub(super) fn record_due(&mut self, k: usize) -> bool {
        debug_assert!(k <= self.next_record);
        if k == self.next_record {
            self.next_record += self.plan.record_every;
            true
        } else {
            false
        }
    }

    /// Records a sample at time `t`: the rotor's current state and the station
    /// forces (`Main`, or the collocated scheme's sum with the stators with mass).
    #[inline]
    pub(super) fn record(&mut self, t: f64, forces: ForceSet, active: usize) {
        let sticking = self.sticking(forces);
        let f = self.ws.instant_forces(forces);
        self.recorder.sample(
            t,
            &self.rotor.u,
            (f, &self.ws.power),
            self.energy,
            (active, sticking),
        );
        if std::mem::take(&mut self.ws.power_set) {
            for p in self.ws.power.iter_mut().flatten() {
                *p = 0.0;
            }
        }
        if self.pairs.any_wear {
            let w = self.wear_state();
            self.recorder.rec.wear.push(w);
        }
        if let Spin::Driven(d) = &self.spin {
            let c = d.cur;
            let td = d.drive_torque(t);
            let rec = &mut self.recorder.rec;
            rec.spin.push([c.phi, c.omega, c.omega_dot, td, d.friction]);
        }
    }

    /// Counts instant tₖ, `k` = `n`, in the contact statistics (the whole run and, for
    /// `plan.steady_from ≤ k < plan.steps`, the analysed steady window): the station forces
    /// of `forces` (what [`Stepper::record`] would record at tₖ), the pairs carrying force and
    /// the smallest gap solved for tₖ, which it resets.
    #[inline]
    pub(super) fn observe(&mut self, n: usize, forces: ForceSet, active: usize) {
        if n == self.boundary {
            self.close_window(n);
        }
        let f = self.ws.instant_forces(forces);
        let force = f.total.first().copied().unwrap_or_default();
        let gap = self.instant_gap;
        self.instant_gap = f64::INFINITY;
        self.stats.min_gap = self.stats.min_gap.min(gap);
        let sticking = self.sticking(forces);
        self.segment
            .observe(n, self.plan.dt, force, (active, sticking), gap);
    }

    /// The pairs in stick at the instant whose forces are `forces`: the step's, or the
    /// collocated scheme's static ones with the stators with mass's.
    #[inline]
    fn sticking(&self, forces: ForceSet) -> usize {
        match forces {
            ForceSet::Main => self.ws.sticking,
            ForceSet::WithMass => self.ws.sticking + self.ws.with_mass_sticking,
        }
    }

    /// The instant that closes the segment opened at instant `from`: the next whole revolution
    /// of the plan, or the plan's end when it comes first.
    pub(super) fn next_boundary(&self, from: usize) -> usize {
        let spr = self.plan.steps_per_rev.max(1);
        if from >= self.plan.steps {
            return usize::MAX;
        }
        ((from / spr + 1) * spr).min(self.plan.steps)
    }

    /// Closes the open segment of contact statistics at instant `n` and opens the next.
    #[cold]
    fn close_window(&mut self, n: usize) {
        let done = std::mem::replace(&mut self.segment, ContactStats::starting_at(n));
        // Sized for the plan up front (and by `extend`): no allocation in the loop.
        self.segments.push(done);
        self.boundary = self.next_boundary(n);
    }

    /// Hands the state at step `n` to the sink when its interval asks for it.
    #[inline]
    pub(super) fn emit(&mut self, sink: &mut Sink<'_>, n: usize, t: f64) -> Result<(), SolveError> {
        match sink.as_mut() {
            Some(s) if s.every() > 0 && n.is_multiple_of(s.every()) && s.wants(n) => {
                self.emit_frame(&mut **s, n, t)
            }
            _ => Ok(()),
        }
    }

    /// Builds the frame of step `n` (massless stators, which keep only their contact DOFs
    /// current, rebuild their field first) and hands it to `sink`.
    #[cold]
    fn emit_frame(&mut self, sink: &mut dyn FrameSink, n: usize, t: f64) -> Result<(), SolveError> {
        for st in self.stators.iter_mut() {
            match st {
                StatorDyn::Massless(c) => c.refresh(),
                StatorDyn::Reduced(r) => r.refresh(),
                StatorDyn::Massive(_) => {}
            }
        }
        sink.frame(&Frame {
            step: n,
            t,
            rotor_u: full_displacement(self.case, &self.rotor.u, &mut self.ws.full_u),
            pairs: &self.ws.frame_pairs,
            spin: self.spin.state(t),
            stators: &self.stators,
            worn: if self.pairs.any_wear {
                &self.pairs.worn
            } else {
                &[]
            },
        })
        .map_err(|e| SolveError::FrameOutput {
            step: n,
            time: t,
            source: Box::new(e),
        })
    }
}
