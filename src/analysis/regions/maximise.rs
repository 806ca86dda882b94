//! A one-dimensional maximiser for the tip of a region and the crest of a weak tongue.

use super::RegionSettings;

/// First step of the climb, relative to φ: below the shift of a tip from its seed (~1e-4
/// relative on the paper's problems), so the climb starts on the tip's own dome.
pub const CLIMB_STEP: f64 = 2e-5;

/// The local maximum of `g` nearest `from` within ±`half_width`: uphill from `from` with
/// doubling steps (first [`CLIMB_STEP`]·φ, at most a quarter of the window) until `g`
/// falls, then a parabola through the bracketing triple, or a golden-section step where
/// the parabola is no help, until the bracket is below `tip_tolerance`·φ or
/// `tip_iterations` steps are spent. None if the climb leaves the window.
///
/// Brent's minimiser (argmin's `BrentOpt`) does the second part, but it cannot start from
/// a known interior point: it would spend evaluations re-finding the bracket's best.
pub fn climb(mut g: impl FnMut(f64) -> f64, s: &RegionSettings, from: f64, half_width: f64) -> Option<f64> {
    let h = (CLIMB_STEP * from.abs()).min(0.25 * half_width);
    let (gm, g0, gp) = (g(from - h), g(from), g(from + h));
    // The bracketing triple (a, b, c), a < b < c, g(b) ≥ g(a), g(c).
    let (mut a, mut b, mut c) = ((from - h, gm), (from, g0), (from + h, gp));
    if gp > g0 || gm > g0 {
        let dir = if gp >= gm { 1.0 } else { -1.0 };
        let (mut prev, mut here) = (b, if dir > 0.0 { c } else { a });
        let mut step = h;
        let next = loop {
            step *= 2.0;
            // The last step stops at the window's edge; a climb already there has left it.
            let x = (here.0 + dir * step).clamp(from - half_width, from + half_width);
            if x == here.0 {
                return None;
            }
            let next = (x, g(x));
            if next.1 < here.1 {
                break next;
            }
            (prev, here) = (here, next);
        };
        (a, b, c) = if dir > 0.0 { (prev, here, next) } else { (next, here, prev) };
    }
    let tolerance = s.tip_tolerance * from.abs();
    let golden = (3.0 - 5f64.sqrt()) / 2.0;
    let mut last_width = f64::INFINITY;
    for _ in 0..s.tip_iterations {
        let width = c.0 - a.0;
        if width <= tolerance {
            break;
        }
        // The parabola's vertex if it lies well inside the bracket and the last step
        // halved it; else golden section into the larger side.
        let vertex = parabola_vertex(a, b, c).filter(|&x| {
            let margin = 0.25 * tolerance;
            x > a.0 + margin && x < c.0 - margin && (x - b.0).abs() > margin && width < 0.5 * last_width
        });
        last_width = width;
        let x = vertex.unwrap_or(if c.0 - b.0 > b.0 - a.0 {
            b.0 + golden * (c.0 - b.0)
        } else {
            b.0 - golden * (b.0 - a.0)
        });
        let u = (x, g(x));
        if u.1 >= b.1 {
            if u.0 > b.0 {
                a = b;
            } else {
                c = b;
            }
            b = u;
        } else if u.0 > b.0 {
            c = u;
        } else {
            a = u;
        }
    }
    Some(parabola_vertex(a, b, c).map_or(b.0, |x| x.clamp(a.0, c.0)))
}

/// The vertex of the parabola through three points (x ascending), if it opens downward.
fn parabola_vertex((x0, y0): (f64, f64), (x1, y1): (f64, f64), (x2, y2): (f64, f64)) -> Option<f64> {
    let (d0, d2) = ((y1 - y0) / (x1 - x0), (y2 - y1) / (x2 - x1));
    let curvature = (d2 - d0) / (x2 - x0);
    if curvature.is_nan() || curvature >= 0.0 {
        return None;
    }
    // Vertex of the Newton form: x where the slope d0 + curvature·(2x − x0 − x1) vanishes.
    let x = 0.5 * (x0 + x1) - d0 / (2.0 * curvature);
    x.is_finite().then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The most evaluations of `g` a [`climb`] makes in a window of half-width at most
    /// `half_width_over_phi`·φ: three for the first triple; one per doubling step, of which
    /// at most ⌈log₂(half-width/h)⌉ stay inside the window (after k of them the climb is
    /// (2^(k+1) − 1)·h from its start, and the first step h is CLIMB_STEP·φ or a quarter of
    /// the half-width, whichever is smaller); and one per refinement step
    /// (`tip_iterations`).
    fn most_climb_evaluations(s: &RegionSettings, half_width_over_phi: f64) -> f64 {
        let steps = (half_width_over_phi / CLIMB_STEP).max(4.0);
        3.0 + steps.log2().ceil() + s.tip_iterations as f64
    }

    /// A climb that only rises never turns back: it doubles its steps to the window's
    /// edge and stops there. Its count of evaluations is the bound's doubling part.
    #[test]
    fn a_climb_up_a_slope_to_the_edge_stays_within_the_bound() {
        let s = RegionSettings::default();
        for (phi, over_phi) in [(1000.0, 3e-3), (1800.0, 5e-3), (500.0, 1e-4), (2000.0, 0.1)] {
            let mut calls = 0usize;
            let tip = climb(
                |x| {
                    calls += 1;
                    x
                },
                &s,
                phi,
                over_phi * phi,
            );
            assert_eq!(tip, None, "a rising slope leaves the window");
            let bound = most_climb_evaluations(&s, over_phi) - s.tip_iterations as f64;
            assert!(calls as f64 <= bound, "{calls} evaluations, bound {bound} at {over_phi}");
        }
    }
}
