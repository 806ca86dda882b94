//! Stability-chart rendering: the (φ, β) stability charts of Figs. 8, 9, 11 and 13
//! ([`StabilityPlot`], one or several overlaid layers), the growth-rate map of Fig. 12
//! ([`GrowthMap`]) and the chart CSV ([`chart_csv`]). Rendering only: no file I/O here.
//!
//! Each grid point is drawn as the cell around it (cell edges halfway between
//! neighbouring grid values, the outer cells as wide as their inner neighbours).
//! Horizontally adjacent cells of one β row with the same colour are merged into one
//! rectangle, and identical runs of consecutive rows into one block, so that a
//! 557 × 41 chart is a few hundred rectangles rather than tens of thousands. Cells map to
//! half-open pixel ranges, so semi-transparent neighbours never double-blend a seam.
//! Failed points (no verdict) are drawn as black crosses, never dropped.

use super::plot::{render_png, render_svg, PlotError};
use crate::analysis::chart::{ChartPoint, ChartResult};
use crate::analysis::floquet::PointStatus;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::collections::HashMap;
use std::hash::Hash;
use std::ops::Range;

/// Layer colour for the open-circuit chart (Fig. 11).
pub const OPEN_CIRCUIT_COLOR: (u8, u8, u8) = (31, 119, 180);
/// Layer colour for the closed-circuit chart (Fig. 11).
pub const CLOSED_CIRCUIT_COLOR: (u8, u8, u8) = (214, 39, 40);
/// Opacity of every layer after the first, so overlaps stay visible.
pub const OVERLAY_ALPHA: f64 = 0.6;
/// x-axis label of every chart.
pub const X_LABEL: &str = "excitation frequency φ (rad/s)";
/// y-axis label of every chart.
pub const Y_LABEL: &str = "dynamic load β";
/// Colour-bar label of the growth map.
pub const GROWTH_LABEL: &str = "growth rate ln(max|μ|)/T (1/s)";

/// Number of colour levels of the growth map (cells of one level merge in the SVG).
const GROWTH_LEVELS: usize = 128;
/// Colour of failed points.
const FAILED_COLOR: RGBColor = BLACK;
/// Half-size of a failed-point cross (pixels).
const CROSS_SIZE: i32 = 3;
/// Marker line colour.
const MARKER_COLOR: RGBColor = RGBColor(110, 110, 110);
/// Grid line colour.
const GRID_COLOR: RGBColor = RGBColor(225, 225, 225);

type Chart2d<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn err<E: std::fmt::Debug>(e: E) -> PlotError {
    PlotError(format!("{e:?}"))
}

/// Tick label: integers without a decimal point, others rounded to 6 decimals.
fn tick(v: &f64) -> String {
    if v.is_finite() && v.abs() < 1e15 && (v - v.round()).abs() <= 1e-9 * v.abs().max(1.0) {
        format!("{:.0}", v.round())
    } else {
        ((v * 1e6).round() / 1e6).to_string()
    }
}

fn rgb(c: (u8, u8, u8)) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

/// `top` over `bottom` with opacity `alpha`.
fn blend(top: (u8, u8, u8), bottom: (u8, u8, u8), alpha: f64) -> RGBColor {
    let mix = |t: u8, b: u8| (alpha * f64::from(t) + (1.0 - alpha) * f64::from(b)).round() as u8;
    RGBColor(mix(top.0, bottom.0), mix(top.1, bottom.1), mix(top.2, bottom.2))
}

/// One chart of a [`StabilityPlot`].
#[derive(Debug, Clone)]
pub struct Layer {
    /// Legend text; empty for no legend entry.
    pub name: String,
    /// RGB colour of its unstable cells.
    pub color: (u8, u8, u8),
    /// The chart drawn (its φ and β grid and verdicts).
    pub chart: ChartResult,
}

/// Stability chart (Figs. 8, 9, 11, 13): unstable cells filled in the layer colour,
/// stable cells white, failed points as black crosses. The first layer is opaque, later
/// ones are drawn over it with opacity [`OVERLAY_ALPHA`].
#[derive(Debug, Clone)]
pub struct StabilityPlot {
    /// Caption drawn above the plot.
    pub title: String,
    /// Charts, drawn in order.
    pub layers: Vec<Layer>,
    /// Vertical dashed marker lines at φ (rad/s) with a label at the top.
    pub markers: Vec<(f64, String)>,
    /// Polylines drawn over the chart in (φ, β), e.g. tracked region boundaries.
    pub lines: Vec<super::plot::Series>,
}

/// Growth-rate map (Fig. 12): unstable cells coloured by growth rate (viridis), stable
/// cells white, failed points as black crosses, colour bar on the right.
#[derive(Debug, Clone)]
pub struct GrowthMap {
    /// Caption drawn above the plot.
    pub title: String,
    /// The chart drawn (its φ and β grid and verdicts).
    pub chart: ChartResult,
    /// Vertical dashed marker lines at φ (rad/s) with a label at the top.
    pub markers: Vec<(f64, String)>,
}

mod cells;
mod draw;
mod growth;
mod table;

use cells::*;
use draw::*;
pub use table::chart_csv;

/// Number of failed points of `chart` (counted from the points, not the summary field).
fn failed_count(chart: &ChartResult) -> usize {
    chart.points.iter().filter(|p| p.status == PointStatus::Failed).count()
}

fn failed_label(n: usize) -> String {
    format!("failed, no verdict ({n})")
}

impl StabilityPlot {
    /// A plot of `layers` (first opaque, later ones semi-transparent), no markers.
    pub fn new(title: &str, layers: Vec<Layer>) -> StabilityPlot {
        StabilityPlot { title: title.to_string(), layers, markers: Vec::new(), lines: Vec::new() }
    }

    /// With polylines in (φ, β) drawn over the chart (e.g. tracked region boundaries).
    pub fn with_lines(mut self, lines: Vec<super::plot::Series>) -> StabilityPlot {
        self.lines = lines;
        self
    }

    /// With vertical marker lines at φ (rad/s), each labelled at the top.
    pub fn with_markers(mut self, markers: Vec<(f64, String)>) -> StabilityPlot {
        self.markers = markers;
        self
    }

    /// Displayed colour of layer `i`'s unstable cells on white.
    fn shown_color(&self, i: usize) -> RGBColor {
        let c = self.layers[i].color;
        if i == 0 {
            rgb(c)
        } else {
            blend(c, (255, 255, 255), OVERLAY_ALPHA)
        }
    }

    fn legend(&self) -> Vec<(Swatch, String)> {
        let mut entries: Vec<(Swatch, String)> = self
            .layers
            .iter()
            .enumerate()
            .filter(|(_, l)| !l.name.is_empty())
            .map(|(i, l)| (Swatch::Fill(self.shown_color(i)), l.name.clone()))
            .collect();
        if let [a, b] = &self.layers[..] {
            entries.push((Swatch::Fill(blend(b.color, a.color, OVERLAY_ALPHA)), "both".to_string()));
        }
        if !self.layers.is_empty() {
            entries.push((Swatch::Fill(WHITE), "stable".to_string()));
        }
        let failed: usize = self.layers.iter().map(|l| failed_count(&l.chart)).sum();
        if failed > 0 {
            entries.push((Swatch::Cross, failed_label(failed)));
        }
        entries
    }

    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        root.fill(&WHITE).map_err(err)?;
        let area = root.titled(&self.title, ("sans-serif", 24)).map_err(err)?;
        let (legend_area, plot_area) = area.split_vertically(34);
        draw_legend(&legend_area, &self.legend())?;
        let (x, y) = ranges(self.layers.iter().map(|l| &l.chart));
        let mut plot = axes(&plot_area, x, y, 25)?;
        for (i, layer) in self.layers.iter().enumerate() {
            let alpha = if i == 0 { 1.0 } else { OVERLAY_ALPHA };
            let color = rgb(layer.color).mix(alpha);
            let cells = blocks(&layer.chart, |p| unstable(p).then_some(()));
            draw_blocks(&mut plot, &layer.chart, &cells, |_| color)?;
        }
        for layer in &self.layers {
            draw_failed(&mut plot, &layer.chart)?;
        }
        draw_markers(&mut plot, &self.markers)?;
        for line in &self.lines {
            let style = ShapeStyle::from(&rgb(line.color)).stroke_width(2);
            plot.draw_series(LineSeries::new(line.points.iter().copied(), style)).map_err(err)?;
        }
        draw_frame(&mut plot)?;
        root.present().map_err(err)
    }

    /// Render as SVG text.
    pub fn svg(&self) -> Result<String, PlotError> {
        render_svg(|root| self.draw(root))
    }

    /// Render as PNG bytes.
    pub fn png(&self) -> Result<Vec<u8>, PlotError> {
        render_png(|root| self.draw(root))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::reduction::ReductionInfo;

    /// 6 φ × 4 β: unstable band at φ ∈ {300, 400} for β ≥ 0.5, one failed point, one
    /// inaccurate point.
    fn synthetic() -> ChartResult {
        let phis: Vec<f64> = (1..=6).map(|i| 100.0 * i as f64).collect();
        let betas = vec![0.0, 0.25, 0.5, 0.75];
        let mut points = Vec::new();
        for &phi in &phis {
            for &beta in &betas {
                let unstable = (phi == 300.0 || phi == 400.0) && beta >= 0.5;
                let ln = if unstable { beta * phi / 1000.0 } else { -0.01 };
                let mut p = ChartPoint {
                    phi,
                    beta,
                    max_multiplier: ln.exp(),
                    ln_max_multiplier: ln,
                    growth_rate: ln * phi / (2.0 * std::f64::consts::PI),
                    stable: !unstable,
                    status: PointStatus::Ok,
                    reason: None,
                };
                if phi == 600.0 && beta == 0.75 {
                    p = ChartPoint {
                        max_multiplier: f64::MAX,
                        ln_max_multiplier: f64::MAX,
                        growth_rate: f64::MAX,
                        stable: false,
                        status: PointStatus::Failed,
                        ..p
                    };
                }
                if phi == 100.0 && beta == 0.25 {
                    p.status = PointStatus::Inaccurate;
                }
                points.push(p);
            }
        }
        ChartResult {
            speed: 2000.0,
            phis,
            betas,
            points,
            instability_tolerance: 1.0001,
            reduction: ReductionInfo { modes: 2, frequencies: vec![1.0, 2.0] },
            failed: 1,
            inaccurate: 1,
        }
    }

    fn check(svg: &str, png: &[u8]) {
        assert!(svg.starts_with("<svg"), "{}", &svg[..svg.len().min(80)]);
        assert!(svg.contains("<rect"));
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    }

    #[test]
    fn edges_are_midpoints() {
        assert_eq!(cell_edges(&[0.0, 1.0, 3.0]), vec![-0.5, 0.5, 2.0, 4.0]);
        assert_eq!(cell_edges(&[2.0]), vec![1.9, 2.1]);
        assert!(cell_edges(&[]).is_empty());
    }

    #[test]
    fn tick_labels() {
        assert_eq!(tick(&1000.0), "1000");
        assert_eq!(tick(&-20.0), "-20");
        assert_eq!(tick(&0.25), "0.25");
        assert_eq!(tick(&0.30000000000000004), "0.3");
    }

    #[test]
    fn blocks_merge_runs_and_rows() {
        let c = synthetic();
        let b = blocks(&c, |p| unstable(p).then_some(()));
        assert_eq!(b, vec![Block { phi: 2..4, beta: 2..4, key: () }]);
        let cells: usize = b.iter().map(|b| b.phi.len() * b.beta.len()).sum();
        assert_eq!(cells, c.points.iter().filter(|p| unstable(p)).count());
    }

    #[test]
    fn stability_plot_renders() {
        let c = synthetic();
        let mut other = c.clone();
        other.points[0].stable = false;
        let plot = StabilityPlot::new(
            "synthetic",
            vec![
                Layer { name: "open circuit".into(), color: OPEN_CIRCUIT_COLOR, chart: c },
                Layer { name: "closed circuit".into(), color: CLOSED_CIRCUIT_COLOR, chart: other },
            ],
        )
        .with_markers(vec![(250.0, "region 1".into()), (9999.0, "outside".into())]);
        let svg = plot.svg().unwrap();
        check(&svg, &plot.png().unwrap());
        assert!(svg.contains("open circuit") && svg.contains("closed circuit"));
        assert!(svg.contains("region 1") && !svg.contains("outside"));
        assert!(svg.contains(&failed_label(2)));
    }

    #[test]
    fn growth_map_renders() {
        let map = GrowthMap::new("growth", synthetic());
        let (lo, hi) = map.growth_range().unwrap();
        assert!(lo > 0.0 && hi > lo && hi.is_finite());
        let svg = map.svg().unwrap();
        check(&svg, &map.png().unwrap());
        assert!(svg.contains("growth rate"));
    }

    #[test]
    fn empty_and_all_stable_charts_render() {
        let mut c = synthetic();
        for p in &mut c.points {
            p.stable = true;
            p.status = PointStatus::Ok;
        }
        let map = GrowthMap::new("stable", c.clone());
        assert!(map.growth_range().is_none());
        map.png().unwrap();
        let empty = ChartResult { phis: vec![], betas: vec![], points: vec![], ..c };
        StabilityPlot::new(
            "empty",
            vec![Layer { name: String::new(), color: OPEN_CIRCUIT_COLOR, chart: empty.clone() }],
        )
        .svg()
        .unwrap();
        GrowthMap::new("empty", empty).png().unwrap();
    }

    #[test]
    fn csv_rows_and_verdicts() {
        let c = synthetic();
        let text = chart_csv(&c).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 1 + c.points.len());
        assert_eq!(lines[0], "phi_rad_s,beta,max_multiplier,ln_max_multiplier,growth_rate_per_s,verdict,status");
        // φ-major: row 1 + 2·4 + 2 is φ = 300, β = 0.5.
        assert!(lines[1 + 2 * 4 + 2].starts_with("300,0.5,"));
        assert!(lines[1 + 2 * 4 + 2].ends_with(",unstable,ok"));
        assert!(lines[1].ends_with(",stable,ok"));
        assert!(lines[2].ends_with(",stable,inaccurate"));
        assert_eq!(lines[c.points.len()], "600,0.75,,,,failed,failed");
        assert_eq!(text.matches(",unstable,").count(), 4);
    }
}
