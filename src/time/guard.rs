//! The divergence guard's bounds per rotor DOF and the names of the DOFs in its errors.

use super::plan::Initial;
use crate::model::Case;

/// Factor between a DOF's divergence bound and the run's scale for it.
const DIVERGENCE_FACTOR: f64 = 1e4;

/// The divergence bound of every rotor DOF: 10⁴ times the run's scale for it, so that a
/// response that grows past it can only be an instability, wherever the stations and the
/// observed node are.
///
/// * displacements (`u_x`, `u_y`, `u_z`, pedestals; m): the length scale `L`, the largest of |Z0(ω)| over
///   every rotor node, the finite clearances and the initial displacement (at least 1 nm);
/// * rotations (`θ_x`, `θ_y`, `θ_z`; rad): the largest forced tilt over every node, and at
///   least `L / ℓ`, ℓ the shortest distance between two rotor nodes (a relative displacement
///   `L` across the shortest element; `L` per metre for a rotor of one node).
pub(crate) fn divergence_bounds(case: &Case, init: Initial) -> Vec<f64> {
    let length = case
        .z0_max
        .max(
            case.stators
                .iter()
                .map(|s| s.clearance)
                .filter(|c| c.is_finite())
                .fold(0.0, f64::max),
        )
        .max(init.u[0].hypot(init.u[1]))
        .max(1e-9);
    let z = &case.rotor.node_z;
    let spacing = z
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min);
    let per_metre = if spacing.is_finite() { spacing } else { 1.0 };
    let tilt = case.tilt0_max.max(length / per_metre);
    let r = case.loop_rotor();
    let mut bound = vec![DIVERGENCE_FACTOR * length; r.ndof];
    let rotations = r
        .node_tilt
        .iter()
        .flatten()
        .flatten()
        .chain(r.node_torsion.iter().flatten());
    for &i in rotations {
        bound[i] = DIVERGENCE_FACTOR * tilt;
    }
    bound
}

/// The name of rotor DOF `i` (`u_y of rotor node 4`) and its unit (`m` or `rad`).
pub(crate) fn dof_name(case: &Case, i: usize) -> (String, &'static str) {
    let r = case.loop_rotor();
    let find = |list: &[Option<usize>]| list.iter().position(|d| *d == Some(i));
    let pair = |n: usize, d: [usize; 2]| d.iter().position(|x| *x == i).map(|c| (n, c));
    if let Some((n, c)) = r
        .node_dofs
        .iter()
        .enumerate()
        .find_map(|(n, d)| pair(n, *d))
    {
        (format!("u_{} of rotor node {n}", ["x", "y"][c]), "m")
    } else if let Some((n, c)) =
        (r.node_tilt.iter().enumerate()).find_map(|(n, d)| d.and_then(|d| pair(n, d)))
    {
        (format!("θ_{} of rotor node {n}", ["x", "y"][c]), "rad")
    } else if let Some(n) = find(&r.node_axial) {
        (format!("u_z of rotor node {n}"), "m")
    } else if let Some(n) = find(&r.node_torsion) {
        (format!("θ_z of rotor node {n}"), "rad")
    } else if let Some(red) = &case.reduced {
        let k = i.saturating_sub(red.statics.len());
        (format!("internal mode {k} of the reduced rotor"), "m")
    } else {
        (format!("rotor DOF {i} (a pedestal)"), "m")
    }
}
