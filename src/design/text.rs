//! Speeds, bands and band edges in words: the pieces of text the objectives' report lines
//! ([`crate::design::objective`]) and the report layer share.

use crate::analysis::regions::{Band, Bound};
use crate::numbers::SpeedUnit;

/// `Ω = 1256.6 rad/s`, or `n = 12000 rpm (1256.6 rad/s)`.
pub fn speed_text(unit: SpeedUnit, speed: f64) -> String {
    format!("{} = {}", unit.symbol(), unit.text(speed))
}

/// The header of a table's speed column: `Ω (rad/s)` or `n (rpm)`.
pub fn speed_header(unit: SpeedUnit) -> String {
    format!("{} ({})", unit.symbol(), unit.unit())
}

/// A speed in a table's speed column (its header's unit), to the rpm or rad/s.
pub fn speed_cell(unit: SpeedUnit, speed: f64) -> String {
    format!("{:.0}", unit.value(speed))
}

/// A stable band around φ_op in a table cell: `[lo, hi] (width)` (rad/s), clipped or
/// unstable said so.
pub fn band_text(b: &Band) -> String {
    match (b.band, b.containing) {
        (Some(x), _) if b.clipped() => {
            format!("[{:.2}, {:.2}] (at least {:.2}: clipped by the window)", x.lo, x.hi, x.width())
        }
        (Some(x), _) => format!("[{:.2}, {:.2}] ({:.2})", x.lo, x.hi, x.width()),
        (None, Some(t)) => format!("φ_op unstable, inside [{:.2}, {:.2}]", t.lo, t.hi),
        _ => "φ_op unstable".into(),
    }
}

/// What bounds a band on one side, in a table cell: the tongue and its edge (rad/s), the
/// window's end, or `–`.
pub fn bound_text(b: &Option<Bound>) -> String {
    match b {
        Some(Bound::Tongue { label, edge, unexplained: Some(u), .. }) => format!(
            "{label} at {edge:.2} (Floquet exponent {:.2} rad/s; nearest {} = {:.2})",
            u.exponent_frequency, u.nearest, u.nearest_frequency
        ),
        Some(Bound::Tongue { label, edge, .. }) => format!("{label} at {edge:.2}"),
        Some(Bound::Window) => "window end (clipped: widen design.phi_range)".into(),
        // No band: φ_op is unstable, and nothing bounds it.
        None => "–".into(),
    }
}
