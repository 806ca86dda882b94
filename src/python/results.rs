//! Results as Python data. Each function takes a command's typed result (the value its
//! JSON document serialises) and returns the fields of its Python class
//! (python/rotorshunt/_results.py) as a dict: numpy arrays built from the typed values,
//! and the document itself (`json`) as dicts and lists made by pythonize from the value.
//! No JSON text on the way.

use crate::commands::{BandOutput, CampbellJson, ModesOutput, RegionsJson, UnbalanceJson};
use crate::design::DesignOutcome;
use numpy::ndarray::Array2;
use numpy::{Complex64, IntoPyArray, PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyFloat, PyList, PyTuple};
use serde::Serialize;
use std::collections::HashMap;

/// `value` as Python data in the JSON data model, as `json.loads` reads the command's JSON
/// text: pythonize's dicts, lists, strings, numbers and None, with its tuples (a
/// `[f64; 2]`, a pair) as lists and the non-finite numbers, which JSON writes as null, as
/// None.
pub(crate) fn json<'py, T: Serialize + ?Sized>(py: Python<'py>, value: &T) -> PyResult<Bound<'py, PyAny>> {
    json_model(pythonize::pythonize(py, value)?)
}

/// A JSON document (a struct's value) as a dict.
fn document<'py, T: Serialize + ?Sized>(py: Python<'py>, value: &T) -> PyResult<Bound<'py, PyDict>> {
    Ok(json(py, value)?.cast_into::<PyDict>()?)
}

/// Tuples as lists and non-finite floats as None, through dicts and lists.
fn json_model(value: Bound<'_, PyAny>) -> PyResult<Bound<'_, PyAny>> {
    let py = value.py();
    if let Ok(dict) = value.cast::<PyDict>() {
        let items: Vec<_> = dict.iter().collect();
        for (k, v) in items {
            dict.set_item(k, json_model(v)?)?;
        }
    } else if let Ok(list) = value.cast::<PyList>() {
        for i in 0..list.len() {
            list.set_item(i, json_model(list.get_item(i)?)?)?;
        }
    } else if let Ok(tuple) = value.cast::<PyTuple>() {
        let items = tuple.iter().map(json_model).collect::<PyResult<Vec<_>>>()?;
        return Ok(PyList::new(py, items)?.into_any());
    } else if value.cast::<PyFloat>().is_ok_and(|f| !f.value().is_finite()) {
        return Ok(py.None().into_bound(py));
    }
    Ok(value)
}

/// A key of a document: None when the document leaves it out.
fn key<'py>(doc: &Bound<'py, PyDict>, key: &str) -> PyResult<Bound<'py, PyAny>> {
    Ok(doc.get_item(key)?.unwrap_or_else(|| doc.py().None().into_bound(doc.py())))
}

/// Values as a numpy array of Python objects (an enum as its name in the JSON).
fn objects<'a, 'py, T: Serialize + 'a>(
    py: Python<'py>,
    values: impl Iterator<Item = &'a T>,
) -> PyResult<Bound<'py, PyArray1<Py<PyAny>>>> {
    let objects = values.map(|v| json(py, v).map(Bound::unbind)).collect::<PyResult<Vec<_>>>()?;
    Ok(PyArray1::from_vec(py, objects))
}

/// `modes`: the whirls' columns as arrays.
pub(crate) fn modes<'py>(py: Python<'py>, out: &ModesOutput) -> PyResult<Bound<'py, PyDict>> {
    let m = &out.modes;
    let floats =
        |f: fn(&crate::analysis::modes::WhirlMode) -> f64| m.iter().map(f).collect::<Vec<_>>().into_pyarray(py);
    let eigenvalues: Vec<Complex64> = m.iter().map(|x| Complex64::new(x.eigenvalue[0], x.eigenvalue[1])).collect();
    let d = PyDict::new(py);
    d.set_item("speed", out.speed)?;
    d.set_item("critical_load", out.critical_load)?;
    d.set_item("static_load", out.static_load)?;
    d.set_item("frequency", floats(|x| x.frequency))?;
    d.set_item("whirl", objects(py, m.iter().map(|x| &x.whirl))?)?;
    d.set_item("damping_ratio", floats(|x| x.damping_ratio))?;
    d.set_item("label", objects(py, m.iter().map(|x| &x.label))?)?;
    d.set_item("kind", objects(py, m.iter().map(|x| &x.kind))?)?;
    d.set_item("eigenvalue", eigenvalues.into_pyarray(py))?;
    d.set_item("json", document(py, out)?)?;
    Ok(d)
}

/// `campbell`: the tracks' frequencies and damping ratios as (track, speed) arrays, NaN
/// where a track has no point.
pub(crate) fn campbell<'py>(py: Python<'py>, doc: &CampbellJson) -> PyResult<Bound<'py, PyDict>> {
    let c = &doc.campbell;
    // A speed's column by its value (−0 as 0), the last of equal speeds.
    let bits = |w: f64| (w + 0.0).to_bits();
    let column: HashMap<u64, usize> = c.speeds.iter().enumerate().map(|(j, &w)| (bits(w), j)).collect();
    let shape = (c.tracks.len(), c.speeds.len());
    let mut frequency = Array2::from_elem(shape, f64::NAN);
    let mut damping = Array2::from_elem(shape, f64::NAN);
    for (i, t) in c.tracks.iter().enumerate() {
        for p in &t.points {
            if let Some(&j) = column.get(&bits(p.speed)) {
                frequency[(i, j)] = p.frequency;
                damping[(i, j)] = p.damping_ratio;
            }
        }
    }
    let data = document(py, doc)?;
    let d = PyDict::new(py);
    d.set_item("speeds", c.speeds.clone().into_pyarray(py))?;
    d.set_item("tags", c.tracks.iter().map(|t| t.tag.as_str()).collect::<Vec<_>>())?;
    d.set_item("whirl", c.tracks.iter().map(|t| json(py, &t.whirl)).collect::<PyResult<Vec<_>>>()?)?;
    d.set_item("frequency", frequency.into_pyarray(py))?;
    d.set_item("damping_ratio", damping.into_pyarray(py))?;
    d.set_item("operating_speeds", doc.operating_speeds.to_vec().into_pyarray(py))?;
    d.set_item("critical_speeds", key(&data, "critical_speeds")?)?;
    d.set_item("json", data)?;
    Ok(d)
}

/// `regions`: the catalogue's numbers and stable bands (an (n, 2) array); the regions
/// themselves are the document's.
pub(crate) fn regions<'py>(py: Python<'py>, doc: &RegionsJson) -> PyResult<Bound<'py, PyDict>> {
    let c = &doc.catalogue;
    let bands: Vec<f64> = c.stable_bands.iter().flat_map(|b| [b.lo, b.hi]).collect();
    let data = document(py, doc)?;
    let d = PyDict::new(py);
    d.set_item("speed", doc.speed)?;
    d.set_item("level", c.level)?;
    d.set_item("beta_max", c.beta_max)?;
    d.set_item("range", (c.range.lo, c.range.hi))?;
    d.set_item("stable_bands", bands.into_pyarray(py).reshape([c.stable_bands.len(), 2])?)?;
    d.set_item("band_margins", key(&data, "band_margins")?)?;
    d.set_item("unexplained", key(&data, "unexplained")?)?;
    d.set_item("evaluations", c.evaluations)?;
    d.set_item("json", data)?;
    Ok(d)
}

/// `band`: the band as (lo, hi), its bounds and margins.
pub(crate) fn band<'py>(py: Python<'py>, out: &BandOutput) -> PyResult<Bound<'py, PyDict>> {
    let b = &out.band;
    let data = document(py, out)?;
    let d = PyDict::new(py);
    d.set_item("phi_op", b.phi_op)?;
    d.set_item("level", b.level)?;
    d.set_item("band", b.band.map(|x| (x.lo, x.hi)))?;
    d.set_item("width", out.width)?;
    d.set_item("left", key(&data, "left")?)?;
    d.set_item("right", key(&data, "right")?)?;
    d.set_item("margins", key(&data, "margins")?)?;
    d.set_item("json", data)?;
    Ok(d)
}

/// `unbalance`: each probe's amplitude and phase over speed, and in real coordinates its
/// orbit's arrays.
pub(crate) fn unbalance<'py>(py: Python<'py>, doc: &UnbalanceJson<'_>) -> PyResult<Bound<'py, PyDict>> {
    let u = &doc.unbalance;
    let array = |v: &Vec<f64>| v.clone().into_pyarray(py);
    let probes = PyList::empty(py);
    for p in &u.probes {
        let orbit = match &p.orbit {
            Some(o) => {
                let orbit = PyDict::new(py);
                for (name, v) in [
                    ("x_amplitude", &o.x_amplitude),
                    ("x_phase", &o.x_phase),
                    ("y_amplitude", &o.y_amplitude),
                    ("y_phase", &o.y_phase),
                    ("major", &o.major),
                    ("minor", &o.minor),
                    ("forward", &o.forward),
                    ("backward", &o.backward),
                ] {
                    orbit.set_item(name, array(v))?;
                }
                Some(orbit)
            }
            None => None,
        };
        let probe = PyDict::new(py);
        probe.set_item("name", &p.probe.name)?;
        probe.set_item("kind", json(py, &p.probe.kind)?)?;
        probe.set_item("node", p.probe.node)?;
        probe.set_item("amplitude", array(&p.amplitude))?;
        probe.set_item("phase", array(&p.phase))?;
        probe.set_item("peaks", json(py, &p.peaks)?)?;
        probe.set_item("orbit", orbit)?;
        probes.append(probe)?;
    }
    let d = PyDict::new(py);
    d.set_item("speeds", array(&u.speeds))?;
    d.set_item("probes", probes)?;
    d.set_item("json", document(py, doc)?)?;
    Ok(d)
}

/// `design`: the outcome's status, variables (before and after, and their names) and the
/// outcome as report.json has it; `summary` and `tuned_toml` as given.
pub(crate) fn design<'py>(
    py: Python<'py>,
    outcome: &DesignOutcome,
    tuned_toml: String,
    summary: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let variables: Vec<String> =
        outcome.spec.variables.iter().map(|v| format!("branch {} {}", v.branch + 1, v.parameter.key())).collect();
    let d = PyDict::new(py);
    d.set_item("status", crate::commands::status_word(outcome.status))?;
    d.set_item("verified", outcome.verified())?;
    d.set_item("file_name", crate::commands::design_file_name(outcome.status))?;
    d.set_item("tuned_toml", tuned_toml)?;
    d.set_item("before", outcome.before.clone().into_pyarray(py))?;
    d.set_item("after", outcome.after.clone().into_pyarray(py))?;
    d.set_item("variables", variables)?;
    d.set_item("outcome", document(py, outcome)?)?;
    d.set_item("summary", summary)?;
    Ok(d)
}
