//! `rubsim sweep`: the speed sweep of `[run.sweep]`, once or per value of `[run.sweep.vary]`,
//! run as cases ([`rubsim::study`]) and assembled by [`rubsim::study::assemble`]; here, what it
//! prints of each variant.

use rubsim::analysis::{self, SweepResults};
use rubsim::study::assemble::Assembled;

/// Prints a sweep's speeds, time, steps, largest estimated error, regimes and peaks.
pub fn report(a: &Assembled<'_>) {
    let (variant, res, regimes, peaks) = (a.variant, &a.res, &a.regimes, &a.peaks);
    let max_err = res.max_estimated_error();
    // A variant's lines start with its overrides.
    let prefix = if variant.prefix.is_empty() {
        String::new()
    } else {
        format!("{}: ", variant.label())
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
    print_refined(
        &prefix,
        res,
        &analysis::notices::speeds_where(res, |r| r.step_refinement.is_some()),
    );
    for w in analysis::notices::sweep_warnings(&prefix, res) {
        eprintln!("warning: {w}");
    }
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
