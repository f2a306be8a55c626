//! Full spectra of the orbit x + iy: one run's ([`full_spectrum`]) and full-spectrum cascades
//! ([`full_cascade`]: sweeps, rows of maps, the windows of a transient), with the frequency
//! signed — positive is forward whirl (with the spin), negative backward whirl.

use std::path::Path;

use plotters::prelude::*;

use super::chart::{draw_no_data, render_titled, Axes, Frame};
use super::geom::{finite_range, padded};
use super::mesh_field::{colour_bar, viridis};
use super::style::{font, tick_formatter, FIG_H, FIG_W};
use crate::error::Result;

/// One row of a full-spectrum cascade: its lines drawn at height `y`, the ±1× guides at
/// `±speed` there.
#[derive(Debug, Clone, PartialEq)]
pub struct WhirlRow {
    /// Where the row is drawn (the speed ω/ωn, or the parameter of a map's row).
    pub y: f64,
    /// The rotor speed of the row, in the unit of the frequencies (f/ωn: ω/ωn).
    pub speed: f64,
    /// `(signed frequency, amplitude)` of its lines.
    pub lines: Vec<(f64, f64)>,
}

const FRAME: Frame = Frame {
    top: 20,
    right: 24,
    bottom: 12,
    left: 12,
    x_area: 60,
    y_area: 80,
};

const FORWARD: RGBColor = RGBColor(214, 39, 40);
const BACKWARD: RGBColor = RGBColor(31, 119, 180);

/// One run's full spectrum: amplitude against signed frequency `f/ωn` (`points`, ascending),
/// drawn as stems, with the ±1× lines at `±speed` (dashed; forward red, backward blue) and the
/// two half-planes labelled.
pub fn full_spectrum(
    path: &Path,
    title: &str,
    points: &[(f64, f64)],
    speed: f64,
    amp_label: &str,
) -> Result<()> {
    let pts: Vec<(f64, f64)> = points
        .iter()
        .copied()
        .filter(|(f, a)| f.is_finite() && a.is_finite())
        .collect();
    let fm = pts
        .iter()
        .map(|p| p.0.abs())
        .fold(speed.abs() * 1.2, f64::max)
        .max(1e-9);
    let amax = pts.iter().map(|p| p.1).fold(0.0, f64::max);
    let ytop = if amax > 0.0 { amax * 1.1 } else { 1.0 };
    let fx = tick_formatter(-fm, fm, 12);
    let fy = tick_formatter(0.0, ytop, 8);
    render_titled(path, (FIG_W, FIG_H), title, |body| {
        let mut chart = FRAME
            .builder(&body)
            .build_cartesian_2d(-fm..fm, 0.0..ytop)?;
        Axes::page(
            "f / ωn   (< 0: backward whirl, > 0: forward whirl)",
            amp_label,
            (12, 8),
            Some((0.10, 0.0)),
        )
        .draw(&mut chart, &fx, &fy)?;
        if pts.is_empty() {
            draw_no_data(chart.plotting_area())?;
            return Ok(());
        }
        for (s, c, label) in [
            (speed, FORWARD, "+1× forward"),
            (-speed, BACKWARD, "−1× backward"),
        ] {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(s, 0.0), (s, ytop)],
                    10,
                    6,
                    c.stroke_width(2),
                ))?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(3))
                });
        }
        chart.draw_series(pts.iter().filter(|p| p.1 > 0.0).map(|&(f, a)| {
            let c = if f < 0.0 { BACKWARD } else { BLACK };
            PathElement::new(vec![(f, 0.0), (f, a)], c.stroke_width(2))
        }))?;
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .margin(12)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK.mix(0.5))
            .label_font(font(17.0))
            .draw()?;
        Ok(())
    })
}

/// A full-spectrum cascade: every row's lines as dots at (signed frequency, `row.y`), coloured
/// by amplitude on the viridis scale (colour bar `amp_label`) and sized with it, the weak
/// drawn first; the ±1× guides through `(±row.speed, row.y)` (forward red, backward blue) and
/// f = 0. Frequencies shown within `±freq_max` (by default, when not finite and positive,
/// the largest in the data).
pub fn full_cascade(
    path: &Path,
    title: &str,
    rows: &[WhirlRow],
    y_desc: &str,
    freq_max: f64,
    amp_label: &str,
) -> Result<()> {
    let fm = if freq_max.is_finite() && freq_max > 0.0 {
        freq_max
    } else {
        finite_range(rows.iter().flat_map(|r| r.lines.iter().map(|l| l.0.abs())))
            .map_or(1.0, |(_, hi)| hi.max(1e-9))
    };
    let mut dots: Vec<(f64, f64, f64)> = rows
        .iter()
        .flat_map(|r| r.lines.iter().map(move |&(f, a)| (f, r.y, a)))
        .filter(|(f, y, a)| f.is_finite() && y.is_finite() && a.is_finite() && f.abs() <= fm)
        .collect();
    dots.sort_by(|p, q| p.2.total_cmp(&q.2));
    let amax = dots.iter().map(|d| d.2).fold(0.0, f64::max);
    let a1 = if amax > 0.0 { amax } else { 1.0 };
    let (ylo, yhi) = padded(finite_range(rows.iter().map(|r| r.y)), 0.04);
    let fx = tick_formatter(-fm, fm, 12);
    let fy = tick_formatter(ylo, yhi, 10);
    let fa = tick_formatter(0.0, a1, 6);
    let mut guides: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.y.is_finite() && r.speed.is_finite())
        .map(|r| (r.speed, r.y))
        .collect();
    guides.sort_by(|p, q| p.1.total_cmp(&q.1));
    render_titled(path, (FIG_W, FIG_H), title, |body| {
        let (w, _) = body.dim_in_pixel();
        let (plot, bar) = body.split_horizontally(w.saturating_sub(170));
        let mut chart = FRAME.builder(&plot).build_cartesian_2d(-fm..fm, ylo..yhi)?;
        Axes::page(
            "f / ωn   (< 0: backward whirl, > 0: forward whirl)",
            y_desc,
            (12, 10),
            Some((0.10, 0.0)),
        )
        .draw(&mut chart, &fx, &fy)?;
        if dots.is_empty() {
            draw_no_data(chart.plotting_area())?;
            return Ok(());
        }
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(0.0, ylo), (0.0, yhi)],
            BLACK.mix(0.4).stroke_width(1),
        )))?;
        for (sign, c, label) in [
            (1.0, FORWARD, "+1× forward"),
            (-1.0, BACKWARD, "−1× backward"),
        ] {
            let pts: Vec<(f64, f64)> = guides
                .iter()
                .map(|&(s, y)| (sign * s, y))
                .filter(|(f, _)| f.abs() <= fm)
                .collect();
            chart
                .draw_series(DashedLineSeries::new(
                    pts,
                    10,
                    6,
                    c.mix(0.8).stroke_width(2),
                ))?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(3))
                });
        }
        chart.draw_series(dots.iter().map(|&(f, y, a)| {
            let r = 2 + (5.0 * (a / a1).clamp(0.0, 1.0)).round() as i32;
            Circle::new((f, y), r, viridis(a, 0.0, a1).filled())
        }))?;
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::LowerRight)
            .margin(12)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK.mix(0.5))
            .label_font(font(17.0))
            .draw()?;
        colour_bar(&bar, amp_label, (0.0, a1), &fa, |v| viridis(v, 0.0, a1))
    })
}
