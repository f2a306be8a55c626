//! FE rotor helpers: the FE model inside a rotor, sub-blocks of sparse matrices and their
//! natural frequencies.

use rubsim::linalg::Csc;
use rubsim::linear;
use rubsim::model::fe_rotor::FeRotor;
use rubsim::model::{FeModel, Rotor};

/// The FE model of an FE rotor (panics for a Jeffcott rotor).
pub fn fe(r: &Rotor) -> &FeModel {
    match r {
        Rotor::Fe(f) => f,
        _ => panic!("FE rotor expected"),
    }
}

/// Rows/columns `dofs` of a sparse matrix as a new sparse matrix (renumbered 0..dofs.len()).
pub fn sub(a: &Csc, dofs: &[usize]) -> Csc {
    let mut at = vec![usize::MAX; a.nrows()];
    for (i, d) in dofs.iter().enumerate() {
        at[*d] = i;
    }
    let t: Vec<(usize, usize, f64)> = a
        .triplets()
        .filter(|(r, c, _)| at[*r] != usize::MAX && at[*c] != usize::MAX)
        .map(|(r, c, v)| (at[r], at[c], v))
        .collect();
    Csc::from_triplets(dofs.len(), dofs.len(), &t)
}

/// Natural frequencies (rad/s) of the block of `dofs` of the rotor at rest.
pub fn block_frequencies(f: &FeRotor, dofs: &[usize]) -> Vec<f64> {
    let (lam, _) = linear::undamped_modes(&sub(&f.m, dofs), &sub(&f.k(0.0), dofs)).unwrap();
    lam.iter().map(|l| l.max(0.0).sqrt()).collect()
}
