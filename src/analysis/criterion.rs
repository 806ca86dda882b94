//! The declared stability criterion: one rule that `band`, `regions`, `design`, `study`
//! and the reports all apply.
//!
//! A point (φ, β) is judged by its growth per period g = ln max|μ| (μ the Floquet
//! multipliers, T = 2π/φ the period), against a [`Threshold`]:
//! - by default ([`Threshold::Growth`]) it is unstable when g > ε − σ_req·T: ε is the
//!   fast path's numerical floor [`PATH_FLOOR`] (growth the path resolves, not its
//!   error) and σ_req ≥ 0 a decay margin (1/s, `analysis.decay_margin`, default 0): with
//!   σ_req > 0 a point is also unstable when its slowest mode decays slower than σ_req.
//!   Onsets, edges and load margins are where g crosses that threshold, so for σ_req = 0
//!   where |μ| = 1 to within the floor;
//! - the paper's rule (Eq. 28, [`Threshold::Multiplier`]), unstable when max|μ| exceeds a
//!   tolerance (1.0001 in the paper), stays available for its figures
//!   (`analysis.instability_tolerance`). It allows a growth rate of up to
//!   ln(tolerance)·φ/2π without calling it growth: 0.02 1/s at 1230 rad/s for 1.0001, as
//!   large as a lightly damped whirl's own decay rate.

use super::floquet::PointSummary;
use super::Settings;
use serde::{Deserialize, Serialize};

/// ε, the numerical floor of the fast Floquet path on the growth per period ln max|μ|
/// (−): the largest ln max|μ| the path may report for a point whose true multipliers lie
/// on or inside the unit circle.
///
/// Measured: with the default 32 CFM4 steps per period max|μ| is within 1e-6 of a
/// converged reference at every tested point of the paper's problems
/// (`Settings::steps_per_period`, tests/floquet_paths.rs, tests/convergence.rs); on the
/// undamped Fig. 11 rotor (R = 0, η = 0, where every stable point has |μ| = 1 exactly) a
/// 4 004-point chart over φ = 100–8000 rad/s, β = 0.1–1 has no point with
/// 1e-12 < ln max|μ| < 1e-4: the stable points stay below 1e-12, six orders under this
/// floor (docs/stability.md, "The criterion"). The reference DSTM path is more accurate
/// (about 1e-8), so the floor holds for both.
pub const PATH_FLOOR: f64 = 1e-6;

/// The rule on a point's growth per period g = ln max|μ| that makes it unstable.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "rule", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Threshold {
    /// Unstable when g > `floor` − `decay_margin`·T, T = 2π/φ (the default).
    Growth {
        /// ε: growth per period below which the path cannot tell growth from its error
        /// (−), [`PATH_FLOOR`].
        floor: f64,
        /// σ_req: the decay rate every point must at least have (1/s); 0 asks only that
        /// nothing grows.
        decay_margin: f64,
    },
    /// The paper's rule (Eq. 28): unstable when max|μ| > `tolerance`.
    Multiplier {
        /// The tolerance on max|μ| (−), above 1.
        tolerance: f64,
    },
}

impl Threshold {
    /// The default rule: growth above the path's floor, no decay margin.
    pub const GROWTH: Threshold = Threshold::Growth { floor: PATH_FLOOR, decay_margin: 0.0 };

    /// The largest growth per period ln max|μ| (−) that is not unstable at φ (rad/s).
    pub fn ln_limit(&self, phi: f64) -> f64 {
        match *self {
            Threshold::Growth { floor, decay_margin } => floor - decay_margin * std::f64::consts::TAU / phi,
            Threshold::Multiplier { tolerance } => tolerance.ln(),
        }
    }

    /// The largest max|μ| (−) that is not unstable at φ (rad/s).
    pub fn multiplier_limit(&self, phi: f64) -> f64 {
        self.ln_limit(phi).exp()
    }

    /// Whether a point at φ (rad/s) with growth per period `ln_max` is unstable; a NaN
    /// (no verdict) is not shown stable and counts as unstable.
    pub fn unstable(&self, phi: f64, ln_max: f64) -> bool {
        ln_max.is_nan() || ln_max > self.ln_limit(phi)
    }

    /// Whether this rule leaves no point unstable that the stricter of itself and the
    /// default rule would call unstable: the paper's tolerance has slack above the floor.
    pub fn has_slack(&self) -> bool {
        self.strict() != *self
    }

    /// The stricter of this rule and the default one ([`Threshold::GROWTH`]): a
    /// [`Threshold::Multiplier`] looser than the floor becomes the default rule; a
    /// growth rule (whose decay margin only makes it stricter) stays as it is.
    pub fn strict(&self) -> Threshold {
        match *self {
            Threshold::Multiplier { tolerance } if tolerance.ln() > PATH_FLOOR => Threshold::GROWTH,
            t => t,
        }
    }

    /// The rule in words, e.g. `ln max|mu| > 1e-6` or `max|mu| > 1.0001`.
    pub fn describe(&self) -> String {
        match *self {
            Threshold::Growth { floor, decay_margin } if decay_margin > 0.0 => {
                format!("ln max|mu| > {floor:e} - {decay_margin} 1/s * T")
            }
            Threshold::Growth { floor, .. } => format!("ln max|mu| > {floor:e}"),
            Threshold::Multiplier { tolerance } => format!("max|mu| > {tolerance}"),
        }
    }
}

/// When an unstable point or tongue counts.
///
/// A point is unstable by the `threshold` (module docs); it counts when its growth rate
/// ln(max|μ|)/T is also at least `min_growth_rate`. A tongue of the unstable set at β_op
/// counts when it contains a counted point and is at least `min_tongue_width` wide there.
/// Tongues are searched up to order `max_order` of (ω_i + ω_j)/k: stable bands are complete
/// up to that order. Tongues the criterion ignores are listed as such, never dropped.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct Criterion {
    /// The rule that makes a point unstable.
    pub threshold: Threshold,
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
            threshold: settings.threshold(),
            min_growth_rate: settings.min_growth_rate,
            min_tongue_width: settings.min_tongue_width,
            max_order: settings.max_tongue_order,
        }
    }

    /// Whether an evaluated point counts as unstable. A point without a verdict (failed
    /// monodromy) counts: it is not shown to be stable.
    pub fn counts(&self, p: &PointSummary) -> bool {
        // A failed point's ln max|μ| is f64::MAX, and a NaN is not shown stable.
        let unstable = self.threshold.unstable(p.phi, p.ln_max_multiplier);
        // A NaN growth rate (no verdict) counts too.
        unstable && (p.growth_rate >= self.min_growth_rate || p.growth_rate.is_nan())
    }

    /// The strict criterion beside this declared one: the stricter of its threshold and
    /// the default ([`Threshold::strict`]), and every unstable point and tongue counts (no
    /// growth-rate or width floor); the same order. Its band says how much of a declared
    /// band lies in the slack of the declared criterion.
    pub fn strict(&self) -> Criterion {
        Criterion { threshold: self.threshold.strict(), min_growth_rate: 0.0, min_tongue_width: 0.0, ..*self }
    }

    /// Whether the strict criterion is this one (nothing ignored, no slack in the
    /// threshold): its band is then the declared band, and needs no search of its own.
    pub fn is_strict(&self) -> bool {
        self.strict() == *self
    }

    /// Whether nothing is ignored (no growth-rate or width floor).
    pub fn ignores_nothing(&self) -> bool {
        self.min_growth_rate == 0.0 && self.min_tongue_width == 0.0
    }

    /// What a stable band at β_op guarantees, in words.
    pub fn guarantee(&self, level: f64) -> String {
        let mut s = format!(
            "no sum-type tongue (omega_f + omega_b)/k of order k <= {} with {}",
            self.max_order,
            self.threshold.describe()
        );
        if self.min_growth_rate > 0.0 {
            s += &format!(" and growth rate >= {} 1/s", self.min_growth_rate);
        }
        if self.min_tongue_width > 0.0 {
            s += &format!(" and width >= {} rad/s", self.min_tongue_width);
        }
        s + &format!(" at beta = {level}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn growth_threshold_scales_the_decay_margin_by_the_period() {
        let phi = std::f64::consts::TAU; // T = 1 s
        let t = Threshold::Growth { floor: 1e-6, decay_margin: 0.5 };
        assert!((t.ln_limit(phi) - (1e-6 - 0.5)).abs() < 1e-15);
        // Decaying at 0.4 1/s is too slow for a margin of 0.5 1/s; at 0.6 it is enough.
        assert!(t.unstable(phi, -0.4));
        assert!(!t.unstable(phi, -0.6));
        // An undamped point (|μ| = 1 to round-off) is stable without a margin.
        assert!(!Threshold::GROWTH.unstable(phi, 1e-13));
        assert!(Threshold::GROWTH.unstable(phi, 2e-6));
        assert!(Threshold::GROWTH.unstable(phi, f64::NAN));
    }

    #[test]
    fn the_papers_tolerance_has_slack_and_its_strict_rule_is_the_floor() {
        let paper = Threshold::Multiplier { tolerance: 1.0001 };
        assert!(paper.has_slack());
        assert_eq!(paper.strict(), Threshold::GROWTH);
        // A tolerance tighter than the floor is its own strict rule.
        let tight = Threshold::Multiplier { tolerance: 1.0 + 1e-8 };
        assert!(!tight.has_slack());
        assert!(!Threshold::GROWTH.has_slack());
        let margin = Threshold::Growth { floor: PATH_FLOOR, decay_margin: 0.1 };
        assert_eq!(margin.strict(), margin);
    }
}
