//! The probe at one load level β_op under the declared criterion: whether φ counts as
//! unstable, the edges of the tongue through a counted point, and the guard lattice. The
//! tongues themselves (the seeds' hits and the guard scan) are [`super::tongues`].
//!
//! Every question the band, the catalogue and the design ask at β_op goes through one
//! [`Level`], which borrows the [`Probe`] of its Floquet system (and its count of
//! monodromy evaluations).
//!
//! **Edges.** The march from a point inside a tongue to its edge ([`Level::edge`]) ends
//! with a bracket (counted, not counted) that is refined on the dyadic lattice of cell
//! [`Level::cell`] (the largest power of two not above `phi_tolerance`): the split point
//! is always the lattice point of largest spacing inside the bracket, so the final cell
//! is the one lattice cell that contains the crossing, whatever the bracket was
//! ([`Split::Lattice`]). The edge reported is that cell's end on the stable side. Two
//! searches that reach the same crossing from different points (the band from φ_op, the
//! catalogue from a seed) report the same number, and a band never contains the resolved
//! crossing itself.
//!
//! **Guard lattice.** Tongues a seed does not find are caught on the lattice of points
//! (1 + g)^n, n ∈ ℤ (g = `RegionSettings::guard_step`): fixed in φ, so the band's march
//! from φ_op and the catalogue's scan of a range visit the same points.

use super::bisect::{bisect, march, Bracket, March, Split};
use super::centre::{twin_groups, ModeBasis};
use super::tongues::{GroupHit, GroupKey};
use super::{Probe, RegionSettings};
use crate::analysis::floquet::PointSummary;
use crate::analysis::{Criterion, Interval};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

/// The probe at one level: the declared criterion on (φ, β_op), seeds' tongues, edges.
pub struct Level<'p> {
    pub(super) probe: &'p Probe<'p>,
    pub(super) basis: Option<ModeBasis>,
    pub(super) criterion: Criterion,
    pub(super) beta: f64,
    pub(super) limits: Interval,
    /// The reduced model's forward and backward whirls (ascending), and the twin group of
    /// each.
    pub(super) whirls: (Vec<f64>, Vec<f64>),
    pub(super) groups: (Vec<Vec<usize>>, Vec<Vec<usize>>),
    pub(super) group_of: (Vec<usize>, Vec<usize>),
    /// Each group search is made once, whichever of its seeds asks first.
    pub(super) searched: Mutex<HashMap<GroupKey, Arc<OnceLock<Vec<GroupHit>>>>>,
    /// (φ, max|μ|) of every point evaluated by [`Level::point`] (guard-lattice points,
    /// march steps, edge refinements): the samples a band's largest max|μ| is read from.
    pub(super) seen: Mutex<Vec<(f64, f64)>>,
}

impl<'p> Level<'p> {
    /// The probe at level β (−) by `criterion`, inside the φ window `limits` (rad/s): no
    /// march goes beyond it. Its evaluations are counted by `probe`.
    pub fn new(probe: &'p Probe<'p>, criterion: Criterion, beta: f64, limits: Interval) -> Level<'p> {
        let fs = probe.system();
        let whirls = fs.whirls().unwrap_or_default();
        let groups = (twin_groups(&whirls.0), twin_groups(&whirls.1));
        let index = |g: &[Vec<usize>], n: usize| {
            let mut v = vec![0; n];
            for (k, members) in g.iter().enumerate() {
                for &m in members {
                    v[m] = k;
                }
            }
            v
        };
        let group_of = (index(&groups.0, whirls.0.len()), index(&groups.1, whirls.1.len()));
        Level {
            probe,
            basis: ModeBasis::new(fs),
            criterion,
            beta,
            limits,
            whirls,
            groups,
            group_of,
            searched: Mutex::new(HashMap::new()),
            seen: Mutex::new(Vec::new()),
        }
    }

    /// The probe of the Floquet system (settings and evaluation count).
    pub fn probe(&self) -> &'p Probe<'p> {
        self.probe
    }

    /// The level β (−).
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// The declared criterion.
    pub fn criterion(&self) -> &Criterion {
        &self.criterion
    }

    /// The φ window (rad/s).
    pub fn limits(&self) -> Interval {
        self.limits
    }

    /// The Floquet point at (φ, β_op); one evaluation.
    pub fn point(&self, phi: f64) -> PointSummary {
        let p = self.probe.point(phi, self.beta);
        self.seen.lock().unwrap_or_else(|e| e.into_inner()).push((phi, p.max_multiplier));
        p
    }

    /// The largest max|μ| among the points this level evaluated inside `band` (ends
    /// included), and how many there were; None without one.
    pub fn largest_inside(&self, band: Interval) -> Option<(f64, usize)> {
        let seen = self.seen.lock().unwrap_or_else(|e| e.into_inner());
        let inside: Vec<f64> = seen.iter().filter(|(phi, _)| band.contains(*phi)).map(|(_, m)| *m).collect();
        let largest = inside.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (!inside.is_empty()).then_some((largest, inside.len()))
    }

    /// Whether (φ, β_op) counts as unstable by the criterion; one evaluation.
    pub fn counts(&self, phi: f64) -> bool {
        self.criterion.counts(&self.point(phi))
    }

    /// The dyadic cell of the edges (rad/s): the largest power of two not above
    /// `phi_tolerance`.
    pub fn cell(&self) -> f64 {
        lattice_cell(self.probe.settings())
    }

    /// The edge of the tongue containing the counted point `inside`, on the side `dir`
    /// (−1 left, +1 right): march outward (`march`) to a point that does not count, then
    /// refine on the lattice (module docs). The window's end if the tongue reaches it.
    pub fn edge(&self, inside: f64, dir: f64) -> f64 {
        let limit = if dir < 0.0 { self.limits.lo } else { self.limits.hi };
        match march(self.probe.settings(), inside, dir, limit, |phi| self.counts(phi)) {
            March::Crossed(bracket) => self.refine(bracket),
            March::Limit(lo) => {
                if (limit - lo) * dir > 0.0 && !self.counts(limit) {
                    self.refine(Bracket { inside: lo, outside: limit })
                } else {
                    limit
                }
            }
        }
    }

    /// Refine a bracket between a counted and an uncounted point to the lattice cell of
    /// the crossing; the cell's end on the uncounted side.
    fn refine(&self, bracket: Bracket) -> f64 {
        let cell = self.cell();
        let b = bisect(bracket, Split::Lattice(cell), |phi| self.counts(phi));
        let k = (b.interval().lo / cell).floor();
        if b.outside > b.inside {
            (k + 1.0) * cell
        } else {
            k * cell
        }
    }

    /// Both edges of the tongue containing the counted point `inside` (the two marches in
    /// parallel), clipped to the window. For a point outside the window only the edge
    /// facing it is searched: None if the tongue does not reach into the window.
    pub fn extent(&self, inside: f64) -> Option<Interval> {
        let limits = self.limits;
        if inside > limits.hi {
            let lo = self.edge(inside, -1.0);
            return (lo < limits.hi).then_some(Interval::new(lo, limits.hi));
        }
        if inside < limits.lo {
            let hi = self.edge(inside, 1.0);
            return (hi > limits.lo).then_some(Interval::new(limits.lo, hi));
        }
        let (lo, hi) = rayon::join(|| self.edge(inside, -1.0), || self.edge(inside, 1.0));
        Some(Interval::new(lo, hi))
    }

    /// The guard lattice points (1 + g)^n inside `window`, ascending.
    pub fn lattice(&self, window: Interval) -> Vec<f64> {
        guard_lattice(self.probe.settings().guard_step, window)
    }
}

/// The dyadic cell of the edges at the level (rad/s): the largest power of two not above
/// `phi_tolerance` ([`Level::cell`]).
pub fn lattice_cell(s: &RegionSettings) -> f64 {
    2f64.powi(s.phi_tolerance.log2().floor() as i32)
}

/// The guard lattice points (1 + g)^n inside `window`, ascending (g = `guard_step`): the
/// points a search visits, and the ones its cost estimate counts
/// ([`crate::analysis::cost`]).
pub fn guard_lattice(g: f64, window: Interval) -> Vec<f64> {
    if g <= 0.0 || window.lo <= 0.0 {
        return Vec::new();
    }
    let base = g.ln_1p();
    let first = (window.lo.ln() / base).ceil() as i64;
    let last = (window.hi.ln() / base).floor() as i64;
    (first..=last).map(|n| lattice_point(g, n)).filter(|p| window.contains(*p)).collect()
}

/// (1 + g)^n, computed the same way wherever it is asked for.
fn lattice_point(g: f64, n: i64) -> f64 {
    (n as f64 * g.ln_1p()).exp()
}
