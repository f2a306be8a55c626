//! Full spectra of x + iy: forward and backward whirl as positive and negative frequencies —
//! a free rotor's forward circle, dry whip's backward whirl at the frequency of
//! docs/ORACLES.md, and the files of `rubsim run` and of a transient.

use crate::common;

use common::cli::{is_png, json, ok};
use common::scenes::{unit_rotor, unit_rotor_in_ring};
use common::{read, repo, scene_model, settings, NO_SETS};
use rubsim::analysis::whirl::WhirlDirection;
use rubsim::analysis::RunSettings;
use rubsim::analysis::{self, Keep};
use rubsim::model::Model;
use rubsim::time::Initial;

#[test]
fn a_free_rotor_whirls_forward_on_a_circle() {
    // No stator: the unbalance response is a forward circle of radius |Z0| — 1× forward 1,
    // backward 0.
    let (ls, model) = scene_model(&unit_rotor(0.2, ""), NO_SETS);
    for nu in [0.5, 2.0] {
        let r = analysis::run_speed(&model, &settings(&ls).request(nu), Keep::default()).unwrap();
        let w = &r.whirl;
        assert!((w.forward_1x_nd - 1.0).abs() < 2e-3, "ν = {nu}: {w:?}");
        assert!(w.backward_1x_nd < 1e-6, "ν = {nu}: {w:?}");
        assert_eq!(w.direction, WhirlDirection::Forward);
        assert!((w.dominant_order - 1.0).abs() < 1e-12, "{w:?}");
    }
}

/// docs/ORACLES.md, dry whip (ring on springs, κ = 25, ξ = 0.2, μ = 0.1, δ = 1 mm): the unit
/// rotor over `revolutions` at no unbalance, started on the backward whirl orbit R = 3.1034 δ,
/// which turns at ω_w = ξ/μ + √(1 + (ξ/μ)²) = 4.23607 ω_n against the spin, with no transient
/// growth. Returns the model, its settings, ω_w (/ω_n) and R (m).
fn dry_whip(revolutions: usize) -> (Model, RunSettings, f64, f64) {
    let delta = 1e-3;
    let (ls, model) = scene_model(&unit_rotor_in_ring(0.1, delta, revolutions), NO_SETS);
    let ww = 0.2 / 0.1 + (1.0 + 2.0_f64 * 2.0).sqrt();
    let r0 = 3.1034 * delta;
    let mut s = settings(&ls);
    s.initial = Initial {
        u: [r0, 0.0],
        v: [0.0, -ww * r0],
    };
    s.max_transient_revolutions = 0;
    (model, s, ww, r0)
}

#[test]
fn dry_whip_reads_backward_at_the_oracle_whirl_frequency() {
    // docs/ORACLES.md (ring on springs, κ = 25, ξ = 0.2, μ = 0.1): the backward whirl orbit at
    // R = 3.1034 δ turns at ω_w = ξ/μ + √(1 + (ξ/μ)²) = 4.23607 ω_n against the spin. Started
    // on it at Ω = 2 ω_n (no unbalance), the rub keeps the rotor whirling backward at −2.1180 Ω
    // — far from any harmonic of Ω, so the line falls between bins and is located by the
    // three-bin interpolation.
    let (model, mut s, ww, r0) = dry_whip(24);
    // The whirl is not periodic on the once-per-revolution section; lengthened for the 0-1 test
    // the run leaves this orbit and runs away (the divergence guard stops it at t ≈ 398 s), so
    // the window read here is the plan's, on the orbit.
    s.classify_revolutions = 0;
    let r = analysis::run_speed(&model, &s.request(2.0), Keep::default()).unwrap();
    let w = &r.whirl;
    assert_eq!(w.direction, WhirlDirection::Backward, "{w:?}");
    let expected = -ww / 2.0;
    assert!(
        (w.dominant_order / expected - 1.0).abs() < 1e-3,
        "dominant {:.5}× against {expected:.5}×",
        w.dominant_order
    );
    // Its radius: without unbalance |Z0| = 0 and the analysis reads metres; 3.1034 δ.
    assert!(
        (w.dominant_nd / r0 - 1.0).abs() < 1e-2,
        "radius {:.4e} m against {r0:.4e} m",
        w.dominant_nd
    );
    // No unbalance: no synchronous line worth the name.
    assert!(w.forward_1x_nd < 0.05 * w.dominant_nd, "{w:?}");
}

#[test]
fn dry_whip_lengthened_for_the_zero_one_test_runs_away_and_keeps_its_window() {
    // The scene of `dry_whip_reads_backward_at_the_oracle_whirl_frequency` without
    // `classify_revolutions = 0`: its window (24 revolutions, not periodic) is lengthened to 400
    // for the 0–1 test, and the continued run leaves the backward whirl orbit and grows until
    // the divergence guard stops it (dry whip building up). The run still gives the window's
    // result — the very numbers of the run that was not lengthened — classified `diverging`,
    // not steady, with the time the continuation ran away.
    let (model, s, ww, _) = dry_whip(24);
    assert!(s.classify_revolutions >= 200, "{}", s.classify_revolutions);
    let r = analysis::run_speed(&model, &s.request(2.0), Keep::default())
        .unwrap_or_else(|e| panic!("the lengthening's runaway must not fail the run: {e}"));
    assert_eq!(
        r.dynamics.regime,
        analysis::Regime::Diverging,
        "{:?}",
        r.dynamics
    );
    assert_eq!(analysis::regime_label(&r), "diverging");
    assert!(!r.steady);
    assert_eq!(r.period, 0);
    let t_window = r.plan.steps as f64 * r.plan.dt;
    let t = r.dynamics.runaway_at_s.expect("runaway time");
    let rev = 2.0 * std::f64::consts::PI / r.omega;
    assert!(t > t_window && t < 400.0 * rev, "ran away at {t} s");
    assert_eq!(r.window_revolutions, 24);
    let mut kept = s;
    kept.classify_revolutions = 0;
    let k = analysis::run_speed(&model, &kept.request(2.0), Keep::default()).unwrap();
    assert_eq!(k.dynamics.regime, analysis::Regime::Undetermined);
    assert_eq!(k.dynamics.runaway_at_s, None);
    assert_eq!(r.extents_nd, k.extents_nd);
    assert_eq!(r.whirl.dominant_order, k.whirl.dominant_order);
    assert!((r.whirl.dominant_order / (-ww / 2.0) - 1.0).abs() < 1e-3);
    // A run that diverges inside its own window still stops with the divergence error: 200
    // planned revolutions (628 s) hold the runaway.
    let (model, long, ..) = dry_whip(200);
    match analysis::run_speed(&model, &long.request(2.0), Keep::default()) {
        Err(e) => assert!(e.to_string().contains("response diverged"), "{e}"),
        Ok(r) => panic!("ran through: {:?}", r.dynamics),
    }
}

#[test]
fn a_free_run_up_whirls_forward_through_its_resonance() {
    // The paper's rotor without the rod, 0.5 → 3 ω_n in 20 s: every window of whole
    // revolutions reads a forward circle (backward 1× under 1 % of it), whose radius peaks at the
    // resonance ν = 1/√(1 − 2ξ²) = 1.0426 (ξ = 0.2; a little later on a run-up).
    let mut text = common::scenes::PAPER.replace(
        "[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1",
        "[run.speed_profile]\nkind = \"ramp\"\nunit = \"speed_ratio\"\nfrom = 0.5\nto = 3.0\nduration = 20.0",
    );
    let (a, b) = (
        text.find("[[stator]]").unwrap(),
        text.find("[run]").unwrap(),
    );
    text = format!("{}{}", &text[..a], &text[b..]);
    let (ls, model) = scene_model(&text, NO_SETS);
    let spec = ls.scene.run.speed_profile.as_ref().unwrap();
    let prep = analysis::prepare_transient(&model, &settings(&ls), spec).unwrap();
    let r = prep.run(&mut []).unwrap();
    let wf = analysis::waterfall::full_waterfall(&r, prep.window_revolutions);
    assert!(wf.len() > 100, "{} windows", wf.len());
    // After the start's free vibration at ω_n has died out (ξ = 0.2: a few revolutions).
    let late: Vec<_> = wf.iter().filter(|w| w.t > 3.0).collect();
    assert!(late.len() > 100);
    for w in late {
        assert!(w.backward_1x < 1e-2 * w.forward_1x, "{w:?}");
        assert!((w.lines[0].0 - 1.0).abs() < 5e-3, "{w:?}");
    }
    let peak = wf.iter().fold(
        &wf[0],
        |m, w| if w.forward_1x > m.forward_1x { w } else { m },
    );
    let nu = peak.omega / r.omega_n;
    assert!((nu - 1.0426).abs() < 0.03, "peak at ν = {nu}");
}

#[test]
fn run_and_transient_write_their_full_spectra() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    let scene = repo("scenes/paper/partial_rub.toml");
    let o = out.display().to_string();
    let text = ok(
        tmp.path(),
        &[
            "run",
            scene.to_str().unwrap(),
            "--speed",
            "1.7",
            "--out",
            &o,
        ],
    );
    assert!(text.contains("whirl forward (+1.000×"), "{text}");
    let csv = read(&out.join("full_spectrum.csv"));
    assert!(csv.starts_with("order,freq_nd,amp_nd\n"));
    // Signed and ascending, within ±1.5 × 1.7 ω_n; the 1× lines on their bins.
    let rows: Vec<[f64; 3]> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect();
    assert!(rows.windows(2).all(|w| w[1][0] > w[0][0]));
    assert!(rows[0][1] < -2.5 && rows[rows.len() - 1][1] > 2.5);
    let sum = json(&out.join("summary.json"));
    let w = &sum["result"]["whirl"];
    let at = |order: f64| {
        rows.iter()
            .find(|r| (r[0] - order).abs() < 1e-9)
            .map(|r| r[2])
            .unwrap()
    };
    let (f, b) = (
        w["forward_1x_nd"].as_f64().unwrap(),
        w["backward_1x_nd"].as_f64().unwrap(),
    );
    assert!((at(1.0) / f - 1.0).abs() < 1e-5 && (at(-1.0) / b - 1.0).abs() < 1e-5);
    assert_eq!(w["direction"], "forward");
    assert!(is_png(&out.join("full_spectrum.png")));
    // A short run-up with rub: the waterfall's table and picture.
    let tr = tmp.path().join("tr");
    let runup = repo("scenes/transients/paper_runup.toml");
    ok(
        tmp.path(),
        &[
            "run",
            runup.to_str().unwrap(),
            "--set",
            "run.speed_profile.duration=2.0",
            "--out",
            tr.to_str().unwrap(),
        ],
    );
    let csv = read(&tr.join("full_waterfall.csv"));
    assert!(csv.starts_with("t_s,omega_rad_s,speed_ratio,fwd_1x_m,bwd_1x_m,rank,order,"));
    let sum = json(&tr.join("summary.json"));
    let n = sum["full_waterfall"]["windows"].as_u64().unwrap();
    assert!(n > 20, "{n} windows");
    assert_eq!(csv.lines().filter(|l| l.contains(",1,")).count() as u64, n);
    assert!(is_png(&tr.join("full_waterfall.png")));
}
