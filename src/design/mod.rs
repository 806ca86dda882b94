//! Shunt design: choose C_f, L (or the tuning frequency of Eq. 4) and R of the branches so
//! that instability regions stay out of the operating bands.
//!
//! Three objectives, each a module of [`objective`] behind its trait:
//! - **widest stable band**: an outer Nelder–Mead (argmin) over the variables scaled to
//!   [0, 1] (log for C_f, L, ω), maximising the smallest width over the speeds of the
//!   stable band at β_op containing φ_op, by the same function as `rotorshunt band`
//!   ([`crate::analysis::regions::band_around`]: the catalogue's seeds, never a chart). The landscape is multimodal
//!   (each region crossing φ_op is a valley), so several starts run in parallel: the
//!   reference design, a physics seed (the tuning that puts the electrical region starts
//!   ω_whirl + ω_e farthest from φ_op) and a Halton spread.
//! - **clear bands**: sequential convex programming from the reference design. Each step
//!   linearises, by central differences, the edges (or the onset) of every region
//!   intruding into a band widened by its clearance, and solves for the least weighted
//!   change that moves each one out (clarabel QP, `qp`) inside a trust region and the
//!   bounds; the step is accepted when the total intrusion decreases. A problem with no
//!   feasible step is reported infeasible with the violated bands.
//! - **least peak response**: the largest unbalance amplitude at a node over a speed
//!   range (`vibration`); Nelder–Mead without constraints (the design that damps best,
//!   always reported), then with the constraints ([`spec::Constraints`]: bands kept
//!   clear, a least band width around φ_op, a peak limit, damping floors) as an exact
//!   penalty, then clarabel steps on the constraints linearised by differences. One
//!   start is the classic single-mode R–L tuning (`vibration::classic_tuning`).
//!
//! Constraints are judged afresh on the tuned design, whatever the objective.
//!
//! Every result is checked independently ([`verify`]): the full region catalogue, the
//! reference (DSTM) Floquet point at the tongue centres near the band, and a grid at
//! β_op over the band(s) [`verify::GRID_STEP`] (0.05 rad/s) apart.

pub mod checks;
pub mod content;
pub mod evaluate;
pub(crate) mod machine;
pub mod objective;
pub mod optimise;
pub mod pareto;
pub(crate) mod qp;
pub(crate) mod robust;
pub(crate) mod sizing;
pub mod spec;
pub(crate) mod text;
pub(crate) mod tolerance;
pub mod verify;
pub(crate) mod vibration;

pub use machine::Machine;
pub use machine::Target;
pub use optimise::{run, run_with, DesignOutcome, Observation, Observer, RunOptions, Status};
pub use qp::QpStatus;
pub use robust::{Build, Robustness, SpeedCheck};
pub use sizing::RefinedCheck;
pub use spec::DesignSpec;
pub use tolerance::Perturbation;
pub use vibration::{Baseline, ClassicTuning, ConstraintCheck, ConstraintKind, PeakValue};

use thiserror::Error;

/// Why a design run failed (an infeasible design is an outcome, not an error).
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum DesignError {
    /// The problem file has no `[design]` table.
    #[error("the problem file has no [design] table: add one (problems/README.md, section [design])")]
    NoDesign,
    /// A spec built in code breaks a rule of the `[design]` table
    /// ([`spec::DesignSpec::check`]); the file layer refuses such a table first.
    #[error("design.{field}: {error}")]
    Spec {
        /// The field, as in `[design]` (e.g. `level`, `phi_range[1]`).
        field: String,
        /// The rule broken.
        error: crate::analysis::limits::ParamError,
    },
    /// A candidate's value breaks its branch parameter's rule, or makes a coefficient of
    /// the branch's charge infinite (the checks a problem file's branch gets).
    #[error("candidate design: design.variables[{variable}] ({name}): {error}")]
    Candidate {
        /// The variable, from 0 (as in `[[design.variables]]`).
        variable: usize,
        /// Its name for reports, e.g. `branch 1 c_f`.
        name: String,
        /// The rule broken, with the value.
        error: crate::model::BranchError,
    },
    /// The analysis of a candidate failed.
    #[error("analysis of a candidate design failed: {0}")]
    Analysis(#[from] crate::analysis::AnalysisError),
    /// The optimiser failed.
    #[error("the Nelder-Mead optimiser failed: {0}")]
    Optimiser(String),
    /// The min-peak-response objective or a peak constraint without a response to judge
    /// (a spec built in code; the file layer asks for `[design.response]`).
    #[error("the design judges an unbalance response but has none: add [design.response] (node, speeds)")]
    NoResponse,
    /// `--pareto` on a design without a trade-off between the peak response and the band
    /// around φ_op ([`pareto::trade_off`]).
    #[error("no Pareto front for key `{}`: {}", .0.key, .0.reason)]
    NoTradeOff(pareto::NoTradeOff),
    /// A front asked with too few or too many points.
    #[error("a Pareto front has {min} to {max} points (its two ends and the points between), not {0}", min = pareto::MIN_POINTS, max = pareto::MAX_POINTS)]
    FrontPoints(usize),
    /// The convex step failed to solve.
    #[error("the convex tuning step failed: {0}")]
    Qp(String),
    /// A damping constraint on a whirl tag the model does not have at the lowest
    /// operating speed ([`checks::modes_exist`]).
    #[error(
        "design.constraints.damping[{index}].mode: the model has no whirl mode `{mode}` at speed {speed} rad/s; its lowest modes there are {}",
        crate::analysis::tag_list(available)
    )]
    UnknownMode {
        /// The constraint, from 0 (as in `[[design.constraints.damping]]`).
        index: usize,
        /// The tag given.
        mode: String,
        /// The speed the tags are taken at (rad/s).
        speed: f64,
        /// The model's tags there, forward then backward, lowest first.
        available: Vec<String>,
    },
    /// The caller asked the run to stop ([`crate::progress::Progress::cancelled`]): the
    /// steps' signal to end at once. [`crate::design::optimise::run_with`] never returns
    /// it: it turns a stop into an outcome with [`crate::design::Status::Stopped`] and the
    /// best design judged before it.
    #[error("the design was stopped by its caller before it ended")]
    Stopped,
}

impl DesignError {
    /// The error's kind, named as docs/errors.md heads its section (an analysis failure
    /// keeps its own kind; a spec value's broken rule is the file layer's kind of it).
    /// Matched here, in the crate, so that a new variant has a name before it compiles.
    pub fn kind(&self) -> &'static str {
        match self {
            DesignError::NoDesign => "NoDesign",
            DesignError::Candidate { .. } => "Candidate",
            DesignError::Analysis(a) => a.kind(),
            DesignError::Optimiser(_) => "Optimiser",
            DesignError::Qp(_) => "Qp",
            DesignError::NoResponse => "NoResponse",
            DesignError::NoTradeOff(_) => "NoTradeOff",
            DesignError::FrontPoints(_) => "FrontPoints",
            DesignError::UnknownMode { .. } => "UnknownMode",
            DesignError::Stopped => "Stopped",
            DesignError::Spec { error, .. } => error.rule.kind(),
        }
    }

    /// Whether the design asked for something that breaks a rule (no `[design]`, a
    /// candidate value a branch cannot take, a spec value out of its range), rather than
    /// the run failing: what the command line exits 2 for, not 1 (docs/errors.md). An
    /// analysis error inside a design counts as the run failing. Matched here, in the
    /// crate, so that a new variant is sorted before it compiles.
    pub fn is_bad_input(&self) -> bool {
        match self {
            DesignError::NoDesign | DesignError::Candidate { .. } | DesignError::Spec { .. } => true,
            DesignError::Analysis(_)
            | DesignError::Optimiser(_)
            | DesignError::Qp(_)
            | DesignError::NoResponse
            | DesignError::NoTradeOff(_)
            | DesignError::FrontPoints(_)
            | DesignError::UnknownMode { .. }
            | DesignError::Stopped => false,
        }
    }
}
