//! `[thermal]`: the slow rub of the Newkirk effect as the user writes it — the hot-spot model of
//! the rubbing section, its thermal bow, and how the vibration (fast) and the heat (slow) are
//! coupled — and its checks (each error names the file, the dotted key and its line).
//!
//! The model (docs/VALIDATION.md §21 derives it and its linear stability): the friction power
//! at the station's contact points heats the rotor on one side. The first circumferential
//! harmonic of that heat, in the rotor's frame, `Q` (W, a vector: its direction is the hot
//! spot's), drives the temperature difference across the section `ΔT` (K, a vector in the
//! rotor's frame) through two lags: the surface zone `S` follows `G Q` with the heating time
//! `τ_h`, and the section's difference follows `S` with the cooling time `τ_c`:
//!
//! ```text
//! τ_h dS/dt = −S + G Q,      τ_c dΔT/dt = −ΔT + S.
//! ```
//!
//! ΔT bends the shaft with curvature `α ΔT / D` over the heated length `a`. On a Jeffcott rotor
//! `a` is centred at the disk of a simply supported span `L`: the disk's bow
//! `b = α a (2L − a)/(8D) ΔT` (toward the hot side), which rotates with the rotor and loads it
//! as `k b e^{iΩt}`. On an FE rotor `a` is centred at the heated station's node and the
//! curvature loads the shaft elements there with their thermal-strain moments, the rotor on
//! its own bearings ([`crate::model::bow`]); `D` is `diameter` either way — the diameter
//! the hot-spot model's ΔT acts across, not the local element's (one ΔT, one curvature over
//! the heated length, even where the shaft steps).
//!
//! Instead of `gain`, `heating_time` and `cooling_time`, `[thermal.conduction]` gives the
//! section's material ([`ConductionSpec`]): ΔT then follows from the first circumferential
//! harmonic of heat conduction in the solid section of diameter D ([`crate::model::section`]).

use super::validate::checks::positive;
use super::{FeRotorSpec, LoadedScene, RotorSpec};
use crate::error::SceneError;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

fn four() -> usize {
    4
}
fn two_hundred() -> f64 {
    200.0
}

/// `[thermal]`: the Newkirk hot-spot model at one station (module docs).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ThermalSpec {
    /// The station whose rub heats the rotor (its name; default: the first station).
    #[serde(default)]
    pub station: Option<String>,
    /// α (1/K): the shaft's coefficient of thermal expansion (steel: 1.2e-5).
    pub expansion: f64,
    /// D (m): the shaft diameter the temperature difference acts across.
    pub diameter: f64,
    /// a (m): the axial length over which ΔT bends the shaft, centred at the disk (Jeffcott)
    /// or at the heated station's node (FE rotor; within the shaft).
    pub heated_length: f64,
    /// L (m): the bearing span of the Jeffcott rotor (default: `rotor.shaft.length`). Not for
    /// an FE rotor, which stands on its own bearings.
    #[serde(default)]
    pub span: Option<f64>,
    /// G (K/W): the steady temperature difference per watt of the heat's first harmonic (the
    /// hot-spot lags; or `[thermal.conduction]`, not both).
    #[serde(default)]
    pub gain: Option<f64>,
    /// τ_h (s): how fast the surface zone follows the heat input (the hot-spot lags).
    #[serde(default)]
    pub heating_time: Option<f64>,
    /// τ_c (s): how fast the section's temperature difference follows the surface, and cools
    /// (the hot-spot lags).
    #[serde(default)]
    pub cooling_time: Option<f64>,
    /// The section's heat conduction in place of the hot-spot lags (`[thermal.conduction]`,
    /// [`crate::model::section`]): the temperature across the solid section of diameter
    /// `diameter` from its material, its surface cooling and the share of the friction heat
    /// that enters the rotor.
    #[serde(default)]
    pub conduction: Option<ConductionSpec>,
    /// Machine time to run (s).
    pub duration: f64,
    /// The coupling step h (s): the heat is advanced by h after each vibration run of
    /// `revolutions` revolutions, whose steady heat input it holds over h. Default: the
    /// vibration run's own length (every revolution of the machine time integrated: the fully
    /// resolved coupling).
    #[serde(default)]
    pub step: Option<f64>,
    /// Revolutions integrated per coupling step (the last one's heat and 1× vector are taken).
    #[serde(default = "four")]
    pub revolutions: usize,
    /// Revolutions integrated before the first coupling step (default:
    /// `run.transient_revolutions`).
    #[serde(default)]
    pub settle_revolutions: Option<usize>,
    /// |ΔT| (K) above which the spiral is taken to run away: the run stops there and reports
    /// its growth rate.
    #[serde(default = "two_hundred")]
    pub max_temperature_difference: f64,
    /// ΔT at t = 0, `[x, y]` in the rotor's frame (K); S starts equal to it.
    #[serde(default)]
    pub initial: [f64; 2],
}

fn thirty_two() -> usize {
    32
}

/// `[thermal.conduction]`: the heated section as a solid steel (or other) disk whose first
/// circumferential harmonic of temperature diffuses from the rubbing surface
/// ([`crate::model::section`] states the equations): the hot-spot model's gain and two time
/// constants then follow from the material instead of being given.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ConductionSpec {
    /// k (W/(m·K)): the shaft's thermal conductivity (steel: 40–50).
    pub conductivity: f64,
    /// ρ (kg/m³): the shaft's density.
    pub density: f64,
    /// c (J/(kg·K)): the shaft's specific heat (steel: 450–500).
    pub specific_heat: f64,
    /// h (W/(m²·K)): the heat transfer coefficient from the shaft's surface to the gas
    /// around it (0: an adiabatic surface; forced air 20–200).
    #[serde(default)]
    pub surface_coefficient: f64,
    /// η: the share of the friction power that flows into the rotor (0 < η ≤ 1; the rest
    /// heats the stator).
    pub heat_fraction: f64,
    /// Radial finite elements of the section, graded toward the surface (2 … 400).
    #[serde(default = "thirty_two")]
    pub cells: usize,
}

/// The most radial elements a section may have: its modes are found by a dense eigensolver.
pub const MAX_SECTION_CELLS: usize = 400;

/// Checks `[thermal]`: every coefficient, length and time positive (an error names its key),
/// a known station, the heated length within the span (Jeffcott) or the shaft (FE rotor: no
/// `span`), no speed profile.
///
/// # Errors
/// [`SceneError::Invalid`] naming the key.
pub fn validate(ls: &LoadedScene, t: &ThermalSpec) -> Result<(), SceneError> {
    let k = |s: &str| format!("thermal.{s}");
    for (name, v) in [
        ("expansion", t.expansion),
        ("diameter", t.diameter),
        ("heated_length", t.heated_length),
        ("duration", t.duration),
        ("max_temperature_difference", t.max_temperature_difference),
    ] {
        positive(ls, &k(name), v)?;
    }
    for (i, v) in t.initial.iter().enumerate() {
        if !v.is_finite() {
            return Err(ls.invalid(
                &k(&format!("initial.{i}")),
                format!("must be finite, got {v}"),
            ));
        }
    }
    validate_section(ls, t)?;
    if let Some(h) = t.step {
        positive(ls, &k("step"), h)?;
    }
    if t.revolutions == 0 {
        return Err(ls.invalid(&k("revolutions"), "must be at least 1"));
    }
    if ls.scene.stations.is_empty() {
        return Err(ls.invalid(
            "thermal",
            "the rub that heats the rotor needs a `[[station]]` and a stator",
        ));
    }
    if let Some(name) = &t.station {
        if !ls.scene.stations.iter().any(|s| &s.name == name) {
            return Err(ls.invalid(&k("station"), format!("no station named `{name}`")));
        }
    }
    let shaft = match &ls.scene.rotor {
        RotorSpec::Jeffcott(j) => j.shaft.as_ref().map(|s| s.length),
        RotorSpec::Fe(f) => return validate_fe(ls, t, f),
    };
    let span = match (t.span, shaft) {
        (Some(l), _) => {
            positive(ls, &k("span"), l)?;
            l
        }
        (None, Some(l)) => l,
        (None, None) => {
            return Err(ls.invalid(
                &k("span"),
                "give the bearing span L (m): the rotor has no `shaft` table to take it from",
            ))
        }
    };
    if t.heated_length > span {
        return Err(ls.invalid(
            &k("heated_length"),
            format!(
                "the heated length {} m exceeds the span {span} m",
                t.heated_length
            ),
        ));
    }
    no_profile(ls)
}

/// The section's heat model: the three hot-spot lags, each positive, or `[thermal.conduction]`
/// with its material positive, h ≥ 0, 0 < η ≤ 1 and 2 … [`MAX_SECTION_CELLS`] cells — one of
/// the two, not both.
fn validate_section(ls: &LoadedScene, t: &ThermalSpec) -> Result<(), SceneError> {
    let lags = [
        ("gain", t.gain),
        ("heating_time", t.heating_time),
        ("cooling_time", t.cooling_time),
    ];
    let Some(c) = &t.conduction else {
        for (name, v) in lags {
            let Some(v) = v else {
                return Err(ls.invalid(
                    &format!("thermal.{name}"),
                    "missing: give the hot-spot lags `gain`, `heating_time` and `cooling_time`, or the section's conduction `[thermal.conduction]`",
                ));
            };
            positive(ls, &format!("thermal.{name}"), v)?;
        }
        return Ok(());
    };
    if let Some((name, _)) = lags.iter().find(|(_, v)| v.is_some()) {
        return Err(ls.invalid(
            &format!("thermal.{name}"),
            "the section's conduction `[thermal.conduction]` gives the gain and the time constants: remove the hot-spot lags `gain`, `heating_time` and `cooling_time` (or the conduction)",
        ));
    }
    let k = |s: &str| format!("thermal.conduction.{s}");
    for (name, v) in [
        ("conductivity", c.conductivity),
        ("density", c.density),
        ("specific_heat", c.specific_heat),
        ("heat_fraction", c.heat_fraction),
    ] {
        positive(ls, &k(name), v)?;
    }
    super::validate::checks::non_negative(ls, &k("surface_coefficient"), c.surface_coefficient)?;
    if c.heat_fraction > 1.0 {
        return Err(ls.invalid(
            &k("heat_fraction"),
            format!(
                "is the share of the friction heat that enters the rotor, at most 1, got {}",
                c.heat_fraction
            ),
        ));
    }
    if !(2..=MAX_SECTION_CELLS).contains(&c.cells) {
        return Err(ls.invalid(
            &k("cells"),
            format!(
                "must be 2 … {MAX_SECTION_CELLS} (the section's modes are found by a dense eigensolver), got {}",
                c.cells
            ),
        ));
    }
    Ok(())
}

/// A thermal run is at one constant speed.
fn no_profile(ls: &LoadedScene) -> Result<(), SceneError> {
    if ls.scene.run.speed_profile.is_some() {
        return Err(ls.invalid(
            "thermal",
            "a thermal run is at one constant speed: remove `[run.speed_profile]` (or `[thermal]`)",
        ));
    }
    Ok(())
}

/// The FE rotor's part of [`validate`]: no `span`, the heated station's node on the shaft and
/// the heated length, centred there, within the shaft's ends.
fn validate_fe(ls: &LoadedScene, t: &ThermalSpec, f: &FeRotorSpec) -> Result<(), SceneError> {
    if t.span.is_some() {
        return Err(ls.invalid(
            "thermal.span",
            "an FE rotor stands on its own bearings: the bow is the shaft's curvature on them, there is no span to give (remove `thermal.span`)",
        ));
    }
    let (st, key) = match &t.station {
        Some(name) => (
            ls.scene.stations.iter().find(|s| &s.name == name),
            "thermal.station",
        ),
        None => (ls.scene.stations.first(), "station.0.node"),
    };
    let node = st.map_or(0, |s| s.node);
    let node_key = st
        .and_then(|s| ls.scene.stations.iter().position(|o| std::ptr::eq(o, s)))
        .map_or_else(
            || "station.0.node".to_string(),
            |i| format!("station.{i}.node"),
        );
    let z = node_positions(f);
    let Some(&zc) = z.get(node) else {
        return Err(ls.invalid(
            key,
            format!(
                "the heated station's node {node} is not a node of the shaft (nodes 0..={})",
                z.len().saturating_sub(1)
            ),
        ));
    };
    let end = z.last().copied().unwrap_or(0.0);
    let half = 0.5 * t.heated_length;
    if zc - half < -1e-12 * end || zc + half > end * (1.0 + 1e-12) {
        return Err(ls.invalid(
            "thermal.heated_length",
            format!(
                "the heated length {} m centred at the station's node {node} (`{node_key}`, z = {zc} m) runs past the shaft's ends (0 … {end} m)",
                t.heated_length
            ),
        ));
    }
    no_profile(ls)
}

/// The FE rotor's node positions (m) from its shaft segments, each cut into `elements` equal
/// elements (as [`crate::resolve::rotor::fe_rotor`] cuts them).
fn node_positions(f: &FeRotorSpec) -> Vec<f64> {
    let mut z = vec![0.0];
    for seg in &f.shaft {
        let n = seg.elements.max(1);
        let z0 = *z.last().unwrap_or(&0.0);
        z.extend((1..=n).map(|i| z0 + seg.length * i as f64 / n as f64));
    }
    z
}

impl ThermalSpec {
    /// The bearing span L (m): `span`, else the Jeffcott shaft's length (validated present).
    pub fn span_of(&self, rotor: &RotorSpec) -> f64 {
        match (self.span, rotor) {
            (Some(l), _) => l,
            (None, RotorSpec::Jeffcott(j)) => j.shaft.as_ref().map_or(f64::NAN, |s| s.length),
            (None, RotorSpec::Fe(_)) => f64::NAN,
        }
    }

    /// The disk's bow per kelvin of ΔT (m/K): `α a (2L − a) / (8 D)`, the midspan deflection of
    /// a simply supported span L with curvature α ΔT / D over its central length a.
    pub fn bow_per_kelvin(&self, rotor: &RotorSpec) -> f64 {
        let (a, l) = (self.heated_length, self.span_of(rotor));
        self.expansion * a * (2.0 * l - a) / (8.0 * self.diameter)
    }
}
