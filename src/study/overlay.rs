//! A finished sweep's Poincaré points read back from its case store, to draw under the
//! branches of `rubsim continue --sweep DIR` (issue 29: the bifurcation diagram overlaid on the
//! sweep's Poincaré points), and the speeds its coexistence check flagged, whose responses
//! that command continues as branches of their own.

use super::store::{scene_hash, CaseStore};
use super::{merge, Kind, Study};
use crate::analysis::coexist_branches::Flagged;
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
    Ok(sweep_results(ls, model, dir)?
        .iter()
        .flat_map(|(r, _)| {
            r.poincare_nd
                .iter()
                .map(move |p| (r.speed_ratio, p[c.min(1)]))
        })
        .collect())
}

/// The speeds of the same sweep whose coexistence check flagged two responses, each with the
/// Poincaré sections of its responses shot as converged periodic orbits (`rubsim continue
/// --sweep DIR` continues them as branches: [`crate::analysis::coexist_branches`]).
///
/// # Errors
/// As [`sweep_poincare`].
pub fn sweep_flagged(ls: &LoadedScene, model: &Model, dir: &Path) -> Result<Vec<Flagged>> {
    Ok(sweep_results(ls, model, dir)?
        .iter()
        .filter_map(|(r, _)| {
            let c = r.coexistence.as_ref().filter(|c| c.coexisting)?;
            let sections = c.orbits.as_ref().map_or(Vec::new(), |o| {
                o.orbits
                    .iter()
                    .filter(|x| x.converged)
                    .map(|x| x.section_nd.clone())
                    .collect()
            });
            Some(Flagged {
                speed_ratio: r.speed_ratio,
                sections,
            })
        })
        .collect())
}

/// Every case of the sweep of `ls` kept in `dir` (checked as [`sweep_poincare`] says).
fn sweep_results(
    ls: &LoadedScene,
    model: &Model,
    dir: &Path,
) -> Result<Vec<(crate::analysis::SpeedResults, crate::plot::Boundary)>> {
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
    merge::results(&[&store], &study, &[], Vec::new()).map_err(|e| at(e.to_string()))
}
