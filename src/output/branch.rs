//! The files of `rubsim continue` (`analysis::branch`): `branch.csv`, `bifurcations.csv` and
//! `branch.png`, the bifurcation diagram of the continued orbit.

use super::OutDir;
use crate::analysis::branch::Branch;
use crate::error::Result;
use crate::plot::{self, Curve};
use std::fmt::Write as _;

/// Header of `branch.csv`: one row per converged point (extents and amplitude / |Z0|; `rho1_*`
/// the multiplier of largest modulus; `instability` empty when stable).
pub const BRANCH_HEADER: &str = "speed_ratio,stable,largest_modulus,rho1_re,rho1_im,instability,x_min_nd,x_max_nd,y_min_nd,y_max_nd,amp_1x_nd,contact_fraction,newton_iterations,residual";

/// Header of `bifurcations.csv`: one row per located change of stability.
pub const BIFURCATIONS_HEADER: &str =
    "kind,speed_ratio,from,to,rho_stable_re,rho_stable_im,rho_unstable_re,rho_unstable_im";

/// Writes `branch.csv`, `bifurcations.csv` and (`png`) `branch.png` — the orbit's largest
/// |x| or |y| (/|Z0|) against ω/ωn, the stable stretches and the unstable ones as separate
/// curves — into `out`.
///
/// # Errors
/// I/O and drawing errors, naming the file.
pub fn write_branch(out: &mut OutDir, title: &str, branch: &Branch, png: bool) -> Result<()> {
    let mut csv = format!("{BRANCH_HEADER}\n");
    for p in &branch.points {
        let e = p.extents_nd;
        let _ = writeln!(
            csv,
            "{},{},{:e},{:e},{:e},{},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e}",
            p.speed_ratio,
            p.stable,
            p.largest_modulus,
            p.rho1[0],
            p.rho1[1],
            p.instability.unwrap_or(""),
            e[0],
            e[1],
            e[2],
            e[3],
            p.amp_1x_nd,
            p.contact_fraction,
            p.iterations,
            p.residual
        );
    }
    out.write("branch.csv", csv.as_bytes())?;
    let mut bif = format!("{BIFURCATIONS_HEADER}\n");
    for b in &branch.bifurcations {
        let _ = writeln!(
            bif,
            "{},{},{},{},{:e},{:e},{:e},{:e}",
            b.kind,
            b.speed_ratio,
            b.between[0],
            b.between[1],
            b.rho[0][0],
            b.rho[0][1],
            b.rho[1][0],
            b.rho[1][1]
        );
    }
    out.write("bifurcations.csv", bif.as_bytes())?;
    if png {
        let p = out.stage("branch.png")?;
        plot::lines(
            &p,
            &format!(
                "{title} — period-{} orbit continued in speed",
                branch.period
            ),
            &curves(branch),
            "ω/ωn",
            "largest |x|, |y| over the orbit / |Z0|",
        )?;
    }
    Ok(())
}

/// The diagram's curves: the orbit's largest |x| or |y| (/|Z0|), split into its stable and
/// unstable stretches (a non-finite value breaks a line where the other holds).
fn curves(branch: &Branch) -> Vec<Curve> {
    [(true, "stable"), (false, "unstable")]
        .into_iter()
        .map(|(stable, how)| Curve {
            label: how.to_string(),
            points: branch
                .points
                .iter()
                .map(|p| {
                    let reach = p.extents_nd.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
                    (
                        p.speed_ratio,
                        if p.stable == stable { reach } else { f64::NAN },
                    )
                })
                .collect(),
        })
        .collect()
}
