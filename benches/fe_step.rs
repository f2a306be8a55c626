//! Steps per second of a 100-element Timoshenko rotor with two contact stations (M̃ factored
//! once — block-tridiagonal LU for a plain shaft chain, faer's sparse LU otherwise — sparse
//! mat-vecs, the rubsim way) against the same linear step with a dense solve of M̃ every
//! step (what a dense-matrix Python/MATLAB loop does), and with a dense pre-factored solve.
//!
//! Run: `cargo bench --bench fe_step` (figures in docs/PERFORMANCE.md);
//! `cargo bench --bench fe_step -- --sparse-only` skips the dense comparison.

use nalgebra::{DMatrix, DVector};
use rubsim::model::fe_rotor::dense;
use rubsim::model::Model;
use rubsim::scene;
use rubsim::time::Scheme;
use rubsim::time::{integrate, plan_steps, Initial};
use std::path::Path;
use std::time::Instant;

fn scene_text(elements: usize) -> String {
    let n = elements;
    let (a, b) = (n / 3, 2 * n / 3);
    format!(
        r#"
[rotor]
kind = "fe"
rayleigh = [10.0, 0.0]
[[rotor.shaft]]
length = 2.0
outer_diameter = 0.08
elements = {n}
material = "steel"
[[rotor.disk]]
node = {a}
outer_diameter = 0.4
width = 0.05
bore = 0.08
material = "steel"
[[rotor.disk]]
node = {b}
outer_diameter = 0.4
width = 0.05
bore = 0.08
material = "steel"
[[rotor.bearing]]
node = 0
stiffness = 5e7
damping = 2e3
[[rotor.bearing]]
node = {n}
stiffness = 5e7
damping = 2e3
[[rotor.unbalance]]
node = {a}
mass = 0.01
radius = 0.2
[[station]]
name = "a"
node = {a}
radius = 0.2
friction = 0.1
[[station]]
name = "b"
node = {b}
radius = 0.2
friction = 0.1
[[stator]]
kind = "ring"
name = "ring_a"
station = "a"
clearance_nd = 0.7
stiffness_ratio = 10.0
[[stator]]
kind = "rod"
name = "rod_b"
station = "b"
clearance_nd = 0.7
length = 0.05
area = 1e-4
stiffness_ratio = 10.0
[run]
speed_ratio = 1.5
revolutions = 4
transient_revolutions = 1
error_estimate = false
"#
    )
}

fn main() {
    for elements in [50usize, 100] {
        let text = scene_text(elements);
        let ls = scene::parse(Path::new("bench.toml"), &text, &[]).expect("scene");
        let model = Model::from_scene(&ls).expect("model");
        let nu = 1.5;
        let case = model
            .case(nu * model.rotor.natural_frequency())
            .expect("case");
        let st = rubsim::analysis::RunSettings::from_run(&ls.scene.run, "y").step;
        let plan = plan_steps(&case, &st).expect("plan");
        // Sparse, factored once (best of 3).
        let mut best = f64::INFINITY;
        let mut steps = 0;
        let mut contact = 0;
        for _ in 0..3 {
            let t0 = Instant::now();
            let (_, stats) =
                integrate(&case, Scheme::Collocated, &plan, Initial::default()).expect("run");
            best = best.min(t0.elapsed().as_secs_f64());
            steps = stats.steps;
            contact = stats.contact_steps;
        }
        let ndof = case.rotor.ndof;
        println!(
            "{elements} elements, {ndof} DOF, 2 stations: M̃ factored once (rubsim): {steps} steps in {best:.3} s = {:.0} steps/s ({:.2} µs/step, {contact} steps in contact)",
            steps as f64 / best,
            best / steps as f64 * 1e6
        );
        if std::env::args().any(|a| a == "--sparse-only") {
            continue;
        }
        // Dense: M̃ assembled dense, LU factorisation + solve every step (linear part only).
        let dt = plan.dt;
        let m = dense(&case.rotor.m);
        let c = dense(&case.rotor.c);
        let k = dense(&case.rotor.k);
        let mt = &m / (dt * dt) + &c / (2.0 * dt);
        let a = &m * (2.0 / (dt * dt)) - &k;
        let b = &c / (2.0 * dt) - &m / (dt * dt);
        let mut u = DVector::<f64>::zeros(ndof);
        let mut up = DVector::<f64>::zeros(ndof);
        let nd = 200;
        let t0 = Instant::now();
        for _ in 0..nd {
            let rhs = &a * &u + &b * &up;
            let un = mt.clone().lu().solve(&rhs).expect("dense solve");
            up = std::mem::replace(&mut u, un);
        }
        let per = t0.elapsed().as_secs_f64() / nd as f64;
        println!(
            "{elements} elements: dense LU every step: {:.0} steps/s ({:.1} µs/step) — sparse is {:.0}× faster",
            1.0 / per,
            per * 1e6,
            per / (best / steps as f64)
        );
        let lu = mt.clone().lu();
        let nd2 = 2000;
        let t0 = Instant::now();
        for _ in 0..nd2 {
            let rhs = &a * &u + &b * &up;
            let un = lu.solve(&rhs).expect("dense solve");
            up = std::mem::replace(&mut u, un);
        }
        let per2 = t0.elapsed().as_secs_f64() / nd2 as f64;
        println!(
            "{elements} elements: dense LU factored once, dense mat-vecs: {:.0} steps/s ({:.1} µs/step)",
            1.0 / per2,
            per2 * 1e6
        );
        let _ = DMatrix::<f64>::zeros(1, 1);
    }
}
