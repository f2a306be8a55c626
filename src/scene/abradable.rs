//! `[stator.abradable]`: an elasto-plastic abradable coating on a stator's contact nodes, as
//! the user writes it, and its checks (each error names the file, the dotted key and its line).
//!
//! **The model** (Legrand, Batailly, Pierre et al., J. Eng. Gas Turbines Power 134, 2012, and
//! JSV 2012: the coating as 1-D elasto-plastic elements in the radial direction). Each contact
//! node carries a radial rod of the coating: thickness `h` (m), Young's modulus `E` (Pa), yield
//! stress `σ_y` (Pa), linear hardening modulus `H` (Pa, ≥ 0), section the node's tributary area
//! `A` (m², the same areas as `[stator.wear]`: a rod's cross-section, a meshed stator's share of
//! its contact boundary). With `d_p ≥ 0` the rod's plastic shortening (m):
//!
//! ```text
//! elastic stiffness       k_a = E A / h                       (N/m, in series with the stator)
//! yield force             f_y(d_p) = A (σ_y + H d_p / h)      (N)
//! normal force            0 ≤ p ≤ f_y(d_p)
//! plastic flow            ḋ_p ≥ 0,  ḋ_p (f_y(d_p) − p) = 0    (d_p never decreases)
//! ```
//!
//! The coating's surface sits at the stator's contact node (the clearance is to the coating)
//! and recedes by `d_p`: the pair's gap opens by `d_p` for good, like a worn depth
//! (`time::abradable`). Its elastic compression `p / k_a` recovers when the force goes.

use super::validate::checks::{non_negative, positive};
use super::{LoadedScene, StatorSpec};
use crate::error::SceneError;
use crate::scene::IntegratorKind;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// `[stator.abradable]`: the elasto-plastic abradable coating of the contact nodes (module
/// docs).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AbradableSpec {
    /// Coating thickness h (m): the length of each node's radial rod of coating.
    pub thickness: f64,
    /// Young's modulus E of the coating (Pa): each node's elastic stiffness is E A / h.
    pub youngs_modulus: f64,
    /// Yield stress σ_y of the coating (Pa): a node's force is at most A σ_y before hardening.
    pub yield_stress: f64,
    /// Linear hardening modulus H (Pa, ≥ 0; 0, the default, is perfectly plastic): the yield
    /// force grows to A (σ_y + H d_p / h) with the plastic shortening d_p.
    #[serde(default)]
    pub hardening_modulus: f64,
}

/// Checks stator `i`'s `abradable`: positive thickness, modulus and yield stress, a hardening
/// modulus ≥ 0, on a stator whose contact nodes have an area (a rod or a meshed stator), in a
/// transient (`[run.speed_profile]`: the coating is cut as the rub goes on), integrated by the
/// explicit schemes (`run.integrator` forward increment or collocated), without stick at the
/// station it faces nor a contact dashpot.
///
/// # Errors
/// [`SceneError::Invalid`] naming the key.
pub fn validate(ls: &LoadedScene, i: usize, stator: &StatorSpec) -> Result<(), SceneError> {
    let Some(a) = stator.abradable() else {
        return Ok(());
    };
    let k = format!("stator.{i}.abradable");
    positive(ls, &format!("{k}.thickness"), a.thickness)?;
    positive(ls, &format!("{k}.youngs_modulus"), a.youngs_modulus)?;
    positive(ls, &format!("{k}.yield_stress"), a.yield_stress)?;
    non_negative(ls, &format!("{k}.hardening_modulus"), a.hardening_modulus)?;
    let stations: Vec<&str> = match stator {
        StatorSpec::Rod(r) => vec![r.station.as_str()],
        StatorSpec::Mesh(m) => std::iter::once(m.station.as_str())
            .chain(m.stations.iter().map(String::as_str))
            .collect(),
        StatorSpec::Ring(_) | StatorSpec::Fe(_) => {
            return Err(ls.invalid(
                &k,
                "an abradable coating is on contact nodes with an area: a meshed stator's contact boundary (`kind = \"mesh\"`, a ring as a meshed annulus) or a rod's tip (`kind = \"rod\"`)",
            ))
        }
    };
    if ls.scene.run.speed_profile.is_none() {
        return Err(ls.invalid(
            &k,
            "the rub cuts the coating and opens the clearance as it goes on, so the run never settles: run it as a transient with `[run.speed_profile]` (`kind = \"constant\"` for one speed, its `duration` the machine time)",
        ));
    }
    if let Some(s @ (IntegratorKind::Newmark | IntegratorKind::GeneralizedAlpha)) =
        ls.scene.run.integrator
    {
        return Err(ls.invalid(
            "run.integrator",
            format!(
                "an abradable coating (`{k}`) is integrated by the explicit schemes (\"forward_increment\", \"collocated\"), not by `{}`",
                s.name()
            ),
        ));
    }
    if let Some(j) = ls
        .scene
        .stations
        .iter()
        .position(|st| st.stick && stations.contains(&st.name.as_str()))
    {
        return Err(ls.invalid(
            &format!("station.{j}.stick"),
            format!("Coulomb friction with stick is not combined with an abradable coating (`{k}`): the coating caps the normal force outside the stick solve; leave one of them out"),
        ));
    }
    if stator.contact_damping().0 > 0.0 {
        return Err(ls.invalid(
            &format!("stator.{i}.contact_damping"),
            format!("a contact dashpot is not combined with an abradable coating (`{k}`): the coating caps the contact force the dashpot adds to; leave one of them out"),
        ));
    }
    Ok(())
}
