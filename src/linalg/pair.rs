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
        Self {
            nrows: a.nrows,
            ncols: a.ncols,
            row_ptr,
            col_idx,
            a: av,
            b: bv,
        }
    }

    /// `y += A x + B z`, allocation free (one read of the pattern, one write per row).
    ///
    /// # Panics
    /// If a slice length does not match the shape.
    #[inline]
    pub fn mul_add(&self, x: &[f64], z: &[f64], y: &mut [f64]) {
        assert!(x.len() == self.ncols && z.len() == self.ncols && y.len() == self.nrows);
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
