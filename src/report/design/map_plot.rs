//! The map of the objective over the box drawn (issue 49): for two variables, every map
//! point coloured by its objective over the two variables (linear axes in the variables'
//! units; the map's points are spread evenly on the scale the design searches each
//! variable on, logarithmic for frequencies and inductances), with the reference, the
//! starts of the local searches and the tuned design marked; with more variables, one
//! panel per pair of variables: the map's slice through the tuned design over the pair
//! ([`crate::design::optimise::MapSlice`], the other variables at their tuned values),
//! with the tuned design marked.

use crate::design::optimise::ObjectiveMap;
use crate::design::spec::{DesignSpec, Variable};
use crate::design::DesignOutcome;
use crate::report::plot::{area_box, with_legend_column, Drawing, Layout, PlotError};
use crate::report::style::{self, err, Entry, Key, Marker};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::cell::Cell;

/// Colour levels of the objective scale.
const LEVELS: usize = 64;
/// Radius of a map point (px).
const POINT_RADIUS: i32 = 6;
/// Colour of the reference design's marker.
const REFERENCE_COLOR: (u8, u8, u8) = (213, 94, 0);
/// Colour of the tuned design's marker.
const TUNED_COLOR: (u8, u8, u8) = (204, 0, 0);
/// Colour of the starts' rings.
const START_COLOR: (u8, u8, u8) = (0, 0, 0);

/// A marked design: legend text (empty: no entry), colour, marker and (x, y) in the
/// variables' units.
pub type Mark = (String, (u8, u8, u8), Marker, (f64, f64));

/// One panel of the map: the points over two variables.
#[derive(Debug, Clone)]
pub struct MapPlot {
    /// Caption.
    pub title: String,
    /// The variables on x and y (bounds, scale, name and unit).
    pub x: Variable,
    /// The variable on y.
    pub y: Variable,
    /// The map's points (x, y, objective; None where the candidate failed).
    pub points: Vec<(f64, f64, Option<f64>)>,
    /// The colour scale's description, with its unit.
    pub objective: String,
    /// Larger is better (the best colour is then the top of the scale).
    pub maximise: bool,
    /// Marked designs: (legend text, colour, marker, (x, y)).
    pub marks: Vec<Mark>,
}

/// The map's panels: one for two variables, one per pair for more; none without a map.
pub fn map_plots(o: &DesignOutcome) -> Vec<(String, MapPlot)> {
    let Some(m) = &o.map else { return Vec::new() };
    let spec = &o.spec;
    let n = spec.variables.len();
    let mut out = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            let name = if n == 2 { "map".to_string() } else { format!("map-{}-{}", i + 1, j + 1) };
            out.push((name, panel(o, m, spec, i, j)));
        }
    }
    out
}

/// The panel of variables `i` (x) and `j` (y): the map's slice over the pair when it has
/// one, else the map itself.
fn panel(o: &DesignOutcome, m: &ObjectiveMap, spec: &DesignSpec, i: usize, j: usize) -> MapPlot {
    let n = spec.variables.len();
    let (what, _) = split_unit(&m.objective);
    if let Some(slice) = m.slices.iter().find(|s| s.pair == (i, j)) {
        return MapPlot {
            title: format!(
                "Slice of {what} through the tuned design over {} and {} (the other variables at their tuned values): {} points",
                spec.variables[i].name(),
                spec.variables[j].name(),
                slice.points.len()
            ),
            x: spec.variables[i].clone(),
            y: spec.variables[j].clone(),
            points: slice.points.iter().map(|p| (p.values[i], p.values[j], p.objective)).collect(),
            objective: m.objective.clone(),
            maximise: m.maximise,
            marks: vec![("tuned design".to_string(), TUNED_COLOR, Marker::Cross, (o.after[i], o.after[j]))],
        };
    }
    let title = if n == 2 {
        format!("Map of the objective over the box ({what}): {} points", m.points.len())
    } else {
        format!(
            "Map of {what}, projected onto {} and {} (the other variables free): {} points",
            spec.variables[i].name(),
            spec.variables[j].name(),
            m.points.len()
        )
    };
    let mut marks = Vec::new();
    // The reference where it lies inside the box (a file's circuit may lie outside it).
    let inside = |k: usize| (spec.variables[k].min..=spec.variables[k].max).contains(&o.before[k]);
    if inside(i) && inside(j) {
        marks.push(("reference".to_string(), REFERENCE_COLOR, Marker::Square, (o.before[i], o.before[j])));
    }
    // The local searches' starts; a clear-bands run's starts table holds its global pass
    // (the map's points), whose convex runs start from the reference and the map's basin.
    let mut starts: Vec<&[f64]> = o
        .starts
        .iter()
        .filter(|s| s.termination != crate::design::optimise::GLOBAL_PASS)
        .map(|s| s.initial.as_slice())
        .collect();
    if starts.is_empty() {
        starts = m.basins.iter().filter_map(|&b| m.points.get(b)).map(|p| p.values.as_slice()).collect();
    }
    for (k, s) in starts.iter().enumerate() {
        let text = if k == 0 { "start of a local search".to_string() } else { String::new() };
        marks.push((text, START_COLOR, Marker::Ring, (s[i], s[j])));
    }
    marks.push(("tuned design".to_string(), TUNED_COLOR, Marker::Cross, (o.after[i], o.after[j])));
    MapPlot {
        title,
        x: spec.variables[i].clone(),
        y: spec.variables[j].clone(),
        points: m.points.iter().map(|p| (p.values[i], p.values[j], p.objective)).collect(),
        objective: m.objective.clone(),
        maximise: m.maximise,
        marks,
    }
}

/// A map's objective description split into what it is and its unit: `band width …, rad/s`
/// gives (`band width …`, `rad/s`); no unit after a comma gives "−".
fn split_unit(objective: &str) -> (&str, &str) {
    objective.rsplit_once(", ").unwrap_or((objective, "−"))
}

/// The axis description of a variable: its name and unit.
fn label(v: &Variable) -> String {
    style::axis_label(&v.name(), "", v.parameter.unit())
}

impl MapPlot {
    /// The objective's range over the points that have one.
    fn range(&self) -> Option<(f64, f64)> {
        let values = self.points.iter().filter_map(|p| p.2).filter(|v| v.is_finite());
        values.fold(None, |acc, v| Some(acc.map_or((v, v), |(a, b): (f64, f64)| (a.min(v), b.max(v)))))
    }

    /// The axes, the points and the marks on `chart` (linear axes in the variables' units);
    /// the plotting area's pixel box.
    fn body<DB: DrawingBackend>(
        &self,
        chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
        color: &dyn Fn(f64) -> RGBColor,
    ) -> Result<[(i32, i32); 2], PlotError> {
        chart
            .configure_mesh()
            .x_desc(label(&self.x))
            .y_desc(label(&self.y))
            .x_label_formatter(&style::tick)
            .y_label_formatter(&style::tick)
            .label_style((style::FONT, style::TICK_SIZE))
            .axis_desc_style((style::FONT, style::AXIS_LABEL_SIZE))
            .light_line_style(TRANSPARENT)
            .draw()
            .map_err(err)?;
        for &(x, y, v) in &self.points {
            match v {
                Some(v) => chart.draw_series(std::iter::once(Circle::new((x, y), POINT_RADIUS, color(v).filled()))),
                None => chart.draw_series(std::iter::once(Cross::new((x, y), 4, BLACK.stroke_width(2)))),
            }
            .map_err(err)?;
        }
        for (_, c, marker, (x, y)) in &self.marks {
            let c = style::rgb(*c);
            let at = (*x, *y);
            let ring = EmptyElement::at(at) + Circle::new((0, 0), 10, c.stroke_width(2));
            let square = EmptyElement::at(at) + Rectangle::new([(-8, -8), (8, 8)], c.stroke_width(3));
            match marker {
                Marker::Ring => chart.draw_series(std::iter::once(ring)),
                Marker::Square => chart.draw_series(std::iter::once(square)),
                _ => chart.draw_series(std::iter::once(Cross::new(at, 9, c.stroke_width(3)))),
            }
            .map_err(err)?;
        }
        Ok(area_box(chart.plotting_area()))
    }
}

/// The layout's plotting area is the map's; its legend is the marks' (the colour bar
/// beside the map is its scale, not a legend).
impl Drawing for MapPlot {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>, layout: &Cell<Layout>) -> Result<(), PlotError> {
        root.fill(&WHITE).map_err(err)?;
        let area = style::titled(&root, &self.title)?;
        let entries: Vec<Entry> = self
            .marks
            .iter()
            .filter(|m| !m.0.is_empty())
            .map(|(text, c, marker, _)| Entry { key: Key::Point(*c, *marker), text: text.clone() })
            .collect();
        let (area, legend_area) = with_legend_column(area, &entries)?;
        let width = area.dim_in_pixel().0;
        let (main, bar) = area.split_horizontally(width.saturating_sub(135));
        let (lo, hi) = match self.range() {
            Some((lo, hi)) if hi > lo => (lo, hi),
            Some((v, _)) => (v - 1.0, v + 1.0),
            None => (0.0, 1.0),
        };
        let top = (LEVELS - 1) as f64;
        let level = move |v: f64| ((v - lo) / (hi - lo)).clamp(0.0, 1.0);
        let color = move |v: f64| -> RGBColor { ViridisRGB.get_color_normalized((level(v) * top).round(), 0.0, top) };
        // Each axis over its variable's box with 3 % of room.
        let range = |v: &Variable| {
            let d = 0.03 * (v.max - v.min);
            (v.min - d)..(v.max + d)
        };
        let mut builder = ChartBuilder::on(&main);
        builder.margin(style::MARGIN).x_label_area_size(50).y_label_area_size(85);
        let mut chart = builder.build_cartesian_2d(range(&self.x), range(&self.y)).map_err(err)?;
        let plot_box = self.body(&mut chart, &color)?;
        // The colour scale, aligned with the plotting area.
        let label = format!(
            "objective ({}){}",
            split_unit(&self.objective).1,
            if self.maximise { ", larger is better" } else { ", smaller is better" }
        );
        let mut cbar = style::colour_bar(&bar, (lo, hi), &label, style::ANNOTATION_SIZE)?;
        cbar.draw_series((0..LEVELS).map(|k| {
            let (t0, t1) = (k as f64 / LEVELS as f64, (k + 1) as f64 / LEVELS as f64);
            let v = lo + (t0 + t1) / 2.0 * (hi - lo);
            Rectangle::new([(0.0, lo + t0 * (hi - lo)), (1.0, lo + t1 * (hi - lo))], color(v).filled())
        }))
        .map_err(err)?;
        let mut legend_box = None;
        if let Some(l) = legend_area {
            let off = area_box(&l)[0];
            let top = plot_box[0].1 - off.1;
            legend_box = style::draw_legend_panel(&l, &entries, top.max(0))?
                .map(|b| [(b[0].0 + off.0, b[0].1 + off.1), (b[1].0 + off.0, b[1].1 + off.1)]);
        }
        layout.set(Layout { plot: plot_box, legend: legend_box });
        root.present().map_err(err)
    }
}
