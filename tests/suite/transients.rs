//! Speed transients (`[run.speed_profile]`): the slow ramp against the steady unbalance
//! response, the fitted order of the transient scheme with and without contact, and the
//! errors of bad profiles.

use crate::common;

use common::scenes::PAPER;
use common::{scene_model, settings};
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

/// Fitted order of the transient scheme: runs at Δt = T/N for N = n0·2^k, every step recorded
/// (`samples_per_rev` large), errors against the finest run at the coarse run's instants.
fn fitted_order(text: &str, integrator: &str, n0: usize, duration: f64) -> (f64, Vec<f64>, usize) {
    let levels = [1usize, 2, 4, 8];
    let finest = 32usize;
    let go = |mult: usize| {
        let dt = format!("run.dt={:e}", duration / (n0 * mult) as f64);
        let integ = format!("run.integrator=\"{integrator}\"");
        run(
            text,
            &[
                dt.as_str(),
                integ.as_str(),
                "run.samples_per_rev=1000000",
                "run.error_estimate=false",
            ],
        )
    };
    let reference = go(finest);
    let mut errs = Vec::new();
    let mut contact = 0;
    for &m in &levels {
        let r = go(m);
        assert_eq!(r.plan.steps, n0 * m, "steps");
        assert_eq!(r.plan.record_every, 1);
        contact = contact.max(r.stats.contact_steps);
        let stride = finest / m;
        let e = r
            .response
            .iter()
            .enumerate()
            .map(|(i, u)| {
                let v = reference.response[i * stride];
                (u[0] - v[0]).hypot(u[1] - v[1])
            })
            .fold(0.0, f64::max);
        errs.push(e);
    }
    let h: Vec<f64> = levels.iter().map(|m| 1.0 / *m as f64).collect();
    (loglog_slope(&h, &errs), errs, contact)
}

#[test]
fn transient_scheme_keeps_its_order_without_and_with_contact() {
    // A fast ramp through the resonance: 0.8 → 2 ω_n in 0.5 s (≈ 18 revolutions).
    let ramp = "[run.speed_profile]\nkind = \"ramp\"\nunit = \"speed_ratio\"\nfrom = 0.8\nto = 2.0\nduration = 0.5";
    let free = paper_profile(ramp, false);
    let (p, e, _) = fitted_order(&free, "collocated", 2500, 0.5);
    eprintln!("free: order {p:.3}, errors {e:?}");
    assert!((p - 2.0).abs() < 0.1, "free rotor: order {p}");
    let rub = paper_profile(ramp, true);
    let (p, e, c) = fitted_order(&rub, "collocated", 2500, 0.5);
    eprintln!("rub, collocated: order {p:.3}, errors {e:?}, contact steps {c}");
    assert!(c > 100, "the run must rub: {c} contact steps");
    assert!((p - 2.0).abs() < 0.3, "collocated with rub: order {p}");
    let (p, e, c) = fitted_order(&rub, "forward_increment", 2500, 0.5);
    eprintln!("rub, forward increment: order {p:.3}, errors {e:?}, contact steps {c}");
    assert!(c > 100, "the run must rub: {c} contact steps");
    assert!(
        (p - 1.0).abs() < 0.15,
        "forward increment with rub: order {p}"
    );
}

/// The error of the paper scene with `profile`, which must fail to load.
fn profile_error(profile: &str) -> String {
    let text = paper_profile(profile, false);
    rubsim::scene::parse(std::path::Path::new("t.toml"), &text, &[])
        .expect_err("a bad profile loads")
        .to_string()
}

/// 1-based line of the first line of `text` that starts with `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.starts_with(needle)).unwrap() + 1
}

#[test]
fn bad_profiles_name_the_key_and_line() {
    let cases: &[(&str, &str, &str, &str)] = &[
        // (profile, key in the message, what it says, the line's start)
        (
            "[run.speed_profile]\nkind = \"ramp\"\nunit = \"rpm\"\nfrom = 3000.0\nto = -100.0\nduration = 2.0",
            "run.speed_profile.to",
            "reverse through zero speed",
            "to = ",
        ),
        (
            "[run.speed_profile]\nkind = \"table\"\nunit = \"rad_per_s\"\npoints = [\n  [0.0, 10.0],\n  [2.0, 20.0],\n  [1.0, 30.0],\n]",
            "run.speed_profile.points.2",
            "increase strictly",
            "  [1.0, 30.0]",
        ),
        (
            "[run.speed_profile]\nkind = \"table\"\nunit = \"rad_per_s\"\npoints = [\n  [-1.0, 10.0],\n  [2.0, 20.0],\n]",
            "run.speed_profile.points.0",
            "finite and ≥ 0",
            "  [-1.0, 10.0]",
        ),
        (
            "[run.speed_profile]\nkind = \"ramp\"\nunit = \"speed_ratio\"\nfrom = 0.5\nto = 6.0\nacceleration = -2.0",
            "run.speed_profile.acceleration",
            "sign of `to − from`",
            "acceleration = ",
        ),
        (
            "[run.speed_profile]\nkind = \"constant\"\nunit = \"speed_ratio\"\nspeed = 1.0\nduration = inf",
            "run.speed_profile.duration",
            "positive finite",
            "duration = ",
        ),
        (
            "[run.speed_profile]\nkind = \"constant\"\nunit = \"speed_ratio\"\nspeed = 1.0\nduration = 1.0\nfrom = 2.0",
            "run.speed_profile.from",
            "does not apply",
            "from = ",
        ),
    ];
    for (profile, key, what, line) in cases {
        let e = profile_error(profile);
        let text = paper_profile(profile, false);
        let at = format!("t.toml:{}: key `{key}`", line_of(&text, line));
        assert!(
            e.contains(&at) && e.contains(what),
            "expected `{at}` … `{what}`, got: {e}"
        );
    }
    // The unit must be said.
    let e = profile_error("[run.speed_profile]\nkind = \"constant\"\nspeed = 1.0\nduration = 1.0");
    assert!(e.contains("unit"), "{e}");
    // A profile and a single speed at once.
    let e = profile_error(
        "speed_ratio = 1.0\n[run.speed_profile]\nkind = \"constant\"\nunit = \"rpm\"\nspeed = 1.0\nduration = 1.0",
    );
    assert!(e.contains("exactly one of"), "{e}");
}

#[test]
#[ignore = "slow tier (scripts/test-slow.sh): a slow FE-rotor ramp and its steady responses"]
fn fe_rotor_ramp_follows_its_steady_response_and_tabulated_bearings_are_refused() {
    use common::scenes::PAPER_FE;
    // The paper's rotor as an 8-element Timoshenko model without gyroscopics (its matrices do
    // not depend on Ω), free, 0.5 → 2 ω_n in 40 s (α/ω_n² = 2.2e-4).
    let mut text = PAPER_FE
        .replace("[rotor]\nkind = \"fe\"\n", "[rotor]\nkind = \"fe\"\ngyroscopic = false\n")
        .replace(
            "[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1",
            "[run.speed_profile]\nkind = \"ramp\"\nunit = \"speed_ratio\"\nfrom = 0.5\nto = 2.0\nduration = 40.0",
        );
    let a = text.find("[[stator]]").unwrap();
    let b = text.find("[run]").unwrap();
    text = format!("{}{}", &text[..a], &text[b..]);
    assert!(text.contains("gyroscopic = false") && text.contains("[run.speed_profile]"));
    let r = run(&text, &[]);
    let (mut amp_err, mut ph_err) = (0.0_f64, 0.0_f64);
    for w in r.windows.iter().filter(|w| w.t > 5.0) {
        amp_err = amp_err.max((w.lines[0].0 - w.steady_1x.0).abs() / w.steady_1x.0);
        ph_err = ph_err.max(dphase(w.lines[0].1, w.steady_1x.1));
    }
    eprintln!(
        "FE ramp: {} windows, amplitude error {amp_err:.3e}, phase error {ph_err:.3e} rad",
        r.windows.len()
    );
    assert!(amp_err < 0.01 && ph_err < 0.01, "{amp_err} {ph_err}");
    // With gyroscopics (the disk at mid-span does not tilt in the first mode: the same response).
    let gyro = text.replace("gyroscopic = false\n", "");
    let r = run(&gyro, &[]);
    let amp_err = r
        .windows
        .iter()
        .filter(|w| w.t > 5.0)
        .map(|w| (w.lines[0].0 - w.steady_1x.0).abs() / w.steady_1x.0)
        .fold(0.0, f64::max);
    assert!(amp_err < 0.01, "gyroscopic: {amp_err}");
    // Bearings tabulated over speed would need K(Ω), C(Ω) to follow Ω(t): refused, saying so.
    let tabulated = gyro.replace(
        "[[rotor.bearing]]\nnode = 0\nstiffness = 1.0e8\n",
        "[[rotor.bearing]]\nnode = 0\nspeeds = [0.0, 400.0]\nkxx = [1.0e8, 2.0e8]\nkyy = 1.0e8\n",
    );
    assert_ne!(tabulated, gyro);
    let (ls, model) = scene_model(&tabulated, &[] as &[&str]);
    let e = prepare_transient(
        &model,
        &settings(&ls),
        ls.scene.run.speed_profile.as_ref().unwrap(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("run.speed_profile") && e.contains("tabulated over speed"),
        "{e}"
    );
}

/// Friswell et al. Example 5.9.1 (two disks off mid-span, so the first modes tilt them and the
/// gyroscopic terms split them) with an unbalance on disk 2, damped bearings, no stator, along
/// `profile`.
fn two_disk_gyro(profile: &str) -> String {
    format!(
        "[rotor]\nkind = \"fe\"\nrayleigh = [20.0, 0.0]\n\
         [[rotor.shaft]]\nlength = 1.5\nouter_diameter = 0.05\nelements = 6\nyoungs_modulus = 211e9\npoisson = 0.29926\ndensity = 7810.0\n\
         [[rotor.disk]]\nnode = 2\nouter_diameter = 0.28\nbore = 0.05\nwidth = 0.07\ndensity = 7810.0\n\
         [[rotor.disk]]\nnode = 4\nouter_diameter = 0.35\nbore = 0.05\nwidth = 0.07\ndensity = 7810.0\n\
         [[rotor.bearing]]\nnode = 0\nstiffness = 1.0e6\ndamping = 1000.0\n\
         [[rotor.bearing]]\nnode = 6\nstiffness = 1.0e6\ndamping = 1000.0\n\
         [[rotor.unbalance]]\nnode = 4\nmass = 0.005\nradius = 0.15\n\
         [output]\nnode = 4\n\
         [run]\n{profile}\n"
    )
}

/// A slow run-up (α = 0.75 rad/s²) through both forward criticals (≈ 88 and ≈ 290 rad/s) with
/// M̃ factored at 200 rad/s: the tracked 1× at disk 2 meets the steady unbalance response of
/// the gyroscopic rotor at each window's speed. (Without the explicit `(Ω − Ω_f) G q̇` term the
/// error is 8.6 %, measured once when the term was written.)
#[test]
#[ignore = "slow tier (scripts/test-slow.sh): a slow gyroscopic FE-rotor run-up and its steady responses"]
fn gyroscopic_fe_rotor_slow_runup_follows_its_steady_response() {
    let text = two_disk_gyro(
        "[run.speed_profile]\nkind = \"ramp\"\nunit = \"rad_per_s\"\nfrom = 50.0\nto = 350.0\nduration = 400.0\nreference = 200.0",
    );
    let r = run(&text, &[]);
    let (mut amp_err, mut ph_err, mut n) = (0.0_f64, 0.0_f64, 0);
    for w in r.windows.iter().filter(|w| w.t > 10.0) {
        amp_err = amp_err.max((w.lines[0].0 - w.steady_1x.0).abs() / w.steady_1x.0);
        ph_err = ph_err.max(dphase(w.lines[0].1, w.steady_1x.1));
        n += 1;
    }
    eprintln!(
        "gyroscopic FE ramp: {n} windows, {} steps, amplitude error {amp_err:.3e}, phase error {ph_err:.3e} rad, peak {:?}",
        r.plan.steps, r.peak_1x
    );
    assert!(n > 10_000, "{n} windows");
    assert!(amp_err < 0.01 && ph_err < 0.01, "{amp_err} {ph_err}");
    // The peak of the first forward critical.
    assert!(
        (r.peak_1x.1 - 88.5).abs() < 1.0,
        "peak at {} rad/s",
        r.peak_1x.1
    );
}

#[test]
fn gyroscopic_transient_scheme_keeps_second_order() {
    // A fast ramp 100 → 300 rad/s in 0.2 s (Ω̇ = 1000 rad/s²), M̃ factored at 200 rad/s, so both
    // the explicit (Ω − Ω_f) G q̇ and Ω̇ K_st q act throughout.
    let text = two_disk_gyro(
        "[run.speed_profile]\nkind = \"ramp\"\nunit = \"rad_per_s\"\nfrom = 100.0\nto = 300.0\nduration = 0.2\nreference = 200.0",
    );
    let (p, e, _) = fitted_order(&text, "collocated", 8000, 0.2);
    eprintln!("gyroscopic FE ramp: order {p:.3}, errors {e:?}");
    assert!((p - 2.0).abs() < 0.1, "order {p}");
}

/// K_st is G's y–z-plane rows: `G = K_st − K_stᵀ` over the assembled rotor, K_st nonzero only
/// in the rows of u_y and θ_x, and at a disk's node `K_st[θ_x, θ_y] = I_p` (with the shaft's
/// share).
#[test]
fn k_st_is_the_one_plane_part_of_g() {
    let text = two_disk_gyro(
        "[run.speed_profile]\nkind = \"ramp\"\nunit = \"rad_per_s\"\nfrom = 100.0\nto = 300.0\nduration = 0.2",
    );
    let (_, model) = scene_model(&text, &[] as &[&str]);
    let body = model.rotor.body(0.0).unwrap();
    let gyro = body.gyro.expect("a gyroscopic rotor has its terms");
    let n = body.ndof;
    let dense = |a: &rubsim::linalg::Csc| {
        let mut d = vec![0.0; n * n];
        for (r, c, v) in a.triplets() {
            d[r * n + c] += v;
        }
        d
    };
    let (g, k) = (dense(&gyro.g), dense(&gyro.k_st));
    let scale = g.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(scale > 0.0);
    for r in 0..n {
        for c in 0..n {
            let skew = k[r * n + c] - k[c * n + r];
            assert!((skew - g[r * n + c]).abs() <= 1e-12 * scale, "({r}, {c})");
            if k[r * n + c] != 0.0 {
                assert!(matches!(r % 4, 1 | 2), "K_st row {r} is not u_y or θ_x");
            }
        }
    }
    // Disk 2 (350 mm, 70 mm wide, bore 50 mm): I_p = ρ π w (D⁴ − d⁴)/32.
    let ip = 7810.0 * std::f64::consts::PI * 0.07 * (0.35f64.powi(4) - 0.05f64.powi(4)) / 32.0;
    let (tx, ty) = (4 * 4 + 2, 4 * 4 + 3);
    let shaft = k[tx * n + ty] - ip;
    assert!(
        shaft > 0.0 && shaft < 0.01 * ip,
        "K_st[θx, θy] at disk 2 = {} for I_p = {ip}",
        k[tx * n + ty]
    );
}

/// The implicit schemes hold Ω(t)G and Ω̇K_st inside their step operator, refactored as the
/// speed moves (`time::spin`): on the fast gyroscopic ramp both keep their second order, at
/// steps above the explicit stability limit.
#[test]
fn implicit_gyroscopic_transient_keeps_second_order() {
    let text = two_disk_gyro(
        "[run.speed_profile]\nkind = \"ramp\"\nunit = \"rad_per_s\"\nfrom = 100.0\nto = 300.0\nduration = 0.2\nreference = 200.0",
    );
    for integrator in ["newmark", "generalized_alpha"] {
        let (p, e, _) = fitted_order(&text, integrator, 400, 0.2);
        eprintln!("gyroscopic FE ramp, {integrator}: order {p:.3}, errors {e:?}");
        assert!((p - 2.0).abs() < 0.1, "{integrator}: order {p}");
    }
    // And it converges to the explicit scheme's solution (each at 12,800 steps, errors
    // ≈ 1e-9 m of a ≈ 1e-5 m response): the same equations, not only a self-consistent step.
    let at = |integrator: &str| {
        let integ = format!("run.integrator=\"{integrator}\"");
        let r = run(&text, &["run.dt=1.5625e-5", integ.as_str()]);
        *r.response.last().unwrap()
    };
    let (a, b) = (at("newmark"), at("collocated"));
    let size = a[0].hypot(a[1]);
    let diff = (a[0] - b[0]).hypot(a[1] - b[1]);
    eprintln!("newmark against collocated at the end: {diff:e} of {size:e}");
    assert!(size > 1e-7 && diff < 1e-4 * size, "{diff:e} of {size:e}");
}

/// The seal-ring run-up (scenes/transients/friswell_runup_seal.toml) shortened to the rub
/// (0.9 → 1.3 ω_n in 1 s): the implicit schemes keep their order with gyroscopics and contact.
#[test]
fn implicit_gyroscopic_runup_with_rub_keeps_its_order() {
    let text = seal_runup(false);
    for integrator in ["newmark", "generalized_alpha"] {
        let (p, e, c) = fitted_order(&text, integrator, 2000, 1.0);
        eprintln!("seal run-up, {integrator}: order {p:.3}, errors {e:?}, contact steps {c}");
        assert!(c > 100, "the run must rub: {c} contact steps");
        assert!((p - 2.0).abs() < 0.3, "{integrator} with rub: order {p}");
    }
}

/// A driven rotor's spin is integrated by the explicit central difference only: an implicit
/// scheme is refused naming `run.integrator`; the same gyroscopic rotor on a prescribed
/// profile runs implicitly, in the stepper as through `prepare_transient`.
#[test]
fn implicit_schemes_refuse_driven_rotors_and_run_gyroscopic_profiles() {
    let driven = two_disk_gyro(
        "integrator = \"generalized_alpha\"\n[run.speed_profile]\nkind = \"driven\"\nunit = \"rad_per_s\"\nspeed = 100.0\nduration = 0.5\ndrive_torque = 0.2\ndrag_coefficient = 2.0e-3",
    );
    let (ls, model) = scene_model(&driven, &[] as &[&str]);
    let spec = ls.scene.run.speed_profile.as_ref().unwrap();
    let e = prepare_transient(&model, &settings(&ls), spec)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("`run.integrator`") || e.contains("run.integrator"),
        "{e}"
    );
    let text = two_disk_gyro(
        "integrator = \"generalized_alpha\"\n[run.speed_profile]\nkind = \"ramp\"\nunit = \"rad_per_s\"\nfrom = 100.0\nto = 120.0\nduration = 2.0",
    );
    let (ls, model) = scene_model(&text, &[] as &[&str]);
    let s = settings(&ls);
    let case = model.case(110.0).unwrap();
    let profile = rubsim::model::SpeedProfile::ramp(100.0, 120.0, 2.0, 0.0).unwrap();
    let plan = rubsim::time::plan_duration(&case, &s.step, 120.0, 2.0).unwrap();
    assert!(rubsim::time::Stepper::with_profile(
        &case,
        s.step.integrator,
        &plan,
        Default::default(),
        Some(&profile),
    )
    .is_ok());
    let r = run(&text, &[]);
    assert!(!r.windows.is_empty());
}

/// The seal-ring run-up (scenes/transients/friswell_runup_seal.toml) shortened to the rub
/// (0.9 → 1.3 ω_n in 1 s); `fine`: its shaft in 24 elements instead of 6 (disks, bearing,
/// unbalance and station at the same places).
fn seal_runup(fine: bool) -> String {
    let mut text =
        std::fs::read_to_string(common::repo("scenes/transients/friswell_runup_seal.toml"))
            .unwrap()
            .replace(
                "from = 0.5\nto = 1.5\nduration = 8.0",
                "from = 0.9\nto = 1.3\nduration = 1.0",
            );
    assert!(text.contains("duration = 1.0"));
    if fine {
        text = text
            .replace("elements = 6", "elements = 24")
            .replace("node = 2\n", "node = 8\n")
            .replace("node = 4\n", "node = 16\n")
            .replace("node = 6\n", "node = 24\n");
        assert!(text.contains("elements = 24"));
    }
    text
}

/// A reduced FE rotor (`[run.reduction]`) runs a speed profile with its gyroscopic terms
/// projected on the basis (`Tᵀ G T`, `Tᵀ K_st T`, the basis cut off above the profile's top
/// speed): the explicit step is the reduced model's, ≈ 38× the full shaft's, the scheme keeps
/// its order with the rub, and the tracked 1× meets the full model's.
#[test]
fn reduced_rotor_runs_a_gyroscopic_runup_with_rub() {
    let text = seal_runup(true);
    let reduced = format!("{text}\n[run.reduction]\n");
    let full = run(&text, &[]);
    let red = run(&reduced, &[]);
    eprintln!(
        "full: {} steps (Δt {:.3e} s), reduced: {} steps (Δt {:.3e} s); contact steps {} / {}",
        full.plan.steps,
        full.plan.dt,
        red.plan.steps,
        red.plan.dt,
        full.stats.contact_steps,
        red.stats.contact_steps
    );
    assert!(
        red.plan.dt > 10.0 * full.plan.dt,
        "{} vs {}",
        red.plan.dt,
        full.plan.dt
    );
    assert!(red.stats.contact_steps > 100);
    let peak = |r: &TransientResults| r.windows.iter().map(|w| w.lines[0].0).fold(0.0, f64::max);
    let (pf, pr) = (peak(&full), peak(&red));
    eprintln!("peak 1×: full {pf:e}, reduced {pr:e}");
    assert!((pf - pr).abs() < 1e-4 * pf, "peak 1× {pr} against {pf}");
    for integrator in ["collocated", "newmark"] {
        let (p, e, c) = fitted_order(&reduced, integrator, 2500, 1.0);
        eprintln!(
            "reduced seal run-up, {integrator}: order {p:.3}, errors {e:?}, contact steps {c}"
        );
        assert!(c > 100, "{c} contact steps");
        assert!((p - 2.0).abs() < 0.3, "{integrator}: order {p}");
    }
}

/// A transient run estimates its error (`run.error_estimate`): the tracked 1× against a
/// companion at a coarser step, by Richardson. On the 24-element seal run-up (0.9 → 1.3 ω_n)
/// the estimate meets the true error (against the same scheme at Δt/4) for Newmark at its
/// accuracy step (2.70e-5 against 2.70e-5) and bounds it for the explicit scheme at its
/// stability limit (companion just below the limit: 2.0e-7 against 1.6e-8).
#[test]
fn transient_error_estimate_meets_the_true_error() {
    let text = seal_runup(true);
    let err_1x = |r: &TransientResults, f: &TransientResults| {
        let (t, a): (Vec<f64>, Vec<f64>) = f.windows.iter().map(|w| (w.t, w.lines[0].0)).unzip();
        let peak = a.iter().cloned().fold(0.0, f64::max);
        (r.windows.iter())
            .filter(|w| w.t >= t[0] && w.t <= t[t.len() - 1])
            .map(|w| (w.lines[0].0 - rubsim::math::interp_linear(&t, &a, w.t)).abs())
            .fold(0.0, f64::max)
            / peak
    };
    for integrator in ["newmark", "collocated"] {
        let integ = format!("run.integrator=\"{integrator}\"");
        let r = run(&text, &[integ.as_str()]);
        let e = r.error_estimate.expect("an estimate");
        let dt = format!("run.dt={:e}", r.plan.dt / 4.0);
        let fine = run(
            &text,
            &[integ.as_str(), dt.as_str(), "run.error_estimate=false"],
        );
        let truth = err_1x(&r, &fine);
        eprintln!(
            "{integrator}: Δt {:.3e} s, estimate {:.3e} (companion Δt {:.3e} s), true {truth:.3e}",
            r.plan.dt, e.relative_1x, e.companion_dt
        );
        // Never below the truth; above it by at most 1.5×, or — the explicit run, 1.6e-8 —
        // by the tracking's own resolution, far below any tolerance.
        assert!(
            e.relative_1x > truth / 1.5 && (e.relative_1x < 1.5 * truth || e.relative_1x < 1e-6),
            "{integrator}: estimate {} against {truth}",
            e.relative_1x
        );
    }
}
