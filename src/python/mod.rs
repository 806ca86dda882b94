//! The Python bindings (`--features python`, built by maturin into the `rotorshunt` wheel;
//! docs/python.md). They only convert: every call is the command's checks and its job of
//! the application layer ([`crate::run::Run`]: the same checks, the same numbers and the
//! same error messages as the command line), its arguments taken from Python objects and
//! its typed results handed back as data ([`results`]): numpy arrays, and the command's
//! JSON document as dicts and lists made by pythonize from its `Serialize` value, which
//! the pure-Python part (python/rotorshunt) wraps into result objects with plots. No
//! physics here, and no JSON text.
//!
//! Long calls ([`watch`]) run on a worker thread with the GIL released; the calling
//! thread wakes every 50 ms to check Python's signals (Ctrl-C) and call the progress
//! callback, and a pending signal asks the library to stop through
//! [`crate::progress::Progress::cancelled`].

mod args;
mod problem;
mod results;
mod watch;

use pyo3::prelude::*;

pyo3::create_exception!(_rotorshunt, Error, pyo3::exceptions::PyException, "Any rotorshunt failure.");
pyo3::create_exception!(_rotorshunt, ProblemError, Error, "A problem file that is unreadable or invalid.");
pyo3::create_exception!(_rotorshunt, ArgumentError, Error, "An argument that breaks its rule.");
pyo3::create_exception!(_rotorshunt, CostError, Error, "A run beyond the cost limit: refused before it started, or stopped at its time limit or its allowance of evaluations.");
pyo3::create_exception!(_rotorshunt, AnalysisError, Error, "An analysis that failed on valid input.");
pyo3::create_exception!(_rotorshunt, DesignError, Error, "A design run that failed.");
pyo3::create_exception!(_rotorshunt, RossImportError, Error, "A ROSS rotor that cannot be imported.");
pyo3::create_exception!(_rotorshunt, StudyError, Error, "A study file, shard or study folder that is not valid.");
pyo3::create_exception!(_rotorshunt, OutputError, Error, "An output that cannot or may not be written.");

/// The Python exception of a crate error: the class of its kind, as message the error's
/// text (the paragraph the command line prints after `error: `), and as attribute `kind`
/// the kind's name as docs/errors.md heads its section (e.g. `NotPositive`).
pub(crate) fn to_py(e: crate::commands::Error) -> PyErr {
    let kind = e.kind();
    let err = class_of(e);
    Python::attach(|py| {
        // Setting an attribute on a new exception object cannot fail short of memory;
        // the exception is raised either way.
        let _ = err.value(py).setattr("kind", kind);
    });
    err
}

/// The exception class and message of a crate error.
fn class_of(e: crate::commands::Error) -> PyErr {
    use crate::commands::Error as E;
    let message = e.to_string();
    match e {
        E::Problem(_) => ProblemError::new_err(message),
        E::Ross(_) | E::Import(_) => RossImportError::new_err(message),
        E::Analysis(crate::analysis::AnalysisError::Request(_) | crate::analysis::AnalysisError::Settings(_)) => {
            ArgumentError::new_err(message)
        }
        E::Analysis(_) => AnalysisError::new_err(message),
        E::Design(_) => DesignError::new_err(message),
        E::Argument { .. } | E::Parameter { .. } => ArgumentError::new_err(message),
        E::Cost(_) | E::TimeLimit(_) | E::CountLimit(_) | E::Cancelled { .. } => CostError::new_err(message),
        E::Study { .. }
        | E::StudyTooLarge { .. }
        | E::Shard { .. }
        | E::PlanMismatch { .. }
        | E::NotAStudyFolder { .. }
        | E::SlurmMissing { .. }
        | E::SlurmValue { .. }
        | E::SlurmFailed { .. } => StudyError::new_err(message),
        E::Output { .. }
        | E::Unsafe { .. }
        | E::OutputIsInput { .. }
        | E::OutIsNotAFolder { .. }
        | E::OutputExists { .. }
        | E::FolderNotEmpty { .. }
        | E::NotOwned { .. }
        | E::OtherStudy { .. }
        | E::StudyLocked { .. } => OutputError::new_err(message),
    }
}

/// numpy's array API, loaded at import. rust-numpy loads it at the first array made, and
/// that loading runs Python code (numpy's version check), where a pending Ctrl-C raises:
/// rust-numpy then panics (issue 50: a SIGINT during the first `floquet` call gave a
/// `PanicException`). Here a signal already pending raises from the import; one arriving
/// during the loading itself (a window of microseconds) fails the import with an
/// `ImportError` instead of a panic.
fn load_numpy_api(py: Python<'_>) -> PyResult<()> {
    py.check_signals()?;
    let loaded = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        numpy::PyUntypedArrayMethods::len(&numpy::PyArray1::<f64>::zeros(py, 0, false))
    }));
    match loaded {
        Ok(_) => Ok(()),
        Err(payload) => {
            let text = watch::panic_text(payload.as_ref());
            Err(pyo3::exceptions::PyImportError::new_err(format!("numpy's array API could not be loaded: {text}")))
        }
    }
}

/// For the pure-Python part's own checks (python/rotorshunt): the `ArgumentError` of
/// `argument`, which expected `expected` and was given `value`, worded as the native
/// calls word theirs (not raised: returned, for Python to raise).
#[pyfunction]
fn _argument_error(argument: &str, expected: &str, value: &Bound<'_, PyAny>) -> Py<PyAny> {
    to_py(args::wrong(argument, expected, value)).into_value(value.py()).into_any()
}

/// The native module `rotorshunt._rotorshunt`.
#[pymodule]
fn _rotorshunt(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    load_numpy_api(py)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("Error", py.get_type::<Error>())?;
    m.add("ProblemError", py.get_type::<ProblemError>())?;
    m.add("ArgumentError", py.get_type::<ArgumentError>())?;
    m.add("CostError", py.get_type::<CostError>())?;
    m.add("AnalysisError", py.get_type::<AnalysisError>())?;
    m.add("DesignError", py.get_type::<DesignError>())?;
    m.add("RossImportError", py.get_type::<RossImportError>())?;
    m.add("StudyError", py.get_type::<StudyError>())?;
    m.add("OutputError", py.get_type::<OutputError>())?;
    m.add_class::<problem::NativeProblem>()?;
    m.add_function(wrap_pyfunction!(problem::import_ross, m)?)?;
    m.add_function(wrap_pyfunction!(problem::run_study, m)?)?;
    m.add_function(wrap_pyfunction!(problem::rayon_threads, m)?)?;
    m.add_function(wrap_pyfunction!(problem::_rust_floquet_seconds, m)?)?;
    m.add_function(wrap_pyfunction!(_argument_error, m)?)?;
    Ok(())
}
