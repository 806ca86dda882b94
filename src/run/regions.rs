//! A run's region jobs: the catalogue of instability regions over a φ range (with the
//! chart its boundary plot is drawn over), the stable band around an operating
//! frequency with its margins, and a study's regions case.

use super::{Names, Run, RunError};
use crate::analysis::basis::{Schedule, Sized};
use crate::analysis::chart::{chart, ChartResult};
use crate::analysis::cost::{self, Dense, Estimate, PointCost};
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::modes::whirl_modes_of;
use crate::analysis::regions::margins::{band_margins, load_margin};
use crate::analysis::regions::LoadMargin;
use crate::analysis::regions::{band_sized, catalogue_sized, seeds_for, Band, Catalogue, CatalogueRequest, Margins};
use crate::analysis::{Criterion, Interval, Rotor};
use crate::problem::{Problem, Warning};
use crate::progress::Progress;
use serde::Serialize;
use std::time::Instant;

/// The names of the region catalogue's inputs in a refusal.
pub const REGIONS: Names<'static> =
    Names { phi: "`--phi`", grid: "`--phi` (its range)", load: "`--beta-max`", periods: "`--phi`" };

/// The names of the band search's inputs in a refusal.
pub const BAND: Names<'static> =
    Names { phi: "`--phi` (the window)", grid: "`--phi` (the window)", load: "`--level`", periods: "`--phi`" };

/// The names of a study's inputs in a refusal.
pub const STUDY: Names<'static> = Names {
    phi: "the study's `phi`",
    grid: "the study's `phi` (its range)",
    load: "the study's `beta_max` or `level`",
    periods: "the study",
};

/// The grid of a catalogue's boundary plot over its range up to `beta_max`: 600 φ (rad/s)
/// × 41 β.
pub fn plot_grid(range: Interval, beta_max: f64) -> (Vec<f64>, Vec<f64>) {
    let (lo, hi) = (range.lo, range.hi);
    let phis: Vec<f64> = (0..600).map(|i| lo + (hi - lo) * i as f64 / 599.0).collect();
    let betas: Vec<f64> = (0..41).map(|i| beta_max * i as f64 / 40.0).collect();
    (phis, betas)
}

/// A region catalogue admitted by a run and not yet run ([`Run::catalogue`]).
pub struct CatalogueJob<'r, 'a> {
    run: &'r Run<'a>,
    problem: &'r Problem,
    rotor: Rotor,
    request: CatalogueRequest,
    estimate: Estimate,
    /// The φ range's warnings.
    pub warnings: Vec<Warning>,
}

/// A region catalogue a run computed.
#[derive(Debug)]
pub struct CatalogueRun {
    /// The catalogue on its basis.
    pub sized: Sized<Catalogue>,
    /// Wall time of the search (s).
    pub seconds: f64,
    /// With tracked boundaries, the chart of the boundary plot ([`plot_grid`]).
    pub grid: Option<ChartResult>,
    /// Each stable band's load margin at the catalogue's level.
    pub band_margins: Vec<BandLoadMargin>,
}

/// A stable band at the level (rad/s) and its load margin: the lowest onset over the
/// level among its regions born inside the band (onset/level − 1), searched up to β_max.
#[derive(Debug, Clone, Serialize)]
pub struct BandLoadMargin {
    /// The stable band (rad/s).
    pub band: Interval,
    /// The lowest onset's tongue and margin; null when none is born inside up to β_max
    /// (the margin is then more than β_max/level − 1).
    pub load: Option<LoadMargin>,
}

/// A band search admitted by a run and not yet run ([`Run::band`]).
pub struct BandJob<'r, 'a> {
    run: &'r Run<'a>,
    problem: &'r Problem,
    rotor: Rotor,
    window: Interval,
    phi_op: f64,
    level: f64,
    estimate: Estimate,
    /// The window's warnings.
    pub warnings: Vec<Warning>,
}

/// A stable band a run found, with its margins.
#[derive(Debug)]
pub struct BandRun {
    /// The band on its basis.
    pub sized: Sized<Band>,
    /// Its margins.
    pub margins: Option<Margins>,
    /// Wall time of the search and margins (s).
    pub seconds: f64,
}

/// A study's regions case admitted by a run ([`Run::regions_case`]).
pub struct RegionsCaseJob<'r, 'a> {
    run: &'r Run<'a>,
    problem: &'r Problem,
    rotor: Rotor,
    request: CatalogueRequest,
    phi_op: Option<f64>,
    estimate: Estimate,
    /// The φ range's warnings.
    pub warnings: Vec<Warning>,
}

impl<'a> Run<'a> {
    /// The rotor and the reduced systems a search over a φ window whose top is `top`
    /// (rad/s) is counted on, their dense stages (with the whirls at the speed) admitted
    /// first: the basis schedule's first size, and its second when the basis is sized by
    /// convergence (the least such a search computes, [`crate::analysis::basis`]); what
    /// it computes beyond is bounded while it runs.
    fn prepare(&self, problem: &Problem, top: f64) -> Result<(Rotor, Vec<FloquetSystem>), RunError> {
        self.admit_dense("the region search", problem, Dense::ReducedAndWhirls)?;
        let rotor = Rotor::new(&problem.model)?;
        let (settings, speed) = (&problem.settings, problem.model.speed);
        let schedule = Schedule::new(&rotor, settings, speed, top)?;
        let systems = schedule
            .sizes()
            .iter()
            .take(2)
            .map(|&m| FloquetSystem::with_modes(&rotor, settings, speed, m))
            .collect::<Result<Vec<_>, _>>()?;
        Ok((rotor, systems))
    }

    /// Admit the region catalogue of `problem` asked by `request` (with its boundary
    /// plot's chart when it tracks boundaries); the range's warnings are reported.
    pub fn catalogue<'r>(
        &'r self,
        problem: &'r Problem,
        request: &CatalogueRequest,
    ) -> Result<CatalogueJob<'r, 'a>, RunError> {
        let range = request.range;
        let (rotor, systems) = self.prepare(problem, range.hi)?;
        let settings = &problem.regions;
        // The search's work, from the seeds of the range, before the whirls and the search.
        let criterion = Criterion::of(&problem.settings);
        let mut estimate = Estimate::zero();
        for fs in &systems {
            let seeds = seeds_for(fs, None, range, criterion.max_order)?;
            estimate = estimate.then(cost::catalogue(&PointCost::of(fs), settings, &criterion, &seeds, request));
        }
        let fs = &systems[0];
        if request.track {
            let (phis, betas) = plot_grid(range, request.beta_max);
            estimate = estimate.then(cost::chart(&PointCost::of(fs), &phis, &betas));
        }
        self.admit("the region catalogue", &estimate, &REGIONS)?;
        let warnings = self.range_warning(problem, fs, range, "--phi");
        Ok(CatalogueJob { run: self, problem, rotor, request: *request, estimate, warnings })
    }

    /// Admit the stable band of `problem` around `phi_op` (rad/s) at the load `level` in
    /// `window` (rad/s; all checked by the caller); the window's warnings are reported
    /// under `key` (the flag or key that set the window).
    pub fn band<'r>(
        &'r self,
        problem: &'r Problem,
        phi_op: f64,
        level: f64,
        window: Interval,
        key: &str,
    ) -> Result<BandJob<'r, 'a>, RunError> {
        let (rotor, systems) = self.prepare(problem, window.hi)?;
        let criterion = Criterion::of(&problem.settings);
        let mut estimate = Estimate::zero();
        for fs in &systems {
            let seeds = seeds_for(fs, None, window, criterion.max_order)?;
            let pc = PointCost::of(fs);
            estimate = estimate.then(cost::band_and_margins(&pc, &problem.regions, &criterion, &seeds, window, level));
        }
        self.admit("the band search", &estimate, &BAND)?;
        let warnings = self.range_warning(problem, &systems[0], window, key);
        Ok(BandJob { run: self, problem, rotor, window, phi_op, level, estimate, warnings })
    }

    /// Admit a study's regions case on `problem`: the catalogue asked by `request` and,
    /// with `phi_op` (rad/s), the band over the same range, counted on the reduced system
    /// for the range; the range's warnings are kept, not reported.
    pub fn regions_case<'r>(
        &'r self,
        problem: &'r Problem,
        request: &CatalogueRequest,
        phi_op: Option<f64>,
    ) -> Result<RegionsCaseJob<'r, 'a>, RunError> {
        self.admit_dense("a regions case", problem, Dense::ReducedAndWhirls)?;
        let rotor = Rotor::new(&problem.model)?;
        let range = request.range;
        let fs = FloquetSystem::for_window(&rotor, &problem.settings, problem.model.speed, range.hi)?;
        let (s, criterion, pc) = (&problem.regions, Criterion::of(&fs.settings), PointCost::of(&fs));
        let seeds = seeds_for(&fs, None, range, criterion.max_order)?;
        let mut estimate = cost::catalogue(&pc, s, &criterion, &seeds, &CatalogueRequest { track: false, ..*request });
        if phi_op.is_some() {
            estimate = estimate.then(cost::band(&pc, s, &criterion, &seeds, range, request.level));
        }
        self.admit("a regions case", &estimate, &STUDY)?;
        let warnings = super::floquet::range_warnings(problem, &fs, range, "phi");
        Ok(RegionsCaseJob { run: self, problem, rotor, request: *request, phi_op, estimate, warnings })
    }
}

impl CatalogueJob<'_, '_> {
    /// Run the catalogue: a `catalogue` phase (a step per search) and, with tracked
    /// boundaries, the `chart` of the boundary plot.
    pub fn run(self) -> Result<CatalogueRun, RunError> {
        let CatalogueJob { run, problem, rotor, request, estimate, .. } = self;
        let (settings, speed) = (&problem.settings, problem.model.speed);
        let full = whirl_modes_of(&rotor, settings, speed)?;
        let deadline = run.limits(Some(&estimate));
        let start = Instant::now();
        deadline.phase("catalogue", 0);
        let schedule = Schedule::new(&rotor, settings, speed, request.range.hi)?;
        let sized = catalogue_sized(&rotor, settings, &schedule, speed, &full, &problem.regions, &request, &deadline);
        let seconds = start.elapsed().as_secs_f64();
        run.stopped(&deadline, "the region catalogue")?;
        let sized = sized?;
        let grid = if request.track {
            let (phis, betas) = plot_grid(sized.answer.range, sized.answer.beta_max);
            deadline.phase("chart", phis.len() as u64);
            let c = chart(&sized.system, &phis, &betas, &deadline);
            run.stopped(&deadline, "the region catalogue's boundary plot")?;
            Some(c)
        } else {
            None
        };
        let cat = &sized.answer;
        let band_margins = cat
            .stable_bands
            .iter()
            .map(|b| BandLoadMargin { band: *b, load: load_margin(&cat.regions, *b, request.level) })
            .collect();
        Ok(CatalogueRun { sized, seconds, grid, band_margins })
    }
}

impl BandJob<'_, '_> {
    /// Run the band search (a `band` phase, a step per search) and its margins
    /// (`margins`).
    pub fn run(self) -> Result<BandRun, RunError> {
        let BandJob { run, problem, rotor, window, phi_op, level, estimate, .. } = self;
        let (settings, speed) = (&problem.settings, problem.model.speed);
        let full = whirl_modes_of(&rotor, settings, speed)?;
        let deadline = run.limits(Some(&estimate));
        let start = Instant::now();
        deadline.phase("band", 0);
        let schedule = Schedule::new(&rotor, settings, speed, window.hi)?;
        let s = &problem.regions;
        let sized = band_sized(&rotor, settings, &schedule, speed, &full, s, window, phi_op, level, &deadline);
        run.stopped(&deadline, "the band search")?;
        let sized = sized?;
        deadline.phase("margins", 0);
        let criterion = Criterion::of(settings);
        let labelled = seeds_for(&sized.system, Some(&full), window, criterion.max_order)?;
        let margins = band_margins(&sized.system, &full, s, &labelled, &sized.answer, window, &deadline);
        run.stopped(&deadline, "the band's margin check")?;
        Ok(BandRun { margins: margins?, sized, seconds: start.elapsed().as_secs_f64() })
    }
}

impl RegionsCaseJob<'_, '_> {
    /// Run the case: the catalogue, then the band (before anything is written, so that
    /// a case stopped at its limit writes nothing).
    pub fn run(self) -> Result<(Sized<Catalogue>, Option<Band>), RunError> {
        let RegionsCaseJob { run, problem, rotor, request, phi_op, estimate, .. } = self;
        let (settings, speed) = (&problem.settings, problem.model.speed);
        let full = whirl_modes_of(&rotor, settings, speed)?;
        let s = &problem.regions;
        let deadline = run.limits(Some(&estimate));
        let schedule = Schedule::new(&rotor, settings, speed, request.range.hi)?;
        let cat = catalogue_sized(&rotor, settings, &schedule, speed, &full, s, &request, &deadline);
        run.stopped(&deadline, "the case's region catalogue")?;
        let sized = cat?;
        let band = match phi_op {
            Some(p) => {
                let (range, level) = (request.range, request.level);
                let found = band_sized(&rotor, settings, &schedule, speed, &full, s, range, p, level, &deadline);
                run.stopped(&deadline, "the case's band search")?;
                Some(found?.answer)
            }
            None => None,
        };
        Ok((sized, band))
    }
}
