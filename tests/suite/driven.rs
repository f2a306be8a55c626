//! The driven rotor (`run.speed_profile.kind = "driven"`): the spin angle integrated with the
//! lateral DOFs under drive, drag, rub friction and unbalance reaction torques. Checked
//! against closed forms — a constant torque on a free rotor, the coast-down of the full
//! annular rub — the energy balance of a driven run with rub, and the fitted order.

use crate::common;

use common::scenes::PAPER;
use common::{scene_model, settings};
use rubsim::analysis::{prepare_transient, TransientResults};
use rubsim::math::loglog_slope;
use std::f64::consts::PI;

/// The paper's Jeffcott rotor (m = 2.646 kg, k = 7.363e4 N/m, ξ = 0.2, disk 120 mm: J =
/// m D²/8) driven by `profile` (the keys of `[run.speed_profile]` after `kind = "driven"`);
/// `stator` replaces the rod (`""`: no stator); `unbalance = false` removes the unbalance.
fn driven(profile: &str, stator: &str, unbalance: bool) -> String {
    let mut t = PAPER.replace(
        "[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1",
        &format!("[run.speed_profile]\nkind = \"driven\"\n{profile}"),
    );
    let a = t.find("[[stator]]").unwrap();
    let b = t.find("[run]").unwrap();
    t = format!("{}{}\n{}", &t[..a], stator, &t[b..]);
    if !unbalance {
        let a = t.find("[[rotor.unbalance]]").unwrap();
        let b = t.find("[[station]]").unwrap();
        t = format!("{}{}", &t[..a], &t[b..]);
    }
    t
}

fn run(text: &str, sets: &[&str]) -> TransientResults {
    run_with(text, sets, |_| {})
}

fn run_with(
    text: &str,
    sets: &[&str],
    init: impl FnOnce(&mut rubsim::analysis::RunSettings),
) -> TransientResults {
    let (ls, model) = scene_model(text, sets);
    let mut s = settings(&ls);
    init(&mut s);
    let spec = ls.scene.run.speed_profile.as_ref().unwrap();
    prepare_transient(&model, &s, spec)
        .unwrap()
        .run(&mut [])
        .unwrap()
}

/// The paper rotor's mass (kg), stiffness (N/m), damping (N·s/m) and polar inertia (kg·m²).
fn rotor() -> (f64, f64, f64, f64) {
    let m = 7800.0 * PI * 0.12 * 0.12 / 4.0 * 0.03;
    let k = 48.0 * 200e9 * (PI * 0.01f64.powi(4) / 64.0) / 0.4f64.powi(3);
    (m, k, 0.4 * (m * k).sqrt(), m * 0.12 * 0.12 / 8.0)
}

#[test]
fn constant_torque_on_a_free_rotor_is_uniform_acceleration() {
    // No stator, no unbalance: J Ω̇ = T exactly, Ω = Ω₀ + T t/J, φ = Ω₀ t + T t²/2J.
    let text = driven(
        "unit = \"rad_per_s\"\nspeed = 80.0\nduration = 2.0\ndrive_torque = 0.05",
        "",
        false,
    );
    let r = run(&text, &["run.samples_per_rev=200"]);
    let j = rotor().3;
    let mut worst: f64 = 0.0;
    for s in &r.spin {
        let (t, w, phi) = (s[0], s[1], s[2]);
        let (we, pe) = (80.0 + 0.05 * t / j, 80.0 * t + 0.05 * t * t / (2.0 * j));
        worst = worst
            .max((w - we).abs() / we)
            .max((phi - pe).abs() / pe.max(1.0));
    }
    let last = r.spin.last().unwrap();
    eprintln!(
        "constant torque: Ω(2 s) = {:.9} rad/s, worst relative error {worst:.2e}",
        last[1]
    );
    assert!((last[0] - 2.0).abs() < 1e-9 && r.spin.len() > 1000);
    assert!(worst < 1e-11, "relative error {worst}");
    // The drive torque is recorded, the friction torque is zero.
    assert!(r.torque.iter().all(|t| t[0] == 0.05 && t[1] == 0.0));
}

/// Closed form of the synchronous full annular rub (shared/ORACLES.md): whirl radius r = R/e
/// and lag β at ν = Ω/ω_n for κ, μ, ξ, d = δ/e — the larger root with r > d.
fn annular(nu: f64, kappa: f64, mu: f64, xi: f64, d: f64) -> (f64, f64) {
    let (r, beta) = common::oracles::radial_annular_rub(nu, kappa, mu, xi, d);
    assert!(r > d, "no rub at ν = {nu}");
    (r, beta)
}

#[test]
fn full_annular_rub_oracle_check_values() {
    for (nu, r, b) in [
        (0.8, 1.20291, 37.793),
        (1.0, 1.23273, 35.094),
        (1.2, 1.27061, 33.102),
    ] {
        let (rr, bb) = annular(nu, 25.0, 0.1, 0.2, 1.2);
        assert!(
            (rr - r).abs() < 1e-5 && (bb.to_degrees() - b).abs() < 1e-3,
            "{nu}: {rr} {bb}"
        );
    }
}

#[test]
fn coast_down_under_full_annular_rub_decelerates_by_the_friction_torque() {
    // A massless ring on springs (κ = 25, the radially elastic law of the closed form,
    // docs/ORACLES.md §2) at δ = 1.2 e, μ = 0.1, ξ = 0.2; no drive, no drag,
    // J = 0.02 kg·m²: the rotor coasts from ω_n on the synchronous full-rub orbit, whose
    // normal force N = κ k (r − d) e gives the friction torque R μ N (R = 0.06 m) and
    // Ω̇ = −R μ N / J; the unbalance's reaction m_u e Ω² r e sin β adds 1e-3 of it.
    let (m, k, _, _) = rotor();
    let e = 0.008 * 0.045 / m;
    let d = 1.2;
    let ring = format!(
        "[[stator]]\nkind = \"ring\"\nname = \"ring\"\nstation = \"disk\"\nclearance = {:e}\nstiffness_ratio = 25.0\nkinematics = \"radial\"\n",
        d * e
    );
    let wn = (k / m).sqrt();
    let j = 0.02;
    let text = driven(
        &format!("unit = \"speed_ratio\"\nspeed = 1.0\nduration = 0.6\npolar_inertia = {j}"),
        &ring,
        true,
    );
    let (r0, b0) = annular(1.0, 25.0, 0.1, 0.2, d);
    let r = run_with(&text, &["run.samples_per_rev=400"], |s| {
        s.initial.u = [r0 * e * b0.cos(), -r0 * e * b0.sin()];
        s.initial.v = [wn * r0 * e * b0.sin(), wn * r0 * e * b0.cos()];
    });
    let torque_cf = |w: f64| {
        let (rr, _) = annular(w / wn, 25.0, 0.1, 0.2, d);
        0.06 * 0.1 * 25.0 * k * (rr - d) * e
    };
    // The unbalance's reaction on the orbit z = r e e^{i(φ − β)}: T_u = m_u e Ω² r e sin β.
    let reaction_cf = |w: f64| {
        let (rr, bb) = annular(w / wn, 25.0, 0.1, 0.2, d);
        0.008 * 0.045 * w * w * rr * e * bb.sin()
    };
    // The recorded friction torque against the closed form at the recorded speed.
    let mut worst_t: f64 = 0.0;
    for (s, t) in r.spin.iter().zip(&r.torque).filter(|(s, _)| s[0] > 0.1) {
        worst_t = worst_t.max((t[1] - torque_cf(s[1])).abs() / torque_cf(s[1]));
    }
    // The deceleration over [0.2, 0.6] s (a difference of Ω over whole intervals) against
    // the closed form's mean torque over J.
    let at = |t: f64| r.spin.iter().find(|s| s[0] >= t).unwrap();
    let (a, b) = (at(0.2), at(0.6));
    let decel = (a[1] - b[1]) / (b[0] - a[0]);
    let mean = |f: &dyn Fn(f64) -> f64| 0.5 * (f(a[1]) + f(b[1]));
    let friction_only = mean(&torque_cf) / j;
    let expected = friction_only + mean(&reaction_cf) / j;
    let rel = (decel - expected).abs() / expected;
    eprintln!(
        "coast-down: Ω {:.4} → {:.4} ωn, friction torque within {worst_t:.2e} of R μ κ k (r − d) e, Ω̇ = −{decel:.5} rad/s² vs −{expected:.5} (relative {rel:.2e}; the friction torque alone −{friction_only:.5})",
        a[1] / wn,
        b[1] / wn
    );
    assert!(
        r.stats.contact_steps as f64 > 0.99 * r.stats.steps as f64,
        "the rub must stay full"
    );
    assert!(
        worst_t < 5e-3,
        "friction torque off the closed form by {worst_t}"
    );
    assert!(rel < 2e-4, "deceleration off by {rel}");
    // The friction torque is 98 % of the braking; the unbalance's reaction the rest.
    assert!((friction_only / expected - 0.98).abs() < 0.005);
}

/// The energy terms of a driven run with every step recorded (J): drive work, the change of
/// the stored energy (lateral kinetic and elastic, the massless stator's elastic energy, the
/// spin's ½JΩ² and the unbalance's cross term), and the dissipation (rotor damping, drag,
/// friction). Velocities by central differences of the record, integrals by the trapezoid.
fn energy_residual(
    r: &TransientResults,
    drag: f64,
    ct: f64,
    rec: &rubsim::time::Record,
) -> (f64, f64) {
    let (m, k, c, j) = rotor();
    let me = 0.008 * 0.045;
    let n = r.spin.len();
    let dt = r.plan.dt;
    let v = |i: usize| {
        let (a, b) = (rec.observed[i - 1], rec.observed[i + 1]);
        [(b[0] - a[0]) / (2.0 * dt), (b[1] - a[1]) / (2.0 * dt)]
    };
    let stored = |i: usize| {
        let (u, vi, s) = (rec.observed[i], v(i), r.spin[i]);
        let (w, phi) = (s[1], s[2]);
        0.5 * m * (vi[0] * vi[0] + vi[1] * vi[1])
            + 0.5 * k * (u[0] * u[0] + u[1] * u[1])
            + rec.stator_energy[i]
            + 0.5 * j * w * w
            + me * w * (phi.cos() * vi[1] - phi.sin() * vi[0])
    };
    let power = |i: usize| {
        let (vi, s, t) = (v(i), r.spin[i], r.torque[i]);
        let w = s[1];
        let f = rec.force[i];
        let fnl = rec.force_normal[i];
        let ft = [f[0] - fnl[0], f[1] - fnl[1]];
        let drive = t[0] * w;
        let diss = c * (vi[0] * vi[0] + vi[1] * vi[1])
            + (drag + ct * w) * w
            + (t[1] * w - (ft[0] * vi[0] + ft[1] * vi[1]));
        (drive, diss)
    };
    let (mut work, mut diss) = (0.0, 0.0);
    for i in 2..n - 1 {
        let (a, b) = (power(i - 1), power(i));
        work += 0.5 * dt * (a.0 + b.0);
        diss += 0.5 * dt * (a.1 + b.1);
    }
    let residual = work - (stored(n - 2) - stored(1)) - diss;
    (residual / work, work)
}

#[test]
fn driven_run_with_rub_balances_its_energy() {
    // Run-up from 0.9 ω_n by 0.2 N·m against drag 0.01 N·m + 2e-4 N·m·s/rad × Ω, through the
    // paper's rod rub (δ = 0.6|Z0(ω_n)|, ε 25, μ 0.1), collocated scheme, every step recorded.
    let rod = &PAPER[PAPER.find("[[stator]]").unwrap()..PAPER.find("[run]").unwrap()];
    let text = driven(
        "unit = \"speed_ratio\"\nspeed = 0.9\nduration = 0.4\ndrive_torque = 0.2\ndrag_torque = 0.01\ndrag_coefficient = 2e-4\nreference = 1.0",
        rod,
        true,
    );
    let mut res = Vec::new();
    for n in [10_000usize, 20_000, 40_000] {
        let dt = format!("run.dt={:e}", 0.4 / n as f64);
        let sets = [
            dt.as_str(),
            "run.integrator=\"collocated\"",
            "run.samples_per_rev=1000000",
        ];
        let (ls, model) = scene_model(&text, &sets);
        let s = settings(&ls);
        let prep =
            prepare_transient(&model, &s, ls.scene.run.speed_profile.as_ref().unwrap()).unwrap();
        let (rec, stats) = prep.integrate(&mut []).unwrap();
        let r = rubsim::analysis::transient::analyse_transient(&prep, &rec, stats).unwrap();
        assert_eq!(r.plan.record_every, 1);
        assert!(
            r.stats.contact_steps > n / 20,
            "the run must rub: {}",
            r.stats.contact_steps
        );
        let (rel, work) = energy_residual(&r, 0.01, 2e-4, &rec);
        let fric: f64 = r.friction_energy;
        eprintln!("energy, {n} steps: drive work {work:.5e} J, friction {fric:.3e} J, residual {rel:.3e} of the work");
        res.push(rel.abs());
    }
    assert!(res.iter().all(|r| *r < 1e-6), "energy residuals {res:?}");
    assert!(
        res[2] < res[1] && res[1] < res[0],
        "the residual must shrink with Δt: {res:?}"
    );
}

/// Errors of φ and of the response at Δt = T/(n0·m), m = 1, 2, 4, 8, against m = 32.
fn driven_order(text: &str, integrator: &str, n0: usize, duration: f64) -> (f64, f64, usize) {
    let levels = [1usize, 2, 4, 8];
    let finest = 32usize;
    let go = |mult: usize| {
        let dt = format!("run.dt={:e}", duration / (n0 * mult) as f64);
        let integ = format!("run.integrator=\"{integrator}\"");
        run(
            text,
            &[dt.as_str(), integ.as_str(), "run.samples_per_rev=1000000"],
        )
    };
    let reference = go(finest);
    let (mut ephi, mut eu, mut contact) = (Vec::new(), Vec::new(), 0);
    for &m in &levels {
        let r = go(m);
        contact = contact.max(r.stats.contact_steps);
        let stride = finest / m;
        let mut a: f64 = 0.0;
        let mut b: f64 = 0.0;
        for (i, (s, u)) in r.spin.iter().zip(&r.response).enumerate() {
            let (sr, ur) = (reference.spin[i * stride], reference.response[i * stride]);
            a = a.max((s[2] - sr[2]).abs());
            b = b.max((u[0] - ur[0]).hypot(u[1] - ur[1]));
        }
        ephi.push(a);
        eu.push(b);
    }
    let h: Vec<f64> = levels.iter().map(|m| 1.0 / *m as f64).collect();
    eprintln!("{integrator}: φ errors {ephi:?}, response errors {eu:?}");
    (loglog_slope(&h, &ephi), loglog_slope(&h, &eu), contact)
}

#[test]
fn driven_scheme_is_second_order() {
    // A motor curve (falling torque over speed) with viscous drag and the unbalance's
    // reaction: Ω, Ω̇ and the unbalance force all follow the integrated spin.
    let profile = "unit = \"speed_ratio\"\nspeed = 0.8\nduration = 0.3\ndrive_curve = [[0.0, 1.5], [2.0, 0.5]]\ndrag_coefficient = 5e-4\nreference = 1.0";
    let free = driven(profile, "", true);
    let (pphi, pu, _) = driven_order(&free, "collocated", 1500, 0.3);
    eprintln!("driven, free: order φ {pphi:.3}, response {pu:.3}");
    assert!(
        (pphi - 2.0).abs() < 0.15 && (pu - 2.0).abs() < 0.15,
        "free: {pphi}, {pu}"
    );
    let rod = &PAPER[PAPER.find("[[stator]]").unwrap()..PAPER.find("[run]").unwrap()];
    let rub = driven(profile, rod, true);
    let (pphi, pu, c) = driven_order(&rub, "collocated", 1500, 0.3);
    eprintln!("driven, rub (collocated): order φ {pphi:.3}, response {pu:.3}, {c} contact steps");
    assert!(c > 100, "the run must rub: {c}");
    assert!(pphi > 1.7 && pu > 1.7, "rub: {pphi}, {pu}");
}

/// The error of `text`, which must fail to load; and the 1-based line starting with `needle`.
fn load_error(text: &str) -> String {
    rubsim::scene::parse(std::path::Path::new("t.toml"), text, &[])
        .expect_err("a bad driven profile loads")
        .to_string()
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.starts_with(needle)).unwrap() + 1
}

#[test]
fn bad_driven_profiles_name_the_key_and_line() {
    let base = "unit = \"speed_ratio\"\nspeed = 1.0\nduration = 1.0\n";
    let cases: &[(&str, &str, &str, &str)] = &[
        // (keys after the base, key in the message, what it says, the line's start)
        (
            "drive_torque = 1.0\ndrive_curve = [[0.0, 1.0], [1.0, 0.0]]",
            "run.speed_profile.drive_curve",
            "not both",
            "drive_curve = ",
        ),
        (
            "drive_curve = [\n  [0.0, 1.0],\n  [2.0, 0.5],\n  [1.0, 0.0],\n]",
            "run.speed_profile.drive_curve.2",
            "increase strictly",
            "  [1.0, 0.0]",
        ),
        (
            "drive_torque = 1.0\ndrive_off = 2.0",
            "run.speed_profile.drive_off",
            "a time in the run",
            "drive_off = ",
        ),
        (
            "drive_off = 0.5",
            "run.speed_profile.drive_off",
            "no drive to switch off",
            "drive_off = ",
        ),
        (
            "drag_torque = -0.1",
            "run.speed_profile.drag_torque",
            "zero or positive",
            "drag_torque = ",
        ),
        (
            "polar_inertia = 0.0",
            "run.speed_profile.polar_inertia",
            "positive",
            "polar_inertia = ",
        ),
        (
            "drive_torque = nan",
            "run.speed_profile.drive_torque",
            "finite",
            "drive_torque = ",
        ),
        (
            "hold = 1.0",
            "run.speed_profile.hold",
            "does not apply",
            "hold = ",
        ),
    ];
    for (keys, key, what, line) in cases {
        let text = driven(&format!("{base}{keys}"), "", true);
        let e = load_error(&text);
        let at = format!("t.toml:{}: key `{key}`", line_of(&text, line));
        assert!(
            e.contains(&at) && e.contains(what),
            "expected `{at}` … `{what}`, got: {e}"
        );
    }
    // A driven key in a prescribed profile.
    let text = PAPER.replace(
        "[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1",
        "[run.speed_profile]\nkind = \"constant\"\nunit = \"rpm\"\nspeed = 1000.0\nduration = 1.0\ndrive_torque = 1.0",
    );
    let e = load_error(&text);
    assert!(
        e.contains("run.speed_profile.drive_torque") && e.contains("does not apply"),
        "{e}"
    );
    // A Jeffcott rotor given by its mass has no inertia: refused, naming the key and the table.
    let text = driven(base, "", true).replace(
        "disk = { diameter = 0.12, thickness = 0.03, density = 7800.0 }",
        "mass = 2.646",
    );
    let e = load_error(&text);
    let at = format!(
        "t.toml:{}: key `run.speed_profile`",
        line_of(&text, "[run.speed_profile]")
    );
    assert!(e.contains(&at) && e.contains("polar_inertia"), "{e}");
    // … and accepted with `polar_inertia`.
    let ok = text.replace(
        "kind = \"driven\"\n",
        "kind = \"driven\"\npolar_inertia = 0.005\n",
    );
    let r = run(&ok, &[]);
    // Without drive the unbalance's reaction brakes it by the power its whirl dissipates:
    // T_u = m_u e Ω² |Z0| sin(lag), |Z0| = e ν²/D, sin(lag) = 2ξν/D, D = |1 − ν² + 2iξν|.
    let last = r.spin.last().unwrap();
    let (m, ..) = rotor();
    let (me, nu) = (0.008 * 0.045, last[1] / r.omega_n);
    let dd = ((1.0 - nu * nu).powi(2) + (0.4 * nu).powi(2)).sqrt();
    let tu = me * last[1] * last[1] * (me / m) * nu * nu / dd * (0.4 * nu / dd);
    let rel = (last[3] + tu / 0.005).abs() / (tu / 0.005);
    eprintln!(
        "unbalance braking: Ω̇ = {:.5} rad/s² vs −{:.5} (relative {rel:.2e})",
        last[3],
        tu / 0.005
    );
    assert!(rel < 0.01, "unbalance braking off by {rel}");
}
