//! Branch switching at period doublings (issue 29, `analysis::switch`, `rubsim continue
//! --switch`): on the paper case the period-1 branch doubles at ν 2.2445; the period-2 orbit
//! switched onto there is the one shot from its own settled run, its doublings are where the
//! independently started period-2 branch has them, and from its first doubling a period-4
//! bubble is found that merges back where the period-2 branch regains stability — the period 4
//! the sweep shows at ν 2.4–2.5 (docs/VALIDATION.md §3, §19.1).

use crate::common::{self, cli};
use rubsim::analysis::branch::{continue_in_speed, Branch};
use rubsim::analysis::continuation::continue_switching;
use rubsim::analysis::switch::Diagram;

const PAPER: &str = "scenes/paper/partial_rub.toml";
const NO_SETS: &[&str] = &[];

fn diagram(range: (f64, f64, f64), max_period: usize) -> Diagram {
    let (ls, m) = common::file_model(&common::repo(PAPER), NO_SETS);
    continue_switching(&m, &common::settings(&ls), range, Some(1), max_period).expect("switch")
}

fn doublings(b: &Branch) -> Vec<f64> {
    b.bifurcations
        .iter()
        .filter(|x| x.kind == "period_doubling")
        .map(|x| x.speed_ratio)
        .collect()
}

/// The cascade from ν 2.0 to 2.6 by 0.1, switched up to period 8.
#[test]
fn switching_follows_the_paper_cases_period_doubling_cascade() {
    let d = diagram((2.0, 2.6, 0.1), 8);
    let periods: Vec<usize> = d.branches.iter().map(|b| b.period).collect();
    eprintln!(
        "periods {periods:?}; switched {:#?}; not switched {:?}",
        d.switched, d.not_switched
    );
    let pd1 = doublings(&d.branches[0]);
    assert_eq!(pd1.len(), 1);
    assert!((pd1[0] - 2.2445).abs() < 2e-3, "{pd1:?}");
    // The period-2 branch: switched from the period-1 doubling on its unstable side.
    let r = &d.switched[0];
    assert_eq!((r.branch, r.parent, d.branches[1].period), (1, 0, 2));
    assert!(r.supercritical && (r.found_at_speed_ratio - 2.3).abs() < 1e-12);
    assert!(r.distance > 1e-2, "{}", r.distance);
    // … the orbit shot from its own settled run at 2.3, and the same branch's doublings.
    let (ls, m) = common::file_model(&common::repo(PAPER), NO_SETS);
    let own =
        continue_in_speed(&m, &common::settings(&ls), &[2.3, 2.4, 2.5, 2.6], Some(2)).unwrap();
    let (a, b) = (&d.branches[1].points[0], &own.points[0]);
    for (x, y) in a.extents_nd.iter().zip(&b.extents_nd) {
        assert!(
            (x - y).abs() < 1e-6,
            "{:?} against {:?}",
            a.extents_nd,
            b.extents_nd
        );
    }
    let (pd2, pd_own) = (doublings(&d.branches[1]), doublings(&own));
    eprintln!("period-2 doublings: switched {pd2:?}, own {pd_own:?}");
    assert_eq!(pd2.len(), pd_own.len());
    for (x, y) in pd2.iter().zip(&pd_own) {
        assert!((x - y).abs() < 5e-3, "{pd2:?} against {pd_own:?}");
    }
    // The period-4 bubble: born at the period-2 branch's first doubling, stable at 2.4 (the
    // sweep's period 4), merging back near its second (where period 2 is stable again).
    let four = d
        .switched
        .iter()
        .find(|r| d.branches[r.branch].period == 4)
        .expect("a period-4 branch");
    let b4 = &d.branches[four.branch];
    assert!((four.at_speed_ratio - pd2[0]).abs() < 1e-12);
    assert!(b4.points[0].stable && (b4.points[0].speed_ratio - 2.4).abs() < 1e-12);
    let end = b4.points.last().unwrap().speed_ratio;
    assert!(
        (end - pd2[1]).abs() < 0.01,
        "ends at {end}, the doubling at {}",
        pd2[1]
    );
    assert!(
        b4.ended
            .as_deref()
            .is_some_and(|w| w.contains("merges back")),
        "{:?}",
        b4.ended
    );
    // Its own doubling to period 8, switched too, and every switched orbit a new one.
    assert!(periods.contains(&8), "{periods:?}");
    assert!(d.switched.iter().all(|r| r.distance > 1e-3));
}

/// The doublings located on the switched branches do not depend on the continuation step:
/// steps 0.1 and 0.05 put each of the first three (periods 1, 2 and 4 losing stability)
/// within 0.005 of each other.
#[test]
fn the_switched_doublings_do_not_depend_on_the_step() {
    let first = |d: &Diagram, period: usize| {
        let b = d.branches.iter().find(|b| b.period == period).unwrap();
        doublings(b)[0]
    };
    let (coarse, fine) = (diagram((2.0, 2.6, 0.1), 4), diagram((2.0, 2.6, 0.05), 4));
    for period in [1, 2, 4] {
        let (a, b) = (first(&coarse, period), first(&fine, period));
        eprintln!("period {period}: doubling at {a:.5} (step 0.1), {b:.5} (0.05)");
        assert!((a - b).abs() < 5e-3, "period {period}: {a} against {b}");
    }
    // Period 8 is above --max-period 4: told, not switched.
    assert!(coarse
        .not_switched
        .iter()
        .any(|w| w.contains("period 8 is above")));
}

/// `rubsim continue --switch` writes branches.csv (every branch's points) and switches.csv
/// besides the first branch's files, and says where each branch came from; a `--max-period`
/// below 2 is refused.
#[test]
fn the_continue_command_switches_and_refuses_what_it_cannot() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("s");
    let o = out.to_str().unwrap();
    let base = [
        "continue", PAPER, "--from", "2.0", "--to", "2.6", "--step", "0.1",
    ];
    let mut args = base.to_vec();
    args.extend(["--period", "1", "--switch", "--max-period", "4", "--out", o]);
    let stdout = cli::ok(&common::repo(""), &args);
    assert!(
        stdout.contains("switched at the period doubling of branch 0 at ω/ωn 2.24"),
        "{stdout}"
    );
    let (head, rows) = cli::csv_table(&out.join("branches.csv"));
    assert_eq!(head.join(","), rubsim::output::branch::BRANCHES_HEADER);
    let periods: std::collections::BTreeSet<&str> = rows.iter().map(|r| r[1].as_str()).collect();
    assert_eq!(periods.into_iter().collect::<Vec<_>>(), ["1", "2", "4"]);
    let (head, rows) = cli::csv_table(&out.join("switches.csv"));
    assert_eq!(head.join(","), rubsim::output::branch::SWITCHES_HEADER);
    assert_eq!(rows.len(), 2);
    for f in [
        "branch.csv",
        "bifurcations.csv",
        "branch.png",
        "branch_multipliers.png",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let s = cli::json(&out.join("summary.json"));
    assert_eq!(s["switched"]["branches"].as_array().unwrap().len(), 3);
    let bad = tmp.path().join("bad");
    let mut a = base.to_vec();
    a.extend([
        "--switch",
        "--max-period",
        "1",
        "--out",
        bad.to_str().unwrap(),
    ]);
    let err = cli::fails(&common::repo(""), &a);
    assert!(err.contains("--max-period"), "{err}");
    assert!(!bad.exists());
}

/// The stable orbits of the branches are the sweep's responses: at every speed of the paper
/// case's sweep (ν 0.5 … 6.0) where a branch of the sweep's period is stable, the sweep's
/// Poincaré points (its long runs from the scene's start) lie on that orbit's section points
/// within 1e-4 |Z0|. `rubsim continue --sweep DIR` draws them under the branches; a sweep of
/// other overrides is refused before anything is written.
#[test]
fn the_stable_branches_are_the_sweeps_responses() {
    let tmp = tempfile::tempdir().unwrap();
    let sw = tmp.path().join("sweep");
    cli::ok(
        &common::repo(""),
        &["sweep", PAPER, "--out", sw.to_str().unwrap()],
    );
    let (ls, m) = common::file_model(&common::repo(PAPER), NO_SETS);
    let dots = rubsim::study::overlay::sweep_poincare(&ls, &m, &sw, 1).unwrap();
    let d = continue_switching(&m, &common::settings(&ls), (0.5, 6.0, 0.1), Some(1), 4).unwrap();
    let mut compared = 0;
    let mut worst: f64 = 0.0;
    for b in &d.branches {
        for p in b.points.iter().filter(|p| p.stable) {
            let at: Vec<f64> = dots
                .iter()
                .filter(|q| (q.0 - p.speed_ratio).abs() < 1e-9)
                .map(|q| q.1)
                .collect();
            // The sweep's response there has this period when its points are the orbit's k.
            let near = |y: f64| {
                p.poincare_nd
                    .iter()
                    .map(|s| (s[1] - y).abs())
                    .fold(f64::INFINITY, f64::min)
            };
            if at.is_empty() || at.iter().any(|&y| near(y) > 1e-2) {
                continue; // another response (a coexisting one, or another period)
            }
            compared += 1;
            worst = at.iter().map(|&y| near(y)).fold(worst, f64::max);
        }
    }
    eprintln!(
        "{compared} stable branch points against the sweep: largest distance {worst:.2e} |Z0|"
    );
    assert!(compared >= 30, "{compared}");
    assert!(worst < 1e-4, "{worst}");
    let out = tmp.path().join("c");
    let args = [
        "continue", PAPER, "--period", "1", "--from", "2.0", "--to", "2.6", "--step", "0.1",
    ];
    let mut a = args.to_vec();
    a.extend([
        "--sweep",
        sw.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    cli::ok(&common::repo(""), &a);
    assert!(cli::is_png(&out.join("branch.png")));
    let bad = tmp.path().join("bad");
    let mut a = args.to_vec();
    a.extend([
        "--set",
        "stator.0.clearance_nd=0.5",
        "--sweep",
        sw.to_str().unwrap(),
        "--out",
        bad.to_str().unwrap(),
    ]);
    let err = cli::fails(&common::repo(""), &a);
    assert!(
        err.contains("--sweep") && err.contains("overrides"),
        "{err}"
    );
    assert!(!bad.exists());
}

/// Switching on a pseudo-arclength branch (`rubsim continue --arclength --switch`): the paper
/// case's period-1 branch from ν 2.0 (first step 0.1, 0.05) doubles at 2.2312 / 2.2318 — within
/// 0.015 of the branch in ν alone's 2.2445 (the arclength branch's one N steps a revolution, the
/// finer of the range's ends, is another map than each speed's own plan) —, the period-2
/// orbit is switched onto half a step past it and continued; its own doubling at 2.3770 /
/// 2.3775 is the period-2 branch in ν alone's 2.3742 within 0.0035. From that doubling the
/// period-4 orbit is switched onto too — at step 0.1 from the period-2 orbit half way to the
/// grid point 2.4372 (from the grid point itself, 0.06 past the doubling, no offset reached
/// it) — and doubles again at 2.4194 / 2.4193, the branch in ν alone's 2.4198 within 2e-3. The
/// command writes the branches (no longer refused); from Python the same.
#[test]
fn switching_works_on_a_pseudo_arclength_branch() {
    let (ls, m) = common::file_model(&common::repo(PAPER), NO_SETS);
    let s = common::settings(&ls);
    let mut firsts = Vec::new();
    for h in [0.1, 0.05] {
        let d = rubsim::analysis::continuation::arclength_switching(
            &m,
            &s,
            (2.0, 2.6, h),
            Some(1),
            (200, 4),
        )
        .expect("arclength switching");
        let periods: Vec<usize> = d.branches.iter().map(|b| b.period).collect();
        let (pd1, pd2) = (doublings(&d.branches[0]), doublings(&d.branches[1]));
        let r = &d.switched[0];
        eprintln!(
            "h {h}: periods {periods:?}, doublings {pd1:?} then {pd2:?}, found at {:.4}",
            r.found_at_speed_ratio
        );
        assert_eq!(periods, [1, 2, 4], "{:?}", d.not_switched);
        assert!((pd1[0] - 2.2445).abs() < 0.015, "{pd1:?}");
        assert!((pd2[0] - 2.3742).abs() < 0.0035, "{pd2:?}");
        let pd4 = doublings(&d.branches[2]);
        eprintln!(
            "h {h}: period 4 found at {:.4}, doublings {pd4:?}",
            d.switched[1].found_at_speed_ratio
        );
        assert!((pd4[0] - 2.4198).abs() < 2e-3, "{pd4:?}");
        assert!(r.supercritical && r.found_at_speed_ratio - pd1[0] <= h + 1e-9);
        assert!(d.branches[1]
            .points
            .iter()
            .all(|p| p.poincare_nd.len() == 2));
        let q = &d.branches[1].points[0].poincare_nd;
        assert!((q[0][0] - q[1][0]).hypot(q[0][1] - q[1][1]) > 1e-2, "{q:?}");
        firsts.push(pd1[0]);
    }
    assert!((firsts[0] - firsts[1]).abs() < 1e-3, "{firsts:?}");
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("a");
    cli::ok(
        &common::repo(""),
        &[
            "continue",
            PAPER,
            "--from",
            "2.0",
            "--to",
            "2.6",
            "--step",
            "0.1",
            "--period",
            "1",
            "--arclength",
            "--switch",
            "--max-period",
            "2",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let (_, rows) = cli::csv_table(&out.join("branches.csv"));
    let periods: std::collections::BTreeSet<&str> = rows.iter().map(|r| r[1].as_str()).collect();
    assert_eq!(periods.into_iter().collect::<Vec<_>>(), ["1", "2"]);
}
