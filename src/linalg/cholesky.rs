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
    pub(super) n: usize,
    pub(super) symbolic: SymbolicCholesky<usize>,
    pub(super) values: Vec<f64>,
    /// The supernodal elimination tree for [`Cholesky::path_columns`], built on first use.
    pub(super) paths: std::sync::OnceLock<Option<super::paths::PathTree>>,
}

impl std::fmt::Debug for Cholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Cholesky(n = {})", self.n)
    }
}

/// Caller-owned workspace for [`Cholesky::solve_in_place_with`]: faer's solve scratch for up
/// to `k` right-hand sides of the factor that made it ([`Cholesky::solve_scratch`]). Allocated
/// once, it makes every later solve allocation free.
pub struct CholeskyScratch {
    n: usize,
    k: usize,
    mem: MemBuffer,
}

impl std::fmt::Debug for CholeskyScratch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "CholeskyScratch(n = {}, k = {})", self.n, self.k)
    }
}

impl CholeskyScratch {
    /// The largest number of right-hand sides one solve may have.
    pub fn columns(&self) -> usize {
        self.k
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
        Self::with_params(a, Default::default())
    }

    /// As [`Cholesky::new`], always supernodal (faer picks a simplicial factor for sparse
    /// enough matrices): small test matrices with an elimination tree of supernodes.
    #[cfg(test)]
    pub(crate) fn new_supernodal(a: &Csc) -> Result<Self, LinalgError> {
        Self::with_params(
            a,
            faer::sparse::linalg::cholesky::CholeskySymbolicParams {
                supernodal_flop_ratio_threshold:
                    faer::sparse::linalg::SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
    }

    fn with_params(
        a: &Csc,
        params: faer::sparse::linalg::cholesky::CholeskySymbolicParams<'_>,
    ) -> Result<Self, LinalgError> {
        use faer::linalg::cholesky::llt::factor::LltError;
        assert_eq!(a.nrows, a.ncols);
        let n = a.nrows;
        let r = a.faer_ref();
        let symbolic =
            factorize_symbolic_cholesky(r.symbolic(), Side::Lower, Default::default(), params)
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
            paths: Default::default(),
        })
    }

    /// Size n of the factored matrix.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Stored entries of the factor `L` (its values; 8 bytes each): a solve reads each twice.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// Workspace for solves of up to `k` right-hand sides with
    /// [`Cholesky::solve_in_place_with`] (one allocation; sequential solves).
    pub fn solve_scratch(&self, k: usize) -> CholeskyScratch {
        CholeskyScratch {
            n: self.n,
            k,
            mem: MemBuffer::new(
                self.symbolic
                    .solve_in_place_scratch::<f64>(k, faer::Par::Seq),
            ),
        }
    }

    /// Solves `A X = B` in place for a column-major `n × k` block `b` (`k = b.len()/n`),
    /// sequentially. Allocates its solve scratch on every call: for repeated solves use
    /// [`Cholesky::solve_in_place_with`].
    pub fn solve_in_place(&self, b: &mut [f64]) {
        let k = b.len().checked_div(self.n).unwrap_or(0);
        let mut scratch = self.solve_scratch(k);
        self.solve_in_place_with(b, &mut scratch);
    }

    /// Solves `A X = B` in place for a column-major `n × k` block `b` (`k = b.len()/n`),
    /// sequentially and without allocating, in `scratch` from this factor's
    /// [`Cholesky::solve_scratch`]. The same arithmetic as [`Cholesky::solve_in_place`], so
    /// the same result bit for bit.
    ///
    /// # Panics
    /// If `b.len()` is not a multiple of n, if `k` exceeds the scratch's
    /// [`CholeskyScratch::columns`], or if the scratch was made for a factor of another size.
    pub fn solve_in_place_with(&self, b: &mut [f64], scratch: &mut CholeskyScratch) {
        assert_eq!(scratch.n, self.n, "scratch of a factor of another size");
        solve_block(self.n, b, |m| {
            let k = m.ncols();
            assert!(
                k <= scratch.k,
                "{k} right-hand sides, scratch for {}",
                scratch.k
            );
            LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
                faer::Conj::No,
                m,
                faer::Par::Seq,
                MemStack::new(&mut scratch.mem),
            );
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::tests::lap;

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

    #[test]
    fn scratch_solves_equal_one_off_solves_bit_for_bit() {
        // A wider band than the Laplacian so the factor has fill-in (diagonally dominant, so
        // positive definite).
        let n = 40;
        let mut t: Vec<(usize, usize, f64)> = lap(n).triplets().collect();
        t.extend((0..n).map(|i| (i, i, 1.0)));
        for i in 0..n - 3 {
            t.push((i, i + 3, -0.2));
            t.push((i + 3, i, -0.2));
        }
        let a = Csc::from_triplets(n, n, &t);
        let ch = Cholesky::new(&a).unwrap();
        let rhs = |k: usize| -> Vec<f64> {
            (0..n * k)
                .map(|i| ((i * 37 % 11) as f64 - 5.0) * 0.3)
                .collect()
        };
        // The solve as it was before the scratch API: a fresh faer buffer sized for this call.
        let fresh = |b: &mut [f64]| {
            let k = b.len() / n;
            let mut mem =
                MemBuffer::new(ch.symbolic.solve_in_place_scratch::<f64>(k, faer::Par::Seq));
            LltRef::new(&ch.symbolic, &ch.values).solve_in_place_with_conj(
                faer::Conj::No,
                faer::MatMut::from_column_major_slice_mut(b, n, k),
                faer::Par::Seq,
                MemStack::new(&mut mem),
            );
        };
        let mut scratch = ch.solve_scratch(5);
        assert_eq!(scratch.columns(), 5);
        // Reused for blocks of 5, 1 and 3 columns, in that order and again.
        for k in [5, 1, 3, 5, 1] {
            let mut b0 = rhs(k);
            let mut b1 = b0.clone();
            let mut b2 = b0.clone();
            fresh(&mut b0);
            ch.solve_in_place(&mut b1);
            ch.solve_in_place_with(&mut b2, &mut scratch);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&b0), bits(&b1), "k = {k}");
            assert_eq!(bits(&b0), bits(&b2), "k = {k}");
        }
        // And the solution is right.
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.21).sin()).collect();
        let mut b = vec![0.0; n];
        a.mul_add(1.0, &x, &mut b);
        ch.solve_in_place_with(&mut b, &mut scratch);
        for i in 0..n {
            assert!((b[i] - x[i]).abs() < 1e-12, "{i}");
        }
    }

    #[test]
    fn scratch_can_move_to_a_worker_thread() {
        fn send_sync<T: Send + Sync>() {}
        send_sync::<CholeskyScratch>();
        send_sync::<Cholesky>();
    }

    #[test]
    #[should_panic(expected = "scratch for 1")]
    fn scratch_too_small_panics() {
        let ch = Cholesky::new(&lap(4)).unwrap();
        let mut s = ch.solve_scratch(1);
        ch.solve_in_place_with(&mut [1.0; 8], &mut s);
    }
}
