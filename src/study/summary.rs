//! The typed `summary.json` records of the study commands: a sweep ([`SweepBody`]), a map
//! ([`MapBody`]) and a shard ([`ShardBody`]), each the body of an
//! [`crate::output::summary::Summary`].

use super::store::CaseStore;
use super::variant::{MapAxes, Variant};
use super::{Study, CASES_DIR};
use crate::analysis::{regime_class, RegimeRange, SpeedResults, SweepResults, REGIME_CLASSES};
use serde::Serialize;
use std::collections::BTreeMap;

/// The summary of `rubsim sweep`.
#[derive(Debug, Clone, Serialize)]
pub struct SweepBody<'a> {
    /// One record per variant (one for a plain sweep).
    pub sweeps: Vec<SweepRecord<'a>>,
    /// The cases the tables were assembled from.
    pub cases: CasesRecord,
    /// Wall time of the command (s).
    pub wall_s: f64,
}

/// The summary of `rubsim map`.
#[derive(Debug, Clone, Serialize)]
pub struct MapBody {
    /// The map.
    pub map: MapRecord,
    /// The cases the tables were assembled from.
    pub cases: CasesRecord,
    /// Wall time of the command (s).
    pub wall_s: f64,
}

/// The summary of one shard of a sweep or map (`rubsim sweep --shard i/n`).
#[derive(Debug, Clone, Serialize)]
pub struct ShardBody {
    /// Which shard and what it ran.
    pub shard: ShardRecord,
    /// Wall time of the command (s).
    pub wall_s: f64,
}

/// One sweep of a study (`sweeps[i]` of a sweep's summary).
#[derive(Debug, Clone, Serialize)]
pub struct SweepRecord<'a> {
    /// The variant's overrides (`key=value`); empty for a plain sweep.
    pub variant: &'a [String],
    /// Its sub-folder (`""` for a plain sweep).
    pub directory: &'a str,
    /// Sum of the runs' wall times (s).
    pub wall_s: f64,
    /// Steps of the main runs.
    pub steps: usize,
    /// Largest estimated relative orbit-extents error (0 when not estimated).
    pub max_estimated_extents_error: f64,
    /// The speeds (ω/ω_n) whose steady state was not proven.
    pub unsteady_speeds: Vec<f64>,
    /// The speeds (ω/ω_n) whose step was refined after the run, their own error estimate having
    /// missed `run.tolerance` at the chosen step (each speed's `step_refinement` says why).
    pub refined_speeds: Vec<f64>,
    /// The speed ranges of one regime.
    pub regimes: &'a [RegimeRange],
    /// Quasi-resonance peaks: (Poincaré period, ω/ω_n).
    pub quasi_resonances: &'a [(usize, f64)],
    /// Every speed's results.
    pub speeds: &'a [SpeedResults],
}

impl<'a> SweepRecord<'a> {
    /// The record of `variant`'s sweep `res`, its regimes and peaks.
    pub fn new(
        variant: &'a Variant,
        res: &'a SweepResults,
        regimes: &'a [RegimeRange],
        peaks: &'a [(usize, f64)],
    ) -> Self {
        Self {
            variant: &variant.overrides,
            directory: &variant.prefix,
            wall_s: res.wall_s,
            steps: res.total_steps(),
            max_estimated_extents_error: res.max_estimated_error(),
            unsteady_speeds: res
                .speeds
                .iter()
                .filter(|r| !r.steady)
                .map(|r| r.speed_ratio)
                .collect(),
            refined_speeds: res
                .speeds
                .iter()
                .filter(|r| r.step_refinement.is_some())
                .map(|r| r.speed_ratio)
                .collect(),
            regimes,
            quasi_resonances: peaks,
            speeds: &res.speeds,
        }
    }
}

/// One axis of a map.
#[derive(Debug, Clone, Serialize)]
pub struct AxisRecord {
    /// `speed_ratio` or a dotted scene key.
    pub key: String,
    /// Its values.
    pub values: Vec<f64>,
}

/// A map (`map` of a map's summary).
#[derive(Debug, Clone, Serialize)]
pub struct MapRecord {
    /// The horizontal axis.
    pub x: AxisRecord,
    /// The vertical axis.
    pub y: AxisRecord,
    /// The single speed (ω/ω_n) of a map of two scene keys; `null` with a speed axis.
    pub speed_ratio: Option<f64>,
    /// Number of cases (cells).
    pub cases: usize,
    /// Cells per regime class (classes with no cell left out).
    pub regime_cells: BTreeMap<String, usize>,
}

impl MapRecord {
    /// The record of the map `axes` of `study`, whose cells hold `runs`.
    pub fn new(axes: &MapAxes, study: &Study, runs: &[SpeedResults]) -> Self {
        Self {
            x: AxisRecord {
                key: axes.keys[0].clone(),
                values: axes.values[0].clone(),
            },
            y: AxisRecord {
                key: axes.keys[1].clone(),
                values: axes.values[1].clone(),
            },
            speed_ratio: if axes.speed.is_none() {
                study.speeds.first().copied()
            } else {
                None
            },
            cases: runs.len(),
            regime_cells: regime_cells(runs)
                .into_iter()
                .map(|(name, n)| (name.to_string(), n))
                .collect(),
        }
    }
}

/// The cells of `runs` per regime class (`analysis::REGIME_CLASSES`, in that order), the
/// classes with no cell left out.
pub fn regime_cells(runs: &[SpeedResults]) -> Vec<(&'static str, usize)> {
    let mut counts = vec![0usize; REGIME_CLASSES.len()];
    for r in runs {
        counts[regime_class(r)] += 1;
    }
    REGIME_CLASSES
        .iter()
        .zip(counts)
        .filter(|(_, n)| *n > 0)
        .map(|(name, n)| (*name, n))
        .collect()
}

/// The cases a study's tables were assembled from.
#[derive(Debug, Clone, Serialize)]
pub struct CasesRecord {
    /// Number of cases.
    pub count: usize,
    /// Scene hash of the stores (`null` without a store).
    pub scene_hash: Option<String>,
    /// The store folders read.
    pub folders: Vec<String>,
}

impl CasesRecord {
    /// The record of `count` cases read from `stores`.
    pub fn new(count: usize, stores: &[&CaseStore]) -> Self {
        Self {
            count,
            scene_hash: stores.first().map(|s| s.plan().scene_hash.clone()),
            folders: stores
                .iter()
                .map(|s| s.dir().display().to_string())
                .collect(),
        }
    }
}

/// What a shard ran.
#[derive(Debug, Clone, Serialize)]
pub struct ShardRecord {
    /// Its 1-based index i.
    pub index: usize,
    /// The number of shards n.
    pub count: usize,
    /// Cases of this shard.
    pub cases: usize,
    /// Cases computed by this run (the others were finished already).
    pub computed: usize,
    /// Cases of the whole study.
    pub study_cases: usize,
    /// The folder of the case files in the shard's folder.
    pub cases_dir: &'static str,
}

impl ShardRecord {
    /// The record of shard `shard`'s run `ran`.
    pub fn new(shard: super::Shard, ran: &super::StudyRun) -> Self {
        Self {
            index: shard.index,
            count: shard.count,
            cases: ran.mine,
            computed: ran.computed,
            study_cases: ran.cases,
            cases_dir: CASES_DIR,
        }
    }
}
