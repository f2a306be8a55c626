//! The Timoshenko FE rotor as a model: bad input named by its key (in the scene and in the
//! model layer), modes labelled lateral/axial/torsional, the torsional option leaving the
//! lateral model and response alone, ω/ω_n referring to the first lateral mode, speed-dependent
//! matrices refilled on one pattern, and the block-tridiagonal step solve.
//!
//! Its closed forms and published numbers are checked in `verification.rs`, its orders of
//! convergence in `convergence.rs`, its golden matrices in `regression.rs`.

use crate::common;

use common::fe::{block_frequencies, fe};
use common::scenes::{full_rotor, FRISWELL, GOLDEN_ROTOR, PAPER_FE, PAPER_TORSION};
use common::{model, parse, run_speed, NO_SETS, SHORT_RUN};
use rubsim::linear::{self, Whirl};
use rubsim::model::Rotor;
use rubsim::scene;
use std::path::Path;

// ---------------------------------------------------------------------------------------------
// Bad input.

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
            base.replace("stiffness = 2.0e4", "stiffness = -2.0e4"),
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
        // Free θ_z (no restraint, or one of zero stiffness) under a rubbing station's friction.
        (
            PAPER_TORSION.replace("stiffness = 1000.0", "stiffness = 0.0"),
            "rotor.torsional_support.0.stiffness",
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
    use rubsim::resolve::rotor::fe_rotor;
    let ls = parse(&full_rotor(true, true), NO_SETS);
    let spec = match &ls.scene.rotor {
        rubsim::scene::RotorSpec::Fe(f) => f.clone(),
        _ => unreachable!(),
    };
    let good = fe_rotor(&ls, &spec).unwrap();
    assert!(FeRotor::build(&good).is_ok());
    // Without supports (or with zero stiffness, ROSS's kzz = 0) the DOFs are free.
    let mut d = good.clone();
    d.torsional_supports.clear();
    d.axial_supports[0].stiffness = 0.0;
    let free = FeRotor::build(&d).unwrap();
    assert!(free.free_axial && free.free_torsion);
    assert!(!FeRotor::build(&good).unwrap().free_axial);
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

// ---------------------------------------------------------------------------------------------
// Axial and torsional DOFs (`[rotor] axial = true`, `torsion = true`).

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
        let r = linear::modal(&m.rotor, spin, nmodes).unwrap();
        let roff = linear::modal(&off.rotor, spin, nmodes).unwrap();
        let (mut na, mut nt) = (0, 0);
        for md in r.modes.iter().filter(|x| x.omega_d < top) {
            let e = md.energy;
            assert!((e.iter().sum::<f64>() - 1.0).abs() < 1e-9);
            match md.kind {
                linear::ModeKind::Axial => {
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
                linear::ModeKind::Torsional => {
                    assert!(e[2] > 1.0 - 1e-9 && md.label() == "torsional");
                    assert!(
                        (md.omega_d / wt[nt] - 1.0).abs() < 1e-7,
                        "{} vs {}",
                        md.omega_d,
                        wt[nt]
                    );
                    nt += 1;
                }
                linear::ModeKind::Lateral => {
                    assert!(e[0] > 1.0 - 1e-9);
                    // At rest the whirl is undefined: an isotropic rotor's lateral modes come in
                    // degenerate pairs (any combination of the two is an eigenvector), and on
                    // anisotropic bearings they are planar (κ = 0 at every node), which only
                    // round-off labelled forward or backward before the ω-scaled modal solve.
                    let degenerate = r
                        .modes
                        .iter()
                        .filter(|x| (x.omega_d / md.omega_d - 1.0).abs() < 1e-6)
                        .count()
                        > 1;
                    let planar = md.kappa.iter().all(|k| k.abs() < 1e-6);
                    assert!(
                        matches!(md.whirl, Whirl::Forward | Whirl::Backward)
                            || (spin == 0.0 && (degenerate || planar)),
                        "{:?} at {spin} rad/s, {} rad/s",
                        md.whirl,
                        md.omega_d
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
    let c = rubsim::linear::campbell(&m.rotor, &speeds, 12).unwrap();
    let tors: Vec<_> = c
        .tracks
        .iter()
        .filter(|t| t.kind == linear::ModeKind::Torsional)
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
    let (rt, rl) = (
        run_speed(PAPER_TORSION, &SHORT_RUN, 1.7),
        run_speed(PAPER_FE, &SHORT_RUN, 1.7),
    );
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
    let plain = model(PAPER_FE);
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

// ---------------------------------------------------------------------------------------------
// Matrices and the step solve.

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
