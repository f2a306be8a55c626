//! [`PairCsr`]: two matrices on one row-compressed pattern for the explicit step.

use super::Csc;

/// Two matrices on one row-compressed pattern, for `y += A x + B z` in one pass (the explicit
/// step's right-hand side): one read of the pattern, one write per row.
#[derive(Debug, Clone, PartialEq)]
pub struct PairCsr {
    nrows: usize,
    ncols: usize,
    row_ptr: Vec<usize>,
    col_idx: Vec<usize>,
    a: Vec<f64>,
    b: Vec<f64>,
    /// Square, and row `r` holds exactly one entry, at column `r` (a Jeffcott rotor, a lumped
    /// stator without stiffness-proportional damping): [`PairCsr::mul_add`] skips the pattern.
    diagonal: bool,
}

impl PairCsr {
    /// Union pattern of `a` and `b` (same shape).
    ///
    /// # Panics
    /// If the shapes differ.
    pub fn new(a: &Csc, b: &Csc) -> Self {
        assert_eq!((a.nrows, a.ncols), (b.nrows, b.ncols));
        let mut t: Vec<(usize, usize, f64, f64)> = a
            .triplets()
            .map(|(r, c, v)| (r, c, v, 0.0))
            .chain(b.triplets().map(|(r, c, v)| (r, c, 0.0, v)))
            .collect();
        t.sort_by_key(|x| (x.0, x.1));
        let mut row_ptr = vec![0usize; a.nrows + 1];
        let (mut col_idx, mut av, mut bv) = (Vec::new(), Vec::new(), Vec::new());
        let mut last = None;
        for (r, c, x, y) in t {
            if last == Some((r, c)) {
                *av.last_mut().expect("entry") += x;
                *bv.last_mut().expect("entry") += y;
            } else {
                col_idx.push(c);
                av.push(x);
                bv.push(y);
                row_ptr[r + 1] += 1;
                last = Some((r, c));
            }
        }
        for r in 0..a.nrows {
            row_ptr[r + 1] += row_ptr[r];
        }
        let diagonal =
            a.nrows == a.ncols && (0..a.nrows).all(|r| row_ptr[r + 1] == r + 1 && col_idx[r] == r);
        Self {
            diagonal,
            nrows: a.nrows,
            ncols: a.ncols,
            row_ptr,
            col_idx,
            a: av,
            b: bv,
        }
    }

    /// The diagonals `(A, B)` when both matrices are diagonal on a square pattern (each row
    /// one entry, on the diagonal); `None` otherwise.
    pub fn diagonal(&self) -> Option<(&[f64], &[f64])> {
        self.diagonal.then_some((&self.a[..], &self.b[..]))
    }

    /// `y += A x + B z`, allocation free (one read of the pattern, one write per row).
    ///
    /// # Panics
    /// If a slice length does not match the shape.
    #[inline]
    pub fn mul_add(&self, x: &[f64], z: &[f64], y: &mut [f64]) {
        assert!(x.len() == self.ncols && z.len() == self.ncols && y.len() == self.nrows);
        if self.diagonal {
            // The same sums as the general loop below (`0 + (a x + b z)` per row), without
            // reading the pattern.
            let rows = y.iter_mut().zip(x).zip(z).zip(self.a.iter().zip(&self.b));
            for (((yr, x), z), (a, b)) in rows {
                *yr += 0.0 + (a * x + b * z);
            }
            return;
        }
        for (r, yr) in y.iter_mut().enumerate() {
            let (s, e) = (self.row_ptr[r], self.row_ptr[r + 1]);
            let mut acc = 0.0;
            for ((c, a), b) in self.col_idx[s..e]
                .iter()
                .zip(&self.a[s..e])
                .zip(&self.b[s..e])
            {
                // `col_idx < ncols` by construction and x, z have ncols entries (asserted).
                acc += a * x[*c] + b * z[*c];
            }
            *yr += acc;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `y += A x + B z` against the dense sums, on a diagonal pair (its one-pass path) and on
    /// a pair with off-diagonal entries (the pattern path): the same values bit for bit.
    #[test]
    #[allow(clippy::needless_range_loop)] // dense reference indexes several arrays
    fn diagonal_and_general_paths_give_the_dense_sums() {
        let x = [0.3, -1.7, 2.9];
        let z = [-0.11, 0.5, 1e-3];
        let y0 = [1.0, -2.0, 0.25];
        for off in [false, true] {
            let mut ta = vec![(0, 0, 2.0), (1, 1, -3.5), (2, 2, 0.75)];
            let tb = vec![(0, 0, 0.125), (1, 1, 4.0), (2, 2, -1.5)];
            if off {
                ta.push((0, 2, 1.25));
            }
            let (a, b) = (Csc::from_triplets(3, 3, &ta), Csc::from_triplets(3, 3, &tb));
            let p = PairCsr::new(&a, &b);
            assert_eq!(p.diagonal().is_some(), !off);
            let mut y = y0;
            p.mul_add(&x, &z, &mut y);
            for r in 0..3 {
                let mut acc = 0.0;
                for c in 0..3 {
                    let (av, bv) = (a.get(r, c), b.get(r, c));
                    if av != 0.0 || bv != 0.0 {
                        acc += av * x[c] + bv * z[c];
                    }
                }
                assert_eq!(y[r], y0[r] + acc, "row {r}, off-diagonal {off}");
            }
        }
    }
}
