//! The FE rotor's triplets: M, K (shaft) and G of the shaft elements, disks, point masses and
//! pedestals, and the Rayleigh damping matrix of `rayleigh_on` when it is not the assembly's
//! (see [`super`]'s module docs for the conventions).

use crate::assembly::scatter;
use crate::element::timoshenko::{axial_element, disk, shaft_element, torsion_element};
use crate::resolve::rotor::FeRotorData;
use crate::scene::RayleighOn;

/// The triplets of M, K (shaft) and G, the Rayleigh damping of `rayleigh_on` when it is not the
/// assembly's (`Σ_e α M_e + β K_e` over the shaft elements, and with `"rotor"` `α` times the
/// disks' and point masses' mass too), with the total mass and polar inertia.
pub(super) struct Triplets {
    pub(super) mt: Vec<(usize, usize, f64)>,
    pub(super) kt: Vec<(usize, usize, f64)>,
    pub(super) gt: Vec<(usize, usize, f64)>,
    pub(super) rt: Vec<(usize, usize, f64)>,
    pub(super) total_mass: f64,
    pub(super) total_ip: f64,
}

impl Triplets {
    /// Scatters the shaft elements, disks, point masses and pedestals, then the axial and
    /// torsional DOFs.
    pub(super) fn assemble(
        d: &FeRotorData,
        pedestal_dofs: &[Option<usize>],
        node_axial: &[Option<usize>],
        node_torsion: &[Option<usize>],
    ) -> Self {
        let (mut mt, mut kt, mut gt, mut rt) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let [alpha, beta] = d.rayleigh;
        let rayleigh = |rt: &mut Vec<_>, dofs: &[usize], m: &[f64], k: &[f64]| {
            let c: Vec<f64> = m.iter().zip(k).map(|(m, k)| alpha * m + beta * k).collect();
            scatter(rt, dofs, &c);
        };
        let mut total_mass = 0.0;
        let mut total_ip = 0.0;
        for (i, e) in d.elements.iter().enumerate() {
            let el = shaft_element(e);
            let dofs: [usize; 8] = std::array::from_fn(|k| 4 * i + k);
            scatter(&mut mt, &dofs, el.m.as_flattened());
            scatter(&mut kt, &dofs, el.k.as_flattened());
            scatter(&mut gt, &dofs, el.g.as_flattened());
            rayleigh(&mut rt, &dofs, el.m.as_flattened(), el.k.as_flattened());
            total_mass += e.mass();
            total_ip += e.spin_inertia();
        }
        // ROSS 3's rotor-level Rayleigh damping: α times the disks' and point masses' mass too.
        let body_alpha = if d.rayleigh_on == RayleighOn::Rotor {
            alpha
        } else {
            0.0
        };
        let body_mass = |mt: &mut Vec<_>, rt: &mut Vec<_>, r: usize, c: usize, m: f64| {
            mt.push((r, c, m));
            if body_alpha != 0.0 {
                rt.push((r, c, body_alpha * m));
            }
        };
        for dk in &d.disks {
            let (m, g) = disk(dk.mass, dk.id, dk.ip);
            let dofs: [usize; 4] = std::array::from_fn(|k| 4 * dk.node + k);
            for (k, row) in m.iter().enumerate() {
                for (l, v) in row.iter().enumerate().filter(|(_, v)| **v != 0.0) {
                    body_mass(&mut mt, &mut rt, dofs[k], dofs[l], *v);
                }
            }
            scatter(&mut gt, &dofs, g.as_flattened());
            total_mass += dk.mass;
            total_ip += dk.ip;
        }
        for (n, m) in &d.point_masses {
            body_mass(&mut mt, &mut rt, 4 * n, 4 * n, *m);
            body_mass(&mut mt, &mut rt, 4 * n + 1, 4 * n + 1, *m);
            total_mass += m;
        }
        for (b, pd) in d.bearings.iter().zip(pedestal_dofs) {
            if let (Some((pm, _, _)), Some(p)) = (b.pedestal, pd) {
                mt.push((*p, *p, pm));
                mt.push((p + 1, p + 1, pm));
            }
        }
        // Axial and torsional DOFs (after every lateral triplet, so the lateral entries sum in
        // the same order as without them): bar and torsion elements, disks, point masses.
        for (i, e) in d.elements.iter().enumerate() {
            for (dofs, el) in [
                (node_axial, axial_element(e)),
                (node_torsion, torsion_element(e)),
            ] {
                if let (Some(a), Some(b)) = (dofs[i], dofs[i + 1]) {
                    let ab = [a, b];
                    scatter(&mut mt, &ab, el.m.as_flattened());
                    scatter(&mut kt, &ab, el.k.as_flattened());
                    rayleigh(&mut rt, &ab, el.m.as_flattened(), el.k.as_flattened());
                }
            }
        }
        for dk in &d.disks {
            if let Some(a) = node_axial[dk.node] {
                body_mass(&mut mt, &mut rt, a, a, dk.mass);
            }
            if let Some(t) = node_torsion[dk.node] {
                body_mass(&mut mt, &mut rt, t, t, dk.ip);
            }
        }
        for (n, m) in &d.point_masses {
            if let Some(a) = node_axial[*n] {
                body_mass(&mut mt, &mut rt, a, a, *m);
            }
        }
        Triplets {
            mt,
            kt,
            gt,
            rt,
            total_mass,
            total_ip,
        }
    }
}
