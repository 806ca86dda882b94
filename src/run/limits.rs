//! The limits of a run ([`Budget`]): the counts before it starts ([`MAX_OPERATIONS`],
//! [`MAX_BYTES`], times the `--max-cost` factor), and, while it runs, its time limit
//! measured there and its allowance of monodromy evaluations, counted by the searches as
//! they make them; the refusal of a run counted beyond them ([`CostError`]) and the
//! errors of a run stopped while it ran ([`Stopped`]).

use crate::analysis::cost::{Driver, Estimate, Part};
use crate::analysis::limits::{self, compact, ParamError};
use serde::Serialize;
use thiserror::Error;

/// Most floating-point operations a run may be counted at before it starts: 5·10¹³. The
/// bundled problems' largest count, the robust speed-range design's 3.0e13 (each
/// candidate's nominal build at its 5 speeds and 4 refinements, and its 4 corners at the
/// worst speed; docs/errors.md, `Cost`), is 1.7 times below this. The runs the limit is
/// for are counted at 10¹⁴ and far beyond (φ = 1e-3 for 1e3 in a response, φ near
/// 1e-300, a robust design of every tolerance at a low φ_op): a slip of units or digits
/// more often than an intent, and `--max-cost` admits them deliberately. What a count
/// takes is measured while the run runs ([`MAX_SECONDS`]). On the shared 2-core host this
/// was written on, one core did 1.2e10 of them a second in the response's RK4 loop (scalar
/// complex arithmetic), 2.4e10 in a chart (matrix products), so a run counted at the limit
/// is 35 to 70 minutes of computing there; an unbalance response's small sparse solves
/// are slower per operation (about 3e9 a second), and the time limit bounds those.
pub const MAX_OPERATIONS: f64 = 5.0e13;

/// Most bytes of dense matrices a run may hold at once: 400 MiB. With the process's own
/// ~20 MB the peak stays under 500 MB; `check` reaches it near 880 shaft elements, the
/// whirl solvers (`modes`, `campbell`, `regions`, `band`) near 440.
pub const MAX_BYTES: f64 = 400.0 * 1024.0 * 1024.0;

/// The command line's time limit while a run runs (s of wall time, times the
/// `--max-cost` factor): one hour, measured on the machine that runs it.
pub const MAX_SECONDS: f64 = 3600.0;

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
        assert!(e.to_string().starts_with("the chart would need about 1.0e300 floating-point operations, more than the 5.0e13 allowed: 91 points; change LowFrequency"), "{e}");
        let nan = Estimate::work(f64::NAN, Driver::Grid, String::new());
        assert!(b.admit("x", &nan, &|_| String::new()).is_err(), "a NaN estimate is refused");
        assert!(Budget::new(2.0)
            .unwrap()
            .admit("the chart", &Estimate::work(7.5e13, Driver::Grid, String::new()), &|_| String::new())
            .is_ok());
        assert!(b
            .admit("the chart", &Estimate::work(7.5e13, Driver::Grid, String::new()), &|_| String::new())
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
        // 1000 evaluations counted at 5e12 operations: ten times the count fits the limit.
        assert_eq!(b.allowance(&of(1000.0, 5.0e12)), Some(10_000));
        assert_eq!(Budget::new(2.0).unwrap().allowance(&of(1000.0, 5.0e12)), Some(20_000));
        // A count at or beyond the limit is allowed no less than itself.
        assert_eq!(b.allowance(&of(1000.0, 1.0e14)), Some(1000));
        // No region search, or no work: no allowance.
        assert_eq!(b.allowance(&of(0.0, 1.0e12)), None);
        assert_eq!(b.allowance(&of(10.0, 0.0)), None);
        // A huge allowance saturates.
        assert_eq!(Budget::new(1e300).unwrap().allowance(&of(1e10, 1.0)), Some(u64::MAX));
        // The running bound carries it; a stop at it is a count stop naming both numbers.
        let d = b.running(&crate::progress::Silent, &of(3.0, 5.0e13));
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
