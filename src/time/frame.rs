//! Full-state frames handed to sinks (VTK/HDF5 writers, stress probes) during a run.

use super::stator::StatorDyn;
use crate::math::V2;

/// Force of one active contact pair in a frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairForce {
    /// Station index.
    pub station: usize,
    /// Stator index.
    pub stator: usize,
    /// Stator node of the target (ring targets: 0).
    pub node: usize,
    /// Unit normal from the section centre toward the stator.
    pub n: V2,
    /// Normal force p ≥ 0 (N, compression).
    pub p: f64,
    /// Force on the stator node `(n + μ a) p` (N); the rotor section gets its opposite.
    pub force: V2,
}

/// The full state at one instant, handed to a [`FrameSink`] (VTK/HDF5 writers).
pub struct Frame<'a> {
    /// Step index.
    pub step: usize,
    /// Time (s).
    pub t: f64,
    /// Rotor DOF vector (m, rad).
    pub rotor_u: &'a [f64],
    /// Pairs in contact at this instant.
    pub pairs: &'a [PairForce],
    /// Spin state at `t` of a run whose speed varies (φ, Ω, Ω̇ of the speed profile or of a
    /// driven rotor's spin DOF); `None` at constant speed, where φ = Ω t.
    pub spin: Option<crate::model::SpinState>,
    pub(crate) stators: &'a [StatorDyn],
    /// With wear (`[stator.wear]`): the worn depth of every contact target so far (m), stator
    /// by stator, target by target; empty otherwise.
    pub worn: &'a [f64],
}

impl Frame<'_> {
    /// Free-DOF displacement vector of stator `k` (m), in the numbering of
    /// [`crate::model::StatorModel::node_dofs`].
    pub fn stator_u(&self, k: usize) -> &[f64] {
        match &self.stators[k] {
            StatorDyn::Massless(c) => &c.u,
            StatorDyn::Massive(b) => &b.u,
            StatorDyn::Reduced(r) => &r.field,
        }
    }
}

/// Receives frames during integration, every [`FrameSink::every`] steps (state at that step).
/// Writers stream to disk from here, so memory does not grow with the run. Sinks are attached
/// by the caller (the command layer); they never drive a run.
pub trait FrameSink {
    /// Interval in steps (0: never called).
    fn every(&self) -> usize;
    /// Consumes one frame; an error stops the run (reported with the frame's step and time).
    fn frame(&mut self, frame: &Frame<'_>) -> crate::error::Result<()>;
    /// Whether the frame of `step` (a multiple of [`FrameSink::every`]) is used at all; when
    /// false the loop builds no frame (massless stators rebuild no field). Default: true.
    fn wants(&self, step: usize) -> bool {
        let _ = step;
        true
    }
}
