//! Meshed stators: element verification (patch tests, ring under diametral loads; the
//! convergence slopes are in convergence.rs), the gmsh pipeline (cache, errors naming files and groups) and
//! meshed stators in contact.
//!
//! Structured polar meshes are written as MSH 4.1 text here and go through the same reader and
//! assembler as gmsh's meshes; the gmsh tests need `gmsh` on the PATH (scripts/setup.sh).

use rubsim::element::solid2d::{self, Elastic2, Plane};
use rubsim::linalg::{Cholesky, Csc};
use rubsim::mesh::gmsh::{self as gm, MeshRequest};
use rubsim::mesh::{CellKind, Mesh};
use rubsim::model::stator::mesh as mesh_stator;
use rubsim::model::stator::{StatorElement, StatorModel};
use rubsim::scene::MeshStatorSpec;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const E: f64 = 200e9;
const NU: f64 = 0.3;

fn spec(extra: &str) -> MeshStatorSpec {
    toml::from_str(&format!(
        "name = \"s\"\nstation = \"disk\"\ngeometry = \"x.msh\"\nthickness = 0.01\nyoungs_modulus = {E}\npoisson_ratio = {NU}\n{extra}"
    ))
    .expect("spec")
}

/// A structured polar mesh of the ring sector r0 ≤ r ≤ r1, t0 ≤ θ ≤ t1 as MSH 4.1 text
/// (`full`: t1 = t0 + 2π, periodic). Groups: `stator` (surface), `stator_contact` (r = r0),
/// `stator_fixed` (r = r1), `edge_t0` (θ = t0), `edge_t1` (θ = t1).
#[allow(clippy::too_many_arguments)]
fn ring_msh(
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

fn model_of(msh: &str, spec: &MeshStatorSpec) -> (Mesh, StatorModel) {
    let mesh = Mesh::parse(Path::new("ring.msh"), msh.as_bytes()).expect("parse");
    let m = mesh_stator::from_spec(&mesh, spec, 0, &[], PathBuf::from("ring.msh"), true)
        .expect("model");
    (mesh, m)
}

fn solve(k: &Csc, f: &[f64]) -> Vec<f64> {
    let mut u = f.to_vec();
    Cholesky::new(k).expect("SPD").solve_in_place(&mut u);
    u
}

#[test]
fn patch_test_reproduces_linear_fields_on_distorted_cells() {
    // A 2×2 patch on [0, 1]² with the centre node moved and, for quadratic cells, mid nodes
    // off the chords' midpoints: prescribing a linear field on the boundary must give it
    // exactly inside, with constant stress.
    let mat = Elastic2 {
        youngs_modulus: E,
        poisson_ratio: NU,
        thickness: 0.01,
        plane: Plane::Stress,
    };
    let field = |x: [f64; 2]| {
        [
            1e-3 + 2e-4 * x[0] - 1e-4 * x[1],
            -5e-4 + 3e-4 * x[0] + 1e-4 * x[1],
        ]
    };
    for kind in [
        CellKind::Tri3,
        CellKind::Tri6,
        CellKind::Quad4,
        CellKind::Quad8,
        CellKind::Quad9,
    ] {
        let msh = ring_msh(kind, 1.0, 2.0, 0.0, 0.5, 2, 2, false);
        let mut mesh = Mesh::parse(Path::new("patch.msh"), msh.as_bytes()).unwrap();
        // Map the sector onto a distorted square patch: node (r, θ) → (r − 1, 2θ) + distortion.
        for p in mesh.nodes.iter_mut() {
            let (r, t) = (p[0].hypot(p[1]), p[1].atan2(p[0]));
            let (x, y) = (r - 1.0, 2.0 * t);
            let bump = (x * (1.0 - x) * y * (1.0 - y)) * 16.0;
            *p = [
                x + 0.08 * bump,
                y - 0.05 * bump + 0.02 * (x * PI).sin() * y * (1.0 - y),
                0.0,
            ];
        }
        let nd = 2 * mesh.nodes.len();
        let mut kt = Vec::new();
        let mut boundary = vec![false; mesh.nodes.len()];
        for (i, p) in mesh.nodes.iter().enumerate() {
            boundary[i] = p[0].abs() < 1e-12
                || (p[0] - 1.0).abs() < 1e-12
                || p[1].abs() < 1e-12
                || (p[1] - 1.0).abs() < 1e-12;
        }
        for b in mesh.blocks.iter().filter(|b| b.kind.dim() == 2) {
            for c in b.cells() {
                let x: Vec<[f64; 2]> = c
                    .iter()
                    .map(|&n| [mesh.nodes[n][0], mesh.nodes[n][1]])
                    .collect();
                assert!(solid2d::det_j_range(b.kind, &x).0 > 0.0);
                let n2 = 2 * c.len();
                let mut ke = vec![0.0; n2 * n2];
                solid2d::stiffness(b.kind, &x, &mat, &mut ke);
                for i in 0..n2 {
                    for j in 0..n2 {
                        kt.push((2 * c[i / 2] + i % 2, 2 * c[j / 2] + j % 2, ke[i * n2 + j]));
                    }
                }
            }
        }
        let k = Csc::from_triplets(nd, nd, &kt);
        let used: Vec<bool> = (0..mesh.nodes.len())
            .map(|n| {
                mesh.blocks
                    .iter()
                    .filter(|b| b.kind.dim() == 2)
                    .any(|b| b.conn.contains(&n))
            })
            .collect();
        // Interior unknowns: K_ii u_i = −K_ib u_b.
        let free: Vec<usize> = (0..nd)
            .filter(|d| used[d / 2] && !boundary[d / 2])
            .collect();
        let mut map = vec![usize::MAX; nd];
        for (i, &d) in free.iter().enumerate() {
            map[d] = i;
        }
        let ub: Vec<f64> = (0..nd)
            .map(|d| {
                if boundary[d / 2] {
                    field([mesh.nodes[d / 2][0], mesh.nodes[d / 2][1]])[d % 2]
                } else {
                    0.0
                }
            })
            .collect();
        let mut rhs = vec![0.0; free.len()];
        let mut kii = Vec::new();
        for (r, c, v) in k.triplets() {
            if map[r] == usize::MAX {
                continue;
            }
            if map[c] != usize::MAX {
                kii.push((map[r], map[c], v));
            } else {
                rhs[map[r]] -= v * ub[c];
            }
        }
        let u = solve(&Csc::from_triplets(free.len(), free.len(), &kii), &rhs);
        for (i, &d) in free.iter().enumerate() {
            let ex = field([mesh.nodes[d / 2][0], mesh.nodes[d / 2][1]])[d % 2];
            assert!(
                (u[i] - ex).abs() < 1e-12,
                "{kind:?}: DOF {d}: {} vs {ex}",
                u[i]
            );
        }
    }
}

#[test]
fn ring_under_diametral_loads_matches_curved_beam_theory() {
    // Thin ring (mean radius R, radial thickness h = R/25), quarter model with symmetry,
    // compressed by P along y: the horizontal diameter grows by P R³/(E I) (2/π − 1/2)
    // (Roark, thin ring under diametral loads: 0.1366 P R³/(E I)).
    let (rm, h, t) = (0.1, 0.004, 0.01);
    let p = 100.0;
    let sp = spec("fixed = []\nfixed_x = [\"edge_t1\"]\nfixed_y = [\"edge_t0\"]");
    for kind in [CellKind::Quad8, CellKind::Tri6] {
        let msh = ring_msh(
            kind,
            rm - h / 2.0,
            rm + h / 2.0,
            0.0,
            PI / 2.0,
            2,
            96,
            false,
        );
        let (mesh, m) = model_of(&msh, &sp);
        let mut f = vec![0.0; m.ndof];
        // P/2 on the quarter, at the outer node of the θ = 90° section, pointing down.
        let top = (0..mesh.nodes.len())
            .filter(|&i| m.node_dofs[i][1].is_some())
            .max_by(|&a, &b| mesh.nodes[a][1].total_cmp(&mesh.nodes[b][1]))
            .unwrap();
        f[m.node_dofs[top][1].unwrap()] = -p / 2.0;
        let u = solve(&m.k, &f);
        let mid = (0..mesh.nodes.len())
            .find(|&i| mesh.nodes[i][1].abs() < 1e-12 && (mesh.nodes[i][0] - rm).abs() < 1e-9)
            .expect("mid-thickness node on the x axis");
        let dx = 2.0 * u[m.node_dofs[mid][0].unwrap()];
        let i = t * h.powi(3) / 12.0;
        let theory = p * rm.powi(3) / (E * i) * (2.0 / PI - 0.5);
        eprintln!("diametral ring {kind:?}: Δd = {dx:.6e} m, curved-beam theory {theory:.6e} m");
        assert!(
            (dx / theory - 1.0).abs() < 0.005,
            "{kind:?}: Δd = {dx:.4e}, theory {theory:.4e}"
        );
    }
}

#[test]
fn clockwise_surfaces_are_renumbered_and_a_folded_cell_is_rejected() {
    let sp = spec("");
    let msh = ring_msh(CellKind::Quad4, 0.06, 0.08, 0.0, 2.0 * PI, 2, 32, true);
    // Mirror y: every cell becomes clockwise; the model must be the same (renumbered).
    let mirrored: String = {
        let mut out = String::new();
        let mut in_nodes = false;
        for l in msh.lines() {
            if l == "$Nodes" {
                in_nodes = true;
            } else if l == "$EndNodes" {
                in_nodes = false;
            }
            let w: Vec<&str> = l.split_whitespace().collect();
            if in_nodes && w.len() == 3 && w[0].contains('e') {
                let y: f64 = w[1].parse().unwrap();
                let _ = writeln!(out, "{} {:.17e} 0", w[0], -y);
            } else {
                let _ = writeln!(out, "{l}");
            }
        }
        out
    };
    let (_, a) = model_of(&msh, &sp);
    let (_, b) = model_of(&mirrored, &sp);
    assert!((a.contact_stiffness_bound() / b.contact_stiffness_bound() - 1.0).abs() < 1e-10);
    // Swap two nodes of one cell: a bow-tie among counter-clockwise cells.
    let mut lines: Vec<String> = msh.lines().map(str::to_string).collect();
    let first = lines.iter().position(|l| l.starts_with("2 1 3 ")).unwrap() + 1;
    let w: Vec<String> = lines[first]
        .split_whitespace()
        .map(str::to_string)
        .collect();
    lines[first] = format!("{} {} {} {} {}", w[0], w[1], w[3], w[2], w[4]);
    let bad = lines.join("\n") + "\n";
    let mesh = Mesh::parse(Path::new("folded.msh"), bad.as_bytes()).unwrap();
    let e = mesh_stator::from_spec(&mesh, &sp, 0, &[], PathBuf::from("folded.msh"), true)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("folded.msh") && e.contains("inverted") && e.contains("`stator`"),
        "{e}"
    );
}

// ---------------------------------------------------------------------------------------------
// The gmsh pipeline.

fn gmsh_available() -> bool {
    std::process::Command::new(gm::gmsh_program())
        .arg("--version")
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false)
}

/// The gmsh tests need gmsh; without it they fail (set RUBSIM_SKIP_GMSH=1 to skip them).
fn need_gmsh() -> bool {
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

fn repo(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

#[test]
fn gmsh_meshes_once_then_serves_the_cache() {
    if !need_gmsh() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut req = MeshRequest::new(repo("geometry/annulus.geo"));
    req.parameters.insert("h".into(), 0.006);
    let a = gm::mesh(&req, dir.path()).unwrap();
    assert!(!a.from_cache);
    let stamp = std::fs::metadata(&a.msh).unwrap().modified().unwrap();
    let b = gm::mesh(&req, dir.path()).unwrap();
    assert!(b.from_cache && b.msh == a.msh);
    assert_eq!(
        std::fs::metadata(&b.msh).unwrap().modified().unwrap(),
        stamp
    );
    // A different parameter is a different mesh.
    req.parameters.insert("h".into(), 0.005);
    let c = gm::mesh(&req, dir.path()).unwrap();
    assert!(!c.from_cache && c.msh != a.msh);
    let m = Mesh::read(&c.msh).unwrap();
    assert_eq!(m.dim(), 2);
    let n = m.boundary_normals("stator_contact").unwrap();
    for (i, v) in &n {
        let x = m.nodes[*i];
        let r = x[0].hypot(x[1]);
        assert!((r - 0.0601).abs() < 1e-9);
        // The inner circle's outward normal points to the axis.
        assert!(
            (v[0] + x[0] / r).abs() < 1e-2 && (v[1] + x[1] / r).abs() < 1e-2,
            "{v:?} at {x:?}"
        );
    }
}

#[test]
fn gmsh_errors_name_the_file_and_carry_gmshs_message() {
    if !need_gmsh() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let cache = d.join("meshes");
    // Syntax error: gmsh's own message with the line.
    std::fs::write(
        d.join("bad.geo"),
        "SetFactory(\"OpenCASCADE\");\nDisk(1) = {0, 0, 0, 1;\n",
    )
    .unwrap();
    let e = gm::mesh(&MeshRequest::new(d.join("bad.geo")), &cache)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bad.geo") && e.contains("gmsh failed") && e.contains("syntax error"),
        "{e}"
    );
    // A STEP file that does not exist, named by the geometry.
    std::fs::write(
        d.join("step.geo"),
        "SetFactory(\"OpenCASCADE\");\nv() = ShapeFromFile(\"part.step\");\n",
    )
    .unwrap();
    let e = gm::mesh(&MeshRequest::new(d.join("step.geo")), &cache)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("part.step") && e.contains("no such file") && e.contains("step.geo"),
        "{e}"
    );
    // A STEP file given directly that does not exist.
    let e = gm::mesh(&MeshRequest::new(d.join("missing.step")), &cache)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("missing.step") && e.contains("no such file"),
        "{e}"
    );
    // Unknown parameter.
    let mut req = MeshRequest::new(repo("geometry/annulus.geo"));
    req.parameters.insert("radius".into(), 1.0);
    let e = gm::mesh(&req, &cache).unwrap_err().to_string();
    assert!(
        e.contains("annulus.geo") && e.contains("`radius`") && e.contains("ri"),
        "{e}"
    );
    // gmsh missing (in a child process: the environment is process wide).
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rubsim"))
        .args([
            "mesh",
            repo("geometry/rod.geo").to_str().unwrap(),
            "--cache",
        ])
        .arg(d.join("other"))
        .env("RUBSIM_GMSH", "/nonexistent/gmsh")
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        e.contains("rod.geo") && e.contains("/nonexistent/gmsh") && e.contains("setup.sh"),
        "{e}"
    );
}

fn build_geo(geo_text: &str, name: &str, extra: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    let geo = dir.path().join(name);
    std::fs::write(&geo, geo_text).unwrap();
    let mut sp = spec(extra);
    sp.geometry = geo.display().to_string();
    let built = rubsim::resolve::mesh::load_mesh(&sp, &dir.path().join("scene.toml"))
        .map_err(rubsim::error::Error::from)
        .and_then(|(mesh, geo, cached)| mesh_stator::from_spec(&mesh, &sp, 0, &[], geo, cached));
    match built {
        Ok(_) => String::new(),
        Err(e) => e.to_string(),
    }
}

#[test]
fn bad_meshes_give_errors_naming_file_and_group() {
    if !need_gmsh() {
        return;
    }
    let ok = "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {-0.01, 0.061, 0, 0.02, 0.01};\nPhysical Surface(\"stator\") = {1};\nPhysical Curve(\"stator_contact\") = {1};\nPhysical Curve(\"stator_fixed\") = {3};\n";
    assert_eq!(build_geo(ok, "ok.geo", ""), "");
    // Misnamed contact group.
    let e = build_geo(
        &ok.replace("\"stator_contact\"", "\"contact\""),
        "misnamed.geo",
        "",
    );
    assert!(
        e.contains("misnamed") && e.contains("`stator_contact`") && e.contains("contact (dim 1)"),
        "{e}"
    );
    // Missing fixed group.
    let e = build_geo(
        &ok.replace("Physical Curve(\"stator_fixed\") = {3};\n", ""),
        "nofix.geo",
        "",
    );
    assert!(e.contains("nofix") && e.contains("`stator_fixed`"), "{e}");
    // Contact group of the wrong dimension.
    let e = build_geo(ok, "dim.geo", "contact_group = \"stator\"");
    assert!(
        e.contains("dim") && e.contains("`stator`") && e.contains("dimension"),
        "{e}"
    );
    // No surface group: nothing 2-D to build.
    let e = build_geo(
        &ok.replace("Physical Surface(\"stator\") = {1};\n", ""),
        "nosurf.geo",
        "",
    );
    assert!(e.contains("nosurf") && e.contains("empty mesh"), "{e}");
    // Two rectangles sharing an edge without being fused: non-conforming.
    let two = "SetFactory(\"OpenCASCADE\");\nRectangle(1) = {-0.01, 0.061, 0, 0.01, 0.01};\nRectangle(2) = {0, 0.061, 0, 0.01, 0.01};\nMesh.MeshSizeMax = 0.002;\nPhysical Surface(\"stator\") = {1, 2};\nPhysical Curve(\"stator_contact\") = {1, 5};\nPhysical Curve(\"stator_fixed\") = {3, 7};\n";
    let e = build_geo(two, "apart.geo", "");
    assert!(e.contains("apart") && e.contains("non-conforming"), "{e}");
    // Fused with BooleanFragments: fine.
    let fused = two.replace(
        "Mesh.MeshSizeMax",
        "BooleanFragments{ Surface{1}; Delete; }{ Surface{2}; Delete; }\nMesh.MeshSizeMax",
    );
    let e = build_geo(&fused, "fused.geo", "contact_group = \"stator\"");
    assert!(!e.contains("non-conforming"), "{e}");
}

#[test]
fn scene_with_meshed_rod_runs_and_matches_the_bar_model_stiffness() {
    if !need_gmsh() {
        return;
    }
    let ls = rubsim::scene::load(&repo("scenes/stators/rod2d.toml"), &[]).unwrap();
    let model = rubsim::model::Model::from_scene(&ls).unwrap();
    let case = model.case(1.7 * model.rotor.natural_frequency()).unwrap();
    let s = &case.stators[0];
    // E A / L of the bar model; the 2-D body pushed at its whole tip is slightly stiffer.
    let ks = 3e9 * 25e-6 / 0.04;
    let kb = s.contact_stiffness_bound();
    assert!(kb > ks && kb < 1.03 * ks, "{kb} vs {ks}");
    // Placed at its clearance: the tip's nearest node at δ = 0.6 |Z0| above the disk.
    assert!((s.clearance / (0.6 * case.z0) - 1.0).abs() < 1e-9);
}

// ---------------------------------------------------------------------------------------------
// 3-D: tetrahedra.

#[test]
fn element_eigenvalue_bound_is_above_the_true_one_and_below_gershgorin() {
    for kind in [CellKind::Quad4, CellKind::Tri6, CellKind::Quad8] {
        let msh = ring_msh(kind, 0.06, 0.08, 0.0, 2.0 * PI, 2, 24, true);
        let (_, m) = model_of(&msh, &spec("density = 7800.0"));
        let n = m.ndof;
        let k = nalgebra::DMatrix::from_fn(n, n, |i, j| m.k.get(i, j));
        let md = m.m.diagonal();
        let a = nalgebra::DMatrix::from_fn(n, n, |i, j| k[(i, j)] / (md[i] * md[j]).sqrt());
        let exact = a.symmetric_eigenvalues().max();
        let elem = m.mesh.as_ref().unwrap().omega_max_sq.unwrap();
        let used = m.omega_max_sq_bound();
        assert!(
            elem >= exact * (1.0 - 1e-9),
            "{kind:?}: element bound {elem:.4e} < exact {exact:.4e}"
        );
        assert!(
            elem < 2.0 * exact,
            "{kind:?}: element bound {elem:.4e} ≫ exact {exact:.4e}"
        );
        assert!(used <= elem && used >= exact * (1.0 - 1e-9));
        eprintln!(
            "{kind:?}: λ_max exact {exact:.4e}, element bound {elem:.4e} ({:.3}×)",
            elem / exact
        );
    }
}

#[test]
fn step_import_meshes_like_the_geometry_it_came_from() {
    if !need_gmsh() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let geo = gm::mesh(
        &MeshRequest::new(repo("geometry/labyrinth_seal.geo")),
        dir.path(),
    )
    .unwrap();
    let step = gm::mesh(
        &MeshRequest::new(repo("geometry/labyrinth_seal_step.geo")),
        dir.path(),
    )
    .unwrap();
    let (a, b) = (
        Mesh::read(&geo.msh).unwrap(),
        Mesh::read(&step.msh).unwrap(),
    );
    // Same part, same groups: the contact boundary and node counts agree closely.
    let (ca, cb) = (
        a.group_nodes("stator_contact").unwrap().len(),
        b.group_nodes("stator_contact").unwrap().len(),
    );
    assert_eq!(ca, cb);
    assert!((a.nodes.len() as f64 / b.nodes.len() as f64 - 1.0).abs() < 0.02);
    // The STEP file alone: bodies grouped as `stator`, boundary entities as `boundary_<tag>`.
    let raw = gm::mesh(
        &MeshRequest::new(repo("geometry/labyrinth_seal.step")),
        dir.path(),
    )
    .unwrap();
    let m = Mesh::read(&raw.msh).unwrap();
    assert_eq!(m.dim(), 3);
    assert_eq!(m.group("stator").unwrap().dim, 3);
    assert!(
        m.groups
            .iter()
            .filter(|g| g.name.starts_with("boundary_"))
            .count()
            >= 8
    );
    // Cache keys do not depend on where the repository lies (the STEP's path is not hashed).
    assert_eq!(
        step.key,
        gm::cache_key(&MeshRequest::new(repo("geometry/labyrinth_seal_step.geo"))).unwrap()
    );
}

#[test]
fn three_d_seal_scene_builds_with_tetrahedra() {
    if !need_gmsh() {
        return;
    }
    let ls = rubsim::scene::load(&repo("scenes/stators/labyrinth_seal.toml"), &[]).unwrap();
    let model = rubsim::model::Model::from_scene(&ls).unwrap();
    let case = model.case(model.rotor.natural_frequency()).unwrap();
    let s = &case.stators[0];
    let md = s.mesh.as_ref().unwrap();
    assert_eq!(md.dim, 3);
    assert!(s
        .elements
        .iter()
        .all(|e| matches!(e, StatorElement::Solid3 { .. })));
    // Geometry clearance: tooth tips at 60.2 mm around a 60 mm disk.
    assert!((s.clearance - 2e-4).abs() < 1e-9, "{}", s.clearance);
    // Every contact normal points toward the axis.
    for (t, n) in s.targets.iter().zip(&md.contact_normals) {
        let rubsim::model::Target::Node { x0, .. } = t else {
            panic!()
        };
        assert!(n[0] * x0[0] + n[1] * x0[1] < 0.0);
    }
}

#[test]
fn three_d_contact_nodes_face_the_station_at_their_axial_position() {
    if !need_gmsh() {
        return;
    }
    // An FE rotor with stations at z = 0.5 m (node 2) and 0.75 m (node 3); a two-tooth seal
    // whose teeth sit at those positions (pitch 0.25 m, centred at axial_origin = 0.625 m).
    let text = r#"
[rotor]
kind = "fe"
[[rotor.shaft]]
length = 1.5
outer_diameter = 0.05
elements = 6
material = "steel"
[[rotor.bearing]]
node = 0
stiffness = 1.0e6
[[rotor.bearing]]
node = 6
stiffness = 1.0e6
[[rotor.unbalance]]
node = 2
mass = 0.001
radius = 0.05
[[station]]
name = "a"
node = 2
radius = 0.06
[[station]]
name = "b"
node = 3
radius = 0.06
[[stator]]
kind = "mesh"
name = "seal"
station = "a"
stations = ["b"]
axial_origin = 0.625
geometry = "geometry/labyrinth_seal.geo"
parameters = { teeth = 2, pitch = 0.25, tooth = 0.005, margin = 0.005, h = 0.012, ht = 0.006 }
youngs_modulus = 70e9
poisson_ratio = 0.33
[run]
speed_ratio = 1.0
"#;
    let ls =
        rubsim::scene::parse(&repo("scenes/stators/two_station_seal.toml"), text, &[]).unwrap();
    let model = rubsim::model::Model::from_scene(&ls).unwrap();
    let case = model.case(model.rotor.natural_frequency()).unwrap();
    let s = &case.stators[0];
    let md = s.mesh.as_ref().unwrap();
    let mut seen = [0usize; 2];
    for (t, tg) in s.targets.iter().enumerate() {
        let rubsim::model::Target::Node { node, .. } = tg else {
            panic!()
        };
        let z = md.node_z[*node] + 0.625;
        let expect = if z < 0.625 { 0 } else { 1 };
        assert_eq!(s.target_station(t), expect, "node at z = {z}");
        seen[expect] += 1;
    }
    assert!(seen[0] > 0 && seen[1] > 0, "{seen:?}");
    assert_eq!(s.stations(), vec![0, 1]);
    // It runs: both stations can rub their tooth.
    let mut st = rubsim::analysis::RunSettings::from_run(&ls.scene.run, "y");
    st.step.revolutions = 6;
    st.transient_revolutions = 3;
    st.error_estimate = false;
    st.initial.u = [0.0, 3e-4];
    let r = rubsim::analysis::run_speed(&model, &st, 1.0, Default::default()).unwrap();
    assert!(
        r.stats.contact_steps > 0 && r.stats.min_gap > -1e-9,
        "{:?}",
        r.stats
    );
}
