//! The reproducers of issue 13 (hardening) items 5, 6, 8, 9 and 10 that concern input: each
//! one a clean error naming its key (no panic, no abort, no hang), or the correct result.

use crate::common;

use common::cli::{fails, in_repo, ok};
use common::repo;

const PAPER: &str = "scenes/paper/partial_rub.toml";
const FE: &str = "scenes/fe/paper_rotor_rub.toml";
const STUDY: &str = "scenes/paper/sensitivity/fig11_clearance.toml";
const TWO: &str = "scenes/fe/two_disk_two_stations.toml";

/// `rubsim check scene --set set…` fails cleanly; its stderr names every one of `needles`.
fn refused(scene: &str, sets: &[&str], needles: &[&str]) -> String {
    let mut args = vec!["check", scene];
    for s in sets {
        args.extend(["--set", s]);
    }
    let err = fails(&repo(""), &args);
    for n in needles {
        assert!(err.contains(n), "{args:?}: `{n}` not in:\n{err}");
    }
    err
}

#[test]
fn panics_and_aborts_of_the_report_are_key_naming_errors() {
    for (scene, set, key) in [
        (
            FE,
            "rotor.bearing.0.stiffness=[]",
            "`rotor.bearing.0.stiffness`",
        ),
        (PAPER, "run.sweep.to=1e308", "`run.sweep.to`"),
        (PAPER, "run.sweep.step=1e-300", "`run.sweep.step`"),
        (PAPER, "run.sweep.step=1e-12", "`run.sweep.step`"),
        (
            FE,
            "rotor.shaft.0.elements=1000000000",
            "`rotor.shaft.0.elements`",
        ),
        (PAPER, "run.revolutions=1000000000", "`run.revolutions`"),
        (
            PAPER,
            "run.samples_per_rev=1000000000",
            "`run.samples_per_rev`",
        ),
    ] {
        let err = refused(scene, &[set], &[key]);
        assert!(!err.contains("panicked"), "{set}: {err}");
    }
}

#[test]
fn invalid_input_of_the_report_is_refused_naming_the_key() {
    for (scene, set, key) in [
        (
            PAPER,
            "rotor.unbalance.0.phase_deg=nan",
            "rotor.unbalance.0.phase_deg",
        ),
        (
            PAPER,
            "rotor.unbalance.0.phase_deg=inf",
            "rotor.unbalance.0.phase_deg",
        ),
        (
            PAPER,
            "rotor.unbalance.0.phase_deg=1e308",
            "rotor.unbalance.0.phase_deg",
        ),
        (
            PAPER,
            "run.initial_displacement=[nan, 0.0]",
            "run.initial_displacement",
        ),
        (
            PAPER,
            "run.initial_displacement=[inf, 0.0]",
            "run.initial_displacement",
        ),
        (
            PAPER,
            "run.initial_displacement=[1e200, 0.0]",
            "run.initial_displacement",
        ),
        (PAPER, "output.orbit_grids.0.1=nan", "output.orbit_grids.0"),
        (PAPER, "output.orbit_grids.0.1=-1.0", "output.orbit_grids.0"),
        (
            PAPER,
            "output.force_histories.0=-1.7",
            "output.force_histories",
        ),
        (
            STUDY,
            "run.sweep.vary.values=[0.5, nan]",
            "run.sweep.vary.values",
        ),
        (
            STUDY,
            "run.sweep.vary.values=[0.5, -0.5]",
            "run.sweep.vary.values",
        ),
        (
            STUDY,
            "run.sweep.vary.values=[0.5, 0.5]",
            "run.sweep.vary.values",
        ),
        (
            STUDY,
            "run.sweep.vary.key=\"stator.0.nonsense\"",
            "run.sweep.vary.key",
        ),
        (
            FE,
            "rotor.bearing.0.stiffness=-1e8",
            "rotor.bearing.0.stiffness",
        ),
        (
            FE,
            "rotor.bearing.0.damping=-10.0",
            "rotor.bearing.0.damping",
        ),
        (FE, "rotor.disk.0.density=-7800.0", "rotor.disk.0.density"),
        (TWO, "stator.0.damping=10.0", "stator.0.damping"),
        (PAPER, "stator.0.length=1e308", "stator.0.length"),
    ] {
        let err = refused(scene, &[set], &[&format!("`{key}`")]);
        assert!(err.contains(".toml:"), "{set}: no file:line in {err}");
    }
}

#[test]
fn a_ring_far_lighter_than_the_rotor_is_refused_with_the_reason() {
    refused(
        TWO,
        &["stator.0.mass=1e-6"],
        &["`stator.0.mass = 0`", "modal mass"],
    );
}

#[test]
fn type_errors_inside_rotor_and_stator_entries_name_the_key_and_its_line() {
    let err = refused(FE, &["rotor.shaft.0.elements=\"many\""], &[]);
    assert!(
        err.contains("paper_rotor_rub.toml:14: key `rotor.shaft.0.elements`"),
        "{err}"
    );
    let err = refused(PAPER, &["stator.0.angle_deg=\"up\""], &[]);
    assert!(
        err.contains("partial_rub.toml:30: key `stator.0.angle_deg`"),
        "{err}"
    );
}

#[test]
fn set_appends_an_array_entry_and_switches_alternative_keys() {
    let out = ok(
        &repo(""),
        &[
            "check",
            FE,
            "--set",
            "rotor.unbalance.1.mass=0.01",
            "--set",
            "rotor.unbalance.1.radius=0.01",
            "--set",
            "rotor.unbalance.1.node=2",
        ],
    );
    assert_eq!(out.matches("  unbalance m_u·e").count(), 2, "{out}");
    assert!(
        out.contains("1.0000e-4 kg·m at 0.0° on DOFs [8, 9]"),
        "{out}"
    );
    let out = ok(
        &repo(""),
        &["check", PAPER, "--set", "stator.0.clearance=1e-4"],
    );
    assert!(out.contains("clearance δ = 1.0000e-4 m"), "{out}");
    // Beyond the end by more than one: refused, saying how to append.
    refused(
        PAPER,
        &["rotor.unbalance.2.mass=0.01"],
        &["index 2 out of range", "index 1 appends one"],
    );
}

#[test]
fn absurd_plans_are_refused_with_the_figure_and_the_key() {
    // A bearing of stiffness 0 leaves the rotor pivoting: refused as such when the model is
    // built (`an_fe_rotor_without_a_bearing_is_blamed_on_its_bearings_not_on_a_stator`). A
    // bearing of 1e-3 N/m holds it, barely: ω_n collapses, a revolution lasts minutes — at the
    // full model's explicit limit, the paper's rule. (The error target, `run.auto_step`, runs
    // it reduced and implicit at 1 344 steps a revolution: nothing absurd left.)
    refused(
        FE,
        &["rotor.bearing.1.stiffness=1e-3", "run.auto_step=false"],
        &["steps", "`run.max_steps`", "bearings"],
    );
    refused(
        PAPER,
        &["run.dt=1e-9"],
        &["1.657e10 steps", "set by `run.dt`", "`run.max_steps`"],
    );
    refused(
        PAPER,
        &["run.samples_per_rev=1000000"],
        &["record", "`run.samples_per_rev`"],
    );
    // The same guard before `run` starts: refused at once, nothing computed.
    let t = std::time::Instant::now();
    let (success, _, err) = in_repo(&["run", PAPER, "--speed", "1.7", "--set", "run.dt=1e-9"]);
    assert!(!success && err.contains("`run.max_steps`"), "{err}");
    assert!(t.elapsed().as_secs() < 30, "took {:?}", t.elapsed());
    // The budget is a key: a smaller one refuses the plain scene, a larger one accepts.
    refused(
        PAPER,
        &["run.max_steps=1000"],
        &["above the limit of 1000 steps"],
    );
    ok(
        &repo(""),
        &["check", PAPER, "--set", "run.max_steps=5000000000"],
    );
}

#[test]
fn check_prints_the_estimate_and_the_asked_step() {
    let out = ok(&repo(""), &["check", PAPER, "--set", "run.dt=1e-5"]);
    assert!(
        out.contains("run.dt = 1.0000e-5 s asked; rounded down to 9.9759e-6 s"),
        "{out}"
    );
    assert!(out.contains("estimate at ω/ωn = 0.50:"), "{out}");
    assert!(out.contains("steps (+"), "{out}");
    assert!(out.contains("estimate of the sweep (56 runs"), "{out}");
}

#[test]
fn run_states_its_estimate_on_stderr_only() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("o");
    let (success, stdout, stderr) = in_repo(&[
        "run",
        PAPER,
        "--speed",
        "1.7",
        "--set",
        "output.png=false",
        "--set",
        "run.revolutions=120",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(success, "{stderr}");
    assert!(stderr.contains("estimate at ω/ωn = 1.700:"), "{stderr}");
    assert!(!stdout.contains("estimate"), "{stdout}");
}

#[test]
fn an_fe_rotor_without_a_bearing_is_blamed_on_its_bearings_not_on_a_stator() {
    // Issue 13, item 8: removing an FE rotor bearing (a zero stiffness, or both bearings on one
    // node) failed with "stator rod stiffness: matrix is singular … fix more DOFs": the rod's
    // stiffness ε k_r was round-off because k_r came from a numerically singular rotor K.
    // Each is now blamed on its own key, with the file and line.
    for (set, key) in [
        (
            "rotor.bearing.0.stiffness=0",
            "toml:27: key `rotor.bearing.0.stiffness`",
        ),
        ("rotor.bearing.1.node=0", "key `rotor.bearing.1.node`"),
        ("rotor.bearing.1.kyy=0", "key `rotor.bearing.1.kyy`"),
    ] {
        let scene = if set.contains("kyy") { TWO } else { FE };
        let err = refused(scene, &[set], &[key, "the rotor pivots"]);
        assert!(!err.contains("stator"), "{set}: blames a stator: {err}");
    }
}

#[test]
fn huge_speed_profile_values_are_refused_naming_the_key() {
    // A speed profile to 1e308 × ω_n overflowed to an infinite speed and was reported without
    // its key ("speed profile: point 1 is not finite").
    refused(
        "scenes/transients/paper_runup.toml",
        &["run.speed_profile.to=1e308"],
        &["`run.speed_profile.to`", "1e100"],
    );
}

#[test]
fn a_damping_ratio_without_physical_meaning_is_refused_naming_the_key() {
    // Issue 13 follow-up: `rotor.damping_ratio=1e90` ran, with an orbit of 1e-90 of the
    // clearance scale and an estimated error of 1.5e83. Above ξ = 10 (no resonance left) the
    // value is refused: as a ratio, as the ratio a damping coefficient makes with the rotor's
    // mass and stiffness, as a modal damping ratio.
    refused(
        PAPER,
        &["rotor.damping_ratio=1e90"],
        &["key `rotor.damping_ratio`", "above 10", "N·s/m"],
    );
    // The paper's rotor: m = 2.65 kg, k = 7.36e4 N/m, so 1e5 N·s/m is ξ ≈ 113.
    refused(
        PAPER,
        &["rotor.damping=1.0e5"],
        &["key `rotor.damping`", "a damping ratio of 1.1"],
    );
    refused(
        FE,
        &["rotor.modal_damping.ratio=11.0"],
        &["key `rotor.modal_damping.ratio`", "above 10"],
    );
    // Overdamped but within the bound: legal.
    for set in ["rotor.damping_ratio=10.0", "rotor.damping_ratio=2.0"] {
        let (ok, _, err) = in_repo(&["check", PAPER, "--set", set]);
        assert!(ok, "{set}: {err}");
    }
}

#[test]
fn the_last_mutants_refused_without_their_key_now_name_it() {
    // A zero bearing stiffness on Friswell's two-disk rotor: K's factorisation missed the
    // singularity by round-off (ω_n = 1.5e-4 rad/s), and only the step budget refused the run,
    // naming `run.max_steps`. The bearings are now checked on the data: a rotor held at fewer
    // than two nodes pivots.
    let err = refused(
        "scenes/fe/friswell_5_9_1.toml",
        &["rotor.bearing.1.stiffness=0"],
        &[
            "friswell_5_9_1.toml:34: key `rotor.bearing.1.stiffness`",
            "the rotor pivots",
        ],
    );
    assert!(!err.contains("run.max_steps"), "{err}");
    // The segmented casing without its support beams: the segments float, and the
    // factorisation said only "free rigid-body or mechanism mode" for the stator. The supports
    // are now found to hold no node of the stator's elements, on a curve group that lacks its
    // `frames` entry.
    refused(
        "scenes/stators/segmented_casing_beams.toml",
        &["stator.0.frames=[]"],
        &[
            "segmented_casing_beams.toml:38: key `stator.0.frames`",
            "the group(s) support",
            "rigid-body mode",
        ],
    );
}

#[test]
fn slurm_numbers_that_would_wrap_around_are_refused() {
    // MIN = 2⁶⁴ − 1 with COUNT = 3 made MIN + COUNT wrap to 2 = MAX + 1: the contiguity check
    // passed and the task ran as shard 1/3.
    let tmp = tempfile::tempdir().unwrap();
    let max = u64::MAX.to_string();
    let o = common::cli::command(&repo(""))
        .args(["sweep", STUDY, "--out"])
        .arg(tmp.path().join("d"))
        .env("SLURM_ARRAY_TASK_ID", &max)
        .env("SLURM_ARRAY_TASK_MIN", &max)
        .env("SLURM_ARRAY_TASK_MAX", "1")
        .env("SLURM_ARRAY_TASK_COUNT", "3")
        .output()
        .unwrap();
    let err = common::cli::text(&o.stderr);
    assert!(!o.status.success(), "{err}");
    assert!(
        err.contains("SLURM_ARRAY_TASK_MIN=18446744073709551615")
            && err.contains("is not a task number"),
        "{err}"
    );
    assert!(!tmp.path().join("d").exists(), "nothing written: {err}");
}

#[test]
fn sizes_that_would_abort_on_memory_are_refused_with_their_estimate() {
    // 20 000 elements: a 51 GB dense matrix aborted `check` (exit 134); 2 000: `check` ran for
    // an hour and a half without a word. Both are refused before the model is built, naming
    // the key, the DOFs and the estimate.
    for (elements, needs) in [("20000", "≈ 307.23 GB"), ("2000", "≈ 94.0 min")] {
        let err = refused(
            FE,
            &[
                &format!("rotor.shaft.0.elements={elements}"),
                &format!("rotor.bearing.1.node={elements}"),
            ],
            &[
                "paper_rotor_rub.toml:14: key `rotor.shaft.0.elements`",
                &format!("rotor.shaft.0.elements = {elements}"),
                needs,
                "above the limit of",
            ],
        );
        assert!(!err.contains("memory allocation"), "{err}");
    }
    // Within the limit, `check` states the estimate.
    let out = common::cli::ok(&repo(""), &["check", FE]);
    assert!(
        out.contains("for the dense operations of the model's set-up on its 36 DOFs"),
        "{out}"
    );
    // A window of 10⁹ revolutions allocated 512 GB in `track_orders`: the run is refused before
    // it starts, naming the key and how many revolutions the profile turns.
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("o");
    let (ok, _, err) = in_repo(&[
        "run",
        "scenes/transients/paper_runup.toml",
        "--set",
        "run.speed_profile.window_revolutions=1000000000",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(!ok, "{err}");
    assert!(
        err.contains("run.speed_profile.window_revolutions")
            && err.contains("the profile turns at most 4778 revolutions"),
        "{err}"
    );
    assert!(!out.exists(), "nothing written: {err}");
}

#[test]
fn order_tracking_with_a_window_longer_than_the_signal_allocates_nothing() {
    // Three revolutions of signal and a window of usize::MAX revolutions: no window fits, and
    // the w × 64 resampling buffer (a capacity overflow) is never asked for.
    let t: Vec<f64> = (0..=300).map(|i| f64::from(i) * 0.01).collect();
    let phi: Vec<f64> = t.iter().map(|t| 2.0 * std::f64::consts::PI * t).collect();
    let x: Vec<f64> = phi.iter().map(|p| p.cos()).collect();
    let orders = [1.0];
    for w in [4, usize::MAX / 64, usize::MAX] {
        assert!(rubsim::analysis::transient::track_orders(&t, &phi, &x, &orders, w).is_empty());
    }
    assert_eq!(
        rubsim::analysis::transient::track_orders(&t, &phi, &x, &orders, 1).len(),
        3
    );
}

/// `rubsim check scene --set set…` (a path in the repository or an absolute one) fails
/// cleanly naming every one of `needles`, with no sign of a saturated number or a run that
/// started.
fn transient_refused(scene: &str, sets: &[&str], needles: &[&str]) {
    let err = refused(scene, sets, needles);
    for bad in [
        "18446744073709551615",
        "4294967295",
        "non-finite",
        "diverged",
    ] {
        assert!(!err.contains(bad), "{sets:?}: {err}");
    }
}

#[test]
fn absurd_speed_profiles_are_refused_by_check_naming_the_key() {
    const RUNUP: &str = "scenes/transients/paper_runup.toml";
    const TABLE: &str = "scenes/transients/paper_runup_coastdown.toml";
    // A ramp in 1e-300 s: "18446744073709551615 steps/rev", then "non-finite value at step 1".
    // Now below the smallest magnitude, with its line; 1e-20 s is a single step of the run.
    transient_refused(
        RUNUP,
        &["run.speed_profile.duration=1e-300"],
        &[
            "paper_runup.toml:51: key `run.speed_profile.duration`",
            "below 1e-50",
        ],
    );
    transient_refused(
        RUNUP,
        &["run.speed_profile.duration=1e-20"],
        &["run.speed_profile.duration", "a single time step"],
    );
    // The same by an acceleration of 1e300.
    let tmp = tempfile::tempdir().unwrap();
    let src = std::fs::read_to_string(repo(RUNUP)).unwrap();
    let acc = tmp.path().join("acc.toml");
    std::fs::write(&acc, src.replace("duration = 30.0", "acceleration = 1e300")).unwrap();
    transient_refused(
        acc.to_str().unwrap(),
        &[],
        &["run.speed_profile.acceleration", "a single time step"],
    );
    // A table jumping from 0.5 to 6 ω_n in 1e-300 s: "response diverged at step 1".
    transient_refused(
        TABLE,
        &["run.speed_profile.points=[[0,0.5],[1e-300,6],[2,6]]"],
        &["run.speed_profile.points.1", "below 1e-50"],
    );
    transient_refused(
        TABLE,
        &["run.speed_profile.points=[[0,0.5],[1e-9,6],[2,6]]"],
        &["run.speed_profile.points.1", "less than one time step"],
    );
    // 10⁹ s: refused as before, but with the true number of revolutions (not 4294967295) and
    // the profile named instead of `run.revolutions`.
    transient_refused(
        RUNUP,
        &["run.speed_profile.duration=1e9"],
        &[
            "× 159282420040 revolutions",
            "a shorter profile (`run.speed_profile`",
        ],
    );
    // Three numbers in a point: the third was dropped.
    let src = std::fs::read_to_string(repo(TABLE)).unwrap();
    let three = tmp.path().join("three.toml");
    std::fs::write(
        &three,
        src.replace("[[0.0, 0.5], [30.0", "[[0.0, 0.5, 7.0], [30.0"),
    )
    .unwrap();
    transient_refused(
        three.to_str().unwrap(),
        &[],
        &[
            "line 41",
            "`run.speed_profile.points.0` has 3 numbers",
            "each point is [t, speed]",
        ],
    );
}

#[test]
fn absurdly_small_values_are_refused_naming_their_key() {
    // Finite and positive, but 1e-300: "rotor mass matrix … singular", or the stator blamed.
    for (scene, set, key) in [
        (FE, "rotor.shaft.0.length=1e-300", "`rotor.shaft.0.length`"),
        (
            FE,
            "rotor.shaft.0.outer_diameter=1e-300",
            "`rotor.shaft.0.outer_diameter`",
        ),
        (PAPER, "rotor.damping_ratio=1e-300", "`rotor.damping_ratio`"),
        (PAPER, "stator.0.length=1e-300", "`stator.0.length`"),
    ] {
        let err = refused(scene, &[set], &[key, "below 1e-50 in magnitude"]);
        assert!(!err.contains("singular"), "{set}: {err}");
    }
}

// ---------------------------------------------------------------------------------------------
// Issue 31 items 3 and 9: a refinement that does not refine, shards' conflicting copies of a
// case, a case file's non-finite numbers.

/// `rubsim refine` meshes every value first and refuses a study whose meshes do not grow:
/// the rod's structured (transfinite) mesh ignores `size_factor`, so both values give the same
/// mesh. Nothing is written.
#[test]
fn a_refinement_study_whose_mesh_does_not_refine_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("refine");
    let scene = repo("scenes/stators/rod2d.toml");
    let err = fails(
        &repo(""),
        &[
            "refine",
            scene.to_str().unwrap(),
            "--key",
            "stator.0.size_factor",
            "--values",
            "1,0.5",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    for part in ["`stator.0.size_factor` = 0.5", "not refined", "= 1 before"] {
        assert!(err.contains(part), "{part}: {err}");
    }
    assert!(!out.exists(), "the refused study wrote {out:?}");
}

/// The paper's sweep cut to 4 speeds and short runs, into `out` (extra arguments after).
fn small_sweep(out: &std::path::Path, extra: &[&str]) -> String {
    let args = small_sweep_args(out, extra);
    ok(
        &repo(""),
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
    )
}

/// The arguments of [`small_sweep`].
fn small_sweep_args(out: &std::path::Path, extra: &[&str]) -> Vec<String> {
    let scene = repo(PAPER);
    let mut args = vec![
        "sweep",
        scene.to_str().unwrap(),
        "--set",
        "run.sweep.from=1.4",
        "--set",
        "run.sweep.to=1.7",
        "--set",
        "run.sweep.step=0.1",
        "--set",
        "run.revolutions=120",
        "--set",
        "run.transient_revolutions=60",
        "--jobs",
        "1",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    args.into_iter().map(String::from).collect()
}

/// Rewrites the case file `p` with `edit` and recomputes its end line, as someone who knows the
/// format would: the file is whole, and only its numbers can tell.
fn reseal(p: &std::path::Path, edit: impl FnOnce(&str) -> String) {
    let text = std::fs::read_to_string(p).unwrap();
    let body = text.trim_end_matches('\n');
    let body = &body[..body.rfind('\n').unwrap() + 1];
    let new = edit(body);
    assert_ne!(new, body, "the edit changed nothing");
    let mut h = rubsim::math::Fnv128::new();
    h.write(new.as_bytes());
    std::fs::write(p, format!("{new}# end {}\n", h.hex())).unwrap();
}

/// Replaces the value of the first line `key = …` of a case file's text.
fn set_value(text: &str, key: &str, value: &str) -> String {
    let prefix = format!("{key} = ");
    let mut done = false;
    text.lines()
        .map(|l| {
            if !done && l.starts_with(&prefix) {
                done = true;
                format!("{prefix}{value}")
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + "\n"
}

/// A case file whose `amp_1x_nd` was set to NaN (its end line recomputed) is refused when it is
/// read, naming the file and the field, instead of being drawn.
#[test]
fn a_case_file_with_a_non_finite_number_is_refused_naming_file_and_field() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("sweep");
    small_sweep(&out, &[]);
    let case = out.join("cases/speed_ratio=1.5.toml");
    reseal(&case, |t| set_value(t, "amp_1x_nd", "nan"));
    let args = small_sweep_args(&out, &[]);
    let err = fails(
        &repo(""),
        &args.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    assert!(
        err.contains("speed_ratio=1.5.toml")
            && err.contains("results.amp_1x_nd")
            && err.contains("NaN"),
        "{err}"
    );
}

/// Two shard layouts of one sweep hold the same case; a copy edited to other numbers (its end
/// line recomputed) is named with both files, not silently dropped or taken.
#[test]
fn merge_names_two_differing_copies_of_a_case_and_refuses() {
    let tmp = tempfile::tempdir().unwrap();
    let dist = tmp.path().join("dist");
    for shard in ["1/2", "2/2", "1/3"] {
        small_sweep(&dist, &["--shard", shard]);
    }
    let d = dist.to_str().unwrap();
    // Identical copies (shard 1 of 2 and shard 1 of 3 share speed_ratio=1.4): merged.
    ok(&repo(""), &["merge", d]);
    let copy = dist.join("shard-1-of-3/cases/speed_ratio=1.4.toml");
    assert!(
        copy.is_file()
            && dist
                .join("shard-1-of-2/cases/speed_ratio=1.4.toml")
                .is_file()
    );
    reseal(&copy, |t| set_value(t, "amp_1x_nd", "0.123456789"));
    let err = fails(&repo(""), &["merge", d]);
    for part in [
        "speed_ratio=1.4",
        "differ",
        "shard-1-of-2/cases/speed_ratio=1.4.toml",
        "shard-1-of-3/cases/speed_ratio=1.4.toml",
    ] {
        assert!(err.contains(part), "{part}: {err}");
    }
}

#[test]
fn a_stator_needs_a_name_of_its_own() {
    // Events, the outputs (worn_depth.csv, the series) and the messages name stators: an empty
    // or repeated name is refused at the name (the mutation test's `stator.0.name = ""` and
    // duplicated `stator` entry were refused only by the event that could not find them).
    let text = common::scenes::PAPER;
    let err = |sets: &[&str]| -> String {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        match rubsim::scene::parse("names.toml".as_ref(), text, &sets) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{sets:?} accepted"),
        }
    };
    let e = err(&["stator.0.name=\"\""]);
    assert!(
        e.contains("`stator.0.name`") && e.contains("empty name"),
        "{e}"
    );
    let e = err(&[
        "stator.1.kind=\"ring\"",
        "stator.1.name=\"rod\"",
        "stator.1.station=\"disk\"",
        "stator.1.clearance=1e-3",
        "stator.1.stiffness=1e6",
    ]);
    assert!(
        e.contains("`stator.1.name`") && e.contains("duplicate stator name `rod`"),
        "{e}"
    );
}
