//! Branches of autonomous periodic orbits (issue 29): a self-excited whirl — dry whip — shot
//! at each value of a parameter ([`super::parameter::Continued`]: the speed ν, or a numeric
//! scene key at a fixed speed) with its period unknown ([`super::autonomous`]).
//!
//! **Natural continuation.** The first value's orbit is shot from its settled run
//! ([`shoot_autonomous`]); each next one by Newton from the previous orbit's fixed point and
//! period ([`shoot_autonomous_from`]), with the first orbit's `N` steps a period for the whole
//! branch: every point is a fixed point of one map `P_T(x; p)`, smooth in the parameter `p` and
//! in `T`. Where Newton does not converge at the next value, the step is halved (at most
//! [`MAX_STEP_HALVINGS`] times) and the value reached through the intermediate ones; a branch
//! that cannot go on ends there and says why (`ended`) — the whirl leaves the ring, no orbit
//! exists beyond (dry whip below the friction μ_c = 2ξ√(1+κ)/κ), or the orbit is no longer
//! periodic.
//!
//! **Stability.** Each point carries its multipliers, the trivial one (the shift along the
//! orbit) set apart; the branch's stretches of stability are its points' verdicts.

use super::autonomous::{shoot_autonomous, shoot_autonomous_from, AutonomousOrbit};
use super::parameter::Continued;
use crate::error::{Error, Result};
use crate::scene::toml_number;
use serde::Serialize;

/// Most halvings of a step between two values of the branch before it ends.
pub const MAX_STEP_HALVINGS: usize = 4;

/// A branch of autonomous periodic orbits (module docs).
#[derive(Debug, Clone, Serialize)]
pub struct AutonomousBranch {
    /// What it is continued in: `speed_ratio`, or the scene key.
    pub parameter: String,
    /// ν of every point of a branch in a key; `None` for a branch in speed.
    pub at_speed_ratio: Option<f64>,
    /// The converged orbits, in the order continued (each with its `parameter`).
    pub points: Vec<AutonomousOrbit>,
    /// Why the branch ended before its last value, when it did.
    pub ended: Option<String>,
    /// Steps integrated in all, failed attempts included.
    pub steps: u64,
}

impl AutonomousBranch {
    /// The branch's stretches of one stability: `(stable, first point, last point)`, indices
    /// into `points`.
    pub fn stretches(&self) -> Vec<(bool, usize, usize)> {
        let mut out: Vec<(bool, usize, usize)> = Vec::new();
        for (i, p) in self.points.iter().enumerate() {
            match out.last_mut() {
                Some(s) if s.0 == p.stable => s.2 = i,
                _ => out.push((p.stable, i, i)),
            }
        }
        out
    }
}

/// The autonomous orbit of `c` continued over `values` (module docs).
///
/// # Errors
/// [`Error::Study`] when no periodic whirl is found at the first value (Newton did not
/// converge: the whirl may be quasi-periodic or chaotic) or there are no values; the first
/// value's refusals and run errors ([`shoot_autonomous`]).
pub fn follow_autonomous(c: &Continued<'_>, values: &[f64]) -> Result<AutonomousBranch> {
    let Some(&first) = values.first() else {
        return Err(Error::study("", "a branch needs a first value"));
    };
    let mut start = shoot_autonomous(&c.prepare(first)?)?;
    start.parameter = first;
    if !start.converged {
        return Err(Error::study(
            "",
            format!(
                "no autonomous periodic orbit near the settled whirl at {} = {}: Newton's residual {:.2e} after {} iterations (the whirl may be quasi-periodic or chaotic)",
                c.label(),
                toml_number(first),
                start.residual,
                start.iterations
            ),
        ));
    }
    let mut branch = AutonomousBranch {
        parameter: c.name().to_string(),
        at_speed_ratio: c.key().map(|_| c.speed_ratio(first)),
        steps: start.steps,
        points: vec![start],
        ended: None,
    };
    for &v in &values[1..] {
        let Some(prev) = branch.points.last() else {
            break;
        };
        match step_to(c, prev, v, &mut branch.steps) {
            Ok(o) => branch.points.push(o),
            Err(why) => {
                branch.ended = Some(why);
                break;
            }
        }
    }
    Ok(branch)
}

/// The orbit at `v` from `prev`, halving the step where Newton fails (module docs); `steps`
/// counts every attempt's. `Err` says where and why the branch cannot go on.
fn step_to(
    c: &Continued<'_>,
    prev: &AutonomousOrbit,
    v: f64,
    steps: &mut u64,
) -> std::result::Result<AutonomousOrbit, String> {
    let full = v - prev.parameter;
    let mut h = full;
    let mut from = prev.clone();
    loop {
        let target = if (v - from.parameter).abs() <= h.abs() * (1.0 + 1e-9) {
            v
        } else {
            from.parameter + h
        };
        let why = match shoot_at(c, target, &from) {
            Ok(o) if o.converged => {
                *steps += o.steps;
                if target == v {
                    return Ok(o);
                }
                from = o;
                continue;
            }
            Ok(o) => {
                *steps += o.steps;
                format!(
                    "Newton's residual {:.2e} after {} iterations",
                    o.residual, o.iterations
                )
            }
            Err(e) => e.to_string(),
        };
        if h.abs() <= full.abs() / f64::from(1u32 << MAX_STEP_HALVINGS) {
            return Err(format!(
                "no autonomous orbit found at {} = {} from the one at {} ({why}; the step halved {MAX_STEP_HALVINGS} times): the whirl may leave the stator, stop being periodic, or no orbit exists beyond",
                c.label(),
                toml_number(target),
                toml_number(from.parameter),
            ));
        }
        h /= 2.0;
    }
}

/// The orbit at `v` by Newton from `from`.
fn shoot_at(c: &Continued<'_>, v: f64, from: &AutonomousOrbit) -> Result<AutonomousOrbit> {
    let mut o = shoot_autonomous_from(&c.prepare(v)?, from)?;
    o.parameter = v;
    Ok(o)
}

/// An autonomous branch's orbit at a chosen value of its parameter (`rubsim continue
/// --autonomous --orbits-at`), shot from the branch's nearest converged point.
pub struct AutonomousAt {
    /// The value asked.
    pub value: f64,
    /// The value of the branch's point Newton started from.
    pub from: f64,
    /// The orbit found (converged or not).
    pub orbit: AutonomousOrbit,
    /// The run it was found on (its case, step and plan; the series integrates on it).
    pub prep: super::speed::Prepared,
}

/// The orbits of the branch `b` (continued in `c`) at `values`: for each value within the
/// range of its points (to a relative 1e-9), Newton at exactly that value from the nearest
/// point's fixed point and period ([`shoot_autonomous_from`]; at a point's own value it
/// returns that orbit after no iteration); a sentence for each value outside and each shot
/// that failed.
pub fn orbits_at(
    c: &Continued<'_>,
    b: &AutonomousBranch,
    values: &[f64],
) -> (Vec<AutonomousAt>, Vec<String>) {
    let (mut found, mut notes) = (Vec::new(), Vec::new());
    let lo = b
        .points
        .iter()
        .map(|p| p.parameter)
        .fold(f64::INFINITY, f64::min);
    let hi = b
        .points
        .iter()
        .map(|p| p.parameter)
        .fold(f64::NEG_INFINITY, f64::max);
    for &v in values {
        let m = 1e-9 * v.abs().max(1.0);
        let near = b
            .points
            .iter()
            .filter(|_| lo - m <= v && v <= hi + m)
            .min_by(|p, q| (p.parameter - v).abs().total_cmp(&(q.parameter - v).abs()));
        let Some(near) = near else {
            notes.push(format!(
                "--orbits-at {v}: outside the branch's {} {} … {}; no orbit written there",
                c.label(),
                toml_number(lo),
                toml_number(hi)
            ));
            continue;
        };
        let shot = c.prepare(v).and_then(|prep| {
            let mut o = shoot_autonomous_from(&prep, near)?;
            o.parameter = v;
            Ok((prep, o))
        });
        match shot {
            Ok((prep, orbit)) => found.push(AutonomousAt {
                value: v,
                from: near.parameter,
                orbit,
                prep,
            }),
            Err(e) => notes.push(format!(
                "--orbits-at {v}: Newton from the branch's orbit at {} = {} failed: {e}",
                c.label(),
                toml_number(near.parameter)
            )),
        }
    }
    (found, notes)
}
