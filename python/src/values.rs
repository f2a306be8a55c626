//! Python values as TOML: a scene given as a dict, and the values of overrides. Each value is
//! checked where it stands, so an error names its dotted key: `None` (TOML has no null), a
//! NaN or an infinity (no scene key takes one), an integer beyond 64 bits, a key that is not a
//! string, an object of another type.

use crate::errors::scene_key;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// `key.sub` or `sub` at the top.
fn join(key: &str, sub: &str) -> String {
    if key.is_empty() {
        sub.to_string()
    } else {
        format!("{key}.{sub}")
    }
}

/// The TOML value of `obj`, which stands at the dotted `key` of the scene `file` (for errors).
///
/// # Errors
/// A `SceneError` naming the key for `None`, a NaN or infinity and an integer beyond i64; a
/// `TypeError` naming it for an object of no TOML type.
pub fn to_toml(obj: &Bound<'_, PyAny>, file: &str, key: &str) -> PyResult<toml::Value> {
    if obj.is_none() {
        return Err(scene_key(
            file,
            key,
            "None has no TOML form; leave the key out to take its default",
        ));
    }
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(obj.extract()?));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(obj.extract()?));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, v) in d.iter() {
            let k: String = k.extract().map_err(|_| {
                PyTypeError::new_err(format!(
                    "{file}: a key under `{key}` is not a string: {k:?}"
                ))
            })?;
            let sub = join(key, &k);
            t.insert(k, to_toml(&v, file, &sub)?);
        }
        return Ok(toml::Value::Table(t));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() || is_array(obj) {
        let mut a = Vec::new();
        for (i, v) in obj.try_iter()?.enumerate() {
            a.push(to_toml(&v?, file, &join(key, &i.to_string()))?);
        }
        return Ok(toml::Value::Array(a));
    }
    if is_integer(obj) {
        return match obj.extract::<i64>() {
            Ok(i) => Ok(toml::Value::Integer(i)),
            Err(_) => Err(scene_key(file, key, "an integer beyond 64 bits")),
        };
    }
    match obj.extract::<f64>() {
        Ok(x) if x.is_finite() => Ok(toml::Value::Float(x)),
        Ok(x) => Err(scene_key(
            file,
            key,
            &format!("{x} is not a finite number (a scene value must be finite)"),
        )),
        Err(_) => Err(PyTypeError::new_err(format!(
            "{file}: key `{key}`: a {} has no TOML form (give a number, bool, string, list or dict)",
            obj.get_type().name()?
        ))),
    }
}

/// An integer: a Python int or a numpy integer (anything with `__index__` that is not a
/// float).
fn is_integer(obj: &Bound<'_, PyAny>) -> bool {
    obj.is_instance_of::<PyInt>()
        || (!obj.is_instance_of::<PyFloat>() && obj.hasattr("__index__").unwrap_or(false))
}

/// A numpy array (anything with `tolist` and `ndim`), taken as a list.
fn is_array(obj: &Bound<'_, PyAny>) -> bool {
    obj.hasattr("ndim").unwrap_or(false)
        && obj.hasattr("tolist").unwrap_or(false)
        && obj
            .getattr("ndim")
            .and_then(|n| n.extract::<usize>())
            .unwrap_or(0)
            > 0
}

/// The override `key=value` of a Python value (`--set`'s form: the value as TOML text).
///
/// # Errors
/// As [`to_toml`].
pub fn override_text(key: &str, value: &Bound<'_, PyAny>) -> PyResult<String> {
    let v = to_toml(value, "--set", key)?;
    Ok(format!("{key}={v}"))
}
