//! `[stator.wear]`: the wear of a stator's contact nodes by the rub, as the user writes it —
//! Archard's law — and its checks (each error names the file, the dotted key and its line).
//!
//! **Archard's law.** A surface sliding under a normal force `p` over a distance `s` loses the
//! volume `V = k p s`, `k = K/H` the dimensional wear coefficient (m²/N, i.e. m³ per N·m: the
//! dimensionless coefficient K over the softer surface's hardness H; steel on steel 1e-15 …
//! 1e-13, abradable seal coatings up to 1e-10). At a contact node of tributary area `A` (its
//! share of the contact boundary: a 2-D mesh's boundary length times its thickness, a 3-D
//! mesh's boundary area, a rod's cross-section), the surface recedes by
//!
//! ```text
//! Δh = k p |ζ| / A        (m, per step; ζ the slip of the step, docs/STICK.md §1),
//! ```
//!
//! which opens the node's gap by Δh (`time::wear`). The clearance grows where the rotor rubs
//! until, when its orbit stops reaching the worn surface, the rub ends by itself.
//!
//! **Two time scales.** Wear is slow: a seal wears over minutes to hours of rubbing while the
//! vibration changes within a revolution. `run.wear_acceleration` = A multiplies the wear rate
//! (the classic wear magnification): a run of machine time t represents a wear time A t, exact
//! in the limit where the worn depth per revolution is small beside what changes the orbit
//! (docs/VALIDATION.md §23 measures the error against A).

use super::validate::checks::positive;
use super::{LoadedScene, StatorSpec};
use crate::error::SceneError;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// `[stator.wear]`: Archard wear of the stator's contact nodes (module docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WearSpec {
    /// k = K/H (m²/N = m³/(N·m)): Archard's dimensional wear coefficient, the volume worn per
    /// unit normal force and unit sliding distance.
    pub coefficient: f64,
}

/// Checks stator `i`'s `wear`: a positive coefficient, on a stator whose contact nodes have an
/// area (a meshed stator, 2-D with its `thickness`, or a rod), in a run with a speed profile
/// (wear is a transient: it does not settle), and `run.wear_acceleration` positive.
///
/// # Errors
/// [`SceneError::Invalid`] naming the key.
pub fn validate(ls: &LoadedScene, i: usize, stator: &StatorSpec) -> Result<(), SceneError> {
    let Some(w) = stator.wear() else {
        return Ok(());
    };
    let k = format!("stator.{i}.wear");
    positive(ls, &format!("{k}.coefficient"), w.coefficient)?;
    match stator {
        StatorSpec::Rod(_) | StatorSpec::Mesh(_) => {}
        StatorSpec::Ring(_) | StatorSpec::Fe(_) => {
            return Err(ls.invalid(
                &k,
                "wear is at contact nodes with an area: a meshed stator's contact boundary (`kind = \"mesh\"`, a ring as a meshed annulus) or a rod's tip (`kind = \"rod\"`)",
            ))
        }
    }
    if ls.scene.run.speed_profile.is_none() {
        return Err(ls.invalid(
            &k,
            "wear changes the clearance as the rub goes on, so the run never settles: run it as a transient with `[run.speed_profile]` (`kind = \"constant\"` for one speed, its `duration` the machine time)",
        ));
    }
    positive(ls, "run.wear_acceleration", ls.scene.run.wear_acceleration)
}
