//! Scene files: what the user asks for, as plain validated data.
//!
//! A scene is a TOML file read with serde; unknown keys are rejected. All physical values are SI
//! (kg, m, s, N, Pa, rad/s); angles are given in degrees where the key says `_deg`. The paper's
//! non-dimensional inputs (Table 2) are accepted beside the SI ones:
//!
//! * `clearance_nd` = δ/|Z0(ω)|, with |Z0| the steady unbalance response without stator at the
//!   speed being run, so the clearance changes along a sweep;
//! * `speed_ratio` = ω/ω_n;
//! * `damping_ratio` ξ, with c = 2ξ√(m k);
//! * `stiffness_ratio` ε = k_s/k_r.
//!
//! [`load`] reads a file, applies `--set key=value` overrides, deserialises and validates. Errors
//! name the file, the dotted key and the line ([`crate::error::SceneError`]).

pub mod abradable;
pub mod event;
mod output;
mod overrides;
pub mod profile;
pub mod ross;
mod rotor;
mod run;
pub mod schema;
mod stator;
pub mod thermal;
pub mod validate;
pub mod wear;

pub use event::{EventKind, EventSpec};
pub use output::*;
pub use overrides::{apply_override, key_at_span, locate_key, toml_number, ALTERNATIVE_KEYS};
pub use profile::{Interpolation, ProfileKind, SpeedProfileSpec, SpeedUnit};
pub use rotor::*;
pub use run::*;
pub use stator::*;
pub use validate::validate;

use crate::error::SceneError;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A whole scene.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Free text shown in reports.
    #[serde(default)]
    pub title: String,
    /// The rotor model.
    pub rotor: RotorSpec,
    /// Contact stations: rotor sections that can rub (`[[station]]`).
    #[serde(default, rename = "station")]
    pub stations: Vec<StationSpec>,
    /// Stators, each facing one station (`[[stator]]`).
    #[serde(default, rename = "stator")]
    pub stators: Vec<StatorSpec>,
    /// What to run.
    pub run: RunSpec,
    /// What to write.
    #[serde(default)]
    pub output: OutputSpec,
    /// The slow rub of the Newkirk effect: the hot-spot model, its thermal bow and the
    /// coupling of heat and vibration (`[thermal]`; none: no heating).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub thermal: Option<thermal::ThermalSpec>,
}

fn one() -> usize {
    1
}
fn yes() -> bool {
    true
}

/// A scene with where it came from, for error messages.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    /// The validated scene.
    pub scene: Scene,
    /// The file it was read from.
    pub file: PathBuf,
    /// The file's text (for locating keys in later errors).
    pub source: String,
    /// Overrides applied (`key=value`).
    pub overrides: Vec<String>,
}

impl LoadedScene {
    /// This scene again from its file's text with `extra` overrides applied after its own
    /// (a study's variant, a continuation's value of a key): parsed and validated as
    /// [`parse`] does.
    ///
    /// # Errors
    /// As [`parse`]: the scene's own error, naming the key and the override.
    pub fn with_overrides(&self, extra: &[String]) -> Result<LoadedScene, SceneError> {
        let mut sets = self.overrides.clone();
        sets.extend(extra.iter().cloned());
        parse(&self.file, &self.source, &sets)
    }

    /// The value of the dotted key `key` (array entries by index, `stator.0.clearance`) in
    /// the file's text with the overrides applied; `None` when the text has no such key (it
    /// may still be one the scene defaults).
    pub fn value_at(&self, key: &str) -> Option<toml::Value> {
        let mut v: toml::Value = toml::from_str(&self.source).ok()?;
        for a in &self.overrides {
            apply_override(&mut v, a).ok()?;
        }
        let mut cur = &v;
        for part in key.split('.') {
            cur = match cur {
                toml::Value::Table(t) => t.get(part)?,
                toml::Value::Array(a) => a.get(part.parse::<usize>().ok()?)?,
                _ => return None,
            };
        }
        Some(cur.clone())
    }

    /// An `Invalid` error for `key`, with the line of that key in the file when present.
    pub fn invalid(&self, key: &str, message: impl Into<String>) -> SceneError {
        invalid_at(&self.file, &self.source, key, message)
    }
}

fn invalid_at(file: &Path, source: &str, key: &str, message: impl Into<String>) -> SceneError {
    SceneError::Invalid {
        file: file.to_path_buf(),
        key: key.to_string(),
        line: locate_key(source, key),
        message: message.into(),
    }
}

/// Reads, overrides, deserialises and validates a scene file.
pub fn load(path: &Path, overrides: &[String]) -> Result<LoadedScene, SceneError> {
    let source = std::fs::read_to_string(path).map_err(|e| SceneError::Read {
        file: path.to_path_buf(),
        source: e,
    })?;
    parse(path, &source, overrides)
}

/// Like [`load`] but from text already in memory (`path` is used in messages only).
pub fn parse(path: &Path, source: &str, overrides: &[String]) -> Result<LoadedScene, SceneError> {
    let mut value: toml::Value =
        toml::from_str(source).map_err(|e| parse_error(path, source, e))?;
    for a in overrides {
        apply_override(&mut value, a)?;
    }
    let scene: Scene = if overrides.is_empty() {
        toml::from_str(source).map_err(|e| {
            tagged_error(path, source, &value, e.message(), "")
                .unwrap_or_else(|| parse_error(path, source, e))
        })?
    } else {
        // No spans here (the lines of a re-serialised document would not be the file's): when
        // the file alone fails the same way, report that with its lines, else blame the --set.
        Scene::deserialize(value.clone()).map_err(|e| match toml::from_str::<Scene>(source) {
            Err(fe) if fe.message() == e.message() => {
                tagged_error(path, source, &value, fe.message(), "")
                    .unwrap_or_else(|| parse_error(path, source, fe))
            }
            _ => {
                let after = format!(" (after --set {})", overrides.join(" --set "));
                tagged_error(path, source, &value, e.message(), &after).unwrap_or_else(|| {
                    SceneError::Override {
                        assignment: overrides.join(" --set "),
                        message: e.to_string().trim_end().replace('\n', " "),
                    }
                })
            }
        })?
    };
    let loaded = LoadedScene {
        scene,
        file: path.to_path_buf(),
        source: source.to_string(),
        overrides: overrides.to_vec(),
    };
    validate(&loaded)?;
    Ok(loaded)
}

/// A serde error inside a `kind`-tagged table (`[rotor]`, `[[stator]]`), which serde reports
/// at the table without the key: the table is deserialised again as the struct its `kind`
/// names, from its own text, and the key under the error's span is named (with its line in
/// the file). `None` when no tagged table fails with `message`.
fn tagged_error(
    path: &Path,
    source: &str,
    value: &toml::Value,
    message: &str,
    after: &str,
) -> Option<SceneError> {
    fn inner<T: serde::de::DeserializeOwned>(
        table: &toml::Table,
    ) -> Option<(Option<String>, String)> {
        let mut t = table.clone();
        t.remove("kind");
        let text = toml::to_string(&t).ok()?;
        let e = toml::from_str::<T>(&text).err()?;
        let key = e.span().and_then(|s| key_at_span(&text, s));
        Some((key, e.message().to_string()))
    }
    let mut tables: Vec<(String, &toml::Table)> = Vec::new();
    if let Some(r) = value.get("rotor").and_then(|v| v.as_table()) {
        tables.push(("rotor".into(), r));
    }
    if let Some(a) = value.get("stator").and_then(|v| v.as_array()) {
        for (i, t) in a.iter().enumerate() {
            if let Some(t) = t.as_table() {
                tables.push((format!("stator.{i}"), t));
            }
        }
    }
    tables.into_iter().find_map(|(at, t)| {
        let kind = t.get("kind").and_then(|k| k.as_str())?;
        let (key, m) = match (at.as_str(), kind) {
            ("rotor", "fe") => inner::<FeRotorSpec>(t),
            ("rotor", "jeffcott") => inner::<JeffcottSpec>(t),
            (_, "rod") if at != "rotor" => inner::<RodSpec>(t),
            (_, "ring") if at != "rotor" => inner::<RingSpec>(t),
            (_, "fe") if at != "rotor" => inner::<FeStatorSpec>(t),
            (_, "mesh") if at != "rotor" => inner::<MeshStatorSpec>(t),
            _ => None,
        }?;
        // An unknown key directly in the tagged table is named with its line by `parse_error`;
        // one in a sub-table (`[[rotor.unbalance]]`, `[[rotor.shaft]]`) is not, so name its
        // whole dotted key here.
        let nested = key.as_ref().is_some_and(|k| k.contains('.'));
        (m == message && (nested || !message.starts_with("unknown field"))).then(|| {
            let key = key.map(|k| format!("{at}.{k}")).unwrap_or(at);
            invalid_at(path, source, &key, format!("{m}{after}"))
        })
    })
}

/// A TOML/serde error in the file's own text. In a `kind`-tagged table (`[rotor]`,
/// `[[stator]]`) serde reports an unknown key at the table header; name the key's own line too.
fn parse_error(path: &Path, source: &str, e: toml::de::Error) -> SceneError {
    let mut message = e.to_string().trim_end().to_string();
    let key = e
        .message()
        .strip_prefix("unknown field `")
        .and_then(|r| r.split('`').next());
    if let (Some(span), Some(key)) = (e.span(), key) {
        let header = source[..span.start.min(source.len())].matches('\n').count();
        let is_header = |l: &str| {
            let l = l.trim_start();
            let name = l.trim_start_matches('[').trim_start();
            l.starts_with('[') && name.starts_with(|c: char| c.is_ascii_alphabetic() || c == '"')
        };
        let is_key = |l: &str| {
            let r = l.trim_start().strip_prefix(key).map(str::trim_start);
            r.is_some_and(|r| r.starts_with(['=', '.']))
        };
        let found = source
            .lines()
            .enumerate()
            .skip(header + 1)
            .take_while(|(_, l)| !is_header(l))
            .find(|(_, l)| is_key(l));
        if let Some((n, _)) = found {
            message.push_str(&format!("\n`{key}` is on line {}", n + 1));
        }
    }
    SceneError::Parse {
        file: path.to_path_buf(),
        message,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const OK: &str = r#"
title = "t"
[rotor]
kind = "jeffcott"
mass = 2.0
stiffness = 8.0e4
damping_ratio = 0.2
[[rotor.unbalance]]
mass = 0.01
radius = 0.05

[[station]]
name = "disk"
radius = 0.06
friction = 0.1

[[stator]]
kind = "rod"
name = "rod"
station = "disk"
clearance_nd = 0.6
length = 0.04
area = 25e-6
stiffness_ratio = 25

[run]
speed_ratio = 1.7
"#;

    fn p(text: &str, ov: &[&str]) -> Result<LoadedScene, SceneError> {
        let ov: Vec<String> = ov.iter().map(|s| s.to_string()).collect();
        parse(Path::new("scene.toml"), text, &ov)
    }

    #[test]
    fn parses_a_valid_scene() {
        let s = p(OK, &[]).unwrap();
        assert_eq!(s.scene.stators.len(), 1);
        assert_eq!(s.scene.run.integrator(), IntegratorKind::Collocated);
    }

    #[test]
    fn unknown_key_names_line() {
        let bad = OK.replace("radius = 0.06", "radius = 0.06\nfrobnicate = 1");
        let e = p(&bad, &[]).unwrap_err().to_string();
        assert!(e.contains("frobnicate"), "{e}");
        assert!(e.contains("line 15"), "{e}");
    }

    #[test]
    fn negative_mass_names_key_and_line() {
        let bad = OK.replace("mass = 2.0", "mass = -2.0");
        let e = p(&bad, &[]).unwrap_err().to_string();
        assert!(
            e.contains("rotor.mass") && e.contains("scene.toml:5"),
            "{e}"
        );
    }

    #[test]
    fn clearance_in_array_of_tables_is_located() {
        let bad = OK.replace("clearance_nd = 0.6", "clearance_nd = -0.6");
        let e = p(&bad, &[]).unwrap_err().to_string();
        assert!(
            e.contains("stator.0.clearance_nd") && e.contains(":21"),
            "{e}"
        );
    }

    #[test]
    fn override_changes_values_and_is_validated() {
        let s = p(OK, &["stator.0.clearance_nd=0.3", "run.speed_ratio=2.5"]).unwrap();
        match &s.scene.stators[0] {
            StatorSpec::Rod(r) => assert_eq!(r.clearance_nd, Some(0.3)),
            _ => panic!(),
        }
        assert_eq!(s.scene.run.speed_ratio, Some(2.5));
        let e = p(OK, &["station.0.friction=-1"]).unwrap_err().to_string();
        assert!(e.contains("station.0.friction"), "{e}");
        let e = p(OK, &["stator.3.clearance=1"]).unwrap_err().to_string();
        assert!(e.contains("out of range"), "{e}");
    }

    #[test]
    fn missing_section_is_named() {
        let bad = OK.replace("[run]\nspeed_ratio = 1.7", "");
        let e = p(&bad, &[]).unwrap_err().to_string();
        assert!(e.contains("run"), "{e}");
    }
}
