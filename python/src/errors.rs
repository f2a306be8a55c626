//! rubsim's errors as Python exceptions. Every class derives from `RubsimError`; a scene error
//! carries `file`, `key` and `line` (`None` where unknown), an error at one speed of a sweep
//! `speed_ratio`, an error of one case `case`. No error of the library crosses into Python as a
//! panic: the calls return these.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use rubsim::error::{Error, SceneError as SceneInput};

create_exception!(
    rubsim,
    RubsimError,
    PyException,
    "Every error rubsim raises."
);
create_exception!(
    rubsim,
    SceneError,
    RubsimError,
    "Bad scene input; `file`, `key` and `line` say where (None where unknown)."
);
create_exception!(
    rubsim,
    ModelError,
    RubsimError,
    "The scene is valid but its model cannot be built (a rotor its bearings do not hold, a stator that is a mechanism, …)."
);
create_exception!(
    rubsim,
    MeshError,
    RubsimError,
    "A geometry cannot be meshed by gmsh or a mesh cannot be read."
);
create_exception!(
    rubsim,
    SolveError,
    RubsimError,
    "The time integration stopped: numerically unstable, a contact solve that did not converge, a step too large."
);
create_exception!(
    rubsim,
    StudyError,
    RubsimError,
    "A sweep or map that cannot be run or assembled as asked."
);
create_exception!(
    rubsim,
    OutputError,
    RubsimError,
    "Results could not be written (the output directory, a file)."
);

/// Adds the exception classes to the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("RubsimError", py.get_type::<RubsimError>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add("MeshError", py.get_type::<MeshError>())?;
    m.add("SolveError", py.get_type::<SolveError>())?;
    m.add("StudyError", py.get_type::<StudyError>())?;
    m.add("OutputError", py.get_type::<OutputError>())?;
    Ok(())
}

/// Where an error happened inside a study: the speed and the case, outermost first.
#[derive(Default)]
struct Place {
    speed_ratio: Option<f64>,
    case: Option<String>,
}

/// The error under the study's and the context's wrappers, with where it happened.
fn innermost<'e>(e: &'e Error, place: &mut Place) -> &'e Error {
    match e {
        Error::AtSpeed {
            speed_ratio,
            source,
        } => {
            place.speed_ratio.get_or_insert(*speed_ratio);
            innermost(source, place)
        }
        Error::AtCase { id, source } => {
            place.case.get_or_insert_with(|| id.clone());
            innermost(source, place)
        }
        Error::Context { cause, .. } => innermost(cause, place),
        _ => e,
    }
}

/// The 1-based line a TOML parser's message names (`… at line 3, column 5`), if any.
fn line_in(message: &str) -> Option<usize> {
    let rest = &message[message.find("line ")? + 5..];
    let digits: String = rest.chars().take_while(char::is_ascii_digit).collect();
    digits.parse().ok()
}

/// The scene error's file, key and line.
fn scene_place(e: &SceneInput) -> (Option<String>, Option<String>, Option<usize>) {
    match e {
        SceneInput::Read { file, .. } => (Some(file.display().to_string()), None, None),
        SceneInput::Parse { file, message } => {
            let key = message
                .split('`')
                .nth(1)
                .filter(|_| message.contains("unknown field") || message.contains("missing field"))
                .map(str::to_string);
            (Some(file.display().to_string()), key, line_in(message))
        }
        SceneInput::Invalid {
            file, key, line, ..
        } => (Some(file.display().to_string()), Some(key.clone()), *line),
        SceneInput::Override { assignment, .. } => (
            None,
            assignment
                .split_once('=')
                .map(|(k, _)| k.trim().to_string()),
            None,
        ),
    }
}

/// The Python exception of a rubsim error: its class by kind, its message the error's whole
/// text, its attributes where it happened.
pub fn to_py(e: Error) -> PyErr {
    let message = e.to_string();
    let mut place = Place::default();
    let inner = innermost(&e, &mut place);
    let mut attrs: Vec<(&str, Option<String>, Option<usize>)> = Vec::new();
    let err = match inner {
        Error::Scene(s) => {
            let (file, key, line) = scene_place(s);
            attrs.push(("file", file, None));
            attrs.push(("key", key, None));
            attrs.push(("line", None, line));
            SceneError::new_err(message)
        }
        Error::Model(_) => ModelError::new_err(message),
        Error::Mesh(_) => MeshError::new_err(message),
        Error::Solve(_) => SolveError::new_err(message),
        Error::Output { .. } => OutputError::new_err(message),
        _ => StudyError::new_err(message),
    };
    Python::attach(|py| {
        let v = err.value(py);
        for (name, text, number) in attrs {
            let _ = match (text, number) {
                (Some(t), _) => v.setattr(name, t),
                (None, Some(n)) => v.setattr(name, n),
                (None, None) => v.setattr(name, py.None()),
            };
        }
        let _ = v.setattr("speed_ratio", place.speed_ratio);
        let _ = v.setattr("case", place.case);
    });
    err
}

/// A scene error naming `key` (a value given from Python that has no TOML form, a NaN).
pub fn scene_key(file: &str, key: &str, message: &str) -> PyErr {
    let err = SceneError::new_err(format!("{file}: key `{key}`: {message}"));
    Python::attach(|py| {
        let v = err.value(py);
        let _ = v.setattr("file", file);
        let _ = v.setattr("key", key);
        let _ = v.setattr("line", py.None());
    });
    err
}

/// Converts a rubsim result into a Python one.
pub trait IntoPy<T> {
    /// The value, or the error as its Python exception ([`to_py`]).
    fn py_err(self) -> PyResult<T>;
}

impl<T, E: Into<Error>> IntoPy<T> for Result<T, E> {
    fn py_err(self) -> PyResult<T> {
        self.map_err(|e| to_py(e.into()))
    }
}
