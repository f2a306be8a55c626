//! The ring stator's exact kinematics (docs/VALIDATION.md §15.1, docs/ORACLES.md §2a): the
//! ring's centre moves by the whole contact force `N(n + μa)/k_s`, the friction-driven
//! tangential part included, and the gap is measured from there. Checked against the closed form
//! of synchronous full annular rub on such a ring at several speeds (both integrators), the
//! massless ring as the limit of rings with vanishing mass (each against its own closed form),
//! and no penetration beyond 1e-3 of the clearance.

use crate::common;

use common::complex::{abs, add, div, mul, scale, C};

use common::scenes::{paper_with_stator, unit_exact_ring, unit_rotor};
use common::{case_and_plan, run_speed, scene_model, SHORT_RUN};
use rubsim::time::{integrate, Initial, Scheme};

/// Synchronous full annular rub of a Jeffcott rotor against a ring on isotropic springs that
/// takes the whole contact force (docs/ORACLES.md §2a), lengths in units of e = m_u ε/m:
/// `ν` the speed ratio, `xi` ξ, `kappa` κ = k_s/k, `mu` μ, `d` δ/e, `s` the ring's complex
/// stiffness over k_s (`1 − m_s Ω²/k_s + i c_s Ω/k_s`; 1 massless). Returns the whirl radius
/// r = R/e and the lag β (rad) of the rotor behind the unbalance; `None` without contact.
fn exact_ring_whirl(nu: f64, xi: f64, kappa: f64, mu: f64, d: f64, s: C) -> Option<(f64, f64)> {
    let h: C = (1.0 - nu * nu, 2.0 * xi * nu);
    let f: C = (1.0, mu);
    // |A + ρB| = ν² with A = H d, B = (1 + iμ)(H/s + κ); ρ = N/(k_s e) the normal deflection.
    let a = scale(h, d);
    let b = mul(f, add(div(h, s), (kappa, 0.0)));
    let qa = b.0 * b.0 + b.1 * b.1;
    let qb = 2.0 * (a.0 * b.0 + a.1 * b.1);
    let qc = a.0 * a.0 + a.1 * a.1 - nu.powi(4);
    let disc = qb * qb - 4.0 * qa * qc;
    let rho = (-qb + disc.sqrt()) / (2.0 * qa);
    if rho.is_nan() || rho <= 0.0 {
        return None;
    }
    // z = c n with c = d + ρ(1 + iμ)/s; the rotor: (H + κρ(1 + iμ)/c) z = ν² at τ = 0.
    let c = add((d, 0.0), div(scale(f, rho), s));
    let total = add(h, div(scale(f, kappa * rho), c));
    Some((abs(c), total.1.atan2(total.0)))
}

/// The same whirl on the radially elastic stator (docs/ORACLES.md §2): force k_s(R − δ) along
/// the radius.
fn radial_whirl(nu: f64, xi: f64, kappa: f64, mu: f64, d: f64) -> f64 {
    common::oracles::radial_annular_rub(nu, kappa, mu, xi, d).0
}

#[test]
fn closed_form_reduces_to_the_radial_one_without_friction() {
    // μ = 0: the ring's centre moves along the normal only, as on the radial stator.
    for nu in [0.8, 1.5, 2.5] {
        let (r, _) = exact_ring_whirl(nu, 0.2, 5.0, 0.0, 0.6, (1.0, 0.0)).unwrap();
        let rr = radial_whirl(nu, 0.2, 5.0, 0.0, 0.6);
        assert!((r / rr - 1.0).abs() < 1e-12, "ν = {nu}: {r} vs {rr}");
    }
}

#[test]
fn full_annular_rub_on_the_exact_ring_matches_its_closed_form() {
    // Unit rotor (m = 1 kg, k = 1 N/m, e = 1e-3 m), ξ = 0.2, μ = 0.1, κ = 5, δ = 0.6 e: the
    // ring deflects by more than the clearance, where the tangential part matters.
    let (xi, kappa, mu, d, e) = (0.2, 5.0, 0.1, 0.6, 1e-3);
    let text = unit_rotor(xi, &unit_exact_ring(d * e, kappa));
    for nu in [1.5, 2.0, 3.0] {
        let (r_e, beta) = exact_ring_whirl(nu, xi, kappa, mu, d, (1.0, 0.0)).unwrap();
        // The test tells the two laws apart: the radial stator's radius is elsewhere.
        let radial = radial_whirl(nu, xi, kappa, mu, d);
        assert!(
            (radial / r_e - 1.0).abs() > 1e-2,
            "ν = {nu}: {radial} vs {r_e}"
        );
        for (kind, harmonics, tol) in [
            (Scheme::Collocated, "4", 1e-3),
            (Scheme::ForwardIncrement, "256", 4e-3),
        ] {
            let (ls, model) = scene_model(&text, &[&format!("run.harmonics={harmonics}")]);
            let (case, plan) = case_and_plan(&ls, &model, nu, kind);
            let r0 = r_e * e;
            let init = Initial {
                u: [r0 * beta.cos(), -r0 * beta.sin()],
                v: [nu * r0 * beta.sin(), nu * r0 * beta.cos()],
            };
            let (rec, stats) = integrate(&case, kind, &plan, init).unwrap();
            let spr = plan.steps_per_rev / plan.record_every;
            let last = rec.len() - 1;
            let (mut rmin, mut rmax) = (f64::INFINITY, 0.0_f64);
            for i in last - 10 * spr..=last {
                let u = rec.disp_at(i, 0);
                rmin = rmin.min(u[0].hypot(u[1]));
                rmax = rmax.max(u[0].hypot(u[1]));
            }
            let u = rec.disp_at(last - last % spr, 0);
            let lag = -u[1].atan2(u[0]);
            assert!(
                (rmax / r0 - 1.0).abs() < tol && (rmin / r0 - 1.0).abs() < tol,
                "{kind:?} ν = {nu}: radius {:.6}..{:.6} e, closed form {r_e:.6}",
                rmin / e,
                rmax / e
            );
            assert!(
                (lag - beta).abs().to_degrees() < 0.3,
                "{kind:?} ν = {nu}: lag {:.4}°, closed form {:.4}°",
                lag.to_degrees(),
                beta.to_degrees()
            );
            assert!(
                stats.min_gap > -1e-3 * d * e,
                "{kind:?} ν = {nu}: penetration {:.3e} m",
                -stats.min_gap
            );
        }
    }
}

/// The reproducer of the issue: the paper's rotor (ξ = 0.2, μ = 0.1) in a ring of ε = 5,
/// δ = 0.5 |Z0|, at ω/ω_n = 2.
fn paper_ring() -> String {
    paper_with_stator(
        "[[stator]]\nkind = \"ring\"\nname = \"ring\"\nstation = \"disk\"\nclearance_nd = 0.5\nstiffness_ratio = 5.0\n",
    )
}

#[test]
fn massless_ring_is_the_limit_of_rings_with_vanishing_mass() {
    let text = paper_ring();
    let mut base: Vec<String> = SHORT_RUN.iter().map(|s| s.to_string()).collect();
    base.push("run.speed_ratio=2.0".into());
    let (_, model) = scene_model(&text, &base);
    let wn = model.rotor.natural_frequency();
    // k_r = 48 E I/L³ of the Table 1 shaft (the scene's), k_s = ε k_r.
    let kr = 48.0 * 200e9 * (std::f64::consts::PI * 0.01_f64.powi(4) / 64.0) / 0.4_f64.powi(3);
    let ks = 5.0 * kr;
    let nu: f64 = 2.0;
    let z0 = nu * nu / ((1.0 - nu * nu).powi(2) + (0.4 * nu).powi(2)).sqrt();
    let d = 0.5 * z0;
    // The closed form in units of |Z0|.
    let oracle = |m: f64| {
        let s = (1.0 - m * (nu * wn).powi(2) / ks, 0.0);
        exact_ring_whirl(nu, 0.2, 5.0, 0.1, d, s).unwrap().0 / z0
    };
    let massless = run_speed(&text, &base, nu);
    let r0 = massless.amp_1x_nd;
    let delta = massless.z0 * 0.5;
    assert!(
        (r0 / oracle(0.0) - 1.0).abs() < 2e-3,
        "massless ring: 1× {r0:.5} |Z0|, closed form {:.5}",
        oracle(0.0)
    );
    assert!(
        massless.penetration_max_m < 1e-3 * delta,
        "massless ring penetrates {:.3e} m of δ = {delta:.3e} m",
        massless.penetration_max_m
    );
    // Masses down by 4 each, the step keeping ω_s Δt = 0.1 (ω_s = √(k_s/m), explicit ring).
    let mut last_gap = f64::INFINITY;
    for m in [0.02, 0.005, 0.00125] {
        let dt = 0.1 * (m / ks).sqrt();
        let mut sets = base.clone();
        sets.push(format!("stator.0.mass={m}"));
        sets.push(format!("run.dt={dt}"));
        let r = run_speed(&text, &sets, nu);
        let rm = r.amp_1x_nd;
        let gap = (rm - r0).abs();
        eprintln!(
            "ring mass {m} kg: 1× {rm:.5} |Z0| (closed form {:.5}), massless {r0:.5}, penetration {:.2e} m",
            oracle(m),
            r.penetration_max_m
        );
        assert!(
            (rm / oracle(m) - 1.0).abs() < 5e-3,
            "mass {m}: 1× {rm:.5}, closed form {:.5}",
            oracle(m)
        );
        assert!(
            gap < 0.5 * last_gap,
            "mass {m}: |r − r_massless| = {gap:.2e} does not shrink (before {last_gap:.2e})"
        );
        assert!(r.penetration_max_m < 1e-3 * delta);
        last_gap = gap;
    }
    assert!(
        last_gap < 1e-3 * r0,
        "lightest ring {last_gap:.2e} from the massless one"
    );
}

#[test]
fn bad_ring_kinematics_are_refused_with_their_key() {
    let text = paper_ring();
    for (set, needle) in [
        (
            "stator.0.kinematics=\"tangential\"",
            "unknown ring kinematics",
        ),
        ("stator.0.kinematics=\"radial\"", ""),
    ] {
        let mut sets = vec![set.to_string(), "run.speed_ratio=2.0".to_string()];
        if needle.is_empty() {
            // Radial is a massless law: with mass it is refused, massless accepted.
            assert!(rubsim::scene::parse(std::path::Path::new("t.toml"), &text, &sets).is_ok());
            sets.push("stator.0.mass=0.1".into());
        }
        let err = rubsim::scene::parse(std::path::Path::new("t.toml"), &text, &sets)
            .expect_err("refused")
            .to_string();
        assert!(err.contains("stator.0.kinematics"), "{err}");
        assert!(err.contains("t.toml"), "{err}");
        if !needle.is_empty() {
            assert!(err.contains(needle), "{err}");
        } else {
            assert!(err.contains("mass = 0"), "{err}");
        }
    }
}
