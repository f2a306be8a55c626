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
    },
}

impl Target {
    /// The target's free DOFs.
    pub fn dofs(&self) -> [Option<usize>; 2] {
        match self {
            Target::Node { dofs, .. } | Target::Ring { dofs, .. } => *dofs,
        }
    }
}
