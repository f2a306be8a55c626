//! A massless stator in the loop (Eq. 49): the compliance `K⁻¹` of its contact DOFs.

use crate::linalg::{Cholesky, CholeskyScratch, LinalgError};
use crate::model::stator::{ContactColumns, MeshStatorData};
use crate::model::StatorModel;
use std::cell::Cell;
use std::sync::Arc;

/// Boundaries with at most this many contact DOFs are condensed up front (every column of
/// `K⁻¹` at the contact DOFs computed before the loop); larger ones column by column, the
/// first time a node enters a contact problem.
pub const EAGER_DOFS: usize = 32;

/// A massless stator condensed to the contact DOFs that touch (Eq. 49): `u = F f` with
/// `F = K⁻¹` and `f` the contact forces (N) applied since the stator was last undeformed, from
/// one sparse Cholesky factor of K (shared by every run of a meshed stator).
///
/// What a step costs is what its contact problem holds, not the mesh nor the boundary:
/// - `F` is kept only among the contact DOFs that have entered a contact problem
///   ([`ContactColumns`], packed symmetric): a DOF's column is computed by a blocked solve the
///   first time it is prepared ([`Compliance::ensure`]; small boundaries, ≤ [`EAGER_DOFS`]
///   contact DOFs, all up front) and kept for the stator's later runs;
/// - the forces are a short list (one entry per DOF pushed); applying one is O(1), undeforming
///   the stator is O(forces), and the displacement of a DOF ([`Compliance::disp_at`]) is
///   `Σ_k F[d, d_k] f_k` over that list;
/// - the whole field is rebuilt by one solve only when a frame asks for it
///   ([`Compliance::refresh`]).
#[derive(Debug)]
pub(crate) struct Compliance {
    chol: Option<Arc<Cholesky>>,
    /// Solve workspace of `chol` for one right-hand side (frames' field rebuilds), so a frame
    /// allocates nothing.
    scratch: Option<Box<CholeskyScratch>>,
    /// Contact DOFs, sorted.
    cd: Vec<usize>,
    /// Free DOF → index in `cd` (`usize::MAX` for interior DOFs).
    slot: Vec<usize>,
    /// Contact slot → index of its DOF in `cols.touched` (`usize::MAX` until computed).
    loc: Vec<usize>,
    /// Contact slots in the order of their targets' angle around the rotor axis (then DOF),
    /// and each slot's position in it: a batch of columns is the missing slots that follow the
    /// one asked for, the targets next to it, so the selected pairs of a contact zone sit
    /// close together in the packed compliance.
    around: Vec<usize>,
    around_pos: Vec<usize>,
    /// The columns computed so far (this run's and the earlier runs').
    cols: ContactColumns,
    /// Per touched index `j`: block of its column and the column's start in it.
    start: Vec<(usize, usize)>,
    /// Forces applied since the last reset: (touched index, DOF, force in N), one entry per DOF.
    forces: Vec<(usize, usize, f64)>,
    /// Touched index → position in `forces` (`usize::MAX`: no force there).
    fpos: Vec<usize>,
    /// Entries of `F` read by the loop (flexibilities and displacements), the work counter of
    /// [`super::RunStats::stator_reads`]; column solves and frames not counted.
    reads: Cell<u64>,
    /// Scratch of length n for refreshes.
    rhs: Vec<f64>,
    /// The whole displacement field (m), valid after [`Compliance::refresh`] only.
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
        if self.cols.touched.len() > g.touched.len() {
            *g = std::mem::take(&mut self.cols);
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
        let mut angle = vec![0.0_f64; ncd];
        for tg in &s.targets {
            if let crate::contact::Target::Node { x0, dofs, .. } = tg {
                for d in dofs.iter().flatten() {
                    angle[slot[*d]] = x0[1].atan2(x0[0]);
                }
            }
        }
        let mut around: Vec<usize> = (0..ncd).collect();
        around.sort_by(|&a, &b| angle[a].total_cmp(&angle[b]).then(a.cmp(&b)));
        let mut around_pos = vec![0; ncd];
        for (k, &j) in around.iter().enumerate() {
            around_pos[j] = k;
        }
        let mut c = Self {
            around,
            around_pos,
            scratch: chol.as_ref().map(|ch| Box::new(ch.solve_scratch(1))),
            chol,
            loc: vec![usize::MAX; ncd],
            cols: ContactColumns::default(),
            start: Vec::new(),
            forces: Vec::new(),
            fpos: Vec::new(),
            reads: Cell::new(0),
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
            c.adopt(&g);
        }
        if ncd <= EAGER_DOFS && c.loc.contains(&usize::MAX) {
            c.compute(
                &(0..ncd)
                    .filter(|&j| c.loc[j] == usize::MAX)
                    .collect::<Vec<_>>(),
            );
        }
        Ok(c)
    }

    /// Starts from the columns earlier runs computed (blocks shared, not copied).
    fn adopt(&mut self, store: &ContactColumns) {
        let contact = |d: usize| self.slot.get(d).is_some_and(|&s| s != usize::MAX);
        if !store.touched.iter().all(|&d| contact(d)) {
            return;
        }
        let mut j = 0;
        for (b, blk) in store.blocks.iter().enumerate() {
            let mut off = 0;
            while off < blk.len() {
                self.start.push((b, off));
                off += j + 1;
                j += 1;
            }
        }
        if j != store.touched.len() {
            self.start.clear();
            return;
        }
        for (k, &d) in store.touched.iter().enumerate() {
            self.loc[self.slot[d]] = k;
        }
        self.fpos = vec![usize::MAX; j];
        self.cols = store.clone();
    }

    /// Columns computed together when one is missing: the next missing contact DOFs around
    /// the axis, its neighbours on the boundary (one blocked solve is several times cheaper
    /// per column than single ones).
    const BATCH: usize = 16;

    /// Computes the column of contact DOF `d` (and a batch after it) if it is not known yet.
    #[inline]
    pub(crate) fn ensure(&mut self, d: usize) {
        let j = self.slot[d];
        if self.loc[j] == usize::MAX {
            self.ensure_slow(j);
        }
    }

    #[cold]
    fn ensure_slow(&mut self, j: usize) {
        let ncd = self.cd.len();
        let at = self.around_pos[j];
        let batch: Vec<usize> = (0..ncd)
            .map(|k| self.around[(at + k) % ncd])
            .filter(|&s| self.loc[s] == usize::MAX)
            .take(Self::BATCH)
            .collect();
        self.compute(&batch);
    }

    /// One blocked solve for the contact slots `batch` (none known yet): their columns packed
    /// after the known ones, rows at every touched DOF up to their own.
    fn compute(&mut self, batch: &[usize]) {
        if batch.is_empty() {
            return;
        }
        let n = self.rhs.len();
        let mut block = vec![0.0; n * batch.len()];
        for (b, &s) in batch.iter().enumerate() {
            block[b * n + self.cd[s]] = 1.0;
        }
        if let Some(ch) = &self.chol {
            ch.solve_in_place(&mut block);
        }
        let m = self.cols.touched.len();
        for &s in batch {
            self.cols.touched.push(self.cd[s]);
        }
        let bi = self.cols.blocks.len();
        let mut packed = Vec::with_capacity(batch.len() * (m + batch.len()));
        for (b, &s) in batch.iter().enumerate() {
            self.loc[s] = m + b;
            self.start.push((bi, packed.len()));
            let x = &block[b * n..(b + 1) * n];
            packed.extend(self.cols.touched[..=m + b].iter().map(|&e| x[e]));
        }
        self.cols.blocks.push(packed.into());
        self.fpos.resize(m + batch.len(), usize::MAX);
    }

    /// `F[i, j]` by touched indices.
    #[inline]
    fn entry(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        let (b, off) = self.start[j];
        self.cols.blocks[b][off + i]
    }

    /// `F[a, b]` (m/N) of two prepared contact DOFs.
    #[inline]
    pub(crate) fn flex(&self, a: usize, b: usize) -> f64 {
        let (la, lb) = (self.loc[self.slot[a]], self.loc[self.slot[b]]);
        debug_assert!(
            la != usize::MAX && lb != usize::MAX,
            "compliance of DOFs {a}, {b} not prepared"
        );
        self.entry_read(la, lb)
    }

    /// The positions of a prepared target's DOFs in the packed compliance (`usize::MAX` for a
    /// DOF it does not have).
    #[inline]
    pub(crate) fn locs(&self, dofs: [Option<usize>; 2]) -> [usize; 2] {
        dofs.map(|d| d.map_or(usize::MAX, |d| self.loc[self.slot[d]]))
    }

    /// `F[i, j]` by positions in the packed compliance ([`Compliance::locs`]), counted as read.
    #[inline]
    pub(crate) fn entry_read(&self, i: usize, j: usize) -> f64 {
        self.reads.set(self.reads.get() + 1);
        self.entry(i, j)
    }

    /// Displacement of contact DOF `d` (m): `Σ_k F[d, d_k] f_k` over the forces applied since
    /// the last reset (0 without any; `d` must be prepared otherwise).
    #[inline]
    pub(crate) fn disp_at(&self, d: usize) -> f64 {
        if self.forces.is_empty() {
            return 0.0;
        }
        let l = self.slot.get(d).and_then(|&s| self.loc.get(s)).copied();
        let Some(l) = l.filter(|&l| l != usize::MAX) else {
            debug_assert!(false, "displacement of DOF {d} not prepared");
            return 0.0;
        };
        self.reads.set(self.reads.get() + self.forces.len() as u64);
        self.forces
            .iter()
            .map(|&(k, _, f)| self.entry(l, k) * f)
            .sum()
    }

    /// Adds the force `f` (N) at contact DOF `d` (prepared by [`Compliance::ensure`] here).
    #[inline]
    pub(crate) fn apply(&mut self, d: usize, f: f64) {
        self.ensure(d);
        let l = self.loc[self.slot[d]];
        match self.fpos[l] {
            usize::MAX => {
                self.fpos[l] = self.forces.len();
                self.forces.push((l, d, f));
            }
            k => self.forces[k].2 += f,
        }
    }

    /// Undeformed: no contact force (Eq. 49).
    #[inline]
    pub(crate) fn reset(&mut self) {
        for &(l, _, _) in &self.forces {
            self.fpos[l] = usize::MAX;
        }
        self.forces.clear();
    }

    /// The first DOF whose force is not finite (the displacement is finite where the forces
    /// are: the columns are).
    pub(crate) fn first_non_finite(&self) -> Option<usize> {
        self.forces
            .iter()
            .find(|(_, _, f)| !f.is_finite())
            .map(|&(_, d, _)| d)
    }

    /// Entries of `F` the loop has read so far.
    pub(crate) fn reads(&self) -> u64 {
        self.reads.get()
    }

    /// Rebuilds the whole displacement field `u` from the contact forces (one solve).
    pub(crate) fn refresh(&mut self) {
        self.rhs.fill(0.0);
        for &(_, d, f) in &self.forces {
            self.rhs[d] += f;
        }
        if let (Some(ch), Some(s)) = (&self.chol, &mut self.scratch) {
            ch.solve_in_place_with(&mut self.rhs, s);
        }
        self.u.copy_from_slice(&self.rhs);
    }
}
