//! One speed, a speed transient and the rotor's modes, run with the GIL released. With an
//! output directory the run writes exactly what `rubsim run` writes there
//! ([`rubsim::study::single`]); without one it writes nothing. Either way the results come back
//! as a dict: `summary` (JSON text: `summary.json`'s body), numpy arrays, `warnings` (list of
//! str) and `dir` (the committed folder or None).

use crate::errors::{IntoPy, StudyError};
use crate::progress::StepProgress;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rubsim::analysis::waterfall::{self, WaterfallWindow};
use rubsim::analysis::{self, Keep, SpeedResults};
use rubsim::error::Result;
use rubsim::model::Model;
use rubsim::output::summary::RunBody;
use rubsim::output::OutDir;
use rubsim::scene::LoadedScene;
use rubsim::study::single;
use rubsim::time::FrameSink;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Where a call writes: the output directory and whether a folder rubsim did not make may be
/// taken (the command line's `--force`).
pub struct Out {
    /// The directory, or none (nothing written).
    pub dir: Option<PathBuf>,
    /// Take a non-empty folder rubsim did not make.
    pub force: bool,
}

impl Out {
    /// The output directory prepared and locked ([`OutDir::prepare`]); `None` without one.
    pub fn open(&self) -> Result<Option<OutDir>> {
        self.dir
            .as_deref()
            .map(|d| open_dir(d, self.force))
            .transpose()
    }
}

/// [`OutDir::prepare`], or [`OutDir::prepare_forced`] with `force`.
pub fn open_dir(dir: &Path, force: bool) -> Result<OutDir> {
    if force {
        OutDir::prepare_forced(dir)
    } else {
        OutDir::prepare(dir)
    }
}

/// `rows × k` values as a numpy array of that shape (rows of `k` columns, flattened in `flat`).
pub fn array2<'py>(py: Python<'py>, flat: Vec<f64>, k: usize) -> PyResult<Bound<'py, PyAny>> {
    let n = flat.len() / k.max(1);
    Ok(PyArray1::from_vec(py, flat).reshape([n, k])?.into_any())
}

/// Pairs as an `n × 2` numpy array.
pub fn pairs<'py>(py: Python<'py>, v: &[[f64; 2]]) -> PyResult<Bound<'py, PyAny>> {
    array2(py, v.iter().flatten().copied().collect(), 2)
}

/// Tuples as an `n × 2` numpy array.
fn tuples<'py>(py: Python<'py>, v: &[(f64, f64)]) -> PyResult<Bound<'py, PyAny>> {
    array2(py, v.iter().flat_map(|&(a, b)| [a, b]).collect(), 2)
}

/// JSON text of a summary body.
pub fn json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| StudyError::new_err(e.to_string()))
}

/// ν = `speed`, else the scene's single speed (`run.speed_ratio`, `run.speed`).
fn speed_of(ls: &LoadedScene, model: &Model, speed: Option<f64>) -> PyResult<f64> {
    speed
        .or_else(|| analysis::single_speed(&ls.scene.run, model))
        .ok_or_else(|| {
            StudyError::new_err(format!(
                "{}: the scene has no run.speed_ratio or run.speed: give speed= (or use sweep())",
                ls.file.display()
            ))
        })
}

/// The run at ν = `speed` (default: the scene's single speed) of `ls`'s `model`, with the step
/// `rubsim run` chooses; see the module.
pub fn run_speed<'py>(
    py: Python<'py>,
    (ls, model): (&LoadedScene, &Model),
    speed: Option<f64>,
    out: Out,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    if ls.scene.run.speed_profile.is_some() {
        return Err(StudyError::new_err(format!(
            "{}: the scene has [run.speed_profile]: run it with transient()",
            ls.file.display()
        )));
    }
    if ls.scene.thermal.is_some() {
        return Err(StudyError::new_err(format!(
            "{}: the scene has [thermal]: run it with thermal()",
            ls.file.display()
        )));
    }
    let v = speed_of(ls, model, speed)?;
    let mut hooks = StepProgress::new(progress);
    let started = Instant::now();
    let ran = py.detach(|| -> Result<(SpeedResults, Option<PathBuf>)> {
        let outd = out.open()?;
        let s = rubsim::study::run_settings(ls, model, &[v])?;
        if let Some(outd) = outd {
            let (r, dir) = single::run_speed(outd, (ls, model), (&s, v), started, &mut hooks)?;
            return Ok((r, Some(dir)));
        }
        let prep = analysis::prepare(model, &s.request_at(0, v))?;
        hooks.plan(prep.plan.steps);
        let mut sinks: [&mut dyn FrameSink; 1] = [&mut hooks];
        let keep = Keep::single_run(&ls.scene.output, v);
        Ok((prep.run(keep, &mut sinks)?, None))
    });
    let (r, dir) = ran.map_err(|e| hooks.error(e))?;
    let d = PyDict::new(py);
    let body = RunBody::new(&r, started.elapsed().as_secs_f64());
    d.set_item("summary", json(&body)?)?;
    d.set_item("orbit", pairs(py, &r.orbit_nd)?)?;
    d.set_item("poincare", pairs(py, &r.poincare_nd)?)?;
    d.set_item("spectrum", tuples(py, &r.spectrum)?)?;
    d.set_item("full_spectrum", tuples(py, &r.full_spectrum)?)?;
    d.set_item("force_history", tuples(py, &r.force_history)?)?;
    let mut warnings = analysis::notices::run_warnings(&r, ls.scene.run.tolerance);
    warnings.append(&mut hooks.warnings);
    d.set_item("warnings", warnings)?;
    d.set_item("dir", dir)?;
    Ok(d)
}

/// The speed transient of `ls` (`[run.speed_profile]`) on `model`; see the module. The arrays:
/// `spin` (t, Ω, φ, Ω̇ per recorded sample), `response` (x, y of the analysed node, m),
/// `contact` (|F| on station 0, friction power, friction energy so far), `torque` (a driven
/// rotor's drive and friction torques; empty otherwise).
pub fn run_transient<'py>(
    py: Python<'py>,
    (ls, model): (&LoadedScene, &Model),
    out: Out,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let spec = ls.scene.run.speed_profile.as_ref().ok_or_else(|| {
        StudyError::new_err(format!(
            "{}: the scene has no [run.speed_profile]: give one (or use run())",
            ls.file.display()
        ))
    })?;
    let mut hooks = StepProgress::new(progress);
    let started = Instant::now();
    type Ran = (
        analysis::TransientResults,
        Vec<WaterfallWindow>,
        Option<PathBuf>,
    );
    let ran = py.detach(|| -> Result<Ran> {
        if let Some(outd) = out.open()? {
            let t = single::run_transient(outd, (ls, model), started, &mut hooks)?;
            return Ok((t.results, t.waterfall, Some(t.dir)));
        }
        let s = analysis::RunSettings::from_scene(&ls.scene);
        let prep =
            analysis::prepare_transient(model, &s, spec)?.with_events(&ls.scene.run.event)?;
        hooks.plan(prep.plan.steps);
        let mut sinks: [&mut dyn FrameSink; 1] = [&mut hooks];
        let r = prep.run(&mut sinks)?;
        let wf = waterfall::full_waterfall(&r, prep.window_revolutions);
        hooks
            .warnings
            .extend(waterfall::roll_warnings(&prep.case, &prep.plan, &wf));
        Ok((r, wf, None))
    });
    let (r, wf, dir) = ran.map_err(|e| hooks.error(e))?;
    let d = PyDict::new(py);
    d.set_item("summary", json(&r)?)?;
    d.set_item(
        "spin",
        array2(py, r.spin.iter().flatten().copied().collect(), 4)?,
    )?;
    d.set_item("response", pairs(py, &r.response)?)?;
    let contact = r.contact.iter().flatten().copied().collect();
    d.set_item("contact", array2(py, contact, 3)?)?;
    d.set_item("torque", pairs(py, &r.torque)?)?;
    d.set_item("waterfall", windows(py, &wf)?)?;
    d.set_item("wear", wear(py, r.wear.as_ref())?)?;
    d.set_item("warnings", std::mem::take(&mut hooks.warnings))?;
    d.set_item("dir", dir)?;
    Ok(d)
}

/// A transient's full-spectrum windows as a dict of numpy columns: `t` (s, middle angle),
/// `omega` (rad/s), `frequency` (the strongest line, rad/s, backward < 0), `contact_fraction`,
/// `stick_fraction` (NaN without stick) and `dry_rub` (a list: "whirl", "whip" or None).
fn windows<'py>(py: Python<'py>, wf: &[WaterfallWindow]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let col = |f: &dyn Fn(&WaterfallWindow) -> f64| {
        PyArray1::from_vec(py, wf.iter().map(f).collect::<Vec<f64>>())
    };
    d.set_item("t", col(&|w| w.t))?;
    d.set_item("omega", col(&|w| w.omega))?;
    d.set_item(
        "frequency",
        col(&|w| w.lines.first().map_or(0.0, |l| l.0 * w.omega)),
    )?;
    d.set_item("contact_fraction", col(&|w| w.contact_fraction))?;
    d.set_item(
        "stick_fraction",
        col(&|w| w.stick_fraction.unwrap_or(f64::NAN)),
    )?;
    let dry: Vec<Option<&str>> = wf.iter().map(|w| w.dry_rub.map(|c| c.key())).collect();
    d.set_item("dry_rub", dry)?;
    Ok(d)
}

/// A transient's wear (`[stator.wear]`) as a dict: `history` (n × 3: t s, volume worn m³,
/// largest depth m), the worn contact nodes' columns `stator` (names), `node`, `x`, `y`, `z`,
/// `angle_deg`, `area`, `depth` and, with an abradable coating, `abraded`; `None` without wear
/// or coating.
fn wear<'py>(
    py: Python<'py>,
    w: Option<&rubsim::analysis::wear::WearResults>,
) -> PyResult<Option<Bound<'py, PyDict>>> {
    let Some(w) = w else {
        return Ok(None);
    };
    let d = PyDict::new(py);
    let flat = w.history.iter().flatten().copied().collect();
    d.set_item("history", array2(py, flat, 3)?)?;
    let col = |f: &dyn Fn(&rubsim::analysis::wear::WornNode) -> f64| {
        PyArray1::from_vec(py, w.nodes.iter().map(f).collect::<Vec<f64>>())
    };
    let names: Vec<&str> = w.nodes.iter().map(|n| n.stator.as_str()).collect();
    d.set_item("stator", names)?;
    let nodes: Vec<usize> = w.nodes.iter().map(|n| n.node).collect();
    d.set_item("node", nodes)?;
    d.set_item("x", col(&|n| n.x))?;
    d.set_item("y", col(&|n| n.y))?;
    d.set_item("z", col(&|n| n.z))?;
    d.set_item("angle_deg", col(&|n| n.angle_deg))?;
    d.set_item("area", col(&|n| n.area_m2))?;
    d.set_item("depth", col(&|n| n.depth_m))?;
    // With an abradable coating (`[stator.abradable]`): its plastic shortening, part of `depth`.
    if w.abradable.is_some() {
        d.set_item("abraded", col(&|n| n.abraded_m))?;
    }
    Ok(Some(d))
}

/// The damped modes of the rotor alone at Ω = `speed` (rad/s), the `modes` lowest: the JSON of
/// `linear::modal`'s results (ω_d, ζ, log dec, whirl, kind, shapes of each mode).
pub fn modal(py: Python<'_>, model: &Model, speed: f64, modes: usize) -> PyResult<String> {
    if !(speed.is_finite() && speed >= 0.0) {
        return Err(StudyError::new_err(format!(
            "speed must be a finite speed ≥ 0 (rad/s), got {speed}"
        )));
    }
    if modes == 0 {
        return Err(StudyError::new_err("modes must be at least 1"));
    }
    let res = py
        .detach(|| rubsim::linear::modal(&model.rotor, speed, modes))
        .py_err()?;
    json(&res)
}

/// Refuses a period of 0 revolutions.
fn check_period(period: Option<usize>) -> PyResult<()> {
    match period {
        Some(0) => Err(StudyError::new_err(
            "period must be a whole number of revolutions ≥ 1, got 0",
        )),
        _ => Ok(()),
    }
}

/// The periodic orbit of `period` revolutions (default: the settled run's) at ν = `speed`
/// (default: the scene's) by shooting, as `rubsim periodic`: the JSON of
/// `analysis::periodic::PeriodicOrbit` (multipliers, stability, the orbit's results) and, with
/// `refine` (`rubsim periodic --refine`), its `refined` member: the
/// `analysis::floquet::StepRefinement` of the multipliers at half the step.
pub fn periodic(
    py: Python<'_>,
    (ls, model): (&LoadedScene, &Model),
    speed: Option<f64>,
    period: Option<usize>,
    refine: bool,
) -> PyResult<String> {
    check_period(period)?;
    let v = speed_of(ls, model, speed)?;
    let (orbit, refined) = py
        .detach(|| {
            let s = rubsim::study::shooting_settings(ls, model, &[v])?;
            analysis::floquet::shoot_refined(model, &s, v, period, refine)
        })
        .py_err()?;
    #[derive(serde::Serialize)]
    struct WithRefined<'a> {
        #[serde(flatten)]
        orbit: &'a analysis::periodic::PeriodicOrbit,
        refined: Option<&'a analysis::floquet::StepRefinement>,
    }
    json(&WithRefined {
        orbit: &orbit,
        refined: refined.as_ref(),
    })
}

/// The autonomous orbit (a whirl at its own frequency, dry whip) at ν = `speed` (default: the
/// scene's single speed), as `rubsim periodic --autonomous`: the JSON of
/// `analysis::autonomous::AutonomousOrbit`.
pub fn periodic_autonomous(
    py: Python<'_>,
    (ls, model): (&LoadedScene, &Model),
    speed: Option<f64>,
) -> PyResult<String> {
    let v = speed_of(ls, model, speed)?;
    let o = py
        .detach(|| {
            let s = rubsim::study::shooting_settings(ls, model, &[v])?;
            let prep = analysis::prepare(model, &analysis::periodic::request_at(&s, v))?;
            analysis::autonomous::shoot_autonomous(&prep)
        })
        .py_err()?;
    json(&o)
}

/// The autonomous orbit continued over ν `from … to` by `step` (default: the scene's
/// `[run.sweep]`), or with `key` over that key's values at the fixed ν `speed` (default: the
/// scene's), as `rubsim continue --autonomous`: the JSON of
/// `analysis::autonomous_branch::AutonomousBranch`.
pub fn continuation_autonomous(
    py: Python<'_>,
    (ls, model): (&LoadedScene, &Model),
    (key, speed): (Option<&str>, Option<f64>),
    range: [Option<f64>; 3],
) -> PyResult<String> {
    let (at, abh, speeds) = match key {
        Some(k) => {
            let v = speed_of(ls, model, speed)?;
            let [Some(a), Some(b), Some(h)] = range else {
                return Err(StudyError::new_err(format!(
                    "key={k} needs from_=, to= and step=, in the key's own units"
                )));
            };
            (Some((k, v)), (a, b, h), vec![v])
        }
        None => {
            let (a, b, h) = sweep_range(ls, range)?;
            let speeds = analysis::continuation::speeds(a, b, h).py_err()?;
            (None, (a, b, h), speeds)
        }
    };
    let branch = py
        .detach(|| {
            let s = rubsim::study::shooting_settings(ls, model, &speeds)?;
            analysis::continuation::continue_autonomous((ls, model), &s, at, abh)
        })
        .py_err()?;
    json(&branch)
}

/// `(from, to, step)` as given, each missing one from the scene's `[run.sweep]`.
fn sweep_range(ls: &LoadedScene, range: [Option<f64>; 3]) -> PyResult<(f64, f64, f64)> {
    let scene = ls.scene.run.sweep.as_ref().map(|s| [s.from, s.to, s.step]);
    let mut abh = [0.0; 3];
    for (k, name) in ["from_", "to", "step"].iter().enumerate() {
        abh[k] = range[k].or(scene.map(|s| s[k])).ok_or_else(|| {
            StudyError::new_err(format!(
                "{}: give {name}= (the scene has no [run.sweep])",
                ls.file.display()
            ))
        })?;
    }
    Ok((abh[0], abh[1], abh[2]))
}

/// The period-`period` orbit continued over ν `from … to` by `step` (default: the scene's
/// `[run.sweep]`), by pseudo-arclength in at most `arclength` points when given, as `rubsim
/// continue`: the JSON of `analysis::branch::Branch`.
pub fn continuation(
    py: Python<'_>,
    (ls, model): (&LoadedScene, &Model),
    range: [Option<f64>; 3],
    period: Option<usize>,
    (arclength, switch): (Option<usize>, Option<usize>),
) -> PyResult<String> {
    check_period(period)?;
    if switch.is_some_and(|m| m < 2) {
        return Err(StudyError::new_err(
            "max_period must be at least 2 (a switched branch doubles the period)",
        ));
    }
    let (a, b, h) = sweep_range(ls, range)?;
    let speeds = analysis::continuation::speeds(a, b, h).py_err()?;
    let s = py
        .detach(|| rubsim::study::shooting_settings(ls, model, &speeds))
        .py_err()?;
    if let Some(max_period) = switch {
        let d = py
            .detach(|| match arclength {
                Some(n) => analysis::continuation::arclength_switching(
                    model,
                    &s,
                    (a, b, h),
                    period,
                    (n, max_period),
                ),
                None => analysis::continuation::continue_switching(
                    model,
                    &s,
                    (a, b, h),
                    period,
                    max_period,
                ),
            })
            .py_err()?;
        return json(&d);
    }
    let branch = py
        .detach(|| analysis::continuation::continue_branch(model, &s, (a, b, h), period, arclength))
        .py_err()?;
    json(&branch)
}

/// The period-`period` orbit at ν = `speed` (default: the scene's single speed) continued over
/// the scene key `key` from `from` to `to` by `step` (the key's units), as `rubsim continue
/// --key`: the JSON of `analysis::switch::Diagram` (its one branch without `switch`).
pub fn continuation_key(
    py: Python<'_>,
    (ls, model): (&LoadedScene, &Model),
    (key, speed): (&str, Option<f64>),
    range: [Option<f64>; 3],
    period: Option<usize>,
    (arclength, switch): (Option<usize>, Option<usize>),
) -> PyResult<String> {
    check_period(period)?;
    let v = speed_of(ls, model, speed)?;
    let [Some(a), Some(b), Some(h)] = range else {
        return Err(StudyError::new_err(format!(
            "key={key} needs from_=, to= and step=, in the key's own units"
        )));
    };
    let branch = analysis::continuation::KeyBranch {
        key,
        speed_ratio: v,
        range: (a, b, h),
        period,
        arclength,
        switch,
    };
    let d = py
        .detach(|| {
            let s = rubsim::study::shooting_settings(ls, model, &[v])?;
            analysis::continuation::continue_key(ls, &s, &branch)
        })
        .py_err()?;
    json(&d)
}

/// The thermal spiral of `[thermal]` at ν = `speed` (default: the scene's), as `rubsim run`
/// runs it: `summary` (JSON of `analysis::thermal::ThermalResults`), per coupling step `t`
/// (s), `delta_t` (K), `bow` (m), `one_x` (m), `heat` (W) — n × 2, rotor frame —, `power` (W),
/// `contact_fraction`, `non_synchronous` (the orbit's change over a revolution relative to its
/// radius; the run stops where it passes 0.05), and `dir`.
pub fn run_thermal<'py>(
    py: Python<'py>,
    (ls, model): (&LoadedScene, &Model),
    speed: Option<f64>,
    out: Out,
) -> PyResult<Bound<'py, PyDict>> {
    let hs = analysis::thermal::HotSpot::of_scene(ls).ok_or_else(|| {
        StudyError::new_err(format!(
            "{}: the scene has no [thermal]: give one (or use run())",
            ls.file.display()
        ))
    })?;
    let v = speed_of(ls, model, speed)?;
    let started = Instant::now();
    let (r, dir) = py
        .detach(
            || -> Result<(analysis::thermal::ThermalResults, Option<PathBuf>)> {
                let outd = out.open()?;
                let s = rubsim::study::run_settings(ls, model, &[v])?;
                if let Some(outd) = outd {
                    let (r, dir) = single::run_thermal(outd, (ls, model), (&s, v), started)?;
                    return Ok((r, Some(dir)));
                }
                Ok((analysis::thermal::run_thermal(model, &s, v, &hs)?, None))
            },
        )
        .py_err()?;
    let d = PyDict::new(py);
    d.set_item("summary", json(&r)?)?;
    let col = |f: &dyn Fn(&analysis::thermal::ThermalSample) -> [f64; 2]| -> Vec<[f64; 2]> {
        r.samples.iter().map(f).collect()
    };
    let t: Vec<f64> = r.samples.iter().map(|s| s.t_s).collect();
    d.set_item("t", PyArray1::from_vec(py, t))?;
    d.set_item("delta_t", pairs(py, &col(&|s| s.delta_t))?)?;
    d.set_item("bow", pairs(py, &col(&|s| s.bow))?)?;
    d.set_item("one_x", pairs(py, &col(&|s| s.one_x))?)?;
    d.set_item("heat", pairs(py, &col(&|s| s.heat))?)?;
    let power: Vec<f64> = r.samples.iter().map(|s| s.power).collect();
    d.set_item("power", PyArray1::from_vec(py, power))?;
    let contact: Vec<f64> = r.samples.iter().map(|s| s.contact_fraction).collect();
    d.set_item("contact_fraction", PyArray1::from_vec(py, contact))?;
    let change: Vec<f64> = r.samples.iter().map(|s| s.non_synchronous).collect();
    d.set_item("non_synchronous", PyArray1::from_vec(py, change))?;
    d.set_item("dir", dir)?;
    Ok(d)
}
