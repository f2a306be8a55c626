//! The stators' share of the Delassus matrix, kept while the selected pairs hold.
//!
//! A contact problem's `W_ij = n_i · (F_r + F_s,ij) b_j` changes with the frozen normals every
//! step, but the flexibility blocks `F_s,ij` between the stator targets of pairs `i` and `j`
//! do not change during a run (a massless stator's `K⁻¹`, a stator with mass's `M̃⁻¹`, a
//! reduced stator's operator, all fixed with Δt). [`PairBlocks`] keeps them for the pairs
//! selected last and, when the selection changes, reads only the rows and columns of the pairs
//! that entered; while the set holds, assembling `W` costs `O(q²)` multiply–adds from
//! contiguous memory.

/// A 2 × 2 flexibility block (m/N): `block[a][b]` the displacement of component `a` of one
/// target per unit force along component `b` of the other.
pub(crate) type Block = [[f64; 2]; 2];

/// What a pair's blocks are read by: its stator and the stator's own index of the target's two
/// DOFs (`usize::MAX` for a DOF the target does not have) — for a massless stator the DOFs'
/// positions in its packed compliance, looked up once per selection change.
pub(crate) type Key = (usize, [usize; 2]);

/// The blocks `F_s,ij` of the selected pairs (row-major q × q).
#[derive(Debug, Default)]
pub(crate) struct PairBlocks {
    /// Candidates the blocks are for, in the selection's order.
    sel: Vec<usize>,
    blocks: Vec<Block>,
    /// The previous selection's, swapped in on a change.
    old_sel: Vec<usize>,
    old_blocks: Vec<Block>,
    /// Per candidate: its index in `old_sel` during an update (`usize::MAX` otherwise).
    pos: Vec<usize>,
    /// New index → old index (`usize::MAX`: entered now).
    map: Vec<usize>,
    /// Per selected pair: the key its blocks are read by.
    keys: Vec<Key>,
    /// Blocks read from the stators so far (the work of a selection change).
    pub(crate) read: u64,
}

impl PairBlocks {
    /// Makes the blocks those of `sel` (candidate indices), reading a block with
    /// `block(key_i, key_j)` only for a pair of candidates not both in the previous selection
    /// (`key(ci)`: the candidate's [`Key`]).
    pub(crate) fn update(
        &mut self,
        sel: &[usize],
        key: impl Fn(usize) -> Key,
        mut block: impl FnMut(&Key, &Key) -> Block,
    ) {
        if sel == self.sel.as_slice() {
            return;
        }
        std::mem::swap(&mut self.sel, &mut self.old_sel);
        std::mem::swap(&mut self.blocks, &mut self.old_blocks);
        self.sel.clear();
        self.sel.extend_from_slice(sel);
        let top = sel.iter().chain(&self.old_sel).max().map_or(0, |m| m + 1);
        if self.pos.len() < top {
            self.pos.resize(top, usize::MAX);
        }
        for (k, &c) in self.old_sel.iter().enumerate() {
            self.pos[c] = k;
        }
        self.map.clear();
        self.map.extend(sel.iter().map(|&c| self.pos[c]));
        for &c in &self.old_sel {
            self.pos[c] = usize::MAX;
        }
        let (q, qo) = (sel.len(), self.old_sel.len());
        self.keys.clear();
        self.keys.extend(sel.iter().map(|&c| key(c)));
        self.blocks.clear();
        self.blocks.resize(q * q, [[0.0; 2]; 2]);
        for i in 0..q {
            let oi = self.map[i];
            for j in 0..q {
                let oj = self.map[j];
                self.blocks[i * q + j] = if oi != usize::MAX && oj != usize::MAX {
                    self.old_blocks[oi * qo + oj]
                } else {
                    self.read += 1;
                    block(&self.keys[i], &self.keys[j])
                };
            }
        }
    }

    /// The block of selected pairs `i`, `j` (indices in the selection of the last update).
    #[cfg(test)]
    pub(crate) fn get(&self, i: usize, j: usize) -> &Block {
        &self.blocks[i * self.sel.len() + j]
    }

    /// The blocks of selected pair `i` with every selected pair, in the selection's order.
    #[inline]
    pub(crate) fn row(&self, i: usize) -> &[Block] {
        let q = self.sel.len();
        &self.blocks[i * q..(i + 1) * q]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(ci: usize) -> Key {
        (0, [ci, ci])
    }

    fn block(ki: &Key, kj: &Key) -> Block {
        exact(ki.1[0], kj.1[0])
    }

    fn exact(ci: usize, cj: usize) -> Block {
        let (a, b) = (ci as f64, cj as f64);
        [[a + b, a - b], [a * b, 1.0 + a]]
    }

    #[test]
    fn blocks_equal_a_fresh_read_and_only_new_pairs_are_read() {
        let mut pb = PairBlocks::default();
        let sels: [&[usize]; 5] = [&[3, 7, 9], &[3, 7, 9], &[7, 9, 12], &[1, 2], &[12, 7]];
        let mut reads = vec![];
        for sel in sels {
            let before = pb.read;
            pb.update(sel, key, block);
            reads.push(pb.read - before);
            for (i, &ci) in sel.iter().enumerate() {
                for (j, &cj) in sel.iter().enumerate() {
                    assert_eq!(*pb.get(i, j), exact(ci, cj), "{sel:?} {ci} {cj}");
                }
            }
        }
        // 9 fresh; none while the set holds; 9 − 4 kept; 4 fresh; 4 fresh (12, 7 were not in
        // the last selection).
        assert_eq!(reads, [9, 0, 5, 4, 4]);
    }
}
