//! Rotor models and their linear matrices.
//!
//! Every rotor is handed to the integrator as a [`RotorBody`]: sparse M, C (damping, plus Ω G
//! for gyroscopic rotors) and K over its DOFs, the DOF pair `[u_x, u_y]` of each node that can
//! carry a contact station, the optional axial `u_z` and torsional `θ_z` DOF of each node, and
//! its unbalance loads. The Jeffcott rotor (paper Eq. 50) has one node with DOFs `[u_x, u_y]`
//! and neither axial nor torsional DOFs.

use crate::linalg::Csc;
use crate::resolve::JeffcottData;

/// An unbalance load: force `me·ω²·(cos(ωt+φ), sin(ωt+φ))` on DOFs `dofs = [x, y]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnbalanceLoad {
    /// Rotor DOFs `[x, y]` of the node carrying the unbalance.
    pub dofs: [usize; 2],
    /// m_u · e (kg·m).
    pub me: f64,
    /// Phase φ (rad).
    pub phase: f64,
}

/// A load fixed in the rotor's frame, on one DOF: in the fixed frame it turns with the rotor,
/// `f(t) = Re(a e^{iφ(t)}) = a_re cos φ − a_im sin φ` (N on a translation, N·m on a rotation),
/// φ the spin angle (`Ω t` at a constant speed). A set of them on the `[u_x, u_y]` (or
/// `[θ_y, θ_x]`) pairs of a rotor is any load the rotor carries round with it — a thermal bow's
/// curvature load ([`crate::model::bow`]): `a_y = −i a_x` on a pair is a forward-rotating vector
/// `|a_x| (cos, sin)(φ + arg a_x)`. Unlike an [`UnbalanceLoad`] its amplitude does not scale
/// with Ω² and a varying speed adds no tangential term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotatingLoad {
    /// The rotor DOF loaded.
    pub dof: usize,
    /// The complex amplitude `a = [re, im]` (N or N·m).
    pub amplitude: [f64; 2],
}

/// Linear rotor model as the integrator sees it: `M ü + C u̇ + K u = f(t)`.
#[derive(Debug, Clone)]
pub struct RotorBody {
    /// Number of DOFs.
    pub ndof: usize,
    /// Mass matrix (kg).
    pub m: Csc,
    /// Damping matrix incl. speed-dependent parts at the speed of the case (N·s/m), sparse.
    pub c: Csc,
    /// Low-rank damping added to `c` (modal damping, `U diag(d) Uᵀ`), kept factored so the
    /// time loop's sparse solve never sees a dense block; `None` without.
    pub c_low: Option<crate::linalg::LowRank>,
    /// Stiffness matrix (N/m).
    pub k: Csc,
    /// `[u_x, u_y]` DOFs of each node (index = rotor node).
    pub node_dofs: Vec<[usize; 2]>,
    /// Rotation DOFs `[θ_x, θ_y]` of each node (rad; θ_y = ∂u_x/∂z, θ_x = −∂u_y/∂z), `None`
    /// when the rotor has none (Jeffcott).
    pub node_tilt: Vec<Option<[usize; 2]>>,
    /// Axial DOF `u_z` of each node (m, along +z), `None` when the rotor has none (Jeffcott,
    /// FE rotors without `axial`). Uncoupled from the lateral DOFs in M, C and K.
    pub node_axial: Vec<Option<usize>>,
    /// Torsional DOF `θ_z` of each node (rad, counter-clockwise seen from +z, the sense of Ω),
    /// `None` when the rotor has none. The friction force of a contact at a station of radius
    /// R loads it with the torque `τ_z = R (n × F)_z = −R μ p (n × a)_z` (`−R μ p` for Ω > 0).
    /// Uncoupled from the lateral DOFs in M, C (including Ω G) and K. The twist does not turn
    /// the friction force: the contact keeps slipping along `a` because the sliding speed
    /// `Ω R + R θ̇_z` stays ≈ `Ω R` (|θ̇_z| ≪ Ω; 2e-3 Ω measured in `tests/suite/verification.rs`).
    pub node_torsion: Vec<Option<usize>>,
    /// Axial position z of each node (m); the Jeffcott rotor's single node is at 0.
    pub node_z: Vec<f64>,
    /// Unbalance loads.
    pub unbalance: Vec<UnbalanceLoad>,
    /// Loads fixed in the rotor's frame ([`RotatingLoad`]; a thermal bow's); none by default.
    pub rotating: Vec<RotatingLoad>,
    /// The speed-dependent terms of a gyroscopic rotor, for a varying speed; `None` when the
    /// rotor has none (Jeffcott rotors, FE rotors without rotary inertia).
    pub gyro: Option<Gyroscopic>,
}

/// The gyroscopic terms of a spinning rotor under a varying speed Ω(t) (rad/s), per unit
/// speed and acceleration: the equations read
/// `M q̈ + (C + Ω G) q̇ + (K + Ω̇ K_st) q = f(t)`.
///
/// Derivation (small tilts, spin about +z): the first rotation θ_x about the fixed x axis, then
/// θ_y about the turned y axis, then the spin φ about the section's axis. The angular velocity
/// along that axis is `φ̇ + θ̇_x θ_y` to second order, so a section of polar inertia I_p has the
/// kinetic energy `½ I_p (φ̇ + θ̇_x θ_y)² ≈ ½ I_p Ω² + I_p Ω θ̇_x θ_y`. Over the rotor this is
/// `T_g = Ω q̇ᵀ A q` with A nonzero only in the y–z plane's rows (u_y, θ_x) and the x–z
/// plane's columns (u_x, θ_y) (A = ρ I_p ∫ N_θxᵀ N_θy dz for a shaft element, I_p at (θ_x, θ_y)
/// for a disk). Lagrange's equations give `d/dt(Ω A q) − Ω Aᵀ q̇ = Ω (A − Aᵀ) q̇ + Ω̇ A q`:
/// `G = A − Aᵀ` (skew-symmetric, as assembled by [`crate::element::timoshenko`]) and
/// `K_st = A`, the part of G in the y–z plane's rows — the one-plane form of ROSS's `Kst`. At
/// a disk: `I_d θ̈_x + I_p Ω θ̇_y + I_p Ω̇ θ_y = M_x`, `I_d θ̈_y − I_p Ω θ̇_x = M_y`. The drive
/// torque I_p Ω̇ acts about the section's axis in this form (the generalised force of φ).
#[derive(Debug, Clone)]
pub struct Gyroscopic {
    /// G per unit spin (kg·m²), skew-symmetric.
    pub g: Csc,
    /// K_st per unit angular acceleration (kg·m²): G's entries in the y–z plane's rows.
    pub k_st: Csc,
}

impl Gyroscopic {
    /// The terms of `g` (G per unit spin) on a rotor whose y–z-plane DOFs (u_y, θ_x) are those
    /// for which `yz(dof)` holds; `None` when G is zero.
    pub fn new(g: &Csc, yz: impl Fn(usize) -> bool) -> Option<Self> {
        if g.values().iter().all(|v| *v == 0.0) {
            return None;
        }
        let t: Vec<(usize, usize, f64)> = g.triplets().filter(|(r, _, _)| yz(*r)).collect();
        Some(Self {
            g: g.clone(),
            k_st: Csc::from_triplets(g.nrows(), g.ncols(), &t),
        })
    }
}

impl RotorBody {
    /// Unbalance force vector at time `t` (s) and speed `omega` (rad/s), added into `f`.
    #[inline]
    pub fn add_unbalance(&self, omega: f64, t: f64, f: &mut [f64]) {
        let w2 = omega * omega;
        for u in &self.unbalance {
            let (s, c) = crate::math::sin_cos(omega * t + u.phase);
            f[u.dofs[0]] += u.me * w2 * c;
            f[u.dofs[1]] += u.me * w2 * s;
        }
    }

    /// [`RotorBody::add_unbalance`] with the directions `(cos, sin)(Ω t + β_u)` of each
    /// unbalance given (`dirs`, one per unbalance in order): `f += m_u e Ω² dirs[u]`.
    #[inline]
    pub fn add_unbalance_dirs(&self, omega: f64, dirs: &[[f64; 2]], f: &mut [f64]) {
        let w2 = omega * omega;
        for (u, d) in self.unbalance.iter().zip(dirs) {
            f[u.dofs[0]] += u.me * w2 * d[0];
            f[u.dofs[1]] += u.me * w2 * d[1];
        }
    }

    /// Unbalance force vector of a varying speed, added into `f` (N): the spin angle φ (rad),
    /// Ω = φ̇ (rad/s) and Ω̇ = φ̈ (rad/s²) of [`crate::model::SpinState`].
    ///
    /// An unbalance mass m_u at radius e and phase β sits at `e (cos θ, sin θ)` from the shaft
    /// centre, θ = φ + β; its acceleration relative to the centre is
    /// `e (−θ̇² (cos θ, sin θ) + θ̈ (−sin θ, cos θ))`, and the force it puts on the shaft is
    /// minus its mass times that:
    /// `f = m_u e (φ̇² (cos θ, sin θ) − φ̈ (−sin θ, cos θ))`
    /// — the centrifugal term, plus a tangential term that pulls the shaft back (against the
    /// spin) while the rotor speeds up and forward while it slows down. At Ω̇ = 0 and
    /// φ = Ω t it is [`RotorBody::add_unbalance`].
    #[inline]
    pub fn add_unbalance_spin(&self, spin: crate::model::SpinState, f: &mut [f64]) {
        let (w2, a) = (spin.omega * spin.omega, spin.omega_dot);
        for u in &self.unbalance {
            let (s, c) = (spin.phi + u.phase).sin_cos();
            f[u.dofs[0]] += u.me * (w2 * c + a * s);
            f[u.dofs[1]] += u.me * (w2 * s - a * c);
        }
    }

    /// The loads fixed in the rotor's frame at the spin angle `phi` (rad), added into `f`:
    /// `f[d] += a_re cos φ − a_im sin φ` ([`RotatingLoad`]); nothing without any.
    #[inline]
    pub fn add_rotating(&self, phi: f64, f: &mut [f64]) {
        if self.rotating.is_empty() {
            return;
        }
        let (s, c) = crate::math::sin_cos(phi);
        for l in &self.rotating {
            f[l.dof] += l.amplitude[0] * c - l.amplitude[1] * s;
        }
    }

    /// Complex resultant `Σ m_u e e^{iφ}` (kg·m) as `[re, im]`.
    pub fn unbalance_resultant(&self) -> [f64; 2] {
        self.unbalance.iter().fold([0.0, 0.0], |acc, u| {
            [acc[0] + u.me * u.phase.cos(), acc[1] + u.me * u.phase.sin()]
        })
    }
}

/// Jeffcott rotor: modal mass, stiffness and damping at the disk.
#[derive(Debug, Clone, PartialEq)]
pub struct Jeffcott {
    /// m_r (kg).
    pub mass: f64,
    /// k_r (N/m).
    pub stiffness: f64,
    /// c_r (N·s/m).
    pub damping: f64,
    /// Unbalances.
    pub unbalance: Vec<UnbalanceLoad>,
    /// Polar moment of inertia of the disk (kg·m²), when the scene gave its geometry.
    pub polar_inertia: Option<f64>,
}

impl Jeffcott {
    /// From resolved data ([`crate::resolve::rotor::jeffcott`]): the unbalances act on the
    /// node's DOFs `[0, 1]`.
    pub fn new(d: &JeffcottData) -> Self {
        Self {
            mass: d.mass,
            stiffness: d.stiffness,
            damping: d.damping,
            unbalance: d
                .unbalances
                .iter()
                .map(|&(me, phase)| UnbalanceLoad {
                    dofs: [0, 1],
                    me,
                    phase,
                })
                .collect(),
            polar_inertia: d.polar_inertia,
        }
    }

    /// ω_n = √(k/m) (rad/s).
    pub fn natural_frequency(&self) -> f64 {
        (self.stiffness / self.mass).sqrt()
    }

    /// ξ = c / (2√(m k)).
    pub fn damping_ratio(&self) -> f64 {
        self.damping / (2.0 * (self.mass * self.stiffness).sqrt())
    }

    /// Steady unbalance response amplitude without stator,
    /// |Z0| = |U| ω² / |k − m ω² + i c ω| (m), U = Σ m_u e e^{iφ}.
    pub fn z0(&self, omega: f64) -> f64 {
        let body = self.body();
        let u = body.unbalance_resultant();
        let re = self.stiffness - self.mass * omega * omega;
        let im = self.damping * omega;
        u[0].hypot(u[1]) * omega * omega / re.hypot(im)
    }

    /// The 2-DOF body `[u_x, u_y]`.
    pub fn body(&self) -> RotorBody {
        let diag = |v: f64| Csc::from_triplets(2, 2, &[(0, 0, v), (1, 1, v)]);
        RotorBody {
            ndof: 2,
            m: diag(self.mass),
            c: diag(self.damping),
            c_low: None,
            k: diag(self.stiffness),
            node_dofs: vec![[0, 1]],
            node_tilt: vec![None],
            node_axial: vec![None],
            node_torsion: vec![None],
            node_z: vec![0.0],
            unbalance: self.unbalance.clone(),
            rotating: Vec::new(),
            gyro: None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{DiskSpec, JeffcottSpec, ShaftSpec, UnbalanceSpec};

    /// A scene for the errors of the resolve stage (none here).
    const SCENE: &str = "[rotor]\nkind = \"jeffcott\"\nmass = 1.0\nstiffness = 1.0\ndamping = 0.0\n[run]\nspeed_ratio = 1.0\n";

    #[test]
    fn paper_table_1_data() {
        let s = JeffcottSpec {
            mass: None,
            stiffness: None,
            damping: None,
            damping_ratio: Some(0.2),
            disk: Some(DiskSpec {
                diameter: 0.12,
                thickness: 0.03,
                density: 7800.0,
            }),
            shaft: Some(ShaftSpec {
                youngs_modulus: 200e9,
                diameter: 0.01,
                length: 0.4,
            }),
            unbalance: vec![UnbalanceSpec {
                mass: 0.008,
                radius: 0.045,
                phase_deg: 0.0,
                node: 0,
            }],
        };
        let ls = crate::scene::parse(std::path::Path::new("t.toml"), SCENE, &[]).unwrap();
        let j = Jeffcott::new(&crate::resolve::rotor::jeffcott(&ls, &s).unwrap());
        assert!((j.stiffness - 73631.0).abs() < 1.0, "{}", j.stiffness);
        assert!((j.mass - 2.6465).abs() < 1e-3, "{}", j.mass);
        assert!((j.damping_ratio() - 0.2).abs() < 1e-12);
        // |Z0|/e peak for ξ = 0.2 is 2.5516 at ν = 1.0426 (docs/ORACLES.md §1).
        let e = 0.008 * 0.045 / j.mass;
        let wn = j.natural_frequency();
        let peak = j.z0(1.0426 * wn) / e;
        assert!((peak - 2.5516).abs() < 2e-4, "{peak}");
    }
}
