//! One run at one speed, as a typed request: the case (ν and the reduction), the scheme and
//! its Δt rule, the start state, the window policy, what follows the run, and how its record
//! is judged. Every run the analyses make is a [`RunRequest`] built by one of the named
//! constructors below — the scene's run ([`RunSettings::request`],
//! [`RunSettings::request_at`]), a step or cut-off pilot ([`RunRequest::pilot`]), an
//! error-estimate companion ([`RunRequest::companion`]), the coexistence check's run from
//! another start ([`RunRequest::coexistence`]), a bench reference ([`RunRequest::reference`]),
//! the stress probe's fixed plan ([`RunRequest::fixed`]) — and every one is run by the same
//! function, `Prepared::execute` ([`super::speed`]).
//!
//! A pilot's end state reaches the run at its speed explicitly: the step choice keeps, for
//! each pilot speed, the index of that speed in the list the choice was made for
//! ([`PilotStart::speed_index`]), and whoever runs the k-th speed of that list asks for
//! [`RunSettings::request_at`]`(k, ν)`.

use super::{RunSettings, StepChoice};
use crate::model::Model;
use crate::resolve::ReductionInput;
use crate::time::{Initial, Scheme, StepParams};

/// Transient revolutions a pilot settles a restart in before its analysed window.
pub const PILOT_RESETTLE: usize = 2;

/// Transient revolutions of a run that starts from its speed's pilot state: the restart at the
/// run's step settles in them (as a pilot's does, [`PILOT_RESETTLE`]), and the steady-state
/// test on the analysed window goes on from there as on any run.
pub const RESTART_TRANSIENT: usize = PILOT_RESETTLE;

/// The disk's state `[x, y]`, `[vx, vy]` at the end of the finest pilot at a pilot speed.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PilotStart {
    /// Index of the pilot speed in the speeds the step choice was made for.
    pub speed_index: usize,
    /// ν = ω/ω_n of the pilots (reported; the run is found by [`PilotStart::speed_index`]).
    pub speed_ratio: f64,
    /// The state (m, m/s), at a whole revolution: the unbalance at its phase of t = 0.
    pub initial: Initial,
}

/// Where a run starts (its state at t = 0).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StartState {
    /// The scene's initial state (`run.initial_displacement`, `run.initial_velocity`).
    Scene(Initial),
    /// The state the step choice's pilots ended in at this speed: the settling they integrated
    /// is not integrated again.
    Pilot(PilotStart),
    /// A state given by the analysis that asks for the run: the coexistence check's other
    /// start, a pilot's settled state or the previous pilot's end.
    Given(Initial),
}

impl StartState {
    /// The state itself (m, m/s).
    pub fn initial(&self) -> Initial {
        match self {
            Self::Scene(i) | Self::Given(i) => *i,
            Self::Pilot(p) => p.initial,
        }
    }
}

/// How long a run is and whether it goes on past its plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Window {
    /// The plan's transient, then its window; while the window's transient residual is above
    /// the tolerance the run goes on and the window slides, up to `max_transient` revolutions
    /// of transient (and `run.max_steps`); a window then not periodic is lengthened to
    /// `classify` revolutions (0: never) for the 0–1 test.
    Settle {
        /// Most transient revolutions (`run.max_transient_revolutions`).
        max_transient: usize,
        /// Revolutions a window that is not periodic is lengthened to
        /// (`run.classify_revolutions`).
        classify: usize,
    },
    /// The plan as it stands, never lengthened: a pilot, a companion, `run.duration`.
    Fixed,
}

/// The runs that follow a run and judge it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct FollowUps {
    /// Companion runs at 2Δt (and 4Δt or Δt/2) estimate its discretisation error.
    pub error_estimate: bool,
    /// A run from another start looks for a coexisting response ([`super::coexist`]).
    pub coexistence: bool,
    /// Where the step was chosen from the tolerance and the error estimate misses it, the step
    /// is refined and the run repeated ([`super::verify`]); not for a run whose frames are
    /// written to a time series as they are computed.
    pub refine_step: bool,
}

/// One run at one speed (module doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunRequest {
    /// ν = ω/ω_n.
    pub speed_ratio: f64,
    /// The scheme, the Δt rule (`dt`, or `dt_scale` × the paper's rule), the plan's
    /// revolutions or duration, the samples per revolution and the step budget.
    pub step: StepParams,
    /// Where the run starts.
    pub start: StartState,
    /// Whether it goes on past its plan.
    pub window: Window,
    /// The runs that follow it.
    pub follow_ups: FollowUps,
    /// Relative tolerance (`run.tolerance`, of the orbit's size) the steady state and the
    /// Poincaré period are judged to.
    pub tolerance: f64,
    /// Analysed response component: 0 = x, 1 = y.
    pub component: usize,
    /// The reduction integrated instead of the scene's (`None`: the scene's, or none).
    pub reduction: Option<ReductionInput>,
    /// The step choice the run reports (`None`: `run.dt` or the paper's rule set Δt).
    pub choice: Option<StepChoice>,
    /// The start and revolutions the run had before [`RunRequest::from_pilot`] replaced them
    /// (`None`: not started from a pilot's state); [`RunRequest::without_pilot`] restores them.
    pub unpiloted: Option<Unpiloted>,
}

/// What [`RunRequest::from_pilot`] replaced: the scene's start, transient and revolutions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unpiloted {
    /// The start before.
    pub start: StartState,
    /// Transient revolutions before.
    pub transient_revolutions: usize,
    /// Revolutions before.
    pub revolutions: usize,
}

impl RunSettings {
    /// The scene's run at ν = `speed_ratio` from the scene's initial state: its window
    /// settles to the steady state (or is `run.duration`, fixed), with the scene's follow-ups
    /// (no coexistence check for a fixed window: its companion would settle past its end).
    pub fn request(&self, speed_ratio: f64) -> RunRequest {
        let fixed = self.step.duration.is_some();
        RunRequest {
            speed_ratio,
            step: self.step,
            start: StartState::Scene(self.initial),
            window: if fixed {
                Window::Fixed
            } else {
                Window::Settle {
                    max_transient: self.max_transient_revolutions,
                    classify: self.classify_revolutions,
                }
            },
            follow_ups: FollowUps {
                error_estimate: self.error_estimate,
                coexistence: self.check_coexistence && !fixed,
                refine_step: self.choice.is_some() && self.error_estimate,
            },
            tolerance: self.tolerance,
            component: self.component,
            reduction: self.reduction,
            choice: self.choice,
            unpiloted: None,
        }
    }

    /// The scene's run at the `index`-th of the speeds the step choice was made for (ν =
    /// `speed_ratio`): [`RunSettings::request`], started from the state the pilots ended in
    /// at that speed when they kept one ([`RunRequest::from_pilot`]).
    pub fn request_at(&self, index: usize, speed_ratio: f64) -> RunRequest {
        let pilot = self.choice.as_ref().and_then(|c| c.start_at(index));
        debug_assert!(pilot.is_none_or(|p| p.speed_ratio == speed_ratio));
        self.request(speed_ratio).from_pilot(pilot)
    }

    /// [`RunSettings::request_at`], or — for a run that writes a time series (`series`:
    /// `output.vtk`, `output.hdf5`) — [`RunSettings::request`] from the scene's own start
    /// state: its frames are the scene's run from t = 0 (`from_revolution` counts revolutions
    /// of that run, its transient included), not a pilot's continuation with the transient
    /// cut; its step is not refined after the run ([`FollowUps::refine_step`]: the frames
    /// already written are the chosen step's).
    pub fn request_for(&self, index: usize, speed_ratio: f64, series: bool) -> RunRequest {
        if series {
            let mut r = self.request(speed_ratio);
            r.follow_ups.refine_step = false;
            r
        } else {
            self.request_at(index, speed_ratio)
        }
    }

    /// The reduction the runs integrate: [`RunSettings::reduction`] when set, else the
    /// scene's (`model.reduction`).
    pub fn reduction_of<'a>(&'a self, model: &'a Model) -> Option<&'a ReductionInput> {
        self.reduction.as_ref().or(model.reduction.as_ref())
    }
}

impl RunRequest {
    /// This run from the start, transient and revolutions it had before
    /// [`RunRequest::from_pilot`] (itself when it was not started from a pilot's state).
    pub fn without_pilot(mut self) -> Self {
        if let Some(u) = self.unpiloted.take() {
            self.start = u.start;
            self.step.transient_revolutions = u.transient_revolutions;
            self.step.revolutions = u.revolutions;
        }
        self
    }

    /// This run started from `pilot`'s end state when given: where the window settles, its
    /// transient cut to at most [`RESTART_TRANSIENT`] revolutions (the window as long as
    /// before, the steady-state test still deciding where the transient ends); a transient
    /// that does not adapt (`max_transient` not above it) is kept. A fixed window
    /// (`run.duration`) starts from the scene's state at t = 0 whatever the pilots did.
    pub fn from_pilot(mut self, pilot: Option<PilotStart>) -> Self {
        let (Some(p), Window::Settle { max_transient, .. }) = (pilot, self.window) else {
            return self;
        };
        let t = self.step.transient_revolutions;
        let cut = if max_transient > t {
            t.min(RESTART_TRANSIENT)
        } else {
            t
        };
        self.unpiloted = Some(Unpiloted {
            start: self.start,
            transient_revolutions: t,
            revolutions: self.step.revolutions,
        });
        self.start = StartState::Pilot(p);
        self.step.transient_revolutions = cut;
        self.step.revolutions = self.step.revolutions.saturating_sub(t - cut);
        self
    }

    /// A pilot of the scene's run at ν = `speed_ratio` by `scheme` at `scale` × the paper's
    /// rule (no `run.dt`): [`super::pilot::PILOT_WINDOW`] revolutions analysed after
    /// [`super::pilot::PILOT_TRANSIENT`] from the scene's start, fixed (even where the run is
    /// `run.duration` long: pilots measure the step on their own short window), no follow-ups
    /// — but never past the run's own end when it is `run.revolutions` long and shorter than
    /// that: its transient is then cut (its window kept, or the whole run when shorter), so a
    /// response that runs away only after the run's end (the ROSS rub scene at 4× its
    /// unbalance: dry whip past 0.62 s of a 0.5 s run) does not stop the step choice.
    pub fn pilot(s: &RunSettings, speed_ratio: f64, scheme: Scheme, scale: f64) -> Self {
        let mut step = s.step;
        step.integrator = scheme;
        step.dt = None;
        step.dt_scale = scale;
        let (transient, window) = (super::pilot::PILOT_TRANSIENT, super::pilot::PILOT_WINDOW);
        let total = match step.duration {
            None => (transient + window).min(step.revolutions.max(1)),
            Some(_) => transient + window,
        };
        step.duration = None;
        step.transient_revolutions = total.saturating_sub(window);
        step.revolutions = total;
        Self {
            step,
            ..s.request(speed_ratio).fixed()
        }
    }

    /// A level of a convergence study: the scene's run at ν = `speed_ratio` by `scheme` at the
    /// fixed Δt `dt` (s), from the scene's start over the scene's revolutions, fixed, no
    /// follow-ups.
    pub fn at_step(s: &RunSettings, speed_ratio: f64, scheme: Scheme, dt: f64) -> Self {
        let mut step = s.step;
        step.integrator = scheme;
        step.dt = Some(dt);
        Self {
            step,
            ..s.request(speed_ratio).fixed()
        }
    }

    /// This pilot restarted from `initial`: [`PILOT_RESETTLE`] revolutions to settle the
    /// restart, then its window.
    pub fn resettled(self, initial: Initial) -> Self {
        let window = self.step.revolutions - self.step.transient_revolutions;
        let mut step = self.step;
        step.transient_revolutions = PILOT_RESETTLE;
        step.revolutions = PILOT_RESETTLE + window;
        Self {
            step,
            start: StartState::Given(initial),
            ..self
        }
    }

    /// This pilot at `scale` × the paper's rule (one level of a pilot's halving steps).
    pub fn at_scale(self, scale: f64) -> Self {
        let mut step = self.step;
        step.dt_scale = scale;
        Self { step, ..self }
    }

    /// This run from `initial` (the previous pilot's end).
    pub fn from_state(self, initial: Initial) -> Self {
        Self {
            start: StartState::Given(initial),
            ..self
        }
    }

    /// The settling run before a pilot from the settled state: this pilot's start at `scale` ×
    /// the paper's rule over `revolutions`, all recorded (no transient cut), fixed.
    pub fn settling(&self, scale: f64, revolutions: usize) -> Self {
        let mut step = self.step;
        step.dt_scale = scale;
        step.revolutions = revolutions;
        step.transient_revolutions = 0;
        Self {
            step,
            ..self.fixed()
        }
    }

    /// This run reduced as `reduction` (a cut-off pilot's).
    pub fn reduced(self, reduction: ReductionInput) -> Self {
        Self {
            reduction: Some(reduction),
            ..self
        }
    }

    /// An error-estimate companion of this run: the same start and scheme over `transient`
    /// revolutions then `window` analysed, fixed, no follow-ups (its Δt is its plan's, from
    /// the run's).
    pub fn companion(&self, transient: usize, window: usize) -> Self {
        let mut step = self.step;
        step.transient_revolutions = transient;
        step.revolutions = transient + window;
        Self {
            step,
            ..self.fixed()
        }
    }

    /// The coexistence check's companion of this run from `initial` (its plan: the run's Δt,
    /// the settling and window the check sets): it settles for at most `max_transient`
    /// revolutions, and a window then not periodic is lengthened as the run's is (its
    /// `classify` revolutions), no follow-ups.
    pub fn coexistence(&self, initial: Initial, max_transient: usize) -> Self {
        let classify = match self.window {
            Window::Settle { classify, .. } => classify,
            Window::Fixed => 0,
        };
        Self {
            start: StartState::Given(initial),
            window: Window::Settle {
                max_transient,
                classify,
            },
            follow_ups: FollowUps::default(),
            ..*self
        }
    }

    /// The converged reference of a bench at this run's speed: collocated at Δt 16× finer
    /// (16× `run.harmonics` of the paper's rule), from the scene's start, no follow-ups.
    pub fn reference(s: &RunSettings, speed_ratio: f64) -> Self {
        let mut step = s.step;
        step.integrator = Scheme::Collocated;
        step.harmonics *= 16.0;
        Self {
            step,
            follow_ups: FollowUps::default(),
            ..s.request(speed_ratio)
        }
    }

    /// This run's plan as it stands, never lengthened and without follow-ups (the stress
    /// probe's runs; what every pilot, companion and study level is).
    pub fn fixed(&self) -> Self {
        Self {
            window: Window::Fixed,
            follow_ups: FollowUps::default(),
            ..*self
        }
    }

    /// The state at t = 0.
    pub fn initial(&self) -> Initial {
        self.start.initial()
    }

    /// Whether the run started from its speed's pilot state.
    pub fn from_pilot_state(&self) -> bool {
        matches!(self.start, StartState::Pilot(_))
    }

    /// The reduction the run integrates: [`RunRequest::reduction`] when set, else the scene's
    /// (`model.reduction`).
    pub fn reduction_of<'a>(&'a self, model: &'a Model) -> Option<&'a ReductionInput> {
        self.reduction.as_ref().or(model.reduction.as_ref())
    }
}
