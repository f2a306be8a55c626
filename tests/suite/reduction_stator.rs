//! Craig–Bampton reduction of a meshed stator with mass (`[run.reduction] stators = true`,
//! issue 15 item 2, docs/IMPLICIT.md §7.2): the fixed-interface modes of the sparse subspace
//! iteration against a dense eigensolution, the reduced frequencies against the full model's,
//! the static flexibility at the contact DOFs, the full field `u = T q`, a rub run reduced
//! against the full explicit one, and the scene key's errors.

use crate::common;

use common::{file_model, repo};
use nalgebra::DMatrix;
use rubsim::model::fe_rotor::dense;
use rubsim::model::stator::reduce::ReducedStator;
use rubsim::model::{Model, StatorModel};
use rubsim::scene;
use std::path::Path;

const ANNULUS: &str = "scenes/stators/annulus.toml";
/// The annulus with mass on a coarse mesh: 128 free DOFs, 32 contact nodes (64 contact DOFs).
const SMALL: [&str; 3] = [
    "stator.0.density=1200",
    "stator.0.parameters.n=32",
    "stator.0.parameters.h=0.01",
];

fn small_model(extra: &[&str]) -> Model {
    let mut sets: Vec<&str> = SMALL.to_vec();
    sets.extend_from_slice(extra);
    file_model(Path::new(&repo(ANNULUS)), &sets).1
}

/// The placed stator of the small annulus at ω/ω_n = 1.2 (full model).
fn small_stator() -> StatorModel {
    stator_with(&[])
}

/// The placed stator of the small annulus with `extra` overrides at ω/ω_n = 1.2.
fn stator_with(extra: &[&str]) -> StatorModel {
    let model = small_model(extra);
    let case = model.case(1.2 * model.rotor.natural_frequency()).unwrap();
    case.stators[0].clone()
}

/// Ascending ω (rad/s) of `K φ = ω² M φ`, dense.
fn dense_frequencies(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Vec<f64> {
    let minv_sqrt = DMatrix::from_diagonal(&m.diagonal().map(|v| 1.0 / v.sqrt()));
    let a = &minv_sqrt * k * &minv_sqrt;
    let a = (&a + a.transpose()) * 0.5;
    let mut w: Vec<f64> = a
        .symmetric_eigen()
        .eigenvalues
        .iter()
        .map(|l| l.max(0.0).sqrt())
        .collect();
    w.sort_by(f64::total_cmp);
    w
}

#[test]
fn the_fixed_interface_modes_are_the_dense_eigensolutions() {
    let s = small_stator();
    assert!(s.m.is_diagonal(), "lumped mass");
    let (k, m) = (dense(&s.k), dense(&s.m));
    let cut = 4.0e5;
    let red = ReducedStator::new(&s, cut).unwrap();
    let ii = &red.interior;
    let kii = DMatrix::from_fn(ii.len(), ii.len(), |r, c| k[(ii[r], ii[c])]);
    let mii = DMatrix::from_fn(ii.len(), ii.len(), |r, c| m[(ii[r], ii[c])]);
    let wref = dense_frequencies(&kii, &mii);
    let below = wref.iter().filter(|w| **w < cut).count();
    assert!(
        below >= 4,
        "{below} fixed-interface modes below the cut-off"
    );
    assert_eq!(
        red.modes.len(),
        below,
        "every mode below the cut-off, no other"
    );
    for (i, (w, wr)) in red.modes.iter().zip(&wref).enumerate() {
        let e = (w - wr).abs() / wr;
        assert!(
            e < 1e-9,
            "fixed-interface mode {i}: {w} against {wr} (error {e:e})"
        );
    }
}

#[test]
fn the_reduced_frequencies_bound_the_full_models_and_converge_with_the_cutoff() {
    // Finer through the wall than the small annulus: a spread of interior modes to cut.
    let s = stator_with(&["stator.0.parameters.h=0.003"]);
    let full = dense_frequencies(&dense(&s.k), &dense(&s.m));
    let mut last = f64::INFINITY;
    for c in [2.0, 3.0, 4.0] {
        let cut = c * full[0];
        let red = ReducedStator::new(&s, cut).unwrap();
        assert_eq!(red.rdof(), red.boundary.len() + red.modes.len());
        // Rayleigh–Ritz: every reduced frequency is at or above the full one of its rank.
        for (i, w) in red.frequencies.iter().enumerate() {
            assert!(
                *w >= full[i] * (1.0 - 1e-9),
                "cut {cut}: ω_r,{i} = {w} < {}",
                full[i]
            );
        }
        // The full model's modes below 0.6 ω_cut, reproduced.
        let n = full.iter().filter(|w| **w < 0.6 * cut).count();
        assert!(n >= 1, "cut {cut}");
        let err = (0..n)
            .map(|i| (red.frequencies[i] - full[i]) / full[i])
            .fold(0.0, f64::max);
        assert!(
            err < 5e-2,
            "cut {cut}: largest error below 0.6 ω_cut {err:e}"
        );
        // A higher cut-off keeps more modes and lowers the error of the lowest mode.
        let e0 = (red.frequencies[0] - full[0]) / full[0];
        assert!(
            e0 < last || e0 < 1e-12,
            "cut {cut}: lowest-mode error {e0:e} not below {last:e}"
        );
        eprintln!(
            "cut {c} ω_1: {} modes, r = {} of {}, lowest-mode error {e0:.2e}, largest below 0.6 ω_cut {err:.2e}, ω_max {:.4e} (full {:.4e})",
            red.modes.len(),
            red.rdof(),
            s.ndof,
            red.omega_max(),
            full.last().unwrap()
        );
        last = e0;
        // The highest mode of the reduced model lies below the full model's.
        assert!(red.omega_max() <= *full.last().unwrap() * (1.0 + 1e-9));
    }
}

#[test]
fn the_static_flexibility_at_the_contact_dofs_is_the_full_models() {
    let s = small_stator();
    let red = ReducedStator::new(&s, 3.0e5).unwrap();
    let kinv = dense(&s.k).cholesky().unwrap().inverse();
    let fr = red.boundary_flexibility().unwrap();
    let b = &red.boundary;
    assert_eq!(b, &s.contact_dofs());
    let scale = (0..b.len()).map(|i| kinv[(b[i], b[i])]).fold(0.0, f64::max);
    for i in 0..b.len() {
        for j in 0..b.len() {
            let e = (fr[(i, j)] - kinv[(b[i], b[j])]).abs() / scale;
            assert!(
                e < 1e-9,
                "({i}, {j}): {} against {}",
                fr[(i, j)],
                kinv[(b[i], b[j])]
            );
        }
    }
}

#[test]
fn the_full_field_is_t_q() {
    let s = small_stator();
    let red = ReducedStator::new(&s, 3.0e5).unwrap();
    let (k, m) = (dense(&s.k), dense(&s.m));
    let (nb, nm, n) = (red.boundary.len(), red.modes.len(), s.ndof);
    let mut scratch = red.expand_scratch();
    let mut u = vec![0.0; n];
    // A boundary coordinate: the constraint mode, K u = 0 on every interior row.
    let mut q = vec![0.0; red.rdof()];
    q[3] = 1e-5;
    red.expand(&q, &mut u, &mut scratch);
    let uv = nalgebra::DVector::from_column_slice(&u);
    let f = &k * &uv;
    let fmax = f.amax();
    assert!(fmax > 0.0);
    for &d in &red.interior {
        assert!(f[d].abs() < 1e-9 * fmax, "interior force {}", f[d]);
    }
    assert_eq!(u[red.boundary[3]], 1e-5);
    // A modal coordinate: a fixed-interface mode, K u = ω² M u on the interior rows and zero
    // at the boundary.
    assert!(nm > 0);
    let mut q = vec![0.0; red.rdof()];
    q[nb] = 1.0;
    red.expand(&q, &mut u, &mut scratch);
    let uv = nalgebra::DVector::from_column_slice(&u);
    let r = &k * &uv - (&m * &uv) * red.modes[0].powi(2);
    let fk = (&k * &uv).amax();
    for &d in &red.interior {
        assert!(r[d].abs() < 1e-7 * fk, "modal residual {}", r[d]);
    }
    for &d in &red.boundary {
        assert_eq!(u[d], 0.0);
    }
    // Mass-normalised: φᵀ M φ = 1.
    let mm = (uv.transpose() * &m * &uv)[(0, 0)];
    assert!((mm - 1.0).abs() < 1e-9, "{mm}");
}

/// Extents, contact fraction and steps of the small annulus at ω/ω_n = 1.2, forward
/// increment at Δt = 4e-6 s (below the full model's stability limit, 4.84e-6 s), 4
/// revolutions; `extra`: the reduction's keys.
fn annulus_run(extra: &[&str]) -> ([f64; 4], f64) {
    let mut sets: Vec<&str> = vec![
        "run.revolutions=4",
        "run.transient_revolutions=2",
        "run.error_estimate=false",
        "run.integrator=\"forward_increment\"",
        "run.dt=4e-6",
        // The orbit is not periodic: a fixed window, not lengthened for the 0-1 test, so that
        // the full and reduced runs are compared over the same 4 revolutions.
        "run.classify_revolutions=0",
    ];
    sets.extend_from_slice(extra);
    let model = small_model(&sets);
    let mut all: Vec<&str> = SMALL.to_vec();
    all.extend_from_slice(&sets);
    let ls = common::load(&repo(ANNULUS), &all);
    let mut s = common::settings(&ls);
    s.step.integrator = rubsim::time::Scheme::ForwardIncrement;
    let r = rubsim::analysis::run_speed(&model, &s.request(1.2), rubsim::analysis::Keep::default())
        .unwrap();
    (r.extents_nd, r.contact_fraction)
}

#[test]
#[ignore = "slow tier (scripts/test-slow.sh): full and reduced runs of a stator with mass at the explicit limit"]
fn a_rub_with_every_mode_kept_is_the_full_run_and_the_default_cutoff_is_close() {
    use rubsim::analysis::{extents_error, ExtentsScale};
    let (ef, cf) = annulus_run(&[]);
    assert!(cf > 0.3, "the rotor rubs: contact fraction {cf}");
    // Every fixed-interface mode kept (the basis spans the whole space): the loop of the
    // reduced stator is the full stator's, up to round-off in a rubbing orbit.
    let (ea, _) = annulus_run(&["run.reduction.stators=true", "run.reduction.cutoff=1e8"]);
    let e_all = extents_error(&ea, &ef, ExtentsScale::Largest);
    assert!(e_all < 1e-4, "every mode kept: extents error {e_all:e}");
    // The default cut-off (2 ω_c, no fixed-interface mode of this stator below it: static
    // condensation on the contact DOFs with the constraint modes' mass).
    let (ed, _) = annulus_run(&["run.reduction.stators=true"]);
    let e_def = extents_error(&ed, &ef, ExtentsScale::Largest);
    assert!(e_def < 1e-2, "default cut-off: extents error {e_def:e}");
}

#[test]
fn run_reduction_stators_is_checked_with_file_key_and_line() {
    let text = std::fs::read_to_string(repo(ANNULUS)).unwrap();
    for (sets, key, words) in [
        // A massless stator: nothing to reduce.
        (
            vec!["run.reduction.stators=true"],
            "run.reduction.stators",
            "has mass",
        ),
        // A Jeffcott rotor is not reduced.
        (
            vec![
                "stator.0.density=1200",
                "run.reduction.stators=true",
                "run.reduction.rotor=true",
            ],
            "run.reduction.rotor",
            "FE rotor",
        ),
        // Nothing asked.
        (
            vec!["stator.0.density=1200", "run.reduction={}"],
            "run.reduction",
            "stators = true",
        ),
    ] {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let err = match scene::parse(Path::new("t.toml"), &text, &sets) {
            Err(e) => e.to_string(),
            Ok(ls) => match Model::from_scene(&ls) {
                Err(e) => e.to_string(),
                Ok(_) => panic!("{sets:?} accepted"),
            },
        };
        assert!(
            err.contains(key) && err.contains("t.toml") && err.contains(words),
            "{err}"
        );
    }
}

#[test]
fn check_reports_the_stators_cutoff_and_basis() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rubsim"))
        .current_dir(repo(""))
        .args(["check", ANNULUS])
        .args(SMALL.iter().flat_map(|s| ["--set", s]))
        .args([
            "--set",
            "run.reduction.stators=true",
            "--set",
            "run.reduction.cutoff=4e5",
            // The reduced basis is reported whatever sets the step; the step choice's pilot
            // runs (minutes of CPU on this stator with mass) are tested in tests/suite/autostep.rs
            // and tests/suite/reduction_auto.rs.
            "--set",
            "run.auto_step=false",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find(|l| l.contains("reduced (`run.reduction.stators`"))
        .unwrap_or_else(|| panic!("{text}"));
    for w in [
        "cut-off ω_cut = 4.0000e5 rad/s",
        "64 boundary (contact) DOFs",
        "instead of 128",
        "explicit limit",
    ] {
        assert!(line.contains(w), "{w}: {line}");
    }
}

/// The budget counts a reduced stator by its r reduced DOFs and its dense r × r operators, not
/// by its mesh (issue 15: the resource estimate of a reduced run).
#[test]
fn the_budget_counts_a_reduced_stator_by_its_reduced_dofs() {
    use rubsim::time::budget::{estimate, NS_DENSE_ENTRY, NS_ROTOR_DOF, NS_STATOR_DOF, NS_STEP};
    let sets = ["run.dt=4e-6", "run.integrator=\"forward_increment\""];
    let budget = |extra: &[&str]| {
        let mut all = sets.to_vec();
        all.extend_from_slice(extra);
        let model = small_model(&all);
        let ls = common::load(&repo(ANNULUS), &[SMALL.as_slice(), &all].concat());
        let mut s = common::settings(&ls);
        s.step.integrator = rubsim::time::Scheme::ForwardIncrement;
        let prep = rubsim::analysis::prepare(&model, &s.request(1.2)).unwrap();
        let r = prep.case.stators[0].reduced.as_ref().map(|r| r.rdof());
        (
            estimate(&prep.case, &prep.plan, false),
            r,
            prep.case.stators[0].ndof,
        )
    };
    let (full, none, n) = budget(&[]);
    assert!(none.is_none());
    let ns = |dof: f64, dense: f64| {
        (NS_STEP + NS_ROTOR_DOF * 2.0 + NS_STATOR_DOF * dof + NS_DENSE_ENTRY * dense) * 1e-9
    };
    assert!((full.step_s - ns(n as f64, 0.0)).abs() < 1e-15, "{full:?}");
    // The default cut-off: the 64 boundary DOFs of the 128 (no fixed-interface mode below it).
    let (red, r, n2) = budget(&["run.reduction.stators=true"]);
    let r = r.expect("reduced");
    assert_eq!(n2, n);
    assert!(r < n, "r = {r} of {n}");
    let rf = r as f64;
    assert!(
        (red.step_s - ns(rf, rf * rf)).abs() < 1e-15,
        "{red:?}: r = {r}"
    );
    assert_eq!(red.steps, full.steps, "the same plan");
    // The dense operators are in the memory figure.
    assert!(red.matrix_bytes >= full.matrix_bytes + 5.0 * 8.0 * rf * rf);
}

/// The steel seal ring with mass of the 10⁵-DOF benchmark (docs/PERFORMANCE.md) on a coarse
/// mesh: 64 contact nodes, h = 1 cm, 386 free DOFs.
const CASING: &str = "scenes/stators/bench_casing_mass.toml";
const CASING_COARSE: [&str; 2] = ["stator.0.parameters.ni=64", "stator.0.parameters.h=0.01"];

/// The observed node's recorded displacements over `revs` revolutions from the scene's initial
/// state (no steady-state extension, as `examples/stator_mass_bench.rs` runs them), and the
/// steps taken; `extra`: overrides after the coarse mesh's.
fn casing_history(revs: usize, extra: &[&str]) -> (Vec<[f64; 2]>, usize) {
    let mut sets: Vec<&str> = CASING_COARSE.to_vec();
    sets.extend_from_slice(extra);
    let (ls, model) = file_model(Path::new(&repo(CASING)), &sets);
    let nu = ls
        .scene
        .run
        .speed_ratio
        .expect("the scene sets run.speed_ratio");
    let case = model.case(nu * model.rotor.natural_frequency()).unwrap();
    let s = common::settings(&ls);
    let mut plan = rubsim::time::plan_steps(&case, &s.step).unwrap();
    plan.steps = plan.steps_per_rev * revs;
    plan.steady_from = plan.steady_from.min(plan.steps);
    let st = rubsim::time::Stepper::new(&case, s.step.integrator, &plan, s.initial).unwrap();
    let (rec, stats) = st.run(None).unwrap();
    (rec.observed, stats.steps)
}

#[test]
#[ignore = "slow tier (scripts/test-slow.sh): the reduced-stator benchmark against its full explicit run"]
fn the_steel_casing_benchmark_reduced_and_implicit_is_the_full_explicit_run_and_bounded() {
    if !common::meshes::gmsh_wanted() {
        return;
    }
    // Full mesh, forward increment at its stability limit; reduced (Craig–Bampton on the 128
    // contact DOFs) and generalised-α (ρ∞ = 0) at the paper rule's Δt: 2 revolutions from the
    // same state, the first impact and the transient into the full annular rub.
    let (full, nf) = casing_history(2, &[]);
    let red_keys = [
        "run.integrator=\"generalized_alpha\"",
        "run.reduction.stators=true",
    ];
    let (red, nr) = casing_history(2, &red_keys);
    assert_eq!(full.len(), red.len(), "the same recording instants");
    assert!(
        nf > nr,
        "the reduced implicit run takes fewer steps: {nr} against {nf}"
    );
    let r = |u: &[f64; 2]| u[0].hypot(u[1]);
    let umax = full.iter().map(r).fold(0.0, f64::max);
    let clearance = 5.0e-5;
    assert!(
        umax > clearance,
        "the rotor reaches the bore: largest |u| {umax:e} m"
    );
    let d: Vec<f64> = full
        .iter()
        .zip(&red)
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]) / umax)
        .collect();
    let max = d.iter().copied().fold(0.0, f64::max);
    let rms = (d.iter().map(|v| v * v).sum::<f64>() / d.len() as f64).sqrt();
    // Measured 9.0e-3 and 2.7e-3 (3.6e3 DOF at the benchmark's mesh: 5.0e-3 and 1.4e-3).
    assert!(
        max < 1.5e-2 && rms < 5e-3,
        "reduced generalised-α against full explicit: max {max:e}, rms {rms:e} of the orbit"
    );
    // Bounded: over 6 revolutions the rotor stays at the bore, pressed a few µm into the ring
    // (measured: largest |u| over the 6th revolution 1.066 δ, smallest 0.71 δ: still bouncing
    // on part of the orbit), where μ = 0.1 whirls away to metres in every scheme (the scene's
    // header).
    let (long, _) = casing_history(6, &red_keys);
    let spr = long.len() / 6;
    let last = long[long.len() - spr..].iter().map(r).fold(0.0, f64::max);
    assert!(
        last > clearance && last < 1.2 * clearance,
        "the 6th revolution stays at the bore: largest |u| {last:e} m"
    );
}
