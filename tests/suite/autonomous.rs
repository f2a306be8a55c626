//! Autonomous periodic orbits (issue 29, item 1: shooting with the period unknown and a phase
//! condition, `analysis::autonomous`): dry whip — the unit rotor's backward whirl in a ring,
//! an unstable orbit no long run settles on — against its closed form (docs/ORACLES.md: the
//! whirl frequency, the radius) and the Floquet multipliers of the circular orbit's
//! linearisation in polar coordinates (docs/VALIDATION.md §19.5); the step's order; bad input.

use crate::common::{self, cli};
use nalgebra::DMatrix;
use rubsim::analysis::autonomous::{shoot_autonomous, AutonomousOrbit};
use rubsim::analysis::{self, autonomous_branch::AutonomousBranch, periodic};

const SCENE: &str = "scenes/periodic/dry_whip.toml";
const XI: f64 = 0.2;
const MU: f64 = 0.1;
const KAPPA: f64 = 25.0;
const DELTA: f64 = 1e-3;

/// The closed-form whirl ω_w/ω_n = ξ/μ + √(1 + (ξ/μ)²) and radius R = κδ/(κ + 1 − ω_w²).
fn whirl() -> (f64, f64) {
    whirl_at(MU)
}

/// [`whirl`] at the friction `mu`.
fn whirl_at(mu: f64) -> (f64, f64) {
    let w = XI / mu + (1.0 + (XI / mu).powi(2)).sqrt();
    (w, KAPPA * DELTA / (KAPPA + 1.0 - w * w))
}

/// The multipliers of the circular orbit: with `z = r e^{iφ}`, `r = R + ρ`, `φ' = −ω + q`, the
/// rub's force `κ(r − δ)(1 + iμ) e^{iφ}` gives `ρ'' + 2ξρ' + (1 + κ − ω²)ρ + 2Rω q = 0` and
/// `R q' + 2ξR q − 2ωρ' + (μκ − 2ξω)ρ = 0`, whose exponents solve
/// `(s² + 2ξs + c)(s + 2ξ) + 4ω²s − 2ω(μκ − 2ξω) = 0`, `c = 1 + κ − ω²`; with the shift along
/// the orbit (φ, exponent 0) the four multipliers are 1 and `exp(s T)`, `T = 2π/ω`.
fn multipliers() -> Vec<[f64; 2]> {
    multipliers_at(MU)
}

/// [`multipliers`] at the friction `mu`.
fn multipliers_at(mu: f64) -> Vec<[f64; 2]> {
    let (w, _) = whirl_at(mu);
    let c = 1.0 + KAPPA - w * w;
    // s³ + a s² + b s + d.
    let a = 4.0 * XI;
    let b = c + 4.0 * XI * XI + 4.0 * w * w;
    let d = 2.0 * XI * c - 2.0 * w * (mu * KAPPA - 2.0 * XI * w);
    let companion = DMatrix::from_row_slice(3, 3, &[-a, -b, -d, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    let t = std::f64::consts::TAU / w;
    let mut rho: Vec<[f64; 2]> = companion
        .complex_eigenvalues()
        .iter()
        .map(|s| {
            let m = (s.re * t).exp();
            [m * (s.im * t).cos(), m * (s.im * t).sin()]
        })
        .collect();
    rho.push([1.0, 0.0]);
    rho.sort_by(|x, y| y[0].hypot(y[1]).total_cmp(&x[0].hypot(x[1])));
    rho
}

fn shoot(sets: &[&str]) -> AutonomousOrbit {
    let (ls, model) = common::file_model(&common::repo(SCENE), sets);
    let s = common::settings(&ls);
    let prep = analysis::prepare(&model, &periodic::request_at(&s, 2.0)).unwrap();
    shoot_autonomous(&prep).unwrap()
}

/// Dry whip shot at Δt = 4, 2, 1 ms: the whirl frequency and the radius converge to the closed
/// form at a fitted order of 2 (1.8 … 2.2), within 2e-6 and 1e-5 at 1 ms; the whirl is backward
/// (−2.118 Ω); the multipliers are the linearisation's to 1e-4 at 1 ms — the trivial one 1 to
/// 1e-6, one real multiplier above 1 (the orbit is unstable: outside it the whip grows).
#[test]
fn dry_whip_is_the_closed_form_autonomous_orbit() {
    let (w, r) = whirl();
    let want = multipliers();
    let dts = [4e-3, 2e-3, 1e-3];
    let (mut ew, mut er) = (Vec::new(), Vec::new());
    let mut last = None;
    for dt in dts {
        let o = shoot(&["run.auto_step=false", &format!("run.dt={dt}")]);
        assert!(o.converged, "{o:?}");
        let radius = 0.5 * (o.radius_m[0] + o.radius_m[1]);
        ew.push((o.whirl_ratio + w).abs() / w);
        er.push((radius - r).abs() / r);
        eprintln!(
            "Δt {dt}: whirl {:.8} ω_n (closed form −{w:.8}), radius {radius:.7e} m ({r:.7e}), {} Newton iterations, trivial ρ − 1 = {:.1e}",
            o.whirl_ratio,
            o.iterations,
            o.trivial_multiplier[0] - 1.0
        );
        assert!((o.radius_m[1] - o.radius_m[0]) < 1e-9 * r, "a circle");
        assert!((o.contact_fraction - 1.0).abs() < 1e-12);
        assert!((o.order - o.whirl_ratio / 2.0).abs() < 1e-12);
        last = Some(o);
    }
    let ow = -rubsim::math::loglog_slope(&dts.map(|d| 1.0 / d), &ew);
    let or = -rubsim::math::loglog_slope(&dts.map(|d| 1.0 / d), &er);
    eprintln!("errors: whirl {ew:?} (order {ow:.2}), radius {er:?} (order {or:.2})");
    assert!(
        (1.8..2.2).contains(&ow) && (1.8..2.2).contains(&or),
        "{ow} {or}"
    );
    assert!(ew[2] < 2e-6 && er[2] < 1e-5);
    let o = last.unwrap();
    assert!(o.whirl_frequency < 0.0 && !o.stable && o.instability == Some("fold"));
    let t = o.trivial_multiplier;
    assert!((t[0] - 1.0).hypot(t[1]) < 1e-6, "{t:?}");
    for (g, e) in o.multipliers.iter().zip(&want) {
        eprintln!(
            "ρ = {:+.7} {:+.7}i, linearisation {:+.7} {:+.7}i",
            g[0], g[1], e[0], e[1]
        );
        assert!(
            (g[0] - e[0]).hypot(g[1] - e[1]) < 1e-4,
            "{g:?} against {e:?}"
        );
    }
    assert!((o.largest_modulus - want[0][0]).abs() < 1e-4);
}

/// `rubsim periodic --autonomous` writes the orbit into summary.json and multipliers.csv;
/// `--period` beside it is refused.
#[test]
fn the_command_writes_the_autonomous_orbit() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("dw");
    let stdout = cli::ok(
        &common::repo(""),
        &[
            "periodic",
            SCENE,
            "--autonomous",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(
        stdout.contains("autonomous orbit") && stdout.contains("backward"),
        "{stdout}"
    );
    let s = cli::json(&out.join("summary.json"));
    let w = s["autonomous"]["whirl_ratio"].as_f64().unwrap();
    assert!((w + whirl().0).abs() < 1e-4, "{w}");
    assert_eq!(s["command"], "periodic");
    let csv = common::read(&out.join("multipliers.csv"));
    assert_eq!(csv.lines().count(), 5, "{csv}");
    let err = cli::fails(
        &common::repo(""),
        &["periodic", SCENE, "--autonomous", "--period", "2"],
    );
    assert!(err.contains("--period"), "{err}");
}

/// Bad input: an unbalance (the motion is forced, not autonomous) is refused naming
/// `rotor.unbalance`; a rotor at rest, or whirling clear of the ring (its motion decays: no
/// self-excited orbit), gets a clear report naming the stator.
#[test]
fn a_forced_or_resting_rotor_is_refused() {
    let text = common::read(&common::repo(SCENE)).replace(
        "damping_ratio = 0.2\n",
        "damping_ratio = 0.2\n\n[[rotor.unbalance]]\nmass = 1.0e-3\nradius = 1.0\n",
    );
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("forced.toml");
    std::fs::write(&path, text).unwrap();
    let err = cli::fails(
        &common::repo(""),
        &[
            "periodic",
            path.to_str().unwrap(),
            "--autonomous",
            "--out",
            tmp.path().join("o").to_str().unwrap(),
        ],
    );
    assert!(err.contains("rotor.unbalance"), "{err}");
    let err = cli::fails(
        &common::repo(""),
        &[
            "periodic",
            SCENE,
            "--autonomous",
            "--set",
            "run.initial_displacement=[0.0,0.0]",
            "--set",
            "run.initial_velocity=[0.0,0.0]",
            "--out",
            tmp.path().join("p").to_str().unwrap(),
        ],
    );
    assert!(err.contains("never touches a stator"), "{err}");
    // A free whirl clear of the ring decays: refused before Newton, not a Newton that wanders
    // (its period ran from 6.4 s to 7e-4 s before the refusal).
    let err = cli::fails(
        &common::repo(""),
        &[
            "periodic",
            SCENE,
            "--autonomous",
            "--set",
            "stator.0.clearance=1.0",
            "--out",
            tmp.path().join("q").to_str().unwrap(),
        ],
    );
    assert!(
        err.contains("never touches a stator") && err.contains("decays"),
        "{err}"
    );
}

/// The whip continued at ν 2 over a key or in speed, at Δt₀ = 1 ms (its N steps a period kept).
fn branch(key: Option<(&str, f64)>, range: (f64, f64, f64)) -> AutonomousBranch {
    let (ls, model) = common::file_model(
        &common::repo(SCENE),
        &["run.auto_step=false", "run.dt=1e-3"],
    );
    let s = common::settings(&ls);
    analysis::continuation::continue_autonomous((&ls, &model), &s, key, range).unwrap()
}

/// Continued in the friction μ 0.1 … 0.3 by 0.05 (`--autonomous --key station.0.friction`):
/// every point is the closed form's whirl and radius at its μ (measured 4e-7 … 9e-6 relative,
/// asserted 2e-5) and its multipliers the linearisation's exp(sT) (5e-6 … 1.2e-5 of max(|ρ|,
/// 1), asserted 1e-4), unstable throughout (the cubic's constant term 2ξc − 2ω_w(μκ − 2ξω_w)
/// < 0 wherever the whip exists: ρ₁ 1.069 … 4.342); each point's trivial multiplier 1 within
/// 1e-6 (measured 4e-9 … 1.7e-7). Δt = T/N grows with T from 0.98 to 2.2 ms.
#[test]
fn the_whip_continued_in_friction_is_the_closed_form() {
    let b = branch(Some(("station.0.friction", 2.0)), (0.1, 0.3, 0.05));
    assert_eq!(b.points.len(), 5, "{:?}", b.ended);
    assert!(b.ended.is_none() && b.parameter == "station.0.friction");
    for o in &b.points {
        let mu = o.parameter;
        let (w, r) = whirl_at(mu);
        let radius = 0.5 * (o.radius_m[0] + o.radius_m[1]);
        let (ew, er) = ((o.whirl_ratio + w).abs() / w, (radius - r).abs() / r);
        let want = multipliers_at(mu);
        // Each expected multiplier against the nearest shot one (two of nearly one modulus
        // may come in either order).
        let em = want
            .iter()
            .map(|e| {
                o.multipliers
                    .iter()
                    .map(|g| (g[0] - e[0]).hypot(g[1] - e[1]) / e[0].hypot(e[1]).max(1.0))
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0_f64, f64::max);
        let t = o.trivial_multiplier;
        eprintln!(
            "μ {mu:.3}: whirl {:.7} (−{w:.7}) {ew:.1e}, radius {radius:.6e} ({r:.6e}) {er:.1e}, ρ₁ {:.6} ({:.6}), multipliers {em:.1e}, trivial {:.1e}, Δt {:.3e}",
            o.whirl_ratio,
            o.largest_modulus,
            want[0][0],
            (t[0] - 1.0).hypot(t[1]),
            o.dt_s
        );
        assert!(ew < 2e-5 && er < 2e-5, "μ {mu}: {ew:e} {er:e}");
        assert!(em < 1e-4, "μ {mu}: {em:e}");
        assert!((t[0] - 1.0).hypot(t[1]) < 1e-6, "{t:?}");
        assert!(!o.stable && o.instability == Some("fold"));
    }
    assert_eq!(b.stretches().len(), 1);
}

/// Continued in speed ν 1.5 … 3 by 0.5: the whip does not depend on the spin (the slip keeps its
/// sign), every point the same orbit within 1e-9 relative, its order −ω_w/(ν ω_n).
#[test]
fn the_whip_continued_in_speed_does_not_change() {
    let b = branch(None, (1.5, 3.0, 0.5));
    assert_eq!(b.points.len(), 4, "{:?}", b.ended);
    let first = &b.points[0];
    for o in &b.points {
        assert!((o.whirl_ratio - first.whirl_ratio).abs() < 1e-9 * first.whirl_ratio.abs());
        assert!((o.radius_m[1] - first.radius_m[1]).abs() < 1e-9 * first.radius_m[1]);
        assert!((o.order - o.whirl_ratio / o.parameter).abs() < 1e-12);
    }
    assert!((first.whirl_ratio + whirl().0).abs() < 2e-6 * whirl().0);
}

/// Continued downwards in μ from 0.1 to 0.07: the whip exists only above μ_c = 2ξ√(1+κ)/κ
/// (its radius κδ/(κ + 1 − ω_w²) grows without bound there), so the branch ends between μ_c
/// and its last converged value 0.09, saying where and why, not with an error.
#[test]
fn the_whip_branch_ends_at_the_critical_friction() {
    let mu_c = 2.0 * XI * (1.0 + KAPPA).sqrt() / KAPPA;
    let b = branch(Some(("station.0.friction", 2.0)), (0.1, 0.07, 0.01));
    let why = b.ended.as_deref().expect("ends");
    eprintln!("μ_c {mu_c:.5}: {why}");
    let last = b.points.last().unwrap().parameter;
    assert!((last - 0.09).abs() < 1e-12, "{last}");
    assert!(why.contains("station.0.friction") && why.contains("no autonomous orbit"));
    let at: f64 = why
        .split("station.0.friction = ")
        .nth(1)
        .and_then(|t| t.split(' ').next())
        .and_then(|t| t.parse().ok())
        .unwrap();
    assert!(at > mu_c && at < 0.09, "failed at {at}, μ_c {mu_c}");
}

/// `rubsim continue --autonomous --key`: branch.csv with the key's column and one row per
/// value, summary.json's `autonomous_branch`; `--period`, `--sweep` and `--orbits-at` beside it
/// refused.
#[test]
fn the_continue_command_writes_the_autonomous_branch() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("b");
    let args = [
        "continue",
        SCENE,
        "--autonomous",
        "--key",
        "station.0.friction",
        "--speed",
        "2",
        "--from",
        "0.1",
        "--to",
        "0.2",
        "--step",
        "0.05",
        "--out",
        out.to_str().unwrap(),
    ];
    let stdout = cli::ok(&common::repo(""), &args);
    assert!(stdout.contains("unstable"), "{stdout}");
    let (head, rows) = cli::csv_table(&out.join("branch.csv"));
    assert_eq!(head[0], "station.0.friction");
    assert_eq!(rows.len(), 3);
    let w = head.iter().position(|h| h == "whirl_ratio").unwrap();
    let got: f64 = rows[1][w].parse().unwrap();
    assert!((got + 3.0).abs() < 1e-4, "{got}");
    let s = cli::json(&out.join("summary.json"));
    assert_eq!(
        s["autonomous_branch"]["points"].as_array().unwrap().len(),
        3
    );
    let err = cli::fails(&common::repo(""), &[&args[..], &["--period", "1"]].concat());
    assert!(err.contains("--period"), "{err}");
    let err = cli::fails(&common::repo(""), &[&args[..], &["--sweep", "x"]].concat());
    assert!(err.contains("--sweep"), "{err}");
    let err = cli::fails(
        &common::repo(""),
        &[&args[..], &["--orbits-at", "2"]].concat(),
    );
    assert!(
        err.contains("--orbits-at") && err.contains("--key"),
        "{err}"
    );
}

/// `rubsim continue --autonomous --orbits-at` on a branch in speed: each value inside the
/// branch shot from its nearest point and written under `orbits/branch0_<ν>/` as one whirl
/// period, listed in summary.json (`orbits`, with the orbit and its series); a value outside
/// the branch is told, not shot. The dry whip does not depend on the speed (the ring and the
/// friction see only the whirl): the orbit at 2.1 is the branch's, its series closing the
/// period to 1e-8 of the radius.
#[test]
fn the_autonomous_branch_writes_the_orbits_asked_for() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("o");
    let o = cli::rubsim(
        &common::repo(""),
        &[
            "continue",
            SCENE,
            "--autonomous",
            "--from",
            "2.0",
            "--to",
            "2.4",
            "--step",
            "0.2",
            "--orbits-at",
            "2.1,3.0",
            "--set",
            "output.vtk={}",
            "--set",
            "output.png=false",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    let err = cli::text(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("--orbits-at 3: outside the branch"), "{err}");
    let s = cli::json(&out.join("summary.json"));
    let orbits = s["orbits"].as_array().unwrap();
    assert_eq!(orbits.len(), 1, "{orbits:?}");
    let (at, point) = (&orbits[0], &s["autonomous_branch"]["points"][0]);
    assert_eq!(at["speed_ratio"], 2.1);
    assert_eq!(at["orbit"]["converged"], true);
    let w = |v: &serde_json::Value| v["whirl_ratio"].as_f64().unwrap();
    assert!((w(&at["orbit"]) - w(point)).abs() < 1e-8, "{at} {point}");
    let dir = out.join(at["series"]["folder"].as_str().unwrap());
    assert!(dir.ends_with("orbits/branch0_2.1"), "{}", dir.display());
    let frames = common::output::pvd(&dir.join("results.pvd"));
    let disp = |i: usize| common::output::rotor_in_frame(&dir.join(&frames[i].1));
    let (first, last) = (disp(0), disp(frames.len() - 1));
    let size = first[0].hypot(first[1]);
    let closed = (last[0] - first[0]).hypot(last[1] - first[1]) / size;
    eprintln!(
        "orbit at 2.1: {} frames, last − first {closed:.1e} of the radius",
        frames.len()
    );
    assert!(closed < 1e-8, "{closed}");
}
