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
        if self.friction_to_ground() {
            n
        } else {
            b
        }
    }

    /// Direction of the force on the stator per unit tangential force `t` along `a` (stick,
    /// `time::stick`): `a`, or nothing for a radially elastic ring.
    #[inline]
    pub fn tangential_direction(&self, a: V2) -> V2 {
        if self.friction_to_ground() {
            [0.0; 2]
        } else {
            a
        }
    }

    /// True for a radially elastic ring: its friction goes to ground, and its material point at
    /// the contact does not move along the tangent.
    #[inline]
    pub fn friction_to_ground(&self) -> bool {
        matches!(self, Target::Ring { radial: true, .. })
    }

    /// True for a ring whose normal follows the solved configuration (exact kinematics).
    #[inline]
    pub fn exact_ring(&self) -> bool {
        matches!(self, Target::Ring { radial: false, .. })
    }
}
