//! The band and the catalogue on a reduced basis sized by convergence
//! ([`crate::analysis::basis`]): each is computed on bases of increasing size until its
//! edges (and onsets) move less than the settings' tolerance, and comes back with the
//! Floquet system it was computed on and the [`crate::analysis::basis::BasisReport`] that says so.
//!
//! What is compared between two sizes:
//! - a band: its edges (or, when φ_op is unstable at both, the edges of the tongue that
//!   contains it), against the larger of `convergence_relative` of the band's width and
//!   `convergence_absolute`; a band at one size and none at the other has not converged;
//! - a catalogue: its stable set at the level, by the longest interval of φ over which
//!   the two sizes disagree ([`stable_set_movement`]: an edge that moved, or a tongue one
//!   size has and the other has not, such as the thin tongues a larger basis's new modes
//!   bring), and the onsets of the regions found at both sizes under the same label and
//!   order with their tips located (an unresolved onset is an upper bound that moves with
//!   where it was found), relative to themselves, for the regions whose two whirls lie at
//!   or below the window's top: the modes whose first-order tongues the window holds,
//!   which the first size of the basis has. A region of a higher whirl (its order-k
//!   tongue reaching down into the window) is listed as the final basis gives it; its
//!   onset converges with that whirl, the last modes of a basis to converge. A region found at one size only is compared through
//!   the stable set it changes, not by its onset.

use super::{band_with, catalogue_with, Band, Catalogue, CatalogueRequest, RegionSettings};
use crate::analysis::basis::{self, sized, Movement, Schedule, Sized, Tolerance};
use crate::analysis::modes::ModesResult;
use crate::analysis::{AnalysisError, Interval, Rotor, Settings};
use crate::progress::Progress;

/// Onsets below this (−) are compared by their absolute change over it rather than
/// relatively: a tongue born at β ≈ 0 (an undamped resonance) moves by round-off.
const ONSET_FLOOR: f64 = 1e-3;

/// The stable band around `phi_op` at `level` in `range` (rad/s) as [`band_with`] finds
/// it, on the bases of `schedule` (of `settings`' kind) at speed Ω (rad/s) until it
/// converges ([`Schedule::new`] for the sizes of `settings` and the range).
#[allow(clippy::too_many_arguments)]
pub fn band_sized(
    rotor: &Rotor,
    settings: &Settings,
    schedule: &Schedule,
    speed: f64,
    full: &ModesResult,
    s: &RegionSettings,
    range: Interval,
    phi_op: f64,
    level: f64,
    progress: &dyn Progress,
) -> Result<Sized<Band>, AnalysisError> {
    sized(rotor, settings, schedule, speed, |fs| band_with(fs, full, s, range, phi_op, level, progress), band_movement)
}

/// The catalogue of `req` as [`catalogue_with`] finds it, on the bases of `schedule` (of
/// `settings`' kind) at speed Ω (rad/s) until it converges.
#[allow(clippy::too_many_arguments)]
pub fn catalogue_sized(
    rotor: &Rotor,
    settings: &Settings,
    schedule: &Schedule,
    speed: f64,
    full: &ModesResult,
    s: &RegionSettings,
    req: &CatalogueRequest,
    progress: &dyn Progress,
) -> Result<Sized<Catalogue>, AnalysisError> {
    sized(rotor, settings, schedule, speed, |fs| catalogue_with(fs, full, s, req, progress), catalogue_movement)
}

/// How far a band moved between two bases (module docs).
pub fn band_movement(a: &Band, b: &Band, tolerance: &Tolerance) -> Movement {
    match (a.band, b.band, a.containing, b.containing) {
        (Some(x), Some(y), ..) => basis::interval_movement(x, y, tolerance, "band edge"),
        (None, None, Some(x), Some(y)) => {
            basis::interval_movement(x, y, tolerance, "edge of the tongue containing phi_op")
        }
        _ => {
            Movement::change("phi_op stable at one size and unstable at the other".into(), "rad/s", tolerance.absolute)
        }
    }
}

/// How far a catalogue moved between two bases (module docs).
pub fn catalogue_movement(a: &Catalogue, b: &Catalogue, tolerance: &Tolerance) -> Movement {
    let mut worst = stable_set_movement(&a.stable_bands, &b.stable_bands, tolerance);
    let top = a.range.hi;
    for r in a.regions.iter().filter(|r| r.whirls.0 <= top && r.whirls.1 <= top) {
        // Onsets whose tip was located at both sizes: an unresolved onset is β_c at some
        // point of the region, an upper bound that moves with where it was found.
        let same = b.regions.iter().find(|q| q.label == r.label && q.order == r.order && q.resolved);
        if let (Some(q), true) = (same, r.resolved) {
            let what = format!("onset of {} (k = {})", r.label, r.order);
            worst =
                worst.worst(basis::relative_movement(r.onset_beta, q.onset_beta, tolerance.onset, ONSET_FLOOR, &what));
        }
    }
    worst
}

/// How far the stable set at the level moved between two bases: the longest interval of φ
/// over which the two sets differ (an edge that moved, or a tongue that one basis has and
/// the other has not), against the edge tolerance of the narrowest stable band that
/// interval touches at either size.
pub fn stable_set_movement(a: &[Interval], b: &[Interval], tolerance: &Tolerance) -> Movement {
    let mut cuts: Vec<f64> = a.iter().chain(b).flat_map(|i| [i.lo, i.hi]).collect();
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let inside = |set: &[Interval], x: f64| set.iter().any(|i| i.lo <= x && x <= i.hi);
    // The pieces between consecutive cuts where the two sets disagree, joined into runs.
    let mut runs: Vec<Interval> = Vec::new();
    for w in cuts.windows(2) {
        let mid = 0.5 * (w[0] + w[1]);
        if inside(a, mid) != inside(b, mid) {
            match runs.last_mut() {
                Some(r) if r.hi == w[0] => r.hi = w[1],
                _ => runs.push(Interval::new(w[0], w[1])),
            }
        }
    }
    let mut worst = Movement::none("stable set at the level", "rad/s", tolerance.absolute);
    for r in runs {
        let touching = a.iter().chain(b).filter(|i| i.lo <= r.hi && r.lo <= i.hi).map(|i| i.width());
        let narrowest = touching.fold(f64::INFINITY, f64::min);
        let tol = tolerance.edge(if narrowest.is_finite() { narrowest } else { 0.0 });
        let moved = Movement::of(
            r.width(),
            tol,
            "rad/s",
            format!("stable set at the level in [{:.2}, {:.2}] rad/s", r.lo, r.hi),
        );
        worst = worst.worst(moved);
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_stable_set_moves_by_its_longest_disagreement() {
        let tol = Tolerance { relative: 0.0025, absolute: 0.5, onset: 0.01 };
        let a = [Interval::new(100.0, 200.0), Interval::new(300.0, 400.0)];
        // An edge moved by 0.25 rad/s and a 0.125 rad/s tongue born inside the second band.
        let b = [Interval::new(100.25, 200.0), Interval::new(300.0, 350.0), Interval::new(350.125, 400.0)];
        let m = stable_set_movement(&a, &b, &tol);
        assert_eq!(m.value, 0.25);
        assert!(m.within(), "{m:?}");
        // A band gone entirely: 100 rad/s, far beyond.
        let m = stable_set_movement(&a, &a[..1], &tol);
        assert_eq!(m.value, 100.0);
        assert!(!m.within());
        assert_eq!(stable_set_movement(&a, &a, &tol).value, 0.0);
    }
}
