//! Shards: one part of a study run on its own (`--shard i/n`, or a Slurm array task whose
//! variables the caller hands in — the library reads no environment), and the shard folders
//! of an output directory.

use super::store::CASES_DIR;
use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

/// One part of a study run on its own (`--shard i/n`): the cases whose index k (in the order
/// of [`super::cases`]) has `k mod n = i − 1`, so every shard gets cases from the whole range.
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

    /// Whether the case of index `k` (order of [`super::cases`]) belongs to this shard.
    pub fn contains(&self, k: usize) -> bool {
        k % self.count == self.index - 1
    }

    /// The shard's folder inside the study's output directory: `shard-<i>-of-<n>`.
    pub fn folder(&self) -> String {
        format!("shard-{}-of-{}", self.index, self.count)
    }
}

/// The `shard-*` folders of `dir` that hold a case store, sorted.
pub fn shard_folders(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("shard-"))
                && p.join(CASES_DIR).is_dir()
        })
        .collect();
    v.sort();
    v
}

/// The shard counts n of the `shard-<i>-of-<n>` folders in `dir`, ascending.
pub fn shard_counts(dir: &Path) -> Vec<usize> {
    let mut v: Vec<usize> = shard_folders(dir)
        .iter()
        .filter_map(|p| {
            let name = p.file_name()?.to_string_lossy().into_owned();
            name.rsplit_once("-of-")?.1.parse().ok()
        })
        .collect();
    v.sort_unstable();
    v.dedup();
    v
}
