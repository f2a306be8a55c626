//! The thermal bow's load on a rotor (the Newkirk effect, `[thermal]`, issue 27).
//!
//! A temperature difference ΔT across the shaft (K; a vector in the rotor's frame, written
//! `ΔT = T_x + i T_y`) bends it with the free curvature `κ = α ΔT / D` over the heated length.
//! That curvature is fixed in the rotor, so in the fixed frame the load turns with it:
//! `f(t) = Re(F_b e^{iΩt})`, `F_b` a complex amplitude per DOF ([`RotatingLoad`]), linear in ΔT.
//!
//! * **FE rotor** ([`fe_bow_load`]): on every shaft element inside the heated length the
//!   thermal-strain load of a beam, `∫ E I κ δφ′ dz`
//!   ([`crate::element::timoshenko::thermal_curvature_load`]) — on a whole element the moment
//!   pair ±E I κ, so on a uniform shaft heated between nodes only the zone's two end moments
//!   remain. The hot side's fibres lengthen, so the shaft bows convex toward it: for ΔT = 1 K
//!   along the rotor's x, which points along `(cos Ωt, sin Ωt)` in the fixed frame, the
//!   curvature is `∂²u_x/∂z² = Re(−κ e^{iΩt})` in the x–z plane and
//!   `∂²u_y/∂z² = Re(iκ e^{iΩt})` in the y–z plane: `F_b = −κ (f_xz − i f_yz)` — between two
//!   supports the bow then points at the hot side, as the Jeffcott rotor's does.
//! * **Jeffcott rotor** ([`jeffcott_bow_load`]): the disk's bow `b = g ΔT` (g the midspan
//!   deflection per kelvin of the simply supported span, [`crate::scene::thermal`]) loads the
//!   disk through the shaft's stiffness, `k b e^{iΩt}`: `F_b = k g ΔT (1, −i)` on `[u_x, u_y]`.
//!
//! The bow itself — the shape the load bends the rotor into at rest on its own supports, `K U
//! = F_b` ([`static_bow`]) — is read in the rotor's frame at a node as
//! `b = (U_x + i U_y)/2` ([`rotor_frame`]): the mean of `(u_x + i u_y) e^{−iΩt}` over a
//! revolution, `U_x` itself for the forward vector `U_y = −i U_x` of an isotropic rotor.

use super::fe_rotor::{dense, FeRotor};
use super::rotor::RotatingLoad;
use crate::element::timoshenko::thermal_curvature_load;
use crate::error::ModelError;
use crate::math::V2;
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use std::collections::BTreeMap;

/// The load of ΔT = 1 K along the rotor frame's x on an FE rotor: the curvature
/// `curvature_per_kelvin` (1/(m·K), α/D) over `z ∈ [centre − length/2, centre + length/2]` (m),
/// the part of it on the shaft; one [`RotatingLoad`] per DOF it reaches (module docs).
pub fn fe_bow_load(
    rotor: &FeRotor,
    centre: f64,
    length: f64,
    curvature_per_kelvin: f64,
) -> Vec<RotatingLoad> {
    let (lo, hi) = (centre - 0.5 * length, centre + 0.5 * length);
    let mut a: BTreeMap<usize, V2> = BTreeMap::new();
    for (e, s) in rotor.elements.iter().enumerate() {
        let z0 = rotor.z[e];
        let x1 = ((lo - z0) / s.length).clamp(0.0, 1.0);
        let x2 = ((hi - z0) / s.length).clamp(0.0, 1.0);
        if x2 <= x1 {
            continue;
        }
        let (fx, fy) = thermal_curvature_load(s, (x1, x2));
        for j in 0..8 {
            if fx[j] != 0.0 || fy[j] != 0.0 {
                let v = a.entry(4 * e + j).or_insert([0.0; 2]);
                v[0] -= curvature_per_kelvin * fx[j];
                v[1] += curvature_per_kelvin * fy[j];
            }
        }
    }
    // Inside the zone the moments of neighbouring elements cancel; drop what is left of them
    // (round-off of E I against the zone's end moments).
    let scale = a.values().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max);
    a.into_iter()
        .filter(|(_, v)| v[0].hypot(v[1]) > 1e-12 * scale)
        .map(|(dof, amplitude)| RotatingLoad { dof, amplitude })
        .collect()
}

/// The load of ΔT = 1 K along the rotor frame's x on a Jeffcott rotor of stiffness `k` (N/m)
/// whose disk bows by `bow_per_kelvin` (m/K): `k g (1, −i)` on `[u_x, u_y]`.
pub fn jeffcott_bow_load(k: f64, bow_per_kelvin: f64) -> Vec<RotatingLoad> {
    let a = k * bow_per_kelvin;
    vec![
        RotatingLoad {
            dof: 0,
            amplitude: [a, 0.0],
        },
        RotatingLoad {
            dof: 1,
            amplitude: [0.0, -a],
        },
    ]
}

/// The load of ΔT (K, rotor frame) from the load per kelvin along x: each amplitude times
/// `T_x + i T_y`.
pub fn scaled(per_kelvin: &[RotatingLoad], dt: V2) -> Vec<RotatingLoad> {
    per_kelvin
        .iter()
        .map(|l| RotatingLoad {
            dof: l.dof,
            amplitude: cmul(l.amplitude, dt),
        })
        .collect()
}

/// `(a₀ + i a₁)(b₀ + i b₁)` as `[re, im]`.
pub fn cmul(a: V2, b: V2) -> V2 {
    [a[0] * b[0] - a[1] * b[1], a[0] * b[1] + a[1] * b[0]]
}

/// The static deflection `U` (m, rad; complex amplitudes of `u = Re(U e^{iΩt})`) of the FE
/// rotor under the rotating load `loads` at rest on its bearings of speed `omega` (rad/s):
/// `K(Ω) U = F_b` on the lateral DOFs (the axial and torsional ones are unloaded: zero).
///
/// # Errors
/// [`ModelError::Singular`] when K cannot be factored (a rotor not held laterally).
pub fn static_bow(
    rotor: &FeRotor,
    omega: f64,
    loads: &[RotatingLoad],
) -> Result<Vec<Complex64>, ModelError> {
    let n = rotor.ndof_lateral;
    let k = dense(&rotor.k(omega));
    let a = DMatrix::<Complex64>::from_fn(n, n, |i, j| Complex64::new(k[(i, j)], 0.0));
    let mut f = DVector::<Complex64>::zeros(n);
    for l in loads.iter().filter(|l| l.dof < n) {
        f[l.dof] += Complex64::new(l.amplitude[0], l.amplitude[1]);
    }
    let u = a.lu().solve(&f).ok_or_else(|| ModelError::Singular {
        what: "rotor stiffness (the thermal bow's static shape)".into(),
        detail: "singular: the rotor is not held laterally".into(),
    })?;
    let mut u: Vec<Complex64> = u.iter().copied().collect();
    u.resize(rotor.ndof, Complex64::new(0.0, 0.0));
    Ok(u)
}

/// A node's displacement in the rotor's frame (m), `(U_x + i U_y)/2` of the complex amplitudes
/// `u` (module docs); `dofs` its `[u_x, u_y]`.
pub fn rotor_frame(u: &[Complex64], dofs: [usize; 2]) -> V2 {
    let z = (u[dofs[0]] + Complex64::i() * u[dofs[1]]) * 0.5;
    [z.re, z.im]
}
