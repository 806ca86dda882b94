//! Orbits of the real coordinates: the ellipse a node describes in a mode or a
//! synchronous response, its forward and backward circular components, and the whirl
//! direction of a mode from its nodes' orbits, as ROSS classifies it.
//!
//! A node's motion x(t) = Re(X·e^{jωt}), y(t) = Re(Y·e^{jωt}) (X, Y the phasors of its v
//! and w DOFs) is, with u = x + jy, u(t) = F·e^{jωt} + B·e^{−jωt}, the sum of
//! a forward circle of radius |F| and a backward one of radius |B|:
//! F = (X + jY)/2, B = (X̄ + jȲ)/2 (|B| = |X − jY|/2). The ellipse has semi-axes
//! |F| + |B| (major) and ||F| − |B|| (minor); it whirls forward (from x towards y, with
//! the spin) when |F| > |B|, backward when |F| < |B|, and is a line when they are equal.

use faer::c64;
use serde::{Deserialize, Serialize};

/// The ellipse of one node.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Orbit {
    /// Radius |F| of the forward circular component (m, or the mode's units).
    pub forward: f64,
    /// Radius |B| of the backward circular component.
    pub backward: f64,
    /// Semi-major axis |F| + |B|.
    pub major: f64,
    /// Semi-minor axis ||F| − |B||.
    pub minor: f64,
    /// κ = ±minor/major: positive for a forward whirl, negative for a backward one, 0 for
    /// a line (ROSS's `kappa`).
    pub kappa: f64,
}

/// Relative difference of |F| and |B| below which an orbit is a line and votes for no
/// direction: round-off of the eigenvectors is ~1e-15 of the orbit; a physical orbit of
/// κ = 1e-12 is a line for every purpose.
pub const LINE_TOLERANCE: f64 = 1e-12;

/// Orbits smaller than this fraction of the mode's largest do not vote on its direction:
/// a node at rest (a nodal point, or a bearing stiff enough to hold it) has an orbit of
/// round-off whose direction is noise. ROSS counts every node; on its example rotors no
/// node is that still, so the classifications agree.
pub const STILL_NODE: f64 = 1e-9;

impl Orbit {
    /// The orbit of the phasors X (x, v) and Y (y, w).
    pub fn of(x: c64, y: c64) -> Orbit {
        let j = c64::new(0.0, 1.0);
        let forward = ((x + j * y) * 0.5).norm();
        let backward = ((x - j * y) * 0.5).norm();
        let major = forward + backward;
        let minor = (forward - backward).abs();
        let kappa = if major > 0.0 && minor > LINE_TOLERANCE * major { (forward - backward) / major } else { 0.0 };
        Orbit { forward, backward, major, minor, kappa }
    }

    /// The direction this orbit votes for: `None` for a line.
    pub fn direction(&self) -> Option<super::modes::Whirl> {
        use super::modes::Whirl;
        if self.kappa > 0.0 {
            Some(Whirl::Forward)
        } else if self.kappa < 0.0 {
            Some(Whirl::Backward)
        } else {
            None
        }
    }
}

/// The whirl direction of a mode from the orbits of its shaft nodes, as ROSS's `Shape`
/// does: forward when every node whirls forward, backward when every node whirls
/// backward, mixed otherwise. Nodes below [`STILL_NODE`] of the largest orbit and lines
/// do not vote; a mode with no voting node (a planar mode: every orbit a line) is mixed
/// (ROSS calls a line backward, κ = 0 not being positive). Returns the direction and the
/// κ of the largest orbit.
pub fn classify(orbits: &[Orbit]) -> (super::modes::Whirl, f64) {
    use super::modes::Whirl;
    let largest = orbits.iter().copied().max_by(|a, b| a.major.total_cmp(&b.major));
    let Some(largest) = largest else { return (Whirl::Mixed, 0.0) };
    let votes = orbits.iter().filter(|o| o.major > STILL_NODE * largest.major).filter_map(Orbit::direction);
    let (mut forward, mut backward) = (false, false);
    for v in votes {
        match v {
            Whirl::Forward => forward = true,
            _ => backward = true,
        }
    }
    let whirl = match (forward, backward) {
        (true, false) => Whirl::Forward,
        (false, true) => Whirl::Backward,
        _ => Whirl::Mixed,
    };
    (whirl, largest.kappa)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::modes::Whirl;

    #[test]
    fn circles_ellipses_and_lines() {
        let j = c64::new(0.0, 1.0);
        // x = cos ωt, y = sin ωt: X = 1, Y = −j, a forward circle.
        let f = Orbit::of(c64::new(1.0, 0.0), -j);
        assert_eq!((f.forward, f.backward, f.kappa), (1.0, 0.0, 1.0));
        // x = cos, y = −sin: backward.
        let b = Orbit::of(c64::new(1.0, 0.0), j);
        assert_eq!(b.kappa, -1.0);
        // x = 2cos, y = sin: forward ellipse with semi-axes 2 and 1.
        let e = Orbit::of(c64::new(2.0, 0.0), -j);
        assert!((e.major - 2.0).abs() < 1e-15 && (e.minor - 1.0).abs() < 1e-15 && e.kappa > 0.0);
        // A line: y in phase with x.
        let l = Orbit::of(c64::new(1.0, 0.0), c64::new(0.5, 0.0));
        assert_eq!((l.kappa, l.direction()), (0.0, None));
        assert_eq!(classify(&[f, e]).0, Whirl::Forward);
        assert_eq!(classify(&[f, b]).0, Whirl::Mixed);
        assert_eq!(classify(&[l, l]).0, Whirl::Mixed);
        // A still node does not vote.
        let still = Orbit::of(c64::new(1e-12, 0.0), j * 1e-12);
        assert_eq!(classify(&[f, still]).0, Whirl::Forward);
    }
}
