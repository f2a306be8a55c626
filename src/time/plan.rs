//! The step plan: which integration scheme, which Δt, how many steps, what is recorded; and
//! the rotor's initial state a run starts from.

use super::newmark::Alpha;
use crate::error::SolveError;
use crate::math::V2;
use crate::model::Case;
use std::f64::consts::PI;

/// Initial state of the rotor, on station 0's node (node 0 without stations).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Initial {
    /// Displacement `[x, y]` (m).
    pub u: V2,
    /// Velocity `[vx, vy]` (m/s).
    pub v: V2,
}

/// The time integrator, and how the contact of massless stators is timed against its step.
///
/// Stators with mass are coupled by forward increment (Eqs. 34–47) in every scheme; the two
/// explicit schemes differ only in the massless stators (Eq. 49). The implicit schemes
/// (`time::newmark`) integrate every body with mass by generalised-α and impose the contact
/// by the same forward increment at tₙ₊₁ on their step operator's flexibility.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Scheme {
    /// The paper's scheme: the massless stator's force enters the forward-increment solve on
    /// the predicted configuration (Eq. 49). First order in Δt with a massless stator;
    /// unconditionally stable with respect to the stator stiffness.
    ForwardIncrement,
    /// The massless stator's contact force is solved at tₙ from the rotor held at uⁿ (a static
    /// complementarity problem on the stator compliance) and applied in the central-difference
    /// step. Second order; explicit in the stator stiffness, so its stable step is `2/ω_c`,
    /// `ω_c = √((k_r + k_s)/m)` for a Jeffcott rotor.
    Collocated,
    /// Implicit Newmark average acceleration (β = ¼, γ = ½): second order without contact,
    /// unconditionally stable, conserves the energy of an undamped linear body; the contact
    /// is imposed at tₙ₊₁ by forward increment on `W = G S⁻¹ Gᵀ` (docs/IMPLICIT.md).
    Newmark,
    /// Implicit generalised-α (Chung–Hulbert) of spectral radius `rho_inf` ∈ [0, 1] at
    /// infinite frequency: second order, unconditionally stable, damps the unresolved high
    /// modes; the contact as for [`Scheme::Newmark`].
    GeneralizedAlpha {
        /// Spectral radius at infinite frequency ρ∞.
        rho_inf: f64,
    },
}

impl Scheme {
    /// Name as written in scene files (`run.integrator`).
    pub fn name(self) -> &'static str {
        match self {
            Scheme::ForwardIncrement => "forward_increment",
            Scheme::Collocated => "collocated",
            Scheme::Newmark => "newmark",
            Scheme::GeneralizedAlpha { .. } => "generalized_alpha",
        }
    }
    /// Nominal order in Δt with a massless stator (used by the error estimate).
    pub fn nominal_order(self) -> f64 {
        match self {
            Scheme::ForwardIncrement => 1.0,
            Scheme::Collocated => 2.0,
            Scheme::Newmark | Scheme::GeneralizedAlpha { .. } => 2.0,
        }
    }
    /// True for the collocated scheme (the massless stators' contact solved at tₙ).
    pub fn collocated(self) -> bool {
        self == Scheme::Collocated
    }
    /// The generalised-α coefficients of an implicit scheme; `None` for the explicit ones.
    pub fn implicit(self) -> Option<Alpha> {
        match self {
            Scheme::ForwardIncrement | Scheme::Collocated => None,
            Scheme::Newmark => Some(Alpha::newmark()),
            Scheme::GeneralizedAlpha { rho_inf } => Some(Alpha::generalized(rho_inf)),
        }
    }
}

/// Fewest steps an implicit scheme may take per period of the highest frequency of the
/// response, `T_min = 2π/ω_c` (the contact frequency of the paper's rule): below, the contact
/// oscillation is not represented at all, whatever the stability.
pub const MIN_IMPLICIT_STEPS_PER_PERIOD: f64 = 4.0;

/// Time-step choices of a run.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepPlan {
    /// Time step (s).
    pub dt: f64,
    /// Steps per revolution (an integer multiple of `samples_per_rev`).
    pub steps_per_rev: usize,
    /// Total steps.
    pub steps: usize,
    /// Record every this many steps.
    pub record_every: usize,
    /// First step of the analysed steady window, `transient_revolutions × steps_per_rev`
    /// (at most `steps`): the window covers the instants `steady_from ≤ k < steps`.
    pub steady_from: usize,
    /// Explicit stability limit (s).
    pub limit: f64,
    /// The paper's rule Δt = min(T_min/(32n), 2π/(32nω)) (s).
    pub rule_dt: f64,
    /// Highest frequency of the system including contact stiffness (rad/s).
    pub omega_max: f64,
}

/// Parameters of a run that fix the step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepParams {
    /// Integration scheme.
    pub integrator: Scheme,
    /// Override Δt (s).
    pub dt: Option<f64>,
    /// Paper rule's n.
    pub harmonics: f64,
    /// A fixed window (s, `run.duration`): the plan takes ⌈duration/Δt⌉ steps and cuts the
    /// first half of its whole revolutions as transient ([`plan_steps`]); `revolutions` and
    /// `transient_revolutions` do not apply. `None`: the run's length is `revolutions`.
    pub duration: Option<f64>,
    /// Total revolutions.
    pub revolutions: usize,
    /// Revolutions cut as transient before the analysed steady window.
    pub transient_revolutions: usize,
    /// Recorded samples per revolution.
    pub samples_per_rev: usize,
    /// Most steps the run may take ([`MAX_STEPS`] unless `run.max_steps` says otherwise).
    pub max_steps: u64,
    /// Without `dt`: Δt is this multiple of the paper's rule (1 by default; the error-target
    /// choice `analysis::autostep` sets it), still capped at 0.8× the stability limit
    /// (explicit) or at `T_min /` [`MIN_IMPLICIT_STEPS_PER_PERIOD`] (implicit), and at one
    /// step per recorded sample.
    pub dt_scale: f64,
}

/// Default of `run.max_steps`: the most integration steps one run may take. At the measured
/// 0.1 µs per step of a Jeffcott rotor (docs/PERFORMANCE.md) that is about two minutes, at 3.4 µs
/// (a 200-DOF FE rotor) about an hour; a plan that needs more is refused with its figures.
pub const MAX_STEPS: u64 = 1_000_000_000;

/// The shortest analysed steady window (revolutions): [`plan_steps`] lengthens a shorter one to
/// it, so that the ½× and ⅓× lines of a periodic response fall on exact frequency bins of the
/// window (the analysis reads the lines over the last whole multiple of 6 revolutions).
pub const WINDOW_MULTIPLE: usize = 6;

/// The revolutions of a run of `revolutions` whose first `transient` are cut: an analysed window
/// `revolutions − transient` shorter than [`WINDOW_MULTIPLE`] is lengthened to it (none when
/// `revolutions ≤ transient`).
pub fn planned_revolutions(revolutions: usize, transient: usize) -> usize {
    let window = revolutions.saturating_sub(transient);
    if window == 0 {
        revolutions
    } else {
        transient + window.max(WINDOW_MULTIPLE)
    }
}

/// Most bytes the record of one run may take (the samples are held in memory for the
/// analysis): 4 GiB.
pub const MAX_RECORD_BYTES: f64 = 4.0 * 1024.0 * 1024.0 * 1024.0;

/// Smallest mass of a stator with mass relative to the rotor's modal mass m_r: a lighter
/// stator is integrated explicitly at a step set by its own (meaningless) frequency and its
/// contact impulses are not resolved; it should be massless.
pub const MIN_STATOR_MASS_RATIO: f64 = 1e-6;

/// Bytes one recorded sample takes: time, observed displacement, stator energy, active pairs,
/// and per station displacement, force and normal force.
pub fn sample_bytes(nstations: usize) -> f64 {
    (8 + 16 + 8 + 4 + nstations.max(1) * 48) as f64
}

/// Contact stiffness bound (N/m) per station, from massless (`massless = true`) or all stators.
fn station_contact_stiffness(case: &Case, massless_only: bool) -> Vec<f64> {
    let mut k = vec![0.0; case.stations.len()];
    for s in &case.stators {
        if !massless_only || s.massless() {
            // A stator facing several stations (3-D meshes) bounds each of them.
            let kb = s.contact_stiffness_bound();
            for st in s.stations() {
                k[st] += kb;
            }
        }
    }
    k
}

/// Safety factor φ on the contact frequency of a massless stator's stiffness applied explicitly
/// (collocated scheme): the contact term of the stability bound is taken as
/// `k_s (M⁻¹)_ii / φ²`, i.e. Δt ≤ φ · 2/√(k_s (M⁻¹)_ii) when the contact dominates, and the free
/// rotor's limit when k_s → 0. The Weyl bound `√(ω_max² + k_s (M⁻¹)_ii)` bounds the highest
/// frequency of the rotor *in* contact (checked against the exact eigenvalue and the
/// amplification matrix of the step: on the FE paper rotor with the rod at a bearing node,
/// k_s = 2.5·10⁹ N/m, it gives 1.957 µs against the exact 1.981 µs, and the step's spectral
/// radius stays below 1 up to that), but a unilateral contact switches that stiffness on and
/// off, and on a multi-DOF rotor the switching pumps energy into the step: that case diverges at
/// 0.66 and 0.80 of the linear limit (1.3 and 1.56 µs, after 3.2·10⁶ and 2.2·10⁵ steps, with
/// or without friction) and runs to the end at 0.61 (1.2 µs); with φ = 0.5 its limit is
/// 1.02 µs. (A Jeffcott rotor stays bounded, though inaccurate, up to 0.93 of the linear limit;
/// the plan's rule keeps it far below either.)
pub const CONTACT_SWITCHING_FACTOR: f64 = 0.5;

/// Stable step of central differences with implicit viscous damping of ratio ξ at frequency ω:
/// Δt ≤ (2/ω)(√(1+ξ²) − ξ).
fn stable_step(w: f64, xi: f64) -> f64 {
    2.0 / w * ((1.0 + xi * xi).sqrt() - xi)
}

/// The explicit stability limit (s) of what enters the loop with mass — the free rotor,
/// stator internal modes and, for the collocated scheme, the massless stators' contact
/// stiffness applied explicitly — and what sets it.
fn stability_limit(case: &Case, scheme: Scheme, w_stators: f64) -> (f64, String) {
    let xi = case.rotor_xi_max;
    let mut limit = stable_step(case.rotor_omega_max, xi.min(1.0));
    let mut reason = format!("free rotor, ω = {:.4e} rad/s", case.rotor_omega_max);
    if w_stators > 0.0 {
        let l = stable_step(w_stators, 0.0);
        if l < limit {
            limit = l;
            reason = format!("stator with mass, ω ≤ {w_stators:.4e} rad/s");
        }
    }
    if scheme == Scheme::Collocated {
        for (s, k) in station_contact_stiffness(case, true).iter().enumerate() {
            if *k > 0.0 {
                // Weyl bound: ω² ≤ ω_max,rotor² + k_s (M⁻¹)_ii at the station node (exact
                // for the Jeffcott rotor: (k_r + k_s)/m).
                // The contact term over φ²: the contact switches on and off.
                let phi2 = CONTACT_SWITCHING_FACTOR * CONTACT_SWITCHING_FACTOR;
                let w = (case.rotor_omega_max.powi(2) + k * case.station_inv_mass[s] / phi2).sqrt();
                let l = stable_step(w, (xi * case.rotor_omega_max / w).min(1.0));
                if l < limit {
                    limit = l;
                    reason = format!(
                        "massless stator stiffness applied explicitly, ω_c ≤ √(ω_max² + k_s (M⁻¹)_ii/φ²) = {w:.4e} rad/s with φ = {CONTACT_SWITCHING_FACTOR}, as the contact switches on and off"
                    );
                }
            }
        }
    }
    (limit, reason)
}

/// Δt before rounding and what set it, for a run whose fastest spin is `omega` (rad/s): see
/// [`plan_steps`].
struct Chosen {
    /// Δt before rounding (s).
    dt: f64,
    /// Explicit stability limit (s).
    limit: f64,
    /// What sets the stability limit.
    reason: String,
    /// The paper rule's Δt (s).
    rule_dt: f64,
    /// Highest frequency of the system including contact stiffness (rad/s).
    omega_max: f64,
}

/// The paper's rule (Sec. 3) with T_min = 2π/ω_c, ω_c the highest frequency of the rotor with
/// every stator's contact stiffness added, capped by the explicit stability limit of what
/// enters the loop with mass (and, for the collocated integrator, the massless stators'
/// contact stiffness), or the user's override checked against that limit; `omega` (rad/s) is
/// the fastest spin of the run.
fn choose_dt(case: &Case, p: &StepParams, omega: f64) -> Result<Chosen, SolveError> {
    check_stator_masses(case)?;
    check_implicit_stators(case, p.integrator)?;
    let m = case.rotor_mass;
    let kr = case.rotor_stiffness;
    // Contact frequency of the reference (Jeffcott-equivalent) system, √((k_r + k_s)/m_r):
    // the T_min of the paper's rule. FE rotors' own high modes only bound stability.
    let w_contact = station_contact_stiffness(case, false)
        .iter()
        .map(|k| ((kr + k) / m).sqrt())
        .fold(case.speed_ratio.recip() * case.omega, f64::max);
    let w_stators = case
        .stators
        .iter()
        .map(|s| s.omega_max_sq_bound().sqrt())
        .fold(0.0, f64::max);
    let omega_max = w_contact.max(w_stators);
    let (limit, reason) = stability_limit(case, p.integrator, w_stators);
    // T_min of the paper's rule: the shortest period the response is made of — rotor modes and
    // the contact frequency. Internal modes of stators with mass only bound stability (above).
    let t_min = 2.0 * PI / w_contact;
    let rule_dt = (t_min / (32.0 * p.harmonics)).min(2.0 * PI / (32.0 * p.harmonics * omega));
    let dt = match p.dt {
        // Implicit: accuracy only — no stability cap, but a step must resolve T_min.
        Some(dt) if p.integrator.implicit().is_some() => {
            let max = t_min / MIN_IMPLICIT_STEPS_PER_PERIOD;
            if dt > max {
                return Err(SolveError::StepTooCoarse {
                    dt,
                    max,
                    integrator: p.integrator.name().into(),
                    reason: format!(
                        "fewer than {MIN_IMPLICIT_STEPS_PER_PERIOD} steps per period T_min = {t_min:.4e} s of the contact frequency {w_contact:.4e} rad/s"
                    ),
                });
            }
            dt
        }
        None if p.integrator.implicit().is_some() => {
            (p.dt_scale * rule_dt).min(t_min / MIN_IMPLICIT_STEPS_PER_PERIOD)
        }
        Some(dt) => {
            if dt > limit {
                return Err(SolveError::StepTooLarge {
                    dt,
                    limit,
                    integrator: p.integrator.name().into(),
                    reason,
                });
            }
            dt
        }
        None => (p.dt_scale * rule_dt).min(0.8 * limit),
    };
    Ok(Chosen {
        dt,
        limit,
        reason,
        rule_dt,
        omega_max,
    })
}

/// Refuses a plan of more than `p.max_steps` steps (counted in floating point, before any cast
/// to an integer) with its figures, what set Δt and the keys to change.
fn check_steps(
    case: &Case,
    p: &StepParams,
    c: &Chosen,
    steps: f64,
    steps_per_rev: f64,
    revolutions: usize,
    t_rev: f64,
) -> Result<(), SolveError> {
    if steps.is_nan() || steps > p.max_steps as f64 {
        let why = match p.dt {
            Some(_) => "`run.dt`".to_string(),
            None if 0.8 * c.limit < p.dt_scale * c.rule_dt && p.integrator.implicit().is_none() => {
                format!("0.8 × the stability limit {:.3e} s: {}", c.limit, c.reason)
            }
            None if p.dt_scale != 1.0 => format!(
                "{:.3} × the paper's rule, the step `run.tolerance` asks for",
                p.dt_scale
            ),
            None => format!(
                "the paper's rule with n = {} (`run.harmonics`)",
                p.harmonics
            ),
        };
        return Err(SolveError::TooManySteps {
            steps,
            steps_per_rev,
            revolutions,
            dt: c.dt,
            why,
            max: p.max_steps,
            advice: advice(case, p, t_rev, &c.reason),
        });
    }
    Ok(())
}

/// Refuses a record of `samples` samples above [`MAX_RECORD_BYTES`].
fn check_record(case: &Case, samples: f64) -> Result<(), SolveError> {
    let bytes = samples * sample_bytes(case.stations.len());
    if bytes > MAX_RECORD_BYTES {
        return Err(SolveError::RecordTooLarge {
            bytes,
            samples,
            max: MAX_RECORD_BYTES,
        });
    }
    Ok(())
}

/// Chooses Δt (the paper's rule capped by the stability limit, or the user's
/// checked Δt; implicit schemes: the paper's rule, or the user's Δt if it resolves T_min),
/// then reduces it so a revolution holds a whole number of recorded samples and steps. The run
/// lasts [`planned_revolutions`]: an analysed window after the `transient_revolutions` shorter
/// than [`WINDOW_MULTIPLE`] revolutions is lengthened to it.
///
/// # Errors
/// [`SolveError::StepTooLarge`] for a user Δt above the stability limit (explicit schemes),
/// [`SolveError::StepTooCoarse`] for a user Δt of an implicit scheme above
/// `T_min/`[`MIN_IMPLICIT_STEPS_PER_PERIOD`],
/// [`SolveError::TooManySteps`] and [`SolveError::RecordTooLarge`] for an absurd plan,
/// [`SolveError::Meaningless`] for a stator with mass far lighter than the rotor.
pub fn plan_steps(case: &Case, p: &StepParams) -> Result<StepPlan, SolveError> {
    let c = choose_dt(case, p, case.omega)?;
    let t_rev = 2.0 * PI / case.omega;
    let spr = p.samples_per_rev;
    // In floating point first: an absurd plan (Δt → 0, a revolution of hours) is refused with
    // its figures before any count is cast to an integer.
    let per_sample = (t_rev / (c.dt * spr as f64) - 1e-9).ceil().max(1.0);
    let steps_per_rev = per_sample * spr as f64;
    let dt = t_rev / steps_per_rev;
    let (steps, revolutions, transient) = match p.duration {
        // A fixed window: ⌈duration/Δt⌉ steps at the rounded Δt (the last one ends within a
        // step past `duration`), the first half of its whole revolutions cut as transient.
        Some(d) => {
            let steps = (d / dt - 1e-9).ceil().max(1.0);
            let whole = (steps / steps_per_rev).floor().min(u32::MAX as f64) as usize;
            (steps, (steps / steps_per_rev).ceil() as usize, whole / 2)
        }
        None => {
            let revolutions = planned_revolutions(p.revolutions, p.transient_revolutions);
            let transient = p.transient_revolutions.min(revolutions);
            (steps_per_rev * revolutions as f64, revolutions, transient)
        }
    };
    check_steps(case, p, &c, steps, steps_per_rev, revolutions, t_rev)?;
    check_record(case, spr as f64 * revolutions as f64 + 1.0)?;
    let (per_sample, steps_per_rev) = (per_sample as usize, steps_per_rev as usize);
    Ok(StepPlan {
        dt,
        steps_per_rev,
        steps: steps as usize,
        record_every: per_sample,
        steady_from: steps_per_rev * transient,
        limit: c.limit,
        rule_dt: c.rule_dt,
        omega_max: c.omega_max,
    })
}

/// The step plan of a transient run of `duration` (s) whose fastest spin is `omega_max`
/// (rad/s): Δt as [`plan_steps`] chooses it at `omega_max` (the paper's rule, capped at 0.8×
/// the stability limit, or the user's checked Δt), then shortened so `duration` holds a whole
/// number of steps; a sample is recorded every `record_every` steps, so that a revolution at
/// `omega_max` holds at least `samples_per_rev` samples (more at lower speeds).
/// `steps_per_rev` is the number of steps of one revolution at `omega_max`, rounded down.
///
/// # Errors
/// As [`plan_steps`].
pub fn plan_duration(
    case: &Case,
    p: &StepParams,
    omega_max: f64,
    duration: f64,
) -> Result<StepPlan, SolveError> {
    let c = choose_dt(case, p, omega_max)?;
    let t_rev = 2.0 * PI / omega_max;
    let steps_f = (duration / c.dt - 1e-9).ceil().max(1.0);
    // `as` saturates: at usize::MAX (≈ 1.8e19) rather than a wrapped or u32-capped count.
    let revolutions = (duration / t_rev).ceil() as usize;
    check_steps(case, p, &c, steps_f, t_rev / c.dt, revolutions, t_rev).map_err(|mut e| {
        // A transient's length is its profile's, not `run.revolutions`: the last advice
        // (fewer revolutions or a larger budget) says so.
        if let SolveError::TooManySteps { advice, .. } = &mut e {
            *advice = format!(
                "{}a shorter profile (`run.speed_profile`, {duration:e} s) or, for a run that is meant, a larger `run.max_steps`",
                advice.rsplit_once("; ").map_or(String::new(), |(a, _)| format!("{a}; "))
            );
        }
        e
    })?;
    let steps = steps_f as usize;
    let dt = duration / steps as f64;
    let record_every = ((t_rev / (dt * p.samples_per_rev as f64)) + 1e-9)
        .floor()
        .max(1.0) as usize;
    check_record(case, (steps / record_every) as f64 + 2.0)?;
    Ok(StepPlan {
        dt,
        steps_per_rev: (t_rev / dt + 1e-9).floor() as usize,
        steps,
        record_every,
        // A transient has no steady part: its contact figures cover the whole run.
        steady_from: 0,
        limit: c.limit,
        rule_dt: c.rule_dt,
        omega_max: c.omega_max,
    })
}

/// What to change when the plan needs too many steps: the keys that set Δt or the length of a
/// revolution, and the budget itself.
fn advice(case: &Case, p: &StepParams, t_rev: f64, reason: &str) -> String {
    let mut a = Vec::new();
    if p.dt.is_some() {
        a.push("raise `run.dt` or leave it out".to_string());
    }
    if reason.starts_with("stator with mass") {
        a.push(
            "make the stiffest stator with mass massless (`density`/`mass` = 0) or coarser".into(),
        );
    } else if reason.starts_with("massless stator") {
        a.push("lower the stators' `stiffness_ratio`/stiffness or use `run.integrator = \"forward_increment\"`".into());
    }
    let w_top = case.rotor_omega_max.max(1.0);
    if case.omega * 1e4 < w_top {
        a.push(format!(
            "the speed ω = {:.3e} rad/s is tiny against the rotor's highest frequency {w_top:.3e} rad/s (a revolution lasts {t_rev:.3e} s): check the rotor's stiffness (bearings, shaft) and the speed keys",
            case.omega
        ));
    }
    a.push(format!(
        "fewer `run.revolutions` ({}) or, for a run that is meant, a larger `run.max_steps`",
        p.revolutions
    ));
    a.join("; ")
}

/// ρ∞ of generalised-α on a case with a stator with mass, and the largest it accepts there.
///
/// While a stator with mass touches the rotor, the rotor section and the stator's contact DOFs
/// (a ring's centre, a rod's or mesh's lumped node) are joined by a rigid unilateral constraint
/// (no compliance between the two masses): the relative normal motion is a mode of infinite
/// frequency that no step resolves. The implicit
/// schemes impose the constraint on displacements at tₙ₊₁, so a closing step puts an
/// acceleration spike `Δu_c/(βΔt²)` into aₙ₊₁ whose error mode the scheme carries on with its
/// spectral radius at infinite frequency, ρ∞, per step (docs/IMPLICIT.md §2): with ρ∞ > 0 the
/// next predictions overshoot, the unilateral contact releases and closes again, and each
/// release returns `½ pₙ gₙ₊₁`. Only ρ∞ = 0 (asymptotic annihilation) removes it in one step.
/// Measured on `tests/data/scenes/ring.toml` at 1.7 ω_n: ρ∞ = 0 gives the converged explicit
/// 1× whirl (1.688 |Z0|) at every step and over variations of the ring's mass, support,
/// damping, friction and the speed; ρ∞ = 0.2 fails with μ = 0.3, ρ∞ ≥ 0.3 runs to a
/// non-periodic orbit of 0.92 |Z0| at any step, ρ∞ = 1 (and Newmark) diverges within 230 steps.
/// The paper's rod with mass (steel, 4 elements, 1.7 ω_n): ρ∞ = 0 runs to the explicit orbit at
/// Δt 5.8e-5 … 7.2e-6 s; ρ∞ = 0.8 fails (contact blow-up) at every Δt ≤ 2.9e-5 s, ρ∞ = 0.5 at
/// 7.2e-6 s.
pub const STATOR_WITH_MASS_RHO_INF: f64 = 0.0;

/// Refuses the implicit schemes with ρ∞ above [`STATOR_WITH_MASS_RHO_INF`] (Newmark: ρ∞ = 1)
/// on a case with a stator with mass.
///
/// Newmark (ρ∞ = 1) keeps the energy of every mode it does not resolve: the stator's internal
/// modes and the rigid rotor–stator constraint of a closed contact (above), excited by each
/// impact; the contact imposed at tₙ₊₁ turns that energy into chatter, and each release returns
/// `½ pₙ gₙ₊₁` to the system (docs/IMPLICIT.md) — measured: the paper's rod with mass (four
/// elements, steel) diverges at 3.1 ω_n at any step tried; the ring with mass of
/// `tests/data/scenes/ring.toml` diverges at its first contacts.
fn check_implicit_stators(case: &Case, scheme: Scheme) -> Result<(), SolveError> {
    let rho = match scheme {
        Scheme::Newmark => 1.0,
        Scheme::GeneralizedAlpha { rho_inf } => rho_inf,
        _ => return Ok(()),
    };
    if rho <= STATOR_WITH_MASS_RHO_INF {
        return Ok(());
    }
    let Some(index) = case.stators.iter().position(|s| !s.massless()) else {
        return Ok(());
    };
    let message = if scheme == Scheme::Newmark {
        "it has mass, and `run.integrator = \"newmark\"` (average acceleration, no numerical dissipation) keeps the energy its contacts put into the unresolved rigid contact between the two masses and the stator's modes, which makes the contact chatter and the run diverge; use `run.integrator = \"generalized_alpha\"` (its default ρ∞ is 0 with a stator with mass) or an explicit integrator".to_string()
    } else {
        format!(
            "it has mass, and `run.integrator = \"generalized_alpha\"` has ρ∞ = {rho} > {STATOR_WITH_MASS_RHO_INF}: the closed contact is a rigid constraint between two masses that no step resolves, and a scheme that keeps a share ρ∞ of it per step makes the contact chatter (measured: a non-periodic orbit of half the converged whirl on a ring, a contact blow-up on the rod); set `run.rho_inf = {STATOR_WITH_MASS_RHO_INF}` (the default with a stator with mass) or use an explicit integrator"
        )
    };
    Err(SolveError::Meaningless {
        index,
        name: case.stators[index].name.clone(),
        message,
    })
}

/// Refuses a stator with mass lighter than [`MIN_STATOR_MASS_RATIO`] × the rotor's modal mass.
fn check_stator_masses(case: &Case) -> Result<(), SolveError> {
    for (index, s) in case.stators.iter().enumerate() {
        if s.massless() {
            continue;
        }
        let dim = s.mesh.as_ref().map_or(2, |m| m.dim.max(2)) as f64;
        let mass = s.m.diagonal().iter().sum::<f64>() / dim;
        let ratio = mass / case.rotor_mass;
        if ratio.is_nan() || ratio < MIN_STATOR_MASS_RATIO {
            let key = if s.is_ring { "mass" } else { "density" };
            return Err(SolveError::Meaningless {
                index,
                name: s.name.clone(),
                message: format!(
                    "its mass {mass:.3e} kg is {ratio:.1e} × the rotor's modal mass {:.3e} kg, below {MIN_STATOR_MASS_RATIO:e}: so light a stator is integrated at a step set by its own frequency ({:.3e} rad/s) and its contact impulses are not resolved; make it massless (`stator.{index}.{key} = 0`) or give it a real mass",
                    case.rotor_mass,
                    s.omega_max_sq_bound().sqrt()
                ),
            });
        }
    }
    Ok(())
}
