//! The design problem of a problem file's `[design]` table, validated: objective, load
//! level, operating speeds and bands, and the circuit variables with their bounds.

use crate::analysis::limits::{self, ParamError, Quantity};
use crate::analysis::Interval;
use serde::{Deserialize, Serialize};

/// What the optimiser is asked to do.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Objective {
    /// Maximise the width of the stable band at β_op containing φ_op (the smallest over
    /// the speeds).
    WidestStableBand,
    /// Keep every operating band clear of instability at β_op by its clearance, with the
    /// least weighted change to the reference design.
    ClearBands,
}

/// A circuit parameter a design may change.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Parameter {
    /// Filtering capacitance C_f (F); searched on a log scale.
    CF,
    /// Inductance L (H); log scale.
    Inductance,
    /// Tuning frequency ω of Eq. (4) (rad/s), L following from it; log scale.
    TuningFrequency,
    /// Resistance R (Ω); linear scale (it may be 0).
    Resistance,
}

impl Parameter {
    /// The key of the parameter in `[[circuit.branches]]`.
    pub fn key(self) -> &'static str {
        match self {
            Parameter::CF => "c_f",
            Parameter::Inductance => "inductance",
            Parameter::TuningFrequency => "tuning_frequency",
            Parameter::Resistance => "resistance",
        }
    }

    /// Unit, for reports.
    pub fn unit(self) -> &'static str {
        match self {
            Parameter::CF => "F",
            Parameter::Inductance => "H",
            Parameter::TuningFrequency => "rad/s",
            Parameter::Resistance => "Ω",
        }
    }

    /// Whether the optimiser works on ln(value) (positive, scale-free parameters).
    pub fn logarithmic(self) -> bool {
        !matches!(self, Parameter::Resistance)
    }
}

/// One design variable: a parameter of one branch with bounds.
#[derive(Debug, Clone, PartialEq, Serialize)]
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
    /// Which parameter.
    pub parameter: Parameter,
    /// Lower bound (SI unit of the parameter).
    pub min: f64,
    /// Upper bound.
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
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
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
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DesignSpec {
    /// The objective.
    pub objective: Objective,
    /// β_op (−).
    pub level: f64,
    /// Operating frequency φ_op (rad/s) of the widest-stable-band objective.
    pub phi_op: Option<f64>,
    /// φ range of the catalogues and band searches (rad/s).
    pub phi_range: (f64, f64),
    /// β_max of the catalogues (−).
    pub beta_max: f64,
    /// Operating speeds Ω (rad/s); the file's `speed` if not given.
    pub speeds: Vec<f64>,
    /// Operating bands (clear-bands).
    pub bands: Vec<Band>,
    /// Design variables.
    pub variables: Vec<Variable>,
    /// Nelder–Mead starts (multi-start).
    pub starts: usize,
    /// Nelder–Mead iterations per start, or sequential convex steps.
    pub max_iterations: usize,
}

/// Most Nelder–Mead starts and iterations (or convex steps) of a design, as the file
/// layer admits them.
pub const MAX_STARTS: u64 = 64;
/// See [`MAX_STARTS`].
pub const MAX_ITERATIONS: u64 = 10_000;

impl DesignSpec {
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
        if let Some(p) = self.phi_op {
            limits::phi_op(p, self.range()).map_err(at("phi_op"))?;
        }
        for (i, &w) in self.speeds.iter().enumerate() {
            limits::speed(w).map_err(at(&format!("speeds[{i}]")))?;
        }
        limits::count(self.speeds.len() as u64, 1, u64::MAX).map_err(at("speeds"))?;
        for (i, b) in self.bands.iter().enumerate() {
            limits::band(b.lo, b.hi).map_err(at(&format!("bands[{i}]")))?;
            limits::span(b.clearance).map_err(at(&format!("bands[{i}].clearance")))?;
        }
        limits::count(self.starts as u64, 1, MAX_STARTS).map_err(at("starts"))?;
        limits::count(self.max_iterations as u64, 1, MAX_ITERATIONS).map_err(at("max_iterations"))?;
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
