//! The declared stability criterion: one rule that `band`, `regions`, `design`, `study`
//! and the reports all apply.

use super::floquet::PointSummary;
use super::Settings;
use serde::Serialize;

/// When an unstable point or tongue counts.
///
/// A point is unstable when max|μ| exceeds `instability_tolerance` (the paper's rule,
/// Eq. 28); it counts when its growth rate ln(max|μ|)/T is also at least
/// `min_growth_rate`. A tongue of the unstable set at β_op counts when it contains a
/// counted point and is at least `min_tongue_width` wide there. Tongues are searched up to
/// order `max_order` of (ω_i + ω_j)/k: stable bands are complete up to that order.
/// Tongues the criterion ignores are listed as such, never dropped.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Criterion {
    /// max|μ| above which a point is unstable (−).
    pub instability_tolerance: f64,
    /// σ_min: smallest growth rate that counts (1/s).
    pub min_growth_rate: f64,
    /// Smallest tongue width at β_op that counts (rad/s).
    pub min_tongue_width: f64,
    /// Highest tongue order searched (the guarantee's k).
    pub max_order: usize,
}

impl Criterion {
    /// The criterion declared by a problem's `[analysis]` settings.
    pub fn of(settings: &Settings) -> Criterion {
        Criterion {
            instability_tolerance: settings.instability_tolerance,
            min_growth_rate: settings.min_growth_rate,
            min_tongue_width: settings.min_tongue_width,
            max_order: settings.max_tongue_order,
        }
    }

    /// Whether an evaluated point counts as unstable. A point without a verdict (failed
    /// monodromy) counts: it is not shown to be stable.
    pub fn counts(&self, p: &PointSummary) -> bool {
        // A NaN growth rate (no verdict) counts too.
        !p.stable && (p.growth_rate >= self.min_growth_rate || p.growth_rate.is_nan())
    }

    /// Whether the paper's criterion is declared as it stands (nothing ignored).
    pub fn ignores_nothing(&self) -> bool {
        self.min_growth_rate == 0.0 && self.min_tongue_width == 0.0
    }

    /// What a stable band at β_op guarantees, in words.
    pub fn guarantee(&self, level: f64) -> String {
        let mut s = format!("no tongue of order <= {} with max|mu| > {}", self.max_order, self.instability_tolerance);
        if self.min_growth_rate > 0.0 {
            s += &format!(" and growth rate >= {} 1/s", self.min_growth_rate);
        }
        if self.min_tongue_width > 0.0 {
            s += &format!(" and width >= {} rad/s", self.min_tongue_width);
        }
        s + &format!(" at beta = {level}")
    }
}
