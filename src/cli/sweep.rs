//! `rubsim sweep`: the speed sweep of `[run.sweep]`, once or per value of `[run.sweep.vary]`,
//! run as cases ([`rubsim::study`]); here, its tables and pictures assembled from the cases.

use anyhow::Result;
use rubsim::analysis::sweep as sw;
use rubsim::analysis::{self, RegimeRange, SpeedResults, SweepResults};
use rubsim::output::whirl::{self as whirl_out, CascadeCase};
use rubsim::output::{csv, figures, OutDir};
use rubsim::plot::Boundary;
use rubsim::scene::LoadedScene;
use rubsim::study::summary::SweepRecord;
use rubsim::study::{Study, Variant};

/// One sweep of the study as assembled: its results, regimes and quasi-resonance peaks.
pub struct Assembled<'a> {
    /// The variant.
    pub variant: &'a Variant,
    /// Its results, in speed order.
    pub res: SweepResults,
    /// Its regimes.
    pub regimes: Vec<RegimeRange>,
    /// Its quasi-resonance peaks (period, ω/ωn).
    pub peaks: Vec<(usize, f64)>,
}

impl Assembled<'_> {
    /// Its record in the summary.
    pub fn record(&self) -> SweepRecord<'_> {
        SweepRecord::new(self.variant, &self.res, &self.regimes, &self.peaks)
    }
}

/// Writes `sweep.csv` and the pictures of every variant of the sweep (below its prefix) from
/// the results of its cases (`results`, in case order: variant-major), prints its regimes;
/// returns the variants' sweeps for the summary.
pub fn assemble<'s>(
    outd: &mut OutDir,
    ls: &LoadedScene,
    study: &'s Study,
    results: Vec<(SpeedResults, Boundary)>,
) -> Result<Vec<Assembled<'s>>> {
    let n = study.speeds.len();
    let mut out = Vec::new();
    let mut it = results.into_iter();
    for variant in &study.variants {
        let (speeds, bounds): (Vec<_>, Vec<_>) = it.by_ref().take(n).unzip();
        let res = SweepResults {
            wall_s: speeds.iter().map(|r: &SpeedResults| r.stats.wall_s).sum(),
            speeds,
        };
        write_variant(outd, variant, ls, &study.speeds, &res, &bounds)?;
        let regimes = analysis::regime_ranges(&res.speeds);
        let peaks = analysis::quasi_resonances(&res.speeds);
        report(variant, &res, &regimes, &peaks);
        out.push(Assembled {
            variant,
            res,
            regimes,
            peaks,
        });
    }
    Ok(out)
}

/// One sweep of the study: its table and pictures below the variant's prefix.
fn write_variant(
    outd: &mut OutDir,
    variant: &Variant,
    ls: &LoadedScene,
    speeds: &[f64],
    res: &SweepResults,
    bounds: &[Boundary],
) -> Result<()> {
    let prefix = variant.prefix.as_str();
    let o = &ls.scene.output;
    csv::write_sweep(outd, prefix, res)?;
    // Every picture of the variant drawn together, in parallel.
    let mut draw = rubsim::output::Drawings::new();
    figures::sweep_drawings(
        outd,
        prefix,
        res,
        &figures::SweepFigures {
            title: &variant.title(&ls.scene.title),
            bounds,
            orbit_grids: &sw::orbit_grids(o, speeds),
            force_histories: &o.force_histories,
            cascade_max: sw::cascade_max(o, speeds),
            png: o.png,
            component: &o.component,
        },
        &mut draw,
    )?;
    let cases: Vec<CascadeCase<'_>> = res
        .speeds
        .iter()
        .map(|r| CascadeCase {
            columns: format!("{:.4}", r.speed_ratio),
            y: r.speed_ratio,
            run: r,
        })
        .collect();
    whirl_out::write_cascade_csv(outd, prefix, "speed_ratio", &cases)?;
    if o.png {
        whirl_out::cascade_drawing(
            outd,
            &format!("{prefix}full_cascade.png"),
            &variant.title(&ls.scene.title),
            &cases,
            ("ω/ωn", sw::cascade_max(o, speeds)),
            &mut draw,
        )?;
    }
    Ok(draw.draw()?)
}

/// Prints a sweep's speeds, time, steps, largest estimated error, regimes and peaks.
fn report(
    variant: &Variant,
    res: &SweepResults,
    regimes: &[analysis::RegimeRange],
    peaks: &[(usize, f64)],
) {
    let max_err = res.max_estimated_error();
    // A variant's lines start with its overrides.
    let prefix = if variant.prefix.is_empty() {
        String::new()
    } else {
        format!("{}: ", variant.label())
    };
    // The speeds (ω/ωn, two decimals) where `flag` holds.
    let speeds_where = |flag: &dyn Fn(&analysis::SpeedResults) -> bool| -> Vec<String> {
        res.speeds
            .iter()
            .filter(|r| flag(r))
            .map(|r| format!("{:.2}", r.speed_ratio))
            .collect()
    };
    println!(
        "{}{} speeds in {:.3} s ({} steps){}",
        prefix,
        res.speeds.len(),
        res.wall_s,
        res.total_steps(),
        if max_err > 0.0 {
            format!(", largest estimated extents error {max_err:.1e}")
        } else {
            String::new()
        }
    );
    let away: Vec<String> = res
        .speeds
        .iter()
        .filter_map(|r| {
            Some(format!(
                "{:.2} (t = {:.3e} s)",
                r.speed_ratio, r.dynamics.runaway_at_s?
            ))
        })
        .collect();
    if !away.is_empty() {
        eprintln!(
            "warning: {}the response runs away when continued at ω/ωn {}: lengthened past its window for the 0–1 test (`run.classify_revolutions`), the run left the divergence bounds; their results are those of the window (regime `diverging`, `steady = false`)",
            prefix,
            away.join(", ")
        );
    }
    let unsteady = speeds_where(&|r| !r.steady && r.dynamics.runaway_at_s.is_none());
    if !unsteady.is_empty() {
        eprintln!(
            "warning: {}the steady state was not proven at {} of {} speeds (ω/ωn {}): their analysed window still changes by more than `run.tolerance` of the orbit's size {}; their results carry that error (`steady = false`, `transient_residual` in sweep.csv)",
            prefix,
            unsteady.len(),
            res.speeds.len(),
            unsteady.join(", "),
            // A fixed window (`run.duration`) carries its warning in each case's record.
            if res.speeds.iter().any(|r| !r.warnings.is_empty()) {
                "at the end of the fixed window `run.duration`, not lengthened"
            } else {
                "after `run.max_transient_revolutions`"
            }
        );
    }
    print_refined(
        &prefix,
        res,
        &speeds_where(&|r| r.step_refinement.is_some()),
    );
    warn_starts(&prefix, res, &speeds_where);
    for r in regimes {
        println!("  {:>27}  ω/ωn {:.2} – {:.2}", r.label(), r.from, r.to);
    }
    if !peaks.is_empty() {
        let p: Vec<String> = peaks
            .iter()
            .map(|(per, v)| format!("{v:.2} ({})", analysis::regime_name(*per)))
            .collect();
        println!("  quasi-resonance peaks: {}", p.join(", "));
    }
}

/// The speeds (ω/ωn, two decimals) of a sweep where a flag of a run holds.
type SpeedsWhere<'a> = dyn Fn(&dyn Fn(&analysis::SpeedResults) -> bool) -> Vec<String> + 'a;

/// Warns of the speeds whose response depends on the start and of those whose coexistence
/// check failed (its companion stopped with an error); `speeds_where` lists the speeds (ω/ωn,
/// two decimals) where a flag holds.
fn warn_starts(prefix: &str, res: &SweepResults, speeds_where: &SpeedsWhere<'_>) {
    let coexisting = speeds_where(&|r| r.coexistence.is_some_and(|c| c.coexisting));
    if !coexisting.is_empty() {
        eprintln!(
            "warning: {}the response depends on the start at {} of {} speeds (ω/ωn {}): a companion at the same scheme and Δt from another start settled on another response (contact fraction, period or extents; `coexisting` and the `coexist_*` columns of sweep.csv); their estimated error covers the time step only",
            prefix,
            coexisting.len(),
            res.speeds.len(),
            coexisting.join(", ")
        );
    }
    let unchecked = speeds_where(&|r| r.coexistence_failed.is_some());
    if !unchecked.is_empty() {
        eprintln!(
            "warning: {}the coexistence check failed at {} of {} speeds (ω/ωn {}): its companion from another start stopped with an error, so whether the response depends on the start is not known there (`coexistence_failed` in each case's record and in summary.json; the first: {})",
            prefix,
            unchecked.len(),
            res.speeds.len(),
            unchecked.join(", "),
            res.speeds
                .iter()
                .find_map(|r| r.coexistence_failed.as_deref())
                .unwrap_or_default()
        );
    }
}

/// The line of a sweep `res` (`prefix`: its variant's) naming the speeds whose step was refined
/// after the run (`refined`, as `report` formats speeds) and the steps the rejected runs took;
/// nothing when none was.
fn print_refined(prefix: &str, res: &SweepResults, refined: &[String]) {
    if !refined.is_empty() {
        println!(
            "  {}step refined after the run at {} of {} speeds (ω/ωn {}): their own error estimate missed `run.tolerance` at the chosen step; the runs rejected took {} steps more (`step_refinement` of each speed in summary.json, `refined_speeds`)",
            prefix,
            refined.len(),
            res.speeds.len(),
            refined.join(", "),
            res.speeds
                .iter()
                .filter_map(|r| r.step_refinement.as_ref())
                .map(|f| f.rejected_steps())
                .sum::<u64>()
        );
    }
}
