//! Settings of the region search: tolerances, steps and margins, each default with its
//! reason.

use serde::{Deserialize, Serialize};

/// The load at which a region's tip is searched, above a bracketed β_c(seed):
/// β = β_c·(1 + `relative`) + `absolute`. The region is a short interval there whose growth
/// maximum is the start, biased by at most its half-width.
///
/// Recorded in outputs as the array `[relative, absolute]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(into = "(f64, f64)", from = "(f64, f64)")]
pub struct TipMargin {
    /// Part proportional to β_c (−).
    pub relative: f64,
    /// Constant part (−).
    pub absolute: f64,
}

impl TipMargin {
    /// The search load above `beta` (−).
    pub fn above(&self, beta: f64) -> f64 {
        beta * (1.0 + self.relative) + self.absolute
    }
}

impl From<(f64, f64)> for TipMargin {
    fn from((relative, absolute): (f64, f64)) -> TipMargin {
        TipMargin { relative, absolute }
    }
}

impl From<TipMargin> for (f64, f64) {
    fn from(m: TipMargin) -> (f64, f64) {
        (m.relative, m.absolute)
    }
}

/// The largest φ step of a march to a region's edge: the larger of `absolute` (rad/s) and
/// `relative`·φ. A stable gap between two tongues at least this wide is never stepped over.
///
/// Recorded in outputs as the array `[absolute, relative]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(into = "(f64, f64)", from = "(f64, f64)")]
pub struct EdgeStep {
    /// Floor of the step (rad/s).
    pub absolute: f64,
    /// Step relative to φ (−).
    pub relative: f64,
}

impl EdgeStep {
    /// The largest step at φ (rad/s).
    pub fn at(&self, phi: f64) -> f64 {
        self.absolute.max(self.relative * phi.abs())
    }
}

impl From<(f64, f64)> for EdgeStep {
    fn from((absolute, relative): (f64, f64)) -> EdgeStep {
        EdgeStep { absolute, relative }
    }
}

impl From<EdgeStep> for (f64, f64) {
    fn from(s: EdgeStep) -> (f64, f64) {
        (s.absolute, s.relative)
    }
}

/// Settings of the region analysis; a problem file may set any of them in `[regions]`
/// (the others keep their defaults).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RegionSettings {
    /// Bracketing step in β (−): β is sampled upward from 0 at this step until the first
    /// unstable sample; an unstable band thinner than this in β can be stepped over.
    pub beta_bracket: f64,
    /// Bisection tolerance on β (−).
    pub beta_tolerance: f64,
    /// Bisection tolerance on φ for region edges (rad/s).
    pub phi_tolerance: f64,
    /// Highest order k of the predicted region starts (ω_i + ω_j)/k.
    pub max_order: usize,
    /// Number of β levels of the boundary tracking between the onset and β_max.
    pub tracking_levels: usize,
    /// Most refinement steps of the tip search once its maximum is bracketed (parabolic,
    /// or golden section where the parabola does not help).
    pub tip_iterations: usize,
    /// The tip search stops when its bracket is narrower than this, relative to φ.
    pub tip_tolerance: f64,
    /// The load of the tip search above β_c(seed).
    pub tip_margin: TipMargin,
    /// Relative spacing g of the guard lattice (1 + g)^n at the level (0 turns it off):
    /// an unstable lattice point outside every seeded tongue is a tongue no seed found,
    /// reported as unexplained. The band's march from φ_op visits the same points.
    pub guard_step: f64,
    /// Secant iterations of the centre search.
    pub centre_iterations: usize,
    /// Largest φ step when marching to a region's edge.
    pub edge_step: EdgeStep,
}

impl RegionSettings {
    /// Whether every setting has its default (a file without `[regions]`).
    pub fn is_default(&self) -> bool {
        *self == RegionSettings::default()
    }

    /// Tight tolerances for finite-difference sensitivities: quantities must be resolved
    /// far below their change over the step (start to ~1e-8·φ, β to 1e-8).
    pub fn precise() -> RegionSettings {
        RegionSettings {
            beta_tolerance: 1e-10,
            phi_tolerance: 1e-5,
            tip_iterations: 60,
            tip_tolerance: 1e-9,
            tip_margin: TipMargin { relative: 1e-4, absolute: 1e-8 },
            ..RegionSettings::default()
        }
    }
}

impl Default for RegionSettings {
    fn default() -> Self {
        RegionSettings {
            // 1/32: regions are wedges opening upward, so only a stable hole thinner than
            // 0.031 in β inside a region can be stepped over — finer than the 0.025 β step
            // of the paper's charts.
            beta_bracket: 1.0 / 32.0,
            // 1e-4: below the resolution any chart of the paper shows (0.025 in β).
            beta_tolerance: 1e-4,
            // 0.2 rad/s: five times finer than the 1 rad/s grid the edges are checked on.
            phi_tolerance: 0.2,
            max_order: 2,
            tracking_levels: 12,
            // 8: parabolic steps converge in 3–5 on a smooth dome; golden steps take over
            // where the region is narrower than the climb's first step.
            tip_iterations: 8,
            // 1e-5: a hundredth of the 0.1 % the starts are checked to.
            tip_tolerance: 1e-5,
            // 5 % + 0.002: a region wide enough for the climb's first steps to see its dome,
            // while the bias (at most its half-width there) stays far below the 0.1 % the
            // start is checked to.
            tip_margin: TipMargin { relative: 0.05, absolute: 2e-3 },
            // 0.5 %: a tongue the seeds missed that is wider than 0.5 % of φ at the level
            // cannot hide between two lattice points (~880 points over 100..8000 rad/s,
            // of which only those in stable bands are evaluated).
            guard_step: 0.005,
            // 3: from the seed the first secant step lands inside a drifted tongue in the
            // cases examined; two more absorb a misidentified first step.
            centre_iterations: 3,
            // 2 rad/s or 0.2 %: below 1000 rad/s twice the 1 rad/s grid the edges are
            // checked on (0.5 % let a gap at 4768 rad/s on Fig. 11 be stepped over).
            edge_step: EdgeStep { absolute: 2.0, relative: 2e-3 },
        }
    }
}
