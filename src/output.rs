//! Writing results: `summary.json`, `sweep.csv`, `convergence.csv` and PNG pictures.
//!
//! Every file is first written into a staging folder inside the output directory and moved
//! into place only when the whole command has succeeded, `summary.json` last; a failed or
//! killed run leaves no file that looks complete. The directory is checked for writability
//! before any computation starts ([`OutDir::prepare`]).

use crate::analysis::{regime_name, ConvergenceResults, SpeedResults, SweepResults};
use crate::error::{Error, Result};
use crate::model::Case;
use crate::plot::{self, Boundary, CascadeLine, Curve, OrbitPanel, Series};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Name of the manifest listing the files of the last completed run in a directory.
pub const MANIFEST: &str = ".rubsim-files";
const STAGING_PREFIX: &str = ".rubsim-partial-";

/// An output directory with a staging area.
#[derive(Debug)]
pub struct OutDir {
    dir: PathBuf,
    staging: PathBuf,
    files: Vec<String>,
    committed: bool,
    created: bool,
}

/// True when a staging folder's owner process no longer runs (Linux `/proc`; elsewhere
/// staging folders of other processes are left alone).
fn stale_staging(name: &str) -> bool {
    match name
        .strip_prefix(STAGING_PREFIX)
        .and_then(|p| p.parse::<u32>().ok())
    {
        Some(pid) => {
            Path::new("/proc/self").exists()
                && pid != std::process::id()
                && !Path::new(&format!("/proc/{pid}")).exists()
        }
        None => false,
    }
}

impl OutDir {
    /// Creates `dir` if needed and checks that files can be written there; removes staging
    /// folders left by killed runs.
    pub fn prepare(dir: &Path) -> Result<Self> {
        if dir.exists() && !dir.is_dir() {
            return Err(Error::output(
                dir,
                "output path exists and is not a directory",
            ));
        }
        let created = !dir.exists();
        std::fs::create_dir_all(dir)
            .map_err(|e| Error::output(dir, format!("cannot create output directory: {e}")))?;
        if let Ok(rd) = std::fs::read_dir(dir) {
            for e in rd.flatten() {
                let name = e.file_name().to_string_lossy().to_string();
                if stale_staging(&name) {
                    let _ = std::fs::remove_dir_all(e.path());
                }
            }
        }
        let staging = dir.join(format!("{STAGING_PREFIX}{}", std::process::id()));
        std::fs::create_dir_all(&staging)
            .map_err(|e| Error::output(dir, format!("output directory is not writable: {e}")))?;
        let probe = staging.join(".probe");
        std::fs::File::create(&probe)
            .and_then(|mut f| f.write_all(b"probe"))
            .map_err(|e| Error::output(dir, format!("output directory is not writable: {e}")))?;
        let _ = std::fs::remove_file(&probe);
        Ok(Self {
            dir: dir.to_path_buf(),
            staging,
            files: Vec::new(),
            committed: false,
            created,
        })
    }

    /// The final directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Staging path of a file to be produced as `name` (relative, may contain `/`).
    pub fn stage(&mut self, name: &str) -> Result<PathBuf> {
        let p = self.staging.join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).map_err(|e| Error::output(parent, e))?;
        }
        if !self.files.iter().any(|f| f == name) {
            self.files.push(name.to_string());
        }
        Ok(p)
    }

    /// The staging folder: files written below it and [`OutDir::adopt`]ed are moved into place
    /// by [`OutDir::commit`] (for writers that run on other threads, e.g. per-speed results).
    pub fn staging_dir(&self) -> &Path {
        &self.staging
    }

    /// Registers `name` (relative), already written below [`OutDir::staging_dir`], for commit.
    pub fn adopt(&mut self, name: &str) -> Result<()> {
        let p = self.staging.join(name);
        if !p.is_file() {
            return Err(Error::output(
                self.dir.join(name),
                "was not written to the staging folder",
            ));
        }
        if !self.files.iter().any(|f| f == name) {
            self.files.push(name.to_string());
        }
        Ok(())
    }

    /// Writes bytes to `name` in the staging area.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<()> {
        let p = self.stage(name)?;
        std::fs::write(&p, bytes).map_err(|e| Error::output(self.dir.join(name), e))
    }

    /// Moves every staged file into place (`summary.json` files last), removes the files of
    /// the previous run in this directory that this run did not produce (from its manifest),
    /// writes the new manifest and removes the staging folder. Returns the final paths.
    pub fn commit(mut self) -> Result<Vec<PathBuf>> {
        let mut names = self.files.clone();
        names.sort_by_key(|n| n.ends_with("summary.json"));
        let manifest = self.dir.join(MANIFEST);
        if let Ok(old) = std::fs::read_to_string(&manifest) {
            for f in old.lines().filter(|l| !l.is_empty() && !l.contains("..")) {
                if !names.iter().any(|n| n == f) {
                    let _ = std::fs::remove_file(self.dir.join(f));
                }
            }
        }
        let mut out = Vec::new();
        for n in &names {
            let from = self.staging.join(n);
            let to = self.dir.join(n);
            if let Some(parent) = to.parent() {
                std::fs::create_dir_all(parent).map_err(|e| Error::output(parent, e))?;
            }
            std::fs::rename(&from, &to).map_err(|e| Error::output(&to, e))?;
            out.push(to);
        }
        std::fs::write(&manifest, names.join("\n") + "\n")
            .map_err(|e| Error::output(&manifest, e))?;
        let _ = std::fs::remove_dir_all(&self.staging);
        self.committed = true;
        Ok(out)
    }
}

impl Drop for OutDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
            if self.created {
                // Only removes the directory when it is still empty.
                let _ = std::fs::remove_dir(&self.dir);
            }
        }
    }
}

/// Stator boundary drawn in orbit plots, in units of |Z0|.
pub fn boundary(case: &Case) -> Boundary {
    let z0 = if case.z0 > 0.0 { case.z0 } else { 1.0 };
    // The boundary is the first stator's, seen from its station: drawn only when the analysed
    // node is that station's node.
    let station_node = case
        .stators
        .first()
        .filter(|s| !s.targets.is_empty())
        .and_then(|s| case.stations.get(s.target_station(0)))
        .map(|st| st.node);
    if station_node.is_some_and(|n| n != case.observed_node) {
        return Boundary::None;
    }
    match case.stators.first() {
        Some(s) if s.is_ring => Boundary::Circle {
            radius: s.clearance / z0,
        },
        Some(s) => match s.angle_deg {
            Some(a) => Boundary::Line {
                angle_deg: a,
                distance: s.clearance / z0,
            },
            None => Boundary::None,
        },
        None => Boundary::None,
    }
}

/// The `sweep.csv` header.
pub const SWEEP_HEADER: &str = "speed_ratio,period,x_min_nd,x_max_nd,y_min_nd,y_max_nd,amp_1x_nd,amp_half_nd,amp_third_nd,contact_force_max_nd,steps,wall_s,dt_s,steps_per_rev,z0_m,clearance_m,contact_fraction,min_gap_m,err_extents_rel";

/// One `sweep.csv` row.
pub fn sweep_row(r: &SpeedResults) -> String {
    format!(
        "{:.4},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{},{:.6},{:.6e},{},{:.6e},{:.6e},{:.4},{:.3e},{}",
        r.speed_ratio,
        r.period,
        r.extents_nd[0],
        r.extents_nd[1],
        r.extents_nd[2],
        r.extents_nd[3],
        r.amp_1x_nd,
        r.amp_half_nd,
        r.amp_third_nd,
        r.contact_force_max_nd,
        r.stats.steps,
        r.stats.wall_s,
        r.plan.dt,
        r.plan.steps_per_rev,
        r.z0,
        r.clearances.first().copied().unwrap_or(f64::NAN),
        r.contact_fraction,
        r.stats.min_gap,
        r.error
            .map(|e| format!("{:.3e}", e.extents_rel))
            .unwrap_or_default()
    )
}

/// What a sweep draws.
#[derive(Debug, Clone)]
pub struct SweepFigures<'a> {
    /// Title on every picture.
    pub title: &'a str,
    /// Stator boundary per speed (orbit panels).
    pub bounds: &'a [Boundary],
    /// Orbit grids (lists of ω/ω_n).
    pub orbit_grids: &'a [Vec<f64>],
    /// Speeds whose contact-force histories are drawn.
    pub force_histories: &'a [f64],
    /// Upper frequency of the cascade (f/ω_n).
    pub cascade_max: f64,
    /// Write PNGs at all.
    pub png: bool,
    /// Analysed component, `"x"` or `"y"`.
    pub component: &'a str,
}

/// Writes the sweep's table and pictures into `out` under `prefix` (e.g. `""` or `"eps_5/"`).
pub fn write_sweep(
    out: &mut OutDir,
    prefix: &str,
    res: &SweepResults,
    fig: &SweepFigures<'_>,
) -> Result<()> {
    let SweepFigures {
        title,
        bounds,
        orbit_grids,
        force_histories,
        cascade_max,
        png,
        component,
    } = fig.clone();
    let mut csv = String::from(SWEEP_HEADER);
    csv.push('\n');
    for r in &res.speeds {
        csv.push_str(&sweep_row(r));
        csv.push('\n');
    }
    out.write(&format!("{prefix}sweep.csv"), csv.as_bytes())?;
    if !png {
        return Ok(());
    }
    let find = |v: f64| {
        res.speeds
            .iter()
            .enumerate()
            .min_by(|a, b| {
                (a.1.speed_ratio - v)
                    .abs()
                    .total_cmp(&(b.1.speed_ratio - v).abs())
            })
            .map(|(i, _)| i)
    };
    let lines: Vec<CascadeLine> = res
        .speeds
        .iter()
        .map(|r| CascadeLine {
            speed: r.speed_ratio,
            freq: r.spectrum.iter().map(|p| p.0).collect(),
            amp: r.spectrum.iter().map(|p| p.1).collect(),
        })
        .collect();
    let p = out.stage(&format!("{prefix}cascade.png"))?;
    plot::cascade(
        &p,
        &format!("{title} — spectrum cascade of {component}/|Z0|"),
        &lines,
        cascade_max,
        0.8 * res.speeds.first().map_or(0.1, |_| step_of(&res.speeds)) * 10.0,
    )?;
    let pts: Vec<(f64, f64)> = res
        .speeds
        .iter()
        .flat_map(|r| {
            let c = if component == "x" { 0 } else { 1 };
            r.poincare_nd.iter().map(move |p| (r.speed_ratio, p[c]))
        })
        .collect();
    let p = out.stage(&format!("{prefix}bifurcation.png"))?;
    plot::bifurcation(
        &p,
        &format!("{title} — Poincaré section once per revolution"),
        &pts,
        &format!("{component}/|Z0| at ωt = 2πk"),
    )?;
    for (g, speeds) in orbit_grids.iter().enumerate() {
        let panels: Vec<OrbitPanel> = speeds
            .iter()
            .filter_map(|v| find(*v))
            .map(|i| {
                let r = &res.speeds[i];
                OrbitPanel {
                    title: format!("ω/ωn = {:.1}  ({})", r.speed_ratio, regime_name(r.period)),
                    x: r.orbit_nd.iter().map(|p| p[0]).collect(),
                    y: r.orbit_nd.iter().map(|p| p[1]).collect(),
                    boundary: bounds.get(i).cloned().unwrap_or(Boundary::None),
                    poincare: r.poincare_nd.iter().map(|p| (p[0], p[1])).collect(),
                }
            })
            .collect();
        let p = out.stage(&format!("{prefix}orbits_{}.png", g + 1))?;
        plot::orbit_grid(
            &p,
            &format!("{title} — orbits of the rotor centre"),
            &panels,
            3,
        )?;
    }
    if !force_histories.is_empty() {
        let series: Vec<Series> = force_histories
            .iter()
            .filter_map(|v| find(*v))
            .map(|i| {
                let r = &res.speeds[i];
                Series {
                    label: format!("ω/ωn = {:.1}", r.speed_ratio),
                    t: r.force_history.iter().map(|p| p.0).collect(),
                    y: r.force_history.iter().map(|p| p.1).collect(),
                }
            })
            .collect();
        let p = out.stage(&format!("{prefix}contact_force.png"))?;
        plot::stacked_series(
            &p,
            &format!("{title} — vertical contact force on the stator"),
            &series,
            "revolutions",
            "F_y / (m_u e ω²)",
        )?;
    }
    let size: Vec<(f64, f64)> = res
        .speeds
        .iter()
        .map(|r| (r.speed_ratio, r.extents_nd[3] - r.extents_nd[2]))
        .collect();
    let per: Vec<(f64, f64)> = res
        .speeds
        .iter()
        .map(|r| (r.speed_ratio, r.period as f64))
        .collect();
    let p = out.stage(&format!("{prefix}regime_map.png"))?;
    plot::lines(
        &p,
        &format!("{title} — regime map"),
        &[
            Curve {
                label: "vertical orbit size / |Z0|".into(),
                points: size,
            },
            Curve {
                label: "Poincaré period (0 = not periodic)".into(),
                points: per,
            },
        ],
        "ω/ωn",
        "",
    )?;
    Ok(())
}

fn step_of(s: &[SpeedResults]) -> f64 {
    if s.len() > 1 {
        (s[s.len() - 1].speed_ratio - s[0].speed_ratio) / (s.len() - 1) as f64
    } else {
        0.1
    }
}

/// Writes the pictures of a single run.
pub fn write_run_pngs(
    out: &mut OutDir,
    title: &str,
    r: &SpeedResults,
    bound: Boundary,
    component: &str,
) -> Result<()> {
    let p = out.stage("orbit.png")?;
    plot::orbit_grid(
        &p,
        title,
        &[OrbitPanel {
            title: format!("ω/ωn = {:.3}  ({})", r.speed_ratio, regime_name(r.period)),
            x: r.orbit_nd.iter().map(|p| p[0]).collect(),
            y: r.orbit_nd.iter().map(|p| p[1]).collect(),
            boundary: bound,
            poincare: r.poincare_nd.iter().map(|p| (p[0], p[1])).collect(),
        }],
        1,
    )?;
    let p = out.stage("spectrum.png")?;
    plot::lines(
        &p,
        &format!("{title} — Hann-windowed spectrum of {component}/|Z0|"),
        &[Curve {
            label: format!("{component}/|Z0|"),
            points: r.spectrum.clone(),
        }],
        "f / ωn",
        "amplitude / |Z0|",
    )?;
    let p = out.stage("contact_force.png")?;
    plot::stacked_series(
        &p,
        &format!("{title} — vertical contact force on the stator"),
        &[Series {
            label: format!("ω/ωn = {:.3}", r.speed_ratio),
            t: r.force_history.iter().map(|p| p.0).collect(),
            y: r.force_history.iter().map(|p| p.1).collect(),
        }],
        "revolutions",
        "F_y / (m_u e ω²)",
    )?;
    Ok(())
}

/// Writes a convergence study: `convergence.csv` and the work-precision / error-vs-Δt plots.
pub fn write_convergence(
    out: &mut OutDir,
    prefix: &str,
    title: &str,
    c: &ConvergenceResults,
    png: bool,
) -> Result<()> {
    let mut csv = String::from(
        "speed_ratio,integrator,dt_s,dt_wn,steps_per_rev,orbit_err,extents_err,err_1x,err_half,err_third,period,wall_s,steps\n",
    );
    for p in &c.points {
        csv.push_str(&format!(
            "{},{},{:.6e},{:.6e},{},{:.4e},{:.4e},{:.4e},{:.4e},{:.4e},{},{:.6},{}\n",
            c.speed_ratio,
            p.integrator,
            p.dt,
            p.dt_wn,
            p.steps_per_rev,
            p.orbit_err,
            p.extents_err,
            p.lines_err[0],
            p.lines_err[1],
            p.lines_err[2],
            p.period,
            p.wall_s,
            p.steps
        ));
    }
    out.write(&format!("{prefix}convergence.csv"), csv.as_bytes())?;
    if !png {
        return Ok(());
    }
    let curves = |f: &dyn Fn(&crate::analysis::ConvergencePoint) -> (f64, f64)| -> Vec<Curve> {
        c.orders
            .iter()
            .map(|(name, order)| Curve {
                label: format!("{name} (observed order {order:.2})"),
                points: c
                    .points
                    .iter()
                    .filter(|p| p.integrator == *name)
                    .map(f)
                    .collect(),
            })
            .collect()
    };
    let p = out.stage(&format!("{prefix}work_precision.png"))?;
    plot::loglog(
        &p,
        &format!("{title} — work-precision at ω/ωn = {}", c.speed_ratio),
        &curves(&|p| (p.wall_s, p.orbit_err)),
        "wall time of the run (s)",
        "relative orbit error",
    )?;
    let p = out.stage(&format!("{prefix}error_vs_dt.png"))?;
    plot::loglog(
        &p,
        &format!(
            "{title} — orbit error against time step at ω/ωn = {}",
            c.speed_ratio
        ),
        &curves(&|p| (p.dt_wn, p.orbit_err)),
        "Δt·ωn",
        "relative orbit error",
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rerun_replaces_results_and_failed_run_leaves_nothing() {
        let tmp = std::env::temp_dir().join(format!("rubsim-outdir-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&tmp);
        let mut o = OutDir::prepare(&tmp).unwrap();
        o.write("a.csv", b"1").unwrap();
        o.write("b.png", b"2").unwrap();
        o.write("summary.json", b"{}").unwrap();
        o.commit().unwrap();
        assert!(tmp.join("b.png").exists());
        // A rerun that produces fewer files removes the stale one.
        let mut o = OutDir::prepare(&tmp).unwrap();
        o.write("a.csv", b"3").unwrap();
        o.write("summary.json", b"{}").unwrap();
        o.commit().unwrap();
        assert!(!tmp.join("b.png").exists());
        assert_eq!(std::fs::read(tmp.join("a.csv")).unwrap(), b"3");
        // A run that fails (dropped without commit) changes nothing and leaves no staging.
        {
            let mut o = OutDir::prepare(&tmp).unwrap();
            o.write("a.csv", b"half").unwrap();
        }
        assert_eq!(std::fs::read(tmp.join("a.csv")).unwrap(), b"3");
        // A staging folder of a dead process is cleaned up by the next prepare.
        let dead = tmp.join(format!("{STAGING_PREFIX}{}", u32::MAX - 7));
        std::fs::create_dir_all(&dead).unwrap();
        let o = OutDir::prepare(&tmp).unwrap();
        assert!(!dead.exists());
        drop(o);
        let left: Vec<_> = std::fs::read_dir(&tmp)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().to_string())
            .filter(|n| n.starts_with(STAGING_PREFIX))
            .collect();
        assert!(left.is_empty(), "{left:?}");
        std::fs::remove_dir_all(&tmp).unwrap();
    }
}
