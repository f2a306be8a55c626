//! What the analysed window of a run can claim: whether its transient has died out
//! ([`stationarity`]), which Poincaré period it has and how surely ([`classify`]), and its
//! spectral lines read where the window resolves them ([`lines_revolutions`],
//! [`crate::signal::line_exact`]).
//!
//! Everything works on the window's samples `X_i` (non-dimensional, `spr` samples per
//! revolution, a whole number of revolutions) and judges sizes relative to the orbit's size
//! `span = max(x_max − x_min, y_max − y_min)`.

use crate::math::{lcm, V2};
use crate::signal::extents;
#[cfg(test)]
use crate::signal::line_exact;
use serde::{Deserialize, Serialize};

/// Blocks the window of a response that never repeats is cut into for the spread of its
/// extents ([`attractor_stationarity`]).
pub const SAMPLING_BLOCKS: usize = 8;

/// Largest confidence reported ([`Classification::confidence`]).
pub const MAX_CONFIDENCE: f64 = 1e6;

/// How stationary the analysed window is: its first, middle and last thirds compared.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Stationarity {
    /// Estimated error of the window's extents and Poincaré section due to what is left of
    /// the transient, relative to the orbit's size (see [`stationarity`]); +∞ when the window
    /// is too short to tell (fewer than 3 revolutions).
    pub residual: f64,
    /// Ratio of the changes between consecutive thirds, `d₂/d₁` (a geometric decay when
    /// below 1; NaN when `d₁` = 0).
    pub decay: f64,
    /// Revolutions of one third.
    pub block_revolutions: usize,
    /// The statistics of the two halves of a window that is quasi-periodic or chaotic
    /// ([`attractor_stationarity`]); `residual` is then theirs. `None` for other windows.
    #[serde(default)]
    pub attractor: Option<AttractorStationarity>,
}

/// How stationary a window that never repeats is, from the statistics of its two halves
/// ([`attractor_stationarity`]); sizes relative to the orbit's size `span`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AttractorStationarity {
    /// `max_k |m_A,k − m_B,k| / span`: the largest change between the halves A, B of the mean
    /// per-revolution extent `m_k` (k over x_min, x_max, y_min, y_max).
    pub mean_change: f64,
    /// The sampling deviation of that change, `3 s_k √(1/4 + 1/4) / span`, s_k the scatter of
    /// the means over [`SAMPLING_BLOCKS`] blocks about their linear trend (batch means), at the
    /// `k` of the largest excess `|m_A,k − m_B,k| − 3 s_k/√2`.
    pub mean_sampling: f64,
    /// The sampling uncertainty of the window's extents, relative to `span`: the larger of
    /// `max_k |X_A,k − X_B,k|` (X the extents of each half) and the batch-means standard error
    /// `max_k sd_b(X_b,k)/√B` of the extents X_b of the B blocks (the error estimate of such a
    /// run uses it).
    pub extents_sampling: f64,
}

impl Stationarity {
    /// Revolutions more of transient after which the residual is expected below `tol / 2`,
    /// from the geometric decay `decay` per third; one window (3 thirds) when the changes do
    /// not decay.
    pub fn revolutions_needed(&self, tol: f64) -> usize {
        let b = self.block_revolutions.max(1);
        if self.decay.is_finite() && self.decay > 0.0 && self.decay < 1.0 && self.residual > 0.0 {
            let thirds = ((0.5 * tol / self.residual).ln() / self.decay.ln()).max(1.0);
            // 20 % margin, whole revolutions, at least one third.
            ((1.2 * thirds * b as f64).ceil() as usize).max(b)
        } else {
            3 * b
        }
    }
}

/// The stationarity of a window of `nrev` revolutions of `spr` samples each (`w.len() ≥
/// nrev·spr`), relative to the orbit size `span`.
///
/// The window is cut in thirds (the last one takes the remainder); of each third `j` the
/// extents `E_j` and the Poincaré section `P_j` (the samples at whole revolutions) are taken.
/// A periodic response of period `p ≤` a third covers its whole orbit in every third, so `E_j`
/// and `P_j` are equal; a decaying transient changes them. The change between thirds is
/// `d_j = max(max_k |E_j,k − E_j+1,k|, H(P_j, P_j+1)) / span` (H the Hausdorff distance).
/// When `d₂ < d₁` the transient is taken as geometric with ratio `ρ = d₂/d₁` per third and the
/// window's error (its extents are those of its first third, the largest) is the Aitken tail
/// `d₁ / (1 − ρ)`; otherwise (no decay: a response that never repeats, or growth) the residual
/// is `max(d₁, d₂)`.
pub fn stationarity(w: &[V2], spr: usize, nrev: usize, span: f64) -> Stationarity {
    let b = nrev / 3;
    if b == 0 || spr == 0 || span <= 0.0 || w.len() < nrev * spr {
        return Stationarity {
            residual: if span > 0.0 { f64::INFINITY } else { 0.0 },
            decay: f64::NAN,
            block_revolutions: b,
            attractor: None,
        };
    }
    let bounds = [0, b * spr, 2 * b * spr, nrev * spr];
    let blocks: Vec<(&[V2], Vec<V2>)> = (0..3)
        .map(|j| {
            let s = &w[bounds[j]..bounds[j + 1]];
            (s, s.iter().step_by(spr).copied().collect())
        })
        .collect();
    let change = |a: &(&[V2], Vec<V2>), c: &(&[V2], Vec<V2>)| {
        let (ea, ec) = (extents(a.0), extents(c.0));
        let de = (0..4).map(|k| (ea[k] - ec[k]).abs()).fold(0.0, f64::max);
        de.max(hausdorff(&a.1, &c.1)) / span
    };
    let d1 = change(&blocks[0], &blocks[1]);
    let d2 = change(&blocks[1], &blocks[2]);
    let decay = if d1 > 0.0 { d2 / d1 } else { f64::NAN };
    let residual = if decay < 1.0 {
        d1 / (1.0 - decay)
    } else {
        d1.max(d2)
    };
    Stationarity {
        residual,
        decay,
        block_revolutions: b,
        attractor: None,
    }
}

/// The stationarity of a window that never repeats (quasi-periodic or chaotic), judged as the
/// statistics of an attractor are: not point by point (a finite sample of a closed curve or of
/// a strange attractor is not the same set in two parts of the window), but by the
/// distribution of its per-revolution extents in the two halves of the window.
///
/// Of every revolution j of the window (`nrev` revolutions of `spr` samples) the extents
/// `e_j = [x_min, x_max, y_min, y_max]` are taken and averaged over [`SAMPLING_BLOCKS`] blocks
/// (batch means, which carry the correlation of successive revolutions). A stationary response
/// has the mean of its first half of blocks within the blocks' scatter of the mean of its
/// second (a quasi-periodic sequence is equidistributed: its block means agree to O(1/n)); a
/// transient that grows or decays moves the halves apart by its trend, while the blocks'
/// scatter is taken about their linear trend, so that the trend does not widen the tolerance.
/// Returns the statistics and the residual `max_k max(0, |m_A,k − m_B,k| − 3 s_k/√2) / span`:
/// the change the sampling does not explain (0 for a stationary window). `None` below 8
/// revolutions or for a point.
pub fn attractor_stationarity(
    w: &[V2],
    spr: usize,
    nrev: usize,
    span: f64,
) -> Option<(AttractorStationarity, f64)> {
    if nrev < 8 || spr == 0 || span <= 0.0 || w.len() < nrev * spr {
        return None;
    }
    let per_rev: Vec<[f64; 4]> = w[..nrev * spr].chunks(spr).map(extents).collect();
    let a = &per_rev[..nrev / 2];
    let stats = |h: &[[f64; 4]], k: usize| {
        let n = h.len() as f64;
        let m = h.iter().map(|e| e[k]).sum::<f64>() / n;
        let v = h.iter().map(|e| (e[k] - m).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
        (m, v / n)
    };
    let (ea, eb) = (
        extents(&w[..a.len() * spr]),
        extents(&w[a.len() * spr..nrev * spr]),
    );
    // Batch means: the extents of blocks of an eighth of the window, the standard error of
    // their mean, √(s²/B) over the B blocks.
    let nb = (nrev / SAMPLING_BLOCKS).max(1);
    let blocks: Vec<[f64; 4]> = per_rev
        .chunks(nb)
        .filter(|c| c.len() == nb)
        .map(|c| {
            let mut e = c[0];
            for x in &c[1..] {
                e = [
                    e[0].min(x[0]),
                    e[1].max(x[1]),
                    e[2].min(x[2]),
                    e[3].max(x[3]),
                ];
            }
            e
        })
        .collect();
    let spread = (0..4)
        .map(|k| stats(&blocks, k).1.sqrt())
        .fold(0.0, f64::max);
    let halves = (0..4).map(|k| (ea[k] - eb[k]).abs()).fold(0.0, f64::max);
    let mut out = AttractorStationarity {
        mean_change: 0.0,
        mean_sampling: 0.0,
        extents_sampling: halves.max(spread) / span,
    };
    // The means of the per-revolution extents over the blocks (batch means): the change
    // between the halves against the blocks' scatter about their linear trend.
    let nbl = blocks.len();
    let mut excess = f64::NEG_INFINITY;
    for k in 0..4 {
        let mb: Vec<f64> = per_rev
            .chunks(nb)
            .take(nbl)
            .map(|c| c.iter().map(|e| e[k]).sum::<f64>() / c.len() as f64)
            .collect();
        let h = nbl / 2;
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
        let d = (mean(&mb[..h]) - mean(&mb[h..])).abs() / span;
        let dev = 3.0 * detrended_sd(&mb) * (1.0 / h as f64 + 1.0 / (nbl - h) as f64).sqrt() / span;
        out.mean_change = out.mean_change.max(d);
        if d - dev > excess {
            excess = d - dev;
            out.mean_sampling = dev;
        }
    }
    Some((out, excess.max(0.0)))
}

/// The stationarity of a window classified quasi-periodic or chaotic (`never_repeats`): its
/// [`attractor_stationarity`] replaces the point-by-point residual of [`stationarity`] in `stn`,
/// and the window is steady when that residual is within `tol`. Other windows, and windows too
/// short for the halves, keep `(stn, steady)`.
#[allow(clippy::too_many_arguments)]
pub fn judge_attractor(
    never_repeats: bool,
    stn: Stationarity,
    steady: bool,
    w: &[V2],
    spr: usize,
    nrev: usize,
    span: f64,
    tol: f64,
) -> (Stationarity, bool) {
    match attractor_stationarity(w, spr, nrev, span) {
        Some((a, residual)) if never_repeats => (
            Stationarity {
                residual,
                attractor: Some(a),
                ..stn
            },
            residual <= tol,
        ),
        _ => (stn, steady),
    }
}

/// Standard deviation of `v` about its least-squares line over the index (n − 2 degrees of
/// freedom; 0 below 3 values).
fn detrended_sd(v: &[f64]) -> f64 {
    let n = v.len();
    if n < 3 {
        return 0.0;
    }
    let nf = n as f64;
    let xm = (nf - 1.0) / 2.0;
    let ym = v.iter().sum::<f64>() / nf;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (i, y) in v.iter().enumerate() {
        sxy += (i as f64 - xm) * (y - ym);
        sxx += (i as f64 - xm).powi(2);
    }
    let b = sxy / sxx;
    let ss: f64 = v
        .iter()
        .enumerate()
        .map(|(i, y)| (y - ym - b * (i as f64 - xm)).powi(2))
        .sum();
    (ss / (nf - 2.0)).sqrt()
}

/// Hausdorff distance between two point sets (0 when either is empty), from squared
/// distances and one square root (the points are orbit positions, far inside the range where
/// x² neither overflows nor underflows to a wrong result; `crate::math::norm`).
fn hausdorff(a: &[V2], b: &[V2]) -> f64 {
    let one = |a: &[V2], b: &[V2]| {
        a.iter()
            .map(|p| b.iter().map(|q| dist2(p, q)).fold(f64::INFINITY, f64::min))
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max)
    };
    one(a, b).max(one(b, a)).sqrt()
}

/// Squared distance of two plane points.
#[inline]
fn dist2(a: &V2, b: &V2) -> f64 {
    let (x, y) = (a[0] - b[0], a[1] - b[1]);
    x * x + y * y
}

/// The Poincaré period of a window and how surely it was told.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Classification {
    /// Period 1–`max_period` in revolutions, 0 when not periodic.
    pub period: usize,
    /// `r_p = max_i |X_{i+p·spr} − X_i| / span` of the period found: how closely the whole
    /// orbit (every sample of a revolution, not only the Poincaré point) repeats after `p`
    /// revolutions; for a response that is not periodic, the smallest `r_q` over the periods
    /// tried.
    pub repeat_residual: f64,
    /// The smallest `r_q` of the shorter periods `q < p` that were rejected (+∞ for p = 1;
    /// for a response that is not periodic, the same as `repeat_residual`).
    pub rejected_residual: f64,
    /// Tolerance the residuals were judged against (relative to the orbit's size).
    pub tolerance: f64,
    /// The factor by which the tolerance could be multiplied or divided without changing the
    /// period: `min(tol / r_p, r_q,min / tol)` (periodic), `r_min / tol` (not periodic); at
    /// most [`MAX_CONFIDENCE`]. Near 1 the period is borderline.
    pub confidence: f64,
}

/// The smallest period `p ∈ 1..=max_period` whose whole-orbit repetition residual
/// `r_p = max_i |X_{i+p·spr} − X_i| / span` is at most `tol`, over a window of `nrev`
/// revolutions (`p` is tried only when the window holds `2p` revolutions).
///
/// Comparing every sample of the revolutions (not only the once-per-revolution point) makes a
/// period-2 orbit whose two loops cross at the sampling phase read 2, not 1: a sub-harmonic
/// line of amplitude `a` gives `r ≥ 2a/span` for every period it does not divide.
pub fn classify(
    w: &[V2],
    spr: usize,
    nrev: usize,
    span: f64,
    tol: f64,
    max_period: usize,
) -> Classification {
    let n = (nrev * spr).min(w.len());
    let mut rejected = f64::INFINITY;
    let mut best = f64::INFINITY;
    if span <= 0.0 || n == 0 {
        // A point: every period fits.
        return Classification {
            period: usize::from(n > 0),
            repeat_residual: 0.0,
            rejected_residual: f64::INFINITY,
            tolerance: tol,
            confidence: MAX_CONFIDENCE,
        };
    }
    for p in 1..=max_period {
        if nrev < 2 * p {
            break;
        }
        let lag = p * spr;
        let r = (0..n - lag)
            .map(|i| dist2(&w[i], &w[i + lag]))
            .fold(0.0, f64::max)
            .sqrt()
            / span;
        if r <= tol {
            let c = (tol / r.max(1e-300)).min(rejected / tol);
            return Classification {
                period: p,
                repeat_residual: r,
                rejected_residual: rejected,
                tolerance: tol,
                confidence: c.min(MAX_CONFIDENCE),
            };
        }
        rejected = rejected.min(r);
        best = best.min(r);
    }
    Classification {
        period: 0,
        repeat_residual: best,
        rejected_residual: best,
        tolerance: tol,
        confidence: (best / tol).min(MAX_CONFIDENCE),
    }
}

/// What a window of `nrev` revolutions (`spr` samples each) claims at the relative tolerance
/// `tol`: its [`stationarity`], whether it is steady (residual ≤ `tol`), and its period
/// ([`classify`] up to `max_period`, judged to `tol` plus twice the residual of a steady window:
/// what is left of the transient makes revolutions differ by up to twice its size). The one
/// rule of the run's analysis and of its decision to lengthen a window that is not periodic.
pub fn judge(
    w: &[V2],
    spr: usize,
    nrev: usize,
    tol: f64,
    max_period: usize,
) -> (Stationarity, bool, Classification) {
    let e = extents(w);
    let span = (e[1] - e[0]).max(e[3] - e[2]);
    let stn = stationarity(w, spr, nrev, span);
    let steady = stn.residual <= tol;
    let period_tol = tol + if steady { 2.0 * stn.residual } else { 0.0 };
    (
        stn,
        steady,
        classify(w, spr, nrev, span, period_tol, max_period),
    )
}

/// Revolutions over which the lines of a response of Poincaré period `period` (0: not
/// periodic) are read from a window of `nrev` revolutions: the largest multiple of
/// `lcm(6, period)` (of 6 when not periodic) not above `nrev`, so that ½×, ⅓× and every line of
/// the period fall on exact bins; `(revolutions, true)`, or `(the largest multiple of 6, false)`
/// when the window is shorter than `lcm(6, period)` (`(nrev, false)` below 6).
pub fn lines_revolutions(nrev: usize, period: usize) -> (usize, bool) {
    let l = lcm(6, period.max(1));
    if nrev >= l {
        (nrev / l * l, true)
    } else if nrev >= 6 {
        (nrev / 6 * 6, false)
    } else {
        (nrev, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn orbit(spr: usize, nrev: usize, f: impl Fn(f64) -> V2) -> Vec<V2> {
        (0..spr * nrev)
            .map(|i| f(2.0 * PI * i as f64 / spr as f64))
            .collect()
    }

    #[test]
    fn a_period_two_crossing_at_the_section_reads_two() {
        // x = cos θ + 0.5 sin(θ/2): the ½× term vanishes at every Poincaré instant θ = 2πk.
        let w = orbit(64, 24, |t| [t.cos() + 0.5 * (t / 2.0).sin(), t.sin()]);
        let e = extents(&w);
        let span = (e[1] - e[0]).max(e[3] - e[2]);
        let c = classify(&w, 64, 24, span, 1e-3, 8);
        assert_eq!(c.period, 2);
        assert!(c.rejected_residual > 0.3, "{c:?}");
        let x: Vec<f64> = w.iter().map(|p| p[0]).collect();
        assert!((line_exact(&x, 64, 0.5) - 0.5).abs() < 1e-12);
        assert!((line_exact(&x, 64, 1.0) - 1.0).abs() < 1e-12);
        assert!(line_exact(&x, 64, 1.0 / 3.0) < 1e-12);
    }

    #[test]
    fn stationarity_sees_a_decaying_transient_and_its_tail() {
        // 1× orbit plus a free whirl at 0.37 of the speed decaying by q per revolution.
        let q: f64 = 0.97;
        let w = orbit(64, 120, |t| {
            let a = 0.2 * q.powf(t / (2.0 * PI));
            [
                t.cos() + a * (0.37 * t).cos(),
                t.sin() + a * (0.37 * t).sin(),
            ]
        });
        let s = stationarity(&w, 64, 120, 2.0);
        // The window's first third carries ≈ 0.2 / 2 of transient on its extents.
        assert!(s.residual > 0.05 && s.residual < 0.3, "{s:?}");
        assert!((s.decay - q.powi(40)).abs() < 0.1, "{s:?}");
        let steady = orbit(64, 120, |t| [t.cos(), 0.5 * t.sin()]);
        assert!(stationarity(&steady, 64, 120, 2.0).residual < 1e-12);
        assert!(stationarity(&steady, 64, 2, 2.0).residual.is_infinite());
    }

    /// A torus (1× circle plus a free whirl at 1/√2 of the speed) is a stationary response whose
    /// thirds are not the same finite sample of its closed curve: the point-by-point residual
    /// reads it unsteady, the halves' statistics steady. The same torus with a free whirl
    /// growing by half over the window, or dying out, is not steady; nor is a chaotic-like
    /// sequence of circles whose radius drifts.
    #[test]
    fn an_attractor_is_steady_by_its_statistics_and_a_transient_is_not() {
        let w0 = 0.5f64.sqrt();
        let torus = |grow: f64| {
            orbit(64, 400, move |t| {
                let a = 0.1 * (1.0 + grow * t / (2.0 * PI * 400.0));
                [t.cos() + a * (w0 * t).cos(), t.sin() + a * (w0 * t).sin()]
            })
        };
        let span = 2.2;
        let still = torus(0.0);
        let point = stationarity(&still, 64, 400, span);
        assert!(point.residual > 1e-3, "{point:?}");
        let (a, residual) = attractor_stationarity(&still, 64, 400, span).unwrap();
        assert_eq!(residual, 0.0, "{a:?}");
        assert!(a.mean_change < 1e-3, "{a:?}");
        let (st, steady) = judge_attractor(true, point, false, &still, 64, 400, span, 1e-3);
        assert!(steady && st.residual == 0.0 && st.attractor.is_some());
        // Not a response that never repeats: the point-by-point verdict stands.
        assert!(!judge_attractor(false, point, false, &still, 64, 400, span, 1e-3).1);
        for grow in [0.5, -0.5] {
            let (a, residual) = attractor_stationarity(&torus(grow), 64, 400, span).unwrap();
            assert!(residual > 1e-3, "growth {grow}: {a:?} {residual}");
        }
        // Circles of a chaotic radius r_{j+1} = 4 r_j (1 − r_j) (logistic map), steady, and
        // drifting by 20 % over the window.
        let circles = |drift: f64| {
            let mut r = 0.3;
            let mut w = Vec::new();
            for j in 0..400 {
                r = 4.0 * r * (1.0 - r);
                let rad = (1.0 + 0.2 * r) * (1.0 + drift * j as f64 / 400.0);
                w.extend((0..64).map(|i| {
                    let t = 2.0 * PI * i as f64 / 64.0;
                    [rad * t.cos(), rad * t.sin()]
                }));
            }
            w
        };
        let (a, residual) = attractor_stationarity(&circles(0.0), 64, 400, 2.4).unwrap();
        assert_eq!(residual, 0.0, "{a:?}");
        assert!(
            a.extents_sampling > 0.0 && a.extents_sampling < 0.05,
            "{a:?}"
        );
        let (a, residual) = attractor_stationarity(&circles(0.2), 64, 400, 2.4).unwrap();
        assert!(residual > 1e-3, "{a:?} {residual}");
    }

    #[test]
    fn lines_need_a_window_of_their_periods() {
        assert_eq!(lines_revolutions(120, 1), (120, true));
        assert_eq!(lines_revolutions(122, 4), (120, true));
        assert_eq!(lines_revolutions(20, 4), (12, true));
        assert_eq!(lines_revolutions(10, 4), (6, false));
        assert_eq!(lines_revolutions(4, 2), (4, false));
        assert_eq!(lines_revolutions(6, 0), (6, true));
    }
}
