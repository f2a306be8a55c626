//! Periodic orbits as VTK/HDF5 time series and the coexistence check through periodic orbits
//! (issue 29, items 3 and 4; docs/VALIDATION.md §19.3, §19.4): the written period starts on the
//! fixed point and closes one period on (read back with `vtkio` and `hdf5-metno`); `rubsim
//! continue --orbits-at` writes the orbits asked for and `rubsim check` lists them; a flagged
//! speed's two responses shot as orbits — the paper case's period-2 and period-3 partial rubs at
//! ν 4.1, the ring's no-contact orbit and full annular rub inside its hysteresis loop (radius
//! against the closed form, docs/ORACLES.md §2) — and a response that is not periodic reported,
//! not shot.

use crate::common;
use common::cli::{json, ok, rubsim, text};
use common::oracles::radial_annular_rub;
use common::output::{pvd, rotor_in_frame};
use common::{file_model, read, repo, run_speed, settings};
use rubsim::analysis::{self, coexist_orbits::CoexistOrbits, periodic, SpeedResults};

const PAPER: &str = "scenes/paper/partial_rub.toml";
const RING: &str = "scenes/periodic/ring_hysteresis.toml";
/// The ring scene's data (scenes/periodic/ring_hysteresis.toml): κ, μ, ξ, δ/e, e (m).
const KAPPA: f64 = 25.0;
const MU: f64 = 0.1;
const XI: f64 = 0.2;
const D: f64 = 1.5;
const E: f64 = 1e-3;

/// `max |a − b|` over `scale`.
fn rel(a: &[f64], b: &[f64], scale: f64) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// The period-2 orbit of the paper case at ν 4.1 (the response its run settles on) written by
/// `results::Series::orbit` as VTK and HDF5: `2N/every + 1` frames at times 2T … 4T, the first
/// on the fixed point and the last on it again, each to the shooting tolerance (measured: first
/// 2.55e-13, last 2.98e-13 of the orbit's size; asserted 1e-9, `periodic::SHOOT_TOLERANCE`).
#[test]
fn the_orbit_series_starts_on_the_fixed_point_and_closes_after_one_period() {
    let (ls, m) = file_model(
        &repo(PAPER),
        &["output.vtk={}", "output.hdf5={}", "output.png=false"],
    );
    let prep = analysis::prepare(&m, &periodic::request_at(&settings(&ls), 4.1)).unwrap();
    let o = periodic::shoot(&prep, Some(2)).unwrap();
    assert!(o.converged && o.stable, "{o:?}");
    let tmp = tempfile::tempdir().unwrap();
    let scene_json = serde_json::to_string(&ls.scene).unwrap();
    let series = rubsim::results::Series {
        output: &ls.scene.output,
        scene_json: &scene_json,
        staging: tmp.path(),
    };
    let files = series.orbit(&m, &prep, &o, "orbit/").unwrap();
    let dir = tmp.path().join("orbit");
    let frames = pvd(&dir.join("results.pvd"));
    let (n, every) = (prep.plan.steps_per_rev, prep.plan.record_every);
    assert_eq!(frames.len(), 2 * n / every + 1);
    assert!(files.iter().any(|f| f == "orbit/results.pvd"), "{files:?}");
    let period = 2.0 * n as f64 * prep.plan.dt;
    assert!(
        (frames[0].0 / period - 1.0).abs() < 1e-12,
        "{}",
        frames[0].0
    );
    assert!((frames.last().unwrap().0 / period - 2.0).abs() < 1e-12);
    let x = o.fixed_state();
    let size = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let first = rotor_in_frame(&dir.join(&frames[0].1));
    let last = rotor_in_frame(&dir.join(&frames.last().unwrap().1));
    let (d0, d1) = (rel(&first, &x[..2], size), rel(&last, &first, size));
    eprintln!("first frame − fixed point {d0:.2e}, last − first {d1:.2e} of the orbit's size");
    assert!(d0 <= periodic::SHOOT_TOLERANCE && d1 <= periodic::SHOOT_TOLERANCE);
    // The frames in between move the rotor by the orbit's size.
    let mid = rotor_in_frame(&dir.join(&frames[frames.len() / 3].1));
    assert!(rel(&mid, &first, size) > 0.1);
    #[cfg(feature = "hdf5")]
    {
        let f = crate::common::output::open_h5(&dir.join("results.vtkhdf"));
        let t: Vec<f64> = common::output::read(&f, "time");
        let u: Vec<f64> = common::output::read(&f, "rotor/u");
        assert_eq!(t.len(), frames.len());
        let nd = u.len() / t.len();
        let (h0, h1) = (&u[..2], &u[u.len() - nd..u.len() - nd + 2]);
        assert_eq!(h0, &first[..], "HDF5 and VTK hold the same frames");
        assert!(rel(h1, h0, size) <= periodic::SHOOT_TOLERANCE);
    }
}

/// `rubsim continue --orbits-at`: at a value between two points the orbit is shot from the
/// nearest one (Newton iterates), at a grid point it is that point's (no iteration), a value
/// outside the branch is reported; each orbit's series under `orbits/branch<i>_<ν>/`, listed in
/// summary.json with its files; the orbit at 4.1 has the extents of `rubsim periodic`'s period-2
/// orbit there (measured 8.3e-11 |Z0|); `rubsim check` lists the orbit series.
#[test]
fn continue_writes_the_orbits_asked_for_and_check_lists_them() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("c");
    let o = out.to_str().unwrap();
    let sets = ["--set", "output.vtk={}", "--set", "output.png=false"];
    let mut args = vec![
        "continue",
        PAPER,
        "--from",
        "3.9",
        "--to",
        "4.1",
        "--step",
        "0.1",
        "--period",
        "2",
        "--orbits-at",
        "4.04,4.1,5",
        "--out",
        o,
    ];
    args.extend_from_slice(&sets);
    let r = rubsim(&repo(""), &args);
    let (stdout, stderr) = (text(&r.stdout), text(&r.stderr));
    assert!(r.status.success(), "{stdout}\n{stderr}");
    assert!(
        stderr.contains("--orbits-at 5: no branch"),
        "the value outside the branch is reported: {stderr}"
    );
    let s = json(&out.join("summary.json"));
    let orbits = s["orbits"].as_array().expect("orbits");
    assert_eq!(orbits.len(), 2, "{orbits:?}");
    let (a, b) = (&orbits[0], &orbits[1]);
    assert_eq!(a["speed_ratio"], 4.04);
    assert_eq!(a["from_speed_ratio"], 4.0);
    assert!(a["converged"].as_bool().unwrap() && a["iterations"].as_u64().unwrap() >= 1);
    assert_eq!(b["from_speed_ratio"], 4.1);
    assert_eq!(b["iterations"], 0, "{b}");
    for (x, folder) in [(a, "orbits/branch0_4.04/"), (b, "orbits/branch0_4.1/")] {
        assert_eq!(x["series"]["folder"], folder);
        let files = x["series"]["files"].as_array().unwrap();
        assert!(files.len() > 100, "{files:?}");
        for f in files {
            assert!(out.join(f.as_str().unwrap()).is_file(), "{f}");
        }
        assert!(out.join(folder).join("results.pvd").is_file());
    }
    // The same orbit as `rubsim periodic --period 2` at 4.1.
    let p = tmp.path().join("p");
    ok(
        &repo(""),
        &[
            "periodic",
            PAPER,
            "--speed",
            "4.1",
            "--period",
            "2",
            "--out",
            p.to_str().unwrap(),
            "--set",
            "output.png=false",
        ],
    );
    let ext = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let shot = ext(&json(&p.join("summary.json"))["periodic"]["orbit"]["extents_nd"]);
    let d = rel(&ext(&b["extents_nd"]), &shot, 1.0);
    eprintln!("extents of the orbit at 4.1 against `rubsim periodic`: {d:.1e} |Z0|");
    assert!(d < 1e-6, "{d}");
    let check = ok(&repo(""), &["check", PAPER, "--set", "output.vtk={}"]);
    assert!(
        check.contains("vtk of a periodic orbit") && check.contains("orbits/branch<i>_<ν>/"),
        "{check}"
    );
}

/// The check's orbits of a run (panics when the speed is not flagged or was not shot).
fn orbits(r: &SpeedResults) -> CoexistOrbits {
    let c = r.coexistence.clone().expect("the check ran");
    assert!(c.coexisting, "flagged: {c:?}");
    c.orbits.expect("a flagged speed's orbits")
}

/// The paper case at ν 4.1 (docs/VALIDATION.md §19: the period-2 and period-3 branches both
/// stable there): the run settles on period 2, the companion from full contact on period 3; both
/// shot as stable orbits, distinct, `coexisting_stable` 2; their extents equal the period-2 orbit
/// `rubsim periodic` shoots there (measured 0: the same run and start) and the period-3 branch continued down
/// to 4.1 from 4.2 (measured 3.8e-11 |Z0|); asserted 1e-6.
#[test]
fn the_paper_case_at_4_1_gets_stable_period_2_and_period_3_orbits() {
    let text_ = read(&repo(PAPER));
    let r = run_speed(&text_, common::NO_SETS, 4.1);
    let o = orbits(&r);
    eprintln!("{}", o.describe());
    let [run, comp] = [&o.orbits[0], &o.orbits[1]];
    assert_eq!((run.response.as_str(), run.period), ("run", 2));
    assert_eq!((comp.response.as_str(), comp.period), ("companion", 3));
    assert!(
        run.converged && run.stable && comp.converged && comp.stable,
        "{o:?}"
    );
    assert!(run.largest_modulus < 1.0 && comp.largest_modulus < 1.0);
    assert_eq!(o.distinct, Some(true));
    assert!(o.distance.unwrap() > 0.1, "{o:?}");
    assert_eq!(o.coexisting_stable, 2);
    let (ls, m) = file_model(&repo(PAPER), common::NO_SETS);
    let s = settings(&ls);
    let p2 = periodic::shoot(&analysis::prepare(&m, &s.request(4.1)).unwrap(), Some(2)).unwrap();
    let d2 = rel(&run.extents_nd, &p2.orbit.extents_nd, 1.0);
    let b3 = analysis::branch::continue_in_speed(&m, &s, &[4.2, 4.1], Some(3)).unwrap();
    let at = b3.points.last().unwrap();
    assert!((at.speed_ratio - 4.1).abs() < 1e-12 && at.stable, "{b3:?}");
    let d3 = rel(&comp.extents_nd, &at.extents_nd, 1.0);
    eprintln!("period 2 against `periodic`: {d2:.1e}; period 3 against its branch: {d3:.1e}");
    assert!(d2 < 1e-6 && d3 < 1e-6, "{d2} {d3}");
}

/// The ring of `ring_hysteresis.toml` at ν 2.8, inside its hysteresis loop: the run (started on
/// the rub) in synchronous full annular rub, the companion on the no-contact orbit; both shot as
/// stable period-1 orbits — the rub's radius against the closed form (ORACLES §2: 2.40026 e;
/// measured 2.40019 e), the free orbit's against |Z0| (1.13055 e against 1.13114 e; contact
/// fraction 0). Asserted 2e-3: 64 samples a revolution read a circle up to 1.2e-3 low.
#[test]
fn the_ring_inside_its_loop_gets_a_stable_free_orbit_and_a_stable_full_rub_orbit() {
    let nu = 2.8;
    let r = run_speed(&read(&repo(RING)), &["run.check_coexistence=true"], nu);
    let o = orbits(&r);
    eprintln!("{}", o.describe());
    let [rub, free] = [&o.orbits[0], &o.orbits[1]];
    assert!(
        rub.converged && rub.stable && free.converged && free.stable,
        "{o:?}"
    );
    assert_eq!((rub.period, free.period), (1, 1));
    assert!(
        rub.contact_fraction >= 0.99 && free.contact_fraction == 0.0,
        "{o:?}"
    );
    assert_eq!((o.distinct, o.coexisting_stable), (Some(true), 2));
    let radius = |e: &[f64; 4]| e.iter().fold(0.0_f64, |m, v| m.max(v.abs())) * r.z0 / E;
    let (full, _) = radial_annular_rub(nu, KAPPA, MU, XI, D);
    let z0 = r.z0 / E;
    let (a, b) = (radius(&rub.extents_nd), radius(&free.extents_nd));
    eprintln!("rub radius {a:.5} e (closed form {full:.5} e); free {b:.5} e (|Z0| {z0:.5} e)");
    // 64 samples a revolution read a circle up to 1 − cos(π/64) = 1.2e-3 below its radius.
    assert!((a / full - 1.0).abs() <= 2e-3, "{a} against {full}");
    assert!((b / z0 - 1.0).abs() <= 2e-3, "{b} against {z0}");
}

/// The ring at ν 3.5, past the rub's Neimark–Sacker point (3.07 – 3.26, §19): the run started
/// on the no-contact linear response stays on it (its orbit 1.08 e reaches past half the
/// clearance, so the check starts the companion in full contact), the companion settles on the
/// rub's torus (contact fraction 0.82, no period: regime undetermined). The run's orbit is shot (stable, no
/// contact); the companion's is not, and the report says why; `coexisting_stable` counts one.
#[test]
fn a_companion_that_is_not_periodic_is_reported_not_shot() {
    let nu: f64 = 3.5;
    // X = e ν² / (1 − ν² + 2iξν): u = Re X, v = Re(iωX) at t = 0 (ω = ν rad/s, ω_n = 1).
    let den = (1.0 - nu * nu, 2.0 * XI * nu);
    let m = den.0 * den.0 + den.1 * den.1;
    let x = (E * nu * nu * den.0 / m, -E * nu * nu * den.1 / m);
    let sets = [
        "run.check_coexistence=true".to_string(),
        format!("run.initial_displacement=[{:e},{:e}]", x.0, x.1),
        format!("run.initial_velocity=[{:e},{:e}]", -nu * x.1, nu * x.0),
    ];
    let r = run_speed(&read(&repo(RING)), &sets, nu);
    assert_eq!(r.contact_fraction, 0.0);
    let o = orbits(&r);
    eprintln!("{}", o.describe());
    let [run, comp] = [&o.orbits[0], &o.orbits[1]];
    assert!(
        run.converged && run.stable && run.contact_fraction == 0.0,
        "{o:?}"
    );
    assert_eq!(comp.period, 0, "{o:?}");
    let why = comp.not_shot.as_deref().expect("not shot");
    assert!(why.contains("not periodic"), "{why}");
    assert_eq!((o.distinct, o.coexisting_stable), (None, 1));
    assert!(o.describe().contains("not shot: not periodic"));
}

/// `rubsim periodic --autonomous` writes the whirl's period as a time series: the dry whip of
/// `scenes/periodic/dry_whip.toml` (a backward whirl at its own frequency, period T unknown to
/// the scene) integrated from its fixed point at Δt = T/N, the frames (every a divisor of N)
/// at times T … 2T, the last on the first again to 1e-8 of the orbit's radius (measured
/// 8.8e-11: the shooting tolerance), VTK and HDF5 alike; summary.json lists the series.
#[test]
fn the_autonomous_orbit_series_closes_after_one_whirl_period() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("a");
    ok(
        &repo(""),
        &[
            "periodic",
            "scenes/periodic/dry_whip.toml",
            "--autonomous",
            "--set",
            "output.vtk={}",
            "--set",
            "output.hdf5={}",
            "--set",
            "output.png=false",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let s = json(&out.join("summary.json"));
    let a = &s["autonomous"];
    assert_eq!(a["converged"], true, "{a}");
    let series = &s["orbit_series"];
    assert_eq!(series["folder"], "orbit/");
    let (n, t) = (
        series["period_steps"].as_u64().unwrap() as usize,
        a["period_s"].as_f64().unwrap(),
    );
    assert_eq!(n, a["steps_per_period"].as_u64().unwrap() as usize);
    let dir = out.join("orbit");
    let frames = pvd(&dir.join("results.pvd"));
    assert!(frames.len() > 10, "{}", frames.len());
    assert!(
        (frames[0].0 / t - 1.0).abs() < 1e-9,
        "{} against T {t}",
        frames[0].0
    );
    assert!((frames.last().unwrap().0 / t - 2.0).abs() < 1e-9);
    let first = rotor_in_frame(&dir.join(&frames[0].1));
    let last = rotor_in_frame(&dir.join(&frames.last().unwrap().1));
    let mid = rotor_in_frame(&dir.join(&frames[frames.len() / 2].1));
    let size = first[0].hypot(first[1]);
    let closed = rel(&last, &first, size);
    eprintln!(
        "autonomous orbit: last − first frame {closed:.2e} of its radius, {} frames",
        frames.len()
    );
    assert!(closed <= 1e-8, "{closed}");
    // Half a whirl period on, the rotor is across the orbit (a whirl, not a fixed point).
    assert!(rel(&mid, &first, size) > 1.0, "{mid:?} {first:?}");
    #[cfg(feature = "hdf5")]
    {
        let f = crate::common::output::open_h5(&dir.join("results.vtkhdf"));
        let times: Vec<f64> = common::output::read(&f, "time");
        assert_eq!(times.len(), frames.len());
    }
}
