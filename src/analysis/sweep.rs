//! A speed sweep: the speeds, what each speed keeps for the pictures, and the one parallel map
//! ([`run_all`], [`sweep`]) that runs a per-speed or per-case closure; a study's variants,
//! cases and shards are `crate::study`'s.

use super::{Keep, SpeedResults};
use crate::error::{Error, Result};
use crate::scene::OutputSpec;
/// Whether a model's runs go one at a time (`run_all`'s `one_at_a_time`).
pub use crate::time::one_at_a_time;
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

/// Runs `run(k, ω/ω_n)` for every speed (k its index in `speeds`) in parallel (rayon), e.g.
/// [`super::prepare`] of [`super::RunSettings::request_at`] then [`super::Prepared::run`] with
/// the sinks that speed wants; `progress` is called after each speed. A failing speed fails
/// the sweep with [`Error::AtSpeed`] naming it. `one_at_a_time` as in [`run_all`].
pub fn sweep<T: Send>(
    one_at_a_time: bool,
    speeds: &[f64],
    run: &(dyn Fn(usize, f64) -> Result<T> + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<Sweep<T>> {
    let t0 = std::time::Instant::now();
    let indexed: Vec<(usize, f64)> = speeds.iter().copied().enumerate().collect();
    let speeds = run_all(
        one_at_a_time,
        &indexed,
        &|&(k, v)| {
            run(k, v).map_err(|e| Error::AtSpeed {
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
/// returned. `one_at_a_time` (a model whose runs each hold large compliance columns of their
/// own, [`crate::time::one_at_a_time`]): the items run in order, one after the other, each
/// with every thread for its columns' solves, and each run starts with the columns the ones
/// before it computed.
pub fn run_all<C: Sync, T: Send>(
    one_at_a_time: bool,
    items: &[C],
    run: &(dyn Fn(&C) -> Result<T> + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<Vec<T>> {
    let one = |c: &C| {
        let r = run(c);
        progress();
        r
    };
    let res: Vec<Result<T>> = if one_at_a_time {
        items.iter().map(one).collect()
    } else {
        items.par_iter().map(one).collect()
    };
    res.into_iter().collect()
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};
    use std::sync::Mutex;

    /// Items one at a time run in their order and never side by side; every item runs even
    /// when one fails, and the first failure in item order is returned.
    #[test]
    fn one_at_a_time_runs_the_items_in_order_alone() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let items: Vec<usize> = (0..12).collect();
        for alone in [true, false] {
            let (now, most) = (AtomicUsize::new(0), AtomicUsize::new(0));
            let order = Mutex::new(Vec::new());
            let run = |&k: &usize| -> Result<usize> {
                let n = now.fetch_add(1, Ordering::SeqCst) + 1;
                most.fetch_max(n, Ordering::SeqCst);
                std::thread::sleep(std::time::Duration::from_millis(5));
                order.lock().unwrap().push(k);
                now.fetch_sub(1, Ordering::SeqCst);
                if k % 5 == 3 {
                    return Err(Error::study("", format!("item {k}")));
                }
                Ok(2 * k)
            };
            let res = pool.install(|| run_all(alone, &items, &run, &|| {}));
            let err = res.unwrap_err().to_string();
            assert!(err.contains("item 3"), "{err}");
            let order = order.into_inner().unwrap();
            assert_eq!(order.len(), items.len(), "every item ran");
            if alone {
                assert_eq!(order, items);
                assert_eq!(most.load(Ordering::SeqCst), 1);
            } else {
                assert_eq!(most.load(Ordering::SeqCst), 2, "two side by side");
            }
        }
    }
}
