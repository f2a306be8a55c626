//! The meshing pipeline of meshed stators: orientation and folded cells, the element bound of
//! the stable step, gmsh (cache, STEP import, its errors and ours naming the file and group),
//! scenes with meshed stators built into models, and 3-D contact nodes assigned to the station
//! at their axial position.
//!
//! Structured polar meshes are written as MSH 4.1 text (`common::meshes`) and go through the same
//! reader and assembler as gmsh's meshes; the gmsh tests need `gmsh` on the PATH
//! (scripts/setup.sh). The solid elements' verification is in `verification.rs` and
//! `convergence.rs`; `rubsim mesh` on the command line in `cli.rs`.

use crate::common;

use common::cli::command;
use common::meshes::{model_of, need_gmsh, ring_msh, spec};
use common::{data, file_model, repo, settings, NO_SETS};
use rubsim::mesh::gmsh::{self as gm, MeshRequest};
use rubsim::mesh::{CellKind, Mesh};
use rubsim::model::stator::mesh as mesh_stator;
use rubsim::model::stator::StatorElement;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------------
// The model of a mesh.

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

// ---------------------------------------------------------------------------------------------
// The gmsh pipeline.

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
    let out = command(&repo(""))
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

/// Builds a meshed stator from the geometry `geo_text` (written as `name` in a temporary
/// directory, with the spec lines `extra`): the error message, empty when it builds.
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

/// The seal geometry's `hxt = 1` meshes its volume with gmsh's HXT (3.6× faster at 10⁶ cells,
/// docs/PERFORMANCE.md §12.2): another tetrahedral mesh of the same surfaces, so the same
/// contact nodes, while the default stays gmsh's Delaunay mesh.
#[test]
fn the_seal_meshes_with_hxt_on_request_over_the_same_contact_surface() {
    if !need_gmsh() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut hxt = MeshRequest::new(repo("geometry/labyrinth_seal.geo"));
    hxt.parameters.insert("hxt".into(), 1.0);
    let (a, b) = (
        gm::mesh(
            &MeshRequest::new(repo("geometry/labyrinth_seal.geo")),
            dir.path(),
        )
        .unwrap(),
        gm::mesh(&hxt, dir.path()).unwrap(),
    );
    assert_ne!(a.key, b.key);
    let (a, b) = (Mesh::read(&a.msh).unwrap(), Mesh::read(&b.msh).unwrap());
    let contact = |m: &Mesh| m.group_nodes("stator_contact").unwrap().len();
    assert_eq!(contact(&a), contact(&b));
    assert_ne!(a.nodes.len(), b.nodes.len(), "HXT gave the Delaunay mesh");
    assert!((a.nodes.len() as f64 / b.nodes.len() as f64 - 1.0).abs() < 0.05);
    assert_eq!(b.dim(), 3);
}

/// The seal geometry's `hi` refines the seal's inside while its tooth tips keep their mesh:
/// the same contact nodes — the same contact problem — over 5× the nodes (the flatness of the
/// contact work in the interior DOFs is tested on it at 10⁶ DOFs, tests/suite/large_stator.rs).
#[test]
fn the_seal_interior_refines_with_hi_over_the_same_contact_nodes() {
    if !need_gmsh() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut fine = MeshRequest::new(repo("geometry/labyrinth_seal.geo"));
    fine.parameters.insert("hi".into(), 0.001);
    fine.parameters.insert("hxt".into(), 1.0);
    let (a, b) = (
        gm::mesh(
            &MeshRequest::new(repo("geometry/labyrinth_seal.geo")),
            dir.path(),
        )
        .unwrap(),
        gm::mesh(&fine, dir.path()).unwrap(),
    );
    let (a, b) = (Mesh::read(&a.msh).unwrap(), Mesh::read(&b.msh).unwrap());
    let tips = |m: &Mesh| {
        let n = m.group_nodes("stator_contact").unwrap();
        n.iter().map(|&i| m.nodes[i]).collect::<Vec<_>>()
    };
    let (ta, tb) = (tips(&a), tips(&b));
    assert_eq!(ta.len(), tb.len(), "the tips' nodes changed in number");
    // Each tip node of the refined mesh is one of the shipped mesh's (to the file's digits).
    let dist = |p: &[f64; 3], q: &[f64; 3]| (0..3).map(|k| (p[k] - q[k]).powi(2)).sum::<f64>();
    let worst = tb
        .iter()
        .map(|p| ta.iter().map(|q| dist(p, q)).fold(f64::INFINITY, f64::min))
        .fold(0.0, f64::max)
        .sqrt();
    assert!(worst < 1e-7, "a tip node moved by {worst:e} m");
    assert!(
        b.nodes.len() > 5 * a.nodes.len(),
        "{} → {} nodes",
        a.nodes.len(),
        b.nodes.len()
    );
}

// ---------------------------------------------------------------------------------------------
// Scenes with meshed stators.

#[test]
fn scene_with_meshed_rod_runs_and_matches_the_bar_model_stiffness() {
    if !need_gmsh() {
        return;
    }
    let (_, model) = file_model(&repo("scenes/stators/rod2d.toml"), NO_SETS);
    let case = model.case(1.7 * model.rotor.natural_frequency()).unwrap();
    let s = &case.stators[0];
    // E A / L of the bar model; the 2-D body pushed at its whole tip is slightly stiffer.
    let ks = 3e9 * 25e-6 / 0.04;
    let kb = s.contact_stiffness_bound();
    assert!(kb > ks && kb < 1.03 * ks, "{kb} vs {ks}");
    // Placed at its clearance: the tip's nearest node at δ = 0.6 |Z0| above the disk.
    assert!((s.clearance / (0.6 * case.z0) - 1.0).abs() < 1e-9);
}

#[test]
fn three_d_seal_scene_builds_with_tetrahedra() {
    if !need_gmsh() {
        return;
    }
    let (_, model) = file_model(&repo("scenes/stators/labyrinth_seal.toml"), NO_SETS);
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
    let (ls, model) = file_model(&data("two_station_seal.toml"), NO_SETS);
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
    let mut st = settings(&ls);
    st.step.revolutions = 6;
    st.step.transient_revolutions = 3;
    st.error_estimate = false;
    st.check_coexistence = false;
    st.initial.u = [0.0, 3e-4];
    // A fixed 6-revolution window: contact and penetration are asserted, not the steady state
    // or the regime, so the transient is not lengthened waiting for a steady state (up to
    // 5 × the scene's default 100 revolutions) nor the window for the 0-1 test (the orbit is
    // not periodic).
    st.max_transient_revolutions = 3;
    st.classify_revolutions = 0;
    let r = rubsim::analysis::run_speed(&model, &st.request(1.0), Default::default()).unwrap();
    assert!(
        r.stats.contact_steps > 0 && r.stats.min_gap > -1e-9,
        "{:?}",
        r.stats
    );
}

/// A refinement of one geometry: (file in geometry/, fixed parameters, the refining parameter,
/// its values coarse to fine, quadrilaterals).
type Refinement = (
    &'static str,
    &'static [(&'static str, f64)],
    &'static str,
    &'static [f64],
    bool,
);

/// The refinements of the fast tier: every geometry of geometry/, coarse (a few seconds in all).
/// The annulus with a fixed boundary count `n` and an `h` well below its spacing is issue 31's
/// reproducer: gmsh's Frontal-Delaunay gave 2 462 nodes at h = 0.002 and 512 at 0.001 (the
/// geometry now switches to gmsh's Delaunay there).
const FAST_REFINEMENTS: &[Refinement] = &[
    (
        "annulus.geo",
        &[("ri", 0.0602), ("n", 128.0)],
        "h",
        &[0.004, 0.002, 0.001],
        true,
    ),
    (
        "annulus.geo",
        &[("ri", 0.0602), ("n", 64.0)],
        "h",
        &[0.004, 0.002, 0.001],
        false,
    ),
    (
        "annulus.geo",
        &[("ri", 0.06005), ("ni", 256.0)],
        "h",
        &[0.004, 0.002],
        true,
    ),
    ("annulus.geo", &[], "h", &[0.004, 0.002], false),
    (
        "diaphragm.geo",
        &[("hc", 0.003)],
        "h",
        &[0.006, 0.004, 0.0025],
        false,
    ),
    (
        "segmented_casing.geo",
        &[("hc", 0.002)],
        "h",
        &[0.004, 0.003, 0.0018],
        false,
    ),
    (
        "labyrinth_seal.geo",
        &[("ht", 0.002)],
        "h",
        &[0.005, 0.004],
        false,
    ),
    (
        "labyrinth_seal_step.geo",
        &[("ht", 0.002)],
        "h",
        &[0.005, 0.004],
        false,
    ),
    ("rod.geo", &[("nx", 4.0)], "ny", &[8.0, 16.0, 32.0], true),
];

/// Finer refinements (tens of thousands of nodes, 3-D meshes below the tooth size): the slow
/// tier.
const SLOW_REFINEMENTS: &[Refinement] = &[
    (
        "annulus.geo",
        &[("ri", 0.0602), ("n", 128.0)],
        "h",
        &[0.001, 0.0007, 0.0005],
        true,
    ),
    (
        "annulus.geo",
        &[("ri", 0.0602), ("n", 256.0)],
        "h",
        &[0.002, 0.001, 0.0005],
        true,
    ),
    (
        "diaphragm.geo",
        &[("hc", 0.002)],
        "h",
        &[0.003, 0.0015],
        false,
    ),
    (
        "segmented_casing.geo",
        &[("hc", 0.002)],
        "h",
        &[0.0015, 0.001],
        false,
    ),
    (
        "labyrinth_seal.geo",
        &[("ht", 0.0015)],
        "h",
        &[0.003, 0.002, 0.0012],
        false,
    ),
    (
        "labyrinth_seal_step.geo",
        &[("ht", 0.0015)],
        "h",
        &[0.003, 0.002],
        false,
    ),
    ("rod.geo", &[("ny", 16.0)], "nx", &[4.0, 8.0], true),
];

/// Meshes every refinement of `cases` and requires more nodes at each step; first checks that
/// every geometry in geometry/ has one (a new geometry must be added).
fn refines_monotonically(cases: &[Refinement]) {
    let mut listed: Vec<&str> = cases.iter().map(|c| c.0).collect();
    listed.sort_unstable();
    listed.dedup();
    let mut shipped: Vec<String> = std::fs::read_dir(repo("geometry"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".geo"))
        .collect();
    shipped.sort_unstable();
    assert_eq!(
        listed, shipped,
        "every geometry in geometry/ must be tested here"
    );
    let dir = tempfile::tempdir().unwrap();
    for (geo, fixed, key, values, quads) in cases {
        let mut counts = Vec::new();
        for v in *values {
            let mut req = MeshRequest::new(repo("geometry").join(geo));
            req.recombine = *quads;
            for (k, x) in *fixed {
                req.parameters.insert((*k).into(), *x);
            }
            req.parameters.insert((*key).into(), *v);
            let m = Mesh::read(&gm::mesh(&req, dir.path()).unwrap().msh).unwrap();
            counts.push((*v, m.nodes.len()));
        }
        for w in counts.windows(2) {
            assert!(
                w[1].1 > w[0].1,
                "{geo} {fixed:?}: {key} = {} gives {} nodes, {key} = {} gave {} (all: {counts:?})",
                w[1].0,
                w[1].1,
                w[0].0,
                w[0].1
            );
        }
    }
}

/// Issue 31 item 3: refining a geometry's size parameter never gives a coarser mesh, for every
/// geometry in geometry/ ([`FAST_REFINEMENTS`]).
#[test]
fn every_geometry_refines_monotonically_with_its_size_parameter() {
    if need_gmsh() {
        refines_monotonically(FAST_REFINEMENTS);
    }
}

/// [`every_geometry_refines_monotonically_with_its_size_parameter`] at finer sizes
/// ([`SLOW_REFINEMENTS`]).
#[test]
#[ignore = "slow tier (scripts/test-slow.sh): every geometry refined to tens of thousands of nodes"]
fn every_geometry_refines_monotonically_at_fine_sizes() {
    if need_gmsh() {
        refines_monotonically(SLOW_REFINEMENTS);
    }
}
