//! The coexistence check through periodic orbits (issue 29, item 4): at a speed the check
//! flags ([`super::coexist`]: the companion from the other start settled on another response),
//! each of the two responses — the run's and the companion's — is shot as a periodic orbit
//! ([`super::periodic`]) from its own settled end state, with the period its run read.
//!
//! Each response gets its period, extents, contact fraction, stability and largest Floquet
//! multiplier; or, instead of a shot, why not: a response that is not periodic (its window
//! repeats with no period up to the classification's — quasi-periodic, chaotic or
//! undetermined, `result.dynamics`), a state above [`periodic::MAX_STATE`], a run that kept no
//! end state (an implicit scheme, a fixed window). Two converged orbits are *distinct* when
//! their Poincaré sections (the observed node's `k` points once per revolution, `/|Z0|`) are
//! more than [`DISTINCT_SECTION`] of the run's orbit size apart (the Hausdorff distance of the
//! two sets, so that two fixed points of one orbit — another of its `k` section points —
//! count as one orbit); `coexisting_stable` counts the stable periodic responses found: both
//! stable and distinct give 2, one orbit reached from both starts (a speed flagged by mistake)
//! at most 1.
//!
//! Only flagged speeds pay: two shots of a few Newton iterations, each a Jacobian of
//! `2 n` maps of `k` revolutions for a state of `n` components (the paper's Jeffcott rotor
//! with its massless rod: n = 4).

pub use super::coexist::{CoexistOrbit, CoexistOrbits, DISTINCT_SECTION};
use super::periodic::{self, PeriodicOrbit};
use super::{Prepared, SpeedResults};
use crate::time::EndState;

impl CoexistOrbits {
    /// One sentence for the console: each orbit, and whether they are two.
    pub fn describe(&self) -> String {
        let each: Vec<String> = self.orbits.iter().map(CoexistOrbit::describe).collect();
        let verdict = match self.distinct {
            Some(true) => format!(
                "two distinct periodic orbits ({:.2} of the orbit's size apart), {} stable",
                self.distance.unwrap_or(f64::NAN),
                self.coexisting_stable
            ),
            Some(false) => format!(
                "both starts shoot to ONE periodic orbit ({:.1e} of its size apart): the companion's window had not settled, the flag is not confirmed",
                self.distance.unwrap_or(f64::NAN)
            ),
            None => format!(
                "{} stable periodic response(s) found",
                self.coexisting_stable
            ),
        };
        format!("{}; {verdict}", each.join("; "))
    }
}

impl CoexistOrbit {
    /// The orbit in words: period, stability, largest |ρ|, extents, contact fraction; or why it
    /// was not shot.
    fn describe(&self) -> String {
        if let Some(why) = &self.not_shot {
            return format!("the {}'s response not shot: {why}", self.response);
        }
        if !self.converged {
            return format!(
                "the {}'s response: no period-{} orbit converged (residual {:.1e})",
                self.response, self.period, self.residual
            );
        }
        let e = &self.extents_nd;
        format!(
            "the {}'s response: a {} period-{} orbit (largest |ρ| {:.3}), x/|Z0| ∈ [{:.3}, {:.3}], y/|Z0| ∈ [{:.3}, {:.3}], contact fraction {:.3}",
            self.response,
            if self.stable { "stable" } else { "unstable" },
            self.period,
            self.largest_modulus,
            e[0],
            e[1],
            e[2],
            e[3],
            self.contact_fraction
        )
    }

    /// A response that was not shot, and why.
    fn not_shot(response: &str, r: &SpeedResults, why: String) -> Self {
        Self {
            response: response.into(),
            period: r.period,
            not_shot: Some(why),
            converged: false,
            residual: f64::NAN,
            stable: false,
            largest_modulus: f64::NAN,
            instability: None,
            extents_nd: r.extents_nd,
            contact_fraction: r.contact_fraction,
            section_nd: Vec::new(),
        }
    }

    /// A response shot as the orbit `o`.
    fn shot(response: &str, o: &PeriodicOrbit) -> Self {
        Self {
            response: response.into(),
            period: o.period,
            not_shot: None,
            converged: o.converged,
            residual: o.residual,
            stable: o.stable,
            largest_modulus: o.largest_modulus,
            instability: o.instability.map(String::from),
            extents_nd: o.orbit.extents_nd,
            contact_fraction: o.orbit.contact_fraction,
            section_nd: super::branch::section(&o.orbit, o.period),
        }
    }
}

/// Shoots the run's response `res` (of `prep`, from its end state `run_end`) and the
/// companion's `c` (from `comp_end`) as periodic orbits (module docs).
pub fn shoot_both(
    prep: &Prepared,
    (res, run_end): (&SpeedResults, Option<&EndState>),
    (c, comp_end): (&SpeedResults, Option<&EndState>),
) -> CoexistOrbits {
    let mut steps = 0;
    let mut shoot = |who: &str, r: &SpeedResults, end: Option<&EndState>| {
        let (o, s) = shoot_one(prep, who, r, end);
        steps += s;
        o
    };
    let a = shoot("run", res, run_end);
    let b = shoot("companion", c, comp_end);
    let both = a.converged && b.converged;
    let distance = both.then(|| {
        let span = super::orbit_span(&res.extents_nd).max(1e-300);
        hausdorff(&a.section_nd, &b.section_nd) / span
    });
    let distinct = distance.map(|d| d > DISTINCT_SECTION);
    let stable = [&a, &b].iter().filter(|o| o.stable).count();
    let coexisting_stable = if distinct == Some(false) {
        stable.min(1)
    } else {
        stable
    };
    CoexistOrbits {
        orbits: vec![a, b],
        distance,
        distinct,
        coexisting_stable,
        steps,
    }
}

/// The response `r` (whose run ended in `end`) shot with the period it read, or why not; the
/// steps it took.
fn shoot_one(
    prep: &Prepared,
    who: &str,
    r: &SpeedResults,
    end: Option<&EndState>,
) -> (CoexistOrbit, u64) {
    if r.period == 0 {
        let why = format!(
            "not periodic (regime {}: no period up to the classification's in its window; a torus or chaos has no periodic orbit to shoot)",
            r.dynamics.regime.name()
        );
        return (CoexistOrbit::not_shot(who, r, why), 0);
    }
    let Some(end) = end else {
        let why = "its run kept no end state to shoot from (an implicit scheme or a fixed window `run.duration`)".to_string();
        return (CoexistOrbit::not_shot(who, r, why), 0);
    };
    match periodic::shoot_state(prep, r.period, end.clone()) {
        Ok(o) => (CoexistOrbit::shot(who, &o), o.steps),
        Err(e) => (CoexistOrbit::not_shot(who, r, e.to_string()), 0),
    }
}

/// The Hausdorff distance of two point sets (∞ when one is empty).
pub(crate) fn hausdorff(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    let near = |p: &[f64; 2], set: &[[f64; 2]]| {
        set.iter()
            .map(|q| (p[0] - q[0]).hypot(p[1] - q[1]))
            .fold(f64::INFINITY, f64::min)
    };
    let one = |x: &[[f64; 2]], y: &[[f64; 2]]| x.iter().map(|p| near(p, y)).fold(0.0, f64::max);
    if a.is_empty() || b.is_empty() {
        return f64::INFINITY;
    }
    one(a, b).max(one(b, a))
}
