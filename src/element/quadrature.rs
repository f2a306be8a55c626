//! Quadrature rules on the reference cells of the solid elements.
//!
//! A rule is a list of points `(ξ, w)` with `∫_ref f dξ ≈ Σ w f(ξ)`; the weights sum to the
//! measure of the reference cell:
//!
//! * Triangle `(0,0), (1,0), (0,1)` (area 1/2): 1 point (degree 1), 3 points (degree 2),
//!   Dunavant's 6 points (degree 4) and 7 points (degree 5).
//! * Quadrilateral `[−1, 1]²` (area 4): Gauss–Legendre 2×2, 3×3, 4×4 (degree 3, 5, 7 in each
//!   coordinate).
//! * Tetrahedron `(0,0,0), (1,0,0), (0,1,0), (0,0,1)` (volume 1/6): 1 point (degree 1),
//!   4 points (degree 2), Walkington's 14 points (degree 5).
//!
//! Which rule a cell gets is chosen by what it must integrate ([`Rule`]): its stiffness or its
//! consistent mass exactly on an undistorted cell, or a higher degree for error norms.

use crate::mesh::CellKind;

/// Which integrand a rule must integrate exactly.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// The stiffness `∫ Bᵀ D B` of an undistorted cell.
    Stiffness,
    /// The consistent mass `∫ ρ NᵀN` of an undistorted cell.
    Mass,
    /// Higher order (degree 5 on simplices, 4×4 Gauss on quadrilaterals), for error norms.
    Accurate,
}

const G2: f64 = 0.577_350_269_189_625_8;
const G3: f64 = 0.774_596_669_241_483_4;
const W3A: f64 = 0.555_555_555_555_555_6;
const W3B: f64 = 0.888_888_888_888_888_8;
const G4A: f64 = 0.339_981_043_584_856_3;
const G4B: f64 = 0.861_136_311_594_052_6;
const W4A: f64 = 0.652_145_154_862_546_2;
const W4B: f64 = 0.347_854_845_137_453_85;

const GAUSS1: [(f64, f64); 1] = [(0.0, 2.0)];
const GAUSS2: [(f64, f64); 2] = [(-G2, 1.0), (G2, 1.0)];
const GAUSS3: [(f64, f64); 3] = [(-G3, W3A), (0.0, W3B), (G3, W3A)];
const GAUSS4: [(f64, f64); 4] = [(-G4B, W4B), (-G4A, W4A), (G4A, W4A), (G4B, W4B)];

/// 1-D Gauss–Legendre points and weights on [−1, 1] with 1 to 4 points (4 for any `n > 4`);
/// `n` points integrate polynomials of degree `2n − 1` exactly.
pub fn gauss_1d(n: usize) -> &'static [(f64, f64)] {
    match n {
        1 => &GAUSS1,
        2 => &GAUSS2,
        3 => &GAUSS3,
        _ => &GAUSS4,
    }
}

/// Tensor-product rule on `[−1, 1]²` from a 1-D rule with `N` points (`M = N²`): points
/// `(ξ_a, η_b)` with weights `w_a w_b`, `a` outer and `b` inner.
const fn tensor<const N: usize, const M: usize>(g: [(f64, f64); N]) -> [([f64; 2], f64); M] {
    let mut out = [([0.0; 2], 0.0); M];
    let mut a = 0;
    while a < N {
        let mut b = 0;
        while b < N {
            out[a * N + b] = ([g[a].0, g[b].0], g[a].1 * g[b].1);
            b += 1;
        }
        a += 1;
    }
    out
}

const QUAD2: [([f64; 2], f64); 4] = tensor(GAUSS2);
const QUAD3: [([f64; 2], f64); 9] = tensor(GAUSS3);
const QUAD4: [([f64; 2], f64); 16] = tensor(GAUSS4);

const TRI1: [([f64; 2], f64); 1] = [([1.0 / 3.0, 1.0 / 3.0], 0.5)];
const TRI3: [([f64; 2], f64); 3] = [
    ([1.0 / 6.0, 1.0 / 6.0], 1.0 / 6.0),
    ([2.0 / 3.0, 1.0 / 6.0], 1.0 / 6.0),
    ([1.0 / 6.0, 2.0 / 3.0], 1.0 / 6.0),
];
// Dunavant degree 4 (6 points) and degree 5 (7 points); weights for the area 1/2.
const DA: f64 = 0.445_948_490_915_965;
const DB: f64 = 0.091_576_213_509_771;
const DWA: f64 = 0.223_381_589_678_011 / 2.0;
const DWB: f64 = 0.109_951_743_655_322 / 2.0;
const TRI6: [([f64; 2], f64); 6] = [
    ([DA, DA], DWA),
    ([1.0 - 2.0 * DA, DA], DWA),
    ([DA, 1.0 - 2.0 * DA], DWA),
    ([DB, DB], DWB),
    ([1.0 - 2.0 * DB, DB], DWB),
    ([DB, 1.0 - 2.0 * DB], DWB),
];
const E1A: f64 = 0.470_142_064_105_115;
const E1B: f64 = 0.059_715_871_789_770;
const E2A: f64 = 0.101_286_507_323_456;
const E2B: f64 = 0.797_426_985_353_087;
const EW1: f64 = 0.132_394_152_788_506 / 2.0;
const EW2: f64 = 0.125_939_180_544_827 / 2.0;
const TRI7: [([f64; 2], f64); 7] = [
    ([1.0 / 3.0, 1.0 / 3.0], 0.225 / 2.0),
    ([E1A, E1A], EW1),
    ([E1B, E1A], EW1),
    ([E1A, E1B], EW1),
    ([E2A, E2A], EW2),
    ([E2B, E2A], EW2),
    ([E2A, E2B], EW2),
];

const A4: f64 = 0.138_196_601_125_010_5;
const B4: f64 = 0.585_410_196_624_968_5;
const TET1: [([f64; 3], f64); 1] = [([0.25, 0.25, 0.25], 1.0 / 6.0)];
const TET4: [([f64; 3], f64); 4] = [
    ([A4, A4, A4], 1.0 / 24.0),
    ([B4, A4, A4], 1.0 / 24.0),
    ([A4, B4, A4], 1.0 / 24.0),
    ([A4, A4, B4], 1.0 / 24.0),
];
const WA: f64 = 0.092_735_250_310_891_2;
const WWA: f64 = 0.012_248_840_519_393_66;
const WB: f64 = 0.310_885_919_263_300_6;
const WWB: f64 = 0.018_781_320_953_002_64;
const WC: f64 = 0.454_496_295_874_350_4;
const WD: f64 = 0.5 - WC;
const WWC: f64 = 0.007_091_003_462_846_911;
const TET14: [([f64; 3], f64); 14] = [
    ([WA, WA, WA], WWA),
    ([1.0 - 3.0 * WA, WA, WA], WWA),
    ([WA, 1.0 - 3.0 * WA, WA], WWA),
    ([WA, WA, 1.0 - 3.0 * WA], WWA),
    ([WB, WB, WB], WWB),
    ([1.0 - 3.0 * WB, WB, WB], WWB),
    ([WB, 1.0 - 3.0 * WB, WB], WWB),
    ([WB, WB, 1.0 - 3.0 * WB], WWB),
    // (ξ, η, ζ) of the six points with two barycentric coordinates WC and two WD.
    ([WC, WD, WD], WWC),
    ([WD, WC, WD], WWC),
    ([WD, WD, WC], WWC),
    ([WC, WC, WD], WWC),
    ([WC, WD, WC], WWC),
    ([WD, WC, WC], WWC),
];

/// Quadrature points `(ξ, w)` of a rule on a 2-D cell.
///
/// Triangles: 1 point (Tri3 stiffness), 3 points (degree 2: Tri3 mass, Tri6 stiffness),
/// 6 points (degree 4: Tri6 mass), 7 points (degree 5: `Accurate`). Quadrilaterals: Gauss
/// 2×2 (Quad4), 3×3 (Quad8/9), 4×4 (`Accurate`).
///
/// # Panics
/// If `kind` is not a 2-D cell.
pub fn points_2d(kind: CellKind, rule: Rule) -> &'static [([f64; 2], f64)] {
    match (kind, rule) {
        (CellKind::Tri3, Rule::Stiffness) => &TRI1,
        (CellKind::Tri3, Rule::Mass) | (CellKind::Tri6, Rule::Stiffness) => &TRI3,
        (CellKind::Tri6, Rule::Mass) => &TRI6,
        (CellKind::Tri3 | CellKind::Tri6, Rule::Accurate) => &TRI7,
        (CellKind::Quad4, Rule::Stiffness | Rule::Mass) => &QUAD2,
        (CellKind::Quad8 | CellKind::Quad9, Rule::Stiffness | Rule::Mass) => &QUAD3,
        (CellKind::Quad4 | CellKind::Quad8 | CellKind::Quad9, Rule::Accurate) => &QUAD4,
        _ => panic!("{} is not a 2-D cell", kind.name()),
    }
}

/// Quadrature points `(ξ, w)` of a rule on a tetrahedron: 1 point (Tet4 stiffness), 4 points
/// (degree 2: Tet4 mass, Tet10 stiffness), 14 points (degree 5: Tet10 mass, `Accurate`).
///
/// # Panics
/// If `kind` is not a tetrahedron.
pub fn points_3d(kind: CellKind, rule: Rule) -> &'static [([f64; 3], f64)] {
    match (kind, rule) {
        (CellKind::Tet4, Rule::Stiffness) => &TET1,
        (CellKind::Tet4, Rule::Mass) | (CellKind::Tet10, Rule::Stiffness) => &TET4,
        (CellKind::Tet10, Rule::Mass) | (CellKind::Tet4 | CellKind::Tet10, Rule::Accurate) => {
            &TET14
        }
        _ => panic!("{} is not a tetrahedron", kind.name()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tensor_rules_are_the_products_of_the_gauss_rules_bit_for_bit() {
        for (n, kind) in [
            (2, CellKind::Quad4),
            (3, CellKind::Quad8),
            (4, CellKind::Quad9),
        ] {
            let rule = if n == 4 { Rule::Accurate } else { Rule::Mass };
            let mut expected = Vec::new();
            for &(a, wa) in gauss_1d(n) {
                for &(b, wb) in gauss_1d(n) {
                    expected.push(([a, b], wa * wb));
                }
            }
            let bits = |q: &[([f64; 2], f64)]| -> Vec<[u64; 3]> {
                q.iter()
                    .map(|(p, w)| [p[0].to_bits(), p[1].to_bits(), w.to_bits()])
                    .collect()
            };
            assert_eq!(bits(points_2d(kind, rule)), bits(&expected), "{n}×{n}");
        }
    }

    #[test]
    fn weights_sum_to_the_reference_measure() {
        let kinds2 = [
            CellKind::Tri3,
            CellKind::Tri6,
            CellKind::Quad4,
            CellKind::Quad8,
            CellKind::Quad9,
        ];
        for rule in [Rule::Stiffness, Rule::Mass, Rule::Accurate] {
            for kind in kinds2 {
                let area = if kind.corners() == 3 { 0.5 } else { 4.0 };
                let s: f64 = points_2d(kind, rule).iter().map(|p| p.1).sum();
                assert!((s - area).abs() < 1e-14, "{kind:?} {rule:?}: {s}");
            }
            for kind in [CellKind::Tet4, CellKind::Tet10] {
                let s: f64 = points_3d(kind, rule).iter().map(|p| p.1).sum();
                assert!((s - 1.0 / 6.0).abs() < 1e-15, "{kind:?} {rule:?}: {s}");
            }
        }
    }
}
