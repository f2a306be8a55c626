//! A convergence study at one speed: each integrator (the two explicit ones, Newmark and
//! generalised-α) at steps per revolution `spr·2^k` against a collocated reference at a finer
//! level (generalised-α where that step is above the explicit stability limit). A level an
//! integrator refuses (above its stability limit, an implicit step that does not resolve the
//! contact frequency, Newmark with a stator with mass) or at which the run diverges is left
//! out. An FE rotor is run in its modal reduction too (`[run.reduction]` at its default
//! cut-off, collocated and generalised-α: [`REDUCED_COLLOCATED`], [`REDUCED_GENERALIZED_ALPHA`])
//! against the full model's reference. With settings chosen from `run.tolerance`
//! ([`crate::analysis::choose`]) the chosen point is measured against the same reference
//! ([`convergence`]'s `chosen`).

use super::discrepancy::{Discrepancy, ExtentsScale, Scales};
use super::{analyse, Keep, RunRequest, RunSettings, SpeedResults};
use crate::error::{Error, Result};
use crate::math::{loglog_slope, V2};
use crate::model::{Case, Model, Rotor};
use crate::resolve::ReductionInput;
use crate::time::{integrate, plan_steps, Record, Scheme};
use serde::Serialize;

/// Revolutions at the end of the runs whose orbits `rubsim convergence` compares.
pub const COMPARE_REVOLUTIONS: usize = 12;

/// Label of the FE rotor's reduced model (`[run.reduction]` at its default cut-off) integrated
/// by collocation in a convergence study.
pub const REDUCED_COLLOCATED: &str = "reduced_collocated";

/// Label of the FE rotor's reduced model integrated by generalised-α in a convergence study.
pub const REDUCED_GENERALIZED_ALPHA: &str = "reduced_generalized_alpha";

/// The case of an FE rotor reduced as `[run.reduction]` with its default cut-off
/// (κ = [`crate::scene::DEFAULT_CUTOFF_FACTOR`], `run.harmonics` of `s`) would reduce it; `None`
/// for a Jeffcott rotor, a model that is reduced already, or a rotor the reduction refuses
/// (free axial or torsional DOFs: no static column).
pub fn reduced_case(model: &Model, s: &RunSettings, case: &Case) -> Option<Case> {
    if !matches!(model.rotor, Rotor::Fe(_)) || model.reduction.is_some() {
        return None;
    }
    let input = ReductionInput {
        cutoff: None,
        cutoff_factor: crate::scene::DEFAULT_CUTOFF_FACTOR,
        harmonics: s.step.harmonics,
        rotor: true,
        stators: false,
        auto: false,
    };
    case.clone().reduced_by(Some(&input)).ok()
}

/// One point of a convergence study.
#[derive(Debug, Clone, Serialize)]
pub struct ConvergencePoint {
    /// Integrator.
    pub integrator: &'static str,
    /// Δt (s).
    pub dt: f64,
    /// Δt·ω_n.
    pub dt_wn: f64,
    /// Steps per revolution.
    pub steps_per_rev: usize,
    /// Relative orbit error over the last revolutions (phase-locked, max norm / orbit size).
    pub orbit_err: f64,
    /// Relative error of the orbit extents.
    pub extents_err: f64,
    /// Errors of the 1×, 1/2×, 1/3× amplitudes relative to the largest reference line.
    pub lines_err: [f64; 3],
    /// Poincaré period found.
    pub period: usize,
    /// Wall time of the loop (s).
    pub wall_s: f64,
    /// Steps taken.
    pub steps: usize,
}

/// A convergence study at one speed.
#[derive(Debug, Clone, Serialize)]
pub struct ConvergenceResults {
    /// ω/ω_n.
    pub speed_ratio: f64,
    /// Reference Δt (s) and integrator.
    pub reference_dt: f64,
    /// Reference integrator: collocated, or generalised-α (ρ∞ = the default) when the
    /// reference step is above the explicit stability limit.
    pub reference_integrator: &'static str,
    /// Reference period.
    pub reference_period: usize,
    /// Points.
    pub points: Vec<ConvergencePoint>,
    /// Observed orders (fitted log–log slope of orbit error against Δt) per integrator.
    pub orders: Vec<(&'static str, f64)>,
    /// The point the error-target choice picks (`run.auto_step`: its integrator at its multiple
    /// of the paper's rule, [`crate::analysis::StepChoice`]), measured like the others; `None`
    /// when the study was not given one.
    pub chosen: Option<ConvergencePoint>,
}

/// A run of `case` with `s`'s settings by `kind` at `spr·2^level` steps per revolution of
/// `t_rev` (s): its results and record.
fn run_at(
    case: &Case,
    s: &RunSettings,
    kind: Scheme,
    level: u32,
    t_rev: f64,
) -> Result<(SpeedResults, Record)> {
    let spr = s.step.samples_per_rev;
    let dt = t_rev / (spr as f64 * (1u64 << level) as f64) * (1.0 + 1e-12);
    run_fixed(case, &RunRequest::at_step(s, case.speed_ratio, kind, dt))
}

/// `request` on `case` over its own plan as it stands (a study's level, not a settling run):
/// its results and record.
fn run_fixed(case: &Case, request: &RunRequest) -> Result<(SpeedResults, Record)> {
    let plan = plan_steps(case, &request.step)?;
    let (rec, stats) = integrate(case, request.step.integrator, &plan, request.initial())?;
    let r = analyse(case, request, &plan, &rec, stats, Keep::default());
    Ok((r, rec))
}

/// The reference run of a study and what a run is measured against.
struct Reference {
    /// The reference's results.
    results: SpeedResults,
    /// Its record's length.
    nrec: usize,
    /// Its orbit over the compared revolutions (m).
    orbit: Vec<V2>,
    /// The largest |orbit| over them (m, at least 1e-300).
    size: f64,
    /// Its scales ([`ExtentsScale::Largest`]).
    scales: Scales,
    /// Samples compared: `compare_revs · samples_per_rev + 1`.
    compared: usize,
    /// ω_n (rad/s).
    wn: f64,
}

impl Reference {
    fn new(results: SpeedResults, rec: &Record, compared: usize, wn: f64) -> Self {
        let nrec = rec.len();
        let cmp_from = nrec.saturating_sub(compared);
        let orbit: Vec<V2> = (cmp_from..nrec).map(|i| rec.observed[i]).collect();
        let size = orbit
            .iter()
            .fold(0.0_f64, |m, p| m.max(p[0].hypot(p[1])))
            .max(1e-300);
        let scales = Scales::of(&results, ExtentsScale::Largest);
        Self {
            results,
            nrec,
            orbit,
            size,
            scales,
            compared,
            wn,
        }
    }

    /// A run's point: orbit error over the compared revolutions (phase-locked sample by sample
    /// with the reference), extents and lines against the reference's ([`Discrepancy`]).
    fn measure(&self, label: &'static str, r: &SpeedResults, rec: &Record) -> ConvergencePoint {
        let n = rec.len().min(self.nrec);
        let from = n.saturating_sub(self.compared);
        let mut oerr = 0.0_f64;
        for (k, i) in (from..n).enumerate() {
            let a = rec.observed[i];
            let b = self.orbit[k.min(self.orbit.len() - 1)];
            oerr = oerr.max((a[0] - b[0]).hypot(a[1] - b[1]));
        }
        let d = Discrepancy::between(r, &self.results, self.scales);
        ConvergencePoint {
            integrator: label,
            dt: r.plan.dt,
            dt_wn: r.plan.dt * self.wn,
            steps_per_rev: r.plan.steps_per_rev,
            orbit_err: oerr / self.size,
            extents_err: d.extents,
            lines_err: d.each_line,
            period: r.period,
            wall_s: r.stats.wall_s,
            steps: r.stats.steps,
        }
    }
}

/// Runs each integrator at steps-per-revolution `spr·2^k` for `k in levels` and compares with
/// a collocated reference at `spr·2^ref_level` (revolutions and transient from `s`); with
/// `chosen` (settings returned by [`crate::analysis::choose`]: integrator and `dt_scale` set,
/// Δt from the paper's rule), that run too, measured against the same reference
/// ([`ConvergenceResults::chosen`]).
pub fn convergence(
    model: &Model,
    s: &RunSettings,
    speed_ratio: f64,
    levels: &[u32],
    ref_level: u32,
    compare_revs: usize,
    chosen: Option<&RunSettings>,
) -> Result<ConvergenceResults> {
    let omega = speed_ratio * model.rotor.natural_frequency();
    let case = model.case(omega)?;
    let spr = s.step.samples_per_rev;
    let t_rev = 2.0 * std::f64::consts::PI / omega;
    let run = |kind: Scheme, level: u32| run_at(&case, s, kind, level, t_rev);
    // The reference: collocated, or generalised-α at the same step where that is above the
    // explicit stability limit (a stiff stator with mass).
    let rho = match s.step.integrator {
        Scheme::GeneralizedAlpha { rho_inf } => rho_inf,
        _ => super::default_rho_inf(&case),
    };
    let (ref_scheme, (rref, recref)) = match run(Scheme::Collocated, ref_level) {
        Err(Error::Solve(crate::error::SolveError::StepTooLarge { .. })) => {
            let g = Scheme::GeneralizedAlpha { rho_inf: rho };
            (g, run(g, ref_level)?)
        }
        r => (Scheme::Collocated, r?),
    };
    let wn = model.rotor.natural_frequency();
    let reference = Reference::new(rref, &recref, compare_revs * spr + 1, wn);
    // Generalised-α at the scene's ρ∞ when it asks for it, else at the default.
    let alpha = match s.step.integrator {
        g @ Scheme::GeneralizedAlpha { .. } => g,
        _ => Scheme::GeneralizedAlpha { rho_inf: rho },
    };
    // The FE rotor in its modal reduction beside the full model (unless the scene reduces it
    // already, when every run is reduced): explicit and implicit, against the same reference.
    let reduced = reduced_case(model, s, &case);
    let mut runs: Vec<(Scheme, &'static str, &Case)> = vec![
        (
            Scheme::ForwardIncrement,
            Scheme::ForwardIncrement.name(),
            &case,
        ),
        (Scheme::Collocated, Scheme::Collocated.name(), &case),
        (Scheme::Newmark, Scheme::Newmark.name(), &case),
        (alpha, alpha.name(), &case),
    ];
    if let Some(rc) = &reduced {
        runs.push((Scheme::Collocated, REDUCED_COLLOCATED, rc));
        runs.push((alpha, REDUCED_GENERALIZED_ALPHA, rc));
    }
    let mut points = Vec::new();
    let mut orders = Vec::new();
    for (kind, label, on) in runs {
        let mut dts = Vec::new();
        let mut errs = Vec::new();
        for &l in levels {
            let (r, rec) = match run_at(on, s, kind, l, t_rev) {
                Ok(x) => x,
                // A level above the scheme's limits, a scheme the scene refuses (Newmark with
                // a stator with mass) or a run that diverges at that step is left out (the
                // picture shows where each scheme works).
                Err(Error::Solve(
                    crate::error::SolveError::StepTooLarge { .. }
                    | crate::error::SolveError::StepTooCoarse { .. }
                    | crate::error::SolveError::Meaningless { .. }
                    | crate::error::SolveError::Diverged { .. }
                    | crate::error::SolveError::NonFinite { .. },
                )) => continue,
                Err(e) => return Err(e),
            };
            let p = reference.measure(label, &r, &rec);
            dts.push(r.plan.dt);
            errs.push(p.orbit_err);
            points.push(p);
        }
        orders.push((label, loglog_slope(&dts, &errs)));
    }
    let chosen = match chosen {
        Some(c) => Some(measure_chosen(model, omega, &case, c, &reference)?),
        None => None,
    };
    Ok(ConvergenceResults {
        speed_ratio,
        reference_dt: reference.results.plan.dt,
        reference_integrator: ref_scheme.name(),
        reference_period: reference.results.period,
        points,
        orders,
        chosen,
    })
}

/// The run of the chosen settings `c` at ω = `omega` (rad/s) measured against `reference`: a
/// reduced scheme chosen runs its own reduction (the cut-off chosen with it), labelled as the
/// reduced rows are.
fn measure_chosen(
    model: &Model,
    omega: f64,
    case: &Case,
    c: &RunSettings,
    reference: &Reference,
) -> Result<ConvergencePoint> {
    let reduced_case;
    let (on, label) = match &c.reduction {
        Some(red) => {
            reduced_case = model.case_with(omega, Some(red))?;
            let label = match c.step.integrator {
                Scheme::Collocated => REDUCED_COLLOCATED,
                Scheme::GeneralizedAlpha { .. } => REDUCED_GENERALIZED_ALPHA,
                _ => "reduced",
            };
            (&reduced_case, label)
        }
        None => (case, c.step.integrator.name()),
    };
    let (r, rec) = run_fixed(on, &c.request(case.speed_ratio).fixed())?;
    Ok(reference.measure(label, &r, &rec))
}
