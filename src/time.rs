//! Explicit central differences with forward-increment Lagrange multipliers (paper Sec. 2.5).
//!
//! Each step (Eqs. 34–47):
//! 1. predict every body with λ = 0: `M̃ u*ⁿ⁺¹ = f̃ⁿ`, `M̃ = M/Δt² + C/(2Δt)`,
//!    `f̃ⁿ = fⁿ + (2M/Δt² − K) uⁿ + (C/(2Δt) − M/Δt²) uⁿ⁻¹` (Eqs. 35–36);
//! 2. freeze `n`, `a` of every candidate pair at the prediction and compute the gaps `g*`;
//! 3. solve the complementarity problem `p ≥ 0`, `g* + W p ≥ 0`, `pᵀ(g* + W p) = 0` with
//!    `W = G_N M̃⁻¹ G_NTᵀ` summed over the bodies in the pair (Eq. 45, with sign handling);
//! 4. correct `uⁿ⁺¹ = u* + M̃⁻¹ G_NTᵀ p` (Eq. 47, compression-positive `p`).
//!
//! Massless stators (Eq. 49) are undeformed at the start of the step and enter `W` through
//! their compliance `K⁻¹` on the contact DOFs, computed once per run.
//!
//! The [`IntegratorKind::Collocated`] variant solves the massless stators' contact at tₙ with
//! the rotor held at uⁿ (a static complementarity problem on the stator compliance) and applies
//! that force in the central-difference step — second order, but explicit in the stator
//! stiffness, so its stable step is `2/ω_c`, `ω_c = √((k_r + k_s)/m)`.
//!
//! The loop allocates nothing: every buffer lives in the workspace built before it, and the
//! recorder is sized for the whole run.

use crate::contact::lcp::{self, LcpWorkspace};
use crate::contact::search::BroadPhase;
use crate::contact::{exact_gap, pair_state, target_disp, Candidate, PairState};
use crate::error::SolveError;
use crate::linalg::{Csc, PairCsr, StepLu};
use crate::math::V2;
use crate::model::{Case, StatorModel};
use crate::scene::IntegratorKind;
use std::f64::consts::PI;
use std::time::Instant;

/// Time-step choices of a run.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct StepPlan {
    /// Time step (s).
    pub dt: f64,
    /// Steps per revolution (an integer multiple of `samples_per_rev`).
    pub steps_per_rev: usize,
    /// Total steps.
    pub steps: usize,
    /// Record every this many steps.
    pub record_every: usize,
    /// Explicit stability limit (s).
    pub limit: f64,
    /// The paper's rule Δt = min(T_min/(32n), 2π/(32nω)) (s).
    pub rule_dt: f64,
    /// Highest frequency of the system including contact stiffness (rad/s).
    pub omega_max: f64,
}

/// Parameters of a run that fix the step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepParams {
    /// Integrator.
    pub integrator: IntegratorKind,
    /// Override Δt (s).
    pub dt: Option<f64>,
    /// Paper rule's n.
    pub harmonics: f64,
    /// Total revolutions.
    pub revolutions: usize,
    /// Recorded samples per revolution.
    pub samples_per_rev: usize,
}

/// Contact stiffness bound (N/m) per station, from massless (`massless = true`) or all stators.
fn station_contact_stiffness(case: &Case, massless_only: bool) -> Vec<f64> {
    let mut k = vec![0.0; case.stations.len()];
    for s in &case.stators {
        if !massless_only || s.massless() {
            // A stator facing several stations (3-D meshes) bounds each of them.
            let kb = s.contact_stiffness_bound();
            for st in s.stations() {
                k[st] += kb;
            }
        }
    }
    k
}

/// Chooses Δt: the paper's rule (Sec. 3) with T_min = 2π/ω_c, ω_c the highest frequency of the
/// rotor with every stator's contact stiffness added, capped by the explicit stability limit of
/// what enters the loop with mass (and, for the collocated integrator, the massless stators'
/// contact stiffness), or the user's override checked against that limit. Δt is then reduced
/// so a revolution holds a whole number of recorded samples and steps.
pub fn plan_steps(case: &Case, p: &StepParams) -> Result<StepPlan, SolveError> {
    let m = case.rotor_mass;
    let kr = case.rotor_stiffness;
    let xi = case.rotor_xi_max;
    let k_all = station_contact_stiffness(case, false);
    let k_ml = station_contact_stiffness(case, true);
    // Contact frequency of the reference (Jeffcott-equivalent) system, √((k_r + k_s)/m_r):
    // the T_min of the paper's rule. FE rotors' own high modes only bound stability.
    let w_contact = k_all
        .iter()
        .map(|k| ((kr + k) / m).sqrt())
        .fold(case.speed_ratio.recip() * case.omega, f64::max);
    let w_stators = case
        .stators
        .iter()
        .map(|s| s.omega_max_sq_bound().sqrt())
        .fold(0.0, f64::max);
    let omega_max = w_contact.max(w_stators);
    // Stability: CD with implicit viscous damping, Δt ≤ (2/ω)(√(1+ξ²) − ξ).
    let lim = |w: f64, z: f64| 2.0 / w * ((1.0 + z * z).sqrt() - z);
    let mut limit = lim(case.rotor_omega_max, xi.min(1.0));
    let mut reason = format!("free rotor, ω = {:.4e} rad/s", case.rotor_omega_max);
    if w_stators > 0.0 {
        let l = lim(w_stators, 0.0);
        if l < limit {
            limit = l;
            reason = format!("stator with mass, ω ≤ {w_stators:.4e} rad/s");
        }
    }
    if p.integrator == IntegratorKind::Collocated {
        for (s, k) in k_ml.iter().enumerate() {
            if *k > 0.0 {
                // Weyl bound: ω² ≤ ω_max,rotor² + k_s (M⁻¹)_ii at the station node (exact
                // for the Jeffcott rotor: (k_r + k_s)/m).
                let w = (case.rotor_omega_max.powi(2) + k * case.station_inv_mass[s]).sqrt();
                let l = lim(w, (xi * case.rotor_omega_max / w).min(1.0));
                if l < limit {
                    limit = l;
                    reason = format!(
                        "massless stator stiffness applied explicitly, ω_c ≤ √(ω_max² + k_s (M⁻¹)_ii) = {w:.4e} rad/s"
                    );
                }
            }
        }
    }
    // T_min of the paper's rule: the shortest period the response is made of — rotor modes and
    // the contact frequency. Internal modes of stators with mass only bound stability (below).
    let t_min = 2.0 * PI / w_contact;
    let rule_dt = (t_min / (32.0 * p.harmonics)).min(2.0 * PI / (32.0 * p.harmonics * case.omega));
    let dt0 = match p.dt {
        Some(dt) => {
            if dt > limit {
                return Err(SolveError::StepTooLarge {
                    dt,
                    limit,
                    integrator: p.integrator.name().into(),
                    reason,
                });
            }
            dt
        }
        None => rule_dt.min(0.8 * limit),
    };
    let t_rev = 2.0 * PI / case.omega;
    let spr = p.samples_per_rev;
    let per_sample = (t_rev / (dt0 * spr as f64) - 1e-9).ceil().max(1.0) as usize;
    let steps_per_rev = per_sample * spr;
    Ok(StepPlan {
        dt: t_rev / steps_per_rev as f64,
        steps_per_rev,
        steps: steps_per_rev * p.revolutions,
        record_every: per_sample,
        limit,
        rule_dt,
        omega_max,
    })
}

/// What the run keeps: rotor-station displacements and contact forces on the rotor, every
/// `every` steps, plus the massless stators' elastic energy.
#[derive(Debug, Clone, Default)]
pub struct Record {
    /// Number of stations.
    pub nstations: usize,
    /// Sample times (s).
    pub t: Vec<f64>,
    /// Station displacements `[x, y]` per sample and station (m), sample-major.
    pub disp: Vec<V2>,
    /// Displacement `[x, y]` of the observed node ([`Case::observed_node`]) per sample (m).
    pub observed: Vec<V2>,
    /// Total contact force on each station `[Fx, Fy]` (N), sample-major.
    pub force: Vec<V2>,
    /// Normal part of the contact force on each station (N), sample-major.
    pub force_normal: Vec<V2>,
    /// Elastic energy stored in massless stators (J) per sample.
    pub stator_energy: Vec<f64>,
    /// Active pairs per sample.
    pub active: Vec<u32>,
}

impl Record {
    fn with_capacity(nstations: usize, samples: usize) -> Self {
        Self {
            nstations,
            t: Vec::with_capacity(samples),
            disp: Vec::with_capacity(samples * nstations),
            observed: Vec::with_capacity(samples),
            force: Vec::with_capacity(samples * nstations),
            force_normal: Vec::with_capacity(samples * nstations),
            stator_energy: Vec::with_capacity(samples),
            active: Vec::with_capacity(samples),
        }
    }
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }
    /// True when nothing was recorded.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }
    /// Displacement of station `s` at sample `i`.
    pub fn disp_at(&self, i: usize, s: usize) -> V2 {
        self.disp[i * self.nstations + s]
    }
    /// Contact force on station `s` at sample `i`.
    pub fn force_at(&self, i: usize, s: usize) -> V2 {
        self.force[i * self.nstations + s]
    }
}

/// Counters of a finished run.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize)]
pub struct RunStats {
    /// Steps taken.
    pub steps: usize,
    /// Wall time of the loop (s).
    pub wall_s: f64,
    /// Most negative gap after correction over the run (m); ≥ 0 means no penetration.
    pub min_gap: f64,
    /// Largest number of simultaneously active pairs.
    pub max_active: usize,
    /// Steps with at least one active pair.
    pub contact_steps: usize,
    /// Total principal pivots of the complementarity solves.
    pub pivots: usize,
}

/// M̃⁻¹ of a body with mass.
#[derive(Debug)]
enum MInv {
    Diag(Vec<f64>),
    Lu {
        lu: Box<StepSolver>,
        /// Columns M̃⁻¹ e_d for contact DOFs, column-major n × ncd.
        cols: Vec<f64>,
        col_of: Vec<usize>,
    },
}

/// The factored M̃: sparse LU, or sparse LU plus the Woodbury correction of a low-rank
/// damping term (modal damping).
#[derive(Debug)]
enum StepSolver {
    /// Block-tridiagonal LU in 4 × 4 node blocks (shaft models without pedestal, axial or
    /// torsional DOFs).
    Block(crate::linalg::BlockTridiag),
    /// General sparse LU with pivoting (faer).
    Sparse(StepLu),
    LowRank(crate::linalg::WoodburyLu),
}

impl StepSolver {
    fn solve_in_place(&mut self, b: &mut [f64]) {
        match self {
            StepSolver::Block(lu) => lu.solve_in_place(b),
            StepSolver::Sparse(lu) => lu.solve_in_place(b),
            StepSolver::LowRank(w) => w.solve_in_place(b),
        }
    }
}

/// A body with mass, integrated explicitly.
#[derive(Debug)]
struct DynBody {
    n: usize,
    /// `A = 2M/Δt² − K` and `B = C/(2Δt) − M/Δt²` on one pattern.
    ab: PairCsr,
    minv: MInv,
    u_prev: Vec<f64>,
    u: Vec<f64>,
    u_next: Vec<f64>,
    rhs: Vec<f64>,
}

impl DynBody {
    /// `low`: an optional low-rank damping term added to `c` (M̃ then gets a Woodbury solve).
    fn new(
        m: &Csc,
        c: &Csc,
        k: &Csc,
        low: Option<&crate::linalg::LowRank>,
        dt: f64,
        contact_dofs: &[usize],
    ) -> Result<Self, String> {
        let n = m.nrows();
        let aop = Csc::lin_comb(2.0 / (dt * dt), m, -1.0, k);
        let bop = Csc::lin_comb(1.0 / (2.0 * dt), c, -1.0 / (dt * dt), m);
        let mt = Csc::lin_comb(1.0 / (dt * dt), m, 1.0 / (2.0 * dt), c);
        let minv = if mt.is_diagonal() && low.is_none() {
            let d = mt.diagonal();
            if let Some(i) = d.iter().position(|v| *v <= 0.0) {
                return Err(format!("M̃ has a non-positive diagonal entry at DOF {i}"));
            }
            MInv::Diag(d.iter().map(|v| 1.0 / v).collect())
        } else {
            let mut lu = match low {
                // M̃ = S + U diag(d/(2Δt)) Uᵀ.
                Some(lr) => {
                    let scaled = crate::linalg::LowRank {
                        n: lr.n,
                        u: lr.u.clone(),
                        d: lr.d.iter().map(|d| d / (2.0 * dt)).collect(),
                    };
                    StepSolver::LowRank(crate::linalg::WoodburyLu::new(&mt, scaled)?)
                }
                // A shaft chain in node blocks gets the block Thomas solver; anything else (or
                // a singular pivot block) the pivoting sparse LU.
                None => match crate::linalg::BlockTridiag::new(&mt) {
                    Ok(Some(b)) => StepSolver::Block(b),
                    _ => StepSolver::Sparse(StepLu::new(&mt)?),
                },
            };
            let mut col_of = vec![usize::MAX; n];
            let mut cols = vec![0.0; n * contact_dofs.len()];
            for (j, &d) in contact_dofs.iter().enumerate() {
                col_of[d] = j;
                cols[j * n + d] = 1.0;
            }
            for c in cols.chunks_mut(n) {
                lu.solve_in_place(c);
            }
            MInv::Lu {
                lu: Box::new(lu),
                cols,
                col_of,
            }
        };
        Ok(Self {
            n,
            ab: PairCsr::new(&aop, &bop),
            minv,
            u_prev: vec![0.0; n],
            u: vec![0.0; n],
            u_next: vec![0.0; n],
            rhs: vec![0.0; n],
        })
    }

    /// `u_next = M̃⁻¹ (rhs + A u + B u_prev)`; `rhs` holds the external force on entry.
    fn predict(&mut self) {
        self.ab.mul_add(&self.u, &self.u_prev, &mut self.rhs);
        // Low-rank damping C_l: its share of B, C_l/(2Δt), is the term the Woodbury solver
        // holds (M̃ = S + C_l/(2Δt)).
        if let MInv::Lu { lu, .. } = &mut self.minv {
            if let StepSolver::LowRank(w) = lu.as_mut() {
                w.low_rank_mul_add(&self.u_prev, &mut self.rhs);
            }
        }
        match &mut self.minv {
            MInv::Diag(inv) => {
                for ((u, r), d) in self.u_next.iter_mut().zip(&self.rhs).zip(inv.iter()) {
                    *u = d * r;
                }
            }
            MInv::Lu { lu, .. } => {
                self.u_next.copy_from_slice(&self.rhs);
                lu.solve_in_place(&mut self.u_next);
            }
        }
    }

    #[inline]
    fn flex(&self, a: usize, b: usize) -> f64 {
        match &self.minv {
            MInv::Diag(inv) => {
                if a == b {
                    inv[a]
                } else {
                    0.0
                }
            }
            MInv::Lu { cols, col_of, .. } => cols[col_of[b] * self.n + a],
        }
    }

    /// `u_next += M̃⁻¹ e_d · f`.
    #[inline]
    fn apply(&mut self, d: usize, f: f64) {
        match &self.minv {
            MInv::Diag(inv) => self.u_next[d] += inv[d] * f,
            MInv::Lu { cols, col_of, .. } => {
                let c = &cols[col_of[d] * self.n..(col_of[d] + 1) * self.n];
                for (u, v) in self.u_next.iter_mut().zip(c) {
                    *u += v * f;
                }
            }
        }
    }

    fn rotate(&mut self) {
        std::mem::swap(&mut self.u_prev, &mut self.u);
        std::mem::swap(&mut self.u, &mut self.u_next);
    }
}

/// A massless stator condensed to its contact boundary (Eq. 49): the columns `K⁻¹ e_d` of the
/// contact DOFs `d`, kept only at the contact DOFs (`ncd` numbers each), from one sparse
/// Cholesky factor of K (shared by every run of a meshed stator). Small boundaries
/// (≤ [`Compliance::EAGER`] contact DOFs) get every column up front; larger ones get a column
/// the first time its DOF enters a contact problem, cached for the run. The loop's work is then
/// proportional to the contact DOFs, not to the mesh: only the contact entries of `u` are kept
/// current, and the full field is rebuilt by one solve when a frame asks for it
/// ([`Compliance::refresh`]).
#[derive(Debug)]
struct Compliance {
    chol: Option<std::sync::Arc<crate::linalg::Cholesky>>,
    /// Contact DOFs, sorted.
    cd: Vec<usize>,
    /// Free DOF → index in `cd` (`usize::MAX` for interior DOFs).
    slot: Vec<usize>,
    /// Contact slot → start of its column in `cols` (`usize::MAX` until computed).
    col: Vec<usize>,
    /// Cached columns, `cd.len()` entries each (rows at the contact DOFs).
    cols: Vec<f64>,
    /// Force applied at each contact slot since the last reset (N).
    f: Vec<f64>,
    /// Scratch of length n for column solves and refreshes.
    rhs: Vec<f64>,
    /// Displacement (m): contact entries current, interior entries valid after `refresh`.
    u: Vec<f64>,
}

impl Compliance {
    /// Boundaries with at most this many contact DOFs are condensed up front.
    const EAGER: usize = 32;

    fn new(s: &StatorModel) -> Result<Self, String> {
        let n = s.ndof;
        let cd = s.contact_dofs();
        let mut slot = vec![usize::MAX; n];
        for (j, &d) in cd.iter().enumerate() {
            slot[d] = j;
        }
        let chol = if n == 0 {
            None
        } else {
            Some(match &s.mesh {
                Some(md) => md.factor(&s.k)?,
                None => std::sync::Arc::new(crate::linalg::Cholesky::new(&s.k)?),
            })
        };
        let ncd = cd.len();
        let mut c = Self {
            chol,
            col: vec![usize::MAX; ncd],
            cols: Vec::with_capacity(ncd * ncd.min(Self::EAGER.max(16))),
            f: vec![0.0; ncd],
            rhs: vec![0.0; n],
            u: vec![0.0; n],
            cd,
            slot,
        };
        if ncd <= Self::EAGER {
            // One blocked solve for every column.
            let n = c.rhs.len();
            let mut block = vec![0.0; n * ncd];
            for (j, &d) in c.cd.iter().enumerate() {
                block[j * n + d] = 1.0;
            }
            if let Some(ch) = &c.chol {
                ch.solve_in_place(&mut block);
            }
            for j in 0..ncd {
                c.col[j] = c.cols.len();
                let col = &block[j * n..(j + 1) * n];
                let cd = &c.cd;
                c.cols.extend(cd.iter().map(|&e| col[e]));
            }
        }
        Ok(c)
    }
    /// Columns computed together when one is missing: the next missing contact DOFs in DOF
    /// order, which for a meshed boundary are its neighbours (one blocked solve is several
    /// times cheaper per column than single ones).
    const BATCH: usize = 16;

    /// Computes the column of contact DOF `d` (and a batch after it) if it is not cached yet.
    fn ensure(&mut self, d: usize) {
        let j = self.slot[d];
        if self.col[j] != usize::MAX {
            return;
        }
        let ncd = self.cd.len();
        let n = self.rhs.len();
        let batch: Vec<usize> = (0..ncd)
            .map(|k| (j + k) % ncd)
            .filter(|&s| self.col[s] == usize::MAX)
            .take(Self::BATCH)
            .collect();
        let mut block = vec![0.0; n * batch.len()];
        for (b, &s) in batch.iter().enumerate() {
            block[b * n + self.cd[s]] = 1.0;
        }
        if let Some(ch) = &self.chol {
            ch.solve_in_place(&mut block);
        }
        for (b, &s) in batch.iter().enumerate() {
            self.col[s] = self.cols.len();
            let c = &block[b * n..(b + 1) * n];
            self.cols.extend(self.cd.iter().map(|&e| c[e]));
        }
    }
    #[inline]
    fn flex(&self, a: usize, b: usize) -> f64 {
        let c = self.col[self.slot[b]];
        debug_assert!(c != usize::MAX, "compliance column of DOF {b} not prepared");
        self.cols[c + self.slot[a]]
    }
    #[inline]
    fn apply(&mut self, d: usize, f: f64) {
        self.ensure(d);
        let j = self.slot[d];
        self.f[j] += f;
        let c = &self.cols[self.col[j]..self.col[j] + self.cd.len()];
        for (&e, v) in self.cd.iter().zip(c) {
            self.u[e] += v * f;
        }
    }
    /// Undeformed: no contact force (Eq. 49).
    fn reset(&mut self) {
        for &e in &self.cd {
            self.u[e] = 0.0;
        }
        self.f.fill(0.0);
    }
    /// Rebuilds the whole displacement field from the contact forces (one solve).
    fn refresh(&mut self) {
        self.rhs.fill(0.0);
        for (&e, f) in self.cd.iter().zip(&self.f) {
            self.rhs[e] = *f;
        }
        if let Some(ch) = &self.chol {
            ch.solve_in_place(&mut self.rhs);
        }
        self.u.copy_from_slice(&self.rhs);
    }
}

#[derive(Debug)]
enum StatorDyn {
    Massless(Compliance),
    Massive(Box<DynBody>),
}

impl StatorDyn {
    /// Current (predicted) displacement vector.
    fn disp(&self) -> &[f64] {
        match self {
            StatorDyn::Massless(c) => &c.u,
            StatorDyn::Massive(b) => &b.u_next,
        }
    }
    fn flex(&self, a: usize, b: usize) -> f64 {
        match self {
            StatorDyn::Massless(c) => c.flex(a, b),
            StatorDyn::Massive(d) => d.flex(a, b),
        }
    }
    fn apply(&mut self, d: usize, f: f64) {
        match self {
            StatorDyn::Massless(c) => c.apply(d, f),
            StatorDyn::Massive(b) => b.apply(d, f),
        }
    }
    /// Makes `flex` available for a target's DOFs (massless: computes missing columns).
    fn prepare(&mut self, dofs: [Option<usize>; 2]) {
        if let StatorDyn::Massless(c) = self {
            for d in dofs.into_iter().flatten() {
                c.ensure(d);
            }
        }
    }
    /// First DOF whose current value is not finite (massless: the contact DOFs, the only ones
    /// the loop updates).
    fn first_non_finite(&self) -> Option<usize> {
        match self {
            StatorDyn::Massless(c) => c.cd.iter().copied().find(|&d| !c.u[d].is_finite()),
            StatorDyn::Massive(b) => b.u_next.iter().position(|v| !v.is_finite()),
        }
    }
}

/// Force of one active contact pair in a frame.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PairForce {
    /// Station index.
    pub station: usize,
    /// Stator index.
    pub stator: usize,
    /// Stator node of the target (ring targets: 0).
    pub node: usize,
    /// Unit normal from the section centre toward the stator.
    pub n: V2,
    /// Normal force p ≥ 0 (N, compression).
    pub p: f64,
    /// Force on the stator node `(n + μ a) p` (N); the rotor section gets its opposite.
    pub force: V2,
}

/// The full state at one instant, handed to a [`FrameSink`] (VTK/HDF5 writers).
pub struct Frame<'a> {
    /// Step index.
    pub step: usize,
    /// Time (s).
    pub t: f64,
    /// Rotor DOF vector (m, rad).
    pub rotor_u: &'a [f64],
    /// Pairs in contact at this instant.
    pub pairs: &'a [PairForce],
    stators: &'a [StatorDyn],
}

impl Frame<'_> {
    /// Free-DOF displacement vector of stator `k` (m), in the numbering of
    /// [`crate::model::StatorModel::node_dofs`].
    pub fn stator_u(&self, k: usize) -> &[f64] {
        match &self.stators[k] {
            StatorDyn::Massless(c) => &c.u,
            StatorDyn::Massive(b) => &b.u,
        }
    }
}

/// Receives frames during integration, every [`FrameSink::every`] steps (state at that step).
/// Writers stream to disk from here, so memory does not grow with the run.
pub trait FrameSink {
    /// Interval in steps (0: never called).
    fn every(&self) -> usize;
    /// Consumes one frame; an error stops the run.
    fn frame(&mut self, frame: &Frame<'_>) -> Result<(), String>;
}

/// Initial state of the rotor (node 0 of station 0's node or node 0).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Initial {
    /// Displacement `[x, y]` (m).
    pub u: V2,
    /// Velocity `[vx, vy]` (m/s).
    pub v: V2,
}

/// Integrates one case with a step plan, returning the record and counters.
pub fn integrate(
    case: &Case,
    integrator: IntegratorKind,
    plan: &StepPlan,
    init: Initial,
) -> Result<(Record, RunStats), SolveError> {
    integrate_with(case, integrator, plan, init, None)
}

/// [`integrate`] with an optional [`FrameSink`] receiving full-state frames.
pub fn integrate_with(
    case: &Case,
    integrator: IntegratorKind,
    plan: &StepPlan,
    init: Initial,
    mut sink: Option<&mut dyn FrameSink>,
) -> Result<(Record, RunStats), SolveError> {
    let dt = plan.dt;
    let omega = case.omega;
    let model_err = |m: String| SolveError::Contact {
        step: 0,
        time: 0.0,
        pairs: 0,
        message: m,
    };
    // Rotor contact DOFs: every station's node.
    let mut rotor_cd: Vec<usize> = case
        .stations
        .iter()
        .flat_map(|s| case.rotor.node_dofs[s.node])
        .collect();
    // With torsional DOFs, each station node's θ_z too: the friction torque acts there.
    rotor_cd.extend(
        case.stations
            .iter()
            .filter_map(|s| case.rotor.node_torsion.get(s.node).copied().flatten()),
    );
    rotor_cd.sort_unstable();
    rotor_cd.dedup();
    let mut rotor = DynBody::new(
        &case.rotor.m,
        &case.rotor.c,
        &case.rotor.k,
        case.rotor.c_low.as_ref(),
        dt,
        &rotor_cd,
    )
    .map_err(|e| model_err(format!("rotor: {e}")))?;
    let mut stators: Vec<StatorDyn> = Vec::with_capacity(case.stators.len());
    for s in &case.stators {
        stators.push(if s.massless() {
            StatorDyn::Massless(
                Compliance::new(s).map_err(|e| model_err(format!("stator `{}`: {e}", s.name)))?,
            )
        } else {
            StatorDyn::Massive(Box::new(
                DynBody::new(&s.m, &s.c, &s.k, None, dt, &s.contact_dofs())
                    .map_err(|e| model_err(format!("stator `{}`: {e}", s.name)))?,
            ))
        });
    }
    let mut cands: Vec<Candidate> = Vec::new();
    for (k, s) in case.stators.iter().enumerate() {
        for t in 0..s.targets.len() {
            let station = s.target_station(t);
            let st = &case.stations[station];
            cands.push(Candidate {
                station,
                stator: k,
                target: t,
                mu: st.friction,
                radius: st.radius,
            });
        }
    }
    let nc = cands.len();
    let station_dofs: Vec<[usize; 2]> = case
        .stations
        .iter()
        .map(|s| case.rotor.node_dofs[s.node])
        .collect();
    let massless: Vec<bool> = case.stators.iter().map(|s| s.massless()).collect();
    let collocated = integrator == IntegratorKind::Collocated;
    // Broad phase (contact::search): node targets of massless stators stay at their
    // undeformed position in every prediction and are indexed; the others (stators with mass,
    // ring targets) are visited every step.
    let mut indexed = Vec::new();
    let mut dynamic = Vec::new();
    for (ci, c) in cands.iter().enumerate() {
        match &case.stators[c.stator].targets[c.target] {
            crate::model::Target::Node { x0, .. } if massless[c.stator] => {
                indexed.push((ci, c.station, *x0))
            }
            _ => dynamic.push(ci),
        }
    }
    let broad = BroadPhase::new(&indexed, 16);
    drop(indexed);
    let mut near: Vec<usize> = Vec::with_capacity(nc);
    let mut centre: Vec<V2> = vec![[0.0; 2]; case.stations.len()];
    let mut reach: Vec<f64> = vec![0.0; case.stations.len()];
    // The candidates that may have g < margin with the stations displaced as in `u`: from the
    // index when `with_index`, plus the dynamic candidates whose stator passes `keep`; sorted.
    let gather = |near: &mut Vec<usize>,
                  u: &[f64],
                  margin: f64,
                  with_index: bool,
                  keep: &dyn Fn(usize) -> bool,
                  centre: &mut [V2],
                  reach: &mut [f64]| {
        near.clear();
        if with_index && !broad.is_empty() {
            for (s, d) in station_dofs.iter().enumerate() {
                centre[s] = [u[d[0]], u[d[1]]];
                reach[s] = case.stations[s].radius + margin;
            }
            broad.query(centre, reach, near);
        }
        let before = near.len();
        near.extend(dynamic.iter().copied().filter(|&ci| keep(cands[ci].stator)));
        if before > 0 && near.len() > before {
            near.sort_unstable();
        }
    };

    // Initial conditions on node 0's DOFs (station 0's node when there is one).
    let node0 = case.stations.first().map_or(0, |s| s.node);
    let d0 = case.rotor.node_dofs[node0];
    let dobs = case.rotor.node_dofs[case.observed_node];
    let mdiag = case.rotor.m.diagonal();
    {
        let mut f0 = vec![0.0; rotor.n];
        case.rotor.add_unbalance(omega, 0.0, &mut f0);
        let mut u0 = vec![0.0; rotor.n];
        let mut v0 = vec![0.0; rotor.n];
        for c in 0..2 {
            u0[d0[c]] = init.u[c];
            v0[d0[c]] = init.v[c];
        }
        case.rotor.k.mul_add(-1.0, &u0, &mut f0);
        case.rotor.c.mul_add(-1.0, &v0, &mut f0);
        if let Some(lr) = &case.rotor.c_low {
            lr.mul_add(-1.0, &v0, &mut f0, &mut vec![0.0; lr.rank()]);
        }
        for i in 0..rotor.n {
            let a0 = if case.rotor.m.is_diagonal() && mdiag[i] > 0.0 {
                f0[i] / mdiag[i]
            } else {
                0.0
            };
            rotor.u[i] = u0[i];
            rotor.u_prev[i] = u0[i] - dt * v0[i] + 0.5 * dt * dt * a0;
        }
    }
    let scale = case
        .z0
        .max(
            case.stators
                .iter()
                .map(|s| s.clearance)
                .filter(|c| c.is_finite())
                .fold(0.0, f64::max),
        )
        .max(init.u[0].hypot(init.u[1]))
        .max(1e-9);
    let bound = 1e4 * scale;

    // Workspaces.
    // The dense contact buffers are sized for up to LCP_CAP pairs at once (all candidates when
    // fewer) and grow in the loop only if a contact problem is larger (large meshed stators).
    const LCP_CAP: usize = 256;
    let cap0 = nc.clamp(1, LCP_CAP);
    let mut ws = LcpWorkspace::new(cap0);
    let mut states = vec![PairState::default(); nc];
    // Per candidate: did it carry force when last solved (the LCP's warm start); guess buffer.
    let mut carried = vec![false; nc];
    let mut guess = vec![false; nc];
    let mut sel: Vec<usize> = Vec::with_capacity(nc);
    let mut wmat = vec![0.0; cap0 * cap0];
    let mut gvec = vec![0.0; cap0];
    let mut pvec = vec![0.0; cap0];
    fn grow(
        q: usize,
        ws: &mut LcpWorkspace,
        wmat: &mut Vec<f64>,
        g: &mut Vec<f64>,
        p: &mut Vec<f64>,
    ) {
        if q > ws.capacity() {
            *ws = LcpWorkspace::new(q);
            wmat.resize(q * q, 0.0);
            g.resize(q, 0.0);
            p.resize(q, 0.0);
        }
    }
    let nsamples = plan.steps / plan.record_every + 2;
    let nst = case.stations.len().max(1);
    let mut rec = Record::with_capacity(nst, nsamples);
    let mut fst = vec![[0.0; 2]; nst];
    let mut fst_n = vec![[0.0; 2]; nst];
    // Collocated runs: forces of stators with mass, solved by forward increment in the step
    // that ends at the next recorded instant, kept apart from the massless stators' static
    // forces (which alone enter the next prediction) and added to what is recorded there.
    let mut dyn_f = vec![[0.0; 2]; nst];
    let mut dyn_fn = vec![[0.0; 2]; nst];
    let mut rec_f = vec![[0.0; 2]; nst];
    let mut rec_fn = vec![[0.0; 2]; nst];
    let mut dyn_pairs: Vec<PairForce> = Vec::with_capacity(nc);
    let mut dyn_active = 0usize;
    let mut stats = RunStats {
        min_gap: f64::INFINITY,
        ..Default::default()
    };
    let start = Instant::now();

    // One LCP over a selection of pairs; `rotor_in` says whether the rotor's flexibility
    // enters W (forward increment) or the rotor is held (collocated static solve).
    #[allow(clippy::too_many_arguments, clippy::needless_range_loop)]
    fn solve_pairs(
        sel: &[usize],
        cands: &[Candidate],
        states: &[PairState],
        case: &Case,
        station_dofs: &[[usize; 2]],
        rotor: &mut DynBody,
        rotor_in: bool,
        stators: &mut [StatorDyn],
        wmat: &mut [f64],
        gvec: &mut [f64],
        pvec: &mut [f64],
        ws: &mut LcpWorkspace,
        fst: &mut [V2],
        fst_n: &mut [V2],
        carried: &mut [bool],
        guess: &mut [bool],
        step: usize,
        time: f64,
    ) -> Result<usize, SolveError> {
        let q = sel.len();
        for &ci in sel {
            let c = &cands[ci];
            stators[c.stator].prepare(case.stators[c.stator].targets[c.target].dofs());
        }
        for (i, &ci) in sel.iter().enumerate() {
            let c = &cands[ci];
            let si = &states[ci];
            let rdi = station_dofs[c.station];
            let tdi = case.stators[c.stator].targets[c.target].dofs();
            gvec[i] = si.g;
            for (j, &cj) in sel.iter().enumerate() {
                let d = &cands[cj];
                let bj = states[cj].b(d.mu);
                let mut w = 0.0;
                if rotor_in {
                    let rdj = station_dofs[d.station];
                    for a in 0..2 {
                        for b in 0..2 {
                            w += si.n[a] * rotor.flex(rdi[a], rdj[b]) * bj[b];
                        }
                    }
                }
                if c.stator == d.stator {
                    let tdj = case.stators[d.stator].targets[d.target].dofs();
                    let body = &stators[c.stator];
                    for a in 0..2 {
                        for b in 0..2 {
                            if let (Some(x), Some(y)) = (tdi[a], tdj[b]) {
                                w += si.n[a] * body.flex(x, y) * bj[b];
                            }
                        }
                    }
                }
                wmat[i * q + j] = w;
            }
        }
        // Warm start: the pairs that carried force when last solved start active.
        for (i, &ci) in sel.iter().enumerate() {
            guess[i] = carried[ci];
        }
        let piv = lcp::solve_warm(q, &wmat[..q * q], &gvec[..q], &mut pvec[..q], ws, guess)
            .map_err(|e| SolveError::Contact {
                step,
                time,
                pairs: q,
                message: e.to_string(),
            })?;
        for (i, &ci) in sel.iter().enumerate() {
            carried[ci] = pvec[i] > 0.0;
        }
        for (i, &ci) in sel.iter().enumerate() {
            let p = pvec[i];
            if p == 0.0 {
                continue;
            }
            let c = &cands[ci];
            let b = states[ci].b(c.mu);
            let n = states[ci].n;
            let rd = station_dofs[c.station];
            if rotor_in {
                rotor.apply(rd[0], -b[0] * p);
                rotor.apply(rd[1], -b[1] * p);
            }
            // Friction torque on the station's θ_z (rotors with torsional DOFs): the force
            // −(n + μa)p acts at R·n from the section centre, τ_z = R (n × F)_z = −R μ p (n × a)_z.
            // θ_z is uncoupled from the lateral DOFs in M̃ (M, C + ΩG, bearings have no entries
            // between them), so the torque moves no gap and W above is unchanged. Collocated
            // static solve (rotor held): the torque joins the step's load like `fst`.
            let tz = case.rotor.node_torsion.get(case.stations[c.station].node);
            if let Some(&Some(tz)) = tz {
                let tau = -c.radius * (n[0] * b[1] - n[1] * b[0]) * p;
                if rotor_in {
                    rotor.apply(tz, tau);
                } else {
                    rotor.rhs[tz] += tau;
                }
            }
            fst[c.station][0] -= b[0] * p;
            fst[c.station][1] -= b[1] * p;
            fst_n[c.station][0] -= n[0] * p;
            fst_n[c.station][1] -= n[1] * p;
            let td = case.stators[c.stator].targets[c.target].dofs();
            for a in 0..2 {
                if let Some(d) = td[a] {
                    stators[c.stator].apply(d, b[a] * p);
                }
            }
        }
        Ok(piv)
    }

    let stator_energy =
        |stators: &[StatorDyn], states: &[PairState], sel: &[usize], pvec: &[f64]| {
            let mut e = 0.0;
            for (i, &ci) in sel.iter().enumerate() {
                let c = &cands[ci];
                if let StatorDyn::Massless(cm) = &stators[c.stator] {
                    let b = states[ci].b(c.mu);
                    let us = target_disp(case.stators[c.stator].targets[c.target].dofs(), &cm.u);
                    e += 0.5 * pvec[i] * (b[0] * us[0] + b[1] * us[1]);
                }
            }
            e
        };

    let mut energy_now = 0.0;
    let record = |rec: &mut Record,
                  t: f64,
                  rotor_u: &[f64],
                  fst: &[V2],
                  fst_n: &[V2],
                  energy: f64,
                  active: usize| {
        rec.t.push(t);
        rec.observed.push([rotor_u[dobs[0]], rotor_u[dobs[1]]]);
        for (s, d) in station_dofs.iter().enumerate() {
            rec.disp.push([rotor_u[d[0]], rotor_u[d[1]]]);
            rec.force.push(fst[s]);
            rec.force_normal.push(fst_n[s]);
        }
        if station_dofs.is_empty() {
            rec.disp.push([rotor_u[d0[0]], rotor_u[d0[1]]]);
            rec.force.push([0.0; 2]);
            rec.force_normal.push([0.0; 2]);
        }
        rec.stator_energy.push(energy);
        rec.active.push(active as u32);
    };

    // Frozen geometry of candidate `ci` with the rotor at `u` and the stator at `stator_u`
    // (None: undeformed, the start of a massless stator's step).
    let pair_at = |ci: usize, u: &[f64], stator_u: Option<&[f64]>| -> PairState {
        let c = &cands[ci];
        let rd = station_dofs[c.station];
        let tg = &case.stators[c.stator].targets[c.target];
        let us = stator_u.map_or([0.0; 2], |s| target_disp(tg.dofs(), s));
        pair_state(tg, c.radius, [u[rd[0]], u[rd[1]]], us, omega)
    };
    // Frames: pairs in contact at the frame's instant, preallocated.
    let mut frame_pairs: Vec<PairForce> = Vec::with_capacity(nc);
    let collect_pairs =
        |out: &mut Vec<PairForce>, sel: &[usize], states: &[PairState], pvec: &[f64]| {
            for (i, &ci) in sel.iter().enumerate() {
                let p = pvec[i];
                if p > 0.0 && out.len() < out.capacity() {
                    let c = &cands[ci];
                    let b = states[ci].b(c.mu);
                    let node = match &case.stators[c.stator].targets[c.target] {
                        crate::model::Target::Node { node, .. } => *node,
                        crate::model::Target::Ring { .. } => 0,
                    };
                    out.push(PairForce {
                        station: c.station,
                        stator: c.stator,
                        node,
                        n: states[ci].n,
                        p,
                        force: [b[0] * p, b[1] * p],
                    });
                }
            }
        };
    let emit = |sink: &mut Option<&mut dyn FrameSink>,
                step: usize,
                t: f64,
                rotor_u: &[f64],
                pairs: &[PairForce],
                stators: &mut [StatorDyn]|
     -> Result<(), SolveError> {
        if let Some(s) = sink.as_mut() {
            let every = s.every();
            if every > 0 && step % every == 0 {
                // Massless stators keep only their contact DOFs current: rebuild the field.
                for st in stators.iter_mut() {
                    if let StatorDyn::Massless(c) = st {
                        c.refresh();
                    }
                }
                let stators = &*stators;
                s.frame(&Frame {
                    step,
                    t,
                    rotor_u,
                    pairs,
                    stators,
                })
                .map_err(|message| SolveError::FrameOutput {
                    step,
                    time: t,
                    message,
                })?;
            }
        }
        Ok(())
    };
    if !collocated {
        record(&mut rec, 0.0, &rotor.u, &fst, &fst_n, 0.0, 0);
        emit(&mut sink, 0, 0.0, &rotor.u, &frame_pairs, &mut stators)?;
    }
    for step in 0..=plan.steps {
        let t = step as f64 * dt;
        frame_pairs.clear();
        for f in fst.iter_mut().chain(fst_n.iter_mut()) {
            *f = [0.0; 2];
        }
        rotor.rhs.fill(0.0);
        let mut active_now = 0;
        if collocated {
            // Static contact of massless stators with the rotor held at uⁿ.
            sel.clear();
            let mut deepest = 0.0_f64;
            for (k, st) in stators.iter_mut().enumerate() {
                if let StatorDyn::Massless(c) = st {
                    if massless[k] {
                        c.reset();
                    }
                }
            }
            let keep = |k: usize| massless[k];
            gather(
                &mut near,
                &rotor.u,
                0.0,
                true,
                &keep,
                &mut centre,
                &mut reach,
            );
            for &ci in &near {
                states[ci] = pair_at(ci, &rotor.u, None);
                deepest = deepest.max(-states[ci].g);
            }
            if deepest > 0.0 {
                // Every pair with g < deepest, from the nodes within r + deepest.
                gather(
                    &mut near,
                    &rotor.u,
                    deepest,
                    true,
                    &keep,
                    &mut centre,
                    &mut reach,
                );
                for &ci in &near {
                    states[ci] = pair_at(ci, &rotor.u, None);
                    if states[ci].g < deepest {
                        sel.push(ci);
                    }
                }
                grow(sel.len(), &mut ws, &mut wmat, &mut gvec, &mut pvec);
                stats.pivots += solve_pairs(
                    &sel,
                    &cands,
                    &states,
                    case,
                    &station_dofs,
                    &mut rotor,
                    false,
                    &mut stators,
                    &mut wmat,
                    &mut gvec,
                    &mut pvec,
                    &mut ws,
                    &mut fst,
                    &mut fst_n,
                    &mut carried,
                    &mut guess,
                    step,
                    t,
                )?;
                active_now = pvec[..sel.len()].iter().filter(|p| **p > 0.0).count();
                energy_now = stator_energy(&stators, &states, &sel, &pvec);
                collect_pairs(&mut frame_pairs, &sel, &states, &pvec);
                for &ci in sel.iter() {
                    let c = &cands[ci];
                    let rd = station_dofs[c.station];
                    let uc = [rotor.u[rd[0]], rotor.u[rd[1]]];
                    let tg = &case.stators[c.stator].targets[c.target];
                    if let StatorDyn::Massless(cm) = &stators[c.stator] {
                        let g = exact_gap(tg, c.radius, uc, target_disp(tg.dofs(), &cm.u));
                        stats.min_gap = stats.min_gap.min(g);
                    }
                }
            } else {
                energy_now = 0.0;
            }
            // Add the stators with mass, whose forces of the step ending now act at tₙ.
            for s in 0..nst {
                for a in 0..2 {
                    rec_f[s][a] = fst[s][a] + dyn_f[s][a];
                    rec_fn[s][a] = fst_n[s][a] + dyn_fn[s][a];
                }
            }
            for pf in &dyn_pairs {
                if frame_pairs.len() < frame_pairs.capacity() {
                    frame_pairs.push(*pf);
                }
            }
            let recorded_active = active_now + dyn_active;
            if step % plan.record_every == 0 {
                record(
                    &mut rec,
                    t,
                    &rotor.u,
                    &rec_f,
                    &rec_fn,
                    energy_now,
                    recorded_active,
                );
            }
            emit(&mut sink, step, t, &rotor.u, &frame_pairs, &mut stators)?;
            if step == plan.steps {
                break;
            }
            for f in dyn_f.iter_mut().chain(dyn_fn.iter_mut()) {
                *f = [0.0; 2];
            }
            dyn_pairs.clear();
            dyn_active = 0;
            for (s, d) in station_dofs.iter().enumerate() {
                rotor.rhs[d[0]] += fst[s][0];
                rotor.rhs[d[1]] += fst[s][1];
            }
        } else if step == plan.steps {
            break;
        }
        // Predict.
        case.rotor.add_unbalance(omega, t, &mut rotor.rhs);
        rotor.predict();
        for (k, st) in stators.iter_mut().enumerate() {
            match st {
                StatorDyn::Massive(b) => {
                    b.rhs.fill(0.0);
                    b.predict();
                }
                StatorDyn::Massless(c) => {
                    if !collocated && massless[k] {
                        c.reset();
                    }
                }
            }
        }
        // Forward-increment contact on the predicted configuration.
        sel.clear();
        let mut deepest = 0.0_f64;
        let keep = |k: usize| !(collocated && massless[k]);
        let u_pred = &rotor.u_next;
        gather(
            &mut near,
            u_pred,
            0.0,
            !collocated,
            &keep,
            &mut centre,
            &mut reach,
        );
        for &ci in &near {
            let c = &cands[ci];
            states[ci] = pair_at(ci, u_pred, Some(stators[c.stator].disp()));
            deepest = deepest.max(-states[ci].g);
        }
        if deepest > 0.0 {
            gather(
                &mut near,
                u_pred,
                deepest,
                !collocated,
                &keep,
                &mut centre,
                &mut reach,
            );
            for &ci in &near {
                let c = &cands[ci];
                states[ci] = pair_at(ci, u_pred, Some(stators[c.stator].disp()));
                if states[ci].g < deepest {
                    sel.push(ci);
                }
            }
            if !collocated {
                for f in fst.iter_mut().chain(fst_n.iter_mut()) {
                    *f = [0.0; 2];
                }
            }
            grow(sel.len(), &mut ws, &mut wmat, &mut gvec, &mut pvec);
            // Collocated: these are the stators with mass; their forces go to `dyn_*`.
            let (acc_f, acc_fn) = if collocated {
                (&mut dyn_f, &mut dyn_fn)
            } else {
                (&mut fst, &mut fst_n)
            };
            stats.pivots += solve_pairs(
                &sel,
                &cands,
                &states,
                case,
                &station_dofs,
                &mut rotor,
                true,
                &mut stators,
                &mut wmat,
                &mut gvec,
                &mut pvec,
                &mut ws,
                acc_f,
                acc_fn,
                &mut carried,
                &mut guess,
                step,
                t,
            )?;
            let act = pvec[..sel.len()].iter().filter(|p| **p > 0.0).count();
            if collocated {
                collect_pairs(&mut dyn_pairs, &sel, &states, &pvec);
                dyn_active = act;
                active_now += act;
            } else {
                collect_pairs(&mut frame_pairs, &sel, &states, &pvec);
                active_now = act;
                energy_now = stator_energy(&stators, &states, &sel, &pvec);
            }
            for &ci in sel.iter() {
                let c = &cands[ci];
                let rd = station_dofs[c.station];
                let uc = [rotor.u_next[rd[0]], rotor.u_next[rd[1]]];
                let tg = &case.stators[c.stator].targets[c.target];
                let us = target_disp(tg.dofs(), stators[c.stator].disp());
                stats.min_gap = stats.min_gap.min(exact_gap(tg, c.radius, uc, us));
            }
        } else if !collocated {
            energy_now = 0.0;
        }
        if active_now > 0 {
            stats.contact_steps += 1;
            stats.max_active = stats.max_active.max(active_now);
        }
        // Stability guard.
        for (i, v) in rotor.u_next.iter().enumerate() {
            if v.is_nan() || v.abs() > bound {
                return Err(if v.is_finite() {
                    SolveError::Diverged {
                        step: step + 1,
                        time: t + dt,
                        magnitude: v.abs(),
                        bound,
                        dt,
                        limit: plan.limit,
                    }
                } else {
                    SolveError::NonFinite {
                        step: step + 1,
                        time: t + dt,
                        what: "rotor".into(),
                        dof: i,
                        dt,
                        limit: plan.limit,
                    }
                });
            }
        }
        for (k, st) in stators.iter().enumerate() {
            if let Some(i) = st.first_non_finite() {
                return Err(SolveError::NonFinite {
                    step: step + 1,
                    time: t + dt,
                    what: format!("stator `{}`", case.stators[k].name),
                    dof: i,
                    dt,
                    limit: plan.limit,
                });
            }
        }
        rotor.rotate();
        for st in stators.iter_mut() {
            if let StatorDyn::Massive(b) = st {
                b.rotate();
            }
        }
        stats.steps += 1;
        if !collocated {
            if (step + 1) % plan.record_every == 0 {
                record(
                    &mut rec,
                    t + dt,
                    &rotor.u,
                    &fst,
                    &fst_n,
                    energy_now,
                    active_now,
                );
            }
            emit(
                &mut sink,
                step + 1,
                t + dt,
                &rotor.u,
                &frame_pairs,
                &mut stators,
            )?;
        }
    }
    stats.wall_s = start.elapsed().as_secs_f64();
    if stats.min_gap == f64::INFINITY {
        stats.min_gap = f64::NAN;
    }
    Ok((rec, stats))
}
