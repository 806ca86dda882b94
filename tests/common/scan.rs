//! The points of the band truth tests (tests/band_truth.rs, tests/held_out_band.rs)
//! inside a band: a scan over the whole band and the acceptance's 0.05 rad/s grid where
//! the catalogue puts a tongue (docs/decisions.md, "Fewer points after all").

use rotorshunt::analysis::regions::{Catalogue, CENTRE_WINDOW, START_WINDOW};
use rotorshunt::analysis::Interval;

/// Grid spacing (rad/s), from the acceptance.
pub const GRID: f64 = 0.05;
/// Spacing of the scan over the whole of a band (rad/s): [`SCAN_STEPS`] grid steps.
pub const SCAN: f64 = 0.1;
/// Grid steps per scan step.
pub const SCAN_STEPS: i64 = 2;

/// The neighbourhood of a band whose catalogue the truth tests read: widened by this
/// fraction each side, as far as the centre search looks for a seed's tongue.
pub const NEAR: f64 = CENTRE_WINDOW;

/// [lo, hi] widened by [`NEAR`] on each side, clipped to `window` (rad/s).
pub fn neighbourhood(lo: f64, hi: f64, window: Interval) -> Interval {
    Interval::new(lo * (1.0 - NEAR), hi * (1.0 + NEAR)).clipped(&window)
}

/// Grid indices k (points k·GRID) strictly inside (lo, hi).
pub fn grid(lo: f64, hi: f64) -> Vec<i64> {
    let first = (lo / GRID).floor() as i64 + 1;
    let last = (hi / GRID).ceil() as i64 - 1;
    (first..=last).filter(|&k| k as f64 * GRID > lo && k as f64 * GRID < hi).collect()
}

/// Where the catalogue at the level puts a tongue, widened by [`SCAN`]: every region's
/// extent and the start window around its start, the unexplained and the ignored tongues
/// (sorted by lo). A tongue thinner than the scan, inside a band, is looked for on the
/// 0.05 rad/s grid here.
pub fn catalogued_windows(cat: &Catalogue) -> Vec<Interval> {
    let mut out = Vec::new();
    for r in &cat.regions {
        if let (Some(l), Some(h)) = (r.left, r.right) {
            out.push(Interval::new(l - SCAN, h + SCAN));
        }
        let half = (START_WINDOW * r.start).max(SCAN);
        out.push(Interval::new(r.start - half, r.start + half));
    }
    out.extend(cat.unexplained.iter().map(|u| Interval::new(u.lo - SCAN, u.hi + SCAN)));
    out.extend(cat.ignored.iter().map(|t| Interval::new(t.extent.lo - SCAN, t.extent.hi + SCAN)));
    out.sort_by(|a, b| a.lo.total_cmp(&b.lo));
    out
}

/// The points strictly inside (lo, hi) that the truth tests check: every [`SCAN_STEPS`]-th
/// grid point, and every grid point within [`SCAN`] of an edge or inside one of `windows`
/// (sorted by lo).
pub fn band_points(lo: f64, hi: f64, windows: &[Interval]) -> Vec<i64> {
    let near = |x: f64| {
        let upto = windows.partition_point(|w| w.lo <= x);
        windows[..upto].iter().any(|w| x <= w.hi)
    };
    grid(lo, hi)
        .into_iter()
        .filter(|&k| {
            let x = k as f64 * GRID;
            k % SCAN_STEPS == 0 || x - lo <= SCAN || hi - x <= SCAN || near(x)
        })
        .collect()
}
