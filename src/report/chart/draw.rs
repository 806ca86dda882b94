//! Drawing pieces shared by the stability chart and the growth map: axes, blocks,
//! failed points, markers, frame and legend.

use super::*;

/// Cartesian chart with the shared axes, labels and light grid on `area`.
pub(super) fn axes<'a, DB: DrawingBackend>(
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
        .y_label_formatter(&tick)
        .label_style((style::FONT, style::TICK_SIZE))
        .axis_desc_style((style::FONT, style::AXIS_LABEL_SIZE))
        .bold_line_style(GRID_COLOR)
        .light_line_style(TRANSPARENT)
        .draw()
        .map_err(err)?;
    Ok(chart)
}

/// Draw `blocks` of `chart` as filled rectangles, coloured by key.
pub(super) fn draw_blocks<DB: DrawingBackend, K>(
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
pub(super) fn draw_failed<DB: DrawingBackend>(
    plot: &mut Chart2d<'_, DB>,
    chart: &ChartResult,
) -> Result<usize, PlotError> {
    let failed: Vec<(f64, f64)> =
        chart.points.iter().filter(|p| p.status == PointStatus::Failed).map(|p| (p.phi, p.beta)).collect();
    plot.draw_series(failed.iter().map(|&c| Cross::new(c, CROSS_SIZE, FAILED_COLOR.stroke_width(1)))).map_err(err)?;
    Ok(failed.len())
}

/// Dashed grey vertical lines (1 px) with labels at the top, staggered downwards when
/// they would overlap and skipped when three lines of labels are not enough. Markers
/// outside the x range are not drawn.
pub(super) fn draw_markers<DB: DrawingBackend>(
    plot: &mut Chart2d<'_, DB>,
    markers: &[(f64, String)],
    occupied: &mut clip::Occupied,
) -> Result<(), PlotError> {
    const LABEL_LINES: i32 = 3;
    let x = plot.x_range();
    let y = plot.y_range();
    let mut visible: Vec<&(f64, String)> =
        markers.iter().filter(|(m, _)| m.is_finite() && *m >= x.start && *m <= x.end).collect();
    visible.sort_by(|a, b| a.0.total_cmp(&b.0));
    let style = ShapeStyle::from(&MARKER_COLOR).stroke_width(style::THIN);
    let font = (style::FONT, style::ANNOTATION_SIZE + 1).into_font().color(&RGBColor(40, 40, 40));
    let right_px = plot.backend_coord(&(x.end, y.end)).0;
    let origin = area_box(plot.plotting_area())[0];
    for (m, _) in &visible {
        plot.draw_series(std::iter::once(DashedPathElement::new(vec![(*m, y.start), (*m, y.end)], 5, 4, style)))
            .map_err(err)?;
    }
    for (m, label) in visible {
        if label.is_empty() {
            continue;
        }
        let (w, h) = plot.plotting_area().estimate_text_size(label, &font).map_err(err)?;
        let (w, h) = (w as i32, h as i32);
        let px = plot.backend_coord(&(*m, y.end)).0;
        // Label to the right of the line, or to the left near the right edge.
        let dx = if px + w + 8 > right_px { -w - 6 } else { 4 };
        for line in 0..LABEL_LINES {
            let dy = 4 + line * (h + 4);
            let py = plot.backend_coord(&(*m, y.end)).1;
            let b = [(px + dx - 2, py + dy - 1), (px + dx + w + 2, py + dy + h + 1)];
            if !occupied.claim(b) {
                continue;
            }
            let _ = origin;
            let anchor = EmptyElement::at((*m, y.end))
                + Rectangle::new([(dx - 2, dy - 1), (dx + w + 2, dy + h + 1)], WHITE.mix(0.85).filled())
                + Text::new(label.clone(), (dx, dy), font.clone());
            plot.plotting_area().draw(&anchor).map_err(err)?;
            break;
        }
    }
    Ok(())
}

/// Shaded φ spans over the whole β range with 1 px edges, and bars over their β
/// interval with a 1 px outline, clipped to the plotting area.
pub(super) fn draw_spans<DB: DrawingBackend>(plot: &mut Chart2d<'_, DB>, spans: &[Span]) -> Result<(), PlotError> {
    let (x, y) = (plot.x_range(), plot.y_range());
    for s in spans {
        let (lo, hi) = (s.lo.max(x.start), s.hi.min(x.end));
        let (b0, b1) = s.beta.map_or((y.start, y.end), |(b0, b1)| (b0.max(y.start), b1.min(y.end)));
        let ordered = |a: f64, b: f64| a.partial_cmp(&b) == Some(std::cmp::Ordering::Less);
        if !ordered(lo, hi) || !ordered(b0, b1) {
            continue;
        }
        let fill = if s.beta.is_some() { bar_fill(s.color) } else { span_fill(s.color) };
        plot.draw_series(std::iter::once(Rectangle::new([(lo, b0), (hi, b1)], rgb(fill).filled()))).map_err(err)?;
        let edge = rgb(s.color).stroke_width(style::THIN);
        if s.beta.is_some() {
            plot.draw_series(std::iter::once(Rectangle::new([(lo, b0), (hi, b1)], edge))).map_err(err)?;
            continue;
        }
        for e in [s.lo, s.hi].into_iter().filter(|e| *e >= x.start && *e <= x.end) {
            plot.draw_series(std::iter::once(PathElement::new(vec![(e, y.start), (e, y.end)], edge))).map_err(err)?;
        }
    }
    Ok(())
}

/// Regions as filled polygons at their true width, clipped to the plotting area, with a
/// 1 px outline; a region thinner than a pixel is still drawn as a 1 px line.
pub(super) fn draw_regions<DB: DrawingBackend>(
    plot: &mut Chart2d<'_, DB>,
    regions: &[RegionShape],
) -> Result<(), PlotError> {
    let (x, y) = (plot.x_range(), plot.y_range());
    let (x, y) = ((x.start, x.end), (y.start, y.end));
    for r in regions {
        let poly = clip::clip_polygon(&r.outline, x, y);
        if poly.len() < 3 {
            continue;
        }
        plot.draw_series(std::iter::once(Polygon::new(poly.clone(), rgb(REGION_FILL).mix(0.55).filled())))
            .map_err(err)?;
        let mut closed = r.outline.clone();
        if let Some(&first) = r.outline.first() {
            closed.push(first);
        }
        for piece in clip::clip_polyline(&closed, x, y) {
            plot.draw_series(std::iter::once(PathElement::new(piece, rgb(REGION_LINE).stroke_width(style::THIN))))
                .map_err(err)?;
        }
    }
    Ok(())
}

/// Region labels at the start of each region: beside its tip (the lowest point inside
/// the plot), on the right where the tongue, widening upwards, leaves room; skipped where
/// they would collide with a label already drawn.
pub(super) fn draw_region_labels<DB: DrawingBackend>(
    plot: &mut Chart2d<'_, DB>,
    regions: &[RegionShape],
    occupied: &mut clip::Occupied,
) -> Result<(), PlotError> {
    let (x, y) = (plot.x_range(), plot.y_range());
    let font = (style::FONT, style::ANNOTATION_SIZE).into_font().color(&BLACK);
    let mut order: Vec<(&RegionShape, (f64, f64))> = regions
        .iter()
        .filter(|r| !r.label.is_empty())
        .filter_map(|r| {
            let inside: Vec<(f64, f64)> = clip::clip_polygon(&r.outline, (x.start, x.end), (y.start, y.end));
            inside.into_iter().min_by(|a, b| a.1.total_cmp(&b.1)).map(|tip| (r, tip))
        })
        .collect();
    // Lowest onset first: the regions that reach furthest down are the ones that matter.
    order.sort_by(|a, b| a.1 .1.total_cmp(&b.1 .1));
    for (r, tip) in order {
        let (w, h) = plot.plotting_area().estimate_text_size(&r.label, &font).map_err(err)?;
        let (w, h) = (w as i32, h as i32);
        let (px, py) = plot.backend_coord(&tip);
        let top_px = plot.backend_coord(&(tip.0, y.end)).1;
        let bottom_px = plot.backend_coord(&(tip.0, y.start)).1;
        // Right of the tip, its baseline at the tip's height, inside the plot.
        let ly = (py - h - 2).clamp(top_px + 2, (bottom_px - h - 4).max(top_px + 2));
        let lx = px + 4;
        let b = [(lx - 2, ly - 1), (lx + w + 2, ly + h + 1)];
        if !occupied.claim(b) {
            continue;
        }
        let dy = ly - py;
        let anchor = EmptyElement::at(tip)
            + Rectangle::new([(2, dy - 1), (w + 6, dy + h + 1)], WHITE.mix(0.8).filled())
            + Text::new(r.label.clone(), (4, dy), font.clone());
        plot.plotting_area().draw(&anchor).map_err(err)?;
    }
    Ok(())
}

/// Frame around the plotting area (plotters draws only the left and bottom axes).
pub(super) fn draw_frame<DB: DrawingBackend>(plot: &mut Chart2d<'_, DB>) -> Result<(), PlotError> {
    let (x, y) = (plot.x_range(), plot.y_range());
    plot.draw_series(std::iter::once(Rectangle::new([(x.start, y.start), (x.end, y.end)], BLACK.stroke_width(1))))
        .map_err(err)?;
    Ok(())
}
