//! Runs with contact beyond the closed forms: every kind of stator (the rod, the rod written as
//! a general FE stator, a rod and a ring with mass, an arc of nodes several of which touch at
//! once) with both integrators keeps the gap closed and agrees with its equivalent; the paper's
//! case under extreme parameters runs to the end; a step above the stability limit is refused.

use crate::common;

use common::scenes::{paper_single, paper_single_si, paper_with_stator};
use common::{run_speed, scene_model, settings};
use rubsim::analysis::{self, Keep, SpeedResults};

// ---------------------------------------------------------------------------------------------
// Stators.

/// One speed ω/ω_n = `nu` of `text` with the overrides `ov`, without the 2Δt companion run.
fn run(text: &str, ov: &[&str], nu: f64) -> SpeedResults {
    let mut o: Vec<String> = ov.iter().map(|s| s.to_string()).collect();
    o.push("run.error_estimate=false".into());
    o.push(format!("run.speed_ratio={nu}"));
    run_speed(text, &o, nu)
}

/// The paper's rod written as a general FE stator: 3 bar elements, base fixed, lateral DOFs
/// guided. k_s = E A / L = 25 k_r with k_r = 48EI/L³ of the Table 1 shaft.
fn fe_rod(clearance: f64, density: f64) -> String {
    let kr = 48.0 * 200e9 * (std::f64::consts::PI * 0.01_f64.powi(4) / 64.0) / 0.4_f64.powi(3);
    let e = 25.0 * kr * 0.04 / 25e-6;
    let y0 = 0.06 + clearance;
    let nodes: Vec<String> = (0..4)
        .map(|i| format!("[0.0, {}]", y0 + 0.04 * i as f64 / 3.0))
        .collect();
    let els: Vec<String> = (0..3)
        .map(|i| format!("{{ kind = \"bar\", nodes = [{i}, {}], youngs_modulus = {e}, area = 25e-6, density = {density} }}", i + 1))
        .collect();
    let stator = format!(
        "[[stator]]\nkind = \"fe\"\nname = \"rod\"\nstation = \"disk\"\nnodes = [{}]\nelements = [{}]\nfixed = [[0, 0], [1, 0], [2, 0], [3, 0], [3, 1]]\ncontact_nodes = [0]\n",
        nodes.join(", "),
        els.join(", ")
    );
    paper_with_stator(&stator)
}

#[test]
fn fe_stator_reproduces_the_rod() {
    let rod = run(&paper_single_si(), &["stator.0.elements=3"], 1.7);
    let fe = run(&fe_rod(1.2e-4, 0.0), &[], 1.7);
    for i in 0..4 {
        assert!(
            (rod.extents_nd[i] - fe.extents_nd[i]).abs() < 1e-9,
            "{:?} vs {:?}",
            rod.extents_nd,
            fe.extents_nd
        );
    }
    assert_eq!(rod.period, fe.period);
}

#[test]
fn light_stator_with_mass_approaches_the_massless_one() {
    // Forward increment couples rotor and stator masses; a rod of small density behaves like
    // the massless rod (its axial modes are far above the rotor's).
    let fi = "run.integrator=\"forward_increment\"";
    let massless = run(
        &paper_single_si(),
        &["stator.0.elements=3", fi, "run.harmonics=16"],
        1.7,
    );
    let massive = run(
        &paper_single_si(),
        &[
            "stator.0.elements=3",
            "stator.0.density=20.0",
            fi,
            "run.harmonics=16",
        ],
        1.7,
    );
    let span = massless.extents_nd[3] - massless.extents_nd[2];
    for i in 0..4 {
        assert!(
            (massless.extents_nd[i] - massive.extents_nd[i]).abs() < 0.05 * span,
            "{:?} vs {:?}",
            massless.extents_nd,
            massive.extents_nd
        );
    }
    assert!(massive.stats.min_gap >= -1e-12, "{}", massive.stats.min_gap);
}

#[test]
fn ring_with_mass_runs_and_does_not_penetrate() {
    let ring = "[[stator]]\nkind = \"ring\"\nname = \"ring\"\nstation = \"disk\"\nclearance_nd = 0.8\nstiffness_ratio = 25.0\nmass = 0.5\ndamping = 50.0\n";
    let text = paper_with_stator(ring);
    let r = run(&text, &["run.integrator=\"forward_increment\""], 1.2);
    assert!(r.stats.contact_steps > 0);
    assert!(
        r.stats.min_gap >= -1e-6 * r.clearances[0],
        "{}",
        r.stats.min_gap
    );
}

#[test]
fn several_nodes_in_contact_at_once() {
    // An arc of 9 nodes above the rotor, each on a radial spring: the rotor presses several
    // of them together, so the complementarity solve has several active pairs.
    let n = 9;
    let r0 = 0.06 + 1.0e-4;
    let mut nodes = Vec::new();
    let mut els = Vec::new();
    for i in 0..n {
        let th = std::f64::consts::FRAC_PI_2 + (i as f64 - 4.0) * 0.002;
        nodes.push(format!("[{}, {}]", r0 * th.cos(), r0 * th.sin()));
        els.push(format!(
            "{{ kind = \"spring\", node = {i}, stiffness = 2.0e5, angle_deg = {} }}",
            th.to_degrees()
        ));
        els.push(format!(
            "{{ kind = \"spring\", node = {i}, stiffness = 2.0e5, angle_deg = {} }}",
            th.to_degrees() + 90.0
        ));
    }
    let contact: Vec<String> = (0..n).map(|i| i.to_string()).collect();
    let stator = format!(
        "[[stator]]\nkind = \"fe\"\nname = \"arc\"\nstation = \"disk\"\nnodes = [{}]\nelements = [{}]\nfixed = []\ncontact_nodes = [{}]\n",
        nodes.join(", "),
        els.join(", "),
        contact.join(", ")
    );
    let text = paper_with_stator(&stator);
    for kind in ["collocated", "forward_increment"] {
        let r = run(&text, &[&format!("run.integrator=\"{kind}\"")], 1.7);
        assert!(
            r.stats.max_active >= 2,
            "{kind}: max active {}",
            r.stats.max_active
        );
        assert!(
            r.stats.min_gap >= -1e-9 * r.clearances[0],
            "{kind}: {}",
            r.stats.min_gap
        );
    }
}

#[test]
fn collocated_run_records_the_forces_of_a_stator_with_mass() {
    // Collocated runs solve stators with mass by forward increment inside the step; with no
    // massless stator the two integrators take the same steps, so the collocated run must
    // report the same contact forces (before the fix it recorded none: only massless-stator
    // forces reached its record).
    let massive = ["stator.0.elements=3", "stator.0.density=20.0"];
    let mut col = massive.to_vec();
    col.push("run.integrator=\"collocated\"");
    let mut fi = massive.to_vec();
    fi.push("run.integrator=\"forward_increment\"");
    let c = run(&paper_single_si(), &col, 1.7);
    let f = run(&paper_single_si(), &fi, 1.7);
    assert!(c.stats.contact_steps > 0);
    assert!(c.contact_force_max_nd > 0.0, "{}", c.contact_force_max_nd);
    assert_eq!(c.extents_nd, f.extents_nd);
    assert!(
        (c.contact_force_max_nd - f.contact_force_max_nd).abs() <= 1e-12 * f.contact_force_max_nd,
        "collocated {} vs forward increment {}",
        c.contact_force_max_nd,
        f.contact_force_max_nd
    );
    assert_eq!(c.contact_fraction, f.contact_fraction);
    assert_eq!(c.stats.contact_steps, f.stats.contact_steps);
}

/// Contact statistics over `[first, last)` of a record: (largest |F| on station 0, samples with
/// an active pair).
fn recorded_contact(rec: &rubsim::time::Record, first: usize, last: usize) -> (f64, usize) {
    (first..last).fold((0.0_f64, 0), |(f, n), i| {
        let v = rec.force_at(i, 0);
        (f.max(v[0].hypot(v[1])), n + usize::from(rec.active[i] > 0))
    })
}

#[test]
fn contact_statistics_count_every_step() {
    // Issue 13, item 4: the peak force, the contact fraction and the penetration are taken at
    // every step, not from the recorded samples. Recording every step, they must equal what the
    // record shows over the analysed window; recording one step in many, they can only be
    // larger than the record's, and the whole run holds the steady window.
    use rubsim::analysis::{analyse, prepare};
    let massive = ["stator.0.elements=3", "stator.0.density=20.0"];
    for (integrator, stator) in [
        ("collocated", &[][..]),
        ("forward_increment", &[][..]),
        ("collocated", &massive[..]),
        ("forward_increment", &massive[..]),
    ] {
        let mut ov = vec![
            format!("run.integrator=\"{integrator}\""),
            // An analysed window of 12 revolutions (a multiple of 6, as planned).
            "run.revolutions=20".into(),
            "run.transient_revolutions=8".into(),
            "run.error_estimate=false".into(),
            "run.speed_ratio=1.7".into(),
        ];
        ov.extend(stator.iter().map(|s| s.to_string()));
        let (ls, model) = scene_model(&paper_single_si(), &ov);
        let mut st = settings(&ls);
        let coarse = prepare(&model, &st.request(1.7)).unwrap();
        assert!(
            coarse.plan.record_every > 1,
            "{integrator}: {:?}",
            coarse.plan
        );
        st.step.samples_per_rev = coarse.plan.steps_per_rev;
        let every = prepare(&model, &st.request(1.7)).unwrap();
        assert_eq!(every.plan.record_every, 1);
        assert_eq!(every.plan.steps, coarse.plan.steps, "{integrator}");
        let what = format!("{integrator}, stator {stator:?}");
        for p in [&every, &coarse] {
            let (rec, stats) = p.integrate(&mut []).unwrap();
            let (plan, spr) = (&p.plan, p.request.step.samples_per_rev);
            let (first, last) = (8 * spr, 20 * spr);
            assert_eq!(plan.steady_from, 8 * plan.steps_per_rev, "{what}");
            let (s, w) = (stats.steady, stats.whole);
            assert_eq!(s.from_step, plan.steady_from, "{what}");
            assert_eq!(s.instants, plan.steps - plan.steady_from, "{what}");
            assert_eq!(w.instants, plan.steps + 1, "{what}");
            assert!(s.contact_instants > 0, "{what}: no contact in the window");
            assert!(w.contact_instants >= s.contact_instants, "{what}");
            assert!(w.force_max >= s.force_max && s.force_max > 0.0, "{what}");
            assert!(w.penetration_max >= s.penetration_max, "{what}");
            assert_eq!(w.penetration_max, (-stats.min_gap).max(0.0), "{what}");
            let (fmax, ncontact) = recorded_contact(&rec, first, last);
            if plan.record_every == 1 {
                assert_eq!(last - first, s.instants, "{what}");
                assert_eq!(ncontact, s.contact_instants, "{what}");
                assert!(
                    (fmax - s.force_max).abs() <= 1e-12 * fmax,
                    "{what}: {fmax} vs {}",
                    s.force_max
                );
            } else {
                assert!(
                    ncontact <= s.contact_instants && fmax <= s.force_max,
                    "{what}"
                );
            }
            let r = analyse(&p.case, &p.request, plan, &rec, stats, Keep::default());
            assert_eq!(
                r.contact_force_max_nd,
                s.force_max / p.case.unbalance_force,
                "{what}"
            );
            assert_eq!(
                r.contact_fraction,
                s.contact_instants as f64 / s.instants as f64
            );
            assert_eq!(r.penetration_max_m, w.penetration_max, "{what}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The paper's case at the limits.

#[test]
fn extreme_cases_run_to_the_end() {
    let text = paper_single();
    for ov in [
        vec!["stator.0.stiffness_ratio=1e4", "run.speed_ratio=1.7"],
        vec!["stator.0.clearance_nd=0.05", "run.speed_ratio=1.7"],
        vec!["station.0.friction=0.5", "run.speed_ratio=1.7"],
        vec!["rotor.damping_ratio=0.01", "run.speed_ratio=1.7"],
        vec!["run.speed_ratio=10.0"],
    ] {
        for kind in ["collocated", "forward_increment"] {
            let mut o = ov.clone();
            let k = format!("run.integrator=\"{kind}\"");
            o.push(&k);
            o.push("run.error_estimate=false");
            let (ls, model) = scene_model(&text, &o);
            let s = settings(&ls);
            let r = analysis::run_speed(
                &model,
                &s.request(ls.scene.run.speed_ratio.unwrap()),
                Keep::default(),
            )
            .unwrap_or_else(|e| panic!("{ov:?} {kind}: {e}"));
            let clearance = r.clearances[0];
            assert!(
                r.extents_nd
                    .iter()
                    .all(|v| v.is_finite() && v.abs() < 100.0),
                "{ov:?} {kind}: {:?}",
                r.extents_nd
            );
            assert!(
                r.stats.min_gap >= -1e-8 * clearance,
                "{ov:?} {kind}: gap {:e}",
                r.stats.min_gap
            );
            assert!(r.amp_1x_nd.is_finite());
        }
    }
}

#[test]
fn unstable_step_is_refused_with_the_limit() {
    let text = paper_single();
    let (ls, model) = scene_model(&text, &["run.speed_ratio=1.7", "run.dt=1e-2"]);
    let s = settings(&ls);
    let e = analysis::run_speed(&model, &s.request(1.7), Keep::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("stability limit"), "{e}");
}

#[test]
fn a_step_beyond_the_stability_limit_is_stopped_as_diverged() {
    // Issue 13, item 8: the divergence bound is per DOF (displacements against the largest
    // |Z0| over the rotor, rotations against the largest forced tilt), so a true instability
    // is still caught: Δt forced to 3 × 2/ω_max of the free rotor (the plan refuses it, so it
    // is set by hand) stops within a few hundred steps as `Diverged`, naming the DOF, before
    // any value overflows to a non-finite one.
    use common::scenes::{PAPER, PAPER_FE};
    use rubsim::error::SolveError;
    use rubsim::time::{integrate, plan_steps, Scheme};
    for (text, units) in [(PAPER, "m"), (PAPER_FE, "m rad")] {
        let (ls, model) = scene_model(
            text,
            &["run.revolutions=20", "run.transient_revolutions=10"],
        );
        let case = model.case(1.7 * model.rotor.natural_frequency()).unwrap();
        for scheme in [Scheme::Collocated, Scheme::ForwardIncrement] {
            let mut st = settings(&ls).step;
            st.integrator = scheme;
            let mut plan = plan_steps(&case, &st).unwrap();
            integrate(&case, scheme, &plan, Default::default())
                .unwrap_or_else(|e| panic!("{scheme:?} at the planned step: {e}"));
            plan.dt = 3.0 * 2.0 / case.rotor_omega_max;
            match integrate(&case, scheme, &plan, Default::default()) {
                Err(SolveError::Diverged {
                    step,
                    dof,
                    unit,
                    magnitude,
                    bound,
                    ..
                }) => {
                    assert!(step < 2000, "{scheme:?}: caught late, step {step}");
                    assert!(magnitude > bound && units.contains(unit), "{dof} {unit}");
                    assert!(dof.contains("of rotor node"), "{dof}");
                }
                Err(e) => panic!("{scheme:?}: expected Diverged, got {e}"),
                Ok((_, stats)) => panic!("{scheme:?}: ran to the end, {} steps", stats.steps),
            }
        }
    }
}

/// Penetration after correction (`summary.json`'s `penetration_max_m`, the exact gap of every
/// pair solved at every step) stays below 1e-3 of the clearance for every kind of stator: the
/// paper's rod at three regimes, the rod as a general FE stator, the massless ring in full
/// annular rub deflecting by several clearances (ε = 5, δ = 0.5 |Z0|: 6.7 % of δ before the
/// ring's tangential displacement entered its gap) and a stiffer one, a ring with mass, and the
/// meshed stators (the rod as a 2-D body, the plain annulus, the segmented casing).
#[test]
fn penetration_stays_below_1e_3_of_the_clearance_for_every_stator_kind() {
    let ring = |extra: &str| {
        paper_with_stator(&format!(
            "[[stator]]\nkind = \"ring\"\nname = \"ring\"\nstation = \"disk\"\n{extra}"
        ))
    };
    let check = |what: &str, r: &SpeedResults| {
        let delta = r.clearances[0];
        eprintln!(
            "{what}: penetration {:.3e} m = {:.2e} δ",
            r.penetration_max_m,
            r.penetration_max_m / delta
        );
        assert!(
            r.penetration_max_m <= 1e-3 * delta,
            "{what}: penetration {:.3e} m, δ = {delta:.3e} m",
            r.penetration_max_m
        );
    };
    let short = ["run.revolutions=80", "run.transient_revolutions=40"];
    let cases: [(&str, String, f64); 7] = [
        ("rod ν = 1.7", paper_single(), 1.7),
        ("rod ν = 3.1", paper_single(), 3.1),
        ("rod ν = 4.9", paper_single(), 4.9),
        ("FE bar rod", fe_rod(1.2e-4, 0.0), 1.7),
        (
            "massless ring ε 5",
            ring("clearance_nd = 0.5\nstiffness_ratio = 5.0\n"),
            2.0,
        ),
        (
            "massless ring ε 25",
            ring("clearance_nd = 0.8\nstiffness_ratio = 25.0\n"),
            1.7,
        ),
        (
            "ring with mass",
            ring("clearance_nd = 0.8\nstiffness_ratio = 25.0\nmass = 0.5\ndamping = 50.0\n"),
            1.7,
        ),
    ];
    for (what, text, nu) in &cases {
        check(what, &run(text, &short, *nu));
    }
    if common::meshes::gmsh_wanted() {
        for (file, nu) in [("rod2d", 1.7), ("annulus", 1.2), ("segmented_casing", 1.5)] {
            let path = common::repo(&format!("scenes/stators/{file}.toml"));
            let (ls, m) =
                common::file_model(&path, &[short[0], short[1], "run.error_estimate=false"]);
            let r = analysis::run_speed(&m, &settings(&ls).request(nu), Keep::default()).unwrap();
            check(&format!("meshed {file} at ν = {nu}"), &r);
        }
    }
}
