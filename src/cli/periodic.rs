//! `rubsim periodic`: the periodic response at one speed by shooting, its Floquet multipliers
//! and stability (`analysis::periodic`).

use super::{default_out, load, shooting_settings, Common, UnitArg};
use anyhow::{Context, Result};
use rubsim::analysis::{
    self, autonomous::AutonomousOrbit, floquet::StepRefinement, periodic::PeriodicOrbit,
};
use rubsim::output::summary::{finish, Base, Summary};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::PathBuf;

/// The body of `summary.json` of `rubsim periodic`.
#[derive(Debug, Serialize)]
struct PeriodicBody<'a> {
    /// The orbit, its multipliers and stability.
    periodic: &'a PeriodicOrbit,
    /// With `--refine`: the multipliers at half the step, their differences, error estimates
    /// and (an orbit without contact) their extrapolation to Δt → 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    refined: Option<&'a StepRefinement>,
    /// The orbit's VTK/HDF5 time series (`orbit/`), when the scene asks for one.
    #[serde(skip_serializing_if = "Option::is_none")]
    orbit_series: Option<OrbitSeries>,
    /// Wall time of the command (s).
    wall_s: f64,
}

/// Options of `rubsim periodic`.
#[derive(clap::Args, Clone)]
pub struct PeriodicArgs {
    #[command(flatten)]
    pub c: Common,
    /// Speed, in `--unit` (default: the scene's single speed).
    #[arg(long)]
    pub speed: Option<f64>,
    /// Unit of `--speed`: ratio (ω/ω_n), rad/s or rpm.
    #[arg(long, value_enum, default_value_t = UnitArg::Ratio)]
    pub unit: UnitArg,
    /// Period of the orbit in revolutions (default: the period the settled run repeats
    /// with, 1 when it does not repeat).
    #[arg(long)]
    pub period: Option<usize>,
    /// The multipliers' own step error: the orbit shot again at half the step, each
    /// multiplier beside its twin, and — an orbit without contact — extrapolated to Δt → 0
    /// (the continuous flow's exp(λT)); multipliers_refined.csv.
    #[arg(long)]
    pub refine: bool,
    /// The orbit of an autonomous system — no unbalance, no load fixed in the rotor: a whirl
    /// at its own frequency (dry whip) — with its period unknown and a phase condition,
    /// started from the settled run's whirl line (`analysis::autonomous`).
    #[arg(long, conflicts_with_all = ["period", "refine"])]
    pub autonomous: bool,
    /// Output directory (default: out/<scene name>/periodic).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Shoots the periodic response at `speed` (default: the scene's single speed) of `period`
/// revolutions (default: the settled run's), and writes `summary.json` and `multipliers.csv`.
pub fn periodic(a: &PeriodicArgs) -> Result<()> {
    let PeriodicArgs {
        c,
        speed,
        unit,
        period,
        refine,
        autonomous,
        out,
    } = a.clone();
    let (ls, model) = load(&c)?;
    if let Some(v) = speed {
        if !(v.is_finite() && v > 0.0) {
            anyhow::bail!("--speed must be a positive speed, got {v}");
        }
    }
    check_period(period)?;
    let v = speed
        .map(|v| unit.ratio(v, model.rotor.natural_frequency()))
        .or_else(|| analysis::single_speed(&ls.scene.run, &model))
        .with_context(|| {
            format!(
                "{}: `rubsim periodic` needs run.speed_ratio or run.speed, or --speed",
                c.scene.display()
            )
        })?;
    let mut outd = super::open_out(&out.unwrap_or_else(|| default_out(&c.scene).join("periodic")))?;
    let t0 = std::time::Instant::now();
    let s = shooting_settings(&ls, &model, &[v])?;
    let prep = analysis::prepare(&model, &analysis::periodic::request_at(&s, v))?;
    if autonomous {
        return write_autonomous(outd, (&ls, &model), &prep, t0);
    }
    let orbit = analysis::periodic::shoot(&prep, period)?;
    let refined = if refine {
        Some(analysis::floquet::refine(&prep, &orbit)?)
    } else {
        None
    };
    report(&orbit);
    let orbit_series = write_series(&mut outd, (&ls, &model), &prep, &orbit, ORBIT_FOLDER)?;
    outd.write("multipliers.csv", multipliers_csv(&orbit).as_bytes())?;
    if let Some(r) = &refined {
        report_refined(r);
        outd.write("multipliers_refined.csv", refined_csv(&orbit, r).as_bytes())?;
    }
    if ls.scene.output.png {
        rubsim::output::branch::write_multipliers(&mut outd, &ls.scene.title, &orbit.multipliers)?;
    }
    let body = PeriodicBody {
        periodic: &orbit,
        refined: refined.as_ref(),
        orbit_series,
        wall_s: t0.elapsed().as_secs_f64(),
    };
    let base = Base::new(&ls, &model, "periodic");
    finish(outd, &Summary { base, body })?;
    Ok(())
}

/// `rubsim periodic --autonomous`: the orbit shot with its period ([`AutonomousOrbit`]),
/// reported, and written as `summary.json` (`autonomous`), `multipliers.csv` and — where the
/// scene asks for VTK/HDF5 — its period as a time series (`orbit/`).
fn write_autonomous(
    mut outd: rubsim::output::OutDir,
    (ls, model): (&rubsim::scene::LoadedScene, &rubsim::model::Model),
    prep: &analysis::Prepared,
    t0: std::time::Instant,
) -> Result<()> {
    let o = analysis::autonomous::shoot_autonomous(prep)?;
    report_autonomous(&o);
    let orbit_series = write_autonomous_series(&mut outd, (ls, model), prep, &o, ORBIT_FOLDER)?;
    outd.write("multipliers.csv", rows_csv(&o.multipliers).as_bytes())?;
    if ls.scene.output.png {
        rubsim::output::branch::write_multipliers(&mut outd, &ls.scene.title, &o.multipliers)?;
    }
    let body = AutonomousBody {
        autonomous: &o,
        orbit_series,
        wall_s: t0.elapsed().as_secs_f64(),
    };
    let base = Base::new(ls, model, "periodic");
    finish(outd, &Summary { base, body })?;
    Ok(())
}

/// The body of `summary.json` of `rubsim periodic --autonomous`.
#[derive(Debug, Serialize)]
struct AutonomousBody<'a> {
    /// The orbit, its period, multipliers and stability.
    autonomous: &'a AutonomousOrbit,
    /// The orbit's time series, when the scene asks for one and the orbit converged.
    #[serde(skip_serializing_if = "Option::is_none")]
    orbit_series: Option<OrbitSeries>,
    /// Wall time of the command (s).
    wall_s: f64,
}

/// Writes the converged autonomous orbit `o` of `prep` as the time series the scene asks for
/// below `folder` (`orbit/`, `orbits/branch0_<ν>/`; `rubsim::results::Series::autonomous_orbit`:
/// one whirl period `T` after a lead-in of one) and adopts the files; `None` when the scene
/// asks for none or the orbit did not converge (a warning says so).
pub fn write_autonomous_series(
    outd: &mut rubsim::output::OutDir,
    (ls, model): (&rubsim::scene::LoadedScene, &rubsim::model::Model),
    prep: &analysis::Prepared,
    o: &AutonomousOrbit,
    folder: &str,
) -> Result<Option<OrbitSeries>> {
    let not_converged = (!o.converged).then(|| {
        format!(
            "ω/ωn = {:.4}: no autonomous orbit converged; its time series ({folder}) is not written",
            o.speed_ratio
        )
    });
    let Some(files) = adopt_series(outd, ls, not_converged, |series| {
        series.autonomous_orbit(model, prep, o, folder)
    })?
    else {
        return Ok(None);
    };
    println!(
        "  orbit series: {folder} ({} file(s), one whirl period of {:.6e} s)",
        files.len(),
        o.period_s
    );
    Ok(Some(OrbitSeries {
        folder: folder.to_string(),
        period_steps: o.steps_per_period,
        dt: o.period_s / o.steps_per_period.max(1) as f64,
        files,
    }))
}

/// The files `write` puts into `outd`'s staging folder through the scene's series writers,
/// adopted; `None` when the scene asks for no series, or — printed as a warning — when the
/// orbit did not converge (`not_converged`: why).
fn adopt_series(
    outd: &mut rubsim::output::OutDir,
    ls: &rubsim::scene::LoadedScene,
    not_converged: Option<String>,
    write: impl FnOnce(&rubsim::results::Series<'_>) -> rubsim::error::Result<Vec<String>>,
) -> Result<Option<Vec<String>>> {
    if !rubsim::results::wanted(&ls.scene.output) {
        return Ok(None);
    }
    if let Some(why) = not_converged {
        eprintln!("warning: {why}");
        return Ok(None);
    }
    let scene_json = serde_json::to_string(&ls.scene)?;
    let series = rubsim::results::Series {
        output: &ls.scene.output,
        scene_json: &scene_json,
        staging: outd.staging_dir(),
    };
    let files = write(&series)?;
    for f in &files {
        outd.adopt(f)?;
    }
    Ok(Some(files))
}

/// Prints an autonomous orbit: its period and whirl, convergence, stability, multipliers.
fn report_autonomous(o: &AutonomousOrbit) {
    println!(
        "ω/ωn = {:.4}: autonomous orbit, period {:.6e} s (started from {:.6e} s), whirl {:+.6} ω_n = {:+.6} Ω ({}), {} steps of Δt = {:.4e} s a period; Newton {} in {} iteration(s), residual {:.2e}; {} steps",
        o.speed_ratio,
        o.period_s,
        o.start_period_s,
        o.whirl_ratio,
        o.order,
        if o.whirl_frequency < 0.0 { "backward" } else { "forward" },
        o.steps_per_period,
        o.dt_s,
        if o.converged { "converged" } else { "did NOT converge" },
        o.iterations,
        o.residual,
        o.steps
    );
    println!(
        "  orbit: radius {:.6e} … {:.6e} m at the first station, contact fraction {:.4}",
        o.radius_m[0], o.radius_m[1], o.contact_fraction
    );
    let t = o.trivial_multiplier;
    let state = match (o.converged, o.stable, o.instability) {
        (false, ..) => "unknown (no periodic orbit found near the settled whirl)".to_string(),
        (true, true, _) => "stable".to_string(),
        (true, false, Some(how)) => format!("unstable ({how})"),
        (true, false, None) => "unstable".to_string(),
    };
    println!(
        "  the shift along the orbit: ρ = {:+.8} {:+.8}i (|ρ − 1| = {:.1e}); largest other |ρ| = {:.6}: {state}",
        t[0],
        t[1],
        (t[0] - 1.0).hypot(t[1]),
        o.largest_modulus
    );
    if !o.converged {
        eprintln!(
            "warning: ω/ωn = {:.4}: shooting did not find an autonomous periodic orbit (residual {:.2e} after {} Newton iterations): the whirl may be quasi-periodic or chaotic",
            o.speed_ratio, o.residual, o.iterations
        );
    }
}

/// How the orbit's monodromy was taken, for the console: the variational one with its
/// linearisation's counters (and a note where a column was one-sided: the orbit on a contact
/// event, its multipliers those of one side), or the differences of whole maps.
fn monodromy_line(o: &PeriodicOrbit) -> String {
    match o.linearisation {
        Some(l) => format!(
            "variational ({} steps in contact linearised{})",
            l.contact_steps,
            if l.one_sided + l.straddled > 0 {
                format!(
                    "; {} contact column(s) one-sided, {} across: the orbit sits on a contact event, a kink of the map, and its multipliers are those of one side",
                    l.one_sided, l.straddled
                )
            } else if l.shrunk > 0 {
                format!(
                    "; {} column(s) near a contact event, their perturbation shrunk: the multipliers may jump with a small change of the scene",
                    l.shrunk
                )
            } else {
                String::new()
            }
        ),
        None => {
            "central differences of whole maps (this scene's step has no linearisation)".to_string()
        }
    }
}

/// The folder of `rubsim periodic`'s orbit series in its output directory.
pub const ORBIT_FOLDER: &str = "orbit/";

/// An orbit's VTK/HDF5 time series as summary.json lists it.
#[derive(Debug, Serialize)]
pub struct OrbitSeries {
    /// Its folder in the output directory (`orbit/`, `orbits/<branch>_<value>/`).
    pub folder: String,
    /// Steps of the written period (`k N`) and Δt (s): the frames lie at steps `k N … 2 k N`
    /// of the integration from the fixed point (the first period a lead-in), times
    /// `k T … 2 k T`.
    pub period_steps: usize,
    /// Δt (s).
    pub dt: f64,
    /// The files written, relative to the output directory.
    pub files: Vec<String>,
}

/// Writes the converged orbit `o` of `prep` as the time series the scene asks for below
/// `folder` (`rubsim::results::Series::orbit`) and adopts the files; `None` when the scene
/// asks for none. An orbit that did not converge is not written (its series would not close):
/// a warning says so.
pub fn write_series(
    outd: &mut rubsim::output::OutDir,
    (ls, model): (&rubsim::scene::LoadedScene, &rubsim::model::Model),
    prep: &analysis::Prepared,
    o: &PeriodicOrbit,
    folder: &str,
) -> Result<Option<OrbitSeries>> {
    let not_converged = (!o.converged).then(|| {
        format!(
            "ω/ωn = {:.4}: no periodic orbit of {} revolution(s) converged; its time series ({folder}) is not written",
            o.speed_ratio, o.period
        )
    });
    let Some(files) = adopt_series(outd, ls, not_converged, |series| {
        series.orbit(model, prep, o, folder)
    })?
    else {
        return Ok(None);
    };
    println!(
        "  orbit series: {folder} ({} file(s), one period of {} revolution(s))",
        files.len(),
        o.period
    );
    Ok(Some(OrbitSeries {
        folder: folder.to_string(),
        period_steps: o.period * prep.plan.steps_per_rev,
        dt: prep.plan.dt,
        files,
    }))
}

/// Refuses `--period 0` (an orbit repeats after a whole number ≥ 1 of revolutions); also
/// `rubsim continue`'s check.
pub fn check_period(period: Option<usize>) -> Result<()> {
    if period == Some(0) {
        anyhow::bail!("--period must be a whole number of revolutions ≥ 1, got 0");
    }
    Ok(())
}

/// Prints the orbit's period, convergence, stability and largest multipliers.
fn report(o: &PeriodicOrbit) {
    println!(
        "ω/ωn = {:.4}: period {} revolution(s), state of {} components; Newton {} in {} iteration(s), residual {:.2e}; {} steps",
        o.speed_ratio,
        o.period,
        o.state_size,
        if o.converged { "converged" } else { "did NOT converge" },
        o.iterations,
        o.residual,
        o.steps
    );
    let r = &o.orbit;
    println!(
        "  orbit: x/|Z0| ∈ [{:.4}, {:.4}], y/|Z0| ∈ [{:.4}, {:.4}], contact fraction {:.4}, 1× {:.4}",
        r.extents_nd[0], r.extents_nd[1], r.extents_nd[2], r.extents_nd[3], r.contact_fraction, r.amp_1x_nd
    );
    let state = match (o.converged, o.stable, o.instability) {
        (false, ..) => {
            "unknown (no periodic orbit of this period found near the settled state)".to_string()
        }
        (true, true, _) => "stable".to_string(),
        (true, false, Some(how)) => format!("unstable ({how})"),
        (true, false, None) => "unstable".to_string(),
    };
    println!("  largest |ρ| = {:.6}: {state}", o.largest_modulus);
    println!("  monodromy: {}", monodromy_line(o));
    for (i, m) in o.multipliers.iter().take(6).enumerate() {
        println!(
            "  ρ{} = {:+.6} {:+.6}i (|ρ| = {:.6})",
            i + 1,
            m[0],
            m[1],
            m[0].hypot(m[1])
        );
    }
    if !o.converged {
        eprintln!(
            "warning: ω/ωn = {:.4}: shooting did not find a periodic orbit of {} revolution(s) (residual {:.2e} after {} Newton iterations): the response there may be of another period (`--period`), quasi-periodic or chaotic; the multipliers are those of the last iterate",
            o.speed_ratio, o.period, o.residual, o.iterations
        );
    }
}

/// `multipliers.csv`: index, real and imaginary parts, modulus and angle (degrees) of each
/// Floquet multiplier, largest modulus first.
fn multipliers_csv(o: &PeriodicOrbit) -> String {
    rows_csv(&o.multipliers)
}

/// [`multipliers_csv`] of the multipliers `rho`.
fn rows_csv(rho: &[[f64; 2]]) -> String {
    let mut s = String::from("index,re,im,modulus,angle_deg\n");
    for (i, m) in rho.iter().enumerate() {
        let _ = writeln!(
            s,
            "{},{:e},{:e},{:e},{:e}",
            i + 1,
            m[0],
            m[1],
            m[0].hypot(m[1]),
            m[1].atan2(m[0]).to_degrees()
        );
    }
    s
}

/// Prints the refinement: the verdict at Δt/2, the largest multipliers' error estimates and
/// (without contact) their extrapolation.
fn report_refined(r: &StepRefinement) {
    println!(
        "  at Δt/2 = {:.4e} s: Newton {} (residual {:.2e}), largest |ρ| = {:.6}: {}{}; {} steps",
        r.dt[1],
        if r.converged {
            "converged"
        } else {
            "did NOT converge"
        },
        r.residual,
        r.largest_modulus,
        if r.stable { "stable" } else { "unstable" },
        if r.verdict_changes {
            " — the step decides the verdict"
        } else {
            ""
        },
        r.steps
    );
    let what = if r.order == 2 {
        "no contact: order 2, extrapolated to Δt → 0"
    } else {
        "contact: order unknown, error bounded by the whole difference"
    };
    println!("  multipliers' step error ({what}):");
    for (i, (h, e)) in r
        .half_step
        .iter()
        .zip(&r.error_estimate)
        .enumerate()
        .take(6)
    {
        let ext = r.extrapolated.as_ref().map_or(String::new(), |x| {
            format!(", extrapolated {:+.10} {:+.10}i", x[i][0], x[i][1])
        });
        println!(
            "  ρ{}(Δt/2) = {:+.6} {:+.6}i ± {:.1e}{ext}",
            i + 1,
            h[0],
            h[1],
            e
        );
    }
}

/// `multipliers_refined.csv`: per multiplier (in multipliers.csv's order) its value at Δt and
/// at Δt/2, their difference, the error estimate of the Δt/2 value, and the extrapolation to
/// Δt → 0 (empty with contact).
fn refined_csv(o: &PeriodicOrbit, r: &StepRefinement) -> String {
    let mut s = String::from(
        "index,re,im,re_half,im_half,difference,error_estimate,re_extrapolated,im_extrapolated\n",
    );
    for (i, (m, h)) in o.multipliers.iter().zip(&r.half_step).enumerate() {
        let ext = r
            .extrapolated
            .as_ref()
            .map_or(",".to_string(), |x| format!("{:e},{:e}", x[i][0], x[i][1]));
        let _ = writeln!(
            s,
            "{},{:e},{:e},{:e},{:e},{:e},{:e},{ext}",
            i + 1,
            m[0],
            m[1],
            h[0],
            h[1],
            r.difference[i],
            r.error_estimate[i]
        );
    }
    s
}
