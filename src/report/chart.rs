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
    /// The chart.
    pub chart: ChartResult,
}

/// Stability chart (Figs. 8, 9, 11, 13): unstable cells filled in the layer colour,
/// stable cells white, failed points as black crosses. The first layer is opaque, later
/// ones are drawn over it with opacity [`OVERLAY_ALPHA`].
#[derive(Debug, Clone)]
pub struct StabilityPlot {
    /// Caption.
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
    /// Caption.
    pub title: String,
    /// The chart.
    pub chart: ChartResult,
    /// Vertical dashed marker lines at φ (rad/s) with a label at the top.
    pub markers: Vec<(f64, String)>,
}

/// Cell edges around grid values: halfway between neighbours, the outer edges half a
/// spacing beyond the end values (±5 % of the value, or ±0.05, for a single value).
fn cell_edges(v: &[f64]) -> Vec<f64> {
    match v.len() {
        0 => Vec::new(),
        1 => {
            let h = if v[0] != 0.0 { 0.05 * v[0].abs() } else { 0.05 };
            vec![v[0] - h, v[0] + h]
        }
        n => {
            let mut e = Vec::with_capacity(n + 1);
            e.push(v[0] - 0.5 * (v[1] - v[0]));
            e.extend(v.windows(2).map(|w| 0.5 * (w[0] + w[1])));
            e.push(v[n - 1] + 0.5 * (v[n - 1] - v[n - 2]));
            e
        }
    }
}

/// A rectangle of grid cells with one key: φ indices × β indices (half-open).
#[derive(Debug, Clone, PartialEq)]
struct Block<K> {
    phi: Range<usize>,
    beta: Range<usize>,
    key: K,
}

/// Cells with `Some(key)` merged into blocks: runs along φ within a β row, then identical
/// runs of consecutive β rows.
fn blocks<K: Copy + Eq + Hash>(chart: &ChartResult, key: impl Fn(&ChartPoint) -> Option<K>) -> Vec<Block<K>> {
    let (np, nb) = (chart.phis.len(), chart.betas.len());
    let key_at = |ip: usize, ib: usize| chart.points.get(ip * nb + ib).and_then(&key);
    let mut out: Vec<Block<K>> = Vec::new();
    let mut prev: HashMap<(usize, usize, K), usize> = HashMap::new();
    for ib in 0..nb {
        let mut cur = HashMap::new();
        let mut ip = 0;
        while ip < np {
            let Some(k) = key_at(ip, ib) else {
                ip += 1;
                continue;
            };
            let start = ip;
            ip += 1;
            while ip < np && key_at(ip, ib) == Some(k) {
                ip += 1;
            }
            let idx = match prev.get(&(start, ip, k)) {
                Some(&i) => {
                    out[i].beta.end = ib + 1;
                    i
                }
                None => {
                    out.push(Block { phi: start..ip, beta: ib..ib + 1, key: k });
                    out.len() - 1
                }
            };
            cur.insert((start, ip, k), idx);
        }
        prev = cur;
    }
    out
}

/// A point that has a verdict and is unstable.
fn unstable(p: &ChartPoint) -> bool {
    !p.stable && p.status != PointStatus::Failed
}

/// Axis ranges covering every cell of every chart ((0, 1) for an empty axis).
fn ranges<'a>(charts: impl Iterator<Item = &'a ChartResult> + Clone) -> ((f64, f64), (f64, f64)) {
    let span = |edges: Vec<Vec<f64>>| {
        let (lo, hi) = edges
            .iter()
            .flatten()
            .filter(|v| v.is_finite())
            .fold((f64::MAX, f64::MIN), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        if lo < hi {
            (lo, hi)
        } else if lo == hi {
            (lo - 0.5, hi + 0.5)
        } else {
            (0.0, 1.0)
        }
    };
    (span(charts.clone().map(|c| cell_edges(&c.phis)).collect()), span(charts.map(|c| cell_edges(&c.betas)).collect()))
}

/// Cartesian chart with the shared axes, labels and light grid on `area`.
fn axes<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    x: (f64, f64),
    y: (f64, f64),
    right_margin: u32,
) -> Result<Chart2d<'a, DB>, PlotError> {
    let mut chart = ChartBuilder::on(area)
        .margin(15)
        .margin_right(right_margin)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(X_LABEL)
        .y_desc(Y_LABEL)
        .x_label_formatter(&tick)
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18))
        .bold_line_style(GRID_COLOR)
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(err)?;
    Ok(chart)
}

/// Draw `blocks` of `chart` as filled rectangles, coloured by key.
fn draw_blocks<DB: DrawingBackend, K>(
    plot: &mut Chart2d<'_, DB>,
    chart: &ChartResult,
    blocks: &[Block<K>],
    color: impl Fn(&K) -> RGBAColor,
) -> Result<(), PlotError> {
    let (pe, be) = (cell_edges(&chart.phis), cell_edges(&chart.betas));
    plot.draw_series(blocks.iter().map(|b| {
        Rectangle::new([(pe[b.phi.start], be[b.beta.start]), (pe[b.phi.end], be[b.beta.end])], color(&b.key).filled())
    }))
    .map_err(err)?;
    Ok(())
}

/// Black crosses at the failed points of `chart`; returns how many.
fn draw_failed<DB: DrawingBackend>(plot: &mut Chart2d<'_, DB>, chart: &ChartResult) -> Result<usize, PlotError> {
    let failed: Vec<(f64, f64)> =
        chart.points.iter().filter(|p| p.status == PointStatus::Failed).map(|p| (p.phi, p.beta)).collect();
    plot.draw_series(failed.iter().map(|&c| Cross::new(c, CROSS_SIZE, FAILED_COLOR.stroke_width(1)))).map_err(err)?;
    Ok(failed.len())
}

/// Dashed grey vertical lines with labels at the top, labels staggered downwards when
/// they would overlap. Markers outside the x range are not drawn.
fn draw_markers<DB: DrawingBackend>(plot: &mut Chart2d<'_, DB>, markers: &[(f64, String)]) -> Result<(), PlotError> {
    let x = plot.x_range();
    let y = plot.y_range();
    let mut visible: Vec<&(f64, String)> =
        markers.iter().filter(|(m, _)| m.is_finite() && *m >= x.start && *m <= x.end).collect();
    visible.sort_by(|a, b| a.0.total_cmp(&b.0));
    let style = ShapeStyle::from(&MARKER_COLOR).stroke_width(1);
    let font = ("sans-serif", 13).into_font().color(&RGBColor(60, 60, 60));
    let right_px = plot.backend_coord(&(x.end, y.end)).0;
    // Right end (pixels) of the last label on each text line.
    let mut lines: Vec<i32> = Vec::new();
    for (m, label) in visible {
        plot.draw_series(std::iter::once(DashedPathElement::new(vec![(*m, y.start), (*m, y.end)], 5, 4, style)))
            .map_err(err)?;
        if label.is_empty() {
            continue;
        }
        let (w, h) = plot.plotting_area().estimate_text_size(label, &font).map_err(err)?;
        let (w, h) = (w as i32, h as i32);
        let px = plot.backend_coord(&(*m, y.end)).0;
        // Label to the right of the line, or to the left near the right edge.
        let dx = if px + w + 8 > right_px { -w - 6 } else { 4 };
        let (left, right) = (px + dx - 2, px + dx + w + 2);
        let line = match lines.iter().position(|&end| end + 4 < left) {
            Some(i) => {
                lines[i] = right;
                i
            }
            None => {
                lines.push(right);
                lines.len() - 1
            }
        };
        let dy = 4 + line as i32 * (h + 4);
        let anchor = EmptyElement::at((*m, y.end))
            + Rectangle::new([(dx - 2, dy - 1), (dx + w + 2, dy + h + 1)], WHITE.mix(0.85).filled())
            + Text::new(label.clone(), (dx, dy), font.clone());
        plot.plotting_area().draw(&anchor).map_err(err)?;
    }
    Ok(())
}

/// Frame around the plotting area (plotters draws only the left and bottom axes).
fn draw_frame<DB: DrawingBackend>(plot: &mut Chart2d<'_, DB>) -> Result<(), PlotError> {
    let (x, y) = (plot.x_range(), plot.y_range());
    plot.draw_series(std::iter::once(Rectangle::new([(x.start, y.start), (x.end, y.end)], BLACK.stroke_width(1))))
        .map_err(err)?;
    Ok(())
}

/// Legend swatch.
enum Swatch {
    Fill(RGBColor),
    Cross,
}

/// Horizontal legend, centred in `area`.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(Swatch, String)],
) -> Result<(), PlotError> {
    const BOX: i32 = 14;
    const GAP: i32 = 6;
    const SPACING: i32 = 26;
    let font = ("sans-serif", 15).into_font().into_text_style(area).pos(Pos::new(HPos::Left, VPos::Center));
    let widths = entries
        .iter()
        .map(|(_, text)| area.estimate_text_size(text, &font).map(|(w, _)| w as i32))
        .collect::<Result<Vec<_>, _>>()
        .map_err(err)?;
    let total: i32 = widths.iter().map(|w| BOX + GAP + w).sum::<i32>() + SPACING * (entries.len() as i32 - 1);
    let (aw, ah) = area.dim_in_pixel();
    let mut x = ((aw as i32 - total) / 2).max(5);
    let yc = ah as i32 / 2;
    for ((swatch, text), w) in entries.iter().zip(widths) {
        let r = [(x, yc - BOX / 2), (x + BOX, yc + BOX / 2)];
        match swatch {
            Swatch::Fill(c) => {
                area.draw(&Rectangle::new(r, c.filled())).map_err(err)?;
                area.draw(&Rectangle::new(r, RGBColor(120, 120, 120).stroke_width(1))).map_err(err)?;
            }
            Swatch::Cross => {
                area.draw(&Cross::new((x + BOX / 2, yc), CROSS_SIZE + 1, FAILED_COLOR.stroke_width(2))).map_err(err)?
            }
        }
        area.draw(&Text::new(text.clone(), (x + BOX + GAP, yc), font.clone())).map_err(err)?;
        x += BOX + GAP + w + SPACING;
    }
    Ok(())
}

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

impl GrowthMap {
    /// A growth-rate map of `chart`, no markers.
    pub fn new(title: &str, chart: ChartResult) -> GrowthMap {
        GrowthMap { title: title.to_string(), chart, markers: Vec::new() }
    }

    /// With vertical marker lines at φ (rad/s), each labelled at the top.
    pub fn with_markers(mut self, markers: Vec<(f64, String)>) -> GrowthMap {
        self.markers = markers;
        self
    }

    /// Min and max growth rate (1/s) over the unstable points, if any.
    pub fn growth_range(&self) -> Option<(f64, f64)> {
        self.chart.points.iter().filter(|p| unstable(p) && p.growth_rate.is_finite()).map(|p| p.growth_rate).fold(
            None,
            |acc, g| match acc {
                None => Some((g, g)),
                Some((lo, hi)) => Some((f64::min(lo, g), f64::max(hi, g))),
            },
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        root.fill(&WHITE).map_err(err)?;
        let area = root.titled(&self.title, ("sans-serif", 24)).map_err(err)?;
        let failed = failed_count(&self.chart);
        let (legend_area, area) = area.split_vertically(if failed > 0 { 34 } else { 0 });
        if failed > 0 {
            draw_legend(&legend_area, &[(Swatch::Cross, failed_label(failed))])?;
        }
        let width = area.dim_in_pixel().0;
        let (main, bar) = area.split_horizontally(width.saturating_sub(135));

        // Colour scale: the unstable growth rates, in GROWTH_LEVELS levels.
        let range = self.growth_range();
        let (lo, hi) = match range {
            Some((lo, hi)) if hi > lo => (lo, hi),
            Some((g, _)) => {
                let d = (0.05 * g.abs()).max(1e-9);
                (g - d, g + d)
            }
            None => (0.0, 1.0),
        };
        let top = (GROWTH_LEVELS - 1) as f64;
        let level = |g: f64| {
            let t = if g.is_finite() { (g - lo) / (hi - lo) } else { 1.0 };
            (t.clamp(0.0, 1.0) * top).round() as usize
        };
        let color = |k: usize| -> RGBAColor { ViridisRGB.get_color_normalized(k as f64, 0.0, top).to_rgba() };

        let (x, y) = ranges(std::iter::once(&self.chart));
        let mut plot = axes(&main, x, y, 10)?;
        let cells = blocks(&self.chart, |p| unstable(p).then(|| level(p.growth_rate)));
        draw_blocks(&mut plot, &self.chart, &cells, |&k| color(k))?;
        draw_failed(&mut plot, &self.chart)?;
        draw_markers(&mut plot, &self.markers)?;
        draw_frame(&mut plot)?;

        // Colour bar, aligned with the main plotting area (same margins and x-label area).
        let mut cbar = ChartBuilder::on(&bar)
            .margin_top(15)
            .margin_bottom(15)
            .margin_left(15)
            .margin_right(5)
            .x_label_area_size(50)
            .right_y_label_area_size(85)
            .build_cartesian_2d(0.0..1.0, lo..hi)
            .map_err(err)?;
        cbar.configure_mesh()
            .disable_x_mesh()
            .disable_y_mesh()
            .disable_x_axis()
            .x_labels(0)
            .y_label_formatter(&tick)
            .y_desc(GROWTH_LABEL)
            .label_style(("sans-serif", 14))
            .axis_desc_style(("sans-serif", 16))
            .draw()
            .map_err(err)?;
        if range.is_some() {
            cbar.draw_series((0..GROWTH_LEVELS).map(|k| {
                let t0 = ((k as f64 - 0.5) / top).max(0.0);
                let t1 = ((k as f64 + 0.5) / top).min(1.0);
                Rectangle::new([(0.0, lo + t0 * (hi - lo)), (1.0, lo + t1 * (hi - lo))], color(k).filled())
            }))
            .map_err(err)?;
        }
        draw_frame(&mut cbar)?;
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

/// A number for the CSV: shortest round-trip text, exponent form from 1e15 on, empty if
/// not finite.
fn csv_number(v: f64) -> String {
    if !v.is_finite() {
        String::new()
    } else if v.abs() >= 1e15 {
        format!("{v:e}")
    } else {
        v.to_string()
    }
}

/// One row per grid point, φ-major (the order of `chart.points`). `verdict` is
/// `stable`, `unstable` or `failed`; failed points have empty numeric fields (their
/// stored values are placeholders). `status` is `ok`, `inaccurate` or `failed`.
pub fn chart_csv(chart: &ChartResult) -> Result<String, csv::Error> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "phi_rad_s",
        "beta",
        "max_multiplier",
        "ln_max_multiplier",
        "growth_rate_per_s",
        "verdict",
        "status",
    ])?;
    for p in &chart.points {
        let failed = p.status == PointStatus::Failed;
        let value = |v: f64| if failed { String::new() } else { csv_number(v) };
        let verdict = if failed {
            "failed"
        } else if p.stable {
            "stable"
        } else {
            "unstable"
        };
        let status = match p.status {
            PointStatus::Ok => "ok",
            PointStatus::Inaccurate => "inaccurate",
            PointStatus::Failed => "failed",
        };
        w.write_record([
            csv_number(p.phi),
            csv_number(p.beta),
            value(p.max_multiplier),
            value(p.ln_max_multiplier),
            value(p.growth_rate),
            verdict.to_string(),
            status.to_string(),
        ])?;
    }
    let bytes = w.into_inner().map_err(|e| e.into_error())?;
    Ok(String::from_utf8_lossy(&bytes).into_owned())
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
