//! What a run costs, counted from its inputs before it starts, and the limits beyond
//! which a command refuses it (written once, here). A run admitted is bounded again while
//! it runs, on whatever machine ([`Budget::running`]): at its time limit measured there
//! (on the command line by default [`MAX_SECONDS`] times the factor; `--time-limit`), and,
//! for the region searches, at its allowance of monodromy evaluations
//! ([`Budget::allowance`]), counted by the searches as they make them. The count before
//! a search is a model of it, built from the search's own loop bounds (`most_…` next to
//! each loop) and checked on every bundled problem by tests/cost_counts.rs. It bounds
//! every loop whose length is known before the search; two are not (a tracked region's
//! width at each load, a design's band around φ_op in each candidate: counted at an
//! expected length). The allowance holds the limit there, and wherever the model is
//! wrong. [`Budget::stopped`] turns either stop into an error ([`Stopped`]) before
//! anything is written.
//!
//! Two resources are bounded before a run, both by counts:
//! - **work**: floating-point operations, at most [`MAX_OPERATIONS`]. A run's count is
//!   the sum over the kernels it will call of each kernel's operation count, from the
//!   sizes of its matrices (the model's DOFs before anything is assembled; the reduced
//!   model's state dimension n = 2M) and the numbers of calls: per-φ tables, CFM4 steps
//!   (whose number per period grows like 1/φ and like ω_max/φ, and doubles with β), RK4
//!   steps, β bracket samples (β_max over the bracket step), seeds and the guard lattice
//!   of a range. The counts are the algorithms' own (leading terms, Golub and Van Loan,
//!   *Matrix Computations*), not rates measured on a machine: how long they take is
//!   measured while the run runs, by its time limit;
//! - **memory**: bytes of the dense matrices a run holds at once, at most [`MAX_BYTES`].
//!
//! A [`Budget`] multiplies both limits (`--max-cost FACTOR`). The counts are cheap
//! (closed forms and sums over at most a few thousand φ values) and mostly upper bounds:
//! a search counts every evaluation its bounds allow.

mod dense;
mod floquet;
mod regions;

pub use dense::{dense, model_dofs, unbalance, Dense};
pub use floquet::{chart, floquet_point, response, response_of, response_steps, PointCost};
pub use regions::{band, band_and_margins, catalogue, points, scan, CatalogueWork, DESIGN_BAND_EVALUATIONS};

use super::floquet::{FloquetSystem, ALIAS_MARGIN, ALIAS_ORDERS};
use super::limits::{self, compact, ParamError};
use super::regions::start::SCREENING_TOLERANCE;
use super::regions::{seeds::Seed, RegionSettings, CENTRE_WINDOW};
use super::{Criterion, Interval, MonodromyMethod};
use serde::Serialize;
use thiserror::Error;

/// Most floating-point operations a run may be counted at before it starts: 3·10¹³. The
/// counts are upper bounds (every evaluation a search's bounds allow): the bundled
/// problems' largest, the robust speed-range design's 8.1e12, is 3.7 times below this
/// (docs/errors.md, `Cost`). The runs the limit is for are counted at 10¹⁴ and far beyond
/// (φ = 1e-3 for 1e3 in a response, φ near 1e-300): a slip of units or digits more often
/// than an intent, and `--max-cost` admits them deliberately. What a count takes is
/// measured while the run runs ([`MAX_SECONDS`]). On the shared 2-core host this was
/// written on, one core did 1.2e10 of them a second in the response's RK4 loop (scalar
/// complex arithmetic), 2.4e10 in a chart (matrix products), so a run counted at the limit
/// is 20 to 45 minutes of computing there; an unbalance response's small sparse solves
/// are slower per operation (about 3e9 a second), and the time limit bounds those.
pub const MAX_OPERATIONS: f64 = 3.0e13;

/// The command line's time limit while a run runs (s of wall time, times the
/// `--max-cost` factor): one hour, measured on the machine that runs it.
pub const MAX_SECONDS: f64 = 3600.0;

/// Most bytes of dense matrices a run may hold at once: 400 MiB. With the process's own
/// ~20 MB the peak stays under 500 MB; `check` reaches it near 880 shaft elements, the
/// whirl solvers (`modes`, `campbell`, `regions`, `band`) near 440.
pub const MAX_BYTES: f64 = 400.0 * 1024.0 * 1024.0;

// Operation counts of the kernels: real floating-point operations (a complex multiply-add
// is 8), n the state dimension 2M of the reduced model or the DOFs of the full one.
// Matrices smaller than 8 × 8 count as 8 × 8 (`floored`): below that a call's fixed work
// (dispatch, bookkeeping, the result's allocation) is no longer small beside its
// arithmetic.

/// The size a kernel's count is taken at: at least [`SMALLEST_COUNTED`].
fn floored(n: f64) -> f64 {
    n.max(SMALLEST_COUNTED)
}
/// The smallest matrix size counted (module comment above).
const SMALLEST_COUNTED: f64 = 8.0;
/// One CFM4 step of the fast path: the step's exponential summed from the per-φ table's
/// Chebyshev coefficients (a real 2n² × p by p product, 4pn², p ≤ 20 for a converged
/// table) and its complex product into the monodromy (8n³).
fn step_ops(n: f64) -> f64 {
    8.0 * floored(n).powi(3) + 80.0 * n * n
}
/// Eigenvalues of the complex n × n monodromy (Hessenberg reduction and shifted QR, about
/// 10n³ complex operations).
fn eig_ops(n: f64) -> f64 {
    40.0 * floored(n).powi(3)
}
/// One exponential at a Chebyshev point: a Taylor polynomial by Paterson–Stockmeyer, about
/// eight complex products.
fn exp_ops(n: f64) -> f64 {
    64.0 * floored(n).powi(3)
}
/// One DSTM step: a Padé-13 exponential with scaling and squaring (six products, a solve
/// and about three squarings: some twelve complex products' work) and its product into
/// the monodromy.
fn dstm_step_ops(n: f64) -> f64 {
    104.0 * floored(n).powi(3)
}
/// One RK4 step of the response: four right-hand sides, each two complex n × n
/// matrix-vector products (B0·y and B1·y), and the vector updates.
fn rk4_ops(n: f64) -> f64 {
    64.0 * floored(n).powi(2) + 64.0 * n
}
/// The symmetric-definite eigensolution of the full model with its vectors (buckling load
/// or modal basis): Cholesky, reduction to standard form, tridiagonalisation and the
/// implicit QR with vectors, about 14n³.
fn dense_eigen_ops(n: f64) -> f64 {
    14.0 * floored(n).powi(3)
}
/// The quadratic eigenproblem of the full model: the complex nonsymmetric eigenproblem of
/// its 2n × 2n linearisation with vectors, about 25(2n)³ complex operations.
fn qep_ops(n: f64) -> f64 {
    100.0 * floored(2.0 * n).powi(3)
}
/// One sparse LU factorisation and solve of the dynamic stiffness, per DOF
/// (`analysis::unbalance`): the shaft's band keeps the factors' fill fixed per DOF, about
/// 8b² complex operations per row for a half-bandwidth b ≤ 11.
const UNBALANCE_SOLVE_OPS_N: f64 = 1000.0;

/// Peak bytes per DOF² of a rotor and its symmetric eigensolutions (`check`: 90 MB at 808
/// DOFs, 334 MB at 1 608).
const ROTOR_BYTES_N2: f64 = 130.0;
/// Bytes per DOF² of the assembled M, C, K, S, G (real, dense) and their copies.
const ASSEMBLED_BYTES_N2: f64 = 48.0;
/// Peak bytes per DOF² of the quadratic eigenproblem (`modes`: 346 MB at 808 DOFs, 1.27
/// GB at 1 608).
const QEP_BYTES_N2: f64 = 530.0;
/// Bytes per DOF² of the mode shapes kept per speed by a Campbell diagram (237 MB for 301
/// speeds at 132 DOFs).
const SHAPES_BYTES_N2: f64 = 40.0;

/// Peak bytes per probe and speed of an unbalance response: the values, and the JSON, CSV
/// and SVG text written from them (118 MB above the process's own for 5 probes × 100 001
/// speeds: 236 bytes).
const UNBALANCE_BYTES_PER_VALUE: f64 = 250.0;

/// What an estimate is driven by: the input a refusal names.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Driver {
    /// The model's size: its DOFs (shaft elements, closed branches).
    Dofs,
    /// The lowest excitation frequency: steps per period grow like 1/φ.
    LowFrequency,
    /// How many points, speeds or values a grid or range holds.
    Grid,
    /// The load: β bracket samples grow like β_max, table steps double with β.
    Load,
    /// The reduced model's size M (`analysis.reduced_modes`) or frequencies.
    ReducedModel,
    /// The rotating speed Ω (a response's step resolves it).
    Speed,
    /// The periods of a time response.
    Periods,
    /// The candidates of a design (starts × iterations).
    Candidates,
    /// The numerical settings (steps per period, DSTM steps).
    Settings,
}

/// One resource of an estimate: the amount, and what drives it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Part {
    /// Floating-point operations (work) or bytes (memory).
    pub amount: f64,
    /// The input that drives it.
    pub driver: Driver,
    /// How it comes about, e.g. `91 points × 2.4e304 CFM4 steps per period`.
    pub detail: String,
}

/// The counted cost of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    /// Floating-point operations.
    pub work: Part,
    /// Bytes of dense matrices held at once.
    pub memory: Part,
    /// Monodromy evaluations of the region searches counted in `work` (0 for work that
    /// is not a region search): what the searches' own count, [`crate::analysis::regions::Catalogue::evaluations`]
    /// and [`crate::analysis::regions::Band::evaluations`], stays within (tests/cost_counts.rs).
    pub evaluations: f64,
}

impl Estimate {
    /// Nothing.
    pub fn zero() -> Estimate {
        let part = |driver| Part { amount: 0.0, driver, detail: String::new() };
        Estimate { work: part(Driver::Grid), memory: part(Driver::Dofs), evaluations: 0.0 }
    }

    /// A work-only estimate of `operations` floating-point operations.
    pub fn work(operations: f64, driver: Driver, detail: String) -> Estimate {
        Estimate { work: Part { amount: operations, driver, detail }, ..Estimate::zero() }
    }

    /// This run followed by `other`: the work adds (the larger part's driver kept), memory
    /// is the larger peak.
    pub fn then(self, other: Estimate) -> Estimate {
        let amount = self.work.amount + other.work.amount;
        let work = if other.work.amount > self.work.amount || self.work.amount.is_nan() {
            Part { amount, ..other.work }
        } else {
            Part { amount, ..self.work }
        };
        let memory = if other.memory.amount > self.memory.amount { other.memory } else { self.memory };
        Estimate { work, memory, evaluations: self.evaluations + other.evaluations }
    }

    /// `count` runs of this one in sequence (`what` names them). The count becomes the
    /// driver unless one run's own driver is an extreme input (a low frequency, a load).
    pub fn times(mut self, count: f64, driver: Driver, what: &str) -> Estimate {
        self.work.amount *= count;
        self.evaluations *= count;
        if count > 1.0 {
            self.work.detail = if self.work.detail.is_empty() {
                format!("{} {what}", compact_count(count))
            } else {
                format!("{} {what}, each: {}", compact_count(count), self.work.detail)
            };
            if !matches!(self.work.driver, Driver::LowFrequency | Driver::Load | Driver::Speed) {
                self.work.driver = driver;
            }
        }
        self
    }
}

fn compact_count(x: f64) -> String {
    if !x.is_finite() {
        "unboundedly many".into()
    } else if x < 1e6 {
        format!("{}", x.round())
    } else {
        format!("{x:.2e}")
    }
}

/// Floating-point operations as a person reads them: 1.2e15.
fn operations_text(x: f64) -> String {
    if !x.is_finite() {
        "unboundedly many".into()
    } else {
        format!("{x:.1e}")
    }
}

/// Bytes as a person reads them (MiB, GiB).
fn bytes_text(b: f64) -> String {
    const MIB: f64 = 1024.0 * 1024.0;
    if !b.is_finite() {
        "unbounded memory".into()
    } else if b >= 1e6 * MIB {
        format!("{b:.1e} bytes")
    } else if b >= 1024.0 * MIB {
        format!("{:.1} GiB", b / (1024.0 * MIB))
    } else {
        format!("{:.0} MiB", b / MIB)
    }
}

/// Which limit an estimate broke.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Resource {
    /// Computing work: floating-point operations.
    Work,
    /// Memory of dense matrices.
    Memory,
}

/// A run refused before it started: its estimated cost is beyond the limit.
#[derive(Debug, Clone, PartialEq, Error, Serialize)]
#[error(
    "{what} would need {}, more than the {}{} allowed: {detail}; change {parameter}, or allow FACTOR times more with --max-cost FACTOR",
    amount_text(*resource, *estimate),
    limit_text(*resource, *limit),
    if *factor == 1.0 { String::new() } else { format!(" (--max-cost {})", compact(*factor)) },
)]
pub struct CostError {
    /// What would run, e.g. `the chart`, `check`.
    pub what: String,
    /// Work or memory: which limit the estimate exceeds.
    pub resource: Resource,
    /// The estimate (floating-point operations or bytes).
    pub estimate: f64,
    /// The limit (floating-point operations or bytes), with the factor applied.
    pub limit: f64,
    /// The `--max-cost` factor in force.
    pub factor: f64,
    /// The key or flag that drives the estimate, e.g. `--phi`, `shaft.elements`.
    pub parameter: String,
    /// How the estimate comes about.
    pub detail: String,
}

fn amount_text(resource: Resource, x: f64) -> String {
    match (resource, x.is_finite()) {
        (Resource::Work, true) => format!("about {} floating-point operations", operations_text(x)),
        (Resource::Memory, true) => format!("about {} of memory", bytes_text(x)),
        (Resource::Work, false) => "unboundedly many floating-point operations".into(),
        (Resource::Memory, false) => bytes_text(x),
    }
}

fn limit_text(resource: Resource, x: f64) -> String {
    match resource {
        Resource::Work => operations_text(x),
        Resource::Memory => bytes_text(x),
    }
}

/// A run stopped while it ran: it passed its time limit, measured on the machine that ran
/// it ([`crate::progress::Deadline`]). What it had computed is dropped and nothing is
/// written.
#[derive(Debug, Clone, PartialEq, Error, Serialize)]
#[error(
    "{what} was stopped at its time limit of {} s (after {:.1} s, measured while it ran); nothing was written; allow more time with --time-limit SECONDS{}",
    compact(*limit),
    elapsed,
    if *explicit { "" } else { " (or --max-cost FACTOR, whose time limit is FACTOR times 3600 s)" },
)]
pub struct TimeLimitError {
    /// What was stopped, e.g. `the chart`.
    pub what: String,
    /// The limit (s of wall time).
    pub limit: f64,
    /// The time the run had taken when it stopped (s).
    pub elapsed: f64,
    /// Whether the limit was given (`--time-limit`) rather than the budget's
    /// [`MAX_SECONDS`] times its factor.
    pub explicit: bool,
}

/// A run stopped while it ran: its region searches passed their allowance of monodromy
/// evaluations ([`Budget::allowance`]), counted as they were made
/// ([`crate::progress::Deadline::with_allowance`]): its work, at its counted cost per
/// evaluation, reached the limit. The parts of the count that bound their loops cannot
/// get here; the ones whose length the search finds as it goes (a tracked region's
/// width, a design's bands) can. What it had computed is dropped and nothing is written.
#[derive(Debug, Clone, PartialEq, Error, Serialize)]
#[error(
    "{what} was stopped at its allowance of {allowed} monodromy evaluations ({used} made, counted while it ran: the work limit in the search's own count); nothing was written; allow FACTOR times more with --max-cost FACTOR"
)]
pub struct CountLimitError {
    /// What was stopped, e.g. `the band search`.
    pub what: String,
    /// The allowance (evaluations).
    pub allowed: u64,
    /// The evaluations made when it stopped.
    pub used: u64,
}

/// Why a run was stopped while it ran ([`Budget::stopped`]): one of a budget's two
/// running limits. Exhaustive on purpose: a caller maps each to its own error, and a
/// third limit must reach every such map before it compiles.
#[derive(Debug, Clone, PartialEq, Error, Serialize)]
pub enum Stopped {
    /// At its time limit.
    #[error(transparent)]
    Time(#[from] TimeLimitError),
    /// At its allowance of evaluations.
    #[error(transparent)]
    Count(#[from] CountLimitError),
}

impl Stopped {
    /// What stopped the run and how to allow more, as a clause for a report of what the
    /// run kept (the error's own text says that nothing was written).
    pub fn reason(&self) -> String {
        match self {
            Stopped::Time(e) => format!(
                "at its time limit of {} s, after {:.1} s; allow more time with --time-limit SECONDS",
                compact(e.limit),
                e.elapsed
            ),
            Stopped::Count(e) => format!(
                "at its allowance of {} monodromy evaluations, {} made; allow more with --max-cost FACTOR",
                e.allowed, e.used
            ),
        }
    }
}

/// The limits of a run: [`MAX_OPERATIONS`] and [`MAX_BYTES`] times a factor
/// (`--max-cost`) for its counts before it starts, and two limits while it runs
/// ([`Budget::running`]): a time measured there ([`RunningLimit`]: none for a library
/// caller, who can stop the run itself; the command line's `--time-limit`, by default
/// [`MAX_SECONDS`] times the factor), and the allowance of evaluations of the estimate
/// it was admitted with ([`Budget::allowance`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Budget {
    factor: f64,
    /// Runs sharing the memory limit.
    memory_share: f64,
    /// The time limit while a run runs.
    running: RunningLimit,
}

/// The time limit of a run while it runs ([`Budget::deadline`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RunningLimit {
    /// None: the caller stops the run ([`crate::progress::Progress::cancelled`]).
    None,
    /// [`Budget::seconds`]: [`MAX_SECONDS`] times the factor (the command line without
    /// `--time-limit`).
    OfFactor,
    /// Seconds of wall time given (`--time-limit`).
    Given(f64),
}

impl Default for Budget {
    fn default() -> Budget {
        Budget { factor: 1.0, memory_share: 1.0, running: RunningLimit::None }
    }
}

impl Budget {
    /// The limits times `factor` (finite, > 0), with no time limit while a run runs.
    pub fn new(factor: f64) -> Result<Budget, ParamError> {
        Ok(Budget { factor: limits::cost_factor(factor)?, ..Budget::default() })
    }

    /// This budget with a time limit of `seconds` of wall time (finite, > 0) while a run
    /// runs.
    pub fn with_time_limit(self, seconds: f64) -> Result<Budget, ParamError> {
        Ok(Budget { running: RunningLimit::Given(limits::time_limit(seconds)?), ..self })
    }

    /// This budget with [`Budget::seconds`], [`MAX_SECONDS`] times its factor, as its
    /// time limit while a run runs (the command line's default).
    pub fn with_estimate_time_limit(self) -> Budget {
        Budget { running: RunningLimit::OfFactor, ..self }
    }

    /// The global flags that give a command line this budget (`--max-cost`,
    /// `--time-limit`), none for the command line's default: what a script that runs the
    /// tool again (a Slurm array task) passes on. Finite positive numbers, written to read
    /// back exactly.
    pub fn flags(&self) -> Vec<String> {
        let mut flags = Vec::new();
        if self.factor != 1.0 {
            flags.extend(["--max-cost".to_string(), format!("{:?}", self.factor)]);
        }
        if let RunningLimit::Given(t) = self.running {
            flags.extend(["--time-limit".to_string(), format!("{t:?}")]);
        }
        flags
    }

    /// The time limit while a run runs (s of wall time), if any.
    pub fn time_limit(&self) -> Option<f64> {
        match self.running {
            RunningLimit::None => None,
            RunningLimit::OfFactor => Some(self.seconds()),
            RunningLimit::Given(t) => Some(t),
        }
    }

    /// A deadline of this budget's time limit, from now, reporting to `progress` (one
    /// that never passes without a limit), without an allowance of evaluations.
    pub fn deadline<'a>(&self, progress: &'a dyn crate::progress::Progress) -> crate::progress::Deadline<'a> {
        crate::progress::Deadline::new(progress, self.time_limit().unwrap_or(f64::INFINITY))
    }

    /// The running bounds of a run admitted with `estimate`, from now, reporting to
    /// `progress`: this budget's time limit and the allowance of evaluations of
    /// `estimate` ([`Budget::allowance`]).
    pub fn running<'a>(
        &self,
        progress: &'a dyn crate::progress::Progress,
        estimate: &Estimate,
    ) -> crate::progress::Deadline<'a> {
        self.deadline(progress).with_allowance(self.allowance(estimate))
    }

    /// The monodromy evaluations a run counted at `estimate` may make while it runs: its
    /// counted evaluations times the room its work leaves under the limit of operations,
    /// at least its count. The limit of work, that is, in the unit the searches count
    /// themselves, at the estimate's operations per evaluation. None for work without a
    /// region search (no evaluations counted).
    pub fn allowance(&self, estimate: &Estimate) -> Option<u64> {
        let (count, work) = (estimate.evaluations, estimate.work.amount);
        (count >= 1.0 && work > 0.0).then(|| {
            // An `as` cast saturates: an allowance beyond u64 is u64::MAX.
            (count * (self.operations() / work).max(1.0)).floor() as u64
        })
    }

    /// The error of `what` when `deadline` (of this budget) stopped a step of it, at its
    /// time limit or at its allowance; what it computed is then incomplete and must not be
    /// kept.
    pub fn stopped(&self, deadline: &crate::progress::Deadline<'_>, what: &str) -> Result<(), Stopped> {
        if !deadline.tripped() {
            return Ok(());
        }
        if deadline.counted_out() {
            return Err(Stopped::Count(CountLimitError {
                what: what.to_string(),
                allowed: deadline.allowance().unwrap_or(u64::MAX),
                used: deadline.evaluations(),
            }));
        }
        Err(Stopped::Time(TimeLimitError {
            what: what.to_string(),
            limit: self.time_limit().unwrap_or(f64::INFINITY),
            elapsed: deadline.elapsed(),
            explicit: matches!(self.running, RunningLimit::Given(_)),
        }))
    }

    /// This budget with its memory limit divided among `parts` runs held at once (the
    /// cases of a study run in parallel); the time limit stays each run's own.
    pub fn share(self, parts: f64) -> Budget {
        Budget { memory_share: self.memory_share * parts.max(1.0), ..self }
    }

    /// The factor.
    pub fn factor(&self) -> f64 {
        self.factor
    }

    /// The command line's default time limit while a run runs: [`MAX_SECONDS`] times the
    /// factor (s).
    pub fn seconds(&self) -> f64 {
        MAX_SECONDS * self.factor
    }

    /// The work limit of a run's count before it starts (floating-point operations).
    pub fn operations(&self) -> f64 {
        MAX_OPERATIONS * self.factor
    }

    /// The memory limit (bytes) of one run.
    pub fn bytes(&self) -> f64 {
        MAX_BYTES * self.factor / self.memory_share
    }

    /// Refuse `estimate` of `what` when either part is beyond its limit (or not finite),
    /// naming the input `name` gives for the driver.
    pub fn admit(&self, what: &str, estimate: &Estimate, name: &dyn Fn(Driver) -> String) -> Result<(), CostError> {
        let refuse = |resource, part: &Part, limit: f64| CostError {
            what: what.to_string(),
            resource,
            estimate: part.amount,
            limit,
            factor: self.factor,
            parameter: name(part.driver),
            detail: part.detail.clone(),
        };
        // A NaN estimate cannot be bounded: refused like an infinite one.
        if estimate.memory.amount.is_nan() || estimate.memory.amount > self.bytes() {
            return Err(refuse(Resource::Memory, &estimate.memory, self.bytes()));
        }
        if estimate.work.amount.is_nan() || estimate.work.amount > self.operations() {
            return Err(refuse(Resource::Work, &estimate.work, self.operations()));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_refuse_beyond_the_limits_and_name_the_driver() {
        let b = Budget::default();
        let cheap = Estimate::work(1.0, Driver::Grid, "x".into());
        assert!(b.admit("the chart", &cheap, &|_| "`--phi`".into()).is_ok());
        let dear = Estimate::work(1e300, Driver::LowFrequency, "91 points".into());
        let e = b.admit("the chart", &dear, &|d| format!("{d:?}")).unwrap_err();
        assert_eq!((e.resource, e.parameter.as_str()), (Resource::Work, "LowFrequency"));
        assert!(e.to_string().starts_with("the chart would need about 1.0e300 floating-point operations, more than the 3.0e13 allowed: 91 points; change LowFrequency"), "{e}");
        let nan = Estimate::work(f64::NAN, Driver::Grid, String::new());
        assert!(b.admit("x", &nan, &|_| String::new()).is_err(), "a NaN estimate is refused");
        assert!(Budget::new(2.0)
            .unwrap()
            .admit("the chart", &Estimate::work(4.5e13, Driver::Grid, String::new()), &|_| String::new())
            .is_ok());
        assert!(b
            .admit("the chart", &Estimate::work(4.5e13, Driver::Grid, String::new()), &|_| String::new())
            .is_err());
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(Budget::new(bad).is_err(), "{bad}");
            assert!(Budget::default().with_time_limit(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn a_budget_gives_the_flags_that_make_it() {
        assert!(Budget::default().flags().is_empty());
        assert!(Budget::default().with_estimate_time_limit().flags().is_empty());
        for b in [
            Budget::new(10.0).unwrap().with_estimate_time_limit(),
            Budget::new(0.1).unwrap().with_time_limit(1e-9).unwrap(),
            Budget::default().with_time_limit(7200.5).unwrap(),
        ] {
            let flags = b.flags();
            let value = |name: &str| flags.iter().position(|f| f == name).map(|i| flags[i + 1].parse::<f64>().unwrap());
            let again = Budget::new(value("--max-cost").unwrap_or(1.0)).unwrap().with_estimate_time_limit();
            let again = match value("--time-limit") {
                Some(t) => again.with_time_limit(t).unwrap(),
                None => again,
            };
            assert_eq!(again, b, "{flags:?}");
        }
    }

    #[test]
    fn the_time_limit_is_none_the_estimates_or_given() {
        assert_eq!(Budget::default().time_limit(), None);
        assert_eq!(Budget::new(0.5).unwrap().time_limit(), None);
        assert_eq!(Budget::new(0.5).unwrap().with_estimate_time_limit().time_limit(), Some(0.5 * MAX_SECONDS));
        let given = Budget::new(0.5).unwrap().with_time_limit(20.0).unwrap();
        assert_eq!((given.time_limit(), given.seconds()), (Some(20.0), 0.5 * MAX_SECONDS));
        // Without a limit the deadline never passes.
        let d = Budget::default().deadline(&crate::progress::Silent);
        assert!(!crate::progress::Progress::cancelled(&d));
        // A deadline that stopped a step is an error naming the limit; one that did not,
        // none.
        let b = Budget::default().with_time_limit(1e-9).unwrap();
        let d = b.deadline(&crate::progress::Silent);
        assert!(b.stopped(&d, "the chart").is_ok());
        std::thread::sleep(std::time::Duration::from_millis(1));
        assert!(crate::progress::Progress::cancelled(&d));
        let Err(Stopped::Time(e)) = b.stopped(&d, "the chart") else { panic!("not a time stop") };
        assert!(e.explicit && e.limit == 1e-9 && e.elapsed > e.limit, "{e:?}");
        assert!(e.to_string().starts_with("the chart was stopped at its time limit of 1e-9 s (after "), "{e}");
        assert!(e.to_string().contains(" s, measured while it ran); nothing was written; "), "{e}");
        assert!(e.to_string().ends_with("--time-limit SECONDS"), "{e}");
        // The limit of --max-cost names the factor as the other way to allow more.
        let b = Budget::new(1e-12).unwrap().with_estimate_time_limit();
        let d = b.deadline(&crate::progress::Silent);
        std::thread::sleep(std::time::Duration::from_millis(1));
        assert!(crate::progress::Progress::cancelled(&d));
        let Err(Stopped::Time(e)) = b.stopped(&d, "the design") else { panic!("not a time stop") };
        assert!(!e.explicit && e.limit == 3.6e-9, "{e:?}");
        assert!(e.to_string().ends_with("(or --max-cost FACTOR, whose time limit is FACTOR times 3600 s)"), "{e}");
    }

    #[test]
    fn the_allowance_is_the_work_limit_in_evaluations_and_never_below_the_count() {
        let of = |evaluations: f64, operations: f64| Estimate {
            evaluations,
            ..Estimate::work(operations, Driver::Grid, String::new())
        };
        let b = Budget::default();
        // 1000 evaluations counted at 3e12 operations: ten times the count fits the limit.
        assert_eq!(b.allowance(&of(1000.0, 3.0e12)), Some(10_000));
        assert_eq!(Budget::new(2.0).unwrap().allowance(&of(1000.0, 3.0e12)), Some(20_000));
        // A count at or beyond the limit is allowed no less than itself.
        assert_eq!(b.allowance(&of(1000.0, 6.0e13)), Some(1000));
        // No region search, or no work: no allowance.
        assert_eq!(b.allowance(&of(0.0, 1.0e12)), None);
        assert_eq!(b.allowance(&of(10.0, 0.0)), None);
        // A huge allowance saturates.
        assert_eq!(Budget::new(1e300).unwrap().allowance(&of(1e10, 1.0)), Some(u64::MAX));
        // The running bound carries it; a stop at it is a count stop naming both numbers.
        let d = b.running(&crate::progress::Silent, &of(3.0, 3.0e13));
        assert_eq!(d.allowance(), Some(3));
        crate::progress::Progress::evaluated(&d, 4);
        assert!(crate::progress::Progress::cancelled(&d));
        let Err(Stopped::Count(e)) = b.stopped(&d, "the catalogue") else { panic!("not a count stop") };
        assert_eq!((e.allowed, e.used), (3, 4));
        assert!(e
            .to_string()
            .starts_with("the catalogue was stopped at its allowance of 3 monodromy evaluations (4 made"));
    }
}
