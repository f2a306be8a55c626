//! A run with wear (`[stator.wear]`): `wear.csv` — per recorded sample the time, the wear time
//! (× `run.wear_acceleration`), the volume worn so far and the largest worn depth —,
//! `worn_depth.csv` — every contact node of the stators that wear at the run's end: stator,
//! node, position, angle, axial position, area, worn depth — and, with pictures, `wear.png`
//! (volume and largest depth against the wear time) and `worn_depth.png` (the worn depth around
//! the circumference, one curve per axial position of a 3-D stator). The worn depth as a field
//! on the stators is the VTK/HDF5 series' point data `worn_depth`.

use super::OutDir;
use crate::analysis::wear::WearResults;
use crate::error::Result;
use crate::plot::{self, Curve, Series};

/// Writes `wear.csv`, `worn_depth.csv` and, with `png`, `wear.png` and `worn_depth.png`.
pub fn write(out: &mut OutDir, title: &str, w: &WearResults, png: bool) -> Result<()> {
    let a = w.acceleration;
    let mut s = String::from("t_s,wear_time_s,worn_volume_m3,max_depth_m\n");
    for h in &w.history {
        s.push_str(&format!(
            "{:.9e},{:.9e},{:.6e},{:.6e}\n",
            h[0],
            a * h[0],
            h[1],
            h[2]
        ));
    }
    out.write("wear.csv", s.as_bytes())?;
    // With an abradable coating, the column `abraded_m` (its plastic shortening, part of the
    // depth) before the depth, which stays the last column.
    let coated = w.abradable.is_some();
    let mut s = String::from("stator,node,x_m,y_m,z_m,angle_deg,area_m2,");
    s.push_str(if coated {
        "abraded_m,depth_m\n"
    } else {
        "depth_m\n"
    });
    for n in &w.nodes {
        s.push_str(&format!(
            "{},{},{:.9e},{:.9e},{:.9e},{:.4},{:.6e},",
            n.stator, n.node, n.x, n.y, n.z, n.angle_deg, n.area_m2
        ));
        if coated {
            s.push_str(&format!("{:.6e},", n.abraded_m));
        }
        s.push_str(&format!("{:.6e}\n", n.depth_m));
    }
    out.write("worn_depth.csv", s.as_bytes())?;
    if !png {
        return Ok(());
    }
    let column = |label: &str, k: usize| Series {
        label: label.into(),
        t: w.history.iter().map(|h| a * h[0]).collect(),
        y: w.history.iter().map(|h| h[k]).collect(),
    };
    let series = [
        column("volume worn (m³)", 1),
        column("largest worn depth (m)", 2),
    ];
    let p = out.stage("wear.png")?;
    plot::stacked_series(
        &p,
        &format!("{title} — wear (magnification A = {a})"),
        &series,
        if a == 1.0 {
            "t (s)"
        } else {
            "wear time A t (s)"
        },
        "",
    )?;
    let p = out.stage("worn_depth.png")?;
    plot::lines(
        &p,
        &format!("{title} — worn depth around the circumference at the end"),
        &depth_curves(w),
        "angle from +x (deg)",
        "worn depth (m)",
    )
}

/// The worn depth against the angle, one curve per stator and axial position (to 1 µm), the
/// nodes of each in angle order.
fn depth_curves(w: &WearResults) -> Vec<Curve> {
    let mut keys: Vec<(String, i64)> = w
        .nodes
        .iter()
        .map(|n| (n.stator.clone(), (n.z * 1e6).round() as i64))
        .collect();
    keys.sort();
    keys.dedup();
    let several = keys.len() > 1;
    keys.into_iter()
        .map(|(stator, z)| {
            let mut points: Vec<(f64, f64)> = w
                .nodes
                .iter()
                .filter(|n| n.stator == stator && (n.z * 1e6).round() as i64 == z)
                .map(|n| (n.angle_deg, n.depth_m))
                .collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            Curve {
                label: if several {
                    format!("{stator}, z = {:.4} m", z as f64 * 1e-6)
                } else {
                    stator
                },
                points,
            }
        })
        .collect()
}
