//! Region boundaries at a load β other than the catalogue's level, by marching and
//! bisection, and their continuation from the onset upward.

use super::{Edges, RegionSettings};
use crate::analysis::floquet::FloquetSystem;

/// Whether (φ, β) is unstable (max|μ| above the tolerance), from a fresh per-φ table;
/// counts one evaluation.
pub fn unstable_at(fs: &FloquetSystem, phi: f64, beta: f64, count: &mut usize) -> bool {
    *count += 1;
    super::critical::unstable(fs, &fs.table(phi, beta), beta)
}

/// The edge of the unstable set at level β next to `inside` (unstable) on the side
/// `dir` (−1 left, +1 right): march outward with growing steps (at most
/// [`RegionSettings::max_edge_step`], so a stable gap that wide between two tongues is
/// never stepped over) until stable, then bisect to `phi_tolerance`.
pub fn edge(fs: &FloquetSystem, s: &RegionSettings, inside: f64, beta: f64, dir: f64, count: &mut usize) -> f64 {
    let mut lo = inside;
    let mut step = (lo * 2e-4).max(4.0 * s.phi_tolerance);
    let mut hi = lo + dir * step;
    while unstable_at(fs, hi, beta, count) {
        lo = hi;
        step = (step * 1.6).min(s.max_edge_step(lo));
        hi = lo + dir * step;
        if hi <= 0.0 {
            return f64::MIN_POSITIVE;
        }
    }
    let (mut inside, mut outside) = (lo, hi);
    while (outside - inside).abs() > s.phi_tolerance {
        let mid = 0.5 * (inside + outside);
        if unstable_at(fs, mid, beta, count) {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    0.5 * (inside + outside)
}

/// Both edges at level β of the region containing φ_in (unstable there).
pub fn edges_at(fs: &FloquetSystem, s: &RegionSettings, phi_in: f64, beta: f64, count: &mut usize) -> Edges {
    Edges { beta, left: edge(fs, s, phi_in, beta, -1.0, count), right: edge(fs, s, phi_in, beta, 1.0, count) }
}

/// Boundary tracking by predictor–corrector continuation from the onset upward: at each
/// level the edges are predicted by linear extrapolation of the last two levels (the
/// midpoint of the prediction is the inside point) and corrected by [`edge`].
pub fn track(
    fs: &FloquetSystem,
    s: &RegionSettings,
    start: f64,
    onset: f64,
    beta_max: f64,
    count: &mut usize,
) -> Vec<Edges> {
    let mut out: Vec<Edges> = Vec::new();
    let levels = s.tracking_levels.max(1);
    for k in 1..=levels {
        let beta = onset + (beta_max - onset) * k as f64 / levels as f64;
        let centre = match out.len() {
            0 => start,
            1 => 0.5 * (out[0].left + out[0].right),
            n => {
                let (p, q) = (&out[n - 2], &out[n - 1]);
                let c = |e: &Edges| 0.5 * (e.left + e.right);
                c(q) + (c(q) - c(p)) * (beta - q.beta) / (q.beta - p.beta)
            }
        };
        // The predicted centre must be inside; else look beside it (a thin region that
        // tilts can slip past a linear prediction) at ±¼, ½, 1 and 2 of the last width,
        // then fall back to the start, then give up.
        let width = out.last().map_or(4.0 * s.phi_tolerance, |e| (e.right - e.left).max(4.0 * s.phi_tolerance));
        let beside = [0.25, 0.5, 1.0, 2.0].into_iter().flat_map(|f| [centre - f * width, centre + f * width]);
        let inside =
            std::iter::once(centre).chain(beside).chain([start]).find(|&phi| unstable_at(fs, phi, beta, count));
        match inside {
            Some(phi) => out.push(edges_at(fs, s, phi, beta, count)),
            None => break,
        }
    }
    out
}
