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

/// The relative difference of two runs' results: the largest of the orbit-extents difference
/// (relative to the largest extent of `b`) and the 1×, ½×, ⅓× line differences (relative to
/// the largest line of `b`) — the measure of [`super::ErrorEstimate`].
pub fn difference(a: &SpeedResults, b: &SpeedResults) -> f64 {
    let ext = extents_error(&a.extents_nd, &b.extents_nd, ExtentsScale::Largest);
    let la = [a.amp_1x_nd, a.amp_half_nd, a.amp_third_nd];
    let lb = [b.amp_1x_nd, b.amp_half_nd, b.amp_third_nd];
    let lmax = lb.iter().fold(1e-300_f64, |m, v| m.max(*v));
    let lines = la
        .iter()
        .zip(lb)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / lmax;
    ext.max(lines)
}
