//! Continuation of periodic orbits in a scene key at a fixed speed (issue 29, item 2:
//! `analysis::parameter`, `rubsim continue --key`): a key's branch point is the orbit shot with
//! the key set (the same map), the ring's synchronous full rub along the ring's stiffness against
//! its closed form (docs/ORACLES.md §2) with its fold in κ by pseudo-arclength, a period
//! doubling of the paper case located in its clearance independently of the step and crossing
//! −1 where `rubsim periodic --set` says, and the refusals of keys that cannot be continued.

use crate::common::{self, cli, repo};
use rubsim::analysis::continuation::{continue_key, KeyBranch};
use rubsim::analysis::switch::Diagram;
use rubsim::analysis::{self, periodic};

const PAPER: &str = "scenes/paper/partial_rub.toml";
const RING: &str = "scenes/periodic/ring_hysteresis.toml";
const NO_SETS: &[&str] = &[];

/// The branch of `scene` in `key` at ν over `range`, with the scene's own step rule.
fn key_branch(
    scene: &str,
    (key, nu): (&str, f64),
    range: (f64, f64, f64),
    period: usize,
    arclength: Option<usize>,
) -> Diagram {
    let (ls, _) = common::file_model(&repo(scene), NO_SETS);
    let b = KeyBranch {
        key,
        speed_ratio: nu,
        range,
        period: Some(period),
        arclength,
        switch: None,
    };
    continue_key(&ls, &common::settings(&ls), &b).expect("continue in the key")
}

/// The period-`k` orbit of `scene` shot at ν with `sets` (what `rubsim periodic --set` does).
fn shoot(scene: &str, nu: f64, k: usize, sets: &[String]) -> periodic::PeriodicOrbit {
    let (ls, m) = common::file_model(&repo(scene), sets);
    let prep = analysis::prepare(&m, &common::settings(&ls).request(nu)).expect("prepare");
    periodic::shoot(&prep, Some(k)).expect("shoot")
}

/// A key's branch on the paper case (`station.0.friction` 0.1 → 0.2 at ν 2.0, its stable
/// period-1 partial rub): each point is the orbit `rubsim periodic --set
/// station.0.friction=v` shoots at ν 2.0 from its own settled run — the same map (the key does
/// not change the step plan here), so the same fixed point to Newton's tolerance. Measured:
/// extents within 1.3e-12 |Z0|, ρ₁ within 8.8e-9.
#[test]
fn a_key_branch_point_is_the_orbit_shot_with_the_key_set() {
    let d = key_branch(
        PAPER,
        ("station.0.friction", 2.0),
        (0.1, 0.2, 0.05),
        1,
        None,
    );
    let b = &d.branches[0];
    assert!(b.ended.is_none(), "{:?}", b.ended);
    assert_eq!(b.parameter, "station.0.friction");
    assert_eq!(b.at_speed_ratio, Some(2.0));
    assert_eq!(b.points.len(), 3);
    let (mut de, mut dr) = (0.0_f64, 0.0_f64);
    for p in &b.points {
        assert_eq!(p.speed_ratio, 2.0);
        let set = format!(
            "station.0.friction={}",
            rubsim::scene::toml_number(p.parameter)
        );
        let o = shoot(PAPER, 2.0, 1, &[set]);
        assert!(o.converged);
        for (a, e) in p.extents_nd.iter().zip(o.orbit.extents_nd) {
            de = de.max((a - e).abs());
        }
        let r = o.multipliers[0];
        dr = dr.max((p.rho1[0] - r[0]).hypot(p.rho1[1] - r[1]));
    }
    eprintln!("key branch against the shot orbits: extents {de:.2e}, ρ₁ {dr:.2e}");
    assert!(de < 1e-9, "extents off by {de}");
    assert!(dr < 1e-6, "ρ₁ off by {dr}");
}

/// The unit rotor in the ring (`scenes/periodic/ring_hysteresis.toml`: δ 1.5 e, ξ 0.2, μ 0.1)
/// at ν 2.8 in synchronous full annular rub (stable there), continued in the ring's stiffness
/// ratio κ from 25 down: the whirl radius along the branch is the closed form's larger root
/// (docs/ORACLES.md §2), and by pseudo-arclength the branch turns at a fold in κ at the closed
/// form's double root (κ 9.31583) and comes back along its smaller root. Measured: radius
/// within 1.1e-3 (natural) and 1.7e-3 (arclength; the speed branch's 2.1e-3: the sampled
/// extents), the fold 9.3183 at the first
/// step 0.5 (2.6e-4 relative; 9.3301 at step 1, 9.2991 at 0.25: the parabola's vertex through
/// points up to 4 steps apart); the natural branch stops between 9.375 and 9.3125.
/// (At ν 4.0 the rub is past its Neimark–Sacker: no settled periodic run to shoot from.)
#[test]
fn the_full_rub_along_the_ring_stiffness_is_the_closed_form_and_folds_at_its_double_root() {
    let (nu, mu, xi, d): (f64, f64, f64, f64) = (2.8, 0.1, 0.2, 1.5);
    let z0 = nu * nu / ((1.0 - nu * nu).powi(2) + (2.0 * xi * nu).powi(2)).sqrt();
    let disc = |k: f64| {
        let (qa, qb, qc) = common::oracles::radial_annular_rub_quadratic(nu, k, mu, xi, d);
        (qb * qb - 4.0 * qa * qc, qa, qb)
    };
    // The closed form's fold: where the quadratic has a double root (disc > 0 above it).
    let (mut lo, mut hi) = (5.0, 25.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if disc(mid).0 > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let radius_error = |b: &rubsim::analysis::branch::Branch| {
        let mut past = false;
        let mut worst = 0.0_f64;
        for w in b.points.windows(2) {
            past |= w[1].parameter > w[0].parameter;
            let p = &w[1];
            let (dd, qa, qb) = disc(p.parameter);
            if dd < 0.0 {
                continue;
            }
            let root = (-qb + if past { -1.0 } else { 1.0 } * dd.sqrt()) / (2.0 * qa);
            if root > d {
                worst = worst.max((p.extents_nd[1] * z0 / root - 1.0).abs());
            }
        }
        worst
    };
    let key = ("stator.0.stiffness_ratio", nu);
    let natural = key_branch(RING, key, (25.0, 10.0, 1.0), 1, None);
    let b = &natural.branches[0];
    assert!(b.ended.is_none(), "{:?}", b.ended);
    assert_eq!(b.points.len(), 16);
    assert!(b.points.iter().all(|p| p.stable));
    let worst = radius_error(b);
    eprintln!("natural: radius against the closed form {worst:.2e} at most");
    assert!(worst < 3e-3, "radius off by {worst}");
    let arc = key_branch(RING, key, (25.0, 5.0, 0.5), 1, Some(200));
    let b = &arc.branches[0];
    let folds: Vec<_> = b.bifurcations.iter().filter(|x| x.kind == "fold").collect();
    assert_eq!(folds.len(), 1, "{:?} {:?}", b.bifurcations, b.ended);
    let fold = folds[0].parameter;
    eprintln!(
        "fold at κ {fold:.6} against {lo:.6} ({:.2e} relative); {} points",
        (fold / lo - 1.0).abs(),
        b.points.len()
    );
    assert!(
        (fold / lo - 1.0).abs() < 1e-3,
        "fold at {fold}, closed form {lo}"
    );
    assert_eq!(folds[0].speed_ratio, nu);
    let worst = radius_error(b);
    eprintln!("arclength: radius against the closed form {worst:.2e} at most");
    assert!(worst < 3e-3, "radius off by {worst}");
}

/// The paper case at ν 2.3 (its period-1 orbit unstable by period doubling, ρ₁ −1.39) continued
/// in the rod's clearance `stator.0.clearance_nd` from 0.6 down to 0.4: the orbit regains
/// stability through ρ = −1; the located doubling is the same at steps 0.05 and 0.025, and
/// `rubsim periodic --set stator.0.clearance_nd=…` at the two ends of the located interval
/// gives ρ₁ real on either side of −1.
#[test]
fn a_period_doubling_in_the_clearance_is_located_independently_of_the_step() {
    let key = ("stator.0.clearance_nd", 2.3);
    let located: Vec<(f64, [f64; 2])> = [0.05, 0.025]
        .iter()
        .map(|&h| {
            let d = key_branch(PAPER, key, (0.6, 0.4, h), 1, None);
            let b = &d.branches[0];
            assert!(b.ended.is_none(), "{:?}", b.ended);
            let pd: Vec<_> = b
                .bifurcations
                .iter()
                .filter(|x| x.kind == "period_doubling")
                .collect();
            assert_eq!(pd.len(), 1, "{:?}", b.bifurcations);
            assert!(pd[0].between[1] - pd[0].between[0] <= h / 64.0 + 1e-12);
            (pd[0].parameter, pd[0].between)
        })
        .collect();
    eprintln!("period doublings in the clearance: {located:?}");
    let (a, b) = (located[0].0, located[1].0);
    assert!((a - b).abs() < 2e-3, "{a} against {b}");
    let rho = |c: f64| {
        let set = format!("stator.0.clearance_nd={}", rubsim::scene::toml_number(c));
        shoot(PAPER, 2.3, 1, &[set]).multipliers[0]
    };
    let [lo, hi] = located[1].1;
    let (r_lo, r_hi) = (rho(lo.min(hi)), rho(lo.max(hi)));
    eprintln!("ρ₁ at {lo}: {r_lo:?}, at {hi}: {r_hi:?}");
    assert!(r_lo[1] == 0.0 && r_hi[1] == 0.0);
    assert!(r_lo[0] > -1.0 && r_hi[0] < -1.0, "{r_lo:?} {r_hi:?}");
}

/// `rubsim continue --key`: branch.csv with the key's column, bifurcations.csv in the key,
/// summary.json naming the parameter; refused before anything runs, naming the key, nothing
/// written: an unknown key, a key that is not a number, a key that changes the state's size
/// (the rod's density from 0 to 7800: a rod with mass), a value the scene refuses (a negative
/// friction), a run setting, `--unit` without `--speed`, `--sweep`.
#[test]
fn the_continue_command_in_a_key_writes_its_column_and_refuses_what_it_cannot_continue() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("k");
    let o = out.to_str().unwrap();
    let stdout = cli::ok(
        &repo(""),
        &[
            "continue",
            PAPER,
            "--key",
            "stator.0.clearance_nd",
            "--speed",
            "2.3",
            "--from",
            "0.6",
            "--to",
            "0.4",
            "--step",
            "0.05",
            "--period",
            "1",
            "--out",
            o,
        ],
    );
    assert!(
        stdout.contains("period_doubling at stator.0.clearance_nd 0.4"),
        "{stdout}"
    );
    let csv = std::fs::read_to_string(out.join("branch.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(
        header.starts_with("stator.0.clearance_nd,speed_ratio,stable,"),
        "{header}"
    );
    assert_eq!(csv.lines().count(), 6);
    assert!(
        csv.lines().nth(1).unwrap().starts_with("0.6,2.3,false,"),
        "{csv}"
    );
    let bif = std::fs::read_to_string(out.join("bifurcations.csv")).unwrap();
    assert!(
        bif.starts_with("kind,stator.0.clearance_nd,from,to,"),
        "{bif}"
    );
    assert!(out.join("branch.png").metadata().unwrap().len() > 10_000);
    let s = cli::json(&out.join("summary.json"));
    assert_eq!(s["branch"]["parameter"], "stator.0.clearance_nd");
    assert_eq!(s["branch"]["at_speed_ratio"], 2.3);
    let bad: &[(&[&str], &str)] = &[
        (&["--key", "station.0.frictoin"], "unknown field `frictoin`"),
        (
            &["--key", "station.0.name"],
            "`station.0.name` is not a number",
        ),
        (
            &[
                "--key",
                "stator.0.density",
                "--from",
                "0",
                "--to",
                "7800",
                "--step",
                "7800",
            ],
            "`stator.0.density` changes the periodic orbit's state",
        ),
        (
            &["--key", "station.0.friction", "--to", "-0.1"],
            "station.0.friction = -0.1",
        ),
        (
            &["--key", "run.dt_scale"],
            "`run.dt_scale` is a setting of the run",
        ),
        (
            &["--key", "station.0.friction", "--unit", "rpm"],
            "--unit applies to --speed only",
        ),
        (&["--key", "station.0.friction", "--sweep", "x"], "--sweep"),
    ];
    for (i, (args, expect)) in bad.iter().enumerate() {
        let dir = tmp.path().join(format!("bad{i}"));
        let mut a = vec!["continue", PAPER, "--period", "1"];
        a.extend_from_slice(args);
        for (flag, v) in [("--from", "0.1"), ("--to", "0.2"), ("--step", "0.1")] {
            if !a.contains(&flag) {
                a.extend([flag, v]);
            }
        }
        if !a.contains(&"--unit") {
            a.extend(["--speed", "2.0"]);
        }
        a.extend(["--out", dir.to_str().unwrap()]);
        let err = cli::fails(&repo(""), &a);
        assert!(err.contains(expect), "{args:?}: {err}");
        assert!(!dir.exists(), "{args:?} wrote {}", dir.display());
    }
}

/// The fold and the Neimark–Sacker point of a pseudo-arclength branch located by bisection in
/// arclength (`analysis::arclength`: the sign of det(∂P/∂y − I) for the fold, the stability
/// for the torus), independently of the continuation step: the ring's fold in its stiffness at
/// ν 2.8 at first steps 1, 0.5 and 0.25 (the vertex through the grid points gave 9.3301,
/// 9.3183, 9.2991), and the ring's full rub in speed losing stability to a torus at steps 0.1
/// and 0.05.
#[test]
fn arclength_folds_and_tori_are_located_independently_of_the_step() {
    let folds: Vec<f64> = [1.0, 0.5, 0.25]
        .iter()
        .map(|&h| {
            let d = key_branch(
                RING,
                ("stator.0.stiffness_ratio", 2.8),
                (25.0, 5.0, h),
                1,
                Some(400),
            );
            let b = &d.branches[0];
            let f: Vec<_> = b.bifurcations.iter().filter(|x| x.kind == "fold").collect();
            assert_eq!(f.len(), 1, "step {h}: {:?}", b.bifurcations);
            f[0].parameter
        })
        .collect();
    let spread = folds
        .iter()
        .fold(0.0_f64, |m, a| m.max((a - folds[1]).abs()));
    eprintln!("folds in κ at steps 1, 0.5, 0.25: {folds:?}, spread {spread:.2e}");
    assert!(spread < 1e-3, "{folds:?}");
    let (ls, m) = common::file_model(&repo(RING), NO_SETS);
    let tori: Vec<f64> = [0.1, 0.05]
        .iter()
        .map(|&h| {
            let b = rubsim::analysis::arclength::continue_arclength(
                &m,
                &common::settings(&ls),
                (1.8, 4.8, h),
                Some(1),
                400,
            )
            .expect("continue");
            let ns: Vec<_> = b
                .bifurcations
                .iter()
                .filter(|x| x.kind == "neimark_sacker")
                .collect();
            assert_eq!(ns.len(), 1, "step {h}: {:?}", b.bifurcations);
            assert!(
                ns[0].between[1] - ns[0].between[0] < h / 16.0,
                "{:?}",
                ns[0]
            );
            ns[0].parameter
        })
        .collect();
    eprintln!("Neimark–Sacker in ν at steps 0.1, 0.05: {tori:?}");
    assert!((tori[0] - tori[1]).abs() < 1e-3, "{tori:?}");
}
