//! Instability regions as objects (Eq. 28 on the Floquet multipliers): critical load
//! curves, region starts and onsets, the unstable set at a load level β_op (its tongues
//! and edges), the catalogue of a φ range, the stable bands, and boundaries by
//! continuation.
//!
//! Every search asks its questions of one [`Probe`] of the Floquet system, which holds the
//! settings and counts the monodromy evaluations (`probe`). One declared [`Criterion`]
//! decides what counts as unstable at β_op, everywhere: the catalogue's stable bands,
//! [`band::band_around`], the design and the study all take the unstable set at β_op from
//! a [`Level`] of that probe, which finds every tongue of order up to the criterion's from
//! its seed and the rest on a fixed guard lattice (`tongues`), with edges that do not
//! depend on where a search began. Onsets and starts (the β direction, `critical`,
//! `start`) and tracked boundaries (`track`) use the paper's tolerance on max|μ|.
//! Every crossing is narrowed by the one bisection of `bisect`.

pub mod band;
pub(crate) mod bisect;
pub(crate) mod centre;
pub(crate) mod critical;
pub(crate) mod level;
pub mod margins;
pub(crate) mod maximise;
pub(crate) mod probe;
pub(crate) mod seeds;
pub mod sensitivity;
pub(crate) mod settings;
pub(crate) mod sized;
pub(crate) mod start;
pub(crate) mod tongues;
pub(crate) mod track;

pub use band::{
    band_around, bound_name, unexplained, Band, Bound, NamedTongue, Side, Unexplained, SAME_EDGE, UNLABELLED,
};
pub use centre::{CentreOutcome, Converged, Detuning, PairGroup};
pub use centre::{ModeBasis, CENTRE_WINDOW};
pub use critical::CriticalLoad;
pub use level::Level;
pub use margins::{LoadMargin, Margins};
pub use probe::{Counter, Probe};
pub use seeds::{seeds, RegionKind, Seed};
pub use settings::{EdgeStep, RegionSettings, TipMargin};
pub use sized::{band_sized, catalogue_sized};
pub use start::{Start, Tip, START_WINDOW};
pub use tongues::Hit;
pub use tongues::{Ignored, Tongue};
pub use track::Edges;

use super::floquet::FloquetSystem;
use super::limits::{self, ParamError};
use super::modes::ModesResult;
use super::{AnalysisError, Criterion, Interval};
use crate::progress::{Progress, Silent};
use rayon::prelude::*;
use serde::Serialize;

/// An instability region.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct Region {
    /// Name of the seed's whirl pair: forward and backward whirl tags (`f1+b1`, `f1+r1`),
    /// or `2 n1` and `n1+n2` at rest.
    pub label: String,
    /// Simple (2ω_i/k) or combination ((ω_i + ω_j)/k).
    pub kind: RegionKind,
    /// Order k of the resonance (−).
    pub order: usize,
    /// The predicted start (ω_i + ω_j)/k (rad/s).
    pub predicted: f64,
    /// ω_i and ω_j: the pair's forward and backward whirls of the reduced model (rad/s).
    pub whirls: (f64, f64),
    /// Start point φ_s = argmin β_c (rad/s).
    pub start: f64,
    /// Onset β_min = min β_c.
    pub onset_beta: f64,
    /// Left edge of its tongue at the level (rad/s), if it was found there.
    pub left: Option<f64>,
    /// Right edge at the level (rad/s).
    pub right: Option<f64>,
    /// right − left (rad/s).
    pub width: Option<f64>,
    /// Whether its tongue at the level counts by the criterion (false: narrower than
    /// `min_tongue_width`, listed but not bounding any band; also false without a tongue).
    pub counted: bool,
    /// Tracked boundary from the onset up to β_max (empty unless tracking was asked).
    pub boundary: Vec<Edges>,
    /// False when the tip was not located — it could not be separated from a neighbouring
    /// region's flank, or the region was found only at the level (a thin or drifted
    /// tongue): `start` is then a point of the region (the seed, or where it was found at
    /// the level) and `onset_beta` is β_c there, an upper bound of the onset.
    pub resolved: bool,
}

/// What a catalogue is asked for.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct CatalogueRequest {
    /// φ range searched (rad/s).
    pub range: Interval,
    /// Highest load searched for onsets, β_max (−).
    pub beta_max: f64,
    /// The level β_op of edges and bands (−), at most β_max.
    pub level: f64,
    /// Also track boundaries from each located onset up to β_max.
    pub track: bool,
}

impl CatalogueRequest {
    /// A request by named values ([`CatalogueRequestBuilder`]).
    pub fn builder() -> CatalogueRequestBuilder {
        CatalogueRequestBuilder::default()
    }

    /// A request checked by the parameter rules ([`crate::analysis::limits`]): the range
    /// finite, 0 < lo < hi within the ratio and frequency bounds, 0 < β_max ≤ the largest
    /// load, 0 < level ≤ β_max.
    pub(crate) fn new(range: Interval, beta_max: f64, level: f64, track: bool) -> Result<CatalogueRequest, ParamError> {
        let req = CatalogueRequest { range, beta_max, level, track };
        req.check()?;
        Ok(req)
    }

    /// Check a request built field by field (the fields are public; the catalogue checks
    /// its request again).
    pub fn check(&self) -> Result<(), ParamError> {
        limits::phi_range(self.range.lo, self.range.hi)?;
        limits::level(self.level, limits::beta_max(self.beta_max)?)?;
        Ok(())
    }
}

/// A [`CatalogueRequest`] by named values, checked when it is built:
/// `CatalogueRequest::builder().range(…).beta_max(1.0).level(0.3).build()`. β_max defaults
/// to 1 (that of `rotorshunt regions`), tracking to off; the range and the level are
/// required (one not set is refused, [`limits::Rule::NotSet`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CatalogueRequestBuilder {
    range: Option<Interval>,
    beta_max: f64,
    level: Option<f64>,
    track: bool,
}

impl Default for CatalogueRequestBuilder {
    fn default() -> CatalogueRequestBuilder {
        CatalogueRequestBuilder { range: None, beta_max: 1.0, level: None, track: false }
    }
}

impl CatalogueRequestBuilder {
    /// The φ range searched (rad/s).
    pub fn range(self, range: Interval) -> CatalogueRequestBuilder {
        CatalogueRequestBuilder { range: Some(range), ..self }
    }
    /// The highest load searched for onsets, β_max (−).
    pub fn beta_max(self, beta_max: f64) -> CatalogueRequestBuilder {
        CatalogueRequestBuilder { beta_max, ..self }
    }
    /// The level β_op of edges and bands (−), at most β_max.
    pub fn level(self, level: f64) -> CatalogueRequestBuilder {
        CatalogueRequestBuilder { level: Some(level), ..self }
    }
    /// Also track boundaries from each located onset up to β_max.
    pub fn track(self, track: bool) -> CatalogueRequestBuilder {
        CatalogueRequestBuilder { track, ..self }
    }
    /// Check the values by the parameter rules.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.build().map(|_| ())
    }
    /// The checked request.
    pub fn build(self) -> Result<CatalogueRequest, ParamError> {
        let req = CatalogueRequest {
            range: limits::required(limits::Quantity::RangeLow, self.range)?,
            beta_max: self.beta_max,
            level: limits::required(limits::Quantity::Level, self.level)?,
            track: self.track,
        };
        req.check()?;
        Ok(req)
    }
}

/// The catalogue of a φ range.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct Catalogue {
    /// Regions whose onset is below β_max, or whose tongue reaches the level, sorted by
    /// start.
    pub regions: Vec<Region>,
    /// Stable φ intervals at the level (rad/s): the complement of every counted tongue.
    pub stable_bands: Vec<Interval>,
    /// The level β_op of edges and bands.
    pub level: f64,
    /// φ range searched (rad/s).
    pub range: Interval,
    /// β_max searched for onsets (−).
    pub beta_max: f64,
    /// Counted tongues at the level in which no seed's pair was identified (found by the
    /// guard lattice or beside a seed): they bound stable bands like any other.
    pub unexplained: Vec<Interval>,
    /// Tongues at the level that the criterion ignores (narrower than its width floor).
    pub ignored: Vec<Tongue>,
    /// The declared stability criterion every verdict used.
    pub criterion: Criterion,
    /// What the stable bands guarantee, in words.
    pub guarantee: String,
    /// Total monodromy evaluations (boundary tracking included).
    pub evaluations: usize,
    /// Of those, the boundary tracking's.
    pub tracking_evaluations: usize,
}

/// The seeds a search of `range` takes: every predicted start (ω_i + ω_j)/k of order up
/// to `max_order` whose centre-search window ±[`CENTRE_WINDOW`] can reach into the range.
/// Every pair is kept, however close its prediction to another's (distinct pairs have
/// distinct tongues). The band around a φ of the range and the catalogue of the range
/// take the same list.
pub fn seeds_for(
    fs: &FloquetSystem,
    full: Option<&ModesResult>,
    range: Interval,
    max_order: usize,
) -> Result<Vec<Seed>, AnalysisError> {
    let reach = Interval::new(range.lo / (1.0 + CENTRE_WINDOW), range.hi / (1.0 - CENTRE_WINDOW));
    seeds(fs, full, reach, max_order)
}

/// Refuse a search whose Floquet points fail the β = 0 check at either end of `range`
/// ([`AnalysisError::Unreliable`]): two tables, against the thousands of points a search
/// evaluates, and not counted among its evaluations. The shortest period (the range's
/// high end) has the fewest steps and the longest period the largest exponents, so the
/// ends are where a model beyond f64's reach fails first.
pub fn check_reliable(fs: &FloquetSystem, range: Interval) -> Result<(), AnalysisError> {
    for phi in [range.lo, range.hi] {
        if let Some(issue) = fs.zero_load_issue(phi) {
            return Err(AnalysisError::Unreliable { phi, issue });
        }
    }
    Ok(())
}

/// The stable band around `phi_op` at `level` in `range` (rad/s), by the criterion of
/// `fs`'s settings: [`band::band_around`] with the seeds of the range. The arguments obey
/// the parameter rules ([`crate::analysis::limits`]: a φ range, a level up to the largest
/// load, φ_op a frequency), and φ_op must lie in the range ([`AnalysisError::OutsideWindow`]).
pub fn band(
    fs: &FloquetSystem,
    full: &ModesResult,
    s: &RegionSettings,
    range: Interval,
    phi_op: f64,
    level: f64,
) -> Result<Band, AnalysisError> {
    band_with(fs, full, s, range, phi_op, level, &Silent)
}

/// [`band()`], reporting its searches to `progress` (`probe`: a step is a seed's search
/// or a guard-lattice point; the steps are learned batch by batch as the sides widen).
pub fn band_with(
    fs: &FloquetSystem,
    full: &ModesResult,
    s: &RegionSettings,
    range: Interval,
    phi_op: f64,
    level: f64,
    progress: &dyn Progress,
) -> Result<Band, AnalysisError> {
    limits::phi_range(range.lo, range.hi)?;
    limits::level(level, limits::MAX_BETA)?;
    limits::frequency(limits::Quantity::OperatingFrequency, phi_op)?;
    if !range.contains(phi_op) {
        return Err(AnalysisError::OutsideWindow { phi: phi_op, window: range });
    }
    check_reliable(fs, range)?;
    let criterion = Criterion::of(&fs.settings);
    let seeds = seeds_for(fs, Some(full), range, criterion.max_order)?;
    let probe = Probe::reporting(fs, s, progress);
    let at = Level::new(&probe, criterion, level, range);
    let mut b = band_around(&at, &seeds, phi_op);
    // The bounds named by the catalogue ([`band::bound_name`]) of each bounding tongue's
    // neighbourhood: its full extent widened by [`NAMING_REACH`] on each side, in the window.
    let mut tongues = Vec::new();
    let mut spent = 0;
    for bound in [&b.left, &b.right] {
        let Some(Bound::Tongue { inside, .. }) = bound else { continue };
        let Some(e) = at.extent(*inside) else { continue };
        let near =
            Interval::new((e.lo * (1.0 - NAMING_REACH)).max(range.lo), (e.hi * (1.0 + NAMING_REACH)).min(range.hi));
        let req = CatalogueRequest { range: near, beta_max: level, level, track: false };
        let cat = catalogue_with(fs, full, s, &req, progress)?;
        spent += cat.evaluations;
        tongues.extend(cat.named_tongues());
    }
    b.name_bounds(&tongues, &|phi| unexplained(fs, full, phi, level));
    b.evaluations = probe.evaluations() + spent;
    Ok(b)
}

/// The catalogue that names a band's bound covers the bounding tongue's extent widened by
/// this fraction of its edges on each side: a seed's tongue is located within
/// [`CENTRE_WINDOW`] of the seed's start, so every seed whose tongue can lie in the
/// bounding one is among that catalogue's seeds. (A reach of 1e-3 named a bound by a
/// higher-order tongue where a bent order-1 tongue, started farther away, shares the edge.)
const NAMING_REACH: f64 = CENTRE_WINDOW;

/// Catalogue every region with onset below β_max in the range, and the unstable set at
/// the level (the request is checked first, [`CatalogueRequest::check`]): starts and
/// onsets of the seeds of order ≤ `max_order` located from their start
/// ([`Probe::locate_start`]), beside the tongues at the level ([`Level::scan`], every
/// order up to the criterion's), in parallel. A seed's region takes the edges of the tongue its
/// pair collides in; a seed of higher order found only at the level has that collision
/// as its start and β_c there as its onset (unresolved). Boundaries are tracked after,
/// and only add to the regions.
pub fn catalogue(
    fs: &FloquetSystem,
    full: &ModesResult,
    s: &RegionSettings,
    req: &CatalogueRequest,
) -> Result<Catalogue, AnalysisError> {
    catalogue_with(fs, full, s, req, &Silent)
}

/// [`catalogue`], reporting its searches to `progress` as steps of the caller's phase
/// (`probe`): each seed's start, each seed's hits at the level, each tongue's extent,
/// each guard-lattice point, each region's onset and each tracked boundary. The steps are
/// announced ([`Progress::extend`]) as each stage learns of them, so the total grows
/// while the search runs.
pub fn catalogue_with(
    fs: &FloquetSystem,
    full: &ModesResult,
    s: &RegionSettings,
    req: &CatalogueRequest,
    progress: &dyn Progress,
) -> Result<Catalogue, AnalysisError> {
    req.check()?;
    check_reliable(fs, req.range)?;
    let criterion = Criterion::of(&fs.settings);
    let seeds = seeds_for(fs, Some(full), req.range, criterion.max_order)?;
    let probe = Probe::reporting(fs, s, progress);
    let level = Level::new(&probe, criterion, req.level, req.range);
    // Each seed searches its own window for its start: ±0.3 %, but less than half-way to
    // the nearest seed of another start (seeds within `phi_tolerance`, degenerate whirls,
    // share one start).
    let half_width = |i: usize| {
        let nearest = seeds
            .iter()
            .map(|x| (x.phi - seeds[i].phi).abs())
            .filter(|&d| d >= s.phi_tolerance)
            .fold(f64::INFINITY, f64::min);
        (START_WINDOW * seeds[i].phi).min(0.45 * nearest)
    };
    let searched = |i: usize| seeds[i].order <= s.max_order && req.range.contains(seeds[i].phi);
    progress.extend((0..seeds.len()).filter(|&i| searched(i)).count() as u64);
    let (located, tongues) = rayon::join(
        || {
            (0..seeds.len())
                .into_par_iter()
                .map(|i| {
                    // A search not begun when the caller asks to stop is skipped.
                    if !searched(i) || progress.cancelled() {
                        return None;
                    }
                    let start = probe.locate_start(seeds[i].phi, half_width(i), req.level, req.beta_max);
                    progress.advance(1);
                    start
                })
                .collect::<Vec<Option<Start>>>()
        },
        || level.scan(&seeds, req.range),
    );
    // Each seed's own collision at the level: (tongue index, φ).
    let own = |i: usize| {
        tongues.iter().enumerate().find_map(|(t, x)| x.seeds.iter().find(|(j, _)| *j == i).map(|(_, p)| (t, *p)))
    };
    progress.extend(seeds.len() as u64);
    let found: Vec<Option<Region>> = (0..seeds.len())
        .into_par_iter()
        .map(|i| {
            if progress.cancelled() {
                return None;
            }
            let seed = &seeds[i];
            let hit = own(i);
            progress.advance(1);
            let tongue = hit.map(|(t, _)| &tongues[t]);
            // A start located on the seed's line above the level, while the tongue reaches
            // the level beside it (a drifted tongue): the onset is at most β_c where it was
            // found, whatever β_max let the seed's line be searched to.
            let (start, onset, resolved) = match (located[i], hit) {
                (Some(st), None) => (st.phi, st.onset, st.resolved),
                (Some(st), Some(_)) if st.onset <= req.level => (st.phi, st.onset, st.resolved),
                (_, Some((_, phi))) => {
                    (phi, probe.critical_load_below(phi, req.level).beta.unwrap_or(req.level), false)
                }
                (None, None) => return None,
            };
            Some(Region {
                label: seed.label.clone(),
                kind: seed.kind,
                order: seed.order,
                predicted: seed.phi,
                whirls: (seed.forward, seed.backward),
                start,
                onset_beta: onset,
                left: tongue.map(|t| t.extent.lo),
                right: tongue.map(|t| t.extent.hi),
                width: tongue.map(|t| t.extent.width()),
                counted: tongue.is_some_and(|t| t.counted),
                boundary: Vec::new(),
                resolved,
            })
        })
        .collect();
    // A thin tongue found from two seeds (e.g. the near-equal r1 and r2) without a located
    // tip is one region: keep the first (lower seed).
    let mut regions: Vec<Region> = Vec::new();
    for r in found.into_iter().flatten() {
        let twin =
            |q: &Region| !r.resolved && !q.resolved && q.left.is_some() && q.left == r.left && q.right == r.right;
        if !regions.iter().any(twin) {
            regions.push(r);
        }
    }
    regions.sort_by(|a, b| a.start.total_cmp(&b.start));
    let before_tracking = probe.evaluations();
    if req.track {
        progress.extend(regions.iter().filter(|r| r.resolved).count() as u64);
        regions.par_iter_mut().filter(|r| r.resolved).for_each(|r| {
            if progress.cancelled() {
                return;
            }
            r.boundary = probe.track(r.start, r.onset_beta, req.beta_max);
            progress.advance(1);
        });
    }
    let tracking = probe.evaluations() - before_tracking;
    let unexplained: Vec<Interval> =
        tongues.iter().filter(|t| t.seeds.is_empty() && t.counted).map(|t| t.extent).collect();
    let mut ignored: Vec<Tongue> = tongues.iter().filter(|t| !t.counted).cloned().collect();
    ignored.extend(level.slow_tongues(&seeds, req.range, &tongues));
    ignored.sort_by(|a, b| a.extent.lo.total_cmp(&b.extent.lo));
    let counted: Vec<Interval> = tongues.iter().filter(|t| t.counted).map(|t| t.extent).collect();
    Ok(Catalogue {
        regions,
        stable_bands: complement(&counted, req.range),
        level: req.level,
        range: req.range,
        beta_max: req.beta_max,
        unexplained,
        ignored,
        criterion,
        guarantee: criterion.guarantee(req.level),
        evaluations: probe.evaluations(),
        tracking_evaluations: tracking,
    })
}

impl Catalogue {
    /// The counted tongues of its regions at the level, each under its region's label and
    /// order: what names a band's bounds ([`band::bound_name`]).
    pub fn named_tongues(&self) -> Vec<NamedTongue> {
        self.regions
            .iter()
            .filter(|r| r.counted)
            .filter_map(|r| {
                Some(NamedTongue { label: r.label.clone(), order: r.order, extent: Interval::new(r.left?, r.right?) })
            })
            .collect()
    }

    /// The stable band containing φ (rad/s), if φ lies in one.
    pub fn band_containing(&self, phi: f64) -> Option<Interval> {
        self.stable_bands.iter().copied().find(|b| b.contains(phi))
    }
}

/// The complement of the union of `spans` within `range`.
pub fn complement(spans: &[Interval], range: Interval) -> Vec<Interval> {
    let mut spans: Vec<Interval> = spans.to_vec();
    spans.sort_by(|a, b| a.lo.total_cmp(&b.lo));
    let mut out = Vec::new();
    let mut cursor = range.lo;
    for sp in spans {
        if sp.lo > cursor {
            out.push(Interval::new(cursor, sp.lo.min(range.hi)));
        }
        cursor = cursor.max(sp.hi);
        if cursor >= range.hi {
            break;
        }
    }
    if cursor < range.hi {
        out.push(Interval::new(cursor, range.hi));
    }
    out.retain(|b| b.hi > b.lo);
    out
}
