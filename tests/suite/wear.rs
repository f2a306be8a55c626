//! Archard wear of the stators' contact nodes (`[stator.wear]`, issue 27; docs/VALIDATION.md
//! §23): the volume worn is Archard's law over the run (against the run's own friction work),
//! a rotor on a fixed orbit wears a rod and a meshed annulus to the orbit's envelope and no
//! further, the rub then ends by itself, the wear magnification trades run time for wear time,
//! and bad input is refused by key.

use crate::common;

use common::scene_model;
use rubsim::analysis::{prepare_transient, TransientResults};

/// The paper's rotor as a plain Jeffcott rotor (m, k, ξ 0.2), its unbalance 0.008 kg × 45 mm.
const M: f64 = 2.646;
const K: f64 = 7.36e4;
const XI: f64 = 0.2;
/// Speed ratio of the runs.
const NU: f64 = 1.2;
/// Archard's coefficient of the scenes (m²/N).
const WEAR: f64 = 1e-13;

/// The free unbalance orbit at ν = `NU`: `Z` (m, complex `x + iy` at t = 0) and Ω (rad/s).
fn free_orbit() -> ((f64, f64), f64) {
    let w = NU * (K / M).sqrt();
    let c = 2.0 * XI * (K * M).sqrt();
    let f = 0.008 * 0.045 * w * w;
    // Z = f / (k − m ω² + i c ω).
    let (a, b) = (K - M * w * w, c * w);
    let d = a * a + b * b;
    ((f * a / d, -f * b / d), w)
}

/// The rotor started on its free orbit at ν = `NU`, facing `stator` (the `[[stator]]` table
/// with its `[stator.wear]`), run at constant speed for `duration` s with the wear magnified
/// `acceleration` times.
fn scene(stator: &str, duration: f64, acceleration: f64) -> String {
    let ((zx, zy), w) = free_orbit();
    format!(
        r#"
[rotor]
kind = "jeffcott"
mass = {M}
stiffness = {K}
damping_ratio = {XI}
[[rotor.unbalance]]
mass = 0.008
radius = 0.045
[[station]]
name = "disk"
radius = 0.06
friction = 0.1
{stator}
[run]
integrator = "collocated"
wear_acceleration = {acceleration}
initial_displacement = [{zx:e}, {zy:e}]
initial_velocity = [{:e}, {:e}]
[run.speed_profile]
kind = "constant"
unit = "speed_ratio"
speed = {NU}
duration = {duration}
reference = {NU}
"#,
        -w * zy,
        w * zx
    )
}

/// A soft rod (ε 0.05: its force hardly moves the rotor, whose orbit stays the free one) at
/// 90°, its tip at 0.8 |Z0| from the rotor's surface, wearing.
fn rod() -> String {
    let ((zx, zy), _) = free_orbit();
    format!(
        r#"[[stator]]
kind = "rod"
name = "rod"
station = "disk"
clearance = {:e}
length = 0.04
area = 25e-6
stiffness_ratio = 0.05
angle_deg = 90.0
[stator.wear]
coefficient = {WEAR}
"#,
        0.8 * zx.hypot(zy)
    )
}

/// The transient of a scene text with overrides.
fn run(text: &str, sets: &[&str]) -> TransientResults {
    let (ls, model) = scene_model(text, sets);
    let spec = ls.scene.run.speed_profile.as_ref().unwrap();
    prepare_transient(&model, &common::settings(&ls), spec)
        .unwrap()
        .run(&mut [])
        .unwrap()
}

#[test]
fn the_volume_worn_is_archard_s_law_over_the_run_s_friction_work() {
    // V = k A Σ p |ζ| and the friction work is μ Σ p |ζ| (permanent slip): V = k A W / μ, with
    // the work integrated from the friction power recorded at every step — the same sum taken
    // by the wear and by the friction power: a wear that read another force, slip or area
    // would miss it.
    let a = 1e5;
    let r = run(&scene(&rod(), 2.0, a), &["run.samples_per_rev=4096"]);
    let w = r.wear.as_ref().unwrap();
    assert!(r.plan.record_every == 1 && w.volume_m3 > 0.0);
    let archard = WEAR * a * r.friction_energy / 0.1;
    assert!(
        (w.volume_m3 / archard - 1.0).abs() < 1e-9,
        "worn {:.6e} m³, Archard over the friction work {archard:.6e} m³",
        w.volume_m3
    );
    // One node, its depth the volume over the rod's area.
    assert_eq!(w.nodes.len(), 1);
    assert!((w.nodes[0].depth_m * 25e-6 / w.volume_m3 - 1.0).abs() < 1e-12);
}

#[test]
fn a_fixed_orbit_wears_a_rod_to_its_reach_and_the_rub_ends() {
    // The free orbit's reach is |Z0| = 0.301 mm, the tip's clearance 0.8 |Z0|: the tip wears
    // toward the interference I = 0.2 |Z0| from below — the rate falls with the contact's depth
    // and length — and never past it.
    let ((zx, zy), _) = free_orbit();
    let i = 0.2 * zx.hypot(zy);
    let r = run(&scene(&rod(), 10.0, 1e5), &[]);
    let w = r.wear.as_ref().unwrap();
    let depth: Vec<f64> = w.history.iter().map(|h| h[2] / i).collect();
    assert!(
        depth.windows(2).all(|d| d[1] >= d[0]),
        "the depth only grows"
    );
    let last = *depth.last().unwrap();
    assert!(last > 0.995 && last < 1.003, "worn to {last} I");
    // Half-way it was at 0.98 I: the approach slows as the contact shortens.
    let half = depth[depth.len() / 2];
    assert!(half > 0.97 && half < last, "{half} I half-way");
}

#[test]
fn a_fixed_orbit_wears_a_meshed_annulus_to_its_circular_envelope() {
    // A soft annulus (E = 10 kPa, 64 nodes on its inner circle 0.8 |Z0| from the rotor's
    // surface, clamped outside) around the rotor's circular orbit: every node wears to the
    // orbit's envelope, the same depth all round, and the rotor then only grazes it.
    let ((zx, zy), _) = free_orbit();
    let z0 = zx.hypot(zy);
    let geo = common::repo("geometry/annulus.geo");
    let stator = format!(
        r#"[[stator]]
kind = "mesh"
name = "seal"
station = "disk"
geometry = "{}"
parameters = {{ ri = {:e}, ro = 0.07, h = 0.004, n = 64 }}
order = 1
quads = true
plane = "stress"
thickness = 0.01
youngs_modulus = 1e4
poisson_ratio = 0.3
[stator.wear]
coefficient = {WEAR}
"#,
        geo.display(),
        0.06 + 0.8 * z0
    );
    let r = run(&scene(&stator, 10.0, 1e8), &[]);
    let w = r.wear.as_ref().unwrap();
    assert_eq!(w.nodes.len(), 64);
    let i = 0.2 * z0;
    let (lo, hi) = w.nodes.iter().fold((f64::INFINITY, 0.0_f64), |(a, b), n| {
        (a.min(n.depth_m), b.max(n.depth_m))
    });
    // The orbit the annulus's light touch leaves is 1e-3 wider than the free one.
    assert!(
        lo / i > 0.995 && hi / i < 1.005,
        "depths {:.5} … {:.5} I",
        lo / i,
        hi / i
    );
    assert!(
        (hi - lo) / i < 1e-4,
        "not uniform: {:.3e} I apart",
        (hi - lo) / i
    );
    // The rotor grazes the worn circle at the end: the force is a trace of what it was.
    let n = r.contact.len();
    let late = r.contact[9 * n / 10..]
        .iter()
        .map(|c| c[0])
        .fold(0.0, f64::max);
    assert!(
        late < 1e-3 * r.contact_force_max,
        "{late} N late, {} N at most",
        r.contact_force_max
    );
}

#[test]
fn the_wear_magnification_trades_run_time_for_wear_time() {
    // The rod's wear over a wear time of 2e5 s: magnified 1e5 times over 2 s of run, or 1e4
    // times over 20 s. The depth at equal wear times agrees to 1 %.
    let ten_times = run(&scene(&rod(), 20.0, 1e4), &[]);
    let fast = run(&scene(&rod(), 2.0, 1e5), &[]);
    let depth_at = |r: &TransientResults, wear_time: f64| {
        let w = r.wear.as_ref().unwrap();
        let t = wear_time / w.acceleration;
        let k = w
            .history
            .partition_point(|h| h[0] < t)
            .min(w.history.len() - 1);
        w.history[k][2]
    };
    for wear_time in [5e4, 1e5, 2e5] {
        let (a, b) = (depth_at(&fast, wear_time), depth_at(&ten_times, wear_time));
        assert!(
            (a / b - 1.0).abs() < 1e-2,
            "at a wear time of {wear_time:e} s: {a:.6e} m magnified 1e5, {b:.6e} m magnified 1e4"
        );
    }
}

#[test]
fn wear_s_bad_input_is_refused_by_key() {
    let text = scene(&rod(), 1.0, 1e5);
    let err = |sets: &[&str]| -> String {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        match rubsim::scene::parse("wear.toml".as_ref(), &text, &sets) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{sets:?} accepted"),
        }
    };
    for (set, key) in [
        ("stator.0.wear.coefficient=0.0", "stator.0.wear.coefficient"),
        (
            "stator.0.wear.coefficient=-1e-13",
            "stator.0.wear.coefficient",
        ),
        ("run.wear_acceleration=0.0", "run.wear_acceleration"),
    ] {
        let e = err(&[set]);
        assert!(e.contains(key), "{set}: {e}");
    }
    // A ring has no contact nodes to wear.
    let ring = text.replace(&rod(), "[[stator]]\nkind = \"ring\"\nname = \"ring\"\nstation = \"disk\"\nclearance = 2e-4\nstiffness = 1e6\n[stator.wear]\ncoefficient = 1e-13\n");
    let e = match rubsim::scene::parse("wear.toml".as_ref(), &ring, &[]) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("wear on a ring accepted"),
    };
    assert!(e.contains("stator.0.wear") && e.contains("mesh"), "{e}");
    // Wear never settles: a steady run of it is refused.
    let a = text.find("[run.speed_profile]").unwrap();
    let steady = format!("{}speed_ratio = {NU}\n", &text[..a]).replace("[run]\n", "[run]\n");
    let e = match rubsim::scene::parse("wear.toml".as_ref(), &steady, &[]) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("a steady run with wear accepted"),
    };
    assert!(
        e.contains("stator.0.wear") && e.contains("speed_profile"),
        "{e}"
    );
}

#[test]
fn the_worn_depth_is_a_field_of_the_series_and_the_command_writes_its_tables() {
    // The annulus case through the command line with VTK and HDF5 series: every frame carries
    // the point field `worn_depth`, whose last frame is worn_depth.csv's; `rubsim check` lists
    // the wear's files and they are written.
    let ((zx, zy), _) = free_orbit();
    let z0 = zx.hypot(zy);
    let geo = common::repo("geometry/annulus.geo");
    let stator = format!(
        "[[stator]]\nkind = \"mesh\"\nname = \"seal\"\nstation = \"disk\"\ngeometry = \"{}\"\n\
         parameters = {{ ri = {:e}, ro = 0.07, h = 0.004, n = 32 }}\norder = 1\nquads = true\n\
         thickness = 0.01\nyoungs_modulus = 1e4\npoisson_ratio = 0.3\n[stator.wear]\ncoefficient = {WEAR}\n",
        geo.display(),
        0.06 + 0.8 * z0
    );
    let text =
        scene(&stator, 1.0, 1e8) + "[output.vtk]\nevery = 2000\n[output.hdf5]\nevery = 2000\n";
    let tmp = tempfile::tempdir().unwrap();
    let file = tmp.path().join("wear.toml");
    std::fs::write(&file, &text).unwrap();
    let out = tmp.path().join("out");
    let stdout = common::cli::ok(
        tmp.path(),
        &[
            "run",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(
        stdout.contains("wear (magnification A = 100000000"),
        "{stdout}"
    );
    for f in ["wear.csv", "worn_depth.csv", "wear.png", "worn_depth.png"] {
        assert!(out.join(f).exists(), "{f}");
    }
    let check = common::cli::ok(tmp.path(), &["check", file.to_str().unwrap()]);
    assert!(
        check.contains("wears (Archard)") && check.contains("worn_depth.csv"),
        "{check}"
    );
    // The deepest node of the table and the series' last frame.
    let table = common::read(&out.join("worn_depth.csv"));
    let deepest = table
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse::<f64>().unwrap())
        .fold(0.0, f64::max);
    assert!(deepest > 0.5 * 0.2 * z0, "worn {deepest} m");
    let pvd = common::read(&out.join("results.pvd"));
    let last = pvd
        .lines()
        .rev()
        .find_map(|l| l.split("file=\"").nth(1))
        .unwrap();
    let vtu = common::read(&out.join(last.split('"').next().unwrap()));
    assert!(vtu.contains("Name=\"worn_depth\""), "no worn_depth field");
    let f = crate::common::output::open_h5(&out.join("results.vtkhdf"));
    let field: Vec<f64> = common::output::read(&f, "VTKHDF/PointData/worn_depth");
    let frames = common::output::read::<f64>(&f, "VTKHDF/Steps/Values").len();
    let per = field.len() / frames;
    let last = field[(frames - 1) * per..]
        .iter()
        .fold(0.0_f64, |m, v| m.max(*v));
    // The last frame is at most 2000 steps before the end, when the wear has long settled.
    assert!(
        last > 0.99 * deepest && last <= deepest * (1.0 + 1e-12),
        "the series' last frame {last} m, the table {deepest} m"
    );
}

#[test]
#[ignore = "slow tier: a 3-D labyrinth seal's run-up, 150 000 steps (about 25 s)"]
fn a_labyrinth_seal_wears_during_a_run_up_at_every_tooth_and_all_round() {
    // scenes/wear/seal_runup.toml: through the critical speed the orbit passes the 0.2 mm
    // clearance all round; every tip of the three teeth wears, nearly the same all round (a
    // circular orbit), and past the critical the rotor runs free of the worn seal.
    let (_tmp, out, _) = common::cli::run_scene("scenes/wear/seal_runup.toml");
    let (cols, table) = common::cli::csv_table(&out.join("worn_depth.csv"));
    let at = |name: &str| cols.iter().position(|c| c == name).unwrap();
    let mut rows: std::collections::BTreeMap<i64, Vec<f64>> = Default::default();
    for r in &table {
        let z: f64 = r[at("z_m")].parse().unwrap();
        let d: f64 = r[at("depth_m")].parse().unwrap();
        rows.entry((z * 1e5).round() as i64).or_default().push(d);
    }
    // Three teeth, their tips' node rows.
    assert!(rows.len() >= 3, "{} axial rows", rows.len());
    for (z, d) in &rows {
        let (lo, hi) = d
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(a, b), v| (a.min(*v), b.max(*v)));
        assert!(
            lo > 1e-4 && hi < 1.1 * lo,
            "z = {z}e-5 m: {lo:.4e} … {hi:.4e} m"
        );
    }
    let summary: serde_json::Value =
        serde_json::from_str(&common::read(&out.join("summary.json"))).unwrap();
    assert_eq!(summary["transient"]["wear"]["free_at_end"], true);
}
