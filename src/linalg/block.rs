//! [`BlockTridiag`]: block Thomas LU of a shaft chain in 4 × 4 node blocks.

use super::{Csc, LinalgError};

/// Block size of [`BlockTridiag`]: the four bending DOFs `[u_x, u_y, θ_x, θ_y]` of a shaft node.
pub const NODE_BLOCK: usize = 4;
type Blk = [[f64; NODE_BLOCK]; NODE_BLOCK];

/// LU factors of a block-tridiagonal matrix of 4 × 4 blocks (DOFs `4i..4i+4` of node i coupled
/// only to nodes i ± 1): the M̃ of a shaft model in its natural numbering. Block Thomas
/// algorithm without pivoting between blocks (M̃ = M/Δt² + (C + ΩG)/(2Δt) has a positive
/// definite symmetric part below the stability limit, so no block pivoting is needed), with the
/// inverse of each 4 × 4 pivot block formed by Gauss–Jordan with partial pivoting:
/// `D₀ = A₀₀`, `Lᵢ = Aᵢ,ᵢ₋₁ Dᵢ₋₁⁻¹`, `Dᵢ = Aᵢᵢ − Lᵢ Aᵢ₋₁,ᵢ`. A solve is three fixed-size 4 × 4
/// products per node, with none of a general sparse solve's indirection.
#[derive(Debug, Clone)]
pub struct BlockTridiag {
    nb: usize,
    dinv: Vec<Blk>,
    lower: Vec<Blk>,
    upper: Vec<Blk>,
}

#[inline]
fn blk_mul(a: &Blk, b: &Blk) -> Blk {
    let mut c = [[0.0; NODE_BLOCK]; NODE_BLOCK];
    for i in 0..NODE_BLOCK {
        for k in 0..NODE_BLOCK {
            for j in 0..NODE_BLOCK {
                c[i][j] += a[i][k] * b[k][j];
            }
        }
    }
    c
}

/// The entries of a run of blocks, row by row.
fn flat(b: &[Blk]) -> &[f64] {
    b.as_flattened().as_flattened()
}

/// Inverse of a 4 × 4 block by Gauss–Jordan with partial pivoting; `None` when a pivot is
/// below `tiny`.
fn blk_inv(a: &Blk, tiny: f64) -> Option<Blk> {
    let mut m = *a;
    let mut inv = [[0.0; NODE_BLOCK]; NODE_BLOCK];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for k in 0..NODE_BLOCK {
        let p = (k..NODE_BLOCK).max_by(|&x, &y| m[x][k].abs().total_cmp(&m[y][k].abs()))?;
        let pivot = m[p][k].abs();
        if pivot.is_nan() || pivot <= tiny {
            return None;
        }
        m.swap(k, p);
        inv.swap(k, p);
        let d = 1.0 / m[k][k];
        for j in 0..NODE_BLOCK {
            m[k][j] *= d;
            inv[k][j] *= d;
        }
        for i in 0..NODE_BLOCK {
            if i != k {
                let f = m[i][k];
                if f != 0.0 {
                    for j in 0..NODE_BLOCK {
                        m[i][j] -= f * m[k][j];
                        inv[i][j] -= f * inv[k][j];
                    }
                }
            }
        }
    }
    Some(inv)
}

/// A block-tridiagonal matrix in 4 × 4 node blocks, unfactored: block row i holds
/// `A_{i,i−1}` (`lower[i]`), `A_{ii}` (`diag[i]`) and `A_{i,i+1}` (`upper[i]`). Linear
/// combinations of such matrices stay on the same blocks, so a matrix that varies with a
/// parameter, `A(d) = A₀ + d A₁`, is refactored from its parts without touching a sparse
/// pattern ([`BlockTridiag::refactor`]).
#[derive(Debug, Clone)]
pub struct BlockParts {
    diag: Vec<Blk>,
    lower: Vec<Blk>,
    upper: Vec<Blk>,
    /// Largest |entry| (for the singularity threshold).
    scale: f64,
}

impl BlockParts {
    /// The blocks of `a` when it is block tridiagonal in 4 × 4 node blocks (`n` a multiple of
    /// 4, no nonzero entry between nodes more than one apart); `None` when it is not.
    pub fn new(a: &Csc) -> Option<Self> {
        let n = a.nrows;
        if n == 0 || !n.is_multiple_of(NODE_BLOCK) || a.ncols != n {
            return None;
        }
        let nb = n / NODE_BLOCK;
        let zero = [[0.0; NODE_BLOCK]; NODE_BLOCK];
        let (mut diag, mut lower, mut upper) = (vec![zero; nb], vec![zero; nb], vec![zero; nb]);
        let scale = a.val.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        for (r, c, v) in a.triplets() {
            let (bi, bj) = (r / NODE_BLOCK, c / NODE_BLOCK);
            let (i, j) = (r % NODE_BLOCK, c % NODE_BLOCK);
            if bi == bj {
                diag[bi][i][j] += v;
            } else if bi == bj + 1 {
                lower[bi][i][j] += v;
            } else if bj == bi + 1 {
                upper[bi][i][j] += v;
            } else if v != 0.0 {
                return None;
            }
        }
        Some(Self {
            diag,
            lower,
            upper,
            scale,
        })
    }

    /// The diagonal (`k` = 0), lower (1) or upper (2) blocks.
    fn part(&self, k: usize) -> &[Blk] {
        match k {
            0 => &self.diag,
            1 => &self.lower,
            _ => &self.upper,
        }
    }

    /// Number of node blocks.
    pub fn blocks(&self) -> usize {
        self.diag.len()
    }

    /// `self = a + c₁ b₁ + c₂ b₂` entry by entry (every part of one size), allocation free;
    /// the singularity scale is the bound `scale(a) + |c₁| scale(b₁) + |c₂| scale(b₂)` of the
    /// largest |entry|.
    ///
    /// # Panics
    /// If the parts differ in size.
    pub fn set_lin_comb(
        &mut self,
        a: &BlockParts,
        (c1, b1): (f64, &BlockParts),
        (c2, b2): (f64, &BlockParts),
    ) {
        let nb = self.blocks();
        assert!(a.blocks() == nb && b1.blocks() == nb && b2.blocks() == nb);
        for k in 0..3 {
            let out = match k {
                0 => &mut self.diag,
                1 => &mut self.lower,
                _ => &mut self.upper,
            };
            let (x, y, z) = (flat(a.part(k)), flat(b1.part(k)), flat(b2.part(k)));
            for (((o, x), y), z) in out
                .as_flattened_mut()
                .as_flattened_mut()
                .iter_mut()
                .zip(x)
                .zip(y)
                .zip(z)
            {
                *o = x + c1 * y + c2 * z;
            }
        }
        self.scale = a.scale + c1.abs() * b1.scale + c2.abs() * b2.scale;
    }
}

impl BlockTridiag {
    /// Factors `a` when it is block tridiagonal in 4 × 4 node blocks (`n` a multiple of 4, no
    /// entry between nodes more than one apart); `Ok(None)` when it is not.
    ///
    /// # Errors
    /// [`LinalgError::SingularBlock`] on a pivot block whose largest pivot is below `1e-13`
    /// times the largest entry of `a`.
    pub fn new(a: &Csc) -> Result<Option<Self>, LinalgError> {
        let Some(parts) = BlockParts::new(a) else {
            return Ok(None);
        };
        let zero = [[0.0; NODE_BLOCK]; NODE_BLOCK];
        let nb = parts.blocks();
        let mut f = Self {
            nb,
            dinv: vec![zero; nb],
            lower: vec![zero; nb],
            upper: vec![zero; nb],
        };
        f.refactor(&parts)?;
        Ok(Some(f))
    }

    /// Factors `parts` in place of the current factor (same number of blocks), allocation free.
    ///
    /// # Errors
    /// As [`BlockTridiag::new`].
    ///
    /// # Panics
    /// If `parts` has another number of blocks.
    pub fn refactor(&mut self, parts: &BlockParts) -> Result<(), LinalgError> {
        assert_eq!(parts.blocks(), self.nb);
        let n = self.nb * NODE_BLOCK;
        let tiny = 1e-13 * parts.scale;
        self.upper.copy_from_slice(&parts.upper);
        for b in 0..self.nb {
            let mut d = parts.diag[b];
            if b > 0 {
                // Lᵦ = Aᵦ,ᵦ₋₁ Dᵦ₋₁⁻¹, Dᵦ = Aᵦᵦ − Lᵦ Aᵦ₋₁,ᵦ.
                self.lower[b] = blk_mul(&parts.lower[b], &self.dinv[b - 1]);
                let lu = blk_mul(&self.lower[b], &self.upper[b - 1]);
                for i in 0..NODE_BLOCK {
                    for j in 0..NODE_BLOCK {
                        d[i][j] -= lu[i][j];
                    }
                }
            }
            self.dinv[b] = blk_inv(&d, tiny).ok_or(LinalgError::SingularBlock { n, node: b })?;
        }
        Ok(())
    }

    /// Solves `A x = b` in place, allocation free.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        assert_eq!(b.len(), self.nb * NODE_BLOCK);
        let mut prev = [0.0; NODE_BLOCK];
        // Forward: yᵢ = bᵢ − Lᵢ yᵢ₋₁.
        for (i, chunk) in b.chunks_exact_mut(NODE_BLOCK).enumerate() {
            if i > 0 {
                let l = &self.lower[i];
                for (r, c) in chunk.iter_mut().enumerate() {
                    *c -= l[r][0] * prev[0]
                        + l[r][1] * prev[1]
                        + l[r][2] * prev[2]
                        + l[r][3] * prev[3];
                }
            }
            prev.copy_from_slice(chunk);
        }
        // Backward: xᵢ = Dᵢ⁻¹ (yᵢ − Uᵢ xᵢ₊₁).
        let mut next = [0.0; NODE_BLOCK];
        for (i, chunk) in b.chunks_exact_mut(NODE_BLOCK).enumerate().rev() {
            let mut y = [chunk[0], chunk[1], chunk[2], chunk[3]];
            if i + 1 < self.nb {
                let u = &self.upper[i];
                for (r, yr) in y.iter_mut().enumerate() {
                    *yr -= u[r][0] * next[0]
                        + u[r][1] * next[1]
                        + u[r][2] * next[2]
                        + u[r][3] * next[3];
                }
            }
            let d = &self.dinv[i];
            for (r, c) in chunk.iter_mut().enumerate() {
                *c = d[r][0] * y[0] + d[r][1] * y[1] + d[r][2] * y[2] + d[r][3] * y[3];
            }
            next.copy_from_slice(chunk);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Lu;

    #[test]
    fn block_tridiagonal_lu_matches_a_pivoting_lu() {
        // 12 nodes of 4 DOFs, unsymmetric blocks (symmetric part + skew part), compared with the
        // pivoting sparse LU; a matrix with an entry two nodes apart is declined.
        let nb = 12;
        let n = 4 * nb;
        let mut t = Vec::new();
        for r in 0..n {
            for c in 0..n {
                let (br, bc): (usize, usize) = (r / 4, c / 4);
                if br.abs_diff(bc) > 1 {
                    continue;
                }
                let sym = if r == c {
                    8.0 + (r % 5) as f64
                } else {
                    0.5 / (1.0 + (r as f64 - c as f64).abs())
                };
                let skew =
                    0.3 * ((r * 7 + c * 3) as f64).sin() - 0.3 * ((c * 7 + r * 3) as f64).sin();
                t.push((r, c, sym + skew));
            }
        }
        let a = Csc::from_triplets(n, n, &t);
        let bt = BlockTridiag::new(&a).unwrap().expect("block tridiagonal");
        let x: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).cos()).collect();
        let mut b = vec![0.0; n];
        a.mul_add(1.0, &x, &mut b);
        let mut b2 = b.clone();
        bt.solve_in_place(&mut b);
        Lu::new(&a).unwrap().solve_in_place(&mut b2);
        for i in 0..n {
            assert!((b[i] - x[i]).abs() < 1e-12, "{i}: {} vs {}", b[i], x[i]);
            assert!((b[i] - b2[i]).abs() < 1e-12);
        }
        t.push((0, 8, 0.1));
        assert!(BlockTridiag::new(&Csc::from_triplets(n, n, &t))
            .unwrap()
            .is_none());
        assert!(BlockTridiag::new(&Csc::from_triplets(6, 6, &[(0, 0, 1.0)]))
            .unwrap()
            .is_none());
    }
}
