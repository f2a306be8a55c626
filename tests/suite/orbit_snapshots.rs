//! Orbit snapshots of a speed transient (`output.snapshot_speeds`): on a slow run-up and
//! coast-down without contact each snapshot is the steady unbalance orbit at its speed, taken
//! where the speed history passes that speed; bad keys are refused by name and line; the CLI
//! writes `orbit_snapshots.csv` and `.png` and warns of a speed never passed.

use crate::common;

use common::scene_model;
use common::scenes::PAPER;
use rubsim::analysis::{orbit_snapshots, prepare_transient, SNAPSHOT_REVOLUTIONS};
use std::f64::consts::PI;

/// The paper's Jeffcott rotor without its rod, with `profile` and `snapshots` (the value of
/// `output.snapshot_speeds`, or nothing when empty).
fn scene(profile: &str, snapshots: &str, rod: bool) -> String {
    let mut t = PAPER.replace("[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1", profile);
    if !rod {
        let a = t.find("[[stator]]").unwrap();
        let b = t.find("[run]").unwrap();
        t = format!("{}{}", &t[..a], &t[b..]);
    }
    if !snapshots.is_empty() {
        t = t.replace(
            "component = \"y\"\n",
            &format!("component = \"y\"\nsnapshot_speeds = {snapshots}\n"),
        );
    }
    t
}

/// Up 0.5 → 3.2 ω_n in `T` s and down again in `T` s, linearly (α/ω_n² = 5.4e-5).
const T: f64 = 300.0;

fn up_down() -> String {
    format!(
        "[run.speed_profile]\nkind = \"table\"\nunit = \"speed_ratio\"\ninterpolation = \"linear\"\npoints = [[0.0, 0.5], [{T}, 3.2], [{}, 0.5]]",
        2.0 * T
    )
}

#[test]
fn slow_up_and_down_snapshots_are_the_steady_orbits_where_the_speed_passes() {
    let text = scene(&up_down(), "[0.8, 1.5, 3.0, 4.0]", false);
    let (ls, model) = scene_model(&text, &[] as &[&str]);
    let s = common::settings(&ls);
    let spec = ls.scene.run.speed_profile.as_ref().unwrap();
    let prep = prepare_transient(&model, &s, spec).unwrap();
    let r = prep.run(&mut []).unwrap();
    let (snaps, missed) = orbit_snapshots(&prep, &r, &ls.scene.output.snapshot_speeds).unwrap();
    assert_eq!(missed, vec![4.0], "4 ω_n is above the profile's 3.2");
    assert_eq!(snaps.len(), 6, "three speeds, each passed up and down");
    // The closed form |Z0|/e = ν²/√((1−ν²)² + (2ξν)²), e = m_u r / M with M the disk's mass.
    let xi = 0.2;
    let mass = 7800.0 * PI * 0.12_f64.powi(2) / 4.0 * 0.03;
    let e = 0.008 * 0.045 / mass;
    let z0 = |nu: f64| e * nu * nu / ((1.0 - nu * nu).powi(2) + (2.0 * xi * nu).powi(2)).sqrt();
    let wn = r.omega_n;
    for (k, sn) in snaps.iter().enumerate() {
        let nu = sn.target;
        // In the order of the targets, then of time: pass 1 up, pass 2 down.
        assert_eq!(sn.target, [0.8, 1.5, 3.0][k / 2]);
        assert_eq!(
            (sn.pass, sn.up),
            if k % 2 == 0 { (1, true) } else { (2, false) }
        );
        // The passage instant on the linear table.
        let t_exact = if sn.up {
            (nu - 0.5) / 2.7 * T
        } else {
            T + (3.2 - nu) / 2.7 * T
        };
        let dt = (sn.t - t_exact).abs();
        // Two revolutions of the local speed, centred on the passage.
        let span = sn.samples.last().unwrap()[0] - sn.samples[0][0];
        let want = SNAPSHOT_REVOLUTIONS * 2.0 * PI / (nu * wn);
        let mid = 0.5 * (sn.samples.last().unwrap()[0] + sn.samples[0][0]);
        // The orbit's mean radius against the closed form, and the steady |Z0| carried.
        let radius =
            sn.samples.iter().map(|v| v[2].hypot(v[3])).sum::<f64>() / sn.samples.len() as f64;
        let (rmin, rmax) = sn.samples.iter().fold((f64::INFINITY, 0.0_f64), |a, v| {
            let q = v[2].hypot(v[3]);
            (a.0.min(q), a.1.max(q))
        });
        let err = (radius - z0(nu)).abs() / z0(nu);
        eprintln!(
            "ν = {nu} pass {} ({}): t = {:.4} s (exact {t_exact:.4}), {} samples over {:.4} s (2 rev {:.4} s), radius {radius:.5e} m [{rmin:.5e}, {rmax:.5e}] against |Z0| {:.5e} m: error {err:.2e}",
            sn.pass,
            if sn.up { "up" } else { "down" },
            sn.t,
            sn.samples.len(),
            span,
            want,
            z0(nu)
        );
        assert!(dt < 1e-3, "passage at {} s, expected {t_exact} s", sn.t);
        assert!(
            (span - want).abs() < 0.02 * want,
            "span {span} s, want {want} s"
        );
        assert!(
            (mid - sn.t).abs() < 0.02 * want,
            "centred at {mid} s, passage {}",
            sn.t
        );
        assert!(sn.samples.len() > 50, "{} samples", sn.samples.len());
        assert!(
            sn.samples.iter().all(|v| (v[1] - nu).abs() < 0.01 * nu),
            "the speed moves by less than 1 % over the snapshot"
        );
        assert!(err < 0.01, "radius error {err}");
        assert!(
            rmax - rmin < 0.02 * z0(nu),
            "not a circle: [{rmin}, {rmax}]"
        );
        assert!(
            (sn.z0 - z0(nu)).abs() < 0.01 * z0(nu),
            "steady |Z0| {}",
            sn.z0
        );
    }
}

/// 1-based line of the first line of `text` that starts with `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.starts_with(needle)).unwrap() + 1
}

#[test]
fn bad_snapshot_speeds_name_the_key_and_line() {
    let ramp = "[run.speed_profile]\nkind = \"ramp\"\nunit = \"speed_ratio\"\nfrom = 0.5\nto = 3.0\nduration = 1.0";
    let cases: &[(&str, &str, &str, &str)] = &[
        (
            ramp,
            "[0.8, -1.5]",
            "output.snapshot_speeds.1",
            "positive finite",
        ),
        (ramp, "[0.0]", "output.snapshot_speeds.0", "positive finite"),
        (
            ramp,
            "[0.8, nan]",
            "output.snapshot_speeds.1",
            "positive finite",
        ),
        (ramp, "[inf]", "output.snapshot_speeds.0", "positive finite"),
        // A sweep: no speed history to pass.
        (
            "[run.sweep]\nfrom = 0.5\nto = 6.0\nstep = 0.1",
            "[1.5]",
            "output.snapshot_speeds",
            "speed transient only",
        ),
    ];
    for (profile, value, key, what) in cases {
        let text = scene(profile, value, false);
        let e = rubsim::scene::parse(std::path::Path::new("t.toml"), &text, &[])
            .expect_err("bad snapshot speeds load")
            .to_string();
        let at = format!(
            "t.toml:{}: key `{key}`",
            line_of(&text, "snapshot_speeds = ")
        );
        assert!(
            e.contains(&at) && e.contains(what),
            "expected `{at}` … `{what}`, got: {e}"
        );
    }
    // A misspelt key is refused by name.
    let text = scene(ramp, "", false).replace(
        "component = \"y\"\n",
        "component = \"y\"\nsnapshot_speed = [1.0]\n",
    );
    let e = rubsim::scene::parse(std::path::Path::new("t.toml"), &text, &[])
        .expect_err("an unknown key loads")
        .to_string();
    assert!(e.contains("snapshot_speed"), "{e}");
}

#[test]
fn cli_writes_the_snapshots_and_warns_of_a_speed_never_passed() {
    // The paper's run-up with its rod, shortened: 0.5 → 3.5 ω_n in 2 s.
    let text = scene(
        "[run.speed_profile]\nkind = \"ramp\"\nunit = \"speed_ratio\"\nfrom = 0.5\nto = 3.5\nduration = 2.0",
        "[1.5, 3.0, 5.0]",
        true,
    );
    let dir = std::env::temp_dir().join(format!("rubsim_snapshots_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("runup.toml");
    std::fs::write(&path, &text).unwrap();
    let out = dir.join("out");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rubsim"))
        .arg("run")
        .arg(&path)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("output.snapshot_speeds") && err.contains("ω/ωn = 5"),
        "no warning for 5 ω_n: {err}"
    );
    let csv = std::fs::read_to_string(out.join("orbit_snapshots.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("speed_ratio_target,pass,direction,t_s,speed_ratio,x_m,y_m")
    );
    let mut keys: Vec<String> = lines
        .map(|l| l.split(',').take(3).collect::<Vec<_>>().join(","))
        .collect();
    keys.dedup();
    assert_eq!(keys, ["1.5,1,up", "3,1,up"]);
    assert!(
        std::fs::metadata(out.join("orbit_snapshots.png"))
            .unwrap()
            .len()
            > 1000
    );
    let sum: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(sum["orbit_snapshots"]["missed_speed_ratios"][0], 5.0);
    assert_eq!(
        sum["orbit_snapshots"]["snapshots"]
            .as_array()
            .unwrap()
            .len(),
        2
    );
    let _ = std::fs::remove_dir_all(&dir);
}
