//! The tongues of the unstable set at one level β_op, found from the seeds
//! (ω_i + ω_j)/k of every order up to the criterion's and from the guard lattice
//! ([`super::level`]), with edges that do not depend on where a search started.
//!
//! A seed's tongue is found by the centre search of its pair (and of its twins',
//! [`super::centre`]), made once per group pair and order; tongues no seed finds are
//! caught on the guard lattice. Each tongue's extent is the lattice-refined edges of
//! [`Level::extent`], and it is labelled by the seeds whose pair collides inside it.

use super::centre::{Converged, PairGroup, CENTRE_WINDOW};
use super::maximise::climb;
use super::seeds::Seed;
use super::Level;
use crate::analysis::floquet::PointSummary;
use crate::analysis::{Criterion, Interval};
use rayon::prelude::*;
use serde::Serialize;

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
/// The sides the lock test looks at, in [`LOCK_STEP`]s of `phi_tolerance`.
const LOCK_SIDES: [f64; 2] = [-1.0, 1.0];
/// |δ| (rad) below which a pair is phase-locked: round-off inside a collided interval.
const LOCKED: f64 = 1e-7;
/// Half-width of that crest search, relative to φ (9 rad/s at 1800 rad/s): the collided
/// interval of a damped order-2 tongue at β = 0.3 on the paper's rotor is 6 rad/s wide.
pub const CREST_SPAN: f64 = 5e-3;

/// Key of a group search: (forward group, backward group, order).
pub(super) type GroupKey = (usize, usize, usize);

/// A counted point of a tongue, and whether a seed's own pair has collided there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    /// φ (rad/s).
    pub phi: f64,
    /// Index of the seed whose pair collides here, if any.
    pub seed: Option<usize>,
}

/// One tongue of the unstable set at β_op.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
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

/// A counted point found by a group search: φ, and the (forward, backward) whirl indices
/// of the assignment whose pair collides there (None: another pair's tongue).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct GroupHit {
    phi: f64,
    pair: Option<(usize, usize)>,
}

impl Level<'_> {
    /// Counted points of seed `index`'s tongue at β_op, and of its twins' (seeds of the
    /// same order whose whirls are in the same twin groups, `super::centre`): the centre
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
        let rest = self.probe.system().paired();
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
        let tolerance = self.probe.settings().phi_tolerance;
        let mut out = Vec::new();
        for a in 0..group.assignments() {
            // An assignment not begun when the caller asks to stop is skipped (a group of
            // a high order holds many, each a centre search of its own).
            if self.probe.progress().cancelled() {
                break;
            }
            let (rf, rb) = group.ranks(a);
            let pair = Some((fm[rf], bm[rb]));
            let outcome = self.probe.centre_search(basis, &group, a, self.beta, &counts);
            out.extend(outcome.others.iter().map(|&(phi, b)| GroupHit {
                phi,
                pair: b.map(|b| {
                    let (rf, rb) = group.ranks(b);
                    (fm[rf], bm[rb])
                }),
            }));
            if let Some(phi) = outcome.own {
                out.push(GroupHit { phi, pair });
            } else if let Some(Converged { phi: x, split }) = outcome.converged {
                // Collided (phase-locked: δ stays 0 on a side of x; the search may converge
                // at the edge of the collided interval) rather than passing through 0;
                // with damping every pair is split, locked or not.
                let locked = || {
                    LOCK_SIDES.iter().map(|side| x + side * LOCK_STEP * tolerance).any(|phi| {
                        self.probe.detuning(basis, &group, phi, self.beta).is_some_and(|d| d.deltas[a].abs() < LOCKED)
                    })
                };
                if split.abs() > SPLIT_TRIGGER && locked() {
                    let start = group.start(a);
                    let window = Interval::new(start * (1.0 - CENTRE_WINDOW), start * (1.0 + CENTRE_WINDOW));
                    let half = (CREST_SPAN * x).min(x - window.lo).min(window.hi - x);
                    // Climb the pair's own growth: the largest multiplier of the whole
                    // monodromy may belong to another, damped mode and be flat here.
                    let growth = |phi: f64| {
                        self.probe.detuning(basis, &group, phi, self.beta).map_or(f64::NEG_INFINITY, |d| d.growths[a])
                    };
                    let crest = climb(growth, self.probe.settings(), x, half);
                    if let Some(c) = crest.filter(|&c| self.counts(c)) {
                        out.push(GroupHit { phi: c, pair });
                    }
                }
            }
        }
        out
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
        let progress = self.probe.progress();
        progress.extend(chosen.len() as u64);
        let mut hits: Vec<Hit> = chosen
            .par_iter()
            .flat_map_iter(|&i| {
                // A search not begun when the caller asks to stop is skipped.
                if progress.cancelled() {
                    return Vec::new();
                }
                let h = self.hits(seeds, i);
                progress.advance(1);
                h
            })
            .collect();
        // Twins report their group's hits once each.
        hits.sort_by(|a, b| a.phi.total_cmp(&b.phi).then(a.seed.cmp(&b.seed)));
        hits.dedup();
        let mut tongues = self.tongues_of(seeds, &hits, &[]);
        let covered = |phi: f64, t: &[Tongue]| t.iter().any(|x| x.extent.contains(phi));
        let lattice = self.lattice(window);
        progress.extend(lattice.len() as u64);
        let guard: Vec<Hit> = lattice
            .into_par_iter()
            .filter(|&p| {
                if progress.cancelled() {
                    return false;
                }
                let counted = !covered(p, &tongues) && self.counts(p);
                progress.advance(1);
                counted
            })
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
        // Rounds over the hits not yet covered. In a round, one hit per stretch that no
        // extent covers: the first, and every later hit that is farther than the largest
        // edge-march step from the previous chosen one. Their extents are marched in order
        // of φ (each extent's two edges in parallel), and a chosen hit inside an extent
        // this round already found is that tongue: one march per tongue, not one per hit
        // (docs/decisions.md, "One march per tongue").
        while !pending.is_empty() {
            let mut round: Vec<f64> = Vec::new();
            for h in &pending {
                if round.last().is_none_or(|&p| h.phi - p > self.probe.settings().edge_step.at(p)) {
                    round.push(h.phi);
                }
            }
            let progress = self.probe.progress();
            progress.extend(round.len() as u64);
            // Hits beyond the window are done with once their march was made: their
            // tongue's extent is clipped to the window and need not contain them.
            let mut done: Vec<f64> = Vec::new();
            for p in round {
                if out.iter().any(|t| t.extent.contains(p)) {
                    progress.advance(1);
                    continue;
                }
                let e = self.extent(p);
                progress.advance(1);
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

    /// The tongues in `window` that are unstable by the tolerance but contain no point
    /// growing as fast as the criterion's `min_growth_rate` (none when it is 0): the scan
    /// of the same window without that floor, less every tongue that overlaps one of
    /// `counted`. Their evaluations are counted by the same probe.
    pub fn slow_tongues(&self, seeds: &[Seed], window: Interval, counted: &[Tongue]) -> Vec<Tongue> {
        if self.criterion.min_growth_rate <= 0.0 {
            return Vec::new();
        }
        let raw = Criterion { min_growth_rate: 0.0, min_tongue_width: 0.0, ..self.criterion };
        let level = Level::new(self.probe, raw, self.beta, self.limits);
        level
            .scan(seeds, window)
            .into_iter()
            .filter(|t| !counted.iter().any(|c| c.counted && c.extent.overlaps(&t.extent)))
            .map(|t| Tongue { counted: false, ignored: Some(Ignored::SlowGrowth), ..t })
            .collect()
    }
}
