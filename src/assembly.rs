//! Assembly: element matrices scattered into the triplets of a global matrix.
//!
//! Every model assembles the same way: an element's `n × n` matrix (row-major, over its `n`
//! local DOFs) is added entry by entry at the global DOFs of those local DOFs, and the triplets
//! are summed by [`crate::linalg::Csc::from_triplets`]. [`scatter`] is that loop, shared by the
//! FE rotor, the general FE stator and the meshed stators; the triplets come out in one fixed
//! order (row by row), so the sums, and the assembled matrices, are the same bit for bit
//! wherever it is used.

/// The global DOF of one local DOF of an element: a `usize` (always free) or an
/// `Option<usize>` (`None`: a fixed DOF, removed from the global system).
pub trait Dof: Copy {
    /// The global index, `None` when the DOF is fixed.
    fn global(self) -> Option<usize>;
}

impl Dof for usize {
    #[inline]
    fn global(self) -> Option<usize> {
        Some(self)
    }
}

impl Dof for Option<usize> {
    #[inline]
    fn global(self) -> Option<usize> {
        self
    }
}

/// Adds the element matrix `ke` (row-major, `n × n` with `n = dofs.len()`) to the triplets `t`
/// of a global matrix: entry `(i, j)` goes to `(dofs[i], dofs[j])`. Fixed DOFs and zero entries
/// are skipped; entries are pushed row by row.
#[inline]
pub fn scatter<D: Dof>(t: &mut Vec<(usize, usize, f64)>, dofs: &[D], ke: &[f64]) {
    let n = dofs.len();
    debug_assert_eq!(ke.len(), n * n, "element matrix of {n} DOFs");
    for (i, di) in dofs.iter().enumerate() {
        let Some(a) = di.global() else { continue };
        for (j, dj) in dofs.iter().enumerate() {
            if let Some(b) = dj.global() {
                let v = ke[i * n + j];
                if v != 0.0 {
                    t.push((a, b, v));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skips_fixed_dofs_and_zeros_row_by_row() {
        let mut t = Vec::new();
        scatter(
            &mut t,
            &[Some(4), None, Some(2)],
            &[1., 2., 3., 4., 5., 6., 0., 8., 9.],
        );
        assert_eq!(t, vec![(4, 4, 1.0), (4, 2, 3.0), (2, 2, 9.0)]);
        let mut u = Vec::new();
        scatter(&mut u, &[7usize, 3], &[1., 0., 2., 3.]);
        assert_eq!(u, vec![(7, 7, 1.0), (3, 7, 2.0), (3, 3, 3.0)]);
    }
}
