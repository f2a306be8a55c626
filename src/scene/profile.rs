//! `[run.speed_profile]`: the spin speed of a transient run as the user writes it, and its
//! checks (each error names the file, the dotted key and its line).

use super::validate::checks::{finite, non_negative, positive};
use super::LoadedScene;
use crate::error::SceneError;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// What a speed profile is made of (`run.speed_profile.kind`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ProfileKind {
    /// One speed `speed` for `duration` seconds.
    Constant,
    /// A linear ramp `from` → `to`, over `duration` seconds or at `acceleration` (unit/s),
    /// then `hold` seconds at `to`.
    Ramp,
    /// `points` = `[[t, speed], …]` (s, unit), times from 0 strictly increasing,
    /// interpolated by the monotone cubic (PCHIP), then `hold` seconds at the last speed.
    Table,
    /// A driven rotor: the spin angle is a degree of freedom, `J φ̈ = T_drive − T_drag −
    /// T_rub − T_unbalance`, from `speed` at t = 0 for `duration` seconds; `polar_inertia`
    /// (default: the rotor's, from its disks and shaft elements), the drive `drive_torque` or
    /// `drive_curve` (none: a free coast-down), switched off at `drive_off`, and the drag
    /// `drag_torque` + `drag_coefficient` Ω ([`crate::model::Drive`]).
    Driven,
}

/// How a table's points are joined (`run.speed_profile.interpolation`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Interpolation {
    /// The monotone cubic (PCHIP): C¹, no overshoot.
    #[default]
    Pchip,
    /// Straight lines: piecewise constant Ω̇ (ramps joined at the points).
    Linear,
}

/// The unit of a profile's speeds (`run.speed_profile.unit`; no default, it must be said).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SpeedUnit {
    /// rad/s.
    RadPerS,
    /// Revolutions per minute, Ω = 2π n/60.
    Rpm,
    /// ω/ω_n, ω_n the rotor's first natural frequency (the unit of `run.speed_ratio`).
    SpeedRatio,
}

/// rad/s per revolution per minute: 2π/60.
const RAD_PER_S_PER_RPM: f64 = std::f64::consts::PI / 30.0;

impl SpeedUnit {
    /// Name as written in scene files.
    pub fn name(self) -> &'static str {
        match self {
            SpeedUnit::RadPerS => "rad_per_s",
            SpeedUnit::Rpm => "rpm",
            SpeedUnit::SpeedRatio => "speed_ratio",
        }
    }
    /// rad/s per unit, for a rotor of first natural frequency `omega_n` (rad/s).
    pub fn to_rad_per_s(self, omega_n: f64) -> f64 {
        match self {
            SpeedUnit::RadPerS => 1.0,
            SpeedUnit::Rpm => RAD_PER_S_PER_RPM,
            SpeedUnit::SpeedRatio => omega_n,
        }
    }
    /// A speed `omega` (rad/s) in revolutions per minute, n = 60 Ω/(2π): the inverse of
    /// [`SpeedUnit::Rpm`]'s factor (the one rad/s ↔ rpm conversion of the program).
    pub fn rpm(omega: f64) -> f64 {
        omega / RAD_PER_S_PER_RPM
    }
}

/// `[run.speed_profile]`: the spin speed Ω(t) ≥ 0 of a transient run (rotation about +z,
/// counter-clockwise seen from +z; a profile never reverses).
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpeedProfileSpec {
    /// Constant, ramp, table or driven.
    pub kind: ProfileKind,
    /// Unit of every speed of the profile (and of `acceleration`, per second).
    pub unit: SpeedUnit,
    /// Constant: the speed.
    pub speed: Option<f64>,
    /// Ramp: first speed.
    pub from: Option<f64>,
    /// Ramp: last speed.
    pub to: Option<f64>,
    /// Constant: the run's length; ramp: the ramp's length (s).
    pub duration: Option<f64>,
    /// Ramp: dΩ/dt (unit/s), the sign of `to − from`.
    pub acceleration: Option<f64>,
    /// Table: `[t, speed]` pairs.
    #[serde(default, deserialize_with = "pairs")]
    pub points: Option<Vec<[f64; 2]>>,
    /// Table: how the points are joined (default `pchip`).
    #[serde(default)]
    pub interpolation: Interpolation,
    /// Seconds at the last speed after a ramp or table (default 0).
    #[serde(default)]
    pub hold: f64,
    /// Speed (in `unit`) at which the speed-dependent inputs are evaluated: `clearance_nd`
    /// (δ = δ_nd |Z0(Ω_ref)|), `stiffness_ratio`, and the unit of the non-dimensional outputs;
    /// default ω_n.
    pub reference: Option<f64>,
    /// Further orders to track besides 1×, ½×, ⅓× (multiples of the spin frequency).
    #[serde(default)]
    pub orders: Vec<f64>,
    /// Revolutions per order-tracking window (a DFT over a whole number of revolutions in the
    /// angle domain); orders k/`window_revolutions` fall on bins exactly. Default 6.
    #[serde(default = "default_window")]
    pub window_revolutions: usize,
    /// Driven: the polar moment of inertia J of everything that spins (kg·m²); default the
    /// rotor's own (disks `½ m (R² + r²)`, shaft elements `ρ I_p ℓ`).
    pub polar_inertia: Option<f64>,
    /// Driven: a constant drive torque (N·m, about +z: > 0 speeds the rotor up).
    pub drive_torque: Option<f64>,
    /// Driven: a motor curve `[[speed, torque], …]` (speed in `unit`, torque N·m), speeds
    /// strictly increasing, interpolated linearly and held beyond its ends.
    pub drive_curve: Option<Vec<[f64; 2]>>,
    /// Driven: the time (s) the drive is switched off (a coast-down from then on).
    pub drive_off: Option<f64>,
    /// Driven: a constant bearing drag torque (N·m, ≥ 0) resisting the spin while Ω > 0.
    #[serde(default)]
    pub drag_torque: f64,
    /// Driven: a viscous drag coefficient c_t (N·m·s/rad, ≥ 0): the torque c_t Ω resists the
    /// spin.
    #[serde(default)]
    pub drag_coefficient: f64,
}

fn default_window() -> usize {
    6
}

const AT: &str = "run.speed_profile";

/// A speed of the profile: finite and ≥ 0 (a negative value would reverse the rotor through
/// zero speed, which a profile does not do).
fn speed_ok(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if !v.is_finite() {
        return Err(ls.invalid(key, format!("must be a finite speed, got {v}")));
    }
    finite(ls, key, v)?;
    if v < 0.0 {
        return Err(ls.invalid(
            key,
            format!("is negative ({v}): the profile would reverse through zero speed; a profile keeps Ω ≥ 0 (rotation about +z)"),
        ));
    }
    Ok(())
}

/// `Err` naming `run.speed_profile.<key>` when the kind `kind` does not use a key given.
fn unused(ls: &LoadedScene, kind: &str, keys: &[(&str, bool)]) -> Result<(), SceneError> {
    match keys.iter().find(|(_, given)| *given) {
        Some((k, _)) => Err(ls.invalid(
            &format!("{AT}.{k}"),
            format!("does not apply to kind = \"{kind}\""),
        )),
        None => Ok(()),
    }
}

/// A required key of a kind.
fn required<T: Copy>(
    ls: &LoadedScene,
    kind: &str,
    key: &str,
    v: Option<T>,
) -> Result<T, SceneError> {
    v.ok_or_else(|| ls.invalid(AT, format!("kind = \"{kind}\" needs `{key}`")))
}

/// Checks `[run.speed_profile]`: the keys of its kind and no others; speeds finite and ≥ 0;
/// a positive duration, or an acceleration of the sign of `to − from`; table times finite,
/// from 0 and strictly increasing, at least two points; a finite `hold` ≥ 0; a positive
/// reference speed; finite positive orders; at least one revolution per tracking window.
pub fn validate(ls: &LoadedScene, p: &SpeedProfileSpec) -> Result<(), SceneError> {
    let k = |s: &str| format!("{AT}.{s}");
    non_negative(ls, &k("hold"), p.hold)?;
    match p.kind {
        ProfileKind::Constant => {
            unused(
                ls,
                "constant",
                &[
                    ("from", p.from.is_some()),
                    ("to", p.to.is_some()),
                    ("acceleration", p.acceleration.is_some()),
                    ("points", p.points.is_some()),
                    ("hold", p.hold != 0.0),
                    ("interpolation", p.interpolation != Interpolation::Pchip),
                    ("polar_inertia", p.polar_inertia.is_some()),
                    ("drive_torque", p.drive_torque.is_some()),
                    ("drive_curve", p.drive_curve.is_some()),
                    ("drive_off", p.drive_off.is_some()),
                    ("drag_torque", p.drag_torque != 0.0),
                    ("drag_coefficient", p.drag_coefficient != 0.0),
                ],
            )?;
            speed_ok(ls, &k("speed"), required(ls, "constant", "speed", p.speed)?)?;
            positive(
                ls,
                &k("duration"),
                required(ls, "constant", "duration", p.duration)?,
            )?;
        }
        ProfileKind::Ramp => ramp_ok(ls, p)?,
        ProfileKind::Table => {
            unused(
                ls,
                "table",
                &[
                    ("speed", p.speed.is_some()),
                    ("from", p.from.is_some()),
                    ("to", p.to.is_some()),
                    ("duration", p.duration.is_some()),
                    ("acceleration", p.acceleration.is_some()),
                    ("polar_inertia", p.polar_inertia.is_some()),
                    ("drive_torque", p.drive_torque.is_some()),
                    ("drive_curve", p.drive_curve.is_some()),
                    ("drive_off", p.drive_off.is_some()),
                    ("drag_torque", p.drag_torque != 0.0),
                    ("drag_coefficient", p.drag_coefficient != 0.0),
                ],
            )?;
            let pts = p.points.as_deref().unwrap_or_default();
            if pts.len() < 2 {
                return Err(ls.invalid(&k("points"), "needs at least two [t, speed] points"));
            }
            table_ok(ls, pts)?;
        }
        ProfileKind::Driven => driven_ok(ls, p)?,
    }
    if let Some(r) = p.reference {
        positive(ls, &k("reference"), r)?;
    }
    for (i, o) in p.orders.iter().enumerate() {
        positive(ls, &format!("{AT}.orders.{i}"), *o)?;
    }
    if p.window_revolutions == 0 {
        return Err(ls.invalid(&k("window_revolutions"), "must be at least 1"));
    }
    Ok(())
}

/// The keys of a ramp: no others; `from` and `to` finite and ≥ 0; a positive `duration` or an
/// `acceleration` of the sign of `to − from`, not both.
fn ramp_ok(ls: &LoadedScene, p: &SpeedProfileSpec) -> Result<(), SceneError> {
    let k = |s: &str| format!("{AT}.{s}");
    unused(
        ls,
        "ramp",
        &[
            ("speed", p.speed.is_some()),
            ("points", p.points.is_some()),
            ("polar_inertia", p.polar_inertia.is_some()),
            ("drive_torque", p.drive_torque.is_some()),
            ("drive_curve", p.drive_curve.is_some()),
            ("drive_off", p.drive_off.is_some()),
            ("drag_torque", p.drag_torque != 0.0),
            ("drag_coefficient", p.drag_coefficient != 0.0),
        ],
    )?;
    let from = required(ls, "ramp", "from", p.from)?;
    let to = required(ls, "ramp", "to", p.to)?;
    speed_ok(ls, &k("from"), from)?;
    speed_ok(ls, &k("to"), to)?;
    match (p.duration, p.acceleration) {
        (Some(_), Some(_)) => {
            return Err(ls.invalid(AT, "give `duration` or `acceleration`, not both"))
        }
        (None, None) => {
            return Err(ls.invalid(AT, "kind = \"ramp\" needs `duration` or `acceleration`"))
        }
        (Some(d), None) => positive(ls, &k("duration"), d)?,
        (None, Some(a)) => {
            if !(a.is_finite() && a != 0.0 && (to - from) * a > 0.0) {
                return Err(ls.invalid(
                    &k("acceleration"),
                    format!(
                        "must be finite, non-zero and of the sign of `to − from` ({}), got {a}",
                        to - from
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// `[[t, speed], …]` with exactly two numbers in each point: serde's `[f64; 2]` alone reads the
/// first two of a longer array and drops the rest.
fn pairs<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<Vec<[f64; 2]>>, D::Error> {
    let Some(points) = Option::<Vec<Vec<f64>>>::deserialize(d)? else {
        return Ok(None);
    };
    (points.iter().enumerate())
        .map(|(i, p)| {
            <[f64; 2]>::try_from(p.as_slice()).map_err(|_| {
                serde::de::Error::custom(format!(
                    "`run.speed_profile.points.{i}` has {} numbers, {p:?}: each point is [t, speed]",
                    p.len()
                ))
            })
        })
        .collect::<Result<Vec<_>, _>>()
        .map(Some)
}

/// Table points: finite times from 0, strictly increasing; speeds finite and ≥ 0.
fn table_ok(ls: &LoadedScene, pts: &[[f64; 2]]) -> Result<(), SceneError> {
    for (i, [t, w]) in pts.iter().enumerate() {
        let key = format!("{AT}.points.{i}");
        if !t.is_finite() || *t < 0.0 {
            return Err(ls.invalid(&key, format!("time must be finite and ≥ 0, got {t}")));
        }
        finite(ls, &key, *t)?;
        if i == 0 && *t != 0.0 {
            return Err(ls.invalid(&key, format!("the table must start at t = 0, got {t}")));
        }
        if i > 0 && *t <= pts[i - 1][0] {
            return Err(ls.invalid(
                &key,
                format!(
                    "times must increase strictly: {t} follows {}",
                    pts[i - 1][0]
                ),
            ));
        }
        speed_ok(ls, &key, *w)?;
    }
    Ok(())
}

/// A driven profile: `speed` (Ω at t = 0, ≥ 0) and a positive `duration`; no ramp or table
/// keys; a positive finite `polar_inertia` when given; at most one of `drive_torque` (finite)
/// and `drive_curve` (at least two points, speeds finite, ≥ 0 and strictly increasing, torques
/// finite); `drive_off` finite in `(0, duration]` and only with a drive; drags finite and ≥ 0.
fn driven_ok(ls: &LoadedScene, p: &SpeedProfileSpec) -> Result<(), SceneError> {
    let k = |s: &str| format!("{AT}.{s}");
    unused(
        ls,
        "driven",
        &[
            ("from", p.from.is_some()),
            ("to", p.to.is_some()),
            ("acceleration", p.acceleration.is_some()),
            ("points", p.points.is_some()),
            ("hold", p.hold != 0.0),
            ("interpolation", p.interpolation != Interpolation::Pchip),
        ],
    )?;
    speed_ok(ls, &k("speed"), required(ls, "driven", "speed", p.speed)?)?;
    let duration = required(ls, "driven", "duration", p.duration)?;
    positive(ls, &k("duration"), duration)?;
    match (p.polar_inertia, &ls.scene.rotor) {
        (Some(j), _) => positive(ls, &k("polar_inertia"), j)?,
        (None, super::RotorSpec::Jeffcott(j)) if j.disk.is_none() => {
            return Err(ls.invalid(
                AT,
                "a driven rotor needs its polar inertia: give `polar_inertia` (kg·m²), or the Jeffcott rotor's `disk` to compute it from (the rotor's `mass` alone has no radius)",
            ))
        }
        (None, _) => {}
    }
    match (p.drive_torque, &p.drive_curve) {
        (Some(_), Some(_)) => {
            return Err(ls.invalid(
                &k("drive_curve"),
                "give `drive_torque` (constant) or `drive_curve` (over speed), not both",
            ))
        }
        (Some(t), None) => finite(ls, &k("drive_torque"), t)?,
        (None, Some(curve)) => {
            if curve.len() < 2 {
                return Err(ls.invalid(
                    &k("drive_curve"),
                    "needs at least two [speed, torque] points",
                ));
            }
            for (i, [w, t]) in curve.iter().enumerate() {
                let key = format!("{AT}.drive_curve.{i}");
                speed_ok(ls, &key, *w)?;
                finite(ls, &key, *t)?;
                if i > 0 && *w <= curve[i - 1][0] {
                    return Err(ls.invalid(
                        &key,
                        format!(
                            "speeds must increase strictly: {w} follows {}",
                            curve[i - 1][0]
                        ),
                    ));
                }
            }
        }
        (None, None) => {
            if p.drive_off.is_some() {
                return Err(ls.invalid(
                    &k("drive_off"),
                    "there is no drive to switch off (give `drive_torque` or `drive_curve`)",
                ));
            }
        }
    }
    if let Some(off) = p.drive_off {
        if !(off.is_finite() && off > 0.0 && off <= duration) {
            return Err(ls.invalid(
                &k("drive_off"),
                format!("must be a time in the run, 0 < t ≤ duration = {duration} s, got {off}"),
            ));
        }
    }
    non_negative(ls, &k("drag_torque"), p.drag_torque)?;
    non_negative(ls, &k("drag_coefficient"), p.drag_coefficient)?;
    Ok(())
}
