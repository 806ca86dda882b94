//! Sensitivities of a region's start φ_s, onset β_min and edges at a level with respect to
//! any numeric parameter p, by central finite differences.
//!
//! Step rule: h = `relative_step`·|p| (1 % by default: large enough that the quantities,
//! resolved to ~1e-8 relative with [`RegionSettings::precise`], change by far more than
//! their resolution; small enough that the O(h²) truncation is below 1e-3 relative for the
//! smooth dependence of whirl frequencies on circuit and rotor parameters). The derivative
//! is repeated with h/2 and the relative disagreement of the two is reported as the check
//! (relative above the catalogue's resolution, see [`sensitivity`]).

use super::{seeds, Probe, RegionSettings, START_WINDOW};
use crate::analysis::Interval;

use crate::analysis::floquet::FloquetSystem;
use crate::analysis::modes::ModesResult;
use serde::Serialize;

/// A region's quantities for one parameter value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct Quantities {
    /// φ_s (rad/s).
    pub start: f64,
    /// Onset β_min = min β_c (−): the lowest dynamic load coefficient at which the region
    /// opens.
    pub onset: f64,
    /// Left edge at the level (rad/s).
    pub left: Option<f64>,
    /// Right edge at the level (rad/s).
    pub right: Option<f64>,
}

/// Derivatives of the quantities with respect to the parameter (per unit of it).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize)]
pub struct Derivatives {
    /// Sensitivity dφ_s/dp of the start frequency φ_s (rad/s per SI unit of the parameter).
    pub start: f64,
    /// Sensitivity dβ_min/dp of the onset β_min (per SI unit of the parameter; β is
    /// dimensionless).
    pub onset: f64,
    /// Sensitivity dφ_l/dp of the tongue's left edge at the level (rad/s per SI unit of the
    /// parameter); `None` unless both perturbed designs have a tongue there.
    pub left: Option<f64>,
    /// Sensitivity dφ_r/dp of the tongue's right edge at the level (rad/s per SI unit of
    /// the parameter); `None` unless both perturbed designs have a tongue there.
    pub right: Option<f64>,
}

/// Sensitivity of a region to one parameter.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct Sensitivity {
    /// Key path of the parameter.
    pub parameter: String,
    /// The parameter's value in the base design (SI unit).
    pub value: f64,
    /// Central-difference step h (SI unit of the parameter).
    pub step: f64,
    /// Central differences with step h.
    pub derivatives: Derivatives,
    /// The same with step h/2.
    pub check: Derivatives,
    /// Largest relative difference between the two (scaled by max(|d|, |d_check|, floor)).
    pub disagreement: f64,
}

/// The region labelled `label` (order k) of a prepared system: start, onset and edges at
/// `level`; None if it has no onset below β_max.
pub fn region_quantities(
    fs: &FloquetSystem,
    full: &ModesResult,
    s: &RegionSettings,
    label: &str,
    order: usize,
    beta_max: f64,
    level: f64,
) -> Option<Quantities> {
    let all = seeds(fs, Some(full), Interval::new(1.0, f64::MAX), order).ok()?;
    let i = all.iter().position(|x| x.label == label && x.order == order)?;
    let seed = all[i].phi;
    let nearest = all
        .iter()
        .enumerate()
        .filter(|(j, _)| *j != i)
        .map(|(_, x)| (x.phi - seed).abs())
        .fold(f64::INFINITY, f64::min);
    let probe = Probe::new(fs, s);
    let st = probe.locate_start(seed, (START_WINDOW * seed).min(0.45 * nearest), level, beta_max)?;
    let edges = (st.onset < level).then(|| probe.edges(st.phi, level));
    Some(Quantities { start: st.phi, onset: st.onset, left: edges.map(|e| e.lo), right: edges.map(|e| e.hi) })
}

fn diff(plus: &Quantities, minus: &Quantities, h: f64) -> Derivatives {
    let d = |a: f64, b: f64| (a - b) / (2.0 * h);
    let opt = |a: Option<f64>, b: Option<f64>| Some(d(a?, b?));
    Derivatives {
        start: d(plus.start, minus.start),
        onset: d(plus.onset, minus.onset),
        left: opt(plus.left, minus.left),
        right: opt(plus.right, minus.right),
    }
}

/// Central differences of `eval` around `value` with steps h and h/2.
pub fn sensitivity(
    parameter: &str,
    value: f64,
    relative_step: f64,
    eval: impl Fn(f64) -> Option<Quantities>,
) -> Option<Sensitivity> {
    let h = relative_step * value.abs().max(f64::MIN_POSITIVE);
    let at = |x: f64| eval(x);
    let derivatives = diff(&at(value + h)?, &at(value - h)?, h);
    let check = diff(&at(value + h / 2.0)?, &at(value - h / 2.0)?, h / 2.0);
    let rel = |a: f64, b: f64, floor: f64| (a - b).abs() / a.abs().max(b.abs()).max(floor);
    // Floors: a derivative whose effect over the check's whole step (2·h/2 = h) is below the
    // catalogue's own resolution (φ: `phi_tolerance` 0.2 rad/s, β: `beta_tolerance` 1e-4)
    // is zero for every purpose and noise-dominated at that step, so it is compared
    // absolutely at that scale instead of relatively.
    let defaults = RegionSettings::default();
    let phi_floor = defaults.phi_tolerance / h;
    let beta_floor = defaults.beta_tolerance / h;
    let mut disagreement =
        rel(derivatives.start, check.start, phi_floor).max(rel(derivatives.onset, check.onset, beta_floor));
    for (a, b) in [(derivatives.left, check.left), (derivatives.right, check.right)] {
        if let (Some(a), Some(b)) = (a, b) {
            disagreement = disagreement.max(rel(a, b, phi_floor));
        }
    }
    Some(Sensitivity { parameter: parameter.to_string(), value, step: h, derivatives, check, disagreement })
}
