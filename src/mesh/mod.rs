//! Meshes of stators as gmsh writes them: nodes, cells grouped in blocks by kind, and the named
//! physical groups that are the contract between a geometry and a scene.
//!
//! # Conventions
//!
//! * Coordinates are in metres, `[x, y, z]`, with the rotor axis along z and the origin on the
//!   undeformed centre of the rotor section the stator faces (so a 2-D stator lies in the
//!   station plane z = 0).
//! * Nodes are numbered `0..nodes.len()` in file order; [`Mesh::node_tags`] keeps gmsh's tags
//!   for messages. Cells keep gmsh's node order (see [`CellKind`]), 0-based.
//! * A physical group is a set of geometric entities of one dimension; its cells are the cells
//!   of those entities. The names rubsim looks for by default are `stator_contact` (the contact
//!   boundary: curves in 2-D, surfaces in 3-D) and `stator_fixed` (fixed supports); groups of the
//!   mesh's top dimension are material regions.
//! * Boundary normals ([`Mesh::boundary_normals`]) point out of the body.
//!
//! [`gmsh`] runs the mesher on parametric `.geo` files and caches its output; [`Mesh::read`]
//! reads MSH 4.1 (ASCII or binary) with the `mshio` crate plus the `$PhysicalNames` section,
//! which `mshio` does not parse.

pub mod gmsh;

use crate::error::MeshError;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Cell types rubsim reads, with gmsh's node ordering.
///
/// Node order (gmsh): corners first, counter-clockwise for 2-D cells in a surface whose normal
/// is +z; then mid-edge nodes of edges (0,1), (1,2), (2,0) for `Tri6`, (0,1), (1,2), (2,3),
/// (3,0) for `Quad8`/`Quad9`, then the centre node of `Quad9`. `Tet10` mid-edge nodes follow
/// edges (0,1), (1,2), (2,0), (0,3), (2,3), (1,3) (gmsh's order, note the last two).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CellKind {
    /// 1-node point.
    Point,
    /// 2-node line.
    Line2,
    /// 3-node line (ends, then middle).
    Line3,
    /// 3-node triangle.
    Tri3,
    /// 6-node triangle.
    Tri6,
    /// 4-node quadrilateral.
    Quad4,
    /// 8-node (serendipity) quadrilateral.
    Quad8,
    /// 9-node (Lagrange) quadrilateral.
    Quad9,
    /// 4-node tetrahedron.
    Tet4,
    /// 10-node tetrahedron.
    Tet10,
}

impl CellKind {
    /// From gmsh's element type number, `None` for types rubsim does not read.
    pub fn from_gmsh(t: mshio::ElementType) -> Option<Self> {
        use mshio::ElementType as E;
        Some(match t {
            E::Pnt => CellKind::Point,
            E::Lin2 => CellKind::Line2,
            E::Lin3 => CellKind::Line3,
            E::Tri3 => CellKind::Tri3,
            E::Tri6 => CellKind::Tri6,
            E::Qua4 => CellKind::Quad4,
            E::Qua8 => CellKind::Quad8,
            E::Qua9 => CellKind::Quad9,
            E::Tet4 => CellKind::Tet4,
            E::Tet10 => CellKind::Tet10,
            _ => return None,
        })
    }

    /// Topological dimension.
    pub fn dim(self) -> usize {
        match self {
            CellKind::Point => 0,
            CellKind::Line2 | CellKind::Line3 => 1,
            CellKind::Tri3
            | CellKind::Tri6
            | CellKind::Quad4
            | CellKind::Quad8
            | CellKind::Quad9 => 2,
            CellKind::Tet4 | CellKind::Tet10 => 3,
        }
    }

    /// Number of nodes.
    pub fn nodes(self) -> usize {
        match self {
            CellKind::Point => 1,
            CellKind::Line2 => 2,
            CellKind::Line3 => 3,
            CellKind::Tri3 => 3,
            CellKind::Tri6 => 6,
            CellKind::Quad4 => 4,
            CellKind::Quad8 => 8,
            CellKind::Quad9 => 9,
            CellKind::Tet4 => 4,
            CellKind::Tet10 => 10,
        }
    }

    /// Number of corner (vertex) nodes, which come first.
    pub fn corners(self) -> usize {
        match self {
            CellKind::Point => 1,
            CellKind::Line2 | CellKind::Line3 => 2,
            CellKind::Tri3 | CellKind::Tri6 => 3,
            CellKind::Quad4 | CellKind::Quad8 | CellKind::Quad9 => 4,
            CellKind::Tet4 | CellKind::Tet10 => 4,
        }
    }

    /// Local corner nodes of each facet (edges of 2-D cells, faces of tetrahedra, ends of
    /// lines). Facets are matched by their sorted corner nodes.
    pub fn facets(self) -> &'static [&'static [usize]] {
        match self {
            CellKind::Point => &[],
            CellKind::Line2 | CellKind::Line3 => &[&[0], &[1]],
            CellKind::Tri3 | CellKind::Tri6 => &[&[0, 1], &[1, 2], &[2, 0]],
            CellKind::Quad4 | CellKind::Quad8 | CellKind::Quad9 => {
                &[&[0, 1], &[1, 2], &[2, 3], &[3, 0]]
            }
            CellKind::Tet4 | CellKind::Tet10 => &[&[0, 2, 1], &[0, 1, 3], &[0, 3, 2], &[1, 2, 3]],
        }
    }

    /// gmsh's name of the type.
    pub fn name(self) -> &'static str {
        match self {
            CellKind::Point => "point",
            CellKind::Line2 => "2-node line",
            CellKind::Line3 => "3-node line",
            CellKind::Tri3 => "3-node triangle",
            CellKind::Tri6 => "6-node triangle",
            CellKind::Quad4 => "4-node quadrilateral",
            CellKind::Quad8 => "8-node quadrilateral",
            CellKind::Quad9 => "9-node quadrilateral",
            CellKind::Tet4 => "4-node tetrahedron",
            CellKind::Tet10 => "10-node tetrahedron",
        }
    }

    /// VTK cell type number (for writers).
    pub fn vtk_type(self) -> u8 {
        match self {
            CellKind::Point => 1,
            CellKind::Line2 => 3,
            CellKind::Line3 => 21,
            CellKind::Tri3 => 5,
            CellKind::Tri6 => 22,
            CellKind::Quad4 => 9,
            CellKind::Quad8 => 23,
            CellKind::Quad9 => 28,
            CellKind::Tet4 => 10,
            CellKind::Tet10 => 24,
        }
    }
}

/// Cells of one kind on one geometric entity.
#[derive(Debug, Clone, PartialEq)]
pub struct CellBlock {
    /// Cell type.
    pub kind: CellKind,
    /// Dimension of the geometric entity (equals `kind.dim()`).
    pub entity_dim: usize,
    /// gmsh tag of the geometric entity.
    pub entity: i32,
    /// Connectivity, `kind.nodes()` 0-based node indices per cell, flat.
    pub conn: Vec<usize>,
    /// gmsh element tag of each cell.
    pub tags: Vec<u64>,
}

impl CellBlock {
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.tags.len()
    }
    /// True when the block has no cells.
    pub fn is_empty(&self) -> bool {
        self.tags.is_empty()
    }
    /// Node indices of cell `i`.
    pub fn cell(&self, i: usize) -> &[usize] {
        let n = self.kind.nodes();
        &self.conn[i * n..(i + 1) * n]
    }
    /// Iterates the cells' node lists.
    pub fn cells(&self) -> impl Iterator<Item = &[usize]> {
        self.conn.chunks_exact(self.kind.nodes())
    }
}

/// A named physical group.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// Name from `$PhysicalNames` (or `group_<tag>` when the file names none).
    pub name: String,
    /// Dimension of its entities.
    pub dim: usize,
    /// gmsh physical tag.
    pub tag: i32,
    /// Tags of its geometric entities (of dimension `dim`).
    pub entities: Vec<i32>,
}

/// A mesh read from a gmsh MSH 4.1 file.
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// The file it was read from (for messages).
    pub file: PathBuf,
    /// Node coordinates `[x, y, z]` (m).
    pub nodes: Vec<[f64; 3]>,
    /// gmsh tag of each node.
    pub node_tags: Vec<u64>,
    /// Cell blocks, one per (entity, kind).
    pub blocks: Vec<CellBlock>,
    /// Physical groups.
    pub groups: Vec<Group>,
}

impl Mesh {
    /// Reads an MSH 4.1 file (ASCII or binary).
    pub fn read(path: &Path) -> Result<Mesh, MeshError> {
        let bytes = std::fs::read(path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                MeshError::MissingFile {
                    file: path.to_path_buf(),
                    referenced_by: None,
                }
            } else {
                MeshError::Io {
                    file: path.to_path_buf(),
                    source: e,
                }
            }
        })?;
        Self::parse(path, &bytes)
    }

    /// Parses the bytes of an MSH 4.1 file; `path` is used in messages only.
    pub fn parse(path: &Path, bytes: &[u8]) -> Result<Mesh, MeshError> {
        let parse_err = |message: String| MeshError::Parse {
            file: path.to_path_buf(),
            message,
        };
        if !bytes.starts_with(b"$MeshFormat") {
            return Err(parse_err(
                "the file does not start with $MeshFormat (not a gmsh .msh file?)".into(),
            ));
        }
        // Version check first: mshio reads 4.1 only and its errors on 2.2 files are cryptic.
        let header = String::from_utf8_lossy(&bytes[..bytes.len().min(64)]);
        let version = header
            .lines()
            .nth(1)
            .and_then(|l| l.split_whitespace().next());
        if version != Some("4.1") {
            return Err(parse_err(format!(
                "MSH format version {} (rubsim reads 4.1: mesh with `-format msh41`)",
                version.unwrap_or("?")
            )));
        }
        let msh = mshio::parse_msh_bytes(bytes).map_err(|e| {
            let bt = e.filtered_backtrace();
            let line = bt.first().map(|(rest, _)| {
                let off = bytes.len() - rest.len();
                bytes[..off].iter().filter(|b| **b == b'\n').count() + 1
            });
            let what: Vec<String> = bt.iter().rev().map(|(_, k)| k.to_string()).collect();
            parse_err(format!(
                "{}{}",
                line.map(|l| format!("line {l}: ")).unwrap_or_default(),
                what.join(": ")
            ))
        })?;
        let names = physical_names(bytes).map_err(parse_err)?;

        // Nodes.
        let mut nodes = Vec::new();
        let mut node_tags = Vec::new();
        if let Some(nd) = &msh.data.nodes {
            let mut next_tag = nd.min_node_tag;
            for b in &nd.node_blocks {
                let mut tags: Vec<u64> = match &b.node_tags {
                    Some(map) => {
                        let mut t = vec![0; b.nodes.len()];
                        for (tag, &i) in map {
                            t[i] = *tag;
                        }
                        t
                    }
                    // Dense numbering: gmsh writes the tags of a dense file in block order.
                    None => (0..b.nodes.len() as u64).map(|i| next_tag + i).collect(),
                };
                next_tag += b.nodes.len() as u64;
                for n in &b.nodes {
                    nodes.push([n.x, n.y, n.z]);
                }
                node_tags.append(&mut tags);
            }
        }
        let index: HashMap<u64, usize> =
            node_tags.iter().enumerate().map(|(i, &t)| (t, i)).collect();
        if index.len() != node_tags.len() {
            return Err(parse_err("duplicate node tags".into()));
        }

        // Cells.
        let mut blocks: Vec<CellBlock> = Vec::new();
        let mut unsupported: Vec<(String, usize, i32, i32)> = Vec::new();
        if let Some(el) = &msh.data.elements {
            for b in &el.element_blocks {
                let Some(kind) = CellKind::from_gmsh(b.element_type) else {
                    unsupported.push((
                        format!("{:?}", b.element_type),
                        b.elements.len(),
                        b.entity_dim,
                        b.entity_tag,
                    ));
                    continue;
                };
                let mut conn = Vec::with_capacity(b.elements.len() * kind.nodes());
                let mut tags = Vec::with_capacity(b.elements.len());
                for e in &b.elements {
                    if e.nodes.len() != kind.nodes() {
                        return Err(parse_err(format!(
                            "element {} has {} nodes, a {} has {}",
                            e.element_tag,
                            e.nodes.len(),
                            kind.name(),
                            kind.nodes()
                        )));
                    }
                    for t in &e.nodes {
                        let i = index.get(t).ok_or_else(|| {
                            parse_err(format!(
                                "element {} refers to node {t}, which is not in $Nodes",
                                e.element_tag
                            ))
                        })?;
                        conn.push(*i);
                    }
                    tags.push(e.element_tag);
                }
                blocks.push(CellBlock {
                    kind,
                    entity_dim: b.entity_dim.max(0) as usize,
                    entity: b.entity_tag,
                    conn,
                    tags,
                });
            }
        }

        // Physical groups: entities carry their physical tags.
        let mut groups: Vec<Group> = Vec::new();
        if let Some(ent) = &msh.data.entities {
            let mut add = |dim: usize, etag: i32, phys: &[i32]| {
                for &p in phys {
                    let p = p.abs();
                    match groups.iter_mut().find(|g| g.dim == dim && g.tag == p) {
                        Some(g) => g.entities.push(etag),
                        None => groups.push(Group {
                            name: names
                                .iter()
                                .find(|(d, t, _)| *d == dim && *t == p)
                                .map(|(_, _, n)| n.clone())
                                .unwrap_or_else(|| format!("group_{p}")),
                            dim,
                            tag: p,
                            entities: vec![etag],
                        }),
                    }
                }
            };
            for e in &ent.points {
                add(0, e.tag, &e.physical_tags);
            }
            for e in &ent.curves {
                add(1, e.tag, &e.physical_tags);
            }
            for e in &ent.surfaces {
                add(2, e.tag, &e.physical_tags);
            }
            for e in &ent.volumes {
                add(3, e.tag, &e.physical_tags);
            }
        }
        // Named groups without entities (possible in hand-written files) still get listed.
        for (d, t, n) in &names {
            if !groups.iter().any(|g| g.dim == *d && g.tag == *t) {
                groups.push(Group {
                    name: n.clone(),
                    dim: *d,
                    tag: *t,
                    entities: vec![],
                });
            }
        }
        let mesh = Mesh {
            file: path.to_path_buf(),
            nodes,
            node_tags,
            blocks,
            groups,
        };
        if let Some((kind, count, dim, entity)) = unsupported.into_iter().next() {
            let group = mesh
                .groups
                .iter()
                .find(|g| g.dim as i32 == dim && g.entities.contains(&entity))
                .map_or_else(
                    || format!("(entity {entity} of dimension {dim})"),
                    |g| g.name.clone(),
                );
            return Err(MeshError::UnsupportedCell {
                file: path.to_path_buf(),
                group,
                kind,
                count,
            });
        }
        Ok(mesh)
    }

    /// Highest dimension of any cell (0 for a mesh without cells).
    pub fn dim(&self) -> usize {
        self.blocks
            .iter()
            .filter(|b| !b.is_empty())
            .map(|b| b.kind.dim())
            .max()
            .unwrap_or(0)
    }

    /// The physical group called `name`.
    pub fn group(&self, name: &str) -> Result<&Group, MeshError> {
        self.groups
            .iter()
            .find(|g| g.name == name)
            .ok_or_else(|| MeshError::MissingGroup {
                file: self.file.clone(),
                name: name.to_string(),
                available: self.group_list(),
            })
    }

    /// The groups as `name (dim d)`, for messages.
    pub fn group_list(&self) -> Vec<String> {
        self.groups
            .iter()
            .map(|g| format!("{} (dim {})", g.name, g.dim))
            .collect()
    }

    /// The cell blocks of a group.
    pub fn group_blocks<'a>(&'a self, g: &'a Group) -> impl Iterator<Item = &'a CellBlock> + 'a {
        self.blocks
            .iter()
            .filter(move |b| b.entity_dim == g.dim && g.entities.contains(&b.entity))
    }

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

/// Parses the `$PhysicalNames` section (ASCII even in binary files): `(dim, tag, name)`.
fn physical_names(bytes: &[u8]) -> Result<Vec<(usize, i32, String)>, String> {
    let start = match find(bytes, b"$PhysicalNames") {
        Some(s) => s + b"$PhysicalNames".len(),
        None => return Ok(vec![]),
    };
    let end = find(&bytes[start..], b"$EndPhysicalNames")
        .ok_or("$PhysicalNames without $EndPhysicalNames")?
        + start;
    let text = std::str::from_utf8(&bytes[start..end])
        .map_err(|_| "$PhysicalNames is not UTF-8 text".to_string())?;
    let mut lines = text.lines().map(str::trim).filter(|l| !l.is_empty());
    let n: usize = lines
        .next()
        .and_then(|l| l.parse().ok())
        .ok_or("$PhysicalNames: missing count")?;
    let mut out = Vec::with_capacity(n);
    for l in lines.take(n) {
        let mut it = l.splitn(3, char::is_whitespace);
        let bad = || format!("$PhysicalNames: cannot read `{l}`");
        let dim: usize = it.next().and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        let tag: i32 = it.next().and_then(|s| s.parse().ok()).ok_or_else(bad)?;
        let name = it
            .next()
            .ok_or_else(bad)?
            .trim()
            .trim_matches('"')
            .to_string();
        out.push((dim, tag, name));
    }
    if out.len() != n {
        return Err(format!(
            "$PhysicalNames announces {n} names, holds {}",
            out.len()
        ));
    }
    Ok(out)
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = sub(a, b);
    dot3(d, d).sqrt()
}
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
    use super::*;

    /// Two triangles forming the unit square, its bottom edge a `stator_contact` group.
    pub(crate) const SQUARE: &str = "$MeshFormat
4.1 0 8
$EndMeshFormat
$PhysicalNames
2
1 2 \"stator_contact\"
2 1 \"stator\"
$EndPhysicalNames
$Entities
0 1 1 0
1 0 0 0 1 0 0 1 2 0
1 0 0 0 1 1 0 1 1 0
$EndEntities
$Nodes
2 4 1 4
1 1 0 2
1
2
0 0 0
1 0 0
2 1 0 2
3
4
1 1 0
0 1 0
$EndNodes
$Elements
2 3 1 3
1 1 1 1
1 1 2
2 1 2 2
2 1 2 3
3 1 3 4
$EndElements
";

    #[test]
    fn reads_nodes_cells_and_named_groups() {
        let m = Mesh::parse(Path::new("sq.msh"), SQUARE.as_bytes()).unwrap();
        assert_eq!(m.nodes.len(), 4);
        assert_eq!(m.dim(), 2);
        assert_eq!(m.group("stator").unwrap().dim, 2);
        assert_eq!(m.group_nodes("stator_contact").unwrap(), vec![0, 1]);
        let n = m.boundary_normals("stator_contact").unwrap();
        // Bottom edge of the square: outward normal −y.
        for (_, v) in n {
            assert!((v[1] + 1.0).abs() < 1e-12 && v[0].abs() < 1e-12, "{v:?}");
        }
        m.check_conforming().unwrap();
        let e = m.group("stator_fixed").unwrap_err().to_string();
        assert!(
            e.contains("sq.msh")
                && e.contains("stator_fixed")
                && e.contains("stator_contact (dim 1)"),
            "{e}"
        );
    }

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

    #[test]
    fn rejects_other_formats_with_the_file_name() {
        let e = Mesh::parse(
            Path::new("old.msh"),
            b"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("old.msh") && e.contains("2.2"), "{e}");
        let e = Mesh::parse(Path::new("x.msh"), b"hello")
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.msh"), "{e}");
    }
}
