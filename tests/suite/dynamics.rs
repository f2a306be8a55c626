//! Quasi-periodic, chaotic or undetermined (issue 11 item 3): the class of a response that is
//! not periodic, told by the 0–1 test on its Poincaré section (`analysis::dynamics`), end to
//! end from the command line on the paper's Jeffcott rub case at light damping, and confirmed
//! by independent indicators — the divergence of two runs from nearby initial states (the
//! largest Lyapunov exponent) and the class at half the step.

use crate::common;

use common::cli::{json, ok, paper_light_damping};
use common::repo;
use std::path::Path;
use tempfile::TempDir;

/// `rubsim run` of the paper case at `speed` with `sets`; returns summary.json.
fn run(dir: &Path, name: &str, speed: &str, sets: &[&str]) -> serde_json::Value {
    paper_light_damping(dir, name, speed, sets).0
}

fn section(s: &serde_json::Value) -> Vec<[f64; 2]> {
    s["result"]["poincare_nd"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| [p[0].as_f64().unwrap(), p[1].as_f64().unwrap()])
        .collect()
}

/// ξ = 0.02, ω/ω_n = 2.45: the window is lengthened to `run.classify_revolutions` (400) and
/// reads chaotic with K > 0.95, at the paper's Δt and at Δt/2 (`run.harmonics = 8`). Two runs
/// whose initial displacements differ by 1e-15 m diverge on the Poincaré section
/// exponentially, by more than 1e8 within 80 revolutions (a largest Lyapunov exponent above
/// 0.2 per revolution), to the size of the orbit.
#[test]
fn a_light_damping_rub_is_chaotic_at_two_steps_and_nearby_states_diverge() {
    let tmp = TempDir::new().unwrap();
    let mut ks = Vec::new();
    for (name, sets) in [("h4", vec![]), ("h8", vec!["run.harmonics=8"])] {
        let s = run(tmp.path(), name, "2.45", &sets);
        let d = &s["result"]["dynamics"];
        assert_eq!(s["dynamics"], "chaotic", "{name}: {d}");
        assert_eq!(s["regime"], "chaotic");
        assert_eq!(s["result"]["period"], 0);
        assert!(s["result"]["window_revolutions"].as_u64().unwrap() >= 400);
        let k = d["zero_one_k"].as_f64().unwrap();
        assert!(k > 0.95, "{name}: K {k}");
        ks.push(k);
    }
    eprintln!("K at Δt, Δt/2: {ks:?}");
    // Nearby initial states, no transient cut: the section from the first revolution.
    let short = [
        "run.transient_revolutions=1",
        "run.max_transient_revolutions=1",
        "run.revolutions=200",
        "run.error_estimate=false",
    ];
    let a = run(
        tmp.path(),
        "la",
        "2.45",
        &[&short[..], &["run.initial_displacement=[1e-6, 0.0]"]].concat(),
    );
    let b = run(
        tmp.path(),
        "lb",
        "2.45",
        &[
            &short[..],
            &["run.initial_displacement=[1.000000001e-6, 0.0]"],
        ]
        .concat(),
    );
    let (pa, pb) = (section(&a), section(&b));
    let d: Vec<f64> = pa
        .iter()
        .zip(&pb)
        .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
        .collect();
    let (d10, d80) = (d[10], d[80]);
    let lambda = (d80 / d10).ln() / 70.0;
    let late = d[100..].iter().fold(0.0_f64, |m, v| m.max(*v));
    eprintln!(
        "separation: rev 10 {d10:.2e}, rev 80 {d80:.2e}, λ ≈ {lambda:.3}/rev, later max {late:.2}"
    );
    assert!(d10 < 1e-9, "{d10}");
    assert!(d80 / d10 > 1e8, "{d10} → {d80}");
    assert!(lambda > 0.2, "{lambda}");
    assert!(
        late > 0.5,
        "the separation saturates at the orbit's size: {late}"
    );
}

/// ξ = 0.02, ω/ω_n = 3.6: not periodic within 8 revolutions, K ≈ 0 — but the Poincaré points
/// repeat after 9: it reads periodic with `long_period` 9 (its whirl line is 4/9×), not
/// quasi-periodic. A periodic run is not lengthened (its window stays 120 revolutions), and
/// `run.classify_revolutions = 0` leaves a chaotic run's 120-revolution window `undetermined`.
#[test]
fn a_long_period_is_periodic_and_short_windows_are_undetermined() {
    let tmp = TempDir::new().unwrap();
    let s = run(tmp.path(), "p9", "3.6", &["run.error_estimate=false"]);
    assert_eq!(s["dynamics"], "periodic");
    assert_eq!(s["regime"], "1/9×");
    assert_eq!(s["result"]["period"], 0);
    assert_eq!(s["result"]["dynamics"]["long_period"], 9);
    let w = s["result"]["whirl"]["dominant_order"].as_f64().unwrap();
    assert!((w.abs() - 4.0 / 9.0).abs() < 1e-6, "{w}");
    let p = run(tmp.path(), "p1", "1.7", &["run.error_estimate=false"]);
    assert_eq!(p["regime"], "1×");
    assert_eq!(p["result"]["window_revolutions"], 120);
    assert!(p["result"]["dynamics"]["zero_one_k"].is_null());
    let u = run(
        tmp.path(),
        "u",
        "2.45",
        &["run.error_estimate=false", "run.classify_revolutions=0"],
    );
    assert_eq!(u["dynamics"], "undetermined");
    assert_eq!(u["regime"], "not periodic (undetermined)");
    assert!(u["result"]["window_revolutions"].as_u64().unwrap() < 200);
}

/// The paper's rotor without damping and out of reach of its stator (`clearance_nd = 50`) at
/// ω/ω_n = √2, started 1e-4 m off centre: the 1× unbalance response plus the free whirl at
/// ω_n, a line at 1/√2 of the speed — two incommensurate frequencies, a 2-torus whose section
/// is a closed curve. It reads quasi-periodic with K < 0.05 at Δt and at Δt/2, its dominant
/// whirl line at 0.7071× (the free whirl) and its 1× line |Z0|. It is steady: the statistics
/// of its two halves agree within their sampling (`stationarity.attractor`), although the
/// thirds of a finite sample of the closed curve differ by 0.9 % of its size point by point.
#[test]
fn an_undamped_free_whirl_on_the_unbalance_response_is_quasi_periodic() {
    let tmp = TempDir::new().unwrap();
    for (name, h) in [("q4", "run.harmonics=4"), ("q8", "run.harmonics=8")] {
        let s = run(
            tmp.path(),
            name,
            "1.41421356",
            &[
                "rotor.damping_ratio=0",
                "stator.0.clearance_nd=50",
                "run.initial_displacement=[1e-4, 0.0]",
                "run.error_estimate=false",
                h,
            ],
        );
        let r = &s["result"];
        assert_eq!(s["dynamics"], "quasi-periodic", "{name}: {}", r["dynamics"]);
        assert_eq!(s["regime"], "quasi-periodic");
        let k = r["dynamics"]["zero_one_k"].as_f64().unwrap();
        assert!(k.abs() < 0.05, "{name}: K {k}");
        let w = r["whirl"]["dominant_order"].as_f64().unwrap();
        assert!((w - 0.5f64.sqrt()).abs() < 2e-3, "{name}: {w}");
        let a1 = r["amp_1x_nd"].as_f64().unwrap();
        assert!((a1 - 1.0).abs() < 1e-2, "{name}: {a1}");
        assert_eq!(r["steady"], true, "{name}: {}", r["stationarity"]);
        let at = &r["stationarity"]["attractor"];
        assert!(at["mean_change"].as_f64().unwrap() < 1e-3, "{name}: {at}");
        eprintln!("{name}: K {k:.4}, whirl {w:.4}×, 1× {a1:.4}, halves {at}");
    }
}

/// `rubsim map` at ξ = 0.02 over ω/ω_n 2.3, 2.4 and δ_nd 0.5, 0.6: the chaotic cells are their
/// own class in `map.csv` (`regime`, with `zero_one_k` > 0.8) and in `summary.json`
/// `regime_cells`, beside the 1/3× ones, and `regime_map.png` is drawn.
#[test]
fn the_regime_map_has_a_chaotic_class() {
    let tmp = TempDir::new().unwrap();
    let scene = repo("scenes/paper/regime_map.toml");
    let out = tmp.path().join("map");
    ok(
        tmp.path(),
        &[
            "map",
            scene.to_str().unwrap(),
            "--set",
            "rotor.damping_ratio=0.02",
            "--set",
            "run.map.x.from=2.3",
            "--set",
            "run.map.x.to=2.4",
            "--set",
            "run.map.y.from=0.5",
            "--set",
            "run.map.y.to=0.6",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let text = common::read(&out.join("map.csv"));
    let mut lines = text.lines();
    let cols: Vec<&str> = lines.next().unwrap().split(',').collect();
    let at = |name: &str| cols.iter().position(|c| *c == name).unwrap();
    assert_eq!(
        cols[cols.len() - 4..],
        ["zero_one_k", "long_period", "stick_fraction", "dry_rub"]
    );
    let mut seen = Vec::new();
    for l in lines {
        let row: Vec<&str> = l.split(',').collect();
        let (speed, regime, k) = (
            row[at("speed_ratio")],
            row[at("regime")],
            row[at("zero_one_k")],
        );
        match speed {
            "2.3" => assert_eq!((regime, k), ("1/3×", "")),
            "2.4" => {
                assert_eq!(regime, "chaotic");
                assert!(k.parse::<f64>().unwrap() > 0.8, "{k}");
            }
            s => panic!("speed {s}"),
        }
        seen.push(regime.to_string());
    }
    assert_eq!(seen.len(), 4);
    let s = json(&out.join("summary.json"));
    assert_eq!(s["map"]["regime_cells"]["chaotic"], 2, "{}", s["map"]);
    assert!(out.join("regime_map.png").is_file());
}

/// An absurd `run.classify_revolutions` is refused before anything runs, naming the key.
#[test]
fn an_absurd_classify_budget_is_refused() {
    let tmp = TempDir::new().unwrap();
    let scene = repo("scenes/paper/partial_rub.toml");
    let err = common::cli::fails(
        tmp.path(),
        &[
            "run",
            scene.to_str().unwrap(),
            "--speed",
            "2.45",
            "--set",
            "run.classify_revolutions=1000000000",
            "--out",
            tmp.path().join("x").to_str().unwrap(),
        ],
    );
    assert!(err.contains("run.classify_revolutions"), "{err}");
    assert!(!tmp.path().join("x").join("summary.json").exists());
}

/// The chaotic map cell ν 2.4, δ_nd 0.5, ξ 0.02 of `scenes/paper/regime_map.toml` (its
/// `output.component = "y"`): its 0–1 test's `K` at the default 400 revolutions depends on
/// round-off (0.87 with `sincos` at every step, 0.68 with the unbalance load read from a
/// per-revolution table), so a window whose `K` falls between the thresholds is lengthened,
/// doubling up to 4 × `run.classify_revolutions`: the cell reads chaotic with `K` above 0.8
/// either way. The lengthening is bounded: with `run.classify_revolutions = 150` the window
/// stays within 600 revolutions.
#[test]
fn the_chaotic_map_cell_reads_chaotic_whatever_the_round_off() {
    let tmp = TempDir::new().unwrap();
    let cell = [
        "stator.0.clearance_nd=0.5",
        "output.component=\"y\"",
        "run.error_estimate=false",
    ];
    let s = run(tmp.path(), "cell", "2.4", &cell);
    let d = &s["result"]["dynamics"];
    assert_eq!(s["dynamics"], "chaotic", "{d}");
    let k = d["zero_one_k"].as_f64().unwrap();
    assert!(k > 0.8, "K {k}");
    let w = s["result"]["window_revolutions"].as_u64().unwrap();
    assert!((400..=1600).contains(&w), "{w} revolutions");
    let short = run(
        tmp.path(),
        "short",
        "2.4",
        &[&cell[..], &["run.classify_revolutions=150"]].concat(),
    );
    let w = short["result"]["window_revolutions"].as_u64().unwrap();
    assert!(w <= 601, "{w} revolutions");
    eprintln!(
        "K {k:.3} over {} revolutions; classify 150: {} over {w}",
        s["result"]["window_revolutions"], short["result"]["dynamics"]
    );
}
