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
        .label_style(("sans-serif", 16))
        .axis_desc_style(("sans-serif", 18))
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

/// Dashed grey vertical lines with labels at the top, labels staggered downwards when
/// they would overlap. Markers outside the x range are not drawn.
pub(super) fn draw_markers<DB: DrawingBackend>(
    plot: &mut Chart2d<'_, DB>,
    markers: &[(f64, String)],
) -> Result<(), PlotError> {
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
pub(super) fn draw_frame<DB: DrawingBackend>(plot: &mut Chart2d<'_, DB>) -> Result<(), PlotError> {
    let (x, y) = (plot.x_range(), plot.y_range());
    plot.draw_series(std::iter::once(Rectangle::new([(x.start, y.start), (x.end, y.end)], BLACK.stroke_width(1))))
        .map_err(err)?;
    Ok(())
}

/// Legend swatch.
pub(super) enum Swatch {
    Fill(RGBColor),
    Cross,
}

/// Horizontal legend, centred in `area`.
pub(super) fn draw_legend<DB: DrawingBackend>(
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
