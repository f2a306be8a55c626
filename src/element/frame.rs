//! Line elements in the station plane: 2-node bars (truss) and 2-node frames (beam-columns,
//! Euler–Bernoulli or Timoshenko) for stator supports and ribs.
//!
//! # Conventions
//!
//! * Bar DOFs `[u_x0, u_y0, u_x1, u_y1]` (m); frame DOFs `[u_x0, u_y0, θ_0, u_x1, u_y1, θ_1]`
//!   (m, rad), θ counter-clockwise about +z. Local matrices are row-major.
//! * Local axis s from node 0 to node 1, `(c, s) = (x₁ − x₀)/L`; the transverse axis is s
//!   rotated by +90°.
//! * Frame bending: `φ = 12 E I / (κ G A L²)` (0 for Euler–Bernoulli) and
//!   `K_b = E I / (L³ (1+φ)) [12, 6L, −12, 6L; 6L, (4+φ)L², −6L, (2−φ)L²; …]` on
//!   `(v₀, θ₀, v₁, θ₁)`; axial `E A / L`.
//! * Consistent mass: axial `ρAL/6 [2 1; 1 2]`, transverse the Euler–Bernoulli cubic
//!   `ρAL/420 [156, 22L, 54, −13L; …]` (used for both theories; rotary inertia neglected).
//!   Lumped (HRZ): `ρAL/2` per node in translation and `ρAL³/78` in rotation.

/// Cross-section of a frame element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameSection {
    /// Young's modulus E (Pa).
    pub youngs_modulus: f64,
    /// Shear modulus G (Pa).
    pub shear_modulus: f64,
    /// Area A (m²).
    pub area: f64,
    /// Second moment of area I about z (m⁴).
    pub inertia: f64,
    /// Shear correction factor κ; `None` for Euler–Bernoulli (no shear deformation).
    pub shear_factor: Option<f64>,
    /// Density ρ (kg/m³).
    pub density: f64,
}

impl FrameSection {
    /// Shear parameter φ = 12 E I / (κ G A L²) of an element of length `l`.
    pub fn phi(&self, l: f64) -> f64 {
        match self.shear_factor {
            Some(k) => {
                12.0 * self.youngs_modulus * self.inertia
                    / (k * self.shear_modulus * self.area * l * l)
            }
            None => 0.0,
        }
    }
}

/// Length and direction cosines of the segment `a → b`.
pub fn geometry(a: [f64; 2], b: [f64; 2]) -> (f64, f64, f64) {
    let l = (b[0] - a[0]).hypot(b[1] - a[1]);
    (l, (b[0] - a[0]) / l, (b[1] - a[1]) / l)
}

/// Bar stiffness `E A / L · q qᵀ`, `q = [c, s, −c, −s]` into `ke` (4×4, N/m).
///
/// # Panics
/// If `ke.len() != 16`.
pub fn bar_stiffness(a: [f64; 2], b: [f64; 2], ea: f64, ke: &mut [f64]) {
    assert_eq!(ke.len(), 16);
    let (l, c, s) = geometry(a, b);
    let q = [c, s, -c, -s];
    for i in 0..4 {
        for j in 0..4 {
            ke[i * 4 + j] = ea / l * q[i] * q[j];
        }
    }
}

/// `T` of the frame: global → local DOFs (6×6, block diagonal rotations).
fn rotation(c: f64, s: f64) -> [[f64; 6]; 6] {
    let mut t = [[0.0; 6]; 6];
    for k in 0..2 {
        let o = 3 * k;
        t[o][o] = c;
        t[o][o + 1] = s;
        t[o + 1][o] = -s;
        t[o + 1][o + 1] = c;
        t[o + 2][o + 2] = 1.0;
    }
    t
}

/// `Tᵀ A T` into row-major `out`.
fn to_global(a: &[[f64; 6]; 6], t: &[[f64; 6]; 6], out: &mut [f64]) {
    let mut at = [[0.0; 6]; 6];
    for i in 0..6 {
        for j in 0..6 {
            at[i][j] = (0..6).map(|k| a[i][k] * t[k][j]).sum();
        }
    }
    for i in 0..6 {
        for j in 0..6 {
            out[i * 6 + j] = (0..6).map(|k| t[k][i] * at[k][j]).sum();
        }
    }
}

/// Frame stiffness into `ke` (6×6, global axes; N/m, N, N·m/rad).
///
/// # Panics
/// If `ke.len() != 36`.
pub fn frame_stiffness(a: [f64; 2], b: [f64; 2], sec: &FrameSection, ke: &mut [f64]) {
    assert_eq!(ke.len(), 36);
    let (l, c, s) = geometry(a, b);
    let phi = sec.phi(l);
    let ka = sec.youngs_modulus * sec.area / l;
    let kb = sec.youngs_modulus * sec.inertia / (l * l * l * (1.0 + phi));
    let mut k = [[0.0; 6]; 6];
    k[0][0] = ka;
    k[0][3] = -ka;
    k[3][0] = -ka;
    k[3][3] = ka;
    let idx = [1, 2, 4, 5];
    let kbm = [
        [12.0, 6.0 * l, -12.0, 6.0 * l],
        [6.0 * l, (4.0 + phi) * l * l, -6.0 * l, (2.0 - phi) * l * l],
        [-12.0, -6.0 * l, 12.0, -6.0 * l],
        [6.0 * l, (2.0 - phi) * l * l, -6.0 * l, (4.0 + phi) * l * l],
    ];
    for i in 0..4 {
        for j in 0..4 {
            k[idx[i]][idx[j]] = kb * kbm[i][j];
        }
    }
    to_global(&k, &rotation(c, s), ke);
}

/// Frame consistent mass into `me` (6×6, global axes; kg, kg·m, kg·m²).
///
/// # Panics
/// If `me.len() != 36`.
pub fn frame_mass_consistent(a: [f64; 2], b: [f64; 2], sec: &FrameSection, me: &mut [f64]) {
    assert_eq!(me.len(), 36);
    let (l, c, s) = geometry(a, b);
    let m = sec.density * sec.area * l;
    let mut k = [[0.0; 6]; 6];
    k[0][0] = m / 3.0;
    k[0][3] = m / 6.0;
    k[3][0] = m / 6.0;
    k[3][3] = m / 3.0;
    let idx = [1, 2, 4, 5];
    let mm = [
        [156.0, 22.0 * l, 54.0, -13.0 * l],
        [22.0 * l, 4.0 * l * l, 13.0 * l, -3.0 * l * l],
        [54.0, 13.0 * l, 156.0, -22.0 * l],
        [-13.0 * l, -3.0 * l * l, -22.0 * l, 4.0 * l * l],
    ];
    for i in 0..4 {
        for j in 0..4 {
            k[idx[i]][idx[j]] = m / 420.0 * mm[i][j];
        }
    }
    to_global(&k, &rotation(c, s), me);
}

/// Frame lumped mass per node `[translation (kg), rotation (kg·m²)]` (HRZ).
pub fn frame_mass_lumped(a: [f64; 2], b: [f64; 2], sec: &FrameSection) -> [f64; 2] {
    let (l, _, _) = geometry(a, b);
    let m = sec.density * sec.area * l;
    [m / 2.0, m * l * l / 78.0]
}

/// Axial force N (tension positive, N), end moments `[M₀, M₁]` (N·m) and shear V (N) of a frame
/// from its global DOFs `u` (`[u_x0, u_y0, θ_0, u_x1, u_y1, θ_1]`): the element end forces
/// `K_local T u` expressed as section forces.
pub fn frame_section_forces(
    a: [f64; 2],
    b: [f64; 2],
    sec: &FrameSection,
    u: &[f64; 6],
) -> (f64, [f64; 2], f64) {
    let mut ke = [0.0; 36];
    frame_stiffness(a, b, sec, &mut ke);
    let f: [f64; 6] = std::array::from_fn(|i| (0..6).map(|j| ke[i * 6 + j] * u[j]).sum());
    let (_, c, s) = geometry(a, b);
    // Local end forces.
    let n1 = c * f[3] + s * f[4];
    let v0 = -s * f[0] + c * f[1];
    (n1, [-f[2], f[5]], v0)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SEC: FrameSection = FrameSection {
        youngs_modulus: 210e9,
        shear_modulus: 80e9,
        area: 1e-4,
        inertia: 1e-9,
        shear_factor: None,
        density: 7800.0,
    };

    fn solve6(k: &[f64], fixed: &[usize], f: &[f64; 6]) -> [f64; 6] {
        let free: Vec<usize> = (0..6).filter(|i| !fixed.contains(i)).collect();
        let n = free.len();
        let a = nalgebra::DMatrix::from_fn(n, n, |i, j| k[free[i] * 6 + free[j]]);
        let r = nalgebra::DVector::from_fn(n, |i, _| f[free[i]]);
        let x = a.lu().solve(&r).unwrap();
        let mut u = [0.0; 6];
        for (i, &d) in free.iter().enumerate() {
            u[d] = x[i];
        }
        u
    }

    #[test]
    fn cantilever_tip_deflection_euler_and_timoshenko() {
        // Oblique cantilever of length 0.3 fixed at node 0, transverse tip load P.
        let ang = 0.7_f64;
        let l = 0.3;
        let a = [0.1, 0.2];
        let b = [a[0] + l * ang.cos(), a[1] + l * ang.sin()];
        let p = 50.0;
        let tr = [-ang.sin(), ang.cos()];
        for sec in [
            SEC,
            FrameSection {
                shear_factor: Some(5.0 / 6.0),
                inertia: 2e-7,
                ..SEC
            },
        ] {
            let mut ke = [0.0; 36];
            frame_stiffness(a, b, &sec, &mut ke);
            let u = solve6(&ke, &[0, 1, 2], &[0.0, 0.0, 0.0, p * tr[0], p * tr[1], 0.0]);
            let v = u[3] * tr[0] + u[4] * tr[1];
            let ei = sec.youngs_modulus * sec.inertia;
            let shear = sec
                .shear_factor
                .map_or(0.0, |k| p * l / (k * sec.shear_modulus * sec.area));
            let exact = p * l.powi(3) / (3.0 * ei) + shear;
            assert!((v / exact - 1.0).abs() < 1e-10, "{v} vs {exact}");
            // Section forces: fixed-end moment P L (sagging sign of the end force).
            let (n, m, _) = frame_section_forces(a, b, &sec, &u);
            assert!(n.abs() < 1e-6 * p && (m[0].abs() - p * l).abs() < 1e-8);
        }
    }

    #[test]
    fn bar_and_frame_axial_agree_and_mass_totals() {
        let a = [0.0, 0.0];
        let b = [0.3, 0.4];
        let mut kb = [0.0; 16];
        bar_stiffness(a, b, SEC.youngs_modulus * SEC.area, &mut kb);
        let mut kf = [0.0; 36];
        frame_stiffness(a, b, &SEC, &mut kf);
        let map = [0, 1, 3, 4];
        // Axial stretch along the bar: same forces.
        let ub = [0.0, 0.0, 0.6e-5, 0.8e-5];
        for i in 0..4 {
            let fb: f64 = (0..4).map(|j| kb[i * 4 + j] * ub[j]).sum();
            let ff: f64 = (0..4).map(|j| kf[map[i] * 6 + map[j]] * ub[j]).sum();
            assert!((fb - ff).abs() < 1e-6 * fb.abs().max(1.0));
        }
        let mut me = [0.0; 36];
        frame_mass_consistent(a, b, &SEC, &mut me);
        let m = SEC.density * SEC.area * 0.5;
        // Rigid translation in x: total inertia force m.
        let fx: f64 = (0..6)
            .map(|i| {
                (0..6)
                    .map(|j| me[i * 6 + j] * [1.0, 0.0, 0.0, 1.0, 0.0, 0.0][j])
                    .sum::<f64>()
                    * [1.0, 0.0, 0.0, 1.0, 0.0, 0.0][i]
            })
            .sum();
        assert!((fx / m - 1.0).abs() < 1e-12);
        let lm = frame_mass_lumped(a, b, &SEC);
        assert!((2.0 * lm[0] / m - 1.0).abs() < 1e-15);
    }
}
