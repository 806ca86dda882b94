//! The application layer: a [`Run`] is one use of the tool, with its limits (the cost
//! budget checked before it starts, a time limit and an allowance of monodromy
//! evaluations while it runs), the observer its progress goes to and a
//! [`CancelToken`] another thread may use to stop it. Its methods are the tool's jobs
//! (whirls, Campbell diagram, Floquet point, chart, time response, region catalogue,
//! stable band, unbalance response, damping, design, Pareto front, a study's case): each
//! admits its work, runs it under the run's limits and returns what it computed; the
//! command line and the Python bindings parse, call one method and render.
//!
//! A limit reached while a job runs stops it within a search step (every search a job
//! calls asks [`Progress::cancelled`] between its steps). What the job had computed is
//! then kept where a best value exists (a design's best candidate so far: an [`Outcome`]
//! whose [`RunStatus`] says what stopped it); elsewhere the job returns
//! [`RunError::Stopped`] or [`RunError::Cancelled`] and nothing of it.

mod admit;
mod design;
mod floquet;
mod limits;
mod outcome;
mod regions;
mod whirls;

pub use admit::{Names, DESIGN, MODEL_ONLY};
pub use design::{DesignJob, DesignRun, FrontJob};
pub use floquet::{range_warnings, ChartJob, ChartRun, PointRun, ResponseJob, ResponseRun, CHART, POINT};
pub use limits::{
    Budget, CostError, CountLimitError, Resource, RunningLimit, Stopped, TimeLimitError, MAX_BYTES, MAX_OPERATIONS,
    MAX_SECONDS,
};
pub use outcome::{CancelToken, Outcome, RunStatus};
pub use regions::{
    plot_grid, BandJob, BandLoadMargin, BandRun, CatalogueJob, CatalogueRun, RegionsCaseJob, BAND, REGIONS, STUDY,
};
pub use whirls::{CampbellJob, CampbellRun, DampingRun, ModesRun, UnbalanceJob, UnbalanceRun};

use crate::analysis::cost::Estimate;
use crate::progress::{Deadline, Progress};
use thiserror::Error;

/// Why a job of a [`Run`] gave no result. Exhaustive on purpose: a front end maps each
/// to its own error, and a new kind must reach every such map before it compiles.
#[derive(Debug, Error)]
pub enum RunError {
    /// The problem is invalid for the job (a key refused at its line).
    #[error(transparent)]
    Problem(#[from] crate::problem::ProblemError),
    /// An analysis failed on valid input.
    #[error(transparent)]
    Analysis(#[from] crate::analysis::AnalysisError),
    /// A design failed.
    #[error(transparent)]
    Design(#[from] crate::design::DesignError),
    /// Refused before it started: its estimate is beyond the run's budget.
    #[error(transparent)]
    Refused(#[from] CostError),
    /// Stopped at a limit while it ran, with nothing to keep.
    #[error(transparent)]
    Stopped(#[from] Stopped),
    /// Stopped by its caller ([`CancelToken::cancel`] or the observer's
    /// [`Progress::cancelled`]), with nothing to keep.
    #[error("{what} was cancelled by its caller; nothing was kept")]
    Cancelled {
        /// What was cancelled, e.g. `the chart`.
        what: String,
    },
}

/// One use of the tool: its limits, its observer and its cancellation
/// ([`Run::new`], then [`Run::with_budget`], [`Run::with_evaluations`],
/// [`Run::with_cancel`]).
pub struct Run<'a> {
    budget: Budget,
    /// At most this many monodromy evaluations while a job runs, beside the allowance
    /// of its estimate (`None`: the estimate's alone).
    evaluations: Option<u64>,
    observer: outcome::Observer<'a>,
}

impl std::fmt::Debug for Run<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Run").field("budget", &self.budget).field("evaluations", &self.evaluations).finish()
    }
}

impl<'a> Run<'a> {
    /// A run reporting to `observer`, with the default budget ([`Budget::default`]: the
    /// limits of work and memory before it starts, no time limit while it runs).
    pub fn new(observer: &'a dyn Progress) -> Run<'a> {
        Run { budget: Budget::default(), evaluations: None, observer: outcome::Observer::new(observer) }
    }

    /// This run with `budget`'s limits (its factor, memory share and time limit).
    pub fn with_budget(self, budget: Budget) -> Run<'a> {
        Run { budget, ..self }
    }

    /// This run with at most `most` monodromy evaluations per job while it runs (at
    /// least 1).
    pub fn with_evaluations(self, most: u64) -> Result<Run<'a>, crate::analysis::limits::ParamError> {
        let most = crate::analysis::limits::count(most, 1, u64::MAX)?;
        Ok(Run { evaluations: Some(most), ..self })
    }

    /// This run stopped when `token` is cancelled (from any thread).
    pub fn with_cancel(self, token: CancelToken) -> Run<'a> {
        Run { observer: self.observer.with_token(token), ..self }
    }

    /// The run's budget.
    pub fn budget(&self) -> &Budget {
        &self.budget
    }

    /// The observer the run reports to (with its cancellation).
    pub fn observer(&self) -> &dyn Progress {
        &self.observer
    }

    /// Admit `estimate` of `what`, or refuse it naming its driver by `names`.
    pub(crate) fn admit(&self, what: &str, estimate: &Estimate, names: &Names<'_>) -> Result<(), RunError> {
        Ok(self.budget.admit(what, estimate, &|d| names.of(d))?)
    }

    /// The running limits of a job admitted at `estimate` (`None`: a job without a count
    /// of evaluations, limited by time alone), from now.
    pub(crate) fn limits(&self, estimate: Option<&Estimate>) -> Deadline<'_> {
        let allowance = estimate.and_then(|e| self.budget.allowance(e));
        let most = match (allowance, self.evaluations) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        self.budget.deadline(&self.observer).with_allowance(most)
    }

    /// What stopped the work of `deadline`, if anything: the error of `what`.
    pub(crate) fn stopped(&self, deadline: &Deadline<'_>, what: &str) -> Result<(), RunError> {
        self.budget.stopped(deadline, what)?;
        if self.observer.cancelled() {
            return Err(RunError::Cancelled { what: what.to_string() });
        }
        Ok(())
    }

    /// The status of a job whose work `deadline` bounded.
    pub(crate) fn status(&self, deadline: &Deadline<'_>) -> RunStatus {
        match self.budget.stopped(deadline, "") {
            Err(Stopped::Time(_)) => RunStatus::TimeLimit,
            Err(Stopped::Count(_)) => RunStatus::EvaluationLimit,
            Ok(()) if self.observer.cancelled() => RunStatus::Cancelled,
            Ok(()) => RunStatus::Completed,
        }
    }
}
