//! The variational equations of the scheme's own step: the monodromy of shooting
//! (`analysis::periodic`) carried along one run instead of differenced over whole runs.
//!
//! **The step's linearisation.** An explicit step of a rotor against massless stators is
//!
//! `uⁿ⁺¹ = ũ + c(Eᵀũ)`,  `ũ = M̃⁻¹ (fⁿ + A uⁿ + B uⁿ⁻¹ + l(Eᵀuⁿ))`,
//!
//! with `E` the rotor's contact DOFs (each station's x and y), `l` the load the collocated
//! scheme's static contact forces (solved with the rotor held at uⁿ) add to the prediction and
//! `c` the forward increment's correction of the prediction ũ (Eqs. 37–47); each scheme has one
//! of the two, the other is zero. Its tangent `(δuⁿ, δuⁿ⁻¹) → (δuⁿ⁺¹, δuⁿ)` is
//!
//! `δũ = M̃⁻¹ (A δuⁿ + B δuⁿ⁻¹ + L Eᵀδuⁿ)`,  `δuⁿ⁺¹ = δũ + D Eᵀδũ`,
//!
//! `L = ∂l/∂y` (N/m) and `D = ∂c/∂y` (n × m, m the contact DOFs). The body's part (`M̃⁻¹`, `A`,
//! `B`) is applied exactly, with the run's own operators. `L` and `D` are the derivatives of the
//! step's contact solve — the complementarity problem, the friction direction, a ring's
//! re-aligned normal, whatever the scene's contact law does — with the solve's *active set*
//! (the pairs carrying force) kept: central differences of the solve itself over each contact
//! DOF, `y ± h`, which costs `2 m` small solves on a step in contact and none on a step out of
//! it. A perturbation that changes the active set (a contact starting or ending within `h`) is
//! shrunk by 10, up to twice, so that an event near the step but not on it falls outside it
//! ([`TangentStats::shrunk`]; a meshed stator, whose pairs change as the rotor slides past its
//! nodes, has such events at every few steps); one that still changes it is not differenced
//! across: the one side that keeps the step's own set is taken (forward or backward
//! difference), and a step where neither side keeps it is counted
//! ([`TangentStats::straddled`]). The product over the map's steps is the monodromy of the
//! discrete map on the orbit's own sequence of active sets: the one-sided derivative along the
//! orbit, never a mean across a contact event, which is what differencing whole maps gives when
//! a perturbation moves an event across a step. `h` is chosen by the caller; the solve's
//! geometry has curvature on the scale of the section radius (its normal turns with the
//! position), so `h` of `10⁻⁴` of the orbit's size leaves a truncation of `(h / R)²` and a
//! round-off of `ε R / h`, both below 10⁻⁹ of the entries.
//!
//! **What is linearised.** [`Stepper::linearisable`]: an explicit scheme at constant speed,
//! every stator massless, no stick, dashpot, wear or abradable coating (those keep state between
//! steps that the map's state `x = (uⁿ, uⁿ⁻¹)` of the rotor does not hold, or take velocities
//! this linearisation does not perturb). Other scenes keep the differences of whole maps.

use super::Stepper;
use crate::error::SolveError;
use crate::time::body::Ops;
use crate::time::drive::Spin;
use crate::time::stator::StatorDyn;

/// One step's contact linearisation, filled by [`Stepper::step`] while a probe is set.
#[derive(Debug)]
pub(crate) struct Probe {
    /// The contact DOF perturbation `h` (m).
    h: f64,
    /// The rotor's contact DOFs `E` (each station's `[x, y]`, in order).
    dofs: Vec<usize>,
    /// `L` (collocated) or `D` (forward increment), n × m column-major.
    jac: Vec<f64>,
    /// Whether `jac` is not zero this step (a solve found pairs).
    any: bool,
    /// The counters so far.
    stats: TangentStats,
}

/// What the linearisation met along a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct TangentStats {
    /// Steps whose contact solve found pairs (each differenced over the contact DOFs).
    pub contact_steps: usize,
    /// Contact DOF columns differenced on one side, the other side's perturbation changing
    /// the step's active set.
    pub one_sided: usize,
    /// Contact DOF columns where both sides changed the active set (a pair within `h` of its
    /// event on both sides): differenced centrally across it.
    pub straddled: usize,
    /// Contact DOF columns whose perturbation was shrunk (by 10, up to twice) because a side
    /// changed the active set: an event near the step but not on it is
    /// then left outside the perturbation, and the column differenced centrally.
    #[serde(default)]
    pub shrunk: usize,
}

/// The factor a column's perturbation is shrunk by while a side changes the active set.
const SHRINK: f64 = 10.0;
/// How many times a column's perturbation is shrunk at most (to `h / SHRINK^SHRINKS`; the
/// round-off `ε R / h` grows by as much, on those columns only).
const SHRINKS: usize = 2;

/// A column's two perturbed solves: the effect and the active set at `+h`, then at `−h`.
type Sides = (Vec<f64>, Vec<usize>, Vec<f64>, Vec<usize>);

/// The tangent columns `(δuⁿ, δuⁿ⁻¹)` of the rotor's state carried along a run: after `N` steps
/// from the identity, the monodromy `∂xᴺ/∂x⁰` of `x = (uⁿ, uⁿ⁻¹)` ([`Tangent::matrix`]).
#[derive(Debug)]
pub struct Tangent {
    n: usize,
    /// `δuⁿ` of each column, n × 2n column-major.
    du: Vec<f64>,
    /// `δuⁿ⁻¹` of each column.
    dup: Vec<f64>,
    /// One column's right-hand side and prediction.
    rhs: Vec<f64>,
}

impl Tangent {
    /// The monodromy so far, `2n × 2n` column-major in the state's layout (`uⁿ` then `uⁿ⁻¹`
    /// rows; the columns perturb the start's `uⁿ` then `uⁿ⁻¹`).
    pub fn matrix(&self) -> Vec<f64> {
        let n = self.n;
        let mut m = vec![0.0; 4 * n * n];
        for j in 0..2 * n {
            let col = &mut m[j * 2 * n..(j + 1) * 2 * n];
            col[..n].copy_from_slice(&self.du[j * n..(j + 1) * n]);
            col[n..].copy_from_slice(&self.dup[j * n..(j + 1) * n]);
        }
        m
    }
}

impl Stepper<'_> {
    /// Whether this run's step has its variational equations here (module docs): an explicit
    /// scheme at constant speed whose every stator is massless, without stick, dashpots, wear
    /// or abradable coatings.
    pub fn linearisable(&self) -> bool {
        let case = self.case;
        matches!(self.spin, Spin::Constant)
            && self.gyro.is_none()
            && matches!(self.rotor.ops, Ops::Central(_))
            && self
                .stators
                .iter()
                .all(|s| matches!(s, StatorDyn::Massless(_)))
            && !self.pairs.any_stick
            && !self.pairs.any_wear
            && !self.pairs.any_layer
            && case.stators.iter().all(|s| !s.dashpot.active())
    }

    /// Starts carrying the tangent from the identity at the current state, the contact DOFs
    /// perturbed by `h` (m) in each step's linearisation; `None` when the run is not
    /// [`Stepper::linearisable`].
    pub fn start_tangent(&mut self, h: f64) -> Option<Tangent> {
        if !self.linearisable() || h.is_nan() || h <= 0.0 {
            return None;
        }
        let n = self.rotor.n;
        let dofs: Vec<usize> = self.pairs.station_dofs.iter().flatten().copied().collect();
        let mut du = vec![0.0; 2 * n * n];
        let mut dup = vec![0.0; 2 * n * n];
        for j in 0..n {
            du[j * n + j] = 1.0;
            dup[(n + j) * n + j] = 1.0;
        }
        self.probe = Some(Box::new(Probe {
            h,
            jac: vec![0.0; n * dofs.len()],
            dofs,
            any: false,
            stats: TangentStats::default(),
        }));
        Some(Tangent {
            n,
            du,
            dup,
            rhs: vec![0.0; n],
        })
    }

    /// The linearisation's counters so far (zero without a tangent).
    pub fn tangent_stats(&self) -> TangentStats {
        self.probe
            .as_ref()
            .map_or_else(Default::default, |p| p.stats)
    }

    /// Steps until the next step is `target` (as [`Stepper::run_to`], without frames),
    /// carrying `tan` through each step.
    ///
    /// # Errors
    /// As [`Stepper::step`].
    pub fn run_tangent_to(&mut self, target: usize, tan: &mut Tangent) -> Result<(), SolveError> {
        self.run_to(self.n, &mut None)?;
        let target = target.min(self.plan.steps);
        while self.n < target {
            self.step(&mut None)?;
            self.carry(tan);
        }
        Ok(())
    }

    /// Carries the tangent through the step just taken (module docs).
    fn carry(&mut self, tan: &mut Tangent) {
        let Some(probe) = self.probe.as_ref() else {
            return;
        };
        let (n, m) = (tan.n, probe.dofs.len());
        let collocated = self.scheme.collocated();
        let jac = probe.any.then_some(&probe.jac);
        for j in 0..2 * n {
            let (du, dup) = (&tan.du[j * n..(j + 1) * n], &tan.dup[j * n..(j + 1) * n]);
            let rhs = &mut tan.rhs;
            rhs.fill(0.0);
            if let (Some(l), true) = (jac, collocated) {
                for (k, &d) in probe.dofs.iter().enumerate() {
                    let y = du[d];
                    if y != 0.0 {
                        let col = &l[k * n..(k + 1) * n];
                        rhs.iter_mut().zip(col).for_each(|(r, c)| *r += c * y);
                    }
                }
            }
            self.rotor.propagate(du, dup, rhs);
            if let (Some(dm), false) = (jac, collocated) {
                let y: Vec<f64> = probe.dofs.iter().map(|&d| rhs[d]).collect();
                for (k, y) in y.iter().enumerate().take(m) {
                    if *y != 0.0 {
                        let col = &dm[k * n..(k + 1) * n];
                        rhs.iter_mut().zip(col).for_each(|(r, c)| *r += c * y);
                    }
                }
            }
            tan.dup[j * n..(j + 1) * n].copy_from_slice(&tan.du[j * n..(j + 1) * n]);
            tan.du[j * n..(j + 1) * n].copy_from_slice(rhs);
        }
    }

    /// Collocated scheme, before the step's static contact: `L`, the derivative of the load
    /// the static forces add to the prediction over the rotor's contact DOFs at uⁿ.
    pub(super) fn probe_static(&mut self, n: usize, t: f64) -> Result<(), SolveError> {
        let Some(mut probe) = self.probe.take() else {
            return Ok(());
        };
        let kept = self.kept();
        let out = self.linearise(&mut probe, n, t, true);
        self.restore(kept);
        self.rotor.rhs.fill(0.0);
        self.probe = Some(probe);
        out
    }

    /// Forward increment, after the prediction: `D`, the derivative of the correction over
    /// the rotor's contact DOFs of the prediction.
    pub(super) fn probe_increment(&mut self, n: usize, t: f64) -> Result<(), SolveError> {
        let Some(mut probe) = self.probe.take() else {
            return Ok(());
        };
        let kept = self.kept();
        let predicted = self.rotor.u_next.clone();
        let out = self.linearise(&mut probe, n, t, false);
        self.rotor.u_next.copy_from_slice(&predicted);
        self.restore(kept);
        self.discard_stator_forces();
        self.probe = Some(probe);
        out
    }

    /// Fills `probe.jac` by differences of the step's contact solve over each contact DOF
    /// (`held`: the collocated static solve, perturbing uⁿ and reading the load; otherwise the
    /// forward increment, perturbing the prediction and reading the corrected state).
    fn linearise(
        &mut self,
        probe: &mut Probe,
        n: usize,
        t: f64,
        held: bool,
    ) -> Result<(), SolveError> {
        let (nominal, active) = self.contact_effect(held, None, n, t)?;
        probe.any = !self.ws.sel.is_empty();
        if !probe.any {
            return Ok(());
        }
        probe.stats.contact_steps += 1;
        let nr = self.rotor.n;
        for k in 0..probe.dofs.len() {
            let d = probe.dofs[k];
            // The perturbation shrunk while a side changes the active set: an event within
            // `h` of the step, not on it, is then left outside and the column is central.
            let mut h = probe.h;
            let mut sides = self.sides(held, (d, h), n, t)?;
            for _ in 0..SHRINKS {
                if sides.1 == active && sides.3 == active {
                    break;
                }
                h /= SHRINK;
                sides = self.sides(held, (d, h), n, t)?;
            }
            probe.stats.shrunk += usize::from(h < probe.h);
            let (plus, pa, minus, ma) = sides;
            let col = &mut probe.jac[k * nr..(k + 1) * nr];
            let (hi, lo, width) = match (pa == active, ma == active) {
                (true, false) => (&plus, &nominal, h),
                (false, true) => (&nominal, &minus, h),
                (both, _) => {
                    probe.stats.straddled += usize::from(!both);
                    (&plus, &minus, 2.0 * h)
                }
            };
            if (pa == active) != (ma == active) {
                probe.stats.one_sided += 1;
            }
            for ((c, a), b) in col.iter_mut().zip(hi).zip(lo) {
                *c = (a - b) / width;
            }
            if !held {
                col[d] -= 1.0; // the correction's derivative: the prediction's own share out
            }
        }
        Ok(())
    }

    /// The contact solve's effect and active set with contact DOF `d` perturbed by `+h` and by
    /// `−h` (`(d, h)`).
    fn sides(
        &mut self,
        held: bool,
        (d, h): (usize, f64),
        n: usize,
        t: f64,
    ) -> Result<Sides, SolveError> {
        let (plus, pa) = self.contact_effect(held, Some((d, h)), n, t)?;
        let (minus, ma) = self.contact_effect(held, Some((d, -h)), n, t)?;
        Ok((plus, pa, minus, ma))
    }

    /// The contact solve's effect with contact DOF `d` perturbed by `s` (`(d, s)`, none: the
    /// step as it is): the static load (held; the prediction's right-hand side) or the
    /// corrected state; and the pairs that carried force.
    fn contact_effect(
        &mut self,
        held: bool,
        perturb: Option<(usize, f64)>,
        n: usize,
        t: f64,
    ) -> Result<(Vec<f64>, Vec<usize>), SolveError> {
        self.ws.main.clear();
        self.ws.frame_pairs.clear();
        if held {
            self.rotor.rhs.fill(0.0);
            let base = perturb.map(|(d, s)| {
                let u = self.rotor.u[d];
                self.rotor.u[d] += s;
                (d, u)
            });
            let out = self.static_contact(n, t);
            if let Some((d, u)) = base {
                self.rotor.u[d] = u;
            }
            out?;
            // The static forces as `load_static_forces` adds them (torsion already in `rhs`).
            for (s, d) in self.pairs.station_dofs.iter().enumerate() {
                self.rotor.rhs[d[0]] += self.ws.main.total[s][0];
                self.rotor.rhs[d[1]] += self.ws.main.total[s][1];
            }
            let active = self.carrying();
            Ok((self.rotor.rhs.clone(), active))
        } else {
            let predicted = self.rotor.u_next.clone();
            if let Some((d, s)) = perturb {
                self.rotor.u_next[d] += s;
            }
            self.discard_stator_forces();
            let out = self.increment_contact(n, t);
            let corrected = std::mem::replace(&mut self.rotor.u_next, predicted);
            out?;
            Ok((corrected, self.carrying()))
        }
    }

    /// The candidate pairs carrying force after the last solve.
    fn carrying(&self) -> Vec<usize> {
        let ws = &self.ws;
        ws.sel
            .iter()
            .zip(&ws.pvec)
            .filter(|(_, p)| **p > 0.0)
            .map(|(c, _)| *c)
            .collect()
    }

    /// The massless stators' forces of a trial solve taken off (the forward increment's
    /// stators start each solve undeformed).
    fn discard_stator_forces(&mut self) {
        for s in self.stators.iter_mut() {
            if let StatorDyn::Massless(c) = s {
                c.discard();
            }
        }
    }

    /// The counters and instant values a trial solve changes.
    fn kept(&self) -> Kept {
        Kept {
            stats: self.stats,
            energy: self.energy,
            active: self.active,
            instant_gap: self.instant_gap,
        }
    }

    /// Puts back what [`Stepper::kept`] took and clears the trial solves' forces.
    fn restore(&mut self, k: Kept) {
        self.stats = k.stats;
        self.energy = k.energy;
        self.active = k.active;
        self.instant_gap = k.instant_gap;
        self.ws.main.clear();
        self.ws.frame_pairs.clear();
        self.ws.friction_torque = 0.0;
        self.ws.sticking = 0;
    }
}

/// What [`Stepper::kept`] keeps across trial solves.
struct Kept {
    stats: crate::time::RunStats,
    energy: f64,
    active: usize,
    instant_gap: f64,
}
