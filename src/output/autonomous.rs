//! The files of `rubsim continue --autonomous` (`analysis::autonomous_branch`): `branch.csv`,
//! one row per converged autonomous orbit, and `branch.png` — the whirl's frequency over ω_n
//! and the first station's radius against the parameter, stable stretches solid and unstable
//! ones dashed. A branch in a scene key has the key's values in a first column named by the
//! key, before `speed_ratio` (the fixed speed), and is drawn over the key.

use super::OutDir;
use crate::analysis::autonomous::AutonomousOrbit;
use crate::analysis::autonomous_branch::AutonomousBranch;
use crate::error::Result;
use crate::plot;
use std::fmt::Write as _;

/// Header of an autonomous `branch.csv` (`rubsim continue --autonomous`): the speed, the
/// verdict, the largest multiplier other than the trivial one and the trivial one, the period
/// (s), the whirl's frequency over ω_n and over Ω (signed: negative backward), the first
/// station's smallest and largest radius over the period (m), its contact fraction, Newton's
/// iterations and residual.
pub const AUTONOMOUS_HEADER: &str = "speed_ratio,stable,largest_modulus,rho1_re,rho1_im,instability,trivial_re,trivial_im,period_s,whirl_ratio,order,radius_min_m,radius_max_m,contact_fraction,newton_iterations,residual";

/// Writes `branch.csv` and, with `png`, `branch.png` of `branch` into `out`.
///
/// # Errors
/// I/O and drawing errors, naming the file.
pub fn write_autonomous_branch(
    out: &mut OutDir,
    title: &str,
    branch: &AutonomousBranch,
    png: bool,
) -> Result<()> {
    let key = branch.at_speed_ratio.map(|_| branch.parameter.as_str());
    let mut csv = match key {
        Some(k) => format!("{k},{AUTONOMOUS_HEADER}\n"),
        None => format!("{AUTONOMOUS_HEADER}\n"),
    };
    for p in &branch.points {
        if key.is_some() {
            let _ = write!(csv, "{},", p.parameter);
        }
        csv.push_str(&row(p));
    }
    out.write("branch.csv", csv.as_bytes())?;
    if png {
        branch_png(out, title, branch, key.unwrap_or("ω/ωn"))?;
    }
    Ok(())
}

/// One row of [`AUTONOMOUS_HEADER`].
fn row(p: &AutonomousOrbit) -> String {
    let rho1 = p
        .multipliers
        .iter()
        .find(|r| **r != p.trivial_multiplier)
        .copied()
        .unwrap_or([f64::NAN; 2]);
    format!(
        "{},{},{:e},{:e},{:e},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{},{},{:e}\n",
        p.speed_ratio,
        p.stable,
        p.largest_modulus,
        rho1[0],
        rho1[1],
        p.instability.unwrap_or(""),
        p.trivial_multiplier[0],
        p.trivial_multiplier[1],
        p.period_s,
        p.whirl_ratio,
        p.order,
        p.radius_m[0],
        p.radius_m[1],
        p.contact_fraction,
        p.iterations,
        p.residual
    )
}

/// A value of an orbit drawn against the parameter.
type Quantity = fn(&AutonomousOrbit) -> f64;

/// `branch.png`: the whirl's frequency over ω_n and the mean radius (mm) against the
/// parameter, each with its stable stretches solid and its unstable ones dashed.
fn branch_png(out: &mut OutDir, title: &str, b: &AutonomousBranch, x_label: &str) -> Result<()> {
    let mut lines = Vec::new();
    let quantities: [(&str, Quantity); 2] = [
        ("whirl ω_w/ω_n", |p| p.whirl_ratio),
        ("radius (mm)", |p| 0.5e3 * (p.radius_m[0] + p.radius_m[1])),
    ];
    for (colour, (name, value)) in quantities.into_iter().enumerate() {
        let points: Vec<(f64, bool, f64)> = b
            .points
            .iter()
            .map(|p| (p.parameter, p.stable, value(p)))
            .collect();
        for (stable, points) in super::branch::stretch_curves(&points) {
            lines.push(plot::BranchLine {
                label: if stable {
                    name.to_string()
                } else {
                    String::new()
                },
                points,
                dashed: !stable,
                colour,
            });
        }
    }
    let p = out.stage("branch.png")?;
    plot::branch_diagram(
        &p,
        &format!("{title} — autonomous orbit (dashed: unstable)"),
        &lines,
        &[],
        (x_label, "whirl ω_w/ω_n; radius (mm)"),
    )
}
