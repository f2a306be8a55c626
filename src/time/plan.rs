//! The step plan: which integration scheme, which Δt, how many steps, what is recorded.

use crate::error::SolveError;
use crate::model::Case;
use std::f64::consts::PI;

/// How the contact of massless stators is timed against the rotor's central-difference step.
///
/// Stators with mass are coupled by forward increment (Eqs. 34–47) in both schemes; the schemes
/// differ only in the massless stators (Eq. 49).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
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
}

impl Scheme {
    /// Name as written in scene files (`run.integrator`).
    pub fn name(self) -> &'static str {
        match self {
            Scheme::ForwardIncrement => "forward_increment",
            Scheme::Collocated => "collocated",
        }
    }
    /// Nominal order in Δt with a massless stator (used by the error estimate).
    pub fn nominal_order(self) -> f64 {
        match self {
            Scheme::ForwardIncrement => 1.0,
            Scheme::Collocated => 2.0,
        }
    }
}

/// Time-step choices of a run.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
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
    /// Total revolutions.
    pub revolutions: usize,
    /// Revolutions cut as transient before the analysed steady window.
    pub transient_revolutions: usize,
    /// Recorded samples per revolution.
    pub samples_per_rev: usize,
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
                let w = (case.rotor_omega_max.powi(2) + k * case.station_inv_mass[s]).sqrt();
                let l = stable_step(w, (xi * case.rotor_omega_max / w).min(1.0));
                if l < limit {
                    limit = l;
                    reason = format!(
                        "massless stator stiffness applied explicitly, ω_c ≤ √(ω_max² + k_s (M⁻¹)_ii) = {w:.4e} rad/s"
                    );
                }
            }
        }
    }
    (limit, reason)
}

/// Δt before rounding, the stability limit, the paper rule's Δt and the highest frequency,
/// for a run whose fastest spin is `omega` (rad/s): see [`plan_steps`].
fn choose_dt(case: &Case, p: &StepParams, omega: f64) -> Result<(f64, f64, f64, f64), SolveError> {
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
    let dt0 = match p.dt {
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
        None => rule_dt.min(0.8 * limit),
    };
    Ok((dt0, limit, rule_dt, omega_max))
}

/// Chooses Δt: the paper's rule (Sec. 3) with T_min = 2π/ω_c, ω_c the highest frequency of the
/// rotor with every stator's contact stiffness added, capped by the explicit stability limit of
/// what enters the loop with mass (and, for the collocated integrator, the massless stators'
/// contact stiffness), or the user's override checked against that limit. Δt is then reduced
/// so a revolution holds a whole number of recorded samples and steps.
pub fn plan_steps(case: &Case, p: &StepParams) -> Result<StepPlan, SolveError> {
    let (dt0, limit, rule_dt, omega_max) = choose_dt(case, p, case.omega)?;
    let t_rev = 2.0 * PI / case.omega;
    let spr = p.samples_per_rev;
    let per_sample = (t_rev / (dt0 * spr as f64) - 1e-9).ceil().max(1.0) as usize;
    let steps_per_rev = per_sample * spr;
    Ok(StepPlan {
        dt: t_rev / steps_per_rev as f64,
        steps_per_rev,
        steps: steps_per_rev * p.revolutions,
        record_every: per_sample,
        steady_from: steps_per_rev * p.transient_revolutions.min(p.revolutions),
        limit,
        rule_dt,
        omega_max,
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
/// [`SolveError::StepTooLarge`] for a user Δt above the stability limit.
pub fn plan_duration(
    case: &Case,
    p: &StepParams,
    omega_max: f64,
    duration: f64,
) -> Result<StepPlan, SolveError> {
    let (dt0, limit, rule_dt, w_max) = choose_dt(case, p, omega_max)?;
    let steps = (duration / dt0 - 1e-9).ceil().max(1.0) as usize;
    let dt = duration / steps as f64;
    let t_rev = 2.0 * PI / omega_max;
    let record_every = ((t_rev / (dt * p.samples_per_rev as f64)) + 1e-9)
        .floor()
        .max(1.0) as usize;
    Ok(StepPlan {
        dt,
        steps_per_rev: (t_rev / dt + 1e-9).floor() as usize,
        steps,
        record_every,
        // A transient has no steady part: its contact figures cover the whole run.
        steady_from: 0,
        limit,
        rule_dt,
        omega_max: w_max,
    })
}
