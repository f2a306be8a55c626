//! Low-rank symmetric terms `U diag(d) Uᵀ` (modal damping) and the Sherman–Morrison–Woodbury
//! solve of a sparse matrix plus such a term.

use super::{Csc, LinalgError, StepLu};

/// A symmetric low-rank matrix `U diag(d) Uᵀ` (n × n) with `U` n × m stored column-major:
/// the form of modal damping, `C_m = Σᵢ 2ζᵢωᵢ (Mφᵢ)(Mφᵢ)ᵀ` over mass-normalised modes φᵢ,
/// which is dense but of rank m. Kept factored so a sparse solver never sees the dense block.
#[derive(Debug, Clone, PartialEq)]
pub struct LowRank {
    /// Rows (and columns) n.
    pub n: usize,
    /// `U`, n × m, column-major.
    pub u: Vec<f64>,
    /// `diag(d)`, m entries.
    pub d: Vec<f64>,
}

impl LowRank {
    /// Rank m (number of columns of U).
    pub fn rank(&self) -> usize {
        self.d.len()
    }

    /// `y += α U diag(d) Uᵀ x`; `scratch` holds at least m entries. Allocation free.
    pub fn mul_add(&self, alpha: f64, x: &[f64], y: &mut [f64], scratch: &mut [f64]) {
        let n = self.n;
        for (j, (s, d)) in scratch.iter_mut().zip(&self.d).enumerate() {
            let col = &self.u[j * n..(j + 1) * n];
            *s = alpha * d * col.iter().zip(x).map(|(a, b)| a * b).sum::<f64>();
        }
        for (j, s) in scratch.iter().take(self.rank()).enumerate() {
            let col = &self.u[j * n..(j + 1) * n];
            for (yi, ui) in y.iter_mut().zip(col) {
                *yi += ui * s;
            }
        }
    }

    /// The entries `(i, j, α (U diag(d) Uᵀ)_ij)` of the dense matrix (frequency-domain use).
    pub fn triplets(&self, alpha: f64) -> Vec<(usize, usize, f64)> {
        let n = self.n;
        let mut t = Vec::with_capacity(n * n);
        for i in 0..n {
            for j in 0..n {
                let v: f64 = (0..self.rank())
                    .map(|k| self.u[k * n + i] * self.d[k] * self.u[k * n + j])
                    .sum();
                if v != 0.0 {
                    t.push((i, j, alpha * v));
                }
            }
        }
        t
    }
}

/// Solves `(S + U diag(d) Uᵀ) x = b` with a sparse LU of `S` and the Sherman–Morrison–Woodbury
/// identity `(S + U D Uᵀ)⁻¹ = S⁻¹ − Y (D⁻¹ + Uᵀ Y)⁻¹ Uᵀ S⁻¹`, `Y = S⁻¹ U` (n × m, kept), the
/// m × m capacitance matrix factored densely with pivoting (S need not be symmetric). Every
/// `d` must be non-zero. Allocation-free solves: one sparse solve plus O(n m + m²).
#[derive(Debug)]
pub struct WoodburyLu {
    s: StepLu,
    lr: LowRank,
    y: Vec<f64>,
    cap: Vec<f64>,
    piv: Vec<usize>,
    t: Vec<f64>,
}

impl WoodburyLu {
    /// Factors `S`, computes `Y = S⁻¹U` and factors the capacitance matrix.
    ///
    /// # Errors
    /// [`LinalgError::LowRankTerm`] for a zero or non-finite `dᵢ`, the errors of
    /// [`StepLu::new`] for `S`, [`LinalgError::SingularCapacitance`] when the capacitance
    /// matrix has a pivot below `1e-14` times its largest entry.
    ///
    /// # Panics
    /// If `lr` is not of the size of `s`.
    pub fn new(s: &Csc, lr: LowRank) -> Result<Self, LinalgError> {
        let n = s.nrows;
        assert_eq!(lr.n, n, "low-rank term of another size");
        if let Some(k) = lr.d.iter().position(|v| *v == 0.0 || !v.is_finite()) {
            return Err(LinalgError::LowRankTerm {
                index: k,
                value: lr.d[k],
            });
        }
        let mut slu = StepLu::new(s)?;
        let m = lr.rank();
        let mut y = lr.u.clone();
        for c in y.chunks_mut(n.max(1)).take(m) {
            slu.solve_in_place(c);
        }
        let mut cap = vec![0.0; m * m];
        for i in 0..m {
            for j in 0..m {
                let ui = &lr.u[i * n..(i + 1) * n];
                let yj = &y[j * n..(j + 1) * n];
                cap[i * m + j] = ui.iter().zip(yj).map(|(a, b)| a * b).sum::<f64>();
            }
            cap[i * m + i] += 1.0 / lr.d[i];
        }
        let mut piv = vec![0; m];
        if !crate::math::lu_in_place(&mut cap, m, &mut piv, 1e-14) {
            return Err(LinalgError::SingularCapacitance { n, rank: m });
        }
        Ok(Self {
            s: slu,
            lr,
            y,
            cap,
            piv,
            t: vec![0.0; m],
        })
    }

    /// `y += U diag(d) Uᵀ x` with the low-rank term this solver was built with (its scratch,
    /// allocation free).
    pub fn low_rank_mul_add(&mut self, x: &[f64], y: &mut [f64]) {
        self.lr.mul_add(1.0, x, y, &mut self.t);
    }

    /// Solves in place (`b` becomes `x`), allocation free.
    pub fn solve_in_place(&mut self, b: &mut [f64]) {
        let n = self.lr.n;
        let m = self.lr.rank();
        self.s.solve_in_place(b);
        for (j, t) in self.t.iter_mut().enumerate() {
            let col = &self.lr.u[j * n..(j + 1) * n];
            *t = col.iter().zip(b.iter()).map(|(a, c)| a * c).sum::<f64>();
        }
        crate::math::lu_solve(&self.cap, m, &self.piv, &mut self.t);
        for (j, t) in self.t.iter().enumerate() {
            let col = &self.y[j * n..(j + 1) * n];
            for (bi, yi) in b.iter_mut().zip(col) {
                *bi -= yi * t;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::tests::lap;

    #[test]
    fn woodbury_solves_sparse_plus_low_rank() {
        // S unsymmetric (a skew part like Ω G), plus a rank-2 dense term: compare with a solve
        // of the assembled matrix.
        let n = 7;
        let mut t: Vec<(usize, usize, f64)> = lap(n).triplets().collect();
        for i in 0..n - 1 {
            t.push((i, i + 1, 0.3));
            t.push((i + 1, i, -0.3));
        }
        let s = Csc::from_triplets(n, n, &t);
        let u: Vec<f64> = (0..2 * n)
            .map(|k| ((k * 7 % 5) as f64 - 2.0) * 0.4)
            .collect();
        let lr = LowRank {
            n,
            u,
            d: vec![1.5, 0.7],
        };
        let mut full = t.clone();
        full.extend(lr.triplets(1.0));
        let a = Csc::from_triplets(n, n, &full);
        let x: Vec<f64> = (0..n).map(|i| (i as f64).sin() + 1.0).collect();
        let mut b = vec![0.0; n];
        a.mul_add(1.0, &x, &mut b);
        // mul_add of the low-rank part agrees with its triplets.
        let mut y1 = vec![0.0; n];
        let mut scratch = vec![0.0; 2];
        lr.mul_add(2.0, &x, &mut y1, &mut scratch);
        let mut y2 = vec![0.0; n];
        Csc::from_triplets(n, n, &lr.triplets(2.0)).mul_add(1.0, &x, &mut y2);
        for i in 0..n {
            assert!((y1[i] - y2[i]).abs() < 1e-12);
        }
        let mut w = WoodburyLu::new(&s, lr).unwrap();
        w.solve_in_place(&mut b);
        for i in 0..n {
            assert!((b[i] - x[i]).abs() < 1e-12, "{i}: {} vs {}", b[i], x[i]);
        }
    }
}
