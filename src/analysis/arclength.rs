//! Pseudo-arclength continuation of a periodic orbit in speed (issue 29): the branch followed
//! around folds, where continuation in ν alone ([`super::branch`]) stops. Written for the
//! speed; a branch in a scene key ([`Continued`]) is the same with the key's value for ν (its
//! one `N` steps a revolution is the key's branch's own).
//!
//! **The map in ν.** Along the branch every point uses the same `N` steps a revolution
//! (`Δt = 2π/(Ω N)`, `N` the finer of the plans at the range's two ends), so the discrete map
//! `P(y; ν)` of `k` revolutions is smooth in ν. Its state is `y = (u, v)` per central body,
//! `v = (uᴺ − uᴺ⁻¹)/Δt` — a velocity, which keeps its meaning as Δt changes with ν (the
//! stepper's `(uᴺ, uᴺ⁻¹)` is rebuilt from it at each speed's Δt).
//!
//! **Continuation.** The unknowns `w = (y ⊘ s, ν)`, `s` the size of each block at the first
//! point (displacements and velocities scaled apart), solve `P(y; ν) − y = 0` with the
//! pseudo-arclength condition `tᵀ (w − w_p) = 0`, `w_p = w_i + h t` predicted along the unit
//! secant `t` of the last two points (the first secant from a step in ν). Newton on the
//! bordered system `[[∂P/∂y − I, ∂P/∂ν], [tᵀ]]`: `∂P/∂y` the variational monodromy of the
//! scheme's step (`periodic::Monodromy`) where the step has its linearisation — a corrector
//! that fails with it is tried again with differences —, else central differences (two maps
//! per column), `∂P/∂ν` by central differences; a step whose Newton does not converge in [`MAX_CORRECTOR`] iterations is halved
//! (at most [`MAX_STEP_HALVINGS`] times) and grows back by 1.5 after an easy one. The
//! multipliers at each point are the eigenvalues of `∂P/∂y` there.
//!
//! **Folds** are where ν turns back: the secant's ν-component changes sign between two points.
//! A simple fold is a real multiplier through +1, where `det(∂P/∂y − I)` changes sign; the
//! segment of the branch on which it does is bisected in arclength [`LOCATE_STEPS`] times (each
//! midpoint predicted on the chord and corrected on the plane normal to it, as any point), and
//! the fold's ν is the vertex of the parabola ν(σ) through the last interval's two ends and its
//! midpoint (σ the arclength). Without such a sign change on either side (two multipliers at
//! once) the vertex through the three grid points around the turn is kept. A change of
//! stability that is not a fold (a multiplier through −1: a period doubling; a complex pair: a
//! Neimark–Sacker point) is located by the same bisection on the segment between its two points,
//! with the stability at each midpoint as the test, and reported at the last interval's middle;
//! so is a grazing point (one point touching a stator, the next not) with contact as the test.

use super::branch::{Bifurcation, Branch, BranchPoint, LOCATE_STEPS};
use super::parameter::Continued;
use super::periodic;
use super::speed::Prepared;
use super::RunSettings;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::time::{EndState, StepPlan};
use nalgebra::{DMatrix, DVector};

mod jacobian;

/// Newton iterations of one corrector.
pub const MAX_CORRECTOR: usize = 10;
/// Halvings of a step whose corrector fails before the branch is reported as ended.
pub const MAX_STEP_HALVINGS: usize = 5;
/// Relative residual of a converged point (as [`periodic::SHOOT_TOLERANCE`]).
const TOLERANCE: f64 = 1e-9;
/// Relative central-difference step of the Jacobians.
const FD_STEP: f64 = 1e-5;

/// The branch's map: the parameter (its runs at one fixed `N` steps a revolution), period and
/// fixed steps a revolution, and the state layout (an end state of the run, the sizes of its
/// central bodies).
struct Arc<'a> {
    c: &'a Continued<'a>,
    k: usize,
    n_rev: usize,
    template: EndState,
    sizes: Vec<usize>,
    /// Scales of the components of `y` (displacement and velocity blocks).
    scale: Vec<f64>,
    steps: u64,
    /// The Jacobians by differences of whole maps even where the step has its linearisation
    /// (`jacobian`: a corrector's retry).
    differences_only: bool,
    /// Whether the last Jacobian was the variational one.
    linearised: bool,
}

/// Continues the period-`period` orbit from ν = `from` (shot from its settled run) over speeds
/// within `[lo, hi]`, starting towards `to` with the step `h` (in ν), for at most `max_points`
/// points (module docs).
///
/// # Errors
/// The first point's shooting errors ([`periodic::shoot`]); later failures end the branch
/// (`ended`).
pub fn continue_arclength(
    model: &Model,
    s: &RunSettings,
    (from, to, h): (f64, f64, f64),
    period: Option<usize>,
    max_points: usize,
) -> Result<Branch> {
    let c = Continued::of_speed(model, s, from.max(to))?;
    arclength_in(c, (from, to, h), period, max_points)
}

/// [`continue_arclength`] in the parameter `c`: from its value `from` towards `to` with the
/// first step `h` (in the parameter), within `[from, to]`, at most `max_points` points.
///
/// # Errors
/// As [`continue_arclength`].
pub fn arclength_in(
    c: Continued<'_>,
    range: (f64, f64, f64),
    period: Option<usize>,
    max_points: usize,
) -> Result<Branch> {
    match started(c, range, period)? {
        Started::Ended(branch) => Ok(branch),
        Started::Shot(cf) => arclength_from(&cf.0, &cf.1, range, max_points),
    }
}

/// `rubsim continue --arclength --switch`: the branch of [`arclength_in`], then the branches
/// switched at its period doublings and theirs up to period `max_period`
/// ([`super::switch::switch_all`]): the orbits on either side of each doubling located in
/// arclength shot half the first step `h` past it from the points' kept states
/// ([`periodic::shoot_from_state`]; the grid points of an arclength branch may lie several
/// steps apart), each with the values beyond it by `h`, away from the doubling, within the
/// range. The switched branches are continued in the
/// parameter alone, at the arclength branch's one `N` steps a revolution.
///
/// # Errors
/// As [`arclength_in`].
pub fn arclength_switching(
    c: Continued<'_>,
    range: (f64, f64, f64),
    period: Option<usize>,
    (max_points, max_period): (usize, usize),
) -> Result<super::switch::Diagram> {
    match started(c, range, period)? {
        Started::Ended(branch) => Ok(super::switch::Diagram::of(branch)),
        Started::Shot(cf) => {
            let (c, first) = *cf;
            let mut branch = arclength_from(&c, &first, range, max_points)?;
            keep_doublings(&c, &mut branch, range);
            Ok(super::switch::switch_all(&c, branch, max_period))
        }
    }
}

/// The first orbit of a pseudo-arclength branch, shot from its settled run at `from`, and the
/// parameter with the branch's one `N` steps a revolution; or the branch that ends there.
enum Started<'a> {
    Shot(Box<(Continued<'a>, periodic::PeriodicOrbit)>),
    Ended(Branch),
}

/// [`Started`] of `c` over `(from, to, _)`.
fn started<'a>(
    c: Continued<'a>,
    (from, to, _): (f64, f64, f64),
    period: Option<usize>,
) -> Result<Started<'a>> {
    let first = c.shoot(from, period)?;
    if !first.converged {
        let k = first.period;
        let mut branch = Branch {
            steps: first.steps,
            ..Branch::empty(k, &c)
        };
        branch.ended = Some(format!(
            "no periodic orbit of {k} revolution(s) at {} = {from:.4} (residual {:.2e})",
            c.label(),
            first.residual
        ));
        return Ok(Started::Ended(branch));
    }
    let c = c.with_fixed_steps((from.min(to), from.max(to)))?;
    Ok(Started::Shot(Box::new((c, first))))
}

/// The branch from the orbit `first` (shot at `from`) over `[from, to]` with the first step `h`
/// in the parameter `c` (its fixed `N` steps a revolution), at most `max_points` points.
fn arclength_from(
    c: &Continued<'_>,
    first: &periodic::PeriodicOrbit,
    (from, to, h): (f64, f64, f64),
    max_points: usize,
) -> Result<Branch> {
    let (lo, hi) = (from.min(to), from.max(to));
    let k = first.period;
    let mut branch = Branch {
        steps: first.steps,
        ..Branch::empty(k, c)
    };
    let n_rev = c.steps_per_rev().unwrap_or(1);
    let (x, end) = (&first.fixed_point.0, &first.fixed_point.1);
    let sizes = end.central_sizes().ok_or_else(|| {
        Error::study(
            "run.integrator",
            "continuation needs central-difference bodies".to_string(),
        )
    })?;
    let dt0 = end.dt;
    let y0 = jacobian::to_uv(x, &sizes, dt0);
    let mut arc = Arc {
        c,
        k,
        n_rev,
        template: end.clone(),
        scale: block_scales(&y0, &sizes),
        sizes,
        steps: 0,
        differences_only: false,
        linearised: false,
    };
    // The first point again at the branch's fixed N, by Newton in y at ν = from.
    let (y0, _) = arc.correct_at(y0, from)?;
    let w0 = arc.w(&y0, from);
    let p0 = arc.point(&y0, from, 0)?;
    branch.points.push(p0);
    let dir = if to >= from { 1.0 } else { -1.0 };
    let (y1, it1) = arc.correct_at(y0.clone(), from + dir * h)?;
    let w1 = arc.w(&y1, from + dir * h);
    branch.points.push(arc.point(&y1, from + dir * h, it1)?);
    let ws = follow(&mut arc, &mut branch, vec![w0, w1], (lo, hi), max_points);
    locate_folds(&mut arc, &ws, &mut branch);
    stability_changes(&mut arc, &ws, &mut branch);
    grazings(&mut arc, &ws, &mut branch);
    branch.steps += arc.steps;
    Ok(branch)
}

/// Continues `branch` from its last two points `ws` (scaled unknowns) by pseudo-arclength
/// until it leaves `[lo, hi]`, holds `max_points` points or its corrector fails with the step
/// halved [`MAX_STEP_HALVINGS`] times. Returns the scaled unknowns of every point, in the
/// order of `branch.points`.
fn follow(
    arc: &mut Arc<'_>,
    branch: &mut Branch,
    mut ws: Vec<Vec<f64>>,
    (lo, hi): (f64, f64),
    max_points: usize,
) -> Vec<Vec<f64>> {
    let mut ds = dist(&ws[0], &ws[1]);
    let ds_max = 4.0 * ds;
    while branch.points.len() < max_points {
        let n = ws.len();
        let t = unit(&sub(&ws[n - 1], &ws[n - 2]));
        let mut step = ds;
        let mut next = None;
        for _ in 0..=MAX_STEP_HALVINGS {
            let wp: Vec<f64> = ws[n - 1]
                .iter()
                .zip(&t)
                .map(|(w, t)| w + step * t)
                .collect();
            if let Ok(Some((w, iters))) = arc.corrector(&wp, &t) {
                next = Some((w, iters));
                break;
            }
            step *= 0.5;
        }
        let Some((w, iters)) = next else {
            branch.ended = Some(format!(
                "the corrector did not converge past {} = {:.4} with the step halved {MAX_STEP_HALVINGS} times",
                arc.c.label(),
                ws[n - 1].last().copied().unwrap_or(f64::NAN)
            ));
            break;
        };
        ds = if iters <= 3 {
            (1.5 * step).min(ds_max)
        } else {
            step
        };
        let v = *w.last().unwrap_or(&f64::NAN);
        let y = arc.y(&w);
        match arc.point(&y, v, iters) {
            Ok(p) => branch.points.push(p),
            Err(e) => {
                branch.ended = Some(format!("{} = {v:.4}: {e}", arc.c.label()));
                break;
            }
        }
        ws.push(w);
        if !(lo..=hi).contains(&v) {
            break;
        }
    }
    ws
}

impl Arc<'_> {
    /// The prepared run at the parameter's value `v` with the branch's `N` steps a revolution,
    /// `k` revolutions.
    fn prep(&self, v: f64) -> Result<Prepared> {
        let mut p = self.c.prepare(v)?;
        p.plan = StepPlan {
            steps: self.k * self.n_rev,
            steady_from: 0,
            ..p.plan
        };
        Ok(p)
    }

    /// The end state of `y` for a run of step `dt` (its `(uᴺ, uᴺ⁻¹)` at that step).
    fn start(&self, y: &[f64], dt: f64) -> Result<EndState> {
        self.template
            .with_state_vector(&jacobian::from_uv(y, &self.sizes, dt))
            .map(|e| e.at_step(dt))
            .ok_or_else(|| Error::study("run", "the branch's state does not fit".to_string()))
    }

    /// `P(y; ν)` in the `(u, v)` layout.
    fn map(&mut self, y: &[f64], v: f64) -> Result<Vec<f64>> {
        let p = self.prep(v)?;
        let start = self.start(y, p.plan.dt)?;
        let end = periodic::end_after(&p, &p.plan, &start)?;
        self.steps += p.plan.steps as u64;
        Ok(jacobian::to_uv(&end, &self.sizes, p.plan.dt))
    }

    /// Newton in `y` at a fixed ν from `y` with the Jacobian [`Arc::dp_dy`] gives; the point
    /// and its iterations (`jacobian`: with a retry by differences, `Arc::correct_at`).
    fn correct_at_once(&mut self, mut y: Vec<f64>, v: f64) -> Result<(Vec<f64>, usize)> {
        for it in 0..=MAX_CORRECTOR {
            let py = self.map(&y, v)?;
            let f: Vec<f64> = py.iter().zip(&y).map(|(p, y)| p - y).collect();
            if self.residual(&f) <= TOLERANCE {
                return Ok((y, it));
            }
            let n = y.len();
            let a = self.dp_dy(&y, v)? - DMatrix::<f64>::identity(n, n);
            let rhs = DVector::from_iterator(n, f.iter().map(|f| -f));
            let Some(d) = a.lu().solve(&rhs) else { break };
            for (y, d) in y.iter_mut().zip(d.iter()) {
                *y += d;
            }
        }
        Err(Error::study(
            "run",
            format!(
                "no periodic orbit of {} revolution(s) at {} = {v:.4} on the branch's step",
                self.k,
                self.c.label()
            ),
        ))
    }

    /// The pseudo-arclength corrector from the prediction `wp` along `t`: the point and its
    /// iterations, `None` when Newton does not converge (`jacobian`: with a retry by
    /// differences, `Arc::corrector`).
    fn corrector_once(&mut self, wp: &[f64], t: &[f64]) -> Result<Option<(Vec<f64>, usize)>> {
        let n = wp.len() - 1;
        let mut w = wp.to_vec();
        for it in 0..=MAX_CORRECTOR {
            let (y, v) = (self.y(&w), w[n]);
            let py = self.map(&y, v)?;
            let f: Vec<f64> = py.iter().zip(&y).map(|(p, y)| p - y).collect();
            let g: f64 = t
                .iter()
                .zip(w.iter().zip(wp))
                .map(|(t, (w, p))| t * (w - p))
                .sum();
            if self.residual(&f) <= TOLERANCE && g.abs() <= 1e-9 {
                return Ok(Some((w, it)));
            }
            // The bordered Jacobian in the scaled unknowns.
            let dy = self.dp_dy(&y, v)?;
            let hv = FD_STEP * v.abs().max(1e-3);
            let (pa, pb) = (self.map(&y, v + hv)?, self.map(&y, v - hv)?);
            let mut a = DMatrix::<f64>::zeros(n + 1, n + 1);
            for i in 0..n {
                for j in 0..n {
                    let id = if i == j { 1.0 } else { 0.0 };
                    a[(i, j)] = (dy[(i, j)] - id) * self.scale[j];
                }
                a[(i, n)] = (pa[i] - pb[i]) / (2.0 * hv);
            }
            for j in 0..=n {
                a[(n, j)] = t[j];
            }
            let rhs = DVector::from_iterator(n + 1, f.iter().map(|f| -f).chain([-g]));
            let Some(d) = a.lu().solve(&rhs) else {
                return Ok(None);
            };
            for (w, d) in w.iter_mut().zip(d.iter()) {
                *w += d;
            }
            if !w.iter().all(|x| x.is_finite()) {
                return Ok(None);
            }
        }
        Ok(None)
    }

    /// `max |f| / max |y|` per block scale.
    fn residual(&self, f: &[f64]) -> f64 {
        f.iter()
            .zip(&self.scale)
            .fold(0.0_f64, |m, (f, s)| m.max(f.abs() / s))
    }

    /// The scaled unknowns of `(y, ν)`.
    fn w(&self, y: &[f64], v: f64) -> Vec<f64> {
        y.iter()
            .zip(&self.scale)
            .map(|(y, s)| y / s)
            .chain([v])
            .collect()
    }

    /// `y` of the scaled unknowns.
    fn y(&self, w: &[f64]) -> Vec<f64> {
        w.iter().zip(&self.scale).map(|(w, s)| w * s).collect()
    }

    /// The branch point at `(y, ν)`: multipliers of `∂P/∂y`, the orbit analysed over `6k`
    /// revolutions.
    fn point(&mut self, y: &[f64], v: f64, iterations: usize) -> Result<BranchPoint> {
        let rho = periodic::floquet(&self.dp_dy(y, v)?);
        let largest = rho.first().map_or(0.0, |r| r[0].hypot(r[1]));
        let p = self.prep(v)?;
        let start = self.start(y, p.plan.dt)?;
        let orbit = periodic::orbit_from(&p, &p.plan, &start, self.k)?;
        self.steps += orbit.stats.steps as u64;
        Ok(BranchPoint {
            speed_ratio: self.c.speed_ratio(v),
            parameter: v,
            stable: largest < 1.0,
            largest_modulus: largest,
            rho1: rho.first().copied().unwrap_or_default(),
            instability: (largest >= 1.0).then(|| periodic::crossing(rho[0], largest)),
            extents_nd: orbit.extents_nd,
            amp_1x_nd: orbit.amp_1x_nd,
            contact_fraction: orbit.contact_fraction,
            poincare_nd: super::branch::section(&orbit, self.k),
            iterations,
            residual: 0.0,
            start: Some(start),
        })
    }
}

/// Each component's scale: the largest |value| of its block (displacements, velocities) per
/// body, never zero.
fn block_scales(y: &[f64], sizes: &[usize]) -> Vec<f64> {
    let mut s = vec![1.0; y.len()];
    let mut at = 0;
    for &n in sizes {
        for b in [at, at + n] {
            let m = y[b..b + n].iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            let m = if m > 0.0 { m } else { 1.0 };
            s[b..b + n].iter_mut().for_each(|x| *x = m);
        }
        at += 2 * n;
    }
    s
}

fn sub(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(a, b)| a - b).collect()
}

fn dist(a: &[f64], b: &[f64]) -> f64 {
    sub(a, b).iter().map(|d| d * d).sum::<f64>().sqrt()
}

fn unit(a: &[f64]) -> Vec<f64> {
    let n = a.iter().map(|d| d * d).sum::<f64>().sqrt().max(1e-300);
    a.iter().map(|d| d / n).collect()
}

/// The vertex of the parabola ν(σ) through the points `ws` (three, in order along the branch),
/// σ the arclength along their chords; the middle one's ν when they are on a line.
fn vertex(ws: [&[f64]; 3]) -> f64 {
    let nu = |w: &[f64]| *w.last().unwrap_or(&f64::NAN);
    let (a, b, c) = (nu(ws[0]), nu(ws[1]), nu(ws[2]));
    let (s1, s2) = (dist(ws[0], ws[1]), dist(ws[1], ws[2]));
    // ν(σ) through (0, a), (s1, b), (s1 + s2, c).
    let (x1, x2) = (s1, s1 + s2);
    let d1 = (b - a) / x1;
    let d2 = (c - b) / (x2 - x1);
    let curv = (d2 - d1) / x2;
    if curv != 0.0 && curv.is_finite() {
        let sv = 0.5 * (x1 - d1 / curv);
        a + d1 * sv + curv * sv * (sv - x1)
    } else {
        b
    }
}

/// A located point: the bracketing unknowns `[a, b]` (the test's value at `a` kept) and their
/// midpoint, after [`LOCATE_STEPS`] bisections or the first corrector that failed.
struct Bracket {
    ends: [Vec<f64>; 2],
    mid: Option<Vec<f64>>,
}

impl Arc<'_> {
    /// `det(∂P/∂y − I) > 0` at the scaled unknowns `w`: its sign changes where a real
    /// multiplier crosses +1 (a fold).
    fn det_positive(&mut self, w: &[f64]) -> Result<bool> {
        let (y, v) = (self.y(w), w[w.len() - 1]);
        let n = y.len();
        let a = self.dp_dy(&y, v)? - DMatrix::<f64>::identity(n, n);
        Ok(a.determinant() > 0.0)
    }

    /// Every multiplier inside the unit circle at the scaled unknowns `w`, and the largest.
    fn stable_at(&mut self, w: &[f64]) -> Result<(bool, [f64; 2])> {
        let (y, v) = (self.y(w), w[w.len() - 1]);
        let rho = periodic::floquet(&self.dp_dy(&y, v)?);
        let r = rho.first().copied().unwrap_or_default();
        Ok((r[0].hypot(r[1]) < 1.0, r))
    }

    /// Whether the orbit at the scaled unknowns `w` touches a stator over its period.
    fn touches_at(&mut self, w: &[f64]) -> Result<bool> {
        let (y, v) = (self.y(w), w[w.len() - 1]);
        let p = self.prep(v)?;
        let start = self.start(&y, p.plan.dt)?;
        let orbit = periodic::orbit_from(&p, &p.plan, &start, self.k)?;
        self.steps += orbit.stats.steps as u64;
        Ok(orbit.contact_fraction > 0.0)
    }

    /// The point halfway along the chord from `a` to `b`, corrected on the plane normal to it;
    /// where that corrector fails (a kink of the branch: a grazing point, where the map is not
    /// smooth), Newton in `y` at the chord's middle value of the parameter from `a`'s state,
    /// then from `b`'s.
    fn midpoint(&mut self, a: &[f64], b: &[f64]) -> Option<Vec<f64>> {
        let t = unit(&sub(b, a));
        let half = 0.5 * dist(a, b);
        let wp: Vec<f64> = a.iter().zip(&t).map(|(a, t)| a + half * t).collect();
        if let Some((w, _)) = self.corrector(&wp, &t).ok().flatten() {
            return Some(w);
        }
        let v = wp[wp.len() - 1];
        for from in [a, b] {
            if let Ok((y, _)) = self.correct_at(self.y(from), v) {
                return Some(self.w(&y, v));
            }
        }
        None
    }

    /// Bisects the segment from `a` to `b` along the branch [`LOCATE_STEPS`] times, keeping the
    /// half on which `test` differs between its ends (`test(a)` given as `at_a`).
    fn bisect(
        &mut self,
        (a, b): (&[f64], &[f64]),
        at_a: bool,
        test: &mut dyn FnMut(&mut Self, &[f64]) -> Result<bool>,
    ) -> Bracket {
        let (mut a, mut b) = (a.to_vec(), b.to_vec());
        let mut mid = None;
        for _ in 0..LOCATE_STEPS {
            let Some(m) = self.midpoint(&a, &b) else {
                break;
            };
            match test(self, &m) {
                Ok(t) if t == at_a => a = m.clone(),
                Ok(_) => b = m.clone(),
                Err(_) => break,
            }
            mid = Some(m);
        }
        let mid = self.midpoint(&a, &b).or(mid);
        Bracket { ends: [a, b], mid }
    }
}

/// Every fold of the branch (ν turns back at a point): located by bisection on the side of the
/// turn where `det(∂P/∂y − I)` changes sign (module docs), else the vertex through the three
/// grid points.
fn locate_folds(arc: &mut Arc<'_>, ws: &[Vec<f64>], branch: &mut Branch) {
    let nu = |w: &Vec<f64>| *w.last().unwrap_or(&f64::NAN);
    let points = &branch.points;
    for i in 1..ws.len().saturating_sub(1) {
        let (a, b, c) = (nu(&ws[i - 1]), nu(&ws[i]), nu(&ws[i + 1]));
        if (b - a) * (c - b) >= 0.0 {
            continue;
        }
        let mut between = [a.min(b).min(c), a.max(b).max(c)];
        // The vertex through the grid points; the turning point itself where that parabola
        // puts it farther than the points' span beyond them (a jump, not a smooth turn).
        let width = between[1] - between[0];
        let mut fold = Some(vertex([&ws[i - 1], &ws[i], &ws[i + 1]]))
            .filter(|f| *f >= between[0] - width && *f <= between[1] + width)
            .unwrap_or(b);
        let dets: Vec<Option<bool>> = (i - 1..=i + 1)
            .map(|j| arc.det_positive(&ws[j]).ok())
            .collect();
        let side = [0, 1]
            .into_iter()
            .find(|&k| matches!((dets[k], dets[k + 1]), (Some(x), Some(y)) if x != y));
        if let Some(k) = side {
            let j = i - 1 + k;
            let at_a = dets[k] == Some(true);
            let r = arc.bisect((&ws[j], &ws[j + 1]), at_a, &mut |arc, w| {
                arc.det_positive(w)
            });
            if let Some(m) = &r.mid {
                fold = vertex([&r.ends[0], m, &r.ends[1]]);
                let (x, y) = (nu(&r.ends[0]), nu(&r.ends[1]));
                between = [x.min(y).min(fold), x.max(y).max(fold)];
            }
        }
        branch.bifurcations.push(Bifurcation {
            kind: "fold",
            between,
            parameter: fold,
            speed_ratio: arc.c.speed_ratio(fold),
            rho: [points[i].rho1, points[i + 1].rho1],
        });
    }
}

/// Changes of stability between consecutive points that no fold explains, located by
/// bisection in arclength (module docs): the last interval and its middle.
fn stability_changes(arc: &mut Arc<'_>, ws: &[Vec<f64>], b: &mut Branch) {
    let mut found = Vec::new();
    for (i, pair) in b.points.windows(2).enumerate() {
        let (p, q) = (&pair[0], &pair[1]);
        if p.stable == q.stable {
            continue;
        }
        let unstable = if p.stable { q } else { p };
        let stable = if p.stable { p } else { q };
        if unstable.instability == Some("fold") {
            continue; // the fold's own report
        }
        let mut rho = [stable.rho1, unstable.rho1];
        let r = arc.bisect((&ws[i], &ws[i + 1]), p.stable, &mut |arc, w| {
            let (st, r) = arc.stable_at(w)?;
            rho[usize::from(!st)] = r;
            Ok(st)
        });
        let nu = |w: &[f64]| *w.last().unwrap_or(&f64::NAN);
        let (x, y) = (nu(&r.ends[0]), nu(&r.ends[1]));
        let (lo, hi) = (x.min(y), x.max(y));
        let at = r.mid.as_deref().map_or(0.5 * (lo + hi), nu).clamp(lo, hi);
        found.push(Bifurcation {
            kind: unstable.instability.unwrap_or("unknown"),
            between: [lo, hi],
            parameter: at,
            speed_ratio: arc.c.speed_ratio(at),
            rho,
        });
    }
    b.bifurcations.extend(found);
}

/// Grazing points between consecutive points one of which touches a stator and the other not,
/// located by bisection in arclength on contact (`branch::Bifurcation`'s `grazing`).
fn grazings(arc: &mut Arc<'_>, ws: &[Vec<f64>], b: &mut Branch) {
    let mut found = Vec::new();
    for (i, pair) in b.points.windows(2).enumerate() {
        let (p, q) = (&pair[0], &pair[1]);
        let (tp, tq) = (p.contact_fraction > 0.0, q.contact_fraction > 0.0);
        if tp == tq {
            continue;
        }
        let r = arc.bisect((&ws[i], &ws[i + 1]), tp, &mut |arc, w| arc.touches_at(w));
        let nu = |w: &[f64]| *w.last().unwrap_or(&f64::NAN);
        let (x, y) = (nu(&r.ends[0]), nu(&r.ends[1]));
        let (lo, hi) = (x.min(y), x.max(y));
        let at = 0.5 * (lo + hi);
        let (free, rub) = if tp { (q, p) } else { (p, q) };
        found.push(Bifurcation {
            kind: "grazing",
            between: [lo, hi],
            parameter: at,
            speed_ratio: arc.c.speed_ratio(at),
            rho: [free.rho1, rub.rho1],
        });
    }
    b.bifurcations.extend(found);
}

/// Keeps, for every period doubling located on the pseudo-arclength `branch`, the orbits on its
/// two sides — half the first step `h` past it, by Newton from the nearer point's kept state
/// (that point's own value where that fails or the point is nearer) — with the values beyond
/// each — by the first step `h`, away from the doubling, within the range — for switching
/// (`branch::Doubling`). A doubling whose orbits do not converge is not kept (switching then
/// lists it as not followed).
fn keep_doublings(c: &Continued<'_>, branch: &mut Branch, (from, to, h): (f64, f64, f64)) {
    let (lo, hi) = (from.min(to), from.max(to));
    let mut kept = Vec::new();
    for (bi, b) in branch.bifurcations.iter().enumerate() {
        if b.kind != "period_doubling" {
            continue;
        }
        let pair = branch.points.windows(2).find(|w| {
            let (a, z) = (
                w[0].parameter.min(w[1].parameter),
                w[0].parameter.max(w[1].parameter),
            );
            w[0].stable != w[1].stable && (a..=z).contains(&b.parameter)
        });
        let Some(pair) = pair else {
            continue;
        };
        // Half the first step past the doubling on the point's side (the grid points of an
        // arclength branch may lie several steps apart), by Newton from the point's state;
        // the point itself where that fails.
        let shot_at = |p: &super::branch::BranchPoint, v: f64| {
            let start = p.start.as_ref()?;
            let prep = c.prepare(v).ok()?;
            let mut o = periodic::shoot_from_state(&prep, branch.period, start).ok()?;
            o.parameter = v;
            o.converged.then_some(o)
        };
        let shot = |p: &super::branch::BranchPoint| -> Option<periodic::PeriodicOrbit> {
            let side = if p.parameter >= b.parameter {
                1.0
            } else {
                -1.0
            };
            let near = b.parameter + side * 0.5 * h;
            let between = (near - p.parameter) * side <= 0.0;
            between
                .then(|| shot_at(p, near))
                .flatten()
                .or_else(|| shot_at(p, p.parameter))
        };
        let (Some(a), Some(z)) = (shot(&pair[0]), shot(&pair[1])) else {
            continue;
        };
        let beyond = |o: &periodic::PeriodicOrbit| -> Vec<f64> {
            let dir = if o.parameter >= b.parameter {
                1.0
            } else {
                -1.0
            };
            (1..)
                .map(|i| o.parameter + dir * h * f64::from(i))
                .take_while(|v| (lo - 1e-12..=hi + 1e-12).contains(v))
                .take(1_000_000)
                .collect()
        };
        let (ba, bz) = (beyond(&a), beyond(&z));
        let (unstable, stable) = if pair[0].stable {
            ((z, bz), (a, ba))
        } else {
            ((a, ba), (z, bz))
        };
        kept.push(super::branch::Doubling {
            bifurcation: bi,
            unstable,
            stable,
        });
    }
    branch.steps += kept
        .iter()
        .map(|d| d.unstable.0.steps + d.stable.0.steps)
        .sum::<u64>();
    branch.doublings = kept;
}
