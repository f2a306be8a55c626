//! A driven rotor: the spin angle φ is a degree of freedom, moved by a drive torque against
//! the rotor's polar inertia and the resisting torques (`run.speed_profile.kind = "driven"`).
//!
//! The equation of the spin (about +z, Ω = φ̇ ≥ 0):
//!
//! `J φ̈ = T_d(t, Ω) − T₀ − c_t Ω − Σ_s R_s μ_s p_s − T_u`
//!
//! * `J` (kg·m²): `run.speed_profile.polar_inertia`, else the rotor's own
//!   ([`crate::model::Rotor::polar_inertia`]: the Jeffcott disk's `m D²/8`; an FE rotor's
//!   shaft elements `ρ I_p ℓ` and disks `I_p`);
//! * `T_d` (N·m): the drive — none, a constant, or a motor curve `T(Ω)` (linear between its
//!   points, held beyond them) — zero from `drive_off` on;
//! * `T₀ + c_t Ω` (N·m): the bearing drag, a constant and a viscous part;
//! * `R_s μ_s p_s`: the rub's friction torque at every contact pair — the tangential part
//!   `μ p` of the Lagrange multiplier times the station's radius `R` (the force `−(n + μa)p`
//!   on the rotor acts at `R n` from the section centre: `τ_z = R (n × (−μ a p))_z = −R μ p`
//!   for `a = ẑ × n`);
//! * `T_u = Σ m_u e (cos θ ü_y − sin θ ü_x)`, θ = φ + β the unbalance's angle, ü its node's
//!   acceleration: the reaction of the unbalance forces on the spin. With the unbalance's
//!   kinetic cross term `L_c = Σ m_u e φ̇ (cos θ u̇_y − sin θ u̇_x)` in the Lagrangian, the
//!   lateral equations get the unbalance force `m_u e (φ̇² cos θ + φ̈ sin θ, φ̇² sin θ − φ̈ cos θ)`
//!   ([`crate::model::RotorBody::add_unbalance_spin`]) and the spin equation `−T_u`; the
//!   energy `½u̇ᵀMu̇ + ½uᵀKu + ½JΩ² + L_c` then changes by the drive's work less the
//!   dissipation (damping, drag, friction), exactly in continuous time. The unbalance's own
//!   `m_u e²` (≪ J) and its mass in the lateral `M` are not added, as at constant speed.
//!
//! The discrete scheme (the same central differences as the lateral DOFs, `time::drive`) is
//! written on [`crate::time`]'s drive integrator and in `docs/VALIDATION.md`.

use super::Rotor;
use crate::error::ModelError;
use crate::scene::{ProfileKind, SpeedProfileSpec};

/// The drive torque's law.
#[derive(Debug, Clone, PartialEq)]
pub enum DriveLaw {
    /// No drive: a free coast-down.
    None,
    /// A constant torque (N·m, > 0 drives the spin about +z).
    Constant(f64),
    /// A motor curve `(Ω rad/s, T N·m)`, Ω strictly increasing; linear between the points,
    /// the end torques held beyond them.
    Curve(Vec<(f64, f64)>),
}

/// A driven rotor's spin data (see the module), SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct Drive {
    /// Polar inertia J (kg·m²), > 0.
    pub inertia: f64,
    /// Ω at t = 0 (rad/s), ≥ 0.
    pub speed0: f64,
    /// The run's length (s).
    pub duration: f64,
    /// The drive torque.
    pub law: DriveLaw,
    /// The time the drive is switched off (s); +∞ when never.
    pub off: f64,
    /// Constant drag T₀ (N·m, ≥ 0), acting while Ω > 0.
    pub drag: f64,
    /// Viscous drag c_t (N·m·s/rad, ≥ 0).
    pub drag_viscous: f64,
}

fn bad(key: &str, message: String) -> ModelError {
    ModelError::Inconsistent {
        what: format!("run.speed_profile.{key}"),
        message,
    }
}

impl Drive {
    /// The drive of a scene's driven profile `p` (speeds in `p.unit`, ω/ω_n with `omega_n`
    /// rad/s), the inertia from `p.polar_inertia` or `rotor`.
    ///
    /// # Errors
    /// [`ModelError::Inconsistent`] naming `run.speed_profile.<key>`: a profile that is not
    /// driven, no inertia (none given and none the rotor's geometry gives), a key missing or
    /// out of range (the scene's validation reports these first, with the key's line).
    pub fn from_spec(
        p: &SpeedProfileSpec,
        omega_n: f64,
        rotor: &Rotor,
    ) -> Result<Self, ModelError> {
        if p.kind != ProfileKind::Driven {
            return Err(bad("kind", "is not \"driven\"".into()));
        }
        let u = p.unit.to_rad_per_s(omega_n);
        let inertia = p.polar_inertia.or_else(|| rotor.polar_inertia()).ok_or_else(|| {
            bad(
                "polar_inertia",
                "a driven rotor needs its polar inertia (kg·m²): none is given and the rotor's geometry gives none".into(),
            )
        })?;
        if !(inertia.is_finite() && inertia > 0.0) {
            return Err(bad(
                "polar_inertia",
                format!("must be positive and finite, got {inertia}"),
            ));
        }
        let speed0 = u * p.speed.ok_or_else(|| bad("speed", "is missing".into()))?;
        let duration = p
            .duration
            .ok_or_else(|| bad("duration", "is missing".into()))?;
        if !(speed0.is_finite() && speed0 >= 0.0) {
            return Err(bad(
                "speed",
                format!("must be finite and ≥ 0, got {speed0} rad/s"),
            ));
        }
        if !(duration.is_finite() && duration > 0.0) {
            return Err(bad(
                "duration",
                format!("must be positive and finite, got {duration}"),
            ));
        }
        let law = match (p.drive_torque, &p.drive_curve) {
            (Some(t), None) => DriveLaw::Constant(t),
            (None, Some(c)) => {
                let pts: Vec<(f64, f64)> = c.iter().map(|[w, t]| (u * w, *t)).collect();
                let ok = pts.len() >= 2
                    && pts
                        .iter()
                        .all(|(w, t)| w.is_finite() && *w >= 0.0 && t.is_finite())
                    && pts.windows(2).all(|w| w[1].0 > w[0].0);
                if !ok {
                    return Err(bad(
                        "drive_curve",
                        "needs two or more [speed, torque] points, finite, speeds ≥ 0 and strictly increasing".into(),
                    ));
                }
                DriveLaw::Curve(pts)
            }
            (None, None) => DriveLaw::None,
            (Some(_), Some(_)) => {
                return Err(bad(
                    "drive_curve",
                    "give `drive_torque` or `drive_curve`, not both".into(),
                ))
            }
        };
        let off = p.drive_off.unwrap_or(f64::INFINITY);
        if off.is_nan() || off <= 0.0 {
            return Err(bad(
                "drive_off",
                format!("must be a positive time, got {off}"),
            ));
        }
        for (key, v) in [
            ("drag_torque", p.drag_torque),
            ("drag_coefficient", p.drag_coefficient),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(bad(key, format!("must be finite and ≥ 0, got {v}")));
            }
        }
        Ok(Self {
            inertia,
            speed0,
            duration,
            law,
            off,
            drag: p.drag_torque,
            drag_viscous: p.drag_coefficient,
        })
    }

    /// The drive torque T_d at time `t` (s) and speed `omega` (rad/s), N·m; 0 from `off` on.
    #[inline]
    pub fn drive_torque(&self, t: f64, omega: f64) -> f64 {
        if t >= self.off {
            return 0.0;
        }
        match &self.law {
            DriveLaw::None => 0.0,
            DriveLaw::Constant(c) => *c,
            DriveLaw::Curve(pts) => {
                let i = pts.partition_point(|(w, _)| *w <= omega);
                if i == 0 {
                    pts[0].1
                } else if i == pts.len() {
                    pts[i - 1].1
                } else {
                    let ((w0, t0), (w1, t1)) = (pts[i - 1], pts[i]);
                    t0 + (t1 - t0) * (omega - w0) / (w1 - w0)
                }
            }
        }
    }

    /// The largest drive torque over every speed (N·m): the bound of the run-up.
    fn max_torque(&self) -> f64 {
        match &self.law {
            DriveLaw::None => 0.0,
            DriveLaw::Constant(c) => *c,
            DriveLaw::Curve(pts) => pts.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max),
        }
    }

    /// An upper bound of Ω over the run (rad/s), the speed the step is planned for:
    /// `Ω₀ + max(T_d)⁺ t_on / J` (drag, friction and the drive's fall only lower it), and for
    /// a motor curve whose last torque is ≤ 0 not above the larger of Ω₀ and the curve's last
    /// speed (beyond it the drive brakes). The unbalance reaction torque oscillates about a
    /// resisting mean and is not bounded here: the stepper refuses a run whose speed passes
    /// 1.5 × this bound ([`crate::error::SolveError`]).
    pub fn speed_bound(&self) -> f64 {
        let t_on = self.off.min(self.duration);
        let by_torque = self.speed0 + self.max_torque().max(0.0) * t_on / self.inertia;
        match &self.law {
            DriveLaw::Curve(pts) if pts[pts.len() - 1].1 <= 0.0 => {
                by_torque.min(self.speed0.max(pts[pts.len() - 1].0))
            }
            _ => by_torque,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drive(law: DriveLaw, off: f64) -> Drive {
        Drive {
            inertia: 2.0,
            speed0: 10.0,
            duration: 5.0,
            law,
            off,
            drag: 0.0,
            drag_viscous: 0.0,
        }
    }

    #[test]
    fn motor_curve_interpolates_holds_and_switches_off() {
        let d = drive(
            DriveLaw::Curve(vec![(0.0, 8.0), (100.0, 4.0), (200.0, -1.0)]),
            3.0,
        );
        assert_eq!(d.drive_torque(0.0, 50.0), 6.0);
        assert_eq!(d.drive_torque(0.0, 150.0), 1.5);
        assert_eq!(d.drive_torque(0.0, 500.0), -1.0);
        assert_eq!(d.drive_torque(3.0, 50.0), 0.0);
        // Ω₀ + 8 · 3 / 2 = 22 below the curve's last speed.
        assert_eq!(d.speed_bound(), 22.0);
        let c = drive(DriveLaw::Constant(4.0), f64::INFINITY);
        assert_eq!(c.speed_bound(), 20.0);
    }
}
