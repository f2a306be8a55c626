//! `rubsim bench`: time the scene's sweep, optionally against a converged reference.

use super::{chosen_settings, load, Common};
use anyhow::Result;
use rubsim::analysis::bench;

/// Times the sweep (best of `repeat`, no output files) and prints wall time, ns per step and
/// the largest estimated error; with `reference`, also the error against a converged sweep.
pub fn bench(c: &Common, repeat: usize, reference: bool) -> Result<()> {
    let (ls, model) = load(c)?;
    let speeds = bench::speeds(&ls.scene.run, &model);
    let t0 = std::time::Instant::now();
    let s = chosen_settings(&ls, &model, &speeds)?;
    let choose_s = t0.elapsed().as_secs_f64();
    let r = bench::best_of(&model, &s, &speeds, repeat)?;
    println!(
        "bench {}: {} speeds, threads {}, best of {}: wall {:.3} s ({:.3} s sweep + {:.3} s choosing the step), {} steps (main runs), {:.1} ns/step (loop time per step, main runs), largest estimated extents error {:.2e}{}",
        c.scene.display(),
        speeds.len(),
        rayon::current_num_threads(),
        repeat.max(1),
        r.wall_s + choose_s,
        r.wall_s,
        choose_s,
        r.total_steps(),
        bench::ns_per_step(&r),
        r.max_estimated_error(),
        if s.error_estimate { " (wall includes the 2Δt companion runs)" } else { "" }
    );
    if reference {
        let rr = bench::reference(&model, &s, &speeds)?;
        let cmp = bench::compare(&r, &rr);
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
