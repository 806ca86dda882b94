//! What a design report shows beyond the optimiser's outcome, computed here so that the
//! report layer only draws and the command only writes: the before/after stability
//! charts at each operating speed over the design's window, and the tuned design's
//! Campbell diagram.

use super::evaluate::Candidate;
use super::spec::{Band, DesignSpec, Objective};
use super::DesignError;
use crate::analysis::campbell::{campbell, CampbellResult};
use crate::analysis::chart::{chart, ChartResult};
use crate::analysis::Interval;
use crate::progress::Progress;

/// Grid of the before/after charts: φ points and β points (400 × 31 resolves a
/// 1 rad/s-wide tongue in a window of a few hundred rad/s, in about a second per chart).
pub const CHART_GRID: (usize, usize) = (400, 31);
/// Whirls tracked in the tuned design's Campbell diagram.
pub const CAMPBELL_WHIRLS: usize = 6;
/// Speeds of the tuned design's Campbell diagram (0 to 1.5 × the largest operating speed).
pub const CAMPBELL_SPEEDS: usize = 31;

/// The before/after charts at one operating speed.
#[derive(Debug, Clone)]
pub struct SpeedCharts {
    /// Ω (rad/s).
    pub speed: f64,
    /// The reference design's chart.
    pub before: ChartResult,
    /// The tuned design's chart.
    pub after: ChartResult,
}

/// The computed figures' data of a design report.
#[derive(Debug, Clone)]
pub struct DesignContent {
    /// The charts (over [`chart_window`]) at each operating speed, in the spec's order.
    pub charts: Vec<SpeedCharts>,
    /// The tuned design's Campbell diagram over 0 to 1.5 × the largest speed.
    pub campbell: CampbellResult,
}

/// The φ window of the charts: half to 1.5 times φ_op for the widest band, the
/// operating bands widened by their clearances and a quarter of their span each side
/// otherwise, inside the design's range (rad/s).
pub fn chart_window(spec: &DesignSpec) -> Interval {
    let (lo, hi) = match spec.objective {
        Objective::WidestStableBand { .. } => {
            let p = spec.objective.phi_op().unwrap_or(spec.phi_range.0);
            (p * 0.5, p * 1.5)
        }
        Objective::ClearBands { .. } => band_window(spec.kept_clear()),
        // The bands kept clear, else φ_op's, else the whole range.
        Objective::MinPeakResponse { .. } => match spec.phi_op() {
            _ if !spec.kept_clear().is_empty() => band_window(spec.kept_clear()),
            Some(p) => (p * 0.5, p * 1.5),
            None => spec.phi_range,
        },
    };
    Interval::new(lo.max(spec.phi_range.0), hi.min(spec.phi_range.1))
}

/// The window around operating bands: their widened span and a quarter of it each side.
fn band_window(bands: &[Band]) -> (f64, f64) {
    let lo = bands.iter().map(|b| b.guarded().lo).fold(f64::INFINITY, f64::min);
    let hi = bands.iter().map(|b| b.guarded().hi).fold(0.0, f64::max);
    (lo - 0.25 * (hi - lo), hi + 0.25 * (hi - lo))
}

/// The charts' grid: [`CHART_GRID`] points over the window in φ (rad/s), and over β from
/// 0 to twice β_op (at most β_max, at least β_op).
pub fn chart_grid(spec: &DesignSpec) -> (Vec<f64>, Vec<f64>) {
    let w = chart_window(spec);
    let phis = (0..CHART_GRID.0).map(|i| w.lo + w.width() * i as f64 / (CHART_GRID.0 - 1) as f64).collect();
    let top = spec.beta_max.min(2.0 * spec.level).max(spec.level);
    let betas = (0..CHART_GRID.1).map(|i| top * i as f64 / (CHART_GRID.1 - 1) as f64).collect();
    (phis, betas)
}

/// The speeds of the Campbell diagram (rad/s).
pub fn campbell_speeds(spec: &DesignSpec) -> Vec<f64> {
    let top = spec.speeds.iter().fold(0.0f64, |m, &w| m.max(w)).max(100.0) * 1.5;
    (0..CAMPBELL_SPEEDS).map(|i| top * i as f64 / (CAMPBELL_SPEEDS - 1) as f64).collect()
}

/// Rows of the charts (φ points × speeds × 2 designs) plus the Campbell speeds: the
/// progress steps [`content`] reports.
pub fn content_steps(spec: &DesignSpec) -> usize {
    2 * spec.speeds.len() * CHART_GRID.0 + CAMPBELL_SPEEDS
}

/// The charts of `before` and `after` at every operating speed and the Campbell diagram
/// of `after`; a step of `progress` per chart row and Campbell speed.
pub fn content(
    spec: &DesignSpec,
    before: &Candidate,
    after: &Candidate,
    progress: &dyn Progress,
) -> Result<DesignContent, DesignError> {
    let (phis, betas) = chart_grid(spec);
    let charts = spec
        .speeds
        .iter()
        .enumerate()
        .map(|(k, &speed)| SpeedCharts {
            speed,
            before: chart(&before.systems[k].1, &phis, &betas, progress),
            after: chart(&after.systems[k].1, &phis, &betas, progress),
        })
        .collect();
    let campbell = campbell(&after.rotor, &after.problem.settings, &campbell_speeds(spec), CAMPBELL_WHIRLS, progress)?;
    Ok(DesignContent { charts, campbell })
}
