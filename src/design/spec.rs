//! The design problem of a problem file's `[design]` table, validated: objective, load
//! level, operating speeds and bands, and the circuit variables with their bounds.

use crate::analysis::limits::{self, ParamError, Quantity};
use crate::analysis::Interval;
pub use crate::design::objective::ObjectiveKind;
use crate::design::objective::{AnyObjective, ObjectiveKeys};
pub use crate::design::tolerance::Tolerances;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// Where and over which speeds an unbalance response is judged (`[design.response]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Response {
    /// The shaft node whose amplitude counts (0 to the number of shaft elements).
    pub node: usize,
    /// The speed range [lo, hi] (rad/s), lo < hi.
    pub speeds: Interval,
    /// Grid speeds over the range, ends included (≥ 3); the peaks between grid speeds are
    /// refined on the analytic response.
    pub points: usize,
}

impl Response {
    /// The speed grid (rad/s): `points` equally spaced speeds from lo to hi.
    pub fn grid(&self) -> Vec<f64> {
        let n = self.points.max(2);
        (0..n).map(|i| self.speeds.lo + (self.speeds.hi - self.speeds.lo) * i as f64 / (n - 1) as f64).collect()
    }
}

/// A stable band around φ_op at β_op at least `width` wide at every operating speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BandWidth {
    /// φ_op (rad/s).
    pub phi_op: f64,
    /// The least width (rad/s), > 0.
    pub width: f64,
}

/// A damping-ratio floor: ζ = −Re λ/|λ| of the whirl tagged `mode` (as `rotorshunt modes`
/// and `damping` tag it at the first operating speed) at least `min` at every operating
/// speed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DampingFloor {
    /// The whirl's tag, e.g. `f1`, `br1`.
    pub mode: String,
    /// The least ζ (−), in [0, 1).
    pub min: f64,
}

/// `[design.margins]`: the stable band around φ_op must hold for every load up to
/// (1 + `beta`)·β_op, with φ_op at least `phi` from each of its edges there (issue 27,
/// point 1). Judged on the band around φ_op at the margin level (1 + `beta`)·β_op: a
/// tongue whose onset lies below that load is in the unstable set there, so a band at
/// the margin level has no counted tongue with a lower onset reaching into it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MarginSpec {
    /// The load margin m (−, relative to β_op), ≥ 0.
    pub beta: f64,
    /// The frequency margin (rad/s), ≥ 0: φ_op − lo and hi − φ_op at the margin level.
    pub phi: f64,
}

impl MarginSpec {
    /// The margin level (1 + m)·β_op (−).
    pub fn level(&self, level: f64) -> f64 {
        (1.0 + self.beta) * level
    }
}

/// Constraints a design of any objective must meet (`[design.constraints]`, and
/// `[[design.bands]]` for the objectives other than clear-bands).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Constraints {
    /// Operating bands kept clear at β_op by their clearance (the true unstable set).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bands: Vec<Band>,
    /// A stable band around φ_op of at least a width.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub min_band_width: Option<BandWidth>,
    /// The largest unbalance amplitude (m) at the response node over the response speeds
    /// at most this; needs [`DesignSpec::response`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_peak: Option<f64>,
    /// Damping-ratio floors of named whirls.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub damping: Vec<DampingFloor>,
    /// Load and frequency margins of the band around φ_op (`[design.margins]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub margins: Option<MarginSpec>,
}

impl Constraints {
    /// Whether there is no constraint.
    pub fn is_empty(&self) -> bool {
        self.bands.is_empty()
            && self.min_band_width.is_none()
            && self.max_peak.is_none()
            && self.damping.is_empty()
            && self.margins.is_none()
    }

    /// Whether a constraint needs the Floquet analysis (bands, a band width or margins).
    pub fn needs_stability(&self) -> bool {
        !self.bands.is_empty() || self.min_band_width.is_some() || self.margins.is_some()
    }
}

/// A circuit parameter a design may change (the model's: [`Branch::set`] sets it).
///
/// [`Branch::set`]: crate::model::Branch::set
pub use crate::model::Parameter;

/// One design variable: a parameter of one branch with bounds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Variable {
    /// The ring (model order) whose branch this is; `None`: the branch of every ring
    /// (their circuits are identical, as in the shorthand).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ring: Option<usize>,
    /// The ring's name, for reports (with `ring`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ring_name: Option<String>,
    /// Branch index, 0-based (`branch = 1` in the file is index 0).
    pub branch: usize,
    /// Which branch parameter (C_f, L, ω or R).
    pub parameter: Parameter,
    /// Lower bound (SI unit of the parameter).
    pub min: f64,
    /// Upper bound (SI unit of the parameter), above `min`.
    pub max: f64,
}

impl Variable {
    /// The value → the unit interval: u = 0 at `min`, 1 at `max` (log or linear).
    pub fn to_unit(&self, value: f64) -> f64 {
        if self.parameter.logarithmic() {
            (value / self.min).ln() / (self.max / self.min).ln()
        } else {
            (value - self.min) / (self.max - self.min)
        }
    }

    /// The unit interval → the value (inverse of [`Variable::to_unit`]).
    pub fn from_unit(&self, u: f64) -> f64 {
        if self.parameter.logarithmic() {
            self.min * (self.max / self.min).powf(u)
        } else {
            self.min + (self.max - self.min) * u
        }
    }

    /// Name for reports, e.g. `branch 1 tuning_frequency` (or `ring drive branch 1 …`).
    pub fn name(&self) -> String {
        match &self.ring_name {
            Some(r) => format!("ring {r} branch {} {}", self.branch + 1, self.parameter.key()),
            None => format!("branch {} {}", self.branch + 1, self.parameter.key()),
        }
    }
}

/// An operating band [lo, hi] (rad/s) that must be free of instability at β_op, with
/// `clearance` (rad/s) on each side.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Band {
    /// Lower end (rad/s).
    pub lo: f64,
    /// Upper end (rad/s).
    pub hi: f64,
    /// Required clearance on both sides (rad/s).
    pub clearance: f64,
}

impl Band {
    /// The band widened by its clearance: no unstable φ may lie in it (rad/s).
    pub fn guarded(&self) -> Interval {
        Interval::new(self.lo - self.clearance, self.hi + self.clearance)
    }
}

/// A validated design problem.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignSpec {
    /// The objective and its data (a type of [`crate::design::objective`], e.g.
    /// [`crate::design::objective::widest_band::WidestStableBand`]).
    pub objective: AnyObjective,
    /// β_op (−).
    pub level: f64,
    /// φ range of the catalogues and band searches (rad/s).
    pub phi_range: (f64, f64),
    /// β_max of the catalogues (−).
    pub beta_max: f64,
    /// Operating speeds Ω (rad/s); the file's `speed` if not given.
    pub speeds: Vec<f64>,
    /// Design variables: branch parameters with bounds (at least one).
    pub variables: Vec<Variable>,
    /// Nelder–Mead starts run in parallel (multi-start), 1–64.
    pub starts: usize,
    /// Nelder–Mead iterations per start, or sequential convex steps.
    pub max_iterations: usize,
    /// `[design.response]` of an objective other than min-peak-response (which carries
    /// its own): judged by the peak constraint and reported before and after; see
    /// [`DesignSpec::response`].
    pub response: Option<Response>,
    /// Constraints on the result, whatever the objective.
    pub constraints: Constraints,
    /// The range of operating speeds (`design.speed_range`, rad/s): `speeds` is then its
    /// grid ([`range_speeds`]), refined near the worst speed by the widest-band objective
    /// and verified on a finer grid ([`VERIFY_SPEEDS`]).
    pub speed_range: Option<Interval>,
    /// Component tolerances (`[design.tolerances]`): the objective and constraints judged
    /// at the worst corner of the tolerance box, the result checked by Monte Carlo.
    pub tolerances: Option<Tolerances>,
    /// The unit the operating speeds are shown in (rpm when the file gave them in rpm,
    /// [`crate::problem::Problem::speed_unit`]); display only, not in the JSON.
    pub speed_unit: crate::numbers::SpeedUnit,
    /// The report's before/after charts: φ points and β points
    /// (`design.chart_phi_points`, `design.chart_beta_points`; [`CHART_GRID`] by default).
    /// They draw what the design is; the design and its verification do not read them.
    pub chart_grid: (usize, usize),
    /// Whether the verification checks the tuned design again on a basis twice as large
    /// (`design.refined_check`, default true; `crate::design::sizing::refined_check`).
    /// Off, that part is not applicable and says so: a quick look at a design, not one to
    /// hand on.
    pub refined_check: bool,
    /// Whether the local searches start from the best distinct basins of a map of the
    /// objective over the whole box (`design.map`, default true; the starts beyond the
    /// reference and the physics seed), or, off, from the first points of the Halton set
    /// as before the map: the reference path the `design` bench compares it with.
    pub map: bool,
    /// The page-one warning thresholds (`[design.warnings]`): what the report calls an
    /// answer on an edge. Display only: the design does not read them.
    pub warnings: WarningLevels,
}

/// A load margin under this (−, onset/β_op − 1) is warned on page one by default: a load
/// 10 % above β_op opens a tongue inside the band.
pub const LOAD_MARGIN_WARNING: f64 = 0.10;
/// A frequency margin min(φ_op − lo, hi − φ_op) under this share of φ_op (−) is warned on
/// page one by default: a drift of the operating frequency by 5 % leaves the band.
pub const FREQUENCY_MARGIN_WARNING: f64 = 0.05;

/// The thresholds under which page one warns of a margin (`[design.warnings]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WarningLevels {
    /// A load margin (−, onset/β_op − 1) under this is warned
    /// (`design.warnings.load_margin`, default [`LOAD_MARGIN_WARNING`]).
    pub load_margin: f64,
    /// A frequency margin under this share of φ_op (−) is warned
    /// (`design.warnings.frequency_margin`, default [`FREQUENCY_MARGIN_WARNING`]).
    pub frequency_margin: f64,
}

impl Default for WarningLevels {
    fn default() -> Self {
        WarningLevels { load_margin: LOAD_MARGIN_WARNING, frequency_margin: FREQUENCY_MARGIN_WARNING }
    }
}

impl WarningLevels {
    fn is_default(&self) -> bool {
        *self == WarningLevels::default()
    }
}

impl DesignSpec {
    /// The design variables at `values` (SI units) in words, e.g. `branch 1
    /// tuning_frequency = 1398.7 rad/s, branch 1 resistance = 19.408 Ω` (5 significant
    /// digits).
    pub fn values_text(&self, values: &[f64]) -> String {
        self.variables
            .iter()
            .zip(values)
            .map(|(var, x)| format!("{} = {} {}", var.name(), crate::numbers::sig(*x, 5), var.parameter.unit()))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Default Nelder–Mead starts of a design (`design.starts`).
pub const DEFAULT_STARTS: usize = 4;
/// Default iterations per start, or convex steps (`design.max_iterations`).
pub const DEFAULT_ITERATIONS: usize = 40;

/// Default β_max of a design's catalogues for β_op = `level` (−): 1, or β_op when above.
pub fn default_beta_max(level: f64) -> f64 {
    level.max(1.0)
}

/// A [`DesignSpec`] built in code, with the defaults a `[design]` table has for every key
/// it does not give, checked when built ([`DesignSpecBuilder::build`]): no field is ever
/// unset. Begin with [`DesignSpec::builder`].
#[derive(Debug, Clone)]
pub struct DesignSpecBuilder {
    spec: DesignSpec,
}

impl DesignSpec {
    /// A spec of `objective` at β_op = `level` (−) over the operating `speeds` (rad/s)
    /// with the design `variables`; everything else as a `[design]` table without the key:
    /// φ range [`crate::analysis::DEFAULT_BAND_RANGE`], β_max = max(1, β_op),
    /// [`DEFAULT_STARTS`], [`DEFAULT_ITERATIONS`], no constraints, response, speed range
    /// or tolerances, the report charts' [`CHART_GRID`], the refined check on.
    pub fn builder(
        objective: impl Into<AnyObjective>,
        level: f64,
        speeds: Vec<f64>,
        variables: Vec<Variable>,
    ) -> DesignSpecBuilder {
        let range = crate::analysis::DEFAULT_BAND_RANGE;
        DesignSpecBuilder {
            spec: DesignSpec {
                objective: objective.into(),
                level,
                phi_range: (range.lo, range.hi),
                beta_max: default_beta_max(level),
                speeds,
                variables,
                starts: DEFAULT_STARTS,
                max_iterations: DEFAULT_ITERATIONS,
                response: None,
                constraints: Constraints::default(),
                speed_range: None,
                tolerances: None,
                speed_unit: crate::numbers::SpeedUnit::RadPerS,
                chart_grid: CHART_GRID,
                refined_check: true,
                map: true,
                warnings: WarningLevels::default(),
            },
        }
    }
}

impl DesignSpecBuilder {
    /// The φ range of the catalogues and band searches, lo < hi (rad/s).
    pub fn phi_range(mut self, lo: f64, hi: f64) -> Self {
        self.spec.phi_range = (lo, hi);
        self
    }
    /// β_max of the catalogues (−), at least β_op.
    pub fn beta_max(mut self, beta_max: f64) -> Self {
        self.spec.beta_max = beta_max;
        self
    }
    /// Nelder–Mead starts (1–64).
    pub fn starts(mut self, starts: usize) -> Self {
        self.spec.starts = starts;
        self
    }
    /// Iterations per start, or convex steps.
    pub fn max_iterations(mut self, iterations: usize) -> Self {
        self.spec.max_iterations = iterations;
        self
    }
    /// The unbalance response judged by a peak constraint and reported (an objective
    /// that carries its own response keeps that one).
    pub fn response(mut self, response: Response) -> Self {
        self.spec.response = Some(response);
        self
    }
    /// Constraints on the result.
    pub fn constraints(mut self, constraints: Constraints) -> Self {
        self.spec.constraints = constraints;
        self
    }
    /// A range of operating speeds (rad/s) over which the design must hold: the speeds
    /// become its grid ([`range_speeds`]), as with `design.speed_range`.
    pub fn speed_range(mut self, range: Interval) -> Self {
        self.spec.speeds = range_speeds(range);
        self.spec.speed_range = Some(range);
        self
    }
    /// Component tolerances, judged at the worst corner of their box.
    pub fn tolerances(mut self, tolerances: Tolerances) -> Self {
        self.spec.tolerances = Some(tolerances);
        self
    }
    /// The report charts' φ and β points.
    pub fn chart_grid(mut self, phi_points: usize, beta_points: usize) -> Self {
        self.spec.chart_grid = (phi_points, beta_points);
        self
    }
    /// Whether the verification re-judges the tuned design on twice its basis (on by
    /// default; off is a quick look, not a design to hand on).
    pub fn refined_check(mut self, on: bool) -> Self {
        self.spec.refined_check = on;
        self
    }
    /// Whether the starts come from a map of the objective over the box (on by default)
    /// or from the first Halton points ([`DesignSpec::map`]).
    pub fn map(mut self, on: bool) -> Self {
        self.spec.map = on;
        self
    }
    /// The page-one warning thresholds ([`DesignSpec::warnings`]).
    pub fn warnings(mut self, levels: WarningLevels) -> Self {
        self.spec.warnings = levels;
        self
    }
    /// The spec, checked by the rules of a `[design]` table ([`DesignSpec::check`]) for a
    /// problem whose rings have `branches[r]` branches each; else the first broken rule
    /// with the key it breaks.
    pub fn build(self, branches: &[usize]) -> Result<DesignSpec, (String, ParamError)> {
        self.spec.check(branches)?;
        Ok(self.spec)
    }
}

/// The report charts' default grid: φ points and β points (400 × 31 resolves a
/// 1 rad/s-wide tongue in a window of a few hundred rad/s, in about a second per chart).
pub const CHART_GRID: (usize, usize) = (400, 31);
/// Most φ points of a report chart (`design.chart_phi_points`): ten times the default.
pub const MAX_CHART_PHI_POINTS: u64 = 4000;
/// Most β points of a report chart (`design.chart_beta_points`): β in steps of 0.5 % of
/// the chart's top.
pub const MAX_CHART_BETA_POINTS: u64 = 401;
/// Fewest points of a report chart in φ or β: both ends.
pub const MIN_CHART_POINTS: u64 = 2;

/// The JSON form of a [`DesignSpec`]: the objective's kind with its data as flat keys
/// (`phi_op`, `bands`), the shape reports have always had. Written from borrowed parts,
/// read into owned ones.
#[derive(Serialize, Deserialize)]
struct SpecJson<'a> {
    objective: ObjectiveKind,
    level: f64,
    phi_op: Option<f64>,
    phi_range: (f64, f64),
    beta_max: f64,
    speeds: Cow<'a, [f64]>,
    bands: Cow<'a, [Band]>,
    variables: Cow<'a, [Variable]>,
    starts: usize,
    max_iterations: usize,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    response: Option<Cow<'a, Response>>,
    #[serde(default, skip_serializing_if = "Constraints::is_empty")]
    constraints: Cow<'a, Constraints>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    speed_range: Option<Interval>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    tolerances: Option<Cow<'a, Tolerances>>,
    /// Written only when not [`CHART_GRID`] (the JSON of a file without the keys is as
    /// it was).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    chart_grid: Option<(usize, usize)>,
    /// Written only when off.
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    refined_check: bool,
    /// Written only when off.
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    map: bool,
    /// Written only when not the defaults.
    #[serde(default, skip_serializing_if = "WarningLevels::is_default")]
    warnings: WarningLevels,
    /// The objective's own keys, when it has any ([`ObjectiveKeys::options`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    objective_options: Option<Cow<'a, serde_json::Value>>,
}

fn yes() -> bool {
    true
}

fn is_true(b: &bool) -> bool {
    *b
}

impl Serialize for DesignSpec {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        SpecJson {
            objective: self.objective.kind(),
            level: self.level,
            phi_op: self.objective.phi_op(),
            phi_range: self.phi_range,
            beta_max: self.beta_max,
            speeds: Cow::Borrowed(&self.speeds),
            bands: Cow::Borrowed(self.objective.bands()),
            variables: Cow::Borrowed(&self.variables),
            starts: self.starts,
            max_iterations: self.max_iterations,
            response: self.response().map(Cow::Borrowed),
            constraints: Cow::Borrowed(&self.constraints),
            speed_range: self.speed_range,
            tolerances: self.tolerances.as_ref().map(Cow::Borrowed),
            chart_grid: (self.chart_grid != CHART_GRID).then_some(self.chart_grid),
            refined_check: self.refined_check,
            map: self.map,
            warnings: self.warnings,
            objective_options: self.objective.keys().options.map(Cow::Borrowed),
        }
        .serialize(serializer)
    }
}

/// A spec read back from its JSON (a report's `spec`): the objective rebuilt from its kind
/// and flat keys. The speed unit, display only, is not in the JSON and reads back as rad/s.
/// What is read is not validated again: [`DesignSpec::check`] does that.
impl<'de> Deserialize<'de> for DesignSpec {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let json = SpecJson::deserialize(deserializer)?;
        let keys = ObjectiveKeys {
            phi_op: json.phi_op,
            bands: Some(&*json.bands),
            response: json.response.as_deref(),
            options: json.objective_options.as_deref(),
        };
        let objective = json.objective.build_from_json(&keys).map_err(serde::de::Error::missing_field)?;
        // A response the objective carries is its own, not the spec's.
        let response = json.response.filter(|_| objective.response().is_none()).map(Cow::into_owned);
        Ok(DesignSpec {
            objective,
            level: json.level,
            phi_range: json.phi_range,
            beta_max: json.beta_max,
            speeds: json.speeds.into_owned(),
            variables: json.variables.into_owned(),
            starts: json.starts,
            max_iterations: json.max_iterations,
            response,
            constraints: json.constraints.into_owned(),
            speed_range: json.speed_range,
            tolerances: json.tolerances.map(Cow::into_owned),
            speed_unit: crate::numbers::SpeedUnit::RadPerS,
            chart_grid: json.chart_grid.unwrap_or(CHART_GRID),
            refined_check: json.refined_check,
            map: json.map,
            warnings: json.warnings,
        })
    }
}

impl DesignSpec {
    /// The builds a robust candidate is judged as: the nominal and each corner of
    /// `[design.tolerances]` ([`crate::design::tolerance::Tolerances::corners`]); 1
    /// without tolerances.
    pub fn builds(&self) -> usize {
        self.tolerances.map_or(1, |t| t.corners().len())
    }
}

/// Speeds of the optimiser's grid over a `design.speed_range`, ends included: the ends
/// and three interior speeds, so a worst case inside the range is bracketed before the
/// refinement near it (`crate::design::robust::SPEED_REFINEMENTS`).
pub const RANGE_SPEEDS: usize = 5;
/// Speeds of the verification's grid over a `design.speed_range`, ends included: eight
/// times finer than the optimiser's.
pub const VERIFY_SPEEDS: usize = 33;

/// `n` equally spaced speeds over `range` (rad/s), ends included.
pub fn speed_grid(range: Interval, n: usize) -> Vec<f64> {
    (0..n).map(|i| range.lo + range.width() * i as f64 / (n - 1) as f64).collect()
}

/// The optimiser's speeds over a speed range ([`RANGE_SPEEDS`]).
pub fn range_speeds(range: Interval) -> Vec<f64> {
    speed_grid(range, RANGE_SPEEDS)
}

/// Most Nelder–Mead starts and iterations (or convex steps) of a design, as the file
/// layer admits them.
pub const MAX_STARTS: u64 = 64;
/// See [`MAX_STARTS`].
pub const MAX_ITERATIONS: u64 = 10_000;
/// Fewest grid speeds of a `[design.response]`: a peak is an interior grid maximum, so
/// the grid needs an interior point.
pub const MIN_RESPONSE_POINTS: u64 = 3;
/// Most grid speeds of a `[design.response]` (one sparse solve each per candidate).
pub const MAX_RESPONSE_POINTS: u64 = 100_000;

impl DesignSpec {
    /// The operating bands kept clear at β_op: the clear-bands objective's, or the band
    /// constraints of the other objectives.
    pub fn kept_clear(&self) -> &[Band] {
        self.objective.keys().bands.unwrap_or(&self.constraints.bands)
    }

    /// The unbalance response of the design: the min-peak-response objective's, else the
    /// `[design.response]` of the others (for the peak constraint and the report).
    pub fn response(&self) -> Option<&Response> {
        self.objective.response().or(self.response.as_ref())
    }

    /// φ_op (rad/s): the widest-stable-band objective's, or the band-width constraint's.
    pub fn phi_op(&self) -> Option<f64> {
        self.objective.phi_op().or(self.constraints.min_band_width.map(|b| b.phi_op))
    }

    /// The φ range of the catalogues and band searches (rad/s).
    pub fn range(&self) -> Interval {
        Interval::new(self.phi_range.0, self.phi_range.1)
    }

    /// Check a spec built in code (its fields are public) by the rules the `[design]`
    /// table obeys ([`crate::analysis::limits`]) for a problem whose rings have
    /// `branches[r]` branches each (model order); the first broken rule with the field's
    /// name (as in `[design]`).
    pub fn check(&self, branches: &[usize]) -> Result<(), (String, ParamError)> {
        let at = |field: &str| {
            let field = field.to_string();
            move |e: ParamError| (field, e)
        };
        let (lo, hi) = self.phi_range;
        limits::phi_range(lo, hi).map_err(|e| {
            let end = if e.quantity == Quantity::RangeLow { 0 } else { 1 };
            (format!("phi_range[{end}]"), e)
        })?;
        let beta_max = limits::beta_max(self.beta_max).map_err(at("beta_max"))?;
        limits::level(self.level, beta_max).map_err(at("level"))?;
        if let Some(p) = self.objective.phi_op() {
            limits::phi_op(p, self.range()).map_err(at("phi_op"))?;
        }
        for (i, &w) in self.speeds.iter().enumerate() {
            limits::speed(w).map_err(at(&format!("speeds[{i}]")))?;
        }
        limits::count(self.speeds.len() as u64, 1, u64::MAX).map_err(at("speeds"))?;
        if let Some(bands) = self.objective.keys().bands {
            limits::count(bands.len() as u64, 1, u64::MAX).map_err(at("bands"))?;
        }
        for (i, b) in self.kept_clear().iter().enumerate() {
            limits::band(b.lo, b.hi).map_err(at(&format!("bands[{i}]")))?;
            limits::span(b.clearance).map_err(at(&format!("bands[{i}].clearance")))?;
        }
        if let Some(r) = self.response() {
            limits::response_speed(r.speeds.lo).map_err(at("response.speeds[0]"))?;
            limits::response_speed(r.speeds.hi).map_err(at("response.speeds[1]"))?;
            if r.speeds.hi <= r.speeds.lo {
                let rule = limits::Rule::NotAboveLow { low: r.speeds.lo };
                return Err((
                    "response.speeds[1]".into(),
                    ParamError { quantity: Quantity::RangeHigh, value: r.speeds.hi, rule },
                ));
            }
            limits::count(r.points as u64, MIN_RESPONSE_POINTS, MAX_RESPONSE_POINTS).map_err(at("response.points"))?;
        }
        if self.constraints.max_peak.is_some() {
            // The peak constraint is judged on the response: a `[design.response]` is needed.
            limits::count(self.response().is_some() as u64, 1, 1).map_err(at("response"))?;
        }
        if let Some(p) = self.constraints.max_peak {
            limits::positive(Quantity::Limit, p).map_err(at("constraints.max_peak"))?;
        }
        if let Some(b) = self.constraints.min_band_width {
            limits::phi_op(b.phi_op, self.range()).map_err(at("phi_op"))?;
            limits::positive(Quantity::Limit, b.width).map_err(at("constraints.min_band_width"))?;
        }
        if let Some(m) = self.constraints.margins {
            limits::non_negative(Quantity::Limit, m.beta).map_err(at("margins.beta"))?;
            limits::non_negative(Quantity::Limit, m.phi).map_err(at("margins.phi"))?;
            // The margins judge the band around φ_op: a φ_op is needed.
            limits::count(self.phi_op().is_some() as u64, 1, 1).map_err(at("phi_op"))?;
            limits::load_margin(m.beta, self.level).map_err(at("margins.beta"))?;
            if let Some(phi_op) = self.phi_op() {
                limits::frequency_margin(m.phi, phi_op, self.range()).map_err(at("margins.phi"))?;
            }
        }
        for (i, d) in self.constraints.damping.iter().enumerate() {
            limits::non_negative(Quantity::Limit, d.min).map_err(at(&format!("constraints.damping[{i}].min")))?;
        }
        limits::count(self.starts as u64, 1, MAX_STARTS).map_err(at("starts"))?;
        limits::count(self.max_iterations as u64, 1, MAX_ITERATIONS).map_err(at("max_iterations"))?;
        limits::count(self.chart_grid.0 as u64, MIN_CHART_POINTS, MAX_CHART_PHI_POINTS)
            .map_err(at("chart_phi_points"))?;
        limits::count(self.chart_grid.1 as u64, MIN_CHART_POINTS, MAX_CHART_BETA_POINTS)
            .map_err(at("chart_beta_points"))?;
        limits::non_negative(Quantity::Limit, self.warnings.load_margin).map_err(at("warnings.load_margin"))?;
        limits::non_negative(Quantity::Limit, self.warnings.frequency_margin)
            .map_err(at("warnings.frequency_margin"))?;
        limits::count(self.variables.len() as u64, 1, u64::MAX).map_err(at("variables"))?;
        for (i, v) in self.variables.iter().enumerate() {
            let key = format!("variables[{i}]");
            let ring = v.ring.unwrap_or(0);
            let rings = limits::count(ring as u64 + 1, 1, branches.len() as u64);
            rings.map_err(at(&format!("{key}.ring")))?;
            let n = branches.get(ring).copied().unwrap_or(0) as u64;
            limits::count(v.branch as u64 + 1, 1, n).map_err(at(&format!("{key}.branch")))?;
            let min = if v.parameter.logarithmic() {
                limits::positive(Quantity::RangeLow, v.min)
            } else {
                limits::non_negative(Quantity::RangeLow, v.min)
            }
            .map_err(at(&format!("{key}.min")))?;
            let max = limits::finite(Quantity::RangeHigh, v.max).map_err(at(&format!("{key}.max")))?;
            if max <= min {
                let e = ParamError {
                    quantity: Quantity::RangeHigh,
                    value: max,
                    rule: limits::Rule::NotAboveLow { low: min },
                };
                return Err((format!("{key}.max"), e));
            }
        }
        Ok(())
    }
}
