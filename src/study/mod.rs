//! Studies made of cases — a speed sweep (`[run.sweep]`, once or per value of
//! `[run.sweep.vary]`) and a 2-D map (`[run.map]`) — as a library API: the stage above
//! [`crate::analysis`] (one speed) and beside [`crate::output`] and [`crate::results`] (files),
//! which it uses.
//!
//! A study is its *variants* of the scene ([`Variant`]: the `[run.sweep.vary]` overrides, or a
//! map's axes) × its speeds; each pair is a *case* named by a typed, stable [`CaseId`]
//! ([`cases`]). [`run()`] (a [`StudyRequest`]) runs the cases still missing — all, or one
//! [`Shard`] of them — through the one parallel map ([`crate::analysis::sweep::run_all`]),
//! each written to the output directory's case store ([`CaseStore`]) as soon as it is done,
//! so that a killed study resumes where it stopped. [`results`] gives every case for the
//! tables and pictures — those the run computed from memory, the others read back; [`Merged`] gathers the stores of a sharded study (`rubsim merge`) so
//! that they are assembled exactly as a one-machine run's. [`summary`] holds the typed
//! `summary.json` records of the study commands.
//!
//! The library reads no environment: a Slurm array's variables are handed in
//! ([`Shard::from_slurm`]), and what a run reports while it runs goes to the caller's
//! [`Progress`].

pub mod assemble;
pub mod case;
pub mod merge;
pub mod overlay;
pub mod packed;
pub mod run;
pub mod segment_spec;
pub mod segments;
pub mod series;
pub mod shard;
pub mod single;
pub mod store;
pub mod summary;
pub mod thermal_map;
pub mod variant;

pub use case::{cases, CaseId, CaseSpec};
pub use merge::{merge_folders, results, Merged};
pub use run::{
    run, run_cases, run_settings, shooting_settings, CasesRequest, Computed, Progress, Quiet,
    StudyRequest, StudyRun,
};
pub use series::SeriesPlan;
pub use shard::{shard_counts, shard_folders, Shard};
pub use store::{scene_hash, CaseRecord, CaseStore, StorePlan, CASES_DIR};
pub use variant::{map_variants, variants, MapAxes, Variant};

use crate::analysis::sweep::{cascade_max, SweepKeep};
use crate::analysis::{sweep_speeds, Keep};
use crate::error::{Error, Result};
use crate::scene::LoadedScene;

/// The two studies made of cases.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// `[run.sweep]`: speeds, once or per value of `[run.sweep.vary]`.
    Sweep,
    /// `[run.map]`: two parameters.
    Map,
}

impl Kind {
    /// The command's name (`sweep`, `map`).
    pub fn name(self) -> &'static str {
        match self {
            Kind::Sweep => "sweep",
            Kind::Map => "map",
        }
    }

    /// The kind of a command's name; `None` for another name.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "sweep" => Some(Kind::Sweep),
            "map" => Some(Kind::Map),
            _ => None,
        }
    }
}

/// A study: its variants of the scene and its speeds; the cases are every speed of every
/// variant ([`Study::cases`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Study {
    /// Which command.
    pub kind: Kind,
    /// The variants (overrides) of the scene.
    pub variants: Vec<Variant>,
    /// The speeds ω/ω_n of every variant.
    pub speeds: Vec<f64>,
    /// A map's axes, else `None`.
    pub map: Option<MapAxes>,
}

impl Study {
    /// The study a scene describes for `kind`; `wn` (ω_n, rad/s) turns a map's `run.speed`
    /// into ω/ω_n.
    ///
    /// # Errors
    /// [`Error::Study`] naming the scene file: no `[run.sweep]` for a sweep, no `[run.map]` or
    /// no speed for a map.
    pub fn of(ls: &LoadedScene, wn: Option<f64>, kind: Kind) -> Result<Self> {
        match kind {
            Kind::Sweep => {
                let spec = ls.scene.run.sweep.as_ref().ok_or_else(|| {
                    Error::study(
                        ls.file.display(),
                        "`rubsim sweep` needs a [run.sweep] table",
                    )
                })?;
                Ok(Self {
                    kind,
                    variants: variants(spec.vary.as_ref()),
                    speeds: sweep_speeds(spec.from, spec.to, spec.step),
                    map: None,
                })
            }
            Kind::Map => {
                let (variants, speeds, axes) = map_variants(ls, wn)?;
                Ok(Self {
                    kind,
                    variants,
                    speeds,
                    map: Some(axes),
                })
            }
        }
    }

    /// The cases of the study, variant-major.
    pub fn cases(&self) -> Vec<CaseSpec> {
        cases(&self.variants, &self.speeds)
    }

    /// What the case at ν = `v` keeps for the pictures (a sweep's orbits, force histories and
    /// spectrum up to the cascade's top; a map's nothing beyond its numbers).
    pub fn keep(&self, ls: &LoadedScene, v: f64) -> Keep {
        match self.kind {
            Kind::Sweep => {
                let o = &ls.scene.output;
                SweepKeep::new(o, cascade_max(o, &self.speeds)).at(v)
            }
            Kind::Map => Keep::default(),
        }
    }
}
