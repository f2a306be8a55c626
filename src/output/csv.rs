//! Every CSV table rubsim writes: `sweep.csv`, `convergence.csv`, `stress.csv`, `refine.csv`,
//! `modes.csv`, `mode_shapes.csv`, `static_deflection.csv`, `campbell.csv`, `unbalance.csv`,
//! `critical_map.csv` (the full spectra's tables are [`super::whirl`]'s).
//!
//! One header line, then one row per record; numbers in SI units (or the `_nd`
//! normalisations of [`crate::analysis`]), formatted with a fixed precision per column.
//! `docs/OUTPUTS.md` lists the columns.

use super::OutDir;
use crate::analysis::refine::RefinePoint;
use crate::analysis::{ConvergenceResults, SpeedResults, StressResults, SweepResults};
use crate::error::Result;
use crate::linear::campbell::CampbellResults;
use crate::linear::critical_map::CriticalMapResults;
use crate::linear::mode_shape::{ellipse, node_shape, RotorLine};
use crate::linear::modes::ModalResults;
use crate::linear::response::ResponsePoint;

/// A table: the header line, then one line per row.
fn table(header: &str, rows: impl IntoIterator<Item = String>) -> String {
    let mut csv = String::from(header);
    csv.push('\n');
    for r in rows {
        csv.push_str(&r);
        csv.push('\n');
    }
    csv
}

/// The `sweep.csv` header.
pub const SWEEP_HEADER: &str = "speed_ratio,period,x_min_nd,x_max_nd,y_min_nd,y_max_nd,amp_1x_nd,amp_half_nd,amp_third_nd,contact_force_max_nd,steps,wall_s,dt_s,steps_per_rev,z0_m,clearance_m,contact_fraction,min_gap_m,err_extents_rel,steady,transient_revolutions,transient_residual,period_confidence,lines_resolved,integrator_chosen,dt_scale,order_observed,error_predicted,fwd_1x_nd,bwd_1x_nd,whirl_order,whirl_amp_nd,whirl,regime,zero_one_k,long_period,coexisting,coexist_start,coexist_contact_fraction,coexist_period,coexist_extents_rel,coexisting_stable,stick_fraction,dry_rub";

/// One `sweep.csv` row.
pub fn sweep_row(r: &SpeedResults) -> String {
    format!(
        "{:.4},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{},{:.6},{:.6e},{},{:.6e},{:.6e},{:.4},{:.3e},{},{},{},{:.3e},{:.3e},{},{},{},{},{},{}",
        r.speed_ratio,
        r.period,
        r.extents_nd[0],
        r.extents_nd[1],
        r.extents_nd[2],
        r.extents_nd[3],
        r.amp_1x_nd,
        r.amp_half_nd,
        r.amp_third_nd,
        r.contact_force_max_nd,
        r.stats.steps,
        r.stats.wall_s,
        r.plan.dt,
        r.plan.steps_per_rev,
        r.z0,
        r.clearances.first().copied().unwrap_or(f64::NAN),
        r.contact_fraction,
        r.stats.min_gap,
        r.error
            .map(|e| format!("{:.3e}", e.extents_rel))
            .unwrap_or_default(),
        r.steady,
        r.transient_revolutions,
        r.stationarity.residual,
        r.classification.confidence,
        r.lines_resolved,
        r.step_choice
            .map(|c| format!(
                "{},{:.4},{:.3},{:.3e}",
                c.integrator.name(),
                c.dt_scale,
                c.order_observed,
                c.error_predicted
            ))
            .unwrap_or_else(|| ",,,".into()),
        whirl_columns(r),
        dynamics_columns(r),
        coexist_columns(r),
        stick_columns(r),
    )
}

/// The stick columns of `sweep.csv` and `map.csv` (`station.N.stick`; docs/STICK.md): the
/// fraction of the steady window's contact instants at which some pair stuck, and the
/// dry-friction class (`whirl`, `whip`); both empty for a run without stick, the class empty
/// for one that is not a backward whirl in full contact.
pub fn stick_columns(r: &SpeedResults) -> String {
    stick_cells(r.stick_fraction, r.dry_rub)
}

/// The two cells `stick_fraction,dry_rub` of a steady window or a transient's window: the
/// fraction to four decimals and the class's key, each empty when `None`.
pub fn stick_cells(
    stick_fraction: Option<f64>,
    dry_rub: Option<crate::analysis::dry::DryRub>,
) -> String {
    format!(
        "{},{}",
        stick_fraction
            .map(|f| format!("{f:.4}"))
            .unwrap_or_default(),
        dry_rub.map_or("", |d| d.key())
    )
}

/// The coexistence columns of `sweep.csv` and `map.csv` ([`crate::analysis::coexist`]): whether
/// the check found another response (`true`, `false`; empty when it was not run), where its
/// companion started (`free`, `full_contact`), the companion's contact fraction and period,
/// the two responses' extents difference over the run's largest |extent|, and at a flagged
/// speed the number of stable periodic responses its orbits found (`coexisting_stable`,
/// [`crate::analysis::coexist_orbits`]; empty elsewhere).
pub fn coexist_columns(r: &SpeedResults) -> String {
    match &r.coexistence {
        Some(c) => format!(
            "{},{},{:.4},{},{:.3e},{}",
            c.coexisting,
            c.start.name(),
            c.contact_fraction,
            c.period,
            c.extents_rel,
            c.orbits
                .as_ref()
                .map_or(String::new(), |o| o.coexisting_stable.to_string())
        ),
        None => ",,,,,".into(),
    }
}

/// The regime columns of `sweep.csv` and `map.csv` ([`crate::analysis::dynamics`]): `periodic`,
/// `quasi-periodic`, `chaotic` or `undetermined`; the 0–1 test's median K (empty when not
/// computed); a period above 8 found on the Poincaré points (empty when none).
pub fn dynamics_columns(r: &SpeedResults) -> String {
    let d = &r.dynamics;
    format!(
        "{},{},{}",
        d.regime.name(),
        d.zero_one_k.map(|k| format!("{k:.4}")).unwrap_or_default(),
        d.long_period.map(|q| q.to_string()).unwrap_or_default()
    )
}

/// The whirl columns of `sweep.csv` and `map.csv`: forward and backward 1× / |Z0|, the signed
/// order f/Ω and amplitude / |Z0| of the dominant line, and its sense (`forward`, `backward`,
/// `no_whirl`).
pub fn whirl_columns(r: &SpeedResults) -> String {
    let w = &r.whirl;
    format!(
        "{:.6},{:.6},{:.6},{:.6},{}",
        w.forward_1x_nd,
        w.backward_1x_nd,
        w.dominant_order,
        w.dominant_nd,
        w.direction.name()
    )
}

/// Writes `prefix + sweep.csv`: [`SWEEP_HEADER`], one [`sweep_row`] per speed.
pub fn write_sweep(out: &mut OutDir, prefix: &str, res: &SweepResults) -> Result<()> {
    let csv = table(SWEEP_HEADER, res.speeds.iter().map(sweep_row));
    out.write(&format!("{prefix}sweep.csv"), csv.as_bytes())
}

/// Writes `prefix + convergence.csv`: one row per point of the study.
pub fn write_convergence(out: &mut OutDir, prefix: &str, c: &ConvergenceResults) -> Result<()> {
    let csv = table(
        "speed_ratio,integrator,dt_s,dt_wn,steps_per_rev,orbit_err,extents_err,err_1x,err_half,err_third,period,wall_s,steps",
        c.points.iter().map(|p| (p, "")).chain(c.chosen.iter().map(|p| (p, "chosen "))).map(|(p, tag)| {
            format!(
                "{},{tag}{},{:.6e},{:.6e},{},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{},{:.6},{}",
                c.speed_ratio,
                p.integrator,
                p.dt,
                p.dt_wn,
                p.steps_per_rev,
                p.orbit_err,
                p.extents_err,
                p.lines_err[0],
                p.lines_err[1],
                p.lines_err[2],
                p.period,
                p.wall_s,
                p.steps
            )
        }),
    );
    out.write(&format!("{prefix}convergence.csv"), csv.as_bytes())
}

/// Writes `stress.csv`: one row per sample of every stator's trace, speed after speed.
pub fn write_stress(out: &mut OutDir, runs: &[StressResults]) -> Result<()> {
    let rows = runs.iter().flat_map(|r| {
        let v = r.speed_ratio;
        r.traces.iter().flat_map(move |tr| {
            (0..tr.t.len()).map(move |i| {
                format!(
                    "{v},{},{:.9e},{:.6e},{:.6e},{:.6e},{}",
                    tr.stator, tr.t[i], tr.force[i], tr.stress[i], tr.strain[i], tr.element[i]
                )
            })
        })
    });
    let csv = table(
        "speed_ratio,stator,t_s,contact_force_N,stress_Pa,strain,element",
        rows,
    );
    out.write("stress.csv", csv.as_bytes())
}

/// Writes `refine.csv`: one row per refinement, `(value of the key, its run)`.
pub fn write_refine(out: &mut OutDir, points: &[(String, RefinePoint)]) -> Result<()> {
    let rows = points.iter().map(|(v, p)| {
        let r = &p.results;
        format!(
            "{v},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.4},{},{},{:.4},{:.3},{:.3}",
            p.targets,
            p.dofs,
            r.extents_nd[0],
            r.extents_nd[1],
            r.extents_nd[2],
            r.extents_nd[3],
            r.amp_1x_nd,
            r.contact_force_max_nd,
            p.ripple,
            r.period,
            r.stats.steps,
            r.stats.wall_s,
            p.us_per_step,
            p.setup_s
        )
    });
    let csv = table(
        "value,targets,dofs,x_min_nd,x_max_nd,y_min_nd,y_max_nd,amp_1x_nd,contact_force_max_nd,ripple,period,steps,wall_s,us_per_step,setup_s",
        rows,
    );
    out.write("refine.csv", csv.as_bytes())
}

/// Writes `modes.csv`: one row per mode. `whirl` is FW/BW/mixed, `-` for axial and torsional
/// modes; `kind` and the kinetic-energy shares say where the mode sits.
pub fn write_modes(out: &mut OutDir, res: &ModalResults) -> Result<()> {
    let rows = res.modes.iter().enumerate().map(|(i, m)| {
        format!(
            "{},{:.8e},{:.8e},{:.6e},{:.6e},{},{},{:.6},{:.6},{:.6}",
            i + 1,
            m.omega_d,
            m.freq_hz,
            m.damping_ratio,
            m.log_dec,
            m.whirl.label(),
            m.kind.label(),
            m.energy[0],
            m.energy[1],
            m.energy[2]
        )
    });
    let csv = table(
        "mode,omega_d_rad_s,freq_hz,damping_ratio,log_dec,whirl,kind,energy_lateral,energy_axial,energy_torsional",
        rows,
    );
    out.write("modes.csv", csv.as_bytes())
}

/// Writes `mode_shapes.csv`: one row per mode and node — the node's axial position (m), the
/// real and imaginary parts of its normalised shape `[u_x, u_y, θ_x, θ_y]` (the mode's largest
/// entry is 1; rotations in rad per unit of it) and its whirl ellipse (major and signed minor
/// semi-axes, positive forward; [`crate::linear::mode_shape::ellipse`]).
pub fn write_mode_shapes(out: &mut OutDir, res: &ModalResults, line: &RotorLine) -> Result<()> {
    let mut rows = Vec::new();
    for (i, m) in res.modes.iter().enumerate() {
        for (n, p) in node_shape(m).iter().enumerate() {
            let e = ellipse(p[0], p[1]);
            let mut row = format!(
                "{},{},{:.8e}",
                i + 1,
                n,
                line.z.get(n).copied().unwrap_or(0.0)
            );
            for c in p {
                row.push_str(&format!(",{:.10e},{:.10e}", c.re, c.im));
            }
            row.push_str(&format!(",{:.10e},{:.10e}", e.major, e.minor));
            rows.push(row);
        }
    }
    let csv = table(
        "mode,node,z_m,ux_re,ux_im,uy_re,uy_im,theta_x_re,theta_x_im,theta_y_re,theta_y_im,major,minor",
        rows,
    );
    out.write("mode_shapes.csv", csv.as_bytes())
}

/// Writes `critical_map.csv`: per swept bearing stiffness (N/m), the forward and then the
/// backward synchronous critical speeds (rad/s), lowest first (empty where there are fewer).
pub fn write_critical_map(out: &mut OutDir, res: &CriticalMapResults) -> Result<()> {
    let mut header = String::from("stiffness_n_m");
    for w in ["forward", "backward"] {
        for m in 1..=res.modes {
            header.push_str(&format!(",{w}_{m}_rad_s"));
        }
    }
    let num = |v: f64| {
        if v.is_finite() {
            format!("{v:.8e}")
        } else {
            String::new()
        }
    };
    let rows = res.stiffness.iter().zip(&res.speeds).map(|(k, c)| {
        let mut row = format!("{k:.6e}");
        for v in c.forward.iter().chain(&c.backward) {
            row.push(',');
            row.push_str(&num(*v));
        }
        row
    });
    out.write("critical_map.csv", table(&header, rows).as_bytes())
}

/// Writes `static_deflection.csv`: `[u_x, u_y]` (m) of every rotor node.
pub fn write_static_deflection(out: &mut OutDir, nodes: &[[f64; 2]]) -> Result<()> {
    let rows = nodes
        .iter()
        .enumerate()
        .map(|(i, u)| format!("{i},{:.8e},{:.8e}", u[0], u[1]));
    let csv = table("node,ux_m,uy_m", rows);
    out.write("static_deflection.csv", csv.as_bytes())
}

/// Writes `campbell.csv`: per spin speed (rad/s), ω_d and the log decrement of every tracked
/// mode.
pub fn write_campbell(out: &mut OutDir, speeds: &[f64], res: &CampbellResults) -> Result<()> {
    let mut header = String::from("speed_rad_s");
    for t in &res.tracks {
        header.push_str(&format!(
            ",{}_omega_d,{}_log_dec",
            t.label.replace(' ', "_"),
            t.label.replace(' ', "_")
        ));
    }
    let rows = speeds.iter().enumerate().map(|(i, s)| {
        let mut row = format!("{s:.6e}");
        for t in &res.tracks {
            row.push_str(&format!(",{:.6e},{:.6e}", t.omega_d[i], t.log_dec[i]));
        }
        row
    });
    let csv = table(&header, rows);
    out.write("campbell.csv", csv.as_bytes())
}

/// Writes `unbalance.csv`: one row per speed and node (10 significant digits, phases to 1e-6°).
pub fn write_unbalance(out: &mut OutDir, res: &[ResponsePoint]) -> Result<()> {
    let rows = res.iter().map(|r| {
        format!(
            "{:.9e},{},{:.9e},{:.6},{:.9e},{:.6},{:.9e}",
            r.speed, r.node, r.x_amp, r.x_phase_deg, r.y_amp, r.y_phase_deg, r.major
        )
    });
    let csv = table(
        "speed_rad_s,node,x_amp_m,x_phase_deg,y_amp_m,y_phase_deg,major_m",
        rows,
    );
    out.write("unbalance.csv", csv.as_bytes())
}

/// One cell of a map: its two parameter values and its run.
#[derive(Debug, Clone, Copy)]
pub struct MapCell<'a> {
    /// Value of the horizontal parameter.
    pub x: f64,
    /// Value of the vertical parameter.
    pub y: f64,
    /// The run.
    pub run: &'a SpeedResults,
}

/// The orbit size of a run: the larger of its horizontal and vertical extents, / |Z0|.
pub fn orbit_size_nd(r: &SpeedResults) -> f64 {
    (r.extents_nd[1] - r.extents_nd[0]).max(r.extents_nd[3] - r.extents_nd[2])
}

/// Writes `map.csv`: one row per cell — the two parameters (columns named by their keys; a
/// `speed_ratio` column besides when neither is the speed), the Poincaré period and regime
/// class ([`crate::analysis::REGIME_CLASSES`]), extents, orbit size ([`orbit_size_nd`]), line
/// amplitudes, contact fraction and peak force, the error estimate (relative extents error and
/// whether the companion run found the same period), the coexistence check
/// ([`coexist_columns`]), the steady-state proof (`steady`, the
/// transient residual, the period's confidence, whether the lines are resolved: as in
/// `sweep.csv`), steps and wall time, then the whirl columns ([`whirl_columns`]), the 0–1 test's K
/// and a period above 8 found on the Poincaré points ([`dynamics_columns`]).
pub fn write_map(out: &mut OutDir, keys: [&str; 2], cells: &[MapCell<'_>]) -> Result<()> {
    let speed_col = !keys.contains(&"speed_ratio");
    let header = format!(
        "{},{}{},period,regime,x_min_nd,x_max_nd,y_min_nd,y_max_nd,orbit_size_nd,amp_1x_nd,amp_half_nd,amp_third_nd,contact_fraction,contact_force_max_nd,err_extents_rel,err_same_period,coexisting,coexist_start,coexist_contact_fraction,coexist_period,coexist_extents_rel,coexisting_stable,steady,transient_residual,period_confidence,lines_resolved,steps,wall_s,fwd_1x_nd,bwd_1x_nd,whirl_order,whirl_amp_nd,whirl,zero_one_k,long_period,stick_fraction,dry_rub",
        keys[0],
        keys[1],
        if speed_col { ",speed_ratio" } else { "" }
    );
    let rows = cells.iter().map(|c| {
        let r = c.run;
        format!(
            "{},{}{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.4},{:.6},{},{},{},{},{:.3e},{:.3e},{},{},{:.6},{},{},{},{}",
            crate::scene::toml_number(c.x),
            crate::scene::toml_number(c.y),
            if speed_col {
                format!(",{}", crate::scene::toml_number(r.speed_ratio))
            } else {
                String::new()
            },
            r.period,
            crate::analysis::REGIME_CLASSES[crate::analysis::regime_class(r)],
            r.extents_nd[0],
            r.extents_nd[1],
            r.extents_nd[2],
            r.extents_nd[3],
            orbit_size_nd(r),
            r.amp_1x_nd,
            r.amp_half_nd,
            r.amp_third_nd,
            r.contact_fraction,
            r.contact_force_max_nd,
            r.error
                .map(|e| format!("{:.3e}", e.extents_rel))
                .unwrap_or_default(),
            r.error.map(|e| e.same_period.to_string()).unwrap_or_default(),
            coexist_columns(r),
            r.steady,
            r.stationarity.residual,
            r.classification.confidence,
            r.lines_resolved,
            r.stats.steps,
            r.stats.wall_s,
            whirl_columns(r),
            r.dynamics
                .zero_one_k
                .map(|k| format!("{k:.4}"))
                .unwrap_or_default(),
            r.dynamics
                .long_period
                .map(|q| q.to_string())
                .unwrap_or_default(),
            stick_columns(r)
        )
    });
    out.write("map.csv", table(&header, rows).as_bytes())
}
