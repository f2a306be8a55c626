//! Dry-friction backward whirl and whip (issue 28; docs/STICK.md §4): a run whose stations
//! stick (`station.N.stick`) told by its steady window.
//!
//! * **Dry whirl** — the section rolls on the stator: full annular contact (a contact fraction of
//!   at least [`FULL_CONTACT`], the coexistence check's), the full spectrum's
//!   strongest line backward, and some pair sticking at least [`ROLLING`] of the contact
//!   instants. Its whirl is locked to the rolling speed, `ω = −R Ω/δ` for a rigid stator.
//! * **Dry whip** — the same backward whirl in full contact, but slipping (less than
//!   [`ROLLING`] in stick): the whirl leaves the rolling speed and locks near a natural
//!   frequency of the coupled rotor–stator system.
//!
//! A run without stick is not classified: its friction is permanent slip, so it cannot roll,
//! and its backward whirl (if any) keeps its period label.

use super::coexist::FULL_CONTACT;
use super::whirl::{WhirlDirection, WhirlLines};
use crate::model::Case;
use crate::time::{ContactStats, Record, StepPlan};
use serde::{Deserialize, Serialize};

/// Fraction of the contact instants in stick from which a backward whirl rolls (dry whirl)
/// rather than slips (dry whip).
pub const ROLLING: f64 = 0.5;

/// The dry-friction backward whirl of a run with stick.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DryRub {
    /// Rolling backward whirl (stick).
    Whirl,
    /// Slipping backward whirl (slip).
    Whip,
}

impl DryRub {
    /// The class's key in tables (`sweep.csv`, `map.csv`, `full_waterfall.csv`) and JSON:
    /// "whirl" or "whip".
    pub fn key(self) -> &'static str {
        match self {
            DryRub::Whirl => "whirl",
            DryRub::Whip => "whip",
        }
    }

    /// The regime's name: "dry whirl" or "dry whip".
    pub fn label(self) -> &'static str {
        match self {
            DryRub::Whirl => "dry whirl",
            DryRub::Whip => "dry whip",
        }
    }
}

/// The class of a steady window with contact fraction `contact`, fraction of its contact
/// instants in stick `stick` and whirl `whirl`; `None` when it is not a backward whirl in full
/// annular contact.
pub fn classify(contact: f64, stick: f64, whirl: &WhirlLines) -> Option<DryRub> {
    if contact < FULL_CONTACT
        || whirl.direction != WhirlDirection::Backward
        || whirl.dominant_order >= 0.0
    {
        return None;
    }
    Some(if stick >= ROLLING {
        DryRub::Whirl
    } else {
        DryRub::Whip
    })
}

/// A run of `case` with its steady window's contact statistics `steady` and whirl `whirl`: the
/// fraction of the contact instants in stick and the class — both `None` when no station of
/// the case sticks.
pub fn of_run(
    case: &Case,
    steady: &ContactStats,
    whirl: &WhirlLines,
) -> (Option<f64>, Option<DryRub>) {
    if !case.stations.iter().any(|st| st.stick) {
        return (None, None);
    }
    let stick = steady.stick_fraction();
    (Some(stick), classify(steady.fraction(), stick, whirl))
}

/// Fewest time steps per period of a roll's whirl `−RΩ/δ` below which
/// [`roll_resolution`] warns: the explicit schemes' rolling error is first order in `ωΔt`,
/// the implicit ones' `(ωΔt)²/6` (docs/STICK.md §3.3), so 16 steps a whirl give errors of
/// about 0.4 and 2.6e-2.
pub const ROLL_STEPS: f64 = 16.0;

/// Whether a window whose contact fraction is `contact` and whose contact instants stuck for a
/// fraction `stick` rolls: full annular contact, mostly in stick — [`classify`]'s dry whirl
/// without the whirl's direction, which a whirl beyond the samples' orders aliases.
pub fn rolls(contact: f64, stick: f64) -> bool {
    contact >= FULL_CONTACT && stick >= ROLLING
}

/// Whether a window of `case` whose contact statistics are `stats` rolls ([`rolls`]); false
/// when no station of the case sticks.
pub fn window_rolls(case: &Case, stats: &ContactStats) -> bool {
    case.stations.iter().any(|st| st.stick) && rolls(stats.fraction(), stats.stick_fraction())
}

/// Whether the recorded samples of `rec` from sample `from` on roll ([`rolls`]), counted on
/// the samples (a pair carrying force, a pair in stick); false when no station of `case`
/// sticks or no sample is left.
pub fn record_rolls(case: &Case, rec: &Record, from: usize) -> bool {
    if !case.stations.iter().any(|st| st.stick) || from >= rec.len() {
        return false;
    }
    let (active, sticking) = (&rec.active[from..], &rec.sticking[from..]);
    let contact = active.iter().filter(|a| **a > 0).count();
    let stuck = (active.iter().zip(sticking))
        .filter(|(a, s)| **a > 0 && **s > 0)
        .count();
    contact > 0
        && rolls(
            contact as f64 / active.len() as f64,
            stuck as f64 / contact as f64,
        )
}

/// What a rolling run of `case` at spin `omega` (rad/s) on `plan` cannot resolve, as warnings:
/// for each station with stick and each stator it faces, the roll's whirl `−RΩ/δ` (R the
/// section's radius, δ the stator's clearance) taken in fewer than [`ROLL_STEPS`] steps a
/// period, or beyond the orders the record's samples resolve (half the samples a revolution:
/// its spectra and direction then alias). Empty when the step and the record resolve it.
pub fn roll_resolution(case: &Case, omega: f64, plan: &StepPlan) -> Vec<String> {
    let mut out = Vec::new();
    let w = omega.abs();
    if w == 0.0 || plan.dt <= 0.0 {
        return out;
    }
    let samples = 2.0 * std::f64::consts::PI / (w * plan.dt * plan.record_every.max(1) as f64);
    for st in case
        .stators
        .iter()
        .filter(|s| case.stations[s.station].stick)
    {
        let station = &case.stations[st.station];
        if st.clearance <= 0.0 {
            continue;
        }
        let order = station.radius / st.clearance;
        let steps = 2.0 * std::f64::consts::PI / (order * w * plan.dt);
        let at = format!(
            "station `{}` rolls on stator `{}`: its whirl −R/δ = {order:.4} × the speed, {:.4e} rad/s at Ω = {w:.4e} rad/s",
            station.name,
            st.name,
            order * w
        );
        if steps < ROLL_STEPS {
            out.push(format!(
                "{at}, is taken in {steps:.1} steps a period (Δt = {:.3e} s): the roll's forces and friction carry an error of order (ωΔt)² (implicit) or ωΔt (explicit); give `run.dt` ≤ {:.3e} s ({ROLL_STEPS} steps a whirl)",
                plan.dt,
                2.0 * std::f64::consts::PI / (ROLL_STEPS * order * w)
            ));
        }
        if order > 0.5 * samples {
            out.push(format!(
                "{at}, lies beyond the ±{:.1} orders that {samples:.1} recorded samples a revolution resolve: its spectra alias and its direction may read wrong; give `run.samples_per_rev` ≥ {}",
                0.5 * samples,
                (2.0 * order).ceil() as usize + 1
            ));
        }
    }
    out
}
