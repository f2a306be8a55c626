//! A rigid ring on isotropic springs around its station (scene `kind = "ring"`): the classic
//! rub model, contact circle in circle. The ring's centre takes the whole contact force
//! `(n + μa)p` and its gap is exact (`time::ring`); `kinematics = "radial"` gives the radially
//! elastic stator instead (centre along `n` only, friction to ground).

use super::StatorModel;
use crate::contact::Target;
use crate::linalg::Csc;
use std::sync::Arc;

impl StatorModel {
    /// Rigid ring on isotropic springs `stiffness` around a station of radius `radius`, with
    /// radial clearance `clearance`; `mass` 0 for massless.
    pub fn ring(
        name: &str,
        station: usize,
        radius: f64,
        clearance: f64,
        stiffness: f64,
        mass: f64,
        damping: f64,
    ) -> Self {
        let d = |v: f64| Csc::from_triplets(2, 2, &[(0, 0, v), (1, 1, v)]);
        StatorModel {
            name: name.to_string(),
            station,
            nodes: vec![[0.0, 0.0]],
            node_dofs: vec![[Some(0), Some(1)]],
            ndof: 2,
            k: Arc::new(d(stiffness)),
            m: Arc::new(if mass > 0.0 {
                d(mass)
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
        }
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
        let r = StatorModel::ring("g", 0, 0.05, 1e-4, 2e6, 0.0, 0.0);
        assert!((r.contact_stiffness_bound() - 2e6).abs() < 1e-6);
    }
}
