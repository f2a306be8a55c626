//! Issue 12: the cases of a sweep have identities and files of their own — a sweep killed by
//! SIGKILL resumes without losing or recomputing a finished case, a changed scene is refused,
//! shards merge into exactly the one-machine results, bad input fails clearly.
//!
//! The tests of resume kill a sweep through the test hooks of `study::store`
//! (`RUBSIM_KILL_AFTER_CASES`, `RUBSIM_CASE_LOG`), compiled only with the `fault-injection`
//! feature (`cargo test --release --features fault-injection`, as scripts/test.sh does).

use crate::common;

use common::cli::{command, fails, ok, text, tree, without_timing};
use common::{read, repo};
#[cfg(feature = "fault-injection")]
use std::collections::BTreeMap;
use std::path::Path;

/// The paper's sweep cut to 16 speeds and shorter runs (a few tenths of a second).
const SETS: &[&str] = &[
    "--set",
    "run.sweep.to=2.0",
    "--set",
    "run.revolutions=120",
    "--set",
    "run.transient_revolutions=60",
];

fn scene() -> String {
    repo("scenes/paper/partial_rub.toml").display().to_string()
}

/// `rubsim sweep <paper> SETS --out out extra…` as arguments.
fn sweep_args<'a>(scene: &'a str, out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut a = vec!["sweep", scene];
    a.extend_from_slice(SETS);
    a.extend_from_slice(&["--out", out, "--jobs", "1"]);
    a.extend_from_slice(extra);
    a
}

/// How many times each case id was written, from the test hook's log.
#[cfg(feature = "fault-injection")]
fn counts(log: &Path) -> BTreeMap<String, usize> {
    let mut m = BTreeMap::new();
    for l in read(log).lines() {
        *m.entry(l.to_string()).or_insert(0) += 1;
    }
    m
}

#[cfg(feature = "fault-injection")]
#[test]
fn a_sweep_killed_by_sigkill_resumes_without_recomputing_or_losing_a_case() {
    let tmp = tempfile::tempdir().unwrap();
    let (s, log) = (scene(), tmp.path().join("log"));
    let out = tmp.path().join("killed");
    let out_s = out.display().to_string();
    let killed = command(tmp.path())
        .args(sweep_args(&s, &out_s, &[]))
        .env("RUBSIM_CASE_LOG", &log)
        .env("RUBSIM_KILL_AFTER_CASES", "7")
        .output()
        .unwrap();
    use std::os::unix::process::ExitStatusExt;
    assert_eq!(killed.status.signal(), Some(9), "{}", text(&killed.stderr));
    assert!(!out.join("summary.json").exists());
    assert_eq!(counts(&log).len(), 7);
    // The rerun computes only the 9 missing cases and says so.
    let o = command(tmp.path())
        .args(sweep_args(&s, &out_s, &[]))
        .env("RUBSIM_CASE_LOG", &log)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("7 of 16 cases already finished"),
        "{}",
        text(&o.stderr)
    );
    let c = counts(&log);
    assert_eq!(c.len(), 16, "{c:?}");
    assert!(c.values().all(|n| *n == 1), "a case computed twice: {c:?}");
    // A third run computes nothing.
    ok(tmp.path(), &sweep_args(&s, &out_s, &[]));
    assert_eq!(read(&log).lines().count(), 16);
    // Identical results to an uninterrupted run.
    let whole = tmp.path().join("whole");
    ok(
        tmp.path(),
        &sweep_args(&s, &whole.display().to_string(), &[]),
    );
    assert_eq!(
        without_timing(&read(&out.join("sweep.csv"))),
        without_timing(&read(&whole.join("sweep.csv")))
    );
    assert_eq!(
        std::fs::read(out.join("bifurcation.png")).unwrap(),
        std::fs::read(whole.join("bifurcation.png")).unwrap()
    );
}

#[test]
fn a_changed_scene_is_refused_and_fresh_starts_afresh() {
    let tmp = tempfile::tempdir().unwrap();
    let s = scene();
    let out = tmp.path().join("o").display().to_string();
    ok(tmp.path(), &sweep_args(&s, &out, &[]));
    let mut changed = sweep_args(&s, &out, &[]);
    changed.extend(["--set", "station.0.friction=0.2"]);
    let err = fails(tmp.path(), &changed);
    assert!(
        err.contains("cases of another scene") && err.contains("--fresh"),
        "{err}"
    );
    // The refused run changed nothing.
    assert!(Path::new(&out).join("summary.json").exists());
    changed.push("--fresh");
    let o = command(tmp.path()).args(&changed).output().unwrap();
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("discarded the cases"));
    let sum: serde_json::Value =
        serde_json::from_str(&read(&Path::new(&out).join("summary.json"))).unwrap();
    assert_eq!(sum["scene"]["station"][0]["friction"], 0.2);
}

#[test]
fn a_damaged_case_file_is_named_not_recomputed_or_read() {
    let tmp = tempfile::tempdir().unwrap();
    let s = scene();
    let out = tmp.path().join("o");
    let out_s = out.display().to_string();
    ok(tmp.path(), &sweep_args(&s, &out_s, &[]));
    let before = without_timing(&read(&out.join("sweep.csv")));
    let case = out.join("cases/speed_ratio=1.2.toml");
    let text = read(&case);
    std::fs::write(&case, &text[..text.len() / 2]).unwrap();
    let err = fails(tmp.path(), &sweep_args(&s, &out_s, &[]));
    assert!(
        err.contains("speed_ratio=1.2.toml") && err.contains("half-written or damaged"),
        "{err}"
    );
    assert_eq!(
        read(&case).len(),
        text.len() / 2,
        "the damaged file was touched"
    );
    // Deleted, the case is computed again.
    std::fs::remove_file(&case).unwrap();
    ok(tmp.path(), &sweep_args(&s, &out_s, &[]));
    assert!(case.is_file());
    assert_eq!(without_timing(&read(&out.join("sweep.csv"))), before);
}

/// Issue 26 item 5: the paper's sweep (56 speeds; orbits at the 30 speeds of its orbit grids,
/// force histories at 3) keeps its case files compact — the numeric arrays packed, base64 of
/// their `f64`s: 6.0 MB in all (108 kB a case, at most 479 kB; 31 kB without an orbit), was
/// 11 MB of decimal TOML (198 kB a case, at most 679 kB). The bounds leave about 20 %. A run
/// assembles its table and figures from the results it holds; resumed, from the files: the
/// same bytes.
#[test]
fn the_paper_sweeps_case_files_are_compact_and_read_back_to_the_same_results() {
    let tmp = tempfile::tempdir().unwrap();
    let (s, out) = (scene(), tmp.path().join("o"));
    let out_s = out.display().to_string();
    ok(tmp.path(), &["sweep", &s, "--out", &out_s]);
    let mut sizes = Vec::new();
    for e in std::fs::read_dir(out.join("cases")).unwrap() {
        let e = e.unwrap();
        if e.file_name().to_string_lossy().ends_with(".toml") {
            sizes.push(e.metadata().unwrap().len());
        }
    }
    assert_eq!(sizes.len(), 56);
    let total: u64 = sizes.iter().sum();
    assert!(total / 56 <= 130_000, "{} bytes a case", total / 56);
    assert!(sizes.iter().all(|&n| n <= 576_000), "{sizes:?}");
    assert!(
        sizes.iter().filter(|&&n| n <= 38_000).count() >= 26,
        "the cases without an orbit: {sizes:?}"
    );
    let table = without_timing(&read(&out.join("sweep.csv")));
    let pictures = [
        "orbits_1.png",
        "orbits_4.png",
        "contact_force.png",
        "bifurcation.png",
        "cascade.png",
    ];
    let before: Vec<Vec<u8>> = pictures
        .iter()
        .map(|p| std::fs::read(out.join(p)).unwrap())
        .collect();
    // Two cases deleted (one with an orbit and force history): the rerun computes those and
    // reads the 54 others back.
    for id in ["speed_ratio=1.7", "speed_ratio=2"] {
        std::fs::remove_file(out.join(format!("cases/{id}.toml"))).unwrap();
    }
    let o = command(tmp.path())
        .args(["sweep", &s, "--out", &out_s])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(text(&o.stderr).contains("54 of 56 cases already finished"));
    assert_eq!(without_timing(&read(&out.join("sweep.csv"))), table);
    for (p, b) in pictures.iter().zip(&before) {
        assert!(std::fs::read(out.join(p)).unwrap() == *b, "{p} changed");
    }
}

#[test]
fn shards_merge_into_the_one_machine_results_and_missing_ones_are_listed() {
    let tmp = tempfile::tempdir().unwrap();
    let s = scene();
    let one = tmp.path().join("one");
    ok(tmp.path(), &sweep_args(&s, &one.display().to_string(), &[]));
    let dist = tmp.path().join("dist");
    let d = dist.display().to_string();
    for i in [1, 3] {
        let shard = format!("{i}/3");
        let out = ok(tmp.path(), &sweep_args(&s, &d, &["--shard", &shard]));
        assert!(out.contains("rubsim merge"), "{out}");
    }
    // Shard 2 is missing: the merge names its cases and the shard to run again.
    let err = fails(tmp.path(), &["merge", &d]);
    assert!(err.contains("5 of 16 cases are missing"), "{err}");
    assert!(err.contains("speed_ratio=0.6"), "{err}");
    assert!(err.contains("shards 2 of 3"), "{err}");
    // Shard 2 from a Slurm array task (IDs 0–2): task 1 is shard 2.
    let o = command(tmp.path())
        .args(sweep_args(&s, &d, &[]))
        .env("SLURM_ARRAY_TASK_ID", "1")
        .env("SLURM_ARRAY_TASK_MIN", "0")
        .env("SLURM_ARRAY_TASK_MAX", "2")
        .env("SLURM_ARRAY_TASK_COUNT", "3")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(dist
        .join("shard-2-of-3/cases/speed_ratio=0.6.toml")
        .is_file());
    ok(tmp.path(), &["merge", &d]);
    // Value for value — and case for case, the cases' own timings included.
    let one_csv = read(&one.join("sweep.csv"));
    assert_eq!(
        without_timing(&read(&dist.join("sweep.csv"))),
        without_timing(&one_csv)
    );
    // The full-spectrum cascade's table, drawn from the case files alone: the same lines.
    assert_eq!(
        read(&dist.join("full_cascade.csv")),
        read(&one.join("full_cascade.csv"))
    );
    let cascade = read(&one.join("full_cascade.csv"));
    assert!(cascade.starts_with("speed_ratio,rank,order,freq_nd,amp_nd\n"));
    // The rod pushes up and down only: the 1× orbit is an ellipse, forward with a backward part
    // (near 1.3 ω_n nearly a straight line: planar).
    let header: Vec<&str> = one_csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let row: Vec<&str> = one_csv
        .lines()
        .find(|l| l.starts_with("2.0000,"))
        .unwrap()
        .split(',')
        .collect();
    assert_eq!(row[col("period")], "1", "{row:?}");
    assert_eq!(row[col("whirl")], "forward", "{row:?}");
    assert_eq!(row[col("whirl_order")], "1.000000", "{row:?}");
    let (f, b): (f64, f64) = (
        row[col("fwd_1x_nd")].parse().unwrap(),
        row[col("bwd_1x_nd")].parse().unwrap(),
    );
    assert!(f > 2.0 * b && b > 0.05, "1× forward {f}, backward {b}");
    for f in [
        "cascade.png",
        "bifurcation.png",
        "regime_map.png",
        "orbits_1.png",
        "full_cascade.png",
    ] {
        assert_eq!(
            std::fs::read(dist.join(f)).unwrap(),
            std::fs::read(one.join(f)).unwrap(),
            "{f}"
        );
    }
}

#[test]
fn bad_shards_and_merges_of_different_scenes_fail_clearly() {
    let tmp = tempfile::tempdir().unwrap();
    let s = scene();
    let d = tmp.path().join("d").display().to_string();
    for (shard, says) in [
        ("4/3", "out of range"),
        ("0/3", "out of range"),
        ("1/0", "at least 1"),
        ("x/3", "not a whole number"),
        ("2", "expected i/n"),
        ("1/17", "fewer than 17 shards"),
    ] {
        let err = fails(tmp.path(), &sweep_args(&s, &d, &["--shard", shard]));
        assert!(err.contains(says), "--shard {shard}: {err}");
    }
    let o = command(tmp.path())
        .args(sweep_args(&s, &d, &[]))
        .env("SLURM_ARRAY_TASK_ID", "5")
        .env("SLURM_ARRAY_TASK_MIN", "3")
        .env("SLURM_ARRAY_TASK_MAX", "5")
        .env("SLURM_ARRAY_TASK_COUNT", "2")
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("not contiguous"),
        "{}",
        text(&o.stderr)
    );
    ok(tmp.path(), &sweep_args(&s, &d, &["--shard", "1/2"]));
    let mut other = sweep_args(&s, &d, &["--shard", "2/2"]);
    other.extend(["--set", "station.0.friction=0.3"]);
    ok(tmp.path(), &other);
    let err = fails(tmp.path(), &["merge", &d]);
    assert!(err.contains("different scenes"), "{err}");
    let err = fails(
        tmp.path(),
        &["merge", &tmp.path().join("nothing").display().to_string()],
    );
    assert!(err.contains("no such directory"), "{err}");
}

/// A 4 × 3 map of the paper case over speed and clearance, short runs.
const MAP_SETS: &[&str] = &[
    "--set",
    "run.map.x={ key = \"speed_ratio\", values = [0.8, 1.7, 3.1, 4.9] }",
    "--set",
    "run.map.y={ key = \"stator.0.clearance_nd\", from = 0.4, to = 0.8, step = 0.2 }",
    "--set",
    "run.revolutions=120",
    "--set",
    "run.transient_revolutions=60",
];

fn map_args<'a>(out: &'a str, extra: &[&'a str]) -> Vec<String> {
    let mut a = vec![
        "map".to_string(),
        repo("scenes/paper/regime_map.toml").display().to_string(),
    ];
    a.extend(MAP_SETS.iter().map(|s| s.to_string()));
    a.extend(["--out", out, "--jobs", "1"].map(String::from));
    a.extend(extra.iter().map(|s| s.to_string()));
    a
}

#[test]
fn a_map_writes_its_table_and_pictures_and_its_shards_merge_identically() {
    let tmp = tempfile::tempdir().unwrap();
    let one = tmp.path().join("one");
    let args = map_args(one.to_str().unwrap(), &[]);
    let out = ok(
        tmp.path(),
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    assert!(out.contains("map 4 × 3: 12 cases"), "{out}");
    let csv = read(&one.join("map.csv"));
    let mut lines = csv.lines();
    assert!(lines
        .next()
        .unwrap()
        .starts_with("speed_ratio,stator.0.clearance_nd,period,regime,"));
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    assert_eq!(rows.len(), 12);
    // The row at δ_nd = 0.6 is the paper's sweep at those speeds: the paper's regimes
    // (1× at 1.7, 1/2× at 3.1, 1/3× at 4.9).
    for (v, period) in [("1.7", "1"), ("3.1", "2"), ("4.9", "3")] {
        let r = rows.iter().find(|r| r[0] == v && r[1] == "0.6").unwrap();
        assert_eq!(r[2], period, "{r:?}");
    }
    for f in [
        "regime_map.png",
        "orbit_size_map.png",
        "contact_force_map.png",
        "full_cascade/clearance_nd_0.4.png",
        "full_cascade/clearance_nd_0.8.png",
    ] {
        assert!(common::cli::is_png(&one.join(f)), "{f}");
    }
    let cascade = read(&one.join("full_cascade.csv"));
    assert!(cascade.starts_with("speed_ratio,stator.0.clearance_nd,rank,order,"));
    // Every case keeps its lines, the strongest first.
    assert_eq!(
        cascade.lines().filter(|l| l.contains(",1,")).count(),
        12,
        "{cascade}"
    );
    // Two shards and a merge: the same table and pictures.
    let dist = tmp.path().join("dist");
    for s in ["1/2", "2/2"] {
        let a = map_args(dist.to_str().unwrap(), &["--shard", s]);
        ok(
            tmp.path(),
            &a.iter().map(String::as_str).collect::<Vec<_>>(),
        );
    }
    ok(tmp.path(), &["merge", dist.to_str().unwrap()]);
    assert_eq!(
        without_timing(&read(&dist.join("map.csv"))),
        without_timing(&csv)
    );
    assert_eq!(read(&dist.join("full_cascade.csv")), cascade);
    for f in [
        "regime_map.png",
        "orbit_size_map.png",
        "contact_force_map.png",
        "full_cascade/clearance_nd_0.6.png",
    ] {
        assert_eq!(
            std::fs::read(dist.join(f)).unwrap(),
            std::fs::read(one.join(f)).unwrap(),
            "{f}"
        );
    }
}

#[test]
fn map_keys_and_values_are_checked_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = repo("scenes/paper/regime_map.toml").display().to_string();
    for (set, says) in [
        (
            "run.map.y={ key = \"stator.0.clearance_typo\", values = [0.5] }",
            "run.map.y.key",
        ),
        (
            "run.map.y={ key = \"stator.0.clearance_nd\", values = [0.5, -1.0] }",
            "run.map.y.values",
        ),
        (
            "run.map.y={ key = \"stator.0.clearance_nd\", values = [0.5], step = 0.1 }",
            "run.map.y.values",
        ),
        (
            "run.map.y={ key = \"speed_ratio\", values = [0.5] }",
            "run.map.y.key",
        ),
        (
            "run.map.x={ key = \"speed_ratio\", from = 2.0, to = 1.0, step = 0.1 }",
            "run.map.x.to",
        ),
    ] {
        let err = fails(tmp.path(), &["check", &scene, "--set", set]);
        assert!(err.contains(says), "{set}: {err}");
    }
}

/// Every file below `dir` (relative paths), sorted: [`common::cli::tree`] without the folders.
fn files(dir: &Path) -> Vec<String> {
    tree(dir)
        .into_iter()
        .filter(|p| dir.join(p).is_file())
        .map(|p| p.display().to_string())
        .collect()
}

/// Issue 12, item 4: cases whose per-speed VTK series are asked for used to run again on every
/// rerun. Their series are kept with the case, so a sweep killed halfway loses none and computes
/// none twice; only changed time-series settings run those cases again.
#[cfg(feature = "fault-injection")]
#[test]
fn per_speed_series_are_kept_with_their_cases_and_not_recomputed_on_resume() {
    let tmp = tempfile::tempdir().unwrap();
    let (s, log) = (scene(), tmp.path().join("log"));
    let series = [
        "--set",
        "output.vtk={ from_revolution = 119.5 }",
        "--set",
        "output.per_speed=[0.6, 1.5]",
    ];
    let out = tmp.path().join("killed");
    let out_s = out.display().to_string();
    let killed = command(tmp.path())
        .args(sweep_args(&s, &out_s, &series))
        .env("RUBSIM_CASE_LOG", &log)
        .env("RUBSIM_KILL_AFTER_CASES", "12")
        .output()
        .unwrap();
    use std::os::unix::process::ExitStatusExt;
    assert_eq!(killed.status.signal(), Some(9), "{}", text(&killed.stderr));
    // Both series cases (the 2nd and the 11th) finished before the kill.
    let c = counts(&log);
    assert!(
        c.contains_key("speed_ratio=0.6") && c.contains_key("speed_ratio=1.5"),
        "{c:?}"
    );
    let o = command(tmp.path())
        .args(sweep_args(&s, &out_s, &series))
        .env("RUBSIM_CASE_LOG", &log)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o.stderr));
    assert!(
        text(&o.stderr).contains("12 of 16 cases already finished"),
        "{}",
        text(&o.stderr)
    );
    let c = counts(&log);
    assert_eq!(c.len(), 16, "{c:?}");
    assert!(c.values().all(|n| *n == 1), "a case computed twice: {c:?}");
    // The same series as an uninterrupted run, byte for byte.
    let whole = tmp.path().join("whole");
    ok(
        tmp.path(),
        &sweep_args(&s, &whole.display().to_string(), &series),
    );
    for sp in ["speed_0.6", "speed_1.5"] {
        let (a, b) = (files(&out.join(sp)), files(&whole.join(sp)));
        assert!(a.iter().any(|f| f.ends_with(".vtu")), "{a:?}");
        assert_eq!(a, b);
        for f in a
            .iter()
            .filter(|f| f.ends_with(".vtu") || f.ends_with(".pvd"))
        {
            assert_eq!(
                std::fs::read(out.join(sp).join(f)).unwrap(),
                std::fs::read(whole.join(sp).join(f)).unwrap(),
                "{sp}/{f}"
            );
        }
    }
    // Other series settings run exactly the two series cases again.
    let other = [
        "--set",
        "output.vtk={ from_revolution = 119.0 }",
        "--set",
        "output.per_speed=[0.6, 1.5]",
    ];
    let o = command(tmp.path())
        .args(sweep_args(&s, &out_s, &other))
        .env("RUBSIM_CASE_LOG", &log)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o.stderr));
    let c = counts(&log);
    let twice: Vec<&String> = c.iter().filter(|(_, n)| **n == 2).map(|(k, _)| k).collect();
    assert_eq!(twice, ["speed_ratio=0.6", "speed_ratio=1.5"], "{c:?}");
    assert!(files(&out.join("speed_1.5")).len() > files(&whole.join("speed_1.5")).len());
    // Without series, none is left in the results or in the store.
    ok(tmp.path(), &sweep_args(&s, &out_s, &[]));
    assert!(!out.join("speed_0.6").exists() && !out.join("cases/series").exists());
}

/// Shards keep the per-speed series of their own cases; `rubsim merge` gathers them into the
/// merged directory as a one-machine run writes them (byte for byte), and names a case whose
/// series no shard keeps.
#[test]
fn merge_gathers_the_per_speed_series_of_the_shards() {
    let tmp = tempfile::tempdir().unwrap();
    let s = scene();
    let series = [
        "--set",
        "output.vtk={ from_revolution = 119.5 }",
        "--set",
        "output.per_speed=[0.6, 1.5]",
    ];
    let one = tmp.path().join("one");
    ok(
        tmp.path(),
        &sweep_args(&s, &one.display().to_string(), &series),
    );
    let dist = tmp.path().join("dist");
    let d = dist.display().to_string();
    for i in 1..=3 {
        let shard = format!("{i}/3");
        let mut extra = series.to_vec();
        extra.extend_from_slice(&["--shard", &shard]);
        ok(tmp.path(), &sweep_args(&s, &d, &extra));
    }
    ok(tmp.path(), &["merge", &d]);
    for sp in ["speed_0.6", "speed_1.5"] {
        let (a, b) = (files(&dist.join(sp)), files(&one.join(sp)));
        assert!(a.iter().any(|f| f.ends_with(".vtu")), "{sp}: {a:?}");
        assert_eq!(a, b, "{sp}");
        for f in &a {
            assert_eq!(
                std::fs::read(dist.join(sp).join(f)).unwrap(),
                std::fs::read(one.join(sp).join(f)).unwrap(),
                "{sp}/{f}"
            );
        }
    }
    // A shard's kept series removed: the merge names the case instead of leaving it out.
    let gone = tree(&dist)
        .into_iter()
        .map(|p| dist.join(p))
        .find(|p| {
            p.is_dir()
                && p.parent().is_some_and(|q| q.ends_with("cases/series"))
                && !p.file_name().unwrap().to_string_lossy().starts_with('.')
        })
        .expect("a kept series folder in a shard");
    std::fs::remove_dir_all(&gone).unwrap();
    let err = fails(tmp.path(), &["merge", &d]);
    assert!(err.contains("asks for its time series"), "{err}");
    assert!(err.contains("run its shard again"), "{err}");
    // Nothing of the earlier merge is lost by the refused one.
    assert!(dist.join("sweep.csv").is_file() && dist.join("speed_1.5").is_dir());
}
