//! Line plots rendered to SVG text and PNG bytes (plotters with an embedded DejaVu font,
//! so no system font libraries are needed). Rendering only: no file I/O here.
//!
//! Placement rule of every legend: a panel to the right of the plotting area, outside
//! it, so it never covers data ([`Layout`] reports both boxes, and the tests check them).

use super::clip;
use super::style::{self, err, Dash, Entry, Key, Marker};
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use std::cell::Cell;
use std::sync::Once;

/// Plot size in pixels.
pub const SIZE: (u32, u32) = (1000, 700);

/// Points between two markers on a marked curve.
const MARKER_EVERY: usize = 8;
/// A marked piece of at most this many points has every point marked: its points are
/// the data (e.g. the designs of a front), not samples of a curve.
const MARK_EVERY_POINT: usize = 2 * MARKER_EVERY;

/// One polyline of a plot.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text; empty for no legend entry.
    pub name: String,
    /// RGB colour of the line.
    pub color: (u8, u8, u8),
    /// Dashed (e.g. backward whirls, reference lines).
    pub dashed: bool,
    /// (x, y) points in the axes' units.
    pub points: Vec<(f64, f64)>,
}

/// A plot of polylines.
#[derive(Debug, Clone)]
pub struct LinePlot {
    /// Caption drawn above the plot.
    pub title: String,
    /// x-axis label with unit.
    pub x_label: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// x axis range, in the x label's unit.
    pub x_range: (f64, f64),
    /// y axis range, in the y label's unit.
    pub y_range: (f64, f64),
    /// The lines, drawn in order.
    pub series: Vec<Series>,
}

/// One styled polyline of a [`CurvePlot`].
#[derive(Debug, Clone)]
pub struct Curve {
    /// Legend text; empty for no legend entry.
    pub name: String,
    /// Line colour as (red, green, blue), 0–255 each.
    pub color: (u8, u8, u8),
    /// Line pattern: solid, dashed or dotted.
    pub dash: Dash,
    /// Marker drawn every few points.
    pub marker: Marker,
    /// Line width (px).
    pub width: u32,
    /// (x, y) points in the axes' units.
    pub points: Vec<(f64, f64)>,
}

impl Curve {
    /// A solid curve of width [`style::LINE_WIDTH`] without marker.
    pub fn new(name: impl Into<String>, color: (u8, u8, u8), points: Vec<(f64, f64)>) -> Curve {
        Curve { name: name.into(), color, dash: Dash::Solid, marker: Marker::None, width: style::LINE_WIDTH, points }
    }
}

/// A plot of styled polylines, with the legend beside the plotting area.
#[derive(Debug, Clone)]
pub struct CurvePlot {
    /// Caption drawn above the plot (fitted: shrunk or wrapped, never clipped).
    pub title: String,
    /// x-axis label with unit.
    pub x_label: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// x axis range, in the x label's unit.
    pub x_range: (f64, f64),
    /// y axis range, in the y label's unit.
    pub y_range: (f64, f64),
    /// A logarithmic y axis (the range must then be positive).
    pub log_y: bool,
    /// The curves, drawn in order; each is clipped to the plotting area.
    pub curves: Vec<Curve>,
}

/// Where a plot's parts landed, in pixels of the whole image ([x0, y0], [x1, y1]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Layout {
    /// The plotting area (inside the axes).
    pub plot: [(i32, i32); 2],
    /// The legend panel, if there is a legend.
    pub legend: Option<[(i32, i32); 2]>,
}

impl Layout {
    /// Whether the legend box and the plotting area overlap.
    pub fn legend_overlaps_plot(&self) -> bool {
        self.legend.is_some_and(|l| {
            let p = self.plot;
            l[0].0 < p[1].0 && p[0].0 < l[1].0 && l[0].1 < p[1].1 && p[0].1 < l[1].1
        })
    }
}

/// A plot that renders to both output forms: every figure a command writes is one of
/// these, written as `NAME.svg` and `NAME.png` side by side. Every [`Drawing`] is one.
pub trait Figure {
    /// Render as SVG text.
    fn svg(&self) -> Result<String, PlotError>;
    /// Render as PNG bytes.
    fn png(&self) -> Result<Vec<u8>, PlotError>;
}

/// A plot drawn on any plotters backend: its SVG and PNG forms ([`Figure`]) and its
/// [`Layout`] all come from the one [`Drawing::draw`].
pub trait Drawing {
    /// Draw the whole image on `root`, and record where the plotting area and the legend
    /// land in `layout`.
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>, layout: &Cell<Layout>) -> Result<(), PlotError>;

    /// Where the plotting area and the legend land (pixels), from a rendering.
    fn layout(&self) -> Result<Layout, PlotError> {
        let cell = Cell::default();
        render_svg(|root| self.draw(root, &cell))?;
        Ok(cell.get())
    }
}

impl<T: Drawing> Figure for T {
    fn svg(&self) -> Result<String, PlotError> {
        render_svg(|root| self.draw(root, &Cell::default()))
    }
    fn png(&self) -> Result<Vec<u8>, PlotError> {
        render_png(|root| self.draw(root, &Cell::default()))
    }
}

/// A failure while drawing (a plotters backend error, as text).
#[derive(Debug, thiserror::Error)]
#[error("plot rendering failed: {0}")]
pub struct PlotError(pub String);

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded DejaVu font is valid by construction; a failure here would only
        // mean text is not drawn, which `draw` then reports as an error.
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, dejavu::sans::regular());
    });
}

/// Legend entries of `curves` (named ones, in order).
fn entries(curves: &[Curve]) -> Vec<Entry> {
    curves
        .iter()
        .filter(|c| !c.name.is_empty())
        .map(|c| Entry { key: Key::Line(c.color, c.dash, c.marker), text: c.name.clone() })
        .collect()
}

/// A plotting area and the legend column beside it (none without legend entries).
pub(crate) type PlotAndLegend<DB> = (DrawingArea<DB, Shift>, Option<DrawingArea<DB, Shift>>);

/// Split `area` into the plotting part and a legend column on its right for `entries`.
pub(crate) fn with_legend_column<DB: DrawingBackend>(
    area: DrawingArea<DB, Shift>,
    entries: &[Entry],
) -> Result<PlotAndLegend<DB>, PlotError> {
    let w = style::legend_width(&area, entries)?;
    if w == 0 {
        return Ok((area, None));
    }
    let total = area.dim_in_pixel().0;
    let (main, legend) = area.split_horizontally(total.saturating_sub(w));
    Ok((main, Some(legend)))
}

/// The pixel box of a drawing area in the whole image.
pub(crate) fn area_box<DB: DrawingBackend, CT: plotters::coord::CoordTranslate>(
    a: &DrawingArea<DB, CT>,
) -> [(i32, i32); 2] {
    let (x, y) = a.get_base_pixel();
    let (w, h) = a.dim_in_pixel();
    [(x, y), (x + w as i32, y + h as i32)]
}

impl Drawing for CurvePlot {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>, layout: &Cell<Layout>) -> Result<(), PlotError> {
        root.fill(&WHITE).map_err(err)?;
        let area = style::titled(&root, &self.title)?;
        let legend = entries(&self.curves);
        let (main, legend_area) = with_legend_column(area, &legend)?;
        let (x0, x1) = self.x_range;
        let (y0, y1) = self.y_range;
        let mut builder = ChartBuilder::on(&main);
        builder.margin(style::MARGIN).x_label_area_size(50).y_label_area_size(85);
        let plot_box = if self.log_y {
            let mut chart = builder.build_cartesian_2d(x0..x1, (y0..y1).log_scale()).map_err(err)?;
            self.axes_and_curves(&mut chart)?
        } else {
            let mut chart = builder.build_cartesian_2d(x0..x1, y0..y1).map_err(err)?;
            self.axes_and_curves(&mut chart)?
        };
        let mut legend_box = None;
        if let Some(l) = legend_area {
            let off = area_box(&l)[0];
            let top = plot_box[0].1 - off.1;
            legend_box = style::draw_legend_panel(&l, &legend, top.max(0))?
                .map(|b| [(b[0].0 + off.0, b[0].1 + off.1), (b[1].0 + off.0, b[1].1 + off.1)]);
        }
        layout.set(Layout { plot: plot_box, legend: legend_box });
        root.present().map_err(err)
    }
}

impl CurvePlot {
    /// The axes in the house style and the curves, clipped to the plotting area, on
    /// `chart`, whose y axis is logarithmic when `log_y` is set (then points at y ≤ 0 are
    /// left out) and linear otherwise. The plotting area's pixel box.
    fn axes_and_curves<DB: DrawingBackend, Y>(
        &self,
        chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, Y>>,
    ) -> Result<[(i32, i32); 2], PlotError>
    where
        Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
    {
        let ((x0, x1), (y0, y1)) = (self.x_range, self.y_range);
        let y_tick: fn(&f64) -> String = if self.log_y { style::log_tick } else { style::tick };
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .x_label_formatter(&style::tick)
            .y_label_formatter(&y_tick)
            .label_style((style::FONT, style::TICK_SIZE))
            .axis_desc_style((style::FONT, style::AXIS_LABEL_SIZE))
            .draw()
            .map_err(err)?;
        let plot_box = area_box(chart.plotting_area());
        for c in &self.curves {
            let clip = if self.log_y {
                let pts: Vec<(f64, f64)> = c.points.iter().copied().filter(|p| p.1 > 0.0).collect();
                clip::clip_polyline(&pts, (x0, x1), (y0, y1))
            } else {
                clip::clip_polyline(&c.points, (x0, x1), (y0, y1))
            };
            draw_pieces(chart, c, clip)?;
        }
        Ok(plot_box)
    }

    /// The pixel position of the data point `p` in the plot (linear axes), given its layout.
    pub fn to_pixel(&self, layout: &Layout, p: (f64, f64)) -> (f64, f64) {
        let [(px0, py0), (px1, py1)] = layout.plot;
        let fx = (p.0 - self.x_range.0) / (self.x_range.1 - self.x_range.0);
        let fy = if self.log_y {
            (p.1.ln() - self.y_range.0.ln()) / (self.y_range.1.ln() - self.y_range.0.ln())
        } else {
            (p.1 - self.y_range.0) / (self.y_range.1 - self.y_range.0)
        };
        (px0 as f64 + fx * (px1 - px0) as f64, py1 as f64 - fy * (py1 - py0) as f64)
    }
}

/// Draw the clipped pieces of `c` on `chart`, with its markers.
pub(crate) fn draw_pieces<DB: DrawingBackend, CT>(
    chart: &mut ChartContext<'_, DB, CT>,
    c: &Curve,
    pieces: Vec<Vec<(f64, f64)>>,
) -> Result<(), PlotError>
where
    CT: plotters::coord::CoordTranslate<From = (f64, f64)>,
{
    let style = ShapeStyle::from(&style::rgb(c.color)).stroke_width(c.width);
    for piece in pieces {
        match c.dash.pattern() {
            None => chart.draw_series(std::iter::once(PathElement::new(piece.clone(), style))).map_err(err)?,
            Some((d, g)) => {
                chart.draw_series(std::iter::once(DashedPathElement::new(piece.clone(), d, g, style))).map_err(err)?
            }
        };
        if c.marker != Marker::None {
            let area = chart.plotting_area();
            // `map_coordinate` gives pixels of the whole image; the stripped area draws
            // relative to its own corner.
            let (xs, ys) = area.get_pixel_range();
            let strip = area.strip_coord_spec();
            let every = if piece.len() <= MARK_EVERY_POINT { 1 } else { MARKER_EVERY };
            for p in piece.iter().step_by(every) {
                let at = area.map_coordinate(p);
                style::draw_marker(&strip, c.marker, c.color, (at.0 - xs.start, at.1 - ys.start))?;
            }
        }
    }
    Ok(())
}

impl LinePlot {
    fn curves(&self) -> CurvePlot {
        CurvePlot {
            title: self.title.clone(),
            x_label: self.x_label.clone(),
            y_label: self.y_label.clone(),
            x_range: self.x_range,
            y_range: self.y_range,
            log_y: false,
            curves: self
                .series
                .iter()
                .map(|s| Curve {
                    dash: if s.dashed { Dash::Dashed } else { Dash::Solid },
                    ..Curve::new(s.name.clone(), s.color, s.points.clone())
                })
                .collect(),
        }
    }
}

/// A line plot is drawn as the curve plot of its series.
impl Drawing for LinePlot {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>, layout: &Cell<Layout>) -> Result<(), PlotError> {
        self.curves().draw(root, layout)
    }
}

/// `points` (ascending x) thinned to at most two per column of `columns` equal x bins:
/// each bin keeps its smallest and largest y in their order, so a line through the result
/// covers exactly the range the full line covers in that pixel column (an envelope, not a
/// staircase of aliased samples). Bins of one or two points keep them as they are.
pub fn envelope(points: &[(f64, f64)], columns: usize) -> Vec<(f64, f64)> {
    let (Some(first), Some(last)) = (points.first(), points.last()) else { return Vec::new() };
    let span = last.0 - first.0;
    if columns == 0 || points.len() <= 2 * columns || span.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return points.to_vec();
    }
    let bin = |x: f64| (((x - first.0) / span * columns as f64) as usize).min(columns - 1);
    let mut out = Vec::with_capacity(2 * columns);
    let mut i = 0;
    while i < points.len() {
        let b = bin(points[i].0);
        let mut j = i;
        while j < points.len() && bin(points[j].0) == b {
            j += 1;
        }
        let chunk = &points[i..j];
        if chunk.len() <= 2 {
            out.extend_from_slice(chunk);
        } else {
            let lo = chunk.iter().enumerate().min_by(|a, b| a.1 .1.total_cmp(&b.1 .1)).map_or(0, |(k, _)| k);
            let hi = chunk.iter().enumerate().max_by(|a, b| a.1 .1.total_cmp(&b.1 .1)).map_or(0, |(k, _)| k);
            let (a, b) = if lo <= hi { (lo, hi) } else { (hi, lo) };
            out.push(chunk[a]);
            if b != a {
                out.push(chunk[b]);
            }
        }
        i = j;
    }
    out
}

/// Render `draw` to SVG text at [`SIZE`], with the embedded font registered.
pub(crate) fn render_svg(
    draw: impl FnOnce(DrawingArea<SVGBackend, Shift>) -> Result<(), PlotError>,
) -> Result<String, PlotError> {
    register_font();
    let mut buf = String::new();
    draw(SVGBackend::with_string(&mut buf, SIZE).into_drawing_area())?;
    // Any control character a label carried: shown, as XML cannot hold it.
    Ok(match crate::report::html::visible(&buf) {
        std::borrow::Cow::Borrowed(_) => buf,
        std::borrow::Cow::Owned(shown) => shown,
    })
}

/// Render `draw` to PNG bytes at [`SIZE`], with the embedded font registered.
pub(crate) fn render_png(
    draw: impl FnOnce(DrawingArea<BitMapBackend, Shift>) -> Result<(), PlotError>,
) -> Result<Vec<u8>, PlotError> {
    register_font();
    let mut rgb = vec![0u8; (SIZE.0 * SIZE.1 * 3) as usize];
    draw(BitMapBackend::with_buffer(&mut rgb, SIZE).into_drawing_area())?;
    encode_png(&rgb, SIZE)
}

/// Encode an RGB8 buffer as PNG.
pub fn encode_png(rgb: &[u8], size: (u32, u32)) -> Result<Vec<u8>, PlotError> {
    let mut out = std::io::Cursor::new(Vec::new());
    image::write_buffer_with_format(
        &mut out,
        rgb,
        size.0,
        size.1,
        image::ColorType::Rgb8,
        image::ImageOutputFormat::Png,
    )
    .map_err(err)?;
    Ok(out.into_inner())
}
