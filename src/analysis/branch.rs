//! A periodic orbit continued in a parameter — the speed, or a scene key at a fixed speed
//! ([`Continued`]) —, its stability along the branch and where it changes (issue 29:
//! natural-parameter continuation; pseudo-arclength, which follows a branch around a fold, is
//! [`super::arclength`]). Written for the speed below; a key's branch is the same with its
//! values for the speeds (one step plan for all of them: [`super::parameter`]).
//!
//! The orbit of period `k` revolutions is shot at the first speed from its settled run
//! ([`super::periodic::shoot`]); at each next speed Newton starts from the previous fixed point,
//! its velocities `(uᴺ − uᴺ⁻¹)/Δt` carried to the new speed's step
//! ([`crate::time::EndState::retimed`]); where Newton does not converge the step is halved
//! ([`MAX_SUBSTEPS`] times at most, the midpoints joining the branch). The branch ends where it
//! still does not (a fold — the orbit turns back, `rubsim continue --arclength` follows it —,
//! or the orbit ceases to exist); the report says at which speed. A reduced model's cut-off is
//! pinned for the whole branch ([`pinned_reduction`]). Between two converged points whose stability differs (every `|ρ| < 1` on one
//! side only) the change is located by bisection in ν ([`LOCATE_STEPS`] halvings, each a
//! Newton from the nearer point) and named by the multiplier that crosses the unit circle on
//! the unstable side: `period_doubling` (ρ through −1), `fold` (through +1) or
//! `neimark_sacker` (a complex pair). Between two points one of which touches a stator over its
//! period and the other not, the grazing point — where the orbit's largest excursion reaches the
//! clearance, a rub beginning or ending, the branch's nonsmooth point — is located by the same
//! bisection on contact (`grazing`).

pub use super::parameter::pinned_reduction;
use super::parameter::Continued;
use super::periodic::{self, PeriodicOrbit};
use super::speed::Prepared;
use super::RunSettings;
use crate::error::Result;
use crate::model::Model;
use serde::{Deserialize, Deserializer, Serialize};

/// Halvings of a continuation step whose Newton does not converge, each reaching the
/// midpoint first (the contact set can change much between two speeds of a sweep's grid).
pub const MAX_SUBSTEPS: usize = 4;

/// Halvings of the interval in which a change of stability is located (the interval shrinks
/// to 1/2⁶ = 1/64 of the continuation step).
pub const LOCATE_STEPS: usize = 6;

/// One converged point of the branch.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BranchPoint {
    /// ν = ω/ω_n of the orbit (a key's branch: its fixed speed).
    pub speed_ratio: f64,
    /// The continued parameter's value: ν for a branch in speed, the key's value (in the key's
    /// own units) for a branch in a key.
    pub parameter: f64,
    /// Every `|ρ| < 1`.
    pub stable: bool,
    /// Largest `|ρ|`.
    pub largest_modulus: f64,
    /// The multiplier of largest modulus `[Re, Im]`.
    pub rho1: [f64; 2],
    /// How it is unstable (`period_doubling`, `fold`, `neimark_sacker`), `None` when stable.
    #[serde(default, deserialize_with = "kind_or_none")]
    pub instability: Option<KindName>,
    /// The orbit's extents `[x_min, x_max, y_min, y_max]` / |Z0|.
    pub extents_nd: [f64; 4],
    /// 1× amplitude / |Z0|.
    pub amp_1x_nd: f64,
    /// Fraction of the period in contact.
    pub contact_fraction: f64,
    /// The orbit's points on the Poincaré section once per revolution, `[x, y]` / |Z0|: its
    /// `period` distinct ones, from the fixed point on.
    pub poincare_nd: Vec<[f64; 2]>,
    /// Newton iterations from the predicted state.
    pub iterations: usize,
    /// Newton's final relative residual.
    pub residual: f64,
    /// The fixed point as a restart state (`rubsim continue --orbits-at`: Newton from the
    /// nearest point, [`super::orbits_at`]); not serialised.
    #[serde(skip)]
    pub(crate) start: Option<crate::time::EndState>,
}

/// A change of stability located between two speeds.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Bifurcation {
    /// `period_doubling`, `fold` or `neimark_sacker`: the unstable side's crossing multiplier;
    /// `grazing`: the orbit's largest excursion reaches the clearance (a rub begins or ends:
    /// the branch's nonsmooth point), whatever the stability on either side.
    #[serde(deserialize_with = "kind")]
    pub kind: KindName,
    /// The located interval of the parameter `[ν_a, ν_b]` (a key's branch: of the key's
    /// values): stable at one end, unstable at the other.
    pub between: [f64; 2],
    /// Its midpoint, the reported location, in the parameter.
    pub parameter: f64,
    /// ν there: the location for a branch in speed, the fixed speed of a key's branch.
    pub speed_ratio: f64,
    /// The crossing multiplier on the stable and on the unstable side (a grazing: the largest
    /// on the side clear of the stators and on the touching side).
    pub rho: [[f64; 2]; 2],
}

/// A branch of period-`k` orbits over speed. Read back (a continuation's segment file,
/// `crate::study::segments`) without its restart states and doublings, which are not written.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Branch {
    /// The continued parameter: `speed_ratio` (ν), or the scene key.
    pub parameter: String,
    /// The fixed ν of a branch in a scene key (`None` for a branch in speed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub at_speed_ratio: Option<f64>,
    /// Period in revolutions.
    pub period: usize,
    /// The converged points, in the order continued.
    pub points: Vec<BranchPoint>,
    /// The changes of stability located along it.
    pub bifurcations: Vec<Bifurcation>,
    /// Why the branch stops before the last speed, when it does.
    #[serde(default)]
    pub ended: Option<String>,
    /// Steps integrated in all.
    pub steps: u64,
    /// The orbits on either side of each located period doubling, for branch switching
    /// ([`super::switch`]); not serialised.
    #[serde(skip)]
    pub(crate) doublings: Vec<Doubling>,
}

/// The two converged grid orbits around a located period doubling, and the parameter's values
/// beyond each (in the order a branch from there would be continued).
#[derive(Debug, Clone)]
pub(crate) struct Doubling {
    /// Index of the bifurcation in [`Branch::bifurcations`].
    pub bifurcation: usize,
    /// The orbit on the side where the branch is unstable, and the speeds beyond it (away from
    /// the doubling).
    pub unstable: (PeriodicOrbit, Vec<f64>),
    /// The orbit on the stable side, and the speeds beyond it.
    pub stable: (PeriodicOrbit, Vec<f64>),
}

impl Branch {
    /// A branch of period `period` in the parameter `c` with no point yet.
    pub(crate) fn empty(period: usize, c: &Continued<'_>) -> Self {
        Self {
            parameter: c.name().to_string(),
            at_speed_ratio: c.key().map(|_| c.speed_ratio(0.0)),
            ..Self::in_speed(period)
        }
    }

    /// A branch of period `period` in speed with no point yet.
    fn in_speed(period: usize) -> Self {
        Self {
            parameter: "speed_ratio".to_string(),
            at_speed_ratio: None,
            period,
            points: Vec::new(),
            bifurcations: Vec::new(),
            ended: None,
            steps: 0,
            doublings: Vec::new(),
        }
    }
}

impl BranchPoint {
    fn of(o: &PeriodicOrbit) -> Self {
        Self {
            speed_ratio: o.speed_ratio,
            parameter: o.parameter,
            stable: o.stable,
            largest_modulus: o.largest_modulus,
            rho1: o.multipliers.first().copied().unwrap_or_default(),
            instability: o.instability,
            extents_nd: o.orbit.extents_nd,
            amp_1x_nd: o.orbit.amp_1x_nd,
            contact_fraction: o.orbit.contact_fraction,
            poincare_nd: section(&o.orbit, o.period),
            iterations: o.iterations,
            residual: o.residual,
            start: o.start_state(),
        }
    }
}

/// The names a bifurcation's `kind` and a point's `instability` take.
pub const KINDS: [&str; 4] = ["period_doubling", "fold", "neimark_sacker", "grazing"];

/// One of [`KINDS`] (spelled through an alias: serde's derive borrows a field written
/// `&str` from its input, which a name read back from a file cannot be).
pub type KindName = &'static str;

/// The name of [`KINDS`] equal to `s`.
fn known<E: serde::de::Error>(s: &str) -> std::result::Result<KindName, E> {
    KINDS
        .into_iter()
        .find(|k| *k == s)
        .ok_or_else(|| E::custom(format!("unknown kind `{s}`, expected one of {KINDS:?}")))
}

/// One of [`KINDS`], read back.
fn kind<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<KindName, D::Error> {
    known(&String::deserialize(d)?)
}

/// One of [`KINDS`] or nothing, read back.
fn kind_or_none<'de, D: Deserializer<'de>>(
    d: D,
) -> std::result::Result<Option<KindName>, D::Error> {
    Option::<String>::deserialize(d)?
        .map(|s| known(&s))
        .transpose()
}

/// The first `k` Poincaré points of an orbit's run (its distinct ones when it has period `k`).
pub(crate) fn section(orbit: &super::SpeedResults, k: usize) -> Vec<[f64; 2]> {
    orbit.poincare_nd.iter().take(k).copied().collect()
}

/// Continues the period-`period` orbit (`None`: the first speed's settled period) over
/// `speeds` (ν, in the order given) with the scene's run settings `s` (module docs).
///
/// # Errors
/// The first speed's shooting errors ([`periodic::shoot`]); a run error at a later speed
/// ends the branch there (`ended`), it is not returned.
pub fn continue_in_speed(
    model: &Model,
    s: &RunSettings,
    speeds: &[f64],
    period: Option<usize>,
) -> Result<Branch> {
    let Some(top) = speeds.iter().copied().reduce(f64::max) else {
        return Ok(Branch::in_speed(period.unwrap_or(1)));
    };
    let c = Continued::of_speed(model, s, top)?;
    continue_in(&c, speeds, period)
}

/// Continues the period-`period` orbit (`None`: the first value's settled period) over the
/// parameter's `values` (in the order given): [`continue_in_speed`] for any parameter.
///
/// # Errors
/// The first value's shooting errors; later ones end the branch (`ended`).
pub fn continue_in(c: &Continued<'_>, values: &[f64], period: Option<usize>) -> Result<Branch> {
    let Some((&first, _)) = values.split_first() else {
        return Ok(Branch::empty(period.unwrap_or(1), c));
    };
    let start = c.shoot(first, period)?;
    Ok(follow(c, start, values, None))
}

/// The branch from the orbit `start` (at `speeds[0]`) over the rest of `speeds`, values of the
/// parameter `c`: Newton at each next speed, a step
/// halved where it fails, changes of stability located; the orbits around each period
/// doubling kept for switching. A run error ends the branch (`ended`). A branch switched from
/// a period-`parent` branch (`Some(parent)`, [`super::switch`]) also ends where its orbit
/// repeats after `parent` revolutions already: it has merged back into its parent (a period
/// halving), and Newton would follow the parent from there as a fixed point of the longer map.
/// Any branch treats an orbit of a longer minimal period than the previous point's (the
/// fewest revolutions after which its Poincaré points repeat) as a failed step: Newton jumped
/// onto the doubled orbit, which the k-revolution map of an orbit that repeats sooner has as
/// a fixed point too.
pub fn follow(
    c: &Continued<'_>,
    start: PeriodicOrbit,
    speeds: &[f64],
    parent: Option<usize>,
) -> Branch {
    let k = start.period;
    let mut steps = start.steps;
    let mut branch = Branch::empty(k, c);
    if !start.converged {
        branch.ended = Some(format!(
            "no periodic orbit of {k} revolution(s) at {} = {:.4} (residual {:.2e})",
            c.label(),
            start.parameter,
            start.residual
        ));
        branch.steps = steps;
        return branch;
    }
    let mut prev = start;
    branch.points.push(BranchPoint::of(&prev));
    // Speeds still to reach, the next last; a step whose Newton fails is halved (up to
    // [`MAX_SUBSTEPS`] times) by reaching its midpoint first.
    let mut todo: Vec<(f64, usize)> = speeds.iter().skip(1).rev().map(|&v| (v, 0)).collect();
    while let Some((v, depth)) = todo.pop() {
        let next = match advance(c, &prev, v, parent) {
            (Advance::Point(o), st) => {
                steps += st;
                o
            }
            (Advance::Failed(_), st) if depth < MAX_SUBSTEPS => {
                steps += st;
                todo.push((v, depth + 1));
                todo.push((0.5 * (prev.parameter + v), depth + 1));
                continue;
            }
            (Advance::Failed(why) | Advance::Error(why), st) => {
                steps += st;
                branch.ended = Some(why);
                break;
            }
        };
        if next.stable != prev.stable {
            let (b, st) = locate(c, &prev, &next);
            steps += st;
            if let Some(b) = b {
                // A doubling named on an orbit that repeats sooner than the map (own_instability)
                // has no −1 multiplier of the map to switch along.
                if b.kind == "period_doubling" && minimal_period(&prev) == prev.period {
                    keep_doubling(&mut branch, (&prev, &next), &todo);
                }
                branch.bifurcations.push(b);
            }
        }
        if touches(&next) != touches(&prev) {
            let (b, st) = locate_grazing(c, &prev, &next);
            steps += st;
            branch.bifurcations.push(b);
        }
        branch.points.push(BranchPoint::of(&next));
        prev = next;
    }
    branch.steps = steps;
    branch
}

/// What one continuation step gave.
enum Advance {
    /// A converged orbit that belongs to the branch.
    Point(PeriodicOrbit),
    /// Newton did not converge, or (a switched branch) converged onto its parent: the step may
    /// be halved; the sentence if it is not.
    Failed(String),
    /// A run error: the branch ends.
    Error(String),
}

/// The branch's orbit at the parameter's value `v` by Newton from `prev` (module docs of
/// [`follow`]), and the steps it took.
fn advance(
    c: &Continued<'_>,
    prev: &PeriodicOrbit,
    v: f64,
    parent: Option<usize>,
) -> (Advance, u64) {
    let k = prev.period;
    let at = c.label();
    let (prep, o) = match c.shoot_from(v, prev) {
        Ok(x) => x,
        Err(e) => return (Advance::Error(format!("{at} = {v:.4}: {e}")), 0),
    };
    let steps = o.steps;
    if !o.converged {
        let why = format!(
            "Newton did not converge at {at} = {v:.4} from the orbit at {:.4} (residual {:.2e}, the step halved {MAX_SUBSTEPS} times): a fold, or the period-{k} orbit ends there",
            prev.parameter, o.residual
        );
        return (Advance::Failed(why), steps);
    }
    match merged(&prep, &o, parent) {
        Ok((false, st)) if minimal_period(&o) > minimal_period(prev) => {
            let why = format!(
                "Newton from the orbit at {at} {:.4} reached an orbit of minimal period {} at {v:.4} where the branch's is {} (another branch, the step halved {MAX_SUBSTEPS} times)",
                prev.parameter,
                minimal_period(&o),
                minimal_period(prev)
            );
            (Advance::Failed(why), steps + st)
        }
        Ok((false, st)) => (Advance::Point(o), steps + st),
        Ok((true, st)) => {
            let p = parent.unwrap_or(k);
            let why = format!(
                "the period-{k} orbit merges back into the period-{p} branch between {at} {:.4} and {v:.4} (Newton from {:.4} reaches an orbit that repeats after {p} revolutions, the step halved {MAX_SUBSTEPS} times)",
                prev.parameter, prev.parameter
            );
            (Advance::Failed(why), steps + st)
        }
        Err(e) => (Advance::Error(format!("{at} = {v:.4}: {e}")), steps),
    }
}

/// Whether the orbit `o` found on `prep` repeats after `parent` revolutions (its `parent`-map
/// residual within [`periodic::DISTINCT`]), and the steps that took; `false` without a parent.
fn merged(prep: &Prepared, o: &PeriodicOrbit, parent: Option<usize>) -> Result<(bool, u64)> {
    let Some(p) = parent else {
        return Ok((false, 0));
    };
    let (r, steps) = periodic::residual_after(prep, o, p)?;
    Ok((r <= periodic::DISTINCT, steps))
}

/// Keeps the grid orbits `prev`, `next` around the period doubling about to be pushed as
/// [`Branch::bifurcations`]' next entry: each with the speeds beyond it — after `next` the
/// speeds still to do (`todo`, the next last), before `prev` the converged speeds back to the
/// branch's start.
fn keep_doubling(
    branch: &mut Branch,
    (prev, next): (&PeriodicOrbit, &PeriodicOrbit),
    todo: &[(f64, usize)],
) {
    let ahead: Vec<f64> = todo.iter().rev().map(|t| t.0).collect();
    let mut behind: Vec<f64> = branch.points.iter().map(|p| p.parameter).collect();
    behind.pop(); // prev itself
    behind.reverse();
    let (a, b) = ((prev.clone(), behind), (next.clone(), ahead));
    let (unstable, stable) = if next.stable { (a, b) } else { (b, a) };
    branch.doublings.push(Doubling {
        bifurcation: branch.bifurcations.len(),
        unstable,
        stable,
    });
}

/// Bisects the interval between `a` and `b` (`test` differing between them) [`LOCATE_STEPS`]
/// times, each midpoint by Newton from the nearer end on `test`'s side of `a`; the last
/// interval's ends (the first with `a`'s value of `test`) and the steps it took. A midpoint
/// whose Newton fails, or reaches an orbit of a longer minimal period than its start's (another
/// branch: near a period doubling the k-revolution map of an orbit that repeats sooner has the
/// doubled orbit as a fixed point too; a shorter one is the branch merging into the orbit it
/// doubled from, which it meets continuously), ends the location at the interval reached.
fn bisect(
    c: &Continued<'_>,
    (a, b): (&PeriodicOrbit, &PeriodicOrbit),
    test: fn(&PeriodicOrbit) -> bool,
) -> (PeriodicOrbit, PeriodicOrbit, u64) {
    let (mut lo, mut hi) = (a.clone(), b.clone());
    let mut steps = 0;
    for _ in 0..LOCATE_STEPS {
        let mid = 0.5 * (lo.parameter + hi.parameter);
        match c.shoot_from(mid, &lo) {
            Ok((_, m)) if m.converged && minimal_period(&m) <= minimal_period(&lo) => {
                steps += m.steps;
                if test(&m) == test(&lo) {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            _ => break,
        }
    }
    (lo, hi, steps)
}

/// How the orbit `o` is unstable as an orbit of its own minimal period `p` when that is
/// shorter than the map's `k` revolutions it was continued with, and the steps that took: the
/// `k`-revolution map's multipliers are the `p`-revolution map's to the power `k/p`, so its
/// crossing at +1 may be the orbit's period doubling (ρ through −1 for even `k/p`); the orbit's
/// fixed point is shot once more on the `p`-revolution map (a fixed point of it already: one
/// monodromy) and named by that map's crossing multiplier. `None` when `p = k` or the shot
/// fails.
fn own_instability(c: &Continued<'_>, o: &PeriodicOrbit) -> (Option<&'static str>, u64) {
    let p = minimal_period(o);
    if p >= o.period {
        return (None, 0);
    }
    let shot = c.prepare(o.parameter).and_then(|prep| {
        let start = o
            .start_state()
            .ok_or_else(|| crate::error::Error::study("run", "no restart state"))?;
        periodic::shoot_from_state(&prep, p, &start)
    });
    match shot {
        Ok(q) if q.converged => (q.instability, q.steps),
        Ok(q) => (None, q.steps),
        Err(_) => (None, 0),
    }
}

/// The orbit's minimal period: the smallest divisor `p` of its period `k` after which its
/// Poincaré points (of the `6k` revolutions run from the fixed point) repeat, within
/// [`periodic::DISTINCT`] of their size.
pub(crate) fn minimal_period(o: &PeriodicOrbit) -> usize {
    let pts = &o.orbit.poincare_nd;
    let size = pts.iter().fold(1e-300_f64, |m, p| m.max(p[0].hypot(p[1])));
    let repeats = |p: usize| {
        pts.len() > p
            && pts
                .iter()
                .zip(&pts[p..])
                .all(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]) <= periodic::DISTINCT * size)
    };
    (1..o.period)
        .filter(|p| o.period.is_multiple_of(*p))
        .find(|&p| repeats(p))
        .unwrap_or(o.period)
}

/// Whether the orbit touches a stator at some instant of its period.
fn touches(o: &PeriodicOrbit) -> bool {
    o.orbit.contact_fraction > 0.0
}

/// The grazing point between `a` and `b`, one clear of the stators over its period and the
/// other touching them: located by bisection on [`touches`] (the orbit's largest excursion
/// reaches the clearance there: the branch's nonsmooth point, where a rub begins or ends).
/// Reported as `grazing`, its `rho` the free side's and the touching side's largest
/// multipliers.
fn locate_grazing(c: &Continued<'_>, a: &PeriodicOrbit, b: &PeriodicOrbit) -> (Bifurcation, u64) {
    let (lo, hi, steps) = bisect(c, (a, b), touches);
    let (free, rub) = if touches(&lo) { (&hi, &lo) } else { (&lo, &hi) };
    let rho = |o: &PeriodicOrbit| o.multipliers.first().copied().unwrap_or_default();
    let at = 0.5 * (lo.parameter + hi.parameter);
    let bif = Bifurcation {
        kind: "grazing",
        between: [lo.parameter, hi.parameter],
        parameter: at,
        speed_ratio: c.speed_ratio(at),
        rho: [rho(free), rho(rub)],
    };
    (bif, steps)
}

/// Bisects the interval between `a` and `b` (stable on one side only) [`LOCATE_STEPS`] times;
/// the bifurcation found (none when a midpoint's Newton fails, which ends the location at the
/// interval reached) and the steps it took.
fn locate(c: &Continued<'_>, a: &PeriodicOrbit, b: &PeriodicOrbit) -> (Option<Bifurcation>, u64) {
    let (lo, hi, mut steps) = bisect(c, (a, b), |o| o.stable);
    let (stable, unstable) = if lo.stable { (&lo, &hi) } else { (&hi, &lo) };
    let rho = |o: &PeriodicOrbit| o.multipliers.first().copied().unwrap_or_default();
    let at = 0.5 * (lo.parameter + hi.parameter);
    let (own, st) = own_instability(c, unstable);
    steps += st;
    let bif = own.or(unstable.instability).map(|kind| Bifurcation {
        kind,
        between: [lo.parameter, hi.parameter],
        parameter: at,
        speed_ratio: c.speed_ratio(at),
        rho: [rho(stable), rho(unstable)],
    });
    (bif, steps)
}
