//! The fuzz targets' functions (fuzz/src/lib.rs, included here as they are) over the committed
//! inputs: the seeds (fuzz/seeds/<target>/) and the inputs of crashes the fuzzers found, kept
//! after the fix (fuzz/regressions/<target>/). `cargo test` thus replays, without cargo-fuzz,
//! what the fuzzers start from and what once failed; an input fails the test by panicking.

mod common;

#[path = "../fuzz/src/lib.rs"]
mod targets;

use common::cli::in_repo;

use std::path::Path;

/// Runs `f` on every file of `fuzz/seeds/<target>/` and `fuzz/regressions/<target>/`; the
/// number of inputs.
fn replay(target: &str, f: fn(&[u8])) -> usize {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz");
    let mut n = 0;
    for dir in ["seeds", "regressions"] {
        let Ok(rd) = std::fs::read_dir(root.join(dir).join(target)) else {
            continue;
        };
        let mut files: Vec<_> = rd.flatten().map(|e| e.path()).collect();
        files.sort();
        for p in files {
            let bytes = std::fs::read(&p).unwrap();
            eprintln!("{}", p.display());
            f(&bytes);
            n += 1;
        }
    }
    n
}

#[test]
fn scene_seeds_and_regressions_load_without_panic() {
    assert!(replay("scene", targets::scene) >= 20);
}

#[test]
fn msh_seeds_and_regressions_read_without_panic() {
    assert!(replay("msh", targets::msh) >= 7);
}

#[test]
fn manifest_seeds_and_regressions_read_without_panic() {
    assert!(replay("manifest", targets::manifest) >= 4);
}

#[test]
fn the_scene_target_reaches_resolution() {
    // The seeds are valid scenes: the target gets past loading for them (a target that
    // rejected everything would fuzz nothing).
    let text = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/seeds/scene/partial_rub-set.toml"),
    )
    .unwrap();
    let s = std::str::from_utf8(&text).unwrap();
    let mut parts = s.split(targets::SEPARATOR);
    let source = parts.next().unwrap();
    let sets: Vec<String> = parts.map(str::to_string).collect();
    assert_eq!(sets.len(), 3);
    let ls = rubsim::scene::parse(Path::new("fuzz.toml"), source, &sets).unwrap();
    rubsim::resolve::resolve(&ls).unwrap();
}

// ---------------------------------------------------------------------------------------------
// Crashes found by fuzzing (and the seeds), each fixed in the library; the input is also in
// fuzz/regressions/.

#[test]
fn a_bearing_table_without_speeds_is_refused_naming_the_key() {
    // Was: index out of bounds in resolve::rotor::bearing (issue 13, item 5).
    let (ok, _, err) = in_repo(&[
        "check",
        "scenes/fe/paper_rotor_rub.toml",
        "--set",
        "rotor.bearing.0.stiffness=[]",
    ]);
    assert!(!ok && !err.contains("panicked"), "{err}");
    assert!(
        err.contains("key `rotor.bearing.0.stiffness`") && err.contains("needs `speeds`"),
        "{err}"
    );
}
