//! VTK and HDF5 time series (issue 5): frame counts, values read back with `vtkio` and
//! `hdf5-metno` against the run's own numbers, physical consistency of the stress recovery,
//! streaming into the staging folder, reruns, per-speed sweeps and faults.

use rubsim::analysis::{Keep, RunSettings};
use rubsim::model::Model;
use rubsim::output::{OutDir, MANIFEST};
use rubsim::results::{self, FramePlan, Layout};
use rubsim::scene::{self, LoadedScene};
use rubsim::time::plan_steps;
use std::path::{Path, PathBuf};
use std::process::Command;
use vtkio::model::{Attribute, DataSet, IOBuffer, Piece, Vtk};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/scenes")
        .join(name)
}

fn load(name: &str, sets: &[&str]) -> (LoadedScene, Model) {
    let ov: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
    let ls = scene::load(&data(name), &ov).expect("scene");
    let model = Model::build(&ls).expect("model");
    (ls, model)
}

/// Runs one speed with the scene's time series into `dir` (through the output directory's
/// staging folder and commit, as the CLI does).
fn run(name: &str, sets: &[&str], dir: &Path) -> (rubsim::analysis::SpeedResults, Vec<PathBuf>) {
    let (ls, model) = load(name, sets);
    let s = RunSettings::from_run(&ls.scene.run, "y");
    let mut out = OutDir::prepare(dir).expect("prepare");
    let staging = out.staging_dir().to_path_buf();
    let (r, names) = results::run_speed(
        &model,
        &s,
        ls.scene.run.speed_ratio.expect("single speed"),
        Keep {
            orbit: true,
            ..Keep::default()
        },
        &ls.scene.output,
        &serde_json::to_string(&ls.scene).unwrap(),
        &staging,
        "",
    )
    .expect("run");
    for n in &names {
        out.adopt(n).expect("adopt");
    }
    (r, out.commit().expect("commit"))
}

fn vtu(path: &Path) -> vtkio::model::UnstructuredGridPiece {
    let vtk = Vtk::import(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    match vtk.data {
        DataSet::UnstructuredGrid { pieces, .. } => match pieces.into_iter().next() {
            Some(Piece::Inline(p)) => *p,
            _ => panic!("no inline piece"),
        },
        _ => panic!("not an unstructured grid"),
    }
}

fn f64s(b: &IOBuffer) -> Vec<f64> {
    match b {
        IOBuffer::F64(v) => v.clone(),
        other => panic!("not f64: {other:?}"),
    }
}

fn array(attrs: &[Attribute], name: &str) -> Vec<f64> {
    for a in attrs {
        if let Attribute::DataArray(d) = a {
            if d.name == name {
                return f64s(&d.data);
            }
        }
    }
    panic!("no array `{name}`")
}

/// `(time, file)` of every `DataSet` line of a `.pvd`.
fn pvd(path: &Path) -> Vec<(f64, String)> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| l.contains("<DataSet"))
        .map(|l| {
            let field = |k: &str| {
                let a = l.find(&format!("{k}=\"")).unwrap() + k.len() + 2;
                let b = a + l[a..].find('"').unwrap();
                l[a..b].to_string()
            };
            (field("timestep").parse().unwrap(), field("file"))
        })
        .collect()
}

#[test]
fn frame_plan_counts_and_window() {
    let (ls, model) = load("single.toml", &[]);
    let s = RunSettings::from_run(&ls.scene.run, "y");
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
    let (_, model) = load("fe_arc.toml", &[]);
    let case = model.case(1.7 * model.rotor.natural_frequency()).unwrap();
    let l = Layout::new(&case);
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
    let sweep = Command::new(env!("CARGO_BIN_EXE_rubsim"))
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

#[test]
fn faults_are_reported_before_the_run() {
    let tmp = tempfile::tempdir().unwrap();
    let cli = |args: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_rubsim"))
            .args(args)
            .current_dir(tmp.path())
            .output()
            .unwrap();
        assert!(!o.status.success(), "should fail: {args:?}");
        String::from_utf8_lossy(&o.stderr).to_string()
    };
    let scene = data("single.toml");
    let scene = scene.to_str().unwrap();
    // The output path is a file.
    std::fs::write(tmp.path().join("file"), "x").unwrap();
    let e = cli(&["run", scene, "--out", "file", "--set", "output.vtk={}"]);
    assert!(e.contains("not a directory"), "{e}");
    // Bad keys name themselves.
    let e = cli(&["run", scene, "--set", "output.vtk={ every = 0 }"]);
    assert!(e.contains("output.vtk.every"), "{e}");
    let e = cli(&[
        "run",
        scene,
        "--set",
        "output.hdf5={ fields = [\"pressure\"] }",
    ]);
    assert!(e.contains("pressure"), "{e}");
    let e = cli(&["run", scene, "--set", "output.per_speed=true"]);
    assert!(e.contains("output.per_speed"), "{e}");
    let e = cli(&[
        "sweep",
        data("sweep.toml").to_str().unwrap(),
        "--set",
        "output.hdf5={}",
        "--set",
        "output.per_speed=[1.55]",
    ]);
    assert!(e.contains("output.per_speed") && e.contains("1.55"), "{e}");
    // A read-only output directory (unless running as root, who may write anyway).
    let ro = tmp.path().join("ro");
    std::fs::create_dir(&ro).unwrap();
    let mut perm = std::fs::metadata(&ro).unwrap().permissions();
    perm.set_readonly(true);
    std::fs::set_permissions(&ro, perm).unwrap();
    if std::fs::write(ro.join("probe"), "x").is_err() {
        let e = cli(&["run", scene, "--out", "ro", "--set", "output.vtk={}"]);
        assert!(e.contains("not writable"), "{e}");
    }
}

#[cfg(feature = "hdf5")]
mod hdf5_file {
    use super::*;
    use hdf5_metno as h5;

    fn read<T: h5::H5Type + Clone>(f: &h5::File, name: &str) -> Vec<T> {
        f.dataset(name)
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .read_raw::<T>()
            .unwrap()
    }

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
                "output.hdf5={}",
            ],
            &dir,
        );
        let f = h5::File::open(dir.join("results.vtkhdf")).unwrap();
        let spr = 64;
        let n = 14 * spr + 1;
        let t: Vec<f64> = read(&f, "time");
        assert_eq!(t.len(), n);
        let u: Vec<f64> = read(&f, "rotor/u");
        assert_eq!(u.len(), 2 * n);
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
        let f = h5::File::open(dir.join("results.vtkhdf")).unwrap();
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
        let f5 = h5::File::open(dir.join("results.vtkhdf")).unwrap();
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
