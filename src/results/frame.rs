//! The state of one frame on the output grid ([`FrameState`]), filled from the time loop's
//! [`Frame`] in buffers reused from frame to frame.

use super::layout::{Layout, RING_POINTS, THETA_Z, U_Z};
use crate::contact::{pair_state, target_disp};
use crate::model::stator::StatorElement;
use crate::model::{Case, Target};
use crate::time::Frame;

/// Strain of an element from its stress (Pa): σ/E for bars and frames (axial), NaN where it is
/// not defined (springs; continuum cells, whose stress is the centroid von Mises stress).
fn element_strain(el: &StatorElement, stress: f64) -> f64 {
    match el {
        StatorElement::Bar { youngs_modulus, .. } => stress / youngs_modulus,
        StatorElement::Frame { section, .. } => stress / section.youngs_modulus,
        _ => f64::NAN,
    }
}

/// The state of one frame on the [`OutputGrid`](super::OutputGrid), in buffers reused from frame to frame.
#[derive(Debug, Clone)]
pub struct FrameState {
    /// Step index.
    pub step: usize,
    /// Time (s).
    pub t: f64,
    /// Spin speed Ω at `t` (rad/s): the case's constant speed, or a transient's Ω(t).
    pub omega: f64,
    /// Ω/ω_n at `t` (ω_n of the rotor, [`crate::model::Case::speed_ratio`]'s unit).
    pub speed_ratio: f64,
    /// Spin angle φ at `t` (rad), φ(0) = 0: Ω t at constant speed, ∫₀ᵗ Ω dt in a transient.
    pub phi: f64,
    /// Angular acceleration Ω̇ at `t` (rad/s²); 0 at constant speed.
    pub omega_dot: f64,
    /// ω_n (rad/s), from the case: Ω_case / (Ω_case/ω_n).
    omega_n: f64,
    /// Rotor DOF vector (m, rad).
    pub rotor_u: Vec<f64>,
    /// Rotor DOF velocities (m/s, rad/s), backward difference over one step.
    pub rotor_v: Vec<f64>,
    /// Twist θ_z of each rotor node (rad, counter-clockwise seen from +z, the sense of Ω;
    /// 0 where the node has no θ_z).
    pub rotor_twist: Vec<f64>,
    /// Twist rate dθ_z/dt of each rotor node (rad/s), from `rotor_v`.
    pub rotor_twist_rate: Vec<f64>,
    /// Point displacements (m); at rotor nodes `[u_x, u_y, u_z]`.
    pub displacement: Vec<[f64; 3]>,
    /// Point velocities (m/s), backward difference over one step.
    pub velocity: Vec<[f64; 3]>,
    /// Point contact forces (N) on the body the point belongs to.
    pub contact_force: Vec<[f64; 3]>,
    /// Normal force p ≥ 0 of every candidate pair (N); 0 when open.
    pub pair_p: Vec<f64>,
    /// Force `(n + μa) p` on the stator node of every pair (N).
    pub pair_force: Vec<[f64; 2]>,
    /// Unit normal of every pair in contact (0 when open).
    pub pair_normal: Vec<[f64; 2]>,
    /// Total contact force on each station of the rotor (N).
    pub station_force: Vec<[f64; 2]>,
    /// Axial force (N) per grid cell: stator elements; NaN for other cells.
    pub axial_force: Vec<f64>,
    /// Stress (Pa) per grid cell: stator elements; NaN for other cells.
    pub stress: Vec<f64>,
    /// Strain per grid cell: stator elements; NaN for other cells.
    pub strain: Vec<f64>,
    /// Undeformed position (m) of the contact point of each ring ([`Layout::rings`]) in this
    /// frame's contact direction: `center0 + R n` (see [`RingSlot`](super::RingSlot)); the `.vtu` writes it.
    pub ring_contact: Vec<[f64; 3]>,
    /// With wear (`[stator.wear]`): the worn depth at every point (m; 0 off the worn contact
    /// nodes); `None` without wear.
    pub worn_depth: Option<Vec<f64>>,
}

impl FrameState {
    /// Buffers for the frames of `case` on `layout`, zero (NaN for cell data) until filled.
    pub fn new(layout: &Layout, case: &Case) -> Self {
        let np = layout.num_points();
        let nc = layout.grid.num_cells();
        let npairs = layout.pairs.len();
        Self {
            step: 0,
            t: 0.0,
            omega: case.omega,
            speed_ratio: case.speed_ratio,
            phi: 0.0,
            omega_dot: 0.0,
            omega_n: if case.speed_ratio > 0.0 {
                case.omega / case.speed_ratio
            } else {
                f64::NAN
            },
            rotor_u: vec![0.0; case.rotor.ndof],
            rotor_v: vec![0.0; case.rotor.ndof],
            rotor_twist: vec![0.0; layout.rotor_dofs.len()],
            rotor_twist_rate: vec![0.0; layout.rotor_dofs.len()],
            displacement: vec![[0.0; 3]; np],
            velocity: vec![[0.0; 3]; np],
            contact_force: vec![[0.0; 3]; np],
            pair_p: vec![0.0; npairs],
            pair_force: vec![[0.0; 2]; npairs],
            pair_normal: vec![[0.0; 2]; npairs],
            station_force: vec![[0.0; 2]; case.stations.len()],
            axial_force: vec![f64::NAN; nc],
            stress: vec![f64::NAN; nc],
            strain: vec![f64::NAN; nc],
            ring_contact: layout
                .rings
                .iter()
                .map(|r| layout.grid.points[r.contact_point])
                .collect(),
            worn_depth: case
                .stators
                .iter()
                .any(|s| s.wear.is_some())
                .then(|| vec![0.0; np]),
        }
    }

    /// Fills displacements, contact forces and element fields from a frame (not velocities).
    pub fn fill(&mut self, layout: &Layout, case: &Case, f: &Frame<'_>) {
        self.step = f.step;
        self.t = f.t;
        let spin = f.spin.unwrap_or(crate::model::SpinState {
            phi: case.omega * f.t,
            omega: case.omega,
            omega_dot: 0.0,
        });
        self.omega = spin.omega;
        self.phi = spin.phi;
        self.omega_dot = spin.omega_dot;
        self.speed_ratio = spin.omega / self.omega_n;
        self.rotor_u.copy_from_slice(f.rotor_u);
        for (k, s) in case.stators.iter().enumerate() {
            let u = f.stator_u(k);
            let c = |i: Option<usize>| i.map_or(0.0, |i| u[i]);
            let first = layout.stator_first_point[k];
            // 3-D meshed stators carry u_z; 2-D ones move in their plane.
            let axial = s.mesh.as_ref().map_or(&[][..], |m| &m.axial_dofs[..]);
            for (n, d) in s.node_dofs.iter().enumerate() {
                let uz = axial.get(n).map_or(0.0, |a| c(*a));
                self.displacement[first + n] = [c(d[0]), c(d[1]), uz];
            }
        }
        let dof = |d: Option<usize>| d.map_or(0.0, |i| f.rotor_u[i]);
        for (n, d) in layout.rotor_dofs.iter().enumerate() {
            self.displacement[layout.rotor_first_point + n] = [dof(d[0]), dof(d[1]), dof(d[U_Z])];
            self.rotor_twist[n] = dof(d[THETA_Z]);
        }
        // Rings: the circle and the contact point move with the ring centre; the contact point
        // sits on the line of centres (the contact kernel's normal).
        for (ring, pos) in layout.rings.iter().zip(self.ring_contact.iter_mut()) {
            let us = target_disp(ring.dofs, f.stator_u(ring.stator));
            let uc = ring.rotor_dofs.map(|i| f.rotor_u[i]);
            let n = pair_state(&ring.target(), 0.0, uc, us, 0.0).n;
            *pos = [
                ring.center0[0] + ring.inner_radius * n[0],
                ring.center0[1] + ring.inner_radius * n[1],
                ring.z,
            ];
            let c = ring.first_circle_point;
            self.displacement[c..=c + RING_POINTS].fill([us[0], us[1], 0.0]);
        }
        self.contact_force.fill([0.0; 3]);
        self.pair_p.fill(0.0);
        self.pair_force.fill([0.0; 2]);
        self.pair_normal.fill([0.0; 2]);
        self.station_force.fill([0.0; 2]);
        for p in f.pairs {
            if let Some(i) = layout.pair_index(p.stator, p.node) {
                self.pair_p[i] += p.p;
                self.pair_force[i][0] += p.force[0];
                self.pair_force[i][1] += p.force[1];
                self.pair_normal[i] = p.n;
                let slot = layout.pairs[i];
                for c in 0..2 {
                    self.contact_force[slot.node_point][c] += p.force[c];
                    self.contact_force[slot.rotor_point][c] -= p.force[c];
                }
            }
            self.station_force[p.station][0] -= p.force[0];
            self.station_force[p.station][1] -= p.force[1];
        }
        if let (Some(depth), false) = (self.worn_depth.as_mut(), f.worn.is_empty()) {
            // The candidates' order: stator by stator, target by target.
            let mut ci = 0;
            for (k, s) in case.stators.iter().enumerate() {
                for tg in &s.targets {
                    if let (Target::Node { node, .. }, Some(h)) = (tg, f.worn.get(ci)) {
                        depth[layout.stator_first_point[k] + node] = *h;
                    }
                    ci += 1;
                }
            }
        }
        for (k, s) in case.stators.iter().enumerate() {
            if s.elements.is_empty() {
                continue;
            }
            let ef = s.element_forces(f.stator_u(k));
            for (e, (force, stress)) in ef.into_iter().enumerate() {
                if let Some(c) = layout.element_cells[k][e] {
                    self.axial_force[c] = force;
                    self.stress[c] = stress;
                    self.strain[c] = element_strain(&s.elements[e], stress);
                }
            }
        }
    }
}
