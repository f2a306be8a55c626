//! The dimension-generic half of the isoparametric solid elements: what a 2-D section
//! ([`crate::element::solid2d`]) and a 3-D tetrahedron ([`crate::element::solid3d`]) compute
//! the same way once their shape functions are known.
//!
//! A cell family in `D` dimensions with `S` Voigt strain components implements [`Solid`] with
//! its shape functions, node coordinates, quadrature rules, Jacobian inverse and the pattern of
//! its strain–displacement matrix; the provided methods are the kernels:
//!
//! * isoparametric map and physical gradients: `J_rc = Σ_a x_a,r ∂N_a/∂ξ_c`,
//!   `∂N_a/∂x_k = Σ_c ∂N_a/∂ξ_c (J⁻¹)_ck`, and the range of det J;
//! * stiffness `K = ∫ Bᵀ D B t dV` (t = 1 in 3-D, the thickness in 2-D; N/m);
//! * scalar mass `∫ ρ N_a N_b dV`, consistent mass (the scalar mass on each of the D
//!   displacement components; kg) and HRZ lumped mass;
//! * strain `ε = B u`, interpolation of position and displacement, measure of the cell.
//!
//! Element DOFs are `[u_0, …, u_{D−1}]` per node in the cell's node order; local matrices are
//! row-major `Dn × Dn`.
//!
//! # Floating point
//!
//! The sums start from `−0.0`, the additive identity of IEEE arithmetic (`−0.0 + x = x` for
//! every `x`, which is also where `Iterator::sum` starts), and take only the non-zero entries of
//! B in ascending order; each kernel therefore performs the same operations in the same order
//! as the hand-written 2-D and 3-D kernels it replaces, and gives the same bits.

use super::quadrature::Rule;
use crate::mesh::CellKind;

/// Length of the per-node scratch arrays: the largest node count of any solid cell (`Tet10`).
const MAX_NODES: usize = 10;

/// A family of isoparametric solid cells in `D` dimensions with `S` strain components: the
/// parts that differ between dimensions; the kernels are the provided methods.
pub(crate) trait Solid<const D: usize, const S: usize> {
    /// Pattern of the strain–displacement matrix `B_a` (S × D) of node a: `B[k][c] = Some(i)`
    /// when strain component k gets `∂N_a/∂x_i · u_c`, `None` when `B_a[k][c] = 0`. Normal
    /// strains first, then engineering shears `γ_pq = ∂u_p/∂x_q + ∂u_q/∂x_p`.
    const B: [[Option<usize>; D]; S];

    /// Quadrature points `(ξ, w)` of a rule on the reference cell of `kind`.
    fn quadrature(kind: CellKind, rule: Rule) -> &'static [([f64; D], f64)];

    /// Reference coordinates of the nodes of `kind`.
    fn node_xi(kind: CellKind) -> &'static [[f64; D]];

    /// Shape functions `n[a]` and reference derivatives `dn[a][c] = ∂N_a/∂ξ_c` at `xi`.
    fn shape(kind: CellKind, xi: [f64; D], n: &mut [f64], dn: &mut [[f64; D]]);

    /// `(det J, J⁻¹)` of a Jacobian `J_rc = ∂x_r/∂ξ_c`.
    fn invert(j: &[[f64; D]; D]) -> (f64, [[f64; D]; D]);

    /// Physical derivatives `g[a][k] = ∂N_a/∂x_k` and shape functions `n` at `xi`; returns
    /// det J (physical measure per reference measure).
    fn gradients(
        kind: CellKind,
        x: &[[f64; D]],
        xi: [f64; D],
        n: &mut [f64],
        g: &mut [[f64; D]],
    ) -> f64 {
        let nn = kind.nodes();
        let mut dn = [[0.0; D]; MAX_NODES];
        Self::shape(kind, xi, n, &mut dn);
        let mut j = [[0.0; D]; D];
        for a in 0..nn {
            for r in 0..D {
                for c in 0..D {
                    j[r][c] += x[a][r] * dn[a][c];
                }
            }
        }
        let (det, inv) = Self::invert(&j);
        // ∂N/∂x_k = Σ_c ∂N/∂ξ_c ∂ξ_c/∂x_k, with ∂ξ/∂x = J⁻¹.
        for a in 0..nn {
            for k in 0..D {
                let mut s = -0.0;
                for c in 0..D {
                    s += dn[a][c] * inv[c][k];
                }
                g[a][k] = s;
            }
        }
        det
    }

    /// Smallest and largest det J over the stiffness quadrature points and the corners.
    fn det_j_range(kind: CellKind, x: &[[f64; D]]) -> (f64, f64) {
        let mut n = [0.0; MAX_NODES];
        let mut g = [[0.0; D]; MAX_NODES];
        let pts = Self::quadrature(kind, Rule::Stiffness)
            .iter()
            .map(|p| p.0)
            .chain(Self::node_xi(kind)[..kind.corners()].iter().copied());
        let mut lo = f64::INFINITY;
        let mut hi = f64::NEG_INFINITY;
        for xi in pts {
            let d = Self::gradients(kind, x, xi, &mut n, &mut g);
            lo = lo.min(d);
            hi = hi.max(d);
        }
        (lo, hi)
    }

    /// Stiffness `K = ∫ Bᵀ D B t dV` into `ke` (row-major `Dn × Dn`, N/m), `d` the S × S
    /// constitutive matrix (Pa), `t` the thickness of a 2-D section (m; 1 in 3-D).
    ///
    /// # Panics
    /// If `ke.len() != (Dn)²`.
    fn stiffness(kind: CellKind, x: &[[f64; D]], d: &[[f64; S]; S], t: f64, ke: &mut [f64]) {
        let nn = kind.nodes();
        let nd = D * nn;
        assert_eq!(ke.len(), nd * nd, "stiffness buffer size");
        ke.fill(0.0);
        let mut n = [0.0; MAX_NODES];
        let mut g = [[0.0; D]; MAX_NODES];
        for &(xi, w) in Self::quadrature(kind, Rule::Stiffness) {
            let f = w * Self::gradients(kind, x, xi, &mut n, &mut g) * t;
            for a in 0..nn {
                let db = d_times_b(&Self::B, d, &g[a]);
                for b in 0..nn {
                    for r in 0..D {
                        for c in 0..D {
                            ke[(D * b + r) * nd + D * a + c] +=
                                f * bt_times(&Self::B, &g[b], &db, r, c);
                        }
                    }
                }
            }
        }
    }

    /// Scalar mass `s[a n + b] = ∫ ρ N_a N_b dV` (n × n, kg), `rho` the density (kg/m³; ρ t in
    /// kg/m² for a 2-D section).
    fn scalar_mass(kind: CellKind, x: &[[f64; D]], rho: f64, s: &mut [f64]) {
        let nn = kind.nodes();
        let mut n = [0.0; MAX_NODES];
        let mut g = [[0.0; D]; MAX_NODES];
        s[..nn * nn].fill(0.0);
        for &(xi, w) in Self::quadrature(kind, Rule::Mass) {
            let f = w * Self::gradients(kind, x, xi, &mut n, &mut g) * rho;
            for a in 0..nn {
                for b in 0..nn {
                    s[a * nn + b] += f * n[a] * n[b];
                }
            }
        }
    }

    /// Consistent mass `M = ∫ ρ NᵀN dV` into `me` (row-major `Dn × Dn`, kg): the scalar mass
    /// on each displacement component.
    ///
    /// # Panics
    /// If `me.len() != (Dn)²`.
    fn mass_consistent(kind: CellKind, x: &[[f64; D]], rho: f64, me: &mut [f64]) {
        let nn = kind.nodes();
        let nd = D * nn;
        assert_eq!(me.len(), nd * nd, "mass buffer size");
        me.fill(0.0);
        let mut s = [0.0; MAX_NODES * MAX_NODES];
        Self::scalar_mass(kind, x, rho, &mut s);
        for a in 0..nn {
            for b in 0..nn {
                for c in 0..D {
                    me[(D * a + c) * nd + D * b + c] = s[a * nn + b];
                }
            }
        }
    }

    /// HRZ lumped mass per node (kg) into `m[..n]`: the diagonal of the scalar mass scaled so
    /// the node masses sum to the element mass `∫ ρ dV`. Positive for every cell type (row
    /// sums are not, for quadratic cells).
    fn mass_lumped(kind: CellKind, x: &[[f64; D]], rho: f64, m: &mut [f64]) {
        let nn = kind.nodes();
        let mut s = [0.0; MAX_NODES * MAX_NODES];
        Self::scalar_mass(kind, x, rho, &mut s);
        let total: f64 = s[..nn * nn].iter().sum();
        let diag: f64 = (0..nn).map(|a| s[a * nn + a]).sum();
        for a in 0..nn {
            m[a] = if diag > 0.0 {
                s[a * nn + a] * total / diag
            } else {
                0.0
            };
        }
    }

    /// Measure of the cell `∫ dV` (m² in 2-D, m³ in 3-D), by the mass rule.
    fn measure(kind: CellKind, x: &[[f64; D]]) -> f64 {
        let mut n = [0.0; MAX_NODES];
        let mut g = [[0.0; D]; MAX_NODES];
        Self::quadrature(kind, Rule::Mass)
            .iter()
            .map(|&(xi, w)| w * Self::gradients(kind, x, xi, &mut n, &mut g))
            .sum()
    }

    /// Voigt strain `ε = Σ_a B_a u_a` at reference point `xi` for element displacements `u`
    /// (m; engineering shear).
    fn strain(kind: CellKind, x: &[[f64; D]], u: &[f64], xi: [f64; D]) -> [f64; S] {
        let mut n = [0.0; MAX_NODES];
        let mut g = [[0.0; D]; MAX_NODES];
        Self::gradients(kind, x, xi, &mut n, &mut g);
        let mut e = [0.0; S];
        for a in 0..kind.nodes() {
            for (k, ek) in e.iter_mut().enumerate() {
                let mut s = -0.0;
                for c in 0..D {
                    if let Some(i) = Self::B[k][c] {
                        s += g[a][i] * u[D * a + c];
                    }
                }
                *ek += s;
            }
        }
        e
    }

    /// Position, interpolated displacement and det J at reference point `xi`:
    /// `(Σ N_a x_a, Σ N_a u_a, det J)`.
    fn interpolate(
        kind: CellKind,
        x: &[[f64; D]],
        u: &[f64],
        xi: [f64; D],
    ) -> ([f64; D], [f64; D], f64) {
        let mut n = [0.0; MAX_NODES];
        let mut g = [[0.0; D]; MAX_NODES];
        let det = Self::gradients(kind, x, xi, &mut n, &mut g);
        let mut p = [0.0; D];
        let mut v = [0.0; D];
        for a in 0..kind.nodes() {
            for k in 0..D {
                p[k] += n[a] * x[a][k];
                v[k] += n[a] * u[D * a + k];
            }
        }
        (p, v, det)
    }
}

/// `D B_a` (S × D) for the B pattern `pattern` and the gradient `ga` of node a:
/// `(D B_a)[r][c] = Σ_k D[r][k] B_a[k][c]` over the non-zero `B_a[k][c]`, k ascending.
fn d_times_b<const D: usize, const S: usize>(
    pattern: &[[Option<usize>; D]; S],
    d: &[[f64; S]; S],
    ga: &[f64; D],
) -> [[f64; D]; S] {
    let mut db = [[0.0; D]; S];
    for (dr, dbr) in d.iter().zip(db.iter_mut()) {
        for (c, v) in dbr.iter_mut().enumerate() {
            let mut s = -0.0;
            for (drk, bk) in dr.iter().zip(pattern) {
                if let Some(i) = bk[c] {
                    s += drk * ga[i];
                }
            }
            *v = s;
        }
    }
    db
}

/// Entry `(r, c)` of `B_bᵀ (D B_a)` for the gradient `gb` of node b: `Σ_k B_b[k][r] (D B_a)[k][c]`
/// over the non-zero `B_b[k][r]`, k ascending.
fn bt_times<const D: usize, const S: usize>(
    pattern: &[[Option<usize>; D]; S],
    gb: &[f64; D],
    db: &[[f64; D]; S],
    r: usize,
    c: usize,
) -> f64 {
    let mut v = -0.0;
    for (bk, dbk) in pattern.iter().zip(db) {
        if let Some(i) = bk[r] {
            v += gb[i] * dbk[c];
        }
    }
    v
}
