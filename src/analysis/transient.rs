//! A speed transient: prepare the case, the profile and the step plan once
//! ([`prepare_transient`]), integrate the whole profile with any set of sinks
//! ([`TransientPrepared::run`]) and analyse the record against time, spin angle and speed
//! ([`analyse_transient`]): the speed history, the response and contact force, the friction
//! energy, and order tracking — amplitude and phase of 1×, ½×, ⅓× and the scene's orders per
//! window of whole revolutions in the angle domain — beside the steady unbalance response at
//! the same speeds (the run-up Bode).

use super::fanout::Fanout;
use super::RunSettings;
use crate::error::{ModelError, Result};
use crate::model::{Case, Drive, Events, Model, SpeedProfile, SpinState};
use crate::scene::{EventSpec, ProfileKind, SpeedProfileSpec};
use crate::time::{plan_duration, FrameSink, Record, RunStats, StepPlan, Stepper};
use num_complex::Complex64;
use serde::Serialize;
use std::f64::consts::PI;

/// A transient run ready to integrate.
#[derive(Debug)]
pub struct TransientPrepared {
    /// Ω(t), Ω̇(t), φ(t); a driven run: Ω₀ held over the run's length (its speed is the
    /// record's, [`crate::time::Record::spin`]).
    pub profile: SpeedProfile,
    /// A driven rotor's spin data (`kind = "driven"`), else `None`.
    pub drive: Option<Drive>,
    /// The run's scheduled events (`[[run.event]]`, [`TransientPrepared::with_events`]).
    pub events: Events,
    /// The run's settings (its `revolutions` do not apply: the profile sets the length).
    pub settings: RunSettings,
    /// The case at the reference speed Ω_ref (clearance, stators, |Z0(Ω_ref)|).
    pub case: Case,
    /// The step plan over the profile's duration.
    pub plan: StepPlan,
    /// Orders tracked: 1, ½, ⅓ and the scene's.
    pub orders: Vec<f64>,
    /// Revolutions per order-tracking window.
    pub window_revolutions: usize,
    /// ω_n (rad/s), the unit of the speed ratios reported.
    pub omega_n: f64,
    /// The highest speed the plan is made for (rad/s).
    top: f64,
    /// The rotor, for the steady unbalance response `q` at each tracked window's Ω
    /// (`x = Re(q e^{iΩt})`, the run-up Bode's reference).
    rotor: crate::model::Rotor,
}

/// Prepares a transient run of `model` along `spec`: the profile in rad/s, the case at
/// Ω_ref = `spec.reference` (default ω_n), the plan at the profile's top speed.
///
/// # Errors
/// [`ModelError::Inconsistent`] for a rotor whose bearings are tabulated over speed
/// ([`crate::model::Rotor::speed_tabulated`]), a profile that never spins, or an implicit
/// scheme on a driven rotor (`run.integrator`); model and plan
/// errors as [`super::prepare`].
pub fn prepare_transient(
    model: &Model,
    settings: &RunSettings,
    spec: &SpeedProfileSpec,
) -> Result<TransientPrepared> {
    if model.rotor.speed_tabulated() {
        return Err(ModelError::Inconsistent {
            what: "run.speed_profile".into(),
            message: "this rotor's bearings are tabulated over speed (K(Ω), C(Ω)); speed transients of such rotors are not implemented — use constant bearing coefficients, or run single speeds".into(),
        }
        .into());
    }
    let omega_n = model.rotor.natural_frequency();
    let (profile, drive, top) = if spec.kind == ProfileKind::Driven {
        let d = Drive::from_spec(spec, omega_n, &model.rotor)?;
        let top = d.speed_bound();
        (SpeedProfile::constant(d.speed0, d.duration)?, Some(d), top)
    } else {
        let p = SpeedProfile::from_spec(spec, omega_n)?;
        let top = p.max_speed();
        (p, None, top)
    };
    if top <= 0.0 {
        return Err(ModelError::Inconsistent {
            what: "run.speed_profile".into(),
            message: "the speed is zero throughout".into(),
        }
        .into());
    }
    let omega_ref = spec
        .reference
        .map_or(omega_n, |r| r * spec.unit.to_rad_per_s(omega_n));
    // A reduced rotor keeps the modes the profile's top speed needs.
    let case = model
        .case_with(omega_ref, None)?
        .reduced_to(model.reduction.as_ref(), top)?;
    if drive.is_some() && settings.step.integrator.implicit().is_some() {
        return Err(ModelError::Inconsistent {
            what: "run.integrator".into(),
            message: "a driven rotor's spin is integrated by the explicit central difference only — use forward_increment or collocated with kind = \"driven\"".into(),
        }
        .into());
    }
    let plan = plan_duration(&case, &settings.step, top, profile.duration())?;
    profile_fits(spec, &profile, omega_n, top, &plan)?;
    let mut orders = vec![1.0, 0.5, 1.0 / 3.0];
    for o in &spec.orders {
        if !orders.iter().any(|k| (k - o).abs() < 1e-12) {
            orders.push(*o);
        }
    }
    Ok(TransientPrepared {
        profile,
        drive,
        events: Events::default(),
        settings: *settings,
        case,
        plan,
        orders,
        window_revolutions: spec.window_revolutions,
        omega_n,
        top,
        rotor: model.rotor.clone(),
    })
}

/// The profile (speeds in `spec.unit`, ω_n for a ratio; `top` its top speed in rad/s) against
/// the run's `plan` (its step Δt; a profile of one step is shorter than the step the run would
/// take) and its order tracking: the run lasts at least one
/// step; a ramp's change of speed too (`duration`, or `acceleration`: |to − from|/|a|); a
/// table's interval across which the speed changes too (`points.i`) — shorter, the speed
/// would jump within a step, Ω̇ beyond anything the step resolves; and a window of
/// `window_revolutions` fits in the revolutions the profile turns at most (its top speed over
/// its duration).
///
/// # Errors
/// [`ModelError::Inconsistent`] naming the key.
fn profile_fits(
    spec: &SpeedProfileSpec,
    profile: &SpeedProfile,
    omega_n: f64,
    top: f64,
    plan: &StepPlan,
) -> std::result::Result<(), ModelError> {
    let (dt, steps) = (plan.dt, plan.steps);
    let u = spec.unit.to_rad_per_s(omega_n);
    let bad = |key: &str, message: String| ModelError::Inconsistent {
        what: format!("run.speed_profile.{key}"),
        message,
    };
    let total = profile.duration();
    // One step for the whole profile: Δt was shortened to its length, every change is in it.
    let one_step = steps <= 1;
    let jump = |lasts: f64, from: f64, to: f64| {
        let step = if one_step {
            "the run's whole profile is a single time step".to_string()
        } else {
            format!("less than one time step Δt = {dt:.4e} s")
        };
        format!(
            "the speed goes from {from} to {to} in {lasts:e} s, {step} (Ω̇ = {:.3e} rad/s²): the step cannot resolve it; let the change last at least one step",
            (to - from) * u / lasts
        )
    };
    match (spec.kind, spec.from, spec.to) {
        (ProfileKind::Ramp, Some(from), Some(to)) if from != to => {
            let (key, lasts) = match (spec.duration, spec.acceleration) {
                (Some(d), _) => ("duration", d),
                (None, Some(a)) => ("acceleration", (to - from) / a),
                (None, None) => ("duration", total),
            };
            if lasts < dt || one_step {
                return Err(bad(key, jump(lasts, from, to)));
            }
        }
        (ProfileKind::Table, ..) => {
            let pts = spec.points.as_deref().unwrap_or_default();
            for (i, w) in pts.windows(2).enumerate() {
                let lasts = w[1][0] - w[0][0];
                if w[1][1] != w[0][1] && (lasts < dt || one_step) {
                    return Err(bad(
                        &format!("points.{}", i + 1),
                        jump(lasts, w[0][1], w[1][1]),
                    ));
                }
            }
        }
        _ => {}
    }
    if one_step {
        return Err(bad(
            "duration",
            format!("the profile lasts {total:e} s, a single time step of the run"),
        ));
    }
    let most_revs = top * total / (2.0 * std::f64::consts::PI);
    if spec.window_revolutions as f64 > most_revs.floor().max(1.0) {
        return Err(bad(
            "window_revolutions",
            format!(
                "{} revolutions per order-tracking window, but the profile turns at most {:.0} revolutions (its top speed {top:.4e} rad/s over {total:.4e} s): no window fits",
                spec.window_revolutions,
                most_revs.floor(),
            ),
        ));
    }
    Ok(())
}

/// One order-tracking window: `window_revolutions` whole revolutions of the spin angle.
#[derive(Debug, Clone, Serialize)]
pub struct OrderWindow {
    /// Time at the window's middle angle (s).
    pub t: f64,
    /// Ω there (rad/s).
    pub omega: f64,
    /// Ω̇ there (rad/s²): > 0 on a run-up, < 0 on a coast-down.
    pub omega_dot: f64,
    /// `(amplitude m, phase rad)` per tracked order: `x ≈ A cos(k φ + ψ)` over the window.
    pub lines: Vec<(f64, f64)>,
    /// Steady unbalance response at Ω of the same component (amplitude m, phase rad), the
    /// frequency-domain reference of the 1× line.
    pub steady_1x: (f64, f64),
}

/// What a transient run gives.
#[derive(Debug, Clone, Serialize)]
pub struct TransientResults {
    /// ω_n (rad/s).
    pub omega_n: f64,
    /// Duration (s) and revolutions φ_end/2π of the profile.
    pub duration: f64,
    /// Revolutions over the run.
    pub revolutions: f64,
    /// Rotor node analysed.
    pub node: usize,
    /// Component analysed, 0 = x, 1 = y.
    pub component: usize,
    /// Orders tracked.
    pub orders: Vec<f64>,
    /// Step plan and loop counters.
    pub plan: StepPlan,
    /// Loop counters.
    pub stats: RunStats,
    /// Friction energy dissipated over the run (J).
    pub friction_energy: f64,
    /// Largest contact-force magnitude on station 0 (N).
    pub contact_force_max: f64,
    /// Peak 1× amplitude (m) and the speed where it occurs (rad/s).
    pub peak_1x: (f64, f64),
    /// Per recorded sample: t (s), Ω (rad/s), φ (rad), Ω̇ (rad/s²).
    #[serde(skip)]
    pub spin: Vec<[f64; 4]>,
    /// Per recorded sample: the analysed node's `[x, y]` (m).
    #[serde(skip)]
    pub response: Vec<[f64; 2]>,
    /// Per recorded sample: |F| on station 0 (N), friction power (W), friction energy so far (J).
    #[serde(skip)]
    pub contact: Vec<[f64; 3]>,
    /// A driven run, per recorded sample: the drive torque T_d and the rub's friction torque
    /// Σ R μ p (N·m); empty for a prescribed profile.
    #[serde(skip)]
    pub torque: Vec<[f64; 2]>,
    /// Per recorded sample: the pairs carrying force and those of them in stick.
    #[serde(skip)]
    pub contact_state: Vec<[u32; 2]>,
    /// Some station has Coulomb friction with stick (`station.N.stick`).
    pub stick: bool,
    /// The wear of the stators with `[stator.wear]` (`super::wear`); `None` without wear.
    pub wear: Option<super::wear::WearResults>,
    /// Order-tracking windows, one per revolution.
    #[serde(skip)]
    pub windows: Vec<OrderWindow>,
    /// The run's estimated error (`run.error_estimate`; `None` when off or when no companion
    /// step can be planned).
    pub error_estimate: Option<TransientError>,
}

/// The estimated error of a transient run: its tracked 1× amplitude against a companion run
/// of the same profile at another step rΔt, by Richardson extrapolation: with A(Δt) the run's,
/// `e ≈ max_t |A(Δt) − A(rΔt)| / |r^p − 1|`, the companion's amplitude interpolated linearly in
/// time at the run's windows. r = 2, or for an explicit run near its stability limit the
/// largest step below it (r ≥ 1.2), else r = ½ (a companion twice the run's cost).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct TransientError {
    /// `e` relative to the run's peak 1× amplitude.
    pub relative_1x: f64,
    /// The order p assumed: 2, or 1 for the forward increment with contact.
    pub order: f64,
    /// The companion's step (s) and its steps.
    pub companion_dt: f64,
    /// The companion's steps.
    pub companion_steps: usize,
}

impl TransientPrepared {
    /// The run with the events `specs` (`[[run.event]]`) scheduled on its case.
    ///
    /// # Errors
    /// [`ModelError::Inconsistent`] as [`Events::from_specs`].
    pub fn with_events(mut self, specs: &[EventSpec]) -> Result<Self> {
        self.events = Events::from_specs(specs, &self.case)?;
        Ok(self)
    }

    /// Integrates the whole profile with `sinks` and analyses the record.
    ///
    /// # Errors
    /// [`crate::error::SolveError`] of the loop, a sink's error included.
    pub fn run(&self, sinks: &mut [&mut dyn FrameSink]) -> Result<TransientResults> {
        let (rec, stats) = self.integrate(sinks)?;
        let mut r = analyse_transient(self, &rec, stats)?;
        if self.settings.error_estimate {
            r.error_estimate = self.estimate_error(&r)?;
        }
        Ok(r)
    }

    /// The error of `r` (this run's results) by a companion run at a coarser step, or Δt/2
    /// where none can be planned ([`TransientError`]); `None` when neither can.
    ///
    /// # Errors
    /// As [`TransientPrepared::run`] for the companion.
    pub fn estimate_error(&self, r: &TransientResults) -> Result<Option<TransientError>> {
        let contact = r.stats.contact_steps > 0;
        let order =
            if contact && self.settings.step.integrator == crate::time::Scheme::ForwardIncrement {
                1.0
            } else {
                2.0
            };
        let Some(plan) = self.companion_plan() else {
            return Ok(None);
        };
        // Step ratio r = Δt_companion/Δt, either side of 1.
        let ratio = plan.dt / self.plan.dt;
        let (rec, stats) = self.integrate_plan(&plan, &mut [])?;
        let c = analyse_transient(self, &rec, stats)?;
        let (tc, ac): (Vec<f64>, Vec<f64>) = c.windows.iter().map(|w| (w.t, w.lines[0].0)).unzip();
        let diff = (r.windows.iter())
            .filter(|w| {
                tc.first().is_some_and(|t0| w.t >= *t0) && tc.last().is_some_and(|t1| w.t <= *t1)
            })
            .map(|w| (w.lines[0].0 - crate::math::interp_linear(&tc, &ac, w.t)).abs())
            .fold(0.0, f64::max);
        // A(Δt) − A(rΔt) ≈ e(Δt)(1 − r^p): e = |ΔA| / |r^p − 1|.
        let e = diff / (ratio.powf(order) - 1.0).abs();
        Ok(Some(TransientError {
            relative_1x: if r.peak_1x.0 > 0.0 {
                e / r.peak_1x.0
            } else {
                0.0
            },
            order,
            companion_dt: plan.dt,
            companion_steps: plan.steps,
        }))
    }

    /// The plan of the error estimate's companion ([`TransientError`]): the coarsest step up to
    /// 2Δt the scheme takes (an explicit run near its stability limit: just below it, at
    /// least 1.2Δt), else Δt/2; `None` when none can be planned.
    pub fn companion_plan(&self) -> Option<StepPlan> {
        let duration = self.profile.duration();
        let at = |dt: f64| {
            let mut step = self.settings.step;
            step.dt = Some(dt);
            crate::time::plan_duration(&self.case, &step, self.top, duration).ok()
        };
        let dt = self.plan.dt;
        let coarse = (2.0 * dt).min(0.99 * self.plan.limit.max(dt));
        (coarse >= 1.2 * dt)
            .then(|| at(coarse))
            .flatten()
            .or_else(|| at(2.0 * dt))
            .or_else(|| at(0.5 * dt))
    }

    /// Integrates the whole profile with `sinks`; returns the record and counters.
    ///
    /// # Errors
    /// As [`TransientPrepared::run`].
    pub fn integrate(&self, sinks: &mut [&mut dyn FrameSink]) -> Result<(Record, RunStats)> {
        self.integrate_plan(&self.plan, sinks)
    }

    /// [`TransientPrepared::integrate`] on `plan` instead of the run's.
    fn integrate_plan(
        &self,
        plan: &StepPlan,
        sinks: &mut [&mut dyn FrameSink],
    ) -> Result<(Record, RunStats)> {
        let s = &self.settings;
        let stepper = match &self.drive {
            Some(d) => Stepper::with_drive(&self.case, s.step.integrator, plan, s.initial, d)?,
            None => Stepper::with_profile(
                &self.case,
                s.step.integrator,
                plan,
                s.initial,
                Some(&self.profile),
            )?,
        };
        let mut stepper = stepper;
        if !self.events.is_empty() {
            stepper.set_events(self.events.clone(), s.initial)?;
        }
        Ok(match sinks {
            [] => stepper.run(None)?,
            [one] => stepper.run(Some(&mut **one))?,
            many => stepper.run(Some(&mut Fanout::new(many)))?,
        })
    }
}

/// The analysis of a transient record (see the module).
///
/// # Errors
/// [`ModelError`] when the steady response of the rotor cannot be computed at a window's speed
/// (a singular dynamic stiffness).
pub fn analyse_transient(
    p: &TransientPrepared,
    rec: &Record,
    stats: RunStats,
) -> Result<TransientResults> {
    let spin: Vec<[f64; 4]> = if rec.spin.is_empty() {
        rec.t
            .iter()
            .map(|&t| {
                let s = p.profile.at(t);
                [t, s.omega, s.phi, s.omega_dot]
            })
            .collect()
    } else {
        (rec.t.iter().zip(&rec.spin))
            .map(|(&t, s)| [t, s[1], s[0], s[2]])
            .collect()
    };
    let torque: Vec<[f64; 2]> = rec.spin.iter().map(|s| [s[3], s[4]]).collect();
    let contact = friction(p, rec);
    let comp = p.settings.component;
    let x: Vec<f64> = rec.observed.iter().map(|d| d[comp]).collect();
    let phi: Vec<f64> = spin.iter().map(|s| s[2]).collect();
    let dof = p.rotor.node_dofs(p.case.observed_node)[comp];
    let mut windows = Vec::new();
    for (t, lines) in track_orders(&rec.t, &phi, &x, &p.orders, p.window_revolutions) {
        let spin = spin_at(p, &spin, t);
        let omega = spin.omega;
        let q = if omega > 0.0 {
            p.rotor.unbalance_response(omega)?[dof]
        } else {
            Complex64::new(0.0, 0.0)
        };
        windows.push(OrderWindow {
            t,
            omega,
            omega_dot: spin.omega_dot,
            lines,
            steady_1x: (q.norm(), q.arg()),
        });
    }
    let peak_1x = windows
        .iter()
        .map(|w| (w.lines[0].0, w.omega))
        .fold((0.0, 0.0), |a, b| if b.0 > a.0 { b } else { a });
    let duration = p.profile.duration();
    Ok(TransientResults {
        omega_n: p.omega_n,
        duration,
        revolutions: spin.last().map_or(0.0, |s| s[2]) / (2.0 * PI),
        node: p.case.observed_node,
        component: comp,
        orders: p.orders.clone(),
        plan: p.plan,
        stats,
        friction_energy: contact.last().map_or(0.0, |c| c[2]),
        contact_force_max: contact.iter().map(|c| c[0]).fold(0.0, f64::max),
        peak_1x,
        spin,
        response: rec.observed.clone(),
        contact,
        torque,
        contact_state: (rec.active.iter().zip(&rec.sticking))
            .map(|(a, s)| [*a, *s])
            .collect(),
        stick: p.case.stations.iter().any(|st| st.stick),
        wear: super::wear::of_record(&p.case, rec, &phi),
        windows,
        error_estimate: None,
    })
}

/// Revolutions of the local speed in an orbit snapshot (`output.snapshot_speeds`).
pub const SNAPSHOT_REVOLUTIONS: f64 = 2.0;

/// The orbit of the analysed node around one passage of the speed history through a chosen
/// speed (`output.snapshot_speeds`).
#[derive(Debug, Clone, Serialize)]
pub struct OrbitSnapshot {
    /// The chosen speed, ω/ω_n.
    pub target: f64,
    /// Which passage through `target` this is, 1 for the first in time.
    pub pass: usize,
    /// `true` when Ω rises through `target` (run-up), `false` when it falls (coast-down).
    pub up: bool,
    /// Instant of the passage (s): Ω(t) = target·ω_n, interpolated linearly between the
    /// recorded samples that bracket it.
    pub t: f64,
    /// The steady unbalance response |Z0| at `target` (m, major semi-axis at the analysed
    /// node, without stator): the unit of the snapshot's picture.
    pub z0: f64,
    /// The recorded samples within ±[`SNAPSHOT_REVOLUTIONS`]/2 revolutions of `target`·ω_n
    /// around `t` (clipped to the run): `[t (s), Ω/ω_n, x (m), y (m)]`.
    #[serde(skip)]
    pub samples: Vec<[f64; 4]>,
}

/// The orbit snapshots of `r` at the speeds `targets` (ω/ω_n): one per target and passage of
/// the recorded speed history through it, in the order of `targets` and then of time, each
/// [`SNAPSHOT_REVOLUTIONS`] revolutions long, 2π·[`SNAPSHOT_REVOLUTIONS`]/Ω_target, centred on
/// the passage. A passage is a pair of consecutive samples with Ω_i < Ω_target ≤ Ω_{i+1}
/// (up) or Ω_i > Ω_target ≥ Ω_{i+1} (down); a speed the run starts at and leaves is not
/// passed. Returns the snapshots and the targets never passed.
///
/// # Errors
/// [`ModelError`] when the steady response |Z0| cannot be computed at a target (a singular
/// dynamic stiffness).
pub fn orbit_snapshots(
    p: &TransientPrepared,
    r: &TransientResults,
    targets: &[f64],
) -> Result<(Vec<OrbitSnapshot>, Vec<f64>)> {
    let wn = r.omega_n;
    let mut snaps = Vec::new();
    let mut missed = Vec::new();
    for &target in targets {
        let w = target * wn;
        let half = SNAPSHOT_REVOLUTIONS * PI / w;
        let z0 = p.rotor.z0(r.node, w)?;
        let mut pass = 0;
        for ab in r.spin.windows(2) {
            let (a, b) = (ab[0], ab[1]);
            let up = a[1] < w && w <= b[1];
            if !(up || (a[1] > w && w >= b[1])) {
                continue;
            }
            pass += 1;
            let t = a[0] + (w - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            let lo = r.spin.partition_point(|s| s[0] < t - half);
            let hi = r.spin.partition_point(|s| s[0] <= t + half);
            let samples = (lo..hi.max(lo))
                .map(|k| {
                    let u = r.response[k];
                    [r.spin[k][0], r.spin[k][1] / wn, u[0], u[1]]
                })
                .collect();
            snaps.push(OrbitSnapshot {
                target,
                pass,
                up,
                t,
                z0,
                samples,
            });
        }
        if pass == 0 {
            missed.push(target);
        }
    }
    Ok((snaps, missed))
}

/// Ω, Ω̇, φ at `t`: the profile's, or a driven run's recorded spin (`[t, Ω, φ, Ω̇]` per
/// sample) interpolated linearly.
fn spin_at(p: &TransientPrepared, spin: &[[f64; 4]], t: f64) -> SpinState {
    if p.drive.is_none() || spin.is_empty() {
        return p.profile.at(t);
    }
    let i = spin
        .partition_point(|s| s[0] < t)
        .clamp(1, spin.len().max(2) - 1);
    let (a, b) = (
        spin[(i - 1).min(spin.len() - 1)],
        spin[i.min(spin.len() - 1)],
    );
    let f = if b[0] > a[0] {
        (t - a[0]) / (b[0] - a[0])
    } else {
        0.0
    };
    let lerp = |k: usize| a[k] + f * (b[k] - a[k]);
    SpinState {
        phi: lerp(2),
        omega: lerp(1),
        omega_dot: lerp(3),
    }
}

/// Per sample: |F| on station 0 (N), the friction power summed over stations (W) and its
/// integral (J, trapezoid). The power is the one the stepper records (`Record::friction_power`):
/// per pair the tangential force times the slip of the section's surface over the stator's
/// material point over the step (docs/STICK.md §1), the stator's own motion included — 0
/// while a pair sticks.
fn friction(p: &TransientPrepared, rec: &Record) -> Vec<[f64; 3]> {
    let n = rec.len();
    let mut out = Vec::with_capacity(n);
    let mut energy = 0.0;
    let mut prev_power = 0.0;
    for i in 0..n {
        let mut power = 0.0;
        for s in 0..p.case.stations.len() {
            power += rec.friction_power_at(i, s);
        }
        if i > 0 {
            energy += 0.5 * (power + prev_power) * (rec.t[i] - rec.t[i - 1]);
        }
        prev_power = power;
        let f = rec.force_at(i, 0);
        out.push([f[0].hypot(f[1]), power, energy]);
    }
    out
}

/// Points of resampling per revolution in the angle domain.
const PER_REV: usize = 64;

/// Order tracking: the signal `x` at times `t` with spin angles `phi` (nondecreasing) is
/// resampled at `PER_REV` equal angle steps per revolution (cubic Lagrange interpolation in
/// φ through the four nearest samples; linear where φ stalls), and over each window of `w`
/// whole revolutions starting at every whole revolution the DFT at each order k gives
/// `X = (2/N) Σ x(φ_j) e^{−i k φ_j}`, `x ≈ Re(X e^{i k φ}) = |X| cos(kφ + arg X)`; orders that
/// are multiples of 1/w are exact bins. Returns per window the time at its middle angle and
/// `(|X|, arg X)` per order.
pub fn track_orders(
    t: &[f64],
    phi: &[f64],
    x: &[f64],
    orders: &[f64],
    w: usize,
) -> Vec<(f64, Vec<(f64, f64)>)> {
    let n = phi.len();
    if n < 4 || w == 0 {
        return Vec::new();
    }
    let revs = (phi[n - 1] / (2.0 * PI)).floor() as usize;
    if w > revs {
        // No window fits: nothing to resample (a buffer of w revolutions is never allocated).
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut cursor = 0usize;
    let big_n = w * PER_REV;
    let mut buf = vec![0.0; big_n];
    for k in 0..(revs + 1).saturating_sub(w) {
        let start = 2.0 * PI * k as f64;
        let mut cur = cursor;
        for (j, b) in buf.iter_mut().enumerate() {
            let a = start + 2.0 * PI * j as f64 / PER_REV as f64;
            while cur + 2 < n && phi[cur + 1] <= a {
                cur += 1;
            }
            if j == 0 {
                cursor = cur;
            }
            *b = interp(phi, x, cur, a);
        }
        let lines = orders
            .iter()
            .map(|&o| {
                let s = buf
                    .iter()
                    .enumerate()
                    .fold(Complex64::new(0.0, 0.0), |acc, (j, v)| {
                        let a = o * 2.0 * PI * j as f64 / PER_REV as f64;
                        acc + Complex64::from_polar(*v, -a)
                    });
                // Relative to the window's own start angle: shift by e^{−i k o start}.
                let xk = s * 2.0 / big_n as f64 * Complex64::from_polar(1.0, -o * start);
                (xk.norm(), xk.arg())
            })
            .collect();
        let mid = start + PI * w as f64;
        let i = phi.partition_point(|p| *p < mid).clamp(1, n - 1);
        let dphi = phi[i] - phi[i - 1];
        let f = if dphi > 0.0 {
            (mid - phi[i - 1]) / dphi
        } else {
            0.0
        };
        out.push((t[i - 1] + f * (t[i] - t[i - 1]), lines));
    }
    out
}

/// x at angle `a` from the samples around index `i` (φ[i] ≤ a ≤ φ[i+1] where possible).
pub(super) fn interp(phi: &[f64], x: &[f64], i: usize, a: f64) -> f64 {
    let n = phi.len();
    let lo = i.saturating_sub(1).min(n - 4);
    let p = &phi[lo..lo + 4];
    let strictly = p.windows(2).all(|w| w[1] > w[0]);
    if !strictly {
        let j = i.min(n - 2);
        let d = phi[j + 1] - phi[j];
        let f = if d > 0.0 {
            ((a - phi[j]) / d).clamp(0.0, 1.0)
        } else {
            0.0
        };
        return x[j] + f * (x[j + 1] - x[j]);
    }
    let mut v = 0.0;
    for m in 0..4 {
        let mut l = 1.0;
        for q in 0..4 {
            if q != m {
                l *= (a - p[q]) / (p[m] - p[q]);
            }
        }
        v += l * x[lo + m];
    }
    v
}
