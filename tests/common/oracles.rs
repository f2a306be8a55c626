//! Closed forms of docs/ORACLES.md that several test files check against, each written once.

/// The synchronous full annular rub on the radially elastic stator (docs/ORACLES.md §2: force
/// k_s(R − δ) along the radius): whirl radius r = R/e and lag β (rad) at ν = Ω/ω_n, for the
/// stiffness ratio κ, friction μ, damping ratio ξ and clearance d = δ/e — the larger root of
/// the quadratic in r² (a rub only where r > d, which the caller checks).
pub fn radial_annular_rub(nu: f64, kappa: f64, mu: f64, xi: f64, d: f64) -> (f64, f64) {
    let (qa, qb, qc) = radial_annular_rub_quadratic(nu, kappa, mu, xi, d);
    let r = (-qb + (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa);
    let beta =
        (2.0 * xi * nu * r + mu * kappa * (r - d)).atan2((1.0 - nu * nu) * r + kappa * (r - d));
    (r, beta)
}

/// The coefficients `(a, b, c)` of the quadratic `a r² + b r + c = 0` in the whirl radius
/// r = R/e of [`radial_annular_rub`]: its larger root the stable full rub, its smaller one the
/// unstable rub, a double root (b² = 4ac) the fold where they meet.
pub fn radial_annular_rub_quadratic(
    nu: f64,
    kappa: f64,
    mu: f64,
    xi: f64,
    d: f64,
) -> (f64, f64, f64) {
    let (a, b, p, q) = (
        1.0 - nu * nu + kappa,
        -kappa * d,
        2.0 * xi * nu + mu * kappa,
        -mu * kappa * d,
    );
    (
        a * a + p * p,
        2.0 * (a * b + p * q),
        b * b + q * q - nu.powi(4),
    )
}

/// The Newkirk spiral of a Jeffcott rotor rubbing all round a radial ring at zero clearance
/// (docs/VALIDATION.md §21): mass `m`, damping `c`, stiffness `k`, ring `k_s` with friction
/// `mu` at the section radius `radius`, speed `omega`, unbalance `me` (kg·m, phase 0), and the
/// hot-spot model's gain `gain` (K/W), times `th`, `tc` (s) and bow per kelvin `bow` (m/K).
/// The rub's force on the rotor is `−k_s (1 + iμ) z`, its heat's first harmonic in the rotor's
/// frame `Q = μ k_s Ω R Z` (Z the 1× vector), so the slow dynamics are linear:
/// `τ_h S' = −S + G Q`, `τ_c ΔT' = −ΔT + S`, `Z = H (m e Ω² + k g ΔT)`,
/// `H = 1 / (k + k_s (1 + iμ) − m Ω² + i c Ω)`.
#[derive(Debug, Clone, Copy)]
pub struct Newkirk {
    pub m: f64,
    pub c: f64,
    pub k: f64,
    pub ks: f64,
    pub mu: f64,
    pub radius: f64,
    pub omega: f64,
    pub me: f64,
    pub gain: f64,
    pub th: f64,
    pub tc: f64,
    pub bow: f64,
}

type C64 = num_complex::Complex64;

impl Newkirk {
    /// The receptance H (m/N) of the rotor with the rub.
    pub fn h(&self) -> C64 {
        let w = self.omega;
        1.0 / C64::new(
            self.k + self.ks - self.m * w * w,
            self.mu * self.ks + self.c * w,
        )
    }

    /// The loop gain Λ = G μ k_s Ω R H k g.
    pub fn lambda(&self) -> C64 {
        self.gain * self.mu * self.ks * self.omega * self.radius * self.h() * self.k * self.bow
    }

    /// The slow dynamics' two eigenvalues s (1/s), the larger real part first: the roots of
    /// `(1 + τ_h s)(1 + τ_c s) = Λ`.
    pub fn rates(&self) -> [C64; 2] {
        let (a, b, c) = (self.th * self.tc, self.th + self.tc, 1.0 - self.lambda());
        let d = (b * b - 4.0 * a * c).sqrt();
        let (s1, s2) = ((-b + d) / (2.0 * a), (-b - d) / (2.0 * a));
        if s1.re >= s2.re {
            [s1, s2]
        } else {
            [s2, s1]
        }
    }

    /// The 1× vector Z (m, rotor frame) at the temperature difference `dt` (K).
    pub fn one_x(&self, dt: C64) -> C64 {
        self.h() * (self.me * self.omega * self.omega + self.k * self.bow * dt)
    }

    /// ΔT (K) at the `times` (s, increasing from 0) from S = ΔT = `start`: the linear ODEs by
    /// fourth-order Runge–Kutta steps of at most 1 ms.
    pub fn trajectory(&self, start: C64, times: &[f64]) -> Vec<C64> {
        let q = self.mu * self.ks * self.omega * self.radius;
        let f = |x: [C64; 2]| {
            let qz = q * self.one_x(x[1]);
            [(self.gain * qz - x[0]) / self.th, (x[0] - x[1]) / self.tc]
        };
        let add = |x: [C64; 2], k: [C64; 2], h: f64| [x[0] + k[0] * h, x[1] + k[1] * h];
        let (mut x, mut t) = ([start, start], 0.0);
        let mut out = Vec::with_capacity(times.len());
        for &target in times {
            while t < target - 1e-12 {
                let h = (target - t).min(1e-3);
                let k1 = f(x);
                let k2 = f(add(x, k1, h / 2.0));
                let k3 = f(add(x, k2, h / 2.0));
                let k4 = f(add(x, k3, h));
                for i in 0..2 {
                    x[i] += (k1[i] + k2[i] * 2.0 + k3[i] * 2.0 + k4[i]) * (h / 6.0);
                }
                t += h;
            }
            out.push(x[1]);
        }
        out
    }
}

/// The modified Bessel function `I_n(x)` of a complex argument by its power series
/// `Σ (x/2)^{2m+n} / (m! (m+n)!)` (good to rounding for |x| ≲ 30, the range the section's
/// transfer function is checked in).
pub fn bessel_i(n: u32, x: C64) -> C64 {
    let half = x / 2.0;
    let mut term = C64::new(1.0, 0.0);
    for k in 1..=n {
        term *= half / k as f64;
    }
    let mut sum = term;
    let q = half * half;
    for m in 1..400 {
        term *= q / (m as f64 * (m + n) as f64);
        sum += term;
        if term.norm() < 1e-18 * sum.norm() && m as f64 > x.norm() {
            break;
        }
    }
    sum
}

/// The heated section's conduction in closed form (docs/VALIDATION.md §21.3,
/// `src/model/section.rs`): the first circumferential harmonic `T₁(r) e^{st}` of a solid
/// cylinder of radius `radius` (m), conductivity `k` (W/(m·K)), heat capacity `rho_c`
/// (J/(m³·K)), surface coefficient `h` (W/(m²·K)), heated over `length` (m) by the share
/// `eta` of the friction heat's first harmonic Q (W).
#[derive(Debug, Clone, Copy)]
pub struct SectionOracle {
    pub radius: f64,
    pub length: f64,
    pub k: f64,
    pub rho_c: f64,
    pub h: f64,
    pub eta: f64,
}

impl SectionOracle {
    /// ΔT/Q (s) (K/W): with λ = √(s ρc/k), `T₁ = A I₁(λ r)`,
    /// `A = q₁ / (k λ I₁′(λR) + h I₁(λR))`, `q₁ = η Q/(π a R)`, and the effective ΔT
    /// `(8/R³) ∫ T₁ r² dr = 8 A I₂(λR)/(R λ)`; at s = 0 its limit `2 q₁ R/(k + hR)` per Q.
    pub fn transfer(&self, s: C64) -> C64 {
        let r = self.radius;
        let flux = self.eta / (std::f64::consts::PI * self.length * r);
        if s.norm() == 0.0 {
            return C64::new(2.0 * flux * r / (self.k + self.h * r), 0.0);
        }
        let lam = (s * self.rho_c / self.k).sqrt();
        let x = lam * r;
        let (i0, i1, i2) = (bessel_i(0, x), bessel_i(1, x), bessel_i(2, x));
        let i1p = i0 - i1 / x;
        let a = flux / (self.k * lam * i1p + self.h * i1);
        a * 8.0 * i2 / (lam * r)
    }
}

/// The spiral's dominant slow eigenvalue s (1/s) for a section's transfer function `t(s)`
/// (K/W) and the rest of the loop `l` (W/K: Λ/G of [`Newkirk`]): the root of `t(s) l = 1`
/// with the largest real part, by Newton (its derivative by differences) from the single-lag
/// guess `(t(0) l − 1)/tau` and its neighbours.
pub fn dominant_root(t: impl Fn(C64) -> C64, l: C64, tau: f64) -> C64 {
    let f = |s: C64| t(s) * l - 1.0;
    let guess = (t(C64::new(0.0, 0.0)) * l - 1.0) / tau;
    let mut best: Option<C64> = None;
    for g in [
        guess,
        guess * 0.5,
        guess * 2.0,
        guess.conj(),
        C64::new(-0.5 / tau, 0.0),
    ] {
        let mut s = g;
        let mut ok = false;
        for _ in 0..100 {
            let e = 1e-7 * (s.norm() + 1.0 / tau);
            let d = (f(s + e) - f(s - e)) / (2.0 * e);
            let step = f(s) / d;
            s -= step;
            if step.norm() < 1e-13 * (s.norm() + 1.0 / tau) {
                ok = true;
                break;
            }
        }
        if ok && s.re.is_finite() && best.is_none_or(|b| s.re > b.re + 1e-9) {
            best = Some(s);
        }
    }
    best.expect("no root converged")
}
