//! What looks implausible in an input without being impossible: the kinds of warning
//! the file layer finds in a problem ([`crate::problem`]'s plausibility checks) and the
//! one that needs computed whirls, a φ range that no instability region can reach
//! ([`phi_range`]). The library returns warnings (in [`crate::problem::Problem`] and in
//! every JSON output); it never prints them.

use super::Interval;
use thiserror::Error;

/// One implausible value, with the numbers that make it so. The text (`Display`) is what
/// the command line prints after `warning: FILE, line N: key `K`: `.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum WarningKind {
    /// A Young's modulus outside the range of engineering solids.
    #[error(
        "E = {value:e} Pa is far from any metal or composite ({lo:e} to {hi:e} Pa): check the unit (Pa, not MPa or GPa)"
    )]
    YoungsModulus {
        /// E (Pa).
        value: f64,
        /// Lower end of the plausible range (Pa).
        lo: f64,
        /// Upper end (Pa).
        hi: f64,
    },
    /// A shaft or disk heavier than any machinery rotor.
    #[error("the {what} weighs {mass:.4e} kg, more than any machinery rotor ({limit:e} kg): check the units (kg, and lengths in m, not mm)")]
    Mass {
        /// `shaft` or `disk`.
        what: &'static str,
        /// Its mass (kg).
        mass: f64,
        /// The limit (kg).
        limit: f64,
    },
    /// A shaft far more slender than machinery shafts.
    #[error("the shaft's slenderness L/D = {length:.4e} m / {diameter:.4e} m = {ratio:.4e} is above {limit} (machinery shafts stay far below): check the length and diameter units (m)")]
    Slenderness {
        /// L (m).
        length: f64,
        /// The largest outer diameter D (m).
        diameter: f64,
        /// L/D.
        ratio: f64,
        /// The limit.
        limit: f64,
    },
    /// A ring angle small enough to be a value in radians.
    #[error("angle_deg = {angle_deg} degrees is at most pi/2: it looks like radians ({angle_deg} rad = {:.4} degrees); the key is in degrees", angle_deg.to_degrees(), angle_deg = crate::analysis::limits::number(*angle_deg))]
    AngleInRadians {
        /// The angle given (degrees).
        angle_deg: f64,
    },
    /// A speed whose peripheral speed no metal rotor survives: likely rpm given as rad/s.
    #[error("{speed} rad/s gives a peripheral speed of {peripheral:.4e} m/s at the radius {radius:.4} m, above the {limit} m/s at which metal disks burst: a speed in rpm is given as `{rpm_key}` (or check that the lengths are in m)", speed = crate::analysis::limits::number(*speed))]
    PeripheralSpeed {
        /// Ω (rad/s).
        speed: f64,
        /// The largest radius of the rotor (m).
        radius: f64,
        /// Ω·radius (m/s).
        peripheral: f64,
        /// The limit (m/s).
        limit: f64,
        /// The rpm key to use instead.
        rpm_key: String,
    },
    /// A speed given in rpm whose peripheral speed no metal rotor survives.
    #[error("{rpm} rpm gives a peripheral speed of {peripheral:.4e} m/s at the radius {radius:.4} m, above the {limit} m/s at which metal disks burst", rpm = crate::analysis::limits::number(*rpm))]
    PeripheralSpeedRpm {
        /// n (rpm).
        rpm: f64,
        /// The largest radius of the rotor (m).
        radius: f64,
        /// Ω·radius (m/s).
        peripheral: f64,
        /// The limit (m/s).
        limit: f64,
    },
    /// A speed outside a bearing's or seal's coefficient table: its coefficients are
    /// held at the nearest end of the table (not extrapolated).
    #[error("{speed} rad/s is outside the table's speeds ({lo} to {hi} rad/s): the coefficients are held at their value at {} rad/s, not extrapolated", if speed < lo { lo } else { hi }, speed = crate::analysis::limits::number(*speed), lo = crate::analysis::limits::number(*lo), hi = crate::analysis::limits::number(*hi))]
    OutsideTable {
        /// The speed (rad/s).
        speed: f64,
        /// The table's first speed (rad/s).
        lo: f64,
        /// Its last speed (rad/s).
        hi: f64,
    },
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

impl WarningKind {
    /// The kind's name, as `docs/errors.md` lists it (`YoungsModulus`, …): the `kind` of
    /// a warning in JSON.
    pub fn name(&self) -> &'static str {
        match self {
            WarningKind::YoungsModulus { .. } => "YoungsModulus",
            WarningKind::Mass { .. } => "Mass",
            WarningKind::Slenderness { .. } => "Slenderness",
            WarningKind::AngleInRadians { .. } => "AngleInRadians",
            WarningKind::PeripheralSpeed { .. } => "PeripheralSpeed",
            WarningKind::PeripheralSpeedRpm { .. } => "PeripheralSpeedRpm",
            WarningKind::RangeAboveWhirls { .. } => "RangeAboveWhirls",
            WarningKind::RangeBelowWhirls { .. } => "RangeBelowWhirls",
            WarningKind::OutsideTable { .. } => "OutsideTable",
        }
    }
}

/// Whether a φ range can hold an instability region of the reduced model at speed Ω
/// whose forward and backward whirls (rad/s) are `forward` and `backward`. Every tongue
/// starts, at zero damping, at a sum ω_fi + ω_bj over its order k; so a range above the
/// largest sum holds none ([`WarningKind::RangeAboveWhirls`]), and a range below the
/// smallest sum over the highest order searched (`max_order`, the criterion's
/// `max_tongue_order`) holds none that the search counts ([`WarningKind::RangeBelowWhirls`]).
/// Both bounds are exact for the undamped model; no tolerance is added, since damping
/// only narrows tongues and lifts their onsets. `None` when the range is plausible or
/// the model has no whirl of one direction.
pub fn phi_range(
    forward: &[f64],
    backward: &[f64],
    range: Interval,
    max_order: usize,
    speed: f64,
) -> Option<WarningKind> {
    let max = |v: &[f64]| v.iter().copied().filter(|x| x.is_finite()).fold(f64::NAN, f64::max);
    let min = |v: &[f64]| v.iter().copied().filter(|x| x.is_finite()).fold(f64::NAN, f64::min);
    let largest_sum = max(forward) + max(backward);
    let smallest_sum = min(forward) + min(backward);
    if !(largest_sum.is_finite() && smallest_sum.is_finite()) {
        return None;
    }
    if largest_sum < range.lo {
        return Some(WarningKind::RangeAboveWhirls { lo: range.lo, hi: range.hi, largest_sum, speed });
    }
    if smallest_sum / max_order.max(1) as f64 > range.hi {
        return Some(WarningKind::RangeBelowWhirls {
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
            Some(WarningKind::RangeAboveWhirls { largest_sum, .. }) if largest_sum == 3550.0
        ));
        assert_eq!(phi_range(&f, &b, Interval::new(10.0, 88.0), 8, 2000.0), None);
        assert!(matches!(
            phi_range(&f, &b, Interval::new(10.0, 87.0), 8, 2000.0),
            Some(WarningKind::RangeBelowWhirls { smallest_sum, order: 8, .. }) if smallest_sum == 700.0
        ));
        assert_eq!(phi_range(&[], &b, Interval::new(3600.0, 8000.0), 8, 0.0), None);
    }
}
