//! The heated section's conduction model (`[thermal.conduction]`, issue 27): the temperature
//! across a solid circular shaft section of radius `R` heated at its surface by the rub, in
//! place of the hot-spot model's two lags.
//!
//! **The equation.** Over the heated length `a` the shaft is taken as a long solid cylinder
//! (conduction along the axis neglected: the heated length is long against the depth the heat
//! reaches in the spiral's time, `√(κ/s)`). Only the first circumferential harmonic of the
//! temperature bends the shaft, `T(r, θ, t) = T₁(r, t)·(cos θ, sin θ)` (a vector `T₁` in the
//! rotor's frame, its direction the hot side's); it obeys
//!
//! ```text
//! ρ c ∂T₁/∂t = k (∂²T₁/∂r² + (1/r) ∂T₁/∂r − T₁/r²),   T₁(0) = 0,
//! k ∂T₁/∂r (R) = q₁ − h T₁(R),
//! ```
//!
//! `k` the conductivity (W/(m·K)), `ρ c` the heat capacity (J/(m³·K)), `h` the surface's heat
//! transfer coefficient (W/(m²·K)), `q₁` the first harmonic of the heat flux into the surface
//! (W/m²). The friction power's first harmonic `Q` (W, rotor frame: `(1/T) ∫ P (cos θ, sin θ) dt`,
//! `θ` the contact point's angle on the rotor) spread over the heated length's surface gives
//! `q₁ = η Q / (π a R)`, η the share of the friction heat that enters the rotor.
//!
//! **The bow.** The section's thermal curvature is `κ_b = α ∫ T x dA / I = (4α/R⁴) ∫₀ᴿ T₁ r² dr`;
//! it is written as the hot-spot model's `α ΔT / D` with the *effective* temperature difference
//! `ΔT = (8/R³) ∫₀ᴿ T₁ r² dr` — for the steady, linear profile `T₁ = A r` exactly the difference
//! across the diameter, `2 A R`. So the rest of the spiral (the bow, its load, the outputs) is
//! the hot-spot model's, with ΔT from here. The surface's own difference `2 T₁(R)` takes the
//! place of the hot-spot model's surface zone `S`.
//!
//! **Discretisation.** Linear finite elements in `r`, `cells` of them graded toward the surface
//! (`r_i = R sin(π i / 2N)`), every integral exact (the `T₁/r²` term's by its logarithm), with a
//! consistent heat-capacity matrix: `C ẏ = −K y + b Q`. Its modes (`K φ = λ C φ`, a dense
//! symmetric eigenproblem after Cholesky) decouple it, so a coupling step with the heat input
//! linear in time is advanced exactly, as the two lags are. Steady gain, for the record:
//! `ΔT/Q = 2η / (π a (k + h R))` (K/W); the slowest time constant `R² / (κ β²)`, `κ = k/ρc`, β
//! the first root of `β J₁′(β) + (hR/k) J₁(β) = 0` (1.8412 for an adiabatic surface).
//! Verified against the closed form `ΔT/Q (s)` in Bessel functions (tests/common/oracles.rs).

use crate::error::{Error, Result};
use crate::math::V2;
use nalgebra::DMatrix;

/// The heated section's material, surface and heat share, resolved (SI units).
#[derive(Debug, Clone, Copy)]
pub struct Conduction {
    /// R (m): the section's radius, half `thermal.diameter`.
    pub radius: f64,
    /// a (m): the heated length the heat is spread over.
    pub heated_length: f64,
    /// k (W/(m·K)).
    pub conductivity: f64,
    /// ρ c (J/(m³·K)).
    pub heat_capacity: f64,
    /// h (W/(m²·K)).
    pub surface_coefficient: f64,
    /// η (0 < η ≤ 1).
    pub heat_fraction: f64,
    /// Radial elements.
    pub cells: usize,
}

impl Conduction {
    /// κ = k / ρc (m²/s).
    pub fn diffusivity(&self) -> f64 {
        self.conductivity / self.heat_capacity
    }

    /// The surface flux's first harmonic per watt of `Q`: `q₁/Q = η / (π a R)` (1/m²).
    pub fn flux_per_watt(&self) -> f64 {
        self.heat_fraction / (std::f64::consts::PI * self.heated_length * self.radius)
    }

    /// The steady ΔT per watt of `Q` (K/W): `2η / (π a (k + h R))` — the hot-spot model's G.
    pub fn steady_gain(&self) -> f64 {
        2.0 * self.flux_per_watt() * self.radius
            / (self.conductivity + self.surface_coefficient * self.radius)
    }
}

/// The discretised section in its modes: `ż_j = −λ_j z_j + β_j Q`, `ΔT = Σ e_j z_j`, the
/// surface's difference `Σ s_j z_j` (module docs). Each modal coordinate is a vector in the
/// rotor's frame, the two components independent.
#[derive(Debug, Clone)]
pub struct Section {
    /// λ_j (1/s), increasing.
    rates: Vec<f64>,
    /// β_j (K/(W·s) per mode).
    input: Vec<f64>,
    /// e_j: ΔT per unit of z_j.
    delta: Vec<f64>,
    /// s_j: the surface's difference `2 T₁(R)` per unit of z_j.
    surface: Vec<f64>,
    /// The modal coordinates of the linear profile `T₁ = r ΔT / (2R)` per kelvin.
    linear: Vec<f64>,
}

impl Section {
    /// The modes of the section `c` (module docs).
    ///
    /// # Errors
    /// [`Error::Study`] when its heat-capacity matrix is not positive definite (it always is
    /// for a positive ρc and radius; the check guards the arithmetic).
    pub fn new(c: &Conduction) -> Result<Self> {
        let n = c.cells.max(2);
        let r: Vec<f64> = (0..=n)
            .map(|i| c.radius * (0.5 * std::f64::consts::PI * i as f64 / n as f64).sin())
            .collect();
        let (cap, stiff, out, lin) = assemble(c, &r);
        let chol = cap.clone().cholesky().ok_or_else(|| {
            Error::study(
                "thermal.conduction",
                "the section's heat-capacity matrix is not positive definite",
            )
        })?;
        let l = chol.l();
        let l_inv_k = l.solve_lower_triangular(&stiff).unwrap_or(stiff.clone());
        let a = l
            .solve_lower_triangular(&l_inv_k.transpose())
            .unwrap_or(l_inv_k);
        let a = (&a + a.transpose()) * 0.5;
        let eig = a.symmetric_eigen();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
        // Φ = L⁻ᵀ V: C-orthonormal mode shapes.
        let phi = l
            .transpose()
            .solve_upper_triangular(&eig.eigenvectors)
            .unwrap_or(eig.eigenvectors.clone());
        let input_node = c.flux_per_watt() * c.radius;
        let lin_c = &cap * nalgebra::DVector::from_vec(lin);
        let mut s = Self {
            rates: Vec::with_capacity(n),
            input: Vec::with_capacity(n),
            delta: Vec::with_capacity(n),
            surface: Vec::with_capacity(n),
            linear: Vec::with_capacity(n),
        };
        for j in order {
            let col = phi.column(j);
            s.rates.push(eig.eigenvalues[j].max(0.0));
            s.input.push(col[n - 1] * input_node);
            s.delta.push(col.iter().zip(&out).map(|(p, e)| p * e).sum());
            s.surface.push(2.0 * col[n - 1]);
            s.linear.push(col.dot(&lin_c));
        }
        Ok(s)
    }

    /// The modal state of the steady (linear) profile whose ΔT is `dt` (K).
    pub fn initial(&self, dt: V2) -> Vec<V2> {
        self.linear.iter().map(|l| [l * dt[0], l * dt[1]]).collect()
    }

    /// ΔT (K) of the modal state `z`.
    pub fn delta_t(&self, z: &[V2]) -> V2 {
        dot(&self.delta, z)
    }

    /// The surface's difference `2 T₁(R)` (K) of the modal state `z`.
    pub fn surface(&self, z: &[V2]) -> V2 {
        dot(&self.surface, z)
    }

    /// Advances `z` over `h` seconds with the input `Q(t) = q0 + q1 t` (W, W/s) exactly:
    /// `z_j(h) = A + B h + (z_j(0) − A) e^{−λ h}`, `B = β q1/λ`, `A = β q0/λ − β q1/λ²`
    /// (written without its cancellations for small λh).
    pub fn advance(&self, z: &mut [V2], (q0, q1): (V2, V2), h: f64) {
        for (j, zj) in z.iter_mut().enumerate() {
            let (l, b) = (self.rates[j], self.input[j]);
            let x = l * h;
            let decay = (-x).exp();
            // (1 − e^{−x})/λ and (x − 1 + e^{−x})/λ², both → their series for small x.
            let (f0, f1) = if x < 1e-2 {
                (
                    h * (1.0 - x / 2.0 + x * x / 6.0 - x * x * x / 24.0),
                    h * h * (0.5 - x / 6.0 + x * x / 24.0 - x * x * x / 120.0),
                )
            } else {
                (-(-x).exp_m1() / l, (x + (-x).exp_m1()) / (l * l))
            };
            for k in 0..2 {
                zj[k] = zj[k] * decay + b * (q0[k] * f0 + q1[k] * f1);
            }
        }
    }

    /// The discretised section's transfer function `ΔT/Q (s) = Σ e_j β_j / (s + λ_j)` (K/W),
    /// `s = (re, im)` (1/s); at s = 0 its steady gain.
    pub fn transfer(&self, s: V2) -> V2 {
        let mut h = [0.0; 2];
        for j in 0..self.rates.len() {
            let w = self.delta[j] * self.input[j];
            let (a, b) = (s[0] + self.rates[j], s[1]);
            let d = a * a + b * b;
            h[0] += w * a / d;
            h[1] -= w * b / d;
        }
        h
    }

    /// The slowest mode's time constant 1/λ₁ (s).
    pub fn slowest_time(&self) -> f64 {
        1.0 / self.rates.first().copied().unwrap_or(f64::INFINITY)
    }

    /// The modes' count.
    pub fn modes(&self) -> usize {
        self.rates.len()
    }
}

fn dot(w: &[f64], z: &[V2]) -> V2 {
    w.iter()
        .zip(z)
        .fold([0.0; 2], |a, (w, z)| [a[0] + w * z[0], a[1] + w * z[1]])
}

/// The heat-capacity and conduction matrices over the nodes 1..=N of `r` (node 0, the centre,
/// held at T₁ = 0), the ΔT functional `(8/R³) ∫ N_i r² dr` and the nodal values of the linear
/// profile per kelvin of ΔT. Every integral exact: shapes `N = p + q r` on each element.
fn assemble(c: &Conduction, r: &[f64]) -> (DMatrix<f64>, DMatrix<f64>, Vec<f64>, Vec<f64>) {
    let n = r.len() - 1;
    let big_r = c.radius;
    let mut cap = DMatrix::zeros(n, n);
    let mut stiff = DMatrix::zeros(n, n);
    let mut out = vec![0.0; n];
    for e in 0..n {
        let (ra, rb) = (r[e], r[e + 1]);
        let len = rb - ra;
        let pow = |k: i32| (rb.powi(k) - ra.powi(k)) / k as f64;
        let (i1, i2, i3) = (pow(2), pow(3), pow(4));
        // Node e (index e − 1; the centre when e = 0) and node e + 1 (index e).
        let shapes = [(rb / len, -1.0 / len, e), (-ra / len, 1.0 / len, e + 1)];
        for &(pi, qi, ni) in &shapes {
            if ni == 0 {
                continue;
            }
            out[ni - 1] += 8.0 / big_r.powi(3) * (pi * i2 + qi * i3);
            for &(pj, qj, nj) in &shapes {
                if nj == 0 {
                    continue;
                }
                let cross = pi * qj + pj * qi;
                cap[(ni - 1, nj - 1)] +=
                    c.heat_capacity * (pi * pj * i1 + cross * i2 + qi * qj * i3);
                // ∫ N_i N_j / r dr: p_i p_j ≠ 0 only away from the centre (node 0 is held).
                let log = if pi * pj != 0.0 {
                    pi * pj * (rb / ra).ln()
                } else {
                    0.0
                };
                // k (∫ N_i′ N_j′ r dr + ∫ N_i N_j / r dr): the gradient's q_i q_j ∫ r dr once,
                // and once more from the 1/r term's q_i q_j r² / r.
                stiff[(ni - 1, nj - 1)] +=
                    c.conductivity * (2.0 * qi * qj * i1 + log + cross * len);
            }
        }
    }
    stiff[(n - 1, n - 1)] += c.surface_coefficient * big_r;
    let lin = r[1..].iter().map(|ri| ri / (2.0 * big_r)).collect();
    (cap, stiff, out, lin)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn steel(h: f64, cells: usize) -> Conduction {
        Conduction {
            radius: 0.05,
            heated_length: 0.2,
            conductivity: 45.0,
            heat_capacity: 7850.0 * 460.0,
            surface_coefficient: h,
            heat_fraction: 0.5,
            cells,
        }
    }

    /// The discrete steady gain is the closed form's (a linear profile is in the elements'
    /// space, so to rounding), and the slowest time of an adiabatic section is R²/(κ 1.8412²)
    /// to the discretisation's error.
    #[test]
    fn the_steady_gain_and_the_slowest_time_are_the_closed_forms() {
        for h in [0.0, 100.0] {
            let c = steel(h, 32);
            let s = Section::new(&c).unwrap();
            let g = s.transfer([0.0, 0.0]);
            assert!((g[0] / c.steady_gain() - 1.0).abs() < 1e-10, "{g:?}");
        }
        let c = steel(0.0, 64);
        let s = Section::new(&c).unwrap();
        let want = c.radius.powi(2) / (c.diffusivity() * 1.841_183_781_340_659_f64.powi(2));
        assert!(
            (s.slowest_time() / want - 1.0).abs() < 1e-3,
            "{}",
            s.slowest_time()
        );
    }

    /// An advance over h with a constant input equals the sum of many shorter ones, and a long
    /// one reaches the steady gain.
    #[test]
    fn the_modes_advance_exactly() {
        let c = steel(50.0, 16);
        let s = Section::new(&c).unwrap();
        let q = ([3.0, -1.0], [0.2, 0.1]);
        let mut one = s.initial([0.5, 0.0]);
        s.advance(&mut one, q, 40.0);
        let mut many = s.initial([0.5, 0.0]);
        for i in 0..400 {
            let t = 0.1 * i as f64;
            let qi = [q.0[0] + q.1[0] * t, q.0[1] + q.1[1] * t];
            s.advance(&mut many, (qi, q.1), 0.1);
        }
        let (a, b) = (s.delta_t(&one), s.delta_t(&many));
        assert!(
            (a[0] - b[0]).hypot(a[1] - b[1]) < 1e-10 * a[0].hypot(a[1]),
            "{a:?} {b:?}"
        );
        let mut z = s.initial([0.0, 0.0]);
        s.advance(&mut z, ([1.0, 0.0], [0.0, 0.0]), 1e6);
        assert!((s.delta_t(&z)[0] / c.steady_gain() - 1.0).abs() < 1e-9);
        let z0 = s.initial([2.0, -1.0]);
        let d = s.delta_t(&z0);
        assert!(
            (d[0] - 2.0).abs() < 1e-12 && (d[1] + 1.0).abs() < 1e-12,
            "{d:?}"
        );
    }
}
