//! The stepper: one step of the paper's algorithm, predict → select → solve → correct → guard
//! → record, for both schemes.

use super::body::{DynBody, Ops};
use super::compliance::Compliance;
use super::drive::{add_event_unbalance, set_clearance, Spin, SpinDof};
use super::frame::FrameSink;
use super::guard::{divergence_bounds, dof_name};
use super::loop_rotor::{
    add_rotating, add_unbalance, full_len, rotor_contact_dofs, UnbalanceTable,
};
use super::plan::{Initial, Scheme, StepPlan};
use super::record::{ContactStats, Record, Recorder, RunStats};
use super::reduced::ReducedDyn;
use super::select::{Pairs, Phase};
use super::spin::GyroLoad;
use super::stator::StatorDyn;
use super::workspace::{ForceSet, Held, StepWorkspace};
use crate::error::{LinalgError, SolveError};
use crate::linalg::Cholesky;
use crate::model::{Case, Drive, Events, SpeedProfile};
use std::time::Instant;

mod instants;
mod restart;
mod tangent;

pub use restart::{EndState, History};
pub use tangent::{Tangent, TangentStats};

/// A frame sink, or none.
pub type Sink<'s> = Option<&'s mut dyn FrameSink>;

/// Integrates one case step by step: owns the bodies (rotor and stators with mass integrated
/// by central differences, massless stators as the compliance of their contact DOFs), the
/// candidate pairs and their broad phase, every buffer of a step (its workspace) and the
/// record.
///
/// [`Stepper::step`] is the paper's algorithm (Sec. 2.5); the schemes ([`Scheme`]) differ
/// only in when the massless stators' contact is solved:
/// * forward increment: predict every body with λ = 0 (massless stators undeformed, Eq. 49),
///   select the pairs penetrating the prediction, solve, correct (Eqs. 34–47);
/// * collocated: first solve the massless stators' contact at tₙ with the rotor held at uⁿ
///   and load the prediction with it; then the same forward increment for stators with mass;
/// * implicit (Newmark, generalised-α): the forward increment's phases, each body predicting
///   with its implicit operator and the load at tₙ₊₁ (`super::newmark`).
#[derive(Debug)]
pub struct Stepper<'a> {
    pub(crate) case: &'a Case,
    /// The speed: the case's constant speed (the constant-speed path, unchanged), a profile
    /// Ω(t), or a driven rotor's spin DOF (`time::drive`).
    pub(crate) spin: Spin<'a>,
    /// A gyroscopic rotor's load of the speed's change (a transient run only).
    gyro: Option<GyroLoad>,
    /// Scheduled unbalances and clearance changes ([`Stepper::set_events`]).
    pub(crate) events: Events,
    /// The constant speed's unbalance load over a revolution (`None`: `sincos` each step).
    unbalance: Option<UnbalanceTable>,
    pub(crate) plan: StepPlan,
    scheme: Scheme,
    pub(crate) pairs: Pairs,
    /// Collocated static phase: massless stators, undeformed, rotor at uⁿ.
    static_phase: Phase,
    /// Forward-increment phase on the prediction (collocated: stators with mass only).
    increment_phase: Phase,
    pub(crate) rotor: DynBody,
    pub(crate) stators: Vec<StatorDyn>,
    pub(crate) ws: StepWorkspace,
    recorder: Recorder,
    pub(crate) stats: RunStats,
    /// Divergence bound of each rotor DOF (m or rad, [`divergence_bounds`]).
    bound: Vec<f64>,
    /// Elastic energy in the massless stators after the last solve (J).
    energy: f64,
    /// Pairs carrying force in the current step.
    active: usize,
    /// Smallest post-correction gap of the pairs solved for the instant the next
    /// [`Stepper::observe`] counts (m; +∞ when none).
    instant_gap: f64,
    /// Volume worn off the stators so far (m³, `super::wear`).
    pub(crate) worn_volume: f64,
    /// The abradable coatings so far (`super::abradable`): the volume cut off them (m³) and the
    /// plastic work done on them (J, `Σ p Δ`).
    pub(crate) abradable: [f64; 2],
    /// Contact statistics of the open segment of instants (one revolution of
    /// `plan.steps_per_rev` steps, the last one ending at `plan.steps`); closed into
    /// `segments` at `boundary`.
    segment: ContactStats,
    /// Closed segments, in order: segment `i` holds the instants `i × steps_per_rev ≤ k <
    /// (i + 1) × steps_per_rev` (the last one ends at `plan.steps`).
    segments: Vec<ContactStats>,
    /// The instant that closes the open segment.
    boundary: usize,
    /// Whether the initial instant has been handled (forward increment: recorded at t = 0).
    started: bool,
    /// The next instant to record, a multiple of `plan.record_every` (a counter instead of a
    /// division each step).
    pub(crate) next_record: usize,
    /// Index of the next step.
    n: usize,
    /// The contact's linearisation each step takes while a tangent is carried (`tangent`).
    probe: Option<Box<tangent::Probe>>,
}

impl<'a> Stepper<'a> {
    /// Builds the bodies (M̃ factored once, massless stators condensed), the candidate pairs,
    /// the workspace and a record sized for the whole run, and sets the initial state.
    ///
    /// # Errors
    /// [`SolveError::Factorization`] when M̃ of a body or K of a massless stator cannot be
    /// factored.
    pub fn new(
        case: &'a Case,
        scheme: Scheme,
        plan: &StepPlan,
        init: Initial,
    ) -> Result<Self, SolveError> {
        Self::with_profile(case, scheme, plan, init, None)
    }

    /// [`Stepper::new`] for a speed that follows `spin` (a transient run; `None`: the case's
    /// constant speed). The profile sets the unbalance load of every step
    /// ([`crate::model::RotorBody::add_unbalance_spin`]: φ(t), Ω(t), Ω̇(t)); the step
    /// operators are the case's, factored at its speed, and a gyroscopic rotor's
    /// `(Ω − Ω_case) G q̇ + Ω̇ K_st q` corrects the prediction by a second solve on the same
    /// factor (`time::spin`).
    /// Bearings tabulated over speed are not followed (see
    /// [`crate::model::Rotor::speed_tabulated`]). The tangent `a = Ω × n` depends only on the
    /// sign of Ω, which a profile keeps.
    ///
    /// # Errors
    /// As [`Stepper::new`]; [`SolveError::GyroscopicTransient`] for a profile on a gyroscopic
    /// rotor with an implicit scheme (the correction needs M̃'s factor).
    pub fn with_profile(
        case: &'a Case,
        scheme: Scheme,
        plan: &StepPlan,
        init: Initial,
        spin: Option<&'a SpeedProfile>,
    ) -> Result<Self, SolveError> {
        Self::build(
            case,
            scheme,
            plan,
            init,
            spin.map_or(Spin::Constant, Spin::Profile),
        )
    }

    /// [`Stepper::new`] for a driven rotor: the spin angle φ is integrated with the lateral
    /// DOFs under the drive, drag, rub friction and unbalance reaction torques of `drive`
    /// (`time::drive`); the unbalance load and a gyroscopic rotor's correction take its
    /// φ, Ω, Ω̇. Explicit schemes only (the caller refuses the implicit ones).
    ///
    /// # Errors
    /// As [`Stepper::new`].
    pub fn with_drive(
        case: &'a Case,
        scheme: Scheme,
        plan: &StepPlan,
        init: Initial,
        drive: &'a Drive,
    ) -> Result<Self, SolveError> {
        let spin = Spin::Driven(SpinDof::new(drive, plan.dt));
        Self::build(case, scheme, plan, init, spin)
    }

    /// The stepper of `case` by `scheme` over `plan` from `init`, its speed as `spin`.
    fn build(
        case: &'a Case,
        scheme: Scheme,
        plan: &StepPlan,
        init: Initial,
        spin: Spin<'a>,
    ) -> Result<Self, SolveError> {
        let lr = case.loop_rotor();
        refuse_driven(case, scheme, &spin)?;
        let dt = plan.dt;
        let factor_err = |what: String| factor_err(what, dt);
        let rotor = DynBody::new(
            &lr.m,
            &lr.c,
            &lr.k,
            lr.c_low.as_ref(),
            dt,
            &rotor_contact_dofs(case),
            scheme.implicit(),
        )
        .map_err(factor_err("rotor".into()))?;
        let stators = stator_bodies(case, scheme, dt)?;
        let pairs = Pairs::new(case);
        let (static_phase, increment_phase) = phases(case, scheme, &pairs);
        let node0 = case.stations.first().map_or(0, |s| s.node);
        let recorder = Recorder::new(
            pairs.station_dofs.clone(),
            lr.node_dofs[case.observed_node],
            lr.node_dofs[node0],
            plan.steps / plan.record_every + 2,
        );
        let gyro = match (&spin, &lr.gyro) {
            (Spin::Profile(_) | Spin::Driven(_), Some(g)) => Some(GyroLoad::new(
                g,
                case.omega,
                dt,
                scheme.implicit().map(|co| (lr, co)),
            )),
            _ => None,
        };
        let unbalance = matches!(spin, Spin::Constant)
            .then(|| UnbalanceTable::new(case, dt, plan.steps_per_rev))
            .flatten();
        let mut st = Self {
            case,
            unbalance,
            spin,
            gyro,
            events: Events::default(),
            plan: *plan,
            scheme,
            ws: StepWorkspace::new(pairs.len(), case.stations.len(), full_len(case))
                .with_friction(&pairs.cands),
            pairs,
            static_phase,
            increment_phase,
            rotor,
            stators,
            recorder,
            stats: RunStats {
                min_gap: f64::INFINITY,
                ..Default::default()
            },
            bound: divergence_bounds(case, init),
            energy: 0.0,
            active: 0,
            instant_gap: f64::INFINITY,
            worn_volume: 0.0,
            abradable: [0.0; 2],
            segment: ContactStats::starting_at(0),
            segments: Vec::with_capacity(plan.steps / plan.steps_per_rev.max(1) + 2),
            boundary: 0,
            started: false,
            // Forward increment records t = 0 when it starts, then every `record_every` steps.
            next_record: if scheme.collocated() {
                0
            } else {
                plan.record_every
            },
            n: 0,
            probe: None,
        };
        if let Spin::Driven(_) = st.spin {
            st.recorder
                .rec
                .spin
                .reserve(plan.steps / plan.record_every + 2);
        }
        st.boundary = st.next_boundary(0);
        st.set_initial(init, node0).map_err(factor_err(
            "rotor mass matrix (initial acceleration)".into(),
        ))?;
        Ok(st)
    }

    /// uⁿ and uⁿ⁻¹ of the rotor from the initial displacement and velocity on `node`'s DOFs:
    /// `u⁻¹ = u⁰ − Δt v⁰ + ½Δt² a⁰`, `a⁰ = M⁻¹(f⁰ − K u⁰ − C v⁰)` (a sparse Cholesky factor of
    /// a non-diagonal M; 0 if M cannot be factored, a first-order start); implicit schemes:
    /// u⁰, v⁰ and a⁰ (M factored once when it is not diagonal).
    fn set_initial(&mut self, init: Initial, node: usize) -> Result<(), LinalgError> {
        let (case, dt) = (self.case, self.plan.dt);
        let (n, lr) = (self.rotor.n, case.loop_rotor());
        let d0 = lr.node_dofs[node];
        let mdiag = lr.m.diagonal();
        let mut f0 = vec![0.0; n];
        add_unbalance(case, self.spin.state(0.0), 0.0, &mut f0);
        add_event_unbalance(&self.events, case, self.spin.state(0.0), 0.0, &mut f0);
        add_rotating(case, self.spin.state(0.0), 0.0, &mut f0);
        let mut u0 = vec![0.0; n];
        let mut v0 = vec![0.0; n];
        for c in 0..2 {
            u0[d0[c]] = init.u[c];
            v0[d0[c]] = init.v[c];
        }
        let fext = f0.clone();
        lr.k.mul_add(-1.0, &u0, &mut f0);
        lr.c.mul_add(-1.0, &v0, &mut f0);
        if let Some(lr) = &lr.c_low {
            lr.mul_add(-1.0, &v0, &mut f0, &mut vec![0.0; lr.rank()]);
        }
        if let (Some(g), Some(s)) = (&mut self.gyro, self.spin.state(0.0)) {
            g.add_initial(s, &u0, &v0, &mut f0);
        }
        if let Ops::Implicit(imp) = &mut self.rotor.ops {
            self.rotor.u.copy_from_slice(&u0);
            self.rotor.u_prev.copy_from_slice(&u0);
            return imp.start(&lr.m, &v0, &fext, f0);
        }
        // a⁰ = M⁻¹ f⁰: a consistent start keeps the scheme's second order (a⁰ = 0 would put
        // an O(Δt) error in the initial velocity).
        let a0 = if lr.m.is_diagonal() {
            f0.iter()
                .zip(&mdiag)
                .map(|(f, m)| if *m > 0.0 { f / m } else { 0.0 })
                .collect()
        } else {
            match Cholesky::new(&lr.m) {
                Ok(ch) => {
                    ch.solve_in_place(&mut f0);
                    f0
                }
                Err(_) => vec![0.0; n],
            }
        };
        for i in 0..n {
            self.rotor.u[i] = u0[i];
            self.rotor.u_prev[i] = u0[i] - dt * v0[i] + 0.5 * dt * dt * a0[i];
        }
        Ok(())
    }

    /// Schedules `events` (`[[run.event]]`, [`crate::model::Events`]): the unbalances join
    /// the load from their t₀ (and a driven rotor's reaction torque), the clearance changes
    /// offset their stators' gaps; the initial state is recomputed with them at t = 0.
    ///
    /// # Errors
    /// As [`Stepper::new`] (the initial acceleration's factor).
    pub fn set_events(&mut self, events: Events, init: Initial) -> Result<(), SolveError> {
        self.events = events;
        let node0 = self.case.stations.first().map_or(0, |s| s.node);
        let dt = self.plan.dt;
        self.set_initial(init, node0)
            .map_err(|source| SolveError::Factorization {
                what: "rotor mass matrix (initial acceleration)".into(),
                dt,
                source,
            })
    }

    /// Runs every step of the plan, handing frames to `sink`; returns the record and counters.
    pub fn run(self, mut sink: Sink<'_>) -> Result<(Record, RunStats), SolveError> {
        self.finish(&mut sink)
    }

    /// Steps until the next step is `target` (at most `plan.steps`): the state is then
    /// uᵗᵃʳᵍᵉᵗ, every instant before it recorded and counted. A run can be driven in chunks
    /// (`run_to`, look at [`Stepper::recorded`], [`Stepper::extend`], `run_to` again) and ended by
    /// [`Stepper::finish`]; the steps taken are the same as one [`Stepper::run`].
    ///
    /// # Errors
    /// As [`Stepper::step`].
    pub fn run_to(&mut self, target: usize, sink: &mut Sink<'_>) -> Result<(), SolveError> {
        let start = Instant::now();
        if !self.started {
            self.started = true;
            if !self.scheme.collocated() {
                // The initial state: nothing in contact yet.
                self.record(0.0, ForceSet::Main, 0);
                self.observe(0, ForceSet::Main, 0);
                self.emit(sink, 0, 0.0)?;
            }
        }
        let target = target.min(self.plan.steps);
        while self.n < target {
            self.step(sink)?;
        }
        self.stats.wall_s += start.elapsed().as_secs_f64();
        Ok(())
    }

    /// The samples recorded so far.
    pub fn recorded(&self) -> &Record {
        &self.recorder.rec
    }

    /// The plan as it stands (lengthened by [`Stepper::extend`]).
    pub fn plan(&self) -> &StepPlan {
        &self.plan
    }

    /// Lengthens the run to `steps` steps with the analysed steady window starting at step
    /// `steady_from` (both whole revolutions of the plan; `steps` not below the steps already
    /// taken): a run whose transient has not died out goes on. The record grows for the new
    /// samples here, not in the loop.
    pub fn extend(&mut self, steps: usize, steady_from: usize) {
        let steps = steps.max(self.plan.steps).max(self.n);
        let more = (steps - self.plan.steps) / self.plan.record_every + 1;
        self.recorder.reserve(more);
        self.segments
            .reserve((steps - self.plan.steps) / self.plan.steps_per_rev.max(1) + 1);
        self.plan.steps = steps;
        self.plan.steady_from = steady_from.min(steps);
        self.boundary = self.next_boundary(self.segment.from_step);
    }

    /// Runs the rest of the plan and ends the run (the collocated scheme solves and records
    /// the final instant's contact); returns the record and the counters, whose contact
    /// statistics cover the whole run and the steady window `plan.steady_from ≤ k <
    /// plan.steps` as the plan stands.
    ///
    /// # Errors
    /// As [`Stepper::step`].
    pub fn finish(mut self, sink: &mut Sink<'_>) -> Result<(Record, RunStats), SolveError> {
        self.run_to(self.plan.steps, sink)?;
        let start = Instant::now();
        while self.step(sink)? {}
        let mut stats = self.stats;
        let spr = self.plan.steps_per_rev.max(1);
        let steady_seg = self.plan.steady_from / spr;
        let mut whole = ContactStats::starting_at(0);
        let mut steady = ContactStats::starting_at(self.plan.steady_from);
        for (i, seg) in self.segments.iter().enumerate() {
            whole = whole.merge(*seg);
            if i >= steady_seg {
                steady = steady.merge(*seg);
            }
        }
        // The open segment holds the final instant only (the steady window ends before it).
        stats.whole = whole.merge(self.segment);
        stats.steady = steady;
        stats.wall_s += start.elapsed().as_secs_f64();
        stats.stator_reads = self
            .stators
            .iter()
            .map(|s| match s {
                StatorDyn::Massless(c) => c.reads(),
                _ => 0,
            })
            .sum();
        for s in &self.stators {
            if let StatorDyn::Massless(c) = s {
                let (n, t) = c.columns_computed();
                stats.columns += n;
                stats.columns_s += t;
            }
        }
        if stats.min_gap == f64::INFINITY {
            stats.min_gap = f64::NAN;
        }
        let mut rec = self.recorder.rec;
        if self.pairs.any_wear {
            rec.worn = self.pairs.worn;
        }
        if self.pairs.any_layer {
            rec.abraded = self.pairs.abraded;
            rec.abradable = self.abradable;
        }
        Ok((rec, stats))
    }

    /// One step of the plan, tₙ → tₙ₊₁; false once the plan is done (the collocated scheme
    /// still solves and records the final instant's contact then).
    pub fn step(&mut self, sink: &mut Sink<'_>) -> Result<bool, SolveError> {
        let (n, dt) = (self.n, self.plan.dt);
        let t = n as f64 * dt;
        self.begin_step();
        if self.scheme.collocated() {
            set_clearance(&self.events, &mut self.pairs, t);
            self.probe_static(n, t)?;
            self.static_contact(n, t)?;
            self.record_collocated(sink, n, t)?;
            if n == self.plan.steps {
                return Ok(false);
            }
            self.load_static_forces();
        } else if n == self.plan.steps {
            return Ok(false);
        }
        self.predict(t)?;
        set_clearance(&self.events, &mut self.pairs, t + dt);
        if !self.scheme.collocated() {
            self.probe_increment(n, t)?;
        }
        self.increment_contact(n, t)?;
        if self.active > 0 {
            self.stats.contact_steps += 1;
            self.stats.max_active = self.stats.max_active.max(self.active);
        }
        self.guard(n + 1, t + dt)?;
        if let Spin::Driven(d) = &mut self.spin {
            let f = self.ws.friction_torque;
            d.advance(self.case, &self.events, &self.rotor, f, n, t)?;
        }
        self.advance();
        if !self.scheme.collocated() {
            self.observe(n + 1, ForceSet::Main, self.active);
            if self.record_due(n + 1) {
                self.record(t + dt, ForceSet::Main, self.active);
            }
            self.emit(sink, n + 1, t + dt)?;
        }
        self.n += 1;
        Ok(true)
    }

    /// Clears what a step accumulates: frame pairs, station forces, the rotor's load.
    fn begin_step(&mut self) {
        self.ws.frame_pairs.clear();
        self.ws.main.clear();
        self.rotor.rhs.fill(0.0);
        self.ws.friction_torque = 0.0;
        self.ws.sticking = 0;
        self.active = 0;
    }

    /// Collocated scheme: contact of the massless stators at tₙ, rotor held at uⁿ, stators
    /// undeformed at the start of the solve.
    fn static_contact(&mut self, n: usize, t: f64) -> Result<(), SolveError> {
        for st in self.stators.iter_mut() {
            if let StatorDyn::Massless(c) = st {
                c.reset();
            }
        }
        let found = self.pairs.select(
            self.case,
            &mut self.ws,
            &self.rotor.u,
            &self.stators,
            &self.static_phase,
        );
        if !found {
            self.energy = 0.0;
            return Ok(());
        }
        self.stats.pivots += self.solve_contact(Held::Rotor, ForceSet::Main, n, t)?;
        self.active = self.ws.active();
        self.energy = self.stator_energy();
        self.collect_pairs(ForceSet::Main);
        self.instant_gap = self.pairs.min_gap(
            self.case,
            &self.ws.sel,
            &self.rotor.u,
            &self.ws.us,
            self.instant_gap,
        );
        Ok(())
    }

    /// Collocated scheme: the static contact forces load the rotor's prediction; the stators
    /// with mass start a new step.
    fn load_static_forces(&mut self) {
        let ws = &mut self.ws;
        ws.with_mass.clear();
        ws.with_mass_pairs.clear();
        ws.with_mass_active = 0;
        ws.with_mass_sticking = 0;
        for (s, d) in self.pairs.station_dofs.iter().enumerate() {
            self.rotor.rhs[d[0]] += ws.main.total[s][0];
            self.rotor.rhs[d[1]] += ws.main.total[s][1];
        }
    }

    /// Predicts every body with mass with λ = 0 (Eqs. 35–36; implicit schemes: the load at
    /// tₙ₊₁); forward increment and implicit schemes: massless stators start undeformed
    /// (Eq. 49).
    fn predict(&mut self, t: f64) -> Result<(), SolveError> {
        let implicit = matches!(self.rotor.ops, Ops::Implicit(_));
        let at = if implicit { t + self.plan.dt } else { t };
        // The spin state at the load's instant, and at tₙ (the same instant unless implicit).
        let next = self.spin.state(at);
        let now = if implicit { self.spin.state(t) } else { next };
        match &self.unbalance {
            Some(table) => table.add(
                self.case,
                self.n + usize::from(implicit),
                &mut self.rotor.rhs,
            ),
            None => add_unbalance(self.case, next, at, &mut self.rotor.rhs),
        }
        add_event_unbalance(&self.events, self.case, next, at, &mut self.rotor.rhs);
        add_rotating(self.case, next, at, &mut self.rotor.rhs);
        match (&mut self.gyro, now, next) {
            (Some(g), Some(now), Some(next)) if implicit => {
                if self.rotor.load() {
                    g.implicit_step(now, next, &mut self.rotor)
                        .map_err(|source| SolveError::Factorization {
                            what: format!("rotor step operator at Ω = {:.6e} rad/s", next.omega),
                            dt: self.plan.dt,
                            source,
                        })?;
                    self.rotor.solve();
                }
            }
            (Some(g), Some(now), _) => {
                self.rotor.predict();
                g.correct(now, &mut self.rotor);
            }
            _ => self.rotor.predict(),
        }
        let collocated = self.scheme.collocated();
        for st in self.stators.iter_mut() {
            match st {
                StatorDyn::Massive(b) => {
                    b.rhs.fill(0.0);
                    b.predict();
                }
                StatorDyn::Reduced(r) => {
                    r.body.rhs.fill(0.0);
                    r.body.predict();
                    r.sync();
                }
                StatorDyn::Massless(c) => {
                    if !collocated {
                        c.reset();
                    }
                }
            }
        }
        Ok(())
    }

    /// Forward-increment contact on the predicted configuration: select, solve, correct
    /// (Eqs. 37–47).
    fn increment_contact(&mut self, n: usize, t: f64) -> Result<(), SolveError> {
        let collocated = self.scheme.collocated();
        let found = self.pairs.select(
            self.case,
            &mut self.ws,
            &self.rotor.u_next,
            &self.stators,
            &self.increment_phase,
        );
        if !found {
            if !collocated {
                self.energy = 0.0;
            }
            return Ok(());
        }
        let into = if collocated {
            ForceSet::WithMass
        } else {
            ForceSet::Main
        };
        let static_sticking = std::mem::take(&mut self.ws.sticking);
        self.stats.pivots += self.solve_contact(Held::No, into, n, t)?;
        let act = self.ws.active();
        self.collect_pairs(into);
        if collocated {
            self.ws.with_mass_active = act;
            self.ws.with_mass_sticking = self.ws.sticking;
            self.ws.sticking = static_sticking;
            self.active += act;
        } else {
            self.active = act;
            self.energy = self.stator_energy();
        }
        // The gaps of the instant tₙ₊₁ this solve ends at.
        self.instant_gap = self.pairs.min_gap(
            self.case,
            &self.ws.sel,
            &self.rotor.u_next,
            &self.ws.us,
            self.instant_gap,
        );
        Ok(())
    }

    /// Stops a run that went unstable: a NaN or a rotor DOF beyond its divergence bound, or a
    /// non-finite stator value, at step `n` (time `t`).
    fn guard(&self, n: usize, t: f64) -> Result<(), SolveError> {
        let (dt, limit) = (self.plan.dt, self.plan.limit);
        for (i, (v, bound)) in self.rotor.u_next.iter().zip(&self.bound).enumerate() {
            if v.is_nan() || v.abs() > *bound {
                return Err(if v.is_finite() {
                    let (dof, unit) = dof_name(self.case, i);
                    SolveError::Diverged {
                        step: n,
                        time: t,
                        dof,
                        unit,
                        magnitude: v.abs(),
                        bound: *bound,
                        dt,
                        limit,
                    }
                } else {
                    SolveError::NonFinite {
                        step: n,
                        time: t,
                        what: "rotor".into(),
                        dof: i,
                        dt,
                        limit,
                    }
                });
            }
        }
        for (k, st) in self.stators.iter().enumerate() {
            if let Some(i) = st.first_non_finite() {
                return Err(SolveError::NonFinite {
                    step: n,
                    time: t,
                    what: format!("stator `{}`", self.case.stators[k].name),
                    dof: i,
                    dt,
                    limit,
                });
            }
        }
        Ok(())
    }

    /// uⁿ⁺¹ becomes uⁿ for every body with mass.
    fn advance(&mut self) {
        self.rotor.rotate();
        for st in self.stators.iter_mut() {
            match st {
                StatorDyn::Massive(b) => b.rotate(),
                StatorDyn::Reduced(r) => r.body.rotate(),
                StatorDyn::Massless(_) => {}
            }
        }
        self.stats.steps += 1;
    }
}

/// The error of a factorisation of `what` at step `dt`.
fn factor_err(what: String, dt: f64) -> impl Fn(LinalgError) -> SolveError {
    move |source: LinalgError| SolveError::Factorization {
        what: what.clone(),
        dt,
        source,
    }
}

/// Each stator of `case` in the loop at step `dt`: a massless one as the compliance of its
/// contact DOFs, one with mass as a body of `scheme` — in its Craig–Bampton basis when it is
/// reduced.
fn stator_bodies(case: &Case, scheme: Scheme, dt: f64) -> Result<Vec<StatorDyn>, SolveError> {
    let mut stators = Vec::with_capacity(case.stators.len());
    for s in &case.stators {
        let err = factor_err(format!("stator `{}`", s.name), dt);
        stators.push(if s.massless() {
            StatorDyn::Massless(Box::new(Compliance::new(s).map_err(err)?))
        } else if let Some(red) = &s.reduced {
            StatorDyn::Reduced(Box::new(
                ReducedDyn::new(red, dt, scheme.implicit()).map_err(err)?,
            ))
        } else {
            StatorDyn::Massive(Box::new(
                DynBody::new(
                    &s.m,
                    &s.c,
                    &s.k,
                    None,
                    dt,
                    &s.contact_dofs(),
                    scheme.implicit(),
                )
                .map_err(err)?,
            ))
        });
    }
    Ok(stators)
}

/// The two contact phases of a step: the static phase of the massless stators (collocated
/// scheme: stators undeformed, by the index) and the forward-increment phase (every stator
/// with mass, and the massless ones unless collocated; deformed).
fn phases(case: &Case, scheme: Scheme, pairs: &Pairs) -> (Phase, Phase) {
    let massless: Vec<bool> = case.stators.iter().map(|s| s.massless()).collect();
    let collocated = scheme.collocated();
    let increment_keep: Vec<bool> = massless.iter().map(|m| !(collocated && *m)).collect();
    let static_phase = Phase {
        use_index: true,
        direct: pairs.direct(true, &massless),
        keep: massless,
        deformed: false,
    };
    let increment_phase = Phase {
        use_index: !collocated,
        direct: pairs.direct(!collocated, &increment_keep),
        keep: increment_keep,
        deformed: true,
    };
    (static_phase, increment_phase)
}

/// The driven speed's refusals: a reduced rotor, and gyroscopic loads under an implicit scheme.
fn refuse_driven(case: &Case, scheme: Scheme, spin: &Spin<'_>) -> Result<(), SolveError> {
    if !matches!(spin, Spin::Driven(_)) {
        return Ok(());
    }
    if case.reduced.is_some() {
        return Err(SolveError::ReducedTransient);
    }
    if case.loop_rotor().gyro.is_some() && scheme.implicit().is_some() {
        return Err(SolveError::GyroscopicTransient {
            integrator: scheme.name().into(),
        });
    }
    Ok(())
}
