//! The library's face for one operating speed: the rotor's whirls and its reduced
//! periodic system, with the questions an engineer asks of them (a stability chart, the
//! catalogue of regions, the stable band around an operating frequency) as methods taking
//! validated requests.
//!
//! ```
//! use rotorshunt::{BandRequest, Interval, Problem};
//!
//! let problem = Problem::from_path("problems/fig11-closed-2000.toml", &[]).unwrap();
//! let op = problem.operating_point().unwrap(); // at the file's speed, 2000 rad/s
//! let band = op.band(&BandRequest::new(Interval::new(100.0, 8000.0), 1230.0, 0.3).unwrap()).unwrap();
//! let b = band.band.unwrap();
//! assert!(b.lo < 1230.0 && 1230.0 < b.hi);
//! ```

use super::chart::{chart, ChartResult};
use super::limits::{self, ParamError, Quantity};
use super::modes::{whirl_modes_of, ModesResult};
use super::regions::{band, catalogue, Band, Catalogue, CatalogueRequest, RegionSettings};
use super::{floquet::FloquetSystem, AnalysisError, Interval, Rotor, Settings};

/// Most points along either axis of a [`ChartRequest`]: a 1 rad/s grid over the widest
/// φ ratio the limits admit stays far below it, and a chart this large already takes hours.
pub const MAX_CHART_AXIS: usize = 1_000_000;

/// The rotor at one speed Ω: its whirls (full model) and its reduced periodic system
/// (Eq. 22–24), built once and shared by every question asked at that speed.
#[derive(Debug, Clone)]
pub struct OperatingPoint {
    /// Speed Ω (rad/s).
    pub speed: f64,
    /// Whirl modes of the full model at Ω, with the static load αP_cr.
    pub modes: ModesResult,
    /// The reduced periodic system whose monodromy gives the Floquet multipliers.
    pub floquet: FloquetSystem,
    /// The region search's numerical settings (defaults unless replaced).
    pub regions: RegionSettings,
}

impl OperatingPoint {
    /// Whirls and the reduced system of `rotor` at speed Ω (rad/s).
    pub fn new(rotor: &Rotor, settings: &Settings, speed: f64) -> Result<OperatingPoint, AnalysisError> {
        let speed = limits::speed(speed)?;
        Ok(OperatingPoint {
            speed,
            modes: whirl_modes_of(rotor, settings, speed)?,
            floquet: FloquetSystem::new(rotor, settings, speed)?,
            regions: RegionSettings::default(),
        })
    }

    /// The stability chart on the request's grid (Figs. 8–13), points in parallel.
    pub fn chart(&self, req: &ChartRequest) -> ChartResult {
        chart(&self.floquet, &req.phis, &req.betas, &|| {})
    }

    /// The catalogue of regions over the request's φ range.
    pub fn catalogue(&self, req: &CatalogueRequest) -> Result<Catalogue, AnalysisError> {
        catalogue(&self.floquet, &self.modes, &self.regions, req)
    }

    /// The stable band around the request's φ_op at its level.
    pub fn band(&self, req: &BandRequest) -> Result<Band, AnalysisError> {
        band(&self.floquet, &self.modes, &self.regions, req.range, req.phi_op, req.level)
    }
}

/// The grid of a stability chart: excitation frequencies φ (rad/s) × load levels β (−).
#[derive(Debug, Clone, PartialEq)]
pub struct ChartRequest {
    phis: Vec<f64>,
    betas: Vec<f64>,
}

impl ChartRequest {
    /// The grid `phi.lo, phi.lo + phi_step, … ≤ phi.hi` × `0, beta_step, … ≤ beta_max`
    /// (rad/s and −), each checked by the parameter rules ([`crate::analysis::limits`]).
    pub fn grid(phi: Interval, phi_step: f64, beta_max: f64, beta_step: f64) -> Result<ChartRequest, ParamError> {
        let phi = limits::phi_range(phi.lo, phi.hi)?;
        let phi_step = limits::positive(Quantity::Frequency, phi_step)?;
        let beta_max = limits::beta_max(beta_max)?;
        let beta_step = limits::positive(Quantity::Load, beta_step)?;
        let axis = |lo: f64, hi: f64, step: f64| -> Result<Vec<f64>, ParamError> {
            let n = ((hi - lo) / step + 1e-9).floor() + 1.0;
            let n = limits::count(n as u64, 1, MAX_CHART_AXIS as u64)? as usize;
            Ok((0..n).map(|i| lo + step * i as f64).collect())
        };
        ChartRequest::values(axis(phi.lo, phi.hi, phi_step)?, axis(0.0, beta_max, beta_step)?)
    }

    /// A grid of given values: every φ a frequency (rad/s), every β a load (−).
    pub fn values(phis: Vec<f64>, betas: Vec<f64>) -> Result<ChartRequest, ParamError> {
        for &p in &phis {
            limits::frequency(Quantity::Frequency, p)?;
        }
        for &b in &betas {
            limits::load(b)?;
        }
        limits::count(phis.len() as u64, 1, MAX_CHART_AXIS as u64)?;
        limits::count(betas.len() as u64, 1, MAX_CHART_AXIS as u64)?;
        Ok(ChartRequest { phis, betas })
    }

    /// The φ values (rad/s).
    pub fn phis(&self) -> &[f64] {
        &self.phis
    }

    /// The β values (−).
    pub fn betas(&self) -> &[f64] {
        &self.betas
    }
}

/// The stable band asked for: around φ_op (rad/s) at level β_op (−), searched over a φ
/// range (rad/s) that contains φ_op.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandRequest {
    range: Interval,
    phi_op: f64,
    level: f64,
}

impl BandRequest {
    /// A request checked by the parameter rules: a φ range, φ_op inside it, a level up to
    /// the largest load.
    pub fn new(range: Interval, phi_op: f64, level: f64) -> Result<BandRequest, ParamError> {
        let range = limits::phi_range(range.lo, range.hi)?;
        let phi_op = limits::phi_op(phi_op, range)?;
        let level = limits::level(level, limits::MAX_BETA)?;
        Ok(BandRequest { range, phi_op, level })
    }
}
