//! ROSS's damping conventions, by the version of the saved file, as the scene's
//! `rotor.rayleigh` and `rotor.rayleigh_on`.
//!
//! **ROSS 2** (checked with 2.3.0) keeps Rayleigh factors on the shaft elements only
//! (`ShaftElement.alpha`, `.beta`; `ShaftElement.C = alpha M_e + beta K_e`), and its `[parameters]`
//! table is empty: `C = Σ_e (α M_e + β K_e) + C_bearings` — `rayleigh_on = "shaft"`.
//!
//! **ROSS 3** (checked with 3.0.0's `rotor_assembly.py`, `Rotor._build_base_matrices` and
//! `Rotor.C`) saves the rotor's own damping under `[parameters]`: `alpha` (1/s), `beta` (s),
//! `default_damping_ratio` and, when given, `modal_damping_ratio`. Its base matrices sum every
//! element but the bearings — M0 the shaft elements', disks' and point masses' mass, K0 the shaft
//! elements' stiffness (disks and point masses have none), C0 their `C` (the shaft elements'
//! `alpha M_e + beta K_e`) — and then exactly one kind of damping is kept:
//! - rotor-level (`alpha` or `beta` ≠ 0): `C0 = alpha M0 + beta K0` — `rayleigh_on = "rotor"`.
//!   When the elements' factors or `modal_damping_ratio` are given too, ROSS warns ("More than
//!   one type of damping was provided. Global proportional damping has been chosen …") and
//!   ignores them; so does the scene, and it says so in its header;
//! - element-level alone: C0 as ROSS 2's — `rayleigh_on = "shaft"`;
//! - modal alone (`modal_damping_ratio`): C0 from ζ per mode of `M(0)⁻¹ K(0)` with the bearings
//!   at zero frequency, `default_damping_ratio` on the remaining modes — not rubsim's
//!   `rotor.modal_damping` (one ζ, bearings at the run's speed): refused. With the elements'
//!   factors too, ROSS 3.0.0 keeps neither (C0 = 0): refused as well.
//!
//! Either way the bearings' own C (`cxx … cyy`, `czz`) is added to C0 (`Rotor.C`), as the
//! scene's bearings and axial supports add theirs. Gyroscopics do not enter C in either
//! version (ROSS adds `speed · G` in its state matrix, rubsim `Ω G` likewise).
//!
//! Rotor-level factors are read from `[parameters]`, where ROSS 3.0.0 writes them, or from the
//! top of the file; both at once are refused.

use super::source::Source;
use crate::error::SceneError;
use toml::Value;

/// The saved file's format, as its keys tell it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Format {
    /// ROSS 2: no rotor-level damping keys, bearing tables by a smoothing spline.
    Ross2,
    /// ROSS 3: rotor-level damping under `[parameters]`, bearing tables by `interpolation`.
    Ross3,
}

/// The keys ROSS 3.0.0 writes under `[parameters]` and ROSS 2.3.0 does not (ROSS 3 writes the
/// first three always, `modal_damping_ratio` when it is given).
const ROSS3_PARAMETERS: [&str; 4] = [
    "alpha",
    "beta",
    "default_damping_ratio",
    "modal_damping_ratio",
];

impl Format {
    /// ROSS 3 when the file has any of ROSS 3's rotor-level damping keys (under `[parameters]`
    /// or at its top), a bearing table with ROSS 3's `interpolation` key, or a `ross_version`
    /// of 3 or more; else ROSS 2.
    pub fn of(src: &Source) -> Self {
        let parameters = match src.doc.get("parameters") {
            Some(Value::Table(t)) => ROSS3_PARAMETERS.iter().any(|k| t.contains_key(*k)),
            _ => false,
        };
        let top = ["alpha", "beta"].iter().any(|k| src.doc.contains_key(*k));
        let interpolation = src.doc.values().any(|v| {
            v.as_table()
                .is_some_and(|t| t.contains_key("interpolation"))
        });
        let major = match src.doc.get("ross_version") {
            Some(Value::String(v)) => v.split('.').next().and_then(|m| m.parse::<u32>().ok()),
            _ => None,
        };
        if parameters || top || interpolation || major.is_some_and(|m| m >= 3) {
            Format::Ross3
        } else {
            Format::Ross2
        }
    }

    /// The format as the scene's header names it.
    pub fn describe(self) -> &'static str {
        match self {
            Format::Ross2 => "ROSS 2 (Rayleigh factors on the shaft elements)",
            Format::Ross3 => {
                "ROSS 3 (the rotor's damping under [parameters], bearing tables by `interpolation`)"
            }
        }
    }
}

/// The scene's Rayleigh damping: its factors, what they act on, where they come from in the
/// ROSS file and what the scene's header says about them.
#[derive(Debug)]
pub(super) struct Damping {
    /// `[α, β]` (1/s, s).
    pub rayleigh: [f64; 2],
    /// `rotor.rayleigh_on`: `"shaft"` or `"rotor"`.
    pub on: &'static str,
    /// The ROSS table the factors come from (`""`: the file's top level).
    pub table: String,
    /// The header's lines about the damping (without `# `).
    pub comment: Vec<String>,
    /// The shaft elements' factors are ROSS's damping (and so must be the same on every
    /// element); false when the rotor's replace them.
    pub elemental: bool,
}

/// The rotor-level keys of a file: `[parameters]` or its top level, with their values.
struct RotorLevel {
    /// `"parameters"` or `""` (the top level).
    table: String,
    alpha: f64,
    beta: f64,
    /// `modal_damping_ratio` is given.
    modal: bool,
}

/// The rotor-level damping keys of `src`, `None` without any.
fn rotor_level(src: &Source) -> Result<Option<RotorLevel>, SceneError> {
    let empty = toml::Table::new();
    let params = match src.doc.get("parameters") {
        Some(Value::Table(t)) => t,
        Some(_) => {
            let m = "`parameters` is not a table (ROSS writes the rotor's parameters there)";
            return Err(src.error(&["parameters"], m.into()));
        }
        None => &empty,
    };
    let in_params = ["alpha", "beta"].iter().any(|k| params.contains_key(*k));
    let at_top = ["alpha", "beta"].iter().any(|k| src.doc.contains_key(*k));
    if in_params && at_top {
        let key = if src.doc.contains_key("alpha") {
            "alpha"
        } else {
            "beta"
        };
        return Err(src.error(&[key], "Rayleigh factors both at the top of the file and under [parameters]: give the rotor's `alpha`, `beta` once".into()));
    }
    let (table, t) = if at_top {
        ("", &src.doc)
    } else {
        ("parameters", params)
    };
    let el = src.element(table, t);
    let modal = params.contains_key("modal_damping_ratio");
    if !(in_params || at_top || modal) {
        return Ok(None);
    }
    let mut ab = [0.0; 2];
    for (v, k) in ab.iter_mut().zip(["alpha", "beta"]) {
        *v = el.number_or(k, Some(0.0))?;
        if *v < 0.0 {
            let m = format!("`{k}` = {v}: Rayleigh factors must be zero or positive");
            return Err(el.error(k, m));
        }
    }
    Ok(Some(RotorLevel {
        table: table.to_string(),
        alpha: ab[0],
        beta: ab[1],
        modal,
    }))
}

/// ROSS's damping of the file `src` as the scene's: the rotor's factors (ROSS 3) or the shaft
/// elements' (`shaft_table`, the first element's table, and `shaft_factors`, its `[alpha,
/// beta]`; `any_elemental`: some element has a factor ≠ 0).
///
/// # Errors
/// [`SceneError::Invalid`] at `parameters.modal_damping_ratio` for ROSS 3's modal damping, at a
/// rotor-level factor that is negative or not a number, at a top-level factor beside one
/// under `[parameters]`.
pub(super) fn damping(
    src: &Source,
    shaft_table: &str,
    shaft_factors: [f64; 2],
    any_elemental: bool,
) -> Result<Damping, SceneError> {
    let rotor = rotor_level(src)?;
    let shown = |[a, b]: [f64; 2]| format!("α = {a:?} 1/s, β = {b:?} s");
    if let Some(r) = rotor.as_ref().filter(|r| r.alpha != 0.0 || r.beta != 0.0) {
        let at = if r.table.is_empty() {
            "at the top of the file".to_string()
        } else {
            format!("[{}]", r.table)
        };
        let mut comment = vec![
            format!(
                "Damping: ROSS 3's rotor-level Rayleigh factors ({at}) {}, on",
                shown([r.alpha, r.beta])
            ),
            "the mass of the shaft, disks and point masses and on the shaft's stiffness".into(),
            "(`rayleigh_on = \"rotor\"`), plus each bearing's own damping.".into(),
        ];
        let mut ignored = Vec::new();
        if any_elemental {
            ignored.push("the shaft elements' `alpha`, `beta`");
        }
        if r.modal {
            ignored.push("`modal_damping_ratio`");
        }
        if !ignored.is_empty() {
            comment.push(format!(
                "ROSS 3 ignores {} beside them (it warns: \"More than one",
                ignored.join(" and ")
            ));
            comment.push("type of damping was provided\"), and so does this scene.".into());
        }
        return Ok(Damping {
            rayleigh: [r.alpha, r.beta],
            on: "rotor",
            table: r.table.clone(),
            comment,
            elemental: false,
        });
    }
    if rotor.as_ref().is_some_and(|r| r.modal) {
        let also = if any_elemental {
            " (with the shaft elements' `alpha`, `beta` beside it ROSS 3.0.0 keeps neither and the rotor has no damping of its own)"
        } else {
            ""
        };
        let m = format!("ROSS 3's modal damping{also} cannot be represented: ROSS gives ζ per mode of M(0)⁻¹ K(0) with the bearings at zero frequency and `default_damping_ratio` on the other modes, rubsim's `rotor.modal_damping` one ζ on the modes of the bearings at the run's speed; give the rotor Rayleigh factors (`alpha`, `beta`) instead");
        return Err(src.error(&["parameters", "modal_damping_ratio"], m));
    }
    let comment = if any_elemental {
        vec![
            format!(
                "Damping: the shaft elements' Rayleigh factors {}, on each element's",
                shown(shaft_factors)
            ),
            "own mass and stiffness (`rayleigh_on = \"shaft\"`), plus each bearing's own damping."
                .into(),
        ]
    } else {
        vec!["Damping: the bearings' own (no Rayleigh factors in the file).".into()]
    };
    Ok(Damping {
        rayleigh: shaft_factors,
        on: "shaft",
        table: shaft_table.to_string(),
        comment,
        elemental: true,
    })
}
