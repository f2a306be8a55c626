//! Broad phase: which stator nodes can touch a rotor section this step.
//!
//! A node target at undeformed position `x₀` (relative to the undeformed station centre) can
//! have a gap `g = |x₀ + u_s − x_C| − r` below a margin `m` only if `|x₀ + u_s − x_C| < r + m`.
//! For targets that do not move in the prediction (massless stators, whose predicted
//! displacement is zero, Eq. 49) the candidates are the nodes inside the circle of radius
//! `R = r + m` around the displaced section centre `u_C`. In polar coordinates `(ρ, θ)` around
//! the undeformed centre that circle holds a node only if `ρ − |u_C| < R` and
//! `cos(θ − φ_C) > (ρ² + |u_C|² − R²) / (2 ρ |u_C|)`.
//!
//! The targets of each (station, stator) pair are binned by ρ and, within a bin, sorted by θ,
//! so a query visits only the bins that reach the circle and, in each, the angular window of the
//! bin's smallest radius (the widest); a bin of a few nodes is taken whole. A query returns a superset of the nodes within reach,
//! sorted by candidate index, with no allocation once the output buffer has grown.

use crate::math::V2;
use std::f64::consts::PI;

/// Bins of at most this many nodes are returned whole, without their angular window.
const FEW: usize = 4;

/// One radial bin of targets, sorted by polar angle.
#[derive(Debug, Clone)]
struct Bin {
    rho_min: f64,
    rho_max: f64,
    /// Polar angle in (−π, π] of each entry, ascending.
    theta: Vec<f64>,
    /// Candidate index of each entry.
    cand: Vec<usize>,
}

/// The targets of one (station, stator) pair.
#[derive(Debug, Clone)]
struct Group {
    station: usize,
    bins: Vec<Bin>,
}

/// Broad-phase index over node targets that stay at their undeformed position in the
/// prediction.
#[derive(Debug, Clone, Default)]
pub struct BroadPhase {
    groups: Vec<Group>,
}

impl BroadPhase {
    /// Builds the index: `targets` holds `(candidate index, station, x₀)` of every node target
    /// that does not move in the prediction. `bins` radial bins per group (at least 1).
    pub fn new(targets: &[(usize, usize, V2)], bins: usize) -> Self {
        let mut by_station: Vec<(usize, Vec<(usize, V2)>)> = Vec::new();
        for &(c, s, x) in targets {
            match by_station.iter_mut().find(|g| g.0 == s) {
                Some(g) => g.1.push((c, x)),
                None => by_station.push((s, vec![(c, x)])),
            }
        }
        let nb = bins.max(1);
        let groups = by_station
            .into_iter()
            .map(|(station, pts)| {
                let rho: Vec<f64> = pts.iter().map(|(_, x)| x[0].hypot(x[1])).collect();
                let lo = rho.iter().cloned().fold(f64::INFINITY, f64::min);
                let hi = rho.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
                let w = ((hi - lo) / nb as f64).max(f64::MIN_POSITIVE);
                let mut bins: Vec<Vec<(f64, f64, usize)>> = vec![Vec::new(); nb];
                for ((c, x), r) in pts.iter().zip(&rho) {
                    let b = (((r - lo) / w) as usize).min(nb - 1);
                    bins[b].push((*r, x[1].atan2(x[0]), *c));
                }
                let bins = bins
                    .into_iter()
                    .filter(|b| !b.is_empty())
                    .map(|mut b| {
                        b.sort_by(|p, q| p.1.total_cmp(&q.1));
                        Bin {
                            rho_min: b.iter().map(|p| p.0).fold(f64::INFINITY, f64::min),
                            rho_max: b.iter().map(|p| p.0).fold(f64::NEG_INFINITY, f64::max),
                            theta: b.iter().map(|p| p.1).collect(),
                            cand: b.iter().map(|p| p.2).collect(),
                        }
                    })
                    .collect();
                Group { station, bins }
            })
            .collect();
        Self { groups }
    }

    /// Number of indexed targets.
    pub fn len(&self) -> usize {
        self.groups
            .iter()
            .flat_map(|g| &g.bins)
            .map(|b| b.cand.len())
            .sum()
    }

    /// Every indexed candidate, in no particular order.
    pub fn candidates(&self) -> impl Iterator<Item = usize> + '_ {
        self.groups
            .iter()
            .flat_map(|g| &g.bins)
            .flat_map(|b| b.cand.iter().copied())
    }

    /// True when nothing is indexed.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Appends to `out` (cleared first) every indexed candidate that may lie within
    /// `reach[s]` (= r + margin, m) of the centre of station `s`, displaced by `centre[s]` (m);
    /// sorted by candidate index.
    pub fn query(&self, centre: &[V2], reach: &[f64], out: &mut Vec<usize>) {
        out.clear();
        for g in &self.groups {
            let uc = centre[g.station];
            let big_r = reach[g.station];
            let rc = uc[0].hypot(uc[1]);
            // The centre's angle, computed once a bin needs its angular window.
            let mut phi = None;
            for b in &g.bins {
                if b.rho_min - rc >= big_r {
                    continue; // the whole bin is beyond reach
                }
                if b.cand.len() <= FEW {
                    // A window costs more (atan2, acos) than the exact gaps of a few nodes.
                    out.extend_from_slice(&b.cand);
                    continue;
                }
                // Widest half-window: smallest cos bound over the bin's radii.
                let c = if rc == 0.0 {
                    if b.rho_min < big_r {
                        -1.0
                    } else {
                        continue;
                    }
                } else {
                    let f = |r: f64| (r * r + rc * rc - big_r * big_r) / (2.0 * r * rc);
                    let mut c = f(b.rho_min).min(f(b.rho_max));
                    let r_star = (rc * rc - big_r * big_r).max(0.0).sqrt();
                    if r_star > b.rho_min && r_star < b.rho_max {
                        c = c.min(f(r_star));
                    }
                    c
                };
                if c >= 1.0 {
                    continue;
                }
                if c <= -1.0 {
                    out.extend_from_slice(&b.cand);
                    continue;
                }
                let w = c.acos();
                let phi = *phi.get_or_insert_with(|| uc[1].atan2(uc[0]));
                let (a, z) = (phi - w, phi + w);
                // The window [a, z] modulo 2π as at most two ranges in (−π, π].
                let mut take = |lo: f64, hi: f64| {
                    let i = b.theta.partition_point(|t| *t < lo);
                    let j = b.theta.partition_point(|t| *t <= hi);
                    out.extend_from_slice(&b.cand[i..j.max(i)]);
                };
                if a < -PI {
                    take(a + 2.0 * PI, PI);
                    take(-PI, z);
                } else if z > PI {
                    take(a, PI);
                    take(-PI, z - 2.0 * PI);
                } else {
                    take(a, z);
                }
            }
        }
        out.sort_unstable();
        out.dedup();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force against the index over random centres and a ring of nodes plus a radial
    /// spoke (nodes at many radii).
    #[test]
    fn query_is_a_superset_of_the_nodes_within_reach() {
        let mut targets = Vec::new();
        let n = 360;
        for i in 0..n {
            let t = 2.0 * PI * i as f64 / n as f64 - PI + 1e-3;
            let r = 0.0601;
            targets.push((i, 0, [r * t.cos(), r * t.sin()]));
        }
        for k in 0..40 {
            let r = 0.0601 + 0.001 * k as f64;
            targets.push((n + k, 0, [r * 0.3_f64.cos(), r * 0.3_f64.sin()]));
        }
        let bp = BroadPhase::new(&targets, 8);
        assert_eq!(bp.len(), targets.len());
        let mut out = Vec::new();
        let mut seed = 12345u64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % 1_000_000) as f64 / 1e6
        };
        let mut visited = 0;
        let mut within = 0;
        for _ in 0..2000 {
            let a = 2.0 * PI * rnd();
            let m = 3e-4 * rnd();
            let uc = [m * a.cos(), m * a.sin()];
            let reach = 0.06 + 2e-4 * rnd();
            bp.query(&[uc], &[reach], &mut out);
            visited += out.len();
            for (c, _, x) in &targets {
                let d = (x[0] - uc[0]).hypot(x[1] - uc[1]);
                if d < reach {
                    within += 1;
                    assert!(
                        out.binary_search(c).is_ok(),
                        "node {c} at distance {d} < {reach} missed"
                    );
                }
            }
        }
        // The broad phase visits far fewer nodes than all of them.
        assert!(
            visited < 2000 * targets.len() / 2,
            "visited {visited}, within {within}"
        );
    }

    #[test]
    fn centred_rotor_reaches_nothing_beyond_its_radius() {
        let bp = BroadPhase::new(&[(0, 0, [0.0, 0.07]), (1, 0, [0.05, 0.0])], 2);
        let mut out = Vec::new();
        bp.query(&[[0.0, 0.0]], &[0.06], &mut out);
        assert_eq!(out, vec![1]);
    }
}
