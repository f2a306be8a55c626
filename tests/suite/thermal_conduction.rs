//! The heated section's conduction (issue 27, `[thermal.conduction]`, `model::section`): the
//! discretised section against the closed form of the first circumferential harmonic of heat
//! in a solid cylinder (Bessel functions, `oracles::SectionOracle`), converging at a fitted
//! order of 2 in its cells; the spiral of a Jeffcott rotor with a conducting section against
//! the linear theory's dominant root of `t(s) Λ/G = 1` (docs/VALIDATION.md §21.3); and bad
//! input named by key.

use crate::common::{self, cli, oracles};
use num_complex::Complex64 as C64;
use oracles::{dominant_root, Newkirk, SectionOracle};
use rubsim::analysis::thermal::{run_thermal, HeatLaw, HotSpot, ThermalResults};
use rubsim::model::section::{Conduction, Section};
use rubsim::model::Rotor;

const SCENE: &str = "scenes/thermal/newkirk_conduction.toml";

fn c(v: [f64; 2]) -> C64 {
    C64::new(v[0], v[1])
}

fn oracle(c: &Conduction) -> SectionOracle {
    SectionOracle {
        radius: c.radius,
        length: c.heated_length,
        k: c.conductivity,
        rho_c: c.heat_capacity,
        h: c.surface_coefficient,
        eta: c.heat_fraction,
    }
}

/// A generator body's section (R 0.15 m, steel, h 50 W/(m²·K)) at frequencies s from its
/// slowest rate to 30 times it (|λR| up to 12) and on the imaginary axis: the discrete transfer
/// function ΔT/Q equals the closed form to 1e-3 at 32 cells and converges at a fitted order of
/// 2 (1.9 … 2.1); the steady gain to rounding.
#[test]
fn the_section_is_the_closed_form_conduction() {
    let base = Conduction {
        radius: 0.15,
        heated_length: 0.4,
        conductivity: 45.0,
        heat_capacity: 7850.0 * 460.0,
        surface_coefficient: 50.0,
        heat_fraction: 0.5,
        cells: 32,
    };
    let o = oracle(&base);
    let slow = Section::new(&base).unwrap().slowest_time().recip();
    let points: Vec<C64> = [
        (1.0, 0.0),
        (0.0, 1.0),
        (3.0, -3.0),
        (-0.5, 10.0),
        (30.0, 0.0),
    ]
    .iter()
    .map(|&(a, b)| C64::new(a, b) * slow)
    .collect();
    let error = |cells: usize| {
        let s = Section::new(&Conduction { cells, ..base }).unwrap();
        points
            .iter()
            .map(|&p| {
                let want = o.transfer(p);
                (c(s.transfer([p.re, p.im])) - want).norm() / want.norm()
            })
            .fold(0.0, f64::max)
    };
    let cells = [8.0, 16.0, 32.0, 64.0];
    let errs: Vec<f64> = cells.iter().map(|&n| error(n as usize)).collect();
    let order = -rubsim::math::loglog_slope(&cells, &errs);
    eprintln!("section against the closed form: {errs:?} at {cells:?} cells, order {order:.2}");
    assert!((1.9..2.1).contains(&order), "{order}");
    assert!(errs[2] < 1e-3, "{}", errs[2]);
    let s = Section::new(&base).unwrap();
    let g0 = s.transfer([0.0, 0.0])[0];
    assert!((g0 / o.transfer(C64::new(0.0, 0.0)).re - 1.0).abs() < 1e-12);
    assert!((g0 / base.steady_gain() - 1.0).abs() < 1e-12);
    eprintln!(
        "steady gain {g0:.5} K/W, slowest time {:.1} s",
        s.slowest_time()
    );
}

/// The scene's run with overrides, its section, and the rest of its loop Λ/G (W/K).
fn run(sets: &[&str]) -> (ThermalResults, Conduction, C64, f64) {
    let (ls, model) = common::file_model(&common::repo(SCENE), sets);
    let s = common::settings(&ls);
    let v = ls.scene.run.speed_ratio.unwrap();
    let hs = HotSpot::of_scene(&ls).unwrap();
    let HeatLaw::Conduction(cond) = hs.heat else {
        panic!("a conducting section")
    };
    let r = run_thermal(&model, &s, v, &hs).unwrap();
    let Rotor::Jeffcott(j) = &model.rotor else {
        panic!("a Jeffcott rotor")
    };
    let station = &ls.scene.stations[0];
    let nk = Newkirk {
        m: j.mass,
        c: j.damping,
        k: j.stiffness,
        ks: 0.5 * j.stiffness,
        mu: station.friction,
        radius: station.radius,
        omega: r.omega,
        me: 0.008 * 0.045,
        gain: 1.0,
        th: 1.0,
        tc: 1.0,
        bow: r.bow_per_kelvin,
    };
    (r, cond, nk.lambda(), 2.0 * j.mass / j.damping)
}

/// Against speed: the spiral's fitted growth and rotation follow the theory's dominant root of
/// `t(s) Λ/G = 1` — `t` the section's closed-form transfer function — at ν 1.0 … 2.0: growing
/// at ν 1.1, below the coupled critical speed √1.5, and settling on either side. Each run is
/// kept to the linear regime (|1×| ≪ R). The bound is 7 % of |s|, or 1.5 τ_v |s| of it where
/// that is larger: the theory takes the 1× vector to follow the bow at once, good to the ratio
/// of the vibration's settling time τ_v = 2m/c (0.12 s) to the spiral's 1/|s| — with this
/// thin shaft's fast heat 5 % at ν 1.1 (measured 5.0 %), 26 % at ν 1.3 (measured 3.5 %). At
/// the resonance ν 1.0 the run sits 5.0 % from the theory whatever its duration (10 … 40 s)
/// or chunk (2 … 8 revolutions): the offset docs/VALIDATION.md §21.1 reports there for the
/// hot-spot lags too, not explained.
#[test]
fn the_spiral_with_conduction_follows_its_theory_against_speed() {
    for (nu, duration) in [
        (1.0, 20.0),
        (1.1, 10.0),
        (1.2, 20.0),
        (1.3, 10.0),
        (2.0, 20.0),
    ] {
        let (r, cond, l, tau_v) = run(&[
            &format!("run.speed_ratio={nu}"),
            &format!("thermal.duration={duration}"),
            "thermal.max_temperature_difference=1e4",
            "run.error_estimate=false",
        ]);
        let o = oracle(&cond);
        let tau = Section::new(&cond).unwrap().slowest_time();
        let want = dominant_root(|s| o.transfer(s), l, tau);
        let got = C64::new(r.growth_rate, r.rotation_rate);
        eprintln!(
            "ν {nu}: Λ = {:.3}, s = {want:.4} (theory), {got:.4} (run)",
            l * o.transfer(C64::new(0.0, 0.0))
        );
        let bound = want.norm() * (0.07f64).max(1.5 * tau_v * want.norm());
        eprintln!(
            "  |Δs| = {:.2e}, {:.1} % of |s| (bound {:.1} %)",
            (got - want).norm(),
            100.0 * (got - want).norm() / want.norm(),
            100.0 * bound / want.norm()
        );
        assert!((got - want).norm() < bound, "ν {nu}: {got} against {want}");
        assert_eq!(got.re > 0.0, nu == 1.1, "ν {nu}");
    }
}

/// `scenes/thermal/generator_conduction.toml`: the generator-like FE rotor at 1 500 rpm with
/// its body's own conduction (steel, R 0.15 m) and the accelerated coupling (h = 5 s) over ten
/// minutes: the spiral grows at the theory's root of `t(s) Λ/G = 1` with the rotor's own
/// receptance (k_s 2 MN/m), within 5 % of |s|; the run stays synchronous.
#[test]
fn the_generator_with_conduction_spirals_as_its_theory_says() {
    let path = common::repo("scenes/thermal/generator_conduction.toml");
    let (ls, model) = common::file_model(&path, common::NO_SETS);
    let hs = HotSpot::of_scene(&ls).unwrap();
    let HeatLaw::Conduction(cond) = hs.heat else {
        panic!("a conducting section")
    };
    let speed = ls.scene.run.speed.unwrap() / model.rotor.natural_frequency();
    let r = run_thermal(&model, &common::settings(&ls), speed, &hs).unwrap();
    let l = crate::thermal_fe::fe_loop(&ls, &model, r.omega, 2.0e6);
    let o = oracle(&cond);
    let section = Section::new(&cond).unwrap();
    let want = dominant_root(|s| o.transfer(s), l, section.slowest_time());
    let got = C64::new(r.growth_rate, r.rotation_rate);
    eprintln!(
        "generator with conduction, ν {speed:.3}: G = {:.4} K/W, slowest {:.0} s, Λ = {:.3}, s = {want:.3e} (theory), {got:.3e} (run), |Δs|/|s| = {:.3}; {} steps",
        cond.steady_gain(),
        section.slowest_time(),
        l * cond.steady_gain(),
        (got - want).norm() / want.norm(),
        r.steps
    );
    assert!(r.unsynchronous_at_s.is_none() && r.runaway_at_s.is_none());
    assert!(want.re > 0.0 && got.re > 0.0);
    assert!(
        (got - want).norm() < 0.05 * want.norm(),
        "{got} against {want}"
    );
}

/// Bad input: each of the section's coefficients zero or negative, a heat share above 1, too
/// few or too many cells, the lags beside the conduction, neither — refused naming its key.
#[test]
fn bad_conduction_input_is_refused_by_key() {
    let cases: [(&[&str], &str); 8] = [
        (
            &["thermal.conduction.conductivity=0"],
            "thermal.conduction.conductivity",
        ),
        (
            &["thermal.conduction.density=-7900"],
            "thermal.conduction.density",
        ),
        (
            &["thermal.conduction.specific_heat=0"],
            "thermal.conduction.specific_heat",
        ),
        (
            &["thermal.conduction.surface_coefficient=-1"],
            "thermal.conduction.surface_coefficient",
        ),
        (
            &["thermal.conduction.heat_fraction=1.5"],
            "thermal.conduction.heat_fraction",
        ),
        (
            &["thermal.conduction.heat_fraction=0"],
            "thermal.conduction.heat_fraction",
        ),
        (&["thermal.conduction.cells=1"], "thermal.conduction.cells"),
        (&["thermal.gain=5"], "thermal.gain"),
    ];
    for (sets, key) in cases {
        let mut args = vec!["check", SCENE];
        for s in sets {
            args.extend(["--set", s]);
        }
        let err = cli::fails(&common::repo(""), &args);
        assert!(err.contains(key), "{sets:?}: {err}");
    }
    let err = cli::fails(
        &common::repo(""),
        &[
            "check",
            "scenes/thermal/newkirk_ring.toml",
            "--set",
            "thermal.cells=4",
        ],
    );
    assert!(err.contains("thermal.cells"), "{err}");
    let text = common::read(&common::repo("scenes/thermal/newkirk_ring.toml"))
        .replace("gain = 5.0 ", "# no gain ");
    let err = rubsim::scene::parse(std::path::Path::new("x.toml"), &text, &[] as &[String])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("thermal.gain") && err.contains("[thermal.conduction]"),
        "{err}"
    );
}
