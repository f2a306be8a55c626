//! `[[run.event]]`: a sudden unbalance (blade-off) against the Jeffcott rotor's closed-form
//! steady response, a clearance that closes in, and the errors of bad events.

use crate::common;

use common::scenes::PAPER;
use common::{scene_model, settings};
use num_complex::Complex64;
use rubsim::analysis::{prepare_transient, TransientResults};
use std::f64::consts::PI;

/// The paper's rotor and rod at a constant `nu` ω_n for `duration` s with `events` appended;
/// `rod = false`: no stator.
fn scene(nu: f64, duration: f64, events: &str, rod: bool) -> String {
    let mut t = PAPER.replace(
        "[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1",
        &format!("[run.speed_profile]\nkind = \"constant\"\nunit = \"speed_ratio\"\nspeed = {nu}\nduration = {duration}\nreference = 1.0\n\n{events}"),
    );
    if !rod {
        let a = t.find("[[stator]]").unwrap();
        let b = t.find("[run]").unwrap();
        t = format!("{}{}", &t[..a], &t[b..]);
    }
    t
}

fn run(text: &str, sets: &[&str]) -> TransientResults {
    let (ls, model) = scene_model(text, sets);
    let s = settings(&ls);
    prepare_transient(&model, &s, ls.scene.run.speed_profile.as_ref().unwrap())
        .unwrap()
        .with_events(&ls.scene.run.event)
        .unwrap()
        .run(&mut [])
        .unwrap()
}

/// The Jeffcott rotor's steady response to the unbalance `u` (kg·m, complex) at ν:
/// `z = (u/m) ν² / (1 − ν² + 2iξν) e^{iΩt}`.
fn steady(u: Complex64, nu: f64) -> Complex64 {
    let m = 7800.0 * PI * 0.12 * 0.12 / 4.0 * 0.03;
    u / m * nu * nu / Complex64::new(1.0 - nu * nu, 0.4 * nu)
}

/// Largest |z − z_cf| over the samples with `from ≤ t < to`, relative to |z_cf|.
fn off(r: &TransientResults, u: Complex64, from: f64, to: f64) -> f64 {
    let nu = r.spin[0][1] / r.omega_n;
    let z = steady(u, nu);
    let mut worst: f64 = 0.0;
    for (s, x) in r
        .spin
        .iter()
        .zip(&r.response)
        .filter(|(s, _)| s[0] >= from && s[0] < to)
    {
        let cf = z * Complex64::from_polar(1.0, s[2]);
        worst = worst.max(Complex64::new(x[0] - cf.re, x[1] - cf.im).norm() / z.norm());
    }
    worst
}

#[test]
fn blade_off_converges_to_the_steady_response_of_the_new_unbalance() {
    // At 1.5 ω_n, a blade of 20 g at 45 mm and 120° leaves at t₀ = 0.5 s (a step; and a 5 ms
    // ramp): the response goes from the steady response of the original unbalance
    // (8 g × 45 mm at 0°) to that of the sum, within the decay e^{−ξ ω_n t} of the free whirl.
    let u0 = Complex64::new(0.008 * 0.045, 0.0);
    let u1 = u0 + Complex64::from_polar(0.02 * 0.045, 120f64.to_radians());
    for duration in [0.0, 0.005] {
        let ev = format!("[[run.event]]\nkind = \"unbalance\"\ntime = 0.5\nduration = {duration}\nmass = 0.02\nradius = 0.045\nphase_deg = 120.0\n");
        let r = run(&scene(1.5, 1.0, &ev, false), &["run.samples_per_rev=100"]);
        let before = off(&r, u0, 0.4, 0.5);
        let after = off(&r, u1, 0.9, 1.01);
        let just = off(&r, u1, 0.51, 0.52);
        eprintln!("blade-off (ramp {duration} s): before {before:.2e}, just after {just:.2e}, 0.4 s after {after:.2e} of the steady response");
        // The level left is the scheme's own phase error at the plan's Δt, the same before
        // and after.
        assert!(before < 1e-3, "before the event: {before}");
        assert!(just > 0.05, "the event must disturb the orbit: {just}");
        assert!(after < 1e-3, "after the event: {after}");
        // … which falls as Δt²: a quarter of the step, a sixteenth of the error.
        let dt = format!("run.dt={:e}", r.plan.dt / 4.0);
        let fine = run(
            &scene(1.5, 1.0, &ev, false),
            &[dt.as_str(), "run.samples_per_rev=100"],
        );
        let after_fine = off(&fine, u1, 0.9, 1.01);
        eprintln!("  at Δt/4: {after_fine:.2e}");
        assert!(after_fine < after / 10.0, "{after_fine} vs {after}");
    }
}

#[test]
fn a_clearance_that_closes_in_starts_the_rub() {
    // The rod at δ = 0.6|Z0(ω_n)| does not touch the free orbit at 2 ω_n (|Z0(2ω_n)| =
    // 0.99 e < δ = 1.5 e); closed to 0.5 e over 0.05 s from t₀ = 0.3 s it rubs.
    let e = 0.008 * 0.045 / (7800.0 * PI * 0.12 * 0.12 / 4.0 * 0.03);
    let ev = format!("[[run.event]]\nkind = \"clearance\"\nstator = \"rod\"\ntime = 0.3\nduration = 0.05\nclearance = {:e}\n", 0.5 * e);
    let r = run(&scene(2.0, 0.6, &ev, true), &["run.samples_per_rev=100"]);
    // The start from rest overshoots onto the rod; after 0.15 s the free orbit is steady.
    let first = r
        .spin
        .iter()
        .zip(&r.contact)
        .find(|(s, c)| s[0] > 0.15 && c[0] > 0.0)
        .map(|(s, _)| s[0]);
    eprintln!(
        "clearance event: first contact at {first:?} s, max |F| {:.3e} N",
        r.contact_force_max
    );
    let first = first.expect("the rod must be touched");
    assert!(first > 0.3 && first < 0.36, "first contact at {first} s");
    assert!(r.contact_force_max > 1.0);
    // Without the event the run never rubs.
    let r = run(&scene(2.0, 0.6, "", true), &["run.samples_per_rev=100"]);
    assert!(r
        .spin
        .iter()
        .zip(&r.contact)
        .all(|(s, c)| s[0] < 0.15 || c[0] == 0.0));
}

fn load_error(text: &str) -> String {
    rubsim::scene::parse(std::path::Path::new("t.toml"), text, &[])
        .expect_err("a bad event loads")
        .to_string()
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.starts_with(needle)).unwrap() + 1
}

#[test]
fn bad_events_name_the_key_and_line() {
    let ub = "[[run.event]]\nkind = \"unbalance\"\nmass = 0.01\nradius = 0.05\n";
    let cases: &[(String, &str, &str, &str)] = &[
        (format!("{ub}time = 2.0"), "run.event.0.time", "ends after the run", "time = 2.0"),
        (format!("{ub}time = 0.5\nduration = 0.6"), "run.event.0.time", "ends after the run", "time = 0.5"),
        (format!("{ub}time = -0.1"), "run.event.0.time", "finite time ≥ 0", "time = -0.1"),
        (format!("{ub}time = nan"), "run.event.0.time", "finite time ≥ 0", "time = nan"),
        (format!("{ub}time = 0.1\nnode = 3"), "run.event.0.node", "does not exist", "node = 3"),
        (format!("{ub}time = 0.1\nstator = \"rod\""), "run.event.0.stator", "does not apply", "stator = "),
        (
            "[[run.event]]\nkind = \"clearance\"\ntime = 0.1\nstator = \"seal\"\nclearance = 1e-4".into(),
            "run.event.0.stator",
            "no stator is named `seal`: the scene's stators (`stator`) are `rod`",
            "stator = ",
        ),
        (
            "[[run.event]]\nkind = \"clearance\"\ntime = 0.1\nstator = \"rod\"\nclearance = -1e-4".into(),
            "run.event.0.clearance",
            "positive",
            "clearance = -1e-4",
        ),
        (
            format!("{ub}time = 0.1\n\n[[run.event]]\nkind = \"unbalance\"\ntime = 0.2\nmass = 0.0\nradius = 0.05"),
            "run.event.1.mass",
            "positive",
            "mass = 0.0",
        ),
    ];
    for (events, key, what, line) in cases {
        let text = scene(1.0, 1.0, events, true);
        let e = load_error(&text);
        let n = text
            .lines()
            .enumerate()
            .filter(|(_, l)| l.starts_with(line))
            .last()
            .unwrap()
            .0
            + 1;
        let at = format!("t.toml:{n}: key `{key}`");
        assert!(
            e.contains(&at) && e.contains(what),
            "expected `{at}` … `{what}`, got: {e}"
        );
    }
    // Events belong to a transient run.
    let text = PAPER.replace(
        "[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1",
        &format!("speed_ratio = 1.0\n{ub}time = 0.1"),
    );
    let e = load_error(&text);
    assert!(
        e.contains("run.event") && e.contains("[run.speed_profile]"),
        "{e}"
    );
    let _ = line_of;
}

#[test]
fn cli_driven_blade_off_writes_the_torques_and_bad_events_fail() {
    use common::cli::{fails, ok};
    let tmp = tempfile::TempDir::new().unwrap();
    // The Jeffcott paper rotor driven at 2 ω_n (free orbit 1.29 e inside δ = 1.5 e), a blade-off at 0.2 s onto the rod, coasting.
    let text = PAPER.replace(
        "[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1",
        "[run.speed_profile]\nkind = \"driven\"\nunit = \"speed_ratio\"\nspeed = 2.0\nduration = 0.6\nreference = 1.0\n\n[[run.event]]\nkind = \"unbalance\"\ntime = 0.2\nmass = 0.03\nradius = 0.045\nphase_deg = 90.0\n",
    ).replace("orbit_grids", "png = false\norbit_grids");
    let scene = tmp.path().join("bo.toml");
    std::fs::write(&scene, &text).unwrap();
    let out = tmp.path().join("o");
    ok(
        tmp.path(),
        &[
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let csv = std::fs::read_to_string(out.join("speed_history.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t_s,omega_rad_s,speed_ratio,phi_rad,omega_dot_rad_s2,drive_torque_nm,friction_torque_nm"
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    let rub_before = rows
        .iter()
        .filter(|r| r[0] > 0.1 && r[0] < 0.2)
        .any(|r| r[6] > 0.0);
    let rub_after = rows.iter().filter(|r| r[0] > 0.25).any(|r| r[6] > 0.0);
    assert!(!rub_before && rub_after, "the blade-off must start the rub");
    let (w0, w1) = (rows[0][1], rows[rows.len() - 1][1]);
    assert!(w1 < 0.99 * w0, "the rub must slow the rotor: {w0} → {w1}");
    // An event after the run's end: exit 2, the key and line named.
    std::fs::write(&scene, text.replace("time = 0.2", "time = 0.7")).unwrap();
    let e = fails(
        tmp.path(),
        &[
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(
        e.contains("key `run.event.0.time`") && e.contains("ends after the run"),
        "{e}"
    );
}
