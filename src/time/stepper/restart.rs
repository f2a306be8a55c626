//! Restarting a constant-speed run at another step from where a run ended: the companion of
//! the error estimate that is finer than the run (`analysis::speed`) starts from the run's
//! settled state instead of integrating the transient again.

use super::Stepper;
use crate::time::body::{DynBody, Ops};
use crate::time::drive::Spin;
use crate::time::stator::StatorDyn;

/// A body's state: the last three displacements of central differences (`u[0]` = uᴺ, `u[1]` =
/// uᴺ⁻¹, `u[2]` = uᴺ⁻²), or an implicit body's displacement, velocity, acceleration and load.
#[derive(Debug, Clone)]
enum BodyState {
    Central([Vec<f64>; 3]),
    Implicit(Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>),
    /// A massless stator: no state between steps.
    None,
}

/// The displacements of the bodies one step before the end (uᴺ⁻¹ and uᴺ⁻²), taken by
/// [`Stepper::history`] one step before [`Stepper::end_state`].
#[derive(Debug, Clone)]
pub struct History {
    step: usize,
    bodies: Vec<(Vec<f64>, Vec<f64>)>,
}

/// The state of every body at the end of a constant-speed run of step `dt`, at step `step`
/// ([`Stepper::end_state`]), from which a run at another step restarts
/// ([`Stepper::restart`]).
#[derive(Debug, Clone)]
pub struct EndState {
    /// Δt of the run it comes from (s).
    pub dt: f64,
    /// Index of the step it was taken at (the next step to take).
    pub step: usize,
    bodies: Vec<BodyState>,
}

impl EndState {
    /// The state as one vector for shooting (`analysis::periodic`): each body of central
    /// differences in order (the rotor, then the stators with mass) as its uᴺ then uᴺ⁻¹ (m,
    /// rad), massless stators contributing nothing. `None` when a body is implicit.
    pub fn state_vector(&self) -> Option<Vec<f64>> {
        let mut x = Vec::new();
        for b in &self.bodies {
            match b {
                BodyState::Central(u) => {
                    x.extend_from_slice(&u[0]);
                    x.extend_from_slice(&u[1]);
                }
                BodyState::Implicit(..) => return None,
                BodyState::None => {}
            }
        }
        Some(x)
    }

    /// This state with its vector replaced by `x` ([`EndState::state_vector`]'s layout): a
    /// restart at the same step then starts exactly from uᴺ = x's first half and uᴺ⁻¹ = its
    /// second (per body). `None` when `x` has another length or a body is implicit.
    pub fn with_state_vector(&self, x: &[f64]) -> Option<EndState> {
        let mut out = self.clone();
        let mut at = 0;
        for b in &mut out.bodies {
            match b {
                BodyState::Central(u) => {
                    let n = u[0].len();
                    let (now, before) = (x.get(at..at + n)?, x.get(at + n..at + 2 * n)?);
                    u[0].copy_from_slice(now);
                    u[1].copy_from_slice(before);
                    at += 2 * n;
                }
                BodyState::Implicit(..) => return None,
                BodyState::None => {}
            }
        }
        (at == x.len()).then_some(out)
    }
}

impl EndState {
    /// The sizes of the central-difference bodies in [`EndState::state_vector`]'s order (the
    /// state holds `2 n` components per body); `None` when a body is implicit.
    pub fn central_sizes(&self) -> Option<Vec<usize>> {
        let mut v = Vec::new();
        for b in &self.bodies {
            match b {
                BodyState::Central(u) => v.push(u[0].len()),
                BodyState::Implicit(..) => return None,
                BodyState::None => {}
            }
        }
        Some(v)
    }

    /// This state's displacements taken as those of a run of step `dt` (s): its step set to
    /// `dt`, nothing else changed, so that [`Stepper::restart`] at `dt` takes `uᴺ` and `uᴺ⁻¹`
    /// exactly as they are (the caller made them at that step).
    pub fn at_step(mut self, dt: f64) -> EndState {
        self.dt = dt;
        self
    }

    /// This state carried to a run of step `dt` (s) — a predictor for a neighbouring speed
    /// whose plan has another Δt (`analysis::branch`): each central body's earlier
    /// displacements moved along their increments to the new step,
    /// `uᴺ⁻ʲ ← uᴺ − (uᴺ − uᴺ⁻ʲ) dt/Δt_e` (the velocities kept to first order), and its step set
    /// to `dt`, so that [`Stepper::restart`] at `dt` takes them as they are. Implicit bodies
    /// (u, v, a) need no change.
    pub fn retimed(&self, dt: f64) -> EndState {
        let mut out = self.clone();
        let r = dt / self.dt;
        for b in &mut out.bodies {
            if let BodyState::Central(u) = b {
                let [now, u1, u2] = u;
                for ((a, b1), b2) in now.iter().zip(u1.iter_mut()).zip(u2.iter_mut()) {
                    *b1 = a - (a - *b1) * r;
                    *b2 = a - (a - *b2) * r;
                }
            }
        }
        out.dt = dt;
        out
    }
}

/// The bodies of a stepper that carry state: the rotor, then each stator's (its reduced body
/// for a reduced stator; `None` for a massless one).
fn bodies<'b>(rotor: &'b DynBody, stators: &'b [StatorDyn]) -> Vec<Option<&'b DynBody>> {
    std::iter::once(Some(rotor))
        .chain(stators.iter().map(|s| match s {
            StatorDyn::Massless(_) => None,
            StatorDyn::Massive(b) => Some(&**b),
            StatorDyn::Reduced(r) => Some(&r.body),
        }))
        .collect()
}

impl Stepper<'_> {
    /// The bodies' uⁿ and uⁿ⁻¹ now (n the next step), to be handed to [`Stepper::end_state`]
    /// one step later.
    pub fn history(&self) -> History {
        History {
            step: self.n,
            bodies: bodies(&self.rotor, &self.stators)
                .into_iter()
                .map(|b| {
                    b.map_or((Vec::new(), Vec::new()), |b| {
                        (b.u.clone(), b.u_prev.clone())
                    })
                })
                .collect(),
        }
    }

    /// The state of every body now, with `older` taken one step before (central differences
    /// need uᴺ⁻² to restart at another step). `None` when `older` is not from the step before
    /// or the speed is not constant.
    pub fn end_state(&self, older: &History) -> Option<EndState> {
        if older.step + 1 != self.n || !matches!(self.spin, Spin::Constant) {
            return None;
        }
        let now = bodies(&self.rotor, &self.stators);
        let bodies = now
            .into_iter()
            .zip(&older.bodies)
            .map(|(b, (_, u2))| match b {
                None => BodyState::None,
                Some(b) => match &b.ops {
                    Ops::Central(_) => {
                        BodyState::Central([b.u.clone(), b.u_prev.clone(), u2.clone()])
                    }
                    Ops::Implicit(imp) => {
                        let (v, a, load) = imp.state();
                        BodyState::Implicit(b.u.clone(), v.to_vec(), a.to_vec(), load.to_vec())
                    }
                },
            })
            .collect();
        Some(EndState {
            dt: self.plan.dt,
            step: self.n,
            bodies,
        })
    }

    /// How far this stepper's state is from `end`, taken by a run of the same case at the same
    /// step: over every body with a state, the largest of `max_i |u_i − U_i| / max_i |U_i|` and
    /// the same for the velocity (central differences: the last increment `u − u_prev` against
    /// `Uᴺ − Uᴺ⁻¹`; an implicit body: v against V). Meaningful at the same phase of the load:
    /// both at whole revolutions of a constant speed. `None` when the steps differ, the speed is
    /// not constant or the bodies do not match.
    pub fn state_gap(&self, end: &EndState) -> Option<f64> {
        let same_dt = (self.plan.dt - end.dt).abs() <= 1e-12 * end.dt.abs();
        if !same_dt || !matches!(self.spin, Spin::Constant) {
            return None;
        }
        let now = bodies(&self.rotor, &self.stators);
        if now.len() != end.bodies.len() {
            return None;
        }
        // max |a − b| / max |b| over two equal-length lists (0 when b is all zero and a = b).
        let rel = |a: &mut dyn Iterator<Item = (f64, f64)>| {
            let (mut d, mut m) = (0.0_f64, 0.0_f64);
            for (x, y) in a {
                d = d.max((x - y).abs());
                m = m.max(y.abs());
            }
            if d == 0.0 {
                0.0
            } else {
                d / m
            }
        };
        let mut gap = 0.0_f64;
        for (b, s) in now.iter().zip(&end.bodies) {
            let g = match (b, s) {
                (None, BodyState::None) => 0.0,
                (Some(b), BodyState::Central(u))
                    if matches!(b.ops, Ops::Central(_))
                        && u[0].len() == b.n
                        && u[1].len() == b.n =>
                {
                    let du = rel(&mut b.u.iter().copied().zip(u[0].iter().copied()));
                    let inc = |i: usize| (b.u[i] - b.u_prev[i], u[0][i] - u[1][i]);
                    du.max(rel(&mut (0..b.n).map(inc)))
                }
                (Some(b), BodyState::Implicit(u, v, ..)) if u.len() == b.n => {
                    let Ops::Implicit(imp) = &b.ops else {
                        return None;
                    };
                    let du = rel(&mut b.u.iter().copied().zip(u.iter().copied()));
                    let vb = imp.state().0;
                    du.max(rel(&mut vb.iter().copied().zip(v.iter().copied())))
                }
                _ => return None,
            };
            gap = gap.max(g);
        }
        Some(gap)
    }

    /// Sets the state of a stepper that has not started from `end`, the end of a run of the same
    /// case and scheme at another step Δt_e, taken at a whole revolution (the load's phase is
    /// then the one at t = 0): an implicit body takes u, v, a and the load as they are (and
    /// u⁻¹ = u − Δt v, the instant before that only a dashpot reads); a body
    /// of central differences takes uᴺ as u⁰ and, as u⁻¹, the quadratic through uᴺ, uᴺ⁻¹,
    /// uᴺ⁻² at t = −Δt: with x = −Δt/Δt_e, `u⁻¹ = (x+1)(x+2)/2 uᴺ − x(x+2) uᴺ⁻¹ + x(x+1)/2
    /// uᴺ⁻²` (an error of O(Δt_e³ u‴), below the two steps' difference of O(Δt_e²), which the
    /// restarted run then settles out). Returns false (the stepper unchanged) when `end` does
    /// not fit (another scheme or other bodies) or the stepper has started.
    pub fn restart(&mut self, end: &EndState) -> bool {
        if self.started || !matches!(self.spin, Spin::Constant) {
            return false;
        }
        let dt = self.plan.dt;
        let x = -dt / end.dt;
        let w = [
            0.5 * (x + 1.0) * (x + 2.0),
            -x * (x + 2.0),
            0.5 * x * (x + 1.0),
        ];
        let fits = {
            let now = bodies(&self.rotor, &self.stators);
            now.len() == end.bodies.len()
                && now.iter().zip(&end.bodies).all(|(b, s)| match (b, s) {
                    (None, BodyState::None) => true,
                    (Some(b), BodyState::Central(u)) => {
                        matches!(b.ops, Ops::Central(_)) && u[0].len() == b.n
                    }
                    (Some(b), BodyState::Implicit(u, ..)) => {
                        matches!(b.ops, Ops::Implicit(_)) && u.len() == b.n
                    }
                    _ => false,
                })
        };
        if !fits {
            return false;
        }
        let set = |b: &mut DynBody, s: &BodyState| match s {
            BodyState::Central(u) => {
                b.u.copy_from_slice(&u[0]);
                for (i, p) in b.u_prev.iter_mut().enumerate() {
                    *p = w[0] * u[0][i] + w[1] * u[1][i] + w[2] * u[2][i];
                }
            }
            BodyState::Implicit(u, v, a, load) => {
                b.u.copy_from_slice(u);
                for ((p, u), v) in b.u_prev.iter_mut().zip(u).zip(v) {
                    *p = u - dt * v;
                }
                if let Ops::Implicit(imp) = &mut b.ops {
                    imp.set_state(v, a, load);
                }
            }
            BodyState::None => {}
        };
        set(&mut self.rotor, &end.bodies[0]);
        for (st, s) in self.stators.iter_mut().zip(&end.bodies[1..]) {
            match st {
                StatorDyn::Massless(_) => {}
                StatorDyn::Massive(b) => set(b, s),
                StatorDyn::Reduced(r) => set(&mut r.body, s),
            }
        }
        true
    }
}
