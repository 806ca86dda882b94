//! How a refusal names the inputs that drive an estimate ([`Names`]), and the dense
//! stages of a problem admitted before anything is assembled.

use super::{Run, RunError};
use crate::analysis::cost::{self, Dense, Driver};
use crate::problem::Problem;

/// What a job calls the inputs an estimate can be driven by (a flag of the command line
/// or a key of the file).
#[derive(Debug, Clone, Copy)]
pub struct Names<'a> {
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
    pub fn of(&self, driver: Driver) -> String {
        match driver {
            Driver::Dofs => "`shaft.elements` (2 complex DOFs per node) or the closed branches".into(),
            Driver::LowFrequency => format!("{} (the steps per period grow like 1/phi)", self.phi),
            Driver::Grid => self.grid.into(),
            Driver::Load => self.load.into(),
            Driver::ReducedModel => "`analysis.reduced_modes` (or the model's frequencies)".into(),
            Driver::Speed => "`speed`".into(),
            Driver::Periods => self.periods.into(),
            Driver::Candidates => "`design.starts` or `design.max_iterations`".into(),
            Driver::Builds => {
                "`[design.tolerances]` (2^parts + 1 corners, and `samples`), `design.speed_range`, `design.starts` or `design.max_iterations`".into()
            }
            Driver::Settings => "`analysis.steps_per_period`, `analysis.method` or `analysis.reference_steps`".into(),
        }
    }
}

/// Names for a job without φ, β or periods (`check`, `modes`, `campbell`).
pub const MODEL_ONLY: Names<'static> =
    Names { phi: "the command", grid: "`--speeds`", load: "the load", periods: "the command" };

/// The names of a design's inputs in a refusal.
pub const DESIGN: Names<'static> = Names {
    phi: "`design.phi_range`",
    grid: "`design.phi_range` or `design.bands`",
    load: "`design.level` or `design.beta_max`",
    periods: "the design",
};

impl Run<'_> {
    /// Admit the dense stage `stage` of `problem` (estimated from its DOFs, before
    /// anything is assembled).
    pub(crate) fn admit_dense(&self, what: &str, problem: &Problem, stage: Dense) -> Result<(), RunError> {
        let e = cost::dense(&problem.model, stage, rayon::current_num_threads());
        self.admit(what, &e, &MODEL_ONLY)
    }
}
