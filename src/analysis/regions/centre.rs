//! Tongue centres by multiplier detuning: a thin region that has drifted off its
//! predicted start is found in a few monodromy evaluations instead of a φ scan.
//!
//! At β = 0 the multipliers are μ = exp(λT), T = 2π/φ, so the pair of a seed — the
//! forward whirl λ_i = +jω_i and the backward whirl λ_j = −jω_j of B0 — coincide exactly
//! where (ω_i + ω_j)T = 2πk, the predicted start (Eq. 28; the sum-type combination
//! resonances of section 5 of the paper). At a load β > 0 the pair is identified among
//! the monodromy's eigenvectors and the detuning δ(φ) = arg(μ_i/μ_j) ∈ (−π, π] is zero at
//! the tongue's centre, where the two multipliers collide and leave the unit circle;
//! dδ/dφ ≈ −2πk/φ. A secant iteration on δ from the seed therefore lands inside the
//! tongue however far the static and parametric loads have moved it (the f1+b1 tongues
//! of order 3–6 lie 2.3 % below their sums at β = 0.3 on the paper's rotor), and however
//! thin it is.
//!
//! Identification: in the complex coordinates of the reduced model a forward and a
//! backward whirl of the same bending mode share their shape q, so an eigenvector
//! w = [q̇; q] of the monodromy is matched to a mode by its shape overlap with the mode's q,
//! by its local frequency Im(qᴴq̇)/‖q‖², which separates forward from backward, and by the
//! multiplier's position against exp(λT). The eigenvectors are matched to every whirl of
//! B0 at once, one to one, the best-scoring match first: an eigenvector is one whirl's.
//! Beside and inside a pair's collision its two eigenvectors mix the two whirls, whose
//! shape and local frequency then match either one poorly (a mixture's local frequency can
//! lie anywhere); matched member by member, the pair's backward member was once taken
//! from a foreign whirl whose multiplier sat 0.15 rad away (docs/decisions.md, "A seed's
//! pair"). That eigenvector matches its own whirl far better, which claims it first.
//!
//! **Twins.** Whirls of one direction within [`TWIN`] of each other (the r₁/r₂ and
//! s₁/s₂ modes of two rings on one circuit, 0.2 % apart) mix under the load: their
//! eigenvectors cannot be told apart by shape. Such whirls form a group; the group's
//! multipliers are the best-matching eigenvectors for its members, ranked by their angle
//! (continuity in φ, not shape), and the k-th member takes the k-th. A seed of a group
//! pair searches every assignment of the groups' ranks, so each twin tongue is found by
//! its own secant instead of both landing in the same one.

use super::Probe;
use crate::analysis::floquet::{FloquetSystem, PointSummary};
use faer::c64;
use std::f64::consts::PI;

/// Relative half-width of the φ window the centre search may move in: drifts up to a few
/// per cent are seen at β = 0.3 and grow like β².
pub const CENTRE_WINDOW: f64 = 0.1;
/// Frequency mismatch (relative to the mode's frequency) at which an eigenvector's
/// identification score halves. Generous: the local frequency is read at t = 0, where the
/// load is at its peak α + β, and the first bending whirls soften by a third at β = 0.3;
/// its job is to tell a forward whirl from the backward one of the same shape.
const FREQUENCY_MATCH: f64 = 0.5;

/// |δ| (rad) below which an unstable point is inside the seed's own tongue.
pub const COLLIDED: f64 = 0.05;

/// Angle (rad) between a multiplier and its β = 0 position exp(jλT) at which the
/// identification score halves: loads move a multiplier by the drift of its frequency
/// times T, a few tenths of a radian at β = 0.3.
const ANGLE_MATCH: f64 = 0.5;

/// Whirls of one direction closer than this (relative) form a twin group.
pub const TWIN: f64 = 0.01;

/// The whirl modes of B0: eigenvalue imaginary part and the normalised shape q.
#[derive(Debug, Clone)]
pub struct ModeBasis {
    modes: Vec<(f64, Vec<c64>)>,
    half: usize,
}

impl ModeBasis {
    /// From the eigenvectors of B0; None if the eigensolver fails.
    pub fn new(fs: &FloquetSystem) -> Option<ModeBasis> {
        let b0 = &fs.system.b0;
        let n = b0.nrows();
        let half = n / 2;
        let e = crate::linalg::seq::eigen(b0.as_ref()).ok()?;
        let (s, u) = (&e.values, &e.vectors);
        let modes: Vec<(f64, Vec<c64>)> = (0..n)
            .map(|k| {
                let q: Vec<c64> = (half..n).map(|r| u[(r, k)]).collect();
                let norm = q.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt().max(f64::MIN_POSITIVE);
                (s[k].im, q.into_iter().map(|z| z / norm).collect())
            })
            .collect();
        if modes.is_empty() {
            return None;
        }
        Some(ModeBasis { modes, half })
    }

    /// The index of the mode whose eigenvalue's imaginary part is nearest `im`.
    fn nearest(&self, im: f64) -> usize {
        let mut best = 0;
        for (k, m) in self.modes.iter().enumerate() {
            if (m.0 - im).abs() < (self.modes[best].0 - im).abs() {
                best = k;
            }
        }
        best
    }
}

/// The twin groups of an ascending list of whirl frequencies: runs of neighbours closer
/// than [`TWIN`] (relative), as index lists.
pub fn twin_groups(freqs: &[f64]) -> Vec<Vec<usize>> {
    let mut out: Vec<Vec<usize>> = Vec::new();
    for (i, &w) in freqs.iter().enumerate() {
        match out.last_mut() {
            Some(g) if (w - freqs[*g.last().unwrap_or(&i)]).abs() <= TWIN * w.abs() => g.push(i),
            _ => out.push(vec![i]),
        }
    }
    out
}

/// A pair of whirl groups (forward frequencies ω_i, backward ω_j, each ascending, rad/s)
/// whose combinations (ω_i + ω_j)/k are searched together at one order k.
#[derive(Debug, Clone, PartialEq)]
pub struct PairGroup {
    /// Forward whirl frequencies of the group (rad/s), ascending.
    pub forward: Vec<f64>,
    /// Backward whirl frequencies (rad/s), ascending.
    pub backward: Vec<f64>,
    /// Order k of the combination resonance (−): each assignment starts at (ω_i + ω_j)/k.
    pub order: usize,
}

impl PairGroup {
    /// Number of rank assignments (forward member, backward member).
    pub fn assignments(&self) -> usize {
        self.forward.len() * self.backward.len()
    }

    /// The (forward rank, backward rank) of assignment `a`.
    pub fn ranks(&self, a: usize) -> (usize, usize) {
        (a / self.backward.len(), a % self.backward.len())
    }

    /// The predicted start of assignment `a`, (ω_i + ω_j)/k (rad/s).
    pub fn start(&self, a: usize) -> f64 {
        let (f, b) = self.ranks(a);
        (self.forward[f] + self.backward[b]) / self.order as f64
    }
}

/// The detunings of a pair group's assignments at (φ, β) and the point's summary there.
#[derive(Debug, Clone, PartialEq)]
pub struct Detuning {
    /// δ = arg(μ_i/μ_j) (rad) of each assignment.
    pub deltas: Vec<f64>,
    /// ln|μ_i| − ln|μ_j| of each assignment: the split of a collided pair.
    pub splits: Vec<f64>,
    /// max(ln|μ_i|, ln|μ_j|) of each assignment: the pair's own growth per period.
    pub growths: Vec<f64>,
    /// The point's summary, exactly as `FloquetSystem::point_fast` gives it.
    pub point: PointSummary,
}

impl Probe<'_> {
    /// The detunings of a pair group and the point at (φ, β); one evaluation (plus an
    /// eigenvector solve). None if the eigensolver fails.
    pub fn detuning(&self, basis: &ModeBasis, group: &PairGroup, phi: f64, beta: f64) -> Option<Detuning> {
        self.count();
        detuning(self.system(), basis, group, phi, beta)
    }
}

/// The detunings and the point at (φ, β) (see [`Probe::detuning`]).
fn detuning(fs: &FloquetSystem, basis: &ModeBasis, group: &PairGroup, phi: f64, beta: f64) -> Option<Detuning> {
    let table = fs.table(phi, beta);
    let mono = table.monodromy(&fs.symmetry, beta);
    // The verdict exactly as `point_fast` gives it, from the same monodromy.
    let point = fs.point_of(&table, &mono, beta).summary;
    let e = crate::linalg::seq::eigen(mono.matrix.as_ref()).ok()?;
    let (mu, w) = (&e.values, &e.vectors);
    let (n, h) = (mu.len(), basis.half);
    let period = 2.0 * PI / phi;
    // The score of every eigenvector (columns) for every mode of B0 (rows).
    let scores: Vec<Vec<f64>> = basis
        .modes
        .iter()
        .map(|(lam, q)| {
            let lam = *lam;
            (0..n)
                .map(|c| {
                    let (mut overlap, mut cross, mut norm) = (c64::new(0.0, 0.0), c64::new(0.0, 0.0), 0.0);
                    for r in 0..h {
                        let (qd, qq) = (w[(r, c)], w[(h + r, c)]);
                        overlap += q[r].conj() * qq;
                        cross += qq.conj() * qd;
                        norm += qq.norm_sqr();
                    }
                    if norm <= 0.0 {
                        return 0.0;
                    }
                    let shape = overlap.norm() / norm.sqrt();
                    let mismatch = (cross.im / norm - lam) / (FREQUENCY_MATCH * lam.abs().max(1.0));
                    // Where the multiplier sits against where β = 0 puts it, exp(jλT).
                    let turn = (mu[c] * c64::cis(-lam * period)).arg() / ANGLE_MATCH;
                    shape / ((1.0 + mismatch * mismatch) * (1.0 + turn * turn))
                })
                .collect()
        })
        .collect();
    // Modes and eigenvectors matched one to one, the best-scoring match first (module
    // docs): the eigenvector of each mode.
    let mut matches: Vec<(f64, usize, usize)> = (0..scores.len())
        .flat_map(|m| (0..n).map(move |c| (m, c)))
        .map(|(m, c)| (if scores[m][c].is_nan() { 0.0 } else { scores[m][c] }, m, c))
        .collect();
    matches.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let mut owned: Vec<Option<usize>> = vec![None; scores.len()];
    let mut taken = vec![false; n];
    for (_, m, c) in matches {
        if owned[m].is_none() && !taken[c] {
            owned[m] = Some(c);
            taken[c] = true;
        }
    }
    // The group's eigenvectors: its members' own; then ranked by angle against the group's
    // mean frequency, in the direction of its whirl.
    let choose = |freqs: &[f64], sign: f64| -> Option<Vec<usize>> {
        let mut chosen = Vec::new();
        for &wm in freqs {
            chosen.push(owned[basis.nearest(sign * wm)]?);
        }
        let mean = freqs.iter().sum::<f64>() / freqs.len() as f64;
        let angle = |c: usize| sign * (mu[c] * c64::cis(-sign * mean * period)).arg();
        chosen.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
        Some(chosen)
    };
    let fwd = choose(&group.forward, 1.0)?;
    let bwd = choose(&group.backward, -1.0)?;
    let mut deltas = Vec::with_capacity(group.assignments());
    let mut splits = Vec::with_capacity(group.assignments());
    let mut growths = Vec::with_capacity(group.assignments());
    for a in 0..group.assignments() {
        let (f, b) = group.ranks(a);
        let (mi, mj) = (mu[fwd[f]], mu[bwd[b]]);
        deltas.push((mi / mj).arg());
        let (gi, gj) = (mi.norm().ln(), mj.norm().ln());
        splits.push(gi - gj);
        growths.push(gi.max(gj));
    }
    // The multipliers are those of the scaled product: add its scale to the growths.
    growths.iter_mut().for_each(|g| *g += mono.log_scale);
    deltas.iter().all(|d| d.is_finite()).then_some(Detuning { deltas, splits, growths, point })
}

/// What the centre search of one assignment found at the level.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct CentreOutcome {
    /// A counted point where the assignment's pair has collided (|δ| below `COLLIDED`):
    /// a point of its own tongue.
    pub own: Option<f64>,
    /// Counted points met on the way that belong to another tongue: φ (rad/s) and the
    /// group assignment whose pair has collided there, if any (a twin's tongue), else None
    /// (another pair's).
    pub others: Vec<(f64, Option<usize>)>,
    /// Where the secant converged on δ ≈ 0 without a counted point.
    pub converged: Option<Converged>,
}

/// Where a centre search converged on δ ≈ 0 without a counted point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Converged {
    /// φ (rad/s).
    pub phi: f64,
    /// The pair's split ln|μ_i| − ln|μ_j| there: well above round-off, the pair has
    /// collided and left the circle, but less than the criterion asks, or been held inside
    /// it by damping; its tongue's crest may lie beside this point.
    pub split: f64,
}

impl Probe<'_> {
    /// Points of assignment `a`'s tongue at level β, by a secant iteration on its δ(φ)
    /// from its predicted start within ±[`CENTRE_WINDOW`]. `counts` is the declared
    /// criterion on a point. The search stops at the first counted point where the pair
    /// has collided, when the iteration converges (`converged`), or after
    /// `centre_iterations` steps (or an eigensolver failure) with nothing found.
    pub fn centre_search(
        &self,
        basis: &ModeBasis,
        group: &PairGroup,
        a: usize,
        level: f64,
        counts: &dyn Fn(&PointSummary) -> bool,
    ) -> CentreOutcome {
        let s = self.settings();
        let mut out = CentreOutcome::default();
        let start = group.start(a);
        let (lo, hi) = (start * (1.0 - CENTRE_WINDOW), start * (1.0 + CENTRE_WINDOW));
        // dδ/dφ at β = 0: −(ω_i + ω_j)·2π/φ² = −2πk/φ.
        let slope0 = -2.0 * PI * group.order as f64 / start;
        let eval = |phi: f64, out: &mut CentreOutcome| {
            let d = self.detuning(basis, group, phi, level)?;
            // Inside the pair's own tongue it has collided: δ ≈ 0. A counted point with a
            // large δ belongs to another pair's region (the seed can lie inside a
            // neighbour). Twins' tongues lie closer in δ than COLLIDED: the collided pair is
            // the assignment whose δ is the smallest of the group's there.
            if counts(&d.point) {
                let nearest = (0..d.deltas.len())
                    .min_by(|&x, &y| d.deltas[x].abs().total_cmp(&d.deltas[y].abs()))
                    .filter(|&x| d.deltas[x].abs() < COLLIDED);
                if nearest == Some(a) {
                    out.own = Some(phi);
                } else {
                    out.others.push((phi, nearest));
                }
            }
            Some((d.deltas[a], d.splits[a]))
        };
        let Some(d) = eval(start, &mut out) else { return out };
        if out.own.is_some() {
            return out;
        }
        let (mut x0, mut d0) = (start, d);
        let mut x1 = (x0 - d0.0 / slope0).clamp(lo, hi);
        for _ in 0..s.centre_iterations {
            if (x1 - x0).abs() < 1e-3 * s.phi_tolerance {
                out.converged = Some(Converged { phi: x0, split: d0.1 });
                return out;
            }
            let Some(d) = eval(x1, &mut out) else { return out };
            if out.own.is_some() {
                return out;
            }
            // The secant slope when it is plausible (same sign, within 4× of the β = 0
            // value; a misidentified pair or a wrap of δ gives neither), else the β = 0
            // slope.
            let secant = (d.0 - d0.0) / (x1 - x0);
            let slope =
                if secant.is_finite() && secant / slope0 > 0.25 && secant / slope0 < 4.0 { secant } else { slope0 };
            x0 = x1;
            d0 = d;
            x1 = (x1 - d0.0 / slope).clamp(lo, hi);
        }
        if (x1 - x0).abs() < 1e-3 * s.phi_tolerance {
            out.converged = Some(Converged { phi: x0, split: d0.1 });
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::twin_groups;

    #[test]
    fn twins_are_runs_of_close_whirls() {
        // Table 3's forward whirls: r1/r2 and s1/s2 are twins, the bending whirls are not.
        let f = [398.5, 879.1, 880.9, 1903.8, 2605.9, 2607.4, 4901.8, 6856.4];
        assert_eq!(twin_groups(&f), vec![vec![0], vec![1, 2], vec![3], vec![4, 5], vec![6], vec![7]]);
    }
}
