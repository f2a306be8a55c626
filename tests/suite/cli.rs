//! Command-line tests: the real `rubsim` binary on small scenes in temporary directories.
//!
//! Requirement under test: bad input gets a clear error that names the file, key or line and
//! what is wrong, a non-zero exit, and nothing lost or half-written. Plus the happy paths of
//! `check`, `run` and `sweep`, and the other commands (`modal`, `mesh`, `stress`, `refine`).

use crate::common;

use common::cli::{assert_nothing_written, fails, in_repo, is_png, json, ok, rubsim, tree};
use common::meshes::need_gmsh;
use common::{data, read, repo};
use std::path::{Path, PathBuf};
use tempfile::TempDir;

/// Writes a copy of a test scene with `from` replaced by `to` (which must occur) into `dir`.
fn variant(dir: &Path, base: &str, name: &str, from: &str, to: &str) -> PathBuf {
    let src = read(&data(base));
    assert!(src.contains(from), "`{from}` not in {base}");
    let p = dir.join(name);
    std::fs::write(&p, src.replacen(from, to, 1)).unwrap();
    p
}

/// 1-based line of the first line of `p` containing `needle`.
fn line_of(p: &Path, needle: &str) -> usize {
    read(p)
        .lines()
        .position(|l| l.contains(needle))
        .unwrap_or_else(|| panic!("`{needle}` not in {}", p.display()))
        + 1
}

/// Fails `check`, `run` and `sweep` on `scene` (with extra args), the latter two into a fresh
/// `--out`, and checks that nothing is written; returns the `run` stderr.
fn fails_everywhere(tmp: &Path, scene: &Path, extra: &[&str]) -> String {
    let mut run_err = None;
    for cmd in ["check", "run", "sweep"] {
        let out = tmp.join(format!("out-{cmd}"));
        let _ = std::fs::remove_dir_all(&out);
        let mut args = vec![cmd, scene.to_str().unwrap()];
        args.extend_from_slice(extra);
        if cmd != "check" {
            args.extend_from_slice(&["--out", out.to_str().unwrap()]);
        }
        let err = fails(tmp, &args);
        assert_nothing_written(&out);
        assert_nothing_written(&tmp.join("out"));
        if cmd == "run" {
            run_err = Some(err);
        }
    }
    run_err.unwrap()
}

// ---------------------------------------------------------------------------------------------
// Bad input

#[test]
fn malformed_toml_names_file_and_line() {
    let tmp = TempDir::new().unwrap();
    for (name, from, to, needle) in [
        ("header.toml", "[run]", "[run", "[run"),
        ("value.toml", "mass = 2.0", "mass = 2.0 2", "mass = 2.0 2"),
        (
            "string.toml",
            "name = \"rod\"",
            "name = \"rod",
            "name = \"rod",
        ),
    ] {
        let p = variant(tmp.path(), "single.toml", name, from, to);
        let line = line_of(&p, needle);
        let err = fails_everywhere(tmp.path(), &p, &[]);
        assert!(err.contains(name), "file not named:\n{err}");
        assert!(
            err.contains(&format!("line {line}")),
            "line {line} not named:\n{err}"
        );
    }
}

#[test]
fn unknown_key_names_key_and_line() {
    let tmp = TempDir::new().unwrap();
    // [[station]] is a plain table; [[stator]] and [rotor] are tagged by `kind`, where serde
    // alone would only point at the table header.
    for (name, after) in [
        ("station.toml", "friction = 0.1"),
        ("stator.toml", "area = 25e-6"),
        ("rotor.toml", "damping_ratio = 0.2"),
    ] {
        let p = variant(
            tmp.path(),
            "single.toml",
            name,
            after,
            &format!("{after}\nfrobnicate = 3"),
        );
        let line = line_of(&p, "frobnicate");
        let err = fails_everywhere(tmp.path(), &p, &[]);
        assert!(err.contains(name), "file not named:\n{err}");
        assert!(
            err.contains("unknown field `frobnicate`"),
            "key not named:\n{err}"
        );
        assert!(
            err.contains(&format!("line {line}")),
            "line {line} not named:\n{err}"
        );
    }
}

/// An unknown key in a sub-table of a tagged table (`[[rotor.unbalance]]` under `[rotor]`)
/// was reported at line 1 (`[rotor]`'s header, serde's span) with no line of its own; it names
/// its whole dotted key and its own line now, from the file and from `--set`.
#[test]
fn unknown_key_in_a_sub_table_names_its_dotted_key_and_line() {
    let tmp = TempDir::new().unwrap();
    let p = variant(
        tmp.path(),
        "single.toml",
        "unbalance.toml",
        "radius = 0.05",
        "radiuss = 0.05",
    );
    let line = line_of(&p, "radiuss");
    let err = fails_everywhere(tmp.path(), &p, &[]);
    assert!(
        err.contains(&format!(
            "unbalance.toml:{line}: key `rotor.unbalance.0.radiuss`"
        )) && err.contains("unknown field `radiuss`"),
        "{err}"
    );
    let s = data("single.toml");
    let err = fails_everywhere(tmp.path(), &s, &["--set", "rotor.unbalance.0.magnitude=1"]);
    assert!(
        err.contains("key `rotor.unbalance.0.magnitude`") && err.contains("after --set"),
        "{err}"
    );
}

#[test]
fn inadmissible_values_name_dotted_key_and_file_line() {
    let tmp = TempDir::new().unwrap();
    let cases = [
        ("mass0.toml", "mass = 2.0", "mass = 0", "rotor.mass"),
        (
            "stiff.toml",
            "stiffness = 8.0e4",
            "stiffness = -1",
            "rotor.stiffness",
        ),
        (
            "clear0.toml",
            "clearance_nd = 0.6",
            "clearance = 0",
            "stator.0.clearance",
        ),
        (
            "clearnd.toml",
            "clearance_nd = 0.6",
            "clearance_nd = -0.5",
            "stator.0.clearance_nd",
        ),
        (
            "mu.toml",
            "friction = 0.1",
            "friction = -0.1",
            "station.0.friction",
        ),
    ];
    for (name, from, to, key) in cases {
        let p = variant(tmp.path(), "single.toml", name, from, to);
        let line = line_of(&p, to);
        let err = fails_everywhere(tmp.path(), &p, &[]);
        assert!(
            err.contains(&format!("key `{key}`")),
            "{key} not named:\n{err}"
        );
        let at = format!("{}:{line}", p.display());
        assert!(err.contains(&at), "`{at}` not named:\n{err}");
        assert!(
            err.contains("positive"),
            "what is wrong is not said:\n{err}"
        );
    }
}

#[test]
fn missing_sections_are_named() {
    let tmp = TempDir::new().unwrap();
    let src = read(&data("single.toml"));
    let cut = |from: &str, to: &str| {
        let (a, b) = (src.find(from).unwrap(), src.find(to).unwrap());
        format!("{}{}", &src[..a], &src[b..])
    };
    for (name, text, section) in [
        ("norun.toml", cut("[run]", "[output]"), "run"),
        ("norotor.toml", cut("[rotor]", "[[station]]"), "rotor"),
    ] {
        let p = tmp.path().join(name);
        std::fs::write(&p, text).unwrap();
        let err = fails_everywhere(tmp.path(), &p, &[]);
        assert!(err.contains(name), "file not named:\n{err}");
        assert!(
            err.contains(&format!("missing field `{section}`")),
            "missing [{section}] not named:\n{err}"
        );
    }
    // A [run] without any speed.
    let p = variant(
        tmp.path(),
        "single.toml",
        "nospeed.toml",
        "speed_ratio = 1.7",
        "",
    );
    let err = fails_everywhere(tmp.path(), &p, &[]);
    assert!(
        err.contains("`run`") && err.contains("speed_ratio"),
        "{err}"
    );
}

#[test]
fn unreadable_scene_names_the_path() {
    let tmp = TempDir::new().unwrap();
    let missing = tmp.path().join("no/such/scene.toml");
    let err = fails_everywhere(tmp.path(), &missing, &[]);
    assert!(
        err.contains(&missing.display().to_string()),
        "path not named:\n{err}"
    );
    assert!(err.contains("cannot read"), "{err}");
    // The I/O reason is given once, not repeated by the error chain.
    assert_eq!(err.matches("os error").count(), 1, "{err}");

    let dir = tmp.path().join("a_directory.toml");
    std::fs::create_dir(&dir).unwrap();
    let err = fails(tmp.path(), &["check", dir.to_str().unwrap()]);
    assert!(
        err.contains("a_directory.toml") && err.contains("cannot read"),
        "{err}"
    );
}

#[test]
fn bad_overrides_are_reported() {
    let tmp = TempDir::new().unwrap();
    let s = data("single.toml");
    let cases: [(&str, &[&str]); 6] = [
        (
            "stator.7.clearance=1",
            &["stator.7.clearance", "out of range"],
        ),
        (
            "run.speed_ratio=abc",
            &["run.speed_ratio", "abc", "expected f64"],
        ),
        ("run.speed_ratio=-2", &["run.speed_ratio", "positive"]),
        (
            "rotor.frobnicate=1",
            &["rotor.frobnicate", "unknown field `frobnicate`"],
        ),
        ("bogus.key=3", &["bogus.key", "unknown field `bogus`"]),
        ("no_equals_sign", &["no_equals_sign", "key=value"]),
    ];
    for (set, wanted) in cases {
        let err = fails_everywhere(tmp.path(), &s, &["--set", set]);
        for w in wanted {
            assert!(err.contains(w), "--set {set}: `{w}` not in:\n{err}");
        }
    }
    // A type error from --set must not cite lines of some rewritten document as the file's.
    let err = fails(
        tmp.path(),
        &["check", s.to_str().unwrap(), "--set", "run.speed_ratio=abc"],
    );
    assert!(err.contains("--set run.speed_ratio=abc"), "{err}");
    assert!(
        !err.contains("line "),
        "cites a line that is not in the file:\n{err}"
    );
    // With an override present, an error in the file still cites the file's own line.
    let p = variant(
        tmp.path(),
        "single.toml",
        "typo.toml",
        "length = 0.04",
        "lenght = 0.04",
    );
    let line = line_of(&p, "lenght");
    let err = fails(
        tmp.path(),
        &["check", p.to_str().unwrap(), "--set", "rotor.mass=3"],
    );
    assert!(
        err.contains("lenght") && err.contains(&format!("line {line}")),
        "{err}"
    );
}

#[test]
fn step_above_stability_limit_is_refused() {
    let tmp = TempDir::new().unwrap();
    let err = fails_everywhere(tmp.path(), &data("single.toml"), &["--set", "run.dt=1.0"]);
    assert!(err.contains("stability limit"), "{err}");
    let out = tmp.path().join("sweep");
    let err = fails(
        tmp.path(),
        &[
            "sweep",
            data("sweep.toml").to_str().unwrap(),
            "--set",
            "run.dt=1.0",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(err.contains("stability limit"), "{err}");
    assert_nothing_written(&out);
}

#[test]
fn wrong_command_for_the_scene_is_explained() {
    let tmp = TempDir::new().unwrap();
    let out = tmp.path().join("o");
    let o = out.to_str().unwrap();
    let err = fails(
        tmp.path(),
        &["run", data("sweep.toml").to_str().unwrap(), "--out", o],
    );
    assert!(
        err.contains("sweep.toml") && err.contains("rubsim sweep"),
        "{err}"
    );
    let err = fails(
        tmp.path(),
        &["sweep", data("single.toml").to_str().unwrap(), "--out", o],
    );
    assert!(
        err.contains("single.toml") && err.contains("[run.sweep]"),
        "{err}"
    );
    assert_nothing_written(&out);
}

#[test]
fn output_path_that_is_a_file_is_refused_before_computing() {
    let tmp = TempDir::new().unwrap();
    let file = tmp.path().join("results.txt");
    std::fs::write(&file, "keep me").unwrap();
    for (cmd, scene) in [("run", "single.toml"), ("sweep", "sweep.toml")] {
        // run.dt=1.0 would fail in the integration: the output error must come first.
        let err = fails(
            tmp.path(),
            &[
                cmd,
                data(scene).to_str().unwrap(),
                "--set",
                "run.dt=1.0",
                "--out",
                file.to_str().unwrap(),
            ],
        );
        assert!(
            err.contains(&file.display().to_string()),
            "path not named:\n{err}"
        );
        assert!(
            !err.contains("stability"),
            "computed before checking the output:\n{err}"
        );
        assert_eq!(read(&file), "keep me");
    }
    assert_eq!(tree(tmp.path()), vec![PathBuf::from("results.txt")]);
}

#[test]
fn failed_rerun_keeps_previous_results() {
    let tmp = TempDir::new().unwrap();
    let out = tmp.path().join("res");
    let o = out.to_str().unwrap();
    let s = data("sweep.toml");
    let s = s.to_str().unwrap();
    ok(tmp.path(), &["sweep", s, "--out", o]);
    let before: Vec<(PathBuf, Vec<u8>)> = tree(&out)
        .into_iter()
        .filter(|p| out.join(p).is_file())
        .map(|p| (p.clone(), std::fs::read(out.join(&p)).unwrap()))
        .collect();
    fails(tmp.path(), &["sweep", s, "--set", "run.dt=1.0", "--out", o]);
    fails(
        tmp.path(),
        &["sweep", s, "--set", "rotor.mass=0", "--out", o],
    );
    let after: Vec<(PathBuf, Vec<u8>)> = tree(&out)
        .into_iter()
        .filter(|p| out.join(p).is_file())
        .map(|p| (p.clone(), std::fs::read(out.join(&p)).unwrap()))
        .collect();
    assert!(before == after, "a failed rerun changed {}", out.display());
}

#[test]
fn faults_are_reported_before_the_run() {
    let tmp = tempfile::tempdir().unwrap();
    let cli = |args: &[&str]| {
        let o = rubsim(tmp.path(), args);
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

// ---------------------------------------------------------------------------------------------
// Happy paths

#[test]
fn check_prints_the_resolved_model() {
    let tmp = TempDir::new().unwrap();
    let paper = repo("scenes/paper/partial_rub.toml");
    let stdout = ok(tmp.path(), &["check", paper.to_str().unwrap()]);
    for w in [
        "massless",
        "left out",
        "Δt",
        "stability limit",
        "Jeffcott",
        "rod",
    ] {
        assert!(stdout.contains(w), "`{w}` not in check output:\n{stdout}");
    }
    // check writes nothing.
    assert!(tree(tmp.path()).is_empty(), "{:?}", tree(tmp.path()));
}

#[test]
fn brief_stiff_impacts_count_in_peak_force_and_contact_fraction() {
    // Issue 13, item 4: with ε = 10⁶ the rod is touched for a few steps per revolution, between
    // the recorded samples; the summary said `contact_force_max_nd = 0` and
    // `contact_fraction = 0` while 14 081 steps were in contact. They are counted at every step.
    let tmp = TempDir::new().unwrap();
    let out = tmp.path().join("stiff");
    let scene = repo("scenes/paper/partial_rub.toml");
    ok(
        tmp.path(),
        &[
            "run",
            scene.to_str().unwrap(),
            "--speed",
            "1.7",
            "--set",
            "stator.0.stiffness_ratio=1e6",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let r = &json(&out.join("summary.json"))["result"];
    let (stats, plan) = (&r["stats"], &r["plan"]);
    let u = |v: &serde_json::Value| v.as_u64().unwrap_or_else(|| panic!("{v}")) as usize;
    let f = |v: &serde_json::Value| v.as_f64().unwrap_or_else(|| panic!("{v}"));
    let (steady, whole) = (&stats["steady"], &stats["whole"]);
    // 100 of the 220 revolutions are the transient: the window is the other 120, every step.
    assert_eq!(u(&plan["steady_from"]), 100 * u(&plan["steps_per_rev"]));
    assert_eq!(u(&steady["instants"]), 120 * u(&plan["steps_per_rev"]));
    assert_eq!(u(&whole["instants"]), u(&stats["steps"]) + 1);
    let in_contact = u(&steady["contact_instants"]);
    assert!(in_contact > 0 && in_contact <= u(&whole["contact_instants"]));
    assert_eq!(u(&whole["contact_instants"]), u(&stats["contact_steps"]));
    assert!(u(&stats["contact_steps"]) > 10_000, "{stats}");
    assert_eq!(
        f(&r["contact_fraction"]),
        in_contact as f64 / u(&steady["instants"]) as f64
    );
    let peak = f(&r["contact_force_max_nd"]);
    assert!(peak > 1.0, "peak contact force {peak} × |U|ω²");
    assert_eq!(peak, f(&steady["force_max"]) / f(&r["unbalance_force"]));
    // The penetration of the exact post-correction gaps, over every step.
    let pen = f(&r["penetration_max_m"]);
    assert!((0.0..1e-12).contains(&pen), "penetration {pen} m");
    assert_eq!(pen, f(&whole["penetration_max"]));
}

#[test]
fn station_away_from_the_analysed_response_is_no_false_divergence() {
    // Issue 13, item 8: `station.0.node=0` puts the station (and the analysed node) on a
    // bearing, where |Z0| is 10⁴ times smaller than at the disk; the divergence bound was
    // scaled from that node and applied to every DOF, so the disk's ordinary response stopped
    // the run at step 3339 as "response diverged". The bound now takes the largest |Z0| over
    // the rotor.
    let tmp = TempDir::new().unwrap();
    let scene = repo("scenes/fe/paper_rotor_rub.toml");
    for (integrator, revs) in [("forward_increment", "220"), ("collocated", "20")] {
        let out = tmp.path().join(integrator);
        let (i, r) = (
            format!("run.integrator=\"{integrator}\""),
            format!("run.revolutions={revs}"),
        );
        ok(
            tmp.path(),
            &[
                "run",
                scene.to_str().unwrap(),
                "--speed",
                "1.7",
                "--set",
                "station.0.node=0",
                "--set",
                &i,
                "--set",
                &r,
                "--set",
                "run.transient_revolutions=10",
                "--set",
                "output.png=false",
                // Not what is tested; its companion, lengthened for the 0–1 test, is 10× the run.
                "--set",
                "run.check_coexistence=false",
                "--out",
                out.to_str().unwrap(),
            ],
        );
        let res = &json(&out.join("summary.json"))["result"];
        assert_eq!(res["node"].as_u64(), Some(0));
        assert!(res["extents_nd"][1].as_f64().unwrap() < 2.0, "{res}");
    }
}

#[test]
fn a_stiff_rod_at_a_bearing_node_runs_at_the_planned_step() {
    // Issue 13 follow-up: the rod (k_s = 2.5·10⁹ N/m) at the bearing node 0 of the FE paper
    // rotor, collocated scheme. The plan took 0.8 × the Weyl-bound limit 1.957 µs (Δt =
    // 1.56 µs), below the exact in-contact limit 1.981 µs, and the run diverged at step 684 412
    // (≈ 45 revolutions): the contact switching on and off pumps energy into the step. The
    // contact term of the bound now counts 1/φ² = 4 times (`time::CONTACT_SWITCHING_FACTOR`,
    // limit 1.015 µs): the planned step runs, and a step above the reported limit is refused
    // as such before it runs.
    let tmp = TempDir::new().unwrap();
    let scene = repo("scenes/fe/paper_rotor_rub.toml");
    let scene = scene.to_str().unwrap();
    // The full model at the paper's rule (the error target would run it reduced).
    let node = ["--set", "station.0.node=0", "--set", "run.auto_step=false"];
    let check = ok(tmp.path(), &[&["check", scene][..], &node].concat());
    let limit: f64 = check
        .split("stability limit ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no stability limit in\n{check}"));
    assert!(limit < 1.1e-6, "{limit}: was the linear 1.957 µs");
    let out = tmp.path().join("o");
    let run = [
        "run",
        scene,
        "--speed",
        "1.7",
        "--set",
        "run.revolutions=60",
        "--set",
        "run.transient_revolutions=10",
        "--set",
        "output.png=false",
        // Not what is tested; its companion, lengthened for the 0–1 test, is 4× the run.
        "--set",
        "run.check_coexistence=false",
        "--out",
        out.to_str().unwrap(),
    ];
    ok(tmp.path(), &[&run[..], &node].concat());
    let res = &json(&out.join("summary.json"))["result"];
    assert!(res["extents_nd"][1].as_f64().unwrap() < 2.0, "{res}");
    let dt = format!("run.dt={:e}", 1.1 * limit);
    let err = fails(tmp.path(), &[&run[..], &node, &["--set", &dt]].concat());
    assert!(
        err.contains("stability limit") && err.contains("switches on and off"),
        "{err}"
    );
}

#[test]
fn undamped_rotor_runs_off_its_critical_speed_and_says_why_not_at_it() {
    // Issue 13, item 8: `rotor.damping_ratio=0` is legal, but the model was checked at ω_n
    // where |Z0| is infinite, and the rod placed at an infinite clearance failed as "stator rod
    // stiffness: … fix more DOFs". Off ω_n it runs; at ω_n the error says what is infinite and
    // what to change.
    let tmp = TempDir::new().unwrap();
    let scene = repo("scenes/paper/partial_rub.toml");
    let base = [
        "run",
        scene.to_str().unwrap(),
        "--set",
        "rotor.damping_ratio=0",
        "--set",
        "run.revolutions=20",
        "--set",
        "run.transient_revolutions=10",
        "--set",
        "run.error_estimate=false",
        "--set",
        "output.png=false",
    ];
    let out = tmp.path().join("off");
    let mut args = base.to_vec();
    args.extend(["--speed", "1.7", "--out", out.to_str().unwrap()]);
    ok(tmp.path(), &args);
    assert!(
        json(&out.join("summary.json"))["result"]["z0"]
            .as_f64()
            .unwrap()
            > 0.0
    );
    let out = tmp.path().join("at");
    let mut args = base.to_vec();
    args.extend(["--speed", "1", "--out", out.to_str().unwrap()]);
    let err = fails(tmp.path(), &args);
    for want in [
        "clearance_nd",
        "infinite",
        "critical speed",
        "`clearance`",
        "rotor.damping_ratio",
    ] {
        assert!(err.contains(want), "`{want}` not in: {err}");
    }
    assert!(!err.contains("fix more DOFs"), "{err}");
    assert_nothing_written(&out);
}

#[test]
fn a_clearance_relative_to_z0_names_why_z0_is_unusable() {
    // Issue 13, item 8: mutants blamed "clearance_nd needs a non-zero |Z0|" (or a singular
    // stator) whatever made |Z0| unusable; the error names the input responsible (values
    // beyond 1e100 are refused at load by validation, naming the key, before any model is built).
    let tmp = TempDir::new().unwrap();
    let scene = repo("scenes/paper/partial_rub.toml");
    for (set, speed, wants) in [
        ("rotor.unbalance.0.phase_deg=nan", "1.7", &["phase_deg"][..]),
        (
            "rotor.unbalance.0.mass=0.0",
            "1.7",
            &["without an unbalance", "rotor.unbalance"],
        ),
        ("rotor.damping_ratio=1e308", "1.7", &["rotor.damping_ratio"]),
        ("rotor.disk.diameter=1e300", "1.7", &["rotor.disk.diameter"]),
        (
            "rotor.shaft.youngs_modulus=1e308",
            "1.7",
            &["rotor.shaft.youngs_modulus"],
        ),
        ("rotor.shaft.length=1e300", "1.7", &["rotor.shaft.length"]),
        ("title=\"huge speed\"", "1e308", &["speed", "--speed"]),
    ] {
        let out = tmp.path().join("out");
        let err = fails(
            tmp.path(),
            &[
                "run",
                scene.to_str().unwrap(),
                "--speed",
                speed,
                "--set",
                set,
                "--out",
                out.to_str().unwrap(),
            ],
        );
        for want in wants {
            assert!(err.contains(want), "{set}: `{want}` not in: {err}");
        }
        for blame in ["needs a non-zero", "fix more DOFs", "singular"] {
            assert!(!err.contains(blame), "{set}: blames `{blame}`: {err}");
        }
        assert_nothing_written(&out);
    }
}

#[test]
fn check_labels_each_frequency_for_what_it_is() {
    // Issue 13, item 10: `check` printed the free rotor's highest mode and the frequency with
    // the contact stiffness, two different numbers, both as "ω_max".
    let (okay, out, err) = in_repo(&["check", "scenes/fe/paper_rotor_rub.toml"]);
    assert!(okay, "{err}");
    assert!(out.contains("ω_max,rotor = "), "{out}");
    assert!(out.contains("ω_max,contact = "), "{out}");
    let labels: Vec<&str> = out.matches("ω_max").collect();
    assert_eq!(
        out.matches("ω_max ").count() + out.matches("ω_max=").count(),
        0,
        "{out}"
    );
    assert!(labels.len() >= 2, "{out}");
}

#[cfg(all(feature = "hdf5", target_os = "linux"))]
#[test]
fn hdf5_write_failure_names_the_frames_it_lost() {
    // Issue 13, item 10: a VTK write failure names its step and time (every frame is written
    // as it comes); HDF5 buffers frames, so a failure at the end of the run said only
    // "writing HDF5: …". With the file size limited (SIGXFSZ ignored, so the write fails with
    // EFBIG), the error names the buffered frames' first step and time, and nothing is
    // committed.
    let tmp = TempDir::new().unwrap();
    let out = tmp.path().join("out");
    let o = std::process::Command::new("sh")
        .current_dir(tmp.path())
        .args([
            "-c",
            "trap '' XFSZ; ulimit -f 400; exec \"$0\" \"$@\"",
            env!("CARGO_BIN_EXE_rubsim"),
            "run",
            data("single.toml").to_str().unwrap(),
            "--set",
            "output.hdf5={}",
            "--set",
            "output.png=false",
            "--set",
            "run.error_estimate=false",
            "--out",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && o.status.code() != Some(101), "{err}");
    for want in [
        "results.vtkhdf",
        "writing HDF5",
        "since step 0 (t = ",
        "File too large",
    ] {
        assert!(err.contains(want), "`{want}` not in: {err}");
    }
    assert_nothing_written(&out);
}

#[test]
fn run_writes_summary_and_pictures() {
    let tmp = TempDir::new().unwrap();
    let out = tmp.path().join("single");
    let stdout = ok(
        tmp.path(),
        &[
            "run",
            data("single.toml").to_str().unwrap(),
            "--set",
            "output.png=true",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(stdout.contains("results in"), "{stdout}");
    let sum = json(&out.join("summary.json"));
    assert_eq!(sum["command"], "run");
    let r = &sum["result"];
    let period = r["period"].as_u64().expect("result.period is an integer");
    assert!(period >= 1, "period {period}");
    let min_gap = r["stats"]["min_gap"]
        .as_f64()
        .expect("result.stats.min_gap");
    assert!(min_gap >= -1e-9, "penetration: min_gap = {min_gap}");
    assert!(
        r["contact_fraction"].as_f64().unwrap() > 0.0,
        "scene should rub"
    );
    for png in ["orbit.png", "spectrum.png", "contact_force.png"] {
        assert!(is_png(&out.join(png)), "{png} is not a PNG");
    }
    assert!(
        !tree(&out)
            .iter()
            .any(|p| p.to_string_lossy().contains(".rubsim-partial-")),
        "staging folder left: {:?}",
        tree(&out)
    );
}

#[test]
fn run_without_out_writes_to_out_scene_name() {
    let tmp = TempDir::new().unwrap();
    ok(tmp.path(), &["run", data("single.toml").to_str().unwrap()]);
    let sum = json(&tmp.path().join("out/single/summary.json"));
    assert_eq!(sum["command"], "run");
    // png = false in the scene.
    assert!(!tmp.path().join("out/single/orbit.png").exists());
}

const SWEEP_COLUMNS: &str = "speed_ratio,period,x_min_nd,x_max_nd,y_min_nd,y_max_nd,amp_1x_nd,amp_half_nd,amp_third_nd,contact_force_max_nd,steps,wall_s";

/// Rows of sweep.csv below its header (checked), each split into fields.
fn sweep_rows(out: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let csv = read(&out.join("sweep.csv"));
    let mut lines = csv.lines();
    let header = lines.next().expect("sweep.csv header");
    assert!(
        header == SWEEP_COLUMNS || header.starts_with(&format!("{SWEEP_COLUMNS},")),
        "sweep.csv header: {header}"
    );
    let cols: Vec<String> = header.split(',').map(String::from).collect();
    let rows: Vec<Vec<String>> = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    for r in &rows {
        assert_eq!(r.len(), cols.len(), "ragged row {r:?}");
    }
    (cols, rows)
}

#[test]
fn sweep_writes_csv_and_rerun_replaces_it() {
    let tmp = TempDir::new().unwrap();
    let out = tmp.path().join("sweep");
    let o = out.to_str().unwrap();
    let s = data("sweep.toml");
    let s = s.to_str().unwrap();

    ok(tmp.path(), &["sweep", s, "--out", o]);
    let (cols, rows) = sweep_rows(&out);
    let speeds: Vec<f64> = rows.iter().map(|r| r[0].parse().unwrap()).collect();
    assert_eq!(speeds.len(), 3, "one row per speed: {rows:?}");
    for (got, want) in speeds.iter().zip([1.5, 2.0, 2.5]) {
        assert!((got - want).abs() < 1e-9, "speeds {speeds:?}");
    }
    for r in &rows {
        r[1].parse::<u64>().expect("period is an integer");
        assert!(r[10].parse::<u64>().unwrap() > 0, "steps {r:?}");
    }
    let sum = json(&out.join("summary.json"));
    assert_eq!(sum["command"], "sweep");
    assert_eq!(sum["sweeps"][0]["speeds"].as_array().unwrap().len(), 3);
    let cf = cols
        .iter()
        .position(|c| c == "contact_fraction")
        .expect("contact_fraction column");

    // Rerun with a different setting into the same directory: files are replaced (the cases
    // of the other scene discarded by --fresh; without it the run is refused, issue 12).
    ok(
        tmp.path(),
        &[
            "sweep",
            s,
            "--set",
            "run.sweep.to=2.0",
            "--set",
            "stator.0.clearance_nd=5",
            "--out",
            o,
            "--fresh",
        ],
    );
    let (_, rows) = sweep_rows(&out);
    assert_eq!(rows.len(), 2, "sweep.csv not replaced: {rows:?}");
    for r in &rows {
        assert_eq!(
            r[cf].parse::<f64>().unwrap(),
            0.0,
            "no contact expected: {r:?}"
        );
    }
    let sum = json(&out.join("summary.json"));
    assert_eq!(sum["sweeps"][0]["speeds"].as_array().unwrap().len(), 2);
    assert_eq!(sum["overrides"][1], "stator.0.clearance_nd=5");
    assert!(
        tree(&out)
            .iter()
            .all(|p| !p.to_string_lossy().contains(".rubsim-partial-")),
        "{:?}",
        tree(&out)
    );
}

#[test]
fn override_changes_the_result() {
    let tmp = TempDir::new().unwrap();
    let s = data("single.toml");
    let s = s.to_str().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    ok(tmp.path(), &["run", s, "--out", a.to_str().unwrap()]);
    ok(
        tmp.path(),
        &[
            "run",
            s,
            "--set",
            "stator.0.clearance_nd=5",
            "--out",
            b.to_str().unwrap(),
        ],
    );
    let (a, b) = (json(&a.join("summary.json")), json(&b.join("summary.json")));
    assert!(a["result"]["contact_fraction"].as_f64().unwrap() > 0.0);
    assert_eq!(b["result"]["contact_fraction"].as_f64().unwrap(), 0.0);
    assert_eq!(b["result"]["stats"]["contact_steps"].as_u64().unwrap(), 0);
    assert_eq!(b["overrides"][0], "stator.0.clearance_nd=5");
    assert_eq!(b["scene"]["stator"][0]["clearance_nd"].as_f64(), Some(5.0));
}

#[test]
fn orbits_and_spectra_at_a_chosen_rotor_node() {
    // `output.node` moves the analysis (orbit, period, spectrum, |Z0|) to any rotor node.
    // Oracle: on isotropic bearings and without contact, the steady orbit of every node is the
    // circle of radius |Z0(node)| from the frequency-domain unbalance response, so the
    // non-dimensional extents are ±1 at each node, while |Z0| differs from node to node.
    let tmp = TempDir::new().unwrap();
    let scene = repo("scenes/fe/two_disk_two_stations.toml");
    let scene = scene.to_str().unwrap();
    let free = [
        "run.revolutions=60",
        "run.transient_revolutions=50",
        "run.error_estimate=false",
        "rotor.rayleigh=[20.0, 0.0]",
        "rotor.bearing.1.kyy=1e6",
        "stator.0.clearance_nd=50",
        "stator.1.clearance_nd=50",
        "output.png=false",
    ];
    let run_at = |node: Option<&str>, name: &str| -> serde_json::Value {
        let out = tmp.path().join(name);
        let mut args = vec![
            "run",
            scene,
            "--speed",
            "1.2",
            "--out",
            out.to_str().unwrap(),
        ];
        for f in &free {
            args.extend_from_slice(&["--set", f]);
        }
        if let Some(n) = node {
            args.extend_from_slice(&["--set", n]);
        }
        ok(tmp.path(), &args);
        json(&out.join("summary.json"))["result"].clone()
    };
    let default = run_at(None, "default");
    assert_eq!(default["node"], 2, "default: the first station's node");
    let mut z0s = Vec::new();
    for node in [0, 2, 3] {
        let r = run_at(Some(&format!("output.node={node}")), &format!("n{node}"));
        assert_eq!(r["node"], node);
        assert_eq!(r["contact_fraction"].as_f64(), Some(0.0));
        for (k, e) in r["extents_nd"].as_array().unwrap().iter().enumerate() {
            let want = if k % 2 == 0 { -1.0 } else { 1.0 };
            let e = e.as_f64().unwrap();
            assert!(
                (e - want).abs() < 2e-3,
                "node {node}: extents {}",
                r["extents_nd"]
            );
        }
        z0s.push(r["z0"].as_f64().unwrap());
        if node == 2 {
            assert_eq!(r["extents_nd"], default["extents_nd"]);
        }
    }
    // The journal at the bearing moves less than the shaft between the disks.
    assert!(z0s[0] < 0.5 * z0s[2] && z0s[2] < z0s[1] * 1.5, "{z0s:?}");
    // A node that does not exist is refused, naming the key.
    let err = fails(tmp.path(), &["check", scene, "--set", "output.node=99"]);
    assert!(
        err.contains("output.node") && err.contains("node 99"),
        "{err}"
    );
    let err = fails(
        tmp.path(),
        &[
            "check",
            data("single.toml").to_str().unwrap(),
            "--set",
            "output.node=1",
        ],
    );
    assert!(
        err.contains("output.node") && err.contains("Jeffcott"),
        "{err}"
    );
}

// ---------------------------------------------------------------------------------------------
// Other commands

/// The scene with torsion as the CLI sees it: `rubsim modal` lists the torsional mode in its
/// table and CSV.
#[test]
fn cli_modal_reports_the_torsional_mode() {
    let tmp = TempDir::new().unwrap();
    let dir = tmp.path().join("modal");
    let out = rubsim(
        &repo(""),
        &[
            "modal",
            "scenes/fe/paper_rotor_rub_torsion.toml",
            "--out",
            dir.to_str().unwrap(),
        ],
    );
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let csv = std::fs::read_to_string(dir.join("modes.csv")).unwrap();
    let tors: Vec<&str> = csv.lines().filter(|l| l.contains(",torsional,")).collect();
    assert!(!tors.is_empty(), "{csv}");
    // First torsional mode: disk I_p on the shaft half (G J/0.2 m) in series with the
    // 1000 N·m/rad coupling, ≈ √(274/0.00476) ≈ 240 rad/s minus the shaft's inertia share.
    let w: f64 = tors[0].split(',').nth(1).unwrap().parse().unwrap();
    assert!(w > 225.0 && w < 245.0, "{w}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("torsional"));
}

#[test]
fn cli_mesh_check_stress_and_refine() {
    if !need_gmsh() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    let (ok, out, err) = in_repo(&[
        "mesh",
        "geometry/diaphragm.geo",
        "--set",
        "h=0.008",
        "--cache",
        cache.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(
        out.contains("group `joint`")
            && out.contains("conforming")
            && out.contains("face the axis"),
        "{out}"
    );
    let (ok, out, _) = in_repo(&[
        "mesh",
        "geometry/diaphragm.geo",
        "--set",
        "h=0.008",
        "--cache",
        cache.to_str().unwrap(),
    ]);
    assert!(ok && out.contains("up to date, gmsh not run"), "{out}");
    for scene in [
        "rod2d",
        "annulus",
        "diaphragm",
        "segmented_casing",
        "segmented_casing_beams",
        "labyrinth_seal",
        "labyrinth_seal_step",
        "bench_annulus",
        "bench_casing_mass",
    ] {
        // The meshed stator is resolved the same with or without the step's pilot runs
        // (`run.auto_step`, 110 s of CPU over these scenes, three quarters of it in the two
        // labyrinth seals); the pilots behind `check` are tested in tests/suite/autostep.rs.
        let (ok, out, err) = in_repo(&[
            "check",
            &format!("scenes/stators/{scene}.toml"),
            "--set",
            "run.auto_step=false",
        ]);
        assert!(ok, "{scene}: {err}");
        assert!(
            out.contains("meshed stator (gmsh)") && !out.contains("mesher (no meshed stator)"),
            "{scene}: {out}"
        );
    }
    // Quadratic mesh with frames on 3-node lines (straight between their ends).
    let (ok, out, err) = in_repo(&[
        "check",
        "scenes/stators/segmented_casing_beams.toml",
        "--set",
        "stator.0.order=2",
    ]);
    assert!(ok && out.contains("meshed stator"), "{err}");
    let o = dir.path().join("stress");
    let (ok, out, err) = in_repo(&[
        "stress",
        "scenes/stators/rod2d.toml",
        "--speed",
        "1.7",
        "--set",
        "run.revolutions=30",
        "--set",
        "run.transient_revolutions=10",
        "--out",
        o.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("largest |stress|"), "{out}");
    for f in [
        "stress.csv",
        "stress.png",
        "strain.png",
        "summary.json",
        "stress_field_rod_1.7.png",
    ] {
        assert!(o.join(f).is_file(), "{f} missing");
    }
    let o = dir.path().join("refine");
    let (ok, out, err) = in_repo(&[
        "refine",
        "scenes/stators/rod2d.toml",
        "--key",
        "stator.0.parameters.nx",
        "--values",
        "1,4",
        "--set",
        "run.revolutions=30",
        "--set",
        "run.transient_revolutions=10",
        "--out",
        o.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(
        out.contains("2 contact nodes") && out.contains("5 contact nodes"),
        "{out}"
    );
    assert!(o.join("refine.csv").is_file() && o.join("refine_force.png").is_file());
    // A misnamed group, through the command line: file and group named.
    let (ok, _, err) = in_repo(&[
        "check",
        "scenes/stators/rod2d.toml",
        "--set",
        "stator.0.contact_group=\"tip\"",
    ]);
    assert!(
        !ok && err.contains("rod-") && err.contains(".msh") && err.contains("`tip`"),
        "{err}"
    );
}

#[test]
fn run_with_a_speed_profile_writes_the_transient_outputs() {
    let tmp = TempDir::new().unwrap();
    // The paper's run-up shortened to 2 s (0.5 → 2 ωn): through the rub around the critical.
    let scene = tmp.path().join("runup.toml");
    let text = read(&repo("scenes/transients/paper_runup.toml"))
        .replace("to = 6.0", "to = 2.0")
        .replace("duration = 30.0", "duration = 2.0");
    std::fs::write(&scene, text).unwrap();
    let out = tmp.path().join("o");
    let so = ok(
        tmp.path(),
        &[
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(
        so.contains("speed profile") && so.contains("peak 1×"),
        "{so}"
    );
    // The error estimate: printed, and in summary.json with its companion (the explicit run
    // below half its stability limit: a companion at 2Δt).
    assert!(
        so.contains("estimated error: the tracked 1× within"),
        "{so}"
    );
    for f in [
        "speed_history.csv",
        "response.csv",
        "orders.csv",
        "summary.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    for f in [
        "bode.png",
        "orders.png",
        "response.png",
        "contact_force.png",
    ] {
        assert!(is_png(&out.join(f)), "{f}");
    }
    let s = json(&out.join("summary.json"));
    let tr = &s["transient"];
    assert!(tr["stats"]["contact_steps"].as_u64().unwrap() > 0, "{tr}");
    assert!(tr["friction_energy"].as_f64().unwrap() > 0.0, "{tr}");
    let e = &tr["error_estimate"];
    let rel = e["relative_1x"].as_f64().unwrap();
    assert!(rel > 0.0 && rel < 1e-2, "{e}");
    assert_eq!(e["order"].as_f64(), Some(2.0), "{e}");
    let (dt, cdt) = (
        tr["plan"]["dt"].as_f64().unwrap(),
        e["companion_dt"].as_f64().unwrap(),
    );
    assert!((cdt / dt - 2.0).abs() < 1e-3, "{dt} {cdt}");
    let orders = read(&out.join("orders.csv"));
    assert!(orders.starts_with("t_s,omega_rad_s,speed_ratio,amp_1x_m,phase_1x_rad,amp_0.5x_m"));
    let hist = read(&out.join("speed_history.csv"));
    let last: Vec<f64> = hist
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert!(
        (last[2] - 2.0).abs() < 1e-3,
        "final speed ratio {}",
        last[2]
    );
    // Bad input names the key and its line; --speed does not apply.
    let bad = tmp.path().join("bad.toml");
    std::fs::write(
        &bad,
        read(&scene).replace("duration = 2.0", "acceleration = -1.0"),
    )
    .unwrap();
    let err = fails(tmp.path(), &["check", bad.to_str().unwrap()]);
    let line = line_of(&bad, "acceleration = -1.0");
    assert!(
        err.contains(&format!(
            "bad.toml:{line}: key `run.speed_profile.acceleration`"
        )),
        "{err}"
    );
    let err = fails(
        tmp.path(),
        &[
            "run",
            scene.to_str().unwrap(),
            "--speed",
            "1.0",
            "--out",
            tmp.path().join("o2").to_str().unwrap(),
        ],
    );
    assert!(err.contains("--speed does not apply"), "{err}");
    assert_nothing_written(&tmp.path().join("o2"));
}
