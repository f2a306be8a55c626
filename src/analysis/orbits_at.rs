//! `rubsim continue --orbits-at`: a continued branch's periodic orbit at chosen values of its
//! parameter (ν = ω/ω_n), for its VTK/HDF5 time series (`results::Series::orbit`).
//!
//! A branch keeps each converged point's fixed point ([`super::branch::BranchPoint`]). At a
//! chosen ν inside a branch's range (between its smallest and largest converged speed), the
//! orbit is found by Newton at exactly that ν ([`periodic::shoot_from_state`]) from the
//! branch's converged point nearest to it — its state carried to that speed's step —, so the
//! orbit written is the branch's at the value asked, not the grid point's; at a grid speed
//! Newton starts on the fixed point and returns it after no iteration. The multipliers,
//! stability and residual are the new shot's. A value outside every branch's range is
//! reported, not shot.

use super::branch::Branch;
use super::parameter::request;
use super::periodic::{self, PeriodicOrbit};
use super::speed::{prepare, Prepared};
use super::RunSettings;
use crate::model::Model;
use serde::Serialize;

/// Relative margin (of ν) by which a value may lie outside a branch's range and still be
/// taken as inside it (the grid's speeds are sums of steps).
const RANGE_MARGIN: f64 = 1e-9;

/// A branch's orbit at a chosen value, shot from its nearest converged point.
pub struct OrbitAt {
    /// Index of the branch (0 the one continued, then the switched ones in the order found).
    pub branch: usize,
    /// Its period in revolutions.
    pub period: usize,
    /// The value asked, ν = ω/ω_n.
    pub speed_ratio: f64,
    /// ν of the branch's converged point Newton started from.
    pub from_speed_ratio: f64,
    /// The orbit found (converged or not: [`PeriodicOrbit::converged`]).
    pub orbit: PeriodicOrbit,
    /// The run it was found on (its case, step and plan; the series integrates on it).
    pub prep: Prepared,
}

/// What summary.json lists of an [`OrbitAt`].
#[derive(Debug, Clone, Serialize)]
pub struct OrbitAtRecord {
    /// Index of the branch.
    pub branch: usize,
    /// Its period in revolutions.
    pub period: usize,
    /// The value asked, ν.
    pub speed_ratio: f64,
    /// ν of the converged point Newton started from.
    pub from_speed_ratio: f64,
    /// Newton converged at ν ([`periodic::SHOOT_TOLERANCE`]).
    pub converged: bool,
    /// Newton iterations from that point's state.
    pub iterations: usize,
    /// Newton's final relative residual.
    pub residual: f64,
    /// Every `|ρ| < 1`.
    pub stable: bool,
    /// Largest `|ρ|`.
    pub largest_modulus: f64,
    /// The orbit's extents `[x_min, x_max, y_min, y_max]` / |Z0|.
    pub extents_nd: [f64; 4],
    /// Fraction of the period in contact.
    pub contact_fraction: f64,
}

impl OrbitAt {
    /// The record summary.json lists.
    pub fn record(&self) -> OrbitAtRecord {
        let o = &self.orbit;
        OrbitAtRecord {
            branch: self.branch,
            period: self.period,
            speed_ratio: self.speed_ratio,
            from_speed_ratio: self.from_speed_ratio,
            converged: o.converged,
            iterations: o.iterations,
            residual: o.residual,
            stable: o.stable,
            largest_modulus: o.largest_modulus,
            extents_nd: o.orbit.extents_nd,
            contact_fraction: o.orbit.contact_fraction,
        }
    }
}

/// The orbits of `branches` at the values `values` (ν) with the settings `s` the branches
/// were continued with (a reduced model's cut-off pinned as theirs: [`super::branch::pinned_reduction`]):
/// for each value, every branch whose converged speeds span it (module docs). Returns the
/// orbits, and a sentence for each value no branch spans and each shot that failed.
pub fn orbits_at(
    model: &Model,
    s: &RunSettings,
    branches: &[Branch],
    values: &[f64],
) -> (Vec<OrbitAt>, Vec<String>) {
    let mut found = Vec::new();
    let mut notes = Vec::new();
    for &v in values {
        let mut spanned = false;
        for (i, b) in branches.iter().enumerate() {
            let Some(near) = nearest(b, v) else { continue };
            spanned = true;
            let start = near
                .start
                .as_ref()
                .expect("nearest keeps points with a state");
            let shot = prepare(model, &request(s, v)).and_then(|prep| {
                periodic::shoot_from_state(&prep, b.period, start).map(|o| (prep, o))
            });
            match shot {
                Ok((prep, orbit)) => found.push(OrbitAt {
                    branch: i,
                    period: b.period,
                    speed_ratio: v,
                    from_speed_ratio: near.speed_ratio,
                    orbit,
                    prep,
                }),
                Err(e) => notes.push(format!(
                    "--orbits-at {v}: branch {i} (period {}): Newton from its point at ω/ωn = {:.4} failed: {e}",
                    b.period, near.speed_ratio
                )),
            }
        }
        if !spanned {
            notes.push(format!(
                "--orbits-at {v}: no branch has converged points on both sides of ω/ωn = {v} (or at it); no orbit written there"
            ));
        }
    }
    (found, notes)
}

/// The converged point of `b` nearest to `v` (one that kept its state), when `v` lies within
/// the branch's range of speeds.
fn nearest(b: &Branch, v: f64) -> Option<&super::branch::BranchPoint> {
    let pts = || b.points.iter().filter(|p| p.start.is_some());
    let lo = pts().map(|p| p.speed_ratio).fold(f64::INFINITY, f64::min);
    let hi = pts()
        .map(|p| p.speed_ratio)
        .fold(f64::NEG_INFINITY, f64::max);
    let m = RANGE_MARGIN * v.abs().max(1.0);
    if !(lo - m <= v && v <= hi + m) {
        return None;
    }
    pts().min_by(|a, c| {
        (a.speed_ratio - v)
            .abs()
            .total_cmp(&(c.speed_ratio - v).abs())
    })
}

/// The settings `rubsim continue` continued its branches with from the scene's `s`: a reduced
/// model's cut-off pinned at the top speed as [`super::continuation::continue_branch`] (in ν
/// alone: the grid's highest speed; `around_folds` — pseudo-arclength or switching —: the
/// larger of `from`, `to`) pins it, so the branches' states fit.
///
/// # Errors
/// As [`super::continuation::speeds`] and [`super::branch::pinned_reduction`].
pub fn branch_settings(
    model: &Model,
    s: &RunSettings,
    (from, to, step): (f64, f64, f64),
    around_folds: bool,
) -> crate::error::Result<RunSettings> {
    let top = if around_folds {
        from.max(to)
    } else {
        super::continuation::speeds(from, to, step)?
            .iter()
            .fold(from.min(to), |m, v| m.max(*v))
    };
    super::branch::pinned_reduction(model, s, top)
}
