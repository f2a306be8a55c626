//! The thermal spiral (issue 27, first part): the hot-spot model of `[thermal]` coupled to the
//! rub's vibration (`analysis::thermal`), against the closed form of a Jeffcott rotor rubbing all
//! round a radial ring (docs/VALIDATION.md §21, `oracles::Newkirk`): the spiral's trajectory,
//! growth and rotation below and above the critical speed, the heat against the friction
//! power's closed form, the accelerated coupling against the resolved one, a runaway, the
//! command's files and the errors of bad input.

use crate::common::{self, cli, oracles::Newkirk};
use num_complex::Complex64 as C64;
use rubsim::analysis::thermal::{run_thermal, HotSpot, ThermalResults};
use rubsim::model::Rotor;

const SCENE: &str = "scenes/thermal/newkirk_ring.toml";

/// The scene's thermal run with overrides, and its closed form.
fn run(sets: &[&str]) -> (ThermalResults, Newkirk) {
    let (ls, model) = common::file_model(&common::repo(SCENE), sets);
    let s = common::settings(&ls);
    let v = ls.scene.run.speed_ratio.unwrap();
    let spec = ls.scene.thermal.as_ref().unwrap();
    let hs = HotSpot::of_scene(&ls).unwrap();
    let r = run_thermal(&model, &s, v, &hs).unwrap();
    let Rotor::Jeffcott(j) = &model.rotor else {
        panic!("a Jeffcott rotor")
    };
    let station = &ls.scene.stations[0];
    let nk = Newkirk {
        m: j.mass,
        c: j.damping,
        k: j.stiffness,
        ks: 0.5 * j.stiffness,
        mu: station.friction,
        radius: station.radius,
        omega: r.omega,
        me: 0.008 * 0.045,
        gain: spec.gain.unwrap(),
        th: spec.heating_time.unwrap(),
        tc: spec.cooling_time.unwrap(),
        bow: r.bow_per_kelvin,
    };
    (r, nk)
}

fn c(v: [f64; 2]) -> C64 {
    C64::new(v[0], v[1])
}

/// The largest relative distance of the run's ΔT from the linear theory's over its steps.
fn trajectory_error(r: &ThermalResults, nk: &Newkirk) -> f64 {
    let times: Vec<f64> = r.samples.iter().map(|s| s.t_s).collect();
    let start = c(r.samples[0].delta_t);
    let lin = nk.trajectory(start, &times);
    r.samples
        .iter()
        .zip(&lin)
        .map(|(s, l)| (c(s.delta_t) - l).norm() / l.norm())
        .fold(0.0, f64::max)
}

/// Below the coupled critical speed (ν 0.8 against √1.5) the spiral grows: its ΔT follows the
/// linear theory's trajectory, and its fitted growth and rotation are the theory's dominant
/// eigenvalue (Λ = 1.89 ∠ −11.8°, s = 0.0365 − 0.0155i 1/s).
#[test]
fn below_the_critical_speed_the_spiral_grows_as_the_linear_theory_says() {
    let (r, nk) = run(&["thermal.duration=30"]);
    assert!(r.resolved && r.runaway_at_s.is_none());
    let s = nk.rates()[0];
    let lam = nk.lambda();
    eprintln!(
        "Λ = {:.4} ∠ {:.2}°, s = {s:.5}; run: growth {:.5}, rotation {:.5}",
        lam.norm(),
        lam.arg().to_degrees(),
        r.growth_rate,
        r.rotation_rate
    );
    assert!((lam.norm() - 1.887).abs() < 1e-2 && s.re > 0.0);
    let err = trajectory_error(&r, &nk);
    eprintln!("ΔT against the theory's trajectory: {err:.2e}");
    assert!(err < 1e-2, "{err}");
    assert!(
        (r.growth_rate / s.re - 1.0).abs() < 0.03,
        "{} {}",
        r.growth_rate,
        s.re
    );
    assert!(
        (r.rotation_rate / s.im - 1.0).abs() < 0.05,
        "{} {}",
        r.rotation_rate,
        s.im
    );
}

/// Above it (ν 1.6) the bow's response is in antiphase: the spiral turns and settles as the
/// theory's trajectory does, to the theory's own assumption of a 1× vector that follows the
/// bow at once (here the spiral's time, ≈ 4 s, is 35 times the vibration's settling time,
/// 2m/c ≈ 0.12 s: about 3 %).
#[test]
fn above_the_critical_speed_the_spiral_settles_as_the_linear_theory_says() {
    let (r, nk) = run(&["run.speed_ratio=1.6", "thermal.duration=15"]);
    let s = nk.rates()[0];
    eprintln!(
        "ν 1.6: s = {s:.5}; run: growth {:.5}, rotation {:.5}",
        r.growth_rate, r.rotation_rate
    );
    assert!(s.re < 0.0 && r.growth_rate < 0.0);
    let err = trajectory_error(&r, &nk);
    eprintln!("ΔT against the theory's trajectory: {err:.2e}");
    assert!(err < 3e-2, "{err}");
    // It settles: the last step's change of ΔT is a tenth of the largest (e^{Re s · 12 s}).
    let change = |k: usize| (c(r.samples[k + 1].delta_t) - c(r.samples[k].delta_t)).norm();
    let n = r.samples.len();
    let most = (0..n - 1).map(change).fold(0.0, f64::max);
    assert!(change(n - 2) < 0.1 * most, "{} {most}", change(n - 2));
}

/// Against speed: the spiral's growth and rotation (its dominant slow eigenvalue, fitted from
/// the run) follow the theory's within 5 % of |s| at ν 1.0 … 2.0, across the threshold between
/// ν 1.2 (growing) and 1.3 (settling) that the coupled critical speed √1.5 sets. Each run is
/// kept to the linear regime (|1×| ≪ R).
#[test]
fn the_spiral_follows_the_theory_against_speed() {
    for (nu, duration) in [(1.0, 12.0), (1.2, 8.0), (1.3, 40.0), (2.0, 30.0)] {
        let (r, nk) = run(&[
            &format!("run.speed_ratio={nu}"),
            &format!("thermal.duration={duration}"),
            "thermal.max_temperature_difference=1e4",
        ]);
        let want = nk.rates()[0];
        let got = C64::new(r.growth_rate, r.rotation_rate);
        eprintln!("ν {nu}: s = {want:.4} (theory), {got:.4} (run)");
        assert!(
            (got - want).norm() < 0.05 * want.norm(),
            "ν {nu}: {got} against {want}"
        );
        assert_eq!(got.re > 0.0, nu < 1.25, "ν {nu}");
    }
}

/// Heat in is friction work: the mean friction power of a step is the closed form
/// μ k_s (|Z| − δ)(R + |Z|) Ω of a rub all round, and its first harmonic points at the high spot
/// (the 1× vector's direction) with the same magnitude.
#[test]
fn the_heat_is_the_friction_power_at_the_high_spot() {
    let (r, nk) = run(&["thermal.duration=2"]);
    let delta = 1e-7;
    for s in &r.samples {
        let z = c(s.one_x);
        let want = nk.mu * nk.ks * (z.norm() - delta) * (nk.radius + z.norm()) * nk.omega;
        assert!((s.power / want - 1.0).abs() < 1e-4, "{} {want}", s.power);
        let q = c(s.heat);
        assert!((q.norm() / s.power - 1.0).abs() < 1e-4, "{q} {}", s.power);
        let angle = (q / z).arg();
        assert!(
            angle.abs() < 1e-6,
            "hot spot {angle} rad from the high spot"
        );
        assert!((s.contact_fraction - 1.0).abs() < 1e-12);
    }
}

/// The accelerated coupling (each step integrates the vibration until its 1× vector is steady,
/// then holds the heat, extrapolated, over h): against a step of 1/16 s, the error in ΔT falls
/// as a power of h of fitted order ≥ 1.4 (h = 0.5 … 4 s), and at h = 1 s it is within 1 %, with
/// fewer steps than the resolved run, and follows the theory's spiral.
#[test]
fn the_accelerated_coupling_converges_in_its_step() {
    let at = |h: f64| run(&["thermal.duration=32", &format!("thermal.step={h}")]).0;
    let reference = at(0.0625);
    let error = |r: &ThermalResults| -> f64 {
        r.samples
            .iter()
            .map(|s| {
                let x = interpolate(&reference, s.t_s);
                (c(s.delta_t) - x).norm() / x.norm()
            })
            .fold(0.0, f64::max)
    };
    let hs = [0.5, 1.0, 2.0, 4.0];
    let errs: Vec<f64> = hs.iter().map(|&h| error(&at(h))).collect();
    let order = rubsim::math::loglog_slope(&hs, &errs);
    eprintln!("coupling error against h = 1/16 s: {errs:.3?} at h = {hs:?}; order {order:.2}");
    assert!(order > 1.4, "{order}");
    assert!(errs[1] < 1e-2, "{}", errs[1]);
    let (fine, nk) = run(&["thermal.duration=32"]);
    let coarse = at(1.0);
    eprintln!(
        "h = 1 s: {} steps against the resolved run's {}; ΔT at the end {:.4} K against {:.4} K",
        coarse.steps,
        fine.steps,
        c(coarse.samples.last().unwrap().delta_t).norm(),
        c(fine.samples.last().unwrap().delta_t).norm()
    );
    // Each step integrates until the 1× vector is steady (here ≈ 20 revolutions of the
    // vibration's settling against the step's 21 at h = 1 s): the steps a run saves grow with h/settling.
    assert!(coarse.steps < fine.steps);
    assert!(trajectory_error(&coarse, &nk) < 2e-2);
}

/// ΔT of `r` at `t` (s), linear between its steps.
fn interpolate(r: &ThermalResults, t: f64) -> C64 {
    let k = r
        .samples
        .partition_point(|s| s.t_s <= t)
        .clamp(1, r.samples.len() - 1);
    let (a, b) = (&r.samples[k - 1], &r.samples[k]);
    let w = ((t - a.t_s) / (b.t_s - a.t_s)).clamp(0.0, 1.0);
    c(a.delta_t) * (1.0 - w) + c(b.delta_t) * w
}

/// A spiral that grows without bound stops where |ΔT| passes the bound, with its growth rate,
/// and no number of the run is a NaN.
#[test]
fn a_runaway_stops_with_its_growth_rate() {
    let (r, _) = run(&[]);
    let t = r.runaway_at_s.expect("a runaway");
    assert!(t > 30.0 && t < 120.0, "{t}");
    assert!(r.growth_rate > 0.0 && r.growth_rate.is_finite());
    let last = r.samples.last().unwrap();
    assert!(last.delta_t[0].hypot(last.delta_t[1]) > 200.0);
    for s in &r.samples {
        for v in [s.delta_t, s.bow, s.one_x, s.heat, s.surface] {
            assert!(v[0].is_finite() && v[1].is_finite());
        }
        assert!(s.power.is_finite());
    }
}

/// `rubsim run` of a scene with `[thermal]` writes the spiral's files and says how it ends.
#[test]
fn the_run_command_writes_the_spiral() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("nk");
    let stdout = cli::ok(
        &common::repo(""),
        &[
            "run",
            SCENE,
            "--set",
            "thermal.duration=20",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(
        stdout.contains("thermal spiral") && stdout.contains("growing"),
        "{stdout}"
    );
    for f in ["spiral.csv", "spiral.png", "thermal.png", "summary.json"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let csv = common::read(&out.join("spiral.csv"));
    assert!(csv.starts_with(rubsim::output::thermal::SPIRAL_HEADER));
    let summary: serde_json::Value =
        serde_json::from_str(&common::read(&out.join("summary.json"))).unwrap();
    assert!(summary["thermal"]["growth_rate"].as_f64().unwrap() > 0.0);
    assert_eq!(summary["command"], "run");
}

/// Bad input: zero or negative times, coefficients and lengths, an FE rotor, a Jeffcott rotor
/// without a span, an unknown station — each refused naming its key.
#[test]
fn bad_thermal_input_is_refused_by_key() {
    let cases: [(&[&str], &str); 8] = [
        (&["thermal.heating_time=0"], "thermal.heating_time"),
        (&["thermal.cooling_time=-5"], "thermal.cooling_time"),
        (&["thermal.gain=0"], "thermal.gain"),
        (&["thermal.expansion=-1e-5"], "thermal.expansion"),
        (&["thermal.step=0"], "thermal.step"),
        (&["thermal.revolutions=0"], "thermal.revolutions"),
        (&["thermal.station=\"nowhere\""], "thermal.station"),
        (&["thermal.heated_length=1.0"], "thermal.heated_length"),
    ];
    for (sets, key) in cases {
        let mut args = vec!["check", SCENE];
        for s in sets {
            args.extend(["--set", s]);
        }
        let err = cli::fails(&common::repo(""), &args);
        assert!(err.contains(key), "{sets:?}: {err}");
    }
    let text = common::read(&common::repo(SCENE))
        .replace(
            "disk = { diameter = 0.12, thickness = 0.03, density = 7800.0 }\nshaft = { youngs_modulus = 200e9, diameter = 0.01, length = 0.40 }",
            "mass = 2.646\nstiffness = 73630.0",
        );
    let err = rubsim::scene::parse(std::path::Path::new("x.toml"), &text, &[] as &[String])
        .unwrap_err()
        .to_string();
    assert!(err.contains("thermal.span"), "{err}");
}

/// A thermal run's error estimate (`ThermalError`, `run.error_estimate`): the run at h = 1 s
/// over 32 s of machine time against its companions at 2h and 2Δt, each difference taken whole.
/// The true error of ΔT, against a reference at h = 1/16 s and Δt/2, lies below the estimate
/// and within a factor of 10 of it (measured: 9.9e-3 against 3.4e-3, the coupling's part
/// 9.6e-3, the step's 2.5e-4); the growth rate's estimate is the true error's size (3.96e-5
/// against 3.97e-5 1/s). A resolved run's coupling part is
/// its chunks' (twice as long in the companion).
#[test]
fn the_thermal_error_estimate_bounds_the_coupling_and_step_errors() {
    let (r, _) = run(&["thermal.duration=32", "thermal.step=1"]);
    let e = r.error.as_ref().expect("run.error_estimate is on");
    let step = e.step.expect("the 2Δt companion ran");
    assert_eq!(e.coupling.coupling_step_s, 2.0);
    assert_eq!(step.dt_s, 2.0 * r.dt_s);
    let dt = format!("run.dt={:e}", 0.5 * r.dt_s);
    let (reference, _) = run(&[
        "thermal.duration=32",
        "thermal.step=0.0625",
        &dt,
        "run.error_estimate=false",
    ]);
    assert!(reference.error.is_none());
    let size = r
        .samples
        .iter()
        .map(|s| c(s.delta_t).norm())
        .fold(0.0, f64::max);
    let truth = r
        .samples
        .iter()
        .map(|s| (c(s.delta_t) - interpolate(&reference, s.t_s)).norm() / size)
        .fold(0.0, f64::max);
    eprintln!(
        "ΔT error: estimated {:.3e} (coupling {:.3e}, step {:.3e}), true {truth:.3e}; growth rate ± {:.2e} against {:.2e}",
        e.delta_t,
        e.coupling.delta_t,
        step.delta_t,
        e.growth_rate,
        (r.growth_rate - reference.growth_rate).abs()
    );
    assert!(
        e.delta_t >= truth && e.delta_t < 10.0 * truth,
        "{e:?} against {truth:e}"
    );
    // The growth rate is fitted over each run's last third, its own samples: its estimate is
    // of the true error's size, not a bound (measured 0.997 of it).
    let growth = (r.growth_rate - reference.growth_rate).abs();
    assert!(
        e.growth_rate > 0.5 * growth && e.growth_rate < 10.0 * growth,
        "{e:?} against {growth:e}"
    );
    let (resolved, _) = run(&["thermal.duration=16"]);
    let e = resolved.error.as_ref().unwrap();
    eprintln!("resolved: {e:?}");
    assert!(e.coupling.coupling_step_s > resolved.coupling_step_s);
    assert!(e.delta_t > 0.0 && e.delta_t < 5e-2, "{e:?}");
}
