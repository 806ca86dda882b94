//! Instability regions as objects (Eq. 28 on the Floquet multipliers): critical load
//! curves, region starts and onsets, edges at a load level, boundaries by continuation,
//! the catalogue of a φ range and the stable bands between regions.

pub mod centre;
pub mod critical;
pub mod seeds;
pub mod sensitivity;

pub use centre::{centre_search, ModeBasis, CENTRE_WINDOW};
pub use critical::{critical_load, CriticalLoad, RegionSettings};
pub use seeds::{seeds, RegionKind, Seed};

use super::floquet::FloquetSystem;
use super::modes::ModesResult;
use super::AnalysisError;
use rayon::prelude::*;
use serde::Serialize;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Half-width of the φ window searched for a region's start around its seed, relative.
/// Damping and the static load shift a start from the undamped sum by far less.
pub const START_WINDOW: f64 = 0.003;
/// A growth maximum within this fraction of the window's edge is the neighbour's tip, not
/// this seed's: the seed's own tip is then not located in its window.
const EDGE_FRACTION: f64 = 0.05;

/// Seeds are taken this far (relative) beyond the φ range.
const SEED_MARGIN: f64 = 0.1;

/// Counts monodromy evaluations (shared across threads).
#[derive(Debug, Default)]
pub struct Counter(AtomicUsize);

impl Counter {
    /// Add `n` evaluations.
    pub fn add(&self, n: usize) {
        self.0.fetch_add(n, Ordering::Relaxed);
    }
    /// Evaluations so far.
    pub fn get(&self) -> usize {
        self.0.load(Ordering::Relaxed)
    }
}

/// One edge pair of a region at a load level.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Edges {
    /// β (−).
    pub beta: f64,
    /// Left edge φ_l (rad/s).
    pub left: f64,
    /// Right edge φ_r (rad/s).
    pub right: f64,
}

/// An instability region.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Region {
    /// e.g. `f1+b1`.
    pub label: String,
    /// Simple or combination.
    pub kind: RegionKind,
    /// Order k.
    pub order: usize,
    /// The predicted start (ω_i + ω_j)/k (rad/s).
    pub predicted: f64,
    /// Start point φ_s = argmin β_c (rad/s).
    pub start: f64,
    /// Onset β_min = min β_c.
    pub onset_beta: f64,
    /// Left edge at the requested level (rad/s), if the region reaches it.
    pub left: Option<f64>,
    /// Right edge at the requested level.
    pub right: Option<f64>,
    /// right − left.
    pub width: Option<f64>,
    /// Tracked boundary from the onset up to β_max (empty unless tracking was asked).
    pub boundary: Vec<Edges>,
    /// Monodromy evaluations spent on this region.
    pub evaluations: usize,
    /// False when the tip was not located — it could not be separated from a neighbouring
    /// region's flank, or the region was found only at the level (a thin or drifted
    /// tongue): `start` is then a point of the region (the seed, or where it was found at
    /// the level) and `onset_beta` is β_c there, an upper bound of the onset.
    pub resolved: bool,
}

/// Whether (φ, β) is unstable, from a fresh per-φ table; counts one evaluation.
pub fn unstable_at(fs: &FloquetSystem, phi: f64, beta: f64, count: &mut usize) -> bool {
    *count += 1;
    critical::unstable(fs, &fs.table(phi, beta), beta)
}

/// Bisection tolerance of β_c at a seed before its tip is searched: 1/512, four halvings
/// of the 1/32 bracket. The onset is bisected to `beta_tolerance` where it is reported.
pub const SCREENING_TOLERANCE: f64 = 1.0 / 512.0;

/// First step of the tip climb, relative to φ: below the shift of a tip from its seed
/// (~1e-4 relative on the paper's problems), so the climb starts on the tip's own dome.
const CLIMB_STEP: f64 = 2e-5;

/// The start and onset of the region seeded at `seed_phi`, searched within
/// ±`half_width` (rad/s). (1) β₀ = β_c(seed) is given as a bracket (stable β₋, unstable
/// β₀) at most the tip margin's absolute part wide; (2) at the level β₋(1 + m_rel) + m_abs
/// (`tip_margin`), above β₀, the region is a short
/// interval around its tip that contains the seed, and the tip φ_s is the maximum of
/// ln max|μ| over φ there ([`climb`]: uphill from the seed, then parabolic steps);
/// (3) the onset is β_c(φ_s) ≤ β₀ by [`critical::critical_load_below`] (None if φ_s is
/// stable at β₀: the seed and β₀ stand). None if the climb leaves the window, or ends
/// within [`EDGE_FRACTION`] of its edge: the seed lies on the flank of a neighbouring
/// region, whose tip it is climbing to.
pub fn locate_tip(
    fs: &FloquetSystem,
    s: &RegionSettings,
    seed_phi: f64,
    (below, beta0): (f64, f64),
    half_width: f64,
    beta_max: f64,
    count: &mut usize,
) -> Option<(f64, Option<f64>)> {
    let level = (below * (1.0 + s.tip_margin.0) + s.tip_margin.1).max(beta0).min(beta_max);
    let growth = |phi: f64, count: &mut usize| growth_at(fs, phi, level, count);
    let tip = climb(growth, s, seed_phi, half_width, count)?;
    if (tip - seed_phi).abs() > (1.0 - EDGE_FRACTION) * half_width {
        return None;
    }
    let c1 = critical::critical_load_below(fs, s, tip, beta0);
    *count += c1.evaluations;
    Some((tip, c1.beta))
}

/// The local maximum of `g` nearest `from` within ±`half_width`: uphill from `from` with
/// doubling steps (first [`CLIMB_STEP`]·φ, at most a quarter of the window) until `g`
/// falls, then a parabola through the bracketing triple, or a golden-section step where
/// the parabola is no help, until the bracket is below `tip_tolerance`·φ or
/// `tip_iterations` steps are spent. None if the climb leaves the window.
///
/// Brent's minimiser (argmin's `BrentOpt`) does the second part, but it cannot start from
/// a known interior point: it would spend evaluations re-finding the bracket's best.
fn climb(
    mut g: impl FnMut(f64, &mut usize) -> f64,
    s: &RegionSettings,
    from: f64,
    half_width: f64,
    count: &mut usize,
) -> Option<f64> {
    let h = (CLIMB_STEP * from.abs()).min(0.25 * half_width);
    let (gm, g0, gp) = (g(from - h, count), g(from, count), g(from + h, count));
    // The bracketing triple (a, b, c), a < b < c, g(b) ≥ g(a), g(c).
    let (mut a, mut b, mut c) = ((from - h, gm), (from, g0), (from + h, gp));
    if gp > g0 || gm > g0 {
        let dir = if gp >= gm { 1.0 } else { -1.0 };
        let (mut prev, mut here) = (b, if dir > 0.0 { c } else { a });
        let mut step = h;
        let next = loop {
            step *= 2.0;
            // The last step stops at the window's edge; a climb already there has left it.
            let x = (here.0 + dir * step).clamp(from - half_width, from + half_width);
            if x == here.0 {
                return None;
            }
            let next = (x, g(x, count));
            if next.1 < here.1 {
                break next;
            }
            (prev, here) = (here, next);
        };
        (a, b, c) = if dir > 0.0 { (prev, here, next) } else { (next, here, prev) };
    }
    let tolerance = s.tip_tolerance * from.abs();
    let golden = (3.0 - 5f64.sqrt()) / 2.0;
    let mut last_width = f64::INFINITY;
    for _ in 0..s.tip_iterations {
        let width = c.0 - a.0;
        if width <= tolerance {
            break;
        }
        // The parabola's vertex if it lies well inside the bracket and the last step
        // halved it; else golden section into the larger side.
        let vertex = parabola_vertex(a, b, c).filter(|&x| {
            let margin = 0.25 * tolerance;
            x > a.0 + margin && x < c.0 - margin && (x - b.0).abs() > margin && width < 0.5 * last_width
        });
        last_width = width;
        let x = vertex.unwrap_or(if c.0 - b.0 > b.0 - a.0 {
            b.0 + golden * (c.0 - b.0)
        } else {
            b.0 - golden * (b.0 - a.0)
        });
        let u = (x, g(x, count));
        if u.1 >= b.1 {
            if u.0 > b.0 {
                a = b;
            } else {
                c = b;
            }
            b = u;
        } else if u.0 > b.0 {
            c = u;
        } else {
            a = u;
        }
    }
    Some(parabola_vertex(a, b, c).map_or(b.0, |x| x.clamp(a.0, c.0)))
}

/// The vertex of the parabola through three points (x ascending), if it opens downward.
fn parabola_vertex((x0, y0): (f64, f64), (x1, y1): (f64, f64), (x2, y2): (f64, f64)) -> Option<f64> {
    let (d0, d2) = ((y1 - y0) / (x1 - x0), (y2 - y1) / (x2 - x1));
    let curvature = (d2 - d0) / (x2 - x0);
    if curvature.is_nan() || curvature >= 0.0 {
        return None;
    }
    // Vertex of the Newton form: x where the slope d0 + curvature·(2x − x0 − x1) vanishes.
    let x = 0.5 * (x0 + x1) - d0 / (2.0 * curvature);
    x.is_finite().then_some(x)
}

/// [`locate_tip`] from the seed. Returns (start, onset, resolved); unresolved regions keep
/// the seed and β_c(seed) as start and onset.
///
/// β_c(seed) is screened to [`SCREENING_TOLERANCE`] only: the tip search needs no more
/// (its level lies 5 % + 0.002 above), and the onset reported is then β_c at the tip,
/// bisected to `beta_tolerance`. Where β_c(seed) itself is the onset it is bisected on,
/// on the same table; where β_c at the tip lies inside the screening bracket, one
/// evaluation at the seed tells whether the seed is lower (the onset is then min β_c of
/// the two to the tolerance, as with a fully bisected β_c(seed)).
pub fn locate_start(
    fs: &FloquetSystem,
    s: &RegionSettings,
    seed_phi: f64,
    half_width: f64,
    beta_max: f64,
    count: &mut usize,
) -> Option<(f64, f64, bool)> {
    let table = fs.table(seed_phi, beta_max);
    // Never coarser than the tip margin's absolute part, so that the level, taken from the
    // stable end, is still above β_c(seed).
    let tolerance = SCREENING_TOLERANCE.min(s.tip_margin.1).max(s.beta_tolerance);
    let screened = critical::Crossing::below(fs, s, &table, beta_max, tolerance);
    *count += screened.evaluations;
    let (below, beta0) = screened.bracket?;
    let tip = locate_tip(fs, s, seed_phi, (below, beta0), half_width, beta_max, count);
    // β_c(seed) bisected on from a (stable, unstable) bracket, on the seed's table.
    let refine = |lo: f64, hi: f64, count: &mut usize| {
        let fine = critical::Crossing::bisected(fs, &table, (lo, hi), s.beta_tolerance);
        *count += fine.evaluations;
        fine.bracket.map_or(hi, |b| b.1)
    };
    let (start, onset, resolved) = match tip {
        // β_c at the tip inside the screening bracket: β_c(seed) may be lower by more than
        // the tolerance, which one evaluation on the seed's table tells; the seed is then
        // the better start, and its β_c is bisected on from there.
        Some((phi, Some(beta))) if beta - s.beta_tolerance > below => {
            let probe = beta - s.beta_tolerance;
            *count += 1;
            if critical::unstable(fs, &table, probe) {
                (seed_phi, refine(below, probe, count), true)
            } else {
                (phi, beta, true)
            }
        }
        Some((phi, Some(beta))) => (phi, beta, true),
        Some((_, None)) => (seed_phi, refine(below, beta0, count), true),
        None => (seed_phi, refine(below, beta0, count), false),
    };
    Some((start, onset, resolved))
}

/// The edge of the unstable set at level β next to `inside` (unstable) on the side
/// `dir` (−1 left, +1 right): march outward with growing steps (at most
/// [`RegionSettings::max_edge_step`], so a stable gap that wide between two tongues is
/// never stepped over) until stable, then bisect.
pub fn edge(fs: &FloquetSystem, s: &RegionSettings, inside: f64, beta: f64, dir: f64, count: &mut usize) -> f64 {
    let mut lo = inside;
    let mut step = (lo * 2e-4).max(4.0 * s.phi_tolerance);
    let mut hi = lo + dir * step;
    while unstable_at(fs, hi, beta, count) {
        lo = hi;
        step = (step * 1.6).min(s.max_edge_step(lo));
        hi = lo + dir * step;
        if hi <= 0.0 {
            return f64::MIN_POSITIVE;
        }
    }
    bisect_boundary(fs, s, lo, hi, beta, count)
}

/// ln max|μ| at (φ, β) from a fresh per-φ table; counts one evaluation.
pub fn growth_at(fs: &FloquetSystem, phi: f64, beta: f64, count: &mut usize) -> f64 {
    *count += 1;
    fs.point_fast(&fs.table(phi, beta), beta).summary.ln_max_multiplier
}

/// The stability boundary at level β between an unstable φ and a stable φ, by bisection
/// to `phi_tolerance`: the midpoint of the final bracket. (Predicting the edge from the
/// growth samples — (g − g_outside)² is nearly linear in φ next to an edge — was tried
/// and cost more evaluations than bisection on Fig. 11: the median bracket is already
/// within two halvings of the tolerance. Longer march steps where the growth does not
/// fall saved 0.7 % of the catalogue's evaluations on Fig. 11 (3.5 % on Fig. 13) and gave
/// up the gap guarantee.)
fn bisect_boundary(
    fs: &FloquetSystem,
    s: &RegionSettings,
    unstable: f64,
    stable: f64,
    beta: f64,
    count: &mut usize,
) -> f64 {
    let (mut inside, mut outside) = (unstable, stable);
    while (outside - inside).abs() > s.phi_tolerance {
        let mid = 0.5 * (inside + outside);
        if unstable_at(fs, mid, beta, count) {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    0.5 * (inside + outside)
}

/// Both edges at level β of the region containing φ_in (unstable there).
pub fn edges_at(fs: &FloquetSystem, s: &RegionSettings, phi_in: f64, beta: f64, count: &mut usize) -> Edges {
    Edges { beta, left: edge(fs, s, phi_in, beta, -1.0, count), right: edge(fs, s, phi_in, beta, 1.0, count) }
}

/// Boundary tracking by predictor–corrector continuation from the onset upward: at each
/// level the edges are predicted by linear extrapolation of the last two levels (the
/// midpoint of the prediction is the inside point) and corrected by [`edge`].
pub fn track(
    fs: &FloquetSystem,
    s: &RegionSettings,
    start: f64,
    onset: f64,
    beta_max: f64,
    count: &mut usize,
) -> Vec<Edges> {
    let mut out: Vec<Edges> = Vec::new();
    let levels = s.tracking_levels.max(1);
    for k in 1..=levels {
        let beta = onset + (beta_max - onset) * k as f64 / levels as f64;
        let centre = match out.len() {
            0 => start,
            1 => 0.5 * (out[0].left + out[0].right),
            n => {
                let (p, q) = (&out[n - 2], &out[n - 1]);
                let c = |e: &Edges| 0.5 * (e.left + e.right);
                c(q) + (c(q) - c(p)) * (beta - q.beta) / (q.beta - p.beta)
            }
        };
        // The predicted centre must be inside; else look beside it (a thin region that
        // tilts can slip past a linear prediction) at ±¼, ½, 1 and 2 of the last width,
        // then fall back to the start, then give up.
        let width = out.last().map_or(4.0 * s.phi_tolerance, |e| (e.right - e.left).max(4.0 * s.phi_tolerance));
        let beside = [0.25, 0.5, 1.0, 2.0].into_iter().flat_map(|f| [centre - f * width, centre + f * width]);
        let inside =
            std::iter::once(centre).chain(beside).chain([start]).find(|&phi| unstable_at(fs, phi, beta, count));
        match inside {
            Some(phi) => out.push(edges_at(fs, s, phi, beta, count)),
            None => break,
        }
    }
    out
}

/// A point of the region inside the unstable set at `level`: the start or the seed if
/// either is, otherwise (if `follow`) the centre of the region followed up from its start
/// by continuation (regions bend away from their start as β grows).
#[allow(clippy::too_many_arguments)]
fn inside_at(
    fs: &FloquetSystem,
    s: &RegionSettings,
    start: f64,
    seed: f64,
    onset: f64,
    level: f64,
    follow: bool,
    count: &mut usize,
) -> Option<f64> {
    for phi in [start, seed] {
        if unstable_at(fs, phi, level, count) {
            return Some(phi);
        }
    }
    if !follow {
        return None;
    }
    let path = track(fs, s, start, onset, level, count);
    path.last().filter(|e| (e.beta - level).abs() < 1e-12).map(|e| 0.5 * (e.left + e.right))
}

/// The region of `seed` through the unstable point φ at the level: its edges there, and
/// φ with β_c there as start and onset (an upper bound: the region was not followed down
/// to its tip, `resolved: false`).
fn found_at(fs: &FloquetSystem, s: &RegionSettings, seed: &Seed, phi: f64, level: f64, count: &mut usize) -> Region {
    let e = edges_at(fs, s, phi, level, count);
    let c = critical::critical_load_below(fs, s, phi, level);
    *count += c.evaluations;
    Region {
        label: seed.label.clone(),
        kind: seed.kind,
        order: seed.order,
        predicted: seed.phi,
        start: phi,
        onset_beta: c.beta.unwrap_or(level),
        left: Some(e.left),
        right: Some(e.right),
        width: Some(e.right - e.left),
        boundary: Vec::new(),
        evaluations: 0, // set by the catalogue, which counts the whole search
        resolved: false,
    }
}

/// A thin or drifted region of an order ≥ 2 seed at the level, by the centre search on
/// its multipliers' detuning ([`centre_search`]). Near β = 0 an order-k ≥ 2 tongue is no
/// wider than its centre's drift (both grow like β² at k = 2, the width like β^k above),
/// so it can leave the line φ = seed at once and β_c(seed) never sees it.
/// A point found inside `known` (the edges the seed's region already has at the level)
/// is that region again: None, without the edges and onset a new region would cost.
fn drifted(
    fs: &FloquetSystem,
    basis: Option<&ModeBasis>,
    s: &RegionSettings,
    seed: &Seed,
    level: f64,
    known: Option<(f64, f64)>,
    count: &mut usize,
) -> Option<Region> {
    if seed.order < 2 || level <= 0.0 {
        return None;
    }
    let phi = basis.and_then(|b| centre_search(fs, b, s, seed, level, count))?;
    if known.is_some_and(|(l, h)| l <= phi && phi <= h) {
        return None;
    }
    Some(found_at(fs, s, seed, phi, level, count))
}

/// The catalogue of a φ range.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Catalogue {
    /// Regions whose onset is below β_max, sorted by start.
    pub regions: Vec<Region>,
    /// Stable φ intervals at the level (rad/s).
    pub stable_bands: Vec<[f64; 2]>,
    /// The level β_op of edges and bands.
    pub level: f64,
    /// φ range searched (rad/s).
    pub range: [f64; 2],
    /// β_max.
    pub beta_max: f64,
    /// Unstable intervals at the level found by the coarse guard scan outside every
    /// catalogued region (edges bisected); they are excluded from the stable bands.
    pub unexplained: Vec<Edges>,
    /// Total monodromy evaluations.
    pub evaluations: usize,
}

/// Catalogue every region with onset below β_max in `range`, with edges at `level`,
/// optionally tracking boundaries; regions in parallel over seeds. Seeds of order ≤
/// `max_order` are located from their start; higher orders, up to `search_order`, are
/// searched at the level pair by pair ([`higher_orders`]).
pub fn catalogue(
    fs: &FloquetSystem,
    full: &ModesResult,
    s: &RegionSettings,
    range: (f64, f64),
    beta_max: f64,
    level: f64,
    track_boundaries: bool,
) -> Result<Catalogue, AnalysisError> {
    // Regions starting just outside the range can reach into it at higher loads.
    let mut candidates = seeds(fs, full, (range.0 / (1.0 + SEED_MARGIN), range.1 * (1.0 + SEED_MARGIN)), s.max_order)?;
    // Coinciding predictions (e.g. degenerate whirls) are one region: keep the first.
    candidates.dedup_by(|b, a| (b.phi - a.phi).abs() < s.phi_tolerance);
    // Each seed searches its own window: ±0.3 %, but less than half-way to a neighbour.
    let windows: Vec<f64> = (0..candidates.len())
        .map(|i| {
            let gap = |j: usize| (candidates[j].phi - candidates[i].phi).abs();
            let nearest = [i.checked_sub(1), (i + 1 < candidates.len()).then_some(i + 1)]
                .into_iter()
                .flatten()
                .map(gap)
                .fold(f64::INFINITY, f64::min);
            (START_WINDOW * candidates[i].phi).min(0.45 * nearest)
        })
        .collect();
    let total = Counter::default();
    let basis = ModeBasis::new(fs);
    let mut found: Vec<Option<Region>> = candidates
        .par_iter()
        .zip(windows.par_iter())
        .map(|(seed, &half_width)| {
            faer::set_global_parallelism(faer::Par::Seq);
            let mut count = 0;
            // Screening is β_c at the seed itself (bracketed from below): a region whose tip
            // is at its seed is found even where it bends away from the seed at higher β.
            let region = {
                let located = locate_start(fs, s, seed.phi, half_width, beta_max, &mut count);
                located.map(|(start, onset, resolved)| {
                    // Order ≥ 2 is not continued up to the level: the centre search below
                    // follows a tongue that has left its seed.
                    let at_level = if onset <= level {
                        inside_at(fs, s, start, seed.phi, onset, level, seed.order == 1, &mut count)
                            .map(|phi| edges_at(fs, s, phi, level, &mut count))
                    } else {
                        None
                    };
                    let boundary =
                        if track_boundaries { track(fs, s, start, onset, beta_max, &mut count) } else { Vec::new() };
                    Region {
                        label: seed.label.clone(),
                        kind: seed.kind,
                        order: seed.order,
                        predicted: seed.phi,
                        start,
                        onset_beta: onset,
                        left: at_level.map(|e| e.left),
                        right: at_level.map(|e| e.right),
                        width: at_level.map(|e| e.right - e.left),
                        boundary,
                        evaluations: count,
                        resolved,
                    }
                })
            };
            // Neighbouring seeds (e.g. the near-equal r1 and r2) may find the same thin
            // region at the level: twins are merged below.
            let region = match region {
                None => drifted(fs, basis.as_ref(), s, seed, level, None, &mut count),
                // Not found at the level from its start, or with an unlocated tip (β_c on the
                // line φ = seed only, and edges possibly those of a neighbour containing the
                // seed): a tilted or drifted tongue can reach the level beside the seed.
                // A tongue found inside the edges r already has is r's region: kept as it is.
                Some(r) if !r.resolved || (r.left.is_none() && r.onset_beta <= level) => {
                    let known = r.left.zip(r.right);
                    match drifted(fs, basis.as_ref(), s, seed, level, known, &mut count) {
                        Some(f) if f.onset_beta < r.onset_beta => Some(Region { boundary: r.boundary, ..f }),
                        Some(f) => Some(Region { left: f.left, right: f.right, width: f.width, resolved: false, ..r }),
                        None => Some(r),
                    }
                }
                r => r,
            };
            let region = region.map(|r| Region { evaluations: count, ..r });
            total.add(count);
            region
        })
        .collect();
    // The higher orders and the guard scan (against the regions so far) run side by side.
    let seeded: Vec<(Seed, bool)> = candidates.iter().cloned().zip(found.iter().map(Option::is_some)).collect();
    let spans: Vec<(f64, f64)> = found.iter().flatten().filter_map(|r| Some((r.left?, r.right?))).collect();
    let (more, guarded) = rayon::join(
        || {
            faer::set_global_parallelism(faer::Par::Seq);
            if level > 0.0 {
                higher_orders(fs, basis.as_ref(), s, &seeded, &spans, range, level, &total)
            } else {
                Vec::new()
            }
        },
        || {
            faer::set_global_parallelism(faer::Par::Seq);
            guard_scan(fs, s, &spans, range, level, &total)
        },
    );
    found.extend(more);
    let mut regions: Vec<Region> = Vec::new();
    for r in found.into_iter().flatten() {
        // A thin region found from two seeds: keep the first (lower seed).
        let twin = |q: &Region| {
            !r.resolved
                && !q.resolved
                && r.boundary.is_empty()
                && matches!((q.left, q.right, r.left, r.right), (Some(a), Some(b), Some(c), Some(d))
                    if (a - c).abs() <= s.phi_tolerance && (b - d).abs() <= s.phi_tolerance)
        };
        if !regions.iter().any(twin) {
            regions.push(r);
        }
    }
    regions.sort_by(|a, b| a.start.total_cmp(&b.start));
    // Unstable intervals of the guard scan that a higher-order region explains are dropped.
    let unexplained: Vec<Edges> = guarded
        .into_iter()
        .filter(|e| {
            !regions.iter().any(|r| matches!((r.left, r.right), (Some(l), Some(h)) if l <= e.right && e.left <= h))
        })
        .collect();
    let mut stable_bands = bands(&regions, range);
    for gap in &unexplained {
        stable_bands = subtract(&stable_bands, (gap.left, gap.right));
    }
    Ok(Catalogue {
        regions,
        stable_bands,
        level,
        range: [range.0, range.1],
        beta_max,
        unexplained,
        evaluations: total.get(),
    })
}

/// Orders above `max_order`, searched at the level pair by pair ([`centre_search`]): order
/// k of a pair is searched if order k − 1 or k − 2 was found (a lower order outside the
/// seeded range, or whose seed lies inside a region already found at the level, counts as
/// found). Higher orders of a pair are thinner and start higher, but parity matters: a
/// pair whose modes couple only through a third can skip an order (n1+n4 at rest has
/// regions of order 1 and 3, none of order 2).
#[allow(clippy::too_many_arguments)] // the catalogue's state, passed down once
fn higher_orders(
    fs: &FloquetSystem,
    basis: Option<&ModeBasis>,
    s: &RegionSettings,
    seeded: &[(Seed, bool)],
    spans: &[(f64, f64)],
    range: (f64, f64),
    level: f64,
    total: &Counter,
) -> Vec<Option<Region>> {
    let (lo, hi) = (range.0 / (1.0 + SEED_MARGIN), range.1 * (1.0 + SEED_MARGIN));
    // One entry per pair: its seed and which orders (index k) were found.
    let mut pairs: Vec<(Seed, Vec<bool>)> = Vec::new();
    for (seed, hit) in seeded {
        let same = |p: &(Seed, Vec<bool>)| p.0.forward == seed.forward && p.0.backward == seed.backward;
        let i = match pairs.iter().position(same) {
            Some(i) => i,
            None => {
                // Orders outside the seeded range are unknown: count them as found.
                let flags = (0..=s.search_order.max(s.max_order))
                    .map(|k| k > 0 && k <= s.max_order && !(lo..=hi).contains(&seed.at_order(k).phi))
                    .collect();
                pairs.push((seed.clone(), flags));
                pairs.len() - 1
            }
        };
        pairs[i].1[seed.order] |= *hit;
    }
    // Pairs in parallel (the outermost loop), each pair's orders in sequence; only the
    // centre search is in the chain, the edges and onsets of what it finds follow in a
    // second parallel pass (a long chain would otherwise hold one thread alone).
    let hits: Vec<(Seed, f64, usize)> = pairs
        .into_par_iter()
        .map(|(pair, mut flags)| {
            faer::set_global_parallelism(faer::Par::Seq);
            let mut out = Vec::new();
            for k in s.max_order + 1..=s.search_order {
                let seed = pair.at_order(k);
                if !(flags[k - 1] || flags[k - 2]) || seed.phi < lo {
                    break;
                }
                // Outside the range, or inside a region already found at the level (its
                // tongue could not be told apart there): not searched, counted as found.
                if seed.phi > hi || spans.iter().any(|&(l, r)| l <= seed.phi && seed.phi <= r) {
                    flags[k] = true;
                    continue;
                }
                let mut count = 0;
                let phi = basis.and_then(|b| centre_search(fs, b, s, &seed, level, &mut count));
                total.add(count);
                flags[k] = phi.is_some();
                if let Some(phi) = phi {
                    out.push((seed, phi, count));
                }
            }
            out
        })
        .flatten()
        .collect();
    hits.into_par_iter()
        .map(|(seed, phi, searched)| {
            faer::set_global_parallelism(faer::Par::Seq);
            let mut count = 0;
            let r = found_at(fs, s, &seed, phi, level, &mut count);
            total.add(count);
            Some(Region { evaluations: searched + count, ..r })
        })
        .collect()
}

/// The guard scan at the level: φ on a geometric grid of relative step `guard_step`
/// (rayon over points); an unstable point outside every region's edges is a missed
/// region, whose edges are bisected and returned.
fn guard_scan(
    fs: &FloquetSystem,
    s: &RegionSettings,
    spans: &[(f64, f64)],
    range: (f64, f64),
    level: f64,
    total: &Counter,
) -> Vec<Edges> {
    if s.guard_step <= 0.0 || level <= 0.0 {
        return Vec::new();
    }
    let covered = |phi: f64| spans.iter().any(|&(l, r)| l <= phi && phi <= r);
    let n = ((range.1 / range.0).ln() / s.guard_step.ln_1p()).ceil() as usize;
    let grid: Vec<f64> =
        (0..=n).map(|k| range.0 * (1.0 + s.guard_step).powi(k as i32)).filter(|&p| p <= range.1).collect();
    let hits: Vec<f64> = grid
        .par_iter()
        .filter(|&&phi| !covered(phi))
        .filter(|&&phi| {
            faer::set_global_parallelism(faer::Par::Seq);
            let mut count = 0;
            let hit = unstable_at(fs, phi, level, &mut count);
            total.add(count);
            hit
        })
        .copied()
        .collect();
    let mut out: Vec<Edges> = Vec::new();
    for phi in hits {
        if out.iter().any(|e| e.left <= phi && phi <= e.right) {
            continue;
        }
        let mut count = 0;
        out.push(edges_at(fs, s, phi, level, &mut count));
        total.add(count);
    }
    out
}

/// `bands` minus the interval `gap`.
fn subtract(bands: &[[f64; 2]], gap: (f64, f64)) -> Vec<[f64; 2]> {
    let mut out = Vec::new();
    for b in bands {
        if gap.1 <= b[0] || gap.0 >= b[1] {
            out.push(*b);
            continue;
        }
        if gap.0 > b[0] {
            out.push([b[0], gap.0]);
        }
        if gap.1 < b[1] {
            out.push([gap.1, b[1]]);
        }
    }
    out
}

/// Complement of the union of the regions' [left, right] at the level within `range`.
pub fn bands(regions: &[Region], range: (f64, f64)) -> Vec<[f64; 2]> {
    let mut spans: Vec<(f64, f64)> = regions.iter().filter_map(|r| Some((r.left?, r.right?))).collect();
    spans.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = Vec::new();
    let mut cursor = range.0;
    for (l, r) in spans {
        if l > cursor {
            out.push([cursor, l.min(range.1)]);
        }
        cursor = cursor.max(r);
        if cursor >= range.1 {
            break;
        }
    }
    if cursor < range.1 {
        out.push([cursor, range.1]);
    }
    out.retain(|b| b[1] > b[0]);
    out
}

/// The stable band at level β containing φ_op: march outward from φ_op until unstable on
/// each side (bisecting the edges; the two sides in parallel), or None if φ_op itself is
/// unstable.
pub fn band_at(
    fs: &FloquetSystem,
    s: &RegionSettings,
    phi_op: f64,
    level: f64,
    range: (f64, f64),
    count: &mut usize,
) -> Option<[f64; 2]> {
    if unstable_at(fs, phi_op, level, count) {
        return None;
    }
    let side = |dir: f64| -> (f64, usize) {
        let mut n = 0;
        let count = &mut n;
        // Steps of 0.5 % of φ_op: thinner regions (higher orders) can be stepped over; the
        // catalogue's seeds catch those.
        let step = phi_op * 0.005;
        let mut lo = phi_op;
        loop {
            let hi = lo + dir * step;
            if hi <= range.0 || hi >= range.1 {
                return (if dir < 0.0 { range.0 } else { range.1 }, n);
            }
            if unstable_at(fs, hi, level, count) {
                return (bisect_boundary(fs, s, hi, lo, level, count), n);
            }
            lo = hi;
        }
    };
    // The two sides are independent: the outermost parallel loop of this query.
    let ((left, n_left), (right, n_right)) = rayon::join(
        || {
            faer::set_global_parallelism(faer::Par::Seq);
            side(-1.0)
        },
        || {
            faer::set_global_parallelism(faer::Par::Seq);
            side(1.0)
        },
    );
    *count += n_left + n_right;
    Some([left, right])
}
