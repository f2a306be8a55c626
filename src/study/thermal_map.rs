//! `rubsim map` of a scene with `[thermal]`: the thermal spiral's stability over the map's two
//! axes (`[run.map]`: the speed ω/ω_n and a rub parameter, or two scene keys at the scene's
//! speed) — at every cell the spiral of `analysis::thermal::run_thermal` on the scene with the
//! cell's overrides, its growth rate (the dominant slow eigenvalue's real part, 1/s), its
//! rotation in the rotor's frame, and whether it ran away. Cells are run in parallel and are
//! not kept in a case store (no resume, no shards: each is one spiral of a fraction of a
//! second to seconds).

use super::variant::{map_variants, MapAxes};
use crate::analysis::thermal::{run_thermal, HotSpot, ThermalResults};
use crate::error::{Error, Result, SolveError};
use crate::model::Model;
use crate::scene::LoadedScene;
use rayon::prelude::*;
use serde::Serialize;

/// A cell's class.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stability {
    /// The spiral settles: growth rate < 0.
    Stable,
    /// It grows (growth rate ≥ 0) within the machine time run, without passing
    /// `thermal.max_temperature_difference`.
    Growing,
    /// It passed `thermal.max_temperature_difference`: a runaway.
    Runaway,
    /// The vibration itself is not the synchronous response the spiral needs: it diverged (the
    /// divergence guard, or a value that is not finite) or its orbit changed over a revolution
    /// by more than [`crate::analysis::thermal::MAX_NON_SYNCHRONOUS`] of its radius — a self-excited whirl of the rub
    /// (dry friction whirl, where μ k_s exceeds the damping's c ω), with or without the bow, or
    /// a whirl so lightly damped near that threshold that it has not settled.
    NotSynchronous,
}

impl Stability {
    /// Every class, in the order of their colours.
    pub const ALL: [Stability; 4] = [
        Stability::Stable,
        Stability::Growing,
        Stability::Runaway,
        Stability::NotSynchronous,
    ];

    /// The class's name in tables and pictures.
    pub fn label(self) -> &'static str {
        match self {
            Stability::Stable => "stable",
            Stability::Growing => "growing",
            Stability::Runaway => "runaway",
            Stability::NotSynchronous => "not_synchronous",
        }
    }

    /// The class's category in the maps' palette (`plot::category_map`): stable blue, growing
    /// orange, runaway dark red, not synchronous grey.
    pub fn colour_index(self) -> usize {
        match self {
            Stability::Stable => 0,
            Stability::Growing => 3,
            Stability::Runaway => 11,
            Stability::NotSynchronous => 7,
        }
    }

    /// The class of a spiral's results.
    pub fn of(r: &ThermalResults) -> Self {
        if r.unsynchronous_at_s.is_some() {
            Stability::NotSynchronous
        } else if r.runaway_at_s.is_some() {
            Stability::Runaway
        } else if r.growth_rate < 0.0 {
            Stability::Stable
        } else {
            Stability::Growing
        }
    }
}

/// One cell of the map.
#[derive(Debug, Clone, Serialize)]
pub struct ThermalCell {
    /// The horizontal and the vertical axis's values.
    pub at: [f64; 2],
    /// ω/ω_n of the spiral.
    pub speed_ratio: f64,
    /// The spiral's growth rate (1/s): > 0 grows, < 0 settles; NaN where the vibration is not synchronous.
    pub growth_rate: f64,
    /// Its rotation rate in the rotor's frame (rad/s; < 0 against the spin).
    pub rotation_rate: f64,
    /// The machine time at which it ran away (s), if it did.
    pub runaway_at_s: Option<f64>,
    /// Where the vibration was not synchronous, the time it was found: the machine time at which the orbit
    /// stopped being synchronous, or the divergence's time in the vibration's own clock (s).
    pub unsynchronous_at_s: Option<f64>,
    /// |ΔT| at the spiral's end (K).
    pub delta_t_end: f64,
    /// The class.
    pub stability: Stability,
}

impl ThermalCell {
    /// The cell at `at`, ω/ω_n `speed_ratio`, of a spiral's results.
    fn of(at: [f64; 2], speed_ratio: f64, r: &ThermalResults) -> Self {
        // A vibration that is not synchronous has no fitted spiral.
        let fitted = |v: f64| {
            if r.unsynchronous_at_s.is_some() {
                f64::NAN
            } else {
                v
            }
        };
        Self {
            at,
            speed_ratio,
            growth_rate: fitted(r.growth_rate),
            rotation_rate: fitted(r.rotation_rate),
            runaway_at_s: r.runaway_at_s,
            unsynchronous_at_s: r.unsynchronous_at_s,
            delta_t_end: r
                .samples
                .last()
                .map_or(0.0, |x| x.delta_t[0].hypot(x.delta_t[1])),
            stability: Stability::of(r),
        }
    }

    /// The cell whose vibration diverged at `time` (s).
    fn diverged(at: [f64; 2], speed_ratio: f64, time: f64) -> Self {
        Self {
            at,
            speed_ratio,
            growth_rate: f64::NAN,
            rotation_rate: f64::NAN,
            runaway_at_s: None,
            unsynchronous_at_s: Some(time),
            delta_t_end: f64::NAN,
            stability: Stability::NotSynchronous,
        }
    }
}

/// The time (s) of a run's divergence stop (the guard, or a value that is not finite), or
/// `None` for any other error.
fn divergence_time(e: &Error) -> Option<f64> {
    match e {
        Error::Solve(SolveError::Diverged { time, .. } | SolveError::NonFinite { time, .. }) => {
            Some(*time)
        }
        Error::AtSpeed { source, .. } | Error::AtCase { source, .. } => divergence_time(source),
        Error::Context { cause, .. } => divergence_time(cause),
        _ => None,
    }
}

/// The map: its axes and its cells, x-major (`cells[ix * ny + iy]`).
#[derive(Debug, Clone)]
pub struct ThermalMap {
    /// The axes.
    pub axes: MapAxes,
    /// The cells.
    pub cells: Vec<ThermalCell>,
}

impl ThermalMap {
    /// The cell at `(ix, iy)`.
    pub fn cell(&self, ix: usize, iy: usize) -> &ThermalCell {
        &self.cells[ix * self.axes.values[1].len() + iy]
    }
}

/// Runs the thermal spiral at every cell of the map of `ls` (`[run.map]`, `[thermal]`): the
/// scene with the command line's overrides and the cell's, its model, settings and hot spot.
///
/// # Errors
/// [`Error::Study`] for a scene without `[run.map]` or `[thermal]`; a cell's scene, model or
/// spiral error, named with the cell's overrides.
pub fn run(ls: &LoadedScene, model: &Model) -> Result<ThermalMap> {
    if ls.scene.thermal.is_none() {
        return Err(Error::study(
            ls.file.display(),
            "the scene has no [thermal]",
        ));
    }
    let (variants, speeds, axes) = map_variants(ls, Some(model.rotor.natural_frequency()))?;
    let ns = speeds.len();
    let at = |v: usize, speed: Option<f64>, e: Error| {
        let speed = speed.map_or(String::new(), |x| format!(" at ω/ωn = {x}"));
        Error::study(
            ls.file.display(),
            format!("map cell {}{speed}: {e}", variants[v].label()),
        )
    };
    // Each variant's scene (from the scene's own text, as a sweep's variants), model and
    // settings, once. The settings are the scene's own step rule: a cell does not choose its
    // step from `run.tolerance` by pilots as `rubsim run` does (per cell that cost 12 × the
    // time, over the map's speeds 40 ×, and moved the tests' agreement with the theory by less
    // than 2 % of its bound: docs/VALIDATION.md §21.1).
    let scenes: Vec<(LoadedScene, Model, crate::analysis::RunSettings)> = variants
        .iter()
        .enumerate()
        .map(|(v, var)| {
            let mut sets = ls.overrides.clone();
            sets.extend(var.overrides.iter().cloned());
            let lv = crate::scene::parse(&ls.file, &ls.source, &sets)
                .map_err(|e| at(v, None, e.into()))?;
            let m = Model::from_scene(&lv).map_err(|e| at(v, None, e))?;
            // A cell's class and growth rate are the map's; its error estimate (two more
            // spirals per cell) is left to `rubsim run` at the cell's speed and values.
            let settings = crate::analysis::RunSettings {
                error_estimate: false,
                ..crate::analysis::RunSettings::from_scene(&lv.scene)
            };
            Ok((lv, m, settings))
        })
        .collect::<Result<_>>()?;
    let cases: Vec<(usize, usize)> = (0..variants.len())
        .flat_map(|v| (0..ns).map(move |s| (v, s)))
        .collect();
    let results: Vec<Result<(usize, ThermalCell)>> = cases
        .par_iter()
        .map(|&(v, s)| {
            let (lv, m, settings) = &scenes[v];
            let at = |e: Error| at(v, Some(speeds[s]), e);
            let hs = HotSpot::of_scene(lv)
                .ok_or_else(|| at(Error::study(ls.file.display(), "no [thermal]")))?;
            let (ix, iy) = axes.cell(v * ns + s, ns);
            let at_xy = [axes.values[0][ix], axes.values[1][iy]];
            let cell = match run_thermal(m, settings, speeds[s], &hs) {
                Ok(r) => ThermalCell::of(at_xy, speeds[s], &r),
                Err(e) => ThermalCell::diverged(
                    at_xy,
                    speeds[s],
                    divergence_time(&e).ok_or_else(|| at(e))?,
                ),
            };
            Ok((ix * axes.values[1].len() + iy, cell))
        })
        .collect();
    let mut cells: Vec<Option<ThermalCell>> = vec![None; cases.len()];
    for r in results {
        let (i, c) = r?;
        cells[i] = Some(c);
    }
    Ok(ThermalMap {
        axes,
        cells: cells.into_iter().flatten().collect(),
    })
}

/// Writes the map's `thermal_map.csv` — per cell the axes' values, ω/ω_n (where neither axis is
/// the speed), the growth rate (1/s), the rotation rate (rad/s), the runaway's and the
/// divergence's time (s, empty without one), |ΔT| at the end (K) and the class — and, with `png`, `thermal_stability.png` (the classes) and
/// `growth_rate_map.png` (the growth rate with contours; its zero contour is the threshold).
///
/// # Errors
/// I/O and drawing errors, naming the file.
pub fn write(
    out: &mut crate::output::OutDir,
    title: &str,
    map: &ThermalMap,
    png: bool,
) -> Result<()> {
    let [kx, ky] = &map.axes.keys;
    // The speed is a column of its own only where neither axis is it.
    let speed_col = !map.axes.keys.iter().any(|k| k == crate::scene::SPEED_KEY);
    let time = |t: Option<f64>| t.map_or(String::new(), |t| format!("{t:.6e}"));
    let mut s = format!(
        "{kx},{ky},{}growth_rate_1_s,rotation_rate_rad_s,runaway_at_s,unsynchronous_at_s,delta_t_end_k,stability\n",
        if speed_col { "speed_ratio," } else { "" }
    );
    for c in &map.cells {
        let speed = if speed_col {
            format!("{},", c.speed_ratio)
        } else {
            String::new()
        };
        s.push_str(&format!(
            "{},{},{speed}{:.6e},{:.6e},{},{},{:.6e},{}\n",
            c.at[0],
            c.at[1],
            c.growth_rate,
            c.rotation_rate,
            time(c.runaway_at_s),
            time(c.unsynchronous_at_s),
            c.delta_t_end,
            c.stability.label()
        ));
    }
    out.write("thermal_map.csv", s.as_bytes())?;
    if !png {
        return Ok(());
    }
    let [xs, ys] = &map.axes.values;
    let grid = crate::plot::MapGrid {
        xs,
        ys,
        x_desc: kx,
        y_desc: ky,
    };
    let rows = |f: &dyn Fn(&ThermalCell) -> f64| -> Vec<Vec<f64>> {
        (0..ys.len())
            .map(|iy| (0..xs.len()).map(|ix| f(map.cell(ix, iy))).collect())
            .collect()
    };
    let classes: Vec<Vec<usize>> = (0..ys.len())
        .map(|iy| {
            (0..xs.len())
                .map(|ix| map.cell(ix, iy).stability.colour_index())
                .collect()
        })
        .collect();
    let mut labels = [""; 12];
    for k in Stability::ALL {
        labels[k.colour_index()] = k.label();
    }
    let p = out.stage("thermal_stability.png")?;
    crate::plot::category_map(
        &p,
        &format!("{title} — the thermal spiral's stability"),
        grid,
        &classes,
        &labels,
    )?;
    let p = out.stage("growth_rate_map.png")?;
    crate::plot::field_map(
        &p,
        &format!("{title} — the spiral's growth rate (1/s)"),
        grid,
        &rows(&|c| c.growth_rate),
        "growth rate (1/s)",
        8,
    )
}

/// Writes the map `map` of `ls` into `out` ([`write()`]) and its `summary.json` (command `map`,
/// the body [`MapBody`] with the wall time since `started`), committing the folder; returns it.
///
/// # Errors
/// As [`write()`] and [`crate::output::summary::finish`].
pub fn write_all(
    mut out: crate::output::OutDir,
    (ls, model): (&LoadedScene, &Model),
    map: &ThermalMap,
    started: std::time::Instant,
) -> Result<std::path::PathBuf> {
    use crate::output::summary::{finish, Base, Summary};
    write(&mut out, &ls.scene.title, map, ls.scene.output.png)?;
    let body = MapBody {
        thermal_map: MapRecord::of(map),
        wall_s: started.elapsed().as_secs_f64(),
    };
    finish(
        out,
        &Summary {
            base: Base::new(ls, model, "map"),
            body,
        },
    )
}

/// summary.json's body of a thermal map: the axes, every cell, the count of each class and
/// the wall time of the command.
#[derive(Debug, Clone, Serialize)]
pub struct MapBody<'a> {
    /// The map.
    pub thermal_map: MapRecord<'a>,
    /// Wall time of the command (s).
    pub wall_s: f64,
}

/// The map as summary.json keeps it.
#[derive(Debug, Clone, Serialize)]
pub struct MapRecord<'a> {
    /// The horizontal and the vertical axis's keys.
    pub keys: &'a [String; 2],
    /// Their values.
    pub values: &'a [Vec<f64>; 2],
    /// The cells, x-major.
    pub cells: &'a [ThermalCell],
    /// Cells per class: stable, growing, runaway, not synchronous.
    pub classes: [usize; 4],
}

impl<'a> MapRecord<'a> {
    /// The record of `map`.
    pub fn of(map: &'a ThermalMap) -> Self {
        let mut classes = [0; 4];
        for c in &map.cells {
            if let Some(i) = Stability::ALL.iter().position(|k| *k == c.stability) {
                classes[i] += 1;
            }
        }
        Self {
            keys: &map.axes.keys,
            values: &map.axes.values,
            cells: &map.cells,
            classes,
        }
    }
}
