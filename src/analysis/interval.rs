//! Closed intervals of φ (rad/s) or β: the one shape every region edge, band and window
//! takes.

use serde::{Deserialize, Serialize};

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
