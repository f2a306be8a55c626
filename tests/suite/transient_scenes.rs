//! The transient scenes of `scenes/transients/` run by the real binary, shortened with `--set`:
//! the blade-off coast-down against the meshed diaphragm with its VTK and HDF5 series and its
//! stator stress history, and the FE rotor's run-up through its first critical with a seal
//! ring. What is checked is that the outputs exist and agree with each other: frames carry
//! the spin state of `speed_history.csv` at their instants, the `.vtu` stress field's largest
//! cell stress is the stress history's at that instant, a massless stator is stressed exactly
//! when it carries contact force, and `summary.json` reports the same peaks.

use crate::common;

use common::cli::{is_png, json, ok};
use common::meshes::gmsh_wanted;
use common::output::{array, pvd, vtu};
use common::{read, repo};
use std::collections::HashMap;
use std::path::Path;

/// The columns of a CSV file by header name.
fn csv(p: &Path) -> HashMap<String, Vec<f64>> {
    let text = read(p);
    let mut lines = text.lines();
    let head: Vec<String> = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let mut cols: HashMap<String, Vec<f64>> = head.iter().map(|h| (h.clone(), vec![])).collect();
    for l in lines {
        for (h, v) in head.iter().zip(l.split(',')) {
            cols.get_mut(h).unwrap().push(v.parse().unwrap());
        }
    }
    cols
}

/// The field data of a `.vtu` written by rubsim (its ASCII `<FieldData>` block).
fn field_data(p: &Path) -> HashMap<String, f64> {
    let text = read(p);
    let block = &text[text.find("<FieldData>").unwrap()..text.find("</FieldData>").unwrap()];
    block
        .split("<DataArray ")
        .skip(1)
        .map(|a| {
            let name = a
                .split("Name=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap();
            let v = a.split('>').nth(1).unwrap().split('<').next().unwrap();
            (name.to_string(), v.trim().parse().unwrap())
        })
        .collect()
}

/// Index of the sample of `t` (s) at time `at`, which must be one of them (to 1e-9 relative).
fn sample(t: &[f64], at: f64) -> usize {
    let i = t
        .iter()
        .enumerate()
        .min_by(|a, b| (a.1 - at).abs().total_cmp(&(b.1 - at).abs()))
        .unwrap()
        .0;
    assert!(
        (t[i] - at).abs() <= 1e-9 * at.abs().max(1e-6),
        "no sample at t = {at}"
    );
    i
}

#[test]
fn blade_off_against_the_meshed_diaphragm_writes_a_consistent_series() {
    if !gmsh_wanted() {
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let scene = repo("scenes/transients/blade_off_diaphragm.toml");
    // 0.3 s at Δt = 4 µs: blade off at 0.1 s, drive off at 0.2 s; VTK frames every 2 300 steps (≈ 9 ms,
    // 25 recording intervals of 92 steps, so that every frame is a recorded sample), HDF5 at
    // every recorded sample.
    let stdout = ok(
        &repo(""),
        &[
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--set",
            "run.dt=4.0e-6",
            "--set",
            "run.speed_profile.duration=0.3",
            "--set",
            "run.speed_profile.drive_off=0.2",
            "--set",
            "output.vtk.every=2300",
            "--set",
            "output.hdf5={ fields = [\"displacement\", \"stress\"] }",
        ],
    );
    assert!(
        stdout.contains("stator `diaphragm`: largest stress"),
        "{stdout}"
    );
    for f in [
        "summary.json",
        "speed_history.csv",
        "response.csv",
        "stress_history.csv",
        "results.pvd",
        "results.vtkhdf",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    for f in ["stress_vs_speed.png", "stress_history.png"] {
        assert!(is_png(&out.join(f)), "{f}");
    }
    let speed = csv(&out.join("speed_history.csv"));
    let stress = csv(&out.join("stress_history.csv"));
    let t = &speed["t_s"];
    // One stress sample per recorded sample, at the same instants and speeds.
    assert_eq!(stress["t_s"].len(), t.len());
    for (a, b) in stress["t_s"].iter().zip(t) {
        assert!((a - b).abs() <= 1e-12 + 1e-9 * b, "{a} vs {b}");
    }
    for (a, b) in stress["omega_rad_s"].iter().zip(&speed["omega_rad_s"]) {
        assert!((a - b).abs() <= 1e-9 * b, "{a} vs {b}");
    }
    let (s, f) = (&stress["diaphragm_stress_pa"], &stress["diaphragm_force_n"]);
    // A massless stator is stressed exactly when it carries contact force. The start from
    // rest at full speed grazes the bore, then nothing touches until the blade leaves at
    // 0.1 s; after it the disk rubs (a bouncing rub: contact in every 20 ms).
    for i in 0..t.len() {
        assert_eq!(
            s[i] > 0.0,
            f[i] > 0.0,
            "t = {}: σ {} p {}",
            t[i],
            s[i],
            f[i]
        );
    }
    let touches = |a: f64, b: f64| {
        (0..t.len())
            .filter(|&i| t[i] >= a && t[i] < b && f[i] > 0.0)
            .count()
    };
    assert_eq!(touches(0.02, 0.1), 0);
    for k in 0..10 {
        let a = 0.1 + 0.02 * k as f64;
        assert!(
            touches(a, a + 0.02) > 0,
            "no contact in [{a}, {}) s",
            a + 0.02
        );
    }
    // summary.json: the peak of the history, its time and speed.
    let sum = json(&out.join("summary.json"));
    let peak = &sum["stator_stress"]["peaks"][0];
    assert_eq!(peak["name"], "diaphragm");
    let smax = s.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    assert!(rel(peak["stress_pa"].as_f64().unwrap(), smax) < 1e-6);
    let ipk = sample(t, peak["t_s"].as_f64().unwrap());
    assert!(rel(s[ipk], smax) < 1e-6);
    assert!(
        rel(
            peak["speed_ratio"].as_f64().unwrap(),
            speed["speed_ratio"][ipk]
        ) < 1e-5
    );
    assert_eq!(sum["transient"]["plan"]["record_every"], 92);
    // The VTK frames: 0.3 s / 4 µs = 75 000 steps, a frame every 2 300: 33 frames, each with
    // the spin of its instant and the diaphragm's stress field, whose largest cell stress is
    // the history's at that instant.
    let frames = pvd(&out.join("results.pvd"));
    assert_eq!(frames.len(), 33);
    let mut stressed = 0;
    for (time, file) in &frames {
        let path = out.join(file);
        let fd = field_data(&path);
        assert_eq!(fd["TimeValue"], *time);
        let i = sample(t, *time);
        assert!(rel(fd["omega"], speed["omega_rad_s"][i]) < 1e-9);
        assert!((fd["phi"] - speed["phi_rad"][i]).abs() <= 1e-9 * speed["phi_rad"][i].max(1.0));
        assert!(rel(fd["speed_ratio"], speed["speed_ratio"][i]) < 1e-6);
        let g = vtu(&path);
        let cell_stress = array(&g.data.cell, "stress");
        let vmax = cell_stress
            .iter()
            .filter(|v| v.is_finite())
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        if s[i] == 0.0 {
            assert_eq!(vmax, 0.0, "t = {time}");
        } else {
            assert!(rel(vmax, s[i]) < 1e-6, "t = {time}: {vmax} vs {}", s[i]);
            stressed += 1;
        }
    }
    assert!(stressed > 0, "no frame of the rub stressed");
    // φ grows as ∫Ω dt (trapezoid over the recorded samples) and Ω falls after the drive is off.
    let (w, phi) = (&speed["omega_rad_s"], &speed["phi_rad"]);
    let mut integral = 0.0;
    for i in 1..t.len() {
        integral += 0.5 * (w[i] + w[i - 1]) * (t[i] - t[i - 1]);
    }
    assert!(
        rel(integral, phi[t.len() - 1]) < 1e-5,
        "{integral} vs {}",
        phi[t.len() - 1]
    );
    assert!(w[t.len() - 1] < w[0]);
    #[cfg(feature = "hdf5")]
    {
        let f = crate::common::output::open_h5(&out.join("results.vtkhdf"));
        let ht: Vec<f64> = f.dataset("time").unwrap().read_raw().unwrap();
        let hw: Vec<f64> = f.dataset("spin/omega").unwrap().read_raw().unwrap();
        let hphi: Vec<f64> = f
            .dataset("VTKHDF/FieldData/phi")
            .unwrap()
            .read_raw()
            .unwrap();
        assert_eq!(ht.len(), t.len());
        for i in 0..t.len() {
            assert!(rel(hw[i], w[i]) < 1e-9);
            assert!((hphi[i] - phi[i]).abs() <= 1e-9 * phi[i].max(1.0));
        }
    }
}

#[test]
fn fe_rotor_runs_up_through_its_critical_rubbing_the_seal() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let scene = repo("scenes/transients/friswell_runup_seal.toml");
    // 0.8 → 1.2 ω_n in 3 s: the crossing of the first critical, where the disk rubs.
    ok(
        &repo(""),
        &[
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--set",
            "run.speed_profile.from=0.8",
            "--set",
            "run.speed_profile.to=1.2",
            "--set",
            "run.speed_profile.duration=3.0",
        ],
    );
    let sum = json(&out.join("summary.json"));
    let tr = &sum["transient"];
    let wn = tr["omega_n"].as_f64().unwrap();
    assert!((wn - 86.66).abs() < 1.0, "ω_n = {wn}");
    assert!(tr["stats"]["contact_steps"].as_u64().unwrap() > 0);
    assert!(tr["friction_energy"].as_f64().unwrap() > 0.0);
    // A ring has no elements: no stress history.
    assert!(!out.join("stress_history.csv").exists());
    assert!(sum.get("stator_stress").is_none());
    // The HDF5 series: one frame every 2 000 steps with the profile's speed, a ramp.
    let resp = csv(&out.join("response.csv"));
    let f = &resp["contact_force_n"];
    let nu = &resp["speed_ratio"];
    // Contact only around the critical: none at 0.8 ω_n.
    assert_eq!(f[0], 0.0);
    let first = f.iter().position(|&x| x > 0.0).unwrap();
    assert!(
        nu[first] > 0.85 && nu[first] < 1.05,
        "first contact at {}",
        nu[first]
    );
    #[cfg(feature = "hdf5")]
    {
        let h = crate::common::output::open_h5(&out.join("results.vtkhdf"));
        let t: Vec<f64> = h.dataset("time").unwrap().read_raw().unwrap();
        let r: Vec<f64> = h.dataset("spin/speed_ratio").unwrap().read_raw().unwrap();
        let a: Vec<f64> = h.dataset("spin/omega_dot").unwrap().read_raw().unwrap();
        assert!(t.len() > 10);
        for i in 0..t.len() {
            // Ω(t) = (0.8 + 0.4 t/3) ω_n, Ω̇ = 0.4 ω_n / 3.
            assert!(
                (r[i] - (0.8 + 0.4 * t[i] / 3.0)).abs() < 1e-9,
                "{} at {}",
                r[i],
                t[i]
            );
            assert!((a[i] - 0.4 * wn / 3.0).abs() < 1e-9 * wn);
        }
    }
}
