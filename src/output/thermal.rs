//! The files of a thermal run (`analysis::thermal`): `spiral.csv` (every coupling step), the
//! 1× vector's spiral in the rotor's frame with time marks (`spiral.png`) and the temperature,
//! bow, 1× amplitude and friction power against time (`thermal.png`); for an FE rotor also
//! the bow along the shaft at the last ΔT (`bow_shape.csv`).

use super::OutDir;
use crate::analysis::thermal::ThermalResults;
use crate::error::Result;
use crate::plot::{self, Curve, Series};
use std::fmt::Write as _;

/// Header of `spiral.csv`: per coupling step the machine time (s), ΔT (K), the bow (m), the
/// 1× vector (m) — all in the rotor's frame —, its amplitude (m) and angle (degrees), the heat's
/// first harmonic (W, rotor frame), the mean friction power (W), the contact fraction and the
/// orbit's change over a revolution relative to its radius (`ThermalSample::non_synchronous`).
pub const SPIRAL_HEADER: &str = "t_s,delta_t_x_k,delta_t_y_k,bow_x_m,bow_y_m,one_x_re_m,one_x_im_m,one_x_amp_m,one_x_deg,heat_x_w,heat_y_w,power_w,contact_fraction,non_synchronous";

/// Header of `bow_shape.csv` (FE rotors): per shaft node its axial position (m) and its bow in
/// the rotor's frame (m) at the run's last ΔT — the static deflection of the curvature load on
/// the rotor's bearings (`ThermalResults::bow_shape`).
pub const BOW_SHAPE_HEADER: &str = "z_m,bow_x_m,bow_y_m";

/// Marks on the spiral: about this many along the run.
const MARKS: usize = 10;

/// Writes `spiral.csv` and (`png`) `spiral.png` and `thermal.png` into `out`.
///
/// # Errors
/// I/O and drawing errors, naming the file.
pub fn write_thermal(out: &mut OutDir, title: &str, r: &ThermalResults, png: bool) -> Result<()> {
    let mut csv = format!("{SPIRAL_HEADER}\n");
    for s in &r.samples {
        let z = s.one_x;
        let _ = writeln!(
            csv,
            "{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e}",
            s.t_s,
            s.delta_t[0],
            s.delta_t[1],
            s.bow[0],
            s.bow[1],
            z[0],
            z[1],
            z[0].hypot(z[1]),
            z[1].atan2(z[0]).to_degrees(),
            s.heat[0],
            s.heat[1],
            s.power,
            s.contact_fraction,
            s.non_synchronous
        );
    }
    out.write("spiral.csv", csv.as_bytes())?;
    if !r.bow_shape.is_empty() {
        let mut csv = format!("{BOW_SHAPE_HEADER}\n");
        for p in &r.bow_shape {
            let _ = writeln!(csv, "{},{:e},{:e}", p.z_m, p.bow[0], p.bow[1]);
        }
        out.write("bow_shape.csv", csv.as_bytes())?;
    }
    if !png {
        return Ok(());
    }
    let every = r.samples.len().div_ceil(MARKS).max(1);
    let um = |v: f64| v * 1e6;
    let path: Vec<(f64, f64)> = r
        .samples
        .iter()
        .map(|s| (um(s.one_x[0]), um(s.one_x[1])))
        .collect();
    let mut marks = Vec::new();
    for s in r.samples.iter().step_by(every) {
        marks.push((um(s.one_x[0]), um(s.one_x[1])));
        marks.push((f64::NAN, f64::NAN));
    }
    let step_s = every as f64 * r.coupling_step_s;
    let p = out.stage("spiral.png")?;
    plot::equal_aspect(
        &p,
        &format!(
            "{title} — the 1× vector in the rotor's frame, ω/ωn = {:.3}",
            r.speed_ratio
        ),
        &[
            Curve {
                label: "1× vector".into(),
                points: path,
            },
            Curve {
                label: format!("every {step_s:.4} s from t = 0"),
                points: marks,
            },
            Curve {
                label: "origin".into(),
                points: vec![(0.0, 0.0)],
            },
        ],
        ("Re (µm)", "Im (µm)"),
    )?;
    let t: Vec<f64> = r.samples.iter().map(|s| s.t_s).collect();
    let series =
        |label: &str, f: &dyn Fn(&crate::analysis::thermal::ThermalSample) -> f64| Series {
            label: label.into(),
            t: t.clone(),
            y: r.samples.iter().map(f).collect(),
        };
    let p = out.stage("thermal.png")?;
    plot::stacked_series(
        &p,
        &format!("{title} — heat, bow and vibration"),
        &[
            series("|ΔT| (K)", &|s| s.delta_t[0].hypot(s.delta_t[1])),
            series("|bow| (µm)", &|s| um(s.bow[0].hypot(s.bow[1]))),
            series("|1×| (µm)", &|s| um(s.one_x[0].hypot(s.one_x[1]))),
            series("friction power (W)", &|s| s.power),
        ],
        "t (s)",
        "",
    )
}
