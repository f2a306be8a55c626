//! The Floquet multipliers' own step error (`analysis::floquet`, `rubsim periodic --refine`):
//! the free paper rotor's multipliers at Δt and Δt/2, extrapolated, against the continuous
//! flow's exp(λT) with λ the eigenvalues `rubsim modal` gives (issue 29's target: 1e-8), the
//! error estimate against the true error, and an orbit in contact, which is not extrapolated.

use crate::common;
use common::{cli, repo, set_distance};
use rubsim::analysis::{self, floquet, periodic};

const PAPER: &str = "scenes/paper/partial_rub.toml";

/// The paper rotor without contact (clearance 50 |Z0|) at ν 1.7, its step chosen as
/// `rubsim periodic` chooses it: the multipliers at Δt are exp(λT) of `rubsim modal`'s
/// eigenvalues only to the scheme's O(Δt²); at Δt/2 to a quarter of that; extrapolated, to
/// 1e-8 (measured at N = 384: 7.99e-6 at Δt, 2.00e-6 at Δt/2, 5.8e-11 extrapolated from the
/// variational monodromy; the affine map's differences at `AFFINE_STEP` gave 3.2e-10, at
/// shooting's own difference step 1.7e-8). The error estimate of ρ(Δt/2), |ρ(Δt/2) − ρ(Δt)|/3, is its true error within
/// 1 % (measured: to 4 digits).
#[test]
fn refined_free_rotor_multipliers_are_exp_lambda_t_of_the_modal_eigenvalues() {
    let (ls, m) = common::file_model(&repo(PAPER), &["stator.0.clearance_nd=50"]);
    let prep = analysis::prepare(&m, &common::settings(&ls).request(1.7)).expect("prepare");
    let o = periodic::shoot(&prep, Some(1)).expect("shoot");
    assert!(o.converged && o.stable && o.orbit.contact_fraction == 0.0);
    let r = floquet::refine(&prep, &o).expect("refine");
    assert!(r.converged && r.stable && !r.verdict_changes, "{r:?}");
    assert_eq!(r.order, 2);
    let omega = 1.7 * m.rotor.natural_frequency();
    let period = 2.0 * std::f64::consts::PI / omega;
    let modal = rubsim::linear::modes::modal(&m.rotor, omega, 4).expect("modal");
    let expected: Vec<[f64; 2]> = modal
        .modes
        .iter()
        .flat_map(|md| {
            let (a, b) = ((md.sigma * period).exp(), md.omega_d * period);
            [[a * b.cos(), a * b.sin()], [a * b.cos(), -a * b.sin()]]
        })
        .collect();
    assert_eq!(expected.len(), 4, "{modal:?}");
    let ext = r.extrapolated.as_ref().expect("no contact: extrapolated");
    let (e_dt, e_half, e_ext) = (
        set_distance(&o.multipliers, &expected),
        set_distance(&r.half_step, &expected),
        set_distance(ext, &expected),
    );
    let estimate = r.error_estimate.iter().fold(0.0_f64, |a, b| a.max(*b));
    eprintln!(
        "N = {}: |ρ − exp(λT)| {e_dt:.3e} (Δt), {e_half:.3e} (Δt/2, estimated {estimate:.3e}), {e_ext:.3e} (extrapolated)",
        o.orbit.plan.steps_per_rev
    );
    assert!(
        e_ext < 1e-8,
        "extrapolated multipliers {e_ext:e} from exp(λT)"
    );
    assert!(e_half < e_dt / 3.9, "{e_half:e} against {e_dt:e}");
    assert!(
        (estimate / e_half - 1.0).abs() < 0.01,
        "estimate {estimate:e} against the true {e_half:e}"
    );
}

/// An orbit in contact (the paper case at ν 1.7) is not extrapolated: its order in Δt is not
/// known; the command prints and writes each multiplier's difference as its error bound
/// (multipliers_refined.csv, summary.json's `refined`).
#[test]
fn the_periodic_command_refines_an_orbit_in_contact_without_extrapolating() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("p");
    let o = cli::rubsim(
        &repo(""),
        &[
            "periodic",
            PAPER,
            "--speed",
            "1.7",
            "--refine",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", cli::text(&o.stderr));
    let stdout = cli::text(&o.stdout);
    assert!(stdout.contains("at Δt/2"), "{stdout}");
    assert!(stdout.contains("contact: order unknown"), "{stdout}");
    let s = cli::json(&out.join("summary.json"));
    let r = &s["refined"];
    assert_eq!(r["order"], 1);
    assert!(r["extrapolated"].is_null());
    let dt = (r["dt"][0].as_f64().unwrap(), r["dt"][1].as_f64().unwrap());
    assert!((dt.1 * 2.0 / dt.0 - 1.0).abs() < 1e-12);
    let n = s["periodic"]["multipliers"].as_array().unwrap().len();
    let csv = std::fs::read_to_string(out.join("multipliers_refined.csv")).unwrap();
    assert!(csv.starts_with(
        "index,re,im,re_half,im_half,difference,error_estimate,re_extrapolated,im_extrapolated\n"
    ));
    assert_eq!(csv.lines().count(), n + 1);
    // Each multiplier's bound is the whole difference; the stable orbit stays stable at Δt/2.
    for (d, e) in r["difference"]
        .as_array()
        .unwrap()
        .iter()
        .zip(r["error_estimate"].as_array().unwrap())
    {
        assert_eq!(d, e);
    }
    assert_eq!(r["stable"], true);
    assert_eq!(r["verdict_changes"], false);
}
