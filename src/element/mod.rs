//! Finite-element kernels: pure local functions of element data, filling caller-sized
//! matrices; no global indices, no `Result` (a shape mismatch is a bug and panics).

pub mod frame;
pub mod quadrature;
mod solid;
pub mod solid2d;
pub mod solid3d;
pub mod timoshenko;
