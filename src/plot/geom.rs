//! Plane geometry and data ranges behind the figures: finite data ranges and their padding
//! (linear and logarithmic), runs of finite samples, dense samples along polylines, the legend
//! corner with the least data, equal-aspect ranges, half-plane and rectangle clipping, and the
//! marker shapes.

use plotters::prelude::SeriesLabelPosition;

/// Largest magnitude kept for range computations (guards against overflowing spans).
const HUGE: f64 = 1e150;

/// Minimum and maximum of the finite values (clamped to ±[`HUGE`]); `None` if there are none.
pub(super) fn finite_range<I: IntoIterator<Item = f64>>(values: I) -> Option<(f64, f64)> {
    values
        .into_iter()
        .filter(|v| v.is_finite())
        .map(|v| v.clamp(-HUGE, HUGE))
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
}

/// A drawable range from a data range: padded by `frac` of the span; a zero span is widened by
/// 10 % of the magnitude (or ±1 around zero); no data gives 0..1.
pub(super) fn padded(range: Option<(f64, f64)>, frac: f64) -> (f64, f64) {
    let Some((lo, hi)) = range else {
        return (0.0, 1.0);
    };
    let mag = lo.abs().max(hi.abs());
    let span = hi - lo;
    if span <= mag * 1e-9 || span <= f64::MIN_POSITIVE {
        let d = if mag > 0.0 { 0.1 * mag } else { 1.0 };
        return (lo - d, hi + d);
    }
    (lo - frac * span, hi + frac * span)
}

/// A padded range of decimal exponents (0.15 decade each side, at least one decade wide).
pub(super) fn padded_log(range: Option<(f64, f64)>) -> (f64, f64) {
    match range {
        None => (-1.0, 1.0),
        Some((lo, hi)) if hi - lo < 1.0 => {
            let c = 0.5 * (lo + hi);
            (c - 0.5 - 0.15, c + 0.5 + 0.15)
        }
        Some((lo, hi)) => (lo - 0.15, hi + 0.15),
    }
}

/// [`finite_segments`] of a curve's `(x, y)` points.
pub(super) fn point_segments(points: &[(f64, f64)]) -> Vec<Vec<(f64, f64)>> {
    let (x, y): (Vec<f64>, Vec<f64>) = points.iter().copied().unzip();
    finite_segments(&x, &y)
}

/// Splits the paired samples into runs of finite points.
pub(super) fn finite_segments(x: &[f64], y: &[f64]) -> Vec<Vec<(f64, f64)>> {
    let mut out: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    for (&a, &b) in x.iter().zip(y) {
        if a.is_finite() && b.is_finite() {
            cur.push((a, b));
        } else if !cur.is_empty() {
            out.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// Points along a polyline (normalised coordinates) dense enough to tell where it runs.
pub(super) fn densify(pts: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let stride = (pts.len() / 2000).max(1);
    let mut out = Vec::new();
    for w in pts.windows(2).step_by(stride) {
        for k in 0..8 {
            let t = f64::from(k) / 8.0;
            out.push((
                w[0].0 + t * (w[1].0 - w[0].0),
                w[0].1 + t * (w[1].1 - w[0].1),
            ));
        }
    }
    if let Some(&p) = pts.last() {
        out.push(p);
    }
    out
}

/// The plot corner whose legend-sized box covers the fewest samples (normalised coordinates,
/// 0..1 on both axes, y up).
pub(super) fn legend_corner(samples: &[(f64, f64)], labels: &[&str]) -> SeriesLabelPosition {
    // Approximate legend box relative to a plotting area of about 1040 × 730 pixels.
    let chars = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    let bw = ((70.0 + 10.0 * chars as f64) / 1040.0).min(0.9);
    let bh = ((30.0 + 23.0 * labels.len() as f64) / 730.0).min(0.9);
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let count = |right: bool, upper: bool| {
        samples
            .iter()
            .filter(|(x, y)| {
                let inx = if right { *x >= 1.0 - bw } else { *x <= bw };
                let iny = if upper { *y >= 1.0 - bh } else { *y <= bh };
                inx && iny
            })
            .count()
    };
    let mut best = (usize::MAX, SeriesLabelPosition::UpperRight);
    for (pos, right, upper) in corners {
        let c = count(right, upper);
        if c < best.0 {
            best = (c, pos);
        }
    }
    best.1
}

/// Marker polygon number `i` (pixel offsets around the data point).
pub(super) fn marker_shape(i: usize, r: i32) -> Vec<(i32, i32)> {
    let rf = f64::from(r);
    let ngon = |n: usize, rad: f64, phase: f64| -> Vec<(i32, i32)> {
        (0..n)
            .map(|k| {
                let a = phase + std::f64::consts::TAU * k as f64 / n as f64;
                (
                    (rad * a.cos()).round() as i32,
                    (rad * a.sin()).round() as i32,
                )
            })
            .collect()
    };
    match i % 6 {
        0 => ngon(16, rf, 0.0),
        1 => vec![(-r, -r), (r, -r), (r, r), (-r, r)],
        2 => ngon(3, rf * 1.3, -std::f64::consts::FRAC_PI_2),
        3 => ngon(4, rf * 1.35, 0.0),
        4 => ngon(3, rf * 1.3, std::f64::consts::FRAC_PI_2),
        _ => (0..10)
            .map(|k| {
                let rad = if k % 2 == 0 { rf * 1.45 } else { rf * 0.6 };
                let a = -std::f64::consts::FRAC_PI_2 + std::f64::consts::TAU * f64::from(k) / 10.0;
                (
                    (rad * a.cos()).round() as i32,
                    (rad * a.sin()).round() as i32,
                )
            })
            .collect(),
    }
}

/// Axis ranges containing `pts` (padded) with equal data units per pixel on a plotting area of
/// `pw` × `ph` pixels.
pub(super) fn equal_aspect_ranges(
    pts: &[(f64, f64)],
    pw: f64,
    ph: f64,
) -> ((f64, f64), (f64, f64)) {
    let xr = finite_range(pts.iter().map(|p| p.0));
    let yr = finite_range(pts.iter().map(|p| p.1));
    let (Some((xa, xb)), Some((ya, yb))) = (xr, yr) else {
        let s = 2.0 / pw.min(ph);
        return ((-s * pw / 2.0, s * pw / 2.0), (-s * ph / 2.0, s * ph / 2.0));
    };
    let (cx, cy) = (0.5 * (xa + xb), 0.5 * (ya + yb));
    let mut hx = 0.5 * (xb - xa);
    let mut hy = 0.5 * (yb - ya);
    let mag = cx.abs().max(cy.abs());
    let tiny = (mag * 1e-9).max(1e-300);
    if hx <= tiny && hy <= tiny {
        let h = if mag > 0.0 { 0.1 * mag } else { 1.0 };
        hx = h;
        hy = h;
    }
    let pad = 1.08;
    let s = (2.0 * hx * pad / pw).max(2.0 * hy * pad / ph);
    (
        (cx - s * pw / 2.0, cx + s * pw / 2.0),
        (cy - s * ph / 2.0, cy + s * ph / 2.0),
    )
}

/// Part of the convex polygon `poly` with `p · n ≥ d` (Sutherland–Hodgman, one plane).
pub(super) fn clip_half_plane(poly: &[(f64, f64)], n: (f64, f64), d: f64) -> Vec<(f64, f64)> {
    let side = |p: (f64, f64)| p.0 * n.0 + p.1 * n.1 - d;
    let mut out = Vec::new();
    for i in 0..poly.len() {
        let a = poly[i];
        let b = poly[(i + 1) % poly.len()];
        let (sa, sb) = (side(a), side(b));
        if sa >= 0.0 {
            out.push(a);
        }
        if (sa >= 0.0) != (sb >= 0.0) {
            let t = sa / (sa - sb);
            out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
        }
    }
    out
}

/// Clips the segment `p0`–`p1` to the rectangle `xr` × `yr` (Liang–Barsky).
pub(super) fn clip_segment(
    p0: (f64, f64),
    p1: (f64, f64),
    xr: (f64, f64),
    yr: (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (p1.0 - p0.0, p1.1 - p0.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [
        (-dx, p0.0 - xr.0),
        (dx, xr.1 - p0.0),
        (-dy, p0.1 - yr.0),
        (dy, yr.1 - p0.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 < t1).then_some((
        (p0.0 + t0 * dx, p0.1 + t0 * dy),
        (p0.0 + t1 * dx, p0.1 + t1 * dy),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn helpers() {
        assert_eq!(padded(None, 0.1), (0.0, 1.0));
        assert_eq!(padded(Some((0.0, 0.0)), 0.1), (-1.0, 1.0));
        let (a, b) = padded(Some((2.0, 2.0)), 0.1);
        assert!(a < 2.0 && b > 2.0);
        assert_eq!(
            finite_range([f64::NAN, 1.0, -2.0, f64::INFINITY]),
            Some((-2.0, 1.0))
        );
        assert_eq!(
            finite_segments(&[1.0, f64::NAN, 2.0, 3.0], &[1.0; 4]).len(),
            2
        );
        let sq = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        assert_eq!(clip_half_plane(&sq, (0.0, 1.0), 0.5).len(), 4);
        assert!(clip_half_plane(&sq, (0.0, 1.0), 2.0).is_empty());
        let s = clip_segment((-5.0, 0.0), (5.0, 0.0), (-1.0, 1.0), (-1.0, 1.0));
        assert_eq!(s, Some(((-1.0, 0.0), (1.0, 0.0))));
    }
}
