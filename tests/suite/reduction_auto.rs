//! The reduced schemes in the error-target choice (issue 15 items 2 and 4, issue 11 item 1;
//! docs/IMPLICIT.md §7.3): the cut-off chosen from `run.tolerance` and raised for a tighter
//! one, the reduced result then within the tolerance of the full one; `run.auto_step` picking
//! a reduced scheme on the FE paper rotor, its run within the tolerance of a converged full
//! run; `rubsim check` and `rubsim convergence` reporting it; the two-disk rotor reduced
//! against converged explicit runs.

use crate::common;

use common::{file_model, repo};
use rubsim::analysis::autostep::difference;
use rubsim::analysis::cutoff::{choose_cutoff, TRUNCATION_SHARE};
use rubsim::analysis::{choose, run_speed, Keep, RunSettings};
use rubsim::model::Model;
use rubsim::resolve::ReductionInput;
use rubsim::time::Scheme;
use std::path::Path;

const PAPER: &str = "scenes/fe/paper_rotor_rub.toml";
const TWO_DISK: &str = "scenes/fe/two_disk_two_stations.toml";

fn model_and_settings(scene: &str, sets: &[&str]) -> (Model, RunSettings) {
    let (ls, model) = file_model(Path::new(&repo(scene)), sets);
    (model, common::settings(&ls))
}

/// The rotor-only reduction the choice starts from (κ to be chosen).
fn rotor_reduction(s: &RunSettings) -> ReductionInput {
    ReductionInput {
        cutoff: None,
        cutoff_factor: rubsim::scene::DEFAULT_CUTOFF_FACTOR,
        harmonics: s.step.harmonics,
        rotor: true,
        stators: false,
        auto: true,
    }
}

/// Results of `model` at ν with collocation at Δt = `dt` (s), reduced as `red` (`None`: full).
fn run_at(
    model: &Model,
    s: &RunSettings,
    nu: f64,
    dt: f64,
    red: Option<ReductionInput>,
) -> rubsim::analysis::SpeedResults {
    let mut st = *s;
    st.step.integrator = Scheme::Collocated;
    st.step.dt = Some(dt);
    st.error_estimate = false;
    st.reduction = red;
    run_speed(model, &st.request(nu), Keep::default()).unwrap()
}

#[test]
fn the_cutoff_follows_the_tolerance_and_the_reduced_run_meets_it() {
    let short = [
        "run.revolutions=60",
        "run.transient_revolutions=40",
        "run.error_estimate=false",
    ];
    let (model, s) = model_and_settings(PAPER, &short);
    let nu = 1.7;
    // The full model at a step well below both models' stability limits (6.4e-6 s): the
    // difference of a reduced and a full run at the same step is the truncation alone.
    let dt = 4e-6;
    let full = run_at(&model, &s, nu, dt, None);
    let mut kappas = Vec::new();
    for tol in [1e-3, 1e-4] {
        let st = RunSettings {
            tolerance: tol,
            ..s
        };
        let base = rotor_reduction(&st);
        let c = choose_cutoff(&model, &st, base, &[nu], None).unwrap();
        assert_eq!(c.target, TRUNCATION_SHARE * tol);
        assert!(
            c.truncation_error <= c.target,
            "tol {tol:e}: indicator {:e} above its target",
            c.truncation_error
        );
        let red = ReductionInput {
            cutoff_factor: c.cutoff_factor,
            auto: false,
            ..base
        };
        let r = run_at(&model, &st, nu, dt, Some(red));
        let e = difference(&r, &full);
        println!(
            "tol {tol:e}: κ = {}, indicator {:.2e}, reduced against full {e:.2e}",
            c.cutoff_factor, c.truncation_error
        );
        assert_eq!(r.period, full.period, "same regime");
        assert!(e <= tol, "tol {tol:e}: κ = {}: {e:e}", c.cutoff_factor);
        // The indicator is within a factor 3 of the truncation error it estimates, or both are
        // far below the target.
        assert!(
            c.truncation_error <= 3.0 * e.max(0.1 * c.target)
                && e <= 3.0 * c.truncation_error.max(0.1 * c.target),
            "indicator {:e} against measured {e:e}",
            c.truncation_error
        );
        kappas.push(c.cutoff_factor);
    }
    // At the default factor the indicator is above a quarter of 1e-4: the tighter tolerance
    // raises the cut-off.
    assert_eq!(kappas[0], rubsim::scene::DEFAULT_CUTOFF_FACTOR);
    assert!(kappas[1] > kappas[0], "{kappas:?}");
}

#[test]
#[ignore = "slow tier (scripts/test-slow.sh): the step choice's pilots and a converged reference on the FE rotor"]
fn auto_step_picks_a_reduced_scheme_on_the_fe_rotor_and_meets_the_tolerance() {
    let (model, s) = model_and_settings(PAPER, &["run.auto_step=true"]);
    let nu = 1.7;
    let tol = s.tolerance;
    let c = choose(&model, &s, None, None, &[nu]).unwrap();
    let choice = c.choice.expect("chosen");
    let red = c.reduction.expect("a reduced scheme is chosen");
    assert!(red.rotor && !red.stators);
    let cut = choice.reduction.expect("its cut-off is reported");
    assert_eq!(cut.cutoff_factor, red.cutoff_factor);
    assert!(choice.error_predicted <= tol, "{choice:?}");
    let mut run = c;
    run.error_estimate = false;
    let r = run_speed(&model, &run.request_at(0, nu), Keep::default()).unwrap();
    // The converged full run: collocated at a quarter of the full model's stability limit,
    // over the same revolutions as the chosen run ended with.
    let mut conv = s;
    conv.step.integrator = Scheme::Collocated;
    conv.step.dt = Some(1.6e-6);
    conv.step.transient_revolutions = r.plan.steady_from / r.plan.steps_per_rev;
    conv.step.revolutions = r.plan.steps / r.plan.steps_per_rev;
    conv.max_transient_revolutions = conv.step.transient_revolutions;
    conv.error_estimate = false;
    let full = run_speed(&model, &conv.request(nu), Keep::default()).unwrap();
    let e = difference(&r, &full);
    println!(
        "chosen {:?} at {:.3} × rule, κ = {}, predicted {:.2e}; against the converged full run {e:.2e}; steps {} against {}",
        choice.integrator,
        choice.dt_scale,
        cut.cutoff_factor,
        choice.error_predicted,
        r.stats.steps,
        full.stats.steps
    );
    assert_eq!(r.period, full.period, "same regime");
    assert!(e <= tol, "{e:e}");
    assert!(r.stats.steps * 10 < full.stats.steps);
}

fn rubsim(dir: &Path, args: &[&str]) -> String {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rubsim"))
        .current_dir(dir)
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn check_and_convergence_report_the_reduced_choice() {
    let root = repo("");
    let out = rubsim(
        &root,
        &[
            "check",
            PAPER,
            "--set",
            "run.auto_step=true",
            "--set",
            "run.sweep.from=1.7",
            "--set",
            "run.sweep.to=1.7",
            "--set",
            "run.tolerance=1e-4",
        ],
    );
    let line = out
        .lines()
        .find(|l| l.starts_with("cut-off chosen from run.tolerance = 1e-4"))
        .unwrap_or_else(|| panic!("{out}"));
    assert!(line.contains("κ = 8"), "{line}");
    assert!(line.contains("truncation error indicator"), "{line}");
    let red = out
        .lines()
        .find(|l| l.starts_with("reduction (`[run.reduction]`)"))
        .unwrap_or_else(|| panic!("{out}"));
    assert!(red.contains("8 modes kept"), "{red}");
    // `convergence` marks the chosen reduced point beside the reduced rows.
    let tmp = tempfile::TempDir::new().unwrap();
    let dir = tmp.path().join("conv");
    let scene = repo(PAPER);
    let out = rubsim(
        tmp.path(),
        &[
            "convergence",
            scene.to_str().unwrap(),
            "--speed",
            "1.7",
            "--set",
            "run.auto_step=true",
            "--set",
            "run.revolutions=30",
            "--set",
            "run.transient_revolutions=15",
            "--set",
            "output.png=false",
            "--levels",
            "3",
            "--reference",
            "6",
            "--out",
            dir.to_str().unwrap(),
        ],
    );
    assert!(
        out.contains("chosen by run.tolerance: reduced_collocated"),
        "{out}"
    );
    let csv = common::read(&dir.join("speed_1.7/convergence.csv"));
    assert_eq!(
        csv.matches(",chosen reduced_collocated,").count(),
        1,
        "{csv}"
    );
}

/// The two-disk rotor (two stations, two stators) reduced at the default cut-off against the
/// converged full explicit run at 1.7 ω_n, where the response is periodic (docs/IMPLICIT.md
/// §7: at 1.2 and 3.1 ω_n it is not periodic in either model).
#[test]
#[ignore = "slow tier (scripts/test-slow.sh): a converged explicit reference run"]
fn the_two_disk_rotor_reduced_equals_the_converged_explicit_run() {
    let (model, s) = model_and_settings(
        TWO_DISK,
        &[
            "run.revolutions=80",
            "run.transient_revolutions=40",
            "run.error_estimate=false",
        ],
    );
    let nu = 1.7;
    let tol = s.tolerance;
    let mut red = rotor_reduction(&s);
    red.auto = false;
    // The reduced run at the paper's rule (its own step: the stability limit follows the
    // reduced ω_max), collocated.
    let mut st = s;
    st.step.integrator = Scheme::Collocated;
    st.reduction = Some(red);
    let r = run_speed(&model, &st.request(nu), Keep::default()).unwrap();
    // Converged explicit: the full model at its stability limit's step and at half of it.
    let limit = r.plan.limit.min(
        rubsim::analysis::prepare(&model, &s.request(nu))
            .unwrap()
            .plan
            .limit,
    );
    let f1 = run_at(&model, &s, nu, 0.5 * limit, None);
    let f2 = run_at(&model, &s, nu, 0.25 * limit, None);
    let conv = difference(&f1, &f2);
    let e = difference(&r, &f2);
    println!(
        "two-disk at {nu}: reduced ({} steps/rev) against converged full ({} steps/rev) {e:.2e}; full Δt against Δt/2 {conv:.2e}; periods {} {}",
        r.plan.steps_per_rev, f2.plan.steps_per_rev, r.period, f2.period
    );
    assert!(conv < 0.1 * tol, "the full run is converged: {conv:e}");
    assert_eq!(r.period, f2.period, "same regime");
    assert_eq!(r.period, 1);
    assert!(e <= tol, "{e:e}");
}
