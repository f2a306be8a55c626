//! gmsh under guard (issue 13, items 7 and 10): a time limit, killed with rubsim whatever stops
//! it, no temporary file left in the mesh cache, its repeated lines counted, parameters checked
//! against the bounds a geometry declares before gmsh runs; and what `rubsim mesh` and a scene
//! say about a mesh (`.msh`) given where a geometry is expected.
//!
//! A fake gmsh (a shell script named by `RUBSIM_GMSH`) stands in for a slow or chatty gmsh: it
//! records its pid, writes part of its output file and sleeps.

use crate::common;

use common::cli::{command, fails, in_repo, ok, text, tree};
use common::meshes::{need_gmsh, ring_msh};
use common::repo;
use rubsim::mesh::CellKind;
use std::f64::consts::PI;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// A fake gmsh in `dir`: writes its pid to `dir/gmsh.pid`, 100 kB to its `-o` file, prints
/// `lines` copies of a gmsh error line, then runs `then` (`exec sleep 60`: a gmsh that hangs).
fn fake_gmsh(dir: &Path, lines: usize, then: &str) -> PathBuf {
    let script = dir.join("fake-gmsh");
    let pid = dir.join("gmsh.pid");
    std::fs::write(
        &script,
        format!(
            "#!/bin/sh\nout=\"\"; prev=\"\"\nfor a in \"$@\"; do [ \"$prev\" = \"-o\" ] && out=\"$a\"; prev=\"$a\"; done\n\
             head -c 100000 /dev/zero > \"$out\"\n\
             i=0; while [ $i -lt {lines} ]; do echo 'Error   : Wrong mesh element size lc = 0 (lcmin = 0, lcmax = 0)'; i=$((i+1)); done\n\
             echo $$ > {pid}.tmp && mv {pid}.tmp {pid}\n{then}\n",
            pid = pid.display()
        ),
    )
    .unwrap();
    let mut perm = std::fs::metadata(&script).unwrap().permissions();
    std::os::unix::fs::PermissionsExt::set_mode(&mut perm, 0o755);
    std::fs::set_permissions(&script, perm).unwrap();
    script
}

/// `rubsim mesh geometry/annulus.geo` into the cache `dir/cache` with the fake gmsh `gmsh`.
fn mesh_with(dir: &Path, gmsh: &Path) -> Command {
    let mut c = command(&repo(""));
    c.args(["mesh", "geometry/annulus.geo", "--cache"])
        .arg(dir.join("cache"))
        .env("RUBSIM_GMSH", gmsh)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    c
}

/// The pid the fake gmsh wrote, waiting for it (at most 20 s).
fn gmsh_pid(dir: &Path, rubsim: &mut Child) -> i32 {
    let t0 = Instant::now();
    loop {
        if let Ok(s) = std::fs::read_to_string(dir.join("gmsh.pid")) {
            return s.trim().parse().unwrap();
        }
        if let Ok(Some(st)) = rubsim.try_wait() {
            panic!("rubsim ended before gmsh started: {st}");
        }
        assert!(
            t0.elapsed() < Duration::from_secs(20),
            "fake gmsh never started"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// True while process `pid` exists and is not a zombie.
fn alive(pid: i32) -> bool {
    match std::fs::read_to_string(format!("/proc/{pid}/stat")) {
        Ok(stat) => !stat
            .rsplit_once(')')
            .is_some_and(|(_, rest)| rest.trim_start().starts_with('Z')),
        Err(_) => false,
    }
}

/// Waits up to 5 s for process `pid` to be gone.
fn gone(pid: i32) -> bool {
    let t0 = Instant::now();
    while alive(pid) {
        if t0.elapsed() > Duration::from_secs(5) {
            return false;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    true
}

/// The files in the cache directory (temporary files included).
fn cache_files(dir: &Path) -> Vec<PathBuf> {
    tree(&dir.join("cache"))
}

fn signal(pid: u32, sig: i32) {
    // SAFETY: sending a signal to a child we started.
    assert_eq!(unsafe { libc::kill(pid as i32, sig) }, 0);
}

#[test]
fn a_negative_pitch_is_refused_before_gmsh_runs_naming_the_scene_key() {
    let dir = tempfile::tempdir().unwrap();
    // A gmsh that would hang: the parameter check must come first.
    let gmsh = fake_gmsh(dir.path(), 0, "exec sleep 60");
    let t0 = Instant::now();
    let o = command(&repo(""))
        .args([
            "check",
            "scenes/stators/labyrinth_seal.toml",
            "--set",
            "stator.0.parameters.pitch=-1.0",
        ])
        .env("RUBSIM_GMSH", &gmsh)
        .env("RUBSIM_MESH_DIR", dir.path().join("cache"))
        .output()
        .unwrap();
    let err = text(&o.stderr);
    assert!(!o.status.success() && t0.elapsed() < Duration::from_secs(10));
    assert!(
        err.contains("labyrinth_seal.toml:29")
            && err.contains("stator.0.parameters.pitch")
            && err.contains("labyrinth_seal.geo")
            && err.contains("-1")
            && err.contains("at least 0.0001"),
        "{err}"
    );
    assert!(!dir.path().join("gmsh.pid").exists(), "gmsh ran");
}

#[test]
fn parameters_outside_a_geometrys_bounds_and_non_finite_ones_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let gmsh = fake_gmsh(dir.path(), 0, "exec sleep 60");
    for (set, want) in [
        ("h=0", "`h` = 0: must be at least 0.00001"),
        ("n=-3", "`n` = -3: must be at least 0"),
    ] {
        let o = mesh_with(dir.path(), &gmsh)
            .args(["--set", set])
            .output()
            .unwrap();
        let err = text(&o.stderr);
        assert!(!o.status.success() && err.contains(want), "{set}: {err}");
    }
    // Through the library: NaN is refused whatever the bounds.
    let mut req = rubsim::mesh::gmsh::MeshRequest::new(repo("geometry/rod.geo"));
    req.parameters.insert("y0".into(), f64::NAN);
    let e = rubsim::mesh::gmsh::mesh(&req, &dir.path().join("cache"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("`y0` = NaN") && e.contains("finite"), "{e}");
    assert!(!dir.path().join("gmsh.pid").exists(), "gmsh ran");
}

#[test]
fn the_labyrinth_seal_refuses_teeth_that_cannot_be_built_at_once() {
    if !need_gmsh() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let cache = dir.path().join("cache");
    for (set, want) in [
        (
            "pitch=0.0005",
            "pitch = 0.0005 must exceed the tooth thickness",
        ),
        ("teeth=2.5", "teeth = 2.5 must be a whole number"),
        ("rt=0.07", "rt < rc < ro"),
    ] {
        let t0 = Instant::now();
        let (ok, _, err) = in_repo(&[
            "mesh",
            "geometry/labyrinth_seal.geo",
            "--set",
            set,
            "--cache",
            cache.to_str().unwrap(),
        ]);
        assert!(!ok && err.contains(want), "{set}: {err}");
        assert!(
            t0.elapsed() < Duration::from_secs(20),
            "{set}: {:?}",
            t0.elapsed()
        );
    }
    assert!(tree(&cache).is_empty(), "{:?}", tree(&cache));
}

#[test]
fn gmsh_past_its_time_limit_is_killed_with_an_error_naming_geometry_and_limit() {
    let dir = tempfile::tempdir().unwrap();
    let gmsh = fake_gmsh(dir.path(), 3, "exec sleep 60");
    let t0 = Instant::now();
    let o = mesh_with(dir.path(), &gmsh)
        .env("RUBSIM_GMSH_TIMEOUT", "1.5")
        .output()
        .unwrap();
    let err = text(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(t0.elapsed() < Duration::from_secs(15), "{:?}", t0.elapsed());
    assert!(
        err.contains("annulus.geo")
            && err.contains("within 1.5 s")
            && err.contains("RUBSIM_GMSH_TIMEOUT")
            && err.contains("Wrong mesh element size lc = 0 (lcmin = 0, lcmax = 0) (×3)"),
        "{err}"
    );
    let pid: i32 = std::fs::read_to_string(dir.path().join("gmsh.pid"))
        .unwrap()
        .trim()
        .parse()
        .unwrap();
    assert!(gone(pid), "gmsh {pid} still runs");
    assert!(
        cache_files(dir.path()).is_empty(),
        "{:?}",
        cache_files(dir.path())
    );
    // The command-line option overrides the environment; a bad value is refused.
    let o = mesh_with(dir.path(), &gmsh)
        .args(["--timeout", "0.5"])
        .env("RUBSIM_GMSH_TIMEOUT", "100")
        .output()
        .unwrap();
    assert!(
        text(&o.stderr).contains("within 0.5 s"),
        "{}",
        text(&o.stderr)
    );
    let o = mesh_with(dir.path(), &gmsh)
        .env("RUBSIM_GMSH_TIMEOUT", "soon")
        .output()
        .unwrap();
    assert!(
        text(&o.stderr).contains("RUBSIM_GMSH_TIMEOUT=`soon`"),
        "{}",
        text(&o.stderr)
    );
}

/// Each of SIGTERM, SIGINT and SIGHUP stops rubsim, gmsh and its files. rubsim starts with the
/// signal's default disposition, as from a terminal: a test run started in the background of a
/// script inherits an ignored SIGINT, which rubsim rightly keeps ignored (as under `nohup`) —
/// that made this test fail with "exit status: 2" (gmsh's 60 s sleep over, its mesh unreadable).
#[test]
fn stopping_rubsim_stops_gmsh_and_removes_its_temporary_files() {
    for sig in [libc::SIGTERM, libc::SIGINT, libc::SIGHUP] {
        let dir = tempfile::tempdir().unwrap();
        let gmsh = fake_gmsh(dir.path(), 0, "exec sleep 60");
        let mut cmd = mesh_with(dir.path(), &gmsh);
        // SAFETY: signal(2) is async-signal-safe, called in the child between fork and exec.
        unsafe {
            cmd.pre_exec(move || {
                libc::signal(sig, libc::SIG_DFL);
                Ok(())
            });
        }
        let mut child = cmd.spawn().unwrap();
        let pid = gmsh_pid(dir.path(), &mut child);
        assert!(
            cache_files(dir.path())
                .iter()
                .any(|p| p.to_string_lossy().ends_with(".msh")),
            "the fake gmsh writes its output: {:?}",
            cache_files(dir.path())
        );
        signal(child.id(), sig);
        let status = child.wait().unwrap();
        // rubsim dies of the signal, as it would without gmsh.
        assert_eq!(
            std::os::unix::process::ExitStatusExt::signal(&status),
            Some(sig),
            "{status}"
        );
        assert!(gone(pid), "signal {sig}: gmsh {pid} still runs");
        assert!(
            cache_files(dir.path()).is_empty(),
            "signal {sig}: {:?}",
            cache_files(dir.path())
        );
    }
}

/// A signal ignored when rubsim starts (SIGHUP under `nohup`) stays ignored: the run and gmsh go
/// on; another signal still stops both.
#[test]
fn a_signal_ignored_at_start_stays_ignored_as_under_nohup() {
    let dir = tempfile::tempdir().unwrap();
    let gmsh = fake_gmsh(dir.path(), 0, "exec sleep 60");
    let mut cmd = mesh_with(dir.path(), &gmsh);
    // SAFETY: signal(2) is async-signal-safe, called in the child between fork and exec.
    unsafe {
        cmd.pre_exec(|| {
            libc::signal(libc::SIGHUP, libc::SIG_IGN);
            libc::signal(libc::SIGTERM, libc::SIG_DFL);
            Ok(())
        });
    }
    let mut child = cmd.spawn().unwrap();
    let pid = gmsh_pid(dir.path(), &mut child);
    signal(child.id(), libc::SIGHUP);
    std::thread::sleep(Duration::from_millis(300));
    assert!(
        child.try_wait().unwrap().is_none() && alive(pid),
        "SIGHUP stopped a run that ignores it"
    );
    signal(child.id(), libc::SIGTERM);
    let status = child.wait().unwrap();
    assert_eq!(
        std::os::unix::process::ExitStatusExt::signal(&status),
        Some(libc::SIGTERM),
        "{status}"
    );
    assert!(gone(pid), "gmsh {pid} still runs");
    assert!(
        cache_files(dir.path()).is_empty(),
        "{:?}",
        cache_files(dir.path())
    );
}

#[test]
fn gmsh_dies_with_a_killed_rubsim_and_the_next_run_removes_what_it_left() {
    let dir = tempfile::tempdir().unwrap();
    let gmsh = fake_gmsh(dir.path(), 0, "exec sleep 60");
    let mut child = mesh_with(dir.path(), &gmsh).spawn().unwrap();
    let pid = gmsh_pid(dir.path(), &mut child);
    signal(child.id(), libc::SIGKILL);
    child.wait().unwrap();
    // The kernel kills gmsh with its parent (PR_SET_PDEATHSIG); the files stay behind…
    assert!(gone(pid), "gmsh {pid} outlived a killed rubsim");
    assert!(!cache_files(dir.path()).is_empty());
    // … until the next mesher into that cache (here a gmsh that fails at once).
    std::fs::remove_file(dir.path().join("gmsh.pid")).unwrap();
    let quick = fake_gmsh(dir.path(), 1, "exit 1");
    let o = mesh_with(dir.path(), &quick).output().unwrap();
    assert!(!o.status.success());
    assert!(
        cache_files(dir.path()).is_empty(),
        "{:?}",
        cache_files(dir.path())
    );
}

#[test]
fn a_killed_gmsh_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let gmsh = fake_gmsh(dir.path(), 0, "exec sleep 60");
    let mut child = mesh_with(dir.path(), &gmsh).spawn().unwrap();
    let pid = gmsh_pid(dir.path(), &mut child);
    signal(pid as u32, libc::SIGKILL);
    let o = child.wait_with_output().unwrap();
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("gmsh failed"),
        "{}",
        text(&o.stderr)
    );
    assert!(
        cache_files(dir.path()).is_empty(),
        "{:?}",
        cache_files(dir.path())
    );
}

#[test]
fn repeated_gmsh_lines_are_counted_not_repeated() {
    let dir = tempfile::tempdir().unwrap();
    let gmsh = fake_gmsh(
        dir.path(),
        1038,
        "echo 'Error   : No elements in volume 1'\necho 'Error   : ------------------------------'\necho 'Error   :  1039 errors'\nexit 1",
    );
    let o = mesh_with(dir.path(), &gmsh).output().unwrap();
    let err = text(&o.stderr);
    assert!(!o.status.success());
    assert!(err.lines().count() <= 4, "{err}");
    assert!(
        err.contains("Wrong mesh element size lc = 0 (lcmin = 0, lcmax = 0) (×1038)")
            && err.contains("No elements in volume 1")
            && !err.contains("1039 errors"),
        "{err}"
    );
}

#[test]
fn an_element_size_of_zero_on_a_geometry_without_bounds_prints_a_few_lines() {
    if !need_gmsh() {
        return;
    }
    // annulus.geo without its declared bounds: gmsh itself fails, once per curve and point.
    let dir = tempfile::tempdir().unwrap();
    let geo = dir.path().join("ring.geo");
    std::fs::write(
        &geo,
        "SetFactory(\"OpenCASCADE\");\nDefineConstant[ h = 0.004 ];\nDisk(1) = {0, 0, 0, 0.08, 0.08};\nDisk(2) = {0, 0, 0, 0.06, 0.06};\nBooleanDifference{ Surface{1}; Delete; }{ Surface{2}; Delete; }\nMeshSize{ PointsOf{ Surface{:}; } } = h;\nMesh.MeshSizeMax = h;\nPhysical Surface(\"stator\") = {1};\n",
    )
    .unwrap();
    let (ok, _, err) = in_repo(&[
        "mesh",
        geo.to_str().unwrap(),
        "--set",
        "h=0",
        "--cache",
        dir.path().join("cache").to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.lines().count() < 10 && err.contains("(×"), "{err}");
}

// ---------------------------------------------------------------------------------------------
// A mesh where a geometry is expected.

/// The annulus scene with its geometry replaced by the ring mesh `ring.msh` in `dir`, `extra`
/// in place of its `parameters` line (29) and without its `quads`.
fn msh_scene(dir: &Path, extra: &str) -> PathBuf {
    let msh = ring_msh(CellKind::Quad4, 0.0602, 0.08, 0.0, 2.0 * PI, 2, 32, true);
    std::fs::write(dir.join("ring.msh"), msh).unwrap();
    let scene = std::fs::read_to_string(repo("scenes/stators/annulus.toml"))
        .unwrap()
        .replace(
            "geometry = \"geometry/annulus.geo\"",
            "geometry = \"ring.msh\"",
        )
        .replace("quads = true\n", "")
        .replace(
            "parameters = { ri = 0.0602, ro = 0.08, h = 0.004, n = 128 }",
            extra,
        );
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    path
}

#[test]
fn meshing_options_on_a_msh_geometry_are_refused_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let plain = msh_scene(d, "");
    ok(d, &["check", plain.to_str().unwrap()]);
    for (extra, key) in [
        ("parameters = { h = 0.004 }", "stator.0.parameters.h"),
        ("size_factor = 0.5", "stator.0.size_factor"),
        ("quads = true", "stator.0.quads"),
    ] {
        let scene = msh_scene(d, extra);
        let err = fails(d, &["check", scene.to_str().unwrap()]);
        assert!(
            err.contains(&format!("scene.toml:29: key `{key}`"))
                && err.contains("ring.msh")
                && err.contains("read as it is"),
            "{extra}: {err}"
        );
    }
    // The same through --set.
    let err = fails(
        d,
        &[
            "check",
            plain.to_str().unwrap(),
            "--set",
            "stator.0.parameters.h=0.1",
        ],
    );
    assert!(err.contains("stator.0.parameters.h"), "{err}");
}

#[test]
fn rubsim_mesh_reports_a_msh_file_and_warns_without_a_contact_boundary() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let msh = ring_msh(CellKind::Quad4, 0.0602, 0.08, 0.0, 2.0 * PI, 2, 32, true);
    std::fs::write(d.join("ring.msh"), &msh).unwrap();
    let o = command(d).args(["mesh", "ring.msh"]).output().unwrap();
    let (out, err) = (text(&o.stdout), text(&o.stderr));
    assert!(o.status.success(), "{err}");
    assert!(
        out.contains("read as it is") && out.contains("stator_contact: ") && err.is_empty(),
        "{out}\n{err}"
    );
    // Without `stator_contact`: a warning naming the boundary groups that could serve.
    std::fs::write(
        d.join("nocontact.msh"),
        msh.replace("\"stator_contact\"", "\"inner\""),
    )
    .unwrap();
    let o = command(d).args(["mesh", "nocontact.msh"]).output().unwrap();
    let err = text(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("warning: nocontact.msh: no physical group `stator_contact`")
            && err.contains("`inner`")
            && err.contains("contact_group"),
        "{err}"
    );
    // Naming the group reports it; naming a missing one is an error.
    let out = ok(d, &["mesh", "nocontact.msh", "--contact-group", "inner"]);
    assert!(out.contains("inner: "), "{out}");
    let err = fails(d, &["mesh", "nocontact.msh", "--contact-group", "tip"]);
    assert!(err.contains("no physical group `tip`"), "{err}");
}

#[test]
fn a_binary_msh_is_read_and_an_old_one_gets_the_conversion_command() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // MSH 2.2 binary: the version, what is read and how to convert.
    let mut old = b"$MeshFormat\n2.2 1 8\n".to_vec();
    old.extend_from_slice(&[1, 0, 0, 0, 0xff, 0xfe, 0x80]);
    old.extend_from_slice(b"\n$EndMeshFormat\n");
    std::fs::write(d.join("old.msh"), &old).unwrap();
    let err = fails(d, &["mesh", "old.msh"]);
    assert!(
        err.contains("old.msh")
            && err.contains("version 2.2, binary")
            && err.contains("MSH 4.1, ASCII or binary")
            && err.contains("gmsh FILE.msh -save -format msh41 -o NEW.msh"),
        "{err}"
    );
    // A mesh handed to the mesher (library) is named as such.
    let e = rubsim::mesh::gmsh::mesh(
        &rubsim::mesh::gmsh::MeshRequest::new(d.join("old.msh")),
        &d.join("cache"),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("a gmsh mesh (MSH), not a geometry"), "{e}");
    // A binary file that is not a mesh either.
    std::fs::write(d.join("blob.geo"), [0u8, 159, 146, 150]).unwrap();
    let err = fails(d, &["mesh", "blob.geo"]);
    assert!(err.contains("not text") && err.contains(".step"), "{err}");
    // A binary MSH 4.1 as gmsh writes it is read and reported.
    if !need_gmsh() {
        return;
    }
    ok(
        &repo(""),
        &[
            "mesh",
            "geometry/rod.geo",
            "--cache",
            d.join("cache").to_str().unwrap(),
            "--out",
            d.join("rod.msh").to_str().unwrap(),
        ],
    );
    let bytes = std::fs::read(d.join("rod.msh")).unwrap();
    assert!(bytes.starts_with(b"$MeshFormat\n4.1 1 8"), "not binary");
    let out = ok(d, &["mesh", "rod.msh"]);
    assert!(
        out.contains("read as it is") && out.contains("stator_contact: "),
        "{out}"
    );
}
