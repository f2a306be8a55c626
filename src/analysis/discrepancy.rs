//! How far apart two runs' results are: the orbit-extents and line differences and the scales
//! that make them relative (the error estimate, the step and cut-off pilots, the coexistence
//! check, the convergence study, the bench).

use super::SpeedResults;

/// The largest of `|a_i − b_i|` over two equal-length slices.
pub fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// How an orbit-extents difference is made relative ([`extents_error`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExtentsScale {
    /// By the largest |extent| of the reference, `max_i |e_i|` ([`extent_scale`]): the error
    /// estimate and the convergence study.
    Largest,
    /// By the size of the reference orbit, `max(x_max − x_min, y_max − y_min)`
    /// ([`orbit_span`]): the bench's comparison with a converged sweep.
    Span,
}

/// Largest |extent| of `[x_min, x_max, y_min, y_max]`, at least 1e-300.
pub fn extent_scale(e: &[f64; 4]) -> f64 {
    e.iter().fold(1e-300_f64, |m, v| m.max(v.abs()))
}

/// Size of an orbit from its extents: `max(x_max − x_min, y_max − y_min)`.
pub fn orbit_span(e: &[f64; 4]) -> f64 {
    (e[1] - e[0]).max(e[3] - e[2])
}

/// The orbit-extents error of `x` against `reference`: `max_i |x_i − ref_i|` over
/// `[x_min, x_max, y_min, y_max]`, divided by the reference's scale ([`ExtentsScale`]).
pub fn extents_error(x: &[f64; 4], reference: &[f64; 4], scale: ExtentsScale) -> f64 {
    max_diff(x, reference)
        / match scale {
            ExtentsScale::Largest => extent_scale(reference),
            ExtentsScale::Span => orbit_span(reference),
        }
}

/// The 1×, ½×, ⅓× line amplitudes of a run, `[amp_1x_nd, amp_half_nd, amp_third_nd]` (/|Z0|).
pub fn lines(r: &SpeedResults) -> [f64; 3] {
    [r.amp_1x_nd, r.amp_half_nd, r.amp_third_nd]
}

/// What a [`Discrepancy`] is relative to: the scales of one run, the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scales {
    /// The extents' differences are divided by this: the reference's largest |extent|
    /// ([`extent_scale`], at least 1e-300) with [`ExtentsScale::Largest`], its orbit size
    /// ([`orbit_span`]) with [`ExtentsScale::Span`] (/|Z0|).
    pub extents: f64,
    /// The lines' differences are divided by this: the largest of the reference's 1×, ½×, ⅓×
    /// amplitudes, at least 1e-300 (/|Z0|).
    pub lines: f64,
}

impl Scales {
    /// The scales of `reference`, its extents measured as `extents` says.
    pub fn of(reference: &SpeedResults, extents: ExtentsScale) -> Self {
        let e = &reference.extents_nd;
        Self {
            extents: match extents {
                ExtentsScale::Largest => extent_scale(e),
                ExtentsScale::Span => orbit_span(e),
            },
            lines: lines(reference).iter().fold(1e-300_f64, |m, v| m.max(*v)),
        }
    }
}

/// How far apart two runs' results are, relative to a reference's [`Scales`] — the one
/// measure of the error estimate's companions ([`super::ErrorEstimate`]), the step pilots
/// ([`difference`]), the cut-off pilots ([`super::cutoff`]), the coexistence check
/// ([`super::Coexistence`]) and the convergence study:
///
/// ```text
/// extents = max_i |E_a,i − E_b,i| / scales.extents,   E = [x_min, x_max, y_min, y_max]/|Z0|
/// lines   = max_k |L_a,k − L_b,k| / scales.lines,     L = [1×, ½×, ⅓×] amplitudes/|Z0|
/// ```
///
/// The reference is usually `b` (the finer run, the run a companion is compared with), but
/// the error estimate's second pair (2Δt, 4Δt) is made relative to the run's own scales.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Discrepancy {
    /// The largest difference of the orbit extents over `scales.extents`.
    pub extents: f64,
    /// The largest difference of the 1×, ½×, ⅓× lines over `scales.lines` (the largest of
    /// `each_line`).
    pub lines: f64,
    /// Each line's difference `|L_a,k − L_b,k|` over `scales.lines`: 1×, ½×, ⅓×.
    pub each_line: [f64; 3],
}

impl Discrepancy {
    /// The discrepancy of `a` from `b` relative to `scales` (symmetric in `a` and `b`).
    pub fn between(a: &SpeedResults, b: &SpeedResults, scales: Scales) -> Self {
        let (la, lb) = (lines(a), lines(b));
        Self {
            extents: max_diff(&a.extents_nd, &b.extents_nd) / scales.extents,
            lines: max_diff(&la, &lb) / scales.lines,
            each_line: [0, 1, 2].map(|k| (la[k] - lb[k]).abs() / scales.lines),
        }
    }

    /// The larger of the extents' and the lines' discrepancy.
    pub fn largest(&self) -> f64 {
        self.extents.max(self.lines)
    }
}

/// The relative difference of two runs' results: the largest of the orbit-extents difference
/// (relative to the largest extent of `b`) and the 1×, ½×, ⅓× line differences (relative to
/// the largest line of `b`) — [`Discrepancy::largest`] relative to `b`'s
/// [`ExtentsScale::Largest`] scales, the measure of [`super::ErrorEstimate`].
pub fn difference(a: &SpeedResults, b: &SpeedResults) -> f64 {
    Discrepancy::between(a, b, Scales::of(b, ExtentsScale::Largest)).largest()
}
