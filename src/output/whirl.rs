//! The full spectra of x + iy (forward whirl at positive, backward whirl at negative
//! frequencies; [`crate::analysis::whirl`]) as tables and pictures:
//!
//! * a run: `full_spectrum.csv` (`order, freq_nd, amp_nd`: signed f/Ω, signed f/ω_n, amplitude
//!   / |Z0| per bin, ascending) and `full_spectrum.png`;
//! * a sweep (per variant) and a map: `full_cascade.csv` (per case its strongest lines:
//!   the case's parameters, then `rank, order, freq_nd, amp_nd`) and the cascade
//!   `full_cascade.png` — a map draws one per row of its vertical axis,
//!   `full_cascade/<key>_<value>.png`;
//! * a speed transient: `full_waterfall.csv` (per window of whole revolutions `t_s,
//!   omega_rad_s, speed_ratio, fwd_1x_m, bwd_1x_m`, then per line `rank, order, freq_nd,
//!   amp_m`, then the window's `contact_fraction, stick_fraction, dry_rub`) and
//!   `full_waterfall.png`; with stick, `dry_whirl.png` (the windows' speed, dominant whirl
//!   frequency, stick and contact fractions against time).
//!
//! The cascades are drawn from the lines each case keeps in its results
//! ([`crate::analysis::whirl::WhirlLines::lines`]), so they are assembled from the case files
//! alone.

use super::{Drawings, OutDir};
use crate::analysis::waterfall::WaterfallWindow;
use crate::analysis::SpeedResults;
use crate::error::Result;
use crate::plot::{self, WhirlRow};

/// Writes a run's `full_spectrum.csv` and, with `png`, `full_spectrum.png`.
pub fn write_run(out: &mut OutDir, title: &str, r: &SpeedResults, png: bool) -> Result<()> {
    let nu = r.speed_ratio;
    let mut s = String::from("order,freq_nd,amp_nd\n");
    for (f, a) in &r.full_spectrum {
        s.push_str(&format!("{:.6},{:.6},{:.6e}\n", f / nu, f, a));
    }
    out.write("full_spectrum.csv", s.as_bytes())?;
    if png {
        let w = &r.whirl;
        let p = out.stage("full_spectrum.png")?;
        plot::full_spectrum(
            &p,
            &format!(
                "{title} — full spectrum of (x + iy)/|Z0| at ω/ωn = {:.3}: 1× forward {:.3}, \
                 backward {:.3}; dominant {:+.3}× ({})",
                nu,
                w.forward_1x_nd,
                w.backward_1x_nd,
                w.dominant_order,
                w.direction.name()
            ),
            &r.full_spectrum,
            nu,
            "amplitude / |Z0|",
        )?;
    }
    Ok(())
}

/// One case of a full-spectrum cascade: its leading CSV columns (already formatted, without
/// a trailing comma), the height its row is drawn at and its results.
pub struct CascadeCase<'a> {
    /// The leading columns of its rows in `full_cascade.csv`.
    pub columns: String,
    /// Where its row is drawn (the speed, or the parameter of a map's row).
    pub y: f64,
    /// Its results.
    pub run: &'a SpeedResults,
}

/// Writes `<prefix>full_cascade.csv` (header `<lead_header>,rank,order,freq_nd,amp_nd`, one
/// row per kept line of each case, strongest first).
pub fn write_cascade_csv(
    out: &mut OutDir,
    prefix: &str,
    lead_header: &str,
    cases: &[CascadeCase<'_>],
) -> Result<()> {
    let mut s = format!("{lead_header},rank,order,freq_nd,amp_nd\n");
    for c in cases {
        let nu = c.run.speed_ratio;
        for (k, (o, a)) in c.run.whirl.lines.iter().enumerate() {
            s.push_str(&format!(
                "{},{},{:.6},{:.6},{:.6e}\n",
                c.columns,
                k + 1,
                o,
                o * nu,
                a
            ));
        }
    }
    out.write(&format!("{prefix}full_cascade.csv"), s.as_bytes())
}

/// The full-spectrum cascade of `cases` into `file`, added to `draw`: each case's lines at
/// signed `f/ω_n`, its row at `case.y`; `axis`: the vertical axis's description and the top
/// frequency `freq_max` (f/ω_n), the lines drawn within `±freq_max`.
///
/// # Errors
/// A name that cannot be staged ([`Drawings::add`]).
pub fn cascade_drawing(
    out: &mut OutDir,
    file: &str,
    title: &str,
    cases: &[CascadeCase<'_>],
    axis: (&str, f64),
    draw: &mut Drawings<'_>,
) -> Result<()> {
    let rows: Vec<WhirlRow> = cases
        .iter()
        .map(|c| WhirlRow {
            y: c.y,
            speed: c.run.speed_ratio,
            lines: c
                .run
                .whirl
                .lines
                .iter()
                .map(|(o, a)| (o * c.run.speed_ratio, *a))
                .collect(),
        })
        .collect();
    let t = format!("{title} — full-spectrum cascade of (x + iy)/|Z0|");
    let (y_desc, freq_max) = (axis.0.to_string(), axis.1);
    draw.add(out, file, move |p| {
        plot::full_cascade(p, &t, &rows, &y_desc, freq_max, "amplitude / |Z0|")
    })
}

/// Writes a transient's `full_waterfall.csv` and, with `png`, `full_waterfall.png` (the
/// windows' lines against the speed Ω/ω_n, within ±1.5 × the top speed or the strongest
/// line of any window, whichever is wider) and, when a station has stick, `dry_whirl.png`.
/// Each row ends with its window's contact fraction, stick fraction (empty without stick) and
/// dry-friction class (`whirl`, `whip`, empty otherwise), as `sweep.csv` does.
pub fn write_waterfall(
    out: &mut OutDir,
    title: &str,
    windows: &[WaterfallWindow],
    omega_n: f64,
    png: bool,
) -> Result<()> {
    let mut s = String::from(
        "t_s,omega_rad_s,speed_ratio,fwd_1x_m,bwd_1x_m,rank,order,freq_nd,amp_m,contact_fraction,stick_fraction,dry_rub\n",
    );
    for w in windows {
        let nu = w.omega / omega_n;
        let stick = super::csv::stick_cells(w.stick_fraction, w.dry_rub);
        for (k, (o, a)) in w.lines.iter().enumerate() {
            s.push_str(&format!(
                "{:.9e},{:.6e},{:.6},{:.6e},{:.6e},{},{:.6},{:.6},{:.6e},{:.4},{stick}\n",
                w.t,
                w.omega,
                nu,
                w.forward_1x,
                w.backward_1x,
                k + 1,
                o,
                o * nu,
                a,
                w.contact_fraction,
            ));
        }
    }
    out.write("full_waterfall.csv", s.as_bytes())?;
    if !png {
        return Ok(());
    }
    dry_whirl(out, title, windows, omega_n)?;
    let rows: Vec<WhirlRow> = windows
        .iter()
        .map(|w| {
            let nu = w.omega / omega_n;
            WhirlRow {
                y: nu,
                speed: nu,
                lines: w.lines.iter().map(|(o, a)| (o * nu, *a)).collect(),
            }
        })
        .collect();
    // ±1.5 × the top speed, widened to every window's strongest line (a dry whirl's or whip's
    // backward line lies at many times the speed).
    let strongest = rows
        .iter()
        .filter_map(|r| r.lines.first())
        .map(|l| 1.1 * l.0.abs())
        .filter(|f| f.is_finite());
    let fmax =
        (rows.iter().map(|r| r.speed).fold(1.0, f64::max) * 1.5).max(strongest.fold(0.0, f64::max));
    let p = out.stage("full_waterfall.png")?;
    plot::full_cascade(
        &p,
        &format!("{title} — full-spectrum waterfall of x + iy"),
        &rows,
        "Ω / ωn",
        fmax,
        "amplitude (m)",
    )
}

/// A transient's `dry_whirl.png` when a station has stick (docs/STICK.md §4): per window
/// against time, the speed Ω/ω_n, the dominant whirl frequency / ω_n (backward below zero: a
/// roll follows `−RΩ/δ`, a whip stays locked near the coupled natural frequency), the fraction
/// of the contact samples in stick and the contact fraction.
fn dry_whirl(
    out: &mut OutDir,
    title: &str,
    windows: &[WaterfallWindow],
    omega_n: f64,
) -> Result<()> {
    if windows.iter().all(|w| w.stick_fraction.is_none()) {
        return Ok(());
    }
    let column = |label: &str, f: &dyn Fn(&WaterfallWindow) -> f64| plot::Series {
        label: label.into(),
        t: windows.iter().map(|w| w.t).collect(),
        y: windows.iter().map(f).collect(),
    };
    let series = [
        column("Ω / ωn", &|w| w.omega / omega_n),
        column("dominant whirl frequency / ωn (backward < 0)", &|w| {
            w.lines.first().map_or(0.0, |l| l.0 * w.omega / omega_n)
        }),
        column("fraction of contact samples in stick", &|w| {
            w.stick_fraction.unwrap_or(0.0)
        }),
        column("contact fraction", &|w| w.contact_fraction),
    ];
    let p = out.stage("dry_whirl.png")?;
    plot::stacked_series(
        &p,
        &format!("{title} — dry whirl (stick) and whip (slip), window by window"),
        &series,
        "t (s)",
        "",
    )
}
