//! What the analysed window of a run can claim: whether its transient has died out
//! ([`stationarity`]), which Poincaré period it has and how surely ([`classify`]), and its
//! spectral lines read where the window resolves them ([`lines_revolutions`],
//! [`crate::signal::line_exact`]).
//!
//! Everything works on the window's samples `X_i` (non-dimensional, `spr` samples per
//! revolution, a whole number of revolutions) and judges sizes relative to the orbit's size
//! `span = max(x_max − x_min, y_max − y_min)`.

use crate::math::V2;
use crate::signal::extents;
#[cfg(test)]
use crate::signal::line_exact;
use serde::{Deserialize, Serialize};

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
    }
}

/// Hausdorff distance between two point sets (0 when either is empty).
fn hausdorff(a: &[V2], b: &[V2]) -> f64 {
    let one = |a: &[V2], b: &[V2]| {
        a.iter()
            .map(|p| {
                b.iter()
                    .map(|q| (p[0] - q[0]).hypot(p[1] - q[1]))
                    .fold(f64::INFINITY, f64::min)
            })
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max)
    };
    one(a, b).max(one(b, a))
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
            .map(|i| {
                let (a, b) = (w[i], w[i + lag]);
                (a[0] - b[0]).hypot(a[1] - b[1])
            })
            .fold(0.0, f64::max)
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

/// Least common multiple.
fn lcm(a: usize, b: usize) -> usize {
    a / crate::math::gcd(a, b) * b
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
