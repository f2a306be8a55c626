//! The spin speed of a transient run as a function of time: Ω(t), Ω̇(t) and the spin angle
//! φ(t) = ∫₀ᵗ Ω dτ.
//!
//! Conventions: Ω in rad/s, positive about +z (counter-clockwise seen from +z), never negative
//! (a profile does not reverse); t in s from the run's start; φ(0) = 0, so an unbalance of
//! phase β sits at the angle φ(t) + β from +x. Ω is piecewise cubic Hermite in t: straight
//! pieces for ramps (Ω̇ jumps where a ramp meets a hold), the monotone PCHIP of Fritsch &
//! Carlson for tables (C¹, and a table that only rises never overshoots). φ is the exact
//! integral of each piece, accumulated at the knots. Past the end the speed holds.

use crate::error::ModelError;
use crate::scene::{Interpolation, ProfileKind, SpeedProfileSpec};

/// One cubic piece on `[t0, t1]`: end speeds `w0`, `w1` (rad/s), end slopes `d0`, `d1`
/// (rad/s²), and the spin angle `phi0` at `t0` (rad).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Piece {
    t0: f64,
    t1: f64,
    w0: f64,
    w1: f64,
    d0: f64,
    d1: f64,
    phi0: f64,
}

impl Piece {
    /// Ω, Ω̇ and φ at `t` in the piece: with h = t1 − t0, s = (t − t0)/h,
    /// Ω = h00 w0 + h h10 d0 + h01 w1 + h h11 d1 (the cubic Hermite basis), Ω̇ = dΩ/ds / h and
    /// φ = phi0 + h ∫₀ˢ Ω ds' with ∫h00 = s − s³ + s⁴/2, ∫h10 = s²/2 − 2s³/3 + s⁴/4,
    /// ∫h01 = s³ − s⁴/2, ∫h11 = s⁴/4 − s³/3.
    #[inline]
    fn at(&self, t: f64) -> SpinState {
        let h = self.t1 - self.t0;
        let s = (t - self.t0) / h;
        let (s2, s3) = (s * s, s * s * s);
        let s4 = s2 * s2;
        let (a0, b0, a1, b1) = (self.w0, h * self.d0, self.w1, h * self.d1);
        let omega = (2.0 * s3 - 3.0 * s2 + 1.0) * a0
            + (s3 - 2.0 * s2 + s) * b0
            + (3.0 * s2 - 2.0 * s3) * a1
            + (s3 - s2) * b1;
        let dds = (6.0 * s2 - 6.0 * s) * (a0 - a1)
            + (3.0 * s2 - 4.0 * s + 1.0) * b0
            + (3.0 * s2 - 2.0 * s) * b1;
        let int = (s - s3 + 0.5 * s4) * a0
            + (0.5 * s2 - 2.0 / 3.0 * s3 + 0.25 * s4) * b0
            + (s3 - 0.5 * s4) * a1
            + (0.25 * s4 - s3 / 3.0) * b1;
        SpinState {
            phi: self.phi0 + h * int,
            omega,
            omega_dot: dds / h,
        }
    }
}

/// Ω(t) as a piecewise cubic with φ(t) integrated exactly (see the module).
#[derive(Debug, Clone, PartialEq)]
pub struct SpeedProfile {
    pieces: Vec<Piece>,
}

/// Ω, Ω̇ and φ at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SpinState {
    /// Spin angle φ (rad), φ(0) = 0.
    pub phi: f64,
    /// Spin speed Ω = φ̇ (rad/s), ≥ 0.
    pub omega: f64,
    /// Angular acceleration Ω̇ = φ̈ (rad/s²).
    pub omega_dot: f64,
}

fn bad(message: String) -> ModelError {
    ModelError::Inconsistent {
        what: "speed profile".into(),
        message,
    }
}

impl SpeedProfile {
    /// The profile of pieces `(t1, w1, d0, d1)` after the start `(0, w0)`: each piece runs from
    /// the previous end to `t1`, speed to `w1`, with slopes `d0`, `d1` at its ends.
    fn build(w0: f64, ends: &[(f64, f64, f64, f64)]) -> Result<Self, ModelError> {
        if ends.is_empty() {
            return Err(bad("needs at least two points".into()));
        }
        let (mut t0, mut w, mut phi0) = (0.0, w0, 0.0);
        let mut pieces = Vec::with_capacity(ends.len());
        for (i, &(t1, w1, d0, d1)) in ends.iter().enumerate() {
            if !(t1.is_finite() && w1.is_finite() && d0.is_finite() && d1.is_finite()) {
                return Err(bad(format!(
                    "point {} is not finite ({t1} s, {w1} rad/s)",
                    i + 1
                )));
            }
            if !(w.is_finite() && w >= 0.0 && w1 >= 0.0) {
                return Err(bad(format!(
                    "speeds must be finite and ≥ 0 (no reversal), got {w} and {w1} rad/s"
                )));
            }
            if t1 <= t0 {
                return Err(bad(format!(
                    "times must increase strictly: {t1} follows {t0}"
                )));
            }
            let p = Piece {
                t0,
                t1,
                w0: w,
                w1,
                d0,
                d1,
                phi0,
            };
            phi0 = p.at(t1).phi;
            pieces.push(p);
            (t0, w) = (t1, w1);
        }
        Ok(Self { pieces })
    }

    /// A constant speed `omega` (rad/s) for `duration` (s).
    ///
    /// # Errors
    /// [`ModelError::Inconsistent`] for a speed that is negative or not finite, a duration
    /// that is not positive and finite.
    pub fn constant(omega: f64, duration: f64) -> Result<Self, ModelError> {
        Self::build(omega, &[(duration, omega, 0.0, 0.0)])
    }

    /// A linear ramp `from` → `to` (rad/s) over `duration` (s), then `hold` (s) at `to`:
    /// Ω̇ = (to − from)/duration on the ramp, 0 on the hold.
    ///
    /// # Errors
    /// As [`SpeedProfile::constant`]; a negative or non-finite `hold`.
    pub fn ramp(from: f64, to: f64, duration: f64, hold: f64) -> Result<Self, ModelError> {
        let a = (to - from) / duration;
        let mut ends = vec![(duration, to, a, a)];
        push_hold(&mut ends, hold)?;
        Self::build(from, &ends)
    }

    /// A table of `(t, Ω)` points (s, rad/s) from t = 0, interpolated by the monotone
    /// piecewise cubic Hermite interpolant (PCHIP: Fritsch–Carlson slopes — the weighted
    /// harmonic mean of the neighbouring secants, zero at a local extremum — and
    /// shape-preserving three-point slopes at the ends, as scipy's `PchipInterpolator`), then
    /// `hold` (s) at the last speed.
    ///
    /// # Errors
    /// [`ModelError::Inconsistent`] for fewer than two points, times not finite, not from 0 or
    /// not strictly increasing, speeds not finite or negative, a negative `hold`.
    pub fn table(points: &[(f64, f64)], hold: f64) -> Result<Self, ModelError> {
        Self::table_with(points, hold, Interpolation::Pchip)
    }

    /// [`SpeedProfile::table`] joined by `how`: PCHIP, or straight lines (each piece a ramp
    /// at its secant's Ω̇, which jumps at the points).
    ///
    /// # Errors
    /// As [`SpeedProfile::table`].
    pub fn table_with(
        points: &[(f64, f64)],
        hold: f64,
        how: Interpolation,
    ) -> Result<Self, ModelError> {
        if points.len() < 2 {
            return Err(bad("needs at least two points".into()));
        }
        if points[0].0 != 0.0 {
            return Err(bad(format!("must start at t = 0, got {}", points[0].0)));
        }
        let mut ends: Vec<_> = match how {
            Interpolation::Pchip => {
                let d = pchip_slopes(points);
                (1..points.len())
                    .map(|i| (points[i].0, points[i].1, d[i - 1], d[i]))
                    .collect()
            }
            Interpolation::Linear => (1..points.len())
                .map(|i| {
                    let (a, b) = (points[i - 1], points[i]);
                    let m = (b.1 - a.1) / (b.0 - a.0);
                    (b.0, b.1, m, m)
                })
                .collect(),
        };
        push_hold(&mut ends, hold)?;
        Self::build(points[0].1, &ends)
    }

    /// The profile of a scene's `[run.speed_profile]`, speeds converted to rad/s for a rotor
    /// of first natural frequency `omega_n` (rad/s).
    ///
    /// # Errors
    /// [`ModelError::Inconsistent`] for a driven profile (its speed is integrated,
    /// [`crate::model::Drive`]), when a key its kind needs is missing, or as the
    /// constructors (the scene's validation reports these first, with the key's line).
    pub fn from_spec(p: &SpeedProfileSpec, omega_n: f64) -> Result<Self, ModelError> {
        let u = p.unit.to_rad_per_s(omega_n);
        let need = |v: Option<f64>, key: &str| {
            v.ok_or_else(|| bad(format!("run.speed_profile.{key} is missing")))
        };
        match p.kind {
            ProfileKind::Constant => {
                Self::constant(u * need(p.speed, "speed")?, need(p.duration, "duration")?)
            }
            ProfileKind::Ramp => {
                let (from, to) = (need(p.from, "from")?, need(p.to, "to")?);
                let duration = match (p.duration, p.acceleration) {
                    (Some(d), _) => d,
                    (None, Some(a)) => (to - from) / a,
                    (None, None) => {
                        return Err(bad("a ramp needs `duration` or `acceleration`".into()))
                    }
                };
                Self::ramp(u * from, u * to, duration, p.hold)
            }
            ProfileKind::Table => {
                let pts: Vec<(f64, f64)> = p
                    .points
                    .as_deref()
                    .unwrap_or_default()
                    .iter()
                    .map(|[t, w]| (*t, u * w))
                    .collect();
                Self::table_with(&pts, p.hold, p.interpolation)
            }
            ProfileKind::Driven => Err(bad(
                "kind = \"driven\": the speed is integrated with the rotor, not prescribed (crate::model::Drive)".into(),
            )),
        }
    }

    /// Ω, Ω̇ and φ at time `t` (s); before 0 the start, past the end the last speed held
    /// (Ω̇ = 0, φ growing linearly). Allocation-free (a binary search over the pieces).
    #[inline]
    pub fn at(&self, t: f64) -> SpinState {
        let last = self.pieces[self.pieces.len() - 1];
        if t >= last.t1 {
            let end = last.at(last.t1);
            return SpinState {
                phi: end.phi + end.omega * (t - last.t1),
                omega: end.omega,
                omega_dot: 0.0,
            };
        }
        let i = self.pieces.partition_point(|p| p.t1 <= t);
        self.pieces[i].at(t.max(0.0))
    }

    /// The profile's length (s): the run's duration.
    pub fn duration(&self) -> f64 {
        self.pieces[self.pieces.len() - 1].t1
    }

    /// Ω at the start (rad/s).
    pub fn start_speed(&self) -> f64 {
        self.pieces[0].w0
    }

    /// An upper bound of Ω over the profile (rad/s): the largest knot speed, or the largest
    /// value of a piece sampled at 64 points when a cubic piece can bulge (PCHIP pieces stay
    /// between their end speeds, so the knots bound a table; this guards hand-built slopes).
    pub fn max_speed(&self) -> f64 {
        self.pieces
            .iter()
            .flat_map(|p| (0..=64).map(move |j| p.at(p.t0 + (p.t1 - p.t0) * j as f64 / 64.0).omega))
            .chain(self.pieces.iter().flat_map(|p| [p.w0, p.w1]))
            .fold(0.0, f64::max)
    }

    /// Total spin angle φ at the end (rad); revolutions are φ/2π.
    pub fn total_angle(&self) -> f64 {
        self.at(self.duration()).phi
    }
}

/// Appends a hold of `hold` (s) at the last speed.
fn push_hold(ends: &mut Vec<(f64, f64, f64, f64)>, hold: f64) -> Result<(), ModelError> {
    if !(hold.is_finite() && hold >= 0.0) {
        return Err(bad(format!("hold must be finite and ≥ 0, got {hold}")));
    }
    if hold > 0.0 {
        if let Some(&(t, w, _, _)) = ends.last() {
            ends.push((t + hold, w, 0.0, 0.0));
        }
    }
    Ok(())
}

/// PCHIP slopes (Fritsch & Carlson 1980; Fritsch & Butland's weighted harmonic mean inside,
/// the shape-preserving three-point formula at the ends), as scipy's `PchipInterpolator`.
fn pchip_slopes(p: &[(f64, f64)]) -> Vec<f64> {
    let n = p.len();
    let h: Vec<f64> = (0..n - 1).map(|i| p[i + 1].0 - p[i].0).collect();
    let del: Vec<f64> = (0..n - 1).map(|i| (p[i + 1].1 - p[i].1) / h[i]).collect();
    if n == 2 {
        return vec![del[0], del[0]];
    }
    let mut d = vec![0.0; n];
    for k in 1..n - 1 {
        if del[k - 1] * del[k] > 0.0 {
            let w1 = 2.0 * h[k] + h[k - 1];
            let w2 = h[k] + 2.0 * h[k - 1];
            d[k] = (w1 + w2) / (w1 / del[k - 1] + w2 / del[k]);
        }
    }
    let end = |h0: f64, h1: f64, m0: f64, m1: f64| {
        let d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
        if d * m0 <= 0.0 {
            0.0
        } else if m0 * m1 < 0.0 && d.abs() > 3.0 * m0.abs() {
            3.0 * m0
        } else {
            d
        }
    };
    d[0] = end(h[0], h[1], del[0], del[1]);
    d[n - 1] = end(h[n - 2], h[n - 3], del[n - 2], del[n - 3]);
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ramp_angle_is_exact() {
        // Ω = 10 + 2t on [0, 5]: φ = 10t + t², Ω̇ = 2; then held at 20.
        let p = SpeedProfile::ramp(10.0, 20.0, 5.0, 1.0).unwrap();
        for t in [0.0, 0.3, 2.5, 4.99] {
            let s = p.at(t);
            assert!((s.phi - (10.0 * t + t * t)).abs() < 1e-12, "{t}: {s:?}");
            assert!((s.omega - (10.0 + 2.0 * t)).abs() < 1e-12);
            assert!((s.omega_dot - 2.0).abs() < 1e-12);
        }
        let s = p.at(5.5);
        assert!((s.phi - (75.0 + 10.0)).abs() < 1e-12 && s.omega == 20.0 && s.omega_dot == 0.0);
        assert!((p.duration() - 6.0).abs() < 1e-15);
        assert!((p.total_angle() - 95.0).abs() < 1e-12);
    }

    #[test]
    fn table_is_monotone_and_its_angle_the_integral() {
        let pts = [
            (0.0, 10.0),
            (1.0, 12.0),
            (1.5, 30.0),
            (4.0, 31.0),
            (5.0, 31.0),
        ];
        let p = SpeedProfile::table(&pts, 0.0).unwrap();
        // Knots are met, no overshoot, monotone.
        let mut prev = 0.0;
        let mut phi = 0.0;
        let n = 50_000;
        for j in 0..=n {
            let t = 5.0 * j as f64 / n as f64;
            let s = p.at(t);
            assert!(
                s.omega >= prev - 1e-12 && s.omega <= 31.0 + 1e-12,
                "{t}: {s:?}"
            );
            if j > 0 {
                // Trapezoid with the end-slope correction (exact for cubics).
                let h = 5.0 / n as f64;
                let a = p.at(t - h);
                phi += h * (a.omega + s.omega) / 2.0 + h * h * (a.omega_dot - s.omega_dot) / 12.0;
                assert!((s.phi - phi).abs() < 1e-9, "{t}: {} vs {phi}", s.phi);
            }
            prev = s.omega;
        }
        for (t, w) in pts {
            assert!((p.at(t).omega - w).abs() < 1e-12);
        }
        // Ω̇ is the derivative of Ω (central difference).
        let (t, h) = (1.2, 1e-6);
        let fd = (p.at(t + h).omega - p.at(t - h).omega) / (2.0 * h);
        assert!((fd - p.at(t).omega_dot).abs() < 1e-5 * fd.abs().max(1.0));
    }

    #[test]
    fn bad_profiles_are_errors() {
        assert!(SpeedProfile::ramp(10.0, -1.0, 1.0, 0.0).is_err());
        assert!(SpeedProfile::constant(f64::NAN, 1.0).is_err());
        assert!(SpeedProfile::constant(1.0, 0.0).is_err());
        assert!(SpeedProfile::table(&[(0.0, 1.0), (0.0, 2.0)], 0.0).is_err());
        assert!(SpeedProfile::table(&[(0.1, 1.0), (1.0, 2.0)], 0.0).is_err());
        assert!(SpeedProfile::ramp(1.0, 2.0, 1.0, -1.0).is_err());
    }
}
