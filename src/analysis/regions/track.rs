//! Region boundaries at a load β other than the catalogue's level, by marching and
//! bisection, and their continuation from the onset upward.

use super::bisect::{bisect, march, March, Split};
use super::Probe;
use crate::analysis::Interval;
use serde::Serialize;

/// A tracked boundary at one load: the region's φ interval at β.
///
/// Recorded in outputs as `{"beta", "left", "right"}`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
#[serde(into = "EdgesRecord")]
pub struct Edges {
    /// β (−).
    pub beta: f64,
    /// [φ_l, φ_r] at β (rad/s).
    pub phi: Interval,
}

/// The output form of [`Edges`].
#[derive(Serialize, serde::Deserialize)]
struct EdgesRecord {
    beta: f64,
    left: f64,
    right: f64,
}

impl From<Edges> for EdgesRecord {
    fn from(e: Edges) -> EdgesRecord {
        EdgesRecord { beta: e.beta, left: e.phi.lo, right: e.phi.hi }
    }
}

/// Where a tracked level looks for its inside point when the predicted centre is not
/// inside: at these multiples of the last width, on both sides.
const BESIDE: [f64; 4] = [0.25, 0.5, 1.0, 2.0];

impl Probe<'_> {
    /// The edge of the unstable set at load β next to `inside` (unstable) on the side
    /// `dir` (−1 left, +1 right): march outward (`march`) until stable, then bisect to
    /// `phi_tolerance`; the final bracket's midpoint (rad/s). A march that would step to
    /// φ ≤ 0 ends at the smallest positive φ.
    pub fn edge(&self, inside: f64, beta: f64, dir: f64) -> f64 {
        let s = self.settings();
        let test = |phi: f64| self.unstable(phi, beta);
        let limit = if dir < 0.0 { 0.0 } else { f64::INFINITY };
        match march(s, inside, dir, limit, test) {
            March::Crossed(bracket) => bisect(bracket, Split::Halves(s.phi_tolerance), test).interval().centre(),
            March::Limit(_) => f64::MIN_POSITIVE,
        }
    }

    /// Both edges at load β of the region containing φ_in (unstable there) (rad/s).
    pub fn edges(&self, phi_in: f64, beta: f64) -> Interval {
        let left = self.edge(phi_in, beta, -1.0);
        Interval::new(left, self.edge(phi_in, beta, 1.0))
    }

    /// Boundary tracking by predictor–corrector continuation from the onset up to β_max:
    /// at each level the edges are predicted by linear extrapolation of the last two levels
    /// (the midpoint of the prediction is the inside point) and corrected by
    /// [`Probe::edges`].
    pub fn track(&self, start: f64, onset: f64, beta_max: f64) -> Vec<Edges> {
        let s = self.settings();
        let mut out: Vec<Edges> = Vec::new();
        let levels = s.tracking_levels.max(1);
        for k in 1..=levels {
            let beta = onset + (beta_max - onset) * k as f64 / levels as f64;
            let centre = match out.len() {
                0 => start,
                1 => out[0].phi.centre(),
                n => {
                    let (p, q) = (&out[n - 2], &out[n - 1]);
                    q.phi.centre() + (q.phi.centre() - p.phi.centre()) * (beta - q.beta) / (q.beta - p.beta)
                }
            };
            // The predicted centre must be inside; else look beside it (a thin region that
            // tilts can slip past a linear prediction) at ±¼, ½, 1 and 2 of the last width,
            // then fall back to the start, then give up.
            let width = out.last().map_or(4.0 * s.phi_tolerance, |e| e.phi.width().max(4.0 * s.phi_tolerance));
            let beside = BESIDE.into_iter().flat_map(|f| [centre - f * width, centre + f * width]);
            let inside = std::iter::once(centre).chain(beside).chain([start]).find(|&phi| self.unstable(phi, beta));
            match inside {
                Some(phi) => out.push(Edges { beta, phi: self.edges(phi, beta) }),
                None => break,
            }
        }
        out
    }
}
