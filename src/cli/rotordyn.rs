//! `rubsim modal`, `rubsim campbell`, `rubsim unbalance`, `rubsim critical-map`: linear
//! rotordynamics of the rotor alone (no stator), written as CSV, summary.json and PNG (and the
//! mode shapes as VTK and HDF5).

use super::{default_out, finish, load, Common, UnitArg};
use anyhow::{Context, Result};
use rubsim::linear::{self, mode_shape, ModalResults, RotorLine, Swept};
use rubsim::output::summary::{
    Base, CampbellBody, CriticalMapBody, ModalBody, Summary, UnbalanceBody,
};
use rubsim::output::{csv, figures, OutDir};
use rubsim::scene::SpeedUnit;
use std::path::PathBuf;

/// Modes at one speed (in its unit, default 0) and the static deflection under gravity.
pub fn modal(
    c: &Common,
    (speed, unit): (f64, UnitArg),
    nmodes: usize,
    gravity: f64,
    out: Option<PathBuf>,
) -> Result<()> {
    let (ls, model) = load(c)?;
    let mut outd = super::open_out(&out.unwrap_or_else(|| default_out(&c.scene).join("modal")))?;
    let wn = model.rotor.natural_frequency();
    let omega = unit.rad_per_s(speed, wn);
    let res = linear::modal(&model.rotor, omega, nmodes)?;
    let stat = linear::static_deflection(&model.rotor, gravity)?;
    println!("rotor: {}", model.rotor.describe());
    println!(
        "modes at Ω = {omega} rad/s ({} rpm, ω/ωn = {}):",
        SpeedUnit::rpm(omega),
        omega / wn
    );
    println!(
        "  {:>4} {:>12} {:>10} {:>9} {:>9} {:>9}",
        "mode", "ω_d rad/s", "f Hz", "ζ", "log dec", "type"
    );
    for (i, m) in res.modes.iter().enumerate() {
        println!(
            "  {:>4} {:>12.4} {:>10.4} {:>9.4} {:>9.4} {:>9}",
            i + 1,
            m.omega_d,
            m.freq_hz,
            m.damping_ratio,
            m.log_dec,
            m.label()
        );
    }
    for k in &res.rigid_body {
        println!(
            "  rigid-body mode (ω = 0): free {} DOFs (no support of positive stiffness)",
            k.label()
        );
    }
    csv::write_modes(&mut outd, &res)?;
    let line = mode_shape::rotor_line(&model.rotor);
    csv::write_mode_shapes(&mut outd, &res, &line)?;
    rubsim::output::rotordyn::write_mode_shapes(&mut outd, &ls.scene.title, &res, &line)?;
    write_mode_series(&mut outd, &res, &line)?;
    let nodes = linear::lateral_at_nodes(&model.rotor, &stat);
    let ymax = nodes.iter().fold(0.0_f64, |m, u| m.max(u[1].abs()));
    println!("static deflection under g = {gravity} m/s²: largest |u_y| = {ymax:.4e} m");
    csv::write_static_deflection(&mut outd, &nodes)?;
    let body = ModalBody {
        modal: &res,
        static_deflection_max_m: ymax,
    };
    let base = Base::new(&ls, &model, "modal");
    finish(outd, &Summary { base, body })
}

/// Campbell diagram from `from` to `to` (in their unit).
pub fn campbell(
    c: &Common,
    (from, to, unit): (f64, f64, UnitArg),
    points: usize,
    nmodes: usize,
    out: Option<PathBuf>,
) -> Result<()> {
    let (ls, model) = load(c)?;
    let mut outd = super::open_out(&out.unwrap_or_else(|| default_out(&c.scene).join("campbell")))?;
    let wn = model.rotor.natural_frequency();
    let speeds: Vec<f64> =
        linear::speed_list(unit.rad_per_s(from, wn), unit.rad_per_s(to, wn), points);
    let res = linear::campbell(&model.rotor, &speeds, nmodes)?;
    csv::write_campbell(&mut outd, &speeds, &res)?;
    figures::write_campbell(&mut outd, &ls.scene.title, &speeds, &res)?;
    println!(
        "Campbell diagram, Ω = {:.2} … {:.2} rad/s, {} speeds:",
        speeds[0],
        speeds[speeds.len() - 1],
        speeds.len()
    );
    for t in &res.tracks {
        println!(
            "  mode {:>9}: ω_d {:.3} → {:.3} rad/s",
            t.label,
            t.omega_d[0],
            t.omega_d[t.omega_d.len() - 1]
        );
    }
    for cs in &res.critical_speeds {
        println!(
            "  critical speed: mode {} at {:.3} rad/s ({:.1} rpm)",
            cs.mode, cs.speed, cs.rpm
        );
    }
    let body = CampbellBody { campbell: &res };
    let base = Base::new(&ls, &model, "campbell");
    finish(outd, &Summary { base, body })
}

/// Unbalance response (Bode and polar) at `nodes` (default: every station's node), from
/// `from` to `to` (in their unit).
pub fn unbalance(
    c: &Common,
    (from, to, unit): (f64, f64, UnitArg),
    points: usize,
    nodes: &[usize],
    out: Option<PathBuf>,
) -> Result<()> {
    let (ls, model) = load(c)?;
    let mut outd =
        super::open_out(&out.unwrap_or_else(|| default_out(&c.scene).join("unbalance")))?;
    let wn = model.rotor.natural_frequency();
    let nodes: Vec<usize> = if nodes.is_empty() {
        linear::default_response_nodes(&model)
    } else {
        nodes.to_vec()
    };
    for n in &nodes {
        if *n >= model.rotor.node_count() {
            anyhow::bail!(
                "--node {n} does not exist (the rotor has nodes 0..={})",
                model.rotor.node_count() - 1
            );
        }
    }
    let speeds = linear::speed_list(unit.rad_per_s(from, wn), unit.rad_per_s(to, wn), points);
    let res =
        linear::unbalance_response(&model.rotor, &speeds, &nodes).context("unbalance response")?;
    csv::write_unbalance(&mut outd, &res)?;
    figures::write_unbalance(&mut outd, &ls.scene.title, &nodes, &res)?;
    for n in &nodes {
        let (s, a) = linear::peak_response(&res, *n);
        println!("node {n}: peak amplitude {a:.4e} m at Ω = {s:.3} rad/s");
    }
    let body = UnbalanceBody {
        unbalance_response: &res,
    };
    let base = Base::new(&ls, &model, "unbalance");
    finish(outd, &Summary { base, body })
}

/// The mode shapes as VTK (`modes/mode_NN.vtu`, `.pvd` and frames) and, with the `hdf5`
/// feature, HDF5 (`modes/mode_NN.vtkhdf`).
fn write_mode_series(outd: &mut OutDir, res: &ModalResults, line: &RotorLine) -> Result<()> {
    for (i, m) in res.modes.iter().enumerate() {
        for (name, bytes) in rubsim::results::modes::vtk_files(line, m, i)? {
            outd.write(&name, &bytes)?;
        }
        #[cfg(feature = "hdf5")]
        {
            let name = format!("modes/{}.vtkhdf", rubsim::results::modes::mode_name(i));
            let p = outd.stage(&name)?;
            rubsim::results::mode_hdf5::write_mode(&p, line, m, i, res.speed)?;
        }
    }
    Ok(())
}

/// Undamped critical speed map over `points` bearing stiffnesses from `from` to `to` (N/m, log
/// spaced), all bearings together or only `bearing`.
pub fn critical_map(
    c: &Common,
    (from, to, points): (f64, f64, usize),
    nmodes: usize,
    bearing: Option<usize>,
    out: Option<PathBuf>,
) -> Result<()> {
    if !(from.is_finite() && to.is_finite() && from > 0.0 && to > from) {
        anyhow::bail!(
            "--from {from} --to {to}: the stiffness range must be positive and finite with --to > --from (N/m)"
        );
    }
    if nmodes == 0 {
        anyhow::bail!("--modes 0: ask for at least one critical speed");
    }
    let (ls, model) = load(c)?;
    let mut outd =
        super::open_out(&out.unwrap_or_else(|| default_out(&c.scene).join("critical_map")))?;
    let ks = linear::log_range(from, to, points);
    let swept = bearing.map_or(Swept::All, Swept::One);
    let res = linear::critical_map(&model.rotor, &ks, swept, nmodes)
        .with_context(|| format!("{}: critical speed map", c.scene.display()))?;
    csv::write_critical_map(&mut outd, &res)?;
    rubsim::output::rotordyn::write_critical_map(&mut outd, &ls.scene.title, &res)?;
    let what = match swept {
        Swept::All => "all bearings".to_string(),
        Swept::One(j) => format!("bearing {j}"),
    };
    println!(
        "undamped synchronous critical speeds (forward whirl, rad/s) against the stiffness of {what}:"
    );
    for (k, cs) in res.stiffness.iter().zip(&res.speeds) {
        let row: Vec<String> = cs.forward.iter().map(|v| format!("{v:12.4}")).collect();
        println!("  k = {k:10.4e} N/m: {}", row.join(" "));
    }
    for x in &res.crossings {
        println!(
            "  {} crosses forward mode {} at k = {:.4e} N/m, Ω = {:.3} rad/s ({:.1} rpm)",
            x.bearing,
            x.mode,
            x.stiffness,
            x.speed,
            x.speed * 30.0 / std::f64::consts::PI
        );
    }
    let body = CriticalMapBody { critical_map: &res };
    let base = Base::new(&ls, &model, "critical-map");
    finish(outd, &Summary { base, body })
}
