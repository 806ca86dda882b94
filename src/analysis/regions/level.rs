//! The unstable set at one load level β_op: where its tongues are along φ, found from the
//! seeds (ω_i + ω_j)/k of every order up to the criterion's and from a guard lattice,
//! with edges that do not depend on where a search started.
//!
//! Every question the band, the catalogue and the design ask at β_op goes through one
//! [`Level`]: is φ counted as unstable by the declared [`Criterion`], where is a seed's
//! tongue, where are its edges. It owns the count of monodromy evaluations.
//!
//! **Edges.** The march from a point inside a tongue to its edge ([`Level::edge`]) ends
//! with a bracket (counted, not counted) that is refined on the dyadic lattice of cell
//! [`Level::cell`] (the largest power of two not above `phi_tolerance`): the split point
//! is always the lattice point of largest spacing inside the bracket, so the final cell
//! is the one lattice cell that contains the crossing, whatever the bracket was. The edge
//! reported is that cell's end on the stable side. Two searches that reach the same
//! crossing from different points (the band from φ_op, the catalogue from a seed) report
//! the same number, and a band never contains the resolved crossing itself.
//!
//! **Guard lattice.** Tongues a seed does not find are caught on the lattice of points
//! (1 + g)^n, n ∈ ℤ (g = `RegionSettings::guard_step`): fixed in φ, so the band's march
//! from φ_op and the catalogue's scan of a range visit the same points.

use super::centre::{centre_search, detuning, twin_groups, ModeBasis, PairGroup, CENTRE_WINDOW};
use super::maximise::climb;
use super::seeds::Seed;
use super::RegionSettings;
use crate::analysis::floquet::{FloquetSystem, PointSummary};
use crate::analysis::{Criterion, Interval};
use rayon::prelude::*;
use serde::Serialize;
use std::collections::HashMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

/// A tongue's crest is looked for around the point where its pair's detuning vanishes
/// when the pair's split |ln|μ_i| − ln|μ_j|| there exceeds this: the pair has collided
/// and left the unit circle, but less than the criterion asks (a weak tongue whose growth
/// peaks beside that point), or been held inside it by damping (whose collided interval
/// is wider than the unstable tongue inside it). Round-off gives ~1e-12.
const SPLIT_TRIGGER: f64 = 1e-7;
/// The lock test looks this far (a fraction of `phi_tolerance`) on either side of the
/// converged point: inside the collided interval of even the thinnest tongue the search is
/// for (0.1 rad/s), where a transversal zero of δ has moved δ by 2πk/φ times it (at least
/// 8e-6 rad at φ ≤ 8000 rad/s). Locked on one side suffices: the search can converge on
/// the edge of the collided interval.
const LOCK_STEP: f64 = 0.05;
/// |δ| (rad) below which a pair is phase-locked: round-off inside a collided interval.
const LOCKED: f64 = 1e-7;
/// Half-width of that crest search, relative to φ (9 rad/s at 1800 rad/s): the collided
/// interval of a damped order-2 tongue at β = 0.3 on the paper's rotor is 6 rad/s wide.
const CREST_SPAN: f64 = 5e-3;

/// Key of a group search: (forward group, backward group, order).
type GroupKey = (usize, usize, usize);

/// A counted point of a tongue, and whether a seed's own pair has collided there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// φ (rad/s).
    pub phi: f64,
    /// Index of the seed whose pair collides here, if any.
    pub seed: Option<usize>,
}

/// One tongue of the unstable set at β_op.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Tongue {
    /// Its extent at β_op (rad/s): the outer ends of the lattice cells of its two
    /// crossings, clipped to the search window.
    pub extent: Interval,
    /// A counted point inside it (rad/s).
    pub inside: f64,
    /// (label, order) of the seeds whose pair collides inside it; empty when no seed's
    /// pair was identified there (a tongue found by the guard lattice or beside a seed).
    pub labels: Vec<(String, usize)>,
    /// (seed index, φ of its collision) of those seeds.
    #[serde(skip)]
    pub seeds: Vec<(usize, f64)>,
    /// Whether it counts by the criterion.
    pub counted: bool,
    /// Why the criterion ignores it, when it does.
    pub ignored: Option<Ignored>,
}

/// Why the declared criterion ignores a tongue (it is listed, never dropped).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Ignored {
    /// Narrower at β_op than `min_tongue_width`.
    Narrow,
    /// Unstable (max|μ| above the tolerance) but nowhere growing as fast as
    /// `min_growth_rate`.
    SlowGrowth,
}

impl Tongue {
    /// The label of lowest order (the strongest tongue of those colliding here), or
    /// `unlabelled`.
    pub fn label(&self) -> String {
        self.labels
            .iter()
            .min_by_key(|(_, k)| *k)
            .map_or_else(|| "unlabelled".to_string(), |(l, k)| format!("{l} (k = {k})"))
    }
}

/// The probe at one level: the declared criterion on (φ, β_op), seeds' tongues, edges.
pub struct Level<'a> {
    fs: &'a FloquetSystem,
    basis: Option<ModeBasis>,
    settings: &'a RegionSettings,
    criterion: Criterion,
    beta: f64,
    limits: Interval,
    evaluations: AtomicUsize,
    /// The reduced model's forward and backward whirls (ascending), and the twin group of
    /// each.
    whirls: (Vec<f64>, Vec<f64>),
    groups: (Vec<Vec<usize>>, Vec<Vec<usize>>),
    group_of: (Vec<usize>, Vec<usize>),
    /// Each group search is made once, whichever of its seeds asks first.
    searched: Mutex<HashMap<GroupKey, Arc<OnceLock<Vec<GroupHit>>>>>,
}

/// A counted point found by a group search: φ, and the (forward, backward) whirl indices
/// of the assignment whose pair collides there (None: another pair's tongue).
#[derive(Debug, Clone, Copy, PartialEq)]
struct GroupHit {
    phi: f64,
    pair: Option<(usize, usize)>,
}

impl<'a> Level<'a> {
    /// The probe at level β (−) inside the φ window `limits` (rad/s): no march goes
    /// beyond it.
    pub fn new(
        fs: &'a FloquetSystem,
        settings: &'a RegionSettings,
        criterion: Criterion,
        beta: f64,
        limits: Interval,
    ) -> Level<'a> {
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
            fs,
            basis: ModeBasis::new(fs),
            settings,
            criterion,
            beta,
            limits,
            evaluations: AtomicUsize::new(0),
            whirls,
            groups,
            group_of,
            searched: Mutex::new(HashMap::new()),
        }
    }

    /// The level β (−).
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// The declared criterion.
    pub fn criterion(&self) -> &Criterion {
        &self.criterion
    }

    /// The region-search settings.
    pub fn settings(&self) -> &RegionSettings {
        self.settings
    }

    /// The φ window (rad/s).
    pub fn limits(&self) -> Interval {
        self.limits
    }

    /// Monodromy evaluations so far.
    pub fn evaluations(&self) -> usize {
        self.evaluations.load(Ordering::Relaxed)
    }

    fn add(&self, n: usize) {
        self.evaluations.fetch_add(n, Ordering::Relaxed);
    }

    /// The Floquet point at (φ, β_op); one evaluation.
    pub fn point(&self, phi: f64) -> PointSummary {
        self.add(1);
        self.fs.point_fast(&self.fs.table(phi, self.beta), self.beta).summary
    }

    /// Whether (φ, β_op) counts as unstable by the criterion; one evaluation.
    pub fn counts(&self, phi: f64) -> bool {
        self.criterion.counts(&self.point(phi))
    }

    /// The dyadic cell of the edges (rad/s): the largest power of two not above
    /// `phi_tolerance`.
    pub fn cell(&self) -> f64 {
        2f64.powi(self.settings.phi_tolerance.log2().floor() as i32)
    }

    /// The edge of the tongue containing the counted point `inside`, on the side `dir`
    /// (−1 left, +1 right): march outward (steps growing from 2e-4·φ up to
    /// [`RegionSettings::max_edge_step`], so a stable gap that wide is never stepped over)
    /// to a point that does not count, then refine on the lattice (module docs). The
    /// window's end if the tongue reaches it.
    pub fn edge(&self, inside: f64, dir: f64) -> f64 {
        let limit = if dir < 0.0 { self.limits.lo } else { self.limits.hi };
        let mut lo = inside;
        let mut step = (inside * 2e-4).max(4.0 * self.settings.phi_tolerance);
        loop {
            let hi = lo + dir * step;
            if (hi - limit) * dir >= 0.0 {
                return if (limit - lo) * dir > 0.0 && !self.counts(limit) { self.refine(lo, limit) } else { limit };
            }
            if !self.counts(hi) {
                return self.refine(lo, hi);
            }
            lo = hi;
            step = (step * 1.6).min(self.settings.max_edge_step(lo));
        }
    }

    /// Refine a bracket between a counted and an uncounted point to the lattice cell of
    /// the crossing; the cell's end on the uncounted side.
    fn refine(&self, mut inside: f64, mut outside: f64) -> f64 {
        let cell = self.cell();
        loop {
            let (a, b) = (inside.min(outside), inside.max(outside));
            match split_point(a, b, cell) {
                Some(m) => {
                    if self.counts(m) {
                        inside = m;
                    } else {
                        outside = m;
                    }
                }
                None => {
                    let k = (a / cell).floor();
                    return if outside > inside { (k + 1.0) * cell } else { k * cell };
                }
            }
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

    /// Counted points of seed `index`'s tongue at β_op, and of its twins' (seeds of the
    /// same order whose whirls are in the same twin groups, [`super::centre`]): the centre
    /// search of every rank assignment of the group pair (a point where the pair has
    /// collided, and any counted point of another pair met on the way), and, where a
    /// search converged on a collided pair that does not count, the crest found by a short
    /// climb beside it. Made once per group pair and order.
    pub fn hits(&self, seeds: &[Seed], index: usize) -> Vec<Hit> {
        let seed = &seeds[index];
        let (i, j) = seed.pair;
        if i >= self.group_of.0.len() || j >= self.group_of.1.len() {
            return Vec::new();
        }
        let key = (self.group_of.0[i], self.group_of.1[j], seed.order);
        let cell = {
            let mut map = self.searched.lock().unwrap_or_else(|p| p.into_inner());
            map.entry(key).or_default().clone()
        };
        let found = cell.get_or_init(|| self.group_search(key));
        let rest = self.fs.speed == 0.0;
        // Points beyond the window stay: their tongue may reach into it.
        found
            .iter()
            .map(|h| {
                let seed = h.pair.and_then(|(a, b)| {
                    // At rest f_a + b_b = f_b + b_a: the seeds keep the pair once.
                    let pair = if rest && b < a { (b, a) } else { (a, b) };
                    seeds.iter().position(|x| x.pair == pair && x.order == key.2)
                });
                Hit { phi: h.phi, seed }
            })
            .collect()
    }

    /// The search of one group pair at one order (see [`Level::hits`]).
    fn group_search(&self, (gf, gb, order): GroupKey) -> Vec<GroupHit> {
        let Some(basis) = self.basis.as_ref() else { return Vec::new() };
        let (fm, bm) = (&self.groups.0[gf], &self.groups.1[gb]);
        let group = PairGroup {
            forward: fm.iter().map(|&m| self.whirls.0[m]).collect(),
            backward: bm.iter().map(|&m| self.whirls.1[m]).collect(),
            order,
        };
        let counts = |p: &PointSummary| self.criterion.counts(p);
        let mut out = Vec::new();
        for a in 0..group.assignments() {
            let (rf, rb) = group.ranks(a);
            let pair = Some((fm[rf], bm[rb]));
            let mut n = 0;
            let outcome = centre_search(self.fs, basis, self.settings, &group, a, self.beta, &counts, &mut n);
            self.add(n);
            out.extend(outcome.others.iter().map(|&(phi, b)| GroupHit {
                phi,
                pair: b.map(|b| {
                    let (rf, rb) = group.ranks(b);
                    (fm[rf], bm[rb])
                }),
            }));
            if let Some(phi) = outcome.own {
                out.push(GroupHit { phi, pair });
            } else if let Some((x, split)) = outcome.converged {
                // Collided (phase-locked: δ stays 0 on a side of x; the search may converge
                // at the edge of the collided interval) rather than passing through 0;
                // with damping every pair is split, locked or not.
                let locked = || {
                    [x - LOCK_STEP * self.settings.phi_tolerance, x + LOCK_STEP * self.settings.phi_tolerance]
                        .iter()
                        .any(|&phi| {
                            self.add(1);
                            detuning(self.fs, basis, &group, phi, self.beta).is_some_and(|d| d.deltas[a].abs() < LOCKED)
                        })
                };
                if split.abs() > SPLIT_TRIGGER && locked() {
                    let start = group.start(a);
                    let window = Interval::new(start * (1.0 - CENTRE_WINDOW), start * (1.0 + CENTRE_WINDOW));
                    let half = (CREST_SPAN * x).min(x - window.lo).min(window.hi - x);
                    // Climb the pair's own growth: the largest multiplier of the whole
                    // monodromy may belong to another, damped mode and be flat here.
                    let growth = |phi: f64| {
                        self.add(1);
                        detuning(self.fs, basis, &group, phi, self.beta).map_or(f64::NEG_INFINITY, |d| d.growths[a])
                    };
                    let crest = climb(growth, self.settings, x, half);
                    if let Some(c) = crest.filter(|&c| self.counts(c)) {
                        out.push(GroupHit { phi: c, pair });
                    }
                }
            }
        }
        out
    }

    /// The guard lattice points (1 + g)^n inside `window`, ascending.
    pub fn lattice(&self, window: Interval) -> Vec<f64> {
        let g = self.settings.guard_step;
        if g <= 0.0 || window.lo <= 0.0 {
            return Vec::new();
        }
        let base = g.ln_1p();
        let first = (window.lo.ln() / base).ceil() as i64;
        let last = (window.hi.ln() / base).floor() as i64;
        (first..=last).map(|n| lattice_point(g, n)).filter(|p| window.contains(*p)).collect()
    }

    /// Every tongue of the unstable set in `window` at β_op: from the hits of every seed
    /// whose search window ±[`CENTRE_WINDOW`] meets it (seeds of order up to the
    /// criterion's, in parallel), then from the guard lattice points no tongue covers.
    /// Sorted by position.
    pub fn scan(&self, seeds: &[Seed], window: Interval) -> Vec<Tongue> {
        let reach = |s: &Seed| Interval::new(s.phi * (1.0 - CENTRE_WINDOW), s.phi * (1.0 + CENTRE_WINDOW));
        let chosen: Vec<usize> = (0..seeds.len())
            .filter(|&i| seeds[i].order <= self.criterion.max_order && reach(&seeds[i]).overlaps(&window))
            .collect();
        let mut hits: Vec<Hit> = chosen.par_iter().flat_map_iter(|&i| self.hits(seeds, i)).collect();
        // Twins report their group's hits once each.
        hits.sort_by(|a, b| a.phi.total_cmp(&b.phi).then(a.seed.cmp(&b.seed)));
        hits.dedup();
        let mut tongues = self.tongues_of(seeds, &hits, &[]);
        let covered = |phi: f64, t: &[Tongue]| t.iter().any(|x| x.extent.contains(phi));
        let guard: Vec<Hit> = self
            .lattice(window)
            .into_par_iter()
            .filter(|&p| !covered(p, &tongues) && self.counts(p))
            .map(|phi| Hit { phi, seed: None })
            .collect();
        let more = self.tongues_of(seeds, &guard, &tongues);
        tongues.extend(more);
        tongues.retain(|t| t.extent.overlaps(&window));
        tongues.sort_by(|a, b| a.extent.lo.total_cmp(&b.extent.lo));
        tongues
    }

    /// The tongues through `hits` that are not inside `known`: the extent of each new one
    /// (in parallel), labelled by the seeds whose collision lies inside; hits inside a
    /// tongue already found add their labels to it.
    pub fn tongues_of(&self, seeds: &[Seed], hits: &[Hit], known: &[Tongue]) -> Vec<Tongue> {
        let mut sorted: Vec<Hit> = hits.to_vec();
        sorted.sort_by(|a, b| a.phi.total_cmp(&b.phi).then(a.seed.cmp(&b.seed)));
        let mut out: Vec<Tongue> = Vec::new();
        let mut pending: Vec<Hit> =
            sorted.into_iter().filter(|h| !known.iter().any(|t| t.extent.contains(h.phi))).collect();
        // Rounds: the extents of hits not yet covered, in parallel; a hit inside a new
        // extent is that tongue (its label is attached below).
        while !pending.is_empty() {
            // One hit per stretch that no extent covers: the first, and every later hit that
            // is farther than the largest edge-march step from the previous chosen one.
            let mut round: Vec<f64> = Vec::new();
            for h in &pending {
                if round.last().is_none_or(|&p| h.phi - p > self.settings.max_edge_step(p)) {
                    round.push(h.phi);
                }
            }
            let extents: Vec<(f64, Option<Interval>)> = round.par_iter().map(|&p| (p, self.extent(p))).collect();
            // Hits beyond the window are done with once their march was made: their
            // tongue's extent is clipped to the window and need not contain them.
            let mut done: Vec<f64> = Vec::new();
            for (p, e) in extents {
                if !self.limits.contains(p) {
                    done.push(p);
                }
                let Some(e) = e else { continue };
                if out.iter().any(|t| t.extent == e) {
                    continue;
                }
                let narrow = e.width() < self.criterion.min_tongue_width;
                out.push(Tongue {
                    extent: e,
                    inside: p,
                    labels: Vec::new(),
                    seeds: Vec::new(),
                    counted: !narrow,
                    ignored: narrow.then_some(Ignored::Narrow),
                });
            }
            pending.retain(|h| !out.iter().any(|t| t.extent.contains(h.phi)) && !done.contains(&h.phi));
        }
        let mut by_seed: Vec<&Hit> = hits.iter().filter(|h| h.seed.is_some()).collect();
        by_seed.sort_by(|a, b| a.seed.cmp(&b.seed).then(a.phi.total_cmp(&b.phi)));
        for h in by_seed {
            if let Some(i) = h.seed {
                if let Some(t) = out.iter_mut().find(|t| t.extent.contains(h.phi)) {
                    if !t.seeds.iter().any(|(j, _)| *j == i) {
                        t.seeds.push((i, h.phi));
                        t.labels.push((seeds[i].label.clone(), seeds[i].order));
                    }
                }
            }
        }
        out.sort_by(|a, b| a.extent.lo.total_cmp(&b.extent.lo));
        out
    }
}

impl Level<'_> {
    /// The tongues in `window` that are unstable by the tolerance but contain no point
    /// growing as fast as the criterion's `min_growth_rate` (none when it is 0): the scan
    /// of the same window without that floor, less every tongue that overlaps one of
    /// `counted`. Their evaluations are added to this probe's.
    pub fn slow_tongues(&self, seeds: &[Seed], window: Interval, counted: &[Tongue]) -> Vec<Tongue> {
        if self.criterion.min_growth_rate <= 0.0 {
            return Vec::new();
        }
        let raw = Criterion { min_growth_rate: 0.0, min_tongue_width: 0.0, ..self.criterion };
        let probe = Level::new(self.fs, self.settings, raw, self.beta, self.limits);
        let out = probe
            .scan(seeds, window)
            .into_iter()
            .filter(|t| !counted.iter().any(|c| c.counted && c.extent.overlaps(&t.extent)))
            .map(|t| Tongue { counted: false, ignored: Some(Ignored::SlowGrowth), ..t })
            .collect();
        self.add(probe.evaluations());
        out
    }
}

/// (1 + g)^n, computed the same way wherever it is asked for.
fn lattice_point(g: f64, n: i64) -> f64 {
    (n as f64 * g.ln_1p()).exp()
}

/// The lattice point of largest spacing (a power-of-two multiple of `cell`) strictly
/// inside (a, b); None when (a, b) lies inside one cell.
fn split_point(a: f64, b: f64, cell: f64) -> Option<f64> {
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
    use super::split_point;

    #[test]
    fn lattice_refinement_ends_in_the_crossing_cell_from_any_bracket() {
        // A crossing at x* = 1234.3: brackets of any size and offset end in [1234.25, 1234.375].
        let cell = 0.125;
        let x_star = 1234.3;
        for (a0, b0) in [(1230.0, 1240.0), (1234.01, 1234.99), (1200.3, 1234.31), (1234.29, 1300.0)] {
            let (mut a, mut b) = (a0, b0);
            while let Some(m) = split_point(a, b, cell) {
                if m < x_star {
                    a = m;
                } else {
                    b = m;
                }
            }
            let k = (a / cell).floor();
            assert_eq!((k * cell, (k + 1.0) * cell), (1234.25, 1234.375), "from ({a0}, {b0})");
        }
    }
}
