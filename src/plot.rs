//! PNG figures: orbit grids, spectrum cascades, bifurcation diagrams, stacked time series,
//! log–log work-precision plots and plain line plots.
//!
//! All figures are rendered with `plotters` into a bitmap and written as PNG to exactly the
//! path given by the caller. Text uses the embedded DejaVu Sans font (the `ab_glyph` backend of
//! `plotters` has no system fonts), registered once under the family name `sans-serif`.
//! The bitmap encoder infers the format from the extension, so a target without a `.png`
//! extension (e.g. a temporary name) is rendered to a hidden `.png` sibling and renamed to it.
//!
//! Every function is robust to empty input (a page with the title and "no data" is written),
//! to non-finite values (skipped; lines are broken at them), to single points and to zero
//! data ranges (ranges are padded).

use std::error::Error as StdError;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::FontStyle;

use crate::error::{Error, Result};

/// Font family name under which the embedded DejaVu Sans font is registered.
const FONT: &str = "sans-serif";

/// The embedded font file.
static FONT_BYTES: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

/// Root drawing area of one figure.
type Root<'a> = DrawingArea<BitMapBackend<'a>, Shift>;

/// Result of the drawing closures (any `plotters` error).
type DrawResult = std::result::Result<(), Box<dyn StdError>>;

/// Light grey used for the stator region of orbit panels.
const STATOR_FILL: RGBColor = RGBColor(225, 225, 225);

/// Distinct colours (the "tab10" palette).
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Width of the ordinary (non-grid) figures in pixels.
const FIG_W: u32 = 1200;
/// Height of the ordinary (non-grid) figures in pixels.
const FIG_H: u32 = 900;
/// Font size of figure titles.
const TITLE_SIZE: f64 = 30.0;
/// Font size of tick labels.
const TICK_SIZE: f64 = 17.0;
/// Font size of axis descriptions.
const DESC_SIZE: f64 = 20.0;

/// What to draw as the stator boundary in an orbit panel (non-dimensional units, same as the
/// orbit).
#[derive(Debug, Clone, PartialEq)]
pub enum Boundary {
    /// No boundary.
    None,
    /// A straight line at perpendicular distance `distance` from the origin, normal at
    /// `angle_deg` (90 = horizontal line y = distance, the paper's rod above the rotor).
    Line {
        /// Direction of the line normal (from the origin towards the line), degrees from +x.
        angle_deg: f64,
        /// Perpendicular distance of the line from the origin.
        distance: f64,
    },
    /// A circle of given radius centred at the origin (ring stator).
    Circle {
        /// Radius of the circle.
        radius: f64,
    },
}

/// One orbit panel.
#[derive(Debug, Clone)]
pub struct OrbitPanel {
    /// Panel title (e.g. the rotor speed).
    pub title: String,
    /// Horizontal displacements (non-dimensional).
    pub x: Vec<f64>,
    /// Vertical displacements (non-dimensional, same length as `x`).
    pub y: Vec<f64>,
    /// Stator boundary drawn in the panel.
    pub boundary: Boundary,
    /// Optional Poincaré points (once-per-revolution samples) drawn as dots.
    pub poincare: Vec<(f64, f64)>,
}

/// One spectrum of a cascade: at rotor speed `speed` (ω/ωn), amplitudes `amp` at frequencies
/// `freq` (f/ωn, same length).
#[derive(Debug, Clone)]
pub struct CascadeLine {
    /// Rotor speed ω/ωn of this spectrum (its baseline in the cascade).
    pub speed: f64,
    /// Frequencies f/ωn.
    pub freq: Vec<f64>,
    /// Amplitudes at `freq`.
    pub amp: Vec<f64>,
}

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

// ---------------------------------------------------------------------------------------------
// Public figure functions
// ---------------------------------------------------------------------------------------------

/// Grid of orbit panels (like Figs. 5–8 of the paper): equal aspect ratio per panel, axes
/// labelled `x/|Z0|`, `y/|Z0|`, common title on top. `cols` panels per row.
///
/// Each panel is about 420 × 420 pixels. The stator side of the boundary is shaded grey; the
/// orbit is drawn as a blue line (broken at non-finite samples) and the Poincaré points as red
/// dots. With no panels a page with the title and "no data" is written.
pub fn orbit_grid(path: &Path, title: &str, panels: &[OrbitPanel], cols: usize) -> Result<()> {
    const PANEL: u32 = 420;
    const TITLE_BAND: u32 = 56;
    if panels.is_empty() {
        return render(path, (FIG_W, FIG_H), |root| no_data_page(root, title));
    }
    let cols = cols.clamp(1, panels.len());
    let rows = panels.len().div_ceil(cols);
    let width = (cols as u32 * PANEL).max(640);
    let height = rows as u32 * PANEL + TITLE_BAND;
    render(path, (width, height), |root| {
        let body = titled(root, title)?;
        let cells = body.split_evenly((rows, cols));
        for (cell, panel) in cells.iter().zip(panels) {
            draw_orbit_panel(cell, panel)?;
        }
        Ok(())
    })
}

/// Spectrum cascade (waterfall, like Fig. 12): x = frequency/ωn (0..`freq_max`), y = rotor
/// speed; each spectrum drawn as a line offset vertically at its speed, amplitude scaled so the
/// largest amplitude over all lines spans `peak_height_speeds` speed units (e.g. 0.8).
///
/// Guide lines for 1× (f = speed, solid red), 1/2× (f = speed/2, dashed green) and 1/3×
/// (f = speed/3, dotted orange) are drawn with a legend. The amplitude scale is printed below
/// the title. The largest amplitude is taken over the visible frequency range 0..`freq_max`.
/// Spectra are drawn back to front with a white fill below each line, so lower-speed peaks hide
/// the spectra behind them. A non-finite or non-positive `freq_max` is replaced by the largest
/// frequency in the data; a non-finite or negative `peak_height_speeds` by 0.8.
pub fn cascade(
    path: &Path,
    title: &str,
    lines: &[CascadeLine],
    freq_max: f64,
    peak_height_speeds: f64,
) -> Result<()> {
    let fmax = if freq_max.is_finite() && freq_max > 0.0 {
        freq_max
    } else {
        finite_range(lines.iter().flat_map(|l| l.freq.iter().copied()))
            .map(|(_, hi)| hi)
            .filter(|hi| *hi > 0.0)
            .unwrap_or(1.0)
    };
    let peak = if peak_height_speeds.is_finite() && peak_height_speeds >= 0.0 {
        peak_height_speeds
    } else {
        0.8
    };
    let visible = |f: f64, a: f64| f.is_finite() && a.is_finite() && (0.0..=fmax).contains(&f);
    let lines: Vec<&CascadeLine> = lines.iter().filter(|l| l.speed.is_finite()).collect();
    let amax = lines
        .iter()
        .flat_map(|l| l.freq.iter().zip(&l.amp))
        .filter(|(f, a)| visible(**f, **a))
        .map(|(_, a)| a.abs())
        .fold(0.0_f64, f64::max);
    let scale = if amax > 0.0 { peak / amax } else { 0.0 };

    let (ylo, yhi) = match finite_range(lines.iter().map(|l| l.speed)) {
        None => (0.0, 1.0),
        Some((lo, hi)) => {
            let span = (hi - lo + peak).max(lo.abs().max(hi.abs()) * 0.1).max(1e-9);
            (lo - 0.04 * span, hi + peak + 0.04 * span)
        }
    };

    render(path, (FIG_W, FIG_H), |root| {
        let body = titled(root, title)?;
        let note = if lines.is_empty() {
            String::new()
        } else if amax > 0.0 {
            format!(
                "amplitude scale: {} speed units = max. amplitude {}",
                fmt_sig(peak),
                fmt_sig(amax)
            )
        } else {
            "amplitude scale: all amplitudes zero".to_string()
        };
        let (bw, _) = body.dim_in_pixel();
        body.draw_text(
            &note,
            &font(16.0)
                .color(&RGBColor(90, 90, 90))
                .pos(Pos::new(HPos::Right, VPos::Top)),
            (bw as i32 - 24, 0),
        )?;
        let mut chart = ChartBuilder::on(&body)
            .margin_top(24)
            .margin_right(24)
            .margin_left(12)
            .margin_bottom(12)
            .x_label_area_size(60)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..fmax, ylo..yhi)?;
        let fx = tick_formatter(0.0, fmax, 12);
        let fy = tick_formatter(ylo, yhi, 12);
        chart
            .configure_mesh()
            .x_labels(12)
            .y_labels(12)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .x_desc("f/ωn")
            .y_desc("ω/ωn")
            .label_style(font(TICK_SIZE))
            .axis_desc_style(font(DESC_SIZE))
            .bold_line_style(BLACK.mix(0.10))
            .light_line_style(TRANSPARENT)
            .draw()?;

        if lines.is_empty() {
            draw_no_data(chart.plotting_area())?;
            return Ok(());
        }

        // Back to front: highest speed first, so lower-speed spectra occlude those behind.
        let mut order: Vec<&CascadeLine> = lines.clone();
        order.sort_by(|a, b| b.speed.total_cmp(&a.speed));
        let line_color = RGBColor(20, 40, 110);
        for l in order {
            let n = l.freq.len().min(l.amp.len());
            let mut segments: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
            for i in 0..n {
                let (f, a) = (l.freq[i], l.amp[i]);
                if visible(f, a) {
                    segments
                        .last_mut()
                        .expect("non-empty")
                        .push((f, l.speed + a.abs() * scale));
                } else if segments.last().is_some_and(|s| !s.is_empty()) {
                    segments.push(Vec::new());
                }
            }
            for seg in segments.iter().filter(|s| !s.is_empty()) {
                if seg.len() == 1 {
                    chart.draw_series(std::iter::once(Circle::new(
                        seg[0],
                        2,
                        line_color.filled(),
                    )))?;
                    continue;
                }
                let mut poly = seg.clone();
                poly.push((seg[seg.len() - 1].0, l.speed));
                poly.push((seg[0].0, l.speed));
                chart.draw_series(std::iter::once(Polygon::new(poly, WHITE.filled())))?;
                chart.draw_series(LineSeries::new(seg.iter().copied(), line_color))?;
            }
        }

        // Guide lines f = k·speed.
        let guides: [(f64, &str, RGBColor, u8); 3] = [
            (1.0, "1× (f = ω)", RGBColor(214, 39, 40), 0),
            (0.5, "1/2× (f = ω/2)", RGBColor(44, 160, 44), 1),
            (1.0 / 3.0, "1/3× (f = ω/3)", RGBColor(255, 127, 14), 2),
        ];
        for (k, label, color, kind) in guides {
            let s0 = ylo.max(0.0);
            let s1 = yhi.min(fmax / k);
            let pts: Vec<(f64, f64)> = if s1 > s0 {
                vec![(k * s0, s0), (k * s1, s1)]
            } else {
                Vec::new()
            };
            let style = color.stroke_width(2);
            let anno = match kind {
                0 => chart.draw_series(LineSeries::new(pts, style))?,
                1 => chart.draw_series(DashedLineSeries::new(pts, 12, 7, style))?,
                _ => chart.draw_series(DashedLineSeries::new(pts, 2, 5, style))?,
            };
            anno.label(label).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
            });
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .margin(12)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK.mix(0.5))
            .label_font(font(17.0))
            .draw()?;
        Ok(())
    })
}

/// Bifurcation diagram: Poincaré samples `points` = (speed ω/ωn, value) as small dots; x label
/// `ω/ωn`, y label given.
pub fn bifurcation(path: &Path, title: &str, points: &[(f64, f64)], y_label: &str) -> Result<()> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    let (x0, x1) = padded(finite_range(pts.iter().map(|p| p.0)), 0.02);
    let (y0, y1) = padded(finite_range(pts.iter().map(|p| p.1)), 0.05);
    render(path, (FIG_W, FIG_H), |root| {
        let body = titled(root, title)?;
        let mut chart = ChartBuilder::on(&body)
            .margin(20)
            .margin_right(30)
            .x_label_area_size(60)
            .y_label_area_size(90)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        let fx = tick_formatter(x0, x1, 12);
        let fy = tick_formatter(y0, y1, 12);
        chart
            .configure_mesh()
            .x_labels(12)
            .y_labels(12)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .x_desc("ω/ωn")
            .y_desc(y_label)
            .label_style(font(TICK_SIZE))
            .axis_desc_style(font(DESC_SIZE))
            .bold_line_style(BLACK.mix(0.12))
            .light_line_style(TRANSPARENT)
            .draw()?;
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
        return render(path, (FIG_W, FIG_H), |root| no_data_page(root, title));
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
    render(path, (FIG_W, height), |root| {
        let body = titled(root, title)?;
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
            let mut chart = ChartBuilder::on(&area)
                .caption(&s.label, fitting_font(&area, &s.label, 19.0)?)
                .margin_left(12)
                .margin_right(30)
                .margin_top(4)
                .margin_bottom(if last { 10 } else { 4 })
                .x_label_area_size(if last { 60 } else { 0 })
                .y_label_area_size(100)
                .build_cartesian_2d(x0..x1, y0..y1)?;
            let fy = tick_formatter(y0, y1, 5);
            let mut mesh = chart.configure_mesh();
            mesh.x_labels(12)
                .y_labels(5)
                .x_label_formatter(&fx)
                .y_label_formatter(&fy)
                .y_desc(y_label)
                .label_style(font(15.0))
                .axis_desc_style(font(17.0))
                .bold_line_style(BLACK.mix(0.12))
                .light_line_style(TRANSPARENT);
            if last {
                mesh.x_desc(x_label).x_label_style(font(TICK_SIZE));
            }
            mesh.draw()?;
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
    let samples: Vec<(f64, f64)> = kept
        .iter()
        .flat_map(|c| {
            densify(
                &c.iter()
                    .map(|p| {
                        (
                            (p.0.log10() - lx0) / (lx1 - lx0),
                            (p.1.log10() - ly0) / (ly1 - ly0),
                        )
                    })
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    let labels: Vec<&str> = curves
        .iter()
        .map(|c| c.label.as_str())
        .filter(|l| !l.is_empty())
        .collect();
    let labelled = labels.len();
    let corner = legend_corner(&samples, &labels);
    render(path, (FIG_W, FIG_H), |root| {
        let body = titled(root, title)?;
        let mut chart = ChartBuilder::on(&body)
            .margin(20)
            .margin_right(36)
            .x_label_area_size(60)
            .y_label_area_size(100)
            .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())?;
        let fx = log_formatter(x0, x1);
        let fy = log_formatter(y0, y1);
        chart
            .configure_mesh()
            .x_labels(10)
            .y_labels(10)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .x_desc(x_label)
            .y_desc(y_label)
            .label_style(font(TICK_SIZE))
            .axis_desc_style(font(DESC_SIZE))
            .bold_line_style(BLACK.mix(0.15))
            .light_line_style(BLACK.mix(0.035))
            .draw()?;
        if !has_data {
            draw_no_data(chart.plotting_area())?;
            return Ok(());
        }
        for (i, (curve, pts)) in curves.iter().zip(&kept).enumerate() {
            let color = PALETTE[i % PALETTE.len()];
            let shape = marker_shape(i, 6);
            if pts.len() > 1 {
                chart.draw_series(LineSeries::new(pts.iter().copied(), color.stroke_width(2)))?;
            }
            let anno = chart.draw_series(
                pts.iter()
                    .map(|&p| EmptyElement::at(p) + Polygon::new(shape.clone(), color.filled())),
            )?;
            if !curve.label.is_empty() {
                let legend_shape = marker_shape(i, 6);
                anno.label(curve.label.as_str()).legend(move |(x, y)| {
                    EmptyElement::at((x + 12, y))
                        + PathElement::new(vec![(-12, 0), (12, 0)], color.stroke_width(2))
                        + Polygon::new(legend_shape.clone(), color.filled())
                });
            }
        }
        if labelled > 0 {
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
    let segs: Vec<Vec<Vec<(f64, f64)>>> = curves
        .iter()
        .map(|c| {
            let (x, y): (Vec<f64>, Vec<f64>) = c.points.iter().copied().unzip();
            finite_segments(&x, &y)
        })
        .collect();
    let all = || segs.iter().flatten().flatten();
    let (x0, x1) = padded(finite_range(all().map(|p| p.0)), 0.02);
    let (y0, y1) = padded(finite_range(all().map(|p| p.1)), 0.05);
    let has_data = all().next().is_some();
    let samples: Vec<(f64, f64)> = segs
        .iter()
        .flatten()
        .flat_map(|s| {
            densify(
                &s.iter()
                    .map(|p| ((p.0 - x0) / (x1 - x0), (p.1 - y0) / (y1 - y0)))
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    let labels: Vec<&str> = curves
        .iter()
        .map(|c| c.label.as_str())
        .filter(|l| !l.is_empty())
        .collect();
    let labelled = labels.len();
    let corner = legend_corner(&samples, &labels);
    render(path, (FIG_W, FIG_H), |root| {
        let body = titled(root, title)?;
        let mut chart = ChartBuilder::on(&body)
            .margin(20)
            .margin_right(36)
            .x_label_area_size(60)
            .y_label_area_size(100)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        let fx = tick_formatter(x0, x1, 12);
        let fy = tick_formatter(y0, y1, 12);
        chart
            .configure_mesh()
            .x_labels(12)
            .y_labels(12)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .x_desc(x_label)
            .y_desc(y_label)
            .label_style(font(TICK_SIZE))
            .axis_desc_style(font(DESC_SIZE))
            .bold_line_style(BLACK.mix(0.12))
            .light_line_style(BLACK.mix(0.03))
            .draw()?;
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
        if labelled > 0 {
            draw_legend(&mut chart, corner)?;
        }
        Ok(())
    })
}

// ---------------------------------------------------------------------------------------------
// Rendering infrastructure
// ---------------------------------------------------------------------------------------------

/// Registers the embedded font once; an error message if it cannot be parsed.
fn ensure_font() -> std::result::Result<(), &'static str> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err("the embedded font DejaVuSans.ttf could not be loaded")
    }
}

/// Text style of the embedded font at `size` pixels, black.
fn font(size: f64) -> TextStyle<'static> {
    (FONT, size).into_font().color(&BLACK)
}

/// Renders a figure of `size` pixels with `draw` and writes it as PNG to `path`.
///
/// The bitmap encoder picks the format from the file extension, so a path without a `.png`
/// extension (e.g. a caller's temporary name) is rendered to a uniquely named `.png` sibling
/// first and then renamed to `path`. On failure no file is left behind.
fn render<F>(path: &Path, size: (u32, u32), draw: F) -> Result<()>
where
    F: FnOnce(&Root<'_>) -> DrawResult,
{
    ensure_font().map_err(|m| Error::output(path, m))?;
    let size = (size.0.clamp(200, 20_000), size.1.clamp(200, 20_000));
    let direct = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    let target = if direct {
        path.to_path_buf()
    } else {
        staging_path(path)
    };
    let outcome = (|| -> Result<()> {
        let root = BitMapBackend::new(&target, size).into_drawing_area();
        root.fill(&WHITE)
            .map_err(|e| Error::output(path, format!("cannot draw plot: {e}")))?;
        draw(&root).map_err(|e| Error::output(path, format!("cannot draw plot: {e}")))?;
        root.present()
            .map_err(|e| Error::output(path, format!("cannot write PNG: {e}")))?;
        Ok(())
    })();
    match outcome {
        Ok(()) if direct => Ok(()),
        Ok(()) => std::fs::rename(&target, path).map_err(|e| {
            let _ = std::fs::remove_file(&target);
            Error::output(path, format!("cannot move rendered PNG into place: {e}"))
        }),
        Err(e) => {
            // The bitmap backend saves on drop even after a drawing error; remove the debris.
            let _ = std::fs::remove_file(&target);
            Err(e)
        }
    }
}

/// A unique `.png` sibling of `path` used when `path` itself has no `.png` extension.
fn staging_path(path: &Path) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "plot".to_string());
    let k = COUNTER.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.{}-{k}.staging.png", std::process::id()))
}

/// Draws the figure title at the top of `root` (with some air above it) and returns the area
/// below it.
fn titled<'a>(root: &Root<'a>, title: &str) -> std::result::Result<Root<'a>, Box<dyn StdError>> {
    let root = root.margin(10, 0, 0, 0);
    let style = fitting_font(&root, title, TITLE_SIZE)?;
    Ok(root.titled(title, style)?)
}

/// The embedded font at `size`, shrunk (down to 10 px) so that `text` fits the width of `area`
/// with a 10-pixel margin on each side.
fn fitting_font<C: CoordTranslate>(
    area: &DrawingArea<BitMapBackend<'_>, C>,
    text: &str,
    size: f64,
) -> std::result::Result<TextStyle<'static>, Box<dyn StdError>> {
    let (w, _) = area.dim_in_pixel();
    let avail = f64::from(w.saturating_sub(20).max(1));
    let (tw, _) = area.estimate_text_size(text, &font(size))?;
    if f64::from(tw) <= avail {
        return Ok(font(size));
    }
    Ok(font((size * avail / f64::from(tw)).floor().max(10.0)))
}

/// A page with only the title and a centred "no data".
fn no_data_page(root: &Root<'_>, title: &str) -> DrawResult {
    let body = titled(root, title)?;
    let (w, h) = body.dim_in_pixel();
    body.draw_text(
        "no data",
        &font(32.0)
            .color(&RGBColor(120, 120, 120))
            .pos(Pos::new(HPos::Center, VPos::Center)),
        (w as i32 / 2, h as i32 / 2),
    )?;
    Ok(())
}

/// Writes "no data" in the middle of a plotting area.
fn draw_no_data<C: CoordTranslate>(area: &DrawingArea<BitMapBackend<'_>, C>) -> DrawResult {
    let (w, h) = area.dim_in_pixel();
    let plain = area.strip_coord_spec();
    plain.draw_text(
        "no data",
        &font(26.0)
            .color(&RGBColor(120, 120, 120))
            .pos(Pos::new(HPos::Center, VPos::Center)),
        (w as i32 / 2, h as i32 / 2),
    )?;
    Ok(())
}

/// Draws polyline segments with 1-pixel antialiased lines, once per `brush` offset (data
/// units; several offsets of one pixel give a smooth thicker line, unlike the polygonised wide
/// strokes of the bitmap backend). Segments that collapse to one point are drawn as dots.
fn draw_segments<X, Y>(
    chart: &mut ChartContext<'_, BitMapBackend<'_>, Cartesian2d<X, Y>>,
    segs: &[Vec<(f64, f64)>],
    color: RGBColor,
    brush: &[(f64, f64)],
) -> DrawResult
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    for seg in segs {
        let Some(&first) = seg.first() else {
            continue;
        };
        if seg.iter().all(|p| *p == first) {
            chart.draw_series(std::iter::once(Circle::new(first, 3, color.filled())))?;
            continue;
        }
        for &(dx, dy) in brush {
            chart.draw_series(LineSeries::new(
                seg.iter().map(|p| (p.0 + dx, p.1 + dy)),
                color,
            ))?;
        }
    }
    Ok(())
}

/// Brush offsets (data units) for a two-pixel line on a linear chart.
fn thick_brush<X, Y>(
    chart: &ChartContext<'_, BitMapBackend<'_>, Cartesian2d<X, Y>>,
) -> Vec<(f64, f64)>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let (w, h) = chart.plotting_area().dim_in_pixel();
    let xr = chart.x_range();
    let yr = chart.y_range();
    let dx = (xr.end - xr.start) / f64::from(w.max(1));
    let dy = (yr.end - yr.start) / f64::from(h.max(1));
    vec![(0.0, 0.0), (dx, 0.0), (0.0, dy), (dx, dy)]
}

/// Draws the series legend at `corner`.
fn draw_legend<'a, X, Y>(
    chart: &mut ChartContext<'a, BitMapBackend<'a>, Cartesian2d<X, Y>>,
    corner: SeriesLabelPosition,
) -> DrawResult
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    chart
        .configure_series_labels()
        .position(corner)
        .margin(14)
        .legend_area_size(36)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.mix(0.5))
        .label_font(font(18.0))
        .draw()?;
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Orbit panels
// ---------------------------------------------------------------------------------------------

/// Draws one orbit panel into `cell`.
fn draw_orbit_panel(cell: &Root<'_>, panel: &OrbitPanel) -> DrawResult {
    const ML: i32 = 8;
    const MR: i32 = 22;
    const MT: i32 = 6;
    const MB: i32 = 8;
    const XLA: i32 = 46;
    const YLA: i32 = 62;
    let inner = cell.titled(&panel.title, fitting_font(cell, &panel.title, 20.0)?)?;
    let (w, h) = inner.dim_in_pixel();
    let pw = f64::from((w as i32 - ML - MR - YLA).max(20));
    let ph = f64::from((h as i32 - MT - MB - XLA).max(20));

    let segs = finite_segments(&panel.x, &panel.y);
    let poincare: Vec<(f64, f64)> = panel
        .poincare
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    // Boundary geometry (only if well defined).
    let line = match panel.boundary {
        Boundary::Line {
            angle_deg,
            distance,
        } if angle_deg.is_finite() && distance.is_finite() => {
            let a = angle_deg.to_radians();
            Some(((a.cos(), a.sin()), distance))
        }
        _ => None,
    };
    let circle = match panel.boundary {
        Boundary::Circle { radius } if radius.is_finite() && radius > 0.0 => Some(radius),
        _ => None,
    };

    // Data extent: orbit, Poincaré points, and the boundary (foot of the line, whole circle).
    let mut extent_pts: Vec<(f64, f64)> = segs.iter().flatten().copied().collect();
    extent_pts.extend(&poincare);
    if let Some(((nx, ny), d)) = line {
        extent_pts.push((nx * d, ny * d));
    }
    if let Some(r) = circle {
        extent_pts.extend([(-r, -r), (r, r)]);
    }
    let (xr, yr) = equal_aspect_ranges(&extent_pts, pw, ph);

    let mut chart = ChartBuilder::on(&inner)
        .margin_left(ML)
        .margin_right(MR)
        .margin_top(MT)
        .margin_bottom(MB)
        .x_label_area_size(XLA)
        .y_label_area_size(YLA)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;

    // Stator region (grey) below the mesh.
    if let Some(((nx, ny), d)) = line {
        let rect = [(xr.0, yr.0), (xr.1, yr.0), (xr.1, yr.1), (xr.0, yr.1)];
        let region = clip_half_plane(&rect, (nx, ny), d);
        if region.len() >= 3 {
            chart.draw_series(std::iter::once(Polygon::new(region, STATOR_FILL.filled())))?;
        }
    }
    let circle_pts = circle.map(|r| {
        (0..=360)
            .map(|k| {
                let a = f64::from(k).to_radians();
                (r * a.cos(), r * a.sin())
            })
            .collect::<Vec<_>>()
    });
    if let Some(cp) = &circle_pts {
        chart.draw_series(std::iter::once(Rectangle::new(
            [(xr.0, yr.0), (xr.1, yr.1)],
            STATOR_FILL.filled(),
        )))?;
        chart.draw_series(std::iter::once(Polygon::new(cp.clone(), WHITE.filled())))?;
    }

    let fx = tick_formatter(xr.0, xr.1, 6);
    let fy = tick_formatter(yr.0, yr.1, 6);
    chart
        .configure_mesh()
        .x_labels(6)
        .y_labels(6)
        .x_label_formatter(&fx)
        .y_label_formatter(&fy)
        .x_desc("x/|Z0|")
        .y_desc("y/|Z0|")
        .label_style(font(15.0))
        .axis_desc_style(font(17.0))
        .bold_line_style(BLACK.mix(0.12))
        .light_line_style(TRANSPARENT)
        .draw()?;

    // Boundary line on top of the mesh.
    let edge = RGBColor(30, 30, 30);
    let brush = thick_brush(&chart);
    if let Some(((nx, ny), d)) = line {
        let big = 4.0 * (xr.1 - xr.0 + yr.1 - yr.0 + d.abs());
        let p0 = (nx * d - ny * big, ny * d + nx * big);
        let p1 = (nx * d + ny * big, ny * d - nx * big);
        if let Some((a, b)) = clip_segment(p0, p1, xr, yr) {
            draw_segments(&mut chart, &[vec![a, b]], edge, &brush)?;
        }
    }
    if let Some(cp) = circle_pts {
        draw_segments(&mut chart, &[cp], edge, &brush)?;
    }

    let orbit = PALETTE[0];
    draw_segments(&mut chart, &segs, orbit, &[(0.0, 0.0)])?;
    let red = RGBColor(214, 39, 40).filled();
    chart.draw_series(poincare.iter().map(|&p| Circle::new(p, 3, red)))?;

    if segs.is_empty() && poincare.is_empty() {
        draw_no_data(chart.plotting_area())?;
    }
    Ok(())
}

/// Axis ranges containing `pts` (padded) with equal data units per pixel on a plotting area of
/// `pw` × `ph` pixels.
fn equal_aspect_ranges(pts: &[(f64, f64)], pw: f64, ph: f64) -> ((f64, f64), (f64, f64)) {
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
fn clip_half_plane(poly: &[(f64, f64)], n: (f64, f64), d: f64) -> Vec<(f64, f64)> {
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
fn clip_segment(
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

// ---------------------------------------------------------------------------------------------
// Data helpers
// ---------------------------------------------------------------------------------------------

/// Largest magnitude kept for range computations (guards against overflowing spans).
const HUGE: f64 = 1e150;

/// Minimum and maximum of the finite values (clamped to ±[`HUGE`]); `None` if there are none.
fn finite_range<I: IntoIterator<Item = f64>>(values: I) -> Option<(f64, f64)> {
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
fn padded(range: Option<(f64, f64)>, frac: f64) -> (f64, f64) {
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
fn padded_log(range: Option<(f64, f64)>) -> (f64, f64) {
    match range {
        None => (-1.0, 1.0),
        Some((lo, hi)) if hi - lo < 1.0 => {
            let c = 0.5 * (lo + hi);
            (c - 0.5 - 0.15, c + 0.5 + 0.15)
        }
        Some((lo, hi)) => (lo - 0.15, hi + 0.15),
    }
}

/// Splits the paired samples into runs of finite points.
fn finite_segments(x: &[f64], y: &[f64]) -> Vec<Vec<(f64, f64)>> {
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
fn densify(pts: &[(f64, f64)]) -> Vec<(f64, f64)> {
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
fn legend_corner(samples: &[(f64, f64)], labels: &[&str]) -> SeriesLabelPosition {
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
fn marker_shape(i: usize, r: i32) -> Vec<(i32, i32)> {
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

// ---------------------------------------------------------------------------------------------
// Number formatting
// ---------------------------------------------------------------------------------------------

/// Tick-label formatter for a linear axis over `lo..hi` with about `n` labels: fixed decimals
/// matching the tick step, scientific notation for very large or very small magnitudes.
fn tick_formatter(lo: f64, hi: f64, n: usize) -> impl Fn(&f64) -> String {
    let span = (hi - lo).abs();
    let raw = if span > 0.0 {
        span / n.max(1) as f64
    } else {
        1.0
    };
    let p = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * p)
        .find(|s| *s >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0 * p);
    let mag = lo.abs().max(hi.abs());
    let sci = !(1e-3..1e5).contains(&mag);
    let decimals = (-step.log10().floor()).clamp(0.0, 12.0) as usize;
    let sci_decimals = (mag.log10().floor() - step.log10().floor()).clamp(0.0, 6.0) as usize;
    move |v: &f64| {
        let v = if v.abs() < step * 1e-6 { 0.0 } else { *v };
        if v == 0.0 {
            "0".to_string()
        } else if sci {
            trim_mantissa(&format!("{v:.sci_decimals$e}"))
        } else {
            format!("{v:.decimals$}")
        }
    }
}

/// Removes trailing zeros of the mantissa of a number in `{:e}` format (`1.50e-9` → `1.5e-9`).
fn trim_mantissa(s: &str) -> String {
    match s.split_once('e') {
        Some((m, e)) if m.contains('.') => {
            let m = m.trim_end_matches('0').trim_end_matches('.');
            format!("{m}e{e}")
        }
        _ => s.to_string(),
    }
}

/// Tick-label formatter of a logarithmic axis over `lo..hi`: plain decimals if the whole axis
/// lies within 0.01..10⁴, otherwise powers of ten (`10⁻⁵`, `2×10⁻⁵`) throughout.
fn log_formatter(lo: f64, hi: f64) -> impl Fn(&f64) -> String {
    let plain = lo >= 0.00999 && hi <= 10_001.0;
    move |v: &f64| log_label(*v, plain)
}

/// Tick label of a logarithmic axis: plain decimals if `plain`, otherwise `10⁻⁵` or `2×10⁻⁵`.
fn log_label(v: f64, plain: bool) -> String {
    if !(v.is_finite() && v > 0.0) {
        return String::new();
    }
    let e = v.log10().floor();
    let m = v / 10f64.powf(e);
    let (m, e) = if m >= 9.9995 { (1.0, e + 1.0) } else { (m, e) };
    if plain {
        let d = (-e).max(0.0) as usize + usize::from((m - m.round()).abs() > 1e-6);
        return format!("{v:.d$}");
    }
    let exp = superscript(e as i64);
    if (m - 1.0).abs() < 1e-6 {
        format!("10{exp}")
    } else if (m - m.round()).abs() < 1e-6 {
        format!("{}×10{exp}", m.round())
    } else {
        format!("{m:.1}×10{exp}")
    }
}

/// An integer in Unicode superscript digits.
fn superscript(k: i64) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::new();
    if k < 0 {
        s.push('⁻');
    }
    for c in k.unsigned_abs().to_string().chars() {
        s.push(DIGITS[c.to_digit(10).unwrap_or(0) as usize]);
    }
    s
}

/// A number with about three significant digits.
fn fmt_sig(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".to_string()
    } else if !(1e-3..1e5).contains(&a) {
        format!("{v:.2e}")
    } else {
        let d = (2.0 - a.log10().floor()).clamp(0.0, 6.0) as usize;
        format!("{v:.d$}")
    }
}

/// A 2-D mesh coloured by a value per cell (e.g. the von Mises stress of a meshed stator):
/// each cell a filled polygon, coordinates in m drawn in mm with equal axes, values on a
/// perceptual blue–yellow scale with a colour bar labelled `value_label`; `marks` (m) are drawn
/// as black crosses (e.g. the contact nodes in contact). Non-finite values are drawn grey.
pub fn mesh_field(
    path: &Path,
    title: &str,
    cells: &[(Vec<(f64, f64)>, f64)],
    value_label: &str,
    marks: &[(f64, f64)],
) -> Result<()> {
    if cells.is_empty() {
        return render(path, (FIG_W, FIG_H), |root| no_data_page(root, title));
    }
    let pts = || cells.iter().flat_map(|c| c.0.iter());
    let (x0, x1) = padded(finite_range(pts().map(|p| 1e3 * p.0)), 0.04);
    let (y0, y1) = padded(finite_range(pts().map(|p| 1e3 * p.1)), 0.04);
    let (v0, v1) = padded(finite_range(cells.iter().map(|c| c.1)), 0.0);
    // Equal axes: widen the shorter span to the plot area's aspect ratio.
    let (pw, ph) = (f64::from(FIG_W) - 320.0, f64::from(FIG_H) - 160.0);
    let (sx, sy) = (x1 - x0, y1 - y0);
    let (x0, x1, y0, y1) = if sx / sy > pw / ph {
        let d = 0.5 * (sx * ph / pw - sy);
        (x0, x1, y0 - d, y1 + d)
    } else {
        let d = 0.5 * (sy * pw / ph - sx);
        (x0 - d, x1 + d, y0, y1)
    };
    let colour = |v: f64| -> RGBColor {
        if !v.is_finite() {
            return RGBColor(170, 170, 170);
        }
        // Viridis at five stops, linear in between.
        const STOPS: [(f64, f64, f64); 5] = [
            (68.0, 1.0, 84.0),
            (59.0, 82.0, 139.0),
            (33.0, 145.0, 140.0),
            (94.0, 201.0, 98.0),
            (253.0, 231.0, 37.0),
        ];
        let t = ((v - v0) / (v1 - v0)).clamp(0.0, 1.0) * 4.0;
        let i = (t.floor() as usize).min(3);
        let f = t - i as f64;
        let (a, b) = (STOPS[i], STOPS[i + 1]);
        let mix = |p: f64, q: f64| (p + f * (q - p)).round() as u8;
        RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
    };
    let fx = tick_formatter(x0, x1, 8);
    let fy = tick_formatter(y0, y1, 8);
    let fv = tick_formatter(v0, v1, 6);
    render(path, (FIG_W, FIG_H), |root| {
        let body = titled(root, title)?;
        let (w, _) = body.dim_in_pixel();
        let (plot, bar) = body.split_horizontally(w.saturating_sub(190));
        let mut chart = ChartBuilder::on(&plot)
            .margin(20)
            .x_label_area_size(60)
            .y_label_area_size(80)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        chart
            .configure_mesh()
            .x_desc("x (mm)")
            .y_desc("y (mm)")
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .label_style(font(TICK_SIZE))
            .axis_desc_style(font(20.0))
            .disable_mesh()
            .draw()?;
        chart.draw_series(cells.iter().map(|(poly, v)| {
            let p: Vec<(f64, f64)> = poly.iter().map(|q| (1e3 * q.0, 1e3 * q.1)).collect();
            Polygon::new(p, colour(*v).filled())
        }))?;
        chart.draw_series(
            marks
                .iter()
                .map(|m| Cross::new((1e3 * m.0, 1e3 * m.1), 5, BLACK.stroke_width(2))),
        )?;
        // Colour bar.
        let mut cb = ChartBuilder::on(&bar)
            .margin_top(40)
            .margin_bottom(80)
            .margin_right(20)
            .y_label_area_size(110)
            .caption(value_label, fitting_font(&bar, value_label, 18.0)?)
            .build_cartesian_2d(0.0..1.0, v0..v1)?;
        cb.configure_mesh()
            .disable_x_axis()
            .disable_mesh()
            .y_labels(6)
            .y_label_formatter(&fv)
            .label_style(font(TICK_SIZE))
            .draw()?;
        let n = 200;
        cb.draw_series((0..n).map(|i| {
            let a = v0 + (v1 - v0) * i as f64 / n as f64;
            let b = v0 + (v1 - v0) * (i + 1) as f64 / n as f64;
            Rectangle::new([(0.0, a), (1.0, b)], colour(0.5 * (a + b)).filled())
        }))?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh, unique output directory under the system temp dir.
    fn out_dir(tag: &str) -> PathBuf {
        static N: AtomicUsize = AtomicUsize::new(0);
        let dir = std::env::temp_dir().join(format!(
            "rubsim-plot-test-{}-{}-{tag}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&dir).expect("create test dir");
        dir
    }

    fn assert_png(path: &Path) {
        let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        assert!(
            bytes.len() > 1024,
            "{}: only {} bytes",
            path.display(),
            bytes.len()
        );
        assert_eq!(
            &bytes[..8],
            b"\x89PNG\r\n\x1a\n",
            "{}: not a PNG",
            path.display()
        );
    }

    /// Writes synthetic figures of every kind into `dir`; returns the files.
    fn write_all(dir: &Path) -> Vec<PathBuf> {
        let tau = std::f64::consts::TAU;
        let mut files = Vec::new();

        // Orbit grid: free orbit, rod contact, ring with NaN gap, tiny/degenerate, empty.
        let n = 2000;
        let t: Vec<f64> = (0..n).map(|k| 20.0 * tau * k as f64 / n as f64).collect();
        let circle = |r: f64, cx: f64, cy: f64| -> (Vec<f64>, Vec<f64>) {
            (
                t.iter().map(|s| cx + r * s.cos()).collect(),
                t.iter().map(|s| cy + r * s.sin()).collect(),
            )
        };
        let (x1, y1) = circle(0.6, 0.0, 0.0);
        let (x2, mut y2) = circle(0.9, 0.0, 0.2);
        for y in &mut y2 {
            *y = y.min(1.0);
        }
        let (mut x3, y3) = (
            t.iter()
                .map(|s| 0.7 * s.cos() + 0.2 * (s / 2.0).cos())
                .collect::<Vec<_>>(),
            t.iter()
                .map(|s| 0.7 * s.sin() + 0.2 * (s / 2.0).sin())
                .collect::<Vec<_>>(),
        );
        for v in x3.iter_mut().skip(500).take(50) {
            *v = f64::NAN;
        }
        let panels = vec![
            OrbitPanel {
                title: "ω/ωn = 0.50".into(),
                x: x1,
                y: y1,
                boundary: Boundary::Line {
                    angle_deg: 90.0,
                    distance: 1.0,
                },
                poincare: vec![(0.6, 0.0)],
            },
            OrbitPanel {
                title: "ω/ωn = 1.20 (rub)".into(),
                x: x2,
                y: y2,
                boundary: Boundary::Line {
                    angle_deg: 90.0,
                    distance: 1.0,
                },
                poincare: vec![(0.9, 0.2), (-0.3, 0.9)],
            },
            OrbitPanel {
                title: "ring, 1/2× whirl".into(),
                x: x3,
                y: y3,
                boundary: Boundary::Circle { radius: 1.0 },
                poincare: vec![(0.9, 0.0), (0.5, 0.0)],
            },
            OrbitPanel {
                title: "oblique rod, single point".into(),
                x: vec![0.3],
                y: vec![0.2],
                boundary: Boundary::Line {
                    angle_deg: 45.0,
                    distance: 0.5,
                },
                poincare: vec![],
            },
            OrbitPanel {
                title: "empty".into(),
                x: vec![],
                y: vec![],
                boundary: Boundary::None,
                poincare: vec![],
            },
        ];
        let p = dir.join("orbits.png");
        orbit_grid(&p, "Orbits (synthetic), rod stator", &panels, 3).expect("orbit grid");
        files.push(p);
        let p = dir.join("orbits_empty.png");
        orbit_grid(&p, "No orbits", &[], 3).expect("orbit grid empty");
        files.push(p);

        // Cascade.
        let nf = 400;
        let fmax = 3.0;
        let spectra: Vec<CascadeLine> = (0..30)
            .map(|k| {
                let speed = 0.2 + 0.1 * k as f64;
                let freq: Vec<f64> = (0..nf).map(|i| fmax * i as f64 / nf as f64).collect();
                let peak = |f: f64, f0: f64, a: f64| a * (-((f - f0) / 0.02).powi(2)).exp();
                let amp = freq
                    .iter()
                    .map(|&f| {
                        peak(f, speed, 1.0)
                            + if speed > 2.0 {
                                peak(f, speed / 2.0, 1.5)
                            } else {
                                0.0
                            }
                            + peak(f, 1.0, 0.3)
                            + 0.01
                    })
                    .collect();
                CascadeLine { speed, freq, amp }
            })
            .collect();
        let p = dir.join("cascade.png");
        cascade(&p, "Spectrum cascade |Y| (synthetic)", &spectra, fmax, 0.8).expect("cascade");
        files.push(p);
        let p = dir.join("cascade_empty.png");
        cascade(&p, "Empty cascade", &[], 2.0, 0.8).expect("cascade empty");
        files.push(p);

        // Bifurcation diagram: logistic-map-like cloud + NaN.
        let mut pts = Vec::new();
        for k in 0..400 {
            let s = 0.5 + 2.5 * k as f64 / 400.0;
            let r = 2.8 + 1.2 * (s - 0.5) / 2.5;
            let mut x: f64 = 0.3;
            for i in 0..300 {
                x = r * x * (1.0 - x);
                if i >= 200 {
                    pts.push((s, x));
                }
            }
        }
        pts.push((f64::NAN, 0.5));
        let p = dir.join("bifurcation.png");
        bifurcation(
            &p,
            "Bifurcation diagram (synthetic)",
            &pts,
            "y/|Z0| at t = k·2π/ω",
        )
        .expect("bifurcation");
        files.push(p);
        let p = dir.join("bifurcation_single.png");
        bifurcation(&p, "Single point", &[(1.0, 0.0)], "y").expect("bifurcation single");
        files.push(p);

        // Stacked series.
        let ts: Vec<f64> = (0..3000).map(|k| k as f64 * 1e-4).collect();
        let f1: Vec<f64> = ts
            .iter()
            .map(|t| ((tau * 50.0 * t).sin() * 1200.0).max(0.0))
            .collect();
        let mut f2: Vec<f64> = ts
            .iter()
            .map(|t| ((tau * 25.0 * t).sin() * 3.0e-4).max(0.0))
            .collect();
        f2[1000] = f64::NAN;
        let series = vec![
            Series {
                label: "contact force, node 3".into(),
                t: ts.clone(),
                y: f1,
            },
            Series {
                label: "contact force, node 4".into(),
                t: ts.clone(),
                y: f2,
            },
            Series {
                label: "zero".into(),
                t: ts.clone(),
                y: vec![0.0; ts.len()],
            },
            Series {
                label: "empty".into(),
                t: vec![],
                y: vec![],
            },
        ];
        let p = dir.join("stacked.png");
        stacked_series(&p, "Contact forces (synthetic)", &series, "t (s)", "F (N)")
            .expect("stacked");
        files.push(p);

        // Log–log.
        let curves: Vec<Curve> = (0..7)
            .map(|k| Curve {
                label: format!("method {k} (order {})", k % 3 + 1),
                points: (0..8)
                    .map(|i| {
                        let dt = 1e-3 / 2f64.powi(i);
                        (
                            dt,
                            (k as f64 + 1.0) * dt.powi(k % 3 + 1) * 10f64.powi(k % 3),
                        )
                    })
                    .chain([(0.0, 1.0), (f64::NAN, 1.0)])
                    .collect(),
            })
            .collect();
        let p = dir.join("loglog.png");
        loglog(
            &p,
            "Error vs Δt (synthetic)",
            &curves,
            "Δt (s)",
            "relative error",
        )
        .expect("loglog");
        files.push(p);
        let p = dir.join("loglog_single.png");
        loglog(
            &p,
            "Single point",
            &[Curve {
                label: "one".into(),
                points: vec![(2.0, 3.0)],
            }],
            "x",
            "y",
        )
        .expect("loglog single");
        files.push(p);

        // Lines.
        let xs: Vec<f64> = (0..500).map(|i| i as f64 * 0.01).collect();
        let curves = vec![
            Curve {
                label: "sin".into(),
                points: xs.iter().map(|&x| (x, (tau * x).sin())).collect(),
            },
            Curve {
                label: "cos with NaN gap".into(),
                points: xs
                    .iter()
                    .map(|&x| {
                        (
                            x,
                            if (2.0..2.5).contains(&x) {
                                f64::NAN
                            } else {
                                (tau * x).cos() * 0.5
                            },
                        )
                    })
                    .collect(),
            },
            Curve {
                label: "single point".into(),
                points: vec![(2.5, 0.8)],
            },
        ];
        let p = dir.join("lines.png");
        lines(&p, "Lines (synthetic)", &curves, "f/ωn", "amplitude").expect("lines");
        files.push(p);
        let p = dir.join("lines_flat.png");
        lines(
            &p,
            "Flat",
            &[Curve {
                label: String::new(),
                points: vec![(1.0, 5.0), (1.0, 5.0)],
            }],
            "x",
            "y",
        )
        .expect("lines flat");
        files.push(p);
        files
    }

    #[test]
    fn every_kind_writes_a_png() {
        let dir = out_dir("all");
        for f in write_all(&dir) {
            assert_png(&f);
        }
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn empty_inputs_write_pngs() {
        let dir = out_dir("empty");
        let p = dir.join("a.png");
        stacked_series(&p, "", &[], "t", "y").expect("stacked empty");
        assert_png(&p);
        loglog(&p, "t", &[], "x", "y").expect("loglog empty");
        assert_png(&p);
        lines(&p, "t", &[], "x", "y").expect("lines empty");
        assert_png(&p);
        bifurcation(&p, "t", &[], "y").expect("bifurcation empty");
        assert_png(&p);
        let all_nan = Curve {
            label: "nan".into(),
            points: vec![(f64::NAN, f64::NAN), (-1.0, 0.0)],
        };
        loglog(&p, "t", std::slice::from_ref(&all_nan), "x", "y").expect("loglog nan");
        assert_png(&p);
        lines(&p, "t", &[all_nan], "x", "y").expect("lines nan");
        assert_png(&p);
        let one = CascadeLine {
            speed: 1.0,
            freq: vec![0.0, 0.5, 1.0, f64::NAN],
            amp: vec![0.0, 0.0, 1.0, 2.0],
        };
        cascade(&p, "t", &[one], f64::NAN, f64::NAN).expect("cascade single");
        assert_png(&p);
        orbit_grid(
            &p,
            "t",
            &[OrbitPanel {
                title: String::new(),
                x: vec![f64::NAN; 3],
                y: vec![1.0; 3],
                boundary: Boundary::Circle { radius: -1.0 },
                poincare: vec![(f64::INFINITY, 0.0)],
            }],
            0,
        )
        .expect("orbit nan");
        assert_png(&p);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn non_png_extension_is_written_exactly() {
        let dir = out_dir("tmpname");
        let p = dir.join("figure.png.tmp");
        bifurcation(&p, "tmp", &[(1.0, 2.0), (2.0, 3.0)], "y").expect("bifurcation");
        assert_png(&p);
        let names: Vec<_> = std::fs::read_dir(&dir)
            .expect("read dir")
            .map(|e| e.expect("entry").file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("figure.png.tmp")]);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn missing_directory_is_an_output_error() {
        let dir = out_dir("missing");
        let p = dir.join("no/such/dir/x.png");
        let err = lines(&p, "t", &[], "x", "y").expect_err("must fail");
        assert!(matches!(err, Error::Output { .. }), "{err}");
        assert!(!p.exists());
        let _ = std::fs::remove_dir_all(&dir);
    }

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
        let f = tick_formatter(0.0, 1.0, 10);
        assert_eq!(f(&0.3), "0.3");
        assert_eq!(f(&-1e-17), "0");
        let f = tick_formatter(0.0, 2e-6, 10);
        assert_eq!(f(&1e-6), "1e-6");
        assert_eq!(f(&1.5e-6), "1.5e-6");
        assert_eq!(trim_mantissa("5.00e-10"), "5e-10");
        assert_eq!(log_label(1e-5, false), "10⁻⁵");
        assert_eq!(log_label(0.01, true), "0.01");
        assert_eq!(log_label(0.01, false), "10⁻²");
        assert_eq!(log_label(100.0, true), "100");
        assert_eq!(log_label(2e6, false), "2×10⁶");
        let sq = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        assert_eq!(clip_half_plane(&sq, (0.0, 1.0), 0.5).len(), 4);
        assert!(clip_half_plane(&sq, (0.0, 1.0), 2.0).is_empty());
        let s = clip_segment((-5.0, 0.0), (5.0, 0.0), (-1.0, 1.0), (-1.0, 1.0));
        assert_eq!(s, Some(((-1.0, 0.0), (1.0, 0.0))));
    }
}
