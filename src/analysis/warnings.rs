//! The warning that needs computed whirls: a φ range that no instability region can
//! reach ([`phi_range`]). The file layer's plausibility warnings live with the file layer
//! (`problem::plausibility`), which wraps this one to locate it. The library returns
//! warnings; it never prints them.

use super::Interval;
use thiserror::Error;

/// A φ range that no instability region of the reduced model can reach, with the numbers
/// that make it so.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RangeWarning {
    /// A φ range above every whirl sum of the reduced model: no region starts in it.
    #[error("the phi range [{lo}, {hi}] rad/s lies above every whirl sum of the reduced model (largest omega_f + omega_b = {largest_sum:.4e} rad/s at {speed} rad/s): no instability region starts in it; raise analysis.reduced_modes or check the units", lo = crate::analysis::limits::number(*lo), hi = crate::analysis::limits::number(*hi), speed = crate::analysis::limits::number(*speed))]
    RangeAboveWhirls {
        /// φ range (rad/s).
        lo: f64,
        /// φ range (rad/s).
        hi: f64,
        /// The largest ω_f + ω_b of the reduced model (rad/s).
        largest_sum: f64,
        /// Ω (rad/s).
        speed: f64,
    },
    /// A φ range below every tongue of the orders the criterion searches.
    #[error("the phi range [{lo}, {hi}] rad/s lies below every instability tongue of order <= {order} (smallest omega_f + omega_b = {smallest_sum:.4e} rad/s at {speed} rad/s, over {order}: {:.4e} rad/s): check the range and the units", smallest_sum / *order as f64, lo = crate::analysis::limits::number(*lo), hi = crate::analysis::limits::number(*hi), speed = crate::analysis::limits::number(*speed))]
    RangeBelowWhirls {
        /// φ range (rad/s).
        lo: f64,
        /// φ range (rad/s).
        hi: f64,
        /// The smallest ω_f + ω_b of the reduced model (rad/s).
        smallest_sum: f64,
        /// The criterion's highest tongue order (`analysis.max_tongue_order`).
        order: usize,
        /// Ω (rad/s).
        speed: f64,
    },
}

impl RangeWarning {
    /// The kind's name, as `docs/errors.md` lists it: the `kind` of a warning in JSON.
    pub fn name(&self) -> &'static str {
        match self {
            RangeWarning::RangeAboveWhirls { .. } => "RangeAboveWhirls",
            RangeWarning::RangeBelowWhirls { .. } => "RangeBelowWhirls",
        }
    }
}

/// Whether a φ range can hold an instability region of the reduced model at speed Ω
/// whose forward and backward whirls (rad/s) are `forward` and `backward`. Every tongue
/// starts, at zero damping, at a sum ω_fi + ω_bj over its order k; so a range above the
/// largest sum holds none ([`RangeWarning::RangeAboveWhirls`]), and a range below the
/// smallest sum over the highest order searched (`max_order`, the criterion's
/// `max_tongue_order`) holds none that the search counts ([`RangeWarning::RangeBelowWhirls`]).
/// Both bounds are exact for the undamped model; no tolerance is added, since damping
/// only narrows tongues and lifts their onsets. `None` when the range is plausible or
/// the model has no whirl of one direction.
pub fn phi_range(
    forward: &[f64],
    backward: &[f64],
    range: Interval,
    max_order: usize,
    speed: f64,
) -> Option<RangeWarning> {
    let max = |v: &[f64]| v.iter().copied().filter(|x| x.is_finite()).fold(f64::NAN, f64::max);
    let min = |v: &[f64]| v.iter().copied().filter(|x| x.is_finite()).fold(f64::NAN, f64::min);
    let largest_sum = max(forward) + max(backward);
    let smallest_sum = min(forward) + min(backward);
    if !(largest_sum.is_finite() && smallest_sum.is_finite()) {
        return None;
    }
    if largest_sum < range.lo {
        return Some(RangeWarning::RangeAboveWhirls { lo: range.lo, hi: range.hi, largest_sum, speed });
    }
    if smallest_sum / max_order.max(1) as f64 > range.hi {
        return Some(RangeWarning::RangeBelowWhirls {
            lo: range.lo,
            hi: range.hi,
            smallest_sum,
            order: max_order,
            speed,
        });
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_range_beyond_every_whirl_sum_is_flagged_on_its_side() {
        let (f, b) = ([400.0, 1900.0], [300.0, 1650.0]);
        // Sums run from 700 to 3550 rad/s; order 8 reaches down to 87.5 rad/s.
        assert_eq!(phi_range(&f, &b, Interval::new(100.0, 8000.0), 8, 2000.0), None);
        assert_eq!(phi_range(&f, &b, Interval::new(3000.0, 8000.0), 8, 2000.0), None);
        assert!(matches!(
            phi_range(&f, &b, Interval::new(3600.0, 8000.0), 8, 2000.0),
            Some(RangeWarning::RangeAboveWhirls { largest_sum, .. }) if largest_sum == 3550.0
        ));
        assert_eq!(phi_range(&f, &b, Interval::new(10.0, 88.0), 8, 2000.0), None);
        assert!(matches!(
            phi_range(&f, &b, Interval::new(10.0, 87.0), 8, 2000.0),
            Some(RangeWarning::RangeBelowWhirls { smallest_sum, order: 8, .. }) if smallest_sum == 700.0
        ));
        assert_eq!(phi_range(&[], &b, Interval::new(3600.0, 8000.0), 8, 0.0), None);
    }
}
