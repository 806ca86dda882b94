//! A run's Floquet jobs: one point on a basis sized by convergence, a chart over a grid
//! (with a second configuration beside it), and a time response at one point.

use super::{Names, Run, RunError};
use crate::analysis::basis::{point_sized, Schedule, Sized};
use crate::analysis::chart::{chart, ChartResult};
use crate::analysis::cost::{self, Dense, PointCost};
use crate::analysis::floquet::{FloquetPoint, FloquetSystem};
use crate::analysis::response::{checked_response, response_steps, ResponseResult};
use crate::analysis::unbalance::Probe;
use crate::analysis::{Interval, Rotor};
use crate::problem::{Problem, Warning};
use crate::progress::Progress;
use std::time::Instant;

/// The names of a point job's inputs in a refusal.
pub const POINT: Names<'static> = Names { phi: "`--phi`", grid: "`--phi`", load: "`--beta`", periods: "`--periods`" };

/// The names of a chart's inputs in a refusal.
pub const CHART: Names<'static> =
    Names { phi: "`--phi`", grid: "`--phi` and `--beta`", load: "`--beta`", periods: "`--phi`" };

/// The Floquet point a run computed ([`Run::point`]), on its basis.
pub type PointRun = Sized<FloquetPoint>;

/// A chart admitted by a run and not yet run ([`Run::chart`]).
pub struct ChartJob<'r, 'a> {
    run: &'r Run<'a>,
    phis: &'r [f64],
    betas: &'r [f64],
    main: FloquetSystem,
    other: Option<FloquetSystem>,
    /// The warnings of the φ range on the problem and on the compared one.
    pub warnings: (Vec<Warning>, Vec<Warning>),
}

/// The charts a run computed.
#[derive(Debug)]
pub struct ChartRun {
    /// The problem's chart.
    pub main: ChartResult,
    /// The compared configuration's chart.
    pub other: Option<ChartResult>,
    /// Wall time of the problem's chart (s).
    pub seconds: f64,
}

/// A time response admitted by a run and not yet run ([`Run::response`]).
pub struct ResponseJob<'r, 'a> {
    run: &'r Run<'a>,
    rotor: Rotor,
    fs: FloquetSystem,
    phi: f64,
    beta: f64,
    periods: usize,
}

/// A time response a run computed, with the Floquet point it is checked against.
#[derive(Debug)]
pub struct ResponseRun {
    /// The Floquet point at (φ, β).
    pub point: FloquetPoint,
    /// The response of the reduced system.
    pub response: ResponseResult,
    /// The disks' and supports' probes, each with its displacement u = Φ·q at each
    /// sample time (m), as [v, w] = [Re u, Im u].
    pub physical: Vec<(Probe, Vec<[f64; 2]>)>,
}

impl<'a> Run<'a> {
    /// The reduced system of `problem` for answers up to φ = `top` (rad/s)
    /// ([`FloquetSystem::for_window`]), its dense stages admitted first.
    pub fn reduced_system(&self, problem: &Problem, top: f64) -> Result<FloquetSystem, RunError> {
        Ok(self.rotor_and_system(problem, top)?.1)
    }

    /// The rotor and its reduced system for answers up to φ = `top` (rad/s), the dense
    /// stages admitted first.
    fn rotor_and_system(&self, problem: &Problem, top: f64) -> Result<(Rotor, FloquetSystem), RunError> {
        self.admit_dense("the reduced model", problem, Dense::Reduced)?;
        let rotor = Rotor::new(&problem.model)?;
        let fs = FloquetSystem::for_window(&rotor, &problem.settings, problem.model.speed, top)?;
        Ok((rotor, fs))
    }

    /// The Floquet point at (φ, β) of `problem` (φ in rad/s, checked by the caller) on a
    /// basis sized by convergence (or fixed by the settings, [`point_sized`]), its cost on
    /// the schedule's first two sizes admitted first.
    pub fn point(&self, problem: &Problem, phi: f64, beta: f64) -> Result<PointRun, RunError> {
        self.admit_dense("the reduced model", problem, Dense::Reduced)?;
        let rotor = Rotor::new(&problem.model)?;
        let (settings, speed) = (&problem.settings, problem.model.speed);
        let schedule = Schedule::new(&rotor, settings, speed, phi)?;
        for &m in schedule.sizes().iter().take(2) {
            let fs = FloquetSystem::with_modes(&rotor, settings, speed, m)?;
            self.admit("the Floquet point", &cost::floquet_point(&PointCost::of(&fs), phi, beta), &POINT)?;
        }
        Ok(point_sized(&rotor, settings, speed, phi, beta)?)
    }

    /// Admit the chart of `problem` (and of `other` beside it) over the grid `phis` ×
    /// `betas` (rad/s, −; checked by the caller); the φ range's warnings are reported to
    /// the observer.
    pub fn chart<'r>(
        &'r self,
        problem: &Problem,
        other: Option<&Problem>,
        phis: &'r [f64],
        betas: &'r [f64],
    ) -> Result<ChartJob<'r, 'a>, RunError> {
        let top = phis.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let main = self.reduced_system(problem, top)?;
        let mut estimate = cost::chart(&PointCost::of(&main), phis, betas);
        let other_fs = match other {
            Some(o) => {
                let fs = self.reduced_system(o, top)?;
                estimate = estimate.then(cost::chart(&PointCost::of(&fs), phis, betas));
                Some(fs)
            }
            None => None,
        };
        self.admit("the chart", &estimate, &CHART)?;
        let range = Interval::new(phis.iter().copied().fold(f64::INFINITY, f64::min), top);
        let main_warnings = self.range_warning(problem, &main, range, "--phi");
        let other_warnings = match (other, &other_fs) {
            (Some(o), Some(fs)) => self.range_warning(o, fs, range, "--phi"),
            _ => Vec::new(),
        };
        Ok(ChartJob { run: self, phis, betas, main, other: other_fs, warnings: (main_warnings, other_warnings) })
    }

    /// Admit the chart of one reduced system `fs` over a grid (checked by the caller),
    /// as [`Run::chart`] admits it, and run it (a `chart` phase of a step per φ).
    pub fn chart_of(&self, fs: &FloquetSystem, phis: &[f64], betas: &[f64]) -> Result<ChartResult, RunError> {
        self.admit("the chart", &cost::chart(&PointCost::of(fs), phis, betas), &CHART)?;
        let deadline = self.limits(None);
        let c = run_chart(fs, phis, betas, &deadline, "chart");
        self.stopped(&deadline, "the chart")?;
        Ok(c)
    }

    /// Admit the time response of `problem` at (φ, β) over `periods` load periods
    /// (checked by the caller).
    pub fn response(
        &self,
        problem: &Problem,
        phi: f64,
        beta: f64,
        periods: usize,
    ) -> Result<ResponseJob<'_, 'a>, RunError> {
        let (rotor, fs) = self.rotor_and_system(problem, phi)?;
        self.admit("the response", &cost::response_of(&fs, phi, beta, periods), &POINT)?;
        Ok(ResponseJob { run: self, rotor, fs, phi, beta, periods })
    }

    /// The warnings of a φ range `range` ([`range_warnings`]), reported to the
    /// observer and returned.
    pub fn range_warning(&self, problem: &Problem, fs: &FloquetSystem, range: Interval, key: &str) -> Vec<Warning> {
        let warnings = range_warnings(problem, fs, range, key);
        for w in &warnings {
            self.observer().warning(w);
        }
        warnings
    }
}

/// The warning of a φ range (the flag or key `key`) that no instability region of
/// `problem`'s reduced model `fs` at its speed can reach
/// ([`crate::analysis::warnings::phi_range`]).
pub fn range_warnings(problem: &Problem, fs: &FloquetSystem, range: Interval, key: &str) -> Vec<Warning> {
    let Ok((forward, backward)) = fs.whirls() else { return Vec::new() };
    let order = problem.settings.max_tongue_order;
    crate::analysis::warnings::phi_range(&forward, &backward, range, order, fs.speed)
        .map(|kind| Warning {
            file: problem.file.clone(),
            location: crate::problem::Location::Unknown,
            key: key.to_string(),
            kind: crate::problem::WarningKind::Range(kind),
        })
        .into_iter()
        .collect()
}

fn run_chart(fs: &FloquetSystem, phis: &[f64], betas: &[f64], progress: &dyn Progress, what: &str) -> ChartResult {
    progress.phase(what, phis.len() as u64);
    chart(fs, phis, betas, progress)
}

impl ChartJob<'_, '_> {
    /// Run the charts: a `chart` phase (a step per φ), and `compare` for the second.
    pub fn run(self) -> Result<ChartRun, RunError> {
        let deadline = self.run.limits(None);
        let start = Instant::now();
        let main = run_chart(&self.main, self.phis, self.betas, &deadline, "chart");
        let seconds = start.elapsed().as_secs_f64();
        let other = self.other.as_ref().map(|fs| run_chart(fs, self.phis, self.betas, &deadline, "compare"));
        self.run.stopped(&deadline, "the chart")?;
        Ok(ChartRun { main, other, seconds })
    }
}

impl ResponseJob<'_, '_> {
    /// Run the response: a `floquet point` phase (time only), then `response` (up to a
    /// hundred steps per load period).
    pub fn run(self) -> Result<ResponseRun, RunError> {
        let ResponseJob { run, rotor, fs, phi, beta, periods } = self;
        let deadline = run.limits(None);
        deadline.phase("floquet point", 0);
        let point = fs.point(phi, beta);
        deadline.phase("response", response_steps(&fs, phi, periods));
        let r = checked_response(&fs, phi, beta, periods, &deadline);
        run.stopped(&deadline, "the response")?;
        let response = r?;
        let probes = crate::analysis::unbalance::probes(&rotor, &[])?;
        let physical = probes
            .into_iter()
            .map(|p| {
                let u = response.displacement(fs.reduced.basis.as_ref(), p.dof);
                (p, u)
            })
            .collect();
        Ok(ResponseRun { point, response, physical })
    }
}
