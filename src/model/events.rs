//! The scheduled changes of a transient run (`[[run.event]]`) in model terms: an unbalance
//! that appears (a blade-off) and a stator clearance that changes.
//!
//! * An unbalance event adds `s(t) m_u e` at its node and phase, `s = 0` before t₀, `1` after
//!   t₀ + τ, linear between (τ = 0: a step). Its force is the unbalance force of the current
//!   spin scaled by `s` ([`crate::model::RotorBody::add_unbalance_spin`]), and on a driven
//!   rotor its reaction torque scaled likewise; the momentum of the mass as it is lost (ṡ) is
//!   not modelled.
//! * A clearance event moves the stator's contact surface along each pair's normal by
//!   `Δ(t) = s(t) (δ_new − δ)`, δ the clearance the stator was placed at: every gap of the
//!   stator is `g + Δ` (a ring's inner radius grows by Δ; a rod's tip recedes by Δ along its
//!   axis) — a seal worn open, a diaphragm closing in.

use super::{Case, UnbalanceLoad};
use crate::error::ModelError;
use crate::scene::{EventKind, EventSpec};

/// The ramp `s(t)` of an event from t₀ over τ (s): 0, linear, 1.
#[inline]
fn ramp(t0: f64, tau: f64, t: f64) -> f64 {
    if t < t0 {
        0.0
    } else if tau <= 0.0 || t >= t0 + tau {
        1.0
    } else {
        (t - t0) / tau
    }
}

/// An unbalance that appears at `t0` over `tau` (s).
#[derive(Debug, Clone, PartialEq)]
pub struct UnbalanceEvent {
    /// Its node's DOFs, m_u e (kg·m) and phase (rad).
    pub load: UnbalanceLoad,
    /// t₀ (s).
    pub t0: f64,
    /// τ (s), 0 for a step.
    pub tau: f64,
}

impl UnbalanceEvent {
    /// The share `s(t)` ∈ [0, 1] of the unbalance present at `t` (s).
    #[inline]
    pub fn share(&self, t: f64) -> f64 {
        ramp(self.t0, self.tau, t)
    }
}

/// A stator's clearance changing by `delta` (m) at `t0` over `tau` (s).
#[derive(Debug, Clone, PartialEq)]
pub struct ClearanceEvent {
    /// Index of the stator in the case.
    pub stator: usize,
    /// δ_new − δ (m): > 0 opens the clearance.
    pub delta: f64,
    /// t₀ (s).
    pub t0: f64,
    /// τ (s), 0 for a step.
    pub tau: f64,
}

impl ClearanceEvent {
    /// The gap offset Δ(t) (m) at `t` (s).
    #[inline]
    pub fn offset(&self, t: f64) -> f64 {
        self.delta * ramp(self.t0, self.tau, t)
    }
}

/// Every event of a run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Events {
    /// Unbalances that appear.
    pub unbalance: Vec<UnbalanceEvent>,
    /// Clearances that change.
    pub clearance: Vec<ClearanceEvent>,
}

impl Events {
    /// The events of `specs` for `case` (a stator's δ is its placed clearance).
    ///
    /// # Errors
    /// [`ModelError::Inconsistent`] naming `run.event.N.<key>` for a node or stator the case
    /// does not have, or a stator whose clearance is not finite (the scene's validation
    /// reports the first two with the key's line).
    pub fn from_specs(specs: &[EventSpec], case: &Case) -> Result<Self, ModelError> {
        let mut ev = Events::default();
        for (i, e) in specs.iter().enumerate() {
            let bad = |key: &str, message: String| ModelError::Inconsistent {
                what: format!("run.event.{i}.{key}"),
                message,
            };
            match e.kind {
                EventKind::Unbalance => {
                    let dofs = *case.rotor.node_dofs.get(e.node).ok_or_else(|| {
                        bad("node", format!("node {} is not on the rotor", e.node))
                    })?;
                    let me = e.mass.unwrap_or(0.0) * e.radius.unwrap_or(0.0);
                    ev.unbalance.push(UnbalanceEvent {
                        load: UnbalanceLoad {
                            dofs,
                            me,
                            phase: e.phase_deg.to_radians(),
                        },
                        t0: e.time,
                        tau: e.duration,
                    });
                }
                EventKind::Clearance => {
                    let name = e.stator.as_deref().unwrap_or_default();
                    let k = case
                        .stators
                        .iter()
                        .position(|s| s.name == name)
                        .ok_or_else(|| bad("stator", format!("no stator is named `{name}`")))?;
                    let now = case.stators[k].clearance;
                    if !now.is_finite() {
                        return Err(bad(
                            "stator",
                            format!("stator `{name}` has no finite clearance to change"),
                        ));
                    }
                    ev.clearance.push(ClearanceEvent {
                        stator: k,
                        delta: e.clearance.unwrap_or(now) - now,
                        t0: e.time,
                        tau: e.duration,
                    });
                }
            }
        }
        Ok(ev)
    }

    /// No events.
    pub fn is_empty(&self) -> bool {
        self.unbalance.is_empty() && self.clearance.is_empty()
    }
}
