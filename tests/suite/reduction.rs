//! Modal reduction of the FE rotor that keeps the contact exact (`[run.reduction]`, issue 15
//! item 2, docs/IMPLICIT.md §7): the reduced frequencies below the cut-off against the full
//! model's, the static flexibility at the contact DOFs, rub runs reduced against full on the FE
//! paper rotor and ROSS's rub example, the explicit step it gains, the frames mapped back to the
//! full model, and the scene key's errors.

use crate::common;

use common::{file_model, parse, repo, settings, SHORT_RUN};
use nalgebra::DMatrix;
use rubsim::analysis::{self, extents_error, ExtentsScale, Keep};
use rubsim::model::fe_rotor::dense;
use rubsim::model::{Case, Model};
use rubsim::scene;
use rubsim::time::{plan_steps, Frame, FrameSink, Scheme};
use std::path::Path;

const PAPER: &str = "scenes/fe/paper_rotor_rub.toml";
const ROSS: &str = "scenes/fe/ross_rub_example.toml";

/// The scene's model with and without `[run.reduction]` (the same scene otherwise).
fn models(path: &str, sets: &[&str]) -> (scene::LoadedScene, Model, Model) {
    let mut with = vec!["run.reduction={}"];
    with.extend_from_slice(sets);
    let (ls, reduced) = file_model(Path::new(&repo(path)), &with);
    let mut full = reduced.clone();
    full.reduction = None;
    (ls, full, reduced)
}

fn case_at(model: &Model, nu: f64) -> Case {
    model.case(nu * model.rotor.natural_frequency()).unwrap()
}

#[test]
fn the_reduced_frequencies_below_the_cutoff_are_the_full_models() {
    for (path, nu) in [(PAPER, 1.7), (PAPER, 4.9), (ROSS, 0.69)] {
        let (_, _, reduced) = models(path, &[]);
        let case = case_at(&reduced, nu);
        let red = case.reduced.as_ref().expect("reduced");
        assert!(red.modes >= 2, "{path}: {} modes", red.modes);
        let full = &red.full_frequencies;
        for (i, (w, wf)) in red.frequencies.iter().zip(full).take(red.modes).enumerate() {
            let e = (w - wf).abs() / wf;
            assert!(e < 1e-6, "{path} mode {i}: relative error {e:e}");
        }
        assert!(red.frequency_error < 1e-6, "{}", red.frequency_error);
        // Rayleigh–Ritz bounds from above: every reduced frequency is at or above the full
        // model's of the same rank, and the static columns' frequencies lie above the cut-off.
        for (i, w) in red.frequencies.iter().enumerate() {
            assert!(
                *w >= full[i] * (1.0 - 1e-9),
                "{path}: ω_r,{i} = {w} < {}",
                full[i]
            );
        }
        for w in &red.frequencies[red.modes..] {
            assert!(*w >= red.cutoff * (1.0 - 1e-9), "{path}: {w} below ω_cut");
        }
        // The loop's stability data are the reduced model's.
        assert_eq!(case.rotor_omega_max, red.omega_max());
        // The shaft's top modes are gone: 3.1e5 → 5.0e3 (1.7 ω_n), 1.6e4 (4.9 ω_n) rad/s on
        // the paper rotor; 8.6e5 → 3.4e3 on ROSS's.
        assert!(
            red.omega_max() < full.last().unwrap() / 15.0,
            "{path}: {}",
            red.omega_max()
        );
    }
}

#[test]
fn the_static_flexibility_at_the_contact_dofs_is_the_full_models() {
    for (path, nu) in [(PAPER, 3.1), (ROSS, 0.69)] {
        let (_, _, reduced) = models(path, &[]);
        let case = case_at(&reduced, nu);
        let red = case.reduced.as_ref().unwrap();
        let kfull = dense(&case.rotor.k).cholesky().unwrap();
        let fr = red.interface_flexibility().unwrap();
        let nb = red.statics.len();
        // Every station DOF is an interface DOF.
        for s in &case.stations {
            for d in case.rotor.node_dofs[s.node] {
                assert!(red.statics.contains(&d), "{path}: station DOF {d}");
            }
        }
        for (j, &d) in red.statics.iter().enumerate() {
            let mut e = DMatrix::zeros(case.rotor.ndof, 1);
            e[(d, 0)] = 1.0;
            let u = kfull.solve(&e);
            let scale = u.amax();
            for (i, &b) in red.statics.iter().enumerate() {
                let err = (fr[(i, j)] - u[(b, 0)]).abs() / scale;
                assert!(err < 1e-10, "{path}: F[{b},{d}] relative error {err:e}");
            }
            // The static deflection under that unit load is the full one everywhere:
            // T K_r⁻¹ Tᵀ e_d = K⁻¹ e_d.
            let q: Vec<f64> = (0..red.body.ndof)
                .map(|i| if i < nb { fr[(i, j)] } else { 0.0 })
                .collect();
            let kr = dense(&red.body.k).cholesky().unwrap();
            let mut rhs = DMatrix::zeros(red.body.ndof, 1);
            rhs[(j, 0)] = 1.0;
            let q_all = kr.solve(&rhs);
            let mut full_u = vec![0.0; case.rotor.ndof];
            red.expand(q_all.as_slice(), &mut full_u);
            let err = (0..case.rotor.ndof)
                .map(|i| (full_u[i] - u[(i, 0)]).abs())
                .fold(0.0, f64::max)
                / scale;
            assert!(err < 1e-10, "{path}: static deflection error {err:e}");
            assert!(q[j] > 0.0);
        }
    }
}

#[test]
fn the_explicit_stability_limit_rises_from_the_shafts_top_modes_to_the_reduced_model() {
    let (ls, full, reduced) = models(PAPER, &[]);
    let mut st = settings(&ls).step;
    st.integrator = Scheme::Collocated;
    for nu in [1.7, 3.1, 4.9] {
        let pf = plan_steps(&case_at(&full, nu), &st).unwrap();
        let pr = plan_steps(&case_at(&reduced, nu), &st).unwrap();
        // Measured: 6.4e-6 s → 3.8e-4 s at 1.7 and 3.1 ω_n (ω_max 3.1e5 → 5.0e3 rad/s),
        // 1.2e-4 s at 4.9 ω_n (a higher cut-off: 1.6e4 rad/s); the reduced step is the
        // paper's accuracy rule, 8 to 12× fewer steps.
        assert!(
            pr.limit > 15.0 * pf.limit,
            "{nu}: {} vs {}",
            pr.limit,
            pf.limit
        );
        // The paper's accuracy rule sets the step, not the stability limit.
        assert!(
            pr.dt <= pr.rule_dt && pr.rule_dt < 0.8 * pr.limit,
            "{nu}: Δt {} rule {} limit {}",
            pr.dt,
            pr.rule_dt,
            pr.limit
        );
        assert!(
            pr.steps * 7 < pf.steps,
            "{nu}: {} vs {} steps",
            pr.steps,
            pf.steps
        );
    }
}

/// Period, extents, steps and Δt of the FE paper rotor at ω/ω_n = `nu` (explicit collocated
/// scheme; Δt `dt`, or the plan's).
fn paper_run(
    model: &Model,
    ls: &scene::LoadedScene,
    nu: f64,
    dt: Option<f64>,
) -> (usize, [f64; 4], usize, f64) {
    let mut s = settings(ls);
    s.step.integrator = Scheme::Collocated;
    s.step.dt = dt;
    let r = analysis::run_speed(model, &s.request(nu), Keep::default()).unwrap();
    (r.period, r.extents_nd, r.plan.steps, r.plan.dt)
}

#[test]
fn a_rub_on_the_fe_paper_rotor_reduced_equals_the_full_run() {
    let (ls, full, reduced) = models(PAPER, &SHORT_RUN);
    for (nu, period) in [(1.7, 1), (3.1, 2), (4.9, 3)] {
        let (pf, ef, nf, dtf) = paper_run(&full, &ls, nu, None);
        // At the full run's step: the reduction's own error (the truncated modes).
        let (p1, e1, _, _) = paper_run(&reduced, &ls, nu, Some(dtf));
        // At its own step (the paper's rule, no longer capped by the shaft's top modes).
        let (p2, e2, n2, _) = paper_run(&reduced, &ls, nu, None);
        assert_eq!(pf, period, "full period at {nu}");
        assert_eq!(p1, period, "reduced period at {nu}, full run's Δt");
        assert_eq!(p2, period, "reduced period at {nu}, own Δt");
        let err1 = extents_error(&e1, &ef, ExtentsScale::Largest);
        let err2 = extents_error(&e2, &ef, ExtentsScale::Largest);
        // run.tolerance (1e-3) for the reduction alone; the implicit schemes' bound (2e-3,
        // tests/suite/implicit.rs) for the reduced run at the rule's step, which adds the rule's
        // discretisation error.
        assert!(err1 < 1e-3, "{nu}: reduction error {err1:e}");
        assert!(err2 < 2e-3, "{nu}: reduced run at its step, error {err2:e}");
        assert!(n2 * 7 < nf, "{nu}: {n2} vs {nf} steps");
    }
}

#[test]
fn the_ross_rub_example_reduced_converges_to_the_full_run_as_the_cutoff_rises() {
    // 0.5 s from rest at 1 200 rpm, generalised-α at the scene's step (5 120 steps): the
    // observed node's whole history (the housing node 12), reduced against full. The scene's
    // unbalance (2e-4 kg·m, |Z0| = 3.1e-5 m at node 12) stays inside the 79.5 µm clearance in
    // rubsim; three times it (|Z0| = 1.2 δ) rubs from the first revolutions on (~1 500
    // instants in contact).
    let s0 = ["rotor.unbalance.0.mass=6e-4"];
    let history = |m: &Model, ls: &scene::LoadedScene| {
        let nu = 125.66370614359172 / m.rotor.natural_frequency();
        let p = analysis::prepare(m, &settings(ls).request(nu)).unwrap();
        let (rec, stats) = p.integrate(&mut []).unwrap();
        (rec, stats, p.plan.steps)
    };
    let (ls, full, _) = models(ROSS, &s0);
    let (rf, sf, nf) = history(&full, &ls);
    let amp = (rf.observed.iter())
        .map(|v| v[0].hypot(v[1]))
        .fold(0.0, f64::max);
    let fmax = |r: &rubsim::time::Record| {
        (r.force.iter())
            .map(|f| f[0].hypot(f[1]))
            .fold(0.0, f64::max)
    };
    assert!(sf.contact_steps > 100, "no rub");
    // Measured largest difference over the history / largest amplitude, with the scene's
    // damping as ROSS 3 has it (bearings' C, α and β on the rotor, `rayleigh_on = "rotor"`):
    // 9.9e-4 (κ = 2, the default: 6 modes), 6.7e-4 (κ = 4: 7), 1.5e-4 (κ = 8: 11), 4.8e-6
    // (κ = 16: 15), 3.3e-6 (κ = 32: 22), printed with `-- --nocapture`; the bounds about 2×
    // those (before, with α, β on the assembled M and K and the bearings undamped: 2.1e-3,
    // 1.8e-3, 1.3e-4, 6.4e-6, 3.0e-7, κ = 2, 8, 16 under 3e-3, 2e-4, 1e-5).
    let bounds = [
        (2.0, 2e-3),
        (4.0, 1.5e-3),
        (8.0, 3e-4),
        (16.0, 1e-5),
        (32.0, 1e-5),
    ];
    for (kappa, bound) in bounds {
        let f = format!("run.reduction.cutoff_factor={kappa}");
        let (ls, _, reduced) = models(ROSS, &[s0[0], &f]);
        let (rr, sr, nr) = history(&reduced, &ls);
        assert_eq!((nf, rf.observed.len()), (nr, rr.observed.len()));
        let diff = (rf.observed.iter().zip(&rr.observed))
            .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
            .fold(0.0, f64::max);
        eprintln!(
            "κ {kappa}: history differs by {:.2e} of the largest amplitude",
            diff / amp
        );
        assert!(sr.contact_steps > 100, "κ {kappa}: no rub");
        assert!(
            diff < bound * amp,
            "κ {kappa}: history differs by {:e}",
            diff / amp
        );
        let (ff, fr) = (fmax(&rf), fmax(&rr));
        assert!(
            (ff - fr).abs() < 2e-2 * ff,
            "κ {kappa}: peak force {fr} vs {ff}"
        );
    }
}

/// Keeps the full rotor displacement of every frame.
struct Keepall {
    every: usize,
    u: Vec<Vec<f64>>,
}

impl FrameSink for Keepall {
    fn every(&self) -> usize {
        self.every
    }
    fn frame(&mut self, f: &Frame<'_>) -> rubsim::error::Result<()> {
        self.u.push(f.rotor_u.to_vec());
        Ok(())
    }
}

#[test]
fn frames_of_a_reduced_rotor_carry_the_full_displacement() {
    let (ls, full, reduced) = models(PAPER, &SHORT_RUN);
    let mut s = settings(&ls);
    s.step.integrator = Scheme::Collocated;
    let nu = 3.1;
    let dt = plan_steps(&case_at(&full, nu), &s.step).unwrap().dt;
    s.step.dt = Some(dt);
    let frames = |m: &Model| {
        let p = analysis::prepare(m, &s.request(nu)).unwrap();
        let mut k = Keepall {
            every: p.plan.steps / 20,
            u: Vec::new(),
        };
        p.integrate(&mut [&mut k]).unwrap();
        (k.u, p.case.rotor.node_dofs.clone())
    };
    let (uf, dofs) = frames(&full);
    let (ur, _) = frames(&reduced);
    assert_eq!(uf.len(), ur.len());
    let n = uf[0].len();
    assert!(
        ur.iter().all(|u| u.len() == n),
        "a frame is not the full model's"
    );
    // Every node's translation, at every frame after the first revolutions.
    let amp = uf.iter().flatten().map(|v| v.abs()).fold(0.0, f64::max);
    let mut worst = 0.0_f64;
    for (a, b) in uf.iter().zip(&ur).skip(10) {
        for d in dofs.iter().flatten() {
            worst = worst.max((a[*d] - b[*d]).abs());
        }
    }
    assert!(
        worst < 2e-3 * amp,
        "translations differ by {:e}",
        worst / amp
    );
}

#[test]
fn run_reduction_is_checked_with_file_key_and_line() {
    let jeffcott = "[rotor]\nkind = \"jeffcott\"\nmass = 1.0\nstiffness = 1.0\ndamping = 0.1\n[run]\nspeed_ratio = 1.0\n[run.reduction]\ncutoff = 10.0\n";
    let fe = std::fs::read_to_string(repo(PAPER)).unwrap();
    for (text, sets, key) in [
        (jeffcott.to_string(), vec![], "run.reduction"),
        (
            fe.clone(),
            vec!["run.reduction.cutoff=-1"],
            "run.reduction.cutoff",
        ),
        (
            fe.clone(),
            vec!["run.reduction.cutoff=1e4", "run.reduction.cutoff_factor=2"],
            "run.reduction.cutoff_factor",
        ),
        (
            fe.clone(),
            vec!["run.reduction.cutoff_factor=0.5"],
            "run.reduction.cutoff_factor",
        ),
        (
            fe.clone() + "\n[run.reduction]\nmodes = 3\n",
            vec![],
            "modes",
        ),
    ] {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let ls = scene::parse(Path::new("t.toml"), &text, &sets);
        let err = match ls {
            Err(e) => e.to_string(),
            Ok(ls) => match rubsim::model::Model::from_scene(&ls) {
                Err(e) => e.to_string(),
                Ok(_) => panic!("{sets:?} accepted"),
            },
        };
        assert!(err.contains(key) && err.contains("t.toml"), "{err}");
    }
    // A fixed cut-off is taken as given.
    let ls = parse(&fe, &["run.reduction.cutoff=2000"]);
    let model = Model::from_scene(&ls).unwrap();
    let red = case_at(&model, 1.7).reduced.unwrap();
    assert_eq!(red.cutoff, 2000.0);
    assert_eq!(red.modes, 4);
}

/// Issue 15 item 4: `convergence` runs the FE rotor's reduced model (`[run.reduction]` at its
/// default cut-off) beside the full one, collocated and generalised-α, against the full model's
/// reference — the reduced explicit step is allowed from the coarsest level, where the full
/// explicit schemes are above their stability limit; the reduced generalised-α is second order
/// and within the reduction's own error of the full one at every level (measured 1.43e-2 …
/// 2.08e-4 against 1.43e-2 … 1.80e-4). A Jeffcott rotor has no reduced rows.
#[test]
fn convergence_shows_the_reduced_fe_rotor_beside_the_full_one() {
    let (ls, model) = file_model(
        &repo(PAPER),
        &["run.revolutions=30", "run.transient_revolutions=15"],
    );
    let s = settings(&ls);
    let c = analysis::convergence(&model, &s, 1.7, &[0, 1, 2, 3], 6, 10, None).unwrap();
    let of = |name: &str| -> Vec<analysis::ConvergencePoint> {
        c.points
            .iter()
            .filter(|p| p.integrator == name)
            .cloned()
            .collect()
    };
    let (rga, ga, rcol) = (
        of(analysis::REDUCED_GENERALIZED_ALPHA),
        of("generalized_alpha"),
        of(analysis::REDUCED_COLLOCATED),
    );
    assert_eq!(
        (rga.len(), ga.len(), rcol.len()),
        (4, 4, 4),
        "{:?}",
        c.points
    );
    assert!(of("collocated").iter().all(|p| p.steps_per_rev > 64));
    for (r, f) in rga.iter().zip(&ga) {
        assert_eq!((r.steps_per_rev, r.period), (f.steps_per_rev, 1));
        assert!(
            (r.orbit_err - f.orbit_err).abs() <= 0.1 * f.orbit_err + 5e-5,
            "reduced {r:?} full {f:?}"
        );
    }
    for name in [
        analysis::REDUCED_GENERALIZED_ALPHA,
        analysis::REDUCED_COLLOCATED,
    ] {
        let p = c.orders.iter().find(|o| o.0 == name).unwrap().1;
        assert!((p - 2.0).abs() < 0.2, "{name}: order {p}");
    }
    assert!(rga[3].extents_err <= ls.scene.run.tolerance, "{:?}", rga[3]);
    // The Jeffcott paper case: nothing to reduce.
    let (jls, jm) = file_model(&repo("scenes/paper/partial_rub.toml"), &[] as &[&str]);
    let case = jm.case(1.7 * jm.rotor.natural_frequency()).unwrap();
    assert!(analysis::reduced_case(&jm, &settings(&jls), &case).is_none());
}
