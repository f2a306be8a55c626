//! Verification against independent references: closed-form solutions (docs/ORACLES.md) and
//! published numbers. The Jeffcott rotor with contact (unbalance response, full annular rub,
//! dry-whip threshold, energy balance), the Timoshenko FE rotor (matrices, Friswell's example,
//! the Jeffcott limit, torsion, mass and inertia, friction torque, modal damping) and the 2-D
//! solid elements (patch test, thin ring under diametral loads).
//!
//! Fitted orders of convergence are checked in `convergence.rs`, golden files and pinned
//! results in `regression.rs`.

use crate::common;

use common::fe::{block_frequencies, fe};
use common::meshes::{model_of, ring_msh, solve, spec, E, NU};
use common::scenes::{
    full_rotor, paper_modal, paper_single, ss_shaft, torsion_disk, unit_ring, unit_rotor,
    unit_rotor_in_ring, FRISWELL, PAPER_TORSION,
};
use common::{case_and_plan, model, run_speed, scene_model, settings, NO_SETS, SHORT_RUN};
use rubsim::analysis::{self, Keep};
use rubsim::element::solid2d::{self, Elastic2, Plane};
use rubsim::linalg::Csc;
use rubsim::linear::{self, Whirl};
use rubsim::mesh::{CellKind, Mesh};
use rubsim::model::{Model, Rotor};
use rubsim::scene::LoadedScene;
use rubsim::time::{integrate, Initial, Record, Scheme, StepPlan};
use std::f64::consts::PI;
use std::path::Path;

// ---------------------------------------------------------------------------------------------
// Jeffcott rotor with contact (docs/ORACLES.md §2–4).

#[test]
fn no_contact_response_matches_z0() {
    // ORACLES: |Z0|/e = ν²/√((1−ν²)² + (2ξν)²).
    let (ls, model) = scene_model(&unit_rotor(0.2, ""), NO_SETS);
    let s = settings(&ls);
    for nu in [0.5_f64, 1.0426, 2.0] {
        let r = analysis::run_speed(&model, &s.request(nu), Keep::default()).unwrap();
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
) -> (Record, StepPlan) {
    let (case, plan) = case_and_plan(ls, model, nu, kind);
    let (rec, _) = integrate(&case, kind, &plan, init).unwrap();
    (rec, plan)
}

#[test]
fn full_annular_rub_matches_analytic_whirl() {
    // ORACLES: κ = 25, μ = 0.1, ξ = 0.2, d = δ/e = 1.2.
    let text = unit_rotor(0.2, &unit_ring(1.2e-3));
    for (nu, r_e, beta_deg) in [
        (0.8, 1.20291, 37.793),
        (1.0, 1.23273, 35.094),
        (1.2, 1.27061, 33.102),
    ] {
        for (kind, harmonics) in [(Scheme::Collocated, "4"), (Scheme::ForwardIncrement, "64")] {
            let (ls, model) = scene_model(&text, &[&format!("run.harmonics={harmonics}")]);
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
    let (ls, model) = scene_model(&unit_rotor_in_ring(mu, delta, revs), NO_SETS);
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
    let text = paper_single();
    let (ls, model) = scene_model(
        &text,
        &[
            "run.speed_ratio=1.7",
            "run.samples_per_rev=2048",
            "run.revolutions=40",
            "run.transient_revolutions=20",
        ],
    );
    let nu = 1.7;
    let (case, plan) = case_and_plan(&ls, &model, nu, kind);
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

// ---------------------------------------------------------------------------------------------
// Timoshenko FE rotor.

#[test]
fn assembled_matrices_are_symmetric_skew_and_weigh_right() {
    let m = model(&ss_shaft(10, true));
    let f = fe(&m.rotor);
    assert!(f.rotor.m.asymmetry() < 1e-12);
    assert!(f.rotor.k_shaft.asymmetry() < 1e-12);
    for (r, c, v) in f.rotor.g.triplets() {
        assert!(
            (v + f.rotor.g.get(c, r)).abs() < 1e-15,
            "G not skew at ({r},{c})"
        );
    }
    let mass = 7800.0 * PI * 0.01 * 2.0;
    assert!((f.rotor.total_mass / mass - 1.0).abs() < 1e-12);
    // Polar inertia of a solid cylinder m d²/8.
    assert!((f.rotor.total_polar_inertia / (mass * 0.04 / 8.0) - 1.0).abs() < 1e-12);
}

#[test]
fn free_shaft_has_four_rigid_body_modes() {
    let m = model(&ss_shaft(6, true));
    let f = fe(&m.rotor);
    let k = rubsim::model::fe_rotor::dense(&f.rotor.k_shaft);
    let ev = k.symmetric_eigenvalues();
    let big = ev.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    let zeros = ev.iter().filter(|v| v.abs() < 1e-10 * big).count();
    assert_eq!(zeros, 4, "translations x, y and rotations about x, y");
}

/// Friswell et al. (2010) Example 5.9.1 / ROSS `rotor_example` (`scenes/fe/friswell_5_9_1.toml`):
/// natural frequencies at rest as published, forward/backward split growing with the spin.
#[test]
fn friswell_example_5_9_1_at_rest_and_spinning() {
    let m = model(FRISWELL);
    let w = fe(&m.rotor).rotor.undamped_frequencies(0.0).unwrap();
    for (k, published) in [86.66, 274.31, 716.78].iter().enumerate() {
        let got = w[2 * k];
        eprintln!(
            "Friswell 5.9.1 mode {}: {got:.2} rad/s (published {published})",
            k + 1
        );
        assert!(
            (got / published - 1.0).abs() < 5e-3,
            "mode {}: {got} vs {published}",
            k + 1
        );
    }
    // Spinning: forward/backward split grows with speed (gyroscopic stiffening/softening).
    let split = |rpm: f64| {
        let r = linear::modal(&m.rotor, rpm * 2.0 * PI / 60.0, 4).unwrap();
        let fw = r
            .modes
            .iter()
            .find(|x| x.whirl == Whirl::Forward)
            .unwrap()
            .omega_d;
        let bw = r
            .modes
            .iter()
            .find(|x| x.whirl == Whirl::Backward)
            .unwrap()
            .omega_d;
        fw - bw
    };
    let (s1, s2, s3) = (split(1000.0), split(2000.0), split(4000.0));
    eprintln!("FW − BW of the first pair: {s1:.3}, {s2:.3}, {s3:.3} rad/s at 1000/2000/4000 rpm");
    assert!(s1 > 0.0 && s2 > s1 && s3 > s2);
}

/// The paper's rotor with one element per span and a nearly massless shaft must match the
/// Jeffcott rotor built from the same data (k = 48EI/L³, m = disk mass).
#[test]
fn one_element_per_span_matches_jeffcott() {
    let text = r#"
[rotor]
kind = "fe"
shear = false
rotary_inertia = false
gyroscopic = false
[[rotor.shaft]]
length = 0.4
outer_diameter = 0.01
elements = 2
youngs_modulus = 200e9
poisson = 0.3
density = 1.0
[[rotor.disk]]
node = 1
mass = 2.6465
diametral_inertia = 1e-6
[[rotor.bearing]]
node = 0
stiffness = 1e10
[[rotor.bearing]]
node = 2
stiffness = 1e10
[[station]]
name = "disk"
node = 1
radius = 0.06
[run]
speed_ratio = 1.0
"#;
    let m = model(text);
    let k = 48.0 * 200e9 * (PI * 0.01_f64.powi(4) / 64.0) / 0.4_f64.powi(3);
    let wj = (k / 2.6465_f64).sqrt();
    let wn = m.rotor.natural_frequency();
    assert!((wn / wj - 1.0).abs() < 1e-4, "FE {wn} vs Jeffcott {wj}");
    assert!((fe(&m.rotor).k_ref / k - 1.0).abs() < 1e-4);
}

/// (b) Torsion: a disk I_p at the free end of a shaft fixed at the other. Exact (fixed–free
/// shaft with tip inertia): βL tan βL = ρJL/I_p, ω = β √(G/ρ); for a light shaft
/// ω → √(k_t/I_p), k_t = GJ/L, and Rayleigh's √(k_t/(I_p + ρJL/3)) is within O((ρJL/I_p)²).
/// Node 0 is clamped by dropping its DOF.
#[test]
fn torsion_disk_on_shaft_matches_closed_forms() {
    let (l, d, e, nu, rho) = (0.5_f64, 0.02_f64, 2.1e11_f64, 0.3_f64, 7800.0_f64);
    let gm = e / (2.0 * (1.0 + nu));
    let j = PI * d.powi(4) / 32.0;
    let kt = gm * j / l;
    let shaft_ip = rho * j * l;
    let ip = 100.0 * shaft_ip;
    // βL tan βL = r by bisection on (0, π/2).
    let r = shaft_ip / ip;
    let (mut a, mut b) = (0.0_f64, PI / 2.0 - 1e-12);
    for _ in 0..200 {
        let x = 0.5 * (a + b);
        if x * x.tan() < r {
            a = x;
        } else {
            b = x;
        }
    }
    let exact = 0.5 * (a + b) / l * (gm / rho).sqrt();
    let simple = (kt / ip).sqrt();
    let rayleigh = (kt / (ip + shaft_ip / 3.0)).sqrt();
    for n in [1usize, 4, 16] {
        let m = model(&torsion_disk(n, ip, 1.0e6));
        let f = &fe(&m.rotor).rotor;
        let dofs: Vec<usize> = f.node_torsion.iter().map(|d| d.unwrap()).collect();
        let w = block_frequencies(f, &dofs[1..])[0];
        eprintln!(
            "torsion, {n} elements: ω = {w:.6} rad/s (rel. to exact {:.2e}); exact {exact:.6}, √(k_t/I_p) {simple:.6}, Rayleigh {rayleigh:.6}",
            w / exact - 1.0
        );
        // One element is the Rayleigh–Ritz estimate with a linear twist, exactly
        // √(k_t/(I_p + ρJL/3)); finer meshes converge to the exact root.
        if n == 1 {
            assert!((w / rayleigh - 1.0).abs() < 1e-12, "{w} vs {rayleigh}");
        }
        let tol = if n == 1 { 2e-6 } else { 1e-7 };
        assert!((w / exact - 1.0).abs() < tol, "{n}: {w} vs {exact}");
        assert!((w / simple - 1.0).abs() < r / 6.0 * 1.05, "{w} vs {simple}");
        assert!(w < simple);
    }
}

/// (c) Total mass and polar inertia through the new DOFs: a rigid axial translation carries
/// the whole mass (shaft, disk, point mass; pedestals have no axial DOF), a rigid rotation
/// about z the whole polar inertia (shaft ρJL + disk I_p); neither strains the shaft.
#[test]
fn rigid_axial_and_torsional_motion_carry_total_mass_and_polar_inertia() {
    let m = model(&full_rotor(true, true));
    let f = &fe(&m.rotor).rotor;
    // Shaft: steel tube 50/10 mm, 1.5 m; disk from geometry; point mass 1.25 kg.
    let (od, id, l, rho) = (0.05_f64, 0.01_f64, 1.5_f64, 7810.0_f64);
    let shaft_m = rho * PI * (od * od - id * id) / 4.0 * l;
    let shaft_ip = rho * PI * (od.powi(4) - id.powi(4)) / 32.0 * l;
    let dm = 7810.0 * PI * (0.28_f64.powi(2) - 0.05_f64.powi(2)) / 4.0 * 0.07;
    let dip = dm * (0.14_f64.powi(2) + 0.025_f64.powi(2)) / 2.0;
    let mass = shaft_m + dm + 1.25;
    let ipol = shaft_ip + dip;
    assert!((f.total_mass / mass - 1.0).abs() < 1e-13);
    assert!((f.total_polar_inertia / ipol - 1.0).abs() < 1e-13);
    let quad = |a: &rubsim::linalg::Csc, q: &[f64]| -> f64 {
        a.triplets().map(|(r, c, v)| q[r] * v * q[c]).sum()
    };
    for (dofs, expected, what) in [
        (&f.node_axial, mass, "axial translation"),
        (&f.node_torsion, ipol, "rotation about z"),
    ] {
        let mut q = vec![0.0; f.ndof];
        for d in dofs.iter() {
            q[d.unwrap()] = 1.0;
        }
        let t = quad(&f.m, &q);
        eprintln!("{what}: qᵀMq = {t:.10} (expected {expected:.10})");
        assert!(
            (t / expected - 1.0).abs() < 1e-13,
            "{what}: {t} vs {expected}"
        );
        let mut kq = vec![0.0; f.ndof];
        f.k_shaft.mul_add(1.0, &q, &mut kq);
        let big = f
            .k_shaft
            .triplets()
            .fold(0.0_f64, |a, (_, _, v)| a.max(v.abs()));
        assert!(
            kq.iter().all(|v| v.abs() < 1e-12 * big),
            "{what} strains the shaft"
        );
    }
    // The free shaft now has six rigid-body modes (x, y, tilt about x and y, axial, spin), plus
    // the pedestal's two DOFs, which k_shaft does not hold.
    let ev = rubsim::model::fe_rotor::dense(&f.k_shaft).symmetric_eigenvalues();
    let big = ev.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    assert_eq!(ev.iter().filter(|v| v.abs() < 1e-10 * big).count(), 6 + 2);
}

/// Frames every step: time, θ_z at the drive (node 0) and station (node 4), Σ p.
struct TwistProbe {
    dofs: [usize; 2],
    rows: Vec<[f64; 4]>,
}

impl rubsim::time::FrameSink for TwistProbe {
    fn every(&self) -> usize {
        1
    }
    fn frame(&mut self, fr: &rubsim::time::Frame<'_>) -> rubsim::error::Result<()> {
        let p: f64 = fr.pairs.iter().map(|x| x.p).sum();
        self.rows
            .push([fr.t, fr.rotor_u[self.dofs[0]], fr.rotor_u[self.dofs[1]], p]);
        Ok(())
    }
}

/// (e) Friction torque: the rub's friction μ p acts at the disk rim R and twists the shaft
/// against the spin. Over whole revolutions of the steady response the mean twist is static:
/// θ̄_z(drive) = τ̄/k_t, θ̄_z(disk) − θ̄_z(drive) = τ̄ L/(GJ), τ̄ = −R μ p̄ (p̄ the mean normal
/// force). Checked for a partial rub on the rod (ν = 1.7, period 1) with both integrators (the
/// collocated one adds the torque to the step's load, forward increment applies it through
/// M̃⁻¹ like the contact force), and for a full annular rub on a ring (constant torque).
#[test]
fn friction_torque_twists_the_shaft_by_r_mu_p_over_k() {
    use rubsim::time::Scheme;
    let ring = PAPER_TORSION.replace(
        "[[stator]]\nkind = \"rod\"\nname = \"rod\"\nstation = \"disk\"\nclearance_nd = 0.6\nlength = 0.04\narea = 25e-6\nstiffness_ratio = 25.0\nangle_deg = 90.0\n",
        "[[stator]]\nkind = \"ring\"\nname = \"ring\"\nstation = \"disk\"\nclearance_nd = 0.48\nstiffness_ratio = 25.0\n",
    );
    assert_ne!(ring, PAPER_TORSION);
    let (r, mu, kt) = (0.06, 0.1, 1000.0);
    let gj = 200e9 / 2.6 * PI * 0.01_f64.powi(4) / 32.0;
    let l04 = 0.2;
    for (text, nu, kind, what) in [
        (PAPER_TORSION, 1.7, Scheme::Collocated, "rod, collocated"),
        (
            PAPER_TORSION,
            1.7,
            Scheme::ForwardIncrement,
            "rod, forward increment",
        ),
        (ring.as_str(), 1.0, Scheme::Collocated, "ring, collocated"),
    ] {
        let (ls, m) = scene_model(text, &SHORT_RUN);
        let f = &fe(&m.rotor).rotor;
        let (case, plan) = case_and_plan(&ls, &m, nu, kind);
        let mut probe = TwistProbe {
            dofs: [f.node_torsion[0].unwrap(), f.node_torsion[4].unwrap()],
            rows: Vec::new(),
        };
        let (rec, _) = rubsim::time::integrate_with(
            &case,
            kind,
            &plan,
            rubsim::time::Initial::default(),
            Some(&mut probe),
        )
        .unwrap();
        // Mean over the last 20 whole revolutions.
        let t_rev = 2.0 * PI / case.omega;
        let t_end = probe.rows.last().unwrap()[0];
        let win: Vec<&[f64; 4]> = probe
            .rows
            .iter()
            .filter(|x| x[0] > t_end - 20.0 * t_rev + 0.5 * plan.dt)
            .collect();
        let mean = |i: usize| win.iter().map(|x| x[i]).sum::<f64>() / win.len() as f64;
        let (th0, th4, p) = (mean(1), mean(2), mean(3));
        let tau = -r * mu * p;
        let (want0, want_twist) = (tau / kt, tau * l04 / gj);
        let e0 = th0 / want0 - 1.0;
        let e_twist = (th4 - th0) / want_twist - 1.0;
        let e_tot = th4 / (tau * (1.0 / kt + l04 / gj)) - 1.0;
        // The record's normal force (every recorded sample) gives the same mean.
        let spr = plan.steps_per_rev / plan.record_every;
        let n = rec.len();
        let p_rec = (n - 1 - 20 * spr..n - 1)
            .map(|i| {
                let v = rec.force_normal[i];
                v[0].hypot(v[1])
            })
            .sum::<f64>()
            / (20 * spr) as f64;
        eprintln!(
            "{what}: p̄ = {p:.5} N (record {p_rec:.5}), τ̄ = {tau:.4e} N·m; θ̄_z drive {th0:.5e} rad (rel. err {e0:.2e}), shaft twist {:.5e} rad (rel. err {e_twist:.2e}), disk vs R μ p̄/k_eff rel. err {e_tot:.2e}",
            th4 - th0
        );
        assert!(
            p > 0.0 && th4 < th0 && th0 < 0.0,
            "the rub winds the disk against the spin"
        );
        // Exact but for the window's ends (one step's pair forces at most): measured ~1e-11.
        for e in [e0, e_twist, e_tot] {
            assert!(e.abs() < 1e-3, "{what}: {e}");
        }
        // The recorded samples (every `record_every` steps) see the same mean within ~1 %.
        assert!(
            (p_rec / p - 1.0).abs() < 0.02,
            "{what}: record p̄ {p_rec} vs {p}"
        );
        // The torsional vibration barely changes the sliding speed ΩR + R θ̇_z, so the friction
        // keeps the direction of the spin tangent (permanent slip), as the contact model assumes.
        let slip = win
            .windows(2)
            .map(|w| ((w[1][2] - w[0][2]) / (w[1][0] - w[0][0])).abs())
            .fold(0.0_f64, f64::max)
            / case.omega;
        eprintln!("{what}: max |θ̇_z|/Ω at the disk = {slip:.2e}");
        assert!(slip < 1e-2, "{what}: {slip}");
    }
}

/// Modal damping: the damped modes at rest carry exactly ζ on the selected modes (the x and y
/// halves of the first bending pair together even when `modes = 1`) and nothing on the
/// others (undamped bearings, no Rayleigh); `max_frequency` selects by frequency.
#[test]
fn modal_damping_puts_zeta_on_the_chosen_modes_only() {
    for limit in ["modes = 1", "max_frequency = 500.0"] {
        let text = paper_modal(0.05, limit);
        assert!(text.contains("[rotor.modal_damping]"));
        let m = model(&text);
        let r = linear::modal(&m.rotor, 0.0, 4).unwrap();
        let z: Vec<f64> = r.modes.iter().map(|md| md.damping_ratio).collect();
        assert!(
            (z[0] - 0.05).abs() < 1e-6 && (z[1] - 0.05).abs() < 1e-6,
            "{limit}: {z:?}"
        );
        assert!(z[2].abs() < 1e-6 && z[3].abs() < 1e-6, "{limit}: {z:?}");
    }
    // Without a limit every mode gets ζ.
    let m = model(&paper_modal(0.03, ""));
    let r = linear::modal(&m.rotor, 0.0, 6).unwrap();
    for md in &r.modes {
        assert!(
            (md.damping_ratio - 0.03).abs() < 1e-6,
            "{}",
            md.damping_ratio
        );
    }
}

/// Modal damping in the time loop (sparse LU + Woodbury) agrees with the frequency domain:
/// (1) at resonance, where the amplitude is set by ζ alone, the steady orbit of the disk equals
/// |Z0| of the complex solve (extents ±1 in units of |Z0|); (2) a free decay from an initial
/// displacement falls as exp(−ζ ω_n t) (fitted slope of the log of successive peaks).
#[test]
fn modal_damping_in_the_time_loop_matches_the_frequency_domain() {
    let text = paper_modal(0.05, "modes = 2");
    let free = [
        "stator.0.clearance_nd=100".to_string(),
        "run.error_estimate=false".to_string(),
        "run.revolutions=80".to_string(),
        "run.transient_revolutions=70".to_string(),
        "run.harmonics=16".to_string(),
    ];
    let r = run_speed(&text, &free, 1.0);
    for (k, e) in r.extents_nd.iter().enumerate() {
        let want = if k % 2 == 0 { -1.0 } else { 1.0 };
        assert!(
            (e - want).abs() < 5e-3,
            "extents at resonance {:?}",
            r.extents_nd
        );
    }
    // Free decay: no unbalance, initial displacement at the disk.
    // Every mode damped here: the node's initial kink excites the higher modes too, which would
    // otherwise ring on undamped under the decaying first mode.
    let text = paper_modal(0.05, "").replace("clearance_nd = 0.6", "clearance = 1.0");
    let mut ov: Vec<String> = free[1..].to_vec();
    ov.push("rotor.unbalance.0.mass=0.0".into());
    ov.push("run.initial_displacement=[0.0, 1e-4]".into());
    ov.push("run.revolutions=6".into());
    ov.push("run.transient_revolutions=0".into());
    ov.push("run.samples_per_rev=256".into());
    let (ls, model) = scene_model(&text, &ov);
    let Rotor::Fe(f) = &model.rotor else { panic!() };
    let wn = f.omega_n;
    let omega = 0.3 * wn;
    let case = model.case(omega).unwrap();
    let mut st = settings(&ls);
    st.step.dt = None;
    let plan = rubsim::time::plan_steps(&case, &st.step).unwrap();
    let (rec, _) = rubsim::time::integrate(&case, st.step.integrator, &plan, st.initial).unwrap();
    let y: Vec<f64> = rec.observed.iter().map(|d| d[1]).collect();
    // The largest value in each first-mode period.
    let period = 2.0 * PI / wn;
    let (mut t_pk, mut a_pk) = (Vec::new(), Vec::new());
    let mut k = 0;
    while (k as f64 + 1.0) * period < *rec.t.last().unwrap() {
        let (lo, hi) = (k as f64 * period, (k as f64 + 1.0) * period);
        let best = (0..y.len())
            .filter(|&i| rec.t[i] >= lo && rec.t[i] < hi)
            .max_by(|&a, &b| y[a].total_cmp(&y[b]))
            .unwrap();
        t_pk.push(rec.t[best]);
        a_pk.push(y[best].ln());
        k += 1;
    }
    assert!(t_pk.len() >= 5, "{} peaks", t_pk.len());
    let n = t_pk.len() as f64;
    let (mt, ma) = (t_pk.iter().sum::<f64>() / n, a_pk.iter().sum::<f64>() / n);
    let slope = t_pk
        .iter()
        .zip(&a_pk)
        .map(|(t, a)| (t - mt) * (a - ma))
        .sum::<f64>()
        / t_pk.iter().map(|t| (t - mt).powi(2)).sum::<f64>();
    let zeta = -slope / wn;
    println!(
        "free decay: ζ = {zeta:.5} from {} peaks (ω_n = {wn:.2} rad/s)",
        t_pk.len()
    );
    assert!((zeta - 0.05).abs() < 1e-3, "ζ from the decay {zeta}");
}

// ---------------------------------------------------------------------------------------------
// 2-D solid elements.

#[test]
fn patch_test_reproduces_linear_fields_on_distorted_cells() {
    // A 2×2 patch on [0, 1]² with the centre node moved and, for quadratic cells, mid nodes
    // off the chords' midpoints: prescribing a linear field on the boundary must give it
    // exactly inside, with constant stress.
    let mat = Elastic2 {
        youngs_modulus: E,
        poisson_ratio: NU,
        thickness: 0.01,
        plane: Plane::Stress,
    };
    let field = |x: [f64; 2]| {
        [
            1e-3 + 2e-4 * x[0] - 1e-4 * x[1],
            -5e-4 + 3e-4 * x[0] + 1e-4 * x[1],
        ]
    };
    for kind in [
        CellKind::Tri3,
        CellKind::Tri6,
        CellKind::Quad4,
        CellKind::Quad8,
        CellKind::Quad9,
    ] {
        let msh = ring_msh(kind, 1.0, 2.0, 0.0, 0.5, 2, 2, false);
        let mut mesh = Mesh::parse(Path::new("patch.msh"), msh.as_bytes()).unwrap();
        // Map the sector onto a distorted square patch: node (r, θ) → (r − 1, 2θ) + distortion.
        for p in mesh.nodes.iter_mut() {
            let (r, t) = (p[0].hypot(p[1]), p[1].atan2(p[0]));
            let (x, y) = (r - 1.0, 2.0 * t);
            let bump = (x * (1.0 - x) * y * (1.0 - y)) * 16.0;
            *p = [
                x + 0.08 * bump,
                y - 0.05 * bump + 0.02 * (x * PI).sin() * y * (1.0 - y),
                0.0,
            ];
        }
        let nd = 2 * mesh.nodes.len();
        let mut kt = Vec::new();
        let mut boundary = vec![false; mesh.nodes.len()];
        for (i, p) in mesh.nodes.iter().enumerate() {
            boundary[i] = p[0].abs() < 1e-12
                || (p[0] - 1.0).abs() < 1e-12
                || p[1].abs() < 1e-12
                || (p[1] - 1.0).abs() < 1e-12;
        }
        for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 2) {
            for c in b.cells() {
                let x: Vec<[f64; 2]> = c
                    .iter()
                    .map(|&n| [mesh.nodes[n][0], mesh.nodes[n][1]])
                    .collect();
                assert!(solid2d::det_j_range(b.kind, &x).0 > 0.0);
                let n2 = 2 * c.len();
                let mut ke = vec![0.0; n2 * n2];
                solid2d::stiffness(b.kind, &x, &mat, &mut ke);
                for i in 0..n2 {
                    for j in 0..n2 {
                        kt.push((2 * c[i / 2] + i % 2, 2 * c[j / 2] + j % 2, ke[i * n2 + j]));
                    }
                }
            }
        }
        let k = Csc::from_triplets(nd, nd, &kt);
        let used: Vec<bool> = (0..mesh.nodes.len())
            .map(|n| {
                mesh.blocks
                    .iter()
                    .filter(|b| b.kind.dim() == 2)
                    .any(|b| b.conn.contains(&n))
            })
            .collect();
        // Interior unknowns: K_ii u_i = −K_ib u_b.
        let free: Vec<usize> = (0..nd)
            .filter(|d| used[d / 2] && !boundary[d / 2])
            .collect();
        let mut map = vec![usize::MAX; nd];
        for (i, &d) in free.iter().enumerate() {
            map[d] = i;
        }
        let ub: Vec<f64> = (0..nd)
            .map(|d| {
                if boundary[d / 2] {
                    field([mesh.nodes[d / 2][0], mesh.nodes[d / 2][1]])[d % 2]
                } else {
                    0.0
                }
            })
            .collect();
        let mut rhs = vec![0.0; free.len()];
        let mut kii = Vec::new();
        for (r, c, v) in k.triplets() {
            if map[r] == usize::MAX {
                continue;
            }
            if map[c] != usize::MAX {
                kii.push((map[r], map[c], v));
            } else {
                rhs[map[r]] -= v * ub[c];
            }
        }
        let u = solve(&Csc::from_triplets(free.len(), free.len(), &kii), &rhs);
        for (i, &d) in free.iter().enumerate() {
            let ex = field([mesh.nodes[d / 2][0], mesh.nodes[d / 2][1]])[d % 2];
            assert!(
                (u[i] - ex).abs() < 1e-12,
                "{kind:?}: DOF {d}: {} vs {ex}",
                u[i]
            );
        }
    }
}

#[test]
fn ring_under_diametral_loads_matches_curved_beam_theory() {
    // Thin ring (mean radius R, radial thickness h = R/25), quarter model with symmetry,
    // compressed by P along y: the horizontal diameter grows by P R³/(E I) (2/π − 1/2)
    // (Roark, thin ring under diametral loads: 0.1366 P R³/(E I)).
    let (rm, h, t) = (0.1, 0.004, 0.01);
    let p = 100.0;
    let sp = spec("fixed = []\nfixed_x = [\"edge_t1\"]\nfixed_y = [\"edge_t0\"]");
    for kind in [CellKind::Quad8, CellKind::Tri6] {
        let msh = ring_msh(
            kind,
            rm - h / 2.0,
            rm + h / 2.0,
            0.0,
            PI / 2.0,
            2,
            96,
            false,
        );
        let (mesh, m) = model_of(&msh, &sp);
        let mut f = vec![0.0; m.ndof];
        // P/2 on the quarter, at the outer node of the θ = 90° section, pointing down.
        let top = (0..mesh.nodes.len())
            .filter(|&i| m.node_dofs[i][1].is_some())
            .max_by(|&a, &b| mesh.nodes[a][1].total_cmp(&mesh.nodes[b][1]))
            .unwrap();
        f[m.node_dofs[top][1].unwrap()] = -p / 2.0;
        let u = solve(&m.k, &f);
        let mid = (0..mesh.nodes.len())
            .find(|&i| mesh.nodes[i][1].abs() < 1e-12 && (mesh.nodes[i][0] - rm).abs() < 1e-9)
            .expect("mid-thickness node on the x axis");
        let dx = 2.0 * u[m.node_dofs[mid][0].unwrap()];
        let i = t * h.powi(3) / 12.0;
        let theory = p * rm.powi(3) / (E * i) * (2.0 / PI - 0.5);
        eprintln!("diametral ring {kind:?}: Δd = {dx:.6e} m, curved-beam theory {theory:.6e} m");
        assert!(
            (dx / theory - 1.0).abs() < 0.005,
            "{kind:?}: Δd = {dx:.4e}, theory {theory:.4e}"
        );
    }
}
