//! Exact kinematics of a ring target (circle in circle): the normal that the pair's own
//! displacement under its contact force agrees with.
//!
//! A ring pair's gap is `g = δ − |d|`, `d = x_C − x_S` the section centre relative to the ring
//! centre, `δ` the inner radius minus the section radius. The step freezes the normal `n` and
//! the force direction `b = n + μa` (`a = Ω × n`), so after the solve
//! `d = d̃ − p W b` with `d̃` the relative position with every other pair's force applied and
//! `W` (2×2, m/N) the pair's own relative flexibility: the rotor's at the station plus the
//! ring's at its centre (`Δx_C = −F_r b p`, `Δx_S = +F_s b p`). The linearised gap closes
//! `n·d = δ`, but `|d| = δ` only when `d ∥ n`. A massless ring starts each step undeformed, so
//! the normal frozen at the prediction, `d̃/|d̃|`, misses the ring's own friction-driven
//! displacement `(p/k_s) μa`, which is perpendicular to it: the exact gap is then
//! `δ − √(δ² + (μp/k_s)²) < 0`, a penetration of order `(μ p/k_s)²/(2δ)` — not small when the
//! ring deflects by a fraction of the clearance, as it does in full annular rub.
//!
//! [`align_normal`] finds the normal angle `θ` at which the solved `d(θ)` is parallel to
//! `n(θ)`: with `p(θ) = (n·d̃ − δ)/(n·W b)` (the single pair's closed gap) the residual
//! `ψ(θ) = atan2(t·d, n·d)`, `t = ẑ × n`, vanishes. It is solved by Newton's method (the
//! plain fixed point `n ← d/|d|` diverges once the whirl radius exceeds about twice the
//! clearance: its multiplier is `1 − |d̃|(cos θ + μ sin θ)/δ`).

use crate::math::{dot, V2};

/// The normal `n`, tangent `a` and force `p` of a ring pair whose solved relative position is
/// parallel to its normal; `None` when the pair would not carry force (`p ≤ 0`) or the
/// iteration fails (a degenerate `W`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aligned {
    /// Unit normal from the ring centre toward the section centre.
    pub n: V2,
    /// Normal force (N, compression positive).
    pub p: f64,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// Residual and force of the single pair at normal angle `theta`: the angle of the solved
/// relative position `d(θ)` from `n(θ)` (rad) and `p(θ)` (N).
#[inline]
fn residual(theta: f64, rel: V2, w: [[f64; 2]; 2], mu: f64, spin: f64, clear: f64) -> (f64, f64) {
    let n = [theta.cos(), theta.sin()];
    let t = [-n[1], n[0]];
    let b = [n[0] + mu * spin * t[0], n[1] + mu * spin * t[1]];
    let wb = [
        w[0][0] * b[0] + w[0][1] * b[1],
        w[1][0] * b[0] + w[1][1] * b[1],
    ];
    let den = dot(n, wb);
    let p = (dot(n, rel) - clear) / den;
    let d = [rel[0] - p * wb[0], rel[1] - p * wb[1]];
    (dot(t, d).atan2(dot(n, d)), p)
}

/// Newton's method on the normal angle of a ring pair (module docs): `rel` the relative
/// position `d̃` (m) with every other pair's force applied, `w` the pair's own relative
/// flexibility (m/N, row-major 2×2), `mu` the friction coefficient, `spin` the sign of Ω
/// (`a = spin·ẑ × n`), `clear` the gap's `δ` (m), `n0` the starting normal. Converged when the
/// angle residual is below `tol` (rad).
pub fn align_normal(
    rel: V2,
    w: [[f64; 2]; 2],
    mu: f64,
    spin: f64,
    clear: f64,
    n0: V2,
    tol: f64,
) -> Option<Aligned> {
    const MAX_ITER: usize = 30;
    const H: f64 = 1e-7;
    let mut theta = n0[1].atan2(n0[0]);
    for it in 0..MAX_ITER {
        let (f, p) = residual(theta, rel, w, mu, spin, clear);
        if !(f.is_finite() && p.is_finite()) {
            return None;
        }
        if f.abs() <= tol {
            return (p > 0.0).then_some(Aligned {
                n: [theta.cos(), theta.sin()],
                p,
                iterations: it,
            });
        }
        let (fh, _) = residual(theta + H, rel, w, mu, spin, clear);
        let slope = (fh - f) / H;
        if !(slope.is_finite() && slope.abs() > 0.0) {
            return None;
        }
        // A step of more than a radian is not a correction of a frozen normal.
        theta -= (f / slope).clamp(-1.0, 1.0);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A ring alone (the rotor held): `W = I/k_s`. The exact solution has
    /// `d̃ = (δ + (p/k_s)(1 + iμ)) n` in complex notation.
    #[test]
    fn held_rotor_against_massless_ring_is_exact() {
        let (ks, mu, delta) = (3.7e5, 0.1, 8.8e-5);
        let w = [[1.0 / ks, 0.0], [0.0, 1.0 / ks]];
        // Construct d̃ from a known solution: n at 30°, p = 60 N.
        let th: f64 = 30f64.to_radians();
        let (n, p) = ([th.cos(), th.sin()], 60.0);
        let t = [-n[1], n[0]];
        let rho = p / ks;
        let rel = [
            (delta + rho) * n[0] + mu * rho * t[0],
            (delta + rho) * n[1] + mu * rho * t[1],
        ];
        // Start from the frozen predictor normal d̃/|d̃| (what the linearised step uses).
        let l = rel[0].hypot(rel[1]);
        let al = align_normal(rel, w, mu, 1.0, delta, [rel[0] / l, rel[1] / l], 1e-14).unwrap();
        assert!((al.n[0] - n[0]).abs() < 1e-12 && (al.n[1] - n[1]).abs() < 1e-12);
        assert!((al.p / p - 1.0).abs() < 1e-10, "p = {}", al.p);
        assert!(al.iterations <= 6, "{} iterations", al.iterations);
        // The frozen normal alone leaves the ring's tangential deflection out: penetration
        // √(δ² + (μρ)²) − δ with ρ = n₀·d̃ − δ.
        let rho0 = l - delta;
        let pen0 = (delta * delta + (mu * rho0).powi(2)).sqrt() - delta;
        assert!(pen0 > 1e-3 * delta);
    }

    #[test]
    fn separating_pair_is_not_aligned() {
        let w = [[1e-6, 0.0], [0.0, 1e-6]];
        assert!(align_normal([1e-5, 0.0], w, 0.1, 1.0, 1e-4, [1.0, 0.0], 1e-12).is_none());
    }
}
