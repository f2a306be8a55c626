//! [`PatternAssembly`]: a finite-element matrix summed in place on its sparsity pattern, known
//! from the elements' DOF lists before any element matrix is computed — no triplet list, so a
//! 10⁶-cell mesh assembles in the memory of its matrix (a triplet list of 10⁶ Tet4 cells is
//! 1.4·10⁸ entries, 3.5 GB, and sorting it copied them once more).

use super::Csc;

/// A square matrix being assembled on a fixed pattern: every pair `(dofs[i], dofs[j])` of every
/// element DOF list given to [`PatternAssembly::new`] has a slot (rows sorted within a column),
/// and [`PatternAssembly::add`] sums an element matrix into its slots.
///
/// [`PatternAssembly::finish`] keeps only the slots that received a nonzero contribution, so the
/// result equals [`Csc::from_triplets`] of the triplets [`crate::assembly::scatter`] would have
/// pushed for the same elements in the same order, bit for bit: same pattern, and each entry the
/// sum of the same contributions in element order.
#[derive(Debug)]
pub struct PatternAssembly {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<u32>,
    val: Vec<f64>,
    hit: Vec<bool>,
}

impl PatternAssembly {
    /// The pattern of an `n × n` matrix whose elements have the free DOF lists
    /// `dofs[offsets[e]..offsets[e + 1]]` (`offsets` starts at 0 and ends at `dofs.len()`).
    ///
    /// # Panics
    /// If a DOF is `≥ n`, `n` exceeds `u32::MAX`, or `offsets` is not a non-decreasing list
    /// into `dofs` (bugs in the assembling code).
    pub fn new(n: usize, offsets: &[usize], dofs: &[u32]) -> Self {
        assert!(
            u32::try_from(n).is_ok(),
            "{n} DOFs exceed the pattern's u32 rows"
        );
        // DOF → the elements holding it (compressed: count, prefix sum, fill).
        let mut inc_ptr = vec![0usize; n + 1];
        for &d in dofs {
            inc_ptr[d as usize + 1] += 1;
        }
        for d in 0..n {
            inc_ptr[d + 1] += inc_ptr[d];
        }
        let mut inc = vec![0u32; dofs.len()];
        let mut next = inc_ptr.clone();
        for (e, w) in offsets.windows(2).enumerate() {
            for &d in &dofs[w[0]..w[1]] {
                inc[next[d as usize]] = e as u32;
                next[d as usize] += 1;
            }
        }
        drop(next);
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0);
        let mut row_idx = Vec::new();
        let mut rows: Vec<u32> = Vec::new();
        for d in 0..n {
            rows.clear();
            for &e in &inc[inc_ptr[d]..inc_ptr[d + 1]] {
                let e = e as usize;
                rows.extend_from_slice(&dofs[offsets[e]..offsets[e + 1]]);
            }
            rows.sort_unstable();
            rows.dedup();
            row_idx.extend_from_slice(&rows);
            col_ptr.push(row_idx.len());
        }
        let nnz = row_idx.len();
        Self {
            n,
            col_ptr,
            row_idx,
            val: vec![0.0; nnz],
            hit: vec![false; nnz],
        }
    }

    /// Adds the element matrix `ke` (row-major, `m × m` with `m = dofs.len()`): entry `(i, j)`
    /// to `(dofs[i], dofs[j])`, fixed DOFs (`None`) and zero entries skipped, row by row as
    /// [`crate::assembly::scatter`] pushes them.
    ///
    /// # Panics
    /// If a pair of free DOFs has no slot (the DOF list was not among the pattern's).
    pub fn add(&mut self, dofs: &[Option<usize>], ke: &[f64]) {
        let m = dofs.len();
        debug_assert_eq!(ke.len(), m * m, "element matrix of {m} DOFs");
        for (i, di) in dofs.iter().enumerate() {
            let Some(a) = *di else { continue };
            for (j, dj) in dofs.iter().enumerate() {
                let Some(b) = *dj else { continue };
                let v = ke[i * m + j];
                if v != 0.0 {
                    let k = self.slot(a, b);
                    self.val[k] += v;
                    self.hit[k] = true;
                }
            }
        }
    }

    /// The slot of `(r, c)`.
    fn slot(&self, r: usize, c: usize) -> usize {
        let (s, e) = (self.col_ptr[c], self.col_ptr[c + 1]);
        let pos = self.row_idx[s..e]
            .binary_search(&(r as u32))
            .unwrap_or_else(|_| panic!("entry ({r}, {c}) outside the assembled pattern"));
        s + pos
    }

    /// The assembled matrix: the slots that received a nonzero contribution.
    pub fn finish(self) -> Csc {
        let Self {
            n,
            col_ptr,
            row_idx,
            val,
            hit,
        } = self;
        let kept = hit.iter().filter(|&&h| h).count();
        let mut out_ptr = Vec::with_capacity(n + 1);
        out_ptr.push(0);
        let mut out_row = Vec::with_capacity(kept);
        let mut out_val = Vec::with_capacity(kept);
        for c in 0..n {
            for k in col_ptr[c]..col_ptr[c + 1] {
                if hit[k] {
                    out_row.push(row_idx[k] as usize);
                    out_val.push(val[k]);
                }
            }
            out_ptr.push(out_row.len());
        }
        Csc {
            nrows: n,
            ncols: n,
            col_ptr: out_ptr,
            row_idx: out_row,
            val: out_val,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The triplets `crate::assembly::scatter` pushes (free pairs, nonzero entries, row by row).
    fn scatter(t: &mut Vec<(usize, usize, f64)>, dofs: &[Option<usize>], ke: &[f64]) {
        let m = dofs.len();
        for (i, a) in dofs.iter().enumerate() {
            for (j, b) in dofs.iter().enumerate() {
                if let (Some(a), Some(b)) = (a, b) {
                    if ke[i * m + j] != 0.0 {
                        t.push((*a, *b, ke[i * m + j]));
                    }
                }
            }
        }
    }

    #[test]
    fn equals_the_triplet_assembly_bit_for_bit() {
        // Three overlapping elements on 5 DOFs, one with a fixed DOF and a zero entry.
        let els: Vec<Vec<Option<usize>>> = vec![
            vec![Some(0), Some(1), Some(2)],
            vec![Some(2), None, Some(3)],
            vec![Some(4), Some(1)],
        ];
        let mats: Vec<Vec<f64>> = els
            .iter()
            .enumerate()
            .map(|(e, d)| {
                let m = d.len();
                (0..m * m)
                    .map(|k| {
                        if k == 1 {
                            0.0
                        } else {
                            0.1 + e as f64 + k as f64 / 7.0
                        }
                    })
                    .collect()
            })
            .collect();
        let mut offsets = vec![0];
        let mut flat = Vec::new();
        for d in &els {
            flat.extend(d.iter().flatten().map(|&x| x as u32));
            offsets.push(flat.len());
        }
        let mut pa = PatternAssembly::new(5, &offsets, &flat);
        let mut t = Vec::new();
        for (d, ke) in els.iter().zip(&mats) {
            pa.add(d, ke);
            scatter(&mut t, d, ke);
        }
        let a = pa.finish();
        let b = Csc::from_triplets(5, 5, &t);
        assert_eq!(a, b);
        // (0, 1) of the first element is a zero contribution and nothing else reaches it.
        assert_eq!(a.slot(0, 1), None);
    }
}
