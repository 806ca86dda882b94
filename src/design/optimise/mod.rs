//! The design runs: multi-start Nelder–Mead for the widest stable band, sequential convex
//! programming for clear bands (see the module docs of [`crate::design`]).

use super::evaluate::{follow, intrusions, values_of, Candidate, Intrusion, OperatingBand};
use super::machine::Machine;
use super::qp::{self, Linear, Step, StepProblem};
use super::spec::{DesignSpec, Objective, Parameter, Variable};
use super::verify::{describe, verify, PeakRecheck, Verification, VerificationPart, PEAK_AGREEMENT, PEAK_GRID_FACTOR};
use super::DesignError;
use crate::analysis::regions::{check_reliable, Counter, RegionSettings};
use crate::progress::Progress;
use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use rayon::prelude::*;
use serde::Serialize;
use std::cell::RefCell;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

mod best;
mod convex;
mod min_peak;
mod nelder_mead;
mod observer;
mod outcome;

use best::{BestSoFar, Rank};
use convex::clear_bands;
use min_peak::min_peak;
pub use min_peak::{JudgedDesign, PeakFindings, PeakStep, Price};
use nelder_mead::widest_band;
pub use observer::{Observation, Observer};
pub use outcome::{
    BasisRound, ConvexStep, Cost, DesignOutcome, Findings, HistoryPoint, StartReport, Status, VibrationReport,
    REPORT_DAMPING_WHIRLS,
};

/// Cost of a candidate whose analysis failed (rad/s, far worse than any band).
const FAILED_COST: f64 = 1.0e9;

/// Shared state of a run: the base machine, counters and the progress observer.
struct Context<'a> {
    base: &'a Machine,
    spec: &'a DesignSpec,
    regions: RegionSettings,
    floquet: Counter<'a>,
    candidates: AtomicUsize,
    failures: AtomicUsize,
    first_failure: std::sync::Mutex<Option<String>>,
    progress: &'a dyn Progress,
    /// The reference design (the file's values), built once and checked reliable.
    reference: Candidate,
    /// Starts given by the caller ([`RunOptions::extra_starts`]), scaled to [0, 1].
    extra_starts: Vec<(String, Vec<f64>)>,
    /// The caller's unconstrained optimum ([`RunOptions::unconstrained`]), scaled.
    unconstrained: Option<Vec<f64>>,
    /// The caller's observer ([`RunOptions::observer`]).
    observer: Option<&'a dyn Observer>,
    /// The best design judged so far in the run (kept by a stop).
    best: &'a BestSoFar,
}

/// What a caller adds to a design run beyond its `[design]` table.
#[derive(Clone, Default)]
pub struct RunOptions {
    /// More Nelder–Mead starts of the min-peak-response runs, by name, in variable values
    /// (SI units, as in the problem file), tried beside the classic tuning, the reference
    /// and the Halton points: e.g. a design known to meet a tighter constraint, which the
    /// run then can only improve on ([`crate::design::pareto`] chains its points so).
    pub extra_starts: Vec<(String, Vec<f64>)>,
    /// The min-peak-response design that damps best with no constraint, in variable values
    /// (SI units), when an earlier run of the same objective, variables and bounds found it
    /// (it does not depend on the constraints): its Nelder–Mead runs are skipped and this
    /// design is judged in their place.
    pub unconstrained: Option<Vec<f64>>,
    /// Watches every evaluation of the objective as it is made ([`Observer`]).
    pub observer: Option<std::sync::Arc<dyn Observer>>,
}

impl std::fmt::Debug for RunOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RunOptions")
            .field("extra_starts", &self.extra_starts)
            .field("unconstrained", &self.unconstrained)
            .field("observer", &self.observer.as_ref().map(|_| "an observer"))
            .finish()
    }
}

impl Context<'_> {
    /// Hand one history entry to the caller's observer, with the candidate's scaled
    /// variables `u` (empty: none).
    fn observe(&self, point: HistoryPoint, u: &[f64]) {
        if let Some(o) = self.observer {
            let values = if u.is_empty() { Vec::new() } else { self.values(u) };
            o.observe(&Observation { point, values: &values });
        }
    }

    fn values(&self, u: &[f64]) -> Vec<f64> {
        self.spec.variables.iter().zip(u).map(|(v, &x)| v.from_unit(x.clamp(0.0, 1.0))).collect()
    }

    /// The candidate at `u` (scaled), counted; none once the caller asks to stop (the
    /// objectives take it as failed, so the optimisers run out at once, and the run then
    /// ends [`Status::Stopped`]).
    fn candidate(&self, u: &[f64]) -> Result<Candidate, DesignError> {
        stopped(self.progress)?;
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

    /// Smallest signed band width over the speeds (rad/s) of the design at `u` (scaled),
    /// less the margin penalty, at the worst build of the tolerance box ([`Context::judged`]).
    fn band_objective(&self, u: &[f64], phi_op: f64) -> f64 {
        let value = self.candidate(u).and_then(|c| Ok(self.judged(&c, phi_op)?.0)).unwrap_or(-FAILED_COST);
        if value > -FAILED_COST {
            self.best.offer(Rank(0, -value, 0.0), &self.values(u), self.progress);
        }
        value
    }

    /// What the widest-band objective steers by for a candidate (rad/s): the smallest
    /// signed band width over the speeds, less [`MARGIN_PENALTY`] per rad/s by which the
    /// band at the margin level misses `[design.margins]`; over a speed range, with the
    /// worst speed of the grid refined ([`robust::refined_worst`]). With
    /// `[design.tolerances]`, the smallest of that over the centre and corners of the
    /// tolerance box ([`crate::design::tolerance::Tolerances::corners`]); over a speed
    /// range the corners are judged at the nominal design's refined worst speed alone
    /// ([`robust::judged_at`]), the cheaper set docs/decisions.md ("Design speed")
    /// measures against every corner at every speed. With the nominal bands.
    fn judged(&self, c: &Candidate, phi_op: f64) -> Result<(f64, Vec<OperatingBand>), DesignError> {
        let (spec, s, count) = (self.spec, &self.regions, &self.floquet);
        let nominal = robust::judged(c, spec, phi_op, s, count, MARGIN_PENALTY)?;
        let (worst_speed, mut value) = match spec.speed_range {
            Some(_) => {
                let (w, width) = robust::refined_worst(c, spec, phi_op, &nominal.bands, s, count)?;
                (Some(w), nominal.smallest.min(width) - nominal.penalty)
            }
            None => (None, nominal.value()),
        };
        if let Some(t) = &spec.tolerances {
            let corners = t.corners();
            let worst = corners[1..]
                .par_iter()
                .map(|p| match worst_speed {
                    Some(w) => robust::judged_at(&c.perturbed_rotor(p)?, spec, phi_op, w, s, count, MARGIN_PENALTY),
                    None => Ok(robust::judged(&c.perturbed(spec, p)?, spec, phi_op, s, count, MARGIN_PENALTY)?.value()),
                })
                .collect::<Result<Vec<f64>, DesignError>>()?;
            value = worst.into_iter().fold(value, f64::min);
        }
        Ok((value, nominal.bands))
    }
}

/// Penalty per rad/s of frequency-margin shortfall at the margin level, in rad/s of band
/// width: an exact penalty needs more than the width one rad/s of margin can buy (a
/// bounding tongue moved by δ changes the width and the margin by δ each, so 1 would be
/// the break-even), and 10 keeps the optimiser's steps on the feasible side.
const MARGIN_PENALTY: f64 = 10.0;

use super::robust;

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
///
/// A run that `progress` asks to stop ([`Progress::cancelled`]: a time limit, an
/// allowance of evaluations, Ctrl-C) ends [`Status::Stopped`], not verified, with the
/// best design whose judgement ended before the stop (candidates, and each round's final
/// points and reference, judged afresh; the reference where there is none). Each band search asks too, so the stop comes within a
/// search step.
pub fn run(base: &Machine, spec: &DesignSpec, progress: &dyn Progress) -> Result<DesignOutcome, DesignError> {
    run_with(base, spec, &RunOptions::default(), progress)
}

/// [`run`] with a caller's [`RunOptions`].
pub fn run_with(
    base: &Machine,
    spec: &DesignSpec,
    options: &RunOptions,
    progress: &dyn Progress,
) -> Result<DesignOutcome, DesignError> {
    spec.check(&base.model.rings.iter().map(|r| r.circuit.branches.len()).collect::<Vec<_>>())
        .map_err(|(field, error)| DesignError::Spec { field, error })?;
    let best = BestSoFar::default();
    let mut optimised = None;
    let result = run_steps(base, spec, options, progress, &best, &mut optimised);
    // A stop asked at any point, whatever the steps made of their cut-short searches.
    if !progress.cancelled() {
        return result;
    }
    // The best design judged (a round's tuned design among them once a round has ended),
    // with the runs and history of the last round that ended.
    let mut out = DesignOutcome::empty(spec, values_of(base, spec));
    if let Some(values) = best.values() {
        out.after = values;
    }
    if let Some(o) = optimised {
        (out.starts, out.history, out.convex_steps, out.basis) = (o.starts, o.history, o.convex_steps, o.basis);
        (out.candidates, out.failed_candidates, out.floquet_evaluations) =
            (o.candidates, o.failed_candidates, o.floquet_evaluations);
    }
    out.status = Status::Stopped;
    out.stop = Some("by its caller before it ended".into());
    Ok(out)
}

/// The steps of [`run_with`]; `optimised` is set to the outcome of each optimisation round
/// as it ends (before its verification), `best` is offered every design judged.
fn run_steps(
    base: &Machine,
    spec: &DesignSpec,
    options: &RunOptions,
    progress: &dyn Progress,
    best: &BestSoFar,
    optimised: &mut Option<DesignOutcome>,
) -> Result<DesignOutcome, DesignError> {
    // The basis every candidate is judged on, sized at the reference design.
    progress.phase("basis", 0);
    let sizing = Counter::default();
    let (mut sized, basis) = super::sizing::size_basis(base, spec, &sizing, progress)?;
    stopped(progress)?;
    let started = Instant::now();
    let mut extra: Vec<(String, Vec<f64>)> = options.extra_starts.clone();
    let mut rounds = Vec::new();
    let mut out = optimise_round(&sized, spec, options, &extra, progress, best)?;
    out.basis = Some(basis);
    *optimised = Some(out.clone());
    // Until the basis holds at the tuned design too: a design far from the reference can
    // need more modes than the reference did (its electrical modes moved). Each round
    // starts again on the larger basis, from the previous tuned design as well.
    for round in 1..=BASIS_ROUNDS {
        stopped(progress)?;
        let recheck = super::sizing::recheck(&sized, &base.settings, spec, &out.after, &sizing, progress)?;
        let Some((machine, report)) = recheck else { break };
        rounds.push(BasisRound { modes: out.basis.as_ref().map_or(0, |b| b.modes), values: out.after.clone() });
        if round == BASIS_ROUNDS {
            // The last round's tuned design needs a larger basis than it was run on:
            // said so, and the refined check judges it.
            out.basis = Some(report.not_held());
            break;
        }
        sized = machine;
        extra.push((format!("tuned on M = {}", rounds[rounds.len() - 1].modes), out.after.clone()));
        let mut next = optimise_round(&sized, spec, options, &extra, progress, best)?;
        next.basis = Some(report);
        next.candidates += out.candidates;
        next.failed_candidates += out.failed_candidates;
        next.floquet_evaluations += out.floquet_evaluations;
        next.first_failure = next.first_failure.or(out.first_failure);
        out = next;
        *optimised = Some(out.clone());
    }
    out.floquet_evaluations += sizing.get();
    out.basis_rounds = rounds;
    out.seconds = started.elapsed().as_secs_f64();
    let base = &sized;
    let regions = base.regions.clone();
    stopped(progress)?;
    // Verification, from scratch: the reference and the tuned design rebuilt, their full
    // catalogues, and the checks on the tuned one.
    let checked = Instant::now();
    progress.phase("verification", 0);
    let count = Counter::default();
    let reference = Candidate::new(base, spec, &out.before)?;
    let tuned = Candidate::new(base, spec, &out.after)?;
    out.before_speeds = describe(&reference, spec, &regions, progress)?;
    out.after_speeds = describe(&tuned, spec, &regions, progress)?;
    count.add(out.before_speeds.iter().chain(&out.after_speeds).map(|d| d.catalogue.evaluations).sum());
    let mut after_speeds = std::mem::take(&mut out.after_speeds);
    let mut parts = verify(&tuned, spec, out.after_bands(), &mut after_speeds, &count, progress);
    out.after_speeds = after_speeds;
    parts.push(operating_point_part(spec, &out.after_speeds));
    // The tuned design on a basis twice as large: its band and catalogues again.
    if spec.refined_check {
        let bands: Vec<_> = out.after_speeds.iter().map(|d| d.band.clone()).collect();
        out.refined = super::sizing::refined_check(&tuned, spec, &regions, &bands, &count, progress)?;
        parts.push(refined_part(&out.refined));
    } else {
        let why = "switched off (design.refined_check = false): the answer is not checked on a larger basis";
        parts.push(VerificationPart::of("refined-basis", 0, 0, String::new(), why));
    }
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
        out.constraints_after = crate::design::vibration::check_constraints(&tuned, spec, &regions, peak, &count)?;
        for c in out.constraints_after.iter().filter(|c| !c.met) {
            let message = format!("constraint {} not met: {:e}", c.name, c.value);
            if let Some(d) = out.after_speeds.first_mut() {
                d.failures.push(message);
            }
        }
        let failed = out.constraints_after.iter().filter(|c| !c.met).count();
        let names: Vec<String> = out
            .constraints_after
            .iter()
            .map(|c| format!("{} ({:.6e}: {})", c.name, c.value, if c.met { "met" } else { "NOT met" }))
            .collect();
        parts.push(VerificationPart::of(
            "constraints",
            out.constraints_after.len(),
            failed,
            format!(
                "{} constraint(s) judged afresh on the rebuilt tuned design (bands by the same search as `rotorshunt band`), {failed} not met: {}",
                out.constraints_after.len(),
                names.join("; ")
            ),
            "the constraint list judged empty",
        ));
    }
    // The min-peak design's peak found again on a finer grid by another refinement.
    let mut recheck = None;
    if let (Some(r), Some(f)) = (spec.response(), out.peak_findings()) {
        let optimiser = f.after.peak;
        let (again, points) = crate::design::vibration::peak_recheck(&tuned.rotor, r, PEAK_GRID_FACTOR)?;
        let relative_difference = (again.amplitude - optimiser.amplitude).abs() / optimiser.amplitude.abs();
        let agree = relative_difference <= PEAK_AGREEMENT;
        parts.push(VerificationPart::of(
            "peak",
            1,
            usize::from(!agree),
            format!(
                "the tuned design's peak at node {} over {}..{} rad/s found again on {points} speeds ({PEAK_GRID_FACTOR}× the optimiser's {}), every local maximum refined by parabolic steps: {:.6e} m at {:.3} rad/s against the optimiser's {:.6e} m at {:.3} rad/s, {:.4} % apart (at most {} %)",
                r.node,
                r.speeds.lo,
                r.speeds.hi,
                r.points,
                again.amplitude,
                again.speed,
                optimiser.amplitude,
                optimiser.speed,
                100.0 * relative_difference,
                100.0 * PEAK_AGREEMENT
            ),
            "no peak to recheck",
        ));
        if !agree {
            if let Some(d) = out.after_speeds.first_mut() {
                d.failures.push(format!(
                    "the peak found again ({:.6e} m) differs from the optimiser's ({:.6e} m) by {:.3} %",
                    again.amplitude,
                    optimiser.amplitude,
                    100.0 * relative_difference
                ));
            }
        }
        recheck = Some(PeakRecheck { optimiser, recheck: again, points, relative_difference });
    }
    // The tuned design as built: every corner of the tolerance box and Monte Carlo samples.
    if let (Some(t), Some(phi_op)) = (&spec.tolerances, spec.phi_op()) {
        progress.extend((t.corners().len() + t.samples) as u64);
        let r = robust::check(&tuned, spec, t, phi_op, &regions, &|| progress.advance(1))?;
        count.add(r.evaluations);
        parts.push(VerificationPart::of("tolerances", r.checked(), r.failed(), robust::summary(&r, phi_op), ""));
        out.robustness = Some(r);
    }
    // The tuned design over its speed range, on a grid finer than the optimiser's.
    if let Some(range) = spec.speed_range {
        match spec.phi_op() {
            Some(phi_op) => {
                progress.extend(super::spec::VERIFY_SPEEDS as u64);
                let r = robust::speed_check(&tuned, spec, range, phi_op, &regions, &|| progress.advance(1))?;
                count.add(r.evaluations);
                let summary = robust::speed_summary(&r, phi_op);
                parts.push(VerificationPart::of("speeds", r.bands.len(), r.failing.len(), summary, ""));
                out.speed_check = Some(r);
                // The reference on the same grid, for the report: where it failed.
                let before = robust::speed_check(&reference, spec, range, phi_op, &regions, &|| {})?;
                count.add(before.evaluations);
                out.speed_check_before = Some(before);
            }
            None => parts.push(VerificationPart::of(
                "speeds",
                0,
                0,
                String::new(),
                "the design has no band around phi_op to follow over the speed range; its bands are checked at the optimiser's speeds only",
            )),
        }
    }
    out.verification = Verification::of(parts, recheck);
    if let Some(r) = spec.response() {
        let vibration = |values: &[f64]| -> Result<_, DesignError> {
            let (m, rotor) = crate::design::vibration::rotor_at(base, spec, values)?;
            let response = crate::design::vibration::response_of(&rotor, r)?;
            let speeds = crate::design::vibration::ascending(&spec.speeds);
            let silent = crate::progress::Silent;
            let damping =
                crate::analysis::damping::lowest_damping(&rotor, &m.settings, &speeds, REPORT_DAMPING_WHIRLS, &silent)?;
            Ok((response, damping))
        };
        let (before, damping_before) = vibration(&out.before)?;
        let (after, damping_after) = vibration(&out.after)?;
        if let Findings::MinPeak(f) = &mut out.findings {
            let classic = f.classic_design.as_ref().map(|j| j.values.clone());
            f.baselines = crate::design::vibration::baselines(base, spec, r, classic.as_deref(), &before, &after)?;
        }
        let unconstrained = match out.peak_findings().filter(|f| !f.unconstrained.constraints.is_empty()) {
            Some(f) => Some(vibration(&f.unconstrained.values.clone())?.0),
            None => None,
        };
        out.vibration =
            Some(VibrationReport { response: r.clone(), before, after, unconstrained, damping_before, damping_after });
    }
    if !out.verified() && out.status != Status::Infeasible {
        // Not robust when the builds of the tolerance box are all that failed.
        let failed: Vec<&str> = out
            .verification
            .parts
            .iter()
            .filter(|p| p.status == super::verify::PartStatus::Failed)
            .map(|p| p.part.as_str())
            .collect();
        out.status = if failed == ["tolerances"] { Status::NotRobust } else { Status::NotVerified };
    }
    out.verification_cost = Cost { evaluations: count.get(), seconds: checked.elapsed().as_secs_f64() };
    // A stop asked during the verification leaves its searches incomplete: no verdict.
    stopped(progress)?;
    Ok(out)
}

/// The verification part `operating-point`: φ_op must be stable at β_op on the tuned
/// design at every speed (a design whose φ_op stays inside a tongue is neither improved
/// nor verified, whatever the other parts checked); not applicable without a φ_op.
fn operating_point_part(spec: &DesignSpec, after: &[super::verify::DesignAtSpeed]) -> VerificationPart {
    let Some(phi_op) = spec.phi_op() else {
        return VerificationPart::of("operating-point", 0, 0, String::new(), "the design has no phi_op");
    };
    let unstable: Vec<String> = after
        .iter()
        .filter(|d| d.band.as_ref().is_some_and(|b| b.band.is_none()))
        .map(|d| {
            let t = d.band.as_ref().and_then(|b| b.containing);
            let inside = t.map_or(String::new(), |t| format!(" (inside the tongue [{:.2}, {:.2}] rad/s)", t.lo, t.hi));
            format!("{} rad/s{inside}", d.speed)
        })
        .collect();
    let checked = after.iter().filter(|d| d.band.is_some()).count();
    let summary = if unstable.is_empty() {
        format!("phi_op = {phi_op} rad/s is stable at beta_op = {} at each of the {checked} speed(s)", spec.level)
    } else {
        format!("phi_op = {phi_op} rad/s is UNSTABLE at beta_op = {} at Omega = {}", spec.level, unstable.join(", "))
    };
    VerificationPart::of("operating-point", checked, unstable.len(), summary, "no band around phi_op was searched")
}

/// The verification part `refined-basis` over the speeds' refined checks
/// ([`super::sizing::refined_check`]).
fn refined_part(checks: &[super::sizing::RefinedCheck]) -> VerificationPart {
    let compared: usize = checks.iter().map(|c| c.movements.len()).sum();
    let failed: Vec<String> = checks
        .iter()
        .flat_map(|c| {
            c.movements.iter().filter(|m| !m.within()).map(move |m| format!("{} rad/s: {}", c.speed, m.text()))
        })
        .collect();
    let sizes: Vec<String> = checks.iter().map(|c| format!("M = {} → {}", c.modes, c.refined_modes)).collect();
    let worst = checks
        .iter()
        .flat_map(|c| &c.movements)
        .max_by(|a, b| a.ratio().total_cmp(&b.ratio()))
        .map_or(String::new(), |m| format!("; largest movement {}", m.text()));
    let summary = if failed.is_empty() {
        format!(
            "{compared} comparison(s) on a basis twice the design's ({}) within the tolerance{worst}",
            sizes.join(", ")
        )
    } else {
        format!(
            "{} of {compared} comparison(s) on a basis twice the design's ({}) moved beyond the tolerance: {}",
            failed.len(),
            sizes.join(", "),
            failed.join("; ")
        )
    };
    VerificationPart::of(
        "refined-basis",
        compared,
        failed.len(),
        summary,
        "the model has no more modes than the design's basis, or nothing to compare (no phi_op, no kept-clear band)",
    )
}

/// Most times a design runs again on a larger basis when its tuned design needs one
/// ([`super::sizing::recheck`]): each round is a whole optimisation, and a tuning that
/// moves an electrical mode across the window can need one more size; beyond, the last
/// round's design is verified as it is, its basis said not to hold.
pub const BASIS_ROUNDS: usize = 2;

/// One optimisation of `spec` on `base` (its basis fixed), with `extra` starts beside the
/// caller's: the outcome before its verification, with the counts of the round.
fn optimise_round(
    base: &Machine,
    spec: &DesignSpec,
    options: &RunOptions,
    extra: &[(String, Vec<f64>)],
    progress: &dyn Progress,
    best: &BestSoFar,
) -> Result<DesignOutcome, DesignError> {
    progress.phase("optimise", most_candidates(spec) as u64);
    let before = values_of(base, spec);
    // The reference design's Floquet points must pass the β = 0 check over the design's
    // range at every speed before any candidate is searched, and its whirls must have the
    // damping constraints' tags.
    let reference = Candidate::new(base, spec, &before)?;
    super::checks::modes_exist(&reference.rotor, &base.settings, spec)?;
    for (_, fs) in &reference.systems {
        check_reliable(fs, spec.range())?;
    }
    let ctx = Context {
        base,
        spec,
        regions: base.regions.clone(),
        floquet: Counter::reporting(progress),
        candidates: AtomicUsize::new(0),
        failures: AtomicUsize::new(0),
        first_failure: std::sync::Mutex::new(None),
        progress,
        reference,
        extra_starts: extra.iter().map(|(name, v)| (name.clone(), to_unit(spec, v))).collect(),
        unconstrained: options.unconstrained.as_ref().map(|v| to_unit(spec, v)),
        observer: options.observer.as_deref(),
        best,
    };
    let mut out = DesignOutcome::empty(spec, before);
    match &spec.objective {
        Objective::WidestStableBand { phi_op } => widest_band(&ctx, &mut out, *phi_op)?,
        Objective::ClearBands { .. } => clear_bands(&ctx, &mut out)?,
        Objective::MinPeakResponse { .. } => min_peak(&ctx, &mut out)?,
    }
    out.candidates = ctx.candidates.load(Ordering::Relaxed);
    out.failed_candidates = ctx.failures.load(Ordering::Relaxed);
    out.first_failure = ctx.first_failure.lock().unwrap_or_else(|p| p.into_inner()).clone();
    out.floquet_evaluations = ctx.floquet.get();
    Ok(out)
}

/// [`DesignError::Stopped`] once the caller has asked the run to stop.
fn stopped(progress: &dyn Progress) -> Result<(), DesignError> {
    if progress.cancelled() {
        return Err(DesignError::Stopped);
    }
    Ok(())
}

/// (onset, left, right) of a tongue at the level.
type OnsetEdges = (f64, f64, f64);
/// One Nelder–Mead start's report, history and best point.
type StartRun = (StartReport, Vec<HistoryPoint>, Vec<f64>);
