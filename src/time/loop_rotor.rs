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

/// Adds the loads fixed in the rotor's frame ([`crate::model::rotor::RotatingLoad`]) at time
/// `t` (s) to `rhs`: at the spin angle `Ω t` of the case's constant speed, or `φ` of `spin`.
#[inline]
pub(super) fn add_rotating(
    case: &Case,
    spin: Option<crate::model::SpinState>,
    t: f64,
    rhs: &mut [f64],
) {
    let phi = spin.map_or(case.omega * t, |s| s.phi);
    case.loop_rotor().add_rotating(phi, rhs);
}

/// Most entries (steps of a revolution × unbalances) of an [`UnbalanceTable`]: 1 MiB.
const UNBALANCE_TABLE_MAX: usize = 1 << 16;

/// The constant-speed unbalance load's directions over one revolution:
/// `(cos, sin)(Ω·(kΔt) + β_u)` for each step `k` of a revolution and each unbalance `u` (phase
/// β_u), so a step reads its load instead of calling `sincos` (a tenth of a Jeffcott sweep's
/// CPU). Step `n` reads `k = n mod N`, N the steps of a revolution: Ω·NΔt = 2π to round-off
/// (the plan's Δt is a whole fraction of the revolution), so the load is the same as at
/// t = nΔt to a phase of n/N · 2π · 1e-16 rad, and exactly the same in the first revolution.
#[derive(Debug)]
pub(super) struct UnbalanceTable {
    /// Row-major `[k][u]`.
    dirs: Vec<[f64; 2]>,
    per_step: usize,
    /// Steps of a revolution (the table's rows).
    per_rev: usize,
}

impl UnbalanceTable {
    /// The table of `case` at the step `dt` (s) of a plan with `steps_per_rev` steps a
    /// revolution; `None` without unbalance, when the steps do not close the revolution (Ω·NΔt
    /// off 2π by more than 1e-12 of it) or when it would hold more than
    /// [`UNBALANCE_TABLE_MAX`] entries (a step that fine costs far more than its `sincos`).
    pub(super) fn new(case: &Case, dt: f64, steps_per_rev: usize) -> Option<Self> {
        let ub = &case.loop_rotor().unbalance;
        let w = case.omega;
        let closes = (w * dt * steps_per_rev as f64 - std::f64::consts::TAU).abs()
            <= 1e-12 * std::f64::consts::TAU;
        if ub.is_empty() || !closes || steps_per_rev * ub.len() > UNBALANCE_TABLE_MAX {
            return None;
        }
        let mut dirs = Vec::with_capacity(steps_per_rev * ub.len());
        for k in 0..steps_per_rev {
            let t = k as f64 * dt;
            dirs.extend(ub.iter().map(|u| {
                let (s, c) = crate::math::sin_cos(w * t + u.phase);
                [c, s]
            }));
        }
        Some(Self {
            dirs,
            per_step: ub.len(),
            per_rev: steps_per_rev,
        })
    }

    /// Adds the unbalance load of step `n` (t = nΔt) to `rhs`, as
    /// [`crate::model::RotorBody::add_unbalance`] does at that instant.
    #[inline]
    pub(super) fn add(&self, case: &Case, n: usize, rhs: &mut [f64]) {
        let k = n % self.per_rev;
        let dirs = &self.dirs[k * self.per_step..(k + 1) * self.per_step];
        case.loop_rotor().add_unbalance_dirs(case.omega, dirs, rhs);
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

#[cfg(test)]
mod tests {
    use super::UnbalanceTable;
    use crate::model::Model;

    /// A Jeffcott rotor with two unbalances at different phases.
    const TWO: &str = r#"
title = "two unbalances"
[rotor]
kind = "jeffcott"
mass = 1.0
stiffness = 1.0e4
damping = 1.0
[[rotor.unbalance]]
mass = 1.0e-3
radius = 0.01
[[rotor.unbalance]]
mass = 2.0e-3
radius = 0.02
phase_deg = 70.0
[run]
speed_ratio = 1.3
"#;

    /// Over five revolutions the table's load at step n is the `sincos` load at t = nΔt to a
    /// phase of round-off, exactly in the first revolution; a step that does not close the
    /// revolution gets no table.
    #[test]
    fn the_table_is_the_load_at_every_step() {
        let ls = crate::scene::parse(std::path::Path::new("t.toml"), TWO, &[]).unwrap();
        let model = Model::from_scene(&ls).unwrap();
        let case = model.case(1.3 * model.rotor.natural_frequency()).unwrap();
        let spr = 96;
        let dt = std::f64::consts::TAU / (case.omega * spr as f64);
        let table = UnbalanceTable::new(&case, dt, spr).expect("a table");
        let n_dof = case.loop_rotor().m.nrows();
        for n in 0..5 * spr {
            let (mut a, mut b) = (vec![0.0; n_dof], vec![0.0; n_dof]);
            table.add(&case, n, &mut a);
            case.loop_rotor()
                .add_unbalance(case.omega, n as f64 * dt, &mut b);
            let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
            for (x, y) in a.iter().zip(&b) {
                if n < spr {
                    assert_eq!(x, y, "step {n}");
                } else {
                    assert!((x - y).abs() <= 1e-12 * scale, "step {n}: {x} vs {y}");
                }
            }
        }
        assert!(UnbalanceTable::new(&case, dt * 1.001, spr).is_none());
    }
}
