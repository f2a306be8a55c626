//! The functions the fuzz targets run on each input, shared with the test that replays the
//! committed corpora (`tests/fuzz_corpus.rs` includes this file): each takes arbitrary bytes,
//! hands them to one reader of the library and ignores the result. An input fails when the
//! library panics, aborts (an allocation it cannot make), overflows its stack or hangs.
//!
//! * [`scene`]: scene text and `--set` overrides → [`rubsim::scene::parse`] (TOML,
//!   overrides, validation) → the resolve stage without meshing (rotor, stations, stators other
//!   than meshed ones; the whole [`rubsim::resolve::resolve`] when no stator is meshed).
//! * [`msh`]: bytes of a `.msh` → [`rubsim::mesh::Mesh::parse`] and, when it reads, what
//!   `rubsim mesh` does with a mesh: its summary, the conformity check and the contact
//!   boundary's normals.
//! * [`manifest`]: the text of an output directory's manifest →
//!   [`rubsim::output::parse_manifest`].
//! * [`ross`]: the text of a ROSS rotor file (`Rotor.save`, TOML or JSON) → what
//!   `rubsim import-ross` does with it: [`rubsim::scene::ross::import`], then, for a scene it
//!   returns, [`rubsim::scene::parse`] and [`rubsim::model::Model::from_scene`].

use std::path::Path;

/// Input layout of [`scene`]: the scene text, then up to 4 `--set` assignments, separated by
/// NUL bytes (`text\0key=value\0key=value`).
pub const SEPARATOR: char = '\0';

/// Scene text and `--set` overrides through loading, validation and resolution (no meshing).
pub fn scene(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let mut parts = text.split(SEPARATOR);
    let source = parts.next().unwrap_or_default();
    let sets: Vec<String> = parts.take(4).map(str::to_string).collect();
    let Ok(ls) = rubsim::scene::parse(Path::new("fuzz.toml"), source, &sets) else {
        return;
    };
    let meshed = |s: &rubsim::scene::StatorSpec| matches!(s, rubsim::scene::StatorSpec::Mesh(_));
    if !ls.scene.stators.iter().any(meshed) {
        let _ = rubsim::resolve::resolve(&ls);
        return;
    }
    let _ = rubsim::resolve::rotor::resolve(&ls);
    for (i, s) in ls.scene.stators.iter().enumerate() {
        if !meshed(s) {
            let _ = rubsim::resolve::stator::resolve(&ls, i, s);
        }
    }
}

/// Bytes of a `.msh` file through the reader, then the mesh report of `rubsim mesh`.
pub fn msh(data: &[u8]) {
    let Ok(m) = rubsim::mesh::Mesh::parse(Path::new("fuzz.msh"), data) else {
        return;
    };
    let _ = m.summary();
    let _ = m.check_conforming();
    let _ = m.boundary_summary("stator_contact");
    let _ = m.group_list();
}

/// The text of a manifest (`.rubsim-files`) through the function that reads it.
pub fn manifest(data: &[u8]) {
    let text = String::from_utf8_lossy(data);
    let _ = rubsim::output::parse_manifest(&text);
}

/// The text of a ROSS rotor file through `rubsim import-ross` (without writing the scene): the
/// import, then the scene's loading and its model. The reader takes a text starting with `{`
/// as JSON and any other as TOML, whatever the file's name; the input is handed over under the
/// name its form would have (`fuzz.json`, `fuzz.toml`), so both readers see every mutation of
/// the seeds of both forms (fuzz/seeds/ross/).
pub fn ross(data: &[u8]) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let name = if text.trim_start().starts_with('{') {
        "fuzz.json"
    } else {
        "fuzz.toml"
    };
    let path = Path::new(name);
    let Ok(scene) = rubsim::scene::ross::import(path, text) else {
        return;
    };
    let Ok(ls) = rubsim::scene::parse(path, &scene, &[]) else {
        return;
    };
    let _ = rubsim::model::Model::from_scene(&ls);
}
