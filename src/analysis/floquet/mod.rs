//! Floquet stability of y′ = B(t)·y, B(t) = B0 + β·cos(φt)·B1 (Eq. 24–28).
//!
//! The monodromy Φ(T), T = 2π/φ, comes from one of two paths: the paper's DSTM
//! ([`dstm`], reference) or the fast CFM4 path ([`fast`]); both return a scaled product
//! e^{s}·Φ̂ so that strongly unstable points never overflow. Multipliers μ are the
//! eigenvalues of Φ(T); the point is unstable when max|μ| exceeds the tolerance
//! (1.0001 in the paper).

pub mod dstm;
pub mod fast;
pub mod product;

pub use product::ScaledProduct;

use super::reduction::{PeriodicSystem, ReducedModel, ReductionInfo};
use super::{AnalysisError, MonodromyMethod, Rotor, Settings};
use fast::{PhiTable, Symmetry};
use serde::Serialize;

/// Aliased orders kept clear of the step rate: a combination of two whirls may lie at
/// most at (N − 1 − ALIAS_ORDERS)·φ, so the aliased tongues nearest to it are at least of
/// order 4, as thin as the physical tongues the criterion's search reaches at β ≤ 1.
pub const ALIAS_ORDERS: usize = 4;
/// Relative margin of 2ω_max/φ below the step rate: the whirls drift under the static and
/// parametric load, and the margin keeps them away from the aliased resonance.
pub const ALIAS_MARGIN: f64 = 1.1;

/// Largest |ln max|μ|| reported as a plain `max_multiplier`; beyond it the value is
/// saturated to f64::MAX and only the logarithm is exact.
const LN_F64_MAX: f64 = 709.0;

/// Outcome of one (φ, β) point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PointStatus {
    /// Multipliers computed.
    Ok,
    /// The per-φ interpolant did not converge to its tolerance (result still computed,
    /// but less accurate than stated).
    Inaccurate,
    /// The eigenvalue iteration failed or the monodromy was not finite: no verdict.
    Failed,
}

/// The scalar outcome of one (φ, β) point: what a chart stores.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PointSummary {
    /// Excitation frequency φ (rad/s).
    pub phi: f64,
    /// Dynamic load coefficient β (−).
    pub beta: f64,
    /// max|μ| (saturated at f64::MAX beyond e^709; see `ln_max_multiplier`).
    pub max_multiplier: f64,
    /// ln max|μ|, exact even when max|μ| would overflow.
    pub ln_max_multiplier: f64,
    /// Growth rate ln(max|μ|)/T (1/s).
    pub growth_rate: f64,
    /// max|μ| ≤ tolerance.
    pub stable: bool,
    /// Whether the point was computed normally.
    pub status: PointStatus,
}

/// Floquet result at one point: the summary and all multipliers.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FloquetPoint {
    /// φ, β, max|μ|, growth rate, verdict, status.
    #[serde(flatten)]
    pub summary: PointSummary,
    /// Multipliers e^{s}·(re, im) with s = `multiplier_log_scale` (0 unless huge).
    pub multipliers: Vec<[f64; 2]>,
    /// Natural-log scale factor of `multipliers`.
    pub multiplier_log_scale: f64,
}

impl FloquetPoint {
    fn failed(phi: f64, beta: f64) -> FloquetPoint {
        FloquetPoint {
            summary: PointSummary {
                phi,
                beta,
                max_multiplier: f64::MAX,
                ln_max_multiplier: f64::MAX,
                growth_rate: f64::MAX,
                stable: false,
                status: PointStatus::Failed,
            },
            multipliers: Vec::new(),
            multiplier_log_scale: 0.0,
        }
    }

    /// Multipliers and verdict from a monodromy.
    pub fn from_monodromy(
        phi: f64,
        beta: f64,
        mono: &ScaledProduct,
        tolerance: f64,
        status: PointStatus,
    ) -> FloquetPoint {
        let mut balanced = mono.matrix.clone();
        crate::linalg::balance(&mut balanced);
        let Ok(ev) = balanced.eigenvalues() else {
            return FloquetPoint::failed(phi, beta);
        };
        if ev.iter().any(|z| !z.re.is_finite() || !z.im.is_finite()) || !mono.log_scale.is_finite() {
            return FloquetPoint::failed(phi, beta);
        }
        let max_scaled = ev.iter().map(|z| z.norm()).fold(0.0, f64::max);
        let ln_max = max_scaled.ln() + mono.log_scale;
        let period = 2.0 * std::f64::consts::PI / phi;
        let (multipliers, multiplier_log_scale) = if mono.log_scale.abs() < LN_F64_MAX / 2.0 {
            let f = mono.log_scale.exp();
            (ev.iter().map(|z| [z.re * f, z.im * f]).collect(), 0.0)
        } else {
            (ev.iter().map(|z| [z.re, z.im]).collect(), mono.log_scale)
        };
        FloquetPoint {
            summary: PointSummary {
                phi,
                beta,
                max_multiplier: if ln_max < LN_F64_MAX { ln_max.exp() } else { f64::MAX },
                ln_max_multiplier: ln_max,
                growth_rate: ln_max / period,
                stable: ln_max <= tolerance.ln(),
                status,
            },
            multipliers,
            multiplier_log_scale,
        }
    }
}

/// A rotor prepared for Floquet analysis at one speed: reduced model, B0, B1, X.
#[derive(Debug, Clone)]
pub struct FloquetSystem {
    /// The reduced model.
    pub reduced: ReducedModel,
    /// B0, B1 at the speed.
    pub system: PeriodicSystem,
    /// The transpose symmetry used by the fast path.
    pub symmetry: Symmetry,
    /// Speed Ω (rad/s).
    pub speed: f64,
    /// Settings in force.
    pub settings: Settings,
}

impl FloquetSystem {
    /// Reduce the rotor to `settings.reduced_modes` modes at `speed` (rad/s).
    pub fn new(rotor: &Rotor, settings: &Settings, speed: f64) -> Result<FloquetSystem, AnalysisError> {
        let reduced = ReducedModel::new(rotor, settings.reduced_modes)?;
        let system = reduced.periodic_system(speed);
        let symmetry = Symmetry::new(&system);
        Ok(FloquetSystem { reduced, system, symmetry, speed, settings: settings.clone() })
    }

    /// Eigenvalues λ of B0 (the reduced model at the static load), sorted by |Im λ|:
    /// the whirls whose sums (ω_i + ω_j)/k are where instability regions start.
    pub fn eigenvalues(&self) -> Result<Vec<faer::c64>, AnalysisError> {
        // B0 holds ω² next to 1: balance first, or λ is accurate only to ~ε·ω².
        let mut b0 = self.system.b0.clone();
        crate::linalg::balance(&mut b0);
        let mut ev = b0.eigenvalues().map_err(|_| {
            AnalysisError::Linalg(crate::linalg::LinalgError::NoConvergence { what: "reduced state matrix" })
        })?;
        ev.sort_by(|a, b| a.im.abs().total_cmp(&b.im.abs()).then(a.im.total_cmp(&b.im)));
        Ok(ev)
    }

    /// Forward (Im λ > 0) and backward whirl frequencies of the reduced model (rad/s),
    /// each ascending.
    pub fn whirls(&self) -> Result<(Vec<f64>, Vec<f64>), AnalysisError> {
        let ev = self.eigenvalues()?;
        let f = ev.iter().filter(|z| z.im > 0.0).map(|z| z.im).collect();
        let b = ev.iter().filter(|z| z.im < 0.0).map(|z| -z.im).collect();
        Ok((f, b))
    }

    /// Reduction summary.
    pub fn info(&self) -> ReductionInfo {
        self.reduced.info()
    }

    /// The per-φ table of the fast path for loads up to `beta_max`.
    pub fn table(&self, phi: f64, beta_max: f64) -> PhiTable {
        PhiTable::new(&self.system, phi, beta_max, self.steps_for(phi))
    }

    /// CFM4 steps per period at φ: the configured minimum, or more so that each step
    /// spans at most `max_step_phase` of the lowest basis mode, and so that no
    /// combination of two basis whirls resonates with the step rate.
    ///
    /// The step rule sees the excitation cos φt only at N points per period, so the
    /// discrete system is also excited at (mN ± l)·φ: a combination ω_i + ω_j near
    /// (N − l)·φ gives a tongue of order-l strength that the continuous system does not
    /// have (seen at φ = 1125 rad/s on the open rotor with M = 8: the 17 443 rad/s whirl at
    /// 2ω₇ = 31φ with N = 32 steps gave max|μ| = 1.0012 at β = 0.1, where the DSTM gives
    /// 1). So N − [`ALIAS_ORDERS`] must exceed 2ω_max/φ with [`ALIAS_MARGIN`] to spare.
    pub fn steps_for(&self, phi: f64) -> usize {
        let freqs = &self.reduced.frequencies;
        let w_min = freqs.iter().copied().fold(f64::INFINITY, f64::min);
        let w_max = freqs.iter().copied().fold(0.0, f64::max);
        let period = 2.0 * std::f64::consts::PI / phi;
        let by_phase = (period * w_min / self.settings.max_step_phase).ceil();
        let by_alias = (ALIAS_MARGIN * 2.0 * w_max / phi).ceil() + ALIAS_ORDERS as f64;
        let needed = by_phase.max(by_alias);
        self.settings.steps_per_period.max(if needed.is_finite() { needed.min(1e6) as usize } else { 0 })
    }

    /// One point with the configured method.
    pub fn point(&self, phi: f64, beta: f64) -> FloquetPoint {
        match self.settings.method {
            MonodromyMethod::Fast => self.point_fast(&self.table(phi, beta), beta),
            MonodromyMethod::Dstm => self.point_dstm(phi, beta, self.settings.reference_steps),
        }
    }

    /// One point from a prepared per-φ table (β ≤ the table's β_max).
    pub fn point_fast(&self, table: &PhiTable, beta: f64) -> FloquetPoint {
        self.point_of(table, &table.monodromy(&self.symmetry, beta), beta)
    }

    /// The point of a monodromy computed from `table` at β (for callers that also need
    /// the monodromy itself).
    pub fn point_of(&self, table: &PhiTable, mono: &ScaledProduct, beta: f64) -> FloquetPoint {
        let status = if table.converged { PointStatus::Ok } else { PointStatus::Inaccurate };
        FloquetPoint::from_monodromy(table.phi, beta, mono, self.settings.instability_tolerance, status)
    }

    /// One point by the reference DSTM with `steps` steps.
    pub fn point_dstm(&self, phi: f64, beta: f64, steps: usize) -> FloquetPoint {
        let mono = dstm::monodromy_dstm(&self.system, phi, beta, steps);
        FloquetPoint::from_monodromy(phi, beta, &mono, self.settings.instability_tolerance, PointStatus::Ok)
    }

    /// A row of points at one φ for several β, sharing the per-φ work.
    pub fn row(&self, phi: f64, betas: &[f64]) -> Vec<FloquetPoint> {
        match self.settings.method {
            MonodromyMethod::Fast => {
                let beta_max = betas.iter().fold(0.0f64, |m, b| m.max(b.abs()));
                let table = self.table(phi, beta_max);
                betas.iter().map(|&b| self.point_fast(&table, b)).collect()
            }
            MonodromyMethod::Dstm => {
                betas.iter().map(|&b| self.point_dstm(phi, b, self.settings.reference_steps)).collect()
            }
        }
    }
}
