//! Verification against closed-form results (ORACLES.md) and the paper's case.

use rubsim::analysis::{self, Keep, RunSettings};
use rubsim::model::Model;
use rubsim::scene::{self, LoadedScene};
use rubsim::time::Scheme;
use rubsim::time::{integrate, plan_steps, Initial, Record};
use std::path::Path;

const PAPER: &str = include_str!("../scenes/paper/partial_rub.toml");

fn load(text: &str, ov: &[&str]) -> (LoadedScene, Model) {
    let ov: Vec<String> = ov.iter().map(|s| s.to_string()).collect();
    let ls = scene::parse(Path::new("test.toml"), text, &ov).expect("scene");
    let m = Model::from_scene(&ls).expect("model");
    (ls, m)
}

fn settings(ls: &LoadedScene) -> RunSettings {
    RunSettings::from_run(&ls.scene.run, &ls.scene.output.component)
}

/// Jeffcott rotor with m = 1 kg, k = 1 N/m (ω_n = 1 rad/s), unbalance m_u e = 1e-3 kg·m
/// (e = 1e-3 m), optional ring stator.
fn unit_rotor(xi: f64, ring: &str) -> String {
    format!(
        r#"
[rotor]
kind = "jeffcott"
mass = 1.0
stiffness = 1.0
damping_ratio = {xi}
[[rotor.unbalance]]
mass = 1.0e-3
radius = 1.0
[[station]]
name = "s"
radius = 0.05
friction = 0.1
{ring}
[run]
speed_ratio = 1.0
revolutions = 120
transient_revolutions = 60
error_estimate = false
"#
    )
}

#[test]
fn no_contact_response_matches_z0() {
    // ORACLES: |Z0|/e = ν²/√((1−ν²)² + (2ξν)²).
    let (ls, model) = load(&unit_rotor(0.2, ""), &[]);
    let s = settings(&ls);
    for nu in [0.5_f64, 1.0426, 2.0] {
        let r = analysis::run_speed(&model, &s, nu, Keep::default()).unwrap();
        let z0 = 1e-3 * nu * nu / ((1.0 - nu * nu).powi(2) + (0.4 * nu).powi(2)).sqrt();
        assert!((r.z0 / z0 - 1.0).abs() < 1e-12);
        // Circular orbit of radius |Z0|: both extents and the 1× line.
        assert_eq!(r.period, 1);
        assert!(
            (r.amp_1x_nd - 1.0).abs() < 2e-3,
            "ν = {nu}: 1× = {}",
            r.amp_1x_nd
        );
        assert!(
            (r.extents_nd[1] - 1.0).abs() < 2e-3,
            "ν = {nu}: {:?}",
            r.extents_nd
        );
        assert!(
            (r.extents_nd[2] + 1.0).abs() < 2e-3,
            "ν = {nu}: {:?}",
            r.extents_nd
        );
    }
}

/// Runs one case and returns the record; `init` in metres.
fn record(
    ls: &LoadedScene,
    model: &Model,
    nu: f64,
    init: Initial,
    kind: Scheme,
) -> (Record, rubsim::time::StepPlan) {
    let case = model.case(nu * model.rotor.natural_frequency()).unwrap();
    let mut st = settings(ls).step;
    st.integrator = kind;
    let plan = plan_steps(&case, &st).unwrap();
    let (rec, _) = integrate(&case, kind, &plan, init).unwrap();
    (rec, plan)
}

#[test]
fn full_annular_rub_matches_analytic_whirl() {
    // ORACLES: κ = 25, μ = 0.1, ξ = 0.2, d = δ/e = 1.2.
    let ring = r#"
[[stator]]
kind = "ring"
name = "ring"
station = "s"
clearance = 1.2e-3
stiffness_ratio = 25.0
"#;
    let text = unit_rotor(0.2, ring);
    for (nu, r_e, beta_deg) in [
        (0.8, 1.20291, 37.793),
        (1.0, 1.23273, 35.094),
        (1.2, 1.27061, 33.102),
    ] {
        for (kind, harmonics) in [(Scheme::Collocated, "4"), (Scheme::ForwardIncrement, "64")] {
            let (ls, model) = load(&text, &[&format!("run.harmonics={harmonics}")]);
            let e = 1e-3;
            let b = f64::to_radians(beta_deg);
            let r0 = r_e * e;
            let init = Initial {
                u: [r0 * b.cos(), -r0 * b.sin()],
                v: [nu * r0 * b.sin(), nu * r0 * b.cos()],
            };
            let (rec, plan) = record(&ls, &model, nu, init, kind);
            let spr = plan.steps_per_rev / plan.record_every;
            let last = rec.len() - 1;
            // Radius over the last 10 revolutions and the lag at the Poincaré instants.
            let mut rmin = f64::INFINITY;
            let mut rmax = 0.0_f64;
            for i in last - 10 * spr..=last {
                let d = rec.disp_at(i, 0);
                let r = d[0].hypot(d[1]);
                rmin = rmin.min(r);
                rmax = rmax.max(r);
            }
            let d = rec.disp_at(last - last % spr, 0);
            let lag = -d[1].atan2(d[0]);
            let tol = if kind == Scheme::Collocated {
                1e-3
            } else {
                4e-3
            };
            assert!(
                (rmax / r0 - 1.0).abs() < tol && (rmin / r0 - 1.0).abs() < tol,
                "{kind:?} ν = {nu}: radius {:.6}..{:.6} e, expected {r_e}",
                rmin / e,
                rmax / e
            );
            assert!(
                (lag - b).abs().to_degrees() < 0.3,
                "{kind:?} ν = {nu}: lag {:.4}°, expected {beta_deg}°",
                lag.to_degrees()
            );
        }
    }
}

/// Backward whirl started at radius `r0_over_delta`·δ at the oracle's whirl speed; returns the
/// radius ratio (end / start) after `revs` revolutions of the rotor (Ω = 2 ω_n).
fn backward_whirl(mu: f64, r0_over_delta: f64, revs: usize) -> f64 {
    let delta = 1e-3;
    let text = format!(
        r#"
[rotor]
kind = "jeffcott"
mass = 1.0
stiffness = 1.0
damping_ratio = 0.2
[[station]]
name = "s"
radius = 0.05
friction = {mu}
[[stator]]
kind = "ring"
name = "ring"
station = "s"
clearance = {delta}
stiffness_ratio = 25.0
[run]
speed_ratio = 2.0
revolutions = {revs}
transient_revolutions = 0
harmonics = 16
error_estimate = false
"#
    );
    let (ls, model) = load(&text, &[]);
    let ww = 0.2 / mu + (1.0 + (0.2_f64 / mu).powi(2)).sqrt();
    let r0 = r0_over_delta * delta;
    let init = Initial {
        u: [r0, 0.0],
        v: [0.0, -ww * r0],
    };
    let (rec, plan) = record(&ls, &model, 2.0, init, Scheme::Collocated);
    let spr = plan.steps_per_rev / plan.record_every;
    let last = rec.len() - 1;
    let rmax = (last - spr..=last)
        .map(|i| {
            let d = rec.disp_at(i, 0);
            d[0].hypot(d[1])
        })
        .fold(0.0, f64::max);
    rmax / r0
}

#[test]
fn dry_whip_threshold() {
    // μ_c = 2ξ√(1+κ)/κ = 0.08158; the unstable backward orbit is at R = 3.1034 δ for μ = 0.1.
    let grow = backward_whirl(0.1, 4.0, 30);
    assert!(
        grow > 3.0,
        "μ = 0.1 > μ_c from 4δ: backward whirl must grow, ratio {grow}"
    );
    let inside = backward_whirl(0.1, 2.5, 30);
    assert!(
        inside < 1.0,
        "μ = 0.1 from 2.5δ (inside the unstable orbit): must decay, ratio {inside}"
    );
    let below = backward_whirl(0.07, 4.0, 30);
    eprintln!("dry whip radius ratio after 30 rev: μ=0.1 from 4δ {grow:.3}, from 2.5δ {inside:.3}; μ=0.07 from 4δ {below:.3}");
    assert!(
        below < 1.0,
        "μ = 0.07 < μ_c: backward whirl must decay, ratio {below}"
    );
}

/// Energy balance of a run recorded at every step (collocated: forces at tₙ):
/// ΔE_rotor + ΔE_stator = W_unbalance − W_damping + W_friction.
fn energy_residual(kind: Scheme) -> f64 {
    let text = PAPER.replace("[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1", "");
    let (ls, model) = load(
        &text,
        &[
            "run.speed_ratio=1.7",
            "run.samples_per_rev=2048",
            "run.revolutions=40",
            "run.transient_revolutions=20",
        ],
    );
    let nu = 1.7;
    let case = model.case(nu * model.rotor.natural_frequency()).unwrap();
    let mut st = settings(&ls).step;
    st.integrator = kind;
    let plan = plan_steps(&case, &st).unwrap();
    assert_eq!(plan.record_every, 1);
    let (rec, _) = integrate(&case, kind, &plan, Initial::default()).unwrap();
    let (m, k, c) = match &model.rotor {
        rubsim::model::Rotor::Jeffcott(j) => (j.mass, j.stiffness, j.damping),
        rubsim::model::Rotor::Fe(_) => unreachable!("the paper scene is a Jeffcott rotor"),
    };
    let dt = plan.dt;
    let me = 0.008 * 0.045;
    let w = case.omega;
    let start = 20 * plan.steps_per_rev;
    let end = rec.len() - 2;
    let u = |i: usize| rec.disp_at(i, 0);
    let vel = |i: usize| {
        let (a, b) = (u(i + 1), u(i - 1));
        [(a[0] - b[0]) / (2.0 * dt), (a[1] - b[1]) / (2.0 * dt)]
    };
    // Discrete energy consistent with central differences: kinetic from half-step velocities.
    let energy = |i: usize| {
        let (a, b, cc) = (u(i + 1), u(i), u(i - 1));
        let vp = [(a[0] - b[0]) / dt, (a[1] - b[1]) / dt];
        let vm = [(b[0] - cc[0]) / dt, (b[1] - cc[1]) / dt];
        0.5 * m * (vp[0] * vm[0] + vp[1] * vm[1]) + 0.5 * k * (b[0] * b[0] + b[1] * b[1])
    };
    let (mut w_unb, mut w_damp, mut w_fric, mut gross) = (0.0, 0.0, 0.0, 0.0);
    for i in start..end {
        let du = [
            (u(i + 1)[0] - u(i - 1)[0]) / 2.0,
            (u(i + 1)[1] - u(i - 1)[1]) / 2.0,
        ];
        let t = rec.t[i];
        let f = [me * w * w * (w * t).cos(), me * w * w * (w * t).sin()];
        let v = vel(i);
        let fc = rec.force_at(i, 0);
        let fnorm = rec.force_normal[i];
        let ff = [fc[0] - fnorm[0], fc[1] - fnorm[1]];
        let du_unb = f[0] * du[0] + f[1] * du[1];
        w_unb += du_unb;
        gross += du_unb.abs();
        w_damp += c * (v[0] * du[0] + v[1] * du[1]);
        w_fric += ff[0] * du[0] + ff[1] * du[1];
    }
    let de_r = energy(end) - energy(start);
    let de_s = rec.stator_energy[end] - rec.stator_energy[start];
    (de_r + de_s - (w_unb - w_damp + w_fric)).abs() / gross
}

#[test]
fn energy_balance_closes() {
    let r = energy_residual(Scheme::Collocated);
    assert!(r < 2e-4, "collocated energy residual {r:e}");
    // The forward-increment scheme dissipates at impacts; measured, not required to close.
    let f = energy_residual(Scheme::ForwardIncrement);
    assert!(f.is_finite() && f < 0.5, "forward-increment residual {f:e}");
    eprintln!("energy residual: collocated {r:.2e}, forward increment {f:.2e}");
}
