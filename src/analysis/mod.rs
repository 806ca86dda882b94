//! Analyses of an assembled model; each returns a serialisable result object.

pub mod basis;
pub mod buckling;
pub mod campbell;
pub mod chart;
pub mod cost;
pub mod criterion;
pub mod damping;
pub mod floquet;
pub(crate) mod interval;
pub mod limits;
pub mod ltp;
pub mod modes;
mod operating;
pub(crate) mod orbit;
pub mod reduction;
pub mod regions;
pub mod response;
mod rotor;
pub(crate) mod settings;
pub mod unbalance;
pub mod warnings;

pub use criterion::Criterion;
pub use interval::Interval;
pub use operating::{
    BandRequest, BandRequestBuilder, ChartGrid, ChartRequest, OperatingPoint, DEFAULT_BAND_RANGE, MAX_CHART_AXIS,
};
pub use rotor::Rotor;
pub use settings::{Basis, ModeCount, MonodromyMethod, Settings, SettingsError, SettingsRule, OVERDAMPED_RATIO};

use crate::linalg::LinalgError;
use thiserror::Error;

/// Failures of an analysis.
#[derive(Debug, Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum AnalysisError {
    /// Dense linear algebra failed.
    #[error(transparent)]
    Linalg(#[from] LinalgError),
    /// M (reduced modes) is zero or larger than the number of finite modes.
    #[error("the reduced model asks for {requested} modes but the model has {available} finite modes (analysis.reduced_modes must be between 1 and {available})")]
    ReducedModes {
        /// Requested M.
        requested: usize,
        /// Finite undamped modes of the model.
        available: usize,
    },
    /// A stable band was asked around a φ outside the window searched.
    #[error("phi_op = {phi} rad/s lies outside the phi window {window:.2} rad/s searched for its band")]
    OutsideWindow {
        /// φ_op (rad/s).
        phi: f64,
        /// The window (rad/s).
        window: Interval,
    },
    /// The modal solve behind the reduced model (Eq. 22) did not resolve its basis: the
    /// modes are far from M-orthonormal (masses or stiffnesses spanning too many orders of
    /// magnitude, e.g. a shunt inductance of 1e8 H and more).
    #[error("the {modes} modes of the reduced model are not resolved by the modal solve: their mass matrix deviates from the identity by {drift:.3e} (above 0.1); the masses and stiffnesses span too many orders of magnitude (check L, C_f and R of the shunt branches)")]
    ReducedBasis {
        /// M.
        modes: usize,
        /// max|ΦᵀMΦ − I| (−).
        drift: f64,
    },
    /// The Floquet points of a region search fail the β = 0 check
    /// ([`floquet::PointIssue::ZeroLoad`]): the unloaded monodromy misses exp(λT), so every
    /// verdict of the search would be noise (e.g. a shunt resistance of 1e18 Ω: decay
    /// rates 10¹⁵ times the whirl frequencies, beyond what f64 exponentials resolve).
    #[error("the Floquet points at phi = {} rad/s are not reliable ({issue}): a region search on them would report noise; check the model's parameters for orders of magnitude (R, L, C_f, eta)", short(*phi))]
    Unreliable {
        /// φ of the failed check (rad/s).
        phi: f64,
        /// What the check found.
        issue: floquet::PointIssue,
    },
    /// The time response is stiff: RK4's stability needs more than
    /// [`response::STIFFNESS_LIMIT`] times the steps its accuracy needs.
    #[error("the time response at phi = {} rad/s is stiff: B0 has an eigenvalue of modulus {rate:.3e} 1/s (strong damping: a large R or eta), and RK4 would need {steps:.3e} steps per period, more than {} times the {accuracy_steps} its accuracy needs: not integrated (`rotorshunt floquet` gives the stability without it)", short(*phi), response::STIFFNESS_LIMIT)]
    StiffResponse {
        /// φ (rad/s).
        phi: f64,
        /// Spectral radius of B0 (1/s).
        rate: f64,
        /// Steps per period RK4's stability needs.
        steps: f64,
        /// Steps per period its accuracy needs.
        accuracy_steps: f64,
    },
    /// The time response outgrew f64: its state is not finite from `time` on.
    #[error("the time response at phi = {} rad/s, beta = {} is not finite from t = {time:.6e} s on (it outgrows f64 within the {periods} periods asked): lower --beta or --periods", short(*phi), short(*beta))]
    ResponseNotFinite {
        /// φ (rad/s).
        phi: f64,
        /// β.
        beta: f64,
        /// Time of the first non-finite state (s).
        time: f64,
        /// Periods asked for.
        periods: usize,
    },
    /// The model has no whirl mode at the speed: every eigenvalue is non-oscillatory
    /// (|Im λ| ≤ oscillation_tolerance·|λ|) or not finite.
    #[error("no whirl mode at speed {speed} rad/s: all {eigenvalues} eigenvalues are non-oscillatory or not finite (analysis.oscillation_tolerance = {tolerance})", speed = crate::analysis::limits::number(*speed), tolerance = crate::analysis::limits::number(*tolerance))]
    NoWhirlModes {
        /// Ω (rad/s).
        speed: f64,
        /// Eigenvalues found.
        eigenvalues: usize,
        /// The oscillation tolerance in force.
        tolerance: f64,
    },
    /// A request built in code (a catalogue, a band) breaks a parameter rule
    /// ([`limits`]); the command line checks its flags by the same rules first.
    #[error("the {} of the request {}", quantity_name(.0.quantity), .0)]
    Request(#[from] limits::ParamError),
    /// Settings built in code break a rule of the `[analysis]` table
    /// ([`Settings::validate`]); the file layer refuses such a table first.
    #[error(transparent)]
    Settings(#[from] settings::SettingsError),
    /// A response asked at a shaft node the model does not have.
    #[error("node {node} is off the shaft: the shaft has nodes 0 to {last}")]
    ProbeNodeOffShaft {
        /// The node asked for.
        node: usize,
        /// The last node.
        last: usize,
    },
    /// A probe of a response whose DOF the system does not have (a probe built by hand).
    #[error("the probe's DOF {dof} is not in the system, which has {dofs} DOFs")]
    ProbeOffSystem {
        /// The DOF asked for.
        dof: usize,
        /// The system's DOFs.
        dofs: usize,
    },
    /// The dynamic stiffness is singular at a speed of the grid: the speed is exactly an
    /// undamped critical speed, where the steady-state response is unbounded.
    #[error("the dynamic stiffness is singular at speed {speed} rad/s: the speed is an undamped critical speed of the model (no damping acts on that mode) and the response there is unbounded; move the speed grid off it or add damping (eta, R)", speed = crate::analysis::limits::number(*speed))]
    SingularAtSpeed {
        /// Ω (rad/s).
        speed: f64,
    },
    /// A speed range without any speed.
    #[error("the speed range is empty: give at least one speed (rad/s)")]
    NoSpeeds,
    /// Speeds of a response or damping range that do not ascend strictly.
    #[error(
        "the speeds must ascend strictly: speed {index} is {speed} rad/s, not above the previous {previous} rad/s"
    )]
    SpeedsNotAscending {
        /// Index of the offending speed.
        index: usize,
        /// Its value (rad/s).
        speed: f64,
        /// The speed before it (rad/s).
        previous: f64,
    },
    /// A whirl mode tag the model does not have at the first speed of a range.
    #[error("the model has no whirl mode `{label}` at speed {speed} rad/s; its lowest modes there are {}", tag_list(.available), speed = crate::analysis::limits::number(*speed))]
    UnknownMode {
        /// The tag asked for, e.g. `fr1`.
        label: String,
        /// The speed the tags are taken at (rad/s).
        speed: f64,
        /// The tags the model has there.
        available: Vec<String>,
    },
    /// Matrices given for a linear time-periodic system do not make one
    /// ([`ltp::LtpSystem`]).
    #[error(transparent)]
    Ltp(#[from] ltp::LtpError),
    /// The static part of the load alone buckles the model: α ≥ 1, or, on a circuit that
    /// makes the supports softer than the open circuit P_cr is computed with, K − αP_cr·S
    /// not positive definite (the loaded basis is then undefined).
    #[error("the static load αP_cr = {alpha} × {critical_load:.6e} N is at or above the buckling load of the model as assembled (alpha must be below 1, and below the buckling ratio of the circuit's supports)")]
    StaticLoadBuckles {
        /// α.
        alpha: f64,
        /// P_cr (N).
        critical_load: f64,
    },
}

impl AnalysisError {
    /// The error's kind, named as docs/errors.md heads its section: a request's or a
    /// setting's broken rule is the file layer's kind of that rule. Matched here, in the
    /// crate, so that a new variant has a name before it compiles (the enum is
    /// `#[non_exhaustive]` to users).
    pub fn kind(&self) -> &'static str {
        match self {
            AnalysisError::Linalg(_) => "Linalg",
            AnalysisError::ReducedModes { .. } => "ReducedModes",
            AnalysisError::StaticLoadBuckles { .. } => "StaticLoadBuckles",
            AnalysisError::Ltp(_) => "Ltp",
            AnalysisError::OutsideWindow { .. } => "OutsideWindow",
            AnalysisError::ResponseNotFinite { .. } => "ResponseNotFinite",
            AnalysisError::NoWhirlModes { .. } => "NoWhirlModes",
            AnalysisError::ReducedBasis { .. } => "ReducedBasis",
            AnalysisError::StiffResponse { .. } => "StiffResponse",
            AnalysisError::Unreliable { .. } => "Unreliable",
            AnalysisError::ProbeNodeOffShaft { .. } => "ProbeNodeOffShaft",
            AnalysisError::ProbeOffSystem { .. } => "ProbeOffSystem",
            AnalysisError::SingularAtSpeed { .. } => "SingularAtSpeed",
            AnalysisError::NoSpeeds => "NoSpeeds",
            AnalysisError::SpeedsNotAscending { .. } => "SpeedsNotAscending",
            AnalysisError::UnknownMode { .. } => "UnknownMode",
            AnalysisError::Request(e) => e.rule.kind(),
            AnalysisError::Settings(e) => e.rule.kind(),
        }
    }

    /// Whether the caller asked for something that breaks a rule (a request's or a
    /// setting's value, a probe off the shaft, speeds missing or out of order, a mode the
    /// rotor does not have), rather than an analysis failing on valid input: what the
    /// command line exits 2 for, not 1 (docs/errors.md). Matched here, in the crate, so
    /// that a new variant is sorted before it compiles.
    pub fn is_bad_input(&self) -> bool {
        match self {
            AnalysisError::Request(_)
            | AnalysisError::Settings(_)
            | AnalysisError::ProbeNodeOffShaft { .. }
            | AnalysisError::NoSpeeds
            | AnalysisError::SpeedsNotAscending { .. }
            | AnalysisError::UnknownMode { .. }
            | AnalysisError::Ltp(_) => true,
            AnalysisError::Linalg(_)
            | AnalysisError::ReducedModes { .. }
            | AnalysisError::StaticLoadBuckles { .. }
            | AnalysisError::OutsideWindow { .. }
            | AnalysisError::ResponseNotFinite { .. }
            | AnalysisError::NoWhirlModes { .. }
            | AnalysisError::ReducedBasis { .. }
            | AnalysisError::StiffResponse { .. }
            | AnalysisError::Unreliable { .. }
            | AnalysisError::ProbeOffSystem { .. }
            | AnalysisError::SingularAtSpeed { .. } => false,
        }
    }
}

/// The first `TAGS_LISTED` tags of each whirl direction of `tags` (forward tags start
/// with `f`, backward with `b`), and how many more there are.
pub fn tag_list(tags: &[String]) -> String {
    let mut shown = Vec::new();
    let mut more = 0;
    for prefix in ["f", "b"] {
        let of: Vec<&String> = tags.iter().filter(|t| t.starts_with(prefix)).collect();
        more += of.len().saturating_sub(TAGS_LISTED);
        shown.extend(of.into_iter().take(TAGS_LISTED).map(String::as_str));
    }
    let mut s = shown.join(", ");
    if more > 0 {
        s += &format!(" (and {more} more)");
    }
    s
}

/// Tags per whirl direction an [`AnalysisError::UnknownMode`] message lists: enough for
/// the rotor modes and the electrical modes of a few branches of interest.
const TAGS_LISTED: usize = 8;

/// A number as plain text, in exponent form outside 1e-4…1e15 (1e300, not 301 digits).
fn short(v: f64) -> String {
    if v == 0.0 || (1e-4..1e15).contains(&v.abs()) {
        v.to_string()
    } else {
        format!("{v:e}")
    }
}

/// The name of a quantity in a library request's messages.
fn quantity_name(q: limits::Quantity) -> &'static str {
    use limits::Quantity as Q;
    match q {
        Q::Frequency => "frequency",
        Q::RangeLow => "range's low end",
        Q::RangeHigh => "range's high end",
        Q::Load => "load coefficient",
        Q::BetaMax => "beta_max",
        Q::Level => "level",
        Q::OperatingFrequency => "operating frequency",
        Q::Speed => "speed",
        Q::Count => "count",
        Q::CostFactor => "cost factor",
        Q::TimeLimit => "time limit",
        Q::Limit => "limit",
    }
}
