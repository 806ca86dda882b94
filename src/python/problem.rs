//! The native problem object and the module's functions. Each method is one job of a
//! [`Run`]: the arguments converted ([`super::args`]) and checked as the command checks
//! them, the job run with the GIL released ([`super::watch`]), the typed result handed
//! back as a dict of numpy arrays and Python data ([`super::results`]).

use super::args;
use super::results;
use super::watch::{released, watched};
use crate::analysis::floquet::{FloquetSystem, PointStatus};
use crate::analysis::limits::MAX_COUNT;
use crate::commands;
use crate::commands::Error;
use crate::problem::Problem;
use crate::progress::Silent;
use crate::run::{Budget, PointRun, Run};
use numpy::{Complex64, IntoPyArray, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::OnceLock;

/// A loaded, validated problem (`rotorshunt.Problem` wraps it). Immutable: overrides
/// give a new one. Its reduced system is built once, at the first Floquet call.
#[pyclass(name = "NativeProblem", module = "rotorshunt._rotorshunt", frozen)]
pub(crate) struct NativeProblem {
    problem: Problem,
    system: OnceLock<FloquetSystem>,
}

impl NativeProblem {
    fn new(problem: Problem) -> NativeProblem {
        NativeProblem { problem, system: OnceLock::new() }
    }

    /// The reduced system at the problem's speed, built (and admitted) at the first call.
    fn system(&self) -> Result<&FloquetSystem, Error> {
        if let Some(fs) = self.system.get() {
            return Ok(fs);
        }
        let top = crate::analysis::DEFAULT_BAND_RANGE.hi;
        let fs = Run::new(&Silent).reduced_system(&self.problem, top)?;
        Ok(self.system.get_or_init(|| fs))
    }
}

/// An optional progress callback: `None` or Python's `None` is none; anything else must be
/// callable.
fn callback<'a, 'py>(progress: Option<&'a Bound<'py, PyAny>>) -> PyResult<Option<&'a Bound<'py, PyAny>>> {
    match progress.filter(|p| !p.is_none()) {
        Some(p) if !p.is_callable() => {
            Err(super::to_py(args::wrong("progress", "None or a callable (phase, done, total)", p)))
        }
        p => Ok(p),
    }
}

#[pymethods]
impl NativeProblem {
    /// Load a problem file and apply `set` overrides.
    #[staticmethod]
    #[pyo3(signature = (path, set = None))]
    fn from_file(py: Python<'_>, path: &Bound<'_, PyAny>, set: Option<&Bound<'_, PyAny>>) -> PyResult<NativeProblem> {
        let path = args::path(path, "FILE").map_err(super::to_py)?;
        let overrides = args::overrides(set).map_err(super::to_py)?;
        released(py, || Ok(Problem::from_path(&path, &overrides)?)).map(NativeProblem::new)
    }

    /// Parse a problem text; `name` names it in messages.
    #[staticmethod]
    #[pyo3(signature = (text, name = None, set = None))]
    fn from_toml(
        py: Python<'_>,
        text: &Bound<'_, PyAny>,
        name: Option<&Bound<'_, PyAny>>,
        set: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<NativeProblem> {
        let text = args::text(text, "text", "the problem's TOML text (str)").map_err(super::to_py)?;
        let name = match name.filter(|n| !n.is_none()) {
            Some(n) => args::text(n, "name", "a name for messages (str)").map_err(super::to_py)?,
            None => "<string>".into(),
        };
        let overrides = args::overrides(set).map_err(super::to_py)?;
        released(py, || Ok(Problem::from_text(&text, &name, &overrides)?)).map(NativeProblem::new)
    }

    /// A copy with more overrides, applied after this problem's own.
    fn with_set(&self, py: Python<'_>, set: &Bound<'_, PyAny>) -> PyResult<NativeProblem> {
        let mut overrides = self.problem.overrides.clone();
        overrides.extend(args::overrides(Some(set)).map_err(super::to_py)?);
        let p = &self.problem;
        released(py, || Ok(Problem::from_text(&p.text, &p.file, &overrides)?)).map(NativeProblem::new)
    }

    /// The problem's data, overrides applied, as TOML text (speeds in rad/s).
    fn to_toml(&self) -> PyResult<String> {
        toml::to_string(&self.problem.data).map_err(|e| {
            super::to_py(Error::Output { path: self.problem.file.clone(), message: format!("as TOML: {e}") })
        })
    }

    /// The file name as given.
    #[getter]
    fn file(&self) -> String {
        self.problem.file.clone()
    }

    /// The title (the file name when it has none).
    #[getter]
    fn title(&self) -> String {
        self.problem.data.title.clone().unwrap_or_else(|| self.problem.file.clone())
    }

    /// The overrides applied, as `key.path=value`.
    #[getter]
    fn overrides(&self) -> Vec<String> {
        self.problem.overrides.clone()
    }

    /// The plausibility warnings, one line each (the command line prints them after `warning: `).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.problem.warnings.iter().map(|w| w.to_string()).collect()
    }

    /// The operating speed Ω (rad/s).
    #[getter]
    fn speed(&self) -> f64 {
        self.problem.model.speed
    }

    /// SHA-256 of the text and overrides.
    #[getter]
    fn input_sha256(&self) -> String {
        self.problem.input_sha256.clone()
    }

    /// Whether the file has a `[design]` table.
    #[getter]
    fn has_design(&self) -> bool {
        self.problem.design.is_some()
    }

    /// `check`: the model summary text.
    fn check(&self, py: Python<'_>) -> PyResult<String> {
        let p = &self.problem;
        released(py, || Ok(commands::check_text(p, &Run::new(&Silent).check(p)?)))
    }

    /// `modes --json`: the whirls as arrays, and the document.
    #[pyo3(signature = (speed = None, count = None))]
    fn modes<'py>(
        &self,
        py: Python<'py>,
        speed: Option<&Bound<'py, PyAny>>,
        count: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let speed = args::optional_number(speed, "--speed").map_err(super::to_py)?;
        let count = whirl_count(count)?;
        let p = &self.problem;
        let out = released(py, || {
            let speed = commands::modes_speed(p, speed, count)?;
            let r = Run::new(&Silent).modes(p, speed, count)?;
            Ok(commands::modes_output(p, speed, count, &r))
        })?;
        results::modes(py, &out)
    }

    /// `campbell`: the tracks as (track, speed) arrays, and campbell.json's document.
    #[pyo3(signature = (speeds, count = None, progress = None))]
    fn campbell<'py>(
        &self,
        py: Python<'py>,
        speeds: &Bound<'py, PyAny>,
        count: Option<&Bound<'py, PyAny>>,
        progress: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let speeds = args::numbers(speeds, "--speeds").map_err(super::to_py)?;
        let count = whirl_count(count)?;
        let p = &self.problem;
        let doc = watched(py, callback(progress)?, |pr| {
            commands::campbell_speeds(&speeds)?;
            let r = Run::new(pr).campbell(p, &speeds, count)?.run()?;
            Ok(commands::campbell_output(p, r))
        })?;
        results::campbell(py, &doc)
    }

    /// `floquet`: the point at (φ, β) as a dict, the multipliers a complex array.
    fn floquet<'py>(
        &self,
        py: Python<'py>,
        phi: &Bound<'py, PyAny>,
        beta: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let phi = args::number(phi, "--phi").map_err(super::to_py)?;
        let beta = args::number(beta, "--beta").map_err(super::to_py)?;
        let sized = released(py, || point(&self.problem, phi, beta))?;
        let (speed, point, basis) = (sized.system.speed, sized.answer, sized.basis);
        let scale = point.multiplier_log_scale.exp();
        let mu: Vec<Complex64> = point.multipliers.iter().map(|m| Complex64::new(m[0] * scale, m[1] * scale)).collect();
        let raw: Vec<Complex64> = point.multipliers.iter().map(|m| Complex64::new(m[0], m[1])).collect();
        let s = &point.summary;
        let d = PyDict::new(py);
        d.set_item("speed", speed)?;
        d.set_item("phi", s.phi)?;
        d.set_item("beta", s.beta)?;
        d.set_item("max_multiplier", s.max_multiplier)?;
        d.set_item("ln_max_multiplier", s.ln_max_multiplier)?;
        d.set_item("growth_rate", s.growth_rate)?;
        d.set_item("stable", s.stable)?;
        d.set_item("status", status_word(s.status))?;
        d.set_item("reason", s.reason.as_ref().map(|r| r.to_string()))?;
        d.set_item("multipliers", mu.into_pyarray(py))?;
        d.set_item("scaled_multipliers", raw.into_pyarray(py))?;
        d.set_item("multiplier_log_scale", point.multiplier_log_scale)?;
        d.set_item("basis", basis.text())?;
        Ok(d)
    }

    /// `chart`: the grid's max|μ|, ln max|μ|, growth rate, verdicts and statuses as 2-D
    /// arrays (φ rows, β columns).
    #[pyo3(signature = (phis, betas, progress = None))]
    fn chart<'py>(
        &self,
        py: Python<'py>,
        phis: &Bound<'py, PyAny>,
        betas: &Bound<'py, PyAny>,
        progress: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let phis = args::numbers(phis, "--phi").map_err(super::to_py)?;
        let betas = args::numbers(betas, "--beta").map_err(super::to_py)?;
        if phis.is_empty() || betas.is_empty() {
            let argument = if phis.is_empty() { "--phi" } else { "--beta" };
            return Err(super::to_py(Error::Argument { argument: argument.into(), message: "no values".into() }));
        }
        commands::check_grid(&phis, &betas).map_err(super::to_py)?;
        let fs = released(py, || self.system())?;
        let c = watched(py, callback(progress)?, |pr| Ok(Run::new(pr).chart_of(fs, &phis, &betas)?))?;
        let shape = (phis.len(), betas.len());
        let field =
            |f: &dyn Fn(&crate::analysis::chart::ChartPoint) -> f64| -> Vec<f64> { c.points.iter().map(f).collect() };
        let grid = |v: Vec<f64>| v.into_pyarray(py).reshape([shape.0, shape.1]);
        let d = PyDict::new(py);
        d.set_item("speed", c.speed)?;
        d.set_item("phis", c.phis.clone().into_pyarray(py))?;
        d.set_item("betas", c.betas.clone().into_pyarray(py))?;
        d.set_item("max_multiplier", grid(field(&|p| p.max_multiplier))?)?;
        d.set_item("ln_max_multiplier", grid(field(&|p| p.ln_max_multiplier))?)?;
        d.set_item("growth_rate", grid(field(&|p| p.growth_rate))?)?;
        let stable: Vec<bool> = c.points.iter().map(|p| p.stable).collect();
        d.set_item("stable", stable.into_pyarray(py).reshape([shape.0, shape.1])?)?;
        let status: Vec<u8> = c.points.iter().map(|p| status_code(p.status)).collect();
        d.set_item("status", status.into_pyarray(py).reshape([shape.0, shape.1])?)?;
        d.set_item("status_names", ["ok", "inaccurate", "failed"])?;
        d.set_item("threshold", c.threshold.describe())?;
        d.set_item("failed", c.failed)?;
        d.set_item("inaccurate", c.inaccurate)?;
        d.set_item("unstable", c.unstable())?;
        d.set_item("reduction", results::json(py, &c.reduction)?)?;
        Ok(d)
    }

    /// `regions --json`: the catalogue's numbers and stable bands, and the document.
    #[pyo3(signature = (phi_range, beta_max, level = None, progress = None))]
    fn regions<'py>(
        &self,
        py: Python<'py>,
        phi_range: &Bound<'py, PyAny>,
        beta_max: &Bound<'py, PyAny>,
        level: Option<&Bound<'py, PyAny>>,
        progress: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let phi = range_text(phi_range).map_err(super::to_py)?;
        let beta_max = args::number(beta_max, "--beta-max").map_err(super::to_py)?;
        let level = args::optional_number(level, "--level").map_err(super::to_py)?;
        let p = &self.problem;
        let doc = watched(py, callback(progress)?, |pr| {
            let request = commands::regions_request(&phi, beta_max, level, false)?;
            let run = Run::new(pr);
            let job = run.catalogue(p, &request)?;
            let warnings = job.warnings.clone();
            Ok(commands::regions_output(p, &warnings, job.run()?))
        })?;
        results::regions(py, &doc)
    }

    /// `band --json`: the band, its bounds and margins, and the document.
    #[pyo3(signature = (phi_op, level, phi_range = None, progress = None))]
    fn band<'py>(
        &self,
        py: Python<'py>,
        phi_op: &Bound<'py, PyAny>,
        level: &Bound<'py, PyAny>,
        phi_range: Option<&Bound<'py, PyAny>>,
        progress: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let phi_op = args::number(phi_op, "--phi-op").map_err(super::to_py)?;
        let level = args::number(level, "--level").map_err(super::to_py)?;
        let window = phi_range.filter(|r| !r.is_none()).map(range_text).transpose().map_err(super::to_py)?;
        let p = &self.problem;
        let out = watched(py, callback(progress)?, |pr| {
            let commands::BandRequest { phi_op, level, window, key } =
                commands::band_request(phi_op, level, window.as_deref())?;
            let run = Run::new(pr);
            let job = run.band(p, phi_op, level, window, key)?;
            let warnings = job.warnings.clone();
            Ok(commands::band_output(p, window, &warnings, job.run()?))
        })?;
        results::band(py, &out)
    }

    /// `unbalance --json`: each probe's response as arrays, and unbalance.json's document.
    #[pyo3(signature = (speeds, nodes, progress = None))]
    fn unbalance<'py>(
        &self,
        py: Python<'py>,
        speeds: &Bound<'py, PyAny>,
        nodes: &Bound<'py, PyAny>,
        progress: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let speeds = args::numbers(speeds, "--speeds").map_err(super::to_py)?;
        let nodes = args::nodes(nodes, "--nodes").map_err(super::to_py)?;
        let p = &self.problem;
        let doc = watched(py, callback(progress)?, |pr| {
            commands::unbalance_speeds(&speeds)?;
            let run = Run::new(pr);
            let r = run.unbalance(p, None, &speeds, &nodes).and_then(|job| job.run()).map_err(commands::on_nodes)?;
            Ok(commands::unbalance_output(p, r.main))
        })?;
        results::unbalance(py, &doc)
    }

    /// `design`: the status, the variables before and after, the tuned file's text and the
    /// outcome as report.json has it; with `out`, the report is written there as `design
    /// --out` writes it, and the summary text is included.
    #[pyo3(signature = (out = None, progress = None))]
    fn design<'py>(
        &self,
        py: Python<'py>,
        out: Option<&Bound<'py, PyAny>>,
        progress: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let out = args::optional_path(out, "--out").map_err(super::to_py)?;
        let p = &self.problem;
        let (summary, outcome, tuned) = watched(py, callback(progress)?, |pr| {
            let run = Run::new(pr);
            let job = run.design(p, "the design")?;
            let (summary, outcome) = match &out {
                Some(dir) => {
                    let (text, outcome) = commands::design_into(p, dir, job, pr)?;
                    (Some(text), outcome)
                }
                None => (None, job.run(false)?.value.outcome),
            };
            let tuned = commands::tuned_toml(p, &outcome)?;
            Ok((summary, outcome, tuned))
        })?;
        results::design(py, &outcome, tuned, summary)
    }

    /// `design --pareto K --out DIR`: report.json's document, with the summary text as
    /// `summary`.
    #[pyo3(signature = (points, out, progress = None))]
    fn pareto<'py>(
        &self,
        py: Python<'py>,
        points: &Bound<'py, PyAny>,
        out: &Bound<'py, PyAny>,
        progress: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyAny>> {
        use crate::design::pareto::{MAX_POINTS, MIN_POINTS};
        let k = args::count(points, "--pareto", MIN_POINTS as u64, MAX_POINTS as u64).map_err(super::to_py)?;
        let out = args::path(out, "--out").map_err(super::to_py)?;
        let p = &self.problem;
        let (summary, report) = watched(py, callback(progress)?, |pr| {
            let run = Run::new(pr);
            let job = run.pareto(p, k)?;
            commands::pareto_into(p, k, &out, job, pr)
        })?;
        let report = results::json(py, &report)?;
        report.set_item("summary", summary)?;
        Ok(report)
    }
}

fn status_word(s: PointStatus) -> &'static str {
    match s {
        PointStatus::Ok => "ok",
        PointStatus::Inaccurate => "inaccurate",
        PointStatus::Failed => "failed",
    }
}

/// The Floquet point at (φ, β) of `problem` as `floquet` checks and computes it
/// ([`Run::point`]).
fn point(problem: &Problem, phi: f64, beta: f64) -> Result<PointRun, Error> {
    commands::check_point(phi, beta)?;
    Ok(Run::new(&Silent).point(problem, phi, beta)?)
}

/// A (lo, hi) pair as the command line's `A:B` text (Rust's shortest round-trip form).
fn range_text(range: &Bound<'_, PyAny>) -> Result<String, Error> {
    let v = args::numbers(range, "--phi")?;
    match v.as_slice() {
        [lo, hi] => Ok(format!("{lo}:{hi}")),
        _ => Err(Error::Argument {
            argument: "--phi".into(),
            message: format!("expected two numbers (lo, hi) in rad/s, got {} values", v.len()),
        }),
    }
}

/// `import-ross`: the problem text imported from a ROSS `Rotor.save` file (TOML or JSON),
/// with `rings` (a list of dicts, the `[[rings]]` tables) appended, checked by loading.
#[pyfunction]
#[pyo3(signature = (path, speed = None, rings = None))]
pub(crate) fn import_ross(
    py: Python<'_>,
    path: &Bound<'_, PyAny>,
    speed: Option<&Bound<'_, PyAny>>,
    rings: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let path = args::path(path, "FILE").map_err(super::to_py)?;
    let speed = args::optional_number(speed, "--speed").map_err(super::to_py)?;
    let rings = rings.filter(|r| !r.is_none()).map(args::rings).transpose().map_err(super::to_py)?.unwrap_or_default();
    released(py, || {
        let speed = speed.map(|w| commands::bounds::flag("--speed", crate::analysis::limits::speed(w))).transpose()?;
        let import = crate::import::ross::import_path(&path, crate::import::ross::Options { speed })?;
        let mut text = import.text;
        // No rings, no table: an empty `rings = []` would land in the file's last table.
        if !rings.is_empty() {
            let mut t = toml::Table::new();
            t.insert("rings".into(), toml::Value::Array(rings));
            let extra = toml::to_string(&t).map_err(|e| Error::Argument {
                argument: "rings".into(),
                message: format!("cannot be written as [[rings]] tables: {e}"),
            })?;
            text += "\n";
            text += &extra;
        }
        let name = format!("{} (as imported)", path.display());
        Problem::from_text(&text, &name, &[])?;
        Ok(text)
    })
}

/// `study FILE --out DIR`: the summary text and the number of failed cases.
#[pyfunction]
#[pyo3(signature = (file, out, force = None, allow_non_empty = None, dry_run = None, progress = None))]
pub(crate) fn run_study(
    py: Python<'_>,
    file: &Bound<'_, PyAny>,
    out: &Bound<'_, PyAny>,
    force: Option<&Bound<'_, PyAny>>,
    allow_non_empty: Option<&Bound<'_, PyAny>>,
    dry_run: Option<&Bound<'_, PyAny>>,
    progress: Option<&Bound<'_, PyAny>>,
) -> PyResult<(String, usize)> {
    let file = args::path(file, "FILE").map_err(super::to_py)?;
    let out = args::path(out, "--out").map_err(super::to_py)?;
    let switch =
        |v: Option<&Bound<'_, PyAny>>, flag| v.map_or(Ok(false), |v| args::switch(v, flag)).map_err(super::to_py);
    let (force, allow_non_empty, dry_run) =
        (switch(force, "--force")?, switch(allow_non_empty, "--allow-non-empty")?, switch(dry_run, "--dry-run")?);
    watched(py, callback(progress)?, |pr| {
        let options = commands::StudyOptions {
            force,
            allow_non_empty,
            shard: commands::ShardRequest::Auto,
            array_task_id: None,
            dry_run,
            budget: Budget::default(),
        };
        commands::study_cmd(&file, &out, options, pr)
    })
}

/// The number of worker threads of the library's parallel loops.
#[pyfunction]
pub(crate) fn rayon_threads() -> usize {
    rayon::current_num_threads()
}

/// A point's status as its index in `status_names`.
fn status_code(s: PointStatus) -> u8 {
    match s {
        PointStatus::Ok => 0,
        PointStatus::Inaccurate => 1,
        PointStatus::Failed => 2,
    }
}

/// Benchmark only (python/bench/overhead.py): the wall time (s) of `floquet` at each
/// (φ, β) of `points` called from Rust, the same calls `NativeProblem.floquet` makes
/// (checks, admission, the point), without Python between them.
#[pyfunction]
pub(crate) fn _rust_floquet_seconds(py: Python<'_>, problem: &NativeProblem, points: Vec<(f64, f64)>) -> PyResult<f64> {
    released(py, || {
        let start = std::time::Instant::now();
        for &(phi, beta) in &points {
            std::hint::black_box(point(&problem.problem, phi, beta)?);
        }
        Ok(start.elapsed().as_secs_f64())
    })
}

/// A `count` of whirls as the command line's `--count` takes it: checked by its rule,
/// [`commands::DEFAULT_WHIRL_COUNT`] when not given.
fn whirl_count(count: Option<&Bound<'_, PyAny>>) -> PyResult<usize> {
    match count.filter(|c| !c.is_none()) {
        Some(c) => args::count(c, "--count", 1, MAX_COUNT as u64).map_err(super::to_py),
        None => Ok(commands::DEFAULT_WHIRL_COUNT),
    }
}
