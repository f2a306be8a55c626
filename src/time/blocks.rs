//! The stators' share of the Delassus matrix, kept while the selected pairs hold.
//!
//! A contact problem's `W_ij = n_i · (F_r + F_s,ij) b_j` changes with the frozen normals every
//! step, but the flexibility blocks `F_s,ij` between the stator targets of pairs `i` and `j`
//! do not change during a run (a massless stator's `K⁻¹`, a stator with mass's `M̃⁻¹`, a
//! reduced stator's operator, all fixed with Δt). [`PairBlocks`] keeps them for the pairs
//! selected: each pair holds a slot of a square table while it stays selected, so a change of
//! the selection reads only the row and column of the pairs that entered (one of the two for
//! a symmetric stator: the other is its transpose) and moves none of the blocks kept; while
//! the set holds, assembling `W` costs `O(q²)` multiply–adds from memory already in cache.

/// A 2 × 2 flexibility block (m/N): `block[a][b]` the displacement of component `a` of one
/// target per unit force along component `b` of the other.
pub(crate) type Block = [[f64; 2]; 2];

/// What a pair's blocks are read by: its stator and the stator's own index of the target's two
/// DOFs (`usize::MAX` for a DOF the target does not have) — for a massless stator the DOFs'
/// positions in its packed compliance, looked up once when the pair enters.
pub(crate) type Key = (usize, [usize; 2]);

/// The blocks `F_s,ij` of the selected pairs, by slot: pair `i` of the selection (in the
/// selection's order) holds slot `slot[i]`, its block with pair `j` at
/// `table[slot[i] * cap + slot[j]]`.
#[derive(Debug, Default)]
pub(crate) struct PairBlocks {
    /// Candidates the blocks are for, in the selection's order.
    sel: Vec<usize>,
    /// Per selected pair: its slot.
    slot: Vec<usize>,
    /// Slots per row of `table`.
    cap: usize,
    table: Vec<Block>,
    /// Per candidate: its slot while selected (`usize::MAX` otherwise).
    cand_slot: Vec<usize>,
    /// Per candidate: in the selection being made (an update's mark).
    mark: Vec<bool>,
    /// Per slot: the key of the pair holding it.
    keys: Vec<Key>,
    /// Slots no pair holds.
    free: Vec<usize>,
    /// Slots of the pairs that entered in the current update.
    fresh: Vec<usize>,
    /// Per slot: an entered pair whose row and column are read already (during an update).
    done: Vec<bool>,
    /// Blocks read from the stators so far (the work of a selection change).
    pub(crate) read: u64,
}

impl PairBlocks {
    /// Makes the blocks those of `sel` (candidate indices), reading a block with
    /// `block(key_i, key_j)` only for a pair of candidates not both in the previous selection
    /// (`key(ci)`: the candidate's [`Key`]); when `symmetric(key_i, key_j)`, the block of
    /// `(j, i)` is taken as the transpose of `(i, j)`'s instead of read.
    pub(crate) fn update(
        &mut self,
        sel: &[usize],
        key: impl Fn(usize) -> Key,
        mut block: impl FnMut(&Key, &Key) -> Block,
        symmetric: impl Fn(&Key, &Key) -> bool,
    ) {
        if sel == self.sel.as_slice() {
            return;
        }
        let top = sel.iter().chain(&self.sel).max().map_or(0, |m| m + 1);
        if self.cand_slot.len() < top {
            self.cand_slot.resize(top, usize::MAX);
            self.mark.resize(top, false);
        }
        for &c in sel {
            self.mark[c] = true;
        }
        // Pairs that left give their slots back.
        for &c in &self.sel {
            if !self.mark[c] {
                self.free.push(self.cand_slot[c]);
                self.cand_slot[c] = usize::MAX;
            }
        }
        self.fresh.clear();
        for &c in sel {
            self.mark[c] = false;
            if self.cand_slot[c] == usize::MAX {
                let s = self.free.pop().unwrap_or(self.keys.len());
                if s == self.keys.len() {
                    self.keys.push((0, [usize::MAX; 2]));
                }
                self.keys[s] = key(c);
                self.cand_slot[c] = s;
                self.fresh.push(s);
            }
        }
        self.grow();
        self.sel.clear();
        self.sel.extend_from_slice(sel);
        self.slot.clear();
        self.slot.extend(sel.iter().map(|&c| self.cand_slot[c]));
        // The rows and columns of the pairs that entered: with every selected pair, the
        // entered ones among themselves once.
        if self.done.len() < self.keys.len() {
            self.done.resize(self.keys.len(), false);
        }
        for &a in &self.fresh {
            for &b in &self.slot {
                if self.done[b] {
                    continue;
                }
                let (ka, kb) = (&self.keys[a], &self.keys[b]);
                let ab = block(ka, kb);
                self.read += 1;
                self.table[a * self.cap + b] = ab;
                if a != b {
                    self.table[b * self.cap + a] = if symmetric(ka, kb) {
                        [[ab[0][0], ab[1][0]], [ab[0][1], ab[1][1]]]
                    } else {
                        self.read += 1;
                        block(kb, ka)
                    };
                }
            }
            self.done[a] = true;
        }
        for &a in &self.fresh {
            self.done[a] = false;
        }
    }

    /// Widens the table to the slots in use, the blocks kept where they were.
    fn grow(&mut self) {
        let need = self.keys.len();
        if need <= self.cap {
            return;
        }
        let cap = need.max(2 * self.cap).max(8);
        let mut table = vec![[[0.0; 2]; 2]; cap * cap];
        for r in 0..self.cap {
            table[r * cap..r * cap + self.cap]
                .copy_from_slice(&self.table[r * self.cap..(r + 1) * self.cap]);
        }
        self.table = table;
        self.cap = cap;
    }

    /// The block of selected pairs `i`, `j` (indices in the selection of the last update).
    #[cfg(test)]
    pub(crate) fn get(&self, i: usize, j: usize) -> &Block {
        &self.table[self.slot[i] * self.cap + self.slot[j]]
    }

    /// Each selected pair's slot, in the selection's order.
    #[inline]
    pub(crate) fn slots(&self) -> &[usize] {
        &self.slot
    }

    /// The blocks of selected pair `i` by slot, and each selected pair's slot in the
    /// selection's order: pair `j`'s block is `row[slots[j]]`.
    #[inline]
    pub(crate) fn row(&self, i: usize) -> (&[Block], &[usize]) {
        let s = self.slot[i] * self.cap;
        (&self.table[s..s + self.cap], &self.slot)
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
        let sels: [&[usize]; 6] = [
            &[3, 7, 9],
            &[3, 7, 9],
            &[7, 9, 12],
            &[1, 2],
            &[12, 7],
            &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12],
        ];
        let mut reads = vec![];
        for sel in sels {
            let before = pb.read;
            pb.update(sel, key, block, |_, _| false);
            reads.push(pb.read - before);
            for (i, &ci) in sel.iter().enumerate() {
                for (j, &cj) in sel.iter().enumerate() {
                    assert_eq!(*pb.get(i, j), exact(ci, cj), "{sel:?} {ci} {cj}");
                    let (row, slots) = pb.row(i);
                    assert_eq!(row[slots[j]], exact(ci, cj));
                }
            }
        }
        // 9 fresh; none while the set holds; 9 − 4 kept; 4 fresh; 4 fresh (12, 7 were not in
        // the last selection); 13² − 4 kept.
        assert_eq!(reads, [9, 0, 5, 4, 4, 165]);
    }

    #[test]
    fn a_symmetric_stator_reads_one_of_each_pair_of_blocks() {
        let sym = |ki: &Key, kj: &Key| {
            let (a, b) = (ki.1[0] as f64, kj.1[0] as f64);
            [[a + b, a * b], [a * b, 1.0 + a * a + b * b]]
        };
        let mut pb = PairBlocks::default();
        let mut reads = vec![];
        for sel in [&[3usize, 7, 9][..], &[7, 9, 12, 4]] {
            let before = pb.read;
            pb.update(sel, key, sym, |_, _| true);
            reads.push(pb.read - before);
            for (i, &ci) in sel.iter().enumerate() {
                for (j, &cj) in sel.iter().enumerate() {
                    assert_eq!(*pb.get(i, j), sym(&key(ci), &key(cj)));
                }
            }
        }
        // 3 diagonal + 3 off-diagonal; 2 new rows of 4 less the block they share: 7.
        assert_eq!(reads, [6, 7]);
    }
}
