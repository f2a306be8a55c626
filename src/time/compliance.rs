//! A massless stator in the loop (Eq. 49): the compliance `K⁻¹` of its contact DOFs.

use crate::linalg::{Cholesky, CholeskyScratch, LinalgError};
use crate::model::stator::MeshStatorData;
use crate::model::StatorModel;
use std::sync::Arc;

/// Boundaries with at most this many contact DOFs are condensed up front (every column of
/// `K⁻¹` at the contact DOFs computed before the loop); larger ones column by column, the
/// first time a node enters a contact problem.
pub const EAGER_DOFS: usize = 32;

/// A massless stator condensed to its contact boundary (Eq. 49): the columns `K⁻¹ e_d` of the
/// contact DOFs `d`, kept only at the contact DOFs (`ncd` numbers each), from one sparse
/// Cholesky factor of K (shared by every run of a meshed stator). Small boundaries
/// (≤ [`EAGER_DOFS`] contact DOFs) get every column up front; larger ones get a column
/// the first time its DOF enters a contact problem, cached for the run. The loop's work is then
/// proportional to the contact DOFs, not to the mesh: only the contact entries of `u` are kept
/// current, and the full field is rebuilt by one solve when a frame asks for it
/// ([`Compliance::refresh`]).
#[derive(Debug)]
pub(crate) struct Compliance {
    chol: Option<Arc<Cholesky>>,
    /// Solve workspace of `chol` for one right-hand side (frames' field rebuilds), so a frame
    /// allocates nothing.
    scratch: Option<Box<CholeskyScratch>>,
    /// Contact DOFs, sorted.
    pub(crate) cd: Vec<usize>,
    /// Free DOF → index in `cd` (`usize::MAX` for interior DOFs).
    slot: Vec<usize>,
    /// Contact slot → start of its column in `cols` (`usize::MAX` until computed).
    col: Vec<usize>,
    /// Cached columns, `cd.len()` entries each (rows at the contact DOFs).
    cols: Vec<f64>,
    /// Force applied at each contact slot since the last reset (N).
    f: Vec<f64>,
    /// Scratch of length n for column solves and refreshes.
    rhs: Vec<f64>,
    /// Displacement (m): contact entries current, interior entries valid after `refresh`.
    pub(crate) u: Vec<f64>,
    /// A meshed stator's columns shared between its runs
    /// ([`MeshStatorData::compliance_columns`]): read at the start, written back at the end.
    shared: Option<Arc<MeshStatorData>>,
}

impl Drop for Compliance {
    /// Hands the columns computed to the stator's shared store when this run has more of them.
    fn drop(&mut self) {
        let Some(md) = &self.shared else { return };
        let mut g = md
            .compliance_columns
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner);
        let known = |c: &[usize]| c.iter().filter(|&&k| k != usize::MAX).count();
        if g.0.len() != self.col.len() || known(&self.col) > known(&g.0) {
            g.0 = std::mem::take(&mut self.col);
            g.1 = std::mem::take(&mut self.cols);
        }
    }
}

impl Compliance {
    pub(crate) fn new(s: &StatorModel) -> Result<Self, LinalgError> {
        let n = s.ndof;
        let cd = s.contact_dofs();
        let mut slot = vec![usize::MAX; n];
        for (j, &d) in cd.iter().enumerate() {
            slot[d] = j;
        }
        let chol = if n == 0 {
            None
        } else {
            Some(match &s.mesh {
                Some(md) => md.factor(&s.k)?,
                None => Arc::new(Cholesky::new(&s.k)?),
            })
        };
        let ncd = cd.len();
        let mut c = Self {
            scratch: chol.as_ref().map(|ch| Box::new(ch.solve_scratch(1))),
            chol,
            col: vec![usize::MAX; ncd],
            cols: Vec::with_capacity(ncd * ncd.min(EAGER_DOFS.max(16))),
            f: vec![0.0; ncd],
            rhs: vec![0.0; n],
            u: vec![0.0; n],
            cd,
            slot,
            shared: s.mesh.clone(),
        };
        if let Some(md) = &s.mesh {
            let g = md
                .compliance_columns
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner);
            if g.0.len() == ncd {
                c.col.clone_from(&g.0);
                c.cols.clone_from(&g.1);
            }
        }
        if ncd <= EAGER_DOFS && c.col.contains(&usize::MAX) {
            c.col.fill(usize::MAX);
            c.cols.clear();
            // One blocked solve for every column.
            let n = c.rhs.len();
            let mut block = vec![0.0; n * ncd];
            for (j, &d) in c.cd.iter().enumerate() {
                block[j * n + d] = 1.0;
            }
            if let Some(ch) = &c.chol {
                ch.solve_in_place(&mut block);
            }
            for j in 0..ncd {
                c.col[j] = c.cols.len();
                let col = &block[j * n..(j + 1) * n];
                let cd = &c.cd;
                c.cols.extend(cd.iter().map(|&e| col[e]));
            }
        }
        Ok(c)
    }
    /// Columns computed together when one is missing: the next missing contact DOFs in DOF
    /// order, which for a meshed boundary are its neighbours (one blocked solve is several
    /// times cheaper per column than single ones).
    const BATCH: usize = 16;

    /// Computes the column of contact DOF `d` (and a batch after it) if it is not cached yet.
    pub(crate) fn ensure(&mut self, d: usize) {
        let j = self.slot[d];
        if self.col[j] != usize::MAX {
            return;
        }
        let ncd = self.cd.len();
        let n = self.rhs.len();
        let batch: Vec<usize> = (0..ncd)
            .map(|k| (j + k) % ncd)
            .filter(|&s| self.col[s] == usize::MAX)
            .take(Self::BATCH)
            .collect();
        let mut block = vec![0.0; n * batch.len()];
        for (b, &s) in batch.iter().enumerate() {
            block[b * n + self.cd[s]] = 1.0;
        }
        if let Some(ch) = &self.chol {
            ch.solve_in_place(&mut block);
        }
        for (b, &s) in batch.iter().enumerate() {
            self.col[s] = self.cols.len();
            let c = &block[b * n..(b + 1) * n];
            self.cols.extend(self.cd.iter().map(|&e| c[e]));
        }
    }
    #[inline]
    pub(crate) fn flex(&self, a: usize, b: usize) -> f64 {
        let c = self.col[self.slot[b]];
        debug_assert!(c != usize::MAX, "compliance column of DOF {b} not prepared");
        self.cols[c + self.slot[a]]
    }
    #[inline]
    pub(crate) fn apply(&mut self, d: usize, f: f64) {
        self.ensure(d);
        let j = self.slot[d];
        self.f[j] += f;
        let c = &self.cols[self.col[j]..self.col[j] + self.cd.len()];
        for (&e, v) in self.cd.iter().zip(c) {
            self.u[e] += v * f;
        }
    }
    /// Undeformed: no contact force (Eq. 49).
    pub(crate) fn reset(&mut self) {
        for &e in &self.cd {
            self.u[e] = 0.0;
        }
        self.f.fill(0.0);
    }
    /// Rebuilds the whole displacement field from the contact forces (one solve).
    pub(crate) fn refresh(&mut self) {
        self.rhs.fill(0.0);
        for (&e, f) in self.cd.iter().zip(&self.f) {
            self.rhs[e] = *f;
        }
        if let (Some(ch), Some(s)) = (&self.chol, &mut self.scratch) {
            ch.solve_in_place_with(&mut self.rhs, s);
        }
        self.u.copy_from_slice(&self.rhs);
    }
}
