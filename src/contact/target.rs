//! What a rotor section can touch: the contact target of a stator, in the station plane.
//!
//! Coordinates are relative to the undeformed centre of the station the stator faces (m); the
//! DOFs are the stator's free DOFs (`None` = fixed). The gap and normal of a target are
//! [`super::pair_state`].

use crate::math::V2;

/// What the rotor section can touch.
#[derive(Debug, Clone, PartialEq)]
pub enum Target {
    /// A stator node at undeformed position `x0` (node-to-nodes, paper Method III).
    Node {
        /// Node index in the stator mesh.
        node: usize,
        /// Undeformed position (m).
        x0: V2,
        /// Free DOFs `[x, y]` (None = fixed).
        dofs: [Option<usize>; 2],
    },
    /// The inner circle of a rigid ring centred at `center0 + u` (circle-in-circle contact).
    Ring {
        /// Undeformed centre (m).
        center0: V2,
        /// Inner radius r + δ (m).
        inner_radius: f64,
        /// Free DOFs of the ring centre `[x, y]`.
        dofs: [Option<usize>; 2],
        /// Radially elastic stator (Black's law): the ring's centre takes only the normal
        /// part `n p` of the contact force, the friction `μ a p` goes to ground. False: the
        /// ring takes the whole force `(n + μa) p` (a rigid ring on isotropic springs).
        radial: bool,
    },
}

impl Target {
    /// The target's free DOFs.
    pub fn dofs(&self) -> [Option<usize>; 2] {
        match self {
            Target::Node { dofs, .. } | Target::Ring { dofs, .. } => *dofs,
        }
    }

    /// Direction of the force on the stator per unit normal force: `n + μa` (`b`), or `n`
    /// for a radially elastic ring, whose friction goes to ground.
    #[inline]
    pub fn stator_direction(&self, n: V2, b: V2) -> V2 {
        match self {
            Target::Ring { radial: true, .. } => n,
            _ => b,
        }
    }

    /// True for a ring whose normal follows the solved configuration (exact kinematics).
    #[inline]
    pub fn exact_ring(&self) -> bool {
        matches!(self, Target::Ring { radial: false, .. })
    }
}
