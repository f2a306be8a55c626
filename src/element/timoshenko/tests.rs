//! Unit tests of the Timoshenko shaft element (cylindrical and tapered).
use super::*;

fn sec(shear: bool) -> ShaftSection {
    ShaftSection::cylinder(0.1, 0.05, 0.02, 2.1e11, 0.3, 7800.0, shear, true)
}

/// K, M_t and M_r are exactly the consistent matrices of the shape functions:
/// K = ∫ EI N_φ′ᵀN_φ′ + κGA (N_w′ − N_φ)ᵀ(N_w′ − N_φ), M_t = ρA ∫ N_wᵀN_w,
/// M_r = ρI ∫ N_φᵀN_φ (4-point Gauss, exact for these degree-6 integrands), from a stubby
/// element (L = 0.01 m, Φ = 84) to a slender one (1 m, Φ = 0.008); the shear strain
/// N_w′ − N_φ is constant in the element.
#[test]
fn planar_matrices_are_the_consistent_ones_of_the_shape_functions() {
    let gauss = [
        (-0.861_136_311_594_052_6, 0.347_854_845_137_453_8),
        (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
        (0.861_136_311_594_052_6, 0.347_854_845_137_453_8),
    ];
    for length in [0.01, 0.1, 1.0] {
        let mut s = sec(true);
        s.length = length;
        let (l, p) = (s.length, s.phi());
        let ei = s.youngs_modulus * s.inertia();
        let kga = s.shear_factor() * s.shear_modulus() * s.area();
        let (ra, ri) = (s.density * s.area(), s.density * s.inertia());
        let (nw, nf) = shape_functions(l, p);
        // Nodal interpolation: [w, φ] at ξ = 0 and 1 pick out their own DOF.
        for a in 0..4 {
            let at = |x: f64| [poly(&nw[a], x), poly(&nf[a], x)];
            let (v0, v1) = (at(0.0), at(1.0));
            let mut want = [[0.0; 2], [0.0; 2]];
            want[a / 2][a % 2] = 1.0;
            for (got, w) in [(v0, want[0]), (v1, want[1])] {
                assert!((got[0] - w[0]).abs() < 1e-12 && (got[1] - w[1]).abs() < 1e-12);
            }
            let gamma = |x: f64| dpoly(&nw[a], x) / l - poly(&nf[a], x);
            assert!((gamma(0.0) - gamma(0.7)).abs() < 1e-9 * (1.0 + gamma(0.0).abs()));
        }
        let (k, mt, mr) = planar(&s);
        let mut ki = [[0.0; 4]; 4];
        let mut mti = [[0.0; 4]; 4];
        let mut mri = [[0.0; 4]; 4];
        for (t, wt) in gauss {
            let (x, dz) = ((1.0 + t) / 2.0, wt * l / 2.0);
            for a in 0..4 {
                for b in 0..4 {
                    let (wa, wb) = (poly(&nw[a], x), poly(&nw[b], x));
                    let (fa, fb) = (poly(&nf[a], x), poly(&nf[b], x));
                    let (dfa, dfb) = (dpoly(&nf[a], x) / l, dpoly(&nf[b], x) / l);
                    let (ga, gb) = (dpoly(&nw[a], x) / l - fa, dpoly(&nw[b], x) / l - fb);
                    ki[a][b] += dz * (ei * dfa * dfb + kga * ga * gb);
                    mti[a][b] += dz * ra * wa * wb;
                    mri[a][b] += dz * ri * fa * fb;
                }
            }
        }
        let close = |x: &Planar, y: &Planar, what: &str| {
            let scale = x.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
            for a in 0..4 {
                for b in 0..4 {
                    assert!(
                        (x[a][b] - y[a][b]).abs() < 1e-12 * scale,
                        "{what}[{a}][{b}] at L = {l} (Φ = {p}): {} vs {}",
                        x[a][b],
                        y[a][b]
                    );
                }
            }
        };
        close(&k, &ki, "K");
        close(&mt, &mti, "M_t");
        close(&mr, &mri, "M_r");
    }
}

/// A "tapered" element with equal ends, integrated by quadrature, is the closed-form
/// cylinder (shear on and off, stubby to slender).
#[test]
fn tapered_with_equal_ends_equals_the_cylinder() {
    for shear in [false, true] {
        for length in [0.01, 0.1, 1.0] {
            let mut s = sec(shear);
            s.length = length;
            let (k, mt, mr) = planar(&s);
            let (ki, mti, mri) = planar_integrated(&s);
            for (x, y) in [(k, ki), (mt, mti), (mr, mri)] {
                let scale = x.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
                for (a, b) in x.iter().flatten().zip(y.iter().flatten()) {
                    assert!((a - b).abs() < 1e-13 * scale, "{a} vs {b} (L = {length})");
                }
            }
        }
    }
}

/// ROSS 2.3.0's tapered element `ShaftElement(L=0.5, idl=0.05, odl=0.1, idr=0.05,
/// odr=0.15, material=steel)` (its docstring example; E = 211 GPa, G_s = 81.2 GPa,
/// ρ = 7810 kg/m³), every entry of M, K, G printed by ROSS in full (`repr`) and mapped from
/// ROSS's `[x, y, α, β]` per node to ours `[u_x, u_y, θ_x, θ_y]`; axial and torsional terms
/// and the mass too.
#[test]
fn tapered_element_is_ross_s() {
    const ROSS_M: [[f64; 8]; 8] = [
        [
            11.369864166627563,
            0.0,
            0.0,
            0.8619763682878159,
            5.353950679444589,
            0.0,
            0.0,
            -0.646388940025432,
        ],
        [
            0.0,
            11.369864166627563,
            -0.8619763682878159,
            0.0,
            0.0,
            5.353950679444589,
            0.646388940025432,
            0.0,
        ],
        [
            0.0,
            -0.8619763682878159,
            0.08667494902828685,
            0.0,
            0.0,
            -0.6992654067562956,
            -0.07824937692314068,
            0.0,
        ],
        [
            0.8619763682878159,
            0.0,
            0.0,
            0.08667494902828685,
            0.6992654067562956,
            0.0,
            0.0,
            -0.07824937692314068,
        ],
        [
            5.353950679444589,
            0.0,
            0.0,
            0.6992654067562956,
            18.815298848710402,
            0.0,
            0.0,
            -1.178826178421142,
        ],
        [
            0.0,
            5.353950679444589,
            -0.6992654067562956,
            0.0,
            0.0,
            18.815298848710402,
            1.178826178421142,
            0.0,
        ],
        [
            0.0,
            0.646388940025432,
            -0.07824937692314068,
            0.0,
            0.0,
            1.178826178421142,
            0.11201633450536785,
            0.0,
        ],
        [
            -0.646388940025432,
            0.0,
            0.0,
            -0.07824937692314068,
            -1.178826178421142,
            0.0,
            0.0,
            0.11201633450536785,
        ],
    ];
    const ROSS_K: [[f64; 8]; 8] = [
        [
            219961444.16321272,
            0.0,
            0.0,
            41297546.58763985,
            -219961444.16321272,
            0.0,
            0.0,
            68683175.4939665,
        ],
        [
            0.0,
            219961444.16321272,
            -41297546.58763985,
            0.0,
            0.0,
            -219961444.16321272,
            -68683175.4939665,
            0.0,
        ],
        [
            0.0,
            -41297546.58763985,
            12235263.747718116,
            0.0,
            0.0,
            41297546.58763985,
            8413509.54610181,
            0.0,
        ],
        [
            41297546.58763985,
            0.0,
            0.0,
            12235263.747718116,
            -41297546.58763985,
            0.0,
            0.0,
            8413509.54610181,
        ],
        [
            -219961444.16321272,
            0.0,
            0.0,
            -41297546.58763985,
            219961444.16321272,
            0.0,
            0.0,
            -68683175.4939665,
        ],
        [
            0.0,
            -219961444.16321272,
            41297546.58763985,
            0.0,
            0.0,
            219961444.16321272,
            68683175.4939665,
            0.0,
        ],
        [
            0.0,
            -68683175.4939665,
            8413509.54610181,
            0.0,
            0.0,
            68683175.4939665,
            25928078.200881444,
            0.0,
        ],
        [
            68683175.4939665,
            0.0,
            0.0,
            8413509.54610181,
            -68683175.4939665,
            0.0,
            0.0,
            25928078.200881444,
        ],
    ];
    const ROSS_G: [[f64; 8]; 8] = [
        [
            0.0,
            0.30940809231096106,
            -0.010859023398541407,
            0.0,
            0.0,
            -0.30940809231096106,
            0.014312720418764831,
            0.0,
        ],
        [
            -0.30940809231096106,
            0.0,
            0.0,
            -0.010859023398541407,
            0.30940809231096106,
            0.0,
            0.0,
            0.014312720418764831,
        ],
        [
            0.010859023398541407,
            0.0,
            0.0,
            0.006720596440048442,
            -0.010859023398541407,
            0.0,
            0.0,
            -0.004250396543695845,
        ],
        [
            0.0,
            0.010859023398541407,
            -0.006720596440048442,
            0.0,
            0.0,
            -0.010859023398541407,
            0.004250396543695845,
            0.0,
        ],
        [
            0.0,
            -0.30940809231096106,
            0.010859023398541407,
            0.0,
            0.0,
            0.30940809231096106,
            -0.014312720418764831,
            0.0,
        ],
        [
            0.30940809231096106,
            0.0,
            0.0,
            0.010859023398541407,
            -0.30940809231096106,
            0.0,
            0.0,
            -0.014312720418764831,
        ],
        [
            -0.014312720418764831,
            0.0,
            0.0,
            -0.004250396543695845,
            0.014312720418764831,
            0.0,
            0.0,
            0.019692889765287283,
        ],
        [
            0.0,
            -0.014312720418764831,
            0.004250396543695845,
            0.0,
            0.0,
            0.014312720418764831,
            -0.019692889765287283,
            0.0,
        ],
    ];

    let s = ShaftSection {
        length: 0.5,
        outer_diameter: 0.1,
        inner_diameter: 0.05,
        outer_diameter_right: 0.15,
        inner_diameter_right: 0.05,
        youngs_modulus: 211e9,
        poisson: 211e9 / (2.0 * 81.2e9) - 1.0,
        density: 7810.0,
        shear: true,
        rotary_inertia: true,
    };
    assert!(s.is_tapered());
    let e = shaft_element(&s);
    for (name, got, want) in [("M", e.m, ROSS_M), ("K", e.k, ROSS_K), ("G", e.g, ROSS_G)] {
        let scale = want.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        for i in 0..8 {
            for j in 0..8 {
                assert!(
                    (got[i][j] - want[i][j]).abs() < 1e-13 * scale,
                    "{name}[{i}][{j}]: {} vs ROSS {}",
                    got[i][j],
                    want[i][j]
                );
            }
        }
    }
    let (a, t) = (axial_element(&s), torsion_element(&s));
    for (got, want) in [
        (a.m[0][0], 14.056990878640578),
        (a.k[0][0], 4557272843.113693),
        (t.m[0][0], 0.03793790151905838),
        (t.k[0][0], 4733251.119099935),
        (s.mass(), 40.89306437422714),
    ] {
        assert!((got / want - 1.0).abs() < 1e-13, "{got} vs ROSS {want}");
    }
}

/// A cone refined into n equal tapered elements converges to one mesh-independent rotor:
/// the first pinned–pinned frequency of a solid cone (D 0.1 → 0.05 m over 1 m) changes by
/// less and less, at fourth order without shear (Hermite cubics with an exact section).
#[test]
fn refined_cone_converges_at_fourth_order() {
    let first = |n: usize| -> f64 {
        let nd = 2 * (n + 1);
        let (mut k, mut m) = (vec![vec![0.0; nd]; nd], vec![vec![0.0; nd]; nd]);
        for el in 0..n {
            let (a, b) = (el as f64 / n as f64, (el + 1) as f64 / n as f64);
            let s = ShaftSection {
                length: 1.0 / n as f64,
                outer_diameter: 0.1 - 0.05 * a,
                inner_diameter: 0.0,
                outer_diameter_right: 0.1 - 0.05 * b,
                inner_diameter_right: 0.0,
                ..ShaftSection::cylinder(1.0, 0.1, 0.0, 2.1e11, 0.3, 7800.0, false, false)
            };
            let (kp, mp, _) = planar(&s);
            for p in 0..4 {
                for q in 0..4 {
                    k[2 * el + p][2 * el + q] += kp[p][q];
                    m[2 * el + p][2 * el + q] += mp[p][q];
                }
            }
        }
        // Pins: drop w at both ends; the lowest eigenvalue by inverse iteration on the rest.
        let keep: Vec<usize> = (0..nd).filter(|&i| i != 0 && i != nd - 2).collect();
        let kk = nalgebra::DMatrix::from_fn(keep.len(), keep.len(), |i, j| k[keep[i]][keep[j]]);
        let mm = nalgebra::DMatrix::from_fn(keep.len(), keep.len(), |i, j| m[keep[i]][keep[j]]);
        let lu = kk.lu();
        let mut x = nalgebra::DVector::from_element(keep.len(), 1.0);
        let mut lam = 0.0;
        for _ in 0..200 {
            let y = lu.solve(&(&mm * &x)).expect("pinned cone is not singular");
            lam = x.dot(&(&mm * &x)) / x.dot(&(&mm * &y));
            x = &y / y.norm();
        }
        lam.sqrt()
    };
    let w: Vec<f64> = [4, 8, 16, 32].iter().map(|&n| first(n)).collect();
    let d1 = (w[0] - w[1]).abs();
    let d2 = (w[1] - w[2]).abs();
    let d3 = (w[2] - w[3]).abs();
    let order = (d2 / d3).log2();
    assert!(
        (d1 / d2).log2() > 3.5 && order > 3.8 && order < 4.2,
        "{w:?}: order {order}"
    );
    // Richardson: the error left at 32 elements is about d3/15.
    assert!(d3 / 15.0 / w[3] < 1e-6, "{w:?}");
}

#[test]
fn symmetric_m_k_and_skew_g() {
    let e = shaft_element(&sec(true));
    for i in 0..8 {
        for j in 0..8 {
            assert!((e.m[i][j] - e.m[j][i]).abs() < 1e-12 * e.m[0][0]);
            assert!((e.k[i][j] - e.k[j][i]).abs() < 1e-9 * e.k[0][0]);
            assert!((e.g[i][j] + e.g[j][i]).abs() < 1e-15);
        }
    }
}

#[test]
fn translational_mass_sums_to_rho_a_l() {
    // Rigid translation in x: qᵀ M q = ρ A L (rotary terms vanish for a translation).
    let s = sec(true);
    let e = shaft_element(&s);
    let q = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0];
    let mut mq = 0.0;
    for i in 0..8 {
        for j in 0..8 {
            mq += q[i] * e.m[i][j] * q[j];
        }
    }
    assert!((mq / s.mass() - 1.0).abs() < 1e-12, "{mq} vs {}", s.mass());
}

#[test]
fn rigid_body_modes_have_no_strain_energy() {
    let s = sec(true);
    let e = shaft_element(&s);
    let l = s.length;
    // translations, and rigid rotations: about y (u_x = β z, θ_y = β), about x (u_y = −α z, θ_x = α)
    let modes = [
        [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 0.0, 1.0, l, 0.0, 0.0, 1.0],
        [0.0, 0.0, 1.0, 0.0, 0.0, -l, 1.0, 0.0],
    ];
    for q in modes {
        for i in 0..8 {
            let f: f64 = (0..8).map(|j| e.k[i][j] * q[j]).sum();
            assert!(f.abs() < 1e-6 * e.k[0][0] * 1e-3, "K q ≠ 0: {f} for {q:?}");
        }
    }
}

#[test]
fn axial_and_torsion_elements() {
    let s = sec(true);
    let a = axial_element(&s);
    let t = torsion_element(&s);
    let ea_l = s.youngs_modulus * s.area() / s.length;
    let gj_l = s.youngs_modulus / 2.6 * s.polar_moment() / s.length;
    for (e, k, m) in [
        (a, ea_l, s.mass()),
        (t, gj_l, s.density * s.polar_moment() * s.length),
    ] {
        // Rigid motion: no strain energy, kinetic energy of the whole element.
        let sum_m: f64 = e.m.iter().flatten().sum();
        assert!((sum_m / m - 1.0).abs() < 1e-14, "{sum_m} vs {m}");
        for r in e.k {
            assert!((r[0] + r[1]).abs() < 1e-12 * k);
        }
        assert!((e.k[0][0] / k - 1.0).abs() < 1e-14);
        assert_eq!(e.m[0][1], e.m[1][0]);
        assert_eq!(e.k[0][1], e.k[1][0]);
        assert!((e.m[0][0] / e.m[0][1] - 2.0).abs() < 1e-14);
    }
    // J of a tube: π(D⁴ − d⁴)/32.
    let j = std::f64::consts::PI * (0.05_f64.powi(4) - 0.02_f64.powi(4)) / 32.0;
    assert!((s.polar_moment() / j - 1.0).abs() < 1e-14);
}

#[test]
fn cowper_factor_of_solid_section() {
    let mut s = sec(true);
    s.inner_diameter = 0.0;
    s.inner_diameter_right = 0.0;
    // 6(1+ν)/(7+6ν) for a solid circle.
    assert!((s.shear_factor() - 6.0 * 1.3 / 8.8).abs() < 1e-12);
}

#[test]
fn disk_gyroscopic_matches_shaft_convention() {
    // The shaft's G on a node's rotations has the disk's sign pattern.
    let e = shaft_element(&sec(true));
    assert!(e.g[2][3] > 0.0 && e.g[3][2] < 0.0);
    let (_, g) = disk(1.0, 0.1, 0.2);
    assert!(g[2][3] > 0.0 && g[3][2] < 0.0);
}

/// ROSS's switches are separate: without rotary inertia the mass loses exactly the rotary
/// pattern `M_r`, and `G` (built from `M_r`, `G = 2 M_r` between the planes) is unchanged.
#[test]
fn rotary_inertia_switch_leaves_the_gyroscopic_matrix() {
    for shear in [false, true] {
        let on = shaft_element(&sec(shear));
        let off = shaft_element(&ShaftSection {
            rotary_inertia: false,
            ..sec(shear)
        });
        assert_eq!(on.g, off.g);
        assert_eq!(on.k, off.k);
        // θ_y1–θ_y1 (x–z plane φ₁φ₁): M_r = ρI/(L(1+Φ)²)·r₃L² with r₃ = 2/15 + Φ/6 + Φ²/3.
        let s = sec(shear);
        let p = s.phi();
        let r3 = 2.0 / 15.0 + p / 6.0 + p * p / 3.0;
        let mr = s.density * s.inertia() / (s.length * (1.0 + p).powi(2)) * r3 * s.length.powi(2);
        assert!((on.m[3][3] - off.m[3][3] - mr).abs() < 1e-12 * mr);
        assert!(
            (on.g[3][2] + 2.0 * mr).abs() < 1e-12 * mr,
            "G = −2 M_r at θ_y θ_x"
        );
        assert!(off.g.iter().flatten().any(|v| *v != 0.0));
    }
}

/// The thermal curvature load of a whole element is the moment pair `E I κ [0, −1, 0, 1]`, and
/// the element, loaded by it, bends exactly into the free curvature: `K u = f` for
/// `w = κ z²/2`, `φ = κ z` (with shear: Φ = 84 and 0.008, and Euler–Bernoulli), in both planes
/// with their signs (y–z: `θ_x = −∂u_y/∂z`). Two halves add up to the whole.
#[test]
#[allow(clippy::needless_range_loop)]
fn a_thermal_curvature_load_bends_the_element_into_its_free_curvature() {
    for (length, shear) in [(0.01, true), (1.0, true), (0.3, false)] {
        let mut s = sec(shear);
        s.length = length;
        let ei = s.youngs_modulus * s.inertia();
        let e = shaft_element(&s);
        let (fx, fy) = thermal_curvature_load(&s, (0.0, 1.0));
        let scale = ei;
        let kappa = 1.0;
        // u_x = κz²/2 (θ_y = κz); u_y = κz²/2 (θ_x = −κz).
        let mut ux = [0.0; 8];
        ux[4] = kappa * length * length / 2.0;
        ux[7] = kappa * length;
        let mut uy = [0.0; 8];
        uy[5] = kappa * length * length / 2.0;
        uy[6] = -kappa * length;
        for (u, f) in [(ux, fx), (uy, fy)] {
            for r in 0..8 {
                let ku: f64 = (0..8).map(|c| e.k[r][c] * u[c]).sum();
                assert!(
                    (ku - f[r]).abs() < 1e-9 * scale,
                    "L {length}: row {r}: {ku} vs {}",
                    f[r]
                );
            }
        }
        assert!((fx[3] + ei).abs() < 1e-9 * ei && (fx[7] - ei).abs() < 1e-9 * ei);
        assert!((fy[2] - ei).abs() < 1e-9 * ei && (fy[6] + ei).abs() < 1e-9 * ei);
        let (ax, _) = thermal_curvature_load(&s, (0.0, 0.37));
        let (bx, _) = thermal_curvature_load(&s, (0.37, 1.0));
        for r in 0..8 {
            assert!((ax[r] + bx[r] - fx[r]).abs() < 1e-9 * ei);
        }
    }
}
