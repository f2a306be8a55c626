//! ROSS's element and model options in rubsim's FE rotor: rotary inertia and gyroscopics as
//! separate switches, Rayleigh damping on the shaft elements only, free (unsupported) axial and
//! torsional DOFs with their rigid-body modes — checked against closed forms.

use crate::common;

use common::fe::fe;
use common::scenes::{FRISWELL, PAPER_TORSION};
use common::{model, run_speed, SHORT_RUN};
use rubsim::linear::{self, ModeKind, Whirl};
use rubsim::model::fe_rotor::{dense, undamped_modes};
use std::f64::consts::PI;

/// A uniform steel shaft, 1.5 m × 50 mm in `n` elements on 1 MN/m bearings at the ends, with
/// the `[rotor]` keys `keys` (no disks).
fn bare_shaft(n: usize, keys: &str) -> String {
    format!(
        r#"
[rotor]
kind = "fe"
{keys}
[[rotor.shaft]]
length = 1.5
outer_diameter = 0.05
elements = {n}
youngs_modulus = 211e9
poisson = 0.3
density = 7810.0
[[rotor.bearing]]
node = 0
stiffness = 1.0e6
[[rotor.bearing]]
node = {n}
stiffness = 1.0e6
[run]
speed_ratio = 1.0
"#
    )
}

/// FW − BW of the first pair at 4000 rpm.
fn first_split(text: &str) -> f64 {
    let m = model(text);
    let r = linear::modal(&m.rotor, 4000.0 * PI / 30.0, 4).unwrap();
    let f = |w: Whirl| r.modes.iter().find(|x| x.whirl == w).unwrap().omega_d;
    f(Whirl::Forward) - f(Whirl::Backward)
}

/// ROSS's switches: without rotary inertia the shaft keeps its gyroscopic matrix (the first
/// pair still splits with the spin, by the same order of amplitude), `gyroscopic = false`
/// removes it; the rotary inertia is gone from M (the rest frequency rises).
#[test]
fn rotary_inertia_and_gyroscopics_are_separate_switches() {
    let both = first_split(&bare_shaft(12, ""));
    let no_rot = first_split(&bare_shaft(12, "rotary_inertia = false"));
    let no_gyro = first_split(&bare_shaft(12, "gyroscopic = false"));
    eprintln!("FW − BW at 4000 rpm: {both:.6} (both), {no_rot:.6} (no rotary inertia), {no_gyro:.3e} (no G)");
    assert!(both > 1e-3 && no_rot > 1e-3);
    assert!((no_rot / both - 1.0).abs() < 0.05, "{no_rot} vs {both}");
    assert!(
        no_gyro.abs() < 1e-6 * both,
        "round-off of a double eigenvalue only"
    );
    let w = |t: &str| fe(&model(t).rotor).rotor.lateral_frequencies(0.0).unwrap()[0];
    assert!(w(&bare_shaft(12, "rotary_inertia = false")) > w(&bare_shaft(12, "")));
    // G itself is the same matrix with or without the rotary inertia.
    let g = |t: &str| dense(&fe(&model(t).rotor).rotor.g);
    assert_eq!(
        g(&bare_shaft(6, "rotary_inertia = false")),
        g(&bare_shaft(6, ""))
    );
}

/// Rayleigh damping on the shaft elements only (ROSS's convention): to first order in the
/// damping, mode i of the undamped problem gets ζᵢ = φᵢᵀ C φᵢ / (2ωᵢ) with the mass-normalised
/// φᵢ, C = Σ_e (α M_e + β K_e) — the disks' mass and the bearings' stiffness left out — while
/// the assembly's Rayleigh damping gives ζᵢ = (α/ωᵢ + β ωᵢ)/2 exactly.
#[test]
fn rayleigh_on_the_shaft_only_damps_by_the_shaft_energy() {
    let (alpha, beta) = (0.5, 2.0e-6);
    let text = FRISWELL.replace(
        "kind = \"fe\"",
        &format!("kind = \"fe\"\nrayleigh = [{alpha}, {beta}]"),
    );
    let shaft_text = text.replace("kind = \"fe\"", "kind = \"fe\"\nrayleigh_on = \"shaft\"");
    let (m_asm, m_shaft) = (model(&text), model(&shaft_text));
    let f = &fe(&m_shaft.rotor).rotor;
    let (lam, phi) = undamped_modes(&f.m, &f.k(0.0)).unwrap();
    let cs = dense(f.rayleigh_part.as_ref().unwrap());
    let r_asm = linear::modal(&m_asm.rotor, 0.0, 6).unwrap();
    let r_shaft = linear::modal(&m_shaft.rotor, 0.0, 6).unwrap();
    for (i, l) in lam.iter().enumerate().take(6) {
        let w = l.sqrt();
        let p = phi.column(i);
        let zeta = (p.transpose() * &cs * p)[(0, 0)] / (2.0 * w);
        let (za, zs) = (r_asm.modes[i].damping_ratio, r_shaft.modes[i].damping_ratio);
        let exact = 0.5 * (alpha / w + beta * w);
        eprintln!("mode {}: ω {w:.4}, ζ assembly {za:.6e} (closed form {exact:.6e}), shaft only {zs:.6e} (first order {zeta:.6e})", i + 1);
        assert!((za / exact - 1.0).abs() < 1e-5, "mode {i}: {za} vs {exact}");
        assert!((zs / zeta - 1.0).abs() < 2e-3, "mode {i}: {zs} vs {zeta}");
        assert!(
            zs < 0.9 * za,
            "the disks' α M and the bearings' β K are left out"
        );
    }
}

/// Free axial and torsional DOFs (no support, or ROSS's kzz = 0): one rigid-body mode each,
/// reported as such; the elastic modes are those of a free–free bar and shaft in torsion,
/// which a uniform mesh of linear elements with consistent mass reproduces exactly on its own
/// dispersion relation ω_h² = (c/h)² · 6(1 − cos kh)/(2 + cos kh), k = jπ/L.
#[test]
fn free_axial_and_torsional_dofs_have_rigid_body_modes() {
    let n = 12;
    let text = bare_shaft(
        n,
        "axial = true\ntorsion = true\ngyroscopic = false\n[[rotor.axial_support]]\nnode = 0\nstiffness = 0.0\ndamping = 0.0",
    );
    let m = model(&text);
    let f = &fe(&m.rotor).rotor;
    assert!(f.free_axial && f.free_torsion);
    let r = linear::modal(&m.rotor, 0.0, 40).unwrap();
    assert_eq!(r.rigid_body, vec![ModeKind::Axial, ModeKind::Torsional]);
    let (e, nu, rho, l): (f64, f64, f64, f64) = (211e9, 0.3, 7810.0, 1.5);
    let h = l / n as f64;
    let discrete = |c: f64, j: usize| {
        let kh = j as f64 * PI / l * h;
        (c / h) * (6.0 * (1.0 - kh.cos()) / (2.0 + kh.cos())).sqrt()
    };
    for (kind, c) in [
        (ModeKind::Axial, (e / rho).sqrt()),
        (ModeKind::Torsional, (e / (2.0 * (1.0 + nu)) / rho).sqrt()),
    ] {
        let got: Vec<f64> = r
            .modes
            .iter()
            .filter(|x| x.kind == kind)
            .map(|x| x.omega_d)
            .collect();
        assert!(got.len() >= 2, "{kind:?}: {got:?}");
        for (j, w) in got.iter().take(2).enumerate() {
            let want = discrete(c, j + 1);
            eprintln!(
                "free–free {kind:?} mode {}: {w:.6} rad/s, discrete closed form {want:.6}",
                j + 1
            );
            assert!((w / want - 1.0).abs() < 1e-8, "{kind:?} {j}: {w} vs {want}");
        }
    }
    // The lateral analyses solve the lateral block: no singular K.
    assert!(linear::static_deflection(&m.rotor, 9.81).is_ok());
    let held = model(&bare_shaft(n, "gyroscopic = false"));
    let w_held = fe(&held.rotor).rotor.lateral_frequencies(0.0).unwrap();
    let lateral: Vec<f64> = r
        .modes
        .iter()
        .filter(|x| x.kind == ModeKind::Lateral)
        .map(|x| x.omega_d)
        .collect();
    for (a, b) in lateral.iter().zip(&w_held).take(4) {
        assert!((a / b - 1.0).abs() < 1e-8);
    }
}

/// The time loop with free, unloaded axial and torsional DOFs (the paper's FE rotor rubbing
/// the rod without friction, drive coupling of zero stiffness): it steps, and the lateral
/// response is that of the rotor with a drive (the groups are uncoupled).
#[test]
fn free_unloaded_dofs_do_not_break_the_time_loop() {
    // Held: the same DOFs on springs too soft to change the step (ω_max) or anything lateral.
    let with = |k: &str| {
        PAPER_TORSION
            .replace("torsion = true", "torsion = true\naxial = true")
            .replace("stiffness = 1000.0", &format!("stiffness = {k}"))
            .replace(
                "[[rotor.unbalance]]",
                &format!("[[rotor.axial_support]]\nnode = 0\nstiffness = {k}\n[[rotor.unbalance]]"),
            )
    };
    let mut sets = SHORT_RUN.to_vec();
    sets.push("station.0.friction=0.0");
    let a = run_speed(&with("0.0"), &sets, 1.7);
    let b = run_speed(&with("1e-6"), &sets, 1.7);
    eprintln!(
        "Δt {} / {}; extents free {:?}, held {:?}",
        a.plan.dt, b.plan.dt, a.extents_nd, b.extents_nd
    );
    assert_eq!(a.plan.dt, b.plan.dt);
    for k in 0..4 {
        assert!(a.extents_nd[k].is_finite());
        assert!((a.extents_nd[k] - b.extents_nd[k]).abs() < 1e-8);
    }
}
