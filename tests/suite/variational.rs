//! The variational monodromy (`time::Tangent`, `analysis::periodic::Monodromy`): the
//! multipliers shooting reports, carried along one run of the map with each step's contact
//! linearised on its own active set, against the central differences of whole maps (issue 29's
//! verification) on orbits in contact of both explicit schemes, a ring, a meshed-stator scene
//! and an FE rotor; the free rotor's against the scheme's propagator in closed form; and the
//! scenes whose step has no linearisation keep the differences and say so.

use crate::common;
use common::{repo, set_distance};
use nalgebra::DMatrix;
use rubsim::analysis::periodic::{Difference, Monodromy};
use rubsim::analysis::{self, periodic};

const PAPER: &str = "scenes/paper/partial_rub.toml";

/// The orbit of `scene` at ν (period `k`, or the settled run's) with overrides.
fn shoot(
    scene: &str,
    nu: f64,
    k: Option<usize>,
    sets: &[&str],
) -> (analysis::Prepared, periodic::PeriodicOrbit) {
    let (ls, m) = common::file_model(&repo(scene), sets);
    let prep = analysis::prepare(&m, &common::settings(&ls).request(nu)).expect("prepare");
    let o = periodic::shoot(&prep, k).expect("shoot");
    (prep, o)
}

/// The largest entry difference of two monodromies relative to the largest entry of `b`,
/// and their multipliers' set distance.
fn distance(a: &DMatrix<f64>, b: &DMatrix<f64>) -> (f64, f64) {
    let rho = |m: &DMatrix<f64>| -> Vec<[f64; 2]> {
        m.complex_eigenvalues()
            .iter()
            .map(|c| [c.re, c.im])
            .collect()
    };
    ((a - b).amax() / b.amax(), set_distance(&rho(a), &rho(b)))
}

/// The variational monodromy of `o` (its contact DOFs perturbed by `rel` of max |x|).
fn variational(prep: &analysis::Prepared, o: &periodic::PeriodicOrbit, rel: f64) -> DMatrix<f64> {
    periodic::monodromy_variational(prep, o, rel)
        .expect("variational")
        .expect("a linearisable step")
        .0
}

/// The variational monodromy of `o` at shooting's perturbation against the differences of
/// whole maps of step `rel` (of max |x|).
fn against_differences(
    prep: &analysis::Prepared,
    o: &periodic::PeriodicOrbit,
    rel: f64,
) -> (f64, f64) {
    let d =
        periodic::monodromy_differences(prep, o, rel, Difference::Central).expect("differences");
    distance(&variational(prep, o, 1e-4), &d)
}

/// The paper case's orbits in contact (the default, collocated scheme) — period 1 at ν 1.7 (stable) and 2.3 (unstable through
/// −1), period 2 at 3.1, period 3 at 4.9 —: the reported monodromy is the variational one; it
/// does not depend on its perturbation (10⁻³ against 10⁻⁵ of max |x|: 1e-8 of the entries) and
/// is the limit of the whole maps' differences as their step falls — at 3·10⁻⁶ of max |x| they
/// agree to 5e-8 (measured 4e-9). At shooting's former step of differences, 10⁻⁵, a
/// perturbation moves a contact event across a step at ν 3.1 and the differences miss by 3e-3
/// (multipliers by 2e-2): what the variational monodromy, linearised on each step's own active
/// set, cannot do.
#[test]
fn paper_case_variational_monodromy_is_the_limit_of_the_differences() {
    for (nu, k) in [(1.7, 1), (2.3, 1), (3.1, 2), (4.9, 3)] {
        let (prep, o) = shoot(PAPER, nu, Some(k), &[]);
        assert!(o.converged, "ν {nu}: {o:?}");
        assert!(o.orbit.contact_fraction > 0.05, "ν {nu}: in contact");
        assert_eq!(o.monodromy, Monodromy::Variational);
        let lin = o.linearisation.expect("linearisation counters");
        assert!(lin.contact_steps > 0, "{lin:?}");
        let (own, _) = distance(&variational(&prep, &o, 1e-3), &variational(&prep, &o, 1e-5));
        let (fine, rho) = against_differences(&prep, &o, 3e-6);
        let (coarse, rho_coarse) = against_differences(&prep, &o, 1e-5);
        eprintln!(
            "ν {nu} (period {k}): h 1e-3 vs 1e-5 {own:.1e}; differences at 3e-6: entries {fine:.1e}, multipliers {rho:.1e}; at 1e-5: {coarse:.1e}, {rho_coarse:.1e}; {lin:?}"
        );
        assert!(own < 1e-8, "ν {nu}: perturbation dependence {own:e}");
        assert!(fine < 5e-8, "ν {nu}: entries {fine:e}");
        assert!(rho < 1e-6, "ν {nu}: multipliers {rho:e}");
    }
}

/// The forward-increment scheme (the paper's own; the default is the collocated one) has its
/// multipliers' increments linearised the same way: the paper case at ν 1.7 and 3.1 with
/// `run.integrator = "forward_increment"`.
#[test]
fn forward_increment_variational_monodromy_equals_the_differences() {
    for (nu, k) in [(1.7, 1), (3.1, 2)] {
        let (prep, o) = shoot(PAPER, nu, Some(k), &["run.integrator=forward_increment"]);
        assert!(
            o.converged && o.orbit.contact_fraction > 0.05,
            "ν {nu}: {o:?}"
        );
        assert_eq!(o.monodromy, Monodromy::Variational);
        let (entries, rho) = against_differences(&prep, &o, 3e-6);
        eprintln!("forward increment ν {nu}: entries {entries:.2e}, multipliers {rho:.2e}");
        assert!(entries < 1e-6 && rho < 1e-6, "ν {nu}: {entries:e} {rho:e}");
    }
}

/// Without contact the map is linear and the variational monodromy is the scheme's own
/// propagator exactly: the free paper rotor's multipliers are `z^N` of the central-difference
/// step's roots to round-off (1e-10, measured 9e-12; the differences of whole maps reach 1e-8).
#[test]
fn free_rotor_variational_multipliers_are_the_propagator_to_round_off() {
    let (_, o) = shoot(PAPER, 1.7, Some(1), &["stator.0.clearance_nd=50"]);
    assert!(o.converged && o.orbit.contact_fraction == 0.0);
    assert_eq!(o.monodromy, Monodromy::Variational);
    let (_, m) = common::file_model(&repo(PAPER), common::NO_SETS);
    let wn = m.rotor.natural_frequency();
    let (dt, n) = (o.orbit.plan.dt, o.orbit.plan.steps_per_rev as f64);
    let a = 0.2 * wn * dt;
    let (qa, qb, qc) = (1.0 + a, wn * wn * dt * dt - 2.0, 1.0 - a);
    let disc = qb * qb - 4.0 * qa * qc;
    let z = [-qb / (2.0 * qa), (-disc).sqrt() / (2.0 * qa)];
    let (r, ang) = (z[0].hypot(z[1]), z[1].atan2(z[0]));
    let zn = [r.powf(n) * (n * ang).cos(), r.powf(n) * (n * ang).sin()];
    let expected = [zn, [zn[0], -zn[1]], zn, [zn[0], -zn[1]]];
    let d = set_distance(&o.multipliers, &expected);
    eprintln!("free rotor: |ρ − z^N| ≤ {d:.2e}");
    assert!(d < 1e-10, "{:?} against {expected:?}: {d:e}", o.multipliers);
}

/// A ring (exact ring kinematics re-aligned within the step): the variational monodromy
/// against the central differences.
#[test]
fn ring_variational_monodromy_equals_the_differences() {
    let scene = "scenes/periodic/ring_hysteresis.toml";
    let (prep, o) = shoot(scene, 2.8, Some(1), &["run.integrator=forward_increment"]);
    assert!(o.converged && o.orbit.contact_fraction > 0.05, "{o:?}");
    assert_eq!(o.monodromy, Monodromy::Variational);
    let (entries, rho) = against_differences(&prep, &o, 3e-6);
    eprintln!(
        "ring ν 2.8: entries {entries:.2e}, multipliers {rho:.2e}, {:?}",
        o.linearisation
    );
    assert!(entries < 1e-6 && rho < 1e-6, "{entries:e} {rho:e}");
}

/// The FE paper rotor at ν 1.7 sits on a contact event: the map has a kink there, and its
/// one-sided derivatives differ (by 8e-3 of the largest entry, measured, in the columns of the
/// disk node's y displacement at both time levels), so the central differences, their mean,
/// converge to neither. The variational monodromy, each step linearised on its own active set
/// (two columns' perturbations shrunk past an event near their step), is a one-sided
/// derivative of the map: each of its columns is the forward or the backward differences' of
/// step 10⁻⁷ to 1e-5 (measured 2e-6), while the two sides differ by more than 1e-3 on some
/// column.
#[test]
fn fe_rotor_on_a_kink_variational_monodromy_is_one_sided() {
    let (prep, o) = shoot("scenes/fe/paper_rotor_rub.toml", 1.7, Some(1), &[]);
    assert!(o.converged && o.orbit.contact_fraction > 0.05, "{o:?}");
    assert_eq!(o.monodromy, Monodromy::Variational);
    let v = variational(&prep, &o, 1e-4);
    let side = |kind| periodic::monodromy_differences(&prep, &o, 1e-7, kind).expect("differences");
    let (fwd, bwd) = (side(Difference::Forward), side(Difference::Backward));
    let scale = fwd.amax();
    let (mut worst, mut kink) = (0.0_f64, 0.0_f64);
    for j in 0..v.ncols() {
        let f = (v.column(j) - fwd.column(j)).amax() / scale;
        let b = (v.column(j) - bwd.column(j)).amax() / scale;
        worst = worst.max(f.min(b));
        kink = kink.max((fwd.column(j) - bwd.column(j)).amax() / scale);
    }
    eprintln!("FE rotor ν 1.7: worst column off its nearer side {worst:.2e}; sides differ by {kink:.2e}; {:?}", o.linearisation);
    assert!(kink > 1e-3, "the map is smooth here after all: {kink:e}");
    assert!(worst < 1e-5, "a column matches neither side: {worst:e}");
}

/// A step with no linearisation — here the rod with mass, solved by forward increment within
/// the step — keeps the central differences of whole maps, and the orbit says which it took.
#[test]
fn a_stator_with_mass_keeps_the_differences_and_says_so() {
    let (_, o) = shoot(PAPER, 1.7, Some(1), &["stator.0.density=7800"]);
    assert!(o.converged && o.orbit.contact_fraction > 0.05, "{o:?}");
    assert_eq!(o.monodromy, Monodromy::FiniteDifference);
    assert!(o.linearisation.is_none());
}

/// The paper case's period-1 orbit doubles between ν 2.243 and 2.2445 by a jump: one step
/// fewer in contact a revolution (50 → 49) and the largest multiplier leaps from 0.983 to
/// 1.092 (−ρ: through −1). Both monodromies are the limit of the differences (at 10⁻⁶ of
/// max |x|: 1e-8 of the entries, measured 1.4e-9), which at shooting's former step 10⁻⁵
/// straddle the event and put the crossing at 2.2414 (ρ 0.985 at 2.2414 where it is 0.973):
/// the doubling reported before the variational monodromy.
#[test]
fn the_period_doubling_of_the_paper_case_is_a_jump_at_a_contact_event() {
    let largest = |m: &DMatrix<f64>| {
        m.complex_eigenvalues()
            .iter()
            .map(|c| c.re.hypot(c.im))
            .fold(0.0, f64::max)
    };
    let mut seen = Vec::new();
    for nu in [2.243, 2.2445] {
        let (prep, o) = shoot(PAPER, nu, Some(1), &[]);
        assert!(o.converged, "ν {nu}");
        let v = variational(&prep, &o, 1e-4);
        let d = periodic::monodromy_differences(&prep, &o, 1e-6, Difference::Central).unwrap();
        let (entries, _) = distance(&v, &d);
        let lin = o.linearisation.expect("variational");
        eprintln!(
            "ν {nu}: |ρ₁| {:.4} (differences at 1e-6: {:.4}, entries {entries:.1e}); {lin:?}",
            largest(&v),
            largest(&d)
        );
        assert!(entries < 1e-8, "ν {nu}: {entries:e}");
        assert!((largest(&v) - largest(&d)).abs() < 1e-6);
        seen.push((largest(&v), lin.contact_steps, o.multipliers[0][0]));
    }
    assert!(seen[0].0 < 0.99 && seen[1].0 > 1.05, "{seen:?}");
    assert_eq!((seen[0].1, seen[1].1), (50, 49), "{seen:?}");
    assert!(seen[1].2 < 0.0, "through −1: {seen:?}");
}

/// A meshed stator (`scenes/stators/annulus.toml`: the paper rotor in a polymer annulus of 128
/// Q4 elements around, massless) in full annular rub at ν 1.2: the rotor slides past the
/// boundary nodes and the pairs carrying force change every few steps, so that many columns'
/// perturbations cross an event near the step. Shrinking those perturbations (up to 100-fold)
/// keeps the monodromy independent of its perturbation — 10⁻³ against 10⁻⁵ of max |x|: 1e-4
/// of the entries, measured 6.7e-7, where taking them one-sided and across left 1e-2 (entries
/// of 150 whose multipliers are 0.17) — and equal to the central differences of whole maps at
/// 10⁻⁹ to 1e-4 of the entries (measured 1.4e-5: at 10⁻⁷ and above the differences cross
/// events, at 10⁻¹⁰ their round-off grows); the multipliers to 2e-3 (measured 7.3e-4, the
/// differences' round-off through a monodromy of large entries and small eigenvalues).
#[test]
fn a_meshed_stator_variational_monodromy_is_independent_of_its_perturbation() {
    if !common::meshes::gmsh_wanted() {
        return;
    }
    let (prep, o) = shoot("scenes/stators/annulus.toml", 1.2, Some(1), &[]);
    assert!(o.converged && o.orbit.contact_fraction > 0.5, "{o:?}");
    assert_eq!(o.monodromy, Monodromy::Variational);
    let lin = o.linearisation.expect("variational");
    assert!(lin.shrunk > 0, "{lin:?}");
    let (v3, v5) = (variational(&prep, &o, 1e-3), variational(&prep, &o, 1e-5));
    let (own, own_rho) = distance(&v3, &v5);
    let d = periodic::monodromy_differences(&prep, &o, 1e-9, Difference::Central).unwrap();
    let (entries, rho) = distance(&variational(&prep, &o, 1e-4), &d);
    eprintln!("annulus ν 1.2: h 1e-3 vs 1e-5 {own:.1e} (multipliers {own_rho:.1e}); differences at 1e-9: entries {entries:.1e}, multipliers {rho:.1e}; {lin:?}");
    assert!(own < 1e-4 && own_rho < 1e-4, "{own:e} {own_rho:e}");
    assert!(entries < 1e-4 && rho < 2e-3, "{entries:e} {rho:e}");
}
