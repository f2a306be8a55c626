//! VTK and HDF5 time series (issue 5): frame plans and the grid layout, frame counts, values
//! read back with `vtkio` and `hdf5-metno` against the run's own numbers, physical consistency
//! of the stress recovery, streaming into the staging folder, reruns, per-speed sweeps, the
//! free-space check. (Faults in the output settings on the command line: `cli.rs`.)

use crate::common;

use common::cli::command;
use common::meshes::gmsh_wanted;
use common::output::{array, cells, has_array, ints, points, pvd, run, vectors3, vtu};
use common::{data, file_model, repo, settings, NO_SETS};
use rubsim::output::MANIFEST;
use rubsim::results::{FramePlan, Layout};
use rubsim::time::plan_steps;
use vtkio::model::CellType;

// ---------------------------------------------------------------------------------------------
// Frame plan and layout.

#[test]
fn frame_plan_counts_and_window() {
    let (ls, model) = file_model(&data("single.toml"), NO_SETS);
    let s = settings(&ls);
    let case = model.case(1.7 * model.rotor.natural_frequency()).unwrap();
    let plan = plan_steps(&case, &s.step).unwrap();
    let spec = |every: Option<usize>, from: f64, to: Option<f64>| rubsim::scene::SeriesSpec {
        every,
        fields: rubsim::scene::all_series_fields(),
        from_revolution: from,
        to_revolution: to,
    };
    // Default: the recording interval over the whole run.
    let fp = FramePlan::new(&spec(None, 0.0, None), &plan);
    assert_eq!(fp.every, plan.record_every);
    assert_eq!(fp.count(), plan.steps / plan.record_every + 1);
    // A window of two revolutions every 7 steps: frames at multiples of 7 inside it.
    let fp = FramePlan::new(&spec(Some(7), 3.0, Some(5.0)), &plan);
    let frames: Vec<usize> = (0..=plan.steps).filter(|k| fp.contains(*k)).collect();
    assert_eq!(frames.len(), fp.count());
    assert!(frames.iter().all(|k| k % 7 == 0));
    assert!(frames[0] >= 3 * plan.steps_per_rev && frames[0] < 3 * plan.steps_per_rev + 7);
    assert!(*frames.last().unwrap() <= 5 * plan.steps_per_rev);
}

#[test]
fn layout_maps_every_element_and_pair() {
    let (_, model) = file_model(&data("fe_arc.toml"), NO_SETS);
    let case = model.case(1.7 * model.rotor.natural_frequency()).unwrap();
    let l = Layout::new(&model, &case);
    let s = &case.stators[0];
    assert_eq!(l.num_points(), s.nodes.len() + 1);
    assert!(l.element_cells[0].iter().all(|c| c.is_some()));
    assert_eq!(l.pairs.len(), s.targets.len());
    assert_eq!(l.grid.num_cells(), s.elements.len() + 1 + s.targets.len());
    for (i, p) in l.pairs.iter().enumerate() {
        assert_eq!(l.pair_index(0, p.node), Some(i));
        assert_eq!(
            l.grid.cell(l.body_cells + i),
            &[p.rotor_point as i64, p.stator_point as i64]
        );
    }
}

/// A 3-D seal facing two stations of an FE rotor: its points sit at the mesh's z shifted by
/// `axial_origin` (the rotor's frame), and each pair's line starts at the rotor node of the
/// station its tooth-tip node faces.
#[test]
fn layout_places_3d_stators_at_their_axial_position() {
    if !gmsh_wanted() {
        return;
    }
    let (_, model) = file_model(&data("two_station_seal.toml"), NO_SETS);
    let case = model.case(model.rotor.natural_frequency()).unwrap();
    let l = Layout::new(&model, &case);
    let s = &case.stators[0];
    let md = s.mesh.as_ref().unwrap();
    for (n, p) in s.nodes.iter().enumerate() {
        assert_eq!(l.grid.points[n], [p[0], p[1], md.node_z[n] + 0.625]);
    }
    let rotor_z = &l.grid.points[l.rotor_first_point..];
    assert_eq!(rotor_z.len(), 7);
    assert!((rotor_z[2][2] - 0.5).abs() < 1e-12 && (rotor_z[3][2] - 0.75).abs() < 1e-12);
    let mut seen = [0; 2];
    for (t, p) in l.pairs.iter().enumerate() {
        let station = s.target_station(t);
        assert_eq!(p.station, station);
        assert_eq!(
            p.rotor_point,
            l.rotor_first_point + case.stations[station].node
        );
        // The tooth-tip node is within a tooth's half-thickness of its station's plane.
        let dz = l.grid.points[p.stator_point][2] - rotor_z[case.stations[station].node][2];
        assert!(dz.abs() <= 0.0025 + 1e-9, "pair {t}: {dz}");
        seen[station] += 1;
    }
    assert!(seen[0] > 0 && seen[1] > 0, "{seen:?}");
}

// ---------------------------------------------------------------------------------------------
// VTK frames.

/// The rod: every written frame's bar axial force balances the contact force on the tip
/// (massless stator in static equilibrium), the `.pvd` lists the frames with increasing times,
/// and the rotor displacement in the `.vtu` is the analysed orbit.
#[test]
fn vtk_frames_hold_the_run() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let (r, files) = run(
        "single.toml",
        &["output.vtk={ from_revolution = 20 }"],
        &dir,
    );
    let spr = 64;
    let frames = pvd(&dir.join("results.pvd"));
    // Revolutions 20…30 at the recording interval: 10·64 + 1 frames.
    assert_eq!(frames.len(), 10 * spr + 1);
    assert_eq!(files.len(), frames.len() + 1, "the frames and the .pvd");
    assert!(frames.windows(2).all(|w| w[1].0 > w[0].0));
    let z0 = r.z0;
    let mut contact_frames = 0;
    for (k, (t, file)) in frames.iter().enumerate() {
        let g = vtu(&dir.join(file));
        let d = array(&g.data.point, "displacement");
        // Points: rod tip, rod base, rotor centre.
        assert_eq!(d.len(), 9);
        // The Jeffcott rotor has no θ_z: no twist arrays; it moves in its plane.
        assert!(!has_array(&g.data.point, "twist") && !has_array(&g.data.point, "twist_rate"));
        assert_eq!(d[8], 0.0);
        // Frame k is sample 20·64 + k of the record; the orbit window holds samples
        // 10·64 … 30·64 − 1.
        if k < spr * 10 {
            let o = r.orbit_nd[10 * spr + k];
            assert!(
                (d[6] - o[0] * z0).abs() <= 1e-12 * z0 && (d[7] - o[1] * z0).abs() <= 1e-12 * z0,
                "frame {k} at t = {t}: {:?} vs {:?}",
                &d[6..8],
                [o[0] * z0, o[1] * z0]
            );
        }
        let n = array(&g.data.cell, "normal_force");
        let axial = array(&g.data.cell, "axial_force");
        let cf = array(&g.data.point, "contact_force");
        if n.len() == 3 {
            // Bar, rotor vertex, contact line.
            contact_frames += 1;
            assert!(n[2] > 0.0);
            // Tip force (n + μa)p on the stator; the bar along +y carries −F_y (compression).
            assert!(
                (axial[0] + cf[1]).abs() <= 1e-9 * cf[1].abs(),
                "{axial:?} {cf:?}"
            );
            // Rotor gets the opposite.
            assert!((cf[6] + cf[0]).abs() < 1e-12 && (cf[7] + cf[1]).abs() < 1e-12);
        } else {
            assert_eq!(n, vec![0.0, 0.0]);
            assert!(axial[0].abs() < 1e-12);
        }
    }
    assert!(
        contact_frames > 10 && contact_frames < frames.len(),
        "{contact_frames}"
    );
}

#[test]
fn rerun_replaces_series_and_sweep_writes_chosen_speeds() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    run(
        "single.toml",
        &["output.vtk={ from_revolution = 29 }"],
        &dir,
    );
    let n1 = pvd(&dir.join("results.pvd")).len();
    assert_eq!(n1, 65);
    assert!(dir.join("vtk/frame_000064.vtu").exists());
    // A shorter window: the frames of the first run beyond it are gone, the manifest agrees.
    run(
        "single.toml",
        &["output.vtk={ from_revolution = 29, to_revolution = 29.5 }"],
        &dir,
    );
    let n2 = pvd(&dir.join("results.pvd")).len();
    assert_eq!(n2, 33);
    assert!(!dir.join("vtk/frame_000064.vtu").exists());
    assert!(dir.join("vtk/frame_000032.vtu").exists());
    let manifest = std::fs::read_to_string(dir.join(MANIFEST)).unwrap();
    assert_eq!(manifest.lines().filter(|l| l.ends_with(".vtu")).count(), 33);
    // No staging folder is left behind.
    assert!(std::fs::read_dir(&dir).unwrap().all(|e| !e
        .unwrap()
        .file_name()
        .to_string_lossy()
        .starts_with(".rubsim-partial")));

    // A sweep writes only the speeds asked for, into sub-folders.
    let sweep = command(&repo(""))
        .args(["sweep", data("sweep.toml").to_str().unwrap(), "--out"])
        .arg(tmp.path().join("sw"))
        .args([
            "--set",
            "output.vtk={ from_revolution = 29 }",
            "--set",
            "output.per_speed=[1.5]",
            "--set",
            "run.revolutions=30",
            "--set",
            "run.transient_revolutions=10",
        ])
        .output()
        .unwrap();
    assert!(
        sweep.status.success(),
        "{}",
        String::from_utf8_lossy(&sweep.stderr)
    );
    let folders: Vec<String> = std::fs::read_dir(tmp.path().join("sw"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter(|n| n.starts_with("speed_"))
        .collect();
    assert_eq!(folders, vec!["speed_1.5".to_string()]);
    assert_eq!(pvd(&tmp.path().join("sw/speed_1.5/results.pvd")).len(), 65);
}

/// A ring stator is drawn as its contact circle, moved by the ring's displacement, and its pair
/// line ends on the ring where it faces the section centre.
#[test]
fn ring_stator_is_drawn_as_its_contact_circle() {
    use rubsim::results::RING_POINTS;
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("out");
    let sets: &[&str] = &["output.vtk={ every = 16 }", "output.hdf5={}"];
    #[cfg(not(feature = "hdf5"))]
    let sets = &sets[..1];
    let (_, model) = file_model(&data("ring.toml"), sets);
    let case = model.case(1.7 * model.rotor.natural_frequency()).unwrap();
    let rubsim::model::Target::Ring {
        center0,
        inner_radius: big_r,
        ..
    } = case.stators[0].targets[0]
    else {
        panic!("a ring target")
    };
    let r = case.stations[0].radius;
    assert!(big_r > r);
    run("ring.toml", sets, &dir);
    let frames = pvd(&dir.join("results.pvd"));
    // The whole run every 16 steps: free at first, then rubbing.
    assert!(frames.len() > 100, "{}", frames.len());
    // Points: ring centre, circle, contact point P, rotor centre.
    let (circle, p, rotor) = (1, 1 + RING_POINTS, 2 + RING_POINTS);
    let mut moved = 0.0_f64;
    let mut contact = 0;
    for (_, file) in &frames {
        let g = vtu(&dir.join(file));
        let x = points(&g);
        assert_eq!(x.len(), 3 + RING_POINTS);
        let d = vectors3(&g.data.point, "displacement");
        let us = d[0];
        assert_eq!(x[0], [center0[0], center0[1], 0.0]);
        moved = moved.max(us[0].hypot(us[1]));
        // Displaced ring centre.
        let c = [center0[0] + us[0], center0[1] + us[1]];
        for i in 0..RING_POINTS {
            let k = circle + i;
            // Undeformed on the circle at θ_i, translated with the ring.
            let th = std::f64::consts::TAU * i as f64 / RING_POINTS as f64;
            assert!(
                (x[k][0] - center0[0] - big_r * th.cos()).abs() <= 1e-15 * big_r
                    && (x[k][1] - center0[1] - big_r * th.sin()).abs() <= 1e-15 * big_r
            );
            assert_eq!(d[k], us);
            let q = [x[k][0] + d[k][0] - c[0], x[k][1] + d[k][1] - c[1]];
            assert!(
                (q[0].hypot(q[1]) - big_r).abs() <= 1e-12 * big_r,
                "point {k}: {} vs R = {big_r}",
                q[0].hypot(q[1])
            );
        }
        let cl = cells(&g);
        let closed: Vec<usize> = (circle..circle + RING_POINTS)
            .chain(std::iter::once(circle))
            .collect();
        assert_eq!(cl[0], (CellType::PolyLine, closed));
        assert_eq!(cl[1], (CellType::Vertex, vec![rotor]));
        let part = ints(&g.data.cell, "part");
        let index = ints(&g.data.cell, "index");
        // The circle is a stator cell that is no element; then the rotor.
        assert_eq!((part[0], index[0]), (0, -1));
        assert_eq!((part[1], index[1]), (1, 0));
        // The contact point: the ring's surface point facing the section centre,
        // x_C + (r + g) n with n from the ring centre to the section centre.
        assert_eq!(d[p], us);
        let xc = [d[rotor][0], d[rotor][1]];
        let v = [xc[0] - c[0], xc[1] - c[1]];
        let l = v[0].hypot(v[1]);
        // (1, 0) when the centres coincide (at rest, step 0), as the contact kernel.
        let n = if l > 0.0 {
            [v[0] / l, v[1] / l]
        } else {
            [1.0, 0.0]
        };
        let gap = big_r - r - l;
        let pp = [x[p][0] + d[p][0], x[p][1] + d[p][1]];
        for k in 0..2 {
            assert!(
                (pp[k] - (c[k] + big_r * n[k])).abs() <= 1e-12 * big_r
                    && (pp[k] - (xc[k] + (r + gap) * n[k])).abs() <= 1e-12 * big_r,
                "{pp:?} vs {:?}",
                [c[0] + big_r * n[0], c[1] + big_r * n[1]]
            );
        }
        let nf = array(&g.data.cell, "normal_force");
        let cf = vectors3(&g.data.point, "contact_force");
        if cl.len() == 3 {
            contact += 1;
            assert_eq!(cl[2], (CellType::Line, vec![rotor, p]));
            assert!(nf[2] > 0.0);
            // The force acts on the ring at its centre (its DOFs) and pushes it outward along
            // n; the rotor gets the opposite; P carries none.
            assert!(cf[0][0] * n[0] + cf[0][1] * n[1] > 0.0);
            assert_eq!([cf[rotor][0], cf[rotor][1]], [-cf[0][0], -cf[0][1]]);
            assert_eq!(cf[p], [0.0; 3]);
        } else {
            assert_eq!(cl.len(), 2);
            assert!(cf[0] == [0.0; 3]);
        }
    }
    // The ring moves (by more than a hundredth of the clearance) and is rubbed.
    assert!(moved > 0.01 * (big_r - r), "ring moved by {moved}");
    assert!(contact > 0 && contact < frames.len(), "{contact}");
    #[cfg(feature = "hdf5")]
    {
        // The static VTKHDF grid: the same circle, P at the ring centre, the pair line.
        let f = crate::common::output::open_h5(&dir.join("results.vtkhdf"));
        let pts: Vec<f64> = f.dataset("VTKHDF/Points").unwrap().read_raw().unwrap();
        let g = vtu(&dir.join(&frames[0].1));
        let x = points(&g);
        for k in (0..3 + RING_POINTS).filter(|k| *k != p) {
            assert_eq!(&pts[3 * k..3 * k + 3], &x[k][..]);
        }
        assert_eq!(&pts[3 * p..3 * p + 3], &[center0[0], center0[1], 0.0]);
        let conn: Vec<i64> = f
            .dataset("VTKHDF/Connectivity")
            .unwrap()
            .read_raw()
            .unwrap();
        assert_eq!(conn[conn.len() - 2..], [rotor as i64, p as i64]);
        let types: Vec<u8> = f.dataset("VTKHDF/Types").unwrap().read_raw().unwrap();
        assert_eq!(types, vec![4, 1, 3]);
        let st = f.group("stators/0").unwrap();
        let num = |a: &str| -> i64 { st.attr(a).unwrap().read_scalar().unwrap() };
        assert_eq!(
            (num("num_nodes"), num("num_points")),
            (1, 2 + RING_POINTS as i64)
        );
    }
}

/// VTK's edges of the 10-node tetrahedron, mid-edge nodes 4…9 (`VTK_QUADRATIC_TETRA`).
const VTK_TET10_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];

/// 3-D labyrinth seal (one tooth, coarse Tet4 and Tet10 meshes): every tetrahedron is a VTK
/// cell in VTK's node order with positive volume, points sit at the mesh's z, displacements
/// carry u_z (the written centroid stress is the von Mises stress of the written displacement
/// field), and the VTKHDF grid holds the same cells, points and data.
#[test]
fn tetrahedral_stator_cells_in_vtk_and_hdf5() {
    use rubsim::element::solid3d;
    use rubsim::mesh::CellKind;
    use rubsim::model::stator::StatorElement;
    if !gmsh_wanted() {
        return;
    }
    for (kind, vtk_type, extra) in [
        (CellKind::Tet4, CellType::Tetra, vec![]),
        (
            CellKind::Tet10,
            CellType::QuadraticTetra,
            vec![
                "stator.0.order=2",
                "run.revolutions=1",
                "run.transient_revolutions=0",
            ],
        ),
    ] {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let mut sets = vec!["output.vtk={ every = 960 }", "output.hdf5={ every = 960 }"];
        #[cfg(not(feature = "hdf5"))]
        sets.pop();
        sets.extend(extra);
        let (_, model) = file_model(&data("seal3d.toml"), &sets);
        let case = model.case(model.rotor.natural_frequency()).unwrap();
        let s = &case.stators[0];
        let md = s.mesh.as_ref().unwrap();
        assert_eq!(md.dim, 3);
        let nn = s.nodes.len();
        let ne = s.elements.len();
        run("seal3d.toml", &sets, &dir);
        let frames = pvd(&dir.join("results.pvd"));
        // The frame with the most pairs in contact.
        let (k, g) = frames
            .iter()
            .enumerate()
            .map(|(k, (_, f))| (k, vtu(&dir.join(f))))
            .max_by_key(|(_, g)| cells(g).len())
            .unwrap();
        #[cfg(not(feature = "hdf5"))]
        let _ = k; // the frame index serves the comparison with the HDF5 file
        let cl = cells(&g);
        assert!(cl.len() > ne + 1, "{kind:?}: no pair in contact");
        let x = points(&g);
        assert_eq!(x.len(), nn + 1);
        for (n, (p, z)) in s.nodes.iter().zip(&md.node_z).enumerate() {
            assert_eq!(x[n], [p[0], p[1], *z], "node {n}");
        }
        // The seal spans the station plane (one tooth of 2 mm in a 6 mm carrier).
        let (zmin, zmax) = x[..nn]
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                (a.min(p[2]), b.max(p[2]))
            });
        assert!(zmin < -2e-3 && zmax > 2e-3, "{zmin} {zmax}");
        let d = vectors3(&g.data.point, "displacement");
        let stress = array(&g.data.cell, "stress");
        let smax = stress[..ne].iter().fold(0.0_f64, |a, b| a.max(*b));
        assert!(smax > 0.0);
        // u_z is written: not all zero, zero where it is fixed.
        assert!(d[..nn].iter().any(|v| v[2] != 0.0));
        for (v, a) in d.iter().zip(&md.axial_dofs) {
            if a.is_none() {
                assert_eq!(v[2], 0.0);
            }
        }
        for (e, el) in s.elements.iter().enumerate() {
            let StatorElement::Solid3 {
                kind: ek,
                nodes,
                material,
            } = el
            else {
                panic!("element {e} is not a tetrahedron")
            };
            assert_eq!(*ek, kind);
            let mut vtk_nodes = nodes.clone();
            if kind == CellKind::Tet10 {
                vtk_nodes.swap(8, 9);
            }
            assert_eq!(cl[e], (vtk_type, vtk_nodes.clone()), "cell {e}");
            // In VTK's order: positive volume of the corners, mid-edge nodes on VTK's edges.
            let p = |i: usize| x[vtk_nodes[i]];
            let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
            let (a, b, c) = (sub(p(1), p(0)), sub(p(2), p(0)), sub(p(3), p(0)));
            let vol = (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0;
            assert!(vol > 0.0, "cell {e}: volume {vol}");
            if kind == CellKind::Tet10 {
                for (m, (i, j)) in VTK_TET10_EDGES.into_iter().enumerate() {
                    let mid = [
                        0.5 * (p(i)[0] + p(j)[0]),
                        0.5 * (p(i)[1] + p(j)[1]),
                        0.5 * (p(i)[2] + p(j)[2]),
                    ];
                    let off = sub(p(4 + m), mid);
                    let len = sub(p(i), p(j));
                    let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    // Curved boundary edges bow a little; a misplaced node is half an edge off.
                    assert!(norm(off) <= 0.05 * norm(len), "cell {e} edge {m}");
                }
            }
            // Centroid von Mises stress of the written field (gmsh order for the kernel).
            let xe: Vec<[f64; 3]> = nodes.iter().map(|n| x[*n]).collect();
            let ue: Vec<f64> = nodes.iter().flat_map(|n| d[*n]).collect();
            let sv =
                solid3d::von_mises(material.stress(solid3d::strain(kind, &xe, &ue, [0.25; 3])));
            assert!(
                (sv - stress[e]).abs() <= 1e-9 * smax,
                "cell {e}: {sv} vs {}",
                stress[e]
            );
        }
        // Pairs: lines from the rotor node to tooth-tip nodes.
        for (t, cell) in cl[ne + 1..].iter() {
            assert_eq!(*t, CellType::Line);
            assert_eq!(cell[0], nn);
            assert!(s.targets.iter().any(|tg| matches!(
                tg,
                rubsim::model::Target::Node { node, .. } if *node == cell[1]
            )));
        }
        #[cfg(feature = "hdf5")]
        {
            let f = crate::common::output::open_h5(&dir.join("results.vtkhdf"));
            let read_f = |n: &str| -> Vec<f64> { f.dataset(n).unwrap().read_raw().unwrap() };
            let read_i = |n: &str| -> Vec<i64> { f.dataset(n).unwrap().read_raw().unwrap() };
            let types: Vec<u8> = f.dataset("VTKHDF/Types").unwrap().read_raw().unwrap();
            assert!(types[..ne].iter().all(|t| *t == vtk_type as u8));
            let conn = read_i("VTKHDF/Connectivity");
            let off = read_i("VTKHDF/Offsets");
            for (e, (_, ids)) in cl[..ne].iter().enumerate() {
                let c: Vec<usize> = conn[off[e] as usize..off[e + 1] as usize]
                    .iter()
                    .map(|i| *i as usize)
                    .collect();
                assert_eq!(&c, ids);
            }
            let pts = read_f("VTKHDF/Points");
            assert_eq!(pts, x.iter().flatten().copied().collect::<Vec<_>>());
            let ax = read_i("stators/0/axial_dofs");
            let expect: Vec<i64> = md
                .axial_dofs
                .iter()
                .map(|a| a.map_or(-1, |a| a as i64))
                .collect();
            assert_eq!(ax, expect);
            // Same frames in both writers: frame k of the VTKHDF series is the .vtu's.
            let np = nn + 1;
            let disp = read_f("VTKHDF/PointData/displacement");
            assert_eq!(
                &disp[3 * k * np..3 * (k + 1) * np],
                &d.iter().flatten().copied().collect::<Vec<_>>()[..]
            );
            let nc = types.len();
            let hs = read_f("VTKHDF/CellData/stress");
            assert_eq!(&hs[k * nc..k * nc + ne], &stress[..ne]);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// HDF5 series.

#[cfg(feature = "hdf5")]
mod hdf5_file {
    use super::*;
    use crate::common::output::read;
    use hdf5_metno as h5;

    /// The complete time series of the meshed arc: rotor DOFs equal the analysed orbit, the
    /// VTKHDF steps address every frame, the arc's nodes are in equilibrium with the bar forces
    /// and the contact forces, velocities are the one-step backward difference.
    #[test]
    fn hdf5_series_of_a_meshed_stator() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let (r, _) = run(
            "fe_arc.toml",
            &[
                "run.revolutions=14",
                "run.transient_revolutions=10",
                "run.max_transient_revolutions=10",
                "output.hdf5={}",
                // Not what is tested; its companion from full contact spends 12 s (25× the run) in a
                // contact solve that fails after ≈ 1.2·10⁵ pivoting iterations, and is dropped.
                "run.check_coexistence=false",
            ],
            &dir,
        );
        let f = crate::common::output::open_h5(&dir.join("results.vtkhdf"));
        let spr = 64;
        // The 4-revolution window is lengthened to 6 (½× and ⅓× on exact bins) after the
        // 10 transient revolutions (held at 10: the window does not slide).
        assert_eq!((r.transient_revolutions, r.window_revolutions), (10, 6));
        let n = 16 * spr + 1;
        let t: Vec<f64> = read(&f, "time");
        assert_eq!(t.len(), n);
        let u: Vec<f64> = read(&f, "rotor/u");
        assert_eq!(u.len(), 2 * n);
        // The Jeffcott rotor's one node: [u_x, u_y] only, no rotation, axial or twist DOF.
        let nd: Vec<i64> = read(&f, "rotor/node_dofs");
        assert_eq!(nd, vec![0, 1, -1, -1, -1, -1]);
        assert!(f.dataset("VTKHDF/PointData/twist").is_err());
        for (k, o) in r.orbit_nd.iter().enumerate() {
            let i = 10 * spr + k;
            assert!((u[2 * i] - o[0] * r.z0).abs() <= 1e-12 * r.z0);
            assert!((u[2 * i + 1] - o[1] * r.z0).abs() <= 1e-12 * r.z0);
        }
        // The scene and the units are attributes.
        let scene: h5::types::VarLenUnicode = f.attr("scene").unwrap().read_scalar().unwrap();
        let scene: serde_json::Value = serde_json::from_str(scene.as_str()).unwrap();
        assert_eq!(scene["run"]["revolutions"], 14);
        // VTKHDF: mesh once, NSteps, offsets step by step.
        let v = f.group("VTKHDF").unwrap();
        let nsteps: i64 = v
            .group("Steps")
            .unwrap()
            .attr("NSteps")
            .unwrap()
            .read_scalar()
            .unwrap();
        assert_eq!(nsteps as usize, n);
        let np: Vec<i64> = read(&f, "VTKHDF/NumberOfPoints");
        let npts = np[0] as usize;
        assert_eq!(npts, 301);
        let off: Vec<i64> = read(&f, "VTKHDF/Steps/PointDataOffsets/displacement");
        assert!(off.iter().enumerate().all(|(k, o)| *o == (k * npts) as i64));
        let values: Vec<f64> = read(&f, "VTKHDF/Steps/Values");
        assert_eq!(values, t);
        let disp: Vec<f64> = read(&f, "VTKHDF/PointData/displacement");
        let vel: Vec<f64> = read(&f, "VTKHDF/PointData/velocity");
        let cf: Vec<f64> = read(&f, "VTKHDF/PointData/contact_force");
        let axial: Vec<f64> = read(&f, "VTKHDF/CellData/axial_force");
        let p: Vec<f64> = read(&f, "contact/p");
        let pts: Vec<f64> = read(&f, "VTKHDF/Points");
        let conn: Vec<i64> = read(&f, "VTKHDF/Connectivity");
        let part: Vec<u8> = read(&f, "VTKHDF/CellData/part");
        let nc = part.len();
        assert_eq!(disp.len(), 3 * npts * n);
        // Rotor point (the last) carries the rotor DOFs.
        for k in [0, n / 2, n - 1] {
            assert_eq!(disp[3 * (k * npts + 300)], u[2 * k]);
        }
        // Equilibrium of each free arc node (0..150) in the frame with the most contacts.
        let active = |k: usize| {
            p[k * 150..(k + 1) * 150]
                .iter()
                .filter(|x| **x > 0.0)
                .count()
        };
        let k = (0..n).max_by_key(|k| active(*k)).unwrap();
        assert!(active(k) >= 2, "several nodes in contact at once");
        let mut residual = vec![[0.0_f64; 2]; 150];
        for c in 0..nc {
            if part[c] != 0 {
                continue;
            }
            let (a, b) = (conn[2 * c] as usize, conn[2 * c + 1] as usize);
            let d = [pts[3 * b] - pts[3 * a], pts[3 * b + 1] - pts[3 * a + 1]];
            let l = d[0].hypot(d[1]);
            let nf = axial[k * nc + c];
            for (node, sign) in [(a, 1.0), (b, -1.0)] {
                if node < 150 {
                    residual[node][0] += sign * nf * d[0] / l;
                    residual[node][1] += sign * nf * d[1] / l;
                }
            }
        }
        let fmax = (0..150)
            .map(|i| cf[3 * (k * npts + i)].hypot(cf[3 * (k * npts + i) + 1]))
            .fold(0.0, f64::max);
        assert!(fmax > 0.0);
        for (i, res) in residual.iter().enumerate() {
            let rx = res[0] + cf[3 * (k * npts + i)];
            let ry = res[1] + cf[3 * (k * npts + i) + 1];
            assert!(rx.hypot(ry) <= 1e-8 * fmax, "node {i}: {rx} {ry}");
        }
        // The arc is massless: its velocity is the backward difference of its displacement,
        // zero where it stays undeformed.
        assert!(vel.iter().all(|x| x.is_finite()));
        assert!(vel[..3 * npts].iter().take(3 * 150).all(|x| *x == 0.0));
    }

    /// The paper rotor as FE model with torsional DOFs rubbing the rod
    /// (`scenes/fe/paper_rotor_rub_torsion.toml` at ω/ω_n = 1.7): `/rotor/node_dofs` maps every
    /// node to its DOFs; the point array `twist` of the `.vtu` frames and the VTKHDF grid is the
    /// θ_z entry of the rotor DOF vector at every frame (NaN on the rod), `twist_rate` its
    /// one-step backward difference; the friction torque −R μ p winds the shaft up against the
    /// spin, the disk more than the drive end, as the static twist of the mean torque.
    #[test]
    fn fe_rotor_twist_in_vtk_and_hdf5() {
        use rubsim::results::{THETA_Z, U_Z};
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let scene = repo("scenes/fe/paper_rotor_rub_torsion.toml");
        let sets = [
            "run.revolutions=20",
            "run.transient_revolutions=10",
            "run.error_estimate=false",
            "output.vtk={ from_revolution = 10 }",
            "output.hdf5={ every = 1, from_revolution = 10 }",
        ];
        let speed = 1.7;
        let (_, model) = file_model(&scene, &sets);
        let case = model.case(speed * model.rotor.natural_frequency()).unwrap();
        let layout = Layout::new(&model, &case);
        common::output::run_scene(&scene, &sets, Some(speed), &dir);

        // The DOF map: lateral 4i..4i+4, no u_z, θ_z after every lateral DOF.
        let nn = case.rotor.node_dofs.len();
        assert_eq!(nn, 9);
        let ndof = case.rotor.ndof;
        let f = crate::common::output::open_h5(&dir.join("results.vtkhdf"));
        let format: h5::types::VarLenUnicode = f.attr("format").unwrap().read_scalar().unwrap();
        assert_eq!(format.as_str(), "rubsim results 2 (docs/OUTPUTS.md)");
        let ds = f.dataset("rotor/node_dofs").unwrap();
        assert_eq!(ds.shape(), vec![nn, 6]);
        let cols: h5::types::VarLenUnicode = ds.attr("columns").unwrap().read_scalar().unwrap();
        assert_eq!(cols.as_str(), "u_x u_y theta_x theta_y u_z theta_z");
        let nd: Vec<i64> = read(&f, "rotor/node_dofs");
        let lateral = 4 * nn as i64;
        for i in 0..nn {
            let t = case.rotor.node_torsion[i].unwrap() as i64;
            assert!(t >= lateral && t < ndof as i64);
            let i6 = i as i64 * 4;
            assert_eq!(&nd[6 * i..6 * i + 6], &[i6, i6 + 1, i6 + 2, i6 + 3, -1, t]);
            assert_eq!(
                layout.rotor_dofs[i][THETA_Z], case.rotor.node_torsion[i],
                "node {i}"
            );
            assert_eq!(layout.rotor_dofs[i][U_Z], None);
        }
        let theta_z = |node: usize| nd[6 * node + THETA_Z] as usize;

        // HDF5: the grid's twist is the DOF vector's θ_z at every frame, NaN on the rod.
        let t: Vec<f64> = read(&f, "time");
        let step: Vec<i64> = read(&f, "step");
        let u: Vec<f64> = read(&f, "rotor/u");
        let v: Vec<f64> = read(&f, "rotor/v");
        let n = t.len();
        let spr = f
            .attr("steps_per_rev")
            .unwrap()
            .read_scalar::<i64>()
            .unwrap() as usize;
        assert_eq!(n, 10 * spr + 1, "every step of revolutions 10…20");
        assert!(step
            .iter()
            .enumerate()
            .all(|(k, s)| *s as usize == 10 * spr + k));
        assert_eq!(u.len(), n * ndof);
        let npts = layout.num_points();
        let rf = layout.rotor_first_point;
        assert_eq!(rf + nn, npts);
        let twist: Vec<f64> = read(&f, "VTKHDF/PointData/twist");
        let twist_rate: Vec<f64> = read(&f, "VTKHDF/PointData/twist_rate");
        let disp: Vec<f64> = read(&f, "VTKHDF/PointData/displacement");
        assert_eq!(twist.len(), n * npts);
        let off: Vec<i64> = read(&f, "VTKHDF/Steps/PointDataOffsets/twist");
        assert!(off.iter().enumerate().all(|(k, o)| *o == (k * npts) as i64));
        for k in 0..n {
            let row = &twist[k * npts..(k + 1) * npts];
            assert!(
                row[..rf].iter().all(|x| x.is_nan()),
                "frame {k}: rod points"
            );
            for i in 0..nn {
                assert_eq!(row[rf + i], u[k * ndof + theta_z(i)], "frame {k} node {i}");
                // No axial DOFs: the rotor points stay in their planes.
                assert_eq!(disp[3 * (k * npts + rf + i) + 2], 0.0);
                assert_eq!(
                    twist_rate[k * npts + rf + i],
                    v[k * ndof + theta_z(i)],
                    "frame {k} node {i}"
                );
            }
            if k > 0 {
                // A frame every step: the rate is the difference of consecutive frames.
                let i = 4;
                let fd =
                    (u[k * ndof + theta_z(i)] - u[(k - 1) * ndof + theta_z(i)]) / (t[k] - t[k - 1]);
                let r = twist_rate[k * npts + rf + i];
                assert!((r - fd).abs() <= 1e-9 * fd.abs().max(1e-9), "{r} vs {fd}");
            }
        }

        // VTK: the same twist in every .vtu (frames on the recording interval of the same
        // window, all of them in the HDF5 series, which holds every step).
        let frames = pvd(&dir.join("results.pvd"));
        assert_eq!(frames.len(), 10 * 64 + 1);
        for (tk, file) in &frames {
            let k = t
                .iter()
                .position(|x| x == tk)
                .expect("frame time in the HDF5 series");
            let g = vtu(&dir.join(file));
            let tw = array(&g.data.point, "twist");
            let tr = array(&g.data.point, "twist_rate");
            let d = vectors3(&g.data.point, "displacement");
            assert_eq!(tw.len(), npts);
            assert!(tw[..rf].iter().chain(&tr[..rf]).all(|x| x.is_nan()));
            for i in 0..nn {
                assert_eq!(tw[rf + i], u[k * ndof + theta_z(i)], "t = {tk}, node {i}");
                assert_eq!(tr[rf + i], v[k * ndof + theta_z(i)], "t = {tk}, node {i}");
                assert_eq!(d[rf + i][2], 0.0);
                let lat = &nd[6 * i..6 * i + 2];
                assert_eq!(d[rf + i][0], u[k * ndof + lat[0] as usize]);
                assert_eq!(d[rf + i][1], u[k * ndof + lat[1] as usize]);
            }
        }

        // Physics over the steady window (revolutions 10…20, every step): the friction torque
        // τ = −R μ p opposes the spin, so the disk (node 4) twists backwards on average, more
        // than the drive end (node 0, on the 1000 N·m/rad coupling). Averaged over the window,
        // M θ̈ and C θ̇ leave only their end values, so the mean twist is the static twist under
        // the mean torque: θ̄_0 = τ̄/k_c, θ̄_4 = τ̄ (1/k_c + L/(G J)) over the shaft from the
        // drive to the disk (L = 0.2 m, d = 1 cm, G = E/2.6).
        let p: Vec<f64> = read(&f, "contact/p");
        assert_eq!(p.len(), n, "one pair");
        assert!(p.iter().any(|x| *x > 0.0), "the rotor rubs");
        let mean = |it: &mut dyn Iterator<Item = f64>| {
            let (s, c) = it.fold((0.0, 0), |(s, c), x| (s + x, c + 1));
            s / c as f64
        };
        let (r, mu, kc) = (0.06, 0.1, 1000.0);
        let gj = 200e9 / 2.6 * std::f64::consts::PI * 0.01_f64.powi(4) / 32.0;
        let tau = -r * mu * mean(&mut p.iter().copied());
        let th = |node: usize| mean(&mut (0..n).map(|k| u[k * ndof + theta_z(node)]));
        let (th0, th4, th8) = (th(0), th(4), th(8));
        assert!(th4 < 0.0, "mean twist at the disk {th4}");
        assert!(th4.abs() > th0.abs(), "disk {th4}, drive {th0}");
        let expect0 = tau / kc;
        let expect4 = tau * (1.0 / kc + 0.2 / gj);
        assert!(
            (th0 - expect0).abs() <= 1e-3 * expect0.abs(),
            "{th0} vs {expect0}"
        );
        assert!(
            (th4 - expect4).abs() <= 1e-3 * expect4.abs(),
            "{th4} vs {expect4}"
        );
        // Beyond the disk no torque: the free end (node 8) follows it.
        assert!((th8 - th4).abs() <= 1e-3 * th4.abs(), "{th8} vs {th4}");
    }

    /// With a frame every step the velocity is exactly the difference of consecutive frames.
    #[test]
    fn velocity_is_the_one_step_backward_difference() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        run(
            "single.toml",
            &[
                "run.revolutions=3",
                "run.transient_revolutions=1",
                "run.initial_velocity=[0.01, -0.02]",
                "output.hdf5={ every = 1 }",
            ],
            &dir,
        );
        let f = crate::common::output::open_h5(&dir.join("results.vtkhdf"));
        let t: Vec<f64> = read(&f, "time");
        let u: Vec<f64> = read(&f, "rotor/u");
        let v: Vec<f64> = read(&f, "rotor/v");
        assert_eq!(&v[..2], &[0.01, -0.02], "initial velocity at step 0");
        for k in 1..t.len() {
            for c in 0..2 {
                let fd = (u[2 * k + c] - u[2 * (k - 1) + c]) / (t[k] - t[k - 1]);
                assert!((v[2 * k + c] - fd).abs() <= 1e-9 * fd.abs().max(1e-6));
            }
        }
        // Frames every 5 steps still carry the one-step difference, not a 5-step one.
        run(
            "single.toml",
            &[
                "run.revolutions=3",
                "run.transient_revolutions=1",
                "run.initial_velocity=[0.01, -0.02]",
                "output.hdf5={ every = 5, fields = [\"velocity\", \"displacement\"] }",
            ],
            &dir,
        );
        let f5 = crate::common::output::open_h5(&dir.join("results.vtkhdf"));
        let v5: Vec<f64> = read(&f5, "rotor/v");
        let step5: Vec<i64> = read(&f5, "step");
        for (k, s) in step5.iter().enumerate().skip(1) {
            let i = *s as usize;
            for c in 0..2 {
                assert!(
                    (v5[2 * k + c] - v[2 * i + c]).abs() <= 1e-9 * v[2 * i + c].abs().max(1e-6)
                );
            }
        }
        // No contact group without the field.
        assert!(f5.group("contact").unwrap().dataset("p").is_err());
    }
}

#[test]
fn series_that_cannot_fit_is_refused_before_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let e = rubsim::results::check_free_space(dir.path(), 1e18)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("MB are free") && e.contains("needs about"),
        "{e}"
    );
    rubsim::results::check_free_space(dir.path(), 1.0).unwrap();
}
