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
//! let request = BandRequest::builder().range(Interval::new(100.0, 8000.0)).phi_op(1230.0).level(0.3).build();
//! let band = op.band(&request.unwrap()).unwrap();
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

/// A regular chart grid by its named values (rad/s and −), checked when it is built
/// ([`ChartGrid::validate`], [`ChartGrid::build`]): `ChartRequest::grid().phi(…)
/// .phi_step(…).beta_max(…).beta_step(…).build()`. Every value is required: one not set
/// is refused ([`limits::Rule::NotSet`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ChartGrid {
    phi: Option<Interval>,
    phi_step: Option<f64>,
    beta_max: Option<f64>,
    beta_step: Option<f64>,
}

impl ChartGrid {
    /// The φ range of the grid (rad/s).
    pub fn phi(self, phi: Interval) -> ChartGrid {
        ChartGrid { phi: Some(phi), ..self }
    }
    /// The φ step (rad/s): φ runs `phi.lo, phi.lo + phi_step, … ≤ phi.hi`.
    pub fn phi_step(self, phi_step: f64) -> ChartGrid {
        ChartGrid { phi_step: Some(phi_step), ..self }
    }
    /// The largest load β (−): β runs `0, beta_step, … ≤ beta_max`.
    pub fn beta_max(self, beta_max: f64) -> ChartGrid {
        ChartGrid { beta_max: Some(beta_max), ..self }
    }
    /// The β step (−).
    pub fn beta_step(self, beta_step: f64) -> ChartGrid {
        ChartGrid { beta_step: Some(beta_step), ..self }
    }
    /// The grid's axes, each value checked by the parameter rules
    /// ([`crate::analysis::limits`]) and each axis's length bounded.
    fn axes(&self) -> Result<(Vec<f64>, Vec<f64>), ParamError> {
        let phi = limits::required(Quantity::RangeLow, self.phi)?;
        let phi = limits::phi_range(phi.lo, phi.hi)?;
        let phi_step = limits::positive(Quantity::Frequency, limits::required(Quantity::Frequency, self.phi_step)?)?;
        let beta_max = limits::beta_max(limits::required(Quantity::BetaMax, self.beta_max)?)?;
        let beta_step = limits::positive(Quantity::Load, limits::required(Quantity::Load, self.beta_step)?)?;
        let axis = |lo: f64, hi: f64, step: f64| -> Result<Vec<f64>, ParamError> {
            let grid = Interval::new(lo, hi);
            limits::count(grid.step_count(step) as u64, 1, MAX_CHART_AXIS as u64)?;
            // Within the bound just checked: never the empty default.
            Ok(grid.stepped(step, MAX_CHART_AXIS).unwrap_or_default())
        };
        Ok((axis(phi.lo, phi.hi, phi_step)?, axis(0.0, beta_max, beta_step)?))
    }
    /// Check the values without building the grid.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.axes().map(|_| ())
    }
    /// The checked request.
    pub fn build(self) -> Result<ChartRequest, ParamError> {
        let (phis, betas) = self.axes()?;
        ChartRequest::values(phis, betas)
    }
}

impl ChartRequest {
    /// A regular grid, built by named values ([`ChartGrid`]).
    pub fn grid() -> ChartGrid {
        ChartGrid::default()
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
    /// A request by named values ([`BandRequestBuilder`]).
    pub fn builder() -> BandRequestBuilder {
        BandRequestBuilder::default()
    }

    /// A request checked by the parameter rules: a φ range, φ_op inside it, a level up to
    /// the largest load.
    pub(crate) fn new(range: Interval, phi_op: f64, level: f64) -> Result<BandRequest, ParamError> {
        let range = limits::phi_range(range.lo, range.hi)?;
        let phi_op = limits::phi_op(phi_op, range)?;
        let level = limits::level(level, limits::MAX_BETA)?;
        Ok(BandRequest { range, phi_op, level })
    }

    /// The φ range searched (rad/s).
    pub fn range(&self) -> Interval {
        self.range
    }
    /// φ_op (rad/s).
    pub fn phi_op(&self) -> f64 {
        self.phi_op
    }
    /// β_op (−).
    pub fn level(&self) -> f64 {
        self.level
    }
}

/// A [`BandRequest`] by named values, checked when it is built: `BandRequest::builder()
/// .phi_op(1230.0).level(0.3).build()`. The range defaults to that of `rotorshunt band`
/// ([`DEFAULT_BAND_RANGE`]); φ_op and the level are required (one not set is refused,
/// [`limits::Rule::NotSet`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BandRequestBuilder {
    range: Interval,
    phi_op: Option<f64>,
    level: Option<f64>,
}

/// The φ range a band is searched over when none is given (rad/s): that of `[design]`
/// and of a study's cases, wide enough for every tongue of a machinery rotor whose whirls
/// lie below 4 000 rad/s. (`rotorshunt band` searches φ_op/20 to 20·φ_op by default.)
pub const DEFAULT_BAND_RANGE: Interval = Interval { lo: 100.0, hi: 8000.0 };

impl Default for BandRequestBuilder {
    fn default() -> BandRequestBuilder {
        BandRequestBuilder { range: DEFAULT_BAND_RANGE, phi_op: None, level: None }
    }
}

impl BandRequestBuilder {
    /// The φ range searched (rad/s), containing φ_op.
    pub fn range(self, range: Interval) -> BandRequestBuilder {
        BandRequestBuilder { range, ..self }
    }
    /// The operating excitation frequency φ_op (rad/s).
    pub fn phi_op(self, phi_op: f64) -> BandRequestBuilder {
        BandRequestBuilder { phi_op: Some(phi_op), ..self }
    }
    /// The level β_op of the band (−).
    pub fn level(self, level: f64) -> BandRequestBuilder {
        BandRequestBuilder { level: Some(level), ..self }
    }
    /// Check the values by the parameter rules.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.build().map(|_| ())
    }
    /// The checked request.
    pub fn build(self) -> Result<BandRequest, ParamError> {
        let phi_op = limits::required(Quantity::OperatingFrequency, self.phi_op)?;
        BandRequest::new(self.range, phi_op, limits::required(Quantity::Level, self.level)?)
    }
}
