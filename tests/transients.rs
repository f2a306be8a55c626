//! Speed transients (`[run.speed_profile]`): the slow ramp against the steady unbalance
//! response, the fitted order of the transient scheme with and without contact, and the
//! errors of bad profiles.

mod common;

use common::scenes::PAPER;
use common::{parse, scene_model, settings};
use rubsim::analysis::{prepare_transient, TransientResults};
use rubsim::math::loglog_slope;
use std::f64::consts::PI;

/// The paper's rotor and rod with `profile` (a `[run.speed_profile]` table) instead of the sweep;
/// `rod = false` removes the rod (no contact).
fn paper_profile(profile: &str, rod: bool) -> String {
    let mut t = PAPER.replace("[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1", profile);
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
    let spec = ls.scene.run.speed_profile.as_ref().unwrap();
    prepare_transient(&model, &s, spec)
        .unwrap()
        .run(&mut [])
        .unwrap()
}

/// Wrapped phase difference (rad).
fn dphase(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(2.0 * PI);
    d.min(2.0 * PI - d)
}

#[test]
fn slow_ramp_reproduces_the_steady_unbalance_response() {
    // 0.5 → 3 ω_n in 400 s (α/ω_n² ≈ 3.7e-5): quasi-steady through the resonance (ξ = 0.2).
    let text = paper_profile(
        "[run.speed_profile]\nkind = \"ramp\"\nunit = \"speed_ratio\"\nfrom = 0.5\nto = 3.0\nduration = 400.0",
        false,
    );
    let r = run(&text, &[]);
    let (mut amp_err, mut ph_err, mut n) = (0.0_f64, 0.0_f64, 0);
    for w in r.windows.iter().filter(|w| w.t > 5.0) {
        let (a, p) = w.lines[0];
        let (sa, sp) = w.steady_1x;
        amp_err = amp_err.max((a - sa).abs() / sa);
        ph_err = ph_err.max(dphase(p, sp));
        n += 1;
    }
    eprintln!("slow ramp: {n} windows, max amplitude error {amp_err:.3e}, max phase error {ph_err:.3e} rad");
    assert!(n > 1000, "{n} windows");
    assert!(amp_err < 0.01, "amplitude error {amp_err}");
    assert!(ph_err < 0.01, "phase error {ph_err} rad");
    // The peak of the tracked 1× near the steady peak ν = 1/√(1 − 2ξ²) = 1.0426 (ξ = 0.2).
    let nu = r.peak_1x.1 / r.omega_n;
    assert!((nu - 1.0426).abs() < 0.01, "peak at ν = {nu}");
}
