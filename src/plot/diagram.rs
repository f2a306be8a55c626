//! The bifurcation diagram of continued branches (`rubsim continue`): each branch's stable
//! stretches solid and its unstable ones dashed, in the branch's colour, over an optional cloud
//! of Poincaré points drawn as small grey dots (a sweep's, for comparison).

use std::path::Path;

use plotters::prelude::*;

use super::chart::{draw_legend, draw_no_data, render_titled, Axes};
use super::geom::{finite_range, padded, point_segments};
use super::style::{tick_formatter, FIG_H, FIG_W, PALETTE};
use super::xy::CURVES_FRAME;
use crate::error::Result;

/// One stretch style of a branch: its points (a non-finite value breaks the line), solid or
/// dashed, and its colour's index in the palette.
#[derive(Debug, Clone)]
pub struct BranchLine {
    /// Legend entry (empty: none).
    pub label: String,
    /// (parameter, value) points in the branch's order (ν, or a scene key's value).
    pub points: Vec<(f64, f64)>,
    /// Dashed (an unstable stretch) or solid.
    pub dashed: bool,
    /// Palette index of its colour.
    pub colour: usize,
}

/// Draws `lines` (solid or dashed) over the grey `dots` into `path`, its axes labelled
/// `(x_label, y_label)` (x: ω/ωn, or the scene key a branch is continued in).
///
/// # Errors
/// Drawing and I/O errors, naming the file.
pub fn branch_diagram(
    path: &Path,
    title: &str,
    lines: &[BranchLine],
    dots: &[(f64, f64)],
    (x_label, y_label): (&str, &str),
) -> Result<()> {
    let segs: Vec<Vec<Vec<(f64, f64)>>> = lines.iter().map(|c| point_segments(&c.points)).collect();
    let finite = |p: &&(f64, f64)| p.0.is_finite() && p.1.is_finite();
    let all: Vec<(f64, f64)> = segs
        .iter()
        .flatten()
        .flatten()
        .chain(dots.iter().filter(finite))
        .copied()
        .collect();
    render_titled(path, (FIG_W, FIG_H), title, |body| {
        let (x0, x1) = padded(finite_range(all.iter().map(|p| p.0)), 0.02);
        let (y0, y1) = padded(finite_range(all.iter().map(|p| p.1)), 0.05);
        let mut chart = CURVES_FRAME
            .builder(&body)
            .build_cartesian_2d(x0..x1, y0..y1)?;
        let (fx, fy) = (tick_formatter(x0, x1, 12), tick_formatter(y0, y1, 12));
        Axes::page(x_label, y_label, (12, 12), Some((0.12, 0.03))).draw(&mut chart, &fx, &fy)?;
        if all.is_empty() {
            draw_no_data(chart.plotting_area())?;
            return Ok(());
        }
        let grey = RGBColor(110, 110, 110);
        chart.draw_series(
            dots.iter()
                .filter(finite)
                .map(|p| Circle::new(*p, 2, grey.filled())),
        )?;
        let mut labelled = false;
        for (line, cs) in lines.iter().zip(&segs) {
            let color = PALETTE[line.colour % PALETTE.len()];
            let style = color.stroke_width(3);
            for seg in cs {
                let pts = seg.iter().copied();
                if seg.len() == 1 {
                    chart.draw_series(std::iter::once(Circle::new(seg[0], 3, color.filled())))?;
                } else if line.dashed {
                    chart.draw_series(DashedLineSeries::new(pts, 10, 7, style))?;
                } else {
                    chart.draw_series(LineSeries::new(pts, style))?;
                }
            }
            if !line.label.is_empty() {
                labelled = true;
                let dashed = line.dashed;
                chart
                    .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
                    .label(line.label.as_str())
                    .legend(move |(x, y)| {
                        let w = if dashed { 9 } else { 24 };
                        PathElement::new(vec![(x, y), (x + w, y)], color.stroke_width(3))
                    });
            }
        }
        if labelled {
            draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        }
        Ok(())
    })
}
