//! `rubsim check` lists the files a run of the scene writes: the list must be the files the run
//! then writes, no more and no fewer (a single run, a plain sweep, a sweep varying a key, a speed
//! transient with stator stress and orbit snapshots; with and without pictures).

use crate::common;

use common::cli::{ok, tree};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The names on `check`'s `outputs:` line.
fn listed(args: &[&str]) -> BTreeSet<String> {
    let mut a = vec!["check"];
    a.extend_from_slice(args);
    let out = ok(&repo(), &a);
    let line = out
        .lines()
        .find_map(|l| l.strip_prefix("outputs: "))
        .unwrap_or_else(|| panic!("no `outputs:` line in\n{out}"));
    line.split(", ").map(str::to_string).collect()
}

/// The files the run wrote, relative to `out` (`cases/` stands for the case store).
fn written(out: &Path) -> BTreeSet<String> {
    tree(out)
        .into_iter()
        .filter(|p| !out.join(p).is_dir() || p.starts_with("cases"))
        .map(|p| p.to_string_lossy().into_owned())
        .map(|p| {
            if p.starts_with("cases") {
                "cases/".to_string()
            } else {
                p
            }
        })
        .filter(|p| !p.starts_with('.'))
        .collect()
}

fn same(command: &str, args: &[&str]) {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let mut a = vec![command];
    a.extend_from_slice(args);
    a.extend_from_slice(&["--out", out.to_str().unwrap()]);
    ok(&repo(), &a);
    let want = listed(args);
    let got = written(&out);
    assert_eq!(
        want, got,
        "`rubsim check {args:?}` lists {want:?}, `rubsim {command}` wrote {got:?}"
    );
}

#[test]
fn check_lists_the_files_of_a_single_run() {
    let short = [
        "--set",
        "run.revolutions=30",
        "--set",
        "run.transient_revolutions=20",
    ];
    for png in ["true", "false"] {
        let p = format!("output.png={png}");
        let mut a = vec!["tests/data/scenes/single.toml", "--set", &p];
        a.extend_from_slice(&short);
        same("run", &a);
    }
}

#[test]
fn check_lists_the_files_of_sweeps() {
    same("sweep", &["scenes/paper/partial_rub.toml"]);
    same(
        "sweep",
        &["scenes/paper/partial_rub.toml", "--set", "output.png=false"],
    );
    same(
        "sweep",
        &[
            "scenes/paper/sensitivity/fig14_friction.toml",
            "--set",
            "run.revolutions=30",
            "--set",
            "run.transient_revolutions=20",
        ],
    );
}

#[test]
fn check_lists_the_files_of_runs_with_stick() {
    // A sweep and a transient with stick draw `dry_whirl.png` too.
    same(
        "sweep",
        &[
            "scenes/stick/dry_whirl.toml",
            "--set",
            "run.sweep.from=1.0",
            "--set",
            "run.sweep.to=1.0",
        ],
    );
    same("run", &["scenes/stick/whirl_rundown.toml"]);
}

#[test]
fn check_lists_the_files_of_a_transient() {
    same("run", &["scenes/transients/paper_runup_coastdown.toml"]);
    same(
        "run",
        &[
            "scenes/transients/paper_runup_coastdown.toml",
            "--set",
            "output.png=false",
        ],
    );
}

/// `rubsim check` with the step chosen from `run.tolerance` states the choice once (it was
/// printed on stderr by the choice and again on stdout in the run's description).
#[test]
fn check_states_the_step_choice_once() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = tmp.path().join("paper.toml");
    std::fs::write(&scene, common::scenes::paper_single()).unwrap();
    let o = common::cli::rubsim(
        tmp.path(),
        &[
            "check",
            scene.to_str().unwrap(),
            "--set",
            "run.speed_ratio=2.0",
            "--set",
            "run.auto_step=true",
        ],
    );
    assert!(o.status.success());
    let all = common::cli::text(&o.stdout) + &common::cli::text(&o.stderr);
    assert_eq!(all.matches("step for run.tolerance = ").count(), 1, "{all}");
}

#[test]
fn check_lists_the_files_of_a_thermal_run_and_a_thermal_map() {
    same(
        "run",
        &[
            "scenes/thermal/newkirk_ring.toml",
            "--set",
            "thermal.duration=2",
        ],
    );
    same(
        "map",
        &[
            "scenes/thermal/newkirk_map.toml",
            "--set",
            "run.map.x.step=0.7",
            "--set",
            "run.map.y.values=[0.1]",
        ],
    );
    same(
        "map",
        &[
            "scenes/thermal/newkirk_map.toml",
            "--set",
            "run.map.y.values=[0.1]",
            "--set",
            "output.png=false",
        ],
    );
}
