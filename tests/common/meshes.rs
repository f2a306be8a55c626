//! Meshed-stator fixtures: structured meshes of rings and tubes (written as MSH 4.1 text or
//! built as a [`Mesh`]), the stator model of a mesh, loads, a direct solve, the Lamé solution
//! and the L2 error against it; and the switch for tests that need gmsh.

use rubsim::element::solid2d::{self, Plane, Rule};
use rubsim::linalg::{Cholesky, Csc};
use rubsim::mesh::gmsh as gm;
use rubsim::mesh::{CellKind, Mesh};
use rubsim::model::stator::mesh as mesh_stator;
use rubsim::model::stator::{StatorElement, StatorModel};
use rubsim::scene::MeshStatorSpec;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Young's modulus (Pa) of the meshed test stators.
pub const E: f64 = 200e9;
/// Poisson's ratio of the meshed test stators.
pub const NU: f64 = 0.3;

/// A meshed-stator spec (`s` at station `disk`, geometry `x.msh`, 1 cm thick, [`E`], [`NU`])
/// with the TOML lines `extra`.
pub fn spec(extra: &str) -> MeshStatorSpec {
    toml::from_str(&format!(
        "name = \"s\"\nstation = \"disk\"\ngeometry = \"x.msh\"\nthickness = 0.01\nyoungs_modulus = {E}\npoisson_ratio = {NU}\n{extra}"
    ))
    .expect("spec")
}

/// A structured polar mesh of the ring sector r0 ≤ r ≤ r1, t0 ≤ θ ≤ t1 as MSH 4.1 text
/// (`full`: t1 = t0 + 2π, periodic). Groups: `stator` (surface), `stator_contact` (r = r0),
/// `stator_fixed` (r = r1), `edge_t0` (θ = t0), `edge_t1` (θ = t1).
#[allow(clippy::too_many_arguments)]
pub fn ring_msh(
    kind: CellKind,
    r0: f64,
    r1: f64,
    t0: f64,
    t1: f64,
    nr: usize,
    nt: usize,
    full: bool,
) -> String {
    let quad = matches!(kind, CellKind::Tri6 | CellKind::Quad8 | CellKind::Quad9);
    let ni = 2 * nr + 1;
    let nj = if full { 2 * nt } else { 2 * nt + 1 };
    let id = |i: usize, j: usize| i * nj + (j % nj) + 1;
    let mut s = String::new();
    s.push_str("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n5\n");
    s.push_str("1 2 \"stator_contact\"\n1 3 \"stator_fixed\"\n1 4 \"edge_t0\"\n1 5 \"edge_t1\"\n2 1 \"stator\"\n$EndPhysicalNames\n");
    let ncurves = if full { 2 } else { 4 };
    let _ = writeln!(s, "$Entities\n0 {ncurves} 1 0");
    for c in 1..=ncurves {
        let _ = writeln!(s, "{c} -1 -1 0 1 1 0 1 {} 0", c + 1);
    }
    s.push_str("1 -1 -1 0 1 1 0 1 1 0\n$EndEntities\n");
    let nn = ni * nj;
    let _ = writeln!(s, "$Nodes\n1 {nn} 1 {nn}\n2 1 0 {nn}");
    for k in 1..=nn {
        let _ = writeln!(s, "{k}");
    }
    for i in 0..ni {
        for j in 0..nj {
            let r = r0 + (r1 - r0) * i as f64 / (2 * nr) as f64;
            let t = t0 + (t1 - t0) * j as f64 / (2 * nt) as f64;
            let _ = writeln!(s, "{:.17e} {:.17e} 0", r * t.cos(), r * t.sin());
        }
    }
    s.push_str("$EndNodes\n");
    let mut cells: Vec<Vec<usize>> = Vec::new();
    for i in 0..nr {
        for j in 0..nt {
            let (a, b) = (2 * i, 2 * j);
            let c = [id(a, b), id(a + 2, b), id(a + 2, b + 2), id(a, b + 2)];
            let m = [
                id(a + 1, b),
                id(a + 2, b + 1),
                id(a + 1, b + 2),
                id(a, b + 1),
            ];
            let z = id(a + 1, b + 1);
            match kind {
                CellKind::Quad4 => cells.push(c.to_vec()),
                CellKind::Quad8 => cells.push([&c[..], &m[..]].concat()),
                CellKind::Quad9 => cells.push([&c[..], &m[..], &[z]].concat()),
                CellKind::Tri3 => {
                    cells.push(vec![c[0], c[1], c[2]]);
                    cells.push(vec![c[0], c[2], c[3]]);
                }
                CellKind::Tri6 => {
                    cells.push(vec![c[0], c[1], c[2], m[0], m[1], z]);
                    cells.push(vec![c[0], c[2], c[3], z, m[2], m[3]]);
                }
                _ => unreachable!(),
            }
        }
    }
    let ltype = if quad { 8 } else { 1 };
    let line = |i: usize, j0: usize, di: usize, dj: usize| -> String {
        if quad {
            format!(
                "{} {} {}",
                id(i, j0),
                id(i + 2 * di, j0 + 2 * dj),
                id(i + di, j0 + dj)
            )
        } else {
            format!("{} {}", id(i, j0), id(i + 2 * di, j0 + 2 * dj))
        }
    };
    let mut blocks: Vec<(usize, usize, usize, Vec<String>)> = Vec::new();
    blocks.push((1, 1, ltype, (0..nt).map(|j| line(0, 2 * j, 0, 1)).collect()));
    blocks.push((
        1,
        2,
        ltype,
        (0..nt).map(|j| line(2 * nr, 2 * j, 0, 1)).collect(),
    ));
    if !full {
        blocks.push((1, 3, ltype, (0..nr).map(|i| line(2 * i, 0, 1, 0)).collect()));
        blocks.push((
            1,
            4,
            ltype,
            (0..nr).map(|i| line(2 * i, 2 * nt, 1, 0)).collect(),
        ));
    }
    let ctype = match kind {
        CellKind::Tri3 => 2,
        CellKind::Quad4 => 3,
        CellKind::Tri6 => 9,
        CellKind::Quad9 => 10,
        CellKind::Quad8 => 16,
        _ => unreachable!(),
    };
    blocks.push((
        2,
        1,
        ctype,
        cells
            .iter()
            .map(|c| {
                c.iter()
                    .map(|v| v.to_string())
                    .collect::<Vec<_>>()
                    .join(" ")
            })
            .collect(),
    ));
    let total: usize = blocks.iter().map(|b| b.3.len()).sum();
    let _ = writeln!(s, "$Elements\n{} {total} 1 {total}", blocks.len());
    let mut tag = 1;
    for (d, e, t, lines) in &blocks {
        let _ = writeln!(s, "{d} {e} {t} {}", lines.len());
        for l in lines {
            let _ = writeln!(s, "{tag} {l}");
            tag += 1;
        }
    }
    s.push_str("$EndElements\n");
    s
}

/// The mesh of MSH text and its stator model (as `ring.msh`).
pub fn model_of(msh: &str, spec: &MeshStatorSpec) -> (Mesh, StatorModel) {
    let mesh = Mesh::parse(Path::new("ring.msh"), msh.as_bytes()).expect("parse");
    let m = mesh_stator::from_spec(&mesh, spec, 0, &[], PathBuf::from("ring.msh"), true)
        .expect("model");
    (mesh, m)
}

/// Consistent load of a radial pressure `p` on the inner boundary (`stator_contact` lines).
pub fn pressure_load(mesh: &Mesh, model: &StatorModel, p: f64, t: f64) -> Vec<f64> {
    let mut f = vec![0.0; model.ndof];
    let g = mesh.group("stator_contact").unwrap();
    for b in mesh.group_blocks(g) {
        for c in b.cells() {
            let x: Vec<[f64; 2]> = c
                .iter()
                .map(|&n| [mesh.nodes[n][0], mesh.nodes[n][1]])
                .collect();
            let mut fe = [0.0; 6];
            solid2d::edge_load(
                b.kind,
                &x,
                t,
                |pos, _| {
                    let r = pos[0].hypot(pos[1]);
                    [p * pos[0] / r, p * pos[1] / r]
                },
                &mut fe,
            );
            for (k, &n) in c.iter().enumerate() {
                for comp in 0..2 {
                    if let Some(d) = model.node_dofs[n][comp] {
                        f[d] += fe[2 * k + comp];
                    }
                }
            }
        }
    }
    f
}

/// K⁻¹ f by Cholesky.
pub fn solve(k: &Csc, f: &[f64]) -> Vec<f64> {
    let mut u = f.to_vec();
    Cholesky::new(k).expect("SPD").solve_in_place(&mut u);
    u
}

/// Lamé: ring r0..r1 under inner pressure p, outer edge clamped; radial displacement u(r).
pub fn lame(r0: f64, r1: f64, p: f64, plane: Plane) -> impl Fn(f64) -> f64 {
    let (e, nu) = match plane {
        Plane::Stress => (E, NU),
        Plane::Strain => (E / (1.0 - NU * NU), NU / (1.0 - NU)),
    };
    // u = A r + B / r, u(r1) = 0, σ_rr(r0) = −p.
    let b = p * (1.0 - nu * nu) / (e * ((1.0 + nu) / (r1 * r1) + (1.0 - nu) / (r0 * r0)));
    let a = -b / (r1 * r1);
    move |r| a * r + b / r
}

/// Relative L2 error of the displacement against Lamé.
pub fn l2_error(model: &StatorModel, u: &[f64], exact: &dyn Fn(f64) -> f64) -> f64 {
    let mut q = Vec::new();
    let (mut err, mut norm) = (0.0, 0.0);
    for el in model.elements.iter() {
        let StatorElement::Solid2 { kind, nodes, .. } = el else {
            continue;
        };
        let x: Vec<[f64; 2]> = nodes.iter().map(|&n| model.nodes[n]).collect();
        let ue: Vec<f64> = nodes
            .iter()
            .flat_map(|&n| model.node_dofs[n].map(|d| d.map_or(0.0, |i| u[i])))
            .collect();
        solid2d::quadrature(*kind, Rule::Accurate, &mut q);
        for &(xi, w) in &q {
            let (p, uh, det) = solid2d::interpolate(*kind, &x, &ue, xi);
            let r = p[0].hypot(p[1]);
            let ur = exact(r);
            let ex = [ur * p[0] / r, ur * p[1] / r];
            err += w * det * ((uh[0] - ex[0]).powi(2) + (uh[1] - ex[1]).powi(2));
            norm += w * det * (ex[0] * ex[0] + ex[1] * ex[1]);
        }
    }
    (err / norm).sqrt()
}

/// Structured tetrahedra (each polar hexahedron cut into the six Kuhn tetrahedra) of the
/// quarter tube r0 ≤ r ≤ r1, 0 ≤ θ ≤ π/2, 0 ≤ z ≤ lz, built as a [`Mesh`] with groups
/// `stator` (volume), `stator_contact` (r = r0 faces), `stator_fixed` (r = r1), `sym_y`
/// (θ = 0), `sym_x` (θ = π/2), `ends` (z = 0 and z = lz).
pub fn tube_mesh(kind: CellKind, r0: f64, r1: f64, lz: f64, nr: usize, nt: usize) -> Mesh {
    use rubsim::mesh::{CellBlock, Group};
    let quad = kind == CellKind::Tet10;
    let (ni, nj, nk) = (2 * nr + 1, 2 * nt + 1, 3);
    let id = |i: usize, j: usize, k: usize| (i * nj + j) * nk + k;
    let mut nodes = Vec::new();
    for i in 0..ni {
        for j in 0..nj {
            for k in 0..nk {
                let r = r0 + (r1 - r0) * i as f64 / (2 * nr) as f64;
                let t = PI / 2.0 * j as f64 / (2 * nt) as f64;
                nodes.push([r * t.cos(), r * t.sin(), lz * k as f64 / 2.0]);
            }
        }
    }
    let mut conn = Vec::new();
    let perms = [
        [0, 1, 2],
        [0, 2, 1],
        [1, 0, 2],
        [1, 2, 0],
        [2, 0, 1],
        [2, 1, 0],
    ];
    for i in 0..nr {
        for j in 0..nt {
            let base = [2 * i, 2 * j, 0];
            for p in perms {
                // Corners in grid units (step 2), mid nodes at half steps.
                let mut c = [[0usize; 3]; 4];
                c[0] = base;
                for s in 0..3 {
                    c[s + 1] = c[s];
                    c[s + 1][p[s]] += 2;
                }
                let x: Vec<[f64; 3]> = c.iter().map(|g| nodes[id(g[0], g[1], g[2])]).collect();
                let det = {
                    let a = [x[1][0] - x[0][0], x[1][1] - x[0][1], x[1][2] - x[0][2]];
                    let b = [x[2][0] - x[0][0], x[2][1] - x[0][1], x[2][2] - x[0][2]];
                    let d = [x[3][0] - x[0][0], x[3][1] - x[0][1], x[3][2] - x[0][2]];
                    a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0])
                        + a[2] * (b[0] * d[1] - b[1] * d[0])
                };
                if det < 0.0 {
                    c.swap(1, 2);
                }
                let mid = |a: usize, b: usize| {
                    id(
                        (c[a][0] + c[b][0]) / 2,
                        (c[a][1] + c[b][1]) / 2,
                        (c[a][2] + c[b][2]) / 2,
                    )
                };
                conn.extend(c.iter().map(|g| id(g[0], g[1], g[2])));
                if quad {
                    for (a, b) in [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)] {
                        conn.push(mid(a, b));
                    }
                }
            }
        }
    }
    let ncell = conn.len() / kind.nodes();
    // Boundary faces: the faces of the tetrahedra lying on a boundary surface.
    let fkind = if quad { CellKind::Tri6 } else { CellKind::Tri3 };
    let mut faces: Vec<Vec<usize>> = vec![Vec::new(); 5];
    let on = |n: usize| -> [bool; 5] {
        let k = n % nk;
        let j = (n / nk) % nj;
        let i = n / (nk * nj);
        [
            i == 0,
            i == ni - 1,
            j == 0,
            j == nj - 1,
            k == 0 || k == nk - 1,
        ]
    };
    for c in conn.chunks(kind.nodes()) {
        for f in [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
            let fc: Vec<usize> = f.iter().map(|&a| c[a]).collect();
            for (s, face) in faces.iter_mut().enumerate() {
                let same_end = s != 4 || {
                    let k0 = fc[0] % nk;
                    fc.iter().all(|&n| n % nk == k0)
                };
                if fc.iter().all(|&n| on(n)[s]) && same_end {
                    face.extend(&fc);
                    if quad {
                        let e = |a: usize, b: usize| {
                            let m = [
                                (0, 1, 4),
                                (1, 2, 5),
                                (0, 2, 6),
                                (0, 3, 7),
                                (2, 3, 8),
                                (1, 3, 9),
                            ];
                            let (x, y) = (f[a].min(f[b]), f[a].max(f[b]));
                            c[m.iter().find(|t| t.0 == x && t.1 == y).unwrap().2]
                        };
                        face.extend([e(0, 1), e(1, 2), e(0, 2)]);
                    }
                }
            }
        }
    }
    let mut blocks = vec![CellBlock {
        kind,
        entity_dim: 3,
        entity: 1,
        tags: (1..=ncell as u64).collect(),
        conn,
    }];
    let names = ["stator_contact", "stator_fixed", "sym_y", "sym_x", "ends"];
    let mut groups = vec![Group {
        name: "stator".into(),
        dim: 3,
        tag: 1,
        entities: vec![1],
    }];
    for (s, face) in faces.into_iter().enumerate() {
        let n = face.len() / fkind.nodes();
        blocks.push(CellBlock {
            kind: fkind,
            entity_dim: 2,
            entity: s as i32 + 1,
            tags: (0..n as u64)
                .map(|t| 100_000 * (s as u64 + 1) + t)
                .collect(),
            conn: face,
        });
        groups.push(Group {
            name: names[s].into(),
            dim: 2,
            tag: s as i32 + 2,
            entities: vec![s as i32 + 1],
        });
    }
    Mesh {
        file: PathBuf::from("tube.msh"),
        node_tags: (1..=nodes.len() as u64).collect(),
        nodes,
        blocks,
        groups,
    }
}

// ---------------------------------------------------------------------------------------------
// gmsh.

/// gmsh runs (`gmsh --version`).
pub fn gmsh_available() -> bool {
    std::process::Command::new(gm::gmsh_program())
        .arg("--version")
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// The gmsh tests need gmsh; without it they fail (set RUBSIM_SKIP_GMSH=1 to skip them).
pub fn need_gmsh() -> bool {
    if std::env::var("RUBSIM_SKIP_GMSH").is_ok() {
        eprintln!("RUBSIM_SKIP_GMSH set: skipping a gmsh test");
        return false;
    }
    assert!(
        gmsh_available(),
        "gmsh not found: run scripts/setup.sh (or set RUBSIM_SKIP_GMSH=1)"
    );
    true
}

/// Skips a test that may need gmsh when `RUBSIM_SKIP_GMSH` is set (as [`need_gmsh`] does);
/// otherwise the mesh comes from the cache in `meshes/` or gmsh.
pub fn gmsh_wanted() -> bool {
    if std::env::var("RUBSIM_SKIP_GMSH").is_ok() {
        eprintln!("RUBSIM_SKIP_GMSH set: skipping a test with a meshed stator");
        return false;
    }
    true
}
