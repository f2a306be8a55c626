//! x–y charts: bifurcation diagrams, stacked time series, log–log work-precision plots and
//! plain line plots with a legend.

use std::path::Path;

use plotters::prelude::*;

use super::chart::{draw_legend, draw_no_data, draw_segments, no_data_figure, render_titled};
use super::chart::{thick_brush, Axes, Frame};
use super::geom::{densify, equal_aspect_ranges, finite_range, finite_segments, point_segments};
use super::geom::{legend_corner, marker_shape};
use super::geom::{padded, padded_log};
use super::style::{fitting_font, log_formatter, tick_formatter, FIG_H, FIG_W, PALETTE, TICK_SIZE};
use crate::error::Result;

/// One time series.
#[derive(Debug, Clone)]
pub struct Series {
    /// Panel caption.
    pub label: String,
    /// Abscissae (usually time).
    pub t: Vec<f64>,
    /// Ordinates (same length as `t`).
    pub y: Vec<f64>,
}

/// One curve on a log–log or line plot.
#[derive(Debug, Clone)]
pub struct Curve {
    /// Legend entry (empty: no legend entry).
    pub label: String,
    /// The (x, y) points, drawn in the given order.
    pub points: Vec<(f64, f64)>,
}

/// Frame of the log–log and line plots.
pub(super) const CURVES_FRAME: Frame = Frame {
    top: 20,
    right: 36,
    bottom: 20,
    left: 20,
    x_area: 60,
    y_area: 100,
};

/// Bifurcation diagram: Poincaré samples `points` = (speed ω/ωn, value) as small dots; x label
/// `ω/ωn`, y label given.
pub fn bifurcation(path: &Path, title: &str, points: &[(f64, f64)], y_label: &str) -> Result<()> {
    const FRAME: Frame = Frame {
        top: 20,
        right: 30,
        bottom: 20,
        left: 20,
        x_area: 60,
        y_area: 90,
    };
    let pts: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    let (x0, x1) = padded(finite_range(pts.iter().map(|p| p.0)), 0.02);
    let (y0, y1) = padded(finite_range(pts.iter().map(|p| p.1)), 0.05);
    render_titled(path, (FIG_W, FIG_H), title, |body| {
        let mut chart = FRAME.builder(&body).build_cartesian_2d(x0..x1, y0..y1)?;
        let fx = tick_formatter(x0, x1, 12);
        let fy = tick_formatter(y0, y1, 12);
        Axes::page("ω/ωn", y_label, (12, 12), Some((0.12, 0.0))).draw(&mut chart, &fx, &fy)?;
        if pts.is_empty() {
            draw_no_data(chart.plotting_area())?;
            return Ok(());
        }
        let dot = RGBColor(10, 30, 90).filled();
        let radius = if pts.len() < 20_000 { 3 } else { 1 };
        chart.draw_series(pts.iter().map(|&p| Circle::new(p, radius, dot)))?;
        Ok(())
    })
}

/// Stacked panels, one per series, shared x label (e.g. contact-force histories like Fig. 9).
///
/// All panels share the x range (the union of the data); each panel has its own y range, the
/// series label as caption and `y_label` as y description. Only the bottom panel carries x tick
/// labels and `x_label`.
pub fn stacked_series(
    path: &Path,
    title: &str,
    series: &[Series],
    x_label: &str,
    y_label: &str,
) -> Result<()> {
    const PANEL_H: u32 = 230;
    const BOTTOM_EXTRA: u32 = 60;
    const TITLE_BAND: u32 = 56;
    if series.is_empty() {
        return no_data_figure(path, title);
    }
    let n = series.len();
    let height = (n as u32 * PANEL_H + BOTTOM_EXTRA + TITLE_BAND).max(500);
    let (x0, x1) = padded(
        finite_range(
            series
                .iter()
                .flat_map(|s| s.t.iter().zip(&s.y))
                .filter(|(t, y)| t.is_finite() && y.is_finite())
                .map(|(t, _)| *t),
        ),
        0.0,
    );
    let fx = tick_formatter(x0, x1, 12);
    render_titled(path, (FIG_W, height), title, |body| {
        let (_, bh) = body.dim_in_pixel();
        let panel_h = ((bh as i32 - BOTTOM_EXTRA as i32) / n as i32).max(40);
        let mut rest = body;
        for (i, s) in series.iter().enumerate() {
            let last = i + 1 == n;
            let area = if last {
                rest.clone()
            } else {
                let (top, bottom) = rest.split_vertically(panel_h);
                rest = bottom;
                top
            };
            let segs = finite_segments(&s.t, &s.y);
            let (y0, y1) = padded(finite_range(segs.iter().flatten().map(|p| p.1)), 0.08);
            // Only the bottom panel has an x label area, x tick labels and `x_label`.
            let frame = Frame {
                top: 4,
                right: 30,
                bottom: if last { 10 } else { 4 },
                left: 12,
                x_area: if last { 60 } else { 0 },
                y_area: 100,
            };
            let axes = Axes {
                x_desc: last.then_some(x_label),
                y_desc: y_label,
                labels: (12, 5),
                tick_font: (if last { TICK_SIZE } else { 15.0 }, 15.0),
                desc_font: 17.0,
                grid: Some((0.12, 0.0)),
            };
            let mut chart = frame
                .builder(&area)
                .caption(&s.label, fitting_font(&area, &s.label, 19.0)?)
                .build_cartesian_2d(x0..x1, y0..y1)?;
            let fy = tick_formatter(y0, y1, 5);
            axes.draw(&mut chart, &fx, &fy)?;
            if segs.is_empty() {
                draw_no_data(chart.plotting_area())?;
                continue;
            }
            let color = PALETTE[i % PALETTE.len()];
            draw_segments(&mut chart, &segs, color, &[(0.0, 0.0)])?;
        }
        Ok(())
    })
}

/// Log–log plot of several curves with markers and a legend (e.g. work-precision: x = wall time
/// s, y = relative error; or error vs Δt). Non-positive or non-finite points are skipped; ranges
/// computed from the data with a little padding in log space.
///
/// The legend is placed in the corner with the least data.
pub fn loglog(
    path: &Path,
    title: &str,
    curves: &[Curve],
    x_label: &str,
    y_label: &str,
) -> Result<()> {
    loglog_marked(
        path,
        title,
        curves,
        &vec![true; curves.len()],
        x_label,
        y_label,
    )
}

/// [`loglog`] with markers only on the curves whose entry of `marked` is true (the others are
/// plain lines, e.g. bearing stiffness lines on a critical speed map).
pub fn loglog_marked(
    path: &Path,
    title: &str,
    curves: &[Curve],
    marked: &[bool],
    x_label: &str,
    y_label: &str,
) -> Result<()> {
    let valid = |&(x, y): &(f64, f64)| x.is_finite() && y.is_finite() && x > 0.0 && y > 0.0;
    let kept: Vec<Vec<(f64, f64)>> = curves
        .iter()
        .map(|c| c.points.iter().copied().filter(valid).collect())
        .collect();
    let (lx0, lx1) = padded_log(finite_range(kept.iter().flatten().map(|p| p.0.log10())));
    let (ly0, ly1) = padded_log(finite_range(kept.iter().flatten().map(|p| p.1.log10())));
    let (x0, x1) = (10f64.powf(lx0), 10f64.powf(lx1));
    let (y0, y1) = (10f64.powf(ly0), 10f64.powf(ly1));
    let has_data = kept.iter().any(|c| !c.is_empty());
    let samples = unit_samples(&kept, |p| {
        (
            (p.0.log10() - lx0) / (lx1 - lx0),
            (p.1.log10() - ly0) / (ly1 - ly0),
        )
    });
    let legend = legend_position(curves, &samples);
    render_titled(path, (FIG_W, FIG_H), title, |body| {
        let mut chart = CURVES_FRAME
            .builder(&body)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
        let fx = log_formatter(x0, x1);
        let fy = log_formatter(y0, y1);
        Axes::page(x_label, y_label, (10, 10), Some((0.15, 0.035))).draw(&mut chart, &fx, &fy)?;
        if !has_data {
            draw_no_data(chart.plotting_area())?;
            return Ok(());
        }
        for (i, (curve, pts)) in curves.iter().zip(&kept).enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            let mark = marked.get(i).copied().unwrap_or(true);
            let shape = marker_shape(i, if mark { 6 } else { 0 });
            if pts.len() > 1 {
                chart.draw_series(LineSeries::new(pts.iter().copied(), color.stroke_width(2)))?;
            }
            let anno = chart.draw_series(
                pts.iter()
                    .filter(|_| mark)
                    .map(|&p| EmptyElement::at(p) + Polygon::new(shape.clone(), color.filled())),
            )?;
            if !curve.label.is_empty() {
                let legend_shape = marker_shape(i, if mark { 6 } else { 0 });
                anno.label(curve.label.as_str()).legend(move |(x, y)| {
                    EmptyElement::at((x + 12, y))
                        + PathElement::new(vec![(-12, 0), (12, 0)], color.stroke_width(2))
                        + Polygon::new(legend_shape.clone(), color.filled())
                });
            }
        }
        if let Some(corner) = legend {
            draw_legend(&mut chart, corner)?;
        }
        Ok(())
    })
}

/// Plain x–y line plot of several curves with a legend (linear axes), e.g. a spectrum or regime
/// map.
///
/// Lines are broken at non-finite points; isolated points are drawn as dots. The legend is
/// placed in the corner with the least data.
pub fn lines(
    path: &Path,
    title: &str,
    curves: &[Curve],
    x_label: &str,
    y_label: &str,
) -> Result<()> {
    curves_plot(path, title, curves, (x_label, y_label), false)
}

/// [`lines`] with equal data units per pixel on both axes: paths in a plane drawn to their true
/// shape (a vector's path in the rotor's frame, multipliers about the unit circle).
/// `labels`: the x and y axes' descriptions.
pub fn equal_aspect(
    path: &Path,
    title: &str,
    curves: &[Curve],
    labels: (&str, &str),
) -> Result<()> {
    curves_plot(path, title, curves, labels, true)
}

/// The body of [`lines`] and [`equal_aspect`].
fn curves_plot(
    path: &Path,
    title: &str,
    curves: &[Curve],
    (x_label, y_label): (&str, &str),
    aspect: bool,
) -> Result<()> {
    let segs: Vec<Vec<Vec<(f64, f64)>>> =
        curves.iter().map(|c| point_segments(&c.points)).collect();
    let all = || segs.iter().flatten().flatten();
    let has_data = all().next().is_some();
    render_titled(path, (FIG_W, FIG_H), title, |body| {
        let ((x0, x1), (y0, y1)) = if aspect {
            let f = CURVES_FRAME;
            let (w, h) = body.dim_in_pixel();
            let pw = f64::from((w as i32 - f.left - f.right - f.y_area).max(20));
            let ph = f64::from((h as i32 - f.top - f.bottom - f.x_area).max(20));
            let pts: Vec<(f64, f64)> = all().copied().collect();
            equal_aspect_ranges(&pts, pw, ph)
        } else {
            (
                padded(finite_range(all().map(|p| p.0)), 0.02),
                padded(finite_range(all().map(|p| p.1)), 0.05),
            )
        };
        let samples = unit_samples(segs.iter().flatten(), |p| {
            ((p.0 - x0) / (x1 - x0), (p.1 - y0) / (y1 - y0))
        });
        let legend = legend_position(curves, &samples);
        let mut chart = CURVES_FRAME
            .builder(&body)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        let fx = tick_formatter(x0, x1, 12);
        let fy = tick_formatter(y0, y1, 12);
        Axes::page(x_label, y_label, (12, 12), Some((0.12, 0.03))).draw(&mut chart, &fx, &fy)?;
        if !has_data {
            draw_no_data(chart.plotting_area())?;
            return Ok(());
        }
        let brush = thick_brush(&chart);
        for (i, (curve, cs)) in curves.iter().zip(&segs).enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            draw_segments(&mut chart, cs, color, &brush)?;
            if !curve.label.is_empty() {
                // An empty series that only carries the legend entry.
                chart
                    .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
                    .label(curve.label.as_str())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
                    });
            }
        }
        if let Some(corner) = legend {
            draw_legend(&mut chart, corner)?;
        }
        Ok(())
    })
}

/// Dense samples along the polylines `pls`, mapped by `to_unit` to normalised plot coordinates
/// (0..1 on both axes), for placing the legend.
fn unit_samples<'p>(
    pls: impl IntoIterator<Item = &'p Vec<(f64, f64)>>,
    to_unit: impl Fn(&(f64, f64)) -> (f64, f64),
) -> Vec<(f64, f64)> {
    pls.into_iter()
        .flat_map(|pl| densify(&pl.iter().map(&to_unit).collect::<Vec<_>>()))
        .collect()
}

/// The legend corner of `curves` (the one covering the fewest `samples`), `None` when no curve
/// has a label.
fn legend_position(curves: &[Curve], samples: &[(f64, f64)]) -> Option<SeriesLabelPosition> {
    let labels: Vec<&str> = curves
        .iter()
        .map(|c| c.label.as_str())
        .filter(|l| !l.is_empty())
        .collect();
    (!labels.is_empty()).then(|| legend_corner(samples, &labels))
}
