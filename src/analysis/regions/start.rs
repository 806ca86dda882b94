//! Where a region starts: its tip φ_s = argmin β_c and onset β_min = min β_c, located from
//! the seed (ω_i + ω_j)/k by bracketing β_c(seed) and climbing to the tip.

use super::critical::{self, Crossing};
use super::maximise::climb;
use super::RegionSettings;
use crate::analysis::floquet::FloquetSystem;

/// Half-width of the φ window searched for a region's start around its seed, relative.
/// Damping and the static load shift a start from the undamped sum by far less.
pub const START_WINDOW: f64 = 0.003;

/// A growth maximum within this fraction of the window's edge is the neighbour's tip, not
/// this seed's: the seed's own tip is then not located in its window.
const EDGE_FRACTION: f64 = 0.05;

/// Bisection tolerance of β_c at a seed before its tip is searched: 1/512, four halvings
/// of the 1/32 bracket. The onset is bisected to `beta_tolerance` where it is reported.
pub const SCREENING_TOLERANCE: f64 = 1.0 / 512.0;

/// A located start: φ_s (rad/s), β_min (−), and whether the tip was separated from its
/// neighbours (false: φ_s is the seed and β_min is β_c there, an upper bound).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Start {
    /// φ_s (rad/s).
    pub phi: f64,
    /// β_min (−).
    pub onset: f64,
    /// Whether the tip was located.
    pub resolved: bool,
}

/// ln max|μ| at (φ, β) from a fresh per-φ table; counts one evaluation.
pub fn growth_at(fs: &FloquetSystem, phi: f64, beta: f64, count: &mut usize) -> f64 {
    *count += 1;
    fs.point_fast(&fs.table(phi, beta), beta).summary.ln_max_multiplier
}

/// The tip of the region seeded at `seed_phi`, searched within ±`half_width` (rad/s),
/// from the bracket (stable β₋, unstable β₀) of β_c(seed). At the load
/// β₋(1 + m_rel) + m_abs (`tip_margin`, at most `cap`) the region is a short interval
/// around its tip that contains the seed, and the tip φ_s is the maximum of ln max|μ|
/// over φ there ([`climb`]); the onset is then β_c(φ_s) ≤ β₀ by
/// [`critical::critical_load_below`] (None if φ_s is stable at β₀). None if the climb
/// leaves the window, or ends within [`EDGE_FRACTION`] of its edge: the seed lies on the
/// flank of a neighbouring region, whose tip it is climbing to.
pub fn locate_tip(
    fs: &FloquetSystem,
    s: &RegionSettings,
    seed_phi: f64,
    (below, beta0): (f64, f64),
    half_width: f64,
    cap: f64,
    count: &mut usize,
) -> Option<(f64, Option<f64>)> {
    let level = (below * (1.0 + s.tip_margin.0) + s.tip_margin.1).min(cap).max(beta0);
    let tip = climb(|phi| growth_at(fs, phi, level, count), s, seed_phi, half_width)?;
    if (tip - seed_phi).abs() > (1.0 - EDGE_FRACTION) * half_width {
        return None;
    }
    let c1 = critical::critical_load_below(fs, s, tip, beta0);
    *count += c1.evaluations;
    Some((tip, c1.beta))
}

/// [`locate_tip`] from the seed; None if β_c(seed) is above β_max. Unresolved regions keep
/// the seed and β_c(seed) as start and onset.
///
/// β_c(seed) is bracketed first on a table built to the level β_op (samples k·`beta_bracket`
/// below it, then β_op itself), and only above β_op on a table built to β_max; the tip
/// search of a region with β_c(seed) ≤ β_op stays at or below β_op. So a start and onset at
/// or below β_op do not depend on β_max.
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
    (level, beta_max): (f64, f64),
    count: &mut usize,
) -> Option<Start> {
    // Never coarser than the tip margin's absolute part, so that the level, taken from the
    // stable end, is still above β_c(seed).
    let tolerance = SCREENING_TOLERANCE.min(s.tip_margin.1).max(s.beta_tolerance);
    let pivot = level.min(beta_max);
    let low = fs.table(seed_phi, pivot);
    let screened = Crossing::below(fs, s, &low, (0.0, pivot), tolerance);
    *count += screened.evaluations;
    let (table, screened, cap) = if screened.bracket.is_some() || beta_max <= pivot {
        (low, screened, pivot)
    } else {
        let high = fs.table(seed_phi, beta_max);
        let c = Crossing::below(fs, s, &high, (pivot, beta_max), tolerance);
        *count += c.evaluations;
        (high, c, beta_max)
    };
    let (below, beta0) = screened.bracket?;
    let tip = locate_tip(fs, s, seed_phi, (below, beta0), half_width, cap, count);
    // β_c(seed) bisected on from a (stable, unstable) bracket, on the seed's table.
    let refine = |lo: f64, hi: f64, count: &mut usize| {
        let fine = Crossing::bisected(fs, &table, (lo, hi), s.beta_tolerance);
        *count += fine.evaluations;
        fine.bracket.map_or(hi, |b| b.1)
    };
    let (phi, onset, resolved) = match tip {
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
    Some(Start { phi, onset, resolved })
}
