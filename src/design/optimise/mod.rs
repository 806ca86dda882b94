//! The design runs: multi-start Nelder–Mead for the widest stable band, sequential convex
//! programming for clear bands (see the module docs of [`crate::design`]).

use super::evaluate::{follow, intrusions, operating_bands, values_of, Candidate, Intrusion, OperatingBand};
use super::qp::{self, Linear, Step, StepProblem};
use super::spec::{DesignSpec, Objective, Parameter, Variable};
use super::verify::{describe, verify, DesignAtSpeed};
use super::DesignError;
use crate::analysis::regions::{check_reliable, Counter, RegionSettings};
use crate::problem::Problem;
use crate::progress::Progress;
use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use rayon::prelude::*;
use serde::Serialize;
use std::cell::RefCell;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

mod convex;
mod min_peak;
mod nelder_mead;

use convex::clear_bands;
use min_peak::min_peak;
pub use min_peak::{JudgedDesign, PeakFindings, PeakStep, Price};
use nelder_mead::widest_band;

/// Cost of a candidate whose analysis failed (rad/s, far worse than any band).
const FAILED_COST: f64 = 1.0e9;

/// How the run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Status {
    /// Widest band: the tuned band is wider than the reference's, and verified.
    Improved,
    /// Widest band: no start beat the reference design, which is kept (and verified).
    Unchanged,
    /// Clear bands: every band is clear by its clearance, and verified.
    Feasible,
    /// Clear bands: no design inside the bounds was found that clears every band.
    Infeasible,
    /// The design the optimiser found failed its independent verification
    /// ([`crate::design::verify`]): its band or clearances are not shown to hold.
    NotVerified,
}

impl Status {
    /// Whether the run produced a design that can be handed on (improved, unchanged or
    /// feasible, and verified).
    pub fn is_result(self) -> bool {
        matches!(self, Status::Improved | Status::Unchanged | Status::Feasible)
    }
}

/// One Nelder–Mead start.
#[derive(Debug, Clone, Serialize)]
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
#[derive(Debug, Clone, Copy, Serialize)]
pub struct HistoryPoint {
    /// Start index (widest band) or 0 (clear bands).
    pub start: usize,
    /// Candidate evaluation count within the start / iteration of the convex steps.
    pub step: usize,
    /// Objective (rad/s: signed band width) or total intrusion (rad/s).
    pub value: f64,
    /// Best value so far in this start (same unit as `value`).
    pub best: f64,
}

/// One sequential convex step.
#[derive(Debug, Clone, Serialize)]
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

/// The unbalance response of a design with a `[design.response]`, before and after, and
/// the damping ratios of its lowest whirls: report content.
#[derive(Debug, Clone, Serialize)]
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
    /// Whether the tuned design passed every verification check.
    pub verified: bool,
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
}

impl DesignOutcome {
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
/// other objective), the shape `report.json` has always had.
#[derive(Serialize)]
struct OutcomeJson<'a> {
    spec: &'a DesignSpec,
    status: Status,
    before: &'a [f64],
    after: &'a [f64],
    before_bands: &'a [OperatingBand],
    after_bands: &'a [OperatingBand],
    before_intrusions: &'a [Intrusion],
    after_intrusions: &'a [Intrusion],
    before_speeds: &'a [DesignAtSpeed],
    after_speeds: &'a [DesignAtSpeed],
    verified: bool,
    starts: &'a [StartReport],
    history: &'a [HistoryPoint],
    convex_steps: &'a [ConvexStep],
    linear_infeasible: bool,
    candidates: usize,
    failed_candidates: usize,
    first_failure: &'a Option<String>,
    floquet_evaluations: usize,
    seconds: f64,
    verification_cost: Cost,
    #[serde(skip_serializing_if = "Option::is_none")]
    min_peak: Option<&'a PeakFindings>,
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    constraints_after: &'a [crate::design::vibration::ConstraintCheck],
    #[serde(skip_serializing_if = "Option::is_none")]
    vibration: Option<&'a VibrationReport>,
}

impl Serialize for DesignOutcome {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        OutcomeJson {
            spec: &self.spec,
            status: self.status,
            before: &self.before,
            after: &self.after,
            before_bands: self.before_bands(),
            after_bands: self.after_bands(),
            before_intrusions: self.before_intrusions(),
            after_intrusions: self.after_intrusions(),
            before_speeds: &self.before_speeds,
            after_speeds: &self.after_speeds,
            verified: self.verified,
            starts: &self.starts,
            history: &self.history,
            convex_steps: &self.convex_steps,
            linear_infeasible: self.linear_infeasible(),
            candidates: self.candidates,
            failed_candidates: self.failed_candidates,
            first_failure: &self.first_failure,
            floquet_evaluations: self.floquet_evaluations,
            seconds: self.seconds,
            verification_cost: self.verification_cost,
            min_peak: self.peak_findings(),
            constraints_after: &self.constraints_after,
            vibration: self.vibration.as_ref(),
        }
        .serialize(serializer)
    }
}

/// The cost of a phase of the run.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Cost {
    /// Candidate designs evaluated by this start.
    pub evaluations: usize,
    /// Wall time (s).
    pub seconds: f64,
}

/// Shared state of a run: the base problem, counters and the progress observer.
struct Context<'a> {
    base: &'a Problem,
    spec: &'a DesignSpec,
    regions: RegionSettings,
    floquet: Counter,
    candidates: AtomicUsize,
    failures: AtomicUsize,
    first_failure: std::sync::Mutex<Option<String>>,
    progress: &'a dyn Progress,
    /// The reference design (the file's values), built once and checked reliable.
    reference: Candidate,
}

impl Context<'_> {
    fn values(&self, u: &[f64]) -> Vec<f64> {
        self.spec.variables.iter().zip(u).map(|(v, &x)| v.from_unit(x.clamp(0.0, 1.0))).collect()
    }

    fn candidate(&self, u: &[f64]) -> Result<Candidate, DesignError> {
        self.candidates.fetch_add(1, Ordering::Relaxed);
        self.progress.advance(1);
        let c = Candidate::new(self.base, self.spec, &self.values(u));
        if let Err(e) = &c {
            self.note_failure(e);
        }
        c
    }

    /// Count a failed candidate and keep the smallest message, not the first in time:
    /// independent of thread timing.
    fn note_failure(&self, e: &DesignError) {
        self.failures.fetch_add(1, Ordering::Relaxed);
        let mut first = self.first_failure.lock().unwrap_or_else(|p| p.into_inner());
        let m = e.to_string();
        if first.as_ref().is_none_or(|f| m < *f) {
            *first = Some(m);
        }
    }

    /// The bands around φ_op (rad/s) of a candidate, at every speed.
    fn bands(&self, c: &Candidate, phi_op: f64) -> Result<Vec<OperatingBand>, DesignError> {
        operating_bands(c, self.spec, phi_op, &self.regions, &self.floquet)
    }

    /// Smallest signed band width over the speeds (rad/s) of the design at `u` (scaled).
    fn band_objective(&self, u: &[f64], phi_op: f64) -> f64 {
        match self.candidate(u).and_then(|c| self.bands(&c, phi_op)) {
            Ok(b) => smallest(&b),
            Err(_) => -FAILED_COST,
        }
    }
}

/// The smallest signed band width over the speeds (rad/s).
fn smallest(bands: &[OperatingBand]) -> f64 {
    bands.iter().map(OperatingBand::signed_width).fold(f64::INFINITY, f64::min)
}

fn to_unit(spec: &DesignSpec, values: &[f64]) -> Vec<f64> {
    spec.variables.iter().zip(values).map(|(v, &x)| v.to_unit(x).clamp(0.0, 1.0)).collect()
}

/// The i-th point of the Halton sequence in `dims` dimensions (bases 2, 3, 5, …).
fn halton(i: usize, dims: usize) -> Vec<f64> {
    const PRIMES: [usize; 12] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37];
    (0..dims)
        .map(|d| {
            let b = PRIMES[d % PRIMES.len()];
            let (mut f, mut r, mut k) = (1.0, 0.0, i + 1);
            while k > 0 {
                f /= b as f64;
                r += f * (k % b) as f64;
                k /= b;
            }
            r
        })
        .collect()
}

/// The most candidates a design of `spec` builds: Nelder–Mead: the simplex and 2 per
/// iteration, per start, then each start's final point and the reference; clear-bands:
/// the global pass (4 per start and the reference), 2·(2·variables + 1) per convex step,
/// and the result. An optimiser that converges early builds fewer.
pub fn most_candidates(spec: &DesignSpec) -> usize {
    let (starts, iterations, variables) = (spec.starts, spec.max_iterations, spec.variables.len());
    match spec.objective {
        Objective::WidestStableBand { .. } => starts * (2 * iterations + variables + 1) + starts + 1,
        Objective::ClearBands { .. } => 4 * starts + 1 + 2 * iterations * (2 * variables + 1) + 1,
        // The reference and classic designs; each start's simplex and 2 per iteration,
        // twice (without and with constraints); the convex steps' differences and trials
        // (clear-bands' linearisation of the bands included).
        Objective::MinPeakResponse { .. } => {
            let runs = if spec.constraints.is_empty() { 1 } else { 2 };
            let starts = starts.max(3);
            2 + runs * starts * (2 * iterations + variables + 1) + 8 * (4 * variables + 1)
        }
    }
}

/// Run the design of `base.design`, first checked by the `[design]` rules
/// ([`DesignSpec::check`]: a spec built in code is not trusted). `progress` sees two
/// phases: `optimise`, a step per candidate built (at most [`most_candidates`]), and
/// `verification`, a step per search and grid point of the checks ([`describe`],
/// [`verify`]). The result is verified independently ([`crate::design::verify`]); the
/// catalogues of the reference and the tuned design (for the report) come with it.
pub fn run(base: &Problem, progress: &dyn Progress) -> Result<DesignOutcome, DesignError> {
    let spec = base.design.as_ref().ok_or(DesignError::NoDesign)?;
    spec.check(&base.model.rings.iter().map(|r| r.circuit.branches.len()).collect::<Vec<_>>())
        .map_err(|(field, error)| DesignError::Spec { field, error })?;
    progress.phase("optimise", most_candidates(spec) as u64);
    let started = Instant::now();
    let before = values_of(base, spec);
    // The reference design's Floquet points must pass the β = 0 check over the design's
    // range at every speed before any candidate is searched.
    let reference = Candidate::new(base, spec, &before)?;
    for (_, fs) in &reference.systems {
        check_reliable(fs, spec.range())?;
    }
    let ctx = Context {
        base,
        spec,
        regions: base.regions.clone(),
        floquet: Counter::default(),
        candidates: AtomicUsize::new(0),
        failures: AtomicUsize::new(0),
        first_failure: std::sync::Mutex::new(None),
        progress,
        reference,
    };
    let mut out = DesignOutcome {
        spec: spec.clone(),
        status: Status::Unchanged,
        before: before.clone(),
        after: before.clone(),
        findings: match spec.objective {
            Objective::WidestStableBand { .. } => Findings::WidestBand { before: Vec::new(), after: Vec::new() },
            Objective::ClearBands { .. } => {
                Findings::ClearBands { before: Vec::new(), after: Vec::new(), linear_infeasible: false }
            }
            Objective::MinPeakResponse { .. } => Findings::WidestBand { before: Vec::new(), after: Vec::new() },
        },
        before_speeds: Vec::new(),
        after_speeds: Vec::new(),
        verified: false,
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
    };
    match &spec.objective {
        Objective::WidestStableBand { phi_op } => widest_band(&ctx, &mut out, *phi_op)?,
        Objective::ClearBands { .. } => clear_bands(&ctx, &mut out)?,
        Objective::MinPeakResponse { .. } => min_peak(&ctx, &mut out)?,
    }
    out.candidates = ctx.candidates.load(Ordering::Relaxed);
    out.failed_candidates = ctx.failures.load(Ordering::Relaxed);
    out.first_failure = ctx.first_failure.lock().unwrap_or_else(|p| p.into_inner()).clone();
    out.floquet_evaluations = ctx.floquet.get();
    out.seconds = started.elapsed().as_secs_f64();
    // Verification, from scratch: the reference and the tuned design rebuilt, their full
    // catalogues, and the checks on the tuned one.
    let checked = Instant::now();
    progress.phase("verification", 0);
    let count = Counter::default();
    let reference = Candidate::new(base, spec, &out.before)?;
    let tuned = Candidate::new(base, spec, &out.after)?;
    out.before_speeds = describe(&reference, spec, &ctx.regions, progress)?;
    out.after_speeds = describe(&tuned, spec, &ctx.regions, progress)?;
    count.add(out.before_speeds.iter().chain(&out.after_speeds).map(|d| d.catalogue.evaluations).sum());
    let mut after_speeds = std::mem::take(&mut out.after_speeds);
    out.verified = verify(&tuned, spec, out.after_bands(), &mut after_speeds, &count, progress);
    out.after_speeds = after_speeds;
    match &mut out.findings {
        // Intrusions named after the full model's whirls: the catalogue's region with the
        // same edges (the lattice-refined edges are the same numbers).
        Findings::ClearBands { before, after, .. } => {
            for (ints, speeds) in [(before, &out.before_speeds), (after, &out.after_speeds)] {
                for it in ints.iter_mut() {
                    let Some(d) = speeds.iter().find(|d| d.speed == it.speed) else { continue };
                    let same =
                        |r: &&crate::analysis::regions::Region| r.left == Some(it.left) && r.right == Some(it.right);
                    if let Some(r) = d.catalogue.regions.iter().filter(same).min_by_key(|r| r.order) {
                        it.label = format!("{}/{}", r.label, r.order);
                    }
                }
            }
        }
        Findings::MinPeak(_) => {}
        // The bands with the full model's labels (the same numbers, checked by `verify`).
        Findings::WidestBand { before, after } => {
            for (bands, speeds) in [(before, &out.before_speeds), (after, &out.after_speeds)] {
                for (b, d) in bands.iter_mut().zip(speeds) {
                    if let Some(l) = d.band.as_ref().filter(|l| l.band == b.band.band) {
                        b.band = l.clone();
                    }
                }
            }
        }
    }
    // The constraints, judged afresh on the tuned design.
    if !spec.constraints.is_empty() {
        let peak = match spec.response() {
            Some(r) => Some(crate::design::vibration::peak_of(&tuned.rotor, r)?),
            None => None,
        };
        out.constraints_after = crate::design::vibration::check_constraints(&tuned, spec, &ctx.regions, peak, &count)?;
        for c in out.constraints_after.iter().filter(|c| !c.met) {
            let message = format!("constraint {} not met: {:e}", c.name, c.value);
            if let Some(d) = out.after_speeds.first_mut() {
                d.failures.push(message);
            }
            out.verified = false;
        }
    }
    if let Some(r) = spec.response() {
        let vibration = |values: &[f64]| -> Result<_, DesignError> {
            let (p, rotor) = crate::design::vibration::rotor_at(base, spec, values)?;
            let response = crate::design::vibration::response_of(&rotor, r)?;
            let speeds = crate::design::vibration::ascending(&spec.speeds);
            let silent = crate::progress::Silent;
            let damping =
                crate::analysis::damping::lowest_damping(&rotor, &p.settings, &speeds, REPORT_DAMPING_WHIRLS, &silent)?;
            Ok((response, damping))
        };
        let (before, damping_before) = vibration(&out.before)?;
        let (after, damping_after) = vibration(&out.after)?;
        let unconstrained = match out.peak_findings().filter(|f| !f.unconstrained.constraints.is_empty()) {
            Some(f) => Some(vibration(&f.unconstrained.values.clone())?.0),
            None => None,
        };
        out.vibration =
            Some(VibrationReport { response: r.clone(), before, after, unconstrained, damping_before, damping_after });
    }
    if !out.verified && out.status != Status::Infeasible {
        out.status = Status::NotVerified;
    }
    out.verification_cost = Cost { evaluations: count.get(), seconds: checked.elapsed().as_secs_f64() };
    Ok(out)
}

/// (onset, left, right) of a tongue at the level.
type OnsetEdges = (f64, f64, f64);
/// One Nelder–Mead start's report, history and best point.
type StartRun = (StartReport, Vec<HistoryPoint>, Vec<f64>);
