//! What a design run found: its status, the starts, history and convex steps, the
//! findings of its objective, and the JSON shape of `report.json`.

use super::min_peak::PeakFindings;
use crate::analysis::basis::BasisReport;
use crate::design::evaluate::{Intrusion, OperatingBand};
use crate::design::robust::{Robustness, SpeedCheck};
use crate::design::sizing::RefinedCheck;
use crate::design::spec::DesignSpec;
use crate::design::verify::{DesignAtSpeed, Verification};
use crate::design::vibration::ConstraintCheck;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// How the run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Widest band: the tuned band is wider than the reference's, and verified.
    Improved,
    /// Widest band: no start beat the reference design, which is kept (and verified).
    Unchanged,
    /// Clear bands: every band is clear by its clearance, and verified.
    Feasible,
    /// No design inside the bounds was found that meets every requirement: clears every
    /// band (clear bands), meets the constraints (least peak response), or puts φ_op in a
    /// stable band at every speed (widest band).
    Infeasible,
    /// The design the optimiser found failed its independent verification
    /// ([`crate::design::verify`]): its band or clearances are not shown to hold.
    NotVerified,
    /// The design holds at its nominal component values but not at every build of its
    /// tolerance box (`[design.tolerances]`, `crate::design::robust`): the failing build
    /// is named in the verification.
    NotRobust,
    /// The run was stopped before it ended (a time limit, an allowance of evaluations, or
    /// its caller): the design is the best judged so far, neither optimised to the end nor
    /// verified ([`DesignOutcome::stop`] says what stopped it).
    Stopped,
}

impl Status {
    /// Whether the run produced a design that can be handed on (improved, unchanged or
    /// feasible, and verified).
    pub fn is_result(self) -> bool {
        matches!(self, Status::Improved | Status::Unchanged | Status::Feasible)
    }
}

/// One Nelder–Mead start.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StartReport {
    /// `reference`, `physics seed` or `halton k`.
    pub origin: String,
    /// Starting values (SI units).
    pub initial: Vec<f64>,
    /// Best values found (SI units).
    pub best: Vec<f64>,
    /// Objective at the best point (rad/s).
    pub objective: f64,
    /// Candidate designs evaluated by this start.
    pub evaluations: usize,
    /// Nelder–Mead iterations of this start.
    pub iterations: u64,
    /// argmin's termination reason (e.g. the simplex's spread below the tolerance).
    pub termination: String,
}

/// One entry of the optimiser history.
#[derive(Debug, Clone, Copy, Serialize, Deserialize)]
pub struct HistoryPoint {
    /// Start index (widest band) or 0 (clear bands).
    pub start: usize,
    /// Candidate evaluation count within the start / iteration of the convex steps.
    pub step: usize,
    /// Objective (rad/s: signed band width), total intrusion (rad/s) or peak amplitude
    /// with its penalty (m); +∞ (JSON `null`) where a penalty overflows.
    #[serde(with = "crate::numbers::infinite_as_null")]
    pub value: f64,
    /// Best value so far in this start (same unit as `value`).
    #[serde(with = "crate::numbers::infinite_as_null")]
    pub best: f64,
}

/// One sequential convex step.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ConvexStep {
    /// Iteration of the sequential convex run, from 1.
    pub iteration: usize,
    /// Trust region used (scaled units).
    pub trust: f64,
    /// Linearised constraints (one per intrusion).
    pub constraints: usize,
    /// Total intrusion before (rad/s).
    pub intrusion_before: f64,
    /// Total intrusion at the trial point (rad/s), if evaluated.
    pub intrusion_after: Option<f64>,
    /// Whether the step was taken.
    pub accepted: bool,
    /// Trial values (SI units).
    pub values: Vec<f64>,
    /// Clarabel's verdict on the step's QP (the elastic one's when the plain step was
    /// infeasible): `crate::design::qp::QpStatus`.
    pub qp_status: crate::design::qp::QpStatus,
}

/// What a run found that only its objective has.
#[derive(Debug, Clone)]
pub enum Findings {
    /// Widest stable band.
    WidestBand {
        /// The stable band around φ_op of the reference design at each speed.
        before: Vec<OperatingBand>,
        /// The same for the tuned design.
        after: Vec<OperatingBand>,
    },
    /// Clear bands.
    ClearBands {
        /// Tongues intruding into the widened bands, reference design.
        before: Vec<Intrusion>,
        /// The same for the tuned design (empty when feasible).
        after: Vec<Intrusion>,
        /// The linearised constraints at the final point had no solution inside the
        /// bounds (a sign that the bounds forbid clearing the bands).
        linear_infeasible: bool,
    },
    /// Least peak response: the reference, tuned, unconstrained and classic designs.
    MinPeak(Box<PeakFindings>),
}

/// Which [`Findings`] an objective's outcome has
/// ([`crate::design::objective::Objective::findings`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FindingsKind {
    /// [`Findings::WidestBand`]: the band around φ_op before and after.
    Bands,
    /// [`Findings::ClearBands`]: the tongues intruding into the operating bands.
    Intrusions,
    /// [`Findings::MinPeak`]: the peak responses (a run that judged nothing yet has
    /// [`Findings::WidestBand`], empty).
    Peak,
}

impl FindingsKind {
    /// The findings of a run that has judged nothing yet.
    pub fn empty(self) -> Findings {
        match self {
            FindingsKind::Bands | FindingsKind::Peak => Findings::WidestBand { before: Vec::new(), after: Vec::new() },
            FindingsKind::Intrusions => {
                Findings::ClearBands { before: Vec::new(), after: Vec::new(), linear_infeasible: false }
            }
        }
    }
}

/// The unbalance response of a design with a `[design.response]`, before and after, and
/// the damping ratios of its lowest whirls: report content.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct VibrationReport {
    /// The response node and speeds.
    pub response: crate::design::spec::Response,
    /// The reference design's response at the node (amplitude m, phase rad, peaks).
    pub before: crate::analysis::unbalance::UnbalanceResult,
    /// The tuned design's.
    pub after: crate::analysis::unbalance::UnbalanceResult,
    /// The unconstrained optimum's (min-peak-response with constraints).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unconstrained: Option<crate::analysis::unbalance::UnbalanceResult>,
    /// Damping ratios ζ of the lowest whirls over the operating speeds, reference design.
    pub damping_before: Vec<crate::analysis::damping::ModeDamping>,
    /// The same, tuned design.
    pub damping_after: Vec<crate::analysis::damping::ModeDamping>,
    /// The reference design's lowest whirls damped at the speed of its largest response
    /// at the node: the critical speed a run-up crosses, where a damping shunt works.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crossing_before: Option<CrossingDamping>,
    /// The same, tuned design, at its own largest response.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub crossing_after: Option<CrossingDamping>,
}

/// Damping ratios of the lowest whirls at one speed: where a design's response peaks.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct CrossingDamping {
    /// The speed of the largest response at the node (rad/s).
    pub speed: f64,
    /// The lowest whirls' damping ratios ζ there (−; one point per track).
    pub whirls: Vec<crate::analysis::damping::ModeDamping>,
}

/// Whirls per direction whose damping ratios a report lists.
pub const REPORT_DAMPING_WHIRLS: usize = 3;

/// Everything a design run found.
#[derive(Debug, Clone)]
pub struct DesignOutcome {
    /// The validated design problem that was run.
    pub spec: DesignSpec,
    /// How the run ended: improved, unchanged, feasible, infeasible or not verified.
    pub status: Status,
    /// Variable values of the reference design (SI units, as in the problem file).
    pub before: Vec<f64>,
    /// Variable values of the tuned design.
    pub after: Vec<f64>,
    /// The objective's own findings: bands or intrusions, before and after.
    pub findings: Findings,
    /// The reference design at each speed: whirls and full catalogue.
    pub before_speeds: Vec<DesignAtSpeed>,
    /// The tuned design at each speed: whirls, full catalogue and the verification checks.
    pub after_speeds: Vec<DesignAtSpeed>,
    /// The verification part by part (passed, failed or not applicable, with counts) and
    /// its verdict.
    pub verification: crate::design::verify::Verification,
    /// Nelder–Mead starts (or the clear-bands global pass).
    pub starts: Vec<StartReport>,
    /// Objective or intrusion history.
    pub history: Vec<HistoryPoint>,
    /// Sequential convex steps (clear bands), in order.
    pub convex_steps: Vec<ConvexStep>,
    /// Candidate designs analysed (each a rotor at every speed).
    pub candidates: usize,
    /// Candidates whose analysis failed (counted in `candidates`).
    pub failed_candidates: usize,
    /// One failure's message (the alphabetically first, so that it does not depend on
    /// thread timing).
    pub first_failure: Option<String>,
    /// Monodromy (Floquet) evaluations of the optimisation.
    pub floquet_evaluations: usize,
    /// Wall time of the optimisation (s).
    pub seconds: f64,
    /// Cost of the verification and the report's catalogues.
    pub verification_cost: Cost,
    /// The constraints judged afresh on the tuned design (empty without constraints).
    pub constraints_after: Vec<crate::design::vibration::ConstraintCheck>,
    /// The unbalance response and damping ratios before and after (with a response).
    pub vibration: Option<VibrationReport>,
    /// The tuned design over its tolerance box (with `[design.tolerances]`).
    pub robustness: Option<crate::design::robust::Robustness>,
    /// The tuned design over its speed range (with `design.speed_range`).
    pub speed_check: Option<crate::design::robust::SpeedCheck>,
    /// The reference design on the same speed grid (with `design.speed_range`).
    pub speed_check_before: Option<crate::design::robust::SpeedCheck>,
    /// The reduced basis every candidate was judged on, and how its size was chosen
    /// (`crate::design::sizing`); None only in a report read back from before it was
    /// recorded.
    pub basis: Option<BasisReport>,
    /// The rounds before the last, each on a basis its tuned design turned out to need
    /// more modes than (`crate::design::sizing::recheck`): empty when the first basis
    /// held.
    pub basis_rounds: Vec<BasisRound>,
    /// The tuned design checked again on a basis twice as large, at each speed
    /// (`crate::design::sizing::refined_check`).
    pub refined: Vec<RefinedCheck>,
    /// What stopped the run, for [`Status::Stopped`] (the library says only that it was
    /// asked to stop; a caller that set a limit names it); None for a run that ended.
    pub stop: Option<String>,
    /// The objective over the whole box before the local searches, where the run made one
    /// ([`super::ObjectiveMap`]).
    pub map: Option<super::ObjectiveMap>,
}

impl DesignOutcome {
    /// The outcome of a run that has judged nothing yet: `before` (SI units) kept as the
    /// tuned design, status unchanged, every list empty.
    pub(crate) fn empty(spec: &DesignSpec, before: Vec<f64>) -> DesignOutcome {
        DesignOutcome {
            spec: spec.clone(),
            status: Status::Unchanged,
            after: before.clone(),
            before,
            findings: spec.objective.findings().empty(),
            before_speeds: Vec::new(),
            after_speeds: Vec::new(),
            verification: Verification::of(Vec::new(), None),
            starts: Vec::new(),
            history: Vec::new(),
            convex_steps: Vec::new(),
            candidates: 0,
            failed_candidates: 0,
            first_failure: None,
            floquet_evaluations: 0,
            seconds: 0.0,
            verification_cost: Cost::default(),
            constraints_after: Vec::new(),
            vibration: None,
            robustness: None,
            speed_check: None,
            speed_check_before: None,
            basis: None,
            basis_rounds: Vec::new(),
            refined: Vec::new(),
            stop: None,
            map: None,
        }
    }

    /// Whether the tuned design passed every verification check (the verdict of
    /// [`DesignOutcome::verification`]).
    pub fn verified(&self) -> bool {
        self.verification.passed
    }

    /// Widest band: the reference design's band around φ_op at each speed (else empty).
    pub fn before_bands(&self) -> &[OperatingBand] {
        match &self.findings {
            Findings::WidestBand { before, .. } => before,
            _ => &[],
        }
    }
    /// Widest band: the tuned design's band around φ_op at each speed (else empty).
    pub fn after_bands(&self) -> &[OperatingBand] {
        match &self.findings {
            Findings::WidestBand { after, .. } => after,
            _ => &[],
        }
    }
    /// Clear bands: the reference design's intrusions (else empty).
    pub fn before_intrusions(&self) -> &[Intrusion] {
        match &self.findings {
            Findings::ClearBands { before, .. } => before,
            _ => &[],
        }
    }
    /// Clear bands: the tuned design's intrusions (else empty).
    pub fn after_intrusions(&self) -> &[Intrusion] {
        match &self.findings {
            Findings::ClearBands { after, .. } => after,
            _ => &[],
        }
    }
    /// Clear bands: whether the final linearisation had no solution inside the bounds.
    pub fn linear_infeasible(&self) -> bool {
        matches!(self.findings, Findings::ClearBands { linear_infeasible: true, .. })
    }
    /// Min peak response: its findings (else None).
    pub fn peak_findings(&self) -> Option<&PeakFindings> {
        match &self.findings {
            Findings::MinPeak(f) => Some(f),
            _ => None,
        }
    }
}

/// The JSON form of a [`DesignOutcome`]: every objective's keys present (empty for the
/// other objective), the shape `report.json` has always had. Written from borrowed parts,
/// read into owned ones.
#[derive(Serialize, Deserialize)]
struct OutcomeJson<'a> {
    spec: Cow<'a, DesignSpec>,
    status: Status,
    before: Cow<'a, [f64]>,
    after: Cow<'a, [f64]>,
    before_bands: Cow<'a, [OperatingBand]>,
    after_bands: Cow<'a, [OperatingBand]>,
    before_intrusions: Cow<'a, [Intrusion]>,
    after_intrusions: Cow<'a, [Intrusion]>,
    before_speeds: Cow<'a, [DesignAtSpeed]>,
    after_speeds: Cow<'a, [DesignAtSpeed]>,
    /// The verification's verdict, repeated at the top: read back, it must agree.
    verified: bool,
    verification: Cow<'a, Verification>,
    starts: Cow<'a, [StartReport]>,
    history: Cow<'a, [HistoryPoint]>,
    convex_steps: Cow<'a, [ConvexStep]>,
    linear_infeasible: bool,
    candidates: usize,
    failed_candidates: usize,
    first_failure: Option<String>,
    floquet_evaluations: usize,
    seconds: f64,
    verification_cost: Cost,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    min_peak: Option<Cow<'a, PeakFindings>>,
    #[serde(default, skip_serializing_if = "<[_]>::is_empty")]
    constraints_after: Cow<'a, [ConstraintCheck]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    vibration: Option<Cow<'a, VibrationReport>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    robustness: Option<Cow<'a, Robustness>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    speed_check: Option<Cow<'a, SpeedCheck>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    speed_check_before: Option<Cow<'a, SpeedCheck>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    basis: Option<Cow<'a, BasisReport>>,
    #[serde(default)]
    basis_rounds: Cow<'a, [BasisRound]>,
    #[serde(default)]
    refined: Cow<'a, [RefinedCheck]>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    stop: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    map: Option<Cow<'a, super::ObjectiveMap>>,
}

impl Serialize for DesignOutcome {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        OutcomeJson {
            spec: Cow::Borrowed(&self.spec),
            status: self.status,
            before: Cow::Borrowed(&self.before),
            after: Cow::Borrowed(&self.after),
            before_bands: Cow::Borrowed(self.before_bands()),
            after_bands: Cow::Borrowed(self.after_bands()),
            before_intrusions: Cow::Borrowed(self.before_intrusions()),
            after_intrusions: Cow::Borrowed(self.after_intrusions()),
            before_speeds: Cow::Borrowed(&self.before_speeds),
            after_speeds: Cow::Borrowed(&self.after_speeds),
            verified: self.verified(),
            verification: Cow::Borrowed(&self.verification),
            starts: Cow::Borrowed(&self.starts),
            history: Cow::Borrowed(&self.history),
            convex_steps: Cow::Borrowed(&self.convex_steps),
            linear_infeasible: self.linear_infeasible(),
            candidates: self.candidates,
            failed_candidates: self.failed_candidates,
            first_failure: self.first_failure.clone(),
            floquet_evaluations: self.floquet_evaluations,
            seconds: self.seconds,
            verification_cost: self.verification_cost,
            min_peak: self.peak_findings().map(Cow::Borrowed),
            constraints_after: Cow::Borrowed(&self.constraints_after),
            vibration: self.vibration.as_ref().map(Cow::Borrowed),
            robustness: self.robustness.as_ref().map(Cow::Borrowed),
            speed_check: self.speed_check.as_ref().map(Cow::Borrowed),
            speed_check_before: self.speed_check_before.as_ref().map(Cow::Borrowed),
            basis: self.basis.as_ref().map(Cow::Borrowed),
            basis_rounds: Cow::Borrowed(&self.basis_rounds),
            refined: Cow::Borrowed(&self.refined),
            stop: self.stop.clone(),
            map: self.map.as_ref().map(Cow::Borrowed),
        }
        .serialize(serializer)
    }
}

/// An outcome read back from its JSON (`report.json`): the objective's findings rebuilt
/// from the spec's objective and the flat keys. Refused when the top-level `verified`
/// disagrees with the verification's verdict, or the objective's keys are missing.
impl<'de> Deserialize<'de> for DesignOutcome {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let json = OutcomeJson::deserialize(deserializer)?;
        if json.verified != json.verification.passed {
            return Err(D::Error::custom("`verified` disagrees with `verification.passed`"));
        }
        let findings = match json.spec.objective.findings() {
            FindingsKind::Bands => {
                Findings::WidestBand { before: json.before_bands.into_owned(), after: json.after_bands.into_owned() }
            }
            FindingsKind::Intrusions => Findings::ClearBands {
                before: json.before_intrusions.into_owned(),
                after: json.after_intrusions.into_owned(),
                linear_infeasible: json.linear_infeasible,
            },
            FindingsKind::Peak => Findings::MinPeak(Box::new(
                json.min_peak.ok_or_else(|| D::Error::missing_field("min_peak"))?.into_owned(),
            )),
        };
        Ok(DesignOutcome {
            spec: json.spec.into_owned(),
            status: json.status,
            before: json.before.into_owned(),
            after: json.after.into_owned(),
            findings,
            before_speeds: json.before_speeds.into_owned(),
            after_speeds: json.after_speeds.into_owned(),
            verification: json.verification.into_owned(),
            starts: json.starts.into_owned(),
            history: json.history.into_owned(),
            convex_steps: json.convex_steps.into_owned(),
            candidates: json.candidates,
            failed_candidates: json.failed_candidates,
            first_failure: json.first_failure,
            floquet_evaluations: json.floquet_evaluations,
            seconds: json.seconds,
            verification_cost: json.verification_cost,
            constraints_after: json.constraints_after.into_owned(),
            vibration: json.vibration.map(Cow::into_owned),
            robustness: json.robustness.map(Cow::into_owned),
            speed_check: json.speed_check.map(Cow::into_owned),
            speed_check_before: json.speed_check_before.map(Cow::into_owned),
            basis: json.basis.map(Cow::into_owned),
            basis_rounds: json.basis_rounds.into_owned(),
            refined: json.refined.into_owned(),
            stop: json.stop,
            map: json.map.map(Cow::into_owned),
        })
    }
}

/// A round of a design on a basis its tuned design did not hold on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BasisRound {
    /// The modes M the round ran on (−).
    pub modes: usize,
    /// Its tuned design (SI units, as the variables).
    pub values: Vec<f64>,
}

/// The cost of a phase of the run.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize)]
pub struct Cost {
    /// Candidate designs evaluated by this start.
    pub evaluations: usize,
    /// Wall time (s).
    pub seconds: f64,
}
