//! `rubsim mesh`: mesh a geometry through gmsh (or take it from the cache) and report it.

use anyhow::{bail, Context, Result};
use rubsim::mesh::gmsh::{self, MeshRequest};
use rubsim::mesh::Mesh;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Options of `rubsim mesh`.
#[derive(clap::Args, Clone, Debug)]
pub struct MeshArgs {
    /// Geometry: a gmsh `.geo`, or a CAD file (`.step`, `.stp`, `.brep`, `.iges`, `.igs`).
    pub geometry: PathBuf,
    /// Set a geometry parameter (declared by its `DefineConstant`): `--set ri=0.0601` (repeatable).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    pub set: Vec<String>,
    /// Element order (1 linear, 2 quadratic).
    #[arg(long, default_value_t = 1)]
    pub order: u8,
    /// Recombine triangles into quadrilaterals.
    #[arg(long)]
    pub quads: bool,
    /// Second order without the face-centre node (8-node quadrilaterals).
    #[arg(long)]
    pub serendipity: bool,
    /// Factor on every mesh size.
    #[arg(long, default_value_t = 1.0)]
    pub size_factor: f64,
    /// Cache directory (default: `meshes/` beside the geometry's `geometry/` directory).
    #[arg(long)]
    pub cache: Option<PathBuf>,
    /// Also copy the mesh to this file.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

fn parse_set(set: &[String]) -> Result<BTreeMap<String, f64>> {
    let mut p = BTreeMap::new();
    for a in set {
        let (k, v) = a
            .split_once('=')
            .with_context(|| format!("--set {a}: expected NAME=VALUE"))?;
        let v: f64 = v
            .trim()
            .parse()
            .with_context(|| format!("--set {a}: `{}` is not a number", v.trim()))?;
        if !v.is_finite() {
            bail!("--set {a}: the value must be finite");
        }
        p.insert(k.trim().to_string(), v);
    }
    Ok(p)
}

/// Runs `rubsim mesh`.
pub fn mesh(a: &MeshArgs) -> Result<()> {
    let req = MeshRequest {
        geometry: a.geometry.clone(),
        parameters: parse_set(&a.set)?,
        order: a.order,
        recombine: a.quads,
        serendipity: a.serendipity,
        size_factor: a.size_factor,
        referenced_by: None,
    };
    if !(a.size_factor.is_finite() && a.size_factor > 0.0) {
        bail!("--size-factor must be positive, got {}", a.size_factor);
    }
    let cache = a
        .cache
        .clone()
        .unwrap_or_else(|| gmsh::default_cache_dir(&a.geometry));
    let t0 = std::time::Instant::now();
    let meshed = gmsh::mesh(&req, &cache)?;
    let took = t0.elapsed().as_secs_f64();
    let m = Mesh::read(&meshed.msh)?;
    println!(
        "{}: {} ({})",
        a.geometry.display(),
        meshed.msh.display(),
        if meshed.from_cache {
            "up to date, gmsh not run".to_string()
        } else {
            format!("meshed by gmsh in {took:.2} s")
        }
    );
    report(&m)?;
    if let Some(out) = &a.out {
        std::fs::copy(&meshed.msh, out)
            .with_context(|| format!("copying the mesh to {}", out.display()))?;
        println!("copied to {}", out.display());
    }
    Ok(())
}

/// Prints nodes, cells per kind, groups, and checks conformity and the contact boundary.
fn report(m: &Mesh) -> Result<()> {
    let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
    for b in &m.blocks {
        *kinds.entry(b.kind.name()).or_default() += b.len();
    }
    let (lo, hi) = m.nodes.iter().fold(
        ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
        |(mut lo, mut hi), p| {
            for i in 0..3 {
                lo[i] = lo[i].min(p[i]);
                hi[i] = hi[i].max(p[i]);
            }
            (lo, hi)
        },
    );
    println!(
        "  {}-D mesh, {} nodes, bounding box [{:.4e}, {:.4e}] × [{:.4e}, {:.4e}] × [{:.4e}, {:.4e}] m",
        m.dim(),
        m.nodes.len(),
        lo[0],
        hi[0],
        lo[1],
        hi[1],
        lo[2],
        hi[2]
    );
    for (k, n) in &kinds {
        println!("  {n} × {k}");
    }
    for g in &m.groups {
        let nodes = m.group_nodes(&g.name).map(|v| v.len()).unwrap_or(0);
        let cells: usize = m.group_blocks(g).map(|b| b.len()).sum();
        println!(
            "  group `{}` (dim {}, tag {}): {} entities, {} elements, {} nodes",
            g.name,
            g.dim,
            g.tag,
            g.entities.len(),
            cells,
            nodes
        );
    }
    m.check_conforming()?;
    println!("  conforming: no coincident or hanging nodes");
    if m.groups.iter().any(|g| g.name == "stator_contact") {
        let n = m.boundary_normals("stator_contact")?;
        let rho: Vec<f64> = n
            .iter()
            .map(|(i, _)| m.nodes[*i][0].hypot(m.nodes[*i][1]))
            .collect();
        let inward = n
            .iter()
            .filter(|(i, v)| v[0] * m.nodes[*i][0] + v[1] * m.nodes[*i][1] < 0.0)
            .count();
        println!(
            "  stator_contact: {} nodes at radius {:.6e} … {:.6e} m from the axis; {} of them face the axis (outward normal pointing inward)",
            n.len(),
            rho.iter().cloned().fold(f64::INFINITY, f64::min),
            rho.iter().cloned().fold(0.0, f64::max),
            inward
        );
    }
    Ok(())
}

/// Options of `rubsim stress`.
#[derive(clap::Args, Clone, Debug)]
pub struct StressArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Override a scene value (repeatable), as for the other commands.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Speeds ω/ω_n (repeatable; default: the scene's speed, or 1.7, 3.1, 4.9 — Fig. 10).
    #[arg(long = "speed")]
    pub speeds: Vec<f64>,
    /// Stress samples per revolution.
    #[arg(long, default_value_t = 64)]
    pub per_rev: usize,
    /// Revolutions at the end of the run that are kept (0: all).
    #[arg(long, default_value_t = 5)]
    pub window: usize,
    /// Output directory (default: out/<scene name>/stress).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `rubsim stress`: stress and strain histories of every stator (Fig. 10), the stress
/// field at the instant of largest stress, `stress.csv` and `summary.json`.
pub fn stress(a: &StressArgs) -> Result<()> {
    use rubsim::analysis::RunSettings;
    use rubsim::output::OutDir;
    use rubsim::plot::{self, Series};
    let ls = rubsim::scene::load(&a.scene, &a.set)?;
    let model = rubsim::model::Model::from_scene(&ls)
        .with_context(|| format!("{}: building the model", a.scene.display()))?;
    let settings = RunSettings::from_run(&ls.scene.run, &ls.scene.output.component);
    let speeds: Vec<f64> = if a.speeds.is_empty() {
        match ls.scene.run.speed_ratio.or_else(|| {
            ls.scene
                .run
                .speed
                .map(|w| w / model.rotor.natural_frequency())
        }) {
            Some(v) => vec![v],
            None => vec![1.7, 3.1, 4.9],
        }
    } else {
        a.speeds.clone()
    };
    for v in &speeds {
        if !(v.is_finite() && *v > 0.0) {
            bail!("--speed must be a positive ω/ω_n, got {v}");
        }
    }
    let stem = a
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let dir = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&stem).join("stress"));
    let mut outd = OutDir::prepare(&dir)?;
    let mut csv = String::from("speed_ratio,stator,t_s,contact_force_N,stress_Pa,strain,element\n");
    let mut stress_series = Vec::new();
    let mut strain_series = Vec::new();
    let mut summary = Vec::new();
    for &v in &speeds {
        let prep = rubsim::analysis::prepare(&model, &settings, v)?;
        let mut probe = rubsim::analysis::StressProbe::for_run(&prep, a.per_rev, a.window);
        prep.integrate(&mut [&mut probe])
            .map_err(|e| rubsim::error::Error::AtSpeed {
                speed_ratio: v,
                source: Box::new(e),
            })?;
        let r = rubsim::analysis::StressResults::new(&prep, probe);
        let case = &prep.case;
        for tr in &r.traces {
            for i in 0..tr.t.len() {
                csv.push_str(&format!(
                    "{v},{},{:.9e},{:.6e},{:.6e},{:.6e},{}\n",
                    tr.stator, tr.t[i], tr.force[i], tr.stress[i], tr.strain[i], tr.element[i]
                ));
            }
            let label = format!("ω/ωn = {v}: stator `{}`", tr.name);
            // Time in revolutions before the end, so that the speeds' panels align.
            let t_end = tr.t.last().copied().unwrap_or(0.0);
            let revs: Vec<f64> =
                tr.t.iter()
                    .map(|t| (t - t_end) * r.omega / (2.0 * std::f64::consts::PI))
                    .collect();
            stress_series.push(Series {
                label: label.clone(),
                t: revs.clone(),
                y: tr.stress.iter().map(|s| s / 1e6).collect(),
            });
            strain_series.push(Series {
                label,
                t: revs,
                y: tr.strain.iter().map(|s| s * 1e6).collect(),
            });
            let peak = tr.stress.iter().fold(0.0_f64, |m, s| m.max(s.abs()));
            let st = &case.stators[tr.stator];
            println!(
                "ω/ωn = {v}: stator `{}`: largest |stress| {:.4e} Pa (strain {:.3e}) at t = {:.6} s, {} node(s) in contact then; mean contact force {:.4e} N",
                tr.name,
                peak,
                tr.strain
                    .iter()
                    .fold(0.0_f64, |m, s| m.max(s.abs())),
                tr.peak_time,
                tr.peak_contacts.len(),
                tr.force.iter().sum::<f64>() / tr.force.len().max(1) as f64
            );
            summary.push(serde_json::json!({
                "speed_ratio": v,
                "stator": tr.name,
                "peak_stress_pa": peak,
                "peak_strain": tr.strain.iter().fold(0.0_f64, |m, s| m.max(s.abs())),
                "peak_time_s": tr.peak_time,
                "contacts_at_peak": tr.peak_contacts.len(),
                "samples": tr.t.len(),
                "dt_s": r.plan.dt,
            }));
            // log₁₀ of the stress over four decades below the peak: contact at nodes
            // concentrates it by orders of magnitude.
            let floor = 1e-4 * tr.peak_field.iter().fold(0.0_f64, |m, s| m.max(s.abs())) / 1e6;
            let mpa: Vec<f64> = tr
                .peak_field
                .iter()
                .map(|s| (s.abs() / 1e6).max(floor).max(1e-12).log10())
                .collect();
            let polys = rubsim::output::figures::cell_polygons(st, &mpa);
            if !polys.is_empty() && ls.scene.output.png {
                let marks: Vec<(f64, f64)> = tr
                    .peak_contacts
                    .iter()
                    .map(|&n| (st.nodes[n][0], st.nodes[n][1]))
                    .collect();
                let name = format!("stress_field_{}_{v}.png", tr.name);
                let p = outd.stage(&name)?;
                plot::mesh_field(
                    &p,
                    &format!(
                        "`{}` at ω/ωn = {v}, t = {:.5} s: von Mises stress (contact nodes ×)",
                        tr.name, tr.peak_time
                    ),
                    &polys,
                    "log₁₀ σ_vM (MPa)",
                    &marks,
                )?;
            }
        }
    }
    outd.write("stress.csv", csv.as_bytes())?;
    if ls.scene.output.png {
        let p = outd.stage("stress.png")?;
        plot::stacked_series(
            &p,
            "Largest element stress in the stator (bars: axial, cells: von Mises)",
            &stress_series,
            "t − t_end (revolutions)",
            "σ (MPa)",
        )?;
        let p = outd.stage("strain.png")?;
        plot::stacked_series(
            &p,
            "Strain of that element (σ/E)",
            &strain_series,
            "t − t_end (revolutions)",
            "ε (µm/m)",
        )?;
    }
    outd.write(
        "summary.json",
        serde_json::to_string_pretty(&serde_json::json!({
            "command": "stress",
            "scene_file": a.scene.display().to_string(),
            "overrides": a.set,
            "per_rev": a.per_rev,
            "window_revolutions": a.window,
            "results": summary,
        }))?
        .as_bytes(),
    )?;
    let d = outd.dir().to_path_buf();
    outd.commit()?;
    println!("results in {}", d.display());
    Ok(())
}

/// Options of `rubsim refine`.
#[derive(clap::Args, Clone, Debug)]
pub struct RefineArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Override a scene value (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// The scene key that refines the mesh, e.g. `stator.0.parameters.nx`.
    #[arg(long)]
    pub key: String,
    /// Its values, coarse to fine (comma separated).
    #[arg(long, value_delimiter = ',', required = true)]
    pub values: Vec<String>,
    /// Speed ω/ω_n (default: the scene's, or 1.7).
    #[arg(long)]
    pub speed: Option<f64>,
    /// Revolutions of the force histories drawn.
    #[arg(long, default_value_t = 3)]
    pub window: usize,
    /// Output directory (default: out/<scene name>/refine).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Runs `rubsim refine`: the same scene at several mesh refinements (the node-to-nodes
/// contact's sensitivity to the boundary discretisation): refine.csv, force and orbit overlays.
pub fn refine(a: &RefineArgs) -> Result<()> {
    use rubsim::analysis::{self, Keep, RunSettings};
    use rubsim::output::OutDir;
    use rubsim::plot::{self, Curve};
    let stem = a
        .scene
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let dir = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(&stem).join("refine"));
    let mut outd = OutDir::prepare(&dir)?;
    let mut csv = String::from(
        "value,targets,dofs,x_min_nd,x_max_nd,y_min_nd,y_max_nd,amp_1x_nd,contact_force_max_nd,ripple,period,steps,wall_s,us_per_step,setup_s\n",
    );
    let mut forces = Vec::new();
    let mut orbits = Vec::new();
    let mut rows = Vec::new();
    let mut cost = Vec::new();
    for v in &a.values {
        let mut set = a.set.clone();
        set.push(format!("{}={v}", a.key));
        set.push("run.error_estimate=false".into());
        let ls = rubsim::scene::load(&a.scene, &set)?;
        let model = rubsim::model::Model::from_scene(&ls)
            .with_context(|| format!("{} with {} = {v}", a.scene.display(), a.key))?;
        let speed = a.speed.or(ls.scene.run.speed_ratio).unwrap_or(1.7);
        let s = RunSettings::from_run(&ls.scene.run, &ls.scene.output.component);
        let keep = Keep {
            orbit: true,
            force_history: true,
            spectrum_up_to: None,
        };
        let t0 = std::time::Instant::now();
        let r = analysis::run_speed(&model, &s, speed, keep)?;
        let setup = t0.elapsed().as_secs_f64() - r.stats.wall_s;
        let us = 1e6 * r.stats.wall_s / r.stats.steps.max(1) as f64;
        let case = model.case(r.omega)?;
        let targets: usize = case.stators.iter().map(|m| m.targets.len()).sum();
        let dofs: usize = case.stators.iter().map(|m| m.ndof).sum();
        let t_end = r.force_history.last().map_or(0.0, |p| p.0);
        let tail: Vec<(f64, f64)> = r
            .force_history
            .iter()
            .copied()
            .filter(|p| p.0 >= t_end - a.window as f64)
            .collect();
        let rip = analysis::refine::ripple(&tail);
        csv.push_str(&format!(
            "{v},{targets},{dofs},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.4},{},{},{:.4},{us:.3},{setup:.3}\n",
            r.extents_nd[0],
            r.extents_nd[1],
            r.extents_nd[2],
            r.extents_nd[3],
            r.amp_1x_nd,
            r.contact_force_max_nd,
            rip,
            r.period,
            r.stats.steps,
            r.stats.wall_s
        ));
        println!(
            "{} = {v}: {targets} contact nodes, {dofs} DOF: y/|Z0| ∈ [{:.4}, {:.4}], 1× {:.4}, max force {:.4} (nd), ripple {:.3}, period {}, {} steps in {:.2} s ({us:.2} µs/step; setup {setup:.2} s)",
            a.key,
            r.extents_nd[2],
            r.extents_nd[3],
            r.amp_1x_nd,
            r.contact_force_max_nd,
            rip,
            r.period,
            r.stats.steps,
            r.stats.wall_s
        );
        cost.push((dofs as f64, us));
        let label = format!("{v} ({targets} nodes)");
        forces.push(Curve {
            label: label.clone(),
            points: tail.iter().map(|p| (p.0 - t_end, p.1)).collect(),
        });
        orbits.push(Curve {
            label,
            points: r.orbit_nd.iter().map(|p| (p[0], p[1])).collect(),
        });
        rows.push(serde_json::json!({
            "value": v, "targets": targets, "dofs": dofs, "extents_nd": r.extents_nd,
            "amp_1x_nd": r.amp_1x_nd, "contact_force_max_nd": r.contact_force_max_nd,
            "ripple": rip, "period": r.period, "steps": r.stats.steps, "wall_s": r.stats.wall_s,
            "us_per_step": us, "setup_s": setup, "dt_s": r.plan.dt,
        }));
    }
    outd.write("refine.csv", csv.as_bytes())?;
    let p = outd.stage("refine_force.png")?;
    plot::lines(
        &p,
        &format!("Contact force, last {} revolutions, by {}", a.window, a.key),
        &forces,
        "t − t_end (revolutions)",
        "vertical contact force / (m_u e ω²)",
    )?;
    let p = outd.stage("refine_orbit.png")?;
    plot::lines(
        &p,
        &format!("Steady orbit by {}", a.key),
        &orbits,
        "x / |Z0|",
        "y / |Z0|",
    )?;
    let p = outd.stage("refine_cost.png")?;
    plot::loglog(
        &p,
        "Time per step against stator DOFs",
        &[Curve {
            label: a.key.clone(),
            points: cost,
        }],
        "stator DOFs",
        "wall time per step (µs)",
    )?;
    outd.write(
        "summary.json",
        serde_json::to_string_pretty(&serde_json::json!({
            "command": "refine", "scene_file": a.scene.display().to_string(),
            "key": a.key, "overrides": a.set, "results": rows,
        }))?
        .as_bytes(),
    )?;
    let d = outd.dir().to_path_buf();
    outd.commit()?;
    println!("results in {}", d.display());
    Ok(())
}
