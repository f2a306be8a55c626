//! The rotor as the loop sees it: the case's full body, or its reduction (`[run.reduction]`,
//! [`crate::model::ReducedRotor`]) in `q = [u_B; η]`. The loop loads, reads and guards the
//! loop body ([`Case::loop_rotor`]); frames get the full displacement `u = T q`.

use crate::model::Case;

/// Adds the unbalance load at time `t` (s) to `rhs`: of the case's constant speed, or of the
/// spin state `spin` (φ, Ω, Ω̇ at `t`, [`crate::model::RotorBody::add_unbalance_spin`]).
#[inline]
pub(super) fn add_unbalance(
    case: &Case,
    spin: Option<crate::model::SpinState>,
    t: f64,
    rhs: &mut [f64],
) {
    let lr = case.loop_rotor();
    match spin {
        Some(s) => lr.add_unbalance_spin(s, rhs),
        None => lr.add_unbalance(case.omega, t, rhs),
    }
}

/// Rotor DOFs the contact acts on: every station node's `[u_x, u_y]` and, with torsional
/// DOFs, its θ_z (the friction torque acts there); sorted.
pub(super) fn rotor_contact_dofs(case: &Case) -> Vec<usize> {
    let lr = case.loop_rotor();
    let mut cd: Vec<usize> = case
        .stations
        .iter()
        .flat_map(|s| lr.node_dofs[s.node])
        .collect();
    cd.extend(
        case.stations
            .iter()
            .filter_map(|s| lr.node_torsion.get(s.node).copied().flatten()),
    );
    cd.sort_unstable();
    cd.dedup();
    cd
}

/// Length of the buffer a frame's full displacement needs: the full model's DOFs when the
/// case is reduced, else 0 (the loop's own vector is the full one).
pub(super) fn full_len(case: &Case) -> usize {
    case.reduced.as_ref().map_or(0, |r| r.basis.nrows())
}

/// The full rotor displacement of a frame: `q` itself, or `u = T q` of a reduced rotor
/// written into `full` (sized by [`full_len`]; no allocation).
pub(super) fn full_displacement<'b>(case: &Case, q: &'b [f64], full: &'b mut [f64]) -> &'b [f64] {
    match &case.reduced {
        Some(r) => {
            r.expand(q, full);
            full
        }
        None => q,
    }
}
