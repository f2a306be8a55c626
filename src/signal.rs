//! Signal analysis of recorded responses: Poincaré period, Hann-windowed spectra, extents.
//!
//! Works on plain slices sampled a whole number of times per revolution, so the 1×, 1/2×, 1/3×
//! lines of a record spanning a multiple of 6 revolutions fall exactly on FFT bins.

use crate::math::V2;
use realfft::RealFftPlanner;

/// Smallest period `p ∈ 1..=max_period` (in revolutions) with
/// `max_k |P_{k+p} − P_k| ≤ rel_tol · span` over the once-per-revolution points `pts`, where
/// `span` is the orbit size. Returns 0 when none fits (not periodic: quasi-periodic or chaotic).
pub fn poincare_period(pts: &[V2], span: f64, max_period: usize, rel_tol: f64) -> usize {
    if pts.len() < 2 || span <= 0.0 {
        return if pts.is_empty() { 0 } else { 1 };
    }
    let tol = rel_tol * span;
    for p in 1..=max_period {
        if pts.len() <= 2 * p {
            break;
        }
        let ok = (0..pts.len() - p).all(|k| {
            let a = pts[k];
            let b = pts[k + p];
            (a[0] - b[0]).hypot(a[1] - b[1]) <= tol
        });
        if ok {
            return p;
        }
    }
    0
}

/// Single-sided amplitude spectrum of `x` with a periodic Hann window, after removing the mean.
///
/// Scaled so that a sine of amplitude `A` on a bin reads `A`: `|X_k| · 2 / Σw`. Returns the
/// amplitudes of bins `0..=N/2`; bin `k` is at frequency `k · fs / N`.
pub fn hann_spectrum(x: &[f64]) -> Vec<f64> {
    let n = x.len();
    if n < 2 {
        return vec![0.0; n];
    }
    let mean = x.iter().sum::<f64>() / n as f64;
    let mut buf: Vec<f64> = x
        .iter()
        .enumerate()
        .map(|(i, v)| {
            let w = 0.5 * (1.0 - (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos());
            (v - mean) * w
        })
        .collect();
    let wsum = n as f64 / 2.0;
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(n);
    let mut out = fft.make_output_vec();
    fft.process(&mut buf, &mut out)
        .expect("buffer sizes from the planner");
    out.iter().map(|c| 2.0 * c.norm() / wsum).collect()
}

/// Amplitude of the line at bin `k` (the largest of bins `k−1..=k+1`, to tolerate a record that
/// is not an exact multiple of the line's period).
pub fn line_amplitude(spec: &[f64], k: f64) -> f64 {
    let c = k.round() as isize;
    (c - 1..=c + 1)
        .filter(|i| *i > 0 && (*i as usize) < spec.len())
        .map(|i| spec[i as usize])
        .fold(0.0, f64::max)
}

/// `[x_min, x_max, y_min, y_max]` of a set of points.
pub fn extents(pts: &[V2]) -> [f64; 4] {
    pts.iter().fold(
        [
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ],
        |e, p| {
            [
                e[0].min(p[0]),
                e[1].max(p[0]),
                e[2].min(p[1]),
                e[3].max(p[1]),
            ]
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn sine_reads_its_amplitude_on_its_bin() {
        let n = 64 * 120;
        for (order, amp) in [(1.0, 2.5), (0.5, 0.7), (1.0 / 3.0, 0.2)] {
            let x: Vec<f64> = (0..n)
                .map(|i| 3.0 + amp * (2.0 * PI * order * i as f64 / 64.0 + 0.3).sin())
                .collect();
            let s = hann_spectrum(&x);
            let k = order * 120.0;
            let a = line_amplitude(&s, k);
            assert!((a - amp).abs() < 1e-9 * amp.max(1.0), "order {order}: {a}");
            assert_eq!(s[k.round() as usize], a);
            // DC removed
            assert!(s[0] < 1e-9);
        }
    }

    #[test]
    fn period_detection() {
        let p2: Vec<V2> = (0..40)
            .map(|k| if k % 2 == 0 { [1.0, 0.0] } else { [0.0, 1.0] })
            .collect();
        assert_eq!(poincare_period(&p2, 1.0, 8, 1e-3), 2);
        let p3: Vec<V2> = (0..40).map(|k| [(k % 3) as f64, 0.0]).collect();
        assert_eq!(poincare_period(&p3, 2.0, 8, 1e-3), 3);
        let p1: Vec<V2> = (0..40).map(|_| [0.5, 0.5]).collect();
        assert_eq!(poincare_period(&p1, 1.0, 8, 1e-3), 1);
        // Quasi-periodic: irrational rotation never repeats.
        let q: Vec<V2> = (0..40)
            .map(|k| {
                let a = 2.0 * PI * 0.618034 * k as f64;
                [a.cos(), a.sin()]
            })
            .collect();
        assert_eq!(poincare_period(&q, 2.0, 8, 1e-3), 0);
    }
}
