//! Pictures of the rotor-alone analyses beyond the Campbell and Bode plots: the mode shapes of
//! `rubsim modal` (`mode_NN.png` along the axis, `mode_NN_3d.png` with the whirl ellipses) and
//! the undamped critical speed map of `rubsim critical-map` (`critical_map.png`).

use super::OutDir;
use crate::error::Result;
use crate::linear::critical_map::CriticalMapResults;
use crate::linear::mode_shape::{
    at_phase, ellipse, node_shape, peak_phase, sample_line, RotorLine,
};
use crate::linear::modes::{ModalResults, Mode};
use crate::plot::{self, Curve, Shape3d, ShapeLine};
use num_complex::Complex64;

/// Samples per shaft element of the drawn lines.
const PER_ELEMENT: usize = 8;
/// Points per whirl ellipse.
const ELLIPSE_POINTS: usize = 64;

/// One line of a mode's title: number, ω_d, f, ζ, whirl (or kind).
pub fn mode_caption(index: usize, m: &Mode) -> String {
    format!(
        "mode {}: ω_d = {:.4} rad/s ({:.4} Hz), ζ = {:.4}, {}",
        index + 1,
        m.omega_d,
        m.freq_hz,
        m.damping_ratio,
        m.label()
    )
}

/// Draws `mode_NN.png` and `mode_NN_3d.png` for every mode of `res` (see
/// [`crate::linear::mode_shape`] for the ellipses, the phase and the interpolation).
///
/// The 2-D figure is the shaft line at the phase where its translations are largest
/// ([`peak_phase`]): `u_x` (x plane) and `u_y` (y plane) against z, with the ± major
/// semi-axis of the whirl ellipse as envelope. The 3-D figure draws the ellipse of every node
/// and the line at the same phase.
pub fn write_mode_shapes(
    out: &mut OutDir,
    title: &str,
    res: &ModalResults,
    line: &RotorLine,
) -> Result<()> {
    let disks: Vec<f64> = line.disk_nodes.iter().map(|&n| line.z[n]).collect();
    let bearings: Vec<f64> = line.bearing_nodes.iter().map(|&n| line.z[n]).collect();
    for (i, m) in res.modes.iter().enumerate() {
        let shape = node_shape(m);
        let alpha = peak_phase(&shape);
        let e = Complex64::from_polar(1.0, alpha);
        let samples = sample_line(line, &shape, PER_ELEMENT);
        let z: Vec<f64> = samples.iter().map(|s| s.0).collect();
        let x: Vec<f64> = samples.iter().map(|s| (s.1[0] * e).re).collect();
        let y: Vec<f64> = samples.iter().map(|s| (s.1[1] * e).re).collect();
        let major: Vec<f64> = samples
            .iter()
            .map(|s| ellipse(s.1[0], s.1[1]).major)
            .collect();
        let caption = mode_caption(i, m);
        let name = format!("mode_{:02}", i + 1);
        let p = out.stage(&format!("{name}.png"))?;
        plot::mode_shape_2d(
            &p,
            &format!("{title} — {caption}"),
            &ShapeLine {
                z: &z,
                x: &x,
                y: &y,
                major: &major,
                disks: &disks,
                bearings: &bearings,
            },
            "normalised deflection",
        )?;
        let ellipses: Vec<Vec<(f64, f64, f64)>> = line
            .z
            .iter()
            .zip(&shape)
            .map(|(zn, p)| {
                (0..=ELLIPSE_POINTS)
                    .map(|k| {
                        let t = std::f64::consts::TAU * k as f64 / ELLIPSE_POINTS as f64;
                        let r = Complex64::from_polar(1.0, t);
                        (*zn, (p[0] * r).re, (p[1] * r).re)
                    })
                    .collect()
            })
            .collect();
        let at = at_phase(&shape, alpha);
        let s3 = Shape3d {
            ellipses,
            disk_ellipse: (0..line.z.len())
                .map(|n| line.disk_nodes.contains(&n))
                .collect(),
            line: z
                .iter()
                .zip(x.iter().zip(&y))
                .map(|(z, (x, y))| (*z, *x, *y))
                .collect(),
            nodes: line
                .z
                .iter()
                .zip(&at)
                .map(|(z, p)| (*z, p[0], p[1]))
                .collect(),
            bearings: bearings.clone(),
        };
        let p = out.stage(&format!("{name}_3d.png"))?;
        plot::mode_shape_3d(
            &p,
            &format!("{title} — {caption}"),
            &s3,
            "whirl ellipses of the nodes (dark: disks), shaft line at the phase of largest deflection; axes z (m), u_x, u_y (normalised)",
        )?;
    }
    Ok(())
}

/// Draws `critical_map.png`: the forward critical speeds (rpm) against the bearing stiffness
/// (N/m), log–log, with the scene's bearing lines `kxx(Ω)`, `kyy(Ω)` (Vance's and ROSS's
/// picture).
pub fn write_critical_map(out: &mut OutDir, title: &str, res: &CriticalMapResults) -> Result<()> {
    let rpm = 30.0 / std::f64::consts::PI;
    let mut curves: Vec<Curve> = (0..res.modes)
        .map(|m| Curve {
            label: format!("forward critical speed {}", m + 1),
            points: res
                .stiffness
                .iter()
                .zip(&res.speeds)
                .map(|(k, c)| (*k, c.forward[m] * rpm))
                .collect(),
        })
        .collect();
    let mut marked = vec![true; curves.len()];
    for b in &res.bearing_lines {
        curves.push(Curve {
            label: b.label.clone(),
            points: b
                .points
                .iter()
                .map(|(k, s)| (*k, s * rpm))
                .filter(|p| p.1 > 0.0)
                .collect(),
        });
        marked.push(false);
    }
    let p = out.stage("critical_map.png")?;
    plot::loglog_marked(
        &p,
        &format!("{title} — undamped critical speed map"),
        &curves,
        &marked,
        "bearing stiffness k (N/m)",
        "critical speed (rpm)",
    )
}
