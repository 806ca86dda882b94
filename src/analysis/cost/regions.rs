//! Cost of the region searches from their plan: the seeds a search starts from and the
//! guard lattice points it visits (counted exactly, as the search lists them), times the
//! evaluations of one seed's search at the settings' defaults. How far an edge marches
//! across a tongue, and where a band's outward search stops, are found as the search
//! goes: the running allowance of evaluations ([`crate::run::Budget::allowance`]), the
//! work limit at this count's cost per evaluation, holds the search there.

use super::*;
use crate::analysis::regions::level::guard_lattice;
use crate::analysis::regions::margins::load_margin_reach;
use crate::analysis::regions::CatalogueRequest;

/// Evaluations of one seed's search at a level, besides the steps of its edges across
/// its tongue: at the default settings its centre search takes 4 (done twice, the second
/// with eigenvectors), the lock and crest checks 3, the crest climb 19 (3 for the first
/// triple, 8 doublings across ±0.5 % of φ, 8 refinements) and each edge about 13 (a ramp
/// of 5 steps, the crossing, 7 lattice bisections): 56, and 64 with a tongue a few edge
/// steps wide.
pub const SEED_EVALUATIONS: f64 = 64.0;

/// Evaluations of one crossing in β besides its samples: the test at its start and the
/// bisection of a bracket step to the β tolerance (9 at the defaults, 1/32 to 1e-4).
pub const CROSSING_EVALUATIONS: f64 = 10.0;

/// Evaluations of one region start besides its β samples: four crossings
/// ([`CROSSING_EVALUATIONS`]) and the tip climb (19 at the defaults: 3 for the first
/// triple, 8 doublings, 8 refinements): 59, and 64.
pub const START_EVALUATIONS: f64 = 64.0;

/// Evaluations of one tracked level of a boundary: the inside point (up to 10 tries) and
/// two edges (about 13 each, [`SEED_EVALUATIONS`]), with room for a few steps across.
pub const LEVEL_EVALUATIONS: f64 = 40.0;

/// Evaluations a widest-band design is expected to spend per candidate and speed on its
/// band: the bundled problem takes 105 on average (21 711 over 207 candidates); five times
/// that. The band around φ_op ends at the nearest tongues of each candidate, which are
/// not known before the run.
pub const DESIGN_BAND_EVALUATIONS: f64 = 500.0;

/// Operations and monodromy evaluations, counted together.
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
}

impl std::iter::Sum for Tally {
    fn sum<I: Iterator<Item = Tally>>(iter: I) -> Tally {
        iter.fold(Tally::default(), |a, b| Tally {
            operations: a.operations + b.operations,
            evaluations: a.evaluations + b.evaluations,
        })
    }
}

/// The estimate of a search, driven by its points at φ = `lowest` (rad/s).
fn estimate(pc: &PointCost, t: Tally, lowest: f64, what: String) -> Estimate {
    let (driver, why) = pc.point_driver(lowest);
    let detail = [what, why].into_iter().filter(|x| !x.is_empty()).collect::<Vec<_>>().join("; ");
    Estimate { evaluations: t.evaluations, ..Estimate::work(t.operations, driver, detail) }
}

/// The seeds of order ≤ `order` in `window`.
fn seeds_in(seeds: &[Seed], order: usize, window: Interval) -> impl Iterator<Item = &Seed> {
    seeds.iter().filter(move |x| x.order <= order && window.contains(x.phi))
}

/// A search of the unstable set at `level` over `window`: each seed's search and every
/// guard lattice point; with a growth-rate floor twice (the search is run again without
/// it for the slow tongues it lists as ignored).
fn level_search(
    pc: &PointCost,
    criterion: &Criterion,
    s: &RegionSettings,
    seeds: &[Seed],
    window: Interval,
    level: f64,
) -> Tally {
    let once: Tally = seeds_in(seeds, criterion.max_order, window)
        .map(|x| Tally::of(SEED_EVALUATIONS, pc.point(x.phi, level)))
        .chain(guard_lattice(s.guard_step, window).into_iter().map(|p| Tally::of(1.0, pc.point(p, level))))
        .sum();
    let times = if criterion.min_growth_rate > 0.0 { 2.0 } else { 1.0 };
    Tally { operations: times * once.operations, evaluations: times * once.evaluations }
}

/// A region catalogue (`regions`, a study's regions case, a design's verification): for
/// each seed of order ≤ `s.max_order` in the range its start (β samples up to β_max twice
/// and to the level once, [`START_EVALUATIONS`], the tracked levels), and the search at
/// the level. `seeds` are the range's ([`crate::analysis::regions::seeds_for`]).
pub fn catalogue(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    work: &CatalogueRequest,
) -> Estimate {
    let (range, beta_max, level) = (work.range, work.beta_max, work.level);
    let samples = (2.0 * beta_max + level) / s.beta_bracket;
    let tracked = if work.track { s.tracking_levels as f64 * LEVEL_EVALUATIONS } else { 0.0 };
    // A start's samples share the per-φ tables of its crossings (to the level, to β_max
    // and down from it); its climb and tracked levels are points of their own.
    let starts: Tally = seeds_in(seeds, s.max_order, range)
        .map(|x| {
            let (table, monodromy, point) = pc.costs(x.phi, beta_max);
            let on_tables = Tally::of(samples + 4.0 * CROSSING_EVALUATIONS, monodromy);
            let climb = START_EVALUATIONS - 4.0 * CROSSING_EVALUATIONS + tracked;
            let tables = Tally { operations: 3.0 * table, evaluations: 0.0 };
            [on_tables, Tally::of(climb, point), tables].into_iter().sum()
        })
        .sum();
    let at_level = level_search(pc, criterion, s, seeds, range, level);
    let located = seeds_in(seeds, s.max_order, range).count();
    let total: Tally = [starts, at_level].into_iter().sum();
    let over = format!("phi = {}..{} rad/s", compact(range.lo), compact(range.hi));
    if starts.operations > at_level.operations && samples > START_EVALUATIONS {
        let detail = format!(
            "{located} region starts × {} beta samples up to beta_max = {} (step {})",
            compact_count(samples),
            compact(beta_max),
            compact(s.beta_bracket)
        );
        return Estimate { evaluations: total.evaluations, ..Estimate::work(total.operations, Driver::Load, detail) };
    }
    estimate(pc, total, range.lo, format!("{located} region starts and the search at the level over {over}"))
}

/// The stable band around φ_op at `level` in `window` (`band`, a study's band): the
/// search of the whole window, where the band search stops at the nearest tongue on
/// each side.
pub fn band(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    window: Interval,
    level: f64,
) -> Estimate {
    let work = level_search(pc, criterion, s, seeds, window, level);
    let what = format!("the seeds and guard lattice over phi = {}..{} rad/s", compact(window.lo), compact(window.hi));
    estimate(pc, work, window.lo, what)
}

/// The `band` command's work: the band ([`band`]), its strict band when the declared
/// criterion is not the strict one, and its load margin's catalogue over the window up
/// to [`load_margin_reach`].
pub fn band_and_margins(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    window: Interval,
    level: f64,
) -> Estimate {
    let margins = CatalogueRequest { range: window, beta_max: load_margin_reach(level), level, track: false };
    let mut work = band(pc, s, criterion, seeds, window, level);
    if !criterion.is_strict() {
        work = work.then(band(pc, s, &criterion.strict(), seeds, window, level));
    }
    work.then(catalogue(pc, s, criterion, seeds, &margins))
}

/// The tongues at the level over `windows` (a clear-bands candidate's operating bands)
/// and their onsets (β samples up to the level).
pub fn scan(
    pc: &PointCost,
    s: &RegionSettings,
    criterion: &Criterion,
    seeds: &[Seed],
    windows: &[Interval],
    level: f64,
) -> Estimate {
    let onset = CROSSING_EVALUATIONS + level / s.beta_bracket;
    let work: Tally = windows
        .iter()
        .flat_map(|w| {
            let onsets = seeds_in(seeds, criterion.max_order, *w).flat_map(|x| {
                let (table, monodromy, _) = pc.costs(x.phi, level);
                [Tally { operations: table, evaluations: 0.0 }, Tally::of(onset, monodromy)]
            });
            std::iter::once(level_search(pc, criterion, s, seeds, *w, level)).chain(onsets)
        })
        .sum();
    let lowest = windows.iter().map(|w| w.lo).fold(f64::INFINITY, f64::min);
    estimate(pc, work, lowest, "the operating bands' tongues".into())
}

/// `count` points on tables of their own at (φ, β) (a verification grid, a design's
/// band work per candidate).
pub fn points(pc: &PointCost, count: f64, phi: f64, beta: f64) -> Estimate {
    estimate(pc, Tally::of(count, pc.point(phi, beta)), phi, String::new())
}
