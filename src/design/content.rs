//! What a design report shows beyond the optimiser's outcome, computed here so that the
//! report layer only draws and the command only writes: the before/after stability
//! charts at each operating speed over the design's window (widened to every band they
//! draw), the tuned design's Campbell diagram, and the whirls before and after paired by
//! mode shape.

use super::evaluate::Candidate;
use super::spec::{Band, DesignSpec};
use super::DesignError;
use crate::analysis::campbell::{campbell, CampbellResult};
use crate::analysis::chart::{chart, ChartResult};
use crate::analysis::cost::{self, Driver, Estimate, PointCost};
use crate::analysis::Interval;
use crate::progress::Progress;

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
    /// The charts (over [`drawn_window`]) at each operating speed, in the spec's order.
    pub charts: Vec<SpeedCharts>,
    /// The tuned design's Campbell diagram over 0 to 1.5 × the largest speed.
    pub campbell: CampbellResult,
    /// The tuned design's lowest whirls at each operating speed, each with the reference
    /// design's whirl of the same mode shape ([`pair_whirls`]).
    pub whirls: Vec<SpeedWhirls>,
}

/// The tuned design's whirls at one operating speed, each paired with the reference's.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct SpeedWhirls {
    /// Ω (rad/s).
    pub speed: f64,
    /// The lowest forward, then backward whirls of the tuned design.
    pub pairs: Vec<WhirlPair>,
}

/// A whirl of the tuned design and the reference's whirl with the same mode shape: the
/// same mode by identity (MAC), whatever the labels, which follow frequency order and
/// change when a mode moves past another (the third rotor mode is `f3` before and may be
/// `f4` after, an electrical mode taking its place).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct WhirlPair {
    /// The tuned design's tag (`f1`, `fr1@impeller`, …).
    pub after: String,
    /// Its frequency (rad/s).
    pub after_frequency: f64,
    /// The reference design's whirl of the same shape and direction: its tag; absent when
    /// no reference whirl matches (MAC below [`PAIR_MAC`]).
    pub before: Option<String>,
    /// Its frequency (rad/s).
    pub before_frequency: Option<f64>,
    /// The MAC of the two shapes (−).
    pub mac: Option<f64>,
}

/// Least MAC at which a reference whirl is taken as the same mode as a tuned one.
pub const PAIR_MAC: f64 = 0.5;
/// Whirls per direction the pairing lists (those of the report's whirl table).
pub const PAIRED_WHIRLS: usize = 6;

/// The tuned design's lowest [`PAIRED_WHIRLS`] forward and backward whirls at each
/// operating speed, each paired with the reference whirl of the same direction whose
/// shape is closest (largest MAC), one to one, largest MACs first. The designs differ in
/// their circuits only, so their shapes have the same DOFs.
pub fn pair_whirls(spec: &DesignSpec, before: &Candidate, after: &Candidate) -> Result<Vec<SpeedWhirls>, DesignError> {
    use crate::analysis::campbell::mac;
    use crate::analysis::modes::{whirl_modes_of, Whirl};
    let mut out = Vec::new();
    for &speed in &spec.speeds {
        let b = whirl_modes_of(&before.rotor, &before.machine.settings, speed)?;
        let a = whirl_modes_of(&after.rotor, &after.machine.settings, speed)?;
        let same_dofs = a.shapes.nrows() == b.shapes.nrows();
        let mut pairs = Vec::new();
        for dir in [Whirl::Forward, Whirl::Backward] {
            let mine: Vec<usize> =
                (0..a.modes.len()).filter(|&i| a.modes[i].whirl == dir).take(PAIRED_WHIRLS).collect();
            let theirs: Vec<usize> =
                (0..b.modes.len()).filter(|&j| b.modes[j].whirl == dir).take(3 * PAIRED_WHIRLS).collect();
            // Every candidate pair by MAC, largest first; each whirl used once.
            let mut candidates: Vec<(f64, usize, usize)> = Vec::new();
            if same_dofs {
                for &i in &mine {
                    for &j in &theirs {
                        candidates.push((mac(a.shapes.col(i), b.shapes.col(j)), i, j));
                    }
                }
            }
            candidates.sort_by(|x, y| y.0.total_cmp(&x.0));
            let mut matched: Vec<Option<(usize, f64)>> = vec![None; a.modes.len()];
            let mut used = vec![false; b.modes.len()];
            for (m, i, j) in candidates {
                if m >= PAIR_MAC && matched[i].is_none() && !used[j] {
                    matched[i] = Some((j, m));
                    used[j] = true;
                }
            }
            for &i in &mine {
                let pair = matched[i];
                pairs.push(WhirlPair {
                    after: a.modes[i].tag(),
                    after_frequency: a.modes[i].frequency,
                    before: pair.map(|(j, _)| b.modes[j].tag()),
                    before_frequency: pair.map(|(j, _)| b.modes[j].frequency),
                    mac: pair.map(|(_, m)| m),
                });
            }
        }
        out.push(SpeedWhirls { speed, pairs });
    }
    Ok(out)
}

/// The φ window of the charts: the objective's
/// ([`crate::design::objective::Objective::chart_window`], e.g. half to 1.5 times φ_op for
/// the widest band), inside the design's range (rad/s).
pub fn chart_window(spec: &DesignSpec) -> Interval {
    let (lo, hi) = spec.objective.chart_window(spec);
    Interval::new(lo.max(spec.phi_range.0), hi.min(spec.phi_range.1))
}

/// Margin of the drawn window beyond the bands it must show, as a fraction of their span.
pub const BAND_MARGIN: f64 = 0.1;

/// The φ window the charts draw: [`chart_window`] widened to every band drawn on them
/// (`bands`: the stable bands found before and after, the operating bands with their
/// clearances) plus [`BAND_MARGIN`] of the span each side, inside the design's range, so
/// that no band bar runs off the chart.
pub fn drawn_window(spec: &DesignSpec, bands: &[Interval]) -> Interval {
    let base = chart_window(spec);
    let lo = bands.iter().map(|b| b.lo).fold(base.lo, f64::min);
    let hi = bands.iter().map(|b| b.hi).fold(base.hi, f64::max);
    let pad = if bands.is_empty() { 0.0 } else { BAND_MARGIN * (hi - lo) };
    Interval::new((lo - pad).max(spec.phi_range.0), (hi + pad).min(spec.phi_range.1))
}

/// The window around operating bands: their widened span and a quarter of it each side.
pub fn band_window(bands: &[Band]) -> (f64, f64) {
    let lo = bands.iter().map(|b| b.guarded().lo).fold(f64::INFINITY, f64::min);
    let hi = bands.iter().map(|b| b.guarded().hi).fold(0.0, f64::max);
    (lo - 0.25 * (hi - lo), hi + 0.25 * (hi - lo))
}

/// The charts' grid: the spec's [`DesignSpec::chart_grid`] points over the window in φ
/// (rad/s), and over β from 0 to twice β_op (at most β_max, at least β_op). The window is
/// [`chart_window`]; the report's is [`drawn_window`] (the same number of points).
pub fn chart_grid(spec: &DesignSpec) -> (Vec<f64>, Vec<f64>) {
    grid_over(spec, chart_window(spec))
}

fn grid_over(spec: &DesignSpec, w: Interval) -> (Vec<f64>, Vec<f64>) {
    let (n_phi, n_beta) = spec.chart_grid;
    let phis = (0..n_phi).map(|i| w.lo + w.width() * i as f64 / (n_phi - 1) as f64).collect();
    let top = spec.beta_max.min(2.0 * spec.level).max(spec.level);
    let betas = (0..n_beta).map(|i| top * i as f64 / (n_beta - 1) as f64).collect();
    (phis, betas)
}

/// The charts of the report at one speed (before and after, on [`chart_grid`]),
/// counted before they run.
pub fn cost(pc: &PointCost, spec: &DesignSpec) -> Estimate {
    let (phis, betas) = chart_grid(spec);
    cost::chart(pc, &phis, &betas).times(2.0, Driver::Grid, "charts")
}

/// The speeds of the Campbell diagram (rad/s).
pub fn campbell_speeds(spec: &DesignSpec) -> Vec<f64> {
    let top = spec.speeds.iter().fold(0.0f64, |m, &w| m.max(w)).max(100.0) * 1.5;
    (0..CAMPBELL_SPEEDS).map(|i| top * i as f64 / (CAMPBELL_SPEEDS - 1) as f64).collect()
}

/// Rows of the charts (φ points × speeds × 2 designs) plus the Campbell speeds: the
/// progress steps [`content`] reports.
pub fn content_steps(spec: &DesignSpec) -> usize {
    2 * spec.speeds.len() * spec.chart_grid.0 + CAMPBELL_SPEEDS
}

/// The charts of `before` and `after` at every operating speed over [`drawn_window`] of
/// `bands` (every band the charts draw), the Campbell diagram of `after` and the whirls
/// paired ([`pair_whirls`]); a step of `progress` per chart row and Campbell speed.
pub fn content(
    spec: &DesignSpec,
    before: &Candidate,
    after: &Candidate,
    bands: &[Interval],
    progress: &dyn Progress,
) -> Result<DesignContent, DesignError> {
    let (phis, betas) = grid_over(spec, drawn_window(spec, bands));
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
    let campbell = campbell(&after.rotor, &after.machine.settings, &campbell_speeds(spec), CAMPBELL_WHIRLS, progress)?;
    let whirls = pair_whirls(spec, before, after)?;
    Ok(DesignContent { charts, campbell, whirls })
}
