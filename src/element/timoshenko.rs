//! Timoshenko shaft element with rotary inertia, shear deformation and gyroscopic coupling
//! (Nelson 1980; Friswell, Penny, Garvey & Lees, *Dynamics of Rotating Machines*, 2010).
//!
//! # DOFs and signs
//!
//! Element DOF order `[u_x1, u_y1, θ_x1, θ_y1, u_x2, u_y2, θ_x2, θ_y2]` (m, rad), the rotor axis
//! is z. Rotations follow the right-hand rule about the axes: in the x–z plane `θ_y = ∂u_x/∂z`,
//! in the y–z plane `θ_x = −∂u_y/∂z`. Each plane is the classical planar Timoshenko element in
//! `[w₁, φ₁, w₂, φ₂]` with `φ = ∂w/∂z` (x–z: `w = u_x`, `φ = θ_y`; y–z: `w = u_y`, `φ = −θ_x`).
//!
//! With `Φ = 12 E I / (κ_s G A L²)`:
//! * stiffness `E I/(L³(1+Φ)) [12, 6L, −12, 6L; 6L, (4+Φ)L², −6L, (2−Φ)L²; …]`;
//! * translational mass `ρ A L/(1+Φ)² [m₁ … m₆]` (m₁ = 13/35 + 7Φ/10 + Φ²/3, …);
//! * rotary mass `ρ I/(L(1+Φ)²) [r₁ … r₄]` (r₁ = 6/5, r₂ = 1/10 − Φ/2, …);
//! * gyroscopic `G` (the equations read `M q̈ + (C + Ω G) q̇ + K q = f`), built from the
//!   rotary-mass pattern `R = ρ I_p ∫ N_φᵀ N_φ dz = 2 M_r` (I_p = 2I for a circular section)
//!   as `G[x–z rows, y–z cols] = R`, `G[y–z rows, x–z cols] = −R` in planar coordinates. At a
//!   node's rotations this is the rigid-disk form `I_d θ̈_x + Ω I_p θ̇_y = M_x`,
//!   `I_d θ̈_y − Ω I_p θ̇_x = M_y`; `G` is skew-symmetric.
//!
//! K, M_t and M_r are the consistent matrices of the shear-dependent shape functions (cubic
//! `w`, quadratic `φ`, solving the unloaded static equations; checked term by term in the unit
//! tests and against ROSS `shaft_element.py`). The element is statically exact, but its shear
//! force is constant along it, so with shear on the frequencies converge at second order:
//! `ω_h/ω − 1 ≈ (kh)²/24 · U_shear/U` (k the wavenumber, U_shear/U the mode's share of shear
//! strain energy), against fourth order for Euler–Bernoulli (`tests/convergence.rs`,
//! `pinned_timoshenko_error_is_second_order_through_the_shear_energy`).
//!
//! # Axial and torsional DOFs (optional)
//!
//! A rotor may add an axial displacement `u_z` (m, positive along +z) and a torsional rotation
//! `θ_z` (rad, positive counter-clockwise seen from +z, the sense of the spin Ω) per node. They
//! are two-node linear elements on one scalar DOF per node, `[q₁, q₂]`:
//! * axial bar ([`axial_element`]): `K = E A/L [1, −1; −1, 1]`, consistent mass
//!   `M = ρ A L/6 [2, 1; 1, 2]`;
//! * torsion ([`torsion_element`]): `K = G J/L [1, −1; −1, 1]`, `M = ρ J L/6 [2, 1; 1, 2]`,
//!   with `G = E/(2(1+ν))` and the polar second moment `J = π(D⁴ − d⁴)/32` (the torsion
//!   constant of a circular tube).
//!
//! Linear theory: they are uncoupled from bending (no entries between `u_z`, `θ_z` and the
//! lateral DOFs in M, K or G) and from each other; the spin enters only the bending planes'
//! gyroscopic matrix. Linear elements with consistent mass converge at second order in the
//! element length (frequencies are overestimated by `(ω h/c)²/24` per mode, c the wave speed).

/// Section and material data of one element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShaftSection {
    /// Length L (m).
    pub length: f64,
    /// Outer diameter (m).
    pub outer_diameter: f64,
    /// Inner diameter (m), 0 for a solid shaft.
    pub inner_diameter: f64,
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Density ρ (kg/m³).
    pub density: f64,
    /// Include shear deformation (Timoshenko); false gives Euler–Bernoulli (Φ = 0).
    pub shear: bool,
    /// Include the rotary inertia of the bending rotations in the mass matrix. Independent of
    /// the gyroscopic matrix (ROSS's `rotary_inertia` switch): [`shaft_element`] builds `G`
    /// from the rotary-mass pattern either way, and the rotor's `gyroscopic` switch drops it.
    pub rotary_inertia: bool,
}

impl ShaftSection {
    /// Area A = π(D² − d²)/4 (m²).
    pub fn area(&self) -> f64 {
        std::f64::consts::PI * (self.outer_diameter.powi(2) - self.inner_diameter.powi(2)) / 4.0
    }
    /// Second moment I = π(D⁴ − d⁴)/64 (m⁴).
    pub fn inertia(&self) -> f64 {
        std::f64::consts::PI * (self.outer_diameter.powi(4) - self.inner_diameter.powi(4)) / 64.0
    }
    /// Cowper's shear factor of a tube, κ_s = 6(1+ν)(1+r²)² / ((7+6ν)(1+r²)² + (20+12ν)r²),
    /// r = d/D (5/6-like: 0.886 for a solid section with ν = 0.3).
    pub fn shear_factor(&self) -> f64 {
        let nu = self.poisson;
        let r = self.inner_diameter / self.outer_diameter;
        let a = (1.0 + r * r).powi(2);
        6.0 * (1.0 + nu) * a / ((7.0 + 6.0 * nu) * a + (20.0 + 12.0 * nu) * r * r)
    }
    /// Shear parameter Φ = 12 E I/(κ_s G A L²), G = E/(2(1+ν)); 0 without shear.
    pub fn phi(&self) -> f64 {
        if !self.shear {
            return 0.0;
        }
        let g = self.youngs_modulus / (2.0 * (1.0 + self.poisson));
        12.0 * self.youngs_modulus * self.inertia()
            / (self.shear_factor() * g * self.area() * self.length.powi(2))
    }
    /// Mass ρ A L (kg).
    pub fn mass(&self) -> f64 {
        self.density * self.area() * self.length
    }
    /// Polar second moment J = π(D⁴ − d⁴)/32 = 2I (m⁴), the torsion constant of the tube.
    pub fn polar_moment(&self) -> f64 {
        2.0 * self.inertia()
    }
    /// Shear modulus G = E/(2(1+ν)) (Pa).
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson))
    }
}

/// Matrices of a two-node element with one scalar DOF per node, `[q₁, q₂]` (2×2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalarElement {
    /// Consistent mass: kg (axial) or kg·m² (torsion).
    pub m: [[f64; 2]; 2],
    /// Stiffness: N/m (axial) or N·m/rad (torsion).
    pub k: [[f64; 2]; 2],
}

/// `k [1, −1; −1, 1]` and `m/6 [2, 1; 1, 2]`.
fn scalar_element(k: f64, m: f64) -> ScalarElement {
    ScalarElement {
        m: [[m / 3.0, m / 6.0], [m / 6.0, m / 3.0]],
        k: [[k, -k], [-k, k]],
    }
}

/// Axial bar on `[u_z1, u_z2]` (m): `K = E A/L [1, −1; −1, 1]` (N/m),
/// `M = ρ A L/6 [2, 1; 1, 2]` (kg). Uncoupled from bending.
pub fn axial_element(s: &ShaftSection) -> ScalarElement {
    scalar_element(s.youngs_modulus * s.area() / s.length, s.mass())
}

/// Torsion element on `[θ_z1, θ_z2]` (rad, counter-clockwise seen from +z):
/// `K = G J/L [1, −1; −1, 1]` (N·m/rad), `M = ρ J L/6 [2, 1; 1, 2]` (kg·m²),
/// `G = E/(2(1+ν))`, `J = π(D⁴ − d⁴)/32`. Uncoupled from bending; always has its polar
/// inertia (the `rotary_inertia` switch concerns the bending planes only).
pub fn torsion_element(s: &ShaftSection) -> ScalarElement {
    let j = s.polar_moment();
    scalar_element(s.shear_modulus() * j / s.length, s.density * j * s.length)
}

/// Element matrices (8×8, row-major), DOF order as in the module docs.
#[derive(Debug, Clone, PartialEq)]
pub struct ShaftMatrices {
    /// Mass (translational + rotary), kg and kg·m².
    pub m: [[f64; 8]; 8],
    /// Stiffness, N/m, N, N·m.
    pub k: [[f64; 8]; 8],
    /// Gyroscopic matrix per unit spin (multiply by Ω, rad/s), kg·m².
    pub g: [[f64; 8]; 8],
}

/// Planar DOF indices of the x–z and y–z planes and the sign that maps element DOFs to planar
/// `[w₁, φ₁, w₂, φ₂]`.
const XZ: [usize; 4] = [0, 3, 4, 7];
const YZ: [usize; 4] = [1, 2, 5, 6];
const SYZ: [f64; 4] = [1.0, -1.0, 1.0, -1.0];

/// A 4×4 planar element matrix in `[w₁, φ₁, w₂, φ₂]`.
type Planar = [[f64; 4]; 4];

/// Planar (K, M_t, M_r); `M_r` is the rotary-mass pattern whatever `rotary_inertia` says (the
/// caller leaves it out of the mass matrix when it is off; `G` needs it either way).
#[allow(non_snake_case)]
fn planar(s: &ShaftSection) -> (Planar, Planar, Planar) {
    let L = s.length;
    let p = s.phi();
    let ei = s.youngs_modulus * s.inertia();
    let kf = ei / (L.powi(3) * (1.0 + p));
    let K = [
        [12.0 * kf, 6.0 * L * kf, -12.0 * kf, 6.0 * L * kf],
        [
            6.0 * L * kf,
            (4.0 + p) * L * L * kf,
            -6.0 * L * kf,
            (2.0 - p) * L * L * kf,
        ],
        [-12.0 * kf, -6.0 * L * kf, 12.0 * kf, -6.0 * L * kf],
        [
            6.0 * L * kf,
            (2.0 - p) * L * L * kf,
            -6.0 * L * kf,
            (4.0 + p) * L * L * kf,
        ],
    ];
    let mt = s.mass() / (1.0 + p).powi(2);
    let m1 = 13.0 / 35.0 + 7.0 * p / 10.0 + p * p / 3.0;
    let m2 = 11.0 / 210.0 + 11.0 * p / 120.0 + p * p / 24.0;
    let m3 = 9.0 / 70.0 + 3.0 * p / 10.0 + p * p / 6.0;
    let m4 = 13.0 / 420.0 + 3.0 * p / 40.0 + p * p / 24.0;
    let m5 = 1.0 / 105.0 + p / 60.0 + p * p / 120.0;
    let m6 = 1.0 / 140.0 + p / 60.0 + p * p / 120.0;
    let Mt = [
        [m1 * mt, m2 * L * mt, m3 * mt, -m4 * L * mt],
        [m2 * L * mt, m5 * L * L * mt, m4 * L * mt, -m6 * L * L * mt],
        [m3 * mt, m4 * L * mt, m1 * mt, -m2 * L * mt],
        [
            -m4 * L * mt,
            -m6 * L * L * mt,
            -m2 * L * mt,
            m5 * L * L * mt,
        ],
    ];
    let Mr = {
        let mr = s.density * s.inertia() / (L * (1.0 + p).powi(2));
        let r1 = 6.0 / 5.0;
        let r2 = 1.0 / 10.0 - p / 2.0;
        let r3 = 2.0 / 15.0 + p / 6.0 + p * p / 3.0;
        let r4 = -1.0 / 30.0 - p / 6.0 + p * p / 6.0;
        [
            [r1 * mr, r2 * L * mr, -r1 * mr, r2 * L * mr],
            [r2 * L * mr, r3 * L * L * mr, -r2 * L * mr, r4 * L * L * mr],
            [-r1 * mr, -r2 * L * mr, r1 * mr, -r2 * L * mr],
            [r2 * L * mr, r4 * L * L * mr, -r2 * L * mr, r3 * L * L * mr],
        ]
    };
    (K, Mt, Mr)
}

/// Element matrices of a shaft element. `M` holds the rotary inertia only with
/// `rotary_inertia`; `G` is always built (as in ROSS, where the two are separate switches).
pub fn shaft_element(s: &ShaftSection) -> ShaftMatrices {
    let (kp, mt, mr) = planar(s);
    let rot = if s.rotary_inertia { 1.0 } else { 0.0 };
    let mut m = [[0.0; 8]; 8];
    let mut k = [[0.0; 8]; 8];
    let mut g = [[0.0; 8]; 8];
    for a in 0..4 {
        for b in 0..4 {
            let mp = mt[a][b] + rot * mr[a][b];
            m[XZ[a]][XZ[b]] += mp;
            k[XZ[a]][XZ[b]] += kp[a][b];
            m[YZ[a]][YZ[b]] += SYZ[a] * SYZ[b] * mp;
            k[YZ[a]][YZ[b]] += SYZ[a] * SYZ[b] * kp[a][b];
            // R = 2 M_r (I_p = 2 I); x–z rows, y–z columns: +R; y–z rows, x–z columns: −R.
            let r = 2.0 * mr[a][b];
            g[XZ[a]][YZ[b]] += r * SYZ[b];
            g[YZ[a]][XZ[b]] -= SYZ[a] * r;
        }
    }
    ShaftMatrices { m, k, g }
}

/// Rigid disk at a node: mass `m` on u_x, u_y, diametral inertia `id` on θ_x, θ_y and the
/// gyroscopic block `[[0, I_p], [−I_p, 0]]` on (θ_x, θ_y). Returns (M, G) 4×4 in node DOFs.
/// With axial and torsional DOFs the disk also adds `m` to u_z and `I_p` to θ_z (done by the
/// assembly: they are diagonal).
pub fn disk(m: f64, id: f64, ip: f64) -> ([[f64; 4]; 4], [[f64; 4]; 4]) {
    let mut mm = [[0.0; 4]; 4];
    mm[0][0] = m;
    mm[1][1] = m;
    mm[2][2] = id;
    mm[3][3] = id;
    let mut g = [[0.0; 4]; 4];
    g[2][3] = ip;
    g[3][2] = -ip;
    (mm, g)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sec(shear: bool) -> ShaftSection {
        ShaftSection {
            length: 0.1,
            outer_diameter: 0.05,
            inner_diameter: 0.02,
            youngs_modulus: 2.1e11,
            poisson: 0.3,
            density: 7800.0,
            shear,
            rotary_inertia: true,
        }
    }

    /// The shear-dependent ("interdependent interpolation") shape functions of Friswell et al.
    /// (2010) §5.4 in ξ = z/L, as cubic coefficients `[c₀, c₁, c₂, c₃]` of `[w₁, φ₁, w₂, φ₂]`:
    /// (N_w, N_φ). They solve the unloaded static Timoshenko equations.
    #[allow(non_snake_case)]
    fn shape_functions(L: f64, p: f64) -> ([[f64; 4]; 4], [[f64; 4]; 4]) {
        let d = 1.0 + p;
        let nw = [
            [1.0, -p / d, -3.0 / d, 2.0 / d],
            [
                0.0,
                L * (p + 2.0) / (2.0 * d),
                -L * (p + 4.0) / (2.0 * d),
                L / d,
            ],
            [0.0, p / d, 3.0 / d, -2.0 / d],
            [0.0, -L * p / (2.0 * d), L * (p - 2.0) / (2.0 * d), L / d],
        ];
        let nf = [
            [0.0, -6.0 / (L * d), 6.0 / (L * d), 0.0],
            [1.0, -(4.0 + p) / d, 3.0 / d, 0.0],
            [0.0, 6.0 / (L * d), -6.0 / (L * d), 0.0],
            [0.0, (p - 2.0) / d, 3.0 / d, 0.0],
        ];
        (nw, nf)
    }

    fn poly(c: &[f64; 4], x: f64) -> f64 {
        c[0] + x * (c[1] + x * (c[2] + x * c[3]))
    }

    fn dpoly(c: &[f64; 4], x: f64) -> f64 {
        c[1] + x * (2.0 * c[2] + x * 3.0 * c[3])
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
            let mr =
                s.density * s.inertia() / (s.length * (1.0 + p).powi(2)) * r3 * s.length.powi(2);
            assert!((on.m[3][3] - off.m[3][3] - mr).abs() < 1e-12 * mr);
            assert!(
                (on.g[3][2] + 2.0 * mr).abs() < 1e-12 * mr,
                "G = −2 M_r at θ_y θ_x"
            );
            assert!(off.g.iter().flatten().any(|v| *v != 0.0));
        }
    }
}
