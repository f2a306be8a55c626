//! Fitted orders of convergence: the observed order of each integrator on the paper's case,
//! the Timoshenko and Euler–Bernoulli shaft elements (simply supported and pinned, with the
//! second-order term explained), the axial bar element, the 2-D solid elements on the Lamé
//! thick ring and the tetrahedra on the same tube in 3-D. Each check fits a log–log slope to a
//! sequence of refinements and compares it with the theoretical rate.

use crate::common;

use common::fe::{block_frequencies, fe};
use common::meshes::{l2_error, lame, model_of, pressure_load, ring_msh, solve, spec, tube_mesh};
use common::scenes::{axial_bar, paper_single, ss_shaft};
use common::{model, scene_model, settings};
use rubsim::analysis;
use rubsim::element::solid2d::Plane;
use rubsim::math::loglog_slope;
use rubsim::mesh::CellKind;
use rubsim::model::stator::mesh as mesh_stator;
use rubsim::model::stator::StatorElement;
use std::f64::consts::PI;
use std::path::PathBuf;

// ---------------------------------------------------------------------------------------------
// Time integration.

#[test]
fn observed_orders_are_one_and_two() {
    let text = paper_single();
    let (ls, model) = scene_model(
        &text,
        &[
            "run.speed_ratio=1.7",
            "run.revolutions=60",
            "run.transient_revolutions=30",
        ],
    );
    let s = settings(&ls);
    let c = analysis::convergence(&model, &s, 1.7, &[0, 1, 2, 3, 4], 9, 6, None).unwrap();
    let order = |n: &str| c.orders.iter().find(|o| o.0 == n).unwrap().1;
    let fi = order("forward_increment");
    let co = order("collocated");
    assert!((fi - 1.0).abs() < 0.15, "forward increment order {fi}");
    assert!((co - 2.0).abs() < 0.3, "collocated order {co}");
    // Absolute bound on the finest level (scikit-fem style).
    let finest = c
        .points
        .iter()
        .filter(|p| p.integrator == "collocated")
        .map(|p| p.orbit_err)
        .fold(f64::INFINITY, f64::min);
    assert!(finest < 1e-3, "collocated finest error {finest}");
}

// ---------------------------------------------------------------------------------------------
// Shaft elements.

/// Closed form of a simply supported Timoshenko beam (docs/ORACLES.md §8):
/// Ω_n = ρAL⁴ω²/(EI) = [(g+j)λ² + 1 − √((g−j)²λ⁴ + 2(g+j)λ² + 1)] / (2gj), λ = nπ.
fn ss_closed_form(mode: usize, shear: bool) -> f64 {
    let (l, d, e, nu, rho) = (2.0_f64, 0.2_f64, 2.1e11, 0.3_f64, 7800.0);
    let a = PI * d * d / 4.0;
    let i = PI * d.powi(4) / 64.0;
    let ks = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu);
    let gmod = e / (2.0 * (1.0 + nu));
    let j = i / (a * l * l);
    let g = if shear {
        e * i / (ks * a * gmod * l * l)
    } else {
        0.0
    };
    let lam = mode as f64 * PI;
    let om = if shear {
        ((g + j) * lam.powi(2) + 1.0
            - ((g - j).powi(2) * lam.powi(4) + 2.0 * (g + j) * lam.powi(2) + 1.0).sqrt())
            / (2.0 * g * j)
    } else {
        // Rayleigh beam (rotary inertia only): λ⁴/(1 + jλ²).
        lam.powi(4) / (1.0 + j * lam.powi(2))
    };
    (om * e * i / (rho * a * l.powi(4))).sqrt()
}

#[test]
fn simply_supported_frequencies_and_convergence_rate() {
    for shear in [false, true] {
        let exact: Vec<f64> = (1..=3).map(|n| ss_closed_form(n, shear)).collect();
        let mut hs = Vec::new();
        let mut errs = Vec::new();
        for n in [4usize, 8, 16, 32, 64] {
            let m = model(&ss_shaft(n, shear));
            let w = fe(&m.rotor).rotor.undamped_frequencies(0.0).unwrap();
            // each bending frequency appears twice (x and y planes)
            let w1 = w[0];
            assert!((w[1] / w1 - 1.0).abs() < 1e-6);
            hs.push(2.0 / n as f64);
            errs.push((w1 / exact[0] - 1.0).abs());
            if n == 64 {
                for (k, ex) in exact.iter().enumerate() {
                    let fe_w = w[2 * k];
                    assert!(
                        (fe_w / ex - 1.0).abs() < 2e-3,
                        "shear {shear} mode {}: FE {fe_w} vs {ex}",
                        k + 1
                    );
                }
            }
        }
        // Euler–Bernoulli/Rayleigh (Φ = 0): fourth order until the 1e14 N/m supports' own
        // flexibility (≈ 4e-7) is reached at 32 elements, so fit the first three levels.
        // Timoshenko: second order, inherent to the element (its shear force is constant per
        // element, leaving an error (kh)²/24 · U_shear/U; see
        // `pinned_timoshenko_error_is_second_order_through_the_shear_energy`), to the closed
        // form within 1.4e-6 at 64 (1.77e-6 of discretisation less the supports' ≈ 4e-7).
        let (p, expected, tol) = if shear {
            (loglog_slope(&hs, &errs), 2.0, 0.35)
        } else {
            (loglog_slope(&hs[..3], &errs[..3]), 4.0, 0.5)
        };
        eprintln!("simply supported, shear {shear}: errors {errs:?}, order {p:.2}");
        assert!(
            (p - expected).abs() < tol,
            "shear {shear}: observed order {p}"
        );
    }
    // The ORACLES check values of the closed form (square section there) are for the formula;
    // our circular section gives, for mode 1 with shear:
    let f1 = ss_closed_form(1, true) / (2.0 * PI);
    assert!(f1 > 100.0 && f1 < 130.0, "{f1}");
}

/// First frequency (rad/s) of the shaft of `ss_shaft` as `n` elements of
/// `rubsim::element::timoshenko` in one bending plane (x–z: `[u_x, θ_y]` per node), pinned
/// exactly (u_x = 0 at both ends: no bearing flexibility), from the dense generalised problem.
fn pinned_beam_first_frequency(n: usize, shear: bool, rotary_inertia: bool) -> f64 {
    use nalgebra::DMatrix;
    use rubsim::element::timoshenko::{shaft_element, ShaftSection};
    let s = ShaftSection::cylinder(
        2.0 / n as f64,
        0.2,
        0.0,
        2.1e11,
        0.3,
        7800.0,
        shear,
        rotary_inertia,
    );
    let e = shaft_element(&s);
    const XZ: [usize; 4] = [0, 3, 4, 7];
    let nd = 2 * (n + 1);
    let (mut k, mut m) = (DMatrix::<f64>::zeros(nd, nd), DMatrix::<f64>::zeros(nd, nd));
    for el in 0..n {
        for a in 0..4 {
            for b in 0..4 {
                k[(2 * el + a, 2 * el + b)] += e.k[XZ[a]][XZ[b]];
                m[(2 * el + a, 2 * el + b)] += e.m[XZ[a]][XZ[b]];
            }
        }
    }
    let free: Vec<usize> = (0..nd).filter(|&i| i != 0 && i != 2 * n).collect();
    let k = k.select_rows(&free).select_columns(&free);
    let m = m.select_rows(&free).select_columns(&free);
    // Largest eigenvalue of L⁻¹ M L⁻ᵀ (K = L Lᵀ) is 1/ω₁²: accurate for the lowest mode even
    // when M is nearly singular in the rotations (no rotary inertia).
    let l = k.cholesky().expect("pinned K positive definite").l();
    let linv = l.try_inverse().unwrap();
    let a: DMatrix<f64> = &linv * m * linv.transpose();
    let a = (&a + a.transpose()) * 0.5;
    1.0 / a.symmetric_eigenvalues().max().sqrt()
}

/// Why the Timoshenko element converges at second order and Euler–Bernoulli at fourth.
///
/// The element's shape functions solve the unloaded static Timoshenko equations, so its shear
/// force κGA(w′ − ψ) is constant along each element, while a mode's shear force varies like
/// cos kz. The element's matrices are exactly the consistent ones of those shape functions
/// (checked against Friswell et al. 2010 / ROSS `shaft_element.py` and a symbolic derivation),
/// yet a piecewise-constant shear force leaves an O((kh)²) error in the shear strain energy.
/// Rayleigh–Ritz turns it into ω_h/ω − 1 = (kh)²/24 · U_s/U + O((kh)⁴), where U_s/U is the
/// mode's share of shear strain energy (= s/(1+s), s = EIk²/(κGA), without rotary inertia) —
/// the same (kh)²/24 as a linear bar element, weighted by the shear share. Euler–Bernoulli has
/// no shear energy (U_s = 0) and keeps the Hermite O((kh)⁴). Exact pins (no 1e14 N/m bearing
/// floor) so every digit is discretisation error.
#[test]
fn pinned_timoshenko_error_is_second_order_through_the_shear_energy() {
    let (l, d, e, nu, rho) = (2.0_f64, 0.2_f64, 2.1e11, 0.3_f64, 7800.0);
    let (a, i) = (PI * d * d / 4.0, PI * d.powi(4) / 64.0);
    let kga = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu) * e / (2.0 * (1.0 + nu)) * a;
    let k = PI / l;
    let s = e * i * k * k / kga;
    // Shear without rotary inertia: ω² = EIk⁴/(ρA(1+s)).
    let exact_shear_only = (e * i * k.powi(4) / (rho * a * (1.0 + s))).sqrt();
    let ns = [4usize, 8, 16, 32, 64, 128];
    let hs: Vec<f64> = ns.iter().map(|&n| l / n as f64).collect();
    for (label, shear, rot, exact) in [
        (
            "Euler–Bernoulli + rotary",
            false,
            true,
            ss_closed_form(1, false),
        ),
        (
            "Timoshenko (shear + rotary)",
            true,
            true,
            ss_closed_form(1, true),
        ),
        ("shear, no rotary inertia", true, false, exact_shear_only),
    ] {
        let errs: Vec<f64> = ns
            .iter()
            .map(|&n| pinned_beam_first_frequency(n, shear, rot) / exact - 1.0)
            .collect();
        let scaled: Vec<f64> = errs
            .iter()
            .zip(&hs)
            .map(|(e, h)| e / (k * h).powi(2))
            .collect();
        let last = ns.len() - 1;
        let p_fine = loglog_slope(&hs[last - 1..], &errs[last - 1..]);
        let p_all = loglog_slope(&hs, &errs);
        eprintln!(
            "pinned, {label}: errors {errs:?}; err/(kh)² {scaled:?}; order 4–128 {p_all:.3}, \
             64–128 {p_fine:.4}"
        );
        // Rayleigh–Ritz: the consistent-mass FE frequency bounds the exact one from above.
        assert!(errs.iter().all(|&x| x > 0.0), "{label}: {errs:?}");
        if !shear {
            let p = loglog_slope(&hs[..4], &errs[..4]);
            assert!((p - 4.0).abs() < 0.05, "{label}: order {p}");
        } else {
            assert!((p_fine - 2.0).abs() < 0.02, "{label}: order {p_fine}");
            assert!(p_all < 2.3, "{label}: order {p_all}");
        }
    }
    // Leading coefficient without rotary inertia: (kh)²/24 · s/(1+s), to 0.3 % at 128 elements.
    let n = 128;
    let h = l / n as f64;
    let err = pinned_beam_first_frequency(n, true, false) / exact_shear_only - 1.0;
    let predicted = (k * h).powi(2) / 24.0 * s / (1.0 + s);
    eprintln!("err {err:.6e}, predicted (kh)²/24·s/(1+s) = {predicted:.6e} (s = {s:.6})");
    assert!((err / predicted - 1.0).abs() < 3e-3, "{err} vs {predicted}");
}

/// (a) Fixed–free bar: ω_k = (2k−1)π/(2L) √(E/ρ). Linear elements with consistent mass
/// overestimate ω_k by ≈ (ω_k h/c)²/24: second order, measured as a log–log slope. On a uniform
/// mesh the discrete modes are exact sines at the nodes, so the FE frequency is the discrete
/// dispersion relation ω_h² = (c/h)² 6(1 − cos kh)/(2 + cos kh) at the exact wavenumber k.
/// Node 0 is clamped by dropping its DOF; the thrust bearing's own flexibility is checked last.
#[test]
fn axial_fixed_free_frequencies_converge_at_second_order() {
    let c = (2.1e11_f64 / 7800.0).sqrt();
    let exact = |k: usize| (2 * k - 1) as f64 * PI / (2.0 * 2.0) * c;
    let mut hs = Vec::new();
    let mut errs = [Vec::new(), Vec::new(), Vec::new()];
    for n in [4usize, 8, 16, 32, 64] {
        let m = model(&axial_bar(n));
        let f = &fe(&m.rotor).rotor;
        let dofs: Vec<usize> = f.node_axial.iter().map(|d| d.unwrap()).collect();
        assert_eq!(dofs.len(), n + 1);
        let w = block_frequencies(f, &dofs[1..]);
        let h = 2.0 / n as f64;
        hs.push(h);
        for (k, e) in errs.iter_mut().enumerate() {
            let rel = w[k] / exact(k + 1) - 1.0;
            assert!(
                rel > 0.0,
                "consistent mass overestimates: mode {} {rel}",
                k + 1
            );
            e.push(rel);
            let x = exact(k + 1) / c * h;
            let disc = c / h * (6.0 * (1.0 - x.cos()) / (2.0 + x.cos())).sqrt();
            assert!(
                (w[k] / disc - 1.0).abs() < 1e-9,
                "{n} elements, mode {}: {} vs dispersion {disc}",
                k + 1,
                w[k]
            );
        }
    }
    for (k, e) in errs.iter().enumerate() {
        let p = loglog_slope(&hs, e);
        eprintln!(
            "axial fixed–free mode {}: errors {:?}, order {p:.4}",
            k + 1,
            e.iter().map(|v| format!("{v:.3e}")).collect::<Vec<_>>()
        );
        assert!((p - 2.0).abs() < 0.1, "mode {}: order {p}", k + 1);
    }
    // Finest level: the leading term (ω h/c)²/24 predicts the error of mode 1.
    let lead = (exact(1) * hs[4] / c).powi(2) / 24.0;
    assert!(
        (errs[0][4] / lead - 1.0).abs() < 1e-3,
        "{} vs {lead}",
        errs[0][4]
    );
    assert!(errs[0][4] < 2.6e-5);
    // On the 1e16 N/m thrust bearing instead of the clamp, mode 1 drops by ≈ EA/(k_s L) (half
    // the spring's share of the strain energy, 2EA/(k_s L)).
    let m = model(&axial_bar(64));
    let f = &fe(&m.rotor).rotor;
    let dofs: Vec<usize> = f.node_axial.iter().map(|d| d.unwrap()).collect();
    let w = block_frequencies(f, &dofs)[0];
    let ea = 2.1e11 * PI * 0.01;
    let want = (1.0 + errs[0][4]) * (1.0 - ea / (1.0e16 * 2.0));
    eprintln!(
        "axial mode 1 on the thrust bearing, 64 elements: ω/ω_exact − 1 = {:.5e} (predicted {:.5e})",
        w / exact(1) - 1.0,
        want - 1.0
    );
    assert!((w / exact(1) / want - 1.0).abs() < 2e-8);
}

// ---------------------------------------------------------------------------------------------
// Solid elements (meshed stators).

#[test]
fn lame_thick_ring_converges_at_the_theoretical_rate_per_element() {
    let (r0, r1, p) = (0.06, 0.08, 1e6);
    for (kind, rate, levels) in [
        (CellKind::Tri3, 2.0, [4usize, 8, 16, 32]),
        (CellKind::Quad4, 2.0, [4, 8, 16, 32]),
        (CellKind::Tri6, 3.0, [2, 4, 8, 16]),
        (CellKind::Quad8, 3.0, [2, 4, 8, 16]),
        (CellKind::Quad9, 3.0, [2, 4, 8, 16]),
    ] {
        for plane in [Plane::Stress, Plane::Strain] {
            let sp = spec(if plane == Plane::Strain {
                "plane = \"strain\""
            } else {
                ""
            });
            let exact = lame(r0, r1, p, plane);
            let mut hs = Vec::new();
            let mut errs = Vec::new();
            for nr in levels {
                let msh = ring_msh(kind, r0, r1, 0.0, 2.0 * PI, nr, 16 * nr, true);
                let (mesh, m) = model_of(&msh, &sp);
                let u = solve(&m.k, &pressure_load(&mesh, &m, p, 0.01));
                hs.push((r1 - r0) / nr as f64);
                errs.push(l2_error(&m, &u, &exact));
            }
            let slope = loglog_slope(&hs, &errs);
            eprintln!("convergence {kind:?} {plane:?}: h {hs:?} L2 {errs:?} slope {slope:.3}");
            assert!(
                (slope - rate).abs() < 0.1,
                "{kind:?} {plane:?}: L2 slope {slope:.3} (expected {rate}); errors {errs:?}"
            );
            let finest = *errs.last().unwrap();
            let bound = if rate > 2.5 { 1e-5 } else { 2e-3 };
            assert!(
                finest < bound,
                "{kind:?} {plane:?}: finest error {finest:.2e}"
            );
        }
    }
}

#[test]
fn tetrahedra_converge_to_plane_strain_lame_in_a_tube() {
    use rubsim::element::solid3d;
    let (r0, r1, p) = (0.06, 0.08, 1e6);
    let sp = spec("fixed_x = [\"sym_x\"]\nfixed_y = [\"sym_y\"]\nfixed_z = [\"ends\"]");
    let exact = lame(r0, r1, p, Plane::Strain);
    for (kind, rate, levels) in [
        (CellKind::Tet4, 2.0, [2usize, 4, 8]),
        (CellKind::Tet10, 3.0, [1, 2, 4]),
    ] {
        let mut hs = Vec::new();
        let mut errs = Vec::new();
        for nr in levels {
            let mesh = tube_mesh(kind, r0, r1, (r1 - r0) / nr as f64, nr, 8 * nr);
            mesh.check_conforming().unwrap();
            let m = mesh_stator::from_spec(&mesh, &sp, 0, &[], PathBuf::from("tube.msh"), true)
                .unwrap();
            let md = m.mesh.as_ref().unwrap();
            assert_eq!(md.dim, 3);
            // Inner pressure on the r = r0 faces.
            let mut f = vec![0.0; m.ndof];
            let g = mesh.group("stator_contact").unwrap();
            for b in mesh.group_blocks(g) {
                for c in b.cells() {
                    let x: Vec<[f64; 3]> = c.iter().map(|&n| mesh.nodes[n]).collect();
                    let mut fe = [0.0; 18];
                    solid3d::face_load(
                        b.kind,
                        &x,
                        |q, _| {
                            let r = q[0].hypot(q[1]);
                            [p * q[0] / r, p * q[1] / r, 0.0]
                        },
                        &mut fe,
                    );
                    for (k, &n) in c.iter().enumerate() {
                        let d = [m.node_dofs[n][0], m.node_dofs[n][1], md.axial_dofs[n]];
                        for comp in 0..3 {
                            if let Some(i) = d[comp] {
                                f[i] += fe[3 * k + comp];
                            }
                        }
                    }
                }
            }
            let u = solve(&m.k, &f);
            let (mut err, mut norm) = (0.0, 0.0);
            for el in m.elements.iter() {
                let StatorElement::Solid3 { kind, nodes, .. } = el else {
                    continue;
                };
                let x: Vec<[f64; 3]> = nodes.iter().map(|&n| mesh.nodes[n]).collect();
                let ue: Vec<f64> = nodes
                    .iter()
                    .flat_map(|&n| [m.node_dofs[n][0], m.node_dofs[n][1], md.axial_dofs[n]])
                    .map(|d| d.map_or(0.0, |i| u[i]))
                    .collect();
                for &(xi, w) in solid3d::quadrature(*kind, solid3d::Rule::Accurate) {
                    let (q, uh, det) = solid3d::interpolate(*kind, &x, &ue, xi);
                    let r = q[0].hypot(q[1]);
                    let ur = exact(r);
                    let ex = [ur * q[0] / r, ur * q[1] / r, 0.0];
                    err += w * det * (0..3).map(|c| (uh[c] - ex[c]).powi(2)).sum::<f64>();
                    norm += w * det * (ex[0] * ex[0] + ex[1] * ex[1]);
                }
            }
            hs.push((r1 - r0) / nr as f64);
            errs.push((err / norm).sqrt());
        }
        let slope = loglog_slope(&hs, &errs);
        eprintln!(
            "convergence {kind:?} plane strain (3-D tube): h {hs:?} L2 {errs:?} slope {slope:.3}"
        );
        assert!(
            (slope - rate).abs() < 0.15,
            "{kind:?}: L2 slope {slope:.3}, errors {errs:?}"
        );
    }
}
