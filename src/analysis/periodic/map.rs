//! The discrete Poincaré map of shooting (`super` module docs): its runs, Newton on
//! `P(x) − x` with the variational Jacobian and central differences of whole maps where that
//! fails, and the deflation of a known root.

use super::{
    end_after, floquet, not_restarted, orbit_from, residual, restarted, Difference, Monodromy,
    FD_STEP, MAX_HALVINGS, MAX_NEWTON, SHOOT_TOLERANCE, TANGENT_STEP,
};
use crate::analysis::speed::{Prepared, SpeedResults};
use crate::error::Result;
use crate::time::{EndState, StepPlan, TangentStats};
use nalgebra::DMatrix;
use std::cell::Cell;

/// How Newton ended: the last residual, its iterations and steps.
pub(super) struct Newton {
    pub(super) converged: bool,
    pub(super) iterations: usize,
    pub(super) residual: f64,
    pub(super) steps: u64,
}

/// The discrete Poincaré map of `k` revolutions of a prepared run (module docs).
pub(super) struct Map<'a> {
    prep: &'a Prepared,
    /// `k N` steps, nothing cut.
    pub(super) plan: StepPlan,
    /// The settled end state, whose layout the vectors follow.
    pub(super) end: EndState,
    /// How the last Jacobian was taken.
    pub(super) taken: Cell<(Monodromy, Option<TangentStats>)>,
    /// Newton's Jacobians by differences of whole maps even where the step has its
    /// linearisation ([`newton_with_fallback`]).
    differences_only: Cell<bool>,
}

impl<'a> Map<'a> {
    /// The `k`-revolution map of `prep` at the step of `plan` (nothing cut), its vectors laid
    /// out as `end`.
    pub(super) fn new(prep: &'a Prepared, k: usize, plan: &StepPlan, end: EndState) -> Self {
        let steps = k * plan.steps_per_rev.max(1);
        Self::over(prep, &StepPlan { steps, ..*plan }, end)
    }

    /// The map of `plan`'s steps of `prep` (nothing cut), its vectors laid out as `end`.
    pub(super) fn over(prep: &'a Prepared, plan: &StepPlan, end: EndState) -> Self {
        Self {
            prep,
            plan: StepPlan {
                steady_from: 0,
                ..*plan
            },
            end,
            taken: Cell::new((Monodromy::FiniteDifference, None)),
            differences_only: Cell::new(false),
        }
    }

    /// `P(x)`: the state after the map's `k N` steps from `x`.
    pub(super) fn apply(&self, x: &[f64]) -> Result<Vec<f64>> {
        let start = self.end.with_state_vector(x).ok_or_else(not_restarted)?;
        end_after(self.prep, &self.plan, &start)
    }

    /// Newton on `P(x) − x` from `x` (module docs).
    pub(super) fn newton(
        &self,
        mut x: Vec<f64>,
        deflated: Option<&[f64]>,
    ) -> Result<(Vec<f64>, Newton)> {
        let per_map = self.plan.steps as u64;
        let mut steps = 0u64;
        let mut px = self.apply(&x)?;
        steps += per_map;
        let mut res = residual(&x, &px);
        // The deflated residual D(x)·res a step must lower (D = 1 without deflation).
        let weight = |x: &[f64]| deflated.map_or(1.0, |r| deflation(x, r).0);
        let mut merit = weight(&x) * res;
        let mut iterations = 0;
        while res > SHOOT_TOLERANCE && iterations < MAX_NEWTON {
            iterations += 1;
            let (m, js) = self.jacobian(&x)?;
            steps += js;
            let n = x.len();
            let a = m - DMatrix::<f64>::identity(n, n);
            let f = nalgebra::DVector::from_iterator(n, px.iter().zip(&x).map(|(p, x)| x - p));
            let Some(dx) = a.lu().solve(&f) else {
                break; // M − I singular: a multiplier at +1 (a fold); reported as not converged
            };
            let mut scale = deflated.map_or(1.0, |r| {
                let (d, grad) = deflation(&x, r);
                let g: f64 = grad.iter().zip(dx.iter()).map(|(g, d)| g * d).sum();
                1.0 / (1.0 - g / d)
            });
            if !scale.is_finite() {
                break;
            }
            let mut accepted = false;
            for _ in 0..=MAX_HALVINGS {
                let trial: Vec<f64> = x
                    .iter()
                    .zip(dx.iter())
                    .map(|(x, d)| x + scale * d)
                    .collect();
                let pt = self.apply(&trial)?;
                steps += per_map;
                let rt = residual(&trial, &pt);
                let mt = weight(&trial) * rt;
                if rt.is_finite() && mt < merit {
                    (x, px, res, merit, accepted) = (trial, pt, rt, mt, true);
                    break;
                }
                scale *= 0.5;
            }
            if !accepted {
                break;
            }
        }
        Ok((
            x,
            Newton {
                converged: res <= SHOOT_TOLERANCE,
                iterations,
                residual: res,
                steps,
            },
        ))
    }

    /// `∂P/∂x` at `x` by central differences of step `h` = [`FD_STEP`] `· max |x|` (two maps per
    /// component); and the steps it took. The map's round-off over its `k N` steps (≈ 1e-13 of
    /// `|x|`) divided by `h` bounds the entries' error: ≈ 1e-8, where forward differences at a
    /// step small enough for their truncation would give 1e-6.
    pub(super) fn jacobian(&self, x: &[f64]) -> Result<(DMatrix<f64>, u64)> {
        self.jacobian_at(x, FD_STEP)
    }

    /// `∂P/∂x` at `x`: the variational monodromy where the run's step has its linearisation
    /// ([`Map::variational`]), else [`Map::differences`] of relative step `rel`; and the steps
    /// it took.
    pub(super) fn jacobian_at(&self, x: &[f64], rel: f64) -> Result<(DMatrix<f64>, u64)> {
        if self.differences_only.get() {
            self.taken.set((Monodromy::FiniteDifference, None));
            return self.differences(x, rel, Difference::Central);
        }
        if let Some((m, stats, steps)) = self.variational(x, TANGENT_STEP)? {
            self.taken.set((Monodromy::Variational, Some(stats)));
            return Ok((m, steps));
        }
        self.taken.set((Monodromy::FiniteDifference, None));
        self.differences(x, rel, Difference::Central)
    }

    /// The variational monodromy at `x` (`time::Tangent`): one run of the map carrying the
    /// tangent of the rotor's state, each step's contact linearised with the contact DOFs
    /// perturbed by `rel · max |x|` ([`TANGENT_STEP`] when shooting); its linearisation's counters and the map's
    /// steps. `None` when the run's step has no linearisation (stators with mass, stick,
    /// dashpots, wear, abradable coatings).
    pub(super) fn variational(
        &self,
        x: &[f64],
        rel: f64,
    ) -> Result<Option<(DMatrix<f64>, TangentStats, u64)>> {
        if self.end.central_sizes().is_none_or(|s| s.len() != 1) {
            return Ok(None);
        }
        let start = self.end.with_state_vector(x).ok_or_else(not_restarted)?;
        let mut st = restarted(self.prep, &self.plan, &start)?;
        let scale = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        let h = if scale > 0.0 { rel * scale } else { 1e-9 };
        let Some(mut tan) = st.start_tangent(h) else {
            return Ok(None);
        };
        st.run_tangent_to(self.plan.steps, &mut tan)?;
        let (n, m) = (x.len(), tan.matrix());
        if m.len() != n * n {
            return Ok(None);
        }
        let stats = st.tangent_stats();
        Ok(Some((
            DMatrix::from_column_slice(n, n, &m),
            stats,
            self.plan.steps as u64,
        )))
    }

    /// `∂P/∂x` at `x` by differences (`kind`) of whole maps of relative step `rel` of
    /// `max |x|` (two maps per component, one and the map at `x` one-sided); and the steps
    /// they took.
    pub(super) fn differences(
        &self,
        x: &[f64],
        rel: f64,
        kind: Difference,
    ) -> Result<(DMatrix<f64>, u64)> {
        let n = x.len();
        let h = rel * x.iter().fold(0.0_f64, |m, v| m.max(v.abs())).max(1e-300);
        let mut m = DMatrix::<f64>::zeros(n, n);
        let centre = match kind {
            Difference::Central => None,
            _ => Some(self.apply(x)?),
        };
        let shifted = |j: usize, by: f64| {
            let mut y = x.to_vec();
            y[j] += by;
            self.apply(&y)
        };
        for j in 0..n {
            let (hi, lo, w) = match (kind, &centre) {
                (Difference::Forward, Some(c)) => (shifted(j, h)?, c.clone(), h),
                (Difference::Backward, Some(c)) => (c.clone(), shifted(j, -h)?, h),
                _ => (shifted(j, h)?, shifted(j, -h)?, 2.0 * h),
            };
            for i in 0..n {
                m[(i, j)] = (hi[i] - lo[i]) / w;
            }
        }
        let maps = if centre.is_some() { n + 1 } else { 2 * n };
        Ok((m, (maps * self.plan.steps) as u64))
    }

    /// The Floquet multipliers at `x`, largest modulus first.
    pub(super) fn multipliers(&self, x: &[f64]) -> Result<(Vec<[f64; 2]>, u64)> {
        let (m, steps) = self.jacobian(x)?;
        Ok((floquet(&m), steps))
    }

    /// The orbit from `x` over `6 k` revolutions, analysed as a steady window.
    pub(super) fn orbit(&self, x: &[f64], k: usize) -> Result<(SpeedResults, u64)> {
        let start = self.end.with_state_vector(x).ok_or_else(not_restarted)?;
        let orbit = orbit_from(self.prep, &self.plan, &start, k)?;
        let steps = orbit.stats.steps as u64;
        Ok((orbit, steps))
    }
}

/// Newton on `map` from `x0` with the variational Jacobian; where it does not converge and
/// the Jacobians were variational, Newton again from `x0` with central differences of whole
/// maps. Near a kink of the map (a grazing: the orbit's contact about to begin or end) the
/// variational Jacobian is the derivative of the side the iterate is on, and Newton may cycle
/// between the sides; the differences straddle the kink and take Newton across it. The
/// steps are both Newtons'.
pub(super) fn newton_with_fallback(
    map: &Map<'_>,
    x0: Vec<f64>,
    deflated: Option<&[f64]>,
) -> Result<(Vec<f64>, Newton)> {
    let (x, first) = map.newton(x0.clone(), deflated)?;
    if first.converged || map.taken.get().0 != Monodromy::Variational {
        return Ok((x, first));
    }
    map.differences_only.set(true);
    let again = map.newton(x0, deflated);
    map.differences_only.set(false);
    let (x, mut second) = again?;
    second.steps += first.steps;
    Ok((x, second))
}

/// The deflation `D(x) = 1/d² + 1`, `d = ‖x − r‖₂ / max |r|`, and its gradient ∇D (for
/// [`super::solve_deflated`]).
fn deflation(x: &[f64], r: &[f64]) -> (f64, Vec<f64>) {
    let scale = r.iter().fold(0.0_f64, |m, v| m.max(v.abs())).max(1e-300);
    let d2 = x
        .iter()
        .zip(r)
        .map(|(a, b)| ((a - b) / scale).powi(2))
        .sum::<f64>()
        .max(1e-300);
    let grad = x
        .iter()
        .zip(r)
        .map(|(a, b)| -2.0 * (a - b) / (scale * scale * d2 * d2))
        .collect();
    (1.0 / d2 + 1.0, grad)
}
