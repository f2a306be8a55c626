//! 2-D isoparametric continuum elements in plane stress or plane strain: 3- and 6-node
//! triangles, 4-, 8- and 9-node quadrilaterals (gmsh node order, see [`CellKind`]).
//!
//! # Conventions
//!
//! * Element DOFs are `[u_x0, u_y0, u_x1, u_y1, …]` (m) in the cell's node order; local matrices
//!   are row-major `2n × 2n`.
//! * Strain is engineering strain `ε = [ε_xx, ε_yy, γ_xy]` (γ_xy = ∂u_x/∂y + ∂u_y/∂x), stress
//!   `σ = D ε = [σ_xx, σ_yy, τ_xy]` (Pa), tension positive.
//! * Plane stress: `σ_zz = 0`, `D = E/(1−ν²) [1 ν 0; ν 1 0; 0 0 (1−ν)/2]`. Plane strain:
//!   `ε_zz = 0`, `D = E/((1+ν)(1−2ν)) [1−ν ν 0; ν 1−ν 0; 0 0 (1−2ν)/2]`, `σ_zz = ν(σ_xx+σ_yy)`.
//! * Stiffness `K = ∫ Bᵀ D B t dA` (N/m) with `t` the thickness (m); consistent mass
//!   `M = ∫ ρ t NᵀN dA` (kg); lumped mass by HRZ (diagonal of the consistent mass scaled to the
//!   element mass), which is positive for every cell type (a row sum is not, for `Tri6`, `Quad8`).
//! * Reference cells: triangle `(0,0), (1,0), (0,1)`; quadrilateral `[−1, 1]²`.
//!
//! Kernels are pure functions of the cell's coordinates filling caller buffers; they do not
//! check the Jacobian (call [`det_j_range`] first) and panic on a buffer of the wrong size.
//! This module holds what is particular to 2-D: the material law, the shape functions and the
//! edge loads; the isoparametric kernels are shared with the tetrahedra of
//! [`crate::element::solid3d`] (module `element::solid`), the rules are those of
//! [`crate::element::quadrature`].

pub use super::quadrature::{gauss_1d, Rule};

use super::quadrature;
use super::solid::Solid;
use crate::mesh::CellKind;

/// Largest number of nodes of a 2-D cell.
pub const MAX_NODES: usize = 9;

/// Plane stress or plane strain.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Plane {
    /// σ_zz = 0 (thin plates, the default for stator sections).
    Stress,
    /// ε_zz = 0 (long bodies).
    Strain,
}

/// Isotropic linear elastic material of a 2-D section.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic2 {
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Poisson's ratio ν.
    pub poisson_ratio: f64,
    /// Out-of-plane thickness t (m).
    pub thickness: f64,
    /// Plane stress or strain.
    pub plane: Plane,
}

impl Elastic2 {
    /// The 3×3 constitutive matrix D (Pa).
    pub fn d(&self) -> [[f64; 3]; 3] {
        let (e, v) = (self.youngs_modulus, self.poisson_ratio);
        match self.plane {
            Plane::Stress => {
                let c = e / (1.0 - v * v);
                [
                    [c, c * v, 0.0],
                    [c * v, c, 0.0],
                    [0.0, 0.0, c * (1.0 - v) / 2.0],
                ]
            }
            Plane::Strain => {
                let c = e / ((1.0 + v) * (1.0 - 2.0 * v));
                [
                    [c * (1.0 - v), c * v, 0.0],
                    [c * v, c * (1.0 - v), 0.0],
                    [0.0, 0.0, c * (1.0 - 2.0 * v) / 2.0],
                ]
            }
        }
    }

    /// Stress `[σ_xx, σ_yy, τ_xy, σ_zz]` (Pa) of an engineering strain `[ε_xx, ε_yy, γ_xy]`.
    pub fn stress(&self, eps: [f64; 3]) -> [f64; 4] {
        let d = self.d();
        let s: [f64; 3] = std::array::from_fn(|i| (0..3).map(|j| d[i][j] * eps[j]).sum());
        let szz = match self.plane {
            Plane::Stress => 0.0,
            Plane::Strain => self.poisson_ratio * (s[0] + s[1]),
        };
        [s[0], s[1], s[2], szz]
    }
}

/// von Mises equivalent stress of `[σ_xx, σ_yy, τ_xy, σ_zz]` (Pa).
pub fn von_mises(s: [f64; 4]) -> f64 {
    let [sx, sy, t, sz] = s;
    (0.5 * ((sx - sy).powi(2) + (sy - sz).powi(2) + (sz - sx).powi(2)) + 3.0 * t * t).sqrt()
}

/// Quadrature points `(ξ, w)` of a rule on a cell ([`quadrature::points_2d`]), written into
/// `out`; returns the count.
///
/// # Panics
/// If `kind` is not a 2-D cell.
pub fn quadrature(kind: CellKind, rule: Rule, out: &mut Vec<([f64; 2], f64)>) -> usize {
    out.clear();
    out.extend_from_slice(quadrature::points_2d(kind, rule));
    out.len()
}

/// Reference coordinates of the nodes of a cell.
///
/// # Panics
/// If `kind` is not a 2-D cell.
pub fn node_xi(kind: CellKind) -> &'static [[f64; 2]] {
    match kind {
        CellKind::Tri3 => &[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
        CellKind::Tri6 => &[
            [0.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [0.5, 0.0],
            [0.5, 0.5],
            [0.0, 0.5],
        ],
        CellKind::Quad4 => &[[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]],
        CellKind::Quad8 => &[
            [-1.0, -1.0],
            [1.0, -1.0],
            [1.0, 1.0],
            [-1.0, 1.0],
            [0.0, -1.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [-1.0, 0.0],
        ],
        CellKind::Quad9 => &[
            [-1.0, -1.0],
            [1.0, -1.0],
            [1.0, 1.0],
            [-1.0, 1.0],
            [0.0, -1.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [-1.0, 0.0],
            [0.0, 0.0],
        ],
        _ => panic!("{} is not a 2-D cell", kind.name()),
    }
}

/// Shape functions `n[i]` and their reference derivatives `dn[i] = [∂N_i/∂ξ, ∂N_i/∂η]` at `xi`.
///
/// # Panics
/// If `kind` is not a 2-D cell or the buffers are shorter than its node count.
pub fn shape(kind: CellKind, xi: [f64; 2], n: &mut [f64], dn: &mut [[f64; 2]]) {
    let [x, y] = xi;
    match kind {
        CellKind::Tri3 => {
            n[..3].copy_from_slice(&[1.0 - x - y, x, y]);
            dn[..3].copy_from_slice(&[[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]]);
        }
        CellKind::Tri6 => {
            let l = [1.0 - x - y, x, y];
            // dL/dξ, dL/dη
            let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
            for i in 0..3 {
                n[i] = l[i] * (2.0 * l[i] - 1.0);
                for k in 0..2 {
                    dn[i][k] = (4.0 * l[i] - 1.0) * dl[i][k];
                }
            }
            for (m, (a, b)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
                n[3 + m] = 4.0 * l[a] * l[b];
                for k in 0..2 {
                    dn[3 + m][k] = 4.0 * (dl[a][k] * l[b] + l[a] * dl[b][k]);
                }
            }
        }
        CellKind::Quad4 => {
            for (i, p) in node_xi(kind).iter().enumerate() {
                n[i] = 0.25 * (1.0 + p[0] * x) * (1.0 + p[1] * y);
                dn[i] = [
                    0.25 * p[0] * (1.0 + p[1] * y),
                    0.25 * p[1] * (1.0 + p[0] * x),
                ];
            }
        }
        CellKind::Quad8 => {
            for (i, p) in node_xi(kind).iter().enumerate() {
                if i < 4 {
                    let (a, b) = (1.0 + p[0] * x, 1.0 + p[1] * y);
                    let c = p[0] * x + p[1] * y - 1.0;
                    n[i] = 0.25 * a * b * c;
                    dn[i] = [0.25 * p[0] * b * (c + a), 0.25 * p[1] * a * (c + b)];
                } else if p[0] == 0.0 {
                    n[i] = 0.5 * (1.0 - x * x) * (1.0 + p[1] * y);
                    dn[i] = [-x * (1.0 + p[1] * y), 0.5 * (1.0 - x * x) * p[1]];
                } else {
                    n[i] = 0.5 * (1.0 + p[0] * x) * (1.0 - y * y);
                    dn[i] = [0.5 * p[0] * (1.0 - y * y), -y * (1.0 + p[0] * x)];
                }
            }
        }
        CellKind::Quad9 => {
            // Lagrange quadratics at −1, 0, 1 and their derivatives.
            let l = |t: f64, a: f64| -> (f64, f64) {
                if a < -0.5 {
                    (0.5 * t * (t - 1.0), t - 0.5)
                } else if a > 0.5 {
                    (0.5 * t * (t + 1.0), t + 0.5)
                } else {
                    (1.0 - t * t, -2.0 * t)
                }
            };
            for (i, p) in node_xi(kind).iter().enumerate() {
                let (lx, dlx) = l(x, p[0]);
                let (ly, dly) = l(y, p[1]);
                n[i] = lx * ly;
                dn[i] = [dlx * ly, lx * dly];
            }
        }
        _ => panic!("{} is not a 2-D cell", kind.name()),
    }
}

/// The 2-D cells for the shared kernels of `element::solid`: strain `[ε_xx, ε_yy, γ_xy]`.
pub(crate) struct Section;

impl Solid<2, 3> for Section {
    // ε_xx = ∂u_x/∂x, ε_yy = ∂u_y/∂y, γ_xy = ∂u_x/∂y + ∂u_y/∂x.
    const B: [[Option<usize>; 2]; 3] = [[Some(0), None], [None, Some(1)], [Some(1), Some(0)]];

    fn quadrature(kind: CellKind, rule: Rule) -> &'static [([f64; 2], f64)] {
        quadrature::points_2d(kind, rule)
    }

    fn node_xi(kind: CellKind) -> &'static [[f64; 2]] {
        node_xi(kind)
    }

    fn shape(kind: CellKind, xi: [f64; 2], n: &mut [f64], dn: &mut [[f64; 2]]) {
        shape(kind, xi, n, dn)
    }

    /// `J⁻¹ = [j₁₁ −j₀₁; −j₁₀ j₀₀] / det J`.
    fn invert(j: &[[f64; 2]; 2]) -> (f64, [[f64; 2]; 2]) {
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let inv = [
            [j[1][1] / det, -j[0][1] / det],
            [-j[1][0] / det, j[0][0] / det],
        ];
        (det, inv)
    }
}

/// Smallest and largest det J over the stiffness quadrature points and the corners (a cell is
/// valid when the smallest is positive: counter-clockwise and not folded).
///
/// # Panics
/// If `x` has fewer points than the cell's nodes.
pub fn det_j_range(kind: CellKind, x: &[[f64; 2]]) -> (f64, f64) {
    Section::det_j_range(kind, x)
}

/// Element stiffness `K = ∫ Bᵀ D B t dA` into `ke` (row-major `2n × 2n`, N/m).
///
/// # Panics
/// If `ke.len() != (2n)²` or `x` is too short.
pub fn stiffness(kind: CellKind, x: &[[f64; 2]], mat: &Elastic2, ke: &mut [f64]) {
    Section::stiffness(kind, x, &mat.d(), mat.thickness, ke);
}

/// Consistent mass `M = ∫ ρ t NᵀN dA` into `me` (row-major `2n × 2n`, kg); `rho_t` = ρ t
/// (kg/m²).
///
/// # Panics
/// If `me.len() != (2n)²`.
pub fn mass_consistent(kind: CellKind, x: &[[f64; 2]], rho_t: f64, me: &mut [f64]) {
    Section::mass_consistent(kind, x, rho_t, me);
}

/// HRZ lumped mass per node (kg) into `m[..n]`: the diagonal of the consistent mass scaled so
/// the node masses sum to the element mass ρ t A. Every entry is positive.
pub fn mass_lumped(kind: CellKind, x: &[[f64; 2]], rho_t: f64, m: &mut [f64]) {
    Section::mass_lumped(kind, x, rho_t, m);
}

/// Area of the cell (m²).
pub fn area(kind: CellKind, x: &[[f64; 2]]) -> f64 {
    Section::measure(kind, x)
}

/// Engineering strain `[ε_xx, ε_yy, γ_xy]` at reference point `xi` for element displacements
/// `u` (`[u_x0, u_y0, …]`, m).
pub fn strain(kind: CellKind, x: &[[f64; 2]], u: &[f64], xi: [f64; 2]) -> [f64; 3] {
    Section::strain(kind, x, u, xi)
}

/// Position and interpolated displacement at reference point `xi`, and det J (for error
/// norms): `(x, u, det J)`.
pub fn interpolate(
    kind: CellKind,
    x: &[[f64; 2]],
    u: &[f64],
    xi: [f64; 2],
) -> ([f64; 2], [f64; 2], f64) {
    Section::interpolate(kind, x, u, xi)
}

/// Consistent nodal forces of a traction on an edge (`Line2` or `Line3`, gmsh order: ends then
/// middle) into `f` (`[f_x0, f_y0, …]`, N): `f_a = ∫ N_a t(x, n) thickness ds`, with `n` the
/// unit normal to the right of the edge direction (node 0 → node 1), i.e. `(t_y, −t_x)`.
///
/// # Panics
/// If `kind` is not a line or `f` is shorter than `2 × nodes`.
pub fn edge_load(
    kind: CellKind,
    x: &[[f64; 2]],
    thickness: f64,
    traction: impl Fn([f64; 2], [f64; 2]) -> [f64; 2],
    f: &mut [f64],
) {
    let nn = kind.nodes();
    assert!(matches!(kind, CellKind::Line2 | CellKind::Line3));
    f[..2 * nn].fill(0.0);
    for &(s, w) in gauss_1d(3) {
        // Shape functions on [−1, 1]: ends at ∓1, middle at 0.
        let (n, dn): (Vec<f64>, Vec<f64>) = if nn == 2 {
            (vec![0.5 * (1.0 - s), 0.5 * (1.0 + s)], vec![-0.5, 0.5])
        } else {
            (
                vec![0.5 * s * (s - 1.0), 0.5 * s * (s + 1.0), 1.0 - s * s],
                vec![s - 0.5, s + 0.5, -2.0 * s],
            )
        };
        let mut p = [0.0; 2];
        let mut t = [0.0; 2];
        for a in 0..nn {
            for k in 0..2 {
                p[k] += n[a] * x[a][k];
                t[k] += dn[a] * x[a][k];
            }
        }
        let js = t[0].hypot(t[1]);
        let normal = [t[1] / js, -t[0] / js];
        let tr = traction(p, normal);
        for a in 0..nn {
            for k in 0..2 {
                f[2 * a + k] += w * js * thickness * n[a] * tr[k];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const KINDS: [CellKind; 5] = [
        CellKind::Tri3,
        CellKind::Tri6,
        CellKind::Quad4,
        CellKind::Quad8,
        CellKind::Quad9,
    ];

    /// The reference nodes mapped by a skewing affine map (an undistorted but general cell).
    fn cell(kind: CellKind) -> Vec<[f64; 2]> {
        node_xi(kind)
            .iter()
            .map(|p| {
                [
                    0.3 + 0.02 * p[0] + 0.005 * p[1],
                    -0.1 + 0.003 * p[0] + 0.015 * p[1],
                ]
            })
            .collect()
    }

    const MAT: Elastic2 = Elastic2 {
        youngs_modulus: 200e9,
        poisson_ratio: 0.3,
        thickness: 0.01,
        plane: Plane::Stress,
    };

    #[test]
    fn partition_of_unity_and_nodal_interpolation() {
        for k in KINDS {
            let mut n = [0.0; MAX_NODES];
            let mut dn = [[0.0; 2]; MAX_NODES];
            for (i, p) in node_xi(k).iter().enumerate() {
                shape(k, *p, &mut n, &mut dn);
                for (j, nj) in n[..k.nodes()].iter().enumerate() {
                    let delta = if i == j { 1.0 } else { 0.0 };
                    assert!((nj - delta).abs() < 1e-14, "{k:?}");
                }
            }
            shape(k, [0.21, 0.13], &mut n, &mut dn);
            assert!((n[..k.nodes()].iter().sum::<f64>() - 1.0).abs() < 1e-14);
            let s: [f64; 2] = [0, 1].map(|c| dn[..k.nodes()].iter().map(|d| d[c]).sum());
            assert!(s[0].abs() < 1e-13 && s[1].abs() < 1e-13, "{k:?} {s:?}");
            // Derivatives against central differences.
            let h = 1e-6;
            let mut np = [0.0; MAX_NODES];
            let mut nm = [0.0; MAX_NODES];
            for c in 0..2 {
                let mut a = [0.21, 0.13];
                a[c] += h;
                shape(k, a, &mut np, &mut [[0.0; 2]; MAX_NODES]);
                a[c] -= 2.0 * h;
                shape(k, a, &mut nm, &mut [[0.0; 2]; MAX_NODES]);
                for j in 0..k.nodes() {
                    let fd = (np[j] - nm[j]) / (2.0 * h);
                    assert!((fd - dn[j][c]).abs() < 1e-8, "{k:?} node {j} dir {c}");
                }
            }
        }
    }

    #[test]
    fn quadrature_rules_integrate_their_degree() {
        // Triangle: ∫ ξ^a η^b = a! b! / (a+b+2)!.
        let fact = |n: u32| (1..=n).product::<u32>().max(1) as f64;
        let mut q = Vec::new();
        for (rule, deg) in [(Rule::Stiffness, 1), (Rule::Mass, 4), (Rule::Accurate, 5)] {
            quadrature(CellKind::Tri6, rule, &mut q);
            let deg = if rule == Rule::Stiffness { 2 } else { deg };
            for a in 0..=deg {
                for b in 0..=(deg - a) {
                    let exact = fact(a) * fact(b) / fact(a + b + 2);
                    let s: f64 = q
                        .iter()
                        .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32))
                        .sum();
                    assert!(
                        (s - exact).abs() < 1e-13,
                        "{rule:?} ξ^{a} η^{b}: {s} vs {exact}"
                    );
                }
            }
        }
        for n in 1..=4 {
            for d in 0..2 * n {
                let exact = if d % 2 == 1 {
                    0.0
                } else {
                    2.0 / (d as f64 + 1.0)
                };
                let s: f64 = gauss_1d(n).iter().map(|(x, w)| w * x.powi(d as i32)).sum();
                assert!((s - exact).abs() < 1e-14, "gauss {n} x^{d}");
            }
        }
    }

    #[test]
    fn stiffness_is_symmetric_with_three_rigid_modes() {
        for k in KINDS {
            let x = cell(k);
            let nd = 2 * k.nodes();
            let mut ke = vec![0.0; nd * nd];
            stiffness(k, &x, &MAT, &mut ke);
            let scale = ke.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            for i in 0..nd {
                for j in 0..nd {
                    assert!((ke[i * nd + j] - ke[j * nd + i]).abs() < 1e-12 * scale);
                }
            }
            // Rigid translations and the infinitesimal rotation give no force.
            let modes: [Vec<f64>; 3] = [
                x.iter().flat_map(|_| [1.0, 0.0]).collect(),
                x.iter().flat_map(|_| [0.0, 1.0]).collect(),
                x.iter().flat_map(|p| [-p[1], p[0]]).collect(),
            ];
            for m in &modes {
                for i in 0..nd {
                    let f: f64 = (0..nd).map(|j| ke[i * nd + j] * m[j]).sum();
                    assert!(f.abs() < 1e-9 * scale, "{k:?}: rigid mode force {f}");
                }
            }
            // Exactly three zero eigenvalues: K + rigid projector is positive definite.
            let kk = nalgebra::DMatrix::from_row_slice(nd, nd, &ke);
            let ev = kk.symmetric_eigen().eigenvalues;
            let zeros = ev.iter().filter(|v| v.abs() < 1e-8 * scale).count();
            assert_eq!(zeros, 3, "{k:?}: eigenvalues {ev}");
        }
    }

    #[test]
    fn mass_sums_to_rho_t_area_and_lumps_positive() {
        for k in KINDS {
            let x = cell(k);
            let nd = 2 * k.nodes();
            let a = area(k, &x);
            // The affine map's determinant times the reference area.
            let refa = if matches!(k, CellKind::Tri3 | CellKind::Tri6) {
                0.5
            } else {
                4.0
            };
            let detj = 0.02 * 0.015 - 0.005 * 0.003;
            assert!(
                (a / (refa * detj) - 1.0).abs() < 1e-13,
                "{k:?} area {a} vs {}",
                refa * detj
            );
            let mut me = vec![0.0; nd * nd];
            mass_consistent(k, &x, 7.8e3 * 0.01, &mut me);
            let total: f64 = me.iter().sum::<f64>() / 2.0;
            assert!((total / (7.8e3 * 0.01 * a) - 1.0).abs() < 1e-12);
            let mut ml = vec![0.0; k.nodes()];
            mass_lumped(k, &x, 7.8e3 * 0.01, &mut ml);
            assert!(ml.iter().all(|m| *m > 0.0), "{k:?}: {ml:?}");
            assert!((ml.iter().sum::<f64>() / (7.8e3 * 0.01 * a) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn clockwise_cell_has_negative_jacobian() {
        let mut x = cell(CellKind::Quad4);
        assert!(det_j_range(CellKind::Quad4, &x).0 > 0.0);
        x.swap(1, 3);
        assert!(det_j_range(CellKind::Quad4, &x).1 < 0.0);
    }

    #[test]
    fn edge_load_of_uniform_traction_sums_to_its_resultant() {
        let x = [[0.0, 0.0], [0.2, 0.0], [0.1, 0.0]];
        let mut f = [0.0; 6];
        edge_load(CellKind::Line3, &x, 0.01, |_, n| [0.0, 5.0 * n[1]], &mut f);
        // Edge along +x: right normal is −y; resultant 5 · (−1) · 0.2 · 0.01.
        let fy: f64 = f.iter().skip(1).step_by(2).sum();
        assert!((fy + 0.01).abs() < 1e-15, "{f:?}");
        // Simpson weights 1/6, 1/6, 4/6 for a quadratic edge.
        assert!((f[5] / fy - 2.0 / 3.0).abs() < 1e-12);
    }
}
