//! Analyses over a model: one speed, a speed sweep, a convergence study.
//!
//! Free functions returning `*Results`; nothing here writes files (see [`crate::output`]).
//! Non-dimensional quantities (`_nd`) follow the paper: displacements over |Z0(ω)|, forces over
//! the unbalance force |Σ m_u e e^{iφ}| ω², frequencies over ω_n.

use crate::error::{Error, Result};
use crate::math::{loglog_slope, V2};
use crate::model::Model;
use crate::scene::{Component, IntegratorKind, RunSpec};
use crate::signal::{extents, hann_spectrum, line_amplitude, poincare_period};
use crate::time::{
    integrate, integrate_with, plan_steps, FrameSink, Initial, Record, RunStats, Scheme,
    StepParams, StepPlan,
};
use rayon::prelude::*;
use serde::Serialize;

/// Largest Poincaré period reported (longer ones count as not periodic).
pub const MAX_PERIOD: usize = 8;
/// Relative tolerance of the Poincaré period test (fraction of the orbit size).
pub const PERIOD_TOL: f64 = 2e-3;

/// Settings of a run at one speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSettings {
    /// Integrator and step choices.
    pub step: StepParams,
    /// Revolutions cut as transient.
    pub transient_revolutions: usize,
    /// Companion run at 2Δt for an error estimate.
    pub error_estimate: bool,
    /// Initial rotor state.
    pub initial: Initial,
    /// Analysed response component: 0 = x, 1 = y.
    pub component: usize,
}

impl RunSettings {
    /// From a scene's `[run]` table and its `output.component` (`"x"`, else y: the scene
    /// checks the name when it is loaded).
    pub fn from_run(run: &RunSpec, component: &str) -> Self {
        Self {
            step: StepParams {
                integrator: scheme(run.integrator),
                dt: run.dt,
                harmonics: run.harmonics,
                revolutions: run.revolutions,
                samples_per_rev: run.samples_per_rev,
            },
            transient_revolutions: run.transient_revolutions,
            error_estimate: run.error_estimate,
            initial: Initial {
                u: run.initial_displacement,
                v: run.initial_velocity,
            },
            component: Component::from_name(component).unwrap_or_default().index(),
        }
    }
}

/// The time loop's scheme for the scene's `run.integrator`.
pub fn scheme(kind: IntegratorKind) -> Scheme {
    match kind {
        IntegratorKind::ForwardIncrement => Scheme::ForwardIncrement,
        IntegratorKind::Collocated => Scheme::Collocated,
    }
}

/// Which heavy data a speed result keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Keep {
    /// The steady orbit (analysis window).
    pub orbit: bool,
    /// The contact-force history of the whole run.
    pub force_history: bool,
    /// The spectrum up to this frequency (f/ω_n); 0 keeps none.
    pub spectrum_up_to: Option<u32>,
}

/// Discretisation-error estimate from a companion run at about 2Δt (Richardson, nominal order).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ErrorEstimate {
    /// Companion Δt (s): about 2Δt, or Δt/2 when 2Δt would be unstable.
    pub dt_coarse: f64,
    /// Order assumed.
    pub order: f64,
    /// Estimated relative error of the orbit extents (of the finer run).
    pub extents_rel: f64,
    /// Estimated error of the 1×, 1/2×, 1/3× amplitudes relative to the largest of them.
    pub lines_rel: f64,
    /// Whether the companion run found the same Poincaré period.
    pub same_period: bool,
}

/// Results of a run at one speed.
#[derive(Debug, Clone, Serialize)]
pub struct SpeedResults {
    /// ω/ω_n.
    pub speed_ratio: f64,
    /// ω (rad/s).
    pub omega: f64,
    /// Rotor node whose response is analysed (orbit, Poincaré section, spectrum, extents).
    pub node: usize,
    /// |Z0(ω)| at the analysed node (m).
    pub z0: f64,
    /// Clearance of each stator at this speed (m).
    pub clearances: Vec<f64>,
    /// Unbalance force |U| ω² (N).
    pub unbalance_force: f64,
    /// Poincaré period 1–8, 0 when not periodic.
    pub period: usize,
    /// `[x_min, x_max, y_min, y_max]` / |Z0| over the analysis window.
    pub extents_nd: [f64; 4],
    /// 1× amplitude of the analysed component / |Z0|.
    pub amp_1x_nd: f64,
    /// 1/2× amplitude / |Z0|.
    pub amp_half_nd: f64,
    /// 1/3× amplitude / |Z0|.
    pub amp_third_nd: f64,
    /// Largest contact-force magnitude on station 0 in the analysis window / |U|ω².
    pub contact_force_max_nd: f64,
    /// Fraction of recorded samples in the analysis window with contact.
    pub contact_fraction: f64,
    /// Step plan.
    pub plan: StepPlan,
    /// Loop counters.
    pub stats: RunStats,
    /// Error estimate (None when not asked or not possible).
    pub error: Option<ErrorEstimate>,
    /// Poincaré points / |Z0| (analysis window).
    pub poincare_nd: Vec<V2>,
    /// Steady orbit / |Z0| (kept on request).
    #[serde(skip)]
    pub orbit_nd: Vec<V2>,
    /// Time in revolutions and vertical force on the stator / |U|ω² (kept on request).
    #[serde(skip)]
    pub force_history: Vec<(f64, f64)>,
    /// Spectrum: (f/ω_n, amplitude/|Z0|) (kept on request).
    #[serde(skip)]
    pub spectrum: Vec<(f64, f64)>,
}

/// Runs one speed: builds the case, plans Δt, integrates, analyses.
pub fn run_speed(
    model: &Model,
    s: &RunSettings,
    speed_ratio: f64,
    keep: Keep,
) -> Result<SpeedResults> {
    run_speed_with(model, s, speed_ratio, keep, None)
}

/// [`run_speed`] with a [`FrameSink`] receiving the main run's frames (not the error
/// estimate's companion run).
pub fn run_speed_with(
    model: &Model,
    s: &RunSettings,
    speed_ratio: f64,
    keep: Keep,
    sink: Option<&mut dyn FrameSink>,
) -> Result<SpeedResults> {
    let omega = speed_ratio * model.rotor.natural_frequency();
    let case = model.case(omega)?;
    let plan = plan_steps(&case, &s.step)?;
    let (rec, stats) = integrate_with(&case, s.step.integrator, &plan, s.initial, sink)?;
    let mut res = analyse(&case, s, &plan, &rec, stats, keep);
    if s.error_estimate {
        // Companion run at 2Δt; when 2Δt is above the stability limit, at Δt/2 instead.
        let mut coarse = s.step;
        coarse.dt = Some(2.0 * plan.dt);
        let cplan = plan_steps(&case, &coarse)
            .ok()
            .filter(|c| c.steps_per_rev < plan.steps_per_rev)
            .or_else(|| {
                let mut fine = s.step;
                fine.dt = Some(0.5 * plan.dt);
                plan_steps(&case, &fine).ok()
            });
        if let Some(cplan) = cplan.filter(|c| c.steps_per_rev != plan.steps_per_rev) {
            if let Ok((crec, cstats)) = integrate(&case, s.step.integrator, &cplan, s.initial) {
                {
                    let c = analyse(&case, s, &cplan, &crec, cstats, Keep::default());
                    // Error of the main run ≈ |Q_h − Q_c| / |r^p − 1|, r = h_c / h.
                    let r = plan.steps_per_rev as f64 / cplan.steps_per_rev as f64;
                    let p = s.step.integrator.nominal_order();
                    let denom = (r.powf(p) - 1.0).abs();
                    let span = extent_scale(&res.extents_nd);
                    let ext = (0..4)
                        .map(|i| (res.extents_nd[i] - c.extents_nd[i]).abs())
                        .fold(0.0, f64::max)
                        / span
                        / denom;
                    let lines = [res.amp_1x_nd, res.amp_half_nd, res.amp_third_nd];
                    let clines = [c.amp_1x_nd, c.amp_half_nd, c.amp_third_nd];
                    let lmax = lines.iter().fold(1e-300_f64, |m, v| m.max(*v));
                    let lerr = lines
                        .iter()
                        .zip(clines)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max)
                        / lmax
                        / denom;
                    res.error = Some(ErrorEstimate {
                        dt_coarse: cplan.dt,
                        order: p,
                        extents_rel: ext,
                        lines_rel: lerr,
                        same_period: c.period == res.period,
                    });
                }
            }
        }
    }
    Ok(res)
}

fn extent_scale(e: &[f64; 4]) -> f64 {
    e.iter().fold(1e-300_f64, |m, v| m.max(v.abs()))
}

/// Analysis of a record: transient cut, Poincaré section, extents, spectrum, contact forces.
pub fn analyse(
    case: &crate::model::Case,
    s: &RunSettings,
    plan: &StepPlan,
    rec: &Record,
    stats: RunStats,
    keep: Keep,
) -> SpeedResults {
    let spr = s.step.samples_per_rev;
    let z0 = if case.z0 > 0.0 { case.z0 } else { 1.0 };
    let fu = if case.unbalance_force > 0.0 {
        case.unbalance_force
    } else {
        1.0
    };
    let first = s.transient_revolutions * spr;
    let last = (s.step.revolutions * spr).min(rec.len().saturating_sub(1));
    let window: Vec<V2> = (first..last)
        .map(|i| {
            let d = rec.observed[i];
            [d[0] / z0, d[1] / z0]
        })
        .collect();
    let poincare: Vec<V2> = (first..=last)
        .step_by(spr)
        .map(|i| {
            let d = rec.observed[i];
            [d[0] / z0, d[1] / z0]
        })
        .collect();
    let ext = extents(&window);
    let span = (ext[1] - ext[0]).max(ext[3] - ext[2]);
    let period = poincare_period(&poincare, span, MAX_PERIOD, PERIOD_TOL);
    let comp: Vec<f64> = window.iter().map(|p| p[s.component]).collect();
    let spec = hann_spectrum(&comp);
    let nrev = (last - first) as f64 / spr as f64;
    let amp = |order: f64| line_amplitude(&spec, order * nrev);
    let mut fmax = 0.0_f64;
    let mut ncontact = 0usize;
    for i in first..last {
        let f = rec.force_at(i, 0);
        let m = f[0].hypot(f[1]);
        fmax = fmax.max(m);
        if rec.active[i] > 0 {
            ncontact += 1;
        }
    }
    let spectrum = match keep.spectrum_up_to {
        Some(fm) => spec
            .iter()
            .enumerate()
            .map(|(k, a)| (k as f64 / nrev * case.speed_ratio, *a))
            .take_while(|(f, _)| *f <= fm as f64 + 1e-9)
            .collect(),
        None => Vec::new(),
    };
    let t_rev = 2.0 * std::f64::consts::PI / case.omega;
    SpeedResults {
        speed_ratio: case.speed_ratio,
        omega: case.omega,
        node: case.observed_node,
        z0: case.z0,
        clearances: case.stators.iter().map(|s| s.clearance).collect(),
        unbalance_force: case.unbalance_force,
        period,
        extents_nd: ext,
        amp_1x_nd: amp(1.0),
        amp_half_nd: amp(0.5),
        amp_third_nd: amp(1.0 / 3.0),
        contact_force_max_nd: fmax / fu,
        contact_fraction: if last > first {
            ncontact as f64 / (last - first) as f64
        } else {
            0.0
        },
        plan: *plan,
        stats,
        error: None,
        poincare_nd: poincare,
        orbit_nd: if keep.orbit { window } else { Vec::new() },
        force_history: if keep.force_history {
            (0..rec.len())
                .map(|i| (rec.t[i] / t_rev, -rec.force_at(i, 0)[1] / fu))
                .collect()
        } else {
            Vec::new()
        },
        spectrum,
    }
}

/// The speeds of a sweep (inclusive, rounded to the step's decimals to avoid drift).
pub fn sweep_speeds(from: f64, to: f64, step: f64) -> Vec<f64> {
    let n = ((to - from) / step + 1e-9).floor() as usize;
    (0..=n)
        .map(|i| {
            let v = from + i as f64 * step;
            (v * 1e9).round() / 1e9
        })
        .collect()
}

/// Results of a sweep.
#[derive(Debug, Clone, Serialize)]
pub struct SweepResults {
    /// Per-speed results, in speed order.
    pub speeds: Vec<SpeedResults>,
    /// Wall time of the whole sweep (s).
    pub wall_s: f64,
}

impl SweepResults {
    /// Steps of the main runs (companion runs of the error estimate excluded).
    pub fn total_steps(&self) -> usize {
        self.speeds.iter().map(|r| r.stats.steps).sum()
    }
    /// Largest estimated relative orbit-extents error over the speeds (0 when not estimated).
    pub fn max_estimated_error(&self) -> f64 {
        self.speeds
            .iter()
            .filter_map(|r| r.error.map(|e| e.extents_rel))
            .fold(0.0, f64::max)
    }
}

/// Runs all speeds in parallel (rayon); `progress` is called after each speed.
pub fn sweep(
    model: &Model,
    s: &RunSettings,
    speeds: &[f64],
    keep: &(dyn Fn(f64) -> Keep + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<SweepResults> {
    sweep_with(speeds, &|v| run_speed(model, s, v, keep(v)), progress)
}

/// Runs `run(ω/ω_n)` for all speeds in parallel (rayon), e.g. [`run_speed_with`] with a
/// per-speed [`FrameSink`]; `progress` is called after each speed.
pub fn sweep_with(
    speeds: &[f64],
    run: &(dyn Fn(f64) -> Result<SpeedResults> + Sync),
    progress: &(dyn Fn() + Sync),
) -> Result<SweepResults> {
    let t0 = std::time::Instant::now();
    let res: Vec<Result<SpeedResults>> = speeds
        .par_iter()
        .map(|&v| {
            let r = run(v).map_err(|e| Error::AtSpeed {
                speed_ratio: v,
                source: Box::new(e),
            });
            progress();
            r
        })
        .collect();
    let speeds = res.into_iter().collect::<Result<Vec<_>>>()?;
    Ok(SweepResults {
        speeds,
        wall_s: t0.elapsed().as_secs_f64(),
    })
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
    /// Reference integrator.
    pub reference_integrator: &'static str,
    /// Reference period.
    pub reference_period: usize,
    /// Points.
    pub points: Vec<ConvergencePoint>,
    /// Observed orders (fitted log–log slope of orbit error against Δt) per integrator.
    pub orders: Vec<(&'static str, f64)>,
}

/// Runs each integrator at steps-per-revolution `spr·2^k` for `k in levels` and compares with a
/// collocated reference at `spr·2^ref_level`. Revolutions and transient from `s`.
pub fn convergence(
    model: &Model,
    s: &RunSettings,
    speed_ratio: f64,
    levels: &[u32],
    ref_level: u32,
    compare_revs: usize,
) -> Result<ConvergenceResults> {
    let omega = speed_ratio * model.rotor.natural_frequency();
    let case = model.case(omega)?;
    let spr = s.step.samples_per_rev;
    let t_rev = 2.0 * std::f64::consts::PI / omega;
    let run = |kind: Scheme, level: u32| -> Result<(SpeedResults, Record)> {
        let mut st = *s;
        st.step.integrator = kind;
        st.step.dt = Some(t_rev / (spr as f64 * (1u64 << level) as f64) * (1.0 + 1e-12));
        let plan = plan_steps(&case, &st.step)?;
        let (rec, stats) = integrate(&case, kind, &plan, st.initial)?;
        let r = analyse(&case, &st, &plan, &rec, stats, Keep::default());
        Ok((r, rec))
    };
    let (rref, recref) = run(Scheme::Collocated, ref_level)?;
    let nrec = recref.len();
    let cmp_from = nrec.saturating_sub(compare_revs * spr + 1);
    let ref_orbit: Vec<V2> = (cmp_from..nrec).map(|i| recref.observed[i]).collect();
    let ref_size = ref_orbit
        .iter()
        .fold(0.0_f64, |m, p| m.max(p[0].hypot(p[1])))
        .max(1e-300);
    let ref_lines = [rref.amp_1x_nd, rref.amp_half_nd, rref.amp_third_nd];
    let lmax = ref_lines.iter().fold(1e-300_f64, |m, v| m.max(*v));
    let ref_span = extent_scale(&rref.extents_nd);
    let mut points = Vec::new();
    let mut orders = Vec::new();
    for kind in [Scheme::ForwardIncrement, Scheme::Collocated] {
        let mut dts = Vec::new();
        let mut errs = Vec::new();
        for &l in levels {
            let (r, rec) = match run(kind, l) {
                Ok(x) => x,
                Err(Error::Solve(crate::error::SolveError::StepTooLarge { .. })) => continue,
                Err(e) => return Err(e),
            };
            let n = rec.len().min(nrec);
            let from = n.saturating_sub(compare_revs * spr + 1);
            let mut oerr = 0.0_f64;
            for (k, i) in (from..n).enumerate() {
                let a = rec.observed[i];
                let b = ref_orbit[k.min(ref_orbit.len() - 1)];
                oerr = oerr.max((a[0] - b[0]).hypot(a[1] - b[1]));
            }
            let lines = [r.amp_1x_nd, r.amp_half_nd, r.amp_third_nd];
            let ext_err = (0..4)
                .map(|i| (r.extents_nd[i] - rref.extents_nd[i]).abs())
                .fold(0.0, f64::max)
                / ref_span;
            points.push(ConvergencePoint {
                integrator: kind.name(),
                dt: r.plan.dt,
                dt_wn: r.plan.dt * model.rotor.natural_frequency(),
                steps_per_rev: r.plan.steps_per_rev,
                orbit_err: oerr / ref_size,
                extents_err: ext_err,
                lines_err: [
                    (lines[0] - ref_lines[0]).abs() / lmax,
                    (lines[1] - ref_lines[1]).abs() / lmax,
                    (lines[2] - ref_lines[2]).abs() / lmax,
                ],
                period: r.period,
                wall_s: r.stats.wall_s,
                steps: r.stats.steps,
            });
            dts.push(r.plan.dt);
            errs.push(oerr / ref_size);
        }
        orders.push((kind.name(), loglog_slope(&dts, &errs)));
    }
    Ok(ConvergenceResults {
        speed_ratio,
        reference_dt: rref.plan.dt,
        reference_integrator: Scheme::Collocated.name(),
        reference_period: rref.period,
        points,
        orders,
    })
}
