//! Admissibility rules that types cannot express, with errors naming file, key and line.
//!
//! [`validate()`] runs every rule in a fixed order (rotor, stations, stators, run, output) and
//! reports the first one broken. The rules that choose between keys or turn a name into
//! something else ([`one_of`], [`at_most_one`], [`station_index`], [`extra_station_index`],
//! [`mesh_plane`], [`output_component`]) return what they chose, so the resolve stage
//! ([`crate::resolve`]) reads its choices from the same code that checked them. They and the
//! checks every rule is made of are [`checks`]; the rules per table are `validate/rotor.rs`,
//! `validate/stator.rs` and `validate/run.rs`.

pub mod checks;
mod rotor;
mod run;
mod stator;

use super::*;
use crate::error::SceneError;
pub use checks::{
    at_most_one, dense_rotor_cost, extra_station_index, mesh_plane, one_of, output_component,
    station_index, DenseCost, OneOf, MAX_DAMPING_RATIO, MAX_DENSE_BYTES, MAX_DENSE_SECONDS,
    MAX_MAGNITUDE, MAX_REVOLUTIONS, MAX_ROD_ELEMENTS, MAX_ROTOR_NODES, MAX_SAMPLES_PER_REV,
    MAX_SWEEP_SPEEDS,
};
pub(crate) use rotor::damping_ratio_bound;
use rotor::*;
use run::*;
use stator::*;

/// Checks every admissibility rule that types cannot express.
pub fn validate(ls: &LoadedScene) -> Result<(), SceneError> {
    let s = &ls.scene;
    match &s.rotor {
        RotorSpec::Jeffcott(j) => validate_jeffcott(ls, j)?,
        RotorSpec::Fe(f) => validate_fe_rotor(ls, f)?,
    }
    validate_stations(ls)?;
    let mut names = std::collections::HashSet::new();
    for (i, stator) in s.stators.iter().enumerate() {
        // Events, outputs and the series name stators: a name says which.
        if stator.name().trim().is_empty() {
            return Err(ls.invalid(
                &format!("stator.{i}.name"),
                "empty name: events, the outputs and the series refer to a stator by it",
            ));
        }
        if !names.insert(stator.name()) {
            return Err(ls.invalid(
                &format!("stator.{i}.name"),
                format!("duplicate stator name `{}`", stator.name()),
            ));
        }
        station_index(ls, i, stator.station())?;
        match stator {
            StatorSpec::Rod(r) => validate_rod(ls, i, r)?,
            StatorSpec::Ring(r) => validate_ring(ls, i, r)?,
            StatorSpec::Fe(f) => validate_fe_stator(ls, i, f)?,
            StatorSpec::Mesh(m) => validate_mesh_stator(ls, i, m)?,
        }
        validate_contact_damping(ls, i, stator)?;
        super::wear::validate(ls, i, stator)?;
        super::abradable::validate(ls, i, stator)?;
    }
    validate_run(ls)?;
    output_component(ls)?;
    validate_series(ls)?;
    validate_unbalance_for_clearance(ls)?;
    if let Some(t) = &ls.scene.thermal {
        super::thermal::validate(ls, t)?;
    }
    // Last: every variant of a parameter study is the scene with one key changed, so the scene
    // itself must be valid first (else its own error would be blamed on the study).
    if let Some(v) = ls.scene.run.sweep.as_ref().and_then(|w| w.vary.as_ref()) {
        validate_vary(ls, v)?;
    }
    if let Some(m) = &ls.scene.run.map {
        validate_map(ls, m)?;
    }
    Ok(())
}

/// A clearance given as δ/|Z0| needs an unbalance response: Σ m_u e ≠ 0. Names the unbalance
/// list when it is empty, else the first zero mass or radius.
fn validate_unbalance_for_clearance(ls: &LoadedScene) -> Result<(), SceneError> {
    let s = &ls.scene;
    let nd = s.stators.iter().any(|st| match st {
        StatorSpec::Rod(r) => r.clearance_nd.is_some(),
        StatorSpec::Ring(r) => r.clearance_nd.is_some(),
        StatorSpec::Mesh(m) => m.clearance_nd.is_some(),
        StatorSpec::Fe(_) => false,
    });
    let unbalance = match &s.rotor {
        RotorSpec::Jeffcott(j) => &j.unbalance,
        RotorSpec::Fe(f) => &f.unbalance,
    };
    if !nd || unbalance.iter().any(|u| u.mass * u.radius != 0.0) {
        return Ok(());
    }
    let why = "a stator's `clearance_nd` is a multiple of |Z0|, the unbalance response, which is 0 without an unbalance: give an unbalance or `clearance` in metres";
    let key = unbalance
        .first()
        .map(|u| {
            let f = if u.mass == 0.0 { "mass" } else { "radius" };
            format!("rotor.unbalance.0.{f}")
        })
        .unwrap_or_else(|| "rotor.unbalance".into());
    Err(ls.invalid(&key, why))
}
