//! The files of `rubsim continue` (`analysis::branch`): `branch.csv`, `bifurcations.csv` and
//! `branch.png`, the bifurcation diagram of the continued orbit, `branch_multipliers.png` (its
//! largest multiplier about the unit circle); and `rubsim periodic`'s `multipliers.png`.

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
        write_branch_multipliers(out, title, branch)?;
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

/// The unit circle |ρ| = 1 as a closed curve.
fn unit_circle() -> Curve {
    Curve {
        label: "|ρ| = 1".into(),
        points: (0..=360)
            .map(|k| {
                let a = f64::from(k).to_radians();
                (a.cos(), a.sin())
            })
            .collect(),
    }
}

/// Points drawn as dots (each followed by a break).
fn dots(points: impl Iterator<Item = [f64; 2]>) -> Vec<(f64, f64)> {
    points
        .flat_map(|m| [(m[0], m[1]), (f64::NAN, f64::NAN)])
        .collect()
}

/// Writes `multipliers.png` into `out`: the Floquet multipliers `rho` (`[Re ρ, Im ρ]`) as dots
/// about the unit circle, to scale — a multiplier outside is unstable, through −1 a period
/// doubling, through +1 a fold, a complex pair a Neimark–Sacker.
///
/// # Errors
/// I/O and drawing errors, naming the file.
pub fn write_multipliers(out: &mut OutDir, title: &str, rho: &[[f64; 2]]) -> Result<()> {
    let p = out.stage("multipliers.png")?;
    plot::equal_aspect(
        &p,
        &format!("{title} — Floquet multipliers"),
        &[
            unit_circle(),
            Curve {
                label: "ρ".into(),
                points: dots(rho.iter().copied()),
            },
        ],
        ("Re ρ", "Im ρ"),
    )
}

/// `branch_multipliers.png`: the largest multiplier ρ₁ of every point of the branch, the stable
/// points and the unstable ones apart, about the unit circle (where ρ₁ leaves it is the
/// bifurcation's kind).
fn write_branch_multipliers(out: &mut OutDir, title: &str, branch: &Branch) -> Result<()> {
    let p = out.stage("branch_multipliers.png")?;
    let of = |stable: bool| {
        dots(
            branch
                .points
                .iter()
                .filter(|q| q.stable == stable)
                .map(|q| q.rho1),
        )
    };
    plot::equal_aspect(
        &p,
        &format!(
            "{title} — the largest multiplier along the period-{} branch",
            branch.period
        ),
        &[
            unit_circle(),
            Curve {
                label: "ρ₁, stable".into(),
                points: of(true),
            },
            Curve {
                label: "ρ₁, unstable".into(),
                points: of(false),
            },
        ],
        ("Re ρ₁", "Im ρ₁"),
    )
}
