//! The figures of a design report: the before/after charts with the bands drawn, the
//! tuned design's Campbell diagram, the optimiser's history and the Bode plot.

use crate::design::content::DesignContent;
use crate::design::DesignOutcome;
use crate::report::chart::{Layer, Span, StabilityPlot};
use crate::report::plot::{Figure, LinePlot, Series};
use crate::report::unbalance::{BodeLayer, BodePlot};
use crate::report::{campbell, style};

use super::speed_text;

/// Colour of the reference design's layer and band.
const BEFORE_COLOR: (u8, u8, u8) = (31, 119, 180);
/// Colour of the tuned design's layer and band.
const AFTER_COLOR: (u8, u8, u8) = (214, 39, 40);
/// Height of a band's bar on the charts, as a fraction of β_op (the charts show β up to
/// 2 β_op: each bar is then 3 % of the height).
const BAR_HEIGHT: f64 = 0.06;
/// Colour of an operating band kept clear.
const OPERATING_COLOR: (u8, u8, u8) = (0, 158, 115);
/// Colour of a band's clearances.
const CLEARANCE_COLOR: (u8, u8, u8) = (230, 159, 0);

/// The spans of the design's bands on its charts at speed index `k`: the stable bands
/// before and after (widest band), each operating band and its clearances.
fn spans(o: &DesignOutcome, k: usize) -> Vec<Span> {
    let level = o.spec.level;
    let mut spans = Vec::new();
    // The bands found at β_op: two bars just below the level, the tuned one on top.
    for (name, bands, color, beta) in [
        ("stable band at β_op, before", o.before_bands(), BEFORE_COLOR, (1.0 - 2.0 * BAR_HEIGHT, 1.0 - BAR_HEIGHT)),
        ("stable band at β_op, after", o.after_bands(), AFTER_COLOR, (1.0 - BAR_HEIGHT, 1.0)),
    ] {
        if let Some(b) = bands.get(k).and_then(|b| b.band.band) {
            spans.push(Span {
                lo: b.lo,
                hi: b.hi,
                beta: Some((beta.0 * level, beta.1 * level)),
                name: name.into(),
                color,
            });
        }
    }
    for b in o.spec.kept_clear() {
        spans.push(Span {
            lo: b.lo,
            hi: b.hi,
            beta: None,
            name: "operating band kept clear".into(),
            color: OPERATING_COLOR,
        });
        if b.clearance > 0.0 {
            let g = b.guarded();
            for (lo, hi) in [(g.lo, b.lo), (b.hi, g.hi)] {
                spans.push(Span { lo, hi, beta: None, name: "clearance".into(), color: CLEARANCE_COLOR });
            }
        }
    }
    spans
}

/// The figures of a design report, in the order the report shows them (the first is the
/// key figure of page one): (file stem, figure).
pub fn figures<'a>(o: &'a DesignOutcome, content: DesignContent, title: &str) -> Vec<(String, Box<dyn Figure + 'a>)> {
    let spec = &o.spec;
    let unit = spec.speed_unit;
    let mut out: Vec<(String, Box<dyn Figure + 'a>)> = Vec::new();
    if let Some(v) = &o.vibration {
        let layers = vec![
            BodeLayer { name: "reference circuit".into(), dashed: false, result: &v.before },
            BodeLayer { name: "tuned circuit".into(), dashed: true, result: &v.after },
        ];
        let plot = BodePlot { title: format!("Unbalance response before and after the design: {title}"), layers, unit };
        out.push(("bode".into(), Box::new(plot)));
    }
    let markers: Vec<(f64, String)> = spec.phi_op().map(|p| (p, format!("φ_op = {p}"))).into_iter().collect();
    let charts = content.charts.len();
    for (k, c) in content.charts.into_iter().enumerate() {
        let layers = vec![
            Layer { name: "reference circuit".into(), color: BEFORE_COLOR, chart: c.before },
            Layer { name: "tuned circuit".into(), color: AFTER_COLOR, chart: c.after },
        ];
        let plot = StabilityPlot::new(
            &format!("Stability before and after the design, {}", speed_text(unit, c.speed)),
            layers,
        )
        .with_spans(spans(o, k))
        .with_levels(vec![(spec.level, format!("β_op = {}", spec.level))])
        .with_markers(markers.clone());
        let name = if charts == 1 { "charts".to_string() } else { format!("charts-{}", k + 1) };
        out.push((name, Box::new(plot)));
    }
    let campbell = campbell::campbell_plot(
        &content.campbell,
        &format!("Campbell diagram, tuned circuit: {title}"),
        unit,
        &spec.speeds,
    );
    out.push(("campbell".into(), Box::new(campbell)));
    out.push(("history".into(), Box::new(history_plot(o))));
    for (name, plot) in super::map_plot::map_plots(o) {
        out.push((name, Box::new(plot)));
    }
    out
}

/// The optimiser's best objective so far against its evaluations, one line per start.
fn history_plot(o: &DesignOutcome) -> LinePlot {
    let starts = o.history.iter().map(|h| h.start).max().map_or(0, |m| m + 1);
    let series: Vec<Series> = (0..starts)
        .map(|k| Series {
            name: match o.spec.objective.history_series(k) {
                Some(name) => name.into(),
                None => o.starts.get(k).map_or(format!("start {k}"), |s| s.origin.clone()),
            },
            color: style::color(k),
            dashed: false,
            points: o.history.iter().filter(|h| h.start == k).map(|h| (h.step as f64, h.best)).collect(),
        })
        .collect();
    let ys: Vec<f64> = series.iter().flat_map(|s| s.points.iter().map(|p| p.1)).filter(|y| y.abs() < 1e8).collect();
    let (y0, y1) = ys.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &y| (a.min(y), b.max(y)));
    let (y0, y1) = if y0.is_finite() && y1 > y0 { (y0, y1) } else { (y0.min(0.0) - 1.0, y1.max(0.0) + 1.0) };
    let x1 = series.iter().flat_map(|s| s.points.iter().map(|p| p.0)).fold(1.0, f64::max);
    let (x_label, y_label) = o.spec.objective.history_axes();
    LinePlot {
        title: "Optimiser history (best so far)".into(),
        x_label: x_label.into(),
        y_label: y_label.into(),
        x_range: (0.0, x1),
        y_range: (y0 - 0.05 * (y1 - y0), y1 + 0.05 * (y1 - y0)),
        series: series.into_iter().filter(|s| !s.points.is_empty()).collect(),
    }
}
