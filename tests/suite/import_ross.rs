//! The reproducers of issue 31's `import-ross` items (1, 4, 5, 6 and the `--out` part of 9):
//! no panic on empty or null coefficient lists, nothing read differently from what the file
//! says, no unescaped text in the scene, errors at the user's file, line and ROSS key, and an
//! `--out` that overwrites only when asked, never the input, never through a link.

use crate::common;

use common::cli::{fails, ok};
use common::repo;
use std::fs;
use std::path::{Path, PathBuf};

const TOML: &str = "tests/data/ross/rotor_example.toml";
const JSON: &str = "tests/data/ross/rotor_example.json";

/// `rotor_example` saved by ROSS as TOML with `from` (the first occurrence) replaced by `to`.
fn toml_with(from: &str, to: &str) -> String {
    let text = common::read(&repo(TOML));
    assert!(text.contains(from), "{from}");
    text.replacen(from, to, 1)
}

/// `rotor_example` saved by ROSS as JSON with `value` set at `table` (the first table whose
/// name starts with it), `key`.
fn json_with(table: &str, key: &str, value: serde_json::Value) -> String {
    let mut doc: serde_json::Value = serde_json::from_str(&common::read(&repo(JSON))).unwrap();
    let obj = doc.as_object_mut().unwrap();
    let name = obj.keys().find(|k| k.starts_with(table)).unwrap().clone();
    obj[&name][key] = value;
    serde_json::to_string_pretty(&doc).unwrap()
}

/// `text` written as `name` in `dir`.
fn file(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    fs::write(&p, text).unwrap();
    p
}

/// `rubsim import-ross` of `text` (written as `name`) fails cleanly (no panic, no output);
/// its message names every one of `needles`.
fn refused(name: &str, text: &str, needles: &[&str]) -> String {
    let d = tempfile::tempdir().unwrap();
    let p = file(d.path(), name, text);
    let err = fails(d.path(), &["import-ross", p.to_str().unwrap()]);
    for n in needles {
        assert!(err.contains(n), "{name}: `{n}` not in:\n{err}");
    }
    err
}

/// Item 1: `kxx = []`, `"kxx": [null]`, `kzz = []` panicked (exit 101, ross.rs:324 and 337).
#[test]
fn empty_or_null_coefficient_lists_are_refused_naming_key_and_line() {
    let empty = toml_with("kxx = [ 1000000.0,]", "kxx = []");
    refused(
        "kxx.toml",
        &empty,
        &[
            "kxx.toml:137:",
            "\"BearingElement_Bearing 0\".kxx",
            "empty list",
        ],
    );
    let empty = toml_with("kzz = [ 0,]", "kzz = []");
    refused(
        "kzz.toml",
        &empty,
        &[
            "kzz.toml:141:",
            "\"BearingElement_Bearing 0\".kzz",
            "empty list",
        ],
    );
    let null = json_with("BearingElement", "kxx", serde_json::json!([null]));
    refused(
        "kxx.json",
        &null,
        &["kxx.json:", "\"BearingElement_Bearing 0\".kxx", "null"],
    );
    let empty = json_with("BearingElement", "kzz", serde_json::json!([]));
    refused(
        "kzz.json",
        &empty,
        &[
            "kzz.json:",
            "\"BearingElement_Bearing 0\".kzz",
            "empty list",
        ],
    );
    // A null amid numbers was left out, shifting the list against `frequency`.
    let shifted = json_with("BearingElement", "kxx", serde_json::json!([1e6, null, 2e6]));
    refused("shift.json", &shifted, &["shift.json:", ".kxx", "null"]);
}

/// Item 4: disk `n = -1` became node 0, `n = 2.7` node 2; `kzz = [0, 5.0]` with `czz = [5.0]`
/// became a constant axial stiffness 0.
#[test]
fn what_the_file_says_is_read_or_refused_never_changed() {
    let disk = "[\"DiskElement_Disk 0\"]\nn = 2\n";
    for n in ["-1", "2.7"] {
        let text = toml_with(disk, &disk.replace("n = 2", &format!("n = {n}")));
        let err = refused(
            "disk.toml",
            &text,
            &[
                "disk.toml:113:",
                "\"DiskElement_Disk 0\".n",
                "not a node number",
            ],
        );
        assert!(err.contains(&format!("`n` = {n}")), "{err}");
    }
    let json = json_with("DiskElement", "n", serde_json::json!(-1));
    refused(
        "disk.json",
        &json,
        &[
            "disk.json:",
            "\"DiskElement_Disk 0\".n",
            "not a node number",
        ],
    );
    let json = json_with("BearingElement", "n", serde_json::json!(0.5));
    refused(
        "bearing.json",
        &json,
        &["bearing.json:", ".n", "not a node number"],
    );
    let text =
        toml_with("czz = [ 0,]", "czz = [ 5.0,]").replacen("kzz = [ 0,]", "kzz = [0, 5.0]", 1);
    refused(
        "kzz.toml",
        &text,
        &["kzz.toml:141:", ".kzz", "speed-dependent"],
    );
    // A constant kzz, czz given once per speed is still an axial support.
    let text = toml_with("czz = [ 0,]", "czz = [ 5.0, 5.0,]").replacen(
        "kzz = [ 0,]",
        "kzz = [3.0, 3.0]",
        1,
    );
    let scene = rubsim::scene::ross::import(&repo(TOML), &text).unwrap();
    assert!(
        scene.contains("[[rotor.axial_support]]\nnode = 0\nstiffness = 3.0\ndamping = 5.0\n"),
        "{scene}"
    );
    // A string where a switch or a number belongs was read as its default.
    let text = toml_with("shear_effects = true", "shear_effects = \"no\"");
    refused(
        "flag.toml",
        &text,
        &["flag.toml:19:", ".shear_effects", "not true or false"],
    );
    let text = toml_with("axial_force = 0", "axial_force = \"10\"");
    refused(
        "force.toml",
        &text,
        &["force.toml:17:", ".axial_force", "not a number"],
    );
}

/// Item 5: a `ross_version` (or a table name) with a newline injected keys into the scene; a
/// file named `q"uote.toml` gave a scene that did not parse.
#[test]
fn the_scene_is_written_by_a_serializer_and_nothing_is_injected() {
    let version = "2.3.0)\noutput.component = \"x\"\n#";
    let toml_text = toml_with(
        "ross_version = \"2.3.0\"",
        &format!("ross_version = {}", toml_edit::value(version)),
    );
    let json_text = serde_json::to_string(&{
        let mut d: serde_json::Value = serde_json::from_str(&common::read(&repo(JSON))).unwrap();
        d["ross_version"] = version.into();
        d
    })
    .unwrap();
    // A bearing whose name carries a line break and a table of its own.
    let evil = "BearingElement_B\n[run]\nspeed_ratio = 9.0";
    let named = toml_with(
        "[\"BearingElement_Bearing 1\"]",
        &format!("[{}]", toml_edit::Key::new(evil)),
    );
    for (name, text) in [
        ("v.toml", &toml_text),
        ("v.json", &json_text),
        ("n.toml", &named),
    ] {
        let scene = rubsim::scene::ross::import(Path::new(name), text).unwrap();
        let doc: toml::Table = scene
            .parse()
            .unwrap_or_else(|e| panic!("{name}: {e}\n{scene}"));
        assert!(!doc.contains_key("output"), "{name}: {scene}");
        assert_eq!(
            doc["run"]["speed_ratio"].as_float(),
            Some(1.0),
            "{name}: {scene}"
        );
        assert!(
            scene
                .lines()
                .filter(|l| l.starts_with("speed_ratio"))
                .count()
                == 1,
            "{scene}"
        );
        common::parse(&scene, common::NO_SETS);
    }
    let scene = rubsim::scene::ross::import(Path::new("v.toml"), &toml_text).unwrap();
    assert!(
        scene.contains("ROSS \"2.3.0)\\noutput.component = \\\"x\\\"\\n#\""),
        "{scene}"
    );
    let d = tempfile::tempdir().unwrap();
    let quoted = file(d.path(), "q\"uote.toml", &common::read(&repo(TOML)));
    let scene = ok(d.path(), &["import-ross", quoted.to_str().unwrap()]);
    let doc: toml::Table = scene.parse().unwrap();
    assert_eq!(doc["title"].as_str(), Some("ROSS rotor q\"uote.toml"));
}

/// Item 6: errors named the generated scene's line and key (`…:13: key rotor.shaft.0.length`),
/// or a TOML parse error of `length = NaN`; now the user's file, line and ROSS key.
#[test]
fn errors_name_the_ross_file_line_and_key() {
    let path = repo(TOML);
    let import = |text: &str| {
        rubsim::scene::ross::import(&path, text)
            .unwrap_err()
            .to_string()
    };
    let shaft = "\"ShaftElement_Shaft Element 0\"";
    for (from, to, needles) in [
        (
            "L = 0.25",
            "L = -0.25",
            vec![":11: key", ".L`", "positive", "shaft element n = 0"],
        ),
        (
            "L = 0.25",
            "L = nan",
            vec![":11: key", ".L`", "`L` = NaN is not a finite number"],
        ),
        (
            "L = 0.25",
            "L = inf",
            vec![":11: key", ".L`", "not a finite number"],
        ),
        ("odl = 0.05", "odl = 0.0", vec![":13: key", ".odl`"]),
        (
            "beta = 0.0",
            "beta = -1.0",
            vec![":25: key", ".beta`", "zero or positive"],
        ),
        (
            "E = 211000000000.0",
            "E = -1.0",
            vec![":175: key", ".material.E`"],
        ),
        (
            "G_s = 81200000000.0",
            "G_s = 1e9",
            vec![":176: key", ".material.G_s`", "E/(2·G_s)"],
        ),
    ] {
        let e = import(&toml_with(from, to));
        assert!(
            e.contains("rotor_example.toml:") && e.contains(shaft),
            "{to}: {e}"
        );
        assert!(
            !e.contains("rotor.shaft.0.length =") && !e.contains("parse error"),
            "{to}: {e}"
        );
        for n in needles {
            assert!(e.contains(n), "{to}: `{n}` not in {e}");
        }
    }
    // The same in the JSON form, at its line.
    let json = json_with(
        "ShaftElement_Shaft Element 0",
        "L",
        serde_json::json!(-0.25),
    );
    let line = 1 + json
        .lines()
        .position(|l| l.contains("\"L\": -0.25"))
        .unwrap();
    let e = rubsim::scene::ross::import(&repo(JSON), &json)
        .unwrap_err()
        .to_string();
    let at = format!("rotor_example.json:{line}: key `\"ShaftElement_Shaft Element 0\".L`");
    assert!(e.contains(&at), "{e}");
    // A disk beyond the shaft's last node is named by the disk's `n`.
    let e = import(&toml_with(
        "[\"DiskElement_Disk 0\"]\nn = 2",
        "[\"DiskElement_Disk 0\"]\nn = 9",
    ));
    assert!(
        e.contains("rotor_example.toml:113: key `\"DiskElement_Disk 0\".n`"),
        "{e}"
    );
}

/// Item 9 (import-ross): `--out` overwrote any file, the ROSS file itself included, and wrote
/// through symbolic links.
#[test]
fn out_refuses_existing_files_the_input_and_links() {
    let d = tempfile::tempdir().unwrap();
    let dir = d.path();
    let input = file(dir, "rotor.toml", &common::read(&repo(TOML)));
    let run = |out: &str, force: bool| {
        let mut args = vec!["import-ross", "rotor.toml", "--out", out];
        if force {
            args.push("--force");
        }
        args.iter().map(|s| s.to_string()).collect::<Vec<_>>()
    };
    let refuse = |out: &str, force: bool, what: &str| {
        let args = run(out, force);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let err = fails(dir, &args);
        assert!(err.contains(out) && err.contains(what), "{args:?}: {err}");
    };
    let kept = file(dir, "kept.toml", "# mine\n");
    refuse("kept.toml", false, "--force");
    assert_eq!(common::read(&kept), "# mine\n");
    for force in [false, true] {
        refuse("rotor.toml", force, "the ROSS file");
        assert_eq!(common::read(&input), common::read(&repo(TOML)));
    }
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("kept.toml", dir.join("link.toml")).unwrap();
        std::os::unix::fs::symlink("absent.toml", dir.join("dangling.toml")).unwrap();
        std::os::unix::fs::symlink("rotor.toml", dir.join("input_link.toml")).unwrap();
        for force in [false, true] {
            refuse("link.toml", force, "symbolic link");
            refuse("dangling.toml", force, "symbolic link");
            refuse("input_link.toml", force, "symbolic link");
        }
        assert_eq!(common::read(&kept), "# mine\n");
        assert!(!dir.join("absent.toml").exists());
        // A second name (hard link) of the input is the input.
        fs::hard_link(&input, dir.join("hard.toml")).unwrap();
        refuse("hard.toml", true, "the ROSS file");
    }
    refuse(".", true, "directory");
    // With --force an existing file is replaced, whole; nothing else is left in the folder.
    let args = run("kept.toml", true);
    ok(dir, &args.iter().map(String::as_str).collect::<Vec<_>>());
    let scene = rubsim::scene::ross::import(&input, &common::read(&input)).unwrap();
    assert_eq!(common::read(&kept), scene);
    let args = run("new.toml", false);
    ok(dir, &args.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(common::read(&dir.join("new.toml")), scene);
    let names: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .collect();
    assert!(names.iter().all(|n| !n.contains(".tmp")), "{names:?}");
    // A refused import writes nothing.
    file(dir, "bad.toml", &toml_with("L = 0.25", "L = -0.25"));
    let err = fails(dir, &["import-ross", "bad.toml", "--out", "bad_scene.toml"]);
    assert!(err.contains("bad.toml:11:"), "{err}");
    assert!(!dir.join("bad_scene.toml").exists());
}

/// The rotors ROSS 3.0.0 saved (`scripts/ross3_fixtures.py`) and its `run_modal` results.
const ROSS3: &str = "tests/data/ross/ross3";

/// The scene `import-ross` writes for the ROSS 3 fixture `name`, and its text.
fn ross3_scene(name: &str) -> (String, String) {
    let path = repo(&format!("{ROSS3}/{name}"));
    let text = common::read(&path);
    let scene = rubsim::scene::ross::import(&path, &text).unwrap();
    (scene, text)
}

/// Issue 30: ROSS 3 keeps the Rayleigh factors on the rotor (`[parameters] alpha, beta`), which
/// `import-ross` dropped (ζ₁ 0.0010 against ROSS's 0.0239 for `rotor_example_with_damping`).
/// Imported as `rayleigh_on = "rotor"` with the bearings' own damping, the first 12 modes (ζ <
/// 0.5) at 0 and 1000 rad/s equal ROSS 3.0.0's dense `run_modal` — also for a rotor whose
/// elements carry other factors, which ROSS 3 ignores beside the rotor's.
#[test]
fn ross3_rotor_level_damping_gives_ross3_modes() {
    let reference: serde_json::Value = serde_json::from_str(&common::read(&repo(&format!(
        "{ROSS3}/modal_reference.json"
    ))))
    .unwrap();
    assert_eq!(reference["ross_version"], "3.0.0");
    let floats = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let rotors = reference["rotors"].as_object().unwrap();
    assert_eq!(rotors.len(), 2);
    for (name, speeds) in rotors {
        let (scene, _) = ross3_scene(&format!("{name}.toml"));
        assert!(scene.contains("rayleigh_on = \"rotor\""), "{scene}");
        assert!(scene.contains("# Format: ROSS 3 ("), "{scene}");
        let m = common::build(&common::parse(&scene, common::NO_SETS));
        for (speed, want) in speeds.as_object().unwrap() {
            let omega: f64 = speed.parse().unwrap();
            let got = rubsim::linear::modal(&m.rotor, omega, 200).unwrap();
            let got: Vec<_> = got.modes.iter().filter(|g| g.damping_ratio < 0.5).collect();
            let (wd, zeta) = (floats(&want["wd"]), floats(&want["damping_ratio"]));
            assert_eq!(wd.len(), 12);
            let (mut worst_wd, mut worst_zeta) = (0.0_f64, 0.0_f64);
            for (w, z) in wd.iter().zip(&zeta) {
                let g = got
                    .iter()
                    .min_by(|a, b| (a.omega_d - w).abs().total_cmp(&(b.omega_d - w).abs()))
                    .unwrap();
                worst_wd = worst_wd.max((g.omega_d / w - 1.0).abs());
                worst_zeta = worst_zeta.max((g.damping_ratio / z - 1.0).abs());
            }
            eprintln!("{name} at {omega} rad/s: ω_d {worst_wd:.2e}, ζ {worst_zeta:.2e}");
            assert!(
                worst_wd < 1e-8 && worst_zeta < 1e-8,
                "{name} at {omega}: ω_d {worst_wd:e}, ζ {worst_zeta:e}"
            );
        }
    }
    // ROSS's first mode as the issue measured it (ROSS 3.1.0: ζ₁ = 0.0239).
    let z1 = floats(&rotors["rotor_example_with_damping"]["0.0"]["damping_ratio"])[0];
    assert!((z1 - 0.0239).abs() < 1e-4, "{z1}");
    // The JSON form gives the same scene, table for table.
    let body = |s: &str| -> Vec<String> {
        s.lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("title"))
            .map(String::from)
            .collect()
    };
    let (toml_scene, _) = ross3_scene("rotor_example_with_damping.toml");
    let (json_scene, _) = ross3_scene("rotor_example_with_damping.json");
    assert_eq!(body(&json_scene), body(&toml_scene));
    assert!(
        toml_scene.contains("rayleigh = [8.0501, 1e-5]\nrayleigh_on = \"rotor\"")
            && toml_scene.contains("cyy = 100.4553"),
        "{toml_scene}"
    );
}

/// Each ROSS damping convention maps to its own scene, and what the scene cannot hold is
/// refused at the ROSS file's line and key: ROSS 3's modal damping, rotor-level factors given
/// twice or negative, two-axis bearing tables, an unknown `interpolation`.
#[test]
fn ross3_damping_conventions_mapped_or_refused_by_key() {
    let (_, text) = ross3_scene("both_damping.toml");
    let import = |text: &str| rubsim::scene::ross::import(Path::new("r3.toml"), text);
    // Beside the rotor's factors the elements' are ignored (by ROSS too), even unequal ones.
    let unequal = text.replacen("alpha = 3.0", "alpha = 7.0", 1);
    let scene = import(&unequal).unwrap();
    assert!(
        scene.contains("rayleigh = [1.5, 4e-5]\nrayleigh_on = \"rotor\"")
            && scene.contains("ROSS 3 ignores the shaft elements' `alpha`, `beta`"),
        "{scene}"
    );
    // The rotor's factors zero: the elements' are ROSS 3's damping, as in ROSS 2.
    let elemental =
        text.replacen("alpha = 1.5", "alpha = 0.0", 1)
            .replacen("beta = 4e-5", "beta = 0.0", 1);
    let scene = import(&elemental).unwrap();
    assert!(
        scene.contains("rayleigh = [3.0, 2e-5]\nrayleigh_on = \"shaft\""),
        "{scene}"
    );
    let err = import(&elemental.replacen("alpha = 3.0", "alpha = 7.0", 1))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("\"ShaftElement_Shaft Element 1\".alpha`") && err.contains("must be the same"),
        "{err}"
    );
    // ROSS 2.3.0's element-level factors stay "shaft".
    let ross2 = common::read(&repo(TOML))
        .replace("alpha = 0.0", "alpha = 8.0501")
        .replace("beta = 0.0", "beta = 1e-5");
    let scene = rubsim::scene::ross::import(&repo(TOML), &ross2).unwrap();
    assert!(
        scene.contains("rayleigh = [8.0501, 1e-5]\nrayleigh_on = \"shaft\"")
            && scene.contains("# Format: ROSS 2 ("),
        "{scene}"
    );
    let line = |needle: &str, t: &str| 1 + t.lines().position(|l| l.starts_with(needle)).unwrap();
    // ROSS 3's modal damping, alone or beside the elements' factors.
    let modal = elemental.replacen(
        "[parameters]\n",
        "[parameters]\nmodal_damping_ratio = [ 0.01, 0.02,]\n",
        1,
    );
    let err = import(&modal).unwrap_err().to_string();
    let at = format!(
        "r3.toml:{}: key `parameters.modal_damping_ratio`",
        line("modal_damping_ratio", &modal)
    );
    assert!(
        err.contains(&at) && err.contains("modal damping") && err.contains("keeps neither"),
        "{err}"
    );
    // Negative or non-numeric rotor-level factors, and factors at the top beside [parameters].
    for (from, to, key) in [
        ("alpha = 1.5", "alpha = -1.5", "alpha"),
        ("beta = 4e-5", "beta = \"x\"", "beta"),
    ] {
        let bad = text.replacen(from, to, 1);
        let err = import(&bad).unwrap_err().to_string();
        let at = format!(
            "r3.toml:{}: key `parameters.{key}`",
            line(&format!("{key} = "), &bad)
        );
        assert!(err.contains(&at), "{to}: {err}");
    }
    let twice = text.replacen("ross_version", "alpha = 2.0\nross_version", 1);
    let err = import(&twice).unwrap_err().to_string();
    assert!(
        err.contains(&format!(
            "r3.toml:{}: key `alpha`",
            line("alpha = 2.0", &twice)
        )) && err.contains("once"),
        "{err}"
    );
    // At the top alone they are the rotor's factors too.
    let top = text.replacen("alpha = 1.5\nbeta = 4e-5\n", "", 1).replacen(
        "ross_version",
        "alpha = 1.5\nbeta = 4e-5\nross_version",
        1,
    );
    let scene = import(&top).unwrap();
    assert!(
        scene.contains("rayleigh = [1.5, 4e-5]\nrayleigh_on = \"rotor\"")
            && scene.contains("(at the top of the file)"),
        "{scene}"
    );
    // Bearing tables: over both speed and frequency refused, an unknown interpolation refused,
    // a PCHIP table noted as such.
    let bearing = "[\"BearingElement_Bearing 0\"]\n";
    let grid = text.replacen(
        bearing,
        &format!("{bearing}speed = [ 0.0, 100.0,]\nfrequency = [ 0.0, 100.0,]\n"),
        1,
    );
    let err = import(&grid).unwrap_err().to_string();
    assert!(
        err.contains("\"BearingElement_Bearing 0\".speed") && err.contains("two-axis"),
        "{err}"
    );
    let table = text
        .replacen(
            bearing,
            &format!("{bearing}speed = [ 0.0, 100.0, 200.0,]\n"),
            1,
        )
        .replacen(
            "kxx = [ 1000000.0,]",
            "kxx = [ 1000000.0, 2000000.0, 3000000.0,]",
            1,
        );
    let scene = import(&table).unwrap();
    assert!(
        scene.contains("ROSS 3 interpolates this table by PCHIP")
            && scene.contains("extrapolates linearly"),
        "{scene}"
    );
    let err = import(&table.replacen("interpolation = \"pchip\"", "interpolation = \"cubic\"", 1))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains(".interpolation`") && err.contains("\"pchip\" and \"linear\""),
        "{err}"
    );
    let linear =
        import(&table.replacen("interpolation = \"pchip\"", "interpolation = \"linear\"", 1))
            .unwrap();
    assert!(
        linear.contains("ROSS 3 interpolates this table linearly, as rubsim does"),
        "{linear}"
    );
}
