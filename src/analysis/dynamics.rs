//! What a steady response that is not periodic is: quasi-periodic or chaotic, told by the 0–1
//! test for chaos on its once-per-revolution Poincaré section ([`zero_one_k`], [`dynamics`]).
//!
//! # The 0–1 test (Gottwald & Melbourne)
//!
//! G. A. Gottwald, I. Melbourne, "A new test for chaos in deterministic systems", Proc. R. Soc.
//! Lond. A 460 (2004) 603–611; "On the implementation of the 0–1 test for chaos", SIAM J. Appl.
//! Dyn. Syst. 8 (2009) 129–145 — the correlation method used here. Of an observable `φ(j)`,
//! `j = 1 … N` (here one coordinate of the Poincaré points, its mean removed), and a frequency
//! `c ∈ (0, π)`, the translation variables
//!
//! `p_c(n) = Σ_{j≤n} φ(j) cos(jc)`, `q_c(n) = Σ_{j≤n} φ(j) sin(jc)`
//!
//! are a bounded walk when the dynamics is regular (periodic or quasi-periodic) and a diffusion
//! when it is chaotic. Their mean square displacement
//!
//! `M_c(n) = 1/(N − n) Σ_{j=1}^{N−n} [(p_c(j+n) − p_c(j))² + (q_c(j+n) − q_c(j))²]`,
//! `n = 1 … n_cut = N/10`,
//!
//! is bounded in the first case and grows linearly in the second. `K_c` is the correlation
//! coefficient of `M_c(n)` with `n`; the mean is removed from `φ` first, so the oscillatory term
//! `(Eφ)² (1 − cos nc)/(1 − cos c)` of the 2009 paper is zero. `K` is the median of `K_c` over
//! [`ZERO_ONE_FREQUENCIES`] values of `c` drawn uniformly in `(π/5, 4π/5)` (a fixed seed: the
//! result is reproducible): a `c` resonant with a frequency of a regular response makes `p_c,
//! q_c` grow linearly and that one `K_c` near 1, which the median discards. `K → 0` for regular,
//! `K → 1` for chaotic dynamics as `N → ∞`.
//!
//! # Thresholds
//!
//! The unit tests measure, at `N` = 200, 400, 1000 points: two incommensurate frequencies
//! 0.091, 0.035, −0.005; a period-33 sequence −0.013, −0.006, 0.003; the logistic map at
//! r = 3.97 0.996, 0.999, 0.998; the Hénon map 0.997, 0.997, 0.998. Below 200 points the
//! regular values rise (0.82 for the torus at `N` = 100: `M_c(n)` has not finished its first
//! oscillation within `n_cut`), so fewer than [`MIN_SECTION_POINTS`] = 200 points read
//! `undetermined`, and a window that is not periodic is lengthened to
//! [`crate::scene::DEFAULT_CLASSIFY_REVOLUTIONS`] = 400 revolutions by default, where `K` is
//! within 0.05 of its limit on these maps — and doubled up to four times that while `K` falls
//! between the thresholds below (`super::lengthen`: on a rub's chaotic response `K` at 400
//! points moved 0.87 → 0.68 under a round-off change, and read 0.95–0.99 at 800–1600). A response is called quasi-periodic for `K <` [`K_REGULAR`] = 0.2
//! and chaotic for `K >` [`K_CHAOTIC`] = 0.8 — margins of more than twice the largest
//! finite-`N` deviation measured at 200 points; between the two (weak or intermittent chaos, a
//! torus breaking up) it is `undetermined`.
//!
//! # What is not called quasi-periodic
//!
//! A response with a period above [`super::MAX_PERIOD`] has `K ≈ 0`; its Poincaré points repeat
//! after that period, which [`section_period`] looks for first (up to a quarter of the window),
//! and it reads `periodic` with [`Dynamics::long_period`]. A regular window whose transient is
//! still dying out (`steady = false` and its changes halving or faster from one third of the
//! window to the next, [`super::steady::Stationarity::decay`] < [`SETTLING_DECAY`]) is
//! `undetermined`: it is converging, to what the window cannot tell.

use super::steady::Stationarity;
use crate::math::V2;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Number of frequencies `c` whose `K_c` the median is taken over (the 2009 paper's 100).
pub const ZERO_ONE_FREQUENCIES: usize = 100;
/// Fewest Poincaré points the 0–1 test is applied to; a shorter window is `undetermined`.
pub const MIN_SECTION_POINTS: usize = 200;
/// Below this median `K` a response that is not periodic is quasi-periodic.
pub const K_REGULAR: f64 = 0.2;
/// Above this median `K` a response is chaotic.
pub const K_CHAOTIC: f64 = 0.8;
/// A regular window that is not steady and whose changes decay faster than this ratio per third
/// of the window is still settling (`undetermined`).
pub const SETTLING_DECAY: f64 = 0.5;

/// The kind of a steady response.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "kebab-case")]
pub enum Regime {
    /// Periodic with a Poincaré period 1 … [`super::MAX_PERIOD`].
    #[default]
    Periodic,
    /// Not periodic, regular: the 0–1 test's `K <` [`K_REGULAR`].
    QuasiPeriodic,
    /// Not periodic, chaotic: `K >` [`K_CHAOTIC`].
    Chaotic,
    /// Not periodic and not told apart: too few section points, `K` between the thresholds,
    /// or a regular window still settling.
    Undetermined,
    /// Not periodic in its window and running away when continued: the run lengthened for the
    /// 0–1 test left every bound of the divergence guard ([`Dynamics::runaway_at_s`]); the
    /// results are those of the window before the lengthening (`steady = false`).
    Diverging,
}

impl Regime {
    /// `periodic`, `quasi-periodic`, `chaotic`, `undetermined` or `diverging` (the `regime` of sweep.csv and
    /// summary.json).
    pub fn name(self) -> &'static str {
        match self {
            Regime::Periodic => "periodic",
            Regime::QuasiPeriodic => "quasi-periodic",
            Regime::Chaotic => "chaotic",
            Regime::Undetermined => "undetermined",
            Regime::Diverging => "diverging",
        }
    }
}

/// The regime of a run and what it was told from.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct Dynamics {
    /// The regime.
    pub regime: Regime,
    /// Median `K` of the 0–1 test on the Poincaré section ([`zero_one_k`]); `None` for a
    /// periodic run or a window of fewer than [`MIN_SECTION_POINTS`] points.
    pub zero_one_k: Option<f64>,
    /// Poincaré points the test had (the analysed window's revolutions).
    pub section_points: usize,
    /// A period above [`super::MAX_PERIOD`] found on the Poincaré points alone
    /// ([`section_period`]): the run is periodic although its `period` reads 0.
    #[serde(default)]
    pub long_period: Option<usize>,
    /// Time (s, from the start of the run) at which the run, lengthened past its window for
    /// the 0–1 test, left the divergence guard's bounds ([`Regime::Diverging`]); `None` when it
    /// did not run away or was not lengthened.
    #[serde(default)]
    pub runaway_at_s: Option<f64>,
}

/// The smallest period `q` in `MAX_PERIOD + 1 ..= N/4` of the `N` Poincaré points `section`
/// (revolutions): `max_i |P_{i+q} − P_i| / span ≤ tol`; `None` when none repeats. Four
/// repetitions at least, so that a slow drift does not pass for a period. (A period of the
/// section that the whole orbit does not share — loops crossing at the sampling phase — would
/// read here; below [`super::MAX_PERIOD`] the whole-orbit test rules it out.)
pub fn section_period(section: &[V2], span: f64, tol: f64) -> Option<usize> {
    let n = section.len();
    if span <= 0.0 {
        return None;
    }
    (super::MAX_PERIOD + 1..=n / 4).find(|&q| {
        (0..n - q).all(|i| {
            let (a, b) = (section[i], section[i + q]);
            (a[0] - b[0]).hypot(a[1] - b[1]) <= tol * span
        })
    })
}

/// The regime of a window of Poincaré period `period` (0: not periodic) whose Poincaré points
/// are `section` (one per revolution, of an orbit of size `span`), with the window's
/// stationarity `stn`, steady-state verdict `steady` and the tolerance `tol` its period was
/// judged to; `component` is the coordinate the 0–1 test reads (see the module's documentation
/// for the rule).
pub fn dynamics(
    period: usize,
    section: &[V2],
    component: usize,
    span: f64,
    tol: f64,
    stn: &Stationarity,
    steady: bool,
) -> Dynamics {
    let n = section.len();
    if period > 0 {
        return Dynamics {
            regime: Regime::Periodic,
            zero_one_k: None,
            section_points: n,
            long_period: None,
            runaway_at_s: None,
        };
    }
    if let Some(q) = section_period(section, span, tol) {
        return Dynamics {
            regime: Regime::Periodic,
            zero_one_k: None,
            section_points: n,
            long_period: Some(q),
            runaway_at_s: None,
        };
    }
    let phi: Vec<f64> = section.iter().map(|p| p[component.min(1)]).collect();
    if n < MIN_SECTION_POINTS {
        return Dynamics {
            regime: Regime::Undetermined,
            zero_one_k: None,
            section_points: n,
            long_period: None,
            runaway_at_s: None,
        };
    }
    let k = zero_one_k(&phi);
    let settling = !steady && stn.decay.is_finite() && stn.decay < SETTLING_DECAY;
    let regime = if k > K_CHAOTIC {
        Regime::Chaotic
    } else if k < K_REGULAR && !settling {
        Regime::QuasiPeriodic
    } else {
        Regime::Undetermined
    };
    Dynamics {
        regime,
        zero_one_k: Some(k),
        section_points: n,
        long_period: None,
        runaway_at_s: None,
    }
}

/// Whether a window classified `d` (with its point-by-point stationarity `stn` and verdict
/// `steady`) is a response that never repeats and is not settling: quasi-periodic, chaotic, or
/// undetermined by a `K` between the thresholds on at least [`MIN_SECTION_POINTS`] points
/// without a decaying transient. Its stationarity and error are those of an attractor's
/// statistics ([`super::steady::judge_attractor`]), not of a repeating orbit.
pub fn never_repeats(d: &Dynamics, stn: &Stationarity, steady: bool) -> bool {
    let settling = !steady && stn.decay.is_finite() && stn.decay < SETTLING_DECAY;
    match d.regime {
        Regime::QuasiPeriodic | Regime::Chaotic => true,
        Regime::Undetermined => d.zero_one_k.is_some() && !settling,
        _ => false,
    }
}

/// The median `K` of the 0–1 test for chaos (correlation method) of the sequence `phi` over
/// [`ZERO_ONE_FREQUENCIES`] frequencies `c` in `(π/5, 4π/5)` (module documentation); 0 for a
/// constant sequence or fewer than 20 values (no displacement to correlate).
pub fn zero_one_k(phi: &[f64]) -> f64 {
    let n = phi.len();
    let ncut = n / 10;
    if ncut < 2 {
        return 0.0;
    }
    let mean = phi.iter().sum::<f64>() / n as f64;
    let x: Vec<f64> = phi.iter().map(|v| v - mean).collect();
    if x.iter().all(|v| v.abs() <= 1e-300) {
        return 0.0;
    }
    let mut rng = SplitMix(0x05ee_d0fc_4a05);
    let mut ks: Vec<f64> = (0..ZERO_ONE_FREQUENCIES)
        .map(|_| {
            let c = PI / 5.0 + rng.unit() * 3.0 * PI / 5.0;
            k_of_c(&x, c, ncut)
        })
        .collect();
    ks.sort_by(f64::total_cmp);
    let m = ks.len();
    if m % 2 == 1 {
        ks[m / 2]
    } else {
        0.5 * (ks[m / 2 - 1] + ks[m / 2])
    }
}

/// `K_c`: the correlation of `M_c(n)` with `n`, `n = 1 … ncut`, for the zero-mean `x`.
fn k_of_c(x: &[f64], c: f64, ncut: usize) -> f64 {
    let n = x.len();
    let mut p = Vec::with_capacity(n + 1);
    let mut q = Vec::with_capacity(n + 1);
    let (mut ps, mut qs) = (0.0, 0.0);
    p.push(0.0);
    q.push(0.0);
    for (j, v) in x.iter().enumerate() {
        let a = (j + 1) as f64 * c;
        ps += v * a.cos();
        qs += v * a.sin();
        p.push(ps);
        q.push(qs);
    }
    let msd: Vec<f64> = (1..=ncut)
        .map(|lag| {
            let terms = n - lag;
            (1..=terms)
                .map(|j| (p[j + lag] - p[j]).powi(2) + (q[j + lag] - q[j]).powi(2))
                .sum::<f64>()
                / terms as f64
        })
        .collect();
    let xi: Vec<f64> = (1..=ncut).map(|v| v as f64).collect();
    correlation(&xi, &msd)
}

/// Pearson correlation coefficient of two equal-length sequences (0 when either is constant).
fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma).powi(2);
        sbb += (y - mb).powi(2);
    }
    if saa <= 0.0 || sbb <= 0.0 {
        0.0
    } else {
        sab / (saa * sbb).sqrt()
    }
}

/// SplitMix64 (Steele, Lea, Flood 2014): the fixed-seed draws of `c`.
struct SplitMix(u64);

impl SplitMix {
    /// A uniform draw in [0, 1).
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn logistic(r: f64, n: usize) -> Vec<f64> {
        let mut x = 0.3;
        for _ in 0..1000 {
            x = r * x * (1.0 - x);
        }
        (0..n)
            .map(|_| {
                x = r * x * (1.0 - x);
                x
            })
            .collect()
    }

    fn henon(n: usize) -> Vec<f64> {
        let (mut x, mut y) = (0.1, 0.1);
        for _ in 0..1000 {
            (x, y) = (1.0 - 1.4 * x * x + y, 0.3 * x);
        }
        (0..n)
            .map(|_| {
                (x, y) = (1.0 - 1.4 * x * x + y, 0.3 * x);
                x
            })
            .collect()
    }

    /// Two incommensurate frequencies per step (the section of a 2-torus sampled once per
    /// revolution: ω₂/ω = golden mean, plus √2 of it).
    fn torus(n: usize) -> Vec<f64> {
        let g = 0.5 * (5f64.sqrt() - 1.0);
        (0..n)
            .map(|j| {
                let t = j as f64;
                (2.0 * PI * g * t).cos() + 0.4 * (2.0 * PI * 2f64.sqrt() * g * t + 0.3).sin()
            })
            .collect()
    }

    #[test]
    fn zero_one_k_tells_regular_from_chaotic() {
        for n in [MIN_SECTION_POINTS, 400, 1000] {
            let kq = zero_one_k(&torus(n));
            let kp = zero_one_k(
                &(0..n)
                    .map(|j| (2.0 * PI * j as f64 * 4.0 / 11.0).sin() + [0.3, -1.0, 0.7][j % 3])
                    .collect::<Vec<_>>(),
            );
            let kl = zero_one_k(&logistic(3.97, n));
            let kh = zero_one_k(&henon(n));
            eprintln!("N {n}: torus {kq:.4} period-33 {kp:.4} logistic {kl:.4} henon {kh:.4}");
            // At the fewest points the decision thresholds hold; from 400 points on, K is
            // within 0.05 of its limit.
            let (lo, hi) = if n < 400 {
                (K_REGULAR, K_CHAOTIC)
            } else {
                (0.05, 0.95)
            };
            assert!(kq < lo, "N {n}: torus K {kq}");
            assert!(kp < lo, "N {n}: period-33 K {kp}");
            assert!(kl > hi, "N {n}: logistic K {kl}");
            assert!(kh > hi, "N {n}: Hénon K {kh}");
        }
        // The logistic map's periodic window at r = 3.83 (period 3) is regular.
        assert!(zero_one_k(&logistic(3.83, 300)) < 0.05);
        assert_eq!(zero_one_k(&[1.0; 300]), 0.0);
    }
}
