//! Periodic orbits of an autonomous rotor–stator system by shooting with an unknown period and
//! a phase condition (issue 29, item 1): a whirl at its own frequency — dry whip, a rub's
//! self-excited backward whirl — where nothing forces the motion at the spin's period.
//!
//! **Autonomous.** Without unbalance and without loads fixed in the rotor's frame, a
//! constant-speed run's equations do not depend on time: the spin enters only as a speed (the
//! gyroscopic terms, the slip speed `Ω R` of friction). A periodic orbit's period `T` is then
//! one more unknown, and any time shift of an orbit is an orbit too, so the fixed point is
//! pinned by a phase condition.
//!
//! **The map.** `N` steps of the run's scheme with the step `Δt = T/N` (`N` fixed, from the
//! settled run's whirl frequency and its step): `P_T(x)`, the state `x = (uᴺ, uᴺ⁻¹)` of every
//! body of central differences ([`EndState::state_vector`]) held at the reference step
//! `Δt₀ = T₀/N` — carried to `Δt` before the steps and back after them (`EndState::retimed`:
//! the increments scaled, a velocity kept), so that `x` means the same motion whatever `T`.
//! A periodic orbit is a fixed point `P_T(x) = x`: the discrete orbit of the scheme at the step
//! `T/N`, closing after `N` steps.
//!
//! **Newton with a phase condition.** The unknowns are `x` less one component `x_j` and `T`:
//! `x_j` is held at its start value (a Poincaré section through the settled state, `j` the
//! displacement whose increment is largest there, so the orbit crosses it transversally) —
//! `n` equations `P_T(x) − x = 0` in `n` unknowns. The Jacobian's columns are central
//! differences of the map (`∂P/∂x_i` at relative step 1e-5 of max |x|, `∂P/∂T` at 1e-6 T);
//! steps are halved while the residual does not fall; converged at
//! [`super::periodic::SHOOT_TOLERANCE`], else reported after
//! [`super::periodic::MAX_NEWTON`] iterations (a whirl that is not periodic: a torus, chaos).
//!
//! **Floquet multipliers.** The monodromy `∂P_T/∂x` at the fixed point and fixed `T`: one
//! multiplier is 1 — the orbit shifted along itself — to the differences' accuracy (its
//! distance from 1 is reported, a check of the orbit), the others decide its stability.

use super::periodic::{floquet, residual, restarted, run_to_end, MAX_HALVINGS, MAX_NEWTON};
use super::periodic::{MAX_STATE, SHOOT_TOLERANCE};
use super::speed::{analyse, Prepared};
use super::Keep;
use crate::error::{Error, Result};
use crate::time::{EndState, Record, RunStats, Sink, StepPlan};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Relative central-difference step of the state's columns (of the largest displacement, or
/// increment): 1e-4 balances the map's round-off against the differences' truncation (the
/// dry whip's trivial multiplier 1 to 6.8e-7, against 5.4e-6 at 1e-5 and 1.3e-6 at 1e-3).
const FD_STATE: f64 = 1e-4;
/// Relative central-difference step of the period's column (of T).
const FD_PERIOD: f64 = 1e-6;

/// An autonomous periodic orbit (module docs) and its stability.
#[derive(Debug, Clone, Serialize)]
pub struct AutonomousOrbit {
    /// The value of the parameter a branch is continued in (ν, or a scene key's value); ν for
    /// a single orbit.
    pub parameter: f64,
    /// ν = Ω/ω_n.
    pub speed_ratio: f64,
    /// Whether Newton met the shooting tolerance.
    pub converged: bool,
    /// Newton iterations taken.
    pub iterations: usize,
    /// `max |P_T(x) − x| / max |x|` at the last iterate.
    pub residual: f64,
    /// The period T (s).
    pub period_s: f64,
    /// The period the settled run's whirl line gave, Newton's start (s).
    pub start_period_s: f64,
    /// The whirl's frequency `±2π/T` (rad/s): negative for a backward whirl (against the
    /// spin), read from the orbit's sense of turning at the first station.
    pub whirl_frequency: f64,
    /// The whirl's frequency over ω_n, signed.
    pub whirl_ratio: f64,
    /// The whirl's frequency over Ω (its order in a spectrum), signed.
    pub order: f64,
    /// N: steps of the period; Δt = T/N (s).
    pub steps_per_period: usize,
    /// Δt = T/N (s).
    pub dt_s: f64,
    /// The first station's smallest and largest radius over the period (m).
    pub radius_m: [f64; 2],
    /// Fraction of the period's steps in contact at the first station.
    pub contact_fraction: f64,
    /// The Floquet multipliers `[Re ρ, Im ρ]`, largest modulus first, the trivial one among
    /// them.
    pub multipliers: Vec<[f64; 2]>,
    /// The multiplier of the shift along the orbit (the one nearest 1).
    pub trivial_multiplier: [f64; 2],
    /// The largest |ρ| of the others.
    pub largest_modulus: f64,
    /// Converged and every other |ρ| < 1.
    pub stable: bool,
    /// How the largest other multiplier leaves the unit circle when it does
    /// (`period_doubling`, `fold`, `neimark_sacker`); `None` when stable.
    pub instability: Option<&'static str>,
    /// Components of the state x.
    pub state_size: usize,
    /// Steps integrated in all.
    pub steps: u64,
    /// The fixed point x at the reference step, and its layout.
    #[serde(skip)]
    pub(crate) fixed_point: (Vec<f64>, EndState),
}

impl AutonomousOrbit {
    /// The fixed point `x` at the reference step `T₀/N` ([`EndState::state_vector`]'s
    /// layout).
    pub fn fixed_state(&self) -> &[f64] {
        &self.fixed_point.0
    }

    /// The step plan of the orbit's time series on `plan` (its run's): `2N` steps of
    /// `Δt = T/N` from the fixed point, nothing cut — the first period a lead-in, the second
    /// written (`results::Series::autonomous_orbit`) —, `N` steps to the plan's "revolution",
    /// which is here one period `T` of the whirl, not of the shaft.
    pub fn series_plan(&self, plan: &StepPlan) -> StepPlan {
        let n = self.steps_per_period.max(1);
        StepPlan {
            dt: self.period_s / n as f64,
            steps: 2 * n,
            steps_per_rev: n,
            steady_from: 0,
            ..*plan
        }
    }

    /// Integrates the orbit (found on `prep`) from its fixed point over `plan`
    /// ([`AutonomousOrbit::series_plan`]), handing its frames to `sink`; the record and
    /// counters.
    ///
    /// # Errors
    /// A state that does not restart the run's scheme; the run's errors.
    pub fn integrate(
        &self,
        prep: &Prepared,
        plan: &StepPlan,
        sink: Sink<'_>,
    ) -> Result<(Record, RunStats)> {
        let (x, end) = &self.fixed_point;
        let start = end
            .with_state_vector(x)
            .ok_or_else(not_fitting)?
            .retimed(plan.dt);
        Ok(restarted(prep, plan, &start)?.run(sink)?)
    }
}

/// Runs `prep` to its settled state, reads its whirl frequency and shoots the autonomous
/// periodic orbit near it (module docs).
///
/// # Errors
/// [`Error::Study`] naming the key for a system that is not autonomous (an unbalance, a load
/// fixed in the rotor), a settled run with no whirl to start from, an implicit scheme or a
/// state above [`MAX_STATE`]; the runs' errors.
pub fn shoot_autonomous(prep: &Prepared) -> Result<AutonomousOrbit> {
    autonomous(prep)?;
    let mut req = prep.request;
    req.follow_ups.error_estimate = true;
    let (rec, stats, plan, end, _) = prep.drive_with(&prep.plan, &req, None)?;
    let settled = analyse(&prep.case, &req, &plan, &rec, stats, Keep::default());
    let end = end.ok_or_else(|| {
        Error::study(
            "run.integrator",
            "shooting restarts the run's scheme from its settled state, which this run does not keep (an implicit scheme or a fixed window `run.duration`): use an explicit scheme with a settling window",
        )
    })?;
    if settled.contact_fraction == 0.0 {
        return Err(Error::study(
            "stator",
            format!(
                "the settled run at ω/ωn = {:.4} never touches a stator: without contact and without forcing a damped rotor's motion decays — no self-excited orbit to shoot (start it in contact with `run.initial_displacement`, `run.initial_velocity`, or reduce the clearance)",
                prep.speed_ratio
            ),
        ));
    }
    let order = settled.whirl.dominant_order;
    let radius = settled.whirl.dominant_nd;
    if !(order.is_finite() && order.abs() > 1e-9 && radius > 0.0) {
        return Err(Error::study(
            "run",
            format!(
                "the settled run at ω/ωn = {:.4} does not whirl (no line in its spectrum to start from): an autonomous orbit needs a motion to start from — `run.initial_displacement`, `run.initial_velocity`",
                prep.speed_ratio
            ),
        ));
    }
    let t0 = std::f64::consts::TAU / (order.abs() * prep.omega);
    let n = ((t0 / prep.plan.dt).round() as usize).max(8);
    let mut o = shoot_period(prep, end, t0, n)?;
    o.steps += settled.stats.steps as u64;
    Ok(o)
}

/// The orbit of `prep` by Newton from `from`, an orbit at a neighbouring value of a branch's
/// parameter: its fixed point and period the start, its `N` steps a period kept, so that every
/// point of a branch is a fixed point of one map, smooth in the parameter
/// ([`super::autonomous_branch`]).
///
/// # Errors
/// As [`shoot_autonomous`]; [`Error::Study`] for a state that does not fit `prep`'s run.
pub fn shoot_autonomous_from(prep: &Prepared, from: &AutonomousOrbit) -> Result<AutonomousOrbit> {
    autonomous(prep)?;
    let (x, layout) = &from.fixed_point;
    let end = layout.with_state_vector(x).ok_or_else(not_fitting)?;
    shoot_period(prep, end, from.period_s, from.steps_per_period)
}

/// Refuses a case that is not autonomous.
fn autonomous(prep: &Prepared) -> Result<()> {
    let rotor = prep.case.loop_rotor();
    if rotor.unbalance.iter().any(|u| u.me != 0.0) {
        return Err(Error::study(
            "rotor.unbalance",
            "an unbalance forces the motion at the spin's period: an autonomous orbit (a whirl at its own frequency) needs none — shoot it with `rubsim periodic` without `--autonomous`, or remove the unbalance",
        ));
    }
    if !rotor.rotating.is_empty() {
        return Err(Error::study(
            "thermal",
            "a load fixed in the rotor's frame forces the motion at the spin's period: no autonomous orbit",
        ));
    }
    Ok(())
}

/// Shoots from the state `end` with the period estimate `t0` (s) in `n` steps a period.
///
/// # Errors
/// As [`shoot_autonomous`].
fn shoot_period(prep: &Prepared, end: EndState, t0: f64, n: usize) -> Result<AutonomousOrbit> {
    if t0 / n as f64 > prep.plan.limit {
        return Err(Error::study(
            "run.dt",
            format!(
                "the period {t0:.6e} s in {n} steps makes Δt = {:.4e} s, above the explicit scheme's stability limit {:.4e} s (a branch keeps its first orbit's steps a period: continue over a shorter range, or start where the period is longest)",
                t0 / n as f64,
                prep.plan.limit
            ),
        ));
    }
    let map = PeriodMap::new(prep, n, t0, end)?;
    let x0 = map.end.state_vector().ok_or_else(|| {
        Error::study(
            "run.integrator",
            "shooting needs the state of central differences: choose an explicit scheme (`--set run.integrator=collocated`)",
        )
    })?;
    if x0.len() > MAX_STATE {
        return Err(Error::study(
            "rotor",
            format!(
                "the orbit's state has {} components; shooting is limited to {MAX_STATE}",
                x0.len()
            ),
        ));
    }
    let sizes = map.end.central_sizes().unwrap_or_default();
    let pinned = pinned_component(&x0, &sizes);
    let (x, t, newton) = map.newton(x0, t0, pinned)?;
    let mut steps = newton.steps;
    let (m, ms) = map.jacobian_y(&map.to_y(&x), t)?;
    steps += ms;
    let multipliers = floquet(&m);
    let (record, rs) = map.period_record(&x, t)?;
    steps += rs;
    let trivial_at = (0..multipliers.len())
        .min_by(|&a, &b| {
            let d = |r: [f64; 2]| (r[0] - 1.0).hypot(r[1]);
            d(multipliers[a]).total_cmp(&d(multipliers[b]))
        })
        .unwrap_or(0);
    let others = multipliers
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != trivial_at)
        .map(|(_, r)| *r);
    let largest_other = others.clone().next();
    let largest = largest_other.map_or(0.0, |r| r[0].hypot(r[1]));
    let instability = (largest >= 1.0)
        .then(|| super::periodic::crossing(largest_other.unwrap_or([0.0; 2]), largest));
    let sense = record.sense;
    let whirl = sense * std::f64::consts::TAU / t;
    Ok(AutonomousOrbit {
        parameter: prep.speed_ratio,
        speed_ratio: prep.speed_ratio,
        converged: newton.converged,
        iterations: newton.iterations,
        residual: newton.residual,
        period_s: t,
        start_period_s: t0,
        whirl_frequency: whirl,
        whirl_ratio: whirl / (prep.omega / prep.speed_ratio),
        order: whirl / prep.omega,
        steps_per_period: n,
        dt_s: t / n as f64,
        radius_m: record.radius,
        contact_fraction: record.contact_fraction,
        trivial_multiplier: multipliers
            .get(trivial_at)
            .copied()
            .unwrap_or([f64::NAN; 2]),
        stable: newton.converged && largest < 1.0,
        largest_modulus: largest,
        instability,
        multipliers,
        state_size: x.len(),
        steps,
        fixed_point: (x, map.end.clone()),
    })
}

/// The component the phase condition holds: the rotor's displacement (its uᴺ, the first
/// `sizes[0]` components) whose increment `uᴺ − uᴺ⁻¹` is largest — the orbit crosses
/// `x_j = const` fastest there.
fn pinned_component(x: &[f64], sizes: &[usize]) -> usize {
    let n = sizes
        .first()
        .copied()
        .unwrap_or(x.len() / 2)
        .min(x.len() / 2);
    (0..n)
        .max_by(|&a, &b| (x[a] - x[a + n]).abs().total_cmp(&(x[b] - x[b + n]).abs()))
        .unwrap_or(0)
}

/// How Newton ended.
struct Newton {
    converged: bool,
    iterations: usize,
    residual: f64,
    steps: u64,
}

/// The period's record at the first station: its smallest and largest radius, contact
/// fraction and sense of turning (+1 with the spin, −1 against).
struct PeriodRecord {
    radius: [f64; 2],
    contact_fraction: f64,
    sense: f64,
}

/// The map `P_T` of `N` steps at Δt = T/N on states held at the reference step `T₀/N`.
struct PeriodMap<'a> {
    prep: &'a Prepared,
    steps: usize,
    /// Δt₀ = T₀/N (s).
    reference_dt: f64,
    /// The layout of the vectors, at the reference step.
    end: EndState,
    /// The central bodies' sizes in the layout.
    sizes: Vec<usize>,
}

impl<'a> PeriodMap<'a> {
    fn new(prep: &'a Prepared, steps: usize, t0: f64, end: EndState) -> Result<Self> {
        let reference_dt = t0 / steps as f64;
        let end = end.retimed(reference_dt);
        Ok(Self {
            prep,
            steps,
            reference_dt,
            sizes: end.central_sizes().unwrap_or_default(),
            end,
        })
    }

    /// The state `x = (uᴺ, uᴺ⁻¹)` per body as `y = (uᴺ, uᴺ − uᴺ⁻¹)`: Newton and the
    /// differences work on `y`, whose increments they perturb at their own scale (a step of
    /// max |x| on uᴺ⁻¹ would change the velocity by a large fraction). The multipliers, a
    /// similarity's eigenvalues, are the same in either.
    fn to_y(&self, x: &[f64]) -> Vec<f64> {
        let mut y = x.to_vec();
        let mut at = 0;
        for &n in &self.sizes {
            for i in 0..n {
                y[at + n + i] = x[at + i] - x[at + n + i];
            }
            at += 2 * n;
        }
        y
    }

    /// The inverse of [`PeriodMap::to_y`]: the map `(u, w) ↦ (u, u − w)` is its own inverse.
    fn to_x(&self, y: &[f64]) -> Vec<f64> {
        self.to_y(y)
    }

    /// `P_T` in `y` ([`PeriodMap::to_y`]).
    fn apply_y(&self, y: &[f64], t: f64) -> Result<Vec<f64>> {
        Ok(self.to_y(&self.apply(&self.to_x(y), t)?))
    }

    /// The difference step of each component of `y`: [`FD_STATE`] of the largest displacement
    /// for displacements, of the largest increment for increments.
    fn steps_of(&self, y: &[f64]) -> Vec<f64> {
        let mut is_increment = vec![false; y.len()];
        let mut at = 0;
        for &n in &self.sizes {
            is_increment[at + n..at + 2 * n]
                .iter_mut()
                .for_each(|b| *b = true);
            at += 2 * n;
        }
        let big = |inc: bool| {
            y.iter()
                .zip(&is_increment)
                .filter(|(_, &b)| b == inc)
                .fold(0.0_f64, |m, (v, _)| m.max(v.abs()))
                .max(1e-300)
        };
        let (du, dd) = (FD_STATE * big(false), FD_STATE * big(true));
        is_increment
            .iter()
            .map(|&b| if b { dd } else { du })
            .collect()
    }

    /// The plan of `N` steps at Δt = T/N, recording every step.
    fn plan(&self, t: f64) -> StepPlan {
        StepPlan {
            dt: t / self.steps as f64,
            steps: self.steps,
            steady_from: 0,
            record_every: 1,
            ..self.prep.plan
        }
    }

    /// `P_T(x)`.
    fn apply(&self, x: &[f64], t: f64) -> Result<Vec<f64>> {
        let plan = self.plan(t);
        let start = self
            .end
            .with_state_vector(x)
            .ok_or_else(not_fitting)?
            .at_step(self.reference_dt)
            .retimed(plan.dt);
        let mut st = restarted(self.prep, &plan, &start)?;
        run_to_end(&mut st, plan.steps)?
            .and_then(|e| e.retimed(self.reference_dt).state_vector())
            .ok_or_else(not_fitting)
    }

    /// Newton on `P_T(x) − x` over `x` less `x_pinned`, and `T` (module docs).
    fn newton(&self, x0: Vec<f64>, mut t: f64, pinned: usize) -> Result<(Vec<f64>, f64, Newton)> {
        let per_map = self.steps as u64;
        let mut x = self.to_y(&x0);
        let n = x.len();
        let mut steps = per_map;
        let mut px = self.apply_y(&x, t)?;
        let mut res = residual(&x, &px);
        let mut iterations = 0;
        // The period stays within a factor 1.5 of the start: the orbit run twice is a fixed
        // point at 2T too (a linear start extrapolated from two orbits once converged there),
        // and a free vibration's decay would let T wander off.
        let t_range = (t / 1.5, 1.5 * t);
        while res > SHOOT_TOLERANCE && iterations < MAX_NEWTON {
            iterations += 1;
            let (jx, js) = self.jacobian_y(&x, t)?;
            let ht = FD_PERIOD * t;
            let (pp, pm) = (self.apply_y(&x, t + ht)?, self.apply_y(&x, t - ht)?);
            steps += js + 2 * per_map;
            // Columns: every x_i but the pinned one (∂P/∂x_i − e_i), then ∂P/∂T.
            let mut a = DMatrix::<f64>::zeros(n, n);
            for (col, i) in (0..n).filter(|&i| i != pinned).enumerate() {
                for r in 0..n {
                    a[(r, col)] = jx[(r, i)] - if r == i { 1.0 } else { 0.0 };
                }
            }
            for r in 0..n {
                a[(r, n - 1)] = (pp[r] - pm[r]) / (2.0 * ht);
            }
            let f = DVector::from_iterator(n, px.iter().zip(&x).map(|(p, x)| x - p));
            let Some(d) = a.lu().solve(&f) else {
                break;
            };
            let mut scale = 1.0;
            let mut accepted = false;
            for _ in 0..=MAX_HALVINGS {
                let mut trial = x.clone();
                let mut k = 0;
                for (i, v) in trial.iter_mut().enumerate() {
                    if i != pinned {
                        *v += scale * d[k];
                        k += 1;
                    }
                }
                let tt = t + scale * d[n - 1];
                if tt > t_range.0 && tt < t_range.1 {
                    let pt = self.apply_y(&trial, tt)?;
                    steps += per_map;
                    let rt = residual(&trial, &pt);
                    if rt.is_finite() && rt < res {
                        (x, t, px, res, accepted) = (trial, tt, pt, rt, true);
                        break;
                    }
                }
                scale *= 0.5;
            }
            if !accepted {
                break;
            }
        }
        Ok((
            self.to_x(&x),
            t,
            Newton {
                converged: res <= SHOOT_TOLERANCE,
                iterations,
                residual: res,
                steps,
            },
        ))
    }

    /// `∂P_T/∂y` at fixed T by central differences ([`PeriodMap::steps_of`]), `y` in the
    /// coordinates of [`PeriodMap::to_y`], and the steps it took.
    fn jacobian_y(&self, y: &[f64], t: f64) -> Result<(DMatrix<f64>, u64)> {
        let n = y.len();
        let h = self.steps_of(y);
        let mut m = DMatrix::<f64>::zeros(n, n);
        for j in 0..n {
            let mut yp = y.to_vec();
            yp[j] += h[j];
            let mut ym = y.to_vec();
            ym[j] -= h[j];
            let (pp, pm) = (self.apply_y(&yp, t)?, self.apply_y(&ym, t)?);
            for i in 0..n {
                m[(i, j)] = (pp[i] - pm[i]) / (2.0 * h[j]);
            }
        }
        Ok((m, (2 * n * self.steps) as u64))
    }

    /// One period from `x`, recorded at every step: the first station's radii, contact and
    /// sense of turning.
    fn period_record(&self, x: &[f64], t: f64) -> Result<(PeriodRecord, u64)> {
        let plan = self.plan(t);
        let start = self
            .end
            .with_state_vector(x)
            .ok_or_else(not_fitting)?
            .at_step(self.reference_dt)
            .retimed(plan.dt);
        let (rec, stats) = restarted(self.prep, &plan, &start)?.run(None)?;
        let (mut lo, mut hi, mut contact, mut turn) = (f64::INFINITY, 0.0_f64, 0usize, 0.0);
        let len = rec.len();
        for i in 0..len {
            let u = rec.disp_at(i, 0);
            let r = u[0].hypot(u[1]);
            lo = lo.min(r);
            hi = hi.max(r);
            if rec.nstations > 0 {
                let f = rec.force_normal[i * rec.nstations];
                if f[0].hypot(f[1]) > 0.0 {
                    contact += 1;
                }
            }
            if i > 0 {
                let v = rec.disp_at(i - 1, 0);
                turn += v[0] * u[1] - v[1] * u[0];
            }
        }
        Ok((
            PeriodRecord {
                radius: [lo, hi],
                contact_fraction: contact as f64 / len.max(1) as f64,
                sense: if turn < 0.0 { -1.0 } else { 1.0 },
            },
            stats.steps as u64,
        ))
    }
}

fn not_fitting() -> Error {
    Error::study("run", "the orbit's state does not fit this run")
}
