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

use super::clip;
use super::plot::{area_box, draw_pieces, with_legend_column, Curve, Drawing, Layout, PlotError};
use super::style::{self, err, Dash, Entry, Key, Marker};
use crate::analysis::chart::{ChartPoint, ChartResult};
use crate::analysis::floquet::PointStatus;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::cell::Cell;
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
/// y-axis label of every chart (β is a ratio to P_cr: no unit).
pub const Y_LABEL: &str = "dynamic load β (−)";
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
/// Colour of the β levels (β_op).
const LEVEL_COLOR: (u8, u8, u8) = (0, 0, 0);
/// Fill of a tracked region drawn at true width.
const REGION_FILL: (u8, u8, u8) = (20, 40, 90);
/// Outline of a tracked region.
const REGION_LINE: (u8, u8, u8) = (0, 0, 0);
/// Opacity of a span's shading.
const SPAN_ALPHA: f64 = 0.18;
/// Opacity of a bar's fill: a few pixels tall, it must read against white and cells.
pub const BAR_ALPHA: f64 = 0.7;
/// Grid line colour.
const GRID_COLOR: RGBColor = RGBColor(225, 225, 225);

type Chart2d<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

use style::tick;

/// A span's shading on white.
fn span_fill(c: (u8, u8, u8)) -> (u8, u8, u8) {
    style::blend(c, (255, 255, 255), SPAN_ALPHA)
}

fn bar_fill(c: (u8, u8, u8)) -> (u8, u8, u8) {
    style::blend(c, (255, 255, 255), BAR_ALPHA)
}

fn triple(c: RGBColor) -> (u8, u8, u8) {
    (c.0, c.1, c.2)
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
    /// Polylines drawn over the chart in (φ, β), e.g. tracked region boundaries (1 px,
    /// clipped to the plotting area; named ones get a legend entry).
    pub lines: Vec<super::plot::Series>,
    /// Shaded φ spans (operating bands, clearances) with a legend entry each.
    pub spans: Vec<Span>,
    /// Horizontal lines at a β (the operating level β_op) with a legend entry each.
    pub levels: Vec<(f64, String)>,
    /// Regions drawn at their true width (filled polygons in (φ, β), 1 px outline),
    /// labelled like the paper's figures where the label does not collide.
    pub regions: Vec<RegionShape>,
}

/// A shaded span of φ over the whole β range, or a bar over a β interval (e.g. a stable
/// band found at β_op, drawn just below that level).
#[derive(Debug, Clone)]
pub struct Span {
    /// Lower φ of the span (rad/s).
    pub lo: f64,
    /// Upper φ of the span (rad/s).
    pub hi: f64,
    /// The β interval of a bar (drawn more opaque, [`BAR_ALPHA`], with a 1 px outline);
    /// `None` shades the whole β range.
    pub beta: Option<(f64, f64)>,
    /// Legend text (entries with equal text share one legend line).
    pub name: String,
    /// RGB colour (drawn translucent, under the unstable cells).
    pub color: (u8, u8, u8),
}

/// An instability region drawn at its true width.
#[derive(Debug, Clone)]
pub struct RegionShape {
    /// The label drawn at its start, beside its tip (e.g. `f1+b1`, `2 n1`); empty for none.
    pub label: String,
    /// The closed outline in (φ rad/s, β): the tip, then one edge up and the other down.
    pub outline: Vec<(f64, f64)>,
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
        StabilityPlot {
            title: title.to_string(),
            layers,
            markers: Vec::new(),
            lines: Vec::new(),
            spans: Vec::new(),
            levels: Vec::new(),
            regions: Vec::new(),
        }
    }

    /// With shaded φ spans (operating bands, clearances), each in the legend.
    pub fn with_spans(mut self, spans: Vec<Span>) -> StabilityPlot {
        self.spans = spans;
        self
    }

    /// With horizontal lines at β (e.g. β_op), each in the legend.
    pub fn with_levels(mut self, levels: Vec<(f64, String)>) -> StabilityPlot {
        self.levels = levels;
        self
    }

    /// With regions drawn at their true width and labelled.
    pub fn with_regions(mut self, regions: Vec<RegionShape>) -> StabilityPlot {
        self.regions = regions;
        self
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

    fn legend(&self) -> Vec<Entry> {
        let mut entries: Vec<Entry> = self
            .layers
            .iter()
            .enumerate()
            .filter(|(_, l)| !l.name.is_empty())
            .map(|(i, l)| Entry { key: Key::Fill(triple(self.shown_color(i))), text: format!("unstable: {}", l.name) })
            .collect();
        if let [a, b] = &self.layers[..] {
            entries.push(Entry {
                key: Key::Fill(triple(blend(b.color, a.color, OVERLAY_ALPHA))),
                text: "unstable: both".into(),
            });
        }
        if !self.layers.is_empty() {
            entries.push(Entry { key: Key::Fill((255, 255, 255)), text: "stable".into() });
        }
        if !self.regions.is_empty() {
            entries.push(Entry {
                key: Key::Outlined(REGION_FILL, REGION_LINE),
                text: "tracked region (true width)".into(),
            });
        }
        for s in &self.spans {
            if !entries.iter().any(|e| e.text == s.name) {
                let fill = if s.beta.is_some() { bar_fill(s.color) } else { span_fill(s.color) };
                entries.push(Entry { key: Key::Outlined(fill, s.color), text: s.name.clone() });
            }
        }
        for (_, name) in &self.levels {
            entries.push(Entry { key: Key::Line(LEVEL_COLOR, Dash::Dashed, Marker::None), text: name.clone() });
        }
        for l in self.lines.iter().filter(|l| !l.name.is_empty()) {
            let dash = if l.dashed { Dash::Dashed } else { Dash::Solid };
            entries.push(Entry { key: Key::Line(l.color, dash, Marker::None), text: l.name.clone() });
        }
        if self.markers.iter().any(|(_, t)| !t.is_empty()) {
            entries.push(Entry {
                key: Key::Line(triple(MARKER_COLOR), Dash::Dashed, Marker::None),
                text: "φ markers (labelled at the top)".into(),
            });
        }
        let failed: usize = self.layers.iter().map(|l| failed_count(&l.chart)).sum();
        if failed > 0 {
            entries.push(Entry { key: Key::Cross, text: failed_label(failed) });
        }
        entries
    }
}

impl Drawing for StabilityPlot {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>, layout: &Cell<Layout>) -> Result<(), PlotError> {
        root.fill(&WHITE).map_err(err)?;
        let area = style::titled(&root, &self.title)?;
        let entries = self.legend();
        let (plot_area, legend_area) = with_legend_column(area, &entries)?;
        let (x, y) = ranges(self.layers.iter().map(|l| &l.chart));
        let mut plot = axes(&plot_area, x, y, 25)?;
        draw_spans(&mut plot, &self.spans)?;
        for (i, layer) in self.layers.iter().enumerate() {
            let alpha = if i == 0 { 1.0 } else { OVERLAY_ALPHA };
            let color = rgb(layer.color).mix(alpha);
            let cells = blocks(&layer.chart, |p| unstable(p).then_some(()));
            draw_blocks(&mut plot, &layer.chart, &cells, |_| color)?;
        }
        for layer in &self.layers {
            draw_failed(&mut plot, &layer.chart)?;
        }
        draw_regions(&mut plot, &self.regions)?;
        for line in &self.lines {
            let c = Curve {
                dash: if line.dashed { Dash::Dashed } else { Dash::Solid },
                width: style::THIN,
                ..Curve::new(line.name.clone(), line.color, Vec::new())
            };
            let pieces = clip::clip_polyline(&line.points, (x.0, x.1), (y.0, y.1));
            draw_pieces(&mut plot, &c, pieces)?;
        }
        for (beta, _) in &self.levels {
            let c = Curve { dash: Dash::Dashed, width: style::THIN, ..Curve::new("", LEVEL_COLOR, Vec::new()) };
            let pieces = clip::clip_polyline(&[(x.0, *beta), (x.1, *beta)], (x.0, x.1), (y.0, y.1));
            draw_pieces(&mut plot, &c, pieces)?;
        }
        let mut occupied = clip::Occupied::default();
        draw_markers(&mut plot, &self.markers, &mut occupied)?;
        draw_region_labels(&mut plot, &self.regions, &mut occupied)?;
        draw_frame(&mut plot)?;
        let plot_box = area_box(plot.plotting_area());
        let mut legend_box = None;
        if let Some(l) = legend_area {
            let off = area_box(&l)[0];
            legend_box = style::draw_legend_panel(&l, &entries, (plot_box[0].1 - off.1).max(0))?
                .map(|b| [(b[0].0 + off.0, b[0].1 + off.1), (b[1].0 + off.0, b[1].1 + off.1)]);
        }
        layout.set(Layout { plot: plot_box, legend: legend_box });
        root.present().map_err(err)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::reduction::ReductionInfo;
    use crate::report::plot::Figure;

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
            threshold: crate::analysis::criterion::Threshold::Multiplier { tolerance: 1.0001 },
            reduction: ReductionInfo { modes: 2, frequencies: vec![1.0, 2.0] },
            basis: crate::analysis::basis::BasisReport::fixed(crate::analysis::Basis::Loaded, 2),
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
