//! A 2-D mesh coloured by a value per cell (e.g. the von Mises stress of a meshed stator), with
//! a colour bar.

use std::path::Path;

use plotters::prelude::*;

use super::chart::{no_data_figure, render_titled, Axes, Frame};
use super::geom::{finite_range, padded};
use super::style::{fitting_font, font, tick_formatter, DrawResult, Root, FIG_H, FIG_W, TICK_SIZE};
use crate::error::Result;

/// Frame of the mesh chart (left of the colour bar).
const MESH_FRAME: Frame = Frame {
    top: 20,
    right: 20,
    bottom: 20,
    left: 20,
    x_area: 60,
    y_area: 80,
};

/// Frame of the colour bar (its labels on the left, no x axis).
pub(super) const BAR_FRAME: Frame = Frame {
    top: 40,
    right: 20,
    bottom: 80,
    left: 0,
    x_area: 0,
    y_area: 110,
};

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
        return no_data_figure(path, title);
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
    let colour = |v: f64| viridis(v, v0, v1);
    let fx = tick_formatter(x0, x1, 8);
    let fy = tick_formatter(y0, y1, 8);
    let fv = tick_formatter(v0, v1, 6);
    render_titled(path, (FIG_W, FIG_H), title, |body| {
        let (w, _) = body.dim_in_pixel();
        let (plot, bar) = body.split_horizontally(w.saturating_sub(190));
        let mut chart = MESH_FRAME
            .builder(&plot)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        // Tick counts: plotters' default (11); the formatters assume about 8.
        Axes::page("x (mm)", "y (mm)", (11, 11), None).draw(&mut chart, &fx, &fy)?;
        chart.draw_series(cells.iter().map(|(poly, v)| {
            let p: Vec<(f64, f64)> = poly.iter().map(|q| (1e3 * q.0, 1e3 * q.1)).collect();
            Polygon::new(p, colour(*v).filled())
        }))?;
        chart.draw_series(
            marks
                .iter()
                .map(|m| Cross::new((1e3 * m.0, 1e3 * m.1), 5, BLACK.stroke_width(2))),
        )?;
        colour_bar(&bar, value_label, (v0, v1), &fv, colour)?;
        Ok(())
    })
}

/// Draws a vertical colour bar filling `bar` ([`BAR_FRAME`]): `value_label` as its caption, the
/// values `v0 … v1` on its axis (labelled by `fv`), 200 bands coloured by `colour(v)`.
pub(super) fn colour_bar(
    bar: &Root<'_>,
    value_label: &str,
    (v0, v1): (f64, f64),
    fv: &dyn Fn(&f64) -> String,
    colour: impl Fn(f64) -> RGBColor,
) -> DrawResult {
    let mut cb = BAR_FRAME
        .builder(bar)
        .caption(value_label, fitting_font(bar, value_label, 18.0)?)
        .build_cartesian_2d(0.0..1.0, v0..v1)?;
    cb.configure_mesh()
        .disable_x_axis()
        .disable_mesh()
        .y_labels(6)
        .y_label_formatter(fv)
        .label_style(font(TICK_SIZE))
        .draw()?;
    let n = 200;
    cb.draw_series((0..n).map(|i| {
        let a = v0 + (v1 - v0) * i as f64 / n as f64;
        let b = v0 + (v1 - v0) * (i + 1) as f64 / n as f64;
        Rectangle::new([(0.0, a), (1.0, b)], colour(0.5 * (a + b)).filled())
    }))?;
    Ok(())
}

/// Colour of value `v` on the viridis scale over `v0..v1` (five stops, linear in between;
/// values outside are clamped); grey for a non-finite value.
pub(super) fn viridis(v: f64, v0: f64, v1: f64) -> RGBColor {
    if !v.is_finite() {
        return RGBColor(170, 170, 170);
    }
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
}
