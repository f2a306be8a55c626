//! Branch switching at a period doubling (issue 29): from each period doubling located on a
//! branch of period-`k` orbits ([`super::branch::follow`]), the period-`2k` orbit that branches
//! off it, continued over the speeds beyond — and from its own doublings again, up to a
//! largest period — so that one `rubsim continue --switch` draws the cascade.
//!
//! **The switch.** Where the period-`k` orbit `x` loses (or regains) stability through ρ = −1,
//! a period-`2k` orbit is born from it along the multiplier's eigenvector `v`
//! (`(M − ρ I) v = 0`, M the monodromy at `x`: the right singular vector of its smallest
//! singular value). On the grid orbit beyond the doubling on its unstable side (a
//! supercritical doubling: the new orbit lives where the old one is unstable) — else on its
//! stable side (subcritical) — Newton on the `2k`-revolution map starts from `x + ε v` for
//! ε = [`OFFSETS`] × max |x| in turn, and the first orbit it converges to that is a new one is
//! taken: away from `x` by more than [`DISTINCT`] of max |x| and not repeating after `k`
//! revolutions (its `k`-map residual above [`DISTINCT`]). A `2k` orbit is a fixed point of the
//! `2k` map, as `x` itself is: a start too close to `x` falls back onto it, which is why the
//! offsets grow. Where neither grid orbit gives a new one — a grid orbit far past the
//! doubling, the new orbit out of the offsets' reach — the parent's orbit is shot [`NEARER`]
//! of the way from the doubling to the unstable grid orbit and tried the same way. The new branch is then continued as any other ([`super::branch::follow`]) from
//! that speed over the speeds beyond it, in the parent's direction away from the doubling.
//!
//! Written for the speed; a branch in a scene key ([`Continued`]) switches the same way over
//! the key's values, the records' `at`/`found_at` then in the key.

use super::branch::{follow, Branch, Doubling};
use super::parameter::Continued;
use super::periodic::{self, PeriodicOrbit};
use crate::error::Result;
use nalgebra::DMatrix;
use serde::Serialize;

/// The offsets ε / max |x| of the starts `x + ε v` tried, in order.
pub const OFFSETS: [f64; 4] = [1e-2, 3e-2, 0.1, 0.3];

pub use super::periodic::DISTINCT;

/// Where a switched branch came from.
#[derive(Debug, Clone, Serialize)]
pub struct SwitchRecord {
    /// Index of the new branch in [`Diagram::branches`].
    pub branch: usize,
    /// Index of the branch it switched from.
    pub parent: usize,
    /// Index of the period doubling in the parent's `bifurcations`.
    pub bifurcation: usize,
    /// ν of the doubling (the parent's located midpoint; a key's branch: its fixed speed).
    pub at_speed_ratio: f64,
    /// ν at which the new orbit was first found (a grid orbit of the parent's).
    pub found_at_speed_ratio: f64,
    /// The parameter's value at the doubling (ν, or the key's value).
    pub at: f64,
    /// The parameter's value where the new orbit was first found.
    pub found_at: f64,
    /// Whether it was found on the parent's unstable side (a supercritical doubling).
    pub supercritical: bool,
    /// The offset ε / max |x| of the start that converged.
    pub offset: f64,
    /// max |y − x| / max |x|: how far the new orbit's fixed point lies from the parent's.
    pub distance: f64,
}

/// Every branch of a continuation with switching: the first as continued, then the switched
/// ones in the order found.
#[derive(Debug, Clone, Serialize)]
pub struct Diagram {
    /// The branches; `branches[0]` the one asked for.
    pub branches: Vec<Branch>,
    /// Where each switched branch (`branches[1..]`) came from.
    pub switched: Vec<SwitchRecord>,
    /// Doublings not followed, and why (the largest period reached, no new orbit found).
    pub not_switched: Vec<String>,
    /// Steps integrated in all (the branches' and the switches').
    pub steps: u64,
}

impl Diagram {
    /// The diagram of one branch, without switching.
    pub fn of(branch: Branch) -> Self {
        Self {
            steps: branch.steps,
            branches: vec![branch],
            switched: Vec::new(),
            not_switched: Vec::new(),
        }
    }
}

/// Switches from every period doubling of `first` (continued in the parameter `c`) and of the
/// branches found from it, while the new period is at most `max_period` revolutions (module
/// docs).
pub fn switch_all(c: &Continued<'_>, first: Branch, max_period: usize) -> Diagram {
    let mut d = Diagram {
        steps: first.steps,
        branches: vec![first],
        switched: Vec::new(),
        not_switched: Vec::new(),
    };
    let mut next = 0;
    while next < d.branches.len() {
        let parent = next;
        next += 1;
        let k = d.branches[parent].period;
        for dbl in d.branches[parent].doublings.clone() {
            let at = d.branches[parent].bifurcations[dbl.bifurcation].parameter;
            let on = c.label();
            if 2 * k > max_period {
                d.not_switched.push(format!(
                    "the period doubling of the period-{k} branch at {on} {at:.4}: period {} is above --max-period {max_period}",
                    2 * k
                ));
                continue;
            }
            if let Some(j) = reached(&d, parent, 2 * k, &dbl) {
                d.not_switched.push(format!(
                    "the period doubling of the period-{k} branch at {on} {at:.4}: branch {j} (period {}) already ends there",
                    2 * k
                ));
                continue;
            }
            match doubled(c, &dbl, at) {
                Ok((Some(found), steps)) => {
                    let (orbit, beyond, record) = found;
                    // The found orbit's own steps are the new branch's first (`follow`).
                    d.steps += steps.saturating_sub(orbit.steps);
                    let mut values = vec![orbit.parameter];
                    values.extend(beyond);
                    let b = follow(c, orbit, &values, Some(k));
                    d.steps += b.steps;
                    d.switched.push(SwitchRecord {
                        branch: d.branches.len(),
                        parent,
                        bifurcation: dbl.bifurcation,
                        at_speed_ratio: c.speed_ratio(at),
                        at,
                        ..record
                    });
                    d.branches.push(b);
                }
                Ok((None, steps)) => {
                    d.steps += steps;
                    d.not_switched.push(format!(
                        "the period doubling of the period-{k} branch at {on} {at:.4}: no period-{} orbit found from x + ε v (ε/max|x| = {OFFSETS:?}) on either side, nor nearer the doubling on its unstable side",
                        2 * k
                    ));
                }
                Err(e) => d.not_switched.push(format!(
                    "the period doubling of the period-{k} branch at {on} {at:.4}: {e}"
                )),
            }
        }
    }
    d
}

/// A branch of period `period` switched from `parent` that already ends (or starts) within the
/// grid step of the doubling `dbl` (the distance between its two grid orbits): the same
/// orbit's bubble reached from its other end, not switched twice.
fn reached(d: &Diagram, parent: usize, period: usize, dbl: &Doubling) -> Option<usize> {
    let (a, b) = (dbl.unstable.0.parameter, dbl.stable.0.parameter);
    let (lo, hi) = (a.min(b), a.max(b));
    let h = hi - lo;
    d.switched
        .iter()
        .filter(|r| r.parent == parent && d.branches[r.branch].period == period)
        .find(|r| {
            let pts = &d.branches[r.branch].points;
            [pts.first(), pts.last()]
                .into_iter()
                .flatten()
                .any(|p| p.parameter >= lo - h && p.parameter <= hi + h)
        })
        .map(|r| r.branch)
}

/// A found orbit, the speeds to continue it over and its record (indices filled by the caller).
type Found = (PeriodicOrbit, Vec<f64>, SwitchRecord);

/// The period-2k orbit branching off at the doubling `dbl` (located at `at`): tried on its
/// unstable side's grid orbit, then on its stable side's, then — neither start converging —
/// on the parent's orbits [`NEARER`] of the way from the doubling to the unstable grid orbit
/// (Newton from that orbit): a grid orbit far past the doubling has its new orbit far from it
/// along `v`, out of the offsets' reach. `None` when no start converges to a new orbit. And the
/// steps.
fn doubled(c: &Continued<'_>, dbl: &Doubling, at: f64) -> Result<(Option<Found>, u64)> {
    let mut steps = 0;
    for (side, supercritical) in [(&dbl.unstable, true), (&dbl.stable, false)] {
        let (found, st) = doubled_from(c, &side.0, &side.1, supercritical)?;
        steps += st;
        if found.is_some() {
            return Ok((found, steps));
        }
    }
    let (orbit, beyond) = &dbl.unstable;
    let mut past = vec![orbit.parameter];
    past.extend(beyond);
    for frac in NEARER {
        let v = at + frac * (orbit.parameter - at);
        let Ok((_, near)) = c.shoot_from(v, orbit) else {
            continue;
        };
        steps += near.steps;
        if !near.converged {
            continue;
        }
        let (found, st) = doubled_from(c, &near, &past, true)?;
        steps += st;
        if found.is_some() {
            return Ok((found, steps));
        }
    }
    Ok((None, steps))
}

/// The fractions of the way from a doubling to its unstable side's grid orbit at which the
/// parent's orbit is tried when the grid orbits give no new one.
pub const NEARER: [f64; 2] = [0.5, 0.25];

/// The period-2k orbit from the parent's orbit `orbit` (on the doubling's unstable side when
/// `supercritical`) by deflated Newton from `x + ε v`, ε over [`OFFSETS`], to be continued
/// over `beyond`; `None` when no start converges to a new orbit. And the steps.
fn doubled_from(
    c: &Continued<'_>,
    orbit: &PeriodicOrbit,
    beyond: &[f64],
    supercritical: bool,
) -> Result<(Option<Found>, u64)> {
    let prep = c.prepare(orbit.parameter)?;
    let (m, x, mut steps) = periodic::monodromy(&prep, orbit)?;
    let v = doubling_vector(&m, orbit);
    let scale = x.iter().fold(0.0_f64, |a, b| a.max(b.abs())).max(1e-300);
    for eps in OFFSETS {
        let x0: Vec<f64> = x.iter().zip(&v).map(|(a, b)| a + eps * scale * b).collect();
        let Ok(mut o) = periodic::solve_deflated(&prep, 2 * orbit.period, orbit, x0) else {
            continue;
        };
        o.parameter = orbit.parameter;
        steps += o.steps;
        if !o.converged {
            continue;
        }
        let distance = periodic::residual(&x, &o.fixed_point.0);
        let (half, st) = periodic::residual_after(&prep, &o, orbit.period)?;
        steps += st;
        if distance > DISTINCT && half > DISTINCT {
            let record = SwitchRecord {
                branch: 0,
                parent: 0,
                bifurcation: 0,
                at_speed_ratio: f64::NAN,
                found_at_speed_ratio: orbit.speed_ratio,
                at: f64::NAN,
                found_at: orbit.parameter,
                supercritical,
                offset: eps,
                distance,
            };
            return Ok((Some((o, beyond.to_vec(), record)), steps));
        }
    }
    Ok((None, steps))
}

/// The eigenvector of the monodromy `m` for its real multiplier nearest −1 (of `o`'s): the
/// right singular vector of `m − ρ I` for the smallest singular value, scaled to max-norm 1.
fn doubling_vector(m: &DMatrix<f64>, o: &PeriodicOrbit) -> Vec<f64> {
    let n = m.nrows();
    let rho = o
        .multipliers
        .iter()
        .filter(|r| r[1].abs() <= 1e-9 * r[0].abs().max(1e-300))
        .map(|r| r[0])
        .min_by(|a, b| (a + 1.0).abs().total_cmp(&(b + 1.0).abs()))
        .unwrap_or(-1.0);
    let a = m - DMatrix::<f64>::identity(n, n) * rho;
    let svd = a.svd(false, true);
    let Some(vt) = svd.v_t else {
        return vec![0.0; n];
    };
    let j = (0..svd.singular_values.len())
        .min_by(|&i, &k| svd.singular_values[i].total_cmp(&svd.singular_values[k]))
        .unwrap_or(0);
    let v: Vec<f64> = vt.row(j).iter().copied().collect();
    let top = v.iter().fold(0.0_f64, |a, b| a.max(b.abs())).max(1e-300);
    v.iter().map(|x| x / top).collect()
}
