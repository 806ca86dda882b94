//! A run's jobs on the whirls and the synchronous response: the model checked, the
//! lowest whirls at a speed, the Campbell diagram, the damping ratios tracked over
//! speeds, and the unbalance response (with a second configuration beside it).

use super::admit::MODEL_ONLY;
use super::design::modes_exist;
use super::{Run, RunError};
use crate::analysis::campbell::{campbell, CampbellResult};
use crate::analysis::cost::{self, Dense, Estimate};
use crate::analysis::damping::{lowest_damping, mode_damping, ModeDamping};
use crate::analysis::modes::{lowest_whirls_of, ModesResult};
use crate::analysis::unbalance::{probes, unbalance_response, UnbalanceResult};
use crate::analysis::{AnalysisError, Rotor};
use crate::problem::Problem;
use crate::progress::Progress;

/// The lowest whirls a run computed ([`Run::modes`]).
pub type ModesRun = ModesResult;

/// The Campbell diagram a run computed ([`Run::campbell`]).
pub type CampbellRun = CampbellResult;

/// The damping ratios a run computed ([`Run::damping`]).
pub type DampingRun = Vec<ModeDamping>;

/// A Campbell diagram admitted by a run and not yet run.
pub struct CampbellJob<'r, 'a> {
    run: &'r Run<'a>,
    problem: &'r Problem,
    speeds: &'r [f64],
    count: usize,
}

/// An unbalance response admitted by a run and not yet run ([`Run::unbalance`]).
pub struct UnbalanceJob<'r, 'a> {
    run: &'r Run<'a>,
    problems: Vec<&'r Problem>,
    speeds: &'r [f64],
    nodes: &'r [usize],
}

/// The unbalance responses a run computed: the problem's, and the compared one's.
#[derive(Debug)]
pub struct UnbalanceRun {
    /// The problem's response.
    pub main: UnbalanceResult,
    /// The compared configuration's response.
    pub other: Option<UnbalanceResult>,
}

impl<'a> Run<'a> {
    /// The rotor of `problem`, its dense stages admitted first (and the whirls too when
    /// its design has damping constraints, whose whirl tags are checked against the
    /// model as the design will).
    pub fn check(&self, problem: &Problem) -> Result<Rotor, RunError> {
        self.admit_dense("`check`", problem, Dense::Rotor)?;
        let spec = problem.design.as_ref().filter(|s| !s.constraints.damping.is_empty());
        if spec.is_some() {
            self.admit_dense("`check`", problem, Dense::Whirls(1))?;
        }
        let rotor = Rotor::new(&problem.model)?;
        if let Some(spec) = spec {
            modes_exist(problem, Some(&rotor), spec)?;
        }
        Ok(rotor)
    }

    /// The lowest `count` forward and backward whirls of `problem` at `speed` (rad/s).
    pub fn modes(&self, problem: &Problem, speed: f64, count: usize) -> Result<ModesRun, RunError> {
        self.admit_dense("`modes`", problem, Dense::Whirls(1))?;
        let rotor = Rotor::new(&problem.model)?;
        Ok(lowest_whirls_of(&rotor, &problem.settings, speed, count)?)
    }

    /// Admit the Campbell diagram of `problem` over `speeds` (rad/s, checked by the
    /// caller) with `count` tracks of each whirl direction.
    pub fn campbell<'r>(
        &'r self,
        problem: &'r Problem,
        speeds: &'r [f64],
        count: usize,
    ) -> Result<CampbellJob<'r, 'a>, RunError> {
        if speeds.is_empty() {
            return Err(AnalysisError::NoSpeeds.into());
        }
        let threads = rayon::current_num_threads();
        let estimate = cost::dense(&problem.model, Dense::Whirls(speeds.len()), threads);
        self.admit("the Campbell diagram", &estimate, &MODEL_ONLY)?;
        Ok(CampbellJob { run: self, problem, speeds, count })
    }

    /// The damping ratios of `problem`'s whirls tagged `tags` (by their tag at the first
    /// speed), or of the lowest `count` forward and backward whirls when `tags` is empty,
    /// tracked over `speeds` (rad/s): a `damping` phase, a step per speed.
    pub fn damping(
        &self,
        problem: &Problem,
        speeds: &[f64],
        tags: &[String],
        count: usize,
    ) -> Result<DampingRun, RunError> {
        let threads = rayon::current_num_threads();
        let estimate = cost::dense(&problem.model, Dense::Whirls(speeds.len() + 1), threads);
        self.admit("the damping-ratio tracking", &estimate, &MODEL_ONLY)?;
        let rotor = Rotor::new(&problem.model)?;
        self.observer().phase("damping", speeds.len() as u64);
        let deadline = self.limits(None);
        let result = if tags.is_empty() {
            lowest_damping(&rotor, &problem.settings, speeds, count, &deadline)
        } else {
            mode_damping(&rotor, &problem.settings, speeds, tags, &deadline)
        };
        self.stopped(&deadline, "the damping-ratio tracking")?;
        Ok(result?)
    }

    /// Admit the unbalance response of `problem` (and of `other` beside it) over
    /// `speeds` (rad/s, checked by the caller) at the disks, the supports and the shaft
    /// `nodes`.
    pub fn unbalance<'r>(
        &'r self,
        problem: &'r Problem,
        other: Option<&'r Problem>,
        speeds: &'r [f64],
        nodes: &'r [usize],
    ) -> Result<UnbalanceJob<'r, 'a>, RunError> {
        if speeds.is_empty() {
            return Err(AnalysisError::NoSpeeds.into());
        }
        let problems: Vec<&Problem> = std::iter::once(problem).chain(other).collect();
        let mut estimate = Estimate::zero();
        for p in &problems {
            let last = p.model.shaft.nodes() - 1;
            if let Some(&node) = nodes.iter().find(|&&n| n > last) {
                return Err(AnalysisError::ProbeNodeOffShaft { node, last }.into());
            }
            estimate = estimate.then(cost::unbalance(&p.model, speeds.len(), nodes.len()));
        }
        self.admit("the unbalance response", &estimate, &MODEL_ONLY)?;
        Ok(UnbalanceJob { run: self, problems, speeds, nodes })
    }
}

impl CampbellJob<'_, '_> {
    /// Run the diagram: a `whirls` phase, a step per speed.
    pub fn run(self) -> Result<CampbellRun, RunError> {
        let CampbellJob { run, problem, speeds, count } = self;
        let rotor = Rotor::new(&problem.model)?;
        run.observer().phase("whirls", speeds.len() as u64);
        let deadline = run.limits(None);
        let result = campbell(&rotor, &problem.settings, speeds, count, &deadline);
        run.stopped(&deadline, "the Campbell diagram")?;
        Ok(result?)
    }
}

impl UnbalanceJob<'_, '_> {
    /// Run the responses: an `unbalance` phase (a step per speed), and `compare` for the
    /// second configuration.
    pub fn run(self) -> Result<UnbalanceRun, RunError> {
        let deadline = self.run.limits(None);
        let mut results = Vec::new();
        for (p, what) in self.problems.iter().zip(["unbalance", "compare"]) {
            let rotor = Rotor::new(&p.model)?;
            let probes = probes(&rotor, self.nodes)?;
            deadline.phase(what, self.speeds.len() as u64);
            let r = unbalance_response(&rotor, self.speeds, &probes, &deadline);
            self.run.stopped(&deadline, "the unbalance response")?;
            results.push(r?);
        }
        let mut results = results.into_iter();
        let main = results.next().ok_or(AnalysisError::NoSpeeds)?;
        Ok(UnbalanceRun { main, other: results.next() })
    }
}
