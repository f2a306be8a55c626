//! The heat's side of the thermal spiral: the hot-spot model of a scene ([`HotSpot`]) with its
//! law for the section's temperature difference ([`HeatLaw`]: the two lags of
//! [`crate::scene::thermal`], or the section's conduction of [`crate::model::section`]), and
//! the heat's state that a coupling step advances exactly ([`Heat`]).

use crate::error::Result;
use crate::math::V2;
use crate::model::section::{Conduction, Section};
use serde::Serialize;

/// A conducting section's figures (summary.json's `thermal.section`, the console).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct SectionFacts {
    /// The steady ΔT per watt of the heat's first harmonic (K/W): the lags' G.
    pub steady_gain_k_per_w: f64,
    /// The slowest mode's time constant (s).
    pub slowest_time_s: f64,
    /// Radial elements.
    pub cells: usize,
}

impl SectionFacts {
    /// One line: the law and its figures.
    pub fn describe(&self) -> String {
        format!(
            "the section's conduction ({} radial elements): steady gain {:.4e} K/W, slowest time constant {:.4e} s",
            self.cells, self.steady_gain_k_per_w, self.slowest_time_s
        )
    }
}

impl HeatLaw {
    /// The law in one line: the lags' G, τ_h, τ_c, or the section's figures.
    ///
    /// # Errors
    /// As [`Section::new`].
    pub fn describe(&self) -> Result<String> {
        Ok(match self {
            Self::Lags(l) => format!(
                "the hot-spot lags: G = {:.4e} K/W, τ_h = {} s, τ_c = {} s",
                l.gain, l.heating_time, l.cooling_time
            ),
            Self::Conduction(c) => Heat::new(self, [0.0; 2])?
                .facts()
                .map_or_else(|| format!("{c:?}"), |f| f.describe()),
        })
    }
}

/// How the section's temperature difference ΔT follows the friction heat's first harmonic Q.
#[derive(Debug, Clone, Copy)]
pub enum HeatLaw {
    /// The hot-spot model's two lags (`gain`, `heating_time`, `cooling_time`).
    Lags(Lags),
    /// The section's conduction (`[thermal.conduction]`).
    Conduction(Conduction),
}

/// The two lags `τ_h S' = −S + G Q`, `τ_c ΔT' = −ΔT + S` (module docs of
/// [`crate::scene::thermal`]).
#[derive(Debug, Clone, Copy)]
pub struct Lags {
    /// G (K/W).
    pub gain: f64,
    /// τ_h (s).
    pub heating_time: f64,
    /// τ_c (s).
    pub cooling_time: f64,
}

/// The hot-spot model of a scene, resolved against its model.
#[derive(Debug, Clone, Copy)]
pub struct HotSpot {
    /// The heated station's index.
    pub station: usize,
    /// The Jeffcott disk's bow per kelvin of ΔT (m/K; NaN for an FE rotor, whose bow is
    /// computed from its curvature).
    pub bow_per_kelvin: f64,
    /// The curvature per kelvin α/D (1/(m·K)).
    pub curvature_per_kelvin: f64,
    /// The heated length a (m), centred at the station's node.
    pub heated_length: f64,
    /// The section's law: the two lags or the conduction.
    pub heat: HeatLaw,
    /// Machine time (s).
    pub duration: f64,
    /// Coupling step h (s); `None`: the chunk's own length.
    pub step: Option<f64>,
    /// Revolutions per chunk.
    pub revolutions: usize,
    /// Revolutions before the first coupling.
    pub settle_revolutions: usize,
    /// |ΔT| of a runaway (K).
    pub max_temperature_difference: f64,
    /// ΔT (and S) at t = 0 (K).
    pub initial: V2,
}

impl HotSpot {
    /// The hot-spot model of the scene `ls`: `[thermal]` with its station's index (default: the
    /// first station), the bow per kelvin of its rotor, and the run's transient revolutions as
    /// the default settling; `None` without `[thermal]`.
    pub fn of_scene(ls: &crate::scene::LoadedScene) -> Option<Self> {
        let spec = ls.scene.thermal.as_ref()?;
        let station = spec
            .station
            .as_ref()
            .and_then(|n| ls.scene.stations.iter().position(|s| &s.name == n))
            .unwrap_or(0);
        let settle = ls.scene.run.transient_revolutions;
        Some(Self {
            station,
            bow_per_kelvin: spec.bow_per_kelvin(&ls.scene.rotor),
            curvature_per_kelvin: spec.expansion / spec.diameter,
            heated_length: spec.heated_length,
            heat: law(spec),
            duration: spec.duration,
            step: spec.step,
            revolutions: spec.revolutions,
            settle_revolutions: spec.settle_revolutions.unwrap_or(settle).max(1),
            max_temperature_difference: spec.max_temperature_difference,
            initial: spec.initial,
        })
    }
}

/// The section's law of the scene's `[thermal]` (validated: the three lags, or the
/// conduction).
fn law(spec: &crate::scene::thermal::ThermalSpec) -> HeatLaw {
    match &spec.conduction {
        Some(c) => HeatLaw::Conduction(Conduction {
            radius: 0.5 * spec.diameter,
            heated_length: spec.heated_length,
            conductivity: c.conductivity,
            heat_capacity: c.density * c.specific_heat,
            surface_coefficient: c.surface_coefficient,
            heat_fraction: c.heat_fraction,
            cells: c.cells,
        }),
        None => HeatLaw::Lags(Lags {
            gain: spec.gain.unwrap_or(f64::NAN),
            heating_time: spec.heating_time.unwrap_or(f64::NAN),
            cooling_time: spec.cooling_time.unwrap_or(f64::NAN),
        }),
    }
}

impl Lags {
    /// The heat's state `(S, ΔT)` after `h` seconds from `(s0, t0)` with the input
    /// `G (q0 + q1 t)` (W, W/s): the exact solution of the two lags (module docs of
    /// [`crate::scene::thermal`]), componentwise. With `S(t) = a + b t + d e^{−t/τ_h}`,
    /// `a = G q0 − τ_h G q1`, `b = G q1`, `d = S0 − a`:
    /// `ΔT(t) = a − τ_c b + b t + d τ_h/(τ_h − τ_c) e^{−t/τ_h} + C e^{−t/τ_c}` (the middle
    /// term `d (t/τ) e^{−t/τ}` when τ_h = τ_c = τ), C from ΔT(0) = t0.
    pub fn advance_linear(&self, (s0, t0): (V2, V2), (q0, q1): (V2, V2), h: f64) -> (V2, V2) {
        let (th, tc, g) = (self.heating_time, self.cooling_time, self.gain);
        let (eh, ec) = ((-h / th).exp(), (-h / tc).exp());
        let mut s = [0.0; 2];
        let mut t = [0.0; 2];
        for k in 0..2 {
            let (a, b) = (g * q0[k] - th * g * q1[k], g * q1[k]);
            let d = s0[k] - a;
            s[k] = a + b * h + d * eh;
            let ramp = a - tc * b;
            let (p0, ph) = if (th - tc).abs() > 1e-9 * th.max(tc) {
                let r = d * th / (th - tc);
                (r, r * eh)
            } else {
                (0.0, d * (h / tc) * ec)
            };
            t[k] = ramp + b * h + ph + (t0[k] - ramp - p0) * ec;
        }
        (s, t)
    }
}

/// The heat's state during a run: the lags' `(S, ΔT)`, or the section's modal coordinates.
#[derive(Debug, Clone)]
pub(super) enum Heat {
    /// `(lags, S, ΔT)`.
    Lags(Lags, V2, V2),
    /// The section's modes and their coordinates.
    Section(Box<Section>, Vec<V2>),
}

impl Heat {
    /// The state at t = 0: ΔT = `initial` (the lags' S equal to it; the section's profile the
    /// steady, linear one).
    ///
    /// # Errors
    /// As [`Section::new`].
    pub(super) fn new(law: &HeatLaw, initial: V2) -> Result<Self> {
        Ok(match law {
            HeatLaw::Lags(l) => Self::Lags(*l, initial, initial),
            HeatLaw::Conduction(c) => {
                let s = Section::new(c)?;
                let z = s.initial(initial);
                Self::Section(Box::new(s), z)
            }
        })
    }

    /// The conducting section's figures; `None` for the lags.
    pub(super) fn facts(&self) -> Option<SectionFacts> {
        match self {
            Self::Lags(..) => None,
            Self::Section(s, _) => Some(SectionFacts {
                steady_gain_k_per_w: s.transfer([0.0; 2])[0],
                slowest_time_s: s.slowest_time(),
                cells: s.modes(),
            }),
        }
    }

    /// ΔT (K, rotor frame).
    pub(super) fn delta_t(&self) -> V2 {
        match self {
            Self::Lags(_, _, t) => *t,
            Self::Section(s, z) => s.delta_t(z),
        }
    }

    /// The surface's state (K, rotor frame): the lags' S, the section's surface difference
    /// `2 T₁(R)`.
    pub(super) fn surface(&self) -> V2 {
        match self {
            Self::Lags(_, s, _) => *s,
            Self::Section(s, z) => s.surface(z),
        }
    }

    /// Advances the state over `h` seconds with the input `Q(t) = q0 + q1 t` (W, W/s), exactly.
    pub(super) fn advance(&mut self, q: (V2, V2), h: f64) {
        match self {
            Self::Lags(l, s, t) => (*s, *t) = l.advance_linear((*s, *t), q, h),
            Self::Section(sec, z) => sec.advance(z, q, h),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hot(th: f64, tc: f64) -> HotSpot {
        HotSpot {
            station: 0,
            bow_per_kelvin: 1e-6,
            curvature_per_kelvin: 1e-3,
            heated_length: 0.1,
            heat: HeatLaw::Lags(Lags {
                gain: 2.0,
                heating_time: th,
                cooling_time: tc,
            }),
            duration: 1.0,
            step: None,
            revolutions: 1,
            settle_revolutions: 1,
            max_temperature_difference: 100.0,
            initial: [0.0; 2],
        }
    }

    /// The exact lag update with a linear input agrees with many small steps of the ODEs, for
    /// distinct and for equal time constants, and composes: two steps of h/2 are one of h.
    #[test]
    fn the_two_lags_advance_exactly() {
        for (th, tc) in [(3.0, 7.0), (5.0, 5.0), (7.0, 3.0)] {
            let HeatLaw::Lags(hs) = hot(th, tc).heat else {
                unreachable!()
            };
            let (s0, t0, q, q1) = ([1.0, -2.0], [0.5, 0.25], [3.0, 1.0], [0.5, -0.75]);
            let (s1, t1) = hs.advance_linear((s0, t0), (q, q1), 4.0);
            let (mut s, mut t, mut tau) = (s0, t0, 0.0);
            let n = 400_000;
            let dt = 4.0 / n as f64;
            for _ in 0..n {
                // Midpoint (second order) steps.
                let f = |s: V2, t: V2, tau: f64| {
                    let u = [q[0] + q1[0] * tau, q[1] + q1[1] * tau];
                    let ds = [(hs.gain * u[0] - s[0]) / th, (hs.gain * u[1] - s[1]) / th];
                    let dtt = [(s[0] - t[0]) / tc, (s[1] - t[1]) / tc];
                    (ds, dtt)
                };
                let (a, b) = f(s, t, tau);
                let sm = [s[0] + 0.5 * dt * a[0], s[1] + 0.5 * dt * a[1]];
                let tm = [t[0] + 0.5 * dt * b[0], t[1] + 0.5 * dt * b[1]];
                let (a, b) = f(sm, tm, tau + 0.5 * dt);
                tau += dt;
                s = [s[0] + dt * a[0], s[1] + dt * a[1]];
                t = [t[0] + dt * b[0], t[1] + dt * b[1]];
            }
            for k in 0..2 {
                assert!((s1[k] - s[k]).abs() < 1e-9, "{th} {tc}: S {s1:?} {s:?}");
                assert!((t1[k] - t[k]).abs() < 1e-9, "{th} {tc}: ΔT {t1:?} {t:?}");
            }
            let q2 = [q[0] + 2.0 * q1[0], q[1] + 2.0 * q1[1]];
            let first = hs.advance_linear((s0, t0), (q, q1), 2.0);
            let half = hs.advance_linear(first, (q2, q1), 2.0);
            assert!((half.1[0] - t1[0]).abs() < 1e-12 && (half.1[1] - t1[1]).abs() < 1e-12);
        }
    }
}
