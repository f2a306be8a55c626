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
    /// Inconsistent model data (e.g. an element referencing a missing node).
    #[error("{what}: {message}")]
    Inconsistent {
        /// Which model part.
        what: String,
        /// What is wrong.
        message: String,
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
    /// The response grew beyond any physical bound.
    #[error("response diverged at step {step} (t = {time:.6e} s): |u| = {magnitude:.3e} m exceeds {bound:.3e} m (Δt = {dt:.3e} s, stability limit {limit:.3e} s)")]
    Diverged {
        /// Step index.
        step: usize,
        /// Time (s).
        time: f64,
        /// Offending displacement magnitude (m).
        magnitude: f64,
        /// Bound (m).
        bound: f64,
        /// Time step (s).
        dt: f64,
        /// Stability limit (s).
        limit: f64,
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
    /// A frame writer (VTK/HDF5) failed while the run was streaming its output.
    #[error("writing the frame of step {step} (t = {time:.6e} s) failed: {message}")]
    FrameOutput {
        /// Step index.
        step: usize,
        /// Time (s).
        time: f64,
        /// The writer's message.
        message: String,
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
    /// An error while running one speed of a sweep.
    #[error("at ω/ω_n = {speed_ratio}: {source}")]
    AtSpeed {
        /// The speed ratio being run.
        speed_ratio: f64,
        /// What went wrong.
        source: Box<Error>,
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
    /// Output error helper.
    pub fn output(path: impl Into<PathBuf>, message: impl std::fmt::Display) -> Self {
        Error::Output {
            path: path.into(),
            message: message.to_string(),
        }
    }
}

/// Crate result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
