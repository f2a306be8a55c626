//! The coexistence check through branches (issue 29, item 4): a speed a sweep flagged — its
//! two starts settled on different responses ([`super::coexist`], each shot as a periodic orbit
//! by [`super::coexist_orbits`]) — gets the branch of each response, not only a second start.
//!
//! For each flagged speed ν within a diagram's range ([`add_coexisting`]), each response the
//! sweep shot (its Poincaré section, kept in the case file) is looked for on the diagram's
//! branches at ν (a response the sweep could not shoot — its scheme implicit, its response not
//! periodic — counts as found on none): a branch with a point at ν whose section is within
//! [`DISTINCT_SECTION`] of the response's (the Hausdorff distance, relative to the larger
//! section's size) holds it, and so does a branch — pseudo-arclength's, whose points lie
//! between the grid's speeds — whose section interpolated between its two points around ν is
//! within [`INTERPOLATED_MATCH`]. When a response is on no branch, the speed is run again as the
//! sweep ran it — the settled run and the coexistence check's companion from the other start
//! ([`super::coexist::check_with_companion`]) — both responses are shot ([`periodic::shoot_state`]
//! with the period each run read), and each orbit on no branch yet is continued down and up
//! over the diagram's values from ν ([`super::branch::follow`]) as a new branch. So the two
//! responses of a hysteresis loop appear as two branches with their stability and where each
//! ends (a fold: the jump a run-up or run-down makes), and a later flagged speed whose
//! responses lie on them costs nothing.

use super::branch::{self, Branch};
use super::coexist::DISTINCT_SECTION;
use super::coexist_orbits::hausdorff;
use super::parameter::Continued;
use super::periodic::{self, PeriodicOrbit};
use super::switch::Diagram;
use crate::error::{Error, Result};
use serde::Serialize;

/// A flagged speed of a sweep: ν and the Poincaré sections (`[x, y]` / |Z0|) of the responses
/// shot there that converged.
#[derive(Debug, Clone, PartialEq)]
pub struct Flagged {
    /// ν = ω/ω_n.
    pub speed_ratio: f64,
    /// Each converged response's section points.
    pub sections: Vec<Vec<[f64; 2]>>,
}

/// What a flagged speed's responses were found on.
#[derive(Debug, Clone, Serialize)]
pub struct CoexistRecord {
    /// ν of the flagged speed.
    pub speed_ratio: f64,
    /// The index of the diagram's branch holding each response the sweep shot, in its order;
    /// `None` for a response the shots at ν did not reach again.
    pub on_branch: Vec<Option<usize>>,
    /// The branches this flagged speed added (indices in the diagram).
    pub new_branches: Vec<usize>,
    /// Why the speed was not run again, or what failed when it was.
    pub note: Option<String>,
}

/// Adds to `d` the branches of the responses of each speed of `flagged` that lie on none of
/// its branches ([module docs](self)), continued over `values` (ν, the diagram's grid) in the
/// parameter `c`; one record per flagged speed within the values' range.
pub fn add_coexisting(
    c: &Continued<'_>,
    d: &mut Diagram,
    flagged: &[Flagged],
    values: &[f64],
) -> Vec<CoexistRecord> {
    let (lo, hi) = values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(*v), h.max(*v))
        });
    let mut records = Vec::new();
    for f in flagged
        .iter()
        .filter(|f| f.speed_ratio >= lo - 1e-9 && f.speed_ratio <= hi + 1e-9)
    {
        let found = |d: &Diagram| -> Vec<Option<usize>> {
            let at = |s: &Vec<[f64; 2]>| on_branch(d, f.speed_ratio, s);
            f.sections.iter().map(at).collect()
        };
        let before = found(d);
        let mut rec = CoexistRecord {
            speed_ratio: f.speed_ratio,
            on_branch: before.clone(),
            new_branches: Vec::new(),
            note: None,
        };
        // Both responses known (shot by the sweep) and found: nothing to run. A sweep that
        // could not shoot them (an implicit scheme, a response not periodic) left fewer.
        if before.len() >= 2 && before.iter().all(Option::is_some) {
            rec.note = Some("every response on a branch already".into());
            records.push(rec);
            continue;
        }
        match responses_at(c, f.speed_ratio) {
            Ok((orbits, steps)) => {
                d.steps += steps;
                for o in orbits {
                    let sec = branch::section(&o.orbit, o.period);
                    if on_branch(d, f.speed_ratio, &sec).is_none() {
                        let b = both_ways(c, o, values);
                        d.steps += b.steps;
                        d.branches.push(b);
                        rec.new_branches.push(d.branches.len() - 1);
                    }
                }
                rec.on_branch = found(d);
            }
            Err(e) => rec.note = Some(e.to_string()),
        }
        records.push(rec);
    }
    records
}

/// Relative distance within which a response is on a branch that has no point at its speed
/// (a pseudo-arclength branch): the branch's section interpolated linearly between its two
/// points around the speed, whose error (O(h²) along the branch, and the arclength's own step
/// plan) stays well below the 0.1 – 1 of the orbit's size that coexisting responses lie apart.
pub const INTERPOLATED_MATCH: f64 = 1e-2;

/// The index of the first branch of `d` holding the orbit of section `section` at `v`: a
/// point at `v` within [`DISTINCT_SECTION`], or two consecutive points around `v` whose
/// interpolated section is within [`INTERPOLATED_MATCH`] (relative to the larger section's
/// size).
fn on_branch(d: &Diagram, v: f64, section: &[[f64; 2]]) -> Option<usize> {
    let close = |sec: &[[f64; 2]], tol: f64| {
        let size = sec
            .iter()
            .chain(section)
            .fold(1e-300_f64, |m, q| m.max(q[0].hypot(q[1])));
        hausdorff(sec, section) <= tol * size
    };
    d.branches.iter().position(|b| {
        let exact = b
            .points
            .iter()
            .filter(|p| (p.parameter - v).abs() < 1e-9)
            .any(|p| close(&p.poincare_nd, DISTINCT_SECTION));
        exact
            || b.points.windows(2).any(|w| {
                let (p, q) = (&w[0], &w[1]);
                let (lo, hi) = (p.parameter.min(q.parameter), p.parameter.max(q.parameter));
                if !(lo < v && v < hi) || p.poincare_nd.len() != q.poincare_nd.len() {
                    return false;
                }
                let t = (v - p.parameter) / (q.parameter - p.parameter);
                let sec: Vec<[f64; 2]> = p
                    .poincare_nd
                    .iter()
                    .zip(&q.poincare_nd)
                    .map(|(a, b)| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
                    .collect();
                close(&sec, INTERPOLATED_MATCH)
            })
    })
}

/// The two responses at `v` as the coexistence check finds them — the settled run and its
/// companion from the other start — each shot with the period its run read (those that
/// converged), and the steps of the two runs.
///
/// # Errors
/// The run's errors; [`Error::Study`] when the check has no other start at `v` or its
/// companion failed.
fn responses_at(c: &Continued<'_>, v: f64) -> Result<(Vec<PeriodicOrbit>, u64)> {
    let prep = c.prepare_with_companion(v)?;
    let (res, end) = periodic::settle(&prep)?;
    let mut steps = res.stats.steps as u64;
    let at = format!("ω/ωn = {v}");
    let (_, companion) = super::coexist::check_with_companion(&prep, &res, end.as_ref())
        .map_err(|e| Error::study(&at, e))?
        .ok_or_else(|| Error::study(&at, "the coexistence check has no other start here"))?;
    let mut starts = vec![(res.period, end)];
    if let Some((cr, ce)) = companion {
        steps += cr.stats.steps as u64;
        starts.push((cr.period, ce));
    }
    let mut orbits = Vec::new();
    for (k, e) in starts {
        let Some(e) = e.filter(|_| k > 0) else {
            continue;
        };
        if let Ok(mut o) = periodic::shoot_state(&prep, k, e) {
            if o.converged {
                o.parameter = v;
                orbits.push(o);
            }
        }
    }
    Ok((orbits, steps))
}

/// The branch through the orbit `o` (at `o.parameter`) continued down and up over `values`:
/// its points in increasing ν, its bifurcations, and where each way ended.
fn both_ways(c: &Continued<'_>, o: PeriodicOrbit, values: &[f64]) -> Branch {
    let (v, own) = (o.parameter, o.steps);
    let mut down = vec![v];
    down.extend(values.iter().rev().filter(|x| **x < v - 1e-9));
    let mut up = vec![v];
    up.extend(values.iter().filter(|x| **x > v + 1e-9));
    let below = branch::follow(c, o.clone(), &down, None);
    let mut above = branch::follow(c, o, &up, None);
    let mut points: Vec<_> = below.points.into_iter().rev().collect();
    points.extend(above.points.drain(..).skip(1));
    above.points = points;
    let mut bifs = below.bifurcations;
    bifs.append(&mut above.bifurcations);
    above.bifurcations = bifs;
    // Each way counts the orbit's own shot; once is enough.
    above.steps += below.steps.saturating_sub(own);
    above.ended = match (below.ended, above.ended) {
        (None, None) => None,
        (a, b) => Some(
            [
                a.map(|w| format!("below ν {v}: {w}")),
                b.map(|w| format!("above ν {v}: {w}")),
            ]
            .into_iter()
            .flatten()
            .collect::<Vec<_>>()
            .join("; "),
        ),
    };
    above.doublings = Vec::new();
    above
}
