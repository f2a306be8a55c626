//! A fixed window in one key (issue 25 item 5): `run.duration` integrates exactly that long
//! from the initial state and is never lengthened, its steady-state verdict a warning; `rubsim
//! check` states the steps a run plans and the most its lengthenings may take.

use crate::common;

use common::cli::{fails, json, ok, paper_light_damping};
use common::repo;
use std::path::Path;
use tempfile::TempDir;

const PAPER: &str = "scenes/paper/partial_rub.toml";
const ROSS: &str = "scenes/fe/ross_rub_example.toml";

/// `rubsim run` of the paper's case at ξ = 0.02 (a chaotic rub at ω/ω_n = 2.45: the 0–1 test
/// lengthens its window to 400 revolutions, `tests/suite/dynamics.rs`) with `sets`: summary.json and
/// stderr.
fn paper_run(dir: &Path, name: &str, sets: &[&str]) -> (serde_json::Value, String) {
    let sets: Vec<&str> = ["run.dt=2e-5"].iter().chain(sets).copied().collect();
    paper_light_damping(dir, name, "2.45", &sets)
}

fn u(v: &serde_json::Value) -> usize {
    v.as_u64().unwrap_or_else(|| panic!("not a count: {v}")) as usize
}

/// 0.5 s from rest at Δt = 2e-5 s asked (rounded down to 13 steps per recorded sample, 832 per
/// revolution of 15.4 ms): ⌈0.5/Δt⌉ = 27 057 steps, the last ending within one Δt past 0.5 s,
/// none more although the response is not periodic — the same 32 revolutions without
/// `run.duration` are lengthened to 400 for the 0–1 test. The analysed window is the last 16 of
/// the 32 whole revolutions, not steady, and said so as a warning in summary.json and on stderr.
/// The 2Δt companion covers the same window; the Δt/2 restart from the end is not run.
#[test]
fn half_a_second_from_rest_takes_its_steps_and_is_not_lengthened_when_not_periodic() {
    let tmp = TempDir::new().unwrap();
    let (s, err) = paper_run(tmp.path(), "fixed", &["run.duration=0.5"]);
    let r = &s["result"];
    let dt = r["plan"]["dt"].as_f64().unwrap();
    let steps = u(&r["plan"]["steps"]);
    let spr = u(&r["plan"]["steps_per_rev"]);
    assert_eq!(spr, 832, "{}", r["plan"]);
    assert!((dt - 2.0 * std::f64::consts::PI / (2.45 * 166.8) / 832.0).abs() < 2e-3 * dt);
    assert_eq!(steps, (0.5 / dt - 1e-9).ceil() as usize);
    assert_eq!(steps, 27_057, "Δt = {dt:e}");
    let end = steps as f64 * dt;
    assert!((0.5..0.5 + dt).contains(&end), "ends at {end}");
    assert_eq!(u(&r["stats"]["steps"]), steps, "the run took its plan only");
    let whole = steps / spr;
    assert_eq!(whole, 32);
    assert_eq!(u(&r["transient_revolutions"]), 16);
    assert_eq!(u(&r["window_revolutions"]), 16);
    assert_eq!(r["period"], 0, "not periodic: {}", r["classification"]);
    assert_eq!(r["steady"], false);
    let w = r["warnings"].as_array().unwrap();
    assert_eq!(w.len(), 1, "{w:?}");
    let w = w[0].as_str().unwrap();
    assert!(
        w.contains("run.duration") && w.contains("not lengthened"),
        "{w}"
    );
    assert!(
        err.contains("warning:") && err.contains("fixed window"),
        "{err}"
    );
    assert!(r["coexistence"].is_null(), "no coexistence companion");
    let e = &r["error"];
    let coarse = e["dt_coarse"].as_f64().unwrap();
    assert!(coarse > 1.5 * dt && coarse < 2.5 * dt, "{e}");
    assert!(e["dt_fine"].is_null(), "{e}");
    // The same length as revolutions, without the fixed window: lengthened for the 0–1 test.
    let (free, _) = paper_run(
        tmp.path(),
        "free",
        &["run.revolutions=32", "run.transient_revolutions=16"],
    );
    let f = &free["result"];
    assert_eq!(f["period"], 0);
    assert!(
        u(&f["window_revolutions"]) >= 384,
        "{}",
        f["window_revolutions"]
    );
    assert!(
        u(&f["stats"]["steps"]) > 10 * steps,
        "{}",
        f["stats"]["steps"]
    );
}

/// Keys that lengthen a run or set its length otherwise are refused beside `run.duration`, the
/// message naming both; a duration that is not a positive finite number is refused by its key.
/// A window of 1.5 revolutions analyses one whole revolution, too short to compare one
/// revolution with the next: the warning says so instead of "changes by inf" (the 10⁶-DOF
/// seal's 2-revolution run printed that).
#[test]
fn a_window_too_short_to_judge_says_so() {
    let tmp = TempDir::new().unwrap();
    let (s, err) = paper_run(tmp.path(), "short", &["run.duration=0.023"]);
    let r = &s["result"];
    assert_eq!(r["steady"], false);
    let w = r["warnings"][0].as_str().unwrap();
    assert!(w.contains("too short to compare"), "{w}");
    assert!(!w.contains("inf") && !err.contains(" inf "), "{w}");
}

#[test]
fn conflicting_keys_are_refused_naming_both() {
    let tmp = TempDir::new().unwrap();
    let scene = repo(PAPER);
    let scene = scene.to_str().unwrap();
    for other in [
        "run.classify_revolutions=0",
        "run.max_transient_revolutions=500",
    ] {
        let key = other.split('=').next().unwrap();
        let err = fails(
            tmp.path(),
            &["check", scene, "--set", "run.duration=0.5", "--set", other],
        );
        assert!(
            err.contains("`run.duration`") && err.contains(&format!("`{key}`")),
            "{err}"
        );
    }
    let runup = repo("scenes/transients/paper_runup.toml");
    let err = fails(
        tmp.path(),
        &[
            "check",
            runup.to_str().unwrap(),
            "--set",
            "run.duration=0.5",
        ],
    );
    assert!(
        err.contains("`run.speed_profile`") && err.contains("run.duration"),
        "{err}"
    );
    for bad in ["0", "-0.5", "nan"] {
        let err = fails(
            tmp.path(),
            &["check", scene, "--set", &format!("run.duration={bad}")],
        );
        assert!(err.contains("run.duration"), "{bad}: {err}");
    }
}

/// `rubsim check`'s line "steps at ω/ωn = …: P planned, at most M (…)": (P, M).
fn step_bounds(out: &str) -> (f64, f64) {
    let line = out
        .lines()
        .find(|l| l.contains(" planned, at most "))
        .unwrap_or_else(|| panic!("no step bounds in:\n{out}"));
    let after = line.split_once(": ").unwrap().1;
    let (p, rest) = after.split_once(" planned, at most ").unwrap();
    let m = rest.split_whitespace().next().unwrap();
    (p.parse().unwrap(), m.parse().unwrap())
}

/// The reproducer: ROSS's `run_rubbing` — "0.5 s from rest, this step" (Δt = 1e-4 s) —
/// on the ROSS rub example. As 10 revolutions (the scene's own way) `check` says 5 120 steps
/// planned and at most 400 revolutions' worth and more (the 0–1 test's lengthening and the
/// coexistence check); with `run.duration = 0.5` both figures are 5 120, and the run takes
/// exactly those: 512 steps a revolution of 50 ms (Δt rounded down to 9.765625e-5 s), ending
/// at 0.5 s.
#[test]
fn the_ross_like_half_second_is_planned_and_taken_as_stated() {
    let tmp = TempDir::new().unwrap();
    let scene = repo(ROSS);
    let scene = scene.to_str().unwrap();
    let free = ok(tmp.path(), &["check", scene, "--set", "run.dt=1e-4"]);
    let (p, m) = step_bounds(&free);
    assert_eq!(p, 5120.0, "{free}");
    assert!(
        m >= 400.0 * 512.0 && m >= 40.0 * p,
        "{p} planned, {m} most:\n{free}"
    );
    let sets = ["--set", "run.dt=1e-4", "--set", "run.duration=0.5"];
    let mut args = vec!["check", scene];
    args.extend(sets);
    let fixed = ok(tmp.path(), &args);
    assert_eq!(step_bounds(&fixed), (5120.0, 5120.0), "{fixed}");
    assert!(fixed.contains("never lengthened"), "{fixed}");
    let out = tmp.path().join("ross");
    let mut args = vec!["run", scene, "--out", out.to_str().unwrap()];
    args.extend(sets);
    args.extend(["--set", "output.png=false"]);
    ok(tmp.path(), &args);
    let r = &json(&out.join("summary.json"))["result"];
    assert_eq!(u(&r["plan"]["steps_per_rev"]), 512);
    let dt = r["plan"]["dt"].as_f64().unwrap();
    assert!((dt - 0.05 / 512.0).abs() < 1e-12 * dt, "{dt:e}");
    assert_eq!(u(&r["plan"]["steps"]), 5120);
    assert_eq!(u(&r["stats"]["steps"]), 5120);
    assert_eq!(u(&r["transient_revolutions"]), 5);
    assert_eq!(u(&r["window_revolutions"]), 5);
}
