//! The record of a step refined after the run ([`super::verify`]): the steps its own error
//! estimate rejected, reported with the run delivered ([`super::SpeedResults::step_refinement`]).

use super::dynamics::Regime;
use serde::{Deserialize, Serialize};

/// One run rejected by its own error estimate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RejectedStep {
    /// Its Δt (s).
    pub dt: f64,
    /// Its Δt as a multiple of the paper's rule (`StepParams::dt_scale`).
    pub dt_scale: f64,
    /// Its estimate, `max(extents_rel, lines_rel)` of its [`super::ErrorEstimate`].
    pub estimate: f64,
    /// Whether its companion found the same Poincaré period.
    pub same_period: bool,
    /// Its regime.
    pub regime: Regime,
    /// Its steps (the main run's, companions excluded).
    pub steps: u64,
    /// Its loop's wall time (s).
    pub wall_s: f64,
}

/// The step refined after the run: the steps rejected and how it ended, reported with the run
/// delivered.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StepRefinement {
    /// The steps rejected, coarsest (the pilots' choice) first.
    pub rejected: Vec<RejectedStep>,
    /// Whether the run delivered meets the tolerance by its own estimate.
    pub met: bool,
    /// Why the refinement stopped before meeting the tolerance: `"bound"` (after
    /// `MAX_STEP_REFINEMENTS` halvings) or `"budget"` (the next step's plan above `run.max_steps`);
    /// `None` when it met the tolerance.
    #[serde(default)]
    pub stopped: Option<String>,
}

impl StepRefinement {
    /// Steps of the rejected runs together (their companions excluded).
    pub fn rejected_steps(&self) -> u64 {
        self.rejected.iter().map(|r| r.steps).sum()
    }
}
