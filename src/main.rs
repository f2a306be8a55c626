//! The `rubsim` command: scene → model → integrate → analyse → write.

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use rubsim::analysis::{self, Keep, RunSettings};
use rubsim::model::Model;
use rubsim::output::{self, OutDir};
use rubsim::scene::{self, LoadedScene};
use rubsim::time::FrameSink;
use std::path::{Path, PathBuf};

mod mesh_cmd;
mod rotordyn_cmd;

#[derive(Parser)]
#[command(
    name = "rubsim",
    version,
    about = "Rotor-to-stator rubbing vibration: FE contact with Lagrange multipliers and explicit central differences"
)]
struct Cli {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(clap::Args, Clone)]
struct Common {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Override a scene value: `--set stator.0.clearance_nd=0.5` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
}

#[derive(Subcommand)]
enum Cmd {
    /// Mesh a stator geometry (.geo or STEP) with gmsh into the cache `meshes/` and report it:
    /// nodes, cells, physical groups, conformity, the contact boundary.
    Mesh(mesh_cmd::MeshArgs),
    /// Stress and strain in the stators during a run at one or more speeds (the paper's
    /// Fig. 10): stress.csv, stress.png, strain.png, the stress field at its peak.
    Stress(mesh_cmd::StressArgs),
    /// Run a scene at several mesh refinements (a scene key, e.g. a geometry parameter) and
    /// compare orbits and contact forces: the node-to-nodes contact's mesh sensitivity.
    Refine(mesh_cmd::RefineArgs),
    /// Run one speed (run.speed_ratio or run.speed) and write summary.json and pictures.
    Run {
        #[command(flatten)]
        c: Common,
        /// Output directory (default: out/<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Run at this ω/ω_n instead of the scene's speed (also picks one speed of a sweep scene).
        #[arg(long)]
        speed: Option<f64>,
    },
    /// Run the speed sweep of [run.sweep] in parallel; write sweep.csv, summary.json, pictures.
    Sweep {
        #[command(flatten)]
        c: Common,
        /// Output directory (default: out/<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Worker threads (default: all cores).
        #[arg(long)]
        jobs: Option<usize>,
    },
    /// Validate the scene and print the resolved model: what is built and what is left out.
    Check {
        #[command(flatten)]
        c: Common,
    },
    /// Error against Δt and run time for each integrator at one or more speeds.
    Convergence {
        #[command(flatten)]
        c: Common,
        /// Speeds ω/ω_n (default: the scene's speed, or 1.7, 3.1, 4.9 for a sweep scene).
        #[arg(long = "speed")]
        speeds: Vec<f64>,
        /// Finest level k of the study: steps per revolution = samples_per_rev · 2^k, k = 0..=K.
        #[arg(long, default_value_t = 6)]
        levels: u32,
        /// Reference level (collocated integrator).
        #[arg(long, default_value_t = 11)]
        reference: u32,
        /// Output directory (default: out/<scene name>/convergence).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Damped modes of the rotor alone at one speed, and its static deflection under gravity.
    Modal {
        #[command(flatten)]
        c: Common,
        /// Speed ω/ω_n.
        #[arg(long, default_value_t = 0.0)]
        speed: f64,
        /// Number of modes.
        #[arg(long, default_value_t = 8)]
        modes: usize,
        /// Gravity (m/s², along −y) for the static deflection.
        #[arg(long, default_value_t = 9.81)]
        gravity: f64,
        /// Output directory (default: out/<scene name>/modal).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Campbell diagram with mode tracking, forward/backward labels and critical speeds.
    Campbell {
        #[command(flatten)]
        c: Common,
        /// First speed ω/ω_n.
        #[arg(long, default_value_t = 0.0)]
        from: f64,
        /// Last speed ω/ω_n.
        #[arg(long, default_value_t = 6.0)]
        to: f64,
        /// Number of speeds.
        #[arg(long, default_value_t = 31)]
        points: usize,
        /// Number of modes tracked.
        #[arg(long, default_value_t = 6)]
        modes: usize,
        /// Output directory (default: out/<scene name>/campbell).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Unbalance response (Bode and polar) of the rotor alone at chosen nodes.
    Unbalance {
        #[command(flatten)]
        c: Common,
        /// First speed ω/ω_n.
        #[arg(long, default_value_t = 0.05)]
        from: f64,
        /// Last speed ω/ω_n.
        #[arg(long, default_value_t = 6.0)]
        to: f64,
        /// Number of speeds.
        #[arg(long, default_value_t = 400)]
        points: usize,
        /// Nodes (repeatable; default: the stations' nodes).
        #[arg(long = "node")]
        nodes: Vec<usize>,
        /// Output directory (default: out/<scene name>/unbalance).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Time the scene's sweep (no output files) and print wall time, ns per step and error.
    Bench {
        #[command(flatten)]
        c: Common,
        /// Repetitions (the best is reported).
        #[arg(long, default_value_t = 3)]
        repeat: usize,
        /// Worker threads (default: all cores).
        #[arg(long)]
        jobs: Option<usize>,
        /// Also run a converged reference sweep (collocated, Δt 16× finer) and report the
        /// orbit-extents error of the timed sweep against it.
        #[arg(long)]
        reference: bool,
    },
}

fn load(c: &Common) -> Result<(LoadedScene, Model)> {
    let ls = scene::load(&c.scene, &c.set)?;
    let model = Model::from_scene(&ls)
        .with_context(|| format!("{}: building the model", c.scene.display()))?;
    Ok((ls, model))
}

fn default_out(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_else(|| "scene".into());
    PathBuf::from("out").join(stem)
}

fn settings(ls: &LoadedScene) -> RunSettings {
    RunSettings::from_run(&ls.scene.run, &ls.scene.output.component)
}

fn single_speed(ls: &LoadedScene, model: &Model) -> Option<f64> {
    let r = &ls.scene.run;
    r.speed_ratio
        .or_else(|| r.speed.map(|w| w / model.rotor.natural_frequency()))
}

fn summary_base(ls: &LoadedScene, model: &Model, command: &str) -> serde_json::Value {
    serde_json::json!({
        "rubsim_version": env!("CARGO_PKG_VERSION"),
        "command": command,
        "scene_file": ls.file.display().to_string(),
        "overrides": ls.overrides,
        "scene": ls.scene,
        "model": {
            "rotor": model.rotor.describe(),
            "omega_n_rad_s": model.rotor.natural_frequency(),
        },
        "conventions": {
            "units": "SI; _nd = displacement / |Z0(ω)|, force / (|Σ m_u e e^{iφ}| ω²), frequency / ω_n",
            "axes": "x horizontal, y vertical, rotor spins counter-clockwise seen from +z",
            "period": "Poincaré period in revolutions; 0 = not periodic",
        }
    })
}

fn run(c: &Common, out: Option<PathBuf>, speed: Option<f64>) -> Result<()> {
    let (ls, model) = load(c)?;
    if let Some(v) = speed {
        if !(v.is_finite() && v > 0.0) {
            anyhow::bail!("--speed must be a positive ω/ω_n, got {v}");
        }
    }
    let v = speed.or_else(|| single_speed(&ls, &model)).with_context(|| {
        format!(
            "{}: `rubsim run` needs run.speed_ratio or run.speed, or --speed (this scene has a sweep: use `rubsim sweep`)",
            c.scene.display()
        )
    })?;
    let mut outd = OutDir::prepare(&out.unwrap_or_else(|| default_out(&c.scene)))?;
    let s = settings(&ls);
    let keep = Keep::single_run(&ls.scene.output, v);
    let t0 = std::time::Instant::now();
    let prep = analysis::prepare(&model, &s, v)?;
    // VTK/HDF5 time series (output.vtk, output.hdf5) stream into the staging folder.
    let scene_json = serde_json::to_string(&ls.scene)?;
    let staging = outd.staging_dir().to_path_buf();
    let mut series = rubsim::results::ResultsSink::for_output(
        &model,
        &prep,
        &ls.scene.output,
        &scene_json,
        &staging,
        "",
    )?;
    let mut sinks: Vec<&mut dyn FrameSink> = series.iter_mut().map(|w| w as _).collect();
    let r = prep.run(keep, &mut sinks)?;
    if let Some(w) = series {
        for name in &w.finish()? {
            outd.adopt(name)?;
        }
    }
    if ls.scene.output.png {
        output::figures::write_run(
            &mut outd,
            &ls.scene.title,
            &r,
            output::figures::boundary(&prep.case),
            &ls.scene.output.component,
        )?;
    }
    let mut sum = summary_base(&ls, &model, "run");
    sum["result"] = serde_json::to_value(&r)?;
    sum["regime"] = analysis::regime_name(r.period).into();
    sum["wall_s"] = t0.elapsed().as_secs_f64().into();
    outd.write(
        "summary.json",
        serde_json::to_string_pretty(&sum)?.as_bytes(),
    )?;
    let dir = outd.dir().to_path_buf();
    outd.commit()?;
    println!(
        "ω/ωn = {:.3}: {} | x/|Z0| ∈ [{:.3}, {:.3}], y/|Z0| ∈ [{:.3}, {:.3}] | 1× {:.3}, 1/2× {:.3}, 1/3× {:.3} | {} steps (Δt = {:.3e} s) in {:.3} s | est. rel. error {}",
        r.speed_ratio,
        analysis::regime_name(r.period),
        r.extents_nd[0], r.extents_nd[1], r.extents_nd[2], r.extents_nd[3],
        r.amp_1x_nd, r.amp_half_nd, r.amp_third_nd,
        r.stats.steps, r.plan.dt, r.stats.wall_s,
        r.error.map(|e| format!("{:.1e}", e.extents_rel)).unwrap_or_else(|| "not estimated".into())
    );
    println!("results in {}", dir.display());
    Ok(())
}

/// Writes `summary.json` last, moves every staged file into place and says where.
fn finish(mut outd: OutDir, sum: &serde_json::Value) -> Result<()> {
    outd.write(
        "summary.json",
        serde_json::to_string_pretty(sum)?.as_bytes(),
    )?;
    let dir = outd.dir().to_path_buf();
    outd.commit()?;
    println!("results in {}", dir.display());
    Ok(())
}

fn progress_bar(n: usize) -> ProgressBar {
    let pb = ProgressBar::new(n as u64);
    pb.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} speeds {msg}",
        )
        .expect("valid template"),
    );
    pb
}

fn sweep(c: &Common, out: Option<PathBuf>) -> Result<()> {
    let (ls, model) = load(c)?;
    let sw = ls.scene.run.sweep.clone().with_context(|| {
        format!(
            "{}: `rubsim sweep` needs a [run.sweep] table",
            c.scene.display()
        )
    })?;
    let mut outd = OutDir::prepare(&out.unwrap_or_else(|| default_out(&c.scene)))?;
    let speeds = analysis::sweep_speeds(sw.from, sw.to, sw.step);
    let variants: Vec<(String, Vec<String>)> = match &sw.vary {
        None => vec![(String::new(), Vec::new())],
        Some(v) => v
            .values
            .iter()
            .map(|x| {
                let name = v.key.rsplit('.').next().unwrap_or("value");
                (format!("{name}_{x}/"), vec![format!("{}={}", v.key, x)])
            })
            .collect(),
    };
    let t0 = std::time::Instant::now();
    let mut variant_summaries = Vec::new();
    for (prefix, extra) in &variants {
        let (ls_v, model_v) = if extra.is_empty() {
            (ls.clone(), model.clone())
        } else {
            let mut sets = c.set.clone();
            sets.extend(extra.iter().cloned());
            load(&Common {
                scene: c.scene.clone(),
                set: sets,
            })?
        };
        let s = settings(&ls_v);
        let o = &ls_v.scene.output;
        let fmax = analysis::sweep::cascade_max(o, &speeds);
        let keep = analysis::sweep::SweepKeep::new(o, fmax);
        let pb = progress_bar(speeds.len());
        if !prefix.is_empty() {
            pb.set_message(prefix.trim_end_matches('/').to_string());
        }
        // Per-speed VTK/HDF5 time series (output.per_speed) into `speed_<ν>/` sub-folders.
        let selected = rubsim::results::per_speed_selection(o, &speeds)
            .map_err(|m| ls_v.invalid("output.per_speed", m))?;
        let scene_json = serde_json::to_string(&ls_v.scene)?;
        let staging = outd.staging_dir().to_path_buf();
        let written = std::sync::Mutex::new(Vec::new());
        let run = |v: f64| -> rubsim::error::Result<_> {
            let prep = analysis::prepare(&model_v, &s, v)?;
            let i = speeds.iter().position(|x| *x == v);
            let mut series = if i.is_some_and(|i| selected[i]) {
                let dir = format!("{prefix}{}", rubsim::results::speed_folder(v));
                rubsim::results::ResultsSink::for_output(
                    &model_v,
                    &prep,
                    o,
                    &scene_json,
                    &staging,
                    &dir,
                )?
            } else {
                None
            };
            let mut sinks: Vec<&mut dyn FrameSink> = series.iter_mut().map(|w| w as _).collect();
            let r = prep.run(keep.at(v), &mut sinks)?;
            if let Some(w) = series {
                let names = w.finish()?;
                written.lock().expect("no writer panicked").extend(names);
            }
            Ok((r, output::figures::boundary(&prep.case)))
        };
        let (res, bounds) = analysis::sweep(&speeds, &run, &|| pb.inc(1))?.unzip();
        let mut series = written.into_inner().expect("no writer panicked");
        series.sort();
        for name in &series {
            outd.adopt(name)?;
        }
        pb.finish_and_clear();
        let grids = analysis::sweep::orbit_grids(o, &speeds);
        let title = if extra.is_empty() {
            ls_v.scene.title.clone()
        } else {
            format!("{} [{}]", ls_v.scene.title, extra.join(", "))
        };
        output::csv::write_sweep(&mut outd, prefix, &res)?;
        output::figures::write_sweep(
            &mut outd,
            prefix,
            &res,
            &output::figures::SweepFigures {
                title: &title,
                bounds: &bounds,
                orbit_grids: &grids,
                force_histories: &o.force_histories,
                cascade_max: fmax,
                png: o.png,
                component: &o.component,
            },
        )?;
        let regimes = analysis::regime_ranges(&res.speeds);
        let peaks = analysis::quasi_resonances(&res.speeds);
        let total_steps = res.total_steps();
        let max_err = res.max_estimated_error();
        println!(
            "{}{} speeds in {:.3} s ({} steps){}",
            if prefix.is_empty() {
                String::new()
            } else {
                format!("{}: ", extra.join(", "))
            },
            speeds.len(),
            res.wall_s,
            total_steps,
            if max_err > 0.0 {
                format!(", largest estimated extents error {max_err:.1e}")
            } else {
                String::new()
            }
        );
        for r in &regimes {
            println!(
                "  {:>13}  ω/ωn {:.2} – {:.2}",
                analysis::regime_name(r.period),
                r.from,
                r.to
            );
        }
        if !peaks.is_empty() {
            let p: Vec<String> = peaks
                .iter()
                .map(|(per, v)| format!("{v:.2} ({})", analysis::regime_name(*per)))
                .collect();
            println!("  quasi-resonance peaks: {}", p.join(", "));
        }
        variant_summaries.push(serde_json::json!({
            "variant": extra,
            "directory": prefix,
            "wall_s": res.wall_s,
            "steps": total_steps,
            "max_estimated_extents_error": max_err,
            "regimes": regimes,
            "quasi_resonances": peaks,
            "speeds": res.speeds,
        }));
    }
    let mut sum = summary_base(&ls, &model, "sweep");
    sum["sweeps"] = serde_json::Value::Array(variant_summaries);
    sum["wall_s"] = t0.elapsed().as_secs_f64().into();
    finish(outd, &sum)
}

fn check(c: &Common) -> Result<()> {
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
    let case = model.case(
        single_speed(&ls, &model)
            .or_else(|| s.run.sweep.as_ref().map(|w| w.from))
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
    for (spec, m) in s.stators.iter().zip(&case.stators) {
        let kind = match spec {
            scene::StatorSpec::Rod(_) => "rod (2-D bar elements, lateral DOFs guided)",
            scene::StatorSpec::Ring(_) => {
                "rigid ring on isotropic springs (circle-in-circle contact)"
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
        if m.massless() {
            println!(
                "  massless: enters the time loop as the compliance of its {} contact DOFs (one sparse Cholesky; {}), not as a mesh",
                m.contact_dofs().len(),
                if m.contact_dofs().len() <= rubsim::time::EAGER_DOFS { "every column up front" } else { "columns computed when a node first touches, cached" }
            );
        } else {
            println!(
                "  with mass: lumped, integrated explicitly; ω_max ≤ {:.4e} rad/s",
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
                "  clearance δ = {nd} |Z0(ω)| (= {:.4e} m at ω/ωn = {:.2}; changes with speed)",
                m.clearance, case.speed_ratio
            ),
            None => println!("  clearance δ = {:.4e} m", m.clearance),
        }
    }
    let st = settings(&ls);
    let plan = rubsim::time::plan_steps(&case, &st.step)?;
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
        None => format!("single speed ω/ωn = {:.4}", case.speed_ratio),
    };
    println!("run: {speeds}");
    println!(
        "  integrator {}; {} revolutions, first {} cut as transient; {} samples/rev recorded; error estimate {}",
        s.run.integrator.name(),
        s.run.revolutions,
        s.run.transient_revolutions,
        s.run.samples_per_rev,
        if s.run.error_estimate { "by a companion run at 2Δt" } else { "off" }
    );
    println!(
        "  Δt at ω/ωn = {:.2}: {:.4e} s ({} steps/rev); paper rule (n = {}) {:.4e} s; stability limit {:.4e} s; ω_max {:.4e} rad/s",
        case.speed_ratio, plan.dt, plan.steps_per_rev, s.run.harmonics, plan.rule_dt, plan.limit, plan.omega_max
    );
    println!(
        "built: {} rotor body with {} DOF, {} stator(s), {} contact candidate pair(s)",
        match model.rotor {
            rubsim::model::Rotor::Jeffcott(_) => "Jeffcott",
            rubsim::model::Rotor::Fe(_) =>
                "finite-element (sparse M, C + ΩG, K; M̃ factored once per speed by sparse LU)",
        },
        case.rotor.ndof,
        case.stators.len(),
        case.stators.iter().map(|m| m.targets.len()).sum::<usize>()
    );
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
    println!(
        "outputs: summary.json{}{}",
        if s.run.sweep.is_some() {
            ", sweep.csv"
        } else {
            ""
        },
        if s.output.png {
            if s.run.sweep.is_some() {
                ", cascade.png, bifurcation.png, regime_map.png, orbits_N.png, contact_force.png"
            } else {
                ", orbit.png, spectrum.png, contact_force.png"
            }
        } else {
            ""
        }
    );
    for line in rubsim::results::describe(&s.output, &plan, s.run.sweep.is_some()) {
        println!("  {line}");
    }
    Ok(())
}

fn convergence(
    c: &Common,
    speeds: &[f64],
    levels: u32,
    reference: u32,
    out: Option<PathBuf>,
) -> Result<()> {
    let (ls, model) = load(c)?;
    let speeds: Vec<f64> = if speeds.is_empty() {
        match single_speed(&ls, &model) {
            Some(v) => vec![v],
            None => vec![1.7, 3.1, 4.9],
        }
    } else {
        speeds.to_vec()
    };
    let mut outd =
        OutDir::prepare(&out.unwrap_or_else(|| default_out(&c.scene).join("convergence")))?;
    let mut s = settings(&ls);
    s.error_estimate = false;
    let lv: Vec<u32> = (0..=levels).collect();
    let mut all = Vec::new();
    for v in &speeds {
        let res = analysis::convergence(&model, &s, *v, &lv, reference, 12)?;
        println!(
            "ω/ωn = {v}: reference collocated Δt = {:.3e} s, period {}",
            res.reference_dt, res.reference_period
        );
        println!(
            "  {:>18} {:>10} {:>8} {:>10} {:>10} {:>10} {:>10} {:>6} {:>9}",
            "integrator",
            "Δt·ωn",
            "steps/rev",
            "orbit err",
            "ext err",
            "1× err",
            "sub err",
            "period",
            "wall s"
        );
        for p in &res.points {
            println!(
                "  {:>18} {:>10.3e} {:>8} {:>10.2e} {:>10.2e} {:>10.2e} {:>10.2e} {:>6} {:>9.4}",
                p.integrator,
                p.dt_wn,
                p.steps_per_rev,
                p.orbit_err,
                p.extents_err,
                p.lines_err[0],
                p.lines_err[1].max(p.lines_err[2]),
                p.period,
                p.wall_s
            );
        }
        for (n, o) in &res.orders {
            println!("  observed order {n}: {o:.2}");
        }
        output::csv::write_convergence(&mut outd, &format!("speed_{v}/"), &res)?;
        if ls.scene.output.png {
            output::figures::write_convergence(
                &mut outd,
                &format!("speed_{v}/"),
                &ls.scene.title,
                &res,
            )?;
        }
        all.push(res);
    }
    let mut sum = summary_base(&ls, &model, "convergence");
    sum["studies"] = serde_json::to_value(&all)?;
    finish(outd, &sum)
}

fn bench(c: &Common, repeat: usize, reference: bool) -> Result<()> {
    let (ls, model) = load(c)?;
    let s = settings(&ls);
    let speeds = match &ls.scene.run.sweep {
        Some(w) => analysis::sweep_speeds(w.from, w.to, w.step),
        None => vec![single_speed(&ls, &model).unwrap_or(1.0)],
    };
    let r = analysis::bench::best_of(&model, &s, &speeds, repeat)?;
    let steps = r.total_steps();
    let err = r.max_estimated_error();
    println!(
        "bench {}: {} speeds, threads {}, best of {}: wall {:.3} s, {} steps (main runs), {:.1} ns/step (loop time per step, main runs), largest estimated extents error {:.2e}{}",
        c.scene.display(),
        speeds.len(),
        rayon::current_num_threads(),
        repeat.max(1),
        r.wall_s,
        steps,
        analysis::bench::ns_per_step(&r),
        err,
        if s.error_estimate { " (wall includes the 2Δt companion runs)" } else { "" }
    );
    if reference {
        let rs = analysis::bench::reference_settings(&s);
        let rr = analysis::sweep(
            &speeds,
            &|v| analysis::run_speed(&model, &rs, v, Keep::default()),
            &|| {},
        )?;
        let cmp = analysis::bench::compare(&r, &rr);
        println!(
            "reference: collocated, Δt 16× finer ({:.3} s): orbit-extents error of the timed sweep — median {:.2e}, largest over periodic speeds {:.2e}, largest overall {:.2e} at ω/ωn = {} (reference period {}); {} of {} speeds above 1%",
            rr.wall_s,
            cmp.median,
            cmp.largest_periodic,
            cmp.largest,
            cmp.largest_at,
            cmp.largest_period,
            cmp.above_one_percent,
            cmp.speeds
        );
    }
    Ok(())
}

fn main() {
    // Die quietly on a closed pipe (`rubsim … | head`) instead of panicking in println!.
    // SAFETY: restoring the default disposition of SIGPIPE before any thread is started.
    #[cfg(unix)]
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    let jobs = match &cli.cmd {
        Cmd::Sweep { jobs, .. } | Cmd::Bench { jobs, .. } => *jobs,
        _ => None,
    };
    if let Some(j) = jobs {
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(j.max(1))
            .build_global();
    }
    let r = match &cli.cmd {
        Cmd::Run { c, out, speed } => run(c, out.clone(), *speed),
        Cmd::Sweep { c, out, .. } => sweep(c, out.clone()),
        Cmd::Check { c } => check(c),
        Cmd::Mesh(a) => mesh_cmd::mesh(a),
        Cmd::Stress(a) => mesh_cmd::stress(a),
        Cmd::Refine(a) => mesh_cmd::refine(a),
        Cmd::Modal {
            c,
            speed,
            modes,
            gravity,
            out,
        } => rotordyn_cmd::modal(c, *speed, *modes, *gravity, out.clone()),
        Cmd::Campbell {
            c,
            from,
            to,
            points,
            modes,
            out,
        } => rotordyn_cmd::campbell(c, *from, *to, *points, *modes, out.clone()),
        Cmd::Unbalance {
            c,
            from,
            to,
            points,
            nodes,
            out,
        } => rotordyn_cmd::unbalance(c, *from, *to, *points, nodes, out.clone()),
        Cmd::Convergence {
            c,
            speeds,
            levels,
            reference,
            out,
        } => convergence(c, speeds, *levels, *reference, out.clone()),
        Cmd::Bench {
            c,
            repeat,
            reference,
            ..
        } => bench(c, *repeat, *reference),
    };
    if let Err(e) = r {
        // `{e:#}` would repeat a cause its parent already quotes (e.g. the I/O error of
        // "cannot read scene file: …"); append only causes not already shown.
        let mut msg = e.to_string();
        for cause in e.chain().skip(1) {
            let c = cause.to_string();
            if !msg.ends_with(&c) {
                msg = format!("{msg}: {c}");
            }
        }
        eprintln!("error: {msg}");
        std::process::exit(2);
    }
}
