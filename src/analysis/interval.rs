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
    /// interval or a step that is not positive). A float: a wide interval of small steps
    /// has more points than a `usize` counts.
    pub fn step_count(&self, step: f64) -> f64 {
        if step > 0.0 && self.hi >= self.lo {
            // A last point short of hi by less than the slack (rounding of decimal steps)
            // counts as the end's.
            ((self.hi - self.lo) / step + STEP_SLACK).floor() + 1.0
        } else {
            0.0
        }
    }

    /// The points lo, lo + step, lo + 2·step, … up to hi: the grid of an `A:B:STEP` range
    /// on the command line, each point computed from lo (no accumulated rounding). A last
    /// point within 1e-9 of a step of hi is kept, as computed: for hi on the grid it may
    /// differ from hi by a rounding (0:0.3:0.1 ends on 0.30000000000000004). Empty when
    /// [`Interval::step_count`] is 0; `None` when it is above `most`, the points the
    /// caller will hold.
    pub fn stepped(&self, step: f64, most: usize) -> Option<Vec<f64>> {
        let n = self.step_count(step);
        (n <= most as f64).then(|| (0..n as usize).map(|i| self.lo + i as f64 * step).collect())
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
        // 0.3/0.1 is 2.9999999999999996 in f64: without the slack the grid would stop at
        // 0.2; with it the fourth point is 3·0.1 = 0.30000000000000004.
        assert_eq!(0.3 / 0.1, 2.999_999_999_999_999_6);
        let g = Interval::new(0.0, 0.3).stepped(0.1, 10).unwrap();
        assert_eq!(g, vec![0.0, 0.1, 0.2, 3.0 * 0.1]);
        assert_eq!(Interval::new(100.0, 14000.0).step_count(25.0), 557.0);
        // A point short of the end by more than the slack is not added.
        assert_eq!(Interval::new(0.0, 1.0).stepped(0.3, 10).unwrap(), vec![0.0, 0.3, 0.6, 0.3 * 3.0]);
        assert_eq!(Interval::new(2.0, 2.0).stepped(1.0, 1).unwrap(), vec![2.0]);
    }

    #[test]
    fn no_grid_without_a_positive_step_or_with_ends_reversed() {
        for step in [0.0, -1.0, f64::NAN] {
            assert_eq!(Interval::new(0.0, 1.0).step_count(step), 0.0);
        }
        assert_eq!(Interval::new(1.0, 0.0).stepped(0.1, 10), Some(vec![]));
    }

    #[test]
    fn a_grid_beyond_its_bound_is_refused_not_built() {
        assert_eq!(Interval::new(0.0, 1e300).step_count(1e-300), f64::INFINITY);
        assert_eq!(Interval::new(0.0, 1e300).stepped(1e-300, 1_000_000), None);
        assert_eq!(Interval::new(0.0, 1.0).stepped(0.1, 10), None, "11 points");
    }
}
