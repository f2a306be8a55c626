//! `rubsim convergence`: error against Δt and run time for each integrator.

use super::{default_out, finish, load, settings, Common, UnitArg};
use anyhow::Result;
use rubsim::analysis::{self, convergence::COMPARE_REVOLUTIONS, ConvergenceResults};
use rubsim::output::summary::{Base, ConvergenceBody, Summary};
use rubsim::output::{csv, figures};
use std::path::PathBuf;

/// Runs the study at each speed (in its unit; default: the scene's, or ω/ω_n = 1.7, 3.1, 4.9) with levels
/// `0..=levels` against a collocated reference at level `reference`; writes
/// `speed_<ν>/convergence.csv`, its pictures and `summary.json`.
pub fn convergence(
    c: &Common,
    (speeds, unit): (&[f64], UnitArg),
    levels: u32,
    reference: u32,
    out: Option<PathBuf>,
) -> Result<()> {
    let (ls, model) = load(c)?;
    let wn = model.rotor.natural_frequency();
    let given: Vec<f64> = speeds.iter().map(|v| unit.ratio(*v, wn)).collect();
    let speeds = analysis::study_speeds(&ls.scene.run, &model, &given);
    let mut outd =
        super::open_out(&out.unwrap_or_else(|| default_out(&c.scene).join("convergence")))?;
    let mut s = settings(&ls);
    s.error_estimate = false;
    s.check_coexistence = false;
    // With `run.auto_step` (and no `run.dt`) the point the error-target choice picks at these
    // speeds is run too and marked on the pictures.
    let chosen = if ls.scene.run.auto_step {
        let mut c = super::chosen_settings(&ls, &model, &speeds)?;
        c.error_estimate = false;
        c.check_coexistence = false;
        c.choice.is_some().then_some(c)
    } else {
        None
    };
    let lv: Vec<u32> = (0..=levels).collect();
    let mut all = Vec::new();
    for v in &speeds {
        let res = analysis::convergence(
            &model,
            &s,
            *v,
            &lv,
            reference,
            COMPARE_REVOLUTIONS,
            chosen.as_ref(),
        )?;
        report(*v, &res);
        let prefix = format!("speed_{v}/");
        csv::write_convergence(&mut outd, &prefix, &res)?;
        if ls.scene.output.png {
            figures::write_convergence(&mut outd, &prefix, &ls.scene.title, &res)?;
        }
        all.push(res);
    }
    let sum = Summary {
        base: Base::new(&ls, &model, "convergence"),
        body: ConvergenceBody { studies: &all },
    };
    finish(outd, &sum)
}

/// Prints the study at ω/ω_n = `v`: the reference, one line per point, the observed orders.
fn report(v: f64, res: &ConvergenceResults) {
    println!(
        "ω/ωn = {v}: reference {} Δt = {:.3e} s, period {}",
        res.reference_integrator, res.reference_dt, res.reference_period
    );
    println!(
        "  {:>25} {:>10} {:>8} {:>10} {:>10} {:>10} {:>10} {:>6} {:>9}",
        "integrator",
        "Δt·ωn",
        "steps/rev",
        "orbit err",
        "ext err",
        "1× err",
        "sub err",
        "period",
        "wall s"
    );
    for p in &res.points {
        println!(
            "  {:>25} {:>10.3e} {:>8} {:>10.2e} {:>10.2e} {:>10.2e} {:>10.2e} {:>6} {:>9.4}",
            p.integrator,
            p.dt_wn,
            p.steps_per_rev,
            p.orbit_err,
            p.extents_err,
            p.lines_err[0],
            p.lines_err[1].max(p.lines_err[2]),
            p.period,
            p.wall_s
        );
    }
    if let Some(p) = &res.chosen {
        println!(
            "  chosen by run.tolerance: {} at {} steps/rev: orbit err {:.2e}, ext err {:.2e}, 1× err {:.2e}, sub err {:.2e}, wall {:.4} s",
            p.integrator,
            p.steps_per_rev,
            p.orbit_err,
            p.extents_err,
            p.lines_err[0],
            p.lines_err[1].max(p.lines_err[2]),
            p.wall_s
        );
    }
    for (n, o) in &res.orders {
        println!("  observed order {n}: {o:.2}");
    }
}
