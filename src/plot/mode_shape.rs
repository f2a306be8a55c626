//! Mode shape figures: the shaft line in the x and y planes along the rotor axis (2-D), and the
//! whirl ellipses of the nodes with the shaft line at one phase (3-D, like ROSS's
//! `plot_mode_3d`).

use std::path::Path;

use plotters::prelude::*;

use super::chart::{draw_legend, draw_segments, render_titled, thick_brush, Axes, Frame};
use super::geom::{finite_range, padded};
use super::style::{font, tick_formatter, FIG_H, FIG_W, PALETTE};
use crate::error::Result;

/// A mode shape along the rotor axis, for [`mode_shape_2d`].
#[derive(Debug, Clone, Copy)]
pub struct ShapeLine<'a> {
    /// Axial positions of the samples (m).
    pub z: &'a [f64],
    /// Deflection in the x plane at each sample.
    pub x: &'a [f64],
    /// Deflection in the y plane at each sample.
    pub y: &'a [f64],
    /// Major semi-axis of the whirl ellipse at each sample (≥ 0), drawn as ± envelope.
    pub major: &'a [f64],
    /// Axial positions of the disks (m).
    pub disks: &'a [f64],
    /// Axial positions of the bearings (m).
    pub bearings: &'a [f64],
}

/// Draws a mode shape along the rotor axis: `u_x` and `u_y` at the phase given by the caller,
/// the ± major semi-axis envelope, disks (triangles) and bearings (squares) on the axis.
pub fn mode_shape_2d(path: &Path, title: &str, s: &ShapeLine<'_>, y_label: &str) -> Result<()> {
    const FRAME: Frame = Frame {
        top: 20,
        right: 36,
        bottom: 20,
        left: 20,
        x_area: 60,
        y_area: 100,
    };
    let (z0, z1) = padded(finite_range(s.z.iter().copied()), 0.03);
    let big = s.major.iter().chain(s.x).chain(s.y).fold(0.0_f64, |m, v| {
        if v.is_finite() {
            m.max(v.abs())
        } else {
            m
        }
    });
    let big = if big > 0.0 { big } else { 1.0 };
    let (y0, y1) = (-1.12 * big, 1.12 * big);
    let pts = |v: &[f64]| -> Vec<Vec<(f64, f64)>> {
        vec![s.z.iter().copied().zip(v.iter().copied()).collect()]
    };
    let neg: Vec<f64> = s.major.iter().map(|v| -v).collect();
    render_titled(path, (FIG_W, FIG_H), title, |body| {
        let mut chart = FRAME.builder(&body).build_cartesian_2d(z0..z1, y0..y1)?;
        let fx = tick_formatter(z0, z1, 12);
        let fy = tick_formatter(y0, y1, 12);
        Axes::page(
            "axial position z (m)",
            y_label,
            (12, 12),
            Some((0.12, 0.03)),
        )
        .draw(&mut chart, &fx, &fy)?;
        chart.draw_series(LineSeries::new(
            [(z0, 0.0), (z1, 0.0)],
            BLACK.mix(0.5).stroke_width(1),
        ))?;
        let brush = thick_brush(&chart);
        let grey = RGBColor(150, 150, 150);
        draw_segments(&mut chart, &pts(s.major), grey, &[(0.0, 0.0)])?;
        draw_segments(&mut chart, &pts(&neg), grey, &[(0.0, 0.0)])?;
        draw_segments(&mut chart, &pts(s.x), PALETTE[0], &brush)?;
        draw_segments(&mut chart, &pts(s.y), PALETTE[1], &brush)?;
        for (label, color) in [
            ("x plane (u_x)", PALETTE[0]),
            ("y plane (u_y)", PALETTE[1]),
            ("± major semi-axis", grey),
        ] {
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
                });
        }
        let disk = RGBColor(40, 40, 40);
        chart
            .draw_series(s.disks.iter().map(|&z| {
                EmptyElement::at((z, 0.0))
                    + Polygon::new(vec![(-9, 10), (9, 10), (0, -12)], disk.filled())
            }))?
            .label("disk")
            .legend(move |(x, y)| {
                EmptyElement::at((x + 12, y))
                    + Polygon::new(vec![(-7, 7), (7, 7), (0, -8)], disk.filled())
            });
        let bearing = PALETTE[2];
        chart
            .draw_series(s.bearings.iter().map(|&z| {
                EmptyElement::at((z, 0.0)) + Rectangle::new([(-8, -8), (8, 8)], bearing.filled())
            }))?
            .label("bearing")
            .legend(move |(x, y)| {
                EmptyElement::at((x + 12, y)) + Rectangle::new([(-6, -6), (6, 6)], bearing.filled())
            });
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        Ok(())
    })
}

/// The 3-D picture of a mode, for [`mode_shape_3d`]: points are `(z, u_x, u_y)`.
#[derive(Debug, Clone)]
pub struct Shape3d {
    /// The whirl ellipse of every node (closed polylines).
    pub ellipses: Vec<Vec<(f64, f64, f64)>>,
    /// Which ellipses belong to disk nodes (drawn darker).
    pub disk_ellipse: Vec<bool>,
    /// The shaft line at one phase.
    pub line: Vec<(f64, f64, f64)>,
    /// The nodes on that line.
    pub nodes: Vec<(f64, f64, f64)>,
    /// Axial positions of the bearings (m).
    pub bearings: Vec<f64>,
}

/// Draws the whirl ellipses of the nodes and the shaft line at one phase in 3-D (rotor axis
/// to the right, u_x towards the viewer, u_y up); `note` is written under the title.
pub fn mode_shape_3d(path: &Path, title: &str, s: &Shape3d, note: &str) -> Result<()> {
    let all = || {
        s.ellipses
            .iter()
            .flatten()
            .chain(&s.line)
            .chain(&s.nodes)
            .copied()
    };
    let (z0, z1) = padded(finite_range(all().map(|p| p.0)), 0.02);
    let big = all()
        .fold(0.0_f64, |m, p| m.max(p.1.abs()).max(p.2.abs()))
        .max(1e-300);
    let r = 1.1 * big;
    render_titled(path, (FIG_W, FIG_H), title, |body| {
        let (w, _) = body.dim_in_pixel();
        body.draw_text(
            note,
            &font(18.0).pos(plotters::style::text_anchor::Pos::new(
                plotters::style::text_anchor::HPos::Center,
                plotters::style::text_anchor::VPos::Top,
            )),
            (w as i32 / 2, 4),
        )?;
        let area = body.margin(30, 10, 10, 10);
        let mut chart =
            ChartBuilder::on(&area)
                .margin(20)
                .build_cartesian_3d(z0..z1, -r..r, -r..r)?;
        chart.with_projection(|mut p| {
            p.yaw = 0.55;
            p.pitch = 0.35;
            p.scale = 0.85;
            p.into_matrix()
        });
        let fz = tick_formatter(z0, z1, 8);
        let fr = tick_formatter(-r, r, 5);
        chart
            .configure_axes()
            .label_style(font(15.0))
            .x_labels(8)
            .y_labels(5)
            .z_labels(5)
            .x_formatter(&fz)
            .y_formatter(&fr)
            .z_formatter(&fr)
            .light_grid_style(BLACK.mix(0.06))
            .bold_grid_style(BLACK.mix(0.15))
            .draw()?;
        // Plot coordinates (x, y, z) = (axial, u_y up, u_x towards the viewer).
        let to3 = |p: &(f64, f64, f64)| (p.0, p.2, p.1);
        chart.draw_series(LineSeries::new(
            [(z0, 0.0, 0.0), (z1, 0.0, 0.0)],
            BLACK.mix(0.6).stroke_width(1),
        ))?;
        for (e, disk) in s.ellipses.iter().zip(&s.disk_ellipse) {
            let c = if *disk {
                RGBColor(40, 40, 40)
            } else {
                PALETTE[0]
            };
            chart.draw_series(LineSeries::new(e.iter().map(to3), c.stroke_width(1)))?;
        }
        chart.draw_series(LineSeries::new(
            s.line.iter().map(to3),
            PALETTE[1].stroke_width(3),
        ))?;
        chart.draw_series(
            s.nodes
                .iter()
                .map(|p| Circle::new(to3(p), 3, PALETTE[1].filled())),
        )?;
        chart.draw_series(
            s.bearings
                .iter()
                .map(|&z| Circle::new((z, 0.0, 0.0), 7, PALETTE[2].filled())),
        )?;
        Ok(())
    })
}
