//! Node-to-nodes contact between radially rigid rotor sections and stator nodes (paper
//! Method III, Sec. 2.4).
//!
//! # Conventions
//!
//! * A pair `(C, A)`: `C` the centre of a rotor section of radius `r`, `A` a stator node.
//! * Normal `n = (x_A − x_C)/|x_A − x_C|`, pointing from `C` to `A`.
//! * Gap `g_N = n·(x_A − x_C) − r` (Eq. 4): `g_N ≥ 0` open, `g_N < 0` penetrating.
//! * Tangent `a = Ω × n` (Eq. 10): the direction the rotor surface moves at the contact.
//! * Normal force `p ≥ 0` in **compression** (the paper's λ_N = −p ≤ 0). Permanent slip
//!   (Eq. 19): tangential force `μ p`. The force on the rotor section is `−(n + μ a) p`, the force
//!   on the stator node `+(n + μ a) p`, i.e. the columns of `G_NTᵀ = (G_N + μ G_T)ᵀ` (Eq. 33)
//!   with the paper's sign flipped.
//! * Ring targets (circle-in-circle): the ring's contact point is `x_S + (r+δ) n` with
//!   `n = (x_C − x_S)/|x_C − x_S|`, so `g_N = δ − |x_C − x_S|` has the same linearisation.
//!
//! Within a time step `n` and `a` are frozen at the predicted configuration (paper, after
//! Eq. 47), so the gap is linear in the corrections and the multipliers solve a linear
//! complementarity problem ([`lcp`]). A ring target's normal is then re-aligned with the
//! solved configuration and the problem solved again until they agree ([`ring`]): circle in
//! circle, the normal turns by the ring's own tangential displacement over the clearance, not
//! over the section radius as for a node.

pub mod coulomb;
pub mod lcp;
pub mod ring;
pub mod search;
pub mod target;

use crate::math::{dot, norm, spin_tangent, V2};
pub use target::Target;

/// A dashpot at the contact of one stator (massless stators): while a pair carries force, a
/// dashpot of coefficient `c` (N·s/m) between the rotor section and ground, in parallel with
/// the contact, damps the normal velocity of the rotor section relative to the stator's
/// undeformed surface — the rate of the stator's deflection at the contact point, ḋ — and, with
/// `full`, the section's tangential velocity too (ROSS's rub model damps the whole velocity).
/// The force on the rotor section is `−n c ḋ − a c (a·v_C)` (the second term with `full` only);
/// `c ḋ` may pull while the section withdraws, as in a penalty law `k d + c ḋ`.
/// Time discretisation: `time::solve` and docs/IMPLICIT.md §6.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Dashpot {
    /// Coefficient c (N·s/m); 0: none.
    pub c: f64,
    /// Also damp the tangential velocity.
    pub full: bool,
}

impl Dashpot {
    /// True when there is a dashpot.
    #[inline]
    pub fn active(&self) -> bool {
        self.c > 0.0
    }
}

/// A pair that may come into contact: station `station` against target `target` of stator
/// `stator`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    /// Station index.
    pub station: usize,
    /// Stator index.
    pub stator: usize,
    /// Target index within the stator.
    pub target: usize,
    /// Friction coefficient μ of the station.
    pub mu: f64,
    /// Section radius r (m).
    pub radius: f64,
    /// Coulomb friction with stick: the pair's tangential force is an unknown inside the cone
    /// `|t| ≤ μ p` (`time::stick`); false: permanent slip `t = μ p`.
    pub stick: bool,
}

/// Frozen geometry of a pair in one step.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairState {
    /// Unit normal from the section centre toward the stator.
    pub n: V2,
    /// Unit tangent `Ω × n`.
    pub a: V2,
    /// Gap g_N (m), negative when penetrating.
    pub g: f64,
}

impl PairState {
    /// Direction of the force on the stator per unit normal force: `n + μ a`.
    #[inline]
    pub fn b(&self, mu: f64) -> V2 {
        [self.n[0] + mu * self.a[0], self.n[1] + mu * self.a[1]]
    }
}

/// Displacement of a target's DOFs from a stator displacement vector (`None` → 0).
#[inline]
pub fn target_disp(dofs: [Option<usize>; 2], u: &[f64]) -> V2 {
    [dofs[0].map_or(0.0, |i| u[i]), dofs[1].map_or(0.0, |i| u[i])]
}

/// Gap, normal and tangent of a pair with section centre displaced by `uc` and the target's
/// DOFs displaced by `us` (m), at spin `omega` (rad/s).
#[inline]
pub fn pair_state(target: &Target, radius: f64, uc: V2, us: V2, omega: f64) -> PairState {
    match target {
        Target::Node { x0, .. } => {
            let d = [x0[0] + us[0] - uc[0], x0[1] + us[1] - uc[1]];
            let l = norm(d);
            if l == 0.0 {
                // Degenerate: centre on the node; push outward along the undeformed position.
                let l0 = norm(*x0).max(f64::MIN_POSITIVE);
                let n = [x0[0] / l0, x0[1] / l0];
                return PairState {
                    n,
                    a: spin_tangent(omega, n),
                    g: -radius,
                };
            }
            let n = [d[0] / l, d[1] / l];
            PairState {
                n,
                a: spin_tangent(omega, n),
                g: l - radius,
            }
        }
        Target::Ring {
            center0,
            inner_radius,
            ..
        } => {
            let d = [uc[0] - center0[0] - us[0], uc[1] - center0[1] - us[1]];
            let l = norm(d);
            let n = if l > 0.0 {
                [d[0] / l, d[1] / l]
            } else {
                [1.0, 0.0]
            };
            PairState {
                n,
                a: spin_tangent(omega, n),
                g: inner_radius - radius - l,
            }
        }
    }
}

/// The exact gap (no frozen normal) — used to measure penetration after a step.
#[inline]
pub fn exact_gap(target: &Target, radius: f64, uc: V2, us: V2) -> f64 {
    pair_state(target, radius, uc, us, 0.0).g
}

/// Linearised gap change for a rotor-centre increment `duc` and target increment `dus`:
/// `Δg = n·(du_A − du_C)`.
#[inline]
pub fn gap_increment(ps: &PairState, duc: V2, dus: V2) -> f64 {
    dot(ps.n, [dus[0] - duc[0], dus[1] - duc[1]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_above_rotor_gap_and_directions() {
        let t = Target::Node {
            node: 0,
            x0: [0.0, 0.06 + 1e-4],
            dofs: [None, Some(0)],
        };
        let ps = pair_state(&t, 0.06, [0.0, 2e-4], [0.0, 0.0], 100.0);
        assert!((ps.g + 1e-4).abs() < 1e-15);
        assert_eq!(ps.n, [0.0, 1.0]);
        // CCW spin: surface at the top moves toward −x; the stator is dragged that way.
        assert_eq!(ps.a, [-1.0, 0.0]);
        let b = ps.b(0.1);
        assert_eq!(b, [-0.1, 1.0]);
    }

    #[test]
    fn ring_gap_is_clearance_minus_radius_of_whirl() {
        let t = Target::Ring {
            center0: [0.0, 0.0],
            inner_radius: 0.05 + 1e-3,
            dofs: [Some(0), Some(1)],
            radial: false,
        };
        let ps = pair_state(&t, 0.05, [0.0, -2e-3], [0.0, 0.0], 1.0);
        assert!((ps.g + 1e-3).abs() < 1e-15);
        assert_eq!(ps.n, [0.0, -1.0]);
        // Linearisation: moving the rotor further out by 1e-6 closes the gap by 1e-6.
        let dg = gap_increment(&ps, [0.0, -1e-6], [0.0, 0.0]);
        assert!((dg + 1e-6).abs() < 1e-18);
    }
}
