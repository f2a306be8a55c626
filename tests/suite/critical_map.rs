//! The undamped critical speed map (`rubsim critical-map`, `linear::critical_map`) against
//! closed forms at its two ends (docs/VALIDATION.md, "Undamped critical speed map"): a uniform
//! slender shaft on very stiff bearings has the pinned-pinned beam's critical speeds
//! (Euler–Bernoulli; with shear, rotary inertia and gyroscopics the synchronous forward
//! Timoshenko root), on very soft bearings the rigid-body bounce √(2k/m) and rocking modes.

use crate::common;

use common::cli::{is_png, ok};
use common::{model, repo};
use rubsim::linear::{critical_map, log_range, Swept};
use std::f64::consts::PI;

/// Steel shaft 1 m × 20 mm (L/D = 50), 40 elements, bearings at both ends.
const L: f64 = 1.0;
const D: f64 = 0.02;
const E: f64 = 2.1e11;
const NU: f64 = 0.3;
const RHO: f64 = 7800.0;

fn shaft(switches: &str) -> String {
    format!(
        r#"
title = "uniform shaft"
[rotor]
kind = "fe"
{switches}
[[rotor.shaft]]
length = {L}
outer_diameter = {D}
elements = 40
youngs_modulus = {E}
poisson = {NU}
density = {RHO}
[[rotor.bearing]]
node = 0
kxx = 1e6
kyy = 1e6
[[rotor.bearing]]
node = 40
kxx = 1e6
kyy = 1e6
[run]
speed_ratio = 1.0
"#
    )
}

fn area() -> f64 {
    PI * D * D / 4.0
}
fn inertia() -> f64 {
    PI * D.powi(4) / 64.0
}

/// Pinned-pinned Euler–Bernoulli: Ω_n = (nπ/L)² √(EI/ρA).
fn euler_bernoulli(n: usize) -> f64 {
    (n as f64 * PI / L).powi(2) * (E * inertia() / (RHO * area())).sqrt()
}

/// Pinned-pinned Timoshenko beam in forward synchronous whirl: with `w = W sin kz`,
/// `ψ = Ψ cos kz`, `k = nπ/L`, `s = κGA` and the rotary inertia per length
/// `J = ρI − ρI_p Ω/ω = −ρI` at ω = Ω (I_p = 2I), the root of
/// `(ρAω² − s k²)(Jω² − EIk² − s) − s²k² = 0` (one positive ω² since J < 0).
fn timoshenko_forward(n: usize) -> f64 {
    let k = n as f64 * PI / L;
    let g = E / (2.0 * (1.0 + NU));
    let kappa = 6.0 * (1.0 + NU) / (7.0 + 6.0 * NU);
    let s = kappa * g * area();
    let (ra, ei, j) = (RHO * area(), E * inertia(), -RHO * inertia());
    let a = ra * j;
    let b = ra * (-ei * k * k - s) - s * k * k * j;
    let c = s * ei * k.powi(4);
    let w2 = (-b - (b * b - 4.0 * a * c).sqrt()) / (2.0 * a);
    w2.sqrt()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn stiff_bearings_give_the_pinned_pinned_euler_bernoulli_critical_speeds() {
    let m = model(&shaft(
        "shear = false\nrotary_inertia = false\ngyroscopic = false",
    ));
    let res = critical_map(&m.rotor, &[1e13], Swept::All, 3).unwrap();
    let c = &res.speeds[0];
    for n in 1..=3 {
        let exact = euler_bernoulli(n);
        let e = rel(c.forward[n - 1], exact);
        assert!(
            e < 2e-5,
            "mode {n}: {} vs {exact} ({e:.2e})",
            c.forward[n - 1]
        );
        // Without gyroscopics both whirls share the critical speed.
        assert!(rel(c.backward[n - 1], exact) < 2e-5, "backward {n}");
    }
}

#[test]
fn stiff_bearings_with_shear_rotary_inertia_and_gyroscopics_give_the_timoshenko_root() {
    let m = model(&shaft(""));
    let res = critical_map(&m.rotor, &[1e13], Swept::All, 3).unwrap();
    let c = &res.speeds[0];
    for n in 1..=3 {
        let exact = timoshenko_forward(n);
        let e = rel(c.forward[n - 1], exact);
        assert!(
            e < 2e-5,
            "mode {n}: {} vs {exact} ({e:.2e})",
            c.forward[n - 1]
        );
        // The correction is what the test resolves: larger than the tolerance.
        let shift = rel(exact, euler_bernoulli(n));
        assert!(
            shift > 5.0 * e,
            "mode {n}: correction {shift:.2e} vs error {e:.2e}"
        );
        // Gyroscopic stiffening: the backward critical speed is lower.
        assert!(c.backward[n - 1] < c.forward[n - 1], "mode {n}");
    }
}

#[test]
fn soft_bearings_give_the_rigid_body_bounce_and_rocking_modes() {
    let k = 1.0;
    let mass = RHO * area() * L;
    let r = D / 2.0;
    // Euler–Bernoulli shaft without rotary inertia: I_d = mL²/12, rocking √(6k/m).
    let m = model(&shaft(
        "shear = false\nrotary_inertia = false\ngyroscopic = false",
    ));
    let c = &critical_map(&m.rotor, &[k], Swept::All, 2).unwrap().speeds[0];
    // The shaft's own flexibility (k ≪ 48EI/L³ = 7.9e4 N/m) shifts them by ≤ 5.6e-6.
    let bounce = (2.0 * k / mass).sqrt();
    let rocking = (6.0 * k / mass).sqrt();
    assert!(
        rel(c.forward[0], bounce) < 1e-5,
        "{} vs {bounce}",
        c.forward[0]
    );
    assert!(
        rel(c.forward[1], rocking) < 2e-5,
        "{} vs {rocking}",
        c.forward[1]
    );
    // With rotary inertia and gyroscopics: k L²/2 = Ω² (I_d ∓ I_p), I_d = m(L²/12 + r²/4),
    // I_p = m r²/2 — forward lower inertia, higher speed.
    let m = model(&shaft(""));
    let c = &critical_map(&m.rotor, &[k], Swept::All, 2).unwrap().speeds[0];
    let (id, ip) = (mass * (L * L / 12.0 + r * r / 4.0), mass * r * r / 2.0);
    let fw = (k * L * L / 2.0 / (id - ip)).sqrt();
    let bw = (k * L * L / 2.0 / (id + ip)).sqrt();
    assert!(
        rel(c.forward[0], bounce) < 1e-5,
        "{} vs {bounce}",
        c.forward[0]
    );
    assert!(rel(c.forward[1], fw) < 2e-5, "{} vs {fw}", c.forward[1]);
    assert!(rel(c.backward[1], bw) < 2e-5, "{} vs {bw}", c.backward[1]);
}

#[test]
fn one_named_bearing_and_the_bearing_lines_cross_at_the_rotor_critical_speed() {
    let m = model(&shaft(
        "shear = false\nrotary_inertia = false\ngyroscopic = false",
    ));
    let ks = log_range(1e4, 1e8, 41);
    let all = critical_map(&m.rotor, &ks, Swept::All, 2).unwrap();
    // The scene's bearings (1 MN/m, constant) cross the first forward curve where the map at
    // k = 1e6 (a grid point) is.
    let at = all.speeds[20].forward[0];
    assert!((ks[20] / 1e6 - 1.0).abs() < 1e-12);
    let x = all
        .crossings
        .iter()
        .find(|x| x.mode == 1 && x.bearing.contains("kxx"))
        .expect("a crossing");
    assert!(
        rel(x.stiffness, 1e6) < 1e-9 && rel(x.speed, at) < 1e-3,
        "{x:?} vs {at}"
    );
    // Sweeping one bearing lies between all soft and all stiff.
    let one = critical_map(&m.rotor, &[1e4], Swept::One(1), 1).unwrap();
    assert!(one.speeds[0].forward[0] > all.speeds[0].forward[0]);
    assert!(one.speeds[0].forward[0] < at);
    assert!(critical_map(&m.rotor, &[1e4], Swept::One(2), 1).is_err());
}

#[test]
fn the_command_writes_the_map_and_refuses_a_bad_range() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("cm");
    let scene = repo("scenes/fe/ross_rotor_example.toml");
    let o = out.to_str().unwrap();
    let s = scene.to_str().unwrap();
    let text = ok(
        &repo("."),
        &[
            "critical-map",
            s,
            "--from",
            "1e5",
            "--to",
            "1e9",
            "--points",
            "9",
            "--out",
            o,
        ],
    );
    assert!(text.contains("crosses forward mode 1"), "{text}");
    let csv = std::fs::read_to_string(out.join("critical_map.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 10);
    assert!(lines[0].starts_with("stiffness_n_m,forward_1_rad_s"));
    assert!(is_png(&out.join("critical_map.png")));
    let e = common::cli::fails(&repo("."), &["critical-map", s, "--from", "0", "--out", o]);
    assert!(e.contains("--from 0"), "{e}");
}

/// The uniform shaft without gyroscopics at rest has double eigenvalues, whose modal solve
/// rotates each pair into its forward and backward combinations: those are normalised like
/// every other mode (largest entry exactly 1), as `mode_shapes.csv` and the VTK/HDF5 mode files
/// say (docs/OUTPUTS.md).
#[test]
fn modal_shapes_of_split_degenerate_pairs_keep_their_largest_entry_one() {
    use rubsim::linear::{modal, Whirl};
    let m = model(&shaft("gyroscopic = false"));
    let res = modal(&m.rotor, 0.0, 4).unwrap();
    let whirls: Vec<Whirl> = res.modes.iter().map(|x| x.whirl).collect();
    assert!(
        whirls.contains(&Whirl::Forward) && whirls.contains(&Whirl::Backward),
        "{whirls:?}"
    );
    for md in &res.modes {
        let big = md
            .shape
            .iter()
            .flatten()
            .fold(num_complex::Complex64::new(0.0, 0.0), |b, v| {
                if v.norm() > b.norm() {
                    *v
                } else {
                    b
                }
            });
        assert!((big - 1.0).norm() < 1e-12, "{big}");
    }
}
