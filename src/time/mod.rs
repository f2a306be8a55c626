//! Explicit central differences with forward-increment Lagrange multipliers (paper Sec. 2.5).
//!
//! Each step (Eqs. 34–47), [`Stepper::step`]:
//! 1. **predict** every body with λ = 0: `M̃ u*ⁿ⁺¹ = f̃ⁿ`, `M̃ = M/Δt² + C/(2Δt)`,
//!    `f̃ⁿ = fⁿ + (2M/Δt² − K) uⁿ + (C/(2Δt) − M/Δt²) uⁿ⁻¹` (Eqs. 35–36);
//! 2. **select** the candidate pairs near the rotor (broad phase), freeze `n`, `a` at the
//!    prediction and compute the gaps `g*`; every pair with `g*` below the deepest
//!    penetration enters the problem;
//! 3. **solve** the complementarity problem `p ≥ 0`, `g* + W p ≥ 0`, `pᵀ(g* + W p) = 0` with
//!    `W = G_N M̃⁻¹ G_NTᵀ` summed over the bodies in the pair (Eq. 45, with sign handling);
//! 4. **correct** `uⁿ⁺¹ = u* + M̃⁻¹ G_NTᵀ p` (Eq. 47, compression-positive `p`);
//! 5. **guard**: a NaN or a diverging displacement stops the run with the step, time, Δt and
//!    stability limit;
//! 6. **record** the samples the analysis reads and hand frames to the sinks.
//!
//! Massless stators (Eq. 49) are undeformed at the start of the step and enter `W` through
//! their compliance `K⁻¹` on the contact DOFs ([`compliance`]).
//!
//! The [`Scheme::Collocated`] variant solves the massless stators' contact at tₙ with the rotor
//! held at uⁿ (a static complementarity problem on the stator compliance) and applies that force
//! in the central-difference step — second order, but explicit in the stator stiffness, so its
//! stable step is `2/ω_c`, `ω_c = √((k_r + k_s)/m)`.
//!
//! The implicit schemes [`Scheme::Newmark`] and [`Scheme::GeneralizedAlpha`] ([`newmark`]) run
//! the same forward-increment step with each body's `M̃` replaced by its generalised-α operator
//! `S = (1−α_m)/((1−α_f)βΔt²) M + γ/(βΔt) C + K`: the prediction carries the load at tₙ₊₁, the
//! contact is imposed at tₙ₊₁ on `W = G S⁻¹ Gᵀ`, and no stability limit bounds Δt
//! (docs/IMPLICIT.md).
//!
//! The loop allocates nothing: every buffer lives in the [`Stepper`]'s workspace built before
//! it, and the record is sized for the whole run. The exceptions are a meshed stator's node
//! touching for the first time (its compliance column, cached) and a contact problem larger
//! than any before and than the first capacity of the dense buffers (256 pairs).
//!
//! # Where new physics goes
//!
//! * A speed that varies in time: Ω enters the step in three places only — the external load
//!   of the prediction (`Stepper::predict`: the unbalance force at t), the bodies' step
//!   operators (`M̃`, `A`, `B` of the rotor hold C + ΩG) and the tangent `a = Ω × n` of the pair
//!   geometry (`select`). [`Stepper::with_profile`] makes the load a function of t (φ, Ω, Ω̇ of
//!   a [`crate::model::SpeedProfile`]); the tangent depends only on the sign of Ω, which a
//!   profile keeps; a gyroscopic rotor keeps M̃ factored at the case's speed Ω_f and corrects
//!   each prediction for `(Ω − Ω_f) G q̇ + Ω̇ K_st q` by one more solve on that factor
//!   (`spin`). Speed-tabulated bearings under a varying speed are refused by
//!   `analysis::prepare_transient`. The loop and its phases stay as they are.
//! * Another contact law (stick–slip, wear): the law is the force direction per unit normal
//!   force `b = n + μa` and the unknowns per pair in `solve` (assembly of `W`, correction); the
//!   selection, the schemes and the recording do not change.
//!
//! Files: [`plan`] (Δt and steps, the limits that refuse an absurd run), [`budget`] (steps,
//! memory and time estimated up front), [`record`] (what a run keeps), `body` (a body with mass,
//! central differences or implicit), `reduced` (a Craig–Bampton stator in its reduced coordinates), [`newmark`] (the generalised-α family), `spin` (a gyroscopic rotor's
//! correction for a varying speed), [`compliance`] (massless stators), `select` (which pairs enter a contact problem), `solve` (the contact
//! solve), `ring` (exact ring kinematics in a solve), `workspace` (buffers), `stepper` (the step), [`frame`] (frames for sinks).

mod abradable;
mod blocks;
mod body;
pub mod budget;
pub mod compliance;
mod dashpot;
mod drive;
pub mod frame;
mod guard;
mod loop_rotor;
pub mod newmark;
pub mod plan;
pub mod record;
mod reduced;
mod ring;
mod select;
mod solve;
mod spin;
mod stator;
mod stepper;
mod stick;
mod wear;
mod workspace;

pub use budget::{estimate, one_at_a_time, Budget};
pub use compliance::{path_cost, EAGER_DOFS, PATH_COLUMNS_NNZ};
pub use frame::{Frame, FrameSink, PairForce};
pub use newmark::Alpha;
pub use plan::{
    plan_duration, plan_steps, Initial, Scheme, StepParams, StepPlan, CONTACT_SWITCHING_FACTOR,
    MAX_STEPS, STATOR_WITH_MASS_RHO_INF, WINDOW_MULTIPLE,
};
pub use record::{ContactStats, Record, RunStats};
pub use stepper::{EndState, History, Sink, Stepper, Tangent, TangentStats};

use crate::error::SolveError;
use crate::model::Case;

/// Integrates one case with a step plan, returning the record and counters.
pub fn integrate(
    case: &Case,
    scheme: Scheme,
    plan: &StepPlan,
    init: Initial,
) -> Result<(Record, RunStats), SolveError> {
    integrate_with(case, scheme, plan, init, None)
}

/// [`integrate`] with an optional [`FrameSink`] receiving full-state frames.
pub fn integrate_with(
    case: &Case,
    scheme: Scheme,
    plan: &StepPlan,
    init: Initial,
    sink: Sink<'_>,
) -> Result<(Record, RunStats), SolveError> {
    Stepper::new(case, scheme, plan, init)?.run(sink)
}
