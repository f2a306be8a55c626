//! The spin of a run: the case's constant speed, a prescribed profile, or a driven rotor whose
//! spin angle is integrated with the lateral DOFs ([`crate::model::Drive`]).
//!
//! The driven spin is the explicit central difference of the lateral DOFs, written with
//! half-step speeds (the same scheme: `φⁿ⁺¹ − 2φⁿ + φⁿ⁻¹ = Δt² φ̈ⁿ`):
//!
//! `J (Ω^{n+½} − Ω^{n−½})/Δt = T_d(tₙ, Ω̂ⁿ) − T₀ − c_t (Ω^{n+½} + Ω^{n−½})/2 − T_rubⁿ⁺¹ − T_uⁿ`,
//! `φⁿ⁺¹ = φⁿ + Δt Ω^{n+½}`,
//!
//! solved for Ω^{n+½} after the step's contact solve:
//! * the viscous drag is centred like the lateral damping `C (uⁿ⁺¹ − uⁿ⁻¹)/(2Δt)`;
//! * `T_rubⁿ⁺¹ = Σ R μ p` over the pairs of the step's contact solve — the forward-increment
//!   multipliers that act on the lateral step n (Eqs. 34–47; the collocated scheme: its
//!   static solve at tₙ and the increment of the stators with mass, both loading step n), so
//!   the friction torque and the friction force of a step are the same multipliers;
//! * `T_uⁿ = Σ m_u e (cos θ ü_y − sin θ ü_x)` with `üⁿ = (uⁿ⁺¹ − 2uⁿ + uⁿ⁻¹)/Δt²` of the
//!   corrected step (the unbalance's reaction, see [`crate::model::drive`]);
//! * the state at tₙ that loads the lateral prediction (the unbalance force, the gyroscopic
//!   correction) and the motor curve is `Ω̂̇ⁿ = 2φ̈ⁿ⁻¹ − φ̈ⁿ⁻²` (linear extrapolation of the
//!   last two accelerations), `Ω̂ⁿ = Ω^{n−½} + ½Δt Ω̂̇ⁿ`: both O(Δt²), so the coupled
//!   step keeps the scheme's second order (`tests/suite/driven.rs`, fitted slope). The first step
//!   is the half step `J (Ω^{½} − Ω₀)/(Δt/2) = T⁰ − c_t (Ω^{½} + Ω₀)/2` with the torques of
//!   step 0 (rub and unbalance reaction included): an estimate of φ̈⁰ would put an O(Δt)
//!   error into every later φ. The prediction of step 0 takes
//!   `φ̈⁰ ≈ (T_d(0, Ω₀) − T₀ − c_t Ω₀)/J` (rub and unbalance reaction unknown yet: an error of
//!   one step's unbalance force, O(Δt³) in u¹).
//!
//! A constant torque without rub or unbalance gives `Ω^{n+½} = Ω₀ + (n + ½)Δt T/J` and
//! `Ω̂ⁿ = Ω₀ + tₙ T/J` exactly. The rotor does not reverse: a step that would make
//! Ω^{n+½} < 0 (a rub or a brake stopping the rotor) sets it to 0 — the rotor stops, and
//! stays stopped while the torques do not drive it.

use super::body::DynBody;
use super::select::Pairs;
use crate::error::SolveError;
use crate::model::{Case, Drive, Events, SpeedProfile, SpinState};

/// How a run's spin is given.
#[derive(Debug)]
pub(crate) enum Spin<'a> {
    /// The case's constant speed.
    Constant,
    /// A prescribed profile Ω(t).
    Profile(&'a SpeedProfile),
    /// A driven rotor (see the module).
    Driven(SpinDof<'a>),
}

impl Spin<'_> {
    /// The spin state at tₙ = `t` (driven: the integrator's current instant); `None` at
    /// constant speed.
    #[inline]
    pub(crate) fn state(&self, t: f64) -> Option<SpinState> {
        match self {
            Spin::Constant => None,
            Spin::Profile(p) => Some(p.at(t)),
            Spin::Driven(d) => Some(d.cur),
        }
    }
}

/// The spin angle as a degree of freedom (see the module).
#[derive(Debug)]
pub(crate) struct SpinDof<'a> {
    drive: &'a Drive,
    dt: f64,
    /// The state at the current instant tₙ: φⁿ, Ω̂ⁿ, Ω̂̇ⁿ.
    pub(crate) cur: SpinState,
    /// Ω^{n−½} (rad/s).
    w_half: f64,
    /// φ̈ⁿ⁻¹, φ̈ⁿ⁻² (rad/s²).
    acc: [f64; 2],
    /// The speed above which the run is refused (rad/s): 1.5 × the planned bound.
    limit: f64,
    /// The friction torque of the last step, `Σ R μ p` (N·m, resisting).
    pub(crate) friction: f64,
    /// The unbalance reaction torque of the last step (N·m, resisting when > 0).
    pub(crate) unbalance: f64,
}

impl<'a> SpinDof<'a> {
    /// The spin at rest of `drive` for steps of `dt` (s).
    pub(crate) fn new(drive: &'a Drive, dt: f64) -> Self {
        let w0 = drive.speed0;
        let a0 =
            (drive.drive_torque(0.0, w0) - drive.drag - drive.drag_viscous * w0) / drive.inertia;
        Self {
            drive,
            dt,
            cur: SpinState {
                phi: 0.0,
                omega: w0,
                omega_dot: a0,
            },
            w_half: w0,
            acc: [a0, a0],
            limit: 1.5 * drive.speed_bound().max(w0) + 1e-9,
            friction: 0.0,
            unbalance: 0.0,
        }
    }

    /// The drive torque at the current instant tₙ = `t` (N·m).
    #[inline]
    pub(crate) fn drive_torque(&self, t: f64) -> f64 {
        self.drive.drive_torque(t, self.cur.omega)
    }

    /// The unbalance reaction torque `Σ m_u e (cos θ ü_y − sin θ ü_x)` (N·m) of `case`'s and
    /// the events' unbalances on the lateral step of `rotor` ending in `u_next`, at tₙ = `t`.
    fn unbalance_reaction(&self, case: &Case, events: &Events, rotor: &DynBody, t: f64) -> f64 {
        let inv_dt2 = 1.0 / (self.dt * self.dt);
        let acc = |i: usize| (rotor.u_next[i] - 2.0 * rotor.u[i] + rotor.u_prev[i]) * inv_dt2;
        let loads = (case.loop_rotor().unbalance.iter().map(|u| (u, 1.0)))
            .chain(events.unbalance.iter().map(|e| (&e.load, e.share(t))));
        let mut tu = 0.0;
        for (u, share) in loads {
            let (s, c) = (self.cur.phi + u.phase).sin_cos();
            tu += share * u.me * (c * acc(u.dofs[1]) - s * acc(u.dofs[0]));
        }
        tu
    }

    /// The step's length in Ω (`h`: half a step first), Ω at its start, `J/h` and `c_t/2`.
    fn step_factors(&self, n: usize) -> (f64, f64, f64, f64) {
        let (d, dt) = (self.drive, self.dt);
        // The first step starts from Ω₀ over half a step (the velocity form's start): its
        // torques are the step's own, so no estimate of φ̈⁰ enters φ.
        let (h, w_prev) = if n == 0 {
            (0.5 * dt, d.speed0)
        } else {
            (dt, self.w_half)
        };
        (h, w_prev, d.inertia / h, 0.5 * d.drag_viscous)
    }

    /// The spin increment `φⁿ⁺¹ − φⁿ` of step `n` (from tₙ = `t`) without a friction torque,
    /// the lateral step being the prediction in `rotor.u_next`, and its derivative `κ` with
    /// respect to the friction torque (rad/(N·m), ≥ 0: `Δφ = Δφ₀ − κ T_rub`) — the spin's share
    /// of a sticking pair's tangential flexibility (`time::stick`).
    pub(crate) fn free_increment(
        &self,
        case: &Case,
        events: &Events,
        rotor: &DynBody,
        n: usize,
        t: f64,
    ) -> (f64, f64) {
        let d = self.drive;
        let torque =
            self.drive_torque(t) - d.drag - self.unbalance_reaction(case, events, rotor, t);
        let (_, w_prev, j, ct) = self.step_factors(n);
        let w_next = (w_prev * (j - ct) + torque) / (j + ct);
        (self.dt * w_next, self.dt / (j + ct))
    }

    /// The spin increment of the step that ended at tₙ, `φⁿ − φⁿ⁻¹` (rad).
    pub(crate) fn last_increment(&self) -> f64 {
        self.dt * self.w_half
    }

    /// Steps the spin tₙ → tₙ₊₁ (`n`, `t` = tₙ) with the step's friction torque `friction`
    /// (N·m, `Σ R μ p`) and the unbalance reaction of `case`'s unbalances on the corrected
    /// lateral step of `rotor` (uⁿ⁺¹ in `u_next`).
    ///
    /// # Errors
    /// [`SolveError::SpinOverspeed`] when Ω passes 1.5 × the speed the step was planned for.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn advance(
        &mut self,
        case: &Case,
        events: &Events,
        rotor: &DynBody,
        friction: f64,
        n: usize,
        t: f64,
    ) -> Result<(), SolveError> {
        let (d, dt) = (self.drive, self.dt);
        let tu = self.unbalance_reaction(case, events, rotor, t);
        let torque = self.drive_torque(t) - d.drag - friction - tu;
        let (h, w_prev, j, ct) = self.step_factors(n);
        let w_next = ((w_prev * (j - ct) + torque) / (j + ct)).max(0.0);
        let a = (w_next - w_prev) / h;
        self.cur.phi += dt * w_next;
        self.acc = if n == 0 { [a, a] } else { [a, self.acc[0]] };
        let a_hat = 2.0 * self.acc[0] - self.acc[1];
        self.w_half = w_next;
        self.cur.omega = (w_next + 0.5 * dt * a_hat).max(0.0);
        self.cur.omega_dot = a_hat;
        self.friction = friction;
        self.unbalance = tu;
        if self.cur.omega.is_nan() || self.cur.omega > self.limit {
            return Err(SolveError::SpinOverspeed {
                step: n + 1,
                time: t + dt,
                omega: self.cur.omega,
                bound: self.limit,
            });
        }
        Ok(())
    }
}

/// Adds the unbalance events' load at `t` (s) to `rhs`: each event's share `s(t)` of its
/// unbalance force at the spin state `spin` (the case's constant speed when `None`).
#[inline]
pub(crate) fn add_event_unbalance(
    events: &Events,
    case: &Case,
    spin: Option<SpinState>,
    t: f64,
    rhs: &mut [f64],
) {
    let spin = spin.unwrap_or(SpinState {
        phi: case.omega * t,
        omega: case.omega,
        omega_dot: 0.0,
    });
    let (w2, a) = (spin.omega * spin.omega, spin.omega_dot);
    for e in &events.unbalance {
        let share = e.share(t);
        if share > 0.0 {
            let u = &e.load;
            let (s, c) = (spin.phi + u.phase).sin_cos();
            rhs[u.dofs[0]] += share * u.me * (w2 * c + a * s);
            rhs[u.dofs[1]] += share * u.me * (w2 * s - a * c);
        }
    }
}

/// Sets the clearance events' gap offsets of `pairs` at `t` (s).
#[inline]
pub(crate) fn set_clearance(events: &Events, pairs: &mut Pairs, t: f64) {
    if events.clearance.is_empty() {
        return;
    }
    pairs.offset.fill(0.0);
    for e in &events.clearance {
        pairs.offset[e.stator] += e.offset(t);
    }
    pairs.closer = pairs.offset.iter().fold(0.0_f64, |m, o| m.max(-o));
}
