//! Periodic orbits by shooting (`analysis::periodic`, `rubsim periodic`): the Floquet
//! multipliers of a free Jeffcott rotor against the central-difference propagator in closed
//! form (to round-off) and against exp(λT) (order 2 in Δt), the paper case's period-1 orbit
//! equal to the long run's and losing stability through ρ = −1 where the sweep's period
//! doubling is (ν 2.2 → 2.3), and the command's outputs, its report where no orbit of the
//! period exists, and its refusals.

use crate::common;
use common::{cli, repo, set_distance};
use rubsim::analysis::{self, periodic, Keep};

const PAPER: &str = "scenes/paper/partial_rub.toml";
/// The paper rotor's damping ratio (scene `rotor.damping_ratio`).
const XI: f64 = 0.2;

/// The period-`k` orbit of the paper scene at ν with overrides.
fn shoot(nu: f64, k: Option<usize>, sets: &[&str]) -> periodic::PeriodicOrbit {
    let (ls, m) = common::file_model(&repo(PAPER), sets);
    let prep = analysis::prepare(&m, &common::settings(&ls).request(nu)).expect("prepare");
    periodic::shoot(&prep, k).expect("shoot")
}

/// (re, im) of a complex power `z^n`.
fn cpow(z: [f64; 2], n: f64) -> [f64; 2] {
    let (r, a) = (z[0].hypot(z[1]), z[1].atan2(z[0]));
    let rn = r.powf(n);
    [rn * (n * a).cos(), rn * (n * a).sin()]
}

/// No contact (clearance 50 |Z0|): the map is linear, x and y uncoupled, each with the
/// central-difference step `z² (1 + a) + z (ω_n² Δt² − 2) + (1 − a) = 0`, `a = ξ ω_n Δt`; the
/// multipliers of one revolution of N steps are `z^N` and its conjugate, twice. Shooting's
/// central-difference monodromy gives them to 1e-8 (the map's round-off over h).
#[test]
fn free_rotor_multipliers_are_the_central_difference_propagators() {
    let o = shoot(1.7, Some(1), &["stator.0.clearance_nd=50"]);
    assert!(o.converged && o.stable, "{o:?}");
    assert_eq!(o.orbit.contact_fraction, 0.0);
    let (ls, m) = common::file_model(&repo(PAPER), NO_SETS);
    let _ = ls;
    let wn = m.rotor.natural_frequency();
    let (dt, n) = (o.orbit.plan.dt, o.orbit.plan.steps_per_rev as f64);
    let a = XI * wn * dt;
    let (qa, qb, qc) = (1.0 + a, wn * wn * dt * dt - 2.0, 1.0 - a);
    let disc = qb * qb - 4.0 * qa * qc;
    assert!(disc < 0.0, "an underdamped step has complex roots");
    let z = [-qb / (2.0 * qa), (-disc).sqrt() / (2.0 * qa)];
    let zn = cpow(z, n);
    let expected = [zn, [zn[0], -zn[1]], zn, [zn[0], -zn[1]]];
    let d = set_distance(&o.multipliers, &expected);
    eprintln!(
        "Δt = {dt:e} s, N = {n}: |ρ − z^N| ≤ {d:.2e}, |ρ| = {:.6}",
        o.largest_modulus
    );
    assert!(
        d < 1e-8,
        "multipliers {:?} against {expected:?}: {d:e}",
        o.multipliers
    );
}

/// The same multipliers against the continuous flow's `exp(λ T)`, λ = −ξ ω_n ± i ω_n √(1 − ξ²):
/// the error falls as Δt², a fitted order within 0.1 of 2 over Δt = T/256 and T/512.
#[test]
fn free_rotor_multipliers_converge_to_exp_lambda_t_at_order_two() {
    let (_, m) = common::file_model(&repo(PAPER), NO_SETS);
    let wn = m.rotor.natural_frequency();
    let omega = 1.7 * wn;
    let period = 2.0 * std::f64::consts::PI / omega;
    let err = |per_rev: usize| {
        let dt = format!("run.dt={:e}", period / per_rev as f64);
        let o = shoot(
            1.7,
            Some(1),
            &[
                "stator.0.clearance_nd=50",
                "run.auto_step=false",
                dt.as_str(),
            ],
        );
        assert_eq!(o.orbit.plan.steps_per_rev, per_rev);
        let t = o.orbit.plan.dt * per_rev as f64;
        let (re, im) = (-XI * wn * t, wn * (1.0 - XI * XI).sqrt() * t);
        let e = [re.exp() * im.cos(), re.exp() * im.sin()];
        let expected = [e, [e[0], -e[1]], e, [e[0], -e[1]]];
        set_distance(&o.multipliers, &expected)
    };
    let (e1, e2) = (err(256), err(512));
    let order = (e1 / e2).log2();
    eprintln!("|ρ − exp(λT)|: {e1:.3e} (T/256), {e2:.3e} (T/512), order {order:.3}");
    assert!((order - 2.0).abs() < 0.1, "order {order}");
}

/// The paper case (δ 0.6 |Z0|, ε 25, μ 0.1): at ν 1.7 the shot period-1 orbit is the long run's
/// (extents to 1e-6 of |Z0|, the same discrete orbit) and stable; the period-1 orbit is stable
/// at ν 2.1 and unstable at 2.3 through a real multiplier below −1 — the period doubling the
/// sweep shows between 2.2 (1×) and 2.3 (½×).
#[test]
fn the_paper_case_period_one_orbit_doubles_where_the_sweep_does() {
    let o = shoot(1.7, None, NO_SETS);
    assert!(o.converged && o.stable && o.period == 1, "{o:?}");
    assert!(o.orbit.contact_fraction > 0.1);
    let (ls, m) = common::file_model(&repo(PAPER), NO_SETS);
    let run =
        analysis::run_speed(&m, &common::settings(&ls).request(1.7), Keep::default()).expect("run");
    for (a, b) in o.orbit.extents_nd.iter().zip(&run.extents_nd) {
        assert!(
            (a - b).abs() < 1e-6,
            "{:?} against {:?}",
            o.orbit.extents_nd,
            run.extents_nd
        );
    }
    let stable = shoot(2.1, Some(1), NO_SETS);
    assert!(stable.converged && stable.stable, "{stable:?}");
    let pd = shoot(2.3, Some(1), NO_SETS);
    assert!(pd.converged && !pd.stable, "{pd:?}");
    assert_eq!(pd.instability, Some("period_doubling"));
    let r = pd.multipliers[0];
    assert!(r[0] < -1.0 && r[1] == 0.0, "{:?}", pd.multipliers);
    eprintln!(
        "ν 2.1: |ρ|max {:.4}; ν 2.3: ρ1 = {:.4} ({} Newton iterations from the settled ½× state)",
        stable.largest_modulus, r[0], pd.iterations
    );
}

/// `rubsim periodic`: summary.json (`periodic`: period, convergence, multipliers, stability,
/// how the monodromy was taken) and multipliers.csv; a period of 0 and an implicit scheme are refused, nothing written.
#[test]
fn the_periodic_command_writes_its_multipliers_and_refuses_what_it_cannot_shoot() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("p");
    let o = cli::rubsim(
        &repo(""),
        &[
            "periodic",
            PAPER,
            "--speed",
            "2.3",
            "--period",
            "1",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", cli::text(&o.stderr));
    assert!(cli::text(&o.stdout).contains("unstable (period_doubling)"));
    assert!(cli::text(&o.stdout).contains("monodromy: variational ("));
    let s = cli::json(&out.join("summary.json"));
    assert_eq!(s["command"], "periodic");
    assert_eq!(s["periodic"]["period"], 1);
    assert_eq!(s["periodic"]["stable"], false);
    assert_eq!(s["periodic"]["monodromy"], "variational");
    assert!(
        s["periodic"]["linearisation"]["contact_steps"]
            .as_u64()
            .unwrap()
            > 0
    );
    assert!(out.join("multipliers.png").metadata().unwrap().len() > 10_000);
    let csv = std::fs::read_to_string(out.join("multipliers.csv")).unwrap();
    assert!(csv.starts_with("index,re,im,modulus,angle_deg\n"));
    assert_eq!(csv.lines().count(), 5);
    // Where the response has no orbit of the period asked (ν 2.45 settles on period 4): a
    // report that Newton did not converge, not a Newton that runs on.
    let none = tmp.path().join("none");
    let o = cli::rubsim(
        &repo(""),
        &[
            "periodic",
            PAPER,
            "--speed",
            "2.45",
            "--period",
            "3",
            "--out",
            none.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", cli::text(&o.stderr));
    assert!(
        cli::text(&o.stderr).contains("shooting did not find a periodic orbit of 3 revolution(s)"),
        "{}",
        cli::text(&o.stderr)
    );
    let s = cli::json(&none.join("summary.json"));
    assert_eq!(s["periodic"]["converged"], false);
    assert!(s["periodic"]["iterations"].as_u64().unwrap() <= periodic::MAX_NEWTON as u64);
    let bad = tmp.path().join("bad");
    let err = cli::fails(
        &repo(""),
        &[
            "periodic",
            PAPER,
            "--speed",
            "2.3",
            "--period",
            "0",
            "--out",
            bad.to_str().unwrap(),
        ],
    );
    assert!(err.contains("--period"), "{err}");
    assert!(!bad.exists());
    let err = cli::fails(
        &repo(""),
        &[
            "periodic",
            PAPER,
            "--speed",
            "1.7",
            "--set",
            "run.integrator=newmark",
            "--out",
            bad.to_str().unwrap(),
        ],
    );
    assert!(
        err.contains("run.integrator") && err.contains("implicit"),
        "{err}"
    );
}

const NO_SETS: &[&str] = &[];

/// The branch of period `k` of the paper case over `speeds` (ν), with the scene's settings.
fn branch(k: usize, speeds: &[f64]) -> rubsim::analysis::branch::Branch {
    let (ls, m) = common::file_model(&repo(PAPER), NO_SETS);
    rubsim::analysis::branch::continue_in_speed(&m, &common::settings(&ls), speeds, Some(k))
        .expect("continue")
}

/// ν from `a` to `b` by 0.1 (either way).
fn speeds(a: f64, b: f64) -> Vec<f64> {
    let n = ((b - a).abs() / 0.1).round() as usize;
    (0..=n)
        .map(|i| a + (b - a).signum() * 0.1 * i as f64)
        .collect()
}

/// Continued in speed, the paper case's orbits change stability where its sweep changes
/// regime (docs/VALIDATION.md §3: 1× to 2.2, period 4 at 2.4–2.5, ½× 2.3 and 2.6–4.1, ⅓× 4.2
/// on): the period-1 branch doubles between 2.2 and 2.3; the period-2 branch loses stability
/// between 2.3 and 2.4, regains it between 2.5 and 2.6, and doubles again between 4.1 and 4.2;
/// each located to 1/64 of the step, the multiplier real and on either side of −1.
#[test]
fn the_paper_case_branches_change_stability_where_its_sweep_changes_regime() {
    let b1 = branch(1, &speeds(1.5, 2.6));
    assert!(b1.ended.is_none(), "{:?}", b1.ended);
    assert_eq!(b1.points.len(), 12);
    assert_eq!(b1.bifurcations.len(), 1, "{:?}", b1.bifurcations);
    let b2 = branch(2, &speeds(2.3, 4.3));
    assert!(b2.ended.is_none(), "{:?}", b2.ended);
    let found: Vec<f64> = b1
        .bifurcations
        .iter()
        .chain(&b2.bifurcations)
        .map(|b| {
            assert_eq!(b.kind, "period_doubling");
            assert!(b.between[1] - b.between[0] <= 0.1 / 64.0 + 1e-12, "{b:?}");
            let (s, u) = (b.rho[0], b.rho[1]);
            assert!(
                s[1] == 0.0 && u[1] == 0.0 && s[0] > -1.0 && u[0] < -1.0,
                "{b:?}"
            );
            b.speed_ratio
        })
        .collect();
    eprintln!("period doublings at ν {found:?}");
    let sweep_changes = [(2.2, 2.3), (2.3, 2.4), (2.5, 2.6), (4.1, 4.2)];
    assert_eq!(found.len(), sweep_changes.len(), "{found:?}");
    for (v, (a, b)) in found.iter().zip(sweep_changes) {
        assert!(
            *v > a && *v < b,
            "a period doubling at {v} outside ({a}, {b})"
        );
    }
}

/// The coexistence the sweep's check flags at ν 4.10 (a companion from full contact settles
/// on another response) appears as two stable branches there: period 2 continued up from 2.6
/// and period 3 continued down from 5.8.
#[test]
fn coexisting_responses_are_two_stable_branches() {
    let up = branch(2, &speeds(2.6, 4.1));
    let down = branch(3, &speeds(5.8, 4.1));
    for b in [&up, &down] {
        assert!(b.ended.is_none(), "{:?}", b.ended);
        let last = b.points.last().unwrap();
        assert!(
            (last.speed_ratio - 4.1).abs() < 1e-9 && last.stable,
            "{last:?}"
        );
    }
    let (a, b) = (up.points.last().unwrap(), down.points.last().unwrap());
    assert!(
        (a.contact_fraction - b.contact_fraction).abs() > 0.01,
        "{} against {}",
        a.contact_fraction,
        b.contact_fraction
    );
}

/// `rubsim continue`: branch.csv, bifurcations.csv, branch.png and summary.json; a speed
/// step that is not positive is refused, nothing written.
#[test]
fn the_continue_command_writes_the_branch_and_refuses_a_bad_step() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("c");
    let stdout = cli::ok(
        &repo(""),
        &[
            "continue",
            PAPER,
            "--from",
            "1.5",
            "--to",
            "2.6",
            "--step",
            "0.1",
            "--period",
            "1",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(stdout.contains("period_doubling at ω/ωn 2.24"), "{stdout}");
    let csv = std::fs::read_to_string(out.join("branch.csv")).unwrap();
    assert!(csv.starts_with(rubsim::output::branch::BRANCH_HEADER));
    assert_eq!(csv.lines().count(), 13);
    let bif = std::fs::read_to_string(out.join("bifurcations.csv")).unwrap();
    assert_eq!(bif.lines().count(), 2);
    assert!(out.join("branch.png").metadata().unwrap().len() > 10_000);
    assert!(out.join("branch_multipliers.png").metadata().unwrap().len() > 10_000);
    let s = cli::json(&out.join("summary.json"));
    assert_eq!(s["command"], "continue");
    assert_eq!(s["branch"]["period"], 1);
    let bad = tmp.path().join("bad");
    let err = cli::fails(
        &repo(""),
        &[
            "continue",
            PAPER,
            "--step",
            "0",
            "--out",
            bad.to_str().unwrap(),
        ],
    );
    assert!(err.contains("--step"), "{err}");
    assert!(!bad.exists());
    // Around the fold of the ring scene's full rub by pseudo-arclength.
    let arc = tmp.path().join("arc");
    let stdout = cli::ok(
        &repo(""),
        &[
            "continue",
            "scenes/periodic/ring_hysteresis.toml",
            "--arclength",
            "--period",
            "1",
            "--out",
            arc.to_str().unwrap(),
        ],
    );
    assert!(stdout.contains("fold at ω/ωn 4.545"), "{stdout}");
    let bif = std::fs::read_to_string(arc.join("bifurcations.csv")).unwrap();
    assert!(bif.lines().any(|l| l.starts_with("fold,4.545")), "{bif}");
}

/// Pseudo-arclength around a fold (`rubsim continue --arclength`): the unit rotor in a ring
/// (`scenes/periodic/ring_hysteresis.toml`: κ 25, δ 1.5 e, ξ 0.2, μ 0.1) in synchronous full
/// annular rub, continued up from ν 1.8. The branch turns at a fold and comes back as the
/// unstable smaller orbit: the fold within 1e-3 of the closed form's (docs/ORACLES.md §2: the
/// double root of the whirl radius, ν 4.545144), every point's radius within 5e-3 of the
/// closed form's larger root before the fold and its smaller root after, and the rub losing
/// stability to a torus (a complex pair, Neimark–Sacker) between ν 3.0 and 3.3 — a long run
/// from the rub at 3.5 reads quasi-periodic.
#[test]
fn arclength_follows_the_full_rub_around_its_fold() {
    let (ls, m) = common::file_model(&repo("scenes/periodic/ring_hysteresis.toml"), NO_SETS);
    let b = rubsim::analysis::arclength::continue_arclength(
        &m,
        &common::settings(&ls),
        (1.8, 4.8, 0.1),
        Some(1),
        200,
    )
    .expect("continue");
    assert!(b.ended.is_none(), "{:?}", b.ended);
    let folds: Vec<_> = b.bifurcations.iter().filter(|x| x.kind == "fold").collect();
    assert_eq!(folds.len(), 1, "{:?}", b.bifurcations);
    let (k, mu, xi, d) = (25.0, 0.1, 0.2, 1.5);
    // The closed form's fold: where the quadratic in r has a double root.
    let disc = |nu: f64| {
        let (qa, qb, qc) = common::oracles::radial_annular_rub_quadratic(nu, k, mu, xi, d);
        (qb * qb - 4.0 * qa * qc, qa, qb)
    };
    let (mut lo, mut hi) = (4.0, 5.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if disc(mid).0 > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let fold = folds[0].speed_ratio;
    eprintln!("fold at ν {fold:.6} against {lo:.6}");
    assert!((fold - lo).abs() < 1e-3, "fold at {fold}, closed form {lo}");
    // Radii along the branch: the larger root up to the fold, the smaller after it.
    let mut past = false;
    let mut worst = 0.0_f64;
    for w in b.points.windows(2) {
        past |= w[1].speed_ratio < w[0].speed_ratio;
        let p = &w[1];
        let nu = p.speed_ratio;
        let z0 = nu * nu / ((1.0 - nu * nu).powi(2) + (2.0 * xi * nu).powi(2)).sqrt();
        let r = p.extents_nd[1] * z0;
        let (dd, qa, qb) = disc(nu);
        if dd < 0.0 {
            continue; // the last points around the fold's vertex
        }
        let root = (-qb + if past { -1.0 } else { 1.0 } * dd.sqrt()) / (2.0 * qa);
        if root <= d {
            continue;
        }
        worst = worst.max((r / root - 1.0).abs());
    }
    eprintln!("radius against the closed form: {worst:.2e} at most");
    assert!(worst < 5e-3, "radius off by {worst}");
    let ns: Vec<_> = b
        .bifurcations
        .iter()
        .filter(|x| x.kind == "neimark_sacker")
        .collect();
    assert!(
        ns.iter()
            .any(|x| x.between[0] >= 3.0 && x.between[1] <= 3.3),
        "{:?}",
        b.bifurcations
    );
    assert!(b.points.first().unwrap().stable);
    assert!(b.points.last().unwrap().speed_ratio < 1.8);
}

/// The FE paper rotor (`scenes/fe/paper_rotor_rub.toml`, reduced with the cut-off the tolerance
/// chooses — pinned at the branch's top speed so that one modal basis serves every point)
/// continued from ν 1.5 to 2.6: its period-1 orbit doubles where the Jeffcott rotor's does,
/// 2.2445, within 2e-3 (measured 2.2445 with the cut-off pinned at ν 2.6, 2.2461 at ν 6.0:
/// `rubsim continue … --from 1.5 --to 6.0`, more modes). With the monodromy by differences of
/// whole maps the two rotors' doublings read 2.2258 / 2.2430 against 2.2414, a spread that
/// came from the differences straddling contact events, not from the reduction's truncation
/// (docs/VALIDATION.md §19.7).
#[test]
fn the_fe_paper_rotor_branch_doubles_where_the_jeffcott_does() {
    let (ls, m) = common::file_model(&repo("scenes/fe/paper_rotor_rub.toml"), NO_SETS);
    let sp = speeds(1.5, 2.6);
    let s = rubsim::study::run_settings(&ls, &m, &sp).expect("step choice");
    let b = rubsim::analysis::branch::continue_in_speed(&m, &s, &sp, Some(1)).expect("continue");
    assert!(b.ended.is_none(), "{:?}", b.ended);
    assert_eq!(b.bifurcations.len(), 1, "{:?}", b.bifurcations);
    let pd = &b.bifurcations[0];
    assert_eq!(pd.kind, "period_doubling");
    eprintln!("FE rotor: period doubling at ν {:.4}", pd.speed_ratio);
    assert!((pd.speed_ratio - 2.2445).abs() < 2e-3, "{pd:?}");
}

/// The grazing point of the ring's full rub (`scenes/periodic/ring_hysteresis.toml`: the unit
/// rotor, ξ 0.2, δ 1.5 e): where the free orbit's radius |Z0(ν)| reaches the clearance the rub
/// begins or ends — ν² = x, (1 − δ²) x² + δ² (2 − 4ξ²) x − δ² = 0: ν 0.82780 below the critical
/// speed, the rub's lower end. Continued down from the full rub at ν 1.0 to 0.6 in ν alone and
/// by pseudo-arclength the branch grazes there, located by bisection on contact (to 1/64 of
/// the step in ν alone). (The other root, 1.62069, is where the unstable rub meets the free
/// orbit at a corner of the loop: a natural continuation of the free orbit ends there, and
/// pseudo-arclength does not turn it reliably — not tested.)
#[test]
fn the_ring_rub_grazes_where_the_free_orbit_reaches_the_clearance() {
    let (xi, d) = (0.2_f64, 1.5_f64);
    let (qa, qb, qc) = (1.0 - d * d, d * d * (2.0 - 4.0 * xi * xi), -d * d);
    let disc = (qb * qb - 4.0 * qa * qc).sqrt();
    let lower = ((-qb + disc) / (2.0 * qa))
        .sqrt()
        .min(((-qb - disc) / (2.0 * qa)).sqrt());
    let (ls, m) = common::file_model(&repo("scenes/periodic/ring_hysteresis.toml"), NO_SETS);
    let s = common::settings(&ls);
    let speeds: Vec<f64> = (0..=8).map(|i| 1.0 - 0.05 * i as f64).collect();
    let grazing = |b: &rubsim::analysis::branch::Branch| {
        let g: Vec<_> = b
            .bifurcations
            .iter()
            .filter(|x| x.kind == "grazing")
            .collect();
        assert_eq!(g.len(), 1, "{:?} {:?}", b.bifurcations, b.ended);
        (g[0].parameter, (g[0].between[1] - g[0].between[0]).abs())
    };
    let natural =
        rubsim::analysis::branch::continue_in_speed(&m, &s, &speeds, Some(1)).expect("continue");
    let (at, width) = grazing(&natural);
    eprintln!("grazing in ν alone at {at:.5} (interval {width:.1e}) against {lower:.5}");
    assert!(width <= 0.05 / 64.0 + 1e-12);
    assert!((at - lower).abs() < 1e-3, "{at} against {lower}");
    let arc =
        rubsim::analysis::arclength::continue_arclength(&m, &s, (1.0, 0.6, 0.05), Some(1), 100)
            .expect("continue");
    let (at, width) = grazing(&arc);
    eprintln!("grazing by pseudo-arclength at {at:.5} (interval {width:.1e})");
    assert!(width < 0.01 && (at - lower).abs() < 2e-3, "{at} ({width})");
}

/// A branch of the two-revolution map started on the paper case's period-1 orbit (ν 2.2, its
/// settled run) and continued to 2.3 across the doubling at 2.2445: near the doubling that map
/// has the doubled orbit as a fixed point too, and a bisection midpoint's Newton used to reach
/// it — it then located a "fold" of the doubled orbit at 2.2305, outside the interval where the
/// branch's own multiplier crosses (ρ² through +1 at 2.2445). A midpoint of longer minimal
/// period now ends the location: the interval reported is coarser and holds 2.2445 (measured
/// [2.225, 2.25]), and every point of the branch repeats after one revolution. The crossing is
/// named by the orbit's own one-revolution map: a period doubling, where the two-revolution
/// map's multiplier (ρ², in the file) passes +1.
#[test]
fn a_bisection_does_not_take_the_doubled_orbit_for_the_branch() {
    let (ls, m) = common::file_model(&repo(PAPER), NO_SETS);
    let s = common::settings(&ls);
    let b = rubsim::analysis::branch::continue_in_speed(&m, &s, &[2.2, 2.3], Some(2))
        .expect("continue");
    assert_eq!(b.points.len(), 2, "{:?}", b.ended);
    for p in &b.points {
        let [a, z] = [p.poincare_nd[0], p.poincare_nd[1]];
        assert!(
            (a[0] - z[0]).hypot(a[1] - z[1]) < 1e-6,
            "{:?}",
            p.poincare_nd
        );
    }
    let x = &b.bifurcations[0];
    eprintln!("{} located in [{}, {}]", x.kind, x.between[0], x.between[1]);
    assert_eq!(x.kind, "period_doubling");
    assert!(x.rho[1][0] > 1.0, "{:?}", x.rho);
    assert!(
        x.between[0] < 2.2445 && 2.2445 < x.between[1],
        "{:?}",
        b.bifurcations
    );
}

/// The shooting commands choose their step among the explicit schemes: the ring of
/// `ring_hysteresis.toml` at ν 2.8, whose `rubsim run` takes generalised-α, is shot by `rubsim
/// periodic` without an override — its full annular rub, stable (measured |ρ|max 0.970) —
/// where it used to be refused; `rubsim run` still takes the implicit scheme.
#[test]
fn the_shooting_commands_choose_an_explicit_scheme() {
    let tmp = tempfile::tempdir().unwrap();
    let ring = repo("scenes/periodic/ring_hysteresis.toml");
    let out = tmp.path().join("p");
    let o = cli::rubsim(
        tmp.path(),
        &[
            "periodic",
            ring.to_str().unwrap(),
            "--speed",
            "2.8",
            "--period",
            "1",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let err = cli::text(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("integrator collocated") || err.contains("integrator forward_increment"),
        "{err}"
    );
    let p = &cli::json(&out.join("summary.json"))["periodic"];
    assert_eq!(p["converged"], true);
    assert_eq!(p["stable"], true);
    let run = tmp.path().join("r");
    let o = cli::rubsim(
        tmp.path(),
        &[
            "run",
            ring.to_str().unwrap(),
            "--speed",
            "2.8",
            "--out",
            run.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", cli::text(&o.stderr));
    assert!(cli::text(&o.stderr).contains("integrator generalized_alpha"));
}
