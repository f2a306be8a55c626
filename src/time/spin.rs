//! The speed-dependent terms of a gyroscopic rotor under a varying speed Ω(t).
//!
//! The rotor's equations are `M q̈ + (C + Ω G) q̇ + (K + Ω̇ K_st) q = f(t)`
//! ([`crate::model::rotor::Gyroscopic`]). The step operators are factored once, at the case's
//! speed Ω_f: `M̃ = M/Δt² + (C + Ω_f G)/(2Δt)`, so the constant-speed step is unchanged at
//! Ω = Ω_f. The central-difference step at Ωₙ differs from it by
//! `(Ωₙ − Ω_f) G (uⁿ⁺¹ − uⁿ⁻¹)/(2Δt) + Ω̇ₙ K_st uⁿ` on the left, which the prediction takes in
//! two passes on the one factor:
//!
//! 1. load `−(Ωₙ − Ω_f) G v̂ⁿ − Ω̇ₙ K_st uⁿ` with the second-order backward difference
//!    `v̂ⁿ = (3uⁿ − 4uⁿ⁻¹ + uⁿ⁻²)/(2Δt)` (the velocity whose central difference would need
//!    `û = uⁿ⁻¹ + 2Δt v̂ⁿ` as uⁿ⁺¹), and predict u⁽⁰⁾;
//! 2. correct `uⁿ⁺¹ = u⁽⁰⁾ − M̃⁻¹ (Ωₙ − Ω_f) G (u⁽⁰⁾ − û)/(2Δt)`: one fixed-point step towards
//!    the central difference, whose contraction is `|Ω − Ω_f| Δt I_p/(2 I_d)` ≪ 1.
//!
//! Both passes are second order; the correction is what keeps the step stable. The explicit
//! velocity alone (pass 1) adds to each whirl mode of frequency ω a damping
//! `∓(Ω − Ω_f) (I_p/2I_d) (1 − cos ωΔt)`, negative for one whirl direction, which grows the
//! rotor's highest modes (ωΔt ≈ 1.6) unless their damping exceeds it: the paper's FE rotor
//! diverged at 1.85 ω_n with M̃ at ω_n. After the correction that rate is multiplied by the
//! contraction, `O((Ω − Ω_f)² Δt)`. Cost: one more solve with M̃ and two or three sparse
//! products (G, K_st) per step, measured in `docs/PERFORMANCE.md`.
//!
//! Before the first step uⁿ⁻² is the linear extrapolation `2uⁿ⁻¹ − uⁿ` (v̂⁰ = (u⁰ − u⁻¹)/Δt,
//! one step's first-order velocity: a local error only).

use super::body::DynBody;
use crate::model::rotor::Gyroscopic;
use crate::model::SpinState;

/// The explicit speed-dependent load of a gyroscopic rotor (see the module).
#[derive(Debug)]
pub(crate) struct GyroLoad<'a> {
    terms: &'a Gyroscopic,
    /// The speed M̃ was factored at (rad/s).
    omega_f: f64,
    dt: f64,
    /// uⁿ⁻² (m, rad).
    u_prev2: Vec<f64>,
    /// v̂ⁿ (m/s, rad/s), then the correction's load.
    v: Vec<f64>,
    /// Ωₙ − Ω_f of the step (rad/s).
    d: f64,
    /// The correction's load, then M̃⁻¹ of it.
    rhs: Vec<f64>,
}

impl<'a> GyroLoad<'a> {
    /// The load of `terms` for a step `dt` (s) whose M̃ holds Ω_f G, `omega_f` in rad/s.
    pub(crate) fn new(terms: &'a Gyroscopic, omega_f: f64, dt: f64) -> Self {
        let n = terms.g.nrows();
        Self {
            terms,
            omega_f,
            dt,
            u_prev2: vec![0.0; n],
            v: vec![0.0; n],
            d: 0.0,
            rhs: vec![0.0; n],
        }
    }

    /// Sets uⁿ⁻² from the initial uⁿ = `u` and uⁿ⁻¹ = `u_prev`: `2uⁿ⁻¹ − uⁿ`.
    pub(crate) fn start(&mut self, u: &[f64], u_prev: &[f64]) {
        for ((p2, a), b) in self.u_prev2.iter_mut().zip(u).zip(u_prev) {
            *p2 = 2.0 * b - a;
        }
    }

    /// Pass 1: adds `−(Ω − Ω_f) G v̂ − Ω̇ K_st u` at `spin` to `rhs` (N, N·m); `u`, `u_prev`:
    /// uⁿ, uⁿ⁻¹.
    #[inline]
    pub(crate) fn add(&mut self, spin: SpinState, u: &[f64], u_prev: &[f64], rhs: &mut [f64]) {
        let d = spin.omega - self.omega_f;
        self.d = d;
        if d != 0.0 {
            let h = 0.5 / self.dt;
            for (((v, a), b), c) in self.v.iter_mut().zip(u).zip(u_prev).zip(&self.u_prev2) {
                *v = h * (3.0 * a - 4.0 * b + c);
            }
            self.terms.g.mul_add(-d, &self.v, rhs);
        }
        if spin.omega_dot != 0.0 {
            self.terms.k_st.mul_add(-spin.omega_dot, u, rhs);
        }
    }

    /// Pass 2: corrects the prediction `body.u_next` = u⁽⁰⁾ by `−M̃⁻¹ (Ω − Ω_f) G (u⁽⁰⁾ − û)/(2Δt)`,
    /// `û = uⁿ⁻¹ + 2Δt v̂` (`body.u_prev` is uⁿ⁻¹).
    #[inline]
    pub(crate) fn correct(&mut self, body: &mut DynBody) {
        if self.d == 0.0 {
            return;
        }
        let h = 0.5 / self.dt;
        // v ← (u⁽⁰⁾ − û)/(2Δt) = (u⁽⁰⁾ − uⁿ⁻¹)/(2Δt) − v̂.
        for ((v, a), b) in self.v.iter_mut().zip(&body.u_next).zip(&body.u_prev) {
            *v = h * (a - b) - *v;
        }
        let r = &mut self.rhs;
        r.fill(0.0);
        self.terms.g.mul_add(-self.d, &self.v, r);
        body.correct(r);
    }

    /// Before the bodies advance: uⁿ⁻¹ (`u_prev`) becomes uⁿ⁻².
    #[inline]
    pub(crate) fn advance(&mut self, u_prev: &[f64]) {
        self.u_prev2.copy_from_slice(u_prev);
    }
}
