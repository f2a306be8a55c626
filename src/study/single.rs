//! One run written to an output directory exactly as `rubsim run` writes it — the steady run at
//! one speed ([`run_speed`]) and the speed transient ([`run_transient`]) — for the command line
//! and the Python package alike: the VTK/HDF5 series streamed into the staging folder, the CSVs
//! and figures, `summary.json` last (the commit, [`crate::output::summary::finish`]).
//!
//! What a caller shows while the run goes (an estimate, a progress bar, a Python callback) and
//! the warnings it prints go through [`RunHooks`]; nothing here prints.

use crate::analysis::{self, Keep, Prepared, SpeedResults, TransientPrepared, TransientResults};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::output::summary::{self, Base, RunBody, SnapshotsRecord, Summary};
use crate::output::summary::{ThermalBody, TransientBody, WaterfallRecord};
use crate::output::transient_stress::TransientStress;
use crate::output::{figures, transient as transient_out, whirl as whirl_out, OutDir};
use crate::results::{ResultsSink, Series};
use crate::scene::LoadedScene;
use crate::time::FrameSink;
use std::path::PathBuf;
use std::time::Instant;

/// What a caller of [`run_speed`] or [`run_transient`] sees of the run while it goes.
pub trait RunHooks {
    /// The steady run is prepared (its case and step plan built), before it integrates.
    fn prepared(&mut self, _prep: &Prepared) {}
    /// The transient is prepared, before it integrates.
    fn transient_prepared(&mut self, _prep: &TransientPrepared) {}
    /// A sink that follows the main run's frames (a progress bar, a callback), or none.
    fn progress(&mut self) -> Option<&mut dyn FrameSink> {
        None
    }
    /// Something the user should know that does not stop the run.
    fn warning(&mut self, _message: &str) {}
}

/// [`RunHooks`] that show nothing.
pub struct Silent;

impl RunHooks for Silent {}

/// The scene as JSON, stored with the series and the summary.
fn scene_json(ls: &LoadedScene, outd: &OutDir) -> Result<String> {
    serde_json::to_string(&ls.scene).map_err(|e| Error::output(outd.dir(), e))
}

/// The run of `ls`'s `model` at ν = `speed` (ω/ω_n) with the settings `s` (the step chosen for
/// that speed: [`super::run_settings`]), written into `outd` as `rubsim run` writes it — the
/// VTK/HDF5 series the scene asks for, `orbit.png`, `spectrum.png`, `contact_force.png` and
/// the full-spectrum files when `output.png`, `summary.json` — and committed. `started`: when
/// the command began (the summary's `wall_s`). Returns the results and the committed folder.
///
/// # Errors
/// The run's errors ([`analysis::prepare`], [`Prepared::run`]) and the writers'.
pub fn run_speed(
    mut outd: OutDir,
    (ls, model): (&LoadedScene, &Model),
    (s, speed): (&analysis::RunSettings, f64),
    started: Instant,
    hooks: &mut dyn RunHooks,
) -> Result<(SpeedResults, PathBuf)> {
    let keep = Keep::single_run(&ls.scene.output, speed);
    let writes_series = crate::results::wanted(&ls.scene.output);
    let prep = analysis::prepare(model, &s.request_for(0, speed, writes_series))?;
    hooks.prepared(&prep);
    let scene_json = scene_json(ls, &outd)?;
    let series = Series {
        output: &ls.scene.output,
        scene_json: &scene_json,
        staging: outd.staging_dir(),
    };
    let (r, written) = series.run_with(model, &prep, keep, "", hooks.progress())?;
    for name in &written {
        outd.adopt(name)?;
    }
    if ls.scene.output.png {
        let bound = figures::boundary(&prep.case);
        let component = &ls.scene.output.component;
        figures::write_run(&mut outd, &ls.scene.title, &r, bound, component)?;
    }
    whirl_out::write_run(&mut outd, &ls.scene.title, &r, ls.scene.output.png)?;
    let body = RunBody::new(&r, started.elapsed().as_secs_f64());
    let base = Base::new(ls, model, "run");
    let dir = summary::finish(outd, &Summary { base, body })?;
    Ok((r, dir))
}

/// What [`run_transient`] computed and where it is.
pub struct TransientRun {
    /// The transient's results.
    pub results: TransientResults,
    /// The stators' stress against time and speed, when a stator has elements.
    pub stress: Option<TransientStress>,
    /// The speeds of `output.snapshot_speeds` the speed history never passes.
    pub missed_snapshots: Vec<f64>,
    /// The full-spectrum waterfall's windows, each with its contact state and dry-friction
    /// class (`analysis::waterfall`).
    pub waterfall: Vec<analysis::waterfall::WaterfallWindow>,
    /// The committed output folder.
    pub dir: PathBuf,
}

/// The speed transient of `ls` (`[run.speed_profile]`, its events) on `model`, written into
/// `outd` as `rubsim run` writes it: the VTK/HDF5 series (each frame with Ω, Ω/ω_n, φ, Ω̇), the
/// speed history, response and order tracking (CSV), the stators' stress when they have
/// elements, the orbit snapshots of `output.snapshot_speeds`, the full-spectrum waterfall,
/// their pictures when `output.png`, and `summary.json`; committed.
///
/// # Errors
/// A scene without `[run.speed_profile]` ([`Error::Study`]); the transient's errors
/// ([`analysis::prepare_transient`], [`TransientPrepared::run`]) and the writers'.
pub fn run_transient(
    mut outd: OutDir,
    (ls, model): (&LoadedScene, &Model),
    started: Instant,
    hooks: &mut dyn RunHooks,
) -> Result<TransientRun> {
    let spec =
        ls.scene.run.speed_profile.as_ref().ok_or_else(|| {
            Error::study(ls.file.display(), "the scene has no [run.speed_profile]")
        })?;
    let s = analysis::RunSettings::from_scene(&ls.scene);
    let prep = analysis::prepare_transient(model, &s, spec)?.with_events(&ls.scene.run.event)?;
    hooks.transient_prepared(&prep);
    let scene_json = scene_json(ls, &outd)?;
    let staging = outd.staging_dir().to_path_buf();
    let (output, title) = (&ls.scene.output, &ls.scene.title);
    let mut writer = ResultsSink::for_transient(model, &prep, output, &scene_json, &staging, "")?;
    let mut probe = stress_probe(&prep);
    let mut sinks: Vec<&mut dyn FrameSink> = Vec::with_capacity(3);
    sinks.extend(writer.as_mut().map(|w| w as &mut dyn FrameSink));
    sinks.extend(probe.as_mut().map(|p| p as &mut dyn FrameSink));
    sinks.extend(hooks.progress());
    let r = prep.run(&mut sinks)?;
    drop(sinks);
    for name in writer.map(|w| w.finish()).transpose()?.unwrap_or_default() {
        outd.adopt(&name)?;
    }
    let stress = probe.map(|p| TransientStress::new(&r, p.traces));
    if let Some(st) = &stress {
        st.write_csv(&mut outd)?;
        if output.png {
            st.write_figures(&mut outd, title)?;
        }
    }
    transient_out::write_csv(&mut outd, &r)?;
    let (snaps, missed) = analysis::orbit_snapshots(&prep, &r, &output.snapshot_speeds)?;
    for v in &missed {
        hooks.warning(&missed_snapshot(ls, &r, *v));
    }
    if !output.snapshot_speeds.is_empty() {
        transient_out::write_snapshots(&mut outd, title, &snaps, &prep.case, output.png)?;
    }
    let waterfall = analysis::waterfall::full_waterfall(&r, prep.window_revolutions);
    for w in analysis::waterfall::roll_warnings(&prep.case, &prep.plan, &waterfall) {
        hooks.warning(&w);
    }
    whirl_out::write_waterfall(&mut outd, title, &waterfall, r.omega_n, output.png)?;
    if output.png {
        transient_out::write_figures(&mut outd, title, &r, &output.component)?;
    }
    if let Some(w) = &r.wear {
        crate::output::wear::write(&mut outd, title, w, output.png)?;
    }
    let body = TransientBody {
        transient: &r,
        stator_stress: stress.as_ref(),
        orbit_snapshots: (!output.snapshot_speeds.is_empty()).then_some(SnapshotsRecord {
            revolutions: analysis::SNAPSHOT_REVOLUTIONS,
            snapshots: &snaps,
            missed_speed_ratios: &missed,
        }),
        full_waterfall: WaterfallRecord {
            windows: waterfall.len(),
            window_revolutions: prep.window_revolutions,
            backward_dominant_windows: waterfall
                .iter()
                .filter(|w| w.lines.first().is_some_and(|l| l.0 < 0.0))
                .count(),
            dry_rub: analysis::waterfall::dry_spans(&waterfall, r.omega_n),
        },
        wall_s: started.elapsed().as_secs_f64(),
    };
    let base = Base::new(ls, model, "run");
    let dir = summary::finish(outd, &Summary { base, body })?;
    Ok(TransientRun {
        results: r,
        stress,
        missed_snapshots: missed,
        waterfall,
        dir,
    })
}

/// The stress probe of a transient whose stators have elements (meshed, bars, frames): their
/// largest stress at every recorded sample (the probe's interval is the recording interval, so
/// its instants are the speed history's); `None` without such a stator.
pub fn stress_probe(prep: &TransientPrepared) -> Option<analysis::StressProbe<'_>> {
    prep.case
        .stators
        .iter()
        .any(|s| !s.elements.is_empty())
        .then(|| analysis::StressProbe::new(&prep.case.stators, prep.plan.record_every, 0.0))
}

/// The warning for a snapshot speed `v` (ω/ω_n) the speed history of `r` never passes.
fn missed_snapshot(ls: &LoadedScene, r: &TransientResults, v: f64) -> String {
    let (lo, hi) = r.spin.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), s| {
        (lo.min(s[1]), hi.max(s[1]))
    });
    format!(
        "{}: output.snapshot_speeds: the speed history never passes ω/ωn = {v} (it spans {:.3} … {:.3} ωn); no snapshot at that speed",
        ls.file.display(),
        lo / r.omega_n,
        hi / r.omega_n,
    )
}

/// The thermal spiral of `ls` (`[thermal]`) on `model` at ν = `speed` with the settings `s`,
/// written into `outd` as `rubsim run` writes it — `spiral.csv`, `spiral.png` and `thermal.png`
/// when `output.png`, `summary.json` — and committed. Returns the results and the committed
/// folder.
///
/// # Errors
/// A scene without `[thermal]` ([`Error::Study`]); the run's errors
/// ([`analysis::thermal::run_thermal`]) and the writers'.
pub fn run_thermal(
    mut outd: OutDir,
    (ls, model): (&LoadedScene, &Model),
    (s, speed): (&analysis::RunSettings, f64),
    started: Instant,
) -> Result<(analysis::thermal::ThermalResults, PathBuf)> {
    let hs = analysis::thermal::HotSpot::of_scene(ls)
        .ok_or_else(|| Error::study(ls.file.display(), "the scene has no [thermal]"))?;
    let r = analysis::thermal::run_thermal(model, s, speed, &hs)?;
    crate::output::thermal::write_thermal(&mut outd, &ls.scene.title, &r, ls.scene.output.png)?;
    let body = ThermalBody {
        thermal: &r,
        wall_s: started.elapsed().as_secs_f64(),
    };
    let base = Base::new(ls, model, "run");
    let dir = summary::finish(outd, &Summary { base, body })?;
    Ok((r, dir))
}
