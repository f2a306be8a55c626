//! Spectrum cascades (waterfalls, like Fig. 12 of the paper): one spectrum per rotor speed,
//! drawn at its speed with hidden-line fill, plus the 1×, 1/2× and 1/3× guide lines.

use std::path::Path;

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::chart::{draw_no_data, render_titled, Axes, Frame, LinChart};
use super::geom::finite_range;
use super::style::{fmt_sig, font, tick_formatter, DrawResult, Root, FIG_H, FIG_W};
use crate::error::Result;

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

/// Frame of the cascade chart.
const FRAME: Frame = Frame {
    top: 24,
    right: 24,
    bottom: 12,
    left: 12,
    x_area: 60,
    y_area: 80,
};

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
    let lines: Vec<&CascadeLine> = lines.iter().filter(|l| l.speed.is_finite()).collect();
    let amax = lines
        .iter()
        .flat_map(|l| l.freq.iter().zip(&l.amp))
        .filter(|(f, a)| visible(**f, **a, fmax))
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

    render_titled(path, (FIG_W, FIG_H), title, |body| {
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
        draw_note(&body, &note)?;
        let mut chart = FRAME
            .builder(&body)
            .build_cartesian_2d(0.0..fmax, ylo..yhi)?;
        let fx = tick_formatter(0.0, fmax, 12);
        let fy = tick_formatter(ylo, yhi, 12);
        Axes::page("f/ωn", "ω/ωn", (12, 12), Some((0.10, 0.0))).draw(&mut chart, &fx, &fy)?;

        if lines.is_empty() {
            draw_no_data(chart.plotting_area())?;
            return Ok(());
        }
        draw_spectra(&mut chart, &lines, fmax, scale)?;
        draw_guides(&mut chart, (ylo, yhi), fmax)
    })
}

/// True when the sample (`f`, `a`) is finite and `f` lies in the visible range 0..`fmax`.
fn visible(f: f64, a: f64, fmax: f64) -> bool {
    f.is_finite() && a.is_finite() && (0.0..=fmax).contains(&f)
}

/// Writes `note` (grey, right-aligned) at the top right of `body`.
fn draw_note(body: &Root<'_>, note: &str) -> DrawResult {
    let (bw, _) = body.dim_in_pixel();
    body.draw_text(
        note,
        &font(16.0)
            .color(&RGBColor(90, 90, 90))
            .pos(Pos::new(HPos::Right, VPos::Top)),
        (bw as i32 - 24, 0),
    )?;
    Ok(())
}

/// Draws the spectra back to front (highest speed first, so lower-speed spectra occlude those
/// behind), each at its speed with amplitudes times `scale` and a white fill below the line.
fn draw_spectra(
    chart: &mut LinChart<'_, '_>,
    lines: &[&CascadeLine],
    fmax: f64,
    scale: f64,
) -> DrawResult {
    let mut order: Vec<&CascadeLine> = lines.to_vec();
    order.sort_by(|a, b| b.speed.total_cmp(&a.speed));
    let line_color = RGBColor(20, 40, 110);
    for l in order {
        let n = l.freq.len().min(l.amp.len());
        let mut segments: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
        for i in 0..n {
            let (f, a) = (l.freq[i], l.amp[i]);
            if visible(f, a, fmax) {
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
                chart.draw_series(std::iter::once(Circle::new(seg[0], 2, line_color.filled())))?;
                continue;
            }
            let mut poly = seg.clone();
            poly.push((seg[seg.len() - 1].0, l.speed));
            poly.push((seg[0].0, l.speed));
            chart.draw_series(std::iter::once(Polygon::new(poly, WHITE.filled())))?;
            chart.draw_series(LineSeries::new(seg.iter().copied(), line_color))?;
        }
    }
    Ok(())
}

/// Draws the guide lines f = k·speed (k = 1, 1/2, 1/3) over the speed range `(ylo, yhi)` and
/// their legend.
fn draw_guides<'a>(chart: &mut LinChart<'a, 'a>, (ylo, yhi): (f64, f64), fmax: f64) -> DrawResult {
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
}
