//! The contact dashpot (`stator.N.contact_damping`, issue 15 item 3): restitution of a bounce
//! against the closed form of a mass–spring–dashpot impact, the energy a persistent full
//! annular rub dissipates against `∫ c v² dt` and the closed-form steady orbit, in every
//! scheme; bad input refused with its key.

use crate::common;

use common::*;
use rubsim::time::{plan_steps, Initial, Scheme, StepParams, Stepper, MAX_STEPS};

const SCHEMES: [Scheme; 4] = [
    Scheme::ForwardIncrement,
    Scheme::Collocated,
    Scheme::Newmark,
    Scheme::GeneralizedAlpha { rho_inf: 0.8 },
];

/// A 1 kg rotor on a 1 N/m shaft (its spring negligible over an impact) starting at the
/// centre with 0.1 m/s toward a frictionless massless ring on 10⁶ N/m springs 0.1 mm away:
/// contact frequency ω_c = 1000 rad/s, contact time π/ω_d ≈ 3 ms.
const BOUNCE: &str = r#"
title = "bounce"
[rotor]
kind = "jeffcott"
mass = 1.0
stiffness = 1.0
damping = 0.0
[[station]]
name = "s"
radius = 0.1
friction = 0.0
[[stator]]
kind = "ring"
name = "ring"
station = "s"
clearance = 1.0e-4
stiffness = 1.0e6
[run]
speed_ratio = 1000.0
revolutions = 1
transient_revolutions = 0
error_estimate = false
"#;

/// Velocity of station 0 along y after the bounce (m/s) and the dashpot's energy (J) with
/// `contact_damping = c` in `scheme` at `dt`.
fn bounce(c: f64, mode: &str, scheme: Scheme, dt: f64) -> (f64, f64, f64) {
    let sets = [
        format!("stator.0.contact_damping={c}"),
        format!("stator.0.contact_damping_mode=\"{mode}\""),
    ];
    let (_, model) = scene_model(BOUNCE, &sets);
    let case = model
        .case(model.rotor.natural_frequency() * 1000.0)
        .unwrap();
    let step = StepParams {
        integrator: scheme,
        dt: Some(dt),
        duration: None,
        harmonics: 4.0,
        revolutions: 1,
        transient_revolutions: 0,
        samples_per_rev: 1_000_000,
        max_steps: MAX_STEPS,
        dt_scale: 1.0,
    };
    let plan = plan_steps(&case, &step).unwrap();
    let v0 = 0.1;
    let init = Initial {
        u: [0.0; 2],
        v: [0.0, v0],
    };
    let st = Stepper::new(&case, scheme, &plan, init).unwrap();
    let (rec, stats) = st.run(None).unwrap();
    // Leaving velocity: the slope of y over the free flight after the first contact (the
    // shaft's 1 N/m changes it by < 1e-5 over it).
    let touching = |i: usize| rec.force_at(i, 0)[1] != 0.0;
    let first = (0..rec.len()).find(|&i| touching(i)).expect("no contact");
    let left = (first..rec.len())
        .find(|&i| !touching(i))
        .expect("no release")
        + 2;
    let back = (left..rec.len()).find(|&i| touching(i)).expect("no return") - 2;
    let y = |i: usize| rec.disp_at(i, 0)[1];
    let v1 = (y(back) - y(left)) / (rec.t[back] - rec.t[left]);
    assert!(
        v1 < 0.0,
        "{scheme:?}: the rotor did not come back ({v1} m/s)"
    );
    // The energy the rotor and ring lost over the whole run (several bounces): kinetic from
    // the last two samples (one per step), the shaft's and the ring's elastic energy.
    let last = rec.len() - 1;
    let vy = (y(last) - y(last - 1)) / (rec.t[last] - rec.t[last - 1]);
    let e_end = 0.5 * vy * vy + 0.5 * y(last) * y(last) + rec.stator_energy[last];
    (v1, stats.dashpot_energy, 0.5 * v0 * v0 - e_end)
}

#[test]
#[ignore = "slow tier (scripts/test-slow.sh): a convergence study of the impact"]
fn a_bounce_has_the_restitution_of_a_mass_spring_dashpot_impact() {
    let (m, k) = (1.0_f64, 1.0e6_f64);
    for zeta in [0.05, 0.2] {
        let c = 2.0 * zeta * (k * m).sqrt();
        // Linear spring–dashpot in parallel, contact while the penetration is positive:
        // e = exp(−ζπ/√(1−ζ²)).
        let e_exact = (-zeta * std::f64::consts::PI / (1.0 - zeta * zeta).sqrt()).exp();
        for scheme in SCHEMES {
            let dt = if scheme.implicit().is_some() {
                2e-6
            } else {
                1e-6
            };
            let (v1, ed, lost) = bounce(c, "normal", scheme, dt);
            let e = -v1 / 0.1;
            eprintln!(
                "ζ {zeta}, {scheme:?}: e = {e:.5} (closed form {e_exact:.5}); dashpot energy {ed:.4e} J, kinetic energy lost {lost:.4e} J"
            );
            assert!(
                (e - e_exact).abs() < 2e-3 * e_exact,
                "{scheme:?} ζ {zeta}: e {e} against {e_exact}"
            );
            // What the rotor lost over the run is what the dashpot took (measured: equal to
            // 4 digits in every scheme, e to 5 digits).
            assert!(
                (ed - lost).abs() < 1e-3 * lost,
                "{scheme:?} ζ {zeta}: dashpot {ed} J, lost {lost} J"
            );
        }
    }
    // Without the dashpot the bounce is elastic (to the scheme's impact error).
    let (v1, ed, _) = bounce(0.0, "normal", Scheme::Collocated, 1e-6);
    assert!((v1 + 0.1).abs() < 1e-3 && ed == 0.0, "{v1} {ed}");
}

/// A Jeffcott rotor (ω_n = 1 rad/s, ξ = 0.05) with an unbalance forcing it into a ring
/// (massless, k_s = 4 k_r, μ = 0.1) at 0.9 ω_n: synchronous full annular rub, a circular
/// orbit of radius R that touches the ring all the time.
const RUB: &str = r#"
title = "full annular rub"
[rotor]
kind = "jeffcott"
mass = 1.0
stiffness = 1.0
damping_ratio = 0.05
[[rotor.unbalance]]
mass = 1.0
radius = 1.0e-3
[[station]]
name = "s"
radius = 0.1
friction = 0.1
[[stator]]
kind = "ring"
name = "ring"
station = "s"
clearance = 1.0e-3
stiffness_ratio = 4.0
kinematics = "radial"
[run]
speed_ratio = 0.9
revolutions = 120
transient_revolutions = 100
samples_per_rev = 256
error_estimate = false
"#;

/// The steady radius of synchronous full annular rub: `|A R − B| = F` with
/// `A = k − mω² + k_s + i((c_r + c_d)ω + μ k_s)`, `B = k_s δ (1 + iμ)`, F = m_u e ω² (the force
/// on the rotor −(n + μa) k_s (R − δ) − a c_d ωR, n = e^{iωt}, a = i n); the root above δ.
fn closed_form_radius(cd: f64) -> f64 {
    let (m, k, ks, delta, mu, w) = (1.0_f64, 1.0, 4.0, 1e-3, 0.1, 0.9);
    let cr = 2.0 * 0.05 * (k * m).sqrt();
    let f = 1e-3 * w * w;
    let (ar, ai) = (k - m * w * w + ks, (cr + cd) * w + mu * ks);
    let (br, bi) = (ks * delta, ks * delta * mu);
    // |A|² R² − 2 Re(A B̄) R + |B|² − F² = 0
    let a2 = ar * ar + ai * ai;
    let ab = ar * br + ai * bi;
    let disc = ab * ab - a2 * (br * br + bi * bi - f * f);
    (ab + disc.sqrt()) / a2
}

#[test]
fn a_persistent_rub_dissipates_c_v_squared_in_the_full_mode_and_nothing_normal() {
    let cd = 0.3;
    let r_free = closed_form_radius(0.0);
    let r_exact = closed_form_radius(cd);
    assert!(
        r_exact > 1e-3 && r_free > r_exact * 1.02,
        "{r_free} {r_exact}"
    );
    for scheme in SCHEMES {
        for (mode, r_want) in [("full", r_exact), ("normal", r_free)] {
            let sets = [
                format!("stator.0.contact_damping={cd}"),
                format!("stator.0.contact_damping_mode=\"{mode}\""),
            ];
            let (ls, model) = scene_model(RUB, &sets);
            let (case, plan) = case_and_plan(&ls, &model, 0.9, scheme);
            let st = Stepper::new(&case, scheme, &plan, Initial::default()).unwrap();
            let (rec, stats) = st.run(None).unwrap();
            let from = rec.len() - 20 * 256;
            let radius: Vec<f64> = (from..rec.len())
                .map(|i| {
                    let d = rec.disp_at(i, 0);
                    d[0].hypot(d[1])
                })
                .collect();
            let (rmin, rmax) = radius
                .iter()
                .fold((f64::INFINITY, 0.0_f64), |(a, b), r| (a.min(*r), b.max(*r)));
            eprintln!(
                "{scheme:?} {mode}: R {rmin:.6e} … {rmax:.6e} (closed form {r_want:.6e}); dashpot energy {:.4e} J",
                stats.dashpot_energy
            );
            assert!(rmax - rmin < 1e-3 * r_want, "not a circular orbit");
            assert!(
                (rmax - r_want).abs() < 2e-3 * r_want,
                "{scheme:?} {mode}: R {rmax} against {r_want}"
            );
            // In steady full rub the section's speed is ωR, tangential: over the last 20
            // revolutions the full dashpot takes c (ωR)² × 20 T, the normal one nothing (a
            // circular orbit has no normal velocity).
            let w = 0.9;
            let period = 2.0 * std::f64::consts::PI / w;
            let want = cd * (w * r_exact).powi(2) * 20.0 * period;
            let steps_before = plan.steps - (20.0 * period / plan.dt).round() as usize;
            let got = stats.dashpot_energy - dashpot_until(&case, scheme, &plan, steps_before);
            eprintln!(
                "{scheme:?} {mode}: over 20 revolutions {got:.6e} J, c (ωR)² 20T = {want:.6e} J, {} steps/rev",
                plan.steps_per_rev
            );
            if mode == "full" {
                assert!(
                    (got - want).abs() < 1e-2 * want,
                    "{scheme:?}: dashpot took {got} J over 20 revolutions, c ∫v² dt = {want} J"
                );
            } else {
                assert!(
                    got.abs() < 1e-4 * want,
                    "{scheme:?}: normal dashpot took {got} J"
                );
            }
        }
    }
}

/// The dashpot energy of the same run stopped after `steps` steps.
fn dashpot_until(
    case: &rubsim::model::Case,
    scheme: Scheme,
    plan: &rubsim::time::StepPlan,
    steps: usize,
) -> f64 {
    let mut p = *plan;
    p.steps = steps;
    p.steady_from = p.steady_from.min(steps);
    let st = Stepper::new(case, scheme, &p, Initial::default()).unwrap();
    st.run(None).unwrap().1.dashpot_energy
}

#[test]
fn bad_contact_damping_is_refused_with_its_key() {
    let bad = |sets: &[&str], want: &str| {
        let text = BOUNCE.to_string();
        let sets_owned: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let ls = rubsim::scene::parse(std::path::Path::new("bad.toml"), &text, &sets_owned);
        let err = match ls {
            Err(e) => e.to_string(),
            Ok(ls) => match rubsim::model::Model::from_scene(&ls) {
                Err(e) => e.to_string(),
                Ok(_) => panic!("{sets:?} accepted"),
            },
        };
        assert!(err.contains(want), "{sets:?}: {err}");
        assert!(err.contains("bad.toml"), "{sets:?}: no file in {err}");
    };
    bad(
        &["stator.0.contact_damping=-1.0"],
        "stator.0.contact_damping",
    );
    bad(
        &[
            "stator.0.contact_damping=1.0",
            "stator.0.contact_damping_mode=\"tangent\"",
        ],
        "stator.0.contact_damping_mode",
    );
    // A stator with mass: refused, and the key named.
    bad(
        &["stator.0.contact_damping=1.0", "stator.0.mass=0.1"],
        "stator.0.contact_damping",
    );
    // The massless ring's support `damping` points to `contact_damping`.
    bad(&["stator.0.damping=1.0"], "contact_damping");
}
