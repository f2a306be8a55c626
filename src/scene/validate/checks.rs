//! The checks every admissibility rule is made of, with errors naming file, key and line: a
//! value positive, non-negative, finite, bounded, an angle, a Poisson ratio; one of two keys,
//! at most one of two keys; a station by name; the plane of a 2-D mesh; the output component;
//! and the documented size limits. The rules that choose ([`one_of`], [`at_most_one`],
//! [`station_index`], [`extra_station_index`], [`mesh_plane`], [`output_component`]) return
//! their choice. Used by the rules of [`super`] per table and by [`crate::scene::profile`] and
//! `scene/event.rs`.

use crate::element::solid2d::Plane;
use crate::error::SceneError;
use crate::scene::{Component, LoadedScene, MeshStatorSpec};

/// Most speeds a sweep may hold (`run.sweep`: (to − from)/step + 1).
pub const MAX_SWEEP_SPEEDS: usize = 100_000;
/// Most recorded samples per revolution (`run.samples_per_rev`).
pub const MAX_SAMPLES_PER_REV: usize = 1 << 20;
/// Most revolutions of a run (`run.revolutions`); the step budget (`run.max_steps`, see
/// [`crate::time::plan`]) usually binds first.
pub const MAX_REVOLUTIONS: usize = 100_000_000;
/// Most nodes of an FE rotor's shaft (Σ `rotor.shaft.*.elements` + 1).
pub const MAX_ROTOR_NODES: usize = 100_000;
/// Most elements of a rod stator (`stator.*.elements`).
pub const MAX_ROD_ELEMENTS: usize = 100_000;

/// Most memory the dense operations on an FE rotor's DOFs may take (bytes, 4 GiB, as a run's
/// record): see [`dense_rotor_cost`].
pub const MAX_DENSE_BYTES: f64 = 4.0 * 1024.0 * 1024.0 * 1024.0;
/// Longest estimated time of the dense operations on an FE rotor's DOFs (s): see
/// [`dense_rotor_cost`].
pub const MAX_DENSE_SECONDS: f64 = 3600.0;
/// Dense n × n matrices of f64 an FE rotor of n DOFs holds at once while its model is built:
/// M and K, the Cholesky factor of M and its inverse, L⁻¹KL⁻ᵀ and its eigenvectors; the
/// unbalance response's complex dynamic stiffness (two f64 each) beside dense K, C and M.
pub const DENSE_MATRICES: f64 = 6.0;
/// Seconds per n³ of the dense operations the set-up of an FE rotor of n DOFs takes (the
/// natural frequencies by a dense symmetric eigensolve, the stiffness at the reference node
/// and the unbalance responses by dense LU): `rubsim check` of scenes/fe/paper_rotor_rub.toml
/// at 2004 DOFs took 90 s on the development machine, 1.1·10⁻⁸ s × 2004³.
pub const DENSE_SECONDS_PER_CUBE: f64 = 1.1e-8;

/// What the dense operations on an FE rotor's DOFs cost, estimated before anything is built
/// ([`dense_rotor_cost`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DenseCost {
    /// The rotor's DOFs n.
    pub dofs: usize,
    /// Memory of the dense matrices held at once (bytes): [`DENSE_MATRICES`] × 8 n².
    pub bytes: f64,
    /// Time of the model's set-up (s): [`DENSE_SECONDS_PER_CUBE`] × n³.
    pub seconds: f64,
}

/// The cost of the dense operations on an FE rotor of `dofs` DOFs (memory and time of its
/// set-up: natural frequencies, reference stiffness, unbalance response). Its estimate grows as
/// n² and n³: 20 000 elements (80 004 DOFs) would need 307 GB.
pub fn dense_rotor_cost(dofs: usize) -> DenseCost {
    let n = dofs as f64;
    DenseCost {
        dofs,
        bytes: DENSE_MATRICES * 8.0 * n * n,
        seconds: DENSE_SECONDS_PER_CUBE * n * n * n,
    }
}

impl DenseCost {
    /// `≈ 1.2 GB and ≈ 3.4 min`: the estimate in words.
    pub fn describe(&self) -> String {
        format!(
            "≈ {} and ≈ {} for the dense operations of the model's set-up on its {} DOFs (estimate)",
            bytes(self.bytes),
            duration(self.seconds),
            self.dofs
        )
    }

    /// Why the cost is above [`MAX_DENSE_BYTES`] or [`MAX_DENSE_SECONDS`], or `None` within
    /// them.
    pub fn excess(&self) -> Option<String> {
        (self.bytes > MAX_DENSE_BYTES || self.seconds > MAX_DENSE_SECONDS).then(|| {
            format!(
                "needs {}, above the limit of {} and {}",
                self.describe(),
                bytes(MAX_DENSE_BYTES),
                duration(MAX_DENSE_SECONDS)
            )
        })
    }
}

/// A byte count in kB, MB or GB.
pub fn bytes(b: f64) -> String {
    if b < 1e6 {
        format!("{:.1} kB", b / 1e3)
    } else if b < 1e9 {
        format!("{:.1} MB", b / 1e6)
    } else {
        format!("{:.2} GB", b / 1e9)
    }
}

/// A duration in s, min or h.
pub fn duration(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.2} s")
    } else if s < 7200.0 {
        format!("{:.1} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

/// Largest damping ratio of a rotor (`rotor.damping_ratio`, the ratio that `rotor.damping`
/// gives, c / (2√(m k)), and `rotor.modal_damping.ratio`). Rotor-bearing systems have ratios of
/// a few percent to about 0.3, squeeze-film dampers up to about 1; at ξ = 10 the rotor has no
/// resonance left (its slow pole sits at ω_n/(2ξ) = ω_n/20, its fast one at 2ξω_n) and the
/// response is the damper's — a larger value is a unit mistake (a damping coefficient in N·s/m
/// given as a ratio) or a typo, and its runs measure nothing (with ξ = 10⁹⁰ the orbit is 10⁻⁹⁰
/// of the clearance scale and the error estimate 10⁸³).
pub const MAX_DAMPING_RATIO: f64 = 10.0;

/// Largest magnitude of any number in a scene: beyond it squares and fourth powers (areas,
/// second moments, stiffnesses) overflow or lose every digit, and no physical value is near it.
pub const MAX_MAGNITUDE: f64 = 1e100;

/// Smallest magnitude of a number in a scene other than 0: below it the fourth powers of
/// lengths (second moments of area) and the products of small factors underflow or lose every
/// digit, the matrices turn singular and the error would blame some other part (a shaft
/// 1e-300 m long gave "rotor mass matrix … singular", a damping ratio of 1e-300 blamed the
/// stator). The Planck length is 1.6e-35 m.
pub const MIN_MAGNITUDE: f64 = 1e-50;

/// Which of two alternative keys a scene gives (e.g. `clearance` or `clearance_nd`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OneOf<A, B> {
    /// The first key, with its value.
    First(A),
    /// The second key, with its value.
    Second(B),
}

/// Exactly one of the keys `key_a`, `key_b` (values `a`, `b`); the error names the table `at`.
pub fn one_of<A, B>(
    ls: &LoadedScene,
    (key_a, a): (&str, Option<A>),
    (key_b, b): (&str, Option<B>),
    at: &str,
) -> Result<OneOf<A, B>, SceneError> {
    match (a, b) {
        (Some(a), None) => Ok(OneOf::First(a)),
        (None, Some(b)) => Ok(OneOf::Second(b)),
        (Some(_), Some(_)) => Err(both(ls, key_a, key_b, at)),
        (None, None) => Err(ls.invalid(at, format!("missing: give `{key_a}` or `{key_b}`"))),
    }
}

/// At most one of the keys `key_a`, `key_b` (`None`: neither); the error names the table `at`.
pub fn at_most_one<A, B>(
    ls: &LoadedScene,
    (key_a, a): (&str, Option<A>),
    (key_b, b): (&str, Option<B>),
    at: &str,
) -> Result<Option<OneOf<A, B>>, SceneError> {
    match (a, b) {
        (Some(_), Some(_)) => Err(both(ls, key_a, key_b, at)),
        (Some(a), None) => Ok(Some(OneOf::First(a))),
        (None, Some(b)) => Ok(Some(OneOf::Second(b))),
        (None, None) => Ok(None),
    }
}

fn both(ls: &LoadedScene, key_a: &str, key_b: &str, at: &str) -> SceneError {
    ls.invalid(at, format!("give `{key_a}` or `{key_b}`, not both"))
}

/// Index of the station stator `stator` faces (its `station` key).
pub fn station_index(ls: &LoadedScene, stator: usize, name: &str) -> Result<usize, SceneError> {
    let stations = &ls.scene.stations;
    stations
        .iter()
        .position(|st| st.name == name)
        .ok_or_else(|| {
            let known: Vec<&str> = stations.iter().map(|s| s.name.as_str()).collect();
            ls.invalid(
                &format!("stator.{stator}.station"),
                format!(
                    "no station named `{name}` (stations: {})",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            )
        })
}

/// Index of entry `j` of a meshed stator's further `stations`.
pub fn extra_station_index(
    ls: &LoadedScene,
    stator: usize,
    j: usize,
    name: &str,
) -> Result<usize, SceneError> {
    let stations = &ls.scene.stations;
    stations
        .iter()
        .position(|st| st.name == name)
        .ok_or_else(|| {
            ls.invalid(
                &format!("stator.{stator}.stations.{j}"),
                format!("no station named `{name}`"),
            )
        })
}

/// The plane of the 2-D meshed stator `stator` (`plane = "stress"` or `"strain"`).
pub fn mesh_plane(
    ls: &LoadedScene,
    stator: usize,
    m: &MeshStatorSpec,
) -> Result<Plane, SceneError> {
    m.plane().ok_or_else(|| {
        ls.invalid(
            &format!("stator.{stator}.plane"),
            "must be \"stress\" or \"strain\"",
        )
    })
}

/// The analysed response component (`output.component = "x"` or `"y"`).
pub fn output_component(ls: &LoadedScene) -> Result<Component, SceneError> {
    Component::from_name(&ls.scene.output.component)
        .ok_or_else(|| ls.invalid("output.component", "must be \"x\" or \"y\""))
}

pub(crate) fn positive(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if !(v.is_finite() && v > 0.0) {
        return Err(ls.invalid(
            key,
            format!("must be a positive finite number, got {}", show(v)),
        ));
    }
    bounded(ls, key, v)
}

pub(crate) fn non_negative(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if !(v.is_finite() && v >= 0.0) {
        return Err(ls.invalid(key, format!("must be zero or positive, got {}", show(v))));
    }
    bounded(ls, key, v)
}

/// A number for a message: plain when moderate, else in exponent form (`1e308`, not 309 digits).
pub(crate) fn show(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e7).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

pub(crate) fn finite(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if !v.is_finite() {
        return Err(ls.invalid(key, format!("must be a finite number, got {}", show(v))));
    }
    bounded(ls, key, v)
}

/// `|v|` within [`MAX_MAGNITUDE`], and zero or at least [`MIN_MAGNITUDE`].
pub(crate) fn bounded(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if v.abs() > MAX_MAGNITUDE {
        return Err(ls.invalid(
            key,
            format!("{} is beyond {MAX_MAGNITUDE:e} in magnitude: no physical value is, and the model's arithmetic overflows", show(v)),
        ));
    }
    if v != 0.0 && v.abs() < MIN_MAGNITUDE {
        return Err(ls.invalid(
            key,
            format!("{} is below {MIN_MAGNITUDE:e} in magnitude (and not 0): no physical value is, and the model's arithmetic underflows", show(v)),
        ));
    }
    Ok(())
}

/// An angle in degrees (`phase_deg`, `angle_deg`, `approach_deg`): finite and within ±360°.
pub(crate) fn degrees(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if !(v.is_finite() && v.abs() <= 360.0) {
        return Err(ls.invalid(
            key,
            format!("must be an angle in −360 … 360 degrees, got {}", show(v)),
        ));
    }
    Ok(())
}

pub(crate) fn poisson(ls: &LoadedScene, key: &str, v: f64) -> Result<(), SceneError> {
    if v.is_finite() && v > -1.0 && v < 0.5 {
        Ok(())
    } else {
        Err(ls.invalid(key, format!("must lie in (−1, 0.5), got {}", show(v))))
    }
}
