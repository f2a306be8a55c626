//! Entries of `A⁻¹` among chosen DOFs from forward solves on elimination-tree paths.
//!
//! With `P A Pᵀ = L Lᵀ` (faer's supernodal Cholesky, `P` its fill-reducing permutation), the
//! entry of `A⁻¹` between DOFs `a` and `b` is `(A⁻¹)_ab = y_aᵀ y_b` with `y_a = L⁻¹ P e_a`.
//! The forward solution of a unit load is nonzero only on the path from its column's supernode
//! to the root of the supernodal elimination tree (the rows of a supernode's column block lie
//! in its ancestors), so `y_a` costs the path, not the factor: on the 10⁶-DOF seal 1.0e8 flops
//! against 1.5e9 for a full forward and back solve, and two paths share their common ancestors
//! only, so `y_aᵀ y_b` is a sum over the supernodes both paths pass.
//!
//! [`PathStore`] keeps each computed `y` segment by supernode (the segments of all the columns
//! through supernode `s` side by side, `|s| × count`), so the entries between a new batch of
//! columns and every stored one are one matrix product per supernode of the batch's paths
//! ([`Cholesky::path_columns`]).

use super::Cholesky;
use faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::{Accum, MatMut, MatRef, Par};
use std::sync::Arc;

/// The supernodal elimination tree of a factor and its permutation, built once per factor.
#[derive(Debug)]
pub(crate) struct PathTree {
    /// Supernode `s` holds the permuted columns `begin[s]..begin[s + 1]`.
    begin: Vec<usize>,
    /// Parent supernode (`usize::MAX` for a root).
    parent: Vec<usize>,
    /// Rows of each supernode below its diagonal block.
    below: Vec<usize>,
    /// Permuted column → its supernode.
    sn_of: Vec<u32>,
    /// DOF → its permuted column.
    col_of: Vec<usize>,
}

impl PathTree {
    /// The tree of `ch`'s factor; `None` for a simplicial factor (no supernodes).
    pub(crate) fn new(ch: &Cholesky) -> Option<Self> {
        let SymbolicCholeskyRaw::Supernodal(sn) = ch.symbolic.raw() else {
            return None;
        };
        let ns = sn.n_supernodes();
        let mut begin: Vec<usize> = sn.supernode_begin().to_vec();
        begin.push(*sn.supernode_end().last()?);
        let mut sn_of = vec![0u32; ch.n];
        for s in 0..ns {
            sn_of[begin[s]..begin[s + 1]].fill(u32::try_from(s).ok()?);
        }
        let parent = (0..ns)
            .map(|s| {
                sn.supernode(s)
                    .pattern()
                    .iter()
                    .min()
                    .map_or(usize::MAX, |&r| sn_of[r] as usize)
            })
            .collect();
        let below = (0..ns).map(|s| sn.supernode(s).pattern().len()).collect();
        let col_of = match ch.symbolic.perm() {
            Some(p) => p.arrays().1.to_vec(),
            None => (0..ch.n).collect(),
        };
        Some(Self {
            begin,
            parent,
            below,
            sn_of,
            col_of,
        })
    }

    fn width(&self, s: usize) -> usize {
        self.begin[s + 1] - self.begin[s]
    }

    /// The supernode of DOF `d`'s permuted column.
    fn start(&self, d: usize) -> usize {
        self.sn_of[self.col_of[d]] as usize
    }

    /// Number of entries of `y_d` a [`PathStore`] holds: the widths of the supernodes on its
    /// path, from its column's to the root.
    #[cfg(test)]
    fn path_len(&self, d: usize) -> usize {
        let mut s = self.start(d);
        let mut len = 0;
        while s != usize::MAX {
            len += self.width(s);
            s = self.parent[s];
        }
        len
    }
}

/// What the columns of a set of DOFs cost from their paths ([`Cholesky::path_cost`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PathCost {
    /// Flops of the forward solves, one column at a time: `Σ_paths Σ_s (w_s² + 2 w_s b_s)`
    /// (`w_s` the supernode's width, `b_s` its rows below the diagonal block).
    pub forward_flops: f64,
    /// Flops of the products among them, every pair once: `Σ_s w_s c_s (c_s + 1)` (`c_s`
    /// columns through supernode `s`).
    pub product_flops: f64,
    /// Entries a [`PathStore`] holds for them (8 bytes each): `Σ_s w_s c_s`.
    pub stored_entries: f64,
}

/// The stored forward solutions `y = L⁻¹ P e` of a set of columns, by supernode: through
/// supernode `s`, each column's segment of `|s|` entries side by side (column-major
/// `|s| × count`) and the caller's label of each. A supernode's segments are a list of
/// chunks, each allocated once for a quarter of the columns already held (at least
/// [`CHUNK_COLUMNS`] and the batch's), filled in place and never reallocated: no copy of the
/// segments while they grow (a doubling vector would hold its old and new buffer at once)
/// and at most about a quarter of them allocated and unused. Cloning shares the chunks, as
/// the packed compliance shares its blocks between runs: a chunk a clone shares is not
/// written, a new one is started, so a run that adopted another's columns adds its own
/// without copying them.
#[derive(Debug, Default, Clone)]
pub struct PathStore {
    by_node: Vec<Vec<Arc<Segments>>>,
    /// Entries held (8 bytes each).
    entries: usize,
}

#[derive(Debug, Default, Clone)]
struct Segments {
    vals: Vec<f64>,
    labels: Vec<u32>,
}

impl PathStore {
    /// Bytes of the stored segments.
    pub fn bytes(&self) -> usize {
        8 * self.entries
    }

    /// Bytes allocated for the stored segments (their chunks' capacity, labels included).
    pub fn allocated(&self) -> usize {
        self.by_node
            .iter()
            .flatten()
            .map(|c| 8 * c.vals.capacity() + 4 * c.labels.capacity())
            .sum()
    }
}

/// Fewest columns a new chunk of a supernode's stored segments is allocated for
/// ([`PathStore`]).
pub const CHUNK_COLUMNS: usize = 16;

/// Largest batch of [`Cholesky::path_columns`] (one bit per column in a supernode's mask).
pub const PATH_BATCH: usize = 64;

/// One batch's forward solve: the union of its paths (supernodes ascending, children before
/// parents), each one's offset in the compact block `x` (`width × nb`, column-major) and
/// which of the batch's columns pass it.
struct Batch {
    union: Vec<usize>,
    off: Vec<usize>,
    mask: Vec<u64>,
    width: usize,
    x: Vec<f64>,
}

impl Cholesky {
    /// Adds the forward solutions of unit loads at `dofs` to `store` under `labels` and
    /// returns `F`, column-major `rows × dofs.len()`: `F[l + j·rows] = (A⁻¹)[dof(l), dofs[j]]`
    /// for every label `l < rows` held in `store` (the new ones included), 0 for the other
    /// rows — the entries of `A⁻¹` (m/N for a stiffness) between the batch and every column
    /// stored so far, summed supernode by supernode over the paths both share.
    ///
    /// `None` when the factor is simplicial (no supernodal tree) or `dofs` holds more than
    /// [`PATH_BATCH`] columns; `store` is then unchanged.
    ///
    /// # Panics
    /// If `labels` and `dofs` differ in length or a DOF is not below n.
    pub fn path_columns(
        &self,
        store: &mut PathStore,
        dofs: &[usize],
        labels: &[u32],
        rows: usize,
    ) -> Option<Vec<f64>> {
        assert_eq!(dofs.len(), labels.len());
        let tree = self.path_tree()?;
        if dofs.len() > PATH_BATCH {
            return None;
        }
        let SymbolicCholeskyRaw::Supernodal(sn) = self.symbolic.raw() else {
            return None;
        };
        let llt = SupernodalLltRef::new(sn, &self.values);
        let mut b = Batch::paths(tree, dofs);
        b.forward(tree, &llt)?;
        let nb = dofs.len();
        if store.by_node.len() < tree.parent.len() {
            store.by_node.resize(tree.parent.len(), Vec::new());
        }
        let mut out = vec![0.0; rows * nb];
        let mut g = Vec::new();
        for (&s, &off) in b.union.iter().zip(&b.off) {
            let w = tree.width(s);
            let chunks = &mut store.by_node[s];
            let k = b.mask[s].count_ones() as usize;
            let room = chunks
                .last_mut()
                .and_then(Arc::get_mut)
                .is_some_and(|c| c.vals.capacity() - c.vals.len() >= k * w);
            if !room {
                let held: usize = chunks.iter().map(|c| c.labels.len()).sum();
                let cols = k.max(held / 4).max(CHUNK_COLUMNS);
                chunks.push(Arc::new(Segments {
                    vals: Vec::with_capacity(cols * w),
                    labels: Vec::with_capacity(cols),
                }));
            }
            let segs = chunks
                .last_mut()
                .and_then(Arc::get_mut)
                .expect("a chunk no clone shares");
            for (j, &l) in labels.iter().enumerate() {
                if b.mask[s] & (1 << j) != 0 {
                    let at = j * b.width + off;
                    segs.vals.extend_from_slice(&b.x[at..at + w]);
                    segs.labels.push(l);
                    store.entries += w;
                }
            }
            // gᵀ = xsᵀ · stored (nb × cnt, the chunks one after the other): the stored
            // segments are read in place, column by column, and only the batch's few columns
            // are packed.
            let xs = MatRef::from_column_major_slice_with_stride(&b.x[off..], w, nb, b.width);
            let cnt: usize = chunks.iter().map(|c| c.labels.len()).sum();
            g.clear();
            g.resize(nb * cnt, 0.0);
            products(&mut g, xs, chunks, w);
            let labels = chunks.iter().flat_map(|c| c.labels.iter());
            for (r, &l) in labels.enumerate() {
                let l = l as usize;
                if l < rows {
                    for j in 0..nb {
                        out[l + j * rows] += g[j + r * nb];
                    }
                }
            }
        }
        Some(out)
    }

    /// The work and memory of the columns of `dofs` from their paths; `None` for a simplicial
    /// factor.
    pub fn path_cost(&self, dofs: &[usize]) -> Option<PathCost> {
        let tree = self.path_tree()?;
        let mut count = vec![0u32; tree.parent.len()];
        let mut c = PathCost::default();
        for &d in dofs {
            let mut s = tree.start(d);
            while s != usize::MAX {
                let (w, b) = (tree.width(s) as f64, tree.below[s] as f64);
                c.forward_flops += w * w + 2.0 * w * b;
                count[s] += 1;
                s = tree.parent[s];
            }
        }
        for (s, &k) in count.iter().enumerate() {
            let (w, k) = (tree.width(s) as f64, f64::from(k));
            c.product_flops += w * k * (k + 1.0);
            c.stored_entries += w * k;
        }
        Some(c)
    }

    /// The factor's supernodal elimination tree (built on first use; `None` when simplicial).
    pub(crate) fn path_tree(&self) -> Option<&PathTree> {
        self.paths.get_or_init(|| PathTree::new(self)).as_ref()
    }
}

/// Stored segments per parallel task of [`products`] (below this, one task).
const PRODUCT_CHUNK: usize = 512;

/// `g = xsᵀ · stored` (`nb × cnt`, column-major) for the stored segments of `chunks` (`w ×
/// cnt` in all, the chunks one after the other): the stored columns split among the threads
/// in pieces of at most [`PRODUCT_CHUNK`] columns, each entry one sequential product over the
/// `w` rows in the same order whatever the split.
fn products(g: &mut [f64], xs: MatRef<'_, f64>, chunks: &[Arc<Segments>], w: usize) {
    use rayon::prelude::*;
    let nb = xs.ncols();
    let one = |(g, vals): (&mut [f64], &[f64])| {
        let cnt = vals.len() / w.max(1);
        faer::linalg::matmul::matmul(
            MatMut::from_column_major_slice_mut(g, nb, cnt),
            Accum::Replace,
            xs.transpose(),
            MatRef::from_column_major_slice(vals, w, cnt),
            1.0,
            Par::Seq,
        );
    };
    if w == 0 || nb == 0 {
        return;
    }
    let mut pieces = Vec::new();
    let mut rest = g;
    for c in chunks {
        for v in c.vals.chunks(w * PRODUCT_CHUNK) {
            let (head, tail) = rest.split_at_mut(nb * (v.len() / w));
            pieces.push((head, v));
            rest = tail;
        }
    }
    pieces.into_par_iter().for_each(one);
}

impl Batch {
    /// The union of the paths of `dofs` and the unit loads placed.
    fn paths(tree: &PathTree, dofs: &[usize]) -> Self {
        let ns = tree.parent.len();
        let mut mask = vec![0u64; ns];
        let mut union = Vec::new();
        for (j, &d) in dofs.iter().enumerate() {
            let mut s = tree.start(d);
            while s != usize::MAX {
                if mask[s] == 0 {
                    union.push(s);
                }
                mask[s] |= 1 << j;
                s = tree.parent[s];
            }
        }
        union.sort_unstable();
        let mut width = 0;
        let off: Vec<usize> = union
            .iter()
            .map(|&s| {
                let o = width;
                width += tree.width(s);
                o
            })
            .collect();
        let mut x = vec![0.0; width * dofs.len()];
        for (j, &d) in dofs.iter().enumerate() {
            let s = tree.start(d);
            let k = union.binary_search(&s).unwrap_or_default();
            x[j * width + off[k] + tree.col_of[d] - tree.begin[s]] = 1.0;
        }
        Self {
            union,
            off,
            mask,
            width,
            x,
        }
    }

    /// `x ← L⁻¹ x` over the union's supernodes, children first; `None` if a supernode's rows
    /// fall outside the union (not an elimination tree: never for faer's factors).
    fn forward(&mut self, tree: &PathTree, llt: &SupernodalLltRef<'_, usize, f64>) -> Option<()> {
        let nb = self.x.len().checked_div(self.width).unwrap_or(0);
        // The columns in two fixed halves, one per thread: each column's arithmetic is the
        // same whatever the threads (the split does not depend on them).
        let (a, b) = self.x.split_at_mut(self.width * nb.div_ceil(2));
        let part = |x: &mut [f64]| forward_part(&self.union, &self.off, self.width, x, tree, llt);
        let (ra, rb) = rayon::join(|| part(a), || part(b));
        ra.and(rb)
    }
}

/// `x ← L⁻¹ x` for the columns `x` (column-major, `width` rows each) of a batch over the union
/// `union` of its paths (offsets `off`), children first.
fn forward_part(
    union: &[usize],
    off: &[usize],
    width: usize,
    x: &mut [f64],
    tree: &PathTree,
    llt: &SupernodalLltRef<'_, usize, f64>,
) -> Option<()> {
    let nb = x.len().checked_div(width).unwrap_or(0);
    if nb == 0 {
        return Some(());
    }
    let mut tmp = Vec::new();
    for (&s, &o) in union.iter().zip(off) {
        let node = llt.supernode(s);
        let w = tree.width(s);
        let (top, bot) = node.val().split_at_row(w);
        let xs = MatMut::from_column_major_slice_with_stride_mut(&mut x[o..], w, nb, width);
        faer::linalg::triangular_solve::solve_lower_triangular_in_place(top, xs, Par::Seq);
        let pattern = node.pattern();
        if pattern.is_empty() {
            continue;
        }
        tmp.clear();
        tmp.resize(pattern.len() * nb, 0.0);
        let xs = MatRef::from_column_major_slice_with_stride(&x[o..], w, nb, width);
        faer::linalg::matmul::matmul(
            MatMut::from_column_major_slice_mut(&mut tmp, pattern.len(), nb),
            Accum::Replace,
            bot,
            xs,
            1.0,
            Par::Seq,
        );
        for (i, &r) in pattern.iter().enumerate() {
            let t = tree.sn_of[r] as usize;
            let k = union.binary_search(&t).ok()?;
            let row = off[k] + r - tree.begin[t];
            for j in 0..nb {
                x[row + j * width] -= tmp[i + j * pattern.len()];
            }
        }
    }
    Some(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::Csc;

    /// A 3-D grid Laplacian plus the identity (positive definite, with fill), n = m³.
    fn grid(m: usize) -> Csc {
        let id = |i: usize, j: usize, k: usize| (i * m + j) * m + k;
        let mut t = Vec::new();
        for i in 0..m {
            for j in 0..m {
                for k in 0..m {
                    let a = id(i, j, k);
                    t.push((a, a, 7.0 + (a % 5) as f64 * 0.1));
                    for (di, dj, dk) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                        let (p, q, r) = (i + di, j + dj, k + dk);
                        if p < m && q < m && r < m {
                            let b = id(p, q, r);
                            t.push((a, b, -1.0));
                            t.push((b, a, -1.0));
                        }
                    }
                }
            }
        }
        Csc::from_triplets(m * m * m, m * m * m, &t)
    }

    /// Every entry between the columns added batch by batch equals the full solve's.
    #[test]
    fn path_entries_equal_full_solves() {
        let a = grid(12);
        let n = a.nrows;
        let ch = Cholesky::new_supernodal(&a).unwrap();
        assert!(ch.path_tree().is_some(), "forced supernodal");
        let dofs: Vec<usize> = (0..n).step_by(37).collect();
        let mut store = PathStore::default();
        let rows = dofs.len();
        let mut got = vec![vec![0.0; rows]; rows];
        // Clones kept alive as a run's adopted columns are (the shared store keeps them).
        let mut earlier = Vec::new();
        for (c, chunk) in dofs.chunks(7).enumerate() {
            if c % 3 == 2 {
                earlier.push(store.clone());
            }
            let labels: Vec<u32> = (0..chunk.len()).map(|j| (c * 7 + j) as u32).collect();
            let f = ch.path_columns(&mut store, chunk, &labels, rows).unwrap();
            for (j, &l) in labels.iter().enumerate() {
                for (i, row) in got.iter_mut().enumerate() {
                    if i <= l as usize {
                        row[l as usize] = f[i + j * rows];
                    }
                }
            }
        }
        let mut worst: f64 = 0.0;
        for (jl, &d) in dofs.iter().enumerate() {
            let mut e = vec![0.0; n];
            e[d] = 1.0;
            ch.solve_in_place(&mut e);
            for (il, &di) in dofs.iter().enumerate().take(jl + 1) {
                worst = worst.max((got[il][jl] - e[di]).abs() / e[d].abs());
            }
        }
        assert!(worst < 1e-13, "largest relative difference {worst:.3e}");
        let len: usize = dofs
            .iter()
            .map(|&d| ch.path_tree().unwrap().path_len(d))
            .sum();
        assert_eq!(store.bytes(), 8 * len, "the store holds each path once");
        // What a clone held is shared by the store that went on, not copied.
        let ptrs = |st: &PathStore| -> Vec<*const Segments> {
            st.by_node.iter().flatten().map(Arc::as_ptr).collect()
        };
        let now = ptrs(&store);
        for e in &earlier {
            assert!(
                ptrs(e).iter().all(|p| now.contains(p)),
                "a clone's chunk was copied"
            );
        }
        // Allocated: the entries, a quarter more, a smallest chunk's room per supernode and
        // the batches' room left in the chunks a batch did not fit (here 7 columns a batch).
        let tree = ch.path_tree().unwrap();
        let room: usize = (0..store.by_node.len())
            .filter(|&s| !store.by_node[s].is_empty())
            .map(|s| 12 * (CHUNK_COLUMNS + 7 * store.by_node[s].len()) * tree.width(s))
            .sum();
        let labels = 4 * store
            .by_node
            .iter()
            .flatten()
            .map(|c| c.labels.len())
            .sum::<usize>();
        assert!(
            store.allocated() <= (store.bytes() + labels) * 5 / 4 + room,
            "allocated {} for {} bytes of segments",
            store.allocated(),
            store.bytes()
        );
        let cost = ch.path_cost(&dofs).unwrap();
        assert_eq!(cost.stored_entries, len as f64);
        assert!(cost.forward_flops > 0.0 && cost.product_flops > 0.0);
    }
}
