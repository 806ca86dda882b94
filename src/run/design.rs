//! A run's design jobs: a problem's `[design]` (with the charts of its report when
//! asked), its Pareto front, and the up-front estimate they are admitted by.

use super::admit::DESIGN;
use super::{Outcome, Run, RunError, RunStatus};
use crate::analysis::cost::{self, Dense, Driver, Estimate, PointCost};
use crate::analysis::{Interval, Rotor};
use crate::design::content::{self, content, content_steps, DesignContent, CAMPBELL_SPEEDS};
use crate::design::evaluate::{values_of, Candidate};
use crate::design::objective::CostAt;
use crate::design::pareto::Front;
use crate::design::spec::{DesignSpec, VERIFY_SPEEDS};
use crate::design::verify;
use crate::design::{self, DesignError, DesignOutcome, Status};
use crate::model::Model;
use crate::problem::{Problem, ProblemError, ProblemErrorKind};
use crate::progress::Progress;

/// A design as a run ran it.
#[derive(Debug)]
pub struct DesignRun {
    /// The outcome (the best design judged so far when it was stopped,
    /// [`Status::Stopped`], with [`DesignOutcome::stop`] naming the limit).
    pub outcome: DesignOutcome,
    /// The problem's model with the tuned circuit.
    pub tuned: Model,
    /// The charts and Campbell diagram of the report, when asked and the design ended.
    pub content: Option<DesignContent>,
}

impl DesignJob<'_, '_> {
    /// The estimate the design was admitted by.
    pub fn estimate(&self) -> &Estimate {
        &self.estimate
    }

    /// Run the design; with `charts`, the report's charts and Campbell diagram too (a
    /// `report` phase of a step per chart row and Campbell speed, and 4 more for the
    /// caller's files). A design stopped by a limit or its caller keeps the best design
    /// judged so far; the charts of a design that ended, stopped, are an error.
    pub fn run(self, charts: bool) -> Result<Outcome<DesignRun>, RunError> {
        let DesignJob { run, problem, spec, estimate } = self;
        let machine = problem.machine();
        let deadline = run.limits(Some(&estimate));
        let mut outcome = design::run(&machine, spec, &deadline)?;
        let status = run.status(&deadline);
        let stop = run.budget.stopped(&deadline, "the design").err();
        let evaluations = deadline.evaluations();
        if outcome.status == Status::Stopped {
            outcome.stop = stop.as_ref().map(super::Stopped::reason);
            let tuned = design::evaluate::machine_at(&machine, spec, &outcome.after)?.model;
            let value = DesignRun { outcome, tuned, content: None };
            return Ok(Outcome { status, value, stop, evaluations });
        }
        let after = Candidate::new(&machine, spec, &outcome.after)?;
        let content = if charts {
            let before = Candidate::new(&machine, spec, &outcome.before)?;
            deadline.phase("report", (content_steps(spec) + 4) as u64);
            // Every band the charts draw: the stable bands found before and after, the
            // operating bands with their clearances.
            let bands: Vec<Interval> = outcome
                .before_bands()
                .iter()
                .chain(outcome.after_bands())
                .filter_map(|b| b.band.band)
                .chain(spec.kept_clear().iter().map(|b| b.guarded()))
                .collect();
            let content = content(spec, &before, &after, &bands, &deadline);
            run.stopped(&deadline, "the design's report")?;
            Some(content?)
        } else {
            None
        };
        let tuned = after.machine.model;
        let value = DesignRun { outcome, tuned, content };
        Ok(Outcome { status: RunStatus::Completed, value, stop: None, evaluations })
    }
}

impl FrontJob<'_, '_> {
    /// Run the front.
    pub fn run(self) -> Result<Front, RunError> {
        let FrontJob { run, problem, spec, points, estimate } = self;
        let deadline = run.limits(Some(&estimate));
        let front = design::pareto::front(&problem.machine(), spec, points, &deadline);
        run.stopped(&deadline, "the Pareto front")?;
        Ok(front?)
    }
}

/// The spec of `problem`'s design, or the error of a file without one.
fn spec_of(problem: &Problem) -> Result<&DesignSpec, RunError> {
    problem.design.as_ref().ok_or(RunError::Design(DesignError::NoDesign))
}

/// A design admitted by a run and not yet run ([`Run::design`]): the caller makes what
/// it writes to between the admission and the work.
#[derive(Debug)]
pub struct DesignJob<'r, 'a> {
    run: &'r Run<'a>,
    problem: &'r Problem,
    spec: &'r DesignSpec,
    estimate: Estimate,
}

/// A Pareto front admitted by a run and not yet run ([`Run::pareto`]).
#[derive(Debug)]
pub struct FrontJob<'r, 'a> {
    run: &'r Run<'a>,
    problem: &'r Problem,
    spec: &'r DesignSpec,
    points: usize,
    estimate: Estimate,
}

impl<'a> Run<'a> {
    /// Admit the design of `problem` (its `[design]`) by its estimate as `what` (e.g.
    /// `the design`, `a design case`), its damping constraints' whirls checked against
    /// the model; [`DesignJob::run`] runs it.
    pub fn design<'r>(&'r self, problem: &'r Problem, what: &str) -> Result<DesignJob<'r, 'a>, RunError> {
        let spec = spec_of(problem)?;
        let estimate = self.design_estimate(problem, spec)?;
        self.admit(what, &estimate, &DESIGN)?;
        modes_exist(problem, None, spec)?;
        Ok(DesignJob { run: self, problem, spec, estimate })
    }

    /// Admit the Pareto front of `problem`'s design trade-off with `points` points
    /// ([`design::pareto::front`]); a design without a trade-off is refused at its key.
    pub fn pareto<'r>(&'r self, problem: &'r Problem, points: usize) -> Result<FrontJob<'r, 'a>, RunError> {
        let spec = spec_of(problem)?;
        design::pareto::trade_off(spec).map_err(|e| problem.refuse(&e.key, ProblemErrorKind::NoTradeOff(e.reason)))?;
        // A front is its points' runs, and a point run again when it is dominated.
        let one = self.design_estimate(problem, spec)?;
        let estimate = one.times((2 * points) as f64, Driver::Candidates, "design runs");
        self.admit("the Pareto front", &estimate, &DESIGN)?;
        modes_exist(problem, None, spec)?;
        Ok(FrontJob { run: self, problem, spec, points, estimate })
    }

    /// The estimated cost of `problem`'s design, from its reference candidate (its rotor
    /// and reduced systems are built: bounded by the dense estimate, checked first): every
    /// candidate's dense stages and band (or operating-band) search at every speed, and
    /// the verification with the report (two catalogues per speed, the grids, the DSTM
    /// points at tongue centres, the before/after charts and the Campbell diagram).
    pub fn design_estimate(&self, problem: &Problem, spec: &DesignSpec) -> Result<Estimate, RunError> {
        let threads = rayon::current_num_threads();
        let speeds = spec.speeds.len() as f64;
        let model = &problem.model;
        let dense = cost::dense(model, Dense::Reduced, 1);
        let verify_dense = cost::dense(model, Dense::ReducedAndWhirls, 1);
        let mut memory = dense.memory.clone();
        memory.amount = (memory.amount * threads as f64).max(verify_dense.memory.amount);
        let admitted = Estimate { memory: memory.clone(), ..dense.clone() };
        self.admit("the design", &admitted, &DESIGN)?;
        let machine = problem.machine();
        let reference = Candidate::new(&machine, spec, &values_of(&machine, spec))?;
        let s = problem.regions.clone();
        let criterion = reference.criterion();
        let dense_stages = Estimate::work(dense.work.amount * speeds, Driver::Dofs, dense.work.detail.clone());
        let mut searches = Estimate::zero();
        let mut verification = Estimate::zero();
        for (k, (_, fs)) in reference.systems.iter().enumerate() {
            let pc = PointCost::of(fs);
            let seeds = reference.seeds(k, spec)?;
            let at = CostAt { point: &pc, regions: &s, criterion: &criterion, seeds: &seeds };
            searches = searches.then(spec.objective.candidate_cost(spec, &at));
            verification =
                verification.then(verify::cost(&pc, &s, &criterion, &seeds, spec)).then(content::cost(&pc, spec));
        }
        let (per_candidate, checks) = robust_plan(spec, dense_stages, searches);
        verification = verification.then(checks);
        // The whirls: the physics seed's and the catalogues' at each speed, and the
        // Campbell diagram's speeds.
        let whirls = cost::dense(model, Dense::Whirls(CAMPBELL_SPEEDS + 3 * spec.speeds.len()), threads);
        let total = per_candidate
            .times(design::optimise::most_candidates(spec) as f64, Driver::Candidates, "candidates")
            .then(verification)
            .then(whirls);
        let memory = if memory.amount > total.memory.amount { memory } else { total.memory.clone() };
        Ok(Estimate { memory, ..total })
    }
}

/// A candidate's cost by the design's plan, from its dense stages at the optimiser's
/// speeds (`dense`) and its searches there (`searches`, every speed once): the searches
/// as many times per speed as its objective judges builds and speeds
/// ([`design::objective::Objective::searches_per_candidate`]: the corners of a tolerance
/// box, a speed range's refinements), the dense stages once per build. Then the
/// verification's own checks: the tolerance check's builds (the corners at every speed,
/// the samples at one speed of a range or at every speed) and the speed check's
/// [`VERIFY_SPEEDS`] (twice with margins). The candidate's, and the checks'.
fn robust_plan(spec: &DesignSpec, dense: Estimate, searches: Estimate) -> (Estimate, Estimate) {
    let speeds = spec.speeds.len().max(1) as f64;
    let builds = spec.builds() as f64;
    let one_speed = searches.clone().times(1.0 / speeds, Driver::Builds, "");
    let per_speed = spec.objective.searches_per_candidate(spec) / speeds;
    // `times` by 1 leaves an estimate as it is: one build at its speeds is the plain sum.
    let candidate = dense.times(builds, Driver::Builds, "builds").then(searches.times(
        per_speed,
        Driver::Builds,
        "searches per speed (builds, refinements)",
    ));
    let mut checks = Estimate::zero();
    if let Some(t) = spec.tolerances {
        let sample_speeds = if spec.speed_range.is_some() { 1.0 } else { speeds };
        let count = builds * speeds + t.samples as f64 * sample_speeds;
        checks = checks.then(one_speed.clone().times(count, Driver::Builds, "searches of the tolerance check"));
    }
    if spec.speed_range.is_some() {
        let each = if spec.constraints.margins.is_some() { 2.0 } else { 1.0 };
        checks = checks.then(one_speed.times(VERIFY_SPEEDS as f64 * each, Driver::Builds, "speeds of the speed check"));
    }
    (candidate, checks)
}

/// The damping constraints' whirl tags against the model ([`design::checks::modes_exist`]),
/// checked once the run is admitted and before anything is written; a tag the model lacks
/// is refused as the file's error at the tag's line.
pub(crate) fn modes_exist(problem: &Problem, rotor: Option<&Rotor>, spec: &DesignSpec) -> Result<(), RunError> {
    if spec.constraints.damping.is_empty() {
        return Ok(());
    }
    let built;
    let rotor = match rotor {
        Some(r) => r,
        None => {
            built = Rotor::new(&problem.model)?;
            &built
        }
    };
    match design::checks::modes_exist(rotor, &problem.settings, spec) {
        Err(DesignError::UnknownMode { index, mode, speed, available }) => {
            let e: ProblemError = problem.refuse(
                &format!("design.constraints.damping[{index}].mode"),
                ProblemErrorKind::UnknownMode { mode, speed, available: available.into() },
            );
            Err(e.into())
        }
        other => Ok(other?),
    }
}
