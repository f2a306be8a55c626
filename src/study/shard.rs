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
    /// refused: its tasks do not number the shards; give `--shard i/n` then. Every number is
    /// read whole and combined with checked arithmetic: a value that is not a whole number,
    /// or whose sums would wrap around, is refused naming the variable, never run as some
    /// other shard.
    ///
    /// # Errors
    /// [`Error::Shard`] naming the variables.
    pub fn from_slurm(var: impl Fn(&str) -> Option<String>) -> Result<Option<Self>> {
        if var("SLURM_ARRAY_TASK_ID").is_none() {
            return Ok(None);
        }
        // The four variables, and SLURM_ARRAY_TASK_STEP when it is set (a step ≠ 1 is refused
        // as not contiguous: the error then shows it).
        let mut names = vec![
            "SLURM_ARRAY_TASK_ID",
            "SLURM_ARRAY_TASK_MIN",
            "SLURM_ARRAY_TASK_MAX",
            "SLURM_ARRAY_TASK_COUNT",
        ];
        if var("SLURM_ARRAY_TASK_STEP").is_some() {
            names.push("SLURM_ARRAY_TASK_STEP");
        }
        let given = names
            .iter()
            .map(|k| format!("{k}={}", var(k).unwrap_or_default()))
            .collect::<Vec<_>>()
            .join(", ");
        let bad = |m: String| Error::Shard {
            given: given.clone(),
            message: m,
        };
        // `None` when unset; an error when set but not a whole number.
        let get = |k: &str| -> Result<Option<usize>> {
            var(k)
                .map(|v| {
                    v.trim().parse::<usize>().map_err(|_| {
                        bad(format!(
                            "{k}=`{v}` is not a whole number from 0 to {}",
                            usize::MAX
                        ))
                    })
                })
                .transpose()
        };
        let (Some(id), Some(min), Some(count)) = (
            get("SLURM_ARRAY_TASK_ID")?,
            get("SLURM_ARRAY_TASK_MIN")?,
            get("SLURM_ARRAY_TASK_COUNT")?,
        ) else {
            return Err(bad(
                "a Slurm array task without SLURM_ARRAY_TASK_MIN and SLURM_ARRAY_TASK_COUNT".into(),
            ));
        };
        let not_contiguous = || {
            bad(
                "the array's tasks are not contiguous, so they do not number the shards; \
                 pass --shard i/n explicitly"
                    .into(),
            )
        };
        // MIN + COUNT − 1, the last task of a contiguous array; past usize::MAX it is none.
        let last = count
            .checked_sub(1)
            .and_then(|c| min.checked_add(c))
            .ok_or_else(|| {
                bad(format!(
                    "SLURM_ARRAY_TASK_MIN + SLURM_ARRAY_TASK_COUNT − 1 = {min} + {count} − 1 \
                     is not a task number (COUNT must be at least 1 and the sum at most {})",
                    usize::MAX
                ))
            })?;
        let max = get("SLURM_ARRAY_TASK_MAX")?.unwrap_or(last);
        let step = get("SLURM_ARRAY_TASK_STEP")?.unwrap_or(1);
        if step != 1 || max != last {
            return Err(not_contiguous());
        }
        if !(min..=max).contains(&id) {
            return Err(bad(format!(
                "the task ID {id} is outside the array's tasks {min} to {max}"
            )));
        }
        // id − min < count ≤ usize::MAX, so the index is count at most.
        Self::new(id - min + 1, count).map(Some).map_err(bad)
    }

    /// Whether the case of index `k` (order of [`super::cases`]) belongs to this shard.
    pub fn contains(&self, k: usize) -> bool {
        k % self.count == self.index - 1
    }

    /// Refuses more shards than the `total` items to share (`what`: "the study has 5 cases").
    ///
    /// # Errors
    /// [`Error::Shard`] naming the shard and `what`.
    pub fn check_count(self, total: usize, what: &str) -> Result<()> {
        if self.count > total {
            return Err(Error::Shard {
                given: format!("--shard {}/{}", self.index, self.count),
                message: format!("{what}, fewer than {} shards", self.count),
            });
        }
        Ok(())
    }

    /// The shard's folder inside the study's output directory: `shard-<i>-of-<n>`.
    pub fn folder(&self) -> String {
        format!("shard-{}-of-{}", self.index, self.count)
    }
}

/// For each shard count `n` of `counts`, the line naming the shards of `n` that hold the
/// missing items of `indices` (item k in shard k mod n + 1) and the Slurm array that reruns
/// them: what a merge with items missing tells its user.
pub fn rerun_hint(indices: &[usize], counts: &[usize]) -> String {
    let mut msg = String::new();
    for n in counts.iter().filter(|n| **n > 0) {
        let mut shards: Vec<usize> = indices.iter().map(|k| k % n + 1).collect();
        shards.sort_unstable();
        shards.dedup();
        let list: Vec<String> = shards.iter().map(|s| s.to_string()).collect();
        msg.push_str(&format!(
            "\nthey belong to shards {} of {n}: run those again (Slurm: sbatch --array={} …)",
            list.join(", "),
            list.join(",")
        ));
    }
    msg
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

#[cfg(test)]
mod tests {
    use super::*;

    fn slurm(vars: &[(&str, &str)]) -> Result<Option<Shard>> {
        Shard::from_slurm(|k| {
            vars.iter()
                .find(|(n, _)| *n == k)
                .map(|(_, v)| (*v).to_string())
        })
    }

    #[test]
    fn a_contiguous_array_numbers_the_shards() {
        let s = slurm(&[
            ("SLURM_ARRAY_TASK_ID", "1"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "2"),
            ("SLURM_ARRAY_TASK_COUNT", "3"),
        ]);
        assert_eq!(s.unwrap(), Some(Shard { index: 2, count: 3 }));
        assert_eq!(slurm(&[]).unwrap(), None);
    }

    #[test]
    fn numbers_that_would_wrap_around_are_refused() {
        let max = usize::MAX.to_string();
        for (vars, says) in [
            (
                vec![
                    ("MIN", max.as_str()),
                    ("MAX", "1"),
                    ("COUNT", "3"),
                    ("ID", &max),
                ],
                "is not a task number",
            ),
            (
                vec![("MIN", "0"), ("COUNT", "0"), ("ID", "0")],
                "is not a task number",
            ),
            (
                vec![("MIN", "0"), ("MAX", &max), ("COUNT", &max), ("ID", &max)],
                "not contiguous",
            ),
            (
                vec![("MIN", "1"), ("MAX", "3"), ("COUNT", "3"), ("ID", "0")],
                "outside the array's tasks 1 to 3",
            ),
            (
                vec![("MIN", "1"), ("MAX", "-1"), ("COUNT", "3"), ("ID", "1")],
                "SLURM_ARRAY_TASK_MAX=`-1` is not a whole number",
            ),
            (
                vec![("MIN", "1"), ("COUNT", "3"), ("ID", "99999999999999999999")],
                "SLURM_ARRAY_TASK_ID=`99999999999999999999` is not a whole number",
            ),
        ] {
            let named: Vec<(String, &str)> = vars
                .iter()
                .map(|(k, v)| (format!("SLURM_ARRAY_TASK_{k}"), *v))
                .collect();
            let refs: Vec<(&str, &str)> = named.iter().map(|(k, v)| (k.as_str(), *v)).collect();
            let err = slurm(&refs).expect_err(says).to_string();
            assert!(err.contains(says), "{vars:?}: {err}");
        }
    }

    /// The Slurm variables rubsim reads, each set alone and in pairs to hostile values over a
    /// valid array task (tasks 1 to 3, this one 2): no panic; a refused value is named in the
    /// error with its variable; an accepted one gives a shard in range. Issue 31.
    #[test]
    fn hostile_slurm_values_alone_and_in_pairs_are_refused_naming_the_variable() {
        const VARS: [&str; 5] = [
            "SLURM_ARRAY_TASK_ID",
            "SLURM_ARRAY_TASK_MIN",
            "SLURM_ARRAY_TASK_MAX",
            "SLURM_ARRAY_TASK_COUNT",
            "SLURM_ARRAY_TASK_STEP",
        ];
        let base = [("ID", "2"), ("MIN", "1"), ("MAX", "3"), ("COUNT", "3")];
        let hostile = [
            "".to_string(),
            "-1".into(),
            "18446744073709551616".into(),
            "1e3".into(),
            " 3".into(),
            "３".into(),
            u64::MAX.to_string(),
            usize::MAX.to_string(),
            "0".into(),
            "\u{fffd}".into(),
        ];
        let run = |set: &[(&str, &str)]| {
            let vars: Vec<(String, String)> = base
                .iter()
                .map(|(k, v)| (format!("SLURM_ARRAY_TASK_{k}"), (*v).to_string()))
                .filter(|(k, _)| set.iter().all(|(s, _)| s != k))
                .chain(
                    set.iter()
                        .map(|(k, v)| ((*k).to_string(), (*v).to_string())),
                )
                .collect();
            let got = std::panic::catch_unwind(|| {
                Shard::from_slurm(|k| vars.iter().find(|(n, _)| n == k).map(|(_, v)| v.clone()))
            });
            match got.unwrap_or_else(|_| panic!("{set:?}: panicked")) {
                Ok(Some(s)) => assert!(s.index >= 1 && s.index <= s.count, "{set:?}: {s:?}"),
                Ok(None) => panic!("{set:?}: not taken as an array task"),
                Err(e) => {
                    let e = e.to_string();
                    let named = set.iter().any(|(k, v)| {
                        e.contains(&format!("{k}={v}")) || e.contains(&format!("{k}=`{v}`"))
                    });
                    assert!(named, "{set:?}: the error names no variable set: {e}");
                }
            }
        };
        for (a, va) in VARS.iter().enumerate() {
            for x in &hostile {
                run(&[(va, x)]);
                for vb in &VARS[a + 1..] {
                    for y in &hostile {
                        run(&[(va, x), (vb, y)]);
                    }
                }
            }
        }
    }
}
