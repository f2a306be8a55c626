//! 2-D maps over two parameters: a grid of cells coloured by a category (the regime map) or
//! by a value with a colour bar and contour lines (orbit size, peak contact force).
//!
//! The grid is given by its axis values `xs`, `ys` (increasing or not, not necessarily
//! uniform); each value is the centre of a cell whose edges lie half-way to its neighbours.

use std::path::Path;

use plotters::prelude::*;

use super::chart::{no_data_figure, render_titled, Axes, Frame};
use super::geom::finite_range;
use super::mesh_field::{colour_bar, viridis};
use super::style::{category_colour, font, tick_formatter, FIG_H, FIG_W};
use crate::error::Result;

/// Frame of the map chart.
const MAP_FRAME: Frame = Frame {
    top: 20,
    right: 20,
    bottom: 20,
    left: 20,
    x_area: 60,
    y_area: 90,
};

/// The axes of a map: values and descriptions.
#[derive(Debug, Clone, Copy)]
pub struct MapGrid<'a> {
    /// Horizontal axis values (cell centres).
    pub xs: &'a [f64],
    /// Vertical axis values (cell centres).
    pub ys: &'a [f64],
    /// Horizontal axis description.
    pub x_desc: &'a str,
    /// Vertical axis description.
    pub y_desc: &'a str,
}

/// Cell edges of centres `c`: half-way between neighbours, the ends mirrored (a single value
/// gets a cell of width 1, or 10 % of its magnitude).
fn edges(c: &[f64]) -> Vec<f64> {
    let mut s: Vec<f64> = c.to_vec();
    s.sort_by(f64::total_cmp);
    let n = s.len();
    if n == 1 {
        let h = if s[0] == 0.0 { 0.5 } else { 0.05 * s[0].abs() };
        return vec![s[0] - h, s[0] + h];
    }
    let mut e = Vec::with_capacity(n + 1);
    e.push(s[0] - 0.5 * (s[1] - s[0]));
    for i in 0..n - 1 {
        e.push(0.5 * (s[i] + s[i + 1]));
    }
    e.push(s[n - 1] + 0.5 * (s[n - 1] - s[n - 2]));
    e
}

/// The cell rectangle of value index `i` on an axis of centres `c` with `edges` `e`.
fn span(c: &[f64], e: &[f64], i: usize) -> (f64, f64) {
    let rank = c.iter().filter(|v| **v < c[i]).count();
    (e[rank], e[rank + 1])
}

/// A regime map: cell `(ix, iy)` coloured by category `cells[iy][ix]` (an index into
/// `labels`, drawn with the palette in that order), with a legend of the categories present.
pub fn category_map(
    path: &Path,
    title: &str,
    grid: MapGrid<'_>,
    cells: &[Vec<usize>],
    labels: &[&str],
) -> Result<()> {
    if grid.xs.is_empty() || grid.ys.is_empty() {
        return no_data_figure(path, title);
    }
    let (ex, ey) = (edges(grid.xs), edges(grid.ys));
    let colour = category_colour;
    let fx = tick_formatter(ex[0], ex[ex.len() - 1], 8);
    let fy = tick_formatter(ey[0], ey[ey.len() - 1], 8);
    render_titled(path, (FIG_W, FIG_H), title, |body| {
        let (w, _) = body.dim_in_pixel();
        let (plot, legend) = body.split_horizontally(w.saturating_sub(320));
        let mut chart = MAP_FRAME
            .builder(&plot)
            .build_cartesian_2d(ex[0]..ex[ex.len() - 1], ey[0]..ey[ey.len() - 1])?;
        Axes::page(grid.x_desc, grid.y_desc, (10, 10), None).draw(&mut chart, &fx, &fy)?;
        for (iy, row) in cells.iter().enumerate().take(grid.ys.len()) {
            let (y0, y1) = span(grid.ys, &ey, iy);
            chart.draw_series(row.iter().enumerate().take(grid.xs.len()).map(|(ix, k)| {
                let (x0, x1) = span(grid.xs, &ex, ix);
                Rectangle::new([(x0, y0), (x1, y1)], colour(*k).filled())
            }))?;
        }
        let mut y = 60;
        for (k, label) in labels.iter().enumerate() {
            if !cells.iter().flatten().any(|c| *c == k) {
                continue;
            }
            legend.draw(&Rectangle::new([(20, y), (44, y + 24)], colour(k).filled()))?;
            legend.draw_text(label, &font(18.0), (54, y + 3))?;
            y += 36;
        }
        Ok(())
    })
}

/// A value map: cell `(ix, iy)` coloured by `values[iy][ix]` on the viridis scale with a
/// colour bar labelled `value_label`, and black contour lines at `levels` evenly spaced values
/// (linear interpolation between cell centres, marching squares). Non-finite values are grey
/// and break the contours.
pub fn field_map(
    path: &Path,
    title: &str,
    grid: MapGrid<'_>,
    values: &[Vec<f64>],
    value_label: &str,
    levels: usize,
) -> Result<()> {
    if grid.xs.is_empty() || grid.ys.is_empty() {
        return no_data_figure(path, title);
    }
    let (ex, ey) = (edges(grid.xs), edges(grid.ys));
    let (v0, mut v1) = finite_range(values.iter().flatten().copied()).unwrap_or((0.0, 1.0));
    if v1 <= v0 {
        v1 = v0 + 1.0;
    }
    let fx = tick_formatter(ex[0], ex[ex.len() - 1], 8);
    let fy = tick_formatter(ey[0], ey[ey.len() - 1], 8);
    let fv = tick_formatter(v0, v1, 6);
    let lines = contours(grid.xs, grid.ys, values, v0, v1, levels);
    render_titled(path, (FIG_W, FIG_H), title, |body| {
        let (w, _) = body.dim_in_pixel();
        let (plot, bar) = body.split_horizontally(w.saturating_sub(190));
        let mut chart = MAP_FRAME
            .builder(&plot)
            .build_cartesian_2d(ex[0]..ex[ex.len() - 1], ey[0]..ey[ey.len() - 1])?;
        Axes::page(grid.x_desc, grid.y_desc, (10, 10), None).draw(&mut chart, &fx, &fy)?;
        for (iy, row) in values.iter().enumerate().take(grid.ys.len()) {
            let (y0, y1) = span(grid.ys, &ey, iy);
            chart.draw_series(row.iter().enumerate().take(grid.xs.len()).map(|(ix, v)| {
                let (x0, x1) = span(grid.xs, &ex, ix);
                Rectangle::new([(x0, y0), (x1, y1)], viridis(*v, v0, v1).filled())
            }))?;
        }
        chart.draw_series(
            lines
                .iter()
                .map(|s| PathElement::new(vec![s.0, s.1], BLACK.stroke_width(2))),
        )?;
        colour_bar(&bar, value_label, (v0, v1), &fv, |v| viridis(v, v0, v1))?;
        Ok(())
    })
}

/// A contour segment between two points (axis units).
type Segment = ((f64, f64), (f64, f64));

/// Contour segments of `values[iy][ix]` (at the points `(xs[ix], ys[iy])`) at `levels` values
/// evenly inside `(v0, v1)`, by marching squares; squares with a non-finite corner are skipped.
fn contours(
    xs: &[f64],
    ys: &[f64],
    values: &[Vec<f64>],
    v0: f64,
    v1: f64,
    levels: usize,
) -> Vec<Segment> {
    let mut out = Vec::new();
    let at = |ix: usize, iy: usize| values.get(iy).and_then(|r| r.get(ix)).copied();
    for l in 1..=levels {
        let c = v0 + (v1 - v0) * l as f64 / (levels + 1) as f64;
        for iy in 0..ys.len().saturating_sub(1) {
            for ix in 0..xs.len().saturating_sub(1) {
                // Corners counter-clockwise from (ix, iy).
                let idx = [(ix, iy), (ix + 1, iy), (ix + 1, iy + 1), (ix, iy + 1)];
                let vals: Vec<f64> = idx.iter().filter_map(|&(i, j)| at(i, j)).collect();
                if vals.len() < 4 || vals.iter().any(|v| !v.is_finite()) {
                    continue;
                }
                let pt = |k: usize| (xs[idx[k].0], ys[idx[k].1]);
                // The crossings on the four edges, in edge order.
                let cross: Vec<(f64, f64)> = (0..4)
                    .filter_map(|k| {
                        let (a, b) = (vals[k], vals[(k + 1) % 4]);
                        ((a < c) != (b < c)).then(|| {
                            let t = (c - a) / (b - a);
                            let (p, q) = (pt(k), pt((k + 1) % 4));
                            (p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1))
                        })
                    })
                    .collect();
                for pair in cross.chunks_exact(2) {
                    out.push((pair[0], pair[1]));
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contours_of_a_plane_are_straight_lines_at_the_level() {
        // v = x on a 3 × 3 grid: the level 1.5 crosses every square row at x = 1.5.
        let xs = [0.0, 1.0, 2.0, 3.0];
        let ys = [0.0, 1.0, 2.0];
        let values: Vec<Vec<f64>> = ys.iter().map(|_| xs.to_vec()).collect();
        let segs = contours(&xs, &ys, &values, 0.0, 3.0, 1);
        assert_eq!(segs.len(), 2);
        for (a, b) in segs {
            assert!((a.0 - 1.5).abs() < 1e-12 && (b.0 - 1.5).abs() < 1e-12);
            assert!((a.1 - b.1).abs() == 1.0);
        }
    }

    #[test]
    fn cell_edges_lie_half_way_and_mirror_at_the_ends() {
        assert_eq!(edges(&[1.0, 2.0, 4.0]), vec![0.5, 1.5, 3.0, 5.0]);
        assert_eq!(edges(&[2.0]), vec![1.9, 2.1]);
    }
}
