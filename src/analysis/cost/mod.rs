//! What a run costs, estimated from its inputs before it starts, and the limits beyond
//! which a command refuses it (written once, here). A run admitted is bounded again while
//! it runs, on whatever machine: [`Budget::deadline`] stops it at its time limit measured
//! there (on the command line by default the same [`MAX_SECONDS`] times the factor;
//! `--time-limit`), and
//! [`Budget::stopped`] turns the stop into a [`TimeLimitError`] before anything is written.
//!
//! Two resources are bounded:
//! - **time**: seconds of one core of the reference machine (the shared 2-core host the
//!   rates below were measured on; a faster host finishes sooner), at most
//!   [`MAX_SECONDS`];
//! - **memory**: bytes of the dense matrices a run holds at once, at most [`MAX_BYTES`].
//!
//! A [`Budget`] multiplies both limits (`--max-cost FACTOR`). Estimates are sums of counted
//! operations times measured rates: the dense eigensolvers from the model's DOFs (before
//! anything is assembled), and the Floquet work from the reduced model a command builds
//! anyway (its size M, its lowest and highest frequency and the parametric coupling of
//! B1), summed over the φ values a run visits: per-φ tables, CFM4 steps (whose number per
//! period grows like 1/φ and like ω_max/φ, and doubles with β), β bracket samples (β_max
//! over the bracket step), seeds and the guard lattice of a range. They are cheap
//! (closed forms and sums over at most a few thousand φ values) and mostly upper bounds:
//! a search counts every evaluation its bounds allow.

mod dense;
mod floquet;
mod regions;

pub use dense::{dense, model_dofs, unbalance, Dense};
pub use floquet::{chart, floquet_point, response, response_of, response_steps, PointCost};
pub use regions::{band, catalogue, points, scan, CatalogueWork, DESIGN_BAND_EVALUATIONS};

use super::floquet::{FloquetSystem, ALIAS_MARGIN, ALIAS_ORDERS};
use super::limits::{self, compact, ParamError};
use super::regions::start::SCREENING_TOLERANCE;
use super::regions::{seeds::Seed, RegionSettings, CENTRE_WINDOW};
use super::{Criterion, Interval, MonodromyMethod};
use serde::Serialize;
use thiserror::Error;

/// Most seconds of computing (one core of the reference machine) a run may be estimated
/// at: one hour. The estimates are upper bounds (every evaluation a search's bounds allow,
/// at the largest measured rates), 2 to 200 times the measured time: the Fig. 11
/// catalogue is estimated at 9 s and takes 1.6 s, with `--beta-max 100` at 385 s and
/// takes 2.1 s. The bundled problems' largest estimate, the clear-bands design (284 s),
/// is 12 times below the limit. The runs the limit is for are estimated at 10⁴ s and
/// far beyond (φ = 1e-3 for 1e3 in a response: 4·10⁴ s; φ near 1e-300: 10³⁰⁰ s): a slip of
/// units or digits more often than an intent, and `--max-cost` admits them deliberately.
pub const MAX_SECONDS: f64 = 3600.0;

/// Most bytes of dense matrices a run may hold at once: 400 MiB. With the process's own
/// ~20 MB the peak stays under 500 MB; `check` reaches it near 880 shaft elements, the
/// whirl solvers (`modes`, `campbell`, `regions`, `band`) near 440.
pub const MAX_BYTES: f64 = 400.0 * 1024.0 * 1024.0;

// Rates of the kernels on the reference machine (one thread, release build), n the state
// dimension 2M of the reduced model or the DOFs of the full one. Measured with the
// problems' models at M = 4, 8, 16 and 64–800 shaft elements; each rate is the largest
// seen, so the estimates lean high.

/// One CFM4 exponential applied (split-form product and its share of the batched
/// Chebyshev sums): 3.0e-7, 1.2e-6 and 6e-6 s at n = 8, 16, 32.
const STEP_N3: f64 = 3.0e-10;
const STEP_FIXED: f64 = 2.0e-7;
/// Eigenvalues of the n×n monodromy (balanced): 7e-6, 6e-5, 2.9e-4 s at n = 8, 16, 32.
const EIG_N3: f64 = 1.5e-8;
/// One exponential at a Chebyshev point (Taylor, split form): 2e-6, 6e-6, 3.6e-5 s.
const EXP_N3: f64 = 1.5e-9;
const EXP_FIXED: f64 = 1.5e-6;
/// One DSTM step (Padé exponential and product): ~22 µs at n = 16.
const DSTM_N3: f64 = 1.0e-8;
/// One RK4 step of the response (four dense right-hand sides): 4.6e-7 s at n = 8,
/// 1.5e-6 s at n = 16.
const RK4_N2: f64 = 8.0e-9;
/// The symmetric-definite eigensolution of the full model (buckling load or modal basis):
/// 0.24 s at 808 DOFs, 1.8 s at 1 608.
const DENSE_EIGEN_N3: f64 = 4.5e-10;
/// The quadratic eigenproblem of the full model by shift-invert (complex 2n × 2n): 0.35 s
/// at 208 DOFs, 24 s at 808, 261 s at 1 608: per (2n)³.
const QEP_2N3: f64 = 8.0e-9;
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

/// One numeric sparse LU factorisation and solve of the dynamic stiffness per DOF
/// (`analysis::unbalance`; the shaft's band keeps the factors' fill fixed per DOF):
/// 44–51 µs at 136 DOFs (0.35 µs per DOF, `cargo bench --bench unbalance`, host shared);
/// 1e-6 s per DOF leans high, as the other rates do.
const UNBALANCE_SOLVE_N: f64 = 1.0e-6;

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
    /// Seconds (time) or bytes (memory).
    pub amount: f64,
    /// The input that drives it.
    pub driver: Driver,
    /// How it comes about, e.g. `91 points × 2.4e304 CFM4 steps per period`.
    pub detail: String,
}

/// The estimated cost of a run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Estimate {
    /// Seconds of computing on one core of the reference machine.
    pub time: Part,
    /// Bytes of dense matrices held at once.
    pub memory: Part,
}

impl Estimate {
    /// Nothing.
    pub fn zero() -> Estimate {
        let part = |driver| Part { amount: 0.0, driver, detail: String::new() };
        Estimate { time: part(Driver::Grid), memory: part(Driver::Dofs) }
    }

    /// A time-only estimate.
    pub fn time(seconds: f64, driver: Driver, detail: String) -> Estimate {
        Estimate { time: Part { amount: seconds, driver, detail }, ..Estimate::zero() }
    }

    /// This run followed by `other`: times add (the larger part's driver kept), memory is
    /// the larger peak.
    pub fn then(self, other: Estimate) -> Estimate {
        let amount = self.time.amount + other.time.amount;
        let time = if other.time.amount > self.time.amount || self.time.amount.is_nan() {
            Part { amount, ..other.time }
        } else {
            Part { amount, ..self.time }
        };
        let memory = if other.memory.amount > self.memory.amount { other.memory } else { self.memory };
        Estimate { time, memory }
    }

    /// `count` runs of this one in sequence (`what` names them). The count becomes the
    /// driver unless one run's own driver is an extreme input (a low frequency, a load).
    pub fn times(mut self, count: f64, driver: Driver, what: &str) -> Estimate {
        self.time.amount *= count;
        if count > 1.0 {
            self.time.detail = if self.time.detail.is_empty() {
                format!("{} {what}", compact_count(count))
            } else {
                format!("{} {what}, each: {}", compact_count(count), self.time.detail)
            };
            if !matches!(self.time.driver, Driver::LowFrequency | Driver::Load | Driver::Speed) {
                self.time.driver = driver;
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

/// Seconds as a person reads them.
fn seconds_text(s: f64) -> String {
    if !s.is_finite() {
        "an unbounded time".into()
    } else if s >= 1e7 {
        format!("{s:.1e} s")
    } else if s >= 7200.0 {
        format!("{:.1} h", s / 3600.0)
    } else {
        format!("{s:.0} s")
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
    /// Computing time.
    Time,
    /// Memory of dense matrices.
    Memory,
}

/// A run refused before it started: its estimated cost is beyond the limit.
#[derive(Debug, Clone, PartialEq, Error, Serialize)]
#[error(
    "{what} would {} {}, more than the {}{} allowed: {detail}; change {parameter}, or allow FACTOR times more with --max-cost FACTOR",
    if *resource == Resource::Time { "take" } else { "need" },
    amount_text(*resource, *estimate),
    limit_text(*resource, *limit),
    if *factor == 1.0 { String::new() } else { format!(" (--max-cost {})", compact(*factor)) },
)]
pub struct CostError {
    /// What would run, e.g. `the chart`, `check`.
    pub what: String,
    /// Time or memory: which limit the estimate exceeds.
    pub resource: Resource,
    /// The estimate (s or bytes).
    pub estimate: f64,
    /// The limit (s or bytes), with the factor applied.
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
        (Resource::Time, true) => format!("about {} of computing", seconds_text(x)),
        (Resource::Memory, true) => format!("about {} of memory", bytes_text(x)),
        (_, false) => limit_text(resource, x),
    }
}

fn limit_text(resource: Resource, x: f64) -> String {
    match resource {
        Resource::Time => seconds_text(x),
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

/// The limits of a run: [`MAX_SECONDS`] and [`MAX_BYTES`] times a factor (`--max-cost`)
/// for its estimate before it starts, and a time limit measured while it runs
/// ([`RunningLimit`]: none for a library caller, who can stop the run itself; the
/// command line's `--time-limit`, by default the same seconds).
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
    /// The estimate's limit, [`Budget::seconds`] (the command line without `--time-limit`).
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

    /// This budget with the estimate's limit, [`Budget::seconds`], as its time limit
    /// while a run runs (the command line's default).
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
    /// that never passes without a limit).
    pub fn deadline<'a>(&self, progress: &'a dyn crate::progress::Progress) -> crate::progress::Deadline<'a> {
        crate::progress::Deadline::new(progress, self.time_limit().unwrap_or(f64::INFINITY))
    }

    /// The error of `what` when `deadline` (of this budget) stopped a step of it; what it
    /// computed is then incomplete and must not be kept.
    pub fn stopped(&self, deadline: &crate::progress::Deadline<'_>, what: &str) -> Result<(), TimeLimitError> {
        if !deadline.tripped() {
            return Ok(());
        }
        Err(TimeLimitError {
            what: what.to_string(),
            limit: self.time_limit().unwrap_or(f64::INFINITY),
            elapsed: deadline.elapsed(),
            explicit: matches!(self.running, RunningLimit::Given(_)),
        })
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

    /// The time limit (s).
    pub fn seconds(&self) -> f64 {
        MAX_SECONDS * self.factor
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
        if estimate.time.amount.is_nan() || estimate.time.amount > self.seconds() {
            return Err(refuse(Resource::Time, &estimate.time, self.seconds()));
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
        let cheap = Estimate::time(1.0, Driver::Grid, "x".into());
        assert!(b.admit("the chart", &cheap, &|_| "`--phi`".into()).is_ok());
        let dear = Estimate::time(1e300, Driver::LowFrequency, "91 points".into());
        let e = b.admit("the chart", &dear, &|d| format!("{d:?}")).unwrap_err();
        assert_eq!((e.resource, e.parameter.as_str()), (Resource::Time, "LowFrequency"));
        assert!(e.to_string().starts_with("the chart would take about 1.0e300 s of computing, more than the 3600 s allowed: 91 points; change LowFrequency"), "{e}");
        let nan = Estimate::time(f64::NAN, Driver::Grid, String::new());
        assert!(b.admit("x", &nan, &|_| String::new()).is_err(), "a NaN estimate is refused");
        assert!(Budget::new(2.0)
            .unwrap()
            .admit("the chart", &Estimate::time(1000.0, Driver::Grid, String::new()), &|_| String::new())
            .is_ok());
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
        let e = b.stopped(&d, "the chart").unwrap_err();
        assert!(e.explicit && e.limit == 1e-9 && e.elapsed > e.limit, "{e:?}");
        assert!(e.to_string().starts_with("the chart was stopped at its time limit of 1e-9 s (after "), "{e}");
        assert!(e.to_string().contains(" s, measured while it ran); nothing was written; "), "{e}");
        assert!(e.to_string().ends_with("--time-limit SECONDS"), "{e}");
        // The limit of --max-cost names the factor as the other way to allow more.
        let b = Budget::new(1e-12).unwrap().with_estimate_time_limit();
        let d = b.deadline(&crate::progress::Silent);
        std::thread::sleep(std::time::Duration::from_millis(1));
        assert!(crate::progress::Progress::cancelled(&d));
        let e = b.stopped(&d, "the design").unwrap_err();
        assert!(!e.explicit && e.limit == 3.6e-9, "{e:?}");
        assert!(e.to_string().ends_with("(or --max-cost FACTOR, whose time limit is FACTOR times 3600 s)"), "{e}");
    }
}
