//! Sparse storage and the factorisations the models need, as a thin layer over `faer`.
//!
//! * [`Csc`] ([`csc`]): compressed-sparse-column matrix owned by rubsim (pattern built once
//!   from triplets, duplicates summed) with an allocation-free `y += α A x` for the time loop;
//!   [`PairCsr`] ([`pair`]): two matrices on one row pattern for the explicit step's
//!   `y += A x + B z`; [`PatternAssembly`] ([`pattern`]): a finite-element matrix summed in
//!   place on its pattern from the elements' DOF lists (large meshes, no triplet list).
//! * [`Cholesky`] ([`cholesky`]): sparse `A = L Lᵀ` of a symmetric positive definite stiffness
//!   (massless-stator condensation), with caller-owned solve scratch ([`CholeskyScratch`]) for
//!   solves inside the time loop.
//! * [`Lu`], [`StepLu`] ([`lu`]): sparse LU with pivoting of a general matrix (the unsymmetric
//!   M̃ of rotors with gyroscopics); `StepLu` solves without allocating.
//! * [`BlockTridiag`] ([`block`]): block Thomas LU of a shaft chain in 4 × 4 node blocks;
//!   [`BlockTri`] ([`blockmul`]): `y += A x` of such a matrix by fixed-size block products
//!   (a gyroscopic rotor's per-step correction).
//! * [`LowRank`], [`WoodburyLu`] ([`lowrank`]): a dense symmetric term of low rank (modal
//!   damping) and the Sherman–Morrison–Woodbury solve of sparse + low rank.
//!
//! The factorisations convert to `faer` views without copying the pattern. Every failure is a
//! [`LinalgError`] naming the matrix size and where the factorisation stopped.

pub mod block;
pub mod blockmul;
pub mod cholesky;
pub mod csc;
pub mod lowrank;
pub mod lu;
pub mod pair;
pub mod paths;
pub mod pattern;

pub use crate::error::LinalgError;
pub use block::{BlockParts, BlockTridiag, NODE_BLOCK};
pub use blockmul::BlockTri;
pub use cholesky::{Cholesky, CholeskyScratch};
pub use csc::Csc;
pub use lowrank::{LowRank, WoodburyLu};
pub use lu::{Lu, StepLu};
pub use pair::PairCsr;
pub use paths::{PathCost, PathStore, PATH_BATCH};
pub use pattern::PatternAssembly;

use faer::MatMut;

/// Calls `f` on `b` viewed as a column-major `n × k` block, `k = b.len() / n` (nothing for
/// `n = 0`).
///
/// # Panics
/// If `b.len()` is not a multiple of `n`.
fn solve_block(n: usize, b: &mut [f64], f: impl FnOnce(MatMut<'_, f64>)) {
    if n == 0 {
        return;
    }
    assert_eq!(b.len() % n, 0, "right-hand side is not a multiple of n");
    let k = b.len() / n;
    let m = MatMut::from_column_major_slice_mut(b, n, k);
    f(m);
}

/// The fault of a faer routine that says nothing about the matrix values.
fn exhausted(e: faer::sparse::FaerError) -> crate::error::Exhausted {
    match e {
        faer::sparse::FaerError::IndexOverflow => crate::error::Exhausted::IndexOverflow,
        // `OutOfMemory`, and whatever a later faer adds (the enum is non-exhaustive).
        _ => crate::error::Exhausted::OutOfMemory,
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The 1-D Laplacian `tridiag(−1, 2, −1)` of size n (symmetric positive definite).
    pub(crate) fn lap(n: usize) -> Csc {
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 2.0));
            if i + 1 < n {
                t.push((i, i + 1, -1.0));
                t.push((i + 1, i, -1.0));
            }
        }
        Csc::from_triplets(n, n, &t)
    }

    #[test]
    fn cholesky_and_lu_solve_laplacian() {
        let n = 6;
        let a = lap(n);
        let x: Vec<f64> = (0..n).map(|i| i as f64 + 1.0).collect();
        let mut b = vec![0.0; n];
        a.mul_add(1.0, &x, &mut b);
        let mut b1 = b.clone();
        Cholesky::new(&a).unwrap().solve_in_place(&mut b1);
        let mut b2 = b.clone();
        Lu::new(&a).unwrap().solve_in_place(&mut b2);
        for i in 0..n {
            assert!((b1[i] - x[i]).abs() < 1e-12);
            assert!((b2[i] - x[i]).abs() < 1e-12);
        }
    }
}
