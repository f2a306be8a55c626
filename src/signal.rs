//! Signal analysis of recorded responses: Hann-windowed spectra, exact line amplitudes, the
//! full (two-sided) spectrum of the orbit `z = x + iy` ([`FullSpectrum`]), extents.
//!
//! Works on plain slices sampled a whole number of times per revolution, so the 1×, 1/2×, 1/3×
//! lines of a record spanning a multiple of 6 revolutions fall exactly on FFT bins.

use crate::math::V2;
use realfft::RealFftPlanner;
use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;
use std::cell::RefCell;

thread_local! {
    /// The FFT planners of this thread: they keep the plans they made, so the spectra of a
    /// sweep's windows (all of one length) are planned once per thread.
    static REAL_PLANNER: RefCell<RealFftPlanner<f64>> = RefCell::new(RealFftPlanner::new());
    static PLANNER: RefCell<FftPlanner<f64>> = RefCell::new(FftPlanner::new());
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
    let fft = REAL_PLANNER.with(|p| p.borrow_mut().plan_fft_forward(n));
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
    // The phases repeat every `period` samples: one sine and cosine per phase (the same
    // arguments as sample by sample, so the same sum).
    let phases: Vec<(f64, f64)> = (0..period.min(n))
        .map(|i| (step * ((k * i) % period) as f64).sin_cos())
        .collect();
    let (mut re, mut im) = (0.0, 0.0);
    for (i, v) in x.iter().enumerate() {
        let (s, c) = phases[i % period];
        re += (v - mean) * c;
        im -= (v - mean) * s;
    }
    2.0 * re.hypot(im) / n as f64
}

/// The full spectrum of an orbit: the DFT of the complex signal `z_n = x_n + i y_n` with a
/// rectangular window, after removing the mean,
/// `c_k = (1/N) Σ_n (z_n − z̄) e^{−2πi k n/N}`, for the signed bins `k` (`−N/2 < k ≤ N/2`).
///
/// **Sign convention.** A circular whirl in the sense of the spin (counter-clockwise seen from
/// +z, x towards y: *forward*) `z = A e^{+iωt}` is a line at `+ω`; a whirl against the spin
/// (*backward*) `z = A e^{−iωt}` is a line at `−ω`. `|c_k|` reads the radius `A` of that
/// circular component: an ellipse of semi-axes `a` (along x) and `b` (along y) traced forward,
/// `z = a cos ωt + i b sin ωt`, is `(a+b)/2` at `+ω` plus `(a−b)/2` at `−ω`.
///
/// **Window.** Rectangular, because the records analysed span a whole number of revolutions
/// (and of the Poincaré period): every harmonic of the spin speed Ω, and of Ω/p for a
/// period-p response, falls exactly on a bin and reads its exact amplitude, with no leakage.
/// A line between bins (a whirl not locked to Ω, e.g. dry whip) is located by the
/// three-bin interpolation of [`FullSpectrum::peaks`].
#[derive(Debug, Clone, Default)]
pub struct FullSpectrum {
    c: Vec<Complex64>,
}

/// A spectral line found by [`FullSpectrum::peaks`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    /// Its position in bins, signed (fractional: interpolated between bins).
    pub bin: f64,
    /// Its amplitude (the radius of its circular component).
    pub amp: f64,
}

impl FullSpectrum {
    /// The full spectrum of the orbit `z` (points `[x, y]`); see the type.
    pub fn new(z: &[V2]) -> Self {
        let n = z.len();
        if n == 0 {
            return Self::default();
        }
        let inv = 1.0 / n as f64;
        let mean = z.iter().fold([0.0, 0.0], |m, p| [m[0] + p[0], m[1] + p[1]]);
        let mut c: Vec<Complex64> = z
            .iter()
            .map(|p| Complex64::new((p[0] - mean[0] * inv) * inv, (p[1] - mean[1] * inv) * inv))
            .collect();
        PLANNER
            .with(|p| p.borrow_mut().plan_fft_forward(n))
            .process(&mut c);
        Self { c }
    }

    /// Number of samples N (and of bins).
    pub fn len(&self) -> usize {
        self.c.len()
    }

    /// True for the spectrum of no samples.
    pub fn is_empty(&self) -> bool {
        self.c.is_empty()
    }

    /// The coefficient `c_k` of the signed bin `k` (taken modulo N); 0 when empty.
    pub fn coef(&self, k: isize) -> Complex64 {
        let n = self.c.len() as isize;
        if n == 0 {
            return Complex64::new(0.0, 0.0);
        }
        self.c[k.rem_euclid(n) as usize]
    }

    /// The amplitude `|c_k|` of the signed bin `k`.
    pub fn amp(&self, k: isize) -> f64 {
        self.coef(k).norm()
    }

    /// The signed bins `−⌈N/2⌉ + 1 ..= ⌊N/2⌋` in ascending order with their amplitudes.
    pub fn signed(&self) -> impl Iterator<Item = (isize, f64)> + '_ {
        let n = self.c.len() as isize;
        (-(n - 1) / 2..=n / 2).map(move |k| (k, self.amp(k)))
    }

    /// The `count` strongest lines, strongest first (ties: lower bin first): the bins that are
    /// local maxima of `|c_k|` (`|c_{k−1}| ≤ |c_k| > |c_{k+1}|`) and above `floor` times the
    /// largest amplitude, each refined between bins by Candan's three-bin estimator for the
    /// rectangular window, `δ = tan(π/N)/(π/N) · Re[(c_{k−1} − c_{k+1}) / (2c_k − c_{k−1} −
    /// c_{k+1})]` (clamped to ±½), at `k + δ` with amplitude `|c_k| · N sin(πδ/N) / sin(πδ)`
    /// (the Dirichlet kernel's loss undone). A line on a bin (its neighbours empty) has δ = 0
    /// and its exact amplitude.
    pub fn peaks(&self, count: usize, floor: f64) -> Vec<Line> {
        let n = self.c.len();
        if n < 3 || count == 0 {
            return Vec::new();
        }
        // Squared amplitudes, compared once each.
        let sq: Vec<f64> = self.c.iter().map(|c| c.norm_sqr()).collect();
        let top = sq.iter().copied().fold(0.0, f64::max);
        if top <= 0.0 {
            return Vec::new();
        }
        let cut = floor * floor * top;
        let ni = n as isize;
        let mut lines: Vec<Line> = (-(ni - 1) / 2..=ni / 2)
            .filter(|&k| {
                let i = k.rem_euclid(ni) as usize;
                let a = sq[i];
                a > cut && sq[(i + n - 1) % n] <= a && sq[(i + 1) % n] < a
            })
            .map(|k| self.refine(k, self.amp(k)))
            .collect();
        lines.sort_by(|p, q| q.amp.total_cmp(&p.amp).then(p.bin.total_cmp(&q.bin)));
        lines.truncate(count);
        lines
    }

    /// The line at the local maximum `k` of amplitude `a`, refined (see [`Self::peaks`]).
    fn refine(&self, k: isize, a: f64) -> Line {
        let n = self.c.len() as f64;
        let (m, c, p) = (self.coef(k - 1), self.coef(k), self.coef(k + 1));
        let den = 2.0 * c - m - p;
        let x = std::f64::consts::PI / n;
        let delta = if den.norm() > 0.0 {
            (x.tan() / x * ((m - p) / den).re).clamp(-0.5, 0.5)
        } else {
            0.0
        };
        let gain = if delta.abs() > 1e-12 {
            let pd = std::f64::consts::PI * delta;
            (n * (pd / n).sin() / pd.sin()).abs()
        } else {
            1.0
        };
        Line {
            bin: k as f64 + delta,
            amp: a * gain,
        }
    }
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

    /// `n` samples over `revs` revolutions of `f(θ)`, θ the spin angle.
    fn orbit(n: usize, revs: f64, f: impl Fn(f64) -> V2) -> Vec<V2> {
        (0..n)
            .map(|i| f(2.0 * PI * revs * i as f64 / n as f64))
            .collect()
    }

    #[test]
    fn circles_read_forward_and_backward_and_an_ellipse_splits() {
        // 12 revolutions of 64 samples: 1× is bin ±12.
        let fwd = orbit(768, 12.0, |t| [0.5 + 2.0 * t.cos(), -1.0 + 2.0 * t.sin()]);
        let s = FullSpectrum::new(&fwd);
        assert!((s.amp(12) - 2.0).abs() < 1e-12, "{}", s.amp(12));
        assert!(s.amp(-12) < 1e-12 && s.amp(0) < 1e-12);
        let bwd = orbit(768, 12.0, |t| [1.5 * t.cos(), -1.5 * t.sin()]);
        let s = FullSpectrum::new(&bwd);
        assert!((s.amp(-12) - 1.5).abs() < 1e-12 && s.amp(12) < 1e-12);
        let p = s.peaks(4, 1e-6);
        assert_eq!(
            p,
            vec![Line {
                bin: -12.0,
                amp: s.amp(-12)
            }]
        );
        // Ellipse a = 3 (x), b = 1 (y), traced forward: (a+b)/2 = 2 forward, (a−b)/2 = 1
        // backward; traced backward the two swap.
        for (sign, f, b) in [(1.0, 2.0, 1.0), (-1.0, 1.0, 2.0)] {
            let e = orbit(768, 12.0, |t| {
                [3.0 * (t + 0.4).cos(), sign * (t + 0.4).sin()]
            });
            let s = FullSpectrum::new(&e);
            assert!((s.amp(12) - f).abs() < 1e-12, "{sign}: {}", s.amp(12));
            assert!((s.amp(-12) - b).abs() < 1e-12, "{sign}: {}", s.amp(-12));
            let p = s.peaks(1, 1e-6);
            assert_eq!(p[0].bin, if sign > 0.0 { 12.0 } else { -12.0 });
        }
    }

    #[test]
    fn a_line_between_bins_is_located_and_its_amplitude_restored() {
        // A backward whirl at −2.118 Ω (dry whip, not locked to the spin) of radius 0.8 and a
        // forward 1× of 0.3, over 24 revolutions: −50.83 bins.
        let w = -2.118;
        let z = orbit(24 * 64, 24.0, |t| {
            [
                0.8 * (w * t).cos() + 0.3 * t.cos(),
                0.8 * (w * t).sin() + 0.3 * t.sin(),
            ]
        });
        let s = FullSpectrum::new(&z);
        let p = s.peaks(2, 1e-3);
        assert!((p[0].bin / 24.0 - w).abs() < 1e-6, "{p:?}");
        assert!((p[0].amp - 0.8).abs() < 1e-6, "{p:?}");
        // The 1× on its bin carries a little of the whip's leakage.
        assert!(
            (p[1].bin - 24.0).abs() < 1e-3 && (p[1].amp - 0.3).abs() < 3e-3,
            "{p:?}"
        );
        // Without the refinement the nearest bin (0.17 bin away) reads 5 % low.
        assert!(s.amp(-51) < 0.77, "{}", s.amp(-51));
        assert!(FullSpectrum::new(&[]).peaks(3, 0.0).is_empty());
    }
}
