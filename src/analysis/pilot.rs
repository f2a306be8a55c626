//! What every pilot run shares (the step choice's pilots, [`super::autostep`], and the
//! cut-off's, [`super::cutoff`]): its window and the settings it runs with.

use super::RunSettings;
use crate::time::Scheme;

/// Transient revolutions of a pilot run before its analysed window (started as the run is).
pub const PILOT_TRANSIENT: usize = 10;
/// Analysed revolutions of a pilot run (the shortest window, [`crate::time::plan::WINDOW_MULTIPLE`]).
pub const PILOT_WINDOW: usize = 6;

/// The pilot settings of `s` with `kind` at `scale` × the paper's rule (`StepParams::dt_scale`,
/// no `run.dt`): [`PILOT_WINDOW`] revolutions analysed after [`PILOT_TRANSIENT`], no error
/// estimate, no coexistence check.
pub fn pilot_settings(s: &RunSettings, kind: Scheme, scale: f64) -> RunSettings {
    let mut p = *s;
    p.step.integrator = kind;
    p.step.dt = None;
    p.step.dt_scale = scale;
    p.step.transient_revolutions = PILOT_TRANSIENT;
    p.step.revolutions = PILOT_TRANSIENT + PILOT_WINDOW;
    // Pilots measure the step on their own short window, whatever the run's length.
    p.step.duration = None;
    p.error_estimate = false;
    p.check_coexistence = false;
    p
}
