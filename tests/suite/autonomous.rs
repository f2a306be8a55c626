//! Autonomous periodic orbits (issue 29, item 1: shooting with the period unknown and a phase
//! condition, `analysis::autonomous`): dry whip — the unit rotor's backward whirl in a ring,
//! an unstable orbit no long run settles on — against its closed form (docs/ORACLES.md: the
//! whirl frequency, the radius) and the Floquet multipliers of the circular orbit's
//! linearisation in polar coordinates (docs/VALIDATION.md §19.5); the step's order; bad input.

use crate::common::{self, cli};
use nalgebra::DMatrix;
use rubsim::analysis::autonomous::{shoot_autonomous, AutonomousOrbit};
use rubsim::analysis::{self, periodic};

const SCENE: &str = "scenes/periodic/dry_whip.toml";
const XI: f64 = 0.2;
const MU: f64 = 0.1;
const KAPPA: f64 = 25.0;
const DELTA: f64 = 1e-3;

/// The closed-form whirl ω_w/ω_n = ξ/μ + √(1 + (ξ/μ)²) and radius R = κδ/(κ + 1 − ω_w²).
fn whirl() -> (f64, f64) {
    let w = XI / MU + (1.0 + (XI / MU).powi(2)).sqrt();
    (w, KAPPA * DELTA / (KAPPA + 1.0 - w * w))
}

/// The multipliers of the circular orbit: with `z = r e^{iφ}`, `r = R + ρ`, `φ' = −ω + q`, the
/// rub's force `κ(r − δ)(1 + iμ) e^{iφ}` gives `ρ'' + 2ξρ' + (1 + κ − ω²)ρ + 2Rω q = 0` and
/// `R q' + 2ξR q − 2ωρ' + (μκ − 2ξω)ρ = 0`, whose exponents solve
/// `(s² + 2ξs + c)(s + 2ξ) + 4ω²s − 2ω(μκ − 2ξω) = 0`, `c = 1 + κ − ω²`; with the shift along
/// the orbit (φ, exponent 0) the four multipliers are 1 and `exp(s T)`, `T = 2π/ω`.
fn multipliers() -> Vec<[f64; 2]> {
    let (w, _) = whirl();
    let c = 1.0 + KAPPA - w * w;
    // s³ + a s² + b s + d.
    let a = 4.0 * XI;
    let b = c + 4.0 * XI * XI + 4.0 * w * w;
    let d = 2.0 * XI * c - 2.0 * w * (MU * KAPPA - 2.0 * XI * w);
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
/// `rotor.unbalance`; a rotor at rest (nothing whirls to start from) gets a clear report.
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
    assert!(err.contains("does not whirl"), "{err}");
}
