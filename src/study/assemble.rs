//! A study's tables and pictures assembled from its cases — `sweep.csv` and the sweep figures
//! of every variant, `map.csv` and the map's — and its `summary.json`, exactly as `rubsim
//! sweep`, `rubsim map` and `rubsim merge` write them, for the command line and the Python
//! package alike ([`write()`]). Nothing here prints: the caller reports the regimes it returns.

use super::summary::{CasesRecord, MapBody, MapRecord, SweepBody, SweepRecord};
use super::{CaseStore, Computed, Kind, MapAxes, Study, Variant};
use crate::analysis::sweep as sw;
use crate::analysis::{self, RegimeRange, SpeedResults, SweepResults};
use crate::error::{Error, Result};
use crate::output::csv::{self, MapCell};
use crate::output::summary::{Base, ModelRecord, Summary};
use crate::output::whirl::{self as whirl_out, CascadeCase};
use crate::output::{figures, Drawings, OutDir};
use crate::plot::{Boundary, MapGrid};
use crate::scene::{toml_number, LoadedScene};
use std::path::PathBuf;
use std::time::Instant;

/// A study's tables as assembled: the sweeps of its variants, or its map.
pub enum Tables<'s> {
    /// A sweep's variants.
    Sweep(Vec<Assembled<'s>>),
    /// A map's record and its cases' results in case order.
    Map(MapRecord, Vec<SpeedResults>),
}

/// Writes the tables, pictures and summary of `study` (of the scene `ls`, its model recorded
/// as `model`) into `outd` from the results this process computed (`held`) and the case
/// files of `stores`, and commits `outd`; `started`: when the command began (the summary's
/// `wall_s`). Returns the tables and the committed folder.
///
/// # Errors
/// Missing cases ([`super::results`]); as [`sweep`] and [`map`]; the commit's.
pub fn write<'s>(
    mut outd: OutDir,
    (ls, study): (&LoadedScene, &'s Study),
    (stores, held): (&[&CaseStore], Vec<Computed>),
    model: ModelRecord,
    started: Instant,
) -> Result<(Tables<'s>, PathBuf)> {
    let counts = super::shard_counts(outd.dir());
    let results = super::results(stores, study, &counts, held)?;
    let cases = CasesRecord::new(results.len(), stores);
    let base = Base::with_model(ls, model, study.kind.name());
    let wall_s = || started.elapsed().as_secs_f64();
    match study.kind {
        Kind::Sweep => {
            let variants = sweep(Some(&mut outd), ls, study, results)?;
            let sweeps = variants.iter().map(|v| v.record()).collect();
            let body = SweepBody {
                sweeps,
                cases,
                wall_s: wall_s(),
            };
            let dir = crate::output::summary::finish(outd, &Summary { base, body })?;
            Ok((Tables::Sweep(variants), dir))
        }
        Kind::Map => {
            let (map, runs) = map(&mut outd, ls, study, results)?;
            let body = MapBody {
                map,
                cases,
                wall_s: wall_s(),
            };
            let summary = Summary { base, body };
            let dir = crate::output::summary::finish(outd, &summary)?;
            Ok((Tables::Map(summary.body.map, runs), dir))
        }
    }
}

/// One sweep of the study as assembled: its results, regimes and quasi-resonance peaks.
pub struct Assembled<'a> {
    /// The variant.
    pub variant: &'a Variant,
    /// Its results, in speed order.
    pub res: SweepResults,
    /// Its regimes.
    pub regimes: Vec<RegimeRange>,
    /// Its quasi-resonance peaks (period, ω/ωn).
    pub peaks: Vec<(usize, f64)>,
}

impl Assembled<'_> {
    /// Its record in the summary.
    pub fn record(&self) -> SweepRecord<'_> {
        SweepRecord::new(self.variant, &self.res, &self.regimes, &self.peaks)
    }
}

/// The sweeps of every variant of the study from the results of its cases (`results`, in case
/// order: variant-major), with their regimes and quasi-resonance peaks; with `outd`, each
/// variant's `sweep.csv` and pictures written below its prefix.
///
/// # Errors
/// The writers'.
pub fn sweep<'s>(
    mut outd: Option<&mut OutDir>,
    ls: &LoadedScene,
    study: &'s Study,
    results: Vec<(SpeedResults, Boundary)>,
) -> Result<Vec<Assembled<'s>>> {
    let n = study.speeds.len();
    let mut out = Vec::new();
    let mut it = results.into_iter();
    for variant in &study.variants {
        let (speeds, bounds): (Vec<_>, Vec<_>) = it.by_ref().take(n).unzip();
        let res = SweepResults {
            wall_s: speeds.iter().map(|r: &SpeedResults| r.stats.wall_s).sum(),
            speeds,
        };
        if let Some(outd) = outd.as_deref_mut() {
            write_variant(outd, variant, ls, &study.speeds, &res, &bounds)?;
        }
        let regimes = analysis::regime_ranges(&res.speeds);
        let peaks = analysis::quasi_resonances(&res.speeds);
        out.push(Assembled {
            variant,
            res,
            regimes,
            peaks,
        });
    }
    Ok(out)
}

/// One sweep of the study: its table and pictures below the variant's prefix.
fn write_variant(
    outd: &mut OutDir,
    variant: &Variant,
    ls: &LoadedScene,
    speeds: &[f64],
    res: &SweepResults,
    bounds: &[Boundary],
) -> Result<()> {
    let prefix = variant.prefix.as_str();
    let o = &ls.scene.output;
    csv::write_sweep(outd, prefix, res)?;
    // Every picture of the variant drawn together, in parallel.
    let mut draw = Drawings::new();
    figures::sweep_drawings(
        outd,
        prefix,
        res,
        &figures::SweepFigures {
            title: &variant.title(&ls.scene.title),
            bounds,
            orbit_grids: &sw::orbit_grids(o, speeds),
            force_histories: &o.force_histories,
            cascade_max: sw::cascade_max(o, speeds),
            png: o.png,
            component: &o.component,
        },
        &mut draw,
    )?;
    let cases: Vec<CascadeCase<'_>> = res
        .speeds
        .iter()
        .map(|r| CascadeCase {
            columns: format!("{:.4}", r.speed_ratio),
            y: r.speed_ratio,
            run: r,
        })
        .collect();
    whirl_out::write_cascade_csv(outd, prefix, "speed_ratio", &cases)?;
    if o.png {
        whirl_out::cascade_drawing(
            outd,
            &format!("{prefix}full_cascade.png"),
            &variant.title(&ls.scene.title),
            &cases,
            ("ω/ωn", sw::cascade_max(o, speeds)),
            &mut draw,
        )?;
    }
    draw.draw()
}

/// Writes `map.csv` and the map's pictures from the results of its cases (case order);
/// returns the summary record of the map and the cases' results.
///
/// # Errors
/// A study without map axes or with a cell missing ([`Error::Study`]); the writers'.
pub fn map(
    outd: &mut OutDir,
    ls: &LoadedScene,
    study: &Study,
    results: Vec<(SpeedResults, Boundary)>,
) -> Result<(MapRecord, Vec<SpeedResults>)> {
    let axes = study
        .map
        .as_ref()
        .ok_or_else(|| Error::study("", "a map study without axes"))?;
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
        .ok_or_else(|| Error::study("", "a map cell without its case"))?;
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
    Ok((MapRecord::new(axes, study, &runs), runs))
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
    let fmax = sw::cascade_max(&ls.scene.output, &study.speeds);
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
    if key == crate::scene::SPEED_KEY {
        "ω/ωn".into()
    } else {
        key.to_string()
    }
}
