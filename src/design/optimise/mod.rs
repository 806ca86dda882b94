//! The design runs: multi-start Nelder–Mead for the widest stable band, sequential convex
//! programming for clear bands (see the module docs of [`crate::design`]).

use super::evaluate::{
    as_build, follow, intrusions, intrusions_as_built, values_of, Candidate, EvalContext, Intrusion, OperatingBand,
};
use super::machine::Machine;
use super::qp::{self, Linear, Solved, Step, StepProblem};
use super::spec::{DesignSpec, Parameter, Variable};
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

mod bands_as_built;
mod best;
mod convex;
mod map;
mod min_peak;
mod nelder_mead;
mod observer;
mod outcome;
mod peak_as_built;
mod verification;

use best::{BestSoFar, Rank};
pub(crate) use convex::clear_bands;
pub use convex::GLOBAL_PASS;
pub use map::{
    extra_starts, map_points, slice_points, MapPoint, MapSlice, ObjectiveMap, MAP_POINTS_PER_VARIABLE, SLICE_POINTS,
};
pub(crate) use min_peak::min_peak;
pub use min_peak::{JudgedDesign, PeakFindings, PeakStep, Price};
pub(crate) use nelder_mead::widest_band;
pub use observer::{Observation, Observer};
pub use outcome::{
    BasisRound, ConvexStep, Cost, CrossingDamping, DesignOutcome, Findings, FindingsKind, HistoryPoint, StartReport,
    Status, VibrationReport, REPORT_DAMPING_WHIRLS,
};
pub use peak_as_built::{CornerPeak, PeakAsBuilt};

/// Cost of a candidate whose analysis failed (rad/s, far worse than any band).
const FAILED_COST: f64 = 1.0e9;

/// Shared state of an optimisation round, which an objective's optimiser works with
/// ([`crate::design::objective::Objective::optimise`]): the base machine, the spec, the
/// counters, the progress and the caller's observer, the reference design and the starts.
pub struct Context<'a> {
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
    /// The context every judgement of a candidate in the run reads: the spec, the region
    /// settings and the run's Floquet counter.
    fn eval(&self) -> EvalContext<'_> {
        EvalContext { spec: self.spec, regions: &self.regions, count: &self.floquet }
    }

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
        let (spec, ev) = (self.spec, &self.eval());
        let nominal = robust::judged(c, ev, phi_op, MARGIN_PENALTY)?;
        let (worst_speed, mut value) = match spec.speed_range {
            Some(_) => {
                let (w, width) = robust::refined_worst(c, ev, phi_op, &nominal.bands)?;
                (Some(w), nominal.smallest.min(width) - nominal.penalty)
            }
            None => (None, nominal.value()),
        };
        if let Some(t) = &spec.tolerances {
            let corners = t.corners();
            let worst = corners[1..]
                .par_iter()
                .map(|p| match worst_speed {
                    Some(w) => robust::judged_at(&c.perturbed_rotor(p)?, ev, phi_op, w, MARGIN_PENALTY),
                    None => Ok(robust::judged(&c.perturbed(spec, p)?, ev, phi_op, MARGIN_PENALTY)?.value()),
                })
                .collect::<Result<Vec<f64>, DesignError>>()?;
            value = worst.into_iter().fold(value, f64::min);
        }
        Ok((value, nominal.bands))
    }
}

/// The map's slices through the tuned design `out.after` (more than two variables and a
/// map: [`map::slice_grids`]), `f` the map's objective at a scaled point (None where the
/// candidate fails); each slice's points in parallel.
fn fill_slices(
    ctx: &Context<'_>,
    out: &mut DesignOutcome,
    f: &(dyn Fn(&[f64]) -> Option<f64> + Sync),
) -> Result<(), DesignError> {
    if ctx.spec.variables.len() <= 2 || out.map.is_none() {
        return Ok(());
    }
    let optimum = to_unit(ctx.spec, &out.after);
    let mut slices = Vec::new();
    for (pair, grid) in map::slice_grids(&optimum) {
        let values: Vec<Option<f64>> = grid.par_iter().map(|u| f(u)).collect();
        stopped(ctx.progress)?;
        let points =
            grid.iter().zip(values).map(|(u, objective)| MapPoint { values: ctx.values(u), objective }).collect();
        slices.push(MapSlice { pair, points });
    }
    if let Some(m) = out.map.as_mut() {
        m.slices = slices;
    }
    Ok(())
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

/// The most candidates a design of `spec` builds (its objective's
/// [`crate::design::objective::Objective::most_candidates`]). An optimiser that converges
/// early builds fewer.
pub fn most_candidates(spec: &DesignSpec) -> usize {
    spec.objective.most_candidates(spec)
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
/// points and reference, judged afresh; the reference where there is none). Each band
/// search asks too, so the stop comes within a search step.
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
    stopped(progress)?;
    verification::verify_outcome(&sized, spec, &mut out, progress)?;
    // A stop asked during the verification leaves its searches incomplete: no verdict.
    stopped(progress)?;
    Ok(out)
}

/// Most times a design runs again on a larger basis when its tuned design needs one
/// (`super::sizing::recheck`): each round is a whole optimisation, and a tuning that
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
    spec.objective.optimise(&ctx, &mut out)?;
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
