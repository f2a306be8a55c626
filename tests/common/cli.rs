//! The command-line runner: the real `rubsim` binary in a chosen working directory, success
//! and clean-failure checks, and what a command left on disk.

use super::read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `rubsim` with `cwd` as working directory, to be given arguments (and environment).
pub fn command(cwd: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_rubsim"));
    c.current_dir(cwd);
    c
}

/// Runs `rubsim args…` with `cwd` as working directory (so a default `out/` lands there).
pub fn rubsim(cwd: &Path, args: &[&str]) -> Output {
    command(cwd)
        .args(args)
        .output()
        .expect("run the rubsim binary")
}

/// Runs `rubsim args…` in the repository (paths relative to it): (success, stdout, stderr).
pub fn in_repo(args: &[&str]) -> (bool, String, String) {
    let out = rubsim(&super::repo(""), args);
    (out.status.success(), text(&out.stdout), text(&out.stderr))
}

/// Bytes as text (invalid UTF-8 replaced).
pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Asserts success and returns stdout.
pub fn ok(cwd: &Path, args: &[&str]) -> String {
    let o = rubsim(cwd, args);
    assert!(
        o.status.success(),
        "rubsim {args:?} failed ({}):\n{}",
        o.status,
        text(&o.stderr)
    );
    text(&o.stdout)
}

/// `rubsim run` of the paper's case (`scenes/paper/partial_rub.toml`) at ω/ω_n = `speed` with
/// light damping ξ = 0.02 — where its rub is quasi-periodic or chaotic (`tests/dynamics.rs`) —,
/// no PNGs, and `sets` (`key=value`), into `dir/name`; asserts success and returns its
/// summary.json and stderr.
pub fn paper_light_damping(
    dir: &Path,
    name: &str,
    speed: &str,
    sets: &[&str],
) -> (serde_json::Value, String) {
    let scene = super::repo("scenes/paper/partial_rub.toml");
    let out = dir.join(name);
    let mut args = vec![
        "run",
        scene.to_str().unwrap(),
        "--speed",
        speed,
        "--set",
        "rotor.damping_ratio=0.02",
        "--set",
        "output.png=false",
        "--out",
        out.to_str().unwrap(),
    ];
    for s in sets {
        args.extend(["--set", s]);
    }
    let o = rubsim(dir, &args);
    let err = text(&o.stderr);
    assert!(
        o.status.success(),
        "rubsim {args:?} failed ({}):\n{err}",
        o.status
    );
    (json(&out.join("summary.json")), err)
}

/// Asserts a clean failure (non-zero exit, an `error:` message, no panic) and returns stderr.
pub fn fails(cwd: &Path, args: &[&str]) -> String {
    let o = rubsim(cwd, args);
    let err = text(&o.stderr);
    assert!(
        !o.status.success(),
        "rubsim {args:?} should fail, got success:\n{}",
        text(&o.stdout)
    );
    assert_ne!(
        o.status.code(),
        Some(101),
        "rubsim {args:?} panicked:\n{err}"
    );
    assert!(
        err.contains("error:"),
        "no error message for {args:?}:\n{err}"
    );
    assert!(
        !err.contains("panicked"),
        "rubsim {args:?} panicked:\n{err}"
    );
    assert!(
        !text(&o.stdout).contains("results in"),
        "rubsim {args:?} claims results:\n{}",
        text(&o.stdout)
    );
    err
}

/// Every file and directory below `dir` (relative paths).
pub fn tree(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(d) = todo.pop() {
        let Ok(rd) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in rd {
            let p = e.unwrap().path();
            if p.is_dir() {
                todo.push(p.clone());
            }
            out.push(p.strip_prefix(dir).unwrap().to_path_buf());
        }
    }
    out.sort();
    out
}

/// After a failed command: the output directory (if created at all) holds nothing that looks
/// complete and no staging folder.
pub fn assert_nothing_written(out: &Path) {
    for p in tree(out) {
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        assert!(
            name != "summary.json" && !name.starts_with(".rubsim-partial-"),
            "failed run left {} in {}: {:?}",
            p.display(),
            out.display(),
            tree(out)
        );
    }
}

pub fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&read(p)).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

pub fn is_png(p: &Path) -> bool {
    std::fs::read(p).is_ok_and(|b| b.len() > 8 && b.starts_with(b"\x89PNG\r\n\x1a\n"))
}

/// `rubsim run SCENE --out TMP/run` of a scene of the repository (`scenes/…`): the temporary
/// folder (kept alive by the caller), the output folder and the command's standard output.
pub fn run_scene(scene: &str) -> (tempfile::TempDir, PathBuf, String) {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("run");
    let file = super::repo(scene);
    let stdout = ok(
        tmp.path(),
        &[
            "run",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    (tmp, out, stdout)
}

/// A CSV file as its header and its rows of cells.
pub fn csv_table(p: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = super::read(p);
    let mut lines = text.lines();
    let split = |l: &str| l.split(',').map(str::to_string).collect::<Vec<_>>();
    let header = lines.next().map(split).unwrap_or_default();
    (header, lines.map(split).collect())
}

/// A CSV without its timing column `wall_s` (when it has one), for comparing runs.
pub fn without_timing(csv: &str) -> String {
    let header: Vec<&str> = csv.lines().next().unwrap_or("").split(',').collect();
    let Some(w) = header.iter().position(|h| *h == "wall_s") else {
        return csv.to_string();
    };
    csv.lines()
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            f.remove(w);
            f.join(",")
        })
        .collect::<Vec<_>>()
        .join("\n")
}
