//! What the constraints any objective may carry ask of the verification, the charts and
//! the cost estimate (the operating bands kept clear, a least band width around φ_op):
//! the provided methods of [`super::Objective`].

use super::CostAt;
use crate::analysis::cost::{self, Estimate, DESIGN_BAND_EVALUATIONS};
use crate::analysis::Interval;
use crate::design::content::{band_window, chart_window as clipped_chart_window};
use crate::design::evaluate::neighbourhood;
use crate::design::spec::DesignSpec;
use crate::design::verify::DesignAtSpeed;

/// The bands kept clear, widened by their clearances, and the catalogue's band around
/// the band-width constraint's φ_op when it is that wide (a failure when not), with the
/// number of comparisons made.
pub fn verified_windows(spec: &DesignSpec, d: &mut DesignAtSpeed) -> (Vec<Interval>, usize) {
    let mut w: Vec<Interval> = spec.kept_clear().iter().map(|b| b.guarded()).collect();
    let mut comparisons = 0;
    if let Some(min) = spec.constraints.min_band_width {
        comparisons += 1;
        match d.catalogue_band {
            Some(cb) if cb.width() >= min.width => w.push(cb),
            other => d.failures.push(format!(
                "the catalogue's stable band around {} rad/s ({other:?}) is not {} rad/s wide",
                min.phi_op, min.width
            )),
        }
    }
    (w, comparisons)
}

/// The bands kept clear ([`band_window`]), else half to 1.5 times φ_op, else the whole
/// range (rad/s).
pub fn chart_window(spec: &DesignSpec) -> (f64, f64) {
    match spec.phi_op() {
        _ if !spec.kept_clear().is_empty() => band_window(spec.kept_clear()),
        Some(p) => (p * 0.5, p * 1.5),
        None => spec.phi_range,
    }
}

/// The scan for the tongues in the neighbourhoods of the bands kept clear, then the band
/// search around the band-width constraint's φ_op.
pub fn candidate_cost(spec: &DesignSpec, at: &CostAt<'_>) -> Estimate {
    let range = spec.range();
    let windows: Vec<Interval> = spec.kept_clear().iter().map(|b| neighbourhood(b).clipped(&range)).collect();
    let mut work = cost::scan(at.point, at.regions, at.criterion, at.seeds, &windows, spec.level);
    if let Some(b) = spec.constraints.min_band_width {
        let band = cost::points(at.point, DESIGN_BAND_EVALUATIONS, (0.5 * b.phi_op).max(range.lo), spec.level);
        work = work.then(band);
    }
    work
}

/// The bands kept clear, widened by their clearances, and the charts' window for the
/// band-width constraint's band.
pub fn checked_windows(spec: &DesignSpec) -> Vec<Interval> {
    let range = spec.range();
    let mut w: Vec<Interval> = spec.kept_clear().iter().map(|b| b.guarded().clipped(&range)).collect();
    if spec.constraints.min_band_width.is_some() {
        w.push(clipped_chart_window(spec));
    }
    w
}
