//! The fuzz targets' functions (fuzz/src/lib.rs, included here as they are) over the committed
//! inputs: the seeds (fuzz/seeds/<target>/) and the inputs of crashes the fuzzers found, kept
//! after the fix (fuzz/regressions/<target>/). `cargo test` thus replays, without cargo-fuzz,
//! what the fuzzers start from and what once failed; an input fails the test by panicking.

use crate::common;

#[path = "../../fuzz/src/lib.rs"]
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
    assert!(replay("msh", targets::msh) >= 14);
}

#[test]
fn manifest_seeds_and_regressions_read_without_panic() {
    assert!(replay("manifest", targets::manifest) >= 4);
}

#[test]
fn ross_seeds_and_regressions_import_without_panic() {
    assert!(replay("ross", targets::ross) >= 3);
}

#[test]
fn the_ross_target_imports_its_seeds_in_both_forms() {
    // The seeds are ROSS files import-ross accepts, TOML and JSON: the target gets past the
    // import for each, so the fuzzer mutates from inputs that reach the model.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/seeds/ross");
    let mut forms = Vec::new();
    for name in [
        "rotor_example.toml",
        "rotor_example.json",
        "fluid_film.toml",
    ] {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        let scene = rubsim::scene::ross::import(Path::new(name), &text).unwrap();
        let ls = rubsim::scene::parse(Path::new(name), &scene, &[]).unwrap();
        rubsim::model::Model::from_scene(&ls).unwrap();
        forms.push(text.trim_start().starts_with('{'));
    }
    assert_eq!(forms, [false, true, false]);
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

#[test]
fn msh_section_counts_mshio_would_overflow_on_are_refused_naming_the_file() {
    // Was: `mshio` computes `numEntries − 1` of a `$Nodes`/`$Elements` header unchecked — a
    // panic (nodes_section.rs:39) with overflow checks, as in the fuzz build; without them a
    // wrapped value and a mesh read from a header declaring no nodes. The check before `mshio`
    // looked at the first "$Nodes\n" only, in little-endian: a section after CRLF, a second
    // section, or the same bytes inside an earlier unknown section passed it (the fuzz `msh`
    // run's crash after 761 285 executions, issue 13). Each file is in fuzz/regressions/msh/.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("fuzz/regressions/msh");
    for (file, says) in [
        (
            "nodes_zero_after_crlf.msh",
            "$Nodes (byte 728) declares 0 nodes",
        ),
        ("nodes_zero_behind_decoy.msh", "declares 0 nodes"),
        (
            "nodes_zero_second_section.msh",
            "$Nodes (line 46) declares 0 nodes",
        ),
        (
            "elements_zero_after_crlf.msh",
            "$Elements (line 46) declares 0 elements",
        ),
        ("dense_tags_past_u64.msh", "pass the largest tag"),
    ] {
        let path = dir.join(file);
        let e = match rubsim::mesh::Mesh::read(&path) {
            Ok(m) => format!("read, {} nodes", m.nodes.len()),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(file) && e.contains(says), "{file}: {e}");
    }
}
