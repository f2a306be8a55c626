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
