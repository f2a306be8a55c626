//! [`Csc`]: compressed sparse column storage with the pattern operations the models need
//! (triplet assembly, slots for refilling a fixed pattern, `α A + β B`, `y += α A x`).

use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

/// Square or rectangular sparse matrix in compressed sparse column form.
#[derive(Debug, Clone, PartialEq)]
pub struct Csc {
    pub(super) nrows: usize,
    pub(super) ncols: usize,
    /// Start of each column in `row_idx`/`val` (`ncols + 1` entries).
    pub(super) col_ptr: Vec<usize>,
    /// Row of each stored entry, sorted within a column.
    pub(super) row_idx: Vec<usize>,
    /// Value of each stored entry.
    pub(super) val: Vec<f64>,
}

impl Csc {
    /// A dense `nrows × ncols` matrix with entries `a(i, j)` stored whole (every entry a slot,
    /// zeros included): the reduced operators of a modal or Craig–Bampton basis.
    pub fn dense(nrows: usize, ncols: usize, a: impl Fn(usize, usize) -> f64) -> Self {
        let trip: Vec<(usize, usize, f64)> = (0..ncols)
            .flat_map(|j| (0..nrows).map(move |i| (i, j)))
            .map(|(i, j)| (i, j, a(i, j)))
            .collect();
        Self::from_triplets(nrows, ncols, &trip)
    }

    /// Builds from `(row, col, value)` triplets; duplicates are summed, explicit zeros stored
    /// (they reserve a slot of the pattern).
    ///
    /// # Panics
    /// If an index is out of range (a bug in the assembling code).
    pub fn from_triplets(nrows: usize, ncols: usize, trip: &[(usize, usize, f64)]) -> Self {
        let mut t: Vec<(usize, usize, f64)> = trip.to_vec();
        for &(r, c, _) in &t {
            assert!(
                r < nrows && c < ncols,
                "triplet ({r}, {c}) outside {nrows}×{ncols}"
            );
        }
        t.sort_by_key(|a| (a.1, a.0));
        let mut col_ptr = vec![0usize; ncols + 1];
        let mut row_idx = Vec::with_capacity(t.len());
        let mut val: Vec<f64> = Vec::with_capacity(t.len());
        let mut last: Option<(usize, usize)> = None;
        for (r, c, v) in t {
            if last == Some((r, c)) {
                *val.last_mut().expect("previous entry") += v;
            } else {
                row_idx.push(r);
                val.push(v);
                col_ptr[c + 1] += 1;
                last = Some((r, c));
            }
        }
        for c in 0..ncols {
            col_ptr[c + 1] += col_ptr[c];
        }
        Self {
            nrows,
            ncols,
            col_ptr,
            row_idx,
            val,
        }
    }

    /// All-zero matrix.
    pub fn zeros(nrows: usize, ncols: usize) -> Self {
        Self::from_triplets(nrows, ncols, &[])
    }

    /// Number of rows.
    pub fn nrows(&self) -> usize {
        self.nrows
    }
    /// Number of columns.
    pub fn ncols(&self) -> usize {
        self.ncols
    }
    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.val.len()
    }

    /// Iterates `(row, col, value)` over stored entries.
    pub fn triplets(&self) -> impl Iterator<Item = (usize, usize, f64)> + '_ {
        (0..self.ncols).flat_map(move |c| {
            (self.col_ptr[c]..self.col_ptr[c + 1]).map(move |k| (self.row_idx[k], c, self.val[k]))
        })
    }

    /// Index of entry `(r, c)` in the value array, if it is stored (binary search in its
    /// column; rows are sorted within a column).
    pub fn slot(&self, r: usize, c: usize) -> Option<usize> {
        let (a, b) = (self.col_ptr[c], self.col_ptr[c + 1]);
        self.row_idx[a..b].binary_search(&r).ok().map(|k| a + k)
    }

    /// Stored values, column by column (the order of [`Csc::triplets`]).
    pub fn values(&self) -> &[f64] {
        &self.val
    }

    /// Stored values, mutable: refills a matrix whose pattern is fixed.
    pub fn values_mut(&mut self) -> &mut [f64] {
        &mut self.val
    }

    /// Entry `(r, c)` (zero when not stored).
    pub fn get(&self, r: usize, c: usize) -> f64 {
        (self.col_ptr[c]..self.col_ptr[c + 1])
            .filter(|&k| self.row_idx[k] == r)
            .map(|k| self.val[k])
            .sum()
    }

    /// `α A + β B` on the union pattern (same shape).
    pub fn lin_comb(alpha: f64, a: &Csc, beta: f64, b: &Csc) -> Csc {
        assert_eq!((a.nrows, a.ncols), (b.nrows, b.ncols));
        let t: Vec<(usize, usize, f64)> = a
            .triplets()
            .map(|(r, c, v)| (r, c, alpha * v))
            .chain(b.triplets().map(|(r, c, v)| (r, c, beta * v)))
            .filter(|x| x.2 != 0.0)
            .collect();
        Csc::from_triplets(a.nrows, a.ncols, &t)
    }

    /// `y += α A x` without allocating.
    #[inline]
    pub fn mul_add(&self, alpha: f64, x: &[f64], y: &mut [f64]) {
        debug_assert_eq!(x.len(), self.ncols);
        debug_assert_eq!(y.len(), self.nrows);
        for (c, xv) in x.iter().enumerate() {
            let xc = alpha * xv;
            if xc == 0.0 {
                continue;
            }
            for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                y[self.row_idx[k]] += self.val[k] * xc;
            }
        }
    }

    /// True when every stored entry lies on the diagonal.
    pub fn is_diagonal(&self) -> bool {
        self.triplets().all(|(r, c, v)| r == c || v == 0.0)
    }

    /// The diagonal as a dense vector.
    pub fn diagonal(&self) -> Vec<f64> {
        let mut d = vec![0.0; self.nrows.min(self.ncols)];
        for (r, c, v) in self.triplets() {
            if r == c {
                d[r] += v;
            }
        }
        d
    }

    /// Largest |A_ij − A_ji| relative to the largest |A_ij| (0 for a symmetric matrix).
    pub fn asymmetry(&self) -> f64 {
        let scale = self.val.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        if scale == 0.0 {
            return 0.0;
        }
        self.triplets()
            .map(|(r, c, v)| (v - self.get(c, r)).abs())
            .fold(0.0, f64::max)
            / scale
    }

    /// The matrix as a faer view (no copy).
    pub(super) fn faer_ref(&self) -> SparseColMatRef<'_, usize, f64> {
        SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(
                self.nrows,
                self.ncols,
                &self.col_ptr,
                None,
                &self.row_idx,
            ),
            &self.val,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn duplicates_are_summed_and_matvec_is_right() {
        let a = Csc::from_triplets(2, 2, &[(0, 0, 1.0), (0, 0, 2.0), (1, 0, 4.0)]);
        assert_eq!(a.nnz(), 2);
        let mut y = [0.0; 2];
        a.mul_add(2.0, &[1.0, 5.0], &mut y);
        assert_eq!(y, [6.0, 8.0]);
    }
}
