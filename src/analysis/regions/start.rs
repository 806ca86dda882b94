//! Where a region starts: its tip φ_s = argmin β_c and onset β_min = min β_c, located from
//! the seed (ω_i + ω_j)/k by bracketing β_c(seed) and climbing to the tip.

use super::maximise::climb;
use super::Probe;
use crate::analysis::Interval;

/// Half-width of the φ window searched for a region's start around its seed, relative.
/// Damping and the static load shift a start from the undamped sum by far less.
pub const START_WINDOW: f64 = 0.003;

/// A growth maximum within this fraction of the window's edge is the neighbour's tip, not
/// this seed's: the seed's own tip is then not located in its window.
pub const EDGE_FRACTION: f64 = 0.05;

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

/// A region's tip found by the climb.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tip {
    /// The growth maximum φ_s (rad/s).
    pub phi: f64,
    /// β_c(φ_s) (−), or None if φ_s is stable at the bracket's unstable load.
    pub onset: Option<f64>,
}

impl Probe<'_> {
    /// The tip of the region seeded at `seed_phi`, searched within ±`half_width` (rad/s),
    /// from the bracket [stable β₋, unstable β₀] of β_c(seed). At the load
    /// [`RegionSettings::tip_margin`](super::RegionSettings::tip_margin) above β₋ (at most
    /// `cap`) the region is a short interval around its tip that contains the seed, and
    /// the tip φ_s is the maximum of ln max|μ| over φ there (`climb`); the onset is then
    /// β_c(φ_s) ≤ β₀ by [`Probe::critical_load_below`]. None if the climb leaves the
    /// window, or ends within `EDGE_FRACTION` of its edge: the seed lies on the flank of
    /// a neighbouring region, whose tip it is climbing to.
    pub fn locate_tip(&self, seed_phi: f64, bracket: Interval, half_width: f64, cap: f64) -> Option<Tip> {
        let s = self.settings();
        let level = s.tip_margin.above(bracket.lo).min(cap).max(bracket.hi);
        let tip = climb(|phi| self.growth(phi, level), s, seed_phi, half_width)?;
        if (tip - seed_phi).abs() > (1.0 - EDGE_FRACTION) * half_width {
            return None;
        }
        Some(Tip { phi: tip, onset: self.critical_load_below(tip, bracket.hi).beta })
    }

    /// [`Probe::locate_tip`] from the seed, with the onset at or below the level β_op
    /// (`level`) found whatever `beta_max` is; None if β_c(seed) is above β_max.
    /// Unresolved regions keep the seed and β_c(seed) as start and onset.
    ///
    /// β_c(seed) is bracketed first on a table built to the level β_op (samples
    /// k·`beta_bracket` below it, then β_op itself), and only above β_op on a table built
    /// to β_max; the tip search of a region with β_c(seed) ≤ β_op stays at or below β_op.
    /// So a start and onset at or below β_op do not depend on β_max.
    ///
    /// β_c(seed) is screened to `SCREENING_TOLERANCE` only: the tip search needs no more
    /// (its level lies 5 % + 0.002 above), and the onset reported is then β_c at the tip,
    /// bisected to `beta_tolerance`. Where β_c(seed) itself is the onset it is bisected on,
    /// on the same table; where β_c at the tip lies inside the screening bracket, one
    /// evaluation at the seed tells whether the seed is lower (the onset is then min β_c of
    /// the two to the tolerance, as with a fully bisected β_c(seed)).
    pub fn locate_start(&self, seed_phi: f64, half_width: f64, level: f64, beta_max: f64) -> Option<Start> {
        let s = self.settings();
        let fs = self.system();
        // Never coarser than the tip margin's absolute part, so that the level, taken from
        // the stable end, is still above β_c(seed).
        let tolerance = SCREENING_TOLERANCE.min(s.tip_margin.absolute).max(s.beta_tolerance);
        let pivot = level.min(beta_max);
        let low = fs.table(seed_phi, pivot);
        let screened = self.crossing(&low, Interval::new(0.0, pivot), tolerance);
        let (table, screened, cap) = if screened.is_some() || beta_max <= pivot {
            (low, screened, pivot)
        } else {
            let high = fs.table(seed_phi, beta_max);
            let c = self.crossing(&high, Interval::new(pivot, beta_max), tolerance);
            (high, c, beta_max)
        };
        let bracket = screened?;
        let below = bracket.lo;
        let tip = self.locate_tip(seed_phi, bracket, half_width, cap);
        // β_c(seed) bisected on from a [stable, unstable] bracket, on the seed's table.
        let refine = |lo: f64, hi: f64| self.narrowed(&table, Interval::new(lo, hi), s.beta_tolerance).hi;
        let (phi, onset, resolved) = match tip {
            // β_c at the tip inside the screening bracket: β_c(seed) may be lower by more
            // than the tolerance, which one evaluation on the seed's table tells; the seed is
            // then the better start, and its β_c is bisected on from there.
            Some(Tip { phi, onset: Some(beta) }) if beta - s.beta_tolerance > below => {
                let trial = beta - s.beta_tolerance;
                if self.unstable_on(&table, trial) {
                    (seed_phi, refine(below, trial), true)
                } else {
                    (phi, beta, true)
                }
            }
            Some(Tip { phi, onset: Some(beta) }) => (phi, beta, true),
            Some(Tip { onset: None, .. }) => (seed_phi, refine(below, bracket.hi), true),
            None => (seed_phi, refine(below, bracket.hi), false),
        };
        Some(Start { phi, onset, resolved })
    }
}
