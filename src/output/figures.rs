//! The pictures (PNG) of every command, drawn with [`crate::plot`] from analysis results.
//!
//! Orbits and spectra are in units of |Z0|, forces of the unbalance force |U|ω², speeds and
//! frequencies of ω_n (the `_nd` conventions of [`crate::analysis`]).

use super::{Drawings, OutDir};
use crate::analysis::refine::RefinePoint;
use crate::analysis::{
    regime_label, ConvergencePoint, ConvergenceResults, SpeedResults, StressResults, StressTrace,
    SweepResults,
};
use crate::error::Result;
use crate::linear::campbell::CampbellResults;
use crate::linear::response::ResponsePoint;
use crate::model::stator::{StatorElement, StatorModel};
use crate::model::Case;
use crate::plot::{self, Boundary, CascadeLine, Curve, OrbitPanel, Series};

/// Stator boundary drawn in orbit plots, in units of |Z0|.
pub fn boundary(case: &Case) -> Boundary {
    let z0 = if case.z0 > 0.0 { case.z0 } else { 1.0 };
    // The boundary is the first stator's, seen from its station: drawn only when the analysed
    // node is that station's node.
    let station_node = case
        .stators
        .first()
        .filter(|s| !s.targets.is_empty())
        .and_then(|s| case.stations.get(s.target_station(0)))
        .map(|st| st.node);
    if station_node.is_some_and(|n| n != case.observed_node) {
        return Boundary::None;
    }
    match case.stators.first() {
        Some(s) if s.is_ring => Boundary::Circle {
            radius: s.clearance / z0,
        },
        Some(s) => match s.angle_deg {
            Some(a) => Boundary::Line {
                angle_deg: a,
                distance: s.clearance / z0,
            },
            None => Boundary::None,
        },
        None => Boundary::None,
    }
}

/// What a sweep draws.
#[derive(Debug, Clone)]
pub struct SweepFigures<'a> {
    /// Title on every picture.
    pub title: &'a str,
    /// Stator boundary per speed (orbit panels).
    pub bounds: &'a [Boundary],
    /// Orbit grids (lists of ω/ω_n).
    pub orbit_grids: &'a [Vec<f64>],
    /// Speeds whose contact-force histories are drawn.
    pub force_histories: &'a [f64],
    /// Upper frequency of the cascade (f/ω_n).
    pub cascade_max: f64,
    /// Write PNGs at all.
    pub png: bool,
    /// Analysed component, `"x"` or `"y"`.
    pub component: &'a str,
}

/// A sweep's pictures in `out` under `prefix` (e.g. `""` or `"eps_5/"`), added to `draw`:
/// `cascade.png`, `bifurcation.png`, `orbits_N.png` per orbit grid, `contact_force.png` (when
/// force histories are asked for) and `regime_map.png`; nothing when `fig.png` is false.
///
/// # Errors
/// A name that cannot be staged ([`Drawings::add`]).
pub fn sweep_drawings<'a>(
    out: &mut OutDir,
    prefix: &str,
    res: &'a SweepResults,
    fig: &SweepFigures<'_>,
    draw: &mut Drawings<'a>,
) -> Result<()> {
    if !fig.png {
        return Ok(());
    }
    sweep_spectra(out, prefix, res, fig, draw)?;
    sweep_orbits(out, prefix, res, fig, draw)?;
    sweep_dry_whirl(out, prefix, res, fig.title, draw)?;
    sweep_regime_map(out, prefix, res, fig.title, draw)
}

/// `dry_whirl.png` of a sweep with stick (docs/STICK.md §4): against speed, the dominant
/// whirl frequency (backward below zero: a roll follows `−RΩ/δ`, a whip stays locked near the
/// coupled natural frequency), the fraction of the contact instants in stick and the contact
/// fraction; nothing for a sweep without stick.
fn sweep_dry_whirl(
    out: &mut OutDir,
    prefix: &str,
    res: &SweepResults,
    title: &str,
    draw: &mut Drawings<'_>,
) -> Result<()> {
    if res.speeds.iter().all(|r| r.stick_fraction.is_none()) {
        return Ok(());
    }
    let column = |label: &str, f: &dyn Fn(&SpeedResults) -> f64| plot::Series {
        label: label.into(),
        t: res.speeds.iter().map(|r| r.speed_ratio).collect(),
        y: res.speeds.iter().map(f).collect(),
    };
    let series = vec![
        column(
            "dominant whirl frequency / ωn (backward < 0)",
            &|r: &SpeedResults| r.whirl.dominant_order * r.speed_ratio,
        ),
        column(
            "fraction of contact instants in stick",
            &|r: &SpeedResults| r.stick_fraction.unwrap_or(0.0),
        ),
        column("contact fraction", &|r: &SpeedResults| r.contact_fraction),
    ];
    let t = format!("{title} — dry whirl (stick) and whip (slip)");
    draw.add(out, &format!("{prefix}dry_whirl.png"), move |p| {
        plot::stacked_series(p, &t, &series, "ω/ωn", "")
    })
}

/// Index of the sweep speed nearest ω/ω_n = `v`.
fn nearest(res: &SweepResults, v: f64) -> Option<usize> {
    res.speeds
        .iter()
        .enumerate()
        .min_by(|a, b| {
            (a.1.speed_ratio - v)
                .abs()
                .total_cmp(&(b.1.speed_ratio - v).abs())
        })
        .map(|(i, _)| i)
}

/// `cascade.png` and `bifurcation.png`.
fn sweep_spectra<'a>(
    out: &mut OutDir,
    prefix: &str,
    res: &'a SweepResults,
    fig: &SweepFigures<'_>,
    draw: &mut Drawings<'a>,
) -> Result<()> {
    let (title, component) = (fig.title, fig.component);
    let lines: Vec<CascadeLine> = res
        .speeds
        .iter()
        .map(|r| CascadeLine {
            speed: r.speed_ratio,
            freq: r.spectrum.iter().map(|p| p.0).collect(),
            amp: r.spectrum.iter().map(|p| p.1).collect(),
        })
        .collect();
    let cascade_title = format!("{title} — spectrum cascade of {component}/|Z0|");
    let (top, width) = (
        fig.cascade_max,
        0.8 * res.speeds.first().map_or(0.1, |_| step_of(&res.speeds)) * 10.0,
    );
    draw.add(out, &format!("{prefix}cascade.png"), move |p| {
        plot::cascade(p, &cascade_title, &lines, top, width)
    })?;
    let pts: Vec<(f64, f64)> = res
        .speeds
        .iter()
        .flat_map(|r| {
            let c = if component == "x" { 0 } else { 1 };
            r.poincare_nd.iter().map(move |p| (r.speed_ratio, p[c]))
        })
        .collect();
    let (bif_title, axis) = (
        format!("{title} — Poincaré section once per revolution"),
        format!("{component}/|Z0| at ωt = 2πk"),
    );
    draw.add(out, &format!("{prefix}bifurcation.png"), move |p| {
        plot::bifurcation(p, &bif_title, &pts, &axis)
    })
}

/// `orbits_N.png` per orbit grid and `contact_force.png`.
fn sweep_orbits<'a>(
    out: &mut OutDir,
    prefix: &str,
    res: &'a SweepResults,
    fig: &SweepFigures<'_>,
    draw: &mut Drawings<'a>,
) -> Result<()> {
    let title = fig.title;
    let find = |v: f64| nearest(res, v);
    for (g, speeds) in fig.orbit_grids.iter().enumerate() {
        let panels: Vec<OrbitPanel> = speeds
            .iter()
            .filter_map(|v| find(*v))
            .map(|i| {
                let r = &res.speeds[i];
                OrbitPanel {
                    title: format!("ω/ωn = {:.1}  ({})", r.speed_ratio, regime_label(r)),
                    x: r.orbit_nd.iter().map(|p| p[0]).collect(),
                    y: r.orbit_nd.iter().map(|p| p[1]).collect(),
                    boundary: fig.bounds.get(i).cloned().unwrap_or(Boundary::None),
                    poincare: r.poincare_nd.iter().map(|p| (p[0], p[1])).collect(),
                }
            })
            .collect();
        let grid_title = format!("{title} — orbits of the rotor centre");
        draw.add(out, &format!("{prefix}orbits_{}.png", g + 1), move |p| {
            plot::orbit_grid(p, &grid_title, &panels, 3)
        })?;
    }
    if !fig.force_histories.is_empty() {
        let series: Vec<Series> = fig
            .force_histories
            .iter()
            .filter_map(|v| find(*v))
            .map(|i| {
                let r = &res.speeds[i];
                Series {
                    label: format!("ω/ωn = {:.1}", r.speed_ratio),
                    t: r.force_history.iter().map(|p| p.0).collect(),
                    y: r.force_history.iter().map(|p| p.1).collect(),
                }
            })
            .collect();
        let force_title = format!("{title} — vertical contact force on the stator");
        draw.add(out, &format!("{prefix}contact_force.png"), move |p| {
            plot::stacked_series(p, &force_title, &series, "revolutions", "F_y / (m_u e ω²)")
        })?;
    }
    Ok(())
}

/// `regime_map.png`: vertical orbit size and Poincaré period against speed.
fn sweep_regime_map(
    out: &mut OutDir,
    prefix: &str,
    res: &SweepResults,
    title: &str,
    draw: &mut Drawings<'_>,
) -> Result<()> {
    let size: Vec<(f64, f64)> = res
        .speeds
        .iter()
        .map(|r| (r.speed_ratio, r.extents_nd[3] - r.extents_nd[2]))
        .collect();
    let per: Vec<(f64, f64)> = res
        .speeds
        .iter()
        .map(|r| (r.speed_ratio, r.period as f64))
        .collect();
    let map_title = format!("{title} — regime map");
    let curves = [
        Curve {
            label: "vertical orbit size / |Z0|".into(),
            points: size,
        },
        Curve {
            label: "Poincaré period (0 = not periodic)".into(),
            points: per,
        },
    ];
    draw.add(out, &format!("{prefix}regime_map.png"), move |p| {
        plot::lines(p, &map_title, &curves, "ω/ωn", "")
    })
}

fn step_of(s: &[SpeedResults]) -> f64 {
    if s.len() > 1 {
        (s[s.len() - 1].speed_ratio - s[0].speed_ratio) / (s.len() - 1) as f64
    } else {
        0.1
    }
}

/// Draws a single run (`rubsim run`): `orbit.png` (with the stator boundary `bound`),
/// `spectrum.png` and `contact_force.png`.
pub fn write_run(
    out: &mut OutDir,
    title: &str,
    r: &SpeedResults,
    bound: Boundary,
    component: &str,
) -> Result<()> {
    let p = out.stage("orbit.png")?;
    plot::orbit_grid(
        &p,
        title,
        &[OrbitPanel {
            title: format!("ω/ωn = {:.3}  ({})", r.speed_ratio, regime_label(r)),
            x: r.orbit_nd.iter().map(|p| p[0]).collect(),
            y: r.orbit_nd.iter().map(|p| p[1]).collect(),
            boundary: bound,
            poincare: r.poincare_nd.iter().map(|p| (p[0], p[1])).collect(),
        }],
        1,
    )?;
    let p = out.stage("spectrum.png")?;
    plot::lines(
        &p,
        &format!("{title} — Hann-windowed spectrum of {component}/|Z0|"),
        &[Curve {
            label: format!("{component}/|Z0|"),
            points: r.spectrum.clone(),
        }],
        "f / ωn",
        "amplitude / |Z0|",
    )?;
    let p = out.stage("contact_force.png")?;
    plot::stacked_series(
        &p,
        &format!("{title} — vertical contact force on the stator"),
        &[Series {
            label: format!("ω/ωn = {:.3}", r.speed_ratio),
            t: r.force_history.iter().map(|p| p.0).collect(),
            y: r.force_history.iter().map(|p| p.1).collect(),
        }],
        "revolutions",
        "F_y / (m_u e ω²)",
    )?;
    Ok(())
}

/// Draws a convergence study: `work_precision.png` (orbit error against wall time) and
/// `error_vs_dt.png`, one curve per integrator with its observed order.
pub fn write_convergence(
    out: &mut OutDir,
    prefix: &str,
    title: &str,
    c: &ConvergenceResults,
) -> Result<()> {
    // One curve per integrator, and the point the error-target choice picked (a lone marker).
    let curves = |f: &dyn Fn(&ConvergencePoint) -> (f64, f64)| -> Vec<Curve> {
        c.orders
            .iter()
            .map(|(name, order)| Curve {
                label: format!("{name} (observed order {order:.2})"),
                points: c
                    .points
                    .iter()
                    .filter(|p| p.integrator == *name)
                    .map(f)
                    .collect(),
            })
            .chain(c.chosen.iter().map(|p| Curve {
                label: format!(
                    "chosen by run.tolerance: {}, {} steps/rev",
                    p.integrator, p.steps_per_rev
                ),
                points: vec![f(p)],
            }))
            .collect()
    };
    let p = out.stage(&format!("{prefix}work_precision.png"))?;
    plot::loglog(
        &p,
        &format!("{title} — work-precision at ω/ωn = {}", c.speed_ratio),
        &curves(&|p| (p.wall_s, p.orbit_err)),
        "wall time of the run (s)",
        "relative orbit error",
    )?;
    let p = out.stage(&format!("{prefix}error_vs_dt.png"))?;
    plot::loglog(
        &p,
        &format!(
            "{title} — orbit error against time step at ω/ωn = {}",
            c.speed_ratio
        ),
        &curves(&|p| (p.dt_wn, p.orbit_err)),
        "Δt·ωn",
        "relative orbit error",
    )?;
    Ok(())
}

/// Polygons of the 2-D cells of a stator (corner nodes, m) with a value per element, for
/// [`plot::mesh_field`]; 3-D cells are projected on the station plane, tooth-tip first
/// (cells sorted by decreasing axial position so the ones nearest z = 0 are drawn last).
pub fn cell_polygons(s: &StatorModel, values: &[f64]) -> Vec<(Vec<(f64, f64)>, f64)> {
    type Drawn = (f64, Vec<(f64, f64)>, f64);
    let mut out: Vec<Drawn> = Vec::new();
    for (el, v) in s.elements.iter().zip(values) {
        let (kind, nodes) = match el {
            StatorElement::Solid2 { kind, nodes, .. }
            | StatorElement::Solid3 { kind, nodes, .. } => (*kind, nodes),
            _ => continue,
        };
        let corners = &nodes[..kind.corners()];
        let z = s
            .mesh
            .as_ref()
            .filter(|m| !m.node_z.is_empty())
            .map_or(0.0, |m| {
                corners.iter().map(|&n| m.node_z[n].abs()).sum::<f64>()
            });
        let poly = corners
            .iter()
            .map(|&n| (s.nodes[n][0], s.nodes[n][1]))
            .collect();
        out.push((z, poly, *v));
    }
    out.sort_by(|a, b| b.0.total_cmp(&a.0));
    out.into_iter().map(|(_, p, v)| (p, v)).collect()
}

/// Draws the stress field of one stator at the instant of largest stress of its trace at
/// ω/ω_n = `v`: `stress_field_<stator>_<v>.png`, log₁₀ of the von Mises stress over four
/// decades below the peak (contact at nodes concentrates it by orders of magnitude), the
/// nodes in contact then marked. Nothing for a stator without 2-D or 3-D cells.
pub fn write_stress_field(
    out: &mut OutDir,
    v: f64,
    tr: &StressTrace,
    st: &StatorModel,
) -> Result<()> {
    let floor = 1e-4 * tr.peak_field.iter().fold(0.0_f64, |m, s| m.max(s.abs())) / 1e6;
    let mpa: Vec<f64> = tr
        .peak_field
        .iter()
        .map(|s| (s.abs() / 1e6).max(floor).max(1e-12).log10())
        .collect();
    let polys = cell_polygons(st, &mpa);
    if polys.is_empty() {
        return Ok(());
    }
    let marks: Vec<(f64, f64)> = tr
        .peak_contacts
        .iter()
        .map(|&n| (st.nodes[n][0], st.nodes[n][1]))
        .collect();
    let name = format!("stress_field_{}_{v}.png", tr.name);
    let p = out.stage(&name)?;
    plot::mesh_field(
        &p,
        &format!(
            "`{}` at ω/ωn = {v}, t = {:.5} s: von Mises stress (contact nodes ×)",
            tr.name, tr.peak_time
        ),
        &polys,
        "log₁₀ σ_vM (MPa)",
        &marks,
    )?;
    Ok(())
}

/// Draws `stress.png` and `strain.png`: the largest element stress (MPa) and its strain
/// (µm/m) of every stator at every speed, against time in revolutions before the end of the
/// run so that the speeds' panels align.
pub fn write_stress(out: &mut OutDir, runs: &[StressResults]) -> Result<()> {
    let mut stress_series = Vec::new();
    let mut strain_series = Vec::new();
    for r in runs {
        let v = r.speed_ratio;
        for tr in &r.traces {
            let label = format!("ω/ωn = {v}: stator `{}`", tr.name);
            let t_end = tr.t.last().copied().unwrap_or(0.0);
            let revs: Vec<f64> =
                tr.t.iter()
                    .map(|t| (t - t_end) * r.omega / (2.0 * std::f64::consts::PI))
                    .collect();
            stress_series.push(Series {
                label: label.clone(),
                t: revs.clone(),
                y: tr.stress.iter().map(|s| s / 1e6).collect(),
            });
            strain_series.push(Series {
                label,
                t: revs,
                y: tr.strain.iter().map(|s| s * 1e6).collect(),
            });
        }
    }
    let p = out.stage("stress.png")?;
    plot::stacked_series(
        &p,
        "Largest element stress in the stator (bars: axial, cells: von Mises)",
        &stress_series,
        "t − t_end (revolutions)",
        "σ (MPa)",
    )?;
    let p = out.stage("strain.png")?;
    plot::stacked_series(
        &p,
        "Strain of that element (σ/E)",
        &strain_series,
        "t − t_end (revolutions)",
        "ε (µm/m)",
    )?;
    Ok(())
}

/// Draws a mesh-refinement study by the scene key `key`: `refine_force.png` (the force over
/// the last `window` revolutions), `refine_orbit.png` and `refine_cost.png` (time per step
/// against stator DOFs).
pub fn write_refine(
    out: &mut OutDir,
    key: &str,
    window: usize,
    points: &[(String, RefinePoint)],
) -> Result<()> {
    let mut forces = Vec::new();
    let mut orbits = Vec::new();
    let mut cost = Vec::new();
    for (v, pt) in points {
        cost.push((pt.dofs as f64, pt.us_per_step));
        let label = format!("{v} ({} nodes)", pt.targets);
        forces.push(Curve {
            label: label.clone(),
            points: pt.tail.iter().map(|p| (p.0 - pt.t_end, p.1)).collect(),
        });
        orbits.push(Curve {
            label,
            points: pt.results.orbit_nd.iter().map(|p| (p[0], p[1])).collect(),
        });
    }
    let p = out.stage("refine_force.png")?;
    plot::lines(
        &p,
        &format!("Contact force, last {window} revolutions, by {key}"),
        &forces,
        "t − t_end (revolutions)",
        "vertical contact force / (m_u e ω²)",
    )?;
    let p = out.stage("refine_orbit.png")?;
    plot::lines(
        &p,
        &format!("Steady orbit by {key}"),
        &orbits,
        "x / |Z0|",
        "y / |Z0|",
    )?;
    let p = out.stage("refine_cost.png")?;
    plot::loglog(
        &p,
        "Time per step against stator DOFs",
        &[Curve {
            label: key.to_string(),
            points: cost,
        }],
        "stator DOFs",
        "wall time per step (µs)",
    )?;
    Ok(())
}

/// Draws `campbell.png`: ω_d of every tracked mode against the spin speed (rad/s), with the
/// 1× line ω = Ω.
pub fn write_campbell(
    out: &mut OutDir,
    title: &str,
    speeds: &[f64],
    res: &CampbellResults,
) -> Result<()> {
    let mut curves: Vec<Curve> = res
        .tracks
        .iter()
        .map(|t| Curve {
            label: t.label.clone(),
            points: speeds
                .iter()
                .zip(&t.omega_d)
                .map(|(s, w)| (*s, *w))
                .collect(),
        })
        .collect();
    curves.push(Curve {
        label: "1× (ω = Ω)".into(),
        points: vec![
            (speeds[0], speeds[0]),
            (
                *speeds.last().unwrap_or(&0.0),
                *speeds.last().unwrap_or(&0.0),
            ),
        ],
    });
    let p = out.stage("campbell.png")?;
    plot::lines(
        &p,
        &format!("{title} — Campbell diagram"),
        &curves,
        "spin speed Ω (rad/s)",
        "damped natural frequency ω_d (rad/s)",
    )?;
    Ok(())
}

/// Draws the unbalance response at `nodes`: `bode_amplitude.png` (major semi-axis),
/// `bode_phase.png` (phase of x) and `polar.png` (x in the complex plane).
pub fn write_unbalance(
    out: &mut OutDir,
    title: &str,
    nodes: &[usize],
    res: &[ResponsePoint],
) -> Result<()> {
    let per_node = |f: &dyn Fn(&ResponsePoint) -> (f64, f64)| -> Vec<Curve> {
        nodes
            .iter()
            .map(|n| Curve {
                label: format!("node {n}"),
                points: res.iter().filter(|r| r.node == *n).map(f).collect(),
            })
            .collect()
    };
    type Pick = fn(&ResponsePoint) -> (f64, f64);
    let figures: [(&str, &str, Pick, &str, &str); 3] = [
        (
            "bode_amplitude.png",
            "unbalance response (major semi-axis)",
            |r| (r.speed, r.major),
            "Ω (rad/s)",
            "amplitude (m)",
        ),
        (
            "bode_phase.png",
            "phase of x",
            |r| (r.speed, r.x_phase_deg),
            "Ω (rad/s)",
            "phase (deg)",
        ),
        (
            "polar.png",
            "polar plot of x",
            |r| (r.x_re, r.x_im),
            "Re x (m)",
            "Im x (m)",
        ),
    ];
    for (file, what, pick, xl, yl) in figures {
        let p = out.stage(file)?;
        plot::lines(&p, &format!("{title} — {what}"), &per_node(&pick), xl, yl)?;
    }
    Ok(())
}

/// A map's pictures (`rubsim map`), added to `draw`: `regime_map.png` (cells coloured by
/// regime class, [`crate::analysis::REGIME_CLASSES`]), `orbit_size_map.png` and
/// `contact_force_map.png` (values with contour lines); `runs[iy][ix]` is the run at
/// `(xs[ix], ys[iy])`.
///
/// # Errors
/// A name that cannot be staged ([`Drawings::add`]).
pub fn map_drawings<'a>(
    out: &mut OutDir,
    title: &str,
    grid: plot::MapGrid<'a>,
    runs: &[Vec<&SpeedResults>],
    draw: &mut Drawings<'a>,
) -> Result<()> {
    let classes: Vec<Vec<usize>> = runs
        .iter()
        .map(|row| {
            row.iter()
                .map(|r| crate::analysis::regime_class(r))
                .collect()
        })
        .collect();
    let t = format!("{title} — regime map (Poincaré period)");
    draw.add(out, "regime_map.png", move |p| {
        plot::category_map(p, &t, grid, &classes, &crate::analysis::REGIME_CLASSES)
    })?;
    let field = |f: &dyn Fn(&SpeedResults) -> f64| -> Vec<Vec<f64>> {
        runs.iter()
            .map(|row| row.iter().map(|r| f(r)).collect())
            .collect()
    };
    let (t, size) = (
        format!("{title} — orbit size"),
        field(&super::csv::orbit_size_nd),
    );
    draw.add(out, "orbit_size_map.png", move |p| {
        plot::field_map(p, &t, grid, &size, "orbit size / |Z0|", 8)
    })?;
    let (t, force) = (
        format!("{title} — peak contact force"),
        field(&|r| r.contact_force_max_nd),
    );
    draw.add(out, "contact_force_map.png", move |p| {
        plot::field_map(p, &t, grid, &force, "F_max / (m_u e ω²)", 8)
    })
}
