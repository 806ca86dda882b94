//! Python arguments to Rust values. A value of the wrong type is refused as the command
//! line refuses an argument it cannot parse ([`crate::commands::Error::Argument`], named by the
//! command line's flag, with the value and its type); a value of the right type then meets
//! the same rule, with the same message, as that flag's value.

use crate::analysis::limits::{ParamError, Quantity, Rule};
use crate::commands::Error;
use numpy::{PyUntypedArray, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyByteArray, PyBytes, PyDict, PyFloat, PyMemoryView, PyString};
use std::path::PathBuf;

/// The longest value shown in a message (its repr, cut with `…`).
const SHOWN: usize = 80;

/// A refusal of `value` for `argument`, which expected `what`: the value as Python shows
/// it (on one line, cut to [`SHOWN`] characters) and its type (an array's with its
/// dimensions and dtype).
pub(crate) fn wrong(argument: &str, what: &str, value: &Bound<'_, PyAny>) -> Error {
    let repr = value.repr().map(|r| r.to_string()).unwrap_or_else(|_| "?".into());
    let mut shown = repr.lines().map(str::trim_start).collect::<Vec<_>>().join(" ");
    if shown.chars().count() > SHOWN {
        shown = shown.chars().take(SHOWN - 1).collect::<String>() + "…";
    }
    Error::Argument {
        argument: argument.into(),
        message: format!("expected {what}, got {shown} ({})", type_name(value)),
    }
}

/// The type's name; for a numpy array also its dimensions and dtype (`1-D ndarray of
/// complex128`, `1-D MaskedArray of float64`).
fn type_name(value: &Bound<'_, PyAny>) -> String {
    let name = value.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into());
    match value.cast::<PyUntypedArray>() {
        Ok(a) => {
            let dtype = a.dtype().str().map(|s| s.to_string()).unwrap_or_else(|_| "?".into());
            format!("{}-D {name} of {dtype}", a.ndim())
        }
        Err(_) => name,
    }
}

/// Bytes-like values (bytes, bytearray, memoryview): never numbers, though they iterate as
/// small whole numbers.
fn is_bytes(value: &Bound<'_, PyAny>) -> bool {
    value.is_instance_of::<PyBytes>() || value.is_instance_of::<PyByteArray>() || value.is_instance_of::<PyMemoryView>()
}

/// A real number (int or float, numpy scalars included; not a bool or a string).
pub(crate) fn number(value: &Bound<'_, PyAny>, argument: &str) -> Result<f64, Error> {
    if value.is_instance_of::<PyBool>() || value.is_instance_of::<PyString>() {
        return Err(wrong(argument, "a number", value));
    }
    value.extract::<f64>().map_err(|_| wrong(argument, "a number", value))
}

/// An optional real number: `None` is absent.
pub(crate) fn optional_number(value: Option<&Bound<'_, PyAny>>, argument: &str) -> Result<Option<f64>, Error> {
    match value {
        Some(v) if !v.is_none() => number(v, argument).map(Some),
        _ => Ok(None),
    }
}

/// A whole number ≥ 0 (a negative one breaks the count rule `min..=max`, as the command
/// line's count of that value would).
pub(crate) fn count(value: &Bound<'_, PyAny>, argument: &str, min: u64, max: u64) -> Result<usize, Error> {
    if value.is_instance_of::<PyBool>() {
        return Err(wrong(argument, "a whole number", value));
    }
    let n: i128 = value.extract().map_err(|_| wrong(argument, "a whole number", value))?;
    if n < min as i128 || n > max as i128 {
        let e = ParamError { quantity: Quantity::Count, value: n as f64, rule: Rule::Count { min, max } };
        return Err(Error::parameter(argument, &e));
    }
    usize::try_from(n).map_err(|_| wrong(argument, "a whole number", value))
}

/// A sequence of real numbers (a list, a tuple, a 1-D numpy array, a range).
pub(crate) fn numbers(value: &Bound<'_, PyAny>, argument: &str) -> Result<Vec<f64>, Error> {
    if value.is_instance_of::<PyString>() || value.is_instance_of::<PyDict>() {
        return Err(wrong(argument, "a sequence of numbers", value));
    }
    if let Ok(v) = value.extract::<numpy::PyReadonlyArray1<'_, f64>>() {
        if let Ok(s) = v.as_slice() {
            return Ok(s.to_vec());
        }
    }
    let iter = value.try_iter().map_err(|_| wrong(argument, "a sequence of numbers", value))?;
    let mut out = Vec::new();
    for item in iter {
        let item = item.map_err(|_| wrong(argument, "a sequence of numbers", value))?;
        out.push(number(&item, argument)?);
    }
    Ok(out)
}

/// A sequence of shaft node indices (whole numbers ≥ 0).
pub(crate) fn nodes(value: &Bound<'_, PyAny>, argument: &str) -> Result<Vec<usize>, Error> {
    let bad = || wrong(argument, "a sequence of node indices (e.g. [3, 16])", value);
    if value.is_instance_of::<PyString>() || value.is_instance_of::<PyDict>() {
        return Err(bad());
    }
    let iter = value.try_iter().map_err(|_| bad())?;
    let mut out = Vec::new();
    for item in iter {
        let item = item.map_err(|_| bad())?;
        if item.is_instance_of::<PyBool>() {
            return Err(bad());
        }
        let n: i128 = item.extract().map_err(|_| bad())?;
        let n = usize::try_from(n).map_err(|_| Error::Argument {
            argument: argument.into(),
            message: format!("`{n}` is not a node index (expected e.g. 3,16)"),
        })?;
        out.push(n);
    }
    Ok(out)
}

/// A path: a str or an `os.PathLike` giving one (not bytes, not a number).
pub(crate) fn path(value: &Bound<'_, PyAny>, argument: &str) -> Result<PathBuf, Error> {
    let what = "a path (str or os.PathLike)";
    if is_bytes(value) {
        return Err(wrong(argument, what, value));
    }
    value.extract::<PathBuf>().map_err(|_| wrong(argument, what, value))
}

/// An optional path: `None` is absent.
pub(crate) fn optional_path(value: Option<&Bound<'_, PyAny>>, argument: &str) -> Result<Option<PathBuf>, Error> {
    value.filter(|v| !v.is_none()).map(|v| path(v, argument)).transpose()
}

/// A switch: `True` or `False` (numpy's bools too), not a number or a string.
pub(crate) fn switch(value: &Bound<'_, PyAny>, argument: &str) -> Result<bool, Error> {
    value.extract::<bool>().map_err(|_| wrong(argument, "True or False", value))
}

/// A string.
pub(crate) fn text(value: &Bound<'_, PyAny>, argument: &str, what: &str) -> Result<String, Error> {
    value.extract::<String>().map_err(|_| wrong(argument, what, value))
}

/// `--set` overrides from a dict `{"key.path": value}` (values written as TOML: numbers,
/// bools, strings, lists) or a sequence of `"key.path=value"` strings.
pub(crate) fn overrides(value: Option<&Bound<'_, PyAny>>) -> Result<Vec<String>, Error> {
    let Some(value) = value.filter(|v| !v.is_none()) else { return Ok(Vec::new()) };
    let bad = |v: &Bound<'_, PyAny>| wrong("--set", "a dict {\"key.path\": value} or a list of \"key.path=value\"", v);
    if let Ok(dict) = value.cast::<PyDict>() {
        let mut out = Vec::new();
        for (k, v) in dict.iter() {
            let key: String = k.extract().map_err(|_| bad(&k))?;
            out.push(format!("{key}={}", toml_value(&v).ok_or_else(|| bad(&v))?));
        }
        return Ok(out);
    }
    if value.is_instance_of::<PyString>() {
        return Err(bad(value));
    }
    let iter = value.try_iter().map_err(|_| bad(value))?;
    let mut out = Vec::new();
    for item in iter {
        let item = item.map_err(|_| bad(value))?;
        out.push(item.extract::<String>().map_err(|_| bad(&item))?);
    }
    Ok(out)
}

/// A Python value as TOML text (the form `--set` takes), if it has one.
fn toml_value(v: &Bound<'_, PyAny>) -> Option<String> {
    Some(python_to_toml(v)?.to_string())
}

/// A Python value as a TOML value: bool, int, float, str, list, dict.
pub(crate) fn python_to_toml(v: &Bound<'_, PyAny>) -> Option<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Some(toml::Value::Boolean(v.extract().ok()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Some(toml::Value::Float(v.extract().ok()?));
    }
    // Whole numbers (int, numpy integers: anything with __index__; a float has none).
    if let Ok(i) = v.extract::<i64>() {
        return Some(toml::Value::Integer(i));
    }
    if v.is_instance_of::<PyString>() {
        return Some(toml::Value::String(v.extract().ok()?));
    }
    if let Ok(dict) = v.cast::<PyDict>() {
        let mut t = toml::Table::new();
        for (k, x) in dict.iter() {
            t.insert(k.extract().ok()?, python_to_toml(&x)?);
        }
        return Some(toml::Value::Table(t));
    }
    if let Ok(f) = v.extract::<f64>() {
        return Some(toml::Value::Float(f));
    }
    let iter = v.try_iter().ok()?;
    let mut list = Vec::new();
    for item in iter {
        list.push(python_to_toml(&item.ok()?)?);
    }
    Some(toml::Value::Array(list))
}
