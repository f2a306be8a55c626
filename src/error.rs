//! Error types of the library.
//!
//! One enum per layer that can fail, each variant carrying the data a user needs to find the
//! problem (file, key, line, step, time, limit). The binary wraps them with `anyhow` only at the
//! very top; the library never panics on bad input.

use std::path::PathBuf;

/// Errors in reading, overriding or validating a scene file.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{file}: cannot read scene file: {source}")]
    Read {
        /// Path of the scene file.
        file: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// TOML syntax error or a key of the wrong type / unknown key (message from the TOML parser,
    /// which names the line and column).
    #[error("{file}: {message}")]
    Parse {
        /// Path of the scene file.
        file: PathBuf,
        /// Parser message including line and column.
        message: String,
    },
    /// A value is present and well-typed but not admissible (e.g. a negative mass).
    #[error("{file}{}: key `{key}`: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
    Invalid {
        /// Path of the scene file.
        file: PathBuf,
        /// Dotted key path, e.g. `rotor.mass` or `stator[0].clearance_nd`.
        key: String,
        /// 1-based line in the scene file, when the key is present in the file.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },
    /// A `--set key=value` override could not be applied.
    #[error("--set {assignment}: {message}")]
    Override {
        /// The assignment as given on the command line.
        assignment: String,
        /// What is wrong.
        message: String,
    },
}

/// Errors while building a model from a resolved scene.
#[derive(Debug, thiserror::Error)]
pub enum ModelError {
    /// A matrix that must be positive definite is not (e.g. a stator with a free rigid mode).
    #[error("{what}: matrix is singular or not positive definite ({detail})")]
    Singular {
        /// Which model part.
        what: String,
        /// Solver detail.
        detail: String,
    },
    /// A model matrix could not be factored; `hint` says what in the model causes it.
    #[error("{what}: {hint}: {source}")]
    Factorisation {
        /// Which model matrix (e.g. "stator `casing` stiffness").
        what: String,
        /// The likely cause in the model and its remedy.
        hint: String,
        /// The factorisation's error.
        #[source]
        source: LinalgError,
    },
    /// A clearance given as `clearance_nd` (× |Z0(ω)|) cannot be placed because |Z0(ω)| is
    /// not a positive finite length; `cause` names the input responsible and the remedy.
    #[error("{what}: clearance_nd is relative to |Z0(ω)| at ω = {omega:.6e} rad/s, {cause}")]
    ClearanceScale {
        /// Which stator.
        what: String,
        /// Speed ω (rad/s).
        omega: f64,
        /// Why |Z0| is unusable there, naming the key to change.
        cause: String,
        /// True when only this speed is affected (an undamped rotor at a critical speed):
        /// other speeds of the same model are fine.
        at_this_speed_only: bool,
    },
    /// Inconsistent model data (e.g. an element referencing a missing node).
    #[error("{what}: {message}")]
    Inconsistent {
        /// Which model part.
        what: String,
        /// What is wrong.
        message: String,
    },
}

/// Which factorisation a [`LinalgError`] comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Factorisation {
    /// Sparse Cholesky `A = L Lᵀ` (faer).
    Cholesky,
    /// Sparse LU with partial pivoting `P A Q = L U` (faer).
    Lu,
}

impl std::fmt::Display for Factorisation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Factorisation::Cholesky => "sparse Cholesky",
            Factorisation::Lu => "sparse LU",
        })
    }
}

/// A failure of the factorisation machinery that says nothing about the matrix values: an
/// index that overflows faer's index type, or memory that cannot be allocated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Exhausted {
    /// An index (row, column or fill-in count) exceeds the largest value of the index type.
    IndexOverflow,
    /// A workspace or factor could not be allocated.
    OutOfMemory,
}

impl std::fmt::Display for Exhausted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Exhausted::IndexOverflow => "index overflow",
            Exhausted::OutOfMemory => "out of memory",
        })
    }
}

/// Errors of the factorisations in [`crate::linalg`]. Each names the size `n` of the (square)
/// matrix and where the factorisation stopped; the caller adds which model matrix it was.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinalgError {
    /// The Cholesky factorisation met a pivot `≤ 0`: the matrix is not symmetric positive
    /// definite (for a stiffness: a free rigid-body or mechanism mode).
    #[error("{n}×{n} matrix is not positive definite: the sparse Cholesky factorisation met a non-positive pivot (at {pivot} in its fill-reducing order)")]
    NotPositiveDefinite {
        /// Matrix size.
        n: usize,
        /// Position of the failing pivot as faer reports it (in the fill-reducing order, not
        /// a DOF number of the model).
        pivot: usize,
    },
    /// A diagonal matrix (a lumped step matrix M̃) has an entry `≤ 0` (a non-positive mass).
    #[error("{n}×{n} diagonal matrix has a non-positive entry at {index}")]
    NonPositiveDiagonal {
        /// Matrix size.
        n: usize,
        /// Index of the entry.
        index: usize,
    },
    /// The sparse LU found no non-zero pivot: the matrix is structurally or numerically
    /// singular.
    #[error("{n}×{n} matrix is singular: no pivot at elimination step {step} of the sparse LU")]
    Singular {
        /// Matrix size.
        n: usize,
        /// Elimination step at which no pivot was found.
        step: usize,
    },
    /// A 4 × 4 pivot block of the block-tridiagonal LU is singular (its largest pivot is below
    /// `1e-13` times the largest entry of the matrix).
    #[error("{n}×{n} matrix: singular pivot block at node {node} of the block LU")]
    SingularBlock {
        /// Matrix size.
        n: usize,
        /// Node (block row) of the singular pivot block.
        node: usize,
    },
    /// The `m × m` capacitance matrix `D⁻¹ + Uᵀ S⁻¹ U` of a Woodbury solve is singular.
    #[error("the {rank}×{rank} Woodbury capacitance matrix of a {n}×{n} system is singular")]
    SingularCapacitance {
        /// Size of the sparse part.
        n: usize,
        /// Rank m of the low-rank term.
        rank: usize,
    },
    /// A coefficient `dᵢ` of a low-rank term `U diag(d) Uᵀ` is zero or not finite (the
    /// Woodbury identity needs `D⁻¹`).
    #[error("low-rank term {index} has d = {value}")]
    LowRankTerm {
        /// Index i of the term.
        index: usize,
        /// Its coefficient dᵢ.
        value: f64,
    },
    /// The symbolic analysis (ordering, elimination tree, fill-in) could not run.
    #[error("{n}×{n} matrix with {nnz} stored entries: symbolic {factorisation} analysis failed ({cause})")]
    Symbolic {
        /// Which factorisation.
        factorisation: Factorisation,
        /// Matrix size.
        n: usize,
        /// Stored entries of the matrix.
        nnz: usize,
        /// Why.
        cause: Exhausted,
    },
    /// The factorisation could not run for want of indices or memory (not because of the
    /// values: those failures are the variants above).
    #[error("{n}×{n} matrix: {factorisation} factorisation failed ({cause})")]
    Resources {
        /// Which factorisation.
        factorisation: Factorisation,
        /// Matrix size.
        n: usize,
        /// Why.
        cause: Exhausted,
    },
}

/// Errors raised by the time integration.
#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    /// A state value became NaN or infinite.
    #[error("non-finite value at step {step} (t = {time:.6e} s) in {what} dof {dof}; the integration is unstable (Δt = {dt:.3e} s, stability limit {limit:.3e} s)")]
    NonFinite {
        /// Step index.
        step: usize,
        /// Time (s).
        time: f64,
        /// Which body.
        what: String,
        /// DOF index inside that body.
        dof: usize,
        /// Time step (s).
        dt: f64,
        /// Stability limit (s).
        limit: f64,
    },
    /// The response grew beyond any physical bound: a rotor DOF exceeded 10⁴ times the run's
    /// scale for it (its forced response, the clearances, the initial displacement).
    #[error("response diverged at step {step} (t = {time:.6e} s): |{dof}| = {magnitude:.3e} {unit} exceeds {bound:.3e} {unit}, 10⁴ × the run's largest forced response, clearance or initial displacement (Δt = {dt:.3e} s, stability limit {limit:.3e} s)")]
    Diverged {
        /// Step index.
        step: usize,
        /// Time (s).
        time: f64,
        /// The DOF, e.g. `u_y of rotor node 4`.
        dof: String,
        /// Its unit, `m` or `rad`.
        unit: &'static str,
        /// Offending magnitude (m or rad).
        magnitude: f64,
        /// Bound (m or rad).
        bound: f64,
        /// Time step (s).
        dt: f64,
        /// Stability limit (s).
        limit: f64,
    },
    /// A driven rotor's spin speed passed 1.5 × the speed its step was planned for
    /// ([`crate::model::Drive::speed_bound`]): the unbalance's reaction torque drove it.
    #[error("the driven rotor's speed reached {omega:.4e} rad/s at step {step} (t = {time:.6e} s), above {bound:.4e} rad/s, 1.5 × the speed its time step was planned for (Ω₀ + max drive torque × drive time / J): lower the unbalance or raise `run.speed_profile.polar_inertia`")]
    SpinOverspeed {
        /// Step index.
        step: usize,
        /// Time (s).
        time: f64,
        /// Ω reached (rad/s).
        omega: f64,
        /// The bound (rad/s).
        bound: f64,
    },
    /// A requested time step exceeds the explicit stability limit.
    #[error("time step {dt:.4e} s exceeds the stability limit {limit:.4e} s of the {integrator} integrator ({reason})")]
    StepTooLarge {
        /// Requested step (s).
        dt: f64,
        /// Limit (s).
        limit: f64,
        /// Integrator name.
        integrator: String,
        /// What sets the limit.
        reason: String,
    },
    /// A requested time step of an implicit scheme does not resolve the response.
    #[error("time step {dt:.4e} s of the {integrator} integrator exceeds {max:.4e} s: {reason}; lower `run.dt` or leave it out")]
    StepTooCoarse {
        /// Requested step (s).
        dt: f64,
        /// Largest step accepted (s).
        max: f64,
        /// Integrator name.
        integrator: String,
        /// Why.
        reason: String,
    },
    /// An implicit scheme asked to run a speed transient of a gyroscopic rotor: the Ω(t) G and
    /// Ω̇ K_st terms are corrected on the central-difference factor M̃ only (`time::spin`).
    #[error("the {integrator} integrator does not run speed transients of a gyroscopic rotor yet (the Ω(t)G and Ω̇ K_st terms are corrected for the explicit schemes only): use forward_increment or collocated (`run.integrator`) with `run.speed_profile`")]
    GyroscopicTransient {
        /// Integrator name.
        integrator: String,
    },
    /// A reduced rotor (`[run.reduction]`) asked to run driven: its spin DOF reads the full
    /// rotor's unbalance reactions.
    #[error("a reduced rotor (`[run.reduction]`) runs at constant speed or along a prescribed `run.speed_profile` only: leave out the reduction for a driven rotor")]
    ReducedTransient,
    /// The step plan needs more steps than one run may take (`run.max_steps`).
    #[error("the run needs {steps:.3e} steps ({steps_per_rev:.3e} per revolution × {revolutions} revolutions; Δt = {dt:.3e} s, set by {why}), above the limit of {max} steps (`run.max_steps`): {advice}")]
    TooManySteps {
        /// Steps the plan needs.
        steps: f64,
        /// Steps per revolution.
        steps_per_rev: f64,
        /// Revolutions.
        revolutions: usize,
        /// Δt (s).
        dt: f64,
        /// What sets Δt.
        why: String,
        /// The limit.
        max: u64,
        /// Which keys to change.
        advice: String,
    },
    /// The step chosen from `run.tolerance` (`analysis::autostep`) cannot be met within the
    /// budget.
    #[error("`run.tolerance` = {tolerance:e} cannot be met within the budget: {detail}")]
    ToleranceUnreachable {
        /// The tolerance asked for.
        tolerance: f64,
        /// The figures: integrator, Δt, steps and the limit.
        detail: String,
    },
    /// The record of a run would not fit the memory limit.
    #[error("the run's record needs {bytes:.3e} bytes ({samples:.3e} samples), above the limit of {max:.3e} bytes: lower `run.samples_per_rev` or `run.revolutions`")]
    RecordTooLarge {
        /// Bytes the record needs.
        bytes: f64,
        /// Samples recorded.
        samples: f64,
        /// The limit (bytes).
        max: f64,
    },
    /// A stator's values make no physical sense for the explicit scheme.
    #[error("stator `{name}` (`stator.{index}`): {message}")]
    Meaningless {
        /// Index of the stator (`[[stator]]` entry).
        index: usize,
        /// Its name.
        name: String,
        /// What is wrong, and the key to change.
        message: String,
    },
    /// A frame sink (VTK/HDF5 writer, stress probe) failed while the run was streaming.
    #[error("writing the frame of step {step} (t = {time:.6e} s) failed: {source}")]
    FrameOutput {
        /// Step index.
        step: usize,
        /// Time (s).
        time: f64,
        /// The sink's error.
        source: Box<Error>,
    },
    /// The step matrix of a body (M̃ = M/Δt² + C/(2Δt)) or the stiffness of a massless stator
    /// could not be factored before the loop.
    #[error("{what}: cannot factor its step matrix (Δt = {dt:.3e} s): {source}")]
    Factorization {
        /// Which body (`rotor`, ``stator `name` ``).
        what: String,
        /// Time step (s).
        dt: f64,
        /// The factorisation's error.
        #[source]
        source: LinalgError,
    },
    /// The contact complementarity problem could not be solved.
    #[error("contact solve failed at step {step} (t = {time:.6e} s) with {pairs} candidate pairs: {message}")]
    Contact {
        /// Step index.
        step: usize,
        /// Time (s).
        time: f64,
        /// Number of pairs in the problem.
        pairs: usize,
        /// Detail.
        message: String,
    },
}

/// Errors of the stator geometry pipeline: running gmsh, reading its meshes, checking them.
///
/// Every variant names the file (geometry, STEP or mesh) and, where it applies, the physical
/// group, so that a user can find the line of the `.geo` to fix.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// A file named by a scene or a `.geo` does not exist.
    #[error("{file}: no such file{}", referenced_by.as_ref().map(|r| format!(" (named in {})", r.display())).unwrap_or_default())]
    MissingFile {
        /// The file that was looked for.
        file: PathBuf,
        /// The scene or geometry that names it.
        referenced_by: Option<PathBuf>,
    },
    /// A file exists but cannot be read or written.
    #[error("{file}: {source}")]
    Io {
        /// The file.
        file: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// The gmsh executable cannot be started.
    #[error("{geometry}: cannot run gmsh `{program}` ({message}); install gmsh (scripts/setup.sh, or `apt-get install gmsh`) or point RUBSIM_GMSH at it")]
    GmshNotFound {
        /// The geometry that was to be meshed.
        geometry: PathBuf,
        /// The program name or path tried.
        program: String,
        /// The operating system's message.
        message: String,
    },
    /// gmsh ran and failed (or produced no mesh); `message` holds gmsh's own error lines.
    #[error("{geometry}: gmsh failed{}:\n{message}", status.map(|s| format!(" (exit status {s})")).unwrap_or_default())]
    GmshFailed {
        /// The geometry being meshed.
        geometry: PathBuf,
        /// gmsh's exit status, when it exited.
        status: Option<i32>,
        /// gmsh's error and warning lines.
        message: String,
    },
    /// gmsh ran past its time limit and was killed.
    #[error("{geometry}: gmsh did not finish within {limit_s} s and was stopped; the geometry or its parameters may be wrong (gmsh's last lines below), or the mesh too fine — allow more time with RUBSIM_GMSH_TIMEOUT=<seconds> (or `rubsim mesh --timeout`):\n{message}")]
    GmshTimeout {
        /// The geometry being meshed.
        geometry: PathBuf,
        /// The limit (s).
        limit_s: f64,
        /// gmsh's last lines.
        message: String,
    },
    /// A file given as a geometry to mesh is not one (a mesh, a binary file).
    #[error("{geometry}: not a geometry gmsh can mesh: {message}")]
    NotAGeometry {
        /// The file.
        geometry: PathBuf,
        /// What it is and what is expected.
        message: String,
    },
    /// A parameter value outside the bounds the geometry declares (`Min`, `Max` of its
    /// `DefineConstant`), or not finite.
    #[error("{geometry}: parameter `{name}` = {value}: {}", range_message(*min, *max))]
    ParameterOutOfRange {
        /// The geometry.
        geometry: PathBuf,
        /// The parameter.
        name: String,
        /// The value given.
        value: f64,
        /// Its declared minimum.
        min: Option<f64>,
        /// Its declared maximum.
        max: Option<f64>,
    },
    /// A `-setnumber` parameter that the geometry does not define with `DefineConstant`.
    #[error("{geometry}: parameter `{name}` is not defined by the geometry (it defines: {})", if known.is_empty() { "nothing".to_string() } else { known.join(", ") })]
    UnknownParameter {
        /// The geometry.
        geometry: PathBuf,
        /// The parameter given.
        name: String,
        /// The parameters the geometry defines.
        known: Vec<String>,
    },
    /// The mesh file is not valid MSH 4.1.
    #[error("{file}: not a readable gmsh MSH 4.1 mesh: {message}")]
    Parse {
        /// The mesh file.
        file: PathBuf,
        /// Parser message.
        message: String,
    },
    /// A physical group the scene relies on is not in the mesh.
    #[error("{file}: no physical group `{name}` (groups in the mesh: {}); define it in the geometry with Physical Curve/Surface/Volume(\"{name}\")", if available.is_empty() { "none".to_string() } else { available.join(", ") })]
    MissingGroup {
        /// The mesh file.
        file: PathBuf,
        /// The group looked for.
        name: String,
        /// The groups the mesh has, as `name (dim d)`.
        available: Vec<String>,
    },
    /// A physical group has the wrong dimension or holds nothing usable.
    #[error("{file}: physical group `{group}`: {message}")]
    BadGroup {
        /// The mesh file.
        file: PathBuf,
        /// The group.
        group: String,
        /// What is wrong.
        message: String,
    },
    /// The mesh has no nodes or no cells of the stator's dimension.
    #[error("{file}: empty mesh: {message}")]
    Empty {
        /// The mesh file.
        file: PathBuf,
        /// What is missing.
        message: String,
    },
    /// Elements whose Jacobian determinant is not positive (inverted or degenerate).
    #[error("{file}: {count} inverted or degenerate element(s) in group `{group}`, first gmsh element {element} (det J = {det:.3e}); check the orientation of the surfaces or the node order")]
    Inverted {
        /// The mesh file.
        file: PathBuf,
        /// The material group of the element.
        group: String,
        /// gmsh tag of the first offending element.
        element: u64,
        /// Its smallest Jacobian determinant.
        det: f64,
        /// Number of offending elements.
        count: usize,
    },
    /// Parts of the mesh do not share their interfaces (coincident or hanging nodes).
    #[error("{file}: non-conforming mesh: {message}")]
    NonConforming {
        /// The mesh file.
        file: PathBuf,
        /// What was found.
        message: String,
    },
    /// An element type the stator elements do not implement.
    #[error("{file}: physical group `{group}` holds {count} element(s) of gmsh type {kind}, which rubsim does not implement (2-D: 3/6-node triangles, 4/8/9-node quadrilaterals; 3-D: 4/10-node tetrahedra; lines: 2-node)")]
    UnsupportedCell {
        /// The mesh file.
        file: PathBuf,
        /// The group holding them.
        group: String,
        /// gmsh element type name.
        kind: String,
        /// How many.
        count: usize,
    },
}

/// Crate-wide error.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Scene input error.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Model construction error.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// Time integration error.
    #[error(transparent)]
    Solve(#[from] SolveError),
    /// Geometry, meshing or mesh reading error.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// An error while running one speed of a sweep.
    #[error("at ω/ω_n = {speed_ratio}: {source}")]
    AtSpeed {
        /// The speed ratio being run.
        speed_ratio: f64,
        /// What went wrong.
        source: Box<Error>,
    },
    /// An error while running one case of a sweep or map (named by its id).
    #[error("case {id}: {source}")]
    AtCase {
        /// The case id (its parameters).
        id: String,
        /// What went wrong.
        source: Box<Error>,
    },
    /// A shard request (`--shard i/n`, or the Slurm array's variables) that cannot be served.
    #[error("{given}: {message}")]
    Shard {
        /// What was given (`--shard 5/4`, `SLURM_ARRAY_TASK_ID=…`).
        given: String,
        /// What is wrong.
        message: String,
    },
    /// A study (sweep, map, merge) that cannot be run or assembled as asked: a scene without
    /// the study's table, missing cases, stores of different scenes.
    #[error("{what}{}{message}", if what.is_empty() { "" } else { ": " })]
    Study {
        /// What it concerns (the scene file, a store folder); empty when the message says it.
        what: String,
        /// What is wrong.
        message: String,
    },
    /// An error with what was being done when it happened (`<scene>: building the model`).
    #[error("{context}: {cause}")]
    Context {
        /// What was being done.
        context: String,
        /// What went wrong.
        cause: Box<Error>,
    },
    /// Output writing error.
    #[error("{path}: {message}")]
    Output {
        /// File or directory.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

impl Error {
    /// A study error about `what` (empty: the message says it).
    pub fn study(what: impl std::fmt::Display, message: impl std::fmt::Display) -> Self {
        Error::Study {
            what: what.to_string(),
            message: message.to_string(),
        }
    }

    /// This error with `context`: what was being done when it happened.
    pub fn context(self, context: impl std::fmt::Display) -> Self {
        Error::Context {
            context: context.to_string(),
            cause: Box::new(self),
        }
    }

    /// Output error helper.
    pub fn output(path: impl Into<PathBuf>, message: impl std::fmt::Display) -> Self {
        Error::Output {
            path: path.into(),
            message: message.to_string(),
        }
    }
}

/// "must be …" for a parameter's declared bounds.
fn range_message(min: Option<f64>, max: Option<f64>) -> String {
    let range = match (min, max) {
        (Some(a), Some(b)) => format!("must lie in [{a}, {b}]"),
        (Some(a), None) => format!("must be at least {a}"),
        (None, Some(b)) => format!("must be at most {b}"),
        (None, None) => "must be a finite number".into(),
    };
    format!("{range} (bounds declared by the geometry's DefineConstant)")
}

/// Crate result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
