//! Stability charts over a (φ, β) grid (Figs. 8, 9, 11, 13) and growth-rate maps
//! (Fig. 12). Parallel over φ (the outermost loop; each φ row shares its per-φ work),
//! sequential inside, so results are identical for any thread count.

use super::basis::BasisReport;
use super::criterion::Threshold;
use super::floquet::{FloquetSystem, PointStatus, PointSummary};
use super::reduction::ReductionInfo;
use crate::progress::Progress;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// One chart point: the summary of a Floquet point, without its multiplier list.
pub type ChartPoint = PointSummary;

/// A stability chart.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChartResult {
    /// Speed Ω (rad/s).
    pub speed: f64,
    /// φ values (rad/s).
    pub phis: Vec<f64>,
    /// β values (−).
    pub betas: Vec<f64>,
    /// Points, φ-major: index = i_φ·len(β) + i_β.
    pub points: Vec<ChartPoint>,
    /// The rule that made a point unstable.
    pub threshold: Threshold,
    /// The reduced model the points were computed on (M, frequencies).
    pub reduction: ReductionInfo,
    /// How its basis was chosen.
    pub basis: BasisReport,
    /// Points whose monodromy failed (no verdict; counted apart from unstable ones).
    pub failed: usize,
    /// Points flagged less accurate than the path states (each with its `reason`).
    pub inaccurate: usize,
}

impl ChartResult {
    /// The point at (i_φ, i_β).
    pub fn at(&self, i_phi: usize, i_beta: usize) -> &ChartPoint {
        &self.points[i_phi * self.betas.len() + i_beta]
    }
    /// Number of unstable points (with a verdict: failed points are counted apart).
    pub fn unstable(&self) -> usize {
        self.points.iter().filter(|p| !p.stable && p.status != PointStatus::Failed).count()
    }
}

/// Compute a chart; `progress` advances one step per φ row (the caller names the phase).
/// A row not begun when [`Progress::cancelled`] turns true is skipped: the chart is then
/// incomplete (fewer points than φ × β) and to be discarded.
pub fn chart(fs: &FloquetSystem, phis: &[f64], betas: &[f64], progress: &dyn Progress) -> ChartResult {
    let rows: Vec<Vec<ChartPoint>> = phis
        .par_iter()
        .map(|&phi| {
            if progress.cancelled() {
                return Vec::new();
            }
            let row = fs.row(phi, betas).into_iter().map(|p| p.summary).collect();
            progress.advance(1);
            row
        })
        .collect();
    let points: Vec<ChartPoint> = rows.into_iter().flatten().collect();
    ChartResult {
        speed: fs.speed,
        phis: phis.to_vec(),
        betas: betas.to_vec(),
        failed: points.iter().filter(|p| p.status == PointStatus::Failed).count(),
        inaccurate: points.iter().filter(|p| p.status == PointStatus::Inaccurate).count(),
        points,
        threshold: fs.settings.threshold(),
        reduction: fs.info(),
        basis: fs.basis.clone(),
    }
}
