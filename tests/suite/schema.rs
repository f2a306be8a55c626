//! The JSON Schema of the scene format (`rubsim schema`, issue 25 item 7): the committed
//! `schema/scene.schema.json` and `docs/SCENE.md` are what the binary generates now (so they
//! cannot go stale), and the reference and the taplo rule say what they should. That every scene
//! validates against the schema and that misspelt keys, wrong types and alternatives together
//! are rejected by it is judged by an independent validator: tests/post/test_schema.py
//! (Python's `jsonschema`).

use crate::common;

use common::cli::{in_repo, ok};
use common::{read, repo};
use tempfile::TempDir;

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
