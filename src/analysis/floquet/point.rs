//! The result of one (φ, β) point: its multipliers, verdict, status and, where the point
//! is not trusted, the reason ([`PointIssue`]).

use super::product::ScaledProduct;
use super::{fast, ZERO_LOAD_TOLERANCE};
use crate::analysis::criterion::Threshold;
use serde::{Deserialize, Serialize};

/// Largest |ln max|μ|| reported as a plain `max_multiplier`; beyond it the value is
/// saturated to f64::MAX and only the logarithm is exact.
const LN_F64_MAX: f64 = 709.0;

/// Outcome of one (φ, β) point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PointStatus {
    /// Multipliers computed.
    Ok,
    /// Multipliers computed, but less accurate than the path states; the point's
    /// `reason` says why (a [`PointIssue`]).
    Inaccurate,
    /// The eigenvalue iteration failed or the monodromy was not finite: no verdict.
    Failed,
}

/// Why a point is `inaccurate` or `failed`: serialised (JSON `reason`) as its name, its
/// numbers and the text of its `Display` (`message`), which the CLI prints next to the
/// status.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PointIssue {
    /// The fast path's per-φ Chebyshev interpolant did not reach its tolerance with
    /// `terms` terms (or its samples were not finite).
    Interpolant {
        /// Chebyshev terms of the last attempt.
        terms: usize,
    },
    /// The fast path's parametric coupling per exponential a = x_max·‖τB1‖ is above
    /// [`fast::MAX_COUPLING`] even at the most CFM4 steps (`steps` per period): the CFM4
    /// error is not controlled (β·P_cr huge against the period).
    Coupling {
        /// a (−).
        coupling: f64,
        /// CFM4 steps per period.
        steps: usize,
    },
    /// The β = 0 monodromy of the same path and steps misses exp(λ_k T) by `deviation`
    /// (> [`ZERO_LOAD_TOLERANCE`]; infinite when it has no finite multipliers).
    ZeroLoad {
        /// max_k | |μ_k| − |exp(λ_k T)| | / max_k |exp(λ_k T)|, moduli sorted (−).
        deviation: f64,
    },
    /// B0's eigenvalues, the reference of the β = 0 check, could not be computed.
    NoZeroLoadReference,
    /// The eigenvalue iteration on the monodromy did not converge.
    Eigenvalues,
    /// The monodromy, its multipliers or ln max|μ| are not finite.
    NotFinite,
}

impl PointIssue {
    /// The status a point with this issue has.
    pub fn status(&self) -> PointStatus {
        match self {
            PointIssue::Eigenvalues | PointIssue::NotFinite => PointStatus::Failed,
            _ => PointStatus::Inaccurate,
        }
    }
}

impl std::fmt::Display for PointIssue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PointIssue::Interpolant { terms } => {
                write!(f, "the per-phi Chebyshev interpolant did not converge ({terms} terms)")
            }
            PointIssue::Coupling { coupling, steps } => write!(
                f,
                "the parametric coupling per CFM4 exponential is {coupling:.3e} (above {}) even at {steps} steps per period: beta is too large for this period",
                fast::MAX_COUPLING
            ),
            PointIssue::ZeroLoad { deviation } if deviation.is_finite() => write!(
                f,
                "beta = 0 check: the multipliers at beta = 0 deviate from exp(lambda T) by {deviation:.3e} (tolerance {ZERO_LOAD_TOLERANCE:e})"
            ),
            PointIssue::ZeroLoad { .. } => write!(f, "beta = 0 check: the monodromy at beta = 0 has no finite multipliers"),
            PointIssue::NoZeroLoadReference => {
                write!(f, "beta = 0 check: the eigenvalues of B0 (its reference) could not be computed")
            }
            PointIssue::Eigenvalues => write!(f, "the eigenvalue iteration on the monodromy did not converge"),
            PointIssue::NotFinite => write!(f, "the monodromy or its multipliers are not finite"),
        }
    }
}

/// The JSON form of a [`PointIssue`]: the issue's name (`issue`), its numbers and the
/// text of its `Display` (`message`, not read back). An infinite `deviation` is `null`.
#[derive(Serialize, Deserialize)]
struct IssueJson {
    #[serde(flatten, with = "IssueData")]
    issue: PointIssue,
    #[serde(default, skip_deserializing)]
    message: String,
}

/// [`PointIssue`]'s variants as JSON names them (serde's mirror of the enum).
#[derive(Serialize, Deserialize)]
#[serde(remote = "PointIssue", tag = "issue", rename_all = "kebab-case")]
enum IssueData {
    Interpolant {
        terms: usize,
    },
    Coupling {
        coupling: f64,
        steps: usize,
    },
    ZeroLoad {
        #[serde(with = "crate::numbers::infinite_as_null")]
        deviation: f64,
    },
    NoZeroLoadReference,
    Eigenvalues,
    NotFinite,
}

impl Serialize for PointIssue {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        IssueJson { issue: *self, message: self.to_string() }.serialize(serializer)
    }
}

impl<'de> Deserialize<'de> for PointIssue {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        Ok(IssueJson::deserialize(deserializer)?.issue)
    }
}

/// The scalar outcome of one (φ, β) point: what a chart stores.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct PointSummary {
    /// Excitation frequency φ (rad/s).
    pub phi: f64,
    /// Dynamic load coefficient β (−).
    pub beta: f64,
    /// max|μ| (saturated at f64::MAX beyond e^709; see `ln_max_multiplier`).
    pub max_multiplier: f64,
    /// ln max|μ|, exact even when max|μ| would overflow.
    pub ln_max_multiplier: f64,
    /// Growth rate ln(max|μ|)/T (1/s).
    pub growth_rate: f64,
    /// Not unstable by the settings' threshold ([`Threshold`]).
    pub stable: bool,
    /// Whether the point was computed normally.
    pub status: PointStatus,
    /// Why it was not (absent, and not serialised, when `status` is `ok`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<PointIssue>,
}

impl PointSummary {
    /// Mark an `ok` point with `issue` (a point already flagged keeps its first reason).
    pub fn flag(&mut self, issue: Option<PointIssue>) {
        if let (Some(issue), PointStatus::Ok) = (issue, self.status) {
            self.status = issue.status();
            self.reason = Some(issue);
        }
    }
}

/// Floquet result at one point: the summary and all multipliers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloquetPoint {
    /// φ, β, max|μ|, growth rate, verdict, status.
    #[serde(flatten)]
    pub summary: PointSummary,
    /// Multipliers e^{s}·(re, im) with s = `multiplier_log_scale` (0 unless huge).
    pub multipliers: Vec<[f64; 2]>,
    /// Natural-log scale factor of `multipliers`.
    pub multiplier_log_scale: f64,
}

impl FloquetPoint {
    /// A point without a verdict: placeholders (f64::MAX) for its numbers, the reason.
    pub(super) fn failed(phi: f64, beta: f64, issue: PointIssue) -> FloquetPoint {
        FloquetPoint {
            summary: PointSummary {
                phi,
                beta,
                max_multiplier: f64::MAX,
                ln_max_multiplier: f64::MAX,
                growth_rate: f64::MAX,
                stable: false,
                status: PointStatus::Failed,
                reason: Some(issue),
            },
            multipliers: Vec::new(),
            multiplier_log_scale: 0.0,
        }
    }

    /// Multipliers and verdict from a monodromy, with the status given when they are
    /// computed (`failed`, with its reason, when they cannot be).
    pub fn from_monodromy(
        phi: f64,
        beta: f64,
        mono: &ScaledProduct,
        threshold: Threshold,
        status: PointStatus,
    ) -> FloquetPoint {
        let mut p = FloquetPoint::from_monodromy_with(phi, beta, mono, threshold, None);
        if p.summary.status == PointStatus::Ok {
            p.summary.status = status;
        }
        p
    }

    /// Multipliers and verdict from a monodromy, flagged with `issue` (if any).
    pub fn from_monodromy_with(
        phi: f64,
        beta: f64,
        mono: &ScaledProduct,
        threshold: Threshold,
        issue: Option<PointIssue>,
    ) -> FloquetPoint {
        let mut balanced = mono.matrix.clone();
        crate::linalg::balance(&mut balanced);
        let Ok(ev) = crate::linalg::seq::eigenvalues(balanced.as_ref()) else {
            return FloquetPoint::failed(phi, beta, PointIssue::Eigenvalues);
        };
        if ev.iter().any(|z| !z.re.is_finite() || !z.im.is_finite()) || !mono.log_scale.is_finite() {
            return FloquetPoint::failed(phi, beta, PointIssue::NotFinite);
        }
        let max_scaled = ev.iter().map(|z| z.norm()).fold(0.0, f64::max);
        let ln_max = max_scaled.ln() + mono.log_scale;
        if !ln_max.is_finite() {
            // All multipliers zero (or a modulus overflowing): no finite ln max|μ|.
            return FloquetPoint::failed(phi, beta, PointIssue::NotFinite);
        }
        let period = 2.0 * std::f64::consts::PI / phi;
        let (multipliers, multiplier_log_scale) = if mono.log_scale.abs() < LN_F64_MAX / 2.0 {
            let f = mono.log_scale.exp();
            (ev.iter().map(|z| [z.re * f, z.im * f]).collect(), 0.0)
        } else {
            (ev.iter().map(|z| [z.re, z.im]).collect(), mono.log_scale)
        };
        FloquetPoint {
            summary: PointSummary {
                phi,
                beta,
                max_multiplier: if ln_max < LN_F64_MAX { ln_max.exp() } else { f64::MAX },
                ln_max_multiplier: ln_max,
                growth_rate: ln_max / period,
                stable: !threshold.unstable(phi, ln_max),
                status: issue.map_or(PointStatus::Ok, |i| i.status()),
                reason: issue,
            },
            multipliers,
            multiplier_log_scale,
        }
    }
}
