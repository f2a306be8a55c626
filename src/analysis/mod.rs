//! Analyses over a model: one speed, a speed sweep, a convergence study, a bench, stator
//! stresses, mesh refinement (the linear rotordynamics of the rotor alone is
//! [`crate::linear`]).
//!
//! # One path for a run
//!
//! A run at one speed is prepared once and run once:
//!
//! 1. [`prepare`] builds, for a [`RunRequest`] (ν, scheme and Δt rule, start state, window
//!    policy, follow-ups: [`request`]), the [`Case`](crate::model::Case) at ω = ν ω_n and its
//!    [`StepPlan`](crate::time::StepPlan) (Δt, steps, recording interval) into a [`Prepared`];
//! 2. whoever wants frames — the VTK/HDF5 writers (`crate::results::ResultsSink`), the
//!    [`StressProbe`] — is built from that prepared case and plan by the command layer;
//! 3. [`Prepared::run`] integrates with any set of those sinks (none, one, or several through a
//!    [`Fanout`]), analyses the record into [`SpeedResults`] and runs the follow-ups the
//!    request asks for (the error estimate's companions, the coexistence check).
//!
//! [`RunSettings`] are the scene's settings, shared by a sweep's runs; each run is a request
//! made from them ([`RunSettings::request`], [`RunSettings::request_at`]), and every derived
//! run — a pilot, a companion, a coexistence start, a bench reference — is a request of its
//! own ([`request`]), run by the same driver (`Prepared::execute`).
//!
//! A sweep ([`sweep()`]) is a parallel map of such a per-speed run over the speeds. Sinks never
//! drive a run, and nothing here writes files (see `crate::output`).
//!
//! # Conventions
//!
//! Non-dimensional quantities (`_nd`) follow the paper: displacements over |Z0(ω)|, forces over
//! the unbalance force |Σ m_u e e^{iφ}| ω², frequencies over ω_n; speeds are given as
//! ν = ω/ω_n.
//!
//! Files: [`speed`] (prepare, run to the steady state, analyse, error estimate), [`fanout`]
//! (several frame sinks as one), [`steady`]
//! (stationarity of the window, period classification, where lines are resolved), [`dynamics`]
//! (quasi-periodic or chaotic: the 0–1 test on the Poincaré section), `lengthen` (the window
//! lengthened for that test, and a run that runs away when continued), `richardson` (the step
//! pairs' error estimates; a run that never repeats), [`verify`] (the step choice verified by
//! the run: a run whose own estimate misses the tolerance repeated at half the step),
//! [`refinement`] (what a run so refined reports), [`discrepancy`] (how far apart two runs'
//! results are, relative to a reference run), `pilot` (what every pilot run shares), [`request`] (the typed run request), [`coexist`] (a second response at the same
//! speed, found from another start), [`sweep`](mod@sweep) (speeds, variants, the
//! parallel map), [`convergence`](mod@convergence), [`regimes`] (Poincaré-period ranges, quasi-resonances),
//! [`bench`](mod@bench) (timing and the comparison with a converged sweep), [`stress`] (stator stress
//! probe), [`refine`] (mesh-refinement metrics).

pub mod arclength;
pub mod autonomous;
pub mod autonomous_branch;
pub mod autostep;
pub mod bench;
pub mod branch;
pub mod coexist;
pub mod coexist_branches;
pub mod coexist_orbits;
pub mod continuation;
pub mod convergence;
pub mod cutoff;
pub mod discrepancy;
pub mod dry;
pub mod dynamics;
pub mod estimate;
pub mod fanout;
pub mod floquet;
mod lengthen;
pub mod notices;
pub mod orbits_at;
pub mod parameter;
pub mod periodic;
mod pilot;
pub mod refine;
pub mod refinement;
pub mod regimes;
pub mod request;
mod richardson;
pub mod speed;
pub mod steady;
pub mod stress;
pub mod sweep;
pub mod switch;
pub mod thermal;
pub mod transient;
pub mod verify;
pub mod waterfall;
pub mod wear;
pub mod whirl;

pub use autostep::{choose, StepChoice};
pub use coexist::{Coexistence, Start};
pub use convergence::{
    convergence, reduced_case, ConvergencePoint, ConvergenceResults, REDUCED_COLLOCATED,
    REDUCED_GENERALIZED_ALPHA,
};
pub use discrepancy::{extent_scale, extents_error, orbit_span, ExtentsScale};
pub use dynamics::{Dynamics, Regime};
pub use lengthen::MAX_CLASSIFY_FACTOR;
pub use refinement::{RejectedStep, StepRefinement};
pub use regimes::{
    quasi_resonances, regime_class, regime_label, regime_name, regime_ranges, RegimeRange,
    REGIME_CLASSES,
};
pub use request::{FollowUps, PilotStart, RunRequest, StartState, Unpiloted, Window};
pub use speed::{analyse, prepare, run_speed, ErrorEstimate, Fanout, Prepared, SpeedResults};
pub use stress::{StressProbe, StressResults, StressTrace};
pub use sweep::{sweep, sweep_speeds, Sweep, SweepResults};
pub use transient::{
    orbit_snapshots, prepare_transient, OrbitSnapshot, OrderWindow, TransientPrepared,
    TransientResults, SNAPSHOT_REVOLUTIONS,
};
pub use verify::MAX_STEP_REFINEMENTS;

use crate::model::Model;
use crate::scene::{Component, IntegratorKind, OutputSpec, RunSpec};
use crate::time::{Initial, Scheme, StepParams};

/// Largest Poincaré period reported (longer ones count as not periodic).
pub const MAX_PERIOD: usize = 8;

/// Settings of a run at one speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSettings {
    /// Integrator and step choices.
    pub step: StepParams,
    /// Companion run at 2Δt for an error estimate.
    pub error_estimate: bool,
    /// Run the check for a coexisting response (`run.check_coexistence`, [`coexist`]).
    pub check_coexistence: bool,
    /// Initial rotor state.
    pub initial: Initial,
    /// Analysed response component: 0 = x, 1 = y.
    pub component: usize,
    /// Relative tolerance (`run.tolerance`, of the orbit's size): the steady-state test and
    /// the Poincaré period are judged to it.
    pub tolerance: f64,
    /// Most transient revolutions while waiting for the steady state
    /// (`run.max_transient_revolutions`).
    pub max_transient_revolutions: usize,
    /// Revolutions a window that is not periodic is lengthened to, for the 0–1 test
    /// (`run.classify_revolutions`, [`dynamics`]).
    pub classify_revolutions: usize,
    /// The integrator and Δt chosen from the tolerance ([`autostep::choose`]), reported with
    /// each run; `None` when the scene's rule or `run.dt` set the step.
    pub choice: Option<StepChoice>,
    /// The reduction the runs integrate instead of the scene's `[run.reduction]` (the
    /// error-target choice's reduced schemes and its cut-off, [`autostep::choose`]); `None`:
    /// the model as the scene reduces it, or not.
    pub reduction: Option<crate::resolve::ReductionInput>,
}

impl RunSettings {
    /// From a scene's `[run]` table and its `output.component` (`"x"`, else y: the scene
    /// checks the name when it is loaded).
    pub fn from_run(run: &RunSpec, component: &str) -> Self {
        Self {
            step: StepParams {
                integrator: scheme(run.integrator(), run.rho_inf),
                dt: run.dt,
                duration: run.duration,
                harmonics: run.harmonics,
                revolutions: run.revolutions,
                transient_revolutions: run.transient_revolutions,
                samples_per_rev: run.samples_per_rev,
                max_steps: run.max_steps.unwrap_or(crate::time::plan::MAX_STEPS),
                dt_scale: 1.0,
            },
            error_estimate: run.error_estimate,
            check_coexistence: run.check_coexistence,
            initial: Initial {
                u: run.initial_displacement,
                v: run.initial_velocity,
            },
            component: Component::from_name(component).unwrap_or_default().index(),
            tolerance: run.tolerance,
            max_transient_revolutions: run
                .max_transient_revolutions
                .unwrap_or(run.transient_revolutions * crate::scene::MAX_TRANSIENT_FACTOR),
            classify_revolutions: run.classify_revolutions,
            choice: None,
            reduction: None,
        }
    }

    /// [`RunSettings::from_run`] of a whole scene: `generalized_alpha` without `run.rho_inf`
    /// takes ρ∞ = [`crate::time::STATOR_WITH_MASS_RHO_INF`] when a stator has mass (the only ρ∞
    /// that resolves its rigid contact with the rotor, [`default_rho_inf`]).
    pub fn from_scene(scene: &crate::scene::Scene) -> Self {
        let mut s = Self::from_run(&scene.run, &scene.output.component);
        if scene.run.rho_inf.is_none() && scene.stators.iter().any(|st| st.has_mass()) {
            if let Scheme::GeneralizedAlpha { rho_inf } = &mut s.step.integrator {
                *rho_inf = crate::time::STATOR_WITH_MASS_RHO_INF;
            }
        }
        s
    }
}

/// ρ∞ of generalised-α for `case` when `run.rho_inf` is not given: 0
/// ([`crate::time::STATOR_WITH_MASS_RHO_INF`]) with a stator with mass, whose closed contact
/// with the rotor is a rigid constraint between two masses that only asymptotic annihilation
/// resolves; else [`crate::scene::DEFAULT_RHO_INF`].
pub fn default_rho_inf(case: &crate::model::Case) -> f64 {
    if case.stators.iter().any(|s| !s.massless()) {
        crate::time::STATOR_WITH_MASS_RHO_INF
    } else {
        crate::scene::DEFAULT_RHO_INF
    }
}

/// True when `model` has a ring stator with mass.
pub(crate) fn has_ring_with_mass(model: &Model) -> bool {
    model
        .stators
        .iter()
        .any(|s| matches!(s, crate::model::StatorPlan::Ring(r) if r.mass > 0.0))
}

/// The time loop's scheme for the scene's `run.integrator` (and `run.rho_inf` of
/// `generalized_alpha`, default [`crate::scene::DEFAULT_RHO_INF`]).
pub fn scheme(kind: IntegratorKind, rho_inf: Option<f64>) -> Scheme {
    match kind {
        IntegratorKind::ForwardIncrement => Scheme::ForwardIncrement,
        IntegratorKind::Collocated => Scheme::Collocated,
        IntegratorKind::Newmark => Scheme::Newmark,
        IntegratorKind::GeneralizedAlpha => Scheme::GeneralizedAlpha {
            rho_inf: rho_inf.unwrap_or(crate::scene::DEFAULT_RHO_INF),
        },
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
    /// The full spectrum of x + iy too (up to the same frequency, both signs).
    pub full_spectrum: bool,
}

impl Keep {
    /// Everything the pictures of a single run (`rubsim run`) draw: the orbit, the force
    /// history and the spectrum up to `output.cascade_max_freq`, by default 1.5 max(ν, 1)
    /// (f/ω_n, rounded up to a whole number).
    pub fn single_run(output: &OutputSpec, speed_ratio: f64) -> Self {
        let fmax = output
            .cascade_max_freq
            .unwrap_or(speed_ratio.max(1.0) * 1.5);
        Self {
            orbit: true,
            force_history: true,
            spectrum_up_to: Some(fmax.ceil() as u32),
            full_spectrum: true,
        }
    }
}

/// The scene's single speed as ν = ω/ω_n: `run.speed_ratio`, else `run.speed` (rad/s) over
/// the rotor's ω_n; `None` for a sweep scene.
pub fn single_speed(run: &RunSpec, model: &Model) -> Option<f64> {
    run.speed_ratio
        .or_else(|| run.speed.map(|w| w / model.rotor.natural_frequency()))
}

/// Speeds of a study at a few speeds (convergence, stress): `given`, else the scene's single
/// speed, else ν = 1.7, 3.1, 4.9 (the paper's Fig. 10).
pub fn study_speeds(run: &RunSpec, model: &Model, given: &[f64]) -> Vec<f64> {
    if given.is_empty() {
        match single_speed(run, model) {
            Some(v) => vec![v],
            None => vec![1.7, 3.1, 4.9],
        }
    } else {
        given.to_vec()
    }
}
