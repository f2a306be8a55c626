//! A speed transient window by window: the full-spectrum waterfall of `z = x + iy` over
//! consecutive windows of whole revolutions of the spin angle ([`full_waterfall`]), each with
//! its contact state — the fraction of its samples in contact and, with Coulomb friction with
//! stick, the fraction of those in stick — and its dry-friction class (dry whirl, dry whip:
//! [`super::dry::classify`], the steady runs' rule, docs/STICK.md §4). Consecutive windows of
//! one class make a [`DrySpan`]: where a run-up leaves dry whirl, where a coast-down drops
//! into it.
//!
//! Frequencies are signed as in [`super::whirl`]: positive forward, negative backward.

use super::dry::{classify, roll_resolution, rolls, DryRub};
use super::transient::{interp, TransientResults};
use super::whirl::{whirl_lines, WhirlDirection};
use crate::model::Case;
use crate::time::StepPlan;
use serde::Serialize;
use std::f64::consts::PI;

/// Samples per revolution of a transient's angle-domain windows ([`full_waterfall`]).
pub const WATERFALL_PER_REV: usize = 64;

/// One window of a transient's full-spectrum waterfall ([`full_waterfall`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WaterfallWindow {
    /// Time at the window's middle angle (s).
    pub t: f64,
    /// Times at the window's first and last angle (s).
    pub span: [f64; 2],
    /// Ω at the middle angle (rad/s).
    pub omega: f64,
    /// Forward and backward 1× amplitudes (m), exact.
    pub forward_1x: f64,
    /// Backward 1× amplitude (m).
    pub backward_1x: f64,
    /// The sense of the strongest line.
    pub direction: WhirlDirection,
    /// The strongest lines: `(signed order f/Ω, amplitude m)`, strongest first.
    pub lines: Vec<(f64, f64)>,
    /// Fraction of the window's recorded samples with a pair carrying force.
    pub contact_fraction: f64,
    /// Fraction of the window's samples in contact at which some pair stuck; `None` when no
    /// station has stick (`station.N.stick`).
    pub stick_fraction: Option<f64>,
    /// The window's dry-friction class ([`classify`]); `None` without stick, or when the
    /// window is not a backward whirl in full annular contact.
    pub dry_rub: Option<DryRub>,
}

/// The full-spectrum waterfall of a transient: short-time full spectra of `z = x + iy` over
/// consecutive windows of `w` whole revolutions of the spin angle φ (the window follows the
/// local speed: it always spans `w` revolutions), each resampled at equal angle steps —
/// [`WATERFALL_PER_REV`] a revolution, or the power of two at or above the samples the record
/// holds a revolution there when it holds more (a roll's whirl at −R/δ × the speed stays
/// within the orders resolved) — by cubic interpolation in φ, as the order tracking; rectangular
/// window — so every order `k/w` of the local Ω falls on a bin —
/// the mean removed. Windows start at φ = 0, 2πw, 4πw, …; Ω and t are taken at each window's
/// middle angle. The contact and stick fractions count the recorded samples whose φ lies in
/// the window (`[start, start + 2πw)`).
pub fn full_waterfall(r: &TransientResults, w: usize) -> Vec<WaterfallWindow> {
    let n = r.spin.len().min(r.response.len());
    if n < 4 || w == 0 {
        return Vec::new();
    }
    let phi: Vec<f64> = r.spin[..n].iter().map(|s| s[2]).collect();
    let x: Vec<f64> = r.response[..n].iter().map(|u| u[0]).collect();
    let y: Vec<f64> = r.response[..n].iter().map(|u| u[1]).collect();
    let revs = (phi[n - 1] / (2.0 * PI)).floor() as usize;
    let mut out = Vec::new();
    let mut cur = 0usize;
    // Time and Ω at angle `a`, linear between the samples that bracket it.
    let at = |a: f64| {
        let i = phi.partition_point(|p| *p < a).clamp(1, n - 1);
        let d = phi[i] - phi[i - 1];
        let f = if d > 0.0 { (a - phi[i - 1]) / d } else { 0.0 };
        let lerp = |a: f64, b: f64| a + f * (b - a);
        (
            lerp(r.spin[i - 1][0], r.spin[i][0]),
            lerp(r.spin[i - 1][1], r.spin[i][1]),
        )
    };
    for k in 0..revs / w {
        let start = 2.0 * PI * (k * w) as f64;
        let end = start + 2.0 * PI * w as f64;
        let held = phi.partition_point(|p| *p < end) - phi.partition_point(|p| *p < start);
        // As many angle steps a revolution as the record holds there, at least
        // WATERFALL_PER_REV: the orders the samples resolve are kept.
        let per_rev = WATERFALL_PER_REV.max((held / w).next_power_of_two());
        let m = w * per_rev;
        let mut z = Vec::with_capacity(m);
        for j in 0..m {
            let a = start + 2.0 * PI * j as f64 / per_rev as f64;
            while cur + 2 < n && phi[cur + 1] <= a {
                cur += 1;
            }
            z.push([interp(&phi, &x, cur, a), interp(&phi, &y, cur, a)]);
        }
        let (wl, _) = whirl_lines(&z, w);
        let (t, omega) = at(start + PI * w as f64);
        let (contact_fraction, stick_fraction) = contact_state(r, &phi, [start, end]);
        let dry_rub = stick_fraction.and_then(|s| classify(contact_fraction, s, &wl));
        out.push(WaterfallWindow {
            t,
            span: [at(start).0, at(end).0],
            omega,
            forward_1x: wl.forward_1x_nd,
            backward_1x: wl.backward_1x_nd,
            direction: wl.direction,
            lines: wl.lines,
            contact_fraction,
            stick_fraction,
            dry_rub,
        });
    }
    out
}

/// The fraction of the samples of `r` whose angle `phi` lies in `[a0, a1)` with a pair
/// carrying force, and — when a station has stick — the fraction of those with a pair in
/// stick (0 without contact).
fn contact_state(r: &TransientResults, phi: &[f64], [a0, a1]: [f64; 2]) -> (f64, Option<f64>) {
    let (lo, hi) = (
        phi.partition_point(|p| *p < a0),
        phi.partition_point(|p| *p < a1),
    );
    let states = &r.contact_state[lo.min(r.contact_state.len())..hi.min(r.contact_state.len())];
    let contact = states.iter().filter(|s| s[0] > 0).count();
    let stuck = states.iter().filter(|s| s[0] > 0 && s[1] > 0).count();
    let fraction = |k: usize, of: usize| if of == 0 { 0.0 } else { k as f64 / of as f64 };
    (
        fraction(contact, states.len()),
        r.stick.then(|| fraction(stuck, contact)),
    )
}

/// What the step `plan` of a transient of `case` or its record does not resolve of a roll
/// ([`roll_resolution`]), at the fastest of the `windows` that roll ([`rolls`]); empty when
/// none rolls.
pub fn roll_warnings(case: &Case, plan: &StepPlan, windows: &[WaterfallWindow]) -> Vec<String> {
    let fastest = windows
        .iter()
        .filter(|w| {
            w.stick_fraction
                .is_some_and(|s| rolls(w.contact_fraction, s))
        })
        .map(|w| w.omega.abs())
        .fold(0.0, f64::max);
    if fastest > 0.0 {
        roll_resolution(case, fastest, plan)
    } else {
        Vec::new()
    }
}

/// Consecutive windows of a waterfall in one dry-friction class.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DrySpan {
    /// The class.
    pub regime: DryRub,
    /// Windows in the span.
    pub windows: usize,
    /// Time at the first window's first angle and at the last window's last angle (s).
    pub t_s: [f64; 2],
    /// Ω/ω_n at the first and at the last window's middle angle.
    pub speed_ratio: [f64; 2],
}

/// The spans of consecutive windows of one class in `windows` (ω_n = `omega_n` rad/s), in
/// time order; windows without a class end a span.
pub fn dry_spans(windows: &[WaterfallWindow], omega_n: f64) -> Vec<DrySpan> {
    let mut spans: Vec<DrySpan> = Vec::new();
    let mut open = false;
    for w in windows {
        let Some(regime) = w.dry_rub else {
            open = false;
            continue;
        };
        let nu = w.omega / omega_n;
        match spans.last_mut() {
            Some(s) if open && s.regime == regime => {
                s.windows += 1;
                s.t_s[1] = w.span[1];
                s.speed_ratio[1] = nu;
            }
            _ => spans.push(DrySpan {
                regime,
                windows: 1,
                t_s: w.span,
                speed_ratio: [nu, nu],
            }),
        }
        open = true;
    }
    spans
}

#[cfg(test)]
mod tests {
    use super::*;

    fn window(dry_rub: Option<DryRub>, t: f64) -> WaterfallWindow {
        WaterfallWindow {
            t,
            span: [t - 0.5, t + 0.5],
            omega: 2.0 * t,
            forward_1x: 0.0,
            backward_1x: 0.0,
            direction: WhirlDirection::Backward,
            lines: Vec::new(),
            contact_fraction: 1.0,
            stick_fraction: Some(0.0),
            dry_rub,
        }
    }

    #[test]
    fn spans_join_consecutive_windows_of_one_class_and_break_at_the_others() {
        use DryRub::{Whip, Whirl};
        let w: Vec<WaterfallWindow> = [
            Some(Whip),
            Some(Whip),
            Some(Whirl),
            None,
            Some(Whirl),
            Some(Whirl),
        ]
        .iter()
        .enumerate()
        .map(|(i, c)| window(*c, i as f64 + 1.0))
        .collect();
        let s = dry_spans(&w, 2.0);
        let got: Vec<(DryRub, usize, [f64; 2], [f64; 2])> = s
            .iter()
            .map(|s| (s.regime, s.windows, s.t_s, s.speed_ratio))
            .collect();
        assert_eq!(
            got,
            vec![
                (Whip, 2, [0.5, 2.5], [1.0, 2.0]),
                (Whirl, 1, [2.5, 3.5], [3.0, 3.0]),
                (Whirl, 2, [4.5, 6.5], [5.0, 6.0]),
            ]
        );
        assert!(dry_spans(&[], 1.0).is_empty());
    }
}
