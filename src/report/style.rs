//! The look every plot shares: font, sizes, a categorical palette with line dashes and
//! markers for many series, axis labels with units, tick labels, a title that always
//! fits, and the legend panel drawn beside (never over) the plotting area.

use super::plot::PlotError;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Font family of every text (the embedded DejaVu Sans, registered by the renderers).
pub const FONT: &str = "sans-serif";
/// Largest title size (px); a longer title is shrunk to [`TITLE_MIN_SIZE`], then wrapped.
pub const TITLE_SIZE: u32 = 22;
/// Smallest title size (px) before the title is wrapped onto a second line.
pub const TITLE_MIN_SIZE: u32 = 15;
/// Axis description size (px).
pub const AXIS_LABEL_SIZE: u32 = 18;
/// Tick label size (px).
pub const TICK_SIZE: u32 = 15;
/// Legend text size (px).
pub const LEGEND_SIZE: u32 = 14;
/// Label size of in-plot annotations (tongue labels, marker labels) (px).
pub const ANNOTATION_SIZE: u32 = 12;
/// Margin around the plotting area (px).
pub const MARGIN: u32 = 15;
/// Width of every data line (px): thin, so that close lines stay apart.
pub const LINE_WIDTH: u32 = 2;
/// Width of boundary and reference lines (px): one pixel, never wider than what it marks.
pub const THIN: u32 = 1;

/// A categorical palette of 12 well-separated colours (Paul Tol's "muted" and "bright"
/// schemes merged), readable on white; series beyond 12 reuse a colour with another
/// marker ([`marker`]), so 12 × 4 series stay distinct.
pub const PALETTE: [(u8, u8, u8); 12] = [
    (0, 114, 178),   // blue
    (213, 94, 0),    // vermilion
    (0, 158, 115),   // bluish green
    (204, 121, 167), // reddish purple
    (230, 159, 0),   // orange
    (86, 180, 233),  // sky blue
    (136, 34, 85),   // wine
    (51, 34, 136),   // indigo
    (153, 153, 51),  // olive
    (102, 102, 102), // grey
    (170, 68, 153),  // purple
    (68, 170, 153),  // teal
];

/// Colour of series `k`.
pub fn color(k: usize) -> (u8, u8, u8) {
    PALETTE[k % PALETTE.len()]
}

/// Markers drawn on a line every few points, so that two lines of one colour differ.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    /// No marker.
    None,
    /// A filled circle.
    Circle,
    /// A hollow square.
    Square,
    /// A cross.
    Cross,
    /// A filled triangle.
    Triangle,
    /// A hollow circle, larger than a point (a ring around a point of a scatter).
    Ring,
}

/// Marker of series `k`: none for the first round of colours, then circle, square, cross
/// and triangle for each later round.
pub fn marker(k: usize) -> Marker {
    match k / PALETTE.len() {
        0 => Marker::None,
        1 => Marker::Circle,
        2 => Marker::Square,
        3 => Marker::Cross,
        _ => Marker::Triangle,
    }
}

/// Line pattern.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dash {
    /// Solid.
    Solid,
    /// Dashed (backward whirls, compared configurations, reference lines).
    Dashed,
    /// Dotted (the 1× line, secondary references).
    Dotted,
}

impl Dash {
    /// (dash, gap) lengths in pixels; `None` for a solid line.
    pub fn pattern(self) -> Option<(u32, u32)> {
        match self {
            Dash::Solid => None,
            Dash::Dashed => Some((7, 4)),
            Dash::Dotted => Some((2, 3)),
        }
    }
}

/// `"quantity symbol (unit)"`, the axis description of every plot, e.g.
/// `axis_label("speed", "Ω", "rad/s")` is `"speed Ω (rad/s)"`; an empty unit gives
/// `"(−)"` so that every axis states its unit.
pub fn axis_label(quantity: &str, symbol: &str, unit: &str) -> String {
    let unit = if unit.is_empty() { "−" } else { unit };
    match symbol {
        "" => format!("{quantity} ({unit})"),
        s => format!("{quantity} {s} ({unit})"),
    }
}

/// Tick label: integers without a decimal point ("500", not "500.0"), others rounded to
/// 6 significant decimals without trailing zeros; very large or small values in
/// exponent form.
pub fn tick(v: &f64) -> String {
    let v = *v;
    if !v.is_finite() {
        return v.to_string();
    }
    if v != 0.0 && (v.abs() >= 1e7 || v.abs() < 1e-4) {
        return format!("{v:.2e}").replace(".00e", "e");
    }
    if (v - v.round()).abs() <= 1e-9 * v.abs().max(1.0) {
        let r = v.round();
        return format!("{:.0}", if r == 0.0 { 0.0 } else { r });
    }
    let s = ((v * 1e6).round() / 1e6).to_string();
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

/// Tick label of a log axis: a power of ten as `1e-3`, other values by [`tick`].
pub fn log_tick(v: &f64) -> String {
    let e = v.log10();
    if (e - e.round()).abs() < 1e-9 {
        format!("1e{}", e.round() as i32)
    } else {
        format!("{v:.1e}")
    }
}

pub(crate) fn err<E: std::fmt::Debug>(e: E) -> PlotError {
    PlotError(format!("{e:?}"))
}

/// The title laid out for an area `width` px wide: its font size and its lines. The size
/// shrinks from [`TITLE_SIZE`] to [`TITLE_MIN_SIZE`] until the title fits; a title that
/// still does not fit is wrapped at spaces onto lines that do (a single word longer than
/// the width is cut with an ellipsis), so no title is ever clipped.
pub fn fit_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
    width: u32,
) -> Result<(u32, Vec<String>), PlotError> {
    let room = width.saturating_sub(2 * MARGIN) as i64;
    let text_width = |s: &str, size: u32| -> Result<i64, PlotError> {
        Ok(area.estimate_text_size(s, &TextStyle::from((FONT, size).into_font())).map_err(err)?.0 as i64)
    };
    for size in (TITLE_MIN_SIZE..=TITLE_SIZE).rev() {
        if text_width(title, size)? <= room {
            return Ok((size, vec![title.to_string()]));
        }
    }
    let size = TITLE_MIN_SIZE;
    let mut lines: Vec<String> = Vec::new();
    let mut line = String::new();
    for word in title.split_whitespace() {
        let candidate = if line.is_empty() { word.to_string() } else { format!("{line} {word}") };
        if text_width(&candidate, size)? <= room || line.is_empty() {
            line = candidate;
        } else {
            lines.push(std::mem::take(&mut line));
            line = word.to_string();
        }
    }
    if !line.is_empty() {
        lines.push(line);
    }
    for l in &mut lines {
        while text_width(l, size)? > room && l.chars().count() > 1 {
            l.pop();
            while l.ends_with('…') {
                l.pop();
            }
            l.pop();
            l.push('…');
        }
    }
    Ok((size, lines))
}

/// Draw the fitted title of `title` centred at the top of `root`; the area below it.
pub fn titled<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<DrawingArea<DB, Shift>, PlotError> {
    let (w, _) = root.dim_in_pixel();
    // A control character of the input (an escape) is drawn as its escape, as text.
    let (size, lines) = fit_title(root, &crate::report::html::visible(title), w)?;
    let line_height = (size as f64 * 1.3).ceil() as u32;
    let height = line_height * lines.len() as u32 + 12;
    let (head, rest) = root.split_vertically(height);
    let font = (FONT, size).into_font().into_text_style(&head).pos(Pos::new(HPos::Center, VPos::Top));
    for (i, l) in lines.iter().enumerate() {
        head.draw(&Text::new(l.clone(), ((w / 2) as i32, 6 + (i as u32 * line_height) as i32), font.clone()))
            .map_err(err)?;
    }
    Ok(rest)
}

/// What a legend entry shows beside its text.
#[derive(Debug, Clone)]
pub enum Key {
    /// A line segment of a colour, pattern and marker.
    Line((u8, u8, u8), Dash, Marker),
    /// A filled box of a colour (an area: unstable cells, a band).
    Fill((u8, u8, u8)),
    /// A hatched-looking box: a fill of a colour with a darker outline (a clearance).
    Outlined((u8, u8, u8), (u8, u8, u8)),
    /// A black cross (failed points).
    Cross,
    /// A marker alone, of a colour (points of a scatter).
    Point((u8, u8, u8), Marker),
}

/// One legend entry.
#[derive(Debug, Clone)]
pub struct Entry {
    /// What is drawn beside the text.
    pub key: Key,
    /// Legend text beside the key; cut with an ellipsis beyond `MAX_LEGEND_WIDTH`.
    pub text: String,
}

/// Width of a legend entry's key (px).
const KEY_WIDTH: i32 = 26;
/// Gap between key and text (px).
const KEY_GAP: i32 = 6;
/// Line height of a legend entry (px).
const ENTRY_HEIGHT: i32 = 20;
/// Padding inside the legend panel (px).
const PANEL_PAD: i32 = 8;
/// Widest legend panel (px); longer texts are cut with an ellipsis.
pub const MAX_LEGEND_WIDTH: u32 = 300;

/// The width (px) of a legend panel for `entries` (0 for none), at most
/// [`MAX_LEGEND_WIDTH`].
pub fn legend_width<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, entries: &[Entry]) -> Result<u32, PlotError> {
    if entries.is_empty() {
        return Ok(0);
    }
    let font = TextStyle::from((FONT, LEGEND_SIZE).into_font());
    let mut widest = 0;
    for e in entries {
        widest = widest.max(area.estimate_text_size(&e.text, &font).map_err(err)?.0 as i32);
    }
    Ok(((KEY_WIDTH + KEY_GAP + widest + 2 * PANEL_PAD + MARGIN as i32) as u32).min(MAX_LEGEND_WIDTH))
}

/// Draw a key of size `KEY_WIDTH` × 12 px with its left centre at (x, y) on `area`.
pub fn draw_key<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, key: &Key, x: i32, y: i32) -> Result<(), PlotError> {
    match key {
        Key::Line(c, dash, m) => {
            let style = ShapeStyle::from(&rgb(*c)).stroke_width(LINE_WIDTH);
            let path = vec![(x, y), (x + KEY_WIDTH, y)];
            match dash.pattern() {
                None => area.draw(&PathElement::new(path, style)).map_err(err)?,
                Some((d, g)) => area.draw(&DashedPathElement::new(path, d, g, style)).map_err(err)?,
            }
            draw_marker(area, *m, *c, (x + KEY_WIDTH / 2, y))?;
        }
        Key::Fill(c) => {
            let r = [(x + 4, y - 6), (x + KEY_WIDTH - 4, y + 6)];
            area.draw(&Rectangle::new(r, rgb(*c).filled())).map_err(err)?;
            area.draw(&Rectangle::new(r, RGBColor(120, 120, 120).stroke_width(1))).map_err(err)?;
        }
        Key::Outlined(fill, line) => {
            let r = [(x + 4, y - 6), (x + KEY_WIDTH - 4, y + 6)];
            area.draw(&Rectangle::new(r, rgb(*fill).filled())).map_err(err)?;
            area.draw(&Rectangle::new(r, rgb(*line).stroke_width(1))).map_err(err)?;
        }
        Key::Cross => {
            area.draw(&Cross::new((x + KEY_WIDTH / 2, y), 4, BLACK.stroke_width(2))).map_err(err)?;
        }
        Key::Point(c, m) => draw_marker(area, *m, *c, (x + KEY_WIDTH / 2, y))?,
    }
    Ok(())
}

/// Draw marker `m` of colour `c` centred at pixel `at` of `area`.
pub fn draw_marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    m: Marker,
    c: (u8, u8, u8),
    at: (i32, i32),
) -> Result<(), PlotError> {
    let color = rgb(c);
    match m {
        Marker::None => {}
        Marker::Circle => area.draw(&Circle::new(at, 4, color.filled())).map_err(err)?,
        Marker::Square => area
            .draw(&Rectangle::new([(at.0 - 4, at.1 - 4), (at.0 + 4, at.1 + 4)], color.stroke_width(2)))
            .map_err(err)?,
        Marker::Cross => area.draw(&Cross::new(at, 4, color.stroke_width(2))).map_err(err)?,
        Marker::Triangle => area.draw(&TriangleMarker::new(at, 5, color.filled())).map_err(err)?,
        Marker::Ring => area.draw(&Circle::new(at, 6, color.stroke_width(2))).map_err(err)?,
    }
    Ok(())
}

/// Draw `entries` as a framed legend panel at the top left of `area` (a panel beside the
/// plotting area, so it covers no data); the panel's pixel box in `area`.
pub fn draw_legend_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
    top: i32,
) -> Result<Option<[(i32, i32); 2]>, PlotError> {
    if entries.is_empty() {
        return Ok(None);
    }
    let (w, h) = area.dim_in_pixel();
    let (w, h) = (w as i32, h as i32);
    let font = (FONT, LEGEND_SIZE).into_font().into_text_style(area).pos(Pos::new(HPos::Left, VPos::Center));
    let rows = ((h - top - 2 * PANEL_PAD) / ENTRY_HEIGHT).max(1) as usize;
    let shown = entries.len().min(rows);
    let x0 = MARGIN as i32 / 2;
    let x1 = w - 2;
    let y1 = top + 2 * PANEL_PAD + shown as i32 * ENTRY_HEIGHT - (ENTRY_HEIGHT - 14);
    area.draw(&Rectangle::new([(x0, top), (x1, y1)], WHITE.filled())).map_err(err)?;
    area.draw(&Rectangle::new([(x0, top), (x1, y1)], RGBColor(160, 160, 160).stroke_width(1))).map_err(err)?;
    let room = x1 - (x0 + PANEL_PAD + KEY_WIDTH + KEY_GAP) - PANEL_PAD;
    for (i, e) in entries.iter().take(shown).enumerate() {
        let y = top + PANEL_PAD + 7 + i as i32 * ENTRY_HEIGHT;
        let x = x0 + PANEL_PAD;
        draw_key(area, &e.key, x, y)?;
        let mut text = if i + 1 == shown && shown < entries.len() {
            format!("… {} more", entries.len() - i)
        } else {
            e.text.clone()
        };
        while area.estimate_text_size(&text, &TextStyle::from((FONT, LEGEND_SIZE).into_font())).map_err(err)?.0 as i32
            > room
            && text.chars().count() > 2
        {
            text.pop();
            while text.ends_with('…') {
                text.pop();
            }
            text.pop();
            text.push('…');
        }
        area.draw(&Text::new(text, (x + KEY_WIDTH + KEY_GAP, y), font.clone())).map_err(err)?;
    }
    Ok(Some([(x0, top), (x1, y1)]))
}

/// The RGB colour of a triple.
pub fn rgb(c: (u8, u8, u8)) -> RGBColor {
    RGBColor(c.0, c.1, c.2)
}

/// `top` over `bottom` with opacity `alpha`, as a triple.
pub fn blend(top: (u8, u8, u8), bottom: (u8, u8, u8), alpha: f64) -> (u8, u8, u8) {
    let mix = |t: u8, b: u8| (alpha * f64::from(t) + (1.0 - alpha) * f64::from(b)).round() as u8;
    (mix(top.0, bottom.0), mix(top.1, bottom.1), mix(top.2, bottom.2))
}

/// The axes of a colour bar on `area` for values `lo..hi`, beside a plotting area with the
/// house margins (aligned with it): no x axis, the values labelled on the right and
/// described by `label` at `label_size` (px). The caller fills it with its colours.
pub fn colour_bar<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    (lo, hi): (f64, f64),
    label: &str,
    label_size: u32,
) -> Result<
    ChartContext<'a, DB, Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>>,
    PlotError,
> {
    let mut bar = ChartBuilder::on(area)
        .margin_top(MARGIN)
        .margin_bottom(MARGIN)
        .margin_left(15)
        .margin_right(5)
        .x_label_area_size(50)
        .right_y_label_area_size(85)
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(err)?;
    bar.configure_mesh()
        .disable_x_mesh()
        .disable_y_mesh()
        .disable_x_axis()
        .x_labels(0)
        .y_label_formatter(&tick)
        .y_desc(label)
        .label_style((FONT, TICK_SIZE - 1))
        .axis_desc_style((FONT, label_size))
        .draw()
        .map_err(err)?;
    Ok(bar)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_have_no_spurious_decimals() {
        assert_eq!(tick(&500.0), "500");
        assert_eq!(tick(&-20.0), "-20");
        assert_eq!(tick(&0.0), "0");
        assert_eq!(tick(&-0.0), "0");
        assert_eq!(tick(&0.25), "0.25");
        assert_eq!(tick(&0.30000000000000004), "0.3");
        assert_eq!(tick(&2.5e-6), "2.50e-6");
        assert_eq!(log_tick(&1e-3), "1e-3");
    }

    #[test]
    fn palette_and_markers_tell_48_series_apart() {
        let styles: std::collections::HashSet<_> = (0..48).map(|k| (color(k), format!("{:?}", marker(k)))).collect();
        assert_eq!(styles.len(), 48);
        let distinct: std::collections::HashSet<_> = PALETTE.iter().collect();
        assert_eq!(distinct.len(), PALETTE.len());
    }

    #[test]
    fn axis_labels_carry_units() {
        assert_eq!(axis_label("speed", "Ω", "rad/s"), "speed Ω (rad/s)");
        assert_eq!(axis_label("dynamic load", "β", ""), "dynamic load β (−)");
    }
}
