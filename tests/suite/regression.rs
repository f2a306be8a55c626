//! Regression: results pinned to a golden file or to known values, so that any change shows.
//! The FE rotor's assembled matrices bit for bit against `tests/data/fe_rotor_lateral_golden.txt`
//! (also with the axial and torsional options on), the paper's regimes at pinned speeds with
//! both integrators, and the FE paper rotor's regimes and orbits against the Jeffcott rotor's.

use crate::common;

use common::fe::{fe, sub};
use common::scenes::{full_rotor, GOLDEN_ROTOR, PAPER, PAPER_FE};
use common::{model, repo, run_speed, scene_model, settings, NO_SETS, SHORT_RUN};
use rubsim::analysis::{self, Keep};
use rubsim::linear;
use std::f64::consts::PI;

/// The golden file of the assembled lateral matrices.
const GOLDEN_FILE: &str = "tests/data/fe_rotor_lateral_golden.txt";

// ---------------------------------------------------------------------------------------------
// FE rotor matrices against the golden file.

/// The assembled M, K(Ω), C(Ω), G as `name row col bits` lines (exact f64 bit patterns).
fn matrix_fingerprint(text: &str, omega: f64, ndof: Option<usize>) -> String {
    let m = model(text);
    let f = &fe(&m.rotor).rotor;
    let n = ndof.unwrap_or(f.ndof);
    let mut out = String::new();
    for (name, a) in [
        ("M", f.m.clone()),
        ("K", f.k(omega)),
        ("C", f.c(omega).unwrap()),
        ("G", f.g.clone()),
    ] {
        // K(Ω) and C(Ω) are refilled on a pattern built once (the union over speeds), which
        // stores zeros that a per-speed assembly would drop: compare their values only.
        let refilled = name == "K" || name == "C";
        let mut t: Vec<(usize, usize, f64)> = a
            .triplets()
            .filter(|(r, c, v)| *r < n && *c < n && !(refilled && *v == 0.0))
            .collect();
        t.sort_by_key(|(r, c, _)| (*r, *c));
        for (r, c, v) in t {
            out.push_str(&format!("{name} {r} {c} {:016x}\n", v.to_bits()));
        }
    }
    out
}

/// (d) With axial and torsional DOFs off, M, K, C and G equal, bit for bit, those assembled
/// before the axial/torsion option existed (`tests/data/fe_rotor_lateral_golden.txt`,
/// regenerate with `UPDATE_GOLDEN=1`).
#[test]
fn lateral_matrices_match_golden_bit_for_bit() {
    let path = repo(GOLDEN_FILE);
    let now = matrix_fingerprint(GOLDEN_ROTOR, 120.0, None);
    if std::env::var_os("UPDATE_GOLDEN").is_some() {
        std::fs::write(&path, &now).unwrap();
    }
    let golden = std::fs::read_to_string(&path).expect("golden file");
    assert_eq!(now.lines().count(), golden.lines().count());
    for (a, b) in now.lines().zip(golden.lines()) {
        assert_eq!(a, b, "assembled matrices differ from the golden file");
    }
}

/// (d) M and K symmetric, G skew with no axial or torsional entries, no coupling between the
/// lateral, axial and torsional groups in M, K, C, G; the lateral block equal bit for bit to the
/// golden file (the model without the option), and the option off gives exactly that model.
#[test]
fn axial_torsion_matrices_symmetric_uncoupled_and_lateral_block_unchanged() {
    let path = repo(GOLDEN_FILE);
    let golden = std::fs::read_to_string(path).unwrap();
    let off = model(&full_rotor(false, false));
    let foff = &fe(&off.rotor).rotor;
    assert_eq!(foff.ndof, foff.ndof_lateral);
    assert!(foff
        .node_axial
        .iter()
        .chain(&foff.node_torsion)
        .all(|d| d.is_none()));
    assert_eq!(
        matrix_fingerprint(&full_rotor(false, false), 120.0, None),
        golden
    );
    for (ax, to) in [(true, false), (false, true), (true, true)] {
        let text = full_rotor(ax, to);
        let m = model(&text);
        let f = &fe(&m.rotor).rotor;
        let nn = f.nodes();
        assert_eq!(f.ndof_lateral, foff.ndof);
        assert_eq!(f.ndof, foff.ndof + nn * (ax as usize + to as usize));
        assert_eq!(
            matrix_fingerprint(&text, 120.0, Some(f.ndof_lateral)),
            golden,
            "axial {ax}, torsion {to}: lateral block changed"
        );
        let group = |d: usize| {
            if f.node_axial.contains(&Some(d)) {
                1
            } else if f.node_torsion.contains(&Some(d)) {
                2
            } else {
                0
            }
        };
        let (k, c) = (f.k(120.0), f.c(120.0).unwrap());
        // K and C are unsymmetric only through the cross-coupled bearing (lateral, golden).
        assert!(f.m.asymmetry() < 1e-14 && f.k_shaft.asymmetry() < 1e-14);
        let new: Vec<usize> = (f.ndof_lateral..f.ndof).collect();
        assert!(sub(&k, &new).asymmetry() < 1e-14 && sub(&c, &new).asymmetry() < 1e-14);
        assert!(sub(&k, &new).nnz() > 0);
        for (name, a) in [("M", &f.m), ("K", &k), ("C", &c), ("G", &f.g)] {
            for (r, cc, v) in a.triplets() {
                assert!(
                    v == 0.0 || group(r) == group(cc),
                    "{name} couples DOF {r} and {cc} ({v})"
                );
            }
        }
        for (r, cc, v) in f.g.triplets() {
            assert_eq!(group(r), 0, "G has an axial/torsional entry");
            assert_eq!(v, -f.g.get(cc, r));
        }
        // Supports: stiffness and damping (plus β K) on their DOF.
        if ax {
            let d = f.node_axial[0].unwrap();
            let ea_h = 211e9 * PI * (0.05_f64.powi(2) - 0.01_f64.powi(2)) / 4.0 / 0.25;
            assert!((k.get(d, d) - (ea_h + 5.0e8)).abs() < 1e-6 * ea_h);
            let cd = 2.0e3 + 1.5 * f.m.get(d, d) + 2.0e-5 * k.get(d, d);
            assert!((c.get(d, d) / cd - 1.0).abs() < 1e-12);
        }
        if to {
            let d = f.node_torsion[6].unwrap();
            assert!(
                (c.get(d, d) - (3.0 + 1.5 * f.m.get(d, d) + 2.0e-5 * k.get(d, d))).abs() < 1e-12
            );
        }
        // Unbalance response and static stiffness: lateral only, identical to the model without.
        let (q, qoff) = (
            f.unbalance_response(150.0).unwrap(),
            foff.unbalance_response(150.0).unwrap(),
        );
        assert_eq!(&q[..foff.ndof], &qoff[..]);
        assert!(q[foff.ndof..].iter().all(|v| v.norm() == 0.0));
        assert_eq!(
            f.node_stiffness(3).unwrap(),
            foff.node_stiffness(3).unwrap()
        );
        // Static deflection under gravity: lateral as without, no axial or torsional motion.
        let (s, soff) = (
            linear::static_deflection(&m.rotor, 9.81).unwrap(),
            linear::static_deflection(&off.rotor, 9.81).unwrap(),
        );
        for (a, b) in s.iter().zip(&soff) {
            assert!((a - b).abs() <= 1e-12 * b.abs().max(1e-9), "{a} vs {b}");
        }
        assert!(s[foff.ndof..].iter().all(|v| v.abs() < 1e-20));
        // The body handed to the integrator carries the new DOFs.
        let body = m.rotor.body(150.0).unwrap();
        assert_eq!(body.node_axial, f.node_axial);
        assert_eq!(body.node_torsion, f.node_torsion);
    }
}

// ---------------------------------------------------------------------------------------------
// The paper's case at pinned speeds.

#[test]
fn paper_regimes_at_pinned_speeds_and_no_penetration() {
    let (_, model) = scene_model(PAPER, NO_SETS);
    for kind in ["collocated", "forward_increment"] {
        let (ls2, _) = scene_model(PAPER, &[&format!("run.integrator=\"{kind}\"")]);
        let mut s = settings(&ls2);
        s.error_estimate = false;
        if kind == "forward_increment" {
            s.step.harmonics = 16.0;
        }
        for (nu, period) in [
            (1.0, 1),
            (1.7, 1),
            (2.0, 1),
            (2.8, 2),
            (3.5, 2),
            (4.5, 3),
            (5.5, 3),
        ] {
            let r = analysis::run_speed(&model, &s.request(nu), Keep::default()).unwrap();
            assert_eq!(r.period, period, "{kind} ν = {nu}");
            let clearance = r.clearances[0];
            assert!(
                r.stats.min_gap >= -1e-9 * clearance,
                "{kind} ν = {nu}: penetration {:e} m (clearance {clearance:e})",
                r.stats.min_gap
            );
            assert!(r.stats.contact_steps > 0);
        }
    }
}

/// The paper's rotor as an 8-element Timoshenko model rubbing the rod behaves like the
/// Jeffcott model at the three quasi-resonances (one dominant mode, ε and δ_nd relative to it).
#[test]
fn fe_paper_rotor_rubs_like_the_jeffcott_rotor() {
    for (nu, period) in [(1.7, 1), (3.1, 2), (4.9, 3)] {
        let fe = run_speed(PAPER_FE, &SHORT_RUN, nu);
        let j = run_speed(PAPER, &SHORT_RUN, nu);
        assert_eq!(fe.period, period, "FE at {nu}");
        assert_eq!(j.period, period, "Jeffcott at {nu}");
        let span = j.extents_nd[3] - j.extents_nd[2];
        for i in 0..4 {
            assert!(
                (fe.extents_nd[i] - j.extents_nd[i]).abs() < 0.05 * span,
                "ν = {nu}: FE {:?} vs Jeffcott {:?}",
                fe.extents_nd,
                j.extents_nd
            );
        }
        assert!(fe.stats.min_gap >= -1e-9 * fe.clearances[0]);
    }
}
