//! Tongue centres by multiplier detuning: a thin region that has drifted off its
//! predicted start is found in a few monodromy evaluations instead of a φ scan.
//!
//! At β = 0 the multipliers are μ = exp(λT), T = 2π/φ, so the pair of a seed — the
//! forward whirl λ_i = +jω_i and the backward whirl λ_j = −jω_j of B0 — coincide exactly
//! where (ω_i + ω_j)T = 2πk, the predicted start (Eq. 28; MODEL.md section 5). At a load
//! β > 0 the pair is identified among the monodromy's eigenvectors and the detuning
//! δ(φ) = arg(μ_i/μ_j) ∈ (−π, π] is zero at the tongue's centre, where the two
//! multipliers collide and leave the unit circle; dδ/dφ ≈ −2πk/φ. A secant iteration on δ
//! from the seed therefore lands inside the tongue however far the static and parametric
//! loads have moved it (the f1+b1 tongues of order 3–6 lie 2.3 % below their sums at
//! β = 0.3 on the paper's rotor), and however thin it is.
//!
//! Identification: in the complex coordinates of the reduced model a forward and a
//! backward whirl of the same bending mode share their shape q, so an eigenvector
//! w = [q̇; q] of the monodromy is matched to a mode by its shape overlap with the mode's q
//! and by its local frequency Im(qᴴq̇)/‖q‖², which separates forward from backward.

use super::critical::RegionSettings;
use super::seeds::Seed;
use crate::analysis::floquet::FloquetSystem;
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
const COLLIDED: f64 = 0.05;

/// Angle (rad) between a multiplier and its β = 0 position exp(jλT) at which the
/// identification score halves: loads move a multiplier by the drift of its frequency
/// times T, a few tenths of a radian at β = 0.3.
const ANGLE_MATCH: f64 = 0.5;

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
        let e = b0.eigen().ok()?;
        let s = e.S().column_vector();
        let u = e.U();
        let modes = (0..n)
            .map(|k| {
                let q: Vec<c64> = (half..n).map(|r| u[(r, k)]).collect();
                let norm = q.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt().max(f64::MIN_POSITIVE);
                (s[k].im, q.into_iter().map(|z| z / norm).collect())
            })
            .collect();
        Some(ModeBasis { modes, half })
    }

    /// The mode whose eigenvalue's imaginary part is nearest `im`.
    fn nearest(&self, im: f64) -> &(f64, Vec<c64>) {
        self.modes.iter().min_by(|a, b| (a.0 - im).abs().total_cmp(&(b.0 - im).abs())).expect("B0 has modes")
    }
}

/// The detuning of a seed's pair at (φ, β) and the stability verdict there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Detuning {
    /// δ = arg(μ_i/μ_j) (rad).
    pub delta: f64,
    /// max|μ| above the instability tolerance (the verdict of `FloquetSystem::point_fast`).
    pub unstable: bool,
}

/// δ and the verdict at (φ, β); one monodromy evaluation (plus an eigenvector solve).
/// None if the eigensolver fails.
pub fn detuning(fs: &FloquetSystem, basis: &ModeBasis, seed: &Seed, phi: f64, beta: f64) -> Option<Detuning> {
    let table = fs.table(phi, beta);
    let mono = table.monodromy(&fs.symmetry, beta);
    // The verdict exactly as `point_fast` gives it, from the same monodromy.
    let unstable = !fs.point_of(&table, &mono, beta).summary.stable;
    let e = mono.matrix.eigen().ok()?;
    let mu = e.S().column_vector();
    let w = e.U();
    let (n, h) = (mu.nrows(), basis.half);
    let period = 2.0 * PI / phi;
    let scores = |im: f64| -> Vec<f64> {
        let (lam, q) = basis.nearest(im);
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
    };
    let (si, sj) = (scores(seed.forward), scores(-seed.backward));
    let mut best = (0, 0, f64::NEG_INFINITY);
    for (a, x) in si.iter().enumerate() {
        for (b, y) in sj.iter().enumerate() {
            if a != b && x + y > best.2 {
                best = (a, b, x + y);
            }
        }
    }
    let delta = (mu[best.0] / mu[best.1]).arg();
    delta.is_finite().then_some(Detuning { delta, unstable })
}

/// An unstable φ of the seed's tongue at level β, by a secant iteration on δ(φ) from the
/// seed within ±[`CENTRE_WINDOW`]; None if the iteration converges on a stable φ (the
/// tongue does not reach the level) or does not converge in `centre_iterations`.
pub fn centre_search(
    fs: &FloquetSystem,
    basis: &ModeBasis,
    s: &RegionSettings,
    seed: &Seed,
    level: f64,
    count: &mut usize,
) -> Option<f64> {
    let (lo, hi) = (seed.phi * (1.0 - CENTRE_WINDOW), seed.phi * (1.0 + CENTRE_WINDOW));
    // dδ/dφ at β = 0: −(ω_i + ω_j)·2π/φ² = −2πk/φ.
    let slope0 = -2.0 * PI * seed.order as f64 / seed.phi;
    let mut eval = |phi: f64| {
        *count += 1;
        detuning(fs, basis, seed, phi, level)
    };
    // Inside the seed's own tongue its pair has collided: δ ≈ 0. An unstable point with a
    // large δ belongs to another pair's region (the seed can lie inside a neighbour).
    let own = |d: &Detuning| d.unstable && d.delta.abs() < COLLIDED;
    let (mut x0, d) = (seed.phi, eval(seed.phi)?);
    if own(&d) {
        return Some(x0);
    }
    let mut d0 = d.delta;
    let mut x1 = (x0 - d0 / slope0).clamp(lo, hi);
    for _ in 0..s.centre_iterations {
        if (x1 - x0).abs() < 1e-3 * s.phi_tolerance {
            break;
        }
        let d = eval(x1)?;
        if own(&d) {
            return Some(x1);
        }
        // The secant slope when it is plausible (same sign, within 4× of the β = 0 value;
        // a misidentified pair or a wrap of δ gives neither), else the β = 0 slope.
        let secant = (d.delta - d0) / (x1 - x0);
        let slope = if secant.is_finite() && secant / slope0 > 0.25 && secant / slope0 < 4.0 { secant } else { slope0 };
        x0 = x1;
        d0 = d.delta;
        x1 = (x1 - d0 / slope).clamp(lo, hi);
    }
    None
}
