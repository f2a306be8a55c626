//! ROSS's `rotor_example` (ROSS 2.3.0, 6-DOF, `scenes/fe/ross_rotor_example.toml`): damped
//! natural frequencies against ROSS's own `run_modal`, and the Campbell diagram of the issue's
//! reproducer (0 … 1000 rad/s, 12 modes) keeping every branch; speeds in rad/s and rpm on the
//! command line.

use crate::common;

use common::cli::in_repo;
use common::{build, load, repo, NO_SETS};
use rubsim::linear::campbell;
use rubsim::linear::{self, ModeKind, Whirl};

const SCENE: &str = "scenes/fe/ross_rotor_example.toml";

/// ROSS 2.3.0 `rs.rotor_example().run_modal(Ω, num_modes=24).wd[:12]` (rad/s) at Ω = 0, 500,
/// 1000 rad/s (its rigid-body axial and torsional modes are not in the list).
const ROSS_WD: [(f64, [f64; 12]); 3] = [
    (
        0.0,
        [
            91.79655317547088,
            96.28899976982909,
            274.56594512614095,
            296.50048531747393,
            722.8978749547146,
            765.0004291573102,
            774.3496781516478,
            1069.659599788357,
            1103.6289827274043,
            2042.410086432257,
            2053.8773423900398,
            2604.763404735894,
        ],
    ),
    (
        500.0,
        [
            91.5603507409686,
            96.45663974845561,
            265.40599986984256,
            305.35345475931956,
            658.3465523039288,
            774.3496781550966,
            821.3253588403228,
            1062.9206562939669,
            1107.6454643785125,
            1819.2105447792853,
            2272.34547939333,
            2351.2685062943533,
        ],
    ),
    (
        1000.0,
        [
            90.93010826951645,
            96.88132615727132,
            250.08834688226003,
            319.79053378006876,
            576.9367354592277,
            774.349678155026,
            881.7353472337708,
            1046.9883279087792,
            1115.3664692113998,
            1657.6342686382836,
            2003.5445972850184,
            2717.485705774953,
        ],
    ),
];

fn model() -> rubsim::model::Model {
    build(&load(&repo(SCENE), NO_SETS))
}

/// The 6-DOF model with free axial and torsional DOFs (kzz = 0) gives ROSS's frequencies at
/// rest and spinning, and reports the two rigid-body modes.
#[test]
fn ross_rotor_example_frequencies_match_ross() {
    let m = model();
    for (speed, want) in ROSS_WD {
        let r = linear::modal(&m.rotor, speed, 12).unwrap();
        assert_eq!(r.rigid_body, vec![ModeKind::Axial, ModeKind::Torsional]);
        let worst = r
            .modes
            .iter()
            .zip(want)
            .map(|(g, w)| (g.omega_d / w - 1.0).abs())
            .fold(0.0_f64, f64::max);
        eprintln!("Ω = {speed} rad/s: largest relative difference to ROSS {worst:.2e}");
        assert!(worst < 1e-7, "Ω = {speed}: {worst}");
    }
}

/// The reproducer: 31 speeds from 0 to 1000 rad/s, 12 modes. Every track ends on one
/// of ROSS's frequencies at 1000 rad/s (each once), no track jumps by more than the speed step
/// between two speeds (the slopes here are below 1), and the highest three go 2042 → 1657 (BW),
/// 2054 → 2717 (FW), 2605 → 2004 (BW).
#[test]
fn campbell_of_ross_rotor_example_keeps_every_branch() {
    let m = model();
    let speeds = linear::speed_list(0.0, 1000.0, 31);
    let c = campbell(&m.rotor, &speeds, 12).unwrap();
    let step = speeds[1] - speeds[0];
    let mut ends: Vec<f64> = Vec::new();
    for t in &c.tracks {
        for w in t.omega_d.windows(2) {
            assert!(
                w[1].is_finite() && (w[1] - w[0]).abs() < step,
                "{}: {w:?}",
                t.label
            );
        }
        ends.push(*t.omega_d.last().unwrap());
    }
    let mut sorted = ends.clone();
    sorted.sort_by(f64::total_cmp);
    for (g, w) in sorted.iter().zip(ROSS_WD[2].1) {
        assert!((g / w - 1.0).abs() < 1e-7, "{g} vs {w}");
    }
    let top: Vec<(f64, Whirl)> = c.tracks[9..]
        .iter()
        .map(|t| (*t.omega_d.last().unwrap(), t.whirl))
        .collect();
    eprintln!(
        "tracks 10–12 at 1000 rad/s: {top:?}; {} refined speeds",
        c.refined_speeds
    );
    let want = [
        (1657.634, Whirl::Backward),
        (2717.486, Whirl::Forward),
        (2003.545, Whirl::Backward),
    ];
    for ((g, gw), (w, ww)) in top.iter().zip(want) {
        assert!(
            (g - w).abs() < 1e-3 && *gw == ww,
            "{g} {gw:?} vs {w} {ww:?}"
        );
    }
    // Critical speeds lie inside the range and carry a whirl.
    assert!(!c.critical_speeds.is_empty());
    for cs in &c.critical_speeds {
        assert!(cs.speed > 0.0 && cs.speed < 1000.0);
        assert!(matches!(
            cs.whirl,
            Whirl::Forward | Whirl::Backward | Whirl::NoWhirl | Whirl::Mixed
        ));
    }
}

/// The reproducer on the command line, with the speeds in rad/s; and one speed given in rad/s,
/// rpm and ω/ω_n gives the same modes.
#[test]
fn cli_campbell_reproducer_and_speed_units() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("c");
    let (ok, stdout, err) = in_repo(&[
        "campbell",
        SCENE,
        "--from",
        "0",
        "--to",
        "1000",
        "--unit",
        "rad/s",
        "--modes",
        "12",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert!(stdout.contains("2604.763 → 2003.545"), "{stdout}");
    assert!(stdout.contains("2053.877 → 2717.486"), "{stdout}");
    let wn = model().rotor.natural_frequency();
    let modes = |speed: String, unit: &str| {
        let o = tmp.path().join(format!("m_{unit}").replace('/', "_"));
        let (ok, stdout, err) = in_repo(&[
            "modal",
            SCENE,
            "--speed",
            &speed,
            "--unit",
            unit,
            "--out",
            o.to_str().unwrap(),
        ]);
        assert!(ok, "{err}");
        assert!(stdout.contains("rigid-body mode"), "{stdout}");
        // Mode number, ω_d, f and whirl (an undamped ζ prints as ±0 by round-off).
        stdout
            .lines()
            .filter(|l| l.contains(" BW") || l.contains(" FW"))
            .map(|l| {
                let f: Vec<&str> = l.split_whitespace().collect();
                format!("{} {} {} {}", f[0], f[1], f[2], f[5])
            })
            .collect::<Vec<_>>()
    };
    let a = modes("1000".into(), "rad/s");
    let b = modes(format!("{}", 1000.0 * 30.0 / std::f64::consts::PI), "rpm");
    let c = modes(format!("{}", 1000.0 / wn), "ratio");
    assert!(!a.is_empty());
    assert_eq!(a, b);
    assert_eq!(a, c);
    let (ok, _, err) = in_repo(&["modal", SCENE, "--unit", "furlongs"]);
    assert!(!ok && err.contains("possible values"), "{err}");
}

/// `rubsim import-ross` on the file ROSS 2.3.0's `Rotor.save` wrote for `rotor_example`
/// (`tests/data/ross/rotor_example.toml`): the scene gives ROSS's frequencies; what cannot be
/// represented is refused naming the element table.
#[test]
fn import_ross_rotor_example_and_refusals() {
    let path = repo("tests/data/ross/rotor_example.toml");
    let text = common::read(&path);
    let scene = rubsim::scene::ross::import(&path, &text).unwrap();
    let m = build(&common::parse(&scene, NO_SETS));
    let r = linear::modal(&m.rotor, 1000.0, 12).unwrap();
    for (g, w) in r.modes.iter().zip(ROSS_WD[2].1) {
        assert!((g.omega_d / w - 1.0).abs() < 1e-7, "{} vs {w}", g.omega_d);
    }
    // The same rotor saved by ROSS 2.3.0 as JSON (`rotor_example().save("….json")`, with its
    // `null`s) gives the same scene, table for table.
    let json_path = repo("tests/data/ross/rotor_example.json");
    let json = rubsim::scene::ross::import(&json_path, &common::read(&json_path)).unwrap();
    let body = |s: &str| -> Vec<String> {
        s.lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("title"))
            .map(String::from)
            .collect()
    };
    assert_eq!(body(&json), body(&scene));
    let bad = rubsim::scene::ross::import(&json_path, "{\"ShaftElement_0\": [1, 2")
        .unwrap_err()
        .to_string();
    assert!(
        bad.contains("rotor_example.json") && bad.contains("JSON"),
        "{bad}"
    );
    // A tapered element is read (its right end's diameters), and Rayleigh factors on every
    // element come through as numbers.
    let tapered =
        rubsim::scene::ross::import(&path, &text.replacen("odr = 0.05", "odr = 0.06", 1)).unwrap();
    assert!(tapered.contains("outer_diameter = 0.05\ninner_diameter = 0.0\nouter_diameter_right = 0.06\ninner_diameter_right = 0.0\n"), "{tapered}");
    let damped = rubsim::scene::ross::import(
        &path,
        &text
            .replace("alpha = 0.0", "alpha = 8.0501")
            .replace("beta = 0.0", "beta = 1e-5"),
    )
    .unwrap();
    assert!(damped.contains("rayleigh = [8.0501, 1e-5]\n"), "{damped}");
    build(&common::parse(&tapered, NO_SETS));
    build(&common::parse(&damped, NO_SETS));
    // A seal (ROSS's `SealElement`, here with its leakage) and a ball bearing are bearings in
    // ROSS's matrices: read by the bearing rule, the leakage and the rolling-element geometry
    // left aside: the same bearings (listed in another order), ROSS's frequencies.
    let sealed = text
        .replacen(
            "[\"BearingElement_Bearing 0\"]",
            "[SealElement_S]\nseal_leakage = 0.3",
            1,
        )
        .replacen(
            "[\"BearingElement_Bearing 1\"]",
            "[BallBearingElement_B]\nn_balls = 8\nd_balls = 0.03\nfs = 500.0\nalpha = 0.5",
            1,
        );
    let sealed = rubsim::scene::ross::import(&path, &sealed).unwrap();
    assert_eq!(sealed.matches("[[rotor.bearing]]").count(), 2, "{sealed}");
    assert!(
        !sealed.contains("leakage") && !sealed.contains("balls"),
        "{sealed}"
    );
    let m = build(&common::parse(&sealed, NO_SETS));
    let r = linear::modal(&m.rotor, 1000.0, 12).unwrap();
    for (g, w) in r.modes.iter().zip(ROSS_WD[2].1) {
        assert!((g.omega_d / w - 1.0).abs() < 1e-7, "{} vs {w}", g.omega_d);
    }
    let cases = [
        (
            text.replacen("axial_force = 0", "axial_force = 10.0", 1),
            "axial_force",
        ),
        (
            text.replacen(
                "shear_method_calc = \"cowper\"",
                "shear_method_calc = \"hutchinson\"",
                1,
            ),
            "hutchinson",
        ),
        (
            text.replacen("n = 6\nscale_factor", "n = 6\nn_link = 7\nscale_factor", 1),
            "n_link",
        ),
        (
            text.replacen("mxx = [ 0,]", "mxx = [ 1.0,]", 1),
            "mass coefficient",
        ),
        (
            text.replacen("[\"DiskElement_Disk 0\"]", "[\"SealElement_Seal 0\"]", 1),
            "`kxx` missing",
        ),
        (
            text.replacen("[\"DiskElement_Disk 0\"]", "[\"CouplingElement_C 0\"]", 1),
            "CouplingElement",
        ),
        (
            text.replacen(
                "n = 6\nscale_factor",
                "n = 6\nkp_pid = 1000\nscale_factor",
                1,
            ),
            "magnetic bearing",
        ),
        (
            text.replacen("beta = 0.0", "beta = 1e-5", 1),
            "same on every shaft element",
        ),
    ];
    for (bad, what) in cases {
        let e = rubsim::scene::ross::import(&path, &bad)
            .unwrap_err()
            .to_string();
        eprintln!("{what}: {e}");
        assert!(
            e.contains(what) && e.contains("rotor_example.toml:"),
            "{what}: {e}"
        );
    }
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("imported.toml");
    let (ok, _, err) = in_repo(&[
        "import-ross",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    assert_eq!(common::read(&out), scene);
}

/// Cross-coupled bearing stiffness with kxy ≠ kyx (a seal's destabilising ±k) is a skew part
/// of K that the symmetric undamped basis does not carry: the modal solve adds Φᵀ(K − Kᵀ)Φ/2.
/// Against the eigenvalues of the dense first-order matrix [0, I; −M⁻¹K, −M⁻¹(C + ΩG)] of
/// ROSS's `rotor_example` (imported) with ±2e5 N/m cross-coupling and damping on one bearing,
/// at rest and at 800 rad/s (before the skew part entered, ω_d was off by up to 1e-3; against
/// ROSS, `tests/post/test_ross.py::test_seals_and_rolling_bearings_match_ross`, 8.5e-11).
#[test]
fn cross_coupled_bearing_stiffness_enters_the_modal_solve() {
    let path = repo("tests/data/ross/rotor_example.toml");
    let scene = rubsim::scene::ross::import(&path, &common::read(&path)).unwrap();
    let bearing = "[[rotor.bearing]]\nnode = 0\nkxx = 1000000.0\nkxy = 0.0\nkyx = 0.0\nkyy = 800000.0\ncxx = 0.0\n";
    assert!(scene.contains(bearing), "{scene}");
    let seal = bearing
        .replace("kxy = 0.0\nkyx = 0.0", "kxy = 200000.0\nkyx = -200000.0")
        .replace("cxx = 0.0", "cxx = 300.0");
    let m = build(&common::parse(&scene.replacen(bearing, &seal, 1), NO_SETS));
    for speed in [0.0, 800.0] {
        let r = linear::modal(&m.rotor, speed, 12).unwrap();
        let (mm, k, c, g) = m.rotor.matrices(speed).unwrap();
        let dense = rubsim::model::fe_rotor::dense;
        let minv = dense(&mm).try_inverse().unwrap();
        let n = minv.nrows();
        let mk = -&minv * dense(&k);
        let mc = -&minv * (dense(&c) + dense(&g) * speed);
        let a = nalgebra::DMatrix::from_fn(2 * n, 2 * n, |i, j| match (i < n, j < n) {
            (true, true) => 0.0,
            (true, false) => f64::from(u8::from(j - n == i)),
            (false, true) => mk[(i - n, j)],
            (false, false) => mc[(i - n, j - n)],
        });
        let eig = a.complex_eigenvalues();
        assert_eq!(r.modes.len(), 12);
        for mode in &r.modes {
            let best = eig
                .iter()
                .map(|l| (l.im - mode.omega_d).abs() / mode.omega_d)
                .fold(f64::INFINITY, f64::min);
            // The reference (explicit M⁻¹, unscaled, modes up to 1e6 rad/s) holds ~3e-8.
            assert!(
                best < 1e-6,
                "Ω {speed}: ω_d {} off by {best:e}",
                mode.omega_d
            );
        }
    }
}

/// ROSS 2.3.0's `CylindricalBearing` (short fluid-film bearing, strongly cross-coupled
/// kxy ≠ kyx) saved by `Rotor.save` (`tests/data/ross/fluid_film.toml`: `rotor_example`'s shaft
/// and disks on two of them, tabulated at 1 500, 2 000, 2 500 rpm) names its table's speeds
/// `speed`, not `frequency`: the import refused it ("`kxx` has 3 values but `frequency` has
/// 1"). Read now, it gives ROSS's damped frequencies at a table speed (ROSS's `run_modal(2000
/// rpm)`, the first 12 modes; `tests/post/test_ross.py::test_fluid_film_bearings_match_ross`
/// compares the whole modal solution against the live ROSS).
#[test]
fn import_ross_fluid_film_bearing_reads_its_speed_table() {
    const ROSS_WD_2000_RPM: [f64; 12] = [
        108.01783599254938,
        111.39995539300251,
        121.12479158803058,
        122.48591319595454,
        475.07327562643053,
        482.587778260658,
        774.3496781550652,
        1470.4088776925003,
        1727.8186281090932,
        2161.8459912927883,
        2432.804873145751,
        4372.190306476039,
    ];
    let path = repo("tests/data/ross/fluid_film.toml");
    let scene = rubsim::scene::ross::import(&path, &common::read(&path)).unwrap();
    assert_eq!(scene.matches("[[rotor.bearing]]").count(), 2, "{scene}");
    assert!(
        scene.contains("speeds = [157.07963267948966, 209.43951023931953, 261.79938779914943]"),
        "{scene}"
    );
    assert!(
        scene.contains("a parabola through the three points"),
        "{scene}"
    );
    let m = build(&common::parse(&scene, NO_SETS));
    let r = linear::modal(&m.rotor, 2000.0 * std::f64::consts::PI / 30.0, 40).unwrap();
    for w in ROSS_WD_2000_RPM {
        let g = r
            .modes
            .iter()
            .map(|g| g.omega_d)
            .min_by(|a, b| (a - w).abs().total_cmp(&(b - w).abs()))
            .unwrap();
        assert!((g / w - 1.0).abs() < 1e-7, "ω_d {g} against ROSS's {w}");
    }
}
