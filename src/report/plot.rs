//! Line plots rendered to SVG text and PNG bytes (plotters with an embedded DejaVu font,
//! so no system font libraries are needed). Rendering only: no file I/O here.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::sync::Once;

/// Plot size in pixels.
pub const SIZE: (u32, u32) = (1000, 700);

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

fn err<E: std::fmt::Debug>(e: E) -> PlotError {
    PlotError(format!("{e:?}"))
}

impl LinePlot {
    fn draw<DB: DrawingBackend>(&self, root: DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        root.fill(&WHITE).map_err(err)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(&self.title, ("sans-serif", 24))
            .margin(15)
            .x_label_area_size(50)
            .y_label_area_size(80)
            .build_cartesian_2d(self.x_range.0..self.x_range.1, self.y_range.0..self.y_range.1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style(("sans-serif", 16))
            .axis_desc_style(("sans-serif", 18))
            .draw()
            .map_err(err)?;
        let mut legend = false;
        for s in &self.series {
            let color = RGBColor(s.color.0, s.color.1, s.color.2);
            let style = ShapeStyle::from(&color).stroke_width(2);
            let drawn = if s.dashed {
                chart.draw_series(DashedLineSeries::new(s.points.iter().copied(), 6, 4, style)).map_err(err)?
            } else {
                chart.draw_series(LineSeries::new(s.points.iter().copied(), style)).map_err(err)?
            };
            if !s.name.is_empty() {
                legend = true;
                drawn.label(s.name.clone()).legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
            }
        }
        if legend {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 14))
                .position(SeriesLabelPosition::UpperLeft)
                .draw()
                .map_err(err)?;
        }
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

/// Render `draw` to SVG text at [`SIZE`], with the embedded font registered.
pub(crate) fn render_svg(
    draw: impl FnOnce(DrawingArea<SVGBackend, Shift>) -> Result<(), PlotError>,
) -> Result<String, PlotError> {
    register_font();
    let mut buf = String::new();
    draw(SVGBackend::with_string(&mut buf, SIZE).into_drawing_area())?;
    Ok(buf)
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
