//! The declared stability criterion: one rule that `band`, `regions`, `design`, `study`
//! and the reports all apply.

use super::floquet::PointSummary;
use super::Settings;
use serde::Serialize;

/// The numerical floor of the fast Floquet path on max|μ| (−): with the default 32 CFM4
/// steps per period max|μ| is within 1e-6 of a converged reference at every tested point
/// of the paper's problems (`Settings::steps_per_period`, tests/floquet_paths.rs,
/// tests/convergence.rs). Every band search evaluates on that path, so a max|μ| above
/// 1 + this floor is growth the path resolves, not its error; the strict criterion
/// ([`Criterion::strict`]) counts every such point.
pub const PATH_FLOOR: f64 = 1e-6;

/// When an unstable point or tongue counts.
///
/// A point is unstable when max|μ| exceeds `instability_tolerance` (the paper's rule,
/// Eq. 28); it counts when its growth rate ln(max|μ|)/T is also at least
/// `min_growth_rate`. A tongue of the unstable set at β_op counts when it contains a
/// counted point and is at least `min_tongue_width` wide there. Tongues are searched up to
/// order `max_order` of (ω_i + ω_j)/k: stable bands are complete up to that order.
/// Tongues the criterion ignores are listed as such, never dropped.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
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
        // Unstable by this criterion's own tolerance (the point's verdict is the declared
        // one's: the same test when the tolerances agree); a failed point's ln max|μ| is
        // f64::MAX, and a NaN is not shown stable.
        let unstable = p.ln_max_multiplier > self.instability_tolerance.ln() || p.ln_max_multiplier.is_nan();
        // A NaN growth rate (no verdict) counts too.
        unstable && (p.growth_rate >= self.min_growth_rate || p.growth_rate.is_nan())
    }

    /// The strict criterion beside this declared one: a point is unstable when max|μ|
    /// exceeds 1 + [`PATH_FLOOR`] (or the declared tolerance, if that is stricter), and
    /// every unstable point and tongue counts (no growth-rate or width floor); the same
    /// order. Its band says how much of a declared band lies in the slack of the
    /// declared tolerance.
    pub fn strict(&self) -> Criterion {
        Criterion {
            instability_tolerance: self.instability_tolerance.min(1.0 + PATH_FLOOR),
            min_growth_rate: 0.0,
            min_tongue_width: 0.0,
            max_order: self.max_order,
        }
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
