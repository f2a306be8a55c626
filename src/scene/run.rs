//! `[run]`: speed or sweep, duration, integrator and time step.

use super::yes;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Time integrators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum IntegratorKind {
    /// The paper's scheme: explicit central differences with forward-increment Lagrange
    /// multipliers (Eqs. 34–47), massless stators by Eq. 49. First order in Δt with a massless
    /// stator; unconditionally stable with respect to the stator stiffness.
    ForwardIncrement,
    /// Central differences with the massless stator's contact force solved at tₙ from the rotor
    /// position at tₙ (stator force collocated with the displacement). Second order; its stable
    /// step shrinks as the stator stiffens (Δt < 2/√((k_r + k_s)/m)). Stators with mass are
    /// coupled by forward increment as in the paper.
    Collocated,
    /// Implicit Newmark average acceleration (β = ¼, γ = ½) with the contact imposed at
    /// tₙ₊₁ on the implicit operator's flexibility: unconditionally stable, Δt chosen by
    /// accuracy only (docs/IMPLICIT.md).
    Newmark,
    /// Implicit generalised-α (Chung–Hulbert) of spectral radius `run.rho_inf` at infinite
    /// frequency: as `newmark`, with the unresolved high modes damped.
    GeneralizedAlpha,
}

impl IntegratorKind {
    /// Name as written in scene files.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::ForwardIncrement => "forward_increment",
            IntegratorKind::Collocated => "collocated",
            IntegratorKind::Newmark => "newmark",
            IntegratorKind::GeneralizedAlpha => "generalized_alpha",
        }
    }
    /// Nominal order in Δt with a massless stator (used by the error estimate).
    pub fn nominal_order(self) -> f64 {
        match self {
            IntegratorKind::ForwardIncrement => 1.0,
            IntegratorKind::Collocated => 2.0,
            IntegratorKind::Newmark | IntegratorKind::GeneralizedAlpha => 2.0,
        }
    }
}

/// What to run.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(extend("not" = {"required": ["speed_ratio", "speed"]}))]
pub struct RunSpec {
    /// Speed as ω/ω_n (single run).
    pub speed_ratio: Option<f64>,
    /// Speed ω (rad/s) (single run).
    pub speed: Option<f64>,
    /// Speed sweep over ω/ω_n.
    pub sweep: Option<SweepSpec>,
    /// A 2-D map (`rubsim map`): the runs at every pair of values of two parameters.
    pub map: Option<MapSpec>,
    /// A speed that varies in time (run-up, coast-down, a tabulated history): the run
    /// integrates the whole profile, whose length sets the run's; `revolutions` and
    /// `transient_revolutions` do not apply.
    pub speed_profile: Option<super::SpeedProfileSpec>,
    /// Scheduled changes of a transient run (`[[run.event]]`): a sudden unbalance, a
    /// stator's clearance changing.
    #[serde(default)]
    pub event: Vec<super::EventSpec>,
    /// Wear magnification A (> 0, default 1): stators with `[stator.wear]` wear A times as fast
    /// as Archard's law says, so a run of machine time t represents a wear time A t
    /// (`scene::wear`).
    #[serde(default = "unit_factor")]
    pub wear_acceleration: f64,
    /// A fixed window (s, > 0): the run integrates exactly this long from its start state
    /// (`initial_displacement`, `initial_velocity` at t = 0) at the given or chosen Δt, and is
    /// never lengthened — not for the steady state, not for the 0–1 test — ROSS's
    /// `run_rubbing(t = np.arange(0, duration, dt))`. The steps are ⌈duration/Δt⌉ at the Δt
    /// the run would take anyway (rounded down so a revolution holds a whole number of
    /// recorded samples: the Poincaré section and the 1×, ½×, ⅓× lines need a sample at every
    /// revolution), so the last step ends at most one Δt past `duration` (exactly on it when Δt
    /// divides it); Δt is not stretched to land on `duration`, which would break that rule.
    /// The whole run is recorded (frames, force history); the orbit, spectrum, Poincaré
    /// section, extents and the steady-state verdict are of its second half (the last
    /// ⌈N/2⌉ of its N whole revolutions, and the part revolution at the end; the whole run
    /// below two revolutions). A window that is not steady to `tolerance` is reported as a
    /// warning (summary.json `warnings`, stderr), never lengthened. With it, `revolutions` and
    /// `transient_revolutions` do not apply (as with `speed_profile`; the scenes write them,
    /// so `--set run.duration=…` works on any scene); `max_transient_revolutions`,
    /// `classify_revolutions` and `speed_profile` are refused beside it. A sweep or map runs
    /// this duration at every speed. The error estimate's companions (2Δt and, at a rub, 4Δt)
    /// cover the same duration; the Δt/2 companion restarted from the end and the coexistence
    /// check (`check_coexistence`) would integrate past it and are not run. Pilots of
    /// `auto_step` still choose Δt when `dt` is not given; the run starts from the scene's
    /// initial state, not from their settled one. Left out: the run's length is
    /// `revolutions`, lengthened as the keys above say.
    pub duration: Option<f64>,
    /// Total simulated revolutions.
    #[serde(default = "default_revs")]
    pub revolutions: usize,
    /// Revolutions cut as transient before analysis.
    #[serde(default = "default_transient")]
    pub transient_revolutions: usize,
    /// Relative tolerance of the results (default 1e-3): the steady state is proven when the
    /// analysed window's orbit extents and Poincaré section change by less than this fraction
    /// of the orbit's size, and the Poincaré period is judged to it (`--tol` on the command
    /// line).
    #[serde(default = "default_tolerance")]
    pub tolerance: f64,
    /// Choose Δt and the integrator (and, for an FE rotor or a meshed stator with mass, its
    /// modal reduction) from `tolerance` by pilot runs (`analysis::autostep`) when `dt` is not
    /// given: the commands `run`, `sweep`, `map`, `bench`, `check` and `convergence` do, for
    /// steady runs (a `speed_profile` keeps the rule). Default `true`. `false` is the paper's
    /// rule, an explicit choice: Δt from `harmonics` (Δt ≤ min(T_min/(32 n), 2π/(32 n ω))),
    /// capped by the stability limit, `integrator` or collocated — the paper's scenes
    /// (`scenes/paper/`) and the timing benchmarks (`bench_*`) write it, reproducing the
    /// paper's step at the paper's cost (their rule meets 1e-3 as it is; docs/VALIDATION.md
    /// §16).
    #[serde(default = "crate::scene::yes")]
    pub auto_step: bool,
    /// Most revolutions the transient may grow to while the run waits for the steady state
    /// (default 5 × `transient_revolutions`); a run not steady by then is reported
    /// `steady = false`.
    pub max_transient_revolutions: Option<usize>,
    /// Revolutions the analysed window is lengthened to when the response is not periodic, so
    /// that its Poincaré section holds enough points to tell quasi-periodic from chaotic
    /// (`analysis::dynamics`, default [`DEFAULT_CLASSIFY_REVOLUTIONS`]; within `run.max_steps`).
    /// Periodic runs are not lengthened; 0 never lengthens (a window shorter than
    /// `analysis::dynamics::MIN_SECTION_POINTS` revolutions reads `undetermined`).
    #[serde(default = "default_classify_revolutions")]
    pub classify_revolutions: usize,
    /// Integrator. Left out, a run without `dt` has it chosen with Δt from `run.tolerance`
    /// (`analysis::autostep`, by the commands `run`, `sweep`, `map`, `bench` and `check`);
    /// otherwise, and in the library's plain runs, `collocated` ([`RunSpec::integrator`]).
    pub integrator: Option<IntegratorKind>,
    /// Spectral radius at infinite frequency ρ∞ ∈ [0, 1] of `integrator = "generalized_alpha"`
    /// (default [`DEFAULT_RHO_INF`]; refused with any other integrator): 1 keeps every mode,
    /// lower values damp the modes the step does not resolve.
    #[schemars(extend("default" = DEFAULT_RHO_INF))]
    pub rho_inf: Option<f64>,
    /// Time step override (s). Rounded down so a revolution holds a whole number of steps.
    /// Left out, the commands choose Δt (and the integrator, when not given) from
    /// `run.tolerance` by pilot runs (`analysis::autostep`).
    pub dt: Option<f64>,
    /// The paper's rule Δt ≤ min(T_min/(32 n), 2π/(32 n ω)) with n = `harmonics`.
    #[serde(default = "default_harmonics")]
    pub harmonics: f64,
    /// Recorded samples per revolution (a power of two is best for the FFT).
    #[serde(default = "default_spr")]
    pub samples_per_rev: usize,
    /// Estimate the discretisation error by companion runs at 2Δt and, at a rub, Δt/2
    /// restarted from the run's end state (a steady periodic run:
    /// `analysis::speed::combine_fine`) or 4Δt (`analysis::speed::combine_levels`).
    #[serde(default = "yes")]
    pub error_estimate: bool,
    /// Check that the response is the only one at this speed (`analysis::coexist`): at a rub,
    /// or without contact where the linear orbit reaches half the clearance, a companion at the
    /// same scheme and Δt starts from the other extreme — in full contact at the clearance with
    /// forward synchronous whirl, or on the no-contact linear response when the run is in
    /// full annular rub — settles, and is compared with the run (contact fraction, period,
    /// extents). Default `true`.
    #[serde(default = "yes")]
    pub check_coexistence: bool,
    /// Most integration steps one run may take (default 10⁹, [`crate::time::MAX_STEPS`]): a run
    /// whose plan needs more is refused before it starts, naming the figure. Raise it for a
    /// long run that is meant.
    pub max_steps: Option<u64>,
    /// Initial rotor station displacement `[x, y]` (m) at node 0.
    #[serde(default)]
    pub initial_displacement: [f64; 2],
    /// Initial rotor station velocity `[vx, vy]` (m/s) at node 0.
    #[serde(default)]
    pub initial_velocity: [f64; 2],
    /// Integrate an FE rotor in a reduced basis (`[run.reduction]`, docs/IMPLICIT.md §7): its
    /// lowest undamped modes up to a cut-off plus one static column per contact DOF, so the
    /// contact flexibility stays the full model's. Left out: the full model.
    pub reduction: Option<ReductionSpec>,
}

/// `[run.reduction]`: the cut-off of an FE rotor's modal reduction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReductionSpec {
    /// Cut-off ω_cut (rad/s): every undamped mode below it is kept. Left out: `cutoff_factor`
    /// × the highest frequency the run resolves, max(n ω, ω_c) (n = `run.harmonics`, ω the
    /// case's speed, ω_c the contact frequency √((k_r + Σk_s)/m_r)).
    pub cutoff: Option<f64>,
    /// κ of the default cut-off κ max(n ω, ω_c) (default [`DEFAULT_CUTOFF_FACTOR`], at least 1).
    #[schemars(extend("default" = DEFAULT_CUTOFF_FACTOR))]
    pub cutoff_factor: Option<f64>,
    /// Reduce the FE rotor (default: true for an FE rotor; a Jeffcott rotor cannot be).
    pub rotor: Option<bool>,
    /// Reduce every meshed stator with mass by Craig–Bampton on its contact DOFs with the
    /// fixed-interface modes below the same cut-off (default false; docs/IMPLICIT.md §7.2).
    pub stators: Option<bool>,
}

/// κ of `[run.reduction]`'s default cut-off.
pub const DEFAULT_CUTOFF_FACTOR: f64 = 2.0;

impl RunSpec {
    /// The integrator of a run whose step is not chosen from the tolerance: `run.integrator`,
    /// `collocated` when left out (see docs/VALIDATION.md for why).
    pub fn integrator(&self) -> IntegratorKind {
        self.integrator.unwrap_or(IntegratorKind::Collocated)
    }
}

/// Speed sweep over ω/ω_n, inclusive of both ends.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// First ω/ω_n.
    pub from: f64,
    /// Last ω/ω_n.
    pub to: f64,
    /// Increment.
    pub step: f64,
    /// Optional parameter study: one sweep per value of a scene key (Sec. 4.2 sensitivity).
    pub vary: Option<VarySpec>,
}

/// A sensitivity study: the sweep is repeated for each value of one scene key.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VarySpec {
    /// Dotted key, as for `--set` (e.g. `stator.0.clearance_nd`).
    pub key: String,
    /// Values to set.
    pub values: Vec<f64>,
}

/// ρ∞ of `generalized_alpha` when `run.rho_inf` is not given.
pub const DEFAULT_RHO_INF: f64 = 0.8;

/// A 2-D regime map (`rubsim map`): one run for every pair of values of two parameters — the
/// speed ω/ω_n (key `speed_ratio`) and a scene key, or two scene keys at the scene's speed.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MapSpec {
    /// The horizontal axis.
    pub x: MapAxis,
    /// The vertical axis.
    pub y: MapAxis,
}

/// One axis of a map: a key and its values, as a list or an inclusive range.
#[derive(Debug, Clone, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MapAxis {
    /// `speed_ratio` (ω/ω_n), or a dotted scene key as for `--set` (`stator.0.clearance_nd`).
    pub key: String,
    /// The values, listed.
    pub values: Option<Vec<f64>>,
    /// Or a range: first value …
    pub from: Option<f64>,
    /// … last value (inclusive) …
    pub to: Option<f64>,
    /// … and increment.
    pub step: Option<f64>,
}

/// The key of a map axis that is the speed ω/ω_n.
pub const SPEED_KEY: &str = "speed_ratio";

impl MapAxis {
    /// Whether this axis is the speed ω/ω_n.
    pub fn is_speed(&self) -> bool {
        self.key == SPEED_KEY
    }

    /// The axis's values: the list, or the range `from, from + step, …, to`
    /// ([`inclusive_range`]); empty when neither is given.
    pub fn resolved(&self) -> Vec<f64> {
        match (&self.values, self.from, self.to, self.step) {
            (Some(v), ..) => v.clone(),
            (None, Some(a), Some(b), Some(h)) => inclusive_range(a, b, h),
            _ => Vec::new(),
        }
    }
}

/// The values `from, from + step, …` up to `to` inclusive, each rounded to 9 decimals so that
/// `0.1` steps do not drift.
/// A range whose count is not finite or exceeds 10⁹ (refused by validation) gives no value.
pub fn inclusive_range(from: f64, to: f64, step: f64) -> Vec<f64> {
    let count = ((to - from) / step + 1e-9).floor();
    if !(0.0..1e9).contains(&count) {
        return Vec::new();
    }
    let n = count as usize;
    (0..=n)
        .map(|i| {
            let v = from + i as f64 * step;
            (v * 1e9).round() / 1e9
        })
        .collect()
}

fn default_revs() -> usize {
    220
}
fn default_transient() -> usize {
    100
}
fn default_tolerance() -> f64 {
    1e-3
}
/// Default of `run.classify_revolutions`: twice the fewest section points the 0–1 test is
/// applied to, where its `K` is within 0.05 of its limit on closed-form sequences
/// (`analysis::dynamics`).
pub const DEFAULT_CLASSIFY_REVOLUTIONS: usize = 400;
fn default_classify_revolutions() -> usize {
    DEFAULT_CLASSIFY_REVOLUTIONS
}
/// Default of `run.max_transient_revolutions`: this many times `run.transient_revolutions`.
pub const MAX_TRANSIENT_FACTOR: usize = 5;
fn default_harmonics() -> f64 {
    4.0
}
fn unit_factor() -> f64 {
    1.0
}
fn default_spr() -> usize {
    64
}
