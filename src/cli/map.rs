//! `rubsim map`: the 2-D map of `[run.map]` — speed × a scene key, or two scene keys at the
//! scene's speed — run as the cases of one study ([`super::study`]: the same expansion into
//! variants × speeds as a sweep, the same case files, shards and merge); here, its axes and
//! its table and pictures assembled from the cases.

use super::study::{Kind, Study};
use anyhow::{bail, Context, Result};
use rubsim::analysis::sweep::Variant;
use rubsim::analysis::{SpeedResults, REGIME_CLASSES};
use rubsim::output::csv::{self, MapCell};
use rubsim::output::whirl::{self as whirl_out, CascadeCase};
use rubsim::output::{figures, OutDir};
use rubsim::plot::{Boundary, MapGrid};
use rubsim::scene::{toml_number, LoadedScene};

/// The axes of a map: keys and values, and which one (if any) is the speed.
#[derive(Debug, Clone)]
pub struct MapAxes {
    /// The horizontal and vertical keys.
    pub keys: [String; 2],
    /// Their values.
    pub values: [Vec<f64>; 2],
    /// Index of the speed axis (`speed_ratio`), if one is.
    pub speed: Option<usize>,
}

impl MapAxes {
    /// The grid position `(ix, iy)` of case `k` of the study (variant-major, `ns` speeds per
    /// variant): see [`study`] for the expansion.
    fn cell(&self, k: usize, ns: usize) -> (usize, usize) {
        let (variant, s) = (k / ns, k % ns);
        match self.speed {
            Some(0) => (s, variant),
            Some(_) => (variant, s),
            None => (
                variant / self.values[1].len(),
                variant % self.values[1].len(),
            ),
        }
    }
}

/// The study of a map scene: with a speed axis, one variant per value of the other key and
/// the speed axis as the speeds; with two scene keys, one variant per pair (x-major) at the
/// scene's single speed (`run.speed_ratio`, or `run.speed` over ω_n = `wn`).
pub fn study(ls: &LoadedScene, wn: Option<f64>) -> Result<Study> {
    let m = ls.scene.run.map.as_ref().with_context(|| {
        format!(
            "{}: `rubsim map` needs a [run.map] table",
            ls.file.display()
        )
    })?;
    let axes = MapAxes {
        keys: [m.x.key.clone(), m.y.key.clone()],
        values: [m.x.resolved(), m.y.resolved()],
        speed: [&m.x, &m.y].iter().position(|a| a.is_speed()),
    };
    let over = |k: &str, v: f64| format!("{k}={}", toml_number(v));
    let variant = |overrides: Vec<String>| Variant {
        prefix: String::new(),
        overrides,
    };
    let (variants, speeds) = match axes.speed {
        Some(s) => {
            let o = 1 - s;
            let vs = axes.values[o]
                .iter()
                .map(|v| variant(vec![over(&axes.keys[o], *v)]))
                .collect();
            (vs, axes.values[s].clone())
        }
        None => {
            let run = &ls.scene.run;
            let nu = match (run.speed_ratio, run.speed, wn) {
                (Some(r), _, _) => r,
                (None, Some(w), Some(wn)) => w / wn,
                _ => bail!(
                    "{}: a map of two scene keys runs at `run.speed_ratio` or `run.speed`",
                    ls.file.display()
                ),
            };
            let mut vs = Vec::new();
            for x in &axes.values[0] {
                for y in &axes.values[1] {
                    vs.push(variant(vec![
                        over(&axes.keys[0], *x),
                        over(&axes.keys[1], *y),
                    ]));
                }
            }
            (vs, vec![nu])
        }
    };
    Ok(Study {
        kind: Kind::Map,
        variants,
        speeds,
        map: Some(axes),
    })
}

/// Writes `map.csv` and the map's pictures from the results of its cases (case order), prints
/// the count of cells per regime; returns the summary record of the map.
pub fn assemble(
    outd: &mut OutDir,
    ls: &LoadedScene,
    study: &Study,
    results: Vec<(SpeedResults, Boundary)>,
) -> Result<serde_json::Value> {
    let axes = study.map.as_ref().context("a map study without axes")?;
    let (nx, ny) = (axes.values[0].len(), axes.values[1].len());
    let ns = study.speeds.len();
    let runs: Vec<SpeedResults> = results.into_iter().map(|r| r.0).collect();
    let mut grid: Vec<Vec<Option<&SpeedResults>>> = vec![vec![None; nx]; ny];
    let mut cells = Vec::with_capacity(runs.len());
    for (k, r) in runs.iter().enumerate() {
        let (ix, iy) = axes.cell(k, ns);
        grid[iy][ix] = Some(r);
        cells.push(MapCell {
            x: axes.values[0][ix],
            y: axes.values[1][iy],
            run: r,
        });
    }
    let grid: Vec<Vec<&SpeedResults>> = grid
        .into_iter()
        .map(|row| row.into_iter().collect::<Option<Vec<_>>>())
        .collect::<Option<Vec<_>>>()
        .context("a map cell without its case")?;
    csv::write_map(outd, [&axes.keys[0], &axes.keys[1]], &cells)?;
    full_cascades(outd, ls, study, axes, &cells, &grid)?;
    if ls.scene.output.png {
        figures::write_map(
            outd,
            &ls.scene.title,
            MapGrid {
                xs: &axes.values[0],
                ys: &axes.values[1],
                x_desc: &desc(&axes.keys[0]),
                y_desc: &desc(&axes.keys[1]),
            },
            &grid,
        )?;
    }
    let mut counts = vec![0usize; REGIME_CLASSES.len()];
    for r in &runs {
        counts[rubsim::analysis::regime_class(r)] += 1;
    }
    println!("map {nx} × {ny}: {} cases", runs.len());
    let regimes: serde_json::Map<String, serde_json::Value> = REGIME_CLASSES
        .iter()
        .zip(&counts)
        .filter(|(_, n)| **n > 0)
        .map(|(name, n)| {
            println!("  {name:>27}  {n} cells");
            (name.to_string(), (*n).into())
        })
        .collect();
    Ok(serde_json::json!({
        "x": { "key": axes.keys[0], "values": axes.values[0] },
        "y": { "key": axes.keys[1], "values": axes.values[1] },
        "speed_ratio": if axes.speed.is_none() { study.speeds.first().copied() } else { None },
        "cases": runs.len(),
        "regime_cells": regimes,
    }))
}

/// The map's `full_cascade.csv` (the leading columns of `map.csv`) and, with `output.png`, one
/// `full_cascade/<key>_<value>.png` per value of the axis that is not the speed (the vertical
/// one when neither is), its rows along the other axis.
fn full_cascades(
    outd: &mut OutDir,
    ls: &LoadedScene,
    study: &Study,
    axes: &MapAxes,
    cells: &[MapCell<'_>],
    grid: &[Vec<&SpeedResults>],
) -> Result<()> {
    let speed_col = axes.speed.is_none();
    let lead = |x: f64, y: f64, r: &SpeedResults| {
        let mut s = format!("{},{}", toml_number(x), toml_number(y));
        if speed_col {
            s.push_str(&format!(",{}", toml_number(r.speed_ratio)));
        }
        s
    };
    let cases: Vec<CascadeCase<'_>> = cells
        .iter()
        .map(|c| CascadeCase {
            columns: lead(c.x, c.y, c.run),
            y: c.x,
            run: c.run,
        })
        .collect();
    let header = format!(
        "{},{}{}",
        axes.keys[0],
        axes.keys[1],
        if speed_col { ",speed_ratio" } else { "" }
    );
    whirl_out::write_cascade_csv(outd, "", &header, &cases)?;
    if !ls.scene.output.png {
        return Ok(());
    }
    let along = axes.speed.unwrap_or(0);
    let per = 1 - along;
    let fmax = rubsim::analysis::sweep::cascade_max(&ls.scene.output, &study.speeds);
    let name = axes.keys[per].rsplit('.').next().unwrap_or("value");
    for (j, v) in axes.values[per].iter().enumerate() {
        let row: Vec<CascadeCase<'_>> = axes.values[along]
            .iter()
            .enumerate()
            .map(|(i, a)| {
                let r = if along == 0 { grid[j][i] } else { grid[i][j] };
                CascadeCase {
                    columns: String::new(),
                    y: *a,
                    run: r,
                }
            })
            .collect();
        whirl_out::draw_cascade(
            outd,
            &format!("full_cascade/{name}_{}.png", toml_number(*v)),
            &format!(
                "{} [{} = {}]",
                ls.scene.title,
                axes.keys[per],
                toml_number(*v)
            ),
            &row,
            &desc(&axes.keys[along]),
            fmax,
        )?;
    }
    Ok(())
}

/// An axis description: `ω/ωn` for the speed, else the key.
fn desc(key: &str) -> String {
    if key == rubsim::scene::SPEED_KEY {
        "ω/ωn".into()
    } else {
        key.to_string()
    }
}
