//! Stator stress against time and speed in a speed transient (`rubsim run` with
//! `[run.speed_profile]` and a stator with elements: meshed, bars, frames).
//!
//! The largest element stress of each stator per recorded sample
//! ([`crate::analysis::StressProbe`] on the transient, [`TransientStress`]) goes to:
//! * `stress_history.csv` — `t_s, omega_rad_s, speed_ratio`, then per stator `<name>_stress_pa`
//!   (the element stress of largest magnitude: signed axial stress of a bar or frame, centroid
//!   von Mises stress of a continuum cell), `<name>_element` (its index, −1 when no element
//!   carries stress) and `<name>_force_n` (the total normal contact force Σ p on the stator);
//! * `stress_vs_speed.png` — the peak |stress| per speed bin against Ω/ω_n, one curve per
//!   stator; `stress_history.png` — the same against time.

use super::transient::envelope;
use super::OutDir;
use crate::analysis::{StressTrace, TransientResults};
use crate::error::Result;
use crate::plot::{self, Curve};
use serde::Serialize;

/// The stress histories of a transient, each sample with the spin speed of its instant.
#[derive(Debug, Clone, Serialize)]
pub struct TransientStress {
    /// ω_n (rad/s).
    pub omega_n: f64,
    /// Per sample: Ω (rad/s) at the trace's times (`traces[k].t`, the same for every stator).
    #[serde(skip)]
    pub omega: Vec<f64>,
    /// One trace per stator.
    #[serde(skip)]
    pub traces: Vec<StressTrace>,
    /// Per stator: its name, the largest |stress| (Pa), the time (s) and Ω/ω_n where it
    /// occurs, and the number of its nodes in contact at that instant.
    pub peaks: Vec<StressPeak>,
}

/// The largest stress of one stator over a transient.
#[derive(Debug, Clone, Serialize)]
pub struct StressPeak {
    /// Stator name.
    pub name: String,
    /// Largest |stress| (Pa).
    pub stress_pa: f64,
    /// Its time (s).
    pub t_s: f64,
    /// Ω/ω_n at that time.
    pub speed_ratio: f64,
    /// Stator nodes in contact at that time.
    pub contacts: usize,
}

impl TransientStress {
    /// The probe's `traces` of the transient `r`: Ω at each sample time from the transient's
    /// spin record (`r.spin`, `[t, Ω, φ, Ω̇]`), linear between its samples.
    pub fn new(r: &TransientResults, traces: Vec<StressTrace>) -> Self {
        let t = traces.first().map_or(&[][..], |tr| &tr.t[..]);
        let omega: Vec<f64> = t.iter().map(|&t| omega_at(&r.spin, t)).collect();
        let peaks = traces
            .iter()
            .map(|tr| StressPeak {
                name: tr.name.clone(),
                stress_pa: tr.peak_stress(),
                t_s: tr.peak_time,
                speed_ratio: omega_at(&r.spin, tr.peak_time) / r.omega_n,
                contacts: tr.peak_contacts.len(),
            })
            .collect();
        Self {
            omega_n: r.omega_n,
            omega,
            traces,
            peaks,
        }
    }

    /// Writes `stress_history.csv` (see the module).
    ///
    /// # Errors
    /// [`crate::error::Error::Output`] naming the file.
    pub fn write_csv(&self, out: &mut OutDir) -> Result<()> {
        let mut s = String::from("t_s,omega_rad_s,speed_ratio");
        for tr in &self.traces {
            let n = &tr.name;
            s.push_str(&format!(",{n}_stress_pa,{n}_element,{n}_force_n"));
        }
        s.push('\n');
        let t = self.traces.first().map_or(&[][..], |tr| &tr.t[..]);
        for (i, (&t, &w)) in t.iter().zip(&self.omega).enumerate() {
            s.push_str(&format!("{t:.9e},{w:.9e},{:.6}", w / self.omega_n));
            for tr in &self.traces {
                let e = tr.element[i];
                let e = if e == usize::MAX { -1 } else { e as i64 };
                // `+ 0.0`: an empty sum of forces is −0.
                s.push_str(&format!(
                    ",{:.6e},{e},{:.6e}",
                    tr.stress[i],
                    tr.force[i] + 0.0
                ));
            }
            s.push('\n');
        }
        out.write("stress_history.csv", s.as_bytes())
    }

    /// Draws `stress_vs_speed.png` and `stress_history.png` (see the module).
    ///
    /// # Errors
    /// [`crate::error::Error::Output`] naming the file.
    pub fn write_figures(&self, out: &mut OutDir, title: &str) -> Result<()> {
        let curves = |x: &dyn Fn(usize, f64) -> f64| -> Vec<Curve> {
            self.traces
                .iter()
                .map(|tr| {
                    let pts: Vec<(f64, f64)> = (tr.t.iter().enumerate())
                        .map(|(i, &t)| (x(i, t), tr.stress[i].abs()))
                        .collect();
                    Curve {
                        label: tr.name.clone(),
                        points: envelope(&pts, 1500).0,
                    }
                })
                .collect()
        };
        let p = out.stage("stress_vs_speed.png")?;
        plot::lines(
            &p,
            &format!("{title} — largest stator stress against speed (peak per speed bin)"),
            &curves(&|i, _| self.omega[i] / self.omega_n),
            "Ω / ωn",
            "|σ| max (Pa)",
        )?;
        let p = out.stage("stress_history.png")?;
        plot::lines(
            &p,
            &format!("{title} — largest stator stress against time"),
            &curves(&|_, t| t),
            "t (s)",
            "|σ| max (Pa)",
        )
    }
}

/// Ω (rad/s) at time `t` from `spin` (`[t, Ω, φ, Ω̇]` per sample, times increasing), linear
/// between samples, held beyond the ends; NaN when `spin` is empty or `t` is NaN.
fn omega_at(spin: &[[f64; 4]], t: f64) -> f64 {
    if spin.is_empty() || t.is_nan() {
        return f64::NAN;
    }
    let i = spin.partition_point(|s| s[0] < t);
    if i == 0 {
        return spin[0][1];
    }
    if i == spin.len() {
        return spin[i - 1][1];
    }
    let (a, b) = (spin[i - 1], spin[i]);
    let f = (t - a[0]) / (b[0] - a[0]);
    a[1] + f * (b[1] - a[1])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn omega_between_samples_is_linear_and_held_at_the_ends() {
        let spin = [[0.0, 10.0, 0.0, 0.0], [1.0, 20.0, 15.0, 0.0]];
        assert_eq!(omega_at(&spin, 0.25), 12.5);
        assert_eq!(omega_at(&spin, 1.0), 20.0);
        assert_eq!(omega_at(&spin, -1.0), 10.0);
        assert_eq!(omega_at(&spin, 2.0), 20.0);
        assert!(omega_at(&[], 0.5).is_nan());
    }
}
