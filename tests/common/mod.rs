//! Fixtures shared by the integration tests: where files are, the scenes (`scenes`), scene text
//! or file with `--set` overrides → model → one run, the command-line runner (`cli`), FE rotor
//! helpers (`fe`), structured meshes and the gmsh switch (`meshes`), complex numbers (`complex`), closed forms checked by several
//! files (`oracles`), and the readers of written results (`output`).
//!
//! Every test binary compiles this module (`mod common;`) and uses only part of it, hence the
//! `dead_code` allowance.
#![allow(dead_code)]

pub mod cli;
pub mod complex;
pub mod fe;
pub mod meshes;
pub mod oracles;
pub mod output;
pub mod scenes;

use rubsim::analysis::{self, Keep, RunSettings, SpeedResults};
use rubsim::model::{Case, Model};
use rubsim::scene::{self, LoadedScene};
use rubsim::time::{plan_steps, Scheme, StepPlan};
use std::path::{Path, PathBuf};

/// No `--set` overrides.
pub const NO_SETS: &[&str] = &[];

/// A path inside the repository.
pub fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

/// A small scene file shipped with the tests (`tests/data/scenes/`).
pub fn data(name: &str) -> PathBuf {
    repo("tests/data/scenes").join(name)
}

/// The text of a file; panics naming it.
pub fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn owned(sets: &[impl AsRef<str>]) -> Vec<String> {
    sets.iter().map(|s| s.as_ref().to_string()).collect()
}

/// Scene text with `--set` overrides (`key=value`); messages name it `t.toml`, relative paths
/// in it resolve from the working directory.
pub fn parse(text: &str, sets: &[impl AsRef<str>]) -> LoadedScene {
    scene::parse(Path::new("t.toml"), text, &owned(sets)).expect("scene")
}

/// A scene file with `--set` overrides.
pub fn load(path: &Path, sets: &[impl AsRef<str>]) -> LoadedScene {
    scene::load(path, &owned(sets)).expect("scene")
}

/// The model of a loaded scene.
pub fn build(ls: &LoadedScene) -> Model {
    Model::from_scene(ls).expect("model")
}

/// The model of a scene text as written.
pub fn model(text: &str) -> Model {
    build(&parse(text, NO_SETS))
}

/// Scene text with overrides and its model.
pub fn scene_model(text: &str, sets: &[impl AsRef<str>]) -> (LoadedScene, Model) {
    let ls = parse(text, sets);
    let m = build(&ls);
    (ls, m)
}

/// Scene file with overrides and its model.
pub fn file_model(path: &Path, sets: &[impl AsRef<str>]) -> (LoadedScene, Model) {
    let ls = load(path, sets);
    let m = build(&ls);
    (ls, m)
}

/// Run settings of a scene's `[run]` and `output.component`.
pub fn settings(ls: &LoadedScene) -> RunSettings {
    RunSettings::from_scene(&ls.scene)
}

/// One speed ω/ω_n = `nu` of a scene text with overrides, through the analysis layer (nothing
/// written).
pub fn run_speed(text: &str, sets: &[impl AsRef<str>], nu: f64) -> SpeedResults {
    let (ls, m) = scene_model(text, sets);
    analysis::run_speed(&m, &settings(&ls).request(nu), Keep::default()).expect("run")
}

/// Overrides for a shorter steady run: 80 revolutions, the first 40 cut, no 2Δt companion run.
pub const SHORT_RUN: [&str; 3] = [
    "run.revolutions=80",
    "run.transient_revolutions=40",
    "run.error_estimate=false",
];

/// The case at ω/ω_n = `nu` and its step plan with the scene's step settings and integrator
/// `kind`.
pub fn case_and_plan(ls: &LoadedScene, model: &Model, nu: f64, kind: Scheme) -> (Case, StepPlan) {
    let case = model.case(nu * model.rotor.natural_frequency()).unwrap();
    let mut st = settings(ls).step;
    st.integrator = kind;
    let plan = plan_steps(&case, &st).unwrap();
    (case, plan)
}

/// Largest distance from each multiplier `[Re, Im]` of `found` to the nearest of `expected`,
/// and back (the Hausdorff distance of the two sets in the complex plane).
pub fn set_distance(found: &[[f64; 2]], expected: &[[f64; 2]]) -> f64 {
    let near = |p: &[f64; 2], set: &[[f64; 2]]| {
        set.iter()
            .map(|q| (p[0] - q[0]).hypot(p[1] - q[1]))
            .fold(f64::INFINITY, f64::min)
    };
    let a = found.iter().map(|p| near(p, expected)).fold(0.0, f64::max);
    let b = expected.iter().map(|p| near(p, found)).fold(0.0, f64::max);
    a.max(b)
}
