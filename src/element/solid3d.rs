//! 3-D isoparametric tetrahedra for stators meshed as solids: 4-node (linear) and 10-node
//! (quadratic) tetrahedra in gmsh's node order (see [`CellKind`]).
//!
//! # Conventions
//!
//! * Element DOFs `[u_x0, u_y0, u_z0, u_x1, …]` (m); local matrices row-major `3n × 3n`.
//! * Voigt strain `ε = [ε_xx, ε_yy, ε_zz, γ_yz, γ_xz, γ_xy]` (engineering shear), stress
//!   `σ = D ε` (Pa), tension positive; isotropic
//!   `D = E/((1+ν)(1−2ν)) [1−ν ν ν; ν 1−ν ν; ν ν 1−ν] ⊕ G I₃`, `G = E/(2(1+ν))`.
//! * Reference tetrahedron `(0,0,0), (1,0,0), (0,1,0), (0,0,1)` (volume 1/6); barycentric
//!   `L₀ = 1−ξ−η−ζ, L₁ = ξ, L₂ = η, L₃ = ζ`; `Tet10`: corners `L_i(2L_i−1)`, edges `4 L_a L_b`.
//! * Quadrature: 1 point (Tet4 stiffness), 4 points degree 2 (Tet10 stiffness, Tet4 mass),
//!   14 points degree 5 (Tet10 mass and error norms, Walkington's rule).
//! * Consistent mass `∫ ρ NᵀN dV`; lumped by HRZ (positive for `Tet10`, whose row sums are not).
//!
//! Kernels fill caller buffers and do not check the Jacobian ([`det_j_range`] does). This
//! module holds what is particular to tetrahedra: the material law, the shape functions and
//! the face loads; the isoparametric kernels are shared with the 2-D cells of
//! [`crate::element::solid2d`] (module `element::solid`), the rules are those of
//! [`crate::element::quadrature`].

pub use super::quadrature::Rule;

use super::quadrature;
use super::solid::Solid;
use crate::mesh::CellKind;

/// Largest number of nodes of a tetrahedron.
pub const MAX_NODES: usize = 10;

/// Isotropic linear elastic solid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic3 {
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
}

impl Elastic3 {
    /// The 6×6 constitutive matrix (Pa).
    pub fn d(&self) -> [[f64; 6]; 6] {
        let (e, v) = (self.youngs_modulus, self.poisson_ratio);
        let c = e / ((1.0 + v) * (1.0 - 2.0 * v));
        let g = e / (2.0 * (1.0 + v));
        let mut d = [[0.0; 6]; 6];
        for i in 0..3 {
            for (j, dij) in d[i][..3].iter_mut().enumerate() {
                *dij = if i == j { c * (1.0 - v) } else { c * v };
            }
            d[3 + i][3 + i] = g;
        }
        d
    }

    /// Stress `σ = D ε` (Pa) of a Voigt strain.
    pub fn stress(&self, eps: [f64; 6]) -> [f64; 6] {
        let d = self.d();
        std::array::from_fn(|i| (0..6).map(|j| d[i][j] * eps[j]).sum())
    }
}

/// von Mises stress of a Voigt stress `[σ_xx, σ_yy, σ_zz, τ_yz, τ_xz, τ_xy]` (Pa).
pub fn von_mises(s: [f64; 6]) -> f64 {
    (0.5 * ((s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2))
        + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]))
        .sqrt()
}

/// Quadrature points `(ξ, w)` of a tetrahedron ([`quadrature::points_3d`]).
///
/// # Panics
/// If `kind` is not a tetrahedron.
pub fn quadrature(kind: CellKind, rule: Rule) -> &'static [([f64; 3], f64)] {
    quadrature::points_3d(kind, rule)
}

/// Reference coordinates of the nodes.
///
/// # Panics
/// If `kind` is not a tetrahedron.
pub fn node_xi(kind: CellKind) -> &'static [[f64; 3]] {
    const C: [[f64; 3]; 10] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.5, 0.0, 0.0],
        [0.5, 0.5, 0.0],
        [0.0, 0.5, 0.0],
        [0.0, 0.0, 0.5],
        [0.0, 0.5, 0.5],
        [0.5, 0.0, 0.5],
    ];
    match kind {
        CellKind::Tet4 => &C[..4],
        CellKind::Tet10 => &C,
        _ => panic!("{} is not a tetrahedron", kind.name()),
    }
}

/// gmsh's edges of the 10-node tetrahedron, nodes 4…9.
const EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)];

/// Shape functions and reference derivatives at `xi`.
///
/// # Panics
/// If `kind` is not a tetrahedron or the buffers are too short.
pub fn shape(kind: CellKind, xi: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
    let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
    let dl = [
        [-1.0, -1.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    match kind {
        CellKind::Tet4 => {
            n[..4].copy_from_slice(&l);
            dn[..4].copy_from_slice(&dl);
        }
        CellKind::Tet10 => {
            for i in 0..4 {
                n[i] = l[i] * (2.0 * l[i] - 1.0);
                for k in 0..3 {
                    dn[i][k] = (4.0 * l[i] - 1.0) * dl[i][k];
                }
            }
            for (m, (a, b)) in EDGES.into_iter().enumerate() {
                n[4 + m] = 4.0 * l[a] * l[b];
                for k in 0..3 {
                    dn[4 + m][k] = 4.0 * (dl[a][k] * l[b] + l[a] * dl[b][k]);
                }
            }
        }
        _ => panic!("{} is not a tetrahedron", kind.name()),
    }
}

/// Tetrahedra for the shared kernels of `element::solid`: Voigt strain
/// `[ε_xx, ε_yy, ε_zz, γ_yz, γ_xz, γ_xy]`.
pub(crate) struct Tetrahedron;

impl Solid<3, 6> for Tetrahedron {
    // Normal strains ∂u_i/∂x_i, then γ_yz = ∂u_y/∂z + ∂u_z/∂y, γ_xz = ∂u_x/∂z + ∂u_z/∂x,
    // γ_xy = ∂u_x/∂y + ∂u_y/∂x.
    const B: [[Option<usize>; 3]; 6] = [
        [Some(0), None, None],
        [None, Some(1), None],
        [None, None, Some(2)],
        [None, Some(2), Some(1)],
        [Some(2), None, Some(0)],
        [Some(1), Some(0), None],
    ];

    fn quadrature(kind: CellKind, rule: Rule) -> &'static [([f64; 3], f64)] {
        quadrature::points_3d(kind, rule)
    }

    fn node_xi(kind: CellKind) -> &'static [[f64; 3]] {
        node_xi(kind)
    }

    fn shape(kind: CellKind, xi: [f64; 3], n: &mut [f64], dn: &mut [[f64; 3]]) {
        shape(kind, xi, n, dn)
    }

    /// `J⁻¹ = adj(J) / det J`, det J by the first row.
    fn invert(j: &[[f64; 3]; 3]) -> (f64, [[f64; 3]; 3]) {
        let det = j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
            - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
            + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
        let inv = [
            [
                (j[1][1] * j[2][2] - j[1][2] * j[2][1]) / det,
                (j[0][2] * j[2][1] - j[0][1] * j[2][2]) / det,
                (j[0][1] * j[1][2] - j[0][2] * j[1][1]) / det,
            ],
            [
                (j[1][2] * j[2][0] - j[1][0] * j[2][2]) / det,
                (j[0][0] * j[2][2] - j[0][2] * j[2][0]) / det,
                (j[0][2] * j[1][0] - j[0][0] * j[1][2]) / det,
            ],
            [
                (j[1][0] * j[2][1] - j[1][1] * j[2][0]) / det,
                (j[0][1] * j[2][0] - j[0][0] * j[2][1]) / det,
                (j[0][0] * j[1][1] - j[0][1] * j[1][0]) / det,
            ],
        ];
        (det, inv)
    }
}

/// Smallest and largest det J over the stiffness points and the corners (a cell is valid when
/// the smallest is positive: right-handed node order, not folded).
pub fn det_j_range(kind: CellKind, x: &[[f64; 3]]) -> (f64, f64) {
    Tetrahedron::det_j_range(kind, x)
}

/// Element stiffness `∫ Bᵀ D B dV` into `ke` (row-major `3n × 3n`, N/m).
///
/// # Panics
/// If `ke.len() != (3n)²`.
pub fn stiffness(kind: CellKind, x: &[[f64; 3]], mat: &Elastic3, ke: &mut [f64]) {
    Tetrahedron::stiffness(kind, x, &mat.d(), 1.0, ke);
}

/// Consistent mass `∫ ρ NᵀN dV` into `me` (row-major `3n × 3n`, kg); `rho` in kg/m³.
///
/// # Panics
/// If `me.len() != (3n)²`.
pub fn mass_consistent(kind: CellKind, x: &[[f64; 3]], rho: f64, me: &mut [f64]) {
    Tetrahedron::mass_consistent(kind, x, rho, me);
}

/// HRZ lumped mass per node (kg) into `m[..n]`: the diagonal of the consistent mass scaled so
/// the node masses sum to the element mass ρ V.
pub fn mass_lumped(kind: CellKind, x: &[[f64; 3]], rho: f64, m: &mut [f64]) {
    Tetrahedron::mass_lumped(kind, x, rho, m);
}

/// Voigt strain at `xi` for element displacements `u` (`[u_x0, u_y0, u_z0, …]`, m).
pub fn strain(kind: CellKind, x: &[[f64; 3]], u: &[f64], xi: [f64; 3]) -> [f64; 6] {
    Tetrahedron::strain(kind, x, u, xi)
}

/// Position, displacement and det J at `xi` (for error norms).
pub fn interpolate(
    kind: CellKind,
    x: &[[f64; 3]],
    u: &[f64],
    xi: [f64; 3],
) -> ([f64; 3], [f64; 3], f64) {
    Tetrahedron::interpolate(kind, x, u, xi)
}

/// Consistent nodal forces of a traction on a triangular face (`Tri3` or `Tri6`, gmsh order)
/// into `f` (`[f_x0, f_y0, f_z0, …]`, N): `f_a = ∫ N_a t(x, n) dA`, with `n` the unit normal
/// `(x₁ − x₀) × (x₂ − x₀)` direction (right-hand rule on the node order).
///
/// # Panics
/// If `kind` is not a triangle or `f` is shorter than `3 × nodes`.
pub fn face_load(
    kind: CellKind,
    x: &[[f64; 3]],
    traction: impl Fn([f64; 3], [f64; 3]) -> [f64; 3],
    f: &mut [f64],
) {
    use crate::element::solid2d;
    assert!(matches!(kind, CellKind::Tri3 | CellKind::Tri6));
    let nn = kind.nodes();
    f[..3 * nn].fill(0.0);
    let mut n = [0.0; 6];
    let mut dn = [[0.0; 2]; 6];
    for &(xi, w) in quadrature::points_2d(CellKind::Tri6, Rule::Mass) {
        solid2d::shape(kind, xi, &mut n, &mut dn);
        let mut p = [0.0; 3];
        let mut t1 = [0.0; 3];
        let mut t2 = [0.0; 3];
        for a in 0..nn {
            for k in 0..3 {
                p[k] += n[a] * x[a][k];
                t1[k] += dn[a][0] * x[a][k];
                t2[k] += dn[a][1] * x[a][k];
            }
        }
        let c = [
            t1[1] * t2[2] - t1[2] * t2[1],
            t1[2] * t2[0] - t1[0] * t2[2],
            t1[0] * t2[1] - t1[1] * t2[0],
        ];
        let ja = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
        let tr = traction(p, [c[0] / ja, c[1] / ja, c[2] / ja]);
        for a in 0..nn {
            for k in 0..3 {
                f[3 * a + k] += w * ja * n[a] * tr[k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cell(kind: CellKind) -> Vec<[f64; 3]> {
        node_xi(kind)
            .iter()
            .map(|p| {
                [
                    0.1 + 0.02 * p[0] + 0.004 * p[1] - 0.002 * p[2],
                    0.05 - 0.003 * p[0] + 0.018 * p[1] + 0.001 * p[2],
                    0.2 + 0.002 * p[0] + 0.001 * p[1] + 0.015 * p[2],
                ]
            })
            .collect()
    }

    #[test]
    fn quadrature_degrees_and_partition_of_unity() {
        let f = |n: u32| (1..=n).product::<u32>().max(1) as f64;
        for (rule, deg) in [(Rule::Stiffness, 2), (Rule::Mass, 5), (Rule::Accurate, 5)] {
            let q = quadrature(CellKind::Tet10, rule);
            for a in 0..=deg {
                for b in 0..=(deg - a) {
                    for c in 0..=(deg - a - b) {
                        let exact = f(a) * f(b) * f(c) / f(a + b + c + 3);
                        let s: f64 = q
                            .iter()
                            .map(|(p, w)| {
                                w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32)
                            })
                            .sum();
                        assert!((s - exact).abs() < 1e-15, "{rule:?} {a}{b}{c}");
                    }
                }
            }
        }
        for kind in [CellKind::Tet4, CellKind::Tet10] {
            let mut n = [0.0; MAX_NODES];
            let mut dn = [[0.0; 3]; MAX_NODES];
            for (i, p) in node_xi(kind).iter().enumerate() {
                shape(kind, *p, &mut n, &mut dn);
                for (j, nj) in n[..kind.nodes()].iter().enumerate() {
                    let delta = if i == j { 1.0 } else { 0.0 };
                    assert!((nj - delta).abs() < 1e-14);
                }
            }
        }
    }

    #[test]
    fn stiffness_has_six_rigid_modes_and_mass_totals() {
        for kind in [CellKind::Tet4, CellKind::Tet10] {
            let x = cell(kind);
            assert!(det_j_range(kind, &x).0 > 0.0);
            let nd = 3 * kind.nodes();
            let mat = Elastic3 {
                youngs_modulus: 2e11,
                poisson_ratio: 0.3,
            };
            let mut ke = vec![0.0; nd * nd];
            stiffness(kind, &x, &mat, &mut ke);
            let kk = nalgebra::DMatrix::from_row_slice(nd, nd, &ke);
            let scale = ke.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            assert!((&kk - kk.transpose()).amax() < 1e-12 * scale);
            let ev = kk.symmetric_eigen().eigenvalues;
            assert_eq!(ev.iter().filter(|v| v.abs() < 1e-8 * scale).count(), 6);
            // Rigid rotation about z gives no force.
            let rot: Vec<f64> = x.iter().flat_map(|p| [-p[1], p[0], 0.0]).collect();
            for i in 0..nd {
                let f: f64 = (0..nd).map(|j| ke[i * nd + j] * rot[j]).sum();
                assert!(f.abs() < 1e-9 * scale);
            }
            let vol = {
                let d = det_j_range(kind, &x).0;
                d / 6.0
            };
            let mut me = vec![0.0; nd * nd];
            mass_consistent(kind, &x, 7800.0, &mut me);
            assert!((me.iter().sum::<f64>() / 3.0 / (7800.0 * vol) - 1.0).abs() < 1e-12);
            let mut ml = [0.0; MAX_NODES];
            mass_lumped(kind, &x, 7800.0, &mut ml);
            assert!(ml[..kind.nodes()].iter().all(|m| *m > 0.0));
            assert!((ml.iter().sum::<f64>() / (7800.0 * vol) - 1.0).abs() < 1e-12);
        }
    }
}
