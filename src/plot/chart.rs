//! The building blocks every chart shares: the [`Frame`] (margins and label areas) and the
//! [`Axes`] (ticks, descriptions, grid) of a chart, a titled page, "no data" notes, polylines
//! drawn with a pixel brush, and the legend box.
//!
//! The `ChartBuilder` margins and the mesh configuration (tick counts, formatters,
//! descriptions, fonts, grid colours) are written here once; each figure states only its own
//! numbers, in a `Frame` and an `Axes`.

use std::error::Error as StdError;
use std::path::Path;

use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::style::{
    fitting_font, font, render, DrawResult, Root, DESC_SIZE, FIG_H, FIG_W, TICK_SIZE, TITLE_SIZE,
};
use crate::error::Result;

/// A chart with linear `f64` axes on a bitmap.
pub(super) type LinChart<'a, 'b> =
    ChartContext<'a, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Where a chart sits in its drawing area, in pixels: the margins around it and the sizes of
/// the tick-label areas below (x) and left of (y) the plotting area.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    /// Margin above the chart (and its caption, if any).
    pub top: i32,
    /// Margin right of the plotting area.
    pub right: i32,
    /// Margin below the x label area.
    pub bottom: i32,
    /// Margin left of the y label area.
    pub left: i32,
    /// Height of the x label area (0: no x tick labels or description).
    pub x_area: i32,
    /// Width of the y label area.
    pub y_area: i32,
}

impl Frame {
    /// A chart builder on `area` with this frame; the caller adds a caption if it wants one and
    /// builds the coordinate system.
    pub fn builder<'a, 'b>(&self, area: &'a Root<'b>) -> ChartBuilder<'a, 'b, BitMapBackend<'b>> {
        let mut builder = ChartBuilder::on(area);
        builder
            .margin_top(self.top)
            .margin_right(self.right)
            .margin_bottom(self.bottom)
            .margin_left(self.left)
            .x_label_area_size(self.x_area)
            .y_label_area_size(self.y_area);
        builder
    }
}

/// Grid lines of a chart: the opacity of the black major lines (at the tick labels) and of
/// the minor ones in between (0 gives plotters' `TRANSPARENT`).
pub(super) type Grid = (f64, f64);

/// The dressing of a chart's axes: descriptions, tick labels, fonts and grid lines.
#[derive(Debug, Clone, Copy)]
pub(super) struct Axes<'s> {
    /// Description below the x axis (`None`: none, e.g. on all but the lowest stacked panel).
    pub x_desc: Option<&'s str>,
    /// Description left of the y axis.
    pub y_desc: &'s str,
    /// About how many tick labels on x and on y.
    pub labels: (usize, usize),
    /// Font sizes of the x and the y tick labels.
    pub tick_font: (f64, f64),
    /// Font size of the axis descriptions.
    pub desc_font: f64,
    /// Grid lines; `None` draws none.
    pub grid: Option<Grid>,
}

impl<'s> Axes<'s> {
    /// Axes of a full-page figure: tick labels at [`TICK_SIZE`], descriptions at [`DESC_SIZE`].
    pub fn page(
        x_desc: &'s str,
        y_desc: &'s str,
        labels: (usize, usize),
        grid: Option<Grid>,
    ) -> Self {
        Axes {
            x_desc: Some(x_desc),
            y_desc,
            labels,
            tick_font: (TICK_SIZE, TICK_SIZE),
            desc_font: DESC_SIZE,
            grid,
        }
    }

    /// Draws the axes, tick labels (formatted by `fx`, `fy`), descriptions and grid of `chart`.
    pub fn draw<X, Y>(
        &self,
        chart: &mut ChartContext<'_, BitMapBackend<'_>, Cartesian2d<X, Y>>,
        fx: &dyn Fn(&f64) -> String,
        fy: &dyn Fn(&f64) -> String,
    ) -> DrawResult
    where
        X: Ranged<ValueType = f64> + ValueFormatter<f64>,
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let mut mesh = chart.configure_mesh();
        mesh.x_labels(self.labels.0)
            .y_labels(self.labels.1)
            .x_label_formatter(fx)
            .y_label_formatter(fy)
            .y_desc(self.y_desc)
            .x_label_style(font(self.tick_font.0))
            .y_label_style(font(self.tick_font.1))
            .axis_desc_style(font(self.desc_font));
        if let Some(desc) = self.x_desc {
            mesh.x_desc(desc);
        }
        match self.grid {
            Some((major, minor)) => mesh
                .bold_line_style(BLACK.mix(major))
                .light_line_style(BLACK.mix(minor)),
            None => mesh.disable_mesh(),
        };
        mesh.draw()?;
        Ok(())
    }
}

/// Renders a figure of `size` pixels with `title` on top (see [`titled`]); `draw` fills the
/// area below the title.
pub(super) fn render_titled<F>(path: &Path, size: (u32, u32), title: &str, draw: F) -> Result<()>
where
    F: FnOnce(Root<'_>) -> DrawResult,
{
    render(path, size, |root| draw(titled(root, title)?))
}

/// A standard-size page with only the title and a centred "no data".
pub(super) fn no_data_figure(path: &Path, title: &str) -> Result<()> {
    render(path, (FIG_W, FIG_H), |root| no_data_page(root, title))
}

/// Draws the figure title at the top of `root` (with some air above it) and returns the area
/// below it.
fn titled<'a>(root: &Root<'a>, title: &str) -> std::result::Result<Root<'a>, Box<dyn StdError>> {
    let root = root.margin(10, 0, 0, 0);
    let style = fitting_font(&root, title, TITLE_SIZE)?;
    Ok(root.titled(title, style)?)
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
pub(super) fn draw_no_data<C: CoordTranslate>(
    area: &DrawingArea<BitMapBackend<'_>, C>,
) -> DrawResult {
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
pub(super) fn draw_segments<X, Y>(
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
pub(super) fn thick_brush<X, Y>(
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
pub(super) fn draw_legend<'a, X, Y>(
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
