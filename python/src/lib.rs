//! `rubsim._rubsim`: the native module of the `rubsim` Python package (python/rubsim/ is its
//! Python side, which most users call). It holds a scene ([`scene::NativeScene`]: a TOML file
//! or text with its overrides, validated, and the model built from it once) and runs it through
//! the rubsim library as the command line does — one speed, a speed transient, a sweep, a map,
//! the rotor's modes — with the GIL released while rubsim computes. Results come back as numpy
//! arrays (orbits, spectra, histories) and JSON text (summaries, which the Python side reads
//! into dicts); errors as the Python exceptions of [`errors`], naming the file, key and line.
//!
//! Units and conventions are rubsim's (SI; rotor axis z, Ω > 0 counter-clockwise seen from +z;
//! `_nd` values over |Z0(ω)|, |U|ω² or ω_n: docs/OUTPUTS.md).

use pyo3::prelude::*;

mod errors;
mod progress;
mod runs;
mod scene;
mod studies;
mod values;

/// The module: the scene class, the ROSS import and the exception classes.
#[pymodule]
fn _rubsim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scene::NativeScene>()?;
    m.add_function(wrap_pyfunction!(scene::import_ross, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)
}
