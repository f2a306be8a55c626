//! `summary.json` as typed records serialised by serde: the [`Base`] every scene command
//! shares (version, command, scene, model, conventions), each command's own record
//! ([`Summary`] = base + body), and the finishing step that writes it last and commits the
//! output directory.
//!
//! The file's keys are in alphabetical order at every level (the records go through
//! `serde_json::Value`, whose maps are sorted), whatever the order of the fields below.
//! Sweeps' and maps' records are `crate::study::summary`'s.

use super::OutDir;
use crate::analysis::refine::RefinePoint;
use crate::analysis::{ConvergenceResults, SpeedResults, StressResults, TransientResults};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::scene::{LoadedScene, Scene};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The rotor model as `summary.json` (and a study's case store) records it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ModelRecord {
    /// ω_n, the rotor's first lateral natural frequency at rest (rad/s).
    pub omega_n_rad_s: f64,
    /// The rotor's description (`Rotor::describe`).
    pub rotor: String,
}

impl ModelRecord {
    /// The record of `model`.
    pub fn of(model: &Model) -> Self {
        Self {
            omega_n_rad_s: model.rotor.natural_frequency(),
            rotor: model.rotor.describe(),
        }
    }
}

/// The conventions of the numbers, written into every scene command's summary.
#[derive(Debug, Clone, Serialize)]
pub struct Conventions {
    /// Units and the non-dimensional scales.
    pub units: &'static str,
    /// The axes and the sense of the spin.
    pub axes: &'static str,
    /// What the Poincaré period counts.
    pub period: &'static str,
    /// The dynamics classes.
    pub dynamics: &'static str,
}

/// The conventions of every summary.
pub const CONVENTIONS: Conventions = Conventions {
    units: "SI; _nd = displacement / |Z0(ω)|, force / (|Σ m_u e e^{iφ}| ω²), frequency / ω_n",
    axes: "x horizontal, y vertical, rotor spins counter-clockwise seen from +z",
    period: "Poincaré period in revolutions (the whole orbit repeats to run.tolerance of its size); 0 = not periodic",
    dynamics: "periodic, quasi-periodic (0-1 test K < 0.2 on the Poincaré section), chaotic (K > 0.8) or undetermined; long_period = a period above 8 found on the Poincaré points (docs/OUTPUTS.md)",
};

/// The part of `summary.json` every scene command writes.
#[derive(Debug, Clone, Serialize)]
pub struct Base<'a> {
    /// Version of the program.
    pub rubsim_version: &'static str,
    /// The command (`run`, `sweep`, `map shard`, …).
    pub command: String,
    /// The scene file as given on the command line.
    pub scene_file: String,
    /// The overrides (`--set`, then `run.tolerance` from `--tol`).
    pub overrides: &'a [String],
    /// The resolved scene, every override applied.
    pub scene: &'a Scene,
    /// The rotor model.
    pub model: ModelRecord,
    /// The conventions of the numbers.
    pub conventions: Conventions,
}

impl<'a> Base<'a> {
    /// The base of `command` on the scene `ls` and its model.
    pub fn new(ls: &'a LoadedScene, model: &Model, command: &str) -> Self {
        Self::with_model(ls, ModelRecord::of(model), command)
    }

    /// [`Base::new`] with the model record given (e.g. kept with a study's cases, so
    /// `rubsim merge` needs no model).
    pub fn with_model(ls: &'a LoadedScene, model: ModelRecord, command: &str) -> Self {
        Self {
            rubsim_version: env!("CARGO_PKG_VERSION"),
            command: command.to_string(),
            scene_file: ls.file.display().to_string(),
            overrides: &ls.overrides,
            scene: &ls.scene,
            model,
            conventions: CONVENTIONS,
        }
    }
}

/// A scene command's `summary.json`: the [`Base`] and the command's own keys (`body`).
#[derive(Debug, Clone, Serialize)]
pub struct Summary<'a, T> {
    /// What every scene command writes.
    #[serde(flatten)]
    pub base: Base<'a>,
    /// The command's own keys.
    #[serde(flatten)]
    pub body: T,
}

/// `rubsim run` at one speed.
#[derive(Debug, Clone, Serialize)]
pub struct RunBody<'a> {
    /// The run's results.
    pub result: &'a SpeedResults,
    /// The regime's label (`analysis::regime_label`).
    pub regime: String,
    /// The dynamics class's name.
    pub dynamics: &'static str,
    /// Whether another response coexists (only when the coexistence check ran).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coexisting: Option<bool>,
    /// Wall time of the command (s).
    pub wall_s: f64,
}

impl<'a> RunBody<'a> {
    /// The body of the run `result`, the command having taken `wall_s` seconds.
    pub fn new(result: &'a SpeedResults, wall_s: f64) -> Self {
        Self {
            result,
            regime: crate::analysis::regime_label(result),
            dynamics: result.dynamics.regime.name(),
            coexisting: result.coexistence.as_ref().map(|c| c.coexisting),
            wall_s,
        }
    }
}

/// `rubsim run` of a scene with `[thermal]`: the thermal spiral.
#[derive(Debug, Clone, Serialize)]
pub struct ThermalBody<'a> {
    /// The spiral's results.
    pub thermal: &'a crate::analysis::thermal::ThermalResults,
    /// Wall time of the command (s).
    pub wall_s: f64,
}

/// `rubsim run` of a speed transient.
#[derive(Debug, Clone, Serialize)]
pub struct TransientBody<'a, S, O> {
    /// The transient's results.
    pub transient: &'a TransientResults,
    /// The stators' stress against time and speed (when a stator has elements).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stator_stress: Option<&'a S>,
    /// The orbit snapshots at `output.snapshot_speeds` (when asked for).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub orbit_snapshots: Option<SnapshotsRecord<'a, O>>,
    /// The full-spectrum waterfall's counts.
    pub full_waterfall: WaterfallRecord,
    /// Wall time of the command (s).
    pub wall_s: f64,
}

/// The orbit snapshots of a transient.
#[derive(Debug, Clone, Serialize)]
pub struct SnapshotsRecord<'a, O> {
    /// Revolutions each snapshot spans.
    pub revolutions: f64,
    /// The snapshots.
    pub snapshots: &'a [O],
    /// The asked speeds (ω/ω_n) the speed history never passes.
    pub missed_speed_ratios: &'a [f64],
}

/// The full-spectrum waterfall of a transient, counted.
#[derive(Debug, Clone, Serialize)]
pub struct WaterfallRecord {
    /// Windows of the waterfall.
    pub windows: usize,
    /// Revolutions per window.
    pub window_revolutions: usize,
    /// Windows whose dominant line whirls backward.
    pub backward_dominant_windows: usize,
    /// With stick: the spans of consecutive windows in dry whirl or dry whip, in time order
    /// (`crate::analysis::waterfall::dry_spans`); left out when there are none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub dry_rub: Vec<crate::analysis::waterfall::DrySpan>,
}

/// `rubsim convergence`.
#[derive(Debug, Clone, Serialize)]
pub struct ConvergenceBody<'a> {
    /// One study per speed.
    pub studies: &'a [ConvergenceResults],
}

/// `rubsim modal`, over the modal results `M`.
#[derive(Debug, Clone, Serialize)]
pub struct ModalBody<'a, M> {
    /// The modes.
    pub modal: &'a M,
    /// Largest |u_y| of the static deflection under gravity (m).
    pub static_deflection_max_m: f64,
}

/// `rubsim campbell`, over the Campbell results `C`.
#[derive(Debug, Clone, Serialize)]
pub struct CampbellBody<'a, C> {
    /// The Campbell diagram.
    pub campbell: &'a C,
}

/// `rubsim unbalance`, over the unbalance response `U`.
#[derive(Debug, Clone, Serialize)]
pub struct UnbalanceBody<'a, U> {
    /// The unbalance response.
    pub unbalance_response: &'a U,
}

/// `rubsim critical-map`, over the critical speed map `C`.
#[derive(Debug, Clone, Serialize)]
pub struct CriticalMapBody<'a, C> {
    /// The critical speed map.
    pub critical_map: &'a C,
}

/// Writes `summary` as `summary.json` last (keys sorted, see the module docs), moves every
/// staged file into place; returns the directory.
///
/// # Errors
/// [`Error::Output`] naming the file that could not be written or moved.
pub fn finish<S: Serialize>(mut out: OutDir, summary: &S) -> Result<PathBuf> {
    let path = out.dir().join("summary.json");
    let text = serde_json::to_value(summary)
        .and_then(|v| serde_json::to_string_pretty(&v))
        .map_err(|e| Error::output(&path, e))?;
    out.write("summary.json", text.as_bytes())?;
    let dir = out.dir().to_path_buf();
    out.commit()?;
    Ok(dir)
}

/// One stator at one speed of a stress run, with its peak stress and strain.
#[derive(Debug, Clone, Serialize)]
pub struct StressRecord {
    /// ω/ω_n.
    pub speed_ratio: f64,
    /// The stator's name.
    pub stator: String,
    /// Largest |stress| (Pa).
    pub peak_stress_pa: f64,
    /// Strain at that peak.
    pub peak_strain: f64,
    /// Time of the peak (s).
    pub peak_time_s: f64,
    /// Nodes in contact at the peak.
    pub contacts_at_peak: usize,
    /// Samples of the history.
    pub samples: usize,
    /// Time step (s).
    pub dt_s: f64,
}

/// The records of a stress run: one per stator and speed.
pub fn stress_records(r: &StressResults) -> Vec<StressRecord> {
    r.traces
        .iter()
        .map(|tr| StressRecord {
            speed_ratio: r.speed_ratio,
            stator: tr.name.clone(),
            peak_stress_pa: tr.peak_stress(),
            peak_strain: tr.peak_strain(),
            peak_time_s: tr.peak_time,
            contacts_at_peak: tr.peak_contacts.len(),
            samples: tr.t.len(),
            dt_s: r.plan.dt,
        })
        .collect()
}

/// The `summary.json` of `rubsim stress` (no scene base: the command's own record).
#[derive(Debug, Clone, Serialize)]
pub struct StressSummary<'a> {
    /// `"stress"`.
    pub command: &'static str,
    /// The scene file as given.
    pub scene_file: String,
    /// The overrides (`--set`).
    pub overrides: &'a [String],
    /// Samples per revolution of the stress histories.
    pub per_rev: usize,
    /// Revolutions of the analysed window.
    pub window_revolutions: usize,
    /// One record per stator and speed.
    pub results: Vec<StressRecord>,
}

impl<'a> StressSummary<'a> {
    /// The summary of a stress run of `scene_file`.
    pub fn new(
        scene_file: &Path,
        overrides: &'a [String],
        per_rev: usize,
        window: usize,
        results: Vec<StressRecord>,
    ) -> Self {
        Self {
            command: "stress",
            scene_file: scene_file.display().to_string(),
            overrides,
            per_rev,
            window_revolutions: window,
            results,
        }
    }
}

/// One refinement of `rubsim refine`: the key's value and its run.
#[derive(Debug, Clone, Serialize)]
pub struct RefineRecord {
    /// The key's value.
    pub value: String,
    /// Contact targets of the stator.
    pub targets: usize,
    /// Degrees of freedom of the model.
    pub dofs: usize,
    /// Orbit extents / |Z0|: x min, x max, y min, y max.
    pub extents_nd: [f64; 4],
    /// 1× amplitude / |Z0|.
    pub amp_1x_nd: f64,
    /// Largest contact force / (|U| ω²).
    pub contact_force_max_nd: f64,
    /// Relative ripple of the contact force.
    pub ripple: f64,
    /// Poincaré period (revolutions; 0 = not periodic).
    pub period: usize,
    /// Steps of the main run.
    pub steps: usize,
    /// Wall time of the run (s).
    pub wall_s: f64,
    /// Wall time per step (µs).
    pub us_per_step: f64,
    /// Set-up time (s).
    pub setup_s: f64,
    /// Time step (s).
    pub dt_s: f64,
}

impl RefineRecord {
    /// The record of one refinement `(value of the key, its run)`.
    pub fn new(value: &str, p: &RefinePoint) -> Self {
        let r = &p.results;
        Self {
            value: value.to_string(),
            targets: p.targets,
            dofs: p.dofs,
            extents_nd: r.extents_nd,
            amp_1x_nd: r.amp_1x_nd,
            contact_force_max_nd: r.contact_force_max_nd,
            ripple: p.ripple,
            period: r.period,
            steps: r.stats.steps,
            wall_s: r.stats.wall_s,
            us_per_step: p.us_per_step,
            setup_s: p.setup_s,
            dt_s: r.plan.dt,
        }
    }
}

/// The `summary.json` of `rubsim refine` (no scene base: the command's own record).
#[derive(Debug, Clone, Serialize)]
pub struct RefineSummary<'a> {
    /// `"refine"`.
    pub command: &'static str,
    /// The scene file as given.
    pub scene_file: String,
    /// The refined key.
    pub key: &'a str,
    /// The overrides (`--set`).
    pub overrides: &'a [String],
    /// One record per value of the key.
    pub results: Vec<RefineRecord>,
}

impl<'a> RefineSummary<'a> {
    /// The summary of a refinement of `key` in `scene_file`.
    pub fn new(
        scene_file: &Path,
        key: &'a str,
        overrides: &'a [String],
        results: Vec<RefineRecord>,
    ) -> Self {
        Self {
            command: "refine",
            scene_file: scene_file.display().to_string(),
            key,
            overrides,
            results,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn the_typed_base_and_body_write_the_keys_and_values_of_the_string_keyed_summary() {
        let file =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/single.toml");
        let ls = crate::scene::load(&file, &["run.tolerance=0.001".to_string()]).unwrap();
        let model = Model::from_scene(&ls).unwrap();
        let body = WaterfallRecord {
            windows: 3,
            window_revolutions: 8,
            backward_dominant_windows: 1,
            dry_rub: Vec::new(),
        };
        let typed = Summary {
            base: Base::new(&ls, &model, "run"),
            body: CriticalMapBody {
                critical_map: &body,
            },
        };
        // The summary as it was assembled by string keys before it was typed.
        let keyed = json!({
            "rubsim_version": env!("CARGO_PKG_VERSION"),
            "command": "run",
            "scene_file": ls.file.display().to_string(),
            "overrides": ls.overrides,
            "scene": ls.scene,
            "model": {
                "rotor": model.rotor.describe(),
                "omega_n_rad_s": model.rotor.natural_frequency(),
            },
            "conventions": {
                "units": CONVENTIONS.units,
                "axes": CONVENTIONS.axes,
                "period": CONVENTIONS.period,
                "dynamics": CONVENTIONS.dynamics,
            },
            "critical_map": {
                "windows": 3, "window_revolutions": 8, "backward_dominant_windows": 1,
            },
        });
        let v = serde_json::to_value(&typed).unwrap();
        assert_eq!(v, keyed);
        // Written with its keys sorted at every level, as the keyed summary was.
        assert_eq!(
            serde_json::to_string_pretty(&v).unwrap(),
            serde_json::to_string_pretty(&keyed).unwrap()
        );
        let keys: Vec<&String> = v.as_object().unwrap().keys().collect();
        assert!(keys.windows(2).all(|w| w[0] < w[1]), "{keys:?}");
    }
}
