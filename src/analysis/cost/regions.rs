//! Cost of the region searches: catalogues, bands and intrusion scans, summed over the
//! φ values they visit.

use super::*;
use crate::analysis::regions::centre::most_centre_evaluations;
use crate::analysis::regions::critical::most_crossing_evaluations;
use crate::analysis::regions::level::{guard_lattice, most_edge_evaluations};
use crate::analysis::regions::margins::load_margin_reach;
use crate::analysis::regions::maximise::most_climb_evaluations;
use crate::analysis::regions::tongues::{CREST_SPAN, LOCK_AND_CREST_CHECK};
use crate::analysis::regions::track::most_level_evaluations;
use crate::analysis::regions::START_WINDOW;

/// Evaluations a widest-band design is expected to spend per candidate and speed on its
/// band: the bundled problem takes 105 on average (21 711 over 207 candidates); five times
/// that. Not a bound: the band around φ_op ends at the nearest tongues of each candidate,
/// which are not known before the run, and a bound over the whole range (`band`) is some
/// 60 times this. What a design makes is bounded while it runs, by its allowance of
/// evaluations ([`super::Budget::allowance`]).
pub const DESIGN_BAND_EVALUATIONS: f64 = 500.0;

/// The φ values an edge march may step through across `window` (steps of the largest
/// edge-march step, [`RegionSettings::edge_step`]): where a tongue as wide as the
/// window is marched over.
fn march(s: &RegionSettings, window: Interval) -> impl Iterator<Item = f64> + '_ {
    std::iter::successors(Some(window.lo), move |&p| {
        let next = p + s.edge_step.at(p);
        (next < window.hi && next > p).then_some(next)
    })
}

/// Operations and monodromy evaluations of a region search, counted together.
#[derive(Debug, Clone, Copy, Default)]
struct Tally {
    operations: f64,
    evaluations: f64,
}

impl Tally {
    /// `count` evaluations of `each` operations.
    fn of(count: f64, each: f64) -> Tally {
        Tally { operations: count * each, evaluations: count }
    }
    /// A per-φ table (no evaluation).
    fn table(operations: f64) -> Tally {
        Tally { operations, evaluations: 0.0 }
    }
}

impl std::ops::AddAssign for Tally {
    fn add_assign(&mut self, o: Tally) {
        self.operations += o.operations;
        self.evaluations += o.evaluations;
    }
}

impl std::ops::Add for Tally {
    type Output = Tally;
    fn add(mut self, o: Tally) -> Tally {
        self += o;
        self
    }
}

impl std::iter::Sum for Tally {
    fn sum<I: Iterator<Item = Tally>>(iter: I) -> Tally {
        iter.fold(Tally::default(), |a, b| a + b)
    }
}

/// The estimate of a counted search.
fn estimate(t: Tally, driver: Driver, detail: String) -> Estimate {
    Estimate { evaluations: t.evaluations, ..Estimate::work(t.operations, driver, detail) }
}

/// Evaluations of a crossing in β from `from` to `to` bisected to `tolerance`: the
/// search's own bound ([`most_crossing_evaluations`]).
fn bracket(s: &RegionSettings, from: f64, to: f64, tolerance: f64) -> f64 {
    most_crossing_evaluations(s, Interval::new(from, to), tolerance)
}

/// What a search of the unstable set at `level` over `window` costs (the band, and the
/// level part of a catalogue): each seed of order up to the criterion's whose window
/// reaches it (centre search, crest, both edges), every guard lattice point, and a march
/// across the whole window on both sides (a tongue as wide as the window). `slow`: with a
/// growth-rate floor, the same search again without it (a catalogue and a band scan the
/// level a second time for the slow tongues they list as ignored, `Level::slow_tongues`).
fn level_search(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    window: Interval,
    level: f64,
    slow: bool,
) -> (Tally, usize) {
    if slow && criterion.min_growth_rate > 0.0 {
        let raw = Criterion { min_growth_rate: 0.0, min_tongue_width: 0.0, ..*criterion };
        let (again, _) = level_search(pc, s, &raw, seeds, window, level, false);
        let (once, searched) = level_search(pc, s, criterion, seeds, window, level, false);
        return (once + again, searched);
    }
    let reach = |x: &Seed| Interval::new(x.phi * (1.0 - CENTRE_WINDOW), x.phi * (1.0 + CENTRE_WINDOW));
    // A seed's search at the level: its centre search (each evaluation with eigenvectors,
    // weighed twice), the lock test and the crest's check, and the crest climb.
    let centre = 2.0 * most_centre_evaluations(s);
    let per_seed = LOCK_AND_CREST_CHECK as f64 + most_climb_evaluations(s, CREST_SPAN) + centre;
    let mut work = Tally::default();
    let mut count = 0;
    for x in seeds.iter().filter(|x| x.order <= criterion.max_order && reach(x).overlaps(&window)) {
        let phi = x.phi.clamp(window.lo, window.hi);
        let edges = 2.0 * most_edge_evaluations(s, phi, window);
        work += Tally::of(per_seed + edges, pc.point(phi, level));
        count += 1;
    }
    work += guard_lattice(s.guard_step, window).into_iter().map(|p| Tally::of(1.0, pc.point(p, level))).sum();
    work += march(s, window).map(|p| Tally::of(2.0, pc.point(p, level))).sum();
    (work, count)
}

/// What a catalogue request asks of the search.
#[derive(Debug, Clone, Copy)]
pub struct CatalogueWork {
    /// The φ range (rad/s).
    pub range: Interval,
    /// β_max searched for onsets (−).
    pub beta_max: f64,
    /// The level β_op of edges (−).
    pub level: f64,
    /// Boundaries tracked (`--out`).
    pub track: bool,
}

/// A region catalogue (`regions`, a study's regions case, a design's verification): the
/// starts of the seeds of order ≤ `s.max_order` in the range (β_c bracketed up to β_max at
/// the bracket step, the tip climb, the onset below it), the unstable set at the level
/// (`level_search`), the onsets of regions found only at the level, and the tracking.
/// `seeds` are the range's ([`crate::analysis::regions::seeds_for`]).
pub fn catalogue(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    work: &CatalogueWork,
) -> Estimate {
    let (range, beta_max, level) = (work.range, work.beta_max, work.level);
    let screen = SCREENING_TOLERANCE.min(s.tip_margin.absolute).max(s.beta_tolerance);
    let climb = most_climb_evaluations(s, START_WINDOW);
    let mut starts = Tally::default();
    let mut brackets = Tally::default();
    let mut located = 0usize;
    for x in seeds.iter().filter(|x| x.order <= s.max_order && range.contains(x.phi)) {
        let phi = x.phi;
        located += 1;
        // A table to β_max and a monodromy on it, as every step below that goes to β_max.
        let (table_max, monodromy_max) = (Tally::table(pc.table(phi, beta_max).0), pc.monodromy(phi, beta_max));
        // β_c(seed): to the level on a table built to it, then to β_max on another.
        brackets +=
            Tally::table(pc.table(phi, level).0) + Tally::of(bracket(s, 0.0, level, screen), pc.monodromy(phi, level));
        brackets += table_max + Tally::of(bracket(s, level, beta_max, screen), monodromy_max);
        // The onset at the tip, stepping down from up to β_max, and β_c(seed) refined.
        brackets += table_max + Tally::of(bracket(s, 0.0, beta_max, s.beta_tolerance), monodromy_max);
        starts += Tally::of(climb, pc.point(phi, beta_max))
            + Tally::of(bracket(s, 0.0, 0.0, s.beta_tolerance), monodromy_max);
        if work.track {
            starts += Tally::of(s.tracking_levels as f64 * most_level_evaluations(s, phi), pc.point(phi, beta_max));
        }
    }
    let (at_level, searched) = level_search(pc, s, criterion, seeds, range, level, true);
    // Regions found only at the level: β_c stepped down from the level.
    let onsets: Tally = seeds
        .iter()
        .filter(|x| x.order <= criterion.max_order && range.contains(x.phi))
        .map(|x| onset_at_level(pc, s, x.phi, level))
        .sum();
    let total = starts + brackets + at_level + onsets;
    let samples = bracket(s, 0.0, beta_max, screen);
    let (driver, detail) = if brackets.operations > 0.5 * total.operations {
        (
            Driver::Load,
            format!(
                "{located} region starts × {} beta samples up to beta_max = {} (step {})",
                compact_count(samples),
                compact(beta_max),
                compact(s.beta_bracket)
            ),
        )
    } else {
        let (d, why) = pc.point_driver(range.lo);
        let what = format!(
            "{located} region starts and {searched} seeds at the level over phi = {}..{} rad/s",
            compact(range.lo),
            compact(range.hi)
        );
        let d = if d == Driver::ReducedModel && searched > 1000 { Driver::Grid } else { d };
        (d, if why.is_empty() { what } else { format!("{what}; {why}") })
    };
    estimate(total, driver, detail)
}

/// A region's onset stepped down from the level: a table to the level and its bracket.
fn onset_at_level(pc: &PointCost, s: &RegionSettings, phi: f64, level: f64) -> Tally {
    Tally::table(pc.table(phi, level).0) + Tally::of(bracket(s, 0.0, level, s.beta_tolerance), pc.monodromy(phi, level))
}

/// The stable band around φ_op at `level` in `window` (`band`, a study's band): the
/// search of the whole window (`level_search`), an upper bound of the outward search
/// that stops at the nearest tongue on each side.
pub fn band(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    window: Interval,
    level: f64,
) -> Estimate {
    let (work, searched) = level_search(pc, s, criterion, seeds, window, level, true);
    let (d, why) = pc.point_driver(window.lo);
    let what = format!(
        "{searched} seeds and the guard lattice over phi = {}..{} rad/s",
        compact(window.lo),
        compact(window.hi)
    );
    estimate(work, d, if why.is_empty() { what } else { format!("{what}; {why}") })
}

/// The `band` command's work around φ_op at `level` in `window`: the band search
/// ([`band`]), its strict band (the same search under the strict criterion,
/// [`crate::analysis::regions::margins::strict_band`], when that is not the declared one) and its load margin's catalogue
/// (over the band, at most the window, up to [`load_margin_reach`]).
pub fn band_and_margins(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    window: Interval,
    level: f64,
) -> Estimate {
    let margins = CatalogueWork { range: window, beta_max: load_margin_reach(level), level, track: false };
    let declared = band(pc, s, criterion, seeds, window, level);
    let with_strict = match criterion.is_strict() {
        true => declared,
        false => declared.then(band(pc, s, &criterion.strict(), seeds, window, level)),
    };
    with_strict.then(catalogue(pc, s, criterion, seeds, &margins))
}

/// The search for the tongues at the level over `windows` (a clear-bands candidate's
/// operating bands) and their onsets.
pub fn scan(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    windows: &[Interval],
    level: f64,
) -> Estimate {
    let mut work = Tally::default();
    for w in windows {
        work += level_search(pc, s, criterion, seeds, *w, level, false).0;
        work += seeds
            .iter()
            .filter(|x| x.order <= criterion.max_order && w.contains(x.phi))
            .map(|x| onset_at_level(pc, s, x.phi, level))
            .sum();
    }
    let lowest = windows.iter().map(|w| w.lo).fold(f64::INFINITY, f64::min);
    let (d, why) = pc.point_driver(lowest);
    estimate(work, d, if why.is_empty() { "the operating bands' tongues".into() } else { why })
}

/// `count` points on tables of their own at (φ, β) (a verification grid, a design's
/// band work per candidate).
pub fn points(pc: &PointCost, count: f64, phi: f64, beta: f64) -> Estimate {
    let (d, why) = pc.point_driver(phi);
    estimate(Tally::of(count, pc.point(phi, beta)), d, why)
}
