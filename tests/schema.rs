//! The JSON Schema of the scene format (`rubsim schema`, issue 25 item 7): the committed
//! `schema/scene.schema.json` and `docs/SCENE.md` are what the binary generates now (so they
//! cannot go stale), every scene under `scenes/` validates against the schema, and a misspelt
//! key, a wrong type, an unknown `kind` or two alternative keys together are rejected by it.

mod common;

use common::cli::{in_repo, ok};
use common::{read, repo};
use serde_json::Value;
use std::path::{Path, PathBuf};
use tempfile::TempDir;

/// The committed schema, parsed.
fn committed_schema() -> Value {
    serde_json::from_str(&read(&repo("schema/scene.schema.json"))).expect("schema is JSON")
}

/// A validator of the committed schema (draft 7; no remote references to resolve).
fn validator() -> jsonschema::Validator {
    jsonschema::validator_for(&committed_schema()).expect("the schema compiles")
}

/// A TOML scene as the JSON value the schema judges.
fn as_json(text: &str, what: &str) -> Value {
    let t: toml::Value = toml::from_str(text).unwrap_or_else(|e| panic!("{what}: {e}"));
    serde_json::to_value(t).unwrap_or_else(|e| panic!("{what}: {e}"))
}

/// The schema's complaints about a TOML scene: one line per error, with its JSON pointer.
fn errors(v: &jsonschema::Validator, text: &str) -> Vec<String> {
    v.iter_errors(&as_json(text, "scene"))
        .map(|e| format!("{} at {}", e, e.instance_path()))
        .collect()
}

fn toml_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            toml_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "toml") {
            out.push(p);
        }
    }
}

#[test]
fn committed_schema_and_reference_are_what_the_binary_generates() {
    let (success, stdout, stderr) = in_repo(&["schema"]);
    assert!(success, "rubsim schema failed: {stderr}");
    assert!(
        stdout == read(&repo("schema/scene.schema.json")),
        "schema/scene.schema.json is stale: run `rubsim schema --out schema/scene.schema.json`"
    );
    let tmp = TempDir::new().unwrap();
    let md = tmp.path().join("SCENE.md");
    let json = tmp.path().join("scene.schema.json");
    let args = [
        "schema",
        "--markdown",
        md.to_str().unwrap(),
        "--out",
        json.to_str().unwrap(),
    ];
    assert_eq!(
        ok(tmp.path(), &args),
        "",
        "with files given nothing is printed"
    );
    assert_eq!(read(&json), stdout, "--out writes what is printed");
    assert!(
        read(&md) == read(&repo("docs/SCENE.md")),
        "docs/SCENE.md is stale: run `rubsim schema --markdown docs/SCENE.md`"
    );
}

#[test]
fn reference_documents_every_table_with_units_and_defaults() {
    let md = read(&repo("docs/SCENE.md"));
    for needle in [
        "rubsim schema --markdown docs/SCENE.md",
        "`[rotor]` kind = \"jeffcott\"",
        "`[rotor]` kind = \"fe\"",
        "`[[rotor.shaft]]`",
        "`[[station]]`",
        "`[[stator]]` kind = \"mesh\"",
        "`[run]`",
        "`[run.sweep]`",
        "`[run.speed_profile]`",
        "`[[run.event]]`",
        "`[output]`",
        "| `revolutions` | integer | `220` |",
        "exactly one of `clearance`, `clearance_nd`",
        "(m)",
        "`\"generalized_alpha\"`",
    ] {
        assert!(md.contains(needle), "docs/SCENE.md lacks {needle:?}");
    }
}

#[test]
fn every_scene_in_scenes_validates() {
    let v = validator();
    let mut files = Vec::new();
    toml_files(&repo("scenes"), &mut files);
    assert!(files.len() >= 20, "only {} scenes found", files.len());
    let bad: Vec<String> = files
        .iter()
        .filter_map(|f| {
            let e = errors(&v, &read(f));
            (!e.is_empty()).then(|| format!("{}: {}", f.display(), e.join("; ")))
        })
        .collect();
    assert!(
        bad.is_empty(),
        "scenes the schema rejects:\n{}",
        bad.join("\n")
    );
}

const SCENE: &str = r#"
title = "t"
[rotor]
kind = "jeffcott"
mass = 2.0
stiffness = 8.0e4
damping_ratio = 0.2
[[rotor.unbalance]]
mass = 0.01
radius = 0.05

[[station]]
name = "disk"
radius = 0.06
friction = 0.1

[[stator]]
kind = "rod"
name = "rod"
station = "disk"
clearance_nd = 0.6
length = 0.04
area = 25e-6
stiffness_ratio = 25

[run]
speed_ratio = 1.7
revolutions = 40
"#;

/// `SCENE` with `from` replaced by `to` (which must occur).
fn with(from: &str, to: &str) -> String {
    assert!(SCENE.contains(from), "`{from}` not in the scene");
    SCENE.replacen(from, to, 1)
}

#[test]
fn schema_rejects_misspelt_keys_wrong_types_and_alternatives_together() {
    let v = validator();
    assert_eq!(
        errors(&v, SCENE),
        Vec::<String>::new(),
        "the base scene is valid"
    );
    let cases = [
        (
            "misspelt run key",
            with("revolutions = 40", "revolution = 3"),
            "/run",
        ),
        (
            "wrong type",
            with("revolutions = 40", "revolutions = \"many\""),
            "/run/revolutions",
        ),
        (
            "misspelt key in a tagged table",
            with("length = 0.04", "lenght = 0.04"),
            "/stator/0",
        ),
        (
            "unknown stator kind",
            with("kind = \"rod\"", "kind = \"bar\""),
            "/stator/0",
        ),
        ("misspelt top-level table", with("[run]", "[runs]"), ""),
        (
            "both clearances",
            with("clearance_nd = 0.6", "clearance_nd = 0.6\nclearance = 1e-4"),
            "/stator/0",
        ),
        ("neither mass nor disk", with("mass = 2.0\n", ""), "/rotor"),
        (
            "a value outside the enum",
            with("[run]", "[output]\ncomponent = \"z\"\n[run]"),
            "/output/component",
        ),
    ];
    for (what, text, at) in cases {
        let e = errors(&v, &text);
        assert!(!e.is_empty(), "{what}: the schema accepts it");
        assert!(
            e.iter().any(|m| m.ends_with(&format!(" at {at}"))),
            "{what}: no error at {at:?}: {e:?}"
        );
        // The program refuses the same scene (the schema is not stricter than serde here).
        let ls = rubsim::scene::parse(Path::new("t.toml"), &text, &[]);
        assert!(ls.is_err(), "{what}: rubsim accepts it");
    }
}

#[test]
fn taplo_config_maps_the_scenes_to_the_schema() {
    let taplo: toml::Table =
        toml::from_str(&read(&repo(".taplo.toml"))).expect(".taplo.toml is TOML");
    let rules = taplo["rule"].as_array().expect("[[rule]]");
    let rule = rules
        .iter()
        .find(|r| {
            r["include"]
                .as_array()
                .is_some_and(|i| i.iter().any(|p| p.as_str() == Some("scenes/**/*.toml")))
        })
        .expect("a rule for scenes/**/*.toml");
    let path = rule["schema"]["path"].as_str().expect("schema.path");
    assert!(path.ends_with("schema/scene.schema.json"), "{path}");
    assert!(
        repo(path.trim_start_matches("./")).is_file(),
        "{path} is not a file"
    );
}
