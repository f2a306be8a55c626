//! A rigid ring on springs around its station (scene `kind = "ring"`): the classic rub model,
//! contact circle in circle; isotropic, or with the support `diag(k_x, k_y)`, `diag(c_x, c_y)`. The ring's centre takes the whole contact force
//! `(n + μa)p` and its gap is exact (`time::ring`); `kinematics = "radial"` gives the radially
//! elastic stator instead (centre along `n` only, friction to ground).

use super::StatorModel;
use crate::contact::Target;
use crate::linalg::Csc;
use crate::resolve::RingInput;
use std::sync::Arc;

/// A ring's support: springs and dashpots along x and y to ground, and its mass.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingSupport {
    /// `[k_x, k_y]` (N/m), both > 0; equal for an isotropic ring.
    pub stiffness: [f64; 2],
    /// Ring mass (kg); 0 for a massless ring.
    pub mass: f64,
    /// `[c_x, c_y]` (N·s/m), used only with mass.
    pub damping: [f64; 2],
}

impl RingSupport {
    /// An isotropic support: `stiffness` (N/m), `mass` (kg), `damping` (N·s/m).
    pub fn isotropic(stiffness: f64, mass: f64, damping: f64) -> Self {
        Self {
            stiffness: [stiffness; 2],
            mass,
            damping: [damping; 2],
        }
    }
}

impl StatorModel {
    /// Rigid ring on the springs of `support` around a station of radius `radius`, with radial
    /// clearance `clearance`; a support without mass makes it massless.
    pub fn ring(
        name: &str,
        station: usize,
        radius: f64,
        clearance: f64,
        support: RingSupport,
    ) -> Self {
        let d = |v: [f64; 2]| Csc::from_triplets(2, 2, &[(0, 0, v[0]), (1, 1, v[1])]);
        let RingSupport {
            stiffness,
            mass,
            damping,
        } = support;
        StatorModel {
            name: name.to_string(),
            station,
            nodes: vec![[0.0, 0.0]],
            node_dofs: vec![[Some(0), Some(1)]],
            ndof: 2,
            k: Arc::new(d(stiffness)),
            m: Arc::new(if mass > 0.0 {
                d([mass; 2])
            } else {
                Csc::zeros(2, 2)
            }),
            c: Arc::new(if mass > 0.0 {
                d(damping)
            } else {
                Csc::zeros(2, 2)
            }),
            targets: vec![Target::Ring {
                center0: [0.0, 0.0],
                inner_radius: radius + clearance,
                dofs: [Some(0), Some(1)],
                radial: false,
            }],
            elements: Default::default(),
            clearance,
            angle_deg: None,
            is_ring: true,
            mesh: None,
            dashpot: Default::default(),
            reduced: None,
            wear: None,
        }
    }

    /// The ring of the scene's `r`, facing station `station` of section radius `radius` at
    /// clearance `clearance` (m), its stiffness ratio (if any) taken of `k_r` (N/m).
    pub fn of_ring(r: &RingInput, station: usize, radius: f64, clearance: f64, k_r: f64) -> Self {
        let kx = r.stiffness.value(k_r);
        let support = RingSupport {
            stiffness: [kx, r.stiffness_y.unwrap_or(kx)],
            mass: r.mass,
            damping: [r.damping, r.damping_y.unwrap_or(r.damping)],
        };
        Self::ring(&r.name, station, radius, clearance, support).with_radial_kinematics(r.radial)
    }

    /// Sets the ring's contact to the radially elastic law (`radial`, [`Target::Ring`]).
    pub fn with_radial_kinematics(mut self, radial: bool) -> Self {
        for t in &mut self.targets {
            if let Target::Ring { radial: r, .. } = t {
                *r = radial;
            }
        }
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ring_is_isotropic_spring() {
        let r = StatorModel::ring("g", 0, 0.05, 1e-4, RingSupport::isotropic(2e6, 0.0, 0.0));
        assert!((r.contact_stiffness_bound() - 2e6).abs() < 1e-6);
    }
}
