//! The files of `rubsim continue` (`analysis::branch`): `branch.csv`, `bifurcations.csv` and
//! `branch.png`, the bifurcation diagram of the continued orbit, `branch_multipliers.png` (its
//! largest multiplier about the unit circle); and `rubsim periodic`'s `multipliers.png`.
//!
//! A branch in a scene key (`rubsim continue --key`) has the key's values in a column named by
//! the key: before `speed_ratio` (the fixed speed) in `branch.csv` and `branches.csv`, for
//! `speed_ratio` in `bifurcations.csv` (its `from`, `to` in the key too), `at_<key>` and
//! `found_at_<key>` for `at_speed_ratio`, `found_at_speed_ratio` in `switches.csv`; `branch.png`
//! is drawn over the key.

use super::OutDir;
use crate::analysis::branch::Branch;
use crate::analysis::switch::Diagram;
use crate::error::Result;
use crate::plot::{self, Curve};
use std::fmt::Write as _;

/// Header of `branch.csv`: one row per converged point (extents and amplitude / |Z0|; `rho1_*`
/// the multiplier of largest modulus; `instability` empty when stable).
pub const BRANCH_HEADER: &str = "speed_ratio,stable,largest_modulus,rho1_re,rho1_im,instability,x_min_nd,x_max_nd,y_min_nd,y_max_nd,amp_1x_nd,contact_fraction,newton_iterations,residual";

/// Header of `branches.csv` (`rubsim continue --switch`): [`BRANCH_HEADER`]'s columns after
/// the branch's index (0: the one asked for; the switched ones in the order found) and period.
pub const BRANCHES_HEADER: &str = "branch,period,speed_ratio,stable,largest_modulus,rho1_re,rho1_im,instability,x_min_nd,x_max_nd,y_min_nd,y_max_nd,amp_1x_nd,contact_fraction,newton_iterations,residual";

/// Header of `switches.csv`: one row per switched branch — its index, its parent's, the
/// doubling's index in the parent's bifurcations and speed, where the new orbit was found, on
/// which side, from which offset, and how far from the parent's fixed point.
pub const SWITCHES_HEADER: &str = "branch,period,parent,bifurcation,at_speed_ratio,found_at_speed_ratio,supercritical,offset,distance";

/// Header of `bifurcations.csv`: one row per located change of stability.
pub const BIFURCATIONS_HEADER: &str =
    "kind,speed_ratio,from,to,rho_stable_re,rho_stable_im,rho_unstable_re,rho_unstable_im";

/// Writes `branch.csv`, `bifurcations.csv` and (with `png`, the pictures' view) `branch.png` —
/// the orbit's Poincaré points against ω/ωn, stable stretches solid and unstable ones dashed,
/// over a sweep's points — and `branch_multipliers.png` into `out`.
///
/// # Errors
/// I/O and drawing errors, naming the file.
pub fn write_branch(
    out: &mut OutDir,
    title: &str,
    branch: &Branch,
    png: Option<DiagramView<'_>>,
) -> Result<()> {
    let key = key_of(branch);
    let mut csv = format!("{}\n", with_key(BRANCH_HEADER, key));
    for p in &branch.points {
        csv.push_str(&keyed_row(p, key));
    }
    out.write("branch.csv", csv.as_bytes())?;
    let bif_header = match key {
        Some(k) => BIFURCATIONS_HEADER.replacen("speed_ratio", k, 1),
        None => BIFURCATIONS_HEADER.to_string(),
    };
    let mut bif = format!("{bif_header}\n");
    for b in &branch.bifurcations {
        let _ = writeln!(
            bif,
            "{},{},{},{},{:e},{:e},{:e},{:e}",
            b.kind,
            b.parameter,
            b.between[0],
            b.between[1],
            b.rho[0][0],
            b.rho[0][1],
            b.rho[1][0],
            b.rho[1][1]
        );
    }
    out.write("bifurcations.csv", bif.as_bytes())?;
    if let Some(view) = png {
        write_branch_multipliers(out, title, branch)?;
        branch_png(
            out,
            &format!(
                "{title} — period-{} orbit continued in {}",
                branch.period,
                continued_in(branch)
            ),
            std::slice::from_ref(branch),
            view,
        )?;
    }
    Ok(())
}

/// The key of a branch in a scene key (`None`: a branch in speed).
fn key_of(b: &Branch) -> Option<&str> {
    b.at_speed_ratio.map(|_| b.parameter.as_str())
}

/// What a branch is continued in, for titles: `speed`, or `<key> at ω/ωn ν`.
fn continued_in(b: &Branch) -> String {
    match (key_of(b), b.at_speed_ratio) {
        (Some(k), Some(nu)) => format!("{k} at ω/ωn {nu:.4}"),
        _ => "speed".to_string(),
    }
}

/// `header` of a branch in `key`: the key's column before `speed_ratio`.
fn with_key(header: &str, key: Option<&str>) -> String {
    match key {
        Some(k) => header.replacen("speed_ratio", &format!("{k},speed_ratio"), 1),
        None => header.to_string(),
    }
}

/// A point's row of `branch.csv` (with its newline), after the key's value for a branch in
/// `key`.
fn keyed_row(p: &crate::analysis::branch::BranchPoint, key: Option<&str>) -> String {
    match key {
        Some(_) => format!("{},{}", p.parameter, point_row(p)),
        None => point_row(p),
    }
}

/// A point's row of `branch.csv` (with its newline).
fn point_row(p: &crate::analysis::branch::BranchPoint) -> String {
    let e = p.extents_nd;
    format!(
        "{},{},{:e},{:e},{:e},{},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e}\n",
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
    )
}

/// Writes `rubsim continue --switch`'s files into `out`: the first branch's as
/// [`write_branch`] (its `branch.png` then drawing every branch),
/// `branches.csv` (every branch's points) and `switches.csv` (where each switched branch came
/// from).
///
/// # Errors
/// I/O and drawing errors, naming the file.
pub fn write_diagram(
    out: &mut OutDir,
    title: &str,
    d: &Diagram,
    png: Option<DiagramView<'_>>,
) -> Result<()> {
    let Some(first) = d.branches.first() else {
        return Ok(());
    };
    write_branch(out, title, first, None)?;
    let key = key_of(first);
    let mut csv = format!("{}\n", with_key(BRANCHES_HEADER, key));
    for (i, b) in d.branches.iter().enumerate() {
        for p in &b.points {
            csv.push_str(&format!("{i},{},{}", b.period, keyed_row(p, key)));
        }
    }
    out.write("branches.csv", csv.as_bytes())?;
    let sw_header = match key {
        Some(k) => SWITCHES_HEADER.replacen(
            "at_speed_ratio,found_at_speed_ratio",
            &format!("at_{k},found_at_{k}"),
            1,
        ),
        None => SWITCHES_HEADER.to_string(),
    };
    let mut sw = format!("{sw_header}\n");
    for r in &d.switched {
        let _ = writeln!(
            sw,
            "{},{},{},{},{},{},{},{:e},{:e}",
            r.branch,
            d.branches[r.branch].period,
            r.parent,
            r.bifurcation,
            r.at,
            r.found_at,
            r.supercritical,
            r.offset,
            r.distance
        );
    }
    out.write("switches.csv", sw.as_bytes())?;
    if let Some(view) = png {
        write_branch_multipliers(out, title, first)?;
        branch_png(
            out,
            &format!(
                "{title} — periodic orbits continued in {}{}",
                continued_in(first),
                if d.switched.is_empty() {
                    ""
                } else {
                    ", switched at period doublings"
                }
            ),
            &d.branches,
            view,
        )?;
    }
    Ok(())
}

/// What `branch.png` draws besides the branches: the Poincaré section's component (`"x"` or
/// `"y"`, the scene's `output.component`) and a sweep's Poincaré points `(ν, value / |Z0|)` to
/// draw under them (empty: none).
#[derive(Debug, Clone, Copy)]
pub struct DiagramView<'a> {
    /// `"x"` or `"y"`.
    pub component: &'a str,
    /// The sweep's points, grey.
    pub sweep: &'a [(f64, f64)],
}

/// `branch.png`: every branch of `branches` on the Poincaré section once per revolution — the
/// `component` of each of its orbits' `k` section points against ω/ωn, one line per point, in
/// the branch's colour, stable stretches solid and unstable ones dashed — over the sweep's
/// points.
fn branch_png(
    out: &mut OutDir,
    title: &str,
    branches: &[Branch],
    view: DiagramView<'_>,
) -> Result<()> {
    let c = usize::from(view.component == "y");
    let x_label = branches
        .first()
        .and_then(key_of)
        .unwrap_or("ω/ωn")
        .to_string();
    let mut lines = Vec::new();
    for (i, b) in branches.iter().enumerate() {
        let from = b.points.first().map_or(0.0, |p| p.parameter);
        for j in 0..b.period {
            for (stable, points) in curves(b, &|p| p.poincare_nd.get(j).map_or(f64::NAN, |q| q[c]))
            {
                lines.push(plot::BranchLine {
                    label: match (stable && j == 0, i) {
                        (false, _) => String::new(),
                        (true, 0) => format!("period {}", b.period),
                        (true, _) => format!("period {}, from {x_label} {from:.3}", b.period),
                    },
                    points,
                    dashed: !stable,
                    colour: i,
                });
            }
        }
    }
    let p = out.stage("branch.png")?;
    let sweep = if view.sweep.is_empty() {
        ""
    } else {
        "; grey: the sweep's Poincaré points"
    };
    plot::branch_diagram(
        &p,
        &format!("{title} (dashed: unstable{sweep})"),
        &lines,
        view.sweep,
        (&x_label, &format!("{}/|Z0| at ωt = 2πk", view.component)),
    )
}

/// A branch's values `value(point)` against its parameter (ω/ωn, or its key), as its stable and its unstable stretches
/// ([`stretch_curves`]).
fn curves(
    branch: &Branch,
    value: &dyn Fn(&crate::analysis::branch::BranchPoint) -> f64,
) -> [(bool, Vec<(f64, f64)>); 2] {
    let points: Vec<(f64, bool, f64)> = branch
        .points
        .iter()
        .map(|p| (p.parameter, p.stable, value(p)))
        .collect();
    stretch_curves(&points)
}

/// Points `(parameter, stable, value)` in a branch's order as its stable and its unstable
/// stretches (`(stable, points)`; a NaN breaks a line where the other holds; the segment across
/// a change of stability belongs to the unstable side, so that the line is not broken there).
pub(super) fn stretch_curves(points: &[(f64, bool, f64)]) -> [(bool, Vec<(f64, f64)>); 2] {
    let near = |j: usize| points.get(j).is_some_and(|q| !q.1);
    [true, false].map(|stable| {
        let line = points
            .iter()
            .enumerate()
            .map(|(i, &(x, s, y))| {
                let unstable_near = near(i) || near(i + 1) || (i > 0 && near(i - 1));
                let on = if stable { s } else { unstable_near };
                (x, if on { y } else { f64::NAN })
            })
            .collect();
        (stable, line)
    })
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
