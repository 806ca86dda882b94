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

/// The march's first step relative to φ (−), and its floor in `phi_tolerance`s.
const FIRST_STEP_RELATIVE: f64 = 2e-4;
const FIRST_STEP_TOLERANCES: f64 = 4.0;
/// Each step of a march is this many times the last, up to the edge step.
const STEP_GROWTH: f64 = 1.6;

/// The first step of a march from φ = `inside` (rad/s).
pub(super) fn first_step(s: &RegionSettings, inside: f64) -> f64 {
    (inside * FIRST_STEP_RELATIVE).max(FIRST_STEP_TOLERANCES * s.phi_tolerance)
}

/// The step after `step` once the march has reached φ = `lo` (rad/s).
fn next_step(s: &RegionSettings, step: f64, lo: f64) -> f64 {
    (step * STEP_GROWTH).min(s.edge_step.at(lo))
}

/// March from `inside` (where `test` holds) in the direction `dir` (−1 or +1) to the first
/// point where it fails: steps growing from max(2e-4·φ, 4·`phi_tolerance`) by 1.6 up to
/// [`RegionSettings::edge_step`] at the point reached, so a stable gap that wide is never
/// stepped over. Stops before a step that reaches `limit` (rad/s).
pub fn march(s: &RegionSettings, inside: f64, dir: f64, limit: f64, mut test: impl FnMut(f64) -> bool) -> March {
    let mut lo = inside;
    let mut step = first_step(s, inside);
    loop {
        let hi = lo + dir * step;
        if (hi - limit) * dir >= 0.0 {
            return March::Limit(lo);
        }
        if !test(hi) {
            return March::Crossed(Bracket { inside: lo, outside: hi });
        }
        lo = hi;
        step = next_step(s, step, lo);
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
    use super::{bisect, first_step, march, next_step, Bracket, Split};
    use crate::analysis::regions::RegionSettings;

    /// Most tests [`bisect`] makes on a bracket `width` wide (rad/s, or −): halving to a
    /// tolerance takes ⌈log₂(width/tolerance)⌉; a lattice split halves the largest spacing
    /// inside the bracket at least at every test (the bracket holds no multiple of twice the
    /// spacing it is split at), from at most ⌈log₂(width/cell)⌉ doublings of the cell down to
    /// the cell, one more.
    fn most_splits(width: f64, split: Split) -> f64 {
        match split {
            Split::Halves(tolerance) => (width / tolerance).log2().ceil().max(0.0),
            Split::Lattice(cell) => (width / cell).log2().ceil().max(0.0) + 1.0,
        }
    }

    /// Most steps a march from φ = `inside` (rad/s) takes before its step reaches the edge step: the
    /// march's own steps, walked upward (where the edge step grows with φ, the longest ramp),
    /// without a test. The steps at the full edge step are the march across the width it
    /// goes (what a cost counts across a window).
    fn ramp_steps(s: &RegionSettings, inside: f64) -> usize {
        let (mut lo, mut step, mut n) = (inside, first_step(s, inside), 0);
        while step < s.edge_step.at(lo) {
            lo += step;
            let next = next_step(s, step, lo);
            // A step that no longer grows (φ beyond f64's resolution) ends the ramp.
            if next.partial_cmp(&step) != Some(std::cmp::Ordering::Greater) {
                break;
            }
            step = next;
            n += 1;
        }
        n
    }

    #[test]
    fn bisections_stay_within_their_most_splits() {
        // Brackets of many widths and offsets, crossings anywhere inside: the tests made
        // never pass the bound, and the bound is reached (it is not slack by a factor).
        let mut worst = [0.0f64; 2];
        for k in 0..400 {
            let x = f64::from(k);
            let (a, width) = (1000.0 + 7.31 * x, 0.05 + 0.37 * x);
            let cross = a + width * (0.5 + 0.49 * (1.7 * x).sin());
            for (i, split) in [Split::Halves(1e-3), Split::Lattice(0.125)].into_iter().enumerate() {
                let mut tests = 0.0;
                bisect(Bracket { inside: a, outside: a + width }, split, |m| {
                    tests += 1.0;
                    m < cross
                });
                let most = most_splits(width, split);
                assert!(tests <= most, "{split:?} on [{a}, {}]: {tests} tests, at most {most}", a + width);
                worst[i] = worst[i].max(tests / most.max(1.0));
            }
        }
        assert!(worst.iter().all(|w| *w >= 0.75), "{worst:?}");
    }

    #[test]
    fn a_march_reaches_the_edge_step_within_its_ramp() {
        // From any start, the march's steps that are below the edge step number at most
        // the ramp: marching up or down through a long unstable stretch.
        let s = RegionSettings::default();
        for inside in [0.5, 37.0, 1230.0, 2.5e4, 3.0e6] {
            for dir in [-1.0, 1.0] {
                let (mut last, mut short) = (inside, 0);
                march(&s, inside, dir, if dir < 0.0 { 0.0 } else { f64::INFINITY }, |phi| {
                    let step = (phi - last).abs();
                    if step < s.edge_step.at(last) * (1.0 - 1e-12) {
                        short += 1;
                    }
                    last = phi;
                    (phi - inside).abs() < 400.0 * s.edge_step.at(inside)
                });
                let ramp = ramp_steps(&s, inside);
                assert!(short <= ramp, "from {inside} ({dir}): {short} short steps, ramp {ramp}");
                // Upward, where the edge step grows with φ, the ramp is what the march takes.
                if dir > 0.0 {
                    assert_eq!(short, ramp, "from {inside}");
                }
            }
        }
    }

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
