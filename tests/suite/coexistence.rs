//! The check for coexisting responses (`analysis::coexist`, docs/VALIDATION.md §16.2): a
//! companion at the run's scheme and Δt from the other extreme of the contact — the no-contact
//! linear response for a run in full annular rub, full contact at the clearance for any other —
//! settles and is compared with the run. Checked where two responses are known to coexist (the
//! unit rotor in a ring just above its critical speed: no contact and synchronous full annular
//! rub, the latter against its closed form, docs/ORACLES.md §2; the paper case at ν = 5.8:
//! period-3 and period-2 partial rubs; `segmented_casing_beams` at ν = 1.8), where the response
//! is unique (the paper case at ν = 1.7), and from the command line (summary.json, sweep.csv,
//! the warning, the opt-out and a bad value).

use crate::common;

use common::oracles::radial_annular_rub;
use common::scenes::{unit_ring, unit_rotor};
use common::{cli, read, repo, run_speed, NO_SETS};
use rubsim::analysis::{SpeedResults, Start};
use tempfile::TempDir;

/// Unit rotor (m = 1 kg, k = 1 N/m, e = 1e-3 m), ξ = 0.2, μ = 0.1, in a ring of κ = 25 with the
/// radially elastic contact law at δ = 1.5 e; ν = 1.8, above the critical speed, where the
/// linear orbit |Z0| = 1.377 e fits inside the clearance and a full annular rub of radius
/// 1.762 e exists too.
const XI: f64 = 0.2;
const KAPPA: f64 = 25.0;
const MU: f64 = 0.1;
const D: f64 = 1.5;
const E: f64 = 1e-3;
const NU: f64 = 1.8;

fn ring_scene() -> String {
    unit_rotor(XI, &unit_ring(D * E))
}

/// The largest |extent| of a result, in units of e.
fn radius_over_e(extents_nd: &[f64; 4], z0: f64) -> f64 {
    extents_nd.iter().fold(0.0_f64, |m, v| m.max(v.abs())) * z0 / E
}

/// The sampled extents of a circle at 64 samples per revolution read up to 1 − cos(π/64) =
/// 1.2e-3 below its radius.
const SAMPLING: f64 = 2e-3;

fn coexistence(r: &SpeedResults) -> rubsim::analysis::Coexistence {
    r.coexistence
        .clone()
        .unwrap_or_else(|| panic!("ν = {}: the check was not run", r.speed_ratio))
}

#[test]
fn full_annular_rub_from_rest_coexists_with_the_no_contact_orbit() {
    let r = run_speed(&ring_scene(), NO_SETS, NU);
    let (full, _) = radial_annular_rub(NU, KAPPA, MU, XI, D);
    let radius = radius_over_e(&r.extents_nd, r.z0);
    println!(
        "run: contact {:.3}, radius {radius:.5} e (closed form {full:.5} e); {:?}",
        r.contact_fraction, r.coexistence
    );
    assert!(r.contact_fraction >= 0.99, "{}", r.contact_fraction);
    assert!(
        (radius / full - 1.0).abs() <= SAMPLING,
        "full annular rub radius {radius} e against {full} e"
    );
    let c = coexistence(&r);
    assert_eq!(c.start, Start::Free);
    assert!(c.coexisting, "{c:?}");
    assert!(c.steady && c.period == 1, "{c:?}");
    assert_eq!(c.contact_fraction, 0.0);
    // The companion is on the linear orbit, |Z0| = 1.377 e.
    let linear = radius_over_e(&c.extents_nd, r.z0) * E / r.z0;
    assert!((linear - 1.0).abs() <= SAMPLING, "{linear} |Z0|");
    assert!(c.extents_rel > 0.2, "{c:?}");
}

#[test]
fn no_contact_orbit_started_on_the_linear_response_coexists_with_full_annular_rub() {
    // X = e ν² / (1 − ν² + 2iξν): u = Re X, v = Re(iωX) at t = 0 (ω = ν rad/s).
    let den = (1.0 - NU * NU, 2.0 * XI * NU);
    let m = den.0 * den.0 + den.1 * den.1;
    let x = (E * NU * NU * den.0 / m, -E * NU * NU * den.1 / m);
    let sets = [
        format!("run.initial_displacement=[{:e},{:e}]", x.0, x.1),
        format!("run.initial_velocity=[{:e},{:e}]", -NU * x.1, NU * x.0),
    ];
    let r = run_speed(&ring_scene(), &sets, NU);
    let c = coexistence(&r);
    let (full, _) = radial_annular_rub(NU, KAPPA, MU, XI, D);
    let radius = radius_over_e(&c.extents_nd, r.z0);
    println!(
        "run: contact {:.3}; companion from full contact: {c:?}, radius {radius:.5} e (closed form {full:.5} e)",
        r.contact_fraction
    );
    assert_eq!(r.contact_fraction, 0.0);
    assert_eq!(c.start, Start::FullContact);
    assert!(c.coexisting, "{c:?}");
    assert!(c.contact_fraction >= 0.99, "{c:?}");
    assert!(
        (radius / full - 1.0).abs() <= SAMPLING,
        "the companion's full annular rub radius {radius} e against {full} e"
    );
}

fn paper(nu: f64) -> SpeedResults {
    run_speed(
        &read(&repo("scenes/paper/partial_rub.toml")),
        &["run.error_estimate=false"],
        nu,
    )
}

/// With the error estimate on, the run keeps its end state and the companion stops once its
/// state joins it (`coexist::JOIN_FRACTION`): at ν 1.7 the same verdict as the companion
/// integrated whole, in a fraction of its steps; at ν 5.8, where the companion settles on
/// another response, it never joins and the speed is still flagged.
#[test]
fn a_companion_that_joins_the_run_stops_there_with_the_same_verdict() {
    let scene = read(&repo("scenes/paper/partial_rub.toml"));
    let whole = coexistence(&paper(1.7));
    let r = run_speed(&scene, NO_SETS, 1.7);
    let c = coexistence(&r);
    println!("ν 1.7 joined: {c:?}\nwhole: {whole:?}");
    assert!(c.joined && !whole.joined, "{c:?}");
    assert!(!c.coexisting && !whole.coexisting);
    assert!(c.extents_rel <= 0.01 * 1e-3, "joined within 1e-5: {c:?}");
    assert!(
        whole.extents_rel < 1e-6,
        "the whole companion lands on the run's response"
    );
    assert!(
        2 * c.steps < whole.steps,
        "joined after {} steps, the whole companion took {}",
        c.steps,
        whole.steps
    );
    let flagged = coexistence(&run_speed(&scene, NO_SETS, 5.8));
    assert!(flagged.coexisting && !flagged.joined, "{flagged:?}");
}

#[test]
fn a_unique_partial_rub_is_not_flagged() {
    // The paper case at ν = 1.7: a periodic partial rub that the full-contact start reaches too.
    let r = paper(1.7);
    let c = coexistence(&r);
    println!("ν 1.7: contact {:.4}; {c:?}", r.contact_fraction);
    assert!(r.contact_fraction > 0.0 && r.contact_fraction < 0.5);
    assert_eq!(c.start, Start::FullContact);
    assert!(!c.coexisting, "{c:?}");
    assert_eq!(c.period, r.period);
    assert!(
        (c.contact_fraction - r.contact_fraction).abs() < 1e-3,
        "{c:?}"
    );
    assert!(c.extents_rel < 1e-6, "{c:?}");
}

#[test]
fn the_paper_case_at_5_8_has_coexisting_partial_rubs_of_periods_3_and_2() {
    // From rest a period-3 partial rub (the paper's ⅓× range); from full contact a period-2
    // one, steady to 1e-10 of its size (it stays there over 600 transient revolutions:
    // docs/VALIDATION.md §16.2).
    let r = paper(5.8);
    let c = coexistence(&r);
    println!(
        "ν 5.8: period {}, contact {:.4}; {c:?}",
        r.period, r.contact_fraction
    );
    assert_eq!(r.period, 3);
    assert!(c.coexisting && c.steady, "{c:?}");
    assert_eq!(c.period, 2);
    assert!(c.extents_rel > 0.1, "{c:?}");
}

#[test]
fn segmented_casing_beams_at_1_8_is_flagged_from_the_command_line() {
    if !common::meshes::gmsh_wanted() {
        return;
    }
    let tmp = TempDir::new().unwrap();
    let out = tmp.path().join("r");
    let o = cli::rubsim(
        &repo(""),
        &[
            "run",
            "scenes/stators/segmented_casing_beams.toml",
            "--speed",
            "1.8",
            "--set",
            "output.png=false",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let err = cli::text(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("warning: ω/ωn = 1.800: the response depends on the start"),
        "{err}"
    );
    let s = cli::json(&out.join("summary.json"));
    assert_eq!(s["coexisting"], true);
    let res = &s["result"];
    let c = &res["coexistence"];
    println!("run contact {}, companion {c}", res["contact_fraction"]);
    // From rest: full annular rub; from the linear orbit (|Z0| = 0.94 δ): no contact.
    assert!(res["contact_fraction"].as_f64().unwrap() >= 0.99);
    assert_eq!(c["start"], "free");
    assert!(c["contact_fraction"].as_f64().unwrap() <= 0.01);
    assert!(c["extents_rel"].as_f64().unwrap() > 0.01);
    // The time-step estimate is kept as it is, beside the branch difference.
    assert!(res["error"]["extents_rel"].as_f64().unwrap() < 1e-3);
}

#[test]
fn sweep_csv_marks_the_speed_and_the_check_can_be_turned_off() {
    let tmp = TempDir::new().unwrap();
    let sweep = |name: &str, extra: &[&str]| {
        let out = tmp.path().join(name);
        let mut args = vec![
            "sweep",
            "scenes/paper/partial_rub.toml",
            "--set",
            "run.sweep.from=5.7",
            "--set",
            "run.sweep.to=5.8",
            "--set",
            "output.png=false",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = cli::rubsim(&repo(""), &args);
        let err = cli::text(&o.stderr);
        assert!(o.status.success(), "{err}");
        let text = read(&out.join("sweep.csv"));
        let mut lines = text.lines();
        let cols: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
        let at = |c: &str| cols.iter().position(|x| x == c).unwrap();
        let rows: Vec<(String, String, String, String)> = lines
            .map(|l| {
                let r: Vec<&str> = l.split(',').collect();
                (
                    r[at("speed_ratio")].into(),
                    r[at("coexisting")].into(),
                    r[at("coexist_start")].into(),
                    r[at("coexist_period")].into(),
                )
            })
            .collect();
        (rows, err)
    };
    let (rows, err) = sweep("on", &[]);
    println!("{rows:?}");
    assert_eq!(rows.len(), 2);
    assert_eq!(rows[1].0, "5.8000");
    assert_eq!(
        (rows[1].1.as_str(), rows[1].2.as_str(), rows[1].3.as_str()),
        ("true", "full_contact", "2")
    );
    assert_eq!(rows[0].1, "false");
    assert!(
        err.contains("the response depends on the start at 1 of 2 speeds (ω/ωn 5.80)"),
        "{err}"
    );
    let (rows, err) = sweep("off", &["--set", "run.check_coexistence=false"]);
    assert!(
        rows.iter().all(|r| r.1.is_empty() && r.2.is_empty()),
        "{rows:?}"
    );
    assert!(!err.contains("depends on the start"), "{err}");
    let bad = cli::fails(
        &repo(""),
        &[
            "run",
            "scenes/paper/partial_rub.toml",
            "--speed",
            "1.7",
            "--set",
            "run.check_coexistence=1",
        ],
    );
    assert!(bad.contains("run.check_coexistence"), "{bad}");
}

/// A companion that fails is reported, not dropped: the meshed arc `fe_arc.toml` at ν 1.7 from
/// full contact at the clearance puts 76 pairs with friction into the collocated scheme's
/// contact problem, whose matrix is not a P-matrix there, and principal pivoting gives up at
/// step 234. The run stands; its result says the check could not answer (`coexistence_failed`,
/// naming the speed, the start and the error), and `rubsim run` warns of it.
#[test]
#[ignore = "slow tier: the failing contact solve pivots 1.2·10⁵ times (about 5 s)"]
fn a_failed_companion_is_reported_with_its_error() {
    let tmp = TempDir::new().unwrap();
    let dir = tmp.path().join("out");
    let out = cli::rubsim(
        &repo(""),
        &[
            "run",
            common::data("fe_arc.toml").to_str().unwrap(),
            "--set",
            "run.revolutions=14",
            "--set",
            "run.transient_revolutions=10",
            "--set",
            "run.max_transient_revolutions=10",
            "--out",
            dir.to_str().unwrap(),
        ],
    );
    let err = cli::text(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(
        err.contains("warning: ω/ωn = 1.700: the coexistence check's companion from the full_contact start failed (contact solve failed"),
        "{err}"
    );
    let s = cli::json(&dir.join("summary.json"));
    let why = s["result"]["coexistence_failed"]
        .as_str()
        .unwrap_or_default();
    assert!(why.contains("principal pivoting did not converge"), "{s}");
    assert!(s["result"]["coexistence"].is_null(), "{s}");
    assert!(s.get("coexisting").is_none(), "{s}");
}

/// The ring of `scenes/periodic/ring_hysteresis.toml` swept with the coexistence check (ν 1.8 –
/// 3.0, explicit scheme): every speed is flagged — the run started on the rub stays in full
/// annular rub, the companion from the no-contact orbit stays free. `rubsim continue --sweep`
/// gives the flagged speeds their branches: the run's response lies on the continued branch
/// (the rub), the companion's on none, so the first flagged speed adds its branch — the free
/// orbit, continued over the range — and every later one finds both responses on the two
/// branches. The free branch is the linear orbit (extents within 2e-3 of |Z0|: measured 1.1e-3,
/// the explicit scheme's step error), stable, without contact; the rub branch's radius at ν 2.8
/// is the closed form's 2.40026 e (ORACLES §2: measured 2.4001 e). With `--arclength` the rub's
/// pseudo-arclength points lie between the grid's speeds and the responses are matched on its
/// interpolated section: still two branches, none drawn twice; in two segments
/// (`--segments 2`) the joined rub and the free orbit: the same two, and the same again from
/// two shards merged with `rubsim merge --sweep`.
#[test]
fn flagged_speeds_get_the_branches_of_both_responses() {
    let tmp = tempfile::tempdir().unwrap();
    let ring = common::repo("scenes/periodic/ring_hysteresis.toml");
    let ring = ring.to_str().unwrap();
    let sets = [
        "--set",
        "run.check_coexistence=true",
        "--set",
        "run.integrator=collocated",
        "--set",
        "run.sweep.to=3.0",
    ];
    let sw = tmp.path().join("sweep");
    let mut a = vec!["sweep", ring];
    a.extend(sets);
    a.extend(["--out", sw.to_str().unwrap()]);
    common::cli::ok(tmp.path(), &a);
    let none: &[&str] = &[];
    for (name, extra) in [
        ("c", none),
        ("arc", &["--arclength"][..]),
        ("seg", &["--segments", "2"][..]),
    ] {
        let out = tmp.path().join(name);
        let mut a = vec!["continue", ring, "--period", "1"];
        a.extend(sets);
        a.extend(extra);
        a.extend([
            "--sweep",
            sw.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        let printed = common::cli::ok(tmp.path(), &a);
        assert!(
            printed.contains("coexisting responses at ω/ωn 1.8"),
            "{printed}"
        );
        let (h, rows) = common::cli::csv_table(&out.join("branches.csv"));
        let col = |n: &str| h.iter().position(|c| c == n).unwrap();
        let (b, cf, st, xm, nu) = (
            col("branch"),
            col("contact_fraction"),
            col("stable"),
            col("x_max_nd"),
            col("speed_ratio"),
        );
        let num = |r: &Vec<String>, i: usize| r[i].parse::<f64>().unwrap();
        assert!(
            rows.iter().all(|r| r[b] == "0" || r[b] == "1"),
            "{name}: {rows:?}"
        );
        let free: Vec<_> = rows.iter().filter(|r| r[b] == "1").collect();
        assert_eq!(free.len(), 13, "{name}");
        for r in &free {
            assert_eq!(num(r, cf), 0.0);
            assert_eq!(r[st], "true");
            assert!((num(r, xm) - 1.0).abs() < 2e-3, "{name}: {r:?}");
        }
        assert!(rows
            .iter()
            .filter(|r| r[b] == "0")
            .all(|r| num(r, cf) == 1.0));
        if extra.is_empty() {
            let rub = rows.iter().find(|r| r[b] == "0" && r[nu] == "2.8").unwrap();
            let nu2 = 2.8_f64 * 2.8;
            let z0 = nu2 / ((1.0 - nu2).powi(2) + (2.0 * XI * 2.8).powi(2)).sqrt();
            let radius = num(rub, xm) * z0;
            let (full, _) = radial_annular_rub(2.8, KAPPA, MU, XI, D);
            eprintln!("rub radius at ν 2.8: {radius:.5} e (closed form {full:.5} e)");
            assert!(
                (radius / full - 1.0).abs() < 1e-3,
                "{radius} against {full}"
            );
        }
        let s = common::cli::json(&out.join("summary.json"));
        let recs = s["coexisting"].as_array().unwrap();
        assert!(recs.len() >= 10, "{name}: {recs:?}");
        assert_eq!(recs[0]["new_branches"], serde_json::json!([1]), "{name}");
        assert!(recs[1..]
            .iter()
            .all(|r| r["new_branches"] == serde_json::json!([])));
        assert!(recs.iter().all(|r| r["on_branch"]
            .as_array()
            .unwrap()
            .iter()
            .all(|x| !x.is_null())));
    }
    // The same two segments as two shards, merged with the sweep: the files of the unsharded
    // run with `--sweep` (branches.csv byte for byte, the same coexisting records); a shard
    // given `--sweep` is told to give it to the merge.
    let m = tmp.path().join("merged");
    for shard in ["1/2", "2/2"] {
        let mut a = vec!["continue", ring, "--period", "1"];
        a.extend(sets);
        a.extend([
            "--segments",
            "2",
            "--shard",
            shard,
            "--out",
            m.to_str().unwrap(),
        ]);
        common::cli::ok(tmp.path(), &a);
    }
    let mut a = vec!["continue", ring, "--period", "1"];
    a.extend(sets);
    a.extend([
        "--segments",
        "2",
        "--shard",
        "1/2",
        "--sweep",
        sw.to_str().unwrap(),
    ]);
    let x = tmp.path().join("x");
    a.extend(["--out", x.to_str().unwrap()]);
    let err = common::cli::fails(tmp.path(), &a);
    assert!(err.contains("rubsim merge") && !x.exists(), "{err}");
    let printed = common::cli::ok(
        tmp.path(),
        &[
            "merge",
            m.to_str().unwrap(),
            "--sweep",
            sw.to_str().unwrap(),
        ],
    );
    assert!(
        printed.contains("coexisting responses at ω/ωn 1.8"),
        "{printed}"
    );
    let read = |d: &str, f: &str| std::fs::read_to_string(tmp.path().join(d).join(f)).unwrap();
    assert_eq!(read("merged", "branches.csv"), read("seg", "branches.csv"));
    let json = |d: &str| common::cli::json(&tmp.path().join(d).join("summary.json"));
    assert_eq!(json("merged")["coexisting"], json("seg")["coexisting"]);
    // A sweep's own shards take no --sweep.
    let err = common::cli::fails(
        tmp.path(),
        &[
            "merge",
            sw.to_str().unwrap(),
            "--sweep",
            sw.to_str().unwrap(),
        ],
    );
    assert!(err.contains("not a continuation"), "{err}");
}
