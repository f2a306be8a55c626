//! [`NativeScene`]: a scene as the command line loads it — a TOML file (or text, or a dict)
//! with its overrides (`--set key=value`), validated with file, key and line — and its model,
//! built on first use and kept. What Python calls on it runs with the GIL released.

use crate::errors::{to_py, IntoPy, StudyError};
use crate::runs::{self, Out};
use crate::values::{override_text, to_toml};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rubsim::model::Model;
use rubsim::scene::{self, LoadedScene};
use rubsim::study::Kind;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// A validated scene and, once built, its model.
#[pyclass(module = "rubsim._rubsim", frozen)]
pub struct NativeScene {
    ls: LoadedScene,
    model: OnceLock<Model>,
}

impl NativeScene {
    fn new(ls: LoadedScene) -> Self {
        Self {
            ls,
            model: OnceLock::new(),
        }
    }

    /// The model, built (resolve and build: meshing included) on first use, the GIL released.
    fn model(&self, py: Python<'_>) -> PyResult<&Model> {
        if let Some(m) = self.model.get() {
            return Ok(m);
        }
        let ls = &self.ls;
        let built = py
            .detach(|| Model::from_scene(ls))
            .map_err(|e| to_py(e.context(format!("{}: building the model", ls.file.display()))))?;
        let _ = self.model.set(built);
        self.model
            .get()
            .ok_or_else(|| StudyError::new_err("the model could not be kept"))
    }
}

#[pymethods]
impl NativeScene {
    /// Reads the scene file `path` with the overrides (`key=value`, as `--set`).
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf, overrides: Vec<String>) -> PyResult<Self> {
        let ls = py.detach(|| scene::load(&path, &overrides)).py_err()?;
        Ok(Self::new(ls))
    }

    /// A scene from TOML text; `path` names it in errors and places its relative paths (meshes,
    /// geometries) in its folder.
    #[staticmethod]
    fn parse(text: &str, path: PathBuf, overrides: Vec<String>) -> PyResult<Self> {
        Ok(Self::new(scene::parse(&path, text, &overrides).py_err()?))
    }

    /// A scene from a dict of its tables (as the TOML file would hold them); `path` as for
    /// [`NativeScene::parse`]. Each value is checked where it stands (errors name its key).
    #[staticmethod]
    fn from_dict(d: &Bound<'_, PyDict>, path: PathBuf, overrides: Vec<String>) -> PyResult<Self> {
        let file = path.display().to_string();
        let value = to_toml(d.as_any(), &file, "")?;
        let text = toml::to_string(&value).map_err(|e| {
            crate::errors::scene_key(&file, "", &format!("cannot be written as TOML: {e}"))
        })?;
        Self::parse(&text, path, overrides)
    }

    /// `key=value` of a Python value, as an override (`--set`) takes it.
    #[staticmethod]
    fn override_text(key: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
        override_text(key, value)
    }

    /// This scene with more overrides after its own.
    fn with_overrides(&self, more: Vec<String>) -> PyResult<Self> {
        let mut all = self.ls.overrides.clone();
        all.extend(more);
        Ok(Self::new(
            scene::parse(&self.ls.file, &self.ls.source, &all).py_err()?,
        ))
    }

    /// The scene's title.
    #[getter]
    fn title(&self) -> &str {
        &self.ls.scene.title
    }

    /// The file the scene was read from (or named after).
    #[getter]
    fn file(&self) -> PathBuf {
        self.ls.file.clone()
    }

    /// The scene's text as given (before the overrides).
    #[getter]
    fn source(&self) -> &str {
        &self.ls.source
    }

    /// The overrides applied (`key=value`).
    #[getter]
    fn overrides(&self) -> Vec<String> {
        self.ls.overrides.clone()
    }

    /// The validated scene as JSON text (every default filled in).
    fn to_json(&self) -> PyResult<String> {
        runs::json(&self.ls.scene)
    }

    /// Builds the model (meshing the stators' geometries); raises what stops it.
    fn check(&self, py: Python<'_>) -> PyResult<()> {
        self.model(py).map(drop)
    }

    /// ω_n (rad/s): the rotor's first lateral natural frequency at rest, the unit of ν.
    fn natural_frequency(&self, py: Python<'_>) -> PyResult<f64> {
        Ok(self.model(py)?.rotor.natural_frequency())
    }

    /// One line on the rotor model.
    fn describe(&self, py: Python<'_>) -> PyResult<String> {
        Ok(self.model(py)?.rotor.describe())
    }

    /// The run at ν = `speed` (ω/ω_n; default the scene's); see `runs::run_speed`.
    #[pyo3(signature = (speed=None, out=None, force=false, progress=None))]
    fn run<'py>(
        &self,
        py: Python<'py>,
        speed: Option<f64>,
        out: Option<PathBuf>,
        force: bool,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        if let Some(v) = speed.filter(|v| !(v.is_finite() && *v > 0.0)) {
            return Err(StudyError::new_err(format!(
                "speed must be a positive speed ratio ω/ω_n, got {v}"
            )));
        }
        let model = self.model(py)?;
        let out = Out { dir: out, force };
        runs::run_speed(py, (&self.ls, model), speed, out, progress)
    }

    /// The thermal spiral of `[thermal]`; see `runs::run_thermal`.
    #[pyo3(signature = (speed=None, out=None, force=false))]
    fn thermal<'py>(
        &self,
        py: Python<'py>,
        speed: Option<f64>,
        out: Option<PathBuf>,
        force: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let model = self.model(py)?;
        runs::run_thermal(py, (&self.ls, model), speed, Out { dir: out, force })
    }

    /// The speed transient of `[run.speed_profile]`; see `runs::run_transient`.
    #[pyo3(signature = (out=None, force=false, progress=None))]
    fn transient<'py>(
        &self,
        py: Python<'py>,
        out: Option<PathBuf>,
        force: bool,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let model = self.model(py)?;
        runs::run_transient(py, (&self.ls, model), Out { dir: out, force }, progress)
    }

    /// The sweep (`kind = "sweep"`: `[run.sweep]`) or map (`"map"`: `[run.map]`) of the scene;
    /// see `studies::run` (a map of a scene with `[thermal]`: `studies::thermal_map`).
    #[pyo3(signature = (kind, out=None, force=false, fresh=false, jobs=None, progress=None))]
    #[allow(clippy::too_many_arguments)]
    fn study<'py>(
        &self,
        py: Python<'py>,
        kind: &str,
        out: Option<PathBuf>,
        force: bool,
        fresh: bool,
        jobs: Option<usize>,
        progress: Option<Py<PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kind = match kind {
            "sweep" => Kind::Sweep,
            "map" => Kind::Map,
            other => {
                return Err(StudyError::new_err(format!(
                    "a study is a \"sweep\" or a \"map\", got {other:?}"
                )))
            }
        };
        let model = self.model(py)?;
        let out = Out { dir: out, force };
        if kind == Kind::Map && self.ls.scene.thermal.is_some() {
            return crate::studies::thermal_map(py, (&self.ls, model), out);
        }
        crate::studies::run(py, (&self.ls, model), (kind, fresh, jobs), out, progress)
    }

    /// The periodic orbit at ν = `speed` by shooting (JSON text); see `runs::periodic`.
    #[pyo3(signature = (speed=None, period=None, refine=false))]
    fn periodic(
        &self,
        py: Python<'_>,
        speed: Option<f64>,
        period: Option<usize>,
        refine: bool,
    ) -> PyResult<String> {
        let model = self.model(py)?;
        runs::periodic(py, (&self.ls, model), speed, period, refine)
    }

    /// The autonomous orbit at ν = `speed` (JSON text); see `runs::periodic_autonomous`.
    #[pyo3(signature = (speed=None))]
    fn periodic_autonomous(&self, py: Python<'_>, speed: Option<f64>) -> PyResult<String> {
        let model = self.model(py)?;
        runs::periodic_autonomous(py, (&self.ls, model), speed)
    }

    /// The autonomous orbit continued over speed or a key (JSON text); see
    /// `runs::continuation_autonomous`.
    #[pyo3(signature = (key=None, speed=None, from_=None, to=None, step=None))]
    fn continuation_autonomous(
        &self,
        py: Python<'_>,
        key: Option<&str>,
        speed: Option<f64>,
        from_: Option<f64>,
        to: Option<f64>,
        step: Option<f64>,
    ) -> PyResult<String> {
        let model = self.model(py)?;
        runs::continuation_autonomous(py, (&self.ls, model), (key, speed), [from_, to, step])
    }

    /// A periodic orbit continued over speed (JSON text); see `runs::continuation`. With
    /// `switch = Some(max_period)`: the diagram of `rubsim continue --switch` (JSON text).
    #[pyo3(signature = (from_=None, to=None, step=None, period=None, arclength=None, switch=None))]
    #[allow(clippy::too_many_arguments)]
    fn continuation(
        &self,
        py: Python<'_>,
        from_: Option<f64>,
        to: Option<f64>,
        step: Option<f64>,
        period: Option<usize>,
        arclength: Option<usize>,
        switch: Option<usize>,
    ) -> PyResult<String> {
        let model = self.model(py)?;
        runs::continuation(
            py,
            (&self.ls, model),
            [from_, to, step],
            period,
            (arclength, switch),
        )
    }

    /// A periodic orbit continued over a scene key at one speed (JSON text of the diagram);
    /// see `runs::continuation_key`.
    #[pyo3(signature = (key, speed=None, from_=None, to=None, step=None, period=None, arclength=None, switch=None))]
    #[allow(clippy::too_many_arguments)]
    fn continuation_key(
        &self,
        py: Python<'_>,
        key: &str,
        speed: Option<f64>,
        from_: Option<f64>,
        to: Option<f64>,
        step: Option<f64>,
        period: Option<usize>,
        arclength: Option<usize>,
        switch: Option<usize>,
    ) -> PyResult<String> {
        let model = self.model(py)?;
        runs::continuation_key(
            py,
            (&self.ls, model),
            (key, speed),
            [from_, to, step],
            period,
            (arclength, switch),
        )
    }

    /// The damped modes of the rotor alone at Ω = `speed` rad/s (JSON text).
    #[pyo3(signature = (speed=0.0, modes=12))]
    fn modal(&self, py: Python<'_>, speed: f64, modes: usize) -> PyResult<String> {
        let model = self.model(py)?;
        runs::modal(py, model, speed, modes)
    }
}

/// The scene text of a rotor saved by ROSS (`Rotor.save`: ROSS 2.x or 3.x TOML, `text`, read
/// from `path`), as `rubsim import-ross` writes it; the scene is checked by building it.
#[pyfunction]
pub fn import_ross(py: Python<'_>, text: &str, path: PathBuf) -> PyResult<String> {
    let scene_text = scene::ross::import(Path::new(&path), text).py_err()?;
    let ls = scene::parse(&path, &scene_text, &[]).py_err()?;
    py.detach(|| Model::from_scene(&ls)).py_err()?;
    Ok(scene_text)
}
