//! The design runs: multi-start Nelder–Mead for the widest stable band, sequential convex
//! programming for clear bands (see the module docs of [`crate::design`]).

use super::evaluate::{follow, intrusions, operating_bands, values_of, Candidate, Intrusion, OperatingBand};
use super::qp::{self, Linear, Step, StepProblem};
use super::spec::{DesignSpec, Objective, Parameter, Variable};
use super::verify::{describe, verify, DesignAtSpeed};
use super::DesignError;
use crate::analysis::regions::{check_reliable, Counter, RegionSettings};
use crate::problem::Problem;
use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use rayon::prelude::*;
use serde::Serialize;
use std::cell::RefCell;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

mod convex;
mod nelder_mead;

use convex::clear_bands;
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
    /// Candidate designs evaluated.
    pub evaluations: usize,
    /// Nelder–Mead iterations.
    pub iterations: u64,
    /// argmin's termination reason.
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
    /// Best so far.
    pub best: f64,
}

/// One sequential convex step.
#[derive(Debug, Clone, Serialize)]
pub struct ConvexStep {
    /// Iteration.
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

/// Everything a design run found.
#[derive(Debug, Clone, Serialize)]
pub struct DesignOutcome {
    /// The design problem.
    pub spec: DesignSpec,
    /// How it ended.
    pub status: Status,
    /// Variable values of the reference design (SI units, as in the problem file).
    pub before: Vec<f64>,
    /// Variable values of the tuned design.
    pub after: Vec<f64>,
    /// Widest band: the stable band around φ_op of the reference design at each speed.
    pub before_bands: Vec<OperatingBand>,
    /// Widest band: the same for the tuned design.
    pub after_bands: Vec<OperatingBand>,
    /// Clear bands: tongues intruding into the widened bands, reference design.
    pub before_intrusions: Vec<Intrusion>,
    /// Clear bands: the same for the tuned design (empty when feasible).
    pub after_intrusions: Vec<Intrusion>,
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
    /// Sequential convex steps.
    pub convex_steps: Vec<ConvexStep>,
    /// Clear bands: the linearised constraints at the final point had no solution inside
    /// the bounds (a sign that the bounds forbid clearing the bands).
    pub linear_infeasible: bool,
    /// Candidate designs analysed.
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
}

/// The cost of a phase of the run.
#[derive(Debug, Clone, Copy, Default, Serialize)]
pub struct Cost {
    /// Monodromy evaluations.
    pub evaluations: usize,
    /// Wall time (s).
    pub seconds: f64,
}

/// Shared state of a run: the base problem, counters and the progress callback.
struct Context<'a> {
    base: &'a Problem,
    spec: &'a DesignSpec,
    /// φ_op of the widest-stable-band objective.
    phi_op: Option<f64>,
    regions: RegionSettings,
    floquet: Counter,
    candidates: AtomicUsize,
    failures: AtomicUsize,
    first_failure: std::sync::Mutex<Option<String>>,
    progress: &'a (dyn Fn(usize) + Sync),
    /// The reference design (the file's values), built once and checked reliable.
    reference: Candidate,
}

impl Context<'_> {
    fn values(&self, u: &[f64]) -> Vec<f64> {
        self.spec.variables.iter().zip(u).map(|(v, &x)| v.from_unit(x.clamp(0.0, 1.0))).collect()
    }

    fn candidate(&self, u: &[f64]) -> Result<Candidate, DesignError> {
        let n = self.candidates.fetch_add(1, Ordering::Relaxed) + 1;
        (self.progress)(n);
        let c = Candidate::new(self.base, self.spec, &self.values(u));
        if let Err(e) = &c {
            self.failures.fetch_add(1, Ordering::Relaxed);
            // The smallest message, not the first in time: independent of thread timing.
            let mut first = self.first_failure.lock().unwrap_or_else(|p| p.into_inner());
            let m = e.to_string();
            if first.as_ref().is_none_or(|f| m < *f) {
                *first = Some(m);
            }
        }
        c
    }

    /// The bands around φ_op of the design at `u` (scaled), at every speed.
    fn bands(&self, c: &Candidate) -> Result<Vec<OperatingBand>, DesignError> {
        let phi_op = self.phi_op.ok_or(DesignError::NoOperatingFrequency)?;
        operating_bands(c, self.spec, phi_op, &self.regions, &self.floquet)
    }

    /// Smallest signed band width over the speeds (rad/s).
    fn band_objective(&self, u: &[f64]) -> f64 {
        match self.candidate(u).and_then(|c| self.bands(&c)) {
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

/// Run the design of `base.design`, first checked by the `[design]` rules
/// ([`DesignSpec::check`]: a spec built in code is not trusted); `progress` receives the
/// number of candidates so far. The result is verified independently ([`crate::design::verify`]); the catalogues of
/// the reference and the tuned design (for the report) come with it.
pub fn run(base: &Problem, progress: &(dyn Fn(usize) + Sync)) -> Result<DesignOutcome, DesignError> {
    let spec = base.design.as_ref().ok_or(DesignError::NoDesign)?;
    spec.check(&base.model.rings.iter().map(|r| r.circuit.branches.len()).collect::<Vec<_>>())
        .map_err(|(field, error)| DesignError::Spec { field, error })?;
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
        phi_op: spec.phi_op,
        regions: RegionSettings::default(),
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
        before_bands: Vec::new(),
        after_bands: Vec::new(),
        before_intrusions: Vec::new(),
        after_intrusions: Vec::new(),
        before_speeds: Vec::new(),
        after_speeds: Vec::new(),
        verified: false,
        starts: Vec::new(),
        history: Vec::new(),
        convex_steps: Vec::new(),
        linear_infeasible: false,
        candidates: 0,
        failed_candidates: 0,
        first_failure: None,
        floquet_evaluations: 0,
        seconds: 0.0,
        verification_cost: Cost::default(),
    };
    match spec.objective {
        Objective::WidestStableBand => widest_band(&ctx, &mut out)?,
        Objective::ClearBands => clear_bands(&ctx, &mut out)?,
    }
    out.candidates = ctx.candidates.load(Ordering::Relaxed);
    out.failed_candidates = ctx.failures.load(Ordering::Relaxed);
    out.first_failure = ctx.first_failure.lock().unwrap_or_else(|p| p.into_inner()).clone();
    out.floquet_evaluations = ctx.floquet.get();
    out.seconds = started.elapsed().as_secs_f64();
    // Verification, from scratch: the reference and the tuned design rebuilt, their full
    // catalogues, and the checks on the tuned one.
    let checked = Instant::now();
    let count = Counter::default();
    let reference = Candidate::new(base, spec, &out.before)?;
    let tuned = Candidate::new(base, spec, &out.after)?;
    out.before_speeds = describe(&reference, spec, &ctx.regions)?;
    out.after_speeds = describe(&tuned, spec, &ctx.regions)?;
    count.add(out.before_speeds.iter().chain(&out.after_speeds).map(|d| d.catalogue.evaluations).sum());
    out.verified = verify(&tuned, spec, &out.after_bands, &mut out.after_speeds, &count);
    // Intrusions named after the full model's whirls: the catalogue's region with the
    // same edges (the lattice-refined edges are the same numbers).
    for (ints, speeds) in
        [(&mut out.before_intrusions, &out.before_speeds), (&mut out.after_intrusions, &out.after_speeds)]
    {
        for it in ints.iter_mut() {
            let Some(d) = speeds.iter().find(|d| d.speed == it.speed) else { continue };
            let same = |r: &&crate::analysis::regions::Region| r.left == Some(it.left) && r.right == Some(it.right);
            if let Some(r) = d.catalogue.regions.iter().filter(same).min_by_key(|r| r.order) {
                it.label = format!("{}/{}", r.label, r.order);
            }
        }
    }
    // The bands with the full model's labels (the same numbers, checked by `verify`).
    for (bands, speeds) in [(&mut out.before_bands, &out.before_speeds), (&mut out.after_bands, &out.after_speeds)] {
        for (b, d) in bands.iter_mut().zip(speeds) {
            if let Some(l) = d.band.as_ref().filter(|l| l.band == b.band.band) {
                b.band = l.clone();
            }
        }
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
