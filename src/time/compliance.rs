//! A massless stator in the loop (Eq. 49): the compliance `K⁻¹` of its contact DOFs.

use crate::linalg::{Cholesky, CholeskyScratch, LinalgError};
use crate::model::stator::{ContactColumns, MeshStatorData, NodeBlock};
use crate::model::StatorModel;
use std::cell::Cell;
use std::sync::Arc;

/// Boundaries with at most this many contact DOFs are condensed up front (every column of
/// `K⁻¹` at the contact DOFs computed before the loop); larger ones column by column, the
/// first time a node enters a contact problem.
pub const EAGER_DOFS: usize = 32;

/// Factors of K with at least this many entries (4 MB) compute the compliance columns from
/// forward solves on elimination-tree paths ([`crate::linalg::Cholesky::path_columns`]: the
/// entries among the touched nodes as products of forward solutions; the shipped seal's
/// columns in 0.73 s instead of 1.94 s, the 10⁶-DOF seal's in about a minute instead of 40);
/// smaller ones, whose columns cost little either way, by blocked full solves. The two agree
/// to round-off (docs/PERFORMANCE.md §12.3).
pub const PATH_COLUMNS_NNZ: usize = 500_000;

/// What a massless stator's compliance columns cost when they come from elimination-tree
/// paths (its factor built, with at least [`PATH_COLUMNS_NNZ`] entries and supernodal), every
/// contact DOF counted; `None` when they come from full solves.
pub fn path_cost(s: &StatorModel) -> Option<crate::linalg::PathCost> {
    s.built_factor()
        .filter(|f| f.nnz() >= PATH_COLUMNS_NNZ)
        .and_then(|f| f.path_cost(&s.contact_dofs()))
}

/// A massless stator condensed to the contact DOFs that touch (Eq. 49): `u = F f` with
/// `F = K⁻¹` and `f` the contact forces (N) applied since the stator was last undeformed, from
/// one sparse Cholesky factor of K (shared by every run of a meshed stator).
///
/// What a step costs is what its contact problem holds, not the mesh nor the boundary:
/// - `F` is kept only among the contact nodes (a target's two DOFs) that have entered a
///   contact problem ([`ContactColumns`], packed symmetric by 2 × 2 node blocks, so the block
///   of two targets is one read from one cache line): a node's columns are computed by a
///   blocked solve the first time it is prepared ([`Compliance::ensure`]; small boundaries,
///   ≤ [`EAGER_DOFS`] contact DOFs, all up front) and kept for the stator's later runs;
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
    /// Contact nodes: the DOFs of each (`usize::MAX` for a component it does not have), in
    /// the order of the targets that have them.
    nodes: Vec<[usize; 2]>,
    /// Free DOF → its position `2·node + component` among the contact nodes (`usize::MAX` for
    /// interior DOFs).
    slot: Vec<usize>,
    /// Contact node → its index in `cols.touched` (`usize::MAX` until computed).
    loc: Vec<usize>,
    /// Contact nodes in the order of their targets' angle around the rotor axis (then index),
    /// and each node's position in it: a batch of columns is the missing nodes that follow the
    /// one asked for, the targets next to it, so the selected pairs of a contact zone sit
    /// close together in the packed compliance.
    around: Vec<usize>,
    around_pos: Vec<usize>,
    /// The columns computed so far (this run's and the earlier runs').
    cols: ContactColumns,
    /// Per touched node `j`: block of its node column and the column's start in it.
    start: Vec<(usize, usize)>,
    /// Forces applied since the last reset: (touched position `2·j + component`, DOF, force in
    /// N), one entry per DOF.
    forces: Vec<(usize, usize, f64)>,
    /// The forces of the last solve before the last reset (the displacement at the step's
    /// start, which a pair's stick measures its slip from).
    last: Vec<(usize, usize, f64)>,
    /// Touched position → index in `forces` (`usize::MAX`: no force there).
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
    /// Columns from forward solves on elimination-tree paths ([`PATH_COLUMNS_NNZ`]) instead of
    /// full solves.
    paths: bool,
    /// Columns this compliance computed and their wall time (s).
    computed: (u64, f64),
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
        Self::with_columns(s, None)
    }

    /// As [`Compliance::new`]; `paths` forces the columns' method (`None`: path solves for
    /// factors of at least [`PATH_COLUMNS_NNZ`] entries with a supernodal tree).
    pub(crate) fn with_columns(s: &StatorModel, paths: Option<bool>) -> Result<Self, LinalgError> {
        let n = s.ndof;
        let (nodes, slot, angle) = contact_nodes(s);
        let chol = if n == 0 {
            None
        } else {
            Some(match &s.mesh {
                Some(md) => md.factor(&s.k)?,
                None => Arc::new(Cholesky::new(&s.k)?),
            })
        };
        let nn = nodes.len();
        let mut around: Vec<usize> = (0..nn).collect();
        around.sort_by(|&a, &b| angle[a].total_cmp(&angle[b]).then(a.cmp(&b)));
        let mut around_pos = vec![0; nn];
        for (k, &j) in around.iter().enumerate() {
            around_pos[j] = k;
        }
        let ncd = slot.iter().filter(|&&p| p != usize::MAX).count();
        let paths = chol.as_ref().is_some_and(|ch| {
            paths.unwrap_or(ch.nnz() >= PATH_COLUMNS_NNZ) && ch.path_tree().is_some()
        });
        let mut c = Self {
            paths,
            computed: (0, 0.0),
            around,
            around_pos,
            scratch: chol.as_ref().map(|ch| Box::new(ch.solve_scratch(1))),
            chol,
            loc: vec![usize::MAX; nn],
            cols: ContactColumns::default(),
            start: Vec::new(),
            forces: Vec::new(),
            last: Vec::new(),
            fpos: Vec::new(),
            reads: Cell::new(0),
            rhs: vec![0.0; n],
            u: vec![0.0; n],
            nodes,
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
                &(0..nn)
                    .filter(|&j| c.loc[j] == usize::MAX)
                    .collect::<Vec<_>>(),
            );
        }
        Ok(c)
    }

    /// Starts from the columns earlier runs computed (blocks shared, not copied).
    fn adopt(&mut self, store: &ContactColumns) {
        let node_of = |pair: &[usize; 2]| {
            let d = pair.iter().find(|&&d| d != usize::MAX)?;
            let p = *self.slot.get(*d)?;
            (p != usize::MAX && self.nodes[p / 2] == *pair).then_some(p / 2)
        };
        let Some(found) = store
            .touched
            .iter()
            .map(node_of)
            .collect::<Option<Vec<_>>>()
        else {
            return;
        };
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
        for (k, &node) in found.iter().enumerate() {
            self.loc[node] = k;
        }
        self.fpos = vec![usize::MAX; 2 * j];
        self.cols = store.clone();
    }

    /// Nodes computed together when one is missing: the next missing contact nodes around
    /// the axis, its neighbours on the boundary (one blocked solve is several times cheaper
    /// per column than single ones; 16 columns of two-DOF nodes).
    const BATCH: usize = 8;

    /// Nodes computed together from elimination-tree paths: each batch's products read every
    /// stored forward solution once, so batches as wide as [`crate::linalg::PATH_BATCH`]
    /// columns allow (on the 10⁶-DOF seal, 32 nodes a batch: the run's columns in about a
    /// quarter of the memory traffic of 8).
    const PATH_NODES: usize = crate::linalg::PATH_BATCH / 2;

    /// Computes the columns of contact DOF `d`'s node (and a batch after it) if they are not
    /// known yet.
    #[inline]
    pub(crate) fn ensure(&mut self, d: usize) {
        let node = self.slot[d] / 2;
        if self.loc[node] == usize::MAX {
            self.ensure_slow(node);
        }
    }

    #[cold]
    fn ensure_slow(&mut self, node: usize) {
        let nn = self.nodes.len();
        let at = self.around_pos[node];
        let batch: Vec<usize> = (0..nn)
            .map(|k| self.around[(at + k) % nn])
            .filter(|&s| self.loc[s] == usize::MAX)
            .take(if self.paths {
                Self::PATH_NODES
            } else {
                Self::BATCH
            })
            .collect();
        self.compute(&batch);
    }

    /// One blocked solve for the contact nodes `batch` (none known yet): their node columns
    /// packed after the known ones, blocks with every touched node up to their own.
    fn compute(&mut self, batch: &[usize]) {
        if batch.is_empty() {
            return;
        }
        let t0 = std::time::Instant::now();
        let (col, dofs) = self.solve_columns(batch);
        if !(self.paths && self.compute_from_paths(batch, &col, &dofs)) {
            self.compute_from_solves(batch, &col, &dofs);
        }
        self.computed.0 += dofs.len() as u64;
        self.computed.1 += t0.elapsed().as_secs_f64();
    }

    /// Columns this compliance computed (not adopted from earlier runs) and their wall time (s).
    pub(crate) fn columns_computed(&self) -> (u64, f64) {
        self.computed
    }

    /// The columns of `batch` (its [`Compliance::solve_columns`] `col` and `dofs`) by one
    /// blocked full solve.
    fn compute_from_solves(&mut self, batch: &[usize], col: &[[usize; 2]], dofs: &[usize]) {
        let n = self.rhs.len();
        let mut block = vec![0.0; n * dofs.len()];
        for (c, &d) in dofs.iter().enumerate() {
            block[c * n + d] = 1.0;
        }
        if let Some(ch) = &self.chol {
            ch.solve_in_place(&mut block);
        }
        self.pack(batch, col, |k, _, r| block[k * n + r]);
    }

    /// The solve columns of `batch`'s nodes: each node's column per component (`usize::MAX`
    /// for one it does not have) and the DOF of each column, nodes in order.
    fn solve_columns(&self, batch: &[usize]) -> (Vec<[usize; 2]>, Vec<usize>) {
        let mut col = vec![[usize::MAX; 2]; batch.len()];
        let mut dofs = Vec::new();
        for (cb, &s) in col.iter_mut().zip(batch) {
            for (c, &d) in cb.iter_mut().zip(&self.nodes[s]) {
                if d != usize::MAX {
                    *c = dofs.len();
                    dofs.push(d);
                }
            }
        }
        (col, dofs)
    }

    /// Appends the node columns of `batch` (solve column `col[b][c]` of its node `b`'s
    /// component `c`) after the touched nodes: `value(k, p, r)` is the entry of solve column
    /// `k` at touched position `p = 2·node + component`, DOF `r`.
    fn pack(
        &mut self,
        batch: &[usize],
        col: &[[usize; 2]],
        value: impl Fn(usize, usize, usize) -> f64,
    ) {
        let m = self.cols.touched.len();
        for &s in batch {
            self.cols.touched.push(self.nodes[s]);
        }
        let bi = self.cols.blocks.len();
        let mut packed = Vec::with_capacity(batch.len() * (m + batch.len()));
        for (b, &s) in batch.iter().enumerate() {
            self.loc[s] = m + b;
            self.start.push((bi, packed.len()));
            packed.extend(
                self.cols.touched[..=m + b]
                    .iter()
                    .enumerate()
                    .map(|(t, rows)| {
                        let mut f = NodeBlock::default();
                        for (a, &r) in rows.iter().enumerate() {
                            for (c, &k) in col[b].iter().enumerate() {
                                if r != usize::MAX && k != usize::MAX {
                                    f.0[a][c] = value(k, 2 * t + a, r);
                                }
                            }
                        }
                        f
                    }),
            );
        }
        self.cols.blocks.push(packed.into());
        self.fpos.resize(2 * (m + batch.len()), usize::MAX);
    }

    /// The columns of `batch` (its [`Compliance::solve_columns`] `col` and `dofs`) from forward
    /// solves on their elimination-tree paths
    /// ([`crate::linalg::Cholesky::path_columns`]): the entries with every touched node as
    /// products of the stored forward solutions. `false` (nothing done) if the factor cannot.
    fn compute_from_paths(&mut self, batch: &[usize], col: &[[usize; 2]], dofs: &[usize]) -> bool {
        let Some(ch) = &self.chol else { return false };
        let m = self.cols.touched.len();
        let rows = 2 * (m + batch.len());
        let labels: Vec<u32> = col
            .iter()
            .enumerate()
            .flat_map(|(b, cb)| {
                (0..2)
                    .filter(|&a| cb[a] != usize::MAX)
                    .map(move |a| u32::try_from(2 * (m + b) + a).unwrap_or(u32::MAX))
            })
            .collect();
        if dofs.len() > crate::linalg::PATH_BATCH || rows > u32::MAX as usize {
            return false;
        }
        let Some(f) = ch.path_columns(&mut self.cols.paths, dofs, &labels, rows) else {
            return false;
        };
        self.pack(batch, col, |k, p, _| f[p + k * rows]);
        true
    }

    /// The node block of touched nodes `i ≤ j`.
    #[inline]
    fn node_block(&self, i: usize, j: usize) -> &NodeBlock {
        let (b, off) = self.start[j];
        &self.cols.blocks[b][off + i]
    }

    /// `F[p, q]` by touched positions (`2·node + component`).
    #[inline]
    fn entry(&self, p: usize, q: usize) -> f64 {
        let (i, a, j, b) = (p / 2, p % 2, q / 2, q % 2);
        if i <= j {
            self.node_block(i, j).0[a][b]
        } else {
            self.node_block(j, i).0[b][a]
        }
    }

    /// `F[a, b]` (m/N) of two prepared contact DOFs.
    #[inline]
    pub(crate) fn flex(&self, a: usize, b: usize) -> f64 {
        let [la] = self.locs_of([a]);
        let [lb] = self.locs_of([b]);
        debug_assert!(
            la != usize::MAX && lb != usize::MAX,
            "compliance of DOFs {a}, {b} not prepared"
        );
        self.entry_read(la, lb)
    }

    /// Touched positions of prepared contact DOFs (`usize::MAX` for one not prepared).
    #[inline]
    fn locs_of<const K: usize>(&self, dofs: [usize; K]) -> [usize; K] {
        dofs.map(|d| {
            let p = self.slot[d];
            match self.loc[p / 2] {
                usize::MAX => usize::MAX,
                j => 2 * j + p % 2,
            }
        })
    }

    /// The positions of a prepared target's DOFs in the packed compliance (`usize::MAX` for a
    /// DOF it does not have).
    #[inline]
    pub(crate) fn locs(&self, dofs: [Option<usize>; 2]) -> [usize; 2] {
        dofs.map(|d| d.map_or(usize::MAX, |d| self.locs_of([d])[0]))
    }

    /// `F[i, j]` by positions in the packed compliance ([`Compliance::locs`]), counted as read.
    #[inline]
    pub(crate) fn entry_read(&self, i: usize, j: usize) -> f64 {
        self.reads.set(self.reads.get() + 1);
        self.entry(i, j)
    }

    /// The 2 × 2 block between two prepared targets by their [`Compliance::locs`] (0 for a
    /// DOF a target does not have), its entries counted as read: one node block when both
    /// targets are whole nodes.
    #[inline]
    pub(crate) fn block_read(&self, ki: [usize; 2], kj: [usize; 2]) -> [[f64; 2]; 2] {
        let whole = |k: [usize; 2]| k[0].is_multiple_of(2) && k[1] == k[0] + 1;
        if whole(ki) && whole(kj) {
            self.reads.set(self.reads.get() + 4);
            let (i, j) = (ki[0] / 2, kj[0] / 2);
            if i <= j {
                return self.node_block(i, j).0;
            }
            let f = self.node_block(j, i).0;
            return [[f[0][0], f[1][0]], [f[0][1], f[1][1]]];
        }
        let mut f = [[0.0; 2]; 2];
        for a in 0..2 {
            for b in 0..2 {
                if ki[a] != usize::MAX && kj[b] != usize::MAX {
                    f[a][b] = self.entry_read(ki[a], kj[b]);
                }
            }
        }
        f
    }

    /// Displacement of contact DOF `d` (m): `Σ_k F[d, d_k] f_k` over the forces applied since
    /// the last reset (0 without any; `d` must be prepared otherwise).
    #[inline]
    pub(crate) fn disp_at(&self, d: usize) -> f64 {
        if self.forces.is_empty() {
            return 0.0;
        }
        let contact = self.slot.get(d).is_some_and(|&p| p != usize::MAX);
        let l = if contact {
            self.locs_of([d])[0]
        } else {
            usize::MAX
        };
        if l == usize::MAX {
            debug_assert!(false, "displacement of DOF {d} not prepared");
            return 0.0;
        }
        self.reads.set(self.reads.get() + self.forces.len() as u64);
        self.forces
            .iter()
            .map(|&(k, _, f)| self.entry(l, k) * f)
            .sum()
    }

    /// Displacement of prepared contact DOF `d` (m) under the forces before the last reset: the
    /// stator's displacement at the start of the step (0 without any).
    pub(crate) fn disp_before(&self, d: usize) -> f64 {
        let [l] = self.locs_of([d]);
        if l == usize::MAX {
            return 0.0;
        }
        self.last
            .iter()
            .map(|&(k, _, f)| self.entry(l, k) * f)
            .sum()
    }

    /// Adds the force `f` (N) at contact DOF `d` (prepared by [`Compliance::ensure`] here).
    #[inline]
    pub(crate) fn apply(&mut self, d: usize, f: f64) {
        self.ensure(d);
        let [l] = self.locs_of([d]);
        match self.fpos[l] {
            usize::MAX => {
                self.fpos[l] = self.forces.len();
                self.forces.push((l, d, f));
            }
            k => self.forces[k].2 += f,
        }
    }

    /// The forces applied since the last reset taken off, the forces before it kept (a trial
    /// solve undone: `time::stepper::tangent`).
    pub(crate) fn discard(&mut self) {
        for &(l, _, _) in &self.forces {
            self.fpos[l] = usize::MAX;
        }
        self.forces.clear();
    }

    /// Undeformed: no contact force (Eq. 49).
    #[inline]
    pub(crate) fn reset(&mut self) {
        for &(l, _, _) in &self.forces {
            self.fpos[l] = usize::MAX;
        }
        self.last.clear();
        self.last.extend_from_slice(&self.forces);
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

/// A stator's contact nodes (each target's free DOFs not in an earlier target's node, as one
/// node: `usize::MAX` for a component it does not have), each free DOF's position
/// `2·node + component` (`usize::MAX` for interior DOFs) and each node's angle around the
/// rotor axis (rad; 0 for a ring target).
fn contact_nodes(s: &StatorModel) -> (Vec<[usize; 2]>, Vec<usize>, Vec<f64>) {
    let mut slot = vec![usize::MAX; s.ndof];
    let (mut nodes, mut angle) = (Vec::new(), Vec::new());
    for tg in &s.targets {
        let mut node = [usize::MAX; 2];
        for (a, d) in tg.dofs().iter().enumerate() {
            if let Some(d) = d.filter(|&d| slot[d] == usize::MAX) {
                node[a] = d;
                slot[d] = 2 * nodes.len() + a;
            }
        }
        if node != [usize::MAX; 2] {
            nodes.push(node);
            angle.push(match tg {
                crate::contact::Target::Node { x0, .. } => x0[1].atan2(x0[0]),
                crate::contact::Target::Ring { .. } => 0.0,
            });
        }
    }
    (nodes, slot, angle)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;

    /// The columns from elimination-tree paths equal the full solves' on the shipped seal
    /// (every tooth-tip node, batches as the loop asks for them).
    #[test]
    fn path_columns_equal_full_solves_on_the_seal() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("scenes/stators/labyrinth_seal.toml");
        let ls = crate::scene::load(&path, &[]).unwrap();
        let model = Model::from_scene(&ls).unwrap();
        let case = model.case(model.rotor.natural_frequency()).unwrap();
        let s = &case.stators[0];
        let mut full = Compliance::with_columns(s, Some(false)).unwrap();
        let mut fast = Compliance::with_columns(s, Some(true)).unwrap();
        assert!(fast.paths && !full.paths);
        let dofs: Vec<usize> = s.contact_dofs();
        // In a scattered order, so batches and paths differ from one call to the next.
        for k in 0..dofs.len() {
            let d = dofs[(k * 7919) % dofs.len()];
            full.ensure(d);
            fast.ensure(d);
        }
        let mut worst: f64 = 0.0;
        for (i, &a) in dofs.iter().enumerate().step_by(3) {
            let faa = full.flex(a, a);
            for &b in dofs.iter().skip(i).step_by(5) {
                worst = worst.max((fast.flex(a, b) - full.flex(a, b)).abs() / faa);
            }
        }
        assert!(
            worst < 1e-12,
            "largest difference {worst:.3e} of the diagonal"
        );
        assert!(fast.cols.paths.bytes() > 0);
    }
}
