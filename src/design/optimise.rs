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

/// Edge of the initial Nelder–Mead simplex in scaled units: 10 % of each variable's range
/// (of its logarithm for C_f, L, ω), large enough to step across a narrow region.
const SIMPLEX_STEP: f64 = 0.1;
/// Nelder–Mead stops when the simplex's objective values differ by less than this (rad/s):
/// the band edges themselves are bisected to 0.2 rad/s.
const OBJECTIVE_TOLERANCE: f64 = 0.1;
/// Penalty per scaled unit outside [0, 1] (rad/s): the optimiser evaluates the nearest
/// point inside the bounds and is pushed back in.
const BOUND_PENALTY: f64 = 1.0e4;
/// Cost of a candidate whose analysis failed (rad/s, far worse than any band).
const FAILED_COST: f64 = 1.0e9;
/// Central-difference step of the constraint gradients in scaled units (1 % of a range).
const GRADIENT_STEP: f64 = 0.01;
/// Initial and largest trust region of the convex steps (scaled units).
const TRUST_START: f64 = 0.25;
const TRUST_MAX: f64 = 0.5;
/// A trust region below this means no further progress is possible.
const TRUST_MIN: f64 = 1e-3;
/// Extra margin asked of each linearised constraint (rad/s, β for onsets): the edges are
/// resolved to 0.2 rad/s, so a constraint met exactly could be violated by that much.
const MARGIN_PHI: f64 = 0.5;
const MARGIN_BETA: f64 = 2e-3;
/// How far (rad/s) beyond its own half-width an unlabelled sliver is looked for after a
/// gradient step: a 1 % step moves a region by a few rad/s.
const UNLABELLED_SEARCH: f64 = 10.0;
/// Slack price of the elastic step (per unit of violation): far above any change cost.
const ELASTIC_WEIGHT: f64 = 1.0e3;
/// A convex step smaller than this (scaled units) ends the run.
const STEP_MIN: f64 = 1e-4;
/// Points of the clear-bands global pass per configured start.
const GLOBAL_POINTS_PER_START: usize = 4;

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

/// The Nelder–Mead cost of one start: −(band objective) + bound penalty; records history.
struct BandCost<'a, 'b> {
    ctx: &'a Context<'b>,
    start: usize,
    history: RefCell<Vec<HistoryPoint>>,
}

impl CostFunction for BandCost<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, u: &Self::Param) -> Result<f64, argmin::core::Error> {
        let outside: f64 = u.iter().map(|&x| (x - x.clamp(0.0, 1.0)).abs()).sum();
        let value = self.ctx.band_objective(u);
        let mut h = self.history.borrow_mut();
        let best = h.last().map_or(value, |p| p.best.max(value));
        let step = h.len() + 1;
        h.push(HistoryPoint { start: self.start, step, value, best });
        Ok(-value + BOUND_PENALTY * outside)
    }
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

/// The physics seed: every tuning variable (ω of Eq. 4, or L through it) set so that the
/// predicted electrical region starts ω_w + ω_e (w = the lowest forward and backward
/// mechanical whirls of the reference, at each speed) lie as far from φ_op as the bounds
/// allow; other variables keep their reference values. None without a tuning variable.
fn physics_seed(ctx: &Context<'_>, reference: &[f64], phi_op: f64) -> Result<Option<Vec<f64>>, DesignError> {
    let tuning: Vec<usize> = (0..ctx.spec.variables.len())
        .filter(|&j| matches!(ctx.spec.variables[j].parameter, Parameter::TuningFrequency | Parameter::Inductance))
        .collect();
    if tuning.is_empty() {
        return Ok(None);
    }
    let rotor = crate::analysis::Rotor::new(&ctx.base.model)?;
    let mut whirls = Vec::new();
    for &w in &ctx.spec.speeds {
        let m = crate::analysis::modes::whirl_modes_of(&rotor, &ctx.base.settings, w)?;
        for tag in ["f1", "b1"] {
            if let Some(x) = m.modes.iter().find(|x| x.tag() == tag) {
                whirls.push(x.frequency);
            }
        }
    }
    let cp_t = ctx.base.model.left.cp_t;
    let mut u = to_unit(ctx.spec, reference);
    for &j in &tuning {
        let v: &Variable = &ctx.spec.variables[j];
        // ω_e as a function of the scaled variable (L through Eq. 4 with the branch's C_f).
        let c_f = ctx.base.model.circuit.branches[v.branch].c_f;
        let omega = |x: f64| match v.parameter {
            Parameter::TuningFrequency => v.from_unit(x),
            _ => crate::model::Branch { c_f, inductance: v.from_unit(x), resistance: 0.0 }.tuning_frequency(cp_t),
        };
        let distance = |x: f64| whirls.iter().map(|w| (w + omega(x) - phi_op).abs()).fold(f64::INFINITY, f64::min);
        let best = (0..=200).map(|k| k as f64 / 200.0).max_by(|a, b| distance(*a).total_cmp(&distance(*b)));
        u[j] = best.unwrap_or(u[j]);
    }
    Ok(Some(u))
}

/// Run the design of `base.design`, first checked by the `[design]` rules
/// ([`DesignSpec::check`]: a spec built in code is not trusted); `progress` receives the
/// number of candidates so far. The result is verified independently ([`crate::design::verify`]); the catalogues of
/// the reference and the tuned design (for the report) come with it.
pub fn run(base: &Problem, progress: &(dyn Fn(usize) + Sync)) -> Result<DesignOutcome, DesignError> {
    let spec = base.design.as_ref().ok_or(DesignError::NoDesign)?;
    spec.check(base.model.circuit.branches.len()).map_err(|(field, error)| DesignError::Spec { field, error })?;
    let started = Instant::now();
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
    };
    let before = values_of(base, spec);
    // The reference design's Floquet points must pass the β = 0 check over the design's
    // range at every speed before any candidate is searched.
    for (_, fs) in &Candidate::new(base, spec, &before)?.systems {
        check_reliable(fs, spec.range())?;
    }
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

fn widest_band(ctx: &Context<'_>, out: &mut DesignOutcome) -> Result<(), DesignError> {
    let spec = ctx.spec;
    let phi_op = ctx.phi_op.ok_or(DesignError::NoOperatingFrequency)?;
    let n = spec.variables.len();
    let reference = to_unit(spec, &out.before);
    let mut starts: Vec<(String, Vec<f64>)> = vec![("reference".into(), reference.clone())];
    if let Some(seed) = physics_seed(ctx, &out.before, phi_op)? {
        starts.push(("physics seed".into(), seed));
    }
    let mut k = 0;
    while starts.len() < spec.starts.max(1) {
        starts.push((format!("halton {}", k + 1), halton(k, n)));
        k += 1;
    }
    starts.truncate(spec.starts.max(1));
    // Starts in parallel (the outermost loop); each Nelder–Mead run is sequential.
    let runs: Vec<Result<StartRun, DesignError>> = starts
        .par_iter()
        .enumerate()
        .map(|(i, (origin, u0))| {
            let cost = BandCost { ctx, start: i, history: RefCell::new(Vec::new()) };
            let mut simplex = vec![u0.clone()];
            for j in 0..n {
                let mut p = u0.clone();
                p[j] = if p[j] + SIMPLEX_STEP <= 1.0 { p[j] + SIMPLEX_STEP } else { p[j] - SIMPLEX_STEP };
                simplex.push(p);
            }
            let solver = NelderMead::new(simplex)
                .with_sd_tolerance(OBJECTIVE_TOLERANCE)
                .map_err(|e| DesignError::Optimiser(e.to_string()))?;
            let res = Executor::new(cost, solver)
                .configure(|s| s.max_iters(spec.max_iterations as u64))
                .run()
                .map_err(|e| DesignError::Optimiser(e.to_string()))?;
            let state = res.state();
            let best_u: Vec<f64> = state
                .get_best_param()
                .cloned()
                .unwrap_or_else(|| u0.clone())
                .iter()
                .map(|x| x.clamp(0.0, 1.0))
                .collect();
            let history = res.problem.problem.as_ref().map(|c| c.history.borrow().clone()).unwrap_or_default();
            let report = StartReport {
                origin: origin.clone(),
                initial: ctx.values(u0),
                best: ctx.values(&best_u),
                objective: -state.get_best_cost(),
                evaluations: history.len(),
                iterations: state.get_iter(),
                termination: state.get_termination_reason().map_or("none".into(), |r| r.to_string()),
            };
            Ok((report, history, best_u))
        })
        .collect();
    let mut finals = Vec::new();
    for r in runs {
        let (report, history, u) = r?;
        finals.push(u);
        out.history.extend(history);
        out.starts.push(report);
    }
    let reference_candidate = Candidate::new(ctx.base, spec, &out.before)?;
    out.before_bands = ctx.bands(&reference_candidate)?;
    // The widest band over the starts' best points, by the same band function as the
    // objective (ties: the earlier start).
    let banded: Vec<Result<Vec<OperatingBand>, DesignError>> =
        finals.par_iter().map(|u| ctx.bands(&Candidate::new(ctx.base, spec, &ctx.values(u))?)).collect();
    let mut best: Option<(f64, usize, Vec<OperatingBand>)> = None;
    for (k, b) in banded.into_iter().enumerate() {
        let b = b?;
        let w = smallest(&b);
        if best.as_ref().is_none_or(|x| w > x.0) {
            best = Some((w, k, b));
        }
    }
    match best {
        Some((w, k, bands)) if w > smallest(&out.before_bands) => {
            out.status = Status::Improved;
            out.after = ctx.values(&finals[k]);
            out.after_bands = bands;
        }
        _ => {
            out.status = Status::Unchanged;
            out.after = out.before.clone();
            out.after_bands = out.before_bands.clone();
        }
    }
    Ok(())
}

/// (onset bound, left, right) of an intrusion's tongue in a nearby candidate.
fn intrusion_quantities(ctx: &Context<'_>, c: &Candidate, it: &Intrusion) -> Result<Option<OnsetEdges>, DesignError> {
    follow(c, ctx.spec, &ctx.regions, it, UNLABELLED_SEARCH, &ctx.floquet)
}

fn total(ints: &[Intrusion]) -> f64 {
    ints.iter().map(Intrusion::violation).sum()
}

fn evaluate_bands(ctx: &Context<'_>, u: &[f64]) -> Result<Vec<Intrusion>, DesignError> {
    let c = ctx.candidate(u)?;
    intrusions(&c, ctx.spec, &ctx.regions, &ctx.floquet)
}

/// Squared distance in scaled units (the QP's weights are all 1).
fn change(u: &[f64], r: &[f64]) -> f64 {
    u.iter().zip(r).map(|(a, b)| (a - b) * (a - b)).sum()
}

/// One sequential-convex run from `u0` toward the least change from `reference`.
struct ConvexRun {
    u: Vec<f64>,
    intrusions: Vec<Intrusion>,
    steps: Vec<ConvexStep>,
    /// The linearised constraints had no solution anywhere inside the bounds.
    linear_infeasible: bool,
}

/// The linearised constraints of the current intrusions and neighbours (module docs).
fn linearise(ctx: &Context<'_>, u: &[f64], ints: &[Intrusion]) -> Result<Vec<Linear>, DesignError> {
    let spec = ctx.spec;
    let n = u.len();
    // Central differences (one-sided at a bound); the perturbed candidates in parallel.
    let probes: Vec<(usize, f64)> = (0..n).flat_map(|j| [(j, GRADIENT_STEP), (j, -GRADIENT_STEP)]).collect();
    let probed: Vec<Result<Vec<Option<OnsetEdges>>, DesignError>> = probes
        .par_iter()
        .map(|&(j, h)| {
            let mut p = u.to_vec();
            p[j] = (p[j] + h).clamp(0.0, 1.0);
            let c = ctx.candidate(&p)?;
            ints.iter().map(|it| intrusion_quantities(ctx, &c, it)).collect()
        })
        .collect();
    let probed = probed.into_iter().collect::<Result<Vec<_>, _>>()?;
    let mut constraints = Vec::new();
    for (i, it) in ints.iter().enumerate() {
        let mut grad = [vec![0.0; n], vec![0.0; n], vec![0.0; n]]; // onset, left, right
        for j in 0..n {
            let (up, dn) = (&probed[2 * j][i], &probed[2 * j + 1][i]);
            let span = (u[j] + GRADIENT_STEP).min(1.0) - (u[j] - GRADIENT_STEP).max(0.0);
            if let (Some(a), Some(b)) = (up, dn) {
                grad[0][j] = (a.0 - b.0) / span;
                grad[1][j] = (a.1 - b.1) / span;
                grad[2][j] = (a.2 - b.2) / span;
            }
        }
        let g = spec.bands[it.band].guarded();
        let below = Linear { g: grad[2].clone(), h: g.lo - MARGIN_PHI - it.right };
        let above = Linear { g: grad[1].iter().map(|x| -x).collect(), h: it.left - g.hi - MARGIN_PHI };
        let lifted = Linear { g: grad[0].iter().map(|x| -x).collect(), h: it.onset - spec.level - MARGIN_BETA };
        if !it.inside {
            // A neighbour keeps its side.
            constraints.push(if it.right <= g.lo { below } else { above });
            continue;
        }
        // Three ways out: below the band, above it, or onset above β_op; take the one the
        // linearisation says is the shortest move.
        let cost = |c: &Linear| {
            let norm = c.g.iter().map(|x| x * x).sum::<f64>().sqrt();
            if norm > 0.0 {
                (-c.h).max(0.0) / norm
            } else {
                f64::INFINITY
            }
        };
        let options = [below, above, lifted];
        if let Some(best) = options.into_iter().min_by(|a, b| cost(a).total_cmp(&cost(b))) {
            if cost(&best).is_finite() {
                constraints.push(best);
            }
        }
    }
    Ok(constraints)
}

fn convex_run(ctx: &Context<'_>, u0: &[f64], reference: &[f64]) -> Result<ConvexRun, DesignError> {
    let spec = ctx.spec;
    let n = u0.len();
    let mut u = u0.to_vec();
    let mut ints = evaluate_bands(ctx, &u)?;
    let mut merit = total(&ints);
    let mut trust = TRUST_START;
    let mut steps = Vec::new();
    let mut linear_infeasible = false;
    let weights = vec![1.0; n];
    for iteration in 1..=spec.max_iterations {
        let constraints = linearise(ctx, &u, &ints)?;
        let problem =
            |trust: f64| StepProblem { current: &u, reference, weights: &weights, constraints: &constraints, trust };
        let step = match qp::solve(&problem(trust), None).map_err(DesignError::Qp)? {
            Step::Solved(d) => d,
            Step::Infeasible => {
                linear_infeasible = qp::solve(&problem(1.0), None).map_err(DesignError::Qp)? == Step::Infeasible;
                match qp::solve(&problem(trust), Some(ELASTIC_WEIGHT)).map_err(DesignError::Qp)? {
                    Step::Solved(d) => d,
                    Step::Infeasible => return Err(DesignError::Qp("the elastic step problem is infeasible".into())),
                }
            }
        };
        let size = step.iter().fold(0.0f64, |m, d| m.max(d.abs()));
        if size < STEP_MIN {
            break;
        }
        let trial: Vec<f64> = u.iter().zip(&step).map(|(a, d)| (a + d).clamp(0.0, 1.0)).collect();
        let trial_ints = evaluate_bands(ctx, &trial)?;
        let trial_merit = total(&trial_ints);
        // Accept a smaller intrusion, or, once clear, a smaller change that stays clear.
        let accepted = trial_merit < merit
            || (trial_merit == 0.0 && merit == 0.0 && change(&trial, reference) < change(&u, reference));
        steps.push(ConvexStep {
            iteration,
            trust,
            constraints: constraints.len(),
            intrusion_before: merit,
            intrusion_after: Some(trial_merit),
            accepted,
            values: ctx.values(&trial),
        });
        if accepted {
            u = trial;
            ints = trial_ints;
            merit = trial_merit;
            trust = (2.0 * trust).min(TRUST_MAX);
        } else {
            trust /= 2.0;
            if trust < TRUST_MIN {
                break;
            }
        }
    }
    Ok(ConvexRun { u, intrusions: ints, steps, linear_infeasible })
}

fn clear_bands(ctx: &Context<'_>, out: &mut DesignOutcome) -> Result<(), DesignError> {
    let spec = ctx.spec;
    let n = spec.variables.len();
    let reference = to_unit(spec, &out.before);
    // A coarse global pass: the landscape is disjunctive (a region can leave a band on
    // either side, or pass through a neighbouring band), so the local convex steps from
    // the reference alone can stall. Halton points, in parallel.
    let mut points: Vec<(String, Vec<f64>)> = vec![("reference".into(), reference.clone())];
    points.extend((0..GLOBAL_POINTS_PER_START * spec.starts).map(|k| (format!("halton {}", k + 1), halton(k, n))));
    let merits: Vec<Result<(f64, Vec<Intrusion>), DesignError>> = points
        .par_iter()
        .map(|(_, u)| {
            let ints = evaluate_bands(ctx, u)?;
            Ok((total(&ints), ints))
        })
        .collect();
    let mut scored = Vec::new();
    for ((origin, u), m) in points.iter().zip(merits) {
        let (merit, ints) = m?;
        if origin == "reference" {
            out.before_intrusions = ints.into_iter().filter(|i| i.inside).collect();
        }
        out.starts.push(StartReport {
            origin: origin.clone(),
            initial: ctx.values(u),
            best: ctx.values(u),
            objective: -merit,
            evaluations: 1,
            iterations: 0,
            termination: "global pass".into(),
        });
        scored.push((merit, change(u, &reference), u.clone()));
    }
    // Convex runs from the reference and from the best global point (least intrusion,
    // then least change).
    let mut seeds = vec![reference.clone()];
    if let Some(best) = scored[1..].iter().min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1))) {
        seeds.push(best.2.clone());
    }
    let mut best_run: Option<ConvexRun> = None;
    for (k, u0) in seeds.iter().enumerate() {
        let run = convex_run(ctx, u0, &reference)?;
        let merit = total(&run.intrusions);
        out.history.push(HistoryPoint { start: k, step: 0, value: total(&run.intrusions), best: merit });
        for (i, s) in run.steps.iter().enumerate() {
            let value = s.intrusion_after.unwrap_or(s.intrusion_before);
            out.history.push(HistoryPoint { start: k, step: i + 1, value, best: value.min(s.intrusion_before) });
        }
        out.convex_steps.extend(run.steps.iter().cloned());
        let better = match &best_run {
            None => true,
            Some(b) => {
                let (m0, m1) = (total(&b.intrusions), merit);
                m1 < m0 || (m1 == m0 && change(&run.u, &reference) < change(&b.u, &reference))
            }
        };
        if better {
            best_run = Some(run);
        }
    }
    let run = best_run.expect("at least the reference run");
    out.linear_infeasible = run.linear_infeasible;
    out.after = ctx.values(&run.u);
    out.after_intrusions = run.intrusions.into_iter().filter(|i| i.inside).collect();
    out.status = if out.after_intrusions.is_empty() { Status::Feasible } else { Status::Infeasible };
    Ok(())
}
