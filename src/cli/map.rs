//! `rubsim map`: the 2-D map of `[run.map]` — speed × a scene key, or two scene keys at the
//! scene's speed — run as the cases of one study ([`rubsim::study`]: the same expansion into
//! variants × speeds as a sweep, the same case files, shards and merge); here, its table and
//! pictures assembled from the cases.

use anyhow::{Context, Result};
use rubsim::analysis::SpeedResults;
use rubsim::output::csv::{self, MapCell};
use rubsim::output::whirl::{self as whirl_out, CascadeCase};
use rubsim::output::{figures, Drawings, OutDir};
use rubsim::plot::{Boundary, MapGrid};
use rubsim::scene::{toml_number, LoadedScene};
use rubsim::study::summary::{regime_cells, MapRecord};
use rubsim::study::{MapAxes, Study};

/// Writes `map.csv` and the map's pictures from the results of its cases (case order), prints
/// the count of cells per regime; returns the summary record of the map.
pub fn assemble(
    outd: &mut OutDir,
    ls: &LoadedScene,
    study: &Study,
    results: Vec<(SpeedResults, Boundary)>,
) -> Result<MapRecord> {
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
    // Every picture of the map drawn together, in parallel.
    let descs = [desc(&axes.keys[0]), desc(&axes.keys[1])];
    let mut draw = Drawings::new();
    full_cascades(outd, ls, study, (axes, &cells, &grid), &mut draw)?;
    if ls.scene.output.png {
        figures::map_drawings(
            outd,
            &ls.scene.title,
            MapGrid {
                xs: &axes.values[0],
                ys: &axes.values[1],
                x_desc: &descs[0],
                y_desc: &descs[1],
            },
            &grid,
            &mut draw,
        )?;
    }
    draw.draw()?;
    println!("map {nx} × {ny}: {} cases", runs.len());
    for (name, n) in regime_cells(&runs) {
        println!("  {name:>27}  {n} cells");
    }
    Ok(MapRecord::new(axes, study, &runs))
}

/// The map's `full_cascade.csv` (the leading columns of `map.csv`) and, with `output.png`, one
/// `full_cascade/<key>_<value>.png` per value of the axis that is not the speed (the vertical
/// one when neither is), its rows along the other axis, added to `draw`.
fn full_cascades(
    outd: &mut OutDir,
    ls: &LoadedScene,
    study: &Study,
    (axes, cells, grid): (&MapAxes, &[MapCell<'_>], &[Vec<&SpeedResults>]),
    draw: &mut Drawings<'_>,
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
        whirl_out::cascade_drawing(
            outd,
            &format!("full_cascade/{name}_{}.png", toml_number(*v)),
            &format!(
                "{} [{} = {}]",
                ls.scene.title,
                axes.keys[per],
                toml_number(*v)
            ),
            &row,
            (&desc(&axes.keys[along]), fmax),
            draw,
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
