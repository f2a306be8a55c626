//! [`BlockTri`]: a block-tridiagonal matrix of 4 × 4 node blocks, for `y += A x` by fixed-size
//! block products.
//!
//! A shaft chain's matrices in its natural numbering couple node i's four bending DOFs only
//! with nodes i − 1, i, i + 1 (the pattern [`super::BlockTridiag`] factors). Stored as three
//! dense 4 × 4 blocks per node row, a product is straight-line arithmetic on fixed-size arrays
//! with no column index read — fewer instructions than the same product on a row-compressed
//! pattern ([`super::PairCsr`]), whose cost per stored entry is dominated by the index
//! look-up. Used for a gyroscopic rotor's per-step correction under a varying speed.

use super::{Csc, NODE_BLOCK};

type Blk = [[f64; NODE_BLOCK]; NODE_BLOCK];

/// `A` (`4 nb × 4 nb`) as node blocks: row i holds the blocks of columns i − 1, i, i + 1
/// (zero blocks outside the chain).
#[derive(Debug, Clone, PartialEq)]
pub struct BlockTri {
    nb: usize,
    /// Per node row: `[A_{i,i−1}, A_{ii}, A_{i,i+1}]`.
    a: Vec<[Blk; 3]>,
}

impl BlockTri {
    /// The block form of `a`; `None` when it is not square, its size not a multiple of 4, or
    /// an entry couples nodes further apart than neighbours (duplicates are summed).
    pub fn new(a: &Csc) -> Option<Self> {
        let n = a.nrows;
        if n == 0 || !n.is_multiple_of(NODE_BLOCK) || a.ncols != n {
            return None;
        }
        let nb = n / NODE_BLOCK;
        let mut out = vec![[[[0.0; NODE_BLOCK]; NODE_BLOCK]; 3]; nb];
        for (r, c, v) in a.triplets() {
            let (i, j) = (r / NODE_BLOCK, c / NODE_BLOCK);
            if j + 1 < i || j > i + 1 {
                return None;
            }
            out[i][j + 1 - i][r % NODE_BLOCK][c % NODE_BLOCK] += v;
        }
        Some(Self { nb, a: out })
    }

    /// `yᵣ += Σ_c A_rc sᵣ[c]` with `sᵣ = w` for the rows r of a node block that `use_w`
    /// marks and `sᵣ = x` for the others — `y += A x` when no row is marked. (With A = G and
    /// the marked rows K_st's, `y += G x + K_st (w − x)`.) Allocation free.
    ///
    /// # Panics
    /// If a slice length is not the matrix's size.
    #[inline]
    pub fn mul_add_rows(&self, x: &[f64], w: &[f64], use_w: [bool; NODE_BLOCK], y: &mut [f64]) {
        let n = self.nb * NODE_BLOCK;
        assert!(x.len() == n && w.len() == n && y.len() == n);
        for (i, yb) in y.chunks_exact_mut(NODE_BLOCK).enumerate() {
            let mut acc = [0.0; NODE_BLOCK];
            for (k, blk) in self.a[i].iter().enumerate() {
                // Column block j = i + k − 1, inside the chain.
                let Some(j) = (i + k).checked_sub(1).filter(|&j| j < self.nb) else {
                    continue;
                };
                let span = j * NODE_BLOCK..(j + 1) * NODE_BLOCK;
                let xs: &[f64; NODE_BLOCK] = x[span.clone()].try_into().expect("a node block");
                let ws: &[f64; NODE_BLOCK] = w[span].try_into().expect("a node block");
                for r in 0..NODE_BLOCK {
                    let s = if use_w[r] { ws } else { xs };
                    let row = &blk[r];
                    acc[r] += row[0] * s[0] + row[1] * s[1] + row[2] * s[2] + row[3] * s[3];
                }
            }
            for (yr, s) in yb.iter_mut().zip(acc) {
                *yr += s;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn block_product_matches_the_sparse_product() {
        // Three nodes (12 DOFs), entries in every block of the band, a duplicate; rows 1 and
        // 2 of each node block read w, the others x.
        let mut t = Vec::new();
        for r in 0..12_usize {
            for c in 0..12_usize {
                if (r / 4).abs_diff(c / 4) <= 1 && (r * 7 + c * 3) % 5 != 0 {
                    t.push((r, c, 0.1 * r as f64 - 0.07 * c as f64 + 0.3));
                }
            }
        }
        t.push((5, 6, 0.5));
        let a = Csc::from_triplets(12, 12, &t);
        let p = BlockTri::new(&a).expect("block tridiagonal");
        let x: Vec<f64> = (0..12).map(|i| (i as f64 * 0.37).sin()).collect();
        let w: Vec<f64> = (0..12).map(|i| (i as f64 * 0.91).cos()).collect();
        let use_w = [false, true, true, false];
        let mut y = vec![0.25; 12];
        let mut want = vec![0.25; 12];
        p.mul_add_rows(&x, &w, use_w, &mut y);
        for (r, c, v) in a.triplets() {
            want[r] += v * if use_w[r % 4] { w[c] } else { x[c] };
        }
        for (u, v) in y.iter().zip(&want) {
            assert!((u - v).abs() < 1e-13, "{u} vs {v}");
        }
    }

    #[test]
    fn a_coupling_beyond_the_neighbours_or_a_ragged_size_is_refused() {
        assert!(BlockTri::new(&Csc::from_triplets(12, 12, &[(0, 8, 1.0)])).is_none());
        assert!(BlockTri::new(&Csc::from_triplets(10, 10, &[(0, 0, 1.0)])).is_none());
    }
}
