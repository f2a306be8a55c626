//! Sparse LU with partial pivoting (faer): [`Lu`] for one-off solves, [`StepLu`] for the time
//! loop (allocation-free single right-hand-side solves).

use super::{exhausted, solve_block, Csc, LinalgError};
use crate::error::Factorisation;
use faer::linalg::solvers::Solve;
use faer::MatMut;

/// Sparse LU factor with partial pivoting of a general square matrix.
pub struct Lu {
    n: usize,
    lu: faer::sparse::linalg::solvers::Lu<usize, f64>,
}

impl std::fmt::Debug for Lu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Lu(n = {})", self.n)
    }
}

impl Lu {
    /// Factors `a`.
    ///
    /// # Errors
    /// [`LinalgError::Singular`] when no pivot is found; [`LinalgError::Resources`] when faer runs
    /// out of indices or memory.
    ///
    /// # Panics
    /// If `a` is not square.
    pub fn new(a: &Csc) -> Result<Self, LinalgError> {
        assert_eq!(a.nrows, a.ncols);
        let lu = a.faer_ref().sp_lu().map_err(|e| lu_error(a.nrows, e))?;
        Ok(Self { n: a.nrows, lu })
    }

    /// Solves `A X = B` in place for a column-major `n × k` block `b` (`k = b.len()/n`).
    pub fn solve_in_place(&self, b: &mut [f64]) {
        solve_block(self.n, b, |m| self.lu.solve_in_place(m));
    }
}

/// Sparse LU for the time loop: factored once, solves one right-hand side at a time without
/// allocating (the solve scratch is allocated with the factor).
pub struct StepLu {
    n: usize,
    symbolic: faer::sparse::linalg::lu::SymbolicLu<usize>,
    numeric: faer::sparse::linalg::lu::NumericLu<usize, f64>,
    scratch: faer::dyn_stack::MemBuffer,
}

impl std::fmt::Debug for StepLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "StepLu(n = {})", self.n)
    }
}

impl StepLu {
    /// Symbolic and numeric factorisation of `a` (sequential).
    ///
    /// # Errors
    /// [`LinalgError::Symbolic`] when the symbolic analysis cannot run, [`LinalgError::Singular`]
    /// when no pivot is found, [`LinalgError::Resources`] when faer runs out of memory.
    ///
    /// # Panics
    /// If `a` is not square.
    pub fn new(a: &Csc) -> Result<Self, LinalgError> {
        use faer::dyn_stack::{MemBuffer, MemStack};
        use faer::sparse::linalg::lu::{factorize_symbolic_lu, NumericLu};
        assert_eq!(a.nrows, a.ncols);
        let r = a.faer_ref();
        let n = a.nrows;
        let symbolic = factorize_symbolic_lu(r.symbolic(), Default::default()).map_err(|e| {
            LinalgError::Symbolic {
                factorisation: Factorisation::Lu,
                n,
                nnz: a.nnz(),
                cause: exhausted(e),
            }
        })?;
        let mut numeric = NumericLu::new();
        let par = faer::Par::Seq;
        let mut mem =
            MemBuffer::new(symbolic.factorize_numeric_lu_scratch::<f64>(par, Default::default()));
        symbolic
            .factorize_numeric_lu(
                &mut numeric,
                r,
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| lu_error(n, e))?;
        let scratch = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, par));
        Ok(Self {
            n,
            symbolic,
            numeric,
            scratch,
        })
    }

    /// Solves `A x = b` in place for one vector, allocation free.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        use faer::dyn_stack::MemStack;
        use faer::sparse::linalg::lu::LuRef;
        assert_eq!(b.len(), self.n);
        // SAFETY: `numeric` was produced by `symbolic.factorize_numeric_lu` in `new`.
        let lu = unsafe { LuRef::new_unchecked(&self.symbolic, &self.numeric) };
        let rhs = MatMut::from_column_major_slice_mut(b, self.n, 1);
        lu.solve_in_place_with_conj(
            faer::Conj::No,
            rhs,
            faer::Par::Seq,
            MemStack::new(&mut self.scratch),
        );
    }
}

/// The [`LinalgError`] of faer's numeric LU failure on an `n × n` matrix.
fn lu_error(n: usize, e: faer::sparse::linalg::LuError) -> LinalgError {
    match e {
        faer::sparse::linalg::LuError::SymbolicSingular { index } => {
            LinalgError::Singular { n, step: index }
        }
        faer::sparse::linalg::LuError::Generic(e) => LinalgError::Resources {
            factorisation: Factorisation::Lu,
            n,
            cause: exhausted(e),
        },
    }
}
