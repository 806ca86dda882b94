//! The rules every parameter of an analysis obeys, written once: plain functions on
//! numbers that return the value or a typed [`ParamError`]. Every way a value comes in
//! calls them: the problem file's `[design]` and `speed` (and so `--set` and a study's
//! sweep values), the command-line flags, a study's fields, and the library's request
//! constructors ([`crate::analysis::regions::CatalogueRequestBuilder::build`],
//! [`crate::analysis::regions::band()`], [`crate::design::DesignSpec::check`]). Each entry
//! point names the value by its own key or flag; the rule and its wording are the same.
//!
//! Units: frequencies and speeds in rad/s, load coefficients relative to P_cr.

use super::Interval;
use serde::Serialize;
use thiserror::Error;

/// Highest excitation frequency φ (rad/s) accepted: 10⁷ rad/s (1.6 MHz) is beyond any
/// mechanical excitation of a rotor; a larger value is a slip of units or digits. The cost
/// of a high φ is small (the steps per period do not grow), so the bound is for sense.
pub const MAX_PHI: f64 = 1e7;

/// Highest speed Ω (rad/s) of an unbalance response (`unbalance --speeds`,
/// `[design.response]`): the same 10⁷ rad/s as [`MAX_PHI`], since the unbalance force
/// m·e·Ω² excites the rotor at the frequency Ω, and a rotor's excitation beyond 1.6 MHz
/// is a slip of units or digits (at 1e300 rad/s, Ω² overflows and the response cannot be
/// solved at all). The whirl solvers' speed has no maximum ([`speed`]).
pub const MAX_RESPONSE_SPEED: f64 = MAX_PHI;

/// Largest ratio hi/lo of a φ range (catalogue, band window, design range): four decades.
/// The seeds, the guard lattice and the edge marches of a range all grow with its ratio,
/// and tongues four decades apart belong to unrelated parts of the spectrum: split such a
/// search into several ranges.
pub const MAX_PHI_RATIO: f64 = 1e4;

/// Largest β_max and level (β_op) of a search (−): a dynamic load 100 times the buckling
/// load P_cr, two orders of magnitude beyond the paper's charts (β ≤ 1). The region
/// search brackets β_c in steps of 1/32 up to β_max, so its cost grows with β_max (a
/// value like 1e300 would never end). A point's or a grid's β has no maximum: its cost is
/// bounded whatever β (the per-φ table stops doubling its steps at 4096), and a huge β is
/// a legitimate probe of the numerics (ln max|μ| stays exact beyond 1e300).
pub const MAX_BETA: f64 = 100.0;

/// Most load periods of a time response: the response stores at most 4 000 samples, so
/// more periods only add integration time (bounded in turn by the cost estimate).
pub const MAX_PERIODS: usize = 100_000;

/// Most whirls per direction a command lists or tracks (`--count`): more than any model
/// the limits admit has (2 × 4 100 DOFs).
pub const MAX_COUNT: usize = 10_000;

/// Which parameter a value is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// An excitation frequency φ (rad/s): a point, a grid value, φ_op or a band end.
    Frequency,
    /// The low end of a φ range (rad/s).
    RangeLow,
    /// The high end of a φ range (rad/s).
    RangeHigh,
    /// A load coefficient β of a point or grid (−).
    Load,
    /// The highest load searched, β_max (−).
    BetaMax,
    /// The level β_op of edges and bands (−).
    Level,
    /// The operating frequency φ_op (rad/s).
    OperatingFrequency,
    /// A rotating speed Ω (rad/s).
    Speed,
    /// A whole number: periods, whirls, starts, iterations.
    Count,
    /// The `--max-cost` factor (−).
    CostFactor,
    /// The `--time-limit` of a run (s of wall time).
    TimeLimit,
    /// A design constraint's limit, in its own unit (m, rad/s or −).
    Limit,
}

/// The rule a value breaks.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "rule")]
#[non_exhaustive]
pub enum Rule {
    /// NaN or infinite.
    NotFinite,
    /// Zero or negative where a positive value is needed.
    NotPositive,
    /// Negative where zero is allowed.
    Negative,
    /// Above the largest value the parameter may take.
    TooLarge {
        /// The largest value.
        max: f64,
        /// Its unit, e.g. `rad/s` (empty for a coefficient).
        unit: &'static str,
    },
    /// A range's high end not above its low end.
    NotAboveLow {
        /// The low end (rad/s).
        low: f64,
    },
    /// A range wider than [`MAX_PHI_RATIO`].
    RatioTooLarge {
        /// The low end (rad/s).
        low: f64,
        /// The largest ratio hi/lo.
        max_ratio: f64,
    },
    /// A level above β_max.
    AboveBetaMax {
        /// β_max (−).
        beta_max: f64,
    },
    /// A value outside the range it must lie in.
    Outside {
        /// The range (rad/s).
        range: Interval,
    },
    /// A whole number outside its bounds.
    Count {
        /// Smallest.
        min: u64,
        /// Largest.
        max: u64,
    },
    /// A load margin m whose margin level (1 + m)·β_op lies above the largest β a search
    /// covers ([`MAX_BETA`]).
    MarginLevel {
        /// β_op (−).
        level: f64,
        /// The largest β a search covers (−).
        max_beta: f64,
    },
    /// A frequency margin wider than the room φ_op has inside the φ range: a stable band
    /// is found inside the range, so none reaches farther from φ_op.
    MarginBeyondRange {
        /// φ_op (rad/s).
        phi_op: f64,
        /// The φ range (rad/s).
        range: Interval,
    },
    /// A required value a builder was not given (the value reads NaN).
    NotSet,
}

impl Rule {
    /// The error kind a broken rule is, named as docs/errors.md heads it: the sign and
    /// finiteness rules are kinds of their own, every bound is `OutOfRange`.
    pub fn kind(&self) -> &'static str {
        match self {
            Rule::NotFinite => "NotFinite",
            Rule::NotPositive => "NotPositive",
            Rule::Negative => "Negative",
            Rule::TooLarge { .. }
            | Rule::NotAboveLow { .. }
            | Rule::RatioTooLarge { .. }
            | Rule::AboveBetaMax { .. }
            | Rule::Outside { .. }
            | Rule::Count { .. }
            | Rule::MarginLevel { .. }
            | Rule::MarginBeyondRange { .. } => "OutOfRange",
            // A required value missing, as a required key missing from a file.
            Rule::NotSet => "Schema",
        }
    }
}

/// A value that breaks a rule: the rule, the value, and which parameter it was.
#[derive(Debug, Clone, PartialEq, Error, Serialize)]
#[error("{}", rule_text(rule, *value))]
pub struct ParamError {
    /// Which parameter the value was given for.
    pub quantity: Quantity,
    /// The value given.
    pub value: f64,
    /// The rule it breaks.
    pub rule: Rule,
}

pub use crate::numbers::number;

/// A limit as a person writes it: 1e6 rather than 1000000 beyond 10⁵ (and below 10⁻⁴).
pub fn compact(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && !(1e-4..1e5).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

impl Rule {
    /// What the value must be, in words (completing "must be …"), for the rules that are
    /// not a plain sign or finiteness check.
    pub fn range(&self) -> String {
        let with_unit =
            |x: f64, unit: &str| if unit.is_empty() { compact(x) } else { format!("{} {unit}", compact(x)) };
        match self {
            Rule::NotFinite => "a finite number".into(),
            Rule::NotPositive => "positive".into(),
            Rule::Negative => "at least 0".into(),
            Rule::TooLarge { max, unit } => format!("at most {}", with_unit(*max, unit)),
            Rule::NotAboveLow { low } => format!("above the range's low end, {} rad/s", compact(*low)),
            Rule::RatioTooLarge { low, max_ratio } => format!(
                "at most {} times the range's low end {} rad/s (split a wider search into several ranges)",
                compact(*max_ratio),
                compact(*low)
            ),
            Rule::AboveBetaMax { beta_max } => format!("at most beta_max = {}", compact(*beta_max)),
            Rule::Outside { range } => {
                format!("inside the range [{}, {}] rad/s", compact(range.lo), compact(range.hi))
            }
            Rule::Count { min, max } => format!("a whole number from {min} to {max}"),
            Rule::MarginLevel { level, max_beta } => format!(
                "at most {} (with beta_op = {} a larger margin puts the margin level (1 + beta) beta_op above {}, the largest beta a search covers)",
                crate::numbers::sig(max_beta / level - 1.0, 6),
                compact(*level),
                compact(*max_beta)
            ),
            Rule::MarginBeyondRange { phi_op, range } => format!(
                "at most {} rad/s, the room phi_op = {} rad/s has inside the design's phi range [{}, {}] rad/s (no stable band found there reaches farther)",
                crate::numbers::sig((phi_op - range.lo).min(range.hi - phi_op), 6),
                compact(*phi_op),
                compact(range.lo),
                compact(range.hi)
            ),
            Rule::NotSet => "given".into(),
        }
    }
}

fn rule_text(rule: &Rule, value: f64) -> String {
    match rule {
        // The wording of the problem file's own sign checks.
        Rule::NotFinite => format!("must be a finite number, found {}", number(value)),
        Rule::NotPositive => format!("must be positive, found {}", number(value)),
        Rule::Negative => format!("must not be negative, found {}", number(value)),
        Rule::NotSet => "is required and was not set".into(),
        other => format!("must be {}, found {}", other.range(), number(value)),
    }
}

fn fail(quantity: Quantity, value: f64, rule: Rule) -> ParamError {
    ParamError { quantity, value, rule }
}

/// A required value of a builder: `Rule::NotSet` when it was not given.
pub fn required<T>(quantity: Quantity, v: Option<T>) -> Result<T, ParamError> {
    v.ok_or(fail(quantity, f64::NAN, Rule::NotSet))
}

/// A finite value.
pub fn finite(quantity: Quantity, v: f64) -> Result<f64, ParamError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(fail(quantity, v, Rule::NotFinite))
    }
}

/// A finite value > 0.
pub fn positive(quantity: Quantity, v: f64) -> Result<f64, ParamError> {
    if finite(quantity, v)? > 0.0 {
        Ok(v)
    } else {
        Err(fail(quantity, v, Rule::NotPositive))
    }
}

/// A finite value ≥ 0.
pub fn non_negative(quantity: Quantity, v: f64) -> Result<f64, ParamError> {
    if finite(quantity, v)? >= 0.0 {
        Ok(v)
    } else {
        Err(fail(quantity, v, Rule::Negative))
    }
}

fn at_most(quantity: Quantity, v: f64, max: f64, unit: &'static str) -> Result<f64, ParamError> {
    if v <= max {
        Ok(v)
    } else {
        Err(fail(quantity, v, Rule::TooLarge { max, unit }))
    }
}

/// An excitation frequency φ (rad/s): finite, > 0, at most [`MAX_PHI`].
pub fn frequency(quantity: Quantity, phi: f64) -> Result<f64, ParamError> {
    at_most(quantity, positive(quantity, phi)?, MAX_PHI, "rad/s")
}

/// A φ range [lo, hi] (rad/s): both ends frequencies, lo < hi, hi/lo ≤ [`MAX_PHI_RATIO`].
pub fn phi_range(lo: f64, hi: f64) -> Result<Interval, ParamError> {
    let lo = frequency(Quantity::RangeLow, lo)?;
    let hi = frequency(Quantity::RangeHigh, hi)?;
    if hi <= lo {
        return Err(fail(Quantity::RangeHigh, hi, Rule::NotAboveLow { low: lo }));
    }
    if hi > MAX_PHI_RATIO * lo {
        return Err(fail(Quantity::RangeHigh, hi, Rule::RatioTooLarge { low: lo, max_ratio: MAX_PHI_RATIO }));
    }
    Ok(Interval::new(lo, hi))
}

/// An operating band [lo, hi] (rad/s): both ends frequencies, lo < hi (no ratio bound: a
/// band is a target, not a search).
pub fn band(lo: f64, hi: f64) -> Result<Interval, ParamError> {
    let lo = frequency(Quantity::RangeLow, lo)?;
    let hi = frequency(Quantity::RangeHigh, hi)?;
    if hi <= lo {
        return Err(fail(Quantity::RangeHigh, hi, Rule::NotAboveLow { low: lo }));
    }
    Ok(Interval::new(lo, hi))
}

/// A width along φ (rad/s), e.g. a band's clearance: finite, ≥ 0, at most [`MAX_PHI`].
pub fn span(width: f64) -> Result<f64, ParamError> {
    at_most(Quantity::Frequency, non_negative(Quantity::Frequency, width)?, MAX_PHI, "rad/s")
}

/// A load coefficient β of a point or a grid (−): finite, ≥ 0 (no maximum: see
/// [`MAX_BETA`]).
pub fn load(beta: f64) -> Result<f64, ParamError> {
    non_negative(Quantity::Load, beta)
}

/// The highest load searched, β_max (−): finite, > 0, at most [`MAX_BETA`].
pub fn beta_max(beta_max: f64) -> Result<f64, ParamError> {
    at_most(Quantity::BetaMax, positive(Quantity::BetaMax, beta_max)?, MAX_BETA, "")
}

/// The level β_op (−) of a search up to `beta_max`: finite, > 0, at most β_max (itself
/// at most [`MAX_BETA`]; `beta_max` is checked first by the caller).
pub fn level(level: f64, beta_max: f64) -> Result<f64, ParamError> {
    let level = at_most(Quantity::Level, positive(Quantity::Level, level)?, MAX_BETA, "")?;
    if level > beta_max {
        return Err(fail(Quantity::Level, level, Rule::AboveBetaMax { beta_max }));
    }
    Ok(level)
}

/// The operating frequency φ_op (rad/s): a frequency inside `range`.
pub fn phi_op(phi_op: f64, range: Interval) -> Result<f64, ParamError> {
    let p = frequency(Quantity::OperatingFrequency, phi_op)?;
    if !range.contains(p) {
        return Err(fail(Quantity::OperatingFrequency, p, Rule::Outside { range }));
    }
    Ok(p)
}

/// A load margin m of `[design.margins]` (−, relative to β_op = `level`): finite, ≥ 0,
/// and small enough that the margin level (1 + m)·β_op, where the margins are judged,
/// stays at most [`MAX_BETA`], the largest β a search covers.
pub fn load_margin(m: f64, level: f64) -> Result<f64, ParamError> {
    let m = non_negative(Quantity::Limit, m)?;
    if (1.0 + m) * level > MAX_BETA {
        return Err(fail(Quantity::Limit, m, Rule::MarginLevel { level, max_beta: MAX_BETA }));
    }
    Ok(m)
}

/// A frequency margin of `[design.margins]` (rad/s): finite, ≥ 0, and at most the room
/// φ_op has inside the φ range searched, min(φ_op − lo, hi − φ_op): the band around φ_op
/// is found inside the range, so no band can give a wider margin.
pub fn frequency_margin(phi: f64, phi_op: f64, range: Interval) -> Result<f64, ParamError> {
    let phi = non_negative(Quantity::Limit, phi)?;
    if phi > (phi_op - range.lo).min(range.hi - phi_op) {
        return Err(fail(Quantity::Limit, phi, Rule::MarginBeyondRange { phi_op, range }));
    }
    Ok(phi)
}

/// A rotating speed Ω (rad/s): finite, ≥ 0. No maximum: the whirl solvers' cost does not
/// grow with Ω (at Ω = 1e300 rad/s their modes are flagged by their residuals), and the
/// time response, whose step resolves Ω, is refused by its cost estimate
/// ([`crate::analysis::cost`]) when Ω makes it too long.
pub fn speed(speed: f64) -> Result<f64, ParamError> {
    non_negative(Quantity::Speed, speed)
}

/// A speed Ω (rad/s) of an unbalance response: finite, ≥ 0, at most
/// [`MAX_RESPONSE_SPEED`].
pub fn response_speed(speed: f64) -> Result<f64, ParamError> {
    at_most(Quantity::Speed, non_negative(Quantity::Speed, speed)?, MAX_RESPONSE_SPEED, "rad/s")
}

/// A speed of an unbalance response given in rpm (n, with Ω = n·π/30): finite, ≥ 0, at
/// most [`MAX_RESPONSE_SPEED`] in rpm, so the key in rpm is refused in its own unit.
pub fn response_speed_rpm(rpm: f64) -> Result<f64, ParamError> {
    let max = MAX_RESPONSE_SPEED * 30.0 / std::f64::consts::PI;
    at_most(Quantity::Speed, non_negative(Quantity::Speed, rpm)?, max, "rpm")
}

/// A whole number from `min` to `max`.
pub fn count(n: u64, min: u64, max: u64) -> Result<u64, ParamError> {
    if (min..=max).contains(&n) {
        Ok(n)
    } else {
        Err(fail(Quantity::Count, n as f64, Rule::Count { min, max }))
    }
}

/// The `--max-cost` factor that multiplies the cost limits ([`crate::analysis::cost`]):
/// finite and > 0 (below 1 tightens them).
pub fn cost_factor(factor: f64) -> Result<f64, ParamError> {
    positive(Quantity::CostFactor, factor)
}

/// The `--time-limit` of a run, measured while it runs (s of wall time): finite, > 0.
pub fn time_limit(seconds: f64) -> Result<f64, ParamError> {
    positive(Quantity::TimeLimit, seconds)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_finite_positive_ordered_and_bounded() {
        assert_eq!(phi_range(100.0, 8000.0).unwrap(), Interval::new(100.0, 8000.0));
        for (lo, hi, q) in [
            (f64::NAN, 10.0, Quantity::RangeLow),
            (-1.0, 10.0, Quantity::RangeLow),
            (0.0, 10.0, Quantity::RangeLow),
            (1000.0, f64::INFINITY, Quantity::RangeHigh),
            (1000.0, 500.0, Quantity::RangeHigh),
            (1000.0, 1000.0, Quantity::RangeHigh),
            (1e-300, 1e300, Quantity::RangeHigh),
            (1e-300, 1.0, Quantity::RangeHigh),
        ] {
            assert_eq!(phi_range(lo, hi).unwrap_err().quantity, q, "[{lo}, {hi}]");
        }
    }

    #[test]
    fn levels_lie_in_zero_to_beta_max() {
        assert_eq!(level(0.3, 0.5), Ok(0.3));
        assert_eq!(level(0.5, 0.5), Ok(0.5));
        for bad in [0.0, -0.1, f64::NAN, 0.6, 1e300] {
            assert!(level(bad, 0.5).is_err(), "{bad}");
        }
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e300, MAX_BETA * 1.01] {
            assert!(beta_max(bad).is_err(), "{bad}");
        }
        assert_eq!(beta_max(MAX_BETA), Ok(MAX_BETA));
    }

    #[test]
    fn messages_say_what_the_value_must_be() {
        assert_eq!(
            phi_op(1e9, Interval::new(1000.0, 1500.0)).unwrap_err().to_string(),
            "must be at most 1e7 rad/s, found 1000000000"
        );
        assert_eq!(
            phi_op(2000.0, Interval::new(1000.0, 1500.0)).unwrap_err().to_string(),
            "must be inside the range [1000, 1500] rad/s, found 2000"
        );
        assert_eq!(level(0.7, 0.5).unwrap_err().to_string(), "must be at most beta_max = 0.5, found 0.7");
        assert_eq!(speed(-1.0).unwrap_err().to_string(), "must not be negative, found -1");
        assert_eq!(speed(1e300), Ok(1e300));
        assert_eq!(load(1e300), Ok(1e300));
        assert_eq!(load(f64::NAN).unwrap_err().to_string(), "must be a finite number, found NaN");
        assert_eq!(count(0, 1, 10).unwrap_err().to_string(), "must be a whole number from 1 to 10, found 0");
    }

    #[test]
    fn margins_no_band_can_give_are_refused_quoting_the_value_given() {
        // Issue 50, item 7. β_op = 0.3: the margin level (1 + m)·0.3 reaches MAX_BETA = 100
        // at m = 100/0.3 − 1 = 332.33…; the message quotes the 1000 typed, not 300.3.
        assert_eq!(load_margin(332.0, 0.3), Ok(332.0));
        let e = load_margin(1000.0, 0.3).unwrap_err();
        assert_eq!((e.value, e.rule.kind()), (1000.0, "OutOfRange"));
        assert!(e.to_string().starts_with("must be at most 332.333 (with beta_op = 0.3"), "{e}");
        assert!(e.to_string().ends_with("found 1000"), "{e}");
        // φ_op = 370 in [100, 8000] rad/s: 270 rad/s of room below it.
        let range = Interval::new(100.0, 8000.0);
        assert_eq!(frequency_margin(270.0, 370.0, range), Ok(270.0));
        let e = frequency_margin(1e300, 370.0, range).unwrap_err();
        assert_eq!(e.value, 1e300);
        assert!(e.to_string().starts_with("must be at most 270 rad/s, the room phi_op = 370 rad/s has"), "{e}");
        assert!(e.to_string().ends_with("found 1e300"), "{e}");
        assert!(frequency_margin(270.001, 370.0, range).is_err());
        assert!(frequency_margin(-1.0, 370.0, range).is_err());
    }
}
