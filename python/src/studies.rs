//! Sweeps and maps as rubsim's studies ([`rubsim::study`]), run with the GIL released. With an
//! output directory a study writes exactly what `rubsim sweep` / `rubsim map` write there —
//! its case store (so that a later call resumes it), tables, pictures, series and
//! `summary.json` ([`rubsim::study::assemble::write`]); without one it runs in a temporary
//! folder, removed afterwards, with pictures and series off. The dict returned: `summary`
//! (JSON text of `summary.json`), `runs` (JSON text: every case's results, case order),
//! `regimes` (each case's regime label),
//! `cells` (a map's grid position of each case), `orbits` (the orbits kept: variant index,
//! ω/ω_n, n × 2 array), `warnings`, `dir`.

use crate::errors::{IntoPy, StudyError};
use crate::progress::CaseProgress;
use crate::runs::{json, pairs, Out};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rubsim::analysis::{self, notices, SpeedResults};
use rubsim::error::{Error, Result};
use rubsim::model::Model;
use rubsim::output::summary::ModelRecord;
use rubsim::scene::LoadedScene;
use rubsim::study::assemble::{self, Tables};
use rubsim::study::{self, Kind, Study, StudyRequest};
use std::path::PathBuf;
use std::time::Instant;

/// What a study computed, for the dict.
struct Ran {
    summary: String,
    runs: Vec<SpeedResults>,
    variants: usize,
    cells: Vec<(usize, usize)>,
    warnings: Vec<String>,
    dir: Option<PathBuf>,
}

/// The scene as a study without an output directory runs it: no pictures, no series.
fn unwritten(ls: &LoadedScene) -> LoadedScene {
    let mut quiet = ls.clone();
    quiet.scene.output.png = false;
    quiet.scene.output.vtk = None;
    quiet.scene.output.hdf5 = None;
    quiet.scene.output.per_speed = rubsim::scene::PerSpeed::default();
    quiet
}

/// Runs the study of `kind` of `ls` into `out` (or a temporary folder) and assembles it.
fn run_study(
    (ls, model): (&LoadedScene, &Model),
    (kind, fresh): (Kind, bool),
    out: &Out,
    progress: &CaseProgress,
) -> Result<Ran> {
    let started = Instant::now();
    let temp = match out.dir {
        Some(_) => None,
        None => Some(
            tempfile::Builder::new()
                .prefix("rubsim-py-")
                .tempdir()
                .map_err(|e| Error::output(std::env::temp_dir(), e))?,
        ),
    };
    let quiet;
    let ls = match temp {
        Some(_) => {
            quiet = unwritten(ls);
            &quiet
        }
        None => ls,
    };
    let study = Study::of(ls, Some(model.rotor.natural_frequency()), kind)?;
    let mut outd = match (&temp, &out.dir) {
        (Some(t), _) => crate::runs::open_dir(t.path(), false)?,
        (None, Some(d)) => crate::runs::open_dir(d, out.force)?,
        (None, None) => return Err(Error::study("", "no output folder")),
    };
    let req = StudyRequest {
        scene: ls,
        model,
        study: &study,
        shard: None,
        fresh,
    };
    let ran = study::run(&req, &mut outd, progress)?;
    let stores = [&ran.store];
    let record = ModelRecord::of(model);
    let (tables, dir) = assemble::write(outd, (ls, &study), (&stores, ran.held), record, started)?;
    let summary_path = dir.join("summary.json");
    let summary =
        std::fs::read_to_string(&summary_path).map_err(|e| Error::output(&summary_path, e))?;
    let ns = study.speeds.len();
    let (runs, cells, warnings) = match tables {
        Tables::Sweep(variants) => {
            let warnings = variants
                .iter()
                .flat_map(|a| notices::sweep_warnings(&prefix(&a.variant.label()), &a.res))
                .collect();
            let runs = variants.into_iter().flat_map(|a| a.res.speeds).collect();
            (runs, Vec::new(), warnings)
        }
        Tables::Map(_, runs) => {
            let axes = study.map.as_ref();
            let cells = (0..runs.len())
                .filter_map(|k| axes.map(|a| a.cell(k, ns)))
                .collect();
            (runs, cells, Vec::new())
        }
    };
    Ok(Ran {
        summary,
        runs,
        variants: study.variants.len(),
        cells,
        warnings,
        dir: temp.is_none().then_some(dir),
    })
}

/// A variant's lines start with its overrides.
fn prefix(label: &str) -> String {
    if label.is_empty() {
        String::new()
    } else {
        format!("{label}: ")
    }
}

/// A sweep or map of `ls`'s `model`; see the module. `jobs`: worker threads (default: all
/// cores); `fresh`: discard the cases of another scene in the output directory instead of
/// refusing to run.
pub fn run<'py>(
    py: Python<'py>,
    (ls, model): (&LoadedScene, &Model),
    (kind, fresh, jobs): (Kind, bool, Option<usize>),
    out: Out,
    callback: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let progress = CaseProgress::new(callback);
    let pool = match jobs {
        Some(0) => return Err(StudyError::new_err("jobs must be at least 1")),
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| StudyError::new_err(e.to_string()))?,
        ),
        None => None,
    };
    let go = || run_study((ls, model), (kind, fresh), &out, &progress);
    let ran = py.detach(|| match &pool {
        Some(p) => p.install(go),
        None => go(),
    });
    if let Some(e) = progress.take_raised() {
        return Err(e);
    }
    let ran = ran.py_err()?;
    let d = PyDict::new(py);
    d.set_item("summary", ran.summary)?;
    d.set_item("runs", json(&ran.runs)?)?;
    let regimes: Vec<String> = ran.runs.iter().map(analysis::regime_label).collect();
    d.set_item("regimes", regimes)?;
    d.set_item("cells", ran.cells)?;
    let per = ran.runs.len() / ran.variants.max(1);
    let orbits = ran
        .runs
        .iter()
        .enumerate()
        .filter(|(_, r)| !r.orbit_nd.is_empty())
        .map(|(k, r)| Ok((k / per.max(1), r.speed_ratio, pairs(py, &r.orbit_nd)?)))
        .collect::<PyResult<Vec<_>>>()?;
    d.set_item("orbits", orbits)?;
    let mut warnings = progress.take_warnings();
    warnings.extend(ran.warnings);
    d.set_item("warnings", warnings)?;
    d.set_item("dir", ran.dir)?;
    Ok(d)
}

/// The thermal spiral's stability map of a scene with `[thermal]` and `[run.map]`, as
/// `rubsim map` runs it ([`rubsim::study::thermal_map`]): with `out` its files and
/// `summary.json` written there. The dict: `summary` (JSON text of the map's record — keys,
/// values, every cell, the class counts), `thermal_map` (true), `dir`.
pub fn thermal_map<'py>(
    py: Python<'py>,
    (ls, model): (&LoadedScene, &Model),
    out: Out,
) -> PyResult<Bound<'py, PyDict>> {
    use rubsim::study::thermal_map as tm;
    let started = Instant::now();
    let (summary, dir) = py
        .detach(|| -> Result<(String, Option<PathBuf>)> {
            let outd = out.open()?;
            let map = tm::run(ls, model)?;
            let summary = serde_json::to_string(&tm::MapRecord::of(&map))
                .map_err(|e| Error::study("thermal map", e))?;
            let dir = match outd {
                Some(o) => Some(tm::write_all(o, (ls, model), &map, started)?),
                None => None,
            };
            Ok((summary, dir))
        })
        .py_err()?;
    let d = PyDict::new(py);
    d.set_item("summary", summary)?;
    d.set_item("thermal_map", true)?;
    d.set_item("dir", dir)?;
    Ok(d)
}
