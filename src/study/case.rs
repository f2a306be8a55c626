//! The cases of a study: every speed of every variant, each named by a typed, stable id.

use super::variant::Variant;
use serde::{Deserialize, Serialize};
use std::fmt;

/// The stable id of a case: the variant's overrides, then `speed_ratio=ν`, comma-separated
/// (`stator.0.clearance_nd=0.4,speed_ratio=1.7`); characters `[A-Za-z0-9._=,+-]` only. It
/// names the case's file in the store (`cases/<id>.toml`) and its kept time series; it is
/// written to the case file as a plain string.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(transparent)]
pub struct CaseId(String);

impl CaseId {
    /// The id of the case of `variant` at ν = `speed_ratio` (ω/ω_n).
    pub fn new(variant: &Variant, speed_ratio: f64) -> Self {
        let mut parts = variant.overrides.clone();
        parts.push(format!(
            "speed_ratio={}",
            crate::scene::toml_number(speed_ratio)
        ));
        Self(parts.join(","))
    }

    /// The id of segment `index` (0-based) of a continuation split into `count` segments
    /// (`crate::study::segments`): `segment=<index + 1>-of-<count>`.
    pub fn segment(index: usize, count: usize) -> Self {
        Self(format!("segment={}-of-{count}", index + 1))
    }

    /// The id as text.
    pub fn as_str(&self) -> &str {
        &self.0
    }
}

impl fmt::Display for CaseId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

/// One case of a sweep or map: a variant of the scene at one speed, named by its parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseSpec {
    /// Index k of the case in the study's order ([`cases`]): what shards split by.
    pub index: usize,
    /// Index of its variant in the study's variants.
    pub variant: usize,
    /// Index of its speed in the study's speeds (the speeds the step choice was made for:
    /// [`crate::analysis::RunSettings::request_at`]).
    pub speed: usize,
    /// ω/ω_n.
    pub speed_ratio: f64,
    /// Its stable id.
    pub id: CaseId,
}

/// The cases of a study: every speed of every variant, variant-major (the order of the
/// tables).
pub fn cases(variants: &[Variant], speeds: &[f64]) -> Vec<CaseSpec> {
    variants
        .iter()
        .enumerate()
        .flat_map(|(i, var)| speeds.iter().enumerate().map(move |(j, &v)| (i, var, j, v)))
        .enumerate()
        .map(|(k, (i, var, j, v))| CaseSpec {
            index: k,
            variant: i,
            speed: j,
            speed_ratio: v,
            id: CaseId::new(var, v),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn case_ids_name_the_overrides_then_the_speed_variant_major() {
        let vs = super::super::variant::variants(Some(&crate::scene::VarySpec {
            key: "stator.0.clearance_nd".into(),
            values: vec![0.4, 1.0],
        }));
        let cs = cases(&vs, &[1.5, 2.0]);
        let ids: Vec<&str> = cs.iter().map(|c| c.id.as_str()).collect();
        assert_eq!(
            ids,
            [
                "stator.0.clearance_nd=0.4,speed_ratio=1.5",
                "stator.0.clearance_nd=0.4,speed_ratio=2",
                "stator.0.clearance_nd=1,speed_ratio=1.5",
                "stator.0.clearance_nd=1,speed_ratio=2",
            ]
        );
        assert_eq!(cs.iter().map(|c| c.index).collect::<Vec<_>>(), [0, 1, 2, 3]);
        assert_eq!(cs[2].variant, 1);
    }
}
