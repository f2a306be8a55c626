//! The thermal spiral on the Timoshenko FE rotor (issue 27, items 1 and 5): the bow as a
//! curvature field (`model::bow`) against the moment–area closed form of a simply supported
//! shaft, the simulated spiral against the linear theory with the FE rotor's own receptance
//! (docs/VALIDATION.md §21.2), a reduced rotor, the generator scene and the errors of bad input.

use crate::common::{self, cli};
use num_complex::Complex64 as C64;
use rubsim::analysis::thermal::{run_thermal, HotSpot, ThermalResults};
use rubsim::model::bow::{fe_bow_load, rotor_frame, static_bow};
use rubsim::model::fe_rotor::dense;
use rubsim::model::{Model, Rotor};
use rubsim::scene::LoadedScene;

/// A uniform steel shaft (L 1 m, D 50 mm, 20 elements) on two bearings at its ends: simply
/// supported (the bearings carry no force under a free curvature: two supports make it
/// statically determinate, so their stiffness does not matter).
const SHAFT: &str = r#"
[rotor]
kind = "fe"
[[rotor.shaft]]
length = 1.0
outer_diameter = 0.05
elements = 20
youngs_modulus = 2.1e11
poisson = 0.3
density = 7800.0
[[rotor.bearing]]
node = 0
stiffness = 1.0e7
[[rotor.bearing]]
node = 20
stiffness = 1.0e7
[run]
speed_ratio = 0.5
"#;

/// The bow of a simply supported span `l` under the curvature `κ` (1/m, toward the hot side)
/// over `[c − a/2, c + a/2]`, at `z` (moment–area): `w = κ (F(L) z/L − F(z))` with
/// `F(z) = ∫₀^z ∫₀^s χ`, χ the heated zone's indicator — a parabola inside it, linear outside.
fn bow_closed_form(kappa: f64, l: f64, (c, a): (f64, f64), z: f64) -> f64 {
    let (z1, z2) = (c - a / 2.0, c + a / 2.0);
    let f = |z: f64| {
        if z <= z1 {
            0.0
        } else if z <= z2 {
            (z - z1).powi(2) / 2.0
        } else {
            a * (z - c)
        }
    };
    kappa * (f(l) * z / l - f(z))
}

/// The static bow of the curvature load is the moment–area shape: at midspan
/// `α ΔT a (2L − a)/(8D)` for heating centred there, and at every node the piecewise closed form
/// (parabola in the heated zone, linear outside) — to round-off where the zone's ends are nodes
/// (the element is statically exact and the load is its end moments), to the same where they
/// fall inside elements (the consistent load: measured 1e-15 relative, the element's nodal
/// values exact for any load polynomial in z), off centre too. The bow points at the hot side
/// (ΔT along x: real and positive) and the rotor stays straight in y.
#[test]
fn the_static_bow_is_the_moment_area_closed_form() {
    let model = common::model(SHAFT);
    let Rotor::Fe(f) = &model.rotor else {
        panic!("an FE rotor")
    };
    let r = &f.rotor;
    let (alpha, d) = (1.2e-5, 0.05);
    let kappa = alpha / d;
    for (c, a) in [(0.5, 0.2), (0.5, 0.23), (0.5, 1.0), (0.3, 0.17)] {
        let load = fe_bow_load(r, c, a, kappa);
        let u = static_bow(r, 0.0, &load).unwrap();
        let scale = bow_closed_form(kappa, 1.0, (c, a), c);
        let mut worst: f64 = 0.0;
        for (i, z) in r.z.iter().enumerate() {
            let b = rotor_frame(&u, [4 * i, 4 * i + 1]);
            let want = bow_closed_form(kappa, 1.0, (c, a), *z);
            worst = worst.max((b[0] - want).abs().max(b[1].abs()) / scale);
        }
        let mid = rotor_frame(&u, [40, 41])[0];
        eprintln!("c {c}, a {a}: midspan bow {mid:.6e} m/K, largest error {worst:.1e} of it");
        assert!(worst < 1e-9, "c {c} a {a}: {worst}");
        if c == 0.5 {
            let want = alpha * a * (2.0 - a) / (8.0 * d);
            assert!((mid / want - 1.0).abs() < 1e-9, "{mid} {want}");
        }
    }
}

/// The paper's rotor as 8 Timoshenko elements (docs/VALIDATION.md §21.2): 40 cm shaft of 1 cm,
/// the 12 cm disk at midspan, very stiff bearings, ξ 0.05 of the first mode (α M); a soft seal
/// all round at the disk (a radial ring at 0.1 µm, k_s 36.8 kN/m ≈ ½ k_r, μ 0.2, R 0.06 m);
/// ΔT over a = 0.1 m centred at the disk (its ends at nodes 3 and 5), G 2.5 K/W, τ_h 2 s,
/// τ_c 20 s; chunks of 8 revolutions (the sudden bow of the first chunk excites the shaft's
/// lightly damped higher modes: with 4 the orbit still changed by 5.9 % over its last
/// revolution). Reduced for the time loop (`[run.reduction]`: 36 → 6 DOF, Δt the paper's rule
/// instead of the explicit limit of the 1e8 N/m bearings, 37 × fewer steps).
const FE_SPIRAL: &str = r#"
[rotor]
kind = "fe"
rayleigh = [16.3, 0.0]
[[rotor.shaft]]
length = 0.40
outer_diameter = 0.01
elements = 8
youngs_modulus = 200e9
poisson = 0.3
density = 7800.0
[[rotor.disk]]
node = 4
outer_diameter = 0.12
width = 0.03
density = 7800.0
[[rotor.bearing]]
node = 0
stiffness = 1.0e8
[[rotor.bearing]]
node = 8
stiffness = 1.0e8
[[rotor.unbalance]]
node = 4
mass = 0.008
radius = 0.045
[[station]]
name = "seal"
node = 4
radius = 0.06
friction = 0.2
[[stator]]
kind = "ring"
name = "seal"
station = "seal"
clearance = 1e-7
stiffness = 36800.0
kinematics = "radial"
[run]
speed_ratio = 0.8
revolutions = 200
transient_revolutions = 100
[run.reduction]
rotor = true
[thermal]
station = "seal"
expansion = 1.2e-5
diameter = 0.01
heated_length = 0.1
gain = 2.5
heating_time = 2.0
cooling_time = 20.0
duration = 30.0
revolutions = 8
initial = [1.0, 0.0]
max_temperature_difference = 1e4
"#;

/// The linear theory of the spiral on an FE rotor (docs/VALIDATION.md §21.2): the 1× response
/// at the station per kelvin, `h = (U_x + i U_y)/2` of
/// `(K + K_ring − Ω²M + iΩ(C + ΩG)) U = F_b(ΔT = 1 K)` with the ring at zero clearance as the
/// real stiffness `k_s [1 −μ; μ 1]` on the station's `[u_x, u_y]` (its normal force `−k_s z`
/// and its friction `−iμ k_s z` against the spin), a dense solve; the loop gain
/// `Λ = G μ k_s Ω R h`; the slow eigenvalues, roots of `(1 + τ_h s)(1 + τ_c s) = Λ`, the larger
/// real part first. Returns (Λ, s).
fn fe_theory(ls: &LoadedScene, model: &Model, omega: f64, ks: f64) -> (C64, C64) {
    let spec = ls.scene.thermal.as_ref().unwrap();
    let lam = spec.gain.unwrap() * fe_loop(ls, model, omega, ks);
    let (p, q, s0) = (
        spec.heating_time.unwrap() * spec.cooling_time.unwrap(),
        spec.heating_time.unwrap() + spec.cooling_time.unwrap(),
        1.0 - lam,
    );
    let d = (q * q - 4.0 * p * s0).sqrt();
    let (s1, s2) = ((-q + d) / (2.0 * p), (-q - d) / (2.0 * p));
    (lam, if s1.re >= s2.re { s1 } else { s2 })
}

/// The FE rotor's loop without the section's law: `Λ/G = μ k_s Ω R h` (W/K), `h` the 1×
/// response at the station per kelvin of [`fe_theory`].
pub(crate) fn fe_loop(ls: &LoadedScene, model: &Model, omega: f64, ks: f64) -> C64 {
    let Rotor::Fe(f) = &model.rotor else {
        panic!("an FE rotor")
    };
    let r = &f.rotor;
    let spec = ls.scene.thermal.as_ref().unwrap();
    let st = &ls.scene.stations[0];
    let body = r.body(omega).unwrap();
    let n = r.ndof_lateral;
    let (k, m, c) = (dense(&body.k), dense(&body.m), dense(&body.c));
    let mut a = nalgebra::DMatrix::<C64>::from_fn(n, n, |i, j| {
        C64::new(k[(i, j)] - omega * omega * m[(i, j)], omega * c[(i, j)])
    });
    let (x, y) = (4 * st.node, 4 * st.node + 1);
    a[(x, x)] += ks;
    a[(y, y)] += ks;
    a[(x, y)] -= st.friction * ks;
    a[(y, x)] += st.friction * ks;
    let zc = r.z[st.node];
    let load = fe_bow_load(r, zc, spec.heated_length, spec.expansion / spec.diameter);
    let mut fb = nalgebra::DVector::<C64>::zeros(n);
    for l in &load {
        fb[l.dof] += C64::new(l.amplitude[0], l.amplitude[1]);
    }
    let u: Vec<C64> = a.lu().solve(&fb).unwrap().iter().copied().collect();
    let h = rotor_frame(&u, [x, y]);
    st.friction * ks * omega * st.radius * C64::new(h[0], h[1])
}

/// The spiral of `FE_SPIRAL` with overrides, and its theory (Λ, s).
fn run_fe(sets: &[&str]) -> (ThermalResults, C64, C64) {
    run_text(FE_SPIRAL, sets)
}

/// The spiral of a scene text with overrides, and its theory (Λ, s).
fn run_text(text: &str, sets: &[&str]) -> (ThermalResults, C64, C64) {
    let (ls, model) = common::scene_model(text, sets);
    let v = ls.scene.run.speed_ratio.unwrap();
    let hs = HotSpot::of_scene(&ls).unwrap();
    let r = run_thermal(&model, &common::settings(&ls), v, &hs).unwrap();
    let (lam, s) = fe_theory(&ls, &model, r.omega, 36800.0);
    (r, lam, s)
}

/// The FE rotor's spiral follows the linear theory with its own receptance, below the coupled
/// critical speed (growing) and above it (settling, turning against the spin), across the
/// threshold. Each run kept to its linear regime.
#[test]
fn the_fe_spiral_follows_the_linear_theory_against_speed() {
    // Measured |Δs|/|s|: 2.3 %, 2.7 %, 0.6 %, 0.1 % (the Jeffcott rotor's 3–5 % below the
    // critical speed, where the growth is a difference of nearly equal terms).
    for (nu, duration, tol) in [
        (0.8, 30.0, 0.05),
        (1.0, 12.0, 0.05),
        (1.3, 30.0, 0.05),
        (2.0, 30.0, 0.05),
    ] {
        let (r, lam, want) = run_fe(&[
            &format!("run.speed_ratio={nu}"),
            &format!("thermal.duration={duration}"),
        ]);
        let got = C64::new(r.growth_rate, r.rotation_rate);
        eprintln!(
            "ν {nu}: Λ = {:.4} ∠ {:.2}°, s = {want:.5} (theory), {got:.5} (run), |Δs|/|s| = {:.3}, {} steps",
            lam.norm(),
            lam.arg().to_degrees(),
            (got - want).norm() / want.norm(),
            r.steps
        );
        assert!(r.unsynchronous_at_s.is_none() && r.runaway_at_s.is_none());
        assert!(
            (got - want).norm() < tol * want.norm(),
            "ν {nu}: {got} against {want}"
        );
        assert_eq!(got.re > 0.0, want.re > 0.0, "ν {nu}");
    }
}

/// The reduced rotor (`[run.reduction]`: 4 modes and the seal's 2 static columns) takes the
/// curvature load through its basis (`Tᵀ F_b`) and spirals as the full rotor does: ΔT over
/// 6 s of machine time within 1e-3 of the full model's (measured 3.5e-5; 8e-5 over 30 s),
/// at 1/37 of the steps (the full model's Δt is the explicit limit of its stiff bearings).
#[test]
fn the_reduced_fe_rotor_spirals_as_the_full_one() {
    let short = ["thermal.duration=6"];
    let (reduced, ..) = run_fe(&short);
    let whole = FE_SPIRAL.replace("[run.reduction]\nrotor = true\n", "");
    let (full, ..) = run_text(&whole, &short);
    assert_eq!(reduced.samples.len(), full.samples.len());
    let worst = (reduced.samples.iter().zip(&full.samples))
        .map(|(a, b)| {
            let d = (a.delta_t[0] - b.delta_t[0]).hypot(a.delta_t[1] - b.delta_t[1]);
            d / b.delta_t[0].hypot(b.delta_t[1])
        })
        .fold(0.0, f64::max);
    eprintln!(
        "reduced against full: ΔT within {worst:.2e}; {} against {} steps",
        reduced.steps, full.steps
    );
    assert!(worst < 1e-3, "{worst}");
    assert!(full.steps > 10 * reduced.steps);
}

const GENERATOR: &str = "scenes/thermal/generator_fe.toml";

/// `scenes/thermal/generator_fe.toml`: the generator-like rotor at 1 500 rpm, below its first
/// critical, with the accelerated coupling (h = 5 s) over ten minutes: the spiral grows, at the
/// linear theory's rate and rotation with the rotor's own receptance (k_s 2 MN/m); the run
/// stays synchronous and the bow along the shaft is reported.
#[test]
fn the_generator_scene_spirals_as_the_linear_theory_says() {
    let (ls, model) = common::file_model(&common::repo(GENERATOR), common::NO_SETS);
    let hs = HotSpot::of_scene(&ls).unwrap();
    let speed = ls.scene.run.speed.unwrap() / model.rotor.natural_frequency();
    let r = run_thermal(&model, &common::settings(&ls), speed, &hs).unwrap();
    let (lam, want) = fe_theory(&ls, &model, r.omega, 2.0e6);
    let got = C64::new(r.growth_rate, r.rotation_rate);
    eprintln!(
        "generator, ν {speed:.3}: Λ = {:.4} ∠ {:.2}°, s = {want:.3e} (theory), {got:.3e} (run), |Δs|/|s| = {:.3}; {} steps, bow {:.3e} m/K",
        lam.norm(),
        lam.arg().to_degrees(),
        (got - want).norm() / want.norm(),
        r.steps,
        r.bow_per_kelvin
    );
    assert!(r.unsynchronous_at_s.is_none() && r.runaway_at_s.is_none());
    assert!(want.re > 0.0 && got.re > 0.0);
    assert!(
        // Measured 1.2 % (the accelerated coupling's h = 5 s against the spiral's 530 s).
        (got - want).norm() < 0.05 * want.norm(),
        "{got} against {want}"
    );
    assert_eq!(r.bow_shape.len(), 17);
    // The bow is largest at mid-body and points at the hot side (ΔT's direction).
    let last = r.samples.last().unwrap().delta_t;
    let b = r.bow_shape[8].bow;
    assert!((b[0] * last[0] + b[1] * last[1]) > 0.0);
    let mag = |p: &rubsim::analysis::thermal::BowPoint| p.bow[0].hypot(p.bow[1]);
    assert!(r
        .bow_shape
        .iter()
        .all(|p| mag(p) <= mag(&r.bow_shape[8]) * (1.0 + 1e-12)));
}

/// `rubsim run` of the generator scene writes the spiral's files and the bow along the shaft.
#[test]
fn the_run_command_writes_the_fe_spiral_and_the_bow_shape() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("gen");
    let stdout = cli::ok(
        &common::repo(""),
        &[
            "run",
            GENERATOR,
            "--set",
            "thermal.duration=60",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(stdout.contains("thermal spiral"), "{stdout}");
    for f in [
        "spiral.csv",
        "spiral.png",
        "thermal.png",
        "bow_shape.csv",
        "summary.json",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let csv = common::read(&out.join("bow_shape.csv"));
    assert!(csv.starts_with(rubsim::output::thermal::BOW_SHAPE_HEADER));
    assert_eq!(csv.lines().count(), 18);
}

/// Bad input on an FE rotor: a `span` (the rotor stands on its bearings), a heated length
/// running past the shaft's ends, a heated station whose node is not on the shaft — each
/// refused naming its key.
#[test]
fn bad_fe_thermal_input_is_refused_by_key() {
    let cases: [(&[&str], &str); 4] = [
        (&["thermal.span=3.2"], "thermal.span"),
        (&["thermal.heated_length=3.5"], "thermal.heated_length"),
        (
            &["station.0.node=15", "thermal.heated_length=0.6"],
            "thermal.heated_length",
        ),
        (&["station.0.node=40"], "station.0.node"),
    ];
    for (sets, key) in cases {
        let mut args = vec!["check", GENERATOR];
        for s in sets {
            args.extend(["--set", s]);
        }
        let err = cli::fails(&common::repo(""), &args);
        assert!(err.contains(key), "{sets:?}: {err}");
    }
}
