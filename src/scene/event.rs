//! `[[run.event]]`: what happens at a moment of a transient run — a sudden unbalance (a blade
//! lost) or a stator's clearance changing — and its checks (each error names the file, the
//! dotted key and its line).

use super::validate::checks::{finite, non_negative, positive};
use super::{LoadedScene, RotorSpec, SpeedProfileSpec};
use crate::error::SceneError;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// What an event does (`run.event.N.kind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum EventKind {
    /// An unbalance `mass` × `radius` at `phase_deg` on rotor `node` appears at `time`, as a
    /// step or growing linearly over `duration` (a blade-off).
    Unbalance,
    /// Stator `stator`'s clearance goes to `clearance` (m) at `time`, as a step or linearly
    /// over `duration`.
    Clearance,
}

/// `[[run.event]]`: one scheduled change of a transient run.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EventSpec {
    /// Unbalance or clearance.
    pub kind: EventKind,
    /// t₀ (s from the run's start), finite, ≥ 0.
    pub time: f64,
    /// The change's length (s): 0 (default) a step, else a linear ramp over t₀ … t₀ + duration.
    #[serde(default)]
    pub duration: f64,
    /// Unbalance: the rotor node (default 0; a Jeffcott rotor has node 0 only).
    #[serde(default)]
    pub node: usize,
    /// Unbalance: the mass (kg) lost or added.
    pub mass: Option<f64>,
    /// Unbalance: its radius, the eccentricity (m).
    pub radius: Option<f64>,
    /// Unbalance: its angle from +x at φ = 0 (degrees, counter-clockwise from +z).
    #[serde(default)]
    pub phase_deg: f64,
    /// Clearance: the stator's name.
    pub stator: Option<String>,
    /// Clearance: the new radial clearance (m), > 0.
    pub clearance: Option<f64>,
}

/// The length (s) of a profile the scene's checks accepted.
fn profile_length(p: &SpeedProfileSpec) -> Option<f64> {
    use super::ProfileKind as K;
    let hold = p.hold;
    match p.kind {
        K::Constant | K::Driven => p.duration,
        K::Ramp => match (p.duration, p.acceleration, p.from, p.to) {
            (Some(d), _, _, _) => Some(d + hold),
            (None, Some(a), Some(f), Some(t)) => Some((t - f) / a + hold),
            _ => None,
        },
        K::Table => p.points.as_ref()?.last().map(|l| l[0] + hold),
    }
}

/// Checks `[[run.event]]`: only with `[run.speed_profile]`; times finite, ≥ 0 and the whole
/// change inside the run (`time + duration ≤` the profile's length); a duration finite and
/// ≥ 0; an unbalance's node on the rotor, a positive mass and radius, a finite phase; a
/// clearance event's stator named in `[[stator]]` and a positive clearance; the keys of the
/// other kind absent.
pub fn validate(ls: &LoadedScene, events: &[EventSpec]) -> Result<(), SceneError> {
    if events.is_empty() {
        return Ok(());
    }
    let Some(profile) = &ls.scene.run.speed_profile else {
        return Err(ls.invalid(
            "run.event",
            "events happen in a transient run: add `[run.speed_profile]` (a constant profile for a constant speed)",
        ));
    };
    let length = profile_length(profile).unwrap_or(f64::INFINITY);
    let nodes = match &ls.scene.rotor {
        RotorSpec::Jeffcott(_) => 1,
        RotorSpec::Fe(f) => 1 + f.shaft.iter().map(|s| s.elements).sum::<usize>(),
    };
    for (i, e) in events.iter().enumerate() {
        let k = |s: &str| format!("run.event.{i}.{s}");
        if !(e.time.is_finite() && e.time >= 0.0) {
            return Err(ls.invalid(
                &k("time"),
                format!("must be a finite time ≥ 0 (s), got {}", e.time),
            ));
        }
        non_negative(ls, &k("duration"), e.duration)?;
        if e.time + e.duration > length {
            return Err(ls.invalid(
                &k("time"),
                format!(
                    "the event ({} s + {} s) ends after the run, whose profile lasts {length} s",
                    e.time, e.duration
                ),
            ));
        }
        match e.kind {
            EventKind::Unbalance => validate_unbalance_event(ls, i, e, nodes)?,
            EventKind::Clearance => validate_clearance_event(ls, i, e)?,
        }
    }
    Ok(())
}

/// The first of `keys` given (`true`) for an event of `kind`: an error, it does not apply.
fn unused_keys(
    ls: &LoadedScene,
    i: usize,
    keys: &[(&str, bool)],
    kind: &str,
) -> Result<(), SceneError> {
    match keys.iter().find(|(_, g)| *g) {
        Some((key, _)) => Err(ls.invalid(
            &format!("run.event.{i}.{key}"),
            format!("does not apply to kind = \"{kind}\""),
        )),
        None => Ok(()),
    }
}

/// Event `i` of kind `unbalance`: no clearance keys, a node on the rotor (of `nodes`), a
/// positive mass and radius, a finite phase.
fn validate_unbalance_event(
    ls: &LoadedScene,
    i: usize,
    e: &EventSpec,
    nodes: usize,
) -> Result<(), SceneError> {
    let k = |s: &str| format!("run.event.{i}.{s}");
    unused_keys(
        ls,
        i,
        &[
            ("stator", e.stator.is_some()),
            ("clearance", e.clearance.is_some()),
        ],
        "unbalance",
    )?;
    if e.node >= nodes {
        return Err(ls.invalid(
            &k("node"),
            format!(
                "node {} does not exist (the rotor has nodes 0..={})",
                e.node,
                nodes - 1
            ),
        ));
    }
    let need = |key: &str, v: Option<f64>| {
        v.ok_or_else(|| {
            ls.invalid(
                &format!("run.event.{i}"),
                format!("kind = \"unbalance\" needs `{key}`"),
            )
        })
    };
    positive(ls, &k("mass"), need("mass", e.mass)?)?;
    positive(ls, &k("radius"), need("radius", e.radius)?)?;
    finite(ls, &k("phase_deg"), e.phase_deg)
}

/// Event `i` of kind `clearance`: no unbalance keys, a stator named in `[[stator]]`, a
/// positive clearance.
fn validate_clearance_event(ls: &LoadedScene, i: usize, e: &EventSpec) -> Result<(), SceneError> {
    let k = |s: &str| format!("run.event.{i}.{s}");
    unused_keys(
        ls,
        i,
        &[
            ("mass", e.mass.is_some()),
            ("radius", e.radius.is_some()),
            ("node", e.node != 0),
            ("phase_deg", e.phase_deg != 0.0),
        ],
        "clearance",
    )?;
    let name = e.stator.as_deref().ok_or_else(|| {
        ls.invalid(
            &format!("run.event.{i}"),
            "kind = \"clearance\" needs `stator`",
        )
    })?;
    if !ls.scene.stators.iter().any(|s| s.name() == name) {
        let names: Vec<String> = ls
            .scene
            .stators
            .iter()
            .map(|s| format!("`{}`", s.name()))
            .collect();
        return Err(ls.invalid(
            &k("stator"),
            if names.is_empty() {
                format!("no stator is named `{name}`: the scene has none (`stator` is empty)")
            } else {
                format!(
                    "no stator is named `{name}`: the scene's stators (`stator`) are {}",
                    names.join(", ")
                )
            },
        ));
    }
    let c = e.clearance.ok_or_else(|| {
        ls.invalid(
            &format!("run.event.{i}"),
            "kind = \"clearance\" needs `clearance` (m)",
        )
    })?;
    positive(ls, &k("clearance"), c)
}
