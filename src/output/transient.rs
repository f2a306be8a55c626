//! The tables and pictures of a speed transient (`rubsim run` with `[run.speed_profile]`).
//!
//! CSV (SI units, speeds also as ω/ω_n):
//! * `speed_history.csv` — `t_s, omega_rad_s, speed_ratio, phi_rad, omega_dot_rad_s2` per
//!   recorded sample; a driven rotor's also `drive_torque_nm, friction_torque_nm` (the drive
//!   T_d and the rub's Σ R μ p);
//! * `response.csv` — `t_s, speed_ratio, x_m, y_m, contact_force_n, friction_power_w,
//!   friction_energy_j` per recorded sample (the analysed node; the force on station 0; the
//!   friction summed over the stations);
//! * `orders.csv` — per order-tracking window (one per revolution): `t_s, omega_rad_s,
//!   speed_ratio`, then `amp_<k>_m, phase_<k>_rad` per tracked order k (`x ≈ A cos(kφ + ψ)`),
//!   then `steady_1x_m, steady_1x_phase_rad`, the steady unbalance response at the same speed
//!   (the run-up Bode's reference).
//!
//! * `orbit_snapshots.csv` (scenes with `output.snapshot_speeds`) — per recorded sample of
//!   each snapshot: `speed_ratio_target, pass, direction, t_s, speed_ratio, x_m, y_m`
//!   (`direction` is `up` or `down`; see [`crate::analysis::orbit_snapshots`]).
//!
//! PNG: `orbit_snapshots.png` (one orbit panel per speed and passage, in units of the steady
//! |Z0| at that speed), `speed_history.png`, `bode.png` (tracked 1× amplitude and phase against speed beside
//! the steady response), `orders.png`, `response.png` (the response's envelope against speed),
//! `contact_force.png` (its peak against speed) and `friction_energy.png` (against time).

use super::OutDir;
use crate::analysis::{OrbitSnapshot, TransientResults, SNAPSHOT_REVOLUTIONS};
use crate::error::Result;
use crate::model::Case;
use crate::plot::{self, Boundary, Curve, OrbitPanel};

/// Writes the three CSV tables of a transient.
pub fn write_csv(out: &mut OutDir, r: &TransientResults) -> Result<()> {
    let wn = r.omega_n;
    let driven = !r.torque.is_empty();
    let mut s = String::from("t_s,omega_rad_s,speed_ratio,phi_rad,omega_dot_rad_s2");
    s.push_str(if driven {
        ",drive_torque_nm,friction_torque_nm\n"
    } else {
        "\n"
    });
    for (i, v) in r.spin.iter().enumerate() {
        s.push_str(&format!(
            "{:.9e},{:.9e},{:.6},{:.9e},{:.6e}",
            v[0],
            v[1],
            v[1] / wn,
            v[2],
            v[3]
        ));
        match r.torque.get(i) {
            Some(t) => s.push_str(&format!(",{:.9e},{:.9e}\n", t[0], t[1])),
            None => s.push('\n'),
        }
    }
    out.write("speed_history.csv", s.as_bytes())?;
    let mut s = String::from(
        "t_s,speed_ratio,x_m,y_m,contact_force_n,friction_power_w,friction_energy_j\n",
    );
    for ((v, u), c) in r.spin.iter().zip(&r.response).zip(&r.contact) {
        s.push_str(&format!(
            "{:.9e},{:.6},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e}\n",
            v[0],
            v[1] / wn,
            u[0],
            u[1],
            c[0],
            c[1],
            c[2]
        ));
    }
    out.write("response.csv", s.as_bytes())?;
    let mut s = String::from("t_s,omega_rad_s,speed_ratio");
    for o in &r.orders {
        let k = order_name(*o);
        s.push_str(&format!(",amp_{k}_m,phase_{k}_rad"));
    }
    s.push_str(",steady_1x_m,steady_1x_phase_rad\n");
    for w in &r.windows {
        s.push_str(&format!("{:.9e},{:.6e},{:.6}", w.t, w.omega, w.omega / wn));
        for (a, p) in &w.lines {
            s.push_str(&format!(",{a:.6e},{p:.6}"));
        }
        s.push_str(&format!(",{:.6e},{:.6}\n", w.steady_1x.0, w.steady_1x.1));
    }
    out.write("orders.csv", s.as_bytes())
}

/// Writes `orbit_snapshots.csv` and, with `png`, `orbit_snapshots.png` (see the module); the
/// panels show the first stator's boundary at `case`'s clearance (the run's initial one).
pub fn write_snapshots(
    out: &mut OutDir,
    title: &str,
    snaps: &[OrbitSnapshot],
    case: &Case,
    png: bool,
) -> Result<()> {
    let mut s = String::from("speed_ratio_target,pass,direction,t_s,speed_ratio,x_m,y_m\n");
    for sn in snaps {
        let dir = if sn.up { "up" } else { "down" };
        for v in &sn.samples {
            s.push_str(&format!(
                "{},{},{dir},{:.9e},{:.6},{:.6e},{:.6e}\n",
                sn.target, sn.pass, v[0], v[1], v[2], v[3]
            ));
        }
    }
    out.write("orbit_snapshots.csv", s.as_bytes())?;
    if !png {
        return Ok(());
    }
    let panels: Vec<OrbitPanel> = snaps
        .iter()
        .map(|sn| {
            let z = if sn.z0 > 0.0 { sn.z0 } else { 1.0 };
            // `boundary` is in units of the case's |Z0(Ω_ref)|; the panel's unit is |Z0(Ω)|.
            let k = if case.z0 > 0.0 { case.z0 / z } else { 1.0 / z };
            let boundary = match super::figures::boundary(case) {
                Boundary::Line {
                    angle_deg,
                    distance,
                } => Boundary::Line {
                    angle_deg,
                    distance: distance * k,
                },
                Boundary::Circle { radius } => Boundary::Circle { radius: radius * k },
                Boundary::None => Boundary::None,
            };
            OrbitPanel {
                title: format!(
                    "ω/ωn = {} {} (pass {}, t = {:.3} s)",
                    sn.target,
                    if sn.up { "↑" } else { "↓" },
                    sn.pass,
                    sn.t
                ),
                x: sn.samples.iter().map(|v| v[2] / z).collect(),
                y: sn.samples.iter().map(|v| v[3] / z).collect(),
                boundary,
                poincare: Vec::new(),
            }
        })
        .collect();
    let p = out.stage("orbit_snapshots.png")?;
    plot::orbit_grid(
        &p,
        &format!(
            "{title} — orbit snapshots ({SNAPSHOT_REVOLUTIONS} revolutions; |Z0| at each speed)"
        ),
        &panels,
        3,
    )
}

/// A column name for order `o`: `1x`, `0.5x`, `0.3333x`, `2x`.
fn order_name(o: f64) -> String {
    let s = format!("{o:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    format!("{s}x")
}

/// Points of a curve.
type Polyline = Vec<(f64, f64)>;

/// At most `bins` points of `(x, y)` (x nondecreasing or not): the largest and smallest y in
/// each of `bins` equal x-intervals, in x order — the envelope a dense oscillation fills.
pub(super) fn envelope(points: &[(f64, f64)], bins: usize) -> (Polyline, Polyline) {
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
    if points.is_empty() || hi <= lo {
        return (points.to_vec(), points.to_vec());
    }
    let mut mx = vec![(f64::NAN, f64::NEG_INFINITY); bins];
    let mut mn = vec![(f64::NAN, f64::INFINITY); bins];
    for &(x, y) in points {
        let b = (((x - lo) / (hi - lo)) * bins as f64).min(bins as f64 - 1.0) as usize;
        let xc = lo + (b as f64 + 0.5) * (hi - lo) / bins as f64;
        if y > mx[b].1 {
            mx[b] = (xc, y);
        }
        if y < mn[b].1 {
            mn[b] = (xc, y);
        }
    }
    let keep = |v: Vec<(f64, f64)>| v.into_iter().filter(|p| p.0.is_finite()).collect();
    (keep(mx), keep(mn))
}

/// The curve of `f` per window against Ω/ω_n, split into the run-up (Ω̇ ≥ 0) and the
/// coast-down (Ω̇ < 0) — each present only when the profile has it; a break (NaN) where
/// the direction changes, so a profile that goes up and down draws both branches of the
/// hysteresis on one figure.
fn by_direction(
    r: &TransientResults,
    what: &str,
    f: impl Fn(&crate::analysis::OrderWindow) -> f64,
) -> Vec<Curve> {
    let mut up = Vec::new();
    let mut down = Vec::new();
    let mut last_up = None;
    for w in &r.windows {
        let is_up = w.omega_dot >= 0.0;
        let (this, other) = if is_up {
            (&mut up, &mut down)
        } else {
            (&mut down, &mut up)
        };
        if last_up == Some(!is_up) {
            other.push((f64::NAN, f64::NAN));
        }
        this.push((w.omega / r.omega_n, f(w)));
        last_up = Some(is_up);
    }
    let mut curves = Vec::new();
    for (label, pts) in [("run-up", up), ("coast-down", down)] {
        if pts.iter().any(|p| p.0.is_finite()) {
            curves.push(Curve {
                label: format!("{what}, {label}"),
                points: pts,
            });
        }
    }
    curves
}

/// Draws the pictures of a transient (see the module); `component` names the analysed
/// component (`"x"` or `"y"`).
pub fn write_figures(
    out: &mut OutDir,
    title: &str,
    r: &TransientResults,
    component: &str,
) -> Result<()> {
    let wn = r.omega_n;
    let nu = |w: f64| w / wn;
    let p = out.stage("speed_history.png")?;
    let (hist, _) = envelope(
        &r.spin.iter().map(|v| (v[0], nu(v[1]))).collect::<Vec<_>>(),
        2000,
    );
    plot::lines(
        &p,
        &format!("{title} — speed history"),
        &[Curve {
            label: String::new(),
            points: hist,
        }],
        "t (s)",
        "Ω / ωn",
    )?;
    write_tracking(out, title, r, component)?;
    write_envelopes(out, title, r, component)?;
    Ok(())
}

/// `bode.png`, `bode_phase.png` and `orders.png`: the tracked 1× (amplitude and phase, with
/// the steady unbalance response) and every tracked order against Ω/ω_n.
fn write_tracking(
    out: &mut OutDir,
    title: &str,
    r: &TransientResults,
    component: &str,
) -> Result<()> {
    let wn = r.omega_n;
    let nu = |w: f64| w / wn;
    let p = out.stage("bode.png")?;
    let mut curves = by_direction(r, "1×", |w| w.lines[0].0);
    curves.push(Curve {
        label: "steady unbalance response".into(),
        points: r
            .windows
            .iter()
            .map(|w| (nu(w.omega), w.steady_1x.0))
            .collect(),
    });
    plot::lines(
        &p,
        &format!("{title} — Bode: tracked 1× of {component} against speed"),
        &curves,
        "Ω / ωn",
        "1× amplitude (m)",
    )?;
    let p = out.stage("bode_phase.png")?;
    let mut curves = by_direction(r, "1×", |w| w.lines[0].1.to_degrees());
    curves.push(Curve {
        label: "steady unbalance response".into(),
        points: r
            .windows
            .iter()
            .map(|w| (nu(w.omega), w.steady_1x.1.to_degrees()))
            .collect(),
    });
    plot::lines(
        &p,
        &format!("{title} — Bode: 1× phase of {component}"),
        &curves,
        "Ω / ωn",
        "phase (deg)",
    )?;
    let p = out.stage("orders.png")?;
    let curves: Vec<Curve> = r
        .orders
        .iter()
        .enumerate()
        .flat_map(|(i, o)| by_direction(r, &order_name(*o), move |w| w.lines[i].0))
        .collect();
    plot::lines(
        &p,
        &format!("{title} — order tracking of {component}"),
        &curves,
        "Ω / ωn",
        "amplitude (m)",
    )?;
    Ok(())
}

/// `response.png`, `contact_force.png` and `friction_energy.png`: the envelope of the response
/// and the peak contact force per speed bin against Ω/ω_n, the friction energy against time.
fn write_envelopes(
    out: &mut OutDir,
    title: &str,
    r: &TransientResults,
    component: &str,
) -> Result<()> {
    let wn = r.omega_n;
    let nu = |w: f64| w / wn;
    let c = r.component.min(1);
    let (hi, lo) = envelope(
        &r.spin
            .iter()
            .zip(&r.response)
            .map(|(v, u)| (nu(v[1]), u[c]))
            .collect::<Vec<_>>(),
        1500,
    );
    let p = out.stage("response.png")?;
    plot::lines(
        &p,
        &format!("{title} — {component} against speed (envelope)"),
        &[
            Curve {
                label: format!("max {component}"),
                points: hi,
            },
            Curve {
                label: format!("min {component}"),
                points: lo,
            },
        ],
        "Ω / ωn",
        &format!("{component} (m)"),
    )?;
    let (fmax, _) = envelope(
        &r.spin
            .iter()
            .zip(&r.contact)
            .map(|(v, f)| (nu(v[1]), f[0]))
            .collect::<Vec<_>>(),
        1500,
    );
    let p = out.stage("contact_force.png")?;
    plot::lines(
        &p,
        &format!("{title} — contact force against speed (peak per speed bin)"),
        &[Curve {
            label: String::new(),
            points: fmax,
        }],
        "Ω / ωn",
        "|F| (N)",
    )?;
    let (energy, _) = envelope(
        &r.spin
            .iter()
            .zip(&r.contact)
            .map(|(v, f)| (v[0], f[2]))
            .collect::<Vec<_>>(),
        1500,
    );
    let p = out.stage("friction_energy.png")?;
    plot::lines(
        &p,
        &format!("{title} — friction energy dissipated"),
        &[Curve {
            label: String::new(),
            points: energy,
        }],
        "t (s)",
        "energy (J)",
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_names_and_envelope() {
        assert_eq!(order_name(1.0), "1x");
        assert_eq!(order_name(0.5), "0.5x");
        assert_eq!(order_name(1.0 / 3.0), "0.3333x");
        // 200 rad of a sine, 0.01 rad apart: every bin of 20 rad holds whole periods.
        let pts: Vec<(f64, f64)> = (0..20_000)
            .map(|i| (i as f64, (i as f64 * 0.01).sin()))
            .collect();
        let (hi, lo) = envelope(&pts, 10);
        assert_eq!(hi.len(), 10);
        assert!(hi.iter().all(|p| p.1 > 0.99) && lo.iter().all(|p| p.1 < -0.99));
    }
}
