//! A finished sweep's Poincaré points read back from its case store, to draw under the
//! branches of `rubsim continue --sweep DIR` (issue 29: the bifurcation diagram overlaid on the
//! sweep's Poincaré points).

use super::store::{scene_hash, CaseStore};
use super::{merge, Kind, Study};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::scene::LoadedScene;
use std::path::Path;

/// `(ν, value / |Z0|)` of every Poincaré point of every case of the sweep of `ls` kept in
/// `dir` (the output folder of `rubsim sweep` of the same scene and overrides; its `cases/`
/// store), component `c` (0: x, 1: y).
///
/// # Errors
/// [`Error::Study`] naming `dir`: no case store there, a store of another command, scene or
/// overrides, or cases missing; a damaged case file.
pub fn sweep_poincare(
    ls: &LoadedScene,
    model: &Model,
    dir: &Path,
    c: usize,
) -> Result<Vec<(f64, f64)>> {
    let at = |m: String| Error::study(dir.display(), m);
    let cases = dir.join("cases");
    if !cases.is_dir() {
        return Err(at(format!(
            "no sweep's case store ({} is not a folder): give the output folder of `rubsim sweep {}`",
            cases.display(),
            ls.file.display()
        )));
    }
    let store = CaseStore::read_only(&cases)?;
    let plan = store.plan();
    if plan.command != "sweep" || plan.scene_hash != scene_hash("sweep", &ls.scene) {
        return Err(at(format!(
            "its cases are of `rubsim {}` of {} (overrides {:?}), not of the sweep of {} with these overrides: run `rubsim sweep` of this scene there",
            plan.command,
            plan.scene_file,
            plan.overrides,
            ls.file.display()
        )));
    }
    let study = Study::of(ls, Some(model.rotor.natural_frequency()), Kind::Sweep)?;
    let results =
        merge::results(&[&store], &study, &[], Vec::new()).map_err(|e| at(e.to_string()))?;
    Ok(results
        .iter()
        .flat_map(|(r, _)| {
            r.poincare_nd
                .iter()
                .map(move |p| (r.speed_ratio, p[c.min(1)]))
        })
        .collect())
}
