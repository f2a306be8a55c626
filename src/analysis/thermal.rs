//! The thermal spiral (Newkirk effect) at one speed: the hot-spot model of `[thermal]`
//! ([`crate::scene::thermal`]) coupled to the rub's vibration on two time scales.
//!
//! **Coupling.** The vibration runs in chunks of `revolutions` revolutions of the run's own
//! scheme and Δt, each restarted from the end of the one before (`Stepper::restart`) with the
//! bow of the moment held as a load fixed in the rotor's frame ([`crate::model::bow`]: on a
//! Jeffcott rotor `k b e^{iΩt}` at the disk, on an FE rotor the thermal-strain moments of the
//! heated length; a reduced FE rotor takes it through its basis, `Tᵀ F_b`). From the chunk's last revolution, sampled at every
//! step, come the friction power's mean `P` and its first harmonic in the rotor's frame `Q`
//! (the friction power the stepper records, `t ζ/Δt` per pair — the tangential force times the
//! slip of the section's surface over the stator's material point — as a transient's, placed at
//! the contact normal's angle less the spin angle), and the 1× vector of the station's response
//! in the rotor's frame `Z`. The heat's state (S, ΔT) is then advanced over the coupling step
//! `h` exactly, with `Q` extrapolated linearly from the last two steps: fully resolved when `h`
//! is the chunk's own length (every revolution of the machine time integrated), accelerated
//! when `h` is longer (each step's vibration goes on until its 1× vector is steady to
//! `run.tolerance`, then is taken as settled on the bow of the step). The coupling converges
//! in `h` at a fitted order of 1.7 against the spiral's own time (docs/VALIDATION.md §21); the
//! linear theory's own assumption, a 1× vector that follows the bow at once, is good to the
//! ratio of the vibration's settling time to the spiral's.
//!
//! **Stops.** At `duration`, or when |ΔT| passes `max_temperature_difference`: a runaway,
//! reported with the growth rate of its last steps — never a NaN. Or when the vibration is not
//! the synchronous response the two time scales assume: the station's orbit over a chunk's
//! last revolution differs from the one before, less the drift of its 1× vector, by more than
//! [`MAX_NON_SYNCHRONOUS`] of the largest orbit radius so far (a self-excited whirl of the rub — dry friction whirl where μ k_s exceeds the
//! damping — or a response that does not settle). The heat of a revolution then does not
//! belong to the bow of the moment; the run stops there and says so
//! (`ThermalResults::unsynchronous_at_s`), its growth rate not fitted.

use super::periodic::{restarted, run_to_end, stepper};
use super::speed::{prepare, Prepared};
use super::RunSettings;
use crate::error::{Error, Result};
use crate::math::V2;
use crate::model::bow::{cmul, fe_bow_load, jeffcott_bow_load, rotor_frame, scaled, static_bow};
use crate::model::{Model, RotatingLoad, Rotor};
use crate::time::{EndState, Record, StepPlan, Stepper};
use serde::Serialize;

mod heat;
use heat::Heat;
pub use heat::{HeatLaw, HotSpot, Lags, SectionFacts};

/// One coupling step of a thermal run.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct ThermalSample {
    /// Machine time at the start of the step (s).
    pub t_s: f64,
    /// ΔT, rotor frame (K).
    pub delta_t: V2,
    /// The surface zone's S, rotor frame (K).
    pub surface: V2,
    /// The heated station's bow, rotor frame (m): the disk's of a Jeffcott rotor, the static
    /// deflection of an FE rotor's curvature load at the station's node.
    pub bow: V2,
    /// The station's 1× response vector over the chunk's last revolution, rotor frame (m):
    /// `(1/T) ∫ z e^{−iΩt} dt`.
    pub one_x: V2,
    /// The friction power's first harmonic, rotor frame (W): `(1/T) ∫ P e^{iθ} dt`.
    pub heat: V2,
    /// The friction power's mean over that revolution (W).
    pub power: f64,
    /// Fraction of that revolution's steps in contact.
    pub contact_fraction: f64,
    /// The station's orbit's change over one revolution, relative to its largest radius over
    /// the run so far: `max_k |z_k − z_{k−N} − (Z₁ − Z₀) e^{iΩt_k}| / max |z|` (N steps a
    /// revolution, `Z₁`, `Z₀` the 1× vectors of the two revolutions, rotor frame: the
    /// synchronous drift taken out); ≈ 0 for a synchronous response (any harmonics of Ω) even
    /// while a fast spiral turns it, O(1) for a whirl of its own frequency.
    pub non_synchronous: f64,
}

/// The largest [`ThermalSample::non_synchronous`] of a vibration taken as synchronous: beyond
/// it the run stops ([`ThermalResults::unsynchronous_at_s`]). A synchronous response turned by
/// the spiral reads the drift of its other harmonics only, well below it.
pub const MAX_NON_SYNCHRONOUS: f64 = 0.05;

/// A thermal run's results.
#[derive(Debug, Clone, Serialize)]
pub struct ThermalResults {
    /// ν = ω/ω_n.
    pub speed_ratio: f64,
    /// ω (rad/s).
    pub omega: f64,
    /// The station's bow per kelvin of ΔT, |b|/|ΔT| (m/K).
    pub bow_per_kelvin: f64,
    /// The coupling step h (s) and the revolutions integrated per step.
    pub coupling_step_s: f64,
    /// Revolutions integrated per coupling step, on average (an accelerated step goes on until
    /// its 1× vector is steady to `run.tolerance`).
    pub revolutions_per_step: f64,
    /// Whether every revolution of the machine time was integrated (h = the chunk's length).
    pub resolved: bool,
    /// The coupling steps, in time order, and the state at the end.
    pub samples: Vec<ThermalSample>,
    /// The spiral's growth rate (1/s; > 0: it grows): Re s of its dominant slow mode, from the
    /// ratio of successive steps' changes of ΔT over the last third of the run.
    pub growth_rate: f64,
    /// The spiral's rotation in the rotor's frame (rad/s; > 0 with the spin): Im s.
    pub rotation_rate: f64,
    /// When |ΔT| passed `max_temperature_difference` (s): the spiral ran away and the run
    /// stopped there, `growth_rate` then fitted over its last steps.
    pub runaway_at_s: Option<f64>,
    /// When the vibration stopped being synchronous (s, [`MAX_NON_SYNCHRONOUS`]): the run
    /// stopped there, its growth and rotation rates 0 (not fitted).
    pub unsynchronous_at_s: Option<f64>,
    /// Steps integrated.
    pub steps: u64,
    /// Machine time covered (s).
    pub machine_time_s: f64,
    /// An FE rotor's bow along the shaft at the last ΔT: each node's static deflection under
    /// the curvature load, rotor frame (empty for a Jeffcott rotor).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub bow_shape: Vec<BowPoint>,
    /// The vibration's time step Δt (s).
    pub dt_s: f64,
    /// The run's error estimate (`run.error_estimate`; `None` without it): [`ThermalError`].
    pub error: Option<ThermalError>,
    /// The conducting section's figures (`[thermal.conduction]`; `None` for the hot-spot lags).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub section: Option<SectionFacts>,
}

/// A thermal run's error estimate: the run repeated with its coupling step doubled (2h; a
/// resolved run's chunks twice as long) and with its time step doubled (2Δt), each compared
/// with the run at the coupling steps they share. Each difference is taken whole as the run's
/// error from that source (first order; the coupling converges at a measured order of 1.7 and
/// the step at the scheme's, so the whole difference over-estimates both), and `delta_t` adds
/// the two. The linear theory's own assumption and the hot-spot model's are not in it.
#[derive(Debug, Clone, Serialize)]
pub struct ThermalError {
    /// Estimated error of ΔT over the run, relative to its largest |ΔT|: `coupling.delta_t +
    /// step.delta_t` (the step's part 0 when its companion could not run).
    pub delta_t: f64,
    /// Estimated error of the growth rate (1/s), the two parts added.
    pub growth_rate: f64,
    /// Estimated error of the rotation rate (1/s), the two parts added.
    pub rotation_rate: f64,
    /// The coupling step's part: the run against its companion at 2h.
    pub coupling: Difference,
    /// The time step's part: the run against its companion at 2Δt; `None` when that companion
    /// failed (`step_failed` says why: a 2Δt past the scheme's stability limit, typically).
    pub step: Option<Difference>,
    /// Why the 2Δt companion gave no estimate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_failed: Option<String>,
    /// Steps the companions integrated.
    pub steps: u64,
}

/// How far a companion's spiral is from the run's.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Difference {
    /// The companion's coupling step (s).
    pub coupling_step_s: f64,
    /// The companion's time step (s).
    pub dt_s: f64,
    /// Largest |ΔT − ΔT_companion| at the coupling steps both have, relative to the run's
    /// largest |ΔT| there.
    pub delta_t: f64,
    /// |growth rate − the companion's| (1/s).
    pub growth_rate: f64,
    /// |rotation rate − the companion's| (1/s).
    pub rotation_rate: f64,
}

/// One node of [`ThermalResults::bow_shape`].
#[derive(Debug, Clone, Copy, Serialize)]
pub struct BowPoint {
    /// Axial position (m).
    pub z_m: f64,
    /// The bow, rotor frame (m).
    pub bow: V2,
}

/// A thermal run's bow per kelvin of ΔT along the rotor frame's x.
struct Bow {
    /// The load ([`crate::model::bow`]).
    load: Vec<RotatingLoad>,
    /// The heated station's bow, rotor frame, as a complex number (m/K).
    at_station: V2,
    /// An FE rotor's static bow at each node, `(z, rotor frame)` (m, m/K); empty: Jeffcott.
    shape: Vec<(f64, V2)>,
}

impl Bow {
    /// The bow of `model`'s rotor at the case of `p` (module docs of [`crate::model::bow`]).
    fn of(model: &Model, p: &Prepared, hs: &HotSpot) -> Result<Self> {
        match &model.rotor {
            Rotor::Jeffcott(_) => Ok(Self {
                load: jeffcott_bow_load(p.case.rotor_stiffness, hs.bow_per_kelvin),
                at_station: [hs.bow_per_kelvin, 0.0],
                shape: Vec::new(),
            }),
            Rotor::Fe(f) => {
                let node = p.case.stations[hs.station].node;
                let r = &f.rotor;
                let centre = r.z[node];
                let load = fe_bow_load(r, centre, hs.heated_length, hs.curvature_per_kelvin);
                let u = static_bow(r, p.omega, &load)?;
                let at = |i: usize| rotor_frame(&u, [4 * i, 4 * i + 1]);
                Ok(Self {
                    load,
                    at_station: at(node),
                    shape: (0..r.nodes()).map(|i| (r.z[i], at(i))).collect(),
                })
            }
        }
    }
}

/// Runs the thermal spiral of `model` at ν = `speed_ratio` with the settings `s` and the
/// hot-spot model `hs` (module docs), and — `run.error_estimate` — its error estimate
/// ([`ThermalError`]: about 1.5 to 2 times the run's cost again).
///
/// # Errors
/// As [`prepare`] and the vibration's runs; [`Error::Study`] for a state that does not
/// restart.
pub fn run_thermal(
    model: &Model,
    s: &RunSettings,
    speed_ratio: f64,
    hs: &HotSpot,
) -> Result<ThermalResults> {
    let mut request = s.request_at(0, speed_ratio);
    request.follow_ups = super::FollowUps::default();
    let mut r = spiral(model, &request, speed_ratio, hs)?;
    if s.error_estimate {
        r.error = Some(estimate(model, &request, hs, &r)?);
    }
    Ok(r)
}

/// The run's [`ThermalError`]: its companions at 2h and 2Δt.
///
/// # Errors
/// The 2h companion's (it runs what the run ran, at a longer coupling step).
fn estimate(
    model: &Model,
    request: &super::RunRequest,
    hs: &HotSpot,
    r: &ThermalResults,
) -> Result<ThermalError> {
    let coarse = match hs.step {
        Some(h) => HotSpot {
            step: Some(2.0 * h),
            ..*hs
        },
        None => HotSpot {
            revolutions: 2 * hs.revolutions,
            ..*hs
        },
    };
    let c = spiral(model, request, r.speed_ratio, &coarse)?;
    let coupling = difference(r, &c, 2);
    let mut at_2dt = *request;
    at_2dt.step.dt = Some(2.0 * r.dt_s);
    let (step, step_failed, step_steps) = match spiral(model, &at_2dt, r.speed_ratio, hs) {
        Ok(d) => (Some(difference(r, &d, 1)), None, d.steps),
        Err(e) => (None, Some(e.to_string()), 0),
    };
    let part = |f: fn(&Difference) -> f64| f(&coupling) + step.as_ref().map_or(0.0, f);
    Ok(ThermalError {
        delta_t: part(|d| d.delta_t),
        growth_rate: part(|d| d.growth_rate),
        rotation_rate: part(|d| d.rotation_rate),
        coupling,
        step,
        step_failed,
        steps: c.steps + step_steps,
    })
}

/// How far the companion `c` is from the run `r`, at the coupling steps both have (`c`'s
/// `j`-th at `r`'s `every·j`-th).
fn difference(r: &ThermalResults, c: &ThermalResults, every: usize) -> Difference {
    let (mut worst, mut size) = (0.0_f64, 0.0_f64);
    for (j, b) in c.samples.iter().enumerate() {
        let Some(a) = r.samples.get(every * j) else {
            break;
        };
        let d = [a.delta_t[0] - b.delta_t[0], a.delta_t[1] - b.delta_t[1]];
        worst = worst.max(d[0].hypot(d[1]));
        size = size.max(a.delta_t[0].hypot(a.delta_t[1]));
    }
    Difference {
        coupling_step_s: c.coupling_step_s,
        dt_s: c.dt_s,
        delta_t: if size > 0.0 { worst / size } else { 0.0 },
        growth_rate: (r.growth_rate - c.growth_rate).abs(),
        rotation_rate: (r.rotation_rate - c.rotation_rate).abs(),
    }
}

/// The spiral of `model` run by `request` at ν = `speed_ratio` with the hot-spot model `hs`
/// (module docs), without its error estimate.
fn spiral(
    model: &Model,
    request: &super::RunRequest,
    speed_ratio: f64,
    hs: &HotSpot,
) -> Result<ThermalResults> {
    let mut prep = prepare(model, request)?;
    let bow_model = Bow::of(model, &prep, hs)?;
    let omega = prep.omega;
    let spr = prep.plan.steps_per_rev.max(1);
    let (chunk, settle) = chunk_plans(&prep.plan, hs);
    let chunk_time = chunk.steps as f64 * chunk.dt;
    let h = hs.step.unwrap_or(chunk_time);
    let (mut end, mut steps) = first_state(&prep, &settle)?;
    // An accelerated step's vibration goes on until its 1× vector is steady to the tolerance.
    let steady = hs.step.map(|_| request.tolerance);
    let mut state = Heat::new(&hs.heat, hs.initial)?;
    let mut samples = Vec::new();
    let mut t = 0.0;
    let (mut runaway, mut unsynchronous) = (None, None);
    let mut integrated = 0usize;
    let mut largest = 0.0f64;
    loop {
        let dt = state.delta_t();
        let bow = cmul(bow_model.at_station, dt);
        prep.case.set_rotating(scaled(&bow_model.load, dt));
        let (rec, next, revs) = run_chunk(&prep, &chunk, &end, (hs.station, steady))?;
        steps += (revs * spr) as u64;
        integrated += revs;
        end = next;
        let (heat, power, one_x, contact) = harmonics(&prep, &rec, hs.station, spr);
        let (change, radius) = orbit_change(&prep, &rec, hs.station, spr);
        // Relative to the largest orbit so far: a 1× vector that the bow brings near zero
        // (the bow cancelling the unbalance) does not turn the coupling's small free vibration
        // into a large fraction.
        largest = largest.max(radius);
        let non_synchronous = if largest > 0.0 { change / largest } else { 0.0 };
        samples.push(ThermalSample {
            t_s: t,
            delta_t: dt,
            surface: state.surface(),
            bow,
            one_x,
            heat,
            power,
            contact_fraction: contact,
            non_synchronous,
        });
        if non_synchronous > MAX_NON_SYNCHRONOUS {
            unsynchronous = Some(t);
            break;
        }
        if dt[0].hypot(dt[1]) > hs.max_temperature_difference {
            runaway = Some(t);
            break;
        }
        if t + 0.5 * h > hs.duration {
            break;
        }
        state.advance((heat, heat_slope(&samples, h)), h);
        t += h;
    }
    let (growth_rate, rotation_rate) = match unsynchronous {
        Some(_) => (0.0, 0.0),
        None => rates(&samples, runaway.is_some()),
    };
    let end_dt = samples.last().map_or(hs.initial, |x| x.delta_t);
    Ok(ThermalResults {
        speed_ratio,
        omega,
        bow_per_kelvin: bow_model.at_station[0].hypot(bow_model.at_station[1]),
        coupling_step_s: h,
        revolutions_per_step: integrated as f64 / samples.len().max(1) as f64,
        resolved: hs.step.is_none(),
        machine_time_s: t,
        samples,
        growth_rate,
        rotation_rate,
        runaway_at_s: runaway,
        unsynchronous_at_s: unsynchronous,
        steps,
        bow_shape: (bow_model.shape.iter())
            .map(|&(z_m, b)| BowPoint {
                z_m,
                bow: cmul(b, end_dt),
            })
            .collect(),
        dt_s: chunk.dt,
        error: None,
        section: state.facts(),
    })
}

/// A coupling step's vibration plan (`revolutions` revolutions recorded at every step) and the
/// settling plan before the first (`settle_revolutions`), from the run's own plan.
fn chunk_plans(plan: &StepPlan, hs: &HotSpot) -> (StepPlan, StepPlan) {
    let spr = plan.steps_per_rev.max(1);
    let chunk = StepPlan {
        steps: hs.revolutions * spr,
        steady_from: 0,
        record_every: 1,
        ..*plan
    };
    let settle = StepPlan {
        steps: hs.settle_revolutions * spr,
        ..chunk
    };
    (chunk, settle)
}

/// The heat's slope over the next step (W/s): the last two steps' heat extrapolated linearly
/// (the first step holds its own) — second order in h.
fn heat_slope(samples: &[ThermalSample], h: f64) -> V2 {
    match samples.len() {
        0 | 1 => [0.0; 2],
        n => {
            let (p, q) = (samples[n - 2].heat, samples[n - 1].heat);
            [(q[0] - p[0]) / h, (q[1] - p[1]) / h]
        }
    }
}

/// The state after the settling revolutions from the scene's start.
fn first_state(p: &Prepared, plan: &StepPlan) -> Result<(EndState, u64)> {
    let mut st = stepper(p, plan)?;
    let end = end_of(&mut st, plan.steps)?;
    Ok((end, plan.steps as u64))
}

/// Runs `st` to step `n` and takes its end state.
fn end_of(st: &mut Stepper<'_>, n: usize) -> Result<EndState> {
    run_to_end(st, n)?
        .ok_or_else(|| Error::study("thermal", "the vibration's state could not be taken"))
}

/// Most revolutions of one accelerated step while its 1× vector settles.
pub const MAX_SETTLE_REVOLUTIONS: usize = 400;

/// One chunk from `start`: its record (every step), its end state and its revolutions. With
/// `settle = Some(tol)` (an accelerated step, whose bow has just changed) the chunk goes on a
/// revolution at a time until the station's 1× vector of its last revolution is within
/// `tol` of the one before, relative to its size (at most [`MAX_SETTLE_REVOLUTIONS`]).
fn run_chunk(
    p: &Prepared,
    plan: &StepPlan,
    start: &EndState,
    (station, settle): (usize, Option<f64>),
) -> Result<(Record, EndState, usize)> {
    let spr = plan.steps_per_rev.max(1);
    let mut st = restarted(p, plan, start)?;
    let mut n = plan.steps;
    loop {
        let end = end_of(&mut st, n)?;
        let settled = settle.is_none_or(|tol| {
            let rec = st.recorded();
            let last = one_x(p, rec, station, (rec.len() - 1 - spr, spr));
            let before = one_x(
                p,
                rec,
                station,
                (rec.len().saturating_sub(1 + 2 * spr), spr),
            );
            let d = (last[0] - before[0]).hypot(last[1] - before[1]);
            d <= tol * last[0].hypot(last[1]) || n / spr >= MAX_SETTLE_REVOLUTIONS
        });
        if settled {
            return Ok((st.recorded().clone(), end, n / spr));
        }
        n += spr;
        st.extend(n, 0);
    }
}

/// The station's 1× vector in the rotor's frame (m) over the `count` samples from `from`:
/// the mean of `z e^{−iΩt}`.
fn one_x(p: &Prepared, rec: &Record, station: usize, (from, count): (usize, usize)) -> V2 {
    let mut z = [0.0; 2];
    for i in from..from + count {
        let u = rec.disp_at(i, station);
        let (s, c) = (p.omega * rec.t[i]).sin_cos();
        z[0] += u[0] * c + u[1] * s;
        z[1] += u[1] * c - u[0] * s;
    }
    [z[0] / count as f64, z[1] / count as f64]
}

/// [`ThermalSample::non_synchronous`] of the record's last revolution (`spr` samples, one a
/// step) against the one before, less the drift of the 1× vector between them: `z_k − z_{k−N}
/// − (Z₁ − Z₀) e^{iΩt_k}` (`Z₁`, `Z₀` the two revolutions' 1× vectors in the rotor's frame) —
/// so that a synchronous response turned by a fast spiral reads ≈ 0, and a whirl of its own
/// frequency its size. The largest change and the revolution's largest radius (m); zeros with
/// less than two revolutions.
fn orbit_change(p: &Prepared, rec: &Record, station: usize, spr: usize) -> (f64, f64) {
    let n = rec.len();
    if spr == 0 || n < 2 * spr {
        return (0.0, 0.0);
    }
    let last = one_x(p, rec, station, (n - spr, spr));
    let before = one_x(p, rec, station, (n - 2 * spr, spr));
    let drift = [last[0] - before[0], last[1] - before[1]];
    let (mut change, mut radius) = (0.0f64, 0.0f64);
    for i in n - spr..n {
        let (u, v) = (rec.disp_at(i, station), rec.disp_at(i - spr, station));
        let (sn, cs) = (p.omega * rec.t[i]).sin_cos();
        let sync = [drift[0] * cs - drift[1] * sn, drift[0] * sn + drift[1] * cs];
        let d = [u[0] - v[0] - sync[0], u[1] - v[1] - sync[1]];
        change = change.max(d[0].hypot(d[1]));
        radius = radius.max(u[0].hypot(u[1]));
    }
    (change, radius)
}

/// Over the record's last revolution (`spr` samples, one a step): the friction power's first
/// harmonic in the rotor's frame `Q` (W), its mean (W), the station's 1× vector in the rotor's
/// frame (m) and the fraction of steps in contact.
fn harmonics(p: &Prepared, rec: &Record, station: usize, spr: usize) -> (V2, f64, V2, f64) {
    let omega = p.omega;
    let n = rec.len();
    let from = n.saturating_sub(spr + 1);
    let (mut q, mut power, mut contact) = ([0.0; 2], 0.0, 0usize);
    let z = one_x(p, rec, station, (from, spr.min(n - from)));
    for i in from..(from + spr).min(n) {
        let fn_ = rec.force_normal[i * rec.nstations + station];
        if fn_[0].hypot(fn_[1]) == 0.0 {
            continue;
        }
        contact += 1;
        let pw = rec.friction_power_at(i, station);
        power += pw;
        // The contact point's angle in the rotor's frame: the normal (−F_n / |F_n|) less Ωt.
        let theta = (-fn_[1]).atan2(-fn_[0]) - omega * rec.t[i];
        q[0] += pw * theta.cos();
        q[1] += pw * theta.sin();
    }
    let m = spr as f64;
    ([q[0] / m, q[1] / m], power / m, z, contact as f64 / m)
}

/// The spiral's own rate `s = ln(λ)/h` (growth Re s, 1/s; rotation Im s, rad/s in the rotor's
/// frame): λ, the ratio of successive steps' changes of ΔT, `d_{n+1} ≈ λ d_n` with
/// `d_n = ΔT_{n+1} − ΔT_n` — the dominant mode of the heat's slow dynamics whatever its fixed
/// point — by least squares over the last third of the steps (their last 10 after a runaway).
/// Zero with fewer than 4 steps or no change.
fn rates(samples: &[ThermalSample], runaway: bool) -> (f64, f64) {
    let n = samples.len();
    let from = if runaway {
        n.saturating_sub(10)
    } else {
        n - n / 3
    };
    let pts = &samples[from.min(n.saturating_sub(4))..];
    if pts.len() < 4 {
        return (0.0, 0.0);
    }
    let h = pts[1].t_s - pts[0].t_s;
    let d: Vec<V2> = pts
        .windows(2)
        .map(|w| {
            [
                w[1].delta_t[0] - w[0].delta_t[0],
                w[1].delta_t[1] - w[0].delta_t[1],
            ]
        })
        .collect();
    // λ = Σ d_{n+1} conj(d_n) / Σ |d_n|².
    let (mut re, mut im, mut den) = (0.0, 0.0, 0.0);
    for w in d.windows(2) {
        let (a, b) = (w[0], w[1]);
        re += b[0] * a[0] + b[1] * a[1];
        im += b[1] * a[0] - b[0] * a[1];
        den += a[0] * a[0] + a[1] * a[1];
    }
    if den == 0.0 || h <= 0.0 {
        return (0.0, 0.0);
    }
    let (re, im) = (re / den, im / den);
    ((re.hypot(im)).ln() / h, im.atan2(re) / h)
}
