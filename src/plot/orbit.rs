//! Orbit grids (like Figs. 5–8 of the paper): one equal-aspect panel per orbit, with the stator
//! side of its boundary shaded, the orbit as a line and the Poincaré points as dots.

use std::path::Path;

use plotters::prelude::*;

use super::chart::{draw_no_data, draw_segments, no_data_figure, render_titled, thick_brush};
use super::chart::{Axes, Frame, LinChart};
use super::geom::{clip_half_plane, clip_segment, equal_aspect_ranges, finite_segments};
use super::style::{fitting_font, tick_formatter, DrawResult, Root, PALETTE};
use crate::error::Result;

/// What to draw as the stator boundary in an orbit panel (non-dimensional units, same as the
/// orbit).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
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
        return no_data_figure(path, title);
    }
    let cols = cols.clamp(1, panels.len());
    let rows = panels.len().div_ceil(cols);
    let width = (cols as u32 * PANEL).max(640);
    let height = rows as u32 * PANEL + TITLE_BAND;
    render_titled(path, (width, height), title, |body| {
        let cells = body.split_evenly((rows, cols));
        for (cell, panel) in cells.iter().zip(panels) {
            draw_orbit_panel(cell, panel)?;
        }
        Ok(())
    })
}

/// Frame of an orbit panel's chart inside the panel (below its title).
const PANEL_FRAME: Frame = Frame {
    top: 6,
    right: 22,
    bottom: 8,
    left: 8,
    x_area: 46,
    y_area: 62,
};

/// Axes of an orbit panel.
const PANEL_AXES: Axes<'static> = Axes {
    x_desc: Some("x/|Z0|"),
    y_desc: "y/|Z0|",
    labels: (6, 6),
    tick_font: (15.0, 15.0),
    desc_font: 17.0,
    grid: Some((0.12, 0.0)),
};

/// Light grey used for the stator region of orbit panels.
const STATOR_FILL: RGBColor = RGBColor(225, 225, 225);

/// Draws one orbit panel into `cell`.
fn draw_orbit_panel(cell: &Root<'_>, panel: &OrbitPanel) -> DrawResult {
    let f = PANEL_FRAME;
    let inner = cell.titled(&panel.title, fitting_font(cell, &panel.title, 20.0)?)?;
    let (w, h) = inner.dim_in_pixel();
    let pw = f64::from((w as i32 - f.left - f.right - f.y_area).max(20));
    let ph = f64::from((h as i32 - f.top - f.bottom - f.x_area).max(20));

    let segs = finite_segments(&panel.x, &panel.y);
    let poincare: Vec<(f64, f64)> = panel
        .poincare
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    let stator = Stator::of(&panel.boundary);

    // Data extent: orbit, Poincaré points, and the boundary (foot of the line, whole circle).
    let mut extent_pts: Vec<(f64, f64)> = segs.iter().flatten().copied().collect();
    extent_pts.extend(&poincare);
    stator.extend_extent(&mut extent_pts);
    let (xr, yr) = equal_aspect_ranges(&extent_pts, pw, ph);

    let mut chart = f
        .builder(&inner)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
    // Stator region (grey) below the mesh, its boundary on top of it.
    stator.fill(&mut chart, xr, yr)?;
    let fx = tick_formatter(xr.0, xr.1, 6);
    let fy = tick_formatter(yr.0, yr.1, 6);
    PANEL_AXES.draw(&mut chart, &fx, &fy)?;
    stator.draw_edge(&mut chart, xr, yr)?;

    let orbit = PALETTE[0];
    draw_segments(&mut chart, &segs, orbit, &[(0.0, 0.0)])?;
    let red = RGBColor(214, 39, 40).filled();
    chart.draw_series(poincare.iter().map(|&p| Circle::new(p, 3, red)))?;

    if segs.is_empty() && poincare.is_empty() {
        draw_no_data(chart.plotting_area())?;
    }
    Ok(())
}

/// The stator boundary of a panel in drawable form; a part that is not well defined (non-finite
/// line, non-positive radius) is absent.
struct Stator {
    /// Straight line: unit normal (from the origin towards the line) and distance.
    line: Option<((f64, f64), f64)>,
    /// Circle: radius and the closed polyline of its 361 points.
    circle: Option<(f64, Vec<(f64, f64)>)>,
}

impl Stator {
    /// The drawable form of `boundary`.
    fn of(boundary: &Boundary) -> Self {
        let line = match *boundary {
            Boundary::Line {
                angle_deg,
                distance,
            } if angle_deg.is_finite() && distance.is_finite() => {
                let a = angle_deg.to_radians();
                Some(((a.cos(), a.sin()), distance))
            }
            _ => None,
        };
        let circle = match *boundary {
            Boundary::Circle { radius } if radius.is_finite() && radius > 0.0 => Some(radius),
            _ => None,
        };
        let circle = circle.map(|r| {
            let pts = (0..=360)
                .map(|k| {
                    let a = f64::from(k).to_radians();
                    (r * a.cos(), r * a.sin())
                })
                .collect::<Vec<_>>();
            (r, pts)
        });
        Stator { line, circle }
    }

    /// Adds the points the panel must show: the foot of the line, the circle's bounding box.
    fn extend_extent(&self, pts: &mut Vec<(f64, f64)>) {
        if let Some(((nx, ny), d)) = self.line {
            pts.push((nx * d, ny * d));
        }
        if let Some((r, _)) = self.circle {
            pts.extend([(-r, -r), (r, r)]);
        }
    }

    /// Shades the stator side of the boundary within the ranges `xr` × `yr`.
    fn fill(&self, chart: &mut LinChart<'_, '_>, xr: (f64, f64), yr: (f64, f64)) -> DrawResult {
        if let Some(((nx, ny), d)) = self.line {
            let rect = [(xr.0, yr.0), (xr.1, yr.0), (xr.1, yr.1), (xr.0, yr.1)];
            let region = clip_half_plane(&rect, (nx, ny), d);
            if region.len() >= 3 {
                chart.draw_series(std::iter::once(Polygon::new(region, STATOR_FILL.filled())))?;
            }
        }
        if let Some((_, cp)) = &self.circle {
            chart.draw_series(std::iter::once(Rectangle::new(
                [(xr.0, yr.0), (xr.1, yr.1)],
                STATOR_FILL.filled(),
            )))?;
            chart.draw_series(std::iter::once(Polygon::new(cp.clone(), WHITE.filled())))?;
        }
        Ok(())
    }

    /// Draws the boundary line (clipped to `xr` × `yr`) or circle, two pixels wide.
    fn draw_edge(
        &self,
        chart: &mut LinChart<'_, '_>,
        xr: (f64, f64),
        yr: (f64, f64),
    ) -> DrawResult {
        let edge = RGBColor(30, 30, 30);
        let brush = thick_brush(chart);
        if let Some(((nx, ny), d)) = self.line {
            let big = 4.0 * (xr.1 - xr.0 + yr.1 - yr.0 + d.abs());
            let p0 = (nx * d - ny * big, ny * d + nx * big);
            let p1 = (nx * d + ny * big, ny * d - nx * big);
            if let Some((a, b)) = clip_segment(p0, p1, xr, yr) {
                draw_segments(chart, &[vec![a, b]], edge, &brush)?;
            }
        }
        if let Some((_, cp)) = &self.circle {
            draw_segments(chart, std::slice::from_ref(cp), edge, &brush)?;
        }
        Ok(())
    }
}
