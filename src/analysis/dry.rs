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
use crate::time::ContactStats;
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
