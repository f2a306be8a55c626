//! Signal analysis of recorded responses: Hann-windowed spectra, exact line amplitudes, extents.
//!
//! Works on plain slices sampled a whole number of times per revolution, so the 1×, 1/2×, 1/3×
//! lines of a record spanning a multiple of 6 revolutions fall exactly on FFT bins.

use crate::math::V2;
use realfft::RealFftPlanner;

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

/// Amplitude of the line of `order` cycles per revolution in `x` (`spr` samples per
/// revolution): `|2/N Σ_n (x_n − x̄) e^{−2πi·order·n/spr}|`, the rectangular-window DFT at the
/// line's exact frequency. Exact (no leakage) for a periodic signal when the record spans a
/// whole number of its periods and of the line's; `order · 6` must be a whole number (½×, ⅓×,
/// 1×, …; other orders are read at the nearest sixth).
pub fn line_exact(x: &[f64], spr: usize, order: f64) -> f64 {
    let n = x.len();
    if n == 0 || spr == 0 {
        return 0.0;
    }
    let mean = x.iter().sum::<f64>() / n as f64;
    // e^{−2πi·order·n/spr} = e^{−2πi·m/(6·spr)}, m = (6·order·n) mod 6·spr.
    let k = (order * 6.0).round().max(0.0) as usize;
    let period = 6 * spr;
    let step = 2.0 * std::f64::consts::PI / period as f64;
    let (mut re, mut im) = (0.0, 0.0);
    for (i, v) in x.iter().enumerate() {
        let m = (k * (i % period)) % period;
        let (s, c) = (step * m as f64).sin_cos();
        re += (v - mean) * c;
        im -= (v - mean) * s;
    }
    2.0 * re.hypot(im) / n as f64
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
            let a = line_exact(&x, 64, order);
            assert!((a - amp).abs() < 1e-9 * amp.max(1.0), "order {order}: {a}");
            assert!((s[k.round() as usize] - a).abs() < 1e-9, "order {order}");
            // DC removed
            assert!(s[0] < 1e-9);
        }
    }
}
