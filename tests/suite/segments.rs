//! Issue 29, item 3: a continuation split into segments (`rubsim continue --segments n`,
//! `study::segments`) — the segments join into the branch the unsplit continuation finds, with
//! its bifurcations located at the same values; a run killed by SIGKILL resumes without
//! recomputing a finished segment; shards merge into exactly the one-machine files; segments
//! that do not meet on one orbit are a seam, drawn and reported as separate branches; bad
//! input fails before anything is written.

use crate::common;

use common::cli::{command, csv_table, fails, ok, text, without_timing};
use common::{read, repo};
use std::path::Path;

/// The paper's case with shorter settling runs (each segment's first orbit is shot from one).
const SETS: &[&str] = &[
    "--set",
    "run.revolutions=120",
    "--set",
    "run.transient_revolutions=60",
];

/// `rubsim continue <paper> --from 1.6 --to 2.6 --step 0.1 --period 1` (11 speeds, the
/// period doubling near 2.24 inside) into `out`, with `extra` arguments.
fn args<'a>(scene: &'a str, out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut a = vec!["continue", scene];
    a.extend_from_slice(SETS);
    a.extend_from_slice(&[
        "--from", "1.6", "--to", "2.6", "--step", "0.1", "--period", "1", "--out", out,
    ]);
    a.extend_from_slice(extra);
    a
}

fn paper() -> String {
    repo("scenes/paper/partial_rub.toml").display().to_string()
}

/// The column `name` of a CSV table as numbers.
fn column(p: &Path, name: &str) -> Vec<f64> {
    let (h, rows) = csv_table(p);
    let i = h.iter().position(|c| c == name).unwrap();
    rows.iter().map(|r| r[i].parse().unwrap()).collect()
}

/// Three segments give the unsplit branch: the same speeds, stability and period doubling
/// (located by the same bisection, each interval of the grid belonging to one segment), the
/// orbits within Newton's tolerance of each other (measured: extents within 1e-10, |ρ₁|
/// within 1e-7; the segments' first orbits are shot from their own settled runs).
#[test]
fn segments_join_into_the_branch_the_unsplit_continuation_finds() {
    let tmp = tempfile::tempdir().unwrap();
    let s = paper();
    let (one, seg) = (tmp.path().join("one"), tmp.path().join("seg"));
    ok(tmp.path(), &args(&s, one.to_str().unwrap(), &[]));
    let out = ok(
        tmp.path(),
        &args(&s, seg.to_str().unwrap(), &["--segments", "3"]),
    );
    assert!(out.contains("continued in 3 segments"), "{out}");
    assert_eq!(
        column(&one.join("branch.csv"), "speed_ratio"),
        column(&seg.join("branch.csv"), "speed_ratio")
    );
    let (h1, r1) = csv_table(&one.join("branch.csv"));
    let (_, r2) = csv_table(&seg.join("branch.csv"));
    let st = h1.iter().position(|c| c == "stable").unwrap();
    assert!(r1.iter().zip(&r2).all(|(a, b)| a[st] == b[st]));
    let mut worst = [0.0_f64; 2];
    for (name, k) in [("x_max_nd", 0), ("y_min_nd", 0), ("largest_modulus", 1)] {
        let (a, b) = (
            column(&one.join("branch.csv"), name),
            column(&seg.join("branch.csv"), name),
        );
        for (x, y) in a.iter().zip(&b) {
            worst[k] = worst[k].max((x - y).abs());
        }
    }
    eprintln!(
        "segments against one branch: extents {:.1e}, |ρ₁| {:.1e}",
        worst[0], worst[1]
    );
    assert!(worst[0] < 1e-7 && worst[1] < 1e-5, "{worst:?}");
    let (b1, b2) = (
        csv_table(&one.join("bifurcations.csv")).1,
        csv_table(&seg.join("bifurcations.csv")).1,
    );
    assert_eq!(b1.len(), b2.len());
    assert!(b1.iter().any(|r| r[0] == "period_doubling"), "{b1:?}");
    for (a, b) in b1.iter().zip(&b2) {
        assert_eq!(a[0], b[0]);
        let (x, y): (f64, f64) = (a[1].parse().unwrap(), b[1].parse().unwrap());
        assert!((x - y).abs() < 1e-9, "{} at {x} against {y}", a[0]);
    }
    let (h, rows) = csv_table(&seg.join("segments.csv"));
    assert_eq!(h[..4], ["segment", "from", "to", "points"]);
    let joins: Vec<&str> = rows.iter().map(|r| r[6].as_str()).collect();
    assert_eq!(joins, ["true", "true", ""]);
    let summary = common::cli::json(&seg.join("summary.json"));
    assert_eq!(summary["segments"].as_array().unwrap().len(), 3);
    assert!(summary["seams"].as_array().unwrap().is_empty());
    assert!(!seg.join("branches.csv").exists());
}

/// A segmented continuation killed by SIGKILL after its first segment resumes: the rerun
/// computes only the two missing segments, a third run none, and the files equal an
/// uninterrupted segmented run's byte for byte (each segment is computed alike, whenever).
#[cfg(feature = "fault-injection")]
#[test]
fn a_killed_segmented_continuation_resumes_without_recomputing_a_segment() {
    let tmp = tempfile::tempdir().unwrap();
    let (s, log) = (paper(), tmp.path().join("log"));
    let out = tmp.path().join("killed");
    let o = out.to_str().unwrap();
    let seg = ["--segments", "3", "--jobs", "1"];
    let killed = command(tmp.path())
        .args(args(&s, o, &seg))
        .env("RUBSIM_CASE_LOG", &log)
        .env("RUBSIM_KILL_AFTER_CASES", "1")
        .output()
        .unwrap();
    use std::os::unix::process::ExitStatusExt;
    assert_eq!(killed.status.signal(), Some(9), "{}", text(&killed.stderr));
    assert!(!out.join("summary.json").exists());
    assert_eq!(read(&log).lines().count(), 1);
    let again = command(tmp.path())
        .args(args(&s, o, &seg))
        .env("RUBSIM_CASE_LOG", &log)
        .output()
        .unwrap();
    assert!(again.status.success(), "{}", text(&again.stderr));
    let err = text(&again.stderr);
    assert!(err.contains("1 of 3 segments already finished"), "{err}");
    let mut ids: Vec<String> = read(&log).lines().map(str::to_string).collect();
    ids.sort();
    assert_eq!(
        ids,
        ["segment=1-of-3", "segment=2-of-3", "segment=3-of-3"],
        "a segment computed twice or lost"
    );
    ok(tmp.path(), &args(&s, o, &seg));
    assert_eq!(read(&log).lines().count(), 3);
    let whole = tmp.path().join("whole");
    ok(tmp.path(), &args(&s, whole.to_str().unwrap(), &seg));
    for f in ["branch.csv", "bifurcations.csv"] {
        assert_eq!(read(&out.join(f)), read(&whole.join(f)), "{f}");
    }
    assert_eq!(
        without_timing(&read(&out.join("segments.csv"))),
        without_timing(&read(&whole.join("segments.csv")))
    );
}

/// Two shards (`--shard 1/2`, `--shard 2/2`: segments 1 and 3, and 2) merged by `rubsim merge`
/// write the one-machine run's files; a merge with a shard missing lists the missing segment
/// and the shard to run again.
#[test]
fn shards_of_a_segmented_continuation_merge_into_the_one_machine_files() {
    let tmp = tempfile::tempdir().unwrap();
    let s = paper();
    let (one, dist) = (tmp.path().join("one"), tmp.path().join("dist"));
    let d = dist.to_str().unwrap();
    ok(
        tmp.path(),
        &args(&s, one.to_str().unwrap(), &["--segments", "3"]),
    );
    let first = ok(
        tmp.path(),
        &args(&s, d, &["--segments", "3", "--shard", "1/2"]),
    );
    assert!(first.contains("rubsim merge"), "{first}");
    assert!(dist
        .join("shard-1-of-2/cases/segment=3-of-3.toml")
        .is_file());
    let e = fails(tmp.path(), &["merge", d]);
    assert!(
        e.contains("1 of 3 segments are missing: 2") && e.contains("shards 2 of 2"),
        "{e}"
    );
    ok(
        tmp.path(),
        &args(&s, d, &["--segments", "3", "--shard", "2/2"]),
    );
    ok(tmp.path(), &["merge", d]);
    for f in ["branch.csv", "bifurcations.csv"] {
        assert_eq!(read(&one.join(f)), read(&dist.join(f)), "{f}");
    }
    assert_eq!(
        without_timing(&read(&one.join("segments.csv"))),
        without_timing(&read(&dist.join("segments.csv")))
    );
    assert!(common::cli::is_png(&dist.join("branch.png")));
}

/// What a segmented continuation refuses, before its output folder is written: no segment,
/// more segments than steps, a shard beyond the segments, `--shard` without `--segments`,
/// arclength; a rerun of another range into the same folder (and `--fresh` discards it).
#[test]
fn bad_segment_requests_are_refused_naming_what_is_wrong() {
    let tmp = tempfile::tempdir().unwrap();
    let s = paper();
    let out = tmp.path().join("o");
    let o = out.to_str().unwrap();
    let e = fails(tmp.path(), &args(&s, o, &["--segments", "0"]));
    assert!(e.contains("--segments") && e.contains("1 to 10"), "{e}");
    let e = fails(tmp.path(), &args(&s, o, &["--segments", "11"]));
    assert!(e.contains("11 segment(s)"), "{e}");
    assert!(!out.exists(), "a refused request wrote {}", out.display());
    let e = fails(tmp.path(), &args(&s, o, &["--shard", "1/2"]));
    assert!(e.contains("--segments"), "{e}");
    let e = fails(
        tmp.path(),
        &args(&s, o, &["--segments", "2", "--arclength"]),
    );
    assert!(e.contains("cannot be used with"), "{e}");
    let e = fails(
        tmp.path(),
        &args(&s, o, &["--segments", "2", "--shard", "3/2"]),
    );
    assert!(e.contains("out of range"), "{e}");
    // Another range into a folder of segments is refused, and --fresh discards them.
    let short = ["--segments", "2", "--shard", "2/2"];
    ok(tmp.path(), &args(&s, o, &short));
    let mut other = args(&s, o, &short);
    let at = other.iter().position(|a| *a == "2.6").unwrap();
    other[at] = "2.5";
    let e = fails(tmp.path(), &other);
    assert!(e.contains("cases") && e.contains("in 2 segments"), "{e}");
    other.push("--fresh");
    let done = ok(tmp.path(), &other);
    assert!(done.contains("shard 2/2"), "{done}");
}

/// Segments that find different orbits at their shared value are a seam, not one branch: the
/// paper case's period-2 continuation over ν 2.0 – 2.6 in two segments — the first starts
/// below the period doubling at 2.2445, where its settled run is the period-1 orbit (a fixed
/// point of the two-revolution map, which it continues past the doubling), the second above it,
/// where the settled run is the period-2 orbit. At ν 2.3 the two are different orbits
/// (measured: Poincaré points 0.345 of the orbit's size apart): the console and segments.csv
/// name the seam, and both parts are written as branches (branches.csv), not bridged.
#[test]
fn segments_on_different_orbits_are_a_seam_drawn_as_two_branches() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("p2");
    let s = paper();
    let mut a = vec!["continue", s.as_str()];
    a.extend_from_slice(SETS);
    a.extend_from_slice(&[
        "--from",
        "2.0",
        "--to",
        "2.6",
        "--step",
        "0.1",
        "--period",
        "2",
        "--segments",
        "2",
        "--out",
    ]);
    a.push(out.to_str().unwrap());
    let o = command(tmp.path()).args(&a).output().unwrap();
    assert!(o.status.success(), "{}", text(&o.stderr));
    let err = text(&o.stderr);
    assert!(
        err.contains("segments 1 and 2 do not join at 2.3")
            && err.contains("different period-2 orbits"),
        "{err}"
    );
    let (_, rows) = csv_table(&out.join("segments.csv"));
    assert_eq!(rows[0][6], "false");
    let (h, parts) = csv_table(&out.join("branches.csv"));
    assert_eq!(h[..3], ["branch", "period", "speed_ratio"]);
    let first: Vec<&str> = parts
        .iter()
        .filter(|r| r[0] == "0")
        .map(|r| r[2].as_str())
        .collect();
    let second: Vec<&str> = parts
        .iter()
        .filter(|r| r[0] == "1")
        .map(|r| r[2].as_str())
        .collect();
    assert_eq!(first, ["2", "2.1", "2.2", "2.3"]);
    assert_eq!(second, ["2.3", "2.4", "2.5", "2.6"]);
    let summary = common::cli::json(&out.join("summary.json"));
    assert_eq!(summary["seams"][0]["after_segment"], 1);
    assert_eq!(summary["parts"]["branches"].as_array().unwrap().len(), 2);
}
