//! `rubsim modal`, `rubsim campbell`, `rubsim unbalance`: linear rotordynamics of the rotor
//! alone (no stator), written as CSV, summary.json and PNG.

use super::{default_out, finish, load, summary_base, Common};
use anyhow::{Context, Result};
use rubsim::analysis::rotordyn;
use rubsim::output::OutDir;
use rubsim::plot::{self, Curve};
use std::path::PathBuf;

fn speed_list(from: f64, to: f64, points: usize) -> Vec<f64> {
    let n = points.max(2);
    (0..n)
        .map(|i| from + (to - from) * i as f64 / (n - 1) as f64)
        .collect()
}

/// Modes at one speed (ω/ω_n, default 0) and the static deflection under gravity.
pub fn modal(
    c: &Common,
    speed: f64,
    nmodes: usize,
    gravity: f64,
    out: Option<PathBuf>,
) -> Result<()> {
    let (ls, model) = load(c)?;
    let mut outd = OutDir::prepare(&out.unwrap_or_else(|| default_out(&c.scene).join("modal")))?;
    let wn = model.rotor.natural_frequency();
    let omega = speed * wn;
    let res = rotordyn::modal(&model.rotor, omega, nmodes)?;
    let stat = rotordyn::static_deflection(&model.rotor, gravity)?;
    println!("rotor: {}", model.rotor.describe());
    println!("modes at Ω = {omega:.4} rad/s (ω/ωn = {speed}):");
    println!(
        "  {:>4} {:>12} {:>10} {:>9} {:>9} {:>9}",
        "mode", "ω_d rad/s", "f Hz", "ζ", "log dec", "type"
    );
    // `whirl`: FW/BW/mixed, "-" for axial and torsional modes; `kind` and the kinetic-energy
    // shares say where the mode sits.
    let mut csv = String::from(
        "mode,omega_d_rad_s,freq_hz,damping_ratio,log_dec,whirl,kind,energy_lateral,energy_axial,energy_torsional\n",
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
        csv.push_str(&format!(
            "{},{:.8e},{:.8e},{:.6e},{:.6e},{},{},{:.6},{:.6},{:.6}\n",
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
        ));
    }
    outd.write("modes.csv", csv.as_bytes())?;
    let mut scsv = String::from("node,ux_m,uy_m\n");
    let mut ymax: f64 = 0.0;
    for i in 0..model.rotor.node_count() {
        let d = model.rotor.node_dofs(i);
        scsv.push_str(&format!("{i},{:.8e},{:.8e}\n", stat[d[0]], stat[d[1]]));
        ymax = ymax.max(stat[d[1]].abs());
    }
    println!("static deflection under g = {gravity} m/s²: largest |u_y| = {ymax:.4e} m");
    outd.write("static_deflection.csv", scsv.as_bytes())?;
    let mut sum = summary_base(&ls, &model, "modal");
    sum["modal"] = serde_json::to_value(&res)?;
    sum["static_deflection_max_m"] = ymax.into();
    finish(outd, &sum)
}

/// Campbell diagram from ω/ω_n `from` to `to`.
pub fn campbell(
    c: &Common,
    from: f64,
    to: f64,
    points: usize,
    nmodes: usize,
    out: Option<PathBuf>,
) -> Result<()> {
    let (ls, model) = load(c)?;
    let mut outd = OutDir::prepare(&out.unwrap_or_else(|| default_out(&c.scene).join("campbell")))?;
    let wn = model.rotor.natural_frequency();
    let speeds: Vec<f64> = speed_list(from * wn, to * wn, points);
    let res = rotordyn::campbell(&model.rotor, &speeds, nmodes)?;
    let mut csv = String::from("speed_rad_s");
    for t in &res.tracks {
        csv.push_str(&format!(
            ",{}_omega_d,{}_log_dec",
            t.label.replace(' ', "_"),
            t.label.replace(' ', "_")
        ));
    }
    csv.push('\n');
    for (i, s) in speeds.iter().enumerate() {
        csv.push_str(&format!("{s:.6e}"));
        for t in &res.tracks {
            csv.push_str(&format!(",{:.6e},{:.6e}", t.omega_d[i], t.log_dec[i]));
        }
        csv.push('\n');
    }
    outd.write("campbell.csv", csv.as_bytes())?;
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
    let p = outd.stage("campbell.png")?;
    plot::lines(
        &p,
        &format!("{} — Campbell diagram", ls.scene.title),
        &curves,
        "spin speed Ω (rad/s)",
        "damped natural frequency ω_d (rad/s)",
    )?;
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
    let mut sum = summary_base(&ls, &model, "campbell");
    sum["campbell"] = serde_json::to_value(&res)?;
    finish(outd, &sum)
}

/// Unbalance response (Bode and polar) at `nodes` (default: every station's node).
pub fn unbalance(
    c: &Common,
    from: f64,
    to: f64,
    points: usize,
    nodes: &[usize],
    out: Option<PathBuf>,
) -> Result<()> {
    let (ls, model) = load(c)?;
    let mut outd =
        OutDir::prepare(&out.unwrap_or_else(|| default_out(&c.scene).join("unbalance")))?;
    let wn = model.rotor.natural_frequency();
    let nodes: Vec<usize> = if nodes.is_empty() {
        let v: Vec<usize> = model.stations.iter().map(|s| s.node).collect();
        if v.is_empty() {
            vec![0]
        } else {
            v
        }
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
    let speeds = speed_list(from * wn, to * wn, points);
    let res = rotordyn::unbalance_response(&model.rotor, &speeds, &nodes)
        .context("unbalance response")?;
    let mut csv =
        String::from("speed_rad_s,node,x_amp_m,x_phase_deg,y_amp_m,y_phase_deg,major_m\n");
    for r in &res {
        csv.push_str(&format!(
            "{:.6e},{},{:.6e},{:.3},{:.6e},{:.3},{:.6e}\n",
            r.speed, r.node, r.x_amp, r.x_phase_deg, r.y_amp, r.y_phase_deg, r.major
        ));
    }
    outd.write("unbalance.csv", csv.as_bytes())?;
    let per_node = |f: &dyn Fn(&rotordyn::ResponsePoint) -> (f64, f64)| -> Vec<Curve> {
        nodes
            .iter()
            .map(|n| Curve {
                label: format!("node {n}"),
                points: res.iter().filter(|r| r.node == *n).map(f).collect(),
            })
            .collect()
    };
    let title = &ls.scene.title;
    type Pick = fn(&rotordyn::ResponsePoint) -> (f64, f64);
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
        let p = outd.stage(file)?;
        plot::lines(&p, &format!("{title} — {what}"), &per_node(&pick), xl, yl)?;
    }
    for n in &nodes {
        let (s, a) = res
            .iter()
            .filter(|r| r.node == *n)
            .map(|r| (r.speed, r.major))
            .fold((0.0, 0.0), |b, x| if x.1 > b.1 { x } else { b });
        println!("node {n}: peak amplitude {a:.4e} m at Ω = {s:.3} rad/s");
    }
    let mut sum = summary_base(&ls, &model, "unbalance");
    sum["unbalance_response"] = serde_json::to_value(&res)?;
    finish(outd, &sum)
}
