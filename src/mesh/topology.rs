//! Topology of a [`Mesh`]: the nodes of a group, the facets of the top-dimension cells, outward
//! boundary normals, and the check that the cells form a conforming mesh (no coincident or
//! hanging nodes).

use std::collections::HashMap;

use super::{CellKind, Mesh};
use crate::error::MeshError;

impl Mesh {
    /// Sorted distinct nodes of the cells of group `name`.
    pub fn group_nodes(&self, name: &str) -> Result<Vec<usize>, MeshError> {
        let g = self.group(name)?;
        let mut v: Vec<usize> = self
            .group_blocks(g)
            .flat_map(|b| b.conn.iter().copied())
            .collect();
        v.sort_unstable();
        v.dedup();
        if v.is_empty() {
            return Err(MeshError::BadGroup {
                file: self.file.clone(),
                group: name.to_string(),
                message: format!("the group (dimension {}) has no mesh nodes", g.dim),
            });
        }
        Ok(v)
    }

    /// Cells of the mesh's top dimension, as `(block index, cell index)`.
    pub fn top_cells(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let d = self.dim();
        self.blocks
            .iter()
            .enumerate()
            .filter(move |(_, b)| b.kind.dim() == d)
            .flat_map(|(bi, b)| (0..b.len()).map(move |ci| (bi, ci)))
    }

    /// Map from a facet (sorted corner nodes) of a top-dimension cell to the cells that have it.
    fn facet_map(&self) -> HashMap<Vec<usize>, Vec<(usize, usize)>> {
        let mut map: HashMap<Vec<usize>, Vec<(usize, usize)>> = HashMap::new();
        for (bi, ci) in self.top_cells() {
            let b = &self.blocks[bi];
            let cell = b.cell(ci);
            for f in b.kind.facets() {
                let mut key: Vec<usize> = f.iter().map(|&i| cell[i]).collect();
                key.sort_unstable();
                map.entry(key).or_default().push((bi, ci));
            }
        }
        map
    }

    /// Centroid of the corner nodes of a cell.
    fn centroid(&self, kind: CellKind, cell: &[usize]) -> [f64; 3] {
        let k = kind.corners();
        let mut c = [0.0; 3];
        for &n in &cell[..k] {
            for (ci, x) in c.iter_mut().zip(self.nodes[n]) {
                *ci += x / k as f64;
            }
        }
        c
    }

    /// Tributary measure of each node of boundary group `name` (curves of a 2-D mesh: m; surfaces
    /// of a 3-D mesh: m²), as `(node, measure)` sorted by node: every facet's length (area)
    /// shared equally by its nodes — the lumped share of a uniform load for linear facets; a
    /// quadratic facet's nodes take equal shares too, not its consistent ones (which are zero
    /// at a 6-node triangle's corners).
    pub fn boundary_measures(&self, name: &str) -> Result<Vec<(usize, f64)>, MeshError> {
        let g = self.group(name)?;
        let mut acc: HashMap<usize, f64> = HashMap::new();
        for b in self.group_blocks(g) {
            let k = b.kind.corners();
            for cell in b.cells() {
                let p: Vec<[f64; 3]> = cell[..k].iter().map(|&n| self.nodes[n]).collect();
                let measure = match k {
                    2 => norm3(sub(p[1], p[0])),
                    3 => 0.5 * norm3(cross(sub(p[1], p[0]), sub(p[2], p[0]))),
                    4 => {
                        0.5 * (norm3(cross(sub(p[1], p[0]), sub(p[2], p[0])))
                            + norm3(cross(sub(p[2], p[0]), sub(p[3], p[0]))))
                    }
                    _ => 0.0,
                };
                for &node in cell {
                    *acc.entry(node).or_insert(0.0) += measure / cell.len() as f64;
                }
            }
        }
        let mut out: Vec<(usize, f64)> = acc.into_iter().collect();
        out.sort_unstable_by_key(|x| x.0);
        Ok(out)
    }

    /// Outward unit normals at the nodes of boundary group `name` (curves of a 2-D mesh,
    /// surfaces of a 3-D mesh), as `(node, n)` sorted by node. Each facet's normal is oriented
    /// away from the body cell it bounds; a node's normal is the length- (area-) weighted mean
    /// of its facets' normals.
    pub fn boundary_normals(&self, name: &str) -> Result<Vec<(usize, [f64; 3])>, MeshError> {
        let g = self.group(name)?;
        let d = self.dim();
        let bad = |message: String| MeshError::BadGroup {
            file: self.file.clone(),
            group: name.to_string(),
            message,
        };
        if d < 2 || g.dim + 1 != d {
            return Err(bad(format!(
                "a contact boundary of a {d}-D mesh must be a group of dimension {} (Physical {}), this one has dimension {}",
                d.saturating_sub(1),
                if d == 3 { "Surface" } else { "Curve" },
                g.dim
            )));
        }
        let facets = self.facet_map();
        let mut acc: HashMap<usize, [f64; 3]> = HashMap::new();
        for b in self.group_blocks(g) {
            for (ci, cell) in b.cells().enumerate() {
                let k = b.kind.corners();
                let mut key: Vec<usize> = cell[..k].to_vec();
                key.sort_unstable();
                let owners = facets.get(&key).ok_or_else(|| {
                    bad(format!(
                        "element {} is not a facet of any {d}-D cell (the group must lie on the body's boundary)",
                        b.tags[ci]
                    ))
                })?;
                if owners.len() != 1 {
                    return Err(bad(format!(
                        "element {} lies inside the body (shared by {} cells), not on its boundary",
                        b.tags[ci],
                        owners.len()
                    )));
                }
                let (ob, oc) = owners[0];
                let ob = &self.blocks[ob];
                let cen = self.centroid(ob.kind, ob.cell(oc));
                let p: Vec<[f64; 3]> = cell[..k].iter().map(|&n| self.nodes[n]).collect();
                let mut n = if d == 2 {
                    let t = sub(p[1], p[0]);
                    [t[1], -t[0], 0.0]
                } else {
                    cross(sub(p[1], p[0]), sub(p[2], p[0]))
                };
                let mid = self.centroid(b.kind, cell);
                if dot3(n, sub(mid, cen)) < 0.0 {
                    n = [-n[0], -n[1], -n[2]];
                }
                // |n| is the facet's length (2-D) or twice its area (3-D): weights.
                for &node in cell {
                    let a = acc.entry(node).or_insert([0.0; 3]);
                    for i in 0..3 {
                        a[i] += n[i];
                    }
                }
            }
        }
        let mut out: Vec<(usize, [f64; 3])> = acc
            .into_iter()
            .map(|(k, v)| {
                let l = dot3(v, v).sqrt();
                (
                    k,
                    if l > 0.0 {
                        [v[0] / l, v[1] / l, v[2] / l]
                    } else {
                        v
                    },
                )
            })
            .collect();
        out.sort_unstable_by_key(|x| x.0);
        if out.is_empty() {
            return Err(bad("the group has no elements".into()));
        }
        Ok(out)
    }

    /// Checks that the top-dimension cells form a conforming mesh: no two nodes they use
    /// coincide, and no such node lies inside a boundary facet it does not belong to (a hanging
    /// node, where two parts were meshed without sharing their interface).
    pub fn check_conforming(&self) -> Result<(), MeshError> {
        let d = self.dim();
        let mut used = vec![false; self.nodes.len()];
        for (bi, ci) in self.top_cells() {
            for &n in self.blocks[bi].cell(ci) {
                used[n] = true;
            }
        }
        let ids: Vec<usize> = (0..self.nodes.len()).filter(|&i| used[i]).collect();
        if ids.is_empty() {
            return Ok(());
        }
        let (lo, hi) = bbox(ids.iter().map(|&i| self.nodes[i]));
        let diag = dot3(sub(hi, lo), sub(hi, lo)).sqrt();
        let tol = 1e-9 * diag.max(f64::MIN_POSITIVE);
        // Typical cell size from the number of nodes, for the hash grid.
        let h = (diag / (ids.len() as f64).powf(1.0 / d.max(1) as f64)).max(tol * 10.0);
        let grid = Grid::new(&ids, &self.nodes, lo, h);
        let nonconf = |message: String| MeshError::NonConforming {
            file: self.file.clone(),
            message,
        };
        for &i in &ids {
            for j in grid.near(self.nodes[i], tol) {
                if j > i && dist(self.nodes[i], self.nodes[j]) <= tol {
                    return Err(nonconf(format!(
                        "nodes {} and {} coincide at ({:.6e}, {:.6e}, {:.6e}) but are distinct: the parts they belong to do not share their interface (fuse them with BooleanFragments / Coherence)",
                        self.node_tags[i], self.node_tags[j],
                        self.nodes[i][0], self.nodes[i][1], self.nodes[i][2]
                    )));
                }
            }
        }
        // Hanging nodes on boundary facets.
        for (key, owners) in self.facet_map() {
            if owners.len() != 1 {
                continue;
            }
            let p: Vec<[f64; 3]> = key.iter().map(|&n| self.nodes[n]).collect();
            let (flo, fhi) = bbox(p.iter().copied());
            let c = [
                0.5 * (flo[0] + fhi[0]),
                0.5 * (flo[1] + fhi[1]),
                0.5 * (flo[2] + fhi[2]),
            ];
            let r = 0.5 * dist(flo, fhi) + tol;
            let (ob, oc) = owners[0];
            let own = self.blocks[ob].cell(oc);
            for j in grid.near(c, r) {
                if own.contains(&j) {
                    continue;
                }
                if on_facet(&p, self.nodes[j], tol) {
                    return Err(nonconf(format!(
                        "node {} at ({:.6e}, {:.6e}, {:.6e}) lies on the boundary of element {} without being one of its nodes (hanging node): the parts do not share their interface",
                        self.node_tags[j], self.nodes[j][0], self.nodes[j][1], self.nodes[j][2],
                        self.blocks[ob].tags[oc]
                    )));
                }
            }
        }
        Ok(())
    }
}

/// `a − b`.
fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
/// Dot product.
fn norm3(a: [f64; 3]) -> f64 {
    dot3(a, a).sqrt()
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
/// Cross product `a × b`.
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
/// Euclidean distance.
fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(a, b);
    dot3(d, d).sqrt()
}
/// Axis-aligned bounding box `(lo, hi)` of the points.
fn bbox(pts: impl Iterator<Item = [f64; 3]>) -> ([f64; 3], [f64; 3]) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in pts {
        for i in 0..3 {
            lo[i] = lo[i].min(p[i]);
            hi[i] = hi[i].max(p[i]);
        }
    }
    (lo, hi)
}

/// True when `x` lies on the segment (2 points) or triangle (3 points) `p` within `tol`,
/// strictly away from its corners.
fn on_facet(p: &[[f64; 3]], x: [f64; 3], tol: f64) -> bool {
    if p.iter().any(|c| dist(*c, x) <= tol) {
        return false;
    }
    match p.len() {
        2 => {
            let t = sub(p[1], p[0]);
            let l2 = dot3(t, t);
            let s = dot3(sub(x, p[0]), t) / l2;
            if !(0.0..=1.0).contains(&s) {
                return false;
            }
            let q = [p[0][0] + s * t[0], p[0][1] + s * t[1], p[0][2] + s * t[2]];
            dist(q, x) <= tol
        }
        3 => {
            let e1 = sub(p[1], p[0]);
            let e2 = sub(p[2], p[0]);
            let n = cross(e1, e2);
            let a2 = dot3(n, n);
            let w = sub(x, p[0]);
            if dot3(w, n).abs() / a2.sqrt() > tol {
                return false;
            }
            let b1 = dot3(cross(w, e2), n) / a2;
            let b2 = dot3(cross(e1, w), n) / a2;
            b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0
        }
        _ => false,
    }
}

/// Uniform hash grid over a subset of nodes.
struct Grid {
    lo: [f64; 3],
    h: f64,
    cells: HashMap<[i64; 3], Vec<usize>>,
}

impl Grid {
    fn new(ids: &[usize], x: &[[f64; 3]], lo: [f64; 3], h: f64) -> Self {
        let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        let mut g = Grid {
            lo,
            h,
            cells: HashMap::new(),
        };
        for &i in ids {
            cells.entry(g.key(x[i])).or_default().push(i);
        }
        g.cells = cells;
        g
    }
    fn key(&self, p: [f64; 3]) -> [i64; 3] {
        [
            ((p[0] - self.lo[0]) / self.h).floor() as i64,
            ((p[1] - self.lo[1]) / self.h).floor() as i64,
            ((p[2] - self.lo[2]) / self.h).floor() as i64,
        ]
    }
    /// Nodes within the box of half-width `r` around `c` (a superset of those within `r`).
    fn near(&self, c: [f64; 3], r: f64) -> Vec<usize> {
        let a = self.key([c[0] - r, c[1] - r, c[2] - r]);
        let b = self.key([c[0] + r, c[1] + r, c[2] + r]);
        let mut out = Vec::new();
        for i in a[0]..=b[0] {
            for j in a[1]..=b[1] {
                for k in a[2]..=b[2] {
                    if let Some(v) = self.cells.get(&[i, j, k]) {
                        out.extend_from_slice(v);
                    }
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::SQUARE;
    use super::*;
    use std::path::Path;

    #[test]
    fn duplicate_node_is_non_conforming() {
        // Move node 4 onto node 3's position: two distinct nodes at one point.
        let bad = SQUARE.replace("1 1 0\n0 1 0", "1 1 0\n1 1 0");
        let m = Mesh::parse(Path::new("sq.msh"), bad.as_bytes()).unwrap();
        let e = m.check_conforming().unwrap_err().to_string();
        assert!(
            e.contains("non-conforming") && e.contains("coincide"),
            "{e}"
        );
    }
}
