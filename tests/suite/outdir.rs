//! The output directory protocol through the real binary: a manifest cannot make rubsim
//! delete a file outside `--out`; a second run into a locked directory fails at once; a commit
//! killed at every one of its steps leaves either no `summary.json` or exactly one run's
//! complete results, and the next run recovers; signals and a closed stdout leave the previous
//! results intact or commit the new ones; reruns leave no empty folders.
//!
//! The commit is killed through the test hook `RUBSIM_FAULT_AFTER_STEPS`, compiled only with the
//! `fault-injection` feature (`cargo test --release --features fault-injection`, as
//! scripts/test.sh does); without it a test checks that the variable does nothing.

use crate::common;

use common::cli::{command, ok, text, tree};
use common::data;
use std::collections::BTreeMap;
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Child, Output, Stdio};
use std::time::{Duration, Instant};
use tempfile::TempDir;

/// Every result file below `dir` (protocol files and staging folders excluded) → its bytes.
fn results(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    tree(dir)
        .into_iter()
        .filter(|p| dir.join(p).is_file())
        .map(|p| p.to_string_lossy().into_owned())
        .filter(|p| !p.starts_with(".rubsim-"))
        .map(|p| {
            let b = std::fs::read(dir.join(&p)).unwrap();
            (p, b)
        })
        .collect()
}

/// Names at the top of `dir` that belong to the protocol, apart from the lock and manifest.
fn leftovers(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".rubsim-") && n != ".rubsim-lock" && n != ".rubsim-files")
        .collect()
}

/// Every folder below `dir` that is empty.
fn empty_folders(dir: &Path) -> Vec<String> {
    tree(dir)
        .into_iter()
        .filter(|p| {
            let d = dir.join(p);
            d.is_dir() && std::fs::read_dir(&d).unwrap().next().is_none()
        })
        .map(|p| p.to_string_lossy().into_owned())
        .collect()
}

/// `rubsim run single.toml --out out sets…` as a command (not yet started).
fn run_cmd(cwd: &Path, out: &Path, sets: &[&str]) -> std::process::Command {
    let mut c = command(cwd);
    c.arg("run").arg(data("single.toml")).arg("--out").arg(out);
    for s in sets {
        c.args(["--set", s]);
    }
    c
}

fn run_out(cwd: &Path, out: &Path, sets: &[&str]) -> Output {
    run_cmd(cwd, out, sets).output().unwrap()
}

fn assert_ok(o: &Output) {
    assert!(
        o.status.success(),
        "rubsim failed ({}):\n{}",
        o.status,
        text(&o.stderr)
    );
}

/// Two runs whose file sets differ both ways: A has frames that B lacks, B has pictures.
const A: &[&str] = &["output.vtk={ from_revolution = 29.8 }"];
const B: &[&str] = &["output.vtk={ from_revolution = 29.9 }", "output.png=true"];

/// The results of a completed run, without `summary.json` (it holds the wall time).
#[cfg(feature = "fault-injection")]
fn reference(cwd: &Path, sets: &[&str]) -> BTreeMap<String, Vec<u8>> {
    let dir = cwd.join(format!("ref-{}", sets.len()));
    assert_ok(&run_out(cwd, &dir, sets));
    let mut r = results(&dir);
    assert!(r.remove("summary.json").is_some());
    r
}

/// The directory holds `want` plus a `summary.json` whose overrides are `sets`, and nothing
/// of another run, no staging folder, no journal.
#[cfg(feature = "fault-injection")]
fn assert_complete(dir: &Path, want: &BTreeMap<String, Vec<u8>>, sets: &[&str]) {
    let mut got = results(dir);
    let sum: serde_json::Value =
        serde_json::from_slice(&got.remove("summary.json").expect("summary.json")).unwrap();
    assert_eq!(sum["overrides"], serde_json::json!(sets));
    assert!(
        got.keys().eq(want.keys()),
        "files {:?}\nwant {:?}",
        got.keys(),
        want.keys()
    );
    for (k, v) in want {
        assert!(&got[k] == v, "{k} differs from its run's");
    }
    assert!(leftovers(dir).is_empty(), "{:?}", leftovers(dir));
    assert!(empty_folders(dir).is_empty(), "{:?}", empty_folders(dir));
}

/// Issue 13, item 1: `echo /some/other/file > o/.rubsim-files; rubsim run … --out o` deleted
/// the file. Entries outside the directory are ignored with a warning naming the line.
#[test]
fn manifest_naming_files_outside_the_directory_deletes_nothing() {
    let tmp = TempDir::new().unwrap();
    let victim = tmp.path().join("victim.txt");
    std::fs::write(&victim, "keep me").unwrap();
    let out = tmp.path().join("o");
    std::fs::create_dir(&out).unwrap();
    // A link inside the directory that leads out of it.
    std::os::unix::fs::symlink(tmp.path(), out.join("up")).unwrap();
    std::fs::write(
        out.join(".rubsim-files"),
        format!("{}\n../victim.txt\nup/victim.txt\n", victim.display()),
    )
    .unwrap();
    let o = run_out(tmp.path(), &out, &[]);
    assert_ok(&o);
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "keep me");
    let err = text(&o.stderr);
    for (line, why) in [
        (1, "absolute path"),
        (2, "`..` component"),
        (3, "crosses a symbolic link"),
    ] {
        assert!(
            err.contains(&format!(".rubsim-files:{line}: ignored the entry")) && err.contains(why),
            "no warning for line {line}:\n{err}"
        );
    }
    assert!(out.join("summary.json").is_file());
    // The new manifest lists only this run's files.
    let m = std::fs::read_to_string(out.join(".rubsim-files")).unwrap();
    assert_eq!(m, "full_spectrum.csv\nsummary.json\n");
}

/// The commit is killed (test hook) before each of its steps in turn, from the first to the
/// last; each time the directory holds no `summary.json` or exactly one run's complete
/// results, and the next run recovers to its own complete results.
#[cfg(feature = "fault-injection")]
#[test]
fn commit_killed_at_every_step_leaves_one_complete_run_and_recovers() {
    let tmp = TempDir::new().unwrap();
    let (ref_a, ref_b) = (reference(tmp.path(), A), reference(tmp.path(), B));
    assert!(ref_a.keys().any(|k| !ref_b.contains_key(k)));
    assert!(ref_b.keys().any(|k| !ref_a.contains_key(k)));
    let dir = tmp.path().join("o");
    assert_ok(&run_out(tmp.path(), &dir, A));
    let mut steps = None;
    for n in 0..200 {
        let o = run_cmd(tmp.path(), &dir, B)
            .env("RUBSIM_FAULT_AFTER_STEPS", n.to_string())
            .output()
            .unwrap();
        if o.status.success() {
            assert_complete(&dir, &ref_b, B);
            steps = Some(n);
            break;
        }
        assert_eq!(
            o.status.code(),
            None,
            "not killed at {n}: {}",
            text(&o.stderr)
        );
        // The invariant at the kill.
        let got = results(&dir);
        if got.contains_key("summary.json") {
            let sum: serde_json::Value = serde_json::from_slice(&got["summary.json"]).unwrap();
            if sum["overrides"] == serde_json::json!(A) {
                assert_complete_but_staged(&dir, &ref_a, A);
            } else {
                assert_complete_but_staged(&dir, &ref_b, B);
            }
        } else {
            for (k, v) in &got {
                assert!(
                    ref_a.get(k) == Some(v) || ref_b.get(k) == Some(v),
                    "killed at {n}: {k} belongs to neither run"
                );
            }
        }
        // The next run recovers: completes or discards the commit, then commits its own.
        let o = run_out(tmp.path(), &dir, A);
        assert_ok(&o);
        assert!(
            text(&o.stderr).contains("interrupted") || text(&o.stderr).contains("did not finish"),
            "no note at {n}: {}",
            text(&o.stderr)
        );
        assert_complete(&dir, &ref_a, A);
    }
    let steps = steps.expect("the commit ends");
    // Journal, old marker, the frames of A that B lacks, manifest, B's files, marker, journal
    // removal, staging removal.
    let gone = ref_a.keys().filter(|k| !ref_b.contains_key(*k)).count();
    assert_eq!(steps, 1 + 1 + gone + 1 + ref_b.len() + 1 + 1 + 1);
    println!("fault injection: {steps} kill points checked");
}

/// Without the `fault-injection` feature the hook is not compiled in: a run that names it
/// commits as any other.
#[cfg(not(feature = "fault-injection"))]
#[test]
fn without_the_feature_the_fault_hook_does_nothing() {
    let tmp = TempDir::new().unwrap();
    let dir = tmp.path().join("o");
    let o = run_cmd(tmp.path(), &dir, A)
        .env("RUBSIM_FAULT_AFTER_STEPS", "0")
        .output()
        .unwrap();
    assert_ok(&o);
    assert!(
        !text(&o.stderr).contains("test hook"),
        "{}",
        text(&o.stderr)
    );
    assert!(dir.join("summary.json").exists() && leftovers(&dir).is_empty());
}

/// After a kill, a directory with `summary.json` holds exactly that run's files; only the
/// journal and staging folder of the killed commit may remain beside them.
#[cfg(feature = "fault-injection")]
fn assert_complete_but_staged(dir: &Path, want: &BTreeMap<String, Vec<u8>>, sets: &[&str]) {
    let mut got = results(dir);
    let sum: serde_json::Value =
        serde_json::from_slice(&got.remove("summary.json").unwrap()).unwrap();
    assert_eq!(sum["overrides"], serde_json::json!(sets));
    assert!(
        got == *want,
        "files {:?}\nwant {:?}",
        got.keys(),
        want.keys()
    );
}

/// Waits (≤ 60 s) until `child` has created its staging folder in `dir`.
fn wait_for_staging(child: &mut Child, dir: &Path) {
    let t0 = Instant::now();
    while !dir.is_dir()
        || !std::fs::read_dir(dir).unwrap().flatten().any(|e| {
            e.file_name()
                .to_string_lossy()
                .starts_with(".rubsim-partial-")
        })
    {
        assert!(child.try_wait().unwrap().is_none(), "run ended early");
        assert!(t0.elapsed() < Duration::from_secs(60), "no staging folder");
        std::thread::sleep(Duration::from_millis(10));
    }
}

const LONG: &str = "run.revolutions=10000";

/// Issue 13, item 2: two runs into one `--out` both succeeded and mixed their files. Now the
/// second fails at once naming the directory, and the first's results are whole.
#[test]
fn second_run_into_a_busy_directory_fails_at_once() {
    let tmp = TempDir::new().unwrap();
    let dir = tmp.path().join("o");
    let mut first = run_cmd(tmp.path(), &dir, &[LONG])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for_staging(&mut first, &dir);
    let t0 = Instant::now();
    let o = run_out(tmp.path(), &dir, &["output.png=true"]);
    let err = text(&o.stderr);
    assert!(!o.status.success() && o.status.code() != Some(101), "{err}");
    assert!(
        err.contains(&format!("{}: another rubsim run is writing", dir.display())),
        "{err}"
    );
    assert!(
        first.try_wait().unwrap().is_none(),
        "not a race: {:?}",
        t0.elapsed()
    );
    assert!(first.wait().unwrap().success());
    let got = results(&dir);
    assert_eq!(
        got.keys().collect::<Vec<_>>(),
        ["full_spectrum.csv", "summary.json"]
    );
    let sum: serde_json::Value = serde_json::from_slice(&got["summary.json"]).unwrap();
    assert_eq!(sum["overrides"], serde_json::json!([LONG]));
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
}

/// Two runs started together into one directory: exactly one succeeds, the other fails with
/// the lock message, and the directory holds the winner's complete results.
#[test]
fn two_runs_raced_into_one_directory_one_wins() {
    let tmp = TempDir::new().unwrap();
    let dir = tmp.path().join("o");
    let sets: [&[&str]; 2] = [&[LONG], &[LONG, "output.png=true"]];
    let children: Vec<Child> = sets
        .iter()
        .map(|s| {
            run_cmd(tmp.path(), &dir, s)
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        })
        .collect();
    let outs: Vec<Output> = children
        .into_iter()
        .map(|c| c.wait_with_output().unwrap())
        .collect();
    let won: Vec<usize> = (0..2).filter(|&i| outs[i].status.success()).collect();
    assert_eq!(won.len(), 1, "exactly one run must win");
    let lost = &outs[1 - won[0]];
    assert!(
        text(&lost.stderr).contains("another rubsim run is writing"),
        "{}",
        text(&lost.stderr)
    );
    let got = results(&dir);
    let sum: serde_json::Value = serde_json::from_slice(&got["summary.json"]).unwrap();
    assert_eq!(sum["overrides"], serde_json::json!(sets[won[0]]));
    // Every run writes its full spectrum's table; the winner with pictures, its PNGs too.
    let pictures = ["full_spectrum.png", "orbit.png", "spectrum.png"];
    let mut want: Vec<&str> = vec!["full_spectrum.csv", "summary.json"];
    if won[0] == 1 {
        want.extend(pictures);
        want.push("contact_force.png");
    }
    want.sort_unstable();
    assert_eq!(got.keys().collect::<Vec<_>>(), want);
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
}

/// SIGTERM or SIGINT during a run: the previous results stay intact (the staging folder
/// remains, since no destructor runs on a signal); the next run removes it under the lock.
#[test]
fn signal_during_a_run_keeps_previous_results() {
    let tmp = TempDir::new().unwrap();
    let dir = tmp.path().join("o");
    assert_ok(&run_out(tmp.path(), &dir, A));
    for sig in [libc::SIGTERM, libc::SIGINT] {
        let before = results(&dir);
        let mut cmd = run_cmd(tmp.path(), &dir, &[LONG, "output.png=true"]);
        // A test run in the background may inherit an ignored SIGINT; a terminal's Ctrl-C
        // meets the default disposition.
        // SAFETY: signal(2) is async-signal-safe, called in the child between fork and exec.
        unsafe {
            cmd.pre_exec(|| {
                libc::signal(libc::SIGINT, libc::SIG_DFL);
                Ok(())
            });
        }
        let mut child = cmd
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        wait_for_staging(&mut child, &dir);
        // SAFETY: kill(2) on the PID of a child this test spawned and has not reaped.
        assert_eq!(unsafe { libc::kill(child.id() as i32, sig) }, 0);
        let status = child.wait().unwrap();
        assert!(!status.success());
        assert!(results(&dir) == before, "signal {sig} changed the results");
        let o = run_out(tmp.path(), &dir, A);
        assert_ok(&o);
        assert!(
            text(&o.stderr).contains("removed the staging folder"),
            "{}",
            text(&o.stderr)
        );
        assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
    }
}

/// `rubsim sweep tests/data/sweep.toml --out dir` with both output streams piped.
fn piped_sweep(cwd: &Path, dir: &Path) -> std::process::Child {
    command(cwd)
        .arg("sweep")
        .arg(data("sweep.toml"))
        .arg("--out")
        .arg(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Issue 13, item 10: `rubsim sweep … | head -1` (SIGPIPE) left the results in the staging
/// folder with no `sweep.csv`. A closed stdout no longer stops the run before its commit.
#[test]
fn sweep_into_a_closed_pipe_still_commits() {
    let tmp = TempDir::new().unwrap();
    let dir = tmp.path().join("sw");
    let mut child = piped_sweep(tmp.path(), &dir);
    // Close the reading end before the sweep prints anything, as `head -1` does once done.
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    assert_ok(&o);
    assert!(dir.join("sweep.csv").is_file());
    assert!(dir.join("summary.json").is_file());
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
    // Standard error closed as well (`rubsim sweep … 2>&1 | head -3`): the estimate and the
    // warnings written there panicked the sweep before it committed (exit 101, only `cases/`).
    let dir = tmp.path().join("sw2");
    let mut child = piped_sweep(tmp.path(), &dir);
    drop(child.stdout.take());
    drop(child.stderr.take());
    let status = child.wait().unwrap();
    assert!(status.success(), "{status:?}");
    assert!(dir.join("summary.json").is_file());
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
}

/// Issue 13, item 10: reruns left empty `speed_*/vtk/` folders. The folders that the
/// previous run's files leave empty are removed with them.
#[test]
fn reruns_leave_no_empty_folders() {
    let tmp = TempDir::new().unwrap();
    let dir = tmp.path().join("sw");
    let d = dir.to_str().unwrap();
    let s = data("sweep.toml");
    let s = s.to_str().unwrap();
    let vtk = "output.vtk={ from_revolution = 29.9 }";
    ok(
        tmp.path(),
        &[
            "sweep",
            s,
            "--out",
            d,
            "--set",
            vtk,
            "--set",
            "output.per_speed=[1.5]",
        ],
    );
    assert!(dir.join("speed_1.5/vtk").is_dir());
    ok(
        tmp.path(),
        &[
            "sweep",
            s,
            "--out",
            d,
            "--set",
            vtk,
            "--set",
            "output.per_speed=[2]",
        ],
    );
    assert!(!dir.join("speed_1.5").exists(), "{:?}", tree(&dir));
    assert!(dir.join("speed_2/vtk").is_dir(), "{:?}", tree(&dir));
    ok(tmp.path(), &["sweep", s, "--out", d]);
    assert!(empty_folders(&dir).is_empty(), "{:?}", empty_folders(&dir));
    assert!(!dir.join("speed_2").exists(), "{:?}", tree(&dir));
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
}

/// Issue 13, item 3: a failure partway through the commit (a directory where `spectrum.png`
/// should go) left new pictures beside the previous `summary.json`. Destinations are checked
/// before the commit point: the run fails naming the path, the previous results are intact.
#[test]
fn commit_that_cannot_complete_changes_nothing() {
    let tmp = TempDir::new().unwrap();
    let dir = tmp.path().join("o");
    assert_ok(&run_out(tmp.path(), &dir, A));
    let before = results(&dir);
    std::fs::create_dir(dir.join("spectrum.png")).unwrap();
    let o = run_out(tmp.path(), &dir, B);
    let err = text(&o.stderr);
    assert!(!o.status.success() && o.status.code() != Some(101), "{err}");
    assert!(
        err.contains("spectrum.png: cannot be written: the path is a directory"),
        "{err}"
    );
    assert!(
        results(&dir) == before,
        "the failed run changed the results"
    );
    assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
}

/// Issue 31 item 9: a non-empty folder rubsim did not make (no `.rubsim-` file in it) is not an
/// output directory: its own `summary.json` and `orbit.png` would be replaced. It is refused
/// naming the folder and `--force`, nothing in it changed; `--force` writes into it, after
/// which it is rubsim's; an empty folder is taken as it is.
#[test]
fn a_folder_rubsim_did_not_make_is_refused_unless_forced() {
    let tmp = TempDir::new().unwrap();
    let mine = tmp.path().join("mine");
    std::fs::create_dir(&mine).unwrap();
    std::fs::write(mine.join("summary.json"), "my own notes").unwrap();
    std::fs::write(mine.join("orbit.png"), "my picture").unwrap();
    let before = results(&mine);
    let o = run_out(tmp.path(), &mine, &[]);
    assert!(!o.status.success());
    let err = text(&o.stderr);
    assert!(
        err.contains(&mine.display().to_string())
            && err.contains("not a rubsim output directory")
            && err.contains("--force"),
        "{err}"
    );
    assert_eq!(results(&mine), before, "the folder was changed");
    assert!(
        std::fs::read_dir(&mine).unwrap().count() == 2,
        "a file was added"
    );
    // Forced: written, and from then on the folder is rubsim's.
    let o = run_cmd(tmp.path(), &mine, &[])
        .arg("--force")
        .output()
        .unwrap();
    assert_ok(&o);
    assert_ne!(
        std::fs::read(mine.join("summary.json")).unwrap(),
        b"my own notes"
    );
    assert_ok(&run_out(tmp.path(), &mine, &[]));
    // An empty folder is fine, and so is one holding only rubsim's output folders (a scene's
    // `out/<scene>/` after `rubsim refine` wrote `out/<scene>/refine/`).
    let empty = tmp.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    assert_ok(&run_out(tmp.path(), &empty, &[]));
    let scene = tmp.path().join("scene");
    assert_ok(&run_out(tmp.path(), &scene.join("refine"), &[]));
    assert_ok(&run_out(tmp.path(), &scene, &[]));
}

/// Issue 31 item 9: `--out /` is refused (as root it wrote the results into `/`), `--force`
/// or not, before anything is computed or written.
#[test]
fn the_file_system_root_is_never_an_output_directory() {
    let tmp = TempDir::new().unwrap();
    for force in [false, true] {
        let mut c = run_cmd(tmp.path(), Path::new("/"), &[]);
        if force {
            c.arg("--force");
        }
        let o = c.output().unwrap();
        assert!(!o.status.success());
        let err = text(&o.stderr);
        assert!(err.contains("root of the file system"), "{err}");
    }
    assert!(!Path::new("/summary.json").exists() && !Path::new("/.rubsim-lock").exists());
}
