//! Closed intervals of φ (rad/s) or β: the one shape every region edge, band and window
//! takes.

use serde::{Deserialize, Serialize};

/// The fraction of a step by which a grid's last point may fall short of its interval's
/// end and still be the end: decimal steps (0.025) are not exact in binary.
const STEP_SLACK: f64 = 1e-9;

/// A closed interval [lo, hi].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Interval {
    /// Lower end (rad/s for φ intervals, − for β intervals).
    pub lo: f64,
    /// Upper end, ≥ `lo` (same unit).
    pub hi: f64,
}

impl Interval {
    /// [lo, hi].
    pub const fn new(lo: f64, hi: f64) -> Interval {
        Interval { lo, hi }
    }

    /// hi − lo.
    pub fn width(&self) -> f64 {
        self.hi - self.lo
    }

    /// The midpoint.
    pub fn centre(&self) -> f64 {
        0.5 * (self.lo + self.hi)
    }

    /// lo ≤ x ≤ hi.
    pub fn contains(&self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }

    /// The number of points of [`Interval::stepped`] with `step` (> 0; 0 for an empty
    /// interval or a step that is not positive). A float, as a wide interval of small
    /// steps has more points than a `usize` counts: compare it with a limit before
    /// asking for the points.
    pub fn step_count(&self, step: f64) -> f64 {
        if step > 0.0 && self.hi >= self.lo {
            // A last point within 1e-9 of a step of hi (rounding of decimal steps) is hi.
            ((self.hi - self.lo) / step + STEP_SLACK).floor() + 1.0
        } else {
            0.0
        }
    }

    /// The points lo, lo + step, lo + 2·step, … up to hi (hi itself when it is on the
    /// grid, to 1e-9 of a step): the grid of an `A:B:STEP` range on the command line, each
    /// point computed from lo (no accumulated rounding). Empty when
    /// [`Interval::step_count`] is 0; bound the count first.
    pub fn stepped(&self, step: f64) -> Vec<f64> {
        let n = self.step_count(step) as usize;
        (0..n).map(|i| self.lo + i as f64 * step).collect()
    }

    /// The two intervals share at least one point.
    pub fn overlaps(&self, other: &Interval) -> bool {
        self.lo <= other.hi && other.lo <= self.hi
    }

    /// The interval clipped to `limits`.
    pub fn clipped(&self, limits: &Interval) -> Interval {
        Interval { lo: self.lo.max(limits.lo), hi: self.hi.min(limits.hi) }
    }
}

impl std::fmt::Display for Interval {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match f.precision() {
            Some(p) => write!(f, "[{:.p$}, {:.p$}]", self.lo, self.hi),
            None => write!(f, "[{}, {}]", self.lo, self.hi),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::Interval;

    #[test]
    fn a_grid_ends_on_its_end_despite_decimal_steps() {
        // 0.025 is not exact in binary: 1/0.025 is 39.99999999999999778, yet 1 is the 41st.
        let g = Interval::new(0.0, 1.0).stepped(0.025);
        assert_eq!(g.len(), 41);
        assert_eq!(g[40], 40.0 * 0.025);
        assert_eq!(Interval::new(100.0, 14000.0).step_count(25.0), 557.0);
        // A point short of the end by more than the slack is not added.
        assert_eq!(Interval::new(0.0, 1.0).stepped(0.3), vec![0.0, 0.3, 0.6, 0.3 * 3.0]);
        assert_eq!(Interval::new(2.0, 2.0).stepped(1.0), vec![2.0]);
    }

    #[test]
    fn no_grid_without_a_positive_step_or_with_ends_reversed() {
        for step in [0.0, -1.0, f64::NAN] {
            assert_eq!(Interval::new(0.0, 1.0).step_count(step), 0.0);
        }
        assert!(Interval::new(1.0, 0.0).stepped(0.1).is_empty());
    }
}
