//! Undamped critical speed map: the synchronous critical speeds of an FE rotor against the
//! stiffness of its bearings, swept over a (log) range, with the scene's own bearing lines on
//! it (Vance, *Rotordynamics of Turbomachinery*, §3; ROSS's `run_ucs(synchronous=True)`).
//!
//! # Critical speeds
//!
//! The bearings swept get `kxx = kyy = k` and nothing else (no damping, no cross-coupling);
//! the others (when one bearing is named) keep their direct stiffnesses at rest `kxx(0)`,
//! `kyy(0)`, without damping and cross-coupling, so the problem stays undamped and symmetric.
//! Axial and torsional DOFs are left out (uncoupled). A synchronous whirl
//! `q = Re(φ e^{iΩt})` of the undamped rotor `M q̈ + Ω G q̇ + K q = 0` at the spin speed Ω
//! satisfies `K φ = Ω² (M − iG) φ`, where `M − iG` is Hermitian (G is real skew-symmetric) but
//! may be indefinite. With `K = L Lᵀ` (the bearings hold the rotor, so K is positive definite)
//! it is the Hermitian eigenproblem `L⁻¹(M − iG)L⁻ᵀ ψ = μ ψ`, `μ = 1/Ω²`: every `μ > 0` is a
//! critical speed `Ω = 1/√μ`; a `μ ≤ 0` is a whirl that no spin speed reaches (the forward
//! mode of a disk whose polar inertia exceeds its diametral one).
//!
//! Each critical speed is classified by its whirl, from the circular parts of the translations
//! of every node, `Σ|φ_x + iφ_y|²` (forward, with the spin) against `Σ|φ_x − iφ_y|²`
//! (backward): the larger wins. Without gyroscopic terms the two whirls of an axisymmetric
//! rotor have the same critical speed (a double `μ`, whose solver basis is any mix of them):
//! such a pair (equal to 1e-9) counts once as forward and once as backward. The forward ones
//! are the unbalance critical speeds (an unbalance forces forward synchronous whirl only).
//!
//! # Bearing lines
//!
//! The scene's bearings are drawn on the map as `(kxx(Ω), Ω)` and `(kyy(Ω), Ω)` — vertical
//! lines for constant coefficients, the table for tabulated ones — and the rotor's critical
//! speeds on its own bearings are read where they cross the forward curves (the map's curves
//! interpolated linearly in log k, log Ω).

use super::modes::FULL_BASIS;
use crate::error::ModelError;
use crate::model::fe_rotor::{dense, FeRotor};
use crate::model::Rotor;
use nalgebra::DMatrix;
use num_complex::Complex64;
use serde::Serialize;

/// Which bearings the map sweeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Swept {
    /// Every bearing gets the swept stiffness.
    All,
    /// Only this bearing (index in the scene's `[[rotor.bearing]]` list).
    One(usize),
}

/// The synchronous critical speeds of one rotor, ascending (rad/s).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct CriticalSpeeds {
    /// Forward whirl (the unbalance critical speeds).
    pub forward: Vec<f64>,
    /// Backward whirl.
    pub backward: Vec<f64>,
}

/// One of the scene's bearings as a line on the map.
#[derive(Debug, Clone, Serialize)]
pub struct BearingLine {
    /// E.g. "bearing 0 kxx".
    pub label: String,
    /// `(k N/m, Ω rad/s)` points.
    pub points: Vec<(f64, f64)>,
}

/// A crossing of a bearing line with a forward curve: the rotor's critical speed on that
/// bearing stiffness.
#[derive(Debug, Clone, Serialize)]
pub struct Crossing {
    /// Bearing line label.
    pub bearing: String,
    /// Forward mode (1 = lowest).
    pub mode: usize,
    /// Bearing stiffness at the crossing (N/m).
    pub stiffness: f64,
    /// Critical speed (rad/s).
    pub speed: f64,
}

/// The map.
#[derive(Debug, Clone, Serialize)]
pub struct CriticalMapResults {
    /// Swept bearing stiffness (N/m).
    pub stiffness: Vec<f64>,
    /// Critical speeds at each stiffness (the lowest `modes` of each whirl; `NaN` where fewer).
    pub speeds: Vec<CriticalSpeeds>,
    /// Forward and backward curves hold this many modes.
    pub modes: usize,
    /// The scene's bearings as lines on the map.
    pub bearing_lines: Vec<BearingLine>,
    /// Where the bearing lines cross the forward curves.
    pub crossings: Vec<Crossing>,
}

/// `points` stiffnesses (at least 2) spread evenly in log from `from` to `to` (N/m).
pub fn log_range(from: f64, to: f64, points: usize) -> Vec<f64> {
    let n = points.max(2);
    let (a, b) = (from.ln(), to.ln());
    (0..n)
        .map(|i| (a + (b - a) * i as f64 / (n - 1) as f64).exp())
        .collect()
}

/// The rotor with the swept bearings at `kxx = kyy = k` and every bearing undamped, without
/// cross-coupling and speed independent (the others at their stiffness at rest).
fn with_bearings(fe: &FeRotor, swept: Swept, k: f64) -> FeRotor {
    let mut r = fe.clone();
    for (i, b) in r.bearings.iter_mut().enumerate() {
        let (k0, _) = b.coefficients(0.0);
        let kk = match swept {
            Swept::All => [k, 0.0, 0.0, k],
            Swept::One(j) if j == i => [k, 0.0, 0.0, k],
            Swept::One(_) => [k0[0], 0.0, 0.0, k0[3]],
        };
        b.speeds.clear();
        b.k = vec![kk];
        b.c = vec![[0.0; 4]];
    }
    r
}

/// The synchronous critical speeds of an FE rotor with its bearings as they are at rest,
/// undamped (module docs), at most `nmodes` of each whirl.
///
/// # Errors
/// [`ModelError::Singular`] when the lateral stiffness is not positive definite (a rotor its
/// bearings do not hold); [`ModelError::Inconsistent`] when the problem is larger than the
/// dense solver is meant for.
pub fn synchronous(fe: &FeRotor, nmodes: usize) -> Result<CriticalSpeeds, ModelError> {
    let nl = fe.ndof_lateral;
    if nl > 8 * FULL_BASIS {
        return Err(ModelError::Inconsistent {
            what: "rotor".into(),
            message: format!(
                "{nl} lateral DOFs: the dense synchronous eigenproblem is limited to {}",
                8 * FULL_BASIS
            ),
        });
    }
    let block = |a: DMatrix<f64>| a.view((0, 0), (nl, nl)).into_owned();
    let (m, k, g) = (
        block(dense(&fe.m)),
        block(dense(&fe.k(0.0))),
        block(dense(&fe.g)),
    );
    let l = k.cholesky().ok_or_else(|| ModelError::Singular {
        what: "lateral stiffness of the critical speed map".into(),
        detail: "not positive definite: the bearings do not hold the rotor".into(),
    })?;
    let linv = l.l().try_inverse().ok_or_else(|| ModelError::Singular {
        what: "lateral stiffness of the critical speed map".into(),
        detail: "Cholesky factor not invertible".into(),
    })?;
    let a = DMatrix::from_fn(nl, nl, |r, c| Complex64::new(m[(r, c)], -g[(r, c)]));
    let lc = linv.map(|v| Complex64::new(v, 0.0));
    let h = &lc * a * lc.transpose();
    let h = (&h + h.adjoint()) * Complex64::new(0.5, 0.0);
    let eig = h.symmetric_eigen();
    let phi = lc.transpose() * &eig.eigenvectors;
    let nodes = fe.nodes();
    let i = Complex64::new(0.0, 1.0);
    let mut found: Vec<(f64, bool)> = Vec::new();
    for (j, &mu) in eig.eigenvalues.iter().enumerate() {
        if mu.is_nan() || mu <= 1e-300 {
            continue;
        }
        let (mut fw, mut bw) = (0.0, 0.0);
        for n in 0..nodes {
            let (x, y) = (phi[(4 * n, j)], phi[(4 * n + 1, j)]);
            fw += (x + i * y).norm_sqr();
            bw += (x - i * y).norm_sqr();
        }
        found.push((1.0 / mu.sqrt(), fw >= bw));
    }
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = CriticalSpeeds::default();
    let mut j = 0;
    while j < found.len() {
        let (s, fwd) = found[j];
        let pair = j + 1 < found.len() && (found[j + 1].0 - s).abs() <= 1e-9 * s;
        if pair && found[j + 1].1 == fwd {
            // A double root: one of each whirl (module docs).
            out.forward.push(s);
            out.backward.push(found[j + 1].0);
            j += 2;
            continue;
        }
        if fwd {
            out.forward.push(s);
        } else {
            out.backward.push(s);
        }
        j += 1;
    }
    out.forward.truncate(nmodes);
    out.backward.truncate(nmodes);
    Ok(out)
}

/// The critical speed map of `rotor` over the bearing stiffnesses `stiffness` (N/m) with the
/// lowest `nmodes` critical speeds of each whirl.
///
/// # Errors
/// [`ModelError::Inconsistent`] for a Jeffcott rotor (it has no bearings to sweep) or a
/// bearing index out of range; as [`synchronous`].
pub fn critical_map(
    rotor: &Rotor,
    stiffness: &[f64],
    swept: Swept,
    nmodes: usize,
) -> Result<CriticalMapResults, ModelError> {
    let Rotor::Fe(f) = rotor else {
        return Err(ModelError::Inconsistent {
            what: "rotor".into(),
            message: "a Jeffcott rotor has no bearings to sweep: the map needs an FE rotor \
                      (rotor.kind = \"fe\")"
                .into(),
        });
    };
    let fe = &f.rotor;
    if let Swept::One(j) = swept {
        if j >= fe.bearings.len() {
            return Err(ModelError::Inconsistent {
                what: format!("bearing {j}"),
                message: format!(
                    "does not exist (the rotor has {} bearings, 0..={})",
                    fe.bearings.len(),
                    fe.bearings.len().saturating_sub(1)
                ),
            });
        }
    }
    let speeds = stiffness
        .iter()
        .map(|&k| {
            synchronous(&with_bearings(fe, swept, k), nmodes).map(|mut c| {
                c.forward.resize(nmodes, f64::NAN);
                c.backward.resize(nmodes, f64::NAN);
                c
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let finite = || {
        speeds
            .iter()
            .flat_map(|c| c.forward.iter())
            .copied()
            .filter(|s| s.is_finite())
    };
    let top = finite().fold(0.0_f64, f64::max);
    let low = finite().fold(f64::INFINITY, f64::min).min(top);
    let bearing_lines = bearing_lines(fe, swept, (0.5 * low, 1.5 * top));
    let mut res = CriticalMapResults {
        stiffness: stiffness.to_vec(),
        speeds,
        modes: nmodes,
        bearing_lines,
        crossings: Vec::new(),
    };
    res.crossings = crossings(&res);
    Ok(res)
}

/// The swept bearings' `kxx` and `kyy` against speed: the table of a tabulated bearing, else
/// a vertical line over `(low, top)` rad/s.
fn bearing_lines(fe: &FeRotor, swept: Swept, (low, top): (f64, f64)) -> Vec<BearingLine> {
    let mut out = Vec::new();
    for (i, b) in fe.bearings.iter().enumerate() {
        if matches!(swept, Swept::One(j) if j != i) {
            continue;
        }
        let speeds: Vec<f64> = if b.speeds.len() >= 2 {
            b.speeds.clone()
        } else {
            vec![low, top]
        };
        for (c, name) in [(0, "kxx"), (3, "kyy")] {
            out.push(BearingLine {
                label: format!("bearing {i} (node {}) {name}", b.node),
                points: speeds
                    .iter()
                    .map(|&s| (b.coefficients(s).0[c], s))
                    .collect(),
            });
        }
    }
    out
}

/// The forward curve `mode` at stiffness `k`, interpolated linearly in (log k, log Ω); `None`
/// outside the map.
fn curve_at(res: &CriticalMapResults, mode: usize, k: f64) -> Option<f64> {
    let ks = &res.stiffness;
    let i = ks.windows(2).position(|w| w[0] <= k && k <= w[1])?;
    let (a, b) = (res.speeds[i].forward[mode], res.speeds[i + 1].forward[mode]);
    if a.is_nan() || b.is_nan() || a <= 0.0 || b <= 0.0 {
        return None;
    }
    let t = (k / ks[i]).ln() / (ks[i + 1] / ks[i]).ln();
    Some((a.ln() + t * (b / a).ln()).exp())
}

/// Crossings of every bearing line with every forward curve (module docs): sign changes of
/// `Ω − Ω_c(k(Ω))` along the line, sampled 256 times per segment.
fn crossings(res: &CriticalMapResults) -> Vec<Crossing> {
    let mut out = Vec::new();
    for line in &res.bearing_lines {
        for mode in 0..res.modes {
            let f = |(k, s): (f64, f64)| curve_at(res, mode, k).map(|c| (s - c, k, s));
            let mut prev: Option<(f64, f64, f64)> = None;
            for w in line.points.windows(2) {
                for q in 0..=256 {
                    let t = f64::from(q) / 256.0;
                    let p = (
                        w[0].0 + t * (w[1].0 - w[0].0),
                        w[0].1 + t * (w[1].1 - w[0].1),
                    );
                    let cur = f(p);
                    if let (Some(a), Some(b)) = (prev, cur) {
                        if (a.0 < 0.0 && b.0 >= 0.0) || (a.0 > 0.0 && b.0 <= 0.0) {
                            let u = a.0 / (a.0 - b.0);
                            out.push(Crossing {
                                bearing: line.label.clone(),
                                mode: mode + 1,
                                stiffness: a.1 + u * (b.1 - a.1),
                                speed: a.2 + u * (b.2 - a.2),
                            });
                        }
                    }
                    prev = cur;
                }
            }
        }
    }
    out
}
