//! The `rubsim` command line: parse arguments, load the scene into a model (one place:
//! [`load_scene`]), call one analysis, attach the frame sinks a command wants, hand the
//! results to [`rubsim::output`] and print a short report. No domain logic lives here.

/// `println!` for the whole command line, shadowing std's (textual scope: every command module
/// below): a closed standard output — `rubsim sweep … | head -1`, where writes fail with EPIPE
/// since Rust ignores SIGPIPE — must not stop a run before its results are committed, so
/// errors writing the report to stdout are ignored instead of panicking.
macro_rules! println {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

/// `print!` likewise (`rubsim schema | head -1`).
macro_rules! print {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = write!(std::io::stdout(), $($arg)*);
    }};
}

/// `eprintln!` likewise: the warnings and the estimate on a closed standard error
/// (`rubsim sweep … 2>&1 | head -3`) are dropped, the run goes on to commit its results.
macro_rules! eprintln {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

mod bench;
mod check;
mod continuation;
mod continue_autonomous;
mod continue_key;
mod continue_segments;
mod convergence;
mod import_ross;
mod map;
mod mesh;
mod periodic;
mod progress;
mod refine;
mod rotordyn;
mod run;
mod schema;
mod stress;
mod study;
mod sweep;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use rubsim::analysis::{Prepared, RunSettings};
use rubsim::model::Model;
use rubsim::scene::{self, LoadedScene};
use rubsim::time::FrameSink;
use std::path::{Path, PathBuf};

#[derive(Parser)]
#[command(
    name = "rubsim",
    version,
    about = "Rotor-to-stator rubbing vibration: FE contact with Lagrange multipliers and explicit central differences"
)]
pub struct Cli {
    #[command(subcommand)]
    pub cmd: Cmd,
    /// Write into an existing `--out` that rubsim would refuse: a non-empty directory it did
    /// not make (no `.rubsim-` file in it), whose files of the results' names are replaced
    /// (never the file system's root); for `import-ross`, an existing scene file (never the
    /// ROSS file, never through a link).
    #[arg(long, global = true)]
    pub force: bool,
}

/// The command line's `--force`, for [`open_out`].
static FORCE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

#[derive(clap::Args, Clone)]
pub struct Common {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Override a scene value: `--set stator.0.clearance_nd=0.5` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// Relative tolerance of the results (`run.tolerance`, of the orbit's size): the steady
    /// state is proven and the Poincaré period judged to it.
    #[arg(long, value_name = "REL")]
    pub tol: Option<f64>,
}

impl Common {
    /// The overrides: `--set …` in order, then `run.tolerance` from `--tol`.
    pub fn sets(&self) -> Vec<String> {
        let mut s = self.set.clone();
        if let Some(t) = self.tol {
            s.push(format!("run.tolerance={}", scene::toml_number(t)));
        }
        s
    }
}

/// The unit of the speeds given on the command line (`--unit`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum UnitArg {
    /// ω/ω_n, ω_n the rotor's first (lateral) natural frequency at rest, as `rubsim check`
    /// prints it.
    #[default]
    #[value(name = "ratio", alias = "speed_ratio")]
    Ratio,
    /// rad/s.
    #[value(name = "rad/s", alias = "rad_per_s")]
    RadPerS,
    /// Revolutions per minute (Ω = 2π n/60).
    #[value(name = "rpm")]
    Rpm,
}

impl UnitArg {
    /// The scene's unit of the same name.
    pub fn unit(self) -> rubsim::scene::SpeedUnit {
        match self {
            UnitArg::Ratio => rubsim::scene::SpeedUnit::SpeedRatio,
            UnitArg::RadPerS => rubsim::scene::SpeedUnit::RadPerS,
            UnitArg::Rpm => rubsim::scene::SpeedUnit::Rpm,
        }
    }
    /// A speed `v` in this unit as rad/s, for a rotor of first natural frequency `wn` (rad/s).
    pub fn rad_per_s(self, v: f64, wn: f64) -> f64 {
        v * self.unit().to_rad_per_s(wn)
    }
    /// A speed `v` in this unit as ω/ω_n; a ratio exactly as given (`v ω_n / ω_n` could differ
    /// from `v` in its last bit, and a branch's values built from it from the Python
    /// package's, which takes a ratio as it is).
    pub fn ratio(self, v: f64, wn: f64) -> f64 {
        match self {
            Self::Ratio => v,
            _ => self.rad_per_s(v, wn) / wn,
        }
    }
}

#[derive(Subcommand)]
pub enum Cmd {
    /// Mesh a stator geometry (.geo or STEP) with gmsh into the cache `meshes/` and report it:
    /// nodes, cells, physical groups, conformity, the contact boundary.
    Mesh(mesh::MeshArgs),
    /// Stress and strain in the stators during a run at one or more speeds (the paper's
    /// Fig. 10): stress.csv, stress.png, strain.png, the stress field at its peak.
    Stress(stress::StressArgs),
    /// Run a scene at several mesh refinements (a scene key, e.g. a geometry parameter) and
    /// compare orbits and contact forces: the node-to-nodes contact's mesh sensitivity.
    Refine(refine::RefineArgs),
    /// Run one speed (run.speed_ratio or run.speed) and write summary.json and pictures.
    Run {
        #[command(flatten)]
        c: Common,
        /// Output directory (default: out/<scene name>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Run at this speed (in `--unit`) instead of the scene's (also picks one speed of a
        /// sweep scene).
        #[arg(long)]
        speed: Option<f64>,
        /// Unit of `--speed`: ratio (ω/ω_n), rad/s or rpm.
        #[arg(long, value_enum, default_value_t = UnitArg::Ratio)]
        unit: UnitArg,
    },
    /// Run the speed sweep of [run.sweep] in parallel; write sweep.csv, summary.json, pictures.
    /// Every case is kept in <out>/cases/ as soon as it is done: a rerun computes only the
    /// missing ones.
    Sweep {
        #[command(flatten)]
        c: Common,
        #[command(flatten)]
        a: study::StudyArgs,
    },
    /// Run the 2-D map of [run.map] (speed × a scene key, or two keys) in parallel; write
    /// map.csv, summary.json, regime_map.png, orbit_size_map.png, contact_force_map.png. Cases
    /// are kept in <out>/cases/ like a sweep's.
    Map {
        #[command(flatten)]
        c: Common,
        #[command(flatten)]
        a: study::StudyArgs,
    },
    /// Assemble the cases of a sharded sweep or map (DIR/shard-*/cases, and the cases/ of
    /// further directories) into DIR, as one machine would have written them; lists the
    /// missing cases and their shards. A continuation's segments (`rubsim continue
    /// --segments --shard`) are joined into its branch's files.
    Merge {
        /// Output directory of the study (holding the shard-<i>-of-<n>/ folders).
        dir: PathBuf,
        /// Further directories whose cases join the merge.
        more: Vec<PathBuf>,
        /// A continuation in speed only: the output folder of `rubsim sweep` of the same
        /// scene, drawn under the branches and its flagged speeds' responses added as
        /// branches, as `rubsim continue --sweep`.
        #[arg(long, value_name = "DIR")]
        sweep: Option<PathBuf>,
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
        /// Speeds in `--unit` (default: the scene's speed, or ω/ω_n = 1.7, 3.1, 4.9 for a
        /// sweep scene).
        #[arg(long = "speed")]
        speeds: Vec<f64>,
        /// Unit of `--speed`: ratio (ω/ω_n), rad/s or rpm.
        #[arg(long, value_enum, default_value_t = UnitArg::Ratio)]
        unit: UnitArg,
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
    /// The periodic response at one speed by shooting from the settled run: its Floquet
    /// multipliers and stability (summary.json, multipliers.csv).
    Periodic(periodic::PeriodicArgs),
    /// A periodic orbit continued over speed by shooting from point to point: its stability
    /// along the branch and the located changes of stability (branch.csv, bifurcations.csv,
    /// branch.png, summary.json).
    Continue(continuation::ContinueArgs),
    /// Damped modes of the rotor alone at one speed, and its static deflection under gravity.
    Modal {
        #[command(flatten)]
        c: Common,
        /// Speed, in `--unit`.
        #[arg(long, default_value_t = 0.0)]
        speed: f64,
        /// Unit of the speeds: ratio (ω/ω_n), rad/s or rpm.
        #[arg(long, value_enum, default_value_t = UnitArg::Ratio)]
        unit: UnitArg,
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
        /// First speed, in `--unit`.
        #[arg(long, default_value_t = 0.0)]
        from: f64,
        /// Last speed, in `--unit`.
        #[arg(long, default_value_t = 6.0)]
        to: f64,
        /// Unit of the speeds: ratio (ω/ω_n), rad/s or rpm.
        #[arg(long, value_enum, default_value_t = UnitArg::Ratio)]
        unit: UnitArg,
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
        /// First speed, in `--unit`.
        #[arg(long, default_value_t = 0.05)]
        from: f64,
        /// Last speed, in `--unit`.
        #[arg(long, default_value_t = 6.0)]
        to: f64,
        /// Unit of the speeds: ratio (ω/ω_n), rad/s or rpm.
        #[arg(long, value_enum, default_value_t = UnitArg::Ratio)]
        unit: UnitArg,
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
    /// Undamped critical speed map: the synchronous critical speeds (forward and backward
    /// whirl) against the stiffness of the bearings, with the scene's bearing lines.
    CriticalMap {
        #[command(flatten)]
        c: Common,
        /// Lowest bearing stiffness (N/m).
        #[arg(long, default_value_t = 1e5)]
        from: f64,
        /// Highest bearing stiffness (N/m).
        #[arg(long, default_value_t = 1e10)]
        to: f64,
        /// Number of stiffnesses (log spaced).
        #[arg(long, default_value_t = 40)]
        points: usize,
        /// Critical speeds per whirl direction.
        #[arg(long, default_value_t = 4)]
        modes: usize,
        /// Sweep only this bearing (its index in `[[rotor.bearing]]`; the others keep their
        /// stiffness at rest); default: all bearings together.
        #[arg(long)]
        bearing: Option<usize>,
        /// Output directory (default: out/<scene name>/critical_map).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Read a rotor saved by ROSS (`Rotor.save`, TOML or JSON) and write the equivalent rubsim scene
    /// (what rubsim cannot represent is refused at the ROSS file's line and key).
    ImportRoss {
        /// The ROSS file.
        file: PathBuf,
        /// The scene to write (default: standard output). An existing file is refused
        /// unless `--force` is given; the ROSS file itself and symbolic links always are; the
        /// file is written whole or not at all (temporary file, then rename).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// The JSON Schema of scene files (draft 7, for editors: taplo / Even Better TOML), printed
    /// or written to `--out`; `--markdown FILE` writes the key reference (docs/SCENE.md)
    /// generated from it.
    Schema {
        /// Write the schema to this file instead of printing it.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Write the Markdown reference of every scene key to this file.
        #[arg(long)]
        markdown: Option<PathBuf>,
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

/// Reads the scene file `scene` with the overrides `sets` and builds its model, `what`
/// naming the build in its error. Every command turns its scene file into a model here and
/// nowhere else (`import-ross` builds the scene it imports, to check it before writing it).
pub fn load_scene(
    scene: &Path,
    sets: &[String],
    what: impl FnOnce() -> String,
) -> Result<(LoadedScene, Model)> {
    let ls = scene::load(scene, sets)?;
    let model = Model::from_scene(&ls).with_context(what)?;
    Ok((ls, model))
}

/// [`load_scene`] of a command's scene and overrides.
pub fn load(c: &Common) -> Result<(LoadedScene, Model)> {
    load_scene(&c.scene, &c.sets(), || {
        format!("{}: building the model", c.scene.display())
    })
}

/// The default output directory of a scene: `out/<scene file stem>`.
pub fn default_out(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map(|s| s.to_string_lossy().to_string())
        .unwrap_or_else(|| "scene".into());
    PathBuf::from("out").join(stem)
}

/// The run settings of a scene (`[run]`, analysed component from `[output]`).
pub fn settings(ls: &LoadedScene) -> RunSettings {
    RunSettings::from_scene(&ls.scene)
}

/// The run settings of a scene whose runs are at `speeds` (ω/ω_n): [`settings`], with the
/// integrator and Δt chosen from `run.tolerance` by pilot runs when the scene gives no
/// `run.dt` (`analysis::autostep`); the choice is printed on stderr.
pub fn chosen_settings(ls: &LoadedScene, model: &Model, speeds: &[f64]) -> Result<RunSettings> {
    let s = choose_settings(ls, model, speeds)?;
    if let Some(c) = &s.choice {
        eprintln!("{}", describe_choice(c));
    }
    Ok(s)
}

/// [`chosen_settings`] for the commands that shoot periodic orbits (`periodic`, `continue`):
/// the step chosen among the explicit schemes, whose state the maps restart
/// (`rubsim::study::shooting_settings`); the choice is printed on stderr.
pub fn shooting_settings(ls: &LoadedScene, model: &Model, speeds: &[f64]) -> Result<RunSettings> {
    let s = rubsim::study::shooting_settings(ls, model, speeds)
        .with_context(|| format!("{}: choosing Δt for `run.tolerance`", ls.file.display()))?;
    if let Some(c) = &s.choice {
        eprintln!("{}", describe_choice(c));
    }
    Ok(s)
}

/// [`chosen_settings`] without printing the choice (`rubsim check` prints it in its own
/// description of the run).
pub fn choose_settings(ls: &LoadedScene, model: &Model, speeds: &[f64]) -> Result<RunSettings> {
    rubsim::study::run_settings(ls, model, speeds)
        .with_context(|| format!("{}: choosing Δt for `run.tolerance`", ls.file.display()))
}

/// One line on the integrator and Δt chosen from the tolerance.
pub fn describe_choice(c: &rubsim::analysis::StepChoice) -> String {
    format!(
        "step for run.tolerance = {:e}: integrator {}, Δt = {:.3} × the paper's rule, observed order {:.2} (used {:.2}), predicted error {:.2e}; pilots: {} scheme(s) at {} speed(s), {} steps, {:.3} s",
        c.tolerance,
        c.integrator.name(),
        c.dt_scale,
        c.order_observed,
        c.order_used,
        c.error_predicted,
        c.schemes_piloted,
        c.pilot_speeds,
        c.pilot_steps,
        c.pilot_wall_s
    ) + &c.reduction.map_or(String::new(), |r| {
        format!(
            "; reduced model, cut-off chosen from run.tolerance: κ = {} (ω_cut = κ max(nω, ω_c)), truncation error indicator {:.2e} (target {:.2e}; in the predicted error), {} pilot steps",
            r.cutoff_factor, r.truncation_error, r.target, r.pilot_steps
        )
    })
}

/// A progress bar over `n` speeds.
pub fn progress_bar(n: usize) -> ProgressBar {
    let pb = ProgressBar::new(n as u64);
    pb.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} speeds {msg}",
        )
        .expect("valid template"),
    );
    pb
}

/// Prints the up-front estimate of a prepared run to stderr (stdout stays the report).
pub fn announce(prep: &Prepared) {
    let b = rubsim::time::estimate(
        &prep.case,
        &prep.plan,
        prep.request.follow_ups.error_estimate,
    );
    eprintln!(
        "estimate at ω/ωn = {:.3}: {}",
        prep.speed_ratio,
        b.describe()
    );
}

/// Prints the up-front estimate of a sweep of `runs` runs over `speeds` to stderr, from the
/// plans of its first and last speeds. A speed whose plan is refused is reported by the sweep.
pub fn announce_sweep(model: &Model, settings: &RunSettings, speeds: &[f64], runs: usize) {
    let ends = [0, speeds.len().saturating_sub(1)];
    let b: Vec<_> = ends[..speeds.len().min(2)]
        .iter()
        .filter_map(|&k| rubsim::analysis::prepare(model, &settings.request_at(k, speeds[k])).ok())
        .map(|p| rubsim::time::estimate(&p.case, &p.plan, settings.error_estimate))
        .collect();
    if b.is_empty() {
        return;
    }
    let n = runs as f64 / b.len() as f64;
    let steps: f64 = b.iter().map(|x| x.steps + x.companion_steps).sum::<f64>() * n;
    let wall: f64 = b.iter().map(|x| x.wall_s).sum::<f64>() * n;
    eprintln!(
        "estimate of the sweep ({runs} runs): {steps:.3e} steps, ≈ {} on one core (estimate)",
        rubsim::time::budget::duration(wall)
    );
}

/// Estimated seconds above which a single run shows a progress bar on stderr.
const PROGRESS_AFTER_S: f64 = 2.0;

/// A frame sink that only moves a progress bar (about 200 updates over the run).
pub(crate) struct Progress {
    pub(crate) pb: ProgressBar,
    every: usize,
}

impl FrameSink for Progress {
    fn every(&self) -> usize {
        self.every
    }
    fn frame(&mut self, frame: &rubsim::time::Frame<'_>) -> rubsim::error::Result<()> {
        self.pb.set_position(frame.step as u64);
        Ok(())
    }
}

impl Progress {
    /// A progress bar over the main run of `prep` when it is estimated to take longer than
    /// [`PROGRESS_AFTER_S`] and stderr is a terminal; `None` otherwise.
    pub(crate) fn for_run(prep: &Prepared) -> Option<Self> {
        use std::io::IsTerminal;
        let b = rubsim::time::estimate(&prep.case, &prep.plan, false);
        if b.wall_s < PROGRESS_AFTER_S || !std::io::stderr().is_terminal() {
            return None;
        }
        let pb = ProgressBar::new(prep.plan.steps as u64);
        pb.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} steps, eta {eta}",
            )
            .expect("valid template"),
        );
        Some(Self {
            pb,
            every: (prep.plan.steps / 200).max(1),
        })
    }
}

/// Prepares (and locks) the output directory `dir`; prints its notes (a recovered commit,
/// ignored manifest entries) as warnings on stderr. A non-empty directory rubsim did not make
/// is refused unless the command line's `--force` was given (`OutDir::prepare_forced`).
pub fn open_out(dir: &Path) -> Result<rubsim::output::OutDir> {
    let out = if FORCE.load(std::sync::atomic::Ordering::Relaxed) {
        rubsim::output::OutDir::prepare_forced(dir)?
    } else {
        rubsim::output::OutDir::prepare(dir)?
    };
    for n in out.notes() {
        eprintln!("warning: {n}");
    }
    Ok(out)
}

/// The shard asked for: `--shard i/n`, else a Slurm array task's, else none.
pub fn shard_of(given: Option<&str>) -> Result<Option<rubsim::study::Shard>> {
    use rubsim::study::Shard;
    Ok(match given {
        Some(s) => Some(Shard::parse(s)?),
        // A value that is not UTF-8 reaches the parser (as U+FFFD) and is refused naming its
        // variable; `env::var(k).ok()` would take it as unset and run every case in each task.
        None => {
            Shard::from_slurm(|k| std::env::var_os(k).map(|v| v.to_string_lossy().into_owned()))?
        }
    })
}

/// Writes `summary.json`, commits the output directory and says where the results are.
pub fn finish<S: serde::Serialize>(out: rubsim::output::OutDir, summary: &S) -> Result<()> {
    let dir = rubsim::output::summary::finish(out, summary)?;
    println!("results in {}", dir.display());
    Ok(())
}

/// Parses the command line, sizes the thread pool (`--jobs`) and runs the command.
pub fn run() -> Result<()> {
    let cli = Cli::parse();
    FORCE.store(cli.force, std::sync::atomic::Ordering::Relaxed);
    let jobs = match &cli.cmd {
        Cmd::Sweep { a, .. } | Cmd::Map { a, .. } => a.jobs,
        Cmd::Bench { jobs, .. } => *jobs,
        Cmd::Continue(a) => a.jobs,
        _ => None,
    };
    if let Some(j) = jobs {
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(j.max(1))
            .build_global();
    }
    match &cli.cmd {
        Cmd::Run {
            c,
            out,
            speed,
            unit,
        } => run::run(c, out.clone(), *speed, *unit),
        Cmd::Sweep { c, a } => study::run(c, rubsim::study::Kind::Sweep, a),
        Cmd::Map { c, a } => study::run(c, rubsim::study::Kind::Map, a),
        Cmd::Merge { dir, more, sweep } => {
            let mut dirs = vec![dir.clone()];
            dirs.extend(more.iter().cloned());
            study::merge(&dirs, sweep.as_deref())
        }
        Cmd::Check { c } => check::check(c),
        Cmd::Mesh(a) => mesh::mesh(a),
        Cmd::Stress(a) => stress::stress(a),
        Cmd::Refine(a) => refine::refine(a),
        Cmd::Continue(a) if a.segments.is_some() => continue_segments::continuation_in_segments(a),
        Cmd::Continue(a) if a.autonomous => continue_autonomous::continuation_autonomous(a),
        Cmd::Continue(a) if a.key.is_some() => continue_key::continuation_in_key(a),
        Cmd::Continue(a) => continuation::continuation(a),
        Cmd::Periodic(a) => periodic::periodic(a),
        Cmd::Modal {
            c,
            speed,
            unit,
            modes,
            gravity,
            out,
        } => rotordyn::modal(c, (*speed, *unit), *modes, *gravity, out.clone()),
        Cmd::Campbell {
            c,
            from,
            to,
            unit,
            points,
            modes,
            out,
        } => rotordyn::campbell(c, (*from, *to, *unit), *points, *modes, out.clone()),
        Cmd::Unbalance {
            c,
            from,
            to,
            unit,
            points,
            nodes,
            out,
        } => rotordyn::unbalance(c, (*from, *to, *unit), *points, nodes, out.clone()),
        Cmd::CriticalMap {
            c,
            from,
            to,
            points,
            modes,
            bearing,
            out,
        } => rotordyn::critical_map(c, (*from, *to, *points), *modes, *bearing, out.clone()),
        Cmd::Convergence {
            c,
            speeds,
            unit,
            levels,
            reference,
            out,
        } => convergence::convergence(c, (speeds, *unit), *levels, *reference, out.clone()),
        Cmd::Bench {
            c,
            repeat,
            reference,
            ..
        } => bench::bench(c, *repeat, *reference),
        Cmd::ImportRoss { file, out } => import_ross::import_ross(file, out.as_deref(), cli.force),
        Cmd::Schema { out, markdown } => schema::schema(out.as_deref(), markdown.as_deref()),
    }
}
