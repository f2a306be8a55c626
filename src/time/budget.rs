//! What a run will cost, estimated before it starts: steps, memory and wall time.
//!
//! The refusals live in [`super::plan::plan_steps`] (steps above `run.max_steps`, a record
//! above [`super::plan::MAX_RECORD_BYTES`]); this module only states the figures, for `rubsim
//! check` and before `run`/`sweep`.
//!
//! The time is an *estimate* from a per-step cost model calibrated on the development machine
//! (2 cores; docs/PERFORMANCE.md):
//! `t_step ≈ NS_STEP + NS_ROTOR_DOF·n_rotor + NS_STATOR_DOF·n_mass + NS_CONTACT_MESH·n_meshed`,
//! with `n_rotor` the rotor's DOFs, `n_mass` the DOFs of stators with mass and `n_meshed` the
//! massless meshed stators (their contact solve costs what its pairs hold, not what the mesh
//! holds), plus once per run the massless stators' compliance columns,
//! `NS_FACTOR_ENTRY·nnz(L)·n_contact` (every contact DOF counted), or for factors computed from
//! elimination-tree paths (`compliance::PATH_COLUMNS_NNZ`) `NS_PATH_FLOP` times the paths'
//! forward and product flops (`linalg::PathCost`), their stored forward solutions counted in
//! the memory. A stator reduced by
//! Craig–Bampton (`[run.reduction] stators = true`) counts by its r reduced DOFs, not by its
//! mesh: `NS_STATOR_DOF·r + NS_DENSE_ENTRY·r²` (its operators are dense r × r). It ignores how often the rotor is in contact, so the true
//! time may differ by a factor of a few either way.

use super::plan::{sample_bytes, StepPlan, WINDOW_MULTIPLE};
use crate::model::{Case, Model, StatorModel, StatorPlan};
/// How byte counts and durations are written (shared with the scene's size limits).
pub use crate::scene::validate::checks::{bytes, duration};
use serde::Serialize;

/// Fixed cost of a step (ns): the Jeffcott rotor with a massless rod, 0.1 µs per step.
pub const NS_STEP: f64 = 100.0;
/// Cost per rotor DOF and step (ns): a 204-DOF FE rotor steps in 3.4 µs.
pub const NS_ROTOR_DOF: f64 = 17.0;
/// Cost per DOF of a stator with mass and step (ns): 25–36 ns per DOF for meshed stators.
pub const NS_STATOR_DOF: f64 = 30.0;
/// Cost per entry of a reduced stator's dense r × r operators and step (ns): the step's
/// products with K_r, C_r and the solve with the factored operator (81 µs of CPU a step at
/// r = 256, the annulus with mass at h = 3 mm: docs/PERFORMANCE.md).
pub const NS_DENSE_ENTRY: f64 = 1.1;
/// Cost per step of a massless meshed stator (more than [`super::EAGER_DOFS`] contact DOFs)
/// in contact (ns): its broad phase, the flexibility blocks of the pairs entering the contact
/// problem and the complementarity solve, which grow with the pairs in contact, not with the
/// mesh — about 40–60 µs for the 3-D labyrinth seal in full annular rub (≈ 36 pairs selected,
/// docs/PERFORMANCE.md §12); a few contact DOFs (a rod, a ring) are part of [`NS_STEP`].
pub const NS_CONTACT_MESH: f64 = 50_000.0;
/// Cost per entry of a massless stator's Cholesky factor and compliance column (ns): a column
/// is one blocked forward and back solve, computed once per contact DOF that touches and kept
/// for the stator's later runs; the estimate counts every contact DOF.
pub const NS_FACTOR_ENTRY: f64 = 0.5;

/// Cost per flop of the compliance columns from elimination-tree paths (ns): the forward
/// solves of the contact DOFs and the products among them ([`crate::linalg::PathCost`]),
/// dense triangular solves and matrix products over the paths' supernodes.
pub const NS_PATH_FLOP: f64 = 0.05;

/// A run's own compliance columns ([`column_bytes`]) above this many bytes make the runs of
/// a sweep, a study and the step choice's pilots go one at a time ([`one_at_a_time`]): a run
/// adopts the columns the stator's earlier runs handed back when it starts and hands its own
/// back when it ends, so runs side by side would each compute and hold every column (the
/// 10⁶-DOF seal's pilots peaked at 9.89 GB, 1.8 × a run's, side by side; one at a time, the
/// later runs start with the first one's columns). The time loops then run on one thread and
/// the columns' solves on all of them.
pub const SHARED_COLUMNS_BYTES: f64 = 5.0e8;

/// Bytes of compliance columns one run of the stator `s` may compute and hold by itself,
/// every contact DOF touched (0 for a stator with mass): its packed compliance (16 bytes per
/// pair of contact nodes, [`StatorModel::packed_compliance_bytes`]) and, for columns from
/// elimination-tree paths, the forward solutions kept ([`crate::linalg::PathCost`]) with the
/// room their chunks are allocated with ([`PATH_CHUNK_ROOM`]).
pub fn column_bytes(s: &StatorModel) -> f64 {
    if s.massless() {
        stator_columns(s).0
    } else {
        0.0
    }
}

/// The memory of path forward solutions allocated per byte held: their chunks are allocated
/// for up to a quarter more columns than they hold (`linalg::PathStore`).
pub const PATH_CHUNK_ROOM: f64 = 1.25;

/// A massless stator's [`column_bytes`] and, when its columns come from elimination-tree
/// paths, their cost.
fn stator_columns(s: &StatorModel) -> (f64, Option<crate::linalg::PathCost>) {
    let path = super::compliance::path_cost(s);
    let stored = path
        .as_ref()
        .map_or(0.0, |p| PATH_CHUNK_ROOM * 8.0 * p.stored_entries);
    (s.packed_compliance_bytes() + stored, path)
}

/// Whether the runs of `model` go one at a time: the columns of its meshed stators (the ones
/// shared between runs, assembled once) could exceed [`SHARED_COLUMNS_BYTES`].
pub fn one_at_a_time(model: &Model) -> bool {
    at_once(meshed_column_bytes(model)) == 1
}

/// The [`column_bytes`] of `model`'s meshed stators (assembled once, their columns shared
/// between runs).
pub fn meshed_column_bytes(model: &Model) -> f64 {
    model
        .stators
        .iter()
        .filter_map(|p| match p {
            StatorPlan::Mesh { model, .. } => Some(column_bytes(model)),
            _ => None,
        })
        .sum()
}

/// How many runs hold their own columns at once, `meshed` the [`column_bytes`] of the meshed
/// stators: one when the runs go one at a time (above [`SHARED_COLUMNS_BYTES`]), else the
/// worker threads (rayon's).
fn at_once(meshed: f64) -> usize {
    if meshed > SHARED_COLUMNS_BYTES {
        1
    } else {
        rayon::current_num_threads().max(1)
    }
}

/// Up-front estimate of one run at one speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Budget {
    /// Steps of the main run.
    pub steps: f64,
    /// Steps of the error-estimate companion runs (0 without them; [`companion_steps`]).
    pub companion_steps: f64,
    /// Bytes of the record (main run).
    pub record_bytes: f64,
    /// Bytes of the matrices, factors and compliance columns the loop holds (an upper bound:
    /// a massless stator's compliance among every contact DOF, `8·n_c(n_c+1)/2`, and its
    /// path columns' forward solutions, once per run that holds its own at once: one when
    /// runs go one at a time, [`one_at_a_time`], else one per worker thread).
    pub matrix_bytes: f64,
    /// Estimated cost of one step (s).
    pub step_s: f64,
    /// Estimated wall time of the run, companion included (s), on one core.
    pub wall_s: f64,
}

/// Revolutions the finer companion runs after its restart from the run's end state before its
/// analysed window (at most the run's own transient): the restart's error, of the size of the
/// two steps' difference, decays with the orbit's damping over them (docs/VALIDATION.md §15).
/// The run path (`analysis::speed`) and this budget both count them from here.
pub const FINE_SETTLE_REVOLUTIONS: usize = 16;

/// Steps of the error estimate's companion runs for a run of `plan`, as the run path takes them
/// for a steady periodic response of period 1 (`analysis::speed`; the window analysed is
/// `w = min(W, 6)` revolutions, W the plan's window, T its transient):
///
/// - the first companion at about 2Δt over `T + w` revolutions, with `⌈k/2⌉` steps per
///   recorded sample (`k` the plan's), about half the run's steps per revolution; where that
///   step is not coarser (`k` = 1) or above the explicit stability limit of a plan within it,
///   at Δt/2 instead: `2 × (T + w)` revolutions' worth of the run's steps;
/// - with `rub` (a case with stators, which may touch) and a coarser first companion, the
///   finer one at Δt/2 restarted from the run's end: `min(16, T) + w` revolutions at twice the
///   run's steps per revolution (a response that is not periodic runs one at about 4Δt over the
///   whole window instead, fewer steps).
///
/// An estimate before the run: at speeds without contact the finer one is not run, and a window
/// that is not periodic is longer.
pub fn companion_steps(plan: &StepPlan, rub: bool) -> f64 {
    let spr = plan.steps_per_rev.max(1);
    let k = plan.record_every.max(1);
    let samples = (spr / k) as f64;
    let transient = (plan.steady_from / spr) as f64;
    let w = ((plan.steps.saturating_sub(plan.steady_from) / spr).min(WINDOW_MULTIPLE)) as f64;
    let kc = k.div_ceil(2);
    let dt_c = plan.dt * k as f64 / kc as f64;
    let coarser = kc < k && (dt_c <= plan.limit || plan.dt > plan.limit);
    if !coarser {
        return (transient + w) * 2.0 * spr as f64;
    }
    let first = (transient + w) * samples * kc as f64;
    let fine = if rub {
        (transient.min(FINE_SETTLE_REVOLUTIONS as f64) + w) * 2.0 * spr as f64
    } else {
        0.0
    };
    first + fine
}

/// What may lengthen a run past its plan (`analysis::speed`), for [`step_bounds`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lengthening {
    /// A fixed window (`run.duration`): nothing lengthens it.
    pub fixed: bool,
    /// Most transient revolutions while waiting for the steady state
    /// (`run.max_transient_revolutions`).
    pub max_transient_revolutions: usize,
    /// Most revolutions a window that is not periodic is lengthened to: `run.classify_revolutions`,
    /// doubled while its 0–1 test is undetermined (`analysis::lengthen`: the caller passes
    /// `run.classify_revolutions × analysis::MAX_CLASSIFY_FACTOR`).
    pub classify_revolutions: usize,
    /// The error estimate's companions are run (`run.error_estimate`).
    pub error_estimate: bool,
    /// The coexistence check's companion is run (`run.check_coexistence`).
    pub coexistence: bool,
    /// Most steps one run may take (`run.max_steps`): every lengthening stops there.
    pub max_steps: u64,
}

/// Steps of one run at one speed before it starts: what its plan takes and the most any
/// lengthening may take ([`step_bounds`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StepBounds {
    /// Steps planned: the run's plan and the companions a steady period-1 response takes
    /// ([`companion_steps`]); with a fixed window, the companions' most.
    pub planned: f64,
    /// Most steps of the run itself: the transient at `max_transient_revolutions` and the
    /// window at `classify_revolutions`, within `max_steps`.
    pub run_most: f64,
    /// Most steps of the error estimate's companions over that longest run.
    pub companions_most: f64,
    /// Most steps of the coexistence check's companion.
    pub coexistence_most: f64,
    /// `run_most + companions_most + coexistence_most`: at least `planned`.
    pub most: f64,
}

/// Longest window (revolutions) a companion of a periodic response analyses: lcm(6, period)
/// for a period up to 8 (lcm(6, 7)).
const LONGEST_REPEAT: usize = 42;

/// The steps of a run of `plan`: as planned, and the most once every lengthening is at its cap
/// (`l`; `rub`: the case has stators, so the companions of a rub may run). The run's most is
/// `(T_max + max(W, classify)) × steps/rev` within `max_steps` (T_max = max(T,
/// `max_transient_revolutions`), W the planned window); its companions' most is the first
/// companion over that whole run (at about 2Δt, or Δt/2 where 2Δt is not coarser or not stable)
/// and, at a rub, the larger of the Δt/2 companion restarted from the end (`min(16, T_max)` +
/// 42 revolutions at twice the steps per revolution) and the 4Δt one over the whole run; the
/// coexistence check's companion at most `T_max + max(W, 42, classify)` revolutions at the
/// run's step (it settles as the run does and a window of it that is not periodic is
/// lengthened as the run's is, `analysis::RunRequest::coexistence`).
/// A fixed window takes its plan only: the run, the companions over the same window (no
/// Δt/2 restart) and no coexistence check — planned and most agree.
pub fn step_bounds(plan: &StepPlan, l: &Lengthening, rub: bool) -> StepBounds {
    let spr = plan.steps_per_rev.max(1);
    let k = plan.record_every.max(1);
    let kc = k.div_ceil(2);
    let coarser = kc < k && (plan.dt * k as f64 / kc as f64 <= plan.limit || plan.dt > plan.limit);
    let samples = (spr / k) as f64;
    // The companions over a run of `steps`, `t` revolutions of transient; `fine`: the Δt/2
    // restart may run.
    let companions = |steps: f64, t: f64, fine: bool| -> f64 {
        if !l.error_estimate {
            return 0.0;
        }
        let revs = steps / spr as f64;
        if !coarser {
            return 2.0 * steps;
        }
        let first = revs * samples * kc as f64;
        let fine = if fine {
            (t.min(FINE_SETTLE_REVOLUTIONS as f64) + LONGEST_REPEAT as f64) * 2.0 * spr as f64
        } else {
            0.0
        };
        let coarse = revs * samples * kc.div_ceil(2) as f64;
        first + if rub { fine.max(coarse) } else { 0.0 }
    };
    let steps = plan.steps as f64;
    if l.fixed {
        let c = companions(steps, 0.0, false);
        return StepBounds {
            planned: steps + c,
            run_most: steps,
            companions_most: c,
            coexistence_most: 0.0,
            most: steps + c,
        };
    }
    let t = plan.steady_from / spr;
    let w = plan.steps.saturating_sub(plan.steady_from).div_ceil(spr);
    let t_max = l.max_transient_revolutions.max(t);
    let cap = (l.max_steps as f64).max(steps);
    let run_most = (((t_max + w.max(l.classify_revolutions)) * spr) as f64).min(cap);
    let companions_most = companions(run_most, t_max as f64, true);
    let coexistence_most = if l.coexistence && rub {
        let window = w.max(LONGEST_REPEAT).max(l.classify_revolutions);
        (((t_max + window) * spr) as f64).min(cap)
    } else {
        0.0
    };
    let planned = steps
        + if l.error_estimate {
            companion_steps(plan, rub)
        } else {
            0.0
        };
    let most = run_most + companions_most + coexistence_most;
    StepBounds {
        planned,
        run_most,
        companions_most,
        coexistence_most,
        most: most.max(planned),
    }
}

/// Estimates the cost of running `case` with `plan` (`companion`: with the error estimate's
/// companion runs, [`companion_steps`]).
pub fn estimate(case: &Case, plan: &StepPlan, companion: bool) -> Budget {
    let n_rotor = case.loop_rotor().ndof as f64;
    let mut n_mass = 0.0;
    let mut n_meshed = 0.0;
    let mut columns_s = 0.0;
    let mut n_dense = 0.0;
    // Sparse matrices: about 12 bytes per stored entry (value and row index), six of them per
    // body (M, K, C and the step operators); a massless stator's factor and packed compliance
    // below.
    let mut matrix_bytes = 6.0 * 12.0 * 20.0 * n_rotor;
    let (mut columns_bytes, mut meshed_bytes) = (0.0, 0.0);
    for s in &case.stators {
        let nnz = (s.k.nnz() + s.m.nnz() + s.c.nnz()) as f64;
        matrix_bytes += 2.0 * 12.0 * nnz;
        if s.massless() {
            let nc = s.contact_dofs().len() as f64;
            if nc > super::EAGER_DOFS as f64 {
                n_meshed += 1.0;
            }
            // The factor of K (a meshed stator's, factored when the model was built; an
            // estimate of 30 entries per DOF otherwise) and the columns, below.
            let nnz_l = s.factor_nnz().map_or(30.0 * s.ndof as f64, |n| n as f64);
            matrix_bytes += 8.0 * nnz_l;
            let (bytes, path) = stator_columns(s);
            columns_bytes += bytes;
            if s.mesh.is_some() {
                meshed_bytes += bytes;
            }
            match path {
                Some(p) => {
                    columns_s += NS_PATH_FLOP * 1e-9 * (p.forward_flops + p.product_flops);
                }
                None => columns_s += NS_FACTOR_ENTRY * 1e-9 * nnz_l * nc,
            }
        } else if let Some(r) = &s.reduced {
            // The loop holds the reduced body (dense M_r, C_r, K_r, the step operator and its
            // factor), the fixed-interface modes Φ (n_I × modes) and the factor of K_II for
            // the frames' whole field (about the stiffness's entries, counted above).
            let rd = r.rdof() as f64;
            n_mass += rd;
            n_dense += rd * rd;
            matrix_bytes += 5.0 * 8.0 * rd * rd + 8.0 * (r.interior.len() * r.modes.len()) as f64;
        } else {
            n_mass += s.ndof as f64;
        }
    }
    // The compliance among every contact DOF touched (packed, 8·n_c(n_c+1)/2 bytes) and the
    // forward solutions of path columns, held by each run side by side until it ends.
    matrix_bytes += columns_bytes * at_once(meshed_bytes) as f64;
    let step_s = (NS_STEP
        + NS_ROTOR_DOF * n_rotor
        + NS_STATOR_DOF * n_mass
        + NS_DENSE_ENTRY * n_dense
        + NS_CONTACT_MESH * n_meshed)
        * 1e-9;
    let steps = plan.steps as f64;
    let companion_steps = if companion {
        companion_steps(plan, !case.stators.is_empty())
    } else {
        0.0
    };
    let samples = (plan.steps / plan.record_every.max(1)) as f64 + 1.0;
    Budget {
        steps,
        companion_steps,
        record_bytes: samples * sample_bytes(case.stations.len()),
        matrix_bytes,
        step_s,
        wall_s: step_s * (steps + companion_steps) + columns_s,
    }
}

impl Budget {
    /// One line for the user: steps, memory and the time estimate.
    pub fn describe(&self) -> String {
        format!(
            "{:.3e} steps{}, record {}, matrices ≤ {}, ≈ {} on one core (estimate: {:.2} µs/step from a cost model)",
            self.steps,
            if self.companion_steps > 0.0 {
                format!(" (+ {:.3e} companion)", self.companion_steps)
            } else {
                String::new()
            },
            bytes(self.record_bytes),
            bytes(self.matrix_bytes),
            duration(self.wall_s),
            self.step_s * 1e6
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(spr: usize, k: usize, revs: usize, transient: usize, dt: f64, limit: f64) -> StepPlan {
        StepPlan {
            dt,
            steps_per_rev: spr,
            steps: revs * spr,
            record_every: k,
            steady_from: transient * spr,
            limit,
            rule_dt: dt,
            omega_max: 1.0,
        }
    }

    /// The paper's run (220 revolutions, 100 of transient, 64 samples of 10 steps): the 2Δt
    /// companion takes (100 + 6) × 64 × 5 steps, a quarter of the run's, and the finer one at a
    /// rub (16 + 6) × 1280, a fifth — not the half run counted before.
    #[test]
    fn companions_are_counted_as_the_run_path_takes_them() {
        let p = plan(640, 10, 220, 100, 1e-5, 1.0);
        let main = p.steps as f64;
        let c = companion_steps(&p, false);
        assert_eq!(c, 106.0 * 320.0);
        assert!((c / main - 0.241).abs() < 1e-3, "{}", c / main);
        assert_eq!(companion_steps(&p, true), 106.0 * 320.0 + 22.0 * 1280.0);
        // An odd number of steps per sample: ⌈3/2⌉ = 2, a ratio of 1.5, not 2.
        assert_eq!(
            companion_steps(&plan(192, 3, 220, 100, 1e-5, 1.0), false),
            106.0 * 128.0
        );
        // One step per sample, or 2Δt above the explicit limit: the companion is at Δt/2.
        assert_eq!(
            companion_steps(&plan(64, 1, 220, 100, 1e-5, 1.0), true),
            106.0 * 128.0
        );
        assert_eq!(
            companion_steps(&plan(640, 10, 220, 100, 1e-5, 1.5e-5), true),
            106.0 * 1280.0
        );
        // Every lengthening at its cap: the transient to 500, the window to 400 revolutions,
        // within max_steps; a fixed window takes its plan, planned and most the same.
        let mut l = Lengthening {
            fixed: false,
            max_transient_revolutions: 500,
            classify_revolutions: 400,
            error_estimate: false,
            coexistence: false,
            max_steps: 1_000_000_000,
        };
        let b = step_bounds(&p, &l, true);
        assert_eq!(b.planned, main);
        assert_eq!(b.run_most, 900.0 * 640.0);
        assert_eq!(b.most, b.run_most);
        l.max_steps = 300_000;
        assert_eq!(step_bounds(&p, &l, true).run_most, 300_000.0);
        l.error_estimate = true;
        l.coexistence = true;
        let b = step_bounds(&p, &l, true);
        assert!(
            b.companions_most >= 300_000.0 / 2.0 && b.coexistence_most > 0.0,
            "{b:?}"
        );
        assert_eq!(b.most, b.run_most + b.companions_most + b.coexistence_most);
        // The coexistence companion settles as the run does and its window is lengthened as
        // the run's is: up to 500 + 400 revolutions.
        let wide = Lengthening {
            max_steps: 1_000_000_000,
            ..l
        };
        assert_eq!(step_bounds(&p, &wide, true).coexistence_most, 900.0 * 640.0);
        l.fixed = true;
        let b = step_bounds(&p, &l, true);
        assert_eq!((b.planned, b.most, b.run_most), (b.most, b.planned, main));
        assert_eq!(b.companions_most, 220.0 * 64.0 * 5.0 + 220.0 * 64.0 * 3.0);
        // A short transient settles the finer companion over it only.
        assert_eq!(
            companion_steps(&plan(640, 10, 30, 10, 1e-5, 1.0), true),
            16.0 * 320.0 + 16.0 * 1280.0
        );
    }
}
