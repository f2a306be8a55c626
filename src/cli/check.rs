//! `rubsim check`: validate a scene and print the resolved model.

use super::{choose_settings, describe_choice, load, settings, Common};
use anyhow::Result;
use rubsim::analysis;
use rubsim::model::{Case, Model};
use rubsim::scene::{self, Scene};
use rubsim::time::StepPlan;

/// Validates the scene and prints the resolved model: rotor, stations, stators, the run and
/// its step, what is built and what is left out, the outputs.
pub fn check(c: &Common) -> Result<()> {
    let (ls, model) = load(c)?;
    let s = &ls.scene;
    println!("scene: {}", c.scene.display());
    if !s.title.is_empty() {
        println!("title: {}", s.title);
    }
    for o in &ls.overrides {
        println!("override: {o}");
    }
    println!("rotor: {}", model.rotor.describe());
    if let rubsim::model::Rotor::Fe(f) = &model.rotor {
        println!(
            "  {}",
            rubsim::scene::validate::dense_rotor_cost(f.rotor.ndof).describe()
        );
    }
    let case = model.case(
        analysis::single_speed(&s.run, &model)
            .or_else(|| s.run.sweep.as_ref().map(|w| w.from))
            .or_else(|| {
                // A speed profile places the stators at its reference speed.
                let wn = model.rotor.natural_frequency();
                let p = s.run.speed_profile.as_ref()?;
                p.reference.map(|r| r * p.unit.to_rad_per_s(wn) / wn)
            })
            .unwrap_or(1.0)
            * model.rotor.natural_frequency(),
    )?;
    for u in &case.rotor.unbalance {
        println!(
            "  unbalance m_u·e = {:.4e} kg·m at {:.1}° on DOFs {:?}",
            u.me,
            u.phase.to_degrees(),
            u.dofs
        );
    }
    for st in &model.stations {
        println!(
            "station `{}`: rotor node {}, radius {} m, friction μ = {}",
            st.name, st.node, st.radius, st.friction
        );
    }
    if let Some(hs) = analysis::thermal::HotSpot::of_scene(&ls) {
        println!("thermal: {}", hs.heat.describe()?);
    }
    let st = settings(&ls);
    if let Some(spec) = &s.run.speed_profile {
        print_stators(s, &case);
        let p = analysis::prepare_transient(&model, &st, spec)?.with_events(&s.run.event)?;
        print_transient(s, &p);
        print_built(s, &model, &p.case, &p.plan);
        return Ok(());
    }
    let speeds = match &s.run.sweep {
        Some(w) => analysis::sweep_speeds(w.from, w.to, w.step),
        None => vec![case.speed_ratio],
    };
    // The choice is printed once, in the run's description below.
    let st = choose_settings(&ls, &model, &speeds)?;
    // The reduction the error-target choice picked (a reduced scheme, or the scene's
    // `[run.reduction]` with its cut-off chosen from the tolerance).
    let case = match &st.reduction {
        Some(r) => model.case_with(case.omega, Some(r))?,
        None => case,
    };
    print_stators(s, &case);
    if let Some(r) = st.choice.and_then(|c| c.reduction) {
        println!(
            "cut-off chosen from run.tolerance = {:e}: κ = {} (ω_cut = {:.4e} rad/s at ω/ωn = {:.2}), truncation error indicator E(κ) = 4/3·|run(κ) − run(2κ)| = {:.2e} (target {:.2e} = {} × run.tolerance)",
            st.tolerance,
            r.cutoff_factor,
            (case.reduced.as_ref().map(|x| x.cutoff))
                .or_else(|| case.stators.iter().find_map(|m| m.reduced.as_ref().map(|x| x.cutoff)))
                .unwrap_or(f64::NAN),
            case.speed_ratio,
            r.truncation_error,
            r.target,
            rubsim::analysis::cutoff::TRUNCATION_SHARE
        );
    }
    let plan = rubsim::time::plan_steps(&case, &st.step)?;
    print_run(s, &st, &case, &plan);
    print_budget(s, &model, &st, &case, &plan)?;
    print_built(s, &model, &case, &plan);
    Ok(())
}

/// A stator's wear: Archard's law (`[stator.wear]`) and the abradable coating
/// (`[stator.abradable]`).
fn print_wear(w: &rubsim::model::stator::StatorWear) {
    let (lo, hi) = w
        .areas
        .iter()
        .fold((f64::INFINITY, 0.0_f64), |(a, b), x| (a.min(*x), b.max(*x)));
    // A coating alone (`rate` 0) is no Archard wear.
    if w.rate > 0.0 {
        println!(
            "  wears (Archard): k = {:.4e} m²/N magnified {} times (`run.wear_acceleration`); {} contact nodes of {:.4e} … {:.4e} m² (their depth grows by k p |ζ| / area a step)",
            w.rate / w.acceleration,
            w.acceleration,
            w.areas.len(),
            lo,
            hi
        );
    }
    if let Some(l) = &w.layer {
        println!(
            "  abradable coating: h = {:.4e} m, E = {:.4e} Pa, σ_y = {:.4e} Pa, H = {:.4e} Pa (each node a radial rod E A / h in series, its force at most A (σ_y + H d_p / h))",
            l.thickness, l.youngs_modulus, l.yield_stress, l.hardening_modulus
        );
    }
}

/// Each stator: kind, size, contact stiffness, mesh, how it enters the loop, clearance.
fn print_stators(s: &Scene, case: &Case) {
    for (spec, m) in s.stators.iter().zip(&case.stators) {
        let kind = match spec {
            scene::StatorSpec::Rod(_) => "rod (2-D bar elements, lateral DOFs guided)",
            scene::StatorSpec::Ring(r) if r.kinematics == "radial" => {
                "rigid ring on isotropic springs (circle-in-circle contact; kinematics \"radial\": force along the rotor's radius, friction to ground)"
            }
            scene::StatorSpec::Ring(r) if r.stiffness_y.is_some() || r.damping_y.is_some() => {
                "rigid ring on anisotropic springs (k_x, k_y; circle-in-circle contact; kinematics \"exact\": the normal follows the ring's whole displacement)"
            }
            scene::StatorSpec::Ring(_) => {
                "rigid ring on isotropic springs (circle-in-circle contact; kinematics \"exact\": the normal follows the ring's whole displacement)"
            }
            scene::StatorSpec::Fe(_) => "general 2-D FE stator",
            scene::StatorSpec::Mesh(_) => "meshed stator (gmsh)",
        };
        let ks = m.contact_stiffness_bound();
        println!(
            "stator `{}` facing `{}`: {kind}; {} nodes, {} free DOFs, {} contact targets; contact stiffness ≤ {:.4e} N/m (ε ≤ {:.3})",
            m.name,
            spec.station(),
            m.nodes.len(),
            m.ndof,
            m.targets.len(),
            ks,
            ks / case.rotor_stiffness
        );
        if let Some(md) = &m.mesh {
            println!(
                "  mesh {} ({}) from {}: {}-D, {} cells, contact group {} nodes",
                md.mesh_file.display(),
                if md.from_cache {
                    "up to date, gmsh not run"
                } else {
                    "meshed by gmsh now"
                },
                md.geometry.display(),
                md.dim,
                md.cells,
                m.targets.len()
            );
        }
        if let Some(w) = &m.wear {
            print_wear(w);
        }
        if m.massless() {
            print_massless(m);
        } else if let Some(r) = &m.reduced {
            println!(
                "  with mass, reduced (`run.reduction.stators`, Craig–Bampton): cut-off ω_cut = {:.4e} rad/s; {} fixed-interface modes kept{}; {} boundary (contact) DOFs; {} DOF in the loop instead of {}; ω_max,reduced = {:.4e} rad/s (explicit limit {:.4e} s); contact flexibility exact (constraint modes)",
                r.cutoff,
                r.modes.len(),
                match (r.modes.first(), r.modes.last()) {
                    (Some(a), Some(b)) => format!(" ({a:.4e} … {b:.4e} rad/s)"),
                    _ => String::new(),
                },
                r.boundary.len(),
                r.rdof(),
                r.ndof,
                r.omega_max(),
                2.0 / r.omega_max(),
            );
        } else {
            println!(
                "  with mass: lumped, integrated explicitly; its highest mode ω_max,stator ≤ {:.4e} rad/s",
                m.omega_max_sq_bound().sqrt()
            );
        }
        let nd = match spec {
            scene::StatorSpec::Rod(r) => r.clearance_nd,
            scene::StatorSpec::Ring(r) => r.clearance_nd,
            scene::StatorSpec::Fe(_) => None,
            scene::StatorSpec::Mesh(m) => m.clearance_nd,
        };
        match nd {
            Some(nd) => println!(
                "  clearance δ = {nd} |Z0(ω)| (= {:.4e} m at ω/ωn = {:.2}; {})",
                m.clearance,
                case.speed_ratio,
                if s.run.speed_profile.is_some() {
                    "fixed through the speed profile"
                } else {
                    "changes with speed"
                }
            ),
            None => println!("  clearance δ = {:.4e} m", m.clearance),
        }
    }
}

/// The line of a massless stator: its contact DOFs, factor and compliance bound.
fn print_massless(m: &rubsim::model::StatorModel) {
    let factor = m
        .factor_nnz()
        .map(|n| format!(", factor {}", rubsim::time::budget::bytes(8.0 * n as f64)))
        .unwrap_or_default();
    println!(
        "  massless: enters the time loop as the compliance among its {} contact DOFs (one sparse Cholesky{factor}; {}; ≤ {} when every contact DOF touches), not as a mesh",
        m.contact_dofs().len(),
        if m.contact_dofs().len() <= rubsim::time::EAGER_DOFS { "every column up front" } else { "a column computed when its node first touches, shared by the stator's runs" },
        rubsim::time::budget::bytes(m.packed_compliance_bytes()),
    );
    if let Some(p) = rubsim::time::path_cost(m) {
        println!(
            "  its columns from elimination-tree paths (factor ≥ {} entries): forward solves {:.2e} flops, products among them {:.2e} flops, forward solutions held ≤ {} when every contact DOF touches, allocated ≤ {} (a full solve per column would take {:.2e} flops)",
            rubsim::time::PATH_COLUMNS_NNZ,
            p.forward_flops,
            p.product_flops,
            rubsim::time::budget::bytes(8.0 * p.stored_entries),
            rubsim::time::budget::bytes(rubsim::time::budget::PATH_CHUNK_ROOM * 8.0 * p.stored_entries),
            4.0 * m.factor_nnz().unwrap_or(0) as f64 * m.contact_dofs().len() as f64,
        );
    }
}

/// The run: speeds, integrator, revolutions, Δt at the checked speed.
fn print_run(s: &Scene, st: &analysis::RunSettings, case: &Case, plan: &StepPlan) {
    let speeds = match &s.run.sweep {
        Some(w) => {
            let v = analysis::sweep_speeds(w.from, w.to, w.step);
            format!(
                "sweep ω/ωn {} … {} step {} ({} speeds{})",
                w.from,
                w.to,
                w.step,
                v.len(),
                w.vary
                    .as_ref()
                    .map(|x| format!(", repeated for {} = {:?}", x.key, x.values))
                    .unwrap_or_default()
            )
        }
        None => match (&s.run.map, &s.thermal) {
            (Some(m), Some(t)) => format!(
                "thermal map (`rubsim map`): {} = {:?} × {} = {:?}, the thermal spiral over {} s of machine time at each cell (below: the cell ω/ωn = {:.4})",
                m.x.key,
                m.x.resolved(),
                m.y.key,
                m.y.resolved(),
                t.duration,
                case.speed_ratio
            ),
            _ => format!("single speed ω/ωn = {:.4}", case.speed_ratio),
        },
    };
    println!("run: {speeds}");
    let length = match s.run.duration {
        Some(d) => format!(
            "a fixed window `run.duration` = {d} s from the initial state, never lengthened: {} steps to t = {:.6e} s ({:.2} revolutions), the last {} revolutions analysed (`run.revolutions` and `run.transient_revolutions` do not apply)",
            plan.steps,
            plan.steps as f64 * plan.dt,
            plan.steps as f64 / plan.steps_per_rev.max(1) as f64,
            (plan.steps - plan.steady_from) / plan.steps_per_rev.max(1)
        ),
        None => format!(
            "{} revolutions, first {} cut as transient",
            s.run.revolutions, s.run.transient_revolutions
        ),
    };
    println!(
        "  integrator {}; {length}; {} samples/rev recorded; error estimate {}",
        st.step.integrator.name(),
        s.run.samples_per_rev,
        if s.run.error_estimate {
            "by companion runs at 2Δt (and Δt/2 or 4Δt at a rub)"
        } else {
            "off"
        }
    );
    if let Some(dt) = s.run.dt {
        println!(
            "  run.dt = {dt:.4e} s asked; rounded down to {:.4e} s so a revolution holds whole recorded samples",
            plan.dt
        );
    }
    if let Some(c) = &st.choice {
        println!("  {}", describe_choice(c));
        if st.error_estimate {
            println!(
                "  verified by each run: where its own error estimate misses run.tolerance, Δt is halved and the run repeated, at most {} times from the scene's start (each repeat about twice the steps of the run before it, so at most 6 × the run's own steps more, not counted below; reported as `step_refinement`)",
                analysis::MAX_STEP_REFINEMENTS
            );
        }
    }
    let limit = if st.step.integrator.implicit().is_some() {
        format!(
            "explicit stability limit {:.4e} s (not applied: implicit, Δt by accuracy only)",
            plan.limit
        )
    } else {
        format!("stability limit {:.4e} s", plan.limit)
    };
    println!(
        "  Δt at ω/ωn = {:.2}: {:.4e} s ({} steps/rev); paper rule (n = {}) {:.4e} s; {limit}; highest frequency with the contact stiffness and stator modes ω_max,contact = {:.4e} rad/s",
        case.speed_ratio, plan.dt, plan.steps_per_rev, s.run.harmonics, plan.rule_dt, plan.omega_max
    );
}

/// A transient run: the profile, its length and the step.
fn print_transient(s: &Scene, p: &analysis::TransientPrepared) {
    let wn = p.omega_n;
    let spec = s.run.speed_profile.as_ref();
    if let Some(d) = &p.drive {
        println!(
            "run: driven rotor: J = {:.4e} kg·m², Ω₀/ωn = {:.4}, {:.4} s, drive {:?} (off at {} s), drag {:.3e} N·m + {:.3e} N·m·s/rad × Ω; Δt planned for Ω/ωn ≤ {:.4}; stators placed at Ω_ref/ωn = {:.4}",
            d.inertia,
            d.speed0 / wn,
            d.duration,
            d.law,
            d.off,
            d.drag,
            d.drag_viscous,
            d.speed_bound() / wn,
            p.case.speed_ratio
        );
    } else {
        println!(
        "run: speed profile ({}, unit {}): {:.4} s, {:.1} revolutions, Ω/ωn {:.4} → {:.4} (max {:.4}); stators placed at Ω_ref/ωn = {:.4}",
        spec.map_or("", |x| match x.kind {
            rubsim::scene::ProfileKind::Constant => "constant",
            rubsim::scene::ProfileKind::Ramp => "ramp",
            rubsim::scene::ProfileKind::Table => "table",
            rubsim::scene::ProfileKind::Driven => "driven",
        }),
        spec.map_or("", |x| x.unit.name()),
        p.profile.duration(),
        p.profile.total_angle() / (2.0 * std::f64::consts::PI),
        p.profile.start_speed() / wn,
        p.profile.at(p.profile.duration()).omega / wn,
        p.profile.max_speed() / wn,
        p.case.speed_ratio
    );
    }
    println!(
        "  integrator {}; Δt {:.4e} s ({} steps, {} steps/rev at the top speed), a sample every {} steps; paper rule (n = {}) {:.4e} s; stability limit {:.4e} s; orders tracked {:?} over {} revolutions per window",
        s.run.integrator().name(),
        p.plan.dt,
        p.plan.steps,
        p.plan.steps_per_rev,
        p.plan.record_every,
        s.run.harmonics,
        p.plan.rule_dt,
        p.plan.limit,
        p.orders,
        p.window_revolutions
    );
    match (p.settings.error_estimate, p.companion_plan()) {
        (true, Some(c)) => println!(
            "  error estimate: a companion run at Δt {:.4e} s ({} steps), the tracked 1× compared (`run.error_estimate`)",
            c.dt, c.steps
        ),
        (true, None) => println!("  error estimate: none (no companion step can be planned)"),
        (false, _) => println!("  error estimate: off (`run.error_estimate = false`)"),
    }
}

/// The up-front estimate: steps, memory, time of a run at the checked speed and, for a sweep,
/// of the whole sweep (from its first and last speeds' plans).
fn print_budget(
    s: &Scene,
    model: &Model,
    st: &analysis::RunSettings,
    case: &Case,
    plan: &StepPlan,
) -> Result<()> {
    let b = rubsim::time::estimate(case, plan, st.error_estimate);
    println!(
        "  estimate at ω/ωn = {:.2}: {}",
        case.speed_ratio,
        b.describe()
    );
    if rubsim::time::one_at_a_time(model) {
        println!(
            "  runs one at a time: each may hold {} of compliance columns of its own (above {}), so a sweep's runs and the step choice's pilots run one after the other, each starting with the columns of the ones before",
            rubsim::time::budget::bytes(rubsim::time::budget::meshed_column_bytes(model)),
            rubsim::time::budget::bytes(rubsim::time::budget::SHARED_COLUMNS_BYTES),
        );
    }
    print_step_bounds(s, st, case, plan);
    if let Some(w) = &s.run.sweep {
        let speeds = analysis::sweep_speeds(w.from, w.to, w.step);
        let n = speeds.len();
        let last = analysis::prepare(model, &st.request_at(n - 1, speeds[n - 1]))?;
        let bl = rubsim::time::estimate(&last.case, &last.plan, st.error_estimate);
        let variants = w.vary.as_ref().map_or(1, |v| v.values.len());
        let runs = (n * variants) as f64;
        println!(
            "  estimate of the sweep ({} runs, from the first and last speeds): {:.3e} steps, ≈ {} on one core (estimate)",
            runs,
            runs * (b.steps + b.companion_steps + bl.steps + bl.companion_steps) / 2.0,
            rubsim::time::budget::duration(runs * (b.wall_s + bl.wall_s) / 2.0)
        );
    }
    Ok(())
}

/// The steps of the run at the checked speed: as planned, and the most its lengthenings may
/// take ([`rubsim::time::budget::step_bounds`]), the pilots that chose Δt counted in both.
fn print_step_bounds(s: &Scene, st: &analysis::RunSettings, case: &Case, plan: &StepPlan) {
    let l = rubsim::time::budget::Lengthening {
        fixed: st.step.duration.is_some(),
        max_transient_revolutions: st.max_transient_revolutions,
        // Doubled while the 0–1 test is undetermined, up to this factor (`analysis::lengthen`).
        classify_revolutions: st.classify_revolutions * analysis::MAX_CLASSIFY_FACTOR,
        error_estimate: st.error_estimate,
        coexistence: st.check_coexistence,
        max_steps: st.step.max_steps,
    };
    let b = rubsim::time::budget::step_bounds(plan, &l, !case.stators.is_empty());
    let pilots = st.choice.map_or(0.0, |c| c.pilot_steps as f64);
    let with_pilots = if pilots > 0.0 {
        format!("; both count the {pilots:.0} steps of the pilots that chose Δt")
    } else {
        String::new()
    };
    let why = match s.run.duration {
        Some(d) => format!(
            "the fixed window `run.duration` = {d} s is never lengthened: the run {:.0}, companions {:.0}",
            b.run_most, b.companions_most
        ),
        None => format!(
            "if every lengthening runs to its cap: the run {:.0} (transient up to {} revolutions, `run.max_transient_revolutions`; a window that is not periodic up to {} revolutions, {} × `run.classify_revolutions` while its 0–1 test is undetermined; within `run.max_steps` = {}), companions {:.0}, coexistence check {:.0}",
            b.run_most,
            l.max_transient_revolutions.max(plan.steady_from / plan.steps_per_rev.max(1)),
            l.classify_revolutions,
            analysis::MAX_CLASSIFY_FACTOR,
            l.max_steps,
            b.companions_most,
            b.coexistence_most
        ),
    };
    println!(
        "  steps at ω/ωn = {:.2}: {:.0} planned, at most {:.0} ({why}{with_pilots})",
        case.speed_ratio,
        b.planned + pilots,
        b.most + pilots
    );
}

/// What is built, what is left out, which files a run writes.
fn print_built(s: &Scene, model: &Model, case: &Case, plan: &StepPlan) {
    // A gyroscopic rotor on a speed profile with an implicit scheme: S follows Ω(t), Ω̇(t).
    let follows = s.run.speed_profile.is_some()
        && matches!(
            s.run.integrator(),
            rubsim::scene::IntegratorKind::Newmark
                | rubsim::scene::IntegratorKind::GeneralizedAlpha
        )
        && case.loop_rotor().gyro.is_some();
    println!(
        "built: {} rotor body with {} DOF, {} stator(s), {} contact candidate pair(s)",
        match (&model.rotor, follows) {
            (rubsim::model::Rotor::Jeffcott(_), _) => "Jeffcott",
            (rubsim::model::Rotor::Fe(_), false) =>
                "finite-element (sparse M, C + ΩG, K; M̃ factored once per speed by sparse LU)",
            (rubsim::model::Rotor::Fe(_), true) =>
                "finite-element (sparse M, C + Ω(t)G, K + Ω̇(t)K_st; the implicit step operator refactored as the speed moves)",
        },
        case.rotor.ndof,
        case.stators.len(),
        case.stators.iter().map(|m| m.targets.len()).sum::<usize>()
    );
    if let Some(red) = &case.reduced {
        print_reduction(case, red);
    }
    let mut left = Vec::new();
    if matches!(model.rotor, rubsim::model::Rotor::Jeffcott(_)) {
        left.push("FE rotor assembly and sparse LU of M̃ (Jeffcott M̃ is diagonal)");
    }
    if case.stators.iter().all(|m| m.massless()) {
        left.push("stator mass matrices and stator time stepping (all stators massless)");
    }
    if case.stators.iter().all(|m| m.mesh.is_none()) {
        left.push("mesher (no meshed stator)");
    }
    if !s.output.png {
        left.push("PNG pictures");
    }
    println!("left out: {}", left.join("; "));
    let stress = case.stators.iter().any(|m| !m.elements.is_empty());
    println!("outputs: {}", listed_outputs(s, stress).join(", "));
    if s.run.speed_profile.is_some() {
        for line in rubsim::results::describe(&s.output, plan, false) {
            println!("  {line} (frames carry Ω, Ω/ωn, φ, Ω̇)");
        }
        return;
    }
    for line in rubsim::results::describe(&s.output, plan, s.run.sweep.is_some()) {
        println!("  {line}");
    }
    for line in rubsim::results::describe_orbit(&s.output, plan) {
        println!("  {line}");
    }
}

/// The reduced rotor of `[run.reduction]` at the case's speed: cut-off, modes, static columns,
/// the stability data it changes and its frequencies against the full model's.
fn print_reduction(case: &Case, red: &rubsim::model::ReducedRotor) {
    let kept = &red.full_frequencies[..red.modes.min(red.full_frequencies.len())];
    let names: Vec<String> = (red.statics.iter())
        .map(|&d| {
            let r = &case.rotor;
            let node = |l: &[[usize; 2]]| l.iter().position(|x| x.contains(&d));
            match (
                node(&r.node_dofs),
                r.node_torsion.iter().position(|t| *t == Some(d)),
            ) {
                (Some(n), _) => format!(
                    "u_{} node {n}",
                    ["x", "y"][usize::from(r.node_dofs[n][1] == d)]
                ),
                (None, Some(n)) => format!("θ_z node {n}"),
                _ => format!("DOF {d}"),
            }
        })
        .collect();
    println!(
        "reduction (`[run.reduction]`) at ω/ωn = {:.2}: cut-off ω_cut = {:.4e} rad/s; {} modes kept{}; {} static columns ({}); {} DOF in the loop instead of {}",
        case.speed_ratio,
        red.cutoff,
        red.modes,
        match (kept.first(), kept.last()) {
            (Some(a), Some(b)) => format!(" ({a:.4e} … {b:.4e} rad/s)"),
            _ => String::new(),
        },
        red.statics.len(),
        names.join(", "),
        red.body.ndof,
        case.rotor.ndof,
    );
    println!(
        "  ω_max,reduced = {:.4e} rad/s (full model {:.4e}); largest relative error of the reduced frequencies below the cut-off {:.2e}; contact flexibility exact (static columns)",
        red.omega_max(),
        red.full_frequencies.last().copied().unwrap_or(0.0),
        red.frequency_error,
    );
}

/// The files `rubsim run` or `rubsim sweep` writes for this scene, as listed by `check`: at the
/// top of the output directory, and for a sweep that varies a key, under each variant's folder
/// `<key>_<value>/` (VTK/HDF5 series are listed apart, by `results::describe`). `stress`: some
/// stator has elements (a transient then writes its stress history).
pub(crate) fn listed_outputs(s: &Scene, stress: bool) -> Vec<String> {
    let png = s.output.png;
    // Runs with stick draw their dry whirl and whip (docs/STICK.md §4).
    let stick = s.stations.iter().any(|st| st.stick);
    let mut files: Vec<String> = vec!["summary.json".into()];
    let mut add = |csv: &[&str], pngs: &[&str]| {
        files.extend(csv.iter().map(|f| f.to_string()));
        if png {
            files.extend(pngs.iter().map(|f| f.to_string()));
        }
    };
    if s.thermal.is_some() {
        // A thermal run (`rubsim run`) and a thermal map (`rubsim map`, with `[run.map]`).
        if s.run.map.is_some() {
            add(
                &["thermal_map.csv"],
                &["thermal_stability.png", "growth_rate_map.png"],
            );
        } else if matches!(s.rotor, scene::RotorSpec::Fe(_)) {
            add(
                &["spiral.csv", "bow_shape.csv"],
                &["spiral.png", "thermal.png"],
            );
        } else {
            add(&["spiral.csv"], &["spiral.png", "thermal.png"]);
        }
    } else if s.run.speed_profile.is_some() {
        add(
            &[
                "speed_history.csv",
                "response.csv",
                "orders.csv",
                "full_waterfall.csv",
            ],
            &[
                "speed_history.png",
                "bode.png",
                "bode_phase.png",
                "orders.png",
                "response.png",
                "contact_force.png",
                "friction_energy.png",
                "full_waterfall.png",
            ],
        );
        if stress {
            add(
                &["stress_history.csv"],
                &["stress_vs_speed.png", "stress_history.png"],
            );
        }
        if !s.output.snapshot_speeds.is_empty() {
            add(&["orbit_snapshots.csv"], &["orbit_snapshots.png"]);
        }
        if stick {
            add(&[], &["dry_whirl.png"]);
        }
        if s.stators
            .iter()
            .any(|st| st.wear().is_some() || st.abradable().is_some())
        {
            add(
                &["wear.csv", "worn_depth.csv"],
                &["wear.png", "worn_depth.png"],
            );
        }
    } else if let Some(w) = &s.run.sweep {
        files.push("cases/".into());
        let mut per = vec!["sweep.csv".to_string(), "full_cascade.csv".to_string()];
        if png {
            per.extend(["cascade.png", "bifurcation.png", "regime_map.png"].map(String::from));
            let grids = s.output.orbit_grids.len().max(1);
            per.extend((1..=grids).map(|g| format!("orbits_{g}.png")));
            if !s.output.force_histories.is_empty() {
                per.push("contact_force.png".into());
            }
            per.push("full_cascade.png".into());
            if stick {
                per.push("dry_whirl.png".into());
            }
        }
        let variants = rubsim::study::variants(w.vary.as_ref());
        for v in &variants {
            files.extend(per.iter().map(|f| format!("{}{f}", v.prefix)));
        }
    } else {
        add(
            &["full_spectrum.csv"],
            &[
                "orbit.png",
                "spectrum.png",
                "contact_force.png",
                "full_spectrum.png",
            ],
        );
    }
    files
}
