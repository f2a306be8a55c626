//! A speed sweep: the speeds, the parameter variants of `[run.sweep.vary]`, what each speed
//! keeps for the pictures, and the one parallel map [`sweep`] that runs a per-speed closure.

use super::{Keep, SpeedResults};
use crate::error::{Error, Result};
use crate::scene::{OutputSpec, VarySpec};
use rayon::prelude::*;
use serde::Serialize;

/// The speeds of a sweep (inclusive, rounded to the step's decimals to avoid drift).
pub fn sweep_speeds(from: f64, to: f64, step: f64) -> Vec<f64> {
    crate::scene::inclusive_range(from, to, step)
}

/// Per-speed results of a sweep, in speed order, and its wall time.
#[derive(Debug, Clone, Serialize)]
pub struct Sweep<T> {
    /// Per-speed results, in speed order.
    pub speeds: Vec<T>,
    /// Wall time of the whole sweep (s).
    pub wall_s: f64,
}

/// Results of a sweep of runs at one speed each.
pub type SweepResults = Sweep<SpeedResults>;

impl SweepResults {
    /// Steps of the main runs (companion runs of the error estimate excluded).
    pub fn total_steps(&self) -> usize {
        self.speeds.iter().map(|r| r.stats.steps).sum()
    }
    /// Largest estimated relative orbit-extents error over the speeds (0 when not estimated).
    pub fn max_estimated_error(&self) -> f64 {
        self.speeds
            .iter()
            .filter_map(|r| r.error.map(|e| e.extents_rel))
            .fold(0.0, f64::max)
    }
}

impl<A, B> Sweep<(A, B)> {
    /// Splits a sweep of pairs into a sweep of the first items (same wall time) and the second
    /// items, in speed order.
    pub fn unzip(self) -> (Sweep<A>, Vec<B>) {
        let (a, b) = self.speeds.into_iter().unzip();
        (
            Sweep {
                speeds: a,
                wall_s: self.wall_s,
            },
            b,
        )
    }
}

/// Runs `run(ω/ω_n)` for every speed in parallel (rayon), e.g. [`super::prepare`] then
/// [`super::Prepared::run`] with the sinks that speed wants; `progress` is called after each
/// speed. A failing speed fails the sweep with [`Error::AtSpeed`] naming it.
pub fn sweep<T: Send>(
    speeds: &[f64],
    run: &(dyn Fn(f64) -> Result<T> + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<Sweep<T>> {
    let t0 = std::time::Instant::now();
    let speeds = run_all(
        speeds,
        &|&v| {
            run(v).map_err(|e| Error::AtSpeed {
                speed_ratio: v,
                source: Box::new(e),
            })
        },
        progress,
    )?;
    Ok(Sweep {
        speeds,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}

/// The one parallel map (rayon) of sweeps and maps: `run` on every item, `progress` after
/// each; every item runs even when one fails, and the first failure (in item order) is
/// returned.
pub fn run_all<C: Sync, T: Send>(
    items: &[C],
    run: &(dyn Fn(&C) -> Result<T> + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<T>> {
    let res: Vec<Result<T>> = items
        .par_iter()
        .map(|c| {
            let r = run(c);
            progress();
            r
        })
        .collect();
    res.into_iter().collect()
}

/// One case of a sweep or map: a variant of the scene at one speed, named by its parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseSpec {
    /// Index of its variant in the study's variants.
    pub variant: usize,
    /// ω/ω_n.
    pub speed_ratio: f64,
    /// Stable id: the variant's overrides, then `speed_ratio=ν`, comma-separated
    /// (`stator.0.clearance_nd=0.4,speed_ratio=1.7`); characters `[A-Za-z0-9._=,+-]` only.
    pub id: String,
}

/// The id of the case of `variant` at ν = `speed`.
pub fn case_id(variant: &Variant, speed: f64) -> String {
    let mut parts = variant.overrides.clone();
    parts.push(format!("speed_ratio={}", crate::scene::toml_number(speed)));
    parts.join(",")
}

/// The cases of a study: every speed of every variant, variant-major (the order of the
/// tables).
pub fn cases(variants: &[Variant], speeds: &[f64]) -> Vec<CaseSpec> {
    variants
        .iter()
        .enumerate()
        .flat_map(|(i, var)| {
            speeds.iter().map(move |&v| CaseSpec {
                variant: i,
                speed_ratio: v,
                id: case_id(var, v),
            })
        })
        .collect()
}

/// One part of a study run on its own (`--shard i/n`): the cases whose index k (in the order
/// of [`cases`]) has `k mod n = i − 1`, so every shard gets cases from the whole range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// 1-based index i.
    pub index: usize,
    /// Number of shards n.
    pub count: usize,
}

impl Shard {
    /// Parses `i/n` (1 ≤ i ≤ n).
    ///
    /// # Errors
    /// [`Error::Shard`] naming what was given.
    pub fn parse(text: &str) -> Result<Self> {
        let bad = |m: &str| Error::Shard {
            given: format!("--shard {text}"),
            message: m.to_string(),
        };
        let (i, n) = text
            .split_once('/')
            .ok_or_else(|| bad("expected i/n, e.g. 3/8 (shard 3 of 8)"))?;
        let num = |s: &str, what: &str| {
            s.trim()
                .parse::<usize>()
                .map_err(|_| bad(&format!("{what} `{s}` is not a whole number")))
        };
        Self::new(num(i, "the index")?, num(n, "the count")?).map_err(|m| bad(&m))
    }

    /// Shard `index` of `count`, or why not (index out of 1 ..= count).
    fn new(index: usize, count: usize) -> std::result::Result<Self, String> {
        if count == 0 {
            return Err("the number of shards must be at least 1".into());
        }
        if index == 0 || index > count {
            return Err(format!(
                "shard index {index} is out of range: shards are numbered 1 to {count}"
            ));
        }
        Ok(Self { index, count })
    }

    /// The shard of a Slurm array task, from `SLURM_ARRAY_TASK_ID`, `SLURM_ARRAY_TASK_MIN`
    /// and `SLURM_ARRAY_TASK_COUNT` (read through `var`): i = ID − MIN + 1, n = COUNT. `None`
    /// outside an array job. An array that is not contiguous (`--array=3,5`, a step) is
    /// refused: its tasks do not number the shards; give `--shard i/n` then.
    ///
    /// # Errors
    /// [`Error::Shard`] naming the variables.
    pub fn from_slurm(var: impl Fn(&str) -> Option<String>) -> Result<Option<Self>> {
        let Some(id) = var("SLURM_ARRAY_TASK_ID") else {
            return Ok(None);
        };
        let get = |k: &str| var(k).and_then(|v| v.trim().parse::<usize>().ok());
        let given = format!(
            "SLURM_ARRAY_TASK_ID={id}, SLURM_ARRAY_TASK_MIN={}, SLURM_ARRAY_TASK_MAX={}, \
             SLURM_ARRAY_TASK_COUNT={}",
            var("SLURM_ARRAY_TASK_MIN").unwrap_or_default(),
            var("SLURM_ARRAY_TASK_MAX").unwrap_or_default(),
            var("SLURM_ARRAY_TASK_COUNT").unwrap_or_default()
        );
        let bad = |m: String| Error::Shard {
            given: given.clone(),
            message: m,
        };
        let (Some(id), Some(min), Some(count)) = (
            get("SLURM_ARRAY_TASK_ID"),
            get("SLURM_ARRAY_TASK_MIN"),
            get("SLURM_ARRAY_TASK_COUNT"),
        ) else {
            return Err(bad(
                "a Slurm array task without readable task numbers".into()
            ));
        };
        let max = get("SLURM_ARRAY_TASK_MAX").unwrap_or(min + count.saturating_sub(1));
        let step = get("SLURM_ARRAY_TASK_STEP").unwrap_or(1);
        if step != 1 || max + 1 != min + count || id < min {
            return Err(bad(
                "the array's tasks are not contiguous, so they do not number the shards; \
                 pass --shard i/n explicitly"
                    .into(),
            ));
        }
        Self::new(id - min + 1, count).map(Some).map_err(bad)
    }

    /// Whether the case of index `k` (order of [`cases`]) belongs to this shard.
    pub fn contains(&self, k: usize) -> bool {
        k % self.count == self.index - 1
    }

    /// The shard's folder inside the study's output directory: `shard-<i>-of-<n>`.
    pub fn folder(&self) -> String {
        format!("shard-{}-of-{}", self.index, self.count)
    }
}

/// One sweep of a parameter study (`[run.sweep.vary]`): the overrides it adds and the
/// sub-folder its files go to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Variant {
    /// Sub-folder of its files: `""` for a plain sweep, else `<last key segment>_<value>/`.
    pub prefix: String,
    /// Overrides added to the command line's (`key=value`); empty for a plain sweep.
    pub overrides: Vec<String>,
}

impl Variant {
    /// True for the plain sweep (no override added).
    pub fn is_base(&self) -> bool {
        self.overrides.is_empty()
    }

    /// The overrides as shown to the user: `key=value, …`.
    pub fn label(&self) -> String {
        self.overrides.join(", ")
    }

    /// The pictures' title: the scene's, with the overrides in brackets for a variant.
    pub fn title(&self, scene_title: &str) -> String {
        if self.is_base() {
            scene_title.to_string()
        } else {
            format!("{scene_title} [{}]", self.label())
        }
    }
}

/// The sweeps of a scene: one plain sweep, or one per value of `[run.sweep.vary]`.
pub fn variants(vary: Option<&VarySpec>) -> Vec<Variant> {
    match vary {
        None => vec![Variant {
            prefix: String::new(),
            overrides: Vec::new(),
        }],
        Some(v) => v
            .values
            .iter()
            .map(|x| {
                let name = v.key.rsplit('.').next().unwrap_or("value");
                Variant {
                    prefix: format!("{name}_{x}/"),
                    overrides: vec![format!("{}={}", v.key, crate::scene::toml_number(*x))],
                }
            })
            .collect(),
    }
}

/// Upper frequency of a sweep's cascade (f/ω_n): `output.cascade_max_freq`, by default the
/// top speed (at least 1).
pub fn cascade_max(output: &OutputSpec, speeds: &[f64]) -> f64 {
    output
        .cascade_max_freq
        .unwrap_or_else(|| speeds.iter().cloned().fold(1.0, f64::max))
}

/// The orbit grids drawn: `output.orbit_grids`, by default one grid of up to 9 speeds spread
/// evenly over the sweep.
pub fn orbit_grids(output: &OutputSpec, speeds: &[f64]) -> Vec<Vec<f64>> {
    if output.orbit_grids.is_empty() {
        let n = speeds.len();
        vec![(0..9.min(n)).map(|i| speeds[i * (n - 1) / 8]).collect()]
    } else {
        output.orbit_grids.clone()
    }
}

/// What each speed of a sweep keeps for the pictures: the orbit at the speeds of the orbit
/// grids and force histories (at every speed when none is listed), the force history at the
/// speeds of `output.force_histories`, the spectrum up to the cascade's top frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepKeep {
    orbits: Vec<f64>,
    force_histories: Vec<f64>,
    spectrum_up_to: u32,
}

impl SweepKeep {
    /// From the scene's `[output]` and the cascade's top frequency `cascade_max` (f/ω_n).
    pub fn new(output: &OutputSpec, cascade_max: f64) -> Self {
        Self {
            orbits: output
                .orbit_grids
                .iter()
                .flatten()
                .chain(output.force_histories.iter())
                .copied()
                .collect(),
            force_histories: output.force_histories.clone(),
            spectrum_up_to: cascade_max.ceil() as u32,
        }
    }

    /// What the speed ν = `v` keeps.
    pub fn at(&self, v: f64) -> Keep {
        Keep {
            orbit: self.orbits.iter().any(|w| (w - v).abs() < 1e-6) || self.orbits.is_empty(),
            force_history: self.force_histories.iter().any(|w| (w - v).abs() < 1e-6),
            spectrum_up_to: Some(self.spectrum_up_to),
            full_spectrum: false,
        }
    }
}
