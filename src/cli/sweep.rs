//! `rubsim sweep`: the speed sweep of `[run.sweep]`, once or per value of `[run.sweep.vary]`.

use super::{default_out, finish, load, progress_bar, settings, Common, Series};
use anyhow::{Context, Result};
use rubsim::analysis::sweep::{self as sw, SweepKeep, Variant};
use rubsim::analysis::{self, SweepResults};
use rubsim::model::Model;
use rubsim::output::{csv, figures, summary, OutDir};
use rubsim::results::{per_speed_selection, speed_folder};
use rubsim::scene::LoadedScene;
use std::path::PathBuf;
use std::sync::Mutex;

/// Runs the sweep in parallel and writes `sweep.csv`, `summary.json`, the pictures and the
/// per-speed time series (`output.per_speed`), one sub-folder per variant of a parameter study.
pub fn sweep(c: &Common, out: Option<PathBuf>) -> Result<()> {
    let (ls, model) = load(c)?;
    let spec = ls.scene.run.sweep.clone().with_context(|| {
        format!(
            "{}: `rubsim sweep` needs a [run.sweep] table",
            c.scene.display()
        )
    })?;
    let mut outd = super::open_out(&out.unwrap_or_else(|| default_out(&c.scene)))?;
    let speeds = analysis::sweep_speeds(spec.from, spec.to, spec.step);
    let runs = speeds.len() * spec.vary.as_ref().map_or(1, |v| v.values.len());
    super::announce_sweep(&model, &settings(&ls), &speeds, runs);
    let t0 = std::time::Instant::now();
    let mut records = Vec::new();
    for variant in sw::variants(spec.vary.as_ref()) {
        let record = if variant.is_base() {
            run_variant(&mut outd, &variant, &ls, &model, &speeds)?
        } else {
            let mut set = c.set.clone();
            set.extend(variant.overrides.iter().cloned());
            let (ls_v, model_v) = load(&Common {
                scene: c.scene.clone(),
                set,
                tol: c.tol,
            })?;
            run_variant(&mut outd, &variant, &ls_v, &model_v, &speeds)?
        };
        records.push(record);
    }
    let mut sum = summary::base(&ls, &model, "sweep");
    sum["sweeps"] = serde_json::Value::Array(records);
    sum["wall_s"] = t0.elapsed().as_secs_f64().into();
    finish(outd, &sum)
}

/// One sweep of the study: runs every speed, writes its table, pictures and time series below
/// the variant's prefix, prints its regimes; returns its summary record.
fn run_variant(
    outd: &mut OutDir,
    variant: &Variant,
    ls: &LoadedScene,
    model: &Model,
    speeds: &[f64],
) -> Result<serde_json::Value> {
    let prefix = variant.prefix.as_str();
    let s = settings(ls);
    let o = &ls.scene.output;
    let fmax = sw::cascade_max(o, speeds);
    let keep = SweepKeep::new(o, fmax);
    let pb = progress_bar(speeds.len());
    if !prefix.is_empty() {
        pb.set_message(prefix.trim_end_matches('/').to_string());
    }
    // Per-speed VTK/HDF5 time series (output.per_speed) into `speed_<ν>/` sub-folders.
    let selected = per_speed_selection(o, speeds).map_err(|m| ls.invalid("output.per_speed", m))?;
    let scene_json = serde_json::to_string(&ls.scene)?;
    let series = Series {
        output: o,
        scene_json: &scene_json,
        staging: outd.staging_dir(),
    };
    let written = Mutex::new(Vec::new());
    let run = |v: f64| {
        let prep = analysis::prepare(model, &s, v)?;
        let i = speeds.iter().position(|x| *x == v);
        let (r, names) = if i.is_some_and(|i| selected.get(i).copied().unwrap_or(false)) {
            series.run(
                model,
                &prep,
                keep.at(v),
                &format!("{prefix}{}", speed_folder(v)),
            )?
        } else {
            (prep.run(keep.at(v), &mut [])?, Vec::new())
        };
        written.lock().expect("no writer panicked").extend(names);
        Ok((r, figures::boundary(&prep.case)))
    };
    let (res, bounds) = analysis::sweep(speeds, &run, &|| pb.inc(1))?.unzip();
    let mut names = written.into_inner().expect("no writer panicked");
    names.sort();
    for name in &names {
        outd.adopt(name)?;
    }
    pb.finish_and_clear();
    csv::write_sweep(outd, prefix, &res)?;
    figures::write_sweep(
        outd,
        prefix,
        &res,
        &figures::SweepFigures {
            title: &variant.title(&ls.scene.title),
            bounds: &bounds,
            orbit_grids: &sw::orbit_grids(o, speeds),
            force_histories: &o.force_histories,
            cascade_max: fmax,
            png: o.png,
            component: &o.component,
        },
    )?;
    let regimes = analysis::regime_ranges(&res.speeds);
    let peaks = analysis::quasi_resonances(&res.speeds);
    report(variant, &res, &regimes, &peaks);
    Ok(summary::sweep_variant(variant, &res, &regimes, &peaks))
}

/// Prints a sweep's speeds, time, steps, largest estimated error, regimes and peaks.
fn report(
    variant: &Variant,
    res: &SweepResults,
    regimes: &[analysis::RegimeRange],
    peaks: &[(usize, f64)],
) {
    let max_err = res.max_estimated_error();
    println!(
        "{}{} speeds in {:.3} s ({} steps){}",
        if variant.prefix.is_empty() {
            String::new()
        } else {
            format!("{}: ", variant.label())
        },
        res.speeds.len(),
        res.wall_s,
        res.total_steps(),
        if max_err > 0.0 {
            format!(", largest estimated extents error {max_err:.1e}")
        } else {
            String::new()
        }
    );
    let unsteady: Vec<String> = res
        .speeds
        .iter()
        .filter(|r| !r.steady)
        .map(|r| format!("{:.2}", r.speed_ratio))
        .collect();
    if !unsteady.is_empty() {
        eprintln!(
            "warning: {}the steady state was not proven at {} of {} speeds (ω/ωn {}): their analysed window still changes by more than `run.tolerance` of the orbit's size after `run.max_transient_revolutions`; their results carry that error (`steady = false`, `transient_residual` in sweep.csv)",
            if variant.prefix.is_empty() {
                String::new()
            } else {
                format!("{}: ", variant.label())
            },
            unsteady.len(),
            res.speeds.len(),
            unsteady.join(", ")
        );
    }
    for r in regimes {
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
}
