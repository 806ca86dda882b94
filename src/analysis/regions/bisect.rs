//! One bisection for every crossing the region search narrows (β_c in β, edges in φ), and
//! the outward march that brackets an edge.

use super::RegionSettings;
use crate::analysis::Interval;

/// A bracket of a crossing along one coordinate: the test holds at `inside` and fails at
/// `outside`, which may lie on either side of it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bracket {
    /// Where the test holds.
    pub inside: f64,
    /// Where the predicate fails (the other end of the bracket).
    pub outside: f64,
}

impl Bracket {
    /// The bracket as an interval (lo ≤ hi).
    pub fn interval(&self) -> Interval {
        let (lo, hi) = self.ordered();
        Interval::new(lo, hi)
    }

    fn ordered(&self) -> (f64, f64) {
        if self.inside <= self.outside {
            (self.inside, self.outside)
        } else {
            (self.outside, self.inside)
        }
    }
}

/// Where a bracket is split next.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Split {
    /// At the midpoint, until the bracket is at most this wide.
    Halves(f64),
    /// At the lattice point of largest spacing (a power-of-two multiple of this cell)
    /// strictly inside, until the bracket lies inside one cell: the final cell is the one
    /// lattice cell that contains the crossing, whatever the bracket was.
    Lattice(f64),
}

impl Split {
    /// The next split point strictly inside (a, b), a ≤ b; None when the bracket is done.
    fn point(self, a: f64, b: f64) -> Option<f64> {
        match self {
            Split::Halves(tolerance) => (b - a > tolerance).then_some(0.5 * (a + b)),
            Split::Lattice(cell) => lattice_split(a, b, cell),
        }
    }
}

/// Narrow `bracket` by `split`, testing each split point.
pub fn bisect(mut bracket: Bracket, split: Split, mut test: impl FnMut(f64) -> bool) -> Bracket {
    loop {
        let (a, b) = bracket.ordered();
        let Some(m) = split.point(a, b) else { return bracket };
        if test(m) {
            bracket.inside = m;
        } else {
            bracket.outside = m;
        }
    }
}

/// Where an outward march ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum March {
    /// At a point where the test fails: the bracket from the last point where it held.
    Crossed(Bracket),
    /// The next step would reach the limit: the last point where the test held.
    Limit(f64),
}

/// March from `inside` (where `test` holds) in the direction `dir` (−1 or +1) to the first
/// point where it fails: steps growing from max(2e-4·φ, 4·`phi_tolerance`) by 1.6 up to
/// [`RegionSettings::edge_step`] at the point reached, so a stable gap that wide is never
/// stepped over. Stops before a step that reaches `limit` (rad/s).
pub fn march(s: &RegionSettings, inside: f64, dir: f64, limit: f64, mut test: impl FnMut(f64) -> bool) -> March {
    let mut lo = inside;
    let mut step = (inside * 2e-4).max(4.0 * s.phi_tolerance);
    loop {
        let hi = lo + dir * step;
        if (hi - limit) * dir >= 0.0 {
            return March::Limit(lo);
        }
        if !test(hi) {
            return March::Crossed(Bracket { inside: lo, outside: hi });
        }
        lo = hi;
        step = (step * 1.6).min(s.edge_step.at(lo));
    }
}

/// The lattice point of largest spacing (a power-of-two multiple of `cell`) strictly
/// inside (a, b); None when (a, b) lies inside one cell.
fn lattice_split(a: f64, b: f64, cell: f64) -> Option<f64> {
    if b.partial_cmp(&a) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let mut spacing = cell * 2f64.powi(((b - a) / cell).log2().ceil().max(0.0) as i32);
    while spacing >= cell {
        let m = ((a / spacing).floor() + 1.0) * spacing;
        if m < b {
            return Some(m);
        }
        spacing /= 2.0;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::{bisect, Bracket, Split};

    #[test]
    fn lattice_refinement_ends_in_the_crossing_cell_from_any_bracket() {
        // A crossing at x* = 1234.3: brackets of any size and offset end in [1234.25, 1234.375].
        let cell = 0.125;
        let x_star = 1234.3;
        for (a0, b0) in [(1230.0, 1240.0), (1234.01, 1234.99), (1200.3, 1234.31), (1234.29, 1300.0)] {
            let b = bisect(Bracket { inside: a0, outside: b0 }, Split::Lattice(cell), |m| m < x_star);
            let k = (b.interval().lo / cell).floor();
            assert_eq!((k * cell, (k + 1.0) * cell), (1234.25, 1234.375), "from ({a0}, {b0})");
        }
    }

    #[test]
    fn halving_stops_at_the_tolerance_around_the_crossing() {
        // Either orientation: the final bracket is at most the tolerance wide and holds x*.
        let x_star = 0.3141;
        for (inside, outside) in [(1.0, 0.0), (0.0, 1.0)] {
            let up = inside > outside;
            let b = bisect(Bracket { inside, outside }, Split::Halves(1e-4), |m| (m > x_star) == up);
            let i = b.interval();
            assert!(i.width() <= 1e-4 && i.contains(x_star), "{b:?}");
        }
    }
}
