//! Python arguments to Rust values. A value of the wrong type is refused as the command
//! line refuses an argument it cannot parse ([`crate::commands::Error::Argument`], named by the
//! command line's flag, with the value and its type); a value of the right type then meets
//! the same rule, with the same message, as that flag's value.
//!
//! A real number is a Python int or float or a numpy integer or float (a 0-d array
//! included); a bool, a complex number, a string or bytes is not one, so a complex array
//! is refused rather than cut to its real part, and bytes are not read as small numbers
//! (issue 50). A masked array is refused whole: its masked entries hold values nobody
//! meant, and which entries count is the caller's choice (`a.compressed()`, `a.filled(x)`).

use crate::analysis::limits::{ParamError, Quantity, Rule};
use crate::commands::Error;
use numpy::{PyArrayDescrMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::intern;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyByteArray, PyBytes, PyComplex, PyDict, PyFloat, PyInt, PyMemoryView, PyString};
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

/// A numpy value's dtype kind (`f`, `i`, `u`, `c`, `b`, `O`, …): an array's, or a numpy
/// scalar's; `None` for anything else.
fn numpy_kind(value: &Bound<'_, PyAny>) -> Option<u8> {
    if let Ok(a) = value.cast::<PyUntypedArray>() {
        return Some(a.dtype().kind());
    }
    let dtype = value.getattr(intern!(value.py(), "dtype")).ok()?;
    dtype.cast::<numpy::PyArrayDescr>().ok().map(|d| d.kind())
}

/// A numpy masked array (or its `masked` constant): an array with a mask.
fn is_masked(value: &Bound<'_, PyAny>) -> bool {
    value.cast::<PyUntypedArray>().is_ok() && value.hasattr(intern!(value.py(), "mask")).unwrap_or(false)
}

/// Bytes-like values (bytes, bytearray, memoryview): never numbers, though they iterate as
/// small whole numbers.
fn is_bytes(value: &Bound<'_, PyAny>) -> bool {
    value.is_instance_of::<PyBytes>() || value.is_instance_of::<PyByteArray>() || value.is_instance_of::<PyMemoryView>()
}

/// Whether `value` may be read as a real number: not a bool, string, bytes or complex
/// number, not an array other than a 0-d one, and of numpy's kinds only an integer or a
/// float.
fn is_real(value: &Bound<'_, PyAny>) -> bool {
    if value.is_instance_of::<PyBool>()
        || value.is_instance_of::<PyString>()
        || value.is_instance_of::<PyComplex>()
        || is_bytes(value)
        || is_masked(value)
    {
        return false;
    }
    if let Ok(a) = value.cast::<PyUntypedArray>() {
        if a.ndim() != 0 {
            return false;
        }
    }
    numpy_kind(value).is_none_or(|k| matches!(k, b'f' | b'i' | b'u'))
}

/// A real number (int or float, numpy scalars included; not a bool, a complex number or a
/// string).
pub(crate) fn number(value: &Bound<'_, PyAny>, argument: &str) -> Result<f64, Error> {
    let plain = value.is_exact_instance_of::<PyFloat>() || value.is_exact_instance_of::<PyInt>();
    if !plain && !is_real(value) {
        return Err(wrong(argument, "a real number", value));
    }
    value.extract::<f64>().map_err(|_| wrong(argument, "a real number", value))
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
    if !is_whole(value) {
        return Err(wrong(argument, "a whole number", value));
    }
    let n: i128 = value.extract().map_err(|_| wrong(argument, "a whole number", value))?;
    if n < min as i128 || n > max as i128 {
        let e = ParamError { quantity: Quantity::Count, value: n as f64, rule: Rule::Count { min, max } };
        return Err(Error::parameter(argument, &e));
    }
    usize::try_from(n).map_err(|_| wrong(argument, "a whole number", value))
}

/// Whether `value` may be read as a whole number: a real number ([`is_real`]) of an
/// integer type (a float, even 3.0, has no `__index__` and is then refused by the
/// extraction).
fn is_whole(value: &Bound<'_, PyAny>) -> bool {
    value.is_exact_instance_of::<PyInt>()
        || (is_real(value) && numpy_kind(value).is_none_or(|k| matches!(k, b'i' | b'u')))
}

/// Refuse what iterates but is no sequence of numbers: a string, a dict, bytes (which
/// would read as small whole numbers), a masked array, an array other than a 1-D one, and
/// an array of another kind than `kinds` (or of objects, whose entries are checked one by one).
fn sequence_of<'py>(value: &Bound<'py, PyAny>, argument: &str, what: &str, kinds: &[u8]) -> Result<(), Error> {
    if is_masked(value) {
        let what = format!("{what}, not a masked array (give `a.compressed()` or `a.filled(value)`)");
        return Err(wrong(argument, &what, value));
    }
    if value.is_instance_of::<PyString>() || value.is_instance_of::<PyDict>() || is_bytes(value) {
        return Err(wrong(argument, what, value));
    }
    if let Ok(a) = value.cast::<PyUntypedArray>() {
        let kind = a.dtype().kind();
        if a.ndim() != 1 || !(kinds.contains(&kind) || kind == b'O') {
            return Err(wrong(argument, what, value));
        }
    }
    Ok(())
}

/// A sequence of real numbers (a list, a tuple, a 1-D numpy array of integers or floats, a
/// range).
pub(crate) fn numbers(value: &Bound<'_, PyAny>, argument: &str) -> Result<Vec<f64>, Error> {
    let what = "a sequence of real numbers";
    sequence_of(value, argument, what, b"fiu")?;
    if let Ok(v) = value.extract::<numpy::PyReadonlyArray1<'_, f64>>() {
        if let Ok(s) = v.as_slice() {
            return Ok(s.to_vec());
        }
    }
    let iter = value.try_iter().map_err(|_| wrong(argument, what, value))?;
    let mut out = Vec::new();
    for item in iter {
        let item = item.map_err(|_| wrong(argument, what, value))?;
        out.push(number(&item, argument)?);
    }
    Ok(out)
}

/// A sequence of shaft node indices (whole numbers ≥ 0).
pub(crate) fn nodes(value: &Bound<'_, PyAny>, argument: &str) -> Result<Vec<usize>, Error> {
    let what = "a sequence of node indices (e.g. [3, 16])";
    let bad = || wrong(argument, what, value);
    sequence_of(value, argument, what, b"iu")?;
    let iter = value.try_iter().map_err(|_| bad())?;
    let mut out = Vec::new();
    for item in iter {
        let item = item.map_err(|_| bad())?;
        if !is_whole(&item) {
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
    if value.is_instance_of::<PyString>() || is_bytes(value) || is_masked(value) {
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

/// A Python value as a TOML value: bool, int, float, str, list, dict; none for bytes, a
/// complex number or a masked array (whose entries are not what they show).
pub(crate) fn python_to_toml(v: &Bound<'_, PyAny>) -> Option<toml::Value> {
    if v.is_instance_of::<PyBool>() {
        return Some(toml::Value::Boolean(v.extract().ok()?));
    }
    if v.is_instance_of::<PyFloat>() {
        return Some(toml::Value::Float(v.extract().ok()?));
    }
    if v.is_instance_of::<PyComplex>() || is_bytes(v) || is_masked(v) || numpy_kind(v) == Some(b'c') {
        return None;
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

/// `rings` of `from_ross`: a list (or tuple) of dicts, the `[[rings]]` tables, each as
/// TOML. An empty list is no rings.
pub(crate) fn rings(value: &Bound<'_, PyAny>) -> Result<Vec<toml::Value>, Error> {
    let what = "a list of dicts (the [[rings]] tables)";
    if value.is_instance_of::<PyString>() || value.is_instance_of::<PyDict>() || is_bytes(value) || is_masked(value) {
        return Err(wrong("rings", what, value));
    }
    let iter = value.try_iter().map_err(|_| wrong("rings", what, value))?;
    let mut out = Vec::new();
    for (i, item) in iter.enumerate() {
        let item = item.map_err(|_| wrong("rings", what, value))?;
        if !item.is_instance_of::<PyDict>() {
            return Err(wrong("rings", &format!("a dict (a [[rings]] table) as entry {}", i + 1), &item));
        }
        let table = python_to_toml(&item).ok_or_else(|| {
            let what = format!("a dict of numbers, strings, bools, lists and dicts as entry {}", i + 1);
            wrong("rings", &what, &item)
        })?;
        out.push(table);
    }
    Ok(out)
}
