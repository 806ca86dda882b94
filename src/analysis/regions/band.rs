//! The stable band at β_op around an operating frequency φ_op: the interval containing φ_op
//! in which no tongue counts by the declared criterion, complete up to the criterion's
//! order.
//!
//! Each side is searched outward from φ_op by local work only: the guard lattice points
//! and the seeds (of every order up to the criterion's) whose search window reaches the
//! side are taken in order of the nearest φ they can report, until that φ lies beyond the
//! nearest counted tongue found so far. The band's edge is that tongue's lattice-refined
//! edge (`super::level`), the same number the catalogue of a range reports for it.

use super::seeds::Seed;
use super::tongues::{Hit, Ignored, Tongue};
use super::Level;
use super::CENTRE_WINDOW;
use crate::analysis::floquet::FloquetSystem;
use crate::analysis::modes::{ModesResult, Whirl};
use crate::analysis::Interval;
use rayon::prelude::*;
use serde::Serialize;

/// Searches evaluated together (in parallel) before the nearest tongue is updated: enough
/// to keep two threads busy, few enough that little work lands beyond the tongue.
const BATCH: usize = 8;

/// Two computations of the same tongue edge (rad/s) are the same edge when they differ by
/// at most this: a band's edges and a catalogue's are the same lattice-refined numbers
/// (`super::level`), so only round-off may separate them.
pub const SAME_EDGE: f64 = 1e-9;

/// The name of a bound that no catalogued tongue has: no seed's pair was identified in
/// the tongue (found by the guard lattice or beside a seed).
pub const UNLABELLED: &str = "unlabelled";

/// A catalogued tongue that may name a band's bound: the label and order k of a seed whose
/// pair collides in it (the catalogue's region of that seed), and its extent at β_op.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedTongue {
    /// The seed's whirl pair, e.g. `f1+r2`.
    pub label: String,
    /// Order k of its resonance.
    pub order: usize,
    /// The tongue's extent at β_op (rad/s).
    pub extent: Interval,
}

/// The side of φ_op a bound lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// The bound below the band (its tongue's upper edge is the band's lower edge).
    Below,
    /// The bound above the band (its tongue's lower edge is the band's upper edge).
    Above,
}

/// The one rule naming what bounds a band (used by `band`, the design report's page one
/// and its region table): among `tongues`, those whose edge facing the band (the upper
/// edge for the bound below, the lower edge for the bound above) equals `edge` within
/// [`SAME_EDGE`]; the lowest order k wins, equal orders by the label (byte order). The
/// name reads `label (k = k)`; None when no catalogued tongue has that edge.
pub fn bound_name(tongues: &[NamedTongue], side: Side, edge: f64) -> Option<String> {
    let facing = |t: &NamedTongue| match side {
        Side::Below => t.extent.hi,
        Side::Above => t.extent.lo,
    };
    tongues
        .iter()
        .filter(|t| (facing(t) - edge).abs() <= SAME_EDGE)
        .min_by(|a, b| a.order.cmp(&b.order).then_with(|| a.label.cmp(&b.label)))
        .map(|t| format!("{} (k = {})", t.label, t.order))
}

/// What is known of an unlabelled bound's tongue: the frequency of its unstable Floquet
/// exponent and the whirl frequency nearest to it.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct Unexplained {
    /// Where the exponent was taken: the tongue's counted point (rad/s).
    pub phi: f64,
    /// |Im λ| of the largest multiplier μ = e^{λT} there, folded into [0, φ/2]
    /// (rad/s): |arg μ|·φ/(2π).
    pub exponent_frequency: f64,
    /// The nearest whirl-frequency combination, `tag − m·φ` (or `tag`, m = 0): the whirl
    /// frequency ω folded by whole multiples m of φ nearest the exponent frequency.
    pub nearest: String,
    /// |ω − m·φ| of that combination (rad/s).
    pub nearest_frequency: f64,
}

/// Whirls per direction looked at for the nearest combination of an unlabelled bound.
const EXPLAIN_WHIRLS: usize = 8;

/// The unstable Floquet exponent's frequency at `phi` (β = `level`, reference DSTM path)
/// and the whirl frequency folded by multiples of φ nearest to it ([`Unexplained`]).
pub fn unexplained(fs: &FloquetSystem, full: &ModesResult, phi: f64, level: f64) -> Unexplained {
    let p = fs.point_dstm(phi, level, fs.settings.reference_steps);
    let arg = p
        .multipliers
        .iter()
        .max_by(|a, b| a[0].hypot(a[1]).total_cmp(&b[0].hypot(b[1])))
        .map_or(0.0, |m| m[1].atan2(m[0]));
    let nu = arg.abs() * phi / std::f64::consts::TAU;
    let mut best: Option<(String, f64, f64)> = None;
    for dir in [Whirl::Forward, Whirl::Backward] {
        for m in full.modes.iter().filter(|m| m.whirl == dir).take(EXPLAIN_WHIRLS) {
            // The fold of ω nearest ν: |ω − k·φ| for the k (≥ 0) nearest ω/φ and its
            // neighbours.
            let k0 = (m.frequency / phi).round();
            for k in [k0 - 1.0, k0, k0 + 1.0].into_iter().filter(|k| *k >= 0.0) {
                let folded = (m.frequency - k * phi).abs();
                if best.as_ref().is_none_or(|b| (folded - nu).abs() < (b.1 - nu).abs()) {
                    let name = if k == 0.0 { m.tag() } else { format!("{} − {k}·φ", m.tag()) };
                    best = Some((name, folded, k));
                }
            }
        }
    }
    let (nearest, nearest_frequency) = best.map_or_else(|| ("none".to_string(), f64::NAN), |b| (b.0, b.1));
    Unexplained { phi, exponent_frequency: nu, nearest, nearest_frequency }
}

/// What bounds a band on one side.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Bound {
    /// The end of the search window: no counted tongue before it.
    Window,
    /// A counted tongue.
    Tongue {
        /// Its edge facing φ_op (rad/s).
        edge: f64,
        /// A counted point inside it (rad/s).
        inside: f64,
        /// The lowest-order catalogued tongue with that edge ([`bound_name`]), or
        /// `unlabelled`.
        label: String,
        /// For an unlabelled bound: its exponent's frequency and the nearest whirl
        /// combination ([`unexplained`]); absent otherwise, and before the bound is named.
        #[serde(skip_serializing_if = "Option::is_none")]
        unexplained: Option<Unexplained>,
    },
}

/// The stable band around φ_op at β_op.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct Band {
    /// Operating frequency φ_op (rad/s).
    pub phi_op: f64,
    /// Level β_op (−).
    pub level: f64,
    /// The band [lo, hi] (rad/s), or None when φ_op itself counts as unstable.
    pub band: Option<Interval>,
    /// When φ_op is unstable: the tongue containing it (rad/s).
    pub containing: Option<Interval>,
    /// What bounds the band below: a tongue, or the window's end; None when φ_op is
    /// unstable (no band).
    pub left: Option<Bound>,
    /// What bounds the band above (as `left`).
    pub right: Option<Bound>,
    /// Tongues inside the band that the criterion ignores (narrower than its width floor).
    pub ignored: Vec<Tongue>,
    /// What the band guarantees, in words.
    pub guarantee: String,
    /// The largest max|μ| (−) among the points the band search evaluated at β_op inside
    /// the band (ends included): φ_op, the guard-lattice points it visited and the march
    /// and refinement steps on the stable side of each edge. None without a band.
    pub max_multiplier: Option<f64>,
    /// How many such points there were.
    pub sampled: usize,
    /// Monodromy evaluations used.
    pub evaluations: usize,
}

impl Band {
    /// Name both bounds by [`bound_name`] from the catalogued tongues `tongues`; a bound no
    /// catalogued tongue has is `unlabelled`, with `explain`'s account of it.
    pub fn name_bounds(&mut self, tongues: &[NamedTongue], explain: &dyn Fn(f64) -> Unexplained) {
        for (bound, side) in [(&mut self.left, Side::Below), (&mut self.right, Side::Above)] {
            if let Some(Bound::Tongue { edge, inside, label, unexplained }) = bound {
                match bound_name(tongues, side, *edge) {
                    Some(name) => {
                        *label = name;
                        *unexplained = None;
                    }
                    None => {
                        *label = UNLABELLED.to_string();
                        *unexplained = Some(explain(*inside));
                    }
                }
            }
        }
    }

    /// Whether the band ends at an end of the φ window searched (below or above) rather
    /// than at a tongue: its true extent is at least what the window shows, and may be
    /// wider.
    pub fn clipped(&self) -> bool {
        self.band.is_some() && [&self.left, &self.right].iter().any(|x| matches!(x, Some(Bound::Window)))
    }

    /// The width a widest-band objective counts (rad/s): what tongues bound, not what the
    /// window supplies. Each side bounded by a tongue counts its distance from φ_op; a
    /// side bounded by the window's end counts nothing; a band the window bounds on both
    /// sides (nothing unstable in the whole window) counts its whole width. Where φ_op is
    /// unstable, [`Band::signed_width`].
    pub fn counted_width(&self) -> f64 {
        let Some(b) = self.band else { return self.signed_width() };
        let tongue = |x: &Option<Bound>| matches!(x, Some(Bound::Tongue { .. }));
        match (tongue(&self.left), tongue(&self.right)) {
            (true, true) => b.width(),
            (true, false) => self.phi_op - b.lo,
            (false, true) => b.hi - self.phi_op,
            (false, false) => b.width(),
        }
    }

    /// The band's width (rad/s) if φ_op is stable; otherwise minus the distance from φ_op
    /// to the nearer edge of the tongue containing it (continuous across the transition,
    /// so an optimiser can climb out of a tongue).
    pub fn signed_width(&self) -> f64 {
        match (self.band, self.containing) {
            (Some(b), _) => b.width(),
            (None, Some(t)) => -(self.phi_op - t.lo).min(t.hi - self.phi_op),
            (None, None) => 0.0,
        }
    }
}

/// One search of a side: a guard lattice point or a seed.
#[derive(Debug, Clone, Copy)]
enum Search {
    Lattice(f64),
    Seed(usize),
}

/// The stable band around `phi_op` at the level of `level`, inside its window. `seeds`
/// are the seeds of the window (as the catalogue of that window takes them).
pub fn band_around(level: &Level<'_>, seeds: &[Seed], phi_op: f64) -> Band {
    let start = level.probe().evaluations();
    let criterion = *level.criterion();
    let mut out = Band {
        phi_op,
        level: level.beta(),
        band: None,
        containing: None,
        left: None,
        right: None,
        ignored: Vec::new(),
        guarantee: criterion.guarantee(level.beta()),
        max_multiplier: None,
        sampled: 0,
        evaluations: 0,
    };
    if level.counts(phi_op) {
        out.containing = level.extent(phi_op);
        out.evaluations = level.probe().evaluations() - start;
        return out;
    }
    let reach = |s: &Seed| Interval::new(s.phi * (1.0 - CENTRE_WINDOW), s.phi * (1.0 + CENTRE_WINDOW));
    let limits = level.limits();
    let relevant: Vec<usize> = (0..seeds.len())
        .filter(|&i| seeds[i].order <= criterion.max_order && reach(&seeds[i]).overlaps(&limits))
        .collect();
    // Seeds whose window contains φ_op serve both sides: searched once, first.
    let both: Vec<usize> = relevant.iter().copied().filter(|&i| reach(&seeds[i]).contains(phi_op)).collect();
    let progress = level.probe().progress();
    progress.extend(both.len() as u64);
    let shared: Vec<Hit> = both
        .par_iter()
        .flat_map_iter(|&i| {
            // A search not begun when the caller asks to stop is skipped.
            if progress.cancelled() {
                return Vec::new();
            }
            let h = level.hits(seeds, i);
            progress.advance(1);
            h
        })
        .collect();
    let ((left, left_ignored), (right, right_ignored)) = rayon::join(
        || side(level, seeds, &relevant, &shared, phi_op, -1.0),
        || side(level, seeds, &relevant, &shared, phi_op, 1.0),
    );
    let edge = |b: &Option<Bound>, fallback: f64| match b {
        Some(Bound::Tongue { edge, .. }) => *edge,
        _ => fallback,
    };
    let found = Interval::new(edge(&left, limits.lo), edge(&right, limits.hi));
    out.band = Some(found);
    // A side with no counted tongue before the window's end is bounded by the window.
    out.left = left.or(Some(Bound::Window));
    out.right = right.or(Some(Bound::Window));
    out.ignored = left_ignored.into_iter().chain(right_ignored).collect();
    // Tongues inside the band that grow too slowly to count are listed too (not the
    // bounding tongues, which count where they bound it).
    let bounds: Vec<Tongue> = [&out.left, &out.right]
        .into_iter()
        .filter_map(|b| match b {
            Some(Bound::Tongue { inside, .. }) => Some(Tongue {
                extent: Interval::new(*inside, *inside),
                inside: *inside,
                labels: Vec::new(),
                seeds: Vec::new(),
                counted: true,
                ignored: None,
            }),
            _ => None,
        })
        .collect();
    let slow = level.slow_tongues(seeds, found, &bounds);
    out.ignored.extend(slow.into_iter().filter(|t| t.extent.hi > found.lo && t.extent.lo < found.hi));
    out.ignored.sort_by(|a, b| a.extent.lo.total_cmp(&b.extent.lo));
    if let Some((largest, n)) = level.largest_inside(found) {
        out.max_multiplier = Some(largest);
        out.sampled = n;
    }
    out.evaluations = level.probe().evaluations() - start;
    out
}

/// The nearest counted tongue beyond φ_op on side `dir`, and the ignored tongues before it.
fn side(
    level: &Level<'_>,
    seeds: &[Seed],
    relevant: &[usize],
    shared: &[Hit],
    phi_op: f64,
    dir: f64,
) -> (Option<Bound>, Vec<Tongue>) {
    let limits = level.limits();
    // The key of a search: the nearest φ (beyond φ_op, on this side) it can report.
    let nearest = |s: &Seed| if dir > 0.0 { s.phi * (1.0 - CENTRE_WINDOW) } else { s.phi * (1.0 + CENTRE_WINDOW) };
    let ahead = |x: f64| (x - phi_op) * dir > 0.0;
    // Seeds whose window lies wholly on this side (those containing φ_op were searched
    // already, `shared`).
    let mut searches: Vec<(f64, Search)> = relevant
        .iter()
        .filter(|&&i| ahead(nearest(&seeds[i])))
        .map(|&i| (nearest(&seeds[i]), Search::Seed(i)))
        .collect();
    let window = if dir > 0.0 { Interval::new(phi_op, limits.hi) } else { Interval::new(limits.lo, phi_op) };
    searches.extend(level.lattice(window).into_iter().filter(|&p| ahead(p)).map(|p| (p, Search::Lattice(p))));
    // Nearest first; seeds before lattice points at equal keys, then by index.
    searches.sort_by(|a, b| {
        ((a.0 - phi_op) * dir).total_cmp(&((b.0 - phi_op) * dir)).then_with(|| order_of(&a.1).cmp(&order_of(&b.1)))
    });
    let mut hits: Vec<Hit> = shared.iter().copied().filter(|h| ahead(h.phi)).collect();
    let mut ignored: Vec<Tongue> = Vec::new();
    let mut next = 0;
    loop {
        let candidate = |hits: &[Hit], ignored: &[Tongue]| {
            hits.iter()
                .filter(|h| ahead(h.phi) && !ignored.iter().any(|t| t.extent.contains(h.phi)))
                .min_by(|a, b| ((a.phi - phi_op) * dir).total_cmp(&((b.phi - phi_op) * dir)))
                .copied()
        };
        let best = candidate(&hits, &ignored);
        let before = |key: f64| best.is_none_or(|b| (key - phi_op) * dir < (b.phi - phi_op) * dir);
        let batch: Vec<Search> =
            searches[next..].iter().take_while(|(k, _)| before(*k)).take(BATCH).map(|(_, s)| *s).collect();
        if !batch.is_empty() {
            next += batch.len();
            let progress = level.probe().progress();
            progress.extend(batch.len() as u64);
            let found: Vec<Vec<Hit>> = batch
                .par_iter()
                .map(|s| {
                    if progress.cancelled() {
                        return Vec::new();
                    }
                    let found = match *s {
                        Search::Lattice(p) => {
                            if level.counts(p) {
                                vec![Hit { phi: p, seed: None }]
                            } else {
                                Vec::new()
                            }
                        }
                        Search::Seed(i) => level.hits(seeds, i),
                    };
                    progress.advance(1);
                    found
                })
                .collect();
            hits.extend(found.into_iter().flatten().filter(|h| ahead(h.phi)));
            continue;
        }
        // Every search that could report a nearer point has been made.
        let Some(hit) = best else { return (None, ignored) };
        let criterion = level.criterion();
        let labels = |extent: &Interval| {
            let mut v: Vec<(String, usize)> = Vec::new();
            let mut inside: Vec<usize> =
                hits.iter().filter_map(|h| h.seed.filter(|_| extent.contains(h.phi))).collect();
            inside.sort_unstable();
            inside.dedup();
            v.extend(inside.into_iter().map(|i| (seeds[i].label.clone(), seeds[i].order)));
            v
        };
        let extent = if criterion.min_tongue_width > 0.0 {
            level.extent(hit.phi)
        } else {
            // Only the edge facing φ_op is needed.
            let edge = level.edge(hit.phi, -dir);
            let reaches = if dir > 0.0 { edge < limits.hi } else { edge > limits.lo };
            reaches.then(|| {
                if dir > 0.0 {
                    Interval::new(edge, hit.phi.min(limits.hi))
                } else {
                    Interval::new(hit.phi.max(limits.lo), edge)
                }
            })
        };
        // The nearest tongue lies beyond the window: the band ends at the window.
        let Some(extent) = extent else { return (None, ignored) };
        let narrow = extent.width() < criterion.min_tongue_width;
        let tongue = Tongue {
            extent,
            inside: hit.phi,
            labels: labels(&extent),
            seeds: Vec::new(),
            counted: !narrow,
            ignored: narrow.then_some(Ignored::Narrow),
        };
        if !tongue.counted {
            ignored.push(tongue);
            continue;
        }
        let edge = if dir > 0.0 { extent.lo } else { extent.hi };
        return (Some(Bound::Tongue { edge, inside: hit.phi, label: tongue.label(), unexplained: None }), ignored);
    }
}

fn order_of(s: &Search) -> (u8, usize) {
    match s {
        Search::Seed(i) => (0, *i),
        Search::Lattice(_) => (1, 0),
    }
}
