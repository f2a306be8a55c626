//! Sparse storage and the factorisations the models need, as a thin layer over `faer`.
//!
//! [`Csc`] is a compressed-sparse-column matrix owned by rubsim (pattern built once from
//! triplets, duplicates summed) with an allocation-free `y += α A x` for the time loop. The
//! factorisations convert to `faer` views without copying the pattern: sparse Cholesky for
//! symmetric positive definite stiffness (massless-stator condensation) and sparse LU for the
//! unsymmetric M̃ of rotors with gyroscopics.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{MatMut, Side};

/// Square or rectangular sparse matrix in compressed sparse column form.
#[derive(Debug, Clone, PartialEq)]
pub struct Csc {
    nrows: usize,
    ncols: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    val: Vec<f64>,
}

impl Csc {
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

    fn faer_ref(&self) -> SparseColMatRef<'_, usize, f64> {
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

    /// `y += A x + B z`, allocation free.
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

/// Sparse Cholesky factor `A = L Lᵀ` of a symmetric positive definite matrix.
///
/// Factored with faer's global parallelism; solved sequentially: the solves run inside the
/// time loop (massless-stator compliance columns) and inside parallel sweeps, where threads
/// of a parallel triangular solve only wait for each other.
pub struct Cholesky {
    n: usize,
    symbolic: faer::sparse::linalg::cholesky::SymbolicCholesky<usize>,
    values: Vec<f64>,
}

impl std::fmt::Debug for Cholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Cholesky(n = {})", self.n)
    }
}

impl Cholesky {
    /// Factors `a` (both triangles stored; only the lower one is read).
    pub fn new(a: &Csc) -> Result<Self, String> {
        use faer::dyn_stack::{MemBuffer, MemStack};
        use faer::sparse::linalg::cholesky::factorize_symbolic_cholesky;
        assert_eq!(a.nrows, a.ncols);
        let r = a.faer_ref();
        let symbolic = factorize_symbolic_cholesky(
            r.symbolic(),
            Side::Lower,
            Default::default(),
            Default::default(),
        )
        .map_err(|e| format!("{e:?}"))?;
        let mut values = vec![0.0; symbolic.len_val()];
        let par = faer::get_global_parallelism();
        let mut mem =
            MemBuffer::new(symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()));
        symbolic
            .factorize_numeric_llt(
                &mut values,
                r,
                Side::Lower,
                Default::default(),
                par,
                MemStack::new(&mut mem),
                Default::default(),
            )
            .map_err(|e| format!("{e:?}"))?;
        Ok(Self {
            n: a.nrows,
            symbolic,
            values,
        })
    }

    /// Solves `A X = B` in place for a column-major `n×k` block `b` (k = b.len()/n),
    /// sequentially.
    pub fn solve_in_place(&self, b: &mut [f64]) {
        use faer::dyn_stack::{MemBuffer, MemStack};
        use faer::sparse::linalg::cholesky::LltRef;
        solve_block(self.n, b, |m| {
            let k = m.ncols();
            let par = faer::Par::Seq;
            let mut mem = MemBuffer::new(self.symbolic.solve_in_place_scratch::<f64>(k, par));
            LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
                faer::Conj::No,
                m,
                par,
                MemStack::new(&mut mem),
            );
        });
    }
}

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
    pub fn new(a: &Csc) -> Result<Self, String> {
        assert_eq!(a.nrows, a.ncols);
        let lu = a.faer_ref().sp_lu().map_err(|e| format!("{e:?}"))?;
        Ok(Self { n: a.nrows, lu })
    }

    /// Solves `A X = B` in place for a column-major `n×k` block `b`.
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
    pub fn new(a: &Csc) -> Result<Self, String> {
        use faer::dyn_stack::{MemBuffer, MemStack};
        use faer::sparse::linalg::lu::{factorize_symbolic_lu, NumericLu};
        assert_eq!(a.nrows, a.ncols);
        let r = a.faer_ref();
        let symbolic = factorize_symbolic_lu(r.symbolic(), Default::default())
            .map_err(|e| format!("{e:?}"))?;
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
            .map_err(|e| format!("{e:?}"))?;
        let scratch = MemBuffer::new(symbolic.solve_in_place_scratch::<f64>(1, par));
        Ok(Self {
            n: a.nrows,
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
    pub fn new(s: &Csc, lr: LowRank) -> Result<Self, String> {
        let n = s.nrows;
        assert_eq!(lr.n, n, "low-rank term of another size");
        if let Some(k) = lr.d.iter().position(|v| *v == 0.0 || !v.is_finite()) {
            return Err(format!("low-rank term {k} has d = {}", lr.d[k]));
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
            return Err("the Woodbury capacitance matrix is singular".into());
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

impl BlockTridiag {
    /// Factors `a` when it is block tridiagonal in 4 × 4 node blocks (`n` a multiple of 4, no
    /// entry between nodes more than one apart); `Ok(None)` when it is not, `Err` on a
    /// singular pivot block.
    pub fn new(a: &Csc) -> Result<Option<Self>, String> {
        let n = a.nrows;
        if n == 0 || n % NODE_BLOCK != 0 || a.ncols != n {
            return Ok(None);
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
                return Ok(None);
            }
        }
        let tiny = 1e-13 * scale;
        let mut dinv = vec![zero; nb];
        for b in 0..nb {
            let mut d = diag[b];
            if b > 0 {
                // Lᵦ = Aᵦ,ᵦ₋₁ Dᵦ₋₁⁻¹, Dᵦ = Aᵦᵦ − Lᵦ Aᵦ₋₁,ᵦ.
                lower[b] = blk_mul(&lower[b], &dinv[b - 1]);
                let lu = blk_mul(&lower[b], &upper[b - 1]);
                for i in 0..NODE_BLOCK {
                    for j in 0..NODE_BLOCK {
                        d[i][j] -= lu[i][j];
                    }
                }
            }
            dinv[b] = blk_inv(&d, tiny)
                .ok_or_else(|| format!("singular pivot block at node {b} of the block LU"))?;
        }
        Ok(Some(Self {
            nb,
            dinv,
            lower,
            upper,
        }))
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

fn solve_block(n: usize, b: &mut [f64], f: impl FnOnce(MatMut<'_, f64>)) {
    if n == 0 {
        return;
    }
    assert_eq!(b.len() % n, 0, "right-hand side is not a multiple of n");
    let k = b.len() / n;
    let m = MatMut::from_column_major_slice_mut(b, n, k);
    f(m);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lap(n: usize) -> Csc {
        let mut t = Vec::new();
        for i in 0..n {
            t.push((i, i, 2.0));
            if i + 1 < n {
                t.push((i, i + 1, -1.0));
                t.push((i + 1, i, -1.0));
            }
        }
        Csc::from_triplets(n, n, &t)
    }

    #[test]
    fn duplicates_are_summed_and_matvec_is_right() {
        let a = Csc::from_triplets(2, 2, &[(0, 0, 1.0), (0, 0, 2.0), (1, 0, 4.0)]);
        assert_eq!(a.nnz(), 2);
        let mut y = [0.0; 2];
        a.mul_add(2.0, &[1.0, 5.0], &mut y);
        assert_eq!(y, [6.0, 8.0]);
    }

    #[test]
    fn cholesky_and_lu_solve_laplacian() {
        let n = 6;
        let a = lap(n);
        let x: Vec<f64> = (0..n).map(|i| i as f64 + 1.0).collect();
        let mut b = vec![0.0; n];
        a.mul_add(1.0, &x, &mut b);
        let mut b1 = b.clone();
        Cholesky::new(&a).unwrap().solve_in_place(&mut b1);
        let mut b2 = b.clone();
        Lu::new(&a).unwrap().solve_in_place(&mut b2);
        for i in 0..n {
            assert!((b1[i] - x[i]).abs() < 1e-12);
            assert!((b2[i] - x[i]).abs() < 1e-12);
        }
    }

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

    #[test]
    fn cholesky_rejects_indefinite() {
        let a = Csc::from_triplets(2, 2, &[(0, 0, 1.0), (1, 1, -1.0)]);
        assert!(Cholesky::new(&a).is_err());
    }
}
