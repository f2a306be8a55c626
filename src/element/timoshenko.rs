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
//! strain energy), against fourth order for Euler–Bernoulli (`tests/suite/convergence.rs`,
//! `pinned_timoshenko_error_is_second_order_through_the_shear_energy`).
//!
//! # Tapered (conical) elements
//!
//! An element whose diameters vary linearly from `D_l`, `d_l` at node 1 to `D_r`, `d_r` at
//! node 2 (ROSS's `ShaftElement(idl, odl, idr, odr)`; Greenhill, Bickford & Nelson 1985) keeps
//! the shape functions of the cylinder of its mid-section: Φ = 12 E I_m/(κ_s G A_m L²) with
//! `A_m`, `I_m` the area and second moment at ξ = z/L = ½ (the mean diameters) and κ_s Cowper's
//! factor of the mean diameters. The section varies inside the integrals,
//! `A(ξ) = π(D(ξ)² − d(ξ)²)/4`, `I(ξ) = π(D(ξ)⁴ − d(ξ)⁴)/64` (quadratic and quartic in ξ):
//! * `K = ∫ E I(ξ) N_φ′ᵀN_φ′ dz + ∫ κ_s G A(ξ) γᵀγ dz`, γ = N_w′ − N_φ (constant along z);
//! * `M_t = ∫ ρ A(ξ) N_wᵀN_w dz`, `M_r = ∫ ρ I(ξ) N_φᵀN_φ dz`, `G` from `M_r` as above;
//!
//! integrands of degree ≤ 8 in ξ, integrated exactly by 5-point Gauss–Legendre. These are
//! ROSS's closed-form tapered matrices (its a₁, b₁, a₂, b₂, γ, δ polynomial coefficients),
//! checked entry by entry to 1e-15. A cylindrical element (equal ends) uses the closed forms
//! above, which the quadrature reproduces to round-off. The axial and torsional elements of a
//! tapered element use the mean of the end areas `(A_l + A_r)/2` and `J = I_l + I_r`, as ROSS.
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
    /// Outer diameter at node 1 (m); the element's for a cylinder.
    pub outer_diameter: f64,
    /// Inner diameter at node 1 (m), 0 for a solid shaft.
    pub inner_diameter: f64,
    /// Outer diameter at node 2 (m): `outer_diameter` for a cylinder, else a tapered element
    /// (diameters linear in z).
    pub outer_diameter_right: f64,
    /// Inner diameter at node 2 (m): `inner_diameter` for a cylinder.
    pub inner_diameter_right: f64,
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
    /// A cylindrical element of diameters `outer`, `inner` (m) (both ends equal).
    #[allow(clippy::too_many_arguments)]
    pub fn cylinder(
        length: f64,
        outer: f64,
        inner: f64,
        youngs_modulus: f64,
        poisson: f64,
        density: f64,
        shear: bool,
        rotary_inertia: bool,
    ) -> Self {
        ShaftSection {
            length,
            outer_diameter: outer,
            inner_diameter: inner,
            outer_diameter_right: outer,
            inner_diameter_right: inner,
            youngs_modulus,
            poisson,
            density,
            shear,
            rotary_inertia,
        }
    }
    /// Whether the two ends differ (a tapered element).
    pub fn is_tapered(&self) -> bool {
        self.outer_diameter_right != self.outer_diameter
            || self.inner_diameter_right != self.inner_diameter
    }
    /// Outer and inner diameters (m) at ξ = z/L ∈ [0, 1], linear in ξ.
    pub fn diameters_at(&self, xi: f64) -> (f64, f64) {
        (
            self.outer_diameter + (self.outer_diameter_right - self.outer_diameter) * xi,
            self.inner_diameter + (self.inner_diameter_right - self.inner_diameter) * xi,
        )
    }
    /// Mean diameters (outer, inner) (m): the mid-section's.
    fn mean_diameters(&self) -> (f64, f64) {
        (
            (self.outer_diameter + self.outer_diameter_right) / 2.0,
            (self.inner_diameter + self.inner_diameter_right) / 2.0,
        )
    }
    /// Area A = π(D² − d²)/4 (m²) of the mid-section (the section of a cylinder).
    pub fn area(&self) -> f64 {
        let (o, i) = self.mean_diameters();
        tube_area(o, i)
    }
    /// Second moment I = π(D⁴ − d⁴)/64 (m⁴) of the mid-section (the section of a cylinder).
    pub fn inertia(&self) -> f64 {
        let (o, i) = self.mean_diameters();
        tube_inertia(o, i)
    }
    /// Area (m²) at node 1 (`left`) or node 2.
    pub fn end_area(&self, left: bool) -> f64 {
        if left {
            tube_area(self.outer_diameter, self.inner_diameter)
        } else {
            tube_area(self.outer_diameter_right, self.inner_diameter_right)
        }
    }
    /// Second moment (m⁴) at node 1 (`left`) or node 2.
    pub fn end_inertia(&self, left: bool) -> f64 {
        if left {
            tube_inertia(self.outer_diameter, self.inner_diameter)
        } else {
            tube_inertia(self.outer_diameter_right, self.inner_diameter_right)
        }
    }
    /// Cowper's shear factor of a tube, κ_s = 6(1+ν)(1+r²)² / ((7+6ν)(1+r²)² + (20+12ν)r²),
    /// r = d/D of the mean diameters (5/6-like: 0.886 for a solid section with ν = 0.3).
    pub fn shear_factor(&self) -> f64 {
        let nu = self.poisson;
        let (o, i) = self.mean_diameters();
        let r = i / o;
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
    /// Mass ρ ∫A dz (kg): ρ A L for a cylinder, ρ π L (D_l² + D_l D_r + D_r² − d_l² − d_l d_r −
    /// d_r²)/12 for a tapered element.
    pub fn mass(&self) -> f64 {
        if !self.is_tapered() {
            return self.density * self.area() * self.length;
        }
        let (ol, il, or, ir) = (
            self.outer_diameter,
            self.inner_diameter,
            self.outer_diameter_right,
            self.inner_diameter_right,
        );
        self.density * std::f64::consts::PI * self.length / 12.0
            * ((ol * ol + ol * or + or * or) - (il * il + il * ir + ir * ir))
    }
    /// Spin inertia ρ ∫2I dz (kg·m²): the element's polar moment of inertia about the axis
    /// (5-point Gauss, exact for the quartic I(ξ)).
    pub fn spin_inertia(&self) -> f64 {
        if !self.is_tapered() {
            return self.density * 2.0 * self.inertia() * self.length;
        }
        GAUSS5
            .iter()
            .map(|(t, w)| {
                let (o, i) = self.diameters_at((1.0 + t) / 2.0);
                w * tube_inertia(o, i)
            })
            .sum::<f64>()
            * self.density
            * self.length
    }
    /// Polar second moment J (m⁴) of the torsion element: π(D⁴ − d⁴)/32 = 2I for a cylinder,
    /// `I_l + I_r` (twice the mean of the ends, as ROSS) for a tapered element.
    pub fn polar_moment(&self) -> f64 {
        self.end_inertia(true) + self.end_inertia(false)
    }
    /// Area of the axial element (m²): A for a cylinder, `(A_l + A_r)/2` for a tapered one.
    pub fn axial_area(&self) -> f64 {
        (self.end_area(true) + self.end_area(false)) / 2.0
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
/// A tapered element uses `A = (A_l + A_r)/2` in both (ROSS).
pub fn axial_element(s: &ShaftSection) -> ScalarElement {
    let a = s.axial_area();
    scalar_element(s.youngs_modulus * a / s.length, s.density * a * s.length)
}

/// π(D² − d²)/4 (m²).
fn tube_area(outer: f64, inner: f64) -> f64 {
    std::f64::consts::PI * (outer.powi(2) - inner.powi(2)) / 4.0
}

/// π(D⁴ − d⁴)/64 (m⁴).
fn tube_inertia(outer: f64, inner: f64) -> f64 {
    std::f64::consts::PI * (outer.powi(4) - inner.powi(4)) / 64.0
}

/// 5-point Gauss–Legendre nodes and weights on [−1, 1] (exact to degree 9).
const GAUSS5: [(f64, f64); 5] = [
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (-0.538_469_310_105_683, 0.478_628_670_499_366_5),
    (0.0, 0.568_888_888_888_888_9),
    (0.538_469_310_105_683, 0.478_628_670_499_366_5),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

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
    if s.is_tapered() {
        return planar_integrated(s);
    }
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

/// The shear-dependent ("interdependent interpolation") shape functions of Friswell et al.
/// (2010) §5.4 in ξ = z/L for shear parameter `p` = Φ, as cubic coefficients
/// `[c₀, c₁, c₂, c₃]` (in powers of ξ) of the planar DOFs `[w₁, φ₁, w₂, φ₂]`: (N_w, N_φ). They
/// solve the unloaded static Timoshenko equations; with Φ = 0 they are the Hermite cubics and
/// N_φ = N_w′.
#[allow(non_snake_case)]
fn shape_functions(L: f64, p: f64) -> (Planar, Planar) {
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

/// `c₀ + c₁ξ + c₂ξ² + c₃ξ³`.
fn poly(c: &[f64; 4], x: f64) -> f64 {
    c[0] + x * (c[1] + x * (c[2] + x * c[3]))
}

/// d/dξ of [`poly`].
fn dpoly(c: &[f64; 4], x: f64) -> f64 {
    c[1] + x * (2.0 * c[2] + x * 3.0 * c[3])
}

/// Planar (K, M_t, M_r) as the integrals of the module docs (tapered elements; exact by
/// 5-point Gauss for A(ξ) quadratic, I(ξ) quartic and the cubic shape functions): bending
/// `E I(ξ) N_φ′ᵀN_φ′`, shear `κ_s G A(ξ) γᵀγ` (γ = N_w′ − N_φ; only with shear), translation
/// `ρ A(ξ) N_wᵀN_w`, rotation `ρ I(ξ) N_φᵀN_φ`, with Φ, κ_s of the mid-section.
#[allow(non_snake_case)]
fn planar_integrated(s: &ShaftSection) -> (Planar, Planar, Planar) {
    let L = s.length;
    let (nw, nf) = shape_functions(L, s.phi());
    let kg = if s.shear {
        s.shear_factor() * s.shear_modulus()
    } else {
        0.0
    };
    let (mut k, mut mt, mut mr) = ([[0.0; 4]; 4], [[0.0; 4]; 4], [[0.0; 4]; 4]);
    for (t, wt) in GAUSS5 {
        let (x, dz) = ((1.0 + t) / 2.0, wt * L / 2.0);
        let (o, i) = s.diameters_at(x);
        let (a, ii) = (tube_area(o, i), tube_inertia(o, i));
        let w: [f64; 4] = std::array::from_fn(|j| poly(&nw[j], x));
        let f: [f64; 4] = std::array::from_fn(|j| poly(&nf[j], x));
        let df: [f64; 4] = std::array::from_fn(|j| dpoly(&nf[j], x) / L);
        let g: [f64; 4] = std::array::from_fn(|j| dpoly(&nw[j], x) / L - f[j]);
        for p in 0..4 {
            for q in 0..4 {
                k[p][q] += dz * (s.youngs_modulus * ii * df[p] * df[q] + kg * a * g[p] * g[q]);
                mt[p][q] += dz * s.density * a * w[p] * w[q];
                mr[p][q] += dz * s.density * ii * f[p] * f[q];
            }
        }
    }
    (k, mt, mr)
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

/// The equivalent load of a thermal curvature on the part `ξ ∈ [ξ₁, ξ₂]` (ξ = z/L) of the
/// element, per unit curvature (1/m): `(f_xz, f_yz)`, in element DOFs (N·m per 1/m, i.e. N·m²,
/// on rotations; N·m² per m on translations), for a curvature `∂²u_x/∂z²` in the x–z plane
/// and `∂²u_y/∂z²` in the y–z plane.
///
/// A free curvature κ_T (the thermal strain `α ΔT / D` across the section) enters the bending
/// energy as `½ ∫ E I (φ′ − κ_T)² dz`; the shear strain `w′ − φ` is untouched. Its load is the
/// virtual work `∫ E I κ_T δφ′ dz`: in planar DOFs `∫_{ξ₁}^{ξ₂} E I(ξ) N_φ′ dz` (5-point
/// Gauss, exact for the tapered element's quartic I and the linear N_φ′). On a whole element
/// of constant I this is the moment pair `E I [0, −1, 0, 1]` (`N_φ(1) − N_φ(0)`), and the
/// element, statically exact, bends under it into the free uniform curvature κ_T with no shear
/// (the unit tests check it); on part of an element it is the consistent load, exact as the
/// element is refined.
///
/// # Panics
/// If not `0 ≤ ξ₁ ≤ ξ₂ ≤ 1` (a bug of the caller).
#[allow(non_snake_case)]
pub fn thermal_curvature_load(s: &ShaftSection, (x1, x2): (f64, f64)) -> ([f64; 8], [f64; 8]) {
    assert!((0.0..=x2).contains(&x1) && x2 <= 1.0, "ξ range {x1} … {x2}");
    let L = s.length;
    let (_, nf) = shape_functions(L, s.phi());
    let mut p = [0.0; 4];
    for (t, wt) in GAUSS5 {
        let x = x1 + (x2 - x1) * (1.0 + t) / 2.0;
        let dz = wt * (x2 - x1) * L / 2.0;
        let (o, i) = s.diameters_at(x);
        let ei = s.youngs_modulus * tube_inertia(o, i);
        for (pj, c) in p.iter_mut().zip(&nf) {
            *pj += dz * ei * dpoly(c, x) / L;
        }
    }
    let (mut fx, mut fy) = ([0.0; 8], [0.0; 8]);
    for j in 0..4 {
        fx[XZ[j]] = p[j];
        fy[YZ[j]] = SYZ[j] * p[j];
    }
    (fx, fy)
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
mod tests;
