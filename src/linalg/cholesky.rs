//! Sparse Cholesky `A = L Lᵀ` (faer) of symmetric positive definite matrices, with
//! caller-owned solve scratch for repeated solves.

use super::{exhausted, solve_block, Csc, LinalgError};
use crate::error::Factorisation;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{factorize_symbolic_cholesky, LltRef, SymbolicCholesky};
use faer::Side;

/// Sparse Cholesky factor `A = L Lᵀ` of a symmetric positive definite matrix.
///
/// Factored with faer's global parallelism; solved sequentially: the solves run inside the
/// time loop (massless-stator compliance columns) and inside parallel sweeps, where threads
/// of a parallel triangular solve only wait for each other.
pub struct Cholesky {
    n: usize,
    symbolic: SymbolicCholesky<usize>,
    values: Vec<f64>,
}

impl std::fmt::Debug for Cholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Cholesky(n = {})", self.n)
    }
}

impl Cholesky {
    /// Factors `a` (both triangles stored; only the lower one is read).
    ///
    /// # Errors
    /// [`LinalgError::NotPositiveDefinite`] when a pivot is `≤ 0`; [`LinalgError::Symbolic`]
    /// when the symbolic analysis runs out of indices or memory.
    ///
    /// # Panics
    /// If `a` is not square.
    pub fn new(a: &Csc) -> Result<Self, LinalgError> {
        use faer::linalg::cholesky::llt::factor::LltError;
        assert_eq!(a.nrows, a.ncols);
        let n = a.nrows;
        let r = a.faer_ref();
        let symbolic = factorize_symbolic_cholesky(
            r.symbolic(),
            Side::Lower,
            Default::default(),
            Default::default(),
        )
        .map_err(|e| LinalgError::Symbolic {
            factorisation: Factorisation::Cholesky,
            n,
            nnz: a.nnz(),
            cause: exhausted(e),
        })?;
        let mut values = vec![0.0; symbolic.len_val()];
        let par = faer::get_global_parallelism();
        let mut mem =
            MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()));
        symbolic
            .factorize_numeric_llt(
                &mut values,
                r,
                Side::Lower,
                Default::default(),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| match e {
                LltError::NonPositivePivot { index } => {
                    LinalgError::NotPositiveDefinite { n, pivot: index }
                }
            })?;
        Ok(Self {
            n,
            symbolic,
            values,
        })
    }

    /// Size n of the factored matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Solves `A X = B` in place for a column-major `n × k` block `b` (`k = b.len()/n`),
    /// sequentially.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        solve_block(self.n, b, |m| {
            let k = m.ncols();
            let par = faer::Par::Seq;
            let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(k, par));
            LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
                faer::Conj::No,
                m,
                par,
                MemStack::new(&mut mem),
            );
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_rejects_indefinite() {
        let a = Csc::from_triplets(2, 2, &[(0, 0, 1.0), (1, 1, -1.0)]);
        assert!(Cholesky::new(&a).is_err());
    }

    #[test]
    fn indefinite_matrix_is_reported_with_its_size_and_pivot() {
        let a = Csc::from_triplets(2, 2, &[(0, 0, 1.0), (1, 1, -1.0)]);
        match Cholesky::new(&a).unwrap_err() {
            LinalgError::NotPositiveDefinite { n, pivot } => {
                assert_eq!(n, 2);
                assert!(pivot <= 2, "{pivot}");
            }
            e => panic!("{e:?}"),
        }
    }
}
