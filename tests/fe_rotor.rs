//! Verification of the Timoshenko FE rotor (issue 3).

use rubsim::analysis::rotordyn::{self, Whirl};
use rubsim::model::{Model, Rotor};
use rubsim::scene;
use std::f64::consts::PI;
use std::path::Path;

fn model(text: &str) -> Model {
    let ls = scene::parse(Path::new("t.toml"), text, &[]).expect("scene");
    Model::from_scene(&ls).expect("model")
}

fn fe(r: &Rotor) -> &rubsim::model::FeModel {
    match r {
        Rotor::Fe(f) => f,
        _ => panic!("FE rotor expected"),
    }
}

const RUN: &str = "[run]\nspeed_ratio = 1.0\n";

/// Simply supported uniform shaft (stiff bearings at both ends), `n` elements.
fn ss_shaft(n: usize, shear: bool) -> String {
    format!(
        r#"
[rotor]
kind = "fe"
shear = {shear}
[[rotor.shaft]]
length = 2.0
outer_diameter = 0.2
elements = {n}
youngs_modulus = 2.1e11
poisson = 0.3
density = 7800.0
[[rotor.bearing]]
node = 0
stiffness = 1.0e14
[[rotor.bearing]]
node = {n}
stiffness = 1.0e14
{RUN}"#
    )
}

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

/// Friswell et al. (2010) Example 5.9.1 / ROSS `rotor_example`: 1.5 m, 50 mm steel shaft in 6
/// elements, disks (70 mm wide, bore 50 mm) of 280 mm at node 2 and 350 mm at node 4, bearings
/// of 1 MN/m at the ends.
const FRISWELL: &str = r#"
[rotor]
kind = "fe"
[[rotor.shaft]]
length = 1.5
outer_diameter = 0.05
elements = 6
youngs_modulus = 211e9
poisson = 0.29926
density = 7810.0
[[rotor.disk]]
node = 2
outer_diameter = 0.28
bore = 0.05
width = 0.07
density = 7810.0
[[rotor.disk]]
node = 4
outer_diameter = 0.35
bore = 0.05
width = 0.07
density = 7810.0
[[rotor.bearing]]
node = 0
stiffness = 1.0e6
[[rotor.bearing]]
node = 6
stiffness = 1.0e6
[run]
speed_ratio = 1.0
"#;

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
        let r = rotordyn::modal(&m.rotor, rpm * 2.0 * PI / 60.0, 4).unwrap();
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

const PAPER_FE: &str = include_str!("../scenes/fe/paper_rotor_rub.toml");
fn run_at(text: &str, nu: f64) -> rubsim::analysis::SpeedResults {
    let ov: Vec<String> = vec![
        "run.revolutions=80".into(),
        "run.transient_revolutions=40".into(),
        "run.error_estimate=false".into(),
    ];
    let ls = scene::parse(Path::new("t.toml"), text, &ov).unwrap();
    let m = Model::from_scene(&ls).unwrap();
    let s = rubsim::analysis::RunSettings::from_run(&ls.scene.run, "y");
    rubsim::analysis::run_speed(&m, &s, nu, rubsim::analysis::Keep::default()).unwrap()
}

#[test]
fn bad_fe_rotor_input_names_the_item() {
    let cases = [
        (
            FRISWELL.replace("node = 6\nstiffness = 1.0e6", "node = 9\nstiffness = 1.0e6"),
            "rotor.bearing.1.node",
        ),
        (
            FRISWELL.replace(
                "node = 4\nouter_diameter = 0.35",
                "node = 12\nouter_diameter = 0.35",
            ),
            "rotor.disk.1.node",
        ),
        (
            FRISWELL.replace("length = 1.5", "length = 0.0"),
            "rotor.shaft.0.length",
        ),
        (
            FRISWELL.replace(
                "outer_diameter = 0.05\nelements",
                "outer_diameter = -0.05\nelements",
            ),
            "rotor.shaft.0.outer_diameter",
        ),
        (
            FRISWELL
                .replace("[[rotor.bearing]]\nnode = 0\nstiffness = 1.0e6\n", "")
                .replace("[[rotor.bearing]]\nnode = 6\nstiffness = 1.0e6\n", ""),
            "bearing",
        ),
        (
            FRISWELL.replace(
                "[run]",
                "[[station]]\nname = \"s\"\nnode = 7\nradius = 0.1\n[run]",
            ),
            "station.0.node",
        ),
        (
            FRISWELL.replace("[run]", "[rotor.modal_damping]\nratio = -0.1\n[run]"),
            "rotor.modal_damping.ratio",
        ),
        (
            FRISWELL.replace(
                "[run]",
                "[rotor.modal_damping]\nratio = 0.1\nmodes = 0\n[run]",
            ),
            "rotor.modal_damping.modes",
        ),
    ];
    for (text, key) in cases {
        let e = scene::parse(Path::new("bad.toml"), &text, &[])
            .unwrap_err()
            .to_string();
        assert!(e.contains(key) && e.contains("bad.toml"), "{key}: {e}");
    }
}

/// A rotor with every lateral feature (cross-coupled bearing, pedestal, point mass, Rayleigh
/// damping, gyroscopics) for the golden comparison of the assembled matrices.
const GOLDEN_ROTOR: &str = r#"
[rotor]
kind = "fe"
rayleigh = [1.5, 2.0e-5]
[[rotor.shaft]]
length = 1.5
outer_diameter = 0.05
inner_diameter = 0.01
elements = 6
material = "steel"
[[rotor.disk]]
node = 2
outer_diameter = 0.28
bore = 0.05
width = 0.07
density = 7810.0
[[rotor.point_mass]]
node = 5
mass = 1.25
[[rotor.bearing]]
node = 0
kxx = 1.0e6
kxy = 2.0e5
kyx = -2.0e5
kyy = 1.5e6
cxx = 300.0
cyy = 400.0
[[rotor.bearing]]
node = 6
stiffness = 1.0e6
damping = 250.0
pedestal = { mass = 12.0, stiffness = 3.0e7, damping = 900.0 }
[run]
speed_ratio = 1.0
"#;

// ---------------------------------------------------------------------------------------------
// Axial and torsional DOFs (`[rotor] axial = true`, `torsion = true`).
// ---------------------------------------------------------------------------------------------

/// Rows/columns `dofs` of a sparse matrix as a new sparse matrix (renumbered 0..dofs.len()).
fn sub(a: &rubsim::linalg::Csc, dofs: &[usize]) -> rubsim::linalg::Csc {
    let mut at = vec![usize::MAX; a.nrows()];
    for (i, d) in dofs.iter().enumerate() {
        at[*d] = i;
    }
    let t: Vec<(usize, usize, f64)> = a
        .triplets()
        .filter(|(r, c, _)| at[*r] != usize::MAX && at[*c] != usize::MAX)
        .map(|(r, c, v)| (at[r], at[c], v))
        .collect();
    rubsim::linalg::Csc::from_triplets(dofs.len(), dofs.len(), &t)
}

/// Natural frequencies (rad/s) of the block of `dofs` of the rotor at rest.
fn block_frequencies(f: &rubsim::model::fe_rotor::FeRotor, dofs: &[usize]) -> Vec<f64> {
    let (lam, _) = rotordyn::undamped_modes(&sub(&f.m, dofs), &sub(&f.k(0.0), dofs)).unwrap();
    lam.iter().map(|l| l.max(0.0).sqrt()).collect()
}

/// Disk of polar inertia `ip` at the free end (node `n`) of a steel shaft 0.5 m × 20 mm in `n`
/// elements whose left end (node 0) is held in torsion by `k0` N·m/rad.
fn torsion_disk(n: usize, ip: f64, k0: f64) -> String {
    format!(
        r#"
[rotor]
kind = "fe"
torsion = true
[[rotor.shaft]]
length = 0.5
outer_diameter = 0.02
elements = {n}
youngs_modulus = 2.1e11
poisson = 0.3
density = 7800.0
[[rotor.disk]]
node = {n}
mass = 5.0
polar_inertia = {ip}
diametral_inertia = 0.003
[[rotor.bearing]]
node = 0
stiffness = 1.0e7
[[rotor.bearing]]
node = {n}
stiffness = 1.0e7
[[rotor.torsional_support]]
node = 0
stiffness = {k0}
{RUN}"#
    )
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

/// A rotor with every feature, `axial` and `torsion` set as given.
fn full_rotor(axial: bool, torsion: bool) -> String {
    let mut t = GOLDEN_ROTOR.replace(
        "rayleigh = [1.5, 2.0e-5]",
        &format!("rayleigh = [1.5, 2.0e-5]\naxial = {axial}\ntorsion = {torsion}"),
    );
    let mut extra = String::new();
    if axial {
        extra.push_str("[[rotor.axial_support]]\nnode = 0\nstiffness = 5.0e8\ndamping = 2.0e3\n");
    }
    if torsion {
        extra.push_str("[[rotor.torsional_support]]\nnode = 6\nstiffness = 2.0e4\ndamping = 3.0\n");
    }
    t = t.replace("[run]", &format!("{extra}[run]"));
    t
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

/// Modal analysis labels modes by where their kinetic energy sits: lateral (FW/BW), axial,
/// torsional. The axial and torsional frequencies equal their blocks' and do not move with the
/// spin (G has no entries there); the lateral ones are those of the model without the option.
#[test]
fn modal_and_campbell_label_axial_and_torsional_modes() {
    let text = full_rotor(true, true)
        .replace("rayleigh = [1.5, 2.0e-5]", "rayleigh = [0.0, 0.0]")
        .replace("damping = 2.0e3", "damping = 0.0")
        .replace("damping = 3.0", "damping = 0.0");
    let m = model(&text);
    let f = &fe(&m.rotor).rotor;
    let ax: Vec<usize> = f.node_axial.iter().map(|d| d.unwrap()).collect();
    let to: Vec<usize> = f.node_torsion.iter().map(|d| d.unwrap()).collect();
    let wa = block_frequencies(f, &ax);
    let wt = block_frequencies(f, &to);
    let off = model(
        &full_rotor(false, false).replace("rayleigh = [1.5, 2.0e-5]", "rayleigh = [0.0, 0.0]"),
    );
    let top = 1.2 * wa[0].max(wt[1]);
    let nmodes = 40;
    for spin in [0.0, 300.0] {
        let r = rotordyn::modal(&m.rotor, spin, nmodes).unwrap();
        let roff = rotordyn::modal(&off.rotor, spin, nmodes).unwrap();
        let (mut na, mut nt) = (0, 0);
        for md in r.modes.iter().filter(|x| x.omega_d < top) {
            let e = md.energy;
            assert!((e.iter().sum::<f64>() - 1.0).abs() < 1e-9);
            match md.kind {
                rotordyn::ModeKind::Axial => {
                    assert!(
                        e[1] > 1.0 - 1e-9 && md.whirl == Whirl::NoWhirl && md.label() == "axial"
                    );
                    assert!(
                        (md.omega_d / wa[na] - 1.0).abs() < 1e-7,
                        "{} vs {}",
                        md.omega_d,
                        wa[na]
                    );
                    na += 1;
                }
                rotordyn::ModeKind::Torsional => {
                    assert!(e[2] > 1.0 - 1e-9 && md.label() == "torsional");
                    assert!(
                        (md.omega_d / wt[nt] - 1.0).abs() < 1e-7,
                        "{} vs {}",
                        md.omega_d,
                        wt[nt]
                    );
                    nt += 1;
                }
                rotordyn::ModeKind::Lateral => {
                    assert!(e[0] > 1.0 - 1e-9);
                    assert!(
                        matches!(md.whirl, Whirl::Forward | Whirl::Backward),
                        "{:?}",
                        md.whirl
                    );
                    // Same frequency among the model without axial/torsional DOFs.
                    let near = roff
                        .modes
                        .iter()
                        .map(|x| (x.omega_d / md.omega_d - 1.0).abs())
                        .fold(f64::INFINITY, f64::min);
                    assert!(
                        near < 1e-7,
                        "lateral mode {} not in the lateral model",
                        md.omega_d
                    );
                }
            }
        }
        eprintln!(
            "Ω = {spin}: {na} axial (first {:.2} rad/s), {nt} torsional (first two {:.2}, {:.2} rad/s) below {top:.0} rad/s",
            wa[0], wt[0], wt[1]
        );
        assert!(na >= 1 && nt >= 2);
    }
    // Campbell: the torsional and axial tracks are flat and labelled so.
    let speeds: Vec<f64> = (0..6).map(|i| i as f64 * 200.0).collect();
    let c = rotordyn::campbell(&m.rotor, &speeds, 12).unwrap();
    let tors: Vec<_> = c
        .tracks
        .iter()
        .filter(|t| t.kind == rotordyn::ModeKind::Torsional)
        .collect();
    assert!(!tors.is_empty());
    for t in tors {
        assert!(t.label.ends_with("torsional"), "{}", t.label);
        let w0 = t.omega_d[0];
        assert!(
            t.omega_d.iter().all(|w| (w / w0 - 1.0).abs() < 1e-7),
            "{:?}",
            t.omega_d
        );
    }
}

const PAPER_TORSION: &str = include_str!("../scenes/fe/paper_rotor_rub_torsion.toml");

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
        let ov: Vec<String> = vec![
            "run.revolutions=80".into(),
            "run.transient_revolutions=40".into(),
            "run.error_estimate=false".into(),
        ];
        let ls = scene::parse(Path::new("t.toml"), text, &ov).unwrap();
        let m = Model::from_scene(&ls).unwrap();
        let f = &fe(&m.rotor).rotor;
        let case = m.case(nu * m.rotor.natural_frequency()).unwrap();
        let mut st = rubsim::analysis::RunSettings::from_run(&ls.scene.run, "y").step;
        st.integrator = kind;
        let plan = rubsim::time::plan_steps(&case, &st).unwrap();
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

#[test]
fn bad_axial_torsion_input_names_the_item() {
    let base = full_rotor(true, true);
    let cases = [
        (
            base.replace("node = 6\nstiffness = 2.0e4", "node = 7\nstiffness = 2.0e4"),
            "rotor.torsional_support.0.node",
        ),
        (
            base.replace(
                "node = 0\nstiffness = 5.0e8",
                "node = 40\nstiffness = 5.0e8",
            ),
            "rotor.axial_support.0.node",
        ),
        (
            base.replace("stiffness = 5.0e8", "stiffness = -5.0e8"),
            "rotor.axial_support.0.stiffness",
        ),
        (
            base.replace("stiffness = 2.0e4", "stiffness = 0.0"),
            "rotor.torsional_support.0.stiffness",
        ),
        (
            base.replace("damping = 3.0", "damping = -3.0"),
            "rotor.torsional_support.0.damping",
        ),
        (
            full_rotor(true, true).replace("torsion = true", "torsion = false"),
            "rotor.torsional_support.0",
        ),
        (
            full_rotor(true, false).replace(
                "[[rotor.axial_support]]\nnode = 0\nstiffness = 5.0e8\ndamping = 2.0e3\n",
                "",
            ),
            "rotor.axial",
        ),
        (
            full_rotor(false, false).replace("torsion = false", "torsion = true"),
            "rotor.torsion",
        ),
    ];
    for (text, key) in cases {
        let e = scene::parse(Path::new("bad.toml"), &text, &[])
            .unwrap_err()
            .to_string();
        eprintln!("{key}: {e}");
        assert!(e.contains(key) && e.contains("bad.toml"), "{key}: {e}");
    }
    // The model layer refuses the same on its own (library users who skip the scene).
    use rubsim::model::fe_rotor::{FeRotor, GroundSpring};
    use rubsim::resolve::rotor::data_from_spec;
    let ls = scene::parse(Path::new("t.toml"), &full_rotor(true, true), &[]).unwrap();
    let spec = match &ls.scene.rotor {
        rubsim::scene::RotorSpec::Fe(f) => f.clone(),
        _ => unreachable!(),
    };
    let good = data_from_spec(&spec);
    assert!(FeRotor::build(&good).is_ok());
    let mut d = good.clone();
    d.torsional_supports.clear();
    let e = FeRotor::build(&d).unwrap_err().to_string();
    assert!(e.contains("torsional restraint"), "{e}");
    let mut d = good.clone();
    d.axial_supports.clear();
    let e = FeRotor::build(&d).unwrap_err().to_string();
    assert!(e.contains("axial support"), "{e}");
    let mut d = good.clone();
    d.axial_supports.push(GroundSpring {
        node: 9,
        stiffness: 1.0,
        damping: 0.0,
    });
    let e = FeRotor::build(&d).unwrap_err().to_string();
    assert!(
        e.contains("rotor axial support 1") && e.contains("node 9"),
        "{e}"
    );
    let mut d = good.clone();
    d.torsional_supports[0].stiffness = -1.0;
    let e = FeRotor::build(&d).unwrap_err().to_string();
    assert!(
        e.contains("rotor torsional support 0") && e.contains("stiffness"),
        "{e}"
    );
    let mut d = good;
    d.axial = false;
    let e = FeRotor::build(&d).unwrap_err().to_string();
    assert!(
        e.contains("rotor axial support 0") && e.contains("no axial DOFs"),
        "{e}"
    );
}

/// The torsion scene is the paper rotor plus θ_z: ω_n (first lateral mode), k_r and |Z0| are
/// those of scenes/fe/paper_rotor_rub.toml, and so is the rub's lateral response (torsion is
/// uncoupled from bending; the friction torque only twists the shaft).
#[test]
fn torsion_scene_keeps_the_lateral_model_and_response() {
    let (t, l) = (model(PAPER_TORSION), model(PAPER_FE));
    let (ft, fl) = (fe(&t.rotor), fe(&l.rotor));
    assert_eq!(ft.rotor.ndof, fl.rotor.ndof + 9);
    assert_eq!(
        ft.rotor.lateral_frequencies(0.0).unwrap(),
        fl.rotor.undamped_frequencies(0.0).unwrap()
    );
    // The model's ω_n is the lowest positive frequency of all DOFs: lateral here (the first
    // torsional mode is at ≈ 238 rad/s).
    assert!((ft.omega_n / fl.omega_n - 1.0).abs() < 1e-9);
    assert_eq!(ft.k_ref, fl.k_ref);
    assert!(ft.omega_max >= fl.omega_max);
    let w = 1.7 * fl.omega_n;
    assert_eq!(t.rotor.z0(4, w).unwrap(), l.rotor.z0(4, w).unwrap());
    // Same Δt and response up to the rounding of ω_n (~1e-11).
    let (rt, rl) = (run_at(PAPER_TORSION, 1.7), run_at(PAPER_FE, 1.7));
    assert_eq!(rt.period, rl.period);
    assert!((rt.plan.dt / rl.plan.dt - 1.0).abs() < 1e-9);
    let diff = (0..4)
        .map(|i| (rt.extents_nd[i] - rl.extents_nd[i]).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "torsion scene vs lateral-only at ν = 1.7: ω_n {} vs {}, extents differ by {diff:.2e}",
        ft.omega_n, fl.omega_n
    );
    for i in 0..4 {
        assert!(
            (rt.extents_nd[i] - rl.extents_nd[i]).abs() < 1e-7,
            "{:?} vs {:?}",
            rt.extents_nd,
            rl.extents_nd
        );
    }
}

/// ω/ω_n refers to the first lateral mode even when a soft drive puts a torsional mode below
/// it: the torsion scene with a 50 N·m/rad coupling (torsional mode ≈ 96 rad/s) keeps the
/// lateral ω_n of the scene without torsion, while ω_max (stability) covers every DOF.
#[test]
fn speed_ratio_refers_to_the_first_lateral_mode() {
    let plain = model(include_str!("../scenes/fe/paper_rotor_rub.toml"));
    let soft = PAPER_TORSION.replace("stiffness = 1000.0", "stiffness = 50.0");
    assert_ne!(soft, PAPER_TORSION);
    let tors = model(&soft);
    let (Rotor::Fe(a), Rotor::Fe(b)) = (&plain.rotor, &tors.rotor) else {
        panic!("FE rotors expected")
    };
    let all = b.rotor.undamped_frequencies(0.0).unwrap();
    assert!(
        all[0] < 0.7 * a.omega_n,
        "a torsional mode below ω_n: {all:?}"
    );
    assert!(
        (b.omega_n - a.omega_n).abs() < 1e-9 * a.omega_n,
        "{} vs {}",
        b.omega_n,
        a.omega_n
    );
    assert!(b.omega_max >= *all.last().unwrap() * (1.0 - 1e-12));
}

/// The paper rotor with modal damping instead of Rayleigh damping.
fn paper_modal(ratio: f64, limit: &str) -> String {
    PAPER_FE.replace(
        "rayleigh = [65.3, 0.0]\n",
        &format!("\n[rotor.modal_damping]\nratio = {ratio}\n{limit}\n"),
    )
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
        let r = rotordyn::modal(&m.rotor, 0.0, 4).unwrap();
        let z: Vec<f64> = r.modes.iter().map(|md| md.damping_ratio).collect();
        assert!(
            (z[0] - 0.05).abs() < 1e-6 && (z[1] - 0.05).abs() < 1e-6,
            "{limit}: {z:?}"
        );
        assert!(z[2].abs() < 1e-6 && z[3].abs() < 1e-6, "{limit}: {z:?}");
    }
    // Without a limit every mode gets ζ.
    let m = model(&paper_modal(0.03, ""));
    let r = rotordyn::modal(&m.rotor, 0.0, 6).unwrap();
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
    use rubsim::analysis::{self, Keep, RunSettings};
    let text = paper_modal(0.05, "modes = 2");
    let free = [
        "stator.0.clearance_nd=100".to_string(),
        "run.error_estimate=false".to_string(),
        "run.revolutions=80".to_string(),
        "run.transient_revolutions=70".to_string(),
        "run.harmonics=16".to_string(),
    ];
    let ls = scene::parse(Path::new("t.toml"), &text, &free).unwrap();
    let model = Model::from_scene(&ls).unwrap();
    let s = RunSettings::from_run(&ls.scene.run, "y");
    let r = analysis::run_speed(&model, &s, 1.0, Keep::default()).unwrap();
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
    let ls = scene::parse(Path::new("t.toml"), &text, &ov).unwrap();
    let model = Model::from_scene(&ls).unwrap();
    let Rotor::Fe(f) = &model.rotor else { panic!() };
    let wn = f.omega_n;
    let omega = 0.3 * wn;
    let case = model.case(omega).unwrap();
    let mut st = RunSettings::from_run(&ls.scene.run, "y");
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

/// K(Ω) and C(Ω) are refilled on one pattern built at assembly: with a bearing whose
/// coefficients are tabulated over speed (one of them crossing zero), the pattern is the
/// same at every speed and the values equal a fresh triplet assembly exactly.
#[test]
fn speed_dependent_matrices_are_refilled_on_one_pattern() {
    let text = FRISWELL.replacen(
        "[[rotor.bearing]]\nnode = 0\nstiffness = 1.0e6\n",
        "[[rotor.bearing]]\nnode = 0\nspeeds = [0.0, 200.0, 400.0]\nkxx = [1.0e6, 2.0e6, 3.0e6]\nkyy = [1.0e6, 1.5e6, 2.5e6]\nkxy = [0.0, 4.0e5, -2.0e5]\nkyx = [0.0, -4.0e5, 2.0e5]\ncxx = [100.0, 300.0, 500.0]\ncyy = 200.0\n",
        1,
    );
    assert_ne!(text, FRISWELL);
    let m = model(&text);
    let f = &fe(&m.rotor).rotor;
    let positions = |a: &rubsim::linalg::Csc| -> Vec<(usize, usize)> {
        a.triplets().map(|(r, c, _)| (r, c)).collect()
    };
    let (k0, c0) = (f.k(0.0), f.c_sparse(0.0));
    for w in [0.0, 150.0, 200.0, 333.0, 500.0] {
        let (k, c) = (f.k(w), f.c_sparse(w));
        assert_eq!(positions(&k), positions(&k0));
        assert_eq!(positions(&c), positions(&c0));
        let (kb, cb) = f.bearing_matrices(w);
        let k_ref = rubsim::linalg::Csc::lin_comb(1.0, &f.k_shaft, 1.0, &kb);
        let ray = rubsim::linalg::Csc::lin_comb(f.rayleigh[0], &f.m, f.rayleigh[1], &k_ref);
        let c_ref = rubsim::linalg::Csc::lin_comb(1.0, &cb, 1.0, &ray);
        for (a, b) in [(&k, &k_ref), (&c, &c_ref)] {
            for (r, col, v) in a.triplets() {
                assert!(
                    v == b.get(r, col),
                    "({r}, {col}) at {w}: {v} vs {}",
                    b.get(r, col)
                );
            }
            for (r, col, v) in b.triplets() {
                assert!(
                    v == a.get(r, col),
                    "({r}, {col}) at {w}: {v} vs {}",
                    a.get(r, col)
                );
            }
        }
    }
    // kxy is zero at Ω = 0 yet keeps its slot.
    let k = f.k(0.0);
    assert!(k.slot(0, 1).is_some() && k.get(0, 1) == 0.0);
}

/// The time loop's block-tridiagonal solve of M̃ = M/Δt² + (C + ΩG)/(2Δt) (shaft chains in
/// 4-DOF node blocks) agrees with the pivoting sparse LU on the spinning two-disk rotor; with a
/// pedestal (DOFs numbered after the shaft, coupled to a bearing node far away) the pattern is
/// not block tridiagonal and the general LU is used instead.
#[test]
fn block_tridiagonal_step_solve_matches_the_sparse_lu() {
    use rubsim::linalg::{BlockTridiag, Csc, Lu};
    let m = model(FRISWELL);
    let case = m.case(300.0).unwrap();
    let dt = 1e-5;
    let mt = Csc::lin_comb(
        1.0 / (dt * dt),
        &case.rotor.m,
        1.0 / (2.0 * dt),
        &case.rotor.c,
    );
    assert!(mt.asymmetry() > 0.0, "gyroscopic M̃ is unsymmetric");
    let bt = BlockTridiag::new(&mt).unwrap().expect("shaft chain");
    let n = mt.nrows();
    let x: Vec<f64> = (0..n).map(|i| ((i * 13) as f64).sin()).collect();
    let mut b = vec![0.0; n];
    mt.mul_add(1.0, &x, &mut b);
    let mut b2 = b.clone();
    bt.solve_in_place(&mut b);
    Lu::new(&mt).unwrap().solve_in_place(&mut b2);
    let scale = x.iter().fold(0.0_f64, |a, v| a.max(v.abs()));
    for i in 0..n {
        assert!(
            (b[i] - x[i]).abs() < 1e-10 * scale,
            "{i}: {} vs {}",
            b[i],
            x[i]
        );
        assert!((b[i] - b2[i]).abs() < 1e-10 * scale);
    }
    let gm = model(GOLDEN_ROTOR);
    let g = &fe(&gm.rotor).rotor;
    assert!(g.ndof > 4 * g.nodes(), "the golden rotor has a pedestal");
    let mtp = Csc::lin_comb(
        1.0 / (dt * dt),
        &g.m,
        1.0 / (2.0 * dt),
        &g.c(100.0).unwrap(),
    );
    assert!(
        BlockTridiag::new(&mtp).unwrap().is_none(),
        "pedestal DOFs break the chain"
    );
}
