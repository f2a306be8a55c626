//! A run at a pilot speed started from the state the chosen scheme's pilots ended in
//! ([`start_from_pilot`]): the pilots settled the response there, so the run need not
//! integrate that settling again; its steady-state test still ends its transient.

use super::PILOT_RESETTLE;
use crate::analysis::RunSettings;
use crate::time::Initial;

/// The disk's state `[x, y]`, `[vx, vy]` at the end of the finest pilot at a pilot speed ν.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PilotStart {
    /// ν = ω/ω_n of the pilots.
    pub speed_ratio: f64,
    /// The state (m, m/s), at a whole revolution: the unbalance at its phase of t = 0.
    pub initial: Initial,
}

/// Transient revolutions of a run that starts from its speed's pilot state: the restart at the
/// run's step settles in them (as a pilot's does, [`PILOT_RESETTLE`]), and the steady-state
/// test on the analysed window goes on from there as on any run.
pub const RESTART_TRANSIENT: usize = PILOT_RESETTLE;

/// The pilot state `s`'s choice kept at ν = `speed_ratio`, if any.
pub fn pilot_start(s: &RunSettings, speed_ratio: f64) -> Option<Initial> {
    let c = s.choice.as_ref()?;
    let p = c
        .starts
        .iter()
        .flatten()
        .find(|p| p.speed_ratio == speed_ratio)?;
    Some(p.initial)
}

/// `s` for the run at ν = `speed_ratio`: where the choice kept a pilot state at that speed
/// ([`pilot_start`]), the run starts from it instead of integrating the settling the pilots
/// already did: where its transient adapts (`run.max_transient_revolutions` above it), cut to
/// at most [`RESTART_TRANSIENT`] revolutions, the window as long as before, and the
/// steady-state test still decides where the transient ends (`Prepared::run`); a fixed
/// transient (a reference run's) is kept. Otherwise, and for a fixed window (`run.duration`),
/// `s` unchanged.
pub fn start_from_pilot(s: &RunSettings, speed_ratio: f64) -> RunSettings {
    let mut out = *s;
    if s.step.duration.is_some() {
        // A fixed window (`run.duration`) starts from the scene's initial state at t = 0.
        return out;
    }
    if let Some(init) = pilot_start(s, speed_ratio) {
        let t = s.step.transient_revolutions;
        let cut = if s.max_transient_revolutions > t {
            t.min(RESTART_TRANSIENT)
        } else {
            t
        };
        out.initial = init;
        out.step.transient_revolutions = cut;
        out.step.revolutions = s.step.revolutions.saturating_sub(t - cut);
    }
    out
}
