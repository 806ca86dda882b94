//! The commands' side of the parameter rules and the cost limits: a flag's value checked
//! by its rule ([`rotorshunt::analysis::limits`]) and named by the flag; an estimate
//! ([`rotorshunt::analysis::cost`]) admitted or refused, naming the key or flag that drives it.

use crate::commands::Error;
use rotorshunt::analysis::cost::{self, Budget, Dense, Driver, Estimate};
use rotorshunt::analysis::limits::ParamError;
use rotorshunt::problem::Problem;

/// A flag's value by its rule: the value, or the error naming the flag.
pub(crate) fn flag<T>(argument: &str, r: Result<T, ParamError>) -> Result<T, Error> {
    r.map_err(|e| Error::parameter(argument, &e))
}

/// What a command calls the inputs an estimate can be driven by.
pub(crate) struct Names<'a> {
    /// The φ values or range, e.g. "`--phi`".
    pub phi: &'a str,
    /// The grid's size (points, speeds, range width).
    pub grid: &'a str,
    /// The load (β, β_max or the level).
    pub load: &'a str,
    /// The periods of a response.
    pub periods: &'a str,
}

impl Names<'_> {
    /// The name of `driver`'s input.
    pub(crate) fn of(&self, driver: Driver) -> String {
        match driver {
            Driver::Dofs => "`shaft.elements` (2 complex DOFs per node) or the closed branches".into(),
            Driver::LowFrequency => format!("{} (the steps per period grow like 1/phi)", self.phi),
            Driver::Grid => self.grid.into(),
            Driver::Load => self.load.into(),
            Driver::ReducedModel => "`analysis.reduced_modes` (or the model's frequencies)".into(),
            Driver::Speed => "`speed`".into(),
            Driver::Periods => self.periods.into(),
            Driver::Candidates => "`design.starts` or `design.max_iterations`".into(),
            Driver::Settings => "`analysis.steps_per_period`, `analysis.method` or `analysis.reference_steps`".into(),
        }
    }
}

/// Names for a command without φ, β or periods (`check`, `modes`, `campbell`).
pub(crate) const MODEL_ONLY: Names<'static> =
    Names { phi: "the command", grid: "`--speeds`", load: "the load", periods: "the command" };

/// Admit `estimate` of `what` within `budget`, or refuse it naming its driver.
pub(crate) fn admit(budget: &Budget, what: &str, estimate: &Estimate, names: &Names<'_>) -> Result<(), Error> {
    Ok(budget.admit(what, estimate, &|d| names.of(d))?)
}

/// Admit the dense stage `stage` of `problem` (estimated from its DOFs, before anything is
/// assembled).
pub(crate) fn admit_dense(budget: &Budget, what: &str, problem: &Problem, stage: Dense) -> Result<(), Error> {
    let e = cost::dense(&problem.model, stage, rayon::current_num_threads());
    admit(budget, what, &e, &MODEL_ONLY)
}
